// Pages from elsewhere cannot use a live viewer, in a real browser (Debian's
// chromium driven by playwright-core). During a `sgslam run --realtime --viewer`:
//   - a page served by another server on this machine (a port of this test's),
//   - a DNS-rebinding page (evil.example, which the browser resolves to 127.0.0.1,
//     at the viewer's port: its Origin matches its Host)
// try to open the viewer's WebSocket and send pause, step and requests. The test
// checks that neither socket opens nor gets data, that the run goes on (the
// viewer's own page sees its frames advance, not paused), that the own page works,
// and that a pause ends when the page that held it closes. Then `sgslam view
// --origin` of the run's outputs opens the viewer to a name (viewer.example).
//   node cross_origin_test.mjs --sgslam BIN --work DIR [--chromium PATH] [--screenshot FILE]
// Exit 77 (CTest: skipped) when chromium or playwright-core is missing.
import { spawnSync } from 'node:child_process';
import { mkdirSync, readFileSync, rmSync, unlinkSync, writeFileSync } from 'node:fs';
import http from 'node:http';
import path from 'node:path';

import { check, collectErrors, fail, launchChromium, parseArgs, startServed } from './common.mjs';

const args = parseArgs(process.argv.slice(2));
// evil.example resolves to this machine, as a rebinding attacker's DNS would make
// it; viewer.example too, as a name the user gave it.
// Chromium's own guard (Private/Local Network Access: a page from a public address
// may not reach a loopback one) is turned off: the viewer must hold without it, as
// in browsers that have none.
const browser = await launchChromium(args.chromium, [
  '--host-resolver-rules=MAP evil.example 127.0.0.1, MAP viewer.example 127.0.0.1',
  '--disable-features=BlockInsecurePrivateNetworkRequests,PrivateNetworkAccessSendPreflights,' +
    'PrivateNetworkAccessRespectPreflightResults,LocalNetworkAccessChecks']);
// Waits until fn(arg) holds in page, polled rather than at the page's animation
// frames: a page in the background (the own page while a probe is open) may draw none.
const until = (page, fn, arg, timeout) => page.waitForFunction(fn, arg, { timeout, polling: 100 });
const work = args.work;
rmSync(work, { recursive: true, force: true });
mkdirSync(work, { recursive: true });
const data = makeSequence(path.join(work, 'seq'));

// The page from elsewhere: opens the WebSocket of ?ws=, and says what happened.
const PROBE_PAGE = `<!doctype html><title>elsewhere</title><script>
const probe = window.probe = { opened: false, messages: 0, closed: false, fetched: null };
const q = new URLSearchParams(location.search);
const ws = new WebSocket(q.get('ws'));
ws.onopen = () => {
  probe.opened = true;
  for (const m of [{ control: 'pause' }, { control: 'step' }, { get: 'info' }, { get: 'frame', have: 0 }]) {
    ws.send(JSON.stringify(m));
  }
};
ws.onmessage = () => { probe.messages++; };
ws.onclose = () => { probe.closed = true; };
if (q.has('fetch')) {
  fetch(q.get('fetch')).then((r) => { probe.fetched = r.status; }, (e) => { probe.fetched = String(e); });
}
</script>`;
const elsewhere = http.createServer((req, res) => {
  res.writeHead(200, { 'Content-Type': 'text/html; charset=utf-8' });
  res.end(PROBE_PAGE);
});
await new Promise((resolve) => elsewhere.listen(0, '127.0.0.1', resolve));

const run = startServed(args.sgslam, ['run', '--dataset', data, '--out', path.join(work, 'out'), '--realtime',
                                      '--no-detector', '--viewer=0']);
