// The fin rule of docs/extension/PELT_fur/README.md on small meshes, and the index hash
// against an independently computed value.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Document } from '@gltf-transform/core';
import { buildFins, indexHash, NO_CORNER } from '../src/fins.js';

/** A primitive over `positions` (flat xyz list) with `indices` and per-vertex comb lengths. */
function primitive(positions, indices, lengths) {
  const doc = new Document();
  const buffer = doc.createBuffer();
  const acc = (type, array) => doc.createAccessor().setType(type).setArray(array).setBuffer(buffer);
  const comb = new Float32Array(lengths.flatMap((l) => [0, 0, 1, l]));
  return doc
    .createPrimitive()
    .setAttribute('POSITION', acc('VEC3', new Float32Array(positions)))
    .setAttribute('_FUR_COMB', acc('VEC4', comb))
    .setIndices(acc('SCALAR', new Uint32Array(indices)));
}

// Two triangles (0 1 2) and (2 1 3) sharing edge 1-2.
const QUAD = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0];

test('index hash is xxHash32 over little-endian u32 indices', () => {
  // The xxHash C library's values (Python's xxhash.xxh32), as pelt's own test has them.
  assert.equal(indexHash(new Uint32Array([])), 46947589);
  assert.equal(indexHash(new Uint32Array([0, 1, 2, 2, 1, 3])), 1175828522);
  assert.notEqual(indexHash(new Uint32Array([1, 2, 0, 2, 1, 3])), 1175828522);
});

test('one record per welded edge, in order of its ends, shared edges with both corners', () => {
  const prim = primitive(QUAD, [0, 1, 2, 2, 1, 3], [1, 1, 1, 1]);
  const f = buildFins(prim, prim.getAttribute('_FUR_COMB'));
  // By welded ends: (0,1) from corner 0, (0,2) from corner 2 (2→0), (1,2) from corners 1 and
  // 3 (triangle (2 1 3) runs 2→1 from corner 3), (1,3) from corner 4, (2,3) from corner 5.
  assert.deepEqual([...f.records], [0, NO_CORNER, 2, NO_CORNER, 1, 3, 4, NO_CORNER, 5, NO_CORNER]);
  assert.equal(f.unique, 5);
  assert.equal(f.boundary, 4);
});

test('a seam split only by UVs is one edge; bare edges are left out and counted', () => {
  // Vertex 4 duplicates vertex 2's position (a UV seam): the shared edge still has two faces.
  const seam = [...QUAD, 0, 1, 0];
  const prim = primitive(seam, [0, 1, 2, 4, 1, 3], [0, 1, 0, 0, 0]);
  const f = buildFins(prim, prim.getAttribute('_FUR_COMB'));
  // Fur only at vertex 1: the edges with it at an end are kept, (1,2) with both corners
  // though its triangles use different vertices (2 and 4) at one end.
  assert.equal(f.unique, 5);
  assert.equal(f.bare, 2);
  assert.deepEqual([...f.records], [0, NO_CORNER, 1, 3, 4, NO_CORNER]);
});

test('degenerate triangles make no edges', () => {
  const prim = primitive(QUAD, [0, 1, 2, 1, 1, 3], [1, 1, 1, 1]);
  const f = buildFins(prim, prim.getAttribute('_FUR_COMB'));
  assert.equal(f.unique, 3);
});
