// popcut operator page logic: cutters, queue controls, history and the statistics chart over /api/v1 with the admin token.
'use strict';

const $ = (id) => document.getElementById(id);
const TOKEN_KEY = 'popcut-admin-token';
const FINAL = ['done', 'failed', 'cancelled'];
const WAITING = ['queued', 'planning', 'ready'];
const POLL_MS = 2000;
let token = sessionStorage.getItem(TOKEN_KEY) || '';
let pollTimer = null;
let lastHistory = 0;
let lastStats = 0;
let dragging = false;
// Each view's requests are numbered: an answer that comes back after a newer request was made is
// older than what that one shows, and is dropped.
const asked = { state: 0, history: 0, stats: 0 };     // no redraw of the queue while a row is dragged

// An API answer, or an Error whose message says what popcutd said ("405 ... (method_not_allowed)").
async function api(method, path, body) {
  const headers = { Authorization: 'Bearer ' + token };
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const res = await fetch(path, { method, headers, body: body === undefined ? (method === 'GET' ? undefined : '') : JSON.stringify(body) });
  if (!res.ok) {
    let message = res.status + ' ' + res.statusText;
    try { const e = (await res.json()).error; message = res.status + ': ' + e.message + ' (' + e.code + ')'; } catch (_) { /* not JSON */ }
    const err = new Error(message);
    err.status = res.status;
    throw err;
  }
  return res.json();
}

// The outcome of an operator's action, where the whole shop floor can read it.
function notice(text, isError) {
  const n = $('notice');
  n.hidden = !text;
  n.textContent = text || '';
  n.className = isError ? 'error' : 'ok';
}

function showError(id, err) {
  $(id).hidden = !err;
  $(id).textContent = err ? String(err.message || err) : '';
}

// Runs an action; says what came of it, and refreshes what it changed.
async function act(what, method, path, body) {
  try {
    await api(method, path, body);
    notice(what + ': done.', false);
  } catch (e) {
    notice(what + ' failed: ' + e.message, true);
  }
  refresh(true);
}

function el(tag, cls, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
}

// Puts `fresh` (elements with data-key and data-sig) into `box`, keeping an element already shown
// whose data-sig is the same and only copying its `.live` parts (progress, counts) over: a button
// stays the same element between polls, so a tap on it is never lost to a redraw.
function reconcile(box, fresh) {
  const shown = new Map([...box.children].map((c) => [c.dataset.key, c]));
  const out = fresh.map((n) => {
    const o = shown.get(n.dataset.key);
    if (!o || o.dataset.sig !== n.dataset.sig) return n;
    const from = n.querySelectorAll('.live'), to = o.querySelectorAll('.live');
    from.forEach((f, i) => {
      if (f.tagName === 'PROGRESS') to[i].value = f.value;
      else if (to[i].textContent !== f.textContent) to[i].textContent = f.textContent;
    });
    return o;
  });
  if (out.length !== box.children.length || out.some((n, i) => n !== box.children[i])) box.replaceChildren(...out);
}

function progressBar(value) {
  const bar = el('progress', 'live');
  bar.max = 1;
  bar.value = value;
  return bar;
}

function button(cls, text, onClick) {
  const b = el('button', cls, text);
  b.type = 'button';
  b.addEventListener('click', onClick);
  return b;
}

function seconds(s) {
  if (s === null || s === undefined) return '';
  if (s === 0) return '0 s';
  if (s < 90) return Math.ceil(s) + ' s';
  if (s < 5400) return Math.round(s / 60) + ' min';
  return (s / 3600).toFixed(1) + ' h';
}

function when(unix) {
  if (!unix) return '';
  const d = new Date(unix * 1000);
  const today = new Date().toDateString() === d.toDateString();
  return today ? d.toLocaleTimeString([], { hour: '2-digit', minute: '2-digit' }) : d.toLocaleString([], { month: 'short', day: 'numeric', hour: '2-digit', minute: '2-digit' });
}

