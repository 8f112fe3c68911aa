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
# usage: tools/serve-bench/serve-bench.sh [--cameras "8 16 32"] [--markers 60] [--rate 240]
#                                         [--seconds 4] [--width 1280 --height 800]
#                                         [--serve-args "EXTRA SERVE OPTIONS"] [--realtime-priority N]
#                                         [--bin build/bin] [--out serve-bench]
set -euo pipefail
cameras="8 16 32" markers=60 rate=240 seconds=4 bin=build/bin out=serve-bench width=1280 height=800
serve_args=""
realtime=$([ "$(id -u)" = 0 ] && echo 10 || echo 0)
here=$(cd "$(dirname "$0")/../.." && pwd)
. "$here/tools/sim_bench_common.sh"
while [ $# -gt 0 ]; do
    case "$1" in
        --serve-args) serve_args=${2?}; shift 2 ;;
        -h|--help) sed -n 2,16p "$0"; exit 0 ;;
        *) sim_bench_option "$@" || { echo "serve-bench: unknown argument '$1'" >&2; exit 1; }; shift 2 ;;
    esac
done
sim_bench_motion
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
