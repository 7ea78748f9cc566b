// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The bimslam map report: builds the summary, the floor plans, the plots, the change list and the
// 3D view from the JSON embedded in the page (host_tools/report/README.md lists its fields).
// Plain ES2017 and three.js r111 (Debian's libjs-three); no network.
'use strict';

const D = JSON.parse(document.getElementById('report-data').textContent);
const O = D.origin || [0, 0, 0];  // the model's local origin: data is in the mesh's frame
const SVGNS = 'http://www.w3.org/2000/svg';
const COLORS = ['#1f77b4', '#9467bd', '#17becf', '#8c564b', '#e377c2', '#bcbd22'];

function el(tag, attrs, parent, text) {
  const e = tag.startsWith('svg:') ? document.createElementNS(SVGNS, tag.slice(4))
                                   : document.createElement(tag);
  for (const k in attrs || {}) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}
function b64(s, Type) {
  if (!s) return new Type(0);
  const bin = atob(s);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}
function fmt(v, d) { return v === null || v === undefined ? '–' : Number(v).toFixed(d); }
function local(p) { return [p[0] - O[0], p[1] - O[1], p[2] - O[2]]; }
// The storey a point at height z (local frame) stands on: the highest whose elevation is at most
// z - 0.1 m, else the lowest (as the report's C++ side decides).
function storeyAt(z) {
  let s = 0;
  D.storeys.forEach((st, i) => { if (st.elevation <= z - 0.1) s = i; });
  return s;
}
function storeyIndex(row) {
  const i = D.storeys.findIndex(s => s.name === row.storey);
  return i >= 0 ? i : storeyAt(local(row.min)[2] + 0.2);
}

// ---- deviations (issue 34 item 3) -----------------------------------------------------------
// Each compared element's measured deviation (elements.csv offset_m) and its verdict against the
// tolerance (`--tolerance`): [GlobalId, code (0 within, 1 beyond, 2 not observed), offset_m].
const DEV = D.deviation ? new Map(D.deviation.elements.map(e => [e[0], e])) : null;
function devOf(i) {  // of the model's element i (D.model3d.elements)
  const m = D.model3d.elements[i];
  return m ? DEV.get(m.g) : undefined;
}
const DEV_T = D.deviation ? D.deviation.tolerance_m : 0;
const DEV_NAMES = ['within', 'beyond', 'not_observed'];
const DEV_GREEN = [0.10, 0.62, 0.25], DEV_YELLOW = [0.95, 0.75, 0.05];
const DEV_RED = [0.84, 0.15, 0.16], DEV_GREY = [0.62, 0.62, 0.62];
// Within: green at 0 to yellow at the tolerance; beyond (missing and moved too): red; not
// observed: grey.
function deviationColor(e) {
  if (!e || e[1] === 2) return DEV_GREY;
  if (e[1] === 1) return DEV_RED;
  const f = Math.min(Math.abs(e[2]) / DEV_T, 1);
  return DEV_GREEN.map((c, j) => c + f * (DEV_YELLOW[j] - c));
}
function hex(c) { return '#' + c.map(v => Math.round(v * 255).toString(16).padStart(2, '0')).join(''); }
function cm(m) { return String(+(m * 100).toFixed(2)); }  // 0.01 -> '1', 0.005 -> '0.5'
function deviationText(e) {
  if (!e) return 'not compared';
  if (e[1] === 2) return 'deviation not observed';
  return 'deviation ' + cm(e[2]) + ' cm, ' + DEV_NAMES[e[1]] + ' ±' + cm(DEV_T) + ' cm';
}
// The scale, named in cm: a gradient from 0 to the tolerance, then beyond and not observed.
function deviationLegend(parent) {
  const p = el('p', {class: 'legend deviation-legend'}, parent,
               'Elements by their deviation from the model (cm; tolerance ±' + cm(DEV_T) + ' cm): ');
  const svg = el('svg:svg', {width: 150, height: 24, viewBox: '0 0 150 24', class: 'scale'}, p);
  const id = 'dev-grad-' + document.querySelectorAll('.deviation-legend').length;
  const grad = el('svg:linearGradient', {id: id}, el('svg:defs', {}, svg));
  el('svg:stop', {offset: '0', 'stop-color': hex(DEV_GREEN)}, grad);
  el('svg:stop', {offset: '1', 'stop-color': hex(DEV_YELLOW)}, grad);
  el('svg:rect', {x: 5, y: 2, width: 140, height: 8, fill: 'url(#' + id + ')'}, svg);
  [0, 0.5, 1].forEach(f => el('svg:text', {x: 5 + 140 * f, y: 22, 'text-anchor': f ? (f < 1 ? 'middle' : 'end') : 'start'},
                              svg, cm(f * DEV_T) + (f === 1 ? ' cm' : '')));
  p.appendChild(document.createTextNode(' within '));
  el('span', {class: 'k', style: 'height:10px;background:' + hex(DEV_RED)}, p);
  p.appendChild(document.createTextNode('beyond ' + cm(DEV_T) + ' cm (missing and moved too) '));
  el('span', {class: 'k', style: 'height:10px;background:' + hex(DEV_GREY)}, p);
  p.appendChild(document.createTextNode('not observed'));
  return p;
}

