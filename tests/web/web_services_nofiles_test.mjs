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
import { DEMO_BUILDINGS as BUILDINGS, checker, expectSamePicture, launchBrowser, openPage } from './services_page.mjs';

const [outDir, filesUrl, nofilesUrl, pfilesUrl, pnofilesUrl, missingUrl] = process.argv.slice(2);
const MIN_PSNR = 45.0, MIN_PSNR_NO_POINTS = 30.0;
// The page's own files, served from the export's folder like any page; anything else there is the export's.
const PAGE_FILES = /\/(index\.html|[a-z0-9_]+\.js|histoview\.css|histoview_web\.wasm)(\?|$)/;

const tally = checker(), check = tally.check;
const browser = await launchBrowser();
const open = (url, name, errorsExpected) => openPage(browser, tally, url, name, { outDir, until: 'fatal-error', errorsExpected });
const compare = (a, b, what, min = MIN_PSNR) => expectSamePicture(tally, a.rgba, b.rgba, what, min);
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
tally.finish();
