// popcut designer: drawing on the edit plane, the session's answers shown as pattern, check and 3D card; talks to
// popcutd's /api/v1/designs with the token from ?token= (kept in localStorage, as the kiosk does).
'use strict';

const params = new URLSearchParams(location.search);
if (params.get('token')) localStorage.setItem('popcut-token', params.get('token'));
const token = localStorage.getItem('popcut-token') || '';
const $ = (id) => document.getElementById(id);
const SVG = 'http://www.w3.org/2000/svg';

const ui = { tool: 'wall', shape: 'rect', points: [], cursor: null };
let design = null;      // the last answer: design (its file), pattern, check
let view = null;        // the 3D card
const timings = [];     // ms from a click that finished an edit to the repaint of its answer
window.designTimings = timings;

async function api(method, path, body) {
  const headers = { Authorization: 'Bearer ' + token };
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const res = await fetch(path, { method, headers, body: body === undefined ? (method === 'GET' ? undefined : '') : body });
  const text = await res.text();
  let data = null;
  try { data = JSON.parse(text); } catch (_) { /* an export, or not JSON */ }
  if (!res.ok) {
    const e = data && data.error;
    // A wrong token must not stay in this browser for the next visit.
    if (res.status === 401) localStorage.removeItem('popcut-token');
    throw new Error((e ? e.message : res.status + ' ' + res.statusText) + (res.status === 401 ? ': open this page with ?token=YOUR_TOKEN' : ''));
  }
  return data === null ? text : data;
}

function el(tag, attrs, parent) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

function say(id, text) {
  $(id).hidden = !text;
  $(id).textContent = text || '';
}

// ---- the edit plane: a wall's plane (x, z) with z up, or a roof's (x, y) seen from above, back at the top.

const isWallTool = (tool) => tool === 'wall' || tool === 'opening';
const isOpening = (tool) => tool === 'opening' || tool === 'roof_opening';
const planeT = () => Number($('plane-t').value);
const sheet = () => design.design.sheet;
const planeHeight = () => (isWallTool(ui.tool) ? sheet().back : sheet().floor);
// Plane point (a, b) to SVG user units and back: a wall's z grows upwards.
const toSvg = (a, b) => (isWallTool(ui.tool) ? [a, -b] : [a, b]);
const fromSvg = (x, y) => (isWallTool(ui.tool) ? [x, -y] : [x, y]);

function svgPoint(event) {
  const svg = $('edit');
  const p = svg.createSVGPoint();
  p.x = event.clientX;
  p.y = event.clientY;
  const q = p.matrixTransform(svg.getScreenCTM().inverse());
  return fromSvg(q.x, q.y);
}

// The nearest corner of an item drawn in this kind of plane within 8 pixels, else the grid point.
function snap([a, b]) {
  const svg = $('edit');
  const mmPerPx = svg.viewBox.baseVal.width / svg.clientWidth;
  let best = null, bestD = 8 * mmPerPx;
  for (const it of design.design.items) {
    if (isWallTool(it.tool) !== isWallTool(ui.tool)) continue;
    for (const [x, y] of it.outline || [it.at]) {
      const d = Math.hypot(x - a, y - b);
      if (d < bestD) { best = [x, y]; bestD = d; }
    }
  }
  if (best) return best;
  const g = Number($('grid').value);
  const clamp = (v, hi) => Math.min(Math.max(v, 0), hi);
  return [clamp(Math.round(a / g) * g, sheet().width), clamp(Math.round(b / g) * g, planeHeight())];
}

