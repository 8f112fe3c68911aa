"""Client of the mocap hub's live stream (proto/mocap_stream.proto, version 1).

StreamClient subscribes over UDP (renewing the subscription every second while frames are read)
or joins a multicast group; decode_frame turns one StreamFrame message into a Frame. The hub
answers a first subscription with a challenge (a StreamFrame holding only subscribe_cookie);
the client sends the cookie back in every later request, which proves its address, and only
then do frames flow."""

import dataclasses
import select
import socket
import struct
import time
from typing import Iterator, List, Optional, Sequence

__all__ = ["Frame", "Point", "RigidBody", "StreamClient", "decode_frame", "encode_subscribe",
           "encode_unsubscribe", "DecodeError", "PARTS"]

PARTS = {"points": 1, "bodies": 2, "labels": 4}
VERSION = 1
RENEW_S = 1.0


class DecodeError(ValueError):
    """The bytes are not a StreamFrame."""


@dataclasses.dataclass
class Point:
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    residual_px: float = 0.0
    views: int = 0
    marker: int = 0             # confirmed marker, 1-based; 0 when provisional
    provisional_track: int = 0  # tentative track's serial; 0 for none
    label: str = ""


@dataclasses.dataclass
class RigidBody:
    id: int = 0
    name: str = ""
    tracked: bool = False
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    qx: float = 0.0
    qy: float = 0.0
    qz: float = 0.0
    qw: float = 0.0
    mean_error_mm: float = 0.0
    predicted: bool = False   # not seen: the pose predicted through a short occlusion
    markers: int = 0          # markers fitted


@dataclasses.dataclass
class Frame:
    frame_number: int = 0
    trigger_time_ns: int = 0
    publish_time_ns: int = 0
    cameras: int = 0
    parts: int = 0
    points: List[Point] = dataclasses.field(default_factory=list)
    bodies: List[RigidBody] = dataclasses.field(default_factory=list)
    points_dropped: int = 0
    subscribe_cookie: bytes = b""  # a challenge, not a frame, when set


# ---- protobuf wire format: varints, 32-bit floats, length-delimited fields ----

def _varint(data, pos):
    value = shift = 0
    while True:
        if pos >= len(data) or shift > 63:
            raise DecodeError("truncated varint")
        byte = data[pos]
        pos += 1
        value |= (byte & 0x7F) << shift
        if not byte & 0x80:
            return value & 0xFFFFFFFFFFFFFFFF, pos
        shift += 7


def _fields(data):
    """(field number, wire type, value) of every field; value is int, float bytes or bytes."""
    pos = 0
    while pos < len(data):
        key, pos = _varint(data, pos)
        number, kind = key >> 3, key & 7
        if number == 0:
            raise DecodeError("field number 0")
        if kind == 0:
            value, pos = _varint(data, pos)
        elif kind == 1:
            if pos + 8 > len(data):
                raise DecodeError("truncated fixed64")
            value, pos = data[pos:pos + 8], pos + 8
        elif kind == 2:
            size, pos = _varint(data, pos)
            if pos + size > len(data):
                raise DecodeError("truncated field")
            value, pos = data[pos:pos + size], pos + size
        elif kind == 5:
            if pos + 4 > len(data):
                raise DecodeError("truncated fixed32")
            value, pos = data[pos:pos + 4], pos + 4
        else:
            raise DecodeError(f"wire type {kind}")
        yield number, kind, value


def _float(kind, value):
    if kind != 5:
        raise DecodeError("expected a float")
    return struct.unpack("<f", value)[0]


def _int32(value):
    return value - (1 << 64) if value >= 1 << 63 else value


def _point(data):
    p = Point()
    floats = {1: "x", 2: "y", 3: "z", 4: "residual_px"}
    for number, kind, value in _fields(data):
        if number in floats:
            setattr(p, floats[number], _float(kind, value))
        elif number == 5 and kind == 0:
            p.views = value
        elif number == 6 and kind == 0:
            p.marker = _int32(value)
        elif number == 7 and kind == 0:
            p.provisional_track = value
        elif number == 8 and kind == 2:
            p.label = value.decode("utf-8", "replace")
    return p


def _body(data):
    b = RigidBody()
    floats = {4: "x", 5: "y", 6: "z", 7: "qx", 8: "qy", 9: "qz", 10: "qw", 11: "mean_error_mm"}
    for number, kind, value in _fields(data):
        if number in floats:
            setattr(b, floats[number], _float(kind, value))
        elif number == 1 and kind == 0:
            b.id = value
        elif number == 2 and kind == 2:
            b.name = value.decode("utf-8", "replace")
        elif number == 3 and kind == 0:
            b.tracked = bool(value)
        elif number == 12 and kind == 0:
            b.predicted = bool(value)
        elif number == 13 and kind == 0:
            b.markers = value
    return b


