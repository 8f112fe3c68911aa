#!/bin/busybox sh
# /init of the kernel test's vimc VM (run_kernel.sh vimc): mocap-node's libcamera source on the
# kernel's vimc driver through Debian's libcamera (its vimc pipeline handler and IPA). Checked:
# the camera found, configured and streamed (buffers mapped, requests completed and handed to
# the poll loop), the picture's markers the same in every frame, an exposure the camera cannot
# take refused in the ControlAck, the camera unplugged under the running node (driver unbound,
# module removed) and plugged back (the node reopens it), and the proof that the frames are
# right: frames captured by libcamera's own cam tool, turned into a recording and replayed
# through the node, give the same markers bit for bit.
VM_TAG=KERNEL
. /guest_lib.sh
export LIBCAMERA_LOG_LEVELS='*:ERROR'
export LTTNG_UST_REGISTER_TIMEOUT=0
PORT=7000
W=640
H=480
THRESHOLD=240
NODE_FLAGS="--sync none --hub 127.0.0.1:$PORT --id 7 --threshold $THRESHOLD --max-area 1000000 \
    --insecure-dev-wire --status-interval-ms 200 --reopen-min-ms 100 --reopen-max-ms 800 \
    --width $W --height $H --log-level info"

# The sensor's picture: "100% Color Squares" (a grid of squares of several levels, static; at
# the threshold only the white ones stand out) and no on-screen text (its counters would change
# the picture every frame).
sensor_picture() {
    for d in /sys/class/video4linux/v4l-subdev*; do
        [ "$(cat $d/name)" = "Sensor B" ] && sub=/dev/${d##*/}
    done
    [ -n "$sub" ] && mocap-kernel ctrl $sub "Show Information" 2 && mocap-kernel ctrl $sub "Test Pattern" 4
}
load_vimc() {
    insmod /lib/modules/vimc.ko || return 1
    udevadm settle -t 20 || return 1
    sensor_picture
}
# frames DUMP: one line per frame, its markers (all chunks), in the node's order.
frames() { awk '/^F /{if (f) print f; f = "x"} /^M/{f = f $0} END {if (f) print f}' "$1"; }

if load_modules_until videobuf2-vmalloc.ko; then :; else fail "modules: vimc's dependencies"; finish; fi
# udevd as on a board: libcamera only uses devices udev has processed, and learns of an unplug
# from udev's events.
/lib/systemd/systemd-udevd --daemon
if load_vimc; then
    pass "vimc loaded, udev settled, sensor picture set: $(cat /sys/class/video4linux/*/name | tr '\n' ',')"
else
    fail "vimc: not loaded or sensor controls not set"
    finish
fi

# 1. Streaming, and a control the camera lacks.
mocap-node --source libcamera:0 $NODE_FLAGS >/tmp/node.log 2>&1 &
node_pid=$!
mocap-kernel recv $PORT /tmp/live.dump $node_pid 2000 2000 1.5 >/tmp/recv.log 2>&1 &
recv_pid=$!
if wait_for 30 /tmp/live.dump "^F "; then
    pass "libcamera:0 streams: $(grep -m1 'info: libcamera' /tmp/node.log | sed 's/.*info: //')"
else
    fail "libcamera:0: no frame in 30 s"
fi
sleep 5

# 2. The camera unplugged under the running node: the driver unbound (what a USB unplug does).
# libcamera cannot release a camera whose device vanished, so the node ends with "hardware
# missing" (3) for systemd to restart it; the module can then be removed, loaded again, and a
# node started afresh streams again (the restart a board's systemd unit makes).
echo vimc.0 >/sys/bus/platform/drivers/vimc/unbind
if wait_gone 10 $node_pid; then
    wait $node_pid
    rc=$?
    if [ $rc -eq 3 ]; then
        pass "unplug: node exited with 3 (hardware missing): $(grep -m1 'exiting' /tmp/node.log | sed 's/.*error: //')"
    else
        fail "unplug: node exited with $rc, not 3"
    fi
else
    fail "unplug: the node did not notice within 10 s"
    kill -KILL $node_pid
fi
if rmmod vimc; then pass "vimc removed after the unplug"; else fail "vimc still in use after the node exited"; fi
frames_before=$(grep -c "^F " /tmp/live.dump)
load_vimc || fail "vimc reload"
mocap-node --source libcamera:0 $NODE_FLAGS >/tmp/node2.log 2>&1 &
node_pid=$!
sleep 6
frames_after=$(($(grep -c "^F " /tmp/live.dump) - frames_before))
if [ "$frames_after" -ge 5 ]; then pass "restarted on the reloaded module: $frames_after frames"; else fail "restart: $frames_after frames after the reload"; show node2 /tmp/node2.log; fi
kill -TERM $node_pid
wait $node_pid
rc=$?
[ $rc -eq 0 ] && pass "node exit: status 0 on SIGTERM" || fail "node exit: status $rc"
kill -TERM $recv_pid
wait $recv_pid
grep "^KERNEL:" /tmp/recv.log | sed 's/FIGURE /FIGURE vimc /'

# What the node sent: the static picture gives one marker set, the same in every frame.
n_live=$(frames /tmp/live.dump | wc -l)
n_sets=$(frames /tmp/live.dump | sort -u | wc -l)
n_markers=$(grep -m1 "^F " /tmp/live.dump | cut -d' ' -f8)
if [ "$n_live" -ge 20 ] && [ "$n_sets" -eq 1 ] && [ "$n_markers" -gt 0 ]; then
    pass "markers: $n_live frames, all with the same $n_markers markers"
else
    fail "markers: $n_live frames, $n_sets different marker sets, $n_markers markers in the first"
    show node-status /tmp/node.log | tail -n 3
fi
ack=$(grep -m1 "^A 1 " /tmp/live.dump)
case "$ack" in
"A 1 1 "*) pass "exposure/gain vimc lacks: ControlAck REJECTED (${ack#A 1 1 })" ;;
*) fail "exposure/gain vimc lacks: ack '$ack', not REJECTED" ;;
esac

