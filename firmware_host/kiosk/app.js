// popcut kiosk logic: talks to popcutd's /api/v1 with the kiosk token from ?token= (kept in localStorage).
'use strict';

const params = new URLSearchParams(location.search);
if (params.get('token')) localStorage.setItem('popcut-token', params.get('token'));
const token = localStorage.getItem('popcut-token') || '';
const $ = (id) => document.getElementById(id);
let model = null;        // the chosen model's JSON text
let mesh = null;         // an uploaded mesh file, imported by popcutd with the options shown
let drawing = null;      // an uploaded drawing (SVG, DXF, FOLD), read by popcutd as a card or a sheet
let foldedPicture = null;  // a sheet's folded picture (a data URL): sheets have no opening angle
let previewTimer = null;
let current = 0;         // bumped whenever the model changes: answers about an older one are dropped
const urls = {};         // object URLs in use, freed when replaced
const BLANK = "data:image/svg+xml,%3Csvg xmlns='http://www.w3.org/2000/svg'/%3E";

async function api(method, path, body, type, extra) {
  const headers = Object.assign({ Authorization: 'Bearer ' + token }, extra);
  // A FormData body sets its own multipart Content-Type.
  if (body !== undefined && !(body instanceof FormData)) headers['Content-Type'] = 'application/json';
  const res = await fetch(path, { method, headers, body: body === undefined ? (method === 'POST' ? '' : undefined) : body });
  if (!res.ok) {
    let message = res.status + ' ' + res.statusText;
    try { const e = (await res.json()).error; message = e.message + ' (' + e.code + ')'; } catch (_) { /* not JSON */ }
    throw new Error(message);
  }
  return type === 'blob' ? res.blob() : res.json();
}

// A random (version 4) UUID; crypto.randomUUID is only there on https or localhost, a kiosk on
// the shop's network may be neither.
function newKey() {
  const b = crypto.getRandomValues(new Uint8Array(16));
  b[6] = (b[6] & 0x0f) | 0x40;
  b[8] = (b[8] & 0x3f) | 0x80;
  const h = Array.from(b, (x) => x.toString(16).padStart(2, '0')).join('');
  return [h.slice(0, 8), h.slice(8, 12), h.slice(12, 16), h.slice(16, 20), h.slice(20)].join('-');
}

function showImage(id, blob) {
  if (urls[id]) URL.revokeObjectURL(urls[id]);
  urls[id] = URL.createObjectURL(blob);
  $(id).src = urls[id];
}

// A job name as popcutd takes it (any text, 1-64 characters): control characters and direction
// overrides dropped, spaces trimmed; counted in characters, not UTF-16 halves.
function jobLabel(text) {
  const clean = text.replace(/[\u0000-\u001f\u007f-\u009f\u200e\u200f\u2028\u2029\u202a-\u202e\u2066-\u2069]/g, '').trim();
  return Array.from(clean).slice(0, 64).join('').trim();
}

function showError(id, err) {
  $(id).hidden = !err;
  $(id).textContent = err ? String(err.message || err) : '';
}

// Forgets the shown model (its pictures, label and job name) so that nothing of it can be taken
// for the next one, or queued in its place; `text` says what happens instead. Returns the new
// model's number: an answer that comes back under an older number is about a model gone.
function clearModel(text) {
  current += 1;
  model = null;
  $('queue').disabled = true;
  for (const id of ['pattern', 'preview']) {
    if (urls[id]) URL.revokeObjectURL(urls[id]);
    delete urls[id];
    $(id).src = BLANK;
  }
  foldedPicture = null;
  showSheetPreview(false);
  $('model-name').textContent = text;
  $('name').value = '';
  showError('model-error', null);
  showError('model-warning', null);
  return current;
}

// A model that could not be used: nothing of the one before stays on the page, and why shows.
function failModel(label, err) {
  clearModel('No model: ' + label + ' could not be used.');
  showError('model-error', err);
}