// ---- summary -------------------------------------------------------------------------------
function buildSummary() {
  const S = D.summary, body = document.getElementById('summary-body');
  el('p', {}, body, 'Model ' + D.model.file + ' (' + D.model.schema + ', ' + D.model.elements +
     ' elements, ' + D.storeys.length + ' storeys); reference session of ' +
     (S.reference ? S.reference.keyframes : '?') + ' keyframes along a walk through every room.');
  // The project's visits (bimslam map, issue 33 item 1): this page is of the newest.
  if (S.visits && S.visit) {
    el('p', {class: 'visits'}, body, 'Visit ' + S.visit.label + ' (' + S.visit.start +
       '), the newest of ' + S.visits.length + ': ' + S.visits.map(v => v.label + ' (' +
       v.start + ': ' + v.recordings.map(r => r.name + ' ' +
       (r.anchor_verdict || 'not anchored')).join(', ') + ')').join('; ') + '.');
  }
  const t = el('table', {}, body);
  const h = el('tr', {}, t);
  ['recording', 'odometry', 'anchoring', 'loops', 'accuracy (BIM, no alignment)', 'changes',
   'change scores'].forEach(x => el('th', {}, h, x));
  S.recordings.forEach(r => {
    const tr = el('tr', {}, t);
    el('td', {}, tr, r.name).title = r.path;
    const o = r.odometry;
    el('td', {}, tr, o ? o.scans + ' scans, ' + o.keyframes + ' keyframes, ' + fmt(o.distance_m, 1) +
       ' m; ' + fmt(o.scan_ms_p50, 1) + ' ms per scan (p50)' : '–');
    const a = r.anchor;
    const td = el('td', {}, tr);
    if (a) {
      el('span', {class: 'verdict-' + a.verdict}, td, a.verdict);
      td.appendChild(document.createTextNode(': ' + a.reason));
    } else td.textContent = '–';
    el('td', {}, tr, a ? a.accepted_loops + ' accepted of ' + a.verified + ' verified, ' +
       a.candidates + ' candidates; ' + a.covered_keyframes + '/' + a.keyframes + ' keyframes' : '–');
    const acc = r.accuracy;
    el('td', {}, tr, acc ? 'APE ' + fmt(acc.ape_trans_rmse_m * 100, 2) + ' cm RMSE (max ' +
       fmt(acc.ape_trans_max_m * 100, 1) + '), ' + fmt(acc.ape_rot_rmse_deg, 2) + '° over ' +
       acc.matched + ' poses' : (r.ground_truth ? '–' : 'no ground truth'));
    const c = r.changes;
    el('td', {}, tr, c ? c.new_objects + ' new objects, ' + c.missing + ' missing, ' + c.deviating +
       ' deviating (' + c.moved + ' moved), ' + c.confirmed + ' confirmed, ' + c.transients +
       ' transients' : '–');
    buildScores(el('td', {class: 'scores'}, tr), r);
    if (o && o.verdict === 'untrusted') {
      const b = el('div', {class: 'banner odometry-untrusted'}, body);
      el('strong', {}, b, 'The odometry of ' + r.name + ' is not to be trusted. ');
      const where = (o.failed_stretches || []).map(s => 'scans ' + s.first_scan + '–' +
        s.last_scan + ' (' + fmt(s.first_s, 1) + '–' + fmt(s.last_s, 1) + ' s: ' +
        s.reasons.join(', ') + ')').join('; ');
      b.appendChild(document.createTextNode(o.failed + ' scans failed their registration ' +
        'checks: ' + where + '. The anchoring splits the session there into pieces placed on ' +
        'their own, with no odometry between them; the map, its anchoring and its changes there ' +
        'are not to be trusted.'));
    }
    if (a && a.verdict === 'anchored-in-parts') {
      const b = el('div', {class: 'banner anchored-in-parts'}, body);
      el('strong', {}, b, 'Recording ' + r.name + ' is anchored in parts only. ');
      b.appendChild(document.createTextNode(a.reason + '. Only the anchored pieces are placed ' +
        'in BIM coordinates, shown and compared with the model; the keyframes inside the ' +
        'odometry\'s failed stretches and the pieces not anchored are not.'));
    } else if (!a || a.verdict !== 'anchored') {
      const b = el('div', {class: 'banner'}, body);
      el('strong', {}, b, 'Recording ' + r.name + ' is not anchored' + (a ? ' (' + a.verdict + ')' : '') + '. ');
      b.appendChild(document.createTextNode((a ? a.reason + '. ' : '') +
        'It is not placed in BIM coordinates and has no change detection; its odometry map is ' +
        'shown in its own frame below.'));
    }
  });
}

// The change scores: first of what the walk's keyframes saw (summary.json's seen_scores: objects
// in view by the rule it states), with how many were out of view; all of them below, smaller.
function buildScores(td, r) {
  const sc = r.change_scores, s = r.seen_scores;
  if (!sc) { td.textContent = '–'; return; }
  const of = x => x.truth_matched + ' of ' + x.truth;
  if (s) {
    const a = s.added_in_view, m = s.removed_in_view, rule = s.in_view_rule;
    const out = (n, none) => n + ' out of view, ' + none + ' of them in no beam';
    el('div', {class: 'in-view'}, td, 'in view: added ≥ 0.3 m P ' +
       fmt(a.precision, 2) + ' R ' + fmt(a.recall, 2) + ' F1 ' + fmt(a.f1, 2) + ' (' + of(a) + '; ' +
       out(s.added_out_of_view, s.added_no_beam) + '); removed P ' + fmt(m.precision, 2) + ' R ' +
       fmt(m.recall, 2) + ' (' + of(m) + '; ' + out(s.removed_out_of_view, s.removed_no_beam) + ')');
    el('div', {class: 'in-view-rule'}, td, 'in view = the keyframes put ≥ ' + rule.min_map_points +
       ' map points on it, more than ' + fmt(100 * rule.off_model_m, 0) + ' cm off the model, ' +
       fmt(100 * rule.min_multi_view_fraction, 0) + ' % of them seen twice; removed: ≥ ' +
       fmt(rule.min_expected_area_m2, 2) + ' m² of it in their beams');
  }
  const a = sc.added_large, m = sc.removed;
  el('div', {class: s ? 'all-objects' : ''}, td, (s ? 'all: ' : '') + 'added ≥ 0.3 m P ' +
     fmt(a.precision, 2) + ' R ' + fmt(a.recall, 2) + ' F1 ' + fmt(a.f1, 2) + ' (' + of(a) +
     '); removed P ' + fmt(m.precision, 2) + ' R ' + fmt(m.recall, 2) + ' (' + of(m) +
     '); people as objects ' + sc.people.reported_as_new_objects);
}

