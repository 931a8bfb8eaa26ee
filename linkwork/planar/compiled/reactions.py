"""Inverse dynamics through a numba kernel: the compiled backend of
:func:`~linkwork.planar.dynamics.inverse_dynamics` (``backend="numba"``).

One pass over the positions (over the (design, position) elements of a batch of designs)
computes, element by element, what the NumPy path computes operation by operation over all
positions: the bodies' weight and inertia forces at their centres of mass and the kinetic
energy (:mod:`~linkwork.planar.inertia`), the reactions group by group, last group first
(``_group_reactions`` of :mod:`~linkwork.planar.dynamics`: a dyad's transposed closure system,
2 x 2 by Cramer's rule, then each body's external reaction; the drivers' torques and forces),
the reaction points and the shaking force and moment. The conventions, formulas and order of
operations are those of the NumPy path, which stays the reference: the two agree to rounding
(numba's ``cos``/``sin`` may differ from NumPy's in the last bit).

The kernel is generated per plan structure (:func:`kernel_source`, compiled and cached once
per structure by :mod:`~linkwork.planar.compiled.codegen`): the loops over the bodies, groups
and joints are unrolled while the source is written and every decision of the structure is
taken there, so the bodies' cos, sin and unbalanced loads and the joints' reactions are local
variables; the masses and the joints' geometry are read from the tables per design.

Compiled plans (:func:`encode` gives None for any other, and the NumPy path runs):

* joints: :class:`~linkwork.planar.joints.Revolute`, :class:`~linkwork.planar.joints.Prismatic`
  and :class:`~linkwork.planar.joints.PinInSlot` (exactly these types), none with friction;
* groups: the drivers (a Crank on a revolute joint, a Linear driver on a prismatic one; one or
  several, each a group of its own), the closed-form dyads RRR, RRP, PRR, RPR, RPP, PPR, PRP
  and the one-body slot groups RS, PS.

Not compiled: friction (the Newton solve of :mod:`~linkwork.planar.friction`), gear pairs
(their separating forces), Newton groups and driven cylinders (the global reactions by the
whole constraint Jacobian). The applied loads (:mod:`~linkwork.planar.forces`) are evaluated
by NumPy as always; the kernel takes their resultant on each body.

This module imports numba: :mod:`~linkwork.planar.dynamics` imports it only when the compiled
backend is asked for.
"""

from __future__ import annotations

import functools
import sys
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.planar.compiled import numba_module
from linkwork.planar.compiled.codegen import (
    Source,
    call,
    decorator,
    fingerprint,
    loop,
    structure_kernel,
)
from linkwork.planar.joints import PinInSlot, Prismatic, Revolute
from linkwork.planar.state import Arr
from linkwork.planar.structure import HUNG

__all__ = ["Encoded", "encode", "kernel", "kernel_source", "load_resultants", "solve"]

_numba = numba_module()
#: the kernel's helpers: inlined into it by numba (they take numbers only, see below)
_inline = _numba.njit(cache=True, fastmath=False, error_model="numpy", inline="always")

# joint types, group codes, driver kinds of the encoded plan
_R, _P, _S = 0, 1, 2
_CRANK, _LINEAR, _DYAD, _SLOT = 0, 1, 2, 3
_JOINT_TYPES = {Revolute: _R, Prismatic: _P, PinInSlot: _S}


@dataclass(frozen=True, eq=False)
class Encoded:
    """A compiled plan as the kernel reads it: flat arrays, per-design values on the last
    axis (m = 1 for one design).

    Attributes
    ----------
    nb, nj, nd : int
        Bodies (the frame included), joints, drivers.
    mass, inertia, comx, comy : ndarray (nb, m)
        The bodies' mass properties (row 0, the frame, zero).
    jt, ja, jb, jd : ndarray of int64 (nj,)
        Each joint's type (0 revolute, 1 prismatic, 2 pin-in-slot), body indices a and b and
        driver index (-1: none).
    geo : ndarray (nj, 6, m)
        Each joint's point on a, point on b and line direction in a (x, y each).
    gk, gj, gb : ndarray of int64
        The groups, last first: kind (0 crank, 1 linear driver, 2 dyad, 3 slot group), joints
        (ng, 3) (external joint of the first body, the joint between the bodies -- a slot
        group's slot --, external joint of the second body or -1) and bodies (ng, 2).
    dk : ndarray of int64 (nd,)
        Each driver's kind (0 crank, 1 linear).
    scale : ndarray (m,)
        The plan's length scale [m] (the singularity test of a slot group's 1 x 1 system).
    """

    nb: int
    nj: int
    nd: int
    mass: Arr
    inertia: Arr
    comx: Arr
    comy: Arr
    jt: Arr
    ja: Arr
    jb: Arr
    jd: Arr
    geo: Arr
    gk: Arr
    gj: Arr
    gb: Arr
    dk: Arr
    scale: Arr


