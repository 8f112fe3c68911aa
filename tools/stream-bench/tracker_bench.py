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

usage: tools/stream-bench/tracker_bench.py [--bin build/bin] [--out tracker-bench] [--rate 240]
                                            [--seconds 60] [--cameras 6] [--render-s 4]"""

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
    args = p.parse_args()
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
    rig = Rig(bin_dir, out, args.rate, serve_args=[
        "--bodies", os.path.join(out, "bodies.json"), "--natnet", "127.0.0.1:1510", "--vrpn", "127.0.0.1:3883",
        "--vmc", "127.0.0.1:39539", *(["--realtime-priority", str(args.realtime_priority)] if args.realtime_priority else [])])
    published, natnet, vrpn, vmc = set(), set(), set(), set()
    stop = threading.Event()
    try:
        rig.start(args.cameras)
        wait_for("NatNet and VRPN", lambda: "VRPN on" in rig.log())
        d = dispatcher.Dispatcher()
        d.map("/VMC/Ext/T", lambda _a, t: vmc.add(round(t * args.rate)))
        osc = osc_server.ThreadingOSCUDPServer(("127.0.0.1", 39539), d)
        threading.Thread(target=osc.serve_forever, daemon=True).start()
        threading.Thread(target=vrpn_reader, args=(3883, vrpn, stop), daemon=True).start()
        client = NatNetClient()
        client.set_client_address("0.0.0.0")
        client.set_use_multicast(True)
        # The SDK client reads multicast frames from the start but learns the version from its server
        # info: until then it parses frames as version 0.0 and its reading thread dies on the first.
        # Asking for the version it asks Motive for in its connect (4.1) closes that window.
        client._NatNetClient__nat_net_requested_version = [4, 1, 0, 0]
        client.new_frame_listener = lambda data: natnet.add(data["frame_number"])
        threading.Thread(target=lambda: websocket_messages(rig.api_port, "/api/live", 10**9, timeout=30,
                                                           on_message=lambda f: published.add(f["frame"])),
                         daemon=True).start()
        with contextlib.redirect_stdout(io.StringIO()):
            client.run()
            time.sleep(args.seconds)
            stop.set()
            client.shutdown()
        osc.shutdown()
        status = json.loads(rig.hub("status", "--json").stdout)
        json.dump({k: status.get(k) for k in ("natnet", "vrpn", "vmc")}, open(os.path.join(out, "tracker_status.json"), "w"), indent=1)
    finally:
        rig.stop()
    # /api/live gives a reader that falls behind the newest frame: a frame any reader got was published too.
    published |= natnet | vrpn | vmc
    print(f"3 rigid bodies, {args.cameras} cameras at {args.rate} Hz, {args.seconds:.0f} s: serve published at least "
          f"{len(published)} frames ({status.get('frame_sets', '?')} frame sets since serve started)")
    print("%-8s %-34s %10s %10s %8s %8s %8s" % ("protocol", "reading client", "missed", "of", "p50 ms", "p99 ms",
                                                "max ms"))
    for name, key, client_name, got in (("NatNet", "natnet", "natnetsdk (multicast)", natnet),
                                        ("VRPN", "vrpn", "raw tcp:// reader", vrpn),
                                        ("VMC", "vmc", "python-osc", vmc)):
        lost, span = missed(got, published)
        lat = status.get(key, {}).get("publish_to_sent_ms", {})
        print("%-8s %-34s %10s %10d %8.3f %8.3f %8.3f" % (name, client_name, "-" if lost is None else lost, span,
                                                          lat.get("p50", 0), lat.get("p99", 0), lat.get("max", 0)))
    print("(publish -> handed to the kernel, on the hub: /api/status <protocol>.publish_to_sent_ms)")


if __name__ == "__main__":
    main()
