// What the viewer costs the run (issue #33's targets), measured with alternated
// runs of `sgslam run` on one dataset:
//   off    no --viewer
//   idle   --viewer, no page open (snapshots taken, nothing sent)
//   page   a headless chromium page open for the whole run
//   stuck  a client that asks for the map again and again and never reads
//   puller a client that pulls like the page (frames at 15 Hz, the map at 2 Hz)
//          but draws nothing: the server's own cost, without the browser's
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
  socket.write(upgradeRequest(hostname, port));
  const timer = setInterval(() => {
    socket.write(wsFrame('{"get":"map","pieces_after":-1}'));
    socket.write(wsFrame('{"get":"frame","have":0}'));
  }, 100);
  socket.on('error', () => clearInterval(timer));
  return () => { clearInterval(timer); socket.destroy(); };
}

// The upgrade to /ws as the viewer's own page asks for it (its Host and Origin: the
// server refuses other pages', viewer/src/origin.h).
function upgradeRequest(hostname, port) {
  return `GET /ws HTTP/1.1\r\nHost: ${hostname}:${port}\r\nOrigin: http://${hostname}:${port}\r\n` +
         'Upgrade: websocket\r\nConnection: Upgrade\r\n' +
         'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n';
}

// A masked WebSocket text frame (client to server), payload under 126 bytes.
function wsFrame(text) {
  const payload = Buffer.from(text);
  const mask = Buffer.from([1, 2, 3, 4]);
  return Buffer.concat([Buffer.from([0x81, 0x80 | payload.length]), mask,
                        Buffer.from(payload.map((b, i) => b ^ mask[i % 4]))]);
}

// Pulls frames and maps as the page does, reading (and dropping) what comes.
function pullerClient(url) {
  const { hostname, port } = new URL(url);
  const socket = net.connect(Number(port), hostname);
  let buffer = Buffer.alloc(0), upgraded = false, stopped = false, parts = [];
  const ask = (text, ms) => setTimeout(() => { if (!stopped) socket.write(wsFrame(text)); }, ms);
  socket.write(upgradeRequest(hostname, port));
  socket.on('data', (chunk) => {
    buffer = Buffer.concat([buffer, chunk]);
    if (!upgraded) {
      const end = buffer.indexOf('\r\n\r\n');
      if (end < 0) return;
      buffer = buffer.subarray(end + 4);
      upgraded = true;
      ask('{"get":"frame","have":0}', 0);
      ask('{"get":"map","pieces_after":-1}', 0);
    }
    for (;;) {  // server frames (unmasked; a message may come in several: FIN on the last)
      if (buffer.length < 2) return;
      const fin = (buffer[0] & 0x80) !== 0;
      let length = buffer[1] & 0x7f, at = 2;
      if (length === 126) { if (buffer.length < 4) return; length = buffer.readUInt16BE(2); at = 4; }
      if (length === 127) { if (buffer.length < 10) return; length = Number(buffer.readBigUInt64BE(2)); at = 10; }
      if (buffer.length < at + length) return;
      parts.push(buffer.subarray(at, at + length));
      buffer = buffer.subarray(at + length);
      if (!fin) continue;
      const message = Buffer.concat(parts);
      parts = [];
      const header = JSON.parse(message.subarray(4, 4 + message.readUInt32LE(0)).toString());
      if (header.type === 'frame') ask(`{"get":"frame","have":${header.version}}`, 66);
      if (header.type === 'map') ask('{"get":"map","pieces_after":1000000}', 500);
    }
  });
  socket.on('error', () => {});
  return () => { stopped = true; socket.destroy(); };
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
    } else if (variant === 'puller') {
      stop = pullerClient(url);
    }
    await run.exited;
    if (page) await page.close();
    if (stop) stop();
  }
  const stats = JSON.parse(readFileSync(path.join(out, 'stats.json'), 'utf8'));
  return { frame: stats.median_ms.frame, fps: stats.fps };
}

const variants = (args.variants || 'off,idle,puller,page,stuck').split(',');
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
