"""An independent reference for the swash-plate drive: 3-D points by rotation matrices and the
rod-length constraint solved numerically (brentq), written without linkwork's formulas.

Frame: z0 = rotor axis (towards the slides), the disk axis tilted about x0 by alpha, rotor
angle phi counted from -y0 counter-clockwise seen from +z0 (paper 003); disk centre O1 at
(a, b) horizontally. Other test modules import ``ref_s``, ``ref_delta``, ``ref_stroke``.
"""

import math

import numpy as np
from scipy.optimize import brentq, minimize_scalar


def rot_z(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_x(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def disk_point(phi, R, r, l, alpha, a, b):
    """B: the disk turns by phi about its own axis, which is tilted by alpha about x0."""
    return np.array([a, b, 0.0]) + rot_x(alpha) @ rot_z(phi) @ np.array([0.0, -r, 0.0])


def slide_point(phi, R, z):
    return rot_z(phi) @ np.array([0.0, -R, 0.0]) + np.array([0.0, 0.0, z])


def ref_z(phi, R, r, l, alpha, a, b):
    """Axial coordinate of A solving |A - B| = l with A above B (brentq)."""
    B = disk_point(phi, R, r, l, alpha, a, b)

    def f(z):
        d = slide_point(phi, R, z) - B
        return float(d @ d) - l * l

    lo, hi = B[2], B[2] + l
    if f(lo) > 0:
        raise ValueError("rod cannot reach")
    return brentq(f, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=200)


def ref_s(phi, *p):
    return ref_z(phi, *p) - ref_z(0.0, *p)


def ref_delta(phi, *p):
    R = p[0]
    B = disk_point(phi, *p)
    A = slide_point(phi, R, ref_z(phi, *p))
    e = (A - B) / np.linalg.norm(A - B)
    return math.acos(min(1.0, e[2]))


def ref_stroke(*p, n=721):
    """Stroke from a dense scan of the reference plus bounded scalar refinement."""
    ph = np.linspace(0.0, 2 * math.pi, n)
    s = np.array([ref_s(x, *p) for x in ph])
    h = ph[1] - ph[0]
    out = []
    for sign in (1.0, -1.0):
        k = int(np.argmax(sign * s))
        res = minimize_scalar(lambda x, sg=sign: -sg * ref_s(x, *p), bounds=(ph[k] - h, ph[k] + h),
                              method="bounded", options={"xatol": 1e-12})
        out.append(max(sign * s[k], -res.fun) * sign)
    return out[0] - out[1], out
