// Headless Chromium: the page opens a service scene whose description has no "files" (no web
// export at all; run by tests/web_services_test.sh; docs/services.md, "In the browser"): the module
// meshes the WCS grid and places the origin, up and terrain rectangle by the native loader's rules
// (hv/scene/scene_frame.h), and fits EPSG:4978 with proj4js for earth-centred 3D Tiles.
//   node tests/web/web_services_nofiles_test.mjs OUTDIR FILES_URL NOFILES_URL PFILES_URL PNOFILES_URL MISSING_URL
// FILES_URL: the export's page of the held-out view; NOFILES_URL: the same view with ?scene= a
// description without "files" (terrain from the WCS, buildings from the WFS, a cameras file and
// its photographs by URL outside the export's folder, the held-out views by "views"): no file of
// the export fetched (the page's own files apart), and the picture within MIN_PSNR_NO_POINTS: the
// export's scene also holds the demo's lidar (points.bin, drawn or not: it widens the geometry's
// tile grid and depth ranges, src/hv/render/frame_builder_scene.cpp), which this description
// lacks, so pixels at depth ties may differ. PFILES_URL / PNOFILES_URL: the same data on both
// sides, the point pass on: the export's service page (terrain.bin, the export's PROJ fit) and the
// description without files (the WCS grid meshed in the module, proj4js and the module's fit),
// both with the points of the 3D Tiles tileset: identical or >= MIN_PSNR. MISSING_URL: the
// terrain's WCS and the cameras file answer 404: each named (the description, the field, the
// URL), the buildings still read and the page completes.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const [outDir, filesUrl, nofilesUrl, pfilesUrl, pnofilesUrl, missingUrl] = process.argv.slice(2);
const flags = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync'];
const MIN_PSNR = 45.0, MIN_PSNR_NO_POINTS = 30.0;
const BUILDINGS = 8;  // the demo city's (tests/web_services_test.sh: --buildings 8)
// The page's own files, served from the export's folder like any page; anything else there is the export's.
const PAGE_FILES = /\/(index\.html|[a-z0-9_]+\.js|histoview\.css|histoview_web\.wasm)(\?|$)/;

let passed = 0, failed = 0;
const check = (ok, what) => { if (ok) { passed++; console.log('ok    ' + what); } else { failed++; console.log('FAIL  ' + what); } };

const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: flags });
async function open(url, name, errorsExpected) {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const errors = [], requests = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); if (process.env.HV_WEB_VERBOSE) console.log(name + ': ' + m.text()); });
  page.on('request', (r) => requests.push(r.url()));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.hv && (window.hv.loaded || window.hv.errors.some((e) => !/left out\)$/.test(e))),
                             null, { timeout: 120000, polling: 250 });
  const state = await page.evaluate(() => ({ loaded: hv.loaded, errors: hv.errors, services: hv.services || null,
                                             missing: hv.missing, progress: hv.progress,
                                             sources: document.getElementById('sources').textContent }));
  console.log(`${name}: loaded in ${((Date.now() - t0) / 1000).toFixed(1)} s` + (state.errors.length ? ': ' + state.errors.join(' | ') : ''));
  check(state.loaded, `${name}: the page reports loading complete`);
  if (!errorsExpected)
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
  fs.writeFileSync(path.join(outDir, `web-${name}.png`), Buffer.from(shot.png.split(',')[1], 'base64'));
  await page.close();
  return { state, requests, rgba: Buffer.from(shot.rgba, 'base64') };
}
function compare(a, b, what, min = MIN_PSNR) {
  let se = 0, n = 0, differ = 0;
  for (let i = 0; i < a.rgba.length; i += 4) {
    let d2 = 0;
    for (let c = 0; c < 3; ++c) { const d = a.rgba[i + c] - b.rgba[i + c]; d2 += d * d; n++; }
    se += d2;
    if (d2) differ++;
  }
  const psnr = se === 0 ? Infinity : 10 * Math.log10(255 * 255 / (se / n));
  console.log(`${what}: PSNR ${psnr === Infinity ? 'inf (identical)' : psnr.toFixed(2) + ' dB'}, ${differ} of ${a.rgba.length / 4} pixels differ`);
  check(a.rgba.length === b.rgba.length && psnr >= min, `${what}: identical or >= ${min} dB`);
}
// The export's folder is the page's; a request there that is not the page itself is an export file.
function exportFetches(r, pageUrl) {
  const dir = new URL('.', pageUrl).href;
  return r.requests.filter((u) => u.startsWith(dir) && !PAGE_FILES.test(u.slice(dir.length - 1)));
}

