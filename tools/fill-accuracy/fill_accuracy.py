#!/usr/bin/env python3
"""Fill accuracy of the trajectory editor's methods (mocap-hub edit apply) on real motions.

For every TRC under ../shared/data/motions (or the files given), every gap length (0.1, 0.25, 0.5
and 1 s) and every fill method (spline, linear, pattern, rigid, relational), cuts gaps into the
recording where the marker and its donors are present (with 10 samples either side), fills them
through an edit log ({"op": "delete", ...} then {"op": "fill", ...}) and measures the RMS 3D
error of the filled samples against the recording itself. Donors are the markers whose distance
to the gapped one varies least over the recording (an operator's "same segment"): pattern takes
the first, rigid and relational the first three. Gaps run in sets whose windows do not overlap in
time, so no gap hides another's donors. Prints one table (rmse in mm per method, and the share of
gap samples a method could not fill) per recording and gap length, and the pooled rows.
Usage: fill_accuracy.py BIN_DIR [--gaps-per-cell N] [--seed S] [TRC ...]
"""
import argparse
import glob
import json
import os
import random
import subprocess
import sys
import tempfile

import numpy as np

GAP_SECONDS = [0.1, 0.25, 0.5, 1.0]
METHODS = ["spline", "linear", "pattern", "rigid", "relational"]
CONTEXT = 10


def read_hub_trc(path):
    """A TRC as this hub writes it: (frame numbers, names, points [frames, markers, 3] with NaN gaps)."""
    with open(path) as f:
        lines = f.read().split("\n")
    rate = float(lines[2].split("\t")[0])
    names = [n for n in lines[3].split("\t")[2:] if n]
    frames, rows = [], []
    for line in lines[5:]:
        if not line.strip():
            continue
        cells = line.split("\t")
        frames.append(int(round(float(cells[1]) * rate)))
        values = [float(c) if c.strip() else np.nan for c in cells[2:2 + 3 * len(names)]]
        values += [np.nan] * (3 * len(names) - len(values))
        rows.append(values)
    return np.array(frames), names, np.array(rows).reshape(len(rows), len(names), 3)


def donor_ranking(points):
    """For every marker, the others ordered by how little their distance to it varies."""
    n = points.shape[1]
    ranking = []
    for m in range(n):
        spread = []
        for d in range(n):
            if d == m:
                continue
            dist = np.linalg.norm(points[:, m] - points[:, d], axis=1)
            dist = dist[np.isfinite(dist)]
            spread.append((np.std(dist) if len(dist) > 10 else np.inf, d))
        ranking.append([d for _, d in sorted(spread)])
    return ranking


def place_gaps(points, ranking, length, count, rng):
    """Up to `count` (marker, first index, donors) gaps whose window is fully present for the
    marker and its first three present donors, grouped into sets with disjoint windows."""
    frames, n = points.shape[0], points.shape[1]
    present = np.isfinite(points).all(axis=2)
    gaps = []
    tries = 0
    while len(gaps) < count and tries < 50 * count:
        tries += 1
        m = rng.randrange(n)
        lo = rng.randrange(0, max(1, frames - length - 2 * CONTEXT))
        window = slice(lo, lo + length + 2 * CONTEXT)
        if lo + length + 2 * CONTEXT > frames or not present[window, m].all():
            continue
        donors = [d for d in ranking[m] if present[window, d].all()][:3]
        if len(donors) < 3:
            continue
        gaps.append((m, lo + CONTEXT, donors))
    sets = []
    for gap in gaps:
        for s in sets:
            if all(abs(gap[1] - other[1]) > length + 2 * CONTEXT for other in s):
                s.append(gap)
                break
        else:
            sets.append([gap])
    return sets


def run_set(hub, source, frames, names, gap_set, length, method, workdir):
    ops = []
    for m, first, _ in gap_set:
        ops.append({"op": "delete", "marker": names[m], "from": int(frames[first]), "to": int(frames[first + length - 1])})
    for m, first, donors in gap_set:
        op = {"op": "fill", "marker": names[m], "method": method, "from": int(frames[first]),
              "to": int(frames[first + length - 1])}
        if method == "pattern":
            op["donors"] = [names[donors[0]]]
        elif method in ("rigid", "relational"):
            op["donors"] = [names[d] for d in donors]
        ops.append(op)
    log = os.path.join(workdir, "edits.json")
    with open(log, "w") as f:
        json.dump({"format": "mocap-edits", "version": 1, "operations": ops}, f)
    out = os.path.join(workdir, "edited.trc")
    subprocess.run([hub, "edit", "apply", log, "--input", source, "-o", out, "--json"], check=True,
                   capture_output=True, text=True)
    return read_hub_trc(out)[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("bin_dir")
    parser.add_argument("--gaps-per-cell", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("trc", nargs="*")
    args = parser.parse_args()
    hub = os.path.join(args.bin_dir, "mocap-hub")
    here = os.path.dirname(os.path.abspath(__file__))
    files = args.trc or sorted(glob.glob(os.path.join(here, "..", "..", "..", "shared", "data", "motions", "*.trc")))
    if not files:
        sys.exit("no motions given and none under ../shared/data/motions")
    pooled = {(s, m): [] for s in GAP_SECONDS for m in METHODS}
    pooled_left = {(s, m): [0, 0] for s in GAP_SECONDS for m in METHODS}
    print("| recording | gap | gaps | " + " | ".join(METHODS) + " |")
    print("|---|---|---|" + "---|" * len(METHODS))
    with tempfile.TemporaryDirectory() as workdir:
        for path in files:
            source = os.path.join(workdir, "source.trc")  # the recording as this hub writes it
            subprocess.run([hub, "convert", path, source], check=True, capture_output=True)
            frames, names, truth = read_hub_trc(source)
            with open(source) as f:
                rate = float(f.read().split("\n")[2].split("\t")[0])
            ranking = donor_ranking(truth)
            rng = random.Random(args.seed)
            for seconds in GAP_SECONDS:
                length = max(1, int(round(seconds * rate)))
                sets = place_gaps(truth, ranking, length, args.gaps_per_cell, rng)
                cells = []
                for method in METHODS:
                    errors, left = [], 0
                    for gap_set in sets:
                        edited = run_set(hub, source, frames, names, gap_set, length, method, workdir)
                        for m, first, _ in gap_set:
                            d = np.linalg.norm(edited[first:first + length, m] - truth[first:first + length, m], axis=1)
                            left += int(np.isnan(d).sum())
                            errors.extend(d[np.isfinite(d)] ** 2)
                    total = sum(len(s) for s in sets) * length
                    pooled[(seconds, method)].extend(errors)
                    pooled_left[(seconds, method)][0] += left
                    pooled_left[(seconds, method)][1] += total
                    cell = "%.2f" % np.sqrt(np.mean(errors)) if errors else "n/a"
                    if left:
                        cell += " (%.0f%% unfilled)" % (100.0 * left / total)
                    cells.append(cell)
                gaps = sum(len(s) for s in sets)
                print("| %s | %g s | %d | %s |" % (os.path.basename(path), seconds, gaps, " | ".join(cells)))
                sys.stdout.flush()
    for seconds in GAP_SECONDS:
        cells = []
        for method in METHODS:
            e = pooled[(seconds, method)]
            cell = "%.2f" % np.sqrt(np.mean(e)) if e else "n/a"
            left, total = pooled_left[(seconds, method)]
            if left:
                cell += " (%.0f%% unfilled)" % (100.0 * left / total)
            cells.append(cell)
        print("| all | %g s | | %s |" % (seconds, " | ".join(cells)))


if __name__ == "__main__":
    main()
