"""``linkwork analyze FILE.toml``: analyse a mechanism file over a cycle.

The file's ``type`` picks the analyser from :data:`ANALYZERS` (file type -> ``"module:function"``).
An analyser is called as ``fn(doc, out=Path, angles=ndarray [rad], console=rich Console)``: it
prints a table of the main quantities at ``angles`` and writes the full cycle (CSV, JSON) and its
plots (PNG) into ``out``. A planar file with a linear driver gets its ``--angles`` as slide
positions [m] (typed in mm), or None without the option (the analyser spaces the table over the
file's range).
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from linkwork import files
from linkwork.errors import FileFormatError, ParameterError

#: Crank angles of the table when ``--angles`` is not given [deg].
DEFAULT_ANGLES = "0,30,60,90,120,150,180,210,240,270,300,330"

#: Tables of a ``planar`` file read by other commands (table -> command); each command
#: validates its own and leaves the others alone, so that one file serves them all.
COMMAND_TABLES: dict[str, str] = {"balance": "linkwork balance", "spatial": "linkwork reactions"}

#: File type -> "module:function" of its analyser.
ANALYZERS: dict[str, str] = {
    "sine_press": "linkwork.cli._sine_press:analyze_sine_press",
    "planar": "linkwork.cli._planar:analyze_planar",
    "swashplate": "linkwork.cli.swashplate:analyze_swashplate",
}


def parse_angles_deg(text: str, *, angles: bool = True) -> list[float]:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``); with
    ``angles=False`` any finite numbers (a linear driver's slide positions in mm)."""
    try:
        vals = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        limit = "must be comma-separated numbers in degrees"
        raise ParameterError("--angles", text, limit) from None
    if not vals:
        raise ParameterError("--angles", text, "must list at least one angle")
    bad = [v for v in vals if not np.isfinite(v)]
    if bad:
        raise ParameterError("--angles", bad[0], "must be finite numbers in degrees")
    if angles:
        from linkwork.planar.file import MAX_ANGLE

        lim = math.degrees(MAX_ANGLE)
        far = [v for v in vals if abs(v) > lim]  # -1e300 was printed as a 300-digit angle
        if far:
            raise ParameterError("--angles", f"{far[0]:g}", f"must lie within +-{lim:.6g} deg "
                                 f"(+-{MAX_ANGLE:g} rad): beyond it the float spacing of "
                                 "angles exceeds 1e-10 rad")
    return vals


def parse_angles(text: str) -> np.ndarray:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``) to radians."""
    return np.radians(np.array(parse_angles_deg(text)))


def output_dir(out: Path) -> Path:
    """Create the output folder ``--out`` (with parents), or a ParameterError naming it: an
    existing file of that name or a folder that cannot be created (permissions, read-only
    disk) was "[Errno 17] File exists: 'README.md'" without saying which option."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise ParameterError("--out", str(out), "must be a folder; a file of that name "
                             "exists") from None
    except OSError as exc:
        raise ParameterError("--out", str(out), f"cannot be created as a folder "
                             f"({exc.strerror or exc})") from None
    return out


def without_command_tables(raw: dict[str, Any], keep: str = "") -> dict[str, Any]:
    """A planar file's data without the tables of other commands (:data:`COMMAND_TABLES`),
    except ``keep``."""
    return {k: v for k, v in raw.items() if k == keep or k not in COMMAND_TABLES}


def _resolve(spec: str) -> Callable[..., Any]:
    mod, fn = spec.split(":")
    return getattr(importlib.import_module(mod), fn)


def register(app: typer.Typer) -> None:
    """Add the ``analyze`` command to ``app``."""

    @app.command()
    def analyze(
        file: Annotated[Path, typer.Argument(help="mechanism file (TOML)")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
        angles: Annotated[str | None, typer.Option(
            help="table positions, comma-separated: crank angles in deg (slide positions in mm "
                 f"for a linear driver) [default: {DEFAULT_ANGLES}; a linear driver: 12 "
                 "positions over the file's \\[analysis] range]")] = None,
    ) -> None:
        """Analyse a mechanism over a cycle: table, CSV/JSON and plots in an output folder."""
        from linkwork.cli._console import console as make_console

        raw = files.read_toml(file)
        kind = raw.get("type")
        if kind == "planar" and COMMAND_TABLES.keys() & raw.keys():
            doc = files.validate(file, without_command_tables(raw), files.schemas()["planar"])
        else:
            doc = files.load(file)
        if kind not in ANALYZERS:
            raise FileFormatError(str(file), "type", f"type {kind!r} cannot be analysed; "
                                  f"analysable: {sorted(ANALYZERS)}")
        if getattr(getattr(doc, "driver", None), "type", None) == "linear":
            # a planar file driven by a prismatic joint: positions in mm, as in `reactions`
            table = None if angles is None else np.array(
                parse_angles_deg(angles, angles=False)) * 1e-3
        else:
            table = parse_angles(DEFAULT_ANGLES if angles is None else angles)
        output_dir(out)
        _resolve(ANALYZERS[kind])(doc, out=out, angles=table, console=make_console())
