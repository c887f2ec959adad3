// The preview page of `fixpoint serve`. It talks to the server only through the requests of
// docs/serve-api.md. The YAML in the editor is the source of truth: every request carries it
// whole, and every change the page makes (a slider, a colour, a plugin, pan and zoom) is an
// edit the server applies to that text (POST /api/edit), whose answer replaces the editor's
// text; the preview and the parameter panel then follow from the new text.
'use strict';

const $ = (id) => document.getElementById(id);
const editor = $('text');
const gutter = $('gutter');
const band = $('error-band');
const errorBox = $('error');
const img = $('frame');
const imgbox = $('imgbox');
const stage = $('stage');
const caption = $('caption');
const panel = $('params');

// ------------------------------------------------------------------ requests
const token = new URLSearchParams(location.search).get('token');

function withToken(init = {}) {
  const headers = new Headers(init.headers || {});
  if (token) headers.set('X-Fixpoint-Token', token);
  return { ...init, headers };
}

// An answer as an object: the server's JSON, or for an HTTP error {ok: false, error} (so that a
// 400 or 403 is shown the way a refused config is).
async function answer(r) {
  let data = null;
  try {
    data = await r.json();
  } catch (e) {
    data = null;
  }
  if (r.ok && data) return data;
  const error = (data && data.error) || `${r.status} ${r.statusText}`;
  return { ok: false, error, line: (data && data.line) || 0, column: (data && data.column) || 0 };
}

async function post(url, body, type = 'application/json') {
  let r;
  try {
    r = await fetch(url, withToken({
      method: 'POST',
      headers: { 'Content-Type': type },
      body: type === 'application/json' ? JSON.stringify(body) : body,
    }));
  } catch (e) {
    return { ok: false, error: 'the server does not answer (is fixpoint serve still running?)', line: 0 };
  }
  return answer(r);
}

async function get(url) {
  const r = await fetch(url, withToken());
  return answer(r);
}

// ------------------------------------------------------------------ state
const S = {
  path: '',         // the config's path in the served folder ('' when serve had none)
  suggest: '',      // a file name to offer when saving without a path
  seq: 0,           // the latest refresh: older answers are dropped
  job: null,        // the preview job the image pane follows
  jobRegion: new Map(), // job -> the view/area its text had (for pan and zoom)
  shown: null,      // the region of the image on screen, {xmin, xmax, ymin, ymax}
  pending: null,    // the region pan/zoom is taking the view to, before its image arrives
  frameW: 0,        // the size of the full image (the config's aspect)
  frameH: 0,
  renderer: '',
  regionParam: '',  // 'renderer.view' or 'renderer.area' ('' when none can be moved)
  configW: 0,       // the config's width, for orbit-trap's pixel-centred area
  entries: [],
  signature: '',
  spans: new Map(), // path -> [lo, hi, step] of its slider, kept while the value stays inside
};

function setStatus(text, kind = '') {
  const s = $('status');
  s.textContent = text;
  s.className = 'status' + (kind ? ' ' + kind : '');
  s.title = text;
}

function showPath() {
  $('path').textContent = S.path || '(unsaved)';
}

// ------------------------------------------------------------------ editor
const lineHeight = () => parseFloat(getComputedStyle(editor).lineHeight) || 19;
let errLine = 0;

function renderGutter() {
  const n = editor.value.split('\n').length;
  if (gutter.childElementCount !== n) {
    const frag = document.createDocumentFragment();
    for (let i = 1; i <= n; i++) {
      const d = document.createElement('div');
      d.textContent = i;
      frag.appendChild(d);
    }
    gutter.replaceChildren(frag);
  }
  for (const d of gutter.querySelectorAll('.error')) d.classList.remove('error');
  if (errLine > 0 && errLine <= n) gutter.children[errLine - 1].classList.add('error');
  syncScroll();
}

function syncScroll() {
  gutter.scrollTop = editor.scrollTop;
  if (errLine > 0) {
    const pad = parseFloat(getComputedStyle(editor).paddingTop) || 0;
    band.style.top = `${pad + (errLine - 1) * lineHeight() - editor.scrollTop}px`;
  }
}

function showError(e) {
  errorBox.textContent = e.error;
  errorBox.hidden = false;
  errLine = e.line || 0;
  band.hidden = errLine === 0;
  renderGutter();
}

