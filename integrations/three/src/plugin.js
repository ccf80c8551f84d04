// PeltFurPlugin: a GLTFLoader plugin (loader.register((parser) => new PeltFurPlugin(parser)))
// that draws the PELT_fur extension (docs/extension/PELT_fur) as pelt's forward mode does:
// each fur primitive's base mesh lit along the strands, its shells in one instanced draw
// (instance = shell, blended over inner to outer), and its fins from the fin records. The
// mesh keeps its place in the scene graph, its skeleton and its animations; the plugin
// replaces its material and adds the shells and fins as its children.

import * as THREE from 'three';
import { density, strandParams } from './density.js';
import { cornerList, faceNormals, finArrays, staleness } from './fins.js';
import { finFragment, finVertex, shellDepthFragment, shellFragment, shellVertex } from './shaders.js';

export const EXTENSION = 'PELT_fur';

/** Uniforms every fur material shares: the scene's wind (xyz world direction × strength, w
 * the time in seconds) and gusts (x frequency, y turbulence). */
export const furShared = {
  peltWind: { value: new THREE.Vector4() },
  peltGust: { value: new THREE.Vector4() },
};

/** Sets the wind every fur material bends by (pelt's scene `wind`), at time `t` seconds. */
export function setWind(direction, strength, gustHz, turbulence, t) {
  const d = new THREE.Vector3(...direction).normalize().multiplyScalar(strength);
  furShared.peltWind.value.set(d.x, d.y, d.z, t);
  furShared.peltGust.value.set(gustHz, turbulence, 0, 0);
}

const linear = (c) => new THREE.Color().setRGB(c[0], c[1], c[2], THREE.LinearSRGBColorSpace);

/** A half-float RGBA texture of the density bins from `first`, with its box-filtered levels. */
function densityTexture(d, first) {
  const mipmaps = d.levels.map((level, l) => {
    const side = Math.max(d.side >> l, 1);
    const data = new Uint16Array(side * side * 4);
    for (let i = 0; i < side * side; i++) {
      for (let k = 0; k < 4; k++) data[i * 4 + k] = THREE.DataUtils.toHalfFloat(level[i * 8 + first + k]);
    }
    return { data, width: side, height: side };
  });
  const t = new THREE.DataTexture(mipmaps[0].data, d.side, d.side, THREE.RGBAFormat, THREE.HalfFloatType);
  t.mipmaps = mipmaps;
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.minFilter = THREE.LinearMipmapLinearFilter;
  t.magFilter = THREE.LinearFilter;
  t.generateMipmaps = false;
  t.needsUpdate = true;
  return t;
}

export class PeltFurPlugin {
  /**
   * @param parser GLTFLoader's parser.
   * @param options `shells`: a shell count for every fur primitive (default: by screen
   *   size, the manifest's `shellRule`, at most its `shells`);
   *   `fins`: draw the silhouette fins (default false, as pelt with its analytic coverage);
   *   `warn`: where warnings go (default console.warn); `control`: 'opaque-shells' draws
   *   every shell opaque (a negative control of the tests; the scene loader has more).
   */
  constructor(parser, options = {}) {
    this.name = EXTENSION;
    this.parser = parser;
    this.options = options;
    this.warn = options.warn || ((m) => console.warn(m));
    this.materials = new Map();
  }

  async afterRoot(result) {
    const json = this.parser.json;
    if (!(json.extensionsUsed || []).includes(EXTENSION)) return;
    const meshes = [];
    for (const scene of result.scenes) {
      scene.traverse((o) => {
        if (o.isMesh && o.geometry.attributes._fur_comb && !o.userData.peltFur) meshes.push(o);
      });
    }
    for (const mesh of meshes) await this.attach(mesh);
  }

  /** The glTF primitive and material behind a three mesh. */
  primitiveOf(mesh) {
    const a = this.parser.associations.get(mesh);
    if (!a || a.meshes === undefined) return null;
    const prim = this.parser.json.meshes[a.meshes].primitives[a.primitives ?? 0];
    return { prim, place: `meshes[${a.meshes}].primitives[${a.primitives ?? 0}]` };
  }

