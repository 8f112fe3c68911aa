// A module Web Worker that downloads one .mca archive and decodes it as it streams in
// (archive_decoder.js), posting the header and then each window of frames (their Float32Array
// transferred, not copied) to the page: {type: 'header' | 'window' | 'end' | 'error', ...}.
import { ArchiveDecoder } from './archive_decoder.js';

self.onmessage = async (event) => {
  const decoder = new ArchiveDecoder();
  try {
    const response = await fetch(event.data.url);
    if (!response.ok) throw new Error(`${response.status} ${response.statusText}`);
    const reader = response.body.getReader();
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      for (const message of decoder.push(value)) {
        self.postMessage(message, message.positions ? [message.positions.buffer] : []);
      }
    }
    decoder.finish();
    self.postMessage({ type: 'end' });
  } catch (e) {
    self.postMessage({ type: 'error', message: e.message });
  }
};
