// The writer rules at write time, through a real write and read: a primitive whose triangles
// changed gets fresh records and computedFrom, a cloned primitive gets its own, and scale moved
// out of the positions scales the fur length.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { Document, NodeIO } from '@gltf-transform/core';
import { PeltFur, PELT_FUR } from '../src/index.js';
import { buildFins, cornerList, indexHash } from '../src/fins.js';

/** A furry quad (two triangles) with stale-free PELT_fur, as a pelt bake writes it. */
function furryQuad() {
  const doc = new Document();
  const buffer = doc.createBuffer();
  const acc = (type, array) => doc.createAccessor().setType(type).setArray(array).setBuffer(buffer);
  const prim = doc
    .createPrimitive()
    .setAttribute('POSITION', acc('VEC3', new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0])))
    .setAttribute('_FUR_COMB', acc('VEC4', new Float32Array([0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1])))
    .setIndices(acc('SCALAR', new Uint32Array([0, 1, 2, 2, 1, 3])));
  const ext = doc.createExtension(PeltFur);
  const built = buildFins(prim, prim.getAttribute('_FUR_COMB'));
  const fur = ext.createPrimitive().setInfo({
    combAttribute: '_FUR_COMB',
    fins: { bareEdgesLeftOut: 0 },
    computedFrom: { triangles: 2, indexHash: indexHash(cornerList(prim)) },
  });
  fur.setFins(acc('VEC2', built.records));
  prim.setExtension(PELT_FUR, fur);
  const material = doc.createMaterial('fur');
  const furMaterial = ext.createMaterial().setInfo({ length: 0.5, shells: 8, uvScale: 1 });
  material.setExtension(PELT_FUR, furMaterial);
  prim.setMaterial(material);
  const mesh = doc.createMesh('quad').addPrimitive(prim);
  doc.createScene().addChild(doc.createNode('quad').setMesh(mesh));
  return { doc, prim, mesh };
}

/** The glTF JSON the document writes as (the writer rules run at write). */
async function written(doc) {
  return new NodeIO().registerExtensions([PeltFur]).writeJSON(doc);
}

function primitiveDefs(json) {
  return json.json.meshes.flatMap((m) => m.primitives);
}

test('records whose triangles changed are recomputed; fresh ones are kept', async () => {
  const { doc, prim } = furryQuad();
  const kept = primitiveDefs(await written(doc))[0].extensions[PELT_FUR];
  // Rotate the triangles (a reorder): the stored records name the wrong corners now.
  prim.getIndices().setArray(new Uint32Array([2, 1, 3, 0, 1, 2]));
  const json = await written(doc);
  const def = primitiveDefs(json)[0].extensions[PELT_FUR];
  assert.notDeepEqual(def.computedFrom, kept.computedFrom);
  assert.equal(def.computedFrom.indexHash, indexHash(new Uint32Array([2, 1, 3, 0, 1, 2])));
  const acc = json.json.accessors[def.fins.accessor];
  assert.equal(acc.type, 'VEC2');
  assert.equal(acc.count, 5);
});

test('a cloned primitive gets records for its own triangles', async () => {
  const { doc, prim, mesh } = furryQuad();
  const copy = prim.clone();
  copy.setIndices(prim.getIndices().clone().setArray(new Uint32Array([1, 3, 2, 0, 1, 2])));
  mesh.addPrimitive(copy);
  const defs = primitiveDefs(await written(doc));
  const [a, b] = defs.map((d) => d.extensions[PELT_FUR].computedFrom.indexHash);
  assert.equal(a, indexHash(new Uint32Array([0, 1, 2, 2, 1, 3])));
  assert.equal(b, indexHash(new Uint32Array([1, 3, 2, 0, 1, 2])));
});

test('scale moved out of the positions scales the fur length', async () => {
  const { doc, prim } = furryQuad();
  const io = new NodeIO().registerExtensions([PeltFur]);
  const read = await io.readJSON(await io.writeJSON(doc));
  const p = read.getRoot().listMeshes()[0].listPrimitives()[0];
  // What quantize does: positions divided by 4, the node scaled by 4.
  const pos = p.getAttribute('POSITION');
  pos.setArray(pos.getArray().map((v) => v / 4));
  read.getRoot().listNodes()[0].setScale([4, 4, 4]);
  const json = await io.writeJSON(read);
  assert.equal(json.json.materials[0].extensions[PELT_FUR].length, 0.125);
  // Negative control: untouched positions keep the length.
  const again = await io.writeJSON(await io.readJSON(await io.writeJSON(doc)));
  assert.equal(again.json.materials[0].extensions[PELT_FUR].length, 0.5);
  assert.equal(prim.getExtension(PELT_FUR).getInfo().computedFrom.triangles, 2);
});
