// app.js - the texopt page: choose a model, set parameters, follow the job, fetch the
// result, list jobs. Talks to texoptd only through api.js (the public API).
import { call, json, paramsSchema, followEvents, setToken, getToken } from './api.js';
import { SideBySide, uvLayouts, measureLayouts, medianDensity, drawHeatMap, heatColour, densityColours, metricColours,
  FLAGGED_COLOUR } from './viewer.js';
import { METRICS } from './distortion.js';
import { drawQCost } from './plot.js';

const $ = id => document.getElementById(id);
const FINISHED = ['succeeded', 'failed', 'canceled'];
const FIRST_JOBS_PAGE = '/v1/jobs?limit=10';
// The parameters the form shows; the others keep the engine's defaults.
const SHOWN = ['method', 'budget', 'relative_cost', 'texture_width', 'texture_height', 'target_loss',
  'iterations', 'evaluate'];
const BUDGET_KEYS = { relative_cost: ['relative_cost'], texture_size: ['texture_width', 'texture_height'],
  target_loss: ['target_loss'] };

let model = null;          // {main: File, files: [{file, path}]}
let schema = {}, defaults = {};
let following = null;      // AbortController of the event stream followed
let shownProgress = 0;
let jobsPage = null, jobsNext = null, jobsShown = [];
let viewer = null;
const inputs = new Map();  // job id -> the model uploaded from this page, for the input view

function say(text, isError = false) {
  $('message').textContent = text;
  $('message').className = isError ? 'error' : '';
  if (isError) console.warn(text);
}

function bytes(n) {
  if (n == null) return '–';
  const units = ['B', 'KiB', 'MiB', 'GiB'];
  let i = 0;
  while (n >= 1024 && i < units.length - 1) { n /= 1024; i++; }
  return `${n.toFixed(i ? 1 : 0)} ${units[i]}`;
}

// ---- model choice -----------------------------------------------------------------------

function chooseModel(entries) {
  const main = entries.find(e => /\.(glb|gltf)$/i.test(e.path));
  if (!main) { say('Choose a .glb, or a .gltf with its files.', true); return; }
  model = { main: main.file, files: entries.filter(e => e !== main) };
  if (/\.glb$/i.test(main.path)) model.files = [];
  // A .gltf names its files relative to itself: strip the folder it was dropped in.
  const base = main.path.includes('/') ? main.path.slice(0, main.path.lastIndexOf('/') + 1) : '';
  model.files = model.files.map(e => ({ file: e.file, path: e.path.startsWith(base) ? e.path.slice(base.length) : e.path }));
  const extra = model.files.length ? ` with ${model.files.length} file(s)` : '';
  $('chosen').textContent = `${main.file.name}${extra}, ${bytes(model.files.reduce((s, e) => s + e.file.size, main.file.size))}`;
  $('start').disabled = false;
  say('');
}

async function walk(entry, path, out) {
  if (entry.isFile) {
    out.push({ file: await new Promise((ok, fail) => entry.file(ok, fail)), path: path + entry.name });
  } else if (entry.isDirectory) {
    const reader = entry.createReader();
    for (;;) {
      const batch = await new Promise((ok, fail) => reader.readEntries(ok, fail));
      if (!batch.length) break;
      for (const child of batch) await walk(child, path + entry.name + '/', out);
    }
  }
}

function setUpDrop() {
  const drop = $('drop');
  drop.addEventListener('dragover', e => { e.preventDefault(); drop.classList.add('over'); });
  drop.addEventListener('dragleave', () => drop.classList.remove('over'));
  drop.addEventListener('drop', async e => {
    e.preventDefault();
    drop.classList.remove('over');
    const out = [];
    const items = [...e.dataTransfer.items].map(i => i.webkitGetAsEntry && i.webkitGetAsEntry()).filter(Boolean);
    if (items.length) for (const entry of items) await walk(entry, '', out);
    else for (const file of e.dataTransfer.files) out.push({ file, path: file.name });
    chooseModel(out);
  });
  $('files').addEventListener('change', e => chooseModel([...e.target.files].map(file => ({ file, path: file.name }))));
}

// ---- parameters ---------------------------------------------------------------------------

function inputFor(name, spec, value) {
  let input;
  if (spec.enum) {
    input = document.createElement('select');
    for (const option of spec.enum) input.add(new Option(option, option, false, option === value));
  } else if (spec.type === 'boolean') {
    input = document.createElement('input');
    input.type = 'checkbox';
    input.checked = !!value;
  } else {
    input = document.createElement('input');
    input.type = 'number';
    input.step = spec.type === 'integer' ? '1' : 'any';
    if (spec.minimum !== undefined) input.min = spec.minimum;
    if (spec.maximum !== undefined) input.max = spec.maximum;
    if (value !== undefined && value !== null) input.value = value;
  }
  input.id = 'param-' + name;
  input.name = name;
  return input;
}

