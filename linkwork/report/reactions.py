"""The report of a ``planar`` file's ``[spatial]`` section: spatial joint reactions with
redundant constraints (paper 004; what ``linkwork reactions`` shows)."""

from __future__ import annotations

import numpy as np

from linkwork.io.planar import PlanarFile
from linkwork.plot.html import Section, Table
from linkwork.plot.numbers import fmt, scale_of
from linkwork.report.base import Options, Renderer, diagram, driver_display
from linkwork.studies import reactions as study_reactions
from linkwork.studies.reactions import ReactionsStudy

__all__ = ["RENDERER", "section"]


def applies(doc: PlanarFile) -> bool:
    """The file has a ``[spatial]`` section."""
    return "spatial" in doc.model_fields_set


def run(doc: PlanarFile, options: Options) -> ReactionsStudy:
    """:func:`linkwork.studies.reactions.run` (its positions checked as the command does)."""
    doc.check_spatial_positions(options.file)
    return study_reactions.run(doc)


def section(study: ReactionsStudy, options: Options) -> Section:
    """The count of redundant constraints, axial forces, bending moments and the driving
    torque over the cycle, and the peaks per joint."""
    r, count = study.reactions, study.count
    unit = "m" if study.linear else "rad"
    name = "s1" if study.linear else "φ1"
    phi = np.asarray(study.cycle, dtype=float)
    bend = r.bending()
    d = [diagram("axial forces fz (out of the plane)", phi, unit, name,
                 [(j, r.fz[k]) for k, j in enumerate(r.joints)], "fz", "N"),
         diagram("bending moments √(mx² + my²) of the joints", phi, unit, name,
                 [(j, bend[k]) for k, j in enumerate(r.joints)], "M_b", "N*m"),
         diagram("in-plane reactions √(fx² + fy²)", phi, unit, name,
                 [(j, np.hypot(r.fx[k], r.fy[k])) for k, j in enumerate(r.joints)], "|R|",
                 "N"),
         diagram("driving torque Q" if not study.linear else "driving force Q", phi, unit,
                 name, [("Q", r.Q)], "Q", "N" if study.linear else "N*m")]
    peaks = study.peaks
    sn = scale_of(*(v for k, row in peaks.items() if k != "driver" for c, v in row.items()
                    if c.startswith("f")))
    rows = [[j, *(fmt(row[c], sn) for c in ("fx", "fy", "fz")),
             *(fmt(row[c]) for c in ("mx", "my", "mz", "bending"))]
            for j, row in peaks.items() if j != "driver"]
    du, f, _ = driver_display(unit)
    tab = study.table
    trows = [[fmt(p * f, decimals=1), *(fmt(tab.fz[k][i], sn) for k in range(len(tab.joints))),
              *(fmt(tab.bending()[k][i]) for k in range(len(tab.joints)))]
             for i, p in enumerate(study.table_positions)]
    tables = [
        Table("peaks over the cycle (|value|)", ["joint", "fx [N]", "fy [N]", "fz [N]",
                                                 "mx [N·m]", "my [N·m]", "mz [N·m]",
                                                 "bending [N·m]"], rows),
        Table("axial forces and bending moments at the table positions",
              [f"{name} [{du}]", *(f"fz {j} [N]" for j in tab.joints),
               *(f"M_b {j} [N·m]" for j in tab.joints)], trows,
              positions=list(study.table_positions)),
    ]
    intro = [f"Somov-Malyshev mobility {count.mobility_formula}, true mobility "
             f"{count.mobility}: {count.redundant} redundant constraint"
             f"{'' if count.redundant == 1 else 's'}; reactions by the {study.method} method "
             f"over {phi.size} positions."]
    return Section(title="spatial reactions (paper 004)", key="reactions", intro=intro,
                   diagrams=d, tables=tables)


def notes(study: ReactionsStudy) -> list[tuple[str, str]]:
    """Conventions of the spatial reactions and paper 004's errata that apply."""
    return [("spatial reactions: conventions",
             "z = x × y out of the plane of motion; joint heights z from the plane z = 0. "
             "Reaction of joint J(a, b) = wrench exerted by a on b, reduced to the joint centre, "
             "global components fx, fy, fz, mx, my, mz; Q is also contained in mz of the driver "
             "joint. First-order theory: equilibrium on the nominal geometry, joints as linear "
             "springs in their constrained directions."),
            ("spatial reactions (paper 004): errata that apply",
             "The printed loop closure (1) lacks the rotational closure (axis tilts stress the "
             "loop) and its z row is damaged; rows (3a), (3b), (7b) of the moment equations have "
             "wrong terms; linkwork solves all self-stress states together. See "
             "docs/errata.md, paper 004.")]


RENDERER = Renderer(key="reactions", title="spatial reactions (paper 004)",
                    file_type=PlanarFile, run=run, section=section, applies=applies,
                    notes=notes)
