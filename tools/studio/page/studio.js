// The studio's page: controls that restart the panes' renders, frames polled as they land, the
// error chart, the series, and radiometry at a clicked pixel. No library, no build step: the page
// talks only to the studio that served it (tools/studio/server.cpp lists the API).
'use strict';

const $ = (id) => document.getElementById(id);
// The page's state, also read by the browser test (tests/studio/studio_test.mjs).
const studio = { config: null, status: null, panes: [], frames: [], probe: null, starts: 0 };
window.studio = studio;

const COLORS = ['#d0602a', '#2a6fd0'];
const DEFAULTS = { scene: 'scenes/cornell_spheres', lessons: ['02_whitted', '04_rendering_equation'] };

function showMessage(text) {
  const m = $('message');
  m.textContent = text || '';
  m.hidden = !text;
}

async function api(path, options) {
  const response = await fetch(path, options);
  if (!response.ok) {
    let message = response.statusText;
    try { message = (await response.json()).error; } catch (e) { /* not JSON */ }
    throw new Error(message);
  }
  return response;
}

function lessonInfo(name) {
  return studio.config.lessons.find((l) => l.name === name);
}

// ---- the controls ----

function buildOptions(i) {
  const pane = studio.panes[i];
  const info = lessonInfo(pane.lesson.value);
  pane.options.replaceChildren();
  pane.inputs = {};
  for (const opt of info.options) {
    const label = document.createElement('label');
    label.title = opt.description;
    let input;
    if (opt.is_flag) {
      input = document.createElement('input');
      input.type = 'checkbox';
    } else if (opt.choices.length) {
      input = document.createElement('select');
      for (const c of opt.choices) input.add(new Option(c, c, false, c === opt.default));
    } else {
      input = document.createElement('input');
      input.type = 'text';
      input.size = 5;
      input.placeholder = opt.default;
    }
    input.dataset.flag = opt.flag;
    input.addEventListener('change', () => restart(i));
    label.append(opt.flag.replace(/^--/, '') + ' ', input);
    pane.options.append(label);
    pane.inputs[opt.flag] = input;
  }
}

function paramsOf(i) {
  const pane = studio.panes[i];
  const p = {
    pane: String(i), scene: $('scene').value, lesson: pane.lesson.value,
    '--width': $('width').value, '--height': $('height').value, '--seed': $('seed').value,
    '--spp': $('spp').value,
  };
  if ($('sampler').value !== 'kronecker') p['--sampler'] = $('sampler').value;
  if ($('albedo-on').checked) p['--albedo'] = $('albedo').value;
  for (const [flag, input] of Object.entries(pane.inputs)) {
    if (input.type === 'checkbox') { if (input.checked) p[flag] = '1'; }
    else if (input.value !== '' && input.value !== lessonInfo(pane.lesson.value).options.find((o) => o.flag === flag).default) p[flag] = input.value;
  }
  return p;
}

// Shows a render's parameters in the controls (a reloaded page keeps the class's demo).
function applyParams(i, params) {
  const pane = studio.panes[i];
  if (i === 0) {
    $('scene').value = params.scene;
    for (const key of ['width', 'height', 'seed', 'spp']) if (params['--' + key]) $(key).value = params['--' + key];
    $('sampler').value = params['--sampler'] || 'kronecker';
    $('albedo-on').checked = params['--albedo'] !== undefined;
    if (params['--albedo'] !== undefined) $('albedo').value = params['--albedo'];
  }
  pane.lesson.value = params.lesson;
  buildOptions(i);
  for (const [flag, input] of Object.entries(pane.inputs)) {
    if (input.type === 'checkbox') input.checked = params[flag] === '1';
    else if (params[flag] !== undefined) input.value = params[flag];
  }
}

const timers = [];
function restart(i) {
  clearTimeout(timers[i]);
  timers[i] = setTimeout(() => startPane(i), 150);
}
function restartAll() { studio.panes.forEach((_, i) => restart(i)); }

