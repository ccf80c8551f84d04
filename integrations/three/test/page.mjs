#!/usr/bin/env node
// Opens one of the test pages (test/pages/NAME.html) on a file in headless Chromium and
// prints its result as JSON with the console errors and any request that left the machine:
//   node test/page.mjs NAME FILE [key=value …]
// tests/three_runtime.rs drives it.
import { basename } from 'node:path';
import { withPage } from '../src/node/browser.js';

const [name, file, ...rest] = process.argv.slice(2);
const r = await withPage(file, (scene) => {
  const q = new URLSearchParams({ scene });
  for (const kv of rest) q.set(...kv.split('='));
  return `/test/pages/${basename(name)}.html?${q}`;
});
delete r.png;
console.log(JSON.stringify(r));
