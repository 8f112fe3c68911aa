#!/usr/bin/env python3
"""C3D against two independent implementations from PyPI, both ways:
- files written by mocap-hub (`convert` from TRC, and `reconstruct -o OUT.c3d` of a simulated
  session) read by ezc3d (C++ with Python bindings) and by c3d (pure Python): labels, rate, frame
  count, every coordinate, gaps as invalid points (residual -1);
- files written by ezc3d and by c3d read by mocap-hub (`convert` to TRC, compared value by value).

usage: c3d_interop.py BIN_DIR WORK_DIR"""

import math
import os
import shutil
import sys
import unittest
import warnings

import c3d
import ezc3d
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import run  # noqa: E402

BIN = WORK = None


def hub(*args):
    return run(BIN, *args, timeout=120).stdout


def read_trc(path):
    """(names, rate, {frame_number: [(x, y, z) or None per marker]}) from a TRC's text."""
    with open(path) as f:
        lines = f.read().splitlines()
    keys, values = lines[1].split("\t"), lines[2].split("\t")
    rate = float(values[keys.index("DataRate")])
    names = [n for n in lines[3].split("\t")[2:] if n]
    rows = {}
    for line in lines[5:]:
        cells = line.split("\t")
        if len(cells) < 2 or not cells[0].strip():
            continue
        frame = round(float(cells[1]) * rate)
        points = []
        for m in range(len(names)):
            xyz = cells[2 + 3 * m:5 + 3 * m]
            points.append(tuple(float(v) for v in xyz) if len(xyz) == 3 and all(v.strip() for v in xyz) else None)
        rows[frame] = points
    return names, rate, rows


class C3dInterop(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        cls.truth = os.path.join(WORK, "motion.trc")
        hub("sim", "motion", "-o", cls.truth, "--markers", "14", "--frames", "120", "--rate", "150")

    def check_against_trc(self, c3d_path, trc_path):
        names, rate, rows = read_trc(trc_path)
        frames = sorted(rows)
        # ezc3d
        e = ezc3d.c3d(c3d_path)
        self.assertEqual(list(e["parameters"]["POINT"]["LABELS"]["value"]), names)
        self.assertAlmostEqual(float(e["parameters"]["POINT"]["RATE"]["value"][0]), rate, places=3)
        self.assertEqual(list(e["parameters"]["POINT"]["UNITS"]["value"]), ["mm"])
        points = e["data"]["points"]
        residuals = e["data"]["meta_points"]["residuals"]
        self.assertEqual(points.shape[2], frames[-1] - frames[0] + 1)
        # c3d (pure Python)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with open(c3d_path, "rb") as handle:
                reader = c3d.Reader(handle)
                self.assertEqual([l.strip() for l in reader.point_labels], names)
                self.assertAlmostEqual(reader.point_rate, rate, places=3)
                pure = [p.copy() for _, p, _ in reader.read_frames()]
        self.assertEqual(len(pure), points.shape[2])
        checked = gaps = 0
        for f in frames:
            i = f - frames[0]
            for m, xyz in enumerate(rows[f]):
                if xyz is None:
                    self.assertTrue(math.isnan(points[0, m, i]) or residuals[0, m, i] < 0, (f, m))
                    self.assertLess(pure[i][m, 3], 0, (f, m))
                    gaps += 1
                    continue
                for k in range(3):
                    self.assertAlmostEqual(points[k, m, i], xyz[k], delta=1e-3 * max(1.0, abs(xyz[k])))
                    self.assertAlmostEqual(float(pure[i][m, k]), xyz[k], delta=1e-3 * max(1.0, abs(xyz[k])))
                self.assertGreaterEqual(residuals[0, m, i], 0)
                checked += 1
        self.assertGreater(checked, 0)
        return checked, gaps

    def test_convert_is_read_by_both(self):
        out = os.path.join(WORK, "motion.c3d")
        hub("convert", self.truth, out)
        checked, _ = self.check_against_trc(out, self.truth)
        self.assertEqual(checked, 14 * 120)

    def test_reconstruct_writes_c3d_with_gaps(self):
        rig, session = os.path.join(WORK, "rig.json"), os.path.join(WORK, "session")
        hub("sim", "rig", "--motion", self.truth, "--cameras", "6", "-o", rig)
        hub("sim", "project", "--motion", self.truth, "--rig", rig, "-o", session, "--occlusion", "0.5",
            "--occlusion-frames", "20", "--noise-px", "0.2")
        cal = os.path.join(session, "calibration.json")
        trc, c3d_path = os.path.join(WORK, "out.trc"), os.path.join(WORK, "out.c3d")
        # No gap filling, so that the occlusions stay gaps in both files.
        hub("reconstruct", session, "--calibration", cal, "-o", trc, "--max-spline-gap-s", "0")
        hub("reconstruct", session, "--calibration", cal, "-o", c3d_path, "--max-spline-gap-s", "0")
        checked, gaps = self.check_against_trc(c3d_path, trc)
        self.assertGreater(checked, 1000)
        self.assertGreater(gaps, 0)
        print(f"\nreconstruct -o .c3d: {checked} points and {gaps} gaps agree with the TRC in ezc3d and c3d",
              file=sys.stderr)

    def test_files_of_the_other_implementations_are_read(self):
        labels = ["RASI", "LASI", "RPSI"]
        rng = np.random.default_rng(3)
        data = rng.uniform(-1000, 1000, size=(3, len(labels), 40))
        # ezc3d writes one
        e = ezc3d.c3d()
        e["parameters"]["POINT"]["RATE"]["value"] = [200.0]
        e["parameters"]["POINT"]["LABELS"]["value"] = labels
        points = np.ones((4, len(labels), 40))
        points[:3] = data
        points[:3, 1, 10:15] = np.nan  # a gap
        e["data"]["points"] = points
        by_ezc3d = os.path.join(WORK, "ezc3d.c3d")
        e.write(by_ezc3d)
        # c3d writes one
        by_c3d = os.path.join(WORK, "c3d.c3d")
        writer = c3d.Writer(point_rate=200.0)
        frames = []
        for i in range(40):
            p = np.zeros((len(labels), 5), dtype=np.float32)
            p[:, :3] = data[:, :, i].T
            if 10 <= i < 15:
                p[1, 3] = -1  # the gap, as C3D marks it
            frames.append((p, np.zeros((0, 0), dtype=np.float32)))
        writer.add_frames(frames)
        writer.set_point_labels(labels)
        with open(by_c3d, "wb") as handle:
            writer.write(handle)
        for path in (by_ezc3d, by_c3d):
            trc = path + ".trc"
            hub("convert", path, trc)
            names, rate, rows = read_trc(trc)
            self.assertEqual(names, labels, path)
            self.assertAlmostEqual(rate, 200.0)
            self.assertEqual(len(rows), 40, path)
            for n, f in enumerate(sorted(rows)):
                for m in range(len(labels)):
                    if m == 1 and 10 <= n < 15:
                        self.assertIsNone(rows[f][m], (path, n))
                        continue
                    for k in range(3):
                        self.assertAlmostEqual(rows[f][m][k], data[k, m, n], delta=1e-3 * max(1.0, abs(data[k, m, n])))


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
