"""fixpoint's Python module: render, eval, plugins, describe, errors."""

import io
import threading
import time

import numpy as np
import pytest
from PIL import Image

import fixpoint
from conftest import CLI, SOURCE, run_cli

FIG6A = SOURCE / "configs" / "inversion" / "fig6a.yaml"
SMALL = {"renderer__width": 160, "renderer__height": 120, "renderer__points": 200000}


def test_render_equals_the_png_the_cli_writes(tmp_path):
    png = tmp_path / "cli.png"
    r = run_cli("render", FIG6A, "-o", png, "--quiet", "--set", "renderer.width=160", "--set",
                "renderer.height=120", "--set", "renderer.points=200000")
    assert r.returncode == 0, r.stderr
    image, recipe = fixpoint.render(FIG6A, **SMALL)
    assert image.dtype == np.uint8 and image.shape == (120, 160, 3)
    from_png = np.asarray(Image.open(png).convert("RGB"))
    assert np.array_equal(image, from_png)
    assert image.max() > 0  # not a black image
    # The recipe is the one the CLI embeds.
    assert recipe == fixpoint.read_recipe(png)


def test_render_writes_the_same_file_as_the_cli(tmp_path):
    cli_png, py_png = tmp_path / "cli.png", tmp_path / "py.png"
    r = run_cli("render", FIG6A, "-o", cli_png, "--quiet", "--set", "renderer.width=160", "--set",
                "renderer.height=120", "--set", "renderer.points=200000")
    assert r.returncode == 0, r.stderr
    fixpoint.render(FIG6A, output=py_png, **SMALL)
    assert py_png.read_bytes() == cli_png.read_bytes()


def test_overrides_sets_dicts_and_yaml_text_agree():
    a, _ = fixpoint.render(FIG6A, **SMALL)
    b, _ = fixpoint.render(FIG6A, sets=["renderer.width=160", "renderer.height=120", "renderer.points=2e5"])
    text = FIG6A.read_text()
    c, _ = fixpoint.render(text, **SMALL)
    assert np.array_equal(a, b) and np.array_equal(a, c)


def test_float32_pixels_quantise_to_the_file_pixels():
    raw, _ = fixpoint.render(FIG6A, dtype="float32", **SMALL)
    image, _ = fixpoint.render(FIG6A, **SMALL)
    assert raw.dtype == np.float32 and raw.shape == image.shape
    assert np.array_equal(fixpoint.quantise(raw), image)
    # Hand-checked corners of the conversion: clamped, rounded to the nearest of 255 steps.
    q = fixpoint.quantise(np.array([[[0.0, 1.0, 0.5], [-1.0, 2.0, 0.2]]], dtype=np.float32))
    assert q.tolist() == [[[0, 255, 128], [0, 255, 51]]]


def test_the_image_does_not_depend_on_threads():
    a, _ = fixpoint.render(FIG6A, threads=1, **SMALL)
    b, _ = fixpoint.render(FIG6A, threads=2, **SMALL)
    assert np.array_equal(a, b)


def test_progress_is_reported_and_reaches_one():
    seen = []
    fixpoint.render(FIG6A, progress=seen.append, renderer__points=6e7, renderer__width=64, renderer__height=64)
    # Reported while rendering (every 0.1 s of a render of about half a second or more), not
    # only the final 1.0 given after it.
    assert len(seen) >= 2 and 0 < seen[0] < 1
    assert seen[-1] == 1.0
    assert all(0 <= f <= 1 for f in seen)
    assert seen == sorted(seen)


def test_an_exception_in_progress_stops_the_render():
    class Stop(Exception):
        pass

    def progress(f):
        raise Stop()

    t0 = time.monotonic()
    with pytest.raises(Stop):
        fixpoint.render(FIG6A, progress=progress, renderer__points=2e9, renderer__width=64, renderer__height=64)
    assert time.monotonic() - t0 < 10  # 2e9 points would take minutes


def test_the_gil_is_released_while_rendering():
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.005)

    t = threading.Thread(target=count)
    t.start()
    try:
        fixpoint.render(FIG6A, renderer__points=2e7, renderer__width=64, renderer__height=64)
    finally:
        done.set()
        t.join()
    assert len(ticks) > 10


