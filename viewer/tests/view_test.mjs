// `sgslam view` in a real browser: a finished run's folder (--run, or a synthetic
// run made here) is served, and the test checks that its map is drawn, reports the
// time from opening the page to the map drawn, and saves a screenshot.
//   node view_test.mjs --sgslam BIN --work DIR [--run OUTDIR] [--chromium PATH] [--screenshot FILE]
import { spawnSync } from 'node:child_process';
import { mkdirSync, rmSync } from 'node:fs';
import path from 'node:path';

import { check, collectErrors, fail, launchChromium, parseArgs, startServed } from './common.mjs';

const args = parseArgs(process.argv.slice(2));
const browser = await launchChromium(args.chromium);
let folder = args.run;
if (!folder) {
  rmSync(args.work, { recursive: true, force: true });
  mkdirSync(args.work, { recursive: true });
  const data = path.join(args.work, 'objects');
  folder = path.join(args.work, 'out');
  for (const a of [['synth', '--out', data, '--preset', 'objects', '--frames', '120'],
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
  check(pageErrors.length === 0, `no error in the page's console (${pageErrors.join('; ')})`);
  if (args.screenshot) await page.screenshot({ path: args.screenshot });
} finally {
  await browser.close();
  served.child.kill('SIGINT');
}
check((await served.exited) === 0, 'sgslam view ended cleanly on Ctrl-C');
