// PELT_fur for glTF-Transform (docs/extension/PELT_fur/README.md): the primitive's fin
// records as an Accessor reference and the material's fur textures (every mip level) as
// Texture references, so that prune, dedup, weld, reorder, quantize and meshopt keep and
// remap them. At write, it follows the spec's writer rules: fin records whose triangles a
// transform changed (weld, reorder, simplify, join) are recomputed with a new `computedFrom`,
// and fur `length` follows the scale a transform moved out of the positions (quantize, join).
import {
  Extension,
  ExtensionProperty,
  Primitive,
  PropertyType,
  RefList,
  TextureInfo,
} from '@gltf-transform/core';
import { MeshoptDecoder, MeshoptEncoder } from 'meshoptimizer';
import { buildFins, canonicalizeForMeshopt, cornerList, indexHash } from './fins.js';

await Promise.all([MeshoptEncoder.ready, MeshoptDecoder.ready]);

export const PELT_FUR = 'PELT_fur';
const STEMS = ['heightfield', 'dots', 'fin'];
const FIN_USAGE = 'PELT_FIN';

/** What every PELT_fur property sets in `init()`: its extension, type and parent type. */
function initProperty(property, propertyType, parentType) {
  property.extensionName = PELT_FUR;
  property.propertyType = propertyType;
  property.parentTypes = [parentType];
}

/** A primitive's PELT_fur: plain fields (`info`) and the fin records accessor. */
export class FurPrimitive extends ExtensionProperty {
  static EXTENSION_NAME = PELT_FUR;
  init() {
    initProperty(this, 'PeltFurPrimitive', PropertyType.PRIMITIVE);
  }
  getDefaults() {
    return Object.assign(super.getDefaults(), {
      info: {}, fins: null, added: null, removed: null, extent: null,
    });
  }
  getInfo() { return this.get('info'); }
  setInfo(info) { return this.set('info', info); }
  getFins() { return this.getRef('fins'); }
  setFins(a) { return this.setRef('fins', a, { usage: FIN_USAGE }); }
  getAdded() { return this.getRef('added'); }
  setAdded(a) { return this.setRef('added', a, { usage: FIN_USAGE }); }
  getRemoved() { return this.getRef('removed'); }
  setRemoved(a) { return this.setRef('removed', a, { usage: FIN_USAGE }); }
  /** The largest side of the positions' bounds when read (not written: it tells the writer
   * what scale a transform moved out of the positions). */
  getExtent() { return this.get('extent'); }
  setExtent(e) { return this.set('extent', e); }
}

/** The largest side of a POSITION accessor's bounds, as decoded. */
function extent(position) {
  if (!position || position.getCount() === 0) return null;
  const lo = position.getMinNormalized([]);
  const hi = position.getMaxNormalized([]);
  return Math.max(...hi.map((h, k) => h - lo[k]));
}

/** A material's PELT_fur: plain fields and, per texture, level 0 with its TextureInfo and
 * the textures of the other levels. */
export class FurMaterial extends ExtensionProperty {
  static EXTENSION_NAME = PELT_FUR;
  init() {
    initProperty(this, 'PeltFurMaterial', PropertyType.MATERIAL);
  }
  getDefaults() {
    const d = Object.assign(super.getDefaults(), { info: {} });
    for (const s of STEMS) {
      d[`${s}Texture`] = null;
      d[`${s}TextureInfo`] = new TextureInfo(this.graph, `${s}TextureInfo`);
      d[`${s}Meta`] = {};
      d[`${s}Mips`] = new RefList();
    }
    return d;
  }
  getInfo() { return this.get('info'); }
  setInfo(info) { return this.set('info', info); }
  getTexture(stem) { return this.getRef(`${stem}Texture`); }
  setTexture(stem, t) { return this.setRef(`${stem}Texture`, t); }
  getTextureInfo(stem) { return this.getRef(`${stem}Texture`) ? this.getRef(`${stem}TextureInfo`) : null; }
  getMeta(stem) { return this.get(`${stem}Meta`); }
  setMeta(stem, m) { return this.set(`${stem}Meta`, m); }
  listMips(stem) { return this.listRefs(`${stem}Mips`); }
  addMip(stem, t) { return this.addRef(`${stem}Mips`, t); }
}

/** The PELT_fur extension. */
export class PeltFur extends Extension {
  static EXTENSION_NAME = PELT_FUR;
  extensionName = PELT_FUR;
  prewriteTypes = [PropertyType.ACCESSOR, PropertyType.MESH];

  createPrimitive() { return new FurPrimitive(this.document.getGraph()); }
  createMaterial() { return new FurMaterial(this.document.getGraph()); }