def decode_frame(data: bytes) -> Frame:
    """One StreamFrame message -> Frame; raises DecodeError. Unknown fields are skipped."""
    f = Frame()
    ints = {1: "frame_number", 2: "trigger_time_ns", 3: "publish_time_ns", 4: "cameras", 5: "parts",
            8: "points_dropped"}
    for number, kind, value in _fields(bytes(data)):
        if number in ints and kind == 0:
            setattr(f, ints[number], value)
        elif number == 6 and kind == 2:
            f.points.append(_point(value))
        elif number == 7 and kind == 2:
            f.bodies.append(_body(value))
        elif number == 9 and kind == 2:
            f.subscribe_cookie = bytes(value)
    return f


def _encode_varint(value):
    out = bytearray()
    while True:
        byte, value = value & 0x7F, value >> 7
        out.append(byte | (0x80 if value else 0))
        if not value:
            return bytes(out)


def _parts_bits(parts: Sequence[str]) -> int:
    bits = 0
    for name in parts:
        if name not in PARTS:
            raise ValueError(f"unknown part {name!r} (points, bodies, labels)")
        bits |= PARTS[name]
    return bits


def _bytes_field(number, value):
    return _encode_varint(number << 3 | 2) + _encode_varint(len(value)) + value


MIN_FIRST_REQUEST = 32


def encode_subscribe(parts: Sequence[str] = ("points", "bodies"), cookie: bytes = b"") -> bytes:
    """A Subscribe; without a cookie (the first one) padded to 32 bytes, as large as its answer."""
    subscribe = b"\x08" + _encode_varint(_parts_bits(parts))
    if cookie:
        subscribe += _bytes_field(2, cookie)
    head = b"\x08" + _encode_varint(VERSION)
    if not cookie:
        bare = len(head) + 2 + len(subscribe)
        subscribe += _bytes_field(3, bytes(max(0, MIN_FIRST_REQUEST - bare - 2)))
    return head + b"\x12" + _encode_varint(len(subscribe)) + subscribe


def encode_unsubscribe(cookie: bytes = b"") -> bytes:
    unsubscribe = _bytes_field(1, cookie) if cookie else b""
    return b"\x08" + _encode_varint(VERSION) + b"\x1a" + _encode_varint(len(unsubscribe)) + unsubscribe


class StreamClient:
    """Frames from the hub: StreamClient(host, port, parts) subscribes; StreamClient.multicast
    joins a group. Use as a context manager (or call close())."""

    def __init__(self, host: str, port: int, parts: Sequence[str] = ("points", "bodies"), *,
                 _multicast: Optional[tuple] = None):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 20)
        self.hub = None
        if _multicast:
            group, interface = _multicast
            self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            self.sock.bind((group, port))
            membership = socket.inet_aton(group) + socket.inet_aton(interface or "0.0.0.0")
            self.sock.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, membership)
        else:
            self.hub = (socket.gethostbyname(host), port)
            self.parts = parts
            self.cookie = b""
            self._renew()

    @classmethod
    def multicast(cls, group: str, port: int, interface: Optional[str] = None) -> "StreamClient":
        return cls(group, port, _multicast=(group, interface))

    def _renew(self):
        self.sock.sendto(encode_subscribe(self.parts, self.cookie), self.hub)
        self.next_renew = time.monotonic() + RENEW_S

    def receive(self, timeout: float = 1.0) -> Optional[Frame]:
        """The next frame, or None after `timeout` seconds. Datagrams that are no frame are skipped."""
        deadline = time.monotonic() + timeout
        while True:
            now = time.monotonic()
            if self.hub and now >= self.next_renew:
                self._renew()
            until = min(deadline, self.next_renew) if self.hub else deadline
            ready, _, _ = select.select([self.sock], [], [], max(0.0, until - now))
            if ready:
                try:
                    data, source = self.sock.recvfrom(65536)
                    frame = decode_frame(data)
                    if not frame.subscribe_cookie:
                        return frame
                    if self.hub and source == self.hub:
                        # The hub's challenge (a stale cookie gets a new one): answered at once.
                        self.cookie = frame.subscribe_cookie
                        self._renew()
                except ConnectionRefusedError:
                    pass  # the hub was not up for a renewal; keep trying
                except DecodeError:
                    pass
            if time.monotonic() >= deadline:
                return None

    def frames(self, timeout: float = 5.0) -> Iterator[Frame]:
        """Frames until none arrives for `timeout` seconds."""
        while True:
            frame = self.receive(timeout)
            if frame is None:
                return
            yield frame

    def close(self):
        if self.hub:
            try:
                self.sock.sendto(encode_unsubscribe(self.cookie), self.hub)
            except OSError:
                pass
        self.sock.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
