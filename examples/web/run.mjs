// Opens examples/web/index.html?QUERY in headless Chromium on SwiftShader's WebGPU and prints
// what the page reports in #result (JSON), for tests/app/web_example.rs and for a person:
//
//   node examples/web/run.mjs 'dir=file:///tmp/w/&graph=pbr_gold&textures=file:///repo/graphs/'
//
// It drives Chromium over the DevTools protocol on a pipe (--remote-debugging-pipe: fds 3 and
// 4, messages ending in NUL), polling the page until it has reported, at most TIMEOUT_MS
// (env, default 120000). The browser is $CHROMIUM or `chromium`.
import { spawn } from 'node:child_process';
import { fileURLToPath, pathToFileURL } from 'node:url';
import path from 'node:path';

const query = process.argv[2] ?? '';
const page = pathToFileURL(path.join(path.dirname(fileURLToPath(import.meta.url)), 'index.html'));
const url = `${page.href}?${query}`;
const timeout = Number(process.env.TIMEOUT_MS ?? 120000);
const browser = spawn(process.env.CHROMIUM ?? 'chromium', [
  '--headless=new', '--no-sandbox', '--no-first-run', '--disable-gpu-sandbox',
  '--enable-unsafe-webgpu', '--use-webgpu-adapter=swiftshader',
  '--allow-file-access-from-files', '--remote-debugging-pipe', 'about:blank',
], { stdio: ['ignore', 'ignore', 'pipe', 'pipe', 'pipe'] });
let stderr = '';
browser.stderr.on('data', (d) => { stderr += d; });
const toBrowser = browser.stdio[3];
const fromBrowser = browser.stdio[4];

let next = 1;
const waiting = new Map();
let pending = '';
fromBrowser.on('data', (chunk) => {
  pending += chunk.toString('utf8');
  let end;
  while ((end = pending.indexOf('\0')) >= 0) {
    const message = JSON.parse(pending.slice(0, end));
    pending = pending.slice(end + 1);
    const w = waiting.get(message.id);
    if (w) {
      waiting.delete(message.id);
      if (message.error) w.reject(new Error(JSON.stringify(message.error)));
      else w.resolve(message.result);
    }
  }
});
function send(method, params = {}, sessionId) {
  const id = next++;
  toBrowser.write(JSON.stringify({ id, method, params, ...(sessionId ? { sessionId } : {}) }) + '\0');
  return new Promise((resolve, reject) => waiting.set(id, { resolve, reject }));
}
const fail = (message) => {
  const text = JSON.stringify({ status: 'error', message, browser: stderr.split('\n').filter((l) => /error/i.test(l) && !/dbus|mojo/i.test(l)).slice(-5) });
  browser.kill('SIGKILL');
  process.stdout.write(text + '\n', () => process.exit(1));
};
browser.on('error', (e) => fail(`cannot start ${process.env.CHROMIUM ?? 'chromium'}: ${e.message}`));
const timer = setTimeout(() => fail(`no result within ${timeout} ms`), timeout);

const { targetId } = await send('Target.createTarget', { url });
const { sessionId } = await send('Target.attachToTarget', { targetId, flatten: true });
for (;;) {
  const r = await send('Runtime.evaluate', {
    expression: "document.getElementById('result')?.textContent ?? ''",
    returnByValue: true,
  }, sessionId);
  const text = r.result.value;
  if (text) {
    clearTimeout(timer);
    await send('Browser.close').catch(() => {});
    browser.kill();
    // Exit once the whole result is written: a pipe takes large writes asynchronously.
    process.stdout.write(text + '\n', () => process.exit(JSON.parse(text).status === 'ok' ? 0 : 1));
    break;
  }
  await new Promise((r) => setTimeout(r, 100));
}
