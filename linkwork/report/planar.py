"""The report of a ``planar`` file: kinematics and dynamics over the cycle (what ``linkwork
analyze`` shows), with the animated mechanism.

The study is :func:`linkwork.studies.planar.analyze` with ``on_failure="nan"``: where the
mechanism does not assemble over part of the range, those ranges are stated at the top of the
page, the animation skips them and the diagrams leave them empty.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from linkwork.errors import format_angle_ranges
from linkwork.io.planar import PlanarFile
from linkwork.plot.html import Diagram, Section, Table
from linkwork.plot.numbers import fmt, scale_of, unit_label
from linkwork.plot.scene import Scene
from linkwork.report.base import (
    Options,
    Renderer,
    diagram,
    driver_display,
    prefixed,
)
from linkwork.studies import planar as study_planar
from linkwork.studies.planar import PlanarStudy

__all__ = ["RENDERER", "inputs", "notes", "scene", "section"]


def run(doc: PlanarFile, options: Options) -> PlanarStudy:
    """The study of ``linkwork analyze``, solving the rest of the range where the mechanism
    does not assemble over part of it."""
    return study_planar.analyze(doc, on_failure="nan")


def scene(study: PlanarStudy, options: Options) -> Scene:
    """The mechanism over the cycle, with the requested point paths and instant centres."""
    return study.scene(paths=options.paths, centres=options.centres)


def _several(study: PlanarStudy) -> bool:
    """Several drivers: the positions are numbered along their path."""
    return bool(study.mechanism.n_drivers > 1)


def _coord(study: PlanarStudy) -> tuple[str, str]:
    """Name of the driver coordinate and its SI unit (several drivers: the position's index,
    no unit)."""
    if _several(study):
        return ("position", "")
    return ("φ1", "rad") if study.crank else ("s1", "m")


def _positions(study: PlanarStudy) -> np.ndarray:
    """What the diagrams run over: the driver's positions [rad or m], or the index along
    several drivers' path."""
    kin = study.kinematics
    if _several(study):
        return np.arange(kin.n, dtype=float)
    return np.asarray(kin.phi1, dtype=float)


def _driving(study: PlanarStudy) -> list[Diagram]:
    """The driving torque (force) Q with its mean; several drivers: the torques of the cranks
    and the forces of the linear drivers, each driver's own, and their coordinates along the
    path."""
    dyn = study.dynamics
    name, unit = _coord(study)
    phi = _positions(study)
    if not _several(study):
        qu = study.mechanism.driver.field_units["Q"]
        q_series = [("Q", dyn.Q)]
        if dyn.has_friction:
            q_series.append(("Q without friction", dyn.Q_frictionless))
        mean = fmt(study.means["Q_mean"], scale_of(dyn.Q))
        load = "driving torque" if study.crank else "driving force"
        return [diagram(f"{load} Q", phi, unit, name, q_series, "Q", qu,
                        note=f"mean over the range (work / range): {mean} {unit_label(qu)}")]
    drivers = study.mechanism.drivers
    means = study.means["Q_mean"]
    out = []
    for kind, what, qu, shown, f in (("crank", "driving torques", "N*m", "deg", 180 / math.pi),
                                     ("linear", "driving forces", "N", "mm", 1e3)):
        ks = [k for k, d in enumerate(drivers) if d.kind == kind]
        if not ks:
            continue
        q = np.asarray(dyn.Q, dtype=float)
        note = "mean over the path (work / travel): " + ", ".join(
            f"{drivers[k].joint} " + ("-" if means[drivers[k].joint] is None else
                                      f"{fmt(means[drivers[k].joint], scale_of(q[k]))} "
                                      f"{unit_label(qu)}") for k in ks)
        out.append(diagram(f"{what} Q of the drivers", phi, unit, name,
                           [(f"Q {drivers[k].joint}", q[k]) for k in ks], "Q", qu, note=note))
        out.append(diagram(f"the drivers' coordinates along the path ({kind})", phi, unit, name,
                           [(drivers[k].joint, np.asarray(study.kinematics.phi1[k]) * f)
                            for k in ks], "φ" if kind == "crank" else "s", shown, factor=1.0))
    return out