// `picture`: a sheet's folded picture, shown instead of a preview at the slider's angle.
async function useModel(text, label, shown, picture) {
  const mine = clearModel('Loading ' + label + ' ...');
  foldedPicture = picture || null;
  showSheetPreview(!!picture);
  try {
    JSON.parse(text);
  } catch (e) {
    failModel(label, 'not a JSON model: ' + e.message);
    return false;
  }
  try {
    const pattern = await api('POST', '/api/v1/render/pattern.svg', text, 'blob');
    if (mine !== current) return false;
    showImage('pattern', pattern);
    model = text;
    $('model-name').textContent = shown || label;
    $('name').value = jobLabel(label) || 'my card';
    await renderPreview();
    if (mine !== current) return false;
    $('queue').disabled = !$('device').value;
    return true;
  } catch (e) {
    if (mine === current) failModel(label, e);
    return false;
  }
}

// A card's preview opens to the slider's angle; a sheet's shows it folded as drawn.
function showSheetPreview(on) {
  $('angle').hidden = on;
  $('opened').hidden = on;
  $('folded').hidden = !on;
}

async function renderPreview() {
  if (!model) return;
  if (foldedPicture) {
    $('preview').src = foldedPicture;
    return;
  }
  const mine = current;
  const angle = $('angle').value;
  $('angle-value').textContent = angle;
  try {
    const png = await api('POST', '/api/v1/render/preview.png?angle=' + angle, model, 'blob');
    if (mine === current) showImage('preview', png);
  } catch (e) {
    // 503 busy: every render slot is taken; the picture stays and the next move asks again.
    if (mine === current && !/\(busy\)$/.test(e.message)) showError('model-error', e);
  }
}

const mm = (v) => String(Math.round(v));

// An upload's answer, or null when popcutd refused it (the model is then cleared and why shows)
// or another model was chosen meanwhile.
async function postUpload(path, form, file, mine) {
  let r;
  try {
    r = await api('POST', path, form);
  } catch (e) {
    if (mine === current) failModel(file.name, e);
    return null;
  }
  return mine === current ? r : null;
}

// The mesh goes to popcutd's importer (popcut import's code and options); its model comes back.
async function importMesh() {
  if (!mesh) return;
  const file = mesh;
  const mine = clearModel('Importing ' + file.name + ' ...');
  const form = new FormData();
  form.append('mesh', file, file.name);
  form.append('name', jobLabel(file.name.replace(/\.[^.]*$/, '')) || 'mesh');
  for (const id of ['resolution', 'up', 'front', 'thin-tops']) form.append(id, $(id).value);
  // Sizes only when asked for: empty, the importer's default (120 mm across).
  for (const id of ['height-mm', 'fit-mm']) if ($(id).value.trim()) form.append(id, $(id).value.trim());
  form.append('faces', $('faces').checked ? 'true' : 'false');
  const r = await postUpload('/api/v1/import', form, file, mine);
  if (!r) return;
  const made = file.name + ': ' + r.grid.width + ' x ' + r.grid.depth + ' x ' + r.grid.height + ' voxels, sheet ' +
               mm(r.sheet_mm.width) + ' x ' + mm(r.sheet_mm.height) + ' mm';
  // Named like the API names it: house.
  if (await useModel(JSON.stringify(r.model), file.name.replace(/\.[^.]*$/, ''), made)) showError('model-warning', r.warnings.join('; '));
}

// A drawing goes to popcutd's reader (popcut import-pattern's code): the card it folds into, or
// the sheet's own lines and a picture of it folded, come back; a drawing that folds into no card
// comes back with the conflicting faces and folds named.
async function importDrawing() {
  if (!drawing) return;
  const file = drawing;
  const as = $('read-as').value;
  const mine = clearModel('Reading ' + file.name + ' ...');
  const form = new FormData();
  form.append('drawing', file, file.name);
  form.append('as', as);
  form.append('name', jobLabel(file.name.replace(/\.[^.]*$/, '')) || 'drawing');
  form.append('red-is-cut', $('red-is-cut').checked ? 'true' : 'false');
  if (as === 'sheet' && $('fold').value.trim()) form.append('fold', $('fold').value.trim());
  const r = await postUpload('/api/v1/import/drawing', form, file, mine);
  if (!r) return;
  const size = 'sheet ' + mm(r.sheet_mm.width) + ' x ' + mm(r.sheet_mm.height) + ' mm';
  const made = as === 'card' ? file.name + ': a pop-up card of ' + r.faces + ' faces, ' + size
                             : file.name + ': a sheet of ' + r.regions + ' panels and ' + r.hinges + ' folds, ' + size;
  const text = JSON.stringify(r.model);
  if (!(await useModel(text, file.name.replace(/\.[^.]*$/, ''), made, as === 'sheet' ? r.folded_png : null))) return;
  const warnings = r.warnings.concat(r.problems ? r.problems.map((p) => p.what) : []);
  showError('model-warning', warnings.join('; '));
}

