"""The report of a ``synthesis`` task file: the designs of each task it holds (what ``linkwork
synthesize path|function|motion`` finds), each one animated.

One renderer per task kind (``[path]``, ``[function]``, ``[motion]``), each running
:func:`linkwork.studies.synthesis.run`. Every design is a drawing the player chooses between
(:attr:`linkwork.plot.html.Page.choices`): the linkage over the range it runs
(:meth:`~linkwork.studies.synthesis.SynthesisStudy.motion`; a path task's four-bar, or its
Watt II or Stephenson III six-bar with the traced point P on the dyad's link), with the task's
target points or poses numbered. The diagrams: each design's coupler curve against the
targets (path), its generated output against the wanted function and its structural error
(function), its coupler's angle through the poses (motion), linked to that design's
drawing; all designs' curves together; the Pareto set of accuracy against a force where the
task judges by forces; the Burmester centre and circle points. The ranked designs table: a
row shows that design.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from linkwork.io.synthesis import SynthesisFile
from linkwork.plot.html import Diagram, RefLine, Section, Table
from linkwork.plot.numbers import fmt
from linkwork.plot.scene import Scene, Shape, planar_scene, target_shapes, with_shapes
from linkwork.report.base import Options, Renderer
from linkwork.studies import synthesis as study_synthesis
from linkwork.studies.synthesis import SynthesisStudy, design_summary, design_table

__all__ = ["RENDERERS", "scenes", "section"]

#: Positions of a design's drawing over the range it runs.
POSITIONS = 361
#: What a path task's ``linkage`` names.
LINKAGES = {"fourbar": "four-bar", "stephenson": "Stephenson III six-bar",
            "watt": "Watt II six-bar"}
#: Units and labels of the force metrics a task may judge by.
METRICS = {"error": ("error f", "m²"), "peak_torque": ("peak driving torque", "N·m"),
           "peak_bearing": ("peak bearing load", "N"), "rms_shaking": ("RMS shaking force", "N"),
           "min_transmission_angle": ("minimum transmission angle", "deg")}


def _mm(v: Any) -> str:
    return fmt(float(v) * 1e3)


def _deg(v: Any) -> str:
    return fmt(math.degrees(float(v)))


def _fourbar(study: SynthesisStudy, i: int) -> Any:
    d = study.designs[i]
    return d.fourbar if study.kind == "motion" else d


def _label(study: SynthesisStudy, i: int) -> str:
    d = study.designs[i]
    if study.kind == "path":
        what = f"f = {d.error:.3g} m²"
    elif study.kind == "function":
        err = math.degrees(d.max_error) if d.kind == "fourbar" else d.max_error * 1e3
        what = f"{d.method}, max error {err:.3g} {'deg' if d.kind == 'fourbar' else 'mm'}"
    else:
        what = f"μmin {_deg(d.fourbar.checks.get('min_transmission_angle', math.nan))} deg"
    return f"{study.kind} design {i + 1}: {what}"


def _design_scene(study: SynthesisStudy, i: int) -> Scene:
    """Design ``i`` over its range, with the task's targets (path: points; motion: poses,
    and the pose frame's x axis carried by the coupler)."""
    kin = study.motion(i, POSITIONS)
    sc = planar_scene(kin, title=_label(study, i))
    x0, y0, x1, y1 = sc.bounds()
    size = 0.012 * max(x1 - x0, y1 - y0, 1e-9)
    if study.kind == "path":
        return with_shapes(sc, target_shapes(study.result.points, size=size))
    if study.kind == "motion":
        poses = np.asarray(study.result.poses, dtype=float)
        theta = np.asarray(kin.angle("coupler"), dtype=float)
        offset = poses[0, 2] - theta[0]          # the pose frame turns with the coupler
        P = kin.point("coupler", "P")
        a = theta + offset
        axis = np.stack([np.stack([P.x, P.y]),
                         np.stack([P.x + 6 * size * np.cos(a), P.y + 6 * size * np.sin(a)])])
        carried = Shape("polyline", "tracer", "pose axis on the coupler", axis, colour=1)
        return with_shapes(sc, [*target_shapes(poses[:, :2], size=size, angles=poses[:, 2]),
                                carried])
    return sc


