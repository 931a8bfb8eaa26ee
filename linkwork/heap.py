"""glibc's heap thresholds for bulk NumPy work: inside a Dask worker's tasks
(:func:`roomy_heap`) and for a whole process linkwork owns (:func:`roomy_process_heap`).

Worker malloc settings
----------------------
dask's worker launcher (the nanny) sets ``MALLOC_TRIM_THRESHOLD_=65536`` in every worker
process it starts (dask config ``distributed.nanny.pre-spawn-environ``), so that the workers
give freed memory back to the system. That setting also fixes glibc's ``mmap`` threshold at
128 kB: every NumPy temporary of more than 128 kB becomes a fresh ``mmap`` and every page of it
a page fault, and the freed top of the heap is returned at once. A NumPy kernel that makes
multi-megabyte temporaries then runs 1.5-3x slower on such a worker than in the user's own
process. Two remedies: the library's hottest kernel (the tolerance study's) works in
preallocated buffers, and every task that runs on a cluster (:mod:`linkwork.sweep`) runs inside
:func:`roomy_heap`,
which raises the two glibc thresholds while the task's chunks run and restores the
environment's values (and trims the heap) afterwards, so that the worker gives its memory back
between tasks as its operator asked. Nothing is needed from whoever starts the cluster;
unsetting the variable (``distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_``)
changes nothing for linkwork. The worker settings that do matter: ``docs/dask.md``.

A process of its own
--------------------
Without those variables glibc adapts its thresholds to the blocks a process frees; in bulk
NumPy work they stay low (:func:`roomy_process_heap`). The command line fixes them at the
ceiling of glibc's own adaptation; a library call leaves its caller's heap alone.

This module imports nothing heavier than ``ctypes`` (the command line imports it at start).
"""

from __future__ import annotations

import ctypes
import functools
import os
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["PROCESS_MMAP_THRESHOLD", "PROCESS_TRIM_THRESHOLD", "ROOMY_MMAP_THRESHOLD",
           "ROOMY_TRIM_THRESHOLD", "roomy_heap", "roomy_process_heap"]


#: mallopt(3) parameters of glibc
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
#: While a chunk runs: temporaries up to this size come from the heap, not from fresh mmaps
#: (the largest value glibc accepts on 64-bit systems) ...
ROOMY_MMAP_THRESHOLD = 32 * 2**20
#: ... and up to this much freed memory stays in the heap until the chunk is done.
ROOMY_TRIM_THRESHOLD = 512 * 2**20
#: glibc's default mmap and trim thresholds (what it starts from when the environment does
#: not set them)
_GLIBC_DEFAULT = 128 * 1024


def _find_libc() -> str:
    import ctypes.util  # (imports shutil, subprocess and tempfile: 9 ms, only when needed)

    return ctypes.util.find_library("c") or "libc.so.6"


@functools.cache
def _libc() -> Any:
    """glibc's ``mallopt`` and ``malloc_trim``, or None (another C library or system); looked
    up once per process, first among the symbols the process has loaded (``dlopen(NULL)``,
    30 us), else by ``ctypes.util.find_library`` (it runs ``ldconfig -p`` in a subprocess:
    4-8 ms measured, which every chunk on a worker paid before)."""
    if not sys.platform.startswith("linux"):
        return None
    for where in (lambda: None, _find_libc):
        try:
            libc = ctypes.CDLL(where())
            libc.gnu_get_libc_version  # noqa: B018  (glibc only: musl has no mallopt)
            libc.mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
            libc.malloc_trim.argtypes = [ctypes.c_size_t]
            return libc
        except (OSError, AttributeError):
            continue
    return None


#: glibc's heap thresholds of a whole process that linkwork owns (the command line,
#: :func:`roomy_process_heap`): the ceiling of glibc's own adaptive ones (an mmap threshold
#: that rises with the blocks freed, up to 32 MiB on 64-bit systems, and a trim threshold of
#: twice it), fixed there from the start.
PROCESS_MMAP_THRESHOLD = 32 * 2**20
PROCESS_TRIM_THRESHOLD = 64 * 2**20


