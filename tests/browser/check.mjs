// Opens every HTML report page in Debian's headless Chromium, over the
// Chrome DevTools protocol (Node's built-in WebSocket; no packages), and
// checks what a person would see:
//   - the page loads with no console error and no uncaught exception;
//   - it loads nothing from the network (only file: and data: URLs);
//   - every image has rendered (complete, naturalWidth > 0);
//   - every number marked with data-json-path equals the value at that
//     JSON pointer in the JSON file beside the page, to the 4 significant
//     digits shown;
//   - every link leads to a file that exists;
//   - the demo's front page (index.html at the root) shows four result figures;
//   - a screenshot at a laptop's size (1366×768) is written for review.
// Usage: node --experimental-websocket check.mjs SCREENSHOT_DIR PAGE.html...
// Ends with "N passed, N failed" and a non-zero exit when any check fails.
import { spawn } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, writeFileSync, mkdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve, dirname, relative } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const [shotDir, ...pages] = process.argv.slice(2);
if (!shotDir || pages.length === 0) {
  console.error('usage: check.mjs SCREENSHOT_DIR PAGE.html...');
  process.exit(2);
}
mkdirSync(shotDir, { recursive: true });
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
const profile = mkdtempSync(join(tmpdir(), 'mre-browser-'));
const browser = spawn(chromium, [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  `--user-data-dir=${profile}`, '--remote-debugging-port=0', '--window-size=1366,768',
  'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe'] });

function fail(msg) {
  console.error(msg);
  try { browser.kill(); } catch {}
  try { rmSync(profile, { recursive: true, force: true }); } catch {}
  process.exit(1);
}
const giveUp = setTimeout(() => fail('browser check timed out after 300 s'), 300_000);

