"""The ``linkwork`` command.

A thin layer: it parses, calls the library and prints. Each command lives in its own module of
this package and registers itself on a Typer app through a ``register(app)`` function; the
modules are listed in :data:`COMMAND_MODULES`. A command's module is imported when that command
runs (or its help is asked for), no other command's; none for ``linkwork --help`` and
``--version``: :data:`COMMAND_HELP` gives
the command list its one-line helps (the start-up cost is importing the studies, pydantic and the
engine; docs/performance.md). A command parses its arguments, loads the file
(:func:`linkwork.io.load`), runs a study (:mod:`linkwork.studies`) and renders its result.
Every expected failure (bad file, bad parameter, impossible mechanism) prints one line on
stderr and exits with code 2, Ctrl-C one line naming the command and exit code 130 -- see
:func:`main`. ``-h`` is ``--help`` on every command;
``linkwork --version`` prints the version; ``python -m linkwork`` runs the same app.
"""

from __future__ import annotations

import functools
import importlib
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import Annotated, Any

import numpy as np
import typer

from linkwork import __version__
from linkwork.cli import examples
from linkwork.errors import (
    ExternalToolError,
    FileFormatError,
    LinkworkError,
    MissingExtraError,
)
from linkwork.heap import roomy_process_heap

__all__ = ["COMMAND_HELP", "COMMAND_MODULES", "app", "main"]

#: The commands in the order ``linkwork --help`` lists them (Typer's: commands, then groups),
#: with their one-line help (the first paragraph of each command's help;
#: tests/cli/test_main.py checks they agree).
COMMAND_HELP: dict[str, str] = {
    "analyze": "Analyse a mechanism over a cycle: table, CSV/JSON and plots in an output folder.",
    "balance": "Balance a planar mechanism: paper 001's table, torque and bearing loads, plots.",
    "dynamics": "Machine dynamics: the crank's real motion under its motor, flywheel, start-up, "
                "motor verdicts.",
    "reactions": "Spatial joint reactions (axial forces, bending moments) with redundant "
                 "constraints.",
    "report": "Write a self-contained HTML report: animated mechanism, diagrams, tables.",
    "examples": "List the bundled example files, or copy them into a folder (--copy DIR).",
    "swashplate": "Swash-plate (inclined-disk) drive of rotor machines (paper 003).",
    "synthesize": "Dimensional synthesis of planar linkages: function, motion or path "
                  "generation from a task file.",
}


def _command_modules() -> tuple[ModuleType, ...]:
    # Lazy on purpose (issue 19, item 7): `linkwork --help` and `--version` must not import
    # the studies; tests/docs/test_architecture.py allows this one import in a function.
    from linkwork.cli import (
        analyze,
        balance,
        dynamics,
        reactions,
        report,
        swashplate,
        synthesize,
    )

    return (analyze, balance, dynamics, reactions, report, swashplate, synthesize, examples)


@functools.cache
def _real_commands() -> dict[str, Any]:
    """The Click commands of every command module, registered on one Typer app."""
    full = typer.Typer(add_completion=False, pretty_exceptions_enable=False)
    for module in _command_modules():
        module.register(full)
    return dict(typer.main.get_command(full).commands)  # type: ignore[attr-defined]


#: The commands whose module was imported to run one (:func:`_command`), by name.
_LOADED: dict[str, Any] = {}


def _command(name: str) -> Any:
    """The Click command ``name`` with only its own module imported (``linkwork.cli.<name>``):
    running ``analyze``, or failing in it, imports no other command's studies."""
    if name not in _LOADED:
        module = importlib.import_module(f"linkwork.cli.{name}")
        one = typer.Typer(add_completion=False, pretty_exceptions_enable=False)
        one.callback()(lambda: None)  # a group even with one command: its commands by name
        module.register(one)
        _LOADED[name] = typer.main.get_command(one).commands[name]  # type: ignore[attr-defined]
    return _LOADED[name]


class _Interrupted(Exception):
    """Ctrl-C while a command ran: a KeyboardInterrupt carried past Typer, which would turn it
    into a silent exit 130 (:meth:`_LazyGroup.invoke`, :func:`main`)."""


