"""The report of a file's ``[drive]`` table: machine dynamics (what ``linkwork dynamics``
shows), and the mechanism animated at its real speed.

It renders :class:`~linkwork.studies.dynamics.DynamicsStudy` (a ``planar`` file with a
``[drive]`` table, a ``sine_press`` file with ``[drive]`` and ``[press]``): the crank's real
speed over the turn for every motor, the motors' torque against their limits, the driving
torque of the real motion against the constant-speed assumption, the reduced inertia and
moments, Wittenbauer's energy-mass diagram with its tangents (when a flywheel is sized), the
start from rest and the duty schedule over time; the tables of the motors with their verdict
lines, the flywheel sizing by the three methods, the real against the constant speed, the
energy per revolution and the schedule revolution by revolution. Nothing is computed again:
every number is the study's.

The page's drawing (:mod:`linkwork.report.planar` or :mod:`linkwork.report.sine_press`) gets
each motor's steady state as a real motion (:meth:`linkwork.plot.scene.Scene.timed`): in
"real time" the animation runs through the turn at the crank's real, non-uniform speed.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from linkwork.io.planar import PlanarFile
from linkwork.io.sine_press import SinePressFile
from linkwork.plot.html import Diagram, RefLine, Section, Table
from linkwork.plot.numbers import fmt, scale_of, unit_label
from linkwork.plot.scene import Scene
from linkwork.report.base import Options, Renderer, diagram, prefixed
from linkwork.studies import dynamics as study_dynamics
from linkwork.studies.dynamics import DynamicsStudy

__all__ = ["RENDERER", "diagrams", "inputs", "section", "tables", "timing"]

RPM = 30.0 / math.pi
TWO_PI = 2.0 * math.pi


def applies(doc: PlanarFile | SinePressFile) -> bool:
    """The file has a ``[drive]`` table (a sine press also a ``[press]`` table)."""
    if doc.drive is None:
        return False
    return not isinstance(doc, SinePressFile) or doc.press is not None


def run(doc: PlanarFile | SinePressFile, options: Options) -> DynamicsStudy:
    """:func:`linkwork.studies.dynamics.run`."""
    return study_dynamics.run(doc)


def _steadies(study: DynamicsStudy) -> list[tuple[str, Any]]:
    """(motor name, steady state) of every motor that runs the machine."""
    return [(c.motor.name, c.steady) for c in study.choices if c.steady is not None]


def _closed(ss: Any, values: Any) -> tuple[np.ndarray, np.ndarray]:
    """Crank angles [rad] and values over the whole turn, the first repeated at its end."""
    phi = np.asarray(ss.phi1, dtype=float)
    v = np.asarray(values, dtype=float)
    return np.append(phi, phi[0] + TWO_PI), np.append(v, v[0])


def timing(study: DynamicsStudy, scene: Scene) -> Scene:
    """The page's drawing with every motor's real motion (its steady state) to play it at."""
    if scene.unit != "rad":
        return scene
    for name, ss in _steadies(study):
        label = (f"{name}, mean {fmt(ss.omega_mean * RPM)} rpm, δ = {fmt(ss.delta, digits=3)}")
        scene = scene.timed(label, ss.phi1, ss.t, ss.omega, ss.period)
    return scene


def _flat(name: str, x: np.ndarray, value: float, colour: int = -1, dotted: bool = False
          ) -> RefLine:
    """A horizontal reference line over the abscissas ``x``."""
    return RefLine(name, np.array([float(np.nanmin(x)), float(np.nanmax(x))]),
                   np.array([value, value]), colour, dotted)


def diagrams(study: DynamicsStudy) -> list[Diagram]:
    """Speed, motor torque, driving torque real against constant speed, the reduction, the
    energy-mass diagram, the start-up and the schedule."""
    out: list[Diagram] = []
    runs = _steadies(study)
    if runs:
        ss0 = runs[0][1]
        phi, _ = _closed(ss0, ss0.omega)
        x = np.degrees(phi)
        out.append(Diagram(
            title="crank speed ω over the turn in the steady state (real motion)",
            x=x, series=[(f"{n} (δ = {fmt(ss.delta, digits=3)})", _closed(ss, ss.omega)[1] * RPM)
                         for n, ss in runs], xlabel="φ1 [deg]", ylabel="ω [rpm]",
            positions=phi, angle=True,
            lines=[_flat(f"{n}: mean {fmt(ss.omega_mean * RPM)} rpm", x, ss.omega_mean * RPM,
                         k) for k, (n, ss) in enumerate(runs)],
            note="mean = 2π / period (the time mean); δ = (ω_max − ω_min) / ω_mean"))
        limits = []
        running = [c for c in study.choices if c.steady is not None]
        for k, c in enumerate(running):
            if c.limit is not None:
                limits.append(_flat(f"{c.motor.name}: {c.limit_name} {fmt(c.limit)} N·m", x,
                                    c.limit, k))
            rated = getattr(c.motor, "rated_torque", None)
            if rated:
                limits.append(_flat(f"{c.motor.name}: rated {fmt(rated)} N·m", x, rated, k,
                                    dotted=True))
        out.append(Diagram(
            title="motor torque at its shaft against its limits",
            x=x, series=[(n, _closed(ss, ss.torque)[1]) for n, ss in runs], xlabel="φ1 [deg]",
            ylabel="motor torque [N·m]", positions=phi, angle=True, lines=limits,
            note="dashed: the largest torque at a stable speed (breakdown, stall or peak "
                 "torque); dotted: the rated torque (RMS, the thermal check, in the motors "
                 "table)"))
        if ss0.dynamics_constant is not None:
            q = _closed(ss0, ss0.Q)[1]
            qc = _closed(ss0, ss0.dynamics_constant.Q)[1]
            div, lab = prefixed("N*m", q, qc)
            out.append(Diagram(
                title=f"torque on the crank: real motion ({runs[0][0]}) and constant speed",
                x=x, series=[("real motion", q / div),
                             (f"constant {fmt(ss0.omega_mean * RPM)} rpm", qc / div)],
                xlabel="φ1 [deg]", ylabel=f"Q [{lab}]", positions=phi, angle=True))
        out.append(diagram("the mechanism reduced to the crank: moment of inertia J(φ1)",
                           phi, "rad", "φ1", [("J (links)", _closed(ss0, ss0.J)[1])], "J",
                           "kg·m²", factor=1.0,
                           note=f"the rotors and flywheel add {fmt(ss0.J_rotors)} kg·m² "
                                "(reduced to the crank)"))
        moments = [("loads", ss0.M_loads), ("gravity", ss0.M_gravity),
                   ("friction", ss0.M_friction), ("dampers, drags", ss0.M_damping)]
        shown = [(n, _closed(ss0, v)[1]) for n, v in moments if np.any(np.asarray(v) != 0)]
        if shown:
            out.append(diagram("reduced moments of the loads on the crank (positive: driving)",
                               phi, "rad", "φ1", shown, "M", "N*m"))
    if study.sizing is not None:
        out += _energy_mass(study)
    start = study.choices[0].start
    if start is not None:
        out += _transient(start.run, "start from rest", study,
                          marks=[(start.t_steady, "steady"),
                                 (start.t_mean_speed, "mean speed")],
                          band=(start.steady.omega_mean, start.band))
    if study.schedule is not None:
        out += _transient(study.schedule, "duty schedule", study)
    return out


def _energy_mass(study: DynamicsStudy) -> list[Diagram]:
    """Wittenbauer's diagram: ΔE against J over the turn, the tangents of slopes ω_max²/2 and
    ω_min²/2 meeting at J = −J_F; magnified where the curve is a sliver beside J_F."""
    s = study.sizing
    assert s is not None
    w = s.wittenbauer
    J = np.asarray(w["J"], dtype=float)
    dE = np.asarray(w["dE"], dtype=float)
    phi = np.asarray(s.steady.phi1, dtype=float)
    if phi.shape != J.shape:  # the diagram's nodes are the steady state's positions
        phi = np.asarray(study.machine.grid.nodes[:-1], dtype=float)
    div, lab = prefixed("J", dE)
    fw = float(w["flywheel"])

    def tangents(xs: np.ndarray) -> list[RefLine]:
        return [RefLine(f"tangent of slope {what}", xs, (w[k] * xs + w[b]) / div)
                for what, k, b in (("ω_max²/2", "k_max", "b_max"),
                                   ("ω_min²/2", "k_min", "b_min"))]

    loop_x, loop_y = np.append(J, J[0]), np.append(dE, dE[0]) / div
    loop_p = np.append(phi, phi[0] + TWO_PI)
    full = Diagram(
        title=f"energy-mass diagram (Wittenbauer), δ = {fmt(s.delta, digits=3)}",
        x=loop_x, series=[("ΔE(J) over the turn", loop_y)],
        xlabel="reduced moment of inertia J [kg·m²] (links and rotors; flywheel to the left)",
        ylabel=f"ΔE [{lab}]", positions=loop_p, parametric=True,
        lines=tangents(np.array([-fw, float(J.max())])),
        points=[(f"flywheel {fmt(fw)} kg·m² (the tangents meet at J = −J_F)",
                 np.array([-fw]), np.array([(w["k_max"] * -fw + w["b_max"]) / div]))],
        note=f"the classical flywheel: {fmt(fw)} kg·m²; exact (periodic solve with the motor's "
             f"characteristic): {fmt(s.flywheel)} kg·m²")
    out = [full]
    span = float(J.max() - J.min())
    if fw > 5 * span and span > 0:
        xs = np.array([J.min() - 0.1 * span, J.max() + 0.1 * span])
        out.append(Diagram(
            title="energy-mass diagram: the curve and the tangents, magnified",
            x=loop_x, series=[("ΔE(J) over the turn", loop_y)],
            xlabel="reduced moment of inertia J [kg·m²]", ylabel=f"ΔE [{lab}]",
            positions=loop_p, parametric=True, lines=tangents(xs)))
    return out


def _transient(run: Any, what: str, study: DynamicsStudy, *,
               marks: list[tuple[float, str]] | None = None,
               band: tuple[float, float] | None = None) -> list[Diagram]:
    """Crank speed and motor torque over time, the switches of a schedule marked."""
    t = np.asarray(run.t, dtype=float)
    events = list(marks or [])
    events += [(float(ts), run.modes[int(to)]) for ts, to in zip(run.switch_t, run.switch_to,
                                                                  strict=True)]
    lines = []
    if band is not None:
        mean, b = band
        lines = [_flat(f"steady mean speed ± {fmt(100 * b)} %", t, mean * (1 + b) * RPM, 1),
                 _flat("", t, mean * (1 - b) * RPM, 1)]
    motor = study.choices[0]
    limit = ([_flat(f"{motor.limit_name} {fmt(motor.limit)} N·m", t, motor.limit, 1)]
             if motor.limit is not None else [])
    name = motor.motor.name
    return [Diagram(title=f"{what} with {name}: crank speed over time", x=t,
                    series=[("ω", np.asarray(run.omega) * RPM)], xlabel="t [s]",
                    ylabel="ω [rpm]", lines=lines, marks=events),
            Diagram(title=f"{what} with {name}: motor torque over time", x=t,
                    series=[("motor torque", np.asarray(run.torque))], xlabel="t [s]",
                    ylabel="torque [N·m]", lines=limit, marks=events)]


def tables(study: DynamicsStudy) -> list[Table]:
    """Motors with their verdicts, the flywheel sizing, real against constant speed, the
    energy per revolution, the schedule."""
    out: list[Table] = []
    rows, where = [], []
    for c in study.choices:
        ss = c.steady
        rows.append([c.motor.name, "-" if ss is None else fmt(ss.omega_mean * RPM),
                     "-" if ss is None else fmt(ss.delta, digits=3),
                     fmt(c.power_mean / 1e3), fmt(c.torque_rms), fmt(c.torque_peak),
                     "-" if not math.isfinite(c.phi_torque_peak) else
                     fmt(math.degrees(c.phi_torque_peak) % 360, decimals=0),
                     "-" if c.limit is None else fmt(c.limit),
                     "-" if c.start is None else fmt(c.start.t_steady, digits=3),
                     "OK" if c.ok else "no"])
        where.append(c.phi_torque_peak if math.isfinite(c.phi_torque_peak) else None)
    out.append(Table("motors: steady state over a revolution, start from rest (click a row: "
                     "where its torque peaks)",
                     ["motor", "mean speed [rpm]", "δ", "mean power [kW]", "RMS torque [N·m]",
                      "peak torque [N·m]", "at φ1 [deg]", "limit [N·m]", "start-up [s]", "OK"],
                     rows, positions=where))
    s = study.sizing
    if s is not None:
        out.append(Table(
            f"flywheel on the crank shaft for δ = {fmt(s.delta, digits=3)} (without one: "
            f"δ = {fmt(s.delta_without, digits=4)})",
            ["method", "flywheel [kg·m²]", "deviation from exact [%]"],
            [["exact (periodic solve)", fmt(s.flywheel), ""],
             ["energy method, constant inertia", fmt(s.energy_method),
              "-" if s.deviation_energy is None else fmt(100 * s.deviation_energy, decimals=2)],
             ["Wittenbauer's energy-mass diagram", fmt(s.wittenbauer_flywheel),
              "-" if s.deviation_wittenbauer is None else
              fmt(100 * s.deviation_wittenbauer, decimals=2)]],
            note=f"the classical methods take the mean speed "
                 f"{fmt(s.omega_nominal * RPM)} rpm and a constant driving torque; the exact "
                 f"flywheel reaches δ = {fmt(s.steady.delta, digits=6)} with "
                 f"{study.choices[0].motor.name}'s characteristic "
                 f"({s.iterations} periodic solves)"))
    ss = study.steady
    if ss is not None:
        rows_c = ss.comparison()
        scales = {u: scale_of([r["real"] for r in rows_c if r["unit"] == u]
                              + [r["constant"] for r in rows_c if r["unit"] == u])
                  for u in ("N", "N*m")}
        if rows_c:
            out.append(Table(
                f"{study.choices[0].motor.name}: the real motion against the constant mean "
                f"speed {fmt(ss.omega_mean * RPM)} rpm (peaks over the turn)",
                ["quantity", "real", "constant speed", "real / constant"],
                [[f"{r['name']} [{unit_label(r['unit'])}]", fmt(r["real"], scales[r["unit"]]),
                  fmt(r["constant"], scales[r["unit"]]),
                  "-" if r["ratio"] is None else fmt(r["ratio"], decimals=3)] for r in rows_c]))
        e = ss.energy
        top = abs(e.get("motor", 0.0))
        out.append(Table(
            "energy per revolution (steady state)", ["", "work [J]"],
            [["motor", fmt(e["motor"])], ["external loads, dampers, drags", fmt(e["loads"], top)],
             ["joint friction", fmt(e["friction"], top)], ["gear losses", fmt(e["gear"], top)],
             ["gravity", fmt(e["gravity"], top)],
             ["balance (the solve's energy error)", fmt(e["residual"], top)]],
            note=f"error estimate of the solve: {ss.error_estimate:.1g} of the mean speed"))
    run = study.schedule
    if run is not None:
        r = run.revolutions()
        out.append(Table(
            f"schedule with {study.choices[0].motor.name}, revolution by revolution",
            ["rev", "mode", "t [s]", "ω start [rpm]", "ω min [rpm]", "drop [%]",
             "work on loads [J]", "motor work [J]"],
            [[str(k + 1), run.modes[int(r["mode"][k])], fmt(r["t"][k], digits=4),
              fmt(r["omega_start"][k] * RPM), fmt(r["omega_min"][k] * RPM),
              fmt(100 * r["drop"][k], decimals=2),
              fmt(r["work_loads"][k], scale_of(r["work_motor"])), fmt(r["work_motor"][k])]
             for k in range(r["t"].size)]))
        out.append(Table(
            "switches of the schedule", ["t [s]", "to", "ω before [rpm]", "ω after [rpm]",
                                         "energy lost [J]", "back within 1 % of its mean"],
            [[fmt(run.switch_t[k], digits=4), rec["to"],
              fmt(run.switch_omega_before[k] * RPM), fmt(run.switch_omega_after[k] * RPM),
              fmt(run.switch_energy_loss[k]),
              "not within the segment" if rec["time"] is None else
              f"{rec['revolutions']} rev, {fmt(rec['time'], digits=3)} s"]
             for k, rec in enumerate(run.recovery())]))
    return out


def section(study: DynamicsStudy, options: Options) -> Section:
    """Diagrams, tables and verdict lines of the machine dynamics."""
    m = study.machine
    d = m.drive
    intro = [f"Gear i = {fmt(d.ratio)}, efficiency {fmt(d.eta)}; flywheel "
             f"{fmt(study.flywheel)} kg·m² on the crank shaft"
             f"{' (sized for δ)' if study.sizing is not None else ''}; {m.grid.n} positions a "
             f"revolution. The flywheel is sized with, and the transients run with, the first "
             f"motor ({study.choices[0].motor.name}). In “real time” the animation runs at a "
             "motor's real, non-uniform crank speed."]
    if study.kind == "sine_press":
        intro.append("The working structure at the file's slot angle, continuous working "
                     "strokes (the case the motor and the flywheel are chosen for); the duty "
                     "schedule switches between the modes.")
    return Section(title="machine dynamics: motor, flywheel, real motion", key="dynamics",
                   intro=intro, diagrams=diagrams(study), tables=tables(study),
                   verdicts=[(c.ok, f"{c.motor.name}: {c.verdict}") for c in study.choices],
                   notes=[f"note: {n}" for n in study.notes])


def inputs(doc: PlanarFile | SinePressFile) -> list[Table]:
    """The ``[drive]`` table (and a sine press's ``[press]`` table) with units."""
    drive = doc.drive
    assert drive is not None
    gear = drive.build_gear()
    rows = [["gear", f"i = {fmt(gear.ratio)}, efficiency {fmt(gear.efficiency)}, inertia "
                     f"{fmt(gear.inertia)} kg·m² at the motor shaft"],
            ["flywheel", f"{fmt(drive.flywheel)} kg·m²" if drive.flywheel is not None else
             f"sized for δ = {fmt(drive.delta)} (at most {fmt(drive.max_flywheel)} kg·m²)"
             if drive.delta is not None else "none"],
            ["positions a revolution", str(drive.positions)],
            ["start from rest", f"yes, steady within {fmt(100 * drive.band)} % of the mean "
                                "speed" if drive.start_up else "no"]]
    if drive.schedule:
        rows.append(["schedule", ", ".join(f"{s.revolutions} rev × loads {fmt(s.load)}"
                                           for s in drive.schedule)])
    out = [Table("drive ([drive])", ["", "value"], rows),
           Table("motors ([[drive.motor]]; the first sizes the flywheel and runs the "
                 "transients)", ["motor"],
                 [[m.describe()] for m in drive.motors()])]
    if isinstance(doc, SinePressFile) and doc.press is not None:
        p = doc.press
        out.append(Table("press masses and force ([press])", ["", "value"], [
            ["crank", f"{fmt(p.crank_mass)} kg, {fmt(p.crank_inertia)} kg·m², centre "
                      f"{fmt(p.crank_com * 1e3)} mm from the axis"],
            ["rod", f"{fmt(p.rod_mass)} kg" + ("" if p.rod_inertia is None else
                                              f", {fmt(p.rod_inertia)} kg·m²")],
            ["slider, ram, block", f"{fmt(p.slider_mass)} kg, {fmt(p.ram_mass)} kg, "
                                   f"{fmt(p.block_mass)} kg"],
            ["press force", f"{fmt(p.press_force / 1e3)} kN over the last "
                            f"{fmt(p.working_stroke * 1e3)} mm of the descent"],
            ["gravity", "off" if p.gravity is None else
             "({}, {}) m/s²".format(*(fmt(g) for g in p.gravity))]]))
    return out


def notes(study: DynamicsStudy) -> list[tuple[str, str]]:
    """The conventions of machine dynamics (docs/machine.md)."""
    return [("machine dynamics: conventions",
             "ω: the crank's speed [rpm], positive in the direction of φ1; the mean speed is the "
             "time mean 2π/T; δ = (ω_max − ω_min)/ω_mean. Motor torque at the motor shaft, "
             "positive driving; the gear's efficiency acts against the power's direction. "
             "Reduced moments on the crank, positive driving. The flywheel sits on the crank "
             "shaft. Wittenbauer's diagram takes a constant driving torque and the mean speed "
             "(ω_max + ω_min)/2, the energy method also a constant inertia; the exact flywheel "
             "comes from the periodic solve with the motor's characteristic (docs/machine.md).")]


RENDERER = Renderer(key="dynamics", title="machine dynamics", file_type=(PlanarFile,
                                                                         SinePressFile),
                    run=run, section=section, applies=applies, inputs=inputs, notes=notes,
                    timing=timing)
