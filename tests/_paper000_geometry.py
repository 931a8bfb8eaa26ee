"""Independent geometric constructions for paper 000, used only by the tests.

Nothing here uses linkwork's formulas: the crank pin is placed, the rod end or the slot is found
by a root solve of the bare constraint (scipy.optimize.brentq), and velocities/accelerations come
from central differences in *time* of the constructed positions, with the crank angle following
phi1(t) = phi1_0 + omega1 t + eps1 t^2 / 2.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

XTOL = 1e-15


def crank_slider_positions(phi1: float, L1: float, lambda2: float, lambda_e: float,
                           branch: int = 1) -> dict[str, float]:
    """Crank pin B, slider C on the guide x = e with |BC| = L2, rod angle by Eq. (1) geometry."""
    L2, e = lambda2 * L1, lambda_e * L1
    xb, yb = L1 * math.cos(phi1), L1 * math.sin(phi1)

    def gap(y: float) -> float:
        return math.hypot(e - xb, y - yb) - L2

    if branch == 1:
        y = brentq(gap, yb, yb + L2 + 1e-12, xtol=XTOL, rtol=4 * np.finfo(float).eps)
    else:
        y = brentq(gap, yb - L2 - 1e-12, yb, xtol=XTOL, rtol=4 * np.finfo(float).eps)
    phi2 = math.atan2(e - xb, y - yb)  # from +Y towards +X
    # acute angle between rod line and guide line (unit vectors dotted)
    mu = math.acos(min(1.0, abs(y - yb) / L2))
    return {"X_B": xb, "Y_B": yb, "X_C": e, "Y_C": y, "phi2": phi2, "mu": mu}


def slot_positions(phi1: float, L1: float, alpha: float) -> dict[str, float]:
    """Crank pin B, slider reference point P = (x_P, 0) whose slot line through P with direction
    (cos alpha, sin alpha) contains B.  Returns x_P and the pin's coordinate along the slot."""
    xb, yb = L1 * math.cos(phi1), L1 * math.sin(phi1)
    d = (math.cos(alpha), math.sin(alpha))

    def cross(xp: float) -> float:  # d x (B - P): zero when B lies on the slot line
        return d[0] * yb - d[1] * (xb - xp)

    span = 4 * L1 / math.sin(alpha) + 1.0
    xp = brentq(cross, -span, span, xtol=XTOL, rtol=4 * np.finfo(float).eps)
    along = (xb - xp) * d[0] + yb * d[1]
    return {"x_P": xp, "along": along, "X_B": xb, "Y_B": yb}


def time_derivatives(fun, phi0: float, omega1: float, eps1: float, dphi: float = 2e-3
                     ) -> tuple[float, float, float]:
    """Value, first and second time derivative of fun(phi1(t)) at t = 0 (central differences,
    Richardson-extrapolated; the time step turns the crank by about ``dphi``)."""
    h = dphi / max(abs(omega1), math.sqrt(abs(eps1)), 1e-9)

    def at(t: float) -> float:
        return fun(phi0 + omega1 * t + 0.5 * eps1 * t * t)

    def d1(hh: float) -> float:
        return (at(hh) - at(-hh)) / (2 * hh)

    def d2(hh: float) -> float:
        return (at(hh) - 2 * at(0.0) + at(-hh)) / (hh * hh)

    v = (4 * d1(h / 2) - d1(h)) / 3
    a = (4 * d2(h) - d2(2 * h)) / 3
    return at(0.0), v, a


def unwrap_pair(a: float, b: float) -> float:
    """b - a wrapped into (-pi, pi]."""
    return (b - a + math.pi) % (2 * math.pi) - math.pi


def _crank_phi(t: float, phi0: float, w1: float, e1: float) -> float:
    return phi0 + w1 * t + 0.5 * e1 * t * t


def _time_derivs(fun, t: float, h: float = 1e-4) -> tuple[float, float]:
    f = [fun(t + k * h) for k in (-2, -1, 0, 1, 2)]
    v = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)
    a = (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)
    return v, a
