// page_distortion.mjs - the page's distortion metrics (web/ui/distortion.js) on triangles
// with known answers, run by page_distortion.sh: each metric of an isometry is its minimum,
// a stretch by 2 and a shear give the values of the formulas of engine/param/distortion.h,
// the uniform scale per domain makes a 3x layout isometric, degenerate triangles are left
// out, flips are judged against the input's orientation, and the texel density is texel
// area over 3D area.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

// Imported as .mjs: an older node does not detect the module syntax of a .js file.
const dir = mkdtempSync(join(tmpdir(), 'texopt-distortion-'));
const copy = join(dir, 'distortion.mjs');
copyFileSync(join(process.env.TEXOPT_SOURCE_DIR, 'web', 'ui', 'distortion.js'), copy);
const { METRICS, layoutSingularValues, measureDomains, flippedAgainst, texelCoordinates, texelDensity } =
  await import(pathToFileURL(copy).href);
rmSync(dir, { recursive: true, force: true });

let failures = 0;
function near(actual, expected, what, tolerance = 1e-9) {
  const ok = Math.abs(actual - expected) <= tolerance * Math.max(1, Math.abs(expected));
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}: ${actual} (expected ${expected})`);
  if (!ok) failures++;
}
function same(actual, expected, what) {
  const ok = JSON.stringify(actual) === JSON.stringify(expected);
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}: ${JSON.stringify(actual)} (expected ${JSON.stringify(expected)})`);
  if (!ok) failures++;
}

// The 3D triangle: the plane points (x, y) rotated out of the xy plane and moved, so the
// plane frame is not the axes.
function onTiltedPlane(points) {
  const [c, s] = [Math.cos(0.7), Math.sin(0.7)];
  return Float64Array.from(points.flatMap(([x, y]) => [x * c - y * 0.6 * s + 3, y * 0.8 - 1, x * s + y * 0.6 * c + 2]));
}
const RIGHT = [[0, 0], [2, 0], [0, 1]]; // a right triangle of area 1 in its plane
// A layout of triangles: the 3D triangles and each corner's texel position, in one domain.
function layout(surfaces, texelTriangles, domain = 'one', size = [4, 4]) {
  const uvs = Float32Array.from(texelTriangles.flat(2), (x, i) => x / size[i % 2]);
  const positions = Float64Array.from(surfaces.flatMap(points => [...onTiltedPlane(points)]));
  const l = { positions, uvs, size, domain };
  return Object.assign(l, { texels: texelCoordinates(l) });
}
const metrics = (l, t) => Object.fromEntries(METRICS.map(m => [m.key, m.of(l.sigmaMax[t], l.sigmaMin[t])]));
const byKey = key => METRICS.find(m => m.key === key);

// An isometry: every metric at its minimum, the minima of distortion.h (1, 2, sqrt 2, 1, 1, 4, 1, 1).
const minima = { conformal: 1, mips: 2, isometric: Math.SQRT2, max_isometric: 1, area: 1, symmetric_dirichlet: 4,
  l2_stretch: 1, linf_stretch: 1 };
same(METRICS.map(m => m.key), Object.keys(minima), 'the metrics of distortion.h');
const iso = layout([RIGHT], [RIGHT]);
Object.assign(iso, layoutSingularValues(iso, 1));
for (const [key, value] of Object.entries(metrics(iso, 0))) {
  near(value, minima[key], `isometric triangle: ${key}`);
  near(byKey(key).minimum, minima[key], `minimum of ${key}`);
}

// Stretched by 2 along the plane's x, unscaled: singular values 2 and 1.
const stretched = layout([RIGHT], [[[0, 0], [4, 0], [0, 1]]]);
Object.assign(stretched, layoutSingularValues(stretched, 1));
near(stretched.sigmaMax[0], 2, 'stretch by 2: smax');
near(stretched.sigmaMin[0], 1, 'stretch by 2: smin');
const s2 = { conformal: 2, mips: 2.5, isometric: Math.sqrt(5), max_isometric: 2, area: 2,
  symmetric_dirichlet: 4 + 1 + 1 / 4 + 1, l2_stretch: Math.sqrt((1 + 1 / 4) / 2), linf_stretch: 1 };
for (const [key, value] of Object.entries(metrics(stretched, 0))) near(value, s2[key], `stretch by 2: ${key}`);

