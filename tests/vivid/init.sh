#!/bin/busybox sh
# /init of the vivid test's initramfs (built by run_vivid.sh): loads vivid with a video output
# looped into a video capture device, feeds marker frames into it, runs mocap-node-static against
# the capture device with a receiver on loopback, removes the device under the running node and
# brings it back. Every check prints "VIVID: PASS|FAIL <what>: <detail>" on the serial console,
# then "VIVID: RESULT PASS|FAIL", and the VM powers off; the host script reads those lines.
VM_TAG=VIVID
VM_FINISH_LOGS="node:/tmp/node.log feed:/tmp/feed.log"
. /guest_lib.sh

CAP=/dev/video0
OUT=/dev/video1
PORT=7000
# One instance: video capture (bit 0) and video output (bit 8), one HDMI input and one HDMI
# output (vivid loops only like to like; its S-Video input has no progressive format), at fixed
# device numbers so that the node's --source path is right again after the module is reloaded.
VIVID_OPTS="n_devs=1 node_types=0x101 num_inputs=1 input_types=0x3 num_outputs=1 output_types=0x1 vid_cap_nr=0 vid_out_nr=1"
load_vivid() {
    insmod /lib/modules/vivid.ko $VIVID_OPTS || return 1
    wait_for 5 /sys/class/video4linux/video1/name vid-out
}

for m in $(cat /lib/modules/order); do
    [ "$m" = vivid.ko ] && break
    insmod "/lib/modules/$m" || { fail "modules: insmod $m"; finish; }
done
if load_vivid && grep -q vid-cap /sys/class/video4linux/video0/name; then
    pass "vivid loaded: $(cat /sys/class/video4linux/video0/name) $CAP, $(cat /sys/class/video4linux/video1/name) $OUT"
else
    fail "vivid: no capture and output devices ($(ls /dev | grep video))"
    finish
fi

mocap-vivid recv $PORT >/tmp/recv.log 2>&1 &
recv_pid=$!
mocap-vivid feed $CAP $OUT >/tmp/feed.log 2>&1 &
feed_pid=$!
if wait_for 10 /tmp/feed.log "feed: looping"; then
    pass "output loop: $(grep -m1 'feed: looping' /tmp/feed.log)"
else
    fail "output loop: the feeder never streamed"
    finish
fi

# The subject here is the V4L2 backend: the node sends plain datagrams (the development wire) so
# that mocap-vivid needs no key; the authenticated wire has its own tests (firmware/node/tests).
mocap-node-static --source v4l2:$CAP --sync none --hub 127.0.0.1:$PORT --id 7 --threshold 100 \
    --brightness 75 --contrast 40 --insecure-dev-wire --min-area 4 --status-interval-ms 200 --reopen-min-ms 100 --reopen-max-ms 800 \
    --log-level info >/tmp/node.log 2>&1 &
node_pid=$!
sleep 4

# The device disappears under the running node. rmmod alone is refused while a process holds
# the device open, so the driver is unbound from its platform device first (what an unplug
# does); once the node has closed its descriptor and buffers, the module can go.
if rmmod vivid 2>/tmp/rmmod.err; then
    echo "VIVID: rmmod vivid succeeded while the node held the device"
else
    echo "VIVID: rmmod vivid while streaming: $(cat /tmp/rmmod.err) -> unbinding the driver"
    echo vivid.0 >/sys/bus/platform/drivers/vivid/unbind
    i=0
    until rmmod vivid 2>/dev/null; do
        i=$((i + 1))
        if [ "$i" -ge 50 ]; then
            fail "device removal: vivid still in use 5 s after unbinding (node or feeder holds it)"
            break
        fi
        sleep 0.1
    done
    [ "$i" -lt 50 ] && pass "device removal: vivid unbound and removed under the running node"
fi
sleep 2
if kill -0 $node_pid 2>/dev/null; then
    pass "node survives the lost camera: still running, $(grep -c 'reopening in' /tmp/node.log) failures logged"
else
    fail "node died when the camera disappeared"
fi
if load_vivid; then
    pass "vivid reloaded"
else
    fail "vivid reload"
fi
if wait_for 15 /tmp/node.log "reopened"; then
    pass "node reopened the camera: $(grep -m1 reopened /tmp/node.log)"
else
    fail "node did not reopen the camera within 15 s"
fi
sleep 4

kill -TERM $node_pid
wait $node_pid
rc=$?
if [ "$rc" -eq 0 ]; then pass "node exit: status 0 on SIGTERM"; else fail "node exit: status $rc"; fi
kill -TERM $feed_pid
wait $feed_pid
kill -TERM $recv_pid
wait $recv_pid
recv_rc=$?
grep "^VIVID:" /tmp/recv.log
grep -v "^VIVID:" /tmp/recv.log | sed "s/^/  recv| /"
[ "$recv_rc" -eq 0 ] || failed=$((failed + 1))

