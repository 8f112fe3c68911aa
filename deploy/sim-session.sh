#!/usr/bin/env bash
# Simulated capture session as real processes, driven as an operator drives an installation:
# renders (or reuses) camera frames, starts the live hub (`mocap-hub serve`) and one `mocap-node`
# per camera replaying its frames with a simulated trigger on a shared epoch (each node in its
# own network namespace when possible), prints the node table, captures the session with
# `capture start`/`capture stop`, fills gaps with `reconstruct` and evaluates both the live result
# (every point serve published, as published) and the final TRC against the truth.
set -euo pipefail

usage() {
    cat <<'EOF'
usage: deploy/sim-session.sh --motion M.trc | --frames-dir DIR   [options]
  --motion M.trc       render this motion (ring rig of --cameras cameras) into OUT/frames
  --frames-dir DIR     reuse frames written by `mocap-hub sim render` (cam<ID>/, truth.trc,
                       calibration.json, visibility.tsv); --motion is then not needed
  --cameras N          cameras of the rendered rig (default 8)
  --out DIR            session output directory (default sim-session)
  --bin DIR            where mocap-hub and mocap-node are (default build/bin)
  --render-args "..."  extra `sim render` options (default "--occlusion 0.02 --noise 1.5")
  --reconstruct-args "..."  extra `reconstruct` options for the final TRC (default
                       "--max-ray-distance-mm 3": rendered centroids are precise to ~0.1 px)
  --serve-args "..."   extra `serve` options for the live result (default the same gate)
  --hub-cpus LIST      run serve on these CPUs only (taskset list, e.g. 0), so that benchmarks
  --node-cpus LIST     measure the hub apart from the node processes sharing its machine
  --hub-nice N         run serve at this nice value (deploy/mocap-hub.service runs it at -5;
                       below 0 needs root)
  --threshold T        node detection threshold (default 32: background 12, noise sigma 1.5)
  --network MODE       netns: one network namespace + veth per node (default when root and
                       `ip netns` works); loopback: every node on 127.0.0.1; auto (default)
  --json               print the final figures as one JSON object on stdout
Exit status: 0 done, 1 bad arguments or a step failed.
EOF
}

die() { echo "sim-session: error: $*" >&2; exit 1; }

motion="" frames_dir="" cameras=8 out=sim-session bin=build/bin threshold=32 network=auto json=0
reconstruct_args="--max-ray-distance-mm 3"
serve_args="--max-ray-distance-mm 3"
hub_cpus="" node_cpus="" hub_nice=""
render_args="--occlusion 0.02 --noise 1.5"
while [ $# -gt 0 ]; do
    case "$1" in
        --motion) motion=${2:?}; shift 2 ;;
        --frames-dir) frames_dir=${2:?}; shift 2 ;;
        --cameras) cameras=${2:?}; shift 2 ;;
        --out) out=${2:?}; shift 2 ;;
        --bin) bin=${2:?}; shift 2 ;;
        --render-args) render_args=${2?}; shift 2 ;;
        --reconstruct-args) reconstruct_args=${2?}; shift 2 ;;
        --serve-args) serve_args=${2?}; shift 2 ;;
        --hub-cpus) hub_cpus=${2:?}; shift 2 ;;
        --hub-nice) hub_nice=${2:?}; shift 2 ;;
        --node-cpus) node_cpus=${2:?}; shift 2 ;;
        --threshold) threshold=${2:?}; shift 2 ;;
        --network) network=${2:?}; shift 2 ;;
        --json) json=1; shift ;;
        -h|--help) usage; exit 0 ;;
        *) usage >&2; die "unknown argument '$1'" ;;
    esac
done
hub="$bin/mocap-hub"
node="$bin/mocap-node"
[ -x "$hub" ] || die "$hub not found (build it first, or pass --bin)"
[ -x "$node" ] || die "$node not found (build it first, or pass --bin)"
case "$network" in auto|netns|loopback) ;; *) die "--network must be auto, netns or loopback" ;; esac
[[ "$cameras" =~ ^[0-9]+$ ]] && [ "$cameras" -ge 2 ] || die "--cameras must be a number >= 2"
[[ -z "$hub_nice" || "$hub_nice" =~ ^-?[0-9]+$ ]] || die "--hub-nice must be a whole number"
[[ "$threshold" =~ ^[0-9]+$ ]] || die "--threshold must be a number 1..255"
log() { [ "$json" = 1 ] && echo "$*" >&2 || echo "$*"; }

