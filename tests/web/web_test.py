#!/usr/bin/env python3
"""The web console in a real browser: `mocap-hub serve` with four real `mocap-node` processes on
loopback (tests/serve/live_rig.py), Debian's Chromium headless driven through selenium and
Debian's chromedriver. Asserts on the page what an operator relies on: the node rows are the
running nodes, a threshold typed into the page reaches the node's status, the camera views show
blobs and the auto-mask's regions, the 3D view draws every marker of the frame it shows, a
live wanding started in the page fills each camera's coverage map and ends in the report's plots, a
captured and reconstructed session plays (and scrubs) with the TRC's markers, its files download
byte for byte, a second browser sees the same, and the page reconnects by itself after serve
restarts. Prints the figures (page load, frame rates, traffic per client) and saves screenshots
in WORK_DIR/screenshots; figures are reported, never asserted.

usage: web_test.py BIN_DIR WORK_DIR

Every wait is bounded; every process the test starts is killed at the end."""

import collections
import json
import os
import shutil
import socket
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import STUCK_S, Rig, auth_header, http, render_scene, wait_for, raw_request  # noqa: E402

from selenium import webdriver  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import Select  # noqa: E402
from selenium.common.exceptions import NoSuchElementException, StaleElementReferenceException  # noqa: E402

BIN = WORK = None
CAMERAS = 4
MARKERS = 12
RATE = 100
REFLECTIONS = 6
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"


def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    # No GPU here: WebGL runs on SwiftShader, Chromium's software renderer.
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--enable-unsafe-swiftshader",
                "--window-size=1400,860", "--disable-extensions", "--no-first-run"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def displayed(driver, element_id):
    """The element when it is on the page and shown, else None."""
    try:
        element = driver.find_element(By.ID, element_id)
    except NoSuchElementException:
        return None
    return element if element.is_displayed() else None


def log_in(driver, url, token, wrong_first=False):
    """The console's login: the page shows its form on the hub's 401, the token typed in gets
    the session cookie; the browser's log (the 401s) is drained afterwards."""
    driver.get(url)
    field = wait_for("the login form", lambda: displayed(driver, "login-token"))
    if wrong_first:
        field.send_keys("0" * 64)
        driver.find_element(By.ID, "login-submit").click()
        wait_for("the refusal", lambda: driver.find_element(By.ID, "login-error").text)
        field.clear()
    field.send_keys(token)
    driver.find_element(By.ID, "login-submit").click()
    wait_for("the form to go", lambda: displayed(driver, "login") is None)
    cookies = {c["name"]: c for c in driver.get_cookies()}
    assert cookies["mocap_session"]["httpOnly"] and cookies["mocap_session"]["sameSite"] == "Strict", cookies
    driver.get_log("browser")


def trc_markers_per_frame(path):
    """Frame# -> markers present in that row of a TRC (gaps are empty cells)."""
    with open(path) as f:
        lines = f.read().split("\n")
    count = len([n for n in lines[3].split("\t")[2:] if n])
    present = {}
    for line in lines[5:]:
        if not line.strip():
            continue
        cells = line.split("\t")
        present[int(cells[0])] = sum(1 for m in range(count) if cells[2 + 3 * m].strip())
    return present


class WebConsoleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
        cls.shots = os.path.join(WORK, "screenshots")
        os.makedirs(cls.shots)
        render_scene(BIN, WORK, CAMERAS, RATE, markers=MARKERS, reflections=REFLECTIONS)
        cls.rig = Rig(BIN, WORK, RATE)
        cls.drivers = []
        try:
            cls.rig.start(CAMERAS)
            cls.url = f"http://{cls.rig.api}/"
            cls.page = browser()
            cls.drivers.append(cls.page)
            log_in(cls.page, cls.url, cls.rig.token, wrong_first=True)
        except BaseException:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        for driver in cls.drivers:
            driver.quit()
        cls.rig.stop()

    def js(self, script, driver=None):
        return (driver or self.page).execute_script(script)

    def go(self, page):
        self.page.get(self.url + "#" + page)
        wait_for(f"the {page} page",
                 lambda: self.js("return window.mocapConsole && mocapConsole.currentPage()") == page)

    def hub_state(self, driver):
        return self.js("return document.getElementById('hub-state').textContent", driver)

    def shot(self, name):
        self.page.save_screenshot(os.path.join(self.shots, name + ".png"))

    def traffic_per_second(self, seconds):
        """Bytes the page received per second (HTTP bodies + WebSocket messages) over `seconds`."""
        before = self.js("return {...mocapConsole.traffic, t: performance.now()}")
        time.sleep(seconds)
        after = self.js("return {...mocapConsole.traffic, t: performance.now()}")
        dt = (after["t"] - before["t"]) / 1000
        return ((after["httpBytes"] - before["httpBytes"]) / dt, (after["wsBytes"] - before["wsBytes"]) / dt,
                (after["requests"] - before["requests"]) / dt)

    def test_1_page_loads_and_its_rows_are_the_running_nodes(self):
        start = time.monotonic()
        self.page.get(self.url)
        rows = wait_for("a row per node", lambda: self.page.find_elements(By.CSS_SELECTOR, "#nodes-table tbody tr")
                        if len(self.page.find_elements(By.CSS_SELECTOR, "#nodes-table tbody tr")) == CAMERAS
                        else None)
        rows_s = time.monotonic() - start
        load_ms = self.js("const n = performance.getEntriesByType('navigation')[0]; "
                          "return n.loadEventEnd - n.startTime")
        nodes = self.rig.nodes_json()
        self.assertEqual({int(r.get_attribute("data-node-id")) for r in rows}, set(nodes))
        for row in rows:
            node = nodes[int(row.get_attribute("data-node-id"))]
            wait_for("the row's state",
                     lambda: row.find_element(By.CSS_SELECTOR, "[data-field=state]").text == node["state"])
            self.assertEqual(row.find_element(By.CSS_SELECTOR, "[data-field=address]").text, node["address"])
            # Replayed frames have no exposure or gain: the row says so instead of showing a 0.
            self.assertTrue(node["exposure_fixed"], node)
            self.assertIsNone(node["exposure_us"], node)
            exposure = row.find_element(By.CSS_SELECTOR, "input[data-field=exposure_us]")
            wait_for("the exposure shown as fixed",
                     lambda: exposure.get_attribute("placeholder") == "fixed (recording)" or None)
            self.assertFalse(exposure.is_enabled())
            self.assertEqual(exposure.get_attribute("value"), "")
        errors = [e for e in self.page.get_log("browser") if e["level"] == "SEVERE"]
        self.assertEqual(errors, [], "the console logs no errors")
        print(f"page load on loopback: load event {load_ms:.0f} ms, node rows shown {rows_s * 1000:.0f} ms "
              f"after the request")

    def test_2_threshold_typed_in_the_page_reaches_the_node(self):
        self.go("nodes")
        row = wait_for("node 3's row", lambda: self.page.find_elements(By.CSS_SELECTOR, "tr[data-node-id='3']"))[0]
        field = row.find_element(By.CSS_SELECTOR, "input[data-field=threshold]")
        field.clear()
        field.send_keys("47")
        row.find_element(By.CSS_SELECTOR, "button[data-action=apply]").click()
        result = lambda: row.find_element(By.CSS_SELECTOR, "[data-field=result]").text  # noqa: E731
        try:
            wait_for("the node's answer in the row", lambda: result() == "applied")
        except AssertionError as error:
            raise AssertionError(f"{error}; the row says {result()!r}, node 3: {self.rig.nodes_json()[3]}") from None
        wait_for("node 3's status to say threshold 47", lambda: self.rig.nodes_json()[3]["threshold"] == 47)
        self.assertEqual(self.rig.nodes_json()[1]["threshold"], 32)
        self.rig.hub("node", "3", "set", "threshold=32")
        wait_for("the page to show the node's threshold again",
                 lambda: field.get_attribute("value") == "32", timeout=5)

    def test_3_camera_views_show_blobs_and_auto_masks(self):
        self.go("nodes")
        views = wait_for("a view per camera with blobs", lambda: [
            v for v in self.page.find_elements(By.CSS_SELECTOR, ".camera-view")
            if int(v.get_attribute("data-blobs") or 0) > 0] if len(
            self.page.find_elements(By.CSS_SELECTOR, ".camera-view[data-blobs]")) == CAMERAS else None)
        self.assertEqual(len(views), CAMERAS)
        http_bps, ws_bps, requests = self.traffic_per_second(4)
        print(f"traffic, Nodes page: {http_bps / 1000:.1f} kB/s HTTP ({requests:.1f} requests/s), "
              f"{ws_bps / 1000:.1f} kB/s WebSocket")
        self.page.find_element(By.ID, "mask-frames").clear()
        self.page.find_element(By.ID, "mask-frames").send_keys("50")
        self.page.find_element(By.ID, "auto-mask").click()
        wait_for("the auto-mask's answer", lambda: "masked from" in self.page.find_element(By.ID, "mask-message").text)
        # Each view draws the regions the installation's mask file keeps for its camera.
        with open(os.path.join(WORK, "masks.json")) as f:
            regions = {c["camera_id"]: len(c["regions"]) for c in json.load(f)["cameras"]}
        self.assertGreater(sum(regions.values()), 0, "the rendered reflections were masked")
        wait_for("each camera's masked regions drawn in its view", lambda: all(
            int(v.get_attribute("data-mask-regions") or 0) == regions.get(int(v.get_attribute("data-camera-id")), 0)
            for v in self.page.find_elements(By.CSS_SELECTOR, ".camera-view")))
        # A preview on demand (camera 1, thresholded) becomes the view's background.
        view = self.page.find_element(By.CSS_SELECTOR, ".camera-view[data-camera-id='1']")
        view.find_element(By.XPATH, ".//button[text()='Raw image']").click()
        wait_for("the preview", lambda: view.find_element(By.CSS_SELECTOR, ".message").text == "raw preview")
        time.sleep(0.3)
        self.shot("nodes")

    def test_4_live_view_draws_every_marker_of_its_frame(self):
        self.go("live")
        self.page.find_element(By.ID, "show-ids").click()
        wait_for("markers drawn", lambda: self.js("return mocapConsole.pages.live.scene.drawnMarkers") > 0)
        samples = []
        for _ in range(30):
            drawn, points = self.js("const s = mocapConsole.pages.live.scene; "
                                    "return [s.drawnMarkers, s.drawnFramePoints]")
            self.assertEqual(drawn, points, "the view draws every point of the frame it shows")
            samples.append(drawn)
            time.sleep(0.05)
        # Rigid bodies are drawn as axes at their pose (a frame with one body, handed to the page
        # as the WebSocket would: serve here runs without --bodies).
        visible, position = self.js(
            "const p = mocapConsole.pages.live; p.onFrame({frame: 0, points: [], "
            "bodies: [[1, 1, 0, 100, 200, 300, 0, 0, 0.7071068, 0.7071068, 0.2, 4],"
            "         [2, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0]]});"
            "const a = p.scene.bodyAxes; return [a.map((x) => x.visible), a[0].position.toArray()];")
        self.assertEqual(visible, [True, False], "a tracked body is drawn, one neither tracked nor predicted is not")
        self.assertEqual(position, [100, 200, 300])
        most = collections.Counter(samples).most_common(1)[0][0]
        self.assertEqual(most, MARKERS, f"the rendered subject has {MARKERS} markers: {samples}")
        time.sleep(1.2)
        received, drawn_fps = self.js("const p = mocapConsole.pages.live; return [p.rate.fps, p.scene.fps]")
        frames_before = self.js("return mocapConsole.pages.live.socket.framesReceived")
        http_bps, ws_bps, requests = self.traffic_per_second(4)
        frames = (self.js("return mocapConsole.pages.live.socket.framesReceived") - frames_before) / 4
        print(f"live message size: {ws_bps / frames:.0f} bytes per frame of about {MARKERS} points")
        print(f"live 3D, {MARKERS} markers at {RATE} Hz: {received:.0f} frames/s received (max_fps=60), "
              f"{drawn_fps:.0f} fps drawn in headless Chromium (SwiftShader, 1400x860)")
        print(f"traffic, Live 3D page: {ws_bps / 1000:.1f} kB/s WebSocket + {http_bps / 1000:.1f} kB/s HTTP "
              f"({requests:.1f} requests/s)")
        self.shot("live")

    def test_5_a_view_of_150_markers(self):
        self.go("live")
        wait_for("live frames", lambda: self.js("return mocapConsole.pages.live.frames") > 0)
        if not self.page.find_element(By.ID, "show-ids").is_selected():
            self.page.find_element(By.ID, "show-ids").click()
        result = self.page.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "mocapConsole.pages.live.benchmark(150, 4000).then(done);")
        self.assertEqual(result["drawn"], 150)
        self.assertGreater(result["frames"], 0)
        software = self.js("return mocapConsole.softwareGl")
        print(f"live 3D with 150 markers (ids shown): {result['fps']:.1f} fps drawn over {result['seconds']:.1f} s "
              f"(headless Chromium, {'software WebGL (SwiftShader), no antialiasing' if software else 'GPU'}, "
              f"1400x860, on the 2-core machine beside serve and 4 nodes)")

    def test_6_calibration_page_shows_every_camera(self):
        self.go("calibration")
        rows = wait_for("a row per camera", lambda: self.page.find_elements(
            By.CSS_SELECTOR, "#calibration-table tbody tr") if len(self.page.find_elements(
                By.CSS_SELECTOR, "#calibration-table tbody tr")) == CAMERAS else None)
        self.assertEqual({int(r.get_attribute("data-camera-id")) for r in rows}, set(range(1, CAMERAS + 1)))
        wait_for("node states in the table", lambda: all(
            r.find_elements(By.TAG_NAME, "td")[-1].text == "running"
            for r in self.page.find_elements(By.CSS_SELECTOR, "#calibration-table tbody tr")))
        time.sleep(0.3)
        self.shot("calibration")

    def click_fresh(self, selector):
        try:
            self.page.find_element(By.CSS_SELECTOR, selector).click()
            return True
        except (StaleElementReferenceException, NoSuchElementException):
            return False

    def swap_node_frames(self, frames):
        """Every node replays `frames` from now on (the same rig, another scene)."""
        for node_id, process in list(self.rig.nodes.items()):
            process.kill()
            process.wait()
        self.rig.frames = frames
        for node_id in range(1, CAMERAS + 1):
            self.rig.start_node(node_id)
        wait_for("every node running again", lambda: len([n for n in self.rig.nodes_json().values()
                                                          if n["state"] == "running"]) == CAMERAS, timeout=15)

    def test_6_wanding_a_single_marker_in_the_page(self):
        # The nodes replay one marker waved through the same rig, then a bar of two markers 500 mm
        # apart for the scale.
        wave = os.path.join(WORK, "wave.trc")
        self.rig.hub("sim", "wand", "--rig", os.path.join(WORK, "rig.json"), "-o", os.path.join(WORK, "wave_projected"),
                     "--motion", wave, "--frames", "3000", "--single-marker-frames", "2400", "--rate", str(RATE),
                     "--wand-length", "500", "--seed", "7")
        self.rig.hub("sim", "render", "--motion", wave, "--rig", os.path.join(WORK, "rig.json"), "-o",
                     os.path.join(WORK, "wave_frames"))
        walk_frames = self.rig.frames
        self.swap_node_frames(os.path.join(WORK, "wave_frames"))
        try:
            self.go("calibration")
            Select(self.page.find_element(By.ID, "wand-mode")).select_by_value("single-marker")
            self.assertEqual(self.page.find_element(By.ID, "wand-length").find_element(
                By.XPATH, "preceding-sibling::label[1]").text, "scale bar mm")
            for field, value in (("wand-name", "web_marker"), ("wand-min-samples", "250"), ("wand-coverage", "30"),
                                 ("wand-timeout", "120")):
                box = self.page.find_element(By.ID, field)
                box.clear()
                box.send_keys(value)
            self.page.find_element(By.ID, "wand-start").click()
            state = lambda: self.js("return document.getElementById('wanding-state').dataset.state")  # noqa: E731
            text = lambda: self.js("return document.getElementById('wanding-state').textContent")  # noqa: E731
            wait_for("the wanding to start", lambda: state() == "collecting")
            wait_for("the scale bar's count on the page", lambda: "scale bar in" in text())
            self.assertIn("single marker", text())
            wait_for("the solve", lambda: state() in ("solved", "failed"), timeout=150)
            self.assertEqual(state(), "solved", text())
            self.assertIn("scale from", text())
            rows = self.page.find_elements(By.CSS_SELECTOR, "#wand-report table.single-marker-report tr[data-camera-id]")
            self.assertEqual(len(rows), CAMERAS)
            self.shot("calibration_single_marker")
            # The solved calibration against the truth (rigid alignment; the scale from the bar).
            solved = os.path.join(WORK, "sessions", "web_marker", "wand_calibration.json")
            evaluation = json.loads(self.rig.hub("eval-calibration", "--truth", os.path.join(WORK, "rig.json"),
                                                 "--result", solved, "--json").stdout)
            self.assertLess(evaluation["centre_max_mm"], 1.0, evaluation)
            self.assertLess(evaluation["rotation_max_deg"], 0.05, evaluation)
            self.assertLess(abs(evaluation["scale_error"]), 0.001, evaluation)
            print(f"single-marker wanding in the page: centres max {evaluation['centre_max_mm']:.3f} mm, rotations max "
                  f"{evaluation['rotation_max_deg']:.4f} deg, scale error {100 * evaluation['scale_error']:+.4f} %",
                  file=sys.stderr)
        finally:
            http(self.rig.api_port, "POST", "/api/calibration/wand/stop", b'{"solve": false}')
            Select(self.page.find_element(By.ID, "wand-mode")).select_by_value("wand")
            self.swap_node_frames(walk_frames)

    def test_6_wanding_coverage_then_the_report(self):
        # The nodes replay a wand waved through the same rig.
        wand = os.path.join(WORK, "wand.trc")
        self.rig.hub("sim", "wand", "--rig", os.path.join(WORK, "rig.json"), "-o", os.path.join(WORK, "wand_projected"),
                     "--motion", wand, "--frames", "3000", "--rate", str(RATE), "--wand-length", "500", "--seed", "5")
        self.rig.hub("sim", "render", "--motion", wand, "--rig", os.path.join(WORK, "rig.json"), "-o",
                     os.path.join(WORK, "wand_frames"))
        walk_frames = self.rig.frames
        self.swap_node_frames(os.path.join(WORK, "wand_frames"))
        try:
            self.go("calibration")
            Select(self.page.find_element(By.ID, "wand-mode")).select_by_value("wand")
            for field, value in (("wand-name", "web_wand"), ("wand-min-samples", "250"), ("wand-coverage", "35"),
                                 ("wand-timeout", "120")):
                box = self.page.find_element(By.ID, field)
                box.clear()
                box.send_keys(value)
            self.page.find_element(By.ID, "wand-start").click()
            # The cards are drawn again at every poll: read them in one go.
            state = lambda: self.js("return document.getElementById('wanding-state').dataset.state")  # noqa: E731
            cameras = lambda: self.js("""return [...document.querySelectorAll('#wanding-cameras figure')].map(f => ({
                id: Number(f.dataset.cameraId), samples: Number(f.dataset.samples), enough: f.classList.contains('enough'),
                covered: f.querySelectorAll('rect.covered').length, cells: f.querySelectorAll('rect.cell').length}))""")  # noqa: E731
            wait_for("the wanding to start", lambda: state() == "collecting")
            # Each camera's card fills as the wand is seen: samples grow, cells turn green.
            wait_for("samples in every camera", lambda: len(cameras()) == CAMERAS and all(
                c["samples"] > 60 for c in cameras()), timeout=30)
            self.assertEqual({c["id"] for c in cameras()}, set(range(1, CAMERAS + 1)))
            self.shot("calibration_wanding")
            wait_for("the solve", lambda: state() in ("solved", "failed"), timeout=120)
            state_text = self.js("return document.getElementById('wanding-state').textContent")
            self.assertEqual(state(), "solved", state_text)
            self.assertIn("every camera has enough", state_text)
            for c in cameras():
                self.assertTrue(c["enough"], c)
                self.assertGreaterEqual(c["samples"], 250)
                self.assertGreaterEqual(c["covered"], 0.35 * c["cells"])
            # The report's plots, drawn from the session's wand_figures.json.
            report = wait_for("the report's plots", lambda: self.page.find_elements(
                By.CSS_SELECTOR, "#wand-report figure.plot") or None, timeout=10)
            self.assertEqual({f.get_attribute("data-plot") for f in report},
                             {"residuals", "wand-length", "layout-top", "layout-side"})
            figures = json.loads(http(self.rig.api_port, "GET", "/api/sessions/web_wand/files/wand_figures.json")[1])
            rows = self.page.find_elements(By.CSS_SELECTOR, "#wand-report table.report-cameras tbody tr")
            self.assertEqual([r.find_element(By.CSS_SELECTOR, "td.rating").text for r in rows],
                             [c["rating"] for c in figures["cameras"]])
            residual_bars = self.page.find_elements(By.CSS_SELECTOR, "#wand-report figure[data-plot=residuals] rect.bar")
            self.assertEqual(len(residual_bars), CAMERAS)
            layout = self.page.find_elements(By.CSS_SELECTOR, "#wand-report figure[data-plot=layout-top] circle.camera")
            self.assertEqual(len(layout), CAMERAS)
            histogram = self.page.find_elements(By.CSS_SELECTOR, "#wand-report figure[data-plot=wand-length] rect.bar")
            self.assertEqual(len(histogram), len(figures["wand_length_histogram"]["counts"]))
            maps = self.page.find_elements(By.CSS_SELECTOR, "#wand-report .coverage-maps svg")
            self.assertEqual(len(maps), CAMERAS)
            self.js("document.getElementById('wand-report').scrollIntoView()")
            time.sleep(0.3)
            self.shot("calibration_report")
            self.js("window.scrollTo(0, 0)")
            # The stand-alone report page serve wrote beside the session (as calibrate wand --report
            # writes it) draws the same plots with nothing loaded from anywhere.
            self.page.get("file://" + os.path.join(WORK, "sessions", "web_wand", "wand_report.html"))
            plots = wait_for("the stand-alone report's plots", lambda: self.page.find_elements(
                By.CSS_SELECTOR, "figure.plot") or None)
            self.assertEqual(len(plots), 4)
            self.assertEqual(len(self.page.find_elements(By.CSS_SELECTOR, "table.report-cameras tbody tr")), CAMERAS)
            self.assertEqual(len(self.page.find_elements(By.CSS_SELECTOR, ".coverage-maps svg")), CAMERAS)
            self.page.set_window_size(1400, 1700)
            self.shot("wand_report")
            self.page.set_window_size(1400, 860)
        finally:
            # A wanding left running (a failure above) would hold the capture the next test needs.
            http(self.rig.api_port, "POST", "/api/calibration/wand/stop", b'{"solve": false}')
            self.swap_node_frames(walk_frames)

    def test_7_a_captured_session_plays_and_downloads(self):
        self.go("sessions")
        name = self.page.find_element(By.ID, "capture-name")
        name.clear()
        name.send_keys("web_take")
        self.page.find_element(By.ID, "capture-start").click()
        wait_for("the capture", lambda: "capturing web_take" in self.page.find_element(By.ID, "capture-state").text)
        time.sleep(2.0)
        self.page.find_element(By.ID, "capture-stop").click()
        wait_for("the capture's summary", lambda: self.page.find_element(By.ID, "capture-message").text.startswith(
            "web_take: "))
        self.assertEqual(self.page.find_element(By.ID, "capture-state").text, "not capturing")
        session = os.path.join(WORK, "sessions", "web_take")
        trc = os.path.join(session, "markers.trc")
        calibration = os.path.join(WORK, "frames", "calibration.json")
        self.rig.hub("reconstruct", session, "--calibration", calibration, "-o", trc)
        self.rig.hub("reconstruct", session, "--calibration", calibration, "-o", os.path.join(session, "markers.c3d"))
        # The list is read when the page is shown: show it again.
        self.go("nodes")
        self.go("sessions")
        row = wait_for("the session's row",
                       lambda: self.page.find_elements(By.CSS_SELECTOR, "tr[data-session='web_take']"))[0]
        self.assertEqual(row.find_elements(By.TAG_NAME, "td")[1].text, "complete")
        # The list may be drawn again under the click (the page refreshes it on its own): find the
        # button afresh until a click lands.
        wait_for("a click on the session's files", lambda: self.click_fresh(
            "tr[data-session='web_take'] button[data-action=files]"))
        files = wait_for("its files",
                         lambda: self.page.find_elements(By.CSS_SELECTOR, "#session-details tr[data-file]"))
        names = {f.get_attribute("data-file") for f in files}
        self.assertTrue({"markers.trc", "markers.c3d", "live_points.tsv", "session.json"} <= names, names)
        # The download links give the files byte for byte.
        for file in ("markers.trc", "markers.c3d"):
            link = self.page.find_element(By.CSS_SELECTOR, f"#session-details tr[data-file='{file}'] a")
            self.assertEqual(link.get_attribute("download"), file)
            path = link.get_attribute("href").split(self.rig.api, 1)[1]
            status, body = http(self.rig.api_port, "GET", path)
            self.assertEqual(status, 200)
            with open(os.path.join(session, file), "rb") as f:
                self.assertEqual(body, f.read(), file)
        # Play the TRC: frames advance, and each frame shown draws the TRC's markers of that row.
        present = trc_markers_per_frame(trc)
        # At a quarter of the speed the 2 s take plays for 8 s: it has not ended (and paused by
        # itself) when the play button below pauses it, however slow the machine is.
        self.js("const s = document.getElementById('speed'); s.value = '0.25'; s.dispatchEvent(new Event('change'));")
        self.page.find_element(By.CSS_SELECTOR,
                               "#session-details tr[data-file='markers.trc'] button[data-action=play]").click()
        wait_for("playback", lambda: self.js("return mocapConsole.pages.sessions.player.playing"))
        time.sleep(0.15)  # a render of the new recording
        seen = set()
        end = time.monotonic() + 3
        while time.monotonic() < end and len(seen) < 5:
            frame, drawn, number = self.js(
                "const p = mocapConsole.pages.sessions; const r = p.player.recording;"
                "return [p.player.index, p.scene.drawnMarkers, r.frameNumbers[p.player.index]]")
            self.assertEqual(drawn, present[number], f"TRC frame {number}")
            seen.add(frame)
            time.sleep(0.1)
        self.assertGreaterEqual(len(seen), 3, "the frame shown advances while playing")
        self.page.find_element(By.ID, "play").click()  # pause
        self.assertFalse(self.js("return mocapConsole.pages.sessions.player.playing"))
        # Scrub to the middle: the view shows that frame and stays there while paused.
        frames = len(present)
        self.js(f"const s = document.getElementById('timeline'); s.value = {frames // 2};"
                "s.dispatchEvent(new Event('input'));")
        time.sleep(0.2)  # a render or two
        index, drawn, number = self.js("const p = mocapConsole.pages.sessions; return [p.player.index, "
                                       "p.scene.drawnMarkers, p.player.recording.frameNumbers[p.player.index]]")
        self.assertEqual(index, frames // 2)
        self.assertEqual(drawn, present[number])
        time.sleep(0.3)
        self.assertEqual(self.js("return mocapConsole.pages.sessions.player.index"), frames // 2)
        # Twice the speed: the player's recording time runs at twice its own clock's (the page's
        # performance.now(), so however busy the machine is), and the frames follow.
        self.js("const s = document.getElementById('timeline'); s.value = 0; s.dispatchEvent(new Event('input'));")
        self.js("const s = document.getElementById('speed'); s.value = '2'; s.dispatchEvent(new Event('change'));")
        clock = "const p = mocapConsole.pages.sessions.player; return [p.time, p.last, p.index]"
        self.page.find_element(By.ID, "play").click()
        start_time, start_last, start_index = self.js(clock)
        wait_for("the player to move on", lambda: self.js(clock)[2] > start_index + RATE // 10, timeout=STUCK_S)
        end_time, end_last, end_index = self.js(clock)
        wall = (end_last - start_last) / 1000
        print(f"\nplayback at 2x: {end_index - start_index} frames over {wall:.3f} s of the page's clock, "
              f"{end_time - start_time:.3f} s of the recording", file=sys.stderr)
        self.assertAlmostEqual((end_time - start_time) / wall, 2.0, places=6)
        self.page.find_element(By.ID, "play").click()
        # live_points.tsv (what serve published) plays too: each frame shown draws its points.
        published = collections.Counter()
        with open(os.path.join(session, "live_points.tsv")) as f:
            for line in f:
                if line[:1].isdigit():
                    published[int(line.split("\t")[0])] += 1
        self.page.find_element(By.CSS_SELECTOR,
                               "#session-details tr[data-file='live_points.tsv'] button[data-action=play]").click()
        wait_for("the live points", lambda: self.js(
            "return mocapConsole.pages.sessions.player.recording.markers.length === 0 && "
            "mocapConsole.pages.sessions.player.playing"))
        time.sleep(0.15)
        for _ in range(5):
            drawn, number = self.js("const p = mocapConsole.pages.sessions; "
                                    "return [p.scene.drawnMarkers, p.player.recording.frameNumbers[p.player.index]]")
            self.assertEqual(drawn, published[number], f"published frame {number}")
            time.sleep(0.1)
        self.page.find_element(By.CSS_SELECTOR,
                               "#session-details tr[data-file='markers.trc'] button[data-action=play]").click()
        wait_for("the TRC again",
                 lambda: self.js("return mocapConsole.pages.sessions.player.recording.markers.length") > 0)
        time.sleep(0.6)  # into the take (it lasts 1.1 s at 2x), then paused for the picture
        self.page.find_element(By.ID, "play").click()
        self.shot("sessions")

    def test_7b_a_session_processed_from_the_page(self):
        # The take test_7 captured, processed by a recipe from its details.
        self.go("nodes")
        self.go("sessions")
        wait_for("a click on the session's files", lambda: self.click_fresh(
            "tr[data-session='web_take'] button[data-action=files]"))
        wait_for("the processing form", lambda: self.page.find_elements(By.ID, "process-start"))
        name = self.page.find_element(By.ID, "process-name")
        name.clear()
        name.send_keys("console")
        self.page.find_element(By.ID, "process-c3d").click()
        self.page.find_element(By.ID, "process-start").click()
        # Read in the page in one go: the rows are drawn again each second while a job runs.
        state, text = wait_for("the job to finish", lambda: self.js(
            "const r = [...document.querySelectorAll('#processing-jobs tr[data-state]')]"
            ".find((r) => r.dataset.state === 'done' || r.dataset.state === 'failed');"
            "return r ? [r.dataset.state, r.textContent] : null"), timeout=STUCK_S)
        self.assertEqual(state, "done", text)
        self.assertIn("100 %", text)
        # Its results appear in the details (shown again when the job ended), downloadable as written.
        links = dict(wait_for("the results", lambda: self.js(
            "return [...document.querySelectorAll(\"#processed-results div[data-recipe='console'] a\")]"
            ".map((a) => [a.getAttribute('download'), a.getAttribute('href')])")))
        self.assertTrue({"markers.trc", "markers.c3d", "process.json"} <= set(links), links)
        results = os.path.join(WORK, "sessions", "web_take", "processed", "console")
        for file in ("markers.trc", "markers.c3d"):
            status, body = http(self.rig.api_port, "GET", links[file])
            self.assertEqual(status, 200)
            with open(os.path.join(results, file), "rb") as f:
                self.assertEqual(body, f.read(), file)
        # It plays like the session's own TRC.
        self.page.find_element(By.CSS_SELECTOR, "#processed-results div[data-recipe='console'] "
                                                "button[data-action=play-result]").click()
        wait_for("the processed TRC playing", lambda: "markers.trc" in self.page.find_element(By.ID, "play-title").text
                 and self.js("return mocapConsole.pages.sessions.player.recording.markers.length") > 0)
        # The player sits above the details: brought to the middle of the window, not under the header.
        play = self.page.find_element(By.ID, "play")
        self.page.execute_script("arguments[0].scrollIntoView({block: 'center'})", play)
        play.click()
        # The same recipe again is refused in the page: the results are kept unless replaced.
        self.page.find_element(By.ID, "process-start").click()
        wait_for("the refusal", lambda: "overwrite" in self.page.find_element(By.ID, "process-message").text)

    def test_7c_a_session_annotated_renamed_and_deleted_in_the_page(self):
        status, _ = http(self.rig.api_port, "POST", "/api/capture/start", b'{"name": "web_chores"}')
        self.assertEqual(status, 200)
        time.sleep(0.5)
        status, _ = http(self.rig.api_port, "POST", "/api/capture/stop", b"{}")
        self.assertEqual(status, 200)
        sessions = os.path.join(WORK, "sessions")
        log_bytes = os.path.getsize(os.path.join(sessions, "web_chores", "raw.mlog"))
        self.go("nodes")
        self.go("sessions")
        wait_for("a click on the session's files", lambda: self.click_fresh(
            "tr[data-session='web_chores'] button[data-action=files]"))
        message = lambda: self.page.find_element(By.ID, "session-admin-message").text  # noqa: E731
        notes = wait_for("the notes field", lambda: self.page.find_elements(By.ID, "session-notes"))[0]
        notes.send_keys("subject 3\nleft knee brace")
        self.page.find_element(By.ID, "session-notes-save").click()
        wait_for("the notes saved", lambda: message() == "notes: done" or None)
        with open(os.path.join(sessions, "web_chores", "notes.txt")) as f:
            self.assertEqual(f.read(), "subject 3\nleft knee brace")
        wait_for("the notes in the list", lambda: self.js(
            "const r = document.querySelector(\"tr[data-session='web_chores'] td.notes\");"
            "return r && r.textContent === 'subject 3'") or None)
        # A name a session cannot have is refused with the reason; a good one renames it.
        new_name = self.page.find_element(By.ID, "session-new-name")
        new_name.clear()
        new_name.send_keys("../escape")
        self.page.find_element(By.ID, "session-rename").click()
        wait_for("the refusal", lambda: "cannot name a session" in message() or None)
        new_name = self.page.find_element(By.ID, "session-new-name")
        new_name.clear()
        new_name.send_keys("web_chores_s3")
        self.page.find_element(By.ID, "session-rename").click()
        wait_for("the details under the new name", lambda: self.js(
            "const h = document.querySelector('#session-details h3'); return h && h.textContent") ==
            "web_chores_s3 (complete)" or None)
        self.assertFalse(os.path.exists(os.path.join(sessions, "web_chores")))
        # Delete asks once more, then moves the take aside whole.
        self.page.find_element(By.ID, "session-delete").click()
        confirm = self.page.find_element(By.ID, "session-delete-confirm")
        self.assertTrue(confirm.is_displayed())
        confirm.click()
        wait_for("the deletion", lambda: self.page.find_elements(By.ID, "session-deleted"))
        moved = [d for d in os.listdir(os.path.join(sessions, ".deleted")) if d.startswith("web_chores_s3.")]
        self.assertEqual(len(moved), 1, moved)
        self.assertEqual(os.path.getsize(os.path.join(sessions, ".deleted", moved[0], "raw.mlog")), log_bytes)
        wait_for("the row gone", lambda: not self.page.find_elements(
            By.CSS_SELECTOR, "tr[data-session='web_chores_s3']"))

    def test_8_a_second_browser_and_a_serve_restart(self):
        other = browser()
        self.drivers.append(other)
        log_in(other, self.url, self.rig.token)
        other.get(self.url + "#nodes")
        wait_for("the second browser's node rows", lambda: len(other.find_elements(
            By.CSS_SELECTOR, "#nodes-table tbody tr")) == CAMERAS)
        self.go("live")
        wait_for("live frames", lambda: self.js("return mocapConsole.pages.live.frames") > 0)
        connections = self.js("return mocapConsole.pages.live.socket.connections")
        # serve goes away (killed, as a crash would) and comes back on the same ports.
        self.rig.serve.kill()
        self.rig.serve.wait()
        for driver in (self.page, other):
            wait_for("the page to say the hub is away", lambda: "away" in self.hub_state(driver))
        self.rig.start_serve(self.rig.udp_port, self.rig.api_port)
        for driver in (self.page, other):
            wait_for("the page to reconnect", lambda: self.hub_state(driver) == "connected", timeout=STUCK_S)
        wait_for("the live view to reconnect", lambda: self.js(
            "return mocapConsole.pages.live.socket.connections") == connections + 1, timeout=STUCK_S)
        frames = self.js("return mocapConsole.pages.live.frames")
        wait_for("frames again after the restart",
                 lambda: self.js("return mocapConsole.pages.live.frames") > frames + 10)
        wait_for("the nodes back in the second browser", lambda: len(other.find_elements(
            By.CSS_SELECTOR, "#nodes-table tbody tr")) == CAMERAS)

    def test_9_a_missing_web_root_is_a_usage_error(self):
        result = subprocess.run(
            [os.path.join(BIN, "mocap-hub"), "serve", "--calibration", os.path.join(WORK, "frames", "calibration.json"),
             "--listen", "127.0.0.1:0", "--api", "127.0.0.1:0", "--stream", "off",
             "--sessions-dir", os.path.join(WORK, "sessions_unused"), "--keys", self.rig.keys,
             "--web-root", os.path.join(WORK, "no_such_dir")],
            capture_output=True, text=True, timeout=30)
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("not a directory", result.stderr)

    def test_9_paths_that_leave_the_console_or_the_sessions_are_refused(self):
        port = self.rig.api_port
        with open(os.path.join(WORK, "outside.trc"), "w") as f:
            f.write("outside")
        for path in ("/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/js/..%2f..%2f..%2fetc/passwd",
                     "/vendor/three/../../../../../etc/passwd", "/vendor/three/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
                     "/api/sessions/%2e%2e/files/outside.trc", "/api/sessions/web_take/files/..%2f..%2foutside.trc",
                     "/api/sessions/web_take/files/%2e%2e%2f%2e%2e%2foutside.trc",
                     "/api/sessions/..%2f/files/outside.trc",
                     "/.%2e/outside.trc", "/masks.json", "/api/sessions/web_take/files/.hidden"):
            status, _, body = raw_request(port, f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n{auth_header(port)}"
                                                f"Connection: close\r\n\r\n".encode())
            self.assertIn(status, (400, 403, 404), path)
            self.assertNotIn(b"root:", body, path)
            self.assertNotIn(b"outside", body.replace(b"outside.trc", b""), path)

    def test_9_console_files_are_typed_and_revalidated(self):
        port = self.rig.api_port
        status, headers, body = raw_request(port, b"GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
        self.assertEqual(status, 200)
        self.assertTrue(headers["content-type"].startswith("text/html"))
        self.assertIn(b'<script type="module" src="/js/main.js">', body)
        status, headers, body = raw_request(
            port, b"GET /vendor/three/build/three.module.js HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")
        self.assertEqual(status, 200)
        self.assertTrue(headers["content-type"].startswith("text/javascript"))  # ES modules need it
        self.assertEqual(int(headers["content-length"]), len(body))
        etag = headers["etag"]
        status, _, body = raw_request(port, f"GET /vendor/three/build/three.module.js HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                                            f"If-None-Match: {etag}\r\nConnection: close\r\n\r\n".encode())
        self.assertEqual((status, body), (304, b""))
        status, _, _ = raw_request(port, b"POST /index.html HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\n"
                                         b"Connection: close\r\n\r\n")
        self.assertEqual(status, 405)


def main():
    global BIN, WORK
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    BIN, WORK = sys.argv[1], sys.argv[2]
    for tool in (CHROMIUM, CHROMEDRIVER):
        if not os.path.exists(tool):
            sys.exit(f"{tool} missing: deploy/install-deps.sh installs chromium and chromium-driver")
    unittest.main(argv=sys.argv[:1], verbosity=2)


if __name__ == "__main__":
    main()
