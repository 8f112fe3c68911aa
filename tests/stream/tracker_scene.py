"""A live scene with rigid bodies for the tracker protocols' test and bench (NatNet, VRPN, VMC):
`sim motion`'s walking subject plus three rigid bodies (4 markers each, distinct shapes) moving
and turning around it, `body define` for each from the first frame, a ring of cameras and the
rendered frames in work/frames, ready for live_rig.Rig with serve --bodies work/bodies.json."""

import math
import os

from live_rig import read_trc, run

SHAPES = {
    "wand": [(0, 0, 0), (120, 0, 0), (0, 80, 0), (40, 30, 50)],
    "drone": [(0, 0, 0), (150, 0, 0), (30, 110, 0), (70, 40, -35)],
    "helmet": [(0, 0, 0), (90, 0, 0), (0, 140, 0), (-30, 50, 60)],
}


def rot(axis, angle):
    x, y, z = axis
    n = math.sqrt(x * x + y * y + z * z)
    x, y, z = x / n, y / n, z / n
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


def apply(r, p):
    return [sum(r[i][k] * p[k] for k in range(3)) for i in range(3)]


def make(bin_dir, work, rate, frames, cameras):
    """Writes work/scene.trc, work/bodies.json, work/rig.json and work/frames; returns the body names."""
    motion = os.path.join(work, "motion.trc")
    run(bin_dir, "sim", "motion", "-o", motion, "--markers", "8", "--frames", str(frames), "--rate", str(rate),
        timeout=300)
    names, rows, lines = read_trc(motion)
    centre = [sum(p[k] for p in rows[0] if p) / len(names) for k in range(3)]
    extra = [f"{body}{i + 1}" for body, shape in SHAPES.items() for i in range(len(shape))]
    out = lines[:3]
    out[2] = out[2].replace(f"\t{len(names)}\t", f"\t{len(names) + len(extra)}\t", 1)
    out.append("\t".join(lines[3].split("\t")[:2] + [n for name in names + extra for n in (name, "", "")]))
    out.append("\t\t" + "\t".join(f"{a}{i + 1}" for i in range(len(names) + len(extra)) for a in "XYZ"))
    out.append("")
    data = [line for line in lines[5:] if line.strip()]
    for f, row in enumerate(rows):
        cells = data[f].split("\t")[:2]
        for p in row:
            cells += ["%.4f" % v for v in p]
        s = f / rate
        for b, shape in enumerate(SHAPES.values()):
            r = rot((0.3 * b, 1, 0.2), (0.8 + 0.3 * b) * s + b)
            t = [centre[0] + 400 * math.cos(0.5 * s + 2.1 * b), centre[1] + 700 + 200 * b,
                 centre[2] + 400 * math.sin(0.5 * s + 2.1 * b)]
            for m in shape:
                cells += ["%.4f" % (v + t[k]) for k, v in enumerate(apply(r, m))]
        out.append("\t".join(cells))
    scene = os.path.join(work, "scene.trc")
    with open(scene, "w") as f:
        f.write("\n".join(out) + "\n")
    bodies = os.path.join(work, "bodies.json")
    for body, shape in SHAPES.items():
        run(bin_dir, "body", "define", scene, "--name", body, "--markers",
            ",".join(f"{body}{i + 1}" for i in range(len(shape))), "--frames", "1:1", "-o", bodies)
    rig = os.path.join(work, "rig.json")
    run(bin_dir, "sim", "rig", "--motion", scene, "--cameras", str(cameras), "-o", rig, "--width", "640",
        "--height", "400")
    run(bin_dir, "sim", "render", "--motion", scene, "--rig", rig, "-o", os.path.join(work, "frames"), timeout=600)
    return list(SHAPES)
