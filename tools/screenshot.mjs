// screenshot.mjs - a .glb as a PBR viewer shows it (three.js, RoomEnvironment light, headless
// Chromium through puppeteer-core), saved as a JPEG: for the before/after pictures in
// docs/benchmarks.md. Not a test; nothing checks the pixels.
// Usage: node tools/screenshot.mjs MODEL.glb|.gltf OUT.jpg [--yaw DEG] [--pitch DEG] [--zoom F]
//        [--target X,Y,Z] [--size WxH] [--quality Q]   (OUT ending in .png: a PNG)
// The camera looks at the bounding box's centre (or --target, in the box's units relative to
// its centre, -1..1 per axis) from direction (yaw, pitch), at the distance that frames the
// box, divided by --zoom. CHROMIUM names the browser (default /usr/bin/chromium).
import { createRequire } from 'node:module';
import { createServer } from 'node:http';
import { readFileSync } from 'node:fs';
import { basename, dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const require = createRequire(join(here, 'package.json'));
const puppeteer = require('puppeteer-core');

const args = process.argv.slice(2);
const [model, out] = args.filter((a, i) => !a.startsWith('--') && !(i > 0 && args[i - 1].startsWith('--')));
if (!model || !out) {
  console.error('usage: node tools/screenshot.mjs MODEL.glb OUT.jpg [--yaw DEG] [--pitch DEG] [--zoom F] ' +
    '[--target X,Y,Z] [--size WxH] [--quality Q]');
  process.exit(2);
}
const opt = (name, fallback) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : fallback; };
const view = {
  yaw: Number(opt('--yaw', 30)), pitch: Number(opt('--pitch', 15)), zoom: Number(opt('--zoom', 1)),
  target: opt('--target', '0,0,0').split(',').map(Number),
};
const [width, height] = opt('--size', '640x640').split('x').map(Number);
const quality = Number(opt('--quality', 80));

const three = join(here, 'node_modules', 'three');
const page = `<!doctype html><html><body style="margin:0;background:#fff">
<script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
const view = ${JSON.stringify(view)};
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setSize(${width}, ${height});
renderer.toneMapping = THREE.ACESFilmicToneMapping;
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xffffff);
scene.environment = new THREE.PMREMGenerator(renderer).fromScene(new RoomEnvironment(), 0.04).texture;
const gltf = await new GLTFLoader().loadAsync('/model/' + ${JSON.stringify(encodeURIComponent(basename(model)))});
scene.add(gltf.scene);
const box = new THREE.Box3().setFromObject(gltf.scene);
const size = box.getSize(new THREE.Vector3()), centre = box.getCenter(new THREE.Vector3());
const target = centre.clone().add(new THREE.Vector3(...view.target).multiply(size).multiplyScalar(0.5));
const camera = new THREE.PerspectiveCamera(35, ${width / height}, size.length() / 100, size.length() * 10);
const yaw = view.yaw * Math.PI / 180, pitch = view.pitch * Math.PI / 180;
const dir = new THREE.Vector3(Math.sin(yaw) * Math.cos(pitch), Math.sin(pitch), Math.cos(yaw) * Math.cos(pitch));
const distance = size.length() / (2 * Math.tan(35 * Math.PI / 360)) / view.zoom;
camera.position.copy(target).addScaledVector(dir, distance);
camera.lookAt(target);
renderer.render(scene, camera);
window.rendered = true;
</script></body></html>`;

const types = { '.js': 'text/javascript', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.png': 'image/png' };
const server = createServer((req, res) => {
  const url = decodeURIComponent(req.url.split('?')[0]);
  let file = null;
  if (url === '/') { res.writeHead(200, { 'content-type': 'text/html' }); res.end(page); return; }
  if (url.startsWith('/model/') && !url.includes('..')) file = join(dirname(resolve(model)), url.slice(7));
  else if (url.startsWith('/three/') && !url.includes('..')) file = join(three, url.slice(7));
  try {
    const body = readFileSync(file);
    res.writeHead(200, { 'content-type': types[file.slice(file.lastIndexOf('.'))] || 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404);
    res.end();
  }
});
await new Promise(ok => server.listen(0, '127.0.0.1', ok));
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-dev-shm-usage', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'],
});
try {
  const tab = await browser.newPage();
  const errors = [];
  tab.on('pageerror', e => errors.push(e.message));
  tab.on('console', m => { if (m.type() === 'error') errors.push(m.text()); });
  await tab.setViewport({ width, height });
  await tab.goto(`http://127.0.0.1:${server.address().port}/`, { waitUntil: 'load' });
  await tab.waitForFunction('window.rendered === true', { timeout: 120000 }).catch(() => {
    throw new Error(`not rendered: ${errors.join('; ')}`);
  });
  const png = out.toLowerCase().endsWith('.png');
  await tab.screenshot({ path: out, type: png ? 'png' : 'jpeg', ...(png ? {} : { quality }), clip: { x: 0, y: 0, width, height } });
} finally {
  await browser.close();
  server.close();
}
