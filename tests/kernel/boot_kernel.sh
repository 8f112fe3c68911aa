#!/usr/bin/env bash
# Prints the version of the kernel the kernel tests boot: the newest /boot/vmlinuz-* whose
# modules include vivid and whose linux-headers are installed (vimc.ko and gpio-sim.ko are built
# against them). Exit 1 when there is none.
set -euo pipefail
kver=""
for k in $(ls /boot/vmlinuz-* 2>/dev/null | sed 's|/boot/vmlinuz-||' | sort -V); do
    if modprobe --show-depends -S "$k" vivid >/dev/null 2>&1 && [ -f "/lib/modules/$k/build/Makefile" ]; then
        kver=$k
    fi
done
[ -n "$kver" ] || exit 1
echo "$kver"
