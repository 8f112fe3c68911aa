#!/usr/bin/env python3
"""Marker-set labelling end to end: a labelled motion's first half teaches a marker set (`labels
learn`), the whole motion is projected into 8 simulated cameras with faults, `reconstruct
--labels` names the markers in TRC and C3D, `eval` measures the share of output points correctly
and wrongly named, OpenSim reads the named TRC and ezc3d the named C3D, with the names.
The motion is the simulator's own synthetic walker with names given here, so the test needs no
shared data and skips nothing without it: "another subject" is then the walker made larger with
its markers placed elsewhere, and "the rest of a trial" the walker after its first third. Where
../shared/data/motions exists beside the checkout, those two cases use the real motions: a set
learned from walk.trc names the reconstruction of running.trc (another subject), and the tennis
serve's first half names its whole reconstruction (and, measured on its own, the half it did not
learn from). Figures are printed; the floors asserted on the real cases are what the labeller
reaches today with some room (below issue 14's 99 % where the README says why).

usage: labels_e2e.py BIN_DIR WORK_DIR"""

import asyncio
import json
import math
import os
import re
import shutil
import sys
import unittest
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import SIM_FAULTS, Rig, read_trc, run, wait_for, websocket_messages  # noqa: E402

import mocap_stream  # noqa: E402
import qtm_rt  # noqa: E402

BIN = WORK = None
MOTIONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data", "motions")
def hub(*args):
    return run(BIN, *args, timeout=600).stdout


def rename(path, out, names_of):
    """A TRC with its marker names replaced (names_of: old -> new)."""
    with open(path) as f:
        lines = f.read().splitlines()
    cells = lines[3].split("\t")
    lines[3] = "\t".join(names_of(c) if c.strip() else c for c in cells[:2]) + "\t" + \
        "\t".join(names_of(c) if c.strip() else c for c in cells[2:])
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


def another_subject(path, out, scale=1.08, shift_mm=8.0):
    """The motion as another subject would make it: everything `scale` times larger and each
    marker placed up to shift_mm elsewhere on its segment (a fixed offset per marker)."""
    with open(path) as f:
        lines = f.read().splitlines()
    out_lines = lines[:5]
    for line in lines[5:]:
        cells = line.split("\t")
        if len(cells) < 3 or not cells[0].strip():
            out_lines.append(line)
            continue
        for k in range(2, len(cells)):
            if cells[k].strip():
                marker, axis = divmod(k - 2, 3)
                offset = shift_mm * math.sin(1.7 * marker + 2.3 * axis)
                cells[k] = "%.4f" % (float(cells[k]) * scale + offset)
        out_lines.append("\t".join(cells))
    with open(out, "w") as f:
        f.write("\n".join(out_lines) + "\n")


def first_part(path, out, share):
    """The first `share` of a TRC's frames (header counts fixed)."""
    with open(path) as f:
        lines = f.read().splitlines()
    rows = [line for line in lines[5:] if line.strip()]
    keep = rows[:int(len(rows) * share)]
    fields = lines[2].split("\t")
    fields[2] = str(len(keep))
    lines[2] = "\t".join(fields)
    with open(out, "w") as f:
        f.write("\n".join(lines[:5] + [""] + keep) + "\n")


def last_part(path, out, share):
    """The frames of a TRC after its first `share` (header counts fixed, frame numbers kept)."""
    with open(path) as f:
        lines = f.read().splitlines()
    rows = [line for line in lines[5:] if line.strip()]
    keep = rows[int(len(rows) * share):]
    fields = lines[2].split("\t")
    fields[2] = str(len(keep))
    lines[2] = "\t".join(fields)
    with open(out, "w") as f:
        f.write("\n".join(lines[:5] + [""] + keep) + "\n")


