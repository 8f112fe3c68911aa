#!/usr/bin/env python3
"""The seed rigs' sweep: cameras x centroid noise through the hub, defaults only.

For each motion, camera count (2: two cameras 90 degrees apart, taken from a 4-camera `sim rig`
ring; 3, 4, 8: `sim rig` rings) and noise sigma: `sim project` (the noise, --occlusion), then
`reconstruct` with no option and `eval --session --json`; the known-correspondence floor
(`reconstruct --known-correspondences`) of the same blobs beside it. Prints a markdown table:
found share (markers seen by two or more cameras matched within 20 mm), ghosts and missing per
frame, trajectories / markers, rmse and the floor's rmse.

usage: tools/seed-rigs/sweep.py [--bin build/bin] [--motions walk.trc,...] [--cameras 2,3,4,8]
                                [--noise 0.05,0.2,0.5,1,2] [--width 640 --height 480]
                                [--occlusion 0.02] [--jobs 2] [--json] [--out DIR]
"""
import argparse
import concurrent.futures
import json
import os
import subprocess


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
        for cameras in [int(c) for c in args.cameras.split(",")]:
            rig = os.path.join(args.out, "%s_%dcam_rig.json" % (stem, cameras))
            make_rig(hub, motion, cameras, args.width, args.height, rig)
            cells += [(hub, motion, stem, cameras, noise, rig, args) for noise in args.noise.split(",")]
    if not args.json:
        print("| motion | cameras | noise px | found % | ghosts/frame | missing/frame | trajectories / markers "
              "| rmse mm | floor rmse mm | rmse / floor |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for cell in pool.map(lambda c: run_cell(*c), cells):
            print(json.dumps(cell) if args.json else table_row(cell), flush=True)


if __name__ == "__main__":
    main()
