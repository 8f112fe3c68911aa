// Nodes: one row per node with its live status and controls (threshold, exposure, gain,
// identify), and per camera a 2D view of the blobs it sees now with its mask drawn over them, a
// preview image on demand, and the automatic mask. Reads /api/nodes every second and
// /api/blobs ten times a second while shown.
import { el, formatNumber, getImage, getJson, postJson, deleteJson } from './api.js';

const BLOBS_EVERY_MS = 100;
const NODES_EVERY_MS = 1000;

function lastSeen(seconds) {
  return seconds < 1 ? 'now' : `${seconds.toFixed(0)} s ago`;
}

export class NodesPage {
  constructor(root, hub) {
    this.root = root;
    this.hub = hub;
    this.rows = new Map();    // node id -> {tr, cells, inputs}
    this.views = new Map();   // camera id -> {canvas, caption, preview, blobs}
    this.active = false;
    this.blobFrames = 0;
    const message = el('span', { class: 'message', id: 'mask-message' });
    this.maskMessage = message;
    const frames = el('input', { type: 'number', min: '10', max: '1000', value: '100', id: 'mask-frames' });
    root.append(
      el('h2', { text: 'Nodes' }),
      el('table', { class: 'nodes', id: 'nodes-table' },
        el('thead', {}, el('tr', {}, ...['Node', 'State', 'Address', 'Firmware', 'fps', 'Dropped', 'Detect µs',
          'Temp °C', 'Sync jitter · edges', 'Last seen', 'Threshold', 'Exposure µs', 'Gain ×', '', ''].map(
          (t) => el('th', { text: t })))),
        this.tbody = el('tbody')),
      el('h2', { text: 'Cameras' }),
      el('div', { class: 'toolbar' },
        el('span', { text: 'Masks of static reflections (empty the volume first): ' }),
        frames, el('span', { text: ' frame sets ' }),
        el('button', { id: 'auto-mask', text: 'Auto-mask', onclick: () => this.autoMask(frames.value) }),
        el('button', { id: 'clear-masks', text: 'Clear masks', onclick: () => this.clearMasks() }),
        message),
      this.grid = el('div', { class: 'camera-grid', id: 'camera-grid' }));
  }

  show() {
    this.active = true;
    this.pollNodes();
    this.pollBlobs();
  }

  hide() { this.active = false; }

  async pollNodes() {
    if (!this.active || this.nodesPending) return;
    this.nodesPending = true;
    try {
      this.updateRows(await getJson('/api/nodes'));
    } catch (e) {
      /* the status bar says the hub is away; try again */
    } finally {
      this.nodesPending = false;
      if (this.active) setTimeout(() => this.pollNodes(), NODES_EVERY_MS);
    }
  }

  updateRows(nodes) {
    const seen = new Set();
    for (const node of nodes) {
      seen.add(node.id);
      if (!this.rows.has(node.id)) this.addRow(node);
      const row = this.rows.get(node.id);
      const c = row.cells;
      row.tr.className = node.state === 'lost' ? 'lost' : '';
      c.state.textContent = node.state;
      c.address.textContent = node.address;
      c.firmware.textContent = node.firmware || '–';
      // Before its first frame a running node has no rate or detection time: say what it waits for.
      const waiting = node.state === 'running' && node.frames_sent === 0;
      c.fps.textContent = waiting ? 'waiting for the first trigger' : formatNumber(node.fps, 1);
      c.dropped.textContent = node.frames_dropped;
      c.detect.textContent = waiting ? '–' : formatNumber(node.detect_us_mean, 0);
      c.temperature.textContent = formatNumber(node.temperature_c, 1);
      const jitter = formatNumber(node.sync.edge_jitter_ns / 1000, 1);
      c.sync.textContent = `${jitter} µs · ${node.sync.missed_edges} missed`;
      c.seen.textContent = lastSeen(node.last_seen_s);
      // Exposure and gain: fixed for recorded frames (nothing to set), 0 = the camera's own.
      for (const [key, value] of [['threshold', node.threshold], ['exposure_us', node.exposure_us],
        ['gain', node.gain_milli === null ? null : node.gain_milli / 1000]]) {
        const input = row.inputs[key];
        const fixed = key !== 'threshold' && node.exposure_fixed;
        input.disabled = fixed;
        input.placeholder = fixed ? 'fixed (recording)' : key !== 'threshold' ? "camera's own" : '';
        input.dataset.current = value === null ? '' : value;
        const shown = fixed || (key !== 'threshold' && !value) ? '' : value;
        if (document.activeElement !== input && !input.dataset.edited) input.value = shown;
      }
    }
    for (const [id, row] of this.rows) {
      if (!seen.has(id)) {
        row.tr.remove();
        this.rows.delete(id);
      }
    }
  }

