// The page's map (docs/web.md, "The page"; the desktop viewer's M panel, docs/viewer.md): a 2D
// overview of the scene in its ground plane, north up — the terrain's hillshade, the buildings'
// footprints, every photograph as a dot with its viewing direction (dated ones orange, undated
// ones blue), the view as a red triangle along its heading. The map itself is computed in the
// WebAssembly module (hv/viewer/map_overview.h, viewer.mapData): this file only draws it in a 2D
// canvas and passes clicks back (viewer.mapClick: a dot goes to that photograph, focus + context;
// elsewhere the view flies to the ground there, its heading kept). histoview.js calls
// window.hvBuildMap once the scene is loaded, then ui.update() every frame.
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

    // What does not move, drawn once: background, hillshade, footprints, outlines.
    const base = document.createElement('canvas');
    base.width = W;
    base.height = H;
    const g = base.getContext('2d');
    g.fillStyle = '#2a2c30';
    g.fillRect(0, 0, W, H);
    const s = data.hillshade;
    if (s) {
      const raster = document.createElement('canvas');
      raster.width = s.width;
      raster.height = s.height;
      const img = new ImageData(s.width, s.height);
      for (let i = 0; i < s.grey.length; ++i) {
        img.data[4 * i] = img.data[4 * i + 1] = img.data[4 * i + 2] = s.grey[i];
        img.data[4 * i + 3] = s.alpha[i];
      }
      raster.getContext('2d').putImageData(img, 0, 0);
      g.drawImage(raster, s.lo[0], s.lo[1], s.hi[0] - s.lo[0], s.hi[1] - s.lo[1]);
    }
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
    g.lineWidth = 1;
    g.beginPath();
    const o = data.outlines;
    for (let i = 0; i + 3 < o.length; i += 4) {
      g.moveTo(o[i], o[i + 1]);
      g.lineTo(o[i + 2], o[i + 3]);
    }
    g.stroke();

    const ctx = canvas.getContext('2d');
    let last = '';
    ui.update = (force) => {
      const view = viewer.mapView(W, H), chosen = viewer.focused();
      const key = view + ' ' + chosen;
      if (key === last && !force) return;
      last = key;
      ctx.drawImage(base, 0, 0);
      for (const d of data.dots) {
        ctx.strokeStyle = ctx.fillStyle = d.dated ? DATED : UNDATED;
        ctx.lineWidth = 1.5;
        ctx.beginPath();
        ctx.moveTo(d.x, d.y);
        ctx.lineTo(d.x + 10 * d.dx, d.y + 10 * d.dy);
        ctx.stroke();
        ctx.beginPath();
        ctx.arc(d.x, d.y, 3.5, 0, 2 * Math.PI);
        ctx.fill();
        if (d.photo === chosen) {
          ctx.strokeStyle = CHOSEN;
          ctx.beginPath();
          ctx.arc(d.x, d.y, 6.5, 0, 2 * Math.PI);
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
    canvas.addEventListener('click', (e) => {
      const rect = canvas.getBoundingClientRect();
      click((e.clientX - rect.left) * W / rect.width, (e.clientY - rect.top) * H / rect.height);
    });
    ui.click = click;
    ui.toggle = () => { box.hidden = !box.hidden; };
    ui.update(true);
    return ui;
  };
})();
