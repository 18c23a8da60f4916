// Headless Chromium: the page reads the photographs' cameras from a WFS layer of camera points and
// the photographs from a IIIF image service itself (run by tests/web_services_test.sh; docs/services.md,
// "In the browser").
//   node tests/web/web_services_cameras_test.mjs --files URL --wfs URL --malformed URL --missing URL
//        --photos N --out DIR [--iiif-file URL]
// --files: the export's page; --wfs: the same view with ?scene= a description whose cameras come
// from the WFS layer (ms:cameras; with --iiif-file, its images are IIIF descriptions of iipsrv);
// --iiif-file: the same with the cameras from the export's cameras file by URL, the images from
// iipsrv. Checks: no page errors; every camera read from the WFS; the WFS page renders the picture
// of the cameras-file page (identical or >= 45 dB: the same cameras, whichever reader) and of the
// files (>= 45 dB, or >= 30 dB when the photographs come from iipsrv, which re-encodes them as
// JPEG, the bound of the native test tests/iiif_test.sh); IIIF: a preview and a full image per
// photograph, the bytes reported, previews apart. Faults: --malformed, a camera layer that is
// not GeoJSON: an error naming its URL, the buildings still read and the page completes;
// --missing, one photograph answering 404: an error naming its URL, the others arrive.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const photos = +args.photos;
const flags = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync'];
const BUILDINGS = 8;  // the demo city's (tests/web_services_test.sh: --buildings 8)

let passed = 0, failed = 0;
const check = (ok, what) => { if (ok) { passed++; console.log('ok    ' + what); } else { failed++; console.log('FAIL  ' + what); } };

const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: flags });
// Opens `url`, waits for the page to report loading complete (or, with untilError, for an error
// too), and returns its state, its requests and its canvas's RGBA.
async function open(url, name, { expectErrors = false } = {}) {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const errors = [], requests = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); if (process.env.HV_WEB_VERBOSE) console.log(name + ': ' + m.text()); });
  page.on('request', (r) => requests.push(r.url()));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.hv && (window.hv.loaded || (!window.hv.viewer && window.hv.errors.length > 0)),
                             null, { timeout: 120000, polling: 250 });
  const state = await page.evaluate(() => ({ loaded: hv.loaded, errors: hv.errors, status: hv.status, services: hv.services || null,
                                             photoBytes: hv.photoBytes || null, text: document.getElementById('status').textContent }));
  console.log(`${name}: loaded in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  check(state.loaded, `${name}: the page reports loading complete`);
  if (!expectErrors)
    check(state.errors.length === 0 && errors.length === 0, `${name}: no page errors` +
          (state.errors.length + errors.length ? ': ' + [...state.errors, ...errors].join(' | ') : ''));
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
  fs.writeFileSync(path.join(args.out, `web-${name}.png`), Buffer.from(shot.png.split(',')[1], 'base64'));
  await page.close();
  return { state, requests, errors: [...state.errors, ...errors], rgba: Buffer.from(shot.rgba, 'base64') };
}
// PSNR over RGB (Infinity: identical), and how many pixels differ.
function compare(a, b, what, minDb) {
  let se = 0, n = 0, differ = 0;
  for (let i = 0; i < a.rgba.length; i += 4) {
    let d2 = 0;
    for (let c = 0; c < 3; ++c) { const d = a.rgba[i + c] - b.rgba[i + c]; d2 += d * d; n++; }
    se += d2;
    if (d2) differ++;
  }
  const psnr = se === 0 ? Infinity : 10 * Math.log10(255 * 255 / (se / n));
  console.log(`${what}: PSNR ${psnr === Infinity ? 'inf (identical)' : psnr.toFixed(2) + ' dB'}, ${differ} of ${a.rgba.length / 4} pixels differ`);
  check(a.rgba.length === b.rgba.length && psnr >= minDb, `${what}: identical or >= ${minDb} dB`);
}

try {
  const files = await open(args.files, 'files');
  const wfs = await open(args.wfs, 'wfs-cameras');
  const s = wfs.state.services;
  check(s && s.cameraFeatures === photos && s.cameraPages >= 1 && wfs.state.status.photos === photos,
        `wfs-cameras: ${s ? s.cameraFeatures : 0} cameras from the WFS in ${s ? s.cameraPages : 0} page(s), ` +
        `${wfs.state.status.photos} photographs (${photos} expected)`);
  check(wfs.requests.some((u) => /REQUEST=GetFeature&TYPENAMES=ms%3Acameras/.test(u)) &&
        !wfs.requests.some((u) => /\/cameras[^/]*\.json$/.test(u)),
        'wfs-cameras: the page asked the WFS for the cameras (and fetched no cameras file)');
  if (args['iiif-file']) {
    const iiif = await open(args['iiif-file'], 'iiif-file');
    for (const [name, p] of [['iiif-file', iiif], ['wfs-cameras', wfs]]) {
      const b = p.state.photoBytes;
      console.log(`${name}: ${JSON.stringify(b)}; status: ${p.state.text.replace(/\n/g, ' | ')}`);
      check(b && b.previews === photos && b.images === photos && b.previewBytes > 0 && b.previewBytes < b.imageBytes / 4,
            `${name}: IIIF: ${photos} previews then ${photos} full images, the previews' bytes under a quarter of the full images'`);
      check(/photographs [\d.]+ MB \(\d+\), previews [\d.]+ MB \(\d+\)/.test(p.state.text), `${name}: the status reports the bytes fetched, previews apart`);
      const order = p.requests.filter((u) => /IIIF=/.test(u)).map((u) => (/info\.json/.test(u) ? 'info' : 'image'));
      check(order[0] === 'info', `${name}: the description asked first`);
    }
    compare(wfs, iiif, 'cameras from the WFS vs from the cameras file (photographs from IIIF)', 45);
    compare(wfs, files, 'services (WFS cameras, IIIF photographs) vs files (iipsrv re-encodes as JPEG)', 30);
  } else {
    compare(wfs, files, 'services (WFS cameras) vs files', 45);
  }
  const bad = await open(args.malformed, 'malformed-layer', { expectErrors: true });
  console.log('malformed-layer: ' + bad.errors.join(' | '));
  check(bad.errors.some((e) => /\/files\/malformed-cameras\.json\?[^ ]*REQUEST=GetFeature[^ ]*: not valid JSON/.test(e)),
        'malformed-layer: the error names the layer\'s URL and says it is not valid JSON');
  check(bad.state.services && bad.state.services.features === BUILDINGS, `malformed-layer: the buildings still read (${BUILDINGS})`);
  const missing = await open(args.missing, 'missing-photograph', { expectErrors: true });
  console.log('missing-photograph: ' + missing.errors.join(' | '));
  check(missing.state.errors.length === 1 && /^photograph \S+: \S*\/files\/web\/images\/missing\.jpg: HTTP 404/.test(missing.state.errors[0]),
        'missing-photograph: one error, naming the URL and the status');
  check(missing.state.status.arrived === photos - 1, `missing-photograph: the others arrived (${missing.state.status.arrived} of ${photos - 1})`);
} catch (e) {
  check(false, 'the test ran: ' + (e && e.stack ? e.stack : e));
} finally {
  await browser.close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
