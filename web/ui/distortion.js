// distortion.js - the distortion metrics of the parameterization lecture for a UV layout, per
// triangle, with the definitions of engine/param/distortion.h: each a function of the
// singular values smax >= smin of the Jacobian from the triangle in its 3D plane to texel
// space, after one uniform scale per texture domain makes the domain's texel area equal its
// 3D area (a change of resolution is no distortion). Triangles degenerate in 3D or in texels
// (mesh.h's relative test) are left out of the scale and have no metric. Also each
// triangle's texel density. Pure functions over plain arrays, no three.js and no drawing
// (viewer.js draws), so node can test them.

// Each metric of (smax, smin); `minimum` is its value for an isometry, the least it takes.
export const METRICS = [
  { key: 'conformal', name: 'conformal (angle)', formula: 'σmax/σmin', minimum: 1, of: (a, b) => a / b },
  { key: 'mips', name: 'MIPS', formula: 'σmax/σmin + σmin/σmax', minimum: 2, of: (a, b) => a / b + b / a },
  { key: 'isometric', name: 'isometric', formula: '√(σmax² + 1/σmin²)', minimum: Math.SQRT2,
    of: (a, b) => Math.sqrt(a * a + 1 / (b * b)) },
  { key: 'max_isometric', name: 'max isometric', formula: 'max(σmax, 1/σmin)', minimum: 1,
    of: (a, b) => Math.max(a, 1 / b) },
  { key: 'area', name: 'area', formula: 'max(σmax σmin, 1/(σmax σmin))', minimum: 1,
    of: (a, b) => Math.max(a * b, 1 / (a * b)) },
  { key: 'symmetric_dirichlet', name: 'symmetric Dirichlet', formula: 'σmax² + σmin² + 1/σmax² + 1/σmin²', minimum: 4,
    of: (a, b) => a * a + b * b + 1 / (a * a) + 1 / (b * b) },
  { key: 'l2_stretch', name: 'L2 stretch', formula: '√((1/σmin² + 1/σmax²) / 2)', minimum: 1,
    of: (a, b) => Math.sqrt((1 / (b * b) + 1 / (a * a)) / 2) },
  { key: 'linf_stretch', name: 'L∞ stretch', formula: '1/σmin', minimum: 1, of: (a, b) => 1 / b },
];

const DEGENERATE_RELATIVE = 1e-10; // engine/model/mesh.c

// mesh.h's test: doubled area at most 1e-10 times the longest edge squared.
function isDegenerate(doubledArea, edgesSquared) {
  return doubledArea <= DEGENERATE_RELATIVE * Math.max(...edgesSquared);
}

// Triangle t of 3D positions p (9 per triangle): its edges from corner 0 and doubled area.
function surfaceTriangle(p, t) {
  const o = 9 * t;
  const e1 = [p[o + 3] - p[o], p[o + 4] - p[o + 1], p[o + 5] - p[o + 2]];
  const e2 = [p[o + 6] - p[o], p[o + 7] - p[o + 1], p[o + 8] - p[o + 2]];
  const n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
  const doubled = Math.hypot(...n);
  const e3 = [e2[0] - e1[0], e2[1] - e1[1], e2[2] - e1[2]];
  const sq = e => e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  return { e1, e2, doubled, degenerate: isDegenerate(doubled, [sq(e1), sq(e2), sq(e3)]) };
}

// Triangle t of texel coordinates x (6 per triangle): its edges from corner 0 as the
// columns of T, and its doubled signed area.
function texelTriangle(x, t) {
  const o = 6 * t;
  const T = [[x[o + 2] - x[o], x[o + 4] - x[o]], [x[o + 3] - x[o + 1], x[o + 5] - x[o + 1]]];
  const signed = T[0][0] * T[1][1] - T[0][1] * T[1][0];
  const sq = (u, v) => u * u + v * v;
  const edges = [sq(T[0][0], T[1][0]), sq(T[0][1], T[1][1]), sq(T[0][1] - T[0][0], T[1][1] - T[1][0])];
  return { T, signed, degenerate: isDegenerate(Math.abs(signed), edges) };
}

