// Renders a .glb with three.js's GLTFLoader in headless Chromium (SwiftShader), as any viewer
// without pelt's runtime draws it (KHR_materials_sheen included), to a PNG:
//   node tools/sheen-picture/render.mjs IN.glb OUT.png [WxH] [--no-sheen]
// Needs `npm ci --prefix tools/sheen-picture` and Debian's `chromium`.
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const [input, output] = args;
const size = args.find((a) => /^\d+x\d+$/.test(a)) || '480x270';
const sheen = args.includes('--no-sheen') ? 'off' : 'on';
const types = { '.js': 'text/javascript', '.html': 'text/html', '.glb': 'model/gltf-binary' };

const server = createServer(async (req, res) => {
  const path = new URL(req.url, 'http://x').pathname;
  const file = path === '/asset.glb' ? input
    : path === '/' ? join(here, 'page.html')
    : path.startsWith('/three/') ? join(here, 'node_modules', path) : null;
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[file.slice(file.lastIndexOf('.'))] || 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const browser = await puppeteer.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.error(e));
  await page.goto(`http://127.0.0.1:${server.address().port}/?size=${size}&sheen=${sheen}`);
  await page.waitForFunction('window.result', { timeout: 120000 });
  const r = await page.evaluate('window.result');
  await writeFile(output, Buffer.from(r.png.split(',')[1], 'base64'));
  console.log(`${output}: ${size}, ${r.sheenMaterials} sheen material(s) drawn, ${r.gl}`);
} finally {
  await browser.close();
  server.close();
}
