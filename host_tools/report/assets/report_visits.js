// SPDX-License-Identifier: BSD-3-Clause
// SPDX-FileCopyrightText: 2026 The bimslam authors
// The project's visits (issue 33 item 6): the timeline, the selected visit's walks on the plans,
// the change list since the previous visit or since the model (OUT/history.json, its schema in
// host_tools/mapping/README.md, "History"), and an element's or object's history on click.
// Loaded before report.js, whose globals (D, el, fmt, select, drawWalks, ...) it uses when called.
'use strict';

let visitIndex = -1;  // the selected visit: an index into D.visits (the newest at first)
let changeFilter = 'detected';  // 'previous', 'model' or 'detected' (each recording's, newest)
let changeRows = [];  // the change list's rows as shown

function newestVisit() { return D.visits ? D.visits.length - 1 : -1; }
function visitLabel(k) { return D.visits && k >= 0 ? D.visits[k].label : ''; }
function visitStart(label) {
  const v = (D.visits || []).find(x => x.label === label);
  return v ? v.start : '';
}
// The walks the plans draw for visit k: its anchored recordings' (the sessions of the summary
// without a list of visits, from an older bimslam).
function walksOf(k) {
  if (D.visits && k >= 0) return D.visits[k].walks;
  return D.sessions.filter(s => s.runs).map(s => ({name: s.name, runs: s.runs}));
}
function historyChanges(label) {
  return D.history ? D.history.changes.find(c => c.visit === label) : null;
}
function historyElement(gid) {
  return D.history ? D.history.elements.find(e => e.global_id === gid) : null;
}
function historyObject(id) {
  return D.history ? D.history.objects.find(o => o.id === id) : null;
}
function contradictionsOf(gid) {
  return D.history ? D.history.contradictions.filter(c => c.global_id === gid) : [];
}

// ---- timeline --------------------------------------------------------------------------------
function buildTimeline() {
  const body = document.getElementById('visits-body');
  if (!D.visits) {
    el('p', {}, body, 'One visit (the output of an older bimslam, without a list of visits).');
    return;
  }
  visitIndex = newestVisit();
  const list = el('ol', {class: 'timeline'}, body);
  D.visits.forEach((v, k) => {
    const b = el('button', {class: 'visit', 'data-visit': v.label, type: 'button'}, el('li', {}, list));
    el('strong', {}, b, v.label);
    el('span', {class: 'when'}, b, v.start.replace('T', ' ').replace('Z', ' UTC'));
    el('span', {}, b, v.recordings.map(r => r.name + ' ' + (r.anchor_verdict || 'not anchored')).join(', '));
    el('span', {class: 'counts'}, b, visitCounts(v.label));
    b.addEventListener('click', () => selectVisit(k));
  });
  el('p', {class: 'legend'}, body, 'Click a visit: the plans draw its walks and the change list ' +
     'shows its changes. The summary above is of the newest visit.');
  markTimeline();
}
// What changed at a visit since the one before (history.json), as a short line.
function visitCounts(label) {
  const c = historyChanges(label);
  if (!c) return '';
  const p = c.since_previous;
  const m = c.since_model;
  if (!p) return 'first visit: ' + count(m.new_objects.length, 'new object') + ', ' + m.missing.length +
                 ' missing, ' + m.deviating.length + ' deviating';
  const parts = [['new', p.new], ['gone', p.gone], ['moved', p.moved], ['newly missing', p.newly_missing],
                 ['newly deviating', p.newly_deviating], ['reappeared', p.reappeared],
                 ['in place again', p.in_place_again]].filter(x => x[1].length);
  return parts.length ? parts.map(x => x[1].length + ' ' + x[0]).join(', ') : 'no change since ' + c.previous;
}
function count(n, what) { return n + ' ' + what + (n === 1 ? '' : 's'); }
function markTimeline() {
  document.querySelectorAll('#visits-body button.visit').forEach(b =>
    b.classList.toggle('selected', b.dataset.visit === visitLabel(visitIndex)));
}
function selectVisit(k) {
  visitIndex = k;
  markTimeline();
  drawWalks(k);
  showChanges();
}

