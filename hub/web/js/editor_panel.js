// The trajectory editor (docs/editor.md): one recipe's results of a session, every trajectory on
// a timeline (measured grey, filled coloured by method, gaps empty), a marker and a frame range
// selected on it, the x/y/z graph of the selected marker, the operations as buttons and the edit
// log with undo/redo. Every change is the whole log PUT to /api/sessions/NAME/processed/RECIPE/
// edits: the hub applies it to the results and writes edited.trc/.c3d and edited.filled.tsv beside
// them (never over them); undo drops the last operation and re-applies, redo puts it back.
import { el, getJson, getText, putJson } from './api.js';
import { parseTrc } from './marker_files.js';

const ROW_PX = 14;
const METHOD_COLOURS = { spline: '#2a7de1', linear: '#e1a72a', pattern: '#9b4de1', rigid: '#2ab36b', relational: '#e14d7a' };
const AXIS_COLOURS = ['#d33', '#3a3', '#33d'];

export class EditorPanel {
  constructor() {
    this.session = null;
    this.recipe = null;
    this.log = { format: 'mocap-edits', version: 1, operations: [] };
    this.redo = [];
    this.take = null;       // {names, frames: [frame numbers], points: [frame][marker] -> [x, y, z] | null}
    this.filled = [];       // [{marker, first_frame, last_frame, method}]
    this.selected = 0;      // marker index
    this.range = null;      // [from, to] frame numbers
    this.timeline = el('canvas', { id: 'editor-timeline', width: '900', height: '100' });
    this.graph = el('canvas', { id: 'editor-graph', width: '900', height: '180' });
    this.method = el('select', { id: 'editor-method' },
      ...Object.keys(METHOD_COLOURS).map((m) => el('option', { value: m, text: m })));
    this.donors = el('input', { type: 'text', id: 'editor-donors', size: '24', placeholder: 'donors: A,B,C' });
    this.other = el('input', { type: 'text', id: 'editor-other', size: '12', placeholder: 'other / new name' });
    this.from = el('input', { type: 'number', id: 'editor-from', size: '7' });
    this.to = el('input', { type: 'number', id: 'editor-to', size: '7' });
    this.marker = el('select', { id: 'editor-marker', onchange: () => this.select(Number(this.marker.value)) });
    this.message = el('span', { class: 'message', id: 'editor-message' });
    this.logList = el('ol', { id: 'editor-log' });
    const button = (id, text, onclick) => el('button', { id, text, onclick });
    this.element = el('div', { class: 'editor', id: 'editor', hidden: '' },
      el('h3', { id: 'editor-title', text: 'Edit' }),
      el('div', { class: 'toolbar' }, el('span', { text: 'Marker' }), this.marker, el('span', { text: 'frames' }),
        this.from, this.to, this.method, this.donors, this.other),
      el('div', { class: 'toolbar' },
        button('editor-fill', 'Fill', () => this.fill()),
        button('editor-swap', 'Swap with other', () => this.apply({ op: 'swap', markers: [this.name(), this.otherName()], ...this.rangeFields() })),
        button('editor-split', 'Split at from', () => this.apply({ op: 'split', marker: this.name(), frame: Number(this.from.value), name: this.otherName() })),
        button('editor-join', 'Join other', () => this.apply({ op: 'join', marker: this.name(), other: this.otherName() })),
        button('editor-rename', 'Rename to other', () => this.apply({ op: 'rename', marker: this.name(), name: this.otherName() })),
        button('editor-delete', 'Delete range', () => this.apply({ op: 'delete', marker: this.name(), ...this.rangeFields() })),
        button('editor-spikes', 'Remove spikes', () => this.apply({ op: 'spikes', markers: [this.name()], remove: true })),
        button('editor-undo', 'Undo', () => this.undo()),
        button('editor-redo', 'Redo', () => this.redoLast()), this.message),
      this.timeline, this.graph, el('h4', { text: 'Edit log' }), this.logList);
    this.timeline.addEventListener('mousedown', (e) => this.pick(e, true));
    this.timeline.addEventListener('mouseup', (e) => this.pick(e, false));
  }

