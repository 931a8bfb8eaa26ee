"""Fused compiled loops (numba) with the same outputs as the contenders they bound: the
practical limit of a computation on this machine (one pass over the positions, no temporaries,
scalar ``libm`` transcendentals; compiled before timing, ``fastmath`` off so that the numbers
are those of the algorithm).

* :func:`fourbar` -- the outputs of :func:`linkwork.models.fourbar.fourbar` (theta3, theta4,
  omega3, omega4, eps3, eps4, A, B and the assembly mask) by its algorithm (circle
  intersection, loop-closure derivatives in vector form);
* :func:`crank_slider` -- the 14 outputs of
  :func:`linkwork.models.crank_slider.offset_crank_slider` by its algorithm;
* :func:`engine_fourbar` -- the outputs of :func:`linkwork.planar.kinematics` on
  ``fourbar_mechanism`` (pose, velocity, acceleration of the origin of every body: 9 arrays of
  (4, n), frame row zero) and, with ``reactions``, those of
  :func:`linkwork.planar.inverse_dynamics` that are not identically zero for it (the four
  revolute reactions and their points, the driving torque, the shaking force and moment, the
  kinetic energy), by Newton-Euler written for the four-bar (the coupler-rocker dyad's
  reaction from the moment balances of its two links about their outer joints);
* :func:`tolerance_peaks` -- the peaks of the tolerance study (``c0 + Z d`` over the
  positions, peak |component| and peak bending per joint) for blocks of samples.

Each is checked against the contender it bounds at every size timed (``kinematics.py``,
``tolerance_study.py``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

_NAN = math.nan


@numba.njit(cache=True, inline="always")
def _fourbar_at(t, a, b, c, d, w2):  # type: ignore[no-untyped-def]
    """One position of the four-bar (branch +1, eps1 = 0) by the algorithm of ``fourbar()``:
    A, u = B - A, v = B - O4, u x v, omega3, omega4, eps3, eps4 and whether it assembles."""
    ax = a * math.cos(t)
    ay = a * math.sin(t)
    sx = d - ax
    sy = -ay
    f2 = sx * sx + sy * sy
    k = (b * b - c * c + f2) / (2.0 * f2)
    h2 = b * b / f2 - k * k
    h = math.sqrt(h2) if h2 >= 0.0 else _NAN
    ux = k * sx - h * sy
    uy = k * sy + h * sx
    vx = ux - sx
    vy = uy - sy
    den = ux * vy - uy * vx
    w3 = w2 * (vx * ay - vy * ax) / den
    w4 = w2 * (ux * ay - uy * ax) / den
    gx = w2 * w2 * ax + w3 * w3 * ux - w4 * w4 * vx
    gy = w2 * w2 * ay + w3 * w3 * uy - w4 * w4 * vy
    e3 = (gx * vx + gy * vy) / den
    e4 = (gx * ux + gy * uy) / den
    return ax, ay, ux, uy, vx, vy, den, w3, w4, e3, e4, h2 >= 0.0


@numba.njit(cache=True)
def _fourbar(t, a, b, c, d, w2, out):  # type: ignore[no-untyped-def]
    ok = True
    for i in range(t.size):
        ax, ay, ux, uy, vx, vy, _den, w3, w4, e3, e4, good = _fourbar_at(t[i], a, b, c, d, w2)
        ok = ok and good
        out[0, i] = math.atan2(uy, ux)
        out[1, i] = math.atan2(vy, vx)
        out[2, i] = w3
        out[3, i] = w4
        out[4, i] = e3
        out[5, i] = e4
        out[6, i] = ax
        out[7, i] = ay
        out[8, i] = vx + d
        out[9, i] = vy
    return ok


def fourbar(t: np.ndarray, a: float, b: float, c: float, d: float, w2: float
            ) -> tuple[np.ndarray, bool]:
    """theta3, theta4, omega3, omega4, eps3, eps4, xA, yA, xB, yB as rows of one (10, n)
    array, and whether every position assembles (branch +1, eps1 = 0)."""
    out = np.empty((10, t.size))
    return out, _fourbar(t, a, b, c, d, w2, out)


@numba.njit(cache=True)
def _crank_slider(t, r, l, e, w, out):  # type: ignore[no-untyped-def]
    lam2 = l / r
    lame = e / r
    ok = True
    for i in range(t.size):
        c1 = math.cos(t[i])
        s1 = math.sin(t[i])
        s2 = (lame - c1) / lam2
        if s2 * s2 > 1.0:
            ok = False
        c2 = math.sqrt(1.0 - s2 * s2) if s2 * s2 <= 1.0 else _NAN
        phi2 = math.asin(s2) if s2 * s2 <= 1.0 else _NAN
        xb = r * c1
        yb = r * s1
        inv = 1.0 / (lam2 * c2)
        u21 = s1 * inv
        u21sq = u21 * u21
        ls2 = l * s2
        vq = xb - ls2 * u21
        eq2 = (c1 + lam2 * s2 * u21sq) * inv
        aq = -(yb + l * c2 * u21sq + ls2 * eq2)
        out[0, i] = xb
        out[1, i] = yb
        out[2, i] = e
        out[3, i] = yb + l * c2
        out[4, i] = phi2
        out[5, i] = u21
        out[6, i] = vq
        out[7, i] = eq2
        out[8, i] = aq
        out[9, i] = u21 * w
        out[10, i] = eq2 * (w * w)
        out[11, i] = vq * w
        out[12, i] = aq * (w * w)
        out[13, i] = abs(phi2)
    return ok


def crank_slider(t: np.ndarray, r: float, l: float, e: float, w: float
                 ) -> tuple[np.ndarray, bool]:
    """The 14 outputs of ``offset_crank_slider`` (xB, yB, xC, yC, phi2, u21, vq, eq2, aq,
    omega2, eps2, V_C, a_C, |phi2|, in the order of the flat NumPy form) as rows of one array,
    and whether every position assembles."""
    out = np.empty((14, t.size))
    return out, _crank_slider(t, r, l, e, w, out)


@numba.njit(cache=True)
def _engine_fourbar(t, a, b, c, d, w2, m, inertia, kin, dyn, scalars, reactions):  # type: ignore[no-untyped-def]
    # kin: (9, 4, n) = x, y, theta, vx, vy, omega, ax, ay, eps of frame, crank, coupler, rocker
    # dyn: (4, 4, n) = fx, fy, px, py of joints O2, A, B, O4 (force by a on b)
    # scalars: (5, n) = Q, shaking_fx, shaking_fy, shaking_m, T
    ok = True
    for i in range(t.size):
        ax, ay, ux, uy, vx, vy, den, w3, w4, e3, e4, good = _fourbar_at(t[i], a, b, c, d, w2)
        ok = ok and good
        for q in range(9):
            kin[q, 0, i] = 0.0
        # crank: origin O2, x-axis to A
        kin[0, 1, i] = 0.0
        kin[1, 1, i] = 0.0
        kin[2, 1, i] = t[i]
        kin[3, 1, i] = 0.0
        kin[4, 1, i] = 0.0
        kin[5, 1, i] = w2
        kin[6, 1, i] = 0.0
        kin[7, 1, i] = 0.0
        kin[8, 1, i] = 0.0
        # coupler: origin A, x-axis to B
        vax = -w2 * ay
        vay = w2 * ax
        aax = -w2 * w2 * ax
        aay = -w2 * w2 * ay
        kin[0, 2, i] = ax
        kin[1, 2, i] = ay
        kin[2, 2, i] = math.atan2(uy, ux)
        kin[3, 2, i] = vax
        kin[4, 2, i] = vay
        kin[5, 2, i] = w3
        kin[6, 2, i] = aax
        kin[7, 2, i] = aay
        kin[8, 2, i] = e3
        # rocker: origin O4, x-axis to B
        kin[0, 3, i] = d
        kin[1, 3, i] = 0.0
        kin[2, 3, i] = math.atan2(vy, vx)
        kin[3, 3, i] = 0.0
        kin[4, 3, i] = 0.0
        kin[5, 3, i] = w4
        kin[6, 3, i] = 0.0
        kin[7, 3, i] = 0.0
        kin[8, 3, i] = e4
        if not reactions:
            continue
        # centres of mass at the midpoints; inertia forces -m a_C, couples -I eps
        f1x = m[0] * w2 * w2 * 0.5 * ax
        f1y = m[0] * w2 * w2 * 0.5 * ay
        a2x = aax - e3 * 0.5 * uy - w3 * w3 * 0.5 * ux
        a2y = aay + e3 * 0.5 * ux - w3 * w3 * 0.5 * uy
        f2x = -m[1] * a2x
        f2y = -m[1] * a2y
        a3x = -e4 * 0.5 * vy - w4 * w4 * 0.5 * vx
        a3y = e4 * 0.5 * vx - w4 * w4 * 0.5 * vy
        f3x = -m[2] * a3x
        f3y = -m[2] * a3y
        m2 = -inertia[1] * e3
        m3 = -inertia[2] * e4
        # coupler about A: u x R_B = (u/2) x F2 + M2; rocker about O4: v x R_B = -(v/2) x F3 - M3
        c1 = 0.5 * (ux * f2y - uy * f2x) + m2
        c2 = -(0.5 * (vx * f3y - vy * f3x) + m3)
        rbx = (c1 * vx - ux * c2) / den
        rby = (vy * c1 - uy * c2) / den
        rax = rbx - f2x
        ray = rby - f2y
        r4x = -rbx - f3x
        r4y = -rby - f3y
        r1x = rax - f1x
        r1y = ray - f1y
        Q = ax * ray - ay * rax - 0.5 * (ax * f1y - ay * f1x)   # eps1 = 0: no couple
        bx = d + vx
        by = vy
        dyn[0, 0, i] = r1x
        dyn[1, 0, i] = r1y
        dyn[2, 0, i] = 0.0
        dyn[3, 0, i] = 0.0
        dyn[0, 1, i] = rax
        dyn[1, 1, i] = ray
        dyn[2, 1, i] = ax
        dyn[3, 1, i] = ay
        dyn[0, 2, i] = rbx
        dyn[1, 2, i] = rby
        dyn[2, 2, i] = bx
        dyn[3, 2, i] = by
        dyn[0, 3, i] = r4x
        dyn[1, 3, i] = r4y
        dyn[2, 3, i] = d
        dyn[3, 3, i] = 0.0
        scalars[0, i] = Q
        scalars[1, i] = -(r1x + r4x)
        scalars[2, i] = -(r1y + r4y)
        scalars[3, i] = -d * r4y - Q
        v2x = vax - w3 * 0.5 * uy
        v2y = vay + w3 * 0.5 * ux
        scalars[4, i] = 0.5 * (m[0] * 0.25 * w2 * w2 * a * a + inertia[0] * w2 * w2
                               + m[1] * (v2x * v2x + v2y * v2y) + inertia[1] * w3 * w3
                               + m[2] * 0.25 * w4 * w4 * c * c + inertia[2] * w4 * w4)
    return ok


def engine_fourbar(t: np.ndarray, a: float, b: float, c: float, d: float, w2: float,
                   masses: tuple[float, float, float] = (0.0, 0.0, 0.0),
                   reactions: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """The engine's outputs for ``fourbar_mechanism(a, b, c, d, masses=masses)`` (thin-rod
    inertias, centres of mass at the midpoints, no gravity, no loads, eps1 = 0): the
    kinematics block (9, 4, n); with ``reactions`` the joint block (fx, fy, px, py) x (O2, A,
    B, O4) x n and (Q, shaking_fx, shaking_fy, shaking_m, T) x n; whether all assemble."""
    n = t.size
    m = np.asarray(masses, dtype=float)
    inertia = m * np.array([a, b, c]) ** 2 / 12.0
    kin = np.empty((9, 4, n))
    dyn = np.empty((4, 4, n if reactions else 0))
    sc = np.empty((5, n if reactions else 0))
    ok = _engine_fourbar(t, a, b, c, d, w2, m, inertia, kin, dyn, sc, reactions)
    return kin, dyn, sc, ok


@numba.njit(cache=True)
def _tolerance_peaks(z, c0, draws, n_joints, out):  # type: ignore[no-untyped-def]
    # z (n, m, k), c0 (n, m), draws (S, k) -> out (S, n_joints, 7); m = 6 n_joints
    n, m, k = z.shape
    S = draws.shape[0]
    hi = np.empty(m)
    lo = np.empty(m)
    bend = np.empty(n_joints)
    for s in range(S):
        for r in range(m):
            hi[r] = -np.inf
            lo[r] = np.inf
        for j in range(n_joints):
            bend[j] = 0.0
        for p in range(n):
            for j in range(n_joints):
                b2 = 0.0
                for q in range(6):
                    r = 6 * j + q
                    x = c0[p, r]
                    for kk in range(k):
                        x += z[p, r, kk] * draws[s, kk]
                    if x > hi[r]:
                        hi[r] = x
                    if x < lo[r]:
                        lo[r] = x
                    if q == 3 or q == 4:
                        b2 += x * x
                if b2 > bend[j]:
                    bend[j] = b2
        for j in range(n_joints):
            for q in range(6):
                r = 6 * j + q
                out[s, j, q] = max(hi[r], -lo[r])
            out[s, j, 6] = math.sqrt(bend[j])


def tolerance_peaks(z: np.ndarray, c0: np.ndarray, draws: np.ndarray, n_joints: int
                    ) -> np.ndarray:
    """Peaks (S, n_joints, 7) of ``c0 + Z d`` over the positions for the samples ``draws``."""
    out = np.empty((draws.shape[0], n_joints, 7))
    _tolerance_peaks(np.ascontiguousarray(z), np.ascontiguousarray(c0),
                     np.ascontiguousarray(draws), n_joints, out)
    return out
