// The .mca archive (hub/src/archive/archive_format.h, version 2) decoded as its bytes arrive:
// push() takes each chunk of the download and returns what became complete, the header first,
// then one message per window of frames (a window's range-coded chunk once all of it arrived), so a player can start on the first seconds of an hour's take.
// Limits and refusals as the hub's reader (it names the field); errors throw Error.
//   {type: 'header', rate, names, frames, firstFrame, frameNumbers (Float64Array), window}
//   {type: 'window', first, count, positions: Float32Array(count * markers * 3), NaN for gaps}
import { RangeDecoder, newBitModel, newIntModel } from './archive_range_decoder.js';

const MAX_MARKERS = 4096;
const MAX_WINDOW = 4096;
const MAX_POINTS = 2 ** 28;
const POINTS_PER_BYTE = 1024;
const MEAN_STEP_MM = 1 / 256;

class NeedMore extends Error {}

export class ArchiveDecoder {
  constructor() {
    this.bytes = new Uint8Array(0);
    this.pos = 0;
    this.header = null;
    this.windowIndex = 0;
  }

  push(chunk) {
    const merged = new Uint8Array(this.bytes.length - this.pos + chunk.length);
    merged.set(this.bytes.subarray(this.pos));
    merged.set(chunk, this.bytes.length - this.pos);
    this.bytes = merged;
    this.pos = 0;
    this.view = new DataView(merged.buffer);
    const out = [];
    try {
      for (;;) {
        const start = this.pos;
        try {
          const message = this.header ? this.nextWindow() : this.readHeader();
          if (message) out.push(message);
          if (this.header && this.windowIndex >= this.windows) break;
        } catch (e) {
          if (!(e instanceof NeedMore)) throw e;
          this.pos = start;
          break;
        }
      }
    } finally {
      this.bytes = this.bytes.subarray(this.pos);
      this.pos = 0;
      this.view = new DataView(this.bytes.buffer, this.bytes.byteOffset, this.bytes.byteLength);
    }
    return out;
  }

  // Throws unless the whole archive arrived and nothing followed it.
  finish() {
    if (!this.header || this.windowIndex < this.windows) throw new Error('archive: the file ends before its last block');
    if (this.bytes.length) throw new Error(`archive: ${this.bytes.length} bytes after the last block`);
  }

  need(n) { if (this.pos + n > this.bytes.length) throw new NeedMore(); }
  u8() { this.need(1); return this.bytes[this.pos++]; }
  u32() { this.need(4); const v = this.view.getUint32(this.pos, true); this.pos += 4; return v; }
  f32() { this.need(4); const v = this.view.getFloat32(this.pos, true); this.pos += 4; return v; }
  f64() { this.need(8); const v = this.view.getFloat64(this.pos, true); this.pos += 8; return v; }
  u64() { this.need(8); const v = this.view.getBigUint64(this.pos, true); this.pos += 8; return Number(v); }
  varint(field) {
    let value = 0;
    for (let i = 0; i < 5; ++i) {
      const b = this.u8();
      if (i === 4 && b > 0x0f) throw new Error(`archive: ${field}: varint larger than 32 bits`);
      value += (b & 0x7f) * 2 ** (7 * i);
      if (!(b & 0x80)) {
        if (i > 0 && b === 0) throw new Error(`archive: ${field}: varint not in its shortest form`);
        return value;
      }
    }
    throw new Error(`archive: ${field}: varint longer than 5 bytes`);
  }
  signed(field) {
    const raw = this.varint(field);
    return raw % 2 ? -(raw - 1) / 2 - 1 : raw / 2;
  }
  floats(n, field) {
    this.need(4 * n);
    const out = new Float32Array(n);
    for (let i = 0; i < n; ++i) out[i] = this.view.getFloat32(this.pos + 4 * i, true);
    this.pos += 4 * n;
    for (const v of out) if (!Number.isFinite(v)) throw new Error(`archive: ${field}: not a finite number`);
    return out;
  }

