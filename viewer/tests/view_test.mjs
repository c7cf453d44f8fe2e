// `sgslam view` in a real browser: a finished run's folder (--run, or a synthetic
// run of walkers made here) is served, and the test checks that its map is drawn
// and its mover tracks replayed (when it has tracks.txt), reports the time from
// opening the page to the map drawn, and saves a screenshot.
//   node view_test.mjs --sgslam BIN --work DIR [--run OUTDIR] [--chromium PATH] [--screenshot FILE]
import { spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, rmSync } from 'node:fs';
import path from 'node:path';

import { check, collectErrors, fail, launchChromium, parseArgs, startServed } from './common.mjs';

const args = parseArgs(process.argv.slice(2));
const browser = await launchChromium(args.chromium);
let folder = args.run;
if (!folder) {
  rmSync(args.work, { recursive: true, force: true });
  mkdirSync(args.work, { recursive: true });
  const data = path.join(args.work, 'walkers');
  folder = path.join(args.work, 'out');
  for (const a of [['synth', '--out', data, '--preset', 'walkers', '--frames', '120'],
                   ['run', '--dataset', data, '--out', folder, '--sequential']]) {
    const r = spawnSync(args.sgslam, a, { encoding: 'utf8' });
    if (r.status !== 0) fail(`sgslam ${a[0]} failed: ${r.stderr}`);
  }
}
const served = startServed(args.sgslam, ['view', folder, '--port', '0']);
try {
  const url = await served.url;
  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const pageErrors = collectErrors(page);
  const start = Date.now();
  await page.goto(url);
  // Drawn: the page has rendered after the map arrived.
  await page.waitForFunction(() => window.sgslamViewer && window.sgslamViewer.drawnMaps >= 1, null,
                             { timeout: 60000, polling: 'raf' });
  const seconds = (Date.now() - start) / 1000;
  const v = await page.evaluate(() => window.sgslamViewer);
  console.log(`opened in ${seconds.toFixed(2)} s: ${v.mapPoints} map points, ${v.keyframes} keyframes, ` +
              `${v.cloudPoints} cloud points, ${v.cells} OctoMap cells, ${v.objects} objects`);
  check(!v.info.live && v.mapPoints > 0 && v.keyframes > 0 && v.cloudPoints > 0, 'the finished run\'s map arrived');
  check(v.truthPoints > 0, `the ground truth arrived, aligned (${v.truthPoints} poses)`);
  const view = await page.evaluate(() => window.sgslamViewer.litShare());
  check(view > 0.005, `the 3-D view is drawn (${(100 * view).toFixed(2)} % of its pixels lit)`);
  if (!args.run || existsSync(path.join(folder, 'tracks.txt'))) await checkMovers(page);
  check(pageErrors.length === 0, `no error in the page's console (${pageErrors.join('; ')})`);
  if (args.screenshot) await page.screenshot({ path: args.screenshot });
} finally {
  await browser.close();
  served.child.kill('SIGINT');
}
check((await served.exited) === 0, 'sgslam view ended cleanly on Ctrl-C');

// The movers layer: on at first; the slider replays the tracks, the first frame's
// all tentative (not drawn), the one it starts at with boxes and paths, which are
// drawn where nothing else is.
async function checkMovers(page) {
  const viewer = () => page.evaluate(() => window.sgslamViewer);
  const replayTo = (frame) => page.evaluate((f) => {
    const slider = document.getElementById('c-replay');
    slider.value = f;
    slider.dispatchEvent(new Event('input'));
  }, frame);
  check(await page.isChecked('input[data-layer=movers]'), 'the movers layer is on at first');
  check(await page.isVisible('#c-replay'), 'the finished run\'s tracks have a slider');
  const start = await page.inputValue('#c-replay');
  let v = await viewer();
  check(v.movers > 0 && v.moverTrailPoints > v.movers,
        `at frame ${Number(start) + 1}: ${v.movers} movers drawn, their paths ${v.moverTrailPoints} points ` +
        `(${await page.textContent('#p-movers')}; ${await page.textContent('#p-replay')})`);
  await replayTo(0);
  v = await viewer();
  check(v.movers === 0 && v.moverTrailPoints === 0, 'at the first frame, where every track is tentative, none drawn');
  await replayTo(start);
  for (const layer of ['path', 'truth', 'keyframes', 'points', 'cloud', 'objects']) {
    await page.uncheck(`input[data-layer=${layer}]`);
  }
  const withMovers = await page.evaluate(() => window.sgslamViewer.litShare());
  await page.uncheck('input[data-layer=movers]');
  const without = await page.evaluate(() => window.sgslamViewer.litShare());
  check(withMovers > without, `the movers are drawn (${(100 * withMovers).toFixed(3)} % of the view's pixels lit ` +
                              `with them, ${(100 * without).toFixed(3)} % without)`);
  for (const layer of ['path', 'truth', 'keyframes', 'points', 'cloud', 'objects', 'movers']) {
    await page.check(`input[data-layer=${layer}]`);
  }
}
