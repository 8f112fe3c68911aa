#!/usr/bin/env bash
# Hub-internal latency of the live hub at scale: for each camera count, a synthetic subject of
# MARKERS markers at RATE Hz is rendered and replayed through real mocap-node processes (one per
# camera, each in its own network namespace when root) into `mocap-hub serve`
# (deploy/sim-session.sh), and serve's own figures are printed: last datagram of a frame set
# received (kernel time) -> its 3D result published (complete sets), p50 / p99 / max, and the
# reconstruction + tracking time alone, beside the frame sets assembled (incomplete: a camera
# missed the deadline) and the live result's accuracy. Milliseconds.
# The hub runs on CPU 0 (at nice -5 and its frame loop at real-time priority 10 when root, as
# deploy/mocap-hub.service and hub.conf.example run it; --realtime-priority 0 turns that off) and the nodes
# on the others (taskset), so the figure is the hub's, not the scheduler's: on a small machine
# the nodes' detection would otherwise starve it. Images are 1280x800 by default (--width/--height).
# --skeleton labels|solve replaces the synthetic subject by `skeleton sim`'s walking subject (the
# 41-marker HDM05 set with a toe marker per foot: 43 markers, 20 segments; --markers is then
# ignored) named by a marker set learned from its truth (serve --labels); `solve` also solves its
# skeleton live (serve --skeleton): the two runs' difference is what the live skeleton adds.
# usage: tools/serve-bench/serve-bench.sh [--cameras "8 16 32"] [--markers 60] [--rate 240]
#                                         [--seconds 4] [--width 1280 --height 800]
#                                         [--skeleton labels|solve]
#                                         [--serve-args "EXTRA SERVE OPTIONS"] [--realtime-priority N]
#                                         [--bin build/bin] [--out serve-bench]
set -euo pipefail
cameras="8 16 32" markers=60 rate=240 seconds=4 bin=build/bin out=serve-bench width=1280 height=800
serve_args="" skeleton=""
realtime=$([ "$(id -u)" = 0 ] && echo 10 || echo 0)
here=$(cd "$(dirname "$0")/../.." && pwd)
. "$here/tools/sim_bench_common.sh"
while [ $# -gt 0 ]; do
    case "$1" in
        --serve-args) serve_args=${2?}; shift 2 ;;
        --skeleton) skeleton=${2?}; shift 2 ;;
        -h|--help) sed -n 2,20p "$0"; exit 0 ;;
        *) sim_bench_option "$@" || { echo "serve-bench: unknown argument '$1'" >&2; exit 1; }; shift 2 ;;
    esac
done
if [ -z "$skeleton" ]; then
    sim_bench_motion
else
    case "$skeleton" in labels|solve) ;; *) echo "serve-bench: --skeleton must be labels or solve" >&2; exit 1 ;; esac
    # The subject's names as a one-frame TRC (what `skeleton template --trc` reads).
    names="LFHD RFHD LBHD RBHD C7 T10 CLAV STRN RBAC LSHO LUPA LELB LFRM LWRA LWRB LFIN RSHO RUPA RELB RFRM RWRA"
    names="$names RWRB RFIN LFWT RFWT LBWT RBWT LTHI LKNE LSHN LANK LHEE LTOE LMT5 RTHI RKNE RSHN RANK RHEE RTOE"
    names="$names RMT5 LTOT RTOT"
    mkdir -p "$out"
    python3 - "$out/names.trc" $names <<'PY'
import sys
names = sys.argv[2:]
with open(sys.argv[1], "w") as f:
    f.write("PathFileType\t4\t(X/Y/Z)\tnames.trc\n")
    f.write("DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n")
    f.write("60\t60\t1\t%d\tmm\t60\t1\t1\n" % len(names))
    f.write("Frame#\tTime\t" + "\t\t\t".join(names) + "\t\t\t\n")
    f.write("\t\t" + "\t".join("X%d\tY%d\tZ%d" % (i + 1, i + 1, i + 1) for i in range(len(names))) + "\n\n")
    f.write("1\t0\t" + "\t".join("%d\t%d\t%d" % (i, i, 1000 + i) for i in range(len(names))) + "\n")
PY
    "$bin/mocap-hub" skeleton template --trc "$out/names.trc" -o "$out/template.json" > /dev/null
    rm -rf "$out/subject"
    "$bin/mocap-hub" skeleton sim "$out/template.json" -o "$out/subject" --motion gait --duration "$seconds" \
        --rate "$rate" --seed 7 > /dev/null
    cp "$out/subject/truth.trc" "$out/motion.trc"
    "$bin/mocap-hub" labels learn "$out/motion.trc" -o "$out/labels.json" > /dev/null
    markers=43
    serve_args="$serve_args --labels $out/labels.json"
    [ "$skeleton" != solve ] || serve_args="$serve_args --skeleton $out/subject/truth.skeleton.json"
fi
printf "%7s %7s %6s %10s %11s %11s %11s %11s %11s %11s %13s %12s\n" cameras markers rate "sets" "incomplete" \
    "hub p50" "hub p99" "hub max" "proc p50" "proc p99" "live missing" "live ghosts"
for n in $cameras; do
    sim_bench_render "$out/c$n" "$n"
    sim_bench_session "$out/c$n/frames" "$out/c$n" "$serve_args" > "$out/c$n.json" 2> "$out/c$n.log"
    python3 - "$out/c$n.json" "$n" "$markers" "$rate" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
lat, live = d["latency_ms"], d["live"]
print("%7s %7s %6s %4d/%-5d %11d %11.3f %11.3f %11.3f %11.3f %11.3f %13.4f %12.4f" % (
    sys.argv[2], sys.argv[3], sys.argv[4], d["frame_sets"], d["frames"], lat["incomplete_frame_sets"],
    lat["hub_p50"], lat["hub_p99"], lat["hub_max"], lat["processing_p50"], lat["processing_p99"],
    live["missing_per_frame"], live["ghosts_per_frame"]))
PY
done
