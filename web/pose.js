// The page's pose mode (docs/pose.md, "In the browser"; the desktop viewer's, docs/viewer.md):
// the chosen photograph in a canvas beside the view; a click on it, then a click on the same
// point in the view, makes a pair (the view's point is picked from the renderer's own depth,
// WebViewer::pickView: the browser has no ray caster). From 4 pairs (6 with the focal solved) the
// photograph's camera is solved at each change (hv/pose/pose_session.h: RANSAC + Levenberg–Marquardt,
// the native code) and put into the scene, so the view shows the photograph projected from it;
// each pair's residual is drawn on the photograph (yellow, red for an outlier) from the clicked
// pixel to where the solved camera puts its point. Drag a point to move it, shift-click it (or ×
// in the list) to remove it. "Look from it" is then and now at the solved camera, faded by the
// opacity slider; "save" downloads the camera as a native cameras.json. Leaving puts the scene's
// camera back unless it was saved.
// For scripts and tests: window.hv.poseStart(i, solveFocal), hv.poseState(), hv.pickView(x, y),
// hv.poseProjectOriginal(x, y, z), hv.poseSave(), hv.poseLeave(), hv.poseMapPhoto(u, v) (client
// coordinates of a photograph pixel, for synthetic clicks).
'use strict';

(() => {
  const PHOTO_WIDTH = 480;  // CSS pixels of the photograph's canvas (at least its pixels: see poseMapPhoto)
  const GRAB_PX = 8;         // CSS pixels: a press this near a point drags it
  const CLICK_PX = 3;        // CSS pixels: a press and release this near is a click, not a look

  window.addEventListener('histoview-ready', (e) => build(e.detail));

  function el(tag, props, parent) {
    const n = Object.assign(document.createElement(tag), props || {});
    if (parent) parent.appendChild(n);
    return n;
  }

  function build({ viewer, FS, canvas, thenNow, width, height }) {
    const hv = window.hv;
    // The panel's part.
    const box = el('fieldset', { id: 'pose-box' });
    el('legend', { textContent: 'Pose a photograph' }, box);
    el('p', { className: 'hint', textContent: 'choose a photograph, then pose: click a point on it, then the same ' +
      'point in the view (4 pairs, 6 with the focal)' }, box);
    const start = el('button', { id: 'pose-start', type: 'button', textContent: 'pose the chosen photograph' }, box);
    const focalLabel = el('label', {}, box);
    const focal = el('input', { id: 'pose-focal', type: 'checkbox' }, focalLabel);
    focalLabel.append(' solve the focal (6 pairs)');
    const look = el('button', { id: 'pose-look', type: 'button', textContent: 'look from it', disabled: true }, box);
    const save = el('button', { id: 'pose-save', type: 'button', textContent: 'save cameras.json', disabled: true }, box);
    const opacityLabel = el('label', {}, box);
    opacityLabel.append('opacity ');
    const opacity = el('input', { id: 'pose-opacity', type: 'range', min: 0, max: 1, step: 0.01, value: 0.6 }, opacityLabel);
    const message = el('div', { id: 'pose-message', className: 'hint' }, box);
    const list = el('ol', { id: 'pose-pairs' }, box);
    const panel = document.getElementById('panel');
    panel.insertBefore(box, panel.querySelector('#status'));

    // The photograph, beside the view.
    const side = el('div', { id: 'pose-side', hidden: true });
    const photoCanvas = el('canvas', { id: 'pose-photo' }, side);
    document.getElementById('stage').after(side);
    const ctx = photoCanvas.getContext('2d');
    const img = new Image();
    let url = null, state = { on: false }, drag = null;

    const call = (text) => {
      const s = JSON.parse(text);
      if (s.error) { message.textContent = s.error; return state; }
      state = s;
      render();
      return s;
    };
    // Photograph pixels <-> client coordinates of its canvas.
    const scale = () => photoCanvas.getBoundingClientRect().width / Math.max(1, state.width || 1);
    const toPhoto = (ev) => {
      const r = photoCanvas.getBoundingClientRect();
      return [(ev.clientX - r.left) / scale(), (ev.clientY - r.top) / scale()];
    };
    const nearest = (u, v) => {
      let best = -1, bestD = GRAB_PX / scale();
      (state.pairs || []).forEach((p, i) => {
        const d = Math.hypot(p.u - u, p.v - v);
        if (d <= bestD) { best = i; bestD = d; }
      });
      return best;
    };

    function render() {
      const on = !!state.on;
      side.hidden = !on;
      start.textContent = on ? 'leave pose mode' : 'pose the chosen photograph';
      look.disabled = save.disabled = !(on && state.solved);
      if (!on) { list.textContent = ''; message.textContent = state.message || ''; return; }
      const rms = state.solved ? ` — ${state.rms.toFixed(2)} px RMS, ${state.inliers}/${state.pairs.length} inliers` : '';
      message.textContent = state.message + (state.saved ? ' (saved)' : '') + (state.solved ? rms : '');
      focal.checked = state.solveFocal;
      list.textContent = '';
      state.pairs.forEach((p, i) => {
        const li = el('li', { className: p.inlier === false ? 'outlier' : '' }, list);
        li.append(`(${p.u.toFixed(1)}, ${p.v.toFixed(1)})` + (p.residual !== undefined ? ` ${p.residual.toFixed(2)} px` : '') + ' ');
        const x = el('button', { type: 'button', textContent: '×', title: 'remove this pair' }, li);
        x.addEventListener('click', () => call(viewer.poseRemovePair(i)));
      });
      draw();
    }

    function draw() {
      if (!state.on) return;
      const s = scale() || 1;  // line widths in CSS pixels whatever the photograph's size
      ctx.clearRect(0, 0, photoCanvas.width, photoCanvas.height);
      if (img.complete && img.naturalWidth) ctx.drawImage(img, 0, 0, photoCanvas.width, photoCanvas.height);
      ctx.lineWidth = 1.5 / s;
      ctx.font = `${12 / s}px system-ui, sans-serif`;
      state.pairs.forEach((p, i) => {
        const at = drag && drag.index === i ? drag.to : [p.u, p.v];
        if (p.pu !== undefined && !(drag && drag.index === i)) {
          ctx.strokeStyle = p.inlier ? '#fd3' : '#f33';
          ctx.beginPath();
          ctx.moveTo(p.u, p.v);
          ctx.lineTo(p.pu, p.pv);
          ctx.stroke();
        }
        ctx.strokeStyle = p.inlier === false ? '#f33' : '#3cf';
        ctx.beginPath();
        ctx.arc(at[0], at[1], 5 / s, 0, 2 * Math.PI);
        ctx.stroke();
        ctx.fillStyle = '#fff';
        ctx.fillText(String(i + 1), at[0] + 6 / s, at[1] - 6 / s);
      });
      if (state.pending) {
        const [u, v] = state.pending, r = 7 / s;
        ctx.strokeStyle = '#f0f';
        ctx.beginPath();
        ctx.moveTo(u - r, v); ctx.lineTo(u + r, v); ctx.moveTo(u, v - r); ctx.lineTo(u, v + r);
        ctx.stroke();
      }
    }

    function enter() {
      const s = call(viewer.poseStart(viewer.focused(), focal.checked));
      if (!s.on) return;
      photoCanvas.width = s.width;
      photoCanvas.height = s.height;
      // At least the photograph's own pixels on the page (so a click's position is not coarser
      // than a pixel), at most twice the usual width.
      photoCanvas.style.width = Math.max(PHOTO_WIDTH, s.width) + 'px';
      if (url) URL.revokeObjectURL(url);
      url = URL.createObjectURL(new Blob([FS.readFile(s.image)]));
      img.onload = draw;
      img.src = url;
      render();
    }
    function leave() {
      viewer.poseLeave();
      state = { on: false, message: '' };
      render();
    }
    start.addEventListener('click', () => (state.on ? leave() : enter()));
    focal.addEventListener('change', () => { if (state.on) call(viewer.poseSetSolveFocal(focal.checked)); });
    // Look from the solved camera: then and now at it (the scene holds it now), faded by the slider.
    const thenNowOpacity = document.getElementById('then-now-opacity');
    const fade = () => { thenNowOpacity.value = opacity.value; thenNowOpacity.dispatchEvent(new Event('input')); };
    opacity.addEventListener('input', fade);
    look.addEventListener('click', () => {
      if (!state.solved) return;
      fade();
      const err = thenNow.set(true);
      if (err) message.textContent = err;
    });
    save.addEventListener('click', () => {
      const text = viewer.poseSave();
      if (text.startsWith('{"error"')) { message.textContent = JSON.parse(text).error; return; }
      const a = el('a', { href: URL.createObjectURL(new Blob([text], { type: 'application/json' })),
                          download: `${state.id}.cameras.json` }, document.body);
      a.click();
      a.remove();
      call(viewer.poseState());
    });

    // On the photograph: press near a point to drag it, elsewhere to click (shift: remove).
    photoCanvas.addEventListener('pointerdown', (ev) => {
      if (!state.on) return;
      const [u, v] = toPhoto(ev);
      const i = nearest(u, v);
      if (i >= 0 && ev.shiftKey) { call(viewer.poseRemovePair(i)); return; }
      if (i >= 0) {
        drag = { index: i, to: [u, v] };
        photoCanvas.setPointerCapture(ev.pointerId);
        return;
      }
      call(viewer.poseClickPhoto(u, v));
    });
    photoCanvas.addEventListener('pointermove', (ev) => {
      if (!drag) return;
      drag.to = toPhoto(ev);
      draw();
    });
    photoCanvas.addEventListener('pointerup', (ev) => {
      if (!drag) return;
      const d = drag;
      drag = null;
      const [u, v] = toPhoto(ev);
      call(viewer.poseMovePair(d.index, u, v));
    });

    // On the view: a click (not a look) while a photograph pixel waits makes the pair.
    let down = null;
    canvas.addEventListener('pointerdown', (ev) => { down = [ev.clientX, ev.clientY]; });
    canvas.addEventListener('pointerup', (ev) => {
      if (!down || !state.on) return;
      const moved = Math.hypot(ev.clientX - down[0], ev.clientY - down[1]);
      down = null;
      if (moved > CLICK_PX || state.step !== 'view') return;
      const r = canvas.getBoundingClientRect();
      const x = (ev.clientX - r.left) * width / r.width, y = (ev.clientY - r.top) * height / r.height;
      call(viewer.poseClickView(x, y));
    });

    // For scripts and tests.
    hv.poseStart = (i, solveFocal) => {
      if (i !== undefined) viewer.focusPhoto(i);
      focal.checked = !!solveFocal;
      if (state.on) leave();
      enter();
      return state;
    };
    hv.poseState = () => JSON.parse(viewer.poseState());
    hv.pickView = (x, y) => JSON.parse(viewer.pickView(x, y));
    hv.poseProjectOriginal = (x, y, z) => JSON.parse(viewer.poseProjectOriginal(x, y, z));
    hv.poseSave = () => { const t = viewer.poseSave(); call(viewer.poseState()); return t; };
    hv.poseLeave = leave;
    hv.poseMapPhoto = (u, v) => {
      const r = photoCanvas.getBoundingClientRect();
      return [r.left + u * scale(), r.top + v * scale()];
    };
  }
})();
