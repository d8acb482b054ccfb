// service_page.mjs - drives the page texoptd serves in headless Chromium (puppeteer-core),
// run by service_page.sh. Usage: node service_page.mjs BASE MODEL [TOKEN]
// Uploads MODEL through the file picker with the fast `input` method, follows the progress
// bar to the end, checks the sizes shown and the downloaded file against the API; then
// checks the two 3D views, the UV heat maps (by texel density and by each distortion metric,
// whose values must be `texopt info`'s) and the q-cost plot of two evaluated jobs; then
// starts a slow (perceptual) job and cancels it from the page; fails on any console error.
import { execFileSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const [base, modelPath, token = ''] = process.argv.slice(2);
const require = createRequire(join(process.env.TEXOPT_SOURCE_DIR, 'tools', 'package.json'));
const puppeteer = require('puppeteer-core');

const problems = [];

// The .glb as a .gltf with its files: the binary buffer as model.bin and each image as a
// file of its own (its bytes stay in the buffer too; the images are read from their uri).
function splitGlb(glbPath, dir) {
  const glb = readFileSync(glbPath);
  const jsonLength = glb.readUInt32LE(12);
  const gltf = JSON.parse(glb.subarray(20, 20 + jsonLength).toString());
  const bin = glb.subarray(20 + jsonLength + 8);
  const files = [join(dir, 'model.gltf'), join(dir, 'model.bin')];
  writeFileSync(files[1], bin.subarray(0, gltf.buffers[0].byteLength));
  gltf.buffers[0].uri = 'model.bin';
  gltf.images.forEach((image, i) => {
    const view = gltf.bufferViews[image.bufferView];
    const name = `image${i}.${image.mimeType === 'image/png' ? 'png' : 'jpg'}`;
    writeFileSync(join(dir, name), bin.subarray(view.byteOffset || 0, (view.byteOffset || 0) + view.byteLength));
    files.push(join(dir, name));
    delete image.bufferView;
    delete image.mimeType;
    image.uri = name;
  });
  writeFileSync(files[0], JSON.stringify(gltf));
  return files;
}
function check(ok, what) {
  if (!ok) throw new Error(`check failed: ${what}`);
  console.log(`ok   ${what}`);
}

const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM,
  headless: true,
  // CI runs as root, where Chromium's sandbox cannot start.
  args: ['--no-sandbox', '--disable-dev-shm-usage', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'],
});
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1200, height: 1400 });
  page.on('console', m => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', e => problems.push(`page error: ${e.message}`));
  if (token) await page.evaluateOnNewDocument(t => sessionStorage.setItem('texopt-token', t), token);
  await page.goto(base + '/', { waitUntil: 'load' });

  // The form comes from openapi.yaml and /v1/params.
  await page.waitForSelector('#param-method', { timeout: 15000 });
  const form = await page.evaluate(() => ({
    methods: [...document.querySelectorAll('#param-method option')].map(o => o.value),
    method: document.querySelector('#param-method').value,
    costMax: document.querySelector('#param-relative_cost').max,
    cost: document.querySelector('#param-relative_cost').value,
  }));
  check(form.methods.join() === 'perceptual,input,ssp,tewari,arap,paper', `methods from openapi.yaml (${form.methods})`);
  check(form.method === 'perceptual' && form.cost === '1', 'defaults from /v1/params');
  check(form.costMax === '4', 'relative_cost range from openapi.yaml');

  // 1. a fast job, followed to the end.
  await page.select('#param-method', 'input');
  await page.$eval('#param-relative_cost', el => { el.value = '0.5'; });
  const picker = await page.$('#files');
  await picker.uploadFile(modelPath);
  await page.waitForFunction(() => !document.querySelector('#start').disabled);
  // Samples the bar from the moment the job shows, to see that it never moves back.
  await page.evaluate(() => {
    window.samples = [];
    setInterval(() => { if (!document.querySelector('#job').hidden) window.samples.push(document.querySelector('#bar').value); }, 10);
  });
  await page.click('#start');
  await page.waitForFunction(() => document.querySelector('#result').dataset.job, { timeout: 120000 });
  const done = await page.evaluate(() => ({
    samples: window.samples,
    state: document.querySelector('#state').textContent,
    percent: document.querySelector('#percent').textContent,
    id: document.querySelector('#job').dataset.id,
    rows: [...document.querySelectorAll('#sizes tbody tr')].map(tr => [...tr.cells].map(c => c.textContent)),
    name: document.querySelector('#download').download,
  }));
  check(done.state === 'succeeded' && done.percent === '100%', `job ${done.id} succeeded, bar at 100%`);
  check(done.samples.length > 0 && done.samples.every((v, i) => i === 0 || v >= done.samples[i - 1]),
    `progress bar never moved back (${done.samples.length} samples)`);
  const pixels = done.rows.find(r => r[0] === 'texture pixels');
  check(pixels && pixels[1] === '1,048,576' && pixels[2] === (724 * 724).toLocaleString('en'),
    `texture pixels before/after from the stats (${pixels})`);
  const fileRow = done.rows.find(r => r[0] === 'file bytes');

  // The download link holds the same bytes as /result.
  const headers = token ? { Authorization: `Bearer ${token}` } : {};
  const direct = Buffer.from(await (await fetch(`${base}/v1/jobs/${done.id}/result`, { headers })).arrayBuffer());
  const viaPage = Buffer.from(await page.evaluate(async () => {
    const blob = await (await fetch(document.querySelector('#download').href)).arrayBuffer();
    return [...new Uint8Array(blob)];
  }));
  check(viaPage.length > 1000 && viaPage.subarray(0, 4).toString() === 'glTF', `download is a .glb (${viaPage.length} bytes)`);
  check(direct.equals(viaPage), 'download equals GET /result');
  check(done.name === 'spot-texopt.glb' || done.name.endsWith('-texopt.glb'), `download named ${done.name}`);
  check(fileRow[1] === `${(readFileSync(modelPath).length / 1024).toFixed(1)} KiB` &&
    fileRow[2] === `${(direct.length / 1024).toFixed(1)} KiB`, 'file bytes before/after match the upload and the result');

  // The viewers drew the model, with one camera: the two renders cover the same pixels and
  // look alike (the output is the input at half the texels); after a drag on the output
  // view both renders changed and still agree.
  const compareViews = () => page.evaluate(() => {
    const pixels = id => {
      const src = document.getElementById(id);
      const c = document.createElement('canvas');
      c.width = src.width; c.height = src.height;
      const ctx = c.getContext('2d');
      ctx.drawImage(src, 0, 0);
      return ctx.getImageData(0, 0, c.width, c.height).data;
    };
    const a = pixels('view-in'), b = pixels('view-out');
    const isModel = (d, i) => Math.abs(d[i] - 242) + Math.abs(d[i + 1] - 242) + Math.abs(d[i + 2] - 242) > 12;
    let inA = 0, inB = 0, both = 0, diff = 0;
    for (let i = 0; i < a.length; i += 4) {
      const ma = isModel(a, i), mb = isModel(b, i);
      inA += ma; inB += mb; both += ma && mb;
      if (ma && mb) diff += (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2])) / 3;
    }
    const n = a.length / 4;
    return { coverA: inA / n, coverB: inB / n, iou: both / (inA + inB - both), meanDiff: diff / Math.max(both, 1),
      signature: [...a.filter((_, i) => i % 4004 === 0)].join() };
  });
  await page.waitForFunction(() => document.querySelector('#view-out').width > 0);
  const first = await compareViews();
  check(first.coverA > 0.05 && first.coverB > 0.05, `both viewers drew the model (cover ${first.coverA.toFixed(3)}, ${first.coverB.toFixed(3)})`);
  check(first.iou > 0.97, `the two views show the model from one camera (overlap ${first.iou.toFixed(3)})`);
  check(first.meanDiff < 12, `output render within tolerance of the input render (mean difference ${first.meanDiff.toFixed(2)} of 255)`);
  const box = await (await page.$('#view-out')).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 30, { steps: 8 });
  await page.mouse.up();
  const turned = await compareViews();
  check(turned.signature !== first.signature && turned.iou > 0.97,
    `a drag on the output view turned both (overlap ${turned.iou.toFixed(3)})`);
  // Compare on one view: the output lies on the input, cut at the slider, same camera.
  await page.click('#overlay');
  await page.$eval('#split', el => { el.value = '30'; el.dispatchEvent(new Event('input')); });
  const overlay = await page.evaluate(() => {
    const a = document.querySelector('#view-in').getBoundingClientRect();
    const b = document.querySelector('#view-out').getBoundingClientRect();
    return { same: a.x === b.x && a.y === b.y && a.width === b.width && a.height === b.height,
      clip: document.querySelector('#view-out').style.clipPath };
  });
  check(overlay.same && overlay.clip === 'inset(0px 0px 0px 30%)', `compare on one view (${overlay.clip})`);
  const overlaid = await compareViews();
  check(overlaid.coverA > 0.05 && overlaid.iou > 0.97, `one camera in the overlay too (overlap ${overlaid.iou.toFixed(3)})`);
  await page.click('#overlay');
  const heat = await page.evaluate(() => ['uv-in', 'uv-out'].map(id => {
    const d = document.getElementById(id).getContext('2d').getImageData(0, 0, 360, 360).data;
    let coloured = 0;
    for (let i = 0; i < d.length; i += 4) coloured += d[i] !== 0x33 || d[i + 1] !== 0x33 || d[i + 2] !== 0x33;
    return coloured / (d.length / 4);
  }));
  check(heat[0] > 0.1 && heat[1] > 0.1, `both UV heat maps drawn (${heat.map(h => h.toFixed(3))} of the canvas covered)`);
  check(await page.$eval('#qcost-box', e => e.hidden), 'no q-cost plot for a job without evaluation');

  // The layouts' colouring: texel density by default, or a distortion metric. The `input`
  // method keeps the layout at half the texels: by density the output reads apart from the
  // input, by any metric the two read the same (a change of resolution is no distortion).
  // Switching redraws both from what the page holds, without a request.
  let requests = 0;
  const countRequest = () => { requests++; };
  page.on('request', countRequest);
  const drawnWith = choice => page.evaluate(choice => {
    const select = document.querySelector('#uv-metric');
    const initial = select.value;
    if (choice) { select.value = choice; select.dispatchEvent(new Event('change')); }
    const pixels = id => document.getElementById(id).getContext('2d').getImageData(0, 0, 360, 360).data;
    const meanDifference = (x, y) => {
      let sum = 0;
      for (let i = 0; i < x.length; i++) if (i % 4 !== 3) sum += Math.abs(x[i] - y[i]);
      return sum / (0.75 * x.length);
    };
    const a = pixels('uv-in'), b = pixels('uv-out');
    let flagged = 0, hash = 0;
    const colours = new Set();
    for (let i = 0; i < b.length; i += 4) {
      flagged += b[i] === 0 && b[i + 1] === 200 && b[i + 2] === 0;
      colours.add(b[i] << 16 | b[i + 1] << 8 | b[i + 2]);
      hash = (Math.imul(hash, 31) + b[i] + 7 * b[i + 1] + 13 * b[i + 2]) >>> 0;
    }
    // Against the last drawing by the same choice: Chromium may move a canvas read back often
    // from the GPU to the CPU, which anti-aliases edges differently.
    window.uvDrawn = window.uvDrawn || {};
    const last = window.uvDrawn[select.value];
    window.uvDrawn[select.value] = b;
    return { initial, options: [...select.options].map(o => o.value), inOut: meanDifference(a, b), flagged,
      colours: colours.size, hash, sinceLast: last ? meanDifference(last, b) : null,
      legend: document.querySelector('#uv-legend').textContent };
  }, choice);
  const initial = await drawnWith(null);
  const density = await drawnWith('density'); // a redraw, the reference of the one below
  const MINIMA = { conformal: 1, mips: 2, isometric: 1.41, max_isometric: 1, area: 1, symmetric_dirichlet: 4, l2_stretch: 1,
    linf_stretch: 1 };
  const METRIC_KEYS = Object.keys(MINIMA);
  check(initial.initial === 'density' && density.options.join() === ['density', ...METRIC_KEYS].join(),
    `the layouts' colouring selector, texel density by default (${density.options})`);
  check(density.inOut > 10 && density.legend.includes("against the input's median"),
    `by texel density the output's half texels show (mean difference ${density.inOut.toFixed(1)} of 255)`);
  const hashes = new Set([density.hash]);
  for (const key of METRIC_KEYS) {
    const drawn = await drawnWith(key);
    hashes.add(drawn.hash);
    check(drawn.inOut === 0 && drawn.colours > 20 && drawn.flagged === 0 && drawn.legend.includes(`${MINIMA[key]} (isometry)`),
      `by ${key} the output reads as the input, in ${drawn.colours} colours (legend: ${drawn.legend.slice(0, 50)}…)`);
  }
  check(hashes.size === 1 + METRIC_KEYS.length, `each colouring draws differently (${hashes.size} different canvases)`);
  const back = await drawnWith('density');
  check(back.sinceLast === 0, 'back to texel density, the same drawing again');
  page.off('request', countRequest);
  check(requests === 0, `switching the colouring made no request (${requests})`);
  const legendColours = await page.evaluate(async () => {
    const { metricColours, FLAGGED_COLOUR } = await import('/ui/viewer.js');
    const { METRICS } = await import('/ui/distortion.js');
    const layout = { degenerate: [0, 1, 0, 0], flipped: [0, 0, 1, 0], sigmaMax: [1, 1, 1, 8], sigmaMin: [1, 1, 1, 1] };
    const colourOf = metricColours(METRICS.find(m => m.key === 'conformal'));
    return [0, 1, 2, 3].map(t => colourOf(layout, t) === FLAGGED_COLOUR ? 'flagged' : colourOf(layout, t));
  });
  check(legendColours.join(' ') === 'rgb(255,255,255) flagged flagged rgb(255,0,0)',
    `conformal 1 is white, 8 red, a degenerate or flipped triangle flagged (${legendColours.join(' ')})`);

  // The page's metrics of the result are the engine's: their area-weighted means (L2: root
  // mean square) and maxima are those `texopt info` gives for the result file.
  const resultDir = mkdtempSync(join(tmpdir(), 'texopt-page-'));
  let engine;
  try {
    writeFileSync(join(resultDir, 'result.glb'), direct);
    const info = JSON.parse(execFileSync(process.env.TEXOPT_BIN, ['info', join(resultDir, 'result.glb')]).toString());
    engine = info.domains[0].distortion;
  } finally {
    rmSync(resultDir, { recursive: true, force: true });
  }
  const pageMetrics = await page.evaluate(async () => {
    const { GLTFLoader } = await import('/ui/three-GLTFLoader.js');
    const { uvLayouts, measureLayouts } = await import('/ui/viewer.js');
    const { METRICS } = await import('/ui/distortion.js');
    const bytes = await (await fetch(document.querySelector('#download').href)).arrayBuffer();
    const gltf = await new Promise((ok, fail) => new GLTFLoader().parse(bytes, '', ok, fail));
    const layouts = uvLayouts(gltf.scene);
    measureLayouts([], layouts);
    const area = (p, t) => {
      const e = [3, 6].map(k => [0, 1, 2].map(c => p[9 * t + k + c] - p[9 * t + c]));
      return Math.hypot(e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
        e[0][0] * e[1][1] - e[0][1] * e[1][0]) / 2;
    };
    return Object.fromEntries(METRICS.map(m => {
      let sum = 0, total = 0, max = 0;
      for (const l of layouts)
        for (let t = 0; t < l.degenerate.length; t++) {
          if (l.degenerate[t]) continue;
          const v = m.of(l.sigmaMax[t], l.sigmaMin[t]), a = area(l.positions, t);
          sum += a * (m.key === 'l2_stretch' ? v * v : v);
          total += a;
          max = Math.max(max, v);
        }
      return [m.key, { mean: m.key === 'l2_stretch' ? Math.sqrt(sum / total) : sum / total, max }];
    }));
  });
  const relative = (a, b) => Math.abs(a - b) / Math.abs(b);
  const worst = Math.max(...METRIC_KEYS.flatMap(k => [relative(pageMetrics[k].mean, engine[k].mean),
    relative(pageMetrics[k].max, engine[k].max)]));
  check(worst < 1e-9, `the page's metrics match texopt info's (conformal mean ${pageMetrics.conformal.mean.toFixed(4)}, ` +
    `engine ${engine.conformal.mean.toFixed(4)}; worst relative difference ${worst.toExponential(1)})`);
  // SCREENSHOT_UV=file.png: the layouts by a metric, to look at.
  if (process.env.SCREENSHOT_UV) {
    await drawnWith('conformal');
    await (await page.$('#result')).screenshot({ path: process.env.SCREENSHOT_UV });
    await drawnWith('density');
  }

  // An evaluated job: the q-cost plot shows it beside the other evaluated job of the model.
  for (const cost of ['0.25', '0.5']) {
    await page.$eval('#param-relative_cost', (el, c) => { el.value = c; }, cost);
    await page.$eval('#param-evaluate', el => { el.checked = true; });
    const before = await page.$eval('#job', e => e.dataset.id);
    await page.click('#start');
    await page.waitForFunction(id => document.querySelector('#job').dataset.id !== id &&
      document.querySelector('#result').dataset.job === document.querySelector('#job').dataset.id,
      { timeout: 180000 }, before);
  }
  const plot = await page.$$eval('#qcost circle.point', cs => cs.map(c => Number(c.getAttribute('r'))));
  check(plot.length === 2 && plot.includes(5), `q-cost plot shows the evaluated jobs (${plot.length} points)`);
  check(!(await page.$eval('#qcost-box', e => e.hidden)), 'the q-cost plot shows for an evaluated job');
  const report = await page.$eval('#report', async e => ({
    hidden: e.hidden, href: e.getAttribute('href'),
    head: (await (await fetch(e.href)).text()).slice(0, 200).toLowerCase(),
  }));
  check(!report.hidden && report.head.includes('<html'), `the evaluated job links its report (${report.href.slice(0, 30)})`);
  check(token ? report.href.startsWith('blob:') : report.href.startsWith('/v1/jobs/'),
    token ? 'with a token the report is fetched with it' : 'without a token the report is a plain link');
  // SCREENSHOT=docs/page.jpg regenerates the picture of the README.
  if (process.env.SCREENSHOT) await page.screenshot({ path: process.env.SCREENSHOT, fullPage: true, quality: 80 });
  await page.$eval('#param-evaluate', el => { el.checked = false; });

  // A .gltf with its .bin and image, chosen together: uploaded as multipart, shown in 3D.
  const split = mkdtempSync(join(tmpdir(), 'texopt-page-'));
  try {
    await (await page.$('#files')).uploadFile(...splitGlb(modelPath, split));
    const chosen = await page.$eval('#chosen', e => e.textContent);
    check(chosen.startsWith('model.gltf with 2 file(s)'), `a .gltf with its files chosen (${chosen})`);
    await page.$eval('#param-evaluate', el => { el.checked = false; });
    const previous = await page.$eval('#job', e => e.dataset.id);
    await page.click('#start');
    await page.waitForFunction(id => document.querySelector('#job').dataset.id !== id &&
      document.querySelector('#result').dataset.job === document.querySelector('#job').dataset.id,
      { timeout: 120000 }, previous);
    const gltfViews = await compareViews();
    const gltfPixels = await page.$$eval('#sizes tbody tr', rows => rows.map(r => r.cells[2].textContent));
    check(gltfViews.coverA > 0.05 && gltfViews.iou > 0.97 && gltfPixels.includes((724 * 724).toLocaleString('en')),
      `the .gltf job succeeded and its input drew from its files (overlap ${gltfViews.iou.toFixed(3)})`);
    await (await page.$('#files')).uploadFile(modelPath); // the page's File objects must outlive split/
  } finally {
    rmSync(split, { recursive: true, force: true });
  }

  // 2. a slow job, canceled from the page.
  await page.select('#param-method', 'perceptual');
  const last = await page.$eval('#job', e => e.dataset.id);
  await page.click('#start');
  await page.waitForFunction(id => document.querySelector('#job').dataset.id !== id &&
    document.querySelector('#state').textContent === 'running', { timeout: 60000 }, last);
  await page.click('#cancel');
  await page.waitForFunction(() => document.querySelector('#state').textContent === 'canceled', { timeout: 120000 });
  check(true, 'a running job was canceled from the page');

  // 3. the job list shows both jobs, linked.
  // The list is refreshed when the followed job ends.
  await page.waitForFunction(() => [...document.querySelectorAll('#job-rows tr')].some(r => r.cells[3].textContent === 'canceled'),
    { timeout: 10000 }).catch(() => {});
  const states = await page.$$eval('#job-rows tr', rows => rows.map(r => r.cells[3].textContent));
  check(states.includes('succeeded') && states.includes('canceled'), `job list shows the jobs (${states})`);

  // Paging: 11 jobs are a page of 10 and a page of 1.
  if (!token) {
    const glb = readFileSync(modelPath);
    for (let i = states.length; i < 11; i++) {
      const r = await fetch(`${base}/v1/jobs?method=input&relative_cost=0.1`,
        { method: 'POST', headers: { 'Content-Type': 'model/gltf-binary' }, body: glb });
      if (r.status !== 202) throw new Error(`upload for paging answered ${r.status}`);
    }
    await page.click('#jobs-first');
    await page.waitForFunction(() => document.querySelectorAll('#job-rows tr').length === 10 &&
      !document.querySelector('#jobs-next').disabled, { timeout: 10000 });
    const firstPage = await page.$$eval('#job-rows tr', rows => rows.map(r => r.cells[0].textContent));
    await page.click('#jobs-next');
    await page.waitForFunction(() => document.querySelectorAll('#job-rows tr').length === 1, { timeout: 10000 });
    const secondPage = await page.$$eval('#job-rows tr', rows => rows.map(r => r.cells[0].textContent));
    check(!firstPage.includes(secondPage[0]) && await page.$eval('#jobs-next', b => b.disabled),
      'the job list pages: 10 jobs, then the 11th, then no next page');
    await page.click('#jobs-first');
    await page.waitForFunction(() => document.querySelectorAll('#job-rows tr').length === 10, { timeout: 10000 });
  }

  check(problems.length === 0, `no console errors${problems.length ? ': ' + problems.join('; ') : ''}`);
} finally {
  await browser.close();
}