# Every format vivid offers that the node reads: the spots fed in that format (chroma neutral,
# R = G = B), the node told to use it (pixel_format), its markers at the fed positions.
NODE_FORMATS="GREY NV12 NV21 YU12 YV12 Y10 Y16 YUYV UYVY BX24 XR24 RGB3 BGR3"
offered=$(mocap-vivid formats $CAP | tr '\n' ' ')
tested=""
for f in $offered; do
    case " $NODE_FORMATS " in *" $f "*) ;; *) continue ;; esac
    mocap-vivid feed $CAP $OUT $f >/tmp/feed-$f.log 2>&1 &
    feed_pid=$!
    if wait_for 10 /tmp/feed-$f.log "feed: looping"; then
        mocap-node-static --source v4l2:$CAP --pixel-format $f --sync none --hub 127.0.0.1:$PORT \
            --id 7 --threshold 100 --insecure-dev-wire --min-area 4 --log-level info >/tmp/node-$f.log 2>&1 &
        node_pid=$!
        if mocap-vivid spots $PORT 3 20 >/tmp/spots-$f.log 2>&1 && grep -q "($f *)" /tmp/node-$f.log; then
            pass "format $f: $(cat /tmp/spots-$f.log)"
            tested="$tested $f"
        else
            fail "format $f: $(cat /tmp/spots-$f.log)"
            show node-$f /tmp/node-$f.log
        fi
        kill -TERM $node_pid
        wait $node_pid
    else
        fail "format $f: the feeder never streamed: $(tail -n 1 /tmp/feed-$f.log)"
    fi
    kill -TERM $feed_pid
    wait $feed_pid
done
untested=""
for f in $offered; do case " $tested " in *" $f "*) ;; *) untested="$untested $f" ;; esac; done
echo "VIVID: formats vivid offers that the node does not read:$untested"
# A format the device does not offer: refused at start, named with what the device offers
# (the first format it lists, as v4l2-ctl names it), "hardware missing" (3).
first=${offered%% *}
mocap-node-static --source v4l2:$CAP --pixel-format MJPG --sync none --hub 127.0.0.1:$PORT \
    --id 7 --insecure-dev-wire >/tmp/node-mjpg.log 2>&1
rc=$?
if [ $rc -eq 3 ] && grep -q "pixel_format MJPG is not offered by the device (it offers $first, " /tmp/node-mjpg.log; then
    pass "format vivid lacks refused: $(grep -m1 'MJPG' /tmp/node-mjpg.log | sed 's/.*error: //')"
else
    fail "format vivid lacks: exit $rc, $(cat /tmp/node-mjpg.log)"
fi

# What the node itself says about the device.
# Picture controls (vivid's Brightness and Contrast are 0..255): set at open, and again at the
# reopen after the device came back.
if [ "$(grep -c "v4l2: brightness 75 % of the camera's range = 191" /tmp/node.log)" -ge 2 ] &&
    grep -q "v4l2: contrast 40 % of the camera's range = 102" /tmp/node.log; then
    pass "picture controls: $(grep -m1 'v4l2: brightness' /tmp/node.log | sed 's/.*info: //'), $(grep -m1 'v4l2: contrast' /tmp/node.log | sed 's/.*info: //')"
else
    fail "picture controls: $(grep 'v4l2: \(brightness\|contrast\)' /tmp/node.log | tr '\n' ' ')"
fi
if grep -q "(GREY), [0-9]* mmap buffers" /tmp/node.log; then
    pass "format negotiation and mmap streaming: $(grep -m1 'mmap buffers' /tmp/node.log | sed 's/.*: \/dev/\/dev/')"
else
    fail "format negotiation: no GREY mmap open in the node's log"
fi
if grep -q "no monotonic time stamps" /tmp/node.log; then
    fail "monotonic time stamps: the node fell back to dequeue time"
else
    pass "monotonic time stamps: the node used the kernel's buffer stamps"
fi
# The loss shows on whichever ioctl comes first (DQBUF: "capture failed", QBUF: "cannot requeue").
loss=$(grep "camera $CAP: .*reopening in" /tmp/node.log | grep -v "reopen failed" | head -n 1)
if [ -n "$loss" ]; then
    pass "camera loss logged: ${loss#*error: }"
else
    fail "camera loss: not in the node's log"
fi
# Backoff: the delays of consecutive failed reopens never shrink, and at least one doubles.
delays=$(grep "reopening in" /tmp/node.log | sed 's/.*reopening in \([0-9]*\) ms.*/\1/' | tr '\n' ' ')
prev=0
grew=no
ok=yes
for d in $delays; do
    [ "$d" -lt "$prev" ] && ok=no
    [ "$prev" -gt 0 ] && [ "$d" -eq $((prev * 2)) ] && grew=yes
    prev=$d
done
if [ "$ok" = yes ] && [ "$grew" = yes ]; then
    pass "reopen backoff: delays $delays(ms)"
else
    fail "reopen backoff: delays $delays(ms)"
fi
finish