def diagrams(study: PlanarStudy) -> list[Diagram]:
    """The diagrams over the cycle: driving torque (force), joint reactions, shaking force and
    moment, the bodies' angles, angular velocities and accelerations, slides of the prismatic
    and pin-in-slot joints, transmission angles, kinetic energy, the shaking-force
    hodograph."""
    kin, dyn = study.kinematics, study.dynamics
    name, unit = _coord(study)
    phi = _positions(study)
    out = _driving(study)
    out.append(diagram("joint reactions |R| (force of joint body a on body b)", phi, unit, name,
                       [(j, dyn.reaction_magnitude(j)) for j in dyn.joints], "|R|", "N"))
    ab = np.asarray(dyn.about, dtype=float) * 1e3
    out.append(diagram("shaking force on the frame", phi, unit, name,
                       [("Fx", dyn.shaking_fx), ("Fy", dyn.shaking_fy),
                        ("|F|", np.hypot(dyn.shaking_fx, dyn.shaking_fy))], "F", "N"))
    out.append(diagram(f"shaking moment about ({ab[0]:g}, {ab[1]:g}) mm", phi, unit, name,
                       [("M", dyn.shaking_m)], "M", "N*m"))
    bodies = [b.name for b in study.mechanism.bodies]
    rows = [kin.bodies.index(b) for b in bodies]
    out.append(diagram("angles of the bodies θ", phi, unit, name,
                       [(b, np.unwrap(kin.theta[i])) for b, i in zip(bodies, rows, strict=True)],
                       "θ", "deg", factor=180.0 / math.pi))
    out.append(diagram("angular velocities ω", phi, unit, name,
                       [(b, kin.omega[i]) for b, i in zip(bodies, rows, strict=True)], "ω",
                       "rad/s", factor=1.0))
    out.append(diagram("angular accelerations ε", phi, unit, name,
                       [(b, kin.eps[i]) for b, i in zip(bodies, rows, strict=True)], "ε",
                       "rad/s²", factor=1.0))
    lines = [j.name for j in study.mechanism.joints if j.has_line]
    if lines:
        slides = {j: kin.slide(j) for j in lines}
        out.append(diagram("slides along the guides and slots s (relative to the guide's "
                           "body)", phi, unit, name, [(j, v[0]) for j, v in slides.items()],
                           "s", "mm", factor=1e3))
        out.append(diagram("sliding velocities", phi, unit, name,
                           [(j, v[1]) for j, v in slides.items()], "v", "m/s", factor=1.0))
        out.append(diagram("sliding accelerations", phi, unit, name,
                           [(j, v[2]) for j, v in slides.items()], "a", "m/s²", factor=1.0))
    if study.transmission:
        out.append(diagram("transmission angles μ (90° best)", phi, unit, name,
                           [(k, mu) for k, (mu, _) in study.transmission.items()], "μ", "deg",
                           factor=180.0 / math.pi))
    out.append(diagram("kinetic energy T", phi, unit, name, [("T", dyn.T)], "T", "J"))
    shown = {e["name"] for e in study.loads}
    for u, what in (("N", "forces"), ("N*m", "couples")):
        series = [(f"{ap.name} ({ap.kind})", ap.value) for ap in dyn.loads
                  if ap.name in shown and ap.unit == u]
        if series:
            out.append(diagram(f"loads and force elements: {what} (springs, dampers: tension +)",
                               phi, unit, name, series, "F" if u == "N" else "M", u))
    if any(ap.kind == "spring" for ap in dyn.loads):
        out.append(diagram("energy stored in the springs V", phi, unit, name, [("V", dyn.V)],
                           "V", "J"))
    div, lab = prefixed("N", dyn.shaking_fx, dyn.shaking_fy)
    out.append(Diagram(title="shaking force hodograph (the tip of F over the cycle)",
                       x=np.asarray(dyn.shaking_fx) / div,
                       series=[("F", np.asarray(dyn.shaking_fy) / div)],
                       xlabel=f"Fx [{lab}]", ylabel=f"Fy [{lab}]", positions=phi,
                       parametric=True, equal=True))
    return out


def _shown(study: PlanarStudy) -> tuple[str, float]:
    unit, f, _ = driver_display(_coord(study)[1])
    return unit, f


def _drivers_at(study: PlanarStudy, phi: Any) -> str:
    """Every driver's coordinate at a position (its values ``phi`` [rad or m], one each)."""
    return ", ".join(
        f"{d.joint} {fmt(float(v) * (180 / math.pi if d.kind == 'crank' else 1e3), decimals=1)}"
        f" {'deg' if d.kind == 'crank' else 'mm'}"
        for d, v in zip(study.mechanism.drivers, phi, strict=True))