// One start in flight per pane: a change made while one loads is sent when it returns, with the
// controls as they are then, so the pane ends on the last choice made (the server also drops a
// start that finishes loading after a later one).
async function startPane(i) {
  const pane = studio.panes[i];
  if (pane.starting) { pane.again = true; return; }
  pane.starting = true;
  try {
    do {
      pane.again = false;
      try {
        const query = new URLSearchParams(paramsOf(i));
        await api('/api/start?' + query.toString(), { method: 'POST', body: '', headers: { 'X-Studio': '1' } });
        studio.starts += 1;
        showMessage('');
      } catch (e) {
        showMessage('Pane ' + (i + 1) + ': ' + e.message);
      }
    } while (pane.again);
  } finally {
    pane.starting = false;
  }
}

// ---- what the server renders ----

function frameUrl(i, s) {
  const pane = studio.panes[i];
  return '/api/frame?' + new URLSearchParams({
    pane: i, view: pane.view.value, exposure: $('exposure').value, v: s.version,
  });
}

function updateViews(pane, s) {
  const wanted = ['image'];
  if (s.reference) wanted.push('error');
  for (let k = 0; k < (s.layers || []).length; ++k) wanted.push('layer:' + k, 'sum:' + k);
  const have = [...pane.view.options].map((o) => o.value);
  if (have.join() === wanted.join()) return;
  const current = pane.view.value;
  pane.view.replaceChildren();
  for (const v of wanted) {
    let text = v;
    if (v === 'error') text = 'error against the reference';
    else if (v.startsWith('layer:')) text = s.layers[+v.slice(6)].name;
    else if (v.startsWith('sum:')) text = 'sum up to ' + s.layers[+v.slice(4)].name;
    pane.view.add(new Option(text, v));
  }
  pane.view.value = wanted.includes(current) ? current : 'image';
}

function fmt(x, digits = 3) {
  return x === null || x === undefined ? '-' : Number(x).toPrecision(digits);
}

function updatePane(i, s) {
  const pane = studio.panes[i];
  if (!s || s.state === 'idle') { pane.status.textContent = 'idle'; return; }
  if (s.state === 'error') showMessage(`Pane ${i + 1}: the render failed: ${s.error}`);
  updateViews(pane, s);
  pane.status.textContent =
    `${s.state} · passes ${s.passes} · ${s.spp} / ${s.target_spp} spp · ` +
    `${fmt(s.mrays_per_second)} Mrays/s · render ${fmt(s.seconds)} s · elapsed ${fmt(s.wall_seconds)} s` +
    (s.nan_samples + s.inf_samples > 0 ? ` · ${s.nan_samples} NaN, ${s.inf_samples} inf samples left out` : '');
  pane.command.textContent = s.command;
  const items = (s.notes || []).map((n) => ['note', n]).concat((s.bias || []).map((b) => ['bias', 'biased: ' + b]));
  const text = items.map((x) => x[1]).join('\n');
  if (pane.notes.dataset.text !== text) {
    pane.notes.dataset.text = text;
    pane.notes.replaceChildren(...items.map(([cls, t]) => {
      const li = document.createElement('li');
      li.className = cls;
      li.textContent = t;
      return li;
    }));
  }
  const key = `${s.version}|${pane.view.value}|${$('exposure').value}`;
  if (s.version > 0 && pane.shown !== key && !pane.loading) {
    pane.shown = key;
    pane.loading = true;
    const img = new Image();
    img.onload = () => {
      pane.img.src = img.src;
      pane.img.dataset.generation = s.generation;
      pane.img.dataset.spp = s.spp;
      pane.img.dataset.version = s.version;
      studio.frames[i].push({ generation: s.generation, spp: s.spp, version: s.version });
      if (studio.frames[i].length > 200) studio.frames[i].shift();
      pane.loading = false;
    };
    img.onerror = () => { pane.loading = false; pane.shown = null; };
    img.src = frameUrl(i, s);
  }
  pane.exr.href = `/api/download?pane=${i}&format=exr`;
  pane.png.href = `/api/download?pane=${i}&format=png&exposure=${$('exposure').value}`;
}

