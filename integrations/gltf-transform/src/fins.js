// Fin records recomputed from a primitive's triangles, by the rule of
// docs/extension/PELT_fur/README.md ("Fin records"): one record per welded edge (positions
// welded when bit-equal, -0 as +0) of the proper triangles, as the corners where it starts in
// its two lowest triangles, in order of its ends' welded ids (lower, higher); degenerate
// triangles (two corners welded into one position, or zero area) have no edges; edges with
// comb length 0 at both ends in both triangles are left out. The same rule and order as
// pelt's bake (crates/pelt-geom/src/topology.rs and fins.rs).

import xxhash from 'xxhash-wasm';

const { h32Raw } = await xxhash();

export const NO_CORNER = 0xffffffff;

/** The corner after `c` in its triangle. */
export const nextCorner = (c) => c - (c % 3) + ((c + 1) % 3);

/** xxHash32 (seed 0) of the index list as little-endian u32 values (computedFrom.indexHash).
 * `corners` is a Uint32Array (JavaScript engines are little-endian). */
export function indexHash(corners) {
  const u32 = corners instanceof Uint32Array ? corners : Uint32Array.from(corners);
  return h32Raw(new Uint8Array(u32.buffer, u32.byteOffset, u32.byteLength), 0) >>> 0;
}

/** The primitive's index list (0, 1, 2, … without indices), as a Uint32Array. */
export function cornerList(prim) {
  const indices = prim.getIndices();
  if (indices) return Uint32Array.from(indices.getArray());
  const n = prim.getAttribute('POSITION').getCount();
  return Uint32Array.from({ length: n }, (_, i) => i);
}

/** Dense welded ids of the positions, numbered in order of first appearance. */
function weldPositions(position) {
  const n = position.getCount();
  const ids = new Uint32Array(n);
  const seen = new Map();
  const bits = new Float32Array(3);
  const words = new Uint32Array(bits.buffer);
  const el = [];
  for (let v = 0; v < n; v++) {
    position.getElement(v, el);
    for (let k = 0; k < 3; k++) bits[k] = el[k] === 0 ? 0 : el[k];
    const key = `${words[0]},${words[1]},${words[2]}`;
    let id = seen.get(key);
    if (id === undefined) {
      id = seen.size;
      seen.set(key, id);
    }
    ids[v] = id;
  }
  return ids;
}

/** Whether triangle (a, b, c) of positions has a usable normal (a finite, nonzero cross). */
function hasArea(position, a, b, c) {
  // As f32 values (as pelt decodes them), subtracted in f64.
  const p = [a, b, c].map((v) => position.getElement(v, []).map(Math.fround));
  const u = [0, 1, 2].map((k) => p[1][k] - p[0][k]);
  const w = [0, 1, 2].map((k) => p[2][k] - p[0][k]);
  const n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
  const len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  return Number.isFinite(len2) && len2 > 0;
}

/**
 * The fin records of a TRIANGLES primitive: `{ records: Uint32Array (c0, c1 pairs), unique,
 * boundary, nonmanifold, bare }`. `comb` is the `_FUR_COMB` accessor (its w is the length).
 */
export function buildFins(prim, comb) {
  const corners = cornerList(prim);
  const position = prim.getAttribute('POSITION');
  const pid = weldPositions(position);
  const cp = (c) => pid[corners[c]];
  const sides = [];
  for (let f = 0; f < corners.length / 3; f++) {
    const [a, b, c] = [0, 1, 2].map((k) => cp(3 * f + k));
    if (a === b || b === c || a === c) continue;
    if (!hasArea(position, corners[3 * f], corners[3 * f + 1], corners[3 * f + 2])) continue;
    for (let k = 0; k < 3; k++) {
      const s = 3 * f + k;
      const [x, y] = [cp(s), cp(nextCorner(s))];
      sides.push([Math.min(x, y), Math.max(x, y), f, s]);
    }
  }
  sides.sort((p, q) => p[0] - q[0] || p[1] - q[1] || p[2] - q[2]);
  const el = [];
  const furry = (c) => comb.getElement(corners[c], el)[3] > 0;
  const keep = (c) => furry(c) || furry(nextCorner(c));
  const records = [];
  let [unique, boundary, nonmanifold, bare] = [0, 0, 0, 0];
  for (let i = 0; i < sides.length; ) {
    let j = i + 1;
    while (j < sides.length && sides[j][0] === sides[i][0] && sides[j][1] === sides[i][1]) j++;
    const run = j - i;
    unique++;
    boundary += run === 1 ? 1 : 0;
    nonmanifold += run > 2 ? 1 : 0;
    const c0 = sides[i][3];
    const c1 = run > 1 ? sides[i + 1][3] : NO_CORNER;
    if (keep(c0) || (c1 !== NO_CORNER && keep(c1))) records.push(c0, c1);
    else bare++;
    i = j;
  }
  return { records: Uint32Array.from(records), unique, boundary, nonmanifold, bare };
}

/**
 * EXT_meshopt_compression's triangle codec may rotate each triangle's corners (a, b, c) to
 * (b, c, a): the triangles and their winding stay, the corners (which fin records name) move.
 * When the file will be written with it, the index accessor is given the order its decoder
 * will return (the codec keeps an order it produced), so that records and `computedFrom` are
 * computed from the index list a reader will see. `codec` is meshoptimizer's
 * { MeshoptEncoder, MeshoptDecoder }, both ready.
 */
export function canonicalizeForMeshopt(indices, codec) {
  const array = indices.getArray();
  const size = array.BYTES_PER_ELEMENT;
  if (array.length % 3 !== 0 || (size !== 2 && size !== 4)) return;
  const source = new Uint8Array(array.buffer, array.byteOffset, array.byteLength);
  const encoded = codec.MeshoptEncoder.encodeGltfBuffer(source, array.length, size, 'TRIANGLES');
  const decoded = new Uint8Array(array.byteLength);
  codec.MeshoptDecoder.decodeGltfBuffer(decoded, array.length, size, encoded, 'TRIANGLES');
  indices.setArray(new array.constructor(decoded.buffer));
}