// A device's state in words and a glyph (never by colour alone), from what popcutd reports; the
// sheet, paused-job and blade fields appear once popcutd has them.
function deviceState(d, job) {
  if (d.paused_job) return { key: 'job-paused', glyph: '⏸', text: 'JOB #' + d.paused_job + ' PAUSED' };
  if (job) {
    const pct = Math.floor(job.progress * 100);
    if (d.state === 'pausing') return { key: 'pausing', glyph: '⏸', text: 'PAUSING — finishing #' + job.id };
    return { key: 'cutting', glyph: '▶', text: 'CUTTING ' + pct + '%' };
  }
  // Cutting a job this poll could not fetch: still cutting, without the numbers.
  if (d.job) return { key: 'cutting', glyph: '▶', text: (d.state === 'pausing' ? 'PAUSING — finishing #' : 'CUTTING #') + d.job };
  if (d.state === 'paused') return { key: 'paused', glyph: '⏸', text: 'PAUSED' };
  // The device itself said it has none (GP-GL tray empty): the same step, in its words.
  if (d.tray_empty) return { key: 'awaiting-sheet', glyph: '⚠', text: 'NO SHEET LOADED' };
  if (d.sheet === 'awaiting_sheet') return { key: 'awaiting-sheet', glyph: '⚠', text: 'LOAD A FRESH SHEET' };
  return { key: 'idle', glyph: '●', text: 'IDLE' };
}

function deviceCard(d, jobsById) {
  const job = d.job ? jobsById[d.job] : null;
  const s = deviceState(d, job);
  const card = el('article', 'device');
  card.dataset.name = card.dataset.key = d.name;
  card.dataset.state = s.key;
  card.dataset.sig = JSON.stringify([s.key, d.paused, d.job, d.sheet, d.blade ? d.blade.worn : null, !!d.blade]);
  const head = el('div', 'device-head');
  head.append(el('h3', null, d.name), el('span', 'muted', d.model));
  card.append(head, el('p', 'big-state live', s.glyph + ' ' + s.text));
  if (d.blade && d.blade.worn) {
    card.dataset.blade = 'worn';
    card.append(el('p', 'blade-worn live', '⚠ BLADE WORN — ' + Math.round(d.blade.cut_mm / 1000) + ' m cut'));
  }
  if (job) {
    card.append(el('p', 'device-job live', '#' + job.id + ' ' + job.name + ' — ' + job.strokes_sent + '/' + job.strokes_total +
                   ' strokes' + (job.eta_s !== null ? ' — about ' + seconds(job.eta_s) + ' left' : '')));
    card.append(progressBar(job.progress));
  }
  const buttons = el('div', 'buttons');
  if (d.paused) buttons.append(button('resume-device', 'Resume cutter', () => act('Resuming ' + d.name, 'POST', '/api/v1/devices/' + encodeURIComponent(d.name) + '/resume')));
  else buttons.append(button('pause-device secondary', 'Pause cutter', () => act('Pausing ' + d.name, 'POST', '/api/v1/devices/' + encodeURIComponent(d.name) + '/pause')));
  // A fresh sheet is confirmed only between jobs; popcutd refuses it (409) while the cutter cuts.
  if (d.sheet !== 'loaded' && !job) buttons.append(button('sheet', 'Sheet loaded', () => act('Sheet loaded on ' + d.name, 'POST', '/api/v1/devices/' + encodeURIComponent(d.name) + '/sheet', {})));
  if (d.blade) buttons.append(button('blade secondary', 'Blade changed', () => act('Blade changed on ' + d.name, 'POST', '/api/v1/devices/' + encodeURIComponent(d.name) + '/blade', {})));
  card.append(buttons);
  return card;
}

function renderDevices(devices, jobsById) {
  reconcile($('devices'), devices.map((d) => deviceCard(d, jobsById)));
  const sel = $('filter-device');
  if (sel.options.length === 1) for (const d of devices) sel.append(new Option(d.name, d.name));
}

