"""The HTML player: one self-contained page (inline SVG drawn by a small inline script, its data
as compact JSON), no file, font or address outside it.

Data (:func:`player_data`): each ship's track decimated (:mod:`.decimate`, ``tolerance`` metres
and :data:`HEADING_TOL_DEG`) then quantised: times in milliseconds from the start, positions in
integer quanta of :data:`QUANTUM_FRACTION` x ``tolerance`` metres from an origin, headings in
whole degrees, each column delta-encoded. The player interpolates between key samples as
:func:`.decimate.interpolate` does, so what it draws at any sample time of the trace is within
:func:`bounds` of the recorded state: ``tolerance + quantum / sqrt 2`` metres and
:data:`HEADING_TOL_DEG` + 0.5 degrees. The targets' classes are run-length encoded per step
(the scene's, latched ones flagged), the verdict events listed, the map a palette PNG (data
URI) of the grid's cells within the view, at most the player's pixels.

Safety: no text from an input becomes markup or code. The JSON is inside ``<script
type="application/json">`` with ``<``, ``>``, ``&``, U+2028 and U+2029 escaped as ``\\uXXXX``;
the script puts names into the page only as ``textContent``; the title is HTML-escaped.

Several players can share a page (the report): the script (:data:`SCRIPT`, with :data:`STYLE`)
starts every ``div.usv-player`` not yet started, each reading its own data; one inside a closed
``<details>`` when it opens (a page of many folded players starts none of them at load).
"""

from __future__ import annotations

import base64
import html
import io
import json
import math
from dataclasses import dataclass

import numpy as np

from usvtool.encounter import CLASS_NAMES
from usvtool.report.animation import decimate
from usvtool.report.animation.frames import (
    HULL_MIN_PX,
    MAP_RGB,
    MARK_STYLE,
    TIMELINE_PX,
    fit_view,
    ship_colours,
)
from usvtool.report.animation.scene import MARK_KINDS, Scene

#: The decimation's heading tolerance, degrees (the quantisation adds 0.5).
HEADING_TOL_DEG = 1.5
#: The positions' quantum as a fraction of the tolerance.
QUANTUM_FRACTION = 0.2
#: Speeds the player offers (times real time); the one asked for is added.
SPEEDS = (1, 2, 5, 10, 20, 50, 100)


@dataclass(frozen=True)
class Player:
    """The page, the fragment to embed, the key samples kept and the bounds met."""

    html: str
    fragment: str
    keys: int
    bound_m: float
    bound_deg: float


def bounds(tolerance: float) -> tuple[float, float]:
    """(metres, degrees): how far the player's ships may be from the trace at its samples."""
    q = QUANTUM_FRACTION * tolerance
    return tolerance + q / math.sqrt(2), HEADING_TOL_DEG + 0.5


def player(scene: Scene, size=(800, 600), speed: float = 10.0, wake: float = 60.0,
           tolerance: float = 0.5, name: str = "") -> Player:
    """The player of ``scene`` (module docstring), ``size`` its pixels (width, height)."""
    data, keys = player_data(scene, size, speed, wake, tolerance)
    frag = fragment(data, size[0])
    title = html.escape(scene.title or name or "usvtool animation", quote=True)
    page = ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n{frag}\n"
            f"<script>{SCRIPT}</script>\n</body>\n</html>\n")  # fmt: skip
    bound_m, bound_deg = bounds(tolerance)
    return Player(page, frag, keys, bound_m, bound_deg)


def fragment(data: dict, width: int) -> str:
    """The player's ``div`` holding its data (:data:`SCRIPT` and :data:`STYLE` start and style
    it)."""
    return (f'<div class="usv-player" tabindex="0" style="max-width:{int(width)}px">'
            f'<script type="application/json" class="usv-data">{script_json(data)}</script>'
            "</div>")  # fmt: skip


