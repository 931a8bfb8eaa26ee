"""Writing output files: never half-written, and a record of what was written.

Every file linkwork writes (:func:`linkwork.results.write_csv`,
:func:`~linkwork.results.write_json`, :func:`linkwork.plot.save`) is written through
:func:`atomic_path`: into a hidden temporary file beside the target, in the same folder, renamed
over the target (:func:`os.replace`, atomic on one file system) only when complete. An
interrupted or failing write (Ctrl-C, a full disk, an exception while the rows are produced)
leaves the target as it was -- absent, or the complete file of an earlier run -- and no
temporary file.

:func:`recording` collects the paths completed inside it (the command line uses it to list the
files a run wrote in its output folder, :mod:`linkwork.cli._args`).

This module sits at the bottom of the layers (it imports nothing of linkwork), so that the
results and the plots below them share it.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

__all__ = ["TEMP_MARK", "atomic_path", "recording"]

#: In the name of every temporary file (``.NAME.<random>.part.SUFFIX``): hidden, and with the
#: target's suffix, so that writers that pick the format by suffix (matplotlib) write the same
#: format.
TEMP_MARK = ".part"

_RECORD: contextvars.ContextVar[list[Path] | None] = contextvars.ContextVar(
    "linkwork_outputs_record", default=None)


def _temp_beside(path: Path) -> Path:
    return path.with_name(f".{path.name}.{secrets.token_hex(4)}{TEMP_MARK}{path.suffix}")


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; when the block completes, rename it to ``path``.

    Write the whole file to the yielded path inside the ``with`` block. On normal exit the
    temporary file replaces ``path`` (created with the permissions an ordinary ``open`` gives);
    on any exception, ``KeyboardInterrupt`` included, it is removed and ``path`` is left as it
    was. A completed path is added to the active :func:`recording`, if any::

        with atomic_path(out / "cycle.csv") as tmp:
            with tmp.open("w") as fh:
                ...
    """
    target = Path(path)
    tmp = _temp_beside(target)
    try:
        yield tmp
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    record = _RECORD.get()
    if record is not None:
        record.append(target)


@contextlib.contextmanager
def recording() -> Iterator[list[Path]]:
    """Collect the paths completed by :func:`atomic_path` inside the block, in order (a list
    that grows while the block runs). Recordings do not nest: an inner one collects alone."""
    paths: list[Path] = []
    token = _RECORD.set(paths)
    try:
        yield paths
    finally:
        _RECORD.reset(token)
