/* linkwork viewer: animates a mechanism drawn as SVG and keeps the diagrams' cursors with it.
   Hand-written, no dependencies, no network. linkworkViewer(prefix) reads the JSON of the
   element `${prefix}-data` ({scene, charts}; see linkwork/plot/html.py) and wires the player
   (play/pause, position slider, speed), the diagrams (cursor follows the animation; a click
   or drag on a diagram shows the nearest position) and the table rows that carry a position.
   The view's API is root.linkwork = {show(k), frame(), play(), pause(), playing(), n}. */
"use strict";
function linkworkViewer(prefix) {
  var root = document.getElementById(prefix);
  var node = document.getElementById(prefix + "-data");
  if (!root || !node) { return null; }
  var data = JSON.parse(node.textContent);
  var sc = data.scene;
  var charts = data.charts || [];
  var st = {k: 0, playing: false, t: 0, last: null, speed: 1, raf: 0};
  var BASE_SECONDS = 6;  // one cycle at speed 1x
  function $(id) { return document.getElementById(id); }
  var svg = $(prefix + "-scene");
  var slider = $(prefix + "-slider");
  var button = $(prefix + "-play");
  var speed = $(prefix + "-speed");
  var posText = $(prefix + "-pos");
  var stateText = $(prefix + "-state");
  var shapes = [];
  if (sc) {
    sc.shapes.forEach(function (s) {
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
      shapes.push({s: s, nodes: nodes, labels: labels});
    });
    if (speed && !(sc.period > 0)) {
      var real = speed.querySelector('option[value="real"]');
      if (real) { real.disabled = true; }
    }
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
      var s = c.f2s[k];
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
  function show(k) {
    if (!sc || sc.n === 0) { return; }
    k = ((Math.round(k) % sc.n) + sc.n) % sc.n;
    st.k = k;
    if (slider && Number(slider.value) !== k) { slider.value = String(k); }
    var ok = sc.valid[k] === 1;
    if (posText) {
      posText.textContent = sc.coordinate + " = " + sc.pos[k].toFixed(sc.unit === "deg" ? 1 : 2) +
        " " + sc.unit;
    }
    if (svg) { svg.classList.toggle("lw-off", !ok); }
    if (stateText) {
      stateText.textContent = ok ? "" : "not assembled at this position" +
        (st.playing ? "" : " (the animation skips it)");
    }
    if (ok) { shapes.forEach(function (e) { setShape(e, k); }); }
    setCharts(k);
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
      st.speed = speed.value === "real" ? "real" : Number(speed.value);
    });
  }
  Array.prototype.forEach.call(root.querySelectorAll("input[data-show]"), function (box) {
    var apply = function () { root.classList.toggle("lw-hide-" + box.getAttribute("data-show"), !box.checked); };
    box.addEventListener("change", apply);
    apply();
  });
  Array.prototype.forEach.call(root.querySelectorAll("tr[data-frame]"), function (tr) {
    tr.addEventListener("click", function () { pause(); show(Number(tr.getAttribute("data-frame"))); });
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
    if (best >= 0) { pause(); show(c.s2f[best]); }
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
    n: sc ? sc.n : 0
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