_CACHE: weakref.WeakKeyDictionary[Any, Encoded | None] = weakref.WeakKeyDictionary()


def encode(mech: Any) -> Encoded | None:
    """The plan of ``mech`` encoded for the kernel, or None if the kernel does not cover it
    (see the module docstring); worked out once per plan."""
    plan = mech.plan
    try:
        return _CACHE[plan]
    except KeyError:
        pass
    enc = _encode(mech, plan)
    _CACHE[plan] = enc
    return enc


def _per_design(value: Any, m: int) -> Arr:
    return np.broadcast_to(np.asarray(value, dtype=float), (m,))


def _encode(mech: Any, plan: Any) -> Encoded | None:
    if plan.global_reactions:
        return None
    for rj in plan.joints:
        if type(rj.joint) not in _JOINT_TYPES or rj.joint.has_friction:
            return None
    kinds = plan.driver_kinds
    for rj, kind in zip(plan.drivers, kinds, strict=True):
        if (kind, type(rj.joint)) not in (("crank", Revolute), ("linear", Prismatic)):
            return None
    m = mech.n_designs or 1
    nb, nj = plan.nb, len(plan.joints)
    mass = np.zeros((nb, m))
    inertia = np.zeros((nb, m))
    comx = np.zeros((nb, m))
    comy = np.zeros((nb, m))
    for b in mech.bodies:
        i = mech.index[b.name]
        mass[i], inertia[i] = _per_design(b.mass, m), _per_design(b.inertia, m)
        comx[i], comy[i] = _per_design(b.com[0], m), _per_design(b.com[1], m)
    geo = np.zeros((nj, 6, m))
    jt = np.zeros(nj, dtype=np.int64)
    ja = np.zeros(nj, dtype=np.int64)
    jb = np.zeros(nj, dtype=np.int64)
    jd = np.full(nj, -1, dtype=np.int64)
    for q, rj in enumerate(plan.joints):
        jt[q], ja[q], jb[q] = _JOINT_TYPES[type(rj.joint)], rj.ia, rj.ib
        jd[q] = rj.drive_index if rj.drive else -1
        for k, v in enumerate((*rj.qa, *rj.pb, *rj.u_loc)):
            geo[q, k] = _per_design(v, m)
    index = {id(rj): q for q, rj in enumerate(plan.joints)}
    groups = []
    for g in reversed(plan.groups):
        js = [index[id(rj)] for rj in g.joints]
        if g.kind == "driver":
            code = _CRANK if kinds[g.joints[0].drive_index] == "crank" else _LINEAR
            groups.append((code, (js[0], -1, -1), (g.bodies[0], -1)))
        elif g.kind in ("RS", "PS"):
            groups.append((_SLOT, (js[0], js[1], -1), (g.bodies[0], -1)))
        elif g.kind in HUNG:
            groups.append((_DYAD, (js[0], js[1], js[2]), (g.bodies[0], g.bodies[1])))
        else:
            return None
    return Encoded(nb, nj, len(plan.drivers), mass, inertia, comx, comy, jt, ja, jb, jd, geo,
                   np.array([c for c, _, _ in groups], dtype=np.int64),
                   np.array([j for _, j, _ in groups], dtype=np.int64).reshape(-1, 3),
                   np.array([b for _, _, b in groups], dtype=np.int64).reshape(-1, 2),
                   np.array([0 if k == "crank" else 1 for k in kinds], dtype=np.int64),
                   _per_design(plan.length_scale, m).copy())


