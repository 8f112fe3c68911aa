// A mesh bound to markers (.mdb, written by `mocap-hub mesh drive --binding`; layout in
// hub/src/registration/mesh_binding_file.h) and its deformation in the browser: per frame, each
// vertex is its bound position plus its RBF weights times the driving markers' displacements
// from the static frame, the hub's MarkerDrivenMesh::Deform with the weights it computed once.
// A frame missing a driving marker keeps the last shape (the hub re-solves the RBF without it;
// the console does not). Errors throw Error naming the field.

const LIMITS = { vertices: 2 ** 22, triangles: 2 ** 23, markers: 4096 };

export function parseMeshBinding(buffer) {
  const view = new DataView(buffer);
  const bytes = new Uint8Array(buffer);
  let pos = 0;
  const need = (n, field) => {
    if (pos + n > bytes.length) throw new Error(`mesh binding: ${field}: the file ends early`);
  };
  const u32 = (field) => { need(4, field); const v = view.getUint32(pos, true); pos += 4; return v; };
  need(8, 'magic');
  if (String.fromCharCode(...bytes.subarray(0, 8)) !== 'MOCAPMDB') throw new Error('mesh binding: magic: not a .mdb file');
  pos = 8;
  const version = u32('version');
  if (version !== 1) throw new Error(`mesh binding: version: ${version} is not supported (this reader knows 1)`);
  const vertices = u32('vertices'), triangles = u32('triangles'), markers = u32('markers');
  if (vertices < 1 || vertices > LIMITS.vertices) throw new Error(`mesh binding: vertices: ${vertices} is outside 1..2^22`);
  if (triangles > LIMITS.triangles) throw new Error(`mesh binding: triangles: ${triangles} is past 2^23`);
  if (markers < 4 || markers > LIMITS.markers) throw new Error(`mesh binding: markers: ${markers} is outside 4..4096`);
  const names = [];
  for (let i = 0; i < markers; ++i) {
    need(1, 'name length');
    const length = bytes[pos++];
    if (!length) throw new Error(`mesh binding: name length: 0 for marker ${i}`);
    need(length, 'name');
    names.push(new TextDecoder().decode(bytes.subarray(pos, pos + length)));
    pos += length;
  }
  const floats = (n, field) => {
    need(4 * n, field);
    const out = new Float32Array(n);
    for (let i = 0; i < n; ++i) out[i] = view.getFloat32(pos + 4 * i, true);
    pos += 4 * n;
    return out;
  };
  const staticPositions = floats(3 * markers, 'static');
  const bound = floats(3 * vertices, 'bound');
  need(12 * triangles, 'triangles');
  const index = new Uint32Array(3 * triangles);
  for (let i = 0; i < index.length; ++i) {
    index[i] = view.getUint32(pos + 4 * i, true);
    if (index[i] >= vertices) throw new Error(`mesh binding: triangles: vertex ${index[i]} is outside the mesh`);
  }
  pos += 12 * triangles;
  const weights = floats(vertices * markers, 'weights');
  if (pos !== bytes.length) throw new Error(`mesh binding: ${bytes.length - pos} bytes after the weights`);
  return { names, vertices, markers, staticPositions, bound, index, weights };
}

// Deforms a binding by the frames of a recording whose marker names include the driving ones.
export class MeshDriver {
  constructor(binding, recordingNames) {
    this.binding = binding;
    const column = new Map(recordingNames.map((name, i) => [name, i]));
    this.slotOf = new Map();
    binding.names.forEach((name, slot) => {
      if (!column.has(name)) throw new Error(`mesh binding: marker ${name} is not in the recording`);
      this.slotOf.set(column.get(name), slot);
    });
    this.positions = Float32Array.from(binding.bound);
    this.displacement = new Float64Array(3 * binding.markers);
    this.seen = new Uint8Array(binding.markers);
  }

  // points: [[x, y, z, column, ...], ...] of one frame. False (positions kept) when a driving
  // marker is missing.
  deform(points) {
    const { markers, vertices, weights, bound, staticPositions } = this.binding;
    const d = this.displacement;
    this.seen.fill(0);
    let present = 0;
    for (const p of points) {
      const slot = this.slotOf.get(p[3]);
      if (slot === undefined) continue;
      d[3 * slot] = p[0] - staticPositions[3 * slot];
      d[3 * slot + 1] = p[1] - staticPositions[3 * slot + 1];
      d[3 * slot + 2] = p[2] - staticPositions[3 * slot + 2];
      if (!this.seen[slot]) { this.seen[slot] = 1; present += 1; }
    }
    if (present < markers) return false;
    const out = this.positions;
    for (let v = 0, row = 0; v < vertices; ++v, row += markers) {
      let x = 0, y = 0, z = 0;
      for (let i = 0; i < markers; ++i) {
        const w = weights[row + i];
        x += w * d[3 * i];
        y += w * d[3 * i + 1];
        z += w * d[3 * i + 2];
      }
      out[3 * v] = bound[3 * v] + x;
      out[3 * v + 1] = bound[3 * v + 1] + y;
      out[3 * v + 2] = bound[3 * v + 2] + z;
    }
    return true;
  }
}
