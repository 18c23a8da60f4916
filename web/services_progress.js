// What the page has read of each source, and what is missing (docs/services.md, "In the browser"
// and "What is missing"). Loaded before services.js and histoview.js, which make one tracker per
// page (create) and feed it as the answers arrive:
//   progress  an object per source ("buildings", "terrain", "cameras", "points", "orthophoto",
//             "photographs"): its counts so far, `text` (e.g. "WFS page 2, 1,000 features",
//             "WCS grid 99×55", "5 of 12 previews, 0 of 12 full", "12 of 60 tiles") and `done`;
//   missing   what was asked for and could not be read, as natively (hv/scene/missing_sources.h):
//             {kind, location, reason}, one entry per kind and location, in the order first
//             recorded, a reason without the location it starts with;
// and writes both into the status panel's #sources: a line per source while loading, one line for
// all once loaded, and the missing list (with its summary) while anything is missing.
// window.hv.progress and window.hv.missing are these two (histoview.js).
'use strict';

window.hvServiceProgress = (() => {
  const n = (v) => (v || 0).toLocaleString('en');
  const plural = (k, one, many) => `${n(k)} ${k === 1 ? one : many}`;
  // The text of a source from its counts.
  const texts = {
    buildings: (s) => `${s.service} page ${s.pages}, ${plural(s.features, 'feature', 'features')}`,
    cameras: (s) => (s.service ? `${s.service} page ${s.pages}, ` : 'cameras file, ') + plural(s.features, 'camera', 'cameras'),
    terrain: (s) => (s.cols ? `WCS grid ${s.cols}×${s.rows}` : 'WCS asked'),
    points: (s) => `${s.tiles} of ${s.of} tiles` + (s.failed ? `, ${s.failed} failed` : '') +
                   (s.count !== undefined ? `, ${n(s.count)} points` : ''),
    orthophoto: (s) => `${s.tiles} of ${s.of} tiles` + (s.failed ? `, ${s.failed} failed` : '') +
                       (s.width ? `, ${s.width}×${s.height} px` : ''),
    photographs: (s) => (s.previewsOf ? `${s.previews} of ${s.previewsOf} previews, ${s.full} of ${s.of} full`
                                      : `${s.full} of ${s.of}`) + (s.failed ? `, ${s.failed} failed` : ''),
  };

  // describeMissing (hv/scene/missing_sources.h): "location: reason".
  const describe = (m) => (m.location ? m.location + ': ' + m.reason : m.reason);

  // A tracker writing into `box` (an element, or null: counts only).
  function create(box) {
    const progress = {}, missing = [];
    let loaded = false;
    const t = {
      progress, missing,
      // Updates the counts of `source` (and its text); `done`: nothing more will come.
      set(source, fields) {
        const s = progress[source] = Object.assign(progress[source] || { done: false }, fields);
        s.text = s.failed === true ? 'left out' : (texts[source] || ((x) => x.text || ''))(s);
        t.show();
        return s;
      },
      // Records what could not be read; an entry of the same kind and location is replaced.
      add(kind, location, reason) {
        let r = String(reason);
        if (location && r.startsWith(location + ': ')) r = r.slice(location.length + 2);
        const entry = { kind, location: location || '', reason: r };
        const at = missing.findIndex((m) => m.kind === kind && m.location === entry.location);
        if (at >= 0) missing[at] = entry; else missing.push(entry);
        t.show();
      },
      // MissingSources::lines: "kind: location: reason".
      lines: () => missing.map((m) => m.kind + ': ' + describe(m)),
      // MissingSources::summary: "missing: buildings (WFS:http://…), 2 photographs"; '' when none.
      summary() {
        if (!missing.length) return '';
        const kinds = [...new Set(missing.map((m) => m.kind))];
        return 'missing: ' + kinds.map((k) => {
          const of = missing.filter((m) => m.kind === k);
          return of.length === 1 ? k + (of[0].location ? ` (${of[0].location})` : '') : `${of.length} ${k}s`;
        }).join(', ');
      },
      // The module's errors reading the scene: a camera layer's page it could not read (named by
      // its URL, one of `urls`) leaves cameras missing.
      cameraLayerErrors(errors, urls) {
        for (const line of errors && urls ? errors.trim().split('\n') : []) {
          const url = urls.find((u) => line.includes(u));
          if (url) t.add('cameras', url, line.slice(line.indexOf(url)));
        }
      },
      // Once loaded: one line for all the sources.
      finish() {
        loaded = true;
        t.show();
      },
      text() {
        const names = Object.keys(progress);
        let out = !names.length ? '' : loaded ? 'sources: ' + names.map((k) => `${k} ${progress[k].text}`).join('; ')
                                             : 'sources\n' + names.map((k) => `${k}: ${progress[k].text}`).join('\n');
        if (missing.length) out += (out ? '\n' : '') + t.summary() + '\n' + t.lines().map((l) => '  ' + l).join('\n');
        return out;
      },
      show() {
        if (!box) return;
        box.textContent = t.text();
        box.hidden = !box.textContent;
      },
    };
    return t;
  }

  // The columns and rows of an ESRI ASCII grid's header (the WCS answer), or null.
  function gridSize(text) {
    const c = /^\s*ncols\s+(\d+)/im.exec(text), r = /^\s*nrows\s+(\d+)/im.exec(text);
    return c && r ? { cols: +c[1], rows: +r[1] } : null;
  }

  return { create, gridSize };
})();
