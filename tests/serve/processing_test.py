#!/usr/bin/env python3
"""Sessions processed through a running `mocap-hub serve`, as the console does it: POST
/api/sessions/NAME/process with a recipe, GET /api/processing until the job is done, the results
listed with the session and downloaded. The results equal what `mocap-hub process` writes for the
same recipe on the command line; the session's own files are untouched; results are never replaced
without "overwrite"; bad requests are refused with the field named; a session that cannot be
processed (no calibration of its own, one that does not fit its cameras) fails its job with the
command's own words. Python standard library only.

usage: processing_test.py BIN_DIR WORK_DIR"""

import hashlib
import json
import os
import shutil
import sys
import unittest

from live_rig import Rig, STUCK_S, http, run, wait_for

BIN = WORK = None


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def after_first_line(data):
    """A TRC without its first line (which names the file)."""
    return data.split(b"\n", 1)[1]


class ProcessingThroughServe(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(os.path.join(WORK, "frames"))
        os.makedirs(os.path.join(WORK, "sessions"))
        cls.calibration = os.path.join(WORK, "frames", "calibration.json")
        motion = os.path.join(WORK, "motion.trc")
        run(BIN, "sim", "motion", "--markers", "12", "--frames", "120", "-o", motion)
        run(BIN, "sim", "rig", "--motion", motion, "--cameras", "6", "-o", cls.calibration)
        cls.session = os.path.join(WORK, "sessions", "take1")
        run(BIN, "sim", "project", "--motion", motion, "--rig", cls.calibration, "-o", cls.session,
            "--noise-px", "0.2", "--occlusion", "0.05", "--seed", "3")
        # The command line's result for the same recipe, on a copy of the session.
        cli_session = os.path.join(WORK, "cli_take1")
        shutil.copytree(cls.session, cli_session)
        recipe = os.path.join(WORK, "recipe.json")
        with open(recipe, "w") as f:
            json.dump({"format": "mocap-recipe", "version": 1, "name": "clean", "outputs": ["trc", "c3d"],
                       "max_spline_gap_s": 0.1}, f)
        run(BIN, "process", recipe, cli_session)
        with open(os.path.join(cli_session, "processed", "clean", "markers.trc"), "rb") as f:
            cls.cli_trc = f.read()
        cls.motion = motion
        cls.own_files = {name: digest(os.path.join(cls.session, name)) for name in os.listdir(cls.session)}
        cls.rig = Rig(BIN, WORK, 100)
        cls.rig.start_serve()

    @classmethod
    def tearDownClass(cls):
        cls.rig.stop()

    def api(self, method, path, body=None):
        status, payload = http(self.rig.api_port, method, path, json.dumps(body).encode() if body is not None else b"")
        return status, payload

    def wait_job(self, job_id):
        def finished():
            for job in json.loads(self.api("GET", "/api/processing")[1])["jobs"]:
                if job["id"] == job_id and job["state"] in ("done", "failed"):
                    return job
            return None
        return wait_for(f"processing job {job_id} to finish", finished, timeout=STUCK_S)

    def test_1_a_session_processed_through_the_api_equals_the_command_line(self):
        status, payload = self.api("POST", "/api/sessions/take1/process",
                                   {"recipe": {"name": "clean", "outputs": ["trc", "c3d"], "max_spline_gap_s": 0.1}})
        self.assertEqual(status, 202, payload)
        job = json.loads(payload)
        self.assertEqual((job["session"], job["recipe"]), ("take1", "clean"))
        done = self.wait_job(job["id"])
        self.assertEqual(done["state"], "done", done)
        self.assertEqual(done["exit_status"], 0)
        self.assertEqual(done["outputs"], ["markers.trc", "markers.c3d"])
        self.assertEqual(done["progress"]["step"], "reconstruct")
        self.assertEqual(done["progress"]["done"], done["progress"]["total"])
        self.assertTrue(any("processed by recipe 'clean'" in line for line in done["log"]), done["log"])

        # Listed with the session, downloadable, the same as the command line's.
        session = json.loads(self.api("GET", "/api/sessions/take1")[1])
        results = {p["recipe"]: {f["name"] for f in p["files"]} for p in session["processed"]}
        self.assertLessEqual({"markers.trc", "markers.c3d", "process.json", "process.log", "recipe.json"},
                             results["clean"])
        status, trc = self.api("GET", "/api/sessions/take1/processed/clean/files/markers.trc")
        self.assertEqual(status, 200)
        self.assertEqual(after_first_line(trc), after_first_line(self.cli_trc))
        self.assertEqual(self.api("GET", "/api/sessions/take1/processed/clean/files/nothing.trc")[0], 404)
        self.assertEqual(self.api("GET", "/api/sessions/take1/processed/other/files/markers.trc")[0], 404)
        # The session's own files are untouched.
        for name, before in self.own_files.items():
            self.assertEqual(digest(os.path.join(self.session, name)), before, name)

        # Results are kept: the same recipe again is refused, "overwrite" replaces them.
        status, payload = self.api("POST", "/api/sessions/take1/process", {"recipe": {"name": "clean"}})
        self.assertEqual(status, 409, payload)
        self.assertIn("overwrite", json.loads(payload)["error"])
        status, payload = self.api("POST", "/api/sessions/take1/process",
                                   {"recipe": {"name": "clean"}, "overwrite": True})
        self.assertEqual(status, 202, payload)
        self.assertEqual(self.wait_job(json.loads(payload)["id"])["state"], "done")

    def test_2_bad_requests_are_refused_before_anything_runs(self):
        cases = [({"recipe": {"matcher": "fastest"}}, 400, "matcher"),
                 ({"recipe": {"labels": "serve"}}, 400, "labels"),       # serve runs without a marker set
                 ({"recipe": {"bodies": "../take1/raw.mlog"}}, 400, "bodies"),
                 ({"recipe": {"name": "a b"}}, 400, "name"),
                 ({"recipe": {}, "when": "now"}, 400, "when")]
        for body, expected, word in cases:
            status, payload = self.api("POST", "/api/sessions/take1/process", body)
            self.assertEqual(status, expected, body)
            self.assertIn(word, json.loads(payload)["error"], body)
        self.assertEqual(self.api("POST", "/api/sessions/nosuch/process", {"recipe": {}})[0], 404)
        self.assertEqual(self.api("GET", "/api/sessions/take1/process")[0], 405)

    def test_3_a_session_that_cannot_be_processed_fails_its_job_with_the_reason(self):
        broken = os.path.join(WORK, "sessions", "broken")
        shutil.copytree(self.session, broken, ignore=shutil.ignore_patterns("processed"))
        with open(os.path.join(broken, "session.json")) as f:
            calibration = json.load(f)["calibration"]
        os.remove(os.path.join(broken, calibration))
        status, payload = self.api("POST", "/api/sessions/broken/process", {"recipe": {"name": "clean"}})
        self.assertEqual(status, 202, payload)
        failed = self.wait_job(json.loads(payload)["id"])
        self.assertEqual(failed["state"], "failed", failed)
        self.assertEqual(failed["exit_status"], 1)
        self.assertTrue(any("has no calibration of its own (calibration.json); give a calibration" in line
                            for line in failed["log"]), failed["log"])
        # The request can name the file serve runs with instead.
        status, payload = self.api("POST", "/api/sessions/broken/process",
                                   {"recipe": {"name": "clean", "calibration": "serve"}, "overwrite": True})
        self.assertEqual(status, 202, payload)
        self.assertEqual(self.wait_job(json.loads(payload)["id"])["state"], "done")

    def test_4_a_calibration_that_does_not_fit_fails_its_job_with_the_residuals(self):
        # Camera 3 turned 3 deg after the calibration the session carries.
        turned = os.path.join(WORK, "sessions", "turned")
        run(BIN, "sim", "project", "--motion", self.motion, "--rig", self.calibration, "-o", turned,
            "--noise-px", "0.2", "--occlusion", "0.05", "--seed", "4", "--bump", "3:3:0", "--bump-from-s", "0")
        status, payload = self.api("POST", "/api/sessions/turned/process", {"recipe": {"name": "clean"}})
        self.assertEqual(status, 202, payload)
        failed = self.wait_job(json.loads(payload)["id"])
        self.assertEqual(failed["state"], "failed", failed)
        reason = [line for line in failed["log"] if "does not fit" in line]
        self.assertEqual(len(reason), 1, failed["log"])
        self.assertIn(": camera 3 median ", reason[0])
        self.assertIn("median leave-one-out residual per camera 1: ", reason[0])
        # The console's "even with a misfit calibration".
        status, payload = self.api("POST", "/api/sessions/turned/process",
                                   {"recipe": {"name": "clean", "force_calibration": True}, "overwrite": True})
        self.assertEqual(status, 202, payload)
        self.assertEqual(self.wait_job(json.loads(payload)["id"])["state"], "done")


if __name__ == "__main__":
    BIN, WORK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    unittest.main(argv=sys.argv[:1], verbosity=2)
