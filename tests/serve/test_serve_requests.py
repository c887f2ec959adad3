"""`fixpoint serve` over HTTP (docs/serve-api.md): the page's files and the state, check and
its refusals (the CLI's words), and bad requests (JSON, sizes, types, bodies read before the
host and the token are checked).

Run by CTest (tests/serve/CMakeLists.txt) with FIXPOINT_BIN and FIXPOINT_SOURCE set. Each
server is a subprocess with --port 0 and a temporary --root; it prints its address first
(conftest.py)."""

import http.client
import json
import os
import time

import pytest
from conftest import SOURCE, Server, fig4a_text, cli, position


# ------------------------------------------------------------------ the page and the state
@pytest.mark.parametrize("path,name,ctype", [
    ("", "index.html", "text/html; charset=utf-8"),
    ("index.html", "index.html", "text/html; charset=utf-8"),
    ("app.js", "app.js", "text/javascript; charset=utf-8"),
    ("panel.js", "panel.js", "text/javascript; charset=utf-8"),
    ("style.css", "style.css", "text/css; charset=utf-8"),
])
def test_page_files_come_from_the_binary(srv, path, name, ctype):
    status, h, data = srv.get(path)
    assert status == 200
    assert h["Content-Type"] == ctype
    with open(os.path.join(SOURCE, "web", name), "rb") as f:
        assert data == f.read()


def test_state_is_the_config_and_the_version(srv):
    _, out, _ = cli("--version", cwd=srv.root)
    state = srv.api("api/state")
    assert state["path"] == "fig4a.yaml"
    assert state["text"] == fig4a_text()
    assert state["version"] == out.split()[-1]
    assert state["threads"] == os.cpu_count()


def test_bytes_of_the_config_that_are_not_utf8_are_sent_as_u_fffd(tmp_path):
    with open(tmp_path / "latin1.yaml", "wb") as f:
        f.write(b"# caf\xe9\n" + fig4a_text().encode())
    s = Server(tmp_path, "latin1.yaml")
    try:
        assert s.api("api/state")["text"] == "# caf\ufffd\n" + fig4a_text()
    finally:
        assert s.stop() == 0


def test_without_a_config_the_page_gets_a_starter_that_checks(tmp_path):
    s = Server(tmp_path, "--threads", "3")
    try:
        state = s.api("api/state")
        assert state["path"] == ""
        assert state["threads"] == 3
        assert s.api("api/check", {"text": state["text"], "path": ""}) == {
            "ok": True, "renderer": "chaos-game", "width": 512, "height": 512, "warnings": []}
    finally:
        assert s.stop() == 0


def test_plugins_by_kind_as_the_cli_lists_them(srv):
    _, out, _ = cli("plugins", cwd=srv.root)
    want = {}
    for line in out.splitlines():
        kind, name = line.split()[:2]
        want.setdefault(kind, []).append(name)
    assert srv.api("api/plugins") == want
    # With params=1, each plugin's parameter names, as describe lists them.
    named = srv.api("api/plugins?params=1")
    assert {k: list(v) for k, v in named.items()} == want
    assert named["shape"]["circle"] == ["centre", "radius"]
    assert "centre" in named["shape"]["star-polygon"]


def test_an_unknown_page_is_404(srv):
    status, _, data = srv.get("nothing-here")
    assert status == 404
    assert json.loads(data) == {"error": "no such page: '/nothing-here'"}


# ------------------------------------------------------------------ check, and refusals as the CLI's
def test_check_of_a_good_config(srv):
    assert srv.api("api/check", {"text": fig4a_text(), "path": "fig4a.yaml"}) == {
        "ok": True, "renderer": "chaos-game", "width": 512, "height": 512, "warnings": []}