// The order the cutters take waiting jobs: priority first (once popcutd has it), then place in line.
function queueOrder(a, b) {
  const pa = a.priority || 0, pb = b.priority || 0;
  if (pa !== pb) return pb - pa;
  const la = a.place_in_line === null ? 1e9 : a.place_in_line, lb = b.place_in_line === null ? 1e9 : b.place_in_line;
  return la !== lb ? la - lb : a.id - b.id;
}

function jobControls(j) {
  const id = j.id, path = '/api/v1/jobs/' + id;
  const out = [];
  if (j.state === 'cutting') out.push(button('pause secondary', 'Pause', () => act('Pausing job ' + id, 'POST', path + '/pause', {})));
  if (j.state === 'paused') out.push(button('continue', 'Continue', () => act('Continuing job ' + id, 'POST', path + '/continue', {})));
  if (j.state === 'interrupted') out.push(button('resume', 'Resume', () => act('Resuming job ' + id, 'POST', path + '/resume', {})));
  if (!FINAL.includes(j.state)) out.push(button('cancel danger', 'Cancel', () => {
    if (j.state !== 'cutting' || confirm('Cancel job ' + id + ' while it cuts? The knife is lifted and the sheet stays half cut.')) act('Cancelling job ' + id, 'POST', path + '/cancel');
  }));
  return out;
}

function moveBefore(id, before) {
  return act('Moving job ' + id + ' ahead of job ' + before, 'PATCH', '/api/v1/jobs/' + id, { before });
}

function queueRow(j, ahead) {
  const li = el('li', 'qjob');
  li.dataset.id = li.dataset.key = j.id;
  li.dataset.state = j.state;
  li.dataset.sig = JSON.stringify([j.state, ahead ? ahead.id : null, j.name]);
  const waiting = WAITING.includes(j.state);
  const title = el('div', 'title');
  title.append(el('span', 'handle', waiting ? '☰' : ''), el('strong', null, '#' + j.id + ' ' + j.name), el('span', 'muted', ' by ' + j.owner));
  let where = j.cut_on ? 'on ' + j.cut_on : (j.device ? 'for ' + j.device : 'any ' + j.profile);
  if (j.bound_to && j.state !== 'cutting') where = 'held by ' + j.bound_to;
  if (j.material) where += ' · ' + j.material;
  if (j.priority) where += ' · priority ' + j.priority;
  if (j.place_in_line !== null) where += ' · ' + (j.place_in_line === 0 ? 'next' : j.place_in_line + ' ahead');
  if (j.eta_s !== null) where += ' · done in about ' + seconds(j.eta_s);
  if (j.state === 'cutting' || j.state === 'interrupted' || j.state === 'paused') where += ' · ' + j.strokes_sent + '/' + j.strokes_total + ' strokes';
  if (j.sheets > 1) where += ' · sheet ' + j.sheet + ' of ' + j.sheets;
  if (j.pause === 'requested') where += ' · pause requested';
  if (j.error && j.state !== 'cutting') where += ' · ' + j.error.message;
  const badge = el('span', 'badge s-' + j.state, j.state.toUpperCase());
  const buttons = el('div', 'buttons');
  if (waiting && ahead) buttons.append(button('up secondary', '▲', () => moveBefore(j.id, ahead.id)));
  buttons.append(...jobControls(j));
  li.append(title, badge, el('div', 'where live', where), buttons);
  if (j.state === 'cutting' || j.state === 'paused' || j.state === 'interrupted') li.append(progressBar(j.progress));
  if (waiting) {
    li.draggable = true;
    li.addEventListener('dragstart', (e) => { e.dataTransfer.setData('text/plain', String(j.id)); li.classList.add('dragging'); dragging = true; });
    li.addEventListener('dragend', () => { li.classList.remove('dragging'); dragging = false; });
    li.addEventListener('dragover', (e) => { e.preventDefault(); li.classList.add('drop'); });
    li.addEventListener('dragleave', () => li.classList.remove('drop'));
    li.addEventListener('drop', (e) => {
      e.preventDefault();
      li.classList.remove('drop');
      dragging = false;
      const moved = Number(e.dataTransfer.getData('text/plain'));
      if (moved && moved !== j.id) moveBefore(moved, j.id);
    });
  }
  return li;
}