function drawEditPlane() {
  const svg = $('edit');
  svg.textContent = '';
  if (!design) return;
  const w = sheet().width, h = planeHeight(), m = Math.max(w, h) * 0.04;
  const [x0, y0] = toSvg(0, isWallTool(ui.tool) ? h : 0);
  svg.setAttribute('viewBox', `${x0 - m} ${y0 - m} ${w + 2 * m} ${h + 2 * m}`);
  el('rect', { x: x0, y: y0, width: w, height: h, fill: '#fff', stroke: '#999', 'stroke-width': 0.3 }, svg);
  const g = Number($('grid').value), grid = el('g', { stroke: '#e6e2d8', 'stroke-width': 0.15 }, svg);
  for (let a = 0; a <= w + 1e-9; a += g) el('line', { x1: a, y1: y0, x2: a, y2: y0 + h }, grid);
  for (let b = 0; b <= h + 1e-9; b += g) {
    const y = toSvg(0, b)[1];
    el('line', { x1: 0, y1: y, x2: w, y2: y }, grid);
  }
  el('line', { x1: w / 2, y1: y0, x2: w / 2, y2: y0 + h, stroke: '#b9a', 'stroke-dasharray': '2 1', 'stroke-width': 0.3 }, svg);
  const t = planeT();
  for (const it of design.design.items) {
    if (isWallTool(it.tool) !== isWallTool(ui.tool)) {
      // A wall seen from above is a line at its depth; a roof seen from the front one at its height.
      if (it.tool === 'wall' || it.tool === 'roof') footprint(svg, it);
      continue;
    }
    const here = Math.abs(it.t - t) < 1e-6, opening = it.tool === 'opening' || it.tool === 'roof_opening';
    const style = { fill: opening ? '#fcfbf8' : here ? '#c9d9ec' : 'none', stroke: here ? '#3b4a5a' : '#b8b2a5',
      'stroke-width': here ? 0.5 : 0.3, 'stroke-dasharray': opening ? '1.5 0.8' : 'none', 'data-item': it.id };
    if (it.text) { drawText(svg, it, Object.assign(style, { fill: here ? '#3b4a5a' : '#b8b2a5', stroke: 'none' })); continue; }
    outlinePath(svg, it.outline, style, it.holes);
    if (it.mirror) {
      const m = (ring) => ring.map(([a, b]) => [w - a, b]);
      outlinePath(svg, m(it.outline), Object.assign({}, style, { 'fill-opacity': 0.5 }), (it.holes || []).map(m));
    }
  }
  el('g', { id: 'overlay' }, svg);
  drawOverlay();
}

// An outline as SVG path data in the plane's coordinates.
function pathData(pts, closed) {
  return pts.map((p, i) => (i ? 'L' : 'M') + toSvg(p[0], p[1]).join(' ')).join(' ') + (closed ? ' Z' : '');
}

// An outline and its holes (an imported face's), which show what is behind.
function outlinePath(svg, pts, style, holes) {
  const d = [pts, ...(holes || [])].map((ring) => pathData(ring, true)).join(' ');
  return el('path', Object.assign({ d, 'fill-rule': 'evenodd' }, style), svg);
}

// Letters as the browser sets them in the item's font, near enough to place them by; the pattern
// and the card show the letters popcutd set (and a wall's frame).
function drawText(svg, it, style) {
  const em = it.text.size / 0.729, lines = it.text.string.split('\n');  // DejaVu's H is 0.729 em tall
  const up = isWallTool(it.tool) ? 1 : -1;
  const [x, y] = toSvg(it.at[0], it.at[1] + up * (0.236 * em + (lines.length - 1) * 1.164 * em));
  const t = el('text', Object.assign({ x, y, 'font-family': it.text.font, 'font-size': em, 'xml:space': 'preserve' }, style), svg);
  lines.forEach((line, i) => { el('tspan', { x, dy: i ? 1.164 * em : 0 }, t).textContent = line; });
  return t;
}

const textWidth = (it) => 0.62 * (it.text.size / 0.729) * Math.max(...it.text.string.split('\n').map((l) => l.length));

function footprint(svg, it) {
  const xs = it.text ? [it.at[0], it.at[0] + textWidth(it)] : it.outline.map((p) => p[0]);
  const y = toSvg(0, it.t)[1];
  el('line', { x1: Math.min(...xs), y1: y, x2: Math.max(...xs), y2: y, stroke: '#8fa3b8', 'stroke-width': 0.6 }, svg);
}

