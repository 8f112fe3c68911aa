#!/usr/bin/env python3
"""Rigid bodies end to end: a walking subject and two rigid bodies (4 and 5 markers, moving and
turning near each other) are projected into 8 simulated cameras; `body define` takes each body
from the truth's first frame, refuses an ambiguous twin naming the distances, and `reconstruct
--bodies` writes the poses, which are compared with the truth (position of the pivot in mm,
rotation in degrees), and the virtual markers. Live: the same scene rendered and replayed by
real mocap-node processes into `serve --bodies`, whose /api/live frames, UDP stream (the
project's Python client) and Qualisys RT 6D component (Qualisys' own qtm-rt client) carry the
bodies' poses. Runs with the test virtual environment's Python (tests/requirements.txt).

usage: bodies_e2e.py BIN_DIR WORK_DIR"""

import asyncio
import math
import os
import re
import xml.etree.ElementTree as ET
import shutil
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import Rig, read_trc, run, wait_for, websocket_messages  # noqa: E402

import mocap_stream  # noqa: E402
import qtm_rt  # noqa: E402

BIN = WORK = None
RATE = 100
FRAMES = 300
WAND = [(0, 0, 0), (120, 0, 0), (0, 80, 0), (40, 30, 50)]
DRONE = [(0, 0, 0), (150, 0, 0), (30, 110, 0), (70, 40, -35), (-40, 60, 20)]


def hub(*args, check=True):
    return run(BIN, *args, check=check, timeout=300)


def rot(axis_angle):
    (x, y, z), a = axis_angle
    n = math.sqrt(x * x + y * y + z * z)
    x, y, z = x / n, y / n, z / n
    c, s, t = math.cos(a), math.sin(a), 1 - math.cos(a)
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c]]


def apply(r, p):
    return [sum(r[i][k] * p[k] for k in range(3)) for i in range(3)]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def angle_deg(r):
    return math.degrees(math.acos(max(-1.0, min(1.0, (r[0][0] + r[1][1] + r[2][2] - 1) / 2))))


def quat_to_matrix(x, y, z, w):
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def pose(body, f, centre):
    """(rotation, translation of the body's marker origin) at frame f; y is up."""
    s = f / RATE
    r = rot(((0, 1, 0), 0.9 * s + body)) if body == 0 else matmul(rot(((0, 1, 0), -0.7 * s)), rot(((1, 0, 0), 0.4 * math.sin(s))))
    t = [centre[0] + 250 * math.cos(0.6 * s + 2 * body), centre[1] + 900 + 150 * body, centre[2] + 250 * math.sin(0.6 * s + 2 * body)]
    return r, t


