"""``linkwork reactions FILE.toml``: spatial joint reactions with redundant constraints.

The file is a ``planar`` mechanism file (the engine's format) with an optional ``[spatial]``
table (joint axis lengths and heights, stiffnesses, deviations, out-of-plane loads, tolerances;
see :mod:`linkwork.io.planar`). The command runs :func:`linkwork.studies.reactions.run` and
prints the structural count (Somov-Malyshev, redundant constraints q), a table of every reaction
component per joint at the chosen driver positions and their peaks over the cycle, and writes
CSV/JSON and plots into ``--out``; ``--tolerance-study N`` adds a Monte-Carlo study of the peaks
with a progress bar.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import (
    load_errors,
    output_dir,
    output_run,
    reach_scheduler,
    table_positions,
)
from linkwork.cli._console import console as make_console
from linkwork.cli._console import counting, steps
from linkwork.cli._format import fmt
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.planar import PlanarFile, SpatialSpec
from linkwork.io.toml import read_toml
from linkwork.planar import Mechanism
from linkwork.redundancy import ToleranceStudy
from linkwork.redundancy.tolerance import CHUNK_SAMPLES, check_samples
from linkwork.results import write_json
from linkwork.studies import reactions as study_reactions
from linkwork.studies.reactions import ReactionsStudy
from linkwork.sweep import check_client

__all__ = ["load_problem", "register", "render", "render_tolerance", "run"]

def _model_inputs(mech: Any, spec: SpatialSpec) -> dict[str, Any]:
    """Deprecated private name (tests reach it): :func:`linkwork.studies.reactions.
    model_inputs` of ``spec`` (``mech`` is not used)."""
    return study_reactions.model_inputs(spec)


def _load(path: Path) -> PlanarFile:
    kind = read_toml(path).get("type")
    if kind != "planar":
        raise FileFormatError(str(path), "type", f"must be 'planar' (a mechanism of the planar "
                              f"engine) for 'linkwork reactions'; got {kind!r}")
    doc: PlanarFile = io.load(path, types={"planar": io.PlanarFile})
    return doc


def load_problem(path: Path) -> tuple[Mechanism, dict[str, Any], SpatialSpec]:
    """Read a mechanism file: (mechanism, analysis keywords of :func:`run`, spatial spec).

    The keywords are ``cycle`` (the file's driver positions), ``gravity`` and ``loads`` (a
    function of the driver positions: loads may act on part of the cycle only).
    """
    doc = _load(path)
    gravity = doc.analysis.gravity
    kwargs: dict[str, Any] = {"cycle": doc.positions(), "loads": doc.loads,
                              "gravity": None if gravity is None else tuple(gravity)}
    return doc.mechanism(), kwargs, doc.spatial


def _fmt(v: float, scale: float = 0.0) -> str:
    """4 significant digits, round-off against ``scale`` as 0 (:func:`fmt`)."""
    return fmt(v, scale)


def _scales(study: ReactionsStudy) -> tuple[float, float]:
    """The round-off scales (force [N], moment [N·m]) of the reaction tables: the largest
    force and moment components (and driving forces or torques) over the cycle."""
    peaks = study.peaks
    joints = [v for k, v in peaks.items() if k != "driver"]
    force = max((p[c] for p in joints for c in ("fx", "fy", "fz")), default=0.0)
    moment = max((p[c] for p in joints for c in ("mx", "my", "mz", "bending")), default=0.0)
    for lin, q in zip(study.linear_drivers, _driver_peaks(study), strict=True):
        force, moment = (max(force, q), moment) if lin else (force, max(moment, q))
    return force, moment


def _driver_peaks(study: ReactionsStudy) -> list[float]:
    """Each driver's peak |Q| over the cycle, in driver order."""
    drv = study.peaks["driver"]
    if len(study.mechanism.drivers) == 1:
        return [drv["Q"]]
    return [drv[f"Q {d.joint}"] for d in study.mechanism.drivers]