// The outline being drawn and the cursor: redrawn on every pointer move, so it alone is rebuilt
// (the grid and the items are redrawn only when the design, tool, plane or grid changes).
function drawOverlay() {
  const svg = document.getElementById('overlay');
  if (!svg) return;
  svg.textContent = '';
  const pts = ui.points.slice();
  if (ui.cursor) {
    const [cx, cy] = toSvg(...ui.cursor);
    el('circle', { cx, cy, r: 0.8, fill: '#d62728' }, svg);
    $('hint').textContent = `${isWallTool(ui.tool) ? 'x, z' : 'x, y'} = ${ui.cursor[0]}, ${ui.cursor[1]} mm · ` + hint();
  }
  if (ui.shape === 'text' && ui.cursor && $('text-string').value) {
    drawText(svg, { tool: ui.tool, at: ui.cursor, text: textSpec() }, { fill: '#d6272866' });
  }
  if (!pts.length) return;
  const twoClick = ui.shape !== 'polygon';
  const shown = !ui.cursor ? pts : twoClick ? twoClickOutline(pts[0], ui.cursor) || pts : pts.concat([ui.cursor]);
  el('path', { d: pathData(shown, twoClick), fill: '#d6272822', stroke: '#d62728', 'stroke-width': 0.4 }, svg);
  for (const p of pts) {
    const [cx, cy] = toSvg(...p);
    el('circle', { cx, cy, r: 0.9, fill: '#fff', stroke: '#d62728', 'stroke-width': 0.3 }, svg);
  }
}

function hint() {
  if (ui.shape === 'text') return $('text-string').value ? 'click where the text\'s lower left corner goes' : 'type the text first';
  if (ui.shape === 'rect') return ui.points.length ? 'click the opposite corner (Esc: cancel)' : 'click a corner';
  if (ui.shape !== 'polygon') {
    return ui.points.length ? `click ${ui.shape === 'circle' ? 'a point on the circle' : 'a corner'} (Esc: cancel)` : 'click the centre';
  }
  return ui.points.length < 3 ? 'click each corner' : 'click the first corner or press Enter to close (Esc: cancel)';
}

// The outline a two-click shape makes from its first and second click, or null when degenerate.
function twoClickOutline(first, second) {
  if (ui.shape === 'rect') {
    const r = rectangle(first, second);
    return r[0][0] === r[1][0] || r[0][1] === r[2][1] ? null : r;
  }
  const radius = Math.hypot(second[0] - first[0], second[1] - first[1]);
  if (radius === 0) return null;
  const start = Math.atan2(second[1] - first[1], second[0] - first[0]);
  return regularPolygon(first, radius, start, ui.shape === 'circle' ? circleSides(radius) : sides());
}

// The Sides field, kept to 3..64 and shown as used.
function sides() {
  const n = Math.min(64, Math.max(3, Math.round(Number($('sides').value)) || 6));
  $('sides').value = String(n);
  return n;
}

// A circle cut as a polygon whose every chord stays within 0.02 mm of the true circle
// (sagitta r (1 - cos(pi / n)) <= 0.02), at least 12 sides.
function circleSides(radius) {
  const tolerance = 0.02;
  if (radius <= tolerance) return 12;
  return Math.min(720, Math.max(12, Math.ceil(Math.PI / Math.acos(1 - tolerance / radius))));
}

// Corners to the micrometre (the model keeps nanometres; a micrometre moves no chord past the tolerance).
function regularPolygon([cx, cy], radius, start, sides) {
  const n = Math.max(3, Math.min(720, Math.round(sides) || 3));
  const round = (v) => Math.round(v * 1000) / 1000;
  const out = [];
  for (let k = 0; k < n; ++k) {
    const a = start + (2 * Math.PI * k) / n;
    out.push([round(cx + radius * Math.cos(a)), round(cy + radius * Math.sin(a))]);
  }
  return out;
}

function rectangle([a0, b0], [a1, b1]) {
  const [xa, xb] = [Math.min(a0, a1), Math.max(a0, a1)], [ya, yb] = [Math.min(b0, b1), Math.max(b0, b1)];
  return [[xa, ya], [xb, ya], [xb, yb], [xa, yb]];
}

// Counter-clockwise in the plane's own coordinates, as the design file writes outlines.
function counterClockwise(pts) {
  let twice = 0;
  pts.forEach((p, i) => { const q = pts[(i + 1) % pts.length]; twice += p[0] * q[1] - q[0] * p[1]; });
  return twice < 0 ? pts.slice().reverse() : pts;
}

