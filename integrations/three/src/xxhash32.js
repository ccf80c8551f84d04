// xxHash32 (seed 0) over u32 values as little-endian bytes: `computedFrom.indexHash` of
// docs/extension/PELT_fur ("Stale records"). Every input is a whole number of 4-byte lanes,
// so only the spec's 4-byte tail step is needed. Check values: [] → 46947589,
// [0, 1, 2, 2, 1, 3] → 1175828522 (test/xxhash32.test.js).

const P1 = 2654435761;
const P2 = 2246822519;
const P3 = 3266489917;
const P4 = 668265263;
const P5 = 374761393;

const rotl = (x, r) => (x << r) | (x >>> (32 - r));
const round = (acc, lane) => Math.imul(rotl((acc + Math.imul(lane, P2)) | 0, 13), P1);

/** xxHash32 (seed 0) of the Uint32Array `words`. */
export function indexHash(words) {
  const n = words.length;
  let i = 0;
  let h;
  if (n >= 4) {
    let v1 = (P1 + P2) | 0;
    let v2 = P2;
    let v3 = 0;
    let v4 = -P1 | 0;
    for (; i + 4 <= n; i += 4) {
      v1 = round(v1, words[i]);
      v2 = round(v2, words[i + 1]);
      v3 = round(v3, words[i + 2]);
      v4 = round(v4, words[i + 3]);
    }
    h = (rotl(v1, 1) + rotl(v2, 7) + rotl(v3, 12) + rotl(v4, 18)) | 0;
  } else {
    h = P5;
  }
  h = (h + n * 4) | 0;
  for (; i < n; i++) h = Math.imul(rotl((h + Math.imul(words[i], P3)) | 0, 17), P4);
  h ^= h >>> 15;
  h = Math.imul(h, P2);
  h ^= h >>> 13;
  h = Math.imul(h, P3);
  h ^= h >>> 16;
  return h >>> 0;
}
