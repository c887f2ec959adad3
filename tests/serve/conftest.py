"""What the tests of `fixpoint serve` over HTTP share (test_serve_*.py): a server as a
subprocess with --port 0 and a temporary --root (it prints its address first), a module's
server on a copy of fig4a, the CLI, and the preview's frames."""

import json
import os
import re
import signal
import subprocess
import urllib.error
import urllib.request

import pytest

BIN = os.environ["FIXPOINT_BIN"]
SOURCE = os.environ["FIXPOINT_SOURCE"]
FIG4A = os.path.join(SOURCE, "configs", "inversion", "fig4a.yaml")


class Server:
    def __init__(self, root, *args, cwd=None):
        """Serving `root` (--root), or with cwd= and root None, the folder serve picks itself."""
        self.root = str(root)
        given = [] if cwd is not None else ["--root", self.root]
        self.proc = subprocess.Popen([BIN, "serve", *args, "--port", "0", *given], cwd=cwd,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        line = self.proc.stdout.readline()
        m = re.fullmatch(r"fixpoint serve: open (http://[^/]+/)(\?token=([0-9a-f]{32}))?\n", line)
        assert m, (line, self.proc.stderr.read() if self.proc.poll() is not None else "")
        self.url, self.token = m.group(1), m.group(3)
        self.port = int(self.url.rsplit(":", 1)[1].rstrip("/"))

    def stop(self):
        """SIGINT, as Ctrl-C: the server's exit code."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout=20)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()

    def request(self, method, path, body=None, ctype="application/json", headers=None, base=None):
        """(status, headers, bytes); a dict body is sent as JSON."""
        data = json.dumps(body).encode() if isinstance(body, dict) else body
        h = dict(headers or {})
        if data is not None and ctype is not None:
            h["Content-Type"] = ctype
        req = urllib.request.Request((base or self.url) + path.lstrip("/"), data=data, method=method, headers=h)
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return r.status, r.headers, r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers, e.read()

    def get(self, path, **kw):
        return self.request("GET", path, **kw)

    def post(self, path, body, **kw):
        return self.request("POST", path, body, **kw)

    def api(self, path, body=None, expect=200):
        """The JSON answer of a request that must answer `expect`."""
        status, _, data = self.get(path) if body is None else self.post(path, body)
        assert status == expect, (status, data)
        return json.loads(data)


@pytest.fixture(scope="module")
def root(tmp_path_factory):
    r = tmp_path_factory.mktemp("root")
    (r / "fig4a.yaml").write_text(fig4a_text())
    return r


@pytest.fixture(scope="module")
def srv(root):
    s = Server(root, "fig4a.yaml")
    yield s
    assert s.stop() == 0


def fig4a_text():
    """configs/inversion/fig4a.yaml at 512 x 512 with a tenth of its points: the same checks,
    quicker (the sanitizer build renders it several times, and its finishing time goes with the
    pixels)."""
    with open(FIG4A) as f:
        text = f.read()
    for was, now in (("points: 40000000\n", "points: 4000000\n"), ("width: 1024\n", "width: 512\n"),
                     ("height: 1024\n", "height: 512\n")):
        assert was in text
        text = text.replace(was, now)
    return text


def cli(*args, cwd):
    """`fixpoint ARGS` run in `cwd`: (exit code, stdout, stderr)."""
    r = subprocess.run([BIN, *args], cwd=cwd, capture_output=True, text=True, timeout=600)
    return r.returncode, r.stdout, r.stderr


def position(line):
    m = re.search(r":(\d+):(\d+):", line)
    return (int(m.group(1)), int(m.group(2))) if m else (0, 0)


def frame(s, job, after):
    """/api/frame, asked again while it answers 204 (a slow build: a stage past 10 s)."""
    for _ in range(60):
        got = s.get(f"api/frame?job={job}&after={after}")
        if got[0] != 204:
            return got
    return got


def frames(s, job, after=-1):
    """Every stage of a job, in order: [(headers, png bytes)]."""
    out = []
    while True:
        status, h, data = frame(s, job, after)
        assert status == 200, (status, data)
        out.append((h, data))
        after = int(h["X-Stage"])
        if h["X-Done"] == "1":
            return out
