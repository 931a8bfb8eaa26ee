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

import math
import weakref
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.planar.compiled import numba_module
from linkwork.planar.joints import PinInSlot, Prismatic, Revolute
from linkwork.planar.state import Arr
from linkwork.planar.structure import HUNG

__all__ = ["Encoded", "encode", "load_resultants", "solve"]

_numba = numba_module()
#: the kernels' compilation: cached on disk, IEEE arithmetic (no fastmath), NumPy's error
#: model (a division by zero gives inf or NaN, as in the NumPy path, not an exception)
_jit = _numba.njit(cache=True, fastmath=False, error_model="numpy")
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
          applied: Sequence[Any], chunk: int) -> dict[str, Arr]:
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
    for lo, hi in steps:
        fl = (load_resultants(enc, index, applied, about, arrs[0], arrs[1], slice(lo, hi))
              if wrenches else _NO_LOADS)
        _kernel(*arrs, n, enc.mass, enc.inertia, enc.comx, enc.comy, enc.jt, enc.ja, enc.jb,
                enc.jd, enc.geo, enc.gk, enc.gj, enc.gb, enc.dk, enc.scale,
                float(gravity[0]), float(gravity[1]), float(about[0]), float(about[1]),
                fl, cos, sin, lo, hi, *rows)
    return out


_NO_LOADS = np.zeros((0, 3, 0))
_NO_COS_SIN = np.zeros((0, 0))


# ---------------------------------------------------------------------------------------------
# the kernel: one element at a time. Its helpers take and return numbers only: a helper
# taking arrays, even inlined, costs a reference count taken and released per array and call
# (0.4-0.7 us per element of the four-bar against 0.17 without)
@_inline
def _rot(c: float, s: float, x: float, y: float) -> tuple[float, float]:
    """A local vector (x, y) of a body at angle (cos, sin) = (c, s), in frame axes."""
    return c * x - s * y, s * x + c * y


@_inline
def _direction(rev: float, v0: float, v1: float, x: float, y: float) -> tuple[float, float]:
    """The velocity of the world point (x, y) of a hung body per unit of its unknown rate:
    turning about the pivot (v0, v1) (``rev`` 1) or sliding along (v0, v1) (``rev`` 0)."""
    if rev > 0.0:
        return -(y - v1), x - v0
    return v0, v1