// ---- the change list's rows from the history ----------------------------------------------------
function box(min, max) {
  const size = [0, 1, 2].map(i => max[i] - min[i]);
  return {min: min, max: max, size: size, position: [0, 1, 2].map(i => (min[i] + max[i]) / 2)};
}
// An object where visit `label` saw it (its sighting), else where it was last seen.
function objectRow(id, label, kind, verdict) {
  const o = historyObject(id);
  const s = o.sightings.find(x => x.visit === label && x.centroid);
  const b = s ? box(s.centroid.map((c, i) => c - s.size_m[i] / 2), s.centroid.map((c, i) => c + s.size_m[i] / 2))
              : box(o.box_min, o.box_max);
  return Object.assign(b, {kind: kind, name: 'object ' + id, storey: o.storey, room: '', verdict: verdict,
                           ref: {object: id}});
}
function elementRow(gid, kind, verdict) {
  const e = historyElement(gid);
  verdict = verdict.replace('@', e ? lastObservedBefore(e, visitLabel(visitIndex)) : '?');
  const b = e && e.min ? box(e.min, e.max) : box([0, 0, 0], [0, 0, 0]);
  const c = contradictionsOf(gid).filter(x => x.contradicted_by === visitLabel(visitIndex));
  return Object.assign(b, {kind: kind, name: e ? e.name + ' (' + e['class'] + ')' : gid, global_id: gid,
                           storey: e ? e.storey : '', room: '', verdict: verdict, ref: {element: gid},
                           contradiction: c.map(x => 'contradicts ' + x.visit + ' (' + x.verdict + ')').join('; ')});
}
// The last visit before `label` that observed the element: what its change compares with.
function lastObservedBefore(e, label) {
  let last = '?';
  D.history.visits.forEach((v, k) => {
    if (v.start < visitStart(label) && e.verdicts[k] !== 'not_observed') last = v.label;
  });
  return last;
}
function mm(v) { return Math.round(Math.hypot(v[0], v[1], v[2]) * 1000) + ' mm'; }
function rowsSincePrevious(label) {
  const c = historyChanges(label), p = c && c.since_previous;
  if (!p) return [];
  const since = ' since ' + c.previous;
  return [].concat(
    p.new.map(id => objectRow(id, label, 'new', 'new' + since)),
    p.gone.map(id => objectRow(id, label, 'gone', 'gone' + since)),
    p.moved.map(m => objectRow(m.id, label, 'moved', 'moved by ' + mm(m.offset_m) + ' (' +
                               m.offset_m.map(v => fmt(v, 2)).join(', ') + ' m)' + since)),
    // An element compares with the last earlier visit that observed it ('@').
    p.newly_missing.map(g => elementRow(g, 'newly missing', 'built on @, missing now')),
    p.newly_deviating.map(g => elementRow(g, 'newly deviating', 'confirmed on @, deviating now')),
    p.reappeared.map(g => elementRow(g, 'reappeared', 'missing on @, built now')),
    p.in_place_again.map(g => elementRow(g, 'in place again', 'deviating on @, in place now')));
}
function rowsSinceModel(label) {
  const c = historyChanges(label);
  if (!c) return [];
  const m = c.since_model, asOf = x => ' (as of ' + x.as_of + ')';
  return [].concat(
    m.new_objects.map(o => objectRow(o.id, o.as_of, 'new object', 'present' + asOf(o))),
    m.missing.map(e => elementRow(e.global_id, 'missing', 'missing' + asOf(e))),
    m.deviating.map(e => elementRow(e.global_id, 'deviating', 'deviating by ' + mm(e.offset_m) + asOf(e))));
}
// Each recording's detections of the newest visit (changes.json), as the page showed before
// visits: with their history when there is one.
function rowsDetected() {
  const newest = visitLabel(newestVisit());
  return D.changes.map(c => Object.assign({}, c, {ref: c.global_id ? {element: c.global_id}
    : {object: objectOfDetection(newest, c.session, c.id)}}));
}
function objectOfDetection(label, recording, index) {
  const o = (D.history ? D.history.objects : []).find(x => x.sightings.some(s =>
    s.visit === label && s.recording === recording && s.object === index));
  return o ? o.id : null;
}
function currentRows() {
  if (changeFilter === 'previous') return rowsSincePrevious(visitLabel(visitIndex));
  if (changeFilter === 'model') return rowsSinceModel(visitLabel(visitIndex));
  return rowsDetected();
}
// The filter above the list: since the previous visit or the model (with a history), or each
// recording's detections of the newest visit.
function buildChangeFilter(body) {
  if (!D.history) return;
  const p = el('p', {class: 'filter'}, body, 'Show ');
  const sel = el('select', {id: 'change-filter'}, p);
  el('option', {value: 'previous'}, sel, 'changes since the previous visit');
  el('option', {value: 'model'}, sel, 'changes since the model (as of the selected visit)');
  el('option', {value: 'detected'}, sel, 'each recording\'s detections (newest visit)');
  const first = !historyChanges(visitLabel(visitIndex)) || !historyChanges(visitLabel(visitIndex)).since_previous;
  changeFilter = first ? 'model' : 'previous';
  sel.value = changeFilter;
  sel.addEventListener('change', () => { changeFilter = sel.value; showChanges(); });
  el('span', {id: 'change-caption'}, p);
}
function changeCaption(rows) {
  const label = visitLabel(visitIndex), c = historyChanges(label);
  if (changeFilter === 'detected') return ': the newest visit\'s, ' + rows.length + ' rows.';
  if (changeFilter === 'previous' && c && !c.since_previous) return ': ' + label + ' is the first visit (see since the model).';
  return ': visit ' + label + (changeFilter === 'previous' ? ' against ' + c.previous : '') + ', ' + rows.length + ' rows.';
}

