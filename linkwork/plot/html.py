"""Self-contained HTML: the animated mechanism, diagrams with a cursor, tables, a whole page.

Everything a page needs is inlined (the SVG drawn here, the data as JSON, the viewer script
``viewer.js`` and style ``viewer.css`` beside this module): it opens offline and makes no
network request. The same pieces make the report's page (:func:`page_html`) and a notebook's
display of a result (:func:`view_html`, what ``_repr_html_`` returns).

* :func:`scene_svg` draws a :class:`~linkwork.plot.scene.Scene` at one frame as SVG (lengths in
  mm, y up), every moving shape with an id; the viewer script moves them frame by frame from
  :func:`scene_data` (coordinates in integer multiples of a quantum, at most
  :data:`MAX_FRAMES` frames).
* :class:`Diagram` -> :func:`diagram_svg`: a chart drawn here (axes, ticks, curves), with the
  maps between its samples and the scene's frames (a cursor that follows the animation; a
  click on the chart shows the nearest position).
* :class:`Table`, :class:`Section`, :class:`Page`: the report's structure; a table row may
  carry a driver position (a click shows it).

Positions (``Scene.positions``, ``Diagram.positions``, ``Table.positions``) are the driver
coordinate in SI [rad or m]; what is drawn is in display units (deg, mm) chosen by the caller.
"""

from __future__ import annotations

import html
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from importlib import resources
from typing import Any

import numpy as np

from linkwork.plot.numbers import fmt, unit_label
from linkwork.plot.scene import FORCE_ROLES, PALETTE, Scene, Shape

__all__ = ["MAX_DIAGRAM_SAMPLES", "MAX_FRAMES", "Diagram", "Page", "RefLine", "Section",
           "Table", "diagram_svg", "page_html", "peaks_table", "result_table", "scene_data",
           "scene_svg", "summary_table", "view_html"]

#: Most frames the animation of a page holds (more positions are sampled evenly).
MAX_FRAMES = 720
#: Most samples a diagram's curves hold (a longer cycle keeps each stretch's min and max).
MAX_DIAGRAM_SAMPLES = 1500
#: Relative quantum of the coordinates of the animation (of the drawing's extent).
QUANTUM = 1e-5

#: Diagram size in SVG pixels, and its margins (left, right, top, bottom).
DIAGRAM_SIZE = (560, 250)
DIAGRAM_MARGIN = (64, 12, 26, 40)


def _asset(name: str) -> str:
    return resources.files("linkwork.plot").joinpath(name).read_text(encoding="utf-8")


def _e(s: Any) -> str:
    return html.escape(str(s), quote=True)


def _json(data: Any) -> str:
    """JSON safe inside a ``<script>`` element (no ``</script>``, no ``<!--``)."""
    return json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")


# ---------------------------------------------------------------------------------------------
# the mechanism


def _svg_xy(xy: np.ndarray) -> np.ndarray:
    """World [m] -> SVG user units: mm, y down."""
    out = np.array(xy, dtype=float) * 1e3
    if out.ndim == 3:
        out[:, 1, :] *= -1.0
    else:
        out[:, 1] *= -1.0
    return out


def _fmt(v: float, nd: int) -> str:
    if not math.isfinite(v):
        return "0"
    s = f"{v:.{nd}f}".rstrip("0").rstrip(".") if nd > 0 else f"{v:.0f}"
    return "0" if s in ("-0", "") else s


def _points(xy: np.ndarray, nd: int) -> str:
    return " ".join(f"{_fmt(x, nd)},{_fmt(y, nd)}" for x, y in xy)


def _decimals(scene: Scene) -> tuple[int, float]:
    """Decimals of the drawing's mm and the quantum [mm] of the animation's coordinates."""
    x0, y0, x1, y1 = scene.bounds()
    extent = max(x1 - x0, y1 - y0, 1e-12) * 1e3
    q = 10.0 ** math.floor(math.log10(extent * QUANTUM))
    return max(0, -math.floor(math.log10(q))), q


def _shape_class(s: Shape) -> str:
    cls = f"lw-{s.role}" + (" lw-wide" if s.kind == "polyline" and s.size > 0 else "")
    if s.colour >= 0:
        cls += f" lw-c{s.colour % len(PALETTE)}"
    return cls


