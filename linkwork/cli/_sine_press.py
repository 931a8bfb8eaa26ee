"""Analyser of ``sine_press`` files (``linkwork analyze press.toml``), paper 000.

Prints the main quantities of both modes at the chosen crank angles and a summary (strokes,
dead centres, working range), and writes into the output folder:

* ``idle_cycle.csv/.json`` -- the offset crank-slider over one revolution (all result fields);
* ``working_cycle.csv/.json`` -- the inclined-slot sine mechanism over one revolution;
* ``schedule.csv/.json`` -- the duty schedule over time (if the file has one);
* ``summary.json`` -- the scalar characteristics;
* ``kinematics.png`` -- position, velocity, acceleration of the output link vs crank angle,
  both modes; ``schedule.png`` -- the schedule over time with the switches marked;
  ``working_range.png`` -- the friction force ratio against the slot angle.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from rich.markup import escape
from rich.table import Table

from linkwork.cli._format import fmt
from linkwork.cli._tables import print_table
from linkwork.io.sine_press import SinePressFile
from linkwork.models.variable_structure import MODES
from linkwork.results import write_json
from linkwork.studies import sine_press as study_sine_press
from linkwork.studies.sine_press import SinePressStudy

__all__ = ["analyze_sine_press", "render"]


def _f(x: Any, nd: int = 4) -> str:
    """Fixed decimals (:func:`linkwork.cli._format.fmt`)."""
    return fmt(x, decimals=nd)


def analyze_sine_press(doc: SinePressFile, out: Path, angles: np.ndarray, console: Any
                       ) -> SinePressStudy:
    """Analyse a validated ``sine_press`` document; see the module docstring for the outputs."""
    study = study_sine_press.analyze(doc, angles=angles)
    render(study, out=out, console=console)
    return study


def _mode_tables(study: SinePressStudy) -> tuple[Table, Table]:
    doc, cs, sn = study.doc, study.table_idle, study.table_working
    L1, w1, e1 = doc.crank.L1, doc.crank.speed, doc.crank.eps1
    idle, work = doc.idle, doc.working
    head = (f"{doc.name}: L1 = {L1 * 1e3:.4g} mm, n = {w1 * 30 / math.pi:.4g} rpm, "
            f"eps1 = {e1:.4g} rad/s²")
    l2_mm, e_mm = idle.lambda2 * L1 * 1e3, idle.lambda_e * L1 * 1e3
    ti = Table(title=escape(f"{head}\nidle mode: offset crank-slider, L2 = {l2_mm:.4g} mm, "
                            f"e = {e_mm:.4g} mm"))
    for col in ("φ1 [deg]", "Y_C [mm]", "V_C [m/s]", "a_C [m/s²]", "φ2 [deg]", "ω2 [rad/s]",
                "ε2 [rad/s²]", "pressure angle [deg]"):
        ti.add_column(escape(col), justify="right")
    for i, p in enumerate(study.angles):
        ti.add_row(fmt(math.degrees(p)), _f(cs.Y_C[i] * 1e3, 3), _f(cs.V_C[i]),
                   _f(cs.a_C[i], 3), _f(np.degrees(cs.phi2[i]), 3), _f(cs.omega2[i]),
                   _f(cs.eps2[i], 2), _f(np.degrees(cs.pressure_angle[i]), 3))
    tw = Table(title=escape(f"working mode: sine mechanism, slot at alpha = "
                            f"{math.degrees(work.alpha):.4g} deg"))
    for col in ("φ1 [deg]", "X3 [mm]", "V3 [m/s]", "a3 [m/s²]", "X32 [mm]", "V32 [m/s]",
                "a32 [m/s²]"):
        tw.add_column(escape(col), justify="right")
    for i, p in enumerate(study.angles):
        tw.add_row(fmt(math.degrees(p)), _f(sn.X3[i] * 1e3, 3), _f(sn.V3[i]),
                   _f(sn.a3[i], 3), _f(sn.X32[i] * 1e3, 3), _f(sn.V32[i]), _f(sn.a32[i], 3))
    return ti, tw


def _characteristics(study: SinePressStudy) -> Table:
    si, sw = study.summary["idle"], study.summary["working"]
    s = Table(title="Characteristics", show_header=False)
    s.add_column("quantity")
    s.add_column("value", justify="right")

    def add(label: str, value: str) -> None:
        s.add_row(escape(label), value)

    add("idle: rod L2 / offset e [mm]", f"{si['L2_m'] * 1e3:.4g} / {si['e_m'] * 1e3:.4g}")
    add("idle: stroke of slider C [mm]", f"{si['stroke_m'] * 1e3:.4f}")
    add("idle: dead centres φ1 top / bottom [deg]",
        f"{si['phi1_top_dead_centre_deg']:.3f} / {si['phi1_bottom_dead_centre_deg']:.3f}")
    add("idle: max pressure angle [deg]", f"{si['max_pressure_angle_deg']:.3f}")
    add("working: α [deg], stroke of ram [mm]",
        f"{sw['alpha_deg']:.4g}, {sw['stroke_m'] * 1e3:.4f}")
    add("working: extreme positions φ1 (X3 min / max) [deg]",
        f"{sw['phi1_X3_min_deg']:.3f} / {sw['phi1_X3_max_deg']:.3f}")
    add("working: α range free of jamming [deg]",
        f"({sw['working_range_deg'][0]:.3f}, {sw['working_range_deg'][1]:.3f})")
    add("working: worst-case force ratio η", f"{sw['worst_case_force_ratio']:.4f}")
    sched = study.schedule
    if sched is not None:
        add("schedule: duration [s]", f"{sched.t[-1]:.4g}")
        add("schedule: switches [s] (→ mode entered)", ", ".join(
            f"{x:.4g} (→ {MODES[int(m)]})" for x, m in zip(sched.switch_t, sched.switch_to,
                                                            strict=True)))
    return s


def render(study: SinePressStudy, *, out: Path, console: Any) -> None:
    """Print a :class:`~linkwork.studies.sine_press.SinePressStudy` on ``console`` and write
    its cycles, schedule, summary and plots into ``out``."""
    from linkwork.plot import pyplot, save
    from linkwork.plot.sine import plot_cycle, plot_schedule

    for table in _mode_tables(study):
        print_table(console, table)
    work = study.doc.working
    cyc_idle, cyc_work = study.idle_cycle, study.working_cycle
    written = [cyc_idle.to_csv(out / "idle_cycle.csv"), cyc_idle.to_json(out / "idle_cycle.json"),
               cyc_work.to_csv(out / "working_cycle.csv"),
               cyc_work.to_json(out / "working_cycle.json")]
    name = study.doc.name
    written.append(save(plot_cycle(cyc_idle, cyc_work, name=name)[0].figure,
                        out / "kinematics.png"))
    written.append(save(study.force_ratio.plot(work.alpha, name=name).figure,
                        out / "working_range.png"))
    sched = study.schedule
    if sched is not None:
        written += [sched.to_csv(out / "schedule.csv"), sched.to_json(out / "schedule.json")]
        written.append(save(plot_schedule(sched, name=name)[0].figure, out / "schedule.png"))
    written.append(write_json(out / "summary.json", study.summary))
    pyplot().close("all")
    print_table(console, _characteristics(study))
    console.print(escape("written: " + ", ".join(str(p) for p in written)), highlight=False)
