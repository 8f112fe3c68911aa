// Marker files for playback, parsed in the browser: TRC (as `reconstruct` and OpenSim write
// it: tab-separated, a header of five lines, empty cells for gaps) and a capture's
// live_points.tsv (what serve published, one point per line). Both become a Recording:
//   {rate, frameNumbers: [N], markers: [name], frames: [[x, y, z, id, provisional], ...] per frame}
// Errors throw Error with the line number.

export function parseTrc(text) {
  const lines = text.split(/\r?\n/);
  if (!lines[0] || !lines[0].startsWith('PathFileType')) throw new Error('not a TRC file (line 1)');
  const keys = (lines[1] || '').split('\t');
  const values = (lines[2] || '').split('\t');
  const header = {};
  keys.forEach((key, i) => { header[key.trim()] = (values[i] || '').trim(); });
  const rate = parseFloat(header.DataRate || header.CameraRate);
  if (!(rate > 0)) throw new Error('TRC line 3: no DataRate');
  const scale = header.Units === 'm' ? 1000 : header.Units === 'cm' ? 10 : 1;
  const nameCells = (lines[3] || '').split('\t');
  if (nameCells[0] !== 'Frame#') throw new Error('TRC line 4: must start with Frame#');
  const markers = [];
  for (let i = 2; i < nameCells.length; i += 3) if (nameCells[i]) markers.push(nameCells[i]);
  const frames = [];
  const frameNumbers = [];
  for (let n = 5; n < lines.length; ++n) {
    if (!lines[n].trim()) continue;
    const cells = lines[n].split('\t');
    const frame = parseInt(cells[0], 10);
    if (!Number.isFinite(frame)) throw new Error(`TRC line ${n + 1}: Frame# is not a number`);
    const points = [];
    for (let m = 0; m < markers.length; ++m) {
      const x = cells[2 + 3 * m], y = cells[3 + 3 * m], z = cells[4 + 3 * m];
      if (!x || !y || !z) continue;  // a gap
      points.push([parseFloat(x) * scale, parseFloat(y) * scale, parseFloat(z) * scale, m, 0]);
    }
    frameNumbers.push(frame);
    frames.push(points);
  }
  return { rate, markers, frameNumbers, frames };
}

export function parseLivePoints(text) {
  const lines = text.split(/\r?\n/);
  const match = /^# mocap live points v[12] rate_hz=([0-9.]+)/.exec(lines[0] || '');
  if (!match) throw new Error('not a live points file (line 1)');
  const rate = parseFloat(match[1]);
  const frames = [];
  const frameNumbers = [];
  for (let n = 1; n < lines.length; ++n) {
    const line = lines[n];
    if (!line || line.startsWith('#') || line.startsWith('frame')) continue;
    const c = line.split('\t');
    if (c.length < 8) throw new Error(`live points line ${n + 1}: expected 8 columns`);
    const frame = parseInt(c[0], 10);
    if (frameNumbers.length === 0 || frameNumbers[frameNumbers.length - 1] !== frame) {
      frameNumbers.push(frame);
      frames.push([]);
    }
    frames[frames.length - 1].push([parseFloat(c[1]), parseFloat(c[2]), parseFloat(c[3]), parseInt(c[4], 10),
      parseInt(c[5], 10)]);
  }
  return { rate, markers: [], frameNumbers, frames };
}

export function parseMarkerFile(name, text) {
  return name.endsWith('.trc') ? parseTrc(text) : parseLivePoints(text);
}
