"""The live rig the serve, stream and fault tests share: `mocap-hub serve` with one real
`mocap-node` process per camera on loopback replaying rendered frames, a systemd notify socket
the test owns, small clients (HTTP, WebSocket, PNG) and the wire as a test writes it (protobuf
fields by hand, the sealed envelope, raw-log records), and what the e2e tests around it also take
from here (run for mocap-hub, SIM_FAULTS, percentiles), with the Python standard library only.

Every wait is bounded; stop() kills every process the rig started."""

import base64
import hashlib
import hmac
import json
import os
import re
import socket
import struct
import subprocess
import threading
import time
import zlib


def render_scene(bin_dir, work, cameras, rate, markers=12, frames=200, reflections=0):
    """A synthetic motion, a ring rig and its rendered frames in work/frames."""
    motion = os.path.join(work, "motion.trc")
    run(bin_dir, "sim", "motion", "-o", motion, "--markers", str(markers), "--frames", str(frames),
        "--rate", str(rate))
    rig = os.path.join(work, "rig.json")
    run(bin_dir, "sim", "rig", "--motion", motion, "--cameras", str(cameras), "-o", rig, "--width", "640",
        "--height", "400")
    run(bin_dir, "sim", "render", "--motion", motion, "--rig", rig, "-o", os.path.join(work, "frames"),
        "--reflections", str(reflections))


# A bound for a wait that fails only when something is stuck, never because the machine is busy:
# the live tests assert no timing (their figures are printed; the benchmarks measure them).
STUCK_S = 60.0


def wait_for(what, predicate, timeout=STUCK_S, step=0.05):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(step)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def percentiles(values):
    """(p50, p99, max) of the values: the middle element, element int(0.99 (n - 1)), the last."""
    values = sorted(values)
    return values[len(values) // 2], values[int(0.99 * (len(values) - 1))], values[-1]


# The faults of the hub issue's accuracy runs (`sim project` options).
SIM_FAULTS = ["--noise-px", "0.2", "--occlusion", "0.05", "--occlusion-frames", "5", "--spurious", "2",
              "--drop-frames", "0.002"]


# ---- the wire as an attacker (or a test) writes it: protobuf by hand, the envelope of
# hub/src/wire/envelope.h, HMAC-SHA-512/256 = HMAC-SHA-512 cut to 32 bytes ----

def varint(v):
    out = bytearray()
    while True:
        b, v = v & 0x7F, v >> 7
        out.append(b | (0x80 if v else 0))
        if not v:
            return bytes(out)


def field(number, value):
    """A varint field (int) or a length-delimited one (bytes)."""
    if isinstance(value, int):
        return varint(number << 3) + varint(value)
    return varint(number << 3 | 2) + varint(len(value)) + value


def read_varint(buf, pos):
    value, shift = 0, 0
    while True:
        if pos >= len(buf) or shift > 63:
            raise ValueError("truncated or overlong varint")
        b = buf[pos]
        value |= (b & 0x7F) << shift
        pos, shift = pos + 1, shift + 7
        if not b & 0x80:
            return value, pos


def proto_fields(buf):
    """A protobuf message as a list of (field number, wire type, value): ints for varints,
    bytes for everything else (fixed ones included, as read)."""
    out, pos = [], 0
    while pos < len(buf):
        tag, pos = read_varint(buf, pos)
        number, kind = tag >> 3, tag & 7
        if kind == 0:
            value, pos = read_varint(buf, pos)
        elif kind == 2:
            size, pos = read_varint(buf, pos)
            value, pos = bytes(buf[pos:pos + size]), pos + size
        elif kind in (1, 5):
            size = 8 if kind == 1 else 4
            value, pos = bytes(buf[pos:pos + size]), pos + size
        else:
            raise ValueError(f"wire type {kind}")
        out.append((number, kind, value))
    return out


def proto_encode(fields):
    """proto_fields' inverse."""
    out = bytearray()
    for number, kind, value in fields:
        out += varint(number << 3 | kind)
        if kind == 0:
            out += varint(value)
        elif kind == 2:
            out += varint(len(value)) + value
        else:
            out += value
    return bytes(out)


def marker_frames_in(payloads):
    """(node id, frame number, chunk index, chunk count) of every MarkerFrame packet."""
    out = []
    for payload in payloads:
        for number, kind, value in proto_fields(payload):
            if number == 10 and kind == 2:
                f = {n: v for n, k, v in proto_fields(value) if k == 0}
                out.append((f.get(1, 0), f.get(2, 0), f.get(9, 0), f.get(10, 1)))
    return out


def marker_frame_packet(node, frame, markers):
    marker = b"".join(field(14, field(1, x * 256) + field(2, y * 256) + field(3, 9) + field(4, 200) + field(5, 100))
                      for x, y in markers)
    frame_msg = (field(1, node) + field(2, frame) + field(6, 424242) + field(7, 640) + field(8, 400) +
                 field(10, 1) + field(11, len(markers)) + marker)
    return field(1, 1) + field(10, frame_msg)


def control_packet(node, sequence, command_field, command):
    return field(1, 1) + field(12, field(1, node) + field(2, sequence) + field(command_field, command))


def seal(key, direction, node, payload, counter=None, key_id=1):
    counter = counter or time.time_ns()
    header = bytes([0xA1, direction, key_id, 0]) + node.to_bytes(4, "little") + counter.to_bytes(8, "little")
    body = header + payload
    return body + hmac.new(key, body, hashlib.sha512).digest()[:32]


def sniff_udp_to(port, seconds):
    """Payloads of the UDP datagrams sent to 127.0.0.1:port during `seconds` (a raw socket on
    loopback: root only)."""
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(0x0003))
    s.bind(("lo", 0))
    s.settimeout(0.05)
    out, end = [], time.monotonic() + seconds
    while time.monotonic() < end:
        try:
            frame, meta = s.recvfrom(65535)
        except socket.timeout:
            continue
        if meta[2] == socket.PACKET_OUTGOING or frame[12:14] != b"\x08\x00" or frame[23] != 17:
            continue
        ip = frame[14:]
        udp = ip[(ip[0] & 15) * 4:]
        if int.from_bytes(udp[2:4], "big") == port:
            out.append(bytes(udp[8:int.from_bytes(udp[4:6], "big")]))
    s.close()
    return out