BAD = {
    "typo": fig4a_text().replace("points:", "pionts:"),
    "range": fig4a_text().replace("radius: 0.21685}, colour: \"#c56cf0\"", "radius: -1}, colour: \"#c56cf0\""),
    "yaml": fig4a_text().replace("view: [-1.75, 1.75, -1.75, 1.75]", "view: [-1.75, 1.75, -1.75, 1.75"),
    "memory": fig4a_text().replace("width: 512", "width: 65536").replace("height: 512", "height: 65536"),
    "empty": "",
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_config_the_cli_refuses_is_refused_with_its_text_and_never_previewed(srv, case):
    name = f"bad-{case}.yaml"
    with open(os.path.join(srv.root, name), "w") as f:
        f.write(BAD[case])
    rc, _, err = cli("render", name, "-o", f"bad-{case}.png", "-q", cwd=srv.root)
    assert rc == 2
    line = err.strip()
    assert "\n" not in line
    want = {"ok": False, "error": line, "line": position(line)[0], "column": position(line)[1]}
    if case != "empty":
        assert want["line"] > 0
    body = {"text": BAD[case], "path": name}
    assert srv.api("api/check", body) == want
    assert srv.api("api/preview", body) == want  # no "job": nothing started
    assert not os.path.exists(os.path.join(srv.root, f"bad-{case}.png"))


def test_a_refusal_of_an_unsaved_text_names_it_config(srv):
    got = srv.api("api/check", {"text": "renderer: {type: chaos-gam}", "path": ""})
    assert got["ok"] is False
    assert got["error"] == "<config>:1:18: renderer.type: unknown renderer 'chaos-gam' (did you mean 'chaos-game'?)"
    assert (got["line"], got["column"]) == (1, 18)


# ------------------------------------------------------------------ bad requests
@pytest.mark.parametrize("body,message", [
    (b"{", "bad JSON at line 1, column 2: syntax error while parsing object key - unexpected end of input; "
           "expected string literal"),
    (b'{"text": "a"} x', "bad JSON at line 1, column 15: syntax error while parsing value - invalid literal; "
                         "last read: '\"a\"} x'; expected end of input"),
    (b'{"text": "\\ud800"}', "bad JSON at line 1, column 17: syntax error while parsing value - invalid string: "
                             "surrogate U+D800..U+DBFF must be followed by U+DC00..U+DFFF; last read: '\"\\ud800\"'"),
    (b'{"text": 1e400}', "bad JSON: number overflow parsing '1e400'"),
    # A byte that is not UTF-8 is refused, and quoted back as U+FFFD.
    (b'{"text": "\xff"}', "bad JSON at line 1, column 11: syntax error while parsing value - invalid string: "
                          "ill-formed UTF-8 byte; last read: '\"\ufffd'"),
    # The token being read is quoted by its last 40 bytes only.
    (b'{"text": "' + b"a" * 1000, "bad JSON at line 1, column 1011: syntax error while parsing value - "
                                  "invalid string: missing closing quote; last read: '..." + "a" * 40 + "'"),
    (b'{"text": 1' + b"0" * 1000 + b"}", "bad JSON: number overflow parsing '..." + "0" * 40 + "'"),
    (b'{"text": ' + b"[" * 63 + b"]" * 63 + b"}", "field 'text': expected a string"),  # 64 levels
    (b'{"text": ' + b"[" * 64 + b"]" * 64 + b"}", "bad JSON: nested more than 64 levels"),
    (b"[1, 2]", "the body must be a JSON object"),
    (b'{"path": "fig4a.yaml"}', "missing field 'text' (a string)"),
    (b'{"text": 5}', "field 'text': expected a string"),
    (b'{"text": "a", "path": ["x"]}', "field 'path': expected a string"),
])
def test_bad_json_and_missing_fields_are_400(srv, body, message):
    status, _, data = srv.post("api/check", body)
    assert status == 400
    assert json.loads(data) == {"error": message}


def test_a_body_of_100000_keys_is_refused_within_a_second(srv):
    # An ordered object searches its keys one by one: 100 000 of them took 12.7 s of a request
    # thread (issue 43, item 5). The parser now stops at the 4097th key. The bound is a
    # margin: measured here about 0.01 s, a hundred times less.
    body = b"{" + b",".join(b'"k%d": 1' % i for i in range(100000)) + b"}"
    start = time.monotonic()
    status, _, data = srv.post("api/check", body)
    took = time.monotonic() - start
    assert status == 400
    assert json.loads(data) == {"error": "bad JSON: more than 4096 keys"}
    assert took < 3.0, took  # (12.7 s before; a margin for a loaded machine and the sanitizers)


# What a form of another site can post without a CORS preflight, and no type at all.
FORM = b'--x\r\nContent-Disposition: form-data; name="text"\r\n\r\nrenderer: {}\r\n--x--\r\n'


@pytest.mark.parametrize("ctype,body,shown", [
    (None, b'{"text": ""}', "none"),
    ("text/plain", b'{"text": ""}', "'text/plain'"),
    ("application/x-www-form-urlencoded", b"text=renderer", "'application/x-www-form-urlencoded'"),
    ("multipart/form-data; boundary=x", FORM, "'multipart/form-data'"),
])
def test_a_post_that_is_not_json_is_415(srv, ctype, body, shown):
    c = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=30)
    c.request("POST", "/api/check", body=body, headers={"Content-Type": ctype} if ctype else {})
    r = c.getresponse()
    data = r.read()
    c.close()
    assert r.status == 415
    assert json.loads(data) == {"error": f"POST /api/check takes Content-Type: application/json, not {shown}"}


def test_json_with_a_charset_is_json(srv):
    status, _, _ = srv.post("api/check", {"text": fig4a_text()}, ctype="application/json; charset=utf-8")
    assert status == 200


