// The page's map (docs/web.md, "The page"; the desktop viewer's M panel, docs/viewer.md): a 2D
// overview of the scene in its ground plane, north up — the terrain's hillshade, the buildings'
// footprints, every photograph as a dot with its viewing direction (dated ones orange, undated
// ones blue), the view as a red triangle along its heading. The map itself is computed in the
// WebAssembly module (hv/viewer/map_overview.h, viewer.mapData): this file only draws it in a 2D
// canvas and passes clicks back (viewer.mapClick: a dot goes to that photograph, focus + context;
// elsewhere the view flies to the ground there, its heading kept). The wheel zooms about the
// pointer, a drag pans, "whole map" goes back to the whole extent: the zoom lives in the module
// (viewer.mapZoomAt, mapPan, mapWhole: hv/viewer/map_overview.h's MapZoom, as the desktop map's),
// which returns the zoomed canvas's pixels from mapData's: zoomed = zoom * whole + (tx, ty).
// A click is a release without a drag. histoview.js calls window.hvBuildMap once the scene is
// loaded, then ui.update() every frame.
'use strict';

(function () {
  const DATED = '#f0a028', UNDATED = '#78aae6', VIEW = '#e62828', CHOSEN = '#00e6e6';

  window.hvBuildMap = function (viewer, onClick) {
    const box = document.getElementById('map-box'), canvas = document.getElementById('map');
    const ui = { update() {}, toggle() {}, data: null };
    if (!box || !canvas) return ui;
    const W = canvas.width, H = canvas.height;
    const data = ui.data = JSON.parse(viewer.mapData(W, H));
    if (!data.dots) return ui;
    box.hidden = false;

    // The hillshade as an image, made once.
    const s = data.hillshade;
    let raster = null;
    if (s) {
      raster = document.createElement('canvas');
      raster.width = s.width;
      raster.height = s.height;
      const img = new ImageData(s.width, s.height);
      for (let i = 0; i < s.grey.length; ++i) {
        img.data[4 * i] = img.data[4 * i + 1] = img.data[4 * i + 2] = s.grey[i];
        img.data[4 * i + 3] = s.alpha[i];
      }
      raster.getContext('2d').putImageData(img, 0, 0);
    }
    // What does not move with the view, drawn again when the zoom changes: background, hillshade,
    // footprints, outlines, in mapData's pixels through the zoom's transform.
    let zoom = { zoom: 1, tx: 0, ty: 0 };
    const toCanvas = (x, y) => [zoom.zoom * x + zoom.tx, zoom.zoom * y + zoom.ty];
    const base = document.createElement('canvas');
    base.width = W;
    base.height = H;
    const g = base.getContext('2d');
    const drawBase = () => {
      g.setTransform(1, 0, 0, 1, 0, 0);
      g.fillStyle = '#2a2c30';
      g.fillRect(0, 0, W, H);
      g.setTransform(zoom.zoom, 0, 0, zoom.zoom, zoom.tx, zoom.ty);
      if (raster) g.drawImage(raster, s.lo[0], s.lo[1], s.hi[0] - s.lo[0], s.hi[1] - s.lo[1]);
      g.fillStyle = 'rgba(150, 140, 130, 0.8)';
      const f = data.footprints;
      for (let i = 0; i + 5 < f.length; i += 6) {
        g.beginPath();
        g.moveTo(f[i], f[i + 1]);
        g.lineTo(f[i + 2], f[i + 3]);
        g.lineTo(f[i + 4], f[i + 5]);
        g.closePath();
        g.fill();
      }
      g.strokeStyle = '#281e19';
      g.lineWidth = 1 / zoom.zoom;
      g.beginPath();
      const o = data.outlines;
      for (let i = 0; i + 3 < o.length; i += 4) {
        g.moveTo(o[i], o[i + 1]);
        g.lineTo(o[i + 2], o[i + 3]);
      }
      g.stroke();
    };
    drawBase();

    const ctx = canvas.getContext('2d');
    let last = '';
    ui.update = (force) => {
      const view = viewer.mapView(W, H), chosen = viewer.focused();
      const key = view + ' ' + chosen;
      if (key === last && !force) return;
      last = key;
      ctx.drawImage(base, 0, 0);
      for (const d of data.dots) {
        const [x, y] = toCanvas(d.x, d.y);
        ctx.strokeStyle = ctx.fillStyle = d.dated ? DATED : UNDATED;
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.moveTo(x, y);
        ctx.lineTo(x + 10 * d.dx, y + 10 * d.dy);
        ctx.stroke();
        ctx.beginPath();
        ctx.arc(x, y, 3.5, 0, 2 * Math.PI);
        ctx.fill();
        if (d.photo === chosen) {
          ctx.strokeStyle = CHOSEN;
          ctx.beginPath();
          ctx.arc(x, y, 6.5, 0, 2 * Math.PI);
          ctx.stroke();
        }
      }
      const v = JSON.parse(view);
      let dx = v.dx, dy = v.dy;
      if (!dx && !dy) dy = -1;
      const at = (fwd, side) => [v.x + fwd * dx - side * dy, v.y + fwd * dy + side * dx];
      ctx.fillStyle = VIEW;
      ctx.beginPath();
      ctx.moveTo(...at(11, 0));
      ctx.lineTo(...at(-5, 6));
      ctx.lineTo(...at(-5, -6));
      ctx.closePath();
      ctx.fill();
    };
    // A click in canvas pixels (the canvas may be shown scaled).
    const click = (x, y) => {
      const r = JSON.parse(viewer.mapClick(x, y, W, H));
      ui.update(true);
      if (onClick) onClick(r);
      return r;
    };
    const setZoom = (json) => {
      zoom = JSON.parse(json);
      drawBase();
      ui.update(true);
      return zoom;
    };
    const canvasPx = (e) => {
      const rect = canvas.getBoundingClientRect();
      return [(e.clientX - rect.left) * W / rect.width, (e.clientY - rect.top) * H / rect.height];
    };
    // The wheel: 2^(1/4) a notch (hv::viewer::wheelZoomFactor), a notch being 100 pixels or 3 lines.
    canvas.addEventListener('wheel', (e) => {
      e.preventDefault();
      const notches = -e.deltaY / (e.deltaMode === 1 ? 3 : e.deltaMode === 2 ? 0.3 : 100);
      setZoom(viewer.mapZoomAt(...canvasPx(e), Math.pow(2, notches / 4), W, H));
    }, { passive: false });
    // A drag pans; a release within 3 pixels of the press is a click.
    let press = null;
    canvas.addEventListener('pointerdown', (e) => {
      if (e.button !== 0) return;
      press = { at: canvasPx(e), last: canvasPx(e), moved: 0 };
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener('pointermove', (e) => {
      if (!press) return;
      const p = canvasPx(e);
      press.moved = Math.max(press.moved, Math.hypot(p[0] - press.at[0], p[1] - press.at[1]));
      setZoom(viewer.mapPan(p[0] - press.last[0], p[1] - press.last[1], W, H));
      press.last = p;
    });
    canvas.addEventListener('pointerup', (e) => {
      if (!press) return;
      const moved = press.moved;
      press = null;
      if (moved < 3) click(...canvasPx(e));
    });
    canvas.addEventListener('pointercancel', () => { press = null; });
    const whole = document.createElement('button');
    whole.textContent = 'whole map';
    whole.title = 'the whole scene again (the wheel zooms, a drag pans)';
    whole.addEventListener('click', () => setZoom(viewer.mapWhole(W, H)));
    canvas.after(whole);
    ui.click = click;
    ui.zoomAt = (x, y, factor) => setZoom(viewer.mapZoomAt(x, y, factor, W, H));
    ui.pan = (dx, dy) => setZoom(viewer.mapPan(dx, dy, W, H));
    ui.whole = () => setZoom(viewer.mapWhole(W, H));
    ui.zoom = () => zoom;
    ui.toggle = () => { box.hidden = !box.hidden; };
    ui.update(true);
    return ui;
  };
})();
