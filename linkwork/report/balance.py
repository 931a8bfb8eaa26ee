"""The report of a ``planar`` file's ``[balance]`` section: paper 001's balancing (what
``linkwork balance`` shows), its diagrams linked to the animated mechanism."""

from __future__ import annotations

import math

import numpy as np

from linkwork.io.planar import PlanarFile
from linkwork.plot.html import Diagram, Section, Table
from linkwork.plot.numbers import fmt, unit_label
from linkwork.report.base import Options, Renderer, diagram, prefixed
from linkwork.studies import balance as study_balance
from linkwork.studies.balance import BalanceStudy

__all__ = ["RENDERER", "section"]


def applies(doc: PlanarFile) -> bool:
    """The file has a ``[balance]`` section."""
    return "balance" in doc.model_fields_set


def run(doc: PlanarFile, options: Options) -> BalanceStudy:
    """:func:`linkwork.studies.balance.run` after its check (a crank about a frame joint)."""
    study_balance.check(doc)
    return study_balance.run(doc)


def section(study: BalanceStudy, options: Options) -> Section:
    """The paper's table, counterweights, moved axis, peaks and RMS, harmonics and the cycle's
    diagrams (moments, hodograph, torque, bearings)."""
    comp = study.comparison
    c = comp.cycle
    phi = np.asarray(c.phi1, dtype=float)
    d = [diagram("shaking moment about the crank axis (paper 001)", phi, "rad", "φ1",
                 [("M unbalanced", c.M), ("ΔM1 static", c.dM1), ("ΔM2 first harmonic", c.dM2),
                  ("ΔM3 least squares", c.dM3)], "M", "N*m"),
         diagram("driving torque before and after balancing", phi, "rad", "φ1",
                 [("unbalanced", c.Q0), ("balanced", c.Q1)], "Q", "N*m")]
    div, lab = prefixed("N", c.F0, c.F1)
    d.append(Diagram(title="shaking force hodograph", x=np.asarray(c.F0[:, 0]) / div,
                     series=[("unbalanced", np.asarray(c.F0[:, 1]) / div)],
                     xlabel=f"Fx [{lab}]", ylabel=f"Fy [{lab}]", positions=phi,
                     parametric=True, equal=True,
                     note="after static balancing the shaking force is "
                          + ("zero" if comp.balance.full else "the residual of the table")))
    for joint in c.reactions0:
        curves = [("unbalanced", c.reactions0[joint]), ("static", c.reactions1[joint]),
                  ("moved axis", c.reactions3[joint])]
        if joint == study.mechanism.driver.joint and "O1" in c.reactions3:
            curves.append(("moved counterweight's bearing O1", c.reactions3["O1"]))
        d.append(diagram(f"frame bearing {joint}: |R| before and after", phi, "rad", "φ1",
                         curves, "|R|", "N"))
    rows = [[fmt(math.degrees(p), decimals=1), fmt(comp.M[i], decimals=3),
             fmt(comp.dM1[i], decimals=3), fmt(comp.dM2[i], decimals=3),
             fmt(comp.dM3[i], decimals=3)] for i, p in enumerate(comp.phi1)]
    rows.append(["R_j [%]", "", "", fmt(comp.R2, decimals=1), fmt(comp.R3, decimals=1)])
    tables = [Table("shaking moment about the crank axis [N·m] (paper 001's table)",
                    ["φ1 [deg]", "M unbalanced", "ΔM1 static", "ΔM2 1st harmonic",
                     "ΔM3 least sq."], rows, positions=[*list(comp.phi1), None])]
    fb = comp.balance
    tables.append(Table(
        f"counterweights (static balancing: {'full' if fb.full else 'partial'}; RMS shaking "
        f"force {fmt(fb.force_rms_before)} N -> {fmt(fb.force_rms_after)} N)",
        ["link", "S [kg·m]", "angle on the link [deg]", "radius [mm]", "mass [kg]"],
        [[cw.link, fmt(cw.static_moment, digits=5), fmt(math.degrees(cw.angle), decimals=2),
          "-" if cw.radius is None else fmt(cw.radius * 1e3),
          "-" if cw.radius is None else fmt(cw.mass())] for cw in comp.counterweights],
        note="" if fb.full else f"not fully balanceable: {fb.reason}"))
    tables.append(Table("moved axis O1 of the crank counterweight (relative to O)",
                        ["method", "x [mm]", "y [mm]"],
                        [["first harmonic", fmt(comp.x2 * 1e3, decimals=2),
                          fmt(comp.y2 * 1e3, decimals=2)],
                         ["least squares over the table", fmt(comp.x3 * 1e3, decimals=2),
                          fmt(comp.y3 * 1e3, decimals=2)]]))
    tables.append(Table("peaks and RMS over the cycle", ["quantity", "values"],
                        [[unit_label(q), ", ".join(f"{k} {fmt(v)}" for k, v in vals.items())]
                         for q, vals in comp.summary().items()]))
    tables.append(Table("harmonic amplitudes (f = a0 + Σ A_j cos(j φ1 − ψ_j))",
                        ["quantity", "mean", *(f"A{j}" for j in range(1, 5))],
                        [[n, fmt(h.mean, decimals=3), *(fmt(a, decimals=3)
                                                        for a in h.amplitude)]
                         for n, h in study.harmonics.items()]))
    notes = [f"balancing raises {m}" for m in study.increases]
    return Section(title="balancing (paper 001)", key="balance",
                   intro=[f"Counterweights on {', '.join(cw.link for cw in comp.counterweights)}"
                          f"; cycle of {phi.size} positions over a full turn of the crank."],
                   diagrams=d, tables=tables, notes=notes)


def notes(study: BalanceStudy) -> list[tuple[str, str]]:
    """Paper 001's conventions and errata that apply."""
    return [("balancing (paper 001): conventions",
             "Shaking force F = −Σ m_i a_Si; shaking moment about the crank axis O, "
             "counter-clockwise +, the motor's reaction included. Counterweight angle α from the "
             "link's x axis (first joint → second), α = 180° on the extension beyond the frame "
             "hinge; S = m r about the frame hinge. R_j = (max|ΔM1| − max|ΔM_j|)/max|ΔM1|. RMS "
             "over one cycle by the periodic trapezoid rule."),
            ("balancing (paper 001): errata that apply",
             "The moved counterweight's moment is M_yp = S[ω²(y cos φ − x sin φ) + ε(x cos φ + "
             "y sin φ)] (the printed formula is damaged); formula (1) for the moved axis is exact "
             "only when Σ sin φ_i cos φ_i = 0 and ε = 0, so linkwork solves the least squares "
             "exactly; R_j as above reproduces the paper's 36.9 % and 53.9 % (the printed "
             "formula does not). See docs/errata.md, paper 001.")]


RENDERER = Renderer(key="balance", title="balancing (paper 001)", file_type=PlanarFile,
                    run=run, section=section, applies=applies, notes=notes)