def _nearest_positions(study: PlanarStudy, table: np.ndarray) -> list[float]:
    """The analysed position (index along several drivers' path) nearest each column of
    ``table`` ``(n_drivers, m)`` (every driver's travel counting alike)."""
    phi = np.asarray(study.kinematics.phi1, dtype=float)
    span = np.ptp(phi, axis=1, keepdims=True)
    span = np.where(span > 0, span, 1.0)
    d = np.abs(phi[:, :, None] - table[:, None, :]) / span[:, :, None]
    return [float(k) for k in np.argmin(d.sum(axis=0), axis=0)]


def tables(study: PlanarStudy) -> list[Table]:
    """The characteristics: extremes with their positions, dead centres, means, the structure,
    the table positions (as ``linkwork analyze`` prints), friction losses."""
    name, _ = _coord(study)
    unit, f = _shown(study)
    several = _several(study)
    pos_head = f"{name} [{unit}]" if unit else name
    out: list[Table] = []
    scales: dict[str, float] = {}
    for pk in study.peaks:
        scales[pk["unit"]] = max(scales.get(pk["unit"], 0.0), abs(pk["value"]))
    rows, where = [], []
    for pk in study.peaks:
        value, u = pk["value"], pk["unit"]
        if u == "rad":
            value, u = math.degrees(value), "deg"
        at = ([str(pk["position"]), _drivers_at(study, pk["phi1"])] if several
              else [fmt(pk["phi1"] * f, decimals=1)])
        rows.append([pk["name"], fmt(value, scales.get(pk["unit"], 0.0)), unit_label(u), *at])
        where.append(float(pk["position"]) if several else pk["phi1"])
    blank = ["", ""] if several else [""]
    if several:
        for k, d in enumerate(study.mechanism.drivers):
            qm = study.means["Q_mean"][d.joint]
            rows.append([f"Q {d.joint} mean (work / travel)", "-" if qm is None else
                         fmt(qm, scale_of(study.dynamics.Q[k])),
                         unit_label(d.field_units["Q"]), *blank])
            where.append(None)
        power = study.dynamics.total_power
    else:
        qu = unit_label(study.mechanism.driver.field_units["Q"])
        rows.append(["Q mean (work / range)",
                     fmt(study.means["Q_mean"], scale_of(study.dynamics.Q)), qu, *blank])
        where.append(None)
        power = study.dynamics.power
    rows.append(["driving power, mean", fmt(study.means["power_mean"], scale_of(power)), "W",
                 *blank])
    where.append(None)
    out.append(Table(f"extremes over the cycle ({study.kinematics.n} positions; click a row to "
                     "show it)", ["quantity", "value", "unit", pos_head,
                                  *(["the drivers there"] if several else [])], rows,
                     positions=where))
    if study.dead_centres:
        out.append(Table("dead centres (the output's motion reverses)",
                         ["what", "joint", pos_head],
                         [[lab, joint, fmt(d.phi1 * f, decimals=2)] for d, (lab, joint) in
                          zip(study.dead_centres, study.dead_centre_labels, strict=True)],
                         positions=[d.phi1 for d in study.dead_centres]))
    s = study.structure
    out.append(Table(f"structure: mobility W = {s.mobility}, {s.formula()}",
                     ["group", "kind", "class", "bodies", "joints", "branch"],
                     [[g.key, g.kind, str(g.cls), ", ".join(g.bodies), ", ".join(g.joints),
                       str(study.kinematics.branches.get(g.key, 1))] for g in s.groups]))
    tk, td = study.table_kinematics, study.table_dynamics
    f_n = scales.get("N", 0.0)
    drivers = study.mechanism.drivers
    if several:
        head = [f"{'φ' if d.kind == 'crank' else 's'} {d.joint} "
                f"[{'deg' if d.kind == 'crank' else 'mm'}]" for d in drivers]
        head += [f"Q {d.joint} [{unit_label(d.field_units['Q'])}]" for d in drivers]
        tpos = _nearest_positions(study, np.asarray(study.table_positions, dtype=float))
    else:
        head = [pos_head, f"Q [{unit_label(drivers[0].field_units['Q'])}]"]
        tpos = list(study.table_positions)
    head += [f"|R {j}| [N]" for j in td.joints]
    head += ["|F_sh| [N]", "M_sh [N·m]"] + [f"μ {k} [deg]" for k in study.table_transmission]
    trows = []
    tq = np.asarray(td.Q, dtype=float).reshape(len(drivers), -1)
    tphi = np.asarray(study.table_positions, dtype=float).reshape(len(drivers), -1)
    for i in range(tk.n):
        r = [fmt(tphi[k, i] * (180 / math.pi if d.kind == "crank" else 1e3), decimals=1)
             for k, d in enumerate(drivers)]
        r += [fmt(tq[k, i], scales.get(d.field_units["Q"], 0.0)) for k, d in enumerate(drivers)]
        r += [fmt(td.reaction_magnitude(j)[i], f_n) for j in td.joints]
        r += [fmt(np.hypot(td.shaking_fx[i], td.shaking_fy[i]), f_n),
              fmt(td.shaking_m[i], scales.get("N*m", 0.0))]
        r += [fmt(math.degrees(mu[i]), decimals=1) for mu, _ in study.table_transmission.values()]
        trows.append(r)
    out.append(Table("driving torque, joint reactions, shaking force and moment at the table "
                     "positions", head, trows, positions=tpos))
    if study.loads:
        top = max((abs(e["work"]) for e in study.loads if e["work"] is not None), default=0.0)
        out.append(Table(
            "loads and force elements over the cycle (springs, dampers: tension +)",
            ["load", "kind", "min", "max", "unit", "length [mm]", "work [J]"],
            [[e["name"], e["kind"], fmt(np.nan if e["min"] is None else e["min"],
                                        max(abs(e["min"] or 0), abs(e["max"] or 0))),
              fmt(np.nan if e["max"] is None else e["max"],
                  max(abs(e["min"] or 0), abs(e["max"] or 0))), unit_label(e["unit"]),
              "" if "length" not in e else "..".join(fmt(v * 1e3, decimals=1)
                                                      for v in e["length"]),
              fmt(np.nan if e["work"] is None else e["work"], top)] for e in study.loads],
            note="work: done on the mechanism over the range (negative: taken from it)"))
    fr = study.friction
    if fr is not None:
        top = max((abs(v) for v in fr["losses"].values() if v is not None), default=0.0)
        eta = fr["efficiency_cycle"]
        runs = ", ".join(f"{a * f:.1f}..{b * f:.1f} {unit}".strip()
                         for a, b in fr["self_locking"])
        out.append(Table(
            "friction losses over the cycle", ["joint", "loss [J]", "share of the driver's "
                                               "work [%]"],
            [[j, fmt(np.nan if v is None else v, top),
              fmt(np.nan if fr["loss_share"][j] is None else 100 * fr["loss_share"][j],
                  decimals=2)] for j, v in fr["losses"].items()],
            note=("cycle efficiency (useful work / driver's work): "
                  + (fmt(eta, decimals=4) if eta is not None else "undefined") + "; "
                  + (f"self-locking at {runs}" if runs else "no self-locking over the range"))))
    return out