// ---- history on click ------------------------------------------------------------------------
// Shows an element's ({element: GlobalId}) or object's ({object: id}) history in #history.
function showHistory(ref) {
  const box_ = document.getElementById('history');
  if (!box_ || !D.history || !ref) return;
  box_.textContent = '';
  if (ref.element) elementHistory(box_, ref.element);
  else if (ref.object) objectHistory(box_, ref.object);
  else el('p', {}, box_, 'No history: the history does not follow this object.');
}
function elementHistory(box_, gid) {
  const e = historyElement(gid);
  if (!e) { el('p', {}, box_, 'No visit observed element ' + gid + '.'); return; }
  el('h3', {}, box_, 'History of ' + e.name + ' (' + e['class'] + ') ' + gid + ', ' + e.storey);
  const t = el('table', {class: 'history'}, box_);
  ['visit', 'date', 'verdict'].forEach(x => el('th', {}, t, x));
  D.history.visits.forEach((v, k) => {
    const verdict = e.verdicts[k], d = e.deviations.find(x => x.visit === v.label);
    const tr = el('tr', {class: 'hv verdict-' + verdict, 'data-visit': v.label, 'data-verdict': verdict}, t);
    el('td', {}, tr, v.label);
    el('td', {}, tr, v.start.replace('T', ' ').replace('Z', ' UTC'));
    el('td', {}, tr, verdict.replace('_', ' ') + (d ? ' by ' + mm(d.offset_m) + (d.moved ? ' (moved, ' +
       fmt(d.moved_yaw_deg, 1) + '° about z)' : '') : ''));
  });
  el('p', {}, box_, 'First seen built ' + (e.first_seen_built || 'never') + ', last seen built ' +
     (e.last_seen_built || 'never') + '; last observed ' + (e.last_observed || 'never') + ' (' +
     String(e.last_verdict).replace('_', ' ') + ').');
  contradictionsOf(gid).forEach(c => el('p', {class: 'contradiction'}, box_, '⚠ Contradiction: ' +
    c.contradicted_by + ' (' + c.by_verdict + ') contradicts ' + c.visit + ' (' + c.verdict + '); both are kept.'));
}
function objectHistory(box_, id) {
  const o = historyObject(id);
  el('h3', {}, box_, 'History of object ' + id + ', ' + o.storey + ': ' + o.state +
     (o.gone_in ? ' (gone in ' + o.gone_in + ')' : '') + ', first seen ' + o.first_seen + ', last seen ' + o.last_seen);
  const t = el('table', {class: 'history'}, box_);
  ['visit', 'date', 'sighting', 'centre (m)', 'size (m)'].forEach(x => el('th', {}, t, x));
  o.sightings.forEach(s => {
    const tr = el('tr', {class: 'hv', 'data-visit': s.visit, 'data-verdict': s.status}, t);
    el('td', {}, tr, s.visit);
    el('td', {}, tr, visitStart(s.visit).replace('T', ' ').replace('Z', ' UTC'));
    el('td', {}, tr, s.status.replace('_', ' ') + (s.part ? ' in part (a ' + s.part.size_m.map(v => fmt(v, 2)).join(' × ') + ' m piece)' : '') +
       (s.offset_m ? ' by ' + mm(s.offset_m) : '') +
       (s.floor_seen !== undefined ? ' (' + fmt(100 * s.floor_seen, 0) + ' % of its floor seen)' : ''));
    el('td', {class: 'num'}, tr, s.centroid ? s.centroid.map(v => fmt(v, 2)).join(', ') : '–');
    el('td', {class: 'num'}, tr, s.size_m ? s.size_m.map(v => fmt(v, 2)).join(' × ') : '–');
  });
}
// A click in the 3D view on an element or a new object: its history, and its row (and plan
// marks) shown selected when it is listed.
function inspectHistory(ref) {
  showHistory(ref);
  const e = ref.element ? historyElement(ref.element) : null, o = ref.object ? historyObject(ref.object) : null;
  const line = e ? D.history.visits.map((v, k) => v.label + ' ' + e.verdicts[k].replace('_', ' '))
                 : o.sightings.map(s => s.visit + ' ' + s.status.replace('_', ' '));
  el('div', {class: 'inspect-history'}, document.getElementById('inspect'),
     'History: ' + line.join('; ') + ' (under the change list).');
  markRow(changeRows.findIndex(r => r.ref && (ref.element ? r.ref.element === ref.element : r.ref.object === ref.object)));
}