def scene_svg(scene: Scene, frame: int = 0, *, prefix: str = "lw") -> str:
    """The scene at ``frame`` as an SVG element (mm, y up); moving shapes get the ids
    ``{prefix}-s{i}`` (``i`` their index in ``scene.shapes``) that the viewer moves."""
    nd, _ = _decimals(scene)
    x0, y0, x1, y1 = (v * 1e3 for v in scene.bounds())
    pad = 0.05 * max(x1 - x0, y1 - y0, 1e-9)
    vb = (x0 - pad, -(y1 + pad), (x1 - x0) + 2 * pad, (y1 - y0) + 2 * pad)
    label_size = 0.028 * max(vb[2], vb[3])
    parts = [f'<svg class="lw-scene" id="{prefix}-scene" xmlns="http://www.w3.org/2000/svg" '
             f'viewBox="{" ".join(_fmt(v, nd) for v in vb)}" '
             f'style="--lw-label:{_fmt(label_size, nd)}px" '
             f'preserveAspectRatio="xMidYMid meet" role="img" '
             f'aria-label="{_e(scene.title)}">']
    ok = bool(scene.valid[frame]) if scene.n else False
    for i, s in enumerate(scene.shapes):
        xy = _svg_xy(s.at(frame) if (ok or not s.moving) else np.full(s.at(frame).shape,
                                                                      np.nan))
        sid = f' id="{prefix}-s{i}"' if s.moving else ""
        cls = _shape_class(s) + (" lw-moving" if s.moving else "")
        title = f"<title>{_e(s.name)}</title>"
        width = (f' style="stroke-width:{_fmt(s.size * 1e3, nd)}"'
                 if s.kind == "polyline" and s.size > 0 else "")
        data = f' data-name="{_e(s.name)}"'
        if s.kind == "circle":
            r = _fmt(s.size * 1e3, nd)
            for k, (x, y) in enumerate(xy):
                hide = "" if np.isfinite(x) and np.isfinite(y) else ' visibility="hidden"'
                cid = f' id="{prefix}-s{i}-{k}"' if s.moving else ""
                parts.append(f'<circle{cid} class="{cls}"{data} cx="{_fmt(x, nd)}" '
                             f'cy="{_fmt(y, nd)}" r="{r}"{hide}>{title}</circle>')
                if s.label:
                    lid = f' id="{prefix}-s{i}-{k}-t"' if s.moving else ""
                    lcls = f"lw-label lw-label-{s.role}" + (" lw-moving" if s.moving else "")
                    parts.append(f'<text{lid} class="{lcls}"{hide} '
                                 f'x="{_fmt(x + s.size * 1e3, nd)}" '
                                 f'y="{_fmt(y - s.size * 1e3, nd)}">{_e(s.label)}</text>')
        elif s.kind == "polygon":
            pts = _points(xy, nd) if np.all(np.isfinite(xy)) else ""
            parts.append(f'<polygon{sid} class="{cls}"{data} points="{pts}">{title}</polygon>')
        elif s.moving:
            pts = _points(xy, nd) if np.all(np.isfinite(xy)) else ""
            parts.append(f'<polyline{sid} class="{cls}"{data}{width} points="{pts}">'
                         f'{title}</polyline>')
        else:  # a static line, broken where undefined (a path over unassembled positions)
            parts.append(f'<path class="{cls}"{data}{width} d="{_path_d(xy, nd)}">{title}'
                         "</path>")
    parts.append("</svg>")
    return "".join(parts)


def _path_d(xy: np.ndarray, nd: int) -> str:
    out: list[str] = []
    pen = False
    for x, y in xy:
        if not (np.isfinite(x) and np.isfinite(y)):
            pen = False
            continue
        out.append(f"{'L' if pen else 'M'}{_fmt(x, nd)} {_fmt(y, nd)}")
        pen = True
    return "".join(out) or "M0 0"


def scene_data(scene: Scene, *, prefix: str = "lw", most: int = MAX_FRAMES) -> dict[str, Any]:
    """What the viewer needs to animate ``scene``: the frames' positions (display units) and
    validity, and every moving shape's vertices per frame as integers in units of the quantum
    ``q`` [mm] (``null`` where undefined). At most ``most`` frames (:meth:`Scene.frames`);
    ``frames`` lists the indices into the scene that were kept."""
    idx = scene.frames(most)
    unit, f = scene.display
    _, q = _decimals(scene)
    shapes = []
    for i, s in enumerate(scene.shapes):
        if not s.moving:
            continue
        xy = _svg_xy(s.xy[:, :, idx])                       # (k, 2, m) mm
        ints = np.round(np.moveaxis(xy, -1, 0) / q)         # (m, k, 2)
        flat = [None if not math.isfinite(v) else int(v) for v in ints.reshape(-1).tolist()]
        shapes.append({"id": f"{prefix}-s{i}", "kind": s.kind, "k": int(s.xy.shape[0]),
                       "d": flat, "label": bool(s.label), "r": s.size * 1e3,
                       "role": s.role})
    timings = []
    for tm in scene.timings:
        rad = (tm.unit or ("rad/s" if scene.unit == "rad" else "m/s")) == "rad/s"
        speed_f, speed_unit = (30.0 / math.pi, "rpm") if rad else (1.0, "m/s")
        timings.append({"label": tm.label, "t": [round(float(v), 6) for v in tm.t[idx]],
                        "speed": [round(float(v) * speed_f, 4) for v in tm.speed[idx]],
                        "span": float(tm.span), "unit": speed_unit})
    readouts = [{"label": label, "unit": u,
                 "v": [None if not math.isfinite(v) else round(float(v), 4) for v in vals[idx]]}
                for label, u, vals in scene.readouts]
    return {"n": int(idx.size), "frames": idx.tolist(),
            "pos": [round(float(v) * f, 6) for v in scene.positions[idx]],
            "valid": [int(v) for v in scene.valid[idx]], "q": q, "unit": unit,
            "coordinate": scene.coordinate, "periodic": scene.periodic,
            "period": _period(scene), "shapes": shapes, "timings": timings,
            "readouts": readouts}


