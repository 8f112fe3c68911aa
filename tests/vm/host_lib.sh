# Sourced by the host side of every VM test (tests/vivid/run_vivid.sh, tests/kernel/run_kernel.sh):
# finding qemu and a static busybox, the initramfs root with the guest library, kernel modules in
# load order, and the boot whose serial console is the evidence. The caller defines skip() (exit
# 77 with its reason) and sets work, root, kver, kernel and boot_timeout.

# Sets qemu and busybox, or skips naming what is missing.
vm_find_tools() {
    qemu=$(command -v qemu-system-x86_64) || skip "qemu-system-x86_64 is not installed"
    "$qemu" -version >/dev/null 2>&1 || skip "$qemu does not run on this machine"
    busybox=$(command -v busybox) || skip "busybox is not installed"
    # (readelf's output taken whole: grep -q closing the pipe early fails it under pipefail.)
    if readelf -l "$busybox" 2>/dev/null | grep "program interpreter" >/dev/null; then
        skip "$busybox is dynamically linked (the initramfs needs busybox-static)"
    fi
}

# vm_new_root INIT_SCRIPT: an empty root with busybox, the guest library and INIT_SCRIPT as /init.
vm_new_root() {
    rm -rf "$work"
    mkdir -p "$root/bin" "$root/lib/modules" "$root/dev" "$root/proc" "$root/sys" "$root/tmp" "$root/run"
    cp "$busybox" "$root/bin/busybox"
    cp "$(dirname "${BASH_SOURCE[0]}")/guest_lib.sh" "$root/guest_lib.sh"
    cp "$1" "$root/init"
    chmod 755 "$root/init"
    : >"$root/lib/modules/order"
}

# vm_add_module PATH: a module into /lib/modules, decompressed (busybox insmod reads plain .ko),
# and appended to the load order once.
vm_add_module() {
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

# vm_add_tree_module NAME: NAME and its dependencies as modprobe resolves them in kver's tree.
vm_add_tree_module() {
    local verb path
    while read -r verb path _; do
        [ "$verb" = insmod ] && vm_add_module "$path"
    done < <(modprobe --show-depends -S "$kver" "$1")
}

# vm_boot NAME TAG MEMORY_MB: packs the root, boots kernel under TCG and passes only when qemu
# powered off by itself and the console holds "TAG: RESULT PASS" and no "TAG: FAIL".
vm_boot() {
    local name=$1 tag=$2 memory=$3 console start end qemu_rc
    (cd "$root" && find . | cpio -o -H newc --quiet) >"$work/initramfs.cpio"
    console=$work/console.log
    echo "$name: booting $kernel ($kver) under TCG, initramfs $(du -m "$work/initramfs.cpio" | cut -f1) MB," \
        "modules: $(tr '\n' ' ' <"$root/lib/modules/order")"
    start=$(date +%s.%N)
    set +e
    # no_timer_check: on a busy host the emulated CPU is too slow for the kernel's boot-time check
    # of the IO-APIC timer, which then panics ("IO-APIC + timer doesn't work!", seen here).
    timeout "$boot_timeout" "$qemu" -accel tcg -m "$memory" -smp 1 -nodefaults -display none -no-reboot \
        -serial "file:$console" -kernel "$kernel" -initrd "$work/initramfs.cpio" \
        -append "console=ttyS0 rdinit=/init panic=-1 loglevel=4 no_timer_check"
    qemu_rc=$?
    set -e
    end=$(date +%s.%N)
    cat "$console"
    echo "$name: qemu exited with status $qemu_rc after $(awk -v a="$start" -v b="$end" 'BEGIN{printf "%.1f", b - a}') s"
    if [ "$qemu_rc" -eq 124 ]; then
        echo "FAIL: the VM did not power off within $boot_timeout s"
        exit 1
    fi
    if [ "$qemu_rc" -ne 0 ]; then
        echo "FAIL: qemu exited with status $qemu_rc"
        exit 1
    fi
    if grep -q "^$tag: FAIL" "$console" || ! grep -q "^$tag: RESULT PASS" "$console"; then
        echo "FAIL: see the $tag lines above"
        exit 1
    fi
    echo "$name: $(grep -c "^$tag: PASS" "$console") checks passed"
    grep "^$tag: FIGURE" "$console" || true
}
