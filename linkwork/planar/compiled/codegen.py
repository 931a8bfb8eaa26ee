"""Kernels generated per plan: Python source written once, compiled by numba, cached on disk.

A generated kernel is the plan interpreter unrolled: every decision that depends only on the
plan's structure (its joints' kinds and bodies, its groups' kinds, bodies and joints) is taken
while the source is written, each body's state is a set of local variables rather than rows of
an array, and each design's geometry is read once before its positions. The arithmetic is the
helpers' own (the generated code calls them with the structure's constants), so the results
are those of the interpreter, bit for bit; the kernel runs about twice as fast (measured on the
four-bar at 10^5 positions: 11.3 against 20 ms; see docs/performance.md).

:func:`load` writes the source to a file named by its hash in the kernel directory (once; a
file that exists is not rewritten, so numba's cache of it stays valid) and imports it; numba
caches the compiled machine code beside it, so a structure is compiled once per machine, not
once per process. The directory is ``$LINKWORK_CACHE_DIR/kernels``, else
``$XDG_CACHE_HOME/linkwork/kernels``, else ``~/.cache/linkwork/kernels``; where it cannot be
written, a temporary directory of the process is used (compiled again in each process).

The source names the hash of the helpers' modules in its first line: a new version of a helper
gives new files, never a stale compiled kernel (numba's cache checks the time stamp of the
kernel's own file only, not of the functions it calls).
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile
import threading
from collections.abc import Callable, Hashable, Mapping
from pathlib import Path
from types import ModuleType
from typing import Any

__all__ = ["Source", "call", "choose_dir", "decorator", "fingerprint", "kernel_dir", "load",
           "loop", "structure_kernel"]

_LOADED: dict[str, Callable[..., Any]] = {}
_BY_STRUCTURE: dict[tuple[str, Hashable], Callable[..., Any]] = {}
_DIR: list[Path] = []
#: parallel kernels run one at a time: numba's fallback threading layer (workqueue, where
#: neither OpenMP nor TBB is installed) aborts the process on concurrent launches
_PARALLEL = threading.Lock()
_LOADING = threading.Lock()


class Source:
    """Python source written line by line, indented by blocks."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self.depth = 0

    def __call__(self, *lines: str) -> None:
        self.lines.extend("    " * self.depth + line for line in lines)

    def indent(self, k: int = 1) -> None:
        self.depth += k

    def text(self) -> str:
        return "\n".join(self.lines) + "\n"


def kernel_dir() -> Path:
    """The directory of the generated kernels (chosen once per process: :func:`choose_dir`)."""
    if not _DIR:
        _DIR.append(choose_dir(os.environ))
    return _DIR[0]


def choose_dir(environ: Mapping[str, str]) -> Path:
    """The kernel directory for the environment ``environ`` (see the module docstring),
    created; a new temporary directory where it cannot be written."""
    base = environ.get("LINKWORK_CACHE_DIR")
    if base:
        path = Path(base) / "kernels"
    else:
        xdg = environ.get("XDG_CACHE_HOME")
        path = (Path(xdg) if xdg else Path.home() / ".cache") / "linkwork" / "kernels"
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".probe-{os.getpid()}"
        probe.write_text("")
        probe.unlink()
    except OSError:
        path = Path(tempfile.mkdtemp(prefix="linkwork-kernels-"))
    return path


def fingerprint(*modules: ModuleType) -> str:
    """A hash of the source files of ``modules`` (the helpers a generated kernel calls)."""
    h = hashlib.sha256()
    for mod in modules:
        h.update(Path(mod.__file__ or "").read_bytes())
    return h.hexdigest()[:16]


def structure_kernel(prefix: str, key: Hashable, source: Callable[[], str]) -> Any:
    """The kernel of the plan structure ``key`` (its tables as bytes, and whether parallel):
    ``load(prefix, source())`` the first time, the same function after, without writing the
    source again (a new mechanism of a known structure, e.g. a design changed by a solver,
    costs a dictionary look-up, not the ~0.2 ms of writing its kernel's source)."""
    try:
        return _BY_STRUCTURE[prefix, key]
    except KeyError:
        fn = _BY_STRUCTURE[prefix, key] = load(prefix, source())
        return fn


def load(prefix: str, source: str, name: str = "kernel", directory: Path | None = None
         ) -> Callable[..., Any]:
    """The function ``name`` of the module ``source`` (written to ``directory``, by default
    :func:`kernel_dir`, as ``_linkwork_<prefix>_<hash>.py`` unless it is there with this
    source, then imported; once per process and source)."""
    key = hashlib.sha256(source.encode()).hexdigest()[:24]
    try:
        return _LOADED[key]
    except KeyError:
        pass
    with _LOADING:  # one thread of the process writes and imports a kernel, the others wait
        if key in _LOADED:
            return _LOADED[key]
        modname = f"_linkwork_{prefix}_{key}"
        path = (directory or kernel_dir()) / f"{modname}.py"
        if not path.exists() or path.read_text() != source:
            # a file of its own, then renamed: a process beside this one reads all or none
            fd, tmp = tempfile.mkstemp(suffix=".tmp", prefix=f"{modname}.", dir=path.parent)
            with os.fdopen(fd, "w") as f:
                f.write(source)
            os.replace(tmp, path)
        spec = importlib.util.spec_from_file_location(modname, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[modname] = module
        spec.loader.exec_module(module)
        fn: Callable[..., Any] = getattr(module, name)
        _LOADED[key] = fn
        return fn


def decorator(parallel: bool) -> str:
    """The generated kernels' compilation: cached on disk, IEEE arithmetic (no fastmath),
    NumPy's error model (a division by zero gives inf or NaN, as in the NumPy path); with
    ``parallel``, the outer loop (:func:`loop`) shared among numba's threads."""
    return f'@njit(cache=True, error_model="numpy"{", parallel=True" if parallel else ""})'


def loop(parallel: bool) -> str:
    """The outer loop of a generated kernel: ``prange`` in a parallel one."""
    return "prange" if parallel else "range"


def call(fn: Callable[..., Any], threads: int, *args: Any) -> None:
    """``fn(*args)``: a parallel kernel on ``threads`` of numba's threads (one such call at a
    time in the process), a serial one (``threads`` 1) as it is."""
    if threads == 1:
        fn(*args)
        return
    import numba

    with _PARALLEL:
        before = numba.get_num_threads()
        numba.set_num_threads(threads)
        try:
            fn(*args)
        finally:
            numba.set_num_threads(before)
