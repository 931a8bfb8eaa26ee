/* linkwork viewer: animates a mechanism drawn as SVG and keeps the diagrams' cursors with it.
   Hand-written, no dependencies, no network. linkworkViewer(prefix) reads the JSON of the
   element `${prefix}-data` ({scene, charts}; see linkwork/plot/html.py) and wires the player
   (play/pause, position slider, speed), the diagrams (cursor follows the animation; a click
   or drag on a diagram shows the nearest position) and the table rows that carry a position.
   In real time the animation runs at the driver's constant speed, or at a real motion the
   scene carries (scene.timings: the time and speed at each frame of a machine's steady
   state), frame by frame as the time reaches it.
   A page may hold several drawings (data.alternatives: the designs of a synthesis) that a
   chooser switches between; a diagram and a table row name the drawing they refer to.
   The view's API is root.linkwork = {show(k), frame(), play(), pause(), playing(), clock(),
   choose(j), choice(), n}. */
"use strict";
function linkworkViewer(prefix) {
  var root = document.getElementById(prefix);
  var node = document.getElementById(prefix + "-data");
  if (!root || !node) { return null; }
  var data = JSON.parse(node.textContent);
  var sc = data.scene;
  var charts = data.charts || [];
  var st = {k: 0, playing: false, t: 0, last: null, speed: 1, raf: 0, clock: 0};
  var BASE_SECONDS = 6;  // one cycle at speed 1x
  function $(id) { return document.getElementById(id); }
  var svg = $(prefix + "-scene");
  var scenes = sc ? [sc].concat(data.alternatives || []) : [];
  var svgs = scenes.map(function (_, j) {
    return j === 0 ? svg : $(prefix + "-v" + j + "-scene");
  });
  var chosen = 0;  // the drawing shown (an index into scenes)
  var chooser = $(prefix + "-choice");
  var slider = $(prefix + "-slider");
  var button = $(prefix + "-play");
  var speed = $(prefix + "-speed");
  var posText = $(prefix + "-pos");
  var stateText = $(prefix + "-state");
  var timeText = $(prefix + "-time");
  var driversText = $(prefix + "-drivers");
  function build(scene) {  // the drawn elements of every moving shape of a drawing
    return scene.shapes.map(function (s) {
      var nodes = [];
      var labels = [];
      if (s.kind === "circle") {
        for (var m = 0; m < s.k; m++) {
          nodes.push($(s.id + "-" + m));
          labels.push(s.label ? $(s.id + "-" + m + "-t") : null);
        }
      } else {
        nodes.push($(s.id));
      }
      return {s: s, nodes: nodes, labels: labels};
    });
  }
  function realTime() {
    var real = speed ? speed.querySelector('option[value="real"]') : null;
    if (real) { real.disabled = !(sc.period > 0); }
  }
  var shapes = [];
  if (sc) {
    shapes = build(sc);
    realTime();
  }
  function fmt(v) {
    if (v === null || v === undefined || !isFinite(v)) { return "–"; }
    var a = Math.abs(v);
    if (a !== 0 && (a >= 1e5 || a < 1e-3)) { return v.toExponential(3); }
    return Number(v.toPrecision(4)).toString();
  }
  function setShape(e, k) {
    var s = e.s, q = sc.q, d = s.d, off = k * s.k * 2, m, x, y;
    if (s.kind === "circle") {
      for (m = 0; m < s.k; m++) {
        x = d[off + 2 * m]; y = d[off + 2 * m + 1];
        var c = e.nodes[m], t = e.labels[m];
        if (!c) { continue; }
        if (x === null || y === null) {
          c.setAttribute("visibility", "hidden");
          if (t) { t.setAttribute("visibility", "hidden"); }
          continue;
        }
        x *= q; y *= q;
        c.setAttribute("cx", x.toFixed(6));
        c.setAttribute("cy", y.toFixed(6));
        c.removeAttribute("visibility");
        if (t) {
          t.setAttribute("x", (x + s.r).toFixed(6));
          t.setAttribute("y", (y - s.r).toFixed(6));
          t.removeAttribute("visibility");
        }
      }
      return;
    }
    var pts = [];
    for (m = 0; m < s.k; m++) {
      x = d[off + 2 * m]; y = d[off + 2 * m + 1];
      if (x === null || y === null) { pts = []; break; }
      pts.push((x * q).toFixed(6) + "," + (y * q).toFixed(6));
    }
    if (e.nodes[0]) { e.nodes[0].setAttribute("points", pts.join(" ")); }
  }
  function setCharts(k) {
    charts.forEach(function (c) {
      if (!c.linked) { return; }
      var s = (c.scene || 0) === chosen ? c.f2s[k] : -1;  // linked to another drawing: no cursor
      var cur = $(c.id + "-cursor");
      var j;
      if (s < 0 || s === undefined) {
        if (cur) { cur.setAttribute("visibility", "hidden"); }
        for (j = 0; j < c.py.length; j++) {
          var dot0 = $(c.id + "-dot" + j);
          if (dot0) { dot0.setAttribute("visibility", "hidden"); }
          var v0 = $(c.id + "-v" + j);
          if (v0) { v0.textContent = ""; }
        }
        return;
      }
      if (cur && c.px[s] !== null) {
        cur.setAttribute("x1", c.px[s]);
        cur.setAttribute("x2", c.px[s]);
        cur.removeAttribute("visibility");
      }
      for (j = 0; j < c.py.length; j++) {
        var dot = $(c.id + "-dot" + j), y = c.py[j][s];
        if (dot) {
          if (y === null || c.px[s] === null) { dot.setAttribute("visibility", "hidden"); } else {
            dot.setAttribute("cx", c.px[s]);
            dot.setAttribute("cy", y);
            dot.removeAttribute("visibility");
          }
        }
        var val = $(c.id + "-v" + j);
        if (val) { val.textContent = " " + fmt(c.vals[j][s]); }
      }
    });
  }
  function timing() {
    if (typeof st.speed !== "string" || st.speed.charAt(0) !== "t" || !sc) { return null; }
    return (sc.timings || [])[Number(st.speed.slice(1))] || null;
  }
  function frameAt(tm, clock) {  // the last frame the real motion has reached at `clock`
    var lo = 0, hi = tm.t.length - 1;
    while (lo < hi) {
      var mid = (lo + hi + 1) >> 1;
      if (tm.t[mid] <= clock) { lo = mid; } else { hi = mid - 1; }
    }
    return lo;
  }
  function showTime(k) {
    if (!timeText) { return; }
    var tm = timing();
    timeText.textContent = tm ? "t = " + tm.t[k].toFixed(3) + " s of " + tm.span.toFixed(3) +
      " s, speed " + fmt(tm.speed[k]) + " " + tm.unit : "";
  }
  function show(k) {
    if (!sc || sc.n === 0) { return; }
    k = ((Math.round(k) % sc.n) + sc.n) % sc.n;
    st.k = k;
    if (slider && Number(slider.value) !== k) { slider.value = String(k); }
    var ok = sc.valid[k] === 1;
    if (posText) {
      var p = sc.pos[k];
      if (sc.periodic && sc.unit === "deg") { p = ((p % 360) + 360) % 360; }  // a whole turn
      posText.textContent = sc.unit === "" ? sc.coordinate + " " + p.toFixed(0) + " of " +
        (sc.n - 1) : sc.coordinate + " = " + p.toFixed(sc.unit === "deg" ? 1 : 2) + " " + sc.unit;
    }
    if (driversText) {  // several drivers: each one's coordinate at this position
      driversText.textContent = (sc.readouts || []).map(function (r) {
        return r.label + " = " + (r.v[k] === null ? "–" : r.v[k].toFixed(1)) + " " + r.unit;
      }).join(", ");
    }
    if (svg) { svg.classList.toggle("lw-off", !ok); }
    if (stateText) {
      stateText.textContent = ok ? "" : "not assembled at this position" +
        (st.playing ? "" : " (the animation skips it)");
    }
    if (ok) { shapes.forEach(function (e) { setShape(e, k); }); }
    setCharts(k);
    showTime(k);
    root.setAttribute("data-frame", String(k));
  }
  function nextValid(k, step) {
    for (var i = 0; i < sc.n; i++) {
      k = ((k + step) % sc.n + sc.n) % sc.n;
      if (sc.valid[k] === 1) { return k; }
    }
    return -1;
  }
  function cycleSeconds() {
    if (st.speed === "real" && sc.period > 0) { return sc.period; }
    return BASE_SECONDS / (st.speed === "real" ? 1 : st.speed);
  }
  function tick(now) {
    if (!st.playing) { return; }
    if (st.last === null) { st.last = now; }
    var dt = Math.min((now - st.last) / 1000, 0.25);
    st.last = now;
    var tm = timing();
    if (tm) {
      st.clock += dt;
      if (st.clock >= tm.span) { st.clock -= tm.span * Math.floor(st.clock / tm.span); }
      var at = frameAt(tm, st.clock);
      if (sc.valid[at] !== 1) { at = nextValid(at, 1); }
      if (at < 0) { pause(); return; }
      if (at !== st.k) { show(at); }
      st.raf = window.requestAnimationFrame(tick);
      return;
    }
    st.t += dt * sc.n / cycleSeconds();
    var steps = Math.floor(st.t);
    if (steps >= 1) {
      st.t -= steps;
      var k = st.k;
      for (var i = 0; i < steps; i++) {
        k = nextValid(k, 1);
        if (k < 0) { pause(); return; }
      }
      show(k);
    }
    st.raf = window.requestAnimationFrame(tick);
  }
  function play() {
    if (!sc || st.playing || nextValid(st.k, 0) < 0) { return; }
    st.playing = true; st.last = null; st.t = 0;
    if (sc.valid[st.k] !== 1) { show(nextValid(st.k, 1)); }
    var tm = timing();
    if (tm) { st.clock = tm.t[st.k]; }
    if (button) { button.innerHTML = "&#10074;&#10074; pause"; button.setAttribute("aria-label", "pause"); }
    st.raf = window.requestAnimationFrame(tick);
  }
  function pause() {
    st.playing = false;
    if (st.raf) { window.cancelAnimationFrame(st.raf); st.raf = 0; }
    if (button) { button.innerHTML = "&#9654; play"; button.setAttribute("aria-label", "play"); }
    if (sc) { show(st.k); }
  }
  if (button) { button.addEventListener("click", function () { if (st.playing) { pause(); } else { play(); } }); }
  if (slider) { slider.addEventListener("input", function () { pause(); show(Number(slider.value)); }); }
  if (speed) {
    speed.addEventListener("change", function () {
      var v = speed.value;
      st.speed = v === "real" || v.charAt(0) === "t" ? v : Number(v);
      var tm = timing();
      if (tm) { st.clock = tm.t[st.k]; }
      if (sc) { showTime(st.k); }
    });
  }
  Array.prototype.forEach.call(root.querySelectorAll("input[data-show]"), function (box) {
    var apply = function () { root.classList.toggle("lw-hide-" + box.getAttribute("data-show"), !box.checked); };
    box.addEventListener("change", apply);
    apply();
  });
  function firstValid(scene) {
    if (scene.valid[0] === 1) { return 0; }
    for (var i = 0; i < scene.n; i++) { if (scene.valid[i] === 1) { return i; } }
    return 0;
  }
  function choose(j) {
    j = Number(j);
    if (!(j >= 0 && j < scenes.length) || j === chosen) { return; }
    var was = st.playing;
    pause();
    if (svgs[chosen]) { svgs[chosen].style.display = "none"; }
    if (svgs[j]) { svgs[j].style.display = ""; }
    chosen = j; sc = scenes[j]; svg = svgs[j];
    shapes = build(sc);
    if (slider) { slider.max = String(Math.max(sc.n - 1, 0)); }
    if (chooser && Number(chooser.value) !== j) { chooser.value = String(j); }
    realTime();
    show(firstValid(sc));
    if (was) { play(); }
  }
  if (chooser) { chooser.addEventListener("change", function () { choose(chooser.value); }); }
  Array.prototype.forEach.call(root.querySelectorAll("tr[data-frame], tr[data-choice]"), function (tr) {
    tr.addEventListener("click", function () {
      pause();
      var j = tr.getAttribute("data-choice");
      if (j !== null) { choose(j); }
      if (tr.getAttribute("data-frame") !== null) { show(Number(tr.getAttribute("data-frame"))); }
    });
  });
  function pick(c, el, ev) {
    var box = el.getBoundingClientRect();
    var vb = el.viewBox.baseVal;
    var x = (ev.clientX - box.left) / box.width * vb.width;
    var y = (ev.clientY - box.top) / box.height * vb.height;
    var best = -1, bd = Infinity;
    for (var i = 0; i < c.px.length; i++) {
      var d;
      if (c.px[i] === null) { continue; }
      if (c.parametric) {
        var yy = c.py[0][i];
        if (yy === null) { continue; }
        d = (c.px[i] - x) * (c.px[i] - x) + (yy - y) * (yy - y);
      } else {
        d = Math.abs(c.px[i] - x);
      }
      if (d < bd) { bd = d; best = i; }
    }
    if (best >= 0) { pause(); choose(c.scene || 0); show(c.s2f[best]); }
  }
  charts.forEach(function (c) {
    if (!c.linked) { return; }
    var el = $(c.id);
    if (!el) { return; }
    var down = false;
    el.addEventListener("mousedown", function (ev) { down = true; pick(c, el, ev); ev.preventDefault(); });
    el.addEventListener("mousemove", function (ev) { if (down) { pick(c, el, ev); } });
    window.addEventListener("mouseup", function () { down = false; });
  });
  var player = root.querySelector(".lw-player");
  if (player && sc) {
    player.setAttribute("tabindex", "0");
    player.addEventListener("keydown", function (ev) {
      if (ev.key === " ") { if (st.playing) { pause(); } else { play(); } ev.preventDefault(); }
      if (ev.key === "ArrowRight" || ev.key === "ArrowLeft") {
        pause();
        var k = nextValid(st.k, ev.key === "ArrowRight" ? 1 : -1);
        if (k >= 0) { show(k); }
        ev.preventDefault();
      }
    });
  }
  var api = {
    show: function (k) { pause(); show(k); },
    frame: function () { return st.k; },
    play: play, pause: pause,
    playing: function () { return st.playing; },
    clock: function () { return st.clock; },
    choose: function (j) { choose(j); },
    choice: function () { return chosen; },
    get n() { return sc ? sc.n : 0; }
  };
  root.linkwork = api;
  if (sc && sc.n > 0) {
    var first = sc.valid[0] === 1 ? 0 : nextValid(0, 1);
    show(first < 0 ? 0 : first);
    var still = window.matchMedia && window.matchMedia("(prefers-reduced-motion: reduce)").matches;
    if (!still && first >= 0 && sc.n > 1) { play(); }
  }
  return api;
}
