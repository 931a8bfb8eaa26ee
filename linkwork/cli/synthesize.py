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

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import output_run, reach_scheduler
from linkwork.cli._console import console as make_console
from linkwork.cli._console import steps
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.synthesis import SynthesisFile
from linkwork.results import write_json
from linkwork.studies import synthesis as study_synthesis
from linkwork.studies.synthesis import SynthesisStudy, design_summary, design_table
from linkwork.sweep import check_client, rich_progress

__all__ = ["register", "render", "sub"]

sub = typer.Typer(name="synthesize", no_args_is_help=True, add_completion=False,
                  help="Dimensional synthesis of planar linkages: function, motion or path "
                       "generation from a task file.")


def _table(study: SynthesisStudy) -> Table:
    """The ranked designs (:func:`linkwork.studies.synthesis.design_table`) under a title of
    what the search did."""
    head, rows = design_table(study)
    t = Table(title=escape(f"{study.doc.name}: {design_summary(study)}"))
    for c in head:
        t.add_column(escape(c), justify="left" if c == "method" else "right")
    for row in rows:
        t.add_row(*(escape(v) for v in row))
    return t


def render(study: SynthesisStudy, *, out: Path, console: Any) -> list[Path]:
    """Print the ranked designs of ``study`` and write its table, design files and plots into
    ``out``; returns the files written."""
    from linkwork.plot import save

    res = study.result
    print_table(console, _table(study))
    pareto = study.kind == "path" and res.objective != "sum_squares"
    with steps(3 + pareto, console=make_console(stderr=True)) as step:
        step("writing synthesis.csv, synthesis.json")
        written = [res.to_csv(out / "synthesis.csv"), write_json(out / "synthesis.json",
                                                                  study.to_dict())]
        step(f"writing {len(res.designs)} design files")
        for i, d in enumerate(res.designs):
            written.append(d.to_toml(out / f"design_{i + 1}.toml",
                                     name=f"{study.doc.name}: design {i + 1}"))
        step(f"drawing {study.kind}.png")
        fig = res.plot(n_designs=min(3, len(res.designs))) if study.kind != "function" \
            else res.plot()
        written.append(save(fig.figure, out / f"{study.kind}.png"))
        if pareto:
            from linkwork.plot.synthesis import pareto_figure

            step("drawing pareto.png")
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
        else:  # the search's own bar is the path's screening; the rest in one step
            with steps(1, console=err) as step:
                step(f"{kind} synthesis")
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
