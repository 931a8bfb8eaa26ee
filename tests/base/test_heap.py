"""linkwork.heap: glibc's heap thresholds inside a worker's tasks and for a whole process."""

import os
import subprocess
import sys

import pytest

_FAULTS = r"""
import resource, numpy as np
from linkwork.heap import roomy_heap

def faults(f):
    f()
    a = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    f()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - a

x = np.random.default_rng(0).normal(size=500_000)   # 4 MB

def temporaries():
    for _ in range(40):
        y = np.sin(x) * 2.0 + x     # three 4 MB temporaries per pass
        y.sum()

def inside():
    with roomy_heap():
        temporaries()

print(faults(temporaries), faults(inside), faults(temporaries))
"""


@pytest.mark.parametrize("env", [{"MALLOC_TRIM_THRESHOLD_": "65536"},
                                 {"MALLOC_MMAP_THRESHOLD_": "131072"}])
def test_roomy_heap_reuses_memory_under_fixed_malloc_thresholds(env):
    """With dask's worker setting ``MALLOC_TRIM_THRESHOLD_=65536`` (or a fixed mmap
    threshold) every 4 MB NumPy temporary is a fresh mmap, about 1000 page faults each (39 000
    measured for 40 passes, against 1 900 with glibc's adaptive thresholds). Inside
    ``roomy_heap`` the heap is reused (faults of about one pass); after it the environment's
    setting holds again. Page faults counted by getrusage
    in a fresh interpreter (glibc; the environment is read at its start)."""
    import os
    import subprocess
    import sys

    if not sys.platform.startswith("linux"):
        pytest.skip("glibc malloc thresholds")
    res = subprocess.run([sys.executable, "-c", _FAULTS], capture_output=True, text=True,
                         env={**os.environ, **env}, check=True, timeout=120)
    before, inside, after = (int(v) for v in res.stdout.split())
    assert before > 20_000 and after > 20_000
    assert inside < 4_000


def test_roomy_heap_looks_up_the_c_library_once(monkeypatch):
    """``roomy_heap`` wraps every task on a worker; it found glibc anew each time, and
    ``ctypes.util.find_library`` runs ``ldconfig -p`` in a subprocess (4-8 ms of fork and exec
    per task measured, in a process the worker's CPU count does not include). Now the library
    is looked up once per process, among the symbols already loaded: ten blocks, one load and
    no ``find_library``."""
    import ctypes
    import ctypes.util

    import linkwork.heap as heap

    loads, finds = [], []
    real_cdll, real_find = ctypes.CDLL, ctypes.util.find_library
    monkeypatch.setattr(ctypes, "CDLL", lambda name: (loads.append(name), real_cdll(name))[1])
    monkeypatch.setattr(ctypes.util, "find_library",
                        lambda name: (finds.append(name), real_find(name))[1])
    monkeypatch.setenv("MALLOC_TRIM_THRESHOLD_", "65536")
    heap._libc.cache_clear()
    try:
        for _ in range(10):
            with heap.roomy_heap():
                pass
    finally:
        heap._libc.cache_clear()
    assert loads == [None] and finds == []


_PROCESS = r"""
import resource, sys
import numpy as np
from linkwork.heap import roomy_process_heap

x = np.random.default_rng(0).normal(size=(2048, 720))   # 11.8 MB

def work():
    for _ in range(10):
        a = np.sin(x)
        b = np.cos(x) * a
        c = np.stack([a, b, a * b])   # 35 MB: above any mmap threshold
        del a, b
        c.sum(axis=0).max()
        del c

def faults():
    a = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    work()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - a

work()
before = faults()
done = roomy_process_heap()
work()
print(int(done), before, faults())
"""


def test_roomy_process_heap_fixes_the_thresholds_unless_the_environment_sets_them():
    """glibc's adaptive thresholds leave NumPy temporaries of 12 MB beside blocks of 35 MB to
    fresh mmaps and trims (19,530 faults a pass measured); fixed at 32 / 64 MiB the heap keeps
    them (4,650: the 35 MB blocks alone). Where the environment sets a threshold nothing
    changes, and the call says so."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}
    res = subprocess.run([sys.executable, "-c", _PROCESS], capture_output=True, text=True,
                         env=env, check=True, timeout=120)
    done, before, after = (int(v) for v in res.stdout.split())
    assert done == 1 and after < 0.5 * before
    res = subprocess.run([sys.executable, "-c", _PROCESS], capture_output=True, text=True,
                         env={**env, "MALLOC_TRIM_THRESHOLD_": "65536"}, check=True,
                         timeout=120)
    done, before, after = (int(v) for v in res.stdout.split())
    assert done == 0 and after > 0.5 * before