def test_eval_inversion_in_the_unit_circle_by_hand():
    t = {"type": "inversion", "shape": {"type": "circle", "centre": [0, 0], "radius": 1}}
    pts = np.array([[2.0, 0.0], [0.5, 0.5], [0.0, -4.0]])
    out = fixpoint.eval(t, pts)
    # p / |p|^2
    assert out.tolist() == [[0.5, 0.0], [1.0, 1.0], [0.0, -0.25]]
    assert pts.tolist() == [[2.0, 0.0], [0.5, 0.5], [0.0, -4.0]]  # input untouched
    # An involution: two steps give the points back.
    assert np.allclose(fixpoint.eval(t, pts, steps=2), pts, rtol=0, atol=1e-15)


def test_eval_mann_by_hand():
    # Mann with alpha = 0.25 on the inversion: p' = 0.75 p + 0.25 p / |p|^2.
    t = "{type: inversion, shape: {type: circle, centre: [0, 0], radius: 1}}"
    out = fixpoint.eval(t, [[2.0, 0.0]], scheme="{type: mann, alpha: 0.25}")
    assert out.tolist() == [[0.75 * 2 + 0.25 * 0.5, 0.0]]
    assert fixpoint.eval(t, np.zeros((0, 2))).shape == (0, 2)


def test_eval_agrees_with_the_cli():
    t = "{type: inversion, shape: {type: star-polygon, points: 5, outer_radius: 1, inner_radius: 0.4}}"
    pts = np.array([[0.3, 0.1], [1.5, -0.7], [-0.2, 0.9]])
    import subprocess

    r = subprocess.run([CLI, "eval", t, "--scheme", "{type: ishikawa, alpha: 0.6, a: 0.3}",
                        "--steps", "5"], input="".join(f"{x!r} {y!r}\n" for x, y in pts),
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    cli = np.array([[float(v) for v in line.split()] for line in r.stdout.splitlines()])
    py = fixpoint.eval(t, pts, scheme="{type: ishikawa, alpha: 0.6, a: 0.3}", steps=5)
    assert np.array_equal(cli, py)


def test_plugins_and_describe():
    ps = fixpoint.plugins()
    names = {p["name"] for p in ps}
    assert {"circle", "mann", "chaos-game", "python-scheme"} <= names
    assert all(p["kind"] == "shape" for p in fixpoint.plugins("shape"))
    d = fixpoint.describe("mann")
    assert d["kind"] == "iteration-scheme"
    alpha = next(p for p in d["params"] if p["name"] == "alpha")
    assert alpha["type"] == "sequence" and alpha["default"] == "0.5" and alpha["doc"]
    circle = fixpoint.describe("circle")
    radius = next(p for p in circle["params"] if p["name"] == "radius")
    assert radius["range"][0] == 0 and radius["range_open"][0]


def test_unknown_plugin_and_kind():
    with pytest.raises(fixpoint.Error, match=r"^unknown plugin 'cirlce' \(did you mean 'circle'\?\)$"):
        fixpoint.describe("cirlce")
    with pytest.raises(fixpoint.Error, match=r"^unknown kind 'shapes'$"):
        fixpoint.plugins("shapes")


def test_bad_config_raises_error_with_file_line_column(tmp_path):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text("renderer:\n  type: chaos-game\n  widht: 100\n")
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render(cfg)
    err = e.value
    assert (err.file, err.line, err.column) == (str(cfg), 3, 3)
    assert err.message == "renderer: unknown parameter 'widht' for chaos-game (did you mean 'width'?)"
    # The same line as the CLI's.
    r = run_cli("render", cfg, "-o", tmp_path / "x.png")
    assert r.returncode != 0 and r.stderr.strip() == str(err)


def test_an_image_shows_inline_as_the_png_the_cli_writes(tmp_path):
    png = tmp_path / "cli.png"
    image, _ = fixpoint.render(FIG6A, output=png, **SMALL)
    assert isinstance(image, np.ndarray) and image.dtype == np.uint8
    shown = image._repr_png_()  # what Jupyter shows for an image at the end of a cell
    assert shown.startswith(b"\x89PNG\r\n")
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(shown)).convert("RGB")), image)
    assert np.array_equal(np.asarray(Image.open(png).convert("RGB")), image)
    # Float pixels show as their 8-bit quantisation; a 16-bit image as 16 bits.
    linear, _ = fixpoint.render(FIG6A, dtype="float32", **SMALL)
    assert np.array_equal(np.asarray(Image.open(io.BytesIO(linear._repr_png_())).convert("RGB")), image)
    deep, _ = fixpoint.render(FIG6A, output__bit_depth=16, **SMALL)
    assert deep.dtype == np.uint16 and deep._repr_png_()[24:26] == b"\x10\x02"  # IHDR: 16 bits, RGB
    # A slice that is still an image shows; one that is not shows as an array.
    assert Image.open(io.BytesIO(image[10:20, 5:25]._repr_png_())).size == (20, 10)
    assert image[:, :, 0]._repr_png_() is None and image[:0]._repr_png_() is None