function clearError() {
  errorBox.hidden = true;
  errorBox.textContent = '';
  errLine = 0;
  band.hidden = true;
  renderGutter();
}

// Line and column of an offset, and back: the cursor stays on its line when the server
// rewrites the text (an edit changes a value, rarely the lines around it).
function lineCol(text, off) {
  const before = text.slice(0, off).split('\n');
  return [before.length - 1, before[before.length - 1].length];
}

function offsetOf(text, [line, col]) {
  const lines = text.split('\n');
  const l = Math.min(line, lines.length - 1);
  let off = 0;
  for (let i = 0; i < l; i++) off += lines[i].length + 1;
  return off + Math.min(col, lines[l].length);
}

function setText(text) {
  if (text === editor.value) return;
  const start = lineCol(editor.value, editor.selectionStart);
  const end = lineCol(editor.value, editor.selectionEnd);
  const top = editor.scrollTop;
  const left = editor.scrollLeft;
  editor.value = text;
  editor.setSelectionRange(offsetOf(text, start), offsetOf(text, end));
  editor.scrollTop = top;
  editor.scrollLeft = left;
  renderGutter();
}

let typing = 0;
editor.addEventListener('input', () => {
  renderGutter();
  clearTimeout(typing);
  typing = setTimeout(refresh, 250);
});
editor.addEventListener('scroll', syncScroll);
editor.addEventListener('keydown', (e) => {
  if (e.key === 'Tab' && !e.ctrlKey && !e.altKey && !e.metaKey) {
    // YAML forbids tabs in indentation: a tab key writes two spaces.
    e.preventDefault();
    document.execCommand('insertText', false, '  ');
  }
});
document.addEventListener('keydown', (e) => {
  if ((e.ctrlKey || e.metaKey) && e.key === 's') {
    e.preventDefault();
    save();
  }
});

// ------------------------------------------------------------------ preview
// One refresh per text: start its preview (which cancels the running one on the server) and
// ask for its parameters. A refused config keeps the last good image.
// The previews are posted one after another, each once the one before has answered: two in
// flight at once may reach the server in the other order, and the older text's job would then
// cancel the newer one's, leaving the page following a cancelled job. A text that is no longer
// the newest when its turn comes is not posted.
let previews = Promise.resolve();
async function refresh() {
  clearTimeout(typing);
  const seq = ++S.seq;
  const body = { text: editor.value, path: S.path };
  const preview = previews.then(() => (seq === S.seq ? post('/api/preview', body) : null));
  previews = preview.catch(() => null);
  const [pv, pr] = await Promise.all([preview, post('/api/params', body)]);
  if (seq !== S.seq || !pv) return;
  if (pr.ok) buildPanel(pr.params);
  if (!pv.ok) {
    showError(pv);
    dropPending();
    return;
  }
  clearError();
  // What the picture shows, fitted or given: a pan or zoom writes it into the text.
  const region = boxOf(pv.region);
  S.jobRegion.set(pv.job, region);
  imgbox.classList.toggle('fixed', !(region && S.regionParam));
  follow(pv.job);
}

async function follow(job) {
  S.job = job;
  let after = -1;
  while (S.job === job) {
    let r;
    try {
      r = await fetch(`/api/frame?job=${encodeURIComponent(job)}&after=${after}`, withToken());
    } catch (e) {
      if (S.job === job) setStatus('the server does not answer (is fixpoint serve still running?)', 'bad');
      return;
    }
    if (S.job !== job) return;
    if (r.status === 204) continue; // nothing new within the server's wait: ask again
    if (r.status === 410) return;   // superseded by a newer preview
    if (r.status !== 200) {
      const e = await answer(r);
      if (S.job !== job) return;
      if (r.status === 422) showError(e);
      else setStatus(e.error, 'bad');
      return;
    }
    const blob = await r.blob();
    if (S.job !== job) return;
    const h = (k) => r.headers.get(k);
    const k = Number(h('X-Stage'));
    const done = h('X-Done') === '1';
    showFrame(blob, job, {
      stage: k, stages: Number(h('X-Stages')), width: Number(h('X-Width')), height: Number(h('X-Height')),
      spp: Number(h('X-Samples-Per-Pixel')), seconds: Number(h('X-Seconds')), done,
    });
    after = k;
    if (done) return;
  }
}

