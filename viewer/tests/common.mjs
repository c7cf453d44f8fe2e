// Shared by the viewer's browser tests: arguments, checks, the chromium launch
// (or a skip, 77 for CTest, where it is missing), a served sgslam process and the
// share of a canvas's pixels that differ from the page's background.
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';

export const SKIP = 77;

export function parseArgs(argv) {
  const out = {};
  for (let i = 0; i < argv.length; i++) {
    if (argv[i].startsWith('--')) out[argv[i].slice(2)] = argv[i + 1];
  }
  return out;
}

export function fail(message) {
  console.error(`FAIL: ${message}`);
  process.exitCode = 1;
  throw new Error(message);
}

export function check(condition, message) {
  if (!condition) fail(message);
  console.log(`ok: ${message}`);
}

export async function launchChromium(executablePath = '/usr/bin/chromium', extraArgs = []) {
  if (!existsSync(executablePath)) {
    console.log(`SKIP: no chromium at ${executablePath} (scripts/setup.sh installs Debian's chromium)`);
    process.exit(SKIP);
  }
  let chromium;
  try {
    ({ chromium } = await import('playwright-core'));
  } catch {
    console.log('SKIP: playwright-core is not installed (scripts/setup.sh runs npm ci in viewer)');
    process.exit(SKIP);
  }
  // WebGL without a GPU: SwiftShader, which headless chromium only takes when asked.
  // The page is composited by Skia in software: compositing with SwiftShader took
  // a whole core (18 of 22 s in the GPU process during a run, 2 of 14.5 s without).
  return chromium.launch({
    executablePath,
    args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--ignore-gpu-blocklist',
           '--disable-gpu-compositing', ...extraArgs],
  });
}

// Starts `bin args...` and resolves with the process and the address it prints.
export function startServed(bin, args) {
  const child = spawn(bin, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let log = '';
  const url = new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`no viewer address printed:\n${log}`)), 60000);
    const onData = (chunk) => {
      log += chunk;
      const m = log.match(/open (http:\/\/[^ ]+\/) in a web browser/);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', onData);
    child.on('exit', (code) => reject(new Error(`${bin} ended (${code}) before serving:\n${log}`)));
  });
  const exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve(code ?? signal)));
  return { child, url, exited, log: () => log };
}

// In the page: the share of a 2-D canvas's pixels unlike the background (#15181c).
export function litShare(page, selector) {
  return page.evaluate((sel) => {
    const source = document.querySelector(sel);
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
  }, selector);
}

// Collects the page's uncaught errors and console errors.
export function collectErrors(page) {
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  return errors;
}