def script_json(data) -> str:
    """Compact JSON safe inside a ``<script>`` element: ``<``, ``>``, ``&``, U+2028 and U+2029
    escaped (module docstring)."""
    text = json.dumps(data, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    for c in ("<", ">", "&", "\u2028", "\u2029"):
        text = text.replace(c, f"\\u{ord(c):04x}")
    return text


def player_data(scene: Scene, size, speed: float, wake: float, tolerance: float):
    """The player's JSON data and the number of key samples (module docstring)."""
    tr = scene.trace
    width, height = int(size[0]), int(size[1])
    q = QUANTUM_FRACTION * tolerance
    left, bottom, right, top = fit_view(scene.view, width, height - TIMELINE_PX)
    ox, oy = round(left, 3), round(bottom, 3)
    t0 = float(tr.t[0])
    t_ms = np.rint((tr.t - t0) * 1000).astype(np.int64)
    colours = ship_colours(len(tr.ships))
    ships, keys = [], 0
    for j, name in enumerate(tr.ships):
        kept = decimate.keep(tr.t, tr.x[:, j], tr.y[:, j], tr.heading[:, j], tolerance,
                             HEADING_TOL_DEG)  # fmt: skip
        keys += kept.size
        xq = np.rint((tr.x[kept, j] - ox) / q).astype(np.int64)
        yq = np.rint((tr.y[kept, j] - oy) / q).astype(np.int64)
        hq = np.rint(tr.heading[kept, j]).astype(np.int64) % 360
        dh = (np.diff(hq) + 180) % 360 - 180
        columns = np.stack([np.diff(t_ms[kept], prepend=0), np.diff(xq, prepend=0),
                            np.diff(yq, prepend=0), np.r_[hq[:1], dh]], axis=1)  # fmt: skip
        ships.append({"n": name, "L": round(float(scene.lengths[j]), 3), "c": colours[j],
                      "k": columns.ravel().tolist()})  # fmt: skip
    code = scene.classes.astype(np.int64) + 8 * scene.latched
    cls = []
    for j in range(len(tr.ships)):
        change = np.flatnonzero(np.diff(code[:, j])) + 1
        at = np.r_[0, change]
        cls.append(np.stack([np.diff(t_ms[at], prepend=0), code[at, j]], 1).ravel().tolist()
                   if j else [])  # fmt: skip
    marks = [[int(round((m.t - t0) * 1000)), int(round((m.end - t0) * 1000)),
              MARK_KINDS.index(m.kind), m.ship, m.text] for m in scene.marks]  # fmt: skip
    vw = (right - left) / q
    px = vw / width  # quanta per pixel of the map
    data = {
        "title": scene.title,
        "dur": int(t_ms[-1]),
        "dt": int(np.median(np.diff(t_ms))) if t_ms.size > 1 else 100,
        "q": q,
        "view": [0, 0, round(vw), round((top - bottom) / q)],
        "px": round(px, 4),
        "hmin": round(HULL_MIN_PX * px * q, 3),
        "ships": ships,
        "cls": cls,
        "names": list(CLASS_NAMES),
        "marks": marks,
        "kinds": list(MARK_KINDS),
        "kc": [MARK_STYLE[k][0] for k in MARK_KINDS],
        "goal": None if scene.goal is None else [round((scene.goal[0] - ox) / q),
                                                 round((scene.goal[1] - oy) / q),
                                                 scene.goal_tolerance],  # fmt: skip
        "route": None if scene.route is None else _deltas(scene.route, ox, oy, q),
        "dom": [round(scene.domain[0], 3), round(scene.domain[1], 3)],
        "wake": wake,
        "speed": speed,
        "speeds": sorted({*SPEEDS, speed}),
        "size": [width, height],
        "map": _map_image(scene, (left, bottom, right, top), q, width, height),
    }
    return data, keys


def _deltas(points: np.ndarray, ox: float, oy: float, q: float) -> list[int]:
    xy = np.rint((points - (ox, oy)) / q).astype(np.int64)
    return np.diff(xy, axis=0, prepend=0).ravel().tolist()


def _map_image(scene: Scene, view, q: float, width: int, height: int):
    """The grid's cells within the view as a palette PNG (data URI) and its place in quanta."""
    g = scene.grid
    if g is None:
        return None
    from PIL import Image

    left, bottom, right, top = view
    ox, oy = round(left, 3), round(bottom, 3)
    s = g.cell_size
    gl, _, _, gt = g.bounds
    c0, c1 = max(0, math.floor((left - gl) / s)), min(g.width, math.ceil((right - gl) / s))
    r0, r1 = max(0, math.floor((gt - top) / s)), min(g.height, math.ceil((gt - bottom) / s))
    if c0 >= c1 or r0 >= r1:
        return None
    cells = g.cells[r0:r1, c0:c1]
    f = max(1, math.ceil(max(cells.shape[1] / width, cells.shape[0] / height)))
    shown = cells[::f, ::f]  # at most the player's pixels
    image = Image.fromarray(np.minimum(shown, 2).astype(np.uint8), mode="P")
    palette = [v for value in range(3) for v in MAP_RGB[value]]
    image.putpalette(palette)
    buf = io.BytesIO()
    image.save(buf, format="PNG", optimize=True)
    uri = "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")
    x0, y1 = gl + c0 * s, gt - r0 * s
    w, h = shown.shape[1] * f * s, shown.shape[0] * f * s
    return {"src": uri, "box": [round((x0 - ox) / q), round((y1 - h - oy) / q), round(w / q),
                                round(h / q)]}  # fmt: skip


