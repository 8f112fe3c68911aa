"""A gap filled through the console's trajectory editor (label web): `mocap-hub serve` without
nodes, a session whose processed results (processed/gait/markers.trc) are a simulated motion with
one marker cut for 0.3 s; Debian's Chromium headless through selenium. The operator opens the
results in the editor, picks the marker and the frames, fills by spline, and the hub writes
edited.trc (the gap within 10 mm of the motion: the spline's 0.25 s figures in docs/editor.md),
edited.filled.tsv (the stretch marked spline), edited.c3d (ezc3d reads residual 0 on the filled
samples, 1 on measured ones) and edits.json beside the results, never over them;
Undo puts the gap back, Redo fills it again. The page is saved as WORK_DIR/editor.png
(docs/console/editor.png).
usage: editor_test.py BIN_DIR WORK_DIR"""

import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from console_session import click, console_on_sessions, hub  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import wait_for  # noqa: E402

import ezc3d  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402

MARKERS, RATE, FRAMES = 8, 100, 400
CUT_MARKER, CUT_FROM, CUT_TO = 3, 150, 179  # frame numbers (Time x rate)



def trc(path):
    """names, {frame number: [[x, y, z] or None per marker]} of a TRC this hub wrote."""
    with open(path) as f:
        lines = f.read().split("\n")
    names = [n for n in lines[3].split("\t")[2:] if n]
    rows = {}
    for line in lines[5:]:
        if line.strip():
            cells = line.split("\t")
            values = []
            for m in range(len(names)):
                c = cells[2 + 3 * m:5 + 3 * m]
                values.append([float(v) for v in c] if len(c) == 3 and all(v.strip() for v in c) else None)
            rows[round(float(cells[1]) * RATE)] = values
    return names, rows


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    motion = os.path.join(work, "motion.trc")
    rig = os.path.join(work, "rig.json")
    session = os.path.join(work, "sessions", "take")
    hub(bin_dir, "sim", "motion", "--markers", str(MARKERS), "--frames", str(FRAMES), "--rate", str(RATE), "-o", motion)
    hub(bin_dir, "sim", "rig", "--motion", motion, "--cameras", "4", "-o", rig)
    hub(bin_dir, "sim", "project", "--motion", motion, "--rig", rig, "-o", session)
    names, truth = trc(motion)
    results = os.path.join(session, "processed", "gait")
    os.makedirs(results)
    cut = os.path.join(work, "cut.json")
    with open(cut, "w") as f:
        f.write('{"format": "mocap-edits", "version": 1, "operations": [{"op": "delete", "marker": "%s", '
                '"from": %d, "to": %d}]}' % (names[CUT_MARKER], CUT_FROM, CUT_TO))
    hub(bin_dir, "edit", "apply", cut, "--input", motion, "-o", os.path.join(results, "markers.trc"))
    os.remove(os.path.join(results, "markers.filled.tsv"))
    hub(bin_dir, "convert", os.path.join(results, "markers.trc"), os.path.join(results, "markers.c3d"))
    results_before = open(os.path.join(results, "markers.trc")).read()
    with console_on_sessions(bin_dir, work, rig) as (page, port):
        js = page.execute_script
        wait_for("the session's files", lambda: click(page, "tr[data-session='take'] button[data-action=files]"))
        wait_for("the results' Edit button", lambda: click(page, "#processed-results button[data-action=edit-result]"))
        wait_for("the editor's markers", lambda: len(page.find_elements(By.CSS_SELECTOR, "#editor-marker option")) ==
                 MARKERS)
        # Pick the marker and the frames as the operator does: the row on the timeline, then the range.
        js("const s = document.getElementById('editor-marker'); s.value = arguments[0];"
           "s.dispatchEvent(new Event('change'));", str(CUT_MARKER))
        for field, value in (("editor-from", CUT_FROM - 5), ("editor-to", CUT_TO + 5)):
            box = page.find_element(By.ID, field)
            box.clear()
            box.send_keys(str(value))
        page.find_element(By.CSS_SELECTOR, "#editor-method option[value=spline]").click()
        page.find_element(By.ID, "editor-fill").click()
        wait_for("the fill applied", lambda: "1 of 1 gaps filled" in page.find_element(By.ID, "editor-message").text)
        edited = os.path.join(results, "edited.trc")
        _, rows = trc(edited)
        worst = max(max(abs(a - b) for a, b in zip(rows[f][CUT_MARKER], truth[f][CUT_MARKER]))
                    for f in range(CUT_FROM, CUT_TO + 1))
        assert worst < 10.0, f"the filled gap is {worst:.3f} mm from the motion"
        filled = open(os.path.join(results, "edited.filled.tsv")).read()
        assert f"{names[CUT_MARKER]}\t{CUT_FROM}\t{CUT_TO}\tspline\n" in filled, filled
        assert open(os.path.join(results, "markers.trc")).read() == results_before, "the results were written"
        assert '"spline"' in open(os.path.join(results, "edits.json")).read()
        # edited.c3d as ezc3d (PyPI) reads it: residual 0 on the filled samples, 1 on measured ones.
        c3d = ezc3d.c3d(os.path.join(results, "edited.c3d"))
        column = c3d["parameters"]["POINT"]["LABELS"]["value"].index(names[CUT_MARKER])
        residuals = c3d["data"]["meta_points"]["residuals"][0, column, :]
        assert all(residuals[f] == 0.0 for f in range(CUT_FROM, CUT_TO + 1)), residuals[CUT_FROM:CUT_TO + 1]
        assert residuals[CUT_FROM - 1] == 1.0 and residuals[CUT_TO + 1] == 1.0, residuals
        assert len(page.find_elements(By.CSS_SELECTOR, "#editor-log li")) == 1
        js("document.getElementById('editor-timeline').scrollIntoView({block: 'center'})")
        page.save_screenshot(os.path.join(work, "editor.png"))
        page.find_element(By.ID, "editor-undo").click()
        wait_for("the undo applied", lambda: not page.find_elements(By.CSS_SELECTOR, "#editor-log li"))
        _, rows = trc(edited)
        assert rows[CUT_FROM + 10][CUT_MARKER] is None, "undo left the gap filled"
        page.find_element(By.ID, "editor-redo").click()
        wait_for("the redo applied", lambda: len(page.find_elements(By.CSS_SELECTOR, "#editor-log li")) == 1)
        print(f"gap of {CUT_TO - CUT_FROM + 1} frames filled by spline through the console, "
              f"worst {worst:.3f} mm from the motion; undo and redo re-applied the log")
        return 0



if __name__ == "__main__":
    sys.exit(main())
