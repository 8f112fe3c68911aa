#!/usr/bin/env python3
"""NatNet, VRPN and VMC under load: three rigid bodies around a walking subject at RATE Hz
(tests/stream/tracker_scene.py, CAMERAS cameras, a few seconds rendered and replayed in a loop by
real mocap-node processes) into `mocap-hub serve --natnet --vrpn --vmc` for SECONDS, read at
the same time by
  NatNet  NaturalPoint's Python client (natnetsdk, .venv) on the multicast group
  VRPN    a reader of the raw TCP stream (tcp://), counting Pos_Quat reports by their sequence
          number, which serve sets to the frame number (libmotioncapture's VRPN API polls and
          cannot count frames)
  VMC     python-osc (.venv), by /VMC/Ext/T (the frame's time)
and /api/live (the frames serve published; it skips frames for a reader that falls behind, so a
frame any reader got counts as published too). Prints, per protocol, the frames a client missed
among those published within its span, and serve's own figures from /api/status: the protocol's
publish -> handed-to-the-kernel p50/p99/max (ms) on the hub. Figures, no assertions. Root: runs in
a network namespace of its own (Motive's fixed ports, multicast on its loopback).

Each reader's socket gets an 8 MiB receive buffer and the datagrams its kernel socket still
dropped are printed beside what it missed: those frames left the hub and the Python reader, not
serve, fell behind. --protocols runs some of the three alone (each alone: its publish -> kernel
figure is then its own cost, not the sum of the adapters that send before it on the loop).

usage: tools/stream-bench/tracker_bench.py [--bin build/bin] [--out tracker-bench] [--rate 240]
                                            [--seconds 60] [--cameras 6] [--render-s 4]
                                            [--protocols natnet,vrpn,vmc]"""

import argparse
import contextlib
import io
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "serve"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "stream"))


def in_namespace():
    """Re-runs this script in a new network namespace with multicast on loopback (once)."""
    if os.environ.get("TRACKER_BENCH_NS"):
        return
    setup = "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo"
    env = dict(os.environ, TRACKER_BENCH_NS="1")
    sys.exit(subprocess.call(["unshare", "--net", "sh", "-c", setup + ' && exec "$0" "$@"', sys.executable,
                              *sys.argv], env=env))


def vrpn_reader(port, frames, stop):
    """Pos_Quat reports' sequence numbers (frame numbers) from a tcp:// VRPN connection."""
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.sendall(b"vrpn: ver. 07.35  0".ljust(24, b"\0"))
    buf, types, have_cookie = b"", {}, False
    s.settimeout(0.5)
    while not stop.is_set():
        try:
            chunk = s.recv(65536)
        except socket.timeout:
            continue
        if not chunk:
            break
        buf += chunk
        if not have_cookie:
            if len(buf) < 24:
                continue
            buf, have_cookie = buf[24:], True
        while len(buf) >= 24:
            length, _, _, sender, kind, seq = struct.unpack_from(">IIIiiI", buf)
            total = 24 + (length - 24 + 7) // 8 * 8
            if len(buf) < total:
                break
            if kind == -2:
                name_len = struct.unpack_from(">I", buf, 24)[0]
                types[sender] = buf[28:28 + name_len - 1].decode()
            elif types.get(kind) == "vrpn_Tracker Pos_Quat":
                frames.add(seq)
            buf = buf[total:]
    s.close()


READER_BUFFER = 8 << 20
SO_RCVBUFFORCE = getattr(socket, "SO_RCVBUFFORCE", 33)


def enlarge_receive_buffer(sock):
    """8 MiB (root: past net.core.rmem_max), so a reader's scheduling hiccup does not drop frames."""
    try:
        sock.setsockopt(socket.SOL_SOCKET, SO_RCVBUFFORCE, READER_BUFFER)
    except OSError:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, READER_BUFFER)


def udp_drops(port):
    """Datagrams the kernel dropped at the UDP sockets bound to PORT (the reader's buffer was full)."""
    total = 0
    with open("/proc/net/udp") as f:
        for line in f.readlines()[1:]:
            fields = line.split()
            if int(fields[1].split(":")[1], 16) == port:
                total += int(fields[-1])
    return total