  readHeader() {
    const magic = String.fromCharCode(...Array.from({ length: 8 }, () => this.u8()));
    if (magic !== 'MOCAPMCA') throw new Error('archive: magic: not a mocap archive (.mca starts with MOCAPMCA)');
    const version = this.u32();
    if (version === 1) throw new Error('archive: version: 1 (plain-varint blocks, before the range coder) is not supported; this reader knows version 2: write the archive again with mocap-hub archive');
    if (version !== 2) throw new Error(`archive: version: ${version} is not supported (this reader knows version 2)`);
    const rate = this.f64();
    if (!(rate > 0) || !Number.isFinite(rate)) throw new Error(`archive: rate_hz: ${rate} is not > 0`);
    const markers = this.u32(), frames = this.u32(), window = this.u32();
    if (markers < 1 || markers > MAX_MARKERS) throw new Error(`archive: markers: ${markers} is outside 1..${MAX_MARKERS}`);
    if (frames < 1 || frames * markers > MAX_POINTS) throw new Error(`archive: frames: ${frames} x ${markers} markers is too many`);
    if (window < 1 || window > MAX_WINDOW) throw new Error(`archive: window: ${window} is outside 1..${MAX_WINDOW}`);
    const numbering = this.u8();
    if (numbering > 1) throw new Error(`archive: numbering: ${numbering} is neither 0 nor 1`);
    const frameNumbers = new Float64Array(frames);
    frameNumbers[0] = this.u64();
    for (let i = 1; i < frames; ++i) {
      const step = numbering === 1 ? this.varint('frame increment') : 1;
      if (step === 0) throw new Error('archive: frame increment: 0; frame numbers must increase');
      frameNumbers[i] = frameNumbers[i - 1] + step;
    }
    const names = [];
    for (let m = 0; m < markers; ++m) {
      const length = this.u8();
      if (!length) throw new Error(`archive: name length: 0 for marker ${m}`);
      this.need(length);
      names.push(new TextDecoder().decode(this.bytes.subarray(this.pos, this.pos + length)));
      this.pos += length;
    }
    const groupCount = this.u32();
    if (groupCount < 1 || groupCount > markers) throw new Error(`archive: groups: ${groupCount} is outside 1..${markers}`);
    const grouped = new Uint8Array(markers);
    const groups = [];
    for (let g = 0; g < groupCount; ++g) {
      const size = this.u32();
      if (size < 1 || size > markers) throw new Error(`archive: group size: ${size} is outside 1..${markers}`);
      const group = [];
      for (let j = 0; j < size; ++j) {
        const m = this.u32();
        if (m >= markers || grouped[m]) throw new Error(`archive: group markers: marker ${m} is out of range or in two groups`);
        grouped[m] = 1;
        group.push(m);
      }
      groups.push(group);
    }
    if (grouped.includes(0)) throw new Error('archive: groups: a marker is in no group');
    const gapRuns = [];
    for (let m = 0; m < markers; ++m) {
      const count = this.varint('gap run count');
      if (count < 1 || count > frames + 1) throw new Error(`archive: gap run count: ${count} is outside 1..${frames + 1}`);
      const runs = [];
      let total = 0;
      for (let r = 0; r < count; ++r) { runs.push(this.varint('gap run')); total += runs[r]; }
      if (total !== frames) throw new Error(`archive: gap runs: marker ${m}'s runs cover ${total} frames, not ${frames}`);
      gapRuns.push(runs);
    }
    this.header = { rate, names, frames, window, frameNumbers, groups, gapRuns };
    this.windows = Math.ceil(frames / window);
    // Every marker's quantised mean in the window before, the base of the next window's means.
    this.means = new Float64Array(3 * markers);
    // Per marker: the run it is in and where that run ends, advanced window by window.
    this.runCursor = gapRuns.map((runs) => ({ run: 0, end: runs[0] }));
    return { type: 'header', rate, names, frames, window, frameNumbers };
  }