mkdir -p "$out"
if [ -z "$frames_dir" ]; then
    [ -n "$motion" ] || die "give --motion M.trc or --frames-dir DIR"
    [ -f "$motion" ] || die "$motion: no such motion file"
    frames_dir="$out/frames"
    rm -rf "$frames_dir"
    "$hub" sim rig --motion "$motion" --cameras "$cameras" -o "$out/rig.json" >&2
    # shellcheck disable=SC2086  # render_args is a list of options
    "$hub" sim render --motion "$motion" --rig "$out/rig.json" -o "$frames_dir" $render_args >&2
fi
for f in truth.trc calibration.json visibility.tsv; do
    [ -f "$frames_dir/$f" ] || die "$frames_dir/$f missing (not written by mocap-hub sim render?)"
done
# Rate and frame count from the truth TRC's header (line 3: DataRate CameraRate NumFrames ...).
read -r rate frames < <(awk 'NR == 3 { print $1, $3 }' "$frames_dir/truth.trc")
[[ "$frames" =~ ^[0-9]+$ ]] && [ "$frames" -gt 0 ] || die "$frames_dir/truth.trc: cannot read the frame count"
ids=()
for d in "$frames_dir"/cam*/; do
    [ -f "$d/frames.mcf" ] && ids+=("$(basename "$d" | sed 's/^cam//')")
done
[ "${#ids[@]}" -ge 2 ] || die "$frames_dir: fewer than two cam<ID>/frames.mcf"

# ---- the simulated rig's wire keys: one per node, new for every session (never committed) ----
keys="$out/keys"
rm -rf "$keys"
"$hub" keys new "${ids[@]}" --out "$keys" > /dev/null || die "cannot generate the wire keys"

# ---- network: one namespace per node with its own address, or loopback ----
session_tag=$$
netns_ok=0
if [ "$network" != loopback ]; then
    # The probe needs both a namespace and a veth pair (some containers allow one, not the other).
    if [ "$(id -u)" = 0 ] && command -v ip > /dev/null && ip netns add "mocap-probe-$session_tag" 2> /dev/null; then
        if ip link add "mp${session_tag}a" type veth peer name "mp${session_tag}b" 2> /dev/null; then
            ip link del "mp${session_tag}a" 2> /dev/null || true
            netns_ok=1
        fi
        ip netns del "mocap-probe-$session_tag"
    fi
    if [ "$netns_ok" != 1 ] && [ "$network" = netns ]; then
        die "network namespaces are unavailable (needs root, iproute2's ip netns and veth)"
    elif [ "$netns_ok" != 1 ]; then
        log "network: namespaces unavailable (needs root, ip netns and veth); every node sends over loopback"
    fi
fi
namespaces=()
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2> /dev/null || true; done
    for ns in "${namespaces[@]}"; do ip netns del "$ns" 2> /dev/null || true; done
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# The live hub picks free ports (UDP for the nodes, HTTP for the CLI) and reports them.
session="$out/session"
rm -rf "$session"
# Frame 0 a few seconds ahead, so every process is up before the first trigger.
epoch=$(( $(date +%s%N) + 3000000000 ))
: > "$out/serve.log"
# shellcheck disable=SC2086  # serve_args is a list of options
hub_pin=() node_pin=()
[ -z "$hub_nice" ] || hub_pin=(nice -n "$hub_nice")
[ -z "$hub_cpus" ] || hub_pin+=(taskset -c "$hub_cpus")
[ -z "$node_cpus" ] || node_pin=(taskset -c "$node_cpus")
"${hub_pin[@]}" "$hub" serve --listen 0.0.0.0:0 --api 127.0.0.1:0 --calibration "$frames_dir/calibration.json" \
    --sessions-dir "$out" --api-auth "$out/.api-auth" --rate "$rate" --epoch-ns "$epoch" --keys "$keys" $serve_args \
    > /dev/null 2> "$out/serve.log" &