function rangeText(spec) {
  const lo = spec.minimum !== undefined ? `${spec.minimum} ≤ ` : spec.exclusiveMinimum !== undefined ? `${spec.exclusiveMinimum} < ` : '';
  const hi = spec.maximum !== undefined ? ` ≤ ${spec.maximum}` : spec.exclusiveMaximum !== undefined ? ` < ${spec.exclusiveMaximum}` : '';
  return lo || hi ? `${lo}${spec.type === 'integer' ? 'n' : 'x'}${hi}` : '';
}

async function loadParams() {
  const [yaml, engine] = await Promise.all([(await call('/openapi.yaml')).text(), json('/v1/params')]);
  schema = paramsSchema(yaml);
  defaults = engine.defaults;
  const form = $('param-form');
  form.textContent = '';
  for (const name of SHOWN) {
    const spec = schema[name];
    if (!spec) continue;
    const value = defaults[name] !== undefined ? defaults[name] : spec.default;
    const label = document.createElement('label');
    label.htmlFor = 'param-' + name;
    label.textContent = name.replace(/_/g, ' ');
    const cell = document.createElement('div');
    cell.append(inputFor(name, spec, value));
    const hint = document.createElement('small');
    hint.textContent = ' ' + [rangeText(spec), value !== undefined ? `default ${value}` : ''].filter(Boolean).join(', ');
    cell.append(hint);
    label.dataset.param = name;
    cell.dataset.param = name;
    form.append(label, cell);
  }
  form.addEventListener('change', showBudgetFields);
  showBudgetFields();
}

function showBudgetFields() {
  const budget = $('param-budget') ? $('param-budget').value : 'relative_cost';
  for (const [kind, keys] of Object.entries(BUDGET_KEYS))
    for (const key of keys)
      for (const el of document.querySelectorAll(`[data-param="${key}"]`)) el.hidden = kind !== budget;
}

// The parameters to send: the budget's own keys, and any other shown value that is not the default.
function chosenParams() {
  const params = {};
  const budget = $('param-budget').value;
  for (const name of SHOWN) {
    const input = $('param-' + name);
    if (!input) continue;
    const spec = schema[name];
    let value = spec.type === 'boolean' ? input.checked : spec.enum ? input.value : input.value === '' ? undefined : Number(input.value);
    if (value === undefined) continue;
    const isBudgetKey = Object.values(BUDGET_KEYS).flat().includes(name);
    if (isBudgetKey ? BUDGET_KEYS[budget].includes(name) : value !== defaults[name]) params[name] = value;
  }
  params.budget = budget;
  return params;
}

// ---- jobs -----------------------------------------------------------------------------------

async function start() {
  if (!model) return;
  $('start').disabled = true;
  say('Uploading…');
  const form = new FormData();
  form.append('model', model.main, model.main.name);
  for (const e of model.files) form.append('files', e.file, e.path);
  form.append('params', JSON.stringify(chosenParams()));
  try {
    const response = await call('/v1/jobs', { method: 'POST', body: form });
    const job = await response.json();
    inputs.set(job.id, model);
    say('');
    follow(job);
  } catch (error) {
    say(`Upload refused: ${error.message}`, true);
  } finally {
    $('start').disabled = false;
  }
}

function showJob(job) {
  // Progress is monotonic per run on the server; the bar also never moves back here.
  shownProgress = Math.max(shownProgress, job.progress || 0);
  $('bar').value = shownProgress;
  $('percent').textContent = `${Math.floor(shownProgress * 100)}%`;
  $('state').textContent = job.state;
  $('stage').textContent = job.stage || '–';
  $('eta').textContent = job.eta_seconds != null && !FINISHED.includes(job.state) ? `about ${Math.ceil(job.eta_seconds)} s left` : '';
  const stats = job.running_stats || {};
  $('running').textContent = Object.entries(stats).map(([k, v]) => `${k.replace(/_/g, ' ')} ${Number(v).toFixed(4)}`).join(' · ');
  $('cancel').disabled = FINISHED.includes(job.state);
  if (job.problem) say(`Job ${job.state}: ${job.problem.detail || job.problem.title}`, true);
}