class _LazyGroup(typer.core.TyperGroup):
    """The root group: lists the commands from :data:`COMMAND_HELP`; imports their modules
    only to run one (resolve_command) or when ``commands`` is read."""

    @property  # type: ignore[override]
    def commands(self) -> dict[str, Any]:
        return _real_commands()

    @commands.setter
    def commands(self, value: Any) -> None:  # TyperGroup.__init__ sets the (empty) mapping
        if value:
            raise TypeError("linkwork's commands come from COMMAND_MODULES")

    def list_commands(self, ctx: Any) -> list[str]:
        return list(COMMAND_HELP)

    def get_command(self, ctx: Any, cmd_name: str) -> Any:
        if _real_commands.cache_info().currsize:
            return _real_commands().get(cmd_name)
        if cmd_name not in COMMAND_HELP:
            return None
        if cmd_name in _LOADED:
            return _LOADED[cmd_name]
        return typer.core.TyperCommand(cmd_name, help=COMMAND_HELP[cmd_name])  # listing only

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        if args and args[0] in COMMAND_HELP:  # the command to run: its module only
            _command(args[0])
        return super().resolve_command(ctx, args)

    def invoke(self, ctx: Any) -> Any:
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            raise _Interrupted from None


app = typer.Typer(
    cls=_LazyGroup,
    name="linkwork",
    help="Kinematics, kinetostatics, balancing and synthesis of machine mechanisms.",
    add_completion=True,  # --install-completion / --show-completion (bash, zsh, fish, pwsh)
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    # inherited by every sub-command's context (Click takes the parent's help option names)
    context_settings={"help_option_names": ["-h", "--help"]},
)



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


def __getattr__(name: str) -> Any:
    if name == "COMMAND_MODULES":  # imports them: see the module docstring
        return _command_modules()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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


#: Exit code of a command stopped by Ctrl-C (128 + SIGINT, as the shells report it).
INTERRUPTED = 130


def _doing(args: Sequence[str]) -> str:
    """What the command line was doing, for the interrupt message: its leading words up to the
    first option (``swashplate synthesize``, ``analyze examples/press.toml``)."""
    words: list[str] = []
    for a in args:
        if a.startswith("-") or len(words) == 3:
            break
        words.append(a)
    return " ".join(words) or "linkwork"


def _interrupted(args: Sequence[str]) -> int:
    print(f"linkwork: interrupted (Ctrl-C) during '{_doing(args)}'; no file was left "
          "half-written", file=sys.stderr)
    return INTERRUPTED


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit code (0 ok, 2 bad input or impossible request,
    130 interrupted).

    Expected failures never show a traceback: a :class:`~linkwork.errors.LinkworkError`, a
    missing or unreadable file, or a usage error prints one line on stderr and returns 2.
    Ctrl-C (KeyboardInterrupt) prints one line naming the command and returns 130; no output
    file is left half-written (:func:`linkwork.outputs.atomic_path`).
    """
    args = list(sys.argv[1:] if argv is None else argv)
    try:
        return _main(args)
    except (_Interrupted, KeyboardInterrupt):
        return _interrupted(args)


def _main(args: list[str]) -> int:
    # this process is the command's own: glibc's heap thresholds for bulk NumPy work
    # (linkwork.heap.roomy_process_heap; 11 % off the swash-plate synthesis)
    roomy_process_heap()
    command = typer.main.get_command(app)
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
    except SystemExit as exc:  # Typer's --show-completion / --install-completion exit this way
        return exc.code if isinstance(exc.code, int) else 0 if exc.code is None \
            else _fail(str(exc.code))
    except typer.Abort:
        return _fail("aborted")
    except typer.TyperException as exc:  # usage errors: bad option, missing argument, ...
        fmt = getattr(exc, "format_message", None)
        return _fail(fmt() if callable(fmt) else str(exc))
    except FileFormatError as exc:
        return _fail(str(exc) + _bundled_hint(exc))
    except LinkworkError as exc:
        return _fail(_on_file(exc, args))
    except OSError as exc:
        return _fail(str(exc))
    return int(rv) if isinstance(rv, int) else 0


def _on_file(exc: LinkworkError, args: Sequence[str]) -> str:
    """The message of an error found while a command worked on its input file (a mechanism
    that does not assemble, a study's limit) with the file in front, as the file's own errors
    name it; an error of an option (``--angles = ...``) or one that names the file already as
    it is."""
    text = str(exc)
    if (isinstance(exc, MissingExtraError | ExternalToolError)  # of the machine, not the file
            or str(getattr(exc, "parameter", "")).startswith("-")):
        return text
    files = [a for a in args if not a.startswith("-") and a.endswith(".toml")
             and Path(a).is_file()]
    if not files or files[0] in text:
        return text
    return f"{files[0]}: {text}"


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
