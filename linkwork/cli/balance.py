"""``linkwork balance FILE.toml``: paper 001's balancing comparison for a planar mechanism.

Reads a ``type = "planar"`` mechanism file and its optional ``[balance]`` section
(:class:`linkwork.io.planar.BalanceSection`), runs :func:`linkwork.studies.balance.run` and
renders the :class:`~linkwork.studies.balance.BalanceStudy`::

    [balance]
    links = ["crank", "rocker"]                      # counterweighted frame-hinged links
    radii = { crank = "50 mm", rocker = "100 mm" }   # counterweight radii
    angles = [0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330]   # table [deg]
    n = 360                                          # positions of the full cycle

Prints the table M, dM1, dM2, dM3 with R2, R3, the counterweights, the moved-axis positions and
the peak/RMS summary with every quantity that balancing raises, and writes into ``--out``:
``balance_table.csv/.json``, ``balance_cycle.csv``, ``balance_summary.json``,
``balancing_moments.png``, ``balancing_force.png``, ``balancing_torque.png``,
``balancing_bearings.png`` and, with
``--pareto``, ``balancing_pareto.png`` and ``balance_pareto.json``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import load_errors, output_dir, output_run, parse_angles_deg
from linkwork.cli._console import console as make_console
from linkwork.cli._console import steps
from linkwork.cli._format import fmt, scale_of, unit_label
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.planar import BalanceSection, PlanarFile
from linkwork.io.toml import read_toml
from linkwork.planar import Mechanism
from linkwork.results import write_csv, write_json
from linkwork.studies import balance as study_balance
from linkwork.studies.balance import BalanceStudy, PathBalanceStudy

__all__ = ["BalanceSection", "load_balance_file", "register", "render", "render_path",
           "run_balance"]


def load_balance_file(path: str | Path) -> tuple[Mechanism, BalanceSection, PlanarFile]:
    """Read a planar mechanism file and its ``[balance]`` section.

    Returns (Mechanism, section, validated planar document).
    """
    kind = read_toml(path).get("type")
    if kind != "planar":
        raise FileFormatError(str(path), "type", f"balance needs a 'planar' mechanism file, "
                              f"got {kind!r}")
    doc = io.load(path, types={"planar": io.PlanarFile})
    try:  # before any work
        study_balance.check(doc)
    except ParameterError as exc:
        raise FileFormatError(str(path), exc.parameter, str(exc).removeprefix(
            f"{exc.parameter} = ")) from None
    return doc.mechanism(), doc.balance, doc


def _fmt(x: float, nd: int = 3) -> str:
    """Fixed decimals (:func:`linkwork.cli._format.fmt`)."""
    return fmt(x, decimals=nd)


def _unit_scales(summary: dict[str, dict[str, float]], lever: float) -> dict[str, float]:
    """The round-off scale of each unit of the summary (``[N]``, ``[N*m]``): its largest
    value; moments also the largest force times the counterweights' lever (a mechanism whose
    moments are all round-off has no moment scale of its own)."""
    scales: dict[str, float] = {}
    for q, vals in summary.items():
        unit = q[q.rfind("["):]
        scales[unit] = max(scales.get(unit, 0.0), scale_of(list(vals.values())))
    scales["[N*m]"] = max(scales.get("[N*m]", 0.0), scales.get("[N]", 0.0) * lever)
    return scales


def run_balance(mech: Any, section: BalanceSection, out: Path, console: Any,
                pareto: bool = False, gravity: Any = None, loads: Any = None) -> Any:
    """Run the comparison on ``mech``, print it on ``console``, write the outputs to ``out``.

    ``gravity`` (gx, gy) [m/s²] and ``loads`` (callable phi1 -> external loads) enter the
    driving torque and bearing reactions only.
    Returns the :class:`~linkwork.balancing.comparison.BalancingComparison`.
    """
    study = study_balance.compare(mech, section, pareto=pareto, gravity=gravity, loads=loads)
    render(study, out=out, console=console)
    return study.comparison


def _summary_table(console: Any, title: str, summary: dict[str, dict[str, float]],
                   scales: dict[str, float]) -> None:
    """The peaks and RMS of ``summary`` (quantity -> {variant: value}), one row each."""
    s = Table(title=title)
    s.add_column("quantity")
    s.add_column("values")
    for q, vals in summary.items():
        scale = scales[q[q.rfind("["):]]
        s.add_row(escape(unit_label(q)),
                  escape(", ".join(f"{k} {fmt(v, scale)}" for k, v in vals.items())))
    print_table(console, s)


def _counterweight_lines(console: Any, counterweights: Any) -> None:
    """One line per counterweight: its static moment, angle, radius and mass."""
    for cw in counterweights:
        rm = ("no radius: mass not known" if cw.radius is None else
              f"r = {fmt(cw.radius * 1000)} mm, m = {fmt(cw.mass())} kg")
        console.print(escape(f"  counterweight on {cw.link}: S = {fmt(cw.static_moment, 0, 5)} "
                             f"kg·m at {fmt(np.degrees(cw.angle), decimals=2)} deg, {rm}"),
                      highlight=False)


def _tables(study: BalanceStudy, console: Any) -> None:
    comp = study.comparison
    t = Table(title="Shaking moment about the crank axis [N·m] (paper 001)")
    for h in ("φ1 [deg]", "M unbalanced", "ΔM1 static", "ΔM2 1st harmonic", "ΔM3 least sq."):
        t.add_column(escape(h), justify="right")  # "[deg]" would be read as Rich markup
    for i, p in enumerate(np.degrees(comp.phi1)):
        t.add_row(_fmt(p, 1), _fmt(comp.M[i]), _fmt(comp.dM1[i]), _fmt(comp.dM2[i]),
                  _fmt(comp.dM3[i]))
    t.add_row("R_j [%]", "", "", _fmt(comp.R2, 1), _fmt(comp.R3, 1))
    print_table(console, t)
    fb = comp.balance
    summary = comp.summary()
    lever = max((cw.radius for cw in comp.counterweights if cw.radius is not None),
                default=0.0)
    scales = _unit_scales(summary, lever)
    f_n = scales.get("[N]", 0.0)
    console.print(f"static balancing: {'full' if fb.full else 'PARTIAL'}; RMS shaking force "
                  f"{fmt(fb.force_rms_before, f_n)} N -> {fmt(fb.force_rms_after, f_n, 3)} N",
                  highlight=False)
    if not fb.full:
        console.print(escape(f"  not fully balanceable: {fb.reason}"), highlight=False)
    _counterweight_lines(console, comp.counterweights)
    mm = [fmt(v * 1000, decimals=2) for v in (comp.x2, comp.y2, comp.x3, comp.y3)]
    console.print(f"moved crank-counterweight axis O1: first harmonic (x, y) = "
                  f"({mm[0]}, {mm[1]}) mm; least squares over the table = ({mm[2]}, {mm[3]}) mm",
                  highlight=False)
    _summary_table(console, "Peaks and RMS over the cycle", summary, scales)
    ht = Table(title="Harmonic amplitudes A_j (f = a0 + sum A_j cos(j*phi1 - psi_j))")
    ht.add_column("quantity")
    ht.add_column("mean", justify="right")
    for j in range(1, study_balance.HARMONICS + 1):
        ht.add_column(f"A{j}", justify="right")
    for name, hv in study.harmonics.items():
        ht.add_row(escape(name), _fmt(hv.mean), *(_fmt(a) for a in hv.amplitude))
    print_table(console, ht)
    if study.increases:
        console.print("[bold]balancing raises:[/bold]", highlight=False)
        for m in study.increases:
            console.print(escape(f"  {m.replace('N*m', unit_label('N*m'))}"), highlight=False)


def _plots(study: BalanceStudy, out: Path, name: str | None = None) -> None:
    from linkwork.plot import figure_title, pyplot, save, titled
    from linkwork.plot.balancing import (
        plot_force_hodograph,
        plot_moments,
        plot_pareto,
        plot_torques,
    )

    plt = pyplot()
    c = study.comparison.cycle
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_moments(c.phi1, {"M unbalanced": c.M, "ΔM1 static": c.dM1,
                          "ΔM2 first harmonic": c.dM2, "ΔM3 least squares": c.dM3}, ax=ax,
                 name=name)
    save(fig, out / "balancing_moments.png")
    fig, ax = plt.subplots(figsize=(5, 5))
    plot_force_hodograph({"unbalanced": c.F0, "static": c.F1}, ax=ax, name=name)
    save(fig, out / "balancing_force.png")
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_torques(c.phi1, {"unbalanced": c.Q0, "balanced": c.Q1}, ax=ax, name=name)
    save(fig, out / "balancing_torque.png")
    joints = list(c.reactions0)
    if joints:
        fig, axes = plt.subplots(len(joints), 1, figsize=(7, 2.6 * len(joints) + 0.6),
                                 sharex=True, squeeze=False)
        for ax, joint in zip(axes[:, 0], joints, strict=True):
            curves = {"unbalanced": c.reactions0[joint], "static": c.reactions1[joint],
                      "moved axis (paper 001)": c.reactions3[joint]}
            if joint == study.mechanism.drivers[0].joint and "O1" in c.reactions3:
                curves["moved counterweight's bearing O1"] = c.reactions3["O1"]
            plot_moments(c.phi1, curves, ax=ax, ylabel=f"|R| at {joint} [N]", title="")
            if ax is not axes[-1, 0]:
                ax.set_xlabel("")
        figure_title(fig, titled(name, "Balancing", "frame-bearing reactions before and after "
                                 "balancing"))
        save(fig, out / "balancing_bearings.png")
    p: Any = study.pareto  # arrays, where plot_pareto names sequences
    if p is not None:
        fig, ax = plt.subplots(figsize=(7, 5))
        plot_pareto(p.force_rms, p.moment_rms, p.torque_fluct, ax=ax,
                    points=study.pareto_points(), dominated=p.dominated, name=name)
        save(fig, out / "balancing_pareto.png")


def render(study: BalanceStudy, *, out: Path, console: Any, name: str | None = None) -> None:
    """Print a :class:`~linkwork.studies.balance.BalanceStudy` on ``console`` and write its
    tables, summary and plots into ``out`` (``name``: of the mechanism, on the plots)."""
    _tables(study, console)
    output_dir(out)
    comp = study.comparison
    with steps(2, console=make_console(stderr=True)) as step:
        step("writing balance_table.csv/.json, balance_cycle.csv, balance_summary.json")
        comp.to_csv(out / "balance_table.csv")
        comp.to_json(out / "balance_table.json")
        comp.cycle.to_csv(out / "balance_cycle.csv")
        write_json(out / "balance_summary.json", study.summary())
        step("drawing the plots")
        _plots(study, out, name)
        if study.pareto is not None:
            write_json(out / "balance_pareto.json", study.pareto_dict())
    if study.pareto is not None:
        console.print(f"Pareto set: {int((~study.pareto.dominated).sum())} non-dominated of "
                      f"{len(study.pareto.designs)}", highlight=False)
    console.print(f"written to {escape(str(out))}", highlight=False)


def render_path(study: PathBalanceStudy, *, out: Path, console: Any,
                name: str | None = None) -> None:
    """Print a :class:`~linkwork.studies.balance.PathBalanceStudy` (several drivers) and write
    ``balance_path.csv``, ``balance_summary.json`` and ``balancing_path.png`` into ``out``."""
    fb = study.balance
    drivers = study.mechanism.drivers
    summary = study.summary()
    scales = _unit_scales(summary, max((c.radius or 0.0 for c in fb.counterweights),
                                       default=0.0))
    f_n = scales.get("[N]", 0.0)
    console.print(escape(f"force balance of {len(drivers)} drivers "
                         f"({', '.join(d.joint for d in drivers)}) along their path: the "
                         "counterweights keep the centre of mass of the moving links "
                         f"{'still' if fb.full else 'as still as they can (least squares)'}; "
                         f"{'full' if fb.full else 'PARTIAL'}; RMS shaking force "
                         f"{fmt(fb.force_rms_before, f_n)} N -> "
                         f"{fmt(fb.force_rms_after, f_n, 3)} N"), highlight=False)
    if not fb.full:
        console.print(escape(f"  not fully balanceable: {fb.reason}"), highlight=False)
    _counterweight_lines(console, fb.counterweights)
    console.print(escape(f"not computed: {study.not_computed}"), highlight=False)
    t = Table(title="Shaking force and moment (inertia forces) and driving loads along the path")
    tphi = study.table_positions
    heads = []
    for d in drivers:
        lin = d.kind == "linear"
        heads.append(f"{'s1' if lin else 'φ1'} {d.joint} [{'mm' if lin else 'deg'}]")
    for d in drivers:
        unit = unit_label(d.field_units["Q"])
        heads += [f"Q {d.joint} [{unit}]", f"Q {d.joint} bal."]
    heads += ["|F| [N]", "|F| bal.", f"M [{unit_label('N*m')}]", "M bal."]
    for h in heads:
        t.add_column(escape(h), justify="right")
    tb, ta = study.table_before, study.table_after
    f_nm = scales.get("[N*m]", 0.0)
    for k in range(tphi.shape[1]):
        row = [fmt(tphi[i, k] * 1e3) if d.kind == "linear" else fmt(np.degrees(tphi[i, k]))
               for i, d in enumerate(drivers)]
        for i, d in enumerate(drivers):
            sc = scales.get(f"[{d.field_units['Q']}]", 0.0)
            row += [fmt(study.table_Q0[i, k], sc), fmt(study.table_Q1[i, k], sc)]
        row += [fmt(float(np.hypot(tb.fx[k], tb.fy[k])), f_n),
                fmt(float(np.hypot(ta.fx[k], ta.fy[k])), f_n),
                fmt(tb.moment[k], f_nm), fmt(ta.moment[k], f_nm)]
        t.add_row(*row)
    print_table(console, t)
    _summary_table(console, "Peaks and RMS along the path", summary, scales)
    output_dir(out)
    write_csv(out / "balance_path.csv", study.columns())
    write_json(out / "balance_summary.json", study.to_dict())
    from linkwork.plot import save

    save(study.plot(name=name).figure, out / "balancing_path.png")
    console.print(f"written to {escape(str(out))}", highlight=False)


def register(app: typer.Typer) -> None:
    """Add the ``balance`` command to ``app``."""

    @app.command()
    def balance(
        file: Annotated[Path, typer.Argument(help="planar mechanism file (TOML)")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
        angles: Annotated[str | None, typer.Option(
            help="table crank angles, deg, comma-separated (overrides \\[balance].angles)")
        ] = None,
        pareto: Annotated[bool, typer.Option(
            "--pareto", help="also optimise counterweights and plot the trade-off")] = False,
    ) -> None:
        """Balance a planar mechanism: paper 001's table, torque and bearing loads, plots."""
        _, _, doc = load_balance_file(file)
        if len(doc.drivers) > 1:  # several drivers: force balance along their path
            for option, given in (("--angles", angles), ("--pareto", pareto or None)):
                if given is not None:
                    raise ParameterError(option, given, "is for one crank's cycle; several "
                                         "drivers are balanced along their path")
            doc.check_whole_cycle(file, "`linkwork balance` of several drivers")
            with output_run(out, command="balance", file=file), load_errors(file, doc):
                render_path(study_balance.run_path(doc), out=out, console=make_console(),
                            name=doc.name or None)
            return
        table = None if angles is None else parse_angles_deg(angles)
        # --out checked before the work: an unusable one must not cost an optimisation
        with output_run(out, command="balance", file=file), load_errors(file, doc):
            console = make_console()
            if doc.load:
                console.print("note: the file's external loads enter the driving torque and "
                              "the bearing reactions, not the shaking-moment table (inertia "
                              "forces)", highlight=False)
            try:
                with steps(1, console=make_console(stderr=True)) as step:
                    step("balancing" + (" and optimising the counterweights" if pareto else ""))
                    study = study_balance.run(doc, angles=table, pareto=pareto)
            except ParameterError as exc:  # the joints' friction locks it: the file's keys
                if exc.parameter != "friction":
                    raise
                raise FileFormatError(str(file), "joint friction", str(exc).removeprefix(
                    "friction = ")) from None
            render(study, out=out, console=console, name=doc.name or None)