def head_only(s, method, path, headers):
    """A request whose headers are sent and whose body never is: (status, JSON answer). The
    answer comes only if the server answers before reading the body."""
    c = http.client.HTTPConnection("127.0.0.1", s.port, timeout=30)
    try:
        c.putrequest(method, path, skip_host="Host" in headers)
        for k, v in headers.items():
            c.putheader(k, v)
        c.endheaders()
        r = c.getresponse()
        return r.status, json.loads(r.read())
    finally:
        c.close()


def test_a_body_above_4_mib_is_413(srv):
    # Refused by its Content-Length, before it is read.
    n = (4 << 20) + 1
    assert head_only(srv, "POST", "/api/check", {"Content-Type": "application/json", "Content-Length": str(n)}) \
        == (413, {"error": f"POST /api/check: a body of {n} bytes; at most {4 << 20}"})
    # A chunked body has no Content-Length: refused before it is read (it was read whole, up
    # to 64 MiB, before its size was checked), whatever its size: the answer comes with no
    # byte of the body sent, and to a small body sent whole.
    refused = (411, {"error": "POST /api/check: a body without a Content-Length (chunked) is refused: send its "
                              "length"})
    assert head_only(srv, "POST", "/api/check", {"Content-Type": "application/json",
                                                 "Transfer-Encoding": "chunked"}) == refused
    body = b'{"text": "renderer: {}"}'
    c = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=30)
    c.request("POST", "/api/check", body=iter([body[:10], body[10:]]),
              headers={"Content-Type": "application/json"}, encode_chunked=True)
    r = c.getresponse()
    assert (r.status, json.loads(r.read())) == refused
    c.close()


def test_a_recipe_body_above_64_mib_is_413(srv):
    n = (64 << 20) + 1
    assert head_only(srv, "POST", "/api/recipe", {"Content-Type": "application/octet-stream",
                                                  "Content-Length": str(n)}) \
        == (413, {"error": f"POST /api/recipe: a body of {n} bytes; at most {64 << 20}"})


def test_no_body_is_read_before_the_host_and_the_token(tmp_path):
    # A client that may not use the server cannot make it read a body (up to 64 MiB): the
    # answer comes with the headers, the body never sent.
    n = 64 << 20
    s = Server(tmp_path, "--host", "0.0.0.0")
    try:
        assert head_only(s, "POST", "/api/recipe", {"Content-Type": "application/octet-stream",
                                                    "Content-Length": str(n)}) \
            == (403, {"error": "this server needs its token: open the address it printed, with its ?token=, "
                               "or send the header X-Fixpoint-Token"})
    finally:
        assert s.stop() == 0
    s = Server(tmp_path)
    try:
        for path, ctype in [("/api/recipe", "application/octet-stream"), ("/api/save", "application/json")]:
            status, answer = head_only(s, "POST", path, {"Host": "evil.example", "Content-Type": ctype,
                                                         "Content-Length": str(n)})
            assert status == 403
            assert answer == {"error": f"this server answers only requests to http://127.0.0.1:{s.port}/ or "
                                       f"http://localhost:{s.port}/ (the Host header was 'evil.example')"}
        # The content type too.
        assert head_only(s, "POST", "/api/save", {"Content-Type": "text/plain", "Content-Length": str(n)}) \
            == (415, {"error": "POST /api/save takes Content-Type: application/json, not 'text/plain'"})
    finally:
        assert s.stop() == 0


@pytest.mark.parametrize("query,status,message", [
    ("after=-1", 400, "missing query parameter 'job'"),
    ("job=1", 400, "missing query parameter 'after'"),
    ("job=x&after=-1", 400, "query parameter 'job': expected a whole number, not 'x'"),
    ("job=0&after=-1", 400, "query parameter 'job': expected a job's id (1, 2, ...)"),
    ("job=1&after=-2", 400, "query parameter 'after': expected -1 or a stage"),
    ("job=999999&after=-1", 404, "no job 999999"),
])
def test_bad_frame_queries(srv, query, status, message):
    got, _, data = srv.get("api/frame?" + query)
    assert got == status
    assert json.loads(data) == {"error": message}


def test_a_foreign_host_header_is_403(srv):
    # DNS rebinding: a page of evil.example that resolves to 127.0.0.1 sends its own name.
    # Without a port: the port would be 80 (accepted only when the server is on 80).
    for host, want in [("evil.example:%d", 403), ("127.0.0.1:%d", 200), ("localhost:%d", 200),
                       ("[::1]:%d", 200), ("127.0.0.1:1", 403), ("127.0.0.1", 403), ("localhost", 403),
                       ("127.example.com:%d", 403)]:
        c = http.client.HTTPConnection("127.0.0.1", srv.port, timeout=30)
        c.putrequest("GET", "/api/state", skip_host=True)
        c.putheader("Host", host % srv.port if "%d" in host else host)
        c.endheaders()
        r = c.getresponse()
        data = r.read()
        c.close()
        assert r.status == want, (host, data)
        if want == 403:
            assert json.loads(data)["error"].startswith(
                f"this server answers only requests to http://127.0.0.1:{srv.port}/")