function renderQueue(jobs) {
  const active = jobs.filter((j) => !WAITING.includes(j.state) && !FINAL.includes(j.state)).sort((a, b) => a.id - b.id);
  const waiting = jobs.filter((j) => WAITING.includes(j.state)).sort(queueOrder);
  const rows = active.map((j) => queueRow(j, null));
  waiting.forEach((j, i) => rows.push(queueRow(j, i > 0 ? waiting[i - 1] : null)));
  reconcile($('queue'), rows);
  $('queue-count').textContent = waiting.length + ' waiting, ' + active.length + ' on the cutters';
}

function historyRow(j) {
  const tr = el('tr', 'hjob');
  tr.dataset.id = j.id;
  tr.dataset.state = j.state;
  const outcome = j.state + (j.error && j.state !== 'done' ? ': ' + j.error.message : '');
  const span = j.started_at && j.finished_at ? j.finished_at - j.started_at : null;
  const cut = j.cut_mm !== undefined ? (j.cut_mm / 1000).toFixed(2) + ' m' : j.strokes_sent + '/' + j.strokes_total + ' strokes';
  for (const text of ['#' + j.id + ' ' + j.name, j.owner, j.cut_on || '', j.material || '', outcome, when(j.started_at), when(j.finished_at), seconds(span), cut]) tr.append(el('td', null, text));
  tr.children[4].className = 'outcome s-' + j.state;
  return tr;
}

// The history as the API filters it (?state, ?device, ?since): filters popcutd does not take are
// its 400 answer, shown as such.
async function refreshHistory() {
  const q = new URLSearchParams({ limit: $('filter-limit').value });
  if ($('filter-state').value) q.set('state', $('filter-state').value);
  if ($('filter-device').value) q.set('device', $('filter-device').value);
  if ($('filter-since').value) q.set('since', String(Math.floor(new Date($('filter-since').value + 'T00:00').getTime() / 1000)));
  lastHistory = Date.now();
  const mine = ++asked.history;
  try {
    const r = await api('GET', '/api/v1/jobs?' + q);
    if (mine !== asked.history) return;
    showError('history-error', null);
    $('history').tBodies[0].replaceChildren(...r.jobs.map(historyRow));
  } catch (e) {
    if (mine === asked.history) showError('history-error', 'History: ' + e.message);
  }
}

const SVG = 'http://www.w3.org/2000/svg';
function svg(tag, attrs, text) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

// Fills told apart by pattern as well as colour: done solid, failed hatched, cancelled dotted.
function patterns() {
  const defs = svg('defs', {});
  const hatch = svg('pattern', { id: 'p-failed', width: 8, height: 8, patternUnits: 'userSpaceOnUse', patternTransform: 'rotate(45)' });
  hatch.append(svg('rect', { width: 8, height: 8, fill: '#f3c9c9' }), svg('rect', { width: 4, height: 8, fill: '#b3261e' }));
  const dots = svg('pattern', { id: 'p-cancelled', width: 8, height: 8, patternUnits: 'userSpaceOnUse' });
  dots.append(svg('rect', { width: 8, height: 8, fill: '#e4e4e4' }), svg('circle', { cx: 4, cy: 4, r: 2, fill: '#666' }));
  defs.append(hatch, dots);
  return defs;
}
const FILL = { done: '#2d7d46', failed: 'url(#p-failed)', cancelled: 'url(#p-cancelled)' };