def _period(scene: Scene) -> float:
    """Seconds the cycle takes in reality (0: not known)."""
    if scene.speed <= 0 or scene.n < 2:
        return 0.0
    span = 2 * math.pi if scene.periodic else float(np.ptp(scene.positions))
    return span / scene.speed if span > 0 else 0.0


# ---------------------------------------------------------------------------------------------
# diagrams


@dataclass(frozen=True)
class RefLine:
    """A reference curve of a :class:`Diagram` with its own abscissas (display units), not
    linked to the animation: a limit, a mean, a tangent, another design's curve.

    ``colour``: a palette index (-1: the next after the diagram's series); ``dotted``: dotted
    instead of dashed (a second kind of line of the same colour)."""

    name: str
    x: np.ndarray
    y: np.ndarray
    colour: int = -1
    dotted: bool = False


@dataclass(frozen=True)
class Diagram:
    """A chart of quantities over the cycle (or a parametric curve, a hodograph).

    Attributes
    ----------
    title : str
    x : ndarray (m,)
        Abscissa of the samples, display units.
    series : sequence of (name, ndarray (m,))
        Ordinates, display units (NaN: undefined there).
    xlabel, ylabel : str
        Axis labels with units.
    positions : ndarray (m,) or None
        The driver position [SI] of each sample (links the chart to the animation); None:
        the chart is not linked.
    parametric : bool
        ``x`` is not the driver position (a hodograph): no vertical cursor, a dot per curve.
    angle : bool
        ``x`` is an angle in degrees (ticks at multiples of 30/90 deg).
    equal : bool
        Equal scales on both axes (a hodograph).
    note : str
    lines : sequence of RefLine
        Reference curves with their own abscissas (display units), dashed and not linked to
        the animation: a limit, a tangent, another design's curve.
    points : sequence of (name, x, y) or (name, x, y, colour)
        Marked points (display units), not joined: targets, a Pareto set; ``colour`` a palette
        index (default: the next after the series and lines).
    marks : sequence of (x, label)
        Vertical lines at ``x`` (display units) with a short label: switches, events.
    scene : int
        The page's drawing it is linked to (an index into :attr:`Page.choices`; 0: the
        page's drawing).
    """

    title: str
    x: np.ndarray
    series: Sequence[tuple[str, np.ndarray]]
    xlabel: str
    ylabel: str
    positions: np.ndarray | None = None
    parametric: bool = False
    angle: bool = False
    equal: bool = False
    note: str = ""
    lines: Sequence[RefLine] = ()
    points: Sequence[tuple[str, Any, Any] | tuple[str, Any, Any, int]] = ()
    marks: Sequence[tuple[float, str]] = ()
    scene: int = 0


def _ticks(lo: float, hi: float, angle: bool = False, most: int = 8) -> list[float]:
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return [lo]
    span = hi - lo
    steps = ([1.0, 5.0, 10.0, 15.0, 30.0, 45.0, 90.0, 180.0, 360.0, 720.0] if angle else [])
    step = next((s for s in steps if span / s <= most), 0.0)
    if not step:
        raw = span / most
        mag = 10.0 ** math.floor(math.log10(raw))
        step = next(m * mag for m in (1.0, 2.0, 2.5, 5.0, 10.0) if m * mag >= raw)
    first = math.ceil(lo / step - 1e-9) * step
    return [first + k * step for k in range(math.floor((hi - first) / step + 1e-9) + 1)]


def _tick_text(v: float, ticks: Sequence[float]) -> str:
    step = abs(ticks[1] - ticks[0]) if len(ticks) > 1 else abs(v) or 1.0
    nd = max(0, -math.floor(math.log10(step) + 1e-9))
    if abs(round(step, nd) - step) > 1e-9 * step:  # a step of 0.25, 0.025: one more decimal
        nd += 1
    if nd > 6 or abs(v) >= 1e6:
        return f"{v:.3g}"
    s = f"{v:.{nd}f}"
    return "0" if float(s) == 0 else s


def _decimate(n: int) -> np.ndarray:
    """Sample indices of a curve of ``n`` points kept for drawing (all up to
    :data:`MAX_DIAGRAM_SAMPLES`)."""
    if n <= MAX_DIAGRAM_SAMPLES:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, MAX_DIAGRAM_SAMPLES)).astype(int))


def _range(values: Sequence[np.ndarray]) -> tuple[float, float]:
    finite = [v[np.isfinite(v)] for v in values]
    finite = [v for v in finite if v.size]
    if not finite:
        return (-1.0, 1.0)
    lo = min(float(v.min()) for v in finite)
    hi = max(float(v.max()) for v in finite)
    if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1e-300):
        pad = abs(hi) * 0.1 or 1.0
        return (lo - pad, hi + pad)
    return (lo, hi)


def _nearest(a: np.ndarray, b: np.ndarray, period: float | None
             ) -> tuple[np.ndarray, np.ndarray]:
    """For each value of ``a``, the index of the nearest value of ``b`` (modulo ``period``)."""
    d = np.abs(a[:, None] - b[None, :])
    if period:
        d = np.mod(d, period)
        d = np.minimum(d, period - d)
    d = np.where(np.isfinite(d), d, np.inf)
    return np.argmin(d, axis=1), np.min(d, axis=1)


