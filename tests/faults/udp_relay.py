#!/usr/bin/env python3
"""A UDP relay for the fault suite: nodes send to it as if it were the hub, and it forwards
their datagrams to the hub (and the hub's answers back to each node, one upstream socket per
node address, as a NAT does), losing, duplicating and delaying them at random. With
--shift-node it also plays a node whose clock steps: that node's frames get their frame
numbers and times moved and are sealed again under its key (the envelope of
hub/src/wire/envelope.h), so the hub sees exactly what such a node would send.

usage: udp_relay.py --to HOST:PORT [--listen HOST:PORT] [--loss P] [--dup P] [--reorder P]
                    [--reorder-ms MS] [--seed N] [--shift-node ID --shift-frames N --rate HZ
                    --key-file FILE]
Prints "relay port N" once listening. SIGUSR1 steps the shifted node's clock ahead by
--shift-frames frames, SIGUSR2 behind by as many, SIGHUP back; SIGTERM prints the counts as one
JSON line and exits. Loopback only; every loop iteration is bounded by a 10 ms poll."""

import argparse
import heapq
import json
import os
import random
import re
import select
import signal
import socket
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import proto_encode, proto_fields, seal  # noqa: E402


def host_port(text):
    host, _, port = text.rpartition(":")
    return host, int(port)


def load_key(path):
    with open(path) as f:
        match = re.search(r"^key = (\d+) ([0-9a-f]{64})$", f.read(), re.M)
    return int(match.group(1)), bytes.fromhex(match.group(2))


class Relay:
    def __init__(self, args):
        self.args = args
        self.rng = random.Random(args.seed)
        self.target = host_port(args.to)
        self.front = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.front.bind(host_port(args.listen))
        self.upstream = {}      # node address -> socket towards the hub
        self.client_of = {}     # upstream socket fileno -> node address
        self.pending = []       # (due monotonic, seq, socket, datagram, address)
        self.seq = 0
        self.shift = 0          # frames the shifted node's clock is ahead (negative: behind)
        self.last_counter = 0   # the shifted node's last envelope counter as relayed
        self.key = load_key(args.key_file) if args.key_file else None
        self.counts = {d: {"datagrams": 0, "lost": 0, "duplicated": 0, "delayed": 0} for d in ("up", "down")}
        self.counts["shifted_frames"] = 0

    def schedule(self, sock, datagram, address, direction):
        c = self.counts[direction]
        c["datagrams"] += 1
        if self.rng.random() < self.args.loss:
            c["lost"] += 1
            return
        copies = 2 if self.rng.random() < self.args.dup else 1
        c["duplicated"] += copies - 1
        for _ in range(copies):
            delay = 0.0
            if self.rng.random() < self.args.reorder:
                delay = self.rng.uniform(0.001, self.args.reorder_ms / 1000.0)
                c["delayed"] += 1
            if delay == 0.0:
                sock.sendto(datagram, address)
            else:
                self.seq += 1
                heapq.heappush(self.pending, (time.monotonic() + delay, self.seq, sock, datagram, address))

    def shifted(self, datagram):
        """The datagram as the shifted node would send it with its clock `shift` frames off.
        Its counters stay monotonic across a step back, as the node's own do (envelope.h)."""
        if self.key is None or len(datagram) < 48 or datagram[0] != 0xA1:
            return datagram
        node = int.from_bytes(datagram[4:8], "little")
        if node != self.args.shift_node:
            return datagram
        shift_ns = self.shift * 1_000_000_000 // self.args.rate
        counter = int.from_bytes(datagram[8:16], "little") + shift_ns
        if self.shift == 0 and counter > self.last_counter:
            self.last_counter = counter
            return datagram
        counter = max(counter, self.last_counter + 1)
        self.last_counter = counter
        packet = proto_fields(datagram[16:-32])
        for i, (number, kind, value) in enumerate(packet):
            if number == 10 and kind == 2:  # MarkerFrame: its number and its clock's times move
                frame = [(n, k, v + (self.shift if n == 2 else shift_ns) if n in (2, 3, 4, 5) and k == 0 else v)
                         for n, k, v in proto_fields(value)]
                packet[i] = (number, kind, proto_encode(frame))
                self.counts["shifted_frames"] += 1
        key_id, key = self.key
        return seal(key, datagram[1], node, proto_encode(packet), counter=counter, key_id=key_id)

    def upstream_for(self, address):
        sock = self.upstream.get(address)
        if sock is None:
            sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
            sock.bind(("127.0.0.1", 0))
            self.upstream[address] = sock
            self.client_of[sock.fileno()] = address
        return sock

    def run(self):
        stop = []
        signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
        signal.signal(signal.SIGUSR1, lambda *_: setattr(self, "shift", self.args.shift_frames))
        signal.signal(signal.SIGUSR2, lambda *_: setattr(self, "shift", -self.args.shift_frames))
        signal.signal(signal.SIGHUP, lambda *_: setattr(self, "shift", 0))
        print(f"relay port {self.front.getsockname()[1]}", flush=True)
        while not stop:
            now = time.monotonic()
            while self.pending and self.pending[0][0] <= now:
                _, _, sock, datagram, address = heapq.heappop(self.pending)
                sock.sendto(datagram, address)
            try:
                readable, _, _ = select.select([self.front, *self.upstream.values()], [], [], 0.01)
            except InterruptedError:
                continue
            for sock in readable:
                try:
                    datagram, address = sock.recvfrom(65535)
                except (BlockingIOError, InterruptedError):
                    continue
                if sock is self.front:
                    self.schedule(self.upstream_for(address), self.shifted(datagram), self.target, "up")
                else:
                    self.schedule(self.front, datagram, self.client_of[sock.fileno()], "down")
        print(json.dumps(self.counts), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--to", required=True)
    parser.add_argument("--listen", default="127.0.0.1:0")
    parser.add_argument("--loss", type=float, default=0.0)
    parser.add_argument("--dup", type=float, default=0.0)
    parser.add_argument("--reorder", type=float, default=0.0)
    parser.add_argument("--reorder-ms", type=float, default=30.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--shift-node", type=int, default=0)
    parser.add_argument("--shift-frames", type=int, default=0)
    parser.add_argument("--rate", type=int, default=100)
    parser.add_argument("--key-file")
    args = parser.parse_args()
    for p in (args.loss, args.dup, args.reorder):
        if not 0.0 <= p <= 1.0:
            parser.error("probabilities must lie in 0..1")
    Relay(args).run()


if __name__ == "__main__":
    main()
