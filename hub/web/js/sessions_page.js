// Sessions: capture start/stop, the sessions directory, each session's files to download, and
// playback of a marker file (a reconstructed TRC, the capture's live_points.tsv: what serve
// published, or a .mca archive decoded in a Web Worker as it streams in) in a 3D view with a
// timeline: play, pause, scrub, speed. A mesh binding (.mdb) plays the session's markers (its
// first .mca, else markers.trc) with the mesh they drive, deformed in the page frame by frame. A
// session is processed by a recipe from its details (processing_panel.js).
import { deleteJson, el, getBytes, getJson, getText, postJson, putJson } from './api.js';
import { openArchive } from './archive_recording.js';
import { parseMarkerFile } from './marker_files.js';
import { MeshDriver, parseMeshBinding } from './mesh_binding.js';
import { EditorPanel } from './editor_panel.js';
import { ProcessingPanel } from './processing_panel.js';
import { Scene3D } from './scene3d.js';

function defaultName() {
  const d = new Date();
  const p = (n) => String(n).padStart(2, '0');
  const date = `${d.getFullYear()}${p(d.getMonth() + 1)}${p(d.getDate())}`;
  return `take_${date}_${p(d.getHours())}${p(d.getMinutes())}${p(d.getSeconds())}`;
}

function playable(name) {
  return name.endsWith('.trc') || name.endsWith('.mca') || name.endsWith('.mdb') || name === 'live_points.tsv';
}

// A parsed file holds its frames; an archive decodes them as they arrive (archive_recording.js).
const frameCount = (r) => (r.pointsAt ? r.frameCount : r.frames.length);
const pointsAt = (r, i) => (r.pointsAt ? r.pointsAt(i) : r.frames[i]);

function kilobytes(bytes) {
  return bytes < 1024 ? `${bytes} B` : bytes < 1048576 ? `${(bytes / 1024).toFixed(1)} KiB` :
    `${(bytes / 1048576).toFixed(1)} MiB`;
}

// The timeline of one recording: time runs at `speed` while playing; the frame shown is the
// recording's last frame at or before the time reached.
class Player {
  constructor(root, scene) {
    this.scene = scene;
    this.recording = null;
    this.index = 0;
    this.playing = false;
    this.speed = 1;
    this.framesShown = 0;
    this.mesh = null;  // a MeshDriver while a binding plays
    this.deform = { frames: 0, ms: 0 };  // the mesh's deformation cost, summed
    this.playButton = el('button', { id: 'play', text: 'Play', onclick: () => this.toggle() });
    this.slider = el('input', { type: 'range', id: 'timeline', min: '0', max: '0', value: '0' });
    this.slider.addEventListener('input', () => this.seek(Number(this.slider.value)));
    this.speedSelect = el('select', { id: 'speed' }, ...[0.25, 0.5, 1, 2, 4].map((s) =>
      el('option', { value: String(s), text: `${s}×` })));
    this.speedSelect.value = '1';
    this.speedSelect.addEventListener('change', () => { this.speed = Number(this.speedSelect.value); });
    this.label = el('span', { class: 'time', id: 'play-time' });
    this.title = el('span', { class: 'hint', id: 'play-title', text: 'choose a file to play' });
    root.append(el('div', { class: 'toolbar' }, this.playButton, this.slider, this.speedSelect, this.label,
      this.title));
    scene.beforeRender = () => this.tick();
  }

  // mesh: a MeshDriver for the recording, or null.
  load(recording, title, mesh = null) {
    this.recording = recording;
    this.mesh = mesh;
    this.deform = { frames: 0, ms: 0 };
    this.scene.setMesh(mesh ? mesh.binding : null);
    this.playing = false;
    this.scene.names = recording.markers.length ? recording.markers : null;
    this.slider.max = String(Math.max(frameCount(recording) - 1, 0));
    this.title.textContent = `${title}: ${frameCount(recording)} frames at ${recording.rate} Hz` +
      (recording.markers.length ? `, ${recording.markers.length} markers` : '');
    this.seek(0);
    this.play();
  }

  frameTime(i) {
    const r = this.recording;
    return (r.frameNumbers[i] - r.frameNumbers[0]) / r.rate;
  }

  seek(index) {
    if (!this.recording || !frameCount(this.recording)) return;
    this.index = Math.max(0, Math.min(index, frameCount(this.recording) - 1));
    this.time = this.frameTime(this.index);
    this.last = performance.now();
    this.show();
  }

  show() {
    const points = pointsAt(this.recording, this.index);
    this.scene.setPoints(points);
    if (this.mesh) {
      const start = performance.now();
      if (this.mesh.deform(points)) this.scene.updateMesh(this.mesh.positions);
      this.deform.ms += performance.now() - start;
      this.deform.frames += 1;
    }
    this.slider.value = String(this.index);
    this.label.textContent = `${this.time.toFixed(2)} s · frame ${this.recording.frameNumbers[this.index]}`;
    this.framesShown += 1;
  }

