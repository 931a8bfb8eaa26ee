"""``linkwork reactions FILE.toml``: spatial joint reactions with redundant constraints.

The file is a ``planar`` mechanism file (the engine's format) with an optional ``[spatial]``
table (joint axis lengths and heights, stiffnesses, deviations, out-of-plane loads, tolerances;
see :mod:`linkwork.redundancy.spec`). The command prints the structural count (Somov-Malyshev,
redundant constraints q), a table of every reaction component per joint at the chosen driver
positions and their peaks over the cycle, and writes CSV/JSON and plots into ``--out``;
``--tolerance-study N`` adds a Monte-Carlo study of the peaks with a progress bar.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from linkwork import files
from linkwork.cli.analyze import output_dir
from linkwork.errors import AssemblyError, FileFormatError, ParameterError

__all__ = ["load_problem", "register", "run"]


def load_problem(path: Path) -> tuple[Any, dict[str, Any], Any]:
    """Read a mechanism file: (mechanism, analysis keywords of :func:`run`, spatial spec).

    The mechanism part is validated by the engine's ``planar`` schema (without the ``spatial``
    table), the ``spatial`` table by :func:`linkwork.redundancy.spec.read_spatial`. The
    keywords are ``cycle`` (the file's driver positions), ``gravity`` and ``loads`` (a function
    of the driver positions: loads may act on part of the cycle only).
    """
    from linkwork.redundancy.spec import read_spatial

    raw = files.read_toml(path)
    spatial = read_spatial(path, raw)
    kind = raw.get("type")
    known = files.schemas()
    if kind != "planar" or "planar" not in known:
        raise FileFormatError(str(path), "type", f"must be 'planar' (a mechanism of the planar "
                              f"engine) for 'linkwork reactions'; got {kind!r}")
    from linkwork.cli.analyze import without_command_tables

    data = without_command_tables(raw)  # [spatial] is read above, [balance] by `balance`
    doc = files.validate(path, data, known["planar"])
    gravity = doc.analysis.gravity
    kwargs: dict[str, Any] = {"cycle": doc.positions(), "loads": doc.loads,
                              "gravity": None if gravity is None else tuple(gravity)}
    mech = doc.mechanism()
    _check_names(path, mech, spatial)
    return mech, kwargs, spatial


def _check_names(path: Path, mech: Any, spec: Any) -> None:
    """Every joint and body the ``[spatial]`` table names exists in the mechanism.

    Raises FileFormatError naming the file, the dotted key, the unknown name and the known ones
    (the model layer would name only its own parameter, e.g. ``joints = Z``).
    """
    joints = {j.name: j for j in mech.joints}
    moving = [b.name for b in mech.bodies]

    def known_joint(key: str, name: str) -> Any:
        if name not in joints:
            raise FileFormatError(str(path), key, f"no joint {name!r}; known: {list(joints)}")
        return joints[name]

    for name in spec.joints:
        known_joint(f"spatial.joints.{name}", name)
    for key, body in [*((f"spatial.heights.{b}", b) for b in spec.heights),
                      *((f"spatial.out_of_plane.{i}.body", o.body)
                        for i, o in enumerate(spec.out_of_plane))]:
        if body not in moving:
            raise FileFormatError(str(path), key, f"no moving body {body!r}; known: {moving}")
    for table, items in (("deviation", spec.deviation), ("tolerance", spec.tolerance)):
        for i, item in enumerate(items):
            j = known_joint(f"spatial.{table}.{i}.joint", item.joint)
            if item.body not in (j.a, j.b):
                raise FileFormatError(str(path), f"spatial.{table}.{i}.body",
                                      f"{item.body!r} is not a body of joint {item.joint!r}: "
                                      f"must be {j.a!r} or {j.b!r}")


def _model_inputs(mech: Any, spec: Any) -> dict[str, Any]:
    from linkwork.redundancy import Deviation, OutOfPlaneLoad

    return {
        "joints": spec.joint_kwargs(),
        "default": spec.default_kwargs(),
        "heights": dict(spec.heights),
        "out_of_plane": [OutOfPlaneLoad(o.body, o.fz, o.mx, o.my) for o in spec.out_of_plane],
        "deviations": [Deviation(d.joint, d.body, d.dx, d.dy, d.dz, d.tx, d.ty, d.tz)
                       for d in spec.deviation],
    }


def _fmt(v: float) -> str:
    return f"{v:.4g}"


def run(mech: Any, spec: Any, *, out: Path, angles: np.ndarray, console: Any,
        cycle: np.ndarray | None = None, gravity: Any = None, loads: Any = (),
        method: str = "force",
        tolerance_study: int = 0, seed: int = 0, scheduler: str | None = None,
        chunk_size: int = 2000, plots: bool = True) -> dict[str, Any]:
    """Analyse ``mech`` with the spatial data ``spec`` and report; return what was computed.

    Parameters
    ----------
    mech : linkwork.planar.Mechanism
    spec : linkwork.redundancy.spec.SpatialSpec
    out : Path
        Output folder (created).
    angles : ndarray
        Driver positions for the table [rad, or m for a linear driver].
    console : rich.console.Console
    cycle : ndarray, optional
        Driver positions of the cycle; default ``spec.positions`` (or 360) over one turn;
        ``spec.positions``, when set, resamples the cycle's range.
    gravity : (gx, gy), optional
        Gravity [m/s^2].
    loads : sequence or callable
        External loads of the engine (PointForce, BodyTorque), or a function of the driver
        positions returning them.
    method : {"force", "displacement"}
    tolerance_study : int
        Number of Monte-Carlo samples (0: none).
    seed, scheduler, chunk_size
        For the tolerance study (``scheduler``: a dask.distributed address).
    plots : bool
        Write PNG figures.
    """
    from rich.table import Table

    from linkwork.planar import kinematics
    from linkwork.redundancy import (
        Tolerance,
        body_wrenches,
        count_redundancy,
        deviation_array,
        geometry,
        spatial_model,
        spatial_reactions,
    )
    from linkwork.redundancy import tolerance_study as mc

    output_dir(out)
    inputs = _model_inputs(mech, spec)
    if cycle is None:
        cycle = np.linspace(0.0, 2 * np.pi, spec.positions or 360, endpoint=False)
    elif spec.positions:
        cycle = np.linspace(float(cycle[0]), float(cycle[-1]), spec.positions)
    cycle = np.asarray(cycle, dtype=float)

    def loads_at(phi: np.ndarray) -> Any:
        return list(loads(phi)) if callable(loads) else list(loads)

    res = spatial_reactions(mech, cycle, method=method, gravity=gravity, loads=loads_at(cycle),
                            **inputs)
    try:
        at = spatial_reactions(mech, angles, method=method, gravity=gravity,
                               loads=loads_at(np.asarray(angles, dtype=float)), **inputs)
    except AssemblyError as exc:
        from linkwork.cli._planar import table_positions_error

        raise table_positions_error(exc, angles, mech.driver.kind == "linear") from None
    model = spatial_model(mech, inputs["joints"], inputs["default"])
    kin = kinematics(mech, cycle)
    geom = geometry(mech, kin)
    count = count_redundancy(model, geom, position=len(cycle) // 7)
    console.print(f"[bold]structure in space[/bold]: {count.summary()}")
    linear = mech.driver.kind == "linear"  # positions are slides [m], Q a force [N]
    q_name, q_unit = ("driving force", "N") if linear else ("driving torque", "N·m")

    for k, phi in enumerate(angles):
        where = f"s1 = {phi * 1e3:.4g} mm" if linear else f"φ1 = {np.degrees(phi):.4g} deg"
        t = Table(title=f"reactions at {where} (by body a on body b, at the joint centre)")
        for col in ("joint", "fx [N]", "fy [N]", "fz [N]", "mx [N·m]", "my [N·m]",
                    "mz [N·m]"):
            t.add_column(col, justify="right")
        comp = at.components()
        for j, name in enumerate(at.joints):
            t.add_row(name, *(_fmt(comp[j, i, k]) for i in range(6)))
        t.caption = f"{q_name} Q = {_fmt(at.Q[k])} {q_unit}"
        console.print(t)
    peaks = res.peaks()
    t = Table(title=f"peaks over the cycle ({len(cycle)} positions)")
    for col in ("joint", "|fx| [N]", "|fy| [N]", "|fz| [N]", "|mx| [N·m]", "|my| [N·m]",
                "bending [N·m]"):
        t.add_column(col, justify="right")
    for name in res.joints:
        p = peaks[name]
        t.add_row(name, *(_fmt(p[c]) for c in ("fx", "fy", "fz", "mx", "my", "bending")))
    t.caption = f"peak |Q| = {_fmt(peaks['driver']['Q'])} {q_unit}"
    console.print(t)

    written = [res.to_csv(out / "reactions.csv"), res.to_json(out / "reactions.json")]
    (out / "reactions_peaks.json").write_text(json.dumps(
        {"units": {"f*": "N", "m*": "N*m", "bending": "N*m", "Q": res.units["Q"]},
         "peaks": peaks,
         "redundant_constraints": count.redundant,
         "mobility_somov_malyshev": count.mobility_formula, "mobility": count.mobility},
        indent=1))
    written.append(out / "reactions_peaks.json")
    if plots:
        from linkwork.plot import save
        from linkwork.plot.redundancy import plot_bending

        fig = plot_bending(res)["axes"].ravel()[0].figure
        written.append(save(fig, out / "reactions_bending.png"))

    study = None
    if tolerance_study:
        from linkwork.sweep import rich_progress

        if not spec.tolerance:
            raise ParameterError("--tolerance-study", tolerance_study,
                                 "needs at least one [[spatial.tolerance]] in the file")
        tols = []
        for tspec in spec.tolerance:
            jt = next((j for j in model.joints if j.name == tspec.joint), None)
            if jt is None:
                raise ParameterError("spatial.tolerance.joint", tspec.joint,
                                     f"no such joint; known: {[j.name for j in model.joints]}")
            body = "ground" if tspec.body == mech.frame.name else tspec.body
            if body not in (jt.body_a, jt.body_b):
                raise ParameterError(f"spatial.tolerance {tspec.joint}.body", tspec.body,
                                     "must be one of the joint's bodies")
            tols.append(Tolerance(tspec.joint, "a" if body == jt.body_a else "b",
                                  tspec.component, tspec.limit, tspec.distribution, tspec.mean))
        w = body_wrenches(mech, kin, gravity=gravity, loads=loads_at(cycle),
                          heights=inputs["heights"], out_of_plane=inputs["out_of_plane"])
        # systematic deviations of the file are added as fixed means
        fixed = deviation_array(model, inputs["deviations"], mech.frame.name)
        for j, jt in enumerate(model.joints):
            for side in (0, 1):
                for c, cname in enumerate(("dx", "dy", "dz", "tx", "ty", "tz")):
                    if fixed[j, side, c] != 0.0:
                        tols.append(Tolerance(jt.name, "ab"[side], cname, 0.0, "uniform",
                                              float(fixed[j, side, c])))
        with rich_progress("tolerance study", console=console) as progress:
            study = mc(model, geom, w, tols, tolerance_study, seed=seed, chunk_size=chunk_size,
                       client=scheduler, progress=progress)
        pct = study.percentiles((50.0, 95.0, 99.0))
        t = Table(title=f"tolerance study: peaks over the cycle, N = {tolerance_study}")
        # the samples are drawn around the file's systematic deviations: show their peak too
        sysdev = bool(inputs["deviations"])
        cols = ["joint", "quantity", "no deviation", *(["file's deviations"] if sysdev else []),
                "p50", "p95", "p99"]
        for col in cols:
            t.add_column(col, justify="right")
        for name in study.joints:
            for qty in ("fz", "bending"):
                row = pct[name][qty]
                mid = [_fmt(peaks[name][qty])] if sysdev else []
                t.add_row(name, qty, _fmt(row["nominal"]), *mid,
                          *(_fmt(row[k]) for k in ("p50", "p95", "p99")))
        console.print(t)
        written += [study.to_json(out / "tolerance.json"),
                    study.to_csv(out / "tolerance_samples.csv")]
        if plots:
            from linkwork.plot import pyplot, save
            from linkwork.plot.redundancy import plot_peak_histogram

            for name in study.joints:
                fig, ax = pyplot().subplots(figsize=(7, 4))
                ref = {"file's deviations": peaks[name]["bending"]} if inputs[
                    "deviations"] else None
                plot_peak_histogram(study, name, "bending", ax=ax, reference=ref)
                written.append(save(fig, out / f"tolerance_bending_{name}.png"))
    console.print("written: " + ", ".join(str(p) for p in written))
    return {"reactions": res, "table": at, "count": count, "study": study, "files": written}


def _parse_angles(text: str) -> np.ndarray:
    from linkwork.cli.analyze import parse_angles

    return parse_angles(text)


def register(app: typer.Typer) -> None:
    """Add the ``reactions`` command to ``app``."""

    @app.command()
    def reactions(
        file: Annotated[Path, typer.Argument(help="planar mechanism file (TOML) with an "
                                             "optional \\[spatial] table")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-reactions"),
        angles: Annotated[str, typer.Option(help="driver positions for the table, deg (mm for a "
                                            "linear driver), comma-separated")
                          ] = "0,90,180,270",
        method: Annotated[str, typer.Option(help="force or displacement")] = "force",
        tolerance_study: Annotated[int | None, typer.Option(
            "--tolerance-study", help="Monte-Carlo samples of the deviations (N >= 1)")] = None,
        seed: Annotated[int, typer.Option(help="random seed of the tolerance study")] = 0,
        scheduler: Annotated[str | None, typer.Option(
            help="dask.distributed scheduler address for the tolerance study")] = None,
        chunk_size: Annotated[int, typer.Option(
            help="samples per chunk (unit of work of a cluster and of the progress bar)")] = 2000,
        plots: Annotated[bool, typer.Option("--plots/--no-plots", help="write PNG figures")
                         ] = True,
    ) -> None:
        """Spatial joint reactions (axial forces, bending moments) with redundant constraints."""
        from linkwork.cli._console import console as make_console

        if method not in ("force", "displacement"):
            raise ParameterError("--method", method, "must be 'force' or 'displacement'")
        if tolerance_study is not None and tolerance_study < 1:
            raise ParameterError("--tolerance-study", tolerance_study,
                                 "must be a number of samples >= 1 (leave the option out for "
                                 "no study)")
        if chunk_size < 1:
            raise ParameterError("--chunk-size", chunk_size, "must be >= 1")
        if seed < 0:
            raise ParameterError("--seed", seed, "must be >= 0")
        mech, kwargs, spec = load_problem(file)
        table = _parse_angles(angles)
        if type(mech.driver).__name__ == "Linear":    # positions in mm for a linear driver
            table = np.degrees(table) * 1e-3
        run(mech, spec, out=out, angles=table, console=make_console(), **kwargs, method=method,
            tolerance_study=tolerance_study or 0, seed=seed, scheduler=scheduler,
            chunk_size=chunk_size, plots=plots)
