// The viewer in a real browser (Debian's chromium driven by playwright-core): a
// `sgslam run --viewer` of a synthetic sequence is opened, and the test checks
// that frames, poses, map points, the cloud and objects arrive and are drawn, that
// pause and step hold the run, and saves a screenshot. Then a run of a synthetic
// sequence of walkers (the objects scene has no movers): their tracks are drawn.
//   node browser_test.mjs --sgslam BIN --work DIR [--dataset DIR] [--parallel 1] [--chromium PATH]
//                         [--screenshot FILE]
// (the README's picture: --dataset ../shared/data/dyn_dev --parallel 1 --screenshot docs/viewer.png)
// Exit 77 (CTest: skipped) when chromium or playwright-core is missing.
import { spawnSync } from 'node:child_process';
import { mkdirSync, rmSync } from 'node:fs';
import path from 'node:path';

import { check, collectErrors, fail, launchChromium, litShare, parseArgs, startServed } from './common.mjs';

const args = parseArgs(process.argv.slice(2));
const browser = await launchChromium(args.chromium);
const work = args.work;
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
let data = args.dataset;  // default: a synthetic `objects` sequence made here
if (!data) {
  data = path.join(work, 'objects');
  const synth = spawnSync(args.sgslam, ['synth', '--out', data, '--preset', 'objects', '--frames', '150'],
                          { encoding: 'utf8' });
  if (synth.status !== 0) fail(`sgslam synth failed: ${synth.stderr}`);
}

// Sequential unless --parallel 1 (the sanitizer job's, for more threads at once).
const runArgs = ['run', '--dataset', data, '--out', path.join(work, 'out'), '--viewer=0'];
if (args.parallel !== '1') runArgs.push('--sequential');
const run = startServed(args.sgslam, runArgs);
let page = null;
try {
  const url = await run.url;
  console.log(`viewer at ${url}`);
  page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const pageErrors = collectErrors(page);
  await page.goto(url);
  await page.check('input[data-layer=cells]');  // the OctoMap's cells are sent only while shown
  const viewer = () => page.evaluate(() => window.sgslamViewer);

  // Pause at once: then the map is still small and the run waits for the page.
  await page.waitForFunction(() => window.sgslamViewer && window.sgslamViewer.frames >= 3, null, { timeout: 120000 });  // a loaded machine renders the first frames slowly
  await page.click('#b-pause');
  await page.waitForTimeout(1500);  // a frame being processed when pause was clicked arrives meanwhile
  const held = (await viewer()).frame.index;
  await page.waitForTimeout(1500);
  check((await viewer()).frame.index === held, `paused: the run holds at frame ${held}`);
  await page.click('#b-step');
  await page.waitForFunction((i) => window.sgslamViewer.frame.index === i + 1, held, { timeout: 20000 });
  await page.waitForTimeout(1000);
  check((await viewer()).frame.index === held + 1, 'step: exactly one frame more');
  await page.click('#b-pause');  // resume

  await page.waitForFunction(() => {
    const v = window.sgslamViewer;
    return v.frames >= 20 && v.maps >= 3 && v.mapPoints > 0 && v.cloudPoints > 0 && v.objects > 0 && v.cells > 0 &&
           v.truthPoints > 0;
  }, null, { timeout: 120000 });
  const v = await viewer();
  check(v.frame.pose && v.frame.pose.length === 16, `a pose arrived (frame ${v.frame.index}, ${v.frame.state})`);
  check(v.mapPoints > 0 && v.keyframes > 0, `${v.mapPoints} map points and ${v.keyframes} keyframes arrived`);
  check(v.cloudPoints > 0, `${v.cloudPoints} cloud points in ${v.pieces} pieces arrived`);
  check(v.objects > 0, `${v.objects} objects arrived`);
  check(v.cells > 0, `${v.cells} OctoMap cells arrived`);
  check(v.truthPoints > 0, `the ground truth arrived, aligned (${v.truthPoints} poses)`);
  check(v.errors.length === 0, `no error in the page's handling (${v.errors.join('; ')})`);
  const view = await page.evaluate(() => window.sgslamViewer.litShare());
  const image = await litShare(page, '#image');
  check(view > 0.005, `the 3-D view is drawn (${(100 * view).toFixed(2)} % of its pixels lit)`);
  check(image > 0.5, `the frame is drawn (${(100 * image).toFixed(1)} % of its pixels lit)`);
  check(pageErrors.length === 0, `no error in the page's console (${pageErrors.join('; ')})`);
  if (args.screenshot) {
    await page.uncheck('input[data-layer=cells]');  // the picture shows the cloud's colours
    await page.waitForTimeout(500);
    await page.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
} catch (e) {
  console.error(`sgslam run's log:\n${run.log().slice(-4000)}`);
  if (page) {
    const v = await page.evaluate(() => { const { frame, info, ...rest } = window.sgslamViewer; return rest; });
    console.error(`the page's state: ${JSON.stringify(v)}`);
  }
  throw e;
} finally {
  await browser.close();
  run.child.kill('SIGINT');
}
const code = await run.exited;
check(code === 0 || code === 130, `sgslam run ended cleanly (${code})`);
await checkLiveMovers();

// The movers layer, on at first, draws the confirmed tracks with their paths as
// the frames bring them.
async function checkLiveMovers() {
  const walkers = path.join(work, 'walkers');
  const synth = spawnSync(args.sgslam, ['synth', '--out', walkers, '--preset', 'walkers', '--frames', '90'],
                          { encoding: 'utf8' });
  if (synth.status !== 0) fail(`sgslam synth failed: ${synth.stderr}`);
  const browser = await launchChromium(args.chromium);
  const run = startServed(args.sgslam, ['run', '--dataset', walkers, '--out', path.join(work, 'walkers_out'),
                                        '--viewer=0', '--sequential']);
  try {
    const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
    const pageErrors = collectErrors(page);
    await page.goto(await run.url);
    check(await page.isChecked('input[data-layer=movers]'), 'the movers layer is on at first');
    check(!(await page.isVisible('#c-replay')), 'a live run has no replay slider');
    await page.waitForFunction(() => window.sgslamViewer.movers > 0 && window.sgslamViewer.moverTrailPoints > 10,
                               null, { timeout: 120000 });
    const v = await page.evaluate(() => window.sgslamViewer);
    check(v.frame.movers.some((m) => m.state === 'confirmed' && m.class === 'person' && m.extent.length === 3),
          `frame ${v.frame.index + 1} brought confirmed tracks: ${v.movers} movers drawn, their paths ` +
          `${v.moverTrailPoints} points (${await page.textContent('#p-movers')})`);
    check(v.errors.length === 0 && pageErrors.length === 0,
          `no error in the page (${[...v.errors, ...pageErrors].join('; ')})`);
  } finally {
    await browser.close();
    run.child.kill('SIGINT');
  }
  const code = await run.exited;
  check(code === 0 || code === 130, `sgslam run of the walkers ended cleanly (${code})`);
}