  addRow(node) {
    const cells = {};
    const inputs = {};
    const td = (name) => (cells[name] = el('td', { 'data-field': name }));
    const input = (name, attrs) => {
      const i = el('input', { type: 'number', 'data-field': name, ...attrs });
      i.addEventListener('input', () => { i.dataset.edited = '1'; });
      i.addEventListener('keydown', (e) => { if (e.key === 'Enter') this.apply(node.id); });
      inputs[name] = i;
      return el('td', {}, i);
    };
    const result = el('td', { class: 'message', 'data-field': 'result' });
    const tr = el('tr', { 'data-node-id': node.id },
      el('td', { text: node.id }), td('state'), td('address'), td('firmware'), td('fps'), td('dropped'),
      td('detect'), td('temperature'), td('sync'), td('seen'),
      input('threshold', { min: '1', max: '255' }), input('exposure_us', { min: '1', max: '1000000' }),
      input('gain', { min: '1', max: '64', step: '0.1' }),
      el('td', {},
        el('button', { text: 'Apply', 'data-action': 'apply', onclick: () => this.apply(node.id) }),
        el('button', { text: 'Identify', 'data-action': 'identify', onclick: () => this.identify(node.id) })),
      result);
    cells.result = result;
    const rows = [...this.rows.keys(), node.id].sort((a, b) => a - b);
    const before = this.rows.get(rows[rows.indexOf(node.id) + 1]);
    this.tbody.insertBefore(tr, before ? before.tr : null);
    this.rows.set(node.id, { tr, cells, inputs });
  }

  async apply(id) {
    const row = this.rows.get(id);
    const body = {};
    const changed = (key) => {
      const input = row.inputs[key];
      return input.value !== '' && Number(input.value) !== Number(input.dataset.current);
    };
    if (changed('threshold')) body.threshold = Math.round(Number(row.inputs.threshold.value));
    if (changed('exposure_us')) body.exposure_us = Math.round(Number(row.inputs.exposure_us.value));
    if (changed('gain')) body.gain_milli = Math.round(Number(row.inputs.gain.value) * 1000);
    if (!Object.keys(body).length) {
      row.cells.result.textContent = 'nothing changed';
      return;
    }
    row.cells.result.textContent = 'sending…';
    try {
      const answer = await postJson(`/api/nodes/${id}/settings`, body);
      row.cells.result.textContent = answer.outcome + (answer.reason ? `: ${answer.reason}` : '');
      for (const input of Object.values(row.inputs)) delete input.dataset.edited;
    } catch (e) {
      row.cells.result.textContent = `refused: ${e.message}`;
    }
  }

  async identify(id) {
    const row = this.rows.get(id);
    try {
      const answer = await postJson(`/api/nodes/${id}/identify`, { duration_ms: 3000 });
      row.cells.result.textContent = `identify: ${answer.outcome}`;
    } catch (e) {
      row.cells.result.textContent = `identify refused: ${e.message}`;
    }
  }

  async autoMask(frames) {
    this.maskMessage.textContent = 'collecting frames…';
    try {
      const answer = await postJson('/api/masks/auto', { frames: Number(frames) });
      const found = answer.cameras.map(
        (c) => `cam ${c.camera_id}: ${c.static_blobs_found} blobs, ${c.regions} regions`);
      this.maskMessage.textContent = `masked from ${answer.frames} frame sets (${found.join('; ')})`;
    } catch (e) {
      this.maskMessage.textContent = `auto-mask failed: ${e.message}`;
    }
  }

