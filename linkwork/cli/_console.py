"""The Rich consoles of the commands.

A command's console neither highlights nor replaces emoji codes: what it prints holds strings
from the user's files (mechanism, body and joint names) and options (the output folder), and
Rich's highlighter is quadratic in the length of a string (a name of 100 kB took 94 s). Those
strings are also escaped (``rich.markup.escape``) wherever they meet Rich markup. Tables go
through :func:`linkwork.cli._tables.print_table`, which splits what is wider than the console.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

from rich.markup import escape

#: Width of tables written to a file or a pipe (Rich would use 80 columns and squash them);
#: a table wider than this is split into tables of consecutive columns
#: (:func:`linkwork.cli._tables.print_table`).
PIPE_WIDTH = 160


def console(*, stderr: bool = False) -> Any:
    """A Rich console: the terminal's width on a terminal, :data:`PIPE_WIDTH` otherwise;
    no highlighting, no emoji codes."""
    from rich.console import Console

    con = Console(stderr=stderr, highlight=False, emoji=False)
    if not con.is_terminal:
        con = Console(stderr=stderr, width=PIPE_WIDTH, highlight=False, emoji=False)
    return con


@contextlib.contextmanager
def steps(total: int, *, console: Any) -> Iterator[Callable[[str], None]]:
    """A progress bar of ``total`` named steps: ``step("writing cycle.csv")`` starts the next
    one (and completes the one before).

    Shown on ``console`` (the commands pass a stderr console) only where it is a terminal, and
    erased when done (``transient``), so that a command's stderr keeps its one error line and
    its stdout is untouched; elsewhere ``step`` does nothing. Nothing may be printed on another
    console inside the block (the live bar would tear).
    """
    if not console.is_terminal:
        yield lambda what: None
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        SpinnerColumn,
        TimeElapsedColumn,
    )

    with Progress(SpinnerColumn(), "{task.description}", BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), console=console, transient=True) as bar:
        task = bar.add_task("", total=total)
        started = [0]

        def step(what: str) -> None:
            bar.update(task, description=escape(what), completed=started[0])
            bar.refresh()  # shown at once: a step is seconds of work, not a tight loop
            started[0] += 1

        yield step
        bar.update(task, completed=total)


@contextlib.contextmanager
def counting(description: str, *, console: Any) -> Iterator[Callable[[int, int], None]]:
    """A progress bar of counted work (positions, revolutions) as a ``progress(done, total)``
    callback: on ``console`` (a stderr console) where it is a terminal, erased when done;
    elsewhere the callback does nothing (as :func:`steps`)."""
    if not console.is_terminal:
        yield lambda done, total: None
        return
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeElapsedColumn

    with Progress(escape(description), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as bar:
        task = bar.add_task("", total=None)

        def update(done: int, total: int) -> None:
            bar.update(task, completed=done, total=total)

        yield update