const port = await new Promise((res, rej) => {
  let err = '';
  browser.stderr.on('data', (d) => {
    err += d;
    const m = err.match(/DevTools listening on ws:\/\/[^:]+:(\d+)\//);
    if (m) res(m[1]);
  });
  browser.on('exit', (code) => rej(new Error(`chromium exited (${code}) before listening:\n${err}`)));
}).catch((e) => fail(e.message));

const targets = await (await fetch(`http://127.0.0.1:${port}/json/list`)).json();
const target = targets.find((t) => t.type === 'page');
const ws = new WebSocket(target.webSocketDebuggerUrl);
await new Promise((res) => ws.addEventListener('open', res, { once: true }));

let nextId = 1;
const pending = new Map();
const listeners = [];
ws.addEventListener('message', (ev) => {
  const msg = JSON.parse(ev.data);
  if (msg.id && pending.has(msg.id)) {
    const { res, rej } = pending.get(msg.id);
    pending.delete(msg.id);
    msg.error ? rej(new Error(JSON.stringify(msg.error))) : res(msg.result);
  } else if (msg.method) {
    for (const l of listeners) l(msg);
  }
});
const send = (method, params = {}) => new Promise((res, rej) => {
  const id = nextId++;
  pending.set(id, { res, rej });
  ws.send(JSON.stringify({ id, method, params }));
});
const evaluate = async (expr) => (await send('Runtime.evaluate', { expression: expr, returnByValue: true })).result.value;

let errors = [];
listeners.push((m) => {
  if (m.method === 'Runtime.consoleAPICalled' && (m.params.type === 'error' || m.params.type === 'assert')) {
    errors.push(`console.${m.params.type}: ${m.params.args.map((a) => a.value ?? a.description).join(' ')}`);
  } else if (m.method === 'Runtime.exceptionThrown') {
    errors.push(`exception: ${m.params.exceptionDetails.text}`);
  } else if (m.method === 'Log.entryAdded' && m.params.entry.level === 'error') {
    errors.push(`log: ${m.params.entry.text} ${m.params.entry.url ?? ''}`);
  } else if (m.method === 'Network.requestWillBeSent') {
    const url = m.params.request.url;
    if (!url.startsWith('file:') && !url.startsWith('data:')) errors.push(`network request: ${url}`);
  }
});
await send('Runtime.enable');
await send('Log.enable');
await send('Network.enable');
await send('Page.enable');
await send('Emulation.setDeviceMetricsOverride', { width: 1366, height: 768, deviceScaleFactor: 1, mobile: false });

// The value at a JSON pointer ("#/a/0/b").
function at(value, pointer) {
  for (const raw of pointer.split('/').slice(1)) {
    const key = raw.replace(/~1/g, '/').replace(/~0/g, '~');
    if (value === null || typeof value !== 'object' || !(key in value)) return undefined;
    value = value[key];
  }
  return value;
}

// The page shows 4 significant digits (integers exactly): half a unit in
// the 4th digit, relative, is the most the shown number may differ.
function matches(shown, value) {
  const x = Number(shown);
  if (typeof value !== 'number' || !Number.isFinite(x)) return false;
  return Math.abs(x - value) <= 5.0001e-4 * Math.abs(value) + 1e-12;
}

let passed = 0;
let failed = 0;
function check(ok, what) {
  if (ok) passed++;
  else { failed++; console.log(`FAIL ${what}`); }
}

// Pages are named relative to the folder they all lie in.
const absPages = pages.map((p) => resolve(p));
let root = dirname(absPages[0]);
while (!absPages.every((p) => p.startsWith(root + '/'))) root = dirname(root);

for (const abs of absPages) {
  const name = relative(root, abs);
  errors = [];
  const loaded = new Promise((res) => listeners.push(function onLoad(m) {
    if (m.method === 'Page.loadEventFired') { listeners.splice(listeners.indexOf(onLoad), 1); res(); }
  }));
  await send('Page.navigate', { url: pathToFileURL(abs).href });
  await loaded;

  const images = await evaluate(
    '[...document.images].map((i) => ({ alt: i.alt, ok: i.complete && i.naturalWidth > 0 }))');
  for (const img of images) check(img.ok, `${name}: image ${img.alt} did not render`);

  // The demo's front page opens with its four results, each a figure that rendered.
  if (name === 'index.html') {
    const results = await evaluate(
      '[...document.querySelectorAll("section.results figure")].map((f) => { const i = f.querySelector("img"); ' +
      'return { caption: f.innerText.slice(0, 60), ok: !!i && i.complete && i.naturalWidth > 0 }; })');
    check(results.length === 4, `${name}: ${results.length} result figures, expected 4`);
    for (const r of results) check(r.ok, `${name}: result figure "${r.caption}" has no rendered image`);
  }

  const numbers = await evaluate(
    '[...document.querySelectorAll("[data-json-path]")].map((e) => [e.dataset.jsonPath, e.textContent])');
  const files = new Map();
  let bad = 0;
  for (const [path, shown] of numbers) {
    const [file, pointer] = path.split('#');
    if (!files.has(file)) files.set(file, JSON.parse(readFileSync(resolve(dirname(abs), file), 'utf8')));
    const value = at(files.get(file), pointer);
    if (!matches(shown, value)) {
      bad++;
      if (bad <= 5) console.log(`  ${name}: ${path} shows ${shown}, the file has ${value}`);
    }
  }
  check(bad === 0, `${name}: ${bad} of ${numbers.length} numbers differ from their JSON file`);

  // Every link leads to a file that exists (links are relative file paths).
  const links = await evaluate('[...document.links].map((a) => a.href)');
  const broken = links.filter((href) => !href.startsWith('file:') || !existsSync(fileURLToPath(href)));
  check(broken.length === 0, `${name}: broken links ${broken.slice(0, 5).join(', ')}`);

  const text = await evaluate('document.body.innerText.length');
  check(text > 100, `${name}: page body is (nearly) empty`);

  const shot = await send('Page.captureScreenshot', { format: 'png' });
  const shotName = name.replace(/[\/\\]/g, '__').replace(/\.html$/, '.png');
  writeFileSync(join(shotDir, shotName), Buffer.from(shot.data, 'base64'));

  check(errors.length === 0, `${name}: ${errors.join('; ')}`);
  console.log(`${name}: ${images.length} images, ${numbers.length} numbers, ${links.length} links checked; screenshot ${join(shotDir, shotName)}`);
}

clearTimeout(giveUp);
ws.close();
const exited = new Promise((res) => browser.once('exit', res));
browser.kill();
await exited;
// Chromium's helper processes may still write to the profile for a moment
// after the browser exits: removing it is best effort, never a failed check.
try {
  rmSync(profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 });
} catch (e) {
  console.error(`note: could not remove ${profile}: ${e.code}`);
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
