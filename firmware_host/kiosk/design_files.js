// popcut designer's drafts and files: new card, the token's drafts, open/save popcut.design.v1, SVG/DXF export, the
// card's name (a webOAcard card's from its file), sending it to a cutter and following the job, and the open-and-close animation.
'use strict';

window.DesignerFiles = (() => {
  const $ = (id) => document.getElementById(id);
  let ctx = null;
  let playing = null;
  let angleBefore = 60;  // where the animation puts the card back

  function emptyDesign(width, back, floor) {
    return JSON.stringify({ format: 'popcut.design.v1', sheet: { width, back, floor }, items: [] });
  }

  async function listDrafts() {
    const { designs } = await ctx.api('GET', '/api/v1/designs');
    const select = $('drafts');
    select.length = 1;
    for (const d of designs) {
      const when = new Date(d.updated_at * 1000).toLocaleString();
      select.add(new Option(`${d.name || 'untitled'} (#${d.id}, ${d.items} ${d.items === 1 ? 'item' : 'items'}, ${when})`, String(d.id)));
    }
  }

  // The draft `id` if this token has it, else a new card of the size the New card fields say.
  async function open(id) {
    let answer = null;
    if (id) {
      try { answer = await ctx.api('GET', `/api/v1/designs/${Number(id)}`); } catch (_) { /* gone: start anew */ }
    }
    if (!answer) answer = await create(emptyDesign(num('sheet-width'), num('sheet-back'), num('sheet-floor')));
    if (answer) loaded(answer);
  }

  async function create(text) {
    try {
      return await ctx.api('POST', '/api/v1/designs', text);
    } catch (e) {
      ctx.say('edit-error', e.message);
      return null;
    }
  }

  function loaded(answer) {
    ctx.show(answer);
    const wall = answer.design.items.find((it) => it.tool === 'wall');
    ctx.setPlane(wall ? wall.t : Math.round(answer.design.sheet.floor * 0.4 / 5) * 5);  // on the default grid
    listDrafts().catch(() => {});
  }

  const num = (id) => Number($(id).value);

  async function download(path, filename) {
    const res = await fetch(path, { headers: { Authorization: 'Bearer ' + localStorage.getItem('popcut-token') } });
    if (!res.ok) { ctx.say('edit-error', 'could not download ' + filename + ': ' + res.status); return; }
    const a = document.createElement('a');
    a.href = URL.createObjectURL(await res.blob());
    a.download = filename;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }

  function fileName(ext) {
    const d = ctx.current();
    const stem = (d.design.name || 'card-' + d.id).replace(/[^\p{L}\p{N}_-]+/gu, '-').replace(/^-+|-+$/g, '') || 'card';
    return stem + '.' + ext;
  }

  async function rename() {
    const d = ctx.current(), name = $('name').value.trim();
    if (!d) return;
    if (!name) { $('name').value = d.design.name || ''; return; }  // a draft keeps a name once it has one
    if (name === (d.design.name || '')) return;
    try {
      ctx.show(await ctx.api('PATCH', `/api/v1/designs/${d.id}`, JSON.stringify({ name })));
      listDrafts().catch(() => {});
    } catch (e) { ctx.say('edit-error', e.message); }
  }

  async function devices() {
    try {
      const { devices } = await ctx.api('GET', '/api/v1/devices');
      for (const dev of devices) $('device').add(new Option(dev.name, dev.name));
    } catch (_) { /* no devices: sending stays off */ }
    $('send').disabled = $('device').length === 0;
  }

  async function send() {
    const d = ctx.current();
    if (!d.check.pops_up && !confirm('This card does not pop up (see the check under the pattern). Cut it anyway?')) return;
    $('send').disabled = true;
    try {
      const job = await ctx.api('POST', `/api/v1/designs/${d.id}/submit`, JSON.stringify({ device: $('device').value }));
      follow(job.id);
    } catch (e) {
      $('job').textContent = 'Not sent: ' + e.message;
    } finally {
      $('send').disabled = false;
    }
  }

  // The job's state until it ends, as the kiosk shows it.
  async function follow(id) {
    for (;;) {
      let job;
      try { job = await ctx.api('GET', `/api/v1/jobs/${id}`); } catch (e) { $('job').textContent = e.message; return; }
      const where = job.cut_on || job.device || 'the first free cutter';
      const line = job.state === 'ready' && job.place_in_line === 0 ? ' (next: is a fresh sheet loaded and confirmed?)' : '';
      $('job').textContent = `Job ${id} on ${where}: ${job.state}${line}`;
      $('job').dataset.state = job.state;
      if (['done', 'failed', 'cancelled', 'interrupted'].includes(job.state)) return;
      await new Promise((r) => setTimeout(r, 1000));
    }
  }

  // Opens and closes the card once (0° to 180° and back in four seconds), or stops.
  function play() {
    const setAngle = (deg) => {
      $('angle').value = String(deg);
      $('angle').dispatchEvent(new Event('input'));
    };
    const stop = () => {
      cancelAnimationFrame(playing);
      playing = null;
      $('play').textContent = '▶';
      setAngle(angleBefore);
    };
    if (playing) return stop();
    angleBefore = Number($('angle').value);
    const t0 = performance.now();
    $('play').textContent = '⏸';
    const step = (now) => {
      const f = Math.min(1, (now - t0) / 4000);
      setAngle(Math.round(180 * (f < 0.5 ? f * 2 : 2 - f * 2)));
      if (f < 1) playing = requestAnimationFrame(step);
      else stop();
    };
    playing = requestAnimationFrame(step);
  }

  function wire(context) {
    ctx = context;
    $('new').addEventListener('click', async () => {
      const answer = await create(emptyDesign(num('sheet-width'), num('sheet-back'), num('sheet-floor')));
      if (answer) { $('new-card').open = false; loaded(answer); }
    });
    $('drafts').addEventListener('change', () => { if ($('drafts').value) open($('drafts').value); });
    $('open').addEventListener('change', async () => {
      const file = $('open').files[0];
      if (!file) return;
      let answer = await create(await file.text());
      // A webOAcard card has no name of its own: the draft takes its file's.
      if (answer && !answer.design.name && /\.oa$/i.test(file.name)) {
        const name = file.name.replace(/\.oa$/i, '').slice(0, 64);
        try { answer = await ctx.api('PATCH', `/api/v1/designs/${answer.id}`, JSON.stringify({ name })); } catch (_) { /* keeps no name */ }
      }
      if (answer) loaded(answer);
      $('open').value = '';
    });
    $('save').addEventListener('click', () => download(`/api/v1/designs/${ctx.current().id}/design.json`, fileName('json')));
    for (const kind of ['svg', 'dxf', 'pdf']) {
      $('export-' + kind).addEventListener('click', () => download(`/api/v1/designs/${ctx.current().id}/pattern.${kind}`, fileName(kind)));
    }
    $('name').addEventListener('change', rename);
    $('send').addEventListener('click', send);
    $('play').addEventListener('click', play);
    devices();
  }

  return { wire, open };
})();
