// Headless Chromium: the page reads the photographs' cameras from a WFS layer of camera points and
// the photographs from a IIIF image service itself (run by tests/web_services_test.sh; docs/services.md,
// "In the browser").
//   node tests/web/web_services_cameras_test.mjs --files URL --wfs URL --malformed URL --missing URL
//        --photos N --out DIR [--iiif-file URL --iiif-full-404 URL]
// --files: the export's page; --wfs: the same view with ?scene= a description whose cameras come
// from the WFS layer (ms:cameras; with --iiif-file, its images are IIIF descriptions of iipsrv);
// --iiif-file: the same with the cameras from the export's cameras file by URL, the images from
// iipsrv. Checks: no page errors; every camera read from the WFS; the WFS page renders the picture
// of the cameras-file page (identical or >= 45 dB: the same cameras, whichever reader) and of the
// files (>= 45 dB, or >= 30 dB when the photographs come from iipsrv, which re-encodes them as
// JPEG, the bound of the native test tests/iiif_test.sh); IIIF: a preview and a full image per
// photograph, the bytes reported, previews apart; previews first (openStaged): with the image
// requests held back, the frame has no photograph; with the previews let through and the full
// images held, every photograph joins with its preview and the frame is textured by them; with the
// full images let through, the converged frame is the freely fetching page's. Faults: --malformed, a camera layer that is
// not GeoJSON: an error naming its URL, the buildings still read and the page completes;
// --missing, one photograph answering 404: an error naming its URL, the others arrive;
// --iiif-full-404, --iiif-file with the photographs through the fault proxy, whose previews
// arrive and whose full images answer 404: the previews stay (every photograph joined, the frame
// the staged page's with the previews in), the errors and hv.missing name each full image's URL
// and say the preview is shown.
// Each page's hv.progress (web/services_progress.js) counts what was read (cameras, previews, full
// images), and hv.missing and the status panel name what was not, by kind and URL.
import { DEMO_BUILDINGS as BUILDINGS, canvasRgba, checker, expectSamePicture, launchBrowser, openPage, psnr as psnrOf }
  from './services_page.mjs';

