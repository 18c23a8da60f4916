// The page (docs/web.md): fetches the export made by `histoview web-export` over HTTP, writes what
// arrives into the WebAssembly module's in-memory file system, and drives hv::render::Renderer
// (apps/web/hv_web.cpp) from requestAnimationFrame. No framework. URL parameters:
//   camera=ID  start at this view (views.json) or photograph; default: an overview
//   pose=x,y,z,qw,qx,qy,qz,fov  start at this camera pose (the shared link's, hv/viewer/view_state.h)
//   w=, h=     canvas size (default 960x540)
//   NAME=TEXT  any render setting, as on the command line (`histoview settings`), e.g. k=4,
//              depth-size=2048 (depth= too), points=0 (start with the point cloud hidden)
//   log=debug  the renderer's log level in the console (debug, info, warn, error, off)
//   scene=URL  a service scene (docs/services.md, "In the browser"): the buildings from a WFS, the
//              DTM they stand on from a WCS, the cameras and photographs by URL, points from 3D
//              Tiles (web/services_layers.js), the rest (origin, terrain mesh, traffic) from a web
//              export the description names
// The address bar keeps the current view (history.replaceState): the pose and the render settings
// changed from the page's defaults (the time window `from`/`to`, the traffic's `time` among them),
// so a copied link opens the same view.
// For scripts and tests, window.hv exposes the state (loaded, fraction, progress and missing,
// errors) and a few calls.
'use strict';