def diagram_svg(diagram: Diagram, scene: Scene | None, *, ident: str
                ) -> tuple[str, dict[str, Any]]:
    """The chart as SVG and the viewer's data of it (cursor, click, legend values).

    With a ``scene`` and ``diagram.positions``, ``f2s`` maps every frame of the scene's data
    (:func:`scene_data`) to the chart's nearest sample (-1: no sample within one step) and
    ``s2f`` every sample to the nearest frame.
    """
    w, h = DIAGRAM_SIZE
    ml, mr, mt, mb = DIAGRAM_MARGIN
    keep = _decimate(len(diagram.x))
    x = np.asarray(diagram.x, dtype=float)[keep]
    ys = [np.asarray(y, dtype=float)[keep] for _, y in diagram.series]
    extra = [(ln, np.asarray(ln.x, dtype=float)[_decimate(len(ln.x))],
              np.asarray(ln.y, dtype=float)[_decimate(len(ln.y))]) for ln in diagram.lines]
    dots = [(p[0], np.asarray(p[1], dtype=float).reshape(-1),
             np.asarray(p[2], dtype=float).reshape(-1)) for p in diagram.points]
    xlo, xhi = _range([x, *(a for _, a, _ in extra), *(a for _, a, _ in dots),
                       np.array([m for m, _ in diagram.marks], dtype=float)])
    ylo, yhi = _range([*ys, *(b for _, _, b in extra), *(b for _, _, b in dots)])
    if not diagram.parametric:
        pad = 0.06 * (yhi - ylo)
        ylo, yhi = ylo - pad, yhi + pad
    else:
        px_, py_ = 0.06 * (xhi - xlo), 0.06 * (yhi - ylo)
        xlo, xhi, ylo, yhi = xlo - px_, xhi + px_, ylo - py_, yhi + py_
    if diagram.equal:  # same mm per pixel on both axes
        sx = (xhi - xlo) / (w - ml - mr)
        sy = (yhi - ylo) / (h - mt - mb)
        if sx > sy:
            c = 0.5 * (ylo + yhi)
            ylo, yhi = c - 0.5 * sx * (h - mt - mb), c + 0.5 * sx * (h - mt - mb)
        else:
            c = 0.5 * (xlo + xhi)
            xlo, xhi = c - 0.5 * sy * (w - ml - mr), c + 0.5 * sy * (w - ml - mr)

    def X(v: np.ndarray) -> np.ndarray:
        return ml + (v - xlo) / (xhi - xlo) * (w - ml - mr)

    def Y(v: np.ndarray) -> np.ndarray:
        return h - mb - (v - ylo) / (yhi - ylo) * (h - mt - mb)

    parts = [f'<svg class="lw-chart" id="{ident}" viewBox="0 0 {w} {h}" '
             f'xmlns="http://www.w3.org/2000/svg" role="img" aria-label="{_e(diagram.title)}">',
             f'<rect class="lw-plot" x="{ml}" y="{mt}" width="{w - ml - mr}" '
             f'height="{h - mt - mb}"/>']
    xt = _ticks(xlo, xhi, diagram.angle)
    yt = _ticks(ylo, yhi)
    for v in xt:
        px = float(X(np.array(v)))
        parts.append(f'<line class="lw-grid" x1="{px:.1f}" x2="{px:.1f}" y1="{mt}" '
                     f'y2="{h - mb}"/><text class="lw-tick" x="{px:.1f}" y="{h - mb + 14}" '
                     f'text-anchor="middle">{_e(_tick_text(v, xt))}</text>')
    for v in yt:
        py = float(Y(np.array(v)))
        parts.append(f'<line class="lw-grid" y1="{py:.1f}" y2="{py:.1f}" x1="{ml}" '
                     f'x2="{w - mr}"/><text class="lw-tick" x="{ml - 5}" y="{py + 4:.1f}" '
                     f'text-anchor="end">{_e(_tick_text(v, yt))}</text>')
    if ylo < 0 < yhi:
        py = float(Y(np.array(0.0)))
        parts.append(f'<line class="lw-zero" y1="{py:.1f}" y2="{py:.1f}" x1="{ml}" '
                     f'x2="{w - mr}"/>')
    parts.append(f'<text class="lw-axis" x="{(ml + w - mr) / 2:.0f}" y="{h - 6}" '
                 f'text-anchor="middle">{_e(diagram.xlabel)}</text>')
    parts.append(f'<text class="lw-axis" transform="translate(13 {(mt + h - mb) / 2:.0f}) '
                 f'rotate(-90)" text-anchor="middle">{_e(diagram.ylabel)}</text>')
    for k, (v, label) in enumerate(diagram.marks):
        px = float(X(np.array(v)))
        parts.append(f'<line class="lw-event" x1="{px:.1f}" x2="{px:.1f}" y1="{mt}" '
                     f'y2="{h - mb}"><title>{_e(label)}</title></line>'
                     f'<text class="lw-event-label" x="{px + 2:.1f}" y="{mt + 9 + 10 * (k % 3)}">'
                     f"{_e(label)}</text>")  # staggered: marks close together stay legible
    for k, (ln, a, b) in enumerate(extra):
        pts = np.stack([X(a), Y(b)], axis=1)
        parts.append(f'<path class="lw-curve {_ref_class(ln, len(ys) + k)}" '
                     f'd="{_path_d(pts, 1)}"><title>{_e(ln.name)}</title></path>')
    for k, (name, a, b) in enumerate(dots):
        c = _point_colour(diagram, k)
        for u, v in zip(X(a), Y(b), strict=True):
            if math.isfinite(u) and math.isfinite(v):
                parts.append(f'<circle class="lw-point lw-c{c}" cx="{u:.1f}" cy="{v:.1f}" '
                             f'r="3.2"><title>{_e(name)}</title></circle>')
    pxs = X(x)
    for k, y in enumerate(ys):
        pts = np.stack([pxs, Y(y)], axis=1)
        parts.append(f'<path class="lw-curve lw-c{k % len(PALETTE)}" '
                     f'd="{_path_d(pts, 1)}"><title>{_e(diagram.series[k][0])}</title></path>')
    linked = scene is not None and diagram.positions is not None
    if linked and not diagram.parametric:
        parts.append(f'<line class="lw-cursor" id="{ident}-cursor" x1="0" x2="0" y1="{mt}" '
                     f'y2="{h - mb}" visibility="hidden"/>')
    if linked:
        for k in range(len(ys)):
            parts.append(f'<circle class="lw-dot lw-c{k % len(PALETTE)}" id="{ident}-dot{k}" '
                         'r="3.5" cx="0" cy="0" visibility="hidden"/>')
    parts.append("</svg>")
    data: dict[str, Any] = {
        "id": ident, "parametric": diagram.parametric, "linked": linked,
        "px": [None if not math.isfinite(v) else round(float(v), 1) for v in pxs],
        "py": [[None if not math.isfinite(v) else round(float(v), 1) for v in Y(y)]
               for y in ys],
        "vals": [[None if not math.isfinite(v) else float(f"{v:.5g}") for v in y] for y in ys],
        "names": [n for n, _ in diagram.series],
        "box": [ml, w - mr, mt, h - mb], "scene": int(diagram.scene)}
    if linked and scene is not None and diagram.positions is not None:
        fi = scene.frames(MAX_FRAMES)
        pos = np.asarray(diagram.positions, dtype=float)[keep]
        period = 2 * math.pi if (scene.periodic and scene.unit == "rad") else None
        fpos = scene.positions[fi]
        f2s, dist = _nearest(fpos, pos, period)
        steps = np.abs(np.diff(pos[np.isfinite(pos)]))
        tol = 1.01 * float(steps.max()) if steps.size else math.inf
        data["f2s"] = [int(s) if d <= tol else -1 for s, d in zip(f2s, dist, strict=True)]
        s2f, _ = _nearest(pos, fpos, period)
        data["s2f"] = [int(v) for v in s2f]
    return "".join(parts), data


