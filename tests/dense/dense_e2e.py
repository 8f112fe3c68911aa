#!/usr/bin/env python3
"""ctest e2e (label shared_data): the dense marker set of ../shared/data/dense (123 markers, two
cluster markers 18-30 mm beside each) through the CLI as a user runs it: `sim rig` (10 cameras),
`sim project` with the hub issue's faults (merged blobs flagged by shape, as the node does),
`reconstruct`, `eval` against the known-correspondence floor (`reconstruct
--known-correspondences`). Registered always; skipped (exit 77, "../shared/data missing") where the
shared data is missing.

Asserted (issue 15's limits): with the defaults (predictions; contested ones left to the matcher)
and matching every frame from scratch (--no-predictions): rmse within 1.3x the floor, ghosts <=
0.02 and missing <= 0.01 per frame, trajectories <= 1.05x markers; and --threads 2 writes the very
same file as one thread. Issue 15's at most 10 swaps is not met: an expected failure.
usage: dense_e2e.py BIN_DIR WORK_DIR DENSE_TRC
"""
import json
import os
import shutil
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import SIM_FAULTS, run  # noqa: E402

BIN, WORK, MOTION = sys.argv[1:4]
SKIPPED = 77  # ctest's SKIP_RETURN_CODE for this test


def hub(*args):
    return run(BIN, *args, timeout=900).stdout


def reconstruct(session, rig, name, *options):
    out = os.path.join(WORK, name + ".trc")
    hub("reconstruct", session, "--calibration", rig, "-o", out, *options)
    return out


def evaluate(session, result):
    return json.loads(hub("eval", "--truth", os.path.join(session, "truth.trc"), "--result", result,
                          "--session", session, "--json"))


class DenseMarkers(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        cls.rig = os.path.join(WORK, "rig.json")
        cls.session = os.path.join(WORK, "session")
        hub("sim", "rig", "--motion", MOTION, "--cameras", "10", "-o", cls.rig)
        hub("sim", "project", "--motion", MOTION, "--rig", cls.rig, "-o", cls.session, *SIM_FAULTS)
        truth = os.path.join(cls.session, "truth.trc")
        cls.floor = evaluate(cls.session, reconstruct(cls.session, cls.rig, "floor", "--known-correspondences", truth))
        cls.markers = cls.floor["truth_markers"]

    def figures(self, name, *options):
        figures = evaluate(self.session, reconstruct(self.session, self.rig, name, *options))
        print(f"{name}: " + ", ".join(f"{k} {figures[k]}" for k in
                                      ("rmse_mm", "ghosts_per_frame", "missing_per_frame", "trajectories", "swaps")),
              f"(floor rmse {self.floor['rmse_mm']:.3f} mm, {self.markers} markers)", flush=True)
        return figures

    def meets_the_limits(self, f):
        self.assertLessEqual(f["rmse_mm"], 1.3 * self.floor["rmse_mm"])
        self.assertLessEqual(f["ghosts_per_frame"], 0.02)
        self.assertLessEqual(f["missing_per_frame"], 0.01)
        self.assertLessEqual(f["trajectories"], 1.05 * self.markers)

    def test_predictions_meet_the_limits_on_any_number_of_threads(self):
        self.meets_the_limits(self.figures("predictions"))
        two = reconstruct(self.session, self.rig, "predictions_2_threads", "--threads", "2")
        with open(os.path.join(WORK, "predictions.trc")) as a, open(two) as b:
            # The first line names the file itself.
            self.assertEqual(a.readlines()[1:], b.readlines()[1:], "two threads changed the result")

    def test_matching_every_frame_meets_the_limits(self):
        self.meets_the_limits(self.figures("from_scratch", "--no-predictions"))

    # Issue 15's limit (the swaps are printed with the figures above).
    def test_swaps_at_most_10_with_the_defaults(self):
        result = os.path.join(WORK, "predictions.trc")  # written by the test of the defaults, which runs first
        figures = evaluate(self.session, result) if os.path.isfile(result) else self.figures("predictions")
        self.assertLessEqual(figures["swaps"], 10)


if __name__ == "__main__":
    if not os.path.isfile(MOTION):
        print(f"skipped: ../shared/data missing (no {MOTION})")
        sys.exit(SKIPPED)
    unittest.main(argv=sys.argv[:1], verbosity=2)
