"""What a python-scheme may and may not do to the process (issue 43, items 1 and 2, and the
interpreter the CLI embeds): an image's recipe runs no Python unless --allow-python; a scheme
without a callable step is one clean error line, never an abort."""

import os
import signal

import numpy as np
import pytest
from PIL import Image

import fixpoint
from conftest import MANN_CONFIG, run_cli

SMALL = ["--set", "renderer.width=120", "--set", "renderer.height=120", "--set", "renderer.points=20000"]


def scheme_config(tmp_path, scheme):
    """fig6b with `scheme` (flow YAML) as its iteration, written beside the test's files."""
    cfg = tmp_path / "c.yaml"
    cfg.write_text(MANN_CONFIG.read_text().replace("iteration: {type: mann, alpha: 0.7}", f"iteration: {scheme}"))
    return cfg


@pytest.fixture
def python_image(tmp_path):
    """An image whose recipe holds a python-scheme that, when its code loads, writes a marker
    file: the proof that the code ran. Returns (image, marker)."""
    marker = tmp_path / "ran"
    code = (f"open({str(marker)!r}, 'w').write('x')\\n"
            "def step(T, x, y, n):\\n    tx, ty = T(x, y)\\n    return 0.3 * x + 0.7 * tx, 0.3 * y + 0.7 * ty\\n")
    cfg = scheme_config(tmp_path, '{type: python-scheme, code: "' + code + '"}')
    img = tmp_path / "downloaded.png"
    r = run_cli("render", cfg, "-o", img, "--quiet", *SMALL)
    assert r.returncode == 0, r.stderr
    assert marker.exists() and img.exists()  # a config the user wrote runs its Python
    marker.unlink()
    return img, marker


@pytest.mark.parametrize("command", [["render", "-o", "{out}"], ["validate"], ["explore", "-o", "{out}", "--param", "renderer.iteration.args[0]=0.2..0.9"],
                                     ["render", "--vary", "renderer.points=1000,2000", "-o", "{out}"]])
def test_an_image_s_recipe_runs_no_python(tmp_path, python_image, command):
    img, marker = python_image
    out = tmp_path / "out"
    args = [a.replace("{out}", str(out) + (".png" if command[0] == "render" else "")) for a in command]
    r = run_cli(args[0], img, *args[1:])
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    # Positioned at the scheme in the image's recipe, and saying how to allow it.
    assert lines[0].startswith(f"{img}:"), lines[0]
    assert "renderer.iteration: 'python-scheme' runs the code it carries" in lines[0]
    assert "--allow-python" in lines[0]
    assert not marker.exists(), "the image's Python ran"
    assert not any(p.name.startswith("out") for p in tmp_path.iterdir())


def test_a_set_on_the_image_s_scheme_does_not_launder_it(tmp_path, python_image):
    img, marker = python_image
    r = run_cli("validate", img, "--set", "renderer.iteration.args=[1]")
    assert r.returncode == 2 and "--allow-python" in r.stderr
    assert not marker.exists()


def test_a_scheme_the_user_gives_on_the_command_line_runs(tmp_path, python_image):
    # The recipe's own scheme replaced by one the user typed: nothing of the image's code runs.
    img, marker = python_image
    code = "def step(T, x, y, n):\\n    return T(x, y)\\n"
    r = run_cli("validate", img, "--set", 'renderer.iteration={type: python-scheme, code: "' + code + '"}')
    assert r.returncode == 0, r.stderr
    assert not marker.exists()


def test_allow_python_renders_the_image_s_recipe_to_the_same_bytes(tmp_path, python_image):
    img, marker = python_image
    again = tmp_path / "again.png"
    r = run_cli("render", img, "-o", again, "--quiet", "--allow-python")
    assert r.returncode == 0, r.stderr
    assert marker.exists()
    a, b = np.asarray(Image.open(img)), np.asarray(Image.open(again))
    assert np.array_equal(a, b) and a.max() > 0


def test_the_python_module_refuses_an_image_s_python_too(tmp_path, python_image):
    img, marker = python_image
    with pytest.raises(fixpoint.Error, match=r"runs the code it carries.*--allow-python"):
        fixpoint.render(img)
    assert not marker.exists()
    pixels, _ = fixpoint.render(img, allow_python=True)
    assert marker.exists()
    assert np.array_equal(pixels, np.asarray(Image.open(img)))


