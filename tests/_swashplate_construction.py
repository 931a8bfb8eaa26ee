"""A second independent reference for the swash-plate drive (paper 003), written without linkwork's
formulas: 3-D points by rotation matrices, the rod-length constraint solved numerically,
extremes by dense scans and bounded refinement, finite differences; and the designs of every
scheme the tests use."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar


def rot_z(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_x(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ref_points(phi, R, r, l, alpha, a=0.0, b=0.0, z1=0.0):
    """Slide point A and disk point B [m] at rotor angle phi (disk centre at height z1)."""
    B = np.array([a, b, z1]) + rot_x(alpha) @ rot_z(phi) @ np.array([0.0, -r, 0.0])
    Ah = rot_z(phi) @ np.array([0.0, -R, 0.0])
    dx, dy = Ah[0] - B[0], Ah[1] - B[1]
    horiz2 = dx * dx + dy * dy
    if horiz2 > l * l:
        raise ValueError("rod cannot reach")

    def f(z: float) -> float:
        return horiz2 + (z - B[2]) ** 2 - l * l

    z = brentq(f, B[2], B[2] + 1.01 * l, xtol=1e-16, rtol=1e-15, maxiter=200)
    return np.array([Ah[0], Ah[1], z]), B


@functools.lru_cache(maxsize=256)
def _ref_z0(*p):
    return ref_points(0.0, *p)[0][2]


def ref_s(phi, *p):
    """Slide position s(phi) = z_A(phi) - z_A(0) from the 3-D construction."""
    return ref_points(phi, *p)[0][2] - _ref_z0(*(float(x) for x in p))


def ref_delta(phi, *p):
    """Angle between the rod and the rotor axis from the 3-D rod vector."""
    A, B = ref_points(phi, *p)
    d = A - B
    return math.atan2(math.hypot(d[0], d[1]), d[2])


def fd1(f, x, h=1e-3):
    """Fourth-order central difference of f at x."""
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


def ref_extremes(p, n=1440):
    """(phi_min, s_min, phi_max, s_max): dense sampling, then bounded minimisation around every
    sampled local extreme."""
    ph = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    s = np.array([ref_s(x, *p) for x in ph])
    step = ph[1]
    out = []
    for sign in (1.0, -1.0):  # maxima of sign * s
        v = sign * s
        peaks = np.flatnonzero((v >= np.roll(v, 1)) & (v >= np.roll(v, -1)))
        best = (-np.inf, 0.0)
        for i in peaks:
            res = minimize_scalar(lambda x, sg=sign: -sg * ref_s(x, *p), method="bounded",
                                  bounds=(ph[i] - step, ph[i] + step),
                                  options={"xatol": 1e-10})
            val = -res.fun
            if val > best[0]:
                best = (val, res.x % (2 * math.pi))
        out.append(best)
    (vmax, xmax), (vmin, xmin) = out
    return xmin, -vmin, xmax, vmax


def ref_max_on(f, lo, hi, n=400):
    """Max of f over [lo, hi]: dense sampling, then bounded refinement around the best."""
    x = np.linspace(lo, hi, n)
    v = np.array([f(t) for t in x])
    i = int(np.argmax(v))
    best = v[i]
    step = x[1] - x[0]
    res = minimize_scalar(lambda t: -f(t), method="bounded",
                          bounds=(max(lo, x[i] - step), min(hi, x[i] + step)),
                          options={"xatol": 1e-11})
    return max(best, -res.fun)
