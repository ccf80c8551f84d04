// Headless Chromium for render.mjs and the tests: a loopback server for the package's
// source, viewer, test pages and three (its own paths) and one scene's folder (/scene/), and a page whose `window.result`
// is awaited. Console errors and page errors are collected into the result.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { basename, dirname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const pkg = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const PUBLIC = ['/src/', '/viewer/', '/test/pages/', '/node_modules/three/'];
const TYPES = {
  '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html', '.json': 'application/json',
  '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.png': 'image/png', '.bin': 'application/octet-stream',
};

/** The file under `root` that URL path `rest` names (null outside it). */
function under(root, rest) {
  const p = normalize(join(root, decodeURIComponent(rest)));
  return p === root || p.startsWith(root + sep) ? p : null;
}

export function serve(sceneDir) {
  const server = createServer(async (req, res) => {
    const path = new URL(req.url, 'http://x').pathname;
    // The package's own files (its source, viewer and test pages, and three from its
    // node_modules, at the paths the pages' import maps name) and the scene's folder.
    const file = path.startsWith('/scene/') ? (sceneDir ? under(sceneDir, path.slice(7)) : null)
      : PUBLIC.some((p) => path.startsWith(p)) ? under(pkg, path.slice(1)) : null;
    try {
      if (!file) throw new Error('outside');
      const body = await readFile(file);
      res.writeHead(200, { 'content-type': TYPES[file.slice(file.lastIndexOf('.'))] || 'application/octet-stream' });
      res.end(body);
    } catch {
      res.writeHead(404).end();
    }
  });
  return new Promise((r) => server.listen(0, '127.0.0.1', () => r(server)));
}

export const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
export const FLAGS = ['--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];

/** Opens the page `pathOf(sceneUrlPath)` with the scene file's folder served, waits for
 * `window.result` and returns it, with `consoleErrors` and `requests` outside the server. */
export async function withPage(scenePath, pathOf, { timeout = 300000, page: use } = {}) {
  const dir = scenePath ? dirname(resolve(scenePath)) : null;
  const server = await serve(dir);
  const browser = await puppeteer.launch({ executablePath: CHROMIUM, args: FLAGS });
  try {
    const page = await browser.newPage();
    const consoleErrors = [];
    const outside = [];
    page.on('console', (m) => m.type() === 'error' && consoleErrors.push(m.text()));
    page.on('pageerror', (e) => consoleErrors.push(String(e)));
    page.on('request', (r) => {
      if (!r.url().startsWith(`http://127.0.0.1:${server.address().port}/`) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) outside.push(r.url());
    });
    const base = `http://127.0.0.1:${server.address().port}`;
    await page.goto(base + pathOf(scenePath ? `/scene/${basename(scenePath)}` : null));
    if (use) await use(page);
    await page.waitForFunction('window.result', { timeout });
    const r = await page.evaluate('window.result');
    return { ...r, consoleErrors, outside };
  } finally {
    await browser.close();
    server.close();
  }
}
