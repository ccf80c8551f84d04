// pelt's scene files (docs/preview.md) in three.js: camera, ambient, point and directional
// lights (pelt's windowed falloff, three's shadow maps where `shadows` is set), built-in
// shapes, glTF assets (fur through PeltFurPlugin), transforms, colours, opaque and fur
// materials with their keys, the procedural sky, wind, and an animation at a time, drawn as
// pelt's forward mode draws them into a linear image that is then sRGB-encoded. Not drawn:
// mirrors and glass (drawn opaque), fur springs, cube-map skies (the flat background), alpha
// materials' stipple (blended instead).

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { PeltFurPlugin, furShared, setWind } from './plugin.js';
import {
  outputFragment, outputVertex, skyFragment, skyVertex, surfaceFragment, surfaceVertex,
} from './shaders.js';

/** pelt_scene::shading::BACKGROUND: the linear colour behind a scene without a sky. */
export const BACKGROUND = [0.02, 0.022, 0.028];
const NEUTRAL = { metallic: 0, roughness: 0.5 };

const fullscreen = () => {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array([-1, -1, 0, 3, -1, 0, -1, 3, 0]), 3));
  return g;
};

/** pelt's opaque surface material over a three material's factors and base colour map. */
export function surfaceMaterial(source, tint = [1, 1, 1], doubleSided = false, control = undefined) {
  const c = source?.color ? source.color.clone() : new THREE.Color(1, 1, 1);
  c.multiply(new THREE.Color().setRGB(...tint, THREE.LinearSRGBColorSpace));
  const map = source?.map || null;
  if (map?.matrixAutoUpdate) map.updateMatrix();
  const m = new THREE.ShaderMaterial({
    vertexShader: surfaceVertex,
    fragmentShader: surfaceFragment,
    lights: true,
    uniforms: {
      ...THREE.UniformsUtils.clone(THREE.UniformsLib.lights),
      albedo: { value: new THREE.Vector4(c.r, c.g, c.b, source?.opacity ?? 1) },
      baseMap: { value: map },
      useBaseMap: { value: map ? 1 : 0 },
      baseMapTransform: { value: map && control !== 'no-uv-transform' ? map.matrix : new THREE.Matrix3() },
      metallic: { value: source?.metalness ?? NEUTRAL.metallic },
      roughness: { value: source?.roughness ?? NEUTRAL.roughness },
      opacity: { value: 1 },
    },
  });
  m.side = doubleSided || source?.side === THREE.DoubleSide ? THREE.DoubleSide : THREE.FrontSide;
  return m;
}

/** Built-in shapes (pelt_scene::asset::builtin): white, the quad double-sided. */
function builtin(name) {
  switch (name) {
    case 'builtin:cube': return { geometry: new THREE.BoxGeometry(1, 1, 1), doubleSided: false };
    case 'builtin:sphere': return { geometry: new THREE.SphereGeometry(0.5, 48, 24), doubleSided: false };
    case 'builtin:quad': return { geometry: new THREE.PlaneGeometry(1, 1), doubleSided: true };
    default: throw new Error(`${name}: unknown built-in shape (known: builtin:cube, builtin:sphere, builtin:quad)`);
  }
}

/**
 * Loads scene file `scene` (parsed JSON) whose assets resolve against `base` (a URL).
 * Options: `shells` (force a count, or 'auto': by screen size even where the scene file
 * forces one), `fins`, `animation` and `time`, `resolve(asset) → URL`
 * (default: relative to `base`), `warn`; `control` (the tests' negative controls):
 * 'opaque-shells', 'no-wind', 'no-shadows', 'no-fur-shadow' (the fur casts as its base
 * mesh), 'no-texture' or 'no-uv-transform' (KHR_texture_transform ignored). Returns { scene, camera, mixers, clips (per animated
 * asset: its root and clips), size, render(renderer) }.
 */
