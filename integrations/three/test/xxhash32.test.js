import { test } from 'node:test';
import assert from 'node:assert/strict';
import { indexHash } from '../src/xxhash32.js';

test('xxHash32 gives the specification check values', () => {
  assert.equal(indexHash(new Uint32Array([])), 46947589);
  assert.equal(indexHash(new Uint32Array([0, 1, 2, 2, 1, 3])), 1175828522);
  // Negative control: one index changed changes the hash.
  assert.notEqual(indexHash(new Uint32Array([0, 1, 2, 2, 1, 4])), 1175828522);
});

test('xxHash32 agrees with the reference (xxhash-wasm) on lists longer than one stripe', () => {
  // Values from xxhash-wasm 1.1.0's h32Raw over the same bytes.
  for (const [n, want] of [[5, 3667186696], [17, 3258861056], [1000, 745047615]]) {
    const w = Uint32Array.from({ length: n }, (_, i) => (i * 2654435761) >>> 0);
    assert.equal(indexHash(w), want, `n = ${n}`);
  }
});
