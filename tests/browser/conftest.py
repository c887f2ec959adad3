"""Fixtures of the browser tests: `fixpoint serve` on a copy of a config in a temporary
folder, and headless Chromium driven by Selenium (Debian's chromium and chromedriver)."""

import base64
import io
import os
import pathlib
import shutil
import signal
import subprocess
import time

import pytest

SOURCE = pathlib.Path(os.environ.get("FIXPOINT_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("FIXPOINT_BIN", str(SOURCE / "build" / "bin" / "fixpoint"))
CONFIG = SOURCE / "configs" / "inversion" / "fig4a.yaml"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"

try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.support.ui import WebDriverWait

    SELENIUM = None
except ImportError as e:  # the tests skip, saying why
    SELENIUM = f"selenium is not installed ({e}): apt-get install python3-selenium"


def run_cli(*args, cwd=None):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, cwd=cwd)


class Server:
    """`fixpoint serve --port 0 --root ROOT [CONFIG]`, stopped with SIGINT as a user would."""

    def __init__(self, root, config, *extra):
        self.root = pathlib.Path(root)
        self.proc = subprocess.Popen(
            [CLI, "serve", "--port", "0", "--root", str(root), *extra, *([config] if config else [])],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        prefix = "fixpoint serve: open "
        if not line.startswith(prefix):
            self.proc.kill()
            _, err = self.proc.communicate()
            raise RuntimeError(f"fixpoint serve did not start: {line!r} {err}")
        self.url = line[len(prefix):].strip()

    def stop(self):
        self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise


@pytest.fixture
def root(tmp_path):
    """The served folder: a copy of paper 01's Fig. 4(a) as fig4a.yaml."""
    r = tmp_path / "root"
    r.mkdir()
    shutil.copy(CONFIG, r / "fig4a.yaml")
    return r


@pytest.fixture
def server(root):
    s = Server(root, "fig4a.yaml")
    yield s
    assert s.stop() == 0


@pytest.fixture(scope="session")
def browser():
    if SELENIUM:
        pytest.skip(SELENIUM)
    if not (os.path.exists(CHROMIUM) and os.path.exists(CHROMEDRIVER)):
        pytest.skip("chromium or chromedriver is missing: apt-get install chromium chromium-driver")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1500,900",
              "--force-device-scale-factor=1", "--hide-scrollbars"):
        opts.add_argument(a)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})  # (the console, for its errors)
    d = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    d.set_script_timeout(30)
    yield d
    d.quit()


class Page:
    """The page in the browser, with what the tests read of it."""

    def __init__(self, driver, url, shots):
        self.d = driver
        self.shots = shots
        driver.get(url)
        # Loaded: the config's text is in the editor (its path, or "(unsaved)", in the bar).
        self.wait(lambda: self.js("return document.getElementById('path').textContent"), what="the config")

    def wait(self, cond, timeout=60, what="the page"):
        return WebDriverWait(self.d, timeout, poll_frequency=0.05).until(lambda d: cond(), f"waiting for {what}")

    def js(self, script, *args):
        return self.d.execute_script(script, *args)

    def text(self):
        return self.js("return document.getElementById('text').value")

    def done_job(self):
        """The job of the shown image when it is its last stage, else None."""
        return self.js("const i = document.getElementById('frame');"
                       "return i.dataset.done === '1' && i.complete ? i.dataset.job : null")

    def wait_done(self, other_than=None, timeout=90):
        return self.wait(lambda: (j := self.done_job()) is not None and j != other_than and j,
                         timeout, "the last stage of a preview")

    def image_bytes(self):
        """The PNG the image pane shows, as the server sent it."""
        b64 = self.d.execute_async_script("""
            const done = arguments[arguments.length - 1];
            fetch(document.getElementById('frame').src).then((r) => r.arrayBuffer()).then((b) => {
              let s = ''; const u = new Uint8Array(b);
              for (let i = 0; i < u.length; i += 8192) s += String.fromCharCode(...u.subarray(i, i + 8192));
              done(btoa(s));
            }).catch((e) => done('error: ' + e));""")
        assert not b64.startswith("error"), b64
        return base64.b64decode(b64)

    def set_text(self, text):
        """Type a whole new text (the input event a keystroke fires)."""
        self.js("const t = document.getElementById('text'); t.value = arguments[0];"
                "t.dispatchEvent(new Event('input', {bubbles: true}));", text)

    def shot(self, name):
        path = self.shots / f"{name}.png"
        self.d.save_screenshot(str(path))
        return path


@pytest.fixture
def page(browser, server, tmp_path):
    shots = tmp_path / "shots"
    shots.mkdir()
    return Page(browser, server.url, shots)


def pixels(png):
    from PIL import Image

    im = Image.open(io.BytesIO(png))
    im.load()
    return im


def wait_for(cond, timeout=60, what="a condition"):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        v = cond()
        if v:
            return v
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")