function drawChart(status) {
  const canvas = $('chart');
  const ctx = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height, L = 70, B = 40, T = 10, R = 230;
  ctx.clearRect(0, 0, W, H);
  const series = status.panes.map((p) => (p && p.chart) || []);
  const points = series.flat().filter((q) => q[1] > 0 && q[2] > 0);
  ctx.font = '12px sans-serif';
  ctx.fillStyle = '#555';
  if (!points.length) {
    ctx.fillText('no error yet: waiting for a reference of this scene and size', L, H / 2);
    return;
  }
  const lx = points.map((q) => Math.log10(q[1])), ly = points.map((q) => Math.log10(q[2]));
  const floors = status.panes.map((p) => (p && p.reference_noise) || 0).filter((v) => v > 0);
  floors.forEach((f) => ly.push(Math.log10(f)));
  const x0 = Math.floor(Math.min(...lx)), x1 = Math.ceil(Math.max(...lx)) + (Math.min(...lx) === Math.max(...lx) ? 1 : 0);
  const y0 = Math.floor(Math.min(...ly)), y1 = Math.ceil(Math.max(...ly)) + (Math.min(...ly) === Math.max(...ly) ? 1 : 0);
  const X = (v) => L + (v - x0) / (x1 - x0) * (W - L - R);
  const Y = (v) => H - B - (v - y0) / (y1 - y0) * (H - B - T);
  ctx.strokeStyle = '#ccc';
  for (let d = x0; d <= x1; ++d) { ctx.beginPath(); ctx.moveTo(X(d), T); ctx.lineTo(X(d), H - B); ctx.stroke(); ctx.fillText('1e' + d + ' s', X(d) - 12, H - B + 16); }
  for (let d = y0; d <= y1; ++d) { ctx.beginPath(); ctx.moveTo(L, Y(d)); ctx.lineTo(W - R, Y(d)); ctx.stroke(); ctx.fillText('1e' + d, 10, Y(d) + 4); }
  ctx.fillText('seconds of rendering', (W - R) / 2, H - 6);
  ctx.save(); ctx.translate(12, H / 2 + 40); ctx.rotate(-Math.PI / 2); ctx.fillText('MSE', 0, 0); ctx.restore();
  series.forEach((pts, i) => {
    const good = pts.filter((q) => q[1] > 0 && q[2] > 0);
    if (!good.length) return;
    ctx.strokeStyle = ctx.fillStyle = COLORS[i % COLORS.length];
    ctx.lineWidth = 2;
    ctx.beginPath();
    good.forEach((q, k) => { const x = X(Math.log10(q[1])), y = Y(Math.log10(q[2])); if (k) ctx.lineTo(x, y); else ctx.moveTo(x, y); });
    ctx.stroke();
    const last = good[good.length - 1];
    const p = status.panes[i];
    ctx.fillText(`pane ${i + 1}: ${p.lesson}`, W - R + 8, T + 14 + 32 * i);
    ctx.fillText(`MSE ${fmt(last[2])} at ${last[0]} spp`, W - R + 8, T + 28 + 32 * i);
  });
  ctx.lineWidth = 1;
  if (floors.length) {
    ctx.setLineDash([4, 4]);
    ctx.strokeStyle = '#888';
    const y = Y(Math.log10(floors[0]));
    ctx.beginPath(); ctx.moveTo(L, y); ctx.lineTo(W - R, y); ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = '#888';
    ctx.fillText("the reference's own noise", L + 4, y - 4);
  }
}

function updateReference(status) {
  const parts = [];
  status.panes.forEach((p, i) => { if (p && p.reference) parts.push(`Pane ${i + 1}'s reference: ${p.reference}.`); });
  const r = status.reference;
  if (r && r.state === 'rendering')
    parts.push(`Rendering the reference in the background (${r.lesson}, ${r.spp} / ${r.target_spp} spp): the chart starts when it is done.`);
  $('reference-status').textContent = parts.join(' ');
}

function updateSeries(status) {
  const rows = [];
  status.panes.forEach((p, i) => {
    if (!p || !p.layers || !p.layers.length) return;
    rows.push(`<p>Pane ${i + 1} (${p.lesson}), image mean luminance ${fmt(p.mean_luminance, 4)}:</p>`);
    for (const layer of p.layers)
      rows.push(`<div class="bar"><span class="label">${layer.name}</span><span class="fill" style="width:${Math.max(0, layer.share * 300)}px"></span>${(100 * layer.share).toFixed(2)}% (mean ${fmt(layer.mean, 4)})</div>`);
  });
  const html = rows.join('') || '<p class="description">No pane has bounce layers: choose lesson 4 and set its "bounces" option (8, say).</p>';
  if ($('series').dataset.html !== html) { $('series').dataset.html = html; $('series').innerHTML = html; }
}