export async function loadScene(file, base, options = {}) {
  const warn = options.warn || ((m) => console.warn(m));
  const scene = new THREE.Scene();
  const size = [file.output?.width ?? 640, file.output?.height ?? 360];
  const cam = file.camera || {};
  const camera = new THREE.PerspectiveCamera(cam.fovYDeg ?? 45, size[0] / size[1], cam.near ?? 0.1, cam.far ?? 100);
  camera.position.set(...(cam.position ?? [0, 0, 3]));
  camera.up.set(...(cam.up ?? [0, 1, 0]));
  camera.lookAt(new THREE.Vector3(...(cam.target ?? [0, 0, 0])));
  camera.updateMatrixWorld();
  const ambient = file.ambient ?? [0.03, 0.03, 0.03];
  scene.add(new THREE.AmbientLight(new THREE.Color().setRGB(...ambient, THREE.LinearSRGBColorSpace), 1));
  const shadowSize = file.shadowMaps?.size ?? 512;
  (file.lights || []).forEach((l, i) => scene.add(light(l, i, shadowSize, options.control)));
  const time = options.time ?? 0;
  if (file.wind && options.control !== 'no-wind') {
    const w = file.wind;
    setWind(w.direction, w.strength ?? 1, w.gustHz ?? 0, w.turbulence ?? 0, time);
  } else {
    furShared.peltWind.value.set(0, 0, 0, time);
  }
  const loader = new GLTFLoader();
  // `shells`: a count forces it everywhere; 'auto' releases the counts a scene file forces.
  const forced = options.shells === 'auto' ? undefined : options.shells;
  loader.register((parser) => new PeltFurPlugin(parser, { shells: forced, control: options.control, warn }));
  const mixers = [];
  const clips = [];
  for (const [i, o] of (file.objects || []).entries()) {
    const object = await loadObject(o, i, base, loader, options, warn, mixers, file, clips);
    scene.add(object);
  }
  scene.updateMatrixWorld(true);
  fitSuns(scene);
  await posedFins(scene);
  return { scene, camera, mixers, clips, size, sky: file.sky?.kind === 'procedural', render: (r) => draw(r, scene, camera, file.sky?.kind === 'procedural') };
}

/** Directional lights' shadow cameras fitted to the scene's bounding sphere (pelt fits its
 * orthographic maps to the scene too), with a bias of about a texel. */
function fitSuns(scene) {
  const sphere = new THREE.Box3().setFromObject(scene).getBoundingSphere(new THREE.Sphere());
  if (!Number.isFinite(sphere.radius) || sphere.radius <= 0) return;
  scene.traverse((l) => {
    if (!l.isDirectionalLight) return;
    const dir = l.position.clone().normalize();
    l.position.copy(sphere.center).addScaledVector(dir, sphere.radius * 2);
    l.target.position.copy(sphere.center);
    l.target.updateMatrixWorld();
    const c = l.shadow.camera;
    c.left = c.bottom = -sphere.radius;
    c.right = c.top = sphere.radius;
    c.near = sphere.radius * 0.5;
    c.far = sphere.radius * 3.5;
    c.updateProjectionMatrix();
    l.shadow.bias = -0.0005;
    l.shadow.normalBias = (2 * sphere.radius) / l.shadow.mapSize.x;
  });
}

function light(l, i, shadowSize, control) {
  const color = new THREE.Color().setRGB(...(l.color ?? [1, 1, 1]), THREE.LinearSRGBColorSpace);
  const intensity = l.intensity ?? 1;
  let out;
  if ((l.kind ?? 'point') === 'directional') {
    out = new THREE.DirectionalLight(color, intensity);
    const d = new THREE.Vector3(...l.direction).normalize();
    out.position.copy(d.multiplyScalar(-100));
  } else {
    out = new THREE.PointLight(color, intensity, l.radius, 2);
    out.position.set(...l.position);
  }
  out.name = `lights[${i}]`;
  if (l.shadows && control !== 'no-shadows') {
    out.castShadow = true;
    out.shadow.mapSize.set(shadowSize, shadowSize);
    if (out.isPointLight) {
      out.shadow.camera.near = Math.max(l.radius * 1e-3, 1e-3);
      out.shadow.camera.far = l.radius;
      out.shadow.bias = -0.0005;
    }
  }
  return out;
}

async function loadObject(o, i, base, loader, options, warn, mixers, file, clips) {
  const place = `objects[${i}]`;
  const kind = o.material?.kind ?? 'opaque';
  const tint = o.color ?? [1, 1, 1];
  let root;
  if (String(o.asset).startsWith('builtin:')) {
    const { geometry, doubleSided } = builtin(o.asset);
    root = new THREE.Mesh(geometry, surfaceMaterial(null, tint, doubleSided));
  } else {
    const url = options.resolve ? options.resolve(o.asset) : new URL(o.asset, base).href;
    let gltf;
    try {
      gltf = await loader.loadAsync(url);
    } catch (e) {
      throw new Error(`${place}: ${o.asset}: ${e.message || e}`);
    }
    root = gltf.scene;
    if (gltf.animations.length) clips.push({ root, clips: gltf.animations });
    if (options.animation) {
      const clip = gltf.animations.find((a) => a.name === options.animation);
      if (!clip) {
        throw new Error(`${o.asset}: no animation ${JSON.stringify(options.animation)} (has ${gltf.animations.map((a) => a.name).join(', ') || 'none'})`);
      }
      const mixer = new THREE.AnimationMixer(root);
      mixer.clipAction(clip).play();
      mixer.setTime(Math.min(options.time ?? 0, clip.duration));
      mixers.push(mixer);
    }
    root.traverse((m) => {
      if (!m.isMesh || m.userData.peltFurPart) return;
      const fur = m.userData.peltFur;
      if (fur) {
        configureFur(fur, o, kind, tint, options, place, warn, file);
      } else if (m.material && !m.material.isShaderMaterial) {
        m.material = surfaceMaterial(m.material, tint, false, options.control);
      }
    });
    if (kind !== 'fur' && kind !== 'opaque') warn(`${place}: ${kind} materials are drawn opaque by this runtime`);
  }
  root.traverse((m) => {
    if (m.isMesh && !m.userData.peltFurPart) {
      m.castShadow = true;
      m.receiveShadow = true;
    }
    if (m.userData.peltFurPart) m.receiveShadow = true;
  });
  const t = o.transform || {};
  root.position.set(...(t.translation ?? [0, 0, 0]));
  root.quaternion.set(...(t.rotation ?? [0, 0, 0, 1]));
  root.scale.set(...(t.scale ?? [1, 1, 1]));
  return root;
}