// ---- floor plans -----------------------------------------------------------------------------
const planMarks = {};  // change row index -> [svg elements]
function niceLength(w) {
  for (const v of [0.5, 1, 2, 5, 10, 20, 50, 100]) if (v >= w / 8) return v;
  return 200;
}
// The runs of a walk on this storey (split by height in C++, storey_split.hpp): its floor's, and
// the flights to and from it, dashed. Returns [lines, of which on flights].
function drawRuns(runs, storey, cls, parent, color, name) {
  let n = 0, flights = 0;
  (runs || []).forEach(r => {
    if (r.lower !== storey && r.upper !== storey) return;
    const pts = [];
    for (let i = 0; i + 2 < r.xyz.length; i += 3) pts.push(r.xyz[i].toFixed(2) + ',' + r.xyz[i + 1].toFixed(2));
    if (pts.length < 2) return;
    const flight = r.lower !== r.upper;
    const p = el('svg:polyline', {class: cls + (flight ? ' flight' : ''), points: pts.join(' ')}, parent);
    if (color) p.setAttribute('stroke', color);
    if (name) p.dataset.walk = name;
    ++n;
    flights += flight;
  });
  return [n, flights];
}
// The stairs and ramps joining this storey to another: each tread's outline and the walking line.
function drawStairs(storey, parent) {
  let n = 0;
  (D.flights || []).forEach(f => {
    if (f.lower !== storey && f.upper !== storey) return;
    const g = el('svg:g', {class: 'stair'}, parent);
    el('svg:title', {}, g, f.name + ': ' + f.risers + ' risers of ' + fmt(f.rise_m, 2) + ' m, ' +
       D.storeys[f.lower].name + ' to ' + D.storeys[f.upper].name);
    const t = f.treads;
    let d = '';
    for (let i = 0; i + 7 < t.length; i += 8) {
      d += 'M' + t[i] + ' ' + t[i + 1] + 'L' + t[i + 2] + ' ' + t[i + 3] + 'L' + t[i + 4] + ' ' +
           t[i + 5] + 'L' + t[i + 6] + ' ' + t[i + 7] + 'Z';
    }
    el('svg:path', {class: 'tread', d: d}, g);
    const line = [];
    for (let i = 0; i + 1 < f.line.length; i += 2) line.push(f.line[i].toFixed(2) + ',' + f.line[i + 1].toFixed(2));
    el('svg:polyline', {class: 'stair-line', points: line.join(' ')}, g);
    ++n;
  });
  return n;
}
const planStats = [];  // per storey's plan: what it drew (the self-test reports it)
const planLayers = [];  // per storey's plan: {walks, marks} (SVG groups)
// Visit k's walks on every plan (walksOf, report_visits.js), with the loops of the newest visit's
// anchoring (loops.json is the newest's); a legend names the walks by colour.
function drawWalks(k) {
  const walks = walksOf(k), newest = k === newestVisit();
  planLayers.forEach((layer, si) => {
    layer.walks.textContent = '';
    Object.assign(planStats[si], {trajectory: 0, trajectory_on_flights: 0});
    walks.forEach((w, j) => {
      const [n, flights] = drawRuns(w.runs, si, 'traj', layer.walks, COLORS[j % COLORS.length], w.name);
      planStats[si].trajectory += n;
      planStats[si].trajectory_on_flights += flights;
    });
    if (newest) D.loops.forEach(l => {
      if (storeyAt(l.a[2]) !== si) return;
      el('svg:line', {class: l.accepted ? 'loop-ok' : 'loop-no', x1: l.a[0], y1: l.a[1], x2: l.b[0], y2: l.b[1]}, layer.walks);
      el('svg:circle', {class: l.accepted ? 'loop-ok' : 'loop-no', cx: l.b[0], cy: l.b[1], r: 0.06}, layer.walks);
    });
  });
  const legend = document.getElementById('plans-walks');
  legend.textContent = D.visits ? 'Walks of visit ' + visitLabel(k) + ': ' : 'Walks: ';
  walks.forEach((w, j) => {
    el('span', {class: 'k', style: 'background:' + COLORS[j % COLORS.length]}, legend);
    legend.appendChild(document.createTextNode(w.name + ' '));
  });
  if (!walks.length) legend.appendChild(document.createTextNode('none anchored.'));
}
// The change list's rows on the plans: boxes, each selecting its row.
function drawMarks(rows) {
  for (const k in planMarks) delete planMarks[k];
  planLayers.forEach((layer, si) => {
    layer.marks.textContent = '';
    rows.forEach((c, i) => {
      if (storeyIndex(c) !== si) return;
      const a = local(c.min), b = local(c.max);
      const r = el('svg:rect', {class: markClass(c), x: a[0], y: a[1], width: Math.max(b[0] - a[0], 0.05),
                                height: Math.max(b[1] - a[1], 0.05), 'data-change': i}, layer.marks);
      el('svg:title', {}, r, c.name + ': ' + c.verdict);
      r.addEventListener('click', () => select(i, false));
      (planMarks[i] = planMarks[i] || []).push(r);
    });
  });
}
function markClass(c) {
  if (c.kind === 'gone') return 'gone';
  if (c.ref && c.ref.object || c.kind === 'new object') return 'newobj';
  if (c.kind === 'reappeared' || c.kind === 'in place again') return 'reappeared';
  return c.kind.endsWith('missing') ? 'missing' : 'deviating';
}
// The compared elements' cuts over the plan, each in the colour of its deviation (deviationColor);
// returns how many elements of each verdict it drew.
function drawDeviations(st, parent) {
  const n = {within: 0, beyond: 0, not_observed: 0};
  if (!DEV || !st.segment_elements) return n;
  const g = el('svg:g', {class: 'deviation'}, parent);
  for (const cls in st.segment_elements) {
    const s = st.segments[cls], runs = st.segment_elements[cls];
    let i = 0;
    for (let r = 0; r + 1 < runs.length; r += 2) {
      const e = devOf(runs[r]), first = i;
      i += 4 * runs[r + 1];
      if (!e) continue;
      let d = '';
      for (let k = first; k + 3 < i; k += 4) d += 'M' + s[k] + ' ' + s[k + 1] + 'L' + s[k + 2] + ' ' + s[k + 3];
      const path = el('svg:path', {class: 'dev dev-' + DEV_NAMES[e[1]], d: d, stroke: hex(deviationColor(e))}, g);
      const m = D.model3d.elements[runs[r]];
      el('svg:title', {}, path, (m ? m.n + ' (' + m.c + '): ' : '') + deviationText(e));
      ++n[DEV_NAMES[e[1]]];
    }
  }
  return n;
}
function buildPlans() {
  const body = document.getElementById('plans-body');
  if (DEV) {
    const legend = deviationLegend(document.getElementById('plans-deviation'));
    const lab = el('label', {}, legend);
    const cb = el('input', {type: 'checkbox', id: 'plans-by-deviation'}, lab);
    cb.checked = true;
    lab.appendChild(document.createTextNode(' shown'));
    cb.addEventListener('change', () => document.querySelectorAll('.plan g.deviation').forEach(
      g => { g.style.display = cb.checked ? '' : 'none'; }));
  }
  // The model's box, grown to hold the anchored trajectories (a walk may start outside).
  const bmin = D.bounds.min.slice(), bmax = D.bounds.max.slice();
  const grow = t => {
    for (let i = 0; i + 2 < t.length; i += 3) {
      for (let k = 0; k < 2; ++k) { bmin[k] = Math.min(bmin[k], t[i + k]); bmax[k] = Math.max(bmax[k], t[i + k]); }
    }
  };
  D.sessions.forEach(s => grow(s.trajectory || []));
  (D.visits || []).forEach(v => v.walks.forEach(w => w.runs.forEach(r => grow(r.xyz))));
  const x0 = bmin[0] - 1.5, x1 = bmax[0] + 1.5, y0 = bmin[1] - 2.5, y1 = bmax[1] + 1.5;
  D.storeys.forEach((st, si) => {
    el('h3', {id: 'plan-' + si}, body, st.name + ' (cut ' + fmt(st.cut_z + O[2], 2) + ' m)');
    const div = el('div', {class: 'plan'}, body);
    const svg = el('svg:svg', {viewBox: [x0, -y1, x1 - x0, y1 - y0].join(' '),
                               'data-storey': st.name}, div);
    const g = el('svg:g', {transform: 'scale(1,-1)'}, svg);
    for (const cls of ['other', 'window', 'door', 'column', 'wall']) {
      const s = st.segments[cls];
      if (!s) continue;
      let d = '';
      for (let i = 0; i + 3 < s.length; i += 4) d += 'M' + s[i] + ' ' + s[i + 1] + 'L' + s[i + 2] + ' ' + s[i + 3];
      el('svg:path', {class: cls, d: d}, g);
    }
    planStats.push({storey: st.name, stairs: drawStairs(si, g), walk: drawRuns(D.reference_runs, si, 'walk', g)[0],
                    trajectory: 0, trajectory_on_flights: 0, deviation: drawDeviations(st, g)});
    // The selected visit's walks and loops, and the change list's marks: drawn again when the
    // timeline or the list changes (drawWalks, drawMarks).
    planLayers.push({walks: el('svg:g', {class: 'walks'}, g), marks: el('svg:g', {class: 'marks'}, g)});
    // Scale bar, bottom left (outside the flipped group so that its text reads).
    const L = niceLength(x1 - x0), sx = x0 + 0.8, sy = -y0 - 0.9;
    el('svg:rect', {x: sx, y: sy, width: L, height: 0.18, fill: '#222'}, svg);
    el('svg:rect', {x: sx + L / 2, y: sy, width: L / 2, height: 0.18, fill: '#fff', stroke: '#222', 'stroke-width': 0.03}, svg);
    el('svg:text', {x: sx, y: sy - 0.15}, svg, '0');
    el('svg:text', {x: sx + L, y: sy - 0.15}, svg, L + ' m');
  });
  drawWalks(visitIndex);
  D.sessions.forEach(s => {
    if (!s.own_frame) return;
    el('h3', {}, body, s.name + ': odometry map in its own frame (not anchored)');
    const pts = b64(s.own_frame.points, Float32Array), tr = s.own_frame.trajectory;
    let lo = [1e9, 1e9], hi = [-1e9, -1e9];
    for (let i = 0; i < tr.length; i += 3) for (let k = 0; k < 2; ++k) { lo[k] = Math.min(lo[k], tr[i + k]); hi[k] = Math.max(hi[k], tr[i + k]); }
    lo = [lo[0] - 12, lo[1] - 12]; hi = [hi[0] + 12, hi[1] + 12];
    const div = el('div', {class: 'plan own-frame'}, body);
    const svg = el('svg:svg', {viewBox: [lo[0], -hi[1], hi[0] - lo[0], hi[1] - lo[1]].join(' ')}, div);
    const g = el('svg:g', {transform: 'scale(1,-1)'}, svg);
    let d = '';
    const zmin = tr.length ? tr[2] - 0.3 : 0;
    for (let i = 0; i < pts.length; i += 3 * 2) {
      if (pts[i] < lo[0] || pts[i] > hi[0] || pts[i + 1] < lo[1] || pts[i + 1] > hi[1] || pts[i + 2] < zmin) continue;
      d += 'M' + pts[i].toFixed(2) + ' ' + pts[i + 1].toFixed(2) + 'h0.08';
    }
    el('svg:path', {d: d, stroke: '#777', 'stroke-width': 0.08}, g);
    let p = '';
    for (let i = 0; i + 2 < tr.length; i += 3) p += tr[i].toFixed(2) + ',' + tr[i + 1].toFixed(2) + ' ';
    el('svg:polyline', {class: 'traj', points: p, stroke: '#d62728'}, g);
  });
}

