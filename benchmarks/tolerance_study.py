"""Spatial reactions with redundant constraints: one-cycle solves and the Monte-Carlo study.

The loom four-bar of papers 001/004 as ``examples/loom_fourbar_spatial.toml`` describes it (four
revolute joints, axes of 30 mm, stacked links, gravity, a 4 N·m moment on the rocker, three
systematic deviations and six toleranced ones), over ``--positions`` crank positions (360).

Case "one cycle": :func:`linkwork.redundancy.solve_reactions` with the file's deviations,

``force method``         self-stress states from a batched SVD + compatibility (the default);
``displacement method``  assembled joint stiffness, batched ``numpy.linalg.solve``.

Case "tolerance study": peaks over the cycle of every reaction component and of the bending
moment of every joint, for Monte-Carlo samples of the deviations (the file's six tolerances plus
its three systematic deviations as fixed means, as ``linkwork reactions --tolerance-study``
does),

``tolerance_study``      :func:`linkwork.redundancy.tolerance_study` at each ``--n`` samples,
                         in-process (the affine map deviations -> reactions is built once per
                         position; each chunk of samples is one batched matrix product);
``... dask``             the same at ``--dask-n`` samples on a local dask cluster of worker
                         processes (``LocalCluster(processes=True)``, ``--workers`` 1 and 2,
                         1 thread each, dask's default worker settings: what ``--scheduler``
                         gives), one cluster alive at a time, sampled round-robin with the
                         in-process study and with ``w plain processes`` (the study's set-up
                         here, then the library's kernel over equal shares of the draws on
                         spawned processes, no Dask: the machine's bound for an executor of
                         processes at that moment); speed-ups are in-process time / time per
                         round;
``plain NumPy re-solve`` the reference: for ``--resolve-n`` samples, one straightforward
                         re-solve of the whole compliance problem per sample, written out in
                         this file (stiffness ``A K A^T`` assembled from the joint geometry and
                         the bearing stiffnesses, scaled batched ``numpy.linalg.solve`` over
                         the positions, reactions, peaks);
``plain NumPy, factorised once``  the same with the inverse stiffness of every position computed
                         once before the loop (only the misfit, the right-hand side and three
                         batched mat-vecs per sample): the best a per-sample loop can do;
``solve_reactions per sample`` (force / displacement): the library's one-cycle solver called
                         once per sample;
``plain NumPy affine map, lean kernel``  the approach of ``tolerance_study`` written flat at
                         each ``--n``: the plain NumPy model solved once without deviations and
                         once per toleranced deviation, then ``c0 + Z @ draws`` per chunk of 100
                         samples with a lean peak kernel (in-place sum, ``max(max, -min)``,
                         bending peak = sqrt of the peak of mx² + my²): what the approach costs
                         without the library's kernel.

Per-sample contenders are timed on ``--resolve-n`` samples (spread over the smallest study)
and reported per sample; the ratios compare the time per sample, i.e. the same number of
samples. Every study's time includes its set-up (draws, the one-cycle solve, the affine map).

Before timing, the force and displacement methods are compared (every component of every joint
and Q, relative to the largest value of its kind, 1e-9), and the peaks of every timed contender
are compared with the plain NumPy re-solve of the same samples (relative to the largest peak of
the same quantity, 1e-9; a study is checked on ``--resolve-n`` of its own samples spread over
its N); the dask runs and the plain processes must equal the in-process run of the same
size to 1e-12.

Case "peak kernel": the kernel alone on the largest ``--n`` with the affine map given, the
library's (``tolerance._chunk``) against the lean kernel written flat and a fused numba loop
(``_fused.tolerance_peaks``, the practical limit of a compiled loop), all to 1e-12 of the
library's peaks.
A disagreement aborts.

Usage::

    .venv/bin/python benchmarks/tolerance_study.py                 # plain table on stdout
    .venv/bin/python benchmarks/tolerance_study.py --markdown --json out.json
    .venv/bin/python benchmarks/tolerance_study.py --n 1000 10000 --no-dask --repeat 3

Medians of ``--repeat`` samples (``--long-repeat`` for calls longer than 1 s, to keep the run
under 3 minutes), the contenders of a case sampled round-robin (one sample of each per round,
each sample looping >= 20 ms), so that load from other processes hits all alike.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (
    PlainProcesses,
    Spread,
    cluster_lines,
    cluster_rounds,
    finish,
    fmt_spread,
    fmt_time,
    load,
    ratio,
    time_rounds,
)

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "loom_fourbar_spatial.toml"
RTOL = 1e-9
RTOL_DASK = 1e-12
_COMPS = ("dx", "dy", "dz", "tx", "ty", "tz")


# ---------------------------------------------------------------------------------------------
# the problem
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Problem:
    """The loom four-bar in space over one cycle, with its tolerances."""

    model: Any                 # linkwork.redundancy.SpatialModel
    geom: Any                  # linkwork.redundancy.SpatialGeometry
    wrenches: np.ndarray       # (n, n_bodies, 6)
    deviations: np.ndarray     # systematic, (n_joints, 2, 6)
    tolerances: tuple[Any, ...]
    slots: np.ndarray          # (n_tol, 3): joint, side, component of each tolerance


def load_problem(positions: int = 360, path: Path = EXAMPLE) -> Problem:
    """Read the example file and build the model, geometry and body wrenches of one cycle."""
    from linkwork.cli.reactions import load_problem as read
    from linkwork.planar import kinematics
    from linkwork.redundancy import (
        Deviation,
        OutOfPlaneLoad,
        Tolerance,
        body_wrenches,
        deviation_array,
        geometry,
        spatial_model,
    )

    mech, kw, spec = read(path)
    cycle = np.linspace(0.0, 2 * math.pi, positions, endpoint=False)
    kin = kinematics(mech, cycle)
    model = spatial_model(mech, spec.joint_kwargs(), spec.default_kwargs())
    loads = kw["loads"](cycle) if callable(kw["loads"]) else kw["loads"]
    w = body_wrenches(mech, kin, gravity=kw["gravity"], loads=list(loads),
                      heights=dict(spec.heights),
                      out_of_plane=[OutOfPlaneLoad(o.body, o.fz, o.mx, o.my)
                                    for o in spec.out_of_plane])
    dev = deviation_array(model, [Deviation(d.joint, d.body, d.dx, d.dy, d.dz, d.tx, d.ty, d.tz)
                                  for d in spec.deviation], mech.frame.name)
    tols = []
    for t in spec.tolerance:
        jt = next(j for j in model.joints if j.name == t.joint)
        body = "ground" if t.body == mech.frame.name else t.body
        tols.append(Tolerance(t.joint, "a" if body == jt.body_a else "b", t.component, t.limit,
                              t.distribution, t.mean))
    for j, jt in enumerate(model.joints):          # systematic deviations: fixed means
        for side in (0, 1):
            for c in range(6):
                if dev[j, side, c] != 0.0:
                    tols.append(Tolerance(jt.name, "ab"[side], _COMPS[c], 0.0, "uniform",
                                          float(dev[j, side, c])))
    names = [j.name for j in model.joints]
    slots = np.array([(names.index(t.joint), "ab".index(t.side), _COMPS.index(t.component))
                      for t in tols])
    return Problem(model, geometry(mech, kin), w, dev, tuple(tols), slots)


def deviations_of(prob: Problem, draws: np.ndarray) -> np.ndarray:
    """Deviation arrays (S, n_joints, 2, 6) of sampled tolerance values (S, n_tol)."""
    out = np.zeros((draws.shape[0], len(prob.model.joints), 2, 6))
    for k, (j, side, c) in enumerate(prob.slots):
        out[:, j, side, c] += draws[:, k]
    return out


def peaks_of(comp: np.ndarray) -> np.ndarray:
    """Global components (n_joints, 6, n) -> (n_joints, 7): peak |.| and peak bending."""
    p = np.max(np.abs(comp), axis=-1)
    bend = np.max(np.hypot(comp[:, 3], comp[:, 4]), axis=-1)
    return np.concatenate([p, bend[:, None]], axis=-1)


# ---------------------------------------------------------------------------------------------
# the plain NumPy reference: displacement method written out, one sample at a time
# ---------------------------------------------------------------------------------------------


class PlainNumpy:
    """The compliance problem of a planar mechanism with revolute joints, written out.

    Unknowns: the translation (at the global origin) and the rotation of every moving body,
    6 per body. A revolute joint at ``p = (x, y, z)`` joining body a to body b is five springs
    (fx, fy, fz, mx, my) of stiffness ``k_b, k_b, axial_ratio k_b, k_b e²/12, k_b e²/12`` (or the
    joint's explicit ones); the driver is a torsion spring about z. The stretch of joint j is
    ``s = B_j u + delta_j`` with ``B_j`` = (motion of b at p) - (motion of a at p) and the
    misfit ``delta_j = R(theta_b) d_b - R(theta_a) d_a``; its reaction on b is ``-K s``.
    Equilibrium ``sum B^T K (B u + delta) = w`` is solved per position (lengths scaled by the
    mechanism size, Jacobi-scaled). The reactions do not depend on the driver spring's value
    (the in-plane problem is determinate).
    """

    def __init__(self, prob: Problem) -> None:
        model, geom = prob.model, prob.geom
        if any(j.kind != "revolute" for j in model.joints):
            raise ValueError("the plain NumPy reference handles revolute joints only")
        n, nb = geom.n, model.n_bodies
        self.prob = prob
        length = float(max(np.max(np.abs(geom.points)), max(abs(j.z) for j in model.joints)))
        self.length = length
        # B: (n, 5 nj + 1, 6 nb) in scaled units (rotations times L)
        rows = []
        kvec = []
        for j, jt in enumerate(model.joints):
            x, y = geom.points[:, j, 0], geom.points[:, j, 1]
            z = np.full(n, jt.z)
            bj = np.zeros((n, 5, 6 * nb))
            for body, sign in ((jt.body_b, 1.0), (jt.body_a, -1.0)):
                if body == "ground":
                    continue
                i = 6 * model.body_index(body)
                # translation at p of a body with origin translation t, rotation r: t + r x p
                bj[:, 0, i], bj[:, 1, i + 1], bj[:, 2, i + 2] = sign, sign, sign
                bj[:, 0, i + 4], bj[:, 0, i + 5] = sign * z / length, -sign * y / length
                bj[:, 1, i + 3], bj[:, 1, i + 5] = -sign * z / length, sign * x / length
                bj[:, 2, i + 3], bj[:, 2, i + 4] = sign * y / length, -sign * x / length
                bj[:, 3, i + 3], bj[:, 4, i + 4] = sign, sign
            rows.append(bj)
            if jt.stiffness is None:
                kb, kt = jt.k_bearing, jt.k_bearing * jt.e ** 2 / 12.0
                kj = [kb, kb, jt.axial_ratio * kb, kt, kt]
            else:
                kj = list(jt.stiffness[:5])
            kvec += [*kj[:3], kj[3] / length ** 2, kj[4] / length ** 2]
        drv = model.joints[model.driver_index]
        bd = np.zeros((n, 1, 6 * nb))
        for body, sign in ((drv.body_b, 1.0), (drv.body_a, -1.0)):
            if body != "ground":
                bd[:, 0, 6 * model.body_index(body) + 5] = sign
        rows.append(bd)
        self.B = np.concatenate(rows, axis=1)                      # (n, m + 1, 6 nb)
        self.Bt = np.ascontiguousarray(np.swapaxes(self.B, 1, 2))
        kvec.append(float(np.exp(np.mean(np.log(kvec)))))          # driver spring
        self.k = np.array(kvec)
        w = prob.wrenches.reshape(n, nb, 2, 3).copy()
        w[:, :, 1] /= length                                       # moments in scaled units
        self.w = w.reshape(n, 6 * nb)
        self.angles = np.concatenate([geom.body_angles, np.zeros((n, 1))], axis=1)
        self.cos, self.sin = np.cos(self.angles), np.sin(self.angles)
        self.ab = [(model.body_index(j.body_a), model.body_index(j.body_b))
                   for j in model.joints]
        self.inverse: np.ndarray | None = None

    def stiffness(self) -> tuple[np.ndarray, np.ndarray]:
        """Jacobi-scaled ``B^T K B`` of every position and its diagonal scaling."""
        s = self.Bt @ (self.k[:, None] * self.B)
        d = 1.0 / np.sqrt(np.einsum("nii->ni", s))
        return d[:, :, None] * s * d[:, None, :], d

    def factorise(self) -> None:
        """Invert the scaled stiffness of every position once (for the per-sample loop)."""
        s, d = self.stiffness()
        self.inverse = d[:, :, None] * np.linalg.inv(s) * d[:, None, :]

    def misfit(self, dev: np.ndarray) -> np.ndarray:
        """Scaled misfit of every spring (n, m + 1) for one deviation array (nj, 2, 6)."""
        n = self.B.shape[0]
        out = np.zeros((n, self.B.shape[1]))
        for j, (ia, ib) in enumerate(self.ab):
            glob = np.zeros((n, 6))
            for side, body in ((1, ib), (0, ia)):
                sign = 1.0 if side == 1 else -1.0
                c, s = self.cos[:, body], self.sin[:, body]
                d = dev[j, side]
                for o in (0, 3):                 # rotate (x, y) of offsets and of tilts
                    glob[:, o] += sign * (c * d[o] - s * d[o + 1])
                    glob[:, o + 1] += sign * (s * d[o] + c * d[o + 1])
                    glob[:, o + 2] += sign * d[o + 2]
            out[:, 5 * j:5 * j + 3] = glob[:, :3]
            out[:, 5 * j + 3:5 * j + 5] = glob[:, 3:5] * self.length
        return out

    def reactions(self, dev: np.ndarray, loads: bool = True) -> np.ndarray:
        """Global reaction components (n_joints, 6, n) for one deviation array; Q in mz of the
        driver joint. ``loads=False``: the part caused by the deviations alone."""
        delta = self.misfit(dev)
        kd = self.k * delta
        rhs = -np.einsum("nki,nk->ni", self.B, kd)
        if loads:
            rhs += self.w
        if self.inverse is None:
            s, d = self.stiffness()
            u = d * np.linalg.solve(s, (d * rhs)[..., None])[..., 0]
        else:
            u = np.einsum("nij,nj->ni", self.inverse, rhs)
        r = -self.k * (np.einsum("nki,ni->nk", self.B, u) + delta)     # (n, m + 1), scaled
        nj = len(self.ab)
        comp = np.zeros((nj, 6, r.shape[0]))
        for j in range(nj):
            comp[j, :3] = r[:, 5 * j:5 * j + 3].T
            comp[j, 3:5] = r[:, 5 * j + 3:5 * j + 5].T * self.length
        comp[self.prob.model.driver_index, 5] = r[:, -1] * self.length
        return comp


class PlainAffine:
    """The affine-map approach written flat: the plain NumPy model above solved once without
    deviations and once per toleranced deviation (unit value, no loads), then, for chunks of
    samples, ``components = c0 + Z @ draws`` and the peaks with a lean kernel (in-place sum,
    ``max(max, -min)`` instead of ``abs``, the bending peak as the square root of the peak of
    ``mx² + my²``). Measures what the approach costs without the library's kernel."""

    def __init__(self, prob: Problem, chunk_size: int = 100) -> None:
        self.prob, self.chunk_size = prob, chunk_size

    def draws(self, n: int, seed: int) -> np.ndarray:
        """The samples ``tolerance_study`` draws: one seeded generator, column by column
        (normal: N(mean, (limit/3)²), uniform: U(mean ± limit))."""
        rng = np.random.default_rng(seed)
        out = np.empty((n, len(self.prob.tolerances)))
        for k, t in enumerate(self.prob.tolerances):
            out[:, k] = (rng.normal(t.mean, t.limit / 3.0, n) if t.distribution == "normal"
                         else rng.uniform(t.mean - t.limit, t.mean + t.limit, n))
        return out

    def __call__(self, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
        """Peaks (n, n_joints, 7) and draws of ``n`` samples."""
        prob = self.prob
        draws = self.draws(n, seed)
        plain = PlainNumpy(prob)
        plain.factorise()
        nj, n = len(prob.model.joints), prob.geom.n
        c0 = plain.reactions(np.zeros((nj, 2, 6)))                  # (nj, 6, n)
        z = np.empty((n, nj * 6, len(prob.slots)))
        for k, (j, side, c) in enumerate(prob.slots):
            unit = np.zeros((nj, 2, 6))
            unit[j, side, c] = 1.0
            z[:, :, k] = plain.reactions(unit, loads=False).reshape(nj * 6, n).T
        c0t = np.ascontiguousarray(c0.reshape(nj * 6, n).T)[:, :, None]
        out = np.empty((draws.shape[0], nj, 7))
        for start in range(0, draws.shape[0], self.chunk_size):
            d = draws[start:start + self.chunk_size]
            comp = z @ d.T                                          # (n, 6 nj, S)
            comp += c0t
            peak = np.maximum(comp.max(axis=0), -comp.min(axis=0))  # (6 nj, S)
            m = comp.reshape(n, nj, 6, -1)
            bend = np.sqrt((m[:, :, 3] ** 2 + m[:, :, 4] ** 2).max(axis=0))   # (nj, S)
            out[start:start + len(d), :, :6] = peak.reshape(nj, 6, -1).transpose(2, 0, 1)
            out[start:start + len(d), :, 6] = bend.T
        return out, draws


# ---------------------------------------------------------------------------------------------
# contenders
# ---------------------------------------------------------------------------------------------


@dataclass
class Contender:
    name: str
    samples: int                       # samples per call (0: one-cycle case)
    run: Callable[[], Any]
    output: Callable[[Any], Any]        # result -> what the checks compare


def cycle_contenders(prob: Problem) -> list[Contender]:
    """Force and displacement method over one cycle; output: components (nj, 6, n) and Q."""
    from linkwork.redundancy import solve_reactions

    def out(r: Any) -> np.ndarray:
        return np.concatenate([r.components().reshape(-1, r.Q.size), r.Q[None, :]])

    def solver(m: str) -> Callable[[], Any]:
        return lambda: solve_reactions(prob.model, prob.geom, prob.wrenches, prob.deviations,
                                       method=m)

    return [Contender(f"{m} method", 0, solver(m), out) for m in ("force", "displacement")]


def study_contenders(prob: Problem, sizes: tuple[int, ...], resolve_n: int, seed: int = 1,
                     chunk_size: int = 10_000
                     ) -> tuple[list[Contender], Callable[[np.ndarray], np.ndarray]]:
    """The Monte-Carlo contenders, and the plain NumPy re-solve ``draws -> peaks`` that checks
    them. Per-sample contenders run on ``resolve_n`` samples of the smallest study."""
    from linkwork.redundancy import solve_reactions, tolerance_study

    n0 = min(sizes)
    ref_study = tolerance_study(prob.model, prob.geom, prob.wrenches, prob.tolerances, n0,
                                seed=seed, chunk_size=chunk_size)
    idx = _spread(n0, resolve_n)
    draws = ref_study.draws[idx]
    devs = deviations_of(prob, draws)
    plain = PlainNumpy(prob)
    plain_f = PlainNumpy(prob)
    plain_f.factorise()
    cons: list[Contender] = []

    def per_sample(solve: Callable[[np.ndarray], np.ndarray]) -> Callable[[], np.ndarray]:
        return lambda: np.stack([peaks_of(solve(d)) for d in devs])

    def ident(x: Any) -> tuple[np.ndarray, None]:
        return np.asarray(x), None

    def of_study(st: Any) -> tuple[np.ndarray, np.ndarray]:
        return st.peaks, st.draws

    cons.append(Contender("plain NumPy re-solve", len(idx), per_sample(plain.reactions), ident))
    cons.append(Contender("plain NumPy, factorised once", len(idx),
                          per_sample(plain_f.reactions), ident))
    def library(m: str) -> Callable[[np.ndarray], np.ndarray]:
        return lambda d: solve_reactions(prob.model, prob.geom, prob.wrenches, d,
                                         method=m).components()

    for m in ("force", "displacement"):
        cons.append(Contender(f"solve_reactions per sample ({m})", len(idx),
                              per_sample(library(m)), ident))

    def study(n: int, cl: Any = None) -> Callable[[], Any]:
        return lambda: tolerance_study(prob.model, prob.geom, prob.wrenches, prob.tolerances, n,
                                       seed=seed, chunk_size=chunk_size, client=cl)

    flat = PlainAffine(prob)

    def affine(n: int) -> Callable[[], Any]:
        return lambda: flat(n, seed)

    for n in sizes:
        cons.append(Contender("tolerance_study", n, study(n), of_study))
        cons.append(Contender("plain NumPy affine map, lean kernel", n, affine(n),
                              lambda x: x))
    def resolve(dr: np.ndarray) -> np.ndarray:
        return np.stack([peaks_of(plain.reactions(d)) for d in deviations_of(prob, dr)])

    return cons, resolve


def affine_of(prob: Problem) -> tuple[np.ndarray, np.ndarray]:
    """``c0`` (n, 6 n_joints) and ``Z`` (n, 6 n_joints, n_tol) of the library's affine map
    (``tolerance.affine_map``) for the toleranced deviations of ``prob``."""
    import linkwork.redundancy.tolerance as tol

    names = [j.name for j in prob.model.joints]
    index = [(names.index(t.joint) * 2 + (0 if t.side == "a" else 1)) * 6
             + _COMPS.index(t.component) for t in prob.tolerances]
    _, c0, z = tol.affine_map(prob.model, prob.geom, prob.wrenches, index)
    return c0, z


def library_kernel(prob: Problem, c0: np.ndarray, z: np.ndarray
                   ) -> Callable[[np.ndarray], np.ndarray]:
    """The library's peak kernel ``draws -> peaks`` with the affine map ``c0``, ``Z`` given
    (``tolerance._chunk`` on ``tolerance.affine_blocks``): what ``tolerance_study`` evaluates
    chunk by chunk after its set-up."""
    import functools

    import linkwork.redundancy.tolerance as tol

    return functools.partial(tol._chunk, zb=tol.affine_blocks(c0, z), n=prob.geom.n,
                             n_joints=len(prob.model.joints))


def on_plain_processes(prob: Problem, n: int, seed: int, chunk_size: int
                       ) -> Callable[[PlainProcesses], np.ndarray]:
    """The study of ``n`` samples on plain processes, peaks (n, n_joints, 7): its set-up
    here as ``tolerance_study`` makes it (the same draws, the affine map), then the library's
    kernel over equal shares of the draws, one per process, in chunks of ``chunk_size``."""
    def run(procs: PlainProcesses) -> np.ndarray:
        draws = PlainAffine(prob).draws(n, seed)
        return procs.evaluate(library_kernel(prob, *affine_of(prob)), draws, chunk_size)

    return run


def kernel_contenders(prob: Problem, n: int, seed: int = 1, chunk_size: int = 10_000,
                      fused: bool = True) -> list[Contender]:
    """The peak kernel alone on ``n`` samples, the affine map given (the same ``c0``, ``Z`` and
    draws for all): the library's (``tolerance._chunk`` over chunks of ``chunk_size``, its
    buffers reused block by block), the lean kernel of :class:`PlainAffine` written flat, and
    a fused numba loop (the practical limit). Output: the peaks (n, n_joints, 7)."""
    c0, z = affine_of(prob)
    nj, npos = len(prob.model.joints), prob.geom.n
    kern = library_kernel(prob, c0, z)
    draws = PlainAffine(prob).draws(n, seed)

    def library() -> np.ndarray:
        return np.concatenate([kern(draws[i:i + chunk_size])
                               for i in range(0, n, chunk_size)])

    c0t = np.ascontiguousarray(c0)[:, :, None]

    def lean() -> np.ndarray:
        out = np.empty((n, nj, 7))
        for start in range(0, n, 100):
            d = draws[start:start + 100]
            comp = z @ d.T                                          # (n, 6 nj, S)
            comp += c0t
            peak = np.maximum(comp.max(axis=0), -comp.min(axis=0))  # (6 nj, S)
            m = comp.reshape(npos, nj, 6, -1)
            bend = np.sqrt((m[:, :, 3] ** 2 + m[:, :, 4] ** 2).max(axis=0))
            out[start:start + len(d), :, :6] = peak.reshape(nj, 6, -1).transpose(2, 0, 1)
            out[start:start + len(d), :, 6] = bend.T
        return out

    def ident(x: Any) -> tuple[np.ndarray, None]:
        return np.asarray(x), None

    cons = [Contender("library kernel", n, library, ident),
            Contender("flat NumPy lean kernel", n, lean, ident)]
    if fused:
        try:
            import _fused
        except ImportError:
            return cons
        cons.append(Contender("fused numba loop", n,
                              lambda: _fused.tolerance_peaks(z, c0, draws, nj), ident))
    return cons


def check_kernels(results: list[np.ndarray], cons: list[Contender]) -> dict[str, float]:
    """Every kernel's peaks against the library's, relative to the largest peak of each
    quantity (1e-12: the same arithmetic up to the order of the sums)."""
    ref = results[0]
    scale = np.max(np.abs(ref), axis=(0, 1))
    out = {}
    for con, got in zip(cons[1:], results[1:], strict=True):
        err = _rel(got, ref, scale)
        out[f"kernel: {con.name}, N={con.samples}"] = err
        if not err <= RTOL_DASK:
            raise AssertionError(f"peak kernel: {con.name} disagrees with the library kernel: "
                                 f"{err:.3g} > {RTOL_DASK:g}")
    return out


# ---------------------------------------------------------------------------------------------
# checking and timing
# ---------------------------------------------------------------------------------------------


def _rel(got: np.ndarray, ref: np.ndarray, scale: np.ndarray) -> float:
    return float(np.max(np.abs(got - ref) / scale))


def check_cycle(results: list[np.ndarray], names: list[str], nj: int) -> float:
    """Every component of every joint and Q of each method against the first, relative to the
    largest |value| of its kind (forces; moments and Q); returns the largest difference."""
    ref = results[0]
    kind = np.zeros(ref.shape[0], dtype=int)
    kind[:-1] = (np.arange(nj * 6) % 6 >= 3)
    kind[-1] = 1
    scale = np.array([np.max(np.abs(ref[kind == k])) for k in (0, 1)])[kind][:, None]
    worst = 0.0
    for name, got in zip(names[1:], results[1:], strict=True):
        err = _rel(got, ref, scale)
        worst = max(worst, err)
        if not err <= RTOL:
            raise AssertionError(f"one cycle: {name} disagrees with {names[0]}: max relative "
                                 f"difference {err:.3g} > {RTOL:g}")
    return worst


def check_study(results: dict[str, Any], cons: list[Contender], resolve_n: int,
                resolve: Callable[[np.ndarray], np.ndarray]) -> dict[str, float]:
    """Peaks of every contender against the plain NumPy re-solve of the same samples, relative
    to the largest peak of the same quantity.

    Per-sample contenders ran on the reference samples (the plain NumPy re-solve's); every
    study is checked on ``resolve_n`` of its own samples spread over its N, re-solved by
    ``resolve(draws) -> peaks``.
    """
    ref = results[cons[0].name + "#0"][0]
    scale = np.max(np.abs(ref), axis=(0, 1))                   # (7,) per quantity
    scale = np.maximum(scale, 1e-6 * np.max(scale))
    out: dict[str, float] = {}
    for i, con in enumerate(cons):
        got, draws = results[f"{con.name}#{i}"]
        want = ref
        if draws is not None:                                   # a study: its own samples
            idx = _spread(con.samples, resolve_n)
            got, want = got[idx], resolve(draws[idx])
        err = _rel(got, want, scale)
        out[f"{con.name}, N={con.samples}"] = err
        if not err <= RTOL:
            raise AssertionError(f"tolerance study: {con.name} (N={con.samples}) disagrees "
                                 f"with the plain NumPy re-solve: {err:.3g} > {RTOL:g}")
    return out


def _spread(n: int, k: int) -> np.ndarray:
    """Up to ``k`` sample indices spread evenly over ``range(n)``."""
    return np.unique(np.linspace(0, n - 1, k).round().astype(int))


def _first_calls(cons: list[Contender]) -> tuple[dict[str, Any], list[float]]:
    """One call of each contender (warm-up, agreement check, calibration of the sampling)."""
    results: dict[str, Any] = {}
    firsts = []
    for i, con in enumerate(cons):
        t0 = time.perf_counter()
        res = con.run()
        firsts.append(time.perf_counter() - t0)
        results[f"{con.name}#{i}"] = con.output(res)
    return results, firsts


def run(sizes: tuple[int, ...] = (1_000, 10_000, 100_000), positions: int = 360,
        repeat: int = 5, resolve_n: int = 10, dask_n: int = 100_000, seed: int = 1,
        chunk_size: int = 10_000, long_repeat: int = 3, workers: tuple[int, ...] = (1, 2),
        fused: bool = True) -> dict[str, Any]:
    """Check and time every contender; return rows (with every sample's time) and the
    agreement reached."""
    prob = load_problem(positions)
    nj = len(prob.model.joints)
    rows: list[dict[str, Any]] = []
    # one cycle
    cyc = cycle_contenders(prob)
    res_c, first_c = _first_calls(cyc)
    cycle_err = check_cycle([res_c[f"{c.name}#{i}"] for i, c in enumerate(cyc)],
                            [c.name for c in cyc], nj)
    for con, sp in zip(cyc, time_rounds([c.run for c in cyc], repeat, first=first_c),
                       strict=True):
        rows.append({"case": "one cycle", "contender": con.name, "samples": 0,
                     "positions": positions, "times": sp.samples})
    # the peak kernel alone
    kern = kernel_contenders(prob, max(sizes), seed, chunk_size, fused)
    res_k, first_k = _first_calls(kern)
    kernel_err = check_kernels([res_k[f"{c.name}#{i}"][0] for i, c in enumerate(kern)], kern)
    del res_k
    for con, sp in zip(kern, time_rounds([c.run for c in kern], repeat, first=first_k,
                                         long_repeat=long_repeat), strict=True):
        rows.append({"case": "peak kernel", "contender": con.name, "samples": con.samples,
                     "positions": positions, "times": sp.samples})
    # tolerance study
    cons, resolve = study_contenders(prob, tuple(sizes), resolve_n, seed, chunk_size)
    res_s, first_s = _first_calls(cons)
    study_err = check_study(res_s, cons, resolve_n, resolve)
    del res_s
    times = time_rounds([c.run for c in cons], repeat, first=first_s, long_repeat=long_repeat)
    for con, sp in zip(cons, times, strict=True):
        rows.append({"case": "tolerance study", "contender": con.name, "samples": con.samples,
                     "positions": positions, "times": sp.samples})
    dask_err: dict[str, float] = {}
    clusters = (dask_rounds(prob, dask_n, seed, chunk_size, workers, repeat, dask_err)
                if dask_n and workers else [])
    return {"rows": rows, "agreement": {"force vs displacement (one cycle)": cycle_err,
                                        **kernel_err, **study_err, **dask_err},
            "tolerances": len(prob.tolerances), "resolve_samples": cons[0].samples,
            "dask": clusters, "dask_samples": dask_n}


def dask_rounds(prob: Problem, n: int, seed: int, chunk_size: int, workers: tuple[int, ...],
                repeat: int, agreement: dict[str, float]) -> list[dict[str, Any]]:
    """The study of ``n`` samples in-process, on a local process cluster and on plain
    processes, for each number of ``workers`` (:func:`_common.cluster_rounds`); the peaks of
    both against the in-process study's to :data:`RTOL_DASK` (into ``agreement``)."""
    from linkwork.redundancy import tolerance_study

    def study(client: Any = None) -> Any:
        return tolerance_study(prob.model, prob.geom, prob.wrenches, prob.tolerances, n,
                               seed=seed, chunk_size=chunk_size, client=client)

    def peaks(x: Any) -> np.ndarray:
        return np.asarray(getattr(x, "peaks", x))

    def same(got: Any, want: Any, label: str) -> None:
        g, w = peaks(got), peaks(want)
        err = float(np.max(np.abs(g - w)) / np.max(np.abs(w)))
        agreement[f"tolerance_study, {label}, N={n} vs in-process"] = err
        if not err <= RTOL_DASK:
            raise AssertionError(f"{label}: the peaks differ from the in-process study: "
                                 f"{err:.3g} > {RTOL_DASK:g}")

    return cluster_rounds(workers, study, study, on_plain_processes(prob, n, seed, chunk_size),
                          same, repeat)


def _sp(r: dict[str, Any]) -> Spread:
    return Spread(list(r["times"]))


def table(result: dict[str, Any], markdown: bool = False) -> str:
    """The cases as tables: min / median / max of every contender, ratios per round."""
    rows = result["rows"]
    lines: list[str] = []

    def emit(cells: list[str], widths: list[int]) -> None:
        if markdown:
            lines.append("| " + " | ".join(cells) + " |")
        else:
            lines.append(" ".join(c.ljust(w) if i == 0 else c.rjust(w)
                                  for i, (c, w) in enumerate(zip(cells, widths, strict=True))))

    def head(cells: list[str], widths: list[int]) -> None:
        emit(cells, widths)
        if markdown:
            lines.append("|---|" + "---:|" * (len(cells) - 1))

    cyc = [r for r in rows if r["case"] == "one cycle"]
    base = _sp(next(r for r in cyc if r["contender"] == "displacement method"))
    w = [34, 9, 34, 20]
    head(["one cycle", "positions", "min / median / max", "x displacement method"], w)
    for r in cyc:
        emit([r["contender"], str(r["positions"]), fmt_spread(_sp(r)),
              fmt_spread(ratio(_sp(r), base), "ratio")], w)
    lines.append("")
    kern = [r for r in rows if r["case"] == "peak kernel"]
    if kern:
        lib = _sp(kern[0])
        w = [30, 8, 34, 20]
        head(["peak kernel (affine map given)", "samples", "min / median / max",
              "x library kernel"], w)
        for r in kern:
            emit([r["contender"], str(r["samples"]), fmt_spread(_sp(r)),
                  fmt_spread(ratio(_sp(r), lib), "ratio")], w)
        lines.append("")
    st = [r for r in rows if r["case"] == "tolerance study"]
    plain = _sp(next(r for r in st if r["contender"] == "plain NumPy re-solve"))
    fact = _sp(next(r for r in st if r["contender"] == "plain NumPy, factorised once"))
    plain_per = plain.median / next(r["samples"] for r in st
                                    if r["contender"] == "plain NumPy re-solve")
    fact_per = fact.median / next(r["samples"] for r in st
                                  if r["contender"] == "plain NumPy, factorised once")
    w = [52, 7, 34, 11, 11, 9]
    head(["tolerance study", "samples", "min / median / max", "per sample",
          "x re-solve", "x factor."], w)
    for r in st:
        sp = _sp(r)
        per = sp.median / r["samples"]
        emit([r["contender"], str(r["samples"]), fmt_spread(sp), fmt_time(per),
              f"{plain_per / per:.3g}", f"{fact_per / per:.3g}"], w)
    if result.get("dask"):
        lines += cluster_lines(result["dask"],
                               f"tolerance_study, {result['dask_samples']} samples",
                               markdown=markdown)
    lines.append("")
    lines.append("agreement (max relative difference, checked before timing):")
    for k, v in result["agreement"].items():
        lines.append(f"  {k}: {v:.2g}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    ap.add_argument("--n", type=int, nargs="+", default=[1_000, 10_000, 100_000],
                    help="Monte-Carlo samples of the in-process tolerance study")
    ap.add_argument("--dask-n", type=int, default=100_000,
                    help="samples of the dask runs (0: none)")
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2],
                    help="worker processes of each local dask cluster")
    ap.add_argument("--no-dask", action="store_true", help="skip the dask runs")
    ap.add_argument("--no-fused", action="store_true", help="skip the fused numba kernel")
    ap.add_argument("--resolve-n", type=int, default=10,
                    help="samples of the per-sample contenders")
    ap.add_argument("--positions", type=int, default=360, help="crank positions of the cycle")
    ap.add_argument("--repeat", type=int, default=5, help="rounds (samples per contender)")
    ap.add_argument("--long-repeat", type=int, default=3,
                    help="rounds of calls longer than 1 s")
    ap.add_argument("--chunk-size", type=int, default=10_000,
                    help="samples per chunk of tolerance_study (the library's default)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--markdown", action="store_true", help="print Markdown tables")
    ap.add_argument("--json", help="also write the rows to this JSON file")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    load0 = load()
    result = run(tuple(args.n), args.positions, args.repeat, args.resolve_n,
                 0 if args.no_dask else args.dask_n, args.seed, args.chunk_size,
                 args.long_repeat, tuple(args.workers), not args.no_fused)
    finish(result, table(result, markdown=args.markdown),
           f"{args.repeat} rounds ({args.long_repeat} for calls > 1 s); "
           f"{result['tolerances']} toleranced deviations", load0, t0, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