function follow(job) {
  if (following) following.abort();
  following = new AbortController();
  shownProgress = 0;
  $('job').hidden = false;
  $('result').hidden = true;
  $('job-id').textContent = job.id;
  $('job').dataset.id = job.id;
  showJob(job);
  let last = job;
  followEvents(job.id, (name, next) => { if (name !== 'deleted') { last = next; showJob(next); } }, following.signal)
    .then(async () => {
      if (following.signal.aborted) return;
      last = await json(`/v1/jobs/${job.id}`);
      showJob(last);
      await listJobs(jobsPage); // first: the q-cost plot reads the listed jobs
      if (last.state === 'succeeded') await showResult(last);
    })
    .catch(error => say(`Following the job failed: ${error.message}`, true));
}

async function cancel() {
  const id = $('job').dataset.id;
  try {
    await call(`/v1/jobs/${id}`, { method: 'DELETE' });
    say('Cancel requested.');
  } catch (error) {
    say(`Cancel failed: ${error.message}`, true);
  }
}

function texturePixels(stats, key) {
  let sum = 0;
  for (const domain of stats.domains || [])
    for (const image of domain.images || []) sum += image[key][0] * image[key][1];
  return sum;
}

async function showResult(job) {
  const [stats, result] = await Promise.all([json(`/v1/jobs/${job.id}/stats`), call(`/v1/jobs/${job.id}/result`)]);
  const blob = await result.blob();
  const disposition = result.headers.get('Content-Disposition') || '';
  const name = (disposition.match(/filename="([^"]+)"/) || [])[1] || 'texopt.glb';
  const link = $('download');
  if (link.href.startsWith('blob:')) URL.revokeObjectURL(link.href);
  link.href = URL.createObjectURL(blob);
  link.download = name;
  link.textContent = `Download ${name}`;
  const rows = [
    ['file bytes', job.model && job.model.upload_bytes, blob.size, bytes],
    ['texture pixels', texturePixels(stats, 'input_size'), texturePixels(stats, 'output_size'), n => n.toLocaleString('en')],
  ];
  const body = $('sizes').tBodies[0];
  body.textContent = '';
  for (const [label, before, after, show] of rows) {
    const tr = body.insertRow();
    for (const text of [label, before != null ? show(before) : '–', show(after), before ? (after / before).toFixed(3) : '–'])
      tr.insertCell().textContent = text;
  }
  await showModels(job.id, await blob.arrayBuffer());
  await showQCost(job, stats);
  await linkReport(job);
  $('result').hidden = false;
  $('result').dataset.job = job.id; // complete: scripts driving the page wait for this
}

// A link opens the report in a tab; with a token (a link cannot send it) the report is
// fetched with it and saved as a file instead.
async function linkReport(job) {
  const report = $('report');
  if (report.href.startsWith('blob:')) URL.revokeObjectURL(report.href);
  report.hidden = !(job.links && job.links.report);
  report.removeAttribute('download');
  report.href = '#';
  if (report.hidden) return;
  if (!getToken()) {
    report.href = job.links.report;
    return;
  }
  const html = await (await call(job.links.report)).blob();
  report.href = URL.createObjectURL(html);
  report.download = `${job.id}-report.html`;
}

// The input (when uploaded from this page) and the output side by side, and their layouts.
async function showModels(id, resultBytes) {
  if (!viewer) viewer = new SideBySide([$('view-in'), $('view-out')]);
  $('result').hidden = false; // the canvases need their size before the first frame
  const input = inputs.get(id);
  let inputScene = null;
  if (input) {
    const files = new Map(input.files.map(e => [e.path, e.file]));
    inputScene = await viewer.show(0, await input.main.arrayBuffer(), files);
  }
  const outputScene = await viewer.show(1, resultBytes);
  const before = inputScene ? uvLayouts(inputScene) : [], after = uvLayouts(outputScene);
  measureLayouts(before, after);
  const reference = medianDensity(before.length ? before : after);
  $('uv-metric').onchange = () => drawLayouts(before, after, reference);
  drawLayouts(before, after, reference);
}

// Both UV layouts coloured by what #uv-metric selects (one scale for both), and the legend.
function drawLayouts(before, after, reference) {
  const metric = METRICS.find(m => m.key === $('uv-metric').value);
  const colours = metric ? metricColours(metric) : densityColours(reference);
  drawHeatMap($('uv-in'), before, colours);
  drawHeatMap($('uv-out'), after, colours);
  showHeatLegend(metric);
}

