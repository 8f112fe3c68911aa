#!/usr/bin/env python3
"""A mesh driven by markers plays in the console (label web): a simulated take (40 markers,
60 Hz), a 50 000-vertex mesh made of a grid patch around each marker's static position, bound by
`mocap-hub mesh drive --binding` into the session (face.mdb: bound vertices, triangles, the
hub's RBF weights); `mocap-hub serve` without nodes, Debian's Chromium headless through selenium.
The sessions page's Play on face.mdb plays the take with the mesh deformed in the page frame by
frame at the capture's rate. Asserted: it plays, and the vertices the page draws at frames over
the take are the hub's own deformation (`mesh drive` on those frames, a .pc2) within 0.01 mm:
both apply the same weights to the same marker displacements, the page in float32 (weights,
bound vertices and its output buffer: 2^-24 relative, 0.0001 mm at 2 m) where the hub uses
doubles, so the difference is float rounding, far under 0.01 mm. Printed, not asserted: the
frames per second rendered, with the mesh and for the same take as markers alone (software
WebGL: a relative cost), and the per-frame deformation cost.
usage: mesh_player_test.py BIN_DIR WORK_DIR"""

import os
import shutil
import struct
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from console_session import click, console_on_sessions, hub  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import wait_for  # noqa: E402

from selenium.webdriver.common.by import By  # noqa: E402

MARKERS, RATE, FRAMES = 40, 60, 600
GRID_U, GRID_V, PATCH_MM = 25, 50, 60.0  # 1250 vertices a marker: 50 000 in all
COMPARED = (0, 1, 137, 300, FRAMES - 1)
SAMPLE_STEP = 47  # vertices compared: every 47th (1064 of them, spread over every patch)
TOLERANCE_MM = 0.01



def trc_lines(path):
    with open(path) as f:
        lines = f.read().split("\n")
    return lines[:5], [line for line in lines[5:] if line.strip()]