# 3. The proof: libcamera's own cam tool captures frames of the same stream to files; they are
# turned into a recording and replayed through the node, whose markers must equal the live ones.
fmt=$(sed -n 's/.*libcamera 0 .* \([A-Z0-9]*\), stride.*/\1/p' /tmp/node.log | head -n 1)
size=$(sed -n 's/.*libcamera 0 .*: \([0-9]*x[0-9]*\) .*/\1/p' /tmp/node.log | head -n 1)
mkdir -p /tmp/cam
if cam -c 1 --capture=6 -s width=${size%x*},height=${size#*x},pixelformat=$fmt --file=/tmp/cam/frame-#.bin >/tmp/cam.log 2>&1 &&
    [ "$(ls /tmp/cam | wc -l)" -ge 4 ]; then
    pass "cam captured $(ls /tmp/cam | wc -l) frames of $size $fmt"
else
    fail "cam capture of $size $fmt"
    show cam /tmp/cam.log
fi
# The first frames of a stream may predate the sensor settling: the last four are used.
files=$(ls /tmp/cam/frame-*.bin | sort -t- -k2 -n | tail -n 4)
if mocap-kernel cam2mcf $fmt ${size%x*} ${size#*x} /tmp/replay $files >/tmp/cam2mcf.log 2>&1; then
    mocap-kernel recv $PORT /tmp/replay.dump 1 >/tmp/recv-replay.log 2>&1 &
    recv_pid=$!
    mocap-node --source replay:/tmp/replay --sync sim:30 --as-fast-as-possible $(echo $NODE_FLAGS | sed 's/--sync none//') \
        >/tmp/node-replay.log 2>&1
    sleep 1
    kill -TERM $recv_pid
    wait $recv_pid
    n_replay=$(frames /tmp/replay.dump | wc -l)
    if [ "$n_replay" -eq 4 ] && [ "$(frames /tmp/replay.dump | sort -u)" = "$(frames /tmp/live.dump | sort -u)" ]; then
        show cam2mcf /tmp/cam2mcf.log
        pass "cam's frames replayed through the node: the same $n_markers markers bit for bit in all $n_replay frames"
    else
        fail "cam's frames replayed: $n_replay frames, markers differ from the live stream's"
        show cam2mcf /tmp/cam2mcf.log
        frames /tmp/replay.dump | sort -u | head -c 600
        show node-replay /tmp/node-replay.log
    fi
else
    fail "cam2mcf"
    show cam2mcf /tmp/cam2mcf.log
fi
[ "$failed" -eq 0 ] || { show node /tmp/node.log; show recv /tmp/recv.log; }
finish
