// Headless Chromium end-to-end test of the web page (run by tests/web_test.sh, which serves an
// export of the demo city with a native `histoview render` of the same view as reference.png).
//   node tests/web/web_test.mjs URL OUTDIR [--measure N]
// Loads URL (…/?camera=ID&w=&h=&k=), waits until the page reports loading complete (every
// photograph fetched, the frame converged), checks there were no page errors, compares the
// canvas, with the demo's lidar points drawn, with reference-points.png (native `render --points`;
// PSNR over RGB), switches the points off and compares with reference.png (native `render`), checks
// the point controls, moves the camera and checks the picture changes, then that the panel's debug
// view and a layer switch change it too and converge without errors. Then the historian's tools:
// the time window hides the photographs outside it (list and picture), plays; the screenshot button
// downloads a PNG of the canvas; the traffic has vehicles on the road, plays and moves; the address
// bar's shared link, opened in a second page, restores the camera, the window and the traffic's time;
// then and now lays the chosen photograph over the canvas until the camera moves. The map: the
// photographs' dots where their cameras are (north up, one scale), drawn on the map's canvas; a
// click on a dot goes to that photograph, one elsewhere to the ground there. The photograph
// tests/web_test.sh left undated is listed apart under the timeline, and dated only leaves it out.
// The thumbnails in the list; the Points group (the budget bounds the points drawn); the map's
// wheel zoom, drag and whole map.
// Pose mode: six pairs clicked on the photograph and on the view pose photograph 0 at its known
// camera (within 0.5 m and 0.5°), a misplaced point dragged into place; look from it, save.
// Writes web-points.png and web.png (the canvas) into OUTDIR; HV_WEB_SCREENSHOT=FILE also saves the
// whole page, HV_WEB_POSE_SCREENSHOT=FILE the whole page in pose mode. Prints "N passed, M failed";
// exit code 1 on failure.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const [url, outDir, ...rest] = process.argv.slice(2);
const measure = rest[0] === '--measure' ? parseInt(rest[1], 10) : 0;
// WebGL2 on the CPU: SwiftShader through ANGLE (docs/web.md, PLATFORM notes).
const flags = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--ignore-gpu-blocklist', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync'];
// The bound: the page runs the same renderer and shaders on the same camera, but the photographs
// went through JPEG (the export re-encodes the demo's PNGs at quality 90) and SwiftShader's float
// arithmetic and texture filtering differ from llvmpipe's in the last bits: 44 dB measured on the
// test city (320x240, K = 8). 35 dB (RMS error ~4.5 grey levels) leaves room for that and still
// fails a wrong camera, a missing photograph or depth map, or an upside-down picture (< 25 dB).
const MIN_PSNR = 35.0;
// With the demo city's lidar scan drawn as textured sprites (`render --points`, K = 8): the same
// differences, plus SwiftShader's rasterisation of the sprites and the chunks rebuilt in the
// browser (the same points in each chunk, shuffled in another order: sprites at equal depth may
// swap): 40.3 dB measured on the test city (320x240). The same 35 dB bound still fails a picture
// without the points (24.5 dB against the reference with them) or with the sprites misplaced.
const MIN_PSNR_POINTS = 35.0;
// Switching the points off must change a visible part of the picture: 14.1 % of the pixels
// measured (the trees, which only the lidar scan has, and the sprites over facades and street).
const MIN_POINTS_CHANGE = 0.02;

let passed = 0, failed = 0;
const check = (ok, what) => { if (ok) { passed++; console.log('ok    ' + what); } else { failed++; console.log('FAIL  ' + what); } };

