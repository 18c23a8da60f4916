// Service layers of the page's service scene (docs/services.md, "In the browser"; loaded before
// services.js, which calls window.hvServiceLayers.apply before it writes the manifest):
//   points      {"path": "http://…/tileset.json"} (or "tileset": …; "crs", "tolerance", "budget" as
//               in scene.json): a 3D Tiles 1.0 point tileset. The WebAssembly module chooses the
//               tiles by screen-space error from the photographs' cameras (WebPointTiles,
//               apps/web/hv_web_tiles.cpp, the native reader's rule), the page fetches each batch's
//               pnts contents TILE_FETCHES at a time, the module parses them and writes the points
//               as the web scene's points.bin; the export's points.bin is then not fetched.
//   orthophoto  {"path": "WMTS:http://…"}: below.
// A tile that cannot be fetched or read is named (its URL, what was expected) and left out; a
// tileset that cannot be read leaves the points out, named; the rest of the scene still renders.
'use strict';

window.hvServiceLayers = (() => {
  const TILE_FETCHES = 4;
  const DEFAULT_TOLERANCE = 2, DEFAULT_BUDGET = 20e6;  // pixels, points (scene.json's defaults)

  // Runs `work` over `items`, at most `n` at once.
  async function pool(items, n, work) {
    let next = 0;
    await Promise.all(Array.from({ length: Math.min(n, items.length) }, async () => {
      while (next < items.length) await work(items[next++]);
    }));
  }
  async function fetchOk(url, what) {
    let r;
    try { r = await fetch(url); } catch (e) { throw new Error(url + ': ' + what + ': ' + e.message); }
    if (!r.ok) throw new Error(url + ': ' + what + ': HTTP ' + r.status);
    return r;
  }

  async function points(desc, descUrl, manifest, ctx, info) {
    const src = desc.points;
    const path = src && (typeof src.tileset === 'string' ? src.tileset : src.path);
    if (typeof path !== 'string' || !/tileset\.json([?#]|$)/i.test(path))
      throw new Error(descUrl + ': points: expected {"path": "http://…/tileset.json"} (the browser reads points from 3D Tiles)');
    const url = new URL(path, descUrl).href;
    // Whatever happens below, the export's points are not the ones asked for.
    delete manifest.points;
    const p = info.points = { tileset: url, requests: [], count: 0, tilesRead: 0, tilesKept: 0, failed: 0 };
    // The page's progress (services_progress.js): tiles fetched of those asked so far.
    const P = ctx.progress, tilesAsked = { tiles: 0, of: 0, failed: 0 };
    const tell = (more) => P && P.set('points', Object.assign(tilesAsked, more));
    tell({});
    const text = await (await fetchOk(url, '3D Tiles tileset')).text();
    p.requests.push(url);
    const tiles = new ctx.Module.WebPointTiles();
    try {
      const num = (v, d) => (typeof v === 'number' && Number.isFinite(v) ? v : d);
      const err = tiles.begin(text, url, JSON.stringify(manifest), ctx.root + 'cameras.json', src.crs || '',
                              num(src.tolerance, DEFAULT_TOLERANCE), num(src.budget, DEFAULT_BUDGET));
      if (err) throw new Error(err);
      for (let batch = JSON.parse(tiles.next()); batch.length; batch = JSON.parse(tiles.next())) {
        tell({ of: tilesAsked.of + batch.length });
        await pool(batch, TILE_FETCHES, async ({ tile, url: tileUrl }) => {
          p.requests.push(tileUrl);
          try {
            const bytes = new Uint8Array(await (await fetchOk(tileUrl, 'points tile')).arrayBuffer());
            tiles.arrived(tile, bytes);
            tell({ tiles: tilesAsked.tiles + 1 });
          } catch (e) {
            tiles.failed(tile, e.message);
            tell({ failed: tilesAsked.failed + 1 });
            if (P) P.add('point tile', tileUrl, e.message);
          }
        });
      }
      ctx.put('services/points.bin', new Uint8Array(0));  // its folder
      const r = JSON.parse(tiles.finish(ctx.root + 'services/points.bin'));
      Object.assign(p, { count: r.count, tilesRead: r.tilesRead, tilesKept: r.tilesKept, tilesInTileset: r.tilesInTileset,
                         bytes: r.pntsBytes, failed: r.errors.length, maxFitError: r.maxFitError });
      info.errors.push(...r.errors);
      // A tile fetched but not read (the module names it by its URL) is missing too.
      if (P) for (const e of r.errors) {
        const at = /^(https?:\/\/\S+?): /.exec(e);
        if (at && !P.missing.some((m) => m.location === at[1])) P.add('point tile', at[1], e);
      }
      tell({ count: r.count, done: true });
      for (const n of r.notes) console.warn('histoview: ' + url + ': ' + n);
      if (r.budgetLimited) console.warn(`histoview: ${url}: the point budget stopped the refinement`);
      if (r.count > 0) {
        manifest.points = { path: 'services/points.bin', count: r.count, bytes: r.bytes };
        info.local.push('services/points.bin');
      }
      console.log(`histoview: ${url}: ${r.tilesRead} tiles read of ${r.tilesInTileset}, ${r.tilesKept} kept, ` +
                  `${r.count} points, ${r.pntsBytes} bytes`);
    } finally {
      tiles.delete();
    }
  }

  // orthophoto  {"path": "WMTS:http://…?SERVICE=WMTS&REQUEST=GetCapabilities"} (optional "layer",
  //             "tileMatrixSet", "resolution" in metres per pixel): the capabilities read
  //             (DOMParser), the tile matrix set in the scene CRS (the browser does not reproject),
  //             then as the native reader (docs/services.md, "An orthophoto by WMTS"): the terrain's
  //             rectangle (the export's terrainExtent) at the finest resolution (or "resolution"), at
  //             most MAX_ORTHO_SIDE pixels a side, the tile matrix that resolution needs, its tiles
  //             over the rectangle fetched TILE_FETCHES at a time (the REST template of the layer's
  //             ResourceURL, else KVP GetTile), decoded by the browser (createImageBitmap), mosaicked
  //             and resampled bilinearly onto the rectangle's pixels; the WebAssembly module drapes it
  //             (hv/io/web_orthophoto.h).
  const MAX_ORTHO_SIDE = 4096;
  const kids = (el, name) => (el ? Array.from(el.children).filter((c) => c.localName === name) : []);
  const kid = (el, name) => kids(el, name)[0];
  const textOf = (el, name) => { const k = kid(el, name); return k ? k.textContent.trim() : ''; };
  async function orthophoto(desc, descUrl, manifest, ctx, info) {
    const src = desc.orthophoto;
    const path = src && src.path;
    if (typeof path !== 'string' || !/^WMTS:/i.test(path))
      throw new Error(descUrl + ': orthophoto: expected {"path": "WMTS:http://…"} (the browser reads the orthophoto from a WMTS)');
    delete manifest.orthophoto;
    const rect = manifest.terrainExtent;
    if (!Array.isArray(rect) || rect.length !== 4 || !(rect[2] > rect[0]) || !(rect[3] > rect[1]))
      throw new Error(descUrl + ': orthophoto: the export has no terrainExtent (expected the terrain rectangle web-export writes; export again)');
    const caps = new URL(path.slice(5), descUrl);
    if (![...caps.searchParams.keys()].some((k) => /^request$/i.test(k))) {
      caps.searchParams.set('SERVICE', 'WMTS');
      caps.searchParams.set('REQUEST', 'GetCapabilities');
    }
    const o = info.orthophoto = { capabilities: caps.href, requests: [caps.href], tiles: 0, failed: 0 };
    const P = ctx.progress, tell = (more) => P && P.set('orthophoto', Object.assign({ tiles: o.tiles, failed: o.failed }, more));
    const xml = await (await fetchOk(caps.href, 'WMTS capabilities')).text();
    const doc = new DOMParser().parseFromString(xml, 'application/xml');
    const contents = doc.getElementsByTagNameNS('*', 'Contents')[0];
    if (doc.getElementsByTagName('parsererror').length || !contents)
      throw new Error(caps.href + ': WMTS capabilities: expected XML with a Contents element');
    const layers = kids(contents, 'Layer');
    const layerName = src.layer || '';
    const layer = layerName ? layers.find((l) => textOf(l, 'Identifier') === layerName) : layers[0];
    if (!layer) throw new Error(caps.href + ': WMTS capabilities: no layer' + (layerName ? ' ' + layerName : ''));
    const tmsName = src.tileMatrixSet || textOf(kid(layer, 'TileMatrixSetLink'), 'TileMatrixSet');
    const tms = kids(contents, 'TileMatrixSet').find((t) => textOf(t, 'Identifier') === tmsName);
    if (!tms) throw new Error(caps.href + ': WMTS capabilities: no TileMatrixSet ' + tmsName);
    const crs = textOf(tms, 'SupportedCRS');
    const code = /EPSG[:/]+(?:[\d.]*[:/]+)?(\d+)$/i.exec(crs), sceneCode = /^EPSG:(\d+)$/.exec(desc.crs || manifest.crs || '');
    if (!code || !sceneCode || code[1] !== sceneCode[1])
      throw new Error(`${caps.href}: tile matrix set ${tmsName}: ${crs}, expected the scene CRS ${desc.crs || manifest.crs} ` +
                      '(the browser does not reproject)');
    const matrices = kids(tms, 'TileMatrix').map((m) => {
      const [x, y] = textOf(m, 'TopLeftCorner').split(/\s+/).map(Number);
      return { id: textOf(m, 'Identifier'), res: Number(textOf(m, 'ScaleDenominator')) * 0.28e-3, x, y,
               tw: +textOf(m, 'TileWidth'), th: +textOf(m, 'TileHeight'), mw: +textOf(m, 'MatrixWidth'), mh: +textOf(m, 'MatrixHeight') };
    }).filter((m) => m.res > 0 && Number.isFinite(m.x) && Number.isFinite(m.y) && m.tw > 0 && m.th > 0);
    if (!matrices.length) throw new Error(`${caps.href}: tile matrix set ${tmsName}: no usable TileMatrix (expected ScaleDenominator, TopLeftCorner, TileWidth, TileHeight)`);
    matrices.sort((a, b) => a.res - b.res);
    // The size: the rectangle at the resolution asked, else the finest, within the cap.
    const [minX, minY, maxX, maxY] = rect, w = maxX - minX, h = maxY - minY;
    let pixel = typeof src.resolution === 'number' && src.resolution > 0 ? src.resolution : matrices[0].res;
    pixel = Math.max(pixel, Math.max(w, h) / MAX_ORTHO_SIDE);
    const cols = Math.min(MAX_ORTHO_SIDE, Math.max(1, Math.ceil(w / pixel - 1e-6)));
    const rows = Math.min(MAX_ORTHO_SIDE, Math.max(1, Math.ceil(h / pixel - 1e-6)));
    const pw = w / cols, ph = h / rows;
    // The coarsest matrix at least as fine as the pixels asked.
    const m = matrices.filter((t) => t.res <= Math.min(pw, ph) * (1 + 1e-9)).pop() || matrices[0];
    const spanX = m.res * m.tw, spanY = m.res * m.th;
    const clampInt = (v, hi) => Math.max(0, Math.min(hi, v));
    const c0 = clampInt(Math.floor((minX - m.x) / spanX), m.mw - 1), c1 = clampInt(Math.floor((maxX - m.x) / spanX - 1e-9), m.mw - 1);
    const r0 = clampInt(Math.floor((m.y - maxY) / spanY), m.mh - 1), r1 = clampInt(Math.floor((m.y - minY) / spanY - 1e-9), m.mh - 1);
    // The tile URL: the layer's REST template, else KVP GetTile at the operation's address.
    const style = (kids(layer, 'Style').find((st) => st.getAttribute('isDefault') === 'true') || kid(layer, 'Style'));
    const styleId = style ? textOf(style, 'Identifier') : 'default';
    const resource = kids(layer, 'ResourceURL').find((r) => r.getAttribute('resourceType') === 'tile');
    const format = resource ? resource.getAttribute('format') : textOf(layer, 'Format') || 'image/png';
    let getTile = caps.href.split('?')[0];
    for (const op of doc.getElementsByTagNameNS('*', 'Operation'))
      if (op.getAttribute('name') === 'GetTile') {
        const get = op.getElementsByTagNameNS('*', 'Get')[0];
        const href = get && (get.getAttribute('xlink:href') || get.getAttributeNS('http://www.w3.org/1999/xlink', 'href'));
        if (href) getTile = href;
      }
    const tileUrl = (row, col) => {
      if (resource) {
        return new URL(resource.getAttribute('template').replace(/\{(\w+)\}/g, (all, k) => ({ TileMatrixSet: tmsName, TileMatrix: m.id,
          TileRow: row, TileCol: col, Style: styleId }[k] ?? all)), caps.href).href;
      }
      const u = new URL(getTile, caps.href);
      for (const [k, v] of Object.entries({ SERVICE: 'WMTS', REQUEST: 'GetTile', VERSION: '1.0.0', LAYER: textOf(layer, 'Identifier'),
        STYLE: styleId, FORMAT: format, TILEMATRIXSET: tmsName, TILEMATRIX: m.id, TILEROW: row, TILECOL: col })) u.searchParams.set(k, v);
      return u.href;
    };
    // The mosaic of the tiles over the rectangle; a tile that fails stays transparent, named.
    const mosaic = document.createElement('canvas');
    mosaic.width = (c1 - c0 + 1) * m.tw;
    mosaic.height = (r1 - r0 + 1) * m.th;
    const g = mosaic.getContext('2d', { willReadFrequently: true });
    const tiles = [];
    for (let r = r0; r <= r1; ++r) for (let c = c0; c <= c1; ++c) tiles.push([r, c]);
    tell({ of: tiles.length });
    await pool(tiles, TILE_FETCHES, async ([r, c]) => {
      const url = tileUrl(r, c);
      o.requests.push(url);
      try {
        const blob = await (await fetchOk(url, 'orthophoto tile')).blob();
        let bitmap;
        try {
          bitmap = await createImageBitmap(blob, { premultiplyAlpha: 'none', colorSpaceConversion: 'none' });
        } catch (e) {
          throw new Error(url + ': orthophoto tile: not an image the browser decodes (expected ' + format + ')');
        }
        g.drawImage(bitmap, (c - c0) * m.tw, (r - r0) * m.th);
        bitmap.close();
        o.tiles++;
        tell({});
      } catch (e) {
        o.failed++;
        info.errors.push(e.message + ' (left transparent: untextured terrain shaded there)');
        tell({});
        if (P) P.add('orthophoto tile', url, e.message);
      }
    });
    // Bilinear onto the rectangle's pixels (pixel centres; clamped to the mosaic's edges).
    const src8 = g.getImageData(0, 0, mosaic.width, mosaic.height).data;
    const out = new Uint8Array(cols * rows * 4);
    const ox = m.x + c0 * spanX, oy = m.y - r0 * spanY, W = mosaic.width, H = mosaic.height;
    for (let j = 0; j < rows; ++j) {
      const sy = Math.min(H - 1, Math.max(0, (oy - (maxY - (j + 0.5) * ph)) / m.res - 0.5));
      const y0 = Math.min(H - 2, Math.floor(sy)), fy = sy - Math.max(0, y0), ya = Math.max(0, y0), yb = Math.min(H - 1, ya + 1);
      for (let i = 0; i < cols; ++i) {
        const sx = Math.min(W - 1, Math.max(0, (minX + (i + 0.5) * pw - ox) / m.res - 0.5));
        const x0 = Math.min(W - 2, Math.floor(sx)), fx = sx - Math.max(0, x0), xa = Math.max(0, x0), xb = Math.min(W - 1, xa + 1);
        const a = (ya * W + xa) * 4, b = (ya * W + xb) * 4, c = (yb * W + xa) * 4, d = (yb * W + xb) * 4, at = (j * cols + i) * 4;
        for (let k = 0; k < 4; ++k)
          out[at + k] = Math.round((src8[a + k] * (1 - fx) + src8[b + k] * fx) * (1 - fy) + (src8[c + k] * (1 - fx) + src8[d + k] * fx) * fy);
      }
    }
    ctx.put('services/orthophoto.rgba', out);
    info.local.push('services/orthophoto.rgba');
    manifest.orthophoto = { path: 'services/orthophoto.rgba', width: cols, height: rows, rect, source: path };
    Object.assign(o, { width: cols, height: rows, matrix: m.id, metresPerPixel: pw });
    tell({ width: cols, height: rows, done: true });
    console.log(`histoview: ${caps.href}: orthophoto ${cols} x ${rows} px from ${o.tiles} tiles of matrix ${m.id}`);
  }

  // The layers the description names, into `manifest` (and the file system) before it is written.
  // A layer that fails is named in info.errors and left out; the rest of the scene still loads.
  async function apply(desc, descUrl, manifest, ctx, info) {
    info.errors = info.errors || [];
    info.local = info.local || [];
    if (!ctx || !ctx.Module) return;
    const layers = [['points', points], ['orthophoto', orthophoto]];
    for (const [name, load] of layers) {
      if (!desc[name]) continue;
      try {
        await load(desc, descUrl, manifest, ctx, info);
      } catch (e) {
        info.errors.push(e.message + ` (${name} left out)`);
        if (ctx.progress) {
          const src = desc[name], where = src && typeof (src.tileset || src.path) === 'string' ? src.tileset || src.path : descUrl;
          ctx.progress.set(name, { done: true, failed: true });
          ctx.progress.add(name, where, e.message);
        }
      }
    }
  }

  return { apply };
})();
