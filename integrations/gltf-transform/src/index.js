// PELT_fur for glTF-Transform (docs/extension/PELT_fur/README.md): the primitive's fin
// records as an Accessor reference and the material's fur textures (every mip level) as
// Texture references, so that prune, dedup, weld, reorder, quantize and meshopt keep and
// remap them. Work in progress: stale records are not yet recomputed at write.
import {
  Extension,
  ExtensionProperty,
  PropertyType,
  RefList,
  TextureInfo,
} from '@gltf-transform/core';

export const PELT_FUR = 'PELT_fur';
const STEMS = ['heightfield', 'dots', 'fin'];
const FIN_USAGE = 'PELT_FIN';

/** A primitive's PELT_fur: plain fields (`info`) and the fin records accessor. */
export class FurPrimitive extends ExtensionProperty {
  static EXTENSION_NAME = PELT_FUR;
  init() {
    this.extensionName = PELT_FUR;
    this.propertyType = 'PeltFurPrimitive';
    this.parentTypes = [PropertyType.PRIMITIVE];
  }
  getDefaults() {
    return Object.assign(super.getDefaults(), { info: {}, fins: null, added: null, removed: null });
  }
  getInfo() { return this.get('info'); }
  setInfo(info) { return this.set('info', info); }
  getFins() { return this.getRef('fins'); }
  setFins(a) { return this.setRef('fins', a, { usage: FIN_USAGE }); }
  getAdded() { return this.getRef('added'); }
  setAdded(a) { return this.setRef('added', a, { usage: FIN_USAGE }); }
  getRemoved() { return this.getRef('removed'); }
  setRemoved(a) { return this.setRef('removed', a, { usage: FIN_USAGE }); }
}

/** A material's PELT_fur: plain fields and, per texture, level 0 with its TextureInfo and
 * the textures of the other levels. */
export class FurMaterial extends ExtensionProperty {
  static EXTENSION_NAME = PELT_FUR;
  init() {
    this.extensionName = PELT_FUR;
    this.propertyType = 'PeltFurMaterial';
    this.parentTypes = [PropertyType.MATERIAL];
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
        context.meshes[m].listPrimitives()[p].setExtension(PELT_FUR, fur);
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
    for (const p of this.properties) {
      if (!(p instanceof FurPrimitive)) continue;
      for (const a of [p.getFins(), p.getAdded(), p.getRemoved()]) {
        if (a) context.addAccessorToUsageGroup(a, FIN_USAGE);
      }
    }
    return this;
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