/** A fur primitive's scene-file keys: shells, fins, length, the object's colour. */
function configureFur(fur, o, kind, tint, options, place, warn, file) {
  const u = fur.look.uniforms;
  u.tint.value.setRGB(...tint, THREE.LinearSRGBColorSpace);
  if (options.control === 'no-texture') u.useBaseMap.value = 0;
  if (kind !== 'fur') {
    fur.shells.visible = false;
    if (fur.fins) fur.fins.visible = false;
    return;
  }
  const m = o.material || {};
  if (options.shells === undefined && m.shells !== undefined) {
    // (`shells: 'auto'` leaves the rule on.)
    // A count the scene file gives is forced, as in pelt.
    u.shells.value = m.shells;
    fur.rule.rule = null;
  }
  fur.rule.max = u.shells.value;
  fur.shells.geometry.instanceCount = u.shells.value;
  if (m.length !== undefined) u.furLength.value = m.length;
  if (options.control === 'no-fur-shadow') fur.shells.castShadow = false;
  // pelt's default (pelt_scene::scene): fins with the binary heightfield's coverage only;
  // the analytic coverage holds the silhouette's fur down to MIN_COS without them.
  const fins = options.fins ?? m.fins ?? (file.furCoverage === 'binary');
  if (fur.fins) fur.fins.visible = fins;
  if (fur.fins) fur.fins.material.uniforms.analytic.value = file.furCoverage === 'binary' ? 0 : 1;
  if (m.spring) warn(`${place}: fur springs are not drawn by this runtime`);
}

/** Poses the fins of skinned fur meshes at the mixers' current time. */
export async function posedFins(scene) {
  const fins = [];
  scene.traverse((m) => m.userData.peltFur?.fins && fins.push(m.userData.peltFur.fins));
  await Promise.all(fins.map((f) => f.ready));
  scene.updateMatrixWorld(true);
  scene.traverse((m) => m.isSkinnedMesh && m.skeleton.update());
  for (const f of fins) if (f.source.isSkinnedMesh) f.pose();
}

const outputs = new WeakMap();

/** One frame: sky, scene into a linear half-float target, then sRGB onto the canvas. */
export function draw(renderer, scene, camera, sky) {
  const size = renderer.getDrawingBufferSize(new THREE.Vector2());
  let o = outputs.get(renderer);
  if (!o || o.target.width !== size.x || o.target.height !== size.y) {
    const target = new THREE.WebGLRenderTarget(size.x, size.y, { type: THREE.HalfFloatType, depthBuffer: true });
    const skyMaterial = new THREE.ShaderMaterial({
      vertexShader: skyVertex, fragmentShader: skyFragment, depthTest: false, depthWrite: false,
      uniforms: { peltCameraWorld: { value: new THREE.Matrix4() }, peltTanHalf: { value: new THREE.Vector2() } },
    });
    const outMaterial = new THREE.ShaderMaterial({
      vertexShader: outputVertex, fragmentShader: outputFragment, depthTest: false, depthWrite: false,
      uniforms: { image: { value: target.texture } },
    });
    const quad = (m) => {
      const mesh = new THREE.Mesh(fullscreen(), m);
      mesh.frustumCulled = false;
      const s = new THREE.Scene();
      s.add(mesh);
      return s;
    };
    o = { target, skyMaterial, skyScene: quad(skyMaterial), outScene: quad(outMaterial) };
    outputs.set(renderer, o);
  }
  renderer.autoClear = false;
  renderer.setRenderTarget(o.target);
  renderer.setClearColor(new THREE.Color().setRGB(...BACKGROUND, THREE.LinearSRGBColorSpace), 1);
  renderer.clear(true, true, true);
  if (sky) {
    const th = Math.tan(THREE.MathUtils.degToRad(camera.fov) / 2);
    o.skyMaterial.uniforms.peltTanHalf.value.set(th * camera.aspect, th);
    o.skyMaterial.uniforms.peltCameraWorld.value.copy(camera.matrixWorld);
    renderer.render(o.skyScene, camera);
  }
  renderer.render(scene, camera);
  renderer.setRenderTarget(null);
  renderer.render(o.outScene, camera);
}