@pytest.mark.parametrize("scheme,why", [
    ('{type: python-scheme, code: ""}', "<code> defines no function step(T, x, y, n)"),
    ('{type: python-scheme, code: "step = 5"}', "<code> defines no function step(T, x, y, n)"),
    ('{type: python-scheme, code: "applications = 99\\ndef step(T, x, y, n):\\n    return x, y\\n"}',
     "<code>: applications must be from 1 to 64, got 99"),
    ("{type: python-scheme, file: empty.py}", "empty.py defines no function step(T, x, y, n)"),
    ("{type: python-scheme, file: folder}", "'folder' is not a regular file (a Python file is needed)"),
])
@pytest.mark.parametrize("command", ["validate", "render"])
def test_a_scheme_without_a_callable_step_is_one_line_not_an_abort(tmp_path, scheme, why, command):
    (tmp_path / "empty.py").write_text("")
    (tmp_path / "folder").mkdir()
    cfg = scheme_config(tmp_path, scheme)
    args = ["-o", tmp_path / "out.png"] if command == "render" else []
    r = run_cli(command, cfg, *args, cwd=tmp_path)
    assert r.returncode == 2, (r.returncode, r.stderr)  # not 134 (abort) nor -6 (SIGABRT)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(f"{cfg}:24:"), lines[0]
    assert lines[0].endswith(why), lines[0]
    assert not (tmp_path / "out.png").exists()


def test_os_exit_in_a_scheme_is_an_error_not_a_silent_success(tmp_path):
    # os._exit(0) ended the CLI with exit code 0 and no image.
    cfg = scheme_config(tmp_path, '{type: python-scheme, code: "import os\\nos._exit(0)"}')
    r = run_cli("render", cfg, "-o", tmp_path / "out.png")
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().endswith("SystemExit: os._exit(0): a python-scheme may not end the process"), r.stderr
    assert not (tmp_path / "out.png").exists()


def test_the_cli_s_python_is_the_build_s_not_the_one_on_path(tmp_path):
    # A python3 first on PATH that is not the build's interpreter (pyenv's shim, here one that
    # is no Python at all): an embedded Python that took its prefix from it found no standard
    # library, or another's site-packages without numpy.
    fake = tmp_path / "bin"
    fake.mkdir()
    (fake / "python3").write_text("#!/bin/sh\nexit 3\n")
    (fake / "python3").chmod(0o755)
    cfg = scheme_config(tmp_path, '{type: python-scheme, code: "import numpy\\ndef step(T, x, y, n):\\n'
                                  '    return T(x, y)\\n"}')
    env = dict(os.environ, PATH=f"{fake}:{os.environ['PATH']}")
    import subprocess
    from conftest import CLI
    r = subprocess.run([CLI, "validate", str(cfg)], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    # A module it lacks: the error says which Python ran the code.
    cfg = scheme_config(tmp_path, '{type: python-scheme, code: "import no_such_module_here"}')
    r = subprocess.run([CLI, "validate", str(cfg)], capture_output=True, text=True, env=env)
    assert r.returncode == 2
    assert "ModuleNotFoundError: No module named 'no_such_module_here' (python-scheme runs Python 3." in r.stderr
    assert str(fake) not in r.stderr
    assert r.returncode != -signal.SIGABRT


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_python_that_loops_at_load_stops_on_a_signal(tmp_path, sig):
    # The scheme's code never returns: Ctrl-C and SIGTERM reached only the CLI's flag, which
    # nothing polled while Python ran. Now Python raises KeyboardInterrupt at its next bytecode.
    # Two busy processes beside it, as on a loaded machine: the bound is on what the code
    # controls (the marker is written before the loop, so the signal comes while it loops).
    import subprocess
    import sys
    import time
    from conftest import CLI
    marker = tmp_path / "looping"
    code = f"open({str(marker)!r}, 'w').write('x')\\nwhile True:\\n    pass\\n"
    cfg = scheme_config(tmp_path, '{type: python-scheme, code: "' + code + '"}')
    busy = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(2)]
    try:
        p = subprocess.Popen([CLI, "render", str(cfg), "-o", str(tmp_path / "out.png")],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(1200):  # up to 60 s for the interpreter to start, under load
            if marker.exists() or p.poll() is not None:
                break
            time.sleep(0.05)
        assert marker.exists(), p.communicate()[1] if p.poll() is not None else "the code never ran"
        p.send_signal(sig)
        try:
            _, err = p.communicate(timeout=60)  # (a margin: it stops at the next bytecode)
        except subprocess.TimeoutExpired:
            p.kill()
            pytest.fail("the CLI ignored the signal while Python looped")
    finally:
        for b in busy:
            b.kill()
            b.wait()
    assert p.returncode == 130, err
    assert err.strip() == "fixpoint: interrupted; no image written", err
    assert not (tmp_path / "out.png").exists()


def test_describe_says_which_plugins_run_code():
    assert fixpoint.describe("python-scheme")["runs_code"] is True
    assert fixpoint.describe("mann")["runs_code"] is False
    r = run_cli("describe", "python-scheme")
    assert r.returncode == 0
    assert "runs the code its parameters carry: refused in a recipe read from an image unless --allow-python" \
        in r.stdout
    assert "runs the code" not in run_cli("describe", "mann").stdout
