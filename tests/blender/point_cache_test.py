#!/usr/bin/env python3
"""Mesh driving's point caches read by Blender itself (label blender).

Writes a grid mesh and a capture whose markers sit exactly on some of its vertices and move
smoothly, runs `mocap-hub mesh drive` to .mdd and .pc2 (and the bound mesh), then runs Debian's
Blender headless (blender_check.py): the MDD importer must make one shape key per captured frame,
and at every frame read, Blender's positions of the vertices under markers must be the markers'
positions (RBF interpolation is exact at its centres), by both the MDD shape keys and the PC2
Mesh Cache modifier. An independent reader here checks the files' headers as well.
Usage: point_cache_test.py BIN_DIR WORK_DIR. Exit 77 (skipped) without blender.
"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys

FRAMES = 90
RATE = 60.0


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    blender = shutil.which("blender")
    if blender is None:
        print("SKIPPED: no blender on PATH (Debian package blender)")
        return 77
    os.makedirs(work, exist_ok=True)
    obj_path = os.path.join(work, "sheet.obj")
    trc_path = os.path.join(work, "sheet.trc")
    # A 21 x 21 sheet, 10 mm apart, gently domed off-centre (no symmetry that would let a turned
    # mesh fit the markers as well); markers on every fifth vertex both ways.
    size = 21
    vertices = [(10.0 * i, 10.0 * j, 0.2 * ((i - 7) ** 2 + 0.5 * (j - 12) ** 2) + 3.0 * i)
                for j in range(size) for i in range(size)]
    with open(obj_path, "w") as out:
        for v in vertices:
            out.write("v %.6f %.6f %.6f\n" % v)
        for j in range(size - 1):
            for i in range(size - 1):
                a = j * size + i + 1
                out.write("f %d %d %d %d\n" % (a, a + 1, a + size + 1, a + size))
    marker_vertices = [j * size + i for j in range(0, size, 5) for i in range(0, size, 5)]

    def marker_at(index, frame):
        x, y, z = vertices[index]
        s = math.sin(2 * math.pi * frame / FRAMES)  # 0 at frame 0, the static frame
        return (x + 3 * s * math.cos(y / 50), y, z + 8 * s * math.exp(-((x - 100) ** 2 + (y - 100) ** 2) / 5000))

    names = ["V%d" % v for v in marker_vertices]
    with open(trc_path, "w") as out:
        out.write("PathFileType\t4\t(X/Y/Z)\tsheet.trc\n")
        out.write("DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n")
        out.write("%g\t%g\t%d\t%d\tmm\t%g\t1\t%d\n" % (RATE, RATE, FRAMES, len(names), RATE, FRAMES))
        out.write("Frame#\tTime\t" + "\t\t\t".join(names) + "\n")
        out.write("\t\t" + "\t".join("X%d\tY%d\tZ%d" % (k + 1, k + 1, k + 1) for k in range(len(names))) + "\n\n")
        for f in range(FRAMES):
            cells = []
            for v in marker_vertices:
                cells += ["%.6f" % c for c in marker_at(v, f)]
            out.write("%d\t%.6f\t%s\n" % (f + 1, f / RATE, "\t".join(cells)))

    bound = os.path.join(work, "bound.obj")
    caches = {}
    for ext in ("mdd", "pc2"):
        caches[ext] = os.path.join(work, "sheet." + ext)
        subprocess.run([os.path.join(bin_dir, "mocap-hub"), "mesh", "drive", "--mesh", obj_path, "--markers", trc_path,
                        "--bound-mesh", bound, "-o", caches[ext]], check=True)

    # Independent reading of the headers.
    with open(caches["pc2"], "rb") as f:
        magic, version, points, start, sampling, samples = struct.unpack("<12siiffi", f.read(32))
        assert magic == b"POINTCACHE2\0" and version == 1, (magic, version)
        assert (points, samples) == (len(vertices), FRAMES), (points, samples)
        assert os.path.getsize(caches["pc2"]) == 32 + 12 * points * samples
    with open(caches["mdd"], "rb") as f:
        frames, points = struct.unpack(">2i", f.read(8))
        times = struct.unpack(">%df" % frames, f.read(4 * frames))
        assert (frames, points) == (FRAMES, len(vertices)), (frames, points)
        assert abs(times[-1] - (FRAMES - 1) / RATE) < 1e-5, times[-1]

    frames_to_read = [0, 1, FRAMES // 3, FRAMES - 1]
    vertices_to_read = marker_vertices[::3]
    run = subprocess.run([blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                          os.path.join(os.path.dirname(os.path.abspath(__file__)), "blender_check.py"), "--",
                          bound, caches["mdd"], caches["pc2"], ",".join(map(str, frames_to_read)),
                          ",".join(map(str, vertices_to_read))],
                         capture_output=True, text=True, timeout=240)
    lines = [line for line in run.stdout.splitlines() if line.startswith("RESULT ")]
    if run.returncode != 0 or not lines:
        print(run.stdout[-3000:], run.stderr[-3000:])
        print("FAIL: blender did not run the check")
        return 1
    seen = json.loads(lines[-1][len("RESULT "):])
    failures = []
    if seen["obj_vertices"] != len(vertices):
        failures.append("Blender's OBJ importer read %d vertices, not %d" % (seen["obj_vertices"], len(vertices)))
    if seen["mdd_shape_keys"] != FRAMES + 1:
        failures.append("the MDD import made %d shape keys, not %d frames + Basis" % (seen["mdd_shape_keys"], FRAMES))
    worst = 0.0
    for route in ("mdd", "pc2"):
        for f in frames_to_read:
            for v in vertices_to_read:
                got = seen[route][str(f)][str(v)]
                want = marker_at(v, f)
                worst = max(worst, math.dist(got, want))
    if worst > 0.01:
        failures.append("vertices under markers are %.4f mm from the markers in Blender (bound 0.01)" % worst)
    print("Blender 3 routes: OBJ %d vertices, MDD %d shape keys for %d frames; vertices under markers within %.5f mm"
          % (seen["obj_vertices"], seen["mdd_shape_keys"], FRAMES, worst))
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