function onEditClick(event) {
  if (!design) return;
  const p = snap(svgPoint(event));
  const started = performance.now();
  if (ui.shape === 'text') return addText(p, started);
  if (ui.shape !== 'polygon') {
    if (!ui.points.length) { ui.points = [p]; drawOverlay(); return; }
    const outline = twoClickOutline(ui.points[0], p);
    ui.points = [];
    if (!outline) { say('edit-error', 'The second click must be somewhere else than the first.'); drawOverlay(); return; }
    return addItem(counterClockwise(outline), started);
  }
  const first = ui.points[0];
  if (first && ui.points.length >= 3 && p[0] === first[0] && p[1] === first[1]) return closePolygon(started);
  const last = ui.points[ui.points.length - 1];
  // A double click lands twice on one corner: the second click closes the outline (no dblclick
  // handler, which would come after it and find nothing left to close).
  if (last && ui.points.length >= 3 && last[0] === p[0] && last[1] === p[1]) return closePolygon(started);
  if (!last || last[0] !== p[0] || last[1] !== p[1]) ui.points.push(p);
  drawOverlay();
}

function closePolygon(started) {
  const outline = ui.points;
  if (outline.length < 3) { say('edit-error', 'An outline needs at least three corners.'); return; }
  ui.points = [];
  return addItem(counterClockwise(outline), started);
}

async function addItem(outline, started) {
  const item = { tool: ui.tool, t: planeT(), outline, mirror: $('mirror').checked };
  if (ui.tool === 'wall') item.top = $('tops').checked;
  if (isOpening(ui.tool) && !$('ledge').checked) item.ledge = false;
  await edit('POST', '/items', JSON.stringify(item), started);
}

function textSpec() {
  const spec = { string: $('text-string').value, font: $('text-font').value, size: Number($('text-size').value) };
  if (ui.tool === 'wall') spec.frame = $('text-frame').checked;
  return spec;
}

async function addText(at, started) {
  if (!$('text-string').value.trim()) { say('edit-error', 'Type the text first (the box beside Text).'); return; }
  const item = { tool: ui.tool, t: planeT(), text: textSpec(), at };
  if (ui.tool === 'wall') item.top = $('tops').checked;
  if ($('mirror').checked) item.mirror = true;  // popcutd says why text is not mirrored
  if (isOpening(ui.tool) && !$('ledge').checked) item.ledge = false;
  await edit('POST', '/items', JSON.stringify(item), started);
}

async function loadFonts() {
  const { fonts, default: chosen } = await api('GET', '/api/v1/fonts');
  for (const f of fonts) $('text-font').appendChild(new Option(f, f));
  $('text-font').value = fonts.includes(chosen) ? chosen : fonts[0] || '';
}

// ---- answers

async function edit(method, rest, body, started) {
  try {
    const answer = await api(method, `/api/v1/designs/${design.id}${rest}`, body);
    show(answer, started);
  } catch (e) {
    say('edit-error', e.message);  // the session is as it was: nothing to take back here
    drawEditPlane();
  }
}

function show(answer, started) {
  design = answer;
  say('edit-error', '');  // whatever failed before, this answer stands
  localStorage.setItem('popcut-design', String(design.id));
  if (document.activeElement !== $('name')) $('name').value = design.design.name || '';
  $('undo').disabled = !design.can_undo;
  $('redo').disabled = !design.can_redo;
  drawEditPlane();
  drawPattern();
  drawItems();
  const failing = new Set(design.check.not_standing.map((p) => p.face));
  for (const piece of design.check.loose_pieces) piece.faces.forEach((f) => failing.add(f));
  const dropped = new Set(design.check.cut_out.flatMap((piece) => piece.faces));  // fall out of their openings
  view.setPattern(design.pattern, failing, new Set(design.check.flaps.map((p) => p.face)), dropped);
  document.body.dataset.revision = String(Number(document.body.dataset.revision || 0) + 1);
  const n = design.design.items.length;
  $('status').textContent = `draft ${design.id} · ${n} ${n === 1 ? 'item' : 'items'}` +
    (design.answer_ms === undefined ? '' : ` · answered in ${design.answer_ms} ms`);
  if (started !== undefined) requestAnimationFrame(() => timings.push(performance.now() - started));
}

