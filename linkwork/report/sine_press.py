"""The report of a ``sine_press`` file (paper 000): both modes at the same crank angle, the
characteristics, the force ratio and the duty schedule (what ``linkwork analyze`` shows)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from linkwork.io.sine_press import SinePressFile
from linkwork.plot.html import Diagram, Section, Table
from linkwork.plot.numbers import fmt
from linkwork.plot.scene import Scene
from linkwork.report.base import Options, Renderer, diagram
from linkwork.studies import sine_press as study_sine_press
from linkwork.studies.sine_press import SinePressStudy

__all__ = ["RENDERER", "section"]


def run(doc: SinePressFile, options: Options) -> SinePressStudy:
    return study_sine_press.analyze(doc)


def scene(study: SinePressStudy, options: Options) -> Scene:
    return study.scene()


def section(study: SinePressStudy, options: Options) -> Section:
    """Output motion of both modes over a revolution, the force ratio over slot angles, the
    schedule; the characteristics and the table at the table angles."""
    idle, work = study.idle_cycle, study.working_cycle
    phi = np.asarray(idle.phi1, dtype=float)
    d = [diagram("output position: slider C (idle, Y_C) and ram (working, X3)", phi, "rad",
                 "φ1", [("idle Y_C", idle.Y_C), ("working X3", work.X3)], "s", "mm",
                 factor=1e3),
         diagram("output velocity", phi, "rad", "φ1",
                 [("idle V_C", idle.V_C), ("working V3", work.V3)], "v", "m/s", factor=1.0),
         diagram("output acceleration", phi, "rad", "φ1",
                 [("idle a_C", idle.a_C), ("working a3", work.a3)], "a", "m/s²", factor=1.0),
         diagram("idle mode: rod angle φ2 and pressure angle μ", phi, "rad", "φ1",
                 [("φ2", idle.phi2), ("μ", idle.pressure_angle)], "angle", "deg",
                 factor=180.0 / math.pi),
         diagram("working mode: block in the slot X32 and its relative velocity", phi, "rad",
                 "φ1", [("X32 [mm]", work.X32 * 1e3), ("V32 [mm/s]", work.V32 * 1e3)],
                 "X32, V32", "mm, mm/s", factor=1.0)]
    fr = study.force_ratio
    d.append(Diagram(title="worst-case force ratio η over the slot angle (friction)",
                     x=np.degrees(fr.slot_angle), series=[("η", fr.eta)],
                     xlabel="slot angle α [deg]", ylabel="η [-]", angle=True,
                     note=f"works for {math.degrees(fr.working[0]):.2f} < α < "
                          f"{math.degrees(fr.working[1]):.2f} deg (f_slot {fr.f_slot:g}, "
                          f"f_guide {fr.f_guide:g}); jams outside"))
    sched = study.schedule
    if sched is not None:
        d.append(Diagram(title="duty schedule: the press ram over time", x=sched.t,
                         series=[("ram position [mm]", sched.ram_s * 1e3),
                                 ("ram velocity [mm/s]", sched.ram_v * 1e3)],
                         xlabel="t [s]", ylabel="ram s [mm], v [mm/s]"))
    s = study.summary
    si, sw = s["idle"], s["working"]
    tables = [
        Table("characteristics", ["quantity", "idle mode", "working mode"], [
            ["stroke [mm]", fmt(si["stroke_m"] * 1e3), fmt(sw["stroke_m"] * 1e3)],
            ["extreme positions at φ1 [deg]",
             f"{fmt(si['phi1_top_dead_centre_deg'], decimals=2)} (top), "
             f"{fmt(si['phi1_bottom_dead_centre_deg'], decimals=2)} (bottom)",
             f"{fmt(sw['phi1_X3_min_deg'], decimals=2)} (X3 min), "
             f"{fmt(sw['phi1_X3_max_deg'], decimals=2)} (X3 max)"],
            ["largest pressure angle [deg]", fmt(si["max_pressure_angle_deg"], decimals=2), ""],
            ["slot angle α [deg]", "", fmt(sw["alpha_deg"], decimals=2)],
            ["working range of α [deg]", "", "{} .. {}".format(
                *(fmt(v, decimals=2) for v in sw["working_range_deg"]))],
            ["worst-case force ratio η", "", fmt(sw["worst_case_force_ratio"])],
        ])]
    tphi = np.asarray(study.angles, dtype=float)
    ti, tw = study.table_idle, study.table_working
    tables.append(Table("both modes at the table angles",
                        ["φ1 [deg]", "Y_C [mm]", "V_C [m/s]", "a_C [m/s²]", "X3 [mm]",
                         "V3 [m/s]", "a3 [m/s²]"],
                        [[fmt(math.degrees(p), decimals=1), fmt(ti.Y_C[i] * 1e3, decimals=3),
                          fmt(ti.V_C[i], decimals=4), fmt(ti.a_C[i], decimals=3),
                          fmt(tw.X3[i] * 1e3, decimals=3), fmt(tw.V3[i], decimals=4),
                          fmt(tw.a3[i], decimals=3)] for i, p in enumerate(tphi)],
                        positions=list(tphi)))
    peak_rows, where = [], []
    for label, arr, unit, f in (("idle |a_C| max", idle.a_C, "m/s²", 1.0),
                                ("working |a3| max", work.a3, "m/s²", 1.0),
                                ("idle |V_C| max", idle.V_C, "m/s", 1.0),
                                ("working |V3| max", work.V3, "m/s", 1.0)):
        i = int(np.nanargmax(np.abs(arr)))
        peak_rows.append([label, fmt(float(arr[i]) * f), unit, fmt(math.degrees(phi[i]),
                                                                  decimals=1)])
        where.append(float(phi[i]))
    tables.append(Table("extremes over a revolution (click a row to show it)",
                        ["quantity", "value", "unit", "φ1 [deg]"], peak_rows, positions=where))
    if sched is not None:
        tables.append(Table("duty schedule: switches", ["t [s]", "φ1 [deg]", "to mode",
                                                        "ram velocity jump [m/s]"],
                            [[fmt(t), fmt(math.degrees(p), decimals=1),
                              "working" if m else "idle", fmt(dv)]
                             for t, p, m, dv in zip(sched.switch_t, sched.switch_phi1,
                                                    sched.switch_to, sched.switch_ram_dv,
                                                    strict=True)]))
    return Section(title="press drive (paper 000)", key="sine_press",
                   intro=[f"Crank L1 = {fmt(study.doc.crank.L1 * 1e3)} mm at "
                          f"{fmt(study.doc.crank.speed * 30 / math.pi)} rpm; idle mode: offset "
                          f"crank-slider, working mode: sine mechanism with the slot at "
                          f"α = {fmt(sw['alpha_deg'])} deg."],
                   diagrams=d, tables=tables)


def inputs(doc: SinePressFile) -> list[Table]:
    c, i, w = doc.crank, doc.idle, doc.working
    rows: list[list[Any]] = [
        ["crank L1", f"{fmt(c.L1 * 1e3)} mm"],
        ["crank speed ω1", f"{fmt(c.speed)} rad/s ({fmt(c.speed * 30 / math.pi)} rpm)"],
        ["crank acceleration ε1", f"{fmt(c.eps1)} rad/s²"],
        ["idle: λ2 (rod L2 = λ2 L1)", f"{fmt(i.lambda2)} ({fmt(i.lambda2 * c.L1 * 1e3)} mm)"],
        ["idle: λe (offset e = λe L1)", f"{fmt(i.lambda_e)} ({fmt(i.lambda_e * c.L1 * 1e3)} mm)"],
        ["idle: branch", f"{i.branch:+d}"],
        ["working: slot angle α", f"{fmt(math.degrees(w.alpha))} deg"],
        ["working: friction f_slot, f_guide", f"{fmt(w.f_slot)}, {fmt(w.f_guide)}"],
        ["samples per revolution", str(doc.output.samples_per_revolution)]]
    out = [Table("press drive", ["", "value"], rows)]
    if doc.schedule:
        out.append(Table("duty schedule", ["segment", "mode", "revolutions", "α"],
                         [[str(k + 1), seg.mode, str(getattr(seg, "revolutions", None)
                                                     or getattr(seg, "strokes", "")),
                           "" if seg.alpha is None else f"{fmt(math.degrees(seg.alpha))} deg"]
                          for k, seg in enumerate(doc.schedule)]))
    return out


def notes(study: SinePressStudy) -> list[tuple[str, str]]:
    return [("press drive (paper 000): conventions",
             "φ1 from the right horizontal position of the crank, counter-clockwise. Idle mode: "
             "the slider C runs on the guide X = e parallel to +Y, Y_C along +Y, branch +1 = the "
             "slider on the +Y side of the crank pin. Working mode: α from the ram's line of "
             "motion to the slot, counter-clockwise; X3 = ram displacement from its φ1 = 0 "
             "position, positive towards the crank axis; X32 along the slot."),
            ("press drive (paper 000): errata that apply",
             "The slider acceleration of Eq. (13) is corrected (three terms of the printed form "
             "are wrong); X3 of Eq. (19) is wrong for α ≠ 90° (linkwork: X3 = L1(1 − cos φ1 + "
             "sin φ1/tan α)); the sign of a32 in Eqs. (18), (21) is corrected. See "
             "docs/errata.md, paper 000.")]


RENDERER = Renderer(key="sine_press", title="press drive (paper 000)", file_type=SinePressFile,
                    run=run, section=section, scene=scene, inputs=inputs, notes=notes,
                    primary=True)