  name() { return this.take ? this.take.names[this.selected] : ''; }
  otherName() { return this.other.value.trim(); }
  rangeFields() {
    const from = Number(this.from.value), to = Number(this.to.value);
    return this.from.value !== '' && this.to.value !== '' ? { from, to } : {};
  }

  async open(session, recipe) {
    this.session = session;
    this.recipe = recipe;
    this.redo = [];
    this.element.hidden = false;
    this.element.querySelector('#editor-title').textContent = `Edit ${session} / ${recipe}`;
    try {
      const state = await getJson(this.url());
      this.log = state.edits;
      await this.load(state);
    } catch (e) {
      this.message.textContent = `cannot edit: ${e.message}`;
    }
  }

  url() {
    return `/api/sessions/${encodeURIComponent(this.session)}/processed/${encodeURIComponent(this.recipe)}/edits`;
  }

  fileUrl(file) {
    return `/api/sessions/${encodeURIComponent(this.session)}/processed/${encodeURIComponent(this.recipe)}/files/${encodeURIComponent(file)}`;
  }

  // The edited take when there is one (the log applied), else the results as processed.
  async load(state) {
    const edited = state.outputs.includes('edited.trc');
    const recording = parseTrc(await getText(this.fileUrl(edited ? 'edited.trc' : 'markers.trc')));
    const points = recording.frames.map((frame) => {
      const row = new Array(recording.markers.length).fill(null);
      for (const [x, y, z, m] of frame) row[m] = [x, y, z];
      return row;
    });
    // The hub's frame numbers are Frame# - 1 (Time x rate), as the edit log counts them.
    this.take = { names: recording.markers, frames: recording.frameNumbers.map((f) => f - 1), points };
    this.filled = state.filled || (edited ? parseFilled(await getText(this.fileUrl('edited.filled.tsv'))) : []);
    this.selected = Math.min(this.selected, Math.max(0, this.take.names.length - 1));
    this.marker.replaceChildren(...this.take.names.map((n, i) => el('option', { value: String(i), text: n })));
    this.marker.value = String(this.selected);
    this.render();
  }

  select(marker) {
    this.selected = marker;
    this.marker.value = String(marker);
    this.render();
  }

  fill() {
    const op = { op: 'fill', marker: this.name(), method: this.method.value, ...this.rangeFields() };
    const donors = this.donors.value.split(',').map((s) => s.trim()).filter(Boolean);
    if (donors.length) op.donors = donors;
    return this.apply(op);
  }

  async apply(op) {
    this.redo = [];
    return this.put({ ...this.log, operations: [...this.log.operations, op] });
  }

  async undo() {
    if (!this.log.operations.length) return;
    const ops = [...this.log.operations];
    this.redo.push(ops.pop());
    await this.put({ ...this.log, operations: ops }, true);
  }

  async redoLast() {
    if (!this.redo.length) return;
    const op = this.redo.pop();
    await this.put({ ...this.log, operations: [...this.log.operations, op] }, true);
  }

  async put(log, keepRedo) {
    try {
      const answer = await putJson(this.url(), log);
      this.log = answer.edits;
      const last = answer.operations.length ? answer.operations[answer.operations.length - 1] : 'no edits';
      this.message.textContent = last;
      await this.load(answer);
    } catch (e) {
      this.message.textContent = `refused: ${e.message}`;
      if (!keepRedo) this.redo = [];
    }
  }

  // Press on the timeline: the row picks the marker, press and release the frame range.
  pick(e, down) {
    if (!this.take || !this.take.frames.length) return;
    const r = this.timeline.getBoundingClientRect();
    const x = (e.clientX - r.left) * (this.timeline.width / r.width);
    const y = (e.clientY - r.top) * (this.timeline.height / r.height);
    const frames = this.take.frames;
    const frame = frames[Math.max(0, Math.min(frames.length - 1, Math.round((x / this.timeline.width) * (frames.length - 1))))];
    if (down) {
      this.pressed = frame;
      const row = Math.floor(y / ROW_PX);
      if (row >= 0 && row < this.take.names.length) this.selected = row;
      this.marker.value = String(this.selected);
      return;
    }
    const a = Math.min(this.pressed, frame), b = Math.max(this.pressed, frame);
    this.from.value = String(a);
    this.to.value = String(b);
    this.render();
  }