function albedoNote() {
  const rho = Number($('albedo').value);
  $('albedo-value').textContent = rho.toFixed(2);
  if (!$('albedo-on').checked) { $('albedo-note').textContent = 'Off: the scene\'s own albedos.'; return; }
  $('albedo-note').textContent = rho >= 0.999
    ? 'rho = 1: the series L_e + L_e + L_e + ... does not converge. Every path survives Russian roulette (its weight never drops), so only the suite\'s safety cut at 1000 segments ends it: the furnace shows about 1000 L_e, and each sample costs 1000 bounces. With --max-depth N it shows N L_e. Neither is the answer, because there is none.'
    : `The furnace converges to L_e / (1 - rho) = ${(1 / (1 - rho)).toFixed(3)} L_e; bounce k carries rho^k (1 - rho) of it.`;
}

async function poll() {
  try {
    const status = await (await api('/api/status')).json();
    studio.status = status;
    status.panes.forEach((s, i) => updatePane(i, s));
    drawChart(status);
    updateReference(status);
    updateSeries(status);
  } catch (e) {
    showMessage('The studio does not answer: ' + e.message);
  }
  setTimeout(poll, 250);
}

// ---- radiometry at a pixel ----

function triple(v, digits = 4) { return v ? v.map((x) => fmt(x, digits)).join(', ') : '-'; }

async function probe(i, event) {
  const pane = studio.panes[i];
  const s = studio.status && studio.status.panes[i];
  if (!s || !s.width) return;
  const rect = pane.img.getBoundingClientRect();
  const x = Math.min(s.width - 1, Math.floor((event.clientX - rect.left) / rect.width * s.width));
  const y = Math.min(s.height - 1, Math.floor((event.clientY - rect.top) / rect.height * s.height));
  studio.lastProbe = { pane: i, x, y };
  await showProbe();
}

async function showProbe() {
  if (!studio.lastProbe) return;
  const { pane, x, y } = studio.lastProbe;
  try {
    const q = new URLSearchParams({ pane, x, y, light: $('probe-light').value || 0 });
    const p = await (await api('/api/probe?' + q)).json();
    studio.probe = p;
    const lights = $('probe-light');
    if ([...lights.options].map((o) => o.text).join() !== p.lights.join()) {
      const chosen = lights.value;
      lights.replaceChildren(...p.lights.map((t, k) => new Option(`${k}: ${t}`, k)));
      if (chosen) lights.value = chosen;
    }
    const rows = [['pixel', `(${x}, ${y}) of pane ${pane + 1}, ${p.spp} spp`, '']];
    if (p.hit) {
      rows.push(['surface', `${p.hit.shape}, ${p.hit.front ? 'front' : 'back'} side, at distance ${fmt(p.hit.distance)}`, "the scene's units"]);
      rows.push(['material', `${p.hit.material} (${p.hit.type})`, '']);
    } else rows.push(['surface', 'none: the ray escapes to the background', '']);
    rows.push(['radiance L (mean)', triple(p.L), p.L_units]);
    rows.push(['L standard error', triple(p.L_standard_error, 2) +
      ((((studio.status && studio.status.panes && studio.status.panes[pane] && studio.status.panes[pane].params) || {})['--sampler'] || 'kronecker') !== 'independent'
        ? ' (from the sample variance: the error only for the independent sampler)' : ''), p.L_units]);
    if (p.hit) {
      rows.push(['direct irradiance E', triple(p.E), p.E_units]);
      rows.push(['E standard error', triple(p.E_standard_error, 2) + ` (${p.E_samples} light samples)`, p.E_units]);
      if (p.f_light !== undefined) {
        rows.push(['f(view, light)', p.f ? triple(p.f) : p.f_note, p.f_units]);
        rows.push(['towards', `${p.f_light}, cos(theta_i) = ${fmt(p.cos_theta_i)}`, '']);
      }
    }
    for (const l of p.layers) rows.push([`share of L: ${l.name}`, (100 * l.share).toFixed(2) + '%', '']);
    const table = document.createElement('table');
    for (const [a, b, u] of rows) {
      const tr = table.insertRow();
      tr.insertCell().textContent = a;
      tr.insertCell().textContent = b;
      const c = tr.insertCell(); c.textContent = u; c.className = 'unit';
    }
    $('probe').replaceChildren(table);
  } catch (e) {
    $('probe').textContent = e.message;
  }
}

