#!/usr/bin/env python3
"""The Qualisys-RT-compatible server of `mocap-hub serve --qtm-rt` read by Qualisys' own Python
SDK (qtm-rt from PyPI, in .venv): connect, negotiate, read the General/3D/6D parameters and check
them against the rig, stream 3D (labelled, residuals, no labels) and compare every point with the
same frame on the live WebSocket, stream 6D and 6D Euler (no bodies yet: count 0), poll
GetCurrentFrame, stop, disconnect. Raw sockets add what the SDK cannot send: UDP streaming, bad
commands and garbage, a client that never reads (it must not slow another client nor the hub)
and 100 clients at once. Loopback only; every wait bounded; prints the trigger -> received
latency of the RT path.

usage: qtm_rt_test.py BIN_DIR WORK_DIR"""

import asyncio
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
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import STUCK_S, Rig, percentiles, render_scene, wait_for, websocket_messages  # noqa: E402

import qtm_rt  # noqa: E402
from qtm_rt.packet import QRTComponentType, QRTEvent, QRTPacket  # noqa: E402

BIN = WORK = None
CAMERAS = 4
RATE = 100


def packet(kind, text):
    body = text.encode() + b"\0"
    return struct.pack("<II", 8 + len(body), kind) + body


def missed(rt_numbers, live_numbers):
    """Frames the live WebSocket showed within the RT client's span that the RT client lacks (the
    hub's own frame numbers may have gaps, so "every frame" means every frame it published)."""
    got = set(rt_numbers)
    return [n for n in live_numbers if rt_numbers[0] <= n <= rt_numbers[-1] and n not in got]


class RawClient:
    """The protocol by hand: send command packets, read whole packets back."""

    def __init__(self, port, rcvbuf=None):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if rcvbuf:
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
        self.sock.settimeout(5.0)
        self.sock.connect(("127.0.0.1", port))
        self.buf = b""

    def send(self, text, kind=1):
        self.sock.sendall(packet(kind, text))

    def next(self):
        """(type, body) of the next packet; None once the server closed."""
        while True:
            if len(self.buf) >= 8:
                size, kind = struct.unpack_from("<II", self.buf)
                if len(self.buf) >= size:
                    body, self.buf = self.buf[8:size], self.buf[size:]
                    return kind, body
            chunk = self.sock.recv(65536)
            if not chunk:
                return None
            self.buf += chunk

    def next_not_event(self):
        while True:
            p = self.next()
            if p is None or p[0] != 6:
                return p

    def close(self):
        self.sock.close()


class QtmRtTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        render_scene(BIN, WORK, CAMERAS, RATE)
        cls.rig = Rig(BIN, WORK, RATE, serve_args=["--qtm-rt", "127.0.0.1:0"])
        try:
            cls.rig.start(CAMERAS)
            cls.port = int(wait_for("the Qualisys RT port", lambda: re.search(
                r"Qualisys RT on [^:\s]+:(\d+)", cls.rig.log())).group(1))
            with open(os.path.join(WORK, "frames", "calibration.json")) as f:
                cls.camera_ids = sorted(c["id"] for c in json.load(f)["cameras"])
        except BaseException:
            cls.rig.stop()  # tearDownClass does not run when setUpClass fails
            raise

    @classmethod
    def tearDownClass(cls):
        cls.rig.stop()

    def status(self):
        return json.loads(self.rig.hub("status", "--json").stdout)

    def run_async(self, coroutine):
        return asyncio.run(asyncio.wait_for(coroutine, 60))

    def test_1_parameters_describe_the_rig(self):
        async def go():
            events = []
            conn = await qtm_rt.connect("127.0.0.1", self.port, on_event=events.append)
            self.assertIsNotNone(conn, "qtm_rt.connect failed (version negotiation?)")
            self.assertEqual(await conn.byte_order(), b"Byte order is little endian")
            self.assertTrue((await conn.qtm_version()).startswith(b"QTM Version is mocap-hub"))
            self.assertEqual(await conn.get_state(), QRTEvent.EventConnected)  # frames flow
            general = ET.fromstring(await conn.get_parameters(["general"]))
            # Labels exist once the tracker confirmed markers.
            deadline = time.monotonic() + 10
            while True:
                three_d = ET.fromstring(await conn.get_parameters(["3d"]))
                if int(three_d.findtext("The_3D/Labels")) > 0 or time.monotonic() > deadline:
                    break
                await asyncio.sleep(0.2)
            six_d = ET.fromstring(await conn.get_parameters(["6d"]))
            everything = ET.fromstring(await conn.get_parameters(["all"]))
            conn.disconnect()
            return general, three_d, six_d, everything

        general, three_d, six_d, everything = self.run_async(go())
        self.assertEqual(general.tag, "QTM_Parameters_Ver_1.25")
        self.assertEqual(float(general.findtext("General/Frequency")), RATE)
        self.assertEqual(sorted(int(c.findtext("ID")) for c in general.findall("General/Camera")), self.camera_ids)
        # What strict readers (Qualisys' C++ SDK) insist on is there.
        for path in ("External_Time_Base/Signal_Edge", "Processing_Actions/Tracking",
                     "RealTime_Processing_Actions/AIM", "Reprocessing_Actions/ExportC3D", "Start_On_Trigger_NO"):
            self.assertIsNotNone(general.find("General/" + path), path)
        for camera in general.findall("General/Camera"):
            for path in ("Serial", "Mode", "Video_Frequency", "Marker_Exposure/Max", "Marker_Threshold/Current",
                         "Position/Rot_3_3", "Orientation", "Marker_Res/Width", "Video_Res/Height", "Marker_FOV/Bottom"):
                self.assertIsNotNone(camera.find(path), path)
        # sim motion's subject walks with y up; the cameras around it say so.
        self.assertEqual(three_d.findtext("The_3D/AxisUpwards"), "+Y")
        labels = [l.findtext("Name") for l in three_d.findall("The_3D/Label")]
        self.assertEqual(len(labels), int(three_d.findtext("The_3D/Labels")))
        self.assertGreater(len(labels), 0)
        self.assertTrue(all(re.fullmatch(r"T\d+", n) for n in labels))  # confirmed tracks by id
        self.assertEqual(six_d.findtext("The_6D/Bodies"), "0")
        self.assertEqual([b.tag for b in everything], ["General", "The_3D", "The_6D"])

    def test_2_streamed_3d_is_what_the_live_websocket_shows(self):
        live = {}
        reader = threading.Thread(target=lambda: live.update(
            {m["frame"]: m for m in websocket_messages(self.rig.api_port, "/api/live", 200)}))
        reader.start()

        async def go():
            conn = await qtm_rt.connect("127.0.0.1", self.port)
            got, done = [], asyncio.get_running_loop().create_future()

            def on_packet(p):
                got.append((time.time_ns(), p))
                if len(got) == 200 and not done.done():
                    done.set_result(None)

            await conn.stream_frames(components=["3d", "3dres", "3dnolabels"], on_packet=on_packet)
            await asyncio.wait_for(done, 20)
            await conn.stream_frames_stop()
            await asyncio.sleep(0.3)  # frames already on the wire drain
            labels = [l.findtext("Name") for l in ET.fromstring(await conn.get_parameters(["3d"])).findall(
                "The_3D/Label")]
            conn.disconnect()
            return got, labels

        before = self.status()["qtm_rt"]
        got, labels = self.run_async(go())
        reader.join(20)
        after = self.status()["qtm_rt"]
        numbers = [p.framenumber for _, p in got]
        self.assertEqual(numbers, sorted(set(numbers)))
        # AllFrames: a frame the client lacks is one the server counted as dropped (the client fell
        # more than its queue behind, which only a starved machine makes it do) -- never lost unseen.
        lost = missed(numbers, sorted(live))
        dropped = sum(after[k] - before[k] for k in ("frames_dropped", "queue_dropped"))
        self.assertLessEqual(len(lost), dropped, lost)
        self.assertLess(len(lost), len(numbers) // 10, lost)
        latency = []
        compared = 0
        for received_ns, p in got:
            info, unlabelled = p.get_3d_markers_no_label()
            info3, labelled = p.get_3d_markers()
            info_res, residual = p.get_3d_markers_residual()
            self.assertEqual(len(labelled), info3.marker_count)
            self.assertEqual(len(residual), len(labelled))
            self.assertLessEqual(len(labelled), len(labels))  # labels only grow
            latency.append((received_ns - p.timestamp * 1000) / 1e6)
            frame = live.get(p.framenumber)
            if frame is None:
                continue
            compared += 1
            self.assertEqual(len(unlabelled), len(frame["points"]))
            by_marker = {}
            for m, q in zip(unlabelled, frame["points"]):
                self.assertAlmostEqual(m.x, q[0], delta=2e-3)
                self.assertAlmostEqual(m.y, q[1], delta=2e-3)
                self.assertAlmostEqual(m.z, q[2], delta=2e-3)
                self.assertEqual(m.id, max(q[3], 0))  # the track's id, provisional or confirmed
                if not q[4]:
                    by_marker[q[3]] = q
            for i, (m, r) in enumerate(zip(labelled, residual)):
                q = by_marker.get(int(labels[i][1:]))  # T17: track 17
                if q is None:
                    self.assertTrue(math.isnan(m.x) and math.isnan(m.y) and math.isnan(m.z))
                else:
                    self.assertAlmostEqual(m.x, q[0], delta=2e-3)
                    self.assertAlmostEqual(m.z, q[2], delta=2e-3)
                    self.assertAlmostEqual(r.residual, q[6], delta=2e-3)
            self.assertEqual(sum(1 for m in labelled if not math.isnan(m.x)), len(by_marker))
        self.assertGreater(compared, 100)
        self.assertGreater(sum(len(p.get_3d_markers_no_label()[1]) for _, p in got), 5 * len(got))
        print("\nQualisys RT (qtm-rt, TCP): trigger -> received ms p50 %.3f p99 %.3f max %.3f" %
              percentiles(latency), file=sys.stderr)

    def test_3_six_d_components_and_current_frame(self):
        async def go():
            events = []
            conn = await qtm_rt.connect("127.0.0.1", self.port, on_event=events.append)
            got, done = [], asyncio.get_running_loop().create_future()

            def on_packet(p):
                got.append(p)
                if len(got) == 10 and not done.done():
                    done.set_result(None)

            await conn.stream_frames(frames="frequencydivisor:2",
                                     components=["6d", "6deuler", "6dres", "6deulerres"], on_packet=on_packet)
            await asyncio.wait_for(done, 10)
            await conn.stream_frames_stop()
            await asyncio.sleep(0.3)
            current = await conn.get_current_frame(components=["3dnolabels", "6d"])
            conn.disconnect()
            return got, current

        got, current = self.run_async(go())
        for p in got:
            for getter in (p.get_6d, p.get_6d_euler, p.get_6d_residual, p.get_6d_euler_residual):
                info, bodies = getter()
                self.assertEqual((info.body_count, bodies), (0, []))
        steps = {b.framenumber - a.framenumber for a, b in zip(got, got[1:])}
        self.assertEqual(steps, {2})  # FrequencyDivisor:2
        self.assertIsInstance(current, QRTPacket)
        self.assertIn(QRTComponentType.Component3dNoLabels, current.components)
        self.assertEqual(current.get_6d()[0].body_count, 0)
        self.assertGreater(len(current.get_3d_markers_no_label()[1]), 0)

    def test_4_udp_streaming(self):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as udp:
            udp.bind(("127.0.0.1", 0))
            udp.settimeout(5.0)
            c = RawClient(self.port)
            self.assertEqual(c.next()[1], b"QTM RT Interface connected\0")
            c.send(f"StreamFrames Frequency:25 UDP:{udp.getsockname()[1]} 3DNoLabelsRes")
            frames, latency = [], []
            while len(frames) < 50:
                data = udp.recv(65536)
                received_ns = time.time_ns()
                size, kind = struct.unpack_from("<II", data)
                self.assertEqual((size, kind), (len(data), 3))
                frames.append(QRTPacket(data[8:]))
                latency.append((received_ns - frames[-1].timestamp * 1000) / 1e6)
            c.send("StreamFrames Stop")
            c.send("ByteOrder")
            self.assertEqual(c.next_not_event()[1], b"Byte order is little endian\0")
            c.close()
        info, points = frames[-1].get_3d_markers_no_label_residual()
        self.assertEqual(info.marker_count, len(points))
        steps = [b.framenumber - a.framenumber for a, b in zip(frames, frames[1:])]
        self.assertTrue(all(s == RATE // 25 for s in steps), steps)  # Frequency:25 of 100 Hz
        print("\nQualisys RT (raw socket, UDP): trigger -> received ms p50 %.3f p99 %.3f max %.3f" %
              percentiles(latency), file=sys.stderr)

    def test_5_bad_input_gets_errors_and_the_connection_stays(self):
        async def go():
            conn = await qtm_rt.connect("127.0.0.1", self.port)
            errors = []
            for call in (lambda: conn._protocol.send_command("bogus command"),
                         lambda: conn.get_parameters(["analog"]),
                         lambda: conn.get_current_frame(components=["2d"]),
                         lambda: conn.take_control("secret"),
                         lambda: conn._protocol.send_command("version 9.9")):
                try:
                    await asyncio.wait_for(call(), 5)
                except qtm_rt.QRTCommandException as e:
                    errors.append(str(e))
            ok = await conn.byte_order()
            conn.disconnect()
            return errors, ok

        errors, ok = self.run_async(go())
        self.assertEqual(len(errors), 5, errors)
        self.assertEqual(ok, b"Byte order is little endian")

        c = RawClient(self.port)
        c.next()
        c.sock.sendall(struct.pack("<II", 8 + 20000, 1) + b"A" * 20000)  # a huge line
        kind, body = c.next()
        self.assertEqual(kind, 0)
        self.assertIn(b"too long", body)
        c.send("<QTM_Settings/>", kind=2)
        self.assertEqual(c.next()[0], 0)
        c.send("GetState")
        self.assertEqual(c.next(), (6, b"\x01"))
        c.sock.sendall(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n")  # cannot be framed: error, then closed
        self.assertEqual(c.next()[0], 0)
        self.assertIsNone(c.next())
        c.close()

        c = RawClient(self.port)
        c.next()
        c.send("Quit")
        self.assertEqual(c.next(), (1, b"Bye bye\0"))
        self.assertIsNone(c.next())
        c.close()
        self.assertGreaterEqual(self.status()["qtm_rt"]["errors"], 8)
        self.assertIsNone(self.rig.serve.poll())

    def test_6_a_client_that_never_reads_slows_nobody(self):
        silent = RawClient(self.port, rcvbuf=4096)
        silent.send("StreamFrames AllFrames All")

        async def reader(seconds):
            conn = await qtm_rt.connect("127.0.0.1", self.port)
            got = []
            await conn.stream_frames(components=["3dnolabels"], on_packet=lambda p: got.append(p.framenumber))
            await asyncio.sleep(seconds)
            await conn.stream_frames_stop()
            conn.disconnect()
            return got

        live = []
        try:
            time.sleep(1.0)  # the silent client's buffers fill
            before = self.status()
            watcher = threading.Thread(target=lambda: live.extend(
                m["frame"] for m in websocket_messages(self.rig.api_port, "/api/live", 2 * RATE)))
            watcher.start()
            t0 = time.monotonic()
            got = self.run_async(reader(3.0))
            elapsed = time.monotonic() - t0
            after = self.status()
            watcher.join(STUCK_S)
        finally:
            silent.close()
        published = after["frame_sets"] - before["frame_sets"]
        rt = after["qtm_rt"]
        print(f"\nsilent RT client: serve published {published / elapsed:.1f} frame sets/s (rate {RATE} Hz), "
              f"a reading RT client got {len(got) / 3.0:.1f} frames/s; frames the silent one lost so far "
              f"{rt['frames_dropped']}, RT thread fell behind by {rt['queue_dropped']}", file=sys.stderr)
        self.assertGreater(rt["frames_dropped"], 0)  # the silent client's bound was reached ...
        self.assertEqual(got, sorted(set(got)))
        self.assertGreater(sum(1 for n in live if got[0] <= n <= got[-1]), RATE // 2)  # they overlap
        self.assertEqual(missed(got, live), [])  # ... and the reader lost nothing
        # (The rates printed above are figures, not asserted: they follow how busy the machine is.)
        self.assertGreater(published, 0)
        self.assertEqual(after["incomplete_frame_sets"], before["incomplete_frame_sets"])

    def test_7_capture_events(self):
        async def go():
            events = []
            conn = await qtm_rt.connect("127.0.0.1", self.port, on_event=events.append)
            self.rig.hub("capture", "start", "qtm_rt_events")
            started = await conn.await_event(QRTEvent.EventCaptureStarted, timeout=10)
            state = await conn.get_state()
            self.rig.hub("capture", "stop")
            stopped = await conn.await_event(QRTEvent.EventCaptureStopped, timeout=10)
            conn.disconnect()
            return started, state, stopped

        started, state, stopped = self.run_async(go())
        self.assertEqual((started, state, stopped), (QRTEvent.EventCaptureStarted, QRTEvent.EventCaptureStarted,
                                                     QRTEvent.EventCaptureStopped))

    def test_8_a_hundred_clients_at_once(self):
        clients = []
        try:
            for _ in range(100):
                s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
                s.setblocking(False)
                s.connect_ex(("127.0.0.1", self.port))
                clients.append(s)
            greeting = packet(1, "QTM RT Interface connected")
            got = {}
            deadline = time.monotonic() + 10
            while len(got) < 100 and time.monotonic() < deadline:
                for i, s in enumerate(clients):
                    if got.get(i, b"").startswith(greeting):
                        continue
                    try:
                        data = s.recv(4096)
                    except (BlockingIOError, InterruptedError):
                        continue
                    got[i] = got.get(i, b"") + data
                time.sleep(0.01)
            greeted = sum(1 for v in got.values() if v.startswith(greeting))
            print(f"\n100 RT clients at once: {greeted} greeted, "
                  f"{self.status()['qtm_rt']['clients']} connected", file=sys.stderr)
            self.assertEqual(greeted, 100)
        finally:
            for s in clients:
                s.close()  # all vanish at once
        wait_for("the clients gone", lambda: self.status()["qtm_rt"]["clients"] == 0)
        self.assertIsNone(self.rig.serve.poll())

    def test_9_bad_options(self):
        # A malformed address is a usage error (2); a port in use is a failure (1); both say why.
        calibration = os.path.join(WORK, "frames", "calibration.json")
        for address, status, reason in (("nohost", 2, "HOST:PORT"), (f"127.0.0.1:{self.port}", 1, "listen")):
            out = subprocess.run([os.path.join(BIN, "mocap-hub"), "serve", "--calibration", calibration,
                                  "--listen", "127.0.0.1:0", "--api", "127.0.0.1:0", "--stream", "off",
                                  "--sessions-dir", os.path.join(WORK, "bad_options", "sessions"),
                                  "--keys", self.rig.keys, "--qtm-rt", address], capture_output=True, text=True, timeout=30)
            self.assertEqual(out.returncode, status, out.stderr)
            self.assertIn(reason, out.stderr)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=sys.argv[:1], verbosity=2)