def test_vary_stacks_the_renders_of_each_value_with_captions():
    sweep = fixpoint.vary(FIG6A, "renderer.seed", [1, 2], **SMALL)
    assert sweep.shape == (2, 120, 160, 3) and sweep.dtype == np.uint8
    assert sweep.captions == ["renderer.seed=1", "renderer.seed=2"] and len(sweep.recipes) == 2
    for k, seed in enumerate((1, 2)):
        one, recipe = fixpoint.render(FIG6A, renderer__seed=seed, **SMALL)
        assert np.array_equal(sweep[k], one) and sweep.recipes[k] == recipe
    assert not np.array_equal(sweep[0], sweep[1])
    strip = Image.open(io.BytesIO(sweep._repr_png_()))
    assert strip.size == (2 * 160 + 3, 120)
    # Every child is checked before the first renders: a bad last value renders nothing.
    calls = []
    with pytest.raises(fixpoint.Error, match=r"renderer\.seed"):
        fixpoint.vary(FIG6A, "renderer.seed", [1, -1], progress=calls.append, **SMALL)
    assert calls == []
    # progress covers the whole sweep, once, upwards.
    fixpoint.vary(FIG6A, "renderer.seed", [1, 2], progress=calls.append, **SMALL)
    assert calls == sorted(calls) and calls[-1] == 1.0 and any(0.4 < c < 0.6 for c in calls)


def test_progress_takes_a_tqdm_bar():
    tqdm = pytest.importorskip("tqdm", reason="Debian's python3-tqdm is not installed")
    bar = tqdm.tqdm(total=100, file=io.StringIO())
    fixpoint.render(FIG6A, progress=bar, **SMALL)
    assert bar.n == pytest.approx(100)
    with pytest.raises(TypeError, match="progress: expected a callable, a tqdm bar or True"):
        fixpoint.render(FIG6A, progress=3, **SMALL)


def test_params_and_interact_read_the_declarations():
    ps = {p["path"]: p for p in fixpoint.params(FIG6A)}
    r = ps["renderer.maps[0].shape.radius"]
    assert (r["kind"], r["value"], r["min"], r["min_open"], r["owner"]) == ("real", "0.65", 0.0, True, "circle")
    assert ps["renderer.width"]["value"] == "1024"
    assert fixpoint.params(FIG6A, renderer__width=64)[1]["value"] == "64"
    pytest.importorskip("ipywidgets", reason="Debian's python3-ipywidgets is not installed")
    panel = fixpoint.interact(FIG6A, **SMALL)
    radius = panel.controls["renderer.maps[0].shape.radius"]
    # An open bound is never offered; the value as written; the overrides are the panel's values.
    assert 0 < radius.min < 0.01 and radius.value == 0.65 and panel.controls["renderer.width"].value == 160
    assert "renderer.view" not in panel.controls  # (a list: no slider)
    first = panel.image.value
    assert first == fixpoint.render(FIG6A, **SMALL)[0]._repr_png_()
    radius.value = 0.7
    assert panel.caption.value == "renderer.maps[0].shape.radius=0.7"
    moved, _ = fixpoint.render(FIG6A, sets=["renderer.maps[0].shape.radius=0.7"], **SMALL)
    assert panel.image.value == moved._repr_png_() != first