def section(study: PlanarStudy, options: Options) -> Section:
    """Diagrams and characteristics of the cycle."""
    kin = study.kinematics
    name, _ = _coord(study)
    unit, f = _shown(study)
    tail = (f"Mobility W = {study.structure.mobility}; structure "
            f"{study.structure.formula()}. Click or drag on a diagram to show that position.")
    if _several(study):
        phi = np.asarray(kin.phi1, dtype=float)
        first = _drivers_at(study, phi[:, 0]).split(", ")
        last = _drivers_at(study, phi[:, -1]).split(", ")
        each = "; ".join(f"{d.joint} ({d.kind}) from {a.split(' ', 1)[1]} to "
                         f"{b.split(' ', 1)[1]}"
                         for d, a, b in zip(study.mechanism.drivers, first, last, strict=True))
        intro = [f"{kin.n} positions along the path of {study.mechanism.n_drivers} drivers "
                 f"(numbered 0 to {kin.n - 1}; the player reads out every driver's "
                 f"coordinate): {each}. {tail}"]
    else:
        drv = study.mechanism.driver
        speed = (f"ω1 = {fmt(drv.omega1)} rad/s ({fmt(drv.omega1 * 30 / math.pi)} rpm)"
                 if study.crank else f"v1 = {fmt(drv.omega1)} m/s")
        intro = [f"{kin.n} positions from {name} = {fmt(kin.phi1[0] * f, decimals=2)} to "
                 f"{fmt(kin.phi1[-1] * f, decimals=2)} {unit}, driver {drv.kind} on joint "
                 f"{drv.joint}, {speed}. {tail}"]
    return Section(title="kinematics and dynamics", key="planar", intro=intro,
                   diagrams=diagrams(study), tables=tables(study))


