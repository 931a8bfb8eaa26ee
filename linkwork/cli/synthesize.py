"""``linkwork synthesize function|motion|path TASK.toml``: dimensional synthesis of linkages.

Reads a ``synthesis`` task file (:mod:`linkwork.io.synthesis`), runs the task's study
(:mod:`linkwork.studies.synthesis`) with a progress bar on a terminal, prints the ranked
designs and writes into ``--out``: ``synthesis.csv``/``.json`` (one row per design), a planar
file per design (``design_1.toml`` ...) that ``linkwork analyze`` reads, and the plots
(``path.png`` the coupler curves against the targets, ``pareto.png`` accuracy against dynamics
when judged by forces, ``function.png`` the structural errors, ``motion.png`` the poses,
Burmester points and four-bars).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import output_run, reach_scheduler
from linkwork.cli._console import console as make_console
from linkwork.cli._format import fmt
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.synthesis import SynthesisFile
from linkwork.results import write_json
from linkwork.studies import synthesis as study_synthesis
from linkwork.studies.synthesis import SynthesisStudy
from linkwork.sweep import check_client, rich_progress

__all__ = ["register", "render", "sub"]

sub = typer.Typer(name="synthesize", no_args_is_help=True, add_completion=False,
                  help="Dimensional synthesis of planar linkages: function, motion or path "
                       "generation from a task file.")


def _mm(x: float) -> str:
    return fmt(float(x) * 1e3)


def _deg(x: float) -> str:
    return fmt(math.degrees(float(x)))


def _path_table(study: SynthesisStudy) -> Table:
    res = study.result
    rej = ", ".join(f"{v} {k}" for k, v in res.rejected.items() if v) or "none"
    t = Table(title=escape(
        f"{study.doc.name}: {len(res.designs)} defect-free four-bars of {res.n_evaluated} "
        f"candidates, {res.n_refined} refined ({res.time:.3g} s; rejected: {rej})"))
    cols = ["#", "error [mm²]", "max dev. [mm]", "r1 [mm]", "r2 [mm]", "r3 [mm]", "r4 [mm]",
            "rcx [mm]", "rcy [mm]", "x0 [mm]", "y0 [mm]", "θ0 [deg]", "branch", "μmin [deg]"]
    forces = any(d.forces for d in res.designs)
    if forces:
        cols += ["peak Q [N·m]", "peak bearing [N]", "RMS shaking [N]"]
    for c in cols:
        t.add_column(escape(c), justify="right")
    for i, d in enumerate(res.designs):
        p = d.params
        row = [str(i + 1), fmt(d.error * 1e6), _mm(d.checks.get("max_deviation", math.nan)),
               *(_mm(p[k]) for k in ("r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0")),
               _deg(p["theta0"]), f"{d.branch:+d}",
               _deg(d.checks.get("min_transmission_angle", math.nan))]
        if forces:
            row += [fmt(d.forces.get(k, math.nan)) for k in
                    ("peak_torque", "peak_bearing", "rms_shaking")]
        t.add_row(*row)
    return t


def _sixbar_table(study: SynthesisStudy) -> Table:
    res = study.result
    rej = ", ".join(f"{v} {k}" for k, v in res.rejected.items() if v) or "none"
    t = Table(title=escape(
        f"{study.doc.name}: {len(res.designs)} defect-free {res.kind} six-bars of "
        f"{res.n_evaluated} candidates, {res.n_refined} refined ({res.time:.3g} s; "
        f"rejected: {rej})"))
    lengths = ("r1", "r2", "r3", "r4", "x0", "y0", "cx", "cy", "r5", "r6", "x6", "y6", "px",
               "py")
    cols = ["#", "error [mm²]", "max dev. [mm]", *(f"{k} [mm]" for k in lengths), "θ0 [deg]",
            "branches B, D", "μmin [deg]"]
    for c in cols:
        t.add_column(escape(c), justify="right")
    for i, d in enumerate(res.designs):
        p = d.params
        t.add_row(str(i + 1), fmt(d.error * 1e6), _mm(d.checks.get("max_deviation", math.nan)),
                  *(_mm(p[k]) for k in lengths), _deg(p["theta0"]),
                  f"{d.branches[0]:+d}, {d.branches[1]:+d}",
                  _deg(d.checks.get("min_transmission_angle", math.nan)))
    return t


def _function_table(study: SynthesisStudy) -> Table:
    res = study.result
    four = res.kind == "fourbar"
    t = Table(title=escape(f"{study.doc.name}: {len(res.designs)} {res.kind.replace('_', '-')} "
                           "function generators (structural error over the whole range)"))
    names = ("a", "b", "c", "d") if four else ("L1", "L2", "e", "Y0")
    cols = ["#", "method", *(f"{n} [mm]" for n in names), "branch",
            "max error [deg]" if four else "max error [mm]",
            "RMS error [deg]" if four else "RMS error [mm]"]
    for c in cols:
        t.add_column(escape(c), justify="right" if c != "method" else "left")
    for i, d in enumerate(res.designs):
        conv = math.degrees if four else (lambda v: v * 1e3)
        t.add_row(str(i + 1), escape(d.method), *(_mm(d.params[n]) for n in names),
                  f"{d.branch:+d}", fmt(conv(d.max_error)), fmt(conv(d.rms_error)))
    return t


def _motion_table(study: SynthesisStudy) -> Table:
    res = study.result
    rej = ", ".join(f"{v} {k}" for k, v in res.rejected.items() if v) or "none"
    t = Table(title=escape(f"{study.doc.name}: {len(res.designs)} four-bars through "
                           f"{len(res.poses)} poses from {res.n_dyads} dyads, {res.n_pairs} "
                           f"pairs checked (rejected: {rej})"))
    cols = ["#", "O2 x [mm]", "O2 y [mm]", "O4 x [mm]", "O4 y [mm]", "r1 [mm]", "r2 [mm]",
            "r3 [mm]", "r4 [mm]", "μmin [deg]", "pose error [mm]"]
    for c in cols:
        t.add_column(escape(c), justify="right")
    for i, d in enumerate(res.designs):
        p = d.fourbar.params
        t.add_row(str(i + 1), _mm(d.c1[0]), _mm(d.c1[1]), _mm(d.c2[0]), _mm(d.c2[1]),
                  *(_mm(p[k]) for k in ("r1", "r2", "r3", "r4")),
                  _deg(d.fourbar.checks.get("min_transmission_angle", math.nan)),
                  fmt(d.pose_error * 1e3))
    return t


def render(study: SynthesisStudy, *, out: Path, console: Any) -> list[Path]:
    """Print the ranked designs of ``study`` and write its table, design files and plots into
    ``out``; returns the files written."""
    from linkwork.plot import save

    res = study.result
    six = study.kind == "path" and study.doc.path is not None and \
        study.doc.path.linkage != "fourbar"
    table = {"path": _sixbar_table if six else _path_table, "function": _function_table,
             "motion": _motion_table}[study.kind](study)
    print_table(console, table)
    written = [res.to_csv(out / "synthesis.csv"), write_json(out / "synthesis.json",
                                                              study.to_dict())]
    for i, d in enumerate(res.designs):
        written.append(d.to_toml(out / f"design_{i + 1}.toml",
                                 name=f"{study.doc.name}: design {i + 1}"))
    fig = res.plot(n_designs=min(3, len(res.designs))) if study.kind != "function" \
        else res.plot()
    written.append(save(fig.figure, out / f"{study.kind}.png"))
    if study.kind == "path" and res.objective != "sum_squares":
        from linkwork.plot.synthesis import pareto_figure

        written.append(save(pareto_figure(res, name=study.doc.name).figure,
                            out / "pareto.png"))
    console.print(escape(f"written: {out}/" + ", ".join(p.name for p in written)),
                  highlight=False)
    return written


def _run(kind: str, file: Path, out: Path, scheduler: str | None, seed: int | None,
         candidates: int | None) -> None:
    check_client(scheduler, option="--scheduler")
    doc = io.load(file)
    if not isinstance(doc, SynthesisFile):
        raise FileFormatError(str(file), "type", f"is {doc.type!r}, expected 'synthesis'")
    if getattr(doc, kind) is None:
        have = [k for k in study_synthesis.KINDS if getattr(doc, k) is not None]
        raise FileFormatError(str(file), f"[{kind}]", f"missing: `linkwork synthesize {kind}` "
                              f"needs it (the file has {', '.join(f'[{k}]' for k in have)})")
    if candidates is not None and not 16 <= candidates <= 2**22:
        raise ParameterError("--candidates", candidates, "must be from 16 to 4194304 (2^22)")
    reach_scheduler(scheduler)
    console = make_console()
    err = make_console(stderr=True)
    with output_run(out, command=f"synthesize {kind}", file=file):
        kw: dict[str, Any] = {"client": scheduler, "seed": seed, "n_candidates": candidates}
        if err.is_terminal and kind == "path":
            with rich_progress("screening candidates", console=err, transient=True) as bar:
                study = study_synthesis.run(doc, kind, progress=bar, **kw)
        else:
            study = study_synthesis.run(doc, kind, progress=False, **kw)
        render(study, out=out, console=console)


_OUT = Annotated[Path, typer.Option("--out", "-o", help="output folder")]
_SCHED = Annotated[str | None, typer.Option(help="dask scheduler address (path; optional)")]
_SEED = Annotated[int | None, typer.Option(help="seed of the search (default: the file's)")]
_CAND = Annotated[int | None, typer.Option(help="candidates of the global search (path)")]
_FILE = Annotated[Path, typer.Argument(help="synthesis task file (TOML)")]


@sub.command("path")
def path_cmd(file: _FILE, out: _OUT = Path("linkwork-output"), scheduler: _SCHED = None,
             seed: _SEED = None, candidates: _CAND = None) -> None:
    """Four-bars (or Watt / Stephenson six-bars: [path] linkage) whose coupler point passes
    through the [path] targets, defect-free, ranked."""
    _run("path", file, out, scheduler, seed, candidates)


@sub.command("function")
def function_cmd(file: _FILE, out: _OUT = Path("linkwork-output")) -> None:
    """Four-bars or crank-sliders generating the [function] (precision points, least squares)."""
    _run("function", file, out, None, None, None)


@sub.command("motion")
def motion_cmd(file: _FILE, out: _OUT = Path("linkwork-output")) -> None:
    """Four-bars guiding the coupler through the [motion] poses (Burmester), in order."""
    _run("motion", file, out, None, None, None)


def register(app: typer.Typer) -> None:
    """Add the ``synthesize`` command group to ``app``."""
    app.add_typer(sub, name="synthesize")