function number(x) {
  if (!isFinite(x)) return '?';
  if (x >= 100) return x.toFixed(0);
  if (x >= 10) return x.toFixed(1);
  return x.toPrecision(2).replace(/\.?0+$/, '') || '0';
}

let shownUrl = null;
function showFrame(blob, job, f) {
  const url = URL.createObjectURL(blob);
  const old = shownUrl;
  shownUrl = url;
  img.onload = () => {
    if (old) URL.revokeObjectURL(old);
  };
  img.src = url;
  img.dataset.job = job;
  img.dataset.stage = f.stage;
  img.dataset.done = f.done ? '1' : '0';
  $('placeholder').hidden = true;
  // Drafts are smaller images of the same aspect: the pane shows each at the full image's size.
  S.frameW = f.width;
  S.frameH = f.height;
  fit();
  caption.textContent = `stage ${f.stage + 1}/${f.stages} · ${f.width}×${f.height} · ` +
      `${number(f.spp)} samples/px · ${f.seconds.toFixed(2)} s`;
  caption.classList.toggle('done', f.done);
  const region = S.jobRegion.get(job) || null;
  if (S.pending && S.pending.sent && sameRegion(S.pending, region)) S.pending = null;
  S.shown = region;
  placeImage();
}

function fit() {
  if (!S.frameW || !S.frameH) return;
  const w = stage.clientWidth, h = stage.clientHeight;
  const s = Math.min(w / S.frameW, h / S.frameH);
  imgbox.style.width = `${Math.max(1, Math.floor(S.frameW * s))}px`;
  imgbox.style.height = `${Math.max(1, Math.floor(S.frameH * s))}px`;
}
window.addEventListener('resize', fit);

// ------------------------------------------------------------------ pan and zoom
// The region is [xmin, xmax, ymin, ymax] with y growing upward (row 0 at ymax) in every
// renderer. chaos-game, superfractal and mfs bin a point into pixel floor((x - xmin) W / w):
// the left edge of the image is xmin. orbit-trap samples pixel i at xmin + i w / (W - 1)
// (pixel centres: the first at xmin, the last at xmax).

// The region a preview shows, as /api/preview reports it: the text's view or area, or the one
// the renderer fitted (mfs's points' box, chaos-game's fit_view).
function boxOf(r) {
  if (!Array.isArray(r) || r.length !== 4 || !r.every(isFinite) || !(r[0] < r[1]) || !(r[2] < r[3])) return null;
  return { xmin: r[0], xmax: r[1], ymin: r[2], ymax: r[3] };
}

function sameRegion(a, b) {
  if (!a || !b) return false;
  const close = (x, y, w) => Math.abs(x - y) <= 1e-8 * Math.abs(w);
  const w = a.xmax - a.xmin, h = a.ymax - a.ymin;
  return close(a.xmin, b.xmin, w) && close(a.xmax, b.xmax, w) && close(a.ymin, b.ymin, h) && close(a.ymax, b.ymax, h);
}

// The plane point under (u, v), fractions of the shown image's width and height from its
// top left corner, when the image shows region r.
function planeAt(r, u, v) {
  if (S.renderer === 'orbit-trap') {
    const W = S.frameW || 2, H = S.frameH || 2;
    const i = (u * W - 0.5) / Math.max(1, W - 1), j = (v * H - 0.5) / Math.max(1, H - 1);
    return { x: r.xmin + i * (r.xmax - r.xmin), y: r.ymax - j * (r.ymax - r.ymin) };
  }
  return { x: r.xmin + u * (r.xmax - r.xmin), y: r.ymax - v * (r.ymax - r.ymin) };
}

// The image moved by CSS while the new region's image is on its way: the shown region drawn
// where it lies inside the pending one.
function placeImage() {
  const a = S.shown, b = S.pending;
  if (!a || !b) {
    img.style.transform = '';
    return;
  }
  const W = imgbox.clientWidth, H = imgbox.clientHeight;
  const sx = (a.xmax - a.xmin) / (b.xmax - b.xmin), sy = (a.ymax - a.ymin) / (b.ymax - b.ymin);
  const tx = ((a.xmin - b.xmin) / (b.xmax - b.xmin)) * W;
  const ty = ((b.ymax - a.ymax) / (b.ymax - b.ymin)) * H;
  img.style.transform = `translate(${tx}px, ${ty}px) scale(${sx}, ${sy})`;
}

