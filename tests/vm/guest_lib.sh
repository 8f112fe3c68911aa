# Sourced by the /init of every VM test (tests/vivid/init.sh, tests/kernel/init_vimc.sh and
# init_gpio.sh; copied into the initramfs by host_lib.sh): mounts, the "$VM_TAG: PASS|FAIL" lines
# the host script reads, waiting, module loading, and a process's CPU time. Set before sourcing:
# VM_TAG (the console lines' prefix) and optionally VM_FINISH_LOGS ("name:file ..." shown by
# finish when the file exists).
/bin/busybox mkdir -p /proc /sys /dev /tmp /run
/bin/busybox mount -t devtmpfs devtmpfs /dev
exec </dev/console >/dev/console 2>&1
/bin/busybox --install -s /bin
export PATH=/bin
export HOME=/tmp
mount -t proc proc /proc
mount -t sysfs sysfs /sys
ip link set lo up
failed=0

pass() { echo "$VM_TAG: PASS $*"; }
fail() { echo "$VM_TAG: FAIL $*"; failed=$((failed + 1)); }
show() { [ -f "$2" ] && sed "s/^/  $1| /" "$2"; }
finish() {
    for log in ${VM_FINISH_LOGS:-}; do
        [ -f "${log#*:}" ] && show "${log%%:*}" "${log#*:}"
    done
    if [ "$failed" -eq 0 ]; then echo "$VM_TAG: RESULT PASS"; else echo "$VM_TAG: RESULT FAIL ($failed failed)"; fi
    sync
    poweroff -f
}
# wait_for SECONDS FILE PATTERN: 0 once FILE holds a line matching PATTERN.
wait_for() {
    i=0
    while [ "$i" -lt $(($1 * 10)) ]; do
        grep -q "$3" "$2" 2>/dev/null && return 0
        sleep 0.1
        i=$((i + 1))
    done
    return 1
}
# wait_gone SECONDS PID: 0 once the process has exited.
wait_gone() {
    i=0
    while [ "$i" -lt $(($1 * 10)) ]; do
        kill -0 "$2" 2>/dev/null || return 0
        sleep 0.1
        i=$((i + 1))
    done
    return 1
}
# load_modules_until NAME.ko: every module of /lib/modules/order up to and including NAME.ko.
load_modules_until() {
    for m in $(cat /lib/modules/order); do
        grep -q "^$(echo "${m%.ko}" | tr - _) " /proc/modules || insmod "/lib/modules/$m" || return 1
        [ "$m" = "$1" ] && return 0
    done
    return 1
}
# cpu_ns PID: CPU time the process has used (ns, /proc/PID/schedstat).
cpu_ns() { cut -d' ' -f1 "/proc/$1/schedstat"; }

echo "$VM_TAG: kernel $(uname -r), $(grep -c ^processor /proc/cpuinfo) cpu"