  read(context) {
    const json = context.jsonDoc.json;
    (json.meshes || []).forEach((meshDef, m) => {
      (meshDef.primitives || []).forEach((primDef, p) => {
        const def = primDef.extensions && primDef.extensions[PELT_FUR];
        if (!def) return;
        const fur = this.createPrimitive();
        const { fins, ...info } = def;
        const finInfo = { ...(fins || {}) };
        if (fins && fins.accessor !== undefined) fur.setFins(context.accessors[fins.accessor]);
        if (fins && fins.fromIndices) {
          const { added, removed } = fins.fromIndices;
          if (added !== undefined) fur.setAdded(context.accessors[added]);
          if (removed !== undefined) fur.setRemoved(context.accessors[removed]);
        }
        delete finInfo.accessor;
        delete finInfo.fromIndices;
        fur.setInfo({ ...info, fins: fins ? finInfo : undefined });
        const prim = context.meshes[m].listPrimitives()[p];
        fur.setExtent(extent(prim.getAttribute('POSITION')));
        prim.setExtension(PELT_FUR, fur);
      });
    });
    (json.materials || []).forEach((matDef, m) => {
      const def = matDef.extensions && matDef.extensions[PELT_FUR];
      if (!def) return;
      const fur = this.createMaterial();
      const info = { ...def };
      for (const s of STEMS) {
        const t = def[`${s}Texture`];
        delete info[`${s}Texture`];
        if (!t) continue;
        const source = (i) => context.textures[json.textures[i].source];
        fur.setTexture(s, source(t.index));
        context.setTextureInfo(fur.getTextureInfo(s), t);
        fur.setMeta(s, { format: t.format, width: t.width, height: t.height });
        for (const i of t.mipLevels || []) fur.addMip(s, source(i));
      }
      fur.setInfo(info);
      context.materials[m].setExtension(PELT_FUR, fur);
    });
    return this;
  }

  prewrite(context, type) {
    if (type !== PropertyType.ACCESSOR) return this;
    this.unshare();
    this.followScale();
    const meshopt = this.document
      .getRoot()
      .listExtensionsUsed()
      .some((e) => e.extensionName === 'EXT_meshopt_compression');
    for (const p of this.properties) {
      if (p instanceof FurPrimitive) this.refreshFins(p, meshopt);
    }
    for (const p of this.properties) {
      if (!(p instanceof FurPrimitive)) continue;
      for (const a of [p.getFins(), p.getAdded(), p.getRemoved()]) {
        if (a) context.addAccessorToUsageGroup(a, FIN_USAGE);
      }
    }
    return this;
  }

  /** The primitives that carry `fur`. */
  primitivesOf(fur) {
    return fur.listParents().filter((p) => p instanceof Primitive);
  }

  /** Gives each primitive its own FurPrimitive: a cloned primitive shares its original's, and
   * its records and `computedFrom` describe one index list. */
  unshare() {
    for (const fur of [...this.properties]) {
      if (!(fur instanceof FurPrimitive)) continue;
      for (const prim of this.primitivesOf(fur).slice(1)) {
        prim.setExtension(PELT_FUR, fur.clone());
      }
    }
  }

  /** Recomputes the fin records of the primitives whose index list changed since they were
   * computed (spec, "What a writer must do", 3), or drops them where no rule applies.
   * `meshopt`: whether the file is written with EXT_meshopt_compression. */
  refreshFins(fur, meshopt) {
    const info = fur.getInfo();
    const from = info.computedFrom;
    const prim = this.primitivesOf(fur)[0];
    if (!from || !prim || !info.fins) return;
    if (meshopt && prim.getIndices() && prim.getMode() === Primitive.Mode.TRIANGLES) {
      canonicalizeForMeshopt(prim.getIndices(), { MeshoptEncoder, MeshoptDecoder });
    }
    const corners = cornerList(prim);
    const hash = indexHash(corners);
    if (from.triangles === corners.length / 3 && from.indexHash === hash) return;
    const logger = this.document.getLogger();
    const comb = prim.getAttribute(info.combAttribute || '_FUR_COMB');
    const old = [fur.getFins(), fur.getAdded(), fur.getRemoved()].filter(Boolean);
    fur.setFins(null).setAdded(null).setRemoved(null);
    for (const a of old) if (a.listParents().every((q) => q.propertyType === 'Root')) a.dispose();
    const { fins, computedFrom, edges, ...rest } = info;
    if (prim.getMode() !== Primitive.Mode.TRIANGLES || !comb || corners.length % 3 !== 0) {
      const mesh = prim.listParents().find((p) => p.propertyType === PropertyType.MESH);
      logger.warn(
        `${PELT_FUR}: mesh "${mesh ? mesh.getName() : '?'}": fins dropped: the primitive is ` +
          'no longer a triangle list with a comb',
      );
      fur.setInfo(rest);
      return;
    }
    const built = buildFins(prim, comb);
    const buffer = this.document.getRoot().listBuffers()[0];
    const accessor = this.document
      .createAccessor()
      .setType('VEC2')
      .setArray(built.records)
      .setBuffer(buffer);
    fur.setFins(accessor);
    fur.setInfo({
      ...rest,
      edges: { unique: built.unique, boundary: built.boundary, nonmanifold: built.nonmanifold },
      fins: { bareEdgesLeftOut: built.bare },
      computedFrom: { triangles: corners.length / 3, indexHash: hash },
    });
    logger.info(`${PELT_FUR}: ${built.records.length / 2} fin records recomputed (triangles changed)`);
  }