function dropPending() {
  S.pending = null;
  placeImage();
}

function pointer(e) {
  const r = imgbox.getBoundingClientRect();
  return [(e.clientX - r.left) / r.width, (e.clientY - r.top) / r.height];
}

const movable = () => S.regionParam && S.shown;
let drag = null;
let zoomTimer = 0;

imgbox.addEventListener('mousedown', (e) => {
  if (e.button !== 0 || !movable()) return;
  e.preventDefault();
  const base = S.pending || S.shown;
  drag = { base, at: planeAt(base, ...pointer(e)), x: e.clientX, y: e.clientY, moved: false };
  imgbox.classList.add('dragging');
});

window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  if (Math.abs(e.clientX - drag.x) + Math.abs(e.clientY - drag.y) > 2) drag.moved = true;
  const p = planeAt(drag.base, ...pointer(e));
  const dx = drag.at.x - p.x, dy = drag.at.y - p.y;
  const b = drag.base;
  S.pending = { xmin: b.xmin + dx, xmax: b.xmax + dx, ymin: b.ymin + dy, ymax: b.ymax + dy };
  placeImage();
});

window.addEventListener('mouseup', () => {
  if (!drag) return;
  const moved = drag.moved;
  drag = null;
  imgbox.classList.remove('dragging');
  if (moved) sendRegion();
  else dropPending();
});

imgbox.addEventListener('wheel', (e) => {
  if (!movable()) return;
  e.preventDefault();
  const base = S.pending || S.shown;
  const delta = e.deltaMode === 1 ? e.deltaY * 16 : e.deltaY;
  const f = Math.exp(Math.max(-0.5, Math.min(0.5, delta * 0.002))); // > 1 zooms out
  const p = planeAt(base, ...pointer(e));
  S.pending = {
    xmin: p.x + (base.xmin - p.x) * f, xmax: p.x + (base.xmax - p.x) * f,
    ymin: p.y + (base.ymin - p.y) * f, ymax: p.y + (base.ymax - p.y) * f,
  };
  placeImage();
  clearTimeout(zoomTimer);
  zoomTimer = setTimeout(sendRegion, 250); // one edit for a burst of wheel steps
}, { passive: false });

function real(x) {
  return String(Number(x.toPrecision(10)));
}

async function sendRegion() {
  clearTimeout(zoomTimer);
  const r = S.pending;
  if (!r || !S.regionParam) return;
  r.sent = true;
  // chaos-game's fit_view fits the view again at every render: a view chosen by hand turns it off.
  const fit = (S.entries || []).find((p) => p.path === 'renderer.fit_view');
  if (fit && fit.value.trim() === 'true' && !(await edit('set', 'renderer.fit_view', 'false'))) {
    if (S.pending === r) dropPending();
    return;
  }
  const ok = await edit('set', S.regionParam, `[${real(r.xmin)}, ${real(r.xmax)}, ${real(r.ymin)}, ${real(r.ymax)}]`);
  if (!ok && S.pending === r) dropPending();
}

// ------------------------------------------------------------------ edits
// Edits run one at a time, each on the editor's text as it is when it runs; a slider's stream
// of values collapses to the latest while an edit is under way.
let chain = Promise.resolve(true);
const queued = new Map();

function edit(op, target, value) {
  const task = async () => {
    for (let tries = 0; tries < 3; tries++) {
      const text = editor.value;
      const a = await post('/api/edit', { text, path: S.path, op, target, value });
      if (!a.ok) {
        setStatus(a.error, 'bad');
        return false;
      }
      if (editor.value !== text) continue; // typed over meanwhile: apply to the new text
      setText(a.text);
      setStatus('');
      await refresh();
      return true;
    }
    return false;
  };
  chain = chain.then(task, task);
  return chain;
}

function setParam(target, value) {
  const waiting = queued.has(target);
  queued.set(target, value);
  if (waiting) return;
  const task = async () => {
    const v = queued.get(target);
    queued.delete(target);
    const text = editor.value;
    const a = await post('/api/edit', { text, path: S.path, op: 'set', target, value: v });
    if (!a.ok) {
      setStatus(a.error, 'bad');
      return false;
    }
    if (editor.value === text) {
      setText(a.text);
      setStatus('');
      await refresh();
    }
    return true;
  };
  chain = chain.then(task, task);
}

