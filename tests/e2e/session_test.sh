#!/usr/bin/env bash
# ctest e2e: a small simulated session through real processes (sim render -> one mocap-node per
# camera -> mocap-hub serve over UDP, capture start/stop -> reconstruct -> eval) must meet the
# accuracy targets, the live result included; then the same motion with every marker gone from
# every camera for 250 ms (the nodes send frames without blobs): serve's live result keeps each
# marker's id through it.
# usage: session_test.sh BIN_DIR WORK_DIR
set -euo pipefail
bin=${1:?usage: session_test.sh BIN_DIR WORK_DIR}
work=${2:?usage: session_test.sh BIN_DIR WORK_DIR}
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"
mkdir -p "$work"

"$bin/mocap-hub" sim motion -o "$work/motion.trc" --markers 16 --frames 90 --rate 60 --up y --seed 3
# The nodes share this machine with the rest of the test suite: a node starved of CPU can send a
# frame later than serve's default 20 ms assembly deadline, which would make the live result's
# figures depend on the machine's load. This test is about accuracy, so frame sets wait 150 ms
# (latency is measured by the benchmarks, not here).
serve_args="--max-ray-distance-mm 3 --deadline-ms 150"
"$here/../../deploy/sim-session.sh" --motion "$work/motion.trc" --cameras 4 --out "$work" --bin "$bin" \
    --serve-args "$serve_args" --json > "$work/result.json"
cat "$work/result.json"

# The final TRC (gap-filled) and the live result itself must meet the project's targets.
python3 - "$work/result.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
failures = []
def need(what, value, limit):
    print(f"{what} = {value:.4f} (limit {limit})")
    if not value <= limit:
        failures.append(f"{what} = {value:.4f} > {limit}")
f, l = d["filled"], d["live"]
need("final rmse_mm", f["rmse_mm"], 1.5)
need("final ghosts_per_frame", f["ghosts_per_frame"], 0.02)
need("final missing_per_frame", f["missing_per_frame"], 0.01)
need("live rmse_mm", l["rmse_mm"], 1.5)
need("live ghosts_per_frame", l["ghosts_per_frame"], 0.02)
need("live missing_per_frame", l["missing_per_frame"], 0.01)
need("frames not assembled", d["frames"] - d["frame_sets"], 0)
need("final fragmentation - 1", f["fragmentation"] - 1.0, 0.25)
lat = d["latency_ms"]
if not (0 < lat["trigger_to_send_p50"] <= lat["trigger_to_send_p99"] and
        0 < lat["hub_p50"] <= lat["hub_p99"] <= lat["hub_max"]):
    failures.append(f"latency figures missing or inconsistent: {lat}")
for failure in failures:
    print("session_test: FAILED: " + failure, file=sys.stderr)
sys.exit(1 if failures else 0)
PY

# Frames 41-55 (15 frames at 60 Hz: 250 ms) without any marker.
python3 - "$work/motion.trc" "$work/dropout.trc" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
for i in range(6, len(lines)):
    cells = lines[i].split("\t")
    if len(cells) > 2 and 41 <= int(cells[0]) <= 55:
        lines[i] = "\t".join(cells[:2] + [""] * (len(cells) - 2))
open(sys.argv[2], "w").write("\n".join(lines))
PY
"$here/../../deploy/sim-session.sh" --motion "$work/dropout.trc" --cameras 4 --out "$work/dropout" --bin "$bin" \
    --serve-args "$serve_args" --json > "$work/dropout.json"
python3 - "$work/dropout.json" <<'PY'
import json, sys
live = json.load(open(sys.argv[1]))["live"]
print(f"250 ms drop-out: live id changes {live['id_changes']}, trajectories {live['trajectories']} "
      f"for {live['truth_markers']} markers, ghosts {live['ghosts']}")
if live["id_changes"] != 0 or live["trajectories"] != live["truth_markers"]:
    print("session_test: FAILED: ids changed through a 250 ms drop-out", file=sys.stderr)
    sys.exit(1)
PY
