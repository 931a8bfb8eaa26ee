"""Monte-Carlo tolerance study of the spatial reactions caused by manufacturing deviations.

The reactions are affine in the deviations (first-order theory, :mod:`linkwork.redundancy.core`):
``r = r0 + H delta_c``, with ``r0`` and ``H`` computed once per position by the force method.
A study draws ``N`` samples of the deviations from their tolerance distributions, maps them to
misfits and reactions for all positions at once (vectorised over samples and positions) and keeps
the peak over the cycle of every reaction component of every joint. Samples are processed in
chunks through :func:`linkwork.sweep.evaluate`: in-process by default, on a dask.distributed
cluster when a client or scheduler address is given. The random draws are made up front from one
seeded generator, so the result does not depend on chunking or on the cluster.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_positive
from linkwork.errors import ParameterError
from linkwork.redundancy.core import (
    COMPONENTS,
    SpatialGeometry,
    SpatialModel,
    _joint_frames,
    check_tilt,
    influence,
    misfit,
)
from linkwork.results import Result, write_json
from linkwork.sweep import evaluate

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["CHUNK_SAMPLES", "MEMORY_BUDGET", "PEAK_QUANTITIES", "Tolerance", "ToleranceStudy",
           "affine_blocks", "affine_map", "check_samples", "max_samples", "sample_bytes",
           "tolerance_study"]

#: Quantities whose peak over the cycle is kept per joint: the six components and the bending
#: moment magnitude sqrt(mx² + my²).
PEAK_QUANTITIES: tuple[str, ...] = (*COMPONENTS, "bending")

_DEV_COMPONENTS = ("dx", "dy", "dz", "tx", "ty", "tz")


@dataclass(frozen=True)
class Tolerance:
    """Tolerance of one deviation component of one joint element.

    Parameters
    ----------
    joint : str
        Joint name.
    side : {"a", "b"}
        The element on the joint's body a or body b.
    component : {"dx", "dy", "dz", "tx", "ty", "tz"}
        Offset [m] or tilt [rad], in that body's frame.
    limit : float
        Tolerance half-width (>= 0): for ``"normal"`` the deviation is N(mean, (limit/3)²)
        (``limit`` = 3 sigma); for ``"uniform"`` it is U(mean - limit, mean + limit).
    distribution : {"normal", "uniform"}
    mean : float
        Systematic part of the deviation.
    """

    joint: str
    side: str
    component: str
    limit: float
    distribution: str = "normal"
    mean: float = 0.0

    def __post_init__(self) -> None:
        if self.side not in ("a", "b"):
            raise ParameterError(f"tolerance {self.joint}.side", self.side, "must be 'a' or 'b'")
        if self.component not in _DEV_COMPONENTS:
            raise ParameterError(f"tolerance {self.joint}.component", self.component,
                                 f"must be one of {list(_DEV_COMPONENTS)}")
        if self.distribution not in ("normal", "uniform"):
            raise ParameterError(f"tolerance {self.joint}.distribution", self.distribution,
                                 "must be 'normal' or 'uniform'")
        require_positive(f"tolerance {self.joint}.{self.component}.limit", self.limit,
                         allow_zero=True)
        require_finite(f"tolerance {self.joint}.{self.component}.mean", self.mean)
        if self.component.startswith("t"):  # the deviations drawn must stay small tilts
            check_tilt(f"tolerance {self.joint}.{self.component}: |mean| + limit",
                       abs(self.mean) + self.limit)


@dataclass(frozen=True)
class ToleranceStudy(Result):
    """Peaks over the cycle of the spatial reactions for N Monte-Carlo samples of deviations.

    Attributes
    ----------
    joints : tuple of str
    quantities : tuple of str
        :data:`PEAK_QUANTITIES` (axis 2 of ``peaks``).
    peaks : ndarray, shape (N, n_joints, 7)
        Peak |value| over the cycle per sample [N or N·m]; ``bending`` is sqrt(mx² + my²).
    nominal : ndarray, shape (n_joints, 7)
        The same peaks without deviations.
    draws : ndarray, shape (N, n_tolerances)
        The sampled deviations [m, rad].
    tolerances : tuple of Tolerance
    seed : int or None
    """

    joints: tuple[str, ...]
    quantities: tuple[str, ...]
    peaks: np.ndarray
    nominal: np.ndarray
    draws: np.ndarray
    tolerances: tuple[Tolerance, ...]
    seed: int | None
    units: ClassVar[dict[str, str]] = {"fx": "N", "fy": "N", "fz": "N", "mx": "N*m",
                                       "my": "N*m", "mz": "N*m", "bending": "N*m"}

    @property
    def n_samples(self) -> int:
        """Number of samples N."""
        return int(self.peaks.shape[0])

    def sample(self, joint: str, quantity: str = "bending") -> np.ndarray:
        """Peaks of one quantity of one joint over the samples, shape (N,)."""
        if joint not in self.joints:
            raise ParameterError("joint", joint, f"must be one of {list(self.joints)}")
        if quantity not in self.quantities:
            raise ParameterError("quantity", quantity, f"must be one of {list(self.quantities)}")
        return self.peaks[:, self.joints.index(joint), self.quantities.index(quantity)]

    def percentiles(self, q: Sequence[float] = (50.0, 95.0, 99.0)) -> dict[str, Any]:
        """Percentiles of every peak: {joint: {quantity: {"p50": ..., ...}}} plus nominal."""
        qs = [float(v) for v in q]
        vals = np.percentile(self.peaks, qs, axis=0)   # (len(q), nj, 7)
        out: dict[str, Any] = {}
        for j, name in enumerate(self.joints):
            out[name] = {
                qu: {"nominal": float(self.nominal[j, k]),
                     **{f"p{v:g}": float(vals[i, j, k]) for i, v in enumerate(qs)}}
                for k, qu in enumerate(self.quantities)}
        return out

    def to_json(self, path: str | Path, q: Sequence[float] = (50.0, 95.0, 99.0)) -> Path:
        """Write the percentiles, the tolerances and N as JSON; return the path."""
        data = {"type": "ToleranceStudy", "n_samples": self.n_samples, "seed": self.seed,
                "units": {"f*": "N", "m*": "N*m", "bending": "N*m"},
                "tolerances": [t.__dict__ for t in self.tolerances],
                "percentiles": self.percentiles(q)}
        return write_json(path, data)

    def columns(self) -> dict[str, np.ndarray]:
        """One column per joint and quantity, ``<quantity>_<joint>`` (``bending_B``), one row per
        sample: what :meth:`to_csv` writes (through :meth:`Result.to_csv`) and
        :meth:`to_frame` returns."""
        return {f"{qu}_{j}": self.peaks[:, jj, k]
                for jj, j in enumerate(self.joints) for k, qu in enumerate(self.quantities)}

    def _unit_of(self, column: str) -> str:
        return self.units.get(column.split("_")[0], "")

    def plot(self, quantity: str = "bending", axes: Any = None, **kw: Any) -> Figure:
        """Histograms of the peak ``quantity`` over the samples, one axes per joint: a
        :class:`linkwork.plot.Figure` (:func:`linkwork.plot.redundancy.plot_peak_histogram`)."""
        from linkwork.plot.redundancy import tolerance_figure

        return tolerance_figure(self, quantity, axes=axes, **kw)


def _global(model: SpatialModel, frames: list[np.ndarray], r: np.ndarray) -> np.ndarray:
    """Local unknowns (..., n, m+1) -> global components (..., n_joints, 6, n)."""
    lead = r.shape[:-2]
    n = r.shape[-2]
    out = np.zeros((*lead, len(model.joints), 6, n))
    k = 0
    for j, jt in enumerate(model.joints):
        loc = np.zeros((*lead, n, 6))
        sel = list(jt.constrained)
        loc[..., sel] = r[..., k:k + len(sel)]
        k += len(sel)
        if j in model.driver_indices:
            m = r.shape[-1] - model.n_drivers
            loc[..., 5 if jt.family == "R" else 0] += r[..., m + model.driver_indices.index(j)]
        out[..., j, :, :] = np.swapaxes(np.einsum("nij,...nj->...ni", frames[j], loc), -1, -2)
    return out


def _peaks(comp: np.ndarray) -> np.ndarray:
    """(..., nj, 6, n) -> (..., nj, 7) peak |.| over positions, bending last."""
    p = np.max(np.abs(comp), axis=-1)
    bend = np.max(np.hypot(comp[..., 3, :], comp[..., 4, :]), axis=-1)
    return np.concatenate([p, bend[..., None]], axis=-1)


#: Samples per chunk of a tolerance study (the unit of work of a Dask cluster and of the
#: progress bar): a chunk costs a worker about 0.15 s, some 30x the per-task overhead of a
#: cluster (measured on a 2-process LocalCluster at 10^5 samples: 0.40 s of client and 0.92-0.97
#: s of worker CPU in chunks of 2000, 0.25-0.30 s and 0.77-0.90 s in chunks of 10 000); in
#: process the size does not matter (the kernel works in blocks of KERNEL_BLOCK).
CHUNK_SAMPLES = 10_000
#: On a cluster, at least this many chunks per worker thread (smaller ones where needed, none
#: below MIN_CLUSTER_CHUNK samples): short last tasks balance the workers (the peaks do not
#: depend on the chunking). 10^5 samples on 2 workers: 32 chunks of 3125, 1.58-1.65x
#: in-process against 1.47-1.84x with 10 chunks of 10,000 (docs/performance.md)
CLUSTER_CHUNKS = 16
MIN_CLUSTER_CHUNK = 1_000

#: Samples per block of the peak kernel: a block's reactions (positions x 6 n_joints x block,
#: 4.4 MB for 360 positions and 4 joints) live in one buffer reused by every block of a chunk.
KERNEL_BLOCK = 64
#: Elements of NumPy's ufunc buffers in the peak kernel (its default, 8192, makes 64-132 kB
#: buffers for the strided moments: each freed at once under a Dask worker's malloc setting
#: and page-faulted back, 2x the kernel's time there).
UFUNC_BUFFER = 1024
#: Rows of the affine map (positions x components) per matrix product: products of at most
#: 240 x (n_tol + 1) x KERNEL_BLOCK stay under OpenBLAS's threshold for threads (a threaded
#: product on 2 shared cores ran 4-15x slower), and NumPy loops over them in C.
KERNEL_ROWS = 240


def affine_blocks(c0: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The affine map ``c = c0 + Z d`` as one matrix ``[Z | c0]``, rows (position, component)
    in order, split into blocks of :data:`KERNEL_ROWS` rows (the last one padded with zeros):
    shape ``(n_blocks, KERNEL_ROWS, n_tol + 1)``, the input the peak kernel shares among all
    chunks (scattered once to the workers of a cluster)."""
    n, m, k = z.shape
    rows = n * m
    nblk = -(-rows // KERNEL_ROWS)
    out = np.zeros((nblk * KERNEL_ROWS, k + 1))
    out[:rows, :k] = z.reshape(rows, k)
    out[:rows, k] = c0.reshape(rows)
    return out.reshape(nblk, KERNEL_ROWS, k + 1)


def _chunk(draws: np.ndarray, *, zb: np.ndarray, n: int, n_joints: int) -> np.ndarray:
    """Peaks (S, n_joints, 7) for a chunk of samples ``draws`` (S, n_tol) (module level so that
    Dask can pickle it).

    ``zb``: :func:`affine_blocks` of the global components without deviations ``c0``
    (n, 6 n_joints) and of their derivatives ``Z`` with respect to the sampled deviations
    (n, 6 n_joints, n_tol), over ``n`` positions. The chunk is the unit of work of Dask and of
    the progress bar; the kernel runs over it in blocks of :data:`KERNEL_BLOCK` samples, in
    buffers made once per thread (:func:`_workspace`) and reused by every block and chunk
    (``out=``), with NumPy's ufunc
    buffers held to :data:`UFUNC_BUFFER` elements: no block allocates more than a few kB, so
    the malloc settings of the process (a Dask worker's ``MALLOC_TRIM_THRESHOLD_``, under
    which a freed 64 kB buffer goes back to the system at once) do not slow it down.
    """
    # an array that came over the network (Dask) may be unaligned: matmul would copy it for
    # BLAS at every block (5 500 page faults a chunk, 1.7x the time on a worker); once here
    zb = np.require(zb, np.float64, ["C", "A"])
    S = draws.shape[0]
    k = zb.shape[2] - 1
    m = 6 * n_joints
    blk = KERNEL_BLOCK
    out = np.empty((S, n_joints, 7))
    comp, rhs, peak, low, bend, b2, t2 = _workspace(zb.shape[0], zb.shape[1], k, n, n_joints)
    rhs[k] = 1.0
    # (positions, joints, 6, block): a view of the rows that are not padding
    c = comp.reshape(-1, blk)[:n * m].reshape(n, n_joints, 6, blk)
    c2 = c.reshape(n, m, blk)
    mx, my = c[:, :, 3], c[:, :, 4]
    with np.errstate():  # (the ufunc buffer size is restored with the error state)
        np.setbufsize(UFUNC_BUFFER)
        for lo in range(0, S, blk):
            s = min(blk, S - lo)
            rhs[:k, :s] = draws[lo:lo + s].T
            rhs[:k, s:] = 0.0                             # a partial last block
            np.matmul(zb, rhs, out=comp)                  # c0 + Z d, batched over row blocks
            # peak |x| = max(max x, -min x): no |x| over every position
            np.max(c2, axis=0, out=peak)
            np.min(c2, axis=0, out=low)
            np.negative(low, out=low)
            np.maximum(peak, low, out=peak)
            # bending peak = sqrt of the peak of mx^2 + my^2 (one root per sample), into
            # contiguous buffers (squaring the strided mx in place made NumPy copy it)
            np.multiply(mx, mx, out=b2)
            np.multiply(my, my, out=t2)
            np.add(b2, t2, out=b2)
            np.max(b2, axis=0, out=bend)
            np.sqrt(bend, out=bend)
            o = out[lo:lo + s]
            o[:, :, :6] = peak[:, :s].reshape(n_joints, 6, s).transpose(2, 0, 1)
            o[:, :, 6] = bend[:, :s].T
    return out


_workspaces = threading.local()


def _workspace(nblk: int, rows: int, k: int, n: int, n_joints: int) -> tuple[np.ndarray, ...]:
    """The peak kernel's buffers for this shape, made once per thread and reused by every chunk
    after (6 MB for 360 positions and 4 joints): the block's components (nblk, rows, block),
    the right-hand side [draws^T; 1], the peaks, minima and bending peaks of a block, and
    ``mx^2 + my^2`` with its second term (contiguous). Chunk after chunk on a Dask worker,
    no buffer is freed and faulted back, whatever the worker's malloc settings."""
    key = (nblk, rows, k, n, n_joints, KERNEL_BLOCK)
    cache = getattr(_workspaces, "buffers", None)
    if cache is None or cache[0] != key:
        blk, m = KERNEL_BLOCK, 6 * n_joints
        bufs = (np.empty((nblk, rows, blk)), np.zeros((k + 1, blk)), np.empty((m, blk)),
                np.empty((m, blk)), np.empty((n_joints, blk)), np.empty((n, n_joints, blk)),
                np.empty((n, n_joints, blk)))
        _workspaces.buffers = cache = (key, bufs)
    return cache[1]


#: Memory budget of a tolerance study [bytes]: the draws (N x n_tolerances) and the peaks
#: (N x n_joints x 7) of all samples are kept in the result (the draws are made up front from
#: one seeded generator, so the result does not depend on the chunking), so N is refused above
#: :func:`max_samples`, the number whose arrays fit in this budget.
MEMORY_BUDGET = 2**30

#: Copies of the result's arrays alive at the peak (the chunks' peaks and their concatenation,
#: the draws); measured: ``linkwork reactions examples/loom_fourbar_spatial.toml
#: --tolerance-study 300000`` peaks 150 MB above 1000 samples, 500 B per sample for 4 joints
#: and 9 deviations against 592 B by this count.
_COPIES = 2


def sample_bytes(n_joints: int, n_tolerances: int) -> int:
    """Memory of one Monte-Carlo sample [bytes]: its draws and peaks, :data:`_COPIES` times."""
    return _COPIES * 8 * (7 * int(n_joints) + int(n_tolerances))


def max_samples(n_joints: int, n_tolerances: int) -> int:
    """The most samples of a tolerance study of ``n_joints`` joints and ``n_tolerances`` random
    deviations within :data:`MEMORY_BUDGET` (1 GiB): 1 813 753 for the 4 joints and 9
    deviations of ``examples/loom_fourbar_spatial.toml``."""
    return MEMORY_BUDGET // sample_bytes(n_joints, n_tolerances)


def check_samples(n_samples: Any, n_joints: int, n_tolerances: int,
                  parameter: str = "n_samples") -> int:
    """``n_samples`` as an int, or a :class:`~linkwork.errors.ParameterError` naming
    ``parameter``, the value and the limit: an integer >= 1 and at most :func:`max_samples`."""
    if isinstance(n_samples, bool) or int(n_samples) != n_samples or int(n_samples) < 1:
        raise ParameterError(parameter, n_samples, "must be an integer >= 1")
    limit = max_samples(n_joints, n_tolerances)
    if int(n_samples) > limit:
        per = sample_bytes(n_joints, n_tolerances)
        raise ParameterError(
            parameter, n_samples,
            f"at most {limit} samples for {n_joints} joints and {n_tolerances} deviations "
            f"({per} bytes per sample kept: {int(n_samples) * per / 2**30:.3g} GiB asked, "
            f"{MEMORY_BUDGET / 2**30:g} GiB at the limit); for tighter percentiles run "
            "several studies with different seeds")
    return int(n_samples)


def affine_map(model: SpatialModel, geom: SpatialGeometry, wrenches: ArrayLike,
               index: Sequence[int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The global reaction components as an affine function of the sampled deviations.

    ``index``: the slot of each sampled deviation in the flattened (joint, side, component)
    deviation array. Returns the peaks without deviations (n_joints, 7), ``c0`` (n, 6 n_joints)
    and ``Z`` (n, 6 n_joints, n_tol) with components ``= c0 + Z @ d`` at every position:
    ``Z = P H M`` (P: unknowns -> global components, H: misfit -> unknowns, M: deviations ->
    misfits), computed once per position by the force method (:func:`influence`).
    """
    inf = influence(model, geom, wrenches)
    frames = _joint_frames(model, geom)
    nominal = _peaks(_global(model, frames, inf.r0))
    nj, m1 = len(model.joints), inf.r0.shape[-1]
    basis = np.zeros((len(index), nj * 2 * 6))
    basis[np.arange(len(index)), index] = 1.0
    mis = misfit(model, geom, basis.reshape(len(index), nj, 2, 6))       # (n_tol, n, m)
    dr = np.einsum("nij,tnj->nit", inf.h, mis)                           # (n, m+1, n_tol)
    eye = np.broadcast_to(np.eye(m1)[:, None, :], (m1, geom.n, m1))
    p = _global(model, frames, eye)                                      # (m+1, nj, 6, n)
    p = p.reshape(m1, nj * 6, geom.n).transpose(2, 1, 0)                # (n, 6 nj, m+1)
    c0 = np.einsum("nck,nk->nc", p, inf.r0)
    return nominal, c0, p @ dr


def tolerance_study(model: SpatialModel, geom: SpatialGeometry, wrenches: ArrayLike,
                    tolerances: Sequence[Tolerance], n_samples: int, *,
                    seed: int | None = 0, chunk_size: int = CHUNK_SAMPLES, client: Any = None,
                    progress: Any = None) -> ToleranceStudy:
    """Monte-Carlo study of the peak spatial reactions over a cycle.

    Parameters
    ----------
    model, geom, wrenches
        As for :func:`~linkwork.redundancy.solve_reactions` (the cycle's positions).
    tolerances : sequence of Tolerance
        Independent random deviations (components not listed are zero).
    n_samples : int
        Number of samples N, >= 1 and at most :func:`max_samples` (the draws and peaks of
        every sample are kept: 1 GiB at the limit, :data:`MEMORY_BUDGET`).
    seed : int or None
        Seed of the random generator (``numpy.random.default_rng``).
    chunk_size : int
        Samples per chunk (default :data:`CHUNK_SAMPLES`): the unit of work of a Dask cluster
        and of ``progress`` (the kernel runs over a chunk in blocks of :data:`KERNEL_BLOCK`
        samples, so memory stays bounded whatever the chunk size). On a cluster, smaller where
        needed for :data:`CLUSTER_CHUNKS` chunks per worker thread (none below
        :data:`MIN_CLUSTER_CHUNK` samples). The peaks do not depend on the chunking.
    client : dask.distributed.Client or str, optional
        Spread the chunks over this cluster (see :func:`linkwork.sweep.evaluate`).
    progress : callable, optional
        ``progress(done, total)`` after each chunk (e.g. :func:`linkwork.sweep.rich_progress`).

    Returns
    -------
    ToleranceStudy
    """
    check_samples(n_samples, len(model.joints), len(tolerances))
    if seed is not None and (isinstance(seed, bool) or int(seed) != seed or int(seed) < 0):
        raise ParameterError("seed", seed, "must be None or an integer >= 0")
    if not tolerances:
        raise ParameterError("tolerances", "[]", "must list at least one tolerance")
    names = [j.name for j in model.joints]
    index = []
    for t in tolerances:
        if t.joint not in names:
            raise ParameterError("tolerance.joint", t.joint, f"must be one of {names}")
        index.append((names.index(t.joint) * 2 + (0 if t.side == "a" else 1)) * 6
                     + _DEV_COMPONENTS.index(t.component))
    rng = np.random.default_rng(seed)
    n = int(n_samples)
    draws = np.empty((n, len(tolerances)))
    for k, t in enumerate(tolerances):
        if t.distribution == "normal":
            draws[:, k] = rng.normal(t.mean, t.limit / 3.0, n)
        else:
            draws[:, k] = rng.uniform(t.mean - t.limit, t.mean + t.limit, n)
    nominal, c0, zmat = affine_map(model, geom, wrenches, index)
    nj = len(model.joints)
    func = functools.partial(_chunk, n=geom.n, n_joints=nj)
    peaks = evaluate(func, draws, chunk_size=chunk_size, client=client, progress=progress,
                     shared={"zb": affine_blocks(c0, zmat)}, balance=CLUSTER_CHUNKS,
                     min_chunk=MIN_CLUSTER_CHUNK)
    return ToleranceStudy(joints=tuple(names), quantities=PEAK_QUANTITIES, peaks=peaks,
                          nominal=nominal, draws=draws, tolerances=tuple(tolerances), seed=seed)