def test_validate_checks_as_render_does_and_renders_nothing(tmp_path):
    out = tmp_path / "x.png"
    v = fixpoint.validate(FIG6A, output=out, **SMALL)
    assert (v["width"], v["height"], v["output"], v["exists"], v["streams"]) == (160, 120, str(out), False, False)
    assert v["threads"] >= 1 and v["warnings"] == [] and not out.exists()
    out.write_bytes(b"an earlier render")
    assert fixpoint.validate(FIG6A, output=out)["exists"] is True  # (render() replaces a named file)
    assert out.read_bytes() == b"an earlier render"
    assert fixpoint.validate(FIG6A)["output"] is None
    # Refused as render() refuses: the same line.
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.validate(FIG6A, output=tmp_path / "x.svg")
    with pytest.raises(fixpoint.Error) as r:
        fixpoint.render(FIG6A, output=tmp_path / "x.svg")
    assert str(e.value) == str(r.value) and not (tmp_path / "x.svg").exists()
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.validate({"renderer": {"type": "chaos-game"}})
    assert str(e.value) == "config['renderer']: missing required parameter 'maps' for chaos-game"
    # The memory plan: too large for 24M whole, written in strips without pixels, refused with them.
    big = {"renderer__width": 4000, "renderer__height": 4000}
    assert fixpoint.validate(FIG6A, output=tmp_path / "big.png", pixels=False, memory="24M", **big)["streams"]
    with pytest.raises(fixpoint.Error, match="memory"):
        fixpoint.validate(FIG6A, memory="24M", **big)
    assert not (tmp_path / "big.png").exists()


def test_errors_in_dict_configs_name_the_key_path():
    # A dict has no lines and columns the user saw: the error names its keys as Python does.
    cfg = {"renderer": {"type": "chaos-game", "width": 64, "height": 64, "points": 1000,
                        "maps": [{"type": "inversion", "shape": {"type": "circle", "radius": -0.9}}]}}
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render(cfg)
    assert str(e.value) == "config['renderer']['maps'][0]['shape']['radius']: must be > 0, got -0.9"
    assert e.value.keys == ("renderer", "maps", 0, "shape", "radius")
    assert (e.value.file, e.value.line, e.value.column) == (None, None, None)
    cfg["renderer"]["maps"][0]["shape"]["radius"] = 0.9
    cfg["renderer"]["mapz"] = 1
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render(cfg)
    assert str(e.value) == "config['renderer']: unknown parameter 'mapz' for chaos-game (did you mean 'maps'?)"
    # eval's dicts by the argument's name.
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.eval({"type": "inversion", "shape": {"type": "circle", "radius": -1}}, [[1, 2]])
    assert str(e.value) == "transform['shape']['radius']: must be > 0, got -1"
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.eval({"type": "inversion", "shape": {"type": "circle"}}, [[1, 2]], scheme={"type": "mann", "alpha": "x"})
    assert str(e.value).startswith("scheme['alpha']: cannot read 'x' as a number")
    # YAML text keeps its line and column, and the key path is there too.
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render("{renderer: {type: chaos-game, width: -1}}")
    assert str(e.value) == "<config>:1:38: renderer.width: must be in [1, 65536], got -1"
    assert (e.value.line, e.value.column, e.value.keys) == (1, 38, ("renderer", "width"))


def test_bad_override_and_bad_arguments(tmp_path):
    with pytest.raises(fixpoint.Error) as e:
        fixpoint.render(FIG6A, renderer__points="many")
    # As the CLI's --set: the error names the assignment, which has no file position.
    assert str(e.value) == "--set renderer.points=many: renderer.points: expected an integer, got 'many'"
    assert e.value.file is None and e.value.message == str(e.value)
    with pytest.raises(TypeError):
        fixpoint.render(42)
    with pytest.raises(fixpoint.Error, match="eval: points must be an array of shape"):
        fixpoint.eval("{type: inversion, shape: {type: circle}}", np.zeros((3, 3)))


def test_output_is_checked_before_rendering(tmp_path):
    with pytest.raises(fixpoint.Error, match="x.jpg"):
        fixpoint.render(FIG6A, output=tmp_path / "x.jpg", **SMALL)
    assert not (tmp_path / "x.jpg").exists()


def test_add_plugin_dir_skips_a_broken_file_with_a_warning(tmp_path):
    (tmp_path / "broken.so").write_bytes(b"not a shared library")
    with pytest.warns(RuntimeWarning, match=r"^plugin file skipped: .*broken\.so"):
        fixpoint.add_plugin_dir(tmp_path)
    # Everything else still works.
    assert fixpoint.describe("circle")["kind"] == "shape"
    with pytest.raises(fixpoint.Error, match=r"^plugin folder '.*nowhere' is not a folder$"):
        fixpoint.add_plugin_dir(tmp_path / "nowhere")