// The texel coordinates of a layout {uvs (6 per triangle), size [width, height]}.
export function texelCoordinates({ uvs, size }) {
  return Float64Array.from(uvs, (u, i) => u * size[i % 2]);
}

// Texels per unit of surface of each triangle of a layout {positions, texels} (0 for no surface).
export function texelDensity({ positions, texels }) {
  const density = new Float64Array(texels.length / 6);
  for (let t = 0; t < density.length; t++) {
    const doubled = surfaceTriangle(positions, t).doubled;
    density[t] = doubled > 0 ? Math.abs(texelTriangle(texels, t).signed) / doubled : 0;
  }
  return density;
}

// Singular values [smax, smin] of J = scale T P^-1, P the 3D edges in an orthonormal frame
// of their plane; |det J|, as the plane has no orientation relative to texel space.
function singularValues(surface, T, scale) {
  const { e1, e2, doubled } = surface;
  const l1 = Math.hypot(...e1);
  const along = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) / l1;
  const height = doubled / l1;
  // P = [[l1, along], [0, height]]; its inverse is [[1/l1, -along/(l1 height)], [0, 1/height]].
  const J = T.map(([a, b]) => [scale * a / l1, scale * (b - a * along / l1) / height]);
  const frob = J[0][0] ** 2 + J[0][1] ** 2 + J[1][0] ** 2 + J[1][1] ** 2;
  const det = Math.abs(J[0][0] * J[1][1] - J[0][1] * J[1][0]);
  const smax = Math.sqrt(0.5 * (frob + Math.sqrt(Math.max(0, frob * frob - 4 * det * det))));
  return [smax, det / smax];
}

// The uniform scale of one domain's layouts (each {positions, texels}) making their counted
// texel area equal their counted 3D area; 1 when nothing counts.
function domainScale(layouts) {
  let area3d = 0, areaTexel = 0;
  for (const { positions, texels } of layouts) {
    for (let t = 0; t < texels.length / 6; t++) {
      const surface = surfaceTriangle(positions, t), texel = texelTriangle(texels, t);
      if (surface.degenerate || texel.degenerate) continue;
      area3d += surface.doubled;
      areaTexel += Math.abs(texel.signed);
    }
  }
  return areaTexel > 0 && area3d > 0 ? Math.sqrt(area3d / areaTexel) : 1;
}

// Singular values of each triangle of a layout {positions, texels} at `scale`:
// {sigmaMax, sigmaMin, degenerate (1 per triangle: left out, no metric)}.
export function layoutSingularValues({ positions, texels }, scale) {
  const n = texels.length / 6;
  const sigmaMax = new Float64Array(n), sigmaMin = new Float64Array(n), degenerate = new Uint8Array(n);
  for (let t = 0; t < n; t++) {
    const surface = surfaceTriangle(positions, t), texel = texelTriangle(texels, t);
    degenerate[t] = surface.degenerate || texel.degenerate;
    if (!degenerate[t]) [sigmaMax[t], sigmaMin[t]] = singularValues(surface, texel.T, scale);
  }
  return { sigmaMax, sigmaMin, degenerate };
}

// Adds the singular values to each layout {positions, texels, domain}, scaled per domain
// (layouts with one `domain` key are measured as one).
export function measureDomains(layouts) {
  const domains = new Map();
  for (const layout of layouts) {
    if (!domains.has(layout.domain)) domains.set(layout.domain, []);
    domains.get(layout.domain).push(layout);
  }
  for (const members of domains.values()) {
    const scale = domainScale(members);
    for (const layout of members) Object.assign(layout, layoutSingularValues(layout, scale));
  }
}

// Per triangle of `layout`, 1 where its texel orientation is not that of the same triangle in
// `input` (distortion.h's flip: det grad_phi <= 0 against the input). Null when the two do
// not have the same number of triangles, so the triangles cannot be paired.
export function flippedAgainst(layout, input) {
  const n = layout.texels.length / 6;
  if (input.texels.length / 6 !== n) return null;
  const flipped = new Uint8Array(n);
  for (let t = 0; t < n; t++)
    flipped[t] = !(texelTriangle(layout.texels, t).signed / texelTriangle(input.texels, t).signed > 0);
  return flipped;
}
