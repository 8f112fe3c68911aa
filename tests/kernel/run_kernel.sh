#!/usr/bin/env bash
# The kernel tests (ctest label "kernel"): the node's libcamera source on the kernel's vimc driver
# and its gpio: trigger source on gpio-sim, both in Debian's own kernel booted by
# qemu-system-x86_64 under TCG. vimc.ko and gpio-sim.ko are built out of tree by
# build_modules.sh (cached in MODULE_CACHE by kernel version). The initramfs holds busybox, the
# test's static mocap-kernel tool, the dynamically linked mocap-node with every library it loads
# (the ldd closure, at the same paths), for vimc also libcamera's IPA modules and its cam tool,
# the modules in load order, and /init = init_MODE.sh over init_lib.sh. The serial console is the
# evidence: this passes only if qemu exited by itself and the console holds "KERNEL: RESULT PASS"
# and no "KERNEL: FAIL". Exit 77 (ctest SKIP) with the reason when a package is missing.
# Usage: run_kernel.sh vimc|gpio MOCAP_NODE MOCAP_KERNEL WORK_DIR MODULE_CACHE
set -euo pipefail

mode=$1
node_bin=$2
tool_bin=$3
work=$4
module_cache=$5
here=$(cd "$(dirname "$0")" && pwd)
boot_timeout=${MOCAP_KERNEL_TIMEOUT:-150}

skip() {
    echo "*** kernel test ($mode) SKIPPED: $* ***"
    echo "*** (deploy/install-deps.sh installs qemu-system-x86, linux-image-amd64, busybox-static," \
        "linux-source-6.1, linux-headers-amd64, libcamera-tools, libcamera-ipa) ***"
    exit 77
}

case "$mode" in
vimc | gpio) ;;
*) echo "usage: $0 vimc|gpio MOCAP_NODE MOCAP_KERNEL WORK_DIR MODULE_CACHE" >&2; exit 2 ;;
esac

qemu=$(command -v qemu-system-x86_64) || skip "qemu-system-x86_64 is not installed"
"$qemu" -version >/dev/null 2>&1 || skip "$qemu does not run on this machine"
busybox=$(command -v busybox) || skip "busybox is not installed"
if readelf -l "$busybox" 2>/dev/null | grep "program interpreter" >/dev/null; then
    skip "$busybox is dynamically linked (the initramfs needs busybox-static)"