  play() {
    if (!this.recording) return;
    if (this.index >= frameCount(this.recording) - 1) this.seek(0);
    this.playing = true;
    this.last = performance.now();
    this.playButton.textContent = 'Pause';
  }

  pause() {
    this.playing = false;
    this.playButton.textContent = 'Play';
  }

  toggle() {
    if (this.playing) this.pause();
    else this.play();
  }

  tick() {
    if (!this.playing || !this.recording) return;
    const now = performance.now();
    this.time += ((now - this.last) / 1000) * this.speed;
    this.last = now;
    const frames = frameCount(this.recording);
    let i = this.index;
    while (i + 1 < frames && this.frameTime(i + 1) <= this.time) ++i;
    if (i !== this.index) {
      this.index = i;
      this.show();
    }
    if (i === frames - 1) this.pause();
  }
}

export class SessionsPage {
  constructor(root, hub) {
    this.hub = hub;
    this.active = false;
    this.name = el('input', { type: 'text', id: 'capture-name', value: defaultName(), size: '28' });
    this.captureState = el('span', { class: 'message', id: 'capture-state' });
    this.captureMessage = el('span', { class: 'message', id: 'capture-message' });
    this.list = el('tbody');
    this.details = el('div', { class: 'session-details', id: 'session-details' });
    this.shown = null;  // the session whose details are shown
    this.processing = new ProcessingPanel(
      (session, recipe, file) => this.play(session, file,
        `/api/sessions/${encodeURIComponent(session)}/processed/${encodeURIComponent(recipe)}/files/${encodeURIComponent(file)}`),
      (session) => { if (this.shown === session) this.open(session); },
      (session, recipe) => this.editor.open(session, recipe));
    this.editor = new EditorPanel();
    const view = el('div', { class: 'view3d short', id: 'player-view' });
    const player = el('div', { class: 'player' });
    const left = el('div', { class: 'column' });
    const right = el('div', { class: 'column' });
    root.append(el('div', { class: 'two-columns' }, left, right));
    left.append(
      el('h2', { text: 'Capture' }),
      el('div', { class: 'toolbar' }, el('span', { text: 'Session name ' }), this.name,
        el('button', { id: 'capture-start', text: 'Start capture', onclick: () => this.start() }),
        el('button', { id: 'capture-stop', text: 'Stop', onclick: () => this.stop() }), this.captureState,
        this.captureMessage),
      el('h2', {}, 'Sessions ',
        el('button', { id: 'sessions-refresh', text: 'Refresh', onclick: () => this.refresh() })),
      el('table', { class: 'sessions', id: 'sessions-table' },
        el('thead', {}, el('tr', {}, ...['Session', 'State', 'Frame sets', 'Cameras', 'Rate Hz', 'Notes', ''].map(
          (t) => el('th', { text: t })))), this.list),
      this.details);
    right.append(el('h2', { text: 'Playback' }), player, view);
    this.scene = new Scene3D(view);
    this.player = new Player(player, this.scene);
    hub.onCalibration((cameras) => this.scene.setCameras(cameras));
    hub.onStatus((status) => { if (status) this.showCapture(status); });
  }

  show() {
    this.active = true;
    this.scene.show();
    this.refresh();
  }

  hide() {
    this.active = false;
    this.scene.hide();
    this.player.pause();
    this.processing.stop();
  }

  showCapture(status) {
    const c = status && status.capture;
    this.captureState.textContent = c ? `capturing ${c.name}: ${c.seconds.toFixed(1)} s, ${c.frame_sets} frame sets`
      : 'not capturing';
    this.captureState.className = c ? 'message recording' : 'message';
  }

  async start() {
    try {
      const c = await postJson('/api/capture/start', { name: this.name.value.trim() });
      this.showCapture({ capture: c });
      this.captureMessage.textContent = `started ${c.name} in ${c.path}`;
    } catch (e) {
      this.captureMessage.textContent = `not started: ${e.message}`;
    }
    this.refresh();
  }

  async stop() {
    try {
      const c = await postJson('/api/capture/stop');
      this.showCapture(null);
      this.captureMessage.textContent = `${c.name}: ${c.frame_sets} frame sets in ${c.seconds.toFixed(1)} s`;
      this.name.value = defaultName();
    } catch (e) {
      this.captureMessage.textContent = `not stopped: ${e.message}`;
    }
    this.refresh();
  }

  async refresh() {
    let sessions;
    try {
      sessions = await getJson('/api/sessions');
    } catch (e) {
      return;
    }
    this.list.replaceChildren(...sessions.map((s) => el('tr', { 'data-session': s.name },
      el('td', { text: s.name }), el('td', { text: s.state }), el('td', { text: s.frame_sets ?? '–' }),
      el('td', { text: s.cameras ?? '–' }), el('td', { text: s.rate_hz ?? '–' }),
      el('td', { class: 'notes', text: (s.notes || '').split('\n')[0] }),
      el('td', {}, el('button', { text: 'Files', 'data-action': 'files', onclick: () => this.open(s.name) })))));
  }