  /** The shared look of glTF material `m`: manifest, density and fin textures. */
  async furMaterial(m) {
    if (!this.materials.has(m)) this.materials.set(m, this.loadFurMaterial(m));
    return this.materials.get(m);
  }

  async loadFurMaterial(m) {
    const place = `materials[${m}].extensions.${EXTENSION}`;
    const ext = this.parser.json.materials?.[m]?.extensions?.[EXTENSION];
    if (!ext) return null;
    const d = density(strandParams(ext.strands || {}));
    const fin = await this.levels(ext.finTexture, `${place}.finTexture`);
    fin.wrapS = THREE.RepeatWrapping;
    fin.wrapT = THREE.ClampToEdgeWrapping;
    return { ext, place, density: d, densityLo: densityTexture(d, 0), densityHi: densityTexture(d, 4), fin };
  }

  /** A fur texture with its stored levels as the texture's mipmaps. */
  async levels(info, place) {
    if (!info || !Number.isInteger(info.index)) throw new Error(`${place}: index is missing`);
    const indices = [info.index, ...(info.mipLevels || [])];
    const chain = Math.floor(Math.log2(Math.max(info.width, info.height))) + 1;
    if (indices.length > chain) throw new Error(`${place}: ${indices.length} levels for a ${info.width}×${info.height} texture`);
    const levels = await Promise.all(indices.map((i) => this.parser.getDependency('texture', i)));
    const t = levels[0].clone();
    t.mipmaps = levels.map((l) => l.image);
    t.generateMipmaps = false;
    t.minFilter = THREE.LinearMipmapLinearFilter;
    t.magFilter = THREE.LinearFilter;
    t.colorSpace = THREE.NoColorSpace;
    t.flipY = false;
    t.needsUpdate = true;
    return t;
  }

  async attach(mesh) {
    const found = this.primitiveOf(mesh);
    if (!found) return;
    const { prim, place } = found;
    const pext = prim.extensions?.[EXTENSION];
    if (!pext || prim.material === undefined) return;
    const fur = await this.furMaterial(prim.material);
    if (!fur) return;
    const geometry = mesh.geometry;
    if (!geometry.attributes.tangent) {
      geometry.computeTangents();
      this.warn(`${place}: no TANGENT; three's tangents were computed (pelt regenerates by ${pext.tangents || 'mikktspace'})`);
    }
    const source = mesh.material;
    const look = furLook(fur, source, geometry, this.options.shells, this.options.control);
    mesh.material = look.material(shellVertex, shellFragment, { baseOnly: { value: 1 } });
    const shells = new THREE.InstancedBufferGeometry();
    shells.index = geometry.index;
    for (const [k, a] of Object.entries(geometry.attributes)) shells.setAttribute(k, a);
    shells.instanceCount = look.uniforms.shells.value;
    if (!geometry.boundingSphere) geometry.computeBoundingSphere();
    shells.boundingSphere = geometry.boundingSphere.clone();
    const layer = mesh.isSkinnedMesh ? new THREE.SkinnedMesh(shells, look.material(shellVertex, shellFragment, { baseOnly: { value: 0 } }, true)) : new THREE.Mesh(shells, look.material(shellVertex, shellFragment, { baseOnly: { value: 0 } }, true));
    if (mesh.isSkinnedMesh) layer.bind(mesh.skeleton, mesh.bindMatrix);
    layer.name = `${mesh.name} shells`;
    layer.frustumCulled = false;
    layer.renderOrder = 1;
    layer.userData.peltFurPart = true;
    // The shells cast by their coverage (shellDepthFragment), for every kind of light.
    layer.castShadow = true;
    layer.customDepthMaterial = look.depthMaterial();
    layer.customDistanceMaterial = layer.customDepthMaterial;
    const rule = this.options.shells === undefined ? shellRule(fur.ext, fur.place) : null;
    const state = { look, rule, max: look.uniforms.shells.value, pixels: 0 };
    layer.onBeforeRender = (renderer, _scene, camera) => applyRule(state, layer, renderer, camera);
    // Three draws the shadow maps first: the count of this frame's view there too.
    layer.onBeforeShadow = (renderer, _object, camera) => applyRule(state, layer, renderer, camera);
    mesh.add(layer);
    const fins = this.fins(mesh, pext, look, place);
    if (fins) {
      // As pelt draws them by default with the analytic coverage: off unless asked for.
      fins.visible = this.options.fins ?? false;
      mesh.add(fins);
    }
    mesh.userData.peltFur = { look, shells: layer, fins, place, rule: state };
  }