fi
# (ldd's output taken whole: grep -q closing the pipe early would fail the pipeline under
# pipefail.)
node_libs=$(ldd "$node_bin")
if [ "$mode" = vimc ]; then
    cam=$(command -v cam) || skip "libcamera's cam tool is not installed (libcamera-tools)"
    udevadm=$(command -v udevadm) || skip "udevadm is not installed (udev)"
    ipa_dir=$(ls -d /usr/lib/*/libcamera 2>/dev/null | head -n 1 || true)
    [ -n "$ipa_dir" ] && [ -f "$ipa_dir/ipa_vimc.so" ] || skip "no ipa_vimc.so (libcamera-ipa)"
    case "$node_libs" in *libcamera*) ;; *) skip "$node_bin was built without libcamera" ;; esac
else
    case "$node_libs" in *libgpiod*) ;; *) skip "$node_bin is not linked with libgpiod" ;; esac
fi

kver=$("$here/boot_kernel.sh") || skip "no /boot/vmlinuz-* with vivid in /lib/modules and its linux-headers"
kernel=/boot/vmlinuz-$kver
[ -r "$kernel" ] || skip "$kernel is not readable by $(id -un)"

set +e
moddir=$("$here/build_modules.sh" "$kver" "$module_cache")
rc=$?
set -e
[ "$rc" -eq 77 ] && skip "vimc.ko and gpio-sim.ko could not be built (see above)"
[ "$rc" -eq 0 ] || { echo "FAIL: building vimc.ko and gpio-sim.ko"; exit 1; }

if readelf -l "$tool_bin" | grep "program interpreter" >/dev/null; then
    echo "FAIL: $tool_bin is not statically linked" >&2
    exit 1
fi

rm -rf "$work"
root=$work/root
mkdir -p "$root/bin" "$root/lib/modules" "$root/dev" "$root/proc" "$root/sys" "$root/tmp" \
    "$root/run"
cp "$busybox" "$root/bin/busybox"
cp "$tool_bin" "$root/bin/mocap-kernel"
cp "$node_bin" "$root/bin/mocap-node"
cp "$here/init_lib.sh" "$root/init_lib.sh"
cp "$here/init_$mode.sh" "$root/init"
chmod 755 "$root/init"

# A dynamic program with every shared object it loads, at the paths the loader looks for them.
copy_closure() {
    local f lib
    for f in "$@"; do
        for lib in $(ldd "$f" | awk '/=> \// {print $3} /^\t\/[^ ]*ld-linux/ {print $1}'); do
            if [ ! -e "$root$lib" ]; then
                mkdir -p "$root$(dirname "$lib")"
                cp -L "$lib" "$root$lib"
            fi
        done
    done
}
copy_closure "$node_bin"
if [ "$mode" = vimc ]; then
    cp "$cam" "$root/bin/cam"
    copy_closure "$cam"
    # The vimc IPA module with its signature (checked: a signed module runs in the camera's
    # process, else in its proxy worker, which comes along too) and its configuration.
    mkdir -p "$root$ipa_dir" "$root/usr/share/libcamera/ipa"
    cp "$ipa_dir"/ipa_vimc.so* "$ipa_dir/vimc_ipa_proxy" "$root$ipa_dir/"
    copy_closure "$ipa_dir/ipa_vimc.so" "$ipa_dir/vimc_ipa_proxy"
    cp -r /usr/share/libcamera/ipa/vimc "$root/usr/share/libcamera/ipa/"
    # libcamera finds cameras through udev: only devices udevd has processed count, and an
    # unplug reaches it as a udev event. systemd-udevd runs in the VM (without rules) as it
    # does on a board.
    cp "$udevadm" "$root/bin/udevadm"
    mkdir -p "$root/lib/systemd"
    ln -s /bin/udevadm "$root/lib/systemd/systemd-udevd"
    copy_closure "$udevadm"
fi

# Modules in load order, decompressed (busybox insmod reads plain .ko): each dependency chain as
# modprobe resolves it in the kernel's tree, then the module built here.
: >"$root/lib/modules/order"
add_module() { # PATH
    local path=$1 name
    name=$(basename "$path")
    case "$name" in
    *.ko) cp "$path" "$root/lib/modules/$name" ;;
    *.ko.xz) name=${name%.xz}; xz -dc "$path" >"$root/lib/modules/$name" ;;
    *.ko.zst) name=${name%.zst}; zstd -qdc "$path" >"$root/lib/modules/$name" ;;
    *.ko.gz) name=${name%.gz}; gzip -dc "$path" >"$root/lib/modules/$name" ;;
    *) echo "FAIL: unknown module file $path" >&2; exit 1 ;;
    esac
    grep -qx "$name" "$root/lib/modules/order" || echo "$name" >>"$root/lib/modules/order"
}
add_tree_module() { # NAME
    local verb path
    while read -r verb path _; do
        [ "$verb" = insmod ] && add_module "$path"
    done < <(modprobe --show-depends -S "$kver" "$1")
}
add_built_module() { # FILE.ko
    local dep
    for dep in $(modinfo -F depends "$1" | tr ',' ' '); do
        add_tree_module "$dep"
    done
    add_module "$1"
}
if [ "$mode" = vimc ]; then
    add_built_module "$moddir/vimc.ko"
else
    add_tree_module vivid
    add_built_module "$moddir/gpio-sim.ko"
fi
strip --strip-debug "$root"/lib/modules/*.ko

(cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initramfs.cpio"

console=$work/console.log
echo "kernel/$mode: booting $kernel ($kver) under TCG, initramfs $(du -m "$work/initramfs.cpio" | cut -f1) MB," \
    "modules: $(tr '\n' ' ' <"$root/lib/modules/order")"
start=$(date +%s.%N)
set +e
# no_timer_check: on a busy host the emulated CPU is too slow for the kernel's boot-time check
# of the IO-APIC timer, which then panics ("IO-APIC + timer doesn't work!", seen here).
timeout "$boot_timeout" "$qemu" -accel tcg -m 1024 -smp 1 -nodefaults -display none -no-reboot \
    -serial "file:$console" -kernel "$kernel" -initrd "$work/initramfs.cpio" \
    -append "console=ttyS0 rdinit=/init panic=-1 loglevel=4 no_timer_check"
qemu_rc=$?
set -e
end=$(date +%s.%N)
cat "$console"
echo "kernel/$mode: qemu exited with status $qemu_rc after $(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b - a}') s"

if [ "$qemu_rc" -eq 124 ]; then
    echo "FAIL: the VM did not power off within $boot_timeout s"
    exit 1
fi
if [ "$qemu_rc" -ne 0 ]; then
    echo "FAIL: qemu exited with status $qemu_rc"
    exit 1
fi
if grep -q "^KERNEL: FAIL" "$console" || ! grep -q "^KERNEL: RESULT PASS" "$console"; then
    echo "FAIL: see the KERNEL lines above"
    exit 1
fi
echo "kernel/$mode: $(grep -c '^KERNEL: PASS' "$console") checks passed"
grep "^KERNEL: FIGURE" "$console" || true