def _driving(study: ReactionsStudy, values: list[float], f_n: float, f_nm: float,
             peak: bool = False) -> str:
    """The driving torques and forces ``values`` (one per driver) as a caption (``peak``: of
    their peaks, ``peak |Q O1| = ...``)."""
    drivers = study.mechanism.drivers
    out = []
    for d, lin, v in zip(drivers, study.linear_drivers, values, strict=True):
        what, unit, scale = (("driving force", "N", f_n) if lin
                             else ("driving torque", "N·m", f_nm))
        name = "Q" if len(drivers) == 1 else f"Q {d.joint}"
        head = f"peak |{name}|" if peak else f"{what} {name}"
        out.append(f"{head} = {_fmt(v, scale)} {unit}")
    return ", ".join(out)


def _where(study: ReactionsStudy, k: int) -> str:
    """Table position ``k``: the driver position (one driver), or every driver's position
    along the path (several)."""
    drivers = study.mechanism.drivers
    tphi = np.atleast_2d(study.table_positions)
    parts = []
    for i, (d, lin) in enumerate(zip(drivers, study.linear_drivers, strict=True)):
        name = ("s1" if lin else "φ1") + ("" if len(drivers) == 1 else f" {d.joint}")
        phi = float(tphi[i, k])
        parts.append(f"{name} = {fmt(phi * 1e3)} mm" if lin else
                     f"{name} = {fmt(np.degrees(phi))} deg")
    if len(drivers) == 1:
        return parts[0]
    return f"path position {k + 1}/{tphi.shape[1]}: {', '.join(parts)}"


def run(mech: Any, spec: Any, *, out: Path, angles: np.ndarray, console: Any,
        cycle: np.ndarray | None = None, gravity: Any = None, loads: Any = (),
        method: str = "force",
        tolerance_study: int = 0, seed: int = 0, scheduler: str | None = None,
        chunk_size: int = CHUNK_SAMPLES, plots: bool = True) -> dict[str, Any]:
    """Analyse ``mech`` with the spatial data ``spec`` and report; return what was computed.

    Parameters as :func:`linkwork.studies.reactions.solve` and
    :func:`~linkwork.studies.reactions.tolerance` (``tolerance_study``: the number of samples,
    0 for none); ``out`` the output folder (created), ``console`` a Rich console, ``plots``:
    write PNG figures.
    """
    output_dir(out)
    study = study_reactions.solve(mech, spec, angles=angles, cycle=cycle, gravity=gravity,
                                  loads=loads, method=method)
    tol, written = _report(study, out=out, console=console, plots=plots, n=tolerance_study,
                           seed=seed, scheduler=scheduler, chunk_size=chunk_size)
    return {"reactions": study.reactions, "table": study.table, "count": study.count,
            "study": tol, "files": written}


def _report(study: ReactionsStudy, *, out: Path, console: Any, plots: bool, n: int, seed: int,
            scheduler: str | None, chunk_size: int, mechanism: str | None = None
            ) -> tuple[ToleranceStudy | None, list[Path]]:
    """Render the study, run and render its tolerance study of ``n`` samples (0: none), list
    the files written; return (tolerance study or None, files)."""
    # the tolerances' errors (none in the file, a joint or body not of the model) come
    # before the first file is written
    tols = study_reactions.tolerances(study, n) if n else None
    written = render(study, out=out, console=console, plots=plots, mechanism=mechanism)
    tol = None
    if n:
        # on a terminal's stderr, erased when done (it was printed into stdout, a pipe too)
        with counting("tolerance study", console=make_console(stderr=True)) as progress:
            tol = study_reactions.tolerance(study, n, tols=tols, seed=seed, scheduler=scheduler,
                                            chunk_size=chunk_size, progress=progress)
        written += render_tolerance(study, tol, out=out, console=console, plots=plots,
                                    mechanism=mechanism)
    console.print(escape("written: " + ", ".join(str(p) for p in written)), highlight=False)
    return tol, written


