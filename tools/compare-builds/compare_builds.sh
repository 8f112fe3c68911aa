#!/usr/bin/env bash
# compare_builds.sh BIN_A BIN_B WORK [EXTRA_RECONSTRUCT_ARGS_B]: the shared motions (8 cameras) and dense (10 cameras) with the usual
# faults, reconstructed by two builds from the same sessions (B with the extra options, e.g.
# "--contested-groups"); eval's figures of each side by side with the reconstruct's wall time.
# The shared data: $MOCAP_SHARED_DATA, or ../shared/data beside the checkout.
set -euo pipefail
A=$1 B=$2 W=$3 EXTRA_B=${4:-}
D=${MOCAP_SHARED_DATA:-$(cd "$(dirname "$0")/../../.." && pwd)/shared/data}
mkdir -p "$W"
faults="--noise-px 0.2 --occlusion 0.05 --occlusion-frames 5 --spurious 2 --drop-frames 0.002"
for m in walk running tennis_serve gaps_blank_cells dense_running; do
  f=$D/motions/$m.trc; cams=8
  [ "$m" = dense_running ] && f=$D/dense/$m.trc && cams=10
  s=$W/$m
  if [ ! -d "$s/session" ]; then
    mkdir -p "$s"
    "$A" sim rig --motion "$f" --cameras $cams -o "$s/rig.json" >/dev/null 2>&1
    "$A" sim project --motion "$f" --rig "$s/rig.json" -o "$s/session" $faults >/dev/null 2>&1
  fi
  for side in A B; do
    bin=${!side}
    extra=""
    [ "$side" = B ] && extra=$EXTRA_B
    t0=$(date +%s.%N)
    "$bin" reconstruct "$s/session" --calibration "$s/rig.json" -o "$s/$side.trc" $extra >/dev/null 2>"$s/$side.log" || { echo "$m $side reconstruct failed"; tail -3 "$s/$side.log"; continue; }
    t1=$(date +%s.%N)
    "$bin" eval --truth "$s/session/truth.trc" --result "$s/$side.trc" --session "$s/session" --json > "$s/$side.json" 2>/dev/null
    python3 - "$m" "$side" "$s/$side.json" "$t0" "$t1" <<'PY'
import json,sys
m,side,p,t0,t1=sys.argv[1:]
j=json.load(open(p))
def g(*k):
    for key in k:
        if key in j: return j[key]
    return None
keys=[k for k in ("rmse_mm","ghosts_per_frame","missing_per_frame","trajectories","markers","swaps") if k in j]
print(f"{m:17s} {side} " + " ".join(f"{k}={j[k]:.4f}" if isinstance(j[k],float) else f"{k}={j[k]}" for k in keys) + f" t={float(t1)-float(t0):.1f}s")
PY
  done
done
