#!/usr/bin/env python3
"""An hour-long archive plays in the console (label web): `mocap-hub serve` without nodes, a
session holding a simulated hour (a synthetic minute compressed by `mocap-hub archive`, its
windows repeated sixty times into one .mca written here from the documented layout), Debian's
Chromium headless through selenium. The sessions page's Play decodes the archive in a Web Worker
as it streams in: asserted are that it plays, that every frame of the hour gets decoded, and
that the points it draws are the positions the hub's own reader gives (`convert minute.mca`)
at frames all over the hour. Printed, not asserted: the time from the click to the first frame
played and to the whole hour decoded.
usage: archive_player_test.py BIN_DIR WORK_DIR"""

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

MARKERS, RATE, MINUTE, REPEATS, WINDOW = 30, 60, 3600, 60, 240



def varint(value):
    out = bytearray()
    while value >= 0x80:
        out.append((value & 0x7F) | 0x80)
        value >>= 7
    out.append(value)
    return bytes(out)


def read_varint(data, pos):
    value, shift = 0, 0
    while True:
        b = data[pos]
        pos += 1
        value |= (b & 0x7F) << shift
        shift += 7
        if not b & 0x80:
            return value, pos


def repeat_archive(minute_path, hour_path, repeats):
    """The minute's archive with its windows repeated: an hour with the same layout
    (hub/src/archive/archive_format.h, version 2: the first window's means are absolute, so each
    repeat starts afresh)."""
    data = open(minute_path, "rb").read()
    assert data[:8] == b"MOCAPMCA" and struct.unpack_from("<I", data, 8)[0] == 2
    markers, frames, window = struct.unpack_from("<III", data, 20)
    assert frames % window == 0 and data[32] == 0, "a contiguous minute of whole windows"
    pos = 33 + 8
    for _ in range(markers):
        pos += 1 + data[pos]
    groups_start = pos
    (groups,) = struct.unpack_from("<I", data, pos)
    pos += 4
    for _ in range(groups):
        (size,) = struct.unpack_from("<I", data, pos)
        pos += 4 + 4 * size
    groups_bytes = data[groups_start:pos]
    for _ in range(markers):  # gap runs: a minute without gaps is one run per marker
        count, pos = read_varint(data, pos)
        assert count == 1
        _, pos = read_varint(data, pos)
    blocks = data[pos:]
    header = bytearray(data[:groups_start])
    struct.pack_into("<I", header, 24, frames * repeats)
    with open(hour_path, "wb") as out:
        out.write(header + groups_bytes)
        for _ in range(markers):
            out.write(varint(1) + varint(frames * repeats))
        for _ in range(repeats):
            out.write(blocks)


def trc_rows(path):
    rows = []
    with open(path) as f:
        for line in f.read().split("\n")[5:]:
            if line.strip():
                cells = line.split("\t")
                rows.append([float(c) for c in cells[2:2 + 3 * MARKERS]])
    return rows


def main():
    bin_dir, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    minute_trc = os.path.join(work, "minute.trc")
    rig = os.path.join(work, "rig.json")
    session = os.path.join(work, "sessions", "hour")
    hub(bin_dir, "sim", "motion", "--markers", str(MARKERS), "--frames", str(MINUTE), "--rate", str(RATE),
        "-o", minute_trc)
    hub(bin_dir, "sim", "rig", "--motion", minute_trc, "--cameras", "4", "-o", rig)
    hub(bin_dir, "sim", "project", "--motion", minute_trc, "--rig", rig, "-o", session)
    minute_mca = os.path.join(work, "minute.mca")
    print(hub(bin_dir, "archive", minute_trc, "-o", minute_mca, "--window-frames", str(WINDOW)).strip())
    hour_mca = os.path.join(session, "hour.mca")
    repeat_archive(minute_mca, hour_mca, REPEATS)
    print(f"hour.mca: {os.path.getsize(hour_mca)} bytes for {MINUTE * REPEATS} frames of {MARKERS} markers")
    with console_on_sessions(bin_dir, work, rig) as (page, port):
        js = page.execute_script
        wait_for("the session's files", lambda: click(page, "tr[data-session='hour'] button[data-action=files]"))
        play = wait_for("hour.mca's play button", lambda: page.find_elements(
            By.CSS_SELECTOR, "#session-details tr[data-file='hour.mca'] button[data-action=play]"))[0]
        clicked = time.monotonic()
        play.click()
        wait_for("playback", lambda: js("return mocapConsole.pages.sessions.player.playing"), timeout=30)
        shown = js("return mocapConsole.pages.sessions.player.framesShown")
        wait_for("a frame played after the first", lambda: js(
            "return mocapConsole.pages.sessions.player.framesShown") > shown, timeout=30)
        first_played = time.monotonic() - clicked
        total = MINUTE * REPEATS
        wait_for("the whole hour decoded", lambda: js(
            "return mocapConsole.pages.sessions.player.recording.decodedFrames") == total, timeout=120)
        all_decoded = time.monotonic() - clicked
        assert js("return mocapConsole.pages.sessions.player.recording.frameCount") == total
        # The drawn points are what the hub's reader decodes, in every repeat.
        decoded_trc = os.path.join(work, "minute_decoded.trc")
        hub(bin_dir, "convert", minute_mca, decoded_trc)
        rows = trc_rows(decoded_trc)
        worst = 0.0
        for frame in (0, 1, 239, 240, 1799, MINUTE - 1, MINUTE + 5, 30 * MINUTE + 777, total - 1):
            points = js(f"return mocapConsole.pages.sessions.player.recording.pointsAt({frame})")
            assert len(points) == MARKERS, (frame, len(points))
            row = rows[frame % MINUTE]
            for x, y, z, m, _ in points:
                worst = max(worst, max(abs(x - row[3 * m]), abs(y - row[3 * m + 1]), abs(z - row[3 * m + 2])))
        assert worst < 1e-3, f"the page's points are {worst:.5f} mm from the hub's decoding"
        print(f"hour-long archive: first frame played {first_played:.2f} s after the click, the whole hour "
              f"({total} frames) decoded after {all_decoded:.2f} s; points within {worst:.5f} mm of the hub's decoding")
        return 0



if __name__ == "__main__":
    sys.exit(main())
