"""The Python module renders through the host's render job, as the CLI does: the same checks,
the same files (output.tiled honoured), strips beyond memory, checkpoints."""

import numpy as np
import pytest

import fixpoint
from conftest import SOURCE, run_cli

FIG6A = SOURCE / "configs" / "inversion" / "fig6a.yaml"
SETS = ["renderer.width=300", "renderer.height=200", "renderer.points=200000"]


def cli_render(out, *extra):
    args = ["render", FIG6A, "-o", out, "--quiet"]
    for s in SETS:
        args += ["--set", s]
    r = run_cli(*args, *extra)
    assert r.returncode == 0, r.stderr
    return out.read_bytes()


def test_output_tiled_is_honoured(tmp_path):
    # A tiled TIFF: the CLI's file, byte for byte (the job writes both).
    want = cli_render(tmp_path / "cli.tif", "--set", "output.tiled=true")
    fixpoint.render(FIG6A, sets=SETS + ["output.tiled=true"], output=tmp_path / "py.tif")
    got = (tmp_path / "py.tif").read_bytes()
    assert got == want
    # ... and not the untiled file.
    assert got != cli_render(tmp_path / "plain.tif")
    # Tiles for a PNG are refused at output.tiled, as by the CLI, before anything renders.
    with pytest.raises(fixpoint.Error, match="output.tiled: .*only TIFF and EXR images have tiles"):
        fixpoint.render(FIG6A, sets=SETS + ["output.tiled=true"], output=tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()


def test_beyond_memory_it_streams_in_strips(tmp_path):
    # As tests/cli/test_strips.cpp's set_colour_last: fig6a at its size in 30 MiB is in strips.
    points = ["renderer.points=400000"]
    r = run_cli("render", FIG6A, "-o", tmp_path / "whole.png", "--quiet", "--threads", "2", "--set", points[0])
    assert r.returncode == 0, r.stderr
    image, recipe = fixpoint.render(FIG6A, sets=points, output=tmp_path / "strips.png", pixels=False,
                                    memory="30M", threads=2)
    assert image is None and "renderer:" in recipe
    assert " strips of " in fixpoint.render.last_stats["how"]
    assert (tmp_path / "strips.png").read_bytes() == (tmp_path / "whole.png").read_bytes()
    # With the pixels asked for, the whole image must fit: refused before the render.
    with pytest.raises(fixpoint.Error, match="needs .* of memory"):
        fixpoint.render(FIG6A, sets=points, output=tmp_path / "x.png", memory="30M", threads=2)
    assert not (tmp_path / "x.png").exists()
    with pytest.raises(fixpoint.Error, match="pixels=False needs an output"):
        fixpoint.render(FIG6A, sets=SETS, pixels=False)


def test_checkpoints_resume_to_the_same_image(tmp_path):
    full, _ = fixpoint.render(FIG6A, sets=SETS)
    ck = tmp_path / "r.ckpt"
    half, _ = fixpoint.render(FIG6A, sets=SETS[:2] + ["renderer.points=100000"], checkpoint=ck)
    assert fixpoint.render.last_stats["checkpoints"] >= 1 and ck.exists()
    assert not np.array_equal(half, full)
    resumed, _ = fixpoint.render(FIG6A, sets=SETS, resume=ck)
    assert np.array_equal(resumed, full)
    # The same checks as the CLI's: a checkpoint there already is not written over.
    with pytest.raises(fixpoint.Error, match="exists: continue it with --resume"):
        fixpoint.render(FIG6A, sets=SETS, checkpoint=ck)


def test_an_older_recipe_warns_and_strict_refuses_it(tmp_path):
    # A recipe of render version 1 (no render_version: key) with paper 01's rules, which
    # version 2 changed: a RuntimeWarning naming the change, and with strict=True the CLI's
    # refusal (render_version.hpp).
    old = tmp_path / "old.yaml"
    old.write_text('fixpoint_version: "0.1.0"\n' + FIG6A.read_text())
    with pytest.warns(RuntimeWarning, match="the recipe is of render version 1, this fixpoint renders version"):
        image, recipe = fixpoint.render(old, sets=SETS)
    assert "\nrender_version: " in recipe
    with pytest.raises(fixpoint.Error, match=r"old\.yaml:1:1: the recipe is of render version 1.*refused \(--strict\)"):
        fixpoint.render(old, sets=SETS, strict=True)
    # The recipe it made is of this version: strict renders it, to the same pixels.
    again, _ = fixpoint.render(recipe, strict=True)
    assert np.array_equal(again, image)