// ---- self-test (report.html#selftest) ------------------------------------------------------------
// Every visit selected on the timeline (the walks drawn on the plans, the rows of each filter);
// then the newest again, since the previous visit: a gone object's plan mark clicked (its
// sightings), and the first row with a contradiction (its history's per-visit verdicts).
function visitsSelfTest() {
  const r = {visits: (D.visits || []).map(v => v.label), selected: visitLabel(visitIndex),
             filter: changeFilter, walks: {}, rows: {}};
  const sel = document.getElementById('change-filter');
  const rows = f => { sel.value = f; sel.dispatchEvent(new Event('change'));
    return [...document.querySelectorAll('#changes-body tr.row')].map(tr => tr.dataset.summary); };
  document.querySelectorAll('#visits-body button.visit').forEach(b => {
    b.click();
    r.walks[b.dataset.visit] = [...new Set([...document.querySelectorAll('#plans-body polyline.traj')]
      .map(p => p.dataset.walk))];
    if (sel) r.rows[b.dataset.visit] = {previous: rows('previous'), model: rows('model')};
  });
  if (!sel) return r;
  [...document.querySelectorAll('#visits-body button.visit')].pop().click();
  rows('previous');
  const gone = document.querySelector('.plan rect.gone');  // an object's history from its plan mark
  if (gone) {
    gone.dispatchEvent(new MouseEvent('click', {bubbles: true}));
    r.plan_history = [...document.querySelectorAll('#history tr.hv')].map(tr => tr.dataset.visit + ' ' + tr.dataset.verdict);
  }
  r.contradiction_rows = document.querySelectorAll('#changes-body tr.row.contradiction').length;
  const row = document.querySelector('#changes-body tr.row.contradiction');
  if (row) {
    row.click();
    r.history = [...document.querySelectorAll('#history tr.hv')].map(tr => tr.dataset.visit + ' ' + tr.dataset.verdict);
    r.history_contradictions = document.querySelectorAll('#history .contradiction').length;
  }
  return r;
}