# ---------------------------------------------------------------------------------------------
# tables, sections, pages


@dataclass(frozen=True)
class Table:
    """A table of strings; ``positions`` (one per row, SI, or None) link rows to the
    animation (a click on the row shows that position of the drawing ``scene``, an index
    into :attr:`Page.choices`); ``chooses`` (one per row, or None) makes a click on the row
    show that drawing of :attr:`Page.choices` (a design of a synthesis)."""

    caption: str
    head: Sequence[str]
    rows: Sequence[Sequence[str]]
    positions: Sequence[float | None] | None = None
    note: str = ""
    scene: int = 0
    chooses: Sequence[int | None] | None = None


@dataclass(frozen=True)
class Section:
    """One part of a page: a study's diagrams, tables and notes (or why it is missing), and
    verdict lines ``(ok, text)`` shown under its introduction (a motor that is OK or not)."""

    title: str
    key: str
    intro: Sequence[str] = ()
    diagrams: Sequence[Diagram] = ()
    tables: Sequence[Table] = ()
    notes: Sequence[str] = ()
    error: str = ""
    verdicts: Sequence[tuple[bool, str]] = ()


@dataclass(frozen=True)
class Page:
    """A report: the mechanism's scene, sections, input data, notes and where it came from.

    ``warnings`` are shown at the top (e.g. the ranges where the mechanism does not
    assemble); ``inputs`` are tables of the input data with units and ``source`` the input
    file as written; ``notes`` are (title, text) of the conventions and errata that apply.
    ``choices`` are (label, drawing) the player switches between (the designs of a
    synthesis; the first is ``scene``); diagrams and tables name the one they refer to.
    """

    title: str
    subtitle: str
    scene: Scene | None
    sections: Sequence[Section]
    inputs: Sequence[Table] = ()
    source: str = ""
    source_name: str = ""
    notes: Sequence[tuple[str, str]] = ()
    warnings: Sequence[str] = ()
    version: str = ""
    date: str = ""
    extra: dict[str, Any] = field(default_factory=dict)
    choices: Sequence[tuple[str, Scene]] = ()

    @property
    def scenes(self) -> list[Scene]:
        """The drawings the player shows: the choices (the first is :attr:`scene`), or the
        page's one drawing."""
        if self.choices:
            return [sc for _, sc in self.choices]
        return [] if self.scene is None else [self.scene]


