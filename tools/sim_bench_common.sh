# Sourced by tools/serve-bench/serve-bench.sh and tools/stream-bench/stream-bench.sh, the two
# benchmarks that replay a synthetic subject through real mocap-node processes into
# `mocap-hub serve` (deploy/sim-session.sh): the options they share, the subject and its frames,
# and the session run with the hub apart from the nodes. Each script sets its own defaults for
# the variables below before parsing its arguments, and `here` (the checkout) before calling the
# session.

# Takes one option both benchmarks know (NAME VALUE) into its variable: cameras markers rate
# seconds width height realtime bin out. Returns 1 for any other option.
sim_bench_option() {
    case "$1" in
        --cameras) cameras=${2:?} ;;
        --markers) markers=${2:?} ;;
        --rate) rate=${2:?} ;;
        --seconds) seconds=${2:?} ;;
        --width) width=${2:?} ;;
        --height) height=${2:?} ;;
        --realtime-priority) realtime=${2:?} ;;
        --bin) bin=${2:?} ;;
        --out) out=${2:?} ;;
        *) return 1 ;;
    esac
}

# The subject: MARKERS markers for SECONDS at RATE Hz (seed 7) in $out/motion.trc; sets frames.
sim_bench_motion() {
    mkdir -p "$out"
    frames=$(awk -v s="$seconds" -v r="$rate" 'BEGIN { printf "%d", s * r }')
    "$bin/mocap-hub" sim motion -o "$out/motion.trc" --markers "$markers" --frames "$frames" --rate "$rate" \
        --seed 7 > /dev/null
}

# A ring rig of N cameras (WIDTH x HEIGHT) around the subject and its rendered frames:
# DIR/rig.json and DIR/frames. usage: sim_bench_render DIR N
sim_bench_render() {
    mkdir -p "$1"
    "$bin/mocap-hub" sim rig --motion "$out/motion.trc" --cameras "$2" --width "$width" --height "$height" \
        -o "$1/rig.json" > /dev/null
    rm -rf "$1/frames"
    "$bin/mocap-hub" sim render --motion "$out/motion.trc" --rig "$1/rig.json" -o "$1/frames" \
        --occlusion 0.02 --noise 1.5 > /dev/null
}

# deploy/sim-session.sh on FRAMES_DIR into OUT_DIR, its JSON figures on stdout. The hub runs on
# CPU 0 (at nice -5 when root, as deploy/mocap-hub.service runs it) with the 3 mm ray gate and
# the real-time priority asked for, plus EXTRA serve options; the nodes on the other CPUs.
# usage: sim_bench_session FRAMES_DIR OUT_DIR "EXTRA SERVE OPTIONS"
sim_bench_session() {
    local cpus node_cpus
    local hub_nice=()
    [ "$(id -u)" != 0 ] || hub_nice=(--hub-nice -5)
    cpus=$(nproc)
    node_cpus=$([ "$cpus" -gt 1 ] && echo "1-$((cpus - 1))" || echo 0)
    "$here/deploy/sim-session.sh" --frames-dir "$1" --out "$2" --bin "$bin" \
        --hub-cpus 0 "${hub_nice[@]}" --node-cpus "$node_cpus" --json \
        --serve-args "--max-ray-distance-mm 3 --realtime-priority $realtime $3"
}
