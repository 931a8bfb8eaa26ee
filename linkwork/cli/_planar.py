"""``linkwork analyze`` for ``type = "planar"`` files: the general engine over a cycle.

Prints the structure (mobility, Assur groups), dead centres, and a table at the requested crank
angles: driving torque, every joint reaction's magnitude, shaking force and moment,
transmission angles (the kinetic energy is in the CSV/JSON), and the extremes over the cycle
(largest and smallest driving torque, peak reactions, shaking) with where they occur. Writes
``planar_kinematics.csv`` (every body's and named point's motion), ``planar_dynamics.csv``
(every joint's reaction components, driving torque, shaking force and moment, kinetic
energy), ``planar.json`` (both, with units and the structure) and plots (skeleton with point
paths, guides and slots, driving torque, reactions, shaking). With force elements or load
diagrams also their ranges, work and diagrams' ranges (a table), their columns and
``planar_loads.png``.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rich.markup import escape
from rich.table import Table

from linkwork.cli._console import console as make_console
from linkwork.cli._console import counting, steps
from linkwork.cli._format import fmt, scale_of, unit_label
from linkwork.cli._tables import print_table
from linkwork.io.planar import MAX_WHOLE_POSITIONS, PlanarFile
from linkwork.results import CsvRows, csv_rows, write_csv, write_json
from linkwork.studies import planar as study_planar
from linkwork.studies.planar import (
    PLOT_POSITIONS,
    PlanarStudy,
    PlanarSummary,
    cycle_peaks,
    dead_centre_label,
    named_columns,
    table_positions_error,
)

__all__ = ["analyze_long", "analyze_planar", "cycle_peaks", "dead_centre_label",
           "named_columns", "render", "table_positions_error"]

#: What the tables show: a cycle held whole, or a long cycle's summary.
Study = PlanarStudy | PlanarSummary

#: Deprecated private name (tests reach it): :func:`linkwork.studies.planar.distinct_paths`.
_distinct_paths = study_planar.distinct_paths


def analyze_planar(doc: PlanarFile, *, out: Path, angles: np.ndarray | None, console: Any
                   ) -> PlanarStudy | PlanarSummary:
    """Analyse a planar mechanism file: table on ``console``, CSV/JSON/PNG into ``out``.

    ``angles``: the table's driver positions [rad, or m for a linear driver]; None: those of
    every command (:func:`linkwork.studies.planar.default_table_positions`). A cycle of more
    than :data:`~linkwork.io.planar.MAX_WHOLE_POSITIONS` positions of one driver goes chunk
    by chunk (:func:`analyze_long`).
    """
    if doc.analysis.n > MAX_WHOLE_POSITIONS and len(doc.drivers) == 1:
        return analyze_long(doc, out=out, angles=angles, console=console)
    with steps(1, console=make_console(stderr=True)) as step:
        step(f"solving {doc.analysis.n} positions")
        study = study_planar.analyze(doc, angles=angles)
    render(study, out=out, console=console)
    return study


def analyze_long(doc: PlanarFile, *, out: Path, angles: np.ndarray | None, console: Any
                 ) -> PlanarSummary:
    """:func:`analyze_planar` of a long cycle: solved chunk by chunk
    (:func:`~linkwork.studies.planar.analyze_chunked`), each chunk's rows streamed into
    ``planar_kinematics.csv`` and ``planar_dynamics.csv`` (written beside them and renamed
    when complete), under a progress bar of positions; ``planar.json`` without the
    per-position arrays; the plots drawn at :data:`~linkwork.studies.planar.PLOT_POSITIONS`
    positions (:meth:`~linkwork.studies.planar.PlanarSummary.sample`)."""
    with contextlib.ExitStack() as files, counting(
            f"solving and writing {doc.analysis.n} positions",
            console=make_console(stderr=True)) as progress:
        streams: list[CsvRows] = []

        def sink(kc: dict[str, Any], dc: dict[str, Any]) -> None:
            if not streams:  # headed by the first chunk's columns (the same every chunk)
                for name, cols in zip(FILES[:2], (kc, dc), strict=True):
                    streams.append(files.enter_context(
                        csv_rows(out / name, {k: u for k, (_, u) in cols.items()})))
            for rows, cols in zip(streams, (kc, dc), strict=True):
                rows.append({k: v for k, (v, _) in cols.items()})

        summary = study_planar.analyze_chunked(doc, angles=angles, sink=sink, units=True,
                                               chunk=study_planar.CHUNK_POSITIONS,
                                               progress=progress)
    render(summary, out=out, console=console)
    return summary


@dataclass(frozen=True)
class _Shown:
    """How the tables show the driver: its coordinate (name, unit, from SI) and its load."""

    position: str        # column head of the driver position
    unit: str            # display unit of the position
    scale: float         # SI -> display unit
    load: str            # "driving torque" / "driving force"
    load_unit: str       # unit of Q as printed


#: by the unit of the driver coordinate (``Crank.coordinate``, ``Linear.coordinate``)
_SHOWN = {"rad": _Shown("φ1 [deg]", "deg", 180.0 / np.pi, "driving torque", "N·m"),
          "m": _Shown("s1 [mm]", "mm", 1e3, "driving force", "N")}


def _shown(study: Study) -> _Shown:
    return _SHOWN[study.mechanism.drivers[0].coordinate[1]]


def _driver_heads(study: Study) -> list[tuple[str, _Shown, str]]:
    """Per driver: the column head of its position, how it is shown, the head of its Q (one
    driver: ``φ1 [deg]``, ``Q [N·m]``; several: ``φ1 O1 [deg]``, ``Q O1 [N·m]``)."""
    drivers = study.mechanism.drivers
    out = []
    for d in drivers:
        sh = _SHOWN[d.coordinate[1]]
        if len(drivers) == 1:
            out.append((sh.position, sh, f"Q [{sh.load_unit}]"))
        else:
            name, unit = sh.position.split(" ")
            out.append((f"{name} {d.joint} {unit}", sh, f"Q {d.joint} [{sh.load_unit}]"))
    return out


def _structure_and_dead_centres(study: Study, console: Any) -> None:
    s, shown = study.structure, _shown(study)
    title = escape(study.doc.name or "planar mechanism")
    drivers = study.mechanism.drivers
    given = "" if len(drivers) == 1 else (f" ({len(drivers)} drivers: "
                                          f"{', '.join(d.joint for d in drivers)})")
    console.print(f"[bold]{title}[/bold]: mobility W = {s.mobility}{escape(given)}; structure "
                  f"{escape(s.formula())}", highlight=False)
    if study.dead_centres:
        console.print("dead centres:", highlight=False)
        for d, (label, _) in zip(study.dead_centres, study.dead_centre_labels, strict=True):
            console.print(f"  {escape(label)} at {d.phi1 * shown.scale:.2f} {shown.unit}",
                          highlight=False)


def _scales(study: Study) -> dict[str, float]:
    """The round-off scale of each unit (``N``, ``N*m``; the driver's ``Q`` in its own unit):
    the largest peak over the cycle of the quantities in that unit (:func:`fmt`)."""
    scales: dict[str, float] = {}
    for pk in study.peaks:
        if pk["unit"] != "rad":
            scales[pk["unit"]] = max(scales.get(pk["unit"], 0.0), abs(pk["value"]))
    return scales


def _table(study: Study) -> Table:
    shown = _shown(study)
    tphi = np.atleast_2d(study.table_positions)
    tk, td, trans = study.table_kinematics, study.table_dynamics, study.table_transmission
    tq = np.atleast_2d(td.Q)
    scales = _scales(study)
    f_n, f_nm = scales.get("N", 0.0), scales.get("N*m", 0.0)
    ab = np.asarray(study.table_dynamics.about, dtype=float) * 1e3
    several = study.mechanism.n_drivers > 1
    table = Table(title=escape(
        f"{'driving loads' if several else shown.load}, joint reactions |R| (force of a on "
        f"b), shaking force and moment (about ({ab[0]:g}, {ab[1]:g}) mm)"))
    dh = _driver_heads(study)
    heads = [h for h, _, _ in dh] + [q for _, _, q in dh]
    heads += [f"|R {j}| [N]" for j in td.joints]
    heads += ["|F_sh| [N]", "M_sh [N·m]"] + [f"μ {key} [deg]" for key in trans]
    for h in heads:  # escape: "[mm]", "[deg]" would be read as Rich markup
        table.add_column(escape(h), justify="right", min_width=len(h), no_wrap=True)
    for i in range(tk.n):
        row = [fmt(tphi[k, i] * sh.scale, decimals=1) for k, (_, sh, _) in enumerate(dh)]
        row += [fmt(tq[k, i], scales.get(d.field_units["Q"], 0.0))
                for k, d in enumerate(study.mechanism.drivers)]
        row += [fmt(td.reaction_magnitude(j)[i], f_n) for j in td.joints]
        row += [fmt(np.hypot(td.shaking_fx[i], td.shaking_fy[i]), f_n),
                fmt(td.shaking_m[i], f_nm)]
        row += [fmt(np.degrees(mu[i]), decimals=1) for mu, _ in trans.values()]
        table.add_row(*row)
    return table


def _power_scale(study: Study) -> float:
    """The round-off scale of the driving power: its largest value over the cycle (a long
    cycle's summary keeps its mean and the table's positions)."""
    if isinstance(study, PlanarStudy):
        return scale_of(study.dynamics.total_power)
    return max(scale_of(study.table_dynamics.total_power), abs(study.means["power_mean"]))


def _extremes(study: Study) -> Table:
    shown, scales = _shown(study), _scales(study)
    several = study.mechanism.n_drivers > 1
    ptab = Table(title=escape(f"extremes over the cycle ({study.n} positions of "
                              "[analysis])"))
    ptab.add_column("quantity", no_wrap=True)
    dh = _driver_heads(study)
    for h in ("value", *(("position",) if several else ()), *(h for h, _, _ in dh)):
        ptab.add_column(escape(h), justify="right", no_wrap=True)
    for pk in study.peaks:
        pos = ([fmt(x * sh.scale, decimals=1) for x, (_, sh, _) in zip(pk["phi1"], dh,
                                                                      strict=True)]
               if several else [fmt(pk["phi1"] * shown.scale, decimals=1)])
        value, unit = pk["value"], pk["unit"]
        scale = scales.get(unit, 0.0)
        if unit == "rad":  # transmission angles: shown in degrees, as in the table above
            value, unit = np.degrees(value), "deg"
        ptab.add_row(escape(f"{pk['name']} [{unit_label(unit)}]"), fmt(value, scale),
                     *((str(pk["position"]),) if several else ()), *pos)
    # over a closed cycle the work of the driver is round-off for a conservative mechanism:
    # its scale is that of the driving torque (force), and of the power over the cycle
    blank = [""] * (len(dh) + (1 if several else 0))
    means = study.means["Q_mean"]
    for d, (_, sh, _) in zip(study.mechanism.drivers, dh, strict=True):
        value = means[d.joint] if several else means
        ptab.add_row(escape(f"Q{' ' + d.joint if several else ''} mean (work / range) "
                            f"[{sh.load_unit}]"),
                     fmt(np.nan if value is None else value,
                         scales.get(d.field_units["Q"], 0.0)), *blank)
    ptab.add_row("driving power, mean [W]" if not several else
                 "driving power of all drivers, mean [W]",
                 fmt(study.means["power_mean"], _power_scale(study)), *blank)
    return ptab


def _friction(study: Study, console: Any) -> None:
    """With friction in some joint: the losses per joint over the cycle, the cycle efficiency
    and the self-locking ranges (nothing is printed without friction)."""
    fr = study.friction
    if fr is None:
        return
    shown = _shown(study)
    tab = Table(title=escape(f"friction losses over the cycle ({study.n} positions "
                             "of [analysis])"))
    for h in ("joint", "loss [J]", "share of the driver's work [%]"):
        tab.add_column(escape(h), justify="left" if h == "joint" else "right", no_wrap=True)
    top = max((abs(v) for v in fr["losses"].values() if v is not None), default=0.0)
    for j, loss in fr["losses"].items():
        share = fr["loss_share"][j]
        tab.add_row(escape(j), fmt(np.nan if loss is None else loss, top),
                    fmt(np.nan if share is None else 100 * share, decimals=2))
    print_table(console, tab)
    eta = fr["efficiency_cycle"]
    console.print("cycle efficiency (useful work / driver's work): " + (
        fmt(eta, decimals=4) if eta is not None else
        "undefined (the driver does no positive work over the range, or it self-locks)"),
        highlight=False)
    if fr["self_locking"]:
        runs = ", ".join(f"{a * shown.scale:.1f}..{b * shown.scale:.1f}"
                         for a, b in fr["self_locking"])
        console.print(escape(f"self-locking (no finite {shown.load} moves it) at "
                             f"{shown.position.split()[0]} = {runs} {shown.unit} "
                             f"({fr['locked_positions']} positions; Q undefined there)"),
                      highlight=False)
    else:
        console.print("self-locking: none over the range", highlight=False)


def _loads(study: Study, console: Any) -> None:
    """With force elements or load diagrams: each one's range of values, length, and work over
    the cycle, and where each diagram acts (nothing is printed without them)."""
    if not study.loads:
        return
    shown = _shown(study)
    tab = Table(title=escape(f"loads and force elements over the cycle ({study.n} "
                             "positions of [analysis]; springs and dampers: tension +)"))
    heads = ("load", "kind", "min", "max", "unit", "length [mm]", "work [J]")
    for h in heads:
        tab.add_column(escape(h), justify="left" if h in ("load", "kind", "unit") else "right",
                       no_wrap=True)
    top = max((abs(e["work"]) for e in study.loads if e["work"] is not None), default=0.0)
    for e in study.loads:
        scale = max(abs(e["min"] or 0.0), abs(e["max"] or 0.0))
        length = ("" if "length" not in e else
                  "..".join(fmt(v * 1e3, decimals=1) for v in e["length"]))
        tab.add_row(escape(e["name"]), e["kind"],
                    fmt(np.nan if e["min"] is None else e["min"], scale),
                    fmt(np.nan if e["max"] is None else e["max"], scale), unit_label(e["unit"]),
                    length, fmt(np.nan if e["work"] is None else e["work"], top))
    print_table(console, tab)
    when = {"always": "at every position", "increasing": "while it increases",
            "decreasing": "while it decreases"}
    for e in study.loads:
        d = e.get("diagram")
        if d is None:
            continue
        if d["over"] == "driver":
            what, scale, unit = shown.position.split()[0], shown.scale, shown.unit
        else:
            what, scale, unit = f"the slide s of {d['over']}", 1e3, "mm"
        lo, hi = (fmt(v * scale, decimals=1) for v in d["range"])
        console.print(escape(
            f"{e['name']}: diagram over {what} from {lo} to {hi} {unit}, acting {when[d['when']]}"
            f"; outside its range {'zero' if d['outside'] == 'zero' else 'refused'}"),
            highlight=False)


#: The files that :func:`render` writes, in order (one step of its progress bar each); the
#: loads' figure only with force elements or load diagrams.
FILES = ("planar_kinematics.csv", "planar_dynamics.csv", "planar.json", "planar_skeleton.png",
         "planar_driving_torque.png", "planar_reactions.png", "planar_shaking.png",
         "planar_loads.png")


def _plots(study: Study, out: Path, step: Callable[[str], None] = lambda what: None
           ) -> list[Path]:
    from linkwork.plot import planar as pplot
    from linkwork.plot import save

    if isinstance(study, PlanarStudy):
        kin, dyn = study.kinematics, study.dynamics
    else:  # a long cycle: drawn at PLOT_POSITIONS of its positions
        step(f"solving {min(study.n, PLOT_POSITIONS)} positions for the plots")
        kin, dyn = study.sample()
    step(f"drawing {FILES[3]}")
    plt = pplot.pyplot()
    fig, ax = plt.subplots(figsize=(7, 6))
    good = np.flatnonzero(kin.valid)
    picks = [int(good[k]) for k in np.linspace(0, good.size - 1, 4, endpoint=False).astype(int)]
    name = study.doc.name or None
    pplot.plot_skeleton(kin, picks, ax=ax, name=name)  # every named point's path
    written = [save(fig, out / "planar_skeleton.png")]
    step(f"drawing {FILES[4]}")
    fig, ax = plt.subplots()
    pplot.plot_driving_torque(dyn, ax=ax, name=name)
    written.append(save(fig, out / "planar_driving_torque.png"))
    step(f"drawing {FILES[5]}")
    fig, ax = plt.subplots()
    pplot.plot_reactions(dyn, ax=ax, name=name)
    written.append(save(fig, out / "planar_reactions.png"))
    step(f"drawing {FILES[6]}")
    fig, axes = plt.subplots(2, 1, sharex=True)
    pplot.plot_shaking(dyn, axes=axes, name=name)
    written.append(save(fig, out / "planar_shaking.png"))
    if study.loads:
        step(f"drawing {FILES[7]}")
        units = {e["unit"] for e in study.loads}
        fig, axes = plt.subplots(len(units), 1, sharex=True, squeeze=False)
        pplot.plot_loads(dyn, [e["name"] for e in study.loads], axes=axes[:, 0], name=name)
        written.append(save(fig, out / "planar_loads.png"))
    return written


def render(study: Study, *, out: Path, console: Any) -> None:
    """Print a :class:`~linkwork.studies.planar.PlanarStudy` on ``console`` and write its CSV,
    JSON and plots into ``out``; a long cycle's
    :class:`~linkwork.studies.planar.PlanarSummary`: its CSV files were streamed while it was
    solved (:func:`analyze_long`), its JSON holds no per-position arrays and its plots are
    drawn at :data:`~linkwork.studies.planar.PLOT_POSITIONS` positions."""
    _structure_and_dead_centres(study, console)
    print_table(console, _table(study))
    print_table(console, _extremes(study))
    _friction(study, console)
    _loads(study, console)
    whole = isinstance(study, PlanarStudy)
    n_steps = len(FILES) - (not study.loads) - (0 if whole else 1)
    with steps(n_steps, console=make_console(stderr=True)) as step:
        if isinstance(study, PlanarStudy):
            step(f"writing {FILES[0]}")
            written = [write_csv(out / FILES[0], study.kinematics_columns())]
            step(f"writing {FILES[1]}")
            written.append(write_csv(out / FILES[1], study.dynamics_columns()))
            step(f"writing {FILES[2]}")
            written.append(write_json(out / FILES[2], study.to_dict(lists=False)))
        else:
            written = [out / FILES[0], out / FILES[1]]
            step(f"writing {FILES[2]}")
            written.append(write_json(out / FILES[2], study.to_dict(files=FILES[:2])))
        written += _plots(study, out, step)
    if not whole:
        console.print(escape(f"(a long cycle: {FILES[0]} and {FILES[1]} hold all {study.n} "
                             f"positions, written chunk by chunk; {FILES[2]} its summary, the "
                             f"plots {min(study.n, PLOT_POSITIONS)} positions over the same "
                             "range)"), highlight=False)
    console.print(escape("wrote " + ", ".join(str(w) for w in written)), highlight=False)
