#!/usr/bin/env bash
# README command (1): the main job on a simulated rig. Builds the programs, places an 8-camera
# ring around a walking subject, projects the markers into every camera with realistic faults,
# reconstructs and tracks them into a TRC and prints its accuracy against the truth.
# Environment: MOCAP_BUILD_DIR (default build), MOCAP_SIM_DIR (default sim-run),
# MOCAP_MOTION (a TRC to use instead of the default walk), MOCAP_CAMERAS (default 8).
set -euo pipefail
cd "$(dirname "$0")/.."

build=${MOCAP_BUILD_DIR:-build}
out=${MOCAP_SIM_DIR:-sim-run}
cameras=${MOCAP_CAMERAS:-8}

cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$build.configure.log" 2>&1 \
    || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -j "$(nproc)" --target mocap-hub
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

"$hub" sim rig --motion "$motion" --cameras "$cameras" -o "$out/rig.json"
rm -rf "$out/session"
"$hub" sim project --motion "$motion" --rig "$out/rig.json" -o "$out/session" \
    --noise-px 0.2 --occlusion 0.05 --occlusion-frames 5 --spurious 2 --drop-frames 0.002 --seed 1
"$hub" reconstruct "$out/session" --calibration "$out/rig.json" -o "$out/session/markers.trc"
echo
echo "path: simulated 2D session (sim project) -> reconstruct; rendered frames through mocap-node"
echo "      processes over UDP are the end-to-end step still being built"
echo "TRC:  $out/session/markers.trc"
"$hub" eval --truth "$out/session/truth.trc" --result "$out/session/markers.trc" --session "$out/session"