const args = {};
for (let i = 2; i < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const photos = +args.photos;

const tally = checker(), check = tally.check;
const browser = await launchBrowser();
// Loaded, or (with expectErrors) an error that left the page without a viewer.
const open = (url, name, { expectErrors = false } = {}) =>
  openPage(browser, tally, url, name, { outDir: args.out, until: 'load-failed', errorsExpected: expectErrors });
// The canvas's RGBA (and web-NAME.png in --out).
const shoot = async (page, name) => ({ rgba: await canvasRgba(page, args.out, name) });
// The IIIF page with its image requests held back (the services stay real; Playwright only delays
// the page's requests): every image at first (the frame with no photograph), then the previews
// (each photograph's first image request) while the full images stay held (the frame textured by
// the previews), then the full images (the converged frame). Returns the three canvases and the
// page's state at each stage.
async function openStaged(url, name) {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  const seen = new Set(), held = { preview: [], full: [] }, open = { preview: false, full: false };
  let fullAsked = 0;
  await page.route((u) => /IIIF=/.test(u.href) && !/info\.json/.test(u.href), (route) => {
    const id = route.request().url().replace(/\/full\/.*$/, '');
    const kind = seen.has(id) ? 'full' : 'preview';
    seen.add(id);
    if (kind === 'full') fullAsked++;
    if (open[kind]) route.continue(); else held[kind].push(route);
  });
  const state = () => page.evaluate(() => ({ status: hv.status, photoBytes: hv.photoBytes, loaded: hv.loaded, errors: hv.errors,
                                             text: document.getElementById('status').textContent, progress: hv.progress,
                                             missing: hv.missing, sources: document.getElementById('sources').textContent }));
  const until = (fn, arg) => page.waitForFunction(fn, arg, { timeout: 120000, polling: 250 });
  await page.goto(url);
  // Nothing can arrive: the first frames have no photograph.
  await until(() => window.hv && hv.status && hv.status.frames >= 1 && hv.status.converged && hv.status.arrived === 0);
  const none = await shoot(page, name + '-no-photograph');
  open.preview = true;
  for (const r of held.preview.splice(0)) r.continue();
  await until((n) => hv.status && hv.status.arrived === n && hv.photoBytes.previews === n && hv.status.converged, photos);
  const previewState = await state();
  const previews = await shoot(page, name + '-previews');
  const fullsHeld = held.full.length;
  open.full = true;
  for (const r of held.full.splice(0)) r.continue();
  await until(() => hv.loaded || hv.errors.length > 0);
  const converged = await shoot(page, name + '-converged');
  const finalState = await state();
  await page.close();
  return { none, previews, converged, previewState, finalState, fullsHeld, fullAsked, errors: [...finalState.errors, ...errors] };
}
const psnr = (a, b) => psnrOf(a.rgba, b.rgba).db;
const compare = (a, b, what, minDb) => expectSamePicture(tally, a.rgba, b.rgba, what, minDb);

try {
  const files = await open(args.files, 'files');
  const wfs = await open(args.wfs, 'wfs-cameras');
  const s = wfs.state.services;
  check(s && s.cameraFeatures === photos && s.cameraPages >= 1 && wfs.state.status.photos === photos,
        `wfs-cameras: ${s ? s.cameraFeatures : 0} cameras from the WFS in ${s ? s.cameraPages : 0} page(s), ` +
        `${wfs.state.status.photos} photographs (${photos} expected)`);
  const pc = wfs.state.progress.cameras;
  check(pc && pc.done && pc.service === 'WFS' && pc.features === photos && pc.pages === s.cameraPages &&
        wfs.state.sources.includes(`cameras WFS page ${s.cameraPages}, ${photos} cameras`),
        `wfs-cameras: hv.progress.cameras and the panel: ${pc ? pc.features : 0} cameras (${photos} expected)`);
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
      const pp = p.state.progress.photographs;
      check(pp && pp.done && pp.previews === photos && pp.previewsOf === photos && pp.full === photos && pp.of === photos &&
            p.state.sources.includes(`photographs ${photos} of ${photos} previews, ${photos} of ${photos} full`) &&
            p.state.missing.length === 0,
            `${name}: hv.progress.photographs and the panel: ${photos} of ${photos} previews, ${photos} of ${photos} full; nothing missing`);
    }
    compare(wfs, iiif, 'cameras from the WFS vs from the cameras file (photographs from IIIF)', 45);
    // Previews first: the photographs join with their previews while the full images are held.
    const st = await openStaged(args['iiif-file'], 'iiif-staged');
    console.log(`iiif-staged: previews in: ${JSON.stringify(st.previewState.photoBytes)}, ${st.fullsHeld} full requests held; ` +
                `status: ${st.previewState.text.replace(/\n/g, ' | ')}`);
    check(st.errors.length === 0, 'iiif-staged: no page errors' + (st.errors.length ? ': ' + st.errors.join(' | ') : ''));
    check(st.previewState.photoBytes.images === 0 && st.fullsHeld > 0 && !st.previewState.loaded,
          `iiif-staged: every photograph joined with its preview, no full image in (${st.fullsHeld} held)`);
    check(/previews [\d.]+ MB \(\d+\)/.test(st.previewState.text), 'iiif-staged: the status reports the previews\' bytes');
    console.log('iiif-staged: sources while the full images are held: ' + st.previewState.sources.replace(/\n/g, ' | '));
    check(st.previewState.sources.startsWith('sources\n') &&
          st.previewState.sources.split('\n').includes(`photographs: ${photos} of ${photos} previews, 0 of ${photos} full`),
          'iiif-staged: while loading, the panel has a line per source, the photographs\' counting the previews in and no full image');
    const untextured = psnr(st.none, st.converged), byPreviews = psnr(st.previews, st.converged);
    console.log(`iiif-staged: against the converged frame: no photograph ${untextured.toFixed(2)} dB, previews ${byPreviews.toFixed(2)} dB`);
    check(byPreviews >= 20 && byPreviews >= untextured + 6 && byPreviews < 60,
          'iiif-staged: the previews\' frame is textured (>= 20 dB and 6 dB closer to the converged frame than the frame with ' +
          'no photograph) and is not the full images\' (< 60 dB)');
    check(st.finalState.loaded && st.finalState.photoBytes.images === photos && st.fullAsked === photos,
          `iiif-staged: then every full image replaced its preview (${st.finalState.photoBytes.images} of ${photos})`);
    compare({ rgba: st.converged.rgba }, iiif, 'iiif-staged converged vs the page fetching freely', 45);
    compare({ rgba: st.converged.rgba }, files, 'iiif-staged converged vs files (iipsrv re-encodes as JPEG)', 30);
    compare(wfs, files, 'services (WFS cameras, IIIF photographs) vs files (iipsrv re-encodes as JPEG)', 30);
    if (args['iiif-full-404']) {
      const f = await open(args['iiif-full-404'], 'iiif-full-404', { expectErrors: true });
      const fm = f.state.missing, fp = f.state.progress.photographs, fb = f.state.photoBytes;
      console.log('iiif-full-404: ' + f.state.errors[0] + '; sources: ' + f.state.sources.split('\n').slice(0, 3).join(' | '));
      const full404 = /^http:\/\/[^ ]*\/404-wide\/iiif\?IIIF=[^ ]*\/full\/\d+,[^ ]*$/;
      check(f.state.errors.length === photos && f.state.errors.every((e) => /^photograph \S+: (\S+): HTTP 404 \(its preview shown\)$/.test(e) &&
                                                                         full404.test(e.split(' ')[2].replace(/:$/, ''))),
            `iiif-full-404: ${f.state.errors.length} errors (${photos} expected), each naming the full image's URL and that the preview is shown`);
      check(fm.length === photos && fm.every((m) => m.kind === 'photograph' && full404.test(m.location) && m.reason === 'HTTP 404 (its preview shown)') &&
            f.state.sources.includes(`\nmissing: ${photos} photographs\n`) &&
            f.state.sources.includes('  photograph: ' + fm[0].location + ': HTTP 404 (its preview shown)'),
            'iiif-full-404: hv.missing and the panel: each full image by its URL, its preview shown');
      check(f.state.status.arrived === photos && fb.previews === photos && fb.images === 0 &&
            fp.previews === photos && fp.full === 0 && fp.failed === photos &&
            f.state.sources.includes(`photographs ${photos} of ${photos} previews, 0 of ${photos} full, ${photos} failed`),
            `iiif-full-404: every photograph joined by its preview (${f.state.status.arrived} of ${photos}), no full image`);
      compare(f, st.previews, 'iiif-full-404 vs the staged page with the previews in (the previews stay)', 45);
      const q = psnr(f, iiif);
      console.log(`iiif-full-404 vs the full images: ${q.toFixed(2)} dB`);
      check(q < 60, 'iiif-full-404: not the full images\' frame (< 60 dB)');
    }
  } else {
    compare(wfs, files, 'services (WFS cameras) vs files', 45);
  }
  const bad = await open(args.malformed, 'malformed-layer', { expectErrors: true });
  console.log('malformed-layer: ' + bad.errors.join(' | '));
  check(bad.errors.some((e) => /\/files\/malformed-cameras\.json\?[^ ]*REQUEST=GetFeature[^ ]*: not valid JSON/.test(e)),
        'malformed-layer: the error names the layer\'s URL and says it is not valid JSON');
  check(bad.state.services && bad.state.services.features === BUILDINGS, `malformed-layer: the buildings still read (${BUILDINGS})`);
  console.log('malformed-layer: missing: ' + JSON.stringify(bad.state.missing));
  check(bad.state.missing.some((m) => m.kind === 'cameras' && /\/files\/malformed-cameras\.json\?.*REQUEST=GetFeature/.test(m.location) &&
                                      /not valid JSON/.test(m.reason)) &&
        /^missing: cameras \(http:\/\/[^ ]*malformed-cameras\.json/m.test(bad.state.sources),
        'malformed-layer: hv.missing and the panel name the camera layer\'s page by its URL');
  const missing = await open(args.missing, 'missing-photograph', { expectErrors: true });
  console.log('missing-photograph: ' + missing.errors.join(' | '));
  check(missing.state.errors.length === 1 && /^photograph \S+: \S*\/files\/web\/images\/missing\.jpg: HTTP 404/.test(missing.state.errors[0]),
        'missing-photograph: one error, naming the URL and the status');
  const mm = missing.state.missing, mp = missing.state.progress.photographs;
  console.log('missing-photograph: sources: ' + missing.state.sources.replace(/\n/g, ' | '));
  check(mm.length === 1 && mm[0].kind === 'photograph' && /\/files\/web\/images\/missing\.jpg$/.test(mm[0].location) &&
        /HTTP 404/.test(mm[0].reason) && missing.state.sources.includes('missing: photograph (' + mm[0].location + ')') &&
        missing.state.sources.includes('photograph: ' + mm[0].location + ': '),
        'missing-photograph: hv.missing and the panel: the photograph, by its URL, and why');
  check(mp && mp.failed === 1 && mp.full === photos - 1 && mp.of === photos &&
        missing.state.sources.includes(`photographs ${photos - 1} of ${photos}, 1 failed`),
        `missing-photograph: hv.progress.photographs: ${photos - 1} of ${photos}, 1 failed`);
  check(missing.state.status.arrived === photos - 1, `missing-photograph: the others arrived (${missing.state.status.arrived} of ${photos - 1})`);
} catch (e) {
  check(false, 'the test ran: ' + (e && e.stack ? e.stack : e));
} finally {
  await browser.close();
}
tally.finish();
