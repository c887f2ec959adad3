"""The preview page of `fixpoint serve` in headless Chromium: it shows the config's image as
it refines, changes the YAML through its controls (a slider, the wheel, a drag), shows a
refused config at its line with the CLI's text, saves, renders the bytes the CLI renders, and
opens a dropped image's recipe. Each test leaves screenshots in its tmp folder (shots/)."""

import contextlib
import math
import re
import shutil

import pytest
from conftest import SOURCE, Page, Server, pixels, run_cli

# fig4a.yaml's lines (1-based) that the tests change.
MAP0 = 29  # - {type: inversion, shape: {type: circle, centre: [1, 1], radius: 1}, colour: "#ff6b6b"}
MAP4 = 34  # - {..., centre: [0.30667, 0], radius: 0.21685}, colour: "#ff9f43"}
VIEW = 20  # view: [-1.75, 1.75, -1.75, 1.75]


def changed_lines(a, b):
    la, lb = a.split("\n"), b.split("\n")
    assert len(la) == len(lb)
    return [i + 1 for i, (x, y) in enumerate(zip(la, lb)) if x != y]


def numbers(line):
    return [float(x) for x in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", line)]


def slide(page, path, value):
    """Move the slider of `path` to `value` as a user's drag does: input, then change."""
    page.js("""const s = document.querySelector(`input[type=range][data-path="${arguments[0]}"]`);
               s.value = arguments[1];
               s.dispatchEvent(new Event('input', {bubbles: true}));
               s.dispatchEvent(new Event('change', {bubbles: true}));""", path, value)


def status(page):
    return page.js("return document.getElementById('status').textContent")


def wheel(page, fx, fy, delta):
    """A wheel step of `delta` at the fraction (fx, fy) of the image box; returns where the
    cursor was, as fractions (Chromium keeps clientX and clientY as integers: whole pixels)."""
    return page.js("""const b = document.getElementById('imgbox').getBoundingClientRect();
               const x = Math.round(b.left + arguments[0] * b.width), y = Math.round(b.top + arguments[1] * b.height);
               document.getElementById('frame').dispatchEvent(new WheelEvent('wheel', {
                 deltaY: arguments[2], clientX: x, clientY: y, bubbles: true, cancelable: true}));
               return [(x - b.left) / b.width, (y - b.top) / b.height];""", fx, fy, delta)


@contextlib.contextmanager
def serving(browser, tmp_path, config, name):
    """The page of a server whose folder holds a copy of configs/`config` as `name`."""
    root = tmp_path / "root"
    root.mkdir()
    shutil.copy(SOURCE / "configs" / config, root / name)
    s = Server(root, name)
    try:
        shots = tmp_path / "shots"
        shots.mkdir()
        yield Page(browser, s.url, shots)
    finally:
        assert s.stop() == 0


def test_first_image_refines_to_the_cli_render(page, root):
    assert page.text() == (root / "fig4a.yaml").read_text()
    page.wait_done()
    png = page.image_bytes()
    im = pixels(png).convert("RGB")
    assert im.size == (1024, 1024)
    assert len(im.getcolors(1 << 24)) > 100  # an image, not a blank canvas
    # The last stage is the full render: the pixels `fixpoint render` makes of the same file.
    assert run_cli("render", "fig4a.yaml", "-o", "cli.png", "-q", cwd=root).returncode == 0
    assert pixels((root / "cli.png").read_bytes()).convert("RGB").tobytes() == im.tobytes()
    caption = page.js("return document.getElementById('caption').textContent")
    assert re.fullmatch(r"stage (\d+)/\1 · 1024×1024 · [0-9.]+ samples/px · [0-9.]+ s", caption), caption
    # Shown at the config's aspect (square), inside the pane.
    w, h = page.js("const b = document.getElementById('imgbox'); return [b.clientWidth, b.clientHeight]")
    assert w == h and w > 300
    # The panel has the parameters of the config, values as written.
    assert page.js("return document.querySelector('input[type=number][data-path=\"renderer.width\"]').value") == "1024"
    assert page.js("return document.querySelector('button[data-path=\"renderer.maps\"]').textContent") == "add"
    page.shot("first")


def test_slider_changes_that_line_and_the_image(page):
    first = page.wait_done()
    before = page.image_bytes()
    text = page.text()
    slide(page, "renderer.maps[4].shape.radius", "0.3")
    page.wait(lambda: page.text() != text, what="the edited text")
    new = page.text()
    assert changed_lines(text, new) == [MAP4]
    assert new.split("\n")[MAP4 - 1] == text.split("\n")[MAP4 - 1].replace("radius: 0.21685", "radius: 0.3")
    page.wait_done(other_than=first)
    after = page.image_bytes()
    assert pixels(after).convert("RGB").tobytes() != pixels(before).convert("RGB").tobytes()
    assert page.js("return document.querySelector('input[type=number][data-path=\"renderer.maps[4].shape.radius\"]')"
                   ".value") == "0.3"
    page.shot("slider")


def test_a_tone_slider_retones_the_kept_histogram(page):
    # Only a finishing parameter changes (the colourer's vibrancy): one stage, finished from the
    # full render's kept histogram, and the caption says so (docs/histograms.md).
    first = page.wait_done()
    before = page.image_bytes()
    text = page.text()
    slide(page, "renderer.colourer.vibrancy", "0.4")
    page.wait(lambda: page.text() != text, what="the edited text")
    page.wait_done(other_than=first)
    caption = page.js("return document.getElementById('caption').textContent")
    assert re.fullmatch(r"stage 1/1 · 1024×1024 · [0-9.]+ samples/px · [0-9.]+ s · re-toned, no iterating",
                        caption), caption
    assert page.js("return document.getElementById('frame').dataset.retoned") == "1"
    after = page.image_bytes()
    assert pixels(after).convert("RGB").tobytes() != pixels(before).convert("RGB").tobytes()
    page.shot("retoned")


def test_typo_shows_the_cli_error_at_its_line(page, tmp_path):
    page.wait_done()
    src = page.js("return document.getElementById('frame').src")
    text = page.text()
    bad = text.replace('radius: 1}, colour: "#ffd93d"', 'raduis: 1}, colour: "#ffd93d"')
    assert bad != text
    page.set_text(bad)
    shown = page.wait(lambda: page.js("const e = document.getElementById('error'); return !e.hidden && e.textContent"),
                      what="the error")
    # The CLI's line for the same file.
    cli = tmp_path / "cli"
    cli.mkdir()
    (cli / "fig4a.yaml").write_text(bad)
    r = run_cli("render", "fig4a.yaml", "-o", "x.png", cwd=cli)
    assert r.returncode == 2
    assert shown == r.stderr.decode().strip()
    assert shown.startswith("fig4a.yaml:30:")
    assert page.js("return [...document.querySelectorAll('#gutter .error')].map((e) => e.textContent)") == ["30"]
    assert page.js("return document.getElementById('error-band').hidden") is False
    # The last good image stays, dimmed: it is not this text's.
    assert page.js("return document.getElementById('frame').src") == src
    assert page.js("return document.getElementById('imgbox').classList.contains('stale')")
    assert float(page.js("return getComputedStyle(document.getElementById('frame')).opacity")) < 0.5
    page.shot("typo")
    page.set_text(text)
    page.wait(lambda: page.js("return document.getElementById('error').hidden"), what="the error to clear")
    assert page.js("return document.querySelectorAll('#gutter .error').length") == 0
    assert not page.js("return document.getElementById('imgbox').classList.contains('stale')")


def test_wheel_zooms_about_the_cursor(page):
    first = page.wait_done()
    text = page.text()
    u, v = wheel(page, 0.25, 0.25, -100)
    page.wait(lambda: page.text() != text, what="the new view")
    new = page.text()
    assert changed_lines(text, new) == [VIEW]
    line = new.split("\n")[VIEW - 1]
    assert line.startswith("  view: [")
    # The plane point under the cursor stays; the view shrinks by e^-0.2 about it.
    f = math.exp(-0.2)
    x, y = -1.75 + u * 3.5, 1.75 - v * 3.5
    want = [x + (-1.75 - x) * f, x + (1.75 - x) * f, y + (-1.75 - y) * f, y + (1.75 - y) * f]
    # Written to a tenth of the new view's pixel (3.5 f / 1024 = 0.0028: 4 decimals), no more.
    assert numbers(line) == pytest.approx(want, abs=0.00005 + 1e-12)
    assert max(len(x.split(".")[1]) if "." in x else 0 for x in line.split("[")[1].rstrip("]").split(", ")) <= 4
    page.wait_done(other_than=first)
    assert page.js("return document.getElementById('frame').style.transform") == ""
    page.shot("wheel")


def test_drag_pans(page):
    first = page.wait_done()
    text = page.text()
    w = page.js("""const b = document.getElementById('imgbox').getBoundingClientRect();
                   const f = document.getElementById('frame');
                   const at = (type, dx, dy) => f.dispatchEvent(new MouseEvent(type, {button: 0, bubbles: true,
                     clientX: b.left + b.width / 2 + dx, clientY: b.top + b.height / 2 + dy}));
                   at('mousedown', 0, 0); at('mousemove', 50, 20); at('mousemove', 100, 40); at('mouseup', 100, 40);
                   return b.width;""")
    page.wait(lambda: page.text() != text, what="the new view")
    new = page.text()
    assert changed_lines(text, new) == [VIEW]
    # Dragged right and down: the view moves left and up (y grows upward).
    dx, dy = 100 / w * 3.5, 40 / w * 3.5
    # (To a tenth of a pixel, 3.5 / 1024: 4 decimals.)
    assert numbers(new.split("\n")[VIEW - 1]) == pytest.approx([-1.75 - dx, 1.75 - dx, -1.75 + dy, 1.75 + dy],
                                                               abs=0.00005 + 1e-12)
    page.wait_done(other_than=first)
    page.shot("drag")


def prompt_answer(page, text):
    a = page.wait(lambda: _alert(page), what="a prompt")
    if text is not None:
        a.send_keys(text)
    a.accept()


def _alert(page):
    try:
        return page.d.switch_to.alert
    except Exception:
        return None


def test_save_then_render_gives_the_cli_bytes(page, root):
    first = page.wait_done()
    text = page.text()
    slide(page, "renderer.maps[0].shape.radius", "0.9")
    page.wait(lambda: page.text() != text, what="the edited text")
    assert changed_lines(text, page.text()) == [MAP0]
    page.wait_done(other_than=first)
    page.js("document.getElementById('save').click()")
    page.wait(lambda: status(page) == "saved fig4a.yaml", what="the save")
    assert (root / "fig4a.yaml").read_text() == page.text()

    page.js("document.getElementById('render').click()")
    prompt_answer(page, "page.png")
    page.wait(lambda: status(page).startswith("wrote page.png in "), what="the render")
    assert page.js("return document.getElementById('log').hidden") is False
    # Again: the file exists, the page asks, and replaces it.
    page.js("document.getElementById('render').click()")
    prompt_answer(page, "page.png")
    prompt_answer(page, None)  # "... Replace it?"
    page.wait(lambda: status(page).startswith("wrote page.png in "), what="the second render")

    r = run_cli("render", "fig4a.yaml", "-o", "cli.png", "-q", cwd=root)
    assert r.returncode == 0, r.stderr
    assert (root / "page.png").read_bytes() == (root / "cli.png").read_bytes()
    page.shot("render")


def test_dropped_image_opens_its_recipe(page, root):
    first = page.wait_done()
    r = run_cli("render", "fig4a.yaml", "-o", "other.png", "-q", "--set", "renderer.maps[0].shape.radius=0.8",
                cwd=root)
    assert r.returncode == 0
    recipe = run_cli("recipe", "other.png", cwd=root)
    assert recipe.returncode == 0
    data = (root / "other.png").read_bytes()
    page.js("""const bytes = Uint8Array.from(atob(arguments[0]), (c) => c.charCodeAt(0));
               const dt = new DataTransfer();
               dt.items.add(new File([bytes], 'other.png', {type: 'image/png'}));
               document.getElementById('image-pane').dispatchEvent(
                 new DragEvent('drop', {dataTransfer: dt, bubbles: true, cancelable: true}));""",
            __import__("base64").b64encode(data).decode())
    page.wait(lambda: page.text().strip() == recipe.stdout.decode().strip(), what="the recipe in the editor")
    assert page.js("return document.getElementById('path').textContent") == "(unsaved)"
    page.wait_done(other_than=first)
    page.shot("drop")


def test_token_is_sent_with_every_request(browser, root, tmp_path):
    s = Server(root, "fig4a.yaml", "--host", "0.0.0.0")
    try:
        m = re.fullmatch(r"http://[^/]+:(\d+)/\?token=([0-9a-f]{32})", s.url)
        assert m, s.url
        base = f"http://127.0.0.1:{m.group(1)}/"
        shots = tmp_path / "shots"
        shots.mkdir()
        page = Page(browser, f"{base}?token={m.group(2)}", shots)
        page.wait_done()
        assert page.text() == (root / "fig4a.yaml").read_text()
        page.shot("token")
        # Without it the server refuses, and the page says so.
        browser.get(base)
        assert "token" in browser.page_source
    finally:
        assert s.stop() == 0


def test_colour_and_plugin_controls_write_their_lines(page):
    first = page.wait_done()
    text = page.text()
    page.js("""const c = document.querySelector('input[type=color][data-path="renderer.maps[0].colour"]');
               c.value = '#00ff80'; c.dispatchEvent(new Event('input', {bubbles: true}));""")
    page.wait(lambda: page.text() != text, what="the new colour")
    new = page.text()
    assert changed_lines(text, new) == [MAP0]
    assert new.split("\n")[MAP0 - 1] == text.split("\n")[MAP0 - 1].replace('"#ff6b6b"', '"#00ff80"')
    # A plugin slot: the colourer becomes density, written as {type: density}.
    page.js("""const s = document.querySelector('select[data-path="renderer.colourer"]');
               s.value = 'density'; s.dispatchEvent(new Event('change', {bubbles: true}));""")
    page.wait(lambda: "colourer: {type: density}" in page.text(), what="the new colourer")
    assert changed_lines(new, page.text()) == [21]
    page.wait_done(other_than=first)
    assert page.js("return document.getElementById('error').hidden") is True
    page.shot("controls")


def test_maps_remove_and_add(page):
    page.wait_done()
    text = page.text()
    lines = text.split("\n")
    page.js("document.querySelector('button[data-path=\"renderer.maps[7]\"]').click()")
    page.wait(lambda: page.text() != text, what="the item removed")
    removed = page.text()
    assert removed.split("\n") == lines[:36] + lines[37:]
    page.wait(lambda: page.js("return document.querySelector('button[data-path=\"renderer.maps[7]\"]')") is None,
              what="the panel without maps[7]")
    # "add" appends a copy of the last item (now maps[6]) from its written values, its centre moved
    # right by twice its radius (-0.30667 + 0.4337), so that the new circle shows.
    page.js("document.querySelector('button[data-path=\"renderer.maps\"]').click()")
    page.wait(lambda: page.text() != removed, what="the item added")
    added = page.text().split("\n")
    assert added[:36] == lines[:36]
    assert added[36] == ('    - {type: inversion, shape: {type: circle, centre: [0.12703, 0], radius: 0.21685}, '
                         'colour: "#48dbfb"}')
    page.wait(lambda: page.js("return document.querySelector('button[data-path=\"renderer.maps[7]\"]')") is not None,
              what="the panel with maps[7] again")


def test_orbit_trap_wheel_zooms_its_area(browser, tmp_path):
    # orbit-trap samples pixel i at xmin + i (xmax - xmin) / (W - 1), row 0 at ymax.
    with serving(browser, tmp_path, "orbit-trap/fig5b.yaml", "fig5b.yaml") as page:
        first = page.wait_done()
        text = page.text()
        u, v = wheel(page, 0.7, 0.4, 100)
        page.wait(lambda: page.text() != text, what="the new area")
        line = [x for x in page.text().split("\n") if x.startswith("  area:")][0]
        assert line.endswith("]   # [-2 pi, 2 pi]^2")  # the comment stays
        a = 2 * math.pi
        x = -a + (u * 800 - 0.5) / 799 * 2 * a
        y = a - (v * 800 - 0.5) / 799 * 2 * a
        f = math.exp(0.2)  # zoomed out
        want = [x + (-a - x) * f, x + (a - x) * f, y + (-a - y) * f, y + (a - y) * f]
        # (To a tenth of the new area's pixel: 15.4 / 800 = 0.019, 3 decimals.)
        assert numbers(line.split("#")[0]) == pytest.approx(want, abs=(want[1] - want[0]) / 800 / 10)
        page.wait_done(other_than=first)
        page.shot("orbit-trap")


def test_without_a_config_save_asks_for_a_name(browser, tmp_path):
    root = tmp_path / "empty"
    root.mkdir()
    s = Server(root, None)
    try:
        shots = tmp_path / "shots"
        shots.mkdir()
        page = Page(browser, s.url, shots)
        assert page.js("return document.getElementById('path').textContent") == "(unsaved)"
        page.wait_done()  # the starter config renders
        # A name the server refuses: its reason in the status line, nothing written.
        page.js("document.getElementById('save').click()")
        prompt_answer(page, "notes.txt")
        page.wait(lambda: "a config is saved as .yaml or .yml" in status(page), what="the refusal")
        assert list(root.iterdir()) == []
        # Asked again (still no path), and saved.
        page.js("document.getElementById('save').click()")
        prompt_answer(page, "mine.yaml")
        page.wait(lambda: status(page) == "saved mine.yaml", what="the save")
        assert (root / "mine.yaml").read_text() == page.text()
        assert page.js("return document.getElementById('path').textContent") == "mine.yaml"
        page.shot("no-config")
    finally:
        assert s.stop() == 0


def test_mfs_without_view_zooms_from_its_fitted_box(browser, tmp_path):
    # Paper 05's Fig. 3 gives no view: the picture shows the points' box [-0.05, 1.05]^2 that
    # mfs fitted (the server says so with the preview). The wheel zooms about the cursor from
    # it and writes the renderer's view, binning as chaos-game does (pixel floor((x - xmin) W / w)).
    with serving(browser, tmp_path, "mfs/fig3-0101.yaml", "fig3.yaml") as page:
        first = page.wait_done()
        text = page.text()
        assert "view:" not in text
        assert not page.js("return document.getElementById('imgbox').classList.contains('fixed')")
        u, v = wheel(page, 0.3, 0.6, -100)
        page.wait(lambda: page.text() != text, what="the new view")
        lines = [x for x in page.text().split("\n") if re.match(r"^\s+view:", x)]
        assert len(lines) == 1, page.text()
        x, y = -0.05 + u * 1.1, 1.05 - v * 1.1
        f = math.exp(-0.2)  # zoomed in
        want = [x + (-0.05 - x) * f, x + (1.05 - x) * f, y + (-0.05 - y) * f, y + (1.05 - y) * f]
        assert numbers(lines[0]) == pytest.approx(want, abs=(want[1] - want[0]) / 600 / 10)  # (a tenth of a pixel)
        page.wait_done(other_than=first)
        page.shot("mfs-zoomed")


def test_a_pan_with_fit_view_turns_it_off(browser, tmp_path):
    # chaos-game's fit_view fits the view at every render, so a view written by hand would not
    # move the picture: the page turns fit_view off and writes the view moved from the one
    # fitted (which the server reports with the preview).
    with serving(browser, tmp_path, "gumowski-mira/fig1b-chains.yaml", "gm.yaml") as page:
        text = page.text()
        page.set_text(text.replace("points: 50000000", "points: 2000000"))
        first = page.wait_done()
        shown = page.js("return S.shown")
        assert not re.search(r"^\s+view:", page.text(), re.M)
        u, v = wheel(page, 0.5, 0.5, 100)
        page.wait(lambda: re.search(r"^\s+view:", page.text(), re.M), what="the new view")
        new = page.text()
        assert "  fit_view: false\n" in new and "fit_view: true" not in new
        line = [x for x in new.split("\n") if re.match(r"^\s+view:", x)][0]
        x = shown["xmin"] + u * (shown["xmax"] - shown["xmin"])
        y = shown["ymax"] - v * (shown["ymax"] - shown["ymin"])
        f = math.exp(0.2)
        want = [x + (shown["xmin"] - x) * f, x + (shown["xmax"] - x) * f,
                y + (shown["ymin"] - y) * f, y + (shown["ymax"] - y) * f]
        px = (want[1] - want[0]) / 1024
        assert numbers(line) == pytest.approx(want, abs=px / 10)
        page.wait_done(other_than=first)
        page.shot("fit-view-off")
        # Fit turns fit_view on again; reset brings back the config as opened (fit_view on).
        assert not page.js("return document.getElementById('fit-view').disabled")
        zoomed = page.text()
        page.js("document.getElementById('fit-view').click()")
        page.wait(lambda: "fit_view: true" in page.text(), what="fit_view: true")
        assert changed_lines(zoomed, page.text()) == [zoomed.split("\n").index("  fit_view: false") + 1]
        page.wait(lambda: page.js("return document.getElementById('fit-view').disabled"), what="fit disabled")


def test_previews_are_posted_one_after_another(browser, tmp_path):
    # Texts typed faster than the server answers: each preview is posted once the one before
    # has answered, so that they reach the server in the page's order. Two in flight at once
    # could arrive in the other order, and the older text's job would cancel the newer one's,
    # leaving the page following a cancelled job (it waited for ever).
    with serving(browser, tmp_path, "gumowski-mira/fig1b-chains.yaml", "gm.yaml") as page:
        first = page.wait_done()  # (the page's first preview has answered)
        page.js("""
          window.inFlight = 0; window.mostInFlight = 0; window.posted = [];
          const fetch0 = window.fetch;
          window.fetch = async (url, opts) => {
            const preview = String(url).includes('/api/preview');
            if (preview) {
              window.posted.push(JSON.parse(opts.body).text.match(/points: (\\d+)/)[1]);
              window.mostInFlight = Math.max(window.mostInFlight, ++window.inFlight);
            }
            try { return await fetch0(url, opts); } finally { if (preview) --window.inFlight; }
          };""")
        text = page.text()
        for points in ("2000000", "1000000", "3000000"):
            page.js("const t = document.getElementById('text'); t.value = arguments[0]; refresh();",
                    text.replace("points: 50000000", f"points: {points}"))
        last = page.wait_done(other_than=first)
        assert page.js("return String(S.job)") == last
        assert page.js("return window.mostInFlight") == 1
        # The first went at once; the second was no longer the newest when the first answered.
        assert page.js("return window.posted") == ["2000000", "3000000"]


def key(page, k, shift=False):
    """Ctrl+K (with Shift) as the keyboard sends it, to the editor, which has the focus."""
    page.js("""const t = document.getElementById('text'); t.focus();
               t.dispatchEvent(new KeyboardEvent('keydown', {key: arguments[0], ctrlKey: true,
                 shiftKey: arguments[1], bubbles: true, cancelable: true}));""", k, shift)


def test_undo_and_redo_over_every_kind_of_edit(page):
    # A slider, the wheel and a burst of typing, then Ctrl+Z three times: each text comes back in
    # turn, and the preview follows; Ctrl+Shift+Z and the buttons go forward and back again.
    first = page.wait_done()
    assert page.js("return document.getElementById('undo').disabled")
    t0 = page.text()
    slide(page, "renderer.maps[4].shape.radius", "0.3")
    page.wait(lambda: page.text() != t0, what="the slider's edit")
    t1 = page.text()
    wheel(page, 0.5, 0.5, -100)
    page.wait(lambda: page.text() != t1, what="the wheel's view")
    t2 = page.text()
    page.set_text(t2 + "# typed\n")  # (a burst of typing)
    t3 = page.text()
    assert len({t0, t1, t2, t3}) == 4
    assert changed_lines(t0, t1) == [MAP4] and changed_lines(t1, t2) == [VIEW]
    for want in (t2, t1, t0):
        key(page, "z")
        page.wait(lambda: page.text() == want, what="the text before")
    assert page.js("return document.getElementById('undo').disabled")
    page.wait_done(other_than=first)
    key(page, "z", shift=True)
    page.wait(lambda: page.text() == t1, what="the slider's edit again")
    page.js("document.getElementById('redo').click()")
    page.wait(lambda: page.text() == t2, what="the view again")
    page.js("document.getElementById('undo').click()")
    page.wait(lambda: page.text() == t1, what="undone by the button")
    # A new edit after an undo: nothing to redo.
    slide(page, "renderer.maps[4].shape.radius", "0.25")
    page.wait(lambda: "radius: 0.25" in page.text(), what="a new edit")
    assert page.js("return document.getElementById('redo').disabled")
    page.shot("undo")


def test_reset_view_brings_back_the_view_as_opened(page):
    first = page.wait_done()
    text = page.text()
    # (fig4a's fit_view is false by default: Fit can turn it on.)
    assert not page.js("return document.getElementById('fit-view').disabled")
    wheel(page, 0.3, 0.6, -100)
    page.wait(lambda: page.text() != text, what="the zoomed view")
    page.wait_done(other_than=first)
    page.js("document.getElementById('reset-view').click()")
    page.wait(lambda: page.text().split("\n")[VIEW - 1] == text.split("\n")[VIEW - 1], what="the view as opened")
    assert page.text() == text


def test_superseded_previews_leave_no_console_errors(page):
    # Texts typed one after another, each replacing the preview of the one before: the page drops
    # its wait for the frames of a replaced job before the server cancels it, so the console gets
    # no 410 (nor any other error), and the last text's preview is shown.
    first = page.wait_done()
    page.d.get_log("browser")  # (what came before)
    text = page.text()
    for k in range(4):
        page.set_text(text.replace("points: 40000000", f"points: {2000000 + k * 100000}"))
        page.js("return refresh()")
    page.wait_done(other_than=first)
    errors = [e for e in page.d.get_log("browser") if e["level"] == "SEVERE"]
    assert errors == [], errors


def test_a_shape_switch_keeps_what_carries_over(page):
    # maps[0]'s circle becomes a star polygon: its centre stays (star-polygon declares one), its
    # radius goes (star-polygon has outer and inner radii instead), and the picture renders.
    first = page.wait_done()
    page.wait(lambda: page.js("return S.pluginParams !== null"), what="the plugins' parameters")
    text = page.text()
    page.js("""const s = document.querySelector('select[data-path="renderer.maps[0].shape"]');
               s.value = 'star-polygon'; s.dispatchEvent(new Event('change', {bubbles: true}));""")
    page.wait(lambda: page.text() != text, what="the switched shape")
    new = page.text()
    assert changed_lines(text, new) == [MAP0]
    line = new.split("\n")[MAP0 - 1]
    assert "shape: {type: star-polygon, centre: [1, 1]}" in line, line
    page.wait_done(other_than=first)
    assert page.js("return document.getElementById('error').hidden")


def test_labels_show_whole_and_shift_drags_a_slider_finely(page):
    # Every parameter's name shows whole (a long one wraps after an underscore), and sliders
    # are wide (issue 47: they were 85 px, names cut at 92 px).
    page.wait_done()
    cut = page.js("""return [...document.querySelectorAll('#params .prow > label')]
        .filter(l => l.offsetParent !== null && l.scrollWidth > l.clientWidth + 1)
        .map(l => l.textContent)""")
    assert cut == []
    path = "renderer.maps[4].shape.radius"
    sel = f'input[type=range][data-path="{path}"]'
    lo, hi, w = page.js(f"""const s = document.querySelector('{sel}');
        return [Number(s.min), Number(s.max), s.getBoundingClientRect().width]""")
    assert w >= 140, w
    # A user's Shift+drag of 100 px: the radius moves from where it is by a tenth of what the
    # pointer covers, 100 (hi - lo) / (10 w) (0.054 here), not to where the pointer went down.
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    text = page.text()
    def radius(t):
        return float(re.search(r"radius: ([-0-9.e]+)", t.split("\n")[MAP4 - 1]).group(1))

    r0 = radius(text)
    slider = page.d.find_element(By.CSS_SELECTOR, sel)
    ActionChains(page.d).key_down(Keys.SHIFT).click_and_hold(slider).move_by_offset(100, 0).release() \
        .key_up(Keys.SHIFT).perform()
    page.wait(lambda: page.text() != text, what="the fine drag's edit")
    r1 = radius(page.text())
    assert changed_lines(text, page.text()) == [MAP4]
    assert abs(r1 - (r0 + 100 * (hi - lo) / (10 * w))) <= 0.0025, (r0, r1, lo, hi, w)
    page.shot("fine-drag")