def missed(got, published):
    if not got:
        return None, 0
    lo, hi = min(got), max(got)
    span = [n for n in published if lo <= n <= hi]
    return len([n for n in span if n not in got]), len(span)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--bin", default="build/bin")
    p.add_argument("--out", default="tracker-bench")
    p.add_argument("--rate", type=int, default=240)
    p.add_argument("--seconds", type=float, default=60)
    p.add_argument("--cameras", type=int, default=6)
    p.add_argument("--render-s", type=float, default=4)
    p.add_argument("--realtime-priority", type=int, default=10 if os.geteuid() == 0 else 0,
                   help="serve's frame loop under SCHED_FIFO at this priority, as its unit runs it (0: off)")
    p.add_argument("--protocols", default="natnet,vrpn,vmc",
                   help="comma-separated subset of natnet,vrpn,vmc to serve and read")
    args = p.parse_args()
    protocols = set(args.protocols.split(","))
    if not protocols or protocols - {"natnet", "vrpn", "vmc"}:
        p.error(f"--protocols: {args.protocols!r}: a comma-separated subset of natnet,vrpn,vmc")
    in_namespace()
    from live_rig import Rig, wait_for, websocket_messages
    import tracker_scene
    from natnetsdk.NatNetClient import NatNetClient
    from pythonosc import dispatcher, osc_server

    out = os.path.abspath(args.out)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    bin_dir = os.path.abspath(args.bin)
    tracker_scene.make(bin_dir, out, args.rate, int(args.render_s * args.rate), args.cameras)
    serve_args = ["--bodies", os.path.join(out, "bodies.json")]
    serve_args += ["--natnet", "127.0.0.1:1510"] if "natnet" in protocols else []
    serve_args += ["--vrpn", "127.0.0.1:3883"] if "vrpn" in protocols else []
    serve_args += ["--vmc", "127.0.0.1:39539"] if "vmc" in protocols else []
    serve_args += ["--realtime-priority", str(args.realtime_priority)] if args.realtime_priority else []
    rig = Rig(bin_dir, out, args.rate, serve_args=serve_args)
    drops = {}
    published, natnet, vrpn, vmc = set(), set(), set(), set()
    with_bodies = set()  # frames /api/live showed with a tracked body: VRPN reports only those

    def on_live(frame):
        published.add(frame["frame"])
        if any(body[1] for body in frame["bodies"]):
            with_bodies.add(frame["frame"])

    stop = threading.Event()
    try:
        rig.start(args.cameras)
        wait_for("the protocols", lambda: all(where in rig.log() for name, where in
                                               (("natnet", "NatNet on"), ("vrpn", "VRPN on"), ("vmc", "VMC:"))
                                               if name in protocols))
        osc = None
        if "vmc" in protocols:
            d = dispatcher.Dispatcher()
            d.map("/VMC/Ext/T", lambda _a, t: vmc.add(round(t * args.rate)))
            # One reading thread (the threading server starts a thread per datagram).
            osc = osc_server.BlockingOSCUDPServer(("127.0.0.1", 39539), d)
            enlarge_receive_buffer(osc.socket)
            threading.Thread(target=osc.serve_forever, daemon=True).start()
        if "vrpn" in protocols:
            threading.Thread(target=vrpn_reader, args=(3883, vrpn, stop), daemon=True).start()
        client = NatNetClient()
        client.set_client_address("0.0.0.0")
        client.set_use_multicast(True)
        # The SDK client reads multicast frames from the start but learns the version from its server
        # info: until then it parses frames as version 0.0 and its reading thread dies on the first.
        # Asking for the version it asks Motive for in its connect (4.1) closes that window.
        client._NatNetClient__nat_net_requested_version = [4, 1, 0, 0]
        client.new_frame_listener = lambda data: natnet.add(data["frame_number"])
        def read_live():
            try:
                websocket_messages(rig.api_port, "/api/live", 10**9, timeout=args.seconds + 30, on_message=on_live)
            except (AssertionError, OSError):
                pass  # serve stopped at the end of the run and closed it

        threading.Thread(target=read_live, daemon=True).start()
        with contextlib.redirect_stdout(io.StringIO()):
            if "natnet" in protocols:
                client.run()
                enlarge_receive_buffer(client.data_socket)
            time.sleep(args.seconds)
            stop.set()
            drops = {"natnet": udp_drops(1511), "vmc": udp_drops(39539)}
            if "natnet" in protocols:
                client.shutdown()
        if osc:
            osc.shutdown()
        status = json.loads(rig.hub("status", "--json").stdout)
        json.dump({k: status.get(k) for k in ("stream", "natnet", "vrpn", "vmc")}, open(os.path.join(out, "tracker_status.json"), "w"), indent=1)
    finally:
        rig.stop()
    # /api/live gives a reader that falls behind the newest frame: a frame any reader got was published too.
    published |= natnet | vrpn | vmc
    with_bodies |= vrpn
    print(f"3 rigid bodies, {args.cameras} cameras at {args.rate} Hz, {args.seconds:.0f} s: serve published at least "
          f"{len(published)} frames ({status.get('frame_sets', '?')} frame sets since serve started)")
    print("%-8s %-24s %7s %7s %7s | %-21s | %-21s" % ("", "", "", "", "reader", "publish -> kernel ms",
                                                       "adds ms"))
    print("%-8s %-24s %7s %7s %7s | %6s %6s %7s | %6s %6s %7s" % ("protocol", "reading client", "missed", "of", "drops",
                                                                  "p50", "p99", "max", "p50", "p99", "max"))
    for name, key, client_name, got in (("NatNet", "natnet", "natnetsdk, multicast", natnet),
                                        ("VRPN", "vrpn", "raw tcp:// reader", vrpn),
                                        ("VMC", "vmc", "python-osc", vmc)):
        if key not in protocols:
            continue
        # VRPN has no frame without a tracked body: its frames are those /api/live showed with one.
        lost, span = missed(got, with_bodies if key == "vrpn" else published)
        lat = status.get(key, {}).get("publish_to_sent_ms", {})
        adds = status.get(key, {}).get("adds_ms", {})
        print("%-8s %-24s %7s %7d %7s | %6.3f %6.3f %7.3f | %6.3f %6.3f %7.3f" % (
            name, client_name, "-" if lost is None else lost, span, drops.get(key, "-"),
            lat.get("p50", 0), lat.get("p99", 0), lat.get("max", 0), adds.get("p50", 0), adds.get("p99", 0),
            adds.get("max", 0)))
    print("(reader drops: datagrams the reader's own socket buffer dropped (sent by serve, read too late);\n"
          " publish -> kernel: the 3D result published -> the protocol's last datagram or report handed to the\n"
          " kernel, on the hub, /api/status <protocol>.publish_to_sent_ms (it includes the adapters that sent\n"
          " before it on the loop); adds: the protocol's own part of it, <protocol>.adds_ms)")


if __name__ == "__main__":
    main()