def raw_log_records(path):
    """(receive time ns, payload) of every whole record of a session's raw.mlog, as written
    (hub/src/ingest/session_log.h: a 16-byte file header, then per record u32 magic, u32 length,
    u64 receive time, u32 CRC, payload), and how many bytes a torn last record left."""
    with open(path, "rb") as f:
        data = f.read()
    pos, out = 16, []
    while pos + 20 <= len(data):
        size = int.from_bytes(data[pos + 4:pos + 8], "little")
        if pos + 20 + size > len(data):
            break
        out.append((int.from_bytes(data[pos + 8:pos + 16], "little"), data[pos + 20:pos + 20 + size]))
        pos += 20 + size
    return out, len(data) - pos


def raw_log_payloads(path):
    """Every whole record's payload of a session's raw.mlog."""
    return [payload for _, payload in raw_log_records(path)[0]]


def run(bin_dir, *args, check=True, env=None, timeout=60):
    """mocap-hub ARGS from bin_dir; raises on a non-zero exit unless check is False."""
    result = subprocess.run([os.path.join(bin_dir, "mocap-hub"), *args], capture_output=True, text=True,
                            timeout=timeout, env=env)
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


# The API token of each serve the rigs started, by its API port: the helpers below send it
# (serve wants one on every request; its default token file is WORK/api-auth/operator.token).
TOKENS = {}


def auth_header(port):
    """The Authorization header line for serve's API at `port` ("" when it has no token)."""
    token = TOKENS.get(port)
    return f"Authorization: Bearer {token}\r\n" if token else ""


def websocket_upgrade(port, path, timeout=10.0, headers=None):
    """A socket after a WebSocket upgrade request to `path` (the answer not yet read)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    key = base64.b64encode(os.urandom(16)).decode()
    extra = auth_header(port) if headers is None else headers
    s.sendall((f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
               f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n{extra}\r\n").encode())
    return s


def websocket_messages(port, path, count, timeout=10.0, headers=None, on_message=None):
    """The first `count` data messages of a WebSocket (RFC 6455 client, no extensions): text
    messages parsed as JSON, binary ones as bytes. With on_message, each is handed to it as it
    arrives instead of being kept."""
    s = websocket_upgrade(port, path, timeout, headers)
    buf = b""
    while b"\r\n\r\n" not in buf:
        chunk = s.recv(4096)
        assert chunk, f"{path}: closed before the upgrade"
        buf += chunk
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
        if b0 & 15 not in (1, 2):
            continue
        message = json.loads(payload) if b0 & 15 == 1 else payload
        if on_message:
            on_message(message)
            count -= 1
        else:
            messages.append(message)
    s.close()
    return messages


def raw_request(port, request):
    """One raw HTTP request (bytes as given, nothing normalised) -> (status, headers, body)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    s.sendall(request)
    data = b""
    while True:
        chunk = s.recv(65536)
        if not chunk:
            break
        data += chunk
    s.close()
    head, _, body = data.partition(b"\r\n\r\n")
    lines = head.decode("latin-1").split("\r\n")
    headers = {k.strip().lower(): v.strip() for k, _, v in (line.partition(":") for line in lines[1:])}
    return int(lines[0].split()[1]), headers, body


def http(port, method, path, body=b"", headers=None):
    """One request with the rig's token and, for a state change, the JSON content type (as the
    CLI sends them); `headers` given replaces both."""
    if headers is None:
        headers = auth_header(port) + ("Content-Type: application/json\r\n" if method not in ("GET", "HEAD") else "")
    status, _, payload = raw_request(port, f"{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n"
                                           f"Content-Length: {len(body)}\r\n{headers}Connection: close\r\n\r\n".encode()
                                     + body)
    return status, payload


