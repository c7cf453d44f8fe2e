// `sgslam run --foxglove` and `sgslam view --foxglove` with the official client of
// Foxglove's WebSocket protocol (@foxglove/ws-protocol, over the `ws` package; the
// app itself cannot be installed here): the channels advertised with their
// schemas, every one subscribed, poses, clouds and images received and decoded,
// each message checked against its schema; beside it a client that subscribes to
// everything and then never reads, which must not hold the run up. Then a finished
// run served by `view --foxglove` (its map, sent to a subscriber at once), and a
// port already in use refused with its reason.
//   node foxglove_live_test.mjs --sgslam BIN --work DIR [--runs N] [--dataset DIR]
// --runs N: N runs with the clients and N without, alternated, the tracking
// thread's median frame time of each printed (the cost measure); --dataset:
// a sequence to run in place of rendered walkers.
import { spawn, spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync } from 'node:fs';
import net from 'node:net';
import path from 'node:path';

import { check, fail, parseArgs, SKIP } from './common.mjs';
import { EXPECTED, validate } from './foxglove_common.mjs';

let FoxgloveClient, WebSocket;
try {
  const protocol = await import('@foxglove/ws-protocol');
  FoxgloveClient = protocol.FoxgloveClient ?? protocol.default.FoxgloveClient;  // a CommonJS package
  ({ WebSocket } = await import('ws'));
} catch {
  console.log('SKIP: @foxglove/ws-protocol or ws is not installed (scripts/setup.sh runs npm ci in viewer)');
  process.exit(SKIP);
}

const args = parseArgs(process.argv.slice(2));
rmSync(args.work, { recursive: true, force: true });
mkdirSync(args.work, { recursive: true });
const data = args.dataset ?? path.join(args.work, 'walkers');
if (!args.dataset) {
  const r = spawnSync(args.sgslam, ['synth', '--out', data, '--preset', 'walkers', '--frames', '120'], { encoding: 'utf8' });
  if (r.status !== 0) fail(`sgslam synth failed: ${r.stderr}`);
}

// Starts sgslam and resolves with the Foxglove address it prints.
function start(argv) {
  const child = spawn(args.sgslam, argv, { stdio: ['ignore', 'pipe', 'pipe'] });
  let log = '';
  const url = new Promise((resolve, reject) => {
    const onData = (chunk) => {
      log += chunk;
      const m = log.match(/\(Foxglove WebSocket\) to (ws:\/\/[^ \n]+)/);
      if (m) resolve(m[1]);
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('exit', (code) => reject(new Error(`sgslam ended (${code}) before serving:\n${log}`)));
  });
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve(code ?? signal)));
  return { child, url, exited, log: () => log };
}

// A client of the official library that subscribes to every channel and keeps
// what it receives, checked against the schemas.
function connect(url) {
  const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
  const got = { serverInfo: null, channels: new Map(), bySub: new Map(), count: {}, last: {}, errors: [], bytes: 0 };
  const decoder = new TextDecoder();
  client.on('serverInfo', (info) => { got.serverInfo = info; });
  client.on('advertise', (channels) => {
    for (const c of channels) {
      got.channels.set(c.id, { ...c, parsed: JSON.parse(c.schema) });
      got.bySub.set(client.subscribe(c.id), c.id);
    }
  });
  client.on('message', ({ subscriptionId, data }) => {
    const c = got.channels.get(got.bySub.get(subscriptionId));
    const msg = JSON.parse(decoder.decode(data));
    validate(c.parsed, msg, c.topic, got.errors);
    got.count[c.topic] = (got.count[c.topic] ?? 0) + 1;
    got.last[c.topic] = msg;
    got.bytes += data.byteLength;
  });
  client.on('error', (e) => got.errors.push(`client error: ${e.message ?? e}`));
  return { client, got };
}

// A client that opens the protocol, subscribes to channels 1..11 and never reads
// again: its socket's buffers fill, the server must drop its messages, not wait.
function stalledClient(url) {
  const { hostname, port } = new URL(url);
  const socket = net.connect(Number(port), hostname);
  socket.on('error', () => {});
  socket.on('connect', () => {
    socket.write(`GET / HTTP/1.1\r\nHost: ${hostname}:${port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n` +
                 'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n' +
                 'Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n');
    const body = Buffer.from(JSON.stringify({
      op: 'subscribe', subscriptions: Array.from({ length: 11 }, (_, i) => ({ id: i, channelId: i + 1 })),
    }));
    const mask = Buffer.from([1, 2, 3, 4]);
    const head = body.length < 126 ? Buffer.from([0x81, 0x80 | body.length])
                                   : Buffer.from([0x81, 0x80 | 126, body.length >> 8, body.length & 255]);
    socket.write(Buffer.concat([head, mask, Buffer.from(body.map((b, i) => b ^ mask[i % 4]))]));
    socket.pause();  // and never read
  });
  return socket;
}

function medianMs(out) {
  return JSON.parse(readFileSync(path.join(out, 'stats.json'), 'utf8')).median_ms.frame;
}

