// The viewer in a real browser (Debian's chromium driven by playwright-core): a
// `sgslam run --viewer` of a synthetic sequence is opened, and the test checks
// that frames, poses, map points, the cloud and objects arrive and are drawn, that
// pause and step hold the run, and saves a screenshot.
//   node browser_test.mjs --sgslam BIN --work DIR [--chromium PATH] [--screenshot FILE]
// Exit 77 (CTest: skipped) when chromium or playwright-core is missing.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, rmSync } from 'node:fs';
import path from 'node:path';

const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
  return acc;
}, []));
const chromiumPath = args.chromium || '/usr/bin/chromium';
const SKIP = 77;

function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exitCode = 1;
  throw new Error(message);
}
function check(condition, message) {
  if (!condition) fail(message);
  console.log(`ok: ${message}`);
}

if (!existsSync(chromiumPath)) {
  console.log(`SKIP: no chromium at ${chromiumPath} (scripts/setup.sh installs Debian's chromium)`);
  process.exit(SKIP);
}
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  console.log('SKIP: playwright-core is not installed (scripts/setup.sh runs npm ci in viewer)');
  process.exit(SKIP);
}

const work = args.work;
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
const data = path.join(work, 'objects');
const synth = spawnSync(args.sgslam, ['synth', '--out', data, '--preset', 'objects', '--frames', '150'],
                        { encoding: 'utf8' });
if (synth.status !== 0) fail(`sgslam synth failed: ${synth.stderr}`);

// --sequential: the run waits while the page has it paused.
const run = spawn(args.sgslam, ['run', '--dataset', data, '--out', path.join(work, 'out'), '--viewer=0',
                                '--sequential'], { stdio: ['ignore', 'pipe', 'pipe'] });
let log = '';
const url = await new Promise((resolve, reject) => {
  const timer = setTimeout(() => reject(new Error(`no viewer address printed:\n${log}`)), 30000);
  const onData = (chunk) => {
    log += chunk;
    const m = log.match(/viewer: open (http:\/\/[^ ]+\/) /);
    if (m) { clearTimeout(timer); resolve(m[1]); }
  };
  run.stdout.on('data', onData);
  run.stderr.on('data', onData);
  run.on('exit', (code) => reject(new Error(`sgslam run ended (${code}) before the viewer started:\n${log}`)));
});
console.log(`viewer at ${url}`);

const browser = await chromium.launch({
  executablePath: chromiumPath,
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--ignore-gpu-blocklist'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
  await page.goto(url);
  const viewer = () => page.evaluate(() => window.sgslamViewer);

  // Pause at once: then the map is still small and the run waits for the page.
  await page.waitForFunction(() => window.sgslamViewer && window.sgslamViewer.frames >= 3, null, { timeout: 30000 });
  await page.click('#b-pause');
  await page.waitForTimeout(1500);  // a frame being processed when pause was clicked arrives meanwhile
  const held = (await viewer()).frame.index;
  await page.waitForTimeout(1500);
  check((await viewer()).frame.index === held, `paused: the run holds at frame ${held}`);
  await page.click('#b-step');
  await page.waitForFunction((i) => window.sgslamViewer.frame.index === i + 1, held, { timeout: 10000 });
  await page.waitForTimeout(1000);
  check((await viewer()).frame.index === held + 1, 'step: exactly one frame more');
  await page.click('#b-pause');  // resume

  await page.waitForFunction(() => {
    const v = window.sgslamViewer;
    return v.frames >= 20 && v.maps >= 3 && v.mapPoints > 0 && v.cloudPoints > 0 && v.objects > 0;
  }, null, { timeout: 90000 });
  const v = await viewer();
  check(v.frame.pose && v.frame.pose.length === 16, `a pose arrived (frame ${v.frame.index}, ${v.frame.state})`);
  check(v.mapPoints > 0 && v.keyframes > 0, `${v.mapPoints} map points and ${v.keyframes} keyframes arrived`);
  check(v.cloudPoints > 0, `${v.cloudPoints} cloud points in ${v.pieces} pieces arrived`);
  check(v.objects > 0, `${v.objects} objects arrived`);
  check(v.errors.length === 0, `no error in the page's handling (${v.errors.join('; ')})`);

  // Not blank: the 3-D canvas has many pixels unlike the background, and so does the image.
  const lit = await page.evaluate(() => {
    const count = (source) => {
      const c = document.createElement('canvas');
      c.width = source.width; c.height = source.height;
      const g = c.getContext('2d');
      g.drawImage(source, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      for (let i = 0; i < d.length; i += 4) {
        if (Math.abs(d[i] - 0x15) + Math.abs(d[i + 1] - 0x18) + Math.abs(d[i + 2] - 0x1c) > 30) n++;
      }
      return n / (c.width * c.height);
    };
    return { view: count(document.querySelector('#view3d canvas')), image: count(document.getElementById('image')) };
  });
  check(lit.view > 0.005, `the 3-D view is drawn (${(100 * lit.view).toFixed(2)} % of its pixels lit)`);
  check(lit.image > 0.5, `the frame is drawn (${(100 * lit.image).toFixed(1)} % of its pixels lit)`);
  check(pageErrors.length === 0, `no error in the page's console (${pageErrors.join('; ')})`);
  if (args.screenshot) {
    await page.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
} finally {
  await browser.close();
  run.kill('SIGINT');
}
const code = await new Promise((resolve) => run.on('exit', (c) => resolve(c)));
check(code === 0 || code === 130, `sgslam run ended cleanly (${code})`);
