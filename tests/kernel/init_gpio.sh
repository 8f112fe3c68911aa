#!/bin/busybox sh
# /init of the kernel test's gpio-sim VM (run_kernel.sh gpio): vivid as a free-running camera, a
# gpio-sim chip made through configfs, mocap-kernel as the hub that starts the node on a grid in
# phase with the camera and drives the simulated line at the frame rate, the node pairing each
# edge with its frame; then the falling edge, and the chip removed under the running node.
. /init_lib.sh
PORT=7000
LINE=3
EDGES=${EDGES:-150}
SKIP=7
CFG=/sys/kernel/config/gpio-sim/mocap
# One vivid instance with one webcam input: a camera that runs at its own rate.
VIVID_OPTS="n_devs=1 node_types=0x1 num_inputs=1 input_types=0x0 vid_cap_nr=0"

load_modules_until vivid.ko || { fail "modules: vivid and its dependencies"; finish; }
rmmod vivid
insmod /lib/modules/vivid.ko $VIVID_OPTS || { fail "vivid with $VIVID_OPTS"; finish; }
load_modules_until gpio-sim.ko || { fail "modules: gpio-sim.ko (built out of tree) and configfs"; finish; }
mkdir -p /sys/kernel/config
mount -t configfs none /sys/kernel/config
if mkdir $CFG && mkdir $CFG/bank0 && echo 8 >$CFG/bank0/num_lines && echo 1 >$CFG/live; then
    CHIP=$(cat $CFG/bank0/chip_name)
    PULL=/sys/devices/platform/$(cat $CFG/dev_name)/$CHIP/sim_gpio$LINE/pull
    pass "gpio-sim chip $CHIP ($(cat /sys/bus/gpio/devices/$CHIP/../label 2>/dev/null)), line $LINE driven through $PULL"
else
    fail "gpio-sim: chip not made through configfs"
    finish
fi

# run_node LOG [FLAGS...]: the node on vivid with the gpio trigger, in the background.
run_node() {
    log=$1
    shift
    mocap-node --source v4l2:/dev/video0 --sync gpio:$CHIP:$LINE --hub 127.0.0.1:$PORT --id 7 \
        --insecure-dev-wire --width 320 --height 180 --threshold 250 --rate 30 \
        --trigger-delay-us 2000 --status-interval-ms 200 --reopen-min-ms 100 --reopen-max-ms 400 \
        --log-level info "$@" >"$log" 2>&1 &
    node_pid=$!
}

for edge in rising falling; do
    flags=""
    [ $edge = falling ] && flags="--gpio-falling yes"
    run_node /tmp/node-$edge.log $flags
    mocap-kernel gpio $PORT $PULL $EDGES $SKIP $edge 2000 $node_pid >/tmp/gpio-$edge.log 2>&1
    grep "^KERNEL:" /tmp/gpio-$edge.log | sed "s/gpio:/gpio $edge:/"
    grep "^KERNEL: FAIL" /tmp/gpio-$edge.log >/dev/null && { failed=$((failed + 1)); show tool /tmp/gpio-$edge.log; show node /tmp/node-$edge.log; }
    grep -q "^KERNEL: PASS" /tmp/gpio-$edge.log || { failed=$((failed + 1)); show tool /tmp/gpio-$edge.log; show node /tmp/node-$edge.log; }
    if [ $edge = rising ]; then
        kill -TERM $node_pid
        wait $node_pid
    fi
done

# The chip disappears under the running node (the falling-edge node is still running).
echo 0 >$CFG/live
rmdir $CFG/bank0 $CFG
if rmmod gpio-sim 2>/tmp/rmmod.err; then
    echo "KERNEL: gpio-sim removed under the running node"
else
    fail "gpio-sim removal: $(cat /tmp/rmmod.err)"
fi
if wait_gone 5 $node_pid; then
    wait $node_pid
    rc=$?
    if [ $rc -eq 3 ]; then
        pass "trigger chip removed: node exited with 3 (hardware missing): $(grep -m1 -i 'trigger' /tmp/node-falling.log | tail -n 1)"
    else
        fail "trigger chip removed: node exited with $rc, not 3"
    fi
else
    fail "trigger chip removed: node still running 5 s later"
    kill -TERM $node_pid
fi
show node /tmp/node-falling.log | tail -n 8
finish
