// The parameter panel of the preview page (app.js has the rest): one control per parameter of
// the config, made from the plugins' declarations as /api/params reports them. A change is an
// edit of the text (setParam, in app.js), never a change of the panel itself: the panel is
// built again from the new text.
'use strict';
/* global S, edit, panel, setParam */
/* exported buildPanel */

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
  // (A break opportunity after each underscore: a long name wraps between its words.)
  const label = el('label', { title: e.description || e.name });
  const words = e.name.split('_');
  words.forEach((w, i) => {
    if (i < words.length - 1) label.append(`${w}_`, el('wbr'));
    else label.append(w);
  });
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
  // Shift+drag: fine adjustment, the thumb moving a tenth as far as the pointer, from where it
  // is (no jump to the pointer). A plain drag is the browser's own.
  slider.addEventListener('pointerdown', (ev) => {
    if (!ev.shiftKey) return;
    ev.preventDefault();
    slider.setPointerCapture(ev.pointerId);
    const x0 = ev.clientX, v0 = Number(slider.value), w = slider.getBoundingClientRect().width;
    const lo = Number(slider.min), hi = Number(slider.max);
    const move = (m) => {
      slider.value = Math.min(hi, Math.max(lo, v0 + ((m.clientX - x0) * (hi - lo)) / (10 * w)));
      field.value = read();
      setParam(e.path, read());
    };
    const up = () => {
      slider.removeEventListener('pointermove', move);
      slider.removeEventListener('pointerup', up);
      slider.removeEventListener('pointercancel', up);
    };
    slider.addEventListener('pointermove', move);
    slider.addEventListener('pointerup', up);
    slider.addEventListener('pointercancel', up);
  });
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

// An item of a list as flow YAML, from the entries the config writes. With `type` and `keep`: as
// that plugin, with the parameters `keep` takes (a switch of plugin); `value(c, i)` gives each
// parameter's text, at any depth (the moved copy "add" appends).
function flowOf(entries, at, type = null, keep = () => true, value = (c) => c.value) {
  const top = entries[at];
  const t = type !== null ? type : unquote(top.value);
  const parts = top.kind === 'plugin' || top.kind === 'list' ? [`type: ${t}`] : [];
  for (let i = at + 1; i < entries.length && entries[i].depth > top.depth; i++) {
    const c = entries[i];
    if (c.depth !== top.depth + 1 || !c.path.startsWith(top.path + '.') || !keep(c.name)) continue;
    if (c.kind === 'plugin' && c.value) parts.push(`${c.name}: ${flowOf(entries, i, null, () => true, value)}`);
    else if (c.written && c.kind !== 'list') parts.push(`${c.name}: ${value(c, i)}`);
  }
  return `{${parts.join(', ')}}`;
}

// The copy of item `at` that "add" appends, moved so that it shows: a centre (an inversion's
// circle, a star's) moves right by twice the radius beside it (or 1/4 without one), so the new
// map is not hidden under the one it copies.
function movedCopy(entries, at) {
  const num = (t) => (String(t).match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || []).map(Number);
  const radius = (c) => {
    const parent = c.path.slice(0, c.path.lastIndexOf('.'));
    const r = entries.find((x) => (x.path === `${parent}.radius` || x.path === `${parent}.outer_radius`) && x.value);
    const v = r ? num(r.value)[0] : NaN;
    return isFinite(v) && v > 0 ? v : 0.25;
  };
  return flowOf(entries, at, null, () => true, (c) => {
    const p = num(c.value);
    if (c.kind !== 'point' || c.name !== 'centre' || p.length !== 2) return c.value;
    return `[${Number((p[0] + 2 * radius(c)).toPrecision(6))}, ${p[1]}]`;
  });
}

// The value of a slot switched to plugin n: {type: n} with what the slot writes that n declares
// too (a circle's centre, kept by a star polygon), so that a switch keeps what carries over.
function switchTo(entries, at) {
  const e = entries[at];
  return (n) => {
    const names = ((S.pluginParams || {})[e.plugin_kind] || {})[n];
    return names ? flowOf(entries, at, n, (name) => names.includes(name)) : `{type: ${n}}`;
  };
}

function listHead(e, entries) {
  const add = el('button', { type: 'button', className: 'small', textContent: 'add' });
  add.dataset.path = e.path;
  add.title = `append a copy of the last item of ${e.name}, moved beside it`;
  add.addEventListener('click', () => {
    const last = entries.findIndex((x) => x.path === `${e.path}[${e.count - 1}]`);
    const value = last >= 0 ? movedCopy(entries, last) : '{type: inversion, shape: {type: circle, centre: [0, 0], radius: 0.5}}';
    edit('append', e.path, value);
  });
  const c = el('div', { className: 'ctl' }, el('span', { className: 'hex', textContent: `${e.count} items` }), add);
  c.update = (x) => {
    c.firstChild.textContent = `${x.count} items`;
  };
  return c;
}

function itemHead(e, isPlugin, plugins, entries, at) {
  const parts = [];
  if (isPlugin) parts.push(...selectControl(e, plugins, switchTo(entries, at)).childNodes);
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
  if (parentList) return [itemHead(e, e.kind === 'plugin', e.choices || [], entries, at), 'item'];
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
      return [selectControl(e, e.choices || [], switchTo(entries, at)), e.depth > 0 ? 'head sub' : 'head'];
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
