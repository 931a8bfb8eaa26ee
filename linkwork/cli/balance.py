"""``linkwork balance FILE.toml``: paper 001's balancing comparison for a planar mechanism.

Reads a ``type = "planar"`` mechanism file (the engine's schema) and an optional ``[balance]``
table that only this command reads (it is removed before the mechanism is validated)::

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

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from pydantic import Field, field_validator

from linkwork import files
from linkwork.cli.analyze import output_dir
from linkwork.errors import AssemblyError, FileFormatError, LinkworkError
from linkwork.files import FileModel

__all__ = ["BalanceSection", "load_balance_file", "register", "run_balance"]


class BalanceSection(FileModel):
    """The optional ``[balance]`` table of a planar mechanism file."""

    links: list[str] | None = None
    radii: dict[str, float] | float | None = None
    angles: list[float] | None = None
    n: int = Field(default=360, ge=12, le=20000)

    @field_validator("angles", mode="before")
    @classmethod
    def _angles(cls, v: Any) -> list[float] | None:
        """Table positions in degrees: plain numbers are degrees (as ``--angles``); strings
        carry their unit ("30 deg", "0.5 rad")."""
        from linkwork.planar.file import MAX_ANGLE
        from linkwork.units import to_si

        max_deg = math.degrees(MAX_ANGLE)
        if v is None:
            return None
        if not isinstance(v, list) or not v:
            raise ValueError("must be a non-empty list of angles, e.g. [0, 30, 60] (degrees) "
                             "or [\"0 deg\", \"0.5 rad\"]")
        out = []
        for x in v:
            if isinstance(x, bool) or not isinstance(x, (int, float, str)):
                raise ValueError(f"must be numbers in degrees or angles with a unit (got {x!r})")
            try:
                deg = float(np.degrees(to_si(x, "angle"))) if isinstance(x, str) else float(x)
            except LinkworkError as exc:
                raise ValueError(f"{getattr(exc, 'limit', exc)} (got {x!r})") from None
            if not np.isfinite(deg):
                raise ValueError(f"must be finite (got {x!r})")
            if abs(deg) > max_deg:  # as --angles: no 300-digit angles in the table
                raise ValueError(f"must lie within +-{max_deg:.6g} deg (got {x!r})")
            out.append(deg)
        return out

    @field_validator("radii", mode="before")
    @classmethod
    def _radii(cls, v: Any) -> dict[str, float] | float | None:
        """One length for every link or a table link -> length, each > 0 [m].

        Validated here rather than by a union of pydantic types, whose error locations named
        the union's internal types (``balance.radii.dict[str,function-before[...]].crank``).
        """
        from linkwork.units import to_si

        def one(key: str, x: Any) -> float:
            got = "" if key == "radius" else f" (got {x!r})"  # the file's value is quoted after
            if isinstance(x, bool) or not isinstance(x, (int, float, str)):
                raise ValueError(f"{key} must be a length, e.g. '50 mm'{got}")
            try:
                r = to_si(x, "length", key)
            except LinkworkError as exc:
                raise ValueError(f"{key}: {getattr(exc, 'limit', exc)}{got}") from None
            if not (np.isfinite(r) and r > 0.0):
                raise ValueError(f"{key} must be > 0{got}")
            return r

        if v is None:
            return None
        if isinstance(v, dict):
            return {str(k): one(f"radius of {k}", x) for k, x in v.items()}
        return one("radius", v)


def _to_mechanism(doc: Any) -> Any:
    """The engine Mechanism described by a validated planar document."""
    from linkwork.planar.model import Mechanism

    if isinstance(doc, Mechanism):
        return doc
    for name in ("to_mechanism", "mechanism", "build"):
        attr = getattr(doc, name, None)
        val = attr() if callable(attr) else attr
        if isinstance(val, Mechanism):
            return val
    raise FileFormatError("file", "type", "the planar document does not provide a mechanism")


def load_balance_file(path: str | Path) -> tuple[Any, BalanceSection, Any]:
    """Read a planar mechanism file and its ``[balance]`` table.

    Returns (Mechanism, section, validated planar document).
    """
    from linkwork.cli.analyze import without_command_tables

    raw = files.read_toml(path)
    section = raw.pop("balance", {})
    raw = without_command_tables(raw)  # [spatial] is read by `linkwork reactions`
    kind = raw.get("type")
    if kind != "planar":
        raise FileFormatError(str(path), "type", f"balance needs a 'planar' mechanism file, "
                              f"got {kind!r}")
    schema = files.schemas().get("planar")
    if schema is None:  # the engine's schema module, in case SCHEMA_MODULES does not list it
        import importlib

        try:
            importlib.import_module("linkwork.planar.file")
        except ImportError:
            pass
        schema = files.schemas().get("planar")
    if schema is None:
        raise FileFormatError(str(path), "type", "no schema for 'planar' files is installed")
    doc = files.validate(path, raw, schema)
    if not isinstance(section, dict):
        raise FileFormatError(str(path), "balance", "must be a table")
    sec = files.validate(path, {"balance": section}, _Wrapper).balance
    try:
        mech = _to_mechanism(doc)
    except FileFormatError as exc:
        raise FileFormatError(str(path), exc.key, exc.problem) from None
    return mech, sec, doc


class _Wrapper(FileModel):
    balance: BalanceSection


def _fmt(x: float, nd: int = 3) -> str:
    v = round(float(x), nd)
    return f"{(v if v != 0.0 else 0.0):.{nd}f}"


def run_balance(mech: Any, section: BalanceSection, out: Path, console: Any,
                pareto: bool = False, gravity: Any = None, loads: Any = None) -> Any:
    """Run the comparison on ``mech``, print it on ``console``, write the outputs to ``out``.

    ``gravity`` (gx, gy) [m/s²] and ``loads`` (callable phi1 -> external loads) enter the
    driving torque and bearing reactions only.
    Returns the :class:`~linkwork.balancing.comparison.BalancingComparison`.
    """
    from rich.markup import escape
    from rich.table import Table

    from linkwork.balancing import compare_balancing
    from linkwork.plot import pyplot, save
    from linkwork.plot.balancing import (
        plot_force_hodograph,
        plot_moments,
        plot_pareto,
        plot_torques,
    )

    angles = None if section.angles is None else np.radians(np.asarray(section.angles, float))
    comp = compare_balancing(mech, angles, links=section.links, radii=section.radii,
                             n=section.n, gravity=gravity, loads=loads)
    t = Table(title="Shaking moment about the crank axis [N·m] (paper 001)")
    for h in ("φ1 [deg]", "M unbalanced", "ΔM1 static", "ΔM2 1st harmonic", "ΔM3 least sq."):
        t.add_column(escape(h), justify="right")  # "[deg]" would be read as Rich markup
    for i, p in enumerate(np.degrees(comp.phi1)):
        t.add_row(_fmt(p, 1), _fmt(comp.M[i]), _fmt(comp.dM1[i]), _fmt(comp.dM2[i]),
                  _fmt(comp.dM3[i]))
    t.add_row("R_j [%]", "", "", _fmt(comp.R2, 1), _fmt(comp.R3, 1))
    console.print(t)
    fb = comp.balance
    console.print(f"static balancing: {'full' if fb.full else 'PARTIAL'}; RMS shaking force "
                  f"{fb.force_rms_before:.4g} N -> {fb.force_rms_after:.3g} N")
    if not fb.full:
        console.print(escape(f"  not fully balanceable: {fb.reason}"))
    for cw in comp.counterweights:
        r = cw.radius if cw.radius is not None else float("nan")
        console.print(escape(f"  counterweight on {cw.link}: S = {cw.static_moment:.5g} kg*m "
                             f"at {np.degrees(cw.angle):.2f} deg, r = {r * 1000:.4g} mm, "
                             f"m = {cw.mass():.4g} kg"))
    console.print(f"moved crank-counterweight axis O1: first harmonic (x, y) = "
                  f"({comp.x2 * 1000:.2f}, {comp.y2 * 1000:.2f}) mm; least squares over the "
                  f"table = ({comp.x3 * 1000:.2f}, {comp.y3 * 1000:.2f}) mm")
    s = Table(title="Peaks and RMS over the cycle")
    s.add_column("quantity")
    s.add_column("values")
    for q, vals in comp.summary().items():
        s.add_row(q, ", ".join(f"{k} {v:.4g}" for k, v in vals.items()))
    console.print(s)
    ht = Table(title="Harmonic amplitudes A_j (f = a0 + sum A_j cos(j*phi1 - psi_j))")
    ht.add_column("quantity")
    ht.add_column("mean", justify="right")
    harm = comp.harmonics(4)
    for j in range(1, 5):
        ht.add_column(f"A{j}", justify="right")
    for name, hv in harm.items():
        ht.add_row(name, _fmt(hv.mean), *(_fmt(a) for a in hv.amplitude))
    console.print(ht)
    inc = comp.increases()
    if inc:
        console.print("[bold]balancing raises:[/bold]")
        for m in inc:
            console.print(escape(f"  {m}"))
    output_dir(out)
    comp.to_csv(out / "balance_table.csv")
    comp.to_json(out / "balance_table.json")
    comp.cycle.to_csv(out / "balance_cycle.csv")
    summary: dict[str, Any] = {"summary": comp.summary(), "increases": inc,
                               "R2": comp.R2, "R3": comp.R3,
                               "axis_first_harmonic": [comp.x2, comp.y2],
                               "axis_least_squares": [comp.x3, comp.y3],
                               "counterweights": [
                                   {"link": w.link, "static_moment": w.static_moment,
                                    "angle": w.angle, "radius": w.radius, "mass": w.mass()}
                                   for w in comp.counterweights],
                               "full_force_balance": fb.full, "reason": fb.reason,
                               "harmonics": {n: {"mean": hv.mean,
                                                 "amplitude": hv.amplitude.tolist(),
                                                 "phase": hv.phase.tolist()}
                                             for n, hv in harm.items()}}
    (out / "balance_summary.json").write_text(json.dumps(summary, indent=1))
    plt = pyplot()
    c = comp.cycle
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_moments(c.phi1, {"M unbalanced": c.M, "ΔM1 static": c.dM1,
                          "ΔM2 first harmonic": c.dM2, "ΔM3 least squares": c.dM3}, ax=ax)
    save(fig, out / "balancing_moments.png")
    fig, ax = plt.subplots(figsize=(5, 5))
    plot_force_hodograph({"unbalanced": c.F0, "static": c.F1}, ax=ax)
    save(fig, out / "balancing_force.png")
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_torques(c.phi1, {"unbalanced": c.Q0, "balanced": c.Q1}, ax=ax)
    save(fig, out / "balancing_torque.png")
    joints = list(c.reactions0)
    if joints:
        fig, axes = plt.subplots(len(joints), 1, figsize=(7, 2.6 * len(joints) + 0.6),
                                 sharex=True, squeeze=False)
        for ax, name in zip(axes[:, 0], joints, strict=True):
            curves = {"unbalanced": c.reactions0[name], "static": c.reactions1[name],
                      "moved axis (paper 001)": c.reactions3[name]}
            if name == mech.driver.joint and "O1" in c.reactions3:
                curves["moved counterweight's bearing O1"] = c.reactions3["O1"]
            plot_moments(c.phi1, curves, ax=ax, ylabel=f"|R| at {name} [N]")
            if ax is not axes[-1, 0]:
                ax.set_xlabel("")
        axes[0, 0].set_title("frame-bearing reactions before and after balancing")
        save(fig, out / "balancing_bearings.png")
    if pareto:
        _pareto(mech, section, comp, out, plot_pareto, save, plt, console)
    console.print(f"written to {escape(str(out))}")
    return comp


def _pareto(mech: Any, section: BalanceSection, comp: Any, out: Path,
            plot_pareto: Callable[..., Any], save: Callable[..., Any], plt: Any,
            console: Any) -> None:
    from linkwork.balancing import rms
    from linkwork.balancing.optimal import pareto_set

    p = pareto_set(mech, links=section.links, static_radii=section.radii, n=min(section.n, 180))
    c = comp.cycle
    pts = {"unbalanced": p.unbalanced[:2], "static": p.static[:2],
           "paper 001 (moved axis)": (rms(c.phi1, c.F1), rms(c.phi1, c.dM3))}
    fig, ax = plt.subplots(figsize=(7, 5))
    plot_pareto(p.force_rms, p.moment_rms, p.torque_fluct, ax=ax, points=pts,
                dominated=p.dominated)
    save(fig, out / "balancing_pareto.png")
    (out / "balance_pareto.json").write_text(json.dumps({
        "weights": p.weights.tolist(), "force_rms": p.force_rms.tolist(),
        "moment_rms": p.moment_rms.tolist(), "torque_fluct": p.torque_fluct.tolist(),
        "dominated": p.dominated.tolist(), "unbalanced": list(p.unbalanced),
        "static": list(p.static)}, indent=1))
    console.print(f"Pareto set: {int((~p.dominated).sum())} non-dominated of {len(p.designs)}")


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
        from linkwork.cli._console import console as make_console

        mech, section, doc = load_balance_file(file)
        output_dir(out)  # before the work: an unusable --out must not cost an optimisation
        if angles is not None:
            from linkwork.cli.analyze import parse_angles_deg

            vals = parse_angles_deg(angles)
            section = section.model_copy(update={"angles": vals})
        console = make_console()
        analysis = getattr(doc, "analysis", None)
        gravity = getattr(analysis, "gravity", None)
        loads = doc.loads if getattr(doc, "load", None) else None
        if loads is not None:
            console.print("note: the file's external loads enter the driving torque and the "
                          "bearing reactions, not the shaking-moment table (inertia forces)")
        try:
            run_balance(mech, section, out, console, pareto=pareto, gravity=gravity,
                        loads=loads)
        except AssemblyError as exc:
            raise AssemblyError(f"balancing works on a full turn of the crank (the file's "
                                f"[analysis] range is not used): {exc}") from None
