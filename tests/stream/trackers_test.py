#!/usr/bin/env python3
"""The NatNet, VRPN and VMC adapters of `mocap-hub serve` read by real clients of those
protocols: three rigid bodies and a walking subject rendered and replayed by mocap-node processes
into serve --bodies --natnet --vrpn --vmc, with
  - NaturalPoint's own Python NatNet client (PyPI natnetsdk) over multicast: server info, the
    model definitions (every body by name, its markers), frames whose rigid bodies, labelled
    markers and stamps agree with the same frame on /api/live;
  - libmotioncapture's OptiTrack backend (PyPI motioncapture, the library under ROS 2
    motion_capture_tracking): every body by name, each pose one that /api/live published;
  - libmotioncapture's VRPN backend through the UDP lookup, and again over tcp:// after the
    first client went away (a reconnect): every body as a tracker, poses as published;
  - python-osc as a VMC receiver: /VMC/Ext/OK, /VMC/Ext/T and one /VMC/Ext/Tra/Pos per fitted
    body, in Unity's axes, agreeing with the frame /VMC/Ext/T names;
  - raw sockets for what the clients do not send: refused and unknown NatNet commands, and the
    NatNet command port still answering after garbage.
Poses agree within 0.01 mm and 0.001 degrees. Runs in a network namespace of its own (ctest's
unshare; its loopback carries multicast). Every wait bounded.

usage: trackers_test.py BIN_DIR WORK_DIR"""

import contextlib
import io
import json
import math
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import threading
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import live_rig  # noqa: E402
from live_rig import Rig, wait_for, websocket_messages  # noqa: E402
import tracker_scene  # noqa: E402

import motioncapture  # noqa: E402
from natnetsdk.NatNetClient import NatNetClient  # noqa: E402
from pythonosc import dispatcher, osc_server  # noqa: E402

BIN = WORK = None
RATE = 100
CAMERAS = 6
NATNET, VRPN, VMC = 1510, 3883, 39539
# Writes every /api/live frame as a JSON line: argv[1] the directory of live_rig.py, argv[2] the API port;
# the API token from the file $MOCAP_HUB_TOKEN_FILE names (as the CLI finds it).
COLLECTOR = """
import json, os, sys
sys.path.insert(0, sys.argv[1])
import live_rig
from live_rig import websocket_messages
with open(os.environ["MOCAP_HUB_TOKEN_FILE"]) as f:
    live_rig.TOKENS[int(sys.argv[2])] = f.read().strip()
websocket_messages(int(sys.argv[2]), "/api/live", 10**9, timeout=30,
                   on_message=lambda f: print(json.dumps(f), flush=True))
"""
MM_TOLERANCE = 0.01
DEG_TOLERANCE = 0.001


def angle_deg(q1, q2):
    """Angle of the rotation between two unit quaternions (x, y, z, w), robust near zero."""
    x1, y1, z1, w1 = q1
    x2, y2, z2, w2 = q2
    # q1^-1 q2
    w = w1 * w2 + x1 * x2 + y1 * y2 + z1 * z2
    x = w1 * x2 - x1 * w2 - y1 * z2 + z1 * y2
    y = w1 * y2 + x1 * z2 - y1 * w2 - z1 * x2
    z = w1 * z2 - x1 * y2 + y1 * x2 - z1 * w2
    return math.degrees(2 * math.atan2(math.sqrt(x * x + y * y + z * z), abs(w)))


def pose_error(live_body, position_mm, quaternion):
    """(mm, degrees) between a /api/live body [id, tracked, predicted, x, y, z, qx, qy, qz, qw, ...]
    and a pose."""
    return (math.dist(live_body[3:6], position_mm), angle_deg(live_body[6:10], quaternion))


