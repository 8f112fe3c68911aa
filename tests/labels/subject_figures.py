#!/usr/bin/env python3
"""Labelling figures on two people of one marker set (issue 31): hdm_bd.trc and hdm_mm.trc from
../shared/data/subjects, each projected into 10 simulated cameras (0.2 px, 5 % occlusion,
2 spurious blobs per camera) and reconstructed without names; then each subject's set (learned
from its own truth) names each reconstruction with both whole-take labellers (`labels apply
--labeller trial`, the default, and `subject`, the subject model), over its first 300, 1200 and
2400 frames; `eval` gives the shares of output points right, wrong and unnamed. Then the two
reconstructions joined end to end (hdm_bd's 2400 frames, then hdm_mm's as new tracks: 4800
frames) are named by hdm_mm's set and by a set learned from both people. Last, e2e_labels' two
real cases named by both labellers. Prints tables; asserts nothing (a benchmark: the figures are
what docs/labels.md quotes).

usage: subject_figures.py BIN_DIR WORK_DIR"""

import json
import os
import subprocess
import sys

SUBJECTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "data", "subjects")


def hub(bin_dir, *args):
    return subprocess.run([os.path.join(bin_dir, "mocap-hub"), *args], check=True, capture_output=True,
                          text=True, timeout=3600).stdout


def first_frames(path, out, frames):
    """The first `frames` rows of a TRC (header counts fixed)."""
    with open(path) as f:
        lines = f.read().splitlines()
    rows = [line for line in lines[5:] if line.strip()][:frames]
    fields = lines[2].split("\t")
    fields[2] = str(len(rows))
    lines[2] = "\t".join(fields)
    with open(out, "w") as f:
        f.write("\n".join(lines[:5] + rows) + "\n")


def read_rows(path):
    """A TRC's marker names and its data rows split into cells (frame and time dropped)."""
    with open(path) as f:
        lines = f.read().splitlines()
    names = [c for c in lines[3].split("\t")[2:] if c.strip()]
    rows = [line.split("\t")[2:] for line in lines[5:] if line.strip()]
    return names, [(row + [""] * (3 * len(names)))[:3 * len(names)] for row in rows]


def join(first, second, out, anonymous):
    """Two TRCs end to end (frames renumbered on). Anonymous: the second's columns are new ones
    (its tracks are not the first's); else both name the same markers in the same order."""
    names_a, rows_a = read_rows(first)
    names_b, rows_b = read_rows(second)
    if anonymous:
        names = names_a + ["M%03d" % (len(names_a) + k + 1) for k in range(len(names_b))]
        rows = [r + [""] * len(r_b) for r, r_b in zip(rows_a, [rows_b[0]] * len(rows_a))] + \
            [[""] * (3 * len(names_a)) + r for r in rows_b]
    else:
        assert names_a == names_b, "the trials name other markers"
        names, rows = names_a, rows_a + rows_b
    with open(first) as f:
        header = f.read().splitlines()[:3]
    fields = header[2].split("\t")
    fields[2], fields[3] = str(len(rows)), str(len(names))
    rate = float(fields[0])
    with open(out, "w") as f:
        f.write("\n".join(header[:2] + ["\t".join(fields)]) + "\n")
        f.write("Frame#\tTime\t" + "\t\t\t".join(names) + "\t\t\n")
        f.write("\t\t" + "\t".join(f"{a}{k + 1}" for k in range(len(names)) for a in "XYZ") + "\n\n")
        for i, row in enumerate(rows):
            f.write(f"{i + 1}\t{i / rate:.6f}\t" + "\t".join(row) + "\n")


def name_and_score(bin_dir, marker_set, anon, truth, named, labeller):
    """`labels apply --labeller LABELLER` (the subject model's decisions beside NAMED, .log); eval's report."""
    log = ["--explain", named + ".log"] if labeller == "subject" else []
    hub(bin_dir, "labels", "apply", anon, "--labels", marker_set, "-o", named, "--labeller", labeller, *log)
    return json.loads(hub(bin_dir, "eval", "--truth", truth, "--result", named, "--json"))


