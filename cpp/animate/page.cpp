// The animation page (page.hpp).
#include "animate/page.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace pcsim::animate {

namespace {

// A number in the page's data: `digits` significant digits, shortest form; null if not finite.
void put(std::string& out, double v, int digits) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  out += b;
}

std::string script_safe(std::string json) {
  // Inside <script>, "</" could end the element: JSON allows "<\/".
  for (std::size_t p = 0; (p = json.find("</", p)) != std::string::npos; p += 3) json.replace(p, 2, "<\\/");
  return json;
}

const char* kind_name(modelfile::DrawShape::Kind k) {
  switch (k) {
    case modelfile::DrawShape::Kind::line: return "line";
    case modelfile::DrawShape::Kind::polygon: return "polygon";
    case modelfile::DrawShape::Kind::circle: return "circle";
    case modelfile::DrawShape::Kind::arrow: return "arrow";
  }
  return "line";
}

std::string data_json(const Scene& s) {
  using nlohmann::json;
  const std::size_t P = s.spec.points.size(), dims = s.spatial ? 3 : 2;
  json head = json::object();
  head["title"] = s.title;
  head["model"] = s.model;
  head["modelFile"] = s.model_file;
  head["spatial"] = s.spatial;
  head["steady"] = s.steady;
  head["magnify"] = s.magnify;
  head["meanWindow"] = s.mean_window;
  head["rows"] = s.rows;
  if (!s.mode_pages.empty()) {
    json mp = json::array();
    for (const auto& m : s.mode_pages)
      mp.push_back({{"label", m.label}, {"text", m.text}, {"first", m.first}, {"count", m.count},
                    {"amplitude", m.amplitude}, {"amplitudeText", m.amplitude_text}});
    head["modePages"] = mp;
  }
  json pts = json::array();
  for (const auto& p : s.spec.points) pts.push_back({{"name", p.name}, {"named", p.named}});
  head["points"] = pts;
  json shapes = json::array();
  std::size_t vi = 3 * P, ai = 0;
  for (const auto& sh : s.spec.shapes) {
    json j = {{"kind", kind_name(sh.kind)}, {"pts", sh.points}, {"closed", sh.closed},
              {"color", sh.color}, {"fill", sh.fill}, {"mode", sh.mode}};
    if (sh.kind == modelfile::DrawShape::Kind::circle) j["v"] = vi++;
    if (sh.kind == modelfile::DrawShape::Kind::arrow) {
      j["v"] = vi;
      vi += 3;
      j["f"] = ai++;
      j["force"] = sh.force;
      j["unit"] = sh.unit;
      j["length"] = sh.length;
      j["unitName"] = sh.unit_name;
    }
    shapes.push_back(j);
  }
  head["shapes"] = shapes;
  head["contacts"] = s.contacts;
  json ev = json::array();
  for (const auto& e : s.events) ev.push_back({e.t, e.kind, e.constraint, e.mode_after});
  head["events"] = ev;
  std::string out = head.dump();
  out.pop_back();  // the closing brace: the frames follow
  // The frames: t; per point the moving mean (7 digits) and the deviation from it (5 digits,
  // relative to itself: magnified motion keeps its digits); radii and directions; forces; modes.
  out += ",\"t\":[";
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    if (f) out += ',';
    put(out, s.t[f], 10);
  }
  out += "],\"m\":[";
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    out += f ? ",[" : "[";
    bool first = true;
    for (std::size_t p = 0; p < P; ++p)
      for (std::size_t k = 0; k < dims; ++k) {
        if (!first) out += ',';
        first = false;
        put(out, s.mean[f][3 * p + k], 8);
      }
    out += ']';
  }
  out += "],\"d\":[";
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    out += f ? ",[" : "[";
    bool first = true;
    for (std::size_t p = 0; p < P; ++p)
      for (std::size_t k = 0; k < dims; ++k) {
        if (!first) out += ',';
        first = false;
        const double dev = s.values[f][3 * p + k] - s.mean[f][3 * p + k];
        put(out, dev, 6);
      }
    out += ']';
  }
  out += "],\"v\":[";
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    out += f ? ",[" : "[";
    for (std::size_t k = 3 * P; k < s.values[f].size(); ++k) {
      if (k > 3 * P) out += ',';
      put(out, s.values[f][k], 7);
    }
    out += ']';
  }
  out += "],\"f\":[";
  for (std::size_t f = 0; f < s.t.size(); ++f) {
    out += f ? ",[" : "[";
    for (std::size_t k = 0; k < s.forces[f].size(); ++k) {
      if (k) out += ',';
      put(out, s.forces[f][k], 6);
    }
    out += ']';
  }
  out += "],\"modes\":";
  out += json(s.modes).dump();
  out += '}';
  return script_safe(out);
}