async function liveRun(out, withClients) {
  const run = start(['run', '--dataset', data, '--out', out, '--realtime', '--every-frame', '--foxglove=0']);
  const url = await run.url;
  let live = null, stalled = null;
  if (withClients) {
    stalled = stalledClient(url);
    live = connect(url);
  }
  const status = await run.exited;
  if (status !== 0) fail(`sgslam run --foxglove exited ${status}:\n${run.log()}`);
  live?.client.close();
  stalled?.destroy();
  return { live, ms: medianMs(out), log: run.log() };
}

// One run with the clients, checked.
{
  const { live, ms } = await liveRun(path.join(args.work, 'live'), true);
  const { got } = live;
  check(got.serverInfo?.name === 'sgslam', 'serverInfo from sgslam');
  const advertised = [...got.channels.values()];
  check(advertised.length === Object.keys(EXPECTED).length &&
        advertised.every((c) => EXPECTED[c.topic] === c.schemaName && c.encoding === 'json' &&
                                c.schemaEncoding === 'jsonschema'),
        `the ${advertised.length} channels advertised with their schemas`);
  check(got.errors.length === 0, `every message matches its schema ${got.errors.slice(0, 5).join('; ')}`);
  for (const topic of Object.keys(EXPECTED)) check(got.count[topic] > 0, `${topic}: ${got.count[topic]} messages`);
  const jpeg = Buffer.from(got.last['/camera/image'].data, 'base64');
  check(jpeg[0] === 0xff && jpeg[1] === 0xd8, 'the images are JPEG');
  const cloud = got.last['/map/cloud'];
  check(Buffer.from(cloud.data, 'base64').length === cloud.point_stride * Math.floor(Buffer.from(cloud.data, 'base64').length / cloud.point_stride) &&
        Buffer.from(cloud.data, 'base64').length > 0, 'the dense cloud decodes to whole points');
  const p = got.last['/camera/pose'].pose.position;
  check([p.x, p.y, p.z].every(Number.isFinite), 'poses decode');
  console.log(`received ${Object.values(got.count).reduce((a, b) => a + b)} messages, ` +
              `${(got.bytes / 1048576).toFixed(1)} MiB; median frame ${ms.toFixed(1)} ms with a stalled client beside`);
}

// Alternated runs for the cost (--runs N).
if (Number(args.runs ?? 0) > 0) {
  const withMs = [], withoutMs = [];
  for (let i = 0; i < Number(args.runs); i++) {
    for (const w of i % 2 ? [true, false] : [false, true]) {
      const { ms } = await liveRun(path.join(args.work, `cost-${i}-${w}`), w);
      (w ? withMs : withoutMs).push(ms);
    }
  }
  const median = (a) => [...a].sort((x, y) => x - y)[Math.floor(a.length / 2)];
  console.log(`median frame ms over ${args.runs} runs each: without clients ${median(withoutMs).toFixed(2)} ` +
              `(${withoutMs.map((x) => x.toFixed(1)).join(' ')}), with a subscribed and a stalled client ` +
              `${median(withMs).toFixed(2)} (${withMs.map((x) => x.toFixed(1)).join(' ')})`);
}

// A finished run with `view --foxglove`: the map at once to a subscriber.
{
  const view = start(['view', path.join(args.work, 'live'), '--port', '0', '--foxglove=0']);
  const url = await view.url;
  const { client, got } = connect(url);
  const deadline = Date.now() + 20000;
  while (Date.now() < deadline && !['/map/trajectory', '/map/points', '/map/cloud', '/map/objects'].every((t) => got.count[t] > 0)) {
    await new Promise((r) => setTimeout(r, 100));
  }
  const stats = JSON.parse(readFileSync(path.join(args.work, 'live', 'stats.json'), 'utf8'));
  check(got.last['/map/trajectory']?.poses.length === stats.keyframes, `view: the keyframes (${stats.keyframes})`);
  check(Buffer.from(got.last['/map/points'].data, 'base64').length / 12 === stats.map_points,
        `view: the map points (${stats.map_points})`);
  check(got.count['/map/cloud'] === 1 && got.count['/map/objects'] === 1 && got.errors.length === 0,
        'view: the cloud and objects, each once, as their schemas say');

  // A plain web request is told what the port is; a port in use is refused, named.
  const port = new URL(url).port;
  const answer = await fetch(`http://127.0.0.1:${port}/`).then((r) => r.status + ' ' + r.statusText).catch((e) => e.message);
  check(answer.startsWith('400'), `a plain HTTP request gets 400 (${answer})`);
  const busy = spawnSync(args.sgslam, ['view', path.join(args.work, 'live'), '--port', '0', `--foxglove=${port}`],
                         { encoding: 'utf8', timeout: 20000 });
  check(busy.status !== 0 && /cannot listen on 127\.0\.0\.1:\d+/.test(busy.stderr),
        `a port in use is refused: ${busy.stderr.trim().split('\n').pop()}`);
  client.close();
  view.child.kill('SIGINT');
  check((await view.exited) === 0, 'sgslam view ended cleanly on Ctrl-C');
}