def scenes(study: SynthesisStudy, options: Options) -> list[tuple[str, Scene]]:
    """Every design's drawing, best first."""
    return [(_label(study, i), _design_scene(study, i)) for i in range(len(study.designs))]


def _path_diagrams(study: SynthesisStudy) -> list[Diagram]:
    res = study.result
    pts = np.asarray(res.points, dtype=float) * 1e3
    targets = [("targets", pts[:, 0], pts[:, 1])]
    out = []
    curves = []
    for i in range(len(study.designs)):
        kin = study.motion(i, POSITIONS)
        P = kin.point(study.traced_body, "P")
        curves.append((P.x * 1e3, P.y * 1e3, np.asarray(kin.phi1)))
    out.append(Diagram(
        title="coupler curves of the designs against the targets",
        x=pts[:, 0], series=[], xlabel="x [mm]", ylabel="y [mm]", parametric=True,
        equal=True, lines=[RefLine(f"design {i + 1}", x, y, colour=i)
                           for i, (x, y, _) in enumerate(curves)], points=targets,
        note="each design over the range its crank runs (a full turn when it rotates)"))
    for i, (x, y, phi) in enumerate(curves):
        d = study.designs[i]
        out.append(Diagram(
            title=f"design {i + 1}: coupler point P against the targets",
            x=x, series=[("P", y)], xlabel="x [mm]", ylabel="y [mm]", positions=phi,
            parametric=True, equal=True, points=targets, scene=i,
            note=f"error f = {d.error:.3g} m², largest distance to a target "
                 f"{_mm(d.checks.get('max_deviation', math.nan))} mm"))
    if res.objective != "sum_squares" and any(d.forces for d in study.designs):
        out.append(_pareto(study))
    return out


def _metric(d: Any, k: str) -> float:
    if k == "error":
        return float(d.error)
    if k == "min_transmission_angle":
        return math.degrees(float(d.checks.get(k, math.nan)))
    return float(d.forces.get(k, math.nan))


def _pareto(study: SynthesisStudy) -> Diagram:
    """The designs in the plane of two metrics (the task's first two; the error on a log
    scale), the Pareto set joined."""
    res = study.result
    obj = study.doc.objective
    metrics = list(getattr(obj, "metrics", None) or ["error", "peak_torque"])[:2]
    if len(metrics) < 2:
        metrics = ["error", "peak_torque"]
    kx, ky = metrics
    xs = np.array([_metric(d, kx) for d in study.designs])
    ys = np.array([_metric(d, ky) for d in study.designs])
    logx = kx == "error" and bool(np.all(xs > 0))
    shown = np.log10(xs) if logx else xs
    name_x, unit_x = METRICS[kx]
    name_y, unit_y = METRICS[ky]
    lines = []
    if res.pareto:
        idx = np.array(res.pareto)
        o = idx[np.argsort(shown[idx])]
        lines.append(RefLine("Pareto set", shown[o], ys[o], colour=9))
    return Diagram(
        title=f"accuracy against dynamics: {name_x} and {name_y} of the designs",
        x=shown, series=[], xlabel=(f"log10 {name_x} [{unit_x}]" if logx
                                    else f"{name_x} [{unit_x}]"),
        ylabel=f"{name_y} [{unit_y}]", parametric=True, lines=lines,
        points=[(f"design {i + 1}", shown[[i]], ys[[i]], i) for i in range(len(xs))],
        note=f"{res.objective} objective; the forces re-solved by the engine with the task's "
             "masses, crank speed and tool force (docs/synthesis.md)")


