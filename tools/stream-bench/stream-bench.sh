#!/usr/bin/env bash
# Latency per protocol, trigger edge -> received by a client: a synthetic subject of MARKERS
# markers at RATE Hz, rendered for CAMERAS cameras and replayed through real mocap-node
# processes (deploy/sim-session.sh: nodes in network namespaces when root, hub pinned to CPU 0 at nice -5 and its
# frame loop at real-time priority 10 when root, as deploy/mocap-hub.service runs it; --realtime-priority 0 turns
# that off; nodes to the others) into `mocap-hub serve`, with probe clients on loopback (the C stream client at
# the same real-time priority, as a control loop that consumes it would run):
#   stream  the C client's example (clients/c), which also prints publish -> received: what the
#           stream adds to the hub's own latency
#   osc     python-osc from .venv (tests/requirements.txt), an independent OSC implementation
#   qtm-rt  Qualisys' own Python client (qtm-rt, .venv) on the RT server's TCP stream
# beside serve's own hub-internal figures: last datagram -> published, and the stream's own cost
# on the hub (published -> its last datagram handed to the kernel). Milliseconds, p50 p99 max.
# usage: tools/stream-bench/stream-bench.sh [--cameras 16] [--markers 60] [--rate 240]
#                                           [--seconds 4] [--width 640 --height 400]
#                                           [--realtime-priority N] [--bin build/bin] [--out stream-bench]
set -euo pipefail
cameras=16 markers=60 rate=240 seconds=4 bin=build/bin out=stream-bench width=640 height=400
realtime=$([ "$(id -u)" = 0 ] && echo 10 || echo 0)
here=$(cd "$(dirname "$0")/../.." && pwd)
. "$here/tools/sim_bench_common.sh"
while [ $# -gt 0 ]; do
    case "$1" in
        -h|--help) sed -n 2,16p "$0"; exit 0 ;;
        *) sim_bench_option "$@" || { echo "stream-bench: unknown argument '$1'" >&2; exit 1; }; shift 2 ;;
    esac
done
python=$here/.venv/bin/python
[ -x "$python" ] || { echo "stream-bench: $python missing (tests/run.sh creates it)" >&2; exit 1; }
sim_bench_motion
probe_frames=$((frames - rate / 2))  # what arrives once every node is up
sim_bench_render "$out" "$cameras"

stream_port=17802 osc_port=17810 qtm_port=17822
pids=()
trap 'kill "${pids[@]}" 2> /dev/null || true' EXIT
probe_rt=()
[ "$realtime" = 0 ] || probe_rt=(chrt -f "$realtime")
"${probe_rt[@]}" "$bin/mocap_stream_print" 127.0.0.1 "$stream_port" "$probe_frames" 30 > "$out/stream.txt" 2> "$out/stream.err" &
pids+=($!)
"$python" "$here/tools/stream-bench/osc_probe.py" "$osc_port" "$probe_frames" 30 > "$out/osc.txt" 2> "$out/osc.err" &
pids+=($!)
"$python" "$here/tools/stream-bench/qtm_probe.py" "$qtm_port" "$probe_frames" 30 > "$out/qtm.txt" 2> "$out/qtm.err" &
pids+=($!)
sim_bench_session "$out/frames" "$out/session" \
    "--stream 127.0.0.1:$stream_port --osc 127.0.0.1:$osc_port --qtm-rt 127.0.0.1:$qtm_port" \
    > "$out/session.json" 2> "$out/session.log"
for p in "${pids[@]}"; do wait "$p" || true; done
trap - EXIT

printf "%s cameras x %s markers at %s Hz, %s frames; ms from the trigger edge (hub: last datagram)\n" \
    "$cameras" "$markers" "$rate" "$frames"
printf "%-34s %8s %8s %8s\n" path p50 p99 max
python3 - "$out/session.json" <<'PY'
import json, sys
lat = json.load(open(sys.argv[1]))["latency_ms"]
print("%-34s %8.3f %8.3f %8.3f" % ("hub: last datagram -> published", lat["hub_p50"], lat["hub_p99"], lat["hub_max"]))
if "stream_p50" in lat:
    print("%-34s %8.3f %8.3f %8.3f" % ("stream: published -> sent (hub)", lat["stream_p50"], lat["stream_p99"], lat["stream_max"]))
PY
line() {  # label file key
    local v
    v=$(sed -n "s/^$3 //p" "$2")
    if [ -n "$v" ]; then
        # shellcheck disable=SC2086
        printf "%-34s %8s %8s %8s\n" "$1" $v
    else
        printf "%-34s %s\n" "$1" "no frames (see ${2%.txt}.err)"
    fi
}
line "stream (C client): trigger -> recv" "$out/stream.txt" trigger_to_receive_ms
line "stream: published -> received" "$out/stream.txt" publish_to_receive_ms
line "OSC (python-osc): trigger -> recv" "$out/osc.txt" trigger_to_receive_ms
line "Qualisys RT (qtm-rt): trigger -> recv" "$out/qtm.txt" trigger_to_receive_ms
