#!/usr/bin/env bash
# README command (1): the main job on a simulated rig. Builds the programs, places an 8-camera
# ring around a walking subject and, by default, runs it end to end as real processes: renders
# every camera's frames, replays them through one mocap-node per camera (own network namespace
# when possible) to mocap-hub serve over UDP, reconstructs the TRC and prints its accuracy and
# latency (deploy/sim-session.sh). MOCAP_SIM_PATH=project runs the 2D-projection path instead.
# Environment: MOCAP_BUILD_DIR (default build), MOCAP_SIM_DIR (default sim-run),
# MOCAP_MOTION (a TRC to use instead of the default walk), MOCAP_CAMERAS (default 8),
# MOCAP_SIM_PATH (e2e, the default, or project).
set -euo pipefail
cd "$(dirname "$0")/.."

build=${MOCAP_BUILD_DIR:-build}
out=${MOCAP_SIM_DIR:-sim-run}
cameras=${MOCAP_CAMERAS:-8}
path=${MOCAP_SIM_PATH:-e2e}
case "$path" in
    e2e|project) ;;
    *) echo "run-sim: error: MOCAP_SIM_PATH must be e2e or project, not '$path'" >&2; exit 1 ;;
esac

mkdir -p "$build"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$build/configure.log" 2>&1 \
    || { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)" --target mocap-hub mocap-node
hub="$build/bin/mocap-hub"
mkdir -p "$out"

motion=${MOCAP_MOTION:-}
if [ -z "$motion" ]; then
    if [ -f ../shared/data/motions/walk.trc ]; then
        motion=../shared/data/motions/walk.trc
        echo "motion: recorded walk (../shared/data/motions/walk.trc)"
    else
        motion="$out/walk.trc"
        "$hub" sim motion -o "$motion" --markers 40 --frames 300 --rate 120 --up y
        echo "motion: synthetic walker ($motion); ../shared/data is not beside this checkout"
    fi
fi

if [ "$path" = e2e ]; then
    echo "path: rendered frames -> $cameras mocap-node processes -> mocap-hub serve (UDP) -> reconstruct -> eval"
    deploy/sim-session.sh --motion "$motion" --cameras "$cameras" --out "$out" --bin "$build/bin"
    echo
    echo "TRC:  $out/session/filled.trc"
    exit 0
fi

"$hub" sim rig --motion "$motion" --cameras "$cameras" -o "$out/rig.json"
rm -rf "$out/session"
"$hub" sim project --motion "$motion" --rig "$out/rig.json" -o "$out/session" \
    --noise-px 0.2 --occlusion 0.05 --occlusion-frames 5 --spurious 2 --drop-frames 0.002 --seed 1
"$hub" reconstruct "$out/session" --calibration "$out/rig.json" -o "$out/session/markers.trc"
echo
echo "path: simulated 2D session (sim project) -> reconstruct (no frames, no node processes)"
echo "TRC:  $out/session/markers.trc"
"$hub" eval --truth "$out/session/truth.trc" --result "$out/session/markers.trc" --session "$out/session"
