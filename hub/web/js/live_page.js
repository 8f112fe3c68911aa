// Live 3D: every published frame's markers (confirmed green, provisional orange, ids on demand),
// rigid bodies (axes) and skeletons (bones) over the calibrated cameras and the floor. Frames come from
// /api/live?max_fps=60 while the page is shown; the view draws the newest at the screen's rate.
import { el } from './api.js';
import { LiveSocket } from './live_socket.js';
import { Scene3D } from './scene3d.js';

export class LivePage {
  constructor(root, hub) {
    this.hub = hub;
    this.socket = new LiveSocket('/api/live?max_fps=60');
    this.info = el('div', { class: 'overlay', id: 'live-info' });
    const ids = el('input', { type: 'checkbox', id: 'show-ids' });
    ids.addEventListener('change', () => { this.scene.showIds = ids.checked; });
    const view = el('div', { class: 'view3d', id: 'live-view' });
    root.append(el('div', { class: 'toolbar' }, el('label', {}, ids, ' marker ids'),
      el('span', { class: 'hint', text: ' drag: orbit · right-drag: pan · wheel: zoom' })), view);
    view.append(this.info);
    this.scene = new Scene3D(view);
    this.frame = null;
    this.frames = 0;
    this.rate = { start: performance.now(), frames: 0, fps: 0 };
    this.socket.listeners.add((frame) => this.onFrame(frame));
    this.socket.stateListeners.add(() => this.updateInfo());
    hub.onCalibration((cameras) => this.scene.setCameras(cameras));
    this.benchmarking = false;
  }

  show() {
    this.scene.show();
    this.socket.start();
  }

  hide() {
    this.scene.hide();
    this.socket.stop();
  }

  onFrame(frame) {
    if (this.benchmarking) return;
    this.frame = frame;
    this.frames += 1;
    this.scene.setPoints(frame.points);
    this.scene.setBodies(frame.bodies || []);
    this.scene.setSkeletons(frame.skeletons || []);
    const now = performance.now();
    this.rate.frames += 1;
    if (now - this.rate.start >= 1000) {
      this.rate.fps = (this.rate.frames * 1000) / (now - this.rate.start);
      this.rate = { start: now, frames: 0, fps: this.rate.fps };
      this.updateInfo();
    }
  }

  updateInfo() {
    const f = this.frame;
    const provisional = f ? f.points.filter((p) => p[4]).length : 0;
    const bodies = f && f.bodies ? f.bodies.filter((b) => b[1]).length : 0;
    const skeletons = (f && f.skeletons ? f.skeletons : []).map((s) =>
      ` · ${s.name}: ${s.solved ? `${s.bones.length} bones, ${s.rms_mm.toFixed(1)} mm` : s.state}`).join('');
    const rates = `${this.rate.fps.toFixed(0)} frames/s received · ${this.scene.fps.toFixed(0)} fps drawn`;
    this.info.textContent = this.socket.state !== 'open' ? `live: ${this.socket.state}…` :
      f ? `frame ${f.frame} · ${f.points.length} markers (${provisional} provisional) · ${bodies} bodies${skeletons} · ${rates}`
        : 'waiting for frames';
  }

  // Draws `markers` synthetic markers moving on a sphere for `ms` milliseconds (live frames are
  // ignored meanwhile) and answers the drawing rate: the figure for a volume full of markers.
  benchmark(markers, ms) {
    this.benchmarking = true;
    const points = [];
    for (let i = 0; i < markers; ++i) points.push([0, 0, 0, i, i % 10 === 0 ? 1 : 0]);
    const started = performance.now();
    const renderedBefore = this.scene.framesRendered;
    return new Promise((resolve) => {
      this.scene.beforeRender = () => {
        const t = (performance.now() - started) / 1000;
        points.forEach((p, i) => {
          const a = (i / markers) * Math.PI * 2 + t, b = ((i * 7) % markers) / markers * Math.PI;
          p[0] = 1000 * Math.cos(a) * Math.sin(b);
          p[1] = 1000 * Math.sin(a) * Math.sin(b);
          p[2] = 1000 + 800 * Math.cos(b);
        });
        this.scene.setPoints(points);
      };
      setTimeout(() => {
        const elapsed = performance.now() - started;
        const frames = this.scene.framesRendered - renderedBefore;
        const drawn = this.scene.drawnMarkers;
        this.scene.beforeRender = null;
        this.benchmarking = false;
        resolve({ markers, drawn, frames, seconds: elapsed / 1000, fps: (frames * 1000) / elapsed });
      }, ms);
    });
  }
}
