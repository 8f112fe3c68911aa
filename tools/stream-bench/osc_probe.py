#!/usr/bin/env python3
"""OSC latency probe for stream-bench: listens on 127.0.0.1:PORT with python-osc (an OSC
implementation independent of the hub's liblo) and, after FRAMES /mocap/frame messages or
WAIT_S seconds without one, prints "trigger_to_receive_ms p50 p99 max" over the frames
(trigger time from the message, receive time from this host's clock).

usage: osc_probe.py PORT FRAMES [WAIT_S]"""

import sys
import threading
import time

from pythonosc import dispatcher, osc_server

from probe_report import arguments, report


def main():
    port, frames, wait_s = arguments()
    latency = []
    last = [time.monotonic()]
    done = threading.Event()

    def on_frame(_address, _number, trigger_ns, *_rest):
        now = time.time_ns()
        last[0] = time.monotonic()
        if trigger_ns and now > trigger_ns:
            latency.append((now - trigger_ns) / 1e6)
        if len(latency) >= frames:
            done.set()

    d = dispatcher.Dispatcher()
    d.map("/mocap/frame", on_frame)
    server = osc_server.BlockingOSCUDPServer(("127.0.0.1", port), d)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    while not done.wait(0.2):
        if time.monotonic() - last[0] > wait_s:
            break
    server.shutdown()
    return report(latency, "no OSC frames")


if __name__ == "__main__":
    sys.exit(main())
