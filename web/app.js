// The preview page of `fixpoint serve`. It talks to the server only through the requests of
// docs/serve-api.md. The YAML in the editor is the source of truth: every request carries it
// whole, and every change the page makes (a slider, a colour, a plugin, pan and zoom) is an
// edit the server applies to that text (POST /api/edit), whose answer replaces the editor's
// text; the preview and the parameter panel then follow from the new text.
'use strict';
/* global buildPanel, EditHistory */ // panel.js and history.js, loaded before this file
/* exported setParam */ // (called by panel.js)

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
  entries: [],
  signature: '',
  spans: new Map(), // path -> [lo, hi, step] of its slider, kept while the value stays inside
  lastText: '',     // the editor's text after the last change (what a burst of typing started from)
  home: null,       // the view and fit_view the config was opened with ({region, fit}), for reset
  waiting: null,    // the AbortController of the frame request in flight
  after: -1,        // the last stage of S.job shown
  pluginParams: null, // kind -> plugin -> its parameter names (GET /api/plugins?params=1)
};
const edits = new EditHistory();

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
  imgbox.classList.add('stale'); // (the image is of the last good text, not of this one)
  errLine = e.line || 0;
  band.hidden = errLine === 0;
  renderGutter();
}

function clearError() {
  imgbox.classList.remove('stale');
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

// The text of an edit (recorded for undo) or of undo and redo themselves (record false).
function setText(text, record = true) {
  if (text === editor.value) return;
  if (record) edits.record(editor.value);
  const start = lineCol(editor.value, editor.selectionStart);
  const end = lineCol(editor.value, editor.selectionEnd);
  const top = editor.scrollTop;
  const left = editor.scrollLeft;
  editor.value = text;
  editor.setSelectionRange(offsetOf(text, start), offsetOf(text, end));
  editor.scrollTop = top;
  editor.scrollLeft = left;
  S.lastText = text;
  renderGutter();
  showUndo();
}

// A new document (the page's start, a dropped recipe): nothing to undo, its own home view.
function openText(text) {
  editor.value = text;
  S.lastText = text;
  S.home = null;
  edits.clear();
  renderGutter();
  showUndo();
}

function showUndo() {
  $('undo').disabled = !edits.canUndo();
  $('redo').disabled = !edits.canRedo();
}

function undoRedo(back) {
  const t = back ? edits.undo(editor.value) : edits.redo(editor.value);
  if (t === null) return;
  clearTimeout(burst);
  burst = 0;
  setText(t, false);
  showUndo();
  refresh();
}

let typing = 0, burst = 0;
editor.addEventListener('input', () => {
  // The keystrokes of one pause are one change to undo.
  if (!burst) edits.record(S.lastText);
  S.lastText = editor.value;
  clearTimeout(burst);
  burst = setTimeout(() => { burst = 0; }, 700);
  showUndo();
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
  if (!(e.ctrlKey || e.metaKey) || e.altKey) return;
  const k = e.key.toLowerCase();
  if (k === 's') {
    e.preventDefault();
    save();
  } else if (k === 'z' || k === 'y') {
    // The page's own history, in the editor too: the textarea's would not know the page's edits.
    e.preventDefault();
    undoRedo(k === 'z' && !e.shiftKey);
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
  // The frames of the job this text replaces are no longer wanted: the wait for them is dropped
  // before the server cancels the job (its answer would be a 410 in the console).
  if (S.waiting) S.waiting.abort();
  const seq = ++S.seq;
  const body = { text: editor.value, path: S.path };
  const preview = previews.then(() => (seq === S.seq ? post('/api/preview', body) : null));
  previews = preview.catch(() => null);
  const [pv, pr] = await Promise.all([preview, post('/api/params', body)]);
  if (seq !== S.seq || !pv) return;
  if (pr.ok) {
    buildPanel(pr.params);
    showViewButtons();
  }
  if (!pv.ok) {
    showError(pv);
    dropPending();
    // A refused text starts no preview: the last good one goes on refining (its wait was dropped).
    const finished = img.dataset.job === String(S.job) && img.dataset.done === '1';
    if (S.job && !S.waiting && !finished) follow(S.job, S.after);
    return;
  }
  clearError();
  // What the picture shows, fitted or given: a pan or zoom writes it into the text.
  const region = boxOf(pv.region);
  S.jobRegion.set(pv.job, region);
  imgbox.classList.toggle('fixed', !(region && S.regionParam));
  follow(pv.job);
}

// One wait for a job's frames at a time: following a job drops the wait for the one before, and
// a new text drops it before its preview replaces the job on the server (refresh), so that no
// request of a replaced job is in flight when the server cancels it (a 410 in the console).
async function follow(job, after = -1) {
  if (S.waiting) S.waiting.abort();
  const waiting = new AbortController();
  S.waiting = waiting;
  S.job = job;
  S.after = after;
  try {
    await followFrames(job, waiting.signal);
  } finally {
    if (S.waiting === waiting) S.waiting = null;
  }
}

async function followFrames(job, signal) {
  const current = () => S.job === job && !signal.aborted;
  while (current()) {
    let r;
    try {
      r = await fetch(`/api/frame?job=${encodeURIComponent(job)}&after=${S.after}`, withToken({ signal }));
    } catch (e) {
      if (e.name === 'AbortError') return; // (a newer text's preview replaces this one)
      if (S.job === job) setStatus('the server does not answer (is fixpoint serve still running?)', 'bad');
      return;
    }
    if (!current()) return;
    if (r.status === 204) continue; // nothing new within the server's wait: ask again
    if (r.status === 410) return;   // superseded by a newer preview
    if (r.status !== 200) {
      const e = await answer(r);
      if (!current()) return;
      if (r.status === 422) showError(e);
      else setStatus(e.error, 'bad');
      return;
    }
    const blob = await r.blob().catch(() => null); // (null: dropped while it came)
    if (!current() || !blob) return;
    const h = (k) => r.headers.get(k);
    const k = Number(h('X-Stage'));
    const done = h('X-Done') === '1';
    showFrame(blob, job, {
      stage: k, stages: Number(h('X-Stages')), width: Number(h('X-Width')), height: Number(h('X-Height')),
      spp: Number(h('X-Samples-Per-Pixel')), seconds: Number(h('X-Seconds')), done,
      retoned: h('X-Retoned') === '1',
    });
    S.after = k;
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
  // A change of finishing parameters alone is finished from the kept histogram: say so.
  caption.textContent = `stage ${f.stage + 1}/${f.stages} · ${f.width}×${f.height} · ` +
      `${number(f.spp)} samples/px · ${f.seconds.toFixed(2)} s` +
      (f.retoned ? ' · re-toned, no iterating' : '');
  img.dataset.retoned = f.retoned ? '1' : '0';
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

// A view's number to a tenth of the image's pixel `px` (plane units): no more digits than the
// picture can show.
function real(x, px) {
  const d = px > 0 ? Math.max(0, Math.min(15, Math.ceil(-Math.log10(px)) + 1)) : 10;
  return String(Number(x.toFixed(d)));
}

// Reset: the view (and fit_view) the config was opened with; fit: chaos-game's fit_view.
// (A view the text does not write, fitted by the renderer, is not written back: fit_view is.)
function entryValue(path, written = false) {
  const e = (S.entries || []).find((p) => p.path === path);
  return e && (e.written || !written) ? e.value.trim() : undefined;
}

function showViewButtons() {
  if (S.home === null && S.regionParam)
    S.home = { region: entryValue(S.regionParam, true), fit: entryValue('renderer.fit_view') };
  const fit = entryValue('renderer.fit_view');
  $('fit-view').disabled = fit === undefined || fit === 'true';
  $('reset-view').disabled = !S.home || (S.home.region === undefined && S.home.fit === undefined);
}

async function resetView() {
  const h = S.home;
  if (!h) return;
  if (h.fit !== undefined && entryValue('renderer.fit_view') !== h.fit &&
      !(await edit('set', 'renderer.fit_view', h.fit))) return;
  if (h.region !== undefined && entryValue(S.regionParam) !== h.region) await edit('set', S.regionParam, h.region);
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
  // (The region pending becomes the one written, so that its image is known for it.)
  // (The config's width, not a draft stage's.)
  const width = (S.entries || []).find((p) => p.path === 'renderer.width');
  const px = Math.abs(r.xmax - r.xmin) / Math.max(1, (width && Number(width.value)) || S.frameW);
  const v = [r.xmin, r.xmax, r.ymin, r.ymax].map((x) => real(x, px));
  [r.xmin, r.xmax, r.ymin, r.ymax] = v.map(Number);
  placeImage();
  const ok = await edit('set', S.regionParam, `[${v.join(', ')}]`);
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
  openText(a.text);
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
$('undo').addEventListener('click', () => undoRedo(true));
$('redo').addEventListener('click', () => undoRedo(false));
$('reset-view').addEventListener('click', resetView);
$('fit-view').addEventListener('click', () => edit('set', 'renderer.fit_view', 'true'));
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
  openText(st.text || '');
  refresh();
  // Each plugin's parameter names: what a switch of plugin carries over (panel.js).
  const named = await get('/api/plugins?params=1').catch(() => null);
  if (named && named.ok !== false) S.pluginParams = named;
}

start();
