// The calibration page's wanding panel: start a live wanding in serve (POST
// /api/calibration/wand/start), then per camera its wand samples, a coverage map over its image
// (cells turning from red to green as the wand is seen there) and what to do next, polled from
// GET /api/calibration/wand; stop, cancel, solve again and apply; once solved, the report's plots
// from the session's wand_figures.json (the same module draws `calibrate wand --report`).
// The mode picks the wand or a single marker waved (then a bar of two markers shown for the
// scale, its length in the length field): the single marker's solve has no report plots, its
// figures per camera are shown instead.
import { ApiError, el, formatNumber, getJson, postJson } from './api.js';
import { coverageMap, renderWandReport } from './calibration_plots.js';

const POLL_MS = 500;

export class WandingPanel {
  constructor(root, onApplied) {
    this.onApplied = onApplied;
    this.active = false;
    this.timer = null;
    this.reportKey = null;
    const number = (id, value, min, max, step) => el('input', { type: 'number', id, value, min, max, step });
    this.name = el('input', { type: 'text', id: 'wand-name', value: '', size: 18, placeholder: 'session name' });
    this.mode = el('select', { id: 'wand-mode', onchange: () => this.modeChanged() },
      el('option', { value: 'wand', text: 'wand' }),
      el('option', { value: 'single-marker', text: 'single marker, then scale bar' }));
    this.lengthLabel = el('label', { text: 'wand mm' });
    this.length = number('wand-length', 500, 10, 5000, 1);
    this.samples = number('wand-min-samples', 300, 10, 1000000, 10);
    this.coverage = number('wand-coverage', 40, 5, 100, 5);
    this.timeout = number('wand-timeout', 300, 1, 3600, 10);
    this.message = el('span', { class: 'message', id: 'wand-message' });
    this.stateLine = el('div', { class: 'caption', id: 'wanding-state' });
    this.cameras = el('div', { class: 'wand-cameras', id: 'wanding-cameras' });
    this.report = el('div', { class: 'wand-report', id: 'wand-report' });
    this.startButton = el('button', { id: 'wand-start', text: 'Start wanding', onclick: () => this.start() });
    this.stopButton = el('button', { id: 'wand-stop', text: 'Stop and solve',
      onclick: () => this.act('/api/calibration/wand/stop', { solve: true }) });
    this.cancelButton = el('button', { id: 'wand-cancel', text: 'Cancel',
      onclick: () => this.act('/api/calibration/wand/stop', { solve: false }) });
    this.solveButton = el('button', { id: 'wand-solve', text: 'Solve again',
      onclick: () => this.act('/api/calibration/wand/solve', {}) });
    this.applyButton = el('button', { id: 'wand-apply', text: 'Apply to the live view',
      onclick: () => this.act('/api/calibration/wand/apply', { save: false }) });
    this.saveButton = el('button', { id: 'wand-save', text: 'Apply and save',
      onclick: () => this.act('/api/calibration/wand/apply', { save: true }) });
    root.append(el('h2', { text: 'Wanding' }),
      el('div', { class: 'toolbar' },
        this.name, this.mode, this.lengthLabel, this.length,
        el('label', { text: 'samples per camera' }), this.samples,
        el('label', { text: 'coverage %' }), this.coverage,
        el('label', { text: 'timeout s' }), this.timeout,
        this.startButton, this.stopButton, this.cancelButton, this.solveButton, this.applyButton, this.saveButton,
        this.message),
      this.stateLine, this.cameras, this.report);
  }

  modeChanged() {
    this.lengthLabel.textContent = this.mode.value === 'single-marker' ? 'scale bar mm' : 'wand mm';
  }

  async start() {
    const name = this.name.value.trim() || `wand-${new Date().toISOString().slice(0, 19).replace(/[-:T]/g, '')}`;
    this.name.value = name;
    await this.act('/api/calibration/wand/start', {
      name,
      mode: this.mode.value,
      wand_length_mm: Number(this.length.value),
      min_samples: Number(this.samples.value),
      coverage_target: Number(this.coverage.value) / 100,
      timeout_s: Number(this.timeout.value),
    });
  }

  async act(path, body) {
    this.message.textContent = '';
    try {
      const state = await postJson(path, body);
      this.render(state);
      if (path.endsWith('/apply')) this.onApplied();
    } catch (e) {
      this.message.textContent = e instanceof ApiError ? e.message : String(e);
    }
  }