def render(study: ReactionsStudy, *, out: Path, console: Any, plots: bool = True,
           mechanism: str | None = None) -> list[Path]:
    """Print a :class:`~linkwork.studies.reactions.ReactionsStudy` (count, a table per table
    position, the peaks) and write ``reactions.csv/.json``, ``reactions_peaks.json`` and the
    bending plot into ``out`` (``mechanism``: its name, on the plot); return the paths
    written."""
    console.print(f"[bold]structure in space[/bold]: {escape(study.count.summary())}",
                  highlight=False)
    lossy = [j.name for j in study.mechanism.joints if j.has_friction]
    if lossy:
        console.print(escape(f"note: the spatial reactions leave friction and mesh losses out "
                             f"(joints {', '.join(lossy)}): frictionless joints, the driving "
                             "loads those of a lossless mechanism"), highlight=False)
    at, res, peaks = study.table, study.reactions, study.peaks
    comp = at.components()
    f_n, f_nm = _scales(study)
    col_scale = (f_n, f_n, f_n, f_nm, f_nm, f_nm)
    tq = np.atleast_2d(at.Q)
    for k in range(np.atleast_2d(study.table_positions).shape[1]):
        t = Table(title=f"reactions at {_where(study, k)} (by body a on body b, at the joint "
                  "centre)")
        for col in ("joint", "fx [N]", "fy [N]", "fz [N]", "mx [N·m]", "my [N·m]",
                    "mz [N·m]"):
            t.add_column(col, justify="right")
        for j, name in enumerate(at.joints):
            t.add_row(escape(name), *(_fmt(comp[j, i, k], col_scale[i]) for i in range(6)))
        t.caption = _driving(study, [float(q) for q in tq[:, k]], f_n, f_nm)
        print_table(console, t)
    t = Table(title=f"peaks over the cycle ({study.cycle.shape[-1]} positions)")
    for col in ("joint", "|fx| [N]", "|fy| [N]", "|fz| [N]", "|mx| [N·m]", "|my| [N·m]",
                "bending [N·m]"):
        t.add_column(col, justify="right")
    for name in res.joints:
        p = peaks[name]
        t.add_row(escape(name), *(_fmt(p[c], sc) for c, sc in zip(
            ("fx", "fy", "fz", "mx", "my", "bending"), col_scale, strict=True)))
    t.caption = _driving(study, _driver_peaks(study), f_n, f_nm, peak=True)
    print_table(console, t)
    with steps(2 + plots, console=make_console(stderr=True)) as step:
        step("writing reactions.csv, reactions.json")
        written = [res.to_csv(out / "reactions.csv"), res.to_json(out / "reactions.json")]
        step("writing reactions_peaks.json")
        written.append(write_json(out / "reactions_peaks.json", study.peaks_dict()))
        if plots:
            from linkwork.plot import save
            from linkwork.plot.redundancy import plot_bending

            step("drawing reactions_bending.png")
            fig = plot_bending(res, name=mechanism)["axes"].ravel()[0].figure
            written.append(save(fig, out / "reactions_bending.png"))
    return written


