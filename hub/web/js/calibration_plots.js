// Plots of a wand calibration as SVG, from the figures JSON the hub writes (calib/wand_report.h):
// the per-camera table with ratings, residuals per camera, coverage maps, the wand-length error
// histogram and the camera layout from above and from the side; and the coverage map the
// console's calibration page shows while the wand is waved. No imports: the hub embeds this file
// in its self-contained report page (calibrate wand --report), and the console imports it.

const SVG = 'http://www.w3.org/2000/svg';
const RATING_COLOURS = {
  Exceptional: '#1a7f37', Excellent: '#4c9a2a', Good: '#9a8a00', Fair: '#c76b00', Poor: '#c62828',
};
const RATINGS = ['Exceptional', 'Excellent', 'Good', 'Fair'];

function svgEl(tag, attrs = {}, text) {
  const node = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (text !== undefined) node.textContent = text;
  return node;
}

function htmlEl(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'text') node.textContent = v;
    else node.setAttribute(k, v);
  }
  for (const c of children) node.append(c);
  return node;
}

function fixed(value, digits) {
  return value === null || value === undefined || Number.isNaN(value) ? '–' : Number(value).toFixed(digits);
}

// Red (none) through yellow to green (full or more).
export function coverageColour(count, full) {
  const f = Math.max(0, Math.min(1, count / Math.max(full, 1)));
  return `hsl(${Math.round(120 * f)}, 70%, ${count > 0 ? 45 : 40}%)`;
}

// A camera's image as a grid of cells coloured by sightings; counts row-major from the top left.
export function coverageMap(counts, columns, rows, full, width = 160) {
  const height = Math.round(width * rows / columns);
  const svg = svgEl('svg', { width, height, viewBox: `0 0 ${columns} ${rows}`, class: 'coverage-map',
    'data-plot': 'coverage' });
  counts.forEach((n, i) => {
    const cell = svgEl('rect', { x: i % columns, y: Math.floor(i / columns), width: 0.94, height: 0.94,
      fill: coverageColour(n, full), 'data-count': n, class: n >= full ? 'cell covered' : 'cell' });
    cell.append(svgEl('title', {}, `${n}`));
    svg.append(cell);
  });
  return svg;
}

// Axes with ticks around a plot area; returns the mapping functions.
function axes(svg, box, xRange, yRange, xLabel, yLabel) {
  const [x0, x1] = xRange;
  const [y0, y1] = yRange;
  const sx = (v) => box.left + (v - x0) / (x1 - x0 || 1) * (box.width);
  const sy = (v) => box.top + box.height - (v - y0) / (y1 - y0 || 1) * (box.height);
  svg.append(svgEl('rect', { x: box.left, y: box.top, width: box.width, height: box.height, fill: 'none',
    stroke: '#9aa5b1' }));
  for (let i = 0; i <= 4; i += 1) {
    const xv = x0 + (x1 - x0) * i / 4;
    const yv = y0 + (y1 - y0) * i / 4;
    svg.append(svgEl('text', { x: sx(xv), y: box.top + box.height + 14, 'text-anchor': 'middle',
      'font-size': 10 }, niceLabel(xv)));
    svg.append(svgEl('text', { x: box.left - 4, y: sy(yv) + 3, 'text-anchor': 'end', 'font-size': 10 },
      niceLabel(yv)));
  }
  svg.append(svgEl('text', { x: box.left + box.width / 2, y: box.top + box.height + 28, 'text-anchor': 'middle',
    'font-size': 11 }, xLabel));
  svg.append(svgEl('text', { x: 12, y: box.top + box.height / 2, 'text-anchor': 'middle', 'font-size': 11,
    transform: `rotate(-90 12 ${box.top + box.height / 2})` }, yLabel));
  return { sx, sy };
}

function niceLabel(v) {
  const a = Math.abs(v);
  if (a < 1e-9) return '0';
  if (a >= 100) return v.toFixed(0);
  if (a >= 1) return v.toFixed(1);
  return v.toFixed(a >= 0.1 ? 2 : 3);
}

function figure(caption, plot, name) {
  plot.setAttribute('data-plot', name);
  return htmlEl('figure', { class: 'plot', 'data-plot': name }, htmlEl('figcaption', { text: caption }), plot);
}