def load_resultants(enc: Encoded, index: dict[str, int], applied: Sequence[Any],
                    about: tuple[float, float], x: Arr, y: Arr, sl: slice) -> Arr:
    """The resultant of the loads' wrenches (:class:`~linkwork.planar.forces.Wrench` of each
    applied load) on every body over the positions ``sl``: array (nb, 3, positions) of the
    force (x, y) [N] and its moment [N m] about the body's origin ``(x, y)[i]`` (the frame's
    row, the loads' reactions on it: about the point ``about``, for the shaking moment)."""
    npos = len(range(*sl.indices(x.shape[-1])))
    out = np.zeros((enc.nb, 3, npos))
    for ap in applied:
        for w in ap.wrenches:
            i = index[w.body]
            fx, fy, px, py, mz = (v[sl] if np.ndim(v) else v
                                  for v in (w.fx, w.fy, w.px, w.py, w.mz))
            ox, oy = (about[0], about[1]) if i == 0 else (x[i, sl], y[i, sl])
            out[i, 0] += fx
            out[i, 1] += fy
            out[i, 2] += (px - ox) * fy - (py - oy) * fx + mz
    return out


def solve(enc: Encoded, kin: Any, gravity: tuple[float, float], about: tuple[float, float],
          applied: Sequence[Any], chunk: int, threads: int = 1) -> dict[str, Arr]:
    """Reactions (``fx, fy, mz, px, py`` (nj, ...)), driving loads ``Q`` (nd, ...), shaking
    force and moment and kinetic energy (``shaking_fx, shaking_fy, shaking_m, T``) of the
    motion ``kin`` (arrays (nb, n), or (nb, m, n) for a batch of designs: the results' last
    axes are those of ``kin.x`` after the first), with the loads ``applied`` (one design) in
    chunks of ``chunk`` positions (their resultants are the only temporaries)."""
    shape = kin.x.shape[1:]
    N = int(np.prod(shape))
    n = int(shape[-1])
    keys = ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps")
    arrs = [np.ascontiguousarray(getattr(kin, k), dtype=float).reshape(enc.nb, N)
            for k in keys]
    # every result in one block: one allocation, whose memory the allocator keeps for the
    # next call (separate arrays of a few MB each were returned to the system and faulted in
    # again at every call: 15 of 35 ms at 10^5 positions of the four-bar on this machine)
    nj, nd = enc.nj, enc.nd
    block = np.empty((5 * nj + nd + 4, N))
    rows = [block[k * nj:(k + 1) * nj] for k in range(5)] + [block[5 * nj:5 * nj + nd]]
    rows += [block[5 * nj + nd + k] for k in range(4)]
    names = ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m", "T")
    out = {k: r.reshape(*r.shape[:-1], *shape) for k, r in zip(names, rows, strict=True)}
    wrenches = [w for ap in applied for w in ap.wrenches]
    steps = [(lo, min(lo + chunk, N)) for lo in range(0, N, chunk)] if wrenches else [(0, N)]
    # the bodies' cos, sin where the motion holds them already (Kinematics._cos_sin, computed
    # once per motion: by the loads, or by a kinematics that keeps them), else the kernel's own
    cs = kin.__dict__.get("_cos_sin")
    cos, sin = (_NO_COS_SIN, _NO_COS_SIN) if cs is None else (
        np.ascontiguousarray(v, dtype=float).reshape(enc.nb, N) for v in cs)
    index = kin.mechanism.index
    run = kernel(enc, threads > 1)
    for lo, hi in steps:
        fl = (load_resultants(enc, index, applied, about, arrs[0], arrs[1], slice(lo, hi))
              if wrenches else _NO_LOADS)
        call(run, threads, *arrs, n, enc.mass, enc.inertia, enc.comx, enc.comy, enc.geo,
             enc.scale, float(gravity[0]), float(gravity[1]), float(about[0]),
             float(about[1]), fl, cos, sin, lo, hi, *rows)
    return out


_NO_LOADS = np.zeros((0, 3, 0))
_NO_COS_SIN = np.zeros((0, 0))


# ---------------------------------------------------------------------------------------------
# the kernel's one helper: it takes and returns numbers only (a helper taking arrays, even
# inlined, costs a reference count taken and released per array and call)
@_inline
def _rot(c: float, s: float, x: float, y: float) -> tuple[float, float]:
    """A local vector (x, y) of a body at angle (cos, sin) = (c, s), in frame axes."""
    return c * x - s * y, s * x + c * y