  async open(name) {
    let session;
    try {
      session = await getJson(`/api/sessions/${encodeURIComponent(name)}`);
    } catch (e) {
      this.details.textContent = `${name}: ${e.message}`;
      return;
    }
    this.shown = name;
    const base = `/api/sessions/${encodeURIComponent(name)}/files/`;
    this.details.replaceChildren(el('h3', { text: `${name} (${session.state})` }),
      el('table', { class: 'files' }, el('tbody', {}, ...session.files.map((f) => el('tr', { 'data-file': f.name },
        el('td', {}, el('a', { href: base + encodeURIComponent(f.name), download: f.name, text: f.name })),
        el('td', { text: kilobytes(f.bytes) }),
        el('td', {}, playable(f.name) ? el('button', { text: 'Play', 'data-action': 'play',
          onclick: () => this.play(name, f.name) }) : ''))))),
      this.housekeeping(name, session),
      (session.processed || []).length ? '' : el('p', { class: 'hint', text: 'Not processed yet: Process below ' +
        'reconstructs it into processed/RECIPE/ (live_points.tsv plays what serve published).' }),
      this.processing.element, this.editor.element);
    this.processing.showFor(name, session.processed);
  }

  // Notes, rename and delete (a deleted session is moved to the sessions directory's .deleted/,
  // never erased from here): each answer or refusal is shown beside the buttons.
  housekeeping(name, session) {
    const path = `/api/sessions/${encodeURIComponent(name)}`;
    const message = el('span', { class: 'message', id: 'session-admin-message' });
    const notes = el('textarea', { id: 'session-notes', rows: '3', cols: '60', placeholder: 'notes on this take' });
    notes.value = session.notes || '';
    const newName = el('input', { id: 'session-new-name', type: 'text', value: name, size: '24' });
    const run = async (what, action) => {
      message.textContent = `${what}…`;
      try {
        const answer = await action();
        message.textContent = `${what}: done`;
        return answer;
      } catch (e) {
        message.textContent = `${what}: ${e.message}`;
        return null;
      }
    };
    const confirmDelete = el('button', { id: 'session-delete-confirm', text: 'Yes, delete', hidden: true,
      onclick: async () => {
        const answer = await run('delete', () => deleteJson(path));
        if (!answer) return;
        this.shown = null;
        this.details.replaceChildren(el('p', { id: 'session-deleted', text: `${name} deleted (moved to ${answer.moved_to})` }));
        this.refresh();
      } });
    return el('div', { class: 'session-admin' },
      el('div', {}, notes, el('button', { id: 'session-notes-save', text: 'Save notes',
        onclick: async () => { if (await run('notes', () => putJson(`${path}/notes`, { notes: notes.value }))) this.refresh(); } })),
      el('div', {}, newName, el('button', { id: 'session-rename', text: 'Rename',
        onclick: async () => {
          const answer = await run('rename', () => postJson(`${path}/rename`, { name: newName.value.trim() }));
          if (answer) { this.refresh(); this.open(answer.name); }
        } }),
      el('button', { id: 'session-delete', text: 'Delete…', onclick: () => {
        confirmDelete.hidden = false;
        message.textContent = 'moved to .deleted/ in the sessions directory (remove it there to free the disk)';
      } }), confirmDelete, message));
  }

  // url: where the file is (default: the session's own files).
  async play(session, file, url = `/api/sessions/${encodeURIComponent(session)}/files/${encodeURIComponent(file)}`) {
    this.player.title.textContent = `loading ${file}…`;
    try {
      if (file.endsWith('.mdb')) {
        await this.playMesh(session, file, url);
        return;
      }
      if (file.endsWith('.mca')) {
        const recording = await openArchive(url, (r) => {
          this.player.title.dataset.decoded = String(r.decodedFrames);
          if (r.error) this.player.title.textContent = `${file}: ${r.error}`;
        });
        this.player.title.dataset.decoded = String(recording.decodedFrames);
        this.player.load(recording, `${session}/${file}`);
        return;
      }
      const text = await getText(url);
      this.player.load(parseMarkerFile(file, text), `${session}/${file}`);
    } catch (e) {
      this.player.title.textContent = `${file}: ${e.message}`;
    }
  }

  async playMesh(session, file, url) {
    const binding = parseMeshBinding(await getBytes(url));
    const { files } = await getJson(`/api/sessions/${encodeURIComponent(session)}`);
    const source = (files.find((f) => f.name.endsWith('.mca')) || files.find((f) => f.name === 'markers.trc') || {}).name;
    if (!source) throw new Error('the session holds no .mca or markers.trc to drive the mesh');
    const sourceUrl = `/api/sessions/${encodeURIComponent(session)}/files/${encodeURIComponent(source)}`;
    const recording = source.endsWith('.mca') ? await openArchive(sourceUrl)
      : parseMarkerFile(source, await getText(sourceUrl));
    this.player.load(recording, `${session}/${file} on ${source}, ${binding.vertices} vertices`,
      new MeshDriver(binding, recording.markers));
  }
}
