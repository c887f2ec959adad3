"""docs/python.md stays true: its Python blocks run in order, in one namespace, and what
each print() shows is what the comment after it says."""

import contextlib
import io
import os
import re

from conftest import SOURCE


def blocks(text):
    return re.findall(r"^```python\n(.*?)^```", text, re.S | re.M)


def expected_output(code):
    """The comments after print(...) calls, with the comment lines that continue them."""
    out, lines = [], code.splitlines()
    for i, line in enumerate(lines):
        if "print(" in line and "  # " in line:
            out.append(line.split("  # ", 1)[1])
            for more in lines[i + 1:]:
                if not more.strip().startswith("#"):
                    break
                out.append(more.strip()[2:])
    return out


def test_the_python_guide_runs_and_prints_what_it_says(tmp_path):
    doc = (SOURCE / "docs" / "python.md").read_text()
    os.symlink(SOURCE / "configs", tmp_path / "configs")
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        ns = {}
        found = blocks(doc)
        assert len(found) >= 5
        for code in found:
            buf = io.StringIO()
            with contextlib.redirect_stdout(buf):
                exec(compile(code, "docs/python.md", "exec"), ns)
            assert [l.rstrip() for l in buf.getvalue().splitlines()] == expected_output(code), code
    finally:
        os.chdir(cwd)
    assert (tmp_path / "mann-alpha.png").stat().st_size > 10000
    assert (tmp_path / "m-iteration.png").stat().st_size > 10000


def test_the_front_pages_python_runs(tmp_path):
    """README.md's Python block (its five minutes) runs as it stands, from the repository's
    root, and gives what its comments say."""
    found = blocks((SOURCE / "README.md").read_text())
    assert len(found) == 1
    os.symlink(SOURCE / "configs", tmp_path / "configs")
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        ns = {}
        exec(compile(found[0], "README.md", "exec"), ns)
    finally:
        os.chdir(cwd)
    assert ns["image"].shape == (1024, 1024, 3)
    assert "type: chaos-game" in ns["recipe"]
    # The unit circle and Mann's alpha = 0.5 are the defaults: docs/python.md's first point.
    assert ns["pts"].shape == (1, 2)
    assert abs(ns["pts"][0][0] - 1.00030488) < 1e-8 and ns["pts"][0][1] == 0
