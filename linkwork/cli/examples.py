"""``linkwork examples [--copy DIR]``: the example files bundled with the package.

The wheel carries the repository's ``examples/`` folder as ``linkwork/examples`` (pyproject:
``[tool.hatch.build.targets.wheel.force-include]``), found at run time with
:mod:`importlib.resources`; from a checkout (source tree or editable install) there is no such
folder inside the package and the checkout's ``examples/`` is used. ``linkwork examples`` lists
them (name, file type, the first line of the file's leading comment); ``--copy DIR`` copies them
into ``DIR`` (created), refusing to overwrite any existing file, so that the README's commands
(``linkwork analyze examples/sine_press.toml``) run after ``linkwork examples --copy examples``
in any folder.
"""

from __future__ import annotations

import shutil
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated

import typer

from linkwork.errors import ParameterError
from linkwork.outputs import atomic_path

__all__ = ["Example", "bundled", "copy_examples", "examples_dir", "register"]

#: The checkout's examples folder (used when the package has no bundled copy).
_CHECKOUT_EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@dataclass(frozen=True)
class Example:
    """A bundled example file: its ``name`` (file name), ``type`` (the file's top-level
    ``type`` key), ``description`` (first line of its leading comment) and ``path``."""

    name: str
    type: str
    description: str
    path: Path


def examples_dir() -> Path:
    """The folder of the bundled examples: ``linkwork/examples`` inside an installed wheel,
    else the checkout's ``examples/``."""
    inside = resources.files("linkwork") / "examples"
    if inside.is_dir():
        return Path(str(inside))
    return _CHECKOUT_EXAMPLES


def _describe(path: Path) -> Example:
    text = path.read_text(encoding="utf-8")
    first = next((ln.lstrip("#").strip() for ln in text.splitlines()
                  if ln.startswith("#") and ln.lstrip("#").strip()), "")
    try:
        kind = str(tomllib.loads(text).get("type", "?"))
    except tomllib.TOMLDecodeError:
        kind = "?"
    return Example(path.name, kind, first, path)


def bundled() -> list[Example]:
    """The bundled examples, sorted by name."""
    folder = examples_dir()
    if not folder.is_dir():
        return []
    return [_describe(p) for p in sorted(folder.glob("*.toml"))]


def copy_examples(dest: Path) -> list[Path]:
    """Copy every bundled example into ``dest`` (created with its parents); return the new
    paths. Nothing is copied when any target file exists already (a ParameterError naming it)
    or ``dest`` is not a folder."""
    found = bundled()
    if not found:
        raise ParameterError("--copy", str(dest), "no bundled examples in this installation")
    if dest.exists() and not dest.is_dir():
        raise ParameterError("--copy", str(dest), "must be a folder; a file of that name exists")
    clash = [dest / ex.name for ex in found if (dest / ex.name).exists()]
    if clash:
        more = f" (and {len(clash) - 1} more)" if len(clash) > 1 else ""
        raise ParameterError("--copy", str(dest), f"would overwrite {clash[0]}{more}; "
                             "choose another folder or remove them")
    try:
        dest.mkdir(parents=True, exist_ok=True)
        copied = []
        for ex in found:  # each copied beside and renamed when complete: never half a file
            with atomic_path(dest / ex.name) as tmp:
                shutil.copyfile(ex.path, tmp)
            copied.append(dest / ex.name)
        return copied
    except OSError as exc:
        raise ParameterError("--copy", str(dest), f"cannot be written "
                             f"({exc.strerror or exc})") from None


def register(app: typer.Typer) -> None:
    """Add the ``examples`` command to ``app``."""

    @app.command()
    def examples(
        copy: Annotated[Path | None, typer.Option(
            "--copy", metavar="DIR",
            help="copy the example files into DIR (never overwrites a file)")] = None,
    ) -> None:
        """List the bundled example files, or copy them into a folder (--copy DIR)."""
        if copy is not None:
            written = copy_examples(copy)
            print(f"copied {len(written)} examples into {copy}")
            return
        found = bundled()
        w_name = max((len(ex.name) for ex in found), default=4)
        w_type = max((len(ex.type) for ex in found), default=4)
        for ex in found:
            print(f"{ex.name:<{w_name}}  {ex.type:<{w_type}}  {ex.description}")
        print(f"(in {examples_dir()}; `linkwork examples --copy DIR` copies them)")
