// Service scenes for the page (docs/services.md, "In the browser"): reads a service description
// (`?scene=URL`), fetches what it names from the services, and writes the answers into the
// WebAssembly module's file system beside a manifest (hv/io/web_scene.h) that the module reads.
// Loaded before histoview.js, which calls window.hvServices.loadServiceScene.
'use strict';

window.hvServices = (() => {
  // A service scene (docs/services.md, "In the browser"). The description, a JSON object:
  //   {"format": "histoview-services", "version": 1, "crs": "EPSG:2154",
  //    "files": "scene_web.json",  (optional: a web export's manifest for origin, terrain, points, traffic;
  //                                 without it the module makes them from the services, services_frame.js)
  //    "views": "views.json",      (optional: held-out views, for ?camera=)
  //    "terrain": {"path": "WCS:http://…/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm"},
  //    "buildings": {"path": "WFS:http://…/mapserv?map=city&TYPENAME=ms:buildings", "height": "height"},
  //    "cameras": {"path": "http://…/cameras.json"}}
  // paths relative to the description's URL. The buildings: WFS 2.0 GetFeature as GeoJSON in the
  // scene's CRS, by pages of FEATURE_PAGE (STARTINDEX), or OGC API – Features `items` in the
  // scene's CRS (`crs`, Part 2) following the `next` links; at most MAX_FEATURE_PAGES pages. The
  // DTM the buildings stand on: WCS GetCoverage as an ESRI ASCII grid (text/plain). Both are
  // written into the file system beside a manifest naming them (hv/io/web_scene.h, "buildings"),
  // which the WebAssembly module reads and extrudes as the native loader does. The export's own
  // buildings mesh is not fetched. The cameras file by URL, the photographs relative to it.
  const FEATURE_PAGE = 1000, MAX_FEATURE_PAGES = 100;
  async function fetchText(url) {
    const r = await fetch(url);
    const text = await r.text();
    if (!r.ok) throw new Error(url + ': HTTP ' + r.status + (text ? ': ' + text.slice(0, 200) : ''));
    return { text, type: r.headers.get('Content-Type') || '', crs: r.headers.get('Content-Crs') };
  }
  // The text/plain part of a WCS 2.0 multipart answer (MapServer sends the coverage as the second
  // part of multipart/related), else the whole body.
  function coveragePart(text, type) {
    const m = /boundary="?([^";]+)"?/.exec(type);
    if (!/multipart/i.test(type) || !m) return text;
    for (const part of text.split('--' + m[1])) {
      const at = part.search(/\r?\n\r?\n/);
      if (at < 0) continue;
      const head = part.slice(0, at);
      if (/Content-Type:\s*text\/plain/i.test(head)) return part.slice(at).replace(/^\s+/, '').replace(/\s+$/, '');
    }
    throw new Error('the WCS answer has no text/plain part (expected the coverage as an ESRI ASCII grid)');
  }
  const servicePath = (source, what, prefix) => {
    if (!source || typeof source.path !== 'string') throw new Error(what + ' {"path": "' + prefix + 'http://…"}');
    return source.path;
  };
  async function loadServiceScene(descUrl, put, ctx) {
    const desc = JSON.parse((await fetchText(descUrl)).text);
    if (desc.format !== 'histoview-services') throw new Error(descUrl + ': not a service scene ("format": "histoview-services" expected)');
    const info = { description: descUrl, featurePages: 0, features: 0, requests: [], errors: [], local: [] };
    // Each source's counts as its answers arrive, and what is left out (services_progress.js).
    const P = (ctx && ctx.progress) || window.hvServiceProgress.create(null);
    // With "files", the web export's manifest (origin, up, terrain mesh, points, traffic, the
    // EPSG:4978 fit); without, a manifest made here (services_frame.js): the module meshes the
    // WCS grid and places the origin by the native loader's rules.
    let sceneBase, manifest;
    if (desc.files) {
      sceneBase = new URL(desc.files, descUrl).href;
      manifest = JSON.parse((await fetchText(sceneBase)).text);
      manifest.meshes = manifest.meshes.filter((m) => m.name !== 'buildings');
    } else {
      sceneBase = descUrl;
      manifest = window.hvServiceFrame.emptyManifest(desc);
    }
    const crs = desc.crs || manifest.crs;
    // A source that cannot be read is named (the description, the field, the URL) and left out;
    // the rest of the scene still loads.
    const source = async (field, load) => {
      if (!desc[field]) return;
      try {
        await load();
        if (P.progress[field]) P.set(field, { done: true });
      } catch (e) {
        info.errors.push(descUrl + ': ' + field + ': ' + e.message + ' (' + field + ' left out)');
        const where = desc[field] && typeof desc[field].path === 'string' ? desc[field].path : descUrl;
        P.set(field, { done: true, failed: true });
        P.add(field, where, e.message);
      }
    };
    const b = { geojson: [] };
    // The buildings.
    await source('buildings', async () => {
      const bpath = servicePath(desc.buildings, 'expected a WFS or OGC API source', 'WFS:');
      for (const k of ['height', 'base', 'top', 'validFrom', 'validTo']) if (desc.buildings[k]) b[k] = desc.buildings[k];
      const pagePut = (text) => {
        const name = `services/buildings-${b.geojson.length}.json`;
        put(name, new TextEncoder().encode(text));
        b.geojson.push(name);
        const doc = JSON.parse(text);
        info.featurePages++;
        info.features += (doc.features || []).length;
        P.set('buildings', { service: bpath.startsWith('WFS:') ? 'WFS' : 'OGC API', pages: info.featurePages, features: info.features });
        return doc;
      };
      if (bpath.startsWith('WFS:')) {
        const u = new URL(bpath.slice(4), descUrl);
        const typeName = u.searchParams.get('TYPENAME') || u.searchParams.get('TYPENAMES');
        if (!typeName) throw new Error(bpath + ': no TYPENAME (expected the feature type, e.g. TYPENAME=ms:buildings)');
        for (const k of ['TYPENAME', 'TYPENAMES']) u.searchParams.delete(k);
        for (let start = 0; ; start += FEATURE_PAGE) {
          if (info.featurePages >= MAX_FEATURE_PAGES) throw new Error(bpath + ': more than ' + MAX_FEATURE_PAGES * FEATURE_PAGE + ' features (not read further)');
          const q = new URL(u);
          for (const [k, v] of Object.entries({ SERVICE: 'WFS', VERSION: '2.0.0', REQUEST: 'GetFeature', TYPENAMES: typeName,
            OUTPUTFORMAT: 'geojson', SRSNAME: crs, COUNT: FEATURE_PAGE, STARTINDEX: start })) q.searchParams.set(k, v);
          info.requests.push(q.href);
          const doc = pagePut((await fetchText(q.href)).text);
          if (!Array.isArray(doc.features) || doc.features.length < FEATURE_PAGE) break;
        }
      } else if (bpath.startsWith('OAPIF:')) {
        const code = /^EPSG:(\d+)$/.exec(crs || '');
        if (!code) throw new Error(bpath + ': the scene CRS ' + crs + ' is not EPSG:n (the browser asks the service for it)');
        const crsUri = 'http://www.opengis.net/def/crs/EPSG/0/' + code[1];
        const items = new URL(bpath.slice(6).replace(/\/?$/, '/items'), descUrl);
        items.searchParams.set('f', 'json');
        items.searchParams.set('limit', FEATURE_PAGE);
        items.searchParams.set('crs', crsUri);
        for (let next = items.href; next;) {
          if (info.featurePages >= MAX_FEATURE_PAGES) throw new Error(bpath + ': more than ' + MAX_FEATURE_PAGES + ' pages (not read further)');
          info.requests.push(next);
          const r = await fetchText(next);
          // Without the CRS asked for, the features are longitude, latitude (CRS84): the browser
          // does not reproject, so they are refused rather than placed wrong.
          if (!r.crs || !r.crs.includes(crsUri))
            throw new Error(next + ': the service did not answer in ' + crs + ' (Content-Crs: ' + (r.crs || 'none, i.e. CRS84') +
                            '); the browser does not reproject: use a WFS (WFS:…) that serves the scene CRS');
          const doc = pagePut(r.text);
          const link = (doc.links || []).find((l) => l.rel === 'next');
          next = link ? new URL(link.href, next).href : null;
        }
      } else {
        throw new Error(bpath + ': the browser reads buildings from WFS: or OAPIF: sources (expected one)');
      }
    });
    // The DTM under the buildings and, without an export, the terrain itself.
    await source('terrain', async () => {
      const tpath = servicePath(desc.terrain, 'expected a WCS source', 'WCS:');
      if (!tpath.startsWith('WCS:')) throw new Error(tpath + ': the browser reads the terrain from a WCS: source');
      const q = new URL(tpath.slice(4), descUrl);
      q.searchParams.set('REQUEST', 'GetCoverage');
      q.searchParams.set('FORMAT', 'text/plain');
      info.requests.push(q.href);
      P.set('terrain', {});
      const r = await fetchText(q.href);
      const grid = coveragePart(r.text, r.type);
      P.set('terrain', window.hvServiceProgress.gridSize(grid) || {});
      put('services/dtm.asc', new TextEncoder().encode(grid));
      b.dtm = 'services/dtm.asc';
      if (!desc.files) manifest.terrain = { grid: 'services/dtm.asc' };
    });
    if (b.geojson.length) manifest.buildings = b;
    // The cameras: a WFS / OGC API layer of camera points (services_cameras.js; the photographs'
    // paths relative to the description), or a cameras file by URL (the paths relative to it).
    let photoBase = descUrl;
    manifest.cameras = 'cameras.json';
    put('cameras.json', new TextEncoder().encode('{"cameras": []}'));  // until they are read
    await source('cameras', async () => {
      const cpath = servicePath(desc.cameras, 'expected a WFS, OGC API or cameras file source', '');
      if (/^(WFS|OAPIF):/.test(cpath)) {
        manifest.cameras = await window.hvServiceCameras.loadCameraLayer(cpath, descUrl, crs, put, info, P);
      } else {
        const url = new URL(cpath, descUrl).href;
        info.requests.push(url);
        const text = (await fetchText(url)).text;
        put('cameras.json', new TextEncoder().encode(text));
        let count = 0;
        try { count = (JSON.parse(text).cameras || []).length; } catch (e) { /* named by the module's reader */ }
        P.set('cameras', { features: count });
        photoBase = url;
      }
    });
    if (!desc.cameras) info.errors.push(descUrl + ': cameras: missing (expected {"path": "WFS:http://…"} or a cameras file; no photographs)');
    if (!desc.files) await window.hvServiceFrame.settle(desc, descUrl, manifest, { ...ctx, put }, info);
    if (window.hvServiceLayers) await window.hvServiceLayers.apply(desc, descUrl, manifest, { ...ctx, put }, info);
    put('scene_web.json', new TextEncoder().encode(JSON.stringify(manifest)));
    console.log(`histoview: service scene ${descUrl}: ${info.features} features in ${info.featurePages} pages`);
    const viewsUrl = desc.views ? new URL(desc.views, descUrl).href : null;
    return { manifest, sceneBase, photoBase, viewsUrl, info };
  }

  return { loadServiceScene };
})();
