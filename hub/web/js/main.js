// The console's shell: the hub's status every second (the header; a hub that stops answering is
// shown as away and tried again until it is back, and then the calibration is read again), the
// tabs (Nodes, Live 3D, Calibration, Sessions: one page shown at a time, the others idle), and
// window.mocapConsole for tests and benchmarks.
import { el, formatNumber, getJson, logout, onUnauthorized, traffic } from './api.js';
import { LoginForm } from './login_form.js';
import { CalibrationPage } from './calibration_page.js';
import { LivePage } from './live_page.js';
import { NodesPage } from './nodes_page.js';
import { SessionsPage } from './sessions_page.js';
import { SOFTWARE_GL } from './scene3d.js';

const STATUS_EVERY_MS = 1000;

class Hub {
  constructor(header) {
    this.header = header;
    this.status = null;
    this.connected = false;
    this.reconnects = 0;
    this.statusListeners = [];
    this.calibrationListeners = [];
    this.calibration = null;
    this.who = null;
    this.loginNeeded = false;
  }

  onStatus(listener) { this.statusListeners.push(listener); }

  onCalibration(listener) {
    this.calibrationListeners.push(listener);
    if (this.calibration) listener(this.calibration.cameras, this.calibration.file);
  }

  nodes() { return getJson('/api/nodes'); }

  async loadCalibration() {
    try {
      this.calibration = await getJson('/api/calibration');
      for (const l of this.calibrationListeners) l(this.calibration.cameras, this.calibration.file);
    } catch (e) {
      this.calibration = null;
    }
  }

  async poll() {
    try {
      if (!this.who) this.who = await getJson('/api/whoami');
      this.status = await getJson('/api/status');
      this.loginNeeded = false;
      if (!this.connected) {
        if (this.status && this.everConnected) this.reconnects += 1;
        this.connected = this.everConnected = true;
        this.loadCalibration();
      }
    } catch (e) {
      this.connected = false;
      if (e.status === 401) {
        this.loginNeeded = true;
        this.who = null;
      }
    }
    this.render();
    for (const l of this.statusListeners) l(this.connected ? this.status : null);
    setTimeout(() => this.poll(), STATUS_EVERY_MS);
  }

  render() {
    const s = this.status;
    if (!this.connected) {
      this.header.replaceChildren(this.loginNeeded
        ? el('span', { class: 'state away', id: 'hub-state', text: 'log in' })
        : el('span', { class: 'state away', id: 'hub-state', text: 'hub away – retrying' }));
      return;
    }
    const latency = s.hub_latency_ms || {};
    const items = [
      el('span', { class: 'state ok', id: 'hub-state', text: 'connected' }),
      el('span', { text: `nodes ${s.nodes_online}/${s.cameras}` }),
      el('span', { text: `frame sets ${s.frame_sets} (${s.incomplete_frame_sets} incomplete)` }),
      el('span', { text: `hub latency p99 ${formatNumber(latency.p99, 2)} ms` }),
      el('span', { text: `masks ${s.masks}` }),
      el('span', { text: `up ${formatNumber(s.uptime_s, 0)} s` }),
    ];
    // Frame sets of one camera since the last poll: 3D lost to a late hub or network, said at once.
    const single = s.single_camera_frame_sets - (this.lastSingleCameraSets ?? s.single_camera_frame_sets);
    this.lastSingleCameraSets = s.single_camera_frame_sets;
    if (single > 0) {
      items.push(el('span', { class: 'state away', id: 'single-camera-sets',
                              text: `${single} frame sets from one camera only: the hub is late, no 3D in them` }));
    }
    if (s.capture) items.push(el('span', { class: 'state recording', text: `● ${s.capture.name}` }));
    if (s.last_capture && s.last_capture.state === 'failed') {
      items.push(el('span', { class: 'state away', id: 'capture-failed',
                              text: `capture ${s.last_capture.name} failed: ${s.last_capture.reason}` }));
    }
    if (s.sessions_disk && s.sessions_disk.low) {
      items.push(el('span', { class: 'state away', id: 'disk-low',
                              text: `sessions disk: ${formatNumber(s.sessions_disk.free_bytes / 1048576, 0)} MiB free` }));
    }
    if (this.who) {
      items.push(el('span', { id: 'who', text: `${this.who.name} (${this.who.role})` }));
      if (this.who.tokens_required) {
        items.push(el('button', { id: 'logout', text: 'log out',
                                  onclick: async () => { await logout().catch(() => {}); this.who = null; } }));
      }
    }
    this.header.replaceChildren(...items);
  }
}

function main() {
  const hub = new Hub(document.getElementById('status'));
  const loginForm = new LoginForm(() => { hub.who = null; });
  onUnauthorized(() => loginForm.show());
  const pages = {
    nodes: new NodesPage(document.getElementById('page-nodes'), hub),
    live: new LivePage(document.getElementById('page-live'), hub),
    calibration: new CalibrationPage(document.getElementById('page-calibration'), hub),
    sessions: new SessionsPage(document.getElementById('page-sessions'), hub),
  };
  let current = null;
  const showPage = () => {
    const name = pages[location.hash.slice(1)] ? location.hash.slice(1) : 'nodes';
    if (name === current) return;
    if (current) pages[current].hide();
    for (const [key] of Object.entries(pages)) {
      document.getElementById(`page-${key}`).hidden = key !== name;
      document.querySelector(`nav a[href="#${key}"]`).classList.toggle('active', key === name);
    }
    current = name;
    pages[name].show();
  };
  window.addEventListener('hashchange', showPage);
  showPage();
  hub.poll();
  window.mocapConsole = { hub, pages, traffic, loginForm, softwareGl: SOFTWARE_GL, currentPage: () => current };
}

main();