def run_bounded(what, target, timeout):
    """target() on a daemon thread (the clients block in C without timeouts); its result, or a
    failure naming what did not finish."""
    result = {}

    def go():
        try:
            result["value"] = target()
        except BaseException as e:  # reported in the test's thread
            result["error"] = e

    t = threading.Thread(target=go, daemon=True)
    t.start()
    t.join(timeout)
    if t.is_alive():
        raise AssertionError(f"{what} did not finish within {timeout} s")
    if "error" in result:
        raise result["error"]
    return result["value"]


class TrackersTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        cls.names = tracker_scene.make(BIN, WORK, RATE, 300, CAMERAS)
        cls.rig = Rig(BIN, WORK, RATE, serve_args=[
            "--bodies", os.path.join(WORK, "bodies.json"), "--natnet", f"127.0.0.1:{NATNET}",
            "--vrpn", f"127.0.0.1:{VRPN}", "--vmc", f"127.0.0.1:{VMC}"])
        cls.vmc = []
        d = dispatcher.Dispatcher()
        d.set_default_handler(lambda address, *args: cls.vmc.append((time.monotonic(), address, args)))
        cls.osc = osc_server.ThreadingOSCUDPServer(("127.0.0.1", VMC), d)
        threading.Thread(target=cls.osc.serve_forever, daemon=True).start()
        try:
            cls.rig.start(CAMERAS)
            wait_for("NatNet and VRPN to listen", lambda: "NatNet on" in cls.rig.log() and "VRPN on" in cls.rig.log())
            # Every body fitted before the clients start.
            wait_for("all bodies fitted", lambda: all(
                b[1] for b in websocket_messages(cls.rig.api_port, "/api/live", 1)[0]["bodies"]), timeout=20)
            # Every /api/live frame from now until the rig stops, collected by a process of its own
            # (in this one the clients' threads would slow it until serve drops it as a slow reader);
            # the clients' poses are looked up there.
            cls.live, cls.live_path = {}, os.path.join(WORK, "live.jsonl")
            cls.live_file = open(cls.live_path, "w+")
            cls.collector = subprocess.Popen([sys.executable, "-c", COLLECTOR, os.path.dirname(live_rig.__file__),
                                              str(cls.rig.api_port)], stdout=cls.live_file, env=cls.rig.env)
        except BaseException:
            cls.rig.stop()
            cls.osc.shutdown()
            raise

    @classmethod
    def refresh_live(cls):
        """Takes the frames the collector wrote since the last call."""
        with open(cls.live_path) as f:
            f.seek(getattr(cls, "live_offset", 0))
            while True:
                line = f.readline()
                if not line.endswith("\n"):
                    break
                frame = json.loads(line)
                cls.live[frame["frame"]] = frame
                cls.live_offset = f.tell()
        return cls.live

    def live_frame(self, number):
        """That frame as /api/live published it; None when the collector did not get it (it started
        later, or /api/live skipped it: a reader that falls behind gets the newest frame)."""
        frame = wait_for(f"frame {number} or a later one on /api/live", lambda: self.refresh_live().get(number) or
                         (max(self.live, default=-1) > number and "skipped") or
                         (self.collector.poll() is not None and "gone"), timeout=10)
        self.assertNotEqual(frame, "gone", "the /api/live collector ended")
        return None if frame == "skipped" else frame

    @classmethod
    def tearDownClass(cls):
        cls.collector.kill()
        cls.collector.wait()
        cls.live_file.close()
        cls.rig.stop()
        cls.osc.shutdown()

    def live_bodies(self):
        """Every fitted body pose /api/live showed so far, by body id."""
        out = {}
        for f in list(self.refresh_live().values()):
            for b in f["bodies"]:
                if b[1]:
                    out.setdefault(b[0], []).append(b)
        return out

    def published(self, body_id, position_mm, quaternion):
        """Whether the pose is one /api/live published for that body, within tolerance (these clients
        give no frame number: the pose is looked up among all the body's published poses)."""
        deadline = time.monotonic() + 2
        while True:
            # The replayed motion repeats: a pose's nearest in position may be another lap's.
            best = min((pose_error(b, position_mm, quaternion) for b in self.live_bodies().get(body_id, [])),
                       key=lambda e: max(e[0] / MM_TOLERANCE, e[1] / DEG_TOLERANCE), default=(math.inf, math.inf))
            if (best[0] <= MM_TOLERANCE and best[1] <= DEG_TOLERANCE) or time.monotonic() > deadline:
                return best[0] <= MM_TOLERANCE and best[1] <= DEG_TOLERANCE
            time.sleep(0.2)  # the collector may be a little behind

    def assert_mostly_published(self, who, poses):
        """Most poses (name, position m, quaternion) are published ones: /api/live skips frames for a
        reader that falls behind, and a pose of a skipped frame has no counterpart there; a pose
        conversion error (axes, units, quaternion order) matches none."""
        matched = sum(self.published(self.names.index(n) + 1, [1000 * v for v in p], q) for n, p, q in poses)
        print(f"\n{who}: {matched} of {len(poses)} sampled poses are published ones (within {MM_TOLERANCE} mm and "
              f"{DEG_TOLERANCE} deg)", file=sys.stderr)
        self.assertGreaterEqual(matched, 0.6 * len(poses), who)
        self.assertGreater(matched, 10, who)

    # ---- NatNet ----

    def test_natnet_sdk_client(self):
        frames, descriptions = [], []
        client = NatNetClient()
        client.set_client_address("0.0.0.0")  # the data socket must take the group's datagrams
        client.set_server_address("127.0.0.1")
        client.set_use_multicast(True)
        # The SDK client reads multicast frames from the start but learns the version from its server
        # info: until then it parses frames as version 0.0 and its reading thread dies on the first.
        # Asking for the version it asks Motive for in its connect (4.1) closes that window.
        client._NatNetClient__nat_net_requested_version = [4, 1, 0, 0]
        unpack_frame = client._NatNetClient__unpack_mocap_data
        unpack_desc = client._NatNetClient__unpack_data_descriptions

        def on_frame(*args):
            offset, data = unpack_frame(*args)
            frames.append(data)
            return offset, data

        def on_desc(*args):
            offset, data = unpack_desc(*args)
            descriptions.append(data)
            return offset, data

        client._NatNetClient__unpack_mocap_data = on_frame
        client._NatNetClient__unpack_data_descriptions = on_desc
        with contextlib.redirect_stdout(io.StringIO()):  # the SDK client prints every frame
            try:
                self.assertTrue(client.run(), "natnetsdk could not open its sockets")
                wait_for("server info", client.connected, timeout=5)
                client.send_request(client.command_socket, client.NAT_REQUEST_MODELDEF, "", ("127.0.0.1", NATNET))
                wait_for("200 NatNet frames and the model definitions", lambda: len(frames) >= 200 and descriptions,
                         timeout=20)
            finally:
                client.shutdown()
        self.assertEqual(client.get_application_name(), "mocap-hub")
        self.assertEqual(client.get_nat_net_version_server()[:2], [4, 1])
        rigid = descriptions[0].rigid_body_list
        self.assertEqual([rb.sz_name.decode() if isinstance(rb.sz_name, bytes) else rb.sz_name for rb in rigid],
                         self.names)
        self.assertEqual([rb.id_num for rb in rigid], [1, 2, 3])
        self.assertEqual([len(rb.rb_marker_list) for rb in rigid], [4, 4, 4])
        sets = descriptions[0].marker_set_list
        self.assertEqual([s.marker_set_name.decode() if isinstance(s.marker_set_name, bytes) else s.marker_set_name
                          for s in sets], self.names)
        wait_for("the live frames", lambda: len(self.refresh_live()) > 0)
        compared = bodies = markers = 0
        for data in frames:
            number = data.prefix_data.frame_number
            live = self.live_frame(number)
            if live is None:
                continue
            compared += 1
            suffix = data.suffix_data
            self.assertEqual(suffix.stamp_camera_mid_exposure, live["trigger_ns"])
            self.assertLessEqual(suffix.stamp_camera_mid_exposure, suffix.stamp_data_received)
            self.assertLessEqual(suffix.stamp_data_received, suffix.stamp_transmit)
            self.assertGreaterEqual(suffix.stamp_transmit, live["publish_ns"])
            self.assertAlmostEqual(suffix.timestamp, number / RATE, places=9)
            by_id = {b[0]: b for b in live["bodies"]}
            self.assertEqual(sorted(rb.id_num for rb in data.rigid_body_data.rigid_body_list), sorted(by_id))
            for rb in data.rigid_body_data.rigid_body_list:
                b = by_id[rb.id_num]
                self.assertEqual(bool(rb.tracking_valid), bool(b[1]))
                if not b[1]:
                    continue
                mm, deg = pose_error(b, [1000 * v for v in rb.pos], rb.rot)
                self.assertLessEqual(mm, MM_TOLERANCE, f"frame {number} body {rb.id_num}")
                self.assertLessEqual(deg, DEG_TOLERANCE, f"frame {number} body {rb.id_num}")
                self.assertAlmostEqual(rb.error * 1000, b[10], delta=0.0011)
                bodies += 1
            # Every point is a labelled marker; confirmed ones carry their marker column + 1.
            got = [(m.id_num, [1000 * v for v in m.pos]) for m in data.labeled_marker_data.labeled_marker_list]
            want = [(p[3] + 1 if not p[4] else 0, p[:3]) for p in live["points"]]
            self.assertEqual(len(got), len(want), f"frame {number}")
            for gid, gpos in got:
                nearest = min((math.dist(gpos, wpos) for wid, wpos in want if wid == gid), default=math.inf)
                self.assertLessEqual(nearest, MM_TOLERANCE, f"frame {number}: marker {gid} at {gpos}")
                markers += 1
        print(f"\nNatNet (natnetsdk): {len(frames)} frames, {compared} compared with /api/live: {bodies} body poses, "
              f"{markers} markers agree", file=sys.stderr)
        self.assertGreater(compared, 100)
        self.assertGreater(bodies, 0.75 * 3 * compared)  # poses compared in most frames (fitted ones)

    def test_natnet_libmotioncapture(self):
        def read():
            mc = motioncapture.connect("optitrack", {"hostname": "127.0.0.1"})
            seen = []
            for _ in range(100):
                mc.waitForNextFrame()
                seen.append({name: (list(rb.position), (rb.rotation.x, rb.rotation.y, rb.rotation.z, rb.rotation.w))
                             for name, rb in mc.rigidBodies.items()})
            return seen

        seen = run_bounded("libmotioncapture's OptiTrack client", read, 30)
        names = sorted({n for frame in seen for n in frame})
        self.assertEqual(names, sorted(self.names))
        poses = [(n, p, q) for frame in seen for n, (p, q) in frame.items()]
        self.assert_mostly_published("NatNet (libmotioncapture)", poses[::3])
        print(f"\nNatNet (libmotioncapture): 100 frames, {len(poses)} poses of {names}", file=sys.stderr)

    def test_natnet_commands_raw(self):
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.settimeout(2)
        server = ("127.0.0.1", NATNET)

        def ask(message_id, payload=b""):
            s.sendto(struct.pack("<HH", message_id, len(payload)) + payload, server)
            while True:
                data = s.recv(70000)
                if struct.unpack_from("<H", data)[0] != 7:
                    return data

        self.assertEqual(ask(2, b"FrameRate\0"), struct.pack("<HHf", 3, 4, RATE))
        self.assertEqual(ask(2, b"UnitsToMillimeters\0"), struct.pack("<HHf", 3, 4, 1000.0))
        self.assertEqual(ask(2, b"Bitstream\0"), struct.pack("<HH", 3, 14) + b"Bitstream,4.1\0")
        self.assertEqual(ask(2, b"StartRecording\0"), struct.pack("<HHi", 3, 4, 1))
        self.assertEqual(ask(2, b"NoSuchThing\0"), struct.pack("<HHi", 3, 4, 1))
        self.assertEqual(ask(55), struct.pack("<HH", 100, 0))
        s.sendto(b"\x02\x00\xff\xffgarbage", server)
        self.assertEqual(s.recv(100), struct.pack("<HH", 100, 0))
        self.assertEqual(ask(2, b"FrameRate\0"), struct.pack("<HHf", 3, 4, RATE))  # still answering
        s.close()
        status = json.loads(self.rig.hub("status", "--json").stdout)
        self.assertGreaterEqual(status["natnet"]["refused"], 4)

    # ---- VRPN ----

    def vrpn_read(self, hostname, seconds):
        def read():
            mc = motioncapture.connect("vrpn", {"hostname": hostname})
            seen, end = [], time.monotonic() + seconds
            while time.monotonic() < end:
                mc.waitForNextFrame()
                for name, rb in mc.rigidBodies.items():
                    seen.append((name, list(rb.position), (rb.rotation.x, rb.rotation.y, rb.rotation.z, rb.rotation.w)))
            del mc
            return seen

        return run_bounded(f"libmotioncapture's VRPN client ({hostname})", read, seconds + 20)

    def test_vrpn_libmotioncapture_and_reconnect(self):
        for hostname in (f"127.0.0.1:{VRPN}", f"tcp://127.0.0.1:{VRPN}"):
            seen = self.vrpn_read(hostname, 4)
            names = sorted({n for n, _, _ in seen})
            self.assertEqual(names, sorted(self.names), hostname)
            self.assert_mostly_published(f"VRPN (libmotioncapture, {hostname})", seen[::max(1, len(seen) // 60)])
            print(f"\nVRPN (libmotioncapture, {hostname}): {len(seen)} reports of {names}", file=sys.stderr)
        status = json.loads(self.rig.hub("status", "--json").stdout)
        self.assertGreaterEqual(status["vrpn"]["connections"], 2)
        self.assertGreaterEqual(status["vrpn"]["lookups"], 1)

    # ---- VMC ----

    def test_vmc_python_osc(self):
        wait_for("VMC bundles", lambda: len(self.vmc) > 300, timeout=10)
        messages = list(self.vmc)
        addresses = {a for _, a, _ in messages}
        self.assertEqual(addresses, {"/VMC/Ext/OK", "/VMC/Ext/T", "/VMC/Ext/Tra/Pos"})
        for _, a, args in messages:
            if a == "/VMC/Ext/OK":
                self.assertEqual(len(args), 4)
                self.assertEqual(args[:3], (1, 3, 0))
        # Each tracker follows the T of its bundle: the frame it belongs to.
        compared, skipped, frame = 0, 0, None
        for _, address, args in messages:
            if address == "/VMC/Ext/T":
                frame = round(args[0] * RATE)
            elif address == "/VMC/Ext/Tra/Pos" and frame is not None:
                if compared >= 300:
                    break
                live = self.live_frame(frame)
                if live is None:
                    skipped += 1
                    continue
                name, x, y, z, qx, qy, qz, qw = args
                body = live["bodies"][self.names.index(name)]
                self.assertTrue(body[1], f"frame {frame}: {name} sent but not fitted")
                # Unity from the hub's y-up world: z mirrored (vmc_sender.h).
                mm, deg = pose_error(body, [1000 * x, 1000 * y, -1000 * z], (-qx, -qy, qz, qw))
                self.assertLessEqual(mm, MM_TOLERANCE + 0.001, f"frame {frame} {name}")  # float32 metres
                self.assertLessEqual(deg, DEG_TOLERANCE, f"frame {frame} {name}")
                compared += 1
        print(f"\nVMC (python-osc): {len(messages)} messages, {compared} tracker poses agree", file=sys.stderr)
        self.assertGreater(compared, 100)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