  /** Scales each fur material's `length` by the scale a transform moved out of the positions
   * of its primitives (spec, "What a writer must do", 4); a material whose primitives moved
   * by different scales is split. */
  followScale() {
    const byMaterial = new Map();
    for (const fur of this.properties) {
      if (!(fur instanceof FurPrimitive)) continue;
      for (const prim of this.primitivesOf(fur)) {
        const now = extent(prim.getAttribute('POSITION'));
        const was = fur.getExtent();
        const material = prim.getMaterial();
        if (!now || !was || !material || !material.getExtension(PELT_FUR)) continue;
        const ratio = Math.abs(now / was - 1) < 1e-4 ? 1 : now / was;
        const list = byMaterial.get(material) || [];
        list.push({ prim, ratio });
        byMaterial.set(material, list);
        fur.setExtent(now);
      }
    }
    for (const [material, uses] of byMaterial) {
      const ratios = [...new Set(uses.map((u) => u.ratio))];
      ratios.forEach((ratio, i) => {
        if (ratio === 1 && i === 0) return;
        let target = material;
        if (i > 0) {
          target = material.clone();
          target.setExtension(PELT_FUR, material.getExtension(PELT_FUR).clone());
          for (const u of uses) if (u.ratio === ratio) u.prim.setMaterial(target);
        }
        if (ratio === 1) return;
        const fur = target.getExtension(PELT_FUR);
        const info = fur.getInfo();
        fur.setInfo({ ...info, length: info.length * ratio });
      });
    }
  }

  write(context) {
    const json = context.jsonDoc.json;
    const root = this.document.getRoot();
    for (const mesh of root.listMeshes()) {
      const meshDef = json.meshes[context.meshIndexMap.get(mesh)];
      mesh.listPrimitives().forEach((prim, p) => {
        const fur = prim.getExtension(PELT_FUR);
        if (!fur) return;
        const { fins: finInfo, ...info } = fur.getInfo();
        const def = { ...info };
        const index = (a) => {
          const i = context.accessorIndexMap.get(a);
          if (i === undefined) throw new Error(`${PELT_FUR}: a fin accessor was not written`);
          return i;
        };
        if (finInfo) {
          const fins = { ...finInfo };
          if (fur.getFins()) fins.accessor = index(fur.getFins());
          if (fur.getAdded() || fur.getRemoved()) {
            fins.fromIndices = {};
            if (fur.getAdded()) fins.fromIndices.added = index(fur.getAdded());
            if (fur.getRemoved()) fins.fromIndices.removed = index(fur.getRemoved());
          }
          def.fins = fins;
        }
        const primDef = meshDef.primitives[p];
        primDef.extensions = primDef.extensions || {};
        primDef.extensions[PELT_FUR] = def;
      });
    }
    for (const material of root.listMaterials()) {
      const fur = material.getExtension(PELT_FUR);
      if (!fur) continue;
      const def = { ...fur.getInfo() };
      for (const s of STEMS) {
        const t = fur.getTexture(s);
        if (!t) continue;
        const ti = fur.getTextureInfo(s);
        const info = context.createTextureInfoDef(t, ti);
        const mips = fur.listMips(s).map((m) => context.createTextureInfoDef(m, ti).index);
        def[`${s}Texture`] = { ...info, ...fur.getMeta(s), ...(mips.length ? { mipLevels: mips } : {}) };
      }
      const matDef = json.materials[context.materialIndexMap.get(material)];
      matDef.extensions = matDef.extensions || {};
      matDef.extensions[PELT_FUR] = def;
    }
    return this;
  }
}
