// Headless Chromium: the page reads a service scene's layers itself (run by tests/web_services_test.sh;
// docs/services.md, "In the browser"): points from a 3D Tiles tileset, the orthophoto from a WMTS.
//   node tests/web/web_services_layers_test.mjs OUTDIR FILES_URL POINTS_URL POINTS404_URL POINTSBAD_URL
//        [ORTHO_FILES_URL ORTHO_URL ORTHO_OFF_URL]
// FILES_URL: the export's files with the point pass on; POINTS_URL: the same view with ?scene= a
// description whose points come from the tileset (every tile: tolerance 0). The two canvases must
// be identical or within MIN_PSNR over RGB; the service page must have fetched tileset.json and
// pnts tiles and no points.bin. POINTS404_URL: one tile answered 404; POINTSBAD_URL: a malformed
// tileset.json: each names the URL and what was expected, and the rest of the scene still renders.
// ORTHO_FILES_URL: an export whose orthophoto was read natively from the WMTS; ORTHO_URL: the same
// view with the page reading the WMTS itself (capabilities, GetTile, its own mosaic): identical or
// within MIN_PSNR; ORTHO_OFF_URL: the latter with the orthophoto off, which must differ.
import { checker, launchBrowser, openPage, psnr, shownPsnr as shown } from './services_page.mjs';

const [outDir, filesUrl, pointsUrl, points404Url, pointsBadUrl, orthoFilesUrl, orthoUrl, orthoOffUrl] = process.argv.slice(2);
// The points went through EPSG:4978, 16-bit quantization per tile and the export's fit back
// (hv/scene/geocentric_fit.h), and 8-bit colour: a bound, not equality.
const MIN_PSNR = 45.0;

const tally = checker(), check = tally.check;
const browser = await launchBrowser();
// Loaded, or an error other than a layer left out (those leave the rest loading).
const open = (url, name, errorsExpected) => openPage(browser, tally, url, name, { outDir, until: 'fatal-error', errorsExpected });