  async clearMasks() {
    try {
      const answer = await deleteJson('/api/masks');
      this.maskMessage.textContent = `masks cleared on ${answer.nodes.length} nodes`;
    } catch (e) {
      this.maskMessage.textContent = `clearing failed: ${e.message}`;
    }
  }

  async pollBlobs() {
    if (!this.active || this.blobsPending) return;
    this.blobsPending = true;
    try {
      this.drawBlobs(await getJson('/api/blobs'));
    } catch (e) {
      /* the hub is away: keep the last picture */
    } finally {
      this.blobsPending = false;
      if (this.active) setTimeout(() => this.pollBlobs(), BLOBS_EVERY_MS);
    }
  }

  view(camera) {
    if (this.views.has(camera.id)) return this.views.get(camera.id);
    const canvas = el('canvas', { width: '320', height: String(Math.round((320 * camera.height) / camera.width)) });
    const caption = el('div', { class: 'caption' });
    const status = el('span', { class: 'message' });
    const v = { canvas, caption, status, preview: null, blobs: 0 };
    const card = el('div', { class: 'camera-view', 'data-camera-id': camera.id },
      canvas, caption,
      el('div', {},
        el('button', { text: 'Raw image', onclick: () => this.preview(camera.id, 'raw') }),
        el('button', { text: 'Thresholded', onclick: () => this.preview(camera.id, 'thresholded') }),
        el('button', { text: 'Blobs only', onclick: () => { v.preview = null; status.textContent = ''; } }),
        status));
    v.card = card;
    const ids = [...this.views.keys(), camera.id].sort((a, b) => a - b);
    const before = this.views.get(ids[ids.indexOf(camera.id) + 1]);
    this.grid.insertBefore(card, before ? before.card : null);
    this.views.set(camera.id, v);
    return v;
  }

  async preview(id, mode) {
    const v = this.views.get(id);
    v.status.textContent = 'asking the node…';
    try {
      v.preview = await getImage(`/api/nodes/${id}/preview?mode=${mode}&downscale=2`);
      v.status.textContent = `${mode} preview`;
    } catch (e) {
      v.status.textContent = `no preview: ${e.message}`;
    }
  }

  drawBlobs(answer) {
    this.blobFrames += 1;
    for (const camera of answer.cameras) {
      const v = this.view(camera);
      const ctx = v.canvas.getContext('2d');
      const s = v.canvas.width / camera.width;
      ctx.fillStyle = '#000';
      ctx.fillRect(0, 0, v.canvas.width, v.canvas.height);
      if (v.preview) ctx.drawImage(v.preview, 0, 0, v.canvas.width, v.canvas.height);
      ctx.fillStyle = 'rgba(230, 60, 60, 0.45)';
      ctx.strokeStyle = 'rgba(230, 60, 60, 0.9)';
      for (const [x, y, w, h] of camera.mask) {
        ctx.fillRect(x * s, y * s, Math.max(w * s, 1), Math.max(h * s, 1));
        ctx.strokeRect(x * s, y * s, Math.max(w * s, 1), Math.max(h * s, 1));
      }
      ctx.strokeStyle = '#5dff9d';
      ctx.lineWidth = 1.5;
      for (const [x, y, area] of camera.blobs) {
        ctx.beginPath();
        ctx.arc(x * s, y * s, Math.max(Math.sqrt(area / Math.PI) * s, 2.5), 0, 2 * Math.PI);
        ctx.stroke();
      }
      v.blobs = camera.blobs.length;
      v.card.dataset.blobs = camera.blobs.length;
      v.card.dataset.maskRegions = camera.mask.length;
      v.caption.textContent = `camera ${camera.id} · ${camera.width}×${camera.height} · ` +
        (camera.seen ? `frame ${answer.frame} · ${camera.blobs.length} blobs` : 'no frame') +
        (camera.mask.length ? ` · ${camera.mask.length} masked regions` : '');
    }
  }
}
