#!/usr/bin/env python3
"""The floor step on the console's Calibration page, in a real browser: the still L-frame scene of
tests/wand/world_live_test.py (serve's calibration in a tilted wand world, 4 real mocap-node
processes replaying rendered frames), Debian's Chromium headless through selenium. The operator
picks "y up" and presses "Set the floor"; the page shows the four markers with their errors, the
tilt removed and the file saved, and the camera table moves to the truth's positions. (The
refusals are the API test's cases.) A screenshot goes to WORK_DIR/screenshots/calibration_floor.png.

usage: world_page_test.py BIN_DIR WORK_DIR

Every wait is bounded; every process the test starts is killed at the end."""

import json
import math
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "serve"))
sys.path.insert(0, os.path.join(HERE, "..", "wand"))
sys.path.insert(0, HERE)
from live_rig import Rig, wait_for  # noqa: E402
from world_live_test import CAMERAS, RATE, TILT_DEG, lframe_scene  # noqa: E402
from web_test import browser, log_in  # noqa: E402

from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import Select  # noqa: E402

BIN = WORK = None


def centres(calibration):
    """Camera id -> centre in the world (-R^T t)."""
    out = {}
    for c in calibration["cameras"]:
        r, t = c["rotation"], c["translation"]
        out[c["id"]] = [-sum(r[k][i] * t[k] for k in range(3)) for i in range(3)]
    return out


class WorldPageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with_truth = lframe_scene(BIN, WORK)
        with open(with_truth) as f:
            cls.truth = centres(json.load(f))
        cls.rig = Rig(BIN, WORK, RATE)
        cls.page = None
        try:
            cls.rig.start(CAMERAS)
            cls.page = browser()
            log_in(cls.page, f"http://{cls.rig.api}/", cls.rig.token)
        except BaseException:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        if cls.page:
            cls.page.quit()
        cls.rig.stop()

    def js(self, script):
        return self.page.execute_script(script)

    def table_centres(self):
        """Camera id -> the position the camera table shows (whole mm)."""
        rows = self.page.find_elements(By.CSS_SELECTOR, "#calibration-table tbody tr")
        return {int(r.get_attribute("data-camera-id")): [float(v) for v in r.find_elements(By.TAG_NAME, "td")[5].text.split(",")]
                for r in rows}

    def test_the_floor_step_in_the_page(self):
        self.page.get(f"http://{self.rig.api}/#calibration")
        wait_for("the calibration page", lambda: self.js("return window.mocapConsole && mocapConsole.currentPage()")
                 == "calibration")
        wait_for("a row per camera", lambda: len(self.table_centres()) == CAMERAS)
        before = self.table_centres()
        self.assertGreater(max(math.dist(before[i], self.truth[i]) for i in before), 100.0)
        Select(self.page.find_element(By.ID, "world-up")).select_by_value("y")
        self.page.find_element(By.ID, "world-set").click()
        state = lambda: self.js("return document.getElementById('world-state').dataset.state")  # noqa: E731
        wait_for("the floor step to answer", lambda: state() in ("done", "refused"))
        text = self.page.find_element(By.ID, "world-state").text
        self.assertEqual(state(), "done", text)
        self.assertIn("L-frame found in", text)
        self.assertIn("4 markers", text)
        tilt = float(text.split("tilt removed ")[1].split("°")[0])
        self.assertAlmostEqual(tilt, TILT_DEG, delta=0.1)
        self.assertIn(os.path.join(WORK, "frames", "calibration.json"), text)
        errors = [float(r.find_elements(By.TAG_NAME, "td")[3].text)
                  for r in self.page.find_elements(By.CSS_SELECTOR, "#world-markers tbody tr")]
        self.assertEqual(len(errors), 4)
        self.assertLess(max(errors), 1.0)
        # The camera table follows the new calibration: the truth's positions (the table rounds to mm).
        wait_for("the camera table in the new world", lambda: max(
            math.dist(p, self.truth[i]) for i, p in self.table_centres().items()) < 2.5)
        shots = os.path.join(WORK, "screenshots")
        os.makedirs(shots, exist_ok=True)
        self.page.save_screenshot(os.path.join(shots, "calibration_floor.png"))
        print(f"floor step in the page: {text}", file=sys.stderr)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
