#!/usr/bin/env bash
# The vivid test (ctest label "vivid"): boots the installed Debian kernel in qemu-system-x86_64
# (TCG: no KVM needed) with an initramfs of busybox, mocap-node-static, mocap-vivid, vivid and the
# modules it depends on, and /init = init.sh, which runs the checks and powers off. The serial
# console is the evidence: this passes only if qemu exited by itself and the console holds
# "VIVID: RESULT PASS" and no "VIVID: FAIL". Exit 77 (ctest SKIP) only where qemu or the kernel
# package cannot be had, with the reason.
# Usage: run_vivid.sh MOCAP_NODE_STATIC MOCAP_VIVID WORK_DIR
set -euo pipefail

node_bin=$1
tool_bin=$2
work=$3
here=$(cd "$(dirname "$0")" && pwd)
boot_timeout=${MOCAP_VIVID_TIMEOUT:-200}

skip() {
    echo "*** vivid test SKIPPED: $* ***"
    echo "*** (deploy/install-deps.sh installs qemu-system-x86, linux-image-amd64, busybox-static) ***"
    exit 77
}

qemu=$(command -v qemu-system-x86_64) || skip "qemu-system-x86_64 is not installed"
"$qemu" -version >/dev/null 2>&1 || skip "$qemu does not run on this machine"
busybox=$(command -v busybox) || skip "busybox is not installed"
if readelf -l "$busybox" 2>/dev/null | grep -q "program interpreter"; then
    skip "$busybox is dynamically linked (the initramfs needs busybox-static)"
fi

# The newest installed kernel that ships vivid.
kver=""
for k in $(ls /boot/vmlinuz-* 2>/dev/null | sed 's|/boot/vmlinuz-||' | sort -V); do
    if modprobe --show-depends -S "$k" vivid >/dev/null 2>&1; then
        kver=$k
    fi
done
[ -n "$kver" ] || skip "no /boot/vmlinuz-* with a vivid module in /lib/modules (linux-image-amd64)"
kernel=/boot/vmlinuz-$kver
[ -r "$kernel" ] || skip "$kernel is not readable by $(id -un)"

for f in "$node_bin" "$tool_bin"; do
    if readelf -l "$f" | grep -q "program interpreter"; then
        echo "FAIL: $f is not statically linked" >&2
        exit 1
    fi
done

rm -rf "$work"
root=$work/root
mkdir -p "$root/bin" "$root/lib/modules" "$root/dev" "$root/proc" "$root/sys" "$root/tmp"
cp "$busybox" "$root/bin/busybox"
cp "$node_bin" "$root/bin/mocap-node-static"
cp "$tool_bin" "$root/bin/mocap-vivid"
cp "$here/init.sh" "$root/init"
chmod 755 "$root/init"

# vivid and its dependencies in load order, decompressed where the package compresses them
# (busybox insmod reads plain .ko).
: >"$root/lib/modules/order"
while read -r verb path _; do
    [ "$verb" = insmod ] || continue
    name=$(basename "$path")
    case "$name" in
    *.ko) cp "$path" "$root/lib/modules/$name" ;;
    *.ko.xz) name=${name%.xz}; xz -dc "$path" >"$root/lib/modules/$name" ;;
    *.ko.zst) name=${name%.zst}; zstd -qdc "$path" >"$root/lib/modules/$name" ;;
    *.ko.gz) name=${name%.gz}; gzip -dc "$path" >"$root/lib/modules/$name" ;;
    *) echo "FAIL: unknown module file $path" >&2; exit 1 ;;
    esac
    echo "$name" >>"$root/lib/modules/order"
done < <(modprobe --show-depends -S "$kver" vivid)
grep -qx vivid.ko "$root/lib/modules/order" || { echo "FAIL: vivid.ko not resolved" >&2; exit 1; }

(cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initramfs.cpio"

console=$work/console.log
echo "vivid: booting $kernel ($kver) under TCG, modules: $(tr '\n' ' ' <"$root/lib/modules/order")"
start=$(date +%s.%N)
set +e
# no_timer_check: on a busy host the emulated CPU is too slow for the kernel's boot-time check
# of the IO-APIC timer, which then panics ("IO-APIC + timer doesn't work!", seen here).
timeout "$boot_timeout" "$qemu" -accel tcg -m 384 -smp 1 -nodefaults -display none -no-reboot \
    -serial "file:$console" -kernel "$kernel" -initrd "$work/initramfs.cpio" \
    -append "console=ttyS0 rdinit=/init panic=-1 loglevel=4 no_timer_check"
qemu_rc=$?
set -e
end=$(date +%s.%N)
cat "$console"
echo "vivid: qemu exited with status $qemu_rc after $(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b - a}') s"

if [ "$qemu_rc" -eq 124 ]; then
    echo "FAIL: the VM did not power off within $boot_timeout s"
    exit 1
fi
if [ "$qemu_rc" -ne 0 ]; then
    echo "FAIL: qemu exited with status $qemu_rc"
    exit 1
fi
if grep -q "^VIVID: FAIL" "$console" || ! grep -q "^VIVID: RESULT PASS" "$console"; then
    echo "FAIL: see the VIVID lines above"
    exit 1
fi
echo "vivid: $(grep -c '^VIVID: PASS' "$console") checks passed"
