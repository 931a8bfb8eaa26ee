"""The report of a ``swashplate`` file (paper 003): the drive in two views, its
characteristics and the checks against the file's limits, the drive forces."""

from __future__ import annotations

import math

import numpy as np

from linkwork.io.swashplate import SwashplateFile
from linkwork.plot.html import Section, Table
from linkwork.plot.numbers import fmt
from linkwork.plot.scene import Scene
from linkwork.report.base import Options, Renderer, diagram
from linkwork.studies import swashplate as study_swashplate
from linkwork.studies.swashplate import SwashplateStudy

__all__ = ["RENDERER", "section"]


def run(doc: SwashplateFile, options: Options) -> SwashplateStudy:
    return study_swashplate.analyze(doc)


def scene(study: SwashplateStudy, options: Options) -> Scene:
    """The drawing: the slide and disk points of the model at the cycle's angles (the same
    function the plots and checks use; the slide's height is the cycle's ``s``)."""
    return study.scene()


def section(study: SwashplateStudy, options: Options) -> Section:
    cyc = study.cycle
    phi = np.asarray(cyc.phi, dtype=float)
    d = [diagram("slide position s", phi, "rad", "φ", [("s", cyc.s)], "s", "mm", factor=1e3),
         diagram("pressure angle δz", phi, "rad", "φ", [("δz", cyc.delta_z)], "δz", "deg",
                 factor=180.0 / math.pi),
         diagram("transfer functions Πv = ds/dφ, Πa = d²s/dφ²", phi, "rad", "φ",
                 [("Πv [mm/rad]", cyc.Pi_v * 1e3), ("Πa [mm/rad²]", cyc.Pi_a * 1e3)],
                 "Π", "mm/rad, mm/rad²", factor=1.0)]
    if study.omega > 0:
        d.append(diagram("slide velocity and acceleration", phi, "rad", "φ",
                         [("v [m/s]", cyc.v), ("a [m/s²]", cyc.acc)], "v, a",
                         "m/s, m/s²", factor=1.0))
    f = study.forces
    if f is not None:
        d.append(diagram("forces on one slide", np.asarray(f.phi), "rad", "φ",
                         [("technological force F", f.F), ("rod force S", f.S)], "F, S", "N"))
        d.append(diagram("drive torque", np.asarray(f.phi), "rad", "φ",
                         [("one slide", f.M), (f"all {f.u} slides", f.M_total)], "M", "N*m"))
    c = study.characteristics
    deg = math.degrees
    rows = [["stroke H", fmt(float(c.H) * 1e3), "mm", ""],
            ["s min", fmt(float(c.s_min) * 1e3), "mm", fmt(deg(float(c.phi_min)), decimals=1)],
            ["s max", fmt(float(c.s_max) * 1e3), "mm", fmt(deg(float(c.phi_max)), decimals=1)],
            ["forward / return stroke angles φf, φr",
             f"{fmt(deg(float(c.phi_f)), decimals=1)} / {fmt(deg(float(c.phi_r)), decimals=1)}",
             "deg", ""],
            ["largest pressure angle forward / return",
             f"{fmt(deg(float(c.delta_f)), decimals=2)} / {fmt(deg(float(c.delta_r)), decimals=2)}",
             "deg", ""],
            ["largest |Πv|", fmt(float(c.Pi_v_max) * 1e3), "mm/rad",
             fmt(deg(float(c.phi_Pi_v_max)), decimals=1)],
            ["axial size L (Eq. 13) / exact", f"{fmt(float(c.L) * 1e3)} / "
                                              f"{fmt(float(c.L_exact) * 1e3)}", "mm", ""],
            ["harmonic form error max / RMS", f"{fmt(study.harmonic_error['max'] * 1e3)} / "
                                              f"{fmt(study.harmonic_error['rms'] * 1e3)}", "mm",
             ""]]
    where: list[float | None] = [None, float(c.phi_min), float(c.phi_max), None, None,
                                 float(c.phi_Pi_v_max), None, None]
    s = study.summary
    if "v_max" in s:
        rows.append(["largest slide speed", fmt(s["v_max"]), "m/s", ""])
        where.append(None)
    for key, what in (("v_allow_met", "allowed slide speed met"),
                      ("delta_allow_met", "allowed pressure angle met")):
        if key in s:
            rows.append([what, "yes" if s[key] else "NO", "", ""])
            where.append(None)
    if f is not None:
        rows += [["efficiency over a cycle", fmt(f.efficiency, decimals=3), "", ""],
                 ["peak drive torque (all slides)", fmt(s["peak_torque_total"]), "N·m", ""],
                 ["peak rod force", fmt(s["peak_rod_force"]), "N", ""]]
        where += [None, None, None]
    tables = [Table("characteristics (click a row with an angle to show it)",
                    ["quantity", "value", "unit", "φ [deg]"], rows, positions=where)]
    t = study.table
    tables.append(Table("at the table angles", ["φ [deg]", "s [mm]", "δz [deg]", "Πv [mm/rad]"],
                        [[fmt(deg(p), decimals=1), fmt(t.s[i] * 1e3, decimals=3),
                          fmt(deg(t.delta_z[i]), decimals=3), fmt(t.Pi_v[i] * 1e3, decimals=3)]
                         for i, p in enumerate(study.angles)], positions=list(study.angles)))
    dz = study.design
    return Section(title="swash-plate drive (paper 003)", key="swashplate",
                   intro=[f"Scheme {dz.scheme}: R = {fmt(dz.R * 1e3)} mm, r = "
                          f"{fmt(dz.r * 1e3)} mm, l = {fmt(dz.l * 1e3)} mm, α = "
                          f"{fmt(deg(dz.alpha))} deg, a = {fmt(dz.a * 1e3)} mm, b = "
                          f"{fmt(dz.b * 1e3)} mm."], diagrams=d, tables=tables)


def inputs(doc: SwashplateFile) -> list[Table]:
    d = doc.design()
    rows = [[k, f"{fmt(v * 1e3)} mm" if k in ("R", "r", "l", "a", "b") else
             f"{fmt(math.degrees(v))} deg"] for k, v in d.as_dict().items() if k != "scheme"]
    rows.insert(0, ["scheme", d.scheme])
    op = doc.operation
    rows.append(["rotor speed", f"{fmt(op.omega)} rad/s ({fmt(op.omega * 30 / math.pi)} rpm)"])
    return [Table("drive", ["", "value"], rows)]


def notes(study: SwashplateStudy) -> list[tuple[str, str]]:
    return [("swash-plate drive (paper 003): conventions",
             "Frame x0 y0 z0: z0 along the rotor axis from the disk towards the slides; rotor "
             "angle φ from −y0, counter-clockwise seen from +z0; s(0) = 0; δz in [0, 90°] "
             "between the rod and the rotor axis; forward stroke = s increasing."),
            ("swash-plate drive (paper 003): errata that apply",
             "Eq. (6) has the factor 1/4 (not 4) on A3; the first term of Eq. (10) is "
             "r sin α sin φ; Eq. (10) is 0/0 where δz = 0 and linkwork uses a form finite "
             "there; the stroke is taken from the true extremes; the offset c depends on α. "
             "See docs/errata.md, paper 003.")]


RENDERER = Renderer(key="swashplate", title="swash-plate drive (paper 003)",
                    file_type=SwashplateFile, run=run, section=section, scene=scene,
                    inputs=inputs, notes=notes, primary=True)
