// Fin records (docs/extension/PELT_fur, "Fin records") as instance attributes of the fin
// quads (fins.wgsl's FinIn, built as crates/pelt-scene/src/fur.rs's fin_instances builds
// them): per record the edge's two vertices (position, normal, tangent, tangent-space comb),
// both faces' normals, the fin texture's offset and the edge's length in UV units, and the
// texture coordinates of its middle. Records whose `computedFrom` no longer matches the index
// list are stale and are not read (the caller warns); corners outside the index list are a
// corrupt file.

import { mix64 } from './density.js';
import { indexHash } from './xxhash32.js';

export const NO_CORNER = 0xffffffff;
/** Fins stand only where the fur at one end is longer than this share of the length. */
export const FIN_MIN_LENGTH = 0.05;

const nextCorner = (c) => c - (c % 3) + ((c + 1) % 3);

/** The geometry's index list (0, 1, 2, … without an index), as a Uint32Array. */
export function cornerList(geometry) {
  if (geometry.index) return Uint32Array.from(geometry.index.array);
  return Uint32Array.from({ length: geometry.attributes.position.count }, (_, i) => i);
}

/** Whether the records were computed from this index list: null, or why they are stale. */
export function staleness(corners, computedFrom) {
  if (!computedFrom) return 'no computedFrom';
  const triangles = corners.length / 3;
  if (computedFrom.triangles !== triangles) return `${computedFrom.triangles} triangles recorded, ${triangles} now`;
  const h = indexHash(corners);
  if (computedFrom.indexHash !== h) return `index hash ${computedFrom.indexHash} recorded, ${h} now`;
  return null;
}

/** The fin texture's horizontal offset of edge (a, b) (pelt_scene::fur::edge_offset). */
export function edgeOffset(a, b) {
  const z = mix64((BigInt(Math.min(a, b)) << 32n) | BigInt(Math.max(a, b)));
  return Number(z >> 40n) / 2 ** 24;
}

/**
 * Per-fin instance arrays for `records` (Uint32Array of corner pairs) over `geometry`, whose
 * comb attribute decodes by `decodeComb(i) → [x, y, z, w]`. Throws on a corner outside the
 * index list (`place` names the records in the message).
 */
export function finArrays(geometry, corners, records, decodeComb, place) {
  const pos = geometry.attributes.position;
  const nor = geometry.attributes.normal;
  const tan = geometry.attributes.tangent;
  const uv = geometry.attributes.uv;
  const count = records.length / 2;
  const out = {
    p0: new Float32Array(count * 3), p1: new Float32Array(count * 3),
    n0: new Float32Array(count * 3), n1: new Float32Array(count * 3),
    t0: new Float32Array(count * 4), t1: new Float32Array(count * 4),
    c0: new Float32Array(count * 4), c1: new Float32Array(count * 4),
    fu: new Float32Array(count * 2), fuv: new Float32Array(count * 2),
    faces: new Uint32Array(count * 6),
    ends: new Uint32Array(count * 2),
  };
  const n = corners.length;
  for (let f = 0; f < count; f++) {
    const [r0, r1] = [records[2 * f], records[2 * f + 1]];
    const whole = (c) => c < n && c - (c % 3) + 2 < n;
    if (!whole(r0) || (r1 !== NO_CORNER && !whole(r1))) {
      throw new Error(`${place}[${f}]: corner (${r0}, ${r1}) outside the ${n} corners of the index list`);
    }
    const a = corners[r0];
    const b = corners[nextCorner(r0)];
    out.ends.set([a, b], f * 2);
    const second = r1 === NO_CORNER ? r0 : r1;
    for (const [k, c] of [[0, r0], [3, second]]) {
      const t = c - (c % 3);
      out.faces.set([corners[t], corners[t + 1], corners[t + 2]], f * 6 + k);
    }
    const ca = decodeComb(a);
    const cb = decodeComb(b);
    const bare = Math.max(ca[3], cb[3]) <= FIN_MIN_LENGTH;
    for (const [v, c, p, nn, tt, cc] of [[a, ca, out.p0, out.n0, out.t0, out.c0], [b, cb, out.p1, out.n1, out.t1, out.c1]]) {
      p.set([pos.getX(v), pos.getY(v), pos.getZ(v)], f * 3);
      nn.set([nor.getX(v), nor.getY(v), nor.getZ(v)], f * 3);
      tt.set(tan ? [tan.getX(v), tan.getY(v), tan.getZ(v), tan.getW(v)] : [1, 0, 0, 1], f * 4);
      cc.set([c[0], c[1], c[2], bare ? 0 : c[3]], f * 4);
    }
    const [ua, va, ub, vb] = uv ? [uv.getX(a), uv.getY(a), uv.getX(b), uv.getY(b)] : [0, 0, 0, 0];
    out.fu.set([edgeOffset(a, b), Math.hypot(ua - ub, va - vb)], f * 2);
    out.fuv.set([0.5 * (ua + ub), 0.5 * (va + vb)], f * 2);
  }
  return out;
}

/** Face normals of the fins' two faces (f0, f1) from `position(i) → [x, y, z]`. */
export function faceNormals(faces, position) {
  const count = faces.length / 6;
  const f0 = new Float32Array(count * 3);
  const f1 = new Float32Array(count * 3);
  for (let f = 0; f < count; f++) {
    for (const [k, out] of [[0, f0], [3, f1]]) {
      const [p, q, r] = [0, 1, 2].map((j) => position(faces[f * 6 + k + j]));
      const u = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
      const w = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
      const c = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
      const len = Math.hypot(...c);
      out.set(len > 0 ? c.map((x) => x / len) : [0, 0, 0], f * 3);
    }
  }
  return { f0, f1 };
}