def read_trc(path):
    """A TRC as (marker names, rows of per-marker (x, y, z) or None for a gap, the file's lines)."""
    with open(path) as f:
        lines = f.read().splitlines()
    names = [n for n in lines[3].split("\t")[2:] if n]
    rows = []
    for line in lines[5:]:
        cells = line.split("\t")
        if len(cells) < 2 or not cells[0].strip():
            continue
        rows.append([tuple(float(v) for v in cells[2 + 3 * m:5 + 3 * m]) if cells[2 + 3 * m].strip() else None
                     for m in range(len(names))])
    return names, rows, lines


class Rig:
    """serve + one mocap-node per camera, replaying rendered frames (work/frames) in a loop.
    serve_args are added to serve's command line (streams and the like)."""

    def __init__(self, bin_dir, work, rate, serve_args=(), sessions_dir=None, api_host="127.0.0.1"):
        self.bin, self.work, self.rate, self.serve_args = bin_dir, work, rate, list(serve_args)
        self.sessions_dir = sessions_dir or os.path.join(work, "sessions")
        self.api_host = api_host
        self.frames = os.path.join(work, "frames")
        self.notify_path = os.path.join(work, "notify.sock")
        self.serve = None
        self.nodes = {}
        self.epoch = time.time_ns() + 1_000_000_000
        self.keys = os.path.join(work, "keys")

    def start_serve(self, udp_port=0, api_port=0):
        """serve on the given ports (0: any free one; a restart passes the old ones, so that nodes
        and browsers find it again)."""
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
        self.make_keys()
        self.log_path = os.path.join(self.work, "serve.log")
        with open(self.log_path, "w") as log:
            self.serve = subprocess.Popen(
                [os.path.join(self.bin, "mocap-hub"), "serve", "--listen", f"127.0.0.1:{udp_port}",
                 "--api", f"{self.api_host}:{api_port}",
                 "--calibration", os.path.join(self.frames, "calibration.json"),
                 "--sessions-dir", self.sessions_dir, "--api-auth", os.path.join(self.work, "api-auth"),
                 "--masks-file", os.path.join(self.work, "masks.json"),
                 "--rate", str(self.rate), "--epoch-ns", str(self.epoch), "--request-timeout", "1",
                 "--keys", self.keys,
                 "--stream", "127.0.0.1:0", *self.serve_args],
                stdout=subprocess.DEVNULL, stderr=log, env=env)
        line = wait_for("serve to report its ports", lambda: re.search(
            r"UDP port (\d+) for the nodes, API http://[^:]+:(\d+)", self.log()))
        self.udp_port, self.api_port = int(line.group(1)), int(line.group(2))
        self.api = f"127.0.0.1:{self.api_port}"
        # The local operator's token serve issued at its first start (kept across restarts).
        self.token_file = os.path.join(self.work, "api-auth", "operator.token")
        if os.path.exists(self.token_file):
            with open(self.token_file) as f:
                TOKENS[self.api_port] = self.token = f.read().strip()
        self.env = dict(os.environ, MOCAP_HUB_API=self.api, MOCAP_HUB_TOKEN_FILE=self.token_file)

    def make_keys(self):
        """One wire key per camera of the calibration in work/keys (kept across serve restarts)."""
        if os.path.isdir(self.keys):
            return
        with open(os.path.join(self.frames, "calibration.json")) as f:
            ids = [str(c["id"]) for c in json.load(f)["cameras"]]
        run(self.bin, "keys", "new", *ids, "--out", self.keys)

    def key_file(self, node_id):
        return os.path.join(self.keys, f"node-{node_id}.key")

    def log(self):
        with open(self.log_path) as f:
            return f.read()

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

    def start_node(self, node_id, with_epoch=True, hub_port=None, loop=True):
        """Without the epoch the node numbers frames on a grid of its own until serve sends it the
        session's. hub_port: where it sends (a relay in front of serve; default serve itself);
        loop=False replays the frames once, frame n at the epoch + n / rate."""
        epoch = ["--epoch-ns", str(self.epoch)] if with_epoch else []
        with open(os.path.join(self.work, f"node{node_id}.log"), "a") as log:
            self.nodes[node_id] = subprocess.Popen(
                [os.path.join(self.bin, "mocap-node"), "--source", f"replay:{self.frames}/cam{node_id}",
                 "--sync", f"sim:{self.rate}", *epoch,
                 "--hub", f"127.0.0.1:{hub_port or self.udp_port}", "--id", str(node_id),
                 "--key-file", self.key_file(node_id), "--threshold", "32",
                 *(["--replay-loop"] if loop else []), "--log-level", "warning"],
                stdout=log, stderr=log)

    def start(self, cameras):
        """serve, then one node per camera; returns once every node is running."""
        self.start_serve()
        for node_id in range(1, cameras + 1):
            self.start_node(node_id)
        wait_for("every node running", lambda: len([n for n in self.nodes_json().values()
                                                     if n["state"] == "running"]) == cameras, timeout=15)

    def hub(self, *args, check=True):
        return run(self.bin, *args, check=check, env=self.env)

    def nodes_json(self):
        return {n["id"]: n for n in json.loads(self.hub("nodes", "--json").stdout)}

    def stop(self):
        for p in list(self.nodes.values()) + ([self.serve] if self.serve else []):
            if p.poll() is None:
                p.kill()
            p.wait()