async function loadChoices() {
  const ex = await api('GET', '/api/v1/examples');
  for (const id of ex.examples) {
    const o = document.createElement('option');
    o.value = id;
    o.textContent = (ex.names && ex.names[id]) || id;  // the model's own name
    $('example').appendChild(o);
  }
  const dev = await api('GET', '/api/v1/devices');
  for (const d of dev.devices) {
    const o = document.createElement('option');
    o.value = d.name;
    o.textContent = d.name + ' (' + d.model + ')' + (d.paused ? ' — paused' : '');
    $('device').appendChild(o);
    const f = document.createElement('option');
    f.value = d.name;  // fit-mm takes a cutter's name: the card as large as its media allow
    $('fit-choices').appendChild(f);
  }
  // The stock decides force, speed and passes; without a choice the cutter's profile does.
  const mat = await api('GET', '/api/v1/materials');
  for (const m of mat.materials) {
    const o = document.createElement('option');
    o.value = m.name;
    o.textContent = m.description;
    $('material').appendChild(o);
  }
}

// awaiting: the devices waiting for a fresh sheet after one of this user's jobs, by that job's id.
function jobItem(j, awaiting) {
  let li = document.querySelector('#jobs [data-id="' + j.id + '"]');
  if (!li) {
    li = document.createElement('li');
    li.className = 'job';
    li.dataset.id = j.id;
    li.innerHTML = '<span class="title"></span><button class="pause" hidden>Pause</button>' +
                   '<button class="continue" hidden>Continue</button><button class="cancel">Cancel</button>' +
                   '<button class="sheet" hidden>Sheet loaded</button>' +
                   '<span class="state"></span><span class="where"></span><progress max="1" value="0"></progress>';
    // Pause holds the half-cut card on the cutter to go on with it; cancel gives the job up.
    for (const action of ['pause', 'continue', 'cancel']) {
      li.querySelector('.' + action).addEventListener('click', async () => {
        try { await api('POST', '/api/v1/jobs/' + j.id + '/' + action); } catch (e) { alert(e.message); }
        refreshJobs();
      });
    }
    // The cutter waits for a fresh sheet after this job: its owner says one is loaded.
    li.querySelector('.sheet').addEventListener('click', async () => {
      try { await api('POST', '/api/v1/devices/' + encodeURIComponent(li.dataset.cutOn) + '/sheet'); }
      catch (e) { alert(e.message); }
      refreshJobs();
    });
    $('jobs').prepend(li);
  }
  li.dataset.cutOn = j.cut_on || '';
  li.querySelector('.title').textContent = '#' + j.id + ' ' + j.name;
  li.querySelector('.state').textContent = j.state;
  li.dataset.state = j.state;
  let where = j.cut_on ? 'on ' + j.cut_on : (j.device ? 'for ' + j.device : 'any ' + j.profile);
  if (j.material) where += ' · ' + j.material;
  if (j.place_in_line !== null) where += ' · ' + (j.place_in_line === 0 ? 'next' : j.place_in_line + ' ahead');
  if (j.eta_s !== null) where += ' · about ' + Math.ceil(j.eta_s) + ' s';
  if (j.state === 'cutting' || j.state === 'done') where += ' · ' + j.strokes_sent + '/' + j.strokes_total + ' strokes';
  if (j.sheets > 1) where += ' · sheet ' + j.sheet + ' of ' + j.sheets;
  if (j.error) where += ' · ' + j.error.message;
  li.querySelector('.where').textContent = where;
  li.querySelector('progress').value = j.progress;
  li.querySelector('.cancel').hidden = ['done', 'failed', 'cancelled'].includes(j.state);
  li.querySelector('.pause').hidden = !['ready', 'cutting'].includes(j.state) || j.pause_requested === true;
  li.querySelector('.continue').hidden = j.state !== 'paused';
  li.querySelector('.sheet').hidden = !(awaiting && awaiting.get(j.id) === j.cut_on);
}

