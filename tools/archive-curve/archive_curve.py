#!/usr/bin/env python3
"""Size against error of .mca archives (mocap-hub archive) on the shared recordings.

For every TRC under ../shared/data/{motions,dense,subjects} (or the files given) and every error
bound (and a few fixed component counts), writes the archive, reads it back with `convert` to a
TRC and lets `eval` measure the error independently of the archive's own figure. Prints one
table per recording: the bound or K, mean components, archive bytes, the ratio to the TRC as
given and to the TRC this hub writes (convert's output, same numbers in the hub's own format),
the archive's bits per marker position present in the recording (eval's truth_points), and the
RMS error from eval and from archive.
Usage: archive_curve.py BIN_DIR [--window-frames N] [--marker-set FILE] [TRC ...]
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

BOUNDS_MM = [1.0, 0.5, 0.25, 0.1]
COMPONENTS = [8, 16]


def run_json(command):
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("bin_dir")
    parser.add_argument("--window-frames", type=int, default=0)
    parser.add_argument("--marker-set", default="")
    parser.add_argument("trc", nargs="*")
    args = parser.parse_args()
    hub = os.path.join(args.bin_dir, "mocap-hub")
    files = args.trc
    if not files:
        shared = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data")
        for folder in ("motions", "dense", "subjects"):
            files += sorted(glob.glob(os.path.join(shared, folder, "*.trc")))
    if not files:
        print("no recordings given and none under ../shared/data", file=sys.stderr)
        return 1
    extra = []
    if args.window_frames:
        extra += ["--window-frames", str(args.window_frames)]
    if args.marker_set:
        extra += ["--marker-set", args.marker_set]
    summary = []
    with tempfile.TemporaryDirectory() as work:
        archive, back, hub_trc = (os.path.join(work, name) for name in ("a.mca", "back.trc", "hub.trc"))
        for trc in files:
            subprocess.run([hub, "convert", trc, hub_trc], check=True, capture_output=True)
            trc_bytes, hub_bytes = os.path.getsize(trc), os.path.getsize(hub_trc)
            print("\n%s: TRC %d bytes as given, %d as the hub writes it" % (os.path.relpath(trc), trc_bytes, hub_bytes))
            print("%-10s %6s %10s %9s %9s %7s %9s %9s" % ("setting", "mean K", "bytes", "x TRC", "x hubTRC", "bits/pt",
                                                           "eval mm", "arch mm"))
            settings = [("E=%gmm" % e, ["--max-error-mm", str(e)]) for e in BOUNDS_MM]
            settings += [("K=%d" % k, ["--components", str(k)]) for k in COMPONENTS]
            for label, option in settings:
                made = run_json([hub, "archive", trc, "-o", archive, "--json"] + option + extra)
                subprocess.run([hub, "convert", archive, back], check=True, capture_output=True)
                measured = run_json([hub, "eval", "--truth", trc, "--result", back, "--json"])
                row = (label, made["mean_components"], made["archive_bytes"], trc_bytes / made["archive_bytes"],
                       hub_bytes / made["archive_bytes"], 8.0 * made["archive_bytes"] / measured["truth_points"],
                       measured["rmse_mm"], made["rms_mm"])
                print("%-10s %6.1f %10d %9.1f %9.1f %7.2f %9.3f %9.3f" % row)
                if label == "E=0.5mm":
                    summary.append((os.path.basename(trc),) + row[2:])
    print("\nat a 0.5 mm bound: %-22s %9s %9s %9s %7s %9s" % ("recording", "bytes", "x TRC", "x hubTRC", "bits/pt",
                                                             "eval mm"))
    for name, size, ratio, hub_ratio, bits, rms, _ in summary:
        print("                   %-22s %9d %9.1f %9.1f %7.2f %9.3f" % (name, size, ratio, hub_ratio, bits, rms))
    return 0


if __name__ == "__main__":
    sys.exit(main())
