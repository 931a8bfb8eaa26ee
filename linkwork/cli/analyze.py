"""``linkwork analyze FILE.toml``: analyse a mechanism file over a cycle.

The file's class (:data:`linkwork.io.FILE_TYPES`) picks the analyser from :data:`ANALYZERS`
(file class -> function). An analyser is called as ``fn(doc, out=Path, angles=ndarray [rad],
console=rich Console)``: it runs the file type's study (:mod:`linkwork.studies`) and
prints a table of the main quantities at ``angles`` and writes the full cycle (CSV, JSON) and its
plots (PNG) into ``out``. A planar file with a linear driver gets its ``--angles`` as slide
positions [m] (typed in mm), or None without the option (the analyser spaces the table over the
file's range).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

from linkwork import io
from linkwork.cli._args import (
    load_errors,
    output_dir,
    output_run,
    parse_angles,
    parse_angles_deg,
    table_positions,
)
from linkwork.cli._console import console as make_console
from linkwork.cli._planar import analyze_planar
from linkwork.cli._sine_press import analyze_sine_press
from linkwork.cli.swashplate import analyze_swashplate
from linkwork.errors import FileFormatError

__all__ = ["ANALYZERS", "DEFAULT_ANGLES", "output_dir", "parse_angles", "parse_angles_deg",
           "register"]

#: Crank angles of the table when ``--angles`` is not given [deg].
DEFAULT_ANGLES = "0,30,60,90,120,150,180,210,240,270,300,330"

#: Optional sections of a ``planar`` file that other commands use (section -> command); the
#: file is validated once, with them, by every command.
COMMAND_TABLES: dict[str, str] = {"balance": "linkwork balance", "spatial": "linkwork reactions",
                                  "drive": "linkwork dynamics"}


def without_command_tables(raw: dict[str, Any], keep: str = "") -> dict[str, Any]:
    """A planar file's data without the sections of other commands (:data:`COMMAND_TABLES`),
    except ``keep`` (deprecated: :class:`~linkwork.io.planar.PlanarFile` reads them all)."""
    return {k: v for k, v in raw.items() if k == keep or k not in COMMAND_TABLES}


def synthesis_task(doc: io.SynthesisFile, **_: Any) -> None:
    """A synthesis task is not a mechanism: say which command runs it."""
    kinds = [k for k in ("function", "motion", "path") if getattr(doc, k) is not None]
    raise FileFormatError(doc.name, "type", "'synthesis' is a task, not a mechanism: run "
                          + " or ".join(f"`linkwork synthesize {k} FILE`" for k in kinds)
                          + "; analyse the design files it writes")


#: File class -> its analyser.
ANALYZERS: dict[type, Callable[..., Any]] = {
    io.PlanarFile: analyze_planar,
    io.SinePressFile: analyze_sine_press,
    io.SwashplateFile: analyze_swashplate,
    io.SynthesisFile: synthesis_task,
}


def register(app: typer.Typer) -> None:
    """Add the ``analyze`` command to ``app``."""

    @app.command()
    def analyze(
        file: Annotated[Path, typer.Argument(help="mechanism file (TOML)")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
        angles: Annotated[str | None, typer.Option(
            help="table positions, comma-separated: crank angles in deg (slide positions in mm "
                 f"for a linear driver) [default: {DEFAULT_ANGLES}; a planar file: every 30 "
                 "deg of its \\[analysis] range, a linear driver 12 positions over it]")] = None,
    ) -> None:
        """Analyse a mechanism over a cycle: table, CSV/JSON and plots in an output folder."""
        doc = io.load(file)
        analyzers = ANALYZERS
        if type(doc) not in analyzers:
            kind = getattr(doc, "type", None)
            known = sorted(k for k, c in io.FILE_TYPES.items() if c in analyzers)
            raise FileFormatError(str(file), "type", f"type {kind!r} cannot be analysed; "
                                  f"analysable: {known}")
        if isinstance(doc, io.PlanarFile):
            # None: the positions every command tables (studies.planar.default_table_positions)
            table = None if angles is None else table_positions(doc, angles)
            if len(doc.drivers) > 1:  # one driver's long cycle goes chunk by chunk
                doc.check_whole_cycle(file, "`linkwork analyze` of several drivers")
        else:
            table = parse_angles(DEFAULT_ANGLES if angles is None else angles)
        if isinstance(doc, io.SynthesisFile):  # before the output folder is touched
            synthesis_task(doc)
        with output_run(out, command="analyze", file=file), load_errors(file, doc):
            analyzers[type(doc)](doc, out=out, angles=table, console=make_console())
