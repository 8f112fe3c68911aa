#!/usr/bin/env bash
# The kernel tests (ctest label "kernel"): the node's libcamera source on the kernel's vimc driver
# and its gpio: trigger source on gpio-sim, both in Debian's own kernel booted by
# qemu-system-x86_64 under TCG. vimc.ko and gpio-sim.ko are built out of tree by
# build_modules.sh (cached in MODULE_CACHE by kernel version). The initramfs holds busybox, the
# test's static mocap-kernel tool, the dynamically linked mocap-node with every library it loads
# (the ldd closure, at the same paths), for vimc also libcamera's IPA modules and its cam tool,
# the modules in load order, and /init = init_MODE.sh over ../vm/guest_lib.sh (the host side is ../vm/host_lib.sh). The serial console is the
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
. "$here/../vm/host_lib.sh"

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

vm_find_tools
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

root=$work/root
vm_new_root "$here/init_$mode.sh"
cp "$tool_bin" "$root/bin/mocap-kernel"
cp "$node_bin" "$root/bin/mocap-node"

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

# Modules in load order: each dependency chain as modprobe resolves it in the kernel's tree, then
# the module built here.
add_built_module() { # FILE.ko
    local dep
    for dep in $(modinfo -F depends "$1" | tr ',' ' '); do
        vm_add_tree_module "$dep"
    done
    vm_add_module "$1"
}
if [ "$mode" = vimc ]; then
    add_built_module "$moddir/vimc.ko"
else
    vm_add_tree_module vivid
    add_built_module "$moddir/gpio-sim.ko"
fi
strip --strip-debug "$root"/lib/modules/*.ko

vm_boot "kernel/$mode" KERNEL 1024
