#!/usr/bin/env python3
"""Qualisys RT latency probe for stream-bench: connects Qualisys' own client (qtm-rt, from .venv)
to serve's RT port, retrying until serve is up (up to WAIT_S), streams the 3D component over TCP
and prints "trigger_to_receive_ms p50 p99 max" over FRAMES frames (the packet's timestamp is the
frame's trigger time, in microseconds, on this host's clock).

usage: qtm_probe.py PORT FRAMES [WAIT_S]"""

import asyncio
import sys
import time

import qtm_rt

from probe_report import arguments, report


async def probe(port, frames, wait_s):
    deadline = time.monotonic() + wait_s
    conn = None
    while conn is None and time.monotonic() < deadline:
        conn = await qtm_rt.connect("127.0.0.1", port)
        if conn is None:
            await asyncio.sleep(0.2)
    if conn is None:
        return []
    latency, done = [], asyncio.get_running_loop().create_future()

    def on_packet(packet):
        now_us = time.time_ns() / 1e3
        if packet.timestamp and now_us > packet.timestamp:
            latency.append((now_us - packet.timestamp) / 1e3)
        if len(latency) >= frames and not done.done():
            done.set_result(None)

    await conn.stream_frames(components=["3d"], on_packet=on_packet)
    try:
        await asyncio.wait_for(done, wait_s)
    except asyncio.TimeoutError:
        pass
    conn.disconnect()
    return latency


def main():
    port, frames, wait_s = arguments()
    return report(asyncio.run(probe(port, frames, wait_s)), "no Qualisys RT frames")


if __name__ == "__main__":
    sys.exit(main())
