// What the viewer costs the run (issue #33's targets), measured with alternated
// runs of `sgslam run` on one dataset:
//   off    no --viewer
//   idle   --viewer, no page open (snapshots taken, nothing sent)
//   page   a headless chromium page open for the whole run
//   stuck  a client that asks for the map again and again and never reads
// and prints the medians of the median frame time and fps. Also the page's frame
// rate on a finished run (--view-run OUTDIR) while the mouse turns the view.
//   node viewer/tests/viewer_speed.mjs --sgslam BIN --dataset DIR [--repeats 3] [--variants off,page]
//                                      [--view-run OUTDIR]
import { spawn } from 'node:child_process';
import { readFileSync, rmSync } from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';

import { launchChromium, parseArgs, startServed } from './common.mjs';

const args = parseArgs(process.argv.slice(2));
const repeats = Number(args.repeats || 3);
const browser = await launchChromium(args.chromium);
const median = (v) => { const s = [...v].sort((a, b) => a - b); return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2; };

// A WebSocket client that never reads: the handshake, then masked text frames.
function stuckClient(url) {
  const { hostname, port } = new URL(url);
  const socket = net.connect(Number(port), hostname);
  socket.pause();  // never read: the server's writes pile up in the socket buffers
  const frame = (text) => {
    const payload = Buffer.from(text);
    const mask = Buffer.from([1, 2, 3, 4]);
    const masked = Buffer.from(payload.map((b, i) => b ^ mask[i % 4]));
    return Buffer.concat([Buffer.from([0x81, 0x80 | payload.length]), mask, masked]);
  };
  socket.write(`GET /ws HTTP/1.1\r\nHost: ${hostname}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n` +
               'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n');
  const timer = setInterval(() => {
    socket.write(frame('{"get":"map","pieces_after":-1}'));
    socket.write(frame('{"get":"frame","have":0}'));
  }, 100);
  socket.on('error', () => clearInterval(timer));
  return () => { clearInterval(timer); socket.destroy(); };
}

async function runOnce(variant) {
  const out = path.join(os.tmpdir(), `sgslam-viewer-speed-${variant}`);
  rmSync(out, { recursive: true, force: true });
  const runArgs = ['run', '--dataset', args.dataset, '--out', out];
  if (variant !== 'off') runArgs.push('--viewer=0');
  let page = null, stop = null;
  if (variant === 'off') {
    await new Promise((resolve) => spawn(args.sgslam, runArgs, { stdio: 'ignore' }).on('exit', resolve));
  } else {
    const run = startServed(args.sgslam, runArgs);
    const url = await run.url;
    if (variant === 'page') {
      page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
      await page.goto(url);
    } else if (variant === 'stuck') {
      stop = stuckClient(url);
    }
    await run.exited;
    if (page) await page.close();
    if (stop) stop();
  }
  const stats = JSON.parse(readFileSync(path.join(out, 'stats.json'), 'utf8'));
  return { frame: stats.median_ms.frame, fps: stats.fps };
}

const variants = (args.variants || 'off,idle,page,stuck').split(',');
const results = Object.fromEntries(variants.map((v) => [v, []]));
for (let i = 0; i < repeats; i++) {
  for (const v of variants) {
    const r = await runOnce(v);
    results[v].push(r);
    console.log(`repeat ${i + 1} ${v}: median frame ${r.frame.toFixed(2)} ms, ${r.fps.toFixed(1)} fps`);
  }
}
console.log(`\n| run | median frame ms | fps |\n|---|---|---|`);
for (const v of variants) {
  console.log(`| ${v} | ${median(results[v].map((r) => r.frame)).toFixed(2)} | ${median(results[v].map((r) => r.fps)).toFixed(1)} |`);
}
console.log(`medians of ${repeats} alternated runs on ${args.dataset}`);

if (args['view-run']) {
  const served = startServed(args.sgslam, ['view', args['view-run'], '--port', '0']);
  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  await page.goto(await served.url);
  await page.waitForFunction(() => window.sgslamViewer && window.sgslamViewer.maps >= 1, null, { timeout: 60000 });
  // The view turned by the mouse for 5 s, in steps of 16 ms: drawings per second.
  const box = await page.locator('#view3d canvas').boundingBox();
  const x = box.x + box.width / 2, y = box.y + box.height / 2;
  await page.mouse.move(x, y);
  await page.mouse.down();
  const before = await page.evaluate(() => window.sgslamViewer.renders);
  const start = Date.now();
  for (let i = 0; Date.now() - start < 5000; i++) {
    await page.mouse.move(x + 200 * Math.sin(i / 20), y + 50 * Math.cos(i / 30));
    await page.waitForTimeout(16);
  }
  const fps = (1000 * ((await page.evaluate(() => window.sgslamViewer.renders)) - before)) / (Date.now() - start);
  await page.mouse.up();
  const v = await page.evaluate(() => window.sgslamViewer);
  console.log(`page on ${args['view-run']}, the view turned for 5 s: ${fps.toFixed(1)} fps (${v.cloudPoints} cloud ` +
              `points, ${v.mapPoints} map points, ${v.keyframes} keyframes, ${v.objects} objects)`);
  served.child.kill('SIGINT');
  await served.exited;
}
await browser.close();