@_jit
def _kernel(X: Arr, Y: Arr, TH: Arr, VX: Arr, VY: Arr, W: Arr, AX: Arr, AY: Arr, E: Arr,
            n: int, mass: Arr, inertia: Arr, comx: Arr, comy: Arr, jt: Arr, ja: Arr, jb: Arr,
            jd: Arr, geo: Arr, gk: Arr, gj: Arr, gb: Arr, dk: Arr, scale: Arr, gx: float,
            gy: float, abx: float, aby: float, fl: Arr, cos: Arr, sin: Arr, lo: int, hi: int,
            rfx: Arr, rfy: Arr,
            rmz: Arr, rpx: Arr, rpy: Arr, Q: Arr, sfx: Arr, sfy: Arr, sm: Arr, T: Arr
            ) -> None:
    """Inverse dynamics of the elements lo..hi-1 (element p: design p // n); ``fl`` the
    loads' resultants on the bodies there (:func:`load_resultants`; no loads: empty); ``cs``
    the bodies' ``cos``, ``sin`` (nb, elements) if known (else empty: computed here)."""
    nb = X.shape[0]
    nj = jt.shape[0]
    loads = fl.shape[2] > 0
    known = cos.shape[0] > 0
    c = np.empty(nb)
    s = np.empty(nb)
    Fx = np.zeros(nb)  # the loads on each body not yet balanced: force, moment about O
    Fy = np.zeros(nb)
    M0 = np.zeros(nb)
    hv = np.zeros((2, 3))  # each hung body: (1 turning about a pivot | 0 sliding, vector)
    C = np.zeros((2, 2))  # a closure's coefficients (rows, unknowns)
    for p in range(lo, hi):
        d = p // n
        for i in range(nb):
            th = TH[i, p]
            if known:
                c[i], s[i] = cos[i, p], sin[i, p]
            elif th == 0.0:  # the frame, and any body at angle 0: exactly cos 0, sin 0
                c[i], s[i] = 1.0, 0.0
            else:
                c[i], s[i] = math.cos(th), math.sin(th)
        # weight and inertia force at the centre of mass, inertia couple, kinetic energy
        t = 0.0
        for i in range(1, nb):
            rx, ry = _rot(c[i], s[i], comx[i, d], comy[i, d])
            w, e = W[i, p], E[i, p]
            m, inert = mass[i, d], inertia[i, d]
            vcx, vcy = VX[i, p] - w * ry, VY[i, p] + w * rx
            acx = AX[i, p] - e * ry - w * w * rx
            acy = AY[i, p] + e * rx - w * w * ry
            fx, fy = m * (gx - acx), m * (gy - acy)
            rx2, ry2 = (X[i, p] + rx) - X[i, p], (Y[i, p] + ry) - Y[i, p]
            fm = rx2 * fy - ry2 * fx + (-(inert * e))
            if loads:
                fx += fl[i, 0, p - lo]
                fy += fl[i, 1, p - lo]
                fm += fl[i, 2, p - lo]
            Fx[i], Fy[i] = fx, fy
            M0[i] = fm + X[i, p] * fy - Y[i, p] * fx
            t += 0.5 * m * (vcx * vcx + vcy * vcy) + 0.5 * inert * (w * w)
        T[p] = t
        for q in range(nj):
            rfx[q, p] = 0.0
            rfy[q, p] = 0.0
            rmz[q, p] = 0.0
        # the groups, last first
        for g in range(gk.shape[0]):
            kind = gk[g]
            nh = 2 if kind == _DYAD else 1
            # each body hung on its known neighbour by its external joint (RatePar)
            for h in range(nh):
                q, b = gj[g, 2 * h], gb[g, h]
                if jt[q] == _R:  # turning about the pivot A
                    k = ja[q] if b == jb[q] else jb[q]
                    o = 0 if k == ja[q] else 2
                    rx, ry = _rot(c[k], s[k], geo[q, o, d], geo[q, o + 1, d])
                    hv[h, 0], hv[h, 1], hv[h, 2] = 1.0, X[k, p] + rx, Y[k, p] + ry
                else:  # sliding along the guide u
                    k = ja[q]
                    ux, uy = _rot(c[k], s[k], geo[q, 4, d], geo[q, 5, d])
                    hv[h, 0], hv[h, 1], hv[h, 2] = 0.0, ux, uy
            if kind == _CRANK:  # a torque about the pivot
                q, b = gj[g, 0], gb[g, 0]
                sgn = 1.0 if b == jb[q] else -1.0
                other = ja[q] if sgn > 0 else jb[q]
                torque = -(M0[b] - (hv[0, 1] * Fy[b] - hv[0, 2] * Fx[b]))
                Q[jd[q], p] = sgn * torque
                M0[b] = M0[b] + torque
                if other != 0:
                    M0[other] = M0[other] - torque
            elif kind == _LINEAR:  # a force along the guide at the slider point
                q, b = gj[g, 0], gb[g, 0]
                sgn = 1.0 if b == jb[q] else -1.0
                other = ja[q] if sgn > 0 else jb[q]
                i = jb[q]
                rx, ry = _rot(c[i], s[i], geo[q, 2, d], geo[q, 3, d])
                px, py = X[i, p] + rx, Y[i, p] + ry
                ux, uy = hv[0, 1], hv[0, 2]
                drive = -(Fx[b] * ux + Fy[b] * uy)
                Q[jd[q], p] = sgn * drive
                fx, fy = drive * ux, drive * uy
                Fx[b] = Fx[b] + fx
                Fy[b] = Fy[b] + fy
                M0[b] = M0[b] + px * fy - py * fx + 0.0
                if other != 0:
                    Fx[other] = Fx[other] + -fx
                    Fy[other] = Fy[other] + -fy
                    M0[other] = M0[other] + px * -fy - py * -fx + 0.0
            # the reactions, each recorded on the body it balances (by a on b: the sign) and
            # its opposite applied to the joint's other body: a dyad's or slot group's closure
            # joint first (r = 0), then each hung body's external joint (r = 1, 2)
            for r in range(1 if kind == _CRANK or kind == _LINEAR else 0, nh + 1):
                if r == 0:  # the closure joint: the transposed velocity-closure system
                    q = gj[g, 1]
                    ia, on = ja[q], jb[q]
                    b1, b2 = gb[g, 0], gb[g, 1]
                    ka = 0 if ia == b1 else (1 if nh == 2 and ia == b2 else -1)
                    kb = 0 if on == b1 else (1 if nh == 2 and on == b2 else -1)
                    rx, ry = _rot(c[on], s[on], geo[q, 2, d], geo[q, 3, d])
                    px, py = X[on, p] + rx, Y[on, p] + ry  # the joint's point of b
                    ux, uy = _rot(c[ia], s[ia], geo[q, 4, d], geo[q, 5, d])
                    nx, ny = -uy, ux
                    C[0, 0], C[0, 1], C[1, 0], C[1, 1] = 0.0, 0.0, 0.0, 0.0
                    # its rows in the unknown rates (coefficients only): ka, kb the unknown
                    # of its body a, b (-1: a known body), sg the sign of its term
                    for kk, sg in ((ka, 1.0), (kb, -1.0)):
                        if kk < 0:
                            continue
                        dx, dy = _direction(hv[kk, 0], hv[kk, 1], hv[kk, 2], px, py)
                        if jt[q] == _R:  # v_a(B) = v_b(B)
                            C[0, kk] += sg * dx
                            C[1, kk] += sg * dy
                        else:  # n . (v_b(P) - v_a(P)) = 0; a prismatic pair: w_a = w_b
                            C[0, kk] += -sg * (nx * dx + ny * dy)
                            if jt[q] == _P:
                                C[1, kk] += sg * hv[kk, 0]
                    # the transposed system: sum_r C[r, beta] lambda_r = power of beta's loads
                    pw0, pw1 = 0.0, 0.0
                    for h in range(nh):
                        b = gb[g, h]
                        if hv[h, 0] > 0.0:
                            pw = M0[b] - (hv[h, 1] * Fy[b] - hv[h, 2] * Fx[b])
                        else:
                            pw = Fx[b] * hv[h, 1] + Fy[b] * hv[h, 2]
                        if h == 0:
                            pw0 = pw
                        else:
                            pw1 = pw
                    if nh == 2:
                        a11, a12, a21, a22 = C[0, 0], C[1, 0], C[0, 1], C[1, 1]
                        det = a11 * a22 - a12 * a21
                        norm = math.hypot(a11, a21) * math.hypot(a12, a22)
                        inv = 1.0 / det if abs(det) > 1e-7 * norm else math.nan
                        lam0 = (pw0 * a22 - pw1 * a12) * inv
                        lam1 = (a11 * pw1 - a21 * pw0) * inv
                    else:
                        a = C[0, 0]
                        lam0 = pw0 / a if abs(a) > 1e-7 * scale[d] else math.nan
                        lam1 = 0.0
                    if jt[q] == _R:
                        fx, fy, mz = lam0, lam1, 0.0
                    else:  # normal to the line (and the couple, for a prismatic pair)
                        N = -lam0
                        fx, fy, mz = N * -uy, N * ux, (lam1 if jt[q] == _P else 0.0)
                else:  # balance the hung body with the reaction of its external joint
                    h = r - 1
                    q, on = gj[g, 2 * h], gb[g, h]
                    if hv[h, 0] > 0.0:  # a force through the pivot
                        fx, fy, mz, px, py = -Fx[on], -Fy[on], 0.0, hv[h, 1], hv[h, 2]
                    else:  # a force normal to the guide at the slider point, and a couple
                        i = jb[q]
                        rx, ry = _rot(c[i], s[i], geo[q, 2, d], geo[q, 3, d])
                        px, py = X[i, p] + rx, Y[i, p] + ry
                        nx, ny = -hv[h, 2], hv[h, 1]
                        N = -(Fx[on] * nx + Fy[on] * ny)
                        fx, fy = N * nx, N * ny
                        mz = -(M0[on] - (px * Fy[on] - py * Fx[on]))
                other = jb[q] if on == ja[q] else ja[q]
                sgn = 1.0 if on == jb[q] else -1.0
                rfx[q, p] += sgn * fx
                rfy[q, p] += sgn * fy
                rmz[q, p] += sgn * mz
                if on != 0:
                    Fx[on] = Fx[on] + fx
                    Fy[on] = Fy[on] + fy
                    M0[on] = M0[on] + px * fy - py * fx + mz
                if other != 0:
                    Fx[other] = Fx[other] + -fx
                    Fy[other] = Fy[other] + -fy
                    M0[other] = M0[other] + px * -fy - py * -fx + -mz
        # reaction points and the shaking force and moment on the frame
        shx, shy, shm = 0.0, 0.0, 0.0
        for q in range(nj):
            i = jb[q]
            rx, ry = _rot(c[i], s[i], geo[q, 2, d], geo[q, 3, d])
            px, py = X[i, p] + rx, Y[i, p] + ry
            rpx[q, p] = px
            rpy[q, p] = py
            if ja[q] != 0 and jb[q] != 0:
                continue
            sg = -1.0 if ja[q] == 0 else 1.0
            fx, fy, mz = sg * rfx[q, p], sg * rfy[q, p], sg * rmz[q, p]
            kd = jd[q]
            linear = kd >= 0 and dk[kd] == 1
            if linear:  # the driving force along the guide
                ux, uy = _rot(c[ja[q]], s[ja[q]], geo[q, 4, d], geo[q, 5, d])
                fx = fx + sg * Q[kd, p] * ux
                fy = fy + sg * Q[kd, p] * uy
            shx += fx
            shy += fy
            shm += (px - abx) * fy - (py - aby) * fx + mz
            if kd >= 0 and not linear:  # the motor's reaction torque
                shm += sg * Q[kd, p]
        if loads:  # the loads' reactions on the frame
            shx += fl[0, 0, p - lo]
            shy += fl[0, 1, p - lo]
            shm += fl[0, 2, p - lo]
        sfx[p] = shx
        sfy[p] = shy
        sm[p] = shm