def _function_diagrams(study: SynthesisStudy) -> list[Diagram]:
    res = study.result
    four = res.kind == "fourbar"
    f, unit = (180 / math.pi, "deg") if four else (1e3, "mm")
    what = "rocker angle ψ" if four else "slide Y"
    out = []
    for i, d in enumerate(study.designs):
        x = np.degrees(d.input)
        prec = ([("precision points", np.degrees(d.precision_inputs),
                  np.zeros(len(d.precision_inputs)))]
                if d.precision_inputs is not None else [])
        out.append(Diagram(
            title=f"design {i + 1} ({d.method}): structural error (generated − wanted {what})",
            x=x, series=[("error", np.asarray(d.structural_error) * f)],
            xlabel="input crank angle [deg]", ylabel=f"error [{unit}]", positions=d.input,
            angle=True, points=prec, scene=i,
            note=f"max {fmt(d.max_error * f)} {unit}, RMS {fmt(d.rms_error * f)} {unit}"))
    best = study.designs[0]
    out.append(Diagram(
        title=f"the wanted function and the designs' outputs ({what})",
        x=np.degrees(best.input), series=[("wanted", np.asarray(best.wanted) * f)],
        xlabel="input crank angle [deg]", ylabel=f"{what} [{unit}]", positions=best.input,
        angle=True, lines=[RefLine(f"design {i + 1}", np.degrees(d.input),
                                   np.asarray(d.actual) * f, colour=i + 1)
                           for i, d in enumerate(study.designs)]))
    return out


def _motion_diagrams(study: SynthesisStudy) -> list[Diagram]:
    res = study.result
    poses = np.asarray(res.poses, dtype=float)
    out = []
    for i, d in enumerate(study.designs):
        kin = study.motion(i, POSITIONS)
        theta = np.unwrap(np.asarray(kin.angle("coupler"), dtype=float))
        a = theta + (poses[0, 2] - theta[0])
        fb = d.fourbar
        phi = np.asarray(kin.phi1, dtype=float)
        at = fb.theta2 + float(fb.params["theta0"])           # the crank at the poses
        lo = float(np.min(phi))
        at = lo + np.mod(at - lo + 1e-9, 2 * np.pi) - 1e-9     # within the drawn range
        order = np.argsort(phi)
        near = np.interp(at, phi[order], a[order])
        want = poses[:, 2] + 2 * np.pi * np.round((near - poses[:, 2]) / (2 * np.pi))
        out.append(Diagram(
            title=f"design {i + 1}: the coupler's angle through the poses",
            x=np.degrees(kin.phi1), series=[("pose frame angle", np.degrees(a))],
            xlabel="crank angle φ1 [deg]", ylabel="angle [deg]", positions=kin.phi1,
            angle=True, points=[("poses", np.degrees(at), np.degrees(want))], scene=i,
            note=f"largest pose error {fmt(d.pose_error * 1e3)} mm"))
    burm: list[tuple[str, np.ndarray, np.ndarray]] = []
    for name, arr in (("centre points", res.centre_points),
                      ("circle points (pose 1)", res.circle_points)):
        a = np.asarray(arr, dtype=float).reshape(-1, 2) * 1e3
        if a.size:
            burm.append((name, a[:, 0], a[:, 1]))
    piv = np.array([[*d.c1, *d.c2] for d in study.designs], dtype=float).reshape(-1, 2) * 1e3
    burm.append(("the designs' fixed pivots", piv[:, 0], piv[:, 1]))
    burm.append(("poses", poses[:, 0] * 1e3, poses[:, 1] * 1e3))
    xs = np.concatenate([b[1] for b in burm])
    ys = np.concatenate([b[2] for b in burm])
    out.append(Diagram(
        title="Burmester: centre points, circle points, the designs' pivots",
        x=xs[:1], series=[], xlabel="x [mm]", ylabel="y [mm]", parametric=True, equal=True,
        points=burm, note=f"{res.n_dyads} dyads, {res.n_pairs} pairs checked; "
                          f"all points: x {fmt(xs.min())}..{fmt(xs.max())}, "
                          f"y {fmt(ys.min())}..{fmt(ys.max())} mm"))
    return out