try {
  const files = await open(filesUrl, 'files-points', false);
  const points = await open(pointsUrl, 'services-points', false);
  const fp = files.state.status ? files.state.status.points : 0;
  const p = points.state.services && points.state.services.points;
  console.log('services-points: ' + JSON.stringify(p));
  check(p && p.count === fp && p.count > 0 && p.tilesKept === p.tilesInTileset,
        `services-points: every tile read, ${p ? p.count : 0} points (the export has ${fp})`);
  check(points.state.status && points.state.status.pointsDrawn > 0, 'services-points: the point pass drew the points');
  // The progress per source (web/services_progress.js): the tiles fetched are the tiles read.
  const pp = points.state.progress.points;
  const pnts = points.requests.filter((u) => /\.pnts$/.test(u)).length;
  console.log('services-points: ' + points.state.sources);
  check(pp && pp.done && pp.tiles === p.tilesRead && pp.of === p.tilesRead && pp.tiles === pnts && pp.count === p.count &&
        points.state.sources.includes(`points ${pnts} of ${pnts} tiles, ${p.count.toLocaleString('en')} points`) &&
        points.state.missing.length === 0,
        `services-points: hv.progress.points and the panel: ${pp ? pp.tiles : 0} of ${pp ? pp.of : 0} tiles (${pnts} pnts fetched); nothing missing`);
  check(points.requests.some((u) => /\/tileset\.json$/.test(u)) && points.requests.some((u) => /\.pnts$/.test(u)),
        'services-points: the page fetched tileset.json and pnts tiles');
  check(!points.requests.some((u) => /points\.bin/.test(u)) && files.requests.some((u) => /points\.bin/.test(u)),
        "services-points: the export's points.bin was not fetched (the files page fetched it)");
  const q = psnr(files.rgba, points.rgba);
  console.log('services-points vs files: PSNR ' + shown(q));
  // The export's picture: the tiles carry the points' ASPRS classes (the batch table's
  // Classification), so the point pass leaves out the same transient points (docs/services.md,
  // "3D Tiles in the page"; 45.5 dB measured, 22.2 dB before the classes were written).
  check(files.rgba.length === points.rgba.length && q.db >= MIN_PSNR,
        `services-points: the files page's picture (identical or >= ${MIN_PSNR} dB: ${shown(q)})`);

  const f404 = await open(points404Url, 'points-404', true);
  const e404 = f404.state.errors;
  const p404 = f404.state.services && f404.state.services.points;
  check(e404.some((e) => /\/tiles-404\/[^ ]+\.pnts: points tile: HTTP 404 \(tile root[^ ]* left out\)/.test(e)),
        'points-404: the missing tile named with its URL and status');
  const m404 = f404.state.missing;
  console.log('points-404: missing: ' + JSON.stringify(m404));
  check(m404.length === 1 && m404[0].kind === 'point tile' && /\/tiles-404\/[^ ]+\.pnts$/.test(m404[0].location) &&
        /HTTP 404/.test(m404[0].reason) && f404.state.sources.includes('missing: point tile (' + m404[0].location + ')'),
        'points-404: hv.missing and the panel: the point tile, by its URL, and why');
  const pp404 = f404.state.progress.points;
  check(pp404 && pp404.failed === 1 && pp404.tiles === pp404.of - 1 && f404.state.sources.includes(`points ${pp404.tiles} of ${pp404.of} tiles, 1 failed`),
        `points-404: hv.progress.points: ${pp404 ? pp404.tiles : 0} of ${pp404 ? pp404.of : 0} tiles, 1 failed`);
  check(p404 && p404.failed === 1 && p404.count > 0 && p404.count < p.count,
        `points-404: the other tiles' points render (${p404 ? p404.count : 0} of ${p.count})`);
  const fbad = await open(pointsBadUrl, 'points-bad', true);
  const ebad = fbad.state.errors;
  check(ebad.some((e) => /\/tiles-bad\/tileset\.json: .*expected .* \(points left out\)/.test(e)),
        'points-bad: the malformed tileset.json named with what was expected');
  const mbad = fbad.state.missing;
  check(mbad.length === 1 && mbad[0].kind === 'points' && /\/tiles-bad\/tileset\.json$/.test(mbad[0].location) &&
        /expected/.test(mbad[0].reason) && fbad.state.progress.points.text === 'left out' &&
        /^missing: points \(http:[^ ]*\/tiles-bad\/tileset\.json\)$/m.test(fbad.state.sources),
        'points-bad: hv.missing and the panel: the points, by the tileset\'s URL, and why');
  const qbad = psnr(fbad.rgba, points.rgba);
  check(fbad.state.loaded && fbad.state.status && fbad.state.status.pointsDrawn === 0 && fbad.state.status.arrived > 0,
        'points-bad: the rest of the scene renders without points (' + shown(qbad) + ' against the points page)');
  if (orthoFilesUrl) {
    const of = await open(orthoFilesUrl, 'files-orthophoto', false);
    const os = await open(orthoUrl, 'services-orthophoto', false);
    const o = os.state.services && os.state.services.orthophoto;
    console.log('services-orthophoto: ' + JSON.stringify({ ...o, requests: o ? o.requests.length : 0 }));
    const size = (st) => (st.status && st.status.orthophoto ? st.status.orthophoto.join(' x ') : 'none');
    check(o && o.tiles > 0 && o.failed === 0 && size(os.state) === size(of.state) && size(of.state) !== 'none',
          `services-orthophoto: ${o ? o.tiles : 0} tiles mosaicked into ${size(os.state)} px (the export's: ${size(of.state)})`);
    const po = os.state.progress.orthophoto;
    check(po && po.done && po.tiles === o.tiles && po.of === o.tiles && po.failed === 0 &&
          os.state.sources.includes(`orthophoto ${o.tiles} of ${o.tiles} tiles, ${o.width}×${o.height} px`),
          `services-orthophoto: hv.progress.orthophoto and the panel: ${po ? po.tiles : 0} of ${po ? po.of : 0} tiles`);
    check(os.requests.some((u) => /REQUEST=GetCapabilities/.test(u)) && os.requests.some((u) => /\/mapcache\/wmts\/1\.0\.0\/|REQUEST=GetTile/.test(u)),
          'services-orthophoto: the page asked the WMTS for its capabilities and tiles');
    check(!os.requests.some((u) => /orthophoto\.rgba/.test(u)) && of.requests.some((u) => /orthophoto\.rgba/.test(u)),
          "services-orthophoto: the export's orthophoto was not fetched (the files page fetched it)");
    const qo = psnr(of.rgba, os.rgba);
    console.log('services-orthophoto vs files: PSNR ' + shown(qo));
    check(of.rgba.length === os.rgba.length && qo.db >= MIN_PSNR,
          `services-orthophoto: the files page's picture (identical or >= ${MIN_PSNR} dB)`);
    const off = await open(orthoOffUrl, 'services-orthophoto-off', false);
    const qoff = psnr(off.rgba, os.rgba);
    console.log('orthophoto off vs on: PSNR ' + shown(qoff));
    check(qoff.db < 40, 'services-orthophoto: the orthophoto shows (off differs from on: < 40 dB)');
  }
} catch (e) {
  check(false, 'the test ran: ' + (e && e.stack ? e.stack : e));
} finally {
  await browser.close();
}
tally.finish();