def _table_html(t: Table, scene: Scene | None, tid: str) -> str:
    rows = []
    frames = scene.frames(MAX_FRAMES) if scene is not None else None
    fpos = scene.positions[frames] if scene is not None and frames is not None else None
    period = (2 * math.pi if scene is not None and scene.periodic and scene.unit == "rad"
              else None)
    for i, r in enumerate(t.rows):
        attr = ""
        pos = t.positions[i] if t.positions is not None and i < len(t.positions) else None
        pick = t.chooses[i] if t.chooses is not None and i < len(t.chooses) else None
        if fpos is not None and pos is not None and math.isfinite(pos):
            k, _ = _nearest(np.array([pos]), fpos, period)
            attr = (f' class="lw-goto" data-frame="{int(k[0])}" data-choice="{t.scene}" '
                    'title="show this position"')
        elif pick is not None:
            attr = f' class="lw-goto" data-choice="{int(pick)}" title="show this design"'
        cells = "".join(f"<td>{_e(c)}</td>" for c in r)
        rows.append(f"<tr{attr}>{cells}</tr>")
    head = "".join(f"<th>{_e(h)}</th>" for h in t.head)
    note = f'<p class="lw-note">{_e(t.note)}</p>' if t.note else ""
    return (f'<div class="lw-table-wrap"><table class="lw-table" id="{tid}">'
            f"<caption>{_e(t.caption)}</caption><thead><tr>{head}</tr></thead>"
            f"<tbody>{''.join(rows)}</tbody></table>{note}</div>")


def _point_colour(d: Diagram, k: int) -> int:
    """Palette index of the ``k``-th marked points of ``d``."""
    p = d.points[k]
    c = p[3] if len(p) > 3 else len(d.series) + len(d.lines) + k
    return int(c) % len(PALETTE)


def _ref_class(ln: RefLine, k: int) -> str:
    """CSS classes of a reference line (``k``: its default palette place)."""
    c = (ln.colour if ln.colour >= 0 else k) % len(PALETTE)
    return f"{'lw-ref lw-dotted' if ln.dotted else 'lw-ref'} lw-c{c}"


def _diagram_html(d: Diagram, scene: Scene | None, ident: str) -> tuple[str, dict[str, Any]]:
    svg, data = diagram_svg(d, scene, ident=ident)
    legend = "".join(
        f'<span class="lw-key"><i class="lw-swatch lw-c{k % len(PALETTE)}"></i>{_e(n)}'
        f'<b id="{ident}-v{k}"></b></span>' for k, (n, _) in enumerate(d.series))
    first = len(d.series)
    legend += "".join(
        f'<span class="lw-key"><i class="lw-swatch {_ref_class(ln, first + k)}"></i>'
        f"{_e(ln.name)}</span>" for k, ln in enumerate(d.lines) if ln.name)
    legend += "".join(
        f'<span class="lw-key"><i class="lw-dotkey lw-c{_point_colour(d, k)}"></i>'
        f"{_e(p[0])}</span>" for k, p in enumerate(d.points))
    note = f'<p class="lw-note">{_e(d.note)}</p>' if d.note else ""
    return (f'<figure class="lw-diagram"><figcaption>{_e(d.title)}</figcaption>{svg}'
            f'<div class="lw-legend">{legend}</div>{note}</figure>', data)


def _player(scene: Scene, prefix: str, choices: Sequence[tuple[str, Scene]] = ()) -> str:
    unit, _ = scene.display
    toggles = []
    roles = {s.role for s in scene.shapes}
    for _, other in choices[1:]:
        roles |= {s.role for s in other.shapes}
    if "path" in roles:
        toggles.append(("paths", "point paths", True))
    if "centre" in roles:
        toggles.append(("centres", "instant centres", True))
    if roles & set(FORCE_ROLES):
        toggles.append(("forces", "force elements and loads", True))
    toggles.append(("labels", "labels", True))
    boxes = "".join(f'<label><input type="checkbox" id="{prefix}-show-{k}" '
                    f'data-show="{k}"{" checked" if on else ""}> {_e(t)}</label>'
                    for k, t, on in toggles)
    notes = "".join(f'<p class="lw-note">{_e(n)}</p>' for n in scene.notes)
    constant = ", constant speed" if scene.timings else ""
    timed = "".join(f'<option value="t{k}">real time: {_e(tm.label)}</option>'
                    for k, tm in enumerate(scene.timings))
    svgs = scene_svg(scene, _first_valid(scene), prefix=prefix)
    chooser = ""
    if len(choices) > 1:
        for k, (_, other) in enumerate(choices[1:], start=1):
            svgs += scene_svg(other, _first_valid(other), prefix=f"{prefix}-v{k}").replace(
                "<svg ", '<svg style="display:none" ', 1)
        chooser = (f'<label class="lw-choice">show <select id="{prefix}-choice">'
                   + "".join(f'<option value="{k}">{_e(label)}</option>'
                             for k, (label, _) in enumerate(choices))
                   + "</select></label>")
    return (f'<div class="lw-player">{chooser}{svgs}'
            f'<div class="lw-controls">'
            f'<button type="button" id="{prefix}-play" class="lw-play" aria-label="play">'
            f"&#9654; play</button>"
            f'<input type="range" id="{prefix}-slider" class="lw-slider" min="0" '
            f'max="{max(scene.frames(MAX_FRAMES).size - 1, 0)}" value="0" step="1" '
            f'aria-label="position">'
            f'<label class="lw-speed">speed <select id="{prefix}-speed">'
            f'<option value="0.1">0.1×</option><option value="0.25">0.25×</option>'
            f'<option value="0.5">0.5×</option><option value="1" selected>1×</option>'
            f'<option value="2">2×</option><option value="4">4×</option>'
            f'<option value="real">real time{constant}</option>{timed}</select></label></div>'
            f'<div class="lw-readout"><span id="{prefix}-pos">{_e(scene.coordinate)} '
            f"[{_e(unit)}]</span> <span id=\"{prefix}-drivers\" class=\"lw-drivers\"></span> "
            f"<span id=\"{prefix}-time\" class=\"lw-time\"></span> "
            f"<span id=\"{prefix}-state\" class=\"lw-state\"></span></div>"
            f'<div class="lw-toggles">{boxes}</div>{notes}</div>')