hub_pid=$!
pids+=("$hub_pid")
port="" api_port=""
for _ in $(seq 100); do
    port=$(sed -n 's/.*UDP port \([0-9]*\) for the nodes.*/\1/p' "$out/serve.log" | head -1)
    api_port=$(sed -n 's/.*API http:[^ ]*:\([0-9]*\),.*/\1/p' "$out/serve.log" | head -1)
    [ -n "$port" ] && [ -n "$api_port" ] && break
    kill -0 "$hub_pid" 2> /dev/null || { cat "$out/serve.log" >&2; die "mocap-hub serve failed"; }
    sleep 0.05
done
[ -n "$port" ] && [ -n "$api_port" ] || die "mocap-hub serve did not report its ports"
export MOCAP_HUB_API="127.0.0.1:$api_port" MOCAP_HUB_TOKEN_FILE="$out/.api-auth/operator.token"
"$hub" capture start session > /dev/null || die "capture start failed"

prefix=$(( session_tag % 200 + 20 ))
i=0
for id in "${ids[@]}"; do
    i=$((i + 1))
    run=()
    hub_addr=127.0.0.1
    if [ "$netns_ok" = 1 ]; then
        # A /30 per node: hub side .1 on the host, node side .2 in the namespace.
        ns="mocap-$session_tag-$id"
        host_if="mh${session_tag}x$i"
        node_if="mn${session_tag}x$i"
        host_if=${host_if:0:15} node_if=${node_if:0:15}
        namespaces+=("$ns")
        { ip netns add "$ns" &&
          ip link add "$host_if" type veth peer name "$node_if" &&
          ip link set "$node_if" netns "$ns" &&
          ip addr add "10.$prefix.$i.1/30" dev "$host_if" &&
          ip link set "$host_if" up &&
          ip -n "$ns" addr add "10.$prefix.$i.2/30" dev "$node_if" &&
          ip -n "$ns" link set "$node_if" up &&
          ip -n "$ns" link set lo up; } ||
            die "network namespace for node $id could not be set up (try --network loopback)"
        hub_addr="10.$prefix.$i.1"
        run=(ip netns exec "$ns")
    fi
    "${run[@]}" "${node_pin[@]}" "$node" --source "replay:$frames_dir/cam$id" --sync "sim:$rate" --epoch-ns "$epoch" \
        --hub "$hub_addr:$port" --id "$id" --key-file "$keys/node-$id.key" --threshold "$threshold" --log-level warning \
        > "$out/node$id.log" 2>&1 &
    pids+=("$!")
done
if [ "$netns_ok" = 1 ]; then
    log "network: ${#ids[@]} nodes, each in its own namespace (10.$prefix.N.2 -> hub 10.$prefix.N.1:$port)"
else
    log "network: ${#ids[@]} nodes on loopback -> hub 127.0.0.1:$port"
fi
log "session: ${#ids[@]} cameras x $frames frames at $rate Hz from $frames_dir"

# The operator's view once every node is up.
for _ in $(seq 200); do
    running=$("$hub" nodes --json | grep -c '"state": "running"' || true)
    [ "$running" -ge "${#ids[@]}" ] && break
    sleep 0.05
done
# ...and once frames flow (the table shows a node still waiting for its first trigger as such).
for _ in $(seq 100); do
    waiting=$("$hub" nodes --json | grep -c '"frames_sent": 0,' || true)
    [ "$waiting" -eq 0 ] && break
    sleep 0.05
done
if [ "$json" = 1 ]; then "$hub" nodes >&2; else "$hub" nodes; fi

# Nodes end with their recording; allow the replay's length plus start-up and a margin.
limit=$(awk -v n="$frames" -v r="$rate" 'BEGIN { printf "%d", n / r + 15 }')
failed=0
start=$SECONDS
for p in "${pids[@]:1}"; do
    while kill -0 "$p" 2> /dev/null && [ $((SECONDS - start)) -lt "$limit" ]; do sleep 0.2; done
    if kill -0 "$p" 2> /dev/null; then kill -INT "$p" 2> /dev/null || true; fi
    wait "$p" || failed=1