// Playwright gives the browser a fresh temporary profile itself (it refuses --user-data-dir).
const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', args: flags });
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); if (process.env.HV_WEB_VERBOSE) console.log('console: ' + m.text()); });
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.hv && (window.hv.loaded || window.hv.errors.length > 0), null, { timeout: 240000, polling: 250 });
  const state = await page.evaluate(() => ({ loaded: hv.loaded, errors: hv.errors, status: hv.status }));
  console.log(`loaded in ${((Date.now() - t0) / 1000).toFixed(1)} s: ${JSON.stringify(state.status)}`);
  check(state.loaded, 'the page reports loading complete');
  check(state.errors.length === 0 && pageErrors.length === 0, 'no page errors' +
        (state.errors.length + pageErrors.length ? ': ' + [...state.errors, ...pageErrors].join(' | ') : ''));

  // The canvas and a reference image, compared in the page (a 2D canvas reads both): PSNR over RGB.
  const psnrAgainst = (reference) => page.evaluate(async (reference) => {
    const canvas = document.getElementById('view');
    const grab = (src) => {
      const c = document.createElement('canvas');
      c.width = src.width; c.height = src.height;
      const g = c.getContext('2d');
      g.drawImage(src, 0, 0);
      return g.getImageData(0, 0, c.width, c.height).data;
    };
    const ref = new Image();
    ref.src = reference;
    await ref.decode();
    const a = grab(canvas), b = grab(ref);
    if (ref.width !== canvas.width || ref.height !== canvas.height)
      return { error: `${reference} ${ref.width}x${ref.height}, canvas ${canvas.width}x${canvas.height}` };
    let se = 0, n = 0;
    for (let i = 0; i < a.length; i += 4) for (let c = 0; c < 3; ++c) { const d = a[i + c] - b[i + c]; se += d * d; n++; }
    const mse = se / n;
    return { psnr: mse === 0 ? Infinity : 10 * Math.log10(255 * 255 / mse), png: canvas.toDataURL('image/png') };
  }, reference);
  const compare = async (reference, bound, png, what) => {
    const cmp = await psnrAgainst(reference);
    if (cmp.png) fs.writeFileSync(path.join(outDir, png), Buffer.from(cmp.png.split(',')[1], 'base64'));
    console.log(cmp.error ? cmp.error : `${what}: PSNR ${cmp.psnr.toFixed(2)} dB (bound ${bound} dB)`);
    return !cmp.error && cmp.psnr >= bound;
  };
  const canvasUrl = () => page.evaluate(() => document.getElementById('view').toDataURL('image/png'));
  // The fraction of the canvas's pixels that differ (by more than 24 levels summed over RGB) from
  // an earlier canvas.
  const fractionChanged = (beforeUrl) => page.evaluate(async (url) => {
    const img = new Image();
    img.src = url;
    await img.decode();
    const grab = (src) => {
      const c = document.createElement('canvas');
      c.width = src.width; c.height = src.height;
      const g = c.getContext('2d');
      g.drawImage(src, 0, 0);
      return g.getImageData(0, 0, c.width, c.height).data;
    };
    const a = grab(document.getElementById('view')), b = grab(img);
    let changed = 0;
    for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 24) changed++;
    return changed / (a.length / 4);
  }, beforeUrl);
  // The same once the page has converged again (every control redraws: wait for a frame drawn
  // after the last change, then for convergence).
  const changedSince = async (beforeUrl) => {
    await page.waitForFunction(() => hv.status && hv.status.frames > (window.framesAtChange ?? -1) &&
                                     hv.status.converged && !hv.status.focusing, null, { timeout: 60000, polling: 250 });
    await page.waitForTimeout(300);
    return fractionChanged(beforeUrl);
  };
  // The panel's controls, as a user changes them (the page listens to 'change').
  const setControl = (id, value) => page.evaluate(([id, value]) => {
    const e = document.getElementById(id);
    window.framesAtChange = hv.status.frames;
    if (e.type === 'checkbox') e.checked = value; else e.value = value;
    e.dispatchEvent(new Event('change'));
  }, [id, value]);

  // The demo city has a lidar scan: the page starts with it drawn, as `render --points` draws it.
  check(state.status.points > 0 && state.status.pointsDrawn > 0,
        `the scene's points are loaded and drawn (${state.status.points} points, ${state.status.pointsDrawn} drawn)`);
  check(await compare('reference-points.png', MIN_PSNR_POINTS, 'web-points.png', 'web vs native render --points'),
        'with points: the canvas is the native render --points of the same camera');
  const withPoints = await canvasUrl();
  // Points off: the picture changes, to the native render without points.
  await setControl('points', false);
  const pointsOff = await changedSince(withPoints);
  console.log(`points off: ${(100 * pointsOff).toFixed(1)} % of the pixels changed`);
  check(pointsOff > MIN_POINTS_CHANGE, 'the points switch changes the picture');
  check(await compare('reference.png', MIN_PSNR, 'web.png', 'web vs native render'),
        'the canvas is the native render of the same camera');
  await setControl('points', true);
  const pointsOn = await changedSince(withPoints);
  console.log(`points on again: ${(100 * pointsOn).toFixed(2)} % of the pixels differ from the first picture`);
  check(pointsOn === 0, 'points on again: the same picture');
  // The point controls: transient points hidden (the demo's trees and parked cars), the filter.
  await setControl('hide-transient', true);
  const hidden = await changedSince(withPoints);
  console.log(`transient points hidden: ${(100 * hidden).toFixed(1)} % of the pixels changed`);
  check(hidden > 0.001, 'hiding transient points changes the picture');
  await setControl('hide-transient', false);
  await setControl('point-filter', 'epsilon');
  const epsilon = await changedSince(withPoints);
  console.log(`epsilon filter: ${(100 * epsilon).toFixed(1)} % of the pixels changed`);
  check(epsilon > 0.001, 'the epsilon filter changes the picture');
  await setControl('point-filter', 'auto');
  check(await changedSince(withPoints) === 0, 'filter back to auto: the same picture');
  const pointErrors = await page.evaluate(() => hv.errors);
  check(pointErrors.length === 0 && pageErrors.length === 0, 'no page errors after the point controls');

  if (process.env.HV_WEB_SCREENSHOT) await page.screenshot({ path: process.env.HV_WEB_SCREENSHOT });

  if (measure > 0) {
    // With the points (as the page starts) and without, at the start view.
    const ms = await page.evaluate((n) => hv.measure(n), measure);
    console.log(`frame time with points (median of ${measure}, converged, forced redraw): ${ms.toFixed(1)} ms`);
    await setControl('points', false);
    await changedSince(withPoints);
    const msMesh = await page.evaluate((n) => hv.measure(n), measure);
    console.log(`frame time without points: ${msMesh.toFixed(1)} ms`);
    await setControl('points', true);
    await changedSince(withPoints);
  }

  // Move forward and turn a little: the picture must change, and converge again without errors.
  const before = await canvasUrl();
  await page.evaluate(() => hv.move(0, 1, 0, 40, 0, 0.5));
  await page.waitForFunction(() => hv.status && hv.status.converged && !hv.status.focusing, null, { timeout: 60000, polling: 250 });
  await page.waitForTimeout(300);
  const diff = await fractionChanged(before);
  console.log(`after moving: ${(100 * diff).toFixed(1)} % of the pixels changed`);
  check(diff > 0.2, 'moving the camera changes the picture');
  const after = await page.evaluate(() => hv.errors);
  check(after.length === 0 && pageErrors.length === 0, 'no page errors after moving');

  // Debug view and layer switches (docs/viewer.md): the heat map of contributing images replaces
  // the picture; back to the picture, the terrain switched off leaves background where it was
  // (with the points off: the lidar's ground points would cover most of it).
  await setControl('points', false);
  await changedSince(await canvasUrl());
  const picture = await canvasUrl();
  await setControl('debug-view', 'count');
  const heat = await changedSince(picture);
  console.log(`contributing-images view: ${(100 * heat).toFixed(1)} % of the pixels changed`);
  check(heat > 0.2, 'the debug view replaces the picture');
  await setControl('debug-view', 'picture');
  check(await changedSince(picture) === 0, 'back to the picture');
  await setControl('terrain', false);
  const noTerrain = await changedSince(picture);
  console.log(`terrain off: ${(100 * noTerrain).toFixed(1)} % of the pixels changed`);
  check(noTerrain > 0.02, 'the terrain switch changes the picture');
  await setControl('terrain', true);
  check(await changedSince(picture) === 0, 'terrain on again: the same picture');
  const errorsAfter = await page.evaluate(() => hv.errors);
  check(errorsAfter.length === 0 && pageErrors.length === 0, 'no page errors after the switches');
  // The time window (docs/web.md, "The page"): the same arithmetic as the desktop timeline.
  await setControl('points', true);
  await changedSince(picture);
  const photoCount = state.status.photos;
  const all = await page.evaluate(() => hv.timeWindow());
  check(all.open && all.inWindow.length === photoCount && all.inWindow.every((x) => x),
        'no time window: every photograph in it');
  const firstPicture = await canvasUrl();
  await page.evaluate(() => { window.framesAtChange = hv.status.frames; });
  const narrow = await page.evaluate(() => { const err = hv.setTimeWindow(0, 0.02); return { err, w: hv.timeWindow() }; });
  const outside = await page.evaluate(() => document.querySelectorAll('#photos li.outside').length);
  console.log(`time window ${narrow.w.from} .. ${narrow.w.to}: ${narrow.w.count} dated photographs in it, ${outside} hidden in the list`);
  check(!narrow.err && !narrow.w.open && narrow.w.count < photoCount, 'a narrow time window holds fewer photographs');
  check(outside === narrow.w.inWindow.filter((x) => !x).length && outside > 0,
        'the list hides the photographs outside the window');
  const windowChange = await changedSince(firstPicture);
  console.log(`narrow window: ${(100 * windowChange).toFixed(1)} % of the pixels changed`);
  check(windowChange > 0.02, 'the time window changes the picture (photographs outside it no longer texture it)');
  const beforePlay = await page.evaluate(() => hv.timeWindow());
  await page.click('#timeline-play');
  await page.waitForTimeout(1500);
  await page.click('#timeline-play');
  const played = await page.evaluate(() => hv.timeWindow());
  console.log(`timeline played 1.5 s: ${beforePlay.from} .. ${beforePlay.to} -> ${played.from} .. ${played.to}`);
  check(played.from > beforePlay.from && !played.playing, 'play walks the window forward, pause stops it');
  await page.click('#timeline-all');
  check((await page.evaluate(() => hv.timeWindow())).open, '"all" clears the window');
  await page.evaluate(() => hv.setTimeWindow(0, 0.5));

  // The screenshot button: a PNG of the canvas's size, downloaded.
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#screenshot')]);
  const shot = fs.readFileSync(await download.path());
  const png = shot.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]));
  const [cw, ch] = await page.evaluate(() => [document.getElementById('view').width, document.getElementById('view').height]);
  console.log(`screenshot: ${download.suggestedFilename()}, ${shot.length} bytes, ${shot.readUInt32BE(16)}x${shot.readUInt32BE(20)}`);
  check(png && shot.readUInt32BE(16) === cw && shot.readUInt32BE(20) === ch &&
        download.suggestedFilename() === 'histoview-screenshot-001.png', 'the screenshot is a PNG of the canvas');

  // The traffic (docs/traffic.md, "Playing the traffic"): the demo's SUMO run, exported.
  const traffic = await page.evaluate(() => hv.traffic());
  check(traffic.vehicles > 0 && traffic.end > traffic.begin,
        `the export carries the traffic (${traffic.vehicles} vehicles, ${traffic.begin} .. ${traffic.end} s)`);
  const onRoad = [];
  for (const t of [0.25, 0.5, 0.75].map((f) => traffic.begin + f * (traffic.end - traffic.begin))) {
    await page.evaluate((t) => hv.setTrafficTime(t), t);
    await page.waitForTimeout(200);
    onRoad.push(await page.evaluate(() => ({ time: hv.status.time, vehicles: hv.status.vehicles })));
  }
  console.log('vehicles on the road: ' + onRoad.map((o) => `${o.vehicles} at ${o.time.toFixed(1)} s`).join(', '));
  check(onRoad.some((o) => o.vehicles > 0), 'vehicles are on the road at some time');
  check(new Set(onRoad.map((o) => o.vehicles)).size > 1 || onRoad[0].time !== onRoad[2].time, 'moving the time changes the traffic');
  const trafficStill = await canvasUrl();
  await page.evaluate(() => hv.playTraffic(true));
  await page.waitForTimeout(1500);
  const moving = await page.evaluate(() => hv.status);
  await page.focus('#view');
  await page.keyboard.press('KeyY');  // keys go to the canvas: pause
  await page.waitForTimeout(300);
  const paused = await page.evaluate(() => hv.status);
  console.log(`traffic played 1.5 s: ${onRoad[2].time.toFixed(2)} -> ${moving.time.toFixed(2)} s; ` +
              `${(100 * await fractionChanged(trafficStill)).toFixed(2)} % of the pixels changed`);
  check(moving.trafficPlaying && moving.time !== onRoad[2].time, 'play moves the traffic\'s clock');
  check(!paused.trafficPlaying, 'Y pauses it');

  // The shared link: the address bar holds the view; a second page opened on it restores it.
  await page.waitForTimeout(800);
  const shared = await page.evaluate(() => ({ href: location.href, pose: hv.pose(), w: hv.timeWindow(), time: hv.status.time }));
  console.log('shared link: ' + shared.href);
  check(/[?&]pose=/.test(shared.href) && /[?&]from=/.test(shared.href) && /[?&]time=/.test(shared.href),
        'the address bar holds the pose, the time window and the traffic\'s time');
  const page2 = await browser.newPage({ viewport: { width: 1000, height: 560 } });
  page2.on('pageerror', (e) => pageErrors.push(String(e)));
  await page2.goto(shared.href);
  await page2.waitForFunction(() => window.hv && (window.hv.loaded || window.hv.errors.length > 0), null, { timeout: 240000, polling: 250 });
  const restored = await page2.evaluate(() => ({ pose: hv.pose(), w: hv.timeWindow(), time: hv.status.time, errors: hv.errors }));
  const a = shared.pose.split(',').map(Number), b = restored.pose.split(',').map(Number);
  const poseError = Math.max(...a.map((x, i) => Math.abs(x - b[i])));
  console.log(`restored pose ${restored.pose} (largest difference ${poseError.toExponential(2)}), window ${restored.w.from} .. ${restored.w.to}, time ${restored.time}`);
  check(restored.errors.length === 0 && a.length === 8 && poseError < 2e-4, 'the shared link restores the camera');
  check(restored.w.from === shared.w.from && restored.w.to === shared.w.to && Math.abs(restored.time - shared.time) < 1e-3,
        'the shared link restores the time window and the traffic\'s time');
  await page2.close();

  // Then and now at a photograph: the photograph over the canvas at its rectangle (the canvas
  // letterboxes it: its aspect ratio kept, one side the canvas's), left out of the render; a
  // move ends it.
  const tn = await page.evaluate(async () => {
    hv.focus(0);
    const err = hv.thenNow(true);
    const img = document.getElementById('then-now-image');
    await img.decode();
    return { err, hidden: img.hidden, w: parseFloat(img.style.width), h: parseFloat(img.style.height),
             nw: img.naturalWidth, nh: img.naturalHeight };
  });
  await page.waitForFunction(() => hv.status.thenNow === 0, null, { timeout: 60000, polling: 250 });
  console.log(`then and now: the ${tn.nw}x${tn.nh} photograph at ${tn.w.toFixed(1)}x${tn.h.toFixed(1)} on the ${cw}x${ch} canvas`);
  check(!tn.err && !tn.hidden && Math.abs(tn.w / tn.h - tn.nw / tn.nh) < 0.01 * tn.nw / tn.nh &&
        (Math.abs(tn.w - cw) < 0.01 || Math.abs(tn.h - ch) < 0.01) && tn.w <= cw + 0.01 && tn.h <= ch + 0.01,
        'then and now lays the photograph over the canvas, letterboxed');
  await page.evaluate(() => hv.move(0, 1, 0, 0, 0, 0.1));
  await page.waitForFunction(() => hv.status.thenNow === -1, null, { timeout: 60000, polling: 250 });
  await page.waitForTimeout(300);
  check(await page.evaluate(() => document.getElementById('then-now-image').hidden), 'moving ends then and now');
  // The map (docs/web.md, "The page"): the export's cameras, read here, against the dots the page
  // draws. North up at one scale: x_i - x_j = s (X_i - X_j), y_i - y_j = -s (Y_i - Y_j) (the demo
  // city: a CRS, up = z).
  const map = await page.evaluate(async () => {
    const cams = (await (await fetch('cameras.json')).json()).cameras;
    const m = hv.map();
    const canvas = document.getElementById('map'), g = canvas.getContext('2d');
    const colours = m.dots.map((d) => Array.from(g.getImageData(Math.floor(d.x), Math.floor(d.y), 1, 1).data));
    return { cams, dots: m.dots, view: m.view, undated: m.undated, colours, canvasW: canvas.width, canvasH: canvas.height,
             outlines: m.outlines.length, shade: !!m.hillshade };
  });
  const byId = new Map(map.cams.map((c) => [c.id, c]));
  let far = [0, 1], farD = -1;
  map.dots.forEach((a, i) => map.dots.forEach((b, j) => {
    const A = byId.get(a.id).center, B = byId.get(b.id).center, d = Math.hypot(A[0] - B[0], A[1] - B[1]);
    if (d > farD) { farD = d; far = [i, j]; }
  }));
  const [fi, fj] = far.map((k) => map.dots[k]);
  const scale = Math.hypot(fi.x - fj.x, fi.y - fj.y) / farD;
  let worst = 0;
  for (const d of map.dots) {
    const C = byId.get(d.id).center, C0 = byId.get(fi.id).center;
    const ex = fi.x + scale * (C[0] - C0[0]), ey = fi.y - scale * (C[1] - C0[1]);
    worst = Math.max(worst, Math.hypot(d.x - ex, d.y - ey));
  }
  console.log(`map: ${map.dots.length} dots, ${scale.toFixed(3)} px/m, worst ${worst.toFixed(3)} px; ` +
              `${map.outlines / 4} outline segments, hillshade ${map.shade}`);
  check(map.dots.length === map.cams.length && worst < 0.05 && map.dots.every((d) => d.x >= 0 && d.y >= 0 &&
        d.x <= map.canvasW && d.y <= map.canvasH), 'the map puts every photograph where its camera is, north up');
  check(map.outlines > 0 && map.shade, 'the map has the buildings\' footprints and the terrain\'s hillshade');
  // Each dot drawn in its colour (dated orange, undated blue) at its centre: those at least 8 pixels
  // from every other dot and 14 from the view's triangle (which are drawn over them otherwise).
  const isColour = (c, rgb) => Math.abs(c[0] - rgb[0]) + Math.abs(c[1] - rgb[1]) + Math.abs(c[2] - rgb[2]) < 60;
  const apart = map.dots.map((d) => map.dots.every((e) => e === d || Math.hypot(d.x - e.x, d.y - e.y) >= 8) &&
                                    Math.hypot(d.x - map.view.x, d.y - map.view.y) >= 14);
  const seen = map.dots.filter((d, i) => apart[i] && isColour(map.colours[i], d.dated ? [240, 160, 40] : [120, 170, 230]));
  const nApart = apart.filter(Boolean).length;
  check(nApart >= 3 && seen.length === nApart && map.dots.some((d) => !d.dated),
        `the map draws the dots in their colours (${seen.length} of the ${nApart} apart from the others)`);
  // A click on a dot (as the mouse does it): the view goes to that photograph, then steps back
  // along its axis (focus + context): the camera ends behind the photograph's centre, looking its way.
  const target = map.dots.find((d) => d.photo !== 0 && d.dated) || map.dots[1];
  await page.locator('#map').scrollIntoViewIfNeeded();
  const mapBox = await page.locator('#map').boundingBox();
  await page.mouse.click(mapBox.x + target.x * mapBox.width / map.canvasW, mapBox.y + target.y * mapBox.height / map.canvasH);
  await page.waitForTimeout(500);  // hv.status is refreshed each frame: not the one before the click
  await page.waitForFunction((i) => hv.viewer.focused() === i && !hv.status.focusing, target.photo,
                             { timeout: 60000, polling: 250 });
  const pose = (await page.evaluate(() => hv.pose())).split(',').map(Number);
  const cam = byId.get(target.id), fwd = cam.rotation.slice(6, 9);
  const [, , , qw, qx, qy, qz] = pose;
  const viewFwd = [2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)];
  const back = [0, 1, 2].map((k) => pose[k] - cam.center[k]), backLen = Math.hypot(...back);
  const along = back.reduce((a, v, k) => a - v * fwd[k], 0) / Math.max(backLen, 1e-9);
  const facing = viewFwd.reduce((a, v, k) => a + v * fwd[k], 0);
  console.log(`map click on ${target.id}: ${backLen.toFixed(2)} m behind it (cos ${along.toFixed(4)}), facing cos ${facing.toFixed(4)}`);
  check(backLen > 0.1 && along > 0.999 && facing > 0.98, 'a click on a dot goes to that photograph (focus + context)');
  // A click on the ground, away from the dots: the view flies there, its heading kept.
  let spot = null;
  for (let y = 10; y < map.canvasH && !spot; y += 10)
    for (let x = 10; x < map.canvasW && !spot; x += 10)
      if (map.dots.every((d) => Math.hypot(d.x - x, d.y - y) > 20)) spot = [x, y];
  const gBefore = (await page.evaluate(() => hv.pose())).split(',').map(Number);
  const ground = await page.evaluate(([x, y]) => hv.mapClick(x, y), spot);
  await page.waitForTimeout(500);
  await page.waitForFunction(() => !hv.status.focusing, null, { timeout: 60000, polling: 250 });
  await page.waitForTimeout(300);
  const gAfter = (await page.evaluate(() => hv.pose())).split(',').map(Number);
  const quatSame = Math.abs([3, 4, 5, 6].reduce((a, k) => a + gBefore[k] * gAfter[k], 0)) > 0.9999;
  console.log(`map click on the ground at ${JSON.stringify(ground)}: view at ${gAfter.slice(0, 3).join(', ')}`);
  check(ground.ground && Math.hypot(gAfter[0] - ground.ground[0], gAfter[1] - ground.ground[1]) < 0.01 &&
        gAfter[2] > ground.ground[2] && quatSame, 'a click on the ground flies there, the heading kept');
  // The undated photograph (tests/web_test.sh removed its date from the export) is listed apart;
  // dated only leaves it out of the window.
  const undated = await page.evaluate(async () => {
    const items = Array.from(document.querySelectorAll('#undated-photos li')).map((li) => +li.dataset.index);
    const text = document.getElementById('undated-text').textContent;
    const inWindowBefore = hv.timeWindow().inWindow;
    const box = document.getElementById('timeline-dated-only');
    box.click();
    const w = hv.timeWindow();
    const textAfter = document.getElementById('undated-text').textContent;
    box.click();
    return { items, text, textAfter, before: items.map((i) => inWindowBefore[i]), after: items.map((i) => w.inWindow[i]),
             datedOnly: w.datedOnly, restored: hv.timeWindow().datedOnly === false,
             visible: !document.getElementById('undated-box').hidden };
  });
  console.log(`undated: ${JSON.stringify(undated)}`);
  check(undated.visible && undated.items.length === 1 && map.undated.length === 1 &&
        undated.items[0] === map.undated[0] && undated.text.startsWith('1 undated photograph'),
        'the undated photograph is listed apart under the timeline');
  check(undated.before.every(Boolean) && undated.datedOnly && undated.after.every((v) => !v) && undated.restored &&
        undated.textAfter.includes('dated only'), 'dated only leaves the undated photographs out, and back');
  // Pose mode (web/pose.js): photograph 0 posed from 6 pairs made by synthetic clicks, the known
  // camera being the scene's own. The view at that camera (then and now puts it there); world
  // points picked on it (the renderer's view depth); their pixels in the photograph from the
  // known camera; each pair a click on the photograph's canvas, then one on the view. One pair is
  // first clicked 12 px off and dragged onto its pixel. The solved camera must be the known one.
  const POSE_CENTRE_M = 0.5, POSE_ROTATION_DEG = 0.5;
  const framesBefore = await page.evaluate(() => {
    const frames = hv.status.frames;  // the last tick's: a frame at the new camera comes after it
    hv.focus(0);
    hv.thenNow(true);
    hv.thenNow(false);
    return frames;
  });
  await page.waitForFunction((f) => hv.status.frames > f, framesBefore, { timeout: 60000, polling: 100 });
  await page.click('#pose-start');
  const startState = await page.evaluate(() => hv.poseState());
  check(startState.on && startState.photo === 0 && !(await page.locator('#pose-side').isHidden()),
        'pose mode shows the chosen photograph beside the view');
  // Candidate view pixels (integers: the click lands exactly there) over the canvas, kept where the
  // view shows a surface whose point the known camera sees inside the photograph (8 px margin).
  const candidates = await page.evaluate(({ cw, ch }) => {
    const out = [];
    for (const fy of [0.55, 0.8, 0.35, 0.92, 0.68, 0.45])
      for (const fx of [0.12, 0.88, 0.5, 0.3, 0.7]) {
        const x = Math.round(fx * cw), y = Math.round(fy * ch);
        const p = hv.pickView(x, y);
        if (!p.hit) continue;
        const q = hv.poseProjectOriginal(p.x, p.y, p.z);
        const s = hv.poseState();
        if (q.inFront && q.u > 8 && q.v > 8 && q.u < s.width - 8 && q.v < s.height - 8) out.push({ x, y, world: [p.x, p.y, p.z], u: q.u, v: q.v });
      }
    return out;
  }, { cw, ch });
  // The top-right corner of this view is sky: nothing to pick there.
  check(!(await page.evaluate(({ cw }) => hv.pickView(cw - 3, 3).hit, { cw })), 'the sky gives no point');
  // Six spread over the picture: the first of each row of fractions first.
  const chosen = [];
  for (const c of candidates) if (chosen.length < 6 && !chosen.some((d) => Math.hypot(d.x - c.x, d.y - c.y) < 0.15 * cw)) chosen.push(c);
  console.log(`pose: ${candidates.length} candidate pixels, ${chosen.length} chosen`);
  check(chosen.length === 6, 'six points of the view picked with their pixels in the photograph');
  const photoBox = await page.locator('#pose-photo').boundingBox();
  const photoScale = photoBox.width / startState.width;
  const clickPhoto = (u, v) => page.locator('#pose-photo').click({ position: { x: u * photoScale, y: v * photoScale } });
  for (const [k, c] of chosen.entries()) {
    await clickPhoto(k === 0 ? c.u + 12 : c.u, k === 0 ? c.v - 5 : c.v);
    await page.locator('#view').click({ position: { x: c.x, y: c.y } });
  }
  const unfixed = await page.evaluate(() => hv.poseState());
  // Dragging pair 1 onto its pixel.
  await page.locator('#pose-photo').scrollIntoViewIfNeeded();
  const box2 = await page.locator('#pose-photo').boundingBox();
  await page.mouse.move(box2.x + unfixed.pairs[0].u * photoScale, box2.y + unfixed.pairs[0].v * photoScale);
  await page.mouse.down();
  await page.mouse.move(box2.x + chosen[0].u * photoScale, box2.y + chosen[0].v * photoScale, { steps: 4 });
  await page.mouse.up();
  const posed = await page.evaluate(() => hv.poseState());
  const worldOff = Math.max(...posed.pairs.map((p, k) => Math.hypot(p.x - chosen[k].world[0], p.y - chosen[k].world[1], p.z - chosen[k].world[2])));
  const pixelOff = Math.max(...posed.pairs.map((p, k) => Math.hypot(p.u - chosen[k].u, p.v - chosen[k].v)));
  console.log(`pose: ${posed.pairs.length} pairs; the clicks' world points within ${worldOff.toExponential(2)} m and pixels within ` +
              `${pixelOff.toFixed(3)} px of the intended; before the drag pair 1's residual ` +
              `${unfixed.pairs[0].residual !== undefined ? unfixed.pairs[0].residual.toFixed(2) : '-'} px; ${posed.message}`);
  check(posed.pairs.length === 6 && worldOff < 1e-6 && pixelOff < 1.0, 'six pairs made by clicks on the photograph and on the view');
  const angle = (a, b) => {  // degrees between two row-major rotations
    let tr = 0;
    for (let i = 0; i < 3; ++i) for (let j = 0; j < 3; ++j) tr += a[3 * i + j] * b[3 * i + j];
    return Math.acos(Math.min(1, Math.max(-1, (tr - 1) / 2))) * 180 / Math.PI;
  };
  if (posed.solved) {
    const dc = Math.hypot(...posed.camera.center.map((x, i) => x - posed.original.center[i]));
    const dr = angle(posed.camera.rotation, posed.original.rotation);
    console.log(`pose: solved camera ${dc.toFixed(3)} m and ${dr.toFixed(3)}° from the known one; ${posed.rms.toFixed(2)} px RMS; ` +
                `residuals ${posed.pairs.map((p) => p.residual.toFixed(2)).join(' ')} px`);
    check(dc < POSE_CENTRE_M && dr < POSE_ROTATION_DEG, `the solved camera is the known one (centre < ${POSE_CENTRE_M} m, rotation < ${POSE_ROTATION_DEG}°)`);
    check(posed.pairs.every((p) => p.inlier && p.pu !== undefined), 'every pair an inlier, with its residual line');
    check(unfixed.pairs[0].residual === undefined || unfixed.pairs[0].residual > 2, 'the misplaced point showed as a residual before the drag');
  } else {
    check(false, 'the pairs give a camera: ' + posed.message);
  }
  // The photograph projected from the solved camera: the renderer made again, converging without errors.
  await page.waitForFunction(() => hv.status.converged, null, { timeout: 120000, polling: 250 });
  // HV_WEB_POSE_SCREENSHOT=FILE: the whole page in pose mode (the README's picture).
  if (process.env.HV_WEB_POSE_SCREENSHOT) await page.screenshot({ path: process.env.HV_WEB_POSE_SCREENSHOT, fullPage: true });
  // Look from it, faded by the pose panel's opacity slider; then save the cameras.json.
  await page.locator('#pose-opacity').fill('0.4');
  await page.click('#pose-look');
  await page.waitForFunction(() => hv.status.thenNow === 0, null, { timeout: 60000, polling: 250 });
  const look = await page.evaluate(() => ({ hidden: document.getElementById('then-now-image').hidden,
                                            opacity: document.getElementById('then-now-image').style.opacity }));
  check(!look.hidden && Math.abs(parseFloat(look.opacity) - 0.4) < 1e-6, 'look from it lays the photograph over the view at the slider\'s opacity');
  const [saved] = await Promise.all([page.waitForEvent('download'), page.click('#pose-save')]);
  const savedJson = JSON.parse(fs.readFileSync(await saved.path(), 'utf8'));
  const savedCam = savedJson.cameras && savedJson.cameras[0];
  check(savedCam && savedCam.id === posed.original.id && Math.hypot(...savedCam.center.map((x, i) => x - posed.camera.center[i])) < 1e-9 &&
        saved.suggestedFilename().endsWith('.cameras.json'), 'save downloads the solved camera as a cameras.json');
  await page.click('#pose-start');  // leave: saved, so the solved camera stays
  check(!(await page.evaluate(() => hv.poseState().on)) && await page.locator('#pose-side').isHidden(), 'leaving pose mode hides the photograph');
  await thumbnailsStep(page, check);
  await pointControlsStep(page, check, setControl);
  await mapZoomPanStep(page, check);
  check(pageErrors.length === 0, 'no page errors after the timeline, screenshot, traffic and link' +
        (pageErrors.length ? ': ' + pageErrors.join(' | ') : ''));
} catch (e) {
  check(false, 'the test ran: ' + e.message);
} finally {
  await browser.close();
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);

