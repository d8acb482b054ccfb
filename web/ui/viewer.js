// viewer.js - the input and output models side by side with one camera (turning either
// view turns both), and their UV layouts coloured per triangle by texel density or by a
// distortion metric (distortion.js computes them). Models come in as bytes (the chosen file,
// the job's result); nothing is fetched from elsewhere.
import * as THREE from './three.module.js';
import { GLTFLoader } from './three-GLTFLoader.js';
import { OrbitControls } from './three-OrbitControls.js';
import { flippedAgainst, measureDomains, texelCoordinates, texelDensity } from './distortion.js';

export class SideBySide {
  constructor(canvases) {
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
    this.views = canvases.map(canvas => {
      const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
      renderer.setPixelRatio(1);
      const scene = new THREE.Scene();
      scene.background = new THREE.Color(0xf2f2f2);
      scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 2.0));
      const sun = new THREE.DirectionalLight(0xffffff, 1.5);
      sun.position.set(1, 2, 3);
      scene.add(sun);
      const controls = new OrbitControls(this.camera, canvas);
      controls.addEventListener('change', () => this.render());
      return { canvas, renderer, scene, controls, model: null };
    });
  }

  // Shows a model (ArrayBuffer of a .glb or .gltf; files maps relative URIs to Blobs) in
  // view i; resolves to its three.js scene.
  async show(i, bytes, files = new Map()) {
    const view = this.views[i];
    const urls = [];
    const manager = new THREE.LoadingManager();
    manager.setURLModifier(url => {
      const name = decodeURIComponent(url.replace(/^.*?\/\/[^/]*\//, ''));
      const blob = files.get(url) || files.get(name);
      if (!blob) return url;
      const local = URL.createObjectURL(blob);
      urls.push(local);
      return local;
    });
    const gltf = await new Promise((ok, fail) => new GLTFLoader(manager).parse(bytes, '', ok, fail));
    urls.forEach(u => URL.revokeObjectURL(u));
    if (view.model) view.scene.remove(view.model);
    view.model = gltf.scene;
    view.scene.add(gltf.scene);
    if (i === 0 || !this.views[0].model) this.frame(gltf.scene);
    this.render();
    return gltf.scene;
  }

  frame(object) {
    const box = new THREE.Box3().setFromObject(object);
    const center = box.getCenter(new THREE.Vector3());
    const radius = box.getSize(new THREE.Vector3()).length() / 2 || 1;
    this.camera.position.copy(center).add(new THREE.Vector3(0.6, 0.4, 1).normalize().multiplyScalar(radius * 2.6));
    this.camera.near = radius / 100;
    this.camera.far = radius * 100;
    this.camera.updateProjectionMatrix();
    for (const view of this.views) {
      view.controls.target.copy(center);
      view.controls.update();
    }
  }

  render() {
    for (const view of this.views) {
      const { canvas, renderer } = view;
      const width = canvas.clientWidth || 400, height = canvas.clientHeight || 300;
      if (canvas.width !== width || canvas.height !== height) renderer.setSize(width, height, false);
      this.camera.aspect = width / height;
      this.camera.updateProjectionMatrix();
      // The other view's controls must orbit the target this one moved to.
      for (const other of this.views) if (other !== view) other.controls.target.copy(view.controls.target);
      renderer.render(view.scene, this.camera);
    }
  }
}

// The triangles of each mesh primitive with a base-colour texture, in world space:
// {positions (9 per triangle), uvs (6), texels (6: the uvs in pixels of the texture), size,
// domain (the texture's image: the primitives sharing it are one texture domain)}.
export function uvLayouts(scene) {
  const out = [];
  scene.updateMatrixWorld(true);
  scene.traverse(mesh => {
    const map = mesh.isMesh && mesh.material && mesh.material.map;
    const geometry = mesh.isMesh ? mesh.geometry : null;
    if (!map || !map.image || !geometry.attributes.uv) return;
    const size = [map.image.width, map.image.height];
    const pos = geometry.attributes.position, uv = geometry.attributes.uv;
    const index = geometry.index ? geometry.index.array : [...Array(pos.count).keys()];
    const n = Math.floor(index.length / 3);
    const positions = new Float64Array(n * 9), uvs = new Float32Array(n * 6);
    const p = new THREE.Vector3();
    for (let c = 0; c < 3 * n; c++) {
      p.fromBufferAttribute(pos, index[c]).applyMatrix4(mesh.matrixWorld).toArray(positions, 3 * c);
      uvs[2 * c] = uv.getX(index[c]);
      uvs[2 * c + 1] = uv.getY(index[c]);
    }
    const layout = { positions, uvs, size, domain: map.image };
    out.push(Object.assign(layout, { texels: texelCoordinates(layout) }));
  });
  return out;
}

// Adds to the input's and the output's layouts their texel densities, the singular values
// of their distortion and, where the triangles pair up, the output's flips against the input.
export function measureLayouts(before, after) {
  for (const layout of [...before, ...after]) layout.density = texelDensity(layout);
  measureDomains(before);
  measureDomains(after);
  if (before.length === after.length) after.forEach((layout, i) => { layout.flipped = flippedAgainst(layout, before[i]); });
}

export function medianDensity(layouts) {
  const all = layouts.flatMap(l => [...l.density].filter(d => d > 0)).sort((a, b) => a - b);
  return all.length ? all[all.length >> 1] : 1;
}

// White at `reference`, red at 8x it or more, blue at 1/8 of it or less (log scale between).
export function heatColour(value, reference) {
  const x = Math.max(-1, Math.min(1, Math.log2(value / reference) / 3));
  const toWhite = 1 - Math.abs(x);
  const r = x > 0 ? 255 : Math.round(255 * toWhite), b = x < 0 ? 255 : Math.round(255 * toWhite);
  return `rgb(${r},${Math.round(255 * toWhite)},${b})`;
}

// The colour of a flipped or degenerate triangle, which has no metric.
export const FLAGGED_COLOUR = 'rgb(0,200,0)';

// Colours a triangle by its texel density against `reference` (the input's median).
export function densityColours(reference) {
  return (layout, t) => heatColour(layout.density[t], reference);
}

// Colours a triangle by `metric` (distortion.js METRICS) against its minimum, the isometry's.
export function metricColours(metric) {
  return (layout, t) => layout.degenerate[t] || (layout.flipped && layout.flipped[t]) ? FLAGGED_COLOUR
    : heatColour(metric.of(layout.sigmaMax[t], layout.sigmaMin[t]), metric.minimum);
}

// Draws the UV layouts (uv (0,0) at the top left, as glTF's images) on canvas, each
// triangle in colourOf(layout, triangle).
export function drawHeatMap(canvas, layouts, colourOf) {
  const ctx = canvas.getContext('2d');
  const w = canvas.width, h = canvas.height;
  ctx.fillStyle = '#333';
  ctx.fillRect(0, 0, w, h);
  for (const layout of layouts) {
    for (let t = 0; t < layout.uvs.length / 6; t++) {
      const u = layout.uvs.subarray(6 * t, 6 * t + 6);
      ctx.fillStyle = colourOf(layout, t);
      ctx.beginPath();
      ctx.moveTo(u[0] * w, u[1] * h);
      ctx.lineTo(u[2] * w, u[3] * h);
      ctx.lineTo(u[4] * w, u[5] * h);
      ctx.closePath();
      ctx.fill();
    }
  }
}
