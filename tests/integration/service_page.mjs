// service_page.mjs - drives the page texoptd serves in headless Chromium (puppeteer-core),
// run by service_page.sh. Usage: node service_page.mjs BASE MODEL [TOKEN]
// Uploads MODEL through the file picker with the fast `input` method, follows the progress
// bar to the end, checks the sizes shown and the downloaded file against the API; then
// starts a slow (perceptual) job and cancels it from the page; fails on any console error.
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';

const [base, modelPath, token = ''] = process.argv.slice(2);
const require = createRequire(join(process.env.TEXOPT_SOURCE_DIR, 'tools', 'package.json'));
const puppeteer = require('puppeteer-core');

const problems = [];
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
  check(form.methods.join() === 'perceptual,input,ssp,tewari,arap', `methods from openapi.yaml (${form.methods})`);
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
  await page.waitForFunction(() => !document.querySelector('#result').hidden, { timeout: 120000 });
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

  // 2. a slow job, canceled from the page.
  await page.select('#param-method', 'perceptual');
  await page.click('#start');
  await page.waitForFunction(id => document.querySelector('#job').dataset.id !== id &&
    document.querySelector('#state').textContent === 'running', { timeout: 60000 }, done.id);
  await page.click('#cancel');
  await page.waitForFunction(() => document.querySelector('#state').textContent === 'canceled', { timeout: 120000 });
  check(true, 'a running job was canceled from the page');

  // 3. the job list shows both jobs, linked.
  await page.waitForFunction(() => document.querySelectorAll('#job-rows tr').length >= 2, { timeout: 10000 });
  const states = await page.$$eval('#job-rows tr', rows => rows.map(r => r.cells[3].textContent));
  check(states.includes('succeeded') && states.includes('canceled'), `job list shows the jobs (${states})`);

  if (process.env.SCREENSHOT) await page.screenshot({ path: process.env.SCREENSHOT, fullPage: true });
  check(problems.length === 0, `no console errors${problems.length ? ': ' + problems.join('; ') : ''}`);
} finally {
  await browser.close();
}
