#!/usr/bin/env python3
"""`mocap-hub serve` with real `mocap-node` processes on loopback, driven as an operator would:
through the CLI clients, the HTTP API and the live WebSocket, under a NOTIFY_SOCKET the test
owns (systemd's Type=notify protocol). Python standard library only.

usage: serve_test.py BIN_DIR WORK_DIR

Every wait is bounded; every process the test starts is killed at the end."""

import base64
import json
import os
import random
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
import unittest
import zlib

BIN = WORK = None
CAMERAS = 4
RATE = 100
REFLECTIONS = 6


def wait_for(what, predicate, timeout=10.0, step=0.05):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(step)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def run(*args, check=True, env=None):
    result = subprocess.run([os.path.join(BIN, "mocap-hub"), *args], capture_output=True, text=True,
                            timeout=60, env=env)
    if check and result.returncode != 0:
        raise AssertionError(f"mocap-hub {' '.join(args)} exited {result.returncode}: {result.stderr}")
    return result


def read_png_grey(data):
    """8-bit greyscale PNG -> (width, height, rows); the five PNG row filters undone."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (8, 0), "expected 8-bit grey"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(width)
    for y in range(height):
        line = raw[y * (width + 1):(y + 1) * (width + 1)]
        f, cur = line[0], bytearray(line[1:])
        for x in range(width):
            a = cur[x - 1] if x else 0
            b, c = prev[x], prev[x - 1] if x else 0
            if f == 1:
                cur[x] = (cur[x] + a) & 255
            elif f == 2:
                cur[x] = (cur[x] + b) & 255
            elif f == 3:
                cur[x] = (cur[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                cur[x] = (cur[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(cur)
        prev = cur
    return width, height, rows


def websocket_messages(port, path, count, timeout=10.0):
    """The first `count` text messages of a WebSocket (RFC 6455 client, no extensions)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    key = base64.b64encode(os.urandom(16)).decode()
    s.sendall((f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
               f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
    buf = b""
    while b"\r\n\r\n" not in buf:
        buf += s.recv(4096)
    head, buf = buf.split(b"\r\n\r\n", 1)
    assert b" 101 " in head.split(b"\r\n")[0], head

    def take(n):
        nonlocal buf
        while len(buf) < n:
            chunk = s.recv(65536)
            assert chunk, "WebSocket closed"
            buf += chunk
        out, buf = buf[:n], buf[n:]
        return out

    messages = []
    while len(messages) < count:
        b0, b1 = take(2)
        n = b1 & 127
        if n == 126:
            n = struct.unpack(">H", take(2))[0]
        elif n == 127:
            n = struct.unpack(">Q", take(8))[0]
        payload = take(n)
        if b0 & 15 == 1:
            messages.append(json.loads(payload))
    s.close()
    return messages


def http(port, method, path, body=b"", headers=""):
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    s.sendall(f"{method} {path} HTTP/1.1\r\nHost: x\r\nContent-Length: {len(body)}\r\n{headers}"
              f"Connection: close\r\n\r\n".encode() + body)
    data = b""
    while True:
        chunk = s.recv(65536)
        if not chunk:
            break
        data += chunk
    s.close()
    head, _, payload = data.partition(b"\r\n\r\n")
    return int(head.split()[1]), payload


class Rig:
    """serve + one mocap-node per camera, replaying rendered frames in a loop."""

    def __init__(self):
        self.frames = os.path.join(WORK, "frames")
        self.notify_path = os.path.join(WORK, "notify.sock")
        self.serve = None
        self.nodes = {}

    def start_serve(self):
        if os.path.exists(self.notify_path):
            os.unlink(self.notify_path)
        self.notify = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.notify.bind(self.notify_path)
        self.notify.settimeout(0.2)
        # Read as systemd does, all the time: sd_notify blocks when the socket's queue is full.
        self.received = []
        threading.Thread(target=self.drain_notifications, args=(self.notify,), daemon=True).start()
        env = dict(os.environ, NOTIFY_SOCKET=self.notify_path, WATCHDOG_USEC="400000")
        env.pop("WATCHDOG_PID", None)
        env.pop("MOCAP_HUB_API", None)
        self.log_path = os.path.join(WORK, "serve.log")
        self.serve = subprocess.Popen(
            [os.path.join(BIN, "mocap-hub"), "serve", "--listen", "127.0.0.1:0", "--api", "127.0.0.1:0",
             "--calibration", os.path.join(self.frames, "calibration.json"),
             "--sessions-dir", os.path.join(WORK, "sessions"), "--masks-file", os.path.join(WORK, "masks.json"),
             "--rate", str(RATE), "--epoch-ns", str(self.epoch), "--request-timeout", "1"],
            stdout=subprocess.DEVNULL, stderr=open(self.log_path, "w"), env=env)
        line = wait_for("serve to report its ports", lambda: re.search(
            r"UDP port (\d+) for the nodes, API http://[^:]+:(\d+)", open(self.log_path).read()))
        self.udp_port, self.api_port = int(line.group(1)), int(line.group(2))
        self.api = f"127.0.0.1:{self.api_port}"
        self.env = dict(os.environ, MOCAP_HUB_API=self.api)

    def drain_notifications(self, sock):
        while True:
            try:
                self.received.append(sock.recv(4096).decode())
            except socket.timeout:
                continue
            except OSError:
                return

    def notifications(self, seconds):
        """What serve sent to the notify socket during the next `seconds`."""
        first = len(self.received)
        time.sleep(seconds)
        return "\n".join(self.received[first:])

    def start_node(self, node_id):
        log = open(os.path.join(WORK, f"node{node_id}.log"), "w")
        self.nodes[node_id] = subprocess.Popen(
            [os.path.join(BIN, "mocap-node"), "--source", f"replay:{self.frames}/cam{node_id}",
             "--sync", f"sim:{RATE}", "--epoch-ns", str(self.epoch), "--hub", f"127.0.0.1:{self.udp_port}",
             "--id", str(node_id), "--threshold", "32", "--replay-loop", "--log-level", "warning"],
            stdout=log, stderr=log)

    def hub(self, *args, check=True):
        return run(*args, check=check, env=self.env)

    def nodes_json(self):
        return {n["id"]: n for n in json.loads(self.hub("nodes", "--json").stdout)}

    def stop(self):
        for p in list(self.nodes.values()) + ([self.serve] if self.serve else []):
            if p.poll() is None:
                p.kill()
            p.wait()


class ServeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        motion = os.path.join(WORK, "motion.trc")
        run("sim", "motion", "-o", motion, "--markers", "12", "--frames", "200", "--rate", str(RATE))
        rig = os.path.join(WORK, "rig.json")
        run("sim", "rig", "--motion", motion, "--cameras", str(CAMERAS), "-o", rig, "--width", "640",
            "--height", "400")
        run("sim", "render", "--motion", motion, "--rig", rig, "-o", os.path.join(WORK, "frames"),
            "--reflections", str(REFLECTIONS))
        cls.rig = Rig()
        cls.rig.epoch = time.time_ns() + 1_000_000_000
        cls.rig.start_serve()
        for node_id in range(1, CAMERAS + 1):
            cls.rig.start_node(node_id)
        wait_for("every node running", lambda: len([n for n in cls.rig.nodes_json().values()
                                                     if n["state"] == "running"]) == CAMERAS, timeout=15)

    @classmethod
    def tearDownClass(cls):
        cls.rig.stop()

    def test_1_systemd_ready_and_watchdog_from_the_loop(self):
        self.assertIn("READY=1", self.rig.received[0])
        # Watchdog pings keep coming from the loop at half the 400 ms interval.
        text = self.rig.notifications(1.0)
        self.assertGreaterEqual(text.count("WATCHDOG=1"), 3, text)

    def test_2_threshold_set_through_the_cli_reaches_the_node(self):
        out = self.rig.hub("node", "2", "set", "threshold=57").stdout
        self.assertIn("applied", out)
        wait_for("node 2's status to say threshold 57", lambda: self.rig.nodes_json()[2]["threshold"] == 57)
        self.assertEqual(self.rig.nodes_json()[1]["threshold"], 32)
        self.rig.hub("node", "2", "set", "threshold=32")
        wait_for("threshold back", lambda: self.rig.nodes_json()[2]["threshold"] == 32)

    def test_3_preview_png_shows_the_camera_image(self):
        path = os.path.join(WORK, "preview.png")
        self.rig.hub("node", "1", "preview", "-o", path, "--mode", "raw", "--downscale", "2")
        width, height, rows = read_png_grey(open(path, "rb").read())
        self.assertEqual((width, height), (320, 200))
        pixels = sorted(v for row in rows for v in row)
        median, brightest = pixels[len(pixels) // 2], pixels[-1]
        self.assertLess(median, 32, "the background is below the threshold")
        self.assertGreater(brightest, 64, "markers and reflections are bright spots")
        path = os.path.join(WORK, "thresholded.png")
        self.rig.hub("node", "1", "preview", "-o", path, "--mode", "thresholded", "--downscale", "4")
        width, height, rows = read_png_grey(open(path, "rb").read())
        self.assertEqual((width, height), (160, 100))
        self.assertLessEqual({v for row in rows for v in row}, set(range(256)))

    def test_4_auto_mask_removes_the_static_reflections(self):
        first = json.loads(self.rig.hub("status", "--json").stdout)
        answer = self.rig.hub("mask", "auto", "--frames", "60").stdout
        found = [int(n) for n in re.findall(r"camera \d+: (\d+) static blobs found", answer)]
        self.assertEqual(len(found), CAMERAS, answer)
        self.assertTrue(all(n >= 1 for n in found), answer)
        self.assertEqual(answer.count(": applied"), CAMERAS, answer)
        masks = json.load(open(os.path.join(WORK, "masks.json")))
        self.assertEqual(len(masks["cameras"]), CAMERAS)
        # With the masks on the nodes, nothing static is left in what they send.
        again = self.rig.hub("mask", "auto", "--frames", "60").stdout
        self.assertEqual([int(n) for n in re.findall(r"camera \d+: (\d+) static blobs found", again)], [0] * CAMERAS,
                         again)
        # ... and the masks of the first run are kept (they add up), on the nodes and in the file.
        self.assertEqual(json.load(open(os.path.join(WORK, "masks.json"))), masks)
        self.assertTrue(all(n["masked"] for n in self.rig.nodes_json().values()))
        self.assertGreater(json.loads(self.rig.hub("status", "--json").stdout)["frame_sets"], first["frame_sets"])

    def test_5_capture_reconstruct_and_a_node_restart_mid_capture(self):
        self.rig.hub("capture", "start", "take1")
        self.assertNotEqual(self.rig.hub("capture", "start", "take2", check=False).returncode, 0)
        time.sleep(1.0)
        self.rig.nodes[3].kill()
        self.rig.nodes[3].wait()
        wait_for("node 3 lost", lambda: self.rig.nodes_json()[3]["state"] == "lost", timeout=6)
        self.rig.start_node(3)
        restarted = time.monotonic()
        wait_for("node 3 back", lambda: self.rig.nodes_json()[3]["state"] == "running", timeout=5)
        before = self.rig.nodes_json()[3]["last_frame"]
        wait_for("node 3's frames flowing again", lambda: self.rig.nodes_json()[3]["last_frame"] > before + RATE // 2)
        self.assertLess(time.monotonic() - restarted, 5.0)
        time.sleep(0.5)
        out = self.rig.hub("capture", "stop").stdout
        self.assertIn("take1", out)
        session = os.path.join(WORK, "sessions", "take1")
        info = json.load(open(os.path.join(session, "session.json")))
        self.assertEqual(info["capture_state"], "complete")
        self.assertGreater(info["camera_frames"], RATE * CAMERAS // 2)
        trc = os.path.join(session, "out.trc")
        run("reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", trc)
        rows = [l for l in open(trc).read().splitlines()[5:] if l.strip()]
        self.assertGreater(len(rows), RATE)
        listed = json.loads(self.rig.hub("sessions", "--json").stdout)
        self.assertEqual([s["name"] for s in listed], ["take1"])

    def test_6_live_websocket_frames_carry_every_point(self):
        frames = websocket_messages(self.rig.api_port, "/api/live", 20)
        numbers = [f["frame"] for f in frames]
        self.assertEqual(numbers, sorted(numbers))
        self.assertTrue(all(f["cameras"] >= 2 for f in frames))
        points = [p for f in frames for p in f["points"]]
        self.assertGreater(len(points), 0)
        self.assertTrue(all(len(p) == 7 and p[5] >= 2 for p in points))

    def test_7_bad_requests_get_reasons_not_crashes(self):
        port = self.rig.api_port
        cases = [("POST", "/api/nodes/1/settings", b"{not json", 400),
                 ("POST", "/api/nodes/1/settings", b'{"threshold": 999}', 400),
                 ("POST", "/api/nodes/1/settings", b'{"colour": 1}', 400),
                 ("POST", "/api/nodes/77/settings", b'{"threshold": 20}', 404),
                 ("GET", "/api/nodes/abc", b"", 404),
                 ("DELETE", "/api/status", b"", 405),
                 ("POST", "/api/capture/start", b'{"name": "../../etc"}', 400),
                 ("POST", "/api/capture/stop", b"", 409),
                 ("GET", "/api/nowhere", b"", 404),
                 ("POST", "/api/masks/auto", b"x" * 70000, 413)]
        for method, path, body, status in cases:
            got, payload = http(port, method, path, body)
            self.assertEqual(got, status, (method, path, payload))
            self.assertIn("error", json.loads(payload))
        self.assertEqual(self.rig.serve.poll(), None)

    def test_8_garbage_flood_costs_no_frames_of_the_real_nodes(self):
        status = lambda: json.loads(self.rig.hub("status", "--json").stdout)
        before = status()
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        rng = random.Random(5)
        sent, start = 0, time.monotonic()
        junk = [bytes(rng.randrange(256) for _ in range(rng.randrange(1, 200))) for _ in range(64)]
        while sent < 100_000 and time.monotonic() - start < 3.0:
            sock.sendto(junk[sent % 64], ("127.0.0.1", self.rig.udp_port))
            sent += 1
        elapsed = time.monotonic() - start
        time.sleep(0.5)
        after = status()
        sets = after["frame_sets"] - before["frame_sets"]
        incomplete = after["incomplete_frame_sets"] - before["incomplete_frame_sets"]
        print(f"\nflood: {sent} garbage datagrams in {elapsed:.2f} s ({sent / elapsed:.0f}/s); "
              f"{sets} frame sets meanwhile, {incomplete} incomplete; "
              f"{after['malformed_datagrams'] - before['malformed_datagrams']} counted malformed", file=sys.stderr)
        self.assertGreater(after["malformed_datagrams"], before["malformed_datagrams"])
        self.assertGreater(sets, 0)
        self.assertTrue(all(n["state"] == "running" for n in self.rig.nodes_json().values()))

    def test_9_kill_during_capture_leaves_a_readable_interrupted_session(self):
        self.rig.hub("capture", "start", "crash")
        time.sleep(1.0)
        self.rig.serve.send_signal(signal.SIGKILL)
        self.rig.serve.wait()
        session = os.path.join(WORK, "sessions", "crash")
        self.assertGreater(os.path.getsize(os.path.join(session, "raw.mlog")), 0)
        self.rig.notify.close()
        self.rig.start_serve()
        listed = {s["name"]: s for s in json.loads(self.rig.hub("sessions", "--json").stdout)}
        self.assertEqual(listed["crash"]["state"], "interrupted")
        trc = os.path.join(session, "out.trc")
        run("reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", trc)
        self.assertGreater(len(open(trc).read().splitlines()), 5 + RATE // 2)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