def _first_valid(scene: Scene) -> int:
    good = np.flatnonzero(scene.valid)
    return int(good[0]) if good.size else 0


def _viewer(prefix: str, data: dict[str, Any]) -> str:
    return (f'<script type="application/json" id="{prefix}-data">{_json(data)}</script>'
            f"<script>{_asset('viewer.js')}\nlinkworkViewer({_json(prefix)});</script>")


def _view_data(scene: Scene | None, prefix: str, charts: list[dict[str, Any]],
               choices: Sequence[tuple[str, Scene]] = ()) -> dict[str, Any]:
    data: dict[str, Any] = {
        "scene": scene_data(scene, prefix=prefix) if scene is not None else None,
        "charts": charts}
    if len(choices) > 1:
        data["alternatives"] = [scene_data(sc, prefix=f"{prefix}-v{k}")
                                for k, (_, sc) in enumerate(choices) if k > 0]
        data["labels"] = [label for label, _ in choices]
    return data


def _of(scenes: Sequence[Scene], k: int) -> Scene | None:
    return scenes[k] if 0 <= k < len(scenes) else None


def page_html(page: Page, *, prefix: str = "lw") -> str:
    """The whole report as one self-contained HTML document."""
    scenes = page.scenes
    charts: list[dict[str, Any]] = []
    body: list[str] = []
    nav = "".join(f'<a href="#{prefix}-{_e(s.key)}">{_e(s.title)}</a>' for s in page.sections)
    nav += f'<a href="#{prefix}-inputs">input data</a><a href="#{prefix}-notes">notes</a>'
    for s in page.sections:
        body.append(f'<section class="lw-section" id="{prefix}-{_e(s.key)}">'
                    f"<h2>{_e(s.title)}</h2>")
        body += [f"<p>{_e(p)}</p>" for p in s.intro]
        if s.error:
            body.append(f'<p class="lw-error">{_e(s.error)}</p>')
        if s.verdicts:
            body.append('<ul class="lw-verdicts">' + "".join(
                f'<li class="{"lw-ok" if ok else "lw-bad"}">{_e(t)}</li>'
                for ok, t in s.verdicts) + "</ul>")
        if s.diagrams:
            body.append('<div class="lw-diagrams">')
            for d in s.diagrams:
                ident = f"{prefix}-c{len(charts)}"
                block, data = _diagram_html(d, _of(scenes, d.scene), ident)
                charts.append(data)
                body.append(block)
            body.append("</div>")
        for k, t in enumerate(s.tables):
            body.append(_table_html(t, _of(scenes, t.scene), f"{prefix}-{s.key}-t{k}"))
        body += [f'<p class="lw-note">{_e(n)}</p>' for n in s.notes]
        body.append("</section>")
    inputs = "".join(_table_html(t, None, f"{prefix}-in{k}") for k, t in enumerate(page.inputs))
    if page.source:
        inputs += (f"<details><summary>the input file as written "
                   f"({_e(page.source_name)})</summary><pre>{_e(page.source)}</pre></details>")
    notes = "".join(f"<h3>{_e(t)}</h3><p>{_e(x)}</p>" for t, x in page.notes)
    warn = "".join(f'<p class="lw-warning">{_e(w)}</p>' for w in page.warnings)
    player = (_player(scenes[0], prefix, page.choices) if scenes
              else '<div class="lw-player"><p class="lw-note">no drawing of this mechanism'
                   "</p></div>")
    data = _view_data(scenes[0] if scenes else None, prefix, charts, page.choices)
    return (
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<meta name=\"generator\" content=\"linkwork {_e(page.version)}\">"
        f"<title>{_e(page.title)}</title><style>{_asset('viewer.css')}</style></head>"
        f'<body><div class="lw-root lw-page" id="{prefix}">'
        f'<header><h1>{_e(page.title)}</h1><p class="lw-sub">{_e(page.subtitle)}</p>'
        f"<nav>{nav}</nav>{warn}</header>"
        f'<main class="lw-main"><aside class="lw-aside">{player}</aside>'
        f'<div class="lw-content">{"".join(body)}'
        f'<section class="lw-section" id="{prefix}-inputs"><h2>input data</h2>{inputs}'
        f'</section><section class="lw-section" id="{prefix}-notes"><h2>conventions and '
        f"notes</h2>{notes}</section></div></main>"
        f'<footer>linkwork {_e(page.version)} · {_e(page.date)} · self-contained: no network '
        f"access</footer></div>{_viewer(prefix, data)}</body></html>\n")


