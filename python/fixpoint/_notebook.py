"""What a notebook reaches for: progress bars, a sweep as one stacked array, widgets."""

import numpy as np

from ._picture import Picture


class Progress:
    """render()'s progress= as a callback: a callable (given the fraction done, 0 to 1), a
    tqdm bar (its ``total`` taken as 100 % of the render), or True for a new tqdm bar
    (tqdm.auto, so a notebook gets its widget; closed at the end). None: no progress.
    """

    def __init__(self, progress, what="render"):
        self.bar, self.own, self.call = None, False, None
        if progress is True:
            self.bar = _tqdm()(total=100, desc=what, unit="%", bar_format="{l_bar}{bar}| {elapsed}")
            self.own = True
        elif progress is not None and hasattr(progress, "update") and hasattr(progress, "total"):
            self.bar = progress
        elif progress is not None and not callable(progress):
            raise TypeError(f"progress: expected a callable, a tqdm bar or True, got {type(progress).__name__}")
        else:
            self.call = progress

    def callback(self):
        """A callable taking the fraction done of the whole (0 to 1), or None."""
        if self.bar is None:
            return self.call
        start, total = self.bar.n, self.bar.total or 100

        def update(fraction):
            target = start + fraction * (total - start)
            if target > self.bar.n:
                self.bar.update(target - self.bar.n)
        return update

    def close(self):
        if self.own:
            self.bar.close()


def _tqdm():
    """tqdm's bar: its notebook widget where it works (tqdm.auto, with ipywidgets 7 or later),
    else its text bar (Debian 12's ipywidgets is 6, whose progress widget tqdm cannot style)."""
    try:
        import tqdm.std
    except ImportError:
        raise ImportError("progress=True draws a tqdm bar: install tqdm (Debian: python3-tqdm), "
                          "or pass a callable") from None
    try:
        import ipywidgets
        if int(ipywidgets.__version__.split(".")[0]) >= 7:
            import tqdm.auto
            return tqdm.auto.tqdm
    except (ImportError, ValueError):
        pass
    return tqdm.std.tqdm


class Sweep(Picture):
    """vary()'s result: the images stacked, shape (k, height, width, 3), with ``captions``
    ("PATH=VALUE", one per image) and ``recipes``; a notebook shows them side by side."""

    def __array_finalize__(self, obj):
        self.captions = getattr(obj, "captions", None)
        self.recipes = getattr(obj, "recipes", None)

    def _repr_png_(self):
        a = np.asarray(self)
        if a.ndim != 4 or a.shape[0] == 0:
            return None
        gap = np.zeros((a.shape[1], max(1, a.shape[2] // 50), 3), a.dtype)
        row = np.concatenate([x for img in a for x in (img, gap)][:-1], axis=1)
        return Picture(row)._repr_png_()


def vary(render, validate, yaml, config, path, values, progress=None, **kw):
    """The body of fixpoint.vary (see there)."""
    values = list(values)
    if not values:
        raise ValueError("vary: no values")
    captions = [f"{path}={yaml(v)}" for v in values]
    sets = list(kw.pop("sets", ()))
    # Every child is checked before the first renders, as `fixpoint render --vary` does.
    for c in captions:
        validate(config, sets=sets + [c], **kw)
    bar = Progress(progress, "vary")
    cb, images, recipes = bar.callback(), [], []
    try:
        for i, c in enumerate(captions):
            share = None if cb is None else (lambda f, i=i: cb((i + f) / len(captions)))
            img, recipe = render(config, sets=sets + [c], progress=share, **kw)
            images.append(np.asarray(img))
            recipes.append(recipe)
    finally:
        bar.close()
    if len({i.shape for i in images}) != 1:
        raise ValueError(f"vary: the images differ in size ({sorted({i.shape for i in images})}): "
                         "vary a parameter that keeps the size")
    out = np.stack(images).view(Sweep)
    out.captions, out.recipes = captions, recipes
    return out


def interact(render, params, yaml, config, sets=(), **kw):
    """The body of fixpoint.interact (see there)."""
    try:
        import ipywidgets as w
    except ImportError:
        raise ImportError("interact() builds ipywidgets: install them (Debian: python3-ipywidgets)") from None
    # (keyword overrides, renderer__points=..., are sets for the panel too: its values are the
    # render's)
    sets = list(sets) + [f"{k.replace('__', '.')}={yaml(v)}" for k, v in kw.items() if "__" in k]
    kw = {k: v for k, v in kw.items() if "__" not in k}
    controls = {}
    for p in params(config, sets=sets):
        c = _control(w, p)
        if c is not None:
            controls[p["path"]] = c
    image = w.Image(format="png")
    caption = w.Label()

    def show(_=None):
        changed = [f"{path}={c.value if not isinstance(c.value, bool) else str(c.value).lower()}"
                   for path, c in controls.items() if c.value != c.start]
        try:
            img, _recipe = render(config, sets=sets + changed, **kw)
        except Exception as e:  # a value the plugin refuses: said, and the last image kept
            caption.value = str(e)
            return
        image.value = img._repr_png_()
        caption.value = ", ".join(changed) or "the config as written"

    for c in controls.values():
        c.observe(show, names="value")
    show()
    box = w.VBox([w.VBox(list(controls.values())), image, caption])
    box.controls, box.image, box.caption, box.update = controls, image, caption, show
    return box


def _control(w, p):
    """A widget for a parameter that has one: ranged numbers (a slider), flags, choices."""
    desc = dict(description=p["name"], description_tooltip=f"{p['path']}: {p['description']}",
                layout=w.Layout(width="480px"), continuous_update=False)
    kind, value = p["kind"], p["value"]
    try:
        if kind == "bool":
            c = w.Checkbox(value=value == "true", description=p["name"], indent=False)
        elif kind == "choice":
            c = w.Dropdown(options=p["choices"], value=value, description=p["name"])
        elif kind in ("int", "real") or (kind == "sequence" and value and value[0] not in "[" and "q" not in value):
            v = float(value)
            lo, hi, step = _bounds(v, p, kind == "int")
            if kind == "int":
                c = w.IntSlider(value=int(v), min=int(lo), max=int(hi), **desc)
            else:
                c = w.FloatSlider(value=v, min=lo, max=hi, step=step, readout_format=".4g", **desc)
        else:
            return None
    except (ValueError, TypeError):
        return None  # (a value written in a form this panel does not edit)
    c.start = c.value
    return c


def _bounds(v, p, integer):
    """A slider's ends: the declared range where it is finite, else about the value (an open
    end moved in by a step, so that the slider never offers the excluded bound). The range is
    the declared one where it is near the value (alpha in (0, 1)), else twice the value's size
    about it (a width of 1024 in [1, 65536] slides over [1, 3072])."""
    span = max(1.0, abs(v)) * 2
    lo = v - span if p["min"] is None else max(p["min"], v - span)
    hi = v + span if p["max"] is None else min(p["max"], v + span)
    step = 1 if integer else (hi - lo) / 500
    if p["min"] is not None and p["min_open"]:
        lo += step
    if p["max"] is not None and p["max_open"]:
        hi -= step
    return lo, hi, step