# ---------------------------------------------------------------------------------------------
# the kernel, generated per plan structure (:mod:`~linkwork.planar.compiled.codegen`): the
# interpreter's loops over the bodies, groups and joints unrolled, every decision of the
# structure (joint types and bodies, group kinds, drivers) taken while the source is written;
# the bodies' cos, sin and unbalanced loads, the hung bodies' vectors, the closure coefficients
# and the joints' reactions are local variables. The operations and their order are the
# interpreter's, so are the results, bit for bit.
def _point_b(src: Source, enc: Encoded, q: int) -> None:
    """``px, py``: the world point of joint ``q`` on its body b."""
    i = int(enc.jb[q])
    src(f"rx, ry = _rot(c{i}, s{i}, geo[{q}, 2, d], geo[{q}, 3, d])",
        f"px, py = X[{i}, p] + rx, Y[{i}, p] + ry")


def _write_group(src: Source, enc: Encoded, g: int) -> None:
    """The reactions of group ``g`` (groups last first), its driver's load included."""
    jt, ja, jb, jd = enc.jt, enc.ja, enc.jb, enc.jd
    kind = int(enc.gk[g])
    gj, gb = [int(v) for v in enc.gj[g]], [int(v) for v in enc.gb[g]]
    nh = 2 if kind == _DYAD else 1
    rev = []  # each hung body turns about a pivot (1.0) or slides (0.0)
    for h in range(nh):
        q, b = gj[2 * h], gb[h]
        if jt[q] == _R:  # turning about the pivot A
            k = int(ja[q]) if b == jb[q] else int(jb[q])
            o = 0 if k == ja[q] else 2
            src(f"rx, ry = _rot(c{k}, s{k}, geo[{q}, {o}, d], geo[{q}, {o + 1}, d])",
                f"hv{h}1, hv{h}2 = X[{k}, p] + rx, Y[{k}, p] + ry")
            rev.append(1.0)
        else:  # sliding along the guide u
            k = int(ja[q])
            src(f"hv{h}1, hv{h}2 = _rot(c{k}, s{k}, geo[{q}, 4, d], geo[{q}, 5, d])")
            rev.append(0.0)
    if kind in (_CRANK, _LINEAR):
        q, b = gj[0], gb[0]
        sgn = 1.0 if b == jb[q] else -1.0
        other = int(ja[q]) if sgn > 0 else int(jb[q])
        if kind == _CRANK:  # a torque about the pivot
            src(f"torque = -(M0{b} - (hv01 * Fy{b} - hv02 * Fx{b}))",
                f"Q{jd[q]} = {sgn!r} * torque",
                f"M0{b} = M0{b} + torque")
            if other != 0:
                src(f"M0{other} = M0{other} - torque")
        else:  # a force along the guide at the slider point
            _point_b(src, enc, q)
            src("ux, uy = hv01, hv02",
                f"drive = -(Fx{b} * ux + Fy{b} * uy)",
                f"Q{jd[q]} = {sgn!r} * drive",
                "fx, fy = drive * ux, drive * uy",
                f"Fx{b} = Fx{b} + fx",
                f"Fy{b} = Fy{b} + fy",
                f"M0{b} = M0{b} + px * fy - py * fx + 0.0")
            if other != 0:
                src(f"Fx{other} = Fx{other} + -fx",
                    f"Fy{other} = Fy{other} + -fy",
                    f"M0{other} = M0{other} + px * -fy - py * -fx + 0.0")
    # the reactions: a dyad's or slot group's closure joint first (r = 0), then each hung
    # body's external joint (r = 1, 2)
    for r in range(1 if kind in (_CRANK, _LINEAR) else 0, nh + 1):
        if r == 0:  # the closure joint: the transposed velocity-closure system
            q = gj[1]
            ia, on = int(ja[q]), int(jb[q])
            b1, b2 = gb
            ka = 0 if ia == b1 else (1 if nh == 2 and ia == b2 else -1)
            kb = 0 if on == b1 else (1 if nh == 2 and on == b2 else -1)
            _point_b(src, enc, q)  # (on: the joint's body b)
            src(f"ux, uy = _rot(c{ia}, s{ia}, geo[{q}, 4, d], geo[{q}, 5, d])",
                "nx, ny = -uy, ux",
                "C00, C01, C10, C11 = 0.0, 0.0, 0.0, 0.0")
            for kk, sg in ((ka, 1.0), (kb, -1.0)):
                if kk < 0:
                    continue
                if rev[kk] > 0.0:
                    src(f"dx, dy = -(py - hv{kk}2), px - hv{kk}1")
                else:
                    src(f"dx, dy = hv{kk}1, hv{kk}2")
                if jt[q] == _R:  # v_a(B) = v_b(B)
                    src(f"C0{kk} += {sg!r} * dx", f"C1{kk} += {sg!r} * dy")
                else:  # n . (v_b(P) - v_a(P)) = 0; a prismatic pair: w_a = w_b
                    src(f"C0{kk} += {-sg!r} * (nx * dx + ny * dy)")
                    if jt[q] == _P:
                        src(f"C1{kk} += {sg!r} * {rev[kk]!r}")
            # the transposed system: sum_r C[r, beta] lambda_r = power of beta's loads
            for h in range(nh):
                b = gb[h]
                if rev[h] > 0.0:
                    src(f"pw{h} = M0{b} - (hv{h}1 * Fy{b} - hv{h}2 * Fx{b})")
                else:
                    src(f"pw{h} = Fx{b} * hv{h}1 + Fy{b} * hv{h}2")
            if nh == 2:
                src("a11, a12, a21, a22 = C00, C10, C01, C11",
                    "det = a11 * a22 - a12 * a21",
                    "norm = math.hypot(a11, a21) * math.hypot(a12, a22)",
                    "inv = 1.0 / det if abs(det) > 1e-7 * norm else math.nan",
                    "lam0 = (pw0 * a22 - pw1 * a12) * inv",
                    "lam1 = (a11 * pw1 - a21 * pw0) * inv")
            else:
                src("a = C00",
                    "lam0 = pw0 / a if abs(a) > 1e-7 * scale[d] else math.nan",
                    "lam1 = 0.0")
            if jt[q] == _R:
                src("fx, fy, mz = lam0, lam1, 0.0")
            else:  # normal to the line (and the couple, for a prismatic pair)
                src("N = -lam0",
                    f"fx, fy, mz = N * -uy, N * ux, {'lam1' if jt[q] == _P else '0.0'}")
        else:  # balance the hung body with the reaction of its external joint
            h = r - 1
            q, on = gj[2 * h], gb[h]
            if rev[h] > 0.0:  # a force through the pivot
                src(f"fx, fy, mz, px, py = -Fx{on}, -Fy{on}, 0.0, hv{h}1, hv{h}2")
            else:  # a force normal to the guide at the slider point, and a couple
                _point_b(src, enc, q)
                src(f"nx, ny = -hv{h}2, hv{h}1",
                    f"N = -(Fx{on} * nx + Fy{on} * ny)",
                    "fx, fy = N * nx, N * ny",
                    f"mz = -(M0{on} - (px * Fy{on} - py * Fx{on}))")
        other = int(jb[q]) if on == ja[q] else int(ja[q])
        sgn = 1.0 if on == jb[q] else -1.0
        src(f"rfx{q} += {sgn!r} * fx", f"rfy{q} += {sgn!r} * fy", f"rmz{q} += {sgn!r} * mz")
        if on != 0:
            src(f"Fx{on} = Fx{on} + fx",
                f"Fy{on} = Fy{on} + fy",
                f"M0{on} = M0{on} + px * fy - py * fx + mz")
        if other != 0:
            src(f"Fx{other} = Fx{other} + -fx",
                f"Fy{other} = Fy{other} + -fy",
                f"M0{other} = M0{other} + px * -fy - py * -fx + -mz")


