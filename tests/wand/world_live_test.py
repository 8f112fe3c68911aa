#!/usr/bin/env python3
"""The floor / L-frame step through `serve` end to end: an L-frame (the default 4 markers, y up)
lies still in a simulated 4-camera rig, rendered into camera frames that one real `mocap-node`
process per camera replays on loopback. serve runs with the rig's calibration as a wand leaves it:
the same cameras in a world turned 4 deg off the vertical (and 25 deg about it) and shifted. POST
/api/calibration/world finds the L-frame in live frame sets, and serve's calibration is then the
truth (`eval-calibration --no-align`), saved over --calibration with the old file kept. A wrong
L-frame geometry and an up axis the request cannot use are refused with the reason. Python
standard library only.

usage: world_live_test.py BIN_DIR WORK_DIR

Prints the figures it measured (markers, fit, tilt removed, the cameras against the truth) on
stderr. Every wait is bounded; every process the test starts is killed at the end."""

import glob
import json
import math
import os
import shutil
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import Rig, http, run  # noqa: E402

BIN = WORK = None
CAMERAS = 4
RATE = 100
TILT_DEG = 4.0
# The default L-frame with y up (calib/world_frame.h): origin, 200 and 500 mm along +z, 350 mm along +x.
LFRAME = [(0.0, 0.0, 0.0), (0.0, 0.0, 200.0), (0.0, 0.0, 500.0), (350.0, 0.0, 0.0)]
# Where it lies in the rig's volume (the sim rig is built around a motion above the floor).
PLACE = (300.0, 850.0, 350.0)
MAX_CENTRE_MM = 2.0
MAX_ROTATION_DEG = 0.1


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def matvec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def rotation(axis, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    if axis == "x":
        return [[1, 0, 0], [0, c, -s], [0, s, c]]
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]  # y


def moved_world(calibration, q, shift):
    """The same cameras in the world X' = q X + shift (x_cam = R X + t = R q^T X' + t - R q^T shift)."""
    out = json.loads(json.dumps(calibration))
    for camera in out["cameras"]:
        r = matmul(camera["rotation"], transpose(q))
        camera["translation"] = [t - v for t, v in zip(camera["translation"], matvec(r, shift))]
        camera["rotation"] = r
    return out


def write_static_trc(path, markers, frames, rate):
    rows = ["PathFileType\t4\t(X/Y/Z)\t" + os.path.basename(path),
            "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
            f"{rate}\t{rate}\t{frames}\t{len(markers)}\tmm\t{rate}\t1\t{frames}",
            "Frame#\tTime\t" + "\t\t\t".join(f"L{k + 1}" for k in range(len(markers))),
            "\t\t" + "\t".join(f"X{k + 1}\tY{k + 1}\tZ{k + 1}" for k in range(len(markers))), ""]
    for f in range(frames):
        rows.append(f"{f + 1}\t{f / rate:.5f}\t" + "\t".join(f"{v:.3f}" for m in markers for v in m))
    with open(path, "w") as out:
        out.write("\n".join(rows) + "\n")


def lframe_scene(bin_dir, work):
    """A still L-frame in a 4-camera sim rig, rendered into work/frames for the nodes; serve's
    calibration there is the rig in a tilted wand world. Returns the truth calibration's path
    (the same cameras in the world on the L-frame)."""
    if os.path.isdir(work):
        shutil.rmtree(work)
    os.makedirs(work)
    walk = os.path.join(work, "walk.trc")
    run(bin_dir, "sim", "motion", "-o", walk, "--markers", "4", "--frames", "200", "--rate", str(RATE))
    rig = os.path.join(work, "rig.json")
    run(bin_dir, "sim", "rig", "--motion", walk, "--cameras", str(CAMERAS), "-o", rig, "--width", "640",
        "--height", "400", "--up", "y")
    # The truth: the same cameras in the world whose origin is where the L-frame lies.
    with open(rig) as f:
        truth = moved_world(json.load(f), rotation("x", 0.0), [-v for v in PLACE])
    truth_path = os.path.join(work, "truth.json")
    with open(truth_path, "w") as f:
        json.dump(truth, f)
    # Rendered in the rig's own world, where the L-frame's origin is not (0, 0, 0): a TRC marker
    # at exactly the origin reads as a gap.
    lframe = os.path.join(work, "lframe.trc")
    write_static_trc(lframe, [[p + v for p, v in zip(PLACE, m)] for m in LFRAME], 100, RATE)
    run(bin_dir, "sim", "render", "--motion", lframe, "--rig", rig, "-o", os.path.join(work, "frames"))
    # serve's calibration: the wand's world, tilted and shifted.
    served = moved_world(truth, matmul(rotation("x", TILT_DEG), rotation("y", 25.0)), (400.0, -250.0, 1200.0))
    with open(os.path.join(work, "frames", "calibration.json"), "w") as f:
        json.dump(served, f)
    return truth_path


class WorldFrameLiveTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.truth = lframe_scene(BIN, WORK)
        cls.rig = Rig(BIN, WORK, RATE)
        try:
            cls.rig.start(CAMERAS)
        except Exception:
            cls.rig.stop()
            raise

    @classmethod
    def tearDownClass(cls):
        cls.rig.stop()

    def evaluate(self, path):
        return json.loads(run(BIN, "eval-calibration", "--truth", self.truth, "--result", path, "--no-align",
                              "--json").stdout)

    def test_1_a_wrong_geometry_or_axis_is_refused_with_the_reason(self):
        port = self.rig.api_port
        before = self.evaluate(os.path.join(WORK, "frames", "calibration.json"))
        self.assertGreater(before["centre_max_mm"], 100.0)  # what the step has to undo
        status, body = http(port, "POST", "/api/calibration/world",
                            json.dumps({"up": "y", "lframe": [[0, 0, 0], [0, 0, 300], [0, 0, 600], [250, 0, 0]]}).encode())
        self.assertEqual(status, 422, body)
        reason = json.loads(body)["error"]
        self.assertIn("was found in 0 frames", reason)
        self.assertIn("4 points reconstructed per frame set (median) but not in its geometry", reason)
        status, body = http(port, "POST", "/api/calibration/world", b'{"up": "up"}')
        self.assertEqual(status, 400, body)
        self.assertEqual(glob.glob(os.path.join(WORK, "frames", "calibration.json.*")), [])  # nothing saved

    def test_2_the_lframe_puts_the_world_on_the_floor(self):
        port = self.rig.api_port
        status, body = http(port, "POST", "/api/calibration/world", b'{"up": "y", "frames": 60}')
        self.assertEqual(status, 200, body)
        report = json.loads(body)
        self.assertEqual(report["method"], "lframe")
        self.assertEqual(len(report["markers"]), 4)
        self.assertGreaterEqual(report["frames_used"], 50)
        self.assertAlmostEqual(report["tilt_removed_deg"], TILT_DEG, delta=0.1)
        self.assertLess(report["fit_rms_mm"], 1.0)
        saved = os.path.join(WORK, "frames", "calibration.json")
        self.assertEqual(report["saved"], saved)
        self.assertEqual(len(glob.glob(saved + ".*")), 1)  # the wand's world kept beside it
        status, body = http(port, "GET", "/api/calibration")
        self.assertEqual(json.loads(body)["file"], saved)
        evaluation = self.evaluate(saved)
        self.assertLess(evaluation["centre_max_mm"], MAX_CENTRE_MM, evaluation)
        self.assertLess(evaluation["rotation_max_deg"], MAX_ROTATION_DEG, evaluation)
        with open(saved) as f:
            self.assertEqual(json.load(f)["world_frame"]["method"], "lframe")
        print(f"floor step through serve: L-frame in {report['frames_used']} of {report['frames']} frame sets, "
              f"marker errors {[round(m['error_mm'], 2) for m in report['markers']]} mm, fit {report['fit_rms_mm']:.3f} mm, "
              f"tilt removed {report['tilt_removed_deg']:.3f} deg (applied {TILT_DEG}), moved {report['moved_mm']:.0f} mm, "
              f"turned {report['turned_deg']:.2f} deg; cameras against the truth: centres max "
              f"{evaluation['centre_max_mm']:.3f} mm, rotations max {evaluation['rotation_max_deg']:.4f} deg",
              file=sys.stderr)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
