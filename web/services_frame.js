// A service scene without a web export (docs/services.md, "In the browser"; loaded before
// services.js): the description has no "files", so the page makes the manifest itself
// (hv/io/web_scene_frame.h): the DTM grid from the WCS as "terrain" (the module meshes it as the
// native loader does), the buildings' GeoJSON pages, the cameras; then it asks the module for the
// origin, up and terrain rectangle the native loader gives the same data (webSceneFrame), before
// the layers that need them are fetched (services_layers.js: 3D Tiles points are stored relative to
// the origin, the orthophoto covers the terrain's rectangle). Nothing of an export is fetched.
'use strict';

window.hvServiceFrame = (() => {
  // The manifest before the services are read (hv/io/web_scene.h): no origin, no meshes.
  function emptyManifest(desc) {
    const m = { format: 'histoview-web', version: 1, crs: desc.crs || '', meshes: [] };
    if (Array.isArray(desc.up)) m.up = desc.up;
    return m;
  }

  // Origin, up and terrain rectangle from the module (the native loader's rules), into `manifest`.
  async function settle(desc, descUrl, manifest, ctx, info) {
    ctx.put('scene_web.json', new TextEncoder().encode(JSON.stringify(manifest)));
    const frame = JSON.parse(ctx.Module.webSceneFrame(ctx.root + 'scene_web.json'));
    if (frame.error) throw new Error(descUrl + ': ' + frame.error);
    manifest.origin = frame.origin;
    manifest.up = frame.up;
    if (frame.terrainExtent) manifest.terrainExtent = frame.terrainExtent;
    info.frame = { origin: frame.origin, up: frame.up, terrainExtent: frame.terrainExtent || null };
    console.log(`histoview: ${descUrl}: no export: origin [${frame.origin}], up [${frame.up}]` +
                (frame.terrainExtent ? `, terrain [${frame.terrainExtent}]` : ', no terrain'));
    const sceneCrsTiles = desc.points && desc.points.crs && desc.points.crs === (desc.crs || manifest.crs);
    if (desc.points && !sceneCrsTiles) {
      try {
        manifest.geocentric = await geocentric(desc, descUrl, frame, ctx, info);
      } catch (e) {
        info.errors.push(e.message + ' (earth-centred 3D Tiles cannot be placed)');
      }
    }
  }

  // The EPSG:4978 fit without PROJ (hv/scene/geocentric_fit.h): the module's samples around the
  // scene mapped from the scene CRS, given in the description as a PROJ string ("projection":
  // `histoview info` prints it), into EPSG:4978 by proj4js (tools/web-build.sh copies it beside
  // the page), then fitted by the module as web-export fits PROJ's.
  const ECEF = '+proj=geocent +datum=WGS84 +units=m +no_defs';
  function loadScript(src) {
    return new Promise((resolve, reject) => {
      const s = document.createElement('script');
      s.src = src;
      s.onload = resolve;
      s.onerror = () => reject(new Error(new URL(src, location.href).href + ': not loaded (build the page with tools/web-build.sh)'));
      document.head.appendChild(s);
    });
  }
  async function geocentric(desc, descUrl, frame, ctx, info) {
    if (typeof desc.projection !== 'string' || !desc.projection)
      throw new Error(descUrl + ': projection: missing (expected the scene CRS ' + (desc.crs || '') +
                      ' as a PROJ string, "+proj=…", which `histoview info scene.json` prints)');
    if (!frame.geocentricSamples) throw new Error(descUrl + ': projection: no scene to sample (no terrain, buildings or cameras read)');
    if (!window.proj4) await loadScript('proj4.js');
    let toEcef;
    try {
      toEcef = window.proj4(desc.projection, ECEF);
    } catch (e) {
      throw new Error(descUrl + ': projection: ' + JSON.stringify(desc.projection) + ': not a CRS proj4js reads (' + e.message + ')');
    }
    const scene = frame.geocentricSamples, ecef = [];
    for (let i = 0; i < scene.length; i += 3) ecef.push(...toEcef.forward([scene[i], scene[i + 1], scene[i + 2]]));
    const fit = JSON.parse(ctx.Module.webGeocentricFit(JSON.stringify({ scene, ecef })));
    if (fit.error) throw new Error(descUrl + ': projection: ' + fit.error);
    info.geocentric = { samples: scene.length / 3, maxError: fit.maxError };
    console.log(`histoview: ${descUrl}: EPSG:4978 fit by proj4js over ${scene.length / 3} samples, ` +
                `largest residual ${(fit.maxError * 1000).toFixed(3)} mm`);
    return fit;
  }

  return { emptyManifest, settle };
})();