class BodiesE2e(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        motion = os.path.join(WORK, "motion.trc")
        hub("sim", "motion", "-o", motion, "--markers", "12", "--frames", str(FRAMES), "--rate", str(RATE))
        names, rows, lines = read_trc(motion)
        centre = [sum(p[k] for p in rows[0] if p) / len(names) for k in range(3)]
        cls.truth = {}
        extra = [f"W{i + 1}" for i in range(len(WAND))] + [f"D{i + 1}" for i in range(len(DRONE))]
        out = lines[:3]
        header = lines[3].split("\t")[:2] + [n for name in names + extra for n in (name, "", "")]
        out.append("\t".join(header))
        out.append("\t\t" + "\t".join(f"{a}{i + 1}" for i in range(len(names) + len(extra)) for a in "XYZ"))
        out.append("")
        data = [line for line in lines[5:] if line.strip()]
        out[2] = out[2].replace(f"\t{len(names)}\t", f"\t{len(names) + len(extra)}\t", 1)
        for f, row in enumerate(rows):
            cells = data[f].split("\t")[:2]
            for p in row:
                cells += ["%.4f" % v for v in p]
            for b, shape in enumerate((WAND, DRONE)):
                r, t = pose(b, f, centre)
                cls.truth[(b, f)] = (r, t)
                for m in shape:
                    cells += ["%.4f" % (v + t[k]) for k, v in enumerate(apply(r, m))]
            out.append("\t".join(cells))
        cls.scene = os.path.join(WORK, "scene.trc")
        with open(cls.scene, "w") as f:
            f.write("\n".join(out) + "\n")
        cls.bodies = os.path.join(WORK, "bodies.json")
        hub("body", "define", cls.scene, "--name", "wand", "--markers", "W1,W2,W3,W4", "--frames", "1:1", "-o", cls.bodies)
        hub("body", "define", cls.scene, "--name", "drone", "--markers", "D1,D2,D3,D4,D5", "--frames", "1:1",
            "-o", cls.bodies)
        rig, cls.session = os.path.join(WORK, "rig.json"), os.path.join(WORK, "session")
        hub("sim", "rig", "--motion", cls.scene, "--cameras", "8", "-o", rig)
        hub("sim", "project", "--motion", cls.scene, "--rig", rig, "-o", cls.session, "--noise-px", "0.2",
            "--occlusion", "0.02", "--occlusion-frames", "5")
        cls.out = os.path.join(WORK, "out.trc")
        cls.report = hub("reconstruct", cls.session, "--calibration", os.path.join(cls.session, "calibration.json"),
                         "-o", cls.out, "--bodies", cls.bodies).stdout

    def test_ambiguous_definition_is_refused(self):
        twin = hub("body", "define", self.scene, "--name", "twin", "--markers", "W1,W2,W3,W4,M001", "--frames", "1:1",
                   "-o", self.bodies, check=False)
        self.assertEqual(twin.returncode, 1, twin.stderr)
        self.assertIn("'twin' and 'wand'", twin.stderr)
        self.assertIn("120.0", twin.stderr)
        listed = hub("body", "list", self.bodies).stdout
        self.assertIn("wand", listed)
        self.assertIn("drone", listed)
        self.assertNotIn("twin", listed)

    def test_poses_match_the_truth(self):
        poses = os.path.join(WORK, "out.bodies.tsv")
        with open(poses) as f:
            lines = f.read().splitlines()[1:]
        errors = {0: [], 1: []}
        fitted = {0: 0, 1: 0}
        for line in lines:
            c = line.split("\t")
            b = {"wand": 0, "drone": 1}[c[2]]
            f = int(c[0]) - 1
            if c[3] != "1":
                continue
            fitted[b] += 1
            r_true, t_true = self.truth[(b, f)]
            r0, _ = self.truth[(b, 0)]
            shape = (WAND, DRONE)[b]
            centroid = [sum(m[k] for m in shape) / len(shape) for k in range(3)]
            pivot_true = [v + t_true[k] for k, v in enumerate(apply(r_true, centroid))]
            position = [float(v) for v in c[5:8]]
            r_est = quat_to_matrix(*[float(v) for v in c[8:12]])
            # The body frame is the world's at definition (frame 0): orientation = R_f R_0^T.
            r_expected = matmul(r_true, transpose(r0))
            errors[b].append((math.dist(position, pivot_true), angle_deg(matmul(r_est, transpose(r_expected)))))
        for b in (0, 1):
            mm = sorted(e[0] for e in errors[b])
            deg = sorted(e[1] for e in errors[b])
            print(f"\nbody {b}: fitted in {fitted[b]}/{FRAMES} frames; position error p50 {mm[len(mm) // 2]:.3f} "
                  f"p95 {mm[int(0.95 * len(mm))]:.3f} mm, rotation p50 {deg[len(deg) // 2]:.3f} "
                  f"p95 {deg[int(0.95 * len(deg))]:.3f} deg", file=sys.stderr)
            self.assertGreaterEqual(fitted[b], 0.95 * FRAMES)
            self.assertLess(mm[int(0.95 * len(mm))], 1.0)
            self.assertLess(deg[int(0.95 * len(deg))], 1.0)

    def test_live_bodies_in_serve(self):
        rig = os.path.join(WORK, "rig.json")
        hub("sim", "render", "--motion", self.scene, "--rig", rig, "-o", os.path.join(WORK, "frames"))
        live = Rig(BIN, WORK, RATE, serve_args=["--bodies", self.bodies, "--qtm-rt", "127.0.0.1:0"])
        try:
            live.start(8)
            frames = websocket_messages(live.api_port, "/api/live", 100)
            stream_port = int(re.search(r"stream: UDP port (\d+)", live.log()).group(1))
            with mocap_stream.StreamClient("127.0.0.1", stream_port, parts=("bodies",)) as client:
                streamed = [client.receive(2.0) for _ in range(30)]
            rt_port = int(wait_for("the RT port", lambda: re.search(r"Qualisys RT on [^:\s]+:(\d+)", live.log())).group(1))
            six_d, xml = asyncio.run(asyncio.wait_for(self.qtm_6d(rt_port), 60))
        finally:
            live.stop()
        # The project's stream: both bodies by name, fitted.
        self.assertTrue(all(f is not None and [b.name for b in f.bodies] == ["wand", "drone"] for f in streamed))
        self.assertGreater(sum(b.tracked for f in streamed for b in f.bodies), 0.9 * 2 * len(streamed))
        # Qualisys RT: the 6D parameters list both bodies with their markers, and 6D packets carry
        # two bodies with finite positions and rotation matrices.
        bodies = ET.fromstring(xml).findall("The_6D/Body")
        self.assertEqual([b.findtext("Name") for b in bodies], ["wand", "drone"])
        self.assertEqual([len(b.findall("Points/Point")) for b in bodies], [4, 5])
        counts = [info.body_count for info, _ in six_d]
        self.assertEqual(set(counts), {2})
        finite = sum(1 for _, bs in six_d for position, rotation in bs if not math.isnan(position.x))
        self.assertGreater(finite, 0.9 * 2 * len(six_d))
        names = {1: "wand", 2: "drone"}
        for body_id in names:
            poses = [b for f in frames for b in f["bodies"] if b[0] == body_id]
            self.assertEqual(len(poses), len(frames))
            tracked = [b for b in poses if b[1] == 1]
            errors = sorted(b[10] for b in tracked)
            print(f"\nlive {names[body_id]}: fitted in {len(tracked)}/{len(poses)} frames, mean marker error "
                  f"p50 {errors[len(errors) // 2]:.3f} mm", file=sys.stderr)
            self.assertGreaterEqual(len(tracked), 0.9 * len(poses))
            self.assertLess(errors[len(errors) // 2], 1.0)
            self.assertTrue(all(b[11] >= 3 for b in tracked))

    @staticmethod
    async def qtm_6d(port):
        conn = await qtm_rt.connect("127.0.0.1", port)
        got, done = [], asyncio.get_running_loop().create_future()

        def on_packet(packet):
            got.append(packet.get_6d())
            if len(got) == 30 and not done.done():
                done.set_result(None)

        await conn.stream_frames(components=["6d"], on_packet=on_packet)
        await asyncio.wait_for(done, 10)
        await conn.stream_frames_stop()
        xml = await conn.get_parameters(["6d"])
        conn.disconnect()
        return got, xml

    def test_virtual_markers_in_the_trc(self):
        names, rows, _ = read_trc(self.out)
        self.assertEqual(names[-2:], ["wand", "drone"])
        self.assertGreater(sum(1 for r in rows if r[-1] is not None), 0.95 * FRAMES)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
