"""`fixpoint serve` and clients that send their requests slowly (docs/serve-api.md, "Slow
clients"): they wait without a request thread, within a deadline, and their number is capped.

Forty clients trickling a byte a second once held all 32 request threads: every other request
timed out, and off loopback clients without the token could do it too. Each test here bounds
what the server controls (the deadline, set short through FIXPOINT_SERVE_DEADLINE_MS) with
margins for a loaded machine and a sanitizer build: a request must be answered within 5 s
(it takes milliseconds), a cut must come after the deadline and within 20 s of it.

Run by CTest (tests/serve/CMakeLists.txt) with FIXPOINT_BIN set; loopback only."""

import json
import os
import re
import selectors
import signal
import socket
import subprocess
import time
import urllib.request

BIN = os.environ["FIXPOINT_BIN"]
ANSWER_WITHIN = 5.0  # s: for requests that take milliseconds (those starved took 7 s and more)
CUT_MARGIN = 20.0  # s past the deadline


class Server:
    def __init__(self, root, *args, env=None):
        e = dict(os.environ, **(env or {}))
        self.proc = subprocess.Popen([BIN, "serve", *args, "--port", "0", "--root", str(root)],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=e)
        line = self.proc.stdout.readline()
        m = re.fullmatch(r"fixpoint serve: open http://[^/]+:(\d+)/(\?token=([0-9a-f]{32}))?\n", line)
        assert m, (line, self.proc.stderr.read() if self.proc.poll() is not None else "")
        self.port, self.token = int(m.group(1)), m.group(3)

    def stop(self):
        """SIGINT, as Ctrl-C: (exit code, stderr)."""
        self.proc.send_signal(signal.SIGINT)
        try:
            code = self.proc.wait(timeout=30)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()
        return code, self.proc.stderr.read()

    def get(self, path, headers=None):
        """(status, body, seconds taken) of a request on a fresh connection."""
        req = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", headers=headers or {})
        start = time.monotonic()
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return r.status, r.read(), time.monotonic() - start
        except urllib.error.HTTPError as e:
            return e.code, e.read(), time.monotonic() - start

    def post_json(self, path, body, headers=None):
        req = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", data=json.dumps(body).encode(),
                                     method="POST", headers={"Content-Type": "application/json", **(headers or {})})
        start = time.monotonic()
        with urllib.request.urlopen(req, timeout=60) as r:
            return r.status, r.read(), time.monotonic() - start


class Tricklers:
    """`n` connections that each send `first` at once, then one byte of `rest` a second. Each
    one's start is taken before its connect, so that a cut the server makes after its deadline
    (from its accept) is seen after the deadline here too."""

    def __init__(self, port, n, first, rest):
        self.socks, self.start, self.cut, self.got = [], [], {}, {}
        self.rest = rest
        self.sel = selectors.DefaultSelector()
        for i in range(n):
            self.start.append(time.monotonic())
            s = socket.create_connection(("127.0.0.1", port), timeout=30)
            s.sendall(first)
            s.setblocking(False)
            self.socks.append(s)
            self.got[i] = b""
            self.sel.register(s, selectors.EVENT_READ, i)
        self.sent = 0

    def run(self, seconds):
        """Trickles for `seconds`, noting when the server answers or closes each one."""
        end = time.monotonic() + seconds
        next_byte = time.monotonic() + 1.0
        while time.monotonic() < end and len(self.cut) < len(self.socks):
            for key, _ in self.sel.select(timeout=max(0.0, min(next_byte, end) - time.monotonic())):
                i = key.data
                try:
                    data = key.fileobj.recv(65536)
                except (BlockingIOError, InterruptedError):
                    continue
                except OSError:
                    data = b""
                self.got[i] += data
                if not data:
                    self.cut[i] = time.monotonic() - self.start[i]
                    self.sel.unregister(key.fileobj)
            if time.monotonic() >= next_byte:
                next_byte += 1.0
                byte = self.rest[self.sent % len(self.rest):][:1]
                self.sent += 1
                for i, s in enumerate(self.socks):
                    if i not in self.cut:
                        try:
                            s.send(byte)
                        except OSError:
                            pass

    def close(self):
        for s in self.socks:
            s.close()


