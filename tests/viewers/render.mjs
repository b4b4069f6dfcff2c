#!/usr/bin/env node
// Render a 3DGS PLY with one real web viewer in headless Chromium and save the canvas.
//
//   node render.mjs --viewer gs3d|spark|playcanvas --ply FILE.ply --camera CAM.json
//                   --out OUT.png [--frames N] [--sh D] [--json DETAILS.json]
//                   [--chromium PATH] [--timeout SECONDS] [--verbose]
//
// A plain node:http server on 127.0.0.1 serves page.html, the harness/viewer modules,
// the needed node_modules files (ES modules, mapped by the page's import map) and the
// PLY (as /input.ply). puppeteer-core drives Debian's Chromium with SwiftShader WebGL.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const ROOT = path.dirname(fileURLToPath(import.meta.url));
const PACKAGES = {   // viewer -> npm packages whose versions we report
  gs3d: ['@mkkellogg/gaussian-splats-3d', 'three'],
  spark: ['@sparkjsdev/spark', 'three'],
  playcanvas: ['playcanvas'],
};
// Software WebGL2: ANGLE on SwiftShader (Vulkan). --no-sandbox because we run as root.
const CHROMIUM_ARGS = [
  '--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--use-gl=angle', '--ignore-gpu-blocklist', '--force-device-scale-factor=1',
  '--disable-background-timer-throttling', '--disable-renderer-backgrounding',
];

function parseArgs(argv) {
  const a = { frames: 10, timeout: 300, chromium: process.env.CHROMIUM || '/usr/bin/chromium' };
  for (let i = 0; i < argv.length; i++) {
    const k = argv[i].replace(/^--/, '');
    if (k === 'verbose') a.verbose = true;
    else if (['viewer', 'ply', 'camera', 'out', 'frames', 'sh', 'json', 'chromium', 'timeout'].includes(k)) a[k] = argv[++i];
    else throw new Error(`unknown argument ${argv[i]}`);
  }
  if (!PACKAGES[a.viewer] || !a.ply || !a.camera || !a.out) {
    throw new Error('usage: node render.mjs --viewer gs3d|spark|playcanvas --ply FILE.ply --camera CAM.json --out OUT.png [--frames N] [--sh D] [--json FILE] [--chromium PATH] [--timeout S] [--verbose]');
  }
  a.frames = Number(a.frames);
  a.timeout = Number(a.timeout);
  a.sh = a.sh === undefined ? null : Number(a.sh);
  return a;
}

const MIME = { '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript',
  '.json': 'application/json', '.wasm': 'application/wasm', '.map': 'application/json' };

function serve(plyPath) {
  const server = http.createServer((req, res) => {
    const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    // The PLY may live anywhere; everything else must be inside this directory.
    const file = url === '/input.ply' ? plyPath : path.join(ROOT, url === '/' ? 'page.html' : url);
    if (url !== '/input.ply' && !file.startsWith(ROOT + path.sep)) { res.writeHead(403).end(); return; }
    fs.readFile(file, (err, data) => {
      if (err) { process.stderr.write(`server: 404 ${url}\n`); res.writeHead(404).end(); return; }
      res.writeHead(200, {
        'Content-Type': MIME[path.extname(file)] || 'application/octet-stream',
        'Content-Length': data.length, 'Cache-Control': 'no-store',
      }).end(data);
    });
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const cam = JSON.parse(fs.readFileSync(args.camera, 'utf8'));
  for (const k of ['width', 'height', 'eye', 'target', 'up', 'fovy_deg', 'near', 'far', 'background']) {
    if (cam[k] === undefined) throw new Error(`${args.camera}: missing "${k}"`);
  }
  const versions = Object.fromEntries(PACKAGES[args.viewer].map((p) =>
    [p, JSON.parse(fs.readFileSync(path.join(ROOT, 'node_modules', p, 'package.json'), 'utf8')).version]));

  const tStart = performance.now();
  const server = await serve(path.resolve(args.ply));
  const browser = await puppeteer.launch({
    executablePath: args.chromium, headless: true, args: CHROMIUM_ARGS,
    defaultViewport: { width: cam.width, height: cam.height, deviceScaleFactor: 1 },
  });
  let result;
  try {
    const page = await browser.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    page.on('console', (m) => {
      if (args.verbose || m.type() === 'error') process.stderr.write(`[page ${m.type()}] ${m.text()}\n`);
    });
    await page.goto(`http://127.0.0.1:${server.address().port}/page.html`);
    await page.waitForFunction('window.harnessReady === true');
    const cfg = { viewer: args.viewer, plyUrl: '/input.ply', cam, frames: args.frames, sh: args.sh };
    let timer;
    result = await Promise.race([
      page.evaluate((c) => window.runHarness(c), cfg),
      new Promise((_, rej) => { timer = setTimeout(() => rej(new Error(`timed out after ${args.timeout} s; page errors: ${errors.join(' | ')}`)), args.timeout * 1000); }),
    ]);
    clearTimeout(timer);
    if (errors.length) process.stderr.write(`page errors: ${errors.join(' | ')}\n`);
  } finally {
    await browser.close();
    server.close();
  }

  fs.mkdirSync(path.dirname(path.resolve(args.out)), { recursive: true });
  fs.writeFileSync(args.out, Buffer.from(result.png.split(',')[1], 'base64'));
  const { png, ...details } = result;
  Object.assign(details, { viewer: args.viewer, versions, wallMs: performance.now() - tStart });
  if (args.json) fs.writeFileSync(args.json, JSON.stringify(details, null, 1));
  if (args.verbose) process.stderr.write(`${JSON.stringify(details, null, 1)}\n`);
  if (result.stableAfter < 0 || result.changedWhileTiming) {
    process.stderr.write(`warning: ${args.viewer}: image not stable (stableAfter=${result.stableAfter}, changedWhileTiming=${result.changedWhileTiming})\n`);
  }
  const [W, H] = result.drawingBuffer;
  console.log(`${args.viewer} ${versions[PACKAGES[args.viewer][0]]} ${W}x${H} splats=${result.numSplats} ` +
    `load=${result.loadMs.toFixed(0)}ms frame=${result.frameMs.toFixed(2)}ms(mean of ${args.frames}) -> ${args.out}`);
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
