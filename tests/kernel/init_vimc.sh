#!/bin/busybox sh
# /init of the kernel test's vimc VM (run_kernel.sh vimc).
. /init_lib.sh
export LIBCAMERA_LOG_LEVELS='*:WARN'
export LTTNG_UST_REGISTER_TIMEOUT=0
PORT=7000

if load_modules_until vimc.ko && wait_for 5 /sys/class/video4linux/video0/name .; then
    pass "vimc loaded: $(cat /sys/class/video4linux/*/name | tr '\n' ',')"
else
    fail "vimc: not loaded"
    finish
fi
ls -l /dev/media* /dev/video* /dev/v4l-subdev*
cam -l 2>&1
cam -c 1 -I 2>&1 | head -40
mocap-node --source libcamera:0 --sync none --hub 127.0.0.1:$PORT --id 7 --threshold 100 \
    --insecure-dev-wire --status-interval-ms 200 --reopen-min-ms 100 --reopen-max-ms 800 \
    --width 640 --height 480 --log-level debug >/tmp/node.log 2>&1 &
node_pid=$!
mocap-kernel recv $PORT /tmp/live.dump $node_pid 2000 2000 2 >/tmp/recv.log 2>&1 &
recv_pid=$!
sleep 8
kill -TERM $node_pid
wait $node_pid
echo "node rc $?"
kill -TERM $recv_pid
wait $recv_pid
show node /tmp/node.log
show recv /tmp/recv.log
head -c 3000 /tmp/live.dump
finish
