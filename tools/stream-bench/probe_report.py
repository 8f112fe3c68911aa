"""What the stream-bench probes share: their arguments (PORT FRAMES [WAIT_S]) and their report,
"trigger_to_receive_ms p50 p99 max" then "frames N", worked out the same way for every protocol
so that stream-bench's rows compare."""

import sys


def arguments():
    """PORT, FRAMES and WAIT_S (30 s when not given) from the command line."""
    port, frames = int(sys.argv[1]), int(sys.argv[2])
    wait_s = float(sys.argv[3]) if len(sys.argv) > 3 else 30.0
    return port, frames, wait_s


def report(latency_ms, nothing_received):
    """Prints the report of these latencies and returns 0; with none, says nothing_received on
    stderr and returns 1."""
    if not latency_ms:
        print(nothing_received, file=sys.stderr)
        return 1
    latency = sorted(latency_ms)
    print("trigger_to_receive_ms %.3f %.3f %.3f" % (latency[len(latency) // 2],
                                                    latency[int(0.99 * (len(latency) - 1))], latency[-1]))
    print(f"frames {len(latency)}")
    return 0
