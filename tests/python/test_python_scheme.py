"""Iteration schemes written in Python ({type: python-scheme, file: ...})."""

import numpy as np
import pytest
from PIL import Image

import fixpoint
from conftest import MANN_CONFIG, SOURCE, run_cli

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
    with pytest.raises(fixpoint.Error, match=r"renderer.iteration.file: cannot read 'nope.py': No such file"
                                             r" or directory \(a path in a config is from its folder, in --set from the working folder\)"):
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


# ------------------------------------------------------------------ numbers and coefficients
# Paper 02 eq. (5), Suantai's three-step scheme, as plugins/iterations/suantai.cpp writes it
# with SchemeBase: the coefficients' matrices from k, the combinations through lin.
SUANTAI_PY = """\
applications = 3

def step(T, x, y, n, k):
    p = (x, y)
    tp = T(x, y)
    v = lin(I - k["gamma"], p, k["gamma"], tp)
    tv = T(*v)
    u = lin(I - k["a"] - k["b"], p, k["a"], tv, k["b"], tp)
    tu = T(*u)
    return lin(I - k["alpha"] - k["beta"], p, k["alpha"], tu, k["beta"], tv)
"""

# Paper 02 Fig. 10(a): Suantai in the q-system q^2 = -1, with q parts in three coefficients.
SUANTAI_CONFIG = SOURCE / "configs" / "iterations" / "fig10a.yaml"
COEFS = {"alpha": "0.7+0.1q", "beta": 0.5, "gamma": "0.4+0.5q", "a": 0.3, "b": "0.1-0.2q"}
REAL_COEFS = {"alpha": 0.7, "beta": 0.5, "gamma": [0.4, 0.6, 0.5], "a": 0.3, "b": 0.1}


@pytest.mark.parametrize("numbers, coefs", [
    ({"type": "real"}, REAL_COEFS),
    ({"type": "complex"}, COEFS),
    ({"type": "q-system", "A": -1.0, "B": 0.0}, COEFS),
    ({"type": "q-system", "A": 0.5, "B": 0.25}, COEFS),
], ids=["real", "complex", "q-system", "q-system-A0.5-B0.25"])
@pytest.mark.parametrize("precision", ["float", "double"])
def test_numbers_and_named_coefficients_give_the_cpp_schemes_bits(tmp_path, numbers, coefs, precision):
    (tmp_path / "suantai.py").write_text(SUANTAI_PY)
    small = dict(SMALL, renderer__precision=precision)
    cpp, _ = fixpoint.render(SUANTAI_CONFIG, dtype="float32",
                             renderer__iteration=dict(coefs, type="suantai", numbers=numbers), **small)
    py, recipe = fixpoint.render(SUANTAI_CONFIG, dtype="float32", renderer__iteration=dict(
        coefs, type="python-scheme", file=str(tmp_path / "suantai.py"), numbers=numbers), **small)
    assert cpp.max() > 0
    assert np.array_equal(cpp, py)
    assert "python-scheme" in recipe and numbers["type"] in recipe


def test_the_coefficient_matrices_are_the_number_systems_multipliers():
    # k holds each coefficient at step n as the matrix of multiplying by it: in the q-system
    # q^2 = A + 2Bq, (x + qy)(c + qd) = (cx + Ady) + q(dx + (c + 2Bd)y) (eq. (11)).
    code = ("seen = []\n"
            "def step(T, x, y, n, k):\n"
            "    seen.append((n, k['alpha'].tolist(), k['a'].tolist()))\n"
            "    assert len(seen) < 2 or seen[-1][0] != seen[-2][0] or seen[-1] == seen[-2]\n"
            "    if n < 2:\n"
            "        want = [[0.3, 2 * 0.5], [0.5, 0.3 + 2 * 0.25 * 0.5]] if n == 0 else [[0.9, 0], [0, 0.9]]\n"
            "        assert k['alpha'].tolist() == want, (n, k['alpha'].tolist())\n"
            "        assert k['a'].tolist() == [[1, 0], [0, 1]]\n"
            "    return T(x, y)\n")
    img, _ = fixpoint.render(SUANTAI_CONFIG, renderer__width=50, renderer__height=50, renderer__points=2000,
                             renderer__iteration={"type": "python-scheme", "code": code,
                                                  "numbers": {"type": "q-system", "A": 2.0, "B": 0.25},
                                                  "alpha": ["0.3+0.5q", 0.9], "a": 1})
    assert img.max() > 0


def test_lin_is_scheme_bases_combination_in_the_points_precision():
    # lin rounds each entry to the points' dtype and sums in SchemeBase's grouping.
    code = ("def step(T, x, y, n, k):\n"
            "    r = lin([[0.1, 0.2], [0.3, 0.4]], (x, y), I, (x, y), [[1, 0], [0, 2]], (x, y))\n"
            "    t = x.dtype.type\n"
            "    ex = (t(0.1) * x + t(0.2) * y) + (t(1) * x + t(0) * y) + (t(1) * x + t(0) * y)\n"
            "    ey = (t(0.3) * x + t(0.4) * y) + (t(0) * x + t(1) * y) + (t(0) * x + t(2) * y)\n"
            "    assert r[0].dtype == x.dtype and np.array_equal(r[0], ex) and np.array_equal(r[1], ey)\n"
            "    return T(x, y)\n")
    for precision in ("float", "double"):
        img, _ = fixpoint.render(MANN_CONFIG, renderer__width=50, renderer__height=50, renderer__points=2000,
                                 renderer__precision=precision,
                                 renderer__iteration={"type": "python-scheme", "code": code})
        assert img.max() > 0


