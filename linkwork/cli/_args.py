"""Arguments shared by the commands: table positions (``--angles``) and the output folder.

The output folder keeps a record of what linkwork wrote into it, :data:`MANIFEST`
(``linkwork-run.json``): per command, the file it ran on, when, and the files it wrote (name,
size, modification time). A command runs inside :func:`output_run`: at its end, the files that
the previous run of the same command wrote there and this run did not write again are removed
(they are linkwork's own, left from other inputs or options) and one line says so; a file
linkwork did not write, or one changed since it wrote it, is never touched.
"""

from __future__ import annotations

import contextlib
import datetime
import json
import math
import os
import re
import socket
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.planar import MAX_ANGLE, PlanarFile
from linkwork.outputs import recording
from linkwork.results import write_json

__all__ = ["MANIFEST", "load_errors", "output_dir", "output_run", "parse_angles",
           "parse_angles_deg", "reach_scheduler", "table_positions"]

#: The record of what linkwork wrote into an output folder (see the module docstring).
MANIFEST = "linkwork-run.json"


def parse_angles_deg(text: str, *, angles: bool = True) -> list[float]:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``); with
    ``angles=False`` any finite numbers (a linear driver's slide positions in mm)."""
    try:
        vals = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        limit = "must be comma-separated numbers in degrees"
        raise ParameterError("--angles", text, limit) from None
    if not vals:
        raise ParameterError("--angles", text, "must list at least one angle")
    bad = [v for v in vals if not np.isfinite(v)]
    if bad:
        raise ParameterError("--angles", bad[0], "must be finite numbers in degrees")
    if angles:
        lim = math.degrees(MAX_ANGLE)
        far = [v for v in vals if abs(v) > lim]  # -1e300 was printed as a 300-digit angle
        if far:
            raise ParameterError("--angles", f"{far[0]:g}", f"must lie within +-{lim:.6g} deg "
                                 f"(+-{MAX_ANGLE:g} rad): beyond it the float spacing of "
                                 "angles exceeds 1e-10 rad")
    return vals


def parse_angles(text: str) -> np.ndarray:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``) to radians."""
    return np.radians(np.array(parse_angles_deg(text)))


def table_positions(doc: PlanarFile, text: str) -> np.ndarray:
    """``--angles`` of a planar file: crank angles in degrees, or a linear driver's slide
    positions in mm, to SI [rad or m]."""
    drivers = doc.drivers
    if len(drivers) > 1:
        raise ParameterError("--angles", text, f"gives one driver's positions; this file has "
                             f"{len(drivers)} drivers, whose tables run at 12 positions along "
                             "their path (each [[driver]]'s start to stop)")
    if drivers[0].type == "linear":
        return np.array(parse_angles_deg(text, angles=False)) * 1e-3
    return parse_angles(text)


def output_dir(out: Path) -> Path:
    """Create the output folder ``--out`` (with parents) and check that files can be written
    into it, before any work; else a ParameterError naming it: an existing file of that name,
    a folder that cannot be created, or one that cannot be written into (permissions,
    read-only disk: found before the study, not at its first file)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise ParameterError("--out", str(out), "must be a folder; a file of that name "
                             "exists") from None
    except OSError as exc:
        raise ParameterError("--out", str(out), f"cannot be created as a folder "
                             f"({exc.strerror or exc})") from None
    try:  # a real file, removed at once: os.access ignores read-only mounts
        with tempfile.TemporaryFile(dir=out, prefix=".linkwork-probe-"):
            pass
    except OSError as exc:
        raise ParameterError("--out", str(out), f"cannot be written into "
                             f"({exc.strerror or exc})") from None
    return out


_TCP_ADDRESS = re.compile(r"(?:tcp://)?\[?(?P<host>[^\[\]/]+?)\]?(?::(?P<port>[0-9]{1,5}))?")


def reach_scheduler(address: str | None, option: str = "--scheduler",
                    timeout: float = 5.0) -> None:
    """Check that a dask scheduler at ``address`` (already well-formed,
    :func:`linkwork.sweep.check_client`) accepts a connection, before any work: an
    unreachable one was found after the other outputs were written (dask waits 30 s). Only
    plain TCP addresses (``tcp://`` or no scheme; port 8786 if none) are probed; a
    ParameterError naming ``option`` if the connection fails."""
    m = None if address is None else _TCP_ADDRESS.fullmatch(address)
    if m is None:
        return
    try:
        with socket.create_connection((m["host"], int(m["port"] or 8786)), timeout=timeout):
            pass
    except OSError as exc:
        why = exc.strerror or str(exc) or type(exc).__name__
        raise ParameterError(option, address, f"cannot be reached ({why})") from None