def render_tolerance(study: ReactionsStudy, tol: ToleranceStudy, *, out: Path, console: Any,
                     plots: bool = True, mechanism: str | None = None) -> list[Path]:
    """Print the tolerance study's percentiles of the peaks and write its JSON, samples and
    histograms into ``out``; return the paths written."""
    peaks = study.peaks
    pct = tol.percentiles((50.0, 95.0, 99.0))
    t = Table(title=f"tolerance study: peaks over the cycle, N = {tol.n_samples}")
    # the samples are drawn around the file's systematic deviations: show their peak too
    sysdev = bool(study.inputs["deviations"])
    cols = ["joint", "quantity", "no deviation", *(["file's deviations"] if sysdev else []),
            "p50", "p95", "p99"]
    for col in cols:
        t.add_column(col, justify="right")
    f_n, f_nm = _scales(study)
    for name in tol.joints:
        for qty, sc in (("fz", f_n), ("bending", f_nm)):
            row = pct[name][qty]
            mid = [_fmt(peaks[name][qty], sc)] if sysdev else []
            t.add_row(escape(name), qty, _fmt(row["nominal"], sc), *mid,
                      *(_fmt(row[k], sc) for k in ("p50", "p95", "p99")))
    print_table(console, t)
    written = [tol.to_json(out / "tolerance.json"), tol.to_csv(out / "tolerance_samples.csv")]
    if plots:
        from linkwork.plot import pyplot, save
        from linkwork.plot.redundancy import plot_peak_histogram

        for joint in tol.joints:
            fig, ax = pyplot().subplots(figsize=(7, 4))
            ref = {"file's deviations": peaks[joint]["bending"]} if sysdev else None
            plot_peak_histogram(tol, joint, "bending", ax=ax, reference=ref, name=mechanism)
            written.append(save(fig, out / f"tolerance_bending_{joint}.png"))
    return written


def register(app: typer.Typer) -> None:
    """Add the ``reactions`` command to ``app``."""

    @app.command()
    def reactions(
        file: Annotated[Path, typer.Argument(help="planar mechanism file (TOML) with an "
                                             "optional \\[spatial] table")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
        angles: Annotated[str | None, typer.Option(
            help="driver positions for the table, deg (mm for a linear driver), comma-separated "
                 "[default: as every command: every 30 deg of the file's \\[analysis] range, "
                 "a linear driver 12 positions over it]")] = None,
        method: Annotated[str, typer.Option(help="force or displacement")] = "force",
        tolerance_study: Annotated[int | None, typer.Option(
            "--tolerance-study", help="Monte-Carlo samples of the deviations (N >= 1)")] = None,
        seed: Annotated[int, typer.Option(help="random seed of the tolerance study")] = 0,
        scheduler: Annotated[str | None, typer.Option(
            help="dask.distributed scheduler address for the tolerance study")] = None,
        chunk_size: Annotated[int, typer.Option(
            help="samples per chunk (unit of work of a cluster and of the progress bar)")
        ] = CHUNK_SAMPLES,
        plots: Annotated[bool, typer.Option("--plots/--no-plots", help="write PNG figures")
                         ] = True,
    ) -> None:
        """Spatial joint reactions (axial forces, bending moments) with redundant constraints."""
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
        check_client(scheduler, option="--scheduler")  # address and dask, before any work
        if tolerance_study:
            reach_scheduler(scheduler)  # the study is the only work that uses it
        doc = _load(file)
        doc.check_spatial_positions(file)  # the cycle's size, before any work
        if tolerance_study and doc.spatial.tolerance:  # its memory bound, before any work
            check_samples(tolerance_study, len(doc.mechanism().joints), doc.spatial.n_deviations(),
                          parameter="--tolerance-study")
        table = None if angles is None else table_positions(doc, angles)
        with output_run(out, command="reactions", file=file), load_errors(file, doc):
            n = doc.spatial.positions or doc.analysis.n
            with steps(1, console=make_console(stderr=True)) as step:
                step(f"solving the spatial reactions at {n} positions")
                study = study_reactions.run(doc, angles=table, method=method)
            console = make_console()
            rubbing = [j.name for j in doc.mechanism().joints if j.has_friction]
            if rubbing:  # said, not silently left out: Q differs from analyze's
                console.print(escape(
                    f"note: the spatial reactions are frictionless (paper 004's equations): "
                    f"the friction of joint{'s' * (len(rubbing) > 1)} {', '.join(rubbing)} is "
                    "not used here (linkwork analyze includes it)"), highlight=False)
            _report(study, out=out, console=console, plots=plots,
                    n=tolerance_study or 0, seed=seed, scheduler=scheduler,
                    chunk_size=chunk_size, mechanism=doc.name or None)
