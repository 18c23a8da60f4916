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
import { DEMO_BUILDINGS as BUILDINGS, checker, expectSamePicture, launchBrowser, openPage } from './services_page.mjs';

const [filesUrl, servicesUrl, outDir, oapifUrl] = process.argv.slice(2);
// The same renderer, cameras, photographs and terrain; the buildings' footprints went through
// MapServer's GeoJSON (coordinates to 1 µm) and their roofs are triangulated by ear clipping rather
// than GEOS: the pictures may differ in the last bits at a few pixels, hence a bound, not equality.
const MIN_PSNR = 45.0;

const tally = checker(), check = tally.check;
const browser = await launchBrowser();
const open = (url, name) => openPage(browser, tally, url, name, { outDir });

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
  expectSamePicture(tally, files.rgba, services.rgba, 'the service scene renders the file scene\'s picture (services vs files)', MIN_PSNR);
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
tally.finish();