def write_patch_mesh(trc, obj):
    """A flat grid patch around each marker's position in the first frame, the marker on one of
    its vertices, so that the binding's ICP finds the mesh where the markers are."""
    _, rows = trc_lines(trc)
    cells = rows[0].split("\t")
    vertices, faces = [], []
    for m in range(MARKERS):
        x, y, z = (float(c) for c in cells[2 + 3 * m:5 + 3 * m])
        base = len(vertices)
        for i in range(GRID_U):
            for j in range(GRID_V):
                vertices.append((x + PATCH_MM * (i / (GRID_U - 1) - 0.5), y + PATCH_MM * (j / (GRID_V - 1) - 0.5),
                                 z + 0.2 * ((i + j) % 3)))
        vertices[base + (GRID_U // 2) * GRID_V + GRID_V // 2] = (x, y, z)
        for i in range(GRID_U - 1):
            for j in range(GRID_V - 1):
                a = base + i * GRID_V + j + 1  # OBJ indices start at 1
                faces.append((a, a + GRID_V, a + GRID_V + 1, a + 1))
    with open(obj, "w") as out:
        out.writelines("v %.5f %.5f %.5f\n" % v for v in vertices)
        out.writelines("f %d %d %d %d\n" % f for f in faces)
    return len(vertices)


def read_pc2(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data[:12] == b"POINTCACHE2\0"
    _, points, _, _, samples = struct.unpack_from("<iiffi", data, 12)
    frames = []
    for s in range(samples):
        frames.append(struct.unpack_from("<%df" % (3 * points), data, 32 + 12 * points * s))
    return points, frames


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    take = os.path.join(work, "take.trc")
    rig = os.path.join(work, "rig.json")
    session = os.path.join(work, "sessions", "face")
    hub(bin_dir, "sim", "motion", "--markers", str(MARKERS), "--frames", str(FRAMES), "--rate", str(RATE), "-o", take)
    hub(bin_dir, "sim", "rig", "--motion", take, "--cameras", "4", "-o", rig)
    hub(bin_dir, "sim", "project", "--motion", take, "--rig", rig, "-o", session)
    shutil.copy(take, os.path.join(session, "markers.trc"))
    mesh = os.path.join(work, "patches.obj")
    vertex_count = write_patch_mesh(take, mesh)
    # The hub's deformation of the compared frames (the static frame first): a .pc2 of those
    # frames only, the binding written beside the session's markers.
    header, rows = trc_lines(take)
    subset = os.path.join(work, "compared.trc")
    with open(subset, "w") as out:
        out.write("\n".join(header + [rows[f] for f in COMPARED]) + "\n")
    print(hub(bin_dir, "mesh", "drive", "--mesh", mesh, "--markers", subset, "--static-frame", "0",
              "--binding", os.path.join(session, "face.mdb"), "-o", os.path.join(work, "hub.pc2")).strip())
    points, expected = read_pc2(os.path.join(work, "hub.pc2"))
    assert points == vertex_count and len(expected) == len(COMPARED)
    with console_on_sessions(bin_dir, work, rig) as (page, port):
        js = page.execute_script
        wait_for("the session's files", lambda: click(page, "tr[data-session='face'] button[data-action=files]"))
        player = "mocapConsole.pages.sessions.player"
        # The same take as markers alone first: the frames rendered without the mesh, the
        # baseline the mesh's cost is relative to.
        wait_for("markers.trc's play button", lambda: click(
            page, "#session-details tr[data-file='markers.trc'] button[data-action=play]"))
        wait_for("the markers playing", lambda: js(f"return {player}.playing && {player}.mesh === null"), timeout=60)
        baseline = rendered_per_second(js, player)
        play = wait_for("face.mdb's play button", lambda: page.find_elements(
            By.CSS_SELECTOR, "#session-details tr[data-file='face.mdb'] button[data-action=play]"))[0]
        play.click()
        try:
            wait_for("the mesh playing", lambda: js(f"return {player}.playing && {player}.mesh !== null"), timeout=60)
        except AssertionError:
            print("player's title:", js("return document.getElementById('play-title').textContent"))
            raise
        # Two seconds of playback: frames rendered, capture frames advanced, deformation cost.
        start = js(f"return [performance.now(), {player}.scene.framesRendered, {player}.index, "
                   f"{player}.deform.frames, {player}.deform.ms]")
        time.sleep(2.0)
        end = js(f"return [performance.now(), {player}.scene.framesRendered, {player}.index, "
                 f"{player}.deform.frames, {player}.deform.ms]")
        seconds = (end[0] - start[0]) / 1000
        deformed = end[3] - start[3]
        assert end[2] > start[2], "the take did not advance"
        print(f"mesh of {vertex_count} vertices driven by {MARKERS} markers: {(end[1] - start[1]) / seconds:.1f} "
              f"frames per second rendered ({baseline:.1f} for the markers alone), "
              f"{(end[2] - start[2]) / seconds:.1f} capture frames a second "
              f"(capture rate {RATE} Hz), deformation {(end[4] - start[4]) / max(deformed, 1):.2f} ms a frame "
              f"({deformed} frames deformed)")
        js(f"{player}.pause()")
        worst = 0.0
        for k, frame in enumerate(COMPARED):
            shown = js(f"{player}.seek({frame}); const a = {player}.scene.mesh.geometry.attributes.position.array;"
                       f" const out = []; for (let v = 0; v < a.length / 3; v += {SAMPLE_STEP})"
                       f" out.push(a[3 * v], a[3 * v + 1], a[3 * v + 2]); return out;")
            for n, v in enumerate(range(0, vertex_count, SAMPLE_STEP)):
                for a in range(3):
                    worst = max(worst, abs(shown[3 * n + a] - expected[k][3 * v + a]))
        assert worst < TOLERANCE_MM, f"the page's vertices are {worst:.5f} mm from the hub's deformation"
        print(f"displayed vertices within {worst:.5f} mm of the hub's deformation at frames {COMPARED}")
        return 0


def rendered_per_second(js, player, seconds=2.0):
    start = js(f"return [performance.now(), {player}.scene.framesRendered]")
    time.sleep(seconds)
    end = js(f"return [performance.now(), {player}.scene.framesRendered]")
    return (end[1] - start[1]) * 1000 / (end[0] - start[0])



if __name__ == "__main__":
    sys.exit(main())
