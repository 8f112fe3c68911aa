#!/usr/bin/env python3
"""Seed 001's section 6.1 protocol through the hub, with no gate given.

33 random points in a 497.843 x 788.865 x 748.485 mm box, 4 cameras of 640 x 480 around it
(`sim rig`), 2 px centroid noise, about one view in four hidden (`sim project --occlusion`);
each random set is held still for 8 frames and scored from its 4th frame on. Prints, per seed and
overall, the share of the points seen by two or more cameras that the output has within 20 mm,
the ghosts per frame (output points within 20 mm of no point), and the hidden share of views.

usage: tools/seed-rigs/paper001.py [--bin build/bin] [--seeds 1,2,3] [--sets 40] [--out DIR]
"""
import argparse
import json
import os
import random
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import trc_points  # noqa: E402

BOX_MM = (497.843, 788.865, 748.485)
POINTS = 33
HOLD_FRAMES = 8
SCORED_FROM = 3  # 0-based: the 4th frame of each set
RATE_HZ = 60.0


def make_truth(path, sets, seed):
    rng = random.Random(seed)
    names = ["P%02d" % (i + 1) for i in range(POINTS)]
    rows = []
    for _ in range(sets):
        points = [(rng.uniform(-BOX_MM[0] / 2, BOX_MM[0] / 2), rng.uniform(-BOX_MM[1] / 2, BOX_MM[1] / 2),
                   500.0 + rng.uniform(0.0, BOX_MM[2])) for _ in range(POINTS)]
        rows += [points] * HOLD_FRAMES
    trc_points.write_trc(path, names, RATE_HZ, rows)


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def score(session, result_trc, first_frame_number):
    _, truth = trc_points.read_trc(os.path.join(session, "truth.trc"))
    _, visibility = trc_points.read_visibility(os.path.join(session, "visibility.tsv"))
    _, result = trc_points.read_trc(result_trc)
    seen = found = ghosts = frames = views = hidden = 0
    cameras = 4
    for frame_no, truth_row in sorted(truth.items()):
        index = frame_no - first_frame_number
        if index % HOLD_FRAMES < SCORED_FROM:
            continue
        counts = visibility[index]
        points = [p for p, c in zip(truth_row, counts) if p is not None and c >= 2]
        views += cameras * len(truth_row)
        hidden += sum(cameras - c for c in counts)
        out = [p for p in result.get(frame_no, []) if p is not None]
        matched = trc_points.match(points, out, 20.0)
        all_matched = trc_points.match([p for p in truth_row if p is not None], out, 20.0)
        seen += len(points)
        found += len(matched)
        ghosts += len(out) - len(all_matched)
        frames += 1
    return {"seen": seen, "found": found, "ghosts": ghosts, "frames": frames, "hidden_views": hidden / views}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", default="build/bin")
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--sets", type=int, default=40)
    parser.add_argument("--occlusion", type=float, default=0.042,
                        help="sim project --occlusion (with --occlusion-frames 8: ~1 view in 4 hidden)")
    parser.add_argument("--out", default="paper001-out")
    parser.add_argument("--reconstruct-args", default="", help="extra reconstruct options (none for the target)")
    args = parser.parse_args()
    hub = os.path.join(args.bin, "mocap-hub")
    os.makedirs(args.out, exist_ok=True)
    total = {"seen": 0, "found": 0, "ghosts": 0, "frames": 0}
    for seed in [int(s) for s in args.seeds.split(",")]:
        base = os.path.join(args.out, "seed%d" % seed)
        truth = base + "_truth.trc"
        make_truth(truth, args.sets, seed)
        rig = base + "_rig.json"
        run([hub, "sim", "rig", "--motion", truth, "--cameras", "4", "--width", "640", "--height", "480",
             "--up", "z", "--seed", str(seed), "-o", rig])
        session = base + "_session"
        subprocess.run(["rm", "-rf", session], check=True)
        run([hub, "sim", "project", "--motion", truth, "--rig", rig, "-o", session, "--noise-px", "2",
             "--occlusion", str(args.occlusion), "--occlusion-frames", str(HOLD_FRAMES), "--seed", str(seed)])
        result = base + "_result.trc"
        run([hub, "reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", result]
            + args.reconstruct_args.split())
        _, truth_rows = trc_points.read_trc(os.path.join(session, "truth.trc"))
        figures = score(session, result, min(truth_rows))
        for key in total:
            total[key] += figures[key]
        print("seed %d: found %.2f %% of %d points seen twice or more, %.3f ghosts/frame, %.1f %% of views hidden" %
              (seed, 100.0 * figures["found"] / figures["seen"], figures["seen"],
               figures["ghosts"] / figures["frames"], 100.0 * figures["hidden_views"]))
    print(json.dumps({"found_percent": round(100.0 * total["found"] / total["seen"], 3),
                      "ghosts_per_frame": round(total["ghosts"] / total["frames"], 4),
                      "points_scored": total["seen"], "frames_scored": total["frames"]}))


if __name__ == "__main__":
    main()
