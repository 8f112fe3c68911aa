// The calibration page's floor step, after wanding: a wand calibration's world is its reference
// camera's, so the live view hangs tilted until the world is put on the floor. With the L-frame
// (or three or more floor markers) lying still in view, "Set the floor" asks serve to collect a
// short window of live frame sets, find it and move the calibration's world onto it
// (POST /api/calibration/world); the answer says what was found (markers and their errors, the
// axes, the tilt removed) or why not (the L-frame not seen, other markers in view).
import { ApiError, el, formatNumber, postJson } from './api.js';

const vector = (v) => v.map((x) => formatNumber(x, 1)).join(', ');

export class WorldFramePanel {
  constructor(root, onApplied) {
    this.onApplied = onApplied;
    this.method = el('select', { id: 'world-method' },
      el('option', { value: 'lframe', text: 'L-frame (origin, 200 and 500 mm along one arm, 350 mm along the other)' }),
      el('option', { value: 'floor', text: 'floor markers (3 or more, lying on the floor)' }));
    this.up = el('select', { id: 'world-up' }, ...['z', 'y', 'x'].map((a) => el('option', { value: a, text: `${a} up` })));
    this.frames = el('input', { type: 'number', id: 'world-frames', value: 60, min: 10, max: 2000, step: 10 });
    this.button = el('button', { id: 'world-set', text: 'Set the floor', onclick: () => this.run() });
    this.state = el('div', { class: 'caption', id: 'world-state' });
    this.details = el('div', { id: 'world-details' });
    root.append(el('h2', { text: 'Floor (L-frame)' }),
      el('div', { class: 'toolbar' }, this.method, this.up, el('label', { text: 'frame sets' }), this.frames,
        this.button),
      this.state, this.details);
  }

  async run() {
    this.button.disabled = true;
    this.state.dataset.state = 'running';
    this.state.textContent = 'looking for it in the live frame sets...';
    this.details.replaceChildren();
    try {
      const r = await postJson('/api/calibration/world',
        { method: this.method.value, up: this.up.value, frames: Number(this.frames.value) });
      this.state.dataset.state = 'done';
      const what = r.method === 'lframe' ? `L-frame found in ${r.frames_used} of ${r.frames} frame sets, ` +
        `${r.markers.length} markers, fit ${formatNumber(r.fit_rms_mm, 2)} mm` :
        `floor levelled on ${r.markers.length} markers (${r.frames} frame sets)`;
      this.state.textContent = `${what}; tilt removed ${formatNumber(r.tilt_removed_deg, 2)}°, world moved ` +
        `${formatNumber(r.moved_mm, 0)} mm and turned ${formatNumber(r.turned_deg, 1)}°; saved to ${r.saved}`;
      this.details.append(
        el('table', { class: 'cameras', id: 'world-markers' },
          el('thead', {}, el('tr', {}, ...['Marker', 'Model mm', 'Measured mm', 'Error mm'].map((t) => el('th', { text: t })))),
          el('tbody', {}, ...r.markers.map((m, i) => el('tr', { 'data-marker': i },
            el('td', { text: String(i + 1) }), el('td', { text: m.model ? vector(m.model) : '' }),
            el('td', { text: vector(m.measured) }), el('td', { text: m.error_mm === null ? '' : formatNumber(m.error_mm, 2) }))))),
        el('div', { class: 'hint', id: 'world-axes',
          text: `new axes in the old world: x (${vector(r.axes.x.map((v) => v * 1000))})‰, ` +
            `y (${vector(r.axes.y.map((v) => v * 1000))})‰, z (${vector(r.axes.z.map((v) => v * 1000))})‰` }));
      this.onApplied();
    } catch (e) {
      this.state.dataset.state = 'refused';
      this.state.textContent = `not set: ${e instanceof ApiError ? e.message : String(e)}`;
    } finally {
      this.button.disabled = false;
    }
  }
}