async function refreshJobs() {
  try {
    const [r, dev] = await Promise.all([api('GET', '/api/v1/jobs?limit=20'), api('GET', '/api/v1/devices')]);
    const awaiting = new Map();
    for (const d of dev.devices) if (d.sheet === 'awaiting_sheet' && d.sheet_job !== null) awaiting.set(d.sheet_job, d.name);
    for (const j of r.jobs.slice().reverse()) jobItem(j, awaiting);
  } catch (e) { /* the next poll tries again */ }
}

$('example').addEventListener('change', async () => {
  const id = $('example').value;
  if (!id) return;
  const label = $('example').selectedOptions[0].textContent;
  $('upload').value = '';
  $('import').hidden = true;
  $('drawing').hidden = true;
  mesh = null;
  drawing = null;
  const mine = clearModel('Loading ' + label + ' ...');
  let text;
  try {
    text = JSON.stringify(await api('GET', '/api/v1/examples/' + encodeURIComponent(id)));
  } catch (e) {
    if (mine === current) failModel(label, e);
    return;
  }
  if (mine === current) useModel(text, label);
});
$('upload').addEventListener('change', async () => {
  const f = $('upload').files[0];
  if (!f) return;
  $('example').value = '';
  const isMesh = /\.(obj|stl|off|ply)$/i.test(f.name);
  const isDrawing = /\.(svg|dxf|fold)$/i.test(f.name);
  $('import').hidden = !isMesh;
  $('drawing').hidden = !isDrawing;
  mesh = isMesh ? f : null;
  drawing = isDrawing ? f : null;
  $('fold').value = '';  // another drawing's line names would name nothing in this one
  if (isMesh) importMesh();
  else if (isDrawing) importDrawing();
  else useModel(await f.text(), f.name.replace(/\.json$/i, ''));
});
$('reimport').addEventListener('click', (e) => { e.preventDefault(); importMesh(); });
$('reread').addEventListener('click', (e) => { e.preventDefault(); importDrawing(); });
// Crease angles fold a sheet; a card folds at its own angles.
$('read-as').addEventListener('change', () => {
  $('fold-label').hidden = $('read-as').value !== 'sheet';
  importDrawing();
});
$('angle').addEventListener('input', () => {
  $('angle-value').textContent = $('angle').value;
  clearTimeout(previewTimer);
  previewTimer = setTimeout(renderPreview, 150);  // while the slider moves, one picture at a time
});
$('queue').addEventListener('click', async () => {
  showError('queue-error', null);
  $('queue').disabled = true;
  try {
    const job = { device: $('device').value, name: $('name').value, model: JSON.parse(model) };
    if ($('material').value) job.material = $('material').value;
    const body = JSON.stringify(job);
    // One key per press: the retry after a dropped connection (the job may have been queued)
    // finds the first job instead of queuing a second card.
    const key = { 'Idempotency-Key': newKey() };
    let answer;
    try {
      answer = await api('POST', '/api/v1/jobs', body, 'json', key);
    } catch (e) {
      if (!(e instanceof TypeError)) throw e;  // fetch's network failure; an answer is an Error
      await new Promise((r) => setTimeout(r, 1000));
      answer = await api('POST', '/api/v1/jobs', body, 'json', key);
    }
    jobItem(answer);
  } catch (e) {
    showError('queue-error', e);
  }
  $('queue').disabled = !model;
});

$('who').textContent = token ? '' : 'no token: open this page with ?token=...';
loadChoices().catch((e) => showError('model-error', e));
// Jobs every 2 s while the page is shown, none while it is hidden: a classroom of tablets polling
// faster would only keep the daemon's connection threads busy.
const POLL_MS = 2000;
let pollTimer = null;
function schedulePoll() {
  clearTimeout(pollTimer);
  if (!document.hidden) pollTimer = setTimeout(async () => { await refreshJobs(); schedulePoll(); }, POLL_MS);
}
document.addEventListener('visibilitychange', () => {
  if (!document.hidden) refreshJobs();
  schedulePoll();
});
refreshJobs();
schedulePoll();