function drawDays(days) {
  const chart = $('chart-days');
  const W = 640, H = 240, left = 36, bottom = 28, top = 10;
  chart.setAttribute('viewBox', '0 0 ' + W + ' ' + H);
  const max = Math.max(1, ...days.map((d) => Math.max(d.jobs, d.done + d.failed + d.cancelled)));
  const step = (W - left - 8) / days.length, scale = (H - top - bottom) / max;
  const parts = [patterns()];
  for (const v of new Set([0, Math.ceil(max / 2), max])) {
    const y = H - bottom - v * scale;
    parts.push(svg('line', { x1: left, x2: W - 4, y1: y, y2: y, stroke: '#ccc' }), svg('text', { x: left - 6, y: y + 5, 'text-anchor': 'end', class: 'axis' }, String(v)));
  }
  const every = Math.ceil(days.length / 10);
  days.forEach((d, i) => {
    const x = left + i * step + step * 0.15, w = step * 0.7;
    const g = svg('g', { class: 'day', 'data-date': d.date, 'data-jobs': d.jobs, 'data-done': d.done, 'data-failed': d.failed, 'data-cancelled': d.cancelled });
    g.append(svg('title', {}, d.date + ': ' + d.jobs + ' submitted, ' + d.done + ' done, ' + d.failed + ' failed, ' + d.cancelled + ' cancelled'));
    let y = H - bottom;
    for (const k of ['done', 'failed', 'cancelled']) {
      if (!d[k]) continue;
      const h = d[k] * scale;
      y -= h;
      g.append(svg('rect', { x, y, width: w, height: h, fill: FILL[k], stroke: '#333', 'stroke-width': 0.5, class: 'bar-' + k }));
    }
    // Submitted: a black tick across the bar's slot, at its height.
    if (d.jobs) g.append(svg('line', { x1: x - 2, x2: x + w + 2, y1: H - bottom - d.jobs * scale, y2: H - bottom - d.jobs * scale, stroke: '#000', 'stroke-width': 3, class: 'submitted' }));
    // Every `every`-th date and the last, but not one that would crowd the last's.
    const last = days.length - 1;
    if ((i % every === 0 && last - i >= every) || i === last) g.append(svg('text', { x: x + w / 2, y: H - 8, 'text-anchor': 'middle', class: 'axis' }, d.date.slice(5)));
    parts.push(g);
  });
  chart.replaceChildren(...parts);
  const t = days.reduce((a, d) => ({ jobs: a.jobs + d.jobs, done: a.done + d.done, failed: a.failed + d.failed, cancelled: a.cancelled + d.cancelled }), { jobs: 0, done: 0, failed: 0, cancelled: 0 });
  $('days-legend').textContent = 'Jobs per day — ▬ submitted (' + t.jobs + '), ■ done (' + t.done + '), ▨ failed (' + t.failed + '), ⁘ cancelled (' + t.cancelled + ')';
}

function drawDevices(devices) {
  const chart = $('chart-devices');
  const W = 640, row = 44, H = Math.max(1, devices.length) * row + 8, left = 120, right = 320;
  chart.setAttribute('viewBox', '0 0 ' + W + ' ' + H);
  const max = Math.max(0.01, ...devices.map((d) => d.cutting_s / 3600));
  const parts = [];
  devices.forEach((d, i) => {
    const y = 4 + i * row, h = d.cutting_s / 3600;
    const rate = d.failure_rate === null ? 'no failures counted' : Math.round(d.failure_rate * 100) + '% failed';
    const g = svg('g', { class: 'device-bar', 'data-name': d.name, 'data-cutting-s': d.cutting_s, 'data-jobs': d.jobs, 'data-failure-rate': d.failure_rate === null ? '' : d.failure_rate });
    g.append(svg('text', { x: left - 8, y: y + row / 2 + 5, 'text-anchor': 'end', class: 'label' }, d.name));
    g.append(svg('rect', { x: left, y: y + 6, width: Math.max(2, (W - left - right) * h / max), height: row - 16, fill: '#3b4a5a' }));
    g.append(svg('text', { x: W - right + 8, y: y + row / 2 + 5, class: 'label' }, seconds(d.cutting_s) + ' cutting · ' + d.jobs + (d.jobs === 1 ? ' job · ' : ' jobs · ') + rate));
    parts.push(g);
  });
  chart.replaceChildren(...parts);
}