def roomy_process_heap() -> bool:
    """Fix glibc's heap thresholds of this process at :data:`PROCESS_MMAP_THRESHOLD` and
    :data:`PROCESS_TRIM_THRESHOLD`; return whether they were set.

    glibc adapts its thresholds to the blocks a process frees, but in linkwork's bulk work
    (NumPy temporaries of a few to tens of MB, some above 32 MB) they stay low: the swash-plate
    screening of 16,384 candidates in one process took 2.2 million page faults and 6.1-6.5 s,
    with the thresholds fixed here 36,000 faults and 4.9-5.0 s at the same peak memory
    (164 / 166 MB); ``linkwork swashplate synthesize --candidates 16384`` 9.46 s -> 8.42 s
    (median of 5, peak 197 -> 222 MiB). For a process linkwork owns (the command line calls
    it) or a script of bulk studies; a library call does not change its caller's heap. Nothing
    is changed where the environment sets ``MALLOC_TRIM_THRESHOLD_`` or
    ``MALLOC_MMAP_THRESHOLD_`` (the user's or Dask's choice: :func:`roomy_heap` handles the
    blocks of a worker) or the C library is not glibc.
    """
    if (_env_threshold("MALLOC_TRIM_THRESHOLD_") is not None
            or _env_threshold("MALLOC_MMAP_THRESHOLD_") is not None):
        return False
    libc = _libc()
    if libc is None:
        return False
    libc.mallopt(_M_MMAP_THRESHOLD, PROCESS_MMAP_THRESHOLD)
    libc.mallopt(_M_TRIM_THRESHOLD, PROCESS_TRIM_THRESHOLD)
    return True


def _env_threshold(name: str) -> int | None:
    """The byte count a ``MALLOC_*_`` environment variable sets, or None."""
    raw = os.environ.get(name)
    try:
        return int(raw) if raw is not None else None
    except ValueError:
        return None


_heap_lock = threading.Lock()
_heap_users = 0


@contextmanager
def roomy_heap() -> Iterator[None]:
    """Let NumPy temporaries reuse heap memory while the block runs, whatever the process's
    ``MALLOC_TRIM_THRESHOLD_`` / ``MALLOC_MMAP_THRESHOLD_``.

    Where the environment sets one of the two (dask's worker launcher sets
    ``MALLOC_TRIM_THRESHOLD_=65536``), glibc's thresholds are fixed: each temporary above
    128 kB is a fresh ``mmap`` with a page fault per page. Inside this block they are raised to
    :data:`ROOMY_MMAP_THRESHOLD` / :data:`ROOMY_TRIM_THRESHOLD`; when the last of the threads
    inside leaves, they are set back to what the environment asked (or glibc's defaults) and
    ``malloc_trim(0)`` returns the freed memory to the system, as that setting intends.
    Without either variable (glibc's adaptive thresholds, the usual interactive process),
    and where glibc is absent, it does nothing.
    """
    global _heap_users
    trim = _env_threshold("MALLOC_TRIM_THRESHOLD_")
    mmap = _env_threshold("MALLOC_MMAP_THRESHOLD_")
    libc = _libc() if (trim is not None or mmap is not None) else None
    if libc is None:
        yield
        return
    with _heap_lock:
        _heap_users += 1
        if _heap_users == 1:
            libc.mallopt(_M_MMAP_THRESHOLD, ROOMY_MMAP_THRESHOLD)
            libc.mallopt(_M_TRIM_THRESHOLD, ROOMY_TRIM_THRESHOLD)
    try:
        yield
    finally:
        with _heap_lock:
            _heap_users -= 1
            if _heap_users == 0:
                libc.mallopt(_M_MMAP_THRESHOLD, _GLIBC_DEFAULT if mmap is None else mmap)
                libc.mallopt(_M_TRIM_THRESHOLD, _GLIBC_DEFAULT if trim is None else trim)
                libc.malloc_trim(0)