def kernel_source(enc: Encoded, parallel: bool = False) -> str:
    """The source of the kernel of ``enc``'s plan structure: ``kernel`` with the arguments of
    :func:`solve`'s call (the interpreter's, without the structure's tables); the elements
    shared among numba's threads if ``parallel``."""
    nb, nj, nd = enc.nb, enc.nj, enc.nd
    ja, jb, jd, dk = enc.ja, enc.jb, enc.jd, enc.dk
    src = Source()
    src(f"# generated by linkwork.planar.compiled.reactions; helpers {_helpers_hash()}",
        "import math",
        "from numba import njit, prange",
        "from linkwork.planar.compiled.reactions import _rot",
        "",
        "",
        decorator(parallel),
        "def kernel(X, Y, TH, VX, VY, W, AX, AY, E, n, mass, inertia, comx, comy, geo, scale,",
        "           gx, gy, abx, aby, fl, cos, sin, lo, hi, rfx, rfy, rmz, rpx, rpy, Q, sfx,",
        "           sfy, sm, T):")
    src.indent()
    src("loads = fl.shape[2] > 0",
        "known = cos.shape[0] > 0",
        f"for p in {loop(parallel)}(lo, hi):")
    src.indent()
    src("d = p // n")
    for i in range(nb):
        src(f"th = TH[{i}, p]",
            "if known:",
            f"    c{i}, s{i} = cos[{i}, p], sin[{i}, p]",
            "elif th == 0.0:  # the frame, and any body at angle 0: exactly cos 0, sin 0",
            f"    c{i}, s{i} = 1.0, 0.0",
            "else:",
            f"    c{i}, s{i} = math.cos(th), math.sin(th)")
    # weight and inertia force at the centre of mass, inertia couple, kinetic energy
    src("t = 0.0")
    for i in range(1, nb):
        src(f"rx, ry = _rot(c{i}, s{i}, comx[{i}, d], comy[{i}, d])",
            f"w, e = W[{i}, p], E[{i}, p]",
            f"m, inert = mass[{i}, d], inertia[{i}, d]",
            f"vcx, vcy = VX[{i}, p] - w * ry, VY[{i}, p] + w * rx",
            f"acx = AX[{i}, p] - e * ry - w * w * rx",
            f"acy = AY[{i}, p] + e * rx - w * w * ry",
            "fx, fy = m * (gx - acx), m * (gy - acy)",
            f"rx2, ry2 = (X[{i}, p] + rx) - X[{i}, p], (Y[{i}, p] + ry) - Y[{i}, p]",
            "fm = rx2 * fy - ry2 * fx + (-(inert * e))",
            "if loads:",
            f"    fx += fl[{i}, 0, p - lo]",
            f"    fy += fl[{i}, 1, p - lo]",
            f"    fm += fl[{i}, 2, p - lo]",
            f"Fx{i}, Fy{i} = fx, fy",
            f"M0{i} = fm + X[{i}, p] * fy - Y[{i}, p] * fx",
            "t += 0.5 * m * (vcx * vcx + vcy * vcy) + 0.5 * inert * (w * w)")
    src("T[p] = t")
    for q in range(nj):
        src(f"rfx{q} = rfy{q} = rmz{q} = 0.0")
    for g in range(enc.gk.shape[0]):
        _write_group(src, enc, g)
    # reaction points and the shaking force and moment on the frame
    src("shx, shy, shm = 0.0, 0.0, 0.0")
    for q in range(nj):
        _point_b(src, enc, q)
        src(f"rpx[{q}, p] = px",
            f"rpy[{q}, p] = py",
            f"rfx[{q}, p] = rfx{q}",
            f"rfy[{q}, p] = rfy{q}",
            f"rmz[{q}, p] = rmz{q}")
        if ja[q] != 0 and jb[q] != 0:
            continue
        sg = -1.0 if ja[q] == 0 else 1.0
        src(f"fx, fy, mz = {sg!r} * rfx{q}, {sg!r} * rfy{q}, {sg!r} * rmz{q}")
        kd = int(jd[q])
        linear = kd >= 0 and dk[kd] == 1
        if linear:  # the driving force along the guide
            a = int(ja[q])
            src(f"ux, uy = _rot(c{a}, s{a}, geo[{q}, 4, d], geo[{q}, 5, d])",
                f"fx = fx + {sg!r} * Q{kd} * ux",
                f"fy = fy + {sg!r} * Q{kd} * uy")
        src("shx += fx",
            "shy += fy",
            "shm += (px - abx) * fy - (py - aby) * fx + mz")
        if kd >= 0 and not linear:  # the motor's reaction torque
            src(f"shm += {sg!r} * Q{kd}")
    for kd in range(nd):
        src(f"Q[{kd}, p] = Q{kd}")
    src("if loads:  # the loads' reactions on the frame",
        "    shx += fl[0, 0, p - lo]",
        "    shy += fl[0, 1, p - lo]",
        "    shm += fl[0, 2, p - lo]",
        "sfx[p] = shx",
        "sfy[p] = shy",
        "sm[p] = shm")
    return src.text()


@functools.cache
def _helpers_hash() -> str:
    return fingerprint(sys.modules[__name__])


def kernel(enc: Encoded, parallel: bool = False) -> Any:
    """The compiled kernel of ``enc``'s plan structure, serial or ``parallel`` (generated,
    compiled and cached once per structure: :mod:`~linkwork.planar.compiled.codegen`)."""
    key = (enc.nb, enc.nj, enc.nd, parallel, *(a.tobytes() for a in (
        enc.jt, enc.ja, enc.jb, enc.jd, enc.gk, enc.gj, enc.gb, enc.dk)))
    return structure_kernel("reactions", key, lambda: kernel_source(enc, parallel))