async function refreshStats() {
  lastStats = Date.now();
  const mine = ++asked.stats;
  try {
    const r = await api('GET', '/api/v1/stats?days=' + $('stats-days').value);
    if (mine !== asked.stats) return;
    showError('stats-error', null);
    drawDays(r.days);
    drawDevices(r.devices);
  } catch (e) {
    if (mine === asked.stats) showError('stats-error', 'Statistics: ' + e.message);
  }
}

// Every 2 s the cutters and the jobs they cut (one small request each); the whole list of jobs
// for the queue every 10 s and after each action: popcutd works out every waiting job's place in
// line for it, which takes it ~0.8 s with 1000 jobs waiting.
const LIST_MS = 10000;
let listed = [];     // the last list of jobs
let lastList = 0;
async function refresh(full) {
  clearTimeout(pollTimer);
  const mine = ++asked.state;
  try {
    const listNow = full === true || Date.now() - lastList > LIST_MS;
    if (listNow) lastList = Date.now();
    const [dev, list] = await Promise.all([api('GET', '/api/v1/devices'), listNow ? api('GET', '/api/v1/jobs?limit=1000') : null]);
    const cutting = await Promise.all(dev.devices.filter((d) => d.job).map((d) => api('GET', '/api/v1/jobs/' + d.job).catch(() => null)));
    if (mine !== asked.state) return;
    if (list) listed = list.jobs;
    const byId = {};
    for (const j of listed) byId[j.id] = j;
    for (const j of cutting) if (j) byId[j.id] = j;
    renderDevices(dev.devices, byId);
    if (!dragging) renderQueue(Object.values(byId));
  } catch (e) {
    if (mine !== asked.state) return;
    if (e.status === 401 || e.status === 403) return signOut('The token was refused: ' + e.message);
    notice('popcutd does not answer: ' + e.message, true);
  }
  if (Date.now() - lastHistory > 10000) refreshHistory();
  if (Date.now() - lastStats > 10000) refreshStats();
  clearTimeout(pollTimer);
  if (!document.hidden) pollTimer = setTimeout(refresh, POLL_MS);
}

function signOut(why) {
  clearTimeout(pollTimer);
  sessionStorage.removeItem(TOKEN_KEY);
  token = '';
  $('main').hidden = true;
  $('sign-out').hidden = true;
  $('login').hidden = false;
  showError('login-error', why || null);
}

// The statistics are admin-only: a token they answer for is an admin token.
async function signIn(candidate) {
  token = candidate;
  try {
    await api('GET', '/api/v1/stats?days=1');
  } catch (e) {
    return signOut(e.status === 403 ? 'That is not an admin token (' + e.message + ')' : e.message);
  }
  sessionStorage.setItem(TOKEN_KEY, token);
  $('login').hidden = true;
  $('main').hidden = false;
  $('sign-out').hidden = false;
  lastHistory = lastStats = 0;
  refresh(true);
}

$('login').addEventListener('submit', (e) => { e.preventDefault(); signIn($('admin-token').value.trim()); $('admin-token').value = ''; });
$('sign-out').addEventListener('click', () => signOut(null));
$('history-filter').addEventListener('submit', (e) => { e.preventDefault(); refreshHistory(); });
$('stats-days').addEventListener('change', refreshStats);
document.addEventListener('visibilitychange', () => { if (!document.hidden && token) refresh(true); });
setInterval(() => { $('clock').textContent = new Date().toLocaleTimeString([], { hour: '2-digit', minute: '2-digit' }); }, 1000);
if (token) signIn(token); else signOut(null);