function drawPattern() {
  const svg = $('pattern'), p = design.pattern, s = p.sheet;
  svg.textContent = '';
  // Pattern v grows up the back board; the SVG's y grows down.
  svg.setAttribute('viewBox', `${s.min[0] - 2} ${-s.max[1] - 2} ${s.max[0] - s.min[0] + 4} ${s.max[1] - s.min[1] + 4}`);
  el('rect', { x: s.min[0], y: -s.max[1], width: s.max[0] - s.min[0], height: s.max[1] - s.min[1], fill: '#fff',
    stroke: '#999', 'stroke-width': 0.2 }, svg);
  const bad = new Set(design.check.not_standing.map((q) => q.face));
  const flaps = new Set(design.check.flaps.map((q) => q.face));
  p.faces.forEach((f, i) => {
    if (!bad.has(i) && !flaps.has(i)) return;
    const ring = (r) => r.map(([x, v], k) => (k ? 'L' : 'M') + x + ' ' + -v).join(' ') + ' Z';
    el('path', { d: [f.outer].concat(f.holes).map(ring).join(' '), fill: bad.has(i) ? '#e0483c66' : '#f0a03055',
      'fill-rule': 'evenodd', class: bad.has(i) ? 'failing-face' : 'flap-face', 'data-face': i }, svg);
  });
  const styles = { valley: { stroke: '#1f5fd6', 'stroke-dasharray': '1.5 0.75' },
    mountain: { stroke: '#d62728', 'stroke-dasharray': '2 0.5 0.4 0.5' }, cut: { stroke: '#000' } };
  for (const kind of ['valley', 'mountain', 'cut']) {
    const g = el('g', Object.assign({ class: kind, fill: 'none', 'stroke-width': 0.35, 'stroke-linecap': 'round' }, styles[kind]), svg);
    for (const { a, b } of p.lines.filter((l) => l.kind === kind)) el('line', { x1: a[0], y1: -a[1], x2: b[0], y2: -b[1] }, g);
  }
  const c = design.check;
  $('verdict').className = c.pops_up ? 'ok' : 'bad';
  $('verdict').textContent = c.pops_up ? `Pops up: ${c.faces} faces, ${c.lines.cut} cuts, ${c.lines.mountain + c.lines.valley} folds.`
    : 'Does not pop up' + (c.no_back_board ? ': no back board' : c.no_floor ? ': no floor' : c.sheet_split ? ': the sheet falls in two' : '.');
  const problems = c.not_standing.length + c.loose_pieces.length;
  $('card-verdict').className = c.pops_up ? 'ok' : 'bad';
  $('card-verdict').textContent = c.pops_up ? '✓ pops up' + (c.flaps.length ? ` (${c.flaps.length} hanging: see the check)` : '')
    : `✗ does not pop up${problems ? `: ${problems} ${problems === 1 ? 'problem' : 'problems'} in red` : ''}`;
  const list = $('check');
  list.textContent = '';
  for (const [problems, cls] of [[c.not_standing, 'fail'], [c.loose_pieces, 'fail'], [c.flaps, 'note'], [c.cut_out, 'note']]) {
    for (const q of problems) {
      const li = document.createElement('li');
      li.className = cls;
      li.textContent = q.message;
      list.appendChild(li);
    }
  }
}

const TOOL_NAMES = { wall: 'Wall', opening: 'Opening', roof: 'Roof', roof_opening: 'Roof opening' };

function drawItems() {
  const list = $('items');
  list.textContent = '';
  for (const it of design.design.items) {
    const li = document.createElement('li');
    const xs = (it.outline || [it.at]).map((p) => p[0]), ys = (it.outline || [it.at]).map((p) => p[1]);
    const size = it.text ? `“${it.text.string}” in ${it.text.font}, ${it.text.size} mm` + (it.text.frame === false ? ', no frame' : '')
      : `${+(Math.max(...xs) - Math.min(...xs)).toFixed(1)} × ${+(Math.max(...ys) - Math.min(...ys)).toFixed(1)} mm`;
    li.textContent = `${TOOL_NAMES[it.tool]} at ${isWallTool(it.tool) ? 'y' : 'z'} = ${it.t} mm, ${size}` +
      (it.holes ? `, ${it.holes.length} ${it.holes.length === 1 ? 'hole' : 'holes'}` : '') +
      (it.mirror ? ', mirrored' : '') + (it.top === false ? ', no tops' : '') + (it.ledge === false ? ', drops out' : '');
    li.className = isWallTool(it.tool) === isWallTool(ui.tool) && it.t === planeT() ? 'here' : '';
    li.dataset.item = it.id;
    li.addEventListener('click', () => { setTool(it.tool); setPlane(it.t); });
    const remove = document.createElement('button');
    remove.textContent = '✕';
    remove.title = 'Remove this item';
    remove.addEventListener('click', (e) => { e.stopPropagation(); edit('POST', `/items/${it.id}/remove`, undefined, performance.now()); });
    li.appendChild(remove);
    list.appendChild(li);
  }
}

