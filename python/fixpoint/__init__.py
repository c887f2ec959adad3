"""fixpoint from Python: render configs to numpy arrays, evaluate maps and schemes on points,
list and describe the plugins.

    import fixpoint
    image, recipe = fixpoint.render("configs/inversion/fig6a.yaml", renderer__points=1e6)

Bad input raises fixpoint.Error, whose ``file``, ``line`` and ``column`` point into the
config; its text is the CLI's error line. See docs/python.md.
"""

import json
import os
import warnings as _warnings

from ._errors import Error
from . import _fixpoint

__version__ = _fixpoint.__version__
__all__ = ["Error", "render", "validate", "params", "vary", "interact", "eval", "plugins", "describe", "add_plugin_dir", "quantise", "read_recipe"]


def _warn():
    for w in _fixpoint.take_warnings():
        _warnings.warn(w, RuntimeWarning, stacklevel=3)


def _yaml(value):
    """A Python value as YAML text (JSON is YAML); strings are taken as YAML already."""
    if isinstance(value, str):
        return value
    if isinstance(value, float) and value.is_integer() and abs(value) < 2**53:
        return str(int(value))  # 1e6 -> 1000000: integer parameters take it
    return json.dumps(value)


def _placed(error, config):
    """The error to raise for `config`: a dict's names its key path (fixpoint.Error says why)."""
    return Error(str(error), source="<config>") if isinstance(config, dict) else error


def _config(config):
    """(text or path, is_text) for a path, a YAML string or a dict."""
    if isinstance(config, dict):
        return json.dumps(config), True
    if isinstance(config, os.PathLike):
        return os.fspath(config), False
    if isinstance(config, str):
        # A YAML document has a newline or is a flow mapping; anything else is a path.
        if "\n" in config or config.lstrip().startswith("{"):
            return config, True
        return config, False
    raise TypeError(f"config: expected a path, a YAML string or a dict, got {type(config).__name__}")


def render(config, *, sets=(), threads=0, progress=None, output=None, dtype=None, allow_python=False,
           pixels=True, memory=None, checkpoint=None, checkpoint_every=None, resume=None, strict=False,
           **overrides):
    """Render a config and return ``(image, recipe)``.

    config     a config file (or an image fixpoint wrote: its recipe), YAML text, or a dict.
    sets       overrides as the CLI's --set takes them: ["renderer.points=1e6", ...].
    overrides  the same as keywords, with ``__`` for the dots: renderer__points=1e6;
               values are YAML text or Python values (lists, numbers).
    threads    worker threads (0: all the machine has, or one for a python-scheme, whose Python
               runs one batch at a time); the image does not depend on it.
    progress   called with the fraction done (0 to 1), from this thread, about ten times a
               second; an exception it raises stops the render and is raised here. A tqdm
               bar moves through its total; True draws a new one (tqdm.auto: a notebook's
               widget), where tqdm is installed.
    output     also write the image there, with its recipe, as ``fixpoint render -o`` does
               (``output.tiled`` of the config included).
    pixels     False: only write ``output`` and return ``(None, recipe)``; an image too large
               for memory then renders in strips, as ``fixpoint render`` streams one.
    memory, checkpoint, checkpoint_every, resume
               as the CLI's --memory ("8G"), --checkpoint FILE, --checkpoint-every ("5m") and
               --resume FILE: the same render job, the same checks and bytes.
    dtype      None: the pixels as the image file stores them (uint8, or uint16 for
               ``output.bit_depth: 16``), equal to the PNG's; "float32": linear floats.
    allow_python  run the Python of a python-scheme in an image's recipe (refused by
               default, as ``fixpoint render --allow-python``: an image may come from anywhere).
    strict     refuse a recipe whose image may differ from the one it was made of (an older
               render version whose changes touch it), as ``fixpoint render --strict``.

    The GIL is released while rendering; Ctrl-C stops the render (KeyboardInterrupt).
    ``render.last_stats`` holds the last render's summary (points, restarts, ...).
    """
    text, is_text = _config(config)
    assignments = list(sets) + [f"{k.replace('__', '.')}={_yaml(v)}" for k, v in overrides.items()]
    if dtype not in (None, "float32"):
        raise ValueError(f"dtype: expected None or 'float32', got {dtype!r}")
    try:
        job = {k: os.fspath(v) if isinstance(v, os.PathLike) else str(v)
               for k, v in [("memory", memory), ("checkpoint", checkpoint),
                            ("checkpoint_every", checkpoint_every), ("resume", resume),
                            ("strict", "true" if strict else None)] if v is not None}
        from ._notebook import Progress

        bar = Progress(progress)
        try:
            image, recipe, stats, warns, bit_depth = _fixpoint.render(
                text, is_text, assignments, int(threads), bar.callback(), os.fspath(output) if output else "",
                bool(allow_python), bool(pixels), job)
        finally:
            bar.close()
    except Error as e:
        raise _placed(e, config) from None
    finally:
        _warn()
    for w in warns:
        _warnings.warn(w, RuntimeWarning, stacklevel=2)
    render.last_stats = stats
    if image is None:
        return image, recipe
    from ._picture import Picture  # (numpy, only once an image is returned)

    return Picture(image if dtype == "float32" else _fixpoint.quantise(image, bit_depth)), recipe