STYLE = (
    ".usv-player{font:13px/1.35 sans-serif;color:#222;outline:none;margin:0.5em 0}"
    ".usv-player:focus-visible{box-shadow:0 0 0 2px #0072B2}"
    ".usv-player svg{display:block;width:100%;height:auto}"
    ".usv-map{background:#F4F4F4;border:1px solid #bbb}"
    ".usv-bar{display:flex;flex-wrap:wrap;gap:0.6em;align-items:center;margin:0.3em 0}"
    ".usv-bar input[type=range]{flex:1 1 12em}"
    ".usv-clock{font-family:monospace;white-space:pre}"
    ".usv-last{min-height:1.35em;font-size:12px;color:#444}"
)

# The player's script: ES5 plus typed arrays, no library. The SVG namespace URI below is a
# name, never fetched.
SCRIPT = r"""
(function () {
  "use strict";
  var NS = "http://www.w3.org/2000/svg";
  var HULL = "1,0 0.3,0.32 -1,0.32 -1,-0.32 0.3,-0.32";
  function el(tag, attrs, parent) {
    var e = document.createElementNS(NS, tag);
    for (var a in attrs) { e.setAttribute(a, attrs[a]); }
    if (parent) { parent.appendChild(e); }
    return e;
  }
  function html(tag, parent, text) {
    var e = document.createElement(tag);
    if (text !== undefined) { e.textContent = text; }
    parent.appendChild(e);
    return e;
  }
  function columns(flat, w) {
    var n = flat.length / w, out = [], acc = [], i, c;
    for (c = 0; c < w; c++) { out.push(new Float64Array(n)); acc.push(0); }
    for (i = 0; i < n; i++) {
      for (c = 0; c < w; c++) { acc[c] += flat[i * w + c]; out[c][i] = acc[c]; }
    }
    return out;
  }
  function find(ts, t) {
    var lo = 0, hi = ts.length - 1, m;
    if (t <= ts[0]) { return 0; }
    if (t >= ts[hi]) { return hi; }
    while (hi - lo > 1) { m = (lo + hi) >> 1; if (ts[m] <= t) { lo = m; } else { hi = m; } }
    return lo;
  }
  function turn(a, b) { return ((b - a + 540) % 360) - 180; }
  function at(s, t) {
    var i = find(s.t, t), n = s.t.length;
    if (i >= n - 1) { return [s.x[n - 1], s.y[n - 1], s.h[n - 1] % 360]; }
    var f = Math.min(1, Math.max(0, (t - s.t[i]) / (s.t[i + 1] - s.t[i])));
    return [s.x[i] + f * (s.x[i + 1] - s.x[i]), s.y[i] + f * (s.y[i + 1] - s.y[i]),
            (((s.h[i] + f * turn(s.h[i], s.h[i + 1])) % 360) + 360) % 360];
  }
  function fmt(v, d) { return v.toFixed(d); }
  function start(root) {
    root.setAttribute("data-ready", "1");
    var D = JSON.parse(root.querySelector("script.usv-data").textContent);
    var q = D.q, px = D.px, V = D.view, W = D.size[0];
    var ships = D.ships.map(function (s, j) {
      var c = columns(s.k, 4), h = c[3];
      for (var i = 0; i < h.length; i++) { h[i] = ((h[i] % 360) + 360) % 360; }
      var cl = columns(D.cls[j] || [], 2);
      return {name: s.n, L: s.L, colour: s.c, t: c[0], x: c[1], y: c[2], h: h,
              ct: cl[0] || new Float64Array(0), cv: cl[1] || new Float64Array(0)};
    });
    var title = html("div", root, D.title);
    title.style.fontWeight = "bold";
    var svg = el("svg", {"class": "usv-map", viewBox: [V[0], -(V[1] + V[3]), V[2], V[3]].join(" "),
                         role: "img"}, root);
    el("title", {}, svg).textContent = D.title;
    if (D.map) {
      var b = D.map.box;
      el("image", {href: D.map.src, x: b[0], y: -(b[1] + b[3]), width: b[2], height: b[3],
                   preserveAspectRatio: "none", style: "image-rendering:pixelated"}, svg);
    } else {
      el("rect", {x: V[0], y: -(V[1] + V[3]), width: V[2], height: V[3], fill: "#D6EAF2"}, svg);
    }
    if (D.route) {
      var r = columns(D.route, 2), pts = [];
      for (var i = 0; i < r[0].length; i++) { pts.push(r[0][i] + "," + (-r[1][i])); }
      el("polyline", {points: pts.join(" "), fill: "none", stroke: "#595959",
                      "stroke-width": 1.2 * px,
                      "stroke-dasharray": [4 * px, 3 * px].join(" ")}, svg);
    }
    if (D.goal) {
      el("circle", {cx: D.goal[0], cy: -D.goal[1], r: Math.max(D.goal[2] / q, 3 * px),
                    fill: "none", stroke: "#333", "stroke-width": px}, svg);
      el("circle", {cx: D.goal[0], cy: -D.goal[1], r: 2.5 * px, fill: "gold", stroke: "#000",
                    "stroke-width": 0.6 * px}, svg);
    }
    var wakes = ships.map(function (s) {
      return el("polyline", {fill: "none", stroke: s.colour, "stroke-width": 1.5 * px}, svg);
    });
    var dom = el("ellipse", {rx: D.dom[0] / q, ry: D.dom[1] / q, fill: ships[0].colour,
                             "fill-opacity": 0.15, stroke: ships[0].colour,
                             "stroke-dasharray": [4 * px, 3 * px].join(" "),
                             "stroke-width": px}, svg);
    var hulls = ships.map(function (s) {
      return el("polygon", {points: HULL, fill: s.colour, stroke: "#000",
                            "stroke-width": 0.6, "vector-effect": "non-scaling-stroke"}, svg);
    });
    var labels = ships.map(function () {
      return el("text", {"font-size": 11 * px, "paint-order": "stroke", stroke: "#fff",
                         "stroke-width": 3 * px, fill: "#000"}, svg);
    });
    var scale = Math.max(1, W / 800);
    var tl = el("svg", {viewBox: "0 0 " + W + " " + (58 * scale), "class": "usv-timeline"}, root);
    var x0 = 70, x1 = W - 10, dur = Math.max(D.dur, 1);
    function tx(ms) { return x0 + (x1 - x0) * ms / dur; }
    D.kinds.forEach(function (k, row) {
      var y = 8 + row * 9;
      el("text", {x: x0 - 4, y: y + 3, "font-size": 8, "text-anchor": "end", fill: "#444"}, tl)
        .textContent = k;
      el("line", {x1: x0, x2: x1, y1: y, y2: y, stroke: "#e4e4e4"}, tl);
    });
    D.marks.forEach(function (m) {
      var y = 8 + m[2] * 9, g;
      if (m[1] > m[0]) {
        g = el("rect", {x: tx(m[0]), y: y - 3, width: Math.max(2, tx(m[1]) - tx(m[0])), height: 6,
                        fill: D.kc[m[2]]}, tl);
      } else {
        g = el("circle", {cx: tx(m[0]), cy: y, r: 3.2, fill: D.kc[m[2]], stroke: "#000",
                          "stroke-width": 0.5}, tl);
      }
      el("title", {}, g).textContent = (m[0] / 1000).toFixed(1) + " s: " + m[4];
    });
    var cursor = el("line", {y1: 2, y2: 8 + D.kinds.length * 9, stroke: "#000",
                             "stroke-width": 1.5}, tl);
    var bar = html("div", root);
    bar.className = "usv-bar";
    var play = html("button", bar, "Play");
    play.type = "button";
    var slider = html("input", bar);
    slider.type = "range"; slider.min = 0; slider.max = D.dur; slider.step = D.dt; slider.value = 0;
    slider.setAttribute("aria-label", "time");
    var speed = html("select", bar);
    speed.setAttribute("aria-label", "speed");
    D.speeds.forEach(function (v) {
      var o = html("option", speed, v + "\u00d7");
      o.value = v;
      if (v === D.speed) { o.selected = true; }
    });
    var clock = html("span", bar);
    clock.className = "usv-clock";
    var last = html("div", root);
    last.className = "usv-last";
    var now = 0, playing = false, before = null;
    function draw() {
      var own = null, nearest = Infinity, t = now, wakeMs = D.wake * 1000;
      ships.forEach(function (s, j) {
        var p = at(s, t), X = p[0], Y = -p[1], rot = p[2] - 90;
        var half = Math.max(s.L, D.hmin) / 2 / q;
        hulls[j].setAttribute("transform", "translate(" + X + "," + Y + ") rotate(" + rot +
                              ") scale(" + half + ")");
        var lo = find(s.t, t - wakeMs), hi = find(s.t, t), pts = [];
        if (s.t[lo] < t - wakeMs && lo < hi) { lo += 1; }
        for (var i = lo; i <= hi; i++) { pts.push(s.x[i] + "," + (-s.y[i])); }
        pts.push(X + "," + Y);
        wakes[j].setAttribute("points", pts.join(" "));
        if (j === 0) {
          own = p;
          dom.setAttribute("transform", "translate(" + X + "," + Y + ") rotate(" + rot + ")");
          labels[0].textContent = "";
          return;
        }
        nearest = Math.min(nearest, Math.hypot(p[0] - own[0], p[1] - own[1]) * q);
        var c = s.ct.length ? s.cv[find(s.ct, t)] : 0, code = c % 8, lab = labels[j];
        if (code === 0) { lab.textContent = ""; return; }
        lab.textContent = c >= 8 ? s.name + ": " + D.names[code] : D.names[code];
        lab.setAttribute("font-weight", c >= 8 ? "bold" : "normal");
        lab.setAttribute("x", X + half + 4 * px);
        lab.setAttribute("y", Y - 4 * px);
      });
      var text = "t " + fmt(t / 1000, 1) + " s of " + fmt(D.dur / 1000, 1);
      if (ships.length > 1) { text += "  nearest " + fmt(nearest, 1) + " m"; }
      clock.textContent = text;
      cursor.setAttribute("x1", tx(t)); cursor.setAttribute("x2", tx(t));
      var recent = "";
      for (var m = 0; m < D.marks.length && D.marks[m][0] <= t; m++) {
        recent = fmt(D.marks[m][0] / 1000, 1) + " s: " + D.marks[m][4];
      }
      last.textContent = recent;
      slider.value = t;
    }
    function seek(t) { now = Math.min(D.dur, Math.max(0, t)); draw(); }
    function tick(stamp) {
      if (!playing) { return; }
      if (before !== null) { now += (stamp - before) * Number(speed.value); }
      before = stamp;
      if (now >= D.dur) { now = D.dur; setPlaying(false); }
      draw();
      if (playing) { window.requestAnimationFrame(tick); }
    }
    function setPlaying(on) {
      if (on && now >= D.dur) { now = 0; }
      playing = on; before = null;
      play.textContent = on ? "Pause" : "Play";
      root.setAttribute("data-playing", on ? "1" : "0");
      if (on) { window.requestAnimationFrame(tick); }
    }
    play.addEventListener("click", function () { setPlaying(!playing); });
    slider.addEventListener("input", function () { seek(Number(slider.value)); });
    root.addEventListener("keydown", function (e) {
      var step = e.shiftKey ? 10000 : 1000, tag = e.target.tagName;
      if (tag === "SELECT" || (tag === "BUTTON" && (e.key === " " || e.key === "Enter"))) {
        return;  // the control's own keys
      }
      if (e.key === " " || e.key === "k") { setPlaying(!playing); }
      else if (e.key === "ArrowRight") { seek(now + step); }
      else if (e.key === "ArrowLeft") { seek(now - step); }
      else if (e.key === ".") { seek(now + D.dt); }
      else if (e.key === ",") { seek(now - D.dt); }
      else if (e.key === "Home") { seek(0); }
      else if (e.key === "End") { seek(D.dur); }
      else { return; }
      e.preventDefault();
    });
    root.usvSeek = seek;
    draw();
  }
  function folded(e) {  // inside a closed details element: started when it opens
    for (var p = e.parentElement; p; p = p.parentElement) {
      if (p.tagName === "DETAILS" && !p.open) { return true; }
    }
    return false;
  }
  function startAll() {
    var all = document.querySelectorAll("div.usv-player:not([data-ready])");
    for (var i = 0; i < all.length; i++) { if (!folded(all[i])) { start(all[i]); } }
  }
  document.addEventListener("toggle", function (e) {
    if (e.target.open) { startAll(); }
  }, true);
  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", startAll);
  } else { startAll(); }
})();
"""
