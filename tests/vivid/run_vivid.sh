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
. "$here/../vm/host_lib.sh"

skip() {
    echo "*** vivid test SKIPPED: $* ***"
    echo "*** (deploy/install-deps.sh installs qemu-system-x86, linux-image-amd64, busybox-static) ***"
    exit 77
}

vm_find_tools

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

root=$work/root
vm_new_root "$here/init.sh"
cp "$node_bin" "$root/bin/mocap-node-static"
cp "$tool_bin" "$root/bin/mocap-vivid"

vm_add_tree_module vivid
grep -qx vivid.ko "$root/lib/modules/order" || { echo "FAIL: vivid.ko not resolved" >&2; exit 1; }

vm_boot vivid VIVID 384
