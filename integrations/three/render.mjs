#!/usr/bin/env node
// Renders a pelt scene file with @pelt/three in headless Chromium (WebGL2; SwiftShader
// without a GPU) and writes the PNG, with pelt render's flag names and meanings:
//   node integrations/three/render.mjs SCENE.json -o OUT.png --size WxH [--shells N|auto] [--fins on|off]
//        [--animation NAME --time T] [--bench FRAMES] [--report]
// (--report prints, as JSON, each fur mesh's shell count and projected fur length.)
// Every file of the page is served from this machine (the package, three from its
// node_modules, the scene's folder); nothing is fetched from the network. The browser is
// Debian's `chromium` (or $CHROMIUM).
import { readFile, writeFile } from 'node:fs/promises';
import { withPage } from './src/node/browser.js';

const USAGE = 'usage: node render.mjs SCENE.json -o OUT.png [--size WxH] [--shells N|auto] [--fins on|off] [--animation NAME --time T] [--bench FRAMES] [--report]';

function usage(message) {
  console.error(`error: ${message}\n${USAGE}`);
  process.exit(2);
}

function parse(argv) {
  const o = {};
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      return argv[++i];
    };
    if (a === '-h' || a === '--help') {
      console.log(`Renders a pelt scene file with @pelt/three in headless Chromium (docs/three.md).\n${USAGE}`);
      process.exit(0);
    }
    if (a === '-o' || a === '--output') o.output = value();
    else if (a === '--size') o.size = value();
    else if (a === '--shells') o.shells = value();
    else if (a === '--fins') o.fins = value();
    else if (a === '--animation') o.animation = value();
    else if (a === '--time') o.time = value();
    else if (a === '--bench') o.bench = value();
    else if (a === '--control') o.control = value();
    else if (a === '--report') o.report = true;
    else if (a.startsWith('-')) usage(`unknown flag ${a}`);
    else if (o.scene) usage(`a second input ${a}`);
    else o.scene = a;
  }
  if (!o.scene) usage('no scene file given');
  if (!o.output && !o.bench) usage('no output (-o OUT.png) given');
  if (o.size && !/^\d+x\d+$/.test(o.size)) usage(`--size ${o.size}: expected WxH, e.g. 320x180`);
  if (o.size && o.size.split('x').some((v) => Number(v) < 1 || Number(v) > 8192)) usage(`--size ${o.size}: each side must be 1 to 8192`);
  if (o.shells !== undefined && o.shells !== 'auto' && !(/^\d+$/.test(o.shells) && Number(o.shells) >= 1 && Number(o.shells) <= 256)) usage(`--shells ${o.shells}: expected 1 to 256, or auto`);
  if (o.fins !== undefined && !['on', 'off'].includes(o.fins)) usage(`--fins ${o.fins}: expected on or off`);
  if (o.time !== undefined && !Number.isFinite(Number(o.time))) usage(`--time ${o.time}: expected seconds`);
  if (o.bench !== undefined && !(/^\d+$/.test(o.bench) && Number(o.bench) >= 1)) usage(`--bench ${o.bench}: expected a frame count`);
  return o;
}

const o = parse(process.argv.slice(2));
// The scene file is read here first, so that a missing or malformed one is reported with its
// place before a browser starts.
try {
  const parsed = JSON.parse(await readFile(o.scene, 'utf8'));
  if (parsed === null || typeof parsed !== 'object' || Array.isArray(parsed)) throw new Error('a scene file is a JSON object');
} catch (e) {
  console.error(`error: ${o.scene}: ${e.code === 'ENOENT' ? 'no such file' : e.message}`);
  process.exit(1);
}
const r = await withPage(o.scene, (scene) => {
  const q = new URLSearchParams({ scene });
  for (const k of ['size', 'shells', 'fins', 'animation', 'time', 'control']) if (o[k] !== undefined) q.set(k, o[k]);
  if (o.bench) q.set('frames', o.bench);
  return `/src/page/render.html?${q}`;
});
for (const w of r.warnings || []) console.error(`warning: ${w}`);
for (const e of r.consoleErrors || []) console.error(`browser: ${e}`);
if (r.outside?.length) console.error(`error: the page asked for files outside this machine: ${r.outside.join(', ')}`);
if (r.error || r.consoleErrors?.length || r.outside?.length) {
  if (r.error) console.error(`error: ${o.scene}: ${r.error}`);
  process.exit(1);
}
if (o.output) await writeFile(o.output, Buffer.from(r.png.split(',')[1], 'base64'));
if (o.report) console.log(JSON.stringify({ fur: r.fur, gl: r.gl }));
if (o.bench) {
  const t = [...r.times].sort((a, b) => a - b);
  console.log(JSON.stringify({ frames: t.length, medianMs: t[t.length >> 1], gl: r.gl }));
}