def row(*cells, report):
    print("| " + " | ".join(cells) + f" | {100 * report['correct_share']:.2f} % | {100 * report['wrong_share']:.2f} % | "
          f"{100 * report['unnamed_share']:.2f} % |", flush=True)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    bin_dir, work = sys.argv[1], sys.argv[2]
    if not os.path.isdir(SUBJECTS):
        print("SKIPPED: no ../shared/data/subjects beside the checkout")
        return
    os.makedirs(work, exist_ok=True)
    for s in ("bd", "mm"):
        truth = os.path.join(SUBJECTS, f"hdm_{s}.trc")
        session = os.path.join(work, f"{s}.session")
        anon = os.path.join(work, f"{s}.anon.trc")
        if not os.path.exists(anon):
            rig = os.path.join(work, f"{s}.rig.json")
            hub(bin_dir, "sim", "rig", "--motion", truth, "--cameras", "10", "--up", "z", "-o", rig)
            hub(bin_dir, "sim", "project", "--motion", truth, "--rig", rig, "-o", session, "--noise-px", "0.2",
                "--occlusion", "0.05", "--spurious", "2")
            hub(bin_dir, "reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", anon)
        hub(bin_dir, "labels", "learn", truth, "-o", os.path.join(work, f"{s}.set.json"))
    print("| set from | applied to | frames | labeller | right | wrong | unnamed |")
    print("|---|---|---|---|---|---|---|")
    for learned in ("bd", "mm"):
        for applied in ("mm", "bd") if learned == "bd" else ("bd", "mm"):
            for frames in (300, 1200, 2400):
                anon = os.path.join(work, f"{applied}.anon.{frames}.trc")
                first_frames(os.path.join(work, f"{applied}.anon.trc"), anon, frames)
                truth = os.path.join(work, f"{applied}.truth.{frames}.trc")
                first_frames(os.path.join(SUBJECTS, f"hdm_{applied}.trc"), truth, frames)
                for labeller in ("trial", "subject"):
                    named = os.path.join(work, f"{learned}_on_{applied}.{frames}.{labeller}.trc")
                    report = name_and_score(bin_dir, os.path.join(work, f"{learned}.set.json"), anon, truth, named,
                                            labeller)
                    row(f"hdm_{learned}", f"hdm_{applied}", str(frames), labeller, report=report)
    anon, truth = os.path.join(work, "joined.anon.trc"), os.path.join(work, "joined.truth.trc")
    join(os.path.join(work, "bd.anon.trc"), os.path.join(work, "mm.anon.trc"), anon, True)
    join(os.path.join(SUBJECTS, "hdm_bd.trc"), os.path.join(SUBJECTS, "hdm_mm.trc"), truth, False)
    both = os.path.join(work, "both.set.json")
    hub(bin_dir, "labels", "learn", os.path.join(SUBJECTS, "hdm_bd.trc"), os.path.join(SUBJECTS, "hdm_mm.trc"), "-o", both)
    for label, marker_set in (("hdm_mm", os.path.join(work, "mm.set.json")), ("hdm_bd + hdm_mm", both)):
        for labeller in ("trial", "subject"):
            named = os.path.join(work, "joined_" + label.replace(" + ", "_") + f".{labeller}.trc")
            report = name_and_score(bin_dir, marker_set, anon, truth, named, labeller)
            row(label, "hdm_bd then hdm_mm", "4800", labeller, report=report)
    motions(bin_dir, work)


def motions(bin_dir, work):
    """e2e_labels' two real cases (walk.trc's set on running.trc; the tennis serve's first half on
    the whole serve; 8 cameras, its faults) named by both whole-take labellers."""
    motions_dir = os.path.join(os.path.dirname(SUBJECTS), "motions")
    if not os.path.isdir(motions_dir):
        print("SKIPPED: no ../shared/data/motions beside the checkout")
        return
    tennis = os.path.join(motions_dir, "tennis_serve.trc")
    with open(tennis) as f:
        frames = sum(1 for line in f.read().splitlines()[5:] if line.strip())
    first = os.path.join(work, "tennis_first_half.trc")
    first_frames(tennis, first, frames // 2)
    print("\n| case | labeller | right | wrong | unnamed |")
    print("|---|---|---|---|---|")
    for case, motion, trial in (("running from walk", os.path.join(motions_dir, "running.trc"),
                                 os.path.join(motions_dir, "walk.trc")),
                                ("tennis serve from its first half", tennis, first)):
        stem = os.path.join(work, case.split()[0])
        marker_set, anon, session = stem + ".set.json", stem + ".anon.trc", stem + ".session"
        hub(bin_dir, "labels", "learn", trial, "-o", marker_set)
        if not os.path.exists(anon):
            hub(bin_dir, "sim", "rig", "--motion", motion, "--cameras", "8", "-o", stem + ".rig.json")
            hub(bin_dir, "sim", "project", "--motion", motion, "--rig", stem + ".rig.json", "-o", session,
                "--noise-px", "0.2", "--occlusion", "0.05", "--occlusion-frames", "5", "--spurious", "2",
                "--drop-frames", "0.002")
            hub(bin_dir, "reconstruct", session, "--calibration", os.path.join(session, "calibration.json"), "-o", anon)
        for labeller in ("trial", "subject"):
            report = name_and_score(bin_dir, marker_set, anon, os.path.join(session, "truth.trc"),
                                    f"{stem}.{labeller}.trc", labeller)
            row(case, labeller, report=report)

if __name__ == "__main__":
    main()
