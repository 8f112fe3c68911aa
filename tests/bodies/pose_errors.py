#!/usr/bin/env python3
"""Rigid-body orientation errors against the simulator's true poses, split by how fast the body
turns: per body the median and 95th percentile over every frame with a pose, and the same over
the frames of the fastest angular acceleration (the top 5 % of |w(f+1) - w(f)| in the truth),
where a filter that lags would show. Pose files as `reconstruct --bodies` and `sim project
--bodies` write them (frame, time_s, body, tracked, predicted, x, y, z, qx, qy, qz, qw, ...).

usage: pose_errors.py TRUTH.bodies.tsv RESULT.bodies.tsv [more results...]"""

import math
import sys


def read_poses(path):
    """{(body, frame): (tracked or predicted, quaternion (w, x, y, z))}"""
    poses = {}
    with open(path) as f:
        next(f)
        for line in f:
            c = line.rstrip("\n").split("\t")
            if len(c) < 12:
                continue
            posed = c[3] == "1" or c[4] == "1"  # a row without a pose has empty cells
            poses[(c[2], int(c[0]))] = (posed, (float(c[11]), float(c[8]), float(c[9]), float(c[10])) if posed else None)
    return poses


def multiply(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)


def conjugate(q):
    return (q[0], -q[1], -q[2], -q[3])


def rotation_vector(q):
    """Rotation vector (rad) of a unit quaternion, the short way round."""
    if q[0] < 0:
        q = tuple(-v for v in q)
    s = math.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    if s < 1e-15:
        return (0.0, 0.0, 0.0)
    angle = 2 * math.atan2(s, q[0])
    return tuple(angle * v / s for v in q[1:])


def angle_deg(q):
    return math.degrees(math.sqrt(sum(v * v for v in rotation_vector(q))))


def percentile(values, p):
    values = sorted(values)
    return values[min(len(values) - 1, int(p * len(values)))] if values else float("nan")


def errors(truth_path, result_path):
    """{body: {"all": [deg...], "fast": [deg...]}}: "fast" over the top 5 % angular acceleration."""
    truth, result = read_poses(truth_path), read_poses(result_path)
    out = {}
    for body in sorted({b for b, _ in truth}):
        frames = sorted(f for b, f in truth if b == body and truth[(b, f)][0])
        # World-frame angular velocity per frame step, and its change.
        velocity = {f: rotation_vector(multiply(truth[(body, f + 1)][1], conjugate(truth[(body, f)][1])))
                    for f in frames if truth.get((body, f + 1), (False,))[0]}
        acceleration = {f: math.sqrt(sum((a - b) ** 2 for a, b in zip(velocity[f], velocity[f - 1])))
                        for f in frames if f in velocity and f - 1 in velocity}
        threshold = percentile(list(acceleration.values()), 0.95)
        all_errors, fast = [], []
        for f in frames:
            got = result.get((body, f))
            if not got or not got[0]:
                continue
            e = angle_deg(multiply(got[1], conjugate(truth[(body, f)][1])))
            all_errors.append(e)
            if acceleration.get(f, -1.0) >= threshold:
                fast.append(e)
        speed = [math.degrees(math.sqrt(sum(v * v for v in w))) for w in velocity.values()]
        out[body] = {"all": all_errors, "fast": fast, "speed_deg_per_frame": percentile(speed, 0.5),
                     "fast_acceleration_deg_per_frame2": math.degrees(threshold)}
    return out


def main():
    for result in sys.argv[2:]:
        for body, e in errors(sys.argv[1], result).items():
            print(f"{result} {body}: p50 {percentile(e['all'], 0.5):.3f} p95 {percentile(e['all'], 0.95):.3f} deg; "
                  f"fastest turns ({len(e['fast'])} frames, >= {e['fast_acceleration_deg_per_frame2']:.3f} "
                  f"deg/frame^2 at {e['speed_deg_per_frame']:.2f} deg/frame) p50 {percentile(e['fast'], 0.5):.3f} "
                  f"p95 {percentile(e['fast'], 0.95):.3f} deg")


if __name__ == "__main__":
    main()
