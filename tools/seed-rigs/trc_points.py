"""Minimal TRC and visibility.tsv reading/writing for the seed-rig scripts (standard library only).

A TRC row is Frame#, Time, then X Y Z per marker (empty cells: no sample). Frames are keyed by
their Frame# value, as `mocap-hub eval` keys them.
"""
import math


def write_trc(path, names, rate_hz, rows):
    """rows: list of per-frame lists of (x, y, z) tuples or None, one per name."""
    with open(path, "w") as out:
        out.write("PathFileType\t4\t(X/Y/Z)\t%s\n" % path)
        out.write("DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n")
        out.write("%g\t%g\t%d\t%d\tmm\t%g\t1\t%d\n" % (rate_hz, rate_hz, len(rows), len(names), rate_hz, len(rows)))
        out.write("Frame#\tTime\t" + "\t".join(n + "\t\t" for n in names).rstrip("\t") + "\n")
        out.write("\t\t" + "\t".join("X%d\tY%d\tZ%d" % (i + 1, i + 1, i + 1) for i in range(len(names))) + "\n")
        out.write("\n")
        for f, row in enumerate(rows):
            cells = []
            for p in row:
                cells += ["", "", ""] if p is None else ["%.4f" % v for v in p]
            out.write("%d\t%.6f\t%s\n" % (f + 1, f / rate_hz, "\t".join(cells)))


def read_trc(path):
    """Returns (names, {frame#: [(x, y, z) or None per marker]})."""
    with open(path) as f:
        lines = f.read().splitlines()
    names = [n for n in lines[3].split("\t")[2:] if n.strip()]
    frames = {}
    for line in lines[5:]:
        if not line.strip():
            continue
        cells = line.split("\t")
        points = []
        for m in range(len(names)):
            xyz = cells[2 + 3 * m: 5 + 3 * m]
            if len(xyz) < 3 or any(c.strip() == "" for c in xyz):
                points.append(None)
            else:
                points.append(tuple(float(c) for c in xyz))
        frames[int(float(cells[0]))] = points
    return names, frames


def read_visibility(path):
    """Returns (names, {frame: [views per marker]}) from a session's visibility.tsv."""
    with open(path) as f:
        lines = f.read().splitlines()
    names = lines[0].split("\t")[1:]
    rows = {}
    for line in lines[1:]:
        if line.strip():
            cells = line.split("\t")
            rows[int(cells[0])] = [int(c) for c in cells[1:]]
    return names, rows


def match(truth, result, gate_mm):
    """Greedy one-to-one matching by distance under gate_mm: list of (truth index, result index, d)."""
    pairs = []
    for i, t in enumerate(truth):
        for j, r in enumerate(result):
            d = math.dist(t, r)
            if d < gate_mm:
                pairs.append((d, i, j))
    pairs.sort()
    used_t, used_r, out = set(), set(), []
    for d, i, j in pairs:
        if i not in used_t and j not in used_r:
            used_t.add(i)
            used_r.add(j)
            out.append((i, j, d))
    return out
