#!/usr/bin/env python3
"""Live wanding through `serve` end to end: a wand waved through a simulated rig (`sim wand
--motion`), rendered into camera frames (`sim render`) that one real `mocap-node` process per
camera replays on loopback; `mocap-hub calibrate wand --live` starts the wanding through serve's
API, follows each camera's samples, coverage and advice until serve stops by itself, waits for
its solve and fetches the report. Asserted: every camera is rated and accepted, the solved rig
matches the truth (`eval-calibration` after a rigid alignment), the recorded session solves
again offline (`calibrate wand`) with the same result, the report's figures are complete, and
apply switches serve's calibration. Python standard library only.

usage: wand_live_test.py BIN_DIR WORK_DIR

Prints the figures it measured (collection time, accuracy) on stderr. Every wait is bounded;
every process the test starts is killed at the end."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import Rig, http, run, wait_for  # noqa: E402

BIN = WORK = None
CAMERAS = 4
RATE = 100
WAND_MM = 500.0
# The solver's usual accuracy on simulated rigs (README, calibrate wand): well under a
# millimetre and a few hundredths of a degree; rendered frames add detection noise.
MAX_CENTRE_MM = 2.0
MAX_ROTATION_DEG = 0.1


def read_json(path):
    with open(path) as f:
        return json.load(f)


class LiveWandingTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if os.path.isdir(WORK):
            shutil.rmtree(WORK)
        os.makedirs(WORK)
        walk = os.path.join(WORK, "walk.trc")
        run(BIN, "sim", "motion", "-o", walk, "--markers", "4", "--frames", "1000", "--rate", str(RATE))
        cls.truth = os.path.join(WORK, "rig.json")
        run(BIN, "sim", "rig", "--motion", walk, "--cameras", str(CAMERAS), "-o", cls.truth, "--width", "640",
            "--height", "400")
        wand = os.path.join(WORK, "wand.trc")
        run(BIN, "sim", "wand", "--rig", cls.truth, "-o", os.path.join(WORK, "wand_projected"), "--motion", wand,
            "--frames", "3000", "--rate", str(RATE), "--wand-length", str(WAND_MM), "--seed", "5")
        run(BIN, "sim", "render", "--motion", wand, "--rig", cls.truth, "-o", os.path.join(WORK, "frames"))
        cls.rig = Rig(BIN, WORK, RATE)
        try:
            cls.rig.start(CAMERAS)
        except Exception:
            cls.rig.stop()
            raise

    @classmethod
    def tearDownClass(cls):
        cls.rig.stop()

    def test_live_wanding_rates_every_camera_and_matches_the_truth(self):
        rig = self.rig
        report_dir = os.path.join(WORK, "report")
        live_cal = os.path.join(WORK, "live_calibration.json")
        # Before any wanding: nothing to solve or apply.
        status, body = http(rig.api_port, "POST", "/api/calibration/wand/apply")
        self.assertEqual(status, 409, body)
        # Stopping the wanding's capture ends the wanding too (and solves what was recorded).
        status, body = http(rig.api_port, "POST", "/api/calibration/wand/start",
                            json.dumps({"name": "wand0", "wand_length_mm": WAND_MM}).encode())
        self.assertEqual(status, 200, body)
        self.assertEqual(json.loads(body)["state"], "collecting")
        status, body = http(rig.api_port, "POST", "/api/capture/start", b'{"name": "other"}')
        self.assertEqual(status, 409, body)  # the wanding holds the capture
        time.sleep(0.5)
        rig.hub("capture", "stop")
        wanding = lambda: json.loads(http(rig.api_port, "GET", "/api/calibration/wand")[1])  # noqa: E731
        ended = wait_for("the wanding to end with its capture", lambda: wanding()["state"] != "collecting" and wanding())
        self.assertEqual(ended["stop_reason"], "its capture was stopped")
        wait_for("its solve to end", lambda: wanding()["state"] in ("solved", "failed"), timeout=60)
        # Ctrl-C on calibrate wand --live cancels the wanding in serve as well.
        client = subprocess.Popen([os.path.join(BIN, "mocap-hub"), "calibrate", "wand", "wand_interrupted", "--live",
                                   "--wand-length", str(WAND_MM), "--min-samples", "100000"],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=rig.env)
        try:
            wait_for("the client's wanding", lambda: wanding()["session"] == "wand_interrupted"
                     and wanding()["state"] == "collecting")
            client.send_signal(signal.SIGINT)
            _, err = client.communicate(timeout=10)
        finally:
            if client.poll() is None:
                client.kill()
                client.wait()
        self.assertEqual(client.returncode, 1, err)
        self.assertIn("interrupted", err)
        self.assertEqual(wanding()["state"], "cancelled")
        started = time.monotonic()
        result = rig.hub("calibrate", "wand", "wand1", "--live", "--wand-length", str(WAND_MM),
                         "--min-samples", "300", "--coverage-target", "0.35", "--timeout", "120",
                         "--report", report_dir, "-o", live_cal, "--json", check=False)
        seconds = time.monotonic() - started
        self.assertEqual(result.returncode, 0, result.stderr + result.stdout[-2000:])
        lines = [json.loads(line) for line in result.stdout.splitlines() if line.strip()]
        progress = [line["collection"] for line in lines if line.get("state") == "collecting"]
        final = lines[-1]
        self.assertEqual(final["state"], "solved")
        self.assertEqual(final["stop_reason"], "every camera has enough samples and coverage")
        # The progress was followed as it grew: samples never fall, and advice named what was short.
        self.assertGreater(len(progress), 2)
        samples = [[c["samples"] for c in p["cameras"]] for p in progress]
        for before, after in zip(samples, samples[1:]):
            self.assertTrue(all(b <= a for b, a in zip(before, after)), (before, after))
        self.assertTrue(any(p["advice"] for p in progress))
        self.assertTrue(all(a.startswith("camera ") for p in progress for a in p["advice"]))

        report = final["report"]
        self.assertEqual(len(report["cameras"]), CAMERAS)
        ratings = {"Exceptional", "Excellent", "Good", "Fair", "Poor"}
        for camera in report["cameras"]:
            self.assertTrue(camera["accepted"], camera)
            self.assertIn(camera["rating"], ratings)
            self.assertNotEqual(camera["rating"], "Poor", camera)
        self.assertIn("reprojection_rms_px", report["rating_thresholds"])
        self.assertIn("wand_length_rms_mm", report["rating_thresholds"])

        # Accuracy of the live solve against the truth.
        evaluation = json.loads(run(BIN, "eval-calibration", "--truth", self.truth, "--result", live_cal,
                                    "--json").stdout)
        centre = evaluation["centre_max_mm"]
        rotation = evaluation["rotation_max_deg"]
        self.assertLess(centre, MAX_CENTRE_MM, evaluation)
        self.assertLess(rotation, MAX_ROTATION_DEG, evaluation)

        # The recorded session stays in the sessions directory and solves again offline alike.
        session = os.path.join(WORK, "sessions", "wand1")
        for name in ("wand_calibration.json", "wand_report.html", "wand_figures.json"):
            self.assertTrue(os.path.isfile(os.path.join(session, name)), name)
        offline_cal = os.path.join(WORK, "offline_calibration.json")
        run(BIN, "calibrate", "wand", session, "--intrinsics", os.path.join(WORK, "frames", "calibration.json"),
            "--wand-length", str(WAND_MM), "-o", offline_cal, "--threads", "1")
        offline = json.loads(run(BIN, "eval-calibration", "--truth", live_cal, "--result", offline_cal,
                                 "--json").stdout)
        self.assertLess(offline["centre_max_mm"], 0.01, offline)

        # The report's figures: one entry per camera with every plot's data.
        figures = read_json(os.path.join(report_dir, "wand_figures.json"))
        self.assertEqual(len(figures["cameras"]), CAMERAS)
        for camera in figures["cameras"]:
            for key in ("residuals", "coverage_map", "position", "direction", "rating"):
                self.assertIn(key, camera)
        self.assertEqual(sum(figures["wand_length_histogram"]["counts"]), figures["frames_used"])
        with open(os.path.join(report_dir, "wand_report.html")) as f:
            self.assertIn("renderWandReport", f.read())

        # Apply: serve's calibration is now the solved one.
        status, body = http(rig.api_port, "POST", "/api/calibration/wand/apply", b"{}")
        self.assertEqual(status, 200, body)
        self.assertTrue(json.loads(body)["applied"])
        status, body = http(rig.api_port, "GET", "/api/calibration")
        self.assertEqual(status, 200)
        self.assertTrue(json.loads(body)["file"].endswith("wand1/wand_calibration.json"), body)

        collected = progress[-1]
        print(f"live wanding: {CAMERAS} cameras at {RATE} Hz, {collected['frame_sets']} frame sets seen, "
              f"collection + solve {seconds:.1f} s by the wall clock; camera centres max {centre:.3f} mm, "
              f"rotations max {rotation:.4f} deg, rig rated {report['rating']}, reprojection RMS "
              f"{report['reprojection_rms_px']:.3f} px, wand length RMS {report['wand_length_error']['rms_mm']:.3f} mm; "
              f"ratings {[c['rating'] for c in report['cameras']]}", file=sys.stderr)


if __name__ == "__main__":
    BIN, WORK = sys.argv[1], sys.argv[2]
    unittest.main(argv=[sys.argv[0], "-v"])
