"""`fixpoint serve` over HTTP (docs/serve-api.md): who may ask (the Host header, the token,
loopback) and what may be read or written (paths inside --root, control characters, Python in
a config, pictures).

Run by CTest (tests/serve/CMakeLists.txt) with FIXPOINT_BIN and FIXPOINT_SOURCE set. Each
server is a subprocess with --port 0 and a temporary --root; it prints its address first
(conftest.py)."""

import http.client
import json
import os
import signal
import subprocess

import pytest
from PIL import Image
from conftest import BIN, Server, fig4a_text, cli, position


# ------------------------------------------------------------------ the token
def test_another_host_needs_the_token(tmp_path):
    (tmp_path / "fig4a.yaml").write_text(fig4a_text())
    s = Server(tmp_path, "fig4a.yaml", "--host", "0.0.0.0")
    try:
        assert s.token and s.url == f"http://0.0.0.0:{s.port}/"
        base = f"http://127.0.0.1:{s.port}/"
        need = "this server needs its token: open the address it printed, with its ?token=, or send " \
               "the header X-Fixpoint-Token"
        for path in ["", "app.js", "style.css", "api/state", "api/plugins"]:
            status, _, data = s.get(path, base=base)
            assert status == 403
            assert json.loads(data) == {"error": need}
            status, _, _ = s.get(path + "?token=" + s.token, base=base)
            assert status == 200
            status, _, _ = s.get(path, base=base, headers={"X-Fixpoint-Token": s.token})
            assert status == 200
            status, _, _ = s.get(path + "?token=" + "0" * 32, base=base)
            assert status == 403
        status, _, data = s.post("api/check", {"text": fig4a_text()}, base=base)
        assert status == 403
        status, _, data = s.post("api/check", {"text": fig4a_text()}, base=base,
                                 headers={"X-Fixpoint-Token": s.token})
        assert status == 200 and json.loads(data)["ok"] is True
        # The page links its own files with the token.
        _, _, page = s.get("?token=" + s.token, base=base)
        assert f'src="app.js?token={s.token}"'.encode() in page
        assert f'href="style.css?token={s.token}"'.encode() in page
        # Any Host: the token is the guard off loopback.
        c = http.client.HTTPConnection("127.0.0.1", s.port, timeout=30)
        c.request("GET", "/api/state?token=" + s.token, headers={"Host": "example.org"})
        assert c.getresponse().status == 200
        c.close()
    finally:
        assert s.stop() == 0


def test_loopback_needs_no_token(srv):
    assert srv.token is None
    assert srv.get("api/state")[0] == 200


@pytest.mark.parametrize("host", ["127.0.0.2", "localhost", "::1"])
def test_every_loopback_address_needs_no_token(tmp_path, host):
    s = Server(tmp_path, "--host", host)
    try:
        assert s.token is None
    finally:
        assert s.stop() == 0


