"""The Rich consoles of the commands."""

from __future__ import annotations

from typing import Any

#: Width of tables written to a file or a pipe (Rich would use 80 columns and squash them).
PIPE_WIDTH = 160


def console(*, stderr: bool = False) -> Any:
    """A Rich console: the terminal's width on a terminal, :data:`PIPE_WIDTH` otherwise."""
    from rich.console import Console

    con = Console(stderr=stderr)
    if not con.is_terminal:
        con = Console(stderr=stderr, width=PIPE_WIDTH)
    return con