  /** The fin mesh of a primitive (null without valid records). */
  fins(mesh, pext, look, place) {
    if (!pext.fins) return null;
    if (pext.fins.accessor === undefined) {
      this.warn(`${place}: fins stored as fromIndices (pelt bake --compress) are not read by this runtime; drawn without fins`);
      return null;
    }
    const corners = cornerList(mesh.geometry);
    const why = staleness(corners, pext.computedFrom);
    if (why) {
      this.warn(`${place}: the fin records are stale (${why}); drawn without fins`);
      return null;
    }
    const accessor = this.parser.json.accessors[pext.fins.accessor];
    const rplace = `${place}.extensions.${EXTENSION}.fins`;
    if (!accessor || accessor.type !== 'VEC2' || accessor.componentType !== 5125) {
      throw new Error(`${rplace}: the records must be a VEC2 UNSIGNED_INT accessor`);
    }
    return new FinMesh(mesh, corners, look, rplace, this.parser.getDependency('accessor', pext.fins.accessor));
  }
}

/** The material's shells-by-screen-size rule (crates/pelt-fur/src/shells.rs), checked; null
 * in files written before it (their `shells` is always drawn). */
export function shellRule(ext, place) {
  const r = ext.shellRule;
  if (r === undefined) return null;
  if (!(Number.isFinite(r.pixelsPerShell) && r.pixelsPerShell > 0)) throw new Error(`${place}.shellRule.pixelsPerShell must be a positive number`);
  if (!(Number.isInteger(r.min) && r.min >= 1 && r.min <= 1024)) throw new Error(`${place}.shellRule.min must be 1 to 1024`);
  return r;
}

/** `clamp(⌈pixels / pixelsPerShell⌉, min, max)` (pelt_fur::shells::ShellRule::shells). */
export function shellsFor(rule, pixels, max) {
  const most = Math.max(max, 1);
  const least = Math.min(Math.max(rule.min, 1), most);
  if (!Number.isFinite(pixels)) return most;
  return Math.min(Math.max(Math.ceil(Math.max(pixels, 0) / rule.pixelsPerShell), least), most);
}

/** The longest the fur of `mesh` can project to on `renderer`'s drawing buffer, in pixels:
 * its length through the mesh's largest scale, at the nearest view depth of its bounding box
 * grown by the fur's length (pelt_scene::footprint::fur_pixels, over the asset's box). */
const scratch = { size: new THREE.Vector2(), box: new THREE.Box3(), toView: new THREE.Matrix4(), p: new THREE.Vector3() };

export function furPixels(mesh, furLength, renderer, camera) {
  const size = renderer.getDrawingBufferSize(scratch.size);
  const reach = furLength * mesh.matrixWorld.getMaxScaleOnAxis();
  if (camera.isOrthographicCamera) return (reach * size.y * camera.zoom) / (camera.top - camera.bottom);
  if (!mesh.geometry.boundingBox) mesh.geometry.computeBoundingBox();
  // Every shadow face and the view call this each frame: scratch objects, no allocation.
  const box = scratch.box.copy(mesh.geometry.boundingBox).expandByScalar(furLength);
  const toView = scratch.toView.multiplyMatrices(camera.matrixWorldInverse, mesh.matrixWorld);
  const p = scratch.p;
  let nearest = -Infinity;
  for (let k = 0; k < 8; k++) {
    p.set(k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y, k & 4 ? box.max.z : box.min.z).applyMatrix4(toView);
    nearest = Math.max(nearest, p.z);
  }
  const near = Math.max(-nearest, camera.near);
  const focal = size.y / (2 * Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2));
  return (reach * focal) / near;
}

