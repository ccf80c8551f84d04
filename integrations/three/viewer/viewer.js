// pelt's web viewer: a scene file (?scene=URL, or opened/dropped with its assets) or one
// dropped .glb (framed as `pelt render ASSET.glb` frames it), drawn by @pelt/three; orbit,
// animation clips, and the shell count (0: each asset's own).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { loadScene } from '@pelt/three/scene.js';
import { assetScene } from '@pelt/three/framing.js';
import { furShared } from '@pelt/three/index.js';

const canvas = document.getElementById('view');
const status = document.getElementById('status');
const clipSelect = document.getElementById('clip');
const shellsInput = document.getElementById('shells');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.shadowMap.enabled = true;
let current = null;
let frames = 0;
const clock = new THREE.Clock();

function resize() {
  renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
  if (current) {
    current.camera.aspect = canvas.clientWidth / canvas.clientHeight;
    current.camera.updateProjectionMatrix();
  }
}
window.addEventListener('resize', resize);

/** Shows `file` (a parsed scene) whose assets `resolve` maps to URLs. */
async function show(file, base, resolve, label) {
  const warnings = [];
  const s = await loadScene(file, base, { resolve, warn: (m) => warnings.push(m) });
  const controls = new OrbitControls(s.camera, canvas);
  controls.target.set(...(file.camera?.target ?? [0, 0, 0]));
  controls.update();
  current?.controls.dispose();
  current = { ...s, controls, mixer: null, label };
  clipSelect.replaceChildren(new Option('(none)', ''));
  s.clips.forEach((c, i) => c.clips.forEach((clip, j) => clipSelect.add(new Option(clip.name, `${i}/${j}`))));
  applyShells();
  resize();
  status.textContent = `${label}${warnings.length ? ` (${warnings.length} warning${warnings.length > 1 ? 's' : ''}: ${warnings.join('; ')})` : ''}`;
  for (const w of warnings) console.warn(w);
}

function applyShells() {
  const n = Number(shellsInput.value);
  document.getElementById('shellsValue').textContent = n === 0 ? "asset's" : String(n);
  current?.scene.traverse((m) => {
    const fur = m.userData.peltFur;
    if (!fur) return;
    fur.defaultShells ??= fur.look.uniforms.shells.value;
    const count = n === 0 ? fur.defaultShells : n;
    fur.look.uniforms.shells.value = count;
    fur.shells.geometry.instanceCount = count;
  });
}
shellsInput.addEventListener('input', applyShells);

clipSelect.addEventListener('change', () => {
  if (!current) return;
  current.mixer?.stopAllAction();
  current.mixer = null;
  if (!clipSelect.value) return;
  const [i, j] = clipSelect.value.split('/').map(Number);
  const { root, clips } = current.clips[i];
  current.mixer = new THREE.AnimationMixer(root);
  current.mixer.clipAction(clips[j]).play();
});

/** Opens dropped or chosen files: a scene file with its assets, or one .glb/.gltf. */
async function openFiles(list) {
  const files = [...list];
  const urls = new Map(files.map((f) => [f.name, URL.createObjectURL(f)]));
  const resolve = (asset) => {
    const name = asset.split(/[\\/]/).pop();
    if (!urls.has(name)) throw new Error(`${asset}: not among the opened files (open the scene file together with its assets)`);
    return urls.get(name);
  };
  try {
    const sceneFile = files.find((f) => f.name.endsWith('.json'));
    if (sceneFile) {
      await show(JSON.parse(await sceneFile.text()), location.href, resolve, sceneFile.name);
      return;
    }
    const asset = files.find((f) => /\.(glb|gltf)$/i.test(f.name));
    if (!asset) throw new Error('drop a .glb, or a scene file (.json) with its assets');
    await showAsset(asset.name, urls.get(asset.name));
  } catch (e) {
    status.textContent = String(e.message || e);
    console.warn(e);
  }
}

/** One asset, framed by pelt's default scene. */
async function showAsset(name, url) {
  const { GLTFLoader } = await import('three/addons/loaders/GLTFLoader.js');
  const gltf = await new GLTFLoader().loadAsync(url);
  const box = new THREE.Box3().setFromObject(gltf.scene);
  const fur = (gltf.parser.json.extensionsUsed || []).includes('PELT_fur');
  const length = Math.max(0, ...(gltf.parser.json.materials || []).map((m) => m.extensions?.PELT_fur?.length ?? 0));
  const file = assetScene(name, { min: box.min.toArray(), max: box.max.toArray() }, length, canvas.clientWidth || 640, canvas.clientHeight || 360, fur);
  await show(file, location.href, () => url, name);
}

window.addEventListener('dragover', (e) => e.preventDefault());
window.addEventListener('drop', (e) => {
  e.preventDefault();
  openFiles(e.dataTransfer.files);
});
document.getElementById('open').addEventListener('change', (e) => openFiles(e.target.files));

function frame() {
  requestAnimationFrame(frame);
  if (!current) return;
  const dt = clock.getDelta();
  furShared.peltWind.value.w += dt;
  if (current.mixer) {
    current.mixer.update(dt);
    current.scene.updateMatrixWorld(true);
    current.scene.traverse((m) => m.userData.peltFur?.fins?.source.isSkinnedMesh && m.userData.peltFur.fins.visible && m.userData.peltFur.fins.pose());
  }
  current.controls.update();
  current.render(renderer);
  frames += 1;
  window.peltViewer.frames = frames;
  window.peltViewer.showing = current.label;
}
requestAnimationFrame(frame);

window.peltViewer = { openFiles, frames: 0, showing: null };
const start = new URLSearchParams(location.search).get('scene');
if (start) {
  const url = new URL(start, location.href);
  fetch(url).then((r) => r.json()).then((f) => show(f, url, undefined, start)).catch((e) => {
    status.textContent = String(e.message || e);
    console.warn(e);
  });
}
