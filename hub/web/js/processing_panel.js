// Processing a session from the console: a recipe form (POST /api/sessions/NAME/process), the
// jobs with their progress and the last lines of their log (GET /api/processing, polled while a
// job is queued or running), and each recipe's results with links and Play (SESSION/processed/
// RECIPE/). The hub runs `mocap-hub process` for each job (docs/api.md), so a result equals the
// command line's for the same recipe.
import { el, getJson, postJson } from './api.js';

const POLL_MS = 1000;
const active = (job) => job.state === 'queued' || job.state === 'running';

function percent(progress) {
  if (!progress || !progress.total) return 0;
  return Math.min(100, Math.round((100 * progress.done) / progress.total));
}

export class ProcessingPanel {
  // onPlay(session, recipe, file): play one of a recipe's results; onFinished(session): a job of
  // that session ended (the caller shows its results again); onEdit(session, recipe): open the
  // trajectory editor on a recipe's results (editor_panel.js).
  constructor(onPlay, onFinished, onEdit) {
    this.onPlay = onPlay;
    this.onFinished = onFinished;
    this.onEdit = onEdit;
    this.session = null;
    this.timer = null;
    this.seenActive = new Set();
    this.recipeName = el('input', { type: 'text', id: 'process-name', value: 'default', size: '12' });
    this.trc = el('input', { type: 'checkbox', id: 'process-trc', checked: '' });
    this.c3d = el('input', { type: 'checkbox', id: 'process-c3d' });
    this.gap = el('input', { type: 'number', id: 'process-gap', value: '0.05', min: '0', max: '10', step: '0.01' });
    this.labels = el('select', { id: 'process-labels' }, el('option', { value: '', text: 'no marker set' }),
      el('option', { value: 'serve', text: "serve's marker set" }));
    this.bodies = el('select', { id: 'process-bodies' }, el('option', { value: '', text: 'no rigid bodies' }),
      el('option', { value: 'serve', text: "serve's rigid bodies" }));
    this.overwrite = el('input', { type: 'checkbox', id: 'process-overwrite' });
    // The session's own calibration is checked against its blobs first; a misfit fails the job
    // with every camera's residual unless this is ticked.
    this.forceCalibration = el('input', { type: 'checkbox', id: 'process-force-calibration' });
    this.message = el('span', { class: 'message', id: 'process-message' });
    this.jobs = el('tbody', { id: 'processing-jobs' });
    this.results = el('div', { id: 'processed-results' });
    this.element = el('div', { class: 'processing', id: 'processing' },
      el('h3', { text: 'Process' }),
      el('div', { class: 'toolbar' }, el('span', { text: 'Recipe' }), this.recipeName,
        el('label', {}, this.trc, ' TRC'), el('label', {}, this.c3d, ' C3D'),
        el('span', { text: 'fill gaps up to (s)' }), this.gap, this.labels, this.bodies,
        el('label', {}, this.overwrite, ' replace results'),
        el('label', { title: "reconstruct even when the session's calibration does not fit its cameras" },
          this.forceCalibration, ' even with a misfit calibration'),
        el('button', { id: 'process-start', text: 'Process', onclick: () => this.start() }), this.message),
      this.results,
      el('table', { class: 'jobs' }, el('thead', {}, el('tr', {}, ...['Job', 'Session', 'Recipe', 'State',
        'Progress', 'Log'].map((t) => el('th', { text: t })))), this.jobs));
  }

  // The form for `session`, with its results (the session's "processed" list).
  showFor(session, processed) {
    this.session = session;
    const base = `/api/sessions/${encodeURIComponent(session)}/processed/`;
    this.results.replaceChildren(...(processed || []).map((p) => el('div', { class: 'processed', 'data-recipe': p.recipe },
      el('span', { text: `${p.recipe}: ` }),
      p.files.some((f) => f.name === 'markers.trc') ? el('button', { text: 'Edit', 'data-action': 'edit-result',
        onclick: () => this.onEdit(session, p.recipe) }) : '',
      ...p.files.map((f) => el('span', { class: 'result-file' },
        el('a', { href: `${base}${encodeURIComponent(p.recipe)}/files/${encodeURIComponent(f.name)}`, download: f.name,
          text: f.name }),
        f.name.endsWith('.trc') ? el('button', { text: 'Play', 'data-action': 'play-result',
          onclick: () => this.onPlay(session, p.recipe, f.name) }) : ' ')))));
    this.refresh();
  }

  recipe() {
    const outputs = [this.trc.checked ? 'trc' : null, this.c3d.checked ? 'c3d' : null].filter(Boolean);
    const recipe = { name: this.recipeName.value.trim(), outputs, max_spline_gap_s: Number(this.gap.value) };
    if (this.labels.value) recipe.labels = this.labels.value;
    if (this.bodies.value) recipe.bodies = this.bodies.value;
    if (this.forceCalibration.checked) recipe.force_calibration = true;
    return recipe;
  }

  async start() {
    if (!this.session) return;
    try {
      const job = await postJson(`/api/sessions/${encodeURIComponent(this.session)}/process`,
        { recipe: this.recipe(), overwrite: this.overwrite.checked });
      this.message.textContent = `job ${job.id} ${job.state}`;
    } catch (e) {
      this.message.textContent = `not processed: ${e.message}`;
    }
    this.refresh();
  }

  async refresh() {
    clearTimeout(this.timer);
    let list;
    try {
      list = await getJson('/api/processing');
    } catch (e) {
      return;
    }
    this.jobs.replaceChildren(...list.jobs.map((job) => el('tr', { 'data-job': String(job.id), 'data-state': job.state },
      el('td', { text: String(job.id) }), el('td', { text: job.session }), el('td', { text: job.recipe }),
      el('td', { class: `state ${job.state}`, text: job.state, title: job.reason || '' }),
      el('td', {}, el('progress', { max: '100', value: String(percent(job.progress)) }),
        ` ${percent(job.progress)} %`),
      el('td', { class: 'log', title: job.log.join('\n'), text: job.log.length ? job.log[job.log.length - 1] : '' }))));
    for (const job of list.jobs) {
      if (active(job)) this.seenActive.add(job.id);
      else if (this.seenActive.delete(job.id)) this.onFinished(job.session);
    }
    if (list.jobs.some(active)) this.timer = setTimeout(() => this.refresh(), POLL_MS);
  }

  stop() {
    clearTimeout(this.timer);
  }
}
