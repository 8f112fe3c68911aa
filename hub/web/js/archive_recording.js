// A .mca archive as a recording the sessions page's player plays while it still downloads: a
// Web Worker (archive_worker.js) fetches and decodes it window by window; open() resolves as soon
// as the header and the first window are here, and later windows fill in behind the playhead.
// Frames not decoded yet show no points.

export class ArchiveRecording {
  constructor(header) {
    this.rate = header.rate;
    this.markers = header.names;
    this.frameNumbers = header.frameNumbers;
    this.frameCount = header.frames;
    this.window = header.window;
    this.windows = [];      // Float32Array per decoded window
    this.decodedFrames = 0;
    this.complete = false;
  }

  pointsAt(i) {
    const positions = this.windows[Math.floor(i / this.window)];
    if (!positions) return [];
    const markers = this.markers.length;
    const base = (i % this.window) * markers * 3;
    const points = [];
    for (let m = 0; m < markers; ++m) {
      const x = positions[base + 3 * m];
      if (!Number.isNaN(x)) points.push([x, positions[base + 3 * m + 1], positions[base + 3 * m + 2], m, 0]);
    }
    return points;
  }

  add(message) {
    this.windows[Math.floor(message.first / this.window)] = message.positions;
    this.decodedFrames += message.count;
  }
}

// Resolves with the recording once its first window is decoded; onProgress(recording) follows
// every later window and the end; rejects on an error before the first window (later errors go
// to onProgress's recording.error).
export function openArchive(url, onProgress = () => {}) {
  return new Promise((resolve, reject) => {
    const worker = new Worker(new URL('./archive_worker.js', import.meta.url), { type: 'module' });
    let recording = null;
    let resolved = false;
    worker.onmessage = (event) => {
      const message = event.data;
      if (message.type === 'header') {
        recording = new ArchiveRecording(message);
      } else if (message.type === 'window') {
        recording.add(message);
        if (!resolved) {
          resolved = true;
          resolve(recording);
        } else {
          onProgress(recording);
        }
      } else if (message.type === 'end') {
        recording.complete = true;
        worker.terminate();
        onProgress(recording);
      } else if (message.type === 'error') {
        worker.terminate();
        if (!resolved) reject(new Error(message.message));
        else {
          recording.error = message.message;
          onProgress(recording);
        }
      }
    };
    worker.onerror = (event) => {
      worker.terminate();
      if (!resolved) reject(new Error(event.message || 'archive worker failed'));
    };
    worker.postMessage({ url: new URL(url, location.href).href });
  });
}