// Reprojection RMS and p95 per camera, with the rating limits as dashed lines.
function residualPlot(f) {
  const cams = f.cameras;
  const w = Math.max(320, 60 + 40 * cams.length);
  const h = 240;
  const svg = svgEl('svg', { width: w, height: h });
  const top = Math.max(...cams.map((c) => c.residuals ? c.residuals.p95_px : 0),
    ...cams.map((c) => c.reprojection_rms_px || 0), f.rating_thresholds.reprojection_rms_px.Good) * 1.1;
  const box = { left: 50, top: 10, width: w - 60, height: h - 50 };
  const { sx, sy } = axes(svg, box, [0, cams.length], [0, top], 'camera (bars labelled with the id)', 'px');
  cams.forEach((c, i) => {
    const rms = c.reprojection_rms_px || 0;
    svg.append(svgEl('rect', { x: sx(i + 0.2), y: sy(rms), width: sx(i + 0.8) - sx(i + 0.2), height: sy(0) - sy(rms),
      fill: RATING_COLOURS[c.rating] || '#888', class: 'bar' }));
    if (c.residuals) {
      svg.append(svgEl('line', { x1: sx(i + 0.15), x2: sx(i + 0.85), y1: sy(c.residuals.p95_px),
        y2: sy(c.residuals.p95_px), stroke: '#1d232a', 'stroke-width': 2 }));
    }
    svg.append(svgEl('text', { x: sx(i + 0.5), y: sy(rms) - 3, 'text-anchor': 'middle', 'font-size': 10 },
      `${c.id}`));
  });
  for (const name of RATINGS) {
    const v = f.rating_thresholds.reprojection_rms_px[name];
    if (v > top) continue;
    svg.append(svgEl('line', { x1: box.left, x2: box.left + box.width, y1: sy(v), y2: sy(v),
      stroke: RATING_COLOURS[name], 'stroke-dasharray': '4 3' }));
    svg.append(svgEl('text', { x: box.left + box.width - 2, y: sy(v) - 2, 'text-anchor': 'end', 'font-size': 9,
      fill: RATING_COLOURS[name] }, name));
  }
  return figure('Reprojection error per camera: RMS (bar, labelled with the camera id) and 95th percentile (line)',
    svg, 'residuals');
}

function histogramPlot(hist, caption, xLabel, name) {
  const w = 420;
  const h = 220;
  const svg = svgEl('svg', { width: w, height: h });
  const counts = hist.counts;
  const end = hist.start + hist.bin * counts.length;
  const box = { left: 50, top: 10, width: w - 60, height: h - 50 };
  const { sx, sy } = axes(svg, box, [hist.start, end], [0, Math.max(1, ...counts)], xLabel, 'frames');
  counts.forEach((n, i) => {
    const x = hist.start + i * hist.bin;
    svg.append(svgEl('rect', { x: sx(x), y: sy(n), width: Math.max(0.5, sx(x + hist.bin) - sx(x) - 0.5),
      height: sy(0) - sy(n), fill: '#3f72af', class: 'bar' }));
  });
  return figure(caption, svg, name);
}

// Cameras (dot + viewing direction) and the wand's path, projected on two axes of the plot frame.
function layoutPlot(f, a, b, caption, name) {
  const w = 420;
  const h = 320;
  const svg = svgEl('svg', { width: w, height: h });
  const cams = f.cameras.filter((c) => c.position);
  const points = cams.map((c) => c.position).concat(f.layout.wand_centres);
  if (points.length === 0) return figure(caption, svg, name);
  const lo = [0, 1, 2].map((k) => Math.min(...points.map((p) => p[k])));
  const hi = [0, 1, 2].map((k) => Math.max(...points.map((p) => p[k])));
  // Same scale on both axes.
  const span = Math.max(hi[a] - lo[a], hi[b] - lo[b], 1) * 1.1;
  const ca = (lo[a] + hi[a]) / 2;
  const cb = (lo[b] + hi[b]) / 2;
  const box = { left: 60, top: 10, width: h - 50, height: h - 50 };
  const { sx, sy } = axes(svg, box, [ca - span / 2, ca + span / 2], [cb - span / 2, cb + span / 2],
    `${'xyz'[a]} mm`, `${'xyz'[b]} mm`);
  for (const p of f.layout.wand_centres) {
    svg.append(svgEl('circle', { cx: sx(p[a]), cy: sy(p[b]), r: 1.2, fill: '#b8c2cc', class: 'wand' }));
  }
  for (const c of cams) {
    const p = c.position;
    const d = c.direction;
    const reach = span * 0.12;
    svg.append(svgEl('line', { x1: sx(p[a]), y1: sy(p[b]), x2: sx(p[a] + d[a] * reach), y2: sy(p[b] + d[b] * reach),
      stroke: RATING_COLOURS[c.rating] || '#888', 'stroke-width': 2 }));
    svg.append(svgEl('circle', { cx: sx(p[a]), cy: sy(p[b]), r: 4, fill: RATING_COLOURS[c.rating] || '#888',
      class: 'camera' }));
    svg.append(svgEl('text', { x: sx(p[a]) + 6, y: sy(p[b]) - 6, 'font-size': 10 }, `${c.id}`));
  }
  return figure(caption, svg, name);
}