def warnings(study: PlanarStudy) -> list[str]:
    """The driver ranges where the mechanism does not assemble."""
    ranges = study.unassembled
    if not ranges:
        return []
    n_bad = int(np.sum(~np.asarray(study.kinematics.valid, bool)))
    where = (", ".join(f"positions {a:.0f} to {b:.0f}" for a, b in ranges) if _several(study)
             else format_angle_ranges(ranges, _coord(study)[1]))
    return [f"the mechanism cannot be assembled at {n_bad} of {study.kinematics.n} positions: "
            f"{where}. The animation skips these "
            "positions, the diagrams are empty there, and the extremes are taken over the "
            "assembled positions only."]


def _mm(p: Any) -> str:
    return "({}, {})".format(*(fmt(v * 1e3) for v in p))


def inputs(doc: PlanarFile) -> list[Table]:
    """Bodies, joints, driver, analysis and loads of the file in display units."""
    mech = doc.mechanism()
    bodies = [[b.name, ", ".join(f"{k} {_mm(p)}" for k, p in b.points.items()), fmt(b.mass),
               _mm(b.com), fmt(b.inertia)] for b in (mech.frame, *mech.bodies)]
    out = [Table("bodies (points in the body's own frame)",
                 ["body", "points [mm]", "mass [kg]", "centre of mass [mm]",
                  "inertia [kg·m²]"], bodies)]
    joints = []
    for j in mech.joints:
        extra = []
        if j.has_line:
            extra.append(f"line at {fmt(math.degrees(mech.joint_geometry(j)[2]))} deg in {j.a}")
        for k, u in (("friction", ""), ("radius", "m"), ("length", "m"),
                     ("friction_torque", "N·m")):
            v = getattr(j, k, 0.0)
            if v:
                shown = f"{fmt(v * 1e3)} mm" if u == "m" else f"{fmt(v)} {u}".strip()
                extra.append(f"{k} {shown}")
        joints.append([j.name, type(j).__name__, j.a, j.b, "; ".join(extra)])
    out.append(Table("joints (reaction: force of a on b)", ["joint", "type", "a", "b", "details"],
                     joints))
    a = doc.analysis
    phi = np.asarray(doc.positions(), dtype=float).reshape(-1, a.n)
    tables = doc.driver if isinstance(doc.driver, list) else [doc.driver]
    rows = []
    for row, d in enumerate(tables):
        crank = d.type == "crank"
        unit, f = ("deg", 180 / math.pi) if crank else ("mm", 1e3)
        tag = f" ({d.joint})" if len(tables) > 1 else ""
        rows += [[f"driver{tag}", f"{d.type} on joint {d.joint}"],
                 [f"speed{tag}", f"{fmt(d.omega1)} rad/s ({fmt(d.omega1 * 30 / math.pi)} rpm)"
                  if crank else f"{fmt(d.v1)} m/s"],
                 [f"acceleration{tag}", f"{fmt(d.eps1)} rad/s²" if crank
                  else f"{fmt(d.a1)} m/s²"],
                 [f"range{tag}", f"{fmt(phi[row, 0] * f)} to {fmt(phi[row, -1] * f)} {unit}, "
                                 f"{a.n} positions"]]
    crank = all(d.type == "crank" for d in tables)
    rows += [["branches", ", ".join(f"{k} {v:+d}" for k, v in a.branches.items()) or "+1 (all)"],
            ["gravity", "off" if a.gravity is None else
             "({}, {}) m/s²".format(*(fmt(g) for g in a.gravity))],
            ["shaking moment about", f"{_mm(a.about)} mm"]]
    out.append(Table("drivers and analysis" if len(tables) > 1 else "driver and analysis",
                     ["", "value"], rows))
    plain = [ld for ld in doc.load if ld.type in ("force", "torque") and ld.diagram is None]
    if plain:
        out.append(Table("external loads", ["type", "body", "point", "fx [N]", "fy [N]",
                                            "mz [N·m]", "range", "from frame"],
                         [[ld.type, str(ld.body), _point(ld.point), fmt(ld.fx), fmt(ld.fy),
                           fmt(ld.mz), "all" if ld.phi_range is None else " .. ".join(
                               str(v) for v in ld.phi_range), "yes" if ld.from_frame else "no"]
                          for ld in plain]))
    other = [(i, ld) for i, ld in enumerate(doc.load) if ld not in plain]
    elements = [[sp.name or f"spring.{i}", "spring", _between(sp),
                 f"k {fmt(sp.stiffness * 1e-3)} N/mm, free length {fmt(sp.free_length * 1e3)} "
                 f"mm, preload {fmt(sp.preload)} N"] for i, sp in enumerate(doc.spring)]
    elements += [[dp.name or f"damper.{i}", "damper", _between(dp),
                  f"c {fmt(dp.damping)} N·s/m"] for i, dp in enumerate(doc.damper)]
    elements += [[ld.name or f"load.{i}", ld.type, _on(ld), _value(ld, crank)]
                 for i, ld in other]
    if elements:
        out.append(Table("force elements and load diagrams (springs, dampers: tension +)",
                         ["name", "kind", "on", "value"], elements))
    return out