done
[ "$failed" = 0 ] || log "warning: a node exited with an error (see $out/node*.log)"
sleep 0.2  # the last frame sets' deadline
"$hub" capture stop > /dev/null || die "capture stop failed"
status=$("$hub" status --json)
kill -TERM "$hub_pid" 2> /dev/null || true
wait "$hub_pid" || { cat "$out/serve.log" >&2; die "mocap-hub serve failed"; }
pids=()
[ -s "$session/live_points.tsv" ] || die "$session/live_points.tsv was not written"

# Gap filling needs hindsight: reconstruct the recorded 2D log again offline.
# shellcheck disable=SC2086  # reconstruct_args is a list of options
"$hub" reconstruct "$session" --calibration "$frames_dir/calibration.json" -o "$session/filled.trc" $reconstruct_args \
    > "$out/reconstruct.log" 2>&1 \
    || { cat "$out/reconstruct.log" >&2; die "reconstruct failed"; }
live=$("$hub" eval --truth "$frames_dir/truth.trc" --result "$session/live_points.tsv" --visibility "$frames_dir/visibility.tsv" --json)
filled=$("$hub" eval --truth "$frames_dir/truth.trc" --result "$session/filled.trc" --visibility "$frames_dir/visibility.tsv" --json)
sets=$(python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); print(d["frame_sets"])' "$session/session.json")
latency=$(python3 -c '
import json, sys
s = json.loads(sys.argv[1])
n, h, p = s["node_latency_ms"], s["hub_latency_ms"], s["processing_ms"]
figures = {"trigger_to_send_p50": n["p50"], "trigger_to_send_p99": n["p99"],
           "hub_p50": h["p50"], "hub_p99": h["p99"], "hub_max": h["max"],
           "processing_p50": p["p50"], "processing_p99": p["p99"], "processing_max": p["max"],
           **({"stream_p50": t["p50"], "stream_p99": t["p99"], "stream_max": t["max"]}
              if (t := s.get("stream", {}).get("publish_to_sent_ms", {})).get("frames") else {})}
# Microseconds are the resolution that matters; more digits are noise.
print(json.dumps({**{k: round(v, 3) for k, v in figures.items()},
                  "incomplete_frame_sets": s["incomplete_frame_sets"]}))' "$status")

if [ "$json" = 1 ]; then
    printf '{"trc": "%s", "live_points": "%s", "cameras": %d, "frames": %d, "rate_hz": %s, "network": "%s", "frame_sets": %s, "latency_ms": %s, "live": %s, "filled": %s}\n' \
        "$session/filled.trc" "$session/live_points.tsv" "${#ids[@]}" "$frames" "$rate" \
        "$([ "$netns_ok" = 1 ] && echo netns || echo loopback)" "$sets" "$latency" "$live" "$filled"
else
    echo "frame sets: $sets"
    python3 -c '
import json, sys
l = json.loads(sys.argv[1])
print("latency (ms): trigger -> node sent p50 %.3f p99 %.3f; last datagram -> 3D published p50 %.3f p99 %.3f max %.3f"
      % (l["trigger_to_send_p50"], l["trigger_to_send_p99"], l["hub_p50"], l["hub_p99"], l["hub_max"]))
print("              processing p50 %.3f p99 %.3f max %.3f; incomplete frame sets %d"
      % (l["processing_p50"], l["processing_p99"], l["processing_max"], l["incomplete_frame_sets"]))
if "stream_p50" in l:
    print("              published -> sent to stream clients p50 %.3f p99 %.3f max %.3f"
          % (l["stream_p50"], l["stream_p99"], l["stream_max"]))' "$latency"
    echo
    echo "live result (every point serve published, as published): $session/live_points.tsv"
    "$hub" eval --truth "$frames_dir/truth.trc" --result "$session/live_points.tsv" --visibility "$frames_dir/visibility.tsv"
    echo
    echo "final TRC (reconstructed from the recorded 2D log, gaps filled): $session/filled.trc"
    "$hub" eval --truth "$frames_dir/truth.trc" --result "$session/filled.trc" --visibility "$frames_dir/visibility.tsv"
fi