// ------------------------------------------------------------------ parameters
const unquote = (s) => s.replace(/^\s*(['"])(.*)\1\s*$/, '$2');

function hex2(x) {
  return Math.round(Math.max(0, Math.min(1, x)) * 255).toString(16).padStart(2, '0');
}

// A colour value as #rrggbb, and whether it was written as [r, g, b] in 0..1.
function parseColour(value) {
  const v = unquote(value || '');
  if (/^#[0-9a-fA-F]{6}$/.test(v)) return [v.toLowerCase(), false];
  if (/^#[0-9a-fA-F]{3}$/.test(v)) return ['#' + [...v.slice(1)].map((c) => c + c).join('').toLowerCase(), false];
  const n = (v.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || []).map(Number);
  if (v.startsWith('[') && n.length === 3) return ['#' + n.map(hex2).join(''), true];
  return ['#000000', false];
}

function colourValue(hex, asList) {
  if (!asList) return `"${hex}"`;
  const c = [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16) / 255);
  return `[${c.map((x) => String(Number(x.toPrecision(4)))).join(', ')}]`;
}

function niceStep(span, isInt) {
  if (isInt) return Math.max(1, Math.pow(10, Math.floor(Math.log10(Math.max(1, span / 1000)))));
  return Math.pow(10, Math.floor(Math.log10(span / 500)));
}

// The slider's span: the declared range when it is finite, else one around the value (a
// quarter to four times it, or -10..10 about zero) cut by the declared bound. A positive range
// of three decades or more (a width of 1..65536, a count of points) slides on a log scale, so
// that each decade gets its share of the slider. The number field beside it takes any value.
function sliderSpan(e, v) {
  const kept = S.spans.get(e.path);
  if (kept && v >= kept.lo && v <= kept.hi) return kept;
  const isInt = e.kind === 'int';
  const min = e.min == null ? -Infinity : e.min, max = e.max == null ? Infinity : e.max;
  let lo, hi;
  if (isFinite(min) && isFinite(max)) {
    [lo, hi] = [min, max];
  } else {
    const x = isFinite(v) ? v : isFinite(min) ? min : 0;
    if (x > 0) [lo, hi] = [x / 4, x * 4];
    else if (x < 0) [lo, hi] = [x * 4, x / 4];
    else [lo, hi] = [-10, 10];
    lo = Math.max(lo, min);
    hi = Math.min(hi, max);
    if (!(lo < hi)) [lo, hi] = isFinite(min) ? [min, min + 10] : [max - 10, max];
  }
  const log = lo > 0 && hi / lo >= 1000;
  const step = niceStep(hi - lo, isInt);
  if (!log && (!isFinite(min) || !isFinite(max))) {
    lo = Math.max(min, Math.floor(lo / step) * step);
    hi = Math.min(max, Math.ceil(hi / step) * step);
  }
  const span = { lo, hi, step, log };
  S.spans.set(e.path, span);
  return span;
}

function decimals(step) {
  return step >= 1 ? 0 : Math.min(12, Math.ceil(-Math.log10(step) - 1e-9));
}

function el(tag, props = {}, ...kids) {
  const n = document.createElement(tag);
  Object.assign(n, props);
  for (const k of kids) n.append(k);
  return n;
}

// Unwritten values show the default in grey; optional parameters without one are hidden
// unless "show unset parameters" is ticked.
function mark(r, e) {
  r.classList.toggle('default', !e.written);
  r.classList.toggle('unset', !e.written && !e.required && e.value === '');
}

function row(e, control, cls = '') {
  const label = el('label', { textContent: e.name, title: e.description || e.name });
  const r = el('div', { className: 'prow' + (cls ? ' ' + cls : '') }, label, control);
  mark(r, e);
  r.style.paddingLeft = `${e.depth * 12}px`;
  r.dataset.path = e.path;
  r.title = `${e.path}: ${e.description || ''}${e.default_value ? ` (default ${e.default_value})` : ''}`;
  return r;
}

function numberControl(e) {
  const isInt = e.kind === 'int';
  const slider = el('input', { type: 'range' });
  slider.dataset.path = e.path;
  const field = el('input', { type: 'number', value: e.value, step: isInt ? 1 : 'any' });
  field.dataset.path = e.path;
  if (e.min != null) field.min = e.min;
  if (e.max != null) field.max = e.max;
  let span = null;
  const place = (x, n) => {
    span = sliderSpan(x, n);
    if (span.log) Object.assign(slider, { min: Math.log(span.lo), max: Math.log(span.hi), step: 'any' });
    else Object.assign(slider, { min: span.lo, max: span.hi, step: span.step });
    slider.value = !isFinite(n) ? slider.min : span.log ? Math.log(n) : n;
  };
  place(e, e.value === '' ? NaN : Number(e.value));
  // The slider's position as the value written into the YAML: a multiple of the step, or on a
  // log scale three significant digits.
  const read = () => {
    const s = Number(slider.value);
    if (span.log) {
      const x = Number(Math.exp(s).toPrecision(3));
      return String(isInt ? Math.round(x) : x);
    }
    return isInt ? String(Math.round(s)) : String(Number(s.toFixed(decimals(span.step))));
  };
  slider.addEventListener('input', () => {
    field.value = read();
    setParam(e.path, read());
  });
  slider.addEventListener('change', () => setParam(e.path, read()));
  field.addEventListener('change', () => {
    const t = field.value.trim();
    if (t === '' || !isFinite(Number(t))) return;
    place(e, Number(t));
    setParam(e.path, t);
  });
  const c = el('div', { className: 'ctl' }, slider, field);
  c.update = (x) => {
    const n = Number(x.value);
    if (document.activeElement !== field) field.value = x.value;
    if (document.activeElement !== slider && x.value !== '' && isFinite(n)) place(x, n);
  };
  return c;
}

function selectControl(e, options, toValue) {
  const s = el('select');
  s.dataset.path = e.path;
  const current = unquote(e.value);
  const all = options.includes(current) || current === '' ? options : [current, ...options];
  if (current === '') s.append(el('option', { value: '', textContent: '—', disabled: true }));
  for (const o of all) s.append(el('option', { value: o, textContent: o }));
  s.value = current;
  s.addEventListener('change', () => setParam(e.path, toValue(s.value)));
  const c = el('div', { className: 'ctl' }, s);
  c.update = (x) => {
    if (document.activeElement !== s) s.value = unquote(x.value);
  };
  return c;
}

function colourControl(e) {
  const [hex, asList] = parseColour(e.value);
  const pick = el('input', { type: 'color', value: hex });
  pick.dataset.path = e.path;
  const label = el('span', { className: 'hex', textContent: hex });
  pick.addEventListener('input', () => {
    label.textContent = pick.value;
    setParam(e.path, colourValue(pick.value, asList));
  });
  const c = el('div', { className: 'ctl' }, pick, label);
  c.update = (x) => {
    const [h] = parseColour(x.value);
    if (document.activeElement !== pick) pick.value = h;
    label.textContent = h;
  };
  return c;
}

function boolControl(e) {
  const box = el('input', { type: 'checkbox', checked: unquote(e.value) === 'true' });
  box.dataset.path = e.path;
  box.addEventListener('change', () => setParam(e.path, box.checked ? 'true' : 'false'));
  const c = el('div', { className: 'ctl' }, box);
  c.update = (x) => {
    box.checked = unquote(x.value) === 'true';
  };
  return c;
}

function pointControl(e) {
  const n = (e.value.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || []);
  const xs = [0, 1].map((i) => {
    const f = el('input', { type: 'number', step: 'any', value: n[i] || '', className: 'pt' });
    f.dataset.path = `${e.path}[${i}]`;
    return f;
  });
  const send = () => {
    if (xs.every((f) => f.value.trim() !== '')) setParam(e.path, `[${xs[0].value}, ${xs[1].value}]`);
  };
  for (const f of xs) f.addEventListener('change', send);
  const c = el('div', { className: 'ctl' }, ...xs);
  c.update = (x) => {
    const m = x.value.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || [];
    xs.forEach((f, i) => {
      if (document.activeElement !== f) f.value = m[i] || '';
    });
  };
  return c;
}

// Any other value (a string, a list of numbers or points, a sequence) as its flow YAML.
function textControl(e, quoteIt) {
  const f = el('input', { type: 'text', value: quoteIt ? unquote(e.value) : e.value, spellcheck: false });
  f.dataset.path = e.path;
  f.addEventListener('change', () => setParam(e.path, quoteIt ? JSON.stringify(f.value) : f.value));
  const c = el('div', { className: 'ctl' }, f);
  c.update = (x) => {
    if (document.activeElement !== f) f.value = quoteIt ? unquote(x.value) : x.value;
  };
  return c;
}

const itemIndex = (path) => {
  const m = path.match(/\[(\d+)\]$/);
  return m ? Number(m[1]) : -1;
};

// An item of a list as flow YAML, from the entries the config writes: the copy "add" appends.
function flowOf(entries, at) {
  const top = entries[at];
  const parts = top.kind === 'plugin' || top.kind === 'list' ? [`type: ${unquote(top.value)}`] : [];
  for (let i = at + 1; i < entries.length && entries[i].depth > top.depth; i++) {
    const c = entries[i];
    if (c.depth !== top.depth + 1 || !c.path.startsWith(top.path + '.')) continue;
    if (c.kind === 'plugin' && c.value) parts.push(`${c.name}: ${flowOf(entries, i)}`);
    else if (c.written && c.kind !== 'list') parts.push(`${c.name}: ${c.value}`);
  }
  return `{${parts.join(', ')}}`;
}

function listHead(e, entries) {
  const add = el('button', { type: 'button', className: 'small', textContent: 'add' });
  add.dataset.path = e.path;
  add.title = `append a copy of the last item of ${e.name}`;
  add.addEventListener('click', () => {
    const last = entries.findIndex((x) => x.path === `${e.path}[${e.count - 1}]`);
    const value = last >= 0 ? flowOf(entries, last) : '{type: inversion, shape: {type: circle, centre: [0, 0], radius: 0.5}}';
    edit('append', e.path, value);
  });
  const c = el('div', { className: 'ctl' }, el('span', { className: 'hex', textContent: `${e.count} items` }), add);
  c.update = (x) => {
    c.firstChild.textContent = `${x.count} items`;
  };
  return c;
}

function itemHead(e, isPlugin, plugins) {
  const parts = [];
  if (isPlugin) parts.push(...selectControl(e, plugins, (n) => `{type: ${n}}`).childNodes);
  const rm = el('button', { type: 'button', className: 'small', textContent: 'remove' });
  rm.dataset.path = e.path;
  rm.title = `remove ${e.path}`;
  rm.addEventListener('click', () => edit('remove', e.path, ''));
  const c = el('div', { className: 'ctl' }, ...parts, rm);
  c.update = (x) => {
    const s = c.querySelector('select');
    if (s && document.activeElement !== s) s.value = unquote(x.value);
  };
  return c;
}

function controlFor(e, entries, at, lists) {
  const parentList = lists.has(e.path.replace(/\[\d+\]$/, '')) && itemIndex(e.path) >= 0;
  if (parentList) return [itemHead(e, e.kind === 'plugin', e.choices || []), 'item'];
  switch (e.kind) {
    case 'int':
    case 'real':
      return [numberControl(e), ''];
    case 'bool':
      return [boolControl(e), ''];
    case 'choice':
      return [selectControl(e, e.choices || [], (v) => v), ''];
    case 'colour':
      return [colourControl(e), ''];
    case 'plugin':
      return [selectControl(e, e.choices || [], (n) => `{type: ${n}}`), e.depth > 0 ? 'head sub' : 'head'];
    case 'list':
      return [listHead(e, entries), 'head'];
    case 'point':
      return [pointControl(e), ''];
    case 'string':
      return [textControl(e, true), ''];
    default:
      return [textControl(e, false), ''];
  }
}

function buildPanel(entries) {
  S.entries = entries;
  const top = entries.find((p) => p.path === 'renderer');
  S.renderer = top ? unquote(top.value) : '';
  const reg = entries.find((p) => p.path === 'renderer.view' || p.path === 'renderer.area');
  S.regionParam = reg ? reg.path : '';
  // The same parameters as before: update the controls in place, so that a slider being
  // dragged is not replaced under the pointer.
  const sig = entries.map((e) => `${e.path}|${e.kind}|${(e.choices || []).join(',')}|${e.count}`).join('\n');
  const rows = panel.children;
  if (sig === S.signature && rows.length === entries.length) {
    entries.forEach((e, i) => {
      const r = rows[i];
      mark(r, e);
      const c = r.querySelector('.ctl');
      if (c && c.update) c.update(e);
    });
    return;
  }
  S.signature = sig;
  const lists = new Set(entries.filter((e) => e.kind === 'list').map((e) => e.path));
  const scroll = panel.parentElement.scrollTop;
  const frag = document.createDocumentFragment();
  entries.forEach((e, i) => {
    const [c, cls] = controlFor(e, entries, i, lists);
    frag.append(row(e, c, cls));
  });
  panel.replaceChildren(frag);
  panel.parentElement.scrollTop = scroll;
}

// ------------------------------------------------------------------ save, render, drop
async function save() {
  let path = S.path;
  if (!path) {
    path = prompt('Save the config as (a .yaml file in the served folder):', S.suggest || 'fixpoint.yaml');
    if (!path) return;
  }
  const a = await post('/api/save', { text: editor.value, path });
  if (!a.ok) {
    setStatus(a.error, 'bad');
    return;
  }
  S.path = a.path || path;
  showPath();
  setStatus(`saved ${S.path}`, 'good');
}

function stem(path) {
  const base = (path || S.suggest || 'fixpoint.yaml').split('/').pop();
  return base.replace(/\.[^.]*$/, '') || 'fixpoint';
}

async function render() {
  const output = prompt('Render the full image to (a file in the served folder):', `${stem(S.path)}.png`);
  if (!output) return;
  const button = $('render');
  button.disabled = true;
  setStatus(`rendering ${output}…`);
  try {
    const body = { text: editor.value, path: S.path, output, force: false };
    let a = await post('/api/render', body);
    if (!a.ok && /exist/i.test(a.error) && confirm(`${a.error}\n\nReplace it?`)) {
      setStatus(`rendering ${output}…`);
      a = await post('/api/render', { ...body, force: true });
    }
    if (!a.ok) {
      setStatus(a.error, 'bad');
      if (a.line) showError(a);
      return;
    }
    setStatus(`wrote ${a.output} in ${Number(a.seconds).toFixed(2)} s`, 'good');
    const log = $('log');
    log.textContent = a.summary || '';
    log.hidden = !a.summary;
  } finally {
    button.disabled = false;
  }
}

async function openRecipe(file) {
  setStatus(`reading the recipe of ${file.name}…`);
  const bytes = await new Promise((resolve, reject) => {
    const r = new FileReader();
    r.onload = () => resolve(r.result);
    r.onerror = () => reject(r.error);
    r.readAsArrayBuffer(file);
  });
  const a = await post('/api/recipe', bytes, 'application/octet-stream');
  if (!a.ok) {
    setStatus(a.error, 'bad');
    return;
  }
  // The recipe is a new config: it is not the file being edited, so Save asks for a name.
  S.path = '';
  S.suggest = `${file.name.replace(/\.[^.]*$/, '')}.yaml`;
  showPath();
  editor.value = a.text;
  renderGutter();
  setStatus(`opened the recipe of ${file.name}`, 'good');
  refresh();
}

const drop = $('drop');
let dragDepth = 0;
const hasFiles = (e) => e.dataTransfer && [...e.dataTransfer.types].includes('Files');
window.addEventListener('dragenter', (e) => {
  if (!hasFiles(e)) return;
  dragDepth++;
  drop.hidden = false;
});
window.addEventListener('dragleave', () => {
  dragDepth = Math.max(0, dragDepth - 1);
  if (dragDepth === 0) drop.hidden = true;
});
window.addEventListener('dragover', (e) => {
  if (hasFiles(e)) e.preventDefault();
});
window.addEventListener('drop', (e) => {
  if (!hasFiles(e)) return;
  e.preventDefault();
  dragDepth = 0;
  drop.hidden = true;
  const f = e.dataTransfer.files[0];
  if (f) openRecipe(f);
});

$('save').addEventListener('click', save);
$('show-unset').addEventListener('change', (e) => panel.classList.toggle('all', e.target.checked));
$('render').addEventListener('click', render);

// ------------------------------------------------------------------ start
async function start() {
  const st = await get('/api/state').catch(() => ({ ok: false, error: 'the server does not answer' }));
  if (st.ok === false) {
    setStatus(st.error, 'bad');
    return;
  }
  S.path = st.path || '';
  showPath();
  document.title = `fixpoint · ${S.path || 'new config'}`;
  if (st.version) $('bar').querySelector('.brand').title = `fixpoint ${st.version}, ${st.threads} threads`;
  editor.value = st.text || '';
  renderGutter();
  refresh();
}

start();