def _stat(path: Path) -> dict[str, int] | None:
    """Size and modification time of a regular file (not following links), or None."""
    try:
        st = path.lstat()
    except OSError:
        return None
    if not stat.S_ISREG(st.st_mode):
        return None
    return {"bytes": st.st_size, "mtime_ns": st.st_mtime_ns}


def _plain_name(name: Any) -> bool:
    """A file name of the folder itself (never a path out of it, never the manifest)."""
    return (isinstance(name, str) and name not in ("", ".", "..", MANIFEST)
            and os.sep not in name and "/" not in name and (os.altsep or "/") not in name)


def _read_manifest(folder: Path) -> dict[str, dict[str, Any]]:
    """The runs recorded in ``folder`` (command -> record); {} if none or unreadable (a
    damaged record only means that nothing is removed)."""
    try:
        data = json.loads((folder / MANIFEST).read_text())
        runs = data["runs"]
        out: dict[str, dict[str, Any]] = {}
        for command, run in runs.items():
            files = {f["name"]: {"bytes": int(f["bytes"]), "mtime_ns": int(f["mtime_ns"])}
                     for f in run["files"] if _plain_name(f["name"])}
            out[str(command)] = {**run, "files": files}
        return out
    except (OSError, ValueError, TypeError, KeyError, AttributeError):
        return {}


def _write_manifest(folder: Path, runs: dict[str, dict[str, Any]]) -> None:
    data = {"about": "files written here by linkwork, per command (removed by the next run of "
                     "the same command if it does not write them again and they are unchanged)",
            "runs": {cmd: {**run, "files": [{"name": n, **st} for n, st in run["files"].items()]}
                     for cmd, run in runs.items() if run["files"]}}
    write_json(folder / MANIFEST, data)


#: The tables of a planar file whose entries become the engine's loads.
_LOAD_TABLES = ("load", "spring", "damper")


@contextlib.contextmanager
def load_errors(file: Path, doc: Any) -> Iterator[None]:
    """A load's error raised while a command works on the planar file ``doc`` (a load diagram
    the analysis leaves with ``outside = "error"``, a spring whose points meet at some
    position) as the file's error: its file and its key as the file writes it
    (:meth:`PlanarFile.file_error`: ``spring.0``, ``load.1.diagram.table``)."""
    try:
        yield
    except ParameterError as exc:
        if not isinstance(doc, PlanarFile):
            raise
        err = doc.file_error(exc)
        if err.parameter.split(".")[0] not in _LOAD_TABLES:
            raise
        raise FileFormatError(str(file), err.parameter,
                              str(err).removeprefix(f"{err.parameter} = ")) from None


@contextlib.contextmanager
def output_run(out: Path, *, command: str, file: Path | None = None) -> Iterator[Path]:
    """Run a command that writes into the output folder ``out``: check it (:func:`output_dir`),
    record the files written inside the block in :data:`MANIFEST`, and at the end remove the
    stale files of the previous run of ``command`` there (listed by it, not written again,
    unchanged since), saying so in one line. A failed or interrupted run removes nothing; the
    files it completed are added to the record."""
    folder = output_dir(out)
    runs = _read_manifest(folder)
    before = runs.get(command, {}).get("files", {})
    here = folder.resolve()
    complete = False
    with recording() as written:
        try:
            yield folder
            complete = True
        finally:
            mine = {p.name: st for p in dict.fromkeys(written)
                    if p.parent.resolve() == here and _plain_name(p.name)
                    and (st := _stat(p)) is not None}
            if complete or mine:
                _record(folder, runs, command, file, before, mine, complete)


def _record(folder: Path, runs: dict[str, dict[str, Any]], command: str, file: Path | None,
            before: dict[str, dict[str, int]], mine: dict[str, dict[str, int]],
            complete: bool) -> None:
    for run in runs.values():  # a file belongs to the run that wrote it last
        run["files"] = {n: st for n, st in run["files"].items() if n not in mine}
    files = dict(mine)
    removed: list[str] = []
    for name, st in before.items():
        if name in mine or _stat(folder / name) != st:
            continue  # written again, or gone, or changed since (then not ours to remove)
        if complete:
            with contextlib.suppress(FileNotFoundError):
                (folder / name).unlink()
            removed.append(name)
        else:
            files[name] = st  # a partial run: the earlier files stay on record
    runs[command] = {"command": command, "file": None if file is None else str(file),
                     "time": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
                     "complete": complete, "files": files}
    _write_manifest(folder, runs)
    if removed:
        print(f"removed {len(removed)} stale file{'s' if len(removed) > 1 else ''} of the "
              f"previous '{command}' run in {folder} (not written by this run): "
              + ", ".join(removed))