def test_coefficients_refused_as_the_cpp_schemes_refuse_them(tmp_path):
    four = "def step(T, x, y, n):\n    return T(x, y)\n"
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render(MANN_CONFIG, renderer__iteration={"type": "python-scheme", "code": four, "alpha": 0.5})
    assert str(e.value).endswith(
        "renderer.iteration.alpha: the coefficient is given, but <code>'s step(T, x, y, n) takes none: write "
        "step(T, x, y, n, k) and read its matrix k['alpha']")
    five = "def step(T, x, y, n, k):\n    return T(x, y)\n"
    # A q-number where the scheme computes in the reals: the words of SchemeBase's schemes.
    cpp = py = None
    for scheme in ({"type": "mann"}, {"type": "python-scheme", "code": five}):
        with pytest.raises(fixpoint.Error) as e:
            fixpoint.render(MANN_CONFIG, renderer__iteration=dict(scheme, alpha="0.5+0.2q"))
        # (after the --set that carries the scheme, which differs)
        words = str(e.value)[str(e.value).index(": renderer.iteration.alpha: "):]
        if cpp is None:
            cpp = words
        else:
            py = words
    assert py == cpp
    assert cpp.endswith("renderer.iteration.alpha: 0.5+0.2q is a q-system number, but the scheme computes in the "
                        "real numbers (set numbers: {type: q-system, A: ..., B: ...})")
    with pytest.raises(fixpoint.Error, match=r"step takes \(T, x, y, n\) or \(T, x, y, n, k\), not 3 arguments"):
        fixpoint.render(MANN_CONFIG, renderer__iteration={"type": "python-scheme",
                                                          "code": "def step(T, x, y):\n    return x, y\n"})


def test_lin_refuses_a_matrix_that_is_not_2x2():
    code = "def step(T, x, y, n, k):\n    return lin([1, 2], (x, y), I, T(x, y))\n"
    with pytest.raises(fixpoint.Error, match=r"ValueError: lin: a matrix is 2x2, got the shape \(2,\)"):
        fixpoint.render(MANN_CONFIG, renderer__points=1000,
                        renderer__iteration={"type": "python-scheme", "code": code})


# ------------------------------------------------------------------ file: and threads
def test_file_is_relative_to_the_config(tmp_path, mann_py):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "mann.py").write_text(mann_py.read_text())
    cfg = sub / "mann.yaml"
    cfg.write_text(MANN_CONFIG.read_text().replace("iteration: {type: mann, alpha: 0.7}",
                                                   "iteration: {type: python-scheme, file: mann.py}"))
    sets = ["--set", "renderer.width=100", "--set", "renderer.height=100", "--set", "renderer.points=20000"]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    r = run_cli("render", cfg, "-o", tmp_path / "a.png", "--quiet", *sets, cwd=elsewhere)
    assert r.returncode == 0, r.stderr
    # The recipe names the file absolutely: rendered again from the image, anywhere, it reads it.
    recipe = run_cli("recipe", tmp_path / "a.png").stdout
    assert f'file: "{sub / "mann.py"}"' in recipe
    r = run_cli("render", tmp_path / "a.png", "--allow-python", "-o", tmp_path / "b.png", "--quiet", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert np.array_equal(np.asarray(Image.open(tmp_path / "a.png")), np.asarray(Image.open(tmp_path / "b.png")))
    # On the command line a file is from the working folder.
    r = run_cli("render", cfg, "-o", tmp_path / "c.png", "--quiet", *sets,
                "--set", "renderer.iteration.file=sub/mann.py", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    r = run_cli("render", cfg, "-o", tmp_path / "d.png", *sets, "--set", "renderer.iteration.file=mann.py",
                cwd=elsewhere)
    assert r.returncode == 2
    assert ("renderer.iteration.file: cannot read 'mann.py': No such file or directory (a path in a config is from "
            "its folder, in --set from the working folder)") in r.stderr


def test_one_thread_unless_asked_with_the_reason(tmp_path, mann_py):
    cfg = tmp_path / "mann.yaml"
    cfg.write_text(MANN_CONFIG.read_text().replace("iteration: {type: mann, alpha: 0.7}",
                                                   "iteration: {type: python-scheme, file: mann.py}"))
    sets = ["--set", "renderer.width=100", "--set", "renderer.height=100", "--set", "renderer.points=20000"]
    r = run_cli("render", cfg, "-o", tmp_path / "a.png", *sets)
    assert r.returncode == 0, r.stderr
    assert " 1 thread, " in r.stderr
    assert r.stderr.rstrip().endswith("; 1 thread, as python-scheme runs one batch at a time (--threads N for more)")
    r = run_cli("render", cfg, "-o", tmp_path / "b.png", "--threads", "2", *sets)
    assert r.returncode == 0, r.stderr
    assert " 2 threads, " in r.stderr and "one batch at a time" not in r.stderr
    fixpoint.render(cfg, renderer__points=20000, renderer__width=100, renderer__height=100)
    assert fixpoint.render.last_stats["threads"] == 1
    # A pipeline without it takes every core.
    r = run_cli("render", MANN_CONFIG, "-o", tmp_path / "c.png", *sets)
    assert "one batch at a time" not in r.stderr
