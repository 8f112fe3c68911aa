#!/usr/bin/env python3
"""Simulated rigid bodies end to end: three bodies of 4, 5 and 6 markers (30-120 mm apart, each
shape its own) fly fast around a walking subject (`sim project --bodies`: fast turns and spins,
passing 150 mm apart), 8 simulated cameras with the hub issue's faults; `reconstruct --bodies`
with the same bodies file, and `eval --bodies-truth` against the true poses the simulator wrote:
pose error (mm, degrees), identity swaps (gross errors) and the share of frames with a pose where
at least 3 of a body's markers were seen. The same reconstruction with each frame fitted alone
(`--bodies-window 0`) shows what the refinement over neighbouring frames gains. The live path
(`reconstruct --bodies-live`: what `serve --bodies` publishes, each frame's orientation from that
frame and past ones only) against the same path frame by frame (`--bodies-live-window 0`): it
must gain on the median and not lag at the fastest turns (pose_errors.py). The subject is the
simulator's synthetic walker, and in a test of its own the real walk.trc of ../shared/data/motions
(skipped, saying so, where that folder is missing; MOCAP_SHARED_DATA names another).

usage: sim_bodies_e2e.py BIN_DIR WORK_DIR"""

import json
import os
import shutil
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import SIM_FAULTS, run  # noqa: E402
from pose_errors import errors, percentile  # noqa: E402

BIN = WORK = None
# The shared recordings: ctest passes the configured folder (MOCAP_SHARED_DIR); run by hand, the
# one beside the checkout.
MOTIONS = os.path.join(os.environ.get("MOCAP_SHARED_DATA") or os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data"), "motions")
BODIES = {"version": 1, "bodies": [
    {"name": "wand", "markers": [[0, 0, 0], [110, 0, 0], [30, 75, 0], [45, 20, 60]]},
    {"name": "drone", "markers": [[0, 0, 0], [95, 10, 0], [20, 115, 5], [70, 60, -40], [-35, 50, 25]]},
    {"name": "tool", "markers": [[0, 0, 0], [60, 0, 0], [0, 40, 0], [85, 55, 20], [30, 90, 45], [-20, 35, 70]]}]}


def hub(*args):
    return run(BIN, *args, timeout=600).stdout


def evaluate(session, out, name):
    report = json.loads(hub("eval", "--truth", os.path.join(session, "truth.trc"), "--result", out, "--session",
                            session, "--bodies-truth", os.path.join(session, "truth.bodies.tsv"), "--json"))
    for b in report["rigid_bodies"]["bodies"]:
        print(f"{name} {b['name']}: pose in {100 * b['available_share']:.2f} % of {b['seen']} frames with >= 3 "
              f"markers seen; error p50 {b['p50_mm']:.3f} mm {b['p50_deg']:.3f} deg, p95 {b['p95_mm']:.3f} mm "
              f"{b['p95_deg']:.3f} deg; {b['gross']} gross", file=sys.stderr)
    return report["rigid_bodies"]["bodies"]


def bodies_report(name, motion):
    """(refined, per-frame) reports per body."""
    work = os.path.join(WORK, name)
    os.makedirs(work)
    bodies = os.path.join(work, "bodies.json")
    with open(bodies, "w") as f:
        json.dump(BODIES, f)
    rig, session, out = (os.path.join(work, n) for n in ("rig.json", "session", "out.trc"))
    hub("sim", "rig", "--motion", motion, "--cameras", "8", "-o", rig)
    hub("sim", "project", "--motion", motion, "--rig", rig, "-o", session, "--bodies", bodies, *SIM_FAULTS)
    single = os.path.join(work, "single.trc")
    for path, extra in ((out, []), (single, ["--bodies-window", "0"])):
        hub("reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", path,
            "--bodies", bodies, *extra)
    live, live_single = (os.path.join(work, n) for n in ("live.trc", "live_single.trc"))
    for path, extra in ((live, []), (live_single, ["--bodies-live-window", "0"])):
        hub("reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", path,
            "--bodies", bodies, "--bodies-live", *extra)
    turns = {}
    for path in (live, live_single):
        turns[path] = errors(os.path.join(session, "truth.bodies.tsv"), path[:-4] + ".bodies.tsv")
    return (evaluate(session, out, name), evaluate(session, single, name + " (each frame alone)"),
            evaluate(session, live, name + " live"), evaluate(session, live_single, name + " live, each frame alone"),
            turns[live], turns[live_single])


class SimBodiesE2e(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)

    def check(self, reports, live_target=False):
        bodies, single, live, live_single, live_turns, single_turns = reports
        self.assertEqual([b["name"] for b in bodies], ["wand", "drone", "tool"])
        for b, s in zip(bodies, single):
            self.assertEqual(b["gross"], 0, b["name"])  # identity never swapped
            self.assertGreaterEqual(b["available_share"], 0.995, b["name"])
            # Issue 14's targets. One frame alone cannot reach 0.2 deg here: the rotation's
            # Cramer-Rao bound from one frame's blobs is 0.22-0.30 deg for these bodies (README).
            self.assertLessEqual(b["p50_mm"], 0.5, b["name"])
            self.assertLessEqual(b["p50_deg"], 0.2, b["name"])
            # What the refinement does: a parabola through 13 frames keeps 0.42 of one frame's
            # rotation noise where it holds; occlusions and shrunk windows keep a little more.
            self.assertLess(b["p50_deg"], 0.6 * s["p50_deg"], b["name"])
            # ... and no worse at the fast turns (the tail) than each frame alone.
            self.assertLess(b["p95_deg"], s["p95_deg"], b["name"])
            self.assertEqual(b["fitted"], s["fitted"], b["name"])
        for b, s in zip(live, live_single):
            name = b["name"]
            self.assertEqual(b["gross"], 0, name)
            self.assertGreaterEqual(b["available_share"], 0.995, name)
            self.assertLessEqual(b["p50_mm"], 0.5, name)
            # From past frames only: a parabola through about 30 frames read at its end keeps about
            # half of one frame's noise (measured 0.51-0.75 of it at 100 and 60 Hz, 0.68 at 50 Hz).
            self.assertLess(b["p50_deg"], 0.8 * s["p50_deg"], name)
            self.assertLess(b["p95_deg"], s["p95_deg"], name)
            if live_target:  # 100 Hz: about 30 frames within 90 deg of turn
                self.assertLessEqual(b["p50_deg"], 0.2, name)
            # At the fastest turns (the top 5 % of the true angular acceleration) no lag: no worse
            # than each frame alone there.
            fast, fast_single = live_turns[name]["fast"], single_turns[name]["fast"]
            print(f"live {name} at the fastest turns: p50 {percentile(fast, 0.5):.3f} deg, each frame alone "
                  f"{percentile(fast_single, 0.5):.3f}", file=sys.stderr)
            self.assertLessEqual(percentile(fast, 0.5), percentile(fast_single, 0.5), name)

    def test_bodies_around_a_walking_subject(self):
        motion = os.path.join(WORK, "walker.trc")
        hub("sim", "motion", "-o", motion, "--markers", "20", "--frames", "300", "--rate", "100")
        self.check(bodies_report("synthetic", motion), live_target=True)

    @unittest.skipUnless(os.path.isdir(MOTIONS), "../shared/data missing")
    def test_bodies_around_the_real_walk(self):
        self.check(bodies_report("walk", os.path.join(MOTIONS, "walk.trc")))


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