(() => {
  const params = new URLSearchParams(location.search);
  const intParam = (name, def) => { const v = parseInt(params.get(name), 10); return Number.isFinite(v) && v > 0 ? v : def; };
  const W = intParam('w', 960), H = intParam('h', 540);
  const ROOT = '/scene/';
  const FETCHES_IN_FLIGHT = 4;
  const SCENE_SHARE = 0.1;  // of the progress bar: the scene files; the photographs take the rest

  const $ = (id) => document.getElementById(id);
  const canvas = $('view');
  canvas.width = W;
  canvas.height = H;

  const hv = window.hv = { loaded: false, fraction: 0, errors: [], status: null, viewer: null };
  // Per source what has arrived, and what is missing (services_progress.js; the status panel).
  const sources = window.hvServiceProgress.create($('sources'));
  hv.progress = sources.progress;
  hv.missing = sources.missing;

  function showError(message) {
    const text = String(message);
    hv.errors.push(text);
    const box = $('errors');
    box.hidden = false;
    box.textContent += (box.textContent ? '\n' : '') + text;
    console.error('histoview: ' + text);
  }
  window.addEventListener('error', (e) => showError(e.message || e.error));
  window.addEventListener('unhandledrejection', (e) => showError(e.reason && e.reason.message ? e.reason.message : e.reason));

  function setProgress(value, text) {
    hv.fraction = value;
    $('progress').value = value;
    $('progress-text').textContent = text;
  }

  function mkdirs(FS, path) {
    const parts = path.split('/').slice(1, -1);
    let dir = '';
    for (const p of parts) {
      dir += '/' + p;
      try { FS.mkdir(dir); } catch (e) { /* exists */ }
    }
  }

  // onBytes(n): called as the body arrives, n bytes at a time (for the progress bar).
  async function fetchBytes(url, onBytes) {
    const r = await fetch(url);
    if (!r.ok) throw new Error(url + ': HTTP ' + r.status);
    if (!onBytes || !r.body) {
      const bytes = new Uint8Array(await r.arrayBuffer());
      if (onBytes) onBytes(bytes.length);
      return bytes;
    }
    const reader = r.body.getReader(), parts = [];
    let n = 0;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      parts.push(value);
      n += value.length;
      onBytes(value.length);
    }
    const bytes = new Uint8Array(n);
    let at = 0;
    for (const p of parts) { bytes.set(p, at); at += p.length; }
    return bytes;
  }
  const megabytes = (n) => (n / 1048576).toFixed(1) + ' MB';
  const photoBytesText = (b) => !b || !b.images && !b.previews ? '' : `\nphotographs ${megabytes(b.imageBytes)} (${b.images})` +
    (b.previews ? `, previews ${megabytes(b.previewBytes)} (${b.previews})` : '');

  async function main() {
    if (typeof createHistoview !== 'function')
      throw new Error('histoview_web.js is missing: build it with tools/web-build.sh and export again');
    setProgress(0, 'starting WebAssembly…');
    const Module = await createHistoview({
      print: (t) => console.log(t),
      printErr: (t) => { console.warn(t); if (/^error/i.test(t)) showError(t); },
    });
    const FS = Module.FS;
    if (params.get('log')) Module.setLogLevel(params.get('log'));
    const put = (rel, bytes) => { mkdirs(FS, ROOT + rel); FS.writeFile(ROOT + rel, bytes); };

    // The scene: manifest, meshes, points, cameras (and the optional views). The progress bar's
    // first SCENE_SHARE counts their bytes (the sizes the manifest gives; cameras.json is small).
    setProgress(0, 'loading the scene…');
    // Where the export's files and the photographs come from: beside the page, or for a service
    // scene (?scene=URL) where its description says.
    let sceneBase = location.href, photoBase = location.href, viewsUrl = null, manifest;
    if (params.get('scene')) {
      const s = await window.hvServices.loadServiceScene(new URL(params.get('scene'), location.href).href, put,
                                                         { Module, root: ROOT, progress: sources });
      ({ manifest, sceneBase, photoBase, viewsUrl } = s);
      hv.services = s.info;
      (s.info.errors || []).forEach(showError);
    } else {
      const manifestBytes = await fetchBytes('scene_web.json');
      put('scene_web.json', manifestBytes);
      manifest = JSON.parse(new TextDecoder().decode(manifestBytes));
    }
    const fromScene = (f) => new URL(f, sceneBase).href;
    const sceneFiles = manifest.meshes.map((m) => m.path).concat([manifest.cameras || 'cameras.json']);
    if (manifest.points) sceneFiles.push(manifest.points.path);
    if (manifest.orthophoto) sceneFiles.push(manifest.orthophoto.path);
    if (manifest.traffic) sceneFiles.push(...[manifest.traffic.csv, manifest.traffic.models].filter(Boolean));
    const expected = manifest.meshes.reduce((n, m) => n + 12 * (m.vertices + m.triangles) + (m.tags ? 4 * m.triangles : 0), 0) +
                     (manifest.points ? manifest.points.bytes || 0 : 0);
    let received = 0;
    const sceneProgress = (n) => {
      received += n;
      const f = Math.min(1, received / Math.max(1, expected));
      setProgress(SCENE_SHARE * f, `scene ${megabytes(received)} / ${megabytes(expected)}` +
                  (manifest.points ? `, ${manifest.points.count.toLocaleString('en')} points` : ''));
    };
    await Promise.all(sceneFiles.filter((f) => !hv.services || (f !== manifest.cameras && !(hv.services.local || []).includes(f)))
      .map(async (f) => put(f, await fetchBytes(fromScene(f), sceneProgress))));
    let haveViews = false;
    try { put('views.json', await fetchBytes(viewsUrl || fromScene('views.json'))); haveViews = true; } catch (e) { /* optional */ }

    const viewer = hv.viewer = new Module.WebViewer('#view');
    if (viewer.error()) throw new Error(viewer.error());
    // Render settings named in the URL, before the renderer is made (so those read at its
    // construction apply too).
    for (const [name, value] of params) {
      const setting = name === 'depth' ? 'depth-size' : name;
      if (!['camera', 'pose', 'w', 'h', 'log', 'scene'].includes(name)) {
        const err = viewer.setSetting(setting, value);
        if (err) showError('URL parameter ' + name + '=' + value + ': ' + err);
      }
    }
    const loadErrors = viewer.load(ROOT + 'scene_web.json');
    if (loadErrors) loadErrors.trim().split('\n').forEach(showError);
    sources.cameraLayerErrors(loadErrors, manifest.cameras && manifest.cameras.urls);
    console.log('histoview: ' + viewer.glInfo());
    const st = JSON.parse(viewer.status());
    console.log(`histoview: scene read in ${st.sceneMs.toFixed(0)} ms` +
                (st.points ? ` (${st.points} points in ${st.chunks} chunks)` : ''));

    const camera = params.get('camera'), pose = params.get('pose');
    if (pose) {
      const err = viewer.setPose(pose, W, H);
      if (err) { showError('pose=' + pose + ': ' + err); viewer.overview(W, H); }
    } else if (camera) {
      const err = viewer.setViewFromFile(haveViews ? ROOT + 'views.json' : ROOT + 'cameras.json', camera, W, H);
      if (err) { showError('camera=' + camera + ': ' + err); viewer.overview(W, H); }
    } else {
      viewer.overview(W, H);
    }
    $('speed').value = viewer.speed().toFixed(1);
    buildSettings(viewer, manifest.points ? manifest.points.count : 0);

    const photos = JSON.parse(viewer.photos());
    buildPhotoList(viewer, photos);
    const timelineUi = buildTimeline(viewer);
    const thenNowUi = buildThenNow(viewer, FS);
    const trafficUi = buildTraffic(viewer);
    const mapUi = window.hvBuildMap ? window.hvBuildMap(viewer, () => canvas.focus()) : { update() {}, toggle() {} };

    // Photographs, nearest the start view first, a few requests in flight; each joins the
    // renderer's selection as soon as its bytes (and its mask's) are in the file system.
    const order = JSON.parse(viewer.fetchOrder());
    let done = 0;
    const rel = (p) => p.startsWith(ROOT) ? p.slice(ROOT.length) : p;
    // By path, by URL or from IIIF (services_cameras.js); the bytes fetched, previews apart.
    hv.photoBytes = { previews: 0, previewBytes: 0, images: 0, imageBytes: 0 };
    const iiif = order.filter((i) => window.hvServiceCameras.isIiifInfo(photos[i].image)).length;
    let photosFailed = 0;
    const photoProgress = (more) => sources.set('photographs', Object.assign({
      previews: hv.photoBytes.previews, previewsOf: iiif, full: hv.photoBytes.images, of: order.length, failed: photosFailed }, more));
    photoProgress({});
    window.hvServiceCameras.fetchPhotographs(viewer, photos, order, {
      put, fetchBytes, photoBase, rel, inFlight: FETCHES_IN_FLIGHT,
      arrived: (i, bytes) => {
        const li = document.querySelector('#photos li[data-index="' + i + '"]');
        if (li) { li.classList.remove('pending'); addThumbnail(li, bytes, photos[i].id); }
        photoProgress({});
      },
      failed: (p, e) => {
        showError('photograph ' + p.id + ': ' + e.message);
        photosFailed++;
        sources.add('photograph', e.url || p.image, e.message);
      },
      done: () => { done++; photoProgress({}); },
    }, hv.photoBytes).then(() => { hv.fetched = true; photoProgress({ done: true }); });

    // The frame loop: input, then a progressive frame when something changed.
    // Keys as events: `keys` are down now, `tapped` went down since the last frame, so a tap
    // shorter than a frame (SwiftShader frames are tens of milliseconds) still moves for a frame.
    const keys = new Set(), tapped = new Set();
    let drag = null, look = [0, 0], last = performance.now(), lastErrors = 0;
    canvas.addEventListener('keydown', (e) => {
      keys.add(e.code);
      if (!e.repeat) tapped.add(e.code);
      if (e.code === 'KeyN' || e.code === 'PageDown') viewer.stepPhoto(1);
      if (e.code === 'KeyP' || e.code === 'PageUp') viewer.stepPhoto(-1);
      if (e.code === 'Space' && !e.repeat) timelineUi.toggle();
      if (e.code === 'KeyY' && !e.repeat) trafficUi.toggle();
      if (e.code === 'KeyT' && !e.repeat) thenNowUi.toggle();
      if (e.code === 'KeyM' && !e.repeat) mapUi.toggle();
      if (e.code.startsWith('Arrow') || e.code === 'Space' || e.code.startsWith('Page')) e.preventDefault();
    });
    canvas.addEventListener('keyup', (e) => keys.delete(e.code));
    canvas.addEventListener('blur', () => keys.clear());
    canvas.addEventListener('mousedown', (e) => { drag = [e.clientX, e.clientY]; canvas.focus(); });
    window.addEventListener('mouseup', () => { drag = null; });
    window.addEventListener('mousemove', (e) => {
      if (!drag) return;
      look[0] += e.clientX - drag[0];
      look[1] += e.clientY - drag[1];
      drag = [e.clientX, e.clientY];
    });
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      viewer.setSpeed(Math.min(1e4, Math.max(0.05, viewer.speed() * Math.pow(1.25, e.deltaY < 0 ? 1 : -1))));
      $('speed').value = viewer.speed().toFixed(1);
    }, { passive: false });
    $('speed').addEventListener('change', (e) => viewer.setSpeed(parseFloat(e.target.value) || 1));

    const down = (...codes) => codes.some((c) => keys.has(c) || tapped.has(c)) ? 1 : 0;
    function tick(now) {
      const dt = Math.min(0.1, (now - last) / 1000);
      last = now;
      viewer.move(down('KeyD', 'ArrowRight') - down('KeyA', 'ArrowLeft'), down('KeyW', 'ArrowUp') - down('KeyS', 'ArrowDown'),
                  down('KeyE') - down('KeyQ'), look[0], look[1], keys.has('ShiftLeft') || keys.has('ShiftRight'), dt);
      look = [0, 0];
      tapped.clear();
      viewer.frame(W, H, false, false);
      const s = hv.status = JSON.parse(viewer.status());
      for (; lastErrors < s.errors.length; ++lastErrors) showError(s.errors[lastErrors]);
      const fetched = done / Math.max(1, order.length);
      const complete = done === order.length && s.converged;
      setProgress(complete ? 1 : SCENE_SHARE + (0.95 - SCENE_SHARE) * fetched, complete ? 'loaded' :
                  `photographs ${s.arrived}/${s.photos}, ${s.imagesLoaded || 0} decoded`);
      $('loading').hidden = complete;
      if (complete && !hv.loaded) { hv.loaded = true; sources.finish(); console.log('histoview: loading complete'); }
      $('status').textContent = `frame ${s.lastFrameMs.toFixed(1)} ms\nimages ${s.selected || 0} selected, ` +
        `${s.waiting || 0} waiting\ndepth maps ${s.depthMaps || 0}\n` +
        (s.points ? `points ${(s.pointsDrawn || 0).toLocaleString('en')} drawn\n` : '') +
        (s.converged ? 'converged' : 'refining…') + photoBytesText(hv.photoBytes);
      const f = viewer.focused();
      document.querySelectorAll('#photos li').forEach((li) => li.classList.toggle('focused', +li.dataset.index === f));
      timelineUi.update();
      thenNowUi.update(s);
      trafficUi.update(s);
      mapUi.update();
      shareLink(now);
      requestAnimationFrame(tick);
    }
    requestAnimationFrame(tick);

    // The address bar holds the current view (a shared link restores it), at most twice a second.
    let lastShare = -1e9, shared = '';
    function shareLink(now) {
      if (now - lastShare < 500) return;
      lastShare = now;
      const keep = new URLSearchParams();
      for (const name of ['w', 'h', 'log', 'scene']) if (params.has(name)) keep.set(name, params.get(name));
      const extra = keep.toString();
      const query = viewer.shareQuery() + (extra ? '&' + extra : '');
      if (query === shared) return;
      shared = query;
      history.replaceState(null, '', location.pathname + '?' + query);
    }
    $('copy-link').addEventListener('click', () => {
      lastShare = -1e9;
      shareLink(performance.now());
      if (navigator.clipboard) navigator.clipboard.writeText(location.href).catch(() => {});
    });
    // The canvas as a PNG (its drawing buffer is preserved: the converged frame is still there).
    const screenshotBlob = () => new Promise((resolve, reject) =>
      canvas.toBlob((b) => b ? resolve(b) : reject(new Error('screenshot: the canvas gave no PNG')), 'image/png'));
    let shots = 0;
    $('screenshot').addEventListener('click', async () => {
      const url = URL.createObjectURL(await screenshotBlob());
      const a = document.createElement('a');
      a.href = url;
      a.download = `histoview-screenshot-${String(++shots).padStart(3, '0')}.png`;
      document.body.appendChild(a);
      a.click();
      a.remove();
      setTimeout(() => URL.revokeObjectURL(url), 10000);
    });

    // For scripts and tests.
    hv.screenshot = async () => new Uint8Array(await (await screenshotBlob()).arrayBuffer());
    hv.pose = () => viewer.pose();
    hv.shareQuery = () => viewer.shareQuery();
    hv.setTimeWindow = (a, b) => { const err = viewer.setTimeWindow(a, b); timelineUi.update(true); return err; };
    hv.timeWindow = () => JSON.parse(viewer.timeWindow());
    hv.traffic = () => JSON.parse(viewer.traffic());
    hv.setTrafficTime = (t) => { viewer.setTrafficTime(t); trafficUi.update(JSON.parse(viewer.status()), true); };
    hv.playTraffic = (on) => trafficUi.play(on);
    hv.thenNow = (on) => thenNowUi.set(on);
    hv.move = (right, forward, up, lookX, lookY, dt) => viewer.move(right, forward, up, lookX, lookY, false, dt);
    hv.focus = (i) => viewer.focusPhoto(i);
    hv.map = () => ({ ...mapUi.data, view: JSON.parse(viewer.mapView($('map').width, $('map').height)),
                      zoom: mapUi.zoom ? mapUi.zoom() : null });
    hv.mapClick = (x, y) => mapUi.click(x, y);
    hv.mapWhole = () => mapUi.whole();
    // Median time of n frames rendered back to back at the current view (waiting for the GPU).
    hv.measure = (n) => {
      const t = [];
      for (let i = 0; i < n; ++i) { viewer.frame(W, H, true, true); t.push(JSON.parse(viewer.status()).lastFrameMs); }
      t.sort((a, b) => a - b);
      return t[Math.floor(t.length / 2)];
    };
    canvas.focus();
    // Add-ons of the page (web/pose.js) start from here, with what they drive.
    window.dispatchEvent(new CustomEvent('histoview-ready',
      { detail: { viewer, FS, canvas, thenNow: thenNowUi, width: W, height: H } }));
  }

  // The render settings' controls, made from the schema the renderer declares
  // (viewer.settingsSchema(), src/hv/render/settings_schema.h): a checkbox per boolean, a list of
  // the spellings, a number field, or a text field (lists, dates, values that may be "auto"), a
  // section per group; each change goes through viewer.setSetting, as the command line's options
  // do. A control's id is the setting's name.
  const OPEN_GROUPS = ['Blending', 'Geometry', 'Points', 'Debug'];
  // The points' controls most asked for first in their group (the schema's order otherwise).
  const FIRST = ['points', 'point-budget', 'point-radius', 'point-color'];
  const rank = (s) => { const i = FIRST.indexOf(s.name); return i < 0 ? FIRST.length : i; };
  function buildSettings(viewer, pointCount) {
    const box = $('settings');
    const sections = new Map();
    const schema = JSON.parse(viewer.settingsSchema());
    const groupAt = (s) => schema.findIndex((t) => t.group === s.group);
    const key = (s, i) => [groupAt(s), s.group === 'Points' ? rank(s) : 0, i];
    const sorted = schema.map((s, i) => [key(s, i), s])
      .sort(([a], [b]) => a[0] - b[0] || a[1] - b[1] || a[2] - b[2]).map(([, s]) => s);
    for (const s of sorted) {
      if (s.group === 'Points' && !viewer.hasPoints()) continue;
      let section = sections.get(s.group);
      if (!section) {
        section = document.createElement('details');
        section.open = OPEN_GROUPS.includes(s.group);
        const summary = document.createElement('summary');
        summary.textContent = s.group + (s.group === 'Points' && pointCount ? ` (${pointCount.toLocaleString('en')})` : '');
        section.appendChild(summary);
        box.appendChild(section);
        sections.set(s.group, section);
      }
      const label = document.createElement('label');
      label.title = `--${s.name}: ${s.help}` + (s.unit ? ` (${s.unit})` : '') + `; ${s.expected}` +
                    (s.live ? '' : '; changing it makes a new renderer');
      let input;
      if (s.type === 'bool') {
        input = document.createElement('input');
        input.type = 'checkbox';
        input.checked = s.value === 'true';
      } else if (s.type === 'enum') {
        input = document.createElement('select');
        for (const spelling of s.spellings) input.add(new Option(spelling, spelling));
        input.value = s.value;
      } else {
        input = document.createElement('input');
        const numeric = (s.type === 'int' || s.type === 'double') && !s.auto;
        input.type = numeric ? 'number' : 'text';
        if (numeric) {
          if (s.min !== null) input.min = s.min;
          if (s.max !== null) input.max = s.max;
          input.step = s.type === 'int' ? 1 : 'any';
        } else {
          input.placeholder = s.auto ? 'auto' : '';
        }
        input.value = s.value;
      }
      input.id = s.name;
      input.addEventListener('change', () => {
        const err = viewer.setSetting(s.name, input.type === 'checkbox' ? String(input.checked) : input.value);
        input.classList.toggle('invalid', !!err);
        $('setting-error').textContent = err;
        if (err) console.warn('histoview: ' + err);
      });
      if (s.type === 'bool') label.append(input, ' ' + s.name);
      else label.append(s.name + ' ', input);
      section.appendChild(label);
    }
  }

  // A photograph's thumbnail in the list, made by the browser's own decoder from the bytes just
  // fetched (no second download, nothing exported for it), 96 pixels wide.
  const THUMB_WIDTH = 96;
  async function addThumbnail(li, bytes, id) {
    if (typeof createImageBitmap !== 'function') return;
    try {
      const bitmap = await createImageBitmap(new Blob([bytes]));
      const c = document.createElement('canvas');
      c.width = THUMB_WIDTH;
      c.height = Math.max(1, Math.round(THUMB_WIDTH * bitmap.height / bitmap.width));
      c.getContext('2d').drawImage(bitmap, 0, 0, c.width, c.height);
      bitmap.close();
      c.title = id;
      li.appendChild(c);
    } catch (e) {
      console.warn('histoview: thumbnail of ' + id + ': ' + e.message);
    }
  }

  // The Timeline (the desktop viewer's, docs/viewer.md; the arithmetic is hv/viewer/timeline.h in
  // the WebAssembly module): the dates' histogram, the window's two ends as sliders (positions
  // along the axis), play at years/s, loop, all. The list hides the photographs outside the window
  // (undated ones pass any window).
  const SLIDER_STEPS = 1000;
  function buildTimeline(viewer) {
    const t = JSON.parse(viewer.timeline());
    const box = $('timeline-box');
    const ui = { toggle() {}, update() {} };
    if (!t.dated) return ui;
    box.hidden = false;
    const a = $('window-a'), b = $('window-b'), play = $('timeline-play'), hist = $('histogram');
    let last = '';
    function draw(w) {
      const g = hist.getContext('2d'), n = t.counts.length, max = Math.max(1, ...t.counts);
      g.clearRect(0, 0, hist.width, hist.height);
      t.counts.forEach((c, i) => {
        const x0 = hist.width * i / n, x1 = hist.width * (i + 1) / n;
        const inside = (i + 1) / n > w.a && i / n < w.b;  // the bar meets the window (positions along the axis)
        g.fillStyle = inside ? '#fc6' : '#665';
        const h = (hist.height - 2) * c / max;
        g.fillRect(x0 + 0.5, hist.height - h, Math.max(1, x1 - x0 - 1), h);
      });
      g.fillStyle = '#fc63';
      g.fillRect(hist.width * w.a, 0, Math.max(1, hist.width * (w.b - w.a)), hist.height);
    }
    ui.update = (force) => {
      const text = viewer.timeWindow();
      if (text === last && !force) return;
      last = text;
      const w = JSON.parse(text);
      a.value = Math.round(w.a * SLIDER_STEPS);
      b.value = Math.round(w.b * SLIDER_STEPS);
      $('window-text').textContent = (w.open ? 'all photographs: ' : '') + `${w.from} .. ${w.to}: ${w.count} of ${t.dated} ` +
        'dated photographs' +
        (t.undated ? ` (${t.undated} undated, ${w.datedOnly ? 'left out' : 'always shown'})` : '');
      play.textContent = w.playing ? 'pause (Space)' : 'play (Space)';
      document.querySelectorAll('#photos li, #undated-photos li').forEach((li) => li.classList.toggle('outside', !w.inWindow[+li.dataset.index]));
      $('timeline-dated-only').checked = w.datedOnly;
      if (t.undated) $('undated-text').textContent = `${t.undated} undated photograph${t.undated === 1 ? '' : 's'}` +
        (w.datedOnly ? ' (left out: dated only)' : ' (shown in any window)');
      for (const name of ['from', 'to']) { const input = $(name); if (input) input.value = w.open ? '' : w[name]; }
      draw(w);
    };
    const set = (moved) => {
      let pa = a.value / SLIDER_STEPS, pb = b.value / SLIDER_STEPS;
      if (pa > pb) { if (moved === a) pb = pa; else pa = pb; }
      const err = viewer.setTimeWindow(pa, pb);
      if (err) showError(err);
      ui.update(true);
    };
    a.addEventListener('input', () => set(a));
    b.addEventListener('input', () => set(b));
    ui.toggle = () => {
      if (JSON.parse(viewer.timeWindow()).playing) viewer.stopTimeline();
      else viewer.playTimeline(parseFloat($('timeline-speed').value) || 5, $('timeline-loop').checked);
      ui.update(true);
    };
    play.addEventListener('click', ui.toggle);
    $('timeline-all').addEventListener('click', () => { viewer.clearTimeWindow(); ui.update(true); });
    // The undated photographs, listed apart (they pass any window unless dated only); a click goes
    // to one. Dated only is the render setting `dated-only` (also in the settings' Time window group).
    if (t.undated) {
      $('undated-box').hidden = false;
      const photos = JSON.parse(viewer.photos());
      t.undatedPhotos.forEach((i) => {
        const p = photos[i];
        const li = document.createElement('li');
        li.dataset.index = i;
        li.textContent = p.id + (p.date ? ' — ' + p.date + ' (not a date)' : '');
        li.title = 'go to this photograph, then step back into its surroundings';
        li.addEventListener('click', () => { viewer.focusPhoto(i); canvas.focus(); });
        $('undated-photos').appendChild(li);
      });
    }
    $('timeline-dated-only').addEventListener('change', (e) => {
      const err = viewer.setSetting('dated-only', e.target.checked ? 'true' : 'false');
      if (err) showError(err);
      const control = $('dated-only');
      if (control) control.checked = e.target.checked;
      ui.update(true);
    });
    ui.update(true);
    return ui;
  }

  // Then and now (the desktop viewer's, docs/viewer.md; layout hv/viewer/then_now.h): the view
  // at the chosen photograph's camera fitted to the canvas, the photograph left out of the render
  // and laid over the canvas at its rectangle (photoRectInWindow), faded by the opacity or cut at
  // the swipe line (the photograph left of it). Moving, T, the checkbox or another photograph end it.
  function buildThenNow(viewer, FS) {
    const img = $('then-now-image'), box = $('then-now'), opacity = $('then-now-opacity'), swipe = $('then-now-swipe');
    let url = null;
    const style = () => {
      img.style.opacity = opacity.value;
      img.style.clipPath = `inset(0 ${(100 * (1 - swipe.value)).toFixed(2)}% 0 0)`;
    };
    const ui = {
      set(on) {
        if (!on) { viewer.leaveThenNow(); ui.update(JSON.parse(viewer.status())); return ''; }
        const r = JSON.parse(viewer.enterThenNow(viewer.focused(), canvas.width, canvas.height));
        if (r.error) { box.checked = false; $('setting-error').textContent = r.error; return r.error; }
        if (url) URL.revokeObjectURL(url);
        url = URL.createObjectURL(new Blob([FS.readFile(r.image)]));
        img.src = url;
        img.style.left = r.lo[0] + 'px';
        img.style.top = r.lo[1] + 'px';
        img.style.width = (r.hi[0] - r.lo[0]) + 'px';
        img.style.height = (r.hi[1] - r.lo[1]) + 'px';
        style();
        img.hidden = false;
        box.checked = true;
        return '';
      },
      toggle() { ui.set(viewer.thenNow() < 0); },
      update(s) {
        if (s.thenNow < 0 && !img.hidden) { img.hidden = true; box.checked = false; }
      },
    };
    box.addEventListener('change', () => ui.set(box.checked));
    opacity.addEventListener('input', style);
    swipe.addEventListener('input', style);
    return ui;
  }

  // The Traffic (docs/traffic.md, "Playing the traffic"): play/pause (Y) at a speed, loop, and the
  // simulation's time as a slider over the trajectories' span (hv/viewer/traffic_clock.h).
  function buildTraffic(viewer) {
    const t = JSON.parse(viewer.traffic());
    const ui = { toggle() {}, update() {}, play() {} };
    if (!t.vehicles) return ui;
    $('traffic-box').hidden = false;
    const slider = $('traffic-time'), button = $('traffic-play');
    slider.min = t.begin;
    slider.max = t.end;
    let lastTime = null, lastPlaying = null;
    ui.play = (on) => {
      viewer.playTraffic(on, parseFloat($('traffic-rate').value) || 1, $('traffic-loop').checked);
      ui.update(JSON.parse(viewer.status()), true);
    };
    ui.toggle = () => ui.play(!JSON.parse(viewer.status()).trafficPlaying);
    ui.update = (s, force) => {
      if (!force && s.time === lastTime && s.trafficPlaying === lastPlaying) return;
      lastTime = s.time;
      lastPlaying = s.trafficPlaying;
      slider.value = s.time;
      button.textContent = s.trafficPlaying ? 'pause (Y)' : 'play (Y)';
      $('traffic-text').textContent = `${s.vehicles} of ${t.vehicles} vehicles on the road at ${s.time.toFixed(1)} s ` +
        `(${t.begin.toFixed(1)} .. ${t.end.toFixed(1)} s)`;
      const input = $('time');
      if (input && document.activeElement !== input) input.value = String(s.time);
    };
    slider.addEventListener('input', () => { viewer.setTrafficTime(parseFloat(slider.value)); ui.update(JSON.parse(viewer.status()), true); });
    button.addEventListener('click', ui.toggle);
    $('traffic-rate').addEventListener('change', () => { if (JSON.parse(viewer.status()).trafficPlaying) ui.play(true); });
    ui.update(JSON.parse(viewer.status()), true);
    return ui;
  }

  function buildPhotoList(viewer, photos) {
    const list = $('photos');
    photos.forEach((p, i) => {
      const li = document.createElement('li');
      li.dataset.index = i;
      li.className = 'pending';
      li.textContent = p.id + (p.date ? ' — ' + p.date : '');
      li.title = 'go to this photograph, then step back into its surroundings';
      li.addEventListener('click', () => { viewer.focusPhoto(i); canvas.focus(); });
      list.appendChild(li);
    });
    $('search').addEventListener('input', (e) => {
      const q = e.target.value.toLowerCase();
      list.querySelectorAll('li').forEach((li) => { li.hidden = q && !li.textContent.toLowerCase().includes(q); });
    });
  }

  main().catch((e) => showError(e && e.message ? e.message : e));
})();
