#!/usr/bin/env python3
"""The seed rigs' sweep: cameras x centroid noise through the hub, defaults only.

For each motion, camera count (2: two cameras 90 degrees apart, taken from a 4-camera `sim rig`
ring; 3, 4, 8: `sim rig` rings) and noise sigma: `sim project` (the noise, --occlusion), then
`reconstruct` with no option and `eval --session --json`; the known-correspondence floor
(`reconstruct --known-correspondences`) of the same blobs beside it. Prints a markdown table:
found share (markers seen by two or more cameras matched within 20 mm), ghosts and missing per
frame, trajectories / markers, rmse and the floor's rmse.

With --free-run-hz R the motion is first resampled to R Hz and each cell compares synchronised
cameras with free-running ones (`sim project --free-run`: random phase, rate error, time stamp
jitter) reconstructed as `reconstruct` does by default (each camera's blobs brought to the frame
set's instant) and with --no-time-align: rmse, found share and ghosts of the three.

usage: tools/seed-rigs/sweep.py [--bin build/bin] [--motions walk.trc,...] [--cameras 2,3,4,8]
                                [--noise 0.05,0.2,0.5,1,2] [--width 640 --height 480]
                                [--occlusion 0.02] [--free-run-hz 30] [--jobs 2] [--json]
                                [--project-args "..."] [--out DIR]
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import trc_points  # noqa: E402


def run(cmd, capture=False):
    done = subprocess.run(cmd, check=True, stdout=subprocess.PIPE if capture else subprocess.DEVNULL)
    return done.stdout.decode() if capture else None


def make_rig(hub, motion, cameras, width, height, path):
    """A sim rig ring; two cameras are the first two of a four-camera ring (90 degrees apart)."""
    ring = 4 if cameras == 2 else cameras
    run([hub, "sim", "rig", "--motion", motion, "--cameras", str(ring), "--width", str(width), "--height",
         str(height), "-o", path])
    if cameras == 2:
        with open(path) as f:
            rig = json.load(f)
        rig["cameras"] = rig["cameras"][:2]
        with open(path, "w") as f:
            json.dump(rig, f, indent=1)


def evaluate(hub, truth, result, session=None):
    cmd = [hub, "eval", "--truth", truth, "--result", result, "--json"]
    if session:
        cmd += ["--session", session]
    return json.loads(run(cmd, capture=True))


def run_cell(hub, motion, stem, cameras, noise, rig, args):
    """One cell: project, reconstruct with defaults and with the known correspondences, evaluate both."""
    base = os.path.join(args.out, "%s_%dcam_%spx" % (stem, cameras, noise))
    session = base + "_session"
    run(["rm", "-rf", session])
    run([hub, "sim", "project", "--motion", motion, "--rig", rig, "-o", session, "--noise-px", noise,
         "--occlusion", str(args.occlusion)] + args.project_args.split())
    calibration = os.path.join(session, "calibration.json")
    truth = os.path.join(session, "truth.trc")
    result = base + ".trc"
    floor = base + "_floor.trc"
    run([hub, "reconstruct", session, "--calibration", calibration, "-o", result])
    run([hub, "reconstruct", session, "--calibration", calibration, "-o", floor, "--known-correspondences", truth])
    e = evaluate(hub, truth, result, session)
    f = evaluate(hub, truth, floor)
    expected = e["expected_points"]
    return {"motion": stem, "cameras": cameras, "noise_px": float(noise),
            "found_percent": 100.0 * (1.0 - e["missing"] / expected) if expected else 0.0,
            "ghosts_per_frame": e["ghosts_per_frame"], "missing_per_frame": e["missing_per_frame"],
            "trajectories": e["trajectories"], "markers": e["truth_markers"], "rmse_mm": e["rmse_mm"],
            "floor_rmse_mm": f["rmse_mm"]}


def decimate(motion, rate_hz, path):
    """The motion resampled to rate_hz by keeping every n-th frame (rate_hz must divide its rate)."""
    names, frames = trc_points.read_trc(motion)
    with open(motion) as f:
        source_hz = float(f.read().splitlines()[2].split("\t")[0])
    step = int(round(source_hz / rate_hz))
    if step < 1 or abs(source_hz / step - rate_hz) > 1e-6:
        raise SystemExit("sweep: %g Hz is not %s's %g Hz over a whole number" % (rate_hz, motion, source_hz))
    rows = [frames[k] for k in sorted(frames)][::step]
    trc_points.write_trc(path, names, rate_hz, rows)


def run_free_run_cell(hub, motion, stem, cameras, noise, rig, args):
    """Synchronised and free-running cameras on the same motion: rmse and found of both."""
    base = os.path.join(args.out, "%s_%dhz_%dcam_%spx" % (stem, int(args.free_run_hz), cameras, noise))
    figures = {"motion": stem, "rate_hz": args.free_run_hz, "cameras": cameras, "noise_px": float(noise)}
    for mode, extra, reconstruct_extra in (("sync", [], []), ("free", ["--free-run"], []),
                                           ("free_unaligned", ["--free-run"], ["--no-time-align"])):
        session = base + ("_sync" if mode == "sync" else "_free") + "_session"
        if mode != "free_unaligned":
            run(["rm", "-rf", session])
            run([hub, "sim", "project", "--motion", motion, "--rig", rig, "-o", session, "--noise-px", noise,
                 "--occlusion", str(args.occlusion)] + extra + args.project_args.split())
        truth = os.path.join(session, "truth.trc")
        result = "%s_%s.trc" % (base, mode)
        run([hub, "reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", result]
            + reconstruct_extra)
        e = evaluate(hub, truth, result, session)
        expected = e["expected_points"]
        figures[mode] = {"rmse_mm": e["rmse_mm"], "ghosts_per_frame": e["ghosts_per_frame"],
                         "found_percent": 100.0 * (1.0 - e["missing"] / expected) if expected else 0.0}
    return figures


def free_run_row(c):
    sync, free, raw = c["sync"], c["free"], c["free_unaligned"]
    return "| %s | %g | %d | %g | %.3f (%.2f %%, %.4f) | %.3f (%.2f %%, %.4f) | %.3f (%.2f %%, %.4f) | %.2f |" % (
        c["motion"], c["rate_hz"], c["cameras"], c["noise_px"], sync["rmse_mm"], sync["found_percent"],
        sync["ghosts_per_frame"], free["rmse_mm"], free["found_percent"], free["ghosts_per_frame"], raw["rmse_mm"],
        raw["found_percent"], raw["ghosts_per_frame"], free["rmse_mm"] / sync["rmse_mm"] if sync["rmse_mm"] else 0.0)


def table_row(c):
    ratio = c["rmse_mm"] / c["floor_rmse_mm"] if c["floor_rmse_mm"] else 0.0
    return "| %s | %d | %g | %.2f | %.4f | %.4f | %d / %d | %.3f | %.3f | %.2f |" % (
        c["motion"], c["cameras"], c["noise_px"], c["found_percent"], c["ghosts_per_frame"], c["missing_per_frame"],
        c["trajectories"], c["markers"], c["rmse_mm"], c["floor_rmse_mm"], ratio)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default="build/bin")
    checkout = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser.add_argument("--data", default=os.environ.get("MOCAP_SHARED_DATA", os.path.join(checkout, "../shared/data")),
                        help="the shared data directory (default $MOCAP_SHARED_DATA or CHECKOUT/../shared/data)")
    parser.add_argument("--motions", default="motions/walk.trc")
    parser.add_argument("--cameras", default="2,3,4,8")
    parser.add_argument("--noise", default="0.05,0.2,0.5,1,2")
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--occlusion", type=float, default=0.02)
    parser.add_argument("--project-args", default="", help="more sim project options")
    parser.add_argument("--free-run-hz", type=float, default=0.0,
                        help="instead: synchronised vs free-running cameras (sim project --free-run) on the motion "
                             "resampled to this rate")
    parser.add_argument("--jobs", type=int, default=2, help="cells run at once (default 2)")
    parser.add_argument("--json", action="store_true", help="one JSON object per cell instead of the table")
    parser.add_argument("--out", default="sweep-out")
    args = parser.parse_args()
    if args.jobs < 1:
        parser.error("--jobs must be >= 1, not %d" % args.jobs)
    hub = os.path.join(args.bin, "mocap-hub")
    os.makedirs(args.out, exist_ok=True)
    cells = []
    for motion_name in args.motions.split(","):
        motion = os.path.join(args.data, motion_name)
        if not os.path.isfile(motion):
            parser.error("%s: no such motion file (give --data or set MOCAP_SHARED_DATA)" % motion)
        stem = os.path.splitext(os.path.basename(motion))[0]
        if args.free_run_hz > 0.0:
            resampled = os.path.join(args.out, "%s_%dhz.trc" % (stem, int(args.free_run_hz)))
            decimate(motion, args.free_run_hz, resampled)
            motion = resampled
        for cameras in [int(c) for c in args.cameras.split(",")]:
            rig = os.path.join(args.out, "%s_%dcam_rig.json" % (stem, cameras))
            make_rig(hub, motion, cameras, args.width, args.height, rig)
            cells += [(hub, motion, stem, cameras, noise, rig, args) for noise in args.noise.split(",")]
    if args.free_run_hz > 0.0:
        header = ("| motion | Hz | cameras | noise px | synchronised: rmse mm (found, ghosts/frame) | free-running, "
                  "brought to the set's instant | free-running, as captured (--no-time-align) | free / sync rmse |",
                  "|---|---|---|---|---|---|---|---|")
        run, row = run_free_run_cell, free_run_row
    else:
        header = ("| motion | cameras | noise px | found % | ghosts/frame | missing/frame | trajectories / markers "
                  "| rmse mm | floor rmse mm | rmse / floor |", "|---|---|---|---|---|---|---|---|---|---|")
        run, row = run_cell, table_row
    if not args.json:
        print("\n".join(header))
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for cell in pool.map(lambda c: run(*c), cells):
            print(json.dumps(cell) if args.json else row(cell), flush=True)

if __name__ == "__main__":
    main()