  async poll() {
    if (!this.active) return;
    try {
      this.render(await getJson('/api/calibration/wand'));
    } catch (e) {
      this.stateLine.textContent = `wanding: ${e.message}`;
    }
    this.timer = setTimeout(() => this.poll(), POLL_MS);
  }

  render(w) {
    const s = w.state;
    this.startButton.disabled = s === 'collecting' || s === 'solving';
    this.stopButton.disabled = this.cancelButton.disabled = s !== 'collecting';
    this.solveButton.disabled = !['solved', 'failed', 'cancelled'].includes(s);
    this.applyButton.disabled = this.saveButton.disabled = s !== 'solved' || w.applied;
    this.stateLine.dataset.state = s;
    const c = w.collection;
    let line = `wanding: ${s}`;
    if (w.session) line += ` · session ${w.session}`;
    const single = w.mode === 'single-marker';
    if (single) line += ' · single marker';
    if (c) line += ` · ${formatNumber(c.elapsed_s, 0)} of ${formatNumber(c.timeout_s, 0)} s · ${c.wand_frames} of ` +
      `${c.frame_sets} frame sets with the ${single ? 'marker' : 'wand'}`;
    if (c && single) line += ` · scale bar in ${c.scale_frames} of ${c.min_scale_frames} frame sets`;
    if (w.stop_reason) line += ` · stopped: ${w.stop_reason}`;
    if (s === 'solved' && single) {
      const r = w.solve.report;
      line += ` · solved in ${formatNumber(w.solve.seconds, 1)} s from ${r.frames_used} frames, scale from ` +
        `${r.scale_frames} bar frames (length RMS ${formatNumber(r.scale_length_rms_mm, 3)} mm)`;
    } else if (s === 'solved') {
      line += ` · solved in ${formatNumber(w.solve.seconds, 1)} s, rig rated ${w.solve.report.rating}`;
    }
    if (s === 'failed') line += ` · no calibration: ${w.solve.error}`;
    if (w.applied) line += w.saved_to ? ` · applied and saved to ${w.saved_to}` : ' · applied to the live view';
    this.stateLine.textContent = line;
    if (c) this.renderCameras(c);
    else this.cameras.replaceChildren();
    if (s === 'solved' && single) {
      this.renderSingleMarker(w.solve.report);
      this.reportKey = null;
    } else if (s === 'solved') {
      this.loadReport(w);
    } else {
      this.report.replaceChildren();
      this.reportKey = null;
    }
  }

  renderCameras(c) {
    const g = c.grid;
    this.cameras.replaceChildren(...c.cameras.map((cam) => el('figure', {
      class: `wand-camera ${cam.enough ? 'enough' : 'short'}`, 'data-camera-id': cam.id,
      'data-samples': cam.samples, 'data-coverage': cam.coverage,
    },
    el('figcaption', { text: `camera ${cam.id}: ${cam.samples}/${c.min_samples} samples, ` +
      `${Math.floor(100 * cam.coverage)} % of ${formatNumber(100 * c.coverage_target, 0)} % covered` }),
    coverageMap(cam.counts, g.columns, g.rows, g.cell_samples, 200),
    el('div', { class: 'advice', text: cam.enough ? 'enough' : cam.advice.replace(/^camera \d+: /, '') }))));
  }

  // The single-marker solve's figures per camera (no plots: it writes no wand_figures.json).
  renderSingleMarker(r) {
    this.report.replaceChildren(el('table', { class: 'single-marker-report' },
      el('tr', {}, ...['camera', 'views', 'used', 'RMS px', 'joined through'].map((t) => el('th', { text: t }))),
      ...r.cameras.map((c) => el('tr', { 'data-camera-id': c.id },
        el('td', { text: String(c.id) }), el('td', { text: String(c.views) }), el('td', { text: String(c.used) }),
        el('td', { text: formatNumber(c.rms_px, 3) }),
        el('td', { text: c.joined_through ? String(c.joined_through) : 'reference' })))));
  }

  async loadReport(w) {
    const key = `${w.session}/${w.solve.seconds}`;
    if (key === this.reportKey) return;
    this.reportKey = key;
    try {
      const figures = await getJson(`/api/sessions/${encodeURIComponent(w.session)}/files/wand_figures.json`);
      renderWandReport(this.report, figures);
    } catch (e) {
      this.report.textContent = `the report's figures: ${e.message}`;
      this.reportKey = null;
    }
  }

  show() {
    this.active = true;
    clearTimeout(this.timer);
    this.poll();
  }

  hide() {
    this.active = false;
    clearTimeout(this.timer);
  }
}
