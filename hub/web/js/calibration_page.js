// Calibration: live wanding (wanding_panel.js: per camera samples, coverage map and advice, then
// the solve's report as plots), the floor / L-frame step after it (world_frame_panel.js), and
// the calibration serve runs with, as a camera layout in 3D and a table per camera (resolution,
// intrinsics, distortion, position, distance to the volume's centre, its node).
import { el, formatNumber } from './api.js';
import { Scene3D } from './scene3d.js';
import { WandingPanel } from './wanding_panel.js';
import { WorldFramePanel } from './world_frame_panel.js';

export class CalibrationPage {
  constructor(root, hub) {
    this.hub = hub;
    const view = el('div', { class: 'view3d short', id: 'calibration-view' });
    this.file = el('span', { class: 'hint' });
    this.wanding = new WandingPanel(root, () => hub.loadCalibration());
    this.world = new WorldFramePanel(root, () => hub.loadCalibration());
    root.append(el('h2', { text: 'Camera layout' }), this.file, view,
      el('table', { class: 'cameras', id: 'calibration-table' },
        el('thead', {}, el('tr', {}, ...['Camera', 'Image px', 'fx / fy px', 'cx / cy px', 'k1 / k2',
          'Position mm', 'Distance to centre mm', 'Node'].map((t) => el('th', { text: t })))),
        this.tbody = el('tbody')));
    this.scene = new Scene3D(view);
    this.cameras = [];
    this.nodes = null;  // null until the node list is read: a camera is then "not heard" only if absent
    hub.onCalibration((cameras, file) => {
      this.cameras = cameras;
      this.file.textContent = `${file} · ${cameras.length} cameras`;
      this.scene.setCameras(cameras);
      this.fill();
    });
  }

  fill() {
    const nodes = this.nodes;
    this.tbody.replaceChildren();
    const centre = [0, 0, 0];
    for (const c of this.cameras) c.centre.forEach((v, i) => { centre[i] += v / this.cameras.length; });
    for (const c of this.cameras) {
      const node = nodes && nodes.get(c.id);
      const d = Math.hypot(...c.centre.map((v, i) => v - centre[i]));
      this.tbody.append(el('tr', { 'data-camera-id': c.id },
        el('td', { text: c.id }), el('td', { text: `${c.width}×${c.height}` }),
        el('td', { text: `${formatNumber(c.fx)} / ${formatNumber(c.fy)}` }),
        el('td', { text: `${formatNumber(c.cx)} / ${formatNumber(c.cy)}` }),
        el('td', { text: `${formatNumber(c.distortion[0], 3)} / ${formatNumber(c.distortion[1], 3)}` }),
        el('td', { text: c.centre.map((v) => v.toFixed(0)).join(', ') }),
        el('td', { text: d.toFixed(0) }),
        el('td', { 'data-field': 'node', text: node ? node.state : nodes ? 'not heard' : '…' })));
    }
  }

  // The node states follow while the page is shown (the calibration may arrive before or after
  // the first node list: each fills the table with what is known).
  async refreshNodes() {
    try {
      const nodes = await this.hub.nodes();
      this.nodes = new Map(nodes.map((n) => [n.id, n]));
    } catch (e) {
      /* the status bar says the hub is away; keep what was known */
    }
    this.fill();
  }

  async show() {
    this.wanding.show();
    this.scene.show();
    clearInterval(this.nodeTimer);
    this.nodeTimer = setInterval(() => this.refreshNodes(), 2000);
    await this.refreshNodes();
  }

  hide() {
    clearInterval(this.nodeTimer);
    this.wanding.hide();
    this.scene.hide();
  }
}
