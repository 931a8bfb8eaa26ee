"""An independent model of a four-bar path generator in the literature's parametrisation, to
recompute what linkwork.synthesis reports: error, order, circuit (one branch, no toggle between
the points) and Grashof.

Written apart from linkwork.synthesis.path: the coupler angle comes from Norton's half-angle
form of the loop-closure equation (Design of Machinery, 5th ed., Eqs. (4.10)), the branch from
the side of the line A -> O4 on which B lies, both roots computed and the right one picked.
"""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2 * math.pi


def coupler(theta2: np.ndarray, p: dict, branch: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coupler point (x, y) in the task frame and whether each angle assembles."""
    a, b, c, d = p["r2"], p["r3"], p["r4"], p["r1"]
    t = np.asarray(theta2, dtype=float)
    K1, K4 = d / a, d / b
    K5 = (c * c - d * d - a * a - b * b) / (2 * a * b)
    D = np.cos(t) - K1 + K4 * np.cos(t) + K5
    E = -2 * np.sin(t)
    F = K1 + (K4 - 1) * np.cos(t) + K5
    disc = E * E - 4 * D * F
    ok = disc >= 0
    root = np.sqrt(np.where(ok, disc, 0.0))
    xA, yA = a * np.cos(t), a * np.sin(t)
    best_x = np.full(t.shape, np.nan)
    best_y = np.full(t.shape, np.nan)
    for sgn in (1.0, -1.0):
        th3 = 2 * np.arctan2(-E + sgn * root, 2 * D)
        xB, yB = xA + b * np.cos(th3), yA + b * np.sin(th3)
        side = (d - xA) * (yB - yA) - (0 - yA) * (xB - xA)  # (O4 - A) x (B - A)
        pick = np.sign(side) == branch
        px = xA + p["rcx"] * np.cos(th3) - p["rcy"] * np.sin(th3)
        py = yA + p["rcx"] * np.sin(th3) + p["rcy"] * np.cos(th3)
        best_x = np.where(pick & np.isnan(best_x), px, best_x)
        best_y = np.where(pick & np.isnan(best_y), py, best_y)
    c0, s0 = math.cos(p["theta0"]), math.sin(p["theta0"])
    X = p["x0"] + c0 * best_x - s0 * best_y
    Y = p["y0"] + s0 * best_x + c0 * best_y
    return X, Y, ok & np.isfinite(X)


def error(p: dict, branch: int, points: np.ndarray) -> float:
    x, y, ok = coupler(np.asarray(p["theta2"]), p, branch)
    assert ok.all()
    return float(np.sum((x - points[:, 0]) ** 2 + (y - points[:, 1]) ** 2))


def crank_rocker(p: dict) -> bool:
    """Grashof (s + l < p + q) with the crank r2 the shortest link."""
    r = [p["r1"], p["r2"], p["r3"], p["r4"]]
    s = sorted(r)
    return s[0] + s[3] < s[1] + s[2] and p["r2"] == s[0]


def ordered(theta2: list[float]) -> tuple[bool, int]:
    """Whether the crank angles come in order in one direction within one turn; the
    direction (+1 counter-clockwise)."""
    t = np.asarray(theta2)
    for s in (1, -1):
        steps = np.mod(s * np.diff(t), TWO_PI)
        if steps.sum() <= TWO_PI + 1e-9:
            return True, s
    return False, 0


def one_circuit(p: dict, branch: int, closed: bool, n: int = 2000) -> bool:
    """Every crank angle between consecutive points (and back to the first for a closed
    path or a rotating crank) assembles on the branch: no toggle is passed."""
    ok, s = ordered(p["theta2"])
    if not ok:
        return False
    t = np.asarray(p["theta2"])
    steps = np.mod(s * np.diff(t), TWO_PI)
    total = TWO_PI if (closed or crank_rocker(p)) else steps.sum()
    dense = t[0] + s * np.linspace(0, total, n)
    _, _, good = coupler(dense, p, branch)
    return bool(good.all())
