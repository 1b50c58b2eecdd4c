// popcut kiosk logic: talks to popcutd's /api/v1 with the kiosk token from ?token= (kept in localStorage).
'use strict';

const params = new URLSearchParams(location.search);
if (params.get('token')) localStorage.setItem('popcut-token', params.get('token'));
const token = localStorage.getItem('popcut-token') || '';
const $ = (id) => document.getElementById(id);
let model = null;        // the chosen model's JSON text
let mesh = null;         // an uploaded mesh file, imported by popcutd with the options shown
let previewTimer = null;
const urls = {};         // object URLs in use, freed when replaced

async function api(method, path, body, type) {
  const headers = { Authorization: 'Bearer ' + token };
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

async function useModel(text, label) {
  showError('model-error', null);
  model = null;
  $('queue').disabled = true;
  try {
    JSON.parse(text);
  } catch (e) {
    showError('model-error', 'not a JSON model: ' + e.message);
    return;
  }
  try {
    showImage('pattern', await api('POST', '/api/v1/render/pattern.svg', text, 'blob'));
    model = text;
    $('model-name').textContent = label;
    $('name').value = jobLabel(label) || 'my card';
    await renderPreview();
    $('queue').disabled = !$('device').value;
  } catch (e) {
    showError('model-error', e);
  }
}

async function renderPreview() {
  if (!model) return;
  const angle = $('angle').value;
  $('angle-value').textContent = angle;
  try {
    showImage('preview', await api('POST', '/api/v1/render/preview.png?angle=' + angle, model, 'blob'));
  } catch (e) {
    // 503 busy: every render slot is taken; the picture stays and the next move asks again.
    if (!/\(busy\)$/.test(e.message)) showError('model-error', e);
  }
}

// The mesh goes to popcutd's importer (popcut import's code and options); its model comes back.
async function importMesh() {
  if (!mesh) return;
  showError('model-error', null);
  model = null;
  $('queue').disabled = true;
  $('model-name').textContent = 'Importing ' + mesh.name + ' ...';
  const form = new FormData();
  form.append('mesh', mesh, mesh.name);
  form.append('name', jobLabel(mesh.name.replace(/\.[^.]*$/, '')) || 'mesh');
  for (const id of ['resolution', 'up', 'front', 'thin-tops']) form.append(id, $(id).value);
  form.append('faces', $('faces').checked ? 'true' : 'false');
  try {
    const r = await api('POST', '/api/v1/import', form);
    await useModel(JSON.stringify(r.model), mesh.name.replace(/\.[^.]*$/, ''));  // named like the API names it: house
    $('model-name').textContent = mesh.name + ': ' + r.grid.width + ' x ' + r.grid.depth + ' x ' + r.grid.height + ' voxels';
  } catch (e) {
    $('model-name').textContent = mesh.name;
    showError('model-error', e);
  }
}

async function loadChoices() {
  const ex = await api('GET', '/api/v1/examples');
  for (const name of ex.examples) {
    const o = document.createElement('option');
    o.value = o.textContent = name;
    $('example').appendChild(o);
  }
  const dev = await api('GET', '/api/v1/devices');
  for (const d of dev.devices) {
    const o = document.createElement('option');
    o.value = d.name;
    o.textContent = d.name + ' (' + d.model + ')' + (d.paused ? ' — paused' : '');
    $('device').appendChild(o);
  }
}

function jobItem(j) {
  let li = document.querySelector('#jobs [data-id="' + j.id + '"]');
  if (!li) {
    li = document.createElement('li');
    li.className = 'job';
    li.dataset.id = j.id;
    li.innerHTML = '<span class="title"></span><button class="cancel">Cancel</button>' +
                   '<span class="state"></span><span class="where"></span><progress max="1" value="0"></progress>';
    li.querySelector('.cancel').addEventListener('click', async () => {
      try { await api('POST', '/api/v1/jobs/' + j.id + '/cancel'); } catch (e) { alert(e.message); }
      refreshJobs();
    });
    $('jobs').prepend(li);
  }
  li.querySelector('.title').textContent = '#' + j.id + ' ' + j.name;
  li.querySelector('.state').textContent = j.state;
  li.dataset.state = j.state;
  let where = j.cut_on ? 'on ' + j.cut_on : (j.device ? 'for ' + j.device : 'any ' + j.profile);
  if (j.place_in_line !== null) where += ' · ' + (j.place_in_line === 0 ? 'next' : j.place_in_line + ' ahead');
  if (j.eta_s !== null) where += ' · about ' + Math.ceil(j.eta_s) + ' s';
  if (j.state === 'cutting' || j.state === 'done') where += ' · ' + j.strokes_sent + '/' + j.strokes_total + ' strokes';
  if (j.error) where += ' · ' + j.error.message;
  li.querySelector('.where').textContent = where;
  li.querySelector('progress').value = j.progress;
  li.querySelector('.cancel').hidden = ['done', 'failed', 'cancelled'].includes(j.state);
}

async function refreshJobs() {
  try {
    const r = await api('GET', '/api/v1/jobs?limit=20');
    for (const j of r.jobs.slice().reverse()) jobItem(j);
  } catch (e) { /* the next poll tries again */ }
}

$('example').addEventListener('change', async () => {
  const name = $('example').value;
  if (!name) return;
  $('upload').value = '';
  $('import').hidden = true;
  mesh = null;
  try {
    useModel(JSON.stringify(await api('GET', '/api/v1/examples/' + encodeURIComponent(name))), name);
  } catch (e) { showError('model-error', e); }
});
$('upload').addEventListener('change', async () => {
  const f = $('upload').files[0];
  if (!f) return;
  $('example').value = '';
  const isMesh = /\.(obj|stl|off|ply)$/i.test(f.name);
  $('import').hidden = !isMesh;
  mesh = isMesh ? f : null;
  if (isMesh) importMesh();
  else useModel(await f.text(), f.name.replace(/\.json$/i, ''));
});
$('reimport').addEventListener('click', (e) => { e.preventDefault(); importMesh(); });
$('angle').addEventListener('input', () => {
  $('angle-value').textContent = $('angle').value;
  clearTimeout(previewTimer);
  previewTimer = setTimeout(renderPreview, 150);  // while the slider moves, one picture at a time
});
$('queue').addEventListener('click', async () => {
  showError('queue-error', null);
  $('queue').disabled = true;
  try {
    const body = JSON.stringify({ device: $('device').value, name: $('name').value, model: JSON.parse(model) });
    jobItem(await api('POST', '/api/v1/jobs', body));
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
