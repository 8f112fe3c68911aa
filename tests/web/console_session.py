"""The console tests that play or edit a session's files (archive, mesh and editor tests) share
this: `mocap-hub` as a subprocess, and a `serve` over WORK/sessions on free ports with a logged-in
headless Chromium on its Sessions page, stopped (browser and serve) when the test ends."""
import contextlib
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from web_test import browser, log_in  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "serve"))
from live_rig import wait_for  # noqa: E402

from selenium.webdriver.common.by import By  # noqa: E402


def hub(bin_dir, *args):
    return subprocess.run([os.path.join(bin_dir, "mocap-hub"), *args], check=True, capture_output=True,
                          text=True).stdout


@contextlib.contextmanager
def console_on_sessions(bin_dir, work, calibration):
    """Yields (page, api_port) with the page showing the Sessions page of a serve that runs with
    `calibration` over WORK/sessions (keys for nodes 1-4, no stream)."""
    hub(bin_dir, "keys", "new", "1", "2", "3", "4", "--out", os.path.join(work, "keys"))
    log_path = os.path.join(work, "serve.log")
    with open(log_path, "w") as log:
        serve = subprocess.Popen([os.path.join(bin_dir, "mocap-hub"), "serve", "--listen", "127.0.0.1:0",
                                  "--api", "127.0.0.1:0", "--calibration", calibration, "--sessions-dir",
                                  os.path.join(work, "sessions"), "--masks-file", os.path.join(work, "masks.json"),
                                  "--keys", os.path.join(work, "keys"), "--stream", "off"],
                                 stdout=subprocess.DEVNULL, stderr=log)
    page = None
    try:
        ports = wait_for("serve's ports", lambda: re.search(r"API http://[^:]+:(\d+)", open(log_path).read()))
        port = int(ports.group(1))
        page = browser()
        # The operator logs in with the token serve issued at its first start (beside its
        # sessions directory), as on an installed hub.
        with open(os.path.join(work, "api-auth", "operator.token")) as f:
            log_in(page, f"http://127.0.0.1:{port}/", f.read().strip())
        page.get(f"http://127.0.0.1:{port}/#sessions")
        wait_for("the sessions page", lambda: page.execute_script(
            "return window.mocapConsole && mocapConsole.currentPage()") == "sessions")
        yield page, port
    finally:
        if page is not None:
            page.quit()
        serve.terminate()
        serve.wait(timeout=10)


def click(page, selector):
    """Clicks the first element `selector` finds; False when there is none or it was redrawn
    under the click (call again, e.g. through wait_for)."""
    buttons = page.find_elements(By.CSS_SELECTOR, selector)
    if not buttons:
        return False
    try:
        buttons[0].click()
        return True
    except Exception:  # redrawn under the click: try again
        return False
