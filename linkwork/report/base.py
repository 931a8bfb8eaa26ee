"""What every renderer of the report shares: the renderer record, the options, and helpers that
turn a study's arrays into diagrams and tables in display units.

A renderer (:class:`Renderer`) reads a validated file (:mod:`linkwork.io`), runs its study
(:mod:`linkwork.studies`) and returns a :class:`~linkwork.plot.html.Section`; it never
recomputes what the study holds. Display units: angles in degrees, lengths in mm, forces in N
(kN, MN past 10 kN, 10 MN), moments in N·m; the driver coordinate as φ1 [deg] or s1 [mm].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from linkwork.plot.html import Diagram, Section, Table
from linkwork.plot.numbers import scale_of, unit_label
from linkwork.plot.scene import PointSpec, Scene

__all__ = ["Options", "Renderer", "diagram", "driver_display", "prefixed"]


@dataclass(frozen=True)
class Options:
    """What the report is asked to show besides the defaults.

    Attributes
    ----------
    paths : sequence of (body, point)
        Points whose paths (coupler curves) are drawn: a named point or local (x, y) [m].
    centres : bool
        Draw the instant centres of velocity of every pair of bodies.
    date : str, optional
        The date written on the report (default: today, UTC).
    file : str
        The input file's name, for messages.
    """

    paths: Sequence[PointSpec] = ()
    centres: bool = False
    date: str | None = None
    file: str = "file"


def _always(doc: Any) -> bool:
    return True


@dataclass(frozen=True)
class Renderer:
    """One part of the report.

    Attributes
    ----------
    key : str
        Anchor of its section (``"planar"``).
    title : str
        Heading of its section.
    file_type : type or tuple of types
        The :mod:`linkwork.io` file class (or classes) it reads.
    run : callable
        ``(doc, options) -> study`` (a function of :mod:`linkwork.studies`).
    section : callable
        ``(study, options) -> Section``.
    applies : callable
        ``doc -> bool``: whether the file asks for this part (e.g. has a ``[balance]``).
    scene : callable, optional
        ``(study, options) -> Scene``: the animated mechanism (the first renderer that has one
        draws the page's).
    inputs : callable, optional
        ``doc -> list of Table``: the input data with units.
    notes : callable, optional
        ``study -> list of (title, text)``: the conventions and errata that apply.
    warnings : callable, optional
        ``study -> list of str``: shown at the top of the page.
    scenes : callable, optional
        ``(study, options) -> list of (label, Scene)``: drawings to choose between (the
        designs of a synthesis); its section's diagrams and tables refer to them by their
        index in this list (``Diagram.scene``, ``Table.scene``, ``Table.chooses``).
    timing : callable, optional
        ``(study, scene) -> Scene``: the page's drawing with what this study knows of its
        motion over time (the real speed of a machine: :meth:`Scene.timed`), applied after
        every renderer has run.
    primary : bool
        The report cannot be made without it: its failure fails the report; any other
        renderer's failure is shown in its section.
    """

    key: str
    title: str
    file_type: type | tuple[type, ...]
    run: Callable[[Any, Options], Any]
    section: Callable[[Any, Options], Section]
    applies: Callable[[Any], bool] = _always
    scene: Callable[[Any, Options], Scene] | None = None
    inputs: Callable[[Any], list[Table]] | None = None
    notes: Callable[[Any], list[tuple[str, str]]] | None = None
    warnings: Callable[[Any], list[str]] | None = None
    scenes: Callable[[Any, Options], list[tuple[str, Scene]]] | None = None
    timing: Callable[[Any, Scene], Scene] | None = None
    primary: bool = False
    extra: dict[str, Any] = field(default_factory=dict)


def driver_display(unit: str) -> tuple[str, float, bool]:
    """Display unit, factor from SI and whether it is an angle, for a driver coordinate whose
    SI unit is ``unit`` (``"rad"`` -> deg, ``"m"`` -> mm; ``""``: a position's index along
    several drivers' path, shown as it is)."""
    if unit == "":
        return ("", 1.0, False)
    return ("deg", 180.0 / math.pi, True) if unit == "rad" else ("mm", 1e3, False)


def prefixed(unit: str, *values: Any) -> tuple[float, str]:
    """Divisor and unit label for showing ``values`` [unit]: the unit up to 10 000, then k, M
    (a 300 kN press force is shown as 300 kN)."""
    peak = scale_of(*values)
    for div, prefix in ((1e6, "M"), (1e3, "k")):
        if unit in ("N", "N*m", "W", "J") and peak >= 10 * div:
            return div, prefix + unit_label(unit)
    return 1.0, unit_label(unit)


def diagram(title: str, positions: np.ndarray, unit: str, coordinate: str,
            series: Sequence[tuple[str, np.ndarray]], quantity: str, si_unit: str, *,
            factor: float | None = None, note: str = "") -> Diagram:
    """A diagram of ``series`` [si_unit] over the driver positions ``positions`` [SI, of
    ``unit``]: the x axis in deg or mm, the values scaled to a readable unit (``factor``:
    a fixed factor from SI with ``si_unit`` naming the displayed unit instead)."""
    shown, f, angle = driver_display(unit)
    if factor is None:
        div, label = prefixed(si_unit, *(v for _, v in series))
        scaled = [(n, np.asarray(v, dtype=float) / div) for n, v in series]
    else:
        label = si_unit
        scaled = [(n, np.asarray(v, dtype=float) * factor) for n, v in series]
    pos = np.asarray(positions, dtype=float)
    xlabel = f"{coordinate} [{shown}]" if shown else f"{coordinate} along the drivers' path"
    return Diagram(title=title, x=pos * f, series=scaled, xlabel=xlabel,
                   ylabel=f"{quantity} [{label}]", positions=pos, angle=angle, note=note)