_COUNTER = [0]


def view_html(scene: Scene | None, summary: Table | None = None,
              diagrams: Sequence[Diagram] = (), *, prefix: str | None = None) -> str:
    """A compact view for a notebook: the animated mechanism (if any), a summary table and
    diagrams, as an HTML fragment with its own ids (several can share a page)."""
    if prefix is None:
        _COUNTER[0] += 1
        prefix = f"lwv{_COUNTER[0]}"
    charts: list[dict[str, Any]] = []
    parts = [f'<div class="lw-root lw-view" id="{prefix}"><style>{_asset("viewer.css")}'
             "</style>"]
    if scene is not None:
        parts.append(_player(scene, prefix))
    if summary is not None or diagrams:
        parts.append('<div class="lw-content">')
        if summary is not None:
            parts.append(_table_html(summary, scene, f"{prefix}-summary"))
        for d in diagrams:
            ident = f"{prefix}-c{len(charts)}"
            block, data = _diagram_html(d, scene, ident)
            charts.append(data)
            parts.append(block)
        parts.append("</div>")
    parts.append("</div>")
    parts.append(_viewer(prefix, _view_data(scene, prefix, charts)))
    return "".join(parts)


# ---------------------------------------------------------------------------------------------
# compact tables of results (notebooks)

#: Most rows of a notebook's summary table.
SUMMARY_ROWS = 40


def _flat(prefix: str, value: Any, out: list[tuple[str, Any]]) -> None:
    if isinstance(value, dict):
        for k, v in value.items():
            _flat(f"{prefix}.{k}" if prefix else str(k), v, out)
    elif isinstance(value, list | tuple) and len(value) <= 6 and all(
            isinstance(v, int | float | str | bool) or v is None for v in value):
        out.append((prefix, ", ".join("-" if v is None else str(v) if isinstance(v, str | bool)
                                      else fmt(v) for v in value)))
    elif isinstance(value, bool | str) or value is None:
        out.append((prefix, "-" if value is None else str(value)))
    elif isinstance(value, int | float | np.floating | np.integer):
        out.append((prefix, fmt(value)))


def summary_table(caption: str, values: dict[str, Any]) -> Table:
    """A two-column table of the scalars of a (nested) dict of JSON-able values, keys dotted;
    long lists and arrays left out; at most :data:`SUMMARY_ROWS` rows."""
    rows: list[tuple[str, Any]] = []
    _flat("", values, rows)
    more = len(rows) - SUMMARY_ROWS
    shown = [list(r) for r in rows[:SUMMARY_ROWS]]
    return Table(caption, ["quantity", "value"], shown,
                 note=f"{more} more in the result's to_dict()" if more > 0 else "")


def peaks_table(caption: str, peaks: Sequence[dict[str, Any]], position_unit: str) -> Table:
    """Extremes ``{"name", "value", "unit", "phi1"}`` with their driver positions (rows linked
    to the animation); angles in degrees, positions in deg or mm."""
    f = 180.0 / math.pi if position_unit == "rad" else 1e3
    shown = "deg" if position_unit == "rad" else "mm"
    rows = []
    for pk in peaks:
        value, unit = pk["value"], pk["unit"]
        if unit == "rad":
            value, unit = math.degrees(value), "deg"
        rows.append([pk["name"], fmt(value), unit_label(unit), fmt(pk["phi1"] * f, decimals=1)])
    return Table(caption, ["quantity", "value", "unit", f"at [{shown}]"], rows,
                 positions=[pk["phi1"] for pk in peaks])


def result_table(result: Any) -> Table:
    """A result's fields: scalars with their unit, per-position arrays as their range over the
    positions (min .. max, NaN left out), with the number of positions."""
    units = dict(getattr(result, "units", {}))
    rows: list[list[str]] = []
    for name, value in result.scalars().items():
        if isinstance(value, int | float | str | bool) or value is None:
            shown = value if isinstance(value, str) else (
                "-" if value is None else fmt(value) if not isinstance(value, bool)
                else str(value))
            rows.append([name, shown, unit_label(units.get(name, ""))])
    cols = result.columns()
    n = 0
    for name, arr in cols.items():
        a = np.asarray(arr, dtype=float)
        n = a.shape[-1]
        ok = a[np.isfinite(a)]
        rng = f"{fmt(ok.min())} .. {fmt(ok.max())}" if ok.size else "-"
        rows.append([name, rng, unit_label(result._unit_of(name) if hasattr(result, "_unit_of")
                                           else units.get(name, ""))])
    more = len(rows) - SUMMARY_ROWS
    return Table(f"{type(result).__name__}" + (f" over {n} positions" if n else ""),
                 ["field", "value (range)", "unit"], rows[:SUMMARY_ROWS],
                 note=f"{more} more fields: see to_dict(), to_csv()" if more > 0 else "")
