"""``linkwork report FILE.toml``: one self-contained HTML report of a mechanism file.

The report (:mod:`linkwork.report`) shows the mechanism drawn to scale and animated over the
cycle (play/pause, position slider, speed), the diagrams of the file type's study with a cursor
that follows the animation (a click on a diagram shows that position), the characteristics,
the input data with units and the conventions and errata that apply; it opens offline (scripts,
style and data inlined). ``--animate`` also writes the animation as a GIF (and an MP4 where
ffmpeg is installed). ``--path`` draws the path (coupler curve) of any point, ``--centres`` the
instant centres of velocity. A file that fails validation writes no report (one line, exit 2).
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from linkwork import io
from linkwork.cli._args import load_errors, output_run
from linkwork.cli._console import console as make_console
from linkwork.cli._console import steps
from linkwork.errors import ExternalToolError, ParameterError
from linkwork.io.toml import MAGNITUDE_LIMITS
from linkwork.plot.scene import MAX_ANIMATION_FRAMES, PointSpec
from linkwork.report import Options, animation, build, write

__all__ = ["parse_path", "register"]


def parse_path(text: str, doc: object) -> PointSpec:
    """``--path`` as (body, point): ``BODY.POINT`` (a named point) or ``BODY:X,Y`` (local
    coordinates of the body's frame in mm)."""
    mech = getattr(doc, "mechanism", None)
    if not callable(mech):
        raise ParameterError("--path", text, "only a planar file's points have paths to draw")
    m = mech()
    if ":" in text:
        body, _, xy = text.partition(":")
        try:
            x, y = (float(v) * 1e-3 for v in xy.split(","))
        except ValueError:
            raise ParameterError("--path", text, "must be BODY:X,Y with X, Y in mm (local "
                                 "coordinates of the body's frame)") from None
        limit = MAGNITUDE_LIMITS["length"]
        if not (abs(x) <= limit and abs(y) <= limit):  # NaN too
            raise ParameterError("--path", text, f"X, Y must be finite and within "
                                 f"+-{limit * 1e3:g} mm, far beyond any machine mechanism")
        point: str | tuple[float, float] = (x, y)
    else:
        body, dot, name = text.partition(".")
        if not dot or not name:
            raise ParameterError("--path", text, "must be BODY.POINT (a named point) or "
                                 "BODY:X,Y (mm in the body's frame)")
        point = name
    names = [b.name for b in m.bodies]
    if body not in names:
        raise ParameterError("--path", text, f"no moving body {body!r}; bodies: {names}")
    if isinstance(point, str) and point not in m.body(body).points and point != "com":
        raise ParameterError("--path", text, f"no point {point!r} on {body}; points: "
                             f"{sorted(m.body(body).points)} or com")
    return (body, point)


def register(app: typer.Typer) -> None:
    """Add the ``report`` command to ``app``."""

    @app.command()
    def report(
        file: Annotated[Path, typer.Argument(help="mechanism file (TOML)")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
        animate: Annotated[bool, typer.Option(
            "--animate", help="also write the animation as GIF (and MP4 where ffmpeg is "
                              "installed)")] = False,
        frames: Annotated[int, typer.Option(
            help=f"frames of the GIF/MP4 (at most {MAX_ANIMATION_FRAMES})")] = 90,
        path: Annotated[list[str] | None, typer.Option(
            "--path", help="draw the path of a point: BODY.POINT or BODY:X,Y (mm in the "
                           "body's frame); repeatable")] = None,
        centres: Annotated[bool, typer.Option(
            "--centres", help="draw the instant centres of velocity (Aronhold-Kennedy)")
        ] = False,
    ) -> None:
        """Write a self-contained HTML report: animated mechanism, diagrams, tables."""
        doc = io.load(file)
        if isinstance(doc, io.PlanarFile):
            doc.check_whole_cycle(file, "`linkwork report`")
        if not 1 <= frames <= MAX_ANIMATION_FRAMES:
            raise ParameterError("--frames", frames, f"must be 1 to {MAX_ANIMATION_FRAMES}")
        paths = [parse_path(p, doc) for p in path or ()]
        options = Options(paths=paths, centres=centres, file=str(file))
        stem = file.stem or "report"
        movies = [".gif"] + ([".mp4"] if animate and shutil.which("ffmpeg") else [])
        with output_run(out, command="report", file=file):
            with steps(2 + len(movies) * animate + 2,
                       console=make_console(stderr=True)) as step:
                with load_errors(file, doc):  # a load's error names the file and key
                    page = build(doc, path=file, options=options, step=step)
                step("writing the HTML")
                written = [write(page, out / f"{stem}.html")]
                movie_notes = []
                if animate:
                    for suffix in movies:
                        step(f"drawing {stem}{suffix}")
                        try:
                            written.append(animation(page, out / f"{stem}{suffix}",
                                                     frames=frames))
                        except ExternalToolError as exc:  # the MP4 is the optional one
                            movie_notes.append(f"note: {exc}: no MP4 (the GIF is written)")
            console = make_console()
            for w in page.warnings:
                console.print(escape(f"note: {w}"), highlight=False)
            for note in movie_notes:
                console.print(escape(note), highlight=False)
            if animate and len(movies) == 1:
                console.print("note: ffmpeg is not installed: no MP4 (the GIF is written)",
                              highlight=False)
            console.print(escape("wrote " + ", ".join(
                f"{p} ({p.stat().st_size / 1e3:.0f} kB)" for p in written)), highlight=False)
