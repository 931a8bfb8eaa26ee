"""Printing the commands' tables to the console's width, never cropped.

Rich fits a table that is wider than the console by shrinking its columns: a column that may
wrap folds its numbers over several lines, a column that may not is cut at the right edge, and
the columns beyond the edge are lost without a word (a six-bar's analysis table has 13 columns;
an 80-column terminal showed 6 of them). :func:`print_table` prints a table as it is when its
natural width fits the console; otherwise it splits the table into several tables of
consecutive columns, each repeating the first column (the position, joint or quantity the row
is about) and titled ``... (columns 1-6 of 13)``, ``... (columns 1, 7-12 of 13)``. Every cell
keeps its natural width, so no number is folded or cut. Only a single column too wide for the
console next to the first one is left to wrap, at spaces or, as a last resort, by folding
(never by cropping).
"""

from __future__ import annotations

import copy
from dataclasses import replace
from typing import Any

from rich.console import Console
from rich.measure import Measurement
from rich.table import Table
from rich.text import Text

__all__ = ["print_table", "split_table"]

#: The width at which a table is measured: wide enough that no column is squeezed.
_UNBOUNDED = 1_000_000


def natural_width(console: Console, table: Table) -> int:
    """The width ``table`` takes with every cell on one line (columns not squeezed)."""
    return Measurement.get(console, console.options.update_width(_UNBOUNDED), table).maximum


def _span(columns: list[int]) -> str:
    """``[0, 6, 7, 8]`` -> ``"1, 7-9"`` (1-based, consecutive runs joined by a dash)."""
    runs: list[list[int]] = []
    for c in columns:
        if runs and c == runs[-1][-1] + 1:
            runs[-1].append(c)
        else:
            runs.append([c])
    return ", ".join(f"{r[0] + 1}" if len(r) == 1 else f"{r[0] + 1}-{r[-1] + 1}" for r in runs)


def _columns(table: Table, columns: list[int]) -> Table:
    """``table`` with only ``columns`` (indices into ``table.columns``), in that order."""
    part = copy.copy(table)
    part.columns = [replace(table.columns[c], _index=k, _cells=list(table.columns[c].cells))
                    for k, c in enumerate(columns)]
    return part


def _part(table: Table, columns: list[int], *, last: bool) -> Table:
    """The table of ``columns`` of ``table``, titled with the columns it shows; the caption
    only under the ``last`` part."""
    part = _columns(table, columns)
    note = f"columns {_span(columns)} of {len(table.columns)}"
    title: Any = table.title
    if isinstance(title, Text):
        title = title.copy()
        title.append(f" ({note})")
    elif title:
        title = f"{title} ({note})"
    else:
        title = note
    part.title = title
    if not last:
        part.caption = None
    return part


def _unsqueezable(table: Table) -> Table:
    """``table`` with every column allowed to wrap, folding what does not fit: Rich wraps
    text at spaces, folds a word longer than the column and never cuts one off."""
    fitted = copy.copy(table)
    fitted.columns = [replace(col, no_wrap=False, overflow="fold", _cells=list(col.cells))
                      for col in table.columns]
    return fitted


def _groups(widths: list[int], limit: int, edges: int, rule: int) -> list[list[int]]:
    """Consecutive groups of columns ``1..n-1``, each after column 0, as many per group as fit
    ``limit`` (at least one): the table of a group is ``edges`` + the widths of its columns +
    a ``rule`` between each two."""
    groups: list[list[int]] = []
    group, used = [0], edges + widths[0]
    for c in range(1, len(widths)):
        if len(group) > 1 and used + rule + widths[c] > limit:
            groups.append(group)
            group, used = [0], edges + widths[0]
        group.append(c)
        used += rule + widths[c]
    groups.append(group)
    return groups


def split_table(console: Console, table: Table, width: int | None = None) -> list[Table]:
    """``table`` as tables that each fit ``width`` (default: the console's).

    The table itself if it fits; otherwise as few groups of consecutive columns as fit, each
    after the first column, of widths as even as they can be (the narrowest widest part). A
    group that cannot fit even with one column besides the first is printed alone, its cells
    allowed to wrap (see :func:`_unsqueezable`).
    """
    width = console.width if width is None else width
    n = len(table.columns)
    if natural_width(console, table) <= width:
        return [table]
    if n <= 2:
        return [_unsqueezable(table)]
    edges = 2 if table.box and table.show_edge else 0
    rule = 1 if table.box else 0
    widths = [natural_width(console, _columns(table, [c])) - edges for c in range(n)]
    count = len(_groups(widths, width, edges, rule))
    lo, hi = 1, width  # the narrowest limit that needs no more parts than ``width`` does
    while lo < hi:
        mid = (lo + hi) // 2
        if len(_groups(widths, mid, edges, rule)) <= count:
            hi = mid
        else:
            lo = mid + 1
    groups = _groups(widths, lo, edges, rule)
    parts = [_part(table, g, last=i == len(groups) - 1) for i, g in enumerate(groups)]
    return [p if natural_width(console, p) <= width else _unsqueezable(p) for p in parts]


def print_table(console: Console, table: Table) -> None:
    """Print ``table`` on ``console`` without cropping a column (:func:`split_table`)."""
    for part in split_table(console, table):
        console.print(part, highlight=False)
