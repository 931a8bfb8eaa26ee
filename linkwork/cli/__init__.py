"""The ``linkwork`` command.

A thin layer: it parses, calls the library and prints. Each command lives in its own module of
this package and registers itself on :data:`app` through a ``register(app)`` function; the
modules are listed in :data:`COMMAND_MODULES`. A command parses its arguments, loads the file
(:func:`linkwork.io.load`), runs a study (:mod:`linkwork.studies`) and renders its result.
Every expected failure (bad file, bad parameter, impossible mechanism) prints one line on
stderr and exits with code 2 -- see :func:`main`. ``-h`` is ``--help`` on every command;
``linkwork --version`` prints the version; ``python -m linkwork`` runs the same app.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from linkwork import __version__
from linkwork.cli import analyze, balance, examples, reactions, swashplate
from linkwork.errors import FileFormatError, LinkworkError

__all__ = ["COMMAND_MODULES", "app", "main"]

app = typer.Typer(
    name="linkwork",
    help="Kinematics, kinetostatics, balancing and synthesis of machine mechanisms.",
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    # inherited by every sub-command's context (Click takes the parent's help option names)
    context_settings={"help_option_names": ["-h", "--help"]},
)

#: Modules of linkwork.cli that define commands (each has ``register(app)``).
COMMAND_MODULES = (analyze, balance, reactions, swashplate, examples)


def _print_version(value: bool) -> None:
    if value:
        print(f"linkwork {__version__}")
        raise typer.Exit(0)


@app.callback()
def _root(
    version: Annotated[bool, typer.Option(
        "--version", callback=_print_version, is_eager=True,
        help="Print the version and exit.")] = False,
) -> None:
    """Kinematics, kinetostatics, balancing and synthesis of machine mechanisms."""


for _module in COMMAND_MODULES:
    _module.register(app)


def _fail(message: str) -> int:
    first = " ".join(str(message).split())
    print(f"linkwork: error: {first}", file=sys.stderr)
    return 2


def _bundled_hint(exc: FileFormatError) -> str:
    """For a missing file named like a bundled example: how to get the examples."""
    name = Path(exc.file).name
    if exc.problem != "file not found" or name not in {ex.name for ex in examples.bundled()}:
        return ""
    return (f" ({name} is a bundled example: `linkwork examples --copy examples` copies them "
            "into ./examples)")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code (0 ok, 2 bad input or impossible request).

    Expected failures never show a traceback: a :class:`~linkwork.errors.LinkworkError`, a
    missing or unreadable file, or a usage error prints one line on stderr and returns 2.
    """
    command = typer.main.get_command(app)
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        # an overflow means an input far outside any machine (e.g. speed = 1e200 rad/s): stop
        # with a message instead of writing inf into the output files and exiting 0
        with np.errstate(over="raise"):
            rv = command.main(args=args, prog_name="linkwork", standalone_mode=False)
    except (FloatingPointError, OverflowError) as exc:  # numpy's and Python's float overflow
        why = exc if isinstance(exc, FloatingPointError) else "a result beyond 1.8e308"
        return _fail(f"numerical overflow ({why}): a value of the input is too large for "
                     "double precision; check the magnitudes and units in the file and options")
    except typer.Exit as exc:
        return int(exc.exit_code)
    except typer.Abort:
        return _fail("aborted")
    except typer.TyperException as exc:  # usage errors: bad option, missing argument, ...
        fmt = getattr(exc, "format_message", None)
        return _fail(fmt() if callable(fmt) else str(exc))
    except FileFormatError as exc:
        return _fail(str(exc) + _bundled_hint(exc))
    except (LinkworkError, OSError) as exc:
        return _fail(str(exc))
    return int(rv) if isinstance(rv, int) else 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