def _point(p: Any) -> str:
    return p if isinstance(p, str) else _mm(p) + " mm"


def _between(el: Any) -> str:
    return f"{el.a} {_point(el.point_a)} to {el.b} {_point(el.point_b)}"


def _on(ld: Any) -> str:
    if ld.type == "slide":
        return f"the line of {ld.joint} (reaction on its body a)"
    return str(ld.body) + ("" if ld.type == "torque" else f" {_point(ld.point)}")


def _value(ld: Any, crank: bool) -> str:
    """A load of the file in words: a drag's parts, a constant, or its diagram."""
    if ld.type == "drag":
        return (f"{fmt(ld.force)} N + {fmt(ld.damping)} N·s/m × v against the point's velocity"
                + (", from the frame" if ld.from_frame else ""))
    d = ld.diagram
    if d is None:  # a constant slide force
        rng = "" if ld.phi_range is None else " over " + " .. ".join(map(str, ld.phi_range))
        return f"{fmt(ld.force)} N along the line{rng}"
    over = ("the driver" if d.over == "driver" else f"the slide of {d.over}")
    unit = "N·m" if ld.type == "torque" else "N"
    along = f" at {fmt(math.degrees(ld.angle))} deg" if ld.type == "force" else ""
    rows = "; ".join(f"{x}: {y}" for x, y in d.table)
    when = {"always": "always", "increasing": "while it increases",
            "decreasing": "while it decreases"}[d.when]
    return (f"diagram [{unit}]{along} over {over} ({rows}), {when}, outside its range "
            f"{'zero' if d.outside == 'zero' else 'refused'}" + (
                "" if crank or d.over != "driver" else " (slide of the linear driver)"))


def notes(study: PlanarStudy) -> list[tuple[str, str]]:
    """Sign conventions of the planar engine (docs/conventions.md)."""
    mech = study.mechanism
    ab = np.asarray(study.dynamics.about, dtype=float) * 1e3
    coords, loads = [], []
    for d in mech.drivers:
        drv = mech.joint(d.joint)
        turn = d.kind == "crank"
        coords.append(f"{'φ1 = θ_b − θ_a of' if turn else 's1 along'} joint {d.joint} (bodies "
                      f"{drv.a} → {drv.b})")
        loads.append(f"{'torque' if turn else 'force along the guide'} on body {drv.b} of "
                     f"driver joint {d.joint} through body {drv.a}"
                     f"{', counter-clockwise +' if turn else ''}")
    several = len(coords) > 1
    return [
        ("planar engine: frames and angles",
         "Every body has its own frame; angles counter-clockwise from the fixed x axis. "
         f"The driver coordinate{'s' if several else ''} " + "; ".join(coords) + ". "
         + ("The positions are numbered along the drivers' path (each driver moving from its "
            "start to its stop over the [analysis] positions). " if several else "")
         + "Assembly branches per Assur group as listed in the structure table "
           "(docs/conventions.md, planar engine)."),
        ("reactions, driving torque, shaking",
         "Joint reaction = force exerted by the joint's first body a on its second body b, "
         f"frame axes. Q{' of each driver' if several else ''} = " + "; ".join(loads)
         + "; driving power Q·ω1. Shaking force and moment = what the moving bodies exert on "
           "the frame (motor reaction included), moment counter-clockwise + about "
           f"({ab[0]:g}, {ab[1]:g}) mm. Transmission angle μ in [0, 90°], 90° best."),
    ]


RENDERER = Renderer(key="planar", title="kinematics and dynamics", file_type=PlanarFile,
                    run=run, section=section, scene=scene, inputs=inputs, notes=notes,
                    warnings=warnings, primary=True)