render.last_stats = None


def validate(config, *, sets=(), threads=0, output=None, memory=None, allow_python=False, pixels=True,
             **overrides):
    """Check ``config`` as ``render()`` would (schemas, the plugins' checks, the output path,
    the memory plan) and render nothing, as ``fixpoint validate``. Raises fixpoint.Error
    where render() would; else returns a dict: ``width``, ``height``, ``output`` (the file
    render(output=...) would write, or None), ``exists`` (that file is there: render()
    replaces it), ``threads``, ``streams`` (with pixels=False, too large for ``memory`` whole:
    render() would write it in strips) and ``warnings``. Arguments as render()'s.
    """
    text, is_text = _config(config)
    assignments = list(sets) + [f"{k.replace('__', '.')}={_yaml(v)}" for k, v in overrides.items()]
    try:
        return _fixpoint.validate(text, is_text, assignments, int(threads), os.fspath(output) if output else "",
                                  bool(allow_python), str(memory) if memory is not None else "", bool(pixels))
    except Error as e:
        raise _placed(e, config) from None
    finally:
        _warn()


def params(config, *, sets=(), **overrides):
    """Every parameter of a config, in the order of its tree, as dicts: ``path`` (as sets=
    takes it), ``name``, ``owner`` (the plugin that declares it), ``kind`` (bool, int, real,
    choice, colour, point, sequence, plugin, list, ...), ``value`` (as written, else the
    default; flow YAML), ``written``, ``default``, ``min``/``max`` (the declared range, or
    None) with ``min_open``/``max_open``, ``choices``, ``description``: what serve's page
    and interact() build their controls from."""
    text, is_text = _config(config)
    assignments = list(sets) + [f"{k.replace('__', '.')}={_yaml(v)}" for k, v in overrides.items()]
    try:
        return _fixpoint.params(text, is_text, assignments)
    finally:
        _warn()


def vary(config, path, values, *, progress=None, **kw):
    """Render ``config`` once per value of the parameter at ``path`` ("renderer.iteration.alpha")
    and return the images stacked, shape (k, height, width, 3), with ``.captions``
    ("PATH=VALUE") and ``.recipes``; a notebook shows them side by side. Values are Python
    values or YAML text; the other arguments are render()'s. Every child is validated before
    the first renders (as ``fixpoint render --vary``); ``progress`` covers the whole sweep.
    """
    from ._notebook import vary as run

    return run(render, validate, _yaml, config, path, values, progress=progress, **kw)


def interact(config, *, sets=(), **kw):
    """Sliders, checkboxes and menus (ipywidgets) for a config's ranged numbers, flags and
    choices, read from the plugins' declarations (params()), over its image: each change
    renders again with that value. Returns the widget box (``.controls`` maps each path to its
    widget, ``.image`` is the picture, ``.caption`` says what changed or what was refused).
    Other arguments are render()'s: draft-sized overrides (renderer__points=...) keep it quick.
    """
    from ._notebook import interact as run

    return run(render, params, _yaml, config, sets=sets, **kw)


def eval(transform, points, scheme="{type: picard}", steps=1):  # noqa: A001 (the CLI's name)
    """Apply ``steps`` steps of ``scheme`` with ``transform`` to points, as ``fixpoint eval``.

    transform, scheme  plugin instances as YAML text ("{type: inversion, shape: ...}") or dicts.
    points             an array of shape (n, 2); computed in double precision.
    Returns a new float64 array of shape (n, 2).
    """
    import numpy as np

    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim == 1 and pts.shape[0] == 2:
        pts = pts.reshape(1, 2)
    try:
        return _fixpoint.eval(_yaml(transform), _yaml(scheme), pts, int(steps))
    except Error as e:
        for value, name in ((transform, "transform"), (scheme, "scheme")):
            if isinstance(value, dict) and e.file == f"<{name}>":
                raise Error(str(e), source=f"<{name}>", name=name) from None
        raise
    finally:
        _warn()


def plugins(kind=None):
    """Every plugin found, as dicts (name, kind, version, summary, file); only ``kind`` if given."""
    try:
        return _fixpoint.plugins(kind)
    finally:
        _warn()


def describe(name):
    """A plugin's description: its plugins() entry plus ``params`` (name, type, default, range,
    doc, ...) and ``example``."""
    try:
        return _fixpoint.describe(name)
    finally:
        _warn()


def add_plugin_dir(path):
    """Load the plugins of another folder (as the CLI's --plugin-dir)."""
    _fixpoint.add_plugin_dir(os.fspath(path))
    _warn()


def quantise(pixels, bit_depth=8):
    """Float pixels as an image file of ``bit_depth`` (8 or 16) stores them."""
    return _fixpoint.quantise(pixels, int(bit_depth))


def read_recipe(path):
    """The recipe fixpoint embedded in an image it wrote."""
    return _fixpoint.read_recipe(os.fspath(path))
