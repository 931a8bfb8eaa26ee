"""The engine's compiled backend (optional: ``pip install 'linkwork[numba]'``).

``backend="numba"`` in :func:`~linkwork.planar.kinematics` and
:func:`~linkwork.planar.inverse_dynamics` runs the plans it covers through kernels compiled by
numba, one pass over the positions (and designs) per call instead of one NumPy pass per
operation; the NumPy path stays the default and the reference the compiled kernels are tested
against. numba is imported only when the compiled backend is asked for, so ``import linkwork``
stays light.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from linkwork.errors import MissingExtraError, ParameterError

__all__ = ["BACKENDS", "NUMBA_INSTALL", "check_backend", "check_threads", "numba_module"]

#: The engine's backends: ``"numpy"`` (the default and the reference) and ``"numba"``.
BACKENDS = ("numpy", "numba")
NUMBA_INSTALL = "pip install 'linkwork[numba]'"


def numba_module() -> Any:
    """The numba module, or :class:`~linkwork.errors.MissingExtraError` naming the extra."""
    try:
        import numba
    except ImportError:
        raise MissingExtraError('backend="numba"', "numba", NUMBA_INSTALL) from None
    return numba


def check_backend(backend: Any, *, option: str = "backend") -> str:
    """``backend`` checked: one of :data:`BACKENDS` (else a ParameterError naming ``option``);
    ``"numba"`` also needs numba installed (else a MissingExtraError naming the extra)."""
    if not isinstance(backend, str) or backend not in BACKENDS:
        raise ParameterError(option, backend, f"must be one of {', '.join(map(repr, BACKENDS))}")
    if backend == "numba":
        numba_module()
    return backend


def check_threads(threads: Any, backend: str) -> int:
    """``threads`` checked: an integer >= 1; above 1 only with ``backend="numba"`` and at most
    numba's thread count (``NUMBA_NUM_THREADS``, by default the machine's CPUs); else a
    ParameterError naming ``threads``, its value and the limit."""
    if isinstance(threads, bool) or not isinstance(threads, int | np.integer) or threads < 1:
        raise ParameterError("threads", threads, "must be an integer >= 1")
    if threads > 1 and backend != "numba":
        raise ParameterError("threads", threads, "needs backend='numba' (the NumPy path runs "
                             "on one thread)")
    if threads > 1:
        limit = int(numba_module().config.NUMBA_NUM_THREADS)
        if threads > limit:
            raise ParameterError("threads", threads, f"must be at most {limit}, numba's "
                                 "thread count (NUMBA_NUM_THREADS)")
    return int(threads)
