"""Shared fixtures of the Python tests: the CLI, the source tree, small renders."""

import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("FIXPOINT_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
CLI = os.environ.get("FIXPOINT_BIN", str(SOURCE / "build" / "bin" / "fixpoint"))

# Paper 02 Fig. 6(b) (the Mann iteration, alpha = 0.7): a render with a scheme in it.
MANN_CONFIG = SOURCE / "configs" / "iterations" / "fig6b.yaml"

MANN_PY = """\
a = 0.7

def step(T, x, y, n):
    tx, ty = T(x, y)
    return (1 - a) * x + a * tx, (1 - a) * y + a * ty
"""


def run_cli(*args, cwd=None):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, cwd=cwd)


@pytest.fixture
def mann_py(tmp_path):
    p = tmp_path / "mann.py"
    p.write_text(MANN_PY)
    return p
