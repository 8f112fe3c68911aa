#!/bin/sh
# Detection speed per camera pixel format (the figures in firmware/README.md, "Pixel formats"):
# synthetic marker frames from mocap-detect-bench --make-frames at a webcam's 640x480 and a
# board sensor's 1280x800, each timed with --formats (the node's conversion to luma, or MJPEG
# decode, plus detection). Usage: tools/detect-bench/formats.sh [BUILD_DIR] [REPEAT]
set -eu
build=${1:-build}
repeat=${2:-20}
bench=$build/bin/mocap-detect-bench
[ -x "$bench" ] || bench=$(find "$build" -name mocap-detect-bench -type f -perm -u+x | head -n 1)
[ -x "$bench" ] || { echo "formats.sh: no mocap-detect-bench under $build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for size in 640x480 1280x800; do
    w=${size%x*}
    h=${size#*x}
    "$bench" --make-frames "$work/$size" --count 30 --markers 30 --width "$w" --height "$h" \
        --seed 1 >/dev/null
    echo "== $size, 30 markers, 30 frames, best of $repeat passes"
    "$bench" --frames "$work/$size" --formats --repeat "$repeat" | sed -n '/^format/,$p'
done