def _table(study: SynthesisStudy) -> Table:
    """The ranked designs as ``linkwork synthesize`` prints them
    (:func:`~linkwork.studies.synthesis.design_table`), the Pareto set marked; a row shows
    its design."""
    res = study.result
    head, rows = design_table(study)
    n = len(rows)
    pareto = getattr(res, "pareto", ())           # a six-bar search has no Pareto set
    if study.kind == "path" and pareto:
        head = [*head, "Pareto"]
        rows = [[*r, "yes" if i in pareto else ""] for i, r in enumerate(rows)]
    caption = design_summary(study)
    return Table(f"{caption}; click a row to show the design", head, rows,
                 chooses=list(range(n)))


def section(study: SynthesisStudy, options: Options) -> Section:
    """The ranked designs, their diagrams (each linked to its drawing) and the overviews."""
    res = study.result
    kind = study.kind
    if kind == "path":
        linkage = "fourbar" if study.doc.path is None else study.doc.path.linkage
        intro = [f"{LINKAGES[linkage]}s: {len(res.points)} target points"
                 f"{' (closed path)' if res.closed else ''}, "
                 f"timing {'prescribed' if res.timing is not None else 'free'}, constraints "
                 f"{', '.join(res.constraints) or 'none'}, {res.objective} objective; search "
                 f"of {res.n_evaluated} candidates in {fmt(res.time, digits=3)} s."]
        diagrams = _path_diagrams(study)
    elif kind == "function":
        best = study.designs[0]
        intro = [f"{res.kind.replace('_', '-')} generating y(x) for x in "
                 f"{fmt(res.x_range[0])}..{fmt(res.x_range[1])}: the input crank over "
                 f"{_deg(best.input[0])}..{_deg(best.input[-1])} deg (the best design)."]
        diagrams = _function_diagrams(study)
    else:
        intro = [f"{len(res.poses)} poses of the coupler (point and angle)."]
        diagrams = _motion_diagrams(study)
    intro.append("Each design is a drawing of the player (the chooser above it, or a click on "
                 "a design's row); its diagrams follow it.")
    return Section(title=f"{kind} synthesis", key=f"synthesis-{kind}", intro=intro,
                   diagrams=diagrams, tables=[_table(study)])


def notes(study: SynthesisStudy) -> list[tuple[str, str]]:
    """The parametrisation and conventions of the designs (docs/synthesis.md)."""
    if study.kind == "path" and study.doc.path is not None and \
            study.doc.path.linkage != "fourbar":
        host = ("coupler (Stephenson III: (cx, cy) in the coupler's frame, origin A, x along "
                "A→B)" if study.doc.path.linkage == "stephenson" else
                "rocker (Watt II: (cx, cy) in the rocker's frame, origin O4, x along O4→B)")
        return [(f"{study.kind} synthesis: conventions",
                 "Six-bars: a driving four-bar in the literature's parameters (r1 frame O2O4, r2 "
                 "crank, r3 coupler AB, r4 rocker, the crank pivot (x0, y0), θ0 the frame line's "
                 f"angle; crank angles from the frame line), a point C on its {host}, a dyad "
                 "C-D-O6 (r5 = CD, r6 = O6D, the fixed pivot O6 = (x6, y6)) and the traced point "
                 "P at (px, py) in the frame of CD (origin C, x along C→D); branches of B and of "
                 "D (the engine's convention). The error f is the sum of squared distances to "
                 "the targets. Every design shown is defect-free (order, circuit, toggle of "
                 "either loop, transmission checked by the engine); see docs/synthesis.md.")]
    return [(f"{study.kind} synthesis: conventions",
             "Four-bars in the literature's parameters (Cabrera et al. 2002): r1 frame O2O4, "
             "r2 crank, r3 coupler AB, r4 rocker, the coupler point (rcx, rcy) in the "
             "coupler's frame (origin A, x along A→B), the crank pivot (x0, y0), θ0 the frame "
             "line's angle; crank angles from the frame line; branch +1: B left of A→O4. The "
             "error f is the sum of squared distances to the targets. Every design shown is "
             "defect-free (order, circuit, branch, transmission checked by the engine); see "
             "docs/synthesis.md.")]