// The page's point controls (docs/web.md, "Points"): the Points group is open with the switch, the
// budget, the radius and the colour first; the budget bounds the points a frame draws (the frame's
// pointsDrawn: every visible point under the default budget, at most 1000 under a 1000 budget).
async function pointControlsStep(page, check, setControl) {
  const group = await page.evaluate(() => {
    const d = [...document.querySelectorAll('#settings details')].find((e) => e.querySelector('summary').textContent.startsWith('Points'));
    return d ? { open: d.open, first: [...d.querySelectorAll('input, select')].slice(0, 4).map((e) => e.id) } : { open: false, first: [] };
  });
  check(group.open && group.first.join(',') === 'points,point-budget,point-radius,point-color',
        `the Points group is open, its first controls ${group.first.join(', ')}`);
  const drawnAfterChange = async () => {
    await page.waitForFunction(() => hv.status && hv.status.frames > window.framesAtChange && hv.status.converged &&
                               !hv.status.focusing, null, { timeout: 60000, polling: 250 });
    return page.evaluate(() => hv.status.pointsDrawn);
  };
  const budget = await page.evaluate(() => document.getElementById('point-budget').value);
  await setControl('points', true);
  const all = await drawnAfterChange();
  await setControl('point-budget', '1000');
  const few = await drawnAfterChange();
  await setControl('point-budget', budget);
  const again = await drawnAfterChange();
  console.log(`points drawn: ${all} (budget ${budget}), ${few} (budget 1000), ${again} (budget ${budget} again)`);
  check(all > 1000 && few > 0 && few <= 1000 && again === all, 'the point budget bounds the points a frame draws');
}