// ---- plots -----------------------------------------------------------------------------------
function chart(title, series, xlabel, ylabel, opts) {
  opts = opts || {};
  const W = 440, H = 250, l = 48, r = 10, t = 10, b = 36;
  const div = el('div', {class: 'plot' + (opts.cls ? ' ' + opts.cls : '')}, document.getElementById('plots-body'));
  el('h3', {}, div, title);
  const svg = el('svg:svg', {viewBox: '0 0 ' + W + ' ' + H, 'data-plot': title}, div);
  let xmin = Infinity, xmax = -Infinity, ymin = opts.ymin !== undefined ? opts.ymin : Infinity, ymax = -Infinity;
  series.forEach(s => s.x.forEach((x, i) => {
    xmin = Math.min(xmin, x); xmax = Math.max(xmax, x);
    if (opts.ymin === undefined) ymin = Math.min(ymin, s.y[i]);
    ymax = Math.max(ymax, s.y[i]);
  }));
  if (!isFinite(xmin)) { xmin = 0; xmax = 1; ymin = 0; ymax = 1; }
  if (opts.xmin !== undefined) { xmin = opts.xmin; xmax = opts.xmax; }
  if (xmax === xmin) xmax = xmin + 1;
  if (ymax <= ymin) ymax = ymin + 1;
  const X = x => l + (x - xmin) / (xmax - xmin) * (W - l - r);
  const Y = y => H - b - (y - ymin) / (ymax - ymin) * (H - t - b);
  for (let k = 0; k <= 4; ++k) {
    const y = ymin + (ymax - ymin) * k / 4, x = xmin + (xmax - xmin) * k / 4;
    el('svg:line', {class: 'grid', x1: l, x2: W - r, y1: Y(y), y2: Y(y)}, svg);
    el('svg:text', {x: l - 4, y: Y(y) + 4, 'text-anchor': 'end'}, svg, +y.toPrecision(3));
    if (!opts.noXTicks) el('svg:text', {x: X(x), y: H - b + 14, 'text-anchor': 'middle'}, svg, +x.toPrecision(3));
  }
  el('svg:line', {class: 'axis', x1: l, x2: l, y1: t, y2: H - b}, svg);
  el('svg:line', {class: 'axis', x1: l, x2: W - r, y1: H - b, y2: H - b}, svg);
  el('svg:text', {class: 'xlabel', x: (l + W - r) / 2, y: H - 4, 'text-anchor': 'middle'}, svg, xlabel);
  el('svg:text', {class: 'ylabel', x: 12, y: (t + H - b) / 2, transform: 'rotate(-90 12 ' + (t + H - b) / 2 + ')', 'text-anchor': 'middle'}, svg, ylabel);
  series.forEach((s, k) => {
    if (s.mode === 'dots') {
      s.x.forEach((x, i) => el('svg:circle', {cx: X(x), cy: Y(s.y[i]), r: 2.5, fill: s.color}, svg));
    } else if (s.mode === 'bars') {
      const w = (W - l - r) / Math.max(s.x.length, 1) * 0.7;
      s.x.forEach((x, i) => el('svg:rect', {x: X(x) - w / 2, y: Y(s.y[i]), width: w, height: Y(ymin) - Y(s.y[i]), fill: s.color}, svg));
    } else {
      el('svg:polyline', {points: s.x.map((x, i) => X(x).toFixed(1) + ',' + Y(s.y[i]).toFixed(1)).join(' '),
                          fill: 'none', stroke: s.color, 'stroke-width': 1.5}, svg);
    }
    el('svg:text', {x: W - r - 4, y: t + 12 + 13 * k, 'text-anchor': 'end', fill: s.color}, svg, s.name);
  });
  (opts.marks || []).forEach(m => {  // vertical lines at x, named
    el('svg:line', {class: 'mark', x1: X(m.x), x2: X(m.x), y1: t, y2: H - b}, svg);
    if (m.name) el('svg:text', {x: X(m.x) + 3, y: t + 10, fill: '#b42318'}, svg, m.name);
  });
  return svg;
}
function buildPlots() {
  const ape = D.sessions.filter(s => s.ape);
  if (ape.length) {
    chart('APE over time, BIM coordinates, no alignment', ape.map((s, k) => ({
      name: s.name, x: s.ape.t, y: s.ape.e.map(e => e * 100), color: COLORS[k % COLORS.length]})),
      'time since the first scan (s)', 'position error (cm)', {ymin: 0});
  }
  const ms = D.sessions.filter(s => s.scan_ms);
  chart('Odometry time per scan', ms.map((s, k) => ({
    name: s.name, x: s.scan_ms.map((_, i) => i), y: s.scan_ms, color: COLORS[k % COLORS.length]})),
    'scan number', 'odometry time per scan (ms)', {ymin: 0});
  const ok = D.loops.filter(l => l.accepted), no = D.loops.filter(l => !l.accepted);
  chart('Registration fitness of the loop candidates', [
    {name: 'accepted (' + ok.length + ')', x: ok.map(l => l.inlier_ratio), y: ok.map(l => l.inlier_rmse_m * 100), color: '#1a9c3a', mode: 'dots'},
    {name: 'rejected (' + no.length + ')', x: no.map(l => l.inlier_ratio), y: no.map(l => l.inlier_rmse_m * 100), color: '#d62728', mode: 'dots'}],
    'inlier ratio (fraction of points)', 'inlier RMSE (cm)', {ymin: 0});
  // Loop statistics: accepted, then the rejections by reason (their first words), most first.
  const reasons = {};
  no.forEach(l => { const r = String(l.reason).split(/[:(,;]/)[0].trim().slice(0, 40); reasons[r] = (reasons[r] || 0) + 1; });
  const keys = Object.keys(reasons).sort((a, b) => reasons[b] - reasons[a]).slice(0, 5);
  const names = ['accepted'].concat(keys), counts = [ok.length].concat(keys.map(k => reasons[k]));
  const svg = chart('Loop statistics: accepted, and rejected by reason', [
    {name: 'loops', x: names.map((_, i) => i + 0.5), y: counts, color: '#4c78a8', mode: 'bars'}],
    'outcome (numbered below)', 'number of loops', {ymin: 0, noXTicks: true, xmin: 0, xmax: names.length});
  names.forEach((n, i) => {
    const x = 48 + (i + 0.5) / names.length * 382;
    el('svg:text', {x: x, y: 228, 'text-anchor': 'middle'}, svg, (i + 1) + '');
  });
  const list = el('ol', {style: 'font-size:12px;margin:4px 0 0 16px'}, svg.parentNode);
  names.forEach((n, i) => el('li', {}, list, n + ': ' + counts[i]));
  buildDistanceHistograms();
}
// Scan-vs-BIM (issue 34 item 3): per storey, how far the map's points on the model are from it
// (map_bim.ply's signed distances, as change detection measured them; C++ counts every point,
// not only those the 3D view shows), with the tolerance marked. Storeys with no point are left
// out, said in one line.
const histogramStats = [];
function buildDistanceHistograms() {
  const H = D.distances;
  if (!H) return;
  const empty = [];
  H.storeys.forEach(s => {
    if (!s.points) { empty.push(s.name); return; }
    const x = s.counts.map((_, i) => -H.range_cm + (i + 0.5) * H.bin_cm);
    let within = 0;
    s.counts.forEach((c, i) => { if (DEV_T && Math.abs(x[i]) <= DEV_T * 100) within += c; });
    const marks = DEV_T ? [{x: -DEV_T * 100, name: ''}, {x: DEV_T * 100, name: '±' + cm(DEV_T) + ' cm'}] : [];
    const svg = chart('Scan-vs-BIM: distance of the map\'s points to the model, ' + s.name,
      [{name: s.points.toLocaleString() + ' points', x: x, y: s.counts, color: '#4c78a8', mode: 'bars'}],
      'distance to model (cm)', 'points',
      {ymin: 0, xmin: -H.range_cm, xmax: H.range_cm, marks: marks, cls: 'histogram'});
    const share = s.points ? within / s.points : 0;
    el('p', {class: 'histogram-note'}, svg.parentNode, 'Mean ' + fmt(s.mean_cm, 2) + ' cm, RMS ' +
       fmt(s.rms_cm, 2) + ' cm' + (DEV_T ? '; ' + fmt(100 * share, 1) + ' % of the points within ±' +
       cm(DEV_T) + ' cm' : '') + ' (bins of ' + H.bin_cm + ' cm; the points on the model: within ' +
       H.range_cm + ' cm of it; negative: behind its surface).');
    histogramStats.push({storey: s.name, points: s.points, bins: s.counts.length,
                         bars: svg.querySelectorAll('rect').length, within_share: share});
  });
  if (empty.length) {
    el('p', {class: 'histogram-note'}, document.getElementById('plots-body'),
       'Scan-vs-BIM: no map point on the model on ' + empty.join(', ') + '.');
  }
}

// ---- change list and selection ----------------------------------------------------------------
let selected = -1;
function select(i, fly) {
  markRow(i);
  if (view) view.highlight(changeRows[i], fly);
  showHistory(changeRows[i].ref);
}
// The row and its plan marks shown selected.
function markRow(i) {
  selected = i;
  document.querySelectorAll('#changes-body tr.row').forEach(r => r.classList.toggle('selected', +r.dataset.change === i));
  document.querySelectorAll('.plan .selected').forEach(e => e.classList.remove('selected'));
  (planMarks[i] || []).forEach(e => e.classList.add('selected'));
}
function buildChanges() {
  const body = document.getElementById('changes-body');
  buildChangeFilter(body);  // report_visits.js: with a history, since the previous visit or the model
  el('table', {id: 'change-table'}, body);
  if (D.history) el('div', {id: 'history'}, body, 'Click a row, its mark on a plan or an element in the 3D view to see its history.');
  showChanges();
}
// The list of the selected visit and filter (currentRows, report_visits.js), and its plan marks.
function showChanges() {
  changeRows = currentRows();
  selected = -1;
  const t = document.getElementById('change-table');
  t.textContent = '';
  const caption = document.getElementById('change-caption');
  if (caption) caption.textContent = changeCaption(changeRows);
  drawMarks(changeRows);
  if (!changeRows.length) {
    el('caption', {}, t, D.history ? 'No changes.' : 'No changes (or no anchored recording to compare).');
    return;
  }
  const h = el('tr', {}, t);
  ['#', 'kind', 'element / object', 'size (m)', 'position (m)', 'storey', 'room', 'verdict', 'show']
    .forEach(x => el('th', {}, h, x));
  changeRows.forEach((c, i) => changeRow(t, c, i));
}
function changeRow(t, c, i) {
  const tr = el('tr', {class: 'row' + (c.contradiction ? ' contradiction' : ''), 'data-change': i,
                       'data-summary': c.kind + ': ' + c.name}, t);
  el('td', {class: 'num'}, tr, i + 1);
  el('td', {}, tr, c.kind);
  el('td', {}, tr, c.name + (c.global_id ? ' ' + c.global_id : ''));
  el('td', {class: 'num'}, tr, c.size.map(v => fmt(v, 2)).join(' × '));
  el('td', {class: 'num'}, tr, c.position.map(v => fmt(v, 2)).join(', '));
  el('td', {}, tr, c.storey || '');
  el('td', {}, tr, c.room || '');
  const v = el('td', {}, tr, c.verdict);
  if (c.contradiction) el('div', {class: 'contradiction'}, v, '⚠ ' + c.contradiction);
  const td = el('td', {}, tr);
  const ap = el('a', {href: '#plan-' + storeyIndex(c)}, td, 'plan');
  td.appendChild(document.createTextNode(' '));
  const a3 = el('a', {href: '#view3d'}, td, '3D');
  ap.addEventListener('click', e => { e.stopPropagation(); select(i, false); });
  a3.addEventListener('click', e => { e.stopPropagation(); select(i, true); });
  tr.addEventListener('click', () => select(i, true));
}

// ---- 3D view ---------------------------------------------------------------------------------
let view = null;
function distanceColor(d) {  // |distance to the model|: 0 blue, 5 cm green, 15 cm yellow, 30 cm+ red
  const a = Math.min(Math.abs(d) / 0.3, 1);
  const stops = [[0, [0.1, 0.3, 1]], [0.17, [0.1, 0.8, 0.3]], [0.5, [1, 0.85, 0.1]], [1, [0.9, 0.1, 0.1]]];
  for (let k = 1; k < stops.length; ++k) {
    if (a <= stops[k][0]) {
      const f = (a - stops[k - 1][0]) / (stops[k][0] - stops[k - 1][0]);
      return stops[k - 1][1].map((c, j) => c + f * (stops[k][1][j] - c));
    }
  }
  return stops[3][1];
}
function buildView() {
  const host = document.getElementById('viewer-canvas');
  const note = document.getElementById('viewer-note');
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  const W = host.clientWidth || 800, H = host.clientHeight || 560;
  renderer.setSize(W, H);
  renderer.setClearColor(0xf0f2f5);
  host.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.add(new THREE.AmbientLight(0xffffff, 0.6));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, -2, 3);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(50, W / H, 0.05, 2000);
  camera.up.set(0, 0, 1);
  const lo = D.bounds.min, hi = D.bounds.max;
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], 5);
  camera.position.set(centre.x - 0.2 * size, centre.y - 1.1 * size, centre.z + 0.8 * size);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  const layers = document.getElementById('layers');
  const pickable = [];
  function layer(name, obj, on) {
    obj.visible = on;
    scene.add(obj);
    const lab = el('label', {}, layers);
    const cb = el('input', {type: 'checkbox'}, lab);
    cb.checked = on;
    lab.appendChild(document.createTextNode(' ' + name));
    cb.addEventListener('change', () => { obj.visible = cb.checked; requestRender(); });
    return obj;
  }
  // The storey filter: one storey's model elements, map points and walks (the buffers are ordered
  // storey by storey in C++, so a storey is a draw range; walks are split into runs by storey).
  const filtered = [];
  function showStorey(si) {  // -1: all storeys
    filtered.forEach(o => {
      if (o.isGroup) {
        o.children.forEach(c => { c.visible = si < 0 || c.userData.storeys.includes(si); });
      } else {
        const r = o.userData.ranges;
        if (si < 0 || !r || !r[si]) o.geometry.setDrawRange(0, Infinity);
        else o.geometry.setDrawRange(r[si][0], r[si][1]);
      }
    });
    requestRender();
  }
  function runLines(runs, color) {
    const grp = new THREE.Group();
    (runs || []).forEach(r => {
      const l = line(r.xyz, color);
      l.userData.storeys = [r.lower, r.upper];
      grp.add(l);
    });
    filtered.push(grp);
    return grp;
  }
  const fl = el('label', {}, layers, 'Storey ');
  const sel = el('select', {id: 'storey-filter'}, fl);
  el('option', {value: -1}, sel, 'all storeys');
  D.storeys.forEach((st, i) => el('option', {value: i}, sel, st.name));
  sel.addEventListener('change', () => showStorey(+sel.value));
  const palette = {IfcWall: 0xb0b0b0, IfcWallStandardCase: 0xb0b0b0, IfcSlab: 0xd8d0c0, IfcDoor: 0xb8860b,
                   IfcWindow: 0x3a8fd6, IfcColumn: 0x909090, IfcStair: 0xa08060, IfcFurnishingElement: 0x7fa07f};
  // The model coloured by IFC class or by each element's deviation (deviationColor; elements
  // share no vertices, so a vertex has its element's colour).
  const modelMeshes = [];
  function colourModel(mode) {
    const dev = mode === 'deviation';
    modelMeshes.forEach(m => {
      m.material.vertexColors = dev ? THREE.VertexColors : THREE.NoColors;
      m.material.color.setHex(dev ? 0xffffff : m.userData.color);
      m.material.opacity = dev ? 0.45 : 0.28;
      m.material.needsUpdate = true;
    });
    requestRender();
  }
  if (DEV) {
    const ml = el('label', {}, layers, 'Model colour ');
    const mode = el('select', {id: 'model-colour'}, ml);
    el('option', {value: 'deviation'}, mode, 'by deviation');
    el('option', {value: 'class'}, mode, 'by IFC class');
    mode.addEventListener('change', () => colourModel(mode.value));
    deviationLegend(layers);
  }
  el('strong', {}, layers, 'Model (per class)');
  const coloured = {within: 0, beyond: 0, not_observed: 0, not_compared: 0};  // triangles
  D.model3d.classes.forEach(c => {
    const g = new THREE.BufferGeometry();
    const pos = b64(c.positions, Float32Array), idx = b64(c.indices, Uint32Array);
    const element = b64(c.element, Uint32Array);
    g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    g.setIndex(new THREE.BufferAttribute(idx, 1));
    g.computeVertexNormals();
    if (DEV) {
      const col = new Float32Array(pos.length);
      for (let t = 0; t < element.length; ++t) {
        const e = devOf(element[t]);
        ++coloured[e ? DEV_NAMES[e[1]] : 'not_compared'];
        const rgb = deviationColor(e);
        for (let k = 0; k < 3; ++k) col.set(rgb, 3 * idx[3 * t + k]);
      }
      g.setAttribute('color', new THREE.BufferAttribute(col, 3));
    }
    const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({color: palette[c.name] || 0xc0c0c0,
      transparent: true, opacity: 0.28, depthWrite: false, side: THREE.DoubleSide}));
    m.userData = {kind: 'model', element: element, ranges: c.storeys, color: palette[c.name] || 0xc0c0c0};
    if (DEV) modelMeshes.push(m);
    filtered.push(m);
    const slab = c.name === 'IfcSlab' || c.name === 'IfcRoof' || c.name === 'IfcCovering';
    layer(c.name + ' (' + c.triangles + ')', m, !slab);
    pickable.push(m);
  });
  el('strong', {}, layers, 'Results');
  if (D.map) {
    D.map.sessions.forEach(s => {
      const p = b64(s.points, Float32Array), d = b64(s.distance, Float32Array);
      const col = new Float32Array(p.length);
      for (let i = 0; i < d.length; ++i) col.set(distanceColor(d[i]), 3 * i);
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(p, 3));
      g.setAttribute('color', new THREE.BufferAttribute(col, 3));
      const pts = new THREE.Points(g, new THREE.PointsMaterial({size: 0.05, vertexColors: THREE.VertexColors}));
      pts.userData = {kind: 'map', distance: d, session: s.name, ranges: s.storeys};
      filtered.push(pts);
      layer('map of ' + s.name + ' by distance', pts, true);
      pickable.push(pts);
    });
    note.textContent = 'The map is shown decimated: ' + D.map.shown.toLocaleString() + ' of ' +
      D.map.total.toLocaleString() + ' points (at most ' + D.config.max_map_points.toLocaleString() +
      ', so that a laptop browser renders it smoothly); colour = distance to the model: blue 0, ' +
      'green 5 cm, yellow 15 cm, red 30 cm or more.';
  } else {
    note.textContent = 'No map in BIM coordinates: no recording was anchored.';
  }
  D.objects.forEach(o => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(b64(o.positions, Float32Array), 3));
    const c8 = b64(o.colors, Uint8Array), c = new Float32Array(c8.length);
    for (let i = 0; i < c8.length; ++i) c[i] = c8[i] / 255;
    g.setAttribute('color', new THREE.BufferAttribute(c, 3));
    g.setIndex(new THREE.BufferAttribute(b64(o.indices, Uint32Array), 1));
    g.computeVertexNormals();
    const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors}));
    m.userData = {kind: 'object', object: b64(o.object, Int32Array), session: o.session, ranges: o.storeys};
    filtered.push(m);
    layer('new objects of ' + o.session, m, true);
    pickable.push(m);
  });
  const miss = b64(D.missing3d.positions, Float32Array);
  if (miss.length) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(miss, 3));
    g.computeVertexNormals();
    const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({color: 0xe02020,
      transparent: true, opacity: 0.85, side: THREE.DoubleSide}));
    m.userData = {ranges: D.missing3d.storeys};
    filtered.push(m);
    layer('missing elements (red)', m, true);
  }
  function line(xyz, color) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(xyz), 3));
    return new THREE.Line(g, new THREE.LineBasicMaterial({color: color}));
  }
  if (D.reference_runs) layer('reference walk', runLines(D.reference_runs, 0x666666), true);
  D.sessions.forEach((s, k) => {
    if (s.runs) layer('trajectory ' + s.name, runLines(s.runs, COLORS[k % COLORS.length]), true);
    if (s.own_frame) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(b64(s.own_frame.points, Float32Array), 3));
      const grp = new THREE.Group();
      grp.add(new THREE.Points(g, new THREE.PointsMaterial({size: 0.05, color: 0x777777})));
      grp.add(line(s.own_frame.trajectory, 0xd62728));
      layer(s.name + ': NOT anchored, odometry map in its own frame', grp, false);
    }
  });
  let box = null;
  function render() { renderer.render(scene, camera); }
  // What changes the view draws it once at the next frame, however many changes come before it
  // (the orbit controls' events, a row of checkboxes, the self-test flipping eight classes four
  // times: 32 software-WebGL frames of a 300 000-point map, 2/3 of the browser test's CPU time);
  // drawnPixels() draws at once.
  let pending = false;
  function requestRender() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => { pending = false; render(); });
  }
  controls.addEventListener('change', requestRender);
  // Click-to-inspect (a click, not the end of a drag).
  const ray = new THREE.Raycaster();
  ray.params.Points.threshold = 0.06;
  let down = null;
  renderer.domElement.addEventListener('pointerdown', e => { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', e => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const r = renderer.domElement.getBoundingClientRect();
    ray.setFromCamera(new THREE.Vector2((e.clientX - r.left) / r.width * 2 - 1, -(e.clientY - r.top) / r.height * 2 + 1), camera);
    const hit = ray.intersectObjects(pickable.filter(o => o.visible), false)[0];
    inspect(hit);
  });
  function inspect(hit) {
    const box_ = document.getElementById('inspect');
    if (!hit) { box_.textContent = 'Nothing there.'; return; }
    const u = hit.object.userData, p = hit.point;
    const at = 'at (' + [p.x + O[0], p.y + O[1], p.z + O[2]].map(v => v.toFixed(2)).join(', ') + ') m';
    if (u.kind === 'model') {
      const e = D.model3d.elements[u.element[hit.faceIndex]];
      const dev = DEV ? ', ' + deviationText(devOf(u.element[hit.faceIndex])) : '';
      box_.textContent = e.c + ' "' + e.n + '" ' + e.g + (e.s ? ', ' + e.s : '') + dev + ', ' + at;
      if (historyElement(e.g)) inspectHistory({element: e.g});
    } else if (u.kind === 'map') {
      box_.textContent = 'map point of ' + u.session + ', ' + fmt(u.distance[hit.index] * 100, 1) + ' cm from the model, ' + at;
    } else if (u.kind === 'object') {
      const id = u.object[hit.face.a];
      box_.textContent = 'new object ' + id + ' of ' + u.session + ', ' + at;
      const tracked = objectOfDetection(visitLabel(newestVisit()), u.session, id);
      const i = changeRows.findIndex(c => c.kind === 'new object' && c.id === id && c.session === u.session);
      if (tracked) inspectHistory({object: tracked});
      else if (i >= 0) select(i, false);
    }
  }
  function highlight(c, fly) {
    if (box) scene.remove(box);
    const a = local(c.min), b = local(c.max);
    box = new THREE.Box3Helper(new THREE.Box3(new THREE.Vector3(a[0] - 0.05, a[1] - 0.05, a[2] - 0.05),
      new THREE.Vector3(b[0] + 0.05, b[1] + 0.05, b[2] + 0.05)), 0x0050ff);
    scene.add(box);
    if (fly) {
      const m = new THREE.Vector3((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
      camera.position.copy(m).add(new THREE.Vector3(-3, -5, 4));
      controls.target.copy(m);
      controls.update();
    }
    document.getElementById('inspect').textContent = c.kind + ': ' + c.name + ', ' + c.verdict;
    render();
  }
  // Pixels that differ from the background: the self-test's "the 3D view is not blank".
  function drawnPixels() {
    render();
    const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 0xf0) + Math.abs(px[i + 1] - 0xf2) + Math.abs(px[i + 2] - 0xf5) > 24) ++n;
    }
    return {drawn: n, total: w * h};
  }
  // The self-test's "the colours are on the screen": the model alone (every other layer hidden
  // for the count), pixels whose colour leans green (within) or red (beyond), in a mode.
  function colourPixels(mode) {
    colourModel(mode);
    const hidden = [];
    scene.children.forEach(o => {
      if (o.visible && !modelMeshes.includes(o) && !o.isLight) { hidden.push(o); o.visible = false; }
    });
    render();
    const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let green = 0, red = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i + 1] > px[i] + 25 && px[i + 1] > px[i + 2] + 20) ++green;
      if (px[i] > px[i + 1] + 40 && px[i] > px[i + 2] + 40) ++red;
    }
    hidden.forEach(o => { o.visible = true; });
    return {green: green, red: red};
  }
  if (DEV) colourModel('deviation');  // by deviation at first
  render();
  return {highlight: highlight, drawnPixels: drawnPixels, render: render, coloured: coloured,
          colourPixels: DEV ? colourPixels : null, colourModel: colourModel};
}