// ---- tools, plane and keys

function setTool(tool) {
  ui.tool = tool;
  ui.points = [];
  for (const b of document.querySelectorAll('.tool')) b.setAttribute('aria-pressed', String(b.dataset.tool === tool));
  $('plane-label').textContent = isWallTool(tool) ? 'Depth y' : 'Height z';
  $('tops').disabled = tool !== 'wall';
  $('ledge').disabled = !isOpening(tool);
  $('text-frame').disabled = tool !== 'wall';
  if (design) {
    $('plane-slider').max = String(isWallTool(tool) ? sheet().floor : sheet().back);
    $('plane-title').textContent = `${TOOL_NAMES[tool]} on the plane ${isWallTool(tool) ? 'y' : 'z'} = ${planeT()} mm` +
      (isWallTool(tool) ? ' (seen from the front)' : ' (seen from above, back board at the top)');
    drawEditPlane();
    drawItems();
  }
}

function setShape(shape) {
  ui.shape = shape;
  ui.points = [];
  $('sides-label').hidden = shape !== 'regular';
  $('text-options').hidden = shape !== 'text';
  if (shape === 'text') $('text-string').focus();
  for (const b of document.querySelectorAll('.shape')) b.setAttribute('aria-pressed', String(b.dataset.shape === shape));
  if (design) drawEditPlane();
}

function setPlane(t) {
  $('plane-t').value = String(t);
  $('plane-slider').value = String(t);
  setTool(ui.tool);
}

function onKey(e) {
  if (e.target.tagName === 'INPUT' && e.target.type !== 'range' && e.target.type !== 'checkbox') return;
  if (e.key === 'Escape') { ui.points = []; drawOverlay(); }
  else if (e.key === 'Enter' && ui.shape === 'polygon') closePolygon(performance.now());
  else if ((e.ctrlKey || e.metaKey) && e.key.toLowerCase() === 'z') { e.preventDefault(); edit('POST', e.shiftKey ? '/redo' : '/undo', undefined, performance.now()); }
  else if (e.key === 'w') setTool('wall');
  else if (e.key === 'o') setTool('opening');
  else if (e.key === 'r') setTool('roof');
}

window.DesignerFiles.wire({ api, say, show, current: () => design, setPlane, setTool });

async function start() {
  view = new CardView($('view3d'));
  document.querySelectorAll('.tool').forEach((b) => b.addEventListener('click', () => setTool(b.dataset.tool)));
  document.querySelectorAll('.shape').forEach((b) => b.addEventListener('click', () => setShape(b.dataset.shape)));
  $('plane-t').addEventListener('input', () => { $('plane-slider').value = $('plane-t').value; setTool(ui.tool); });
  $('plane-slider').addEventListener('input', () => setPlane(Number($('plane-slider').value)));
  $('grid').addEventListener('change', () => drawEditPlane());
  $('edit').addEventListener('click', onEditClick);
  $('edit').addEventListener('pointermove', (e) => { if (design) { ui.cursor = snap(svgPoint(e)); drawOverlay(); } });
  $('undo').addEventListener('click', () => edit('POST', '/undo', undefined, performance.now()));
  $('redo').addEventListener('click', () => edit('POST', '/redo', undefined, performance.now()));
  $('angle').addEventListener('input', () => { $('angle-value').textContent = $('angle').value + '°'; view.setAngle(Number($('angle').value)); });
  document.addEventListener('keydown', onKey);
  $('text-string').addEventListener('input', () => drawOverlay());
  setShape('rect');
  setTool('wall');
  if (!token) { $('status').textContent = 'Open this page with ?token=YOUR_TOKEN (from popcutd.toml).'; return; }
  try {
    await loadFonts();
    await window.DesignerFiles.open(params.get('design') || localStorage.getItem('popcut-design'));
  } catch (e) {
    $('status').textContent = e.message;
  }
}

start();