/** Sets the shells drawn this frame by the rule (nothing when a count was forced). */
function applyRule(state, layer, renderer, camera) {
  if (!state.rule) return;
  state.pixels = furPixels(layer, state.look.uniforms.furLength.value, renderer, camera);
  const n = shellsFor(state.rule, state.pixels, state.max);
  state.look.uniforms.shells.value = n;
  layer.geometry.instanceCount = n;
}

/** The material uniforms of a fur primitive, and a maker of its materials. */
function furLook(fur, source, geometry, shells, control) {
  const ext = fur.ext;
  const comb = geometry.attributes._fur_comb;
  const unsigned = comb.normalized && (comb.array instanceof Uint8Array || comb.array instanceof Uint16Array);
  const base = source.map || null;
  // three's own materials update a texture's transform matrix as they draw; a ShaderMaterial
  // must do it itself.
  if (base?.matrixAutoUpdate) base.updateMatrix();
  const uniforms = {
    shells: { value: shells ?? ext.shells },
    furLength: { value: ext.length },
    uvScale: { value: ext.uvScale },
    rootColor: { value: linear(ext.baseColor) },
    tipColor: { value: linear(ext.tipColor) },
    colorFromTexture: { value: ext.colorFromTexture ? 1 : 0 },
    kappa: { value: fur.density.kappa },
    analytic: { value: 1 },
    combUnsigned: { value: unsigned ? 1 : 0 },
    albedo: { value: source.color ? source.color.clone() : new THREE.Color(1, 1, 1) },
    tint: { value: new THREE.Color(1, 1, 1) },
    baseMap: { value: base },
    useBaseMap: { value: base ? 1 : 0 },
    // KHR_texture_transform of the base colour texture (GLTFLoader sets the texture's matrix).
    baseMapTransform: { value: base ? base.matrix : new THREE.Matrix3() },
    densityLo: { value: fur.densityLo },
    densityHi: { value: fur.densityHi },
    finMap: { value: fur.fin },
    controlOpaque: { value: control === 'opaque-shells' ? 1 : 0 },
  };
  const material = (vertexShader, fragmentShader, extra, blended = false) => {
    const u = { ...THREE.UniformsUtils.clone(THREE.UniformsLib.lights), ...uniforms, ...furShared, ...extra };
    const m = new THREE.ShaderMaterial({ vertexShader, fragmentShader, uniforms: u, lights: true, glslVersion: null });
    if (blended) {
      m.transparent = true;
      m.depthWrite = false;
      m.depthFunc = THREE.LessEqualDepth;
      m.blending = THREE.CustomBlending;
      m.blendSrc = THREE.SrcAlphaFactor;
      m.blendDst = THREE.OneMinusSrcAlphaFactor;
      m.blendSrcAlpha = THREE.OneFactor;
      m.blendDstAlpha = THREE.OneMinusSrcAlphaFactor;
      m.side = THREE.FrontSide;
    } else {
      m.side = THREE.DoubleSide;
    }
    return m;
  };
  const depthMaterial = () => new THREE.ShaderMaterial({
    vertexShader: shellVertex,
    fragmentShader: shellDepthFragment,
    uniforms: { ...uniforms, ...furShared, baseOnly: { value: 0 } },
    defines: { PELT_DEPTH: '' },
  });
  return { uniforms, material, depthMaterial };
}

