// What the browser tests of service scenes share (web_services*_test.mjs, run by
// tests/web_services_test.sh): headless Chromium started as tests/web/web_test.mjs starts it, a
// page opened until it reports its load, its canvas read back, PSNR between two canvases, and the
// tally of checks.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

// SwiftShader's WebGL2 in headless Chromium (docs/web.md), nothing fetched but what the page asks.
export const CHROMIUM_FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

export const DEMO_BUILDINGS = 8;  // the demo city's (tests/web_services_test.sh: --buildings 8)

export function launchBrowser() {
  return chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: CHROMIUM_FLAGS });
}

// The tally: check(ok, what) prints one line per check; finish() prints the totals and exits.
export function checker() {
  const tally = { passed: 0, failed: 0 };
  tally.check = (ok, what) => {
    if (ok) { tally.passed++; console.log('ok    ' + what); } else { tally.failed++; console.log('FAIL  ' + what); }
  };
  tally.finish = () => {
    console.log(`${tally.passed} passed, ${tally.failed} failed`);
    process.exit(tally.failed ? 1 : 0);
  };
  return tally;
}

// When a page counts as done: `loaded`, or an error of the kind named by `until`:
//   'any-error'   any error;
//   'fatal-error' an error other than a source left out (those let the rest load on);
//   'load-failed' an error with no viewer made (the scene itself could not be loaded).
function settled(until) {
  const hv = window.hv;
  if (!hv) return false;
  if (hv.loaded) return true;
  if (until === 'fatal-error') return hv.errors.some((e) => !/left out\)$/.test(e));
  if (until === 'load-failed') return !hv.viewer && hv.errors.length > 0;
  return hv.errors.length > 0;
}

// The canvas's RGBA (its drawing buffer is preserved) as a Buffer, and web-NAME.png in outDir.
export async function canvasRgba(page, outDir, name) {
  const shot = await page.evaluate(() => {
    const canvas = document.getElementById('view');
    const c = document.createElement('canvas');
    c.width = canvas.width; c.height = canvas.height;
    const g = c.getContext('2d');
    g.drawImage(canvas, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    let bytes = '';
    for (let i = 0; i < d.length; ++i) bytes += String.fromCharCode(d[i]);
    return { rgba: btoa(bytes), png: canvas.toDataURL('image/png') };
  });
  fs.writeFileSync(path.join(outDir, `web-${name}.png`), Buffer.from(shot.png.split(',')[1], 'base64'));
  return Buffer.from(shot.rgba, 'base64');
}

// Opens `url` as `name`, waits until it is settled (above), checks that it reports loading
// complete and, unless `errorsExpected`, that it had no errors; returns its state (hv.loaded,
// errors, status, services, photoBytes, progress and missing, the status panel's and its sources'
// text), the URLs it requested, every error (the page's and the console's) and its canvas's RGBA.
export async function openPage(browser, tally, url, name, { outDir, until = 'any-error', errorsExpected = false } = {}) {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const errors = [], requests = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    if (m.type() === 'error') errors.push(m.text());
    if (process.env.HV_WEB_VERBOSE) console.log(name + ': ' + m.text());
  });
  page.on('request', (r) => requests.push(r.url()));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(settled, until, { timeout: 120000, polling: 250 });
  const state = await page.evaluate(() => ({ loaded: hv.loaded, errors: hv.errors, status: hv.status,
                                             services: hv.services || null, photoBytes: hv.photoBytes || null,
                                             text: document.getElementById('status').textContent,
                                             progress: hv.progress, missing: hv.missing,
                                             sources: document.getElementById('sources').textContent }));
  console.log(`${name}: loaded in ${((Date.now() - t0) / 1000).toFixed(1)} s` +
              (state.errors.length ? ': ' + state.errors.join(' | ') : ''));
  tally.check(state.loaded, `${name}: the page reports loading complete`);
  if (!errorsExpected)
    tally.check(state.errors.length === 0 && errors.length === 0, `${name}: no page errors` +
                (state.errors.length + errors.length ? ': ' + [...state.errors, ...errors].join(' | ') : ''));
  const rgba = await canvasRgba(page, outDir, name);
  await page.close();
  return { state, requests, errors: [...state.errors, ...errors], rgba };
}

// PSNR over RGB between two canvases' RGBA, and how many pixels differ at all.
export function psnr(a, b) {
  let se = 0, n = 0, differ = 0;
  for (let i = 0; i < a.length; i += 4) {
    let d2 = 0;
    for (let c = 0; c < 3; ++c) { const d = a[i + c] - b[i + c]; d2 += d * d; n++; }
    se += d2;
    if (d2) differ++;
  }
  return { db: se === 0 ? Infinity : 10 * Math.log10(255 * 255 / (se / n)), differ, pixels: a.length / 4 };
}

export const shownPsnr = (p) =>
  (p.db === Infinity ? 'inf (identical)' : p.db.toFixed(2) + ' dB') + `, ${p.differ} of ${p.pixels} pixels differ`;

// Checks that canvas `b` is `a`'s picture: identical or at least `min` dB, the figure printed.
export function expectSamePicture(tally, a, b, what, min) {
  const p = psnr(a, b);
  console.log(`${what}: PSNR ${shownPsnr(p)}`);
  tally.check(a.length === b.length && p.db >= min, `${what}: identical or >= ${min} dB`);
  return p;
}