def test_forty_slow_clients_do_not_starve_the_others(tmp_path):
    # 40 loopback clients trickle their heads (no deadline within the test): requests of
    # others, with and without a body, are answered at once all the while.
    s = Server(tmp_path, env={"FIXPOINT_SERVE_DEADLINE_MS": "600000"})
    slow = Tricklers(s.port, 40, b"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\n", b"X-Slow: " + b"a" * 64)
    try:
        slow.run(3.0)  # every one of them has sent bytes and waits for more
        for _ in range(3):
            status, body, took = s.get("/api/state")
            assert status == 200 and took < ANSWER_WITHIN, (status, took)
            assert "version" in json.loads(body)
            status, body, took = s.post_json("/api/check", {"text": "renderer: {type: nothing}\n"})
            assert status == 200 and took < ANSWER_WITHIN, (status, took)
            slow.run(1.0)
        # The slow ones were held all the while, not cut: the answers did not pass by luck.
        assert slow.cut == {}, slow.cut
    finally:
        slow.close()
        code, err = s.stop()
    assert code == 0 and err == "", err


def test_slow_clients_without_the_token_are_cut_at_the_deadline(tmp_path):
    # Off loopback: 40 clients without the token trickle their heads. They hold no request
    # thread (a request with the token is answered at once), and each is answered 408 and
    # closed once the deadline has passed, not before.
    deadline = 3.0
    s = Server(tmp_path, "--host", "0.0.0.0", env={"FIXPOINT_SERVE_DEADLINE_MS": str(int(deadline * 1000))})
    slow = Tricklers(s.port, 40, b"GET /api/state HTTP/1.1\r\nHost: 127.0.0.1\r\n", b"X-Slow: " + b"a" * 64)
    try:
        slow.run(1.0)
        status, _, took = s.get("/api/state", headers={"X-Fixpoint-Token": s.token})
        assert status == 200 and took < ANSWER_WITHIN, (status, took)
        slow.run(deadline + CUT_MARGIN)
        assert sorted(slow.cut) == list(range(40)), sorted(slow.cut)
        for i, t in slow.cut.items():
            assert deadline <= t <= deadline + CUT_MARGIN, (i, t)
            assert slow.got[i].startswith(b"HTTP/1.1 408 Request Timeout\r\n"), slow.got[i]
            assert slow.got[i].endswith(b'{"error":"the request did not arrive within 3000 ms"}'), slow.got[i]
        # And the server serves on.
        assert s.get("/api/state", headers={"X-Fixpoint-Token": s.token})[0] == 200
    finally:
        slow.close()
        code, err = s.stop()
    assert code == 0 and err == "", err


def test_a_slow_body_is_cut_at_the_deadline(tmp_path):
    # The deadline covers the body too: a head that came whole, then a body trickled. The
    # read fails at the deadline and the connection is closed (a response could not be
    # written in time either).
    deadline = 3.0
    s = Server(tmp_path, env={"FIXPOINT_SERVE_DEADLINE_MS": str(int(deadline * 1000))})
    head = (f"POST /api/check HTTP/1.1\r\nHost: 127.0.0.1:{s.port}\r\nContent-Type: application/json\r\n"
            "Content-Length: 1000\r\n\r\n").encode()
    slow = Tricklers(s.port, 8, head + b'{"text": "', b"a")
    try:
        slow.run(1.0)
        assert s.get("/api/state")[0] == 200
        slow.run(deadline + CUT_MARGIN)
        assert sorted(slow.cut) == list(range(8)), sorted(slow.cut)
        for i, t in slow.cut.items():
            assert deadline <= t <= deadline + CUT_MARGIN and slow.got[i] == b"", (i, t, slow.got[i])
        assert s.get("/api/state")[0] == 200
    finally:
        slow.close()
        code, err = s.stop()
    assert code == 0 and err == "", err


def test_connections_above_the_cap_are_answered_503_at_once(tmp_path):
    s = Server(tmp_path, env={"FIXPOINT_SERVE_CONNECTIONS": "8", "FIXPOINT_SERVE_DEADLINE_MS": "600000"})
    slow = Tricklers(s.port, 8, b"GET /api/state HTTP/1.1\r\n", b"X")
    try:
        # The ninth: accepted after the eight (the listener takes them in order), refused at
        # once without a request sent.
        start = time.monotonic()
        with socket.create_connection(("127.0.0.1", s.port), timeout=ANSWER_WITHIN) as c:
            got = b""
            while chunk := c.recv(65536):
                got += chunk
        assert time.monotonic() - start < ANSWER_WITHIN
        assert got.startswith(b"HTTP/1.1 503 Service Unavailable\r\n"), got
        assert got.endswith(b'{"error":"the server has 8 connections open: try again"}'), got
        assert slow.cut == {}
    finally:
        slow.close()
    # The eight closed, the server takes connections again (once it has seen them go).
    for _ in range(100):
        try:
            status = s.get("/api/state")[0]
        except (ConnectionError, urllib.error.URLError):
            status = None
        if status == 200:
            break
        time.sleep(0.1)
    assert status == 200
    code, err = s.stop()
    assert code == 0 and err == "", err
