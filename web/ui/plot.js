// plot.js - the whole-mesh loss q against relative cost of evaluated jobs, one series per
// method, as SVG (the report of one job holds its own plot; this one spans jobs).
const COLOURS = ['#2a6fdb', '#d9480f', '#2b8a3e', '#862e9c', '#495057'];
const NS = 'http://www.w3.org/2000/svg';

function element(name, attrs, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.append(e);
  return e;
}

// points: [{method, cost, q, current}]; draws into svg (viewBox 0 0 480 260).
export function drawQCost(svg, points) {
  svg.textContent = '';
  svg.setAttribute('viewBox', '0 0 480 260');
  const left = 56, right = 450, top = 10, bottom = 220;
  const costMax = Math.max(1, ...points.map(p => p.cost)), qMax = Math.max(...points.map(p => p.q)) * 1.1 || 1;
  const x = c => left + (right - left) * c / costMax, y = q => bottom - (bottom - top) * q / qMax;
  element('line', { x1: left, y1: bottom, x2: right, y2: bottom, stroke: '#888' }, svg);
  element('line', { x1: left, y1: top, x2: left, y2: bottom, stroke: '#888' }, svg);
  for (let i = 0; i <= 4; i++) {
    element('text', { x: x(costMax * i / 4), y: bottom + 16, 'text-anchor': 'middle', 'font-size': 11 }, svg).textContent = (costMax * i / 4).toFixed(2);
    element('text', { x: left - 4, y: y(qMax * i / 4) + 4, 'text-anchor': 'end', 'font-size': 11 }, svg).textContent = (qMax * i / 4).toFixed(3);
  }
  element('text', { x: (left + right) / 2, y: 252, 'text-anchor': 'middle', 'font-size': 12 }, svg).textContent = 'relative cost (covered texels, output / input)';
  element('text', { x: 12, y: 120, 'font-size': 12, transform: 'rotate(-90 12 120)', 'text-anchor': 'middle' }, svg).textContent = 'q';
  const methods = [...new Set(points.map(p => p.method))];
  methods.forEach((method, i) => {
    const series = points.filter(p => p.method === method).sort((a, b) => a.cost - b.cost);
    const colour = COLOURS[i % COLOURS.length];
    if (series.length > 1)
      element('polyline', { points: series.map(p => `${x(p.cost)},${y(p.q)}`).join(' '), fill: 'none', stroke: colour }, svg);
    for (const p of series)
      element('circle', { cx: x(p.cost), cy: y(p.q), r: p.current ? 5 : 3, fill: colour, class: 'point' }, svg);
    element('text', { x: right - 4, y: top + 14 + 14 * i, 'text-anchor': 'end', fill: colour, 'font-size': 12 }, svg).textContent = method;
  });
}