try {
  const url = await run.url;
  const port = new URL(url).port;
  console.log(`viewer at ${url}, the page from elsewhere at port ${elsewhere.address().port}`);
  const own = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const ownErrors = collectErrors(own);
  await own.goto(url);
  const ownIndex = () => own.evaluate(() => window.sgslamViewer.frame.index);
  await until(own, () => window.sgslamViewer && window.sgslamViewer.frames >= 3, null, 120000);  // a loaded machine renders the first frames slowly

  const other = await probe(`http://127.0.0.1:${elsewhere.address().port}/?ws=ws://127.0.0.1:${port}/ws`);
  check(!other.opened && other.messages === 0,
        `a page from another server on this machine: its WebSocket was refused (${JSON.stringify(other)})`);
  const rebindingUrl = `http://evil.example:${port}/rebind.html`;
  const rebinding = await probe(`${rebindingUrl}?ws=ws://evil.example:${port}/ws&fetch=/index.html`, rebindingUrl);
  check(rebinding.fetched === 403,
        `a DNS-rebinding page reached the viewer, which refused its Host (${rebinding.fetched})`);
  check(!rebinding.opened && rebinding.messages === 0,
        `a DNS-rebinding page: its WebSocket was refused (${JSON.stringify(rebinding)})`);

  const after = await ownIndex();
  await until(own, (i) => window.sgslamViewer.frame.index >= i + 15 && !window.sgslamViewer.frame.paused,
              after, 30000);
  const later = await ownIndex();
  check(later >= after + 15, `the run went on, not paused: frames ${after + 1} to ${later + 1} on the own page`);
  check(/refused a WebSocket from a page at 'http:\/\/127\.0\.0\.1:\d+'/.test(run.log()) &&
        /refused a request for host 'evil\.example:\d+'/.test(run.log()), 'both refusals were logged');

  // A pause ends with the page that held it.
  await own.click('#b-pause');
  await until(own, () => window.sgslamViewer.paused === true, null, 10000);
  const held = await ownIndex();
  check(ownErrors.length === 0, `no error in the own page's console (${ownErrors.join('; ')})`);
  await own.close();
  const next = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  const nextErrors = collectErrors(next);
  await next.goto(url);
  await until(next, (i) => window.sgslamViewer && window.sgslamViewer.frame &&
                           window.sgslamViewer.frame.index >= i + 15 && !window.sgslamViewer.paused,
              held, 30000);
  check(/the last page that held the pause has closed/.test(run.log()),
        `the pause (at frame ${held + 1}) ended when its page closed: a new page sees the run go on`);
  check(nextErrors.length === 0, `no error in the new page's console (${nextErrors.join('; ')})`);
  if (args.screenshot) {
    await until(next, () => window.sgslamViewer.maps >= 2 && window.sgslamViewer.drawnMaps >= 2, null, 30000);
    await next.screenshot({ path: args.screenshot });
    console.log(`screenshot: ${args.screenshot}`);
  }
} catch (e) {
  console.error(`sgslam run's log:\n${run.log().slice(-4000)}`);
  await browser.close();
  throw e;
} finally {
  elsewhere.close();
  run.child.kill('SIGINT');
}
const code = await run.exited;
check(code === 0 || code === 130, `sgslam run ended cleanly (${code})`);

// A name the user allows: the page at http://viewer.example:PORT works.
const port = await freePort();
const view = startServed(args.sgslam, ['view', path.join(work, 'out'), '--port', String(port),
                                       '--origin', `http://viewer.example:${port}`]);
try {
  await view.url;
  const named = await browser.newPage();
  const namedErrors = collectErrors(named);
  await named.goto(`http://viewer.example:${port}/`);
  await until(named, () => window.sgslamViewer && window.sgslamViewer.drawnMaps >= 1, null, 30000);
  const v = await named.evaluate(() => window.sgslamViewer);
  check(v.mapPoints > 0 && namedErrors.length === 0,
        `view --origin: the page at http://viewer.example:${port}/ drew the map (${v.mapPoints} points; ` +
        `errors: ${namedErrors.join('; ')})`);
} catch (e) {
  console.error(`sgslam view's log:\n${view.log().slice(-4000)}`);
  throw e;
} finally {
  await browser.close();
  view.child.kill('SIGINT');
}
check((await view.exited) === 0, 'sgslam view ended cleanly on Ctrl-C');

// A port free now (sgslam view needs it before it serves: the allowed origin names it).
async function freePort() {
  const s = http.createServer();
  await new Promise((resolve) => s.listen(0, '127.0.0.1', resolve));
  const { port } = s.address();
  await new Promise((resolve) => s.close(resolve));
  return port;
}

// Opens pageUrl in a page of its own (served instead as the probe page when it is
// `fulfil`: the rebinding attacker's own server) until its WebSocket has closed.
async function probe(pageUrl, fulfil) {
  const page = await browser.newPage();
  if (fulfil) {
    await page.route((u) => u.href.startsWith(fulfil),
                     (route) => route.fulfill({ contentType: 'text/html', body: PROBE_PAGE }));
  }
  await page.goto(pageUrl);
  await until(page, () => window.probe.closed &&
                          (window.probe.fetched !== null || !new URLSearchParams(location.search).has('fetch')),
              null, 20000);
  const result = await page.evaluate(() => window.probe);
  await page.close();
  return result;
}

// A synthetic sequence that lasts two minutes at 30 Hz, from 60 rendered frames:
// they are listed forth and back again (the camera goes back and forth), without
// the ground truth and detections, which the new timestamps no longer match. The
// run must outlast the test on a busy machine (the test stops it): with
// --realtime, its frames follow the clock however slowly it goes.
function makeSequence(dir) {
  const synth = spawnSync(args.sgslam, ['synth', '--out', dir, '--preset', 'objects', '--frames', '60'],
                          { encoding: 'utf8' });
  if (synth.status !== 0) fail(`sgslam synth failed: ${synth.stderr}`);
  for (const f of ['associations.txt', 'groundtruth.txt', 'detections.txt']) unlinkSync(path.join(dir, f));
  for (const list of ['rgb', 'depth']) {
    const files = readFileSync(path.join(dir, `${list}.txt`), 'utf8').split('\n')
      .filter((l) => l && !l.startsWith('#')).map((l) => l.split(' ')[1]);
    const lines = [];
    for (let i = 0; lines.length < 3600; i++) {
      const k = i % (2 * files.length - 2);
      const t = (1700000000 + i / 30).toFixed(6);
      lines.push(`${t} ${files[k < files.length ? k : 2 * files.length - 2 - k]}`);
    }
    writeFileSync(path.join(dir, `${list}.txt`), `# ${list}, forth and back\n${lines.join('\n')}\n`);
  }
  return dir;
}