def _inputs(kind: str, doc: SynthesisFile) -> list[Table]:
    """The task of ``kind`` as given: target points and the search, the function, the
    poses."""
    if kind == "path" and doc.path is not None:
        p, s, o = doc.path, doc.search, doc.objective
        pts = Table("[path] target points", ["#", "x [mm]", "y [mm]"] + (
            [] if p.timing is None else ["crank angle [deg]"]),
            [[str(i + 1), _mm(x), _mm(y)] + ([] if p.timing is None else [_deg(p.timing[i])])
             for i, (x, y) in enumerate(p.points)])
        rows = [["linkage", LINKAGES[p.linkage]],
                ["timing", "free" if p.timing is None else "prescribed"],
                ["closed path", "yes" if p.closed else "no"],
                ["constraints", ", ".join(p.constraints) or "none"],
                ["min. transmission angle", "-" if p.min_transmission is None else
                 f"{_deg(p.min_transmission)} deg"],
                ["search", f"{s.candidates} candidates, {s.refine} refined, {s.designs} "
                           f"designs, seed {s.seed}"],
                ["objective", o.kind if o.kind == "sum_squares" else
                 f"{o.kind} over {', '.join(o.metrics)} at {fmt(o.omega1 * 30 / math.pi)} "
                 f"rpm, tool force ({fmt(o.force[0])}, {fmt(o.force[1])}) N"]]
        return [pts, Table("[path] task", ["", "value"], rows)]
    if kind == "function" and doc.function is not None:
        f = doc.function
        out = f.output
        rows = [["mechanism", f.mechanism], ["y(x)", f.y if isinstance(f.y, str) else
                                            f"table over x = {f.x}: {f.y}"],
                ["x range", f"{fmt(f.x_range[0])} .. {fmt(f.x_range[1])}"],
                ["input crank", ("searched" if f.input.start is None else
                                 f"from {_deg(f.input.start)} deg")
                 + f", span {_deg(f.input.span)} deg"]]
        if out is not None:
            rows.append(["output", ("searched" if out.start is None else
                                    f"from {_deg(out.start)} deg")
                         + f", span {_deg(out.span)} deg"])
        if f.stroke is not None:
            rows.append(["stroke", f"{_mm(f.stroke)} mm"])
        rows += [["frame d", f"{_mm(f.frame)} mm"], ["precision points", str(f.points)]]
        return [Table("[function] task", ["", "value"], rows)]
    if kind == "motion" and doc.motion is not None:
        m = doc.motion
        rows = [[str(i + 1), _mm(p[0]), _mm(p[1]), _deg(p[2])] for i, p in enumerate(m.poses)]
        return [Table("[motion] poses (the coupler's reference point and angle)",
                      ["#", "x [mm]", "y [mm]", "angle [deg]"], rows,
                      note=("grashof crank-rocker asked; " if m.grashof else "")
                      + ("" if m.min_transmission is None else
                         f"min. transmission angle {_deg(m.min_transmission)} deg"))]
    return []


def _renderer(kind: str) -> Renderer:
    def run(doc: SynthesisFile, options: Options) -> SynthesisStudy:
        return study_synthesis.run(doc, kind)

    def applies(doc: SynthesisFile) -> bool:
        return getattr(doc, kind) is not None

    def inputs(doc: SynthesisFile) -> list[Table]:
        return _inputs(kind, doc)

    return Renderer(key=f"synthesis-{kind}", title=f"{kind} synthesis",
                    file_type=SynthesisFile, run=run, section=section, applies=applies,
                    scenes=scenes, inputs=inputs, notes=notes)


#: One renderer per task kind of a synthesis file.
RENDERERS = [_renderer(kind) for kind in ("path", "function", "motion")]