def test_on_port_80_a_host_without_its_port_is_accepted(tmp_path):
    # A browser leaves out the port of http://127.0.0.1/. Port 80 needs root, and may be taken.
    p = subprocess.Popen([BIN, "serve", "--port", "80", "--root", str(tmp_path)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        if p.stdout.readline() != "fixpoint serve: open http://127.0.0.1:80/\n":
            pytest.skip("port 80: " + p.stderr.read().strip())
        for host, want in [("127.0.0.1", 200), ("localhost", 200), ("127.0.0.1:80", 200), ("evil.example", 403)]:
            c = http.client.HTTPConnection("127.0.0.1", 80, timeout=30)
            c.request("GET", "/api/plugins", headers={"Host": host})
            assert c.getresponse().status == want, host
            c.close()
    finally:
        p.send_signal(signal.SIGINT)
        assert p.wait(timeout=20) == 0


# ------------------------------------------------------------------ paths
@pytest.fixture(scope="module")
def escapes(root, tmp_path_factory):
    outside = tmp_path_factory.mktemp("outside")
    (outside / "x.yaml").write_text(fig4a_text())
    os.symlink(outside, root / "out-dir")
    os.symlink(outside / "x.yaml", root / "out-link.yaml")
    os.symlink(outside / "new.yaml", root / "dangling.yaml")
    (outside / "x.png").write_bytes(b"not an image")
    os.symlink(outside / "x.png", root / "out-link.png")
    os.symlink(outside / "new.png", root / "dangling.png")
    return outside


ESCAPES = {
    "../x.yaml": "'..' is refused: paths stay inside the served folder",
    "a/../../x.yaml": "'..' is refused: paths stay inside the served folder",
    "/etc/passwd.yaml": "an absolute path; paths are relative to the served folder",
    "out-dir/x.yaml": "leaves the served folder through a symbolic link",
    "out-link.yaml": "leaves the served folder through a symbolic link",
    "dangling.yaml": "leaves the served folder through a symbolic link",
}


@pytest.mark.parametrize("path", sorted(ESCAPES))
@pytest.mark.parametrize("endpoint", ["api/check", "api/preview", "api/save", "api/render"])
def test_paths_that_leave_the_root_are_403(srv, escapes, endpoint, path):
    status, _, data = srv.post(endpoint, {"text": fig4a_text(), "path": path, "output": "esc.png"})
    assert status == 403
    message = json.loads(data)["error"]
    assert message.startswith(f"path '{path}': {ESCAPES[path]}")
    assert (escapes / "x.yaml").read_text() == fig4a_text()
    assert sorted(os.listdir(escapes)) == ["x.png", "x.yaml"]


@pytest.mark.parametrize("path", sorted(ESCAPES))
def test_outputs_that_leave_the_root_are_403(srv, escapes, path):
    out = path.replace(".yaml", ".png")
    status, _, data = srv.post("api/render", {"text": fig4a_text(), "path": "fig4a.yaml", "output": out,
                                              "force": True})
    assert status == 403
    assert json.loads(data)["error"].startswith(f"output '{out}': {ESCAPES[path]}")
    assert sorted(os.listdir(escapes)) == ["x.png", "x.yaml"]
    assert (escapes / "x.png").read_bytes() == b"not an image"


def test_an_output_path_in_the_config_that_leaves_the_root_is_403(srv):
    text = fig4a_text().replace("renderer:", "output: {path: ../away.png}\nrenderer:", 1)
    status, _, data = srv.post("api/render", {"text": text, "path": "fig4a.yaml"})
    assert status == 403
    assert json.loads(data) == {"error": "fig4a.yaml:15:16: output '../away.png': '..' is refused: paths stay "
                                         "inside the served folder"}
    # The preview the page asks for at every edit says it at its line before anyone presses
    # "render" (and starts nothing).
    for endpoint in ("api/check", "api/preview"):
        assert srv.api(endpoint, {"text": text, "path": "fig4a.yaml"}) == {
            "ok": False, "line": 15, "column": 16,
            "error": "fig4a.yaml:15:16: output '../away.png': '..' is refused: paths stay inside the served folder"}
    assert not os.path.exists(os.path.join(srv.root, "..", "away.png"))


def test_check_refuses_an_output_path_the_cli_refuses(srv):
    text = fig4a_text().replace("renderer:", "output: {path: out.bmp}\nrenderer:", 1)
    with open(os.path.join(srv.root, "bmp.yaml"), "w") as f:
        f.write(text)
    rc, _, err = cli("render", "bmp.yaml", "-q", cwd=srv.root)
    assert rc == 2 and err.count("\n") == 1 and err.startswith("bmp.yaml:15:16: output.path: "), err
    for endpoint in ("api/check", "api/preview"):  # the page asks for a preview at each edit
        assert srv.api(endpoint, {"text": text, "path": "bmp.yaml"}) == {
            "ok": False, "error": err.strip(), "line": 15, "column": 16}
    assert not os.path.exists(os.path.join(srv.root, "out.bmp"))


def test_a_config_outside_the_root_does_not_start(tmp_path):
    r = subprocess.run([BIN, "serve", "../fig4a.yaml", "--port", "0", "--root", str(tmp_path)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr == "CONFIG '../fig4a.yaml': '..' is refused: paths stay inside the served folder\n"
    r = subprocess.run([BIN, "serve", "none.yaml", "--port", "0", "--root", str(tmp_path)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr == f"CONFIG: 'none.yaml' is not a file in '{os.path.realpath(tmp_path)}'\n"


def test_a_config_path_from_the_working_folder_picks_the_root(tmp_path):
    # Without --root, CONFIG is a path from the working folder, as on any command line.
    (tmp_path / "work").mkdir()
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "a.yaml").write_text(fig4a_text())
    (tmp_path / "work" / "sub").mkdir()
    (tmp_path / "work" / "sub" / "b.yaml").write_text(fig4a_text())
    work, elsewhere = str(tmp_path / "work"), os.path.realpath(tmp_path / "elsewhere")
    # Outside the working folder (absolute, or through ..): its own folder is served, and said.
    for config in (os.path.join(elsewhere, "a.yaml"), "../elsewhere/a.yaml"):
        s = Server(elsewhere, config, cwd=work)
        try:
            assert s.api("api/state")["path"] == "a.yaml"
        finally:
            assert s.stop() == 0
        assert s.proc.stderr.read() == (f"fixpoint serve: serving the config's folder '{elsewhere}' "
                                        "(--root serves another)\n")
    # Inside it: the working folder is served, the config by its path from there.
    for config in ("sub/b.yaml", os.path.join(work, "sub", "b.yaml")):
        s = Server(work, config, cwd=work)
        try:
            assert s.api("api/state")["path"] == "sub/b.yaml"
        finally:
            assert s.stop() == 0
        assert s.proc.stderr.read() == ""
    # With --root, an absolute CONFIG inside it is taken by its path from the root.
    s = Server(tmp_path / "work", os.path.join(work, "sub", "b.yaml"))
    try:
        assert s.api("api/state")["path"] == "sub/b.yaml"
    finally:
        assert s.stop() == 0


def test_a_config_outside_the_given_root_or_missing_is_one_line(tmp_path):
    (tmp_path / "a.yaml").write_text(fig4a_text())
    (tmp_path / "root").mkdir()
    outside = os.path.join(os.path.realpath(tmp_path), "a.yaml")
    r = subprocess.run([BIN, "serve", outside, "--port", "0", "--root", str(tmp_path / "root")],
                       capture_output=True, text=True, timeout=60)
    assert (r.returncode, r.stdout) == (2, "")
    assert r.stderr == (f"CONFIG '{outside}': outside the served folder '{os.path.realpath(tmp_path / 'root')}' "
                        "(--root): serve a folder that holds it, or leave --root out to serve the config's own "
                        "folder\n")
    for missing in (os.path.join(str(tmp_path), "none.yaml"), "../none.yaml"):
        r = subprocess.run([BIN, "serve", missing, "--port", "0"], cwd=tmp_path / "root",
                           capture_output=True, text=True, timeout=60)
        assert (r.returncode, r.stderr) == (2, f"CONFIG: '{missing}' is not a file\n")


def test_a_config_that_became_a_symlink_out_is_403_in_state(tmp_path, tmp_path_factory):
    (tmp_path / "a.yaml").write_text(fig4a_text())
    s = Server(tmp_path, "a.yaml")
    try:
        assert s.api("api/state")["path"] == "a.yaml"
        outside = tmp_path_factory.mktemp("elsewhere")
        (outside / "secret.yaml").write_text("secret: 1\n")
        os.remove(tmp_path / "a.yaml")
        os.symlink(outside / "secret.yaml", tmp_path / "a.yaml")
        assert s.api("api/state", expect=403) == {
            "error": f"CONFIG 'a.yaml': leaves the served folder through a symbolic link (to "
                     f"'{os.path.realpath(outside / 'secret.yaml')}')"}
    finally:
        assert s.stop() == 0


CONTROL = "a control character in a name is refused"


def test_control_characters_in_names_are_refused_and_nothing_is_written(srv):
    before = sorted(os.listdir(srv.root))
    # A NUL ends the name the system sees: "evil.sh\0.yaml" would write evil.sh.
    status, _, data = srv.post("api/save", {"text": "renderer: {}\n", "path": "evil.sh\u0000.yaml"})
    assert (status, json.loads(data)) == (403, {"error": f"path 'evil.sh\\x00.yaml': {CONTROL}"})
    status, _, data = srv.post("api/render", {"text": fig4a_text(), "path": "fig4a.yaml",
                                              "output": "victim\u0000.png"})
    assert (status, json.loads(data)) == (403, {"error": f"output 'victim\\x00.png': {CONTROL}"})
    status, _, data = srv.post("api/check", {"text": fig4a_text(), "path": "fig4a.yaml\u001b"})
    assert (status, json.loads(data)) == (403, {"error": f"path 'fig4a.yaml\\x1b': {CONTROL}"})
    text = fig4a_text().replace("renderer:", 'output: {path: "o2\\0.png"}\nrenderer:', 1)
    line = text.splitlines().index('output: {path: "o2\\0.png"}') + 1
    status, _, data = srv.post("api/render", {"text": text, "path": "fig4a.yaml", "force": True})
    assert (status, json.loads(data)) == (403, {"error": f"fig4a.yaml:{line}:16: output 'o2\\x00.png': {CONTROL}"})
    assert sorted(os.listdir(srv.root)) == before


def python_scheme_text(node):
    """fig4a with an iteration of its own, and where the node stands (line, column)."""
    text = fig4a_text().replace("renderer:\n", f"renderer:\n  iteration: {node}\n", 1)
    line = text.splitlines().index(f"  iteration: {node}") + 1
    return text, line, 14


# Python that would leave a file behind, were it run.
PWN = '{type: python-scheme, code: "open(\'pwned\', \'w\')\\ndef step(T, x, y, n):\\n    return T(x, y)\\n"}'


def has_python_scheme(s):
    """Whether the build has the plugin (FIXPOINT_PYTHON): serve asks its descriptor whether it runs
    code; without it the config is refused as naming an unknown iteration-scheme."""
    return "python-scheme" in s.api("api/plugins").get("iteration-scheme", [])


@pytest.mark.parametrize("endpoint", ["api/check", "api/preview", "api/render"])
def test_python_scheme_is_refused_without_allow_python(srv, endpoint):
    text, line, col = python_scheme_text(PWN)
    got = srv.api(endpoint, {"text": text, "path": "fig4a.yaml", "output": "py.png"})
    if has_python_scheme(srv):
        assert got == {"ok": False, "error": f"fig4a.yaml:{line}:{col}: renderer.iteration: python-scheme runs "
                                             "Python code: fixpoint serve refuses it unless started with "
                                             "--allow-python",
                       "line": line, "column": col}
    else:
        assert got["ok"] is False and "unknown iteration-scheme 'python-scheme'" in got["error"], got
    assert not os.path.exists(os.path.join(srv.root, "pwned"))
    assert not os.path.exists(os.path.join(srv.root, "py.png"))


def test_python_scheme_is_found_anywhere_in_the_tree(srv):
    # In a map of the list (an iteration of its own), where no plugin may even take it.
    text = fig4a_text().replace('colour: "#ff6b6b"}', 'colour: "#ff6b6b", iteration: ' + PWN + '}', 1)
    got = srv.api("api/check", {"text": text})
    if not has_python_scheme(srv):
        assert got["ok"] is False, got
        return
    line = position(got["error"])[0]
    assert got["error"] == (f"<config>:{line}:{got['column']}: renderer.maps[0].iteration: python-scheme runs "
                            "Python code: fixpoint serve refuses it unless started with --allow-python")
    assert text.splitlines()[line - 1][got["column"] - 1:].startswith("{type: python-scheme")


def test_with_allow_python_its_file_stays_inside_the_root(tmp_path, tmp_path_factory):
    outside = tmp_path_factory.mktemp("py-outside")
    (outside / "s.py").write_text("def step(T, x, y, n):\n    return T(x, y)\n")
    os.symlink(outside / "s.py", tmp_path / "link.py")
    s = Server(tmp_path, "--allow-python")
    try:
        if not has_python_scheme(s):
            return  # (the files a plugin reads are its descriptor's: no plugin, nothing to read)
        for name, why in [("../s.py", "'..' is refused: paths stay inside the served folder"),
                          ("link.py", "leaves the served folder through a symbolic link (to "
                                      f"'{os.path.realpath(outside / 's.py')}')")]:
            text, line, col = python_scheme_text(f"{{type: python-scheme, file: {name}}}")
            fcol = text.splitlines()[line - 1].index(name) + 1
            assert s.api("api/check", {"text": text}) == {
                "ok": False, "error": f"<config>:{line}:{fcol}: renderer.iteration.file '{name}': {why}",
                "line": line, "column": fcol}
        # Allowed, inside the root.
        (tmp_path / "s.py").write_text("def step(T, x, y, n):\n    return T(x, y)\n")
        text, _, _ = python_scheme_text("{type: python-scheme, file: s.py}")
        assert s.api("api/check", {"text": text})["ok"] is True
    finally:
        assert s.stop() == 0


SUPERFRACTAL = """renderer:
  type: superfractal
  width: 64
  height: 64
  view: [0, 1, 0, 1]
  picture: PICTURE
  colourer: {type: map-colour}
  maps:
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}
    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0.5]}
"""


def test_a_picture_outside_the_root_is_refused(srv, escapes):
    for name, why in [("../x.png", "'..' is refused: paths stay inside the served folder"),
                      ("/etc/passwd", "an absolute path; paths are relative to the served folder"),
                      ("out-link.png", "leaves the served folder through a symbolic link")]:
        got = srv.api("api/check", {"text": SUPERFRACTAL.replace("PICTURE", name)})
        assert got["ok"] is False and (got["line"], got["column"]) == (6, 12)
        assert got["error"].startswith(f"<config>:6:12: renderer.picture '{name}': {why}")
    # hues is the built-in picture, no file; a picture inside the root is read.
    got = srv.api("api/check", {"text": SUPERFRACTAL.replace("PICTURE", "hues")})
    assert (got["ok"], got["renderer"]) == (True, "superfractal")
    Image.new("RGB", (4, 4), (255, 0, 0)).save(os.path.join(srv.root, "pic.png"))
    got = srv.api("api/check", {"text": SUPERFRACTAL.replace("PICTURE", "pic.png")})
    assert (got["ok"], got["renderer"]) == (True, "superfractal")