// What the colours of the UV layouts mean: density against the input's median, or the
// metric, its minimum (an isometry) and its scale.
function showHeatLegend(metric) {
  const legend = $('uv-legend');
  legend.textContent = '';
  const swatch = (colour, text) => {
    const box = document.createElement('span');
    box.className = 'swatch';
    box.style.background = colour;
    legend.append(box, ` ${text}`);
  };
  if (!metric) {
    legend.append("Texels per unit of surface, against the input's median: ");
    [[1 / 8, '8× fewer · '], [1, 'same · '], [8, '8× more']].forEach(([x, text]) => swatch(heatColour(x, 1), text));
    return;
  }
  const value = x => Number((metric.minimum * x).toPrecision(3));
  legend.append(`${metric.name} ${metric.formula} (σ the singular values of the map from the surface to the ` +
    "layout scaled to the surface's area), on a log scale from its minimum, an isometry's: ");
  [[1, `${value(1)} (isometry) · `], [Math.SQRT2 * 2, `${value(Math.SQRT2 * 2)} · `], [8, `${value(8)} or more · `]]
    .forEach(([x, text]) => swatch(heatColour(x, 1), text));
  swatch(FLAGGED_COLOUR, 'flipped against the input, or degenerate');
}

// q against cost for the evaluated, succeeded jobs of the same model on the listed page.
async function showQCost(job, stats) {
  const box = $('qcost-box');
  box.hidden = !stats.evaluation;
  if (box.hidden) return;
  const point = (s, current) => ({ method: s.method, cost: s.domains[0].relative_cost, q: s.evaluation.q, current });
  const others = jobsShown.filter(j => j.id !== job.id && j.state === 'succeeded' && j.params && j.params.evaluate &&
    j.model && job.model && j.model.name === job.model.name);
  const points = [point(stats, true)];
  for (const other of others) {
    try {
      const s = await json(`/v1/jobs/${other.id}/stats`);
      if (s.evaluation) points.push(point(s, false));
    } catch { /* deleted meanwhile */ }
  }
  drawQCost($('qcost'), points);
}

// Lists a page of jobs: the first, or the one a page's `next` link names.
async function listJobs(url) {
  const page = await json(url || FIRST_JOBS_PAGE);
  jobsPage = url;
  jobsNext = page.next;
  jobsShown = page.jobs;
  const rows = $('job-rows');
  rows.textContent = '';
  for (const job of page.jobs) {
    const tr = rows.insertRow();
    const link = document.createElement('a');
    link.href = `#${job.id}`;
    link.textContent = job.id.slice(0, 8);
    link.addEventListener('click', () => openJob(job.id));
    tr.insertCell().append(link);
    for (const text of [job.model ? job.model.name : '', job.params ? job.params.method : '', job.state,
      `${Math.floor((job.progress || 0) * 100)}%`, job.created_at || ''])
      tr.insertCell().textContent = text;
  }
  $('jobs-next').disabled = !jobsNext;
}

async function openJob(id) {
  try {
    follow(await json(`/v1/jobs/${id}`));
  } catch (error) {
    say(`Job ${id}: ${error.message}`, true);
  }
}

// ---- start-up -------------------------------------------------------------------------------

async function boot() {
  try {
    await loadParams();
    await listJobs(null);
    if (/^#[0-9a-f]{32}$/.test(location.hash)) openJob(location.hash.slice(1));
  } catch (error) {
    say(error.status === 401 ? 'This server needs an API token: enter it under “API token”.' : `The API answered: ${error.message}`,
      true);
    if (error.status === 401) $('token-box').open = true;
  }
}

// Side by side, or the output over the input with the part left of the slider cut away.
function setUpCompare() {
  const update = () => {
    const on = $('overlay').checked;
    $('views').classList.toggle('overlay', on);
    $('split').hidden = !on;
    $('view-out').style.clipPath = on ? `inset(0 0 0 ${$('split').value}%)` : '';
    if (viewer) viewer.render();
  };
  $('overlay').addEventListener('change', update);
  $('split').addEventListener('input', update);
}

// The selector's choices after texel density: distortion.js's metrics.
function setUpMetricChoice() {
  for (const metric of METRICS) $('uv-metric').add(new Option(metric.name, metric.key));
}

function setUp() {
  $('token').value = getToken();
  $('token').addEventListener('change', e => { setToken(e.target.value.trim()); boot(); });
  setUpDrop();
  setUpCompare();
  setUpMetricChoice();
  $('start').addEventListener('click', start);
  $('cancel').addEventListener('click', cancel);
  $('jobs-next').addEventListener('click', () => listJobs(jobsNext));
  $('jobs-first').addEventListener('click', () => listJobs(null));
  boot();
}

setUp();