// ---- start -----------------------------------------------------------------------------------
const timings = {start_ms: Math.round(performance.now())};
function section(name, build) {
  const t0 = performance.now();
  try { build(); } catch (e) { window.reportErrors.push(name + ': ' + (e && e.stack || e)); console.log(e); }
  timings[name] = Math.round(performance.now() - t0);
}
section('summary', buildSummary);
section('timeline', buildTimeline);
section('plans', buildPlans);
section('plots', buildPlots);
section('changes', buildChanges);
section('3D view', () => { view = buildView(); });

// #selftest: what tests/integration/report_browser_test.cpp checks, written into the page.
if (location.hash === '#selftest') {
  requestAnimationFrame(() => {
    const r = {errors: window.reportErrors.slice(), timings_ms: timings};
    r.plans = document.querySelectorAll('#plans-body svg').length;
    r.plan_stats = JSON.parse(JSON.stringify(planStats));
    r.axis_labels = [...document.querySelectorAll('#plots-body svg')].map(svg =>
      [svg.querySelector('.xlabel').textContent, svg.querySelector('.ylabel').textContent]);
    r.plan_paths = document.querySelectorAll('#plans-body svg path.wall').length;
    r.plots = document.querySelectorAll('#plots-body svg').length;
    r.histograms = histogramStats;  // Scan-vs-BIM, per storey with points on the model
    r.histogram_labels = [...document.querySelectorAll('#plots-body .histogram svg')].map(svg =>
      [svg.querySelector('.xlabel').textContent, svg.querySelector('.ylabel').textContent]);
    r.changes = D.changes.length;
    r.not_anchored_banners = document.querySelectorAll(
      '#summary .banner:not(.odometry-untrusted):not(.anchored-in-parts)').length;
    r.in_parts_banners = document.querySelectorAll('#summary .banner.anchored-in-parts').length;
    const untrusted = document.querySelectorAll('#summary .banner.odometry-untrusted');
    r.untrusted_banners = untrusted.length;
    r.untrusted_text = untrusted.length ? untrusted[0].textContent : '';
    const scores = document.querySelector('#summary td.scores');
    r.scores_in_view = scores && scores.querySelector('.in-view') ? scores.querySelector('.in-view').textContent : '';
    r.scores_all = scores && scores.querySelector('.all-objects') ? scores.querySelector('.all-objects').textContent : '';
    r.own_frame_plans = document.querySelectorAll('.plan.own-frame svg').length;
    const visits = document.querySelector('#summary p.visits');
    r.visits_text = visits ? visits.textContent : '';
    r.pixels = view ? view.drawnPixels() : null;
    // The class toggles: every model class switched off draws fewer pixels; on again, as many.
    const classes = [...document.querySelectorAll('#layers input')].slice(0, D.model3d.classes.length);
    const flip = on => classes.forEach(cb => {
      cb.checked = on; cb.dispatchEvent(new Event('change'));
    });
    if (view && classes.length) {
      const shown = classes.filter(cb => cb.checked);
      flip(true);
      const all = view.drawnPixels().drawn;
      flip(false);
      const none = view.drawnPixels().drawn;
      flip(true);
      r.toggles = {classes: classes.length, all: all, none: none, again: view.drawnPixels().drawn};
      classes.forEach(cb => { cb.checked = shown.includes(cb); cb.dispatchEvent(new Event('change')); });
    }
    // The storey filter: each storey alone draws fewer pixels than all of them; all again, as many.
    const sel = document.getElementById('storey-filter');
    if (view && sel) {
      const show = v => { sel.value = String(v); sel.dispatchEvent(new Event('change')); return view.drawnPixels().drawn; };
      const all = show(-1);
      r.storey_filter = {storeys: D.storeys.length, all: all, each: D.storeys.map((_, i) => show(i)), again: show(-1)};
    }
    // Click-to-inspect: a click (pointer down and up in place) at the middle of the 3D view.
    const canvas = document.querySelector('#viewer-canvas canvas');
    if (canvas) {
      const b = canvas.getBoundingClientRect(), x = b.left + b.width / 2, y = b.top + b.height / 2;
      canvas.dispatchEvent(new PointerEvent('pointerdown', {clientX: x, clientY: y, bubbles: true}));
      canvas.dispatchEvent(new PointerEvent('pointerup', {clientX: x, clientY: y, bubbles: true}));
      r.inspect = document.getElementById('inspect').textContent;
    }
    const row = document.querySelector('#changes-body tr.row');
    if (row) {
      row.click();
      r.selected_row = row.classList.contains('selected');
      r.selected_plan = document.querySelectorAll('.plan .selected').length;
      r.selected_change = selected;
    }
    // The deviation views: the elements by verdict, drawn on the plans and coloured in 3D, and
    // the colours on the screen by deviation and by class (then back to deviation).
    if (DEV) {
      const count = {within: 0, beyond: 0, not_observed: 0};
      D.deviation.elements.forEach(e => ++count[DEV_NAMES[e[1]]]);
      r.deviation = {tolerance_cm: DEV_T * 100, elements: count,
                     plans: planStats.map(s => s.deviation),
                     legends: [...document.querySelectorAll('.deviation-legend')].map(p => p.textContent)};
      if (view) {
        r.deviation.triangles = view.coloured;
        r.deviation.pixels = {classes: view.colourPixels('class'), deviation: view.colourPixels('deviation')};
      }
    }
    r.visits_test = visitsSelfTest();  // report_visits.js: the timeline, the filter, a history
    el('pre', {id: 'selftest'}, document.body, JSON.stringify(r));
    document.title = 'selftest done';
  });
}
