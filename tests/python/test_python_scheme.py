"""Iteration schemes written in Python ({type: python-scheme, file: ...})."""

import numpy as np
import pytest
from PIL import Image

import fixpoint
from conftest import MANN_CONFIG, run_cli

SMALL = {"renderer__width": 200, "renderer__height": 200, "renderer__points": 300000}


def py_scheme(path):
    return {"type": "python-scheme", "file": str(path)}


@pytest.mark.parametrize("precision", ["float", "double"])
def test_equals_the_cpp_scheme_to_the_last_bit(mann_py, precision):
    cpp, _ = fixpoint.render(MANN_CONFIG, dtype="float32", renderer__precision=precision, **SMALL)
    for threads in (1, 2, 3):
        py, _ = fixpoint.render(MANN_CONFIG, dtype="float32", renderer__iteration=py_scheme(mann_py),
                                renderer__precision=precision, threads=threads, **SMALL)
        assert np.array_equal(cpp, py), f"{threads} threads"
    assert cpp.max() > 0


def test_inline_code_with_args_equals_the_file():
    code = "def step(T, x, y, n):\n    tx, ty = T(x, y)\n    a = args[0]\n    return (1 - a) * x + a * tx, (1 - a) * y + a * ty\n"
    cpp, _ = fixpoint.render(MANN_CONFIG, **SMALL)
    py, recipe = fixpoint.render(MANN_CONFIG, renderer__iteration={"type": "python-scheme", "code": code, "args": [0.7]},
                                 **SMALL)
    assert np.array_equal(cpp, py)
    assert "python-scheme" in recipe and "args" in recipe


def test_the_cli_renders_a_python_scheme(tmp_path, mann_py):
    cfg = tmp_path / "mann.yaml"
    cfg.write_text(MANN_CONFIG.read_text().replace("iteration: {type: mann, alpha: 0.7}",
                                                   "iteration: {type: python-scheme, file: mann.py}"))
    sets = ["--set", "renderer.width=200", "--set", "renderer.height=200", "--set", "renderer.points=300000"]
    r = run_cli("render", cfg, "-o", tmp_path / "py.png", "--quiet", *sets, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = run_cli("render", MANN_CONFIG, "-o", tmp_path / "cpp.png", "--quiet", *sets)
    assert r.returncode == 0, r.stderr
    a = np.asarray(Image.open(tmp_path / "py.png"))
    b = np.asarray(Image.open(tmp_path / "cpp.png"))
    assert np.array_equal(a, b) and a.max() > 0


def cli_error(tmp_path, code, name="s.py"):
    (tmp_path / name).write_text(code)
    cfg = tmp_path / "c.yaml"
    cfg.write_text(MANN_CONFIG.read_text().replace("iteration: {type: mann, alpha: 0.7}",
                                                   f"iteration: {{type: python-scheme, file: {name}}}"))
    r = run_cli("render", cfg, "-o", tmp_path / "out.png", "--set", "renderer.points=10000", cwd=tmp_path)
    assert r.returncode != 0
    assert not (tmp_path / "out.png").exists()
    return r.stderr.strip().replace(str(cfg), "c.yaml")


def test_a_syntax_error_names_its_line(tmp_path):
    err = cli_error(tmp_path, "a = 1\ndef step(T, x, y, n)\n    return x, y\n")
    assert err == "c.yaml:24:42: renderer.iteration.file: s.py:2: SyntaxError: expected ':'"


def test_no_step_function(tmp_path):
    err = cli_error(tmp_path, "def stepp(T, x, y, n):\n    return x, y\n")
    assert err == "c.yaml:24:42: renderer.iteration.file: s.py defines no function step(T, x, y, n)"


def test_an_exception_in_step_names_its_line(tmp_path):
    err = cli_error(tmp_path, "def step(T, x, y, n):\n    tx, ty = T(x, y)\n    return tx * 2.0, ty[5000000]\n")
    assert err.startswith("c.yaml:19:3: renderer: python-scheme: s.py:3: IndexError: index 5000000 is out of bounds")


def test_a_wrong_result(tmp_path):
    err = cli_error(tmp_path, "def step(T, x, y, n):\n    return x[:1], y[:1]\n")
    assert "python-scheme: s.py: step must return two arrays of" in err
    err = cli_error(tmp_path, "def step(T, x, y, n):\n    return x\n")
    assert err == "c.yaml:19:3: renderer: python-scheme: s.py: step must return a tuple (x, y)"


def test_a_missing_file_and_both_file_and_code(tmp_path):
    with pytest.raises(fixpoint.Error, match=r"renderer.iteration.file: cannot read 'nope.py': No such file"):
        fixpoint.render(MANN_CONFIG, renderer__iteration="{type: python-scheme, file: nope.py}")
    with pytest.raises(fixpoint.Error, match=r"give either 'file' or 'code', not both"):
        fixpoint.render(MANN_CONFIG, renderer__iteration="{type: python-scheme, file: a.py, code: 'x'}")


def test_conformance_passes_for_a_good_scheme(tmp_path, mann_py):
    r = run_cli("conformance", "--example", f"{{file: {mann_py}}}", "python-scheme")
    assert r.returncode == 0, r.stdout + r.stderr
    assert r.stdout.startswith("PASS python-scheme")


@pytest.mark.parametrize("code, finding", [
    # state kept between calls
    ("calls = [0]\ndef step(T, x, y, n):\n    calls[0] += 1\n    tx, ty = T(x, y)\n    return tx + 1e-9 * calls[0], ty\n",
     "iteration-scheme: step() depends on earlier calls"),
    # NaN output
    ("import numpy as np\ndef step(T, x, y, n):\n    tx, ty = T(x, y)\n    return np.sqrt(tx - 1e9), ty\n",
     "non-finite"),
    # a false promise of Picard
    ("picard = True\ndef step(T, x, y, n):\n    tx, ty = T(x, y)\n    return 0.5 * x + 0.5 * tx, 0.5 * y + 0.5 * ty\n",
     "is_picard"),
])
def test_conformance_catches_broken_python_schemes(tmp_path, code, finding):
    f = tmp_path / "broken.py"
    f.write_text(code)
    r = run_cli("conformance", "--example", f"{{file: {f}}}", "python-scheme")
    assert r.returncode == 1
    assert r.stdout.startswith("FAIL python-scheme")
    assert finding in r.stdout, r.stdout