// The map's zoom and pan (web/map.js; hv/viewer/map_overview.h's MapZoom): four wheel notches
// (deltaY -400) on a dot double the scale about it, a drag moves the map with the pointer and goes
// nowhere, a click on the dot where it is now goes to that photograph, "whole map" shows it all.
async function mapZoomPanStep(page, check) {
  await page.evaluate(() => hv.mapWhole());
  const m = await page.evaluate(() => hv.map());
  const W = await page.evaluate(() => document.getElementById('map').width);
  await page.locator('#map').scrollIntoViewIfNeeded();
  const box = await page.locator('#map').boundingBox(), scale = box.width / W;
  // The dot farthest from the others, then a page pixel (integer) on it.
  const gap = (d) => Math.min(...m.dots.filter((e) => e !== d).map((e) => Math.hypot(d.x - e.x, d.y - e.y)));
  const dot = m.dots.reduce((a, b) => (gap(b) > gap(a) ? b : a));
  const px = Math.round(box.x + dot.x * scale), py = Math.round(box.y + dot.y * scale);
  const under = [(px - box.x) / scale, (py - box.y) / scale];  // canvas pixel under the pointer
  await page.mouse.move(px, py);
  await page.mouse.wheel(0, -400);
  await page.waitForFunction(() => hv.map().zoom.zoom !== 1, null, { timeout: 10000, polling: 100 });
  const z = (await page.evaluate(() => hv.map())).zoom;
  const at = (zz, d) => [zz.zoom * d.x + zz.tx, zz.zoom * d.y + zz.ty];
  // The point under the pointer stays there along the side the whole map fills; along the other
  // the map is kept on its extent (MapZoom's limits) and may shift.
  const moved = at(z, { x: under[0], y: under[1] }).map((v, k) => v - under[k]);
  console.log(`map wheel: zoom ${z.zoom.toFixed(4)}, the point under the pointer moved ${moved.map((v) => v.toFixed(3)).join(', ')} px`);
  check(Math.abs(z.zoom - 2) < 1e-9 && Math.min(...moved.map(Math.abs)) < 0.1, 'the wheel zooms the map about the pointer');
  // The drag: 30 and 20 page pixels away from the map's centre (the side the map can pan to).
  const [dx, dy] = [dot.x >= W / 2 ? 30 : -30, dot.y >= W / 2 ? 20 : -20];
  const poseBefore = await page.evaluate(() => hv.pose());
  await page.mouse.down();
  await page.mouse.move(px + dx, py + dy, { steps: 10 });
  await page.mouse.up();
  const zd = (await page.evaluate(() => hv.map())).zoom;
  const shift = [zd.tx - z.tx, zd.ty - z.ty], drag = [dx / scale, dy / scale];
  console.log(`map drag of ${drag.map((v) => v.toFixed(1)).join(', ')} canvas px: the map moved ${shift.map((v) => v.toFixed(1)).join(', ')}`);
  check(zd.zoom === z.zoom && Math.hypot(...shift) > 5 &&
        shift.every((s, k) => s * drag[k] >= 0 && Math.abs(s) <= Math.abs(drag[k]) + 0.5) &&
        await page.evaluate(() => hv.pose()) === poseBefore, 'a drag pans the map and goes nowhere');
  // A click on the dot where it is now.
  const [cx, cy] = at(zd, dot);
  await page.mouse.click(box.x + cx * scale, box.y + cy * scale);
  const chosen = await page.evaluate(() => hv.viewer.focused());
  check(chosen === dot.photo, `a click on the zoomed map goes to the photograph there (${dot.id})`);
  await page.click('#map-box button');
  const whole = (await page.evaluate(() => hv.map())).zoom;
  check(whole.zoom === 1 && whole.tx === 0 && whole.ty === 0, '"whole map" shows the whole map again');
}

// The photographs' thumbnails (web/histoview.js, addThumbnail): every photograph in the list has
// one, 96 pixels wide, of its photograph's aspect ratio (cameras.json's width and height), and not
// blank (its grey levels spread over more than 16 levels).
async function thumbnailsStep(page, check) {
  const t = await page.evaluate(async () => {
    const cams = (await (await fetch('cameras.json')).json()).cameras;
    const items = [...document.querySelectorAll('#photos li')];
    const ok = items.map((li) => {
      const c = li.querySelector('canvas');
      if (!c || c.width !== 96) return false;
      const cam = cams[+li.dataset.index];
      if (cam && Math.abs(c.height - Math.round(96 * cam.height / cam.width)) > 1) return false;
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      let lo = 255, hi = 0;
      for (let k = 0; k < d.length; k += 4) { const g = (d[k] + d[k + 1] + d[k + 2]) / 3; lo = Math.min(lo, g); hi = Math.max(hi, g); }
      return hi - lo > 16;
    });
    return { items: items.length, ok: ok.filter(Boolean).length };
  });
  console.log(`thumbnails: ${t.ok} of ${t.items} photographs`);
  check(t.items > 0 && t.ok === t.items, 'every photograph in the list has its thumbnail');
}
