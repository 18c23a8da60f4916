// Headless Chromium: the page opens a service-backed scene itself (run by tests/web_services_test.sh;
// docs/services.md, "In the browser").
//   node tests/web/web_services_test.mjs FILES_URL SERVICES_URL OUTDIR [OAPIF_URL]
// Loads FILES_URL (the export's files) and SERVICES_URL (the same view with ?scene=: buildings from
// the WFS, the DTM from the WCS, cameras and photographs by URL), waits for each page to report
// loading complete, checks there were no errors, that the service page fetched no buildings mesh
// of the export and read every footprint from the WFS, and compares the two canvases: identical
// or PSNR >= 45 dB over RGB. Writes web-files.png and web-services.png into OUTDIR. OAPIF_URL: a
// description whose buildings come from MapServer's OGC API – Features, which serves CRS84 only:
// the page must refuse it, naming the URL, rather than place the buildings wrong.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const [filesUrl, servicesUrl, outDir, oapifUrl] = process.argv.slice(2);
const flags = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync'];
// The same renderer, cameras, photographs and terrain; the buildings' footprints went through
// MapServer's GeoJSON (coordinates to 1 µm) and their roofs are triangulated by ear clipping rather
// than GEOS: the pictures may differ in the last bits at a few pixels, hence a bound, not equality.
const MIN_PSNR = 45.0;
const BUILDINGS = 8;  // the demo city's (tests/web_services_test.sh: --buildings 8)

let passed = 0, failed = 0;
const check = (ok, what) => { if (ok) { passed++; console.log('ok    ' + what); } else { failed++; console.log('FAIL  ' + what); } };

const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: flags });
async function open(url, name) {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const errors = [], requests = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); if (process.env.HV_WEB_VERBOSE) console.log(name + ': ' + m.text()); });
  page.on('request', (r) => requests.push(r.url()));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.hv && (window.hv.loaded || window.hv.errors.length > 0), null, { timeout: 90000, polling: 250 });
  const state = await page.evaluate(() => ({ loaded: hv.loaded, errors: hv.errors, status: hv.status, services: hv.services || null,
                                             progress: hv.progress, missing: hv.missing,
                                             sources: document.getElementById('sources').textContent }));
  console.log(`${name}: loaded in ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  check(state.loaded, `${name}: the page reports loading complete`);
  check(state.errors.length === 0 && errors.length === 0, `${name}: no page errors` +
        (state.errors.length + errors.length ? ': ' + [...state.errors, ...errors].join(' | ') : ''));
  // The canvas's pixels (its drawing buffer is preserved) and a PNG of it.
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
  await page.close();
  return { state, requests, rgba: Buffer.from(shot.rgba, 'base64') };
}

try {
  const files = await open(filesUrl, 'files');
  const services = await open(servicesUrl, 'services');
  const s = services.state.services;
  check(s && s.features === BUILDINGS && s.featurePages >= 1,
        `services: ${s ? s.features : 0} footprints from the WFS in ${s ? s.featurePages : 0} page(s) (${BUILDINGS} expected)`);
  // The progress per source (web/services_progress.js): the totals read, and the panel's line.
  const pr = services.state.progress, photos = services.state.status.photos;
  console.log('services: ' + services.state.sources);
  check(pr.buildings && pr.buildings.done && pr.buildings.features === BUILDINGS && pr.buildings.pages === s.featurePages,
        `services: hv.progress.buildings: ${pr.buildings ? pr.buildings.features : 0} features in ${pr.buildings ? pr.buildings.pages : 0} page(s)`);
  check(pr.terrain && pr.terrain.done && pr.terrain.cols > 1 && pr.terrain.rows > 1, 'services: hv.progress.terrain: the WCS grid\'s size');
  check(pr.photographs && pr.photographs.done && pr.photographs.full === photos && pr.photographs.of === photos && photos === 12,
        `services: hv.progress.photographs: ${pr.photographs ? pr.photographs.full : 0} of ${photos} (12 expected)`);
  check(services.state.sources.startsWith('sources: ') && !services.state.sources.includes('\n') &&
        services.state.sources.includes(`buildings WFS page ${s.featurePages}, ${BUILDINGS} features`) &&
        services.state.sources.includes(`terrain WCS grid ${pr.terrain.cols}×${pr.terrain.rows}`) &&
        services.state.sources.includes(`photographs ${photos} of ${photos}`),
        'services: the panel\'s one line once loaded names the features, the grid and the photographs');
  check(services.state.missing.length === 0 && files.state.missing.length === 0, 'services, files: nothing missing');
  check(!services.requests.some((u) => /buildings\.bin/.test(u)) && files.requests.some((u) => /buildings\.bin/.test(u)),
        "services: the export's buildings mesh was not fetched (the files page fetched it)");
  check(services.requests.some((u) => /REQUEST=GetFeature/.test(u)) && services.requests.some((u) => /REQUEST=GetCoverage/.test(u)),
        'services: the page asked the WFS and the WCS itself');
  let se = 0, n = 0, differ = 0;
  for (let i = 0; i < files.rgba.length; i += 4) {
    let d2 = 0;
    for (let c = 0; c < 3; ++c) { const d = files.rgba[i + c] - services.rgba[i + c]; d2 += d * d; n++; }
    se += d2;
    if (d2) differ++;
  }
  const psnr = se === 0 ? Infinity : 10 * Math.log10(255 * 255 / (se / n));
  console.log(`services vs files: PSNR ${psnr === Infinity ? 'inf (identical)' : psnr.toFixed(2) + ' dB'}, ${differ} of ${files.rgba.length / 4} pixels differ`);
  check(files.rgba.length === services.rgba.length && psnr >= MIN_PSNR,
        `the service scene renders the file scene's picture (identical or >= ${MIN_PSNR} dB)`);
  if (oapifUrl) {
    const page = await browser.newPage();
    await page.goto(oapifUrl);
    await page.waitForFunction(() => window.hv && (window.hv.loaded || window.hv.errors.length > 0), null, { timeout: 60000, polling: 250 });
    const errors = await page.evaluate(() => hv.errors);
    const missing = await page.evaluate(() => hv.missing);
    console.log('oapif: ' + errors.join(' | '));
    check(missing.length === 1 && missing[0].kind === 'buildings' && /^OAPIF:http:.*\/collections\/buildings$/.test(missing[0].location) &&
          /did not answer in EPSG:2154/.test(missing[0].reason),
          'oapif: hv.missing: the buildings, by the description\'s path, and why');
    check(errors.some((e) => /\/collections\/buildings\/items\?.*: the service did not answer in EPSG:2154 \(Content-Crs: none, i\.e\. CRS84\)/.test(e)),
          'oapif: features in CRS84 refused, naming the URL (the browser does not reproject)');
    await page.close();
  }
} catch (e) {
  check(false, 'the test ran: ' + (e && e.stack ? e.stack : e));
} finally {
  await browser.close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
