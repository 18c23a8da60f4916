// Cameras and photographs from services for the page (docs/services.md, "In the browser"):
// - a camera layer, the service description's "cameras": {"path": "WFS:http://…&TYPENAME=ms:cameras"}
//   (or "OAPIF:http://…/collections/cameras"): GeoJSON pages of camera points in the scene's CRS,
//   written into the module's file system beside the manifest, which names them
//   ("cameras": {"geojson": [...], "urls": [...]}, hv/io/web_scene.h); the module reads them with
//   the portable reader (hv/io/geojson_cameras.h), the native reader's per-feature code;
// - the photographs: by path relative to the description (or to the cameras file), by http(s)
//   URL, or from a IIIF image service (a camera whose image is an info.json): the description,
//   then the preview and the image at the camera's size that the module's size rules choose
//   (hv/io/iiif.h, as natively); the photograph joins with its preview (photoArrived), and its
//   full image replaces the preview in place when it arrives (photoFullArrived).
// Loaded before histoview.js, which calls window.hvServiceCameras.
'use strict';

window.hvServiceCameras = (() => {
  const FEATURE_PAGE = 1000, MAX_FEATURE_PAGES = 100;
  const encode = (text) => new TextEncoder().encode(text);
  async function fetchText(url) {
    const r = await fetch(url);
    const text = await r.text();
    if (!r.ok) throw new Error(url + ': HTTP ' + r.status + (text ? ': ' + text.slice(0, 200) : ''));
    return { text, crs: r.headers.get('Content-Crs') };
  }

  // The camera layer named by `path` (WFS: or OAPIF:, relative to descUrl), paged as the
  // buildings are (services.js), in the scene CRS `crs`. Each page is put as it came: a page that
  // is not GeoJSON is named by its URL when the module reads it, and the paging stops there.
  // Returns the manifest's "cameras" entry; counts into info.cameraPages, info.cameraFeatures.
  // P: the page's progress tracker (services_progress.js), when there is one.
  async function loadCameraLayer(path, descUrl, crs, put, info, P) {
    const layer = { geojson: [], urls: [] };
    info.cameraPages = 0;
    info.cameraFeatures = 0;
    const pagePut = (text, url) => {
      const name = `services/cameras-${layer.geojson.length}.json`;
      put(name, encode(text));
      layer.geojson.push(name);
      layer.urls.push(url);
      info.cameraPages++;
      info.requests.push(url);
      let doc = null;
      try { doc = JSON.parse(text); } catch (e) { /* named by the module's reader */ }
      const features = doc && Array.isArray(doc.features) ? doc.features.length : 0;
      info.cameraFeatures += features;
      if (P) P.set('cameras', { service: path.startsWith('WFS:') ? 'WFS' : 'OGC API', pages: info.cameraPages, features: info.cameraFeatures });
      return { doc, features };
    };
    if (path.startsWith('WFS:')) {
      const u = new URL(path.slice(4), descUrl);
      const typeName = u.searchParams.get('TYPENAME') || u.searchParams.get('TYPENAMES');
      if (!typeName) throw new Error(path + ': no TYPENAME (expected the camera layer, e.g. TYPENAME=ms:cameras)');
      for (const k of ['TYPENAME', 'TYPENAMES']) u.searchParams.delete(k);
      for (let start = 0; ; start += FEATURE_PAGE) {
        if (info.cameraPages >= MAX_FEATURE_PAGES) throw new Error(path + ': more than ' + MAX_FEATURE_PAGES * FEATURE_PAGE + ' cameras (not read further)');
        const q = new URL(u);
        for (const [k, v] of Object.entries({ SERVICE: 'WFS', VERSION: '2.0.0', REQUEST: 'GetFeature', TYPENAMES: typeName,
          OUTPUTFORMAT: 'geojson', SRSNAME: crs, COUNT: FEATURE_PAGE, STARTINDEX: start })) q.searchParams.set(k, v);
        const { features } = pagePut((await fetchText(q.href)).text, q.href);
        if (features < FEATURE_PAGE) break;
      }
    } else if (path.startsWith('OAPIF:')) {
      const code = /^EPSG:(\d+)$/.exec(crs || '');
      if (!code) throw new Error(path + ': the scene CRS ' + crs + ' is not EPSG:n (the browser asks the service for it)');
      const crsUri = 'http://www.opengis.net/def/crs/EPSG/0/' + code[1];
      const items = new URL(path.slice(6).replace(/\/?$/, '/items'), descUrl);
      items.searchParams.set('f', 'json');
      items.searchParams.set('limit', FEATURE_PAGE);
      items.searchParams.set('crs', crsUri);
      for (let next = items.href; next;) {
        if (info.cameraPages >= MAX_FEATURE_PAGES) throw new Error(path + ': more than ' + MAX_FEATURE_PAGES + ' pages (not read further)');
        const r = await fetchText(next);
        // As for the buildings: the browser does not reproject, so CRS84 answers are refused.
        if (!r.crs || !r.crs.includes(crsUri))
          throw new Error(next + ': the service did not answer in ' + crs + ' (Content-Crs: ' + (r.crs || 'none, i.e. CRS84') +
                          '); the browser does not reproject: use a WFS (WFS:…) that serves the scene CRS');
        const { doc } = pagePut(r.text, next);
        const link = doc && (doc.links || []).find((l) => l.rel === 'next');
        next = link ? new URL(link.href, next).href : null;
      }
    } else {
      throw new Error(path + ': the browser reads camera layers from WFS: or OAPIF: sources (expected one; or a cameras file by URL)');
    }
    console.log(`histoview: cameras ${path}: ${info.cameraFeatures} features in ${info.cameraPages} pages`);
    return layer;
  }

  // A IIIF image service's description, as hv::isIiifInfoUrl: an http(s) URL whose path, or query
  // (iipsrv's "…?IIIF=/photo.tif/info.json"), ends in /info.json; a fragment is ignored.
  const isIiifInfo = (url) => /^https?:\/\//i.test(url) && /\/info\.json$/i.test(url.replace(/#.*$/, ''));
  const isHttp = (url) => /^https?:\/\//i.test(url);

  // Fetches the photographs in `order`, `o.inFlight` at a time: each joins the renderer's
  // selection (viewer.photoArrived) as soon as its bytes (and its mask's) are in the file system.
  // A IIIF photograph: its description, then its preview (the module's requests, viewer.iiifPlan),
  // with which it joins; its full image is fetched once every preview has been asked for (as the
  // native image loader orders them) and replaces the preview in place (viewer.photoFullArrived,
  // Renderer::replaceImage). A full image that cannot be fetched leaves the preview, named.
  // `o`: {put(rel, bytes), fetchBytes(url), photoBase, rel(fsPath), inFlight, arrived(i, bytes)
  // (its list entry, when it joins), failed(photo, error: a full image's that failed after its
  // preview joined has `url`, the full image's, and `previewShown`), done() (once per photograph, when it
  // is complete or has failed)}; `bytes` counts what came, previews apart:
  // {previews, previewBytes, images, imageBytes}.
  function fetchPhotographs(viewer, photos, order, o, bytes) {
    let next = 0;
    const fulls = [];  // [i, url]: previews that joined, their full images to fetch
    const count = (b, preview) => {
      if (preview) { bytes.previews++; bytes.previewBytes += b.length; } else { bytes.images++; bytes.imageBytes += b.length; }
      return b;
    };
    const putUrl = (url, b) => o.put(viewer.remoteFilePath(url), b);
    async function fileOrUrl(path) {
      if (isHttp(path)) { const b = await o.fetchBytes(path); putUrl(path, b); return b; }
      const b = await o.fetchBytes(new URL(o.rel(path), o.photoBase).href);
      o.put(o.rel(path), b);
      return b;
    }
    // A photograph's first part: it joins (with its preview, or its image). True when complete.
    async function fetchFirst(i, p) {
      let image, full = null;
      if (!isIiifInfo(p.image)) {
        image = count(await fileOrUrl(p.image), false);
      } else {
        const plan = JSON.parse(viewer.iiifPlan(i, (await fetchText(p.image)).text, p.image));
        if (plan.error) throw new Error(plan.error);
        const first = plan.preview || plan.full;
        image = count(await o.fetchBytes(first.url), !!plan.preview);
        putUrl(first.url, image);
        if (plan.preview) full = plan.full.url;
      }
      if (p.mask) await fileOrUrl(p.mask);
      viewer.photoArrived(i);
      o.arrived(i, image);
      if (full) fulls.push([i, full]);
      return !full;
    }
    async function fetchFull(i, url) {
      let b;
      try {
        b = await o.fetchBytes(url);
      } catch (e) {
        const err = new Error(e.message + ' (its preview shown)');
        err.url = url;
        err.previewShown = true;
        throw err;
      }
      putUrl(url, count(b, false));
      viewer.photoFullArrived(i);
    }
    async function worker() {
      while (next < order.length || fulls.length) {
        const [i, full] = next < order.length ? [order[next++], null] : fulls.shift();
        try {
          if (full ? (await fetchFull(i, full), true) : await fetchFirst(i, photos[i])) o.done();
        } catch (e) {
          o.failed(photos[i], e);
          o.done();
        }
      }
    }
    return Promise.all(Array.from({ length: o.inFlight }, worker));
  }

  return { loadCameraLayer, fetchPhotographs, isIiifInfo };
})();