// ---- start ----

async function init() {
  studio.config = await (await api('/api/config')).json();
  const c = studio.config;
  if (!c.loopback_only) {
    $('bind-warning').hidden = false;
    $('bind-warning').textContent = `This studio listens on ${c.bind}:${c.port}, not only on this machine: anyone who can reach that address can use it.`;
  }
  for (const s of c.scenes) $('scene').add(new Option(s.id, s.id));
  if (c.scenes.some((s) => s.id === DEFAULTS.scene)) $('scene').value = DEFAULTS.scene;
  const describe = () => { const s = c.scenes.find((x) => x.id === $('scene').value); $('scene-description').textContent = s ? s.description : ''; };
  describe();
  for (const id of ['width', 'height']) $(id).max = c.max_size;
  $('spp').max = c.max_spp;
  const template = $('pane-template');
  for (let i = 0; i < c.panes; ++i) {
    const node = template.content.firstElementChild.cloneNode(true);
    node.id = 'pane' + i;
    node.style.borderTop = `4px solid ${COLORS[i % COLORS.length]}`;
    $('panes').append(node);
    const pane = {
      node, lesson: node.querySelector('.lesson'), options: node.querySelector('.options'),
      view: node.querySelector('.view'), img: node.querySelector('.image'),
      status: node.querySelector('.status'), command: node.querySelector('.command'),
      notes: node.querySelector('.notes'), exr: node.querySelector('.download-exr'),
      png: node.querySelector('.download-png'), inputs: {},
    };
    for (const l of c.lessons) pane.lesson.add(new Option(l.label, l.name));
    const wanted = DEFAULTS.lessons[i] || c.lessons[c.lessons.length - 1].name;
    pane.lesson.value = c.lessons.some((l) => l.name === wanted) ? wanted : c.lessons[0].name;
    studio.panes.push(pane);
    studio.frames.push([]);
    buildOptions(i);
    pane.lesson.addEventListener('change', () => { buildOptions(i); restart(i); });
    pane.view.addEventListener('change', () => { pane.shown = null; });
    pane.img.addEventListener('click', (e) => probe(i, e));
    pane.exr.download = ''; pane.png.download = '';
  }
  // A scene with a shipped reference takes its size, so that its chart starts at once.
  $('scene').addEventListener('change', () => {
    const s = c.scenes.find((x) => x.id === $('scene').value);
    if (s && s.reference_size) [$('width').value, $('height').value] = s.reference_size;
  });
  for (const id of ['scene', 'width', 'height', 'seed', 'spp', 'sampler']) $(id).addEventListener('change', () => { describe(); restartAll(); });
  // A probed pixel belongs to its scene and size.
  for (const id of ['scene', 'width', 'height']) $(id).addEventListener('change', () => { studio.lastProbe = null; studio.probe = null; $('probe').textContent = 'No pixel chosen.'; });
  $('exposure').addEventListener('input', () => { $('exposure-value').textContent = $('exposure').value; });
  for (const id of ['albedo', 'albedo-on']) $(id).addEventListener('change', () => { albedoNote(); restartAll(); });
  $('albedo').addEventListener('input', albedoNote);
  $('probe-light').addEventListener('change', showProbe);
  albedoNote();

  // A render already running (another tab, a reload) is shown as it is, not restarted.
  const status = await (await api('/api/status')).json();
  status.panes.forEach((s, i) => {
    if (s && s.params && s.params.lesson) applyParams(i, s.params);
    else startPane(i);
  });
  describe();
  albedoNote();
  poll();
}

init().catch((e) => showMessage('The studio could not start the page: ' + e.message));
