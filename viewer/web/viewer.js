// aslam-viewer page: live / replay view of the Active SLAM stack.
//
// Protocol: viewer/protocol.md. Server -> page JSON frames (hello, update, control_result);
// page -> server text frames ("control COMMAND [TOKEN]", "seek T_S").
//
// Security: nothing received is ever executed or parsed as markup. Every server-provided text
// goes through textContent / createTextNode; numbers are formatted here; colours and CSS
// classes are chosen by the page from fixed lists.
'use strict';

(function () {
  // ------------------------------------------------------------------ helpers

  const $ = (id) => document.getElementById(id);
  const isNum = (v) => typeof v === 'number' && Number.isFinite(v);
  const DASH = '\u2013';

  function fmtFixed(v, d) { return isNum(v) ? v.toFixed(d) : DASH; }
  function fmtInt(v) { return isNum(v) ? String(Math.round(v)) : DASH; }
  function fmtAuto(v) {
    if (!isNum(v)) return DASH;
    const a = Math.abs(v);
    if (a !== 0 && (a >= 1e6 || a < 1e-3)) return v.toExponential(2);
    if (a >= 1000) return v.toFixed(0);
    if (a >= 100) return v.toFixed(1);
    if (a >= 10) return v.toFixed(2);
    return v.toFixed(3);
  }
  // Identifiers and words from the server: shown as plain text, never interpreted.
  function str(v) {
    if (v === null || v === undefined) return '';
    if (typeof v === 'string') return v;
    if (typeof v === 'number') return isNum(v) ? String(v) : DASH;
    if (typeof v === 'boolean') return v ? 'true' : 'false';
    return String(v);
  }
  function strOrDash(v) { const s = str(v); return s === '' ? DASH : s; }
  function setText(id, text) {
    const el = typeof id === 'string' ? $(id) : id;
    if (el && el.textContent !== text) el.textContent = text;
  }
  function td(text, cls) {
    const el = document.createElement('td');
    el.textContent = text;
    if (cls) el.className = cls;
    return el;
  }
  function isPt(p) { return Array.isArray(p) && p.length >= 2 && isNum(p[0]) && isNum(p[1]); }
  function pts(a) {
    const out = [];
    if (!Array.isArray(a)) return out;
    for (let i = 0; i < a.length; i++) if (isPt(a[i])) out.push(a[i]);
    return out;
  }
  function b64ToBytes(s) {
    const bin = atob(s);
    const n = bin.length;
    const out = new Uint8Array(n);
    for (let i = 0; i < n; i++) out[i] = bin.charCodeAt(i);
    return out;
  }
  // Map tiles arrive zlib-compressed (viewer/protocol.md): the browser's own inflater.
  async function inflate(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate'));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }
  // Decodes an update's tiles into t.bytes before the frame is applied.
  async function inflateTiles(msg) {
    const m = msg && msg.type === 'update' ? msg.map : null;
    if (!m || !Array.isArray(m.tiles)) return;
    await Promise.all(m.tiles.map(async (t) => {
      if (t && typeof t.cells === 'string') {
        try { t.bytes = await inflate(b64ToBytes(t.cells)); } catch (e) { t.bytes = null; }
      }
    }));
  }
  function fmtSeek(t) { return String(Math.round(t * 1000) / 1000); }

  // ------------------------------------------------------------------ test hook

  const api = { frames: 0, lastFrontierCount: 0, connected: false, mode: null, t_s: null };
  window.aslamViewer = api;

  // ------------------------------------------------------------------ state

  const TRAIL_MAX = 200000;
  const SERIES_MAX = 200000;

  const S = {
    mode: null,            // "live" | "replay"
    control: false,
    tokenRequired: false,
    replay: null,          // {start, end}
    tS: null,
    map: null,             // grid, see makeGrid()
    pose: null,            // {x, y, yaw}
    trail: [],
    scan: [],
    graph: { nodes: [], edges: [] },
    frontiers: [],
    scores: null,
    scoreById: new Map(),
    chosenId: null,
    ramp: null,            // {min, max} of eligible finite totals
    nav: {},
    explore: {},
    series: [],
    processes: [],
  };

  function resetWorld() {
    S.map = null;
    S.pose = null;
    S.trail = [];
    S.scan = [];
    S.graph = { nodes: [], edges: [] };
    S.frontiers = [];
    S.scores = null;
    S.scoreById = new Map();
    S.chosenId = null;
    S.ramp = null;
    S.nav = {};
    S.explore = {};
    S.series = [];
    S.processes = [];
    S.tS = null;
    api.lastFrontierCount = 0;
    api.t_s = null;
    hover.idx = -1;
    hover.tableIdx = -1;
    hideTooltip();
    renderFrontierTable();
    renderExplore();
    renderNav();
    renderProcesses();
    renderTime();
    invalidate('map', 'charts');
  }

  // ------------------------------------------------------------------ occupancy grid

  // Colour lookup: byte 255 (and anything > 100) = unknown, mid grey; 0..100 = occupancy %,
  // white (free) to black (occupied). Built through a byte buffer so it is endian-agnostic.
  const UNKNOWN_GREY = 128;
  const LUT32 = (function () {
    const b = new Uint8ClampedArray(256 * 4);
    for (let v = 0; v < 256; v++) {
      const g = v <= 100 ? Math.round(255 - v * 2.55) : UNKNOWN_GREY;
      b[v * 4] = g; b[v * 4 + 1] = g; b[v * 4 + 2] = g; b[v * 4 + 3] = 255;
    }
    return new Uint32Array(b.buffer);
  })();
  const GRID_MAX_DIM = 16384;

  function makeGrid(W, H, res, ox, oy, yaw) {
    const canvas = document.createElement('canvas');
    canvas.width = W;
    canvas.height = H;
    const ctx = canvas.getContext('2d');
    const img = ctx.createImageData(W, H);
    const u32 = new Uint32Array(img.data.buffer, img.data.byteOffset, W * H);
    u32.fill(LUT32[255]);
    ctx.putImageData(img, 0, 0);
    // Image row r = grid row r (row 0 = lowest y); drawn with the y-flipped world transform.
    return { width: W, height: H, res, ox, oy, yaw, revision: null, canvas, ctx, img, u32 };
  }

  function applyMap(m) {
    if (!m || typeof m !== 'object') return;
    const old = S.map;
    const o = (m.origin && typeof m.origin === 'object') ? m.origin : {};
    const W = isNum(m.width) ? Math.round(m.width) : (old ? old.width : 0);
    const H = isNum(m.height) ? Math.round(m.height) : (old ? old.height : 0);
    const res = isNum(m.resolution_m) ? m.resolution_m : (old ? old.res : 0);
    const ox = isNum(o.x_m) ? o.x_m : (old ? old.ox : 0);
    const oy = isNum(o.y_m) ? o.y_m : (old ? old.oy : 0);
    const yaw = isNum(o.yaw_rad) ? o.yaw_rad : (old ? old.yaw : 0);
    if (!(W > 0 && H > 0 && res > 0) || W > GRID_MAX_DIM || H > GRID_MAX_DIM) return;

    let g = old;
    const geomChanged = !g || g.width !== W || g.height !== H || g.res !== res ||
      g.ox !== ox || g.oy !== oy || g.yaw !== yaw;
    if (geomChanged) {
      g = makeGrid(W, H, res, ox, oy, yaw);
      S.map = g;
      // The map grew (same resolution, origin moved by whole cells): keep what we have.
      if (old && m.full !== true && old.res === res && old.yaw === yaw) {
        const dx = Math.round((old.ox - ox) / res), dy = Math.round((old.oy - oy) / res);
        for (let r = 0; r < old.height; r++) {
          const to = r + dy;
          if (to < 0 || to >= H) continue;
          const c0 = Math.max(0, -dx), c1 = Math.min(old.width, W - dx);
          if (c1 > c0) g.u32.set(old.u32.subarray(r * old.width + c0, r * old.width + c1), to * W + c0 + dx);
        }
        g.ctx.putImageData(g.img, 0, 0);
      }
    } else if (m.full === true) {
      g.u32.fill(LUT32[255]);
      g.ctx.putImageData(g.img, 0, 0);
    }
    if (m.revision !== undefined) g.revision = m.revision;

    const box = { x0: Infinity, y0: Infinity, x1: -Infinity, y1: -Infinity };
    if (Array.isArray(m.tiles)) {
      for (const t of m.tiles) applyTile(g, t, box);
    }
    if (box.x1 > box.x0 && box.y1 > box.y0) {
      g.ctx.putImageData(g.img, 0, 0, box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0);
    }
    invalidate('map');
  }

  function applyTile(g, t, box) {
    if (!t || typeof t !== 'object') return;
    const tx = isNum(t.x) ? Math.round(t.x) : 0;
    const ty = isNum(t.y) ? Math.round(t.y) : 0;
    const tw = isNum(t.w) ? Math.round(t.w) : 0;
    const th = isNum(t.h) ? Math.round(t.h) : 0;
    if (tw <= 0 || th <= 0) return;
    const bytes = t.bytes;  // inflated by inflateTiles before the frame was applied
    if (!bytes) return;
    if (bytes.length < tw * th) return;
    const W = g.width, H = g.height, u32 = g.u32;
    const x0 = Math.max(0, tx), x1 = Math.min(W, tx + tw);
    const y0 = Math.max(0, ty), y1 = Math.min(H, ty + th);
    if (x0 >= x1 || y0 >= y1) return;
    for (let gy = y0; gy < y1; gy++) {
      let src = (gy - ty) * tw + (x0 - tx);   // tile row 0 = bottom row of the tile
      let dst = gy * W + x0;
      for (let gx = x0; gx < x1; gx++) u32[dst++] = LUT32[bytes[src++]];
    }
    if (x0 < box.x0) box.x0 = x0;
    if (y0 < box.y0) box.y0 = y0;
    if (x1 > box.x1) box.x1 = x1;
    if (y1 > box.y1) box.y1 = y1;
  }

  // ------------------------------------------------------------------ frontier colours

  // Viridis-like ramp, low (dark violet) to high (yellow).
  const RAMP = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  const GREY = 'rgb(175,175,175)';
  function rampColour(f) {
    f = Math.max(0, Math.min(1, f));
    const x = f * (RAMP.length - 1);
    const i = Math.min(RAMP.length - 2, Math.floor(x));
    const t = x - i;
    const a = RAMP[i], b = RAMP[i + 1];
    return 'rgb(' + Math.round(a[0] + (b[0] - a[0]) * t) + ',' +
      Math.round(a[1] + (b[1] - a[1]) * t) + ',' + Math.round(a[2] + (b[2] - a[2]) * t) + ')';
  }
  function rowFor(f) {
    if (!f || typeof f !== 'object') return undefined;
    return S.scoreById.get(idKey(f.id));
  }
  function idKey(id) { return (typeof id === 'number' || typeof id === 'string') ? String(id) : null; }
  function rowScored(row) { return !!row && row.eligible === true && isNum(row.total); }
  function frontierColour(f) {
    const row = rowFor(f);
    if (!rowScored(row) || !S.ramp) return GREY;
    const span = S.ramp.max - S.ramp.min;
    return rampColour(span > 0 ? (row.total - S.ramp.min) / span : 1);
  }
  function recomputeRamp() {
    let min = Infinity, max = -Infinity;
    for (const f of S.frontiers) {
      const row = rowFor(f);
      if (rowScored(row)) {
        if (row.total < min) min = row.total;
        if (row.total > max) max = row.total;
      }
    }
    S.ramp = min <= max ? { min, max } : null;
  }
  function isChosen(f, row) {
    if (!f || typeof f !== 'object') return false;
    if (S.chosenId !== null) return idKey(f.id) === S.chosenId;
    return !!row && row.chosen === true;
  }
  function frontierTarget(f) {
    if (!f || typeof f !== 'object') return null;
    if (isPt(f.target)) return f.target;
    if (isPt(f.centroid)) return f.centroid;
    return null;
  }

  // ------------------------------------------------------------------ applying frames

  function applyScores(sc) {
    S.scores = (sc && typeof sc === 'object') ? sc : null;
    S.scoreById = new Map();
    S.chosenId = null;
    if (S.scores) {
      if (Array.isArray(S.scores.rows)) {
        for (const r of S.scores.rows) {
          if (!r || typeof r !== 'object') continue;
          const k = idKey(r.frontier_id);
          if (k !== null) S.scoreById.set(k, r);
          if (r.chosen === true && S.chosenId === null && S.scores.chosen_frontier_id == null) S.chosenId = k;
        }
      }
      const c = idKey(S.scores.chosen_frontier_id);
      if (c !== null) S.chosenId = c;
    }
  }

  function chosenMarker() {
    if (S.chosenId === null) return null;
    const row = S.scoreById.get(S.chosenId);
    if (row && isPt(row.target)) return row.target;
    for (const f of S.frontiers) {
      if (f && typeof f === 'object' && idKey(f.id) === S.chosenId) return frontierTarget(f);
    }
    return null;
  }

  function mergeObj(dst, src) {
    if (src === null) return {};
    if (!src || typeof src !== 'object') return dst;
    return Object.assign({}, dst, src);
  }

  function applyUpdate(u) {
    if (u.reset === true) resetWorld();
    if (isNum(u.t_s)) { S.tS = u.t_s; api.t_s = u.t_s; }

    const step = (name, fn) => {
      if (!(name in u)) return;
      try { fn(u[name]); } catch (e) { console.warn('aslam-viewer: bad "' + name + '"', e); }
    };

    step('map', (m) => { if (m === null) { S.map = null; invalidate('map'); } else applyMap(m); });
    step('pose', (p) => {
      S.pose = (p && isNum(p.x_m) && isNum(p.y_m))
        ? { x: p.x_m, y: p.y_m, yaw: isNum(p.yaw_rad) ? p.yaw_rad : null } : null;
      invalidate('map');
    });
    step('trail', (t) => { S.trail = pts(t); invalidate('map'); });
    step('trail_append', (t) => {
      const add = pts(t);
      for (const p of add) {
        const last = S.trail[S.trail.length - 1];
        if (last && last[0] === p[0] && last[1] === p[1]) continue;
        S.trail.push(p);
      }
      if (S.trail.length > TRAIL_MAX) S.trail.splice(0, S.trail.length - TRAIL_MAX);
      invalidate('map');
    });
    step('scan', (s) => { S.scan = pts(s); invalidate('map'); });
    step('graph', (g) => {
      if (!g || typeof g !== 'object') { S.graph = { nodes: [], edges: [] }; }
      else {
        S.graph = {
          nodes: 'nodes' in g ? pts(g.nodes) : S.graph.nodes,
          edges: 'edges' in g ? (Array.isArray(g.edges) ? g.edges : []) : S.graph.edges,
        };
        // Node indices refer to node order; keep the raw array if some entries were invalid.
        if ('nodes' in g && Array.isArray(g.nodes) && S.graph.nodes.length !== g.nodes.length) {
          S.graph.nodes = g.nodes.map((p) => (isPt(p) ? p : null));
        }
      }
      invalidate('map');
    });
    // New keyframes and edges after the ones the page has (the old ones did not move).
    step('graph_append', (g) => {
      if (!g || typeof g !== 'object') return;
      if (Array.isArray(g.nodes)) for (const p of g.nodes) S.graph.nodes.push(isPt(p) ? p : null);
      if (Array.isArray(g.edges)) for (const e of g.edges) S.graph.edges.push(e);
      invalidate('map');
    });

    let frontiersChanged = false;
    step('frontiers', (f) => {
      // A frontier without "cells" kept the cells the page has for its id.
      const before = new Map();
      for (const x of S.frontiers) if (x && x.id !== undefined) before.set(x.id, x);
      S.frontiers = (Array.isArray(f) ? f : []).map((x) => {
        if (!x || typeof x !== 'object' || 'cells' in x || !before.has(x.id)) return x;
        return Object.assign({}, x, { cells: before.get(x.id).cells });
      });
      api.lastFrontierCount = S.frontiers.length;
      frontiersChanged = true;
    });
    step('scores', (sc) => { applyScores(sc); frontiersChanged = true; });
    if (frontiersChanged) {
      recomputeRamp();
      renderFrontierTable();
      refreshTooltip();
      invalidate('map');
    }

    step('nav', (n) => { S.nav = mergeObj(S.nav, n); renderNav(); invalidate('map'); });
    step('explore', (e) => { S.explore = mergeObj(S.explore, e); renderExplore(); });
    step('series', (s) => { S.series = Array.isArray(s) ? s.filter(Array.isArray) : []; invalidate('charts'); });
    step('series_append', (s) => {
      if (Array.isArray(s)) for (const p of s) if (Array.isArray(p)) S.series.push(p);
      if (S.series.length > SERIES_MAX) S.series.splice(0, S.series.length - SERIES_MAX);
      invalidate('charts');
    });
    step('processes', (p) => { S.processes = Array.isArray(p) ? p : []; renderProcesses(); });

    renderTime();
    if (S.mode === 'replay' && isNum(S.tS) && !replay.dragging && !replay.playing) {
      replay.t = S.tS;
      slider.value = String(S.tS);
      renderReplayTime();
    }
    api.frames++;
  }

  function applyHello(h) {
    S.mode = h.mode === 'replay' ? 'replay' : 'live';
    api.mode = S.mode;
    S.control = h.control === true;
    S.tokenRequired = h.token_required === true;
    S.replay = null;
    if (S.mode === 'replay') {
      const r = (h.replay && typeof h.replay === 'object') ? h.replay : {};
      const start = isNum(r.start_s) ? r.start_s : 0;
      const end = isNum(r.end_s) && r.end_s >= start ? r.end_s : start;
      S.replay = { start, end };
    }
    // A new session: the first update carries everything known.
    resetWorld();
    setupModeUi();
    updateControlUi();
  }

  function applyControlResult(r) {
    const el = $('control-result');
    const cmd = str(r.command);
    if (r.ok === true) {
      el.textContent = (cmd || 'control') + ': ok';
      el.className = 'detail ok';
    } else {
      const err = str(r.error);
      el.textContent = (cmd || 'control') + ': failed' + (err ? ' \u2014 ' + err : '');
      el.className = 'detail bad';
    }
  }

  function handleMessage(msg) {
    if (!msg || typeof msg !== 'object') return;
    switch (msg.type) {
      case 'hello': applyHello(msg); break;
      case 'update': applyUpdate(msg); break;
      case 'control_result': applyControlResult(msg); break;
      default: break;
    }
  }

  // ------------------------------------------------------------------ side panel rendering

  const frontierTbody = document.querySelector('#frontier-table tbody');
  const processTbody = document.querySelector('#process-table tbody');

  function renderFrontierTable() {
    const frag = document.createDocumentFragment();
    const order = S.frontiers.map((f, i) => ({ f, i, row: rowFor(f) }));
    // Best total first; ineligible / unscored after, then by id.
    const key = (o) => (rowScored(o.row) ? o.row.total : -Infinity);
    order.sort((a, b) => {
      const ka = key(a), kb = key(b);
      if (ka !== kb) return kb - ka;
      const sa = a.row ? 0 : 1, sb = b.row ? 0 : 1;
      if (sa !== sb) return sa - sb;
      const ia = a.f && isNum(a.f.id) ? a.f.id : Infinity, ib = b.f && isNum(b.f.id) ? b.f.id : Infinity;
      return ia === ib ? a.i - b.i : ia - ib;
    });
    let eligible = 0;
    for (const o of order) {
      const f = (o.f && typeof o.f === 'object') ? o.f : {};
      const row = o.row;
      const tr = document.createElement('tr');
      tr.dataset.idx = String(o.i);
      if (isChosen(f, row)) tr.classList.add('chosen');
      if (o.i === hover.idx) tr.classList.add('hover');

      const idCell = document.createElement('td');
      idCell.className = 'swatch-cell';
      const sw = document.createElement('span');
      sw.className = 'swatch';
      sw.style.background = frontierColour(f);
      idCell.appendChild(sw);
      idCell.appendChild(document.createTextNode(strOrDash(f.id) + (isChosen(f, row) ? ' \u2605' : '')));
      tr.appendChild(idCell);

      if (row) {
        tr.appendChild(td(fmtAuto(row.u1)));
        tr.appendChild(td(fmtAuto(row.mean_entropy_bits)));
        tr.appendChild(td(fmtInt(row.ray_cells)));
        tr.appendChild(td(fmtAuto(row.gamma)));
        tr.appendChild(td(fmtAuto(row.rho)));
        tr.appendChild(td(fmtAuto(row.u2)));
        tr.appendChild(td(fmtAuto(row.total)));
        if (row.eligible === true) { tr.appendChild(td('yes', 'yes')); eligible++; }
        else tr.appendChild(td(row.eligible === false ? 'no' + (str(row.reason) ? ': ' + str(row.reason) : '') : DASH, 'no'));
      } else {
        for (let k = 0; k < 8; k++) tr.appendChild(td(DASH));
      }
      frag.appendChild(tr);
    }
    frontierTbody.replaceChildren(frag);
    let summary = '(' + S.frontiers.length + ')';
    if (S.scores) {
      summary = '(' + S.frontiers.length + ', ' + eligible + ' eligible';
      if (isNum(S.scores.decision_id)) summary += ', decision ' + S.scores.decision_id;
      if (str(S.scores.method)) summary += ', ' + str(S.scores.method);
      summary += ')';
    }
    setText('frontier-summary', summary);
  }

  const EXPLORE_STATES = ['waiting', 'exploring', 'done', 'paused', 'returning', 'stopped'];
  function renderExplore() {
    const e = S.explore;
    const st = str(e.state);
    const el = $('explore-state');
    setText(el, st || DASH);
    el.className = 'big-state ' + (EXPLORE_STATES.includes(st) ? 'st-' + st : 'st-other');
    setText('explore-detail', str(e.detail));
    setText('explore-method', strOrDash(e.method));
    setText('explore-decisions', fmtInt(e.decisions));
    setText('explore-goals', fmtInt(e.goals_reached) + ' / ' + fmtInt(e.goals_failed));
    setText('explore-frontiers', fmtInt(e.num_frontiers) + ' / ' + fmtInt(e.num_eligible));
    setText('explore-goal', strOrDash(e.current_goal_id));
  }

  function renderNav() {
    const n = S.nav;
    setText('nav-state', strOrDash(n.state));
    let goal = strOrDash(n.goal_id);
    if (isPt(n.goal)) goal += ' (' + n.goal[0].toFixed(2) + ', ' + n.goal[1].toFixed(2) + ')';
    setText('nav-goal', goal);
    setText('nav-distance', isNum(n.distance_remaining_m) ? n.distance_remaining_m.toFixed(2) + ' m' : DASH);
    setText('nav-detail', strOrDash(n.detail));
  }

  const PROC_STATES = ['running', 'failed', 'backoff'];
  function renderProcesses() {
    const frag = document.createDocumentFragment();
    for (const p0 of S.processes) {
      const p = (p0 && typeof p0 === 'object') ? p0 : {};
      const tr = document.createElement('tr');
      const st = str(p.state);
      tr.appendChild(td(strOrDash(p.name)));
      tr.appendChild(td(strOrDash(p.host)));
      tr.appendChild(td(st || DASH, PROC_STATES.includes(st) ? 'ps-' + st : 'ps-other'));
      tr.appendChild(td(p.pid === null || p.pid === undefined ? DASH : str(p.pid)));
      tr.appendChild(td(fmtInt(p.restarts)));
      tr.appendChild(td(fmtFixed(p.cpu_percent, 1)));
      tr.appendChild(td(fmtFixed(p.rss_mb, 1)));
      tr.appendChild(td(p.last_exit === null || p.last_exit === undefined ? DASH : str(p.last_exit)));
      frag.appendChild(tr);
    }
    processTbody.replaceChildren(frag);
  }

  function renderTime() {
    setText('msg-time', 't = ' + (isNum(S.tS) ? S.tS.toFixed(1) + ' s' : DASH));
  }

  // ------------------------------------------------------------------ connection

  let ws = null;
  let frameChain = Promise.resolve();  // frames in arrival order (tiles inflate asynchronously)
  let reconnectDelay = 2000;
  let reconnectTimer = null;

  function setConnected(on, text) {
    api.connected = on;
    const dot = $('conn-dot');
    dot.className = 'dot ' + (on ? 'on' : 'off');
    setText('conn-text', text || (on ? 'connected' : 'disconnected'));
    if (!on) setPlaying(false);
    updateControlUi();
  }

  function connect() {
    reconnectTimer = null;
    const proto = location.protocol === 'https:' ? 'wss:' : 'ws:';
    let sock;
    try {
      sock = new WebSocket(proto + '//' + location.host + '/ws');
    } catch (e) {
      scheduleReconnect();
      return;
    }
    ws = sock;
    setText('conn-text', 'connecting\u2026');
    sock.onopen = () => {
      if (ws !== sock) return;
      reconnectDelay = 2000;
      setConnected(true);
    };
    sock.onmessage = (ev) => {
      if (ws !== sock || typeof ev.data !== 'string') return;
      let msg;
      try { msg = JSON.parse(ev.data); } catch (e) { return; }
      // Frames apply strictly in order, each after its tiles are inflated.
      frameChain = frameChain.then(() => inflateTiles(msg)).then(() => {
        if (ws !== sock) return;
        try { handleMessage(msg); } catch (e) { console.warn('aslam-viewer: frame failed', e); }
      });
    };
    sock.onclose = () => {
      if (ws !== sock) return;
      ws = null;
      scheduleReconnect();
    };
    sock.onerror = () => { /* a close event follows */ };
  }

  function scheduleReconnect() {
    const delay = reconnectDelay;
    reconnectDelay = Math.min(10000, Math.round(reconnectDelay * 1.5));
    setConnected(false, 'disconnected \u2014 reconnecting in ' + (delay / 1000).toFixed(0) + ' s');
    if (reconnectTimer) clearTimeout(reconnectTimer);
    reconnectTimer = setTimeout(connect, delay);
  }

  function send(text) {
    if (ws && ws.readyState === WebSocket.OPEN) { ws.send(text); return true; }
    return false;
  }

  // ------------------------------------------------------------------ controls

  const pageToken = (function () {
    try { return new URLSearchParams(location.search).get('token') || ''; } catch (e) { return ''; }
  })();
  const CONTROL_BUTTONS = {
    'btn-pause': 'pause',
    'btn-resume': 'resume',
    'btn-stop': 'stop',
    'btn-return-home': 'return_home',
  };

  function updateControlUi() {
    const enabled = S.control && api.connected;
    for (const id of Object.keys(CONTROL_BUTTONS)) $(id).disabled = !enabled;
    let note = '';
    if (api.connected && S.mode !== null) {
      if (!S.control) note = 'control is disabled by the viewer';
      else if (S.tokenRequired && !pageToken) note = 'control needs a token: open this page as /?token=TOKEN';
      else if (S.tokenRequired) note = 'token from the page URL is sent with each request';
    }
    setText('control-note', note);
    if (!enabled) disarmStop();
  }

  function sendControl(cmd) {
    const res = $('control-result');
    if (!S.control) { res.textContent = 'control is disabled by the viewer'; res.className = 'detail bad'; return; }
    if (S.tokenRequired && !pageToken) {
      res.textContent = 'token required: open this page with ?token=TOKEN (printed by aslam-viewer)';
      res.className = 'detail bad';
      return;
    }
    if (S.tokenRequired && /\s/.test(pageToken)) {
      res.textContent = 'the token in the page URL contains spaces';
      res.className = 'detail bad';
      return;
    }
    const text = 'control ' + cmd + (S.tokenRequired ? ' ' + pageToken : '');
    if (send(text)) { res.textContent = cmd + ': sent\u2026'; res.className = 'detail'; }
    else { res.textContent = cmd + ': not connected'; res.className = 'detail bad'; }
  }

  let stopArmTimer = null;
  function disarmStop() {
    if (stopArmTimer) { clearTimeout(stopArmTimer); stopArmTimer = null; }
    const b = $('btn-stop');
    b.classList.remove('armed');
    b.textContent = 'Stop';
  }
  $('btn-stop').addEventListener('click', () => {
    const b = $('btn-stop');
    if (stopArmTimer) {
      disarmStop();
      sendControl('stop');
      return;
    }
    b.classList.add('armed');
    b.textContent = 'Really stop?';
    stopArmTimer = setTimeout(disarmStop, 3000);
  });
  for (const id of ['btn-pause', 'btn-resume', 'btn-return-home']) {
    $(id).addEventListener('click', () => sendControl(CONTROL_BUTTONS[id]));
  }

  // ------------------------------------------------------------------ replay

  const slider = $('time-slider');
  const replay = {
    t: 0, playing: false, playTimer: null, dragging: false,
    lastSentAt: -Infinity, lastSentValue: null, pending: null, throttleTimer: null,
  };
  const SEEK_MIN_INTERVAL_MS = 200;

  function setupModeUi() {
    const badge = $('mode-badge');
    badge.textContent = S.mode || DASH;
    badge.className = 'badge ' + (S.mode === 'replay' ? 'replay' : S.mode === 'live' ? 'live' : '');
    const bar = $('replay-bar');
    if (S.mode === 'replay' && S.replay) {
      slider.min = String(S.replay.start);
      slider.max = String(S.replay.end);
      slider.step = '0.1';
      replay.t = S.replay.start;
      slider.value = String(replay.t);
      bar.hidden = false;
    } else {
      setPlaying(false);
      bar.hidden = true;
    }
    renderReplayTime();
    resizeMapCanvas();
  }

  function renderReplayTime() {
    if (!S.replay) { setText('replay-time', DASH); return; }
    setText('replay-time', replay.t.toFixed(1) + ' / ' + S.replay.end.toFixed(1) + ' s');
  }

  function sendSeek(t) {
    if (S.mode !== 'replay') return;
    replay.lastSentAt = performance.now();
    replay.lastSentValue = t;
    send('seek ' + fmtSeek(t));
  }
  function flushSeek() {
    if (replay.throttleTimer) { clearTimeout(replay.throttleTimer); replay.throttleTimer = null; }
    if (replay.pending === null) return;
    const t = replay.pending;
    replay.pending = null;
    sendSeek(t);
  }
  function throttledSeek(t) {
    replay.pending = t;
    const since = performance.now() - replay.lastSentAt;
    if (since >= SEEK_MIN_INTERVAL_MS) flushSeek();
    else if (!replay.throttleTimer) replay.throttleTimer = setTimeout(flushSeek, SEEK_MIN_INTERVAL_MS - since);
  }
  function finalSeek(t) {
    const alreadySent = replay.pending === null && replay.lastSentValue === t;
    if (replay.throttleTimer) { clearTimeout(replay.throttleTimer); replay.throttleTimer = null; }
    replay.pending = null;
    if (!alreadySent) sendSeek(t);
  }

  slider.addEventListener('pointerdown', () => { replay.dragging = true; });
  window.addEventListener('pointerup', () => { replay.dragging = false; });
  slider.addEventListener('input', () => {
    const t = Number(slider.value);
    if (!isNum(t)) return;
    replay.t = t;
    renderReplayTime();
    throttledSeek(t);
  });
  slider.addEventListener('change', () => {
    replay.dragging = false;
    const t = Number(slider.value);
    if (!isNum(t)) return;
    replay.t = t;
    renderReplayTime();
    finalSeek(t);
  });

  function setPlaying(on) {
    const btn = $('btn-play');
    if (on && (S.mode !== 'replay' || !S.replay)) on = false;
    if (on === replay.playing) return;
    replay.playing = on;
    if (replay.playTimer) { clearInterval(replay.playTimer); replay.playTimer = null; }
    if (on) {
      if (replay.t >= S.replay.end - 1e-6) replay.t = S.replay.start;
      replay.playTimer = setInterval(playTick, 500);
      btn.textContent = '\u275a\u275a pause';
    } else {
      btn.textContent = '\u25b6 play';
    }
  }
  function playTick() {
    if (!replay.playing || !S.replay) return;
    replay.t = Math.min(S.replay.end, replay.t + 0.5);
    if (!replay.dragging) slider.value = String(replay.t);
    renderReplayTime();
    sendSeek(replay.t);
    if (replay.t >= S.replay.end) setPlaying(false);
  }
  $('btn-play').addEventListener('click', () => setPlaying(!replay.playing));

  // ------------------------------------------------------------------ map view

  const mapCanvas = $('map-canvas');
  const mapCtx = mapCanvas.getContext('2d');
  const mapWrap = $('map-wrap');
  const view = { scale: 30, ox: 0, oy: 0, cssW: 0, cssH: 0, dpr: 1, fitted: false, userMoved: false, centred: false };
  const hover = { idx: -1, tableIdx: -1, mx: 0, my: 0, inside: false };

  function resizeMapCanvas() {
    const r = mapWrap.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(r.width)), h = Math.max(1, Math.round(r.height));
    if (w === view.cssW && h === view.cssH && dpr === view.dpr) return;
    if (view.cssW > 0 && view.cssH > 0) {
      // keep the centre of the view where it was
      view.ox += (w - view.cssW) / 2;
      view.oy += (h - view.cssH) / 2;
    } else {
      view.ox = w / 2;
      view.oy = h / 2;
    }
    view.cssW = w; view.cssH = h; view.dpr = dpr;
    mapCanvas.width = Math.round(w * dpr);
    mapCanvas.height = Math.round(h * dpr);
    invalidate('map');
  }

  function w2s(x, y) { return [view.ox + x * view.scale, view.oy - y * view.scale]; }
  function s2w(sx, sy) { return [(sx - view.ox) / view.scale, (view.oy - sy) / view.scale]; }

  function mapExtent() {
    const g = S.map;
    if (!g) return null;
    const wM = g.width * g.res, hM = g.height * g.res;
    const c = Math.cos(g.yaw), s = Math.sin(g.yaw);
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (const [u, v] of [[0, 0], [wM, 0], [0, hM], [wM, hM]]) {
      const x = g.ox + c * u - s * v, y = g.oy + s * u + c * v;
      x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y);
    }
    return [x0, y0, x1, y1];
  }
  function dataExtent() {
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    const add = (p) => { x0 = Math.min(x0, p[0]); y0 = Math.min(y0, p[1]); x1 = Math.max(x1, p[0]); y1 = Math.max(y1, p[1]); };
    if (S.pose) add([S.pose.x, S.pose.y]);
    for (const p of S.trail) add(p);
    for (const p of S.graph.nodes) if (p) add(p);
    for (const p of S.scan) add(p);
    if (!(x1 >= x0)) return null;
    return [x0, y0, x1, y1];
  }
  function fitTo(e) {
    if (!e || view.cssW <= 1 || view.cssH <= 1) return false;
    let [x0, y0, x1, y1] = e;
    const minSpan = 4;
    if (x1 - x0 < minSpan) { const c = (x0 + x1) / 2; x0 = c - minSpan / 2; x1 = c + minSpan / 2; }
    if (y1 - y0 < minSpan) { const c = (y0 + y1) / 2; y0 = c - minSpan / 2; y1 = c + minSpan / 2; }
    const scale = Math.min(view.cssW / (x1 - x0), view.cssH / (y1 - y0)) * 0.94;
    view.scale = Math.max(0.05, Math.min(5000, scale));
    view.ox = view.cssW / 2 - ((x0 + x1) / 2) * view.scale;
    view.oy = view.cssH / 2 + ((y0 + y1) / 2) * view.scale;
    invalidate('map');
    return true;
  }
  function fitView() {
    const e = mapExtent() || dataExtent();
    if (fitTo(e)) view.fitted = !!S.map;
  }
  $('btn-fit').addEventListener('click', () => { view.userMoved = false; fitView(); });

  function autoFit() {
    if (view.fitted || view.userMoved) return;
    if (S.map) { fitView(); return; }
    const e = dataExtent();
    if (e && !view.centred) { view.centred = fitTo(e); }
  }

  // wheel zoom around the cursor
  mapCanvas.addEventListener('wheel', (ev) => {
    ev.preventDefault();
    const r = mapCanvas.getBoundingClientRect();
    const mx = ev.clientX - r.left, my = ev.clientY - r.top;
    let dy = ev.deltaY;
    if (ev.deltaMode === 1) dy *= 16; else if (ev.deltaMode === 2) dy *= 400;
    let f = Math.exp(-dy * 0.0015);
    const newScale = Math.max(0.05, Math.min(5000, view.scale * f));
    f = newScale / view.scale;
    view.ox = mx - (mx - view.ox) * f;
    view.oy = my - (my - view.oy) * f;
    view.scale = newScale;
    view.userMoved = true;
    invalidate('map');
    updateHover(mx, my);
  }, { passive: false });

  // drag pan
  const drag = { active: false, id: null, x: 0, y: 0 };
  mapCanvas.addEventListener('pointerdown', (ev) => {
    if (ev.button !== 0) return;
    drag.active = true; drag.id = ev.pointerId; drag.x = ev.clientX; drag.y = ev.clientY;
    try { mapCanvas.setPointerCapture(ev.pointerId); } catch (e) { /* ignore */ }
    mapCanvas.classList.add('dragging');
    hideTooltip();
  });
  mapCanvas.addEventListener('pointermove', (ev) => {
    const r = mapCanvas.getBoundingClientRect();
    const mx = ev.clientX - r.left, my = ev.clientY - r.top;
    if (drag.active && ev.pointerId === drag.id) {
      view.ox += ev.clientX - drag.x;
      view.oy += ev.clientY - drag.y;
      drag.x = ev.clientX; drag.y = ev.clientY;
      view.userMoved = true;
      invalidate('map');
    } else {
      updateHover(mx, my);
    }
    const [wx, wy] = s2w(mx, my);
    setText('cursor-pos', 'x ' + wx.toFixed(2) + '  y ' + wy.toFixed(2) + ' m');
  });
  const endDrag = (ev) => {
    if (!drag.active || ev.pointerId !== drag.id) return;
    drag.active = false;
    mapCanvas.classList.remove('dragging');
  };
  mapCanvas.addEventListener('pointerup', endDrag);
  mapCanvas.addEventListener('pointercancel', endDrag);
  mapCanvas.addEventListener('pointerleave', () => {
    hover.inside = false;
    setText('cursor-pos', '');
    if (hover.idx !== -1) { hover.idx = -1; syncTableHover(); invalidate('map'); }
    hideTooltip();
  });

  // ------------------------------------------------------------------ hover + tooltip

  const tooltip = $('tooltip');

  function findFrontierAt(mx, my) {
    const [wx, wy] = s2w(mx, my);
    const thr = Math.max(0.3, 8 / view.scale);
    let best = -1, bestD = thr * thr;
    for (let i = 0; i < S.frontiers.length; i++) {
      const f = S.frontiers[i];
      if (!f || typeof f !== 'object') continue;
      const t = frontierTarget(f);
      if (t) {
        const dx = t[0] - wx, dy = t[1] - wy, d = dx * dx + dy * dy;
        if (d <= bestD) { bestD = d; best = i; }
      }
      const cells = f.cells;
      if (Array.isArray(cells)) {
        for (let k = 0; k < cells.length; k++) {
          const c = cells[k];
          if (!isPt(c)) continue;
          const dx = c[0] - wx, dy = c[1] - wy, d = dx * dx + dy * dy;
          if (d < bestD) { bestD = d; best = i; }
        }
      }
    }
    return best;
  }

  function updateHover(mx, my) {
    hover.mx = mx; hover.my = my; hover.inside = true;
    const idx = drag.active ? -1 : findFrontierAt(mx, my);
    if (idx !== hover.idx) {
      hover.idx = idx;
      syncTableHover();
      invalidate('map');
    }
    if (idx >= 0) showTooltip(idx, mx, my); else hideTooltip();
  }

  function refreshTooltip() {
    if (hover.idx >= S.frontiers.length) hover.idx = -1;
    if (hover.inside && !drag.active) updateHover(hover.mx, hover.my);
    else if (hover.idx < 0) hideTooltip();
  }

  function hideTooltip() { if (!tooltip.hidden) tooltip.hidden = true; }

  function showTooltip(idx, mx, my) {
    const f = S.frontiers[idx];
    if (!f || typeof f !== 'object') { hideTooltip(); return; }
    const row = rowFor(f);
    const frag = document.createDocumentFragment();
    const title = document.createElement('div');
    title.className = 'tt-title' + (isChosen(f, row) ? ' chosen' : '');
    let t = 'Frontier ' + strOrDash(f.id);
    if (isNum(f.size)) t += ' \u00b7 ' + Math.round(f.size) + ' cells';
    if (isChosen(f, row)) t += ' \u00b7 chosen \u2605';
    title.textContent = t;
    frag.appendChild(title);
    const grid = document.createElement('div');
    grid.className = 'tt-grid';
    const add = (k, v, cls) => {
      const a = document.createElement('span'); a.className = 'tt-k'; a.textContent = k;
      const b = document.createElement('span'); b.className = 'tt-v' + (cls ? ' ' + cls : ''); b.textContent = v;
      grid.appendChild(a); grid.appendChild(b);
    };
    if (row) {
      add('U1', fmtAuto(row.u1));
      add('\u0112 (mean entropy, bits)', fmtAuto(row.mean_entropy_bits));
      add('K (ray cells)', fmtInt(row.ray_cells));
      add('\u03b3 (gamma)', fmtAuto(row.gamma));
      add('\u03c1 (rho)', fmtAuto(row.rho));
      add('U2', fmtAuto(row.u2));
      add('total', fmtAuto(row.total));
      add('path length', isNum(row.path_length_m) ? row.path_length_m.toFixed(2) + ' m' : DASH);
      if (row.eligible === true) add('eligible', 'yes', 'ok');
      else {
        add('eligible', row.eligible === false ? 'no' : DASH, 'bad');
        add('reason', strOrDash(row.reason), 'bad');
      }
    } else {
      add('score', 'no score row');
    }
    const tgt = frontierTarget(f);
    if (tgt) add('target', '(' + tgt[0].toFixed(2) + ', ' + tgt[1].toFixed(2) + ')');
    frag.appendChild(grid);
    tooltip.replaceChildren(frag);
    tooltip.hidden = false;
    // place next to the cursor, inside the map area
    const tw = tooltip.offsetWidth, th = tooltip.offsetHeight;
    let x = mx + 16, y = my + 16;
    if (x + tw > view.cssW - 4) x = Math.max(4, mx - 16 - tw);
    if (y + th > view.cssH - 4) y = Math.max(4, my - 16 - th);
    tooltip.style.left = x + 'px';
    tooltip.style.top = y + 'px';
  }

  function syncTableHover() {
    for (const tr of frontierTbody.children) {
      const i = Number(tr.dataset.idx);
      tr.classList.toggle('hover', i === hover.idx || i === hover.tableIdx);
    }
  }
  frontierTbody.addEventListener('mouseover', (ev) => {
    const tr = ev.target instanceof Element ? ev.target.closest('tr') : null;
    const i = tr ? Number(tr.dataset.idx) : -1;
    if (i !== hover.tableIdx) { hover.tableIdx = isNum(i) ? i : -1; invalidate('map'); }
  });
  frontierTbody.addEventListener('mouseleave', () => {
    if (hover.tableIdx !== -1) { hover.tableIdx = -1; invalidate('map'); }
  });

  // ------------------------------------------------------------------ drawing (rAF, only when dirty)

  const dirty = { map: false, charts: false };
  let rafPending = false;
  function invalidate(...keys) {
    for (const k of keys) dirty[k] = true;
    if (!rafPending) { rafPending = true; requestAnimationFrame(onFrame); }
  }
  function onFrame() {
    rafPending = false;
    if (dirty.map) {
      dirty.map = false;
      try { autoFit(); } catch (e) { console.warn(e); }
      dirty.map = false;
      try { drawMap(); } catch (e) { console.warn('aslam-viewer: draw failed', e); }
    }
    if (dirty.charts) {
      dirty.charts = false;
      try { drawCharts(); } catch (e) { console.warn('aslam-viewer: chart failed', e); }
    }
  }

  function drawMap() {
    const ctx = mapCtx;
    const dpr = view.dpr, s = view.scale, px = 1 / s;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = '#0f1216';
    ctx.fillRect(0, 0, mapCanvas.width, mapCanvas.height);
    const world = () => ctx.setTransform(dpr * s, 0, 0, -dpr * s, dpr * view.ox, dpr * view.oy);
    const screen = () => ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.lineJoin = 'round';
    ctx.lineCap = 'round';

    // visible world box (for culling points)
    const [vx0, vy1] = s2w(-20, -20);
    const [vx1, vy0] = s2w(view.cssW + 20, view.cssH + 20);
    const visible = (p) => p[0] >= vx0 && p[0] <= vx1 && p[1] >= vy0 && p[1] <= vy1;

    world();

    // occupancy grid
    const g = S.map;
    if (g) {
      ctx.save();
      ctx.translate(g.ox, g.oy);
      if (g.yaw) ctx.rotate(g.yaw);
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(g.canvas, 0, 0, g.width * g.res, g.height * g.res);
      ctx.restore();
      ctx.strokeStyle = 'rgba(120,140,170,0.5)';
      ctx.lineWidth = px;
      ctx.save();
      ctx.translate(g.ox, g.oy);
      if (g.yaw) ctx.rotate(g.yaw);
      ctx.strokeRect(0, 0, g.width * g.res, g.height * g.res);
      ctx.restore();
    }

    // pose graph edges
    const nodes = S.graph.nodes, edges = S.graph.edges;
    if (edges.length) {
      const odo = new Path2D(), loop = new Path2D();
      let nLoop = 0;
      for (const e of edges) {
        if (!Array.isArray(e)) continue;
        const a = nodes[e[0]], b = nodes[e[1]];
        if (!a || !b) continue;
        const p = e[2] === 1 ? loop : odo;
        if (e[2] === 1) nLoop++;
        p.moveTo(a[0], a[1]);
        p.lineTo(b[0], b[1]);
      }
      ctx.strokeStyle = 'rgba(110,118,130,0.9)';
      ctx.lineWidth = 1 * px;
      ctx.stroke(odo);
      if (nLoop) {
        ctx.strokeStyle = '#19c45a';
        ctx.lineWidth = 2 * px;
        ctx.stroke(loop);
      }
    }
    if (nodes.length) {
      const r = 2 * px;
      ctx.fillStyle = '#7c4dff';
      ctx.beginPath();
      for (const n of nodes) if (n && visible(n)) ctx.rect(n[0] - r, n[1] - r, 2 * r, 2 * r);
      ctx.fill();
    }

    // trail: the keyframes in order (as optimized), then the poses since the newest of them
    const trail = S.graph.nodes.filter((n) => n).concat(S.trail);
    if (trail.length > 1) {
      ctx.strokeStyle = '#ff9800';
      ctx.lineWidth = 1.6 * px;
      ctx.beginPath();
      ctx.moveTo(trail[0][0], trail[0][1]);
      for (let i = 1; i < trail.length; i++) ctx.lineTo(trail[i][0], trail[i][1]);
      ctx.stroke();
    }

    // frontier cells: dark under-layer for contrast, then one fill per frontier colour
    const cellRes = g ? g.res : 0.05;
    const side = Math.max(cellRes, 3 * px);
    const hs = side / 2, hu = hs + 1 * px;
    const colours = S.frontiers.map(frontierColour);
    ctx.fillStyle = 'rgba(0,0,0,0.85)';
    ctx.beginPath();
    for (const f of S.frontiers) {
      if (!f || !Array.isArray(f.cells)) continue;
      for (const c of f.cells) if (isPt(c) && visible(c)) ctx.rect(c[0] - hu, c[1] - hu, 2 * hu, 2 * hu);
    }
    ctx.fill();
    for (let i = 0; i < S.frontiers.length; i++) {
      const f = S.frontiers[i];
      if (!f || !Array.isArray(f.cells)) continue;
      ctx.fillStyle = colours[i];
      ctx.beginPath();
      for (const c of f.cells) if (isPt(c) && visible(c)) ctx.rect(c[0] - hs, c[1] - hs, side, side);
      ctx.fill();
    }
    // highlight of the hovered frontier's cells
    for (const hi of new Set([hover.idx, hover.tableIdx])) {
      const f = S.frontiers[hi];
      if (hi < 0 || !f || !Array.isArray(f.cells)) continue;
      ctx.strokeStyle = '#ffffff';
      ctx.lineWidth = 1.5 * px;
      ctx.beginPath();
      for (const c of f.cells) if (isPt(c)) ctx.rect(c[0] - hu, c[1] - hu, 2 * hu, 2 * hu);
      ctx.stroke();
    }

    // navigator path
    const nav = S.nav;
    const path = pts(nav.path);
    if (path.length > 1) {
      ctx.strokeStyle = '#1e6cff';
      ctx.lineWidth = 2.5 * px;
      ctx.beginPath();
      ctx.moveTo(path[0][0], path[0][1]);
      for (let i = 1; i < path.length; i++) ctx.lineTo(path[i][0], path[i][1]);
      ctx.stroke();
    }

    // scan end points
    if (S.scan.length) {
      const r = 1.4 * px;
      ctx.fillStyle = '#ff2020';
      ctx.beginPath();
      for (const p of S.scan) if (visible(p)) ctx.rect(p[0] - r, p[1] - r, 2 * r, 2 * r);
      ctx.fill();
    }

    // robot: circle of 0.2 m with heading line
    if (S.pose) {
      const R = Math.max(0.2, 5 * px);
      ctx.fillStyle = 'rgba(255,152,0,0.85)';
      ctx.strokeStyle = '#1a1a1a';
      ctx.lineWidth = 1.5 * px;
      ctx.beginPath();
      ctx.arc(S.pose.x, S.pose.y, R, 0, Math.PI * 2);
      ctx.fill();
      ctx.stroke();
      if (S.pose.yaw !== null) {
        const L = R * 1.6;
        ctx.strokeStyle = '#1a1a1a';
        ctx.lineWidth = 2.5 * px;
        ctx.beginPath();
        ctx.moveTo(S.pose.x, S.pose.y);
        ctx.lineTo(S.pose.x + L * Math.cos(S.pose.yaw), S.pose.y + L * Math.sin(S.pose.yaw));
        ctx.stroke();
      }
    }

    // ---- screen-space markers
    screen();

    // frontier targets
    for (let i = 0; i < S.frontiers.length; i++) {
      const t = frontierTarget(S.frontiers[i]);
      if (!t) continue;
      const [x, y] = w2s(t[0], t[1]);
      if (x < -20 || y < -20 || x > view.cssW + 20 || y > view.cssH + 20) continue;
      ctx.beginPath();
      ctx.arc(x, y, 3.5, 0, Math.PI * 2);
      ctx.fillStyle = colours[i];
      ctx.fill();
      ctx.lineWidth = 1;
      ctx.strokeStyle = '#000';
      ctx.stroke();
    }

    // navigator goal
    if (isPt(nav.goal)) {
      const [x, y] = w2s(nav.goal[0], nav.goal[1]);
      ctx.strokeStyle = '#1e6cff';
      ctx.lineWidth = 2.5;
      ctx.beginPath();
      ctx.arc(x, y, 7, 0, Math.PI * 2);
      ctx.moveTo(x - 10, y); ctx.lineTo(x + 10, y);
      ctx.moveTo(x, y - 10); ctx.lineTo(x, y + 10);
      ctx.stroke();
    }

    // chosen frontier: ring + star
    const cm = chosenMarker();
    if (cm) {
      const [x, y] = w2s(cm[0], cm[1]);
      ctx.lineWidth = 4;
      ctx.strokeStyle = 'rgba(0,0,0,0.7)';
      ctx.beginPath(); ctx.arc(x, y, 13, 0, Math.PI * 2); ctx.stroke();
      ctx.lineWidth = 2.2;
      ctx.strokeStyle = '#ff2bd6';
      ctx.beginPath(); ctx.arc(x, y, 13, 0, Math.PI * 2); ctx.stroke();
      starPath(ctx, x, y, 7.5, 3.2);
      ctx.fillStyle = '#ff2bd6';
      ctx.fill();
      ctx.lineWidth = 1;
      ctx.strokeStyle = '#fff';
      ctx.stroke();
    }

    // hovered frontier target
    for (const hi of new Set([hover.idx, hover.tableIdx])) {
      const t = hi >= 0 ? frontierTarget(S.frontiers[hi]) : null;
      if (!t) continue;
      const [x, y] = w2s(t[0], t[1]);
      ctx.lineWidth = 2;
      ctx.strokeStyle = '#fff';
      ctx.setLineDash([4, 3]);
      ctx.beginPath(); ctx.arc(x, y, 18, 0, Math.PI * 2); ctx.stroke();
      ctx.setLineDash([]);
    }

    drawLegend(ctx);
    drawScaleBar(ctx);

    if (!S.map && !S.pose && !S.frontiers.length) {
      ctx.fillStyle = '#8c96a5';
      ctx.font = '14px system-ui, sans-serif';
      ctx.textAlign = 'center';
      ctx.fillText(api.connected ? 'waiting for data\u2026' : 'not connected', view.cssW / 2, view.cssH / 2);
      ctx.textAlign = 'left';
    }
  }

  function starPath(ctx, x, y, ro, ri) {
    ctx.beginPath();
    for (let k = 0; k < 10; k++) {
      const r = k % 2 === 0 ? ro : ri;
      const a = -Math.PI / 2 + k * Math.PI / 5;
      const px = x + r * Math.cos(a), py = y + r * Math.sin(a);
      if (k === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
    }
    ctx.closePath();
  }

  function drawLegend(ctx) {
    if (!S.ramp) return;
    const x = 12, w = 140, h = 9, y = view.cssH - 34;
    ctx.fillStyle = 'rgba(15,18,22,0.8)';
    ctx.fillRect(x - 6, y - 18, w + 12, 44);
    for (let i = 0; i < w; i++) {
      ctx.fillStyle = rampColour(i / (w - 1));
      ctx.fillRect(x + i, y, 1, h);
    }
    ctx.fillStyle = '#dde3ea';
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'left';
    ctx.fillText('frontier total utility', x, y - 5);
    ctx.fillText(fmtAuto(S.ramp.min), x, y + h + 12);
    ctx.textAlign = 'right';
    ctx.fillText(fmtAuto(S.ramp.max), x + w, y + h + 12);
    ctx.textAlign = 'left';
  }

  function drawScaleBar(ctx) {
    const target = 100 / view.scale;   // metres in ~100 px
    const p = Math.pow(10, Math.floor(Math.log10(target)));
    let m = p;
    for (const k of [1, 2, 5, 10]) if (k * p <= target) m = k * p;
    const len = m * view.scale;
    const x1 = view.cssW - 14, x0 = x1 - len, y = view.cssH - 14;
    ctx.strokeStyle = '#dde3ea';
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(x0, y - 5); ctx.lineTo(x0, y); ctx.lineTo(x1, y); ctx.lineTo(x1, y - 5);
    ctx.stroke();
    ctx.fillStyle = '#dde3ea';
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    ctx.fillText((m >= 1 ? String(m) : m.toPrecision(1)) + ' m', (x0 + x1) / 2, y - 6);
    ctx.textAlign = 'left';
  }

  // ------------------------------------------------------------------ charts

  const charts = [
    { canvas: $('chart-area'), col: 1, colour: '#4d9bff', last: 'area-last', unit: ' m\u00b2' },
    { canvas: $('chart-dopt'), col: 2, colour: '#3ecf6e', last: 'dopt-last', unit: '' },
  ];

  function drawCharts() {
    for (const c of charts) drawChart(c);
  }

  function drawChart(c) {
    const cv = c.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(cv.clientWidth)), h = Math.max(1, Math.round(cv.clientHeight));
    if (cv.width !== Math.round(w * dpr) || cv.height !== Math.round(h * dpr)) {
      cv.width = Math.round(w * dpr);
      cv.height = Math.round(h * dpr);
    }
    const ctx = cv.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);

    const data = [];
    for (const p of S.series) {
      const t = p[0], v = p[c.col];
      if (isNum(t) && isNum(v)) data.push(t, v);
    }
    const n = data.length / 2;
    setText(c.last, n ? fmtAuto(data[data.length - 1]) + c.unit : '');
    ctx.font = '10px system-ui, sans-serif';
    if (!n) {
      ctx.fillStyle = '#8c96a5';
      ctx.fillText('no data', 8, h / 2 + 3);
      return;
    }
    let t0 = Infinity, t1 = -Infinity, v0 = Infinity, v1 = -Infinity;
    for (let i = 0; i < data.length; i += 2) {
      const t = data[i], v = data[i + 1];
      if (t < t0) t0 = t; if (t > t1) t1 = t;
      if (v < v0) v0 = v; if (v > v1) v1 = v;
    }
    if (t1 <= t0) { t1 = t0 + 1; }
    if (v1 <= v0) { const d = Math.abs(v0) * 0.05 || 1; v0 -= d; v1 += d; }
    const padV = (v1 - v0) * 0.06; v0 -= padV; v1 += padV;
    const L = 44, R = 6, T = 6, B = 14;
    const X = (t) => L + (t - t0) / (t1 - t0) * (w - L - R);
    const Y = (v) => T + (1 - (v - v0) / (v1 - v0)) * (h - T - B);

    ctx.strokeStyle = '#2e3542';
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(L + 0.5, T); ctx.lineTo(L + 0.5, h - B + 0.5); ctx.lineTo(w - R, h - B + 0.5);
    ctx.stroke();

    ctx.fillStyle = '#8c96a5';
    ctx.textAlign = 'right';
    ctx.fillText(fmtAuto(v1), L - 4, T + 8);
    ctx.fillText(fmtAuto(v0), L - 4, h - B);
    ctx.textAlign = 'left';
    ctx.fillText(t0.toFixed(0) + ' s', L + 2, h - 3);
    ctx.textAlign = 'right';
    ctx.fillText(t1.toFixed(0) + ' s', w - R, h - 3);
    ctx.textAlign = 'left';

    ctx.strokeStyle = c.colour;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    ctx.moveTo(X(data[0]), Y(data[1]));
    for (let i = 2; i < data.length; i += 2) ctx.lineTo(X(data[i]), Y(data[i + 1]));
    ctx.stroke();
    if (n === 1) {
      ctx.fillStyle = c.colour;
      ctx.beginPath(); ctx.arc(X(data[0]), Y(data[1]), 2, 0, Math.PI * 2); ctx.fill();
    }
  }

  // ------------------------------------------------------------------ start

  if (typeof ResizeObserver === 'function') {
    new ResizeObserver(() => resizeMapCanvas()).observe(mapWrap);
    const ro = new ResizeObserver(() => invalidate('charts'));
    for (const c of charts) ro.observe(c.canvas);
  }
  window.addEventListener('resize', () => { resizeMapCanvas(); invalidate('charts'); });

  resizeMapCanvas();
  renderExplore();
  renderNav();
  renderFrontierTable();
  renderProcesses();
  renderTime();
  updateControlUi();
  invalidate('map', 'charts');
  connect();
})();