try {
  const files = await open(filesUrl, 'files');
  const nofiles = await open(nofilesUrl, 'nofiles');
  const s = nofiles.state.services || {};
  check(s.features === BUILDINGS, `nofiles: ${s.features} footprints from the WFS (${BUILDINGS} expected)`);
  check(s.frame && Array.isArray(s.frame.origin) && Array.isArray(s.frame.terrainExtent),
        `nofiles: origin ${s.frame && s.frame.origin}, terrain rectangle ${s.frame && s.frame.terrainExtent} from the module`);
  const fromExport = exportFetches(nofiles, nofilesUrl);
  check(fromExport.length === 0, 'nofiles: no file of the export fetched' + (fromExport.length ? ': ' + fromExport.join(' ') : ''));
  check(!nofiles.requests.some((u) => /scene_web\.json|terrain\.bin|buildings\.bin|points\.bin/.test(u)),
        'nofiles: no manifest, mesh or points file fetched');
  check(exportFetches(files, filesUrl).some((u) => /terrain\.bin/.test(u)), "files: the export's page fetched its terrain.bin");
  check(nofiles.requests.some((u) => /REQUEST=GetCoverage/.test(u)) && nofiles.requests.some((u) => /REQUEST=GetFeature/.test(u)),
        'nofiles: the page asked the WCS and the WFS itself');
  compare(files, nofiles, 'nofiles vs files (the export also holds points)', MIN_PSNR_NO_POINTS);

  if (pfilesUrl && pnofilesUrl) {
    const pfiles = await open(pfilesUrl, 'services-points');
    const pnofiles = await open(pnofilesUrl, 'nofiles-points');
    const ps = pnofiles.state.services || {};
    const p = ps.points || {};
    check(p.count > 0 && p.failed === 0, `nofiles-points: ${p.count} points from ${p.tilesRead} tiles`);
    check(ps.geocentric && ps.geocentric.maxError < 1e-3,
          `nofiles-points: the EPSG:4978 fit by proj4js, largest residual ${ps.geocentric ? (ps.geocentric.maxError * 1000).toFixed(4) : '?'} mm (< 1 mm)`);
    check(exportFetches(pnofiles, pnofilesUrl).length === 0, 'nofiles-points: no file of the export fetched');
    compare(pfiles, pnofiles, 'nofiles-points vs services-points (the same data)');
  }

  if (missingUrl) {
    const missing = await open(missingUrl, 'missing', true);
    const e = missing.state.errors;
    check(e.some((m) => /services-missing\.json: terrain: http:\/\/[^ ]*\/files\/no-such-wcs\?[^ ]*: HTTP 404[\s\S]*\(terrain left out\)$/.test(m)),
          'missing: the terrain named with the description, the field and the URL');
    check(e.some((m) => /services-missing\.json: cameras: http:\/\/[^ ]*\/files\/no-such-cameras\.json: HTTP 404[\s\S]*\(cameras left out\)$/.test(m)),
          'missing: the cameras named with the description, the field and the URL');
    check((missing.state.services || {}).features === BUILDINGS, 'missing: the buildings still read');
    // hv.missing (web/services_progress.js): each by the description's path, as natively.
    const mm = missing.state.missing;
    console.log('missing: ' + missing.state.sources.replace(/\n/g, ' | '));
    check(mm.length === 2 && mm[0].kind === 'terrain' && /^WCS:http:\/\/[^ ]*\/files\/no-such-wcs\?/.test(mm[0].location) &&
          /HTTP 404/.test(mm[0].reason) && mm[1].kind === 'cameras' && /^http:\/\/[^ ]*\/files\/no-such-cameras\.json$/.test(mm[1].location) &&
          /HTTP 404/.test(mm[1].reason),
          'missing: hv.missing: the terrain and the cameras, each by its URL, and why');
    check(missing.state.sources.includes(`missing: terrain (${mm[0] && mm[0].location}), cameras (${mm[1] && mm[1].location})`) &&
          missing.state.sources.includes('  terrain: ' + (mm[0] && mm[0].location) + ': ') &&
          missing.state.progress.terrain.text === 'left out' && missing.state.progress.buildings.features === BUILDINGS,
          'missing: the panel lists them; hv.progress: the terrain left out, the buildings read');
  }
} catch (e) {
  check(false, 'the test ran: ' + (e && e.stack ? e.stack : e));
} finally {
  await browser.close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