  render() {
    this.logList.replaceChildren(...this.log.operations.map((op) => el('li', { text: JSON.stringify(op) })));
    if (!this.take) return;
    const { names, frames, points } = this.take;
    const n = frames.length;
    this.timeline.height = Math.max(ROW_PX, names.length * ROW_PX);
    const c = this.timeline.getContext('2d');
    const w = this.timeline.width;
    c.clearRect(0, 0, w, this.timeline.height);
    const xOf = (f) => (n > 1 ? (f / (n - 1)) * (w - 1) : 0);
    const index = new Map(frames.map((f, i) => [f, i]));
    for (let m = 0; m < names.length; ++m) {
      c.fillStyle = m === this.selected ? '#ddeeff' : (m % 2 ? '#fafafa' : '#f0f0f0');
      c.fillRect(0, m * ROW_PX, w, ROW_PX);
      c.fillStyle = '#888';
      for (let i = 0; i < n; ++i) if (points[i][m]) c.fillRect(xOf(i), m * ROW_PX + 3, Math.max(1, w / n), ROW_PX - 6);
      c.fillStyle = '#333';
      c.font = '10px sans-serif';
      c.fillText(names[m], 2, m * ROW_PX + 10);
    }
    for (const s of this.filled) {
      const m = names.indexOf(s.marker);
      if (m < 0 || !index.has(s.first_frame) || !index.has(s.last_frame)) continue;
      c.fillStyle = METHOD_COLOURS[s.method] || '#f0f';
      const a = xOf(index.get(s.first_frame)), b = xOf(index.get(s.last_frame));
      c.fillRect(a, m * ROW_PX + 2, Math.max(2, b - a + w / n), ROW_PX - 4);
    }
    if (this.from.value !== '' && this.to.value !== '') {
      const a = index.get(Number(this.from.value)), b = index.get(Number(this.to.value));
      if (a !== undefined && b !== undefined) {
        c.strokeStyle = '#000';
        c.strokeRect(xOf(a), 0, Math.max(1, xOf(b) - xOf(a)), this.timeline.height);
      }
    }
    this.drawGraph(xOf, w);
  }

  drawGraph(xOf, w) {
    const { frames, points } = this.take;
    const c = this.graph.getContext('2d');
    const h = this.graph.height;
    c.clearRect(0, 0, w, h);
    for (let axis = 0; axis < 3; ++axis) {
      const values = points.map((row) => (row[this.selected] ? row[this.selected][axis] : null));
      const finite = values.filter((v) => v !== null);
      if (!finite.length) continue;
      const lo = Math.min(...finite), hi = Math.max(...finite);
      const yOf = (v) => (h / 3) * axis + (h / 3 - 4) * (1 - (hi > lo ? (v - lo) / (hi - lo) : 0.5)) + 2;
      c.strokeStyle = AXIS_COLOURS[axis];
      c.beginPath();
      let drawing = false;
      for (let i = 0; i < frames.length; ++i) {
        if (values[i] === null) { drawing = false; continue; }
        if (drawing) c.lineTo(xOf(i), yOf(values[i])); else c.moveTo(xOf(i), yOf(values[i]));
        drawing = true;
      }
      c.stroke();
      c.fillStyle = AXIS_COLOURS[axis];
      c.fillText(`${'xyz'[axis]} ${lo.toFixed(0)}..${hi.toFixed(0)} mm`, 2, (h / 3) * axis + 10);
    }
  }
}

// edited.filled.tsv: a comment, a header, then marker, first_frame, last_frame, method.
export function parseFilled(text) {
  return text.split(/\r?\n/).filter((l) => l && !l.startsWith('#') && !l.startsWith('marker\t')).map((l) => {
    const [marker, first, last, method] = l.split('\t');
    return { marker, first_frame: Number(first), last_frame: Number(last), method };
  });
}
