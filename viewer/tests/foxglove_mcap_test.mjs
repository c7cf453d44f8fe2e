// `sgslam run --mcap` read back by the official MCAP reader (@mcap/core, the library
// Foxglove's own app reads files with; the app itself cannot be installed here):
// every channel there with its Foxglove schema, every message decoded and checked
// against its channel's JSON Schema, the content consistent with the run's own
// outputs; then a run stopped by Ctrl-C half-way still leaves a whole, indexed file.
//   node foxglove_mcap_test.mjs --sgslam BIN --work DIR
import { spawn, spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, statSync } from 'node:fs';
import { open } from 'node:fs/promises';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { check, fail, parseArgs, SKIP } from './common.mjs';
import { EXPECTED, validate } from './foxglove_common.mjs';

let McapIndexedReader, McapStreamReader, decompress;
try {
  ({ McapIndexedReader, McapStreamReader } = await import('@mcap/core'));
  ({ decompress } = await import('fzstd'));
} catch {
  console.log('SKIP: @mcap/core or fzstd is not installed (scripts/setup.sh runs npm ci in viewer)');
  process.exit(SKIP);
}

const args = parseArgs(process.argv.slice(2));
const root = path.join(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
rmSync(args.work, { recursive: true, force: true });
mkdirSync(args.work, { recursive: true });

function sgslam(a) {
  const r = spawnSync(args.sgslam, a, { encoding: 'utf8' });
  if (r.status !== 0) fail(`sgslam ${a.join(' ')} failed (${r.status}): ${r.stderr}`);
  return r;
}

async function indexedReader(file) {
  const fh = await open(file, 'r');
  const readable = {
    size: async () => BigInt((await fh.stat()).size),
    read: async (offset, length) => {
      const b = Buffer.alloc(Number(length));
      await fh.read(b, 0, Number(length), Number(offset));
      return b;
    },
  };
  const reader = await McapIndexedReader.Initialize({
    readable, decompressHandlers: { zstd: (b, n) => decompress(b, new Uint8Array(Number(n))) },
  });
  return { reader, close: () => fh.close() };
}

// The check itself finds what is wrong.
{
  const errors = [];
  validate({ type: 'object', properties: { a: { type: 'integer', minimum: 0 } }, required: ['a', 'b'] }, { a: -1.5, c: 1 },
           'm', errors);
  check(errors.length === 3, `the schema check finds a missing, an extra and a wrong field (${errors.join('; ')})`);
}

// The shipped schemas are @foxglove/schemas' own, unchanged.
{
  const r = spawnSync(process.execPath, [path.join(root, 'scripts', 'foxglove_schemas.mjs'), '--check'], { encoding: 'utf8' });
  check(r.status === 0, `foxglove/schemas matches @foxglove/schemas ${r.stderr}`);
}

// A recorded run of walkers with the semantic thread (cloud and objects).
const data = path.join(args.work, 'walkers');
const out = path.join(args.work, 'out');
const file = path.join(args.work, 'run.mcap');
sgslam(['synth', '--out', data, '--preset', 'walkers', '--frames', '90']);
sgslam(['run', '--dataset', data, '--out', out, '--sequential', '--mcap', file]);
const stats = JSON.parse(readFileSync(path.join(out, 'stats.json'), 'utf8'));

{
  const { reader, close } = await indexedReader(file);
  const channels = [...reader.channelsById.values()];
  check(channels.length === Object.keys(EXPECTED).length, `${channels.length} channels`);
  const schemas = new Map();
  for (const c of channels) {
    const s = reader.schemasById.get(c.schemaId);
    check(s && s.name === EXPECTED[c.topic] && s.encoding === 'jsonschema' && c.messageEncoding === 'json',
          `${c.topic}: ${s?.name}, JSON`);
    schemas.set(c.id, JSON.parse(new TextDecoder().decode(s.data)));
  }
  const count = {}, errors = [], last = {};
  let previous = -1n, ordered = true;
  for await (const m of reader.readMessages()) {
    const topic = reader.channelsById.get(m.channelId).topic;
    const msg = JSON.parse(new TextDecoder().decode(m.data));
    validate(schemas.get(m.channelId), msg, topic, errors);
    count[topic] = (count[topic] ?? 0) + 1;
    last[topic] = msg;
    if (m.logTime < previous) ordered = false;
    previous = m.logTime;
    if (topic === '/camera/image') {
      const jpeg = Buffer.from(msg.data, 'base64');
      if (!(jpeg[0] === 0xff && jpeg[1] === 0xd8) || msg.format !== 'jpeg') errors.push('an image is not a JPEG');
    }
    if (topic.startsWith('/map/') && msg.point_stride) {
      const bytes = Buffer.from(msg.data, 'base64').length;
      if (bytes % msg.point_stride !== 0) errors.push(`${topic}: ${bytes} bytes is no whole number of points`);
    }
    if (topic === '/camera/annotations') {
      for (const p of msg.points.flatMap((a) => a.type === 1 ? a.points : [])) {
        if (p.x < 0 || p.y < 0 || p.x > 640 || p.y > 480) { errors.push(`a keypoint outside the image: ${p.x} ${p.y}`); break; }
      }
    }
  }
  check(errors.length === 0, `every message matches its schema ${errors.slice(0, 5).join('; ')}`);
  check(ordered, 'the messages come in log-time order');
  for (const topic of Object.keys(EXPECTED)) check(count[topic] > 0, `${topic}: ${count[topic]} messages`);
  check(count['/camera/image'] === stats.frames && count['/stats'] === stats.frames,
        `an image and a stats message per frame (${stats.frames})`);
  check(count['/camera/pose'] === stats.tracked + (stats.odometry?.frames ?? 0), 'a pose per frame with a pose');
  check(last['/map/trajectory'].poses.length === stats.keyframes, `the final trajectory has every keyframe (${stats.keyframes})`);
  const points = Buffer.from(last['/map/points'].data, 'base64').length / 12;
  check(points === stats.map_points, `the final map points (${points}) are the run's (${stats.map_points})`);
  check(Buffer.from(last['/map/cloud'].data, 'base64').length / 16 > 1000, 'the final dense cloud has points');
  check(reader.statistics.messageCount === BigInt(Object.values(count).reduce((a, b) => a + b)),
        'the summary counts every message');
  // Seeking: the second half alone, by the chunk indexes.
  const mid = (reader.statistics.messageStartTime + reader.statistics.messageEndTime) / 2n;
  let second = 0;
  for await (const m of reader.readMessages({ topics: ['/stats'], startTime: mid })) second += m.logTime >= mid;
  check(second > 0 && second < count['/stats'], `a time range reads only its messages (${second} of ${count['/stats']})`);
  await close();
  const mib = statSync(file).size / 1048576;
  console.log(`${mib.toFixed(1)} MiB for ${stats.frames} frames: ${(mib / stats.frames * 1800).toFixed(0)} MiB a minute at 30 Hz`);
}

// Ctrl-C half-way: the file is still whole (summary, index), with what was recorded.
{
  const cut = path.join(args.work, 'cut.mcap');
  const child = spawn(args.sgslam, ['run', '--dataset', data, '--out', path.join(args.work, 'cut'), '--mcap', cut,
                                    '--realtime', '--every-frame'], { stdio: 'ignore' });
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve(code ?? signal)));
  // The recording starts just before the first frame (cut.mcap.part appears); the
  // 90 frames take 3 s at their pace: the signal 1.5 s in, half-way.
  const deadline = Date.now() + 60000;
  while (Date.now() < deadline) {
    await new Promise((r) => setTimeout(r, 50));
    try { statSync(`${cut}.part`); break; } catch { /* not there yet */ }
  }
  await new Promise((r) => setTimeout(r, 1500));
  child.kill('SIGINT');
  const status = await exited;
  check(status === 130, `the interrupted run ended with 130 (${status})`);
  const stream = new McapStreamReader({ validateCrcs: true, decompressHandlers: { zstd: (b, n) => decompress(b, new Uint8Array(Number(n))) } });
  stream.append(readFileSync(cut));
  let record;
  const kinds = {};
  while ((record = stream.nextRecord())) kinds[record.type] = (kinds[record.type] ?? 0) + 1;
  check(stream.done(), 'the interrupted file reads to its end, every CRC right');
  check(kinds.Footer === 1 && kinds.Statistics === 1 && kinds.ChunkIndex > 0, 'it has its summary and chunk index');
  const { reader, close } = await indexedReader(cut);
  const frames = Number((await reader.statistics).channelMessageCounts.get(
    [...reader.channelsById.values()].find((c) => c.topic === '/stats').id));
  check(frames > 0 && frames < 90, `it holds the ${frames} frames before the signal`);
  await close();
}
