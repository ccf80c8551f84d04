#!/usr/bin/env node
// Drives the viewer page in headless Chromium: opens it on a scene file (?scene=), waits for
// frames, then drops a baked asset onto it (a DataTransfer drop event, as a drag from the
// desktop gives) and waits for frames of that; prints JSON with what it showed, the console
// errors and any request that left the machine:
//   node test/viewer.mjs SCENE.json ASSET.glb      (ASSET in the scene's folder)
// tests/three_runtime.rs drives it.
import { basename } from 'node:path';
import { withPage } from '../src/node/browser.js';

const [scene, asset] = process.argv.slice(2);
const r = await withPage(scene, (s) => `/viewer/index.html?scene=${encodeURIComponent(s)}`, {
  page: async (page) => {
    const framesOf = (label) => `window.peltViewer && window.peltViewer.showing === ${JSON.stringify(label)} && window.peltViewer.frames > 2`;
    await page.waitForFunction(framesOf(`/scene/${basename(scene)}`), { timeout: 240000 });
    const before = await page.evaluate('window.peltViewer.frames');
    await page.evaluate(async (name) => {
      const blob = await (await fetch(`/scene/${name}`)).blob();
      const dt = new DataTransfer();
      dt.items.add(new File([blob], name));
      window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, bubbles: true, cancelable: true }));
    }, basename(asset));
    await page.waitForFunction(`${framesOf(basename(asset))} && window.peltViewer.frames > ${before + 2}`, { timeout: 240000 });
    await page.evaluate(`window.result = { showing: window.peltViewer.showing, frames: window.peltViewer.frames, status: document.getElementById('status').textContent }`);
  },
});
console.log(JSON.stringify(r));