  // One window's range-coded chunk, once all of it arrived: its blocks group by group.
  nextWindow() {
    const h = this.header;
    const first = this.windowIndex * h.window;
    const count = Math.min(h.window, h.frames - first);
    const markers = h.names.length;
    const length = this.varint('window chunk length');
    const minimum = Math.max(5, Math.ceil((count * markers) / POINTS_PER_BYTE));
    if (length < minimum) throw new Error(`archive: window chunk length: ${length} bytes, under the format's minimum ${minimum}`);
    this.need(length);
    const coder = new RangeDecoder(this.bytes.subarray(this.pos, this.pos + length));
    const models = {
      relative: newBitModel(), components: newIntModel(), mean: newIntModel(), timeStart: newIntModel(),
      time: Array.from({ length: 8 }, () => [newIntModel(), newIntModel(), newIntModel()]),
      weights: Array.from({ length: 8 }, newIntModel),
    };
    const values = new Float32Array(count * markers * 3);
    try {
      if (!coder.bit(models.relative, 0)) this.means.fill(0);
      for (const group of h.groups) this.decodeBlock(coder, models, group, count, values);
    } catch (e) {
      throw new Error(`archive: window ${this.windowIndex}: ${e.message}`);
    }
    if (coder.pos !== length) throw new Error(`archive: window ${this.windowIndex}: ${length - coder.pos} bytes left after its blocks`);
    this.pos += length;
    this.applyGaps(first, count, values);
    this.windowIndex += 1;
    return { type: 'window', first, count, positions: values };
  }

  decodeBlock(coder, models, group, count, values) {
    const markers = this.header.names.length;
    const channels = 3 * group.length;
    const limit = 2 ** 29 - 1;
    const k = coder.int(models.components, 'components');
    if (k < 0 || k > Math.min(count, channels)) throw new Error(`components: ${k} is outside 0..the window's rank`);
    const mean = new Float64Array(channels);
    for (let c = 0; c < channels; ++c) {
      const slot = 3 * group[Math.floor(c / 3)] + (c % 3);
      const now = this.means[slot] + coder.int(models.mean, 'mean');
      if (Math.abs(now) > limit) throw new Error(`mean: value ${now} is outside +-(2^29 - 1)`);
      this.means[slot] = now;
      mean[c] = MEAN_STEP_MM * now;
    }
    // time[t * k + q] and weights[c * k + q] as numbers, steps applied.
    const time = new Float64Array(count * k);
    const weights = new Float64Array(channels * k);
    if (k > 0) {
      const timeStep = coder.float();
      if (!(timeStep > 0) || !Number.isFinite(timeStep)) throw new Error('time step: not a finite number > 0');
      for (let q = 0; q < k; ++q) {
        const context = models.time[Math.min(q, 7)];
        let before = 0, earlier = 0, previous = 0;
        for (let t = 0; t < count; ++t) {
          const size = previous === 0 ? 0 : Math.abs(previous) <= 2 ? 1 : 2;
          const delta = coder.int(t < 2 ? models.timeStart : context[size], 'time');
          const now = t === 0 ? delta : t === 1 ? before + delta : 2 * before - earlier + delta;
          if (Math.abs(now) > limit) throw new Error(`time: value ${now} is outside +-(2^29 - 1)`);
          time[t * k + q] = timeStep * now;
          earlier = before;
          before = now;
          previous = delta;
        }
      }
      for (let q = 0; q < k; ++q) {
        const step = coder.float();
        if (!(step > 0) || !Number.isFinite(step)) throw new Error('weight step: not a finite number > 0');
        const model = models.weights[Math.min(q, 7)];
        for (let c = 0; c < channels; ++c) weights[c * k + q] = step * coder.int(model, 'weights');
      }
    }
    for (let t = 0; t < count; ++t) {
      for (let c = 0; c < channels; ++c) {
        let v = mean[c];
        for (let q = 0; q < k; ++q) v += time[t * k + q] * weights[c * k + q];
        values[(t * markers + group[Math.floor(c / 3)]) * 3 + (c % 3)] = v;
      }
    }
  }

  applyGaps(first, count, values) {
    const h = this.header;
    const markers = h.names.length;
    for (let m = 0; m < markers; ++m) {
      const cursor = this.runCursor[m];
      const runs = h.gapRuns[m];
      for (let t = first; t < first + count; ++t) {
        while (t >= cursor.end) { cursor.run += 1; cursor.end += runs[cursor.run]; }
        if (cursor.run % 2 === 1) values.fill(NaN, (( t - first) * markers + m) * 3, ((t - first) * markers + m) * 3 + 3);
      }
    }
  }
}
