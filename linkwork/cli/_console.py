"""The Rich consoles of the commands.

A command's console neither highlights nor replaces emoji codes: what it prints holds strings
from the user's files (mechanism, body and joint names) and options (the output folder), and
Rich's highlighter is quadratic in the length of a string (a name of 100 kB took 94 s). Those
strings are also escaped (``rich.markup.escape``) wherever they meet Rich markup. Tables go
through :func:`linkwork.cli._tables.print_table`, which splits what is wider than the console.
"""

from __future__ import annotations

from typing import Any

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