/** The fins of one fur mesh: an instanced quad per record, posed on the CPU when skinned. */
class FinMesh extends THREE.Mesh {
  constructor(mesh, corners, look, place, recordsPromise) {
    super(new THREE.InstancedBufferGeometry(), look.material(finVertex, finFragment, {}, true));
    this.material.side = THREE.DoubleSide;
    this.name = `${mesh.name} fins`;
    this.frustumCulled = false;
    this.userData.peltFurPart = true;
    this.castShadow = false;
    this.renderOrder = 2;
    this.source = mesh;
    this.ready = recordsPromise.then((records) => this.build(corners, look, records.array, place));
  }

  build(corners, look, records, place) {
    const g = this.source.geometry;
    const comb = g.attributes._fur_comb;
    const unsigned = look.uniforms.combUnsigned.value > 0.5;
    const decode = (i) => {
      const c = [comb.getX(i), comb.getY(i), comb.getZ(i), comb.getW(i)];
      return unsigned ? [2 * c[0] - 1, 2 * c[1] - 1, 2 * c[2] - 1, c[3]] : c;
    };
    const a = finArrays(g, corners, records, decode, place);
    this.arrays = a;
    const geo = this.geometry;
    geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(18), 3));
    for (const k of ['p0', 'p1', 'n0', 'n1', 't0', 't1', 'c0', 'c1', 'fu', 'fuv']) {
      geo.setAttribute(k, new THREE.InstancedBufferAttribute(a[k], a[k].length / (records.length / 2)));
    }
    const pos = g.attributes.position;
    const { f0, f1 } = faceNormals(a.faces, (i) => [pos.getX(i), pos.getY(i), pos.getZ(i)]);
    geo.setAttribute('f0', new THREE.InstancedBufferAttribute(f0, 3));
    geo.setAttribute('f1', new THREE.InstancedBufferAttribute(f1, 3));
    geo.instanceCount = records.length / 2;
    if (this.source.isSkinnedMesh) this.pose();
  }

  /** The fin attributes at the skinned mesh's current pose (SkinnedMesh.getVertexPosition;
   * normals and tangents by the same per-vertex affine skin). */
  pose() {
    const s = this.source;
    const a = this.arrays;
    if (!a) return;
    const g = this.geometry;
    const dir = new THREE.Vector3();
    const posed = (i, p) => s.getVertexPosition(i, p);
    const skinDir = (i, x, y, z, base) => {
      const src = s.geometry.attributes.position;
      dir.set(src.getX(i) + x, src.getY(i) + y, src.getZ(i) + z);
      s.applyBoneTransform(i, dir);
      return dir.sub(base);
    };
    const cache = new Map();
    const vertex = (i) => {
      if (!cache.has(i)) {
        const p = posed(i, new THREE.Vector3());
        const nor = s.geometry.attributes.normal;
        const tan = s.geometry.attributes.tangent;
        const n = skinDir(i, nor.getX(i), nor.getY(i), nor.getZ(i), p).clone();
        const t = skinDir(i, tan.getX(i), tan.getY(i), tan.getZ(i), p).clone();
        cache.set(i, { p, n, t, w: tan.getW(i) });
      }
      return cache.get(i);
    };
    const count = a.faces.length / 6;
    for (let f = 0; f < count; f++) {
      for (const [k, p, n, t] of [[0, 'p0', 'n0', 't0'], [1, 'p1', 'n1', 't1']]) {
        const v = vertex(a.ends[f * 2 + k]);
        g.attributes[p].array.set([v.p.x, v.p.y, v.p.z], f * 3);
        g.attributes[n].array.set([v.n.x, v.n.y, v.n.z], f * 3);
        g.attributes[t].array.set([v.t.x, v.t.y, v.t.z, v.w], f * 4);
      }
    }
    const { f0, f1 } = faceNormals(a.faces, (i) => vertex(i).p.toArray());
    g.attributes.f0.array.set(f0);
    g.attributes.f1.array.set(f1);
    for (const k of ['p0', 'p1', 'n0', 'n1', 't0', 't1', 'f0', 'f1']) g.attributes[k].needsUpdate = true;
  }
}