// The same stretch measured through its domain: scaled by 1/sqrt 2 to keep the area,
// singular values sqrt 2 and 1/sqrt 2.
const stretchedDomain = layout([RIGHT], [[[0, 0], [4, 0], [0, 1]]]);
measureDomains([stretchedDomain]);
const s2n = { conformal: 2, mips: 2.5, isometric: 2, max_isometric: Math.SQRT2, area: 1,
  symmetric_dirichlet: 2 + 0.5 + 0.5 + 2, l2_stretch: Math.sqrt(1.25), linf_stretch: Math.SQRT2 };
for (const [key, value] of Object.entries(metrics(stretchedDomain, 0)))
  near(value, s2n[key], `stretch by 2, area kept: ${key}`);

// A shear J = [[1, 1], [0, 1]]: singular values the golden ratio and its inverse.
const phi = (1 + Math.sqrt(5)) / 2;
const sheared = layout([RIGHT], [[[0, 0], [2, 0], [1, 1]]]);
Object.assign(sheared, layoutSingularValues(sheared, 1));
near(sheared.sigmaMax[0], phi, 'shear: smax');
near(sheared.sigmaMin[0], 1 / phi, 'shear: smin');
near(metrics(sheared, 0).symmetric_dirichlet, 3 + 3, 'shear: symmetric Dirichlet |J|^2 + |J^-1|^2');

// A layout 3x the surface (a change of resolution), mirrored, on a non-square texture:
// isometric after the domain's scale.
const tripled = layout([RIGHT, [[0, 0], [1, 0], [1, 1]]], [[[0, 0], [-6, 0], [0, 3]], [[0, 0], [-3, 0], [-3, 3]]],
  'one', [8, 2]);
same([...tripled.uvs.slice(0, 6)], [0, 0, -0.75, 0, 0, 1.5], 'uvs of a non-square texture');
same([...tripled.texels.slice(0, 6)], [0, 0, -6, 0, 0, 3], 'texel coordinates are the uvs times the texture size');
measureDomains([tripled]);
for (const t of [0, 1])
  for (const [key, value] of Object.entries(metrics(tripled, t))) near(value, minima[key], `3x layout, triangle ${t}: ${key}`);

// Two layouts of one domain share its scale; of two domains, each has its own.
const single = layout([RIGHT], [RIGHT], 'a'), triple = layout([RIGHT], [RIGHT.map(([x, y]) => [3 * x, 3 * y])], 'b');
measureDomains([single, triple]);
near(metrics(single, 0).area, 1, 'own domain at 1x: area 1');
near(metrics(triple, 0).area, 1, 'own domain at 3x: area 1');
triple.domain = 'a';
measureDomains([single, triple]);
// Scale^2 = 2 / (1 + 9): area distortion 10/2 = 5 for the first, 9/5 for the second.
near(metrics(single, 0).area, 5, 'one domain, 1x and 3x: the 1x triangle has area distortion 5');
near(metrics(triple, 0).area, 9 / 5, 'one domain, 1x and 3x: the 3x triangle 9/5');

// Degenerate triangles (flat in 3D, or in texels) are flagged and do not enter the scale.
const withDegenerate = layout([RIGHT, [[0, 0], [1, 0], [2, 0]], RIGHT],
  [RIGHT, [[0, 0], [40, 0], [0, 40]], [[0, 0], [1, 1], [2, 2]]]);
measureDomains([withDegenerate]);
same([...withDegenerate.degenerate], [0, 1, 1], 'flat in 3D and flat in texels are degenerate');
near(metrics(withDegenerate, 0).area, 1, 'the degenerate triangles leave the scale alone');
same([...texelDensity(withDegenerate)], [1, 0, 0], 'texel density: 1 texel per unit, none on a flat triangle');
same([...texelDensity(triple)], [9], 'texel density of a layout 3x the surface: 9');
const sliver = layout([RIGHT], [[[0, 0], [1e6, 0], [0, 1e-5]]]);
same([...layoutSingularValues(sliver, 1).degenerate], [1], 'a sliver below 1e-10 of its length squared is degenerate');

// Flips against the input: a triangle turned over is flipped; a chart mirrored in both is not.
const input = layout([RIGHT, RIGHT], [RIGHT, [[0, 0], [-2, 0], [0, 1]]]);
const output = layout([RIGHT, RIGHT], [[[0, 0], [-2, 0], [0, 1]], [[0, 0], [-2, 0], [0, 1]]]);
same([...flippedAgainst(output, input)], [1, 0], 'flipped against the input orientation');
same(flippedAgainst(layout([RIGHT], [RIGHT]), input), null, 'no pairing when the triangle counts differ');

if (failures) {
  console.log(`page_distortion: ${failures} check(s) failed`);
  process.exit(1);
}
console.log('page_distortion: ok');