def labelled_reconstruction(name, motion, template_trials):
    """Learns a set, projects `motion` with faults, reconstructs with --labels; the eval report."""
    work = os.path.join(WORK, name)
    os.makedirs(work)
    marker_set = os.path.join(work, "set.json")
    hub("labels", "learn", *template_trials, "-o", marker_set)
    rig, session = os.path.join(work, "rig.json"), os.path.join(work, "session")
    hub("sim", "rig", "--motion", motion, "--cameras", "8", "-o", rig)
    hub("sim", "project", "--motion", motion, "--rig", rig, "-o", session, *SIM_FAULTS)
    out = os.path.join(work, "named.trc")
    print(hub("reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", out,
              "--labels", marker_set).strip().splitlines()[-1], file=sys.stderr)
    report = json.loads(hub("eval", "--truth", os.path.join(session, "truth.trc"), "--result", out, "--json"))
    print(f"{name}: {100 * report['correct_share']:.2f} % of points correctly named, "
          f"{100 * report['wrong_share']:.2f} % wrongly", file=sys.stderr)
    return work, session, out, report


class LabelsE2e(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        anonymous = os.path.join(WORK, "walker_anonymous.trc")
        hub("sim", "motion", "-o", anonymous, "--markers", "24", "--frames", "400", "--rate", "100")
        cls.motion = os.path.join(WORK, "walker.trc")
        rename(anonymous, cls.motion, lambda n: "Walker:" + n[1:] if n.startswith("M") else n)
        first = os.path.join(WORK, "walker_first_half.trc")
        first_part(cls.motion, first, 0.5)
        cls.work, cls.session, cls.out, cls.report = labelled_reconstruction("synthetic", cls.motion, [first])

    def test_synthetic_markers_are_named(self):
        self.assertTrue(self.report["labels_compared"])
        self.assertGreaterEqual(self.report["correct_share"], 0.9)
        self.assertLessEqual(self.report["wrong_share"], 0.05)

    def test_subject_labeller_names_the_synthetic_walker(self):
        """--labeller subject (a subject model initialised on the take) names the same
        reconstruction, writes its decisions, and the trial labeller refuses to write a log it has not."""
        out, log = os.path.join(self.work, "subject.trc"), os.path.join(self.work, "subject.log")
        calibration = os.path.join(self.session, "calibration.json")
        marker_set = os.path.join(self.work, "set.json")
        printed = hub("reconstruct", self.session, "--calibration", calibration, "-o", out, "--labels", marker_set,
                      "--labeller", "subject", "--labels-explain", log)
        self.assertIn("initialised at frame", printed)
        report = json.loads(hub("eval", "--truth", os.path.join(self.session, "truth.trc"), "--result", out, "--json"))
        print(f"subject labeller, synthetic: {100 * report['correct_share']:.2f} % right, "
              f"{100 * report['wrong_share']:.2f} % wrong", file=sys.stderr)
        self.assertGreaterEqual(report["correct_share"], 0.9)
        self.assertLessEqual(report["wrong_share"], 0.05)
        with open(log) as f:
            decisions = f.read().splitlines()
        self.assertTrue(any(line.startswith("initialisation: ") for line in decisions), decisions[:5])
        refused = run(BIN, "labels", "apply", out, "--labels", marker_set, "-o", os.path.join(self.work, "x.trc"),
                      "--explain", log, check=False)
        self.assertNotEqual(refused.returncode, 0)
        self.assertIn("--labeller subject", refused.stderr)

    def test_named_trc_read_by_opensim_and_named_c3d_by_ezc3d(self):
        # The opensim wheel on PyPI is built without its C3D adapter (no C3DFileAdapter), so the
        # named C3D is read by ezc3d (the library OpenSim's C3D adapter is built on).
        import ezc3d
        import opensim
        c3d = os.path.join(self.work, "named.c3d")
        hub("reconstruct", self.session, "--calibration", os.path.join(self.session, "calibration.json"), "-o", c3d,
            "--labels", os.path.join(self.work, "set.json"))
        trc = opensim.TimeSeriesTableVec3(self.out)
        trc_names = list(trc.getColumnLabels())
        self.assertGreaterEqual(sum(n.startswith("Walker:") for n in trc_names), 20)
        data = ezc3d.c3d(c3d)
        self.assertEqual(list(data["parameters"]["POINT"]["LABELS"]["value"]), trc_names)
        points = data["data"]["points"]
        self.assertEqual(points.shape[2], trc.getNumRows())
        row = trc.getNumRows() // 2
        for column, name in enumerate(trc_names):
            a = trc.getRowAtIndex(row)[column]
            if any(a.get(k) != a.get(k) for k in range(3)):  # NaN: a gap in both
                continue
            for k in range(3):
                self.assertAlmostEqual(a.get(k), float(points[k, column, row]), delta=0.01, msg=name)

    def test_live_names_in_serve(self):
        rig = os.path.join(self.work, "rig.json")
        live_work = os.path.join(WORK, "live")
        os.makedirs(live_work)
        hub("sim", "rig", "--motion", self.motion, "--cameras", "8", "--width", "640", "--height", "400", "-o", rig)
        hub("sim", "render", "--motion", self.motion, "--rig", rig, "-o", os.path.join(live_work, "frames"))
        marker_set = os.path.join(self.work, "set.json")
        live = Rig(BIN, live_work, 100, serve_args=["--labels", marker_set, "--qtm-rt", "127.0.0.1:0"])
        try:
            live.start(8)
            wait_for("frames to flow", lambda: websocket_messages(live.api_port, "/api/live", 1), timeout=15)
            frames = websocket_messages(live.api_port, "/api/live", 150)
            stream_port = int(re.search(r"stream: UDP port (\d+)", live.log()).group(1))
            with mocap_stream.StreamClient("127.0.0.1", stream_port, parts=("points", "labels")) as client:
                streamed = [client.receive(2.0) for _ in range(30)]
            rt_port = int(wait_for("the RT port", lambda: re.search(r"Qualisys RT on [^:\s]+:(\d+)", live.log())).group(1))
            xml = asyncio.run(asyncio.wait_for(self.qtm_3d_parameters(rt_port), 60))
        finally:
            live.stop()
        truth_names, truth_rows, _ = read_trc(self.motion)
        # Each live frame against the truth frame it shows (the replay loops): the frame whose
        # markers lie nearest its points.
        correct = wrong = points = 0
        for frame in frames[50:]:
            pts = frame["points"]
            if len(pts) < 5:
                continue
            best = min(range(len(truth_rows)), key=lambda f: sum(
                min(math.dist(p[:3], t) for t in truth_rows[f] if t) for p in pts[:5]))
            for p in pts:
                points += 1
                self.assertEqual(len(p), 8)
                if p[7] is None:
                    continue
                t = truth_rows[best][truth_names.index(p[7])]
                if t is not None and math.dist(p[:3], t) < 20:
                    correct += 1
                else:
                    wrong += 1
        print(f"\nlive: {100 * correct / points:.2f} % of points correctly named, {100 * wrong / points:.2f} % wrongly "
              f"({points} points, 100 frames)", file=sys.stderr)
        self.assertGreaterEqual(correct, 0.9 * points)
        self.assertLessEqual(wrong, 0.02 * points)
        named = [p.label for f in streamed if f is not None for p in f.points if p.label]
        self.assertGreater(len(named), 0.8 * sum(len(f.points) for f in streamed if f is not None))
        self.assertTrue(all(n.startswith("Walker:") for n in named))
        labels = [e.findtext("Name") for e in ET.fromstring(xml).findall("The_3D/Label")]
        with open(marker_set) as f:
            self.assertEqual(labels, [m["name"] for m in json.load(f)["markers"]])

    @staticmethod
    async def qtm_3d_parameters(port):
        conn = await qtm_rt.connect("127.0.0.1", port)
        xml = await conn.get_parameters(["3d"])
        conn.disconnect()
        return xml

    def test_another_subject(self):
        """walk.trc's set names running.trc (another person) where the shared data exists; else the
        walker's set names the walker made larger with its markers placed elsewhere."""
        if os.path.isdir(MOTIONS):
            # 90.00 % measured: the four wrist markers (10 %) stay unnamed (README).
            name, motion, trials = "running", os.path.join(MOTIONS, "running.trc"), [os.path.join(MOTIONS, "walk.trc")]
            floor = 0.85
        else:
            name, motion = "other_walker", os.path.join(WORK, "other_walker.trc")
            another_subject(self.motion, motion)
            trials = [os.path.join(WORK, "walker_first_half.trc")]
            floor = 0.9  # 100.00 % measured
        _, _, _, report = labelled_reconstruction(name, motion, trials)
        # What cannot be told apart on another subject stays unnamed, never wrongly named.
        self.assertGreaterEqual(report["correct_share"], floor)
        self.assertLessEqual(report["wrong_share"], 0.001)

    def test_second_half_from_the_first(self):
        """The tennis serve named by a set from its first half where the shared data exists (its
        reconstruction swaps right-arm markers: README); else the walker from its first third."""
        if os.path.isdir(MOTIONS):
            # Measured with three fault seeds: whole serve 96.67-98.31 % right, 0.95-1.86 % wrong
            # (chains of arm markers the tracker rotated in the first half); the second half
            # 99.62-99.71 % right, at most 0.02 % wrong (README).
            name, motion, share = "tennis", os.path.join(MOTIONS, "tennis_serve.trc"), 0.5
            first, floor, wrong = os.path.join(WORK, "tennis_first_half.trc"), 0.96, 0.025
            later_floor, later_wrong = 0.99, 0.001
        else:
            name, motion, share = "walker_third", self.motion, 1.0 / 3.0
            first, floor, wrong = os.path.join(WORK, "walker_first_third.trc"), 0.95, 0.01
            later_floor, later_wrong = 0.95, 0.01
        first_part(motion, first, share)
        work, session, out, report = labelled_reconstruction(name, motion, [first])
        self.assertGreaterEqual(report["correct_share"], floor)
        self.assertLessEqual(report["wrong_share"], wrong)
        # The part the set did not learn from, on its own.
        truth_later, out_later = os.path.join(work, "truth_later.trc"), os.path.join(work, "named_later.trc")
        last_part(os.path.join(session, "truth.trc"), truth_later, share)
        last_part(out, out_later, share)
        later = json.loads(hub("eval", "--truth", truth_later, "--result", out_later, "--json"))
        print(f"{name}, the part not learned from: {100 * later['correct_share']:.2f} % of points correctly named, "
              f"{100 * later['wrong_share']:.2f} % wrongly", file=sys.stderr)
        self.assertGreaterEqual(later["correct_share"], later_floor)
        self.assertLessEqual(later["wrong_share"], later_wrong)

    def test_a_set_learned_from_c3d_equals_the_trc_one(self):
        c3d = os.path.join(WORK, "walker_first_half.c3d")
        hub("convert", os.path.join(WORK, "walker_first_half.trc"), c3d)
        from_c3d = os.path.join(WORK, "set_from_c3d.json")
        hub("labels", "learn", c3d, "-o", from_c3d)
        with open(from_c3d) as f, open(os.path.join(self.work, "set.json")) as g:
            a, b = json.load(f), json.load(g)
        self.assertEqual([m["name"] for m in a["markers"]], [m["name"] for m in b["markers"]])
        # C3D keeps single-precision floats: the statistics agree closely (a pair whose sd sits on
        # the segment threshold may still fall either side of it).
        self.assertEqual(len(a["distances"]), len(b["distances"]))
        for x, y in zip(a["distances"], b["distances"]):
            self.assertEqual((x["a"], x["b"]), (y["a"], y["b"]))
            self.assertAlmostEqual(x["mean"], y["mean"], delta=0.01)
            self.assertAlmostEqual(x["sd"], y["sd"], delta=0.01)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
