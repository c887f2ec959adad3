"""docs/notebook.ipynb, executed as Jupyter runs it (Debian's nbclient and ipykernel): every
cell runs without an error, and its outputs are what the notebook says: the image inline as
the CLI's PNG, validate's dict, the sweep's captions and picture, the dict error by key path,
the widget panel."""

import base64
import io
import os

import numpy as np
import pytest
from PIL import Image

from conftest import SOURCE, run_cli

nbformat = pytest.importorskip("nbformat", reason="Debian's python3-nbformat is not installed")
nbclient = pytest.importorskip("nbclient", reason="Debian's python3-nbclient is not installed")
pytest.importorskip("ipykernel", reason="Debian's python3-ipykernel is not installed")
pytest.importorskip("ipywidgets", reason="Debian's python3-ipywidgets is not installed")


def outputs(cell, kind):
    return [o for o in cell.get("outputs", []) if kind in o.get("data", {}) or o.get("name") == kind]


def test_the_notebook_runs_and_shows_what_it_says(tmp_path):
    os.symlink(SOURCE / "configs", tmp_path / "configs")
    nb = nbformat.read(SOURCE / "docs" / "notebook.ipynb", as_version=4)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    # nbclient 0.7 mimics a front end's Output widgets by reading ipywidgets 7's messages;
    # Debian's ipywidgets 6 sends older ones (no "state"), which it would fail on. The notebook
    # has no Output widget: the mimicry is not needed.
    client.comm_open_handlers.pop("jupyter.widget", None)
    client.execute()
    cells = [c for c in nb.cells if c.cell_type == "code"]
    for c in cells:
        assert not [o for o in c.outputs if o.output_type == "error"], c.source
    # 1. The image, inline: the PNG of `fixpoint render` at the same settings.
    shown = outputs(cells[0], "image/png")
    assert len(shown) == 1
    png = tmp_path / "cli.png"
    r = run_cli("render", "configs/inversion/fig6a.yaml", "-q", "-o", png, "--set", "renderer.width=320", "--set",
                "renderer.height=320", "--set", "renderer.points=2e6", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    inline = np.asarray(Image.open(io.BytesIO(base64.b64decode(shown[0]["data"]["image/png"]))).convert("RGB"))
    assert np.array_equal(inline, np.asarray(Image.open(png).convert("RGB")))
    assert inline.max() > 0
    # 2. validate's dict, nothing written.
    text = outputs(cells[1], "text/plain")[0]["data"]["text/plain"]
    assert "'width': 1024" in text and "'output': 'fig6a.png'" in text and "'exists': False" in text
    assert not (tmp_path / "fig6a.png").exists()
    # 3. The sweep: its captions, and three images side by side.
    printed = "".join(o.get("text", "") for o in cells[2].outputs if o.get("name") == "stdout")
    assert printed == ("(3, 200, 200, 3) ['renderer.iteration.alpha=0.5', 'renderer.iteration.alpha=0.7', "
                       "'renderer.iteration.alpha=0.9']\n")
    strip = Image.open(io.BytesIO(base64.b64decode(outputs(cells[2], "image/png")[0]["data"]["image/png"])))
    assert strip.size == (3 * 200 + 2 * 4, 200)
    # 4. The dict error names its keys.
    printed = "".join(o.get("text", "") for o in cells[3].outputs if o.get("name") == "stdout")
    assert printed == "config['renderer']['maps'][0]['shape']['radius']: must be > 0, got -0.9\n"
    # 5. The panel: a widget, re-rendered for the slider moved.
    printed = "".join(o.get("text", "") for o in cells[4].outputs if o.get("name") == "stdout")
    assert printed == "renderer.maps[0].shape.radius=0.7\n"
    assert outputs(cells[4], "application/vnd.jupyter.widget-view+json")