const char* kPage = R"PCSIM(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>pcsim animate</title>
<style>
body{font:14px sans-serif;margin:8px;color:#222;background:#fafafa}
#view{border:1px solid #bbb;background:#fff;display:block;width:100%;max-width:1000px;height:auto}
#bar{display:flex;flex-wrap:wrap;gap:10px;align-items:center;margin:6px 0;max-width:1000px}
#slider{flex:1;min-width:200px}
#timeline{display:block;width:100%;max-width:1000px;height:28px;border:1px solid #ddd;background:#fff}
.note{color:#555;font-size:12px;max-width:1000px}
#magnote{font-weight:bold;color:#a00}
</style></head><body>
<div id="head"></div>
<canvas id="view" width="1000" height="600"></canvas>
<div id="bar">
<button id="play">pause</button>
<input id="slider" type="range" min="0" max="0" value="0" step="1">
<span id="time"></span>
<label>speed <select id="speed"><option>0.01</option><option>0.05</option><option>0.1</option><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option><option>5</option></select>&times;</label>
<label>magnification <input id="mag" type="number" min="1" max="1e9" step="any" style="width:7em"></label>
</div>
<canvas id="timeline" width="1000" height="28"></canvas>
<div class="note" id="modeinfo"></div>
<div class="note" id="magnote"></div>
<div class="note" id="legend"></div>
<pre id="pcsim-state" hidden></pre>
<script>
"use strict";
const D = /*DATA*/;
const P = D.points.length, DIM = D.spatial ? 3 : 2, F = D.t.length;
const MODE_COLOR = {stick: "#2a9d4a", slip: "#e07b00", flight: "#d62828", contact: "#1f77b4"};
const view = document.getElementById("view"), ctx = view.getContext("2d");
const tl = document.getElementById("timeline"), tctx = tl.getContext("2d");
const slider = document.getElementById("slider"), magIn = document.getElementById("mag");
const playBtn = document.getElementById("play"), speedSel = document.getElementById("speed");
let frame = 0, playing = true, mag = D.magnify, simTime = D.t[0], last = null;
let az = 0.6, el = 0.35, autoRotate = D.spatial;
// A pcsim modes page: each mode's cycle is the frames fLo..fHi (t is then the phase, rad).
const MODES = D.modePages && D.modePages.length ? D.modePages : null;
let fLo = 0, fHi = F - 1, cur = 0;
slider.max = F - 1;
magIn.value = mag;
document.getElementById("head").textContent = "pcsim animate: case '" + D.title + "', model '" + D.model + "' (" + D.modelFile + ")" + (MODES ? ": the mode shapes about the reference state, one cycle each, looped" : D.steady ? ": one period of the periodic steady state, looped" : "") + (D.spatial ? "; drag to orbit the camera" : "");

// The drawn position of point i in frame f: the moving mean plus the magnified deviation.
function point(f, i) {
  const m = D.m[f], d = D.d[f], p = [];
  for (let k = 0; k < DIM; k++) p.push(m[DIM * i + k] + mag * d[DIM * i + k]);
  if (!D.spatial) p.push(0);
  return p;
}
let bounds = null;
function computeBounds() {
  let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let f = fLo; f <= fHi; f++) for (let i = 0; i < P; i++) {
    const p = point(f, i);
    for (let k = 0; k < 3; k++) if (isFinite(p[k])) { lo[k] = Math.min(lo[k], p[k]); hi[k] = Math.max(hi[k], p[k]); }
  }
  for (const s of D.shapes) if (s.kind === "circle") for (let f = fLo; f <= fHi; f += Math.max(1, Math.floor((fHi - fLo + 1) / 200))) {
    const c = point(f, s.pts[0]), r = Math.abs(D.v[f][s.v - 3 * P]);
    if (isFinite(r)) for (let k = 0; k < 2; k++) { lo[k] = Math.min(lo[k], c[k] - r); hi[k] = Math.max(hi[k], c[k] + r); }
  }
  for (let k = 0; k < 3; k++) if (!isFinite(lo[k])) { lo[k] = -1; hi[k] = 1; }
  bounds = {lo, hi, c: [0, 1, 2].map(k => (lo[k] + hi[k]) / 2)};
  bounds.r = Math.max(1e-12, ...[0, 1, 2].map(k => (hi[k] - lo[k]) / 2));
}
// World -> pixels. 2-D: x right, y up, one scale for both. 3-D: z up, the camera orbits (az, el).
let scale = 1;
function project(p) {
  const W = view.width, H = view.height, b = bounds;
  if (!D.spatial) {
    const sx = (W - 40) / Math.max(1e-300, b.hi[0] - b.lo[0]), sy = (H - 40) / Math.max(1e-300, b.hi[1] - b.lo[1]);
    scale = Math.min(sx, sy);
    if (!isFinite(scale) || scale <= 0) scale = 1;
    return [W / 2 + (p[0] - b.c[0]) * scale, H / 2 - (p[1] - b.c[1]) * scale, 0];
  }
  const x = p[0] - b.c[0], y = p[1] - b.c[1], z = p[2] - b.c[2];
  const ca = Math.cos(az), sa = Math.sin(az), ce = Math.cos(el), se = Math.sin(el);
  const xr = ca * x + sa * y, yr = -sa * x + ca * y;     // about z
  const depth = ce * yr + se * z, up = -se * yr + ce * z;  // tilt
  const dist = 4 * b.r, persp = dist / (dist + depth);
  scale = 0.45 * Math.min(W, H) / b.r;
  return [W / 2 + xr * scale * persp, H / 2 - up * scale * persp, depth];
}
function modeOf(f, name) {
  const k = D.contacts.indexOf(name);
  return k < 0 ? null : D.modes[f][k];
}
function arrowHead(a, b, color) {
  const dx = b[0] - a[0], dy = b[1] - a[1], L = Math.hypot(dx, dy);
  if (L < 1) return;
  const ux = dx / L, uy = dy / L, h = Math.min(10, L / 2);
  ctx.fillStyle = color;
  ctx.beginPath();
  ctx.moveTo(b[0], b[1]);
  ctx.lineTo(b[0] - h * ux + 0.5 * h * uy, b[1] - h * uy - 0.5 * h * ux);
  ctx.lineTo(b[0] - h * ux - 0.5 * h * uy, b[1] - h * uy + 0.5 * h * ux);
  ctx.closePath();
  ctx.fill();
}
function draw() {
  const f = frame;
  ctx.clearRect(0, 0, view.width, view.height);
  const px = [], world = [];
  for (let i = 0; i < P; i++) { world.push(point(f, i)); px.push(project(world[i])); }
  ctx.lineWidth = 2;
  for (const s of D.shapes) {
    const m = s.mode ? modeOf(f, s.mode) : null;
    const color = (m && MODE_COLOR[m]) || s.color || "#333";
    ctx.strokeStyle = color;
    if (s.kind === "line" || s.kind === "polygon") {
      ctx.beginPath();
      s.pts.forEach((i, k) => k ? ctx.lineTo(px[i][0], px[i][1]) : ctx.moveTo(px[i][0], px[i][1]));
      if (s.kind === "polygon" || s.closed) ctx.closePath();
      if (s.fill) { ctx.fillStyle = s.fill; ctx.fill(); }
      ctx.stroke();
    } else if (s.kind === "circle") {
      const c = px[s.pts[0]], r = Math.abs(D.v[f][s.v - 3 * P]) * scale;
      ctx.beginPath();
      ctx.arc(c[0], c[1], isFinite(r) ? r : 0, 0, 2 * Math.PI);
      if (s.fill) { ctx.fillStyle = s.fill; ctx.fill(); }
      ctx.stroke();
    } else if (s.kind === "arrow") {
      const v = D.v[f], o = s.v - 3 * P, dir = [v[o], v[o + 1], v[o + 2]];
      const n = Math.hypot(dir[0], dir[1], dir[2]), force = D.f[f][s.f];
      if (!(n > 0) || !isFinite(force)) continue;
      const len = force / s.unit * s.length, a = world[s.pts[0]];
      const tip = [a[0] + len * dir[0] / n, a[1] + len * dir[1] / n, a[2] + len * dir[2] / n];
      const pa = px[s.pts[0]], pb = project(tip);
      ctx.strokeStyle = s.color || "#c0392b";
      ctx.beginPath(); ctx.moveTo(pa[0], pa[1]); ctx.lineTo(pb[0], pb[1]); ctx.stroke();
      arrowHead(pa, pb, s.color || "#c0392b");
    }
  }
  ctx.fillStyle = "#000";
  ctx.font = "12px sans-serif";
  for (let i = 0; i < P; i++) if (D.points[i].named) {
    ctx.beginPath(); ctx.arc(px[i][0], px[i][1], 2.5, 0, 2 * Math.PI); ctx.fill();
    ctx.fillText(D.points[i].name, px[i][0] + 4, px[i][1] - 4);
  }
  // The scale bar of the arrows: each arrow's `length` and what it stands for.
  let y = 18;
  ctx.font = "13px sans-serif";
  for (const s of D.shapes) if (s.kind === "arrow" && !MODES) {  // a mode shape has no forces
    const L = s.length * scale;
    ctx.strokeStyle = s.color || "#c0392b"; ctx.beginPath(); ctx.moveTo(10, y); ctx.lineTo(10 + L, y); ctx.stroke();
    ctx.fillStyle = "#000"; ctx.fillText(s.force + ": " + fmt(s.unit) + " " + s.unitName + " (now " + fmt(D.f[f][s.f]) + " " + s.unitName + ")", 16 + Math.min(L, 300), y + 4);
    y += 18;
  }
  const when = MODES ? MODES[cur].label + ", phase = " + D.t[f].toFixed(3) + " rad" : "t = " + D.t[f].toFixed(4) + " s";
  ctx.fillText(when + "   magnification " + fmt(mag) + "x", 10, view.height - 10);
  document.getElementById("time").textContent = when;
  slider.value = f;
  drawTimeline();
  const named = {}, pixels = {};
  for (let i = 0; i < P; i++) if (D.points[i].named) {
    named[D.points[i].name] = world[i].slice(0, DIM);
    pixels[D.points[i].name] = [px[i][0], px[i][1]];
  }
  const state = {t: D.t[f], frame: f, frames: F, magnify: mag, pixels_per_unit: scale, points: named, pixels: pixels,
                 forces: Object.fromEntries(D.shapes.filter(s => s.kind === "arrow").map(s => [s.force, D.f[f][s.f]])),
                 modes: Object.fromEntries(D.contacts.map((c, k) => [c, D.modes[f][k]]))};
  // The time from the navigation's start to the first drawn frame (what "opens in" means).
  if (window.pcsimOpenedMs === undefined) window.pcsimOpenedMs = performance.now();
  state.opened_ms = window.pcsimOpenedMs;
  if (MODES) { state.mode = cur + 1; state.mode_label = MODES[cur].label; state.phase = D.t[f]; state.amplitude = MODES[cur].amplitude; }
  window.pcsimLast = state;
  document.getElementById("pcsim-state").textContent = JSON.stringify(state);
}
function fmt(v) { return v === null || v === undefined ? "n/a" : String(Number(Number(v).toPrecision(4))); }
window.pcsimState = () => window.pcsimLast;
function drawTimeline() {
  const W = tl.width, H = tl.height, t0 = D.t[fLo], t1 = D.t[fHi], span = Math.max(1e-300, t1 - t0);
  tctx.clearRect(0, 0, W, H);
  const X = t => (t - t0) / span * (W - 1);
  // The contact modes as coloured bands, one row per contact.
  const rows = Math.max(1, D.contacts.length), h = (H - 8) / rows;
  for (let k = 0; k < D.contacts.length; k++) for (let f = 0; f + 1 < F; f++) {
    tctx.fillStyle = MODE_COLOR[D.modes[f][k]] || "#999";
    tctx.fillRect(X(D.t[f]), 8 + k * h, Math.max(1, X(D.t[f + 1]) - X(D.t[f])), h);
  }
  tctx.fillStyle = "#000";
  for (const e of D.events) tctx.fillRect(X(e[0]), 0, 1, 8);
  tctx.fillStyle = "#00f";
  tctx.fillRect(X(D.t[frame]) - 1, 0, 2, H);
}
function setMag(m) {
  if (!(m >= 1)) m = 1;
  mag = m;
  magIn.value = m;
  computeBounds();
  if (MODES) {
    document.getElementById("magnote").textContent = MODES[cur].amplitudeText +
      (mag === 1 ? "" : "; displacements magnified a further " + fmt(mag) + "x about the reference state");
    return;
  }
  document.getElementById("magnote").textContent = mag === 1 ? "true scale (magnification 1)" :
    "displacements magnified " + fmt(mag) + "x about their moving mean (over " +
    (D.meanWindow > 0 ? fmt(D.meanWindow) + " s, one excitation period" : "the whole run") + ")";
}
function frameAt(t) {
  let a = fLo, b = fHi;
  if (MODES) {  // the phase on the cycle: the nearest frame, going round (2 pi after the last is the first)
    const n = fHi - fLo + 1, step = 2 * Math.PI / n, k = Math.round((((t % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI)) / step) % n;
    return fLo + k;
  }
  while (b - a > 1) { const mid = (a + b) >> 1; if (D.t[mid] <= t) a = mid; else b = mid; }
  return Math.abs(D.t[b] - t) < Math.abs(D.t[a] - t) ? b : a;
}
function tick(now) {
  if (playing) {
    if (last !== null) {
      simTime += (now - last) / 1000 * Number(speedSel.value) * (MODES ? Math.PI : 1);  // modes: a cycle in 2 s
      if (MODES) simTime %= 2 * Math.PI;
      else if (simTime > D.t[F - 1]) simTime = D.t[0] + (D.steady ? (simTime - D.t[F - 1]) % Math.max(1e-300, D.t[F - 1] - D.t[0]) : 0);
      frame = frameAt(simTime);
    }
    last = now;
    if (autoRotate) az += 0.005;
    draw();
  } else last = null;
  requestAnimationFrame(tick);
}
playBtn.onclick = () => { playing = !playing; playBtn.textContent = playing ? "pause" : "play"; if (playing) simTime = D.t[frame]; };
slider.oninput = () => { frame = Number(slider.value); simTime = D.t[frame]; draw(); };
magIn.onchange = () => { setMag(Number(magIn.value)); draw(); };
let drag = null;
view.onmousedown = e => { drag = [e.clientX, e.clientY]; autoRotate = false; };
window.onmouseup = () => { drag = null; };
view.onmousemove = e => { if (!drag || !D.spatial) return; az += (e.clientX - drag[0]) * 0.01; el = Math.max(-1.5, Math.min(1.5, el + (e.clientY - drag[1]) * 0.01)); drag = [e.clientX, e.clientY]; draw(); };
// The mode selector of a modes page: the mode's frames, its eigenvalue and frequencies.
function selectMode(k) {
  cur = k; fLo = MODES[k].first; fHi = MODES[k].first + MODES[k].count - 1;
  slider.min = fLo; slider.max = fHi; frame = fLo; simTime = D.t[fLo];
  modeSel.value = String(k);
  document.getElementById("modeinfo").textContent = MODES[k].label + ": " + MODES[k].text;
  setMag(mag);
}
let modeSel = null;
if (MODES) {
  modeSel = document.createElement("select");
  modeSel.id = "modesel";
  MODES.forEach((m, k) => { const o = document.createElement("option"); o.value = String(k); o.textContent = m.label; modeSel.appendChild(o); });
  const lab = document.createElement("label"); lab.textContent = "mode "; lab.appendChild(modeSel);
  document.getElementById("bar").insertBefore(lab, document.getElementById("bar").firstChild);
  modeSel.onchange = () => { selectMode(Number(modeSel.value)); draw(); };
}
// #t=1.25&mag=1: open paused at that time with that magnification (a modes page: #mode=2&phase=1.57).
const q = new URLSearchParams(location.hash.slice(1));
if (MODES) { const k = q.has("mode") ? Math.round(Number(q.get("mode"))) : 1; selectMode(isFinite(k) ? Math.max(0, Math.min(MODES.length - 1, k - 1)) : 0); }
setMag(q.has("mag") ? Number(q.get("mag")) : mag);
if (q.has("az")) az = Number(q.get("az"));
if (MODES && q.has("phase")) { playing = false; playBtn.textContent = "play"; autoRotate = false; frame = frameAt(Number(q.get("phase"))); simTime = D.t[frame]; }
if (q.has("t")) { playing = false; playBtn.textContent = "play"; autoRotate = false; frame = frameAt(Number(q.get("t"))); simTime = D.t[frame]; }
draw();
let legend = MODES ? "Mode shapes: no forces are drawn." : "Arrows: " + (D.shapes.some(s => s.kind === "arrow") ? "each drawn to its own scale (the bars top left)." : "none.");
if (D.contacts.length) legend += " Contact modes on the timeline (" + D.contacts.join(", ") + "): stick green, slip orange, flight red, contact blue; events are the ticks above.";
legend += MODES ? " " + MODES.length + " modes, " + MODES[0].count + " frames per cycle." : " " + F + " frames of " + D.rows + " time-series rows.";
document.getElementById("legend").textContent = legend;
requestAnimationFrame(tick);
</script></body></html>
)PCSIM";

}  // namespace

std::string animation_html(const Scene& scene) {
  std::string page = kPage;
  const std::string marker = "/*DATA*/";
  page.replace(page.find(marker), marker.size(), data_json(scene));
  return page;
}

}  // namespace pcsim::animate