function cameraTable(f) {
  const head = ['Camera', 'Rating', 'RMS px', 'p95 px', 'Wand length RMS mm', 'Coverage', 'Views used / found',
    'Status'];
  const rows = f.cameras.map((c) => htmlEl('tr', { 'data-camera-id': c.id },
    htmlEl('td', { text: c.id }),
    htmlEl('td', { text: c.rating, style: `color: ${RATING_COLOURS[c.rating] || '#888'}; font-weight: 600`,
      class: 'rating' }),
    htmlEl('td', { text: fixed(c.reprojection_rms_px, 3) }),
    htmlEl('td', { text: c.residuals ? fixed(c.residuals.p95_px, 3) : '–' }),
    htmlEl('td', { text: fixed(c.wand_length_error.rms_mm, 3) }),
    htmlEl('td', { text: `${fixed(100 * c.coverage, 0)} %` }),
    htmlEl('td', { text: `${c.views_used} / ${c.views_selected}` }),
    htmlEl('td', { text: c.accepted ? 'accepted' : `refused: ${c.reason}` })));
  return htmlEl('table', { class: 'report-cameras' },
    htmlEl('thead', {}, htmlEl('tr', {}, ...head.map((t) => htmlEl('th', { text: t })))),
    htmlEl('tbody', {}, ...rows));
}

function thresholdText(t) {
  const part = (limits, unit) => RATINGS.map((n) => `${n} ≤ ${limits[n]} ${unit}`).join(', ');
  return `Ratings: reprojection RMS ${part(t.reprojection_rms_px, 'px')}; wand length RMS ` +
    `${part(t.wand_length_rms_mm, 'mm')}; above Fair is Poor; the worse figure decides; a refused camera is Poor.`;
}

// The whole report into root (an element), from the figures JSON.
export function renderWandReport(root, f) {
  const w = f.wand_length_error;
  const accepted = f.cameras.filter((c) => c.accepted).length;
  const maps = htmlEl('div', { class: 'plots coverage-maps' }, ...f.cameras.map((c) => htmlEl('figure',
    { 'data-camera-id': c.id },
    htmlEl('figcaption', { text: `camera ${c.id}: ${fixed(100 * c.coverage, 0)} %` }),
    coverageMap(c.coverage_map.counts, c.coverage_map.columns, c.coverage_map.rows, 1, 120))));
  root.replaceChildren(
    htmlEl('h1', { text: `Wand calibration: ${f.title}` }),
    htmlEl('p', { class: 'summary', text: `${accepted}/${f.cameras.length} cameras accepted · rating ${f.rating} · ` +
      `reprojection RMS ${fixed(f.reprojection_rms_px, 3)} px · wand ${fixed(f.wand_length_mm, 1)} mm, length ` +
      `error RMS ${fixed(w.rms_mm, 3)} mm (p95 ${fixed(w.p95_abs_mm, 3)} mm) over ${w.frames} frames · ` +
      `${f.frames_used} of ${f.frames} frames used · reference camera ${f.reference_camera}` }),
    cameraTable(f),
    htmlEl('p', { class: 'thresholds', text: thresholdText(f.rating_thresholds) }),
    htmlEl('div', { class: 'plots' },
      residualPlot(f),
      histogramPlot(f.wand_length_histogram, 'Wand length error (triangulated minus true), all used frames',
        'mm', 'wand-length'),
      layoutPlot(f, 0, 1, 'Camera layout from above (grey: the wand\u2019s path)', 'layout-top'),
      layoutPlot(f, 0, 2, 'Camera layout from the side', 'layout-side')),
    htmlEl('h2', { text: 'Coverage: where each camera saw the wand (green: seen, red: never)' }),
    maps);
}
