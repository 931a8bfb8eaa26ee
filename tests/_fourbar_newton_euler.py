"""An independent four-bar reference written from scratch (numpy/scipy only, never linkwork's
closed forms or engine), shared by the four-bar and engine tests.

* positions: the loop-closure equations solved numerically (``scipy.optimize.brentq`` on the
  output angle, both roots bracketed on a grid, the branch picked by the side of the line
  A -> O4 on which B lies);
* velocities and accelerations: the loop-closure equations differentiated once and twice by
  hand and solved per position (``numpy.linalg.solve``), checked against central finite
  differences in time in ``tests/models/test_fourbar.py``;
* inverse dynamics: Newton-Euler free-body equations of every moving link (force balance and
  moment balance about its centre of mass) assembled into one 9 x 9 system per position,
  with the unknowns in the documented sign conventions (``docs/fourbar.md``,
  ``docs/planar.md``): reaction of joint J(a, b) = force by a on b; driving torque = motor on
  the crank.

Designs: crank-rocker, double-crank, non-Grashof triple-rocker, a general one; both branches,
variable crank speed, centres of mass off the link lines, oblique gravity, a force at a coupler
point, forces and couples on the other links.  Tolerance of the tests using it (``RTOL``): 1e-9
relative to the largest value of a quantity.  ``_fourbar_closed`` is the one adapter here
that calls linkwork (its closed-form kinetostatics, for the tests to compare).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from linkwork.models.fourbar import fourbar_kinetostatics

RTOL = 1e-9


def e(t):
    """Unit vector at angle t, shape (2, ...)."""
    return np.array([np.cos(t), np.sin(t)])


def ep(t):
    """Derivative of e(t): e turned 90 deg counter-clockwise."""
    return np.array([-np.sin(t), np.cos(t)])


def cross(r, f):
    return r[0] * f[1] - r[1] * f[0]


def rot(t, p):
    """Local point p = (p, q) of a body at angle t, in frame axes."""
    return np.array([np.cos(t) * p[0] - np.sin(t) * p[1], np.sin(t) * p[0] + np.cos(t) * p[1]])


def circle_roots(centre, radius, other, dist):
    """Angles phi with |centre + radius e(phi) - other| = dist: both roots (or None)."""
    def g(phi):
        p = radius * e(phi) + (centre - other).reshape((2,) + (1,) * np.ndim(phi))
        return p[0] * p[0] + p[1] * p[1] - dist * dist

    grid = np.linspace(-np.pi, np.pi, 4001)
    vals = g(grid)
    roots = [brentq(g, grid[k], grid[k + 1], xtol=1e-16, rtol=1e-15)
             for k in np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0)[0]]
    return roots if len(roots) == 2 else None


def fourbar_positions(t2, a, b, c, d, branch):
    """theta3, theta4 by root finding; NaN where the linkage does not assemble."""
    o4 = np.array([d, 0.0])
    th3 = np.full(len(t2), np.nan)
    th4 = np.full(len(t2), np.nan)
    for k, t in enumerate(t2):
        A = a * e(t)
        roots = circle_roots(o4, c, A, b)
        if roots is None:
            continue
        for phi in roots:
            B = o4 + c * e(phi)
            if branch * cross(o4 - A, B - A) > 0:      # B on the left of A -> O4 for +1
                th4[k] = phi
                th3[k] = np.arctan2(*(B - A)[::-1])
    return th3, th4


def fourbar_rates(t2, th3, th4, a, b, c, w2, e2):
    """Velocities and accelerations from the differentiated loop a e2 + b e3 - c e4 - d = 0."""
    n = len(t2)
    w2, e2 = np.broadcast_to(w2, (n,)), np.broadcast_to(e2, (n,))
    out = np.empty((4, n))
    for k in range(n):
        J = np.column_stack([b * ep(th3[k]), -c * ep(th4[k])])
        w = np.linalg.solve(J, -a * ep(t2[k]) * w2[k])
        rhs = (-a * ep(t2[k]) * e2[k] + a * e(t2[k]) * w2[k] ** 2 + b * e(th3[k]) * w[0] ** 2
               - c * e(th4[k]) * w[1] ** 2)
        al = np.linalg.solve(J, rhs)
        out[:, k] = (w[0], w[1], al[0], al[1])
    return out


def body_point(origin, v0, a0, theta, w, al, p):
    """Position, velocity, acceleration of local point p of a body (rigid-body formulas)."""
    r = rot(theta, p)
    jr = np.array([-r[1], r[0]])
    return origin + r, v0 + w * jr, a0 + al * jr - w * w * r


def wrap(x):
    return np.angle(np.exp(1j * np.asarray(x)))


def close(got, want, scale=None, rtol=RTOL):
    """|got - want| <= rtol * scale (default: the largest |want|); returns the relative error."""
    got, want = np.asarray(got, float), np.asarray(want, float)
    s = np.max(np.abs(want)) if scale is None else scale
    err = np.max(np.abs(got - want)) / s
    assert err <= rtol, f"relative deviation {err:.3g} > {rtol:g}"
    return err


def link_points(links, coms, points):
    """Centres of mass (position, velocity, acceleration) and load points (position,
    velocity) of links given as (origin, its velocity, its acceleration, angle, omega, alpha)."""
    out = {"G": [], "vG": [], "aG": [], "P": [], "vP": []}
    for link, com, pt in zip(links, coms, points, strict=True):
        for key, val in zip(("G", "vG", "aG"), body_point(*link, com), strict=True):
            out[key].append(val)
        p, vp, _ = body_point(*link, pt)
        out["P"].append(p)
        out["vP"].append(vp)
    return out["G"], out["vG"], out["aG"], out["P"], out["vP"]


def newton_euler(G, aG, alpha, P, masses, inertias, gravity, forces, moments, unknowns):
    """Solve the free-body equations of the moving bodies at every position.

    Per body i: ``sum F = m_i (a_Gi - g) - F_ext`` and, about its centre of mass G_i,
    ``sum M = J_i alpha_i - M_ext - (P_i - G_i) x F_ext``.  ``unknowns(k)`` lists, for position
    k, ``(body, column, vector, at)``: unknown ``column`` acts on ``body`` as ``vector`` times
    its value at point ``at``, or as a couple ``vector`` (a number) when ``at`` is None.
    Returns the 3 * (number of bodies) unknowns per position, shape (3 nb, n).
    """
    n = aG[0].shape[1]
    g = np.asarray(gravity, float)
    size = 3 * len(masses)
    x = np.empty((size, n))
    for k in range(n):
        M = np.zeros((size, size))
        for body, col, vec, at in unknowns(k):
            if at is None:
                M[3 * body + 2, col] += vec
            else:
                M[3 * body:3 * body + 2, col] += vec
                M[3 * body + 2, col] += cross(at - G[body][:, k], vec)
        rhs = np.zeros(size)
        for i in range(len(masses)):
            fe = np.asarray(forces[i], float)
            rhs[3 * i:3 * i + 2] = masses[i] * (aG[i][:, k] - g) - fe
            rhs[3 * i + 2] = (inertias[i] * alpha[i][k] - moments[i]
                              - cross(P[i][:, k] - G[i][:, k], fe))
        x[:, k] = np.linalg.solve(M, rhs)
    return x


def pin(col, on, off, at):
    """A pin force (columns col, col + 1) on body ``on`` at ``at``, its opposite on ``off``."""
    out = []
    for comp in range(2):
        ex = np.eye(2)[comp]
        out.append((on, col + comp, ex, at))
        if off is not None:
            out.append((off, col + comp, -ex, at))
    return out


DESIGNS = {
    "crank-rocker": (0.1, 0.3, 0.2, 0.3),
    "double-crank": (0.3, 0.2, 0.3, 0.1),
    "non-Grashof": (0.25, 0.2, 0.2, 0.3),
    "general": (0.07, 0.22, 0.15, 0.18),
}


T2 = np.linspace(-np.pi, np.pi, 73)[:-1] + 0.013


def _assembled(design, branch):
    t2 = T2
    th3, th4 = fourbar_positions(t2, *design, branch)
    ok = np.isfinite(th3)
    assert ok.sum() >= 20
    return t2[ok], th3[ok], th4[ok]


def _speeds(t2):
    """A per-position crank speed and acceleration (variable crank speed, eps1 != 0)."""
    return 7.0 + 3.0 * np.sin(t2), -25.0 + 10.0 * np.cos(2 * t2)


MASS = (1.2, 3.1, 2.3)


INERTIA = (0.004, 0.031, 0.011)


COM = ((0.03, 0.015), (0.11, -0.04), (0.09, 0.025))      # link frames, off the link lines


GRAV = (2.7, -9.3)                                          # oblique gravity


F_COUPLER, P_COUPLER = (-40.0, 25.0), (0.12, 0.05)        # force at a coupler point


F_ROCKER, P_ROCKER = (6.0, -11.0), (0.05, -0.03)


F_CRANK, P_CRANK = (3.0, 1.5), (0.02, -0.01)


M_EXT = (0.7, -1.3, 3.5)                                    # couples; 3.5 N m on the rocker


ABOUT = (0.05, -0.12)


LOADS = {"force": (F_CRANK, F_COUPLER, F_ROCKER), "point": (P_CRANK, P_COUPLER, P_ROCKER),
         "moment": M_EXT}


def fourbar_reference(design, branch, t2=None, speeds=None, loads=LOADS, coms=COM):
    """Kinematics and Newton-Euler reactions of the four-bar, all from scratch (default: the
    assembled positions of T2 with the variable crank speed of ``_speeds``)."""
    a, b, c, d = design
    if t2 is None:
        t2, th3, th4 = _assembled(design, branch)
    else:
        th3, th4 = fourbar_positions(t2, *design, branch)
    w2, e2 = (np.broadcast_to(np.asarray(v, float), t2.shape)
              for v in (_speeds(t2) if speeds is None else speeds))
    w3, w4, al3, al4 = fourbar_rates(t2, th3, th4, a, b, c, w2, e2)
    n = len(t2)
    z = np.zeros((2, n))
    O2, O4 = np.zeros((2, n)), np.array([d, 0.0])[:, None] + z
    A, vA, aA = a * e(t2), a * w2 * ep(t2), a * (e2 * ep(t2) - w2**2 * e(t2))
    B = O4 + c * e(th4)
    links = [  # origin, its velocity and acceleration, angle, omega, alpha
        (O2, z, z, t2, w2, e2), (A, vA, aA, th3, w3, al3), (O4, z, z, th4, w4, al4)]
    ext_f, ext_p, ext_m = loads["force"], loads["point"], loads["moment"]
    G, vG, aG, P, vP = link_points(links, coms, ext_p)
    # unknowns: F12 (frame on crank, O2), F23 (crank on coupler, A), F34 (coupler on rocker,
    # B), F14 (frame on rocker, O4), T (motor torque on the crank)
    def unknowns(k):
        return (pin(0, 0, None, O2[:, k]) + pin(2, 1, 0, A[:, k]) + pin(4, 2, 1, B[:, k])
                + pin(6, 2, None, O4[:, k]) + [(0, 8, 1.0, None)])

    alphas = (e2, al3, al4)
    x = newton_euler(G, aG, alphas, P, MASS, INERTIA, GRAV, ext_f, ext_m, unknowns)
    om, al = (w2, w3, w4), alphas
    T = sum(0.5 * MASS[i] * (vG[i] ** 2).sum(0) + 0.5 * INERTIA[i] * om[i] ** 2 for i in range(3))
    dT = sum(MASS[i] * (vG[i] * aG[i]).sum(0) + INERTIA[i] * om[i] * al[i] for i in range(3))
    return dict(t2=t2, w2=w2, e2=e2, x=x, T=T, dT=dT, G=G, vG=vG, aG=aG, P=P, vP=vP, om=om,
                al=al, O4=O4, A=A, B=B, d=d, loads=loads)


def _fourbar_closed(design, branch, ref):
    return fourbar_kinetostatics(
        ref["t2"], *design, ref["w2"], ref["e2"], branch, mass=MASS, inertia=INERTIA, com=COM,
        gravity=GRAV, force=(F_CRANK, F_COUPLER, F_ROCKER),
        force_point=(P_CRANK, P_COUPLER, P_ROCKER), moment=M_EXT)


def _shaking_ref(ref, about):
    """Force and moment (about ``about``) of the moving links on the frame, from the reactions."""
    f12, f14, T = ref["x"][0:2], ref["x"][6:8], ref["x"][8]
    o2 = -np.asarray(about, float)[:, None] + 0.0 * f12
    o4 = ref["O4"] - np.asarray(about, float)[:, None]
    return -(f12 + f14), cross(o2, -f12) + cross(o4, -f14) - T


def check_reactions(pairs, q, x):
    """Four pin reactions (fx, fy) and the driving torque against the reference's unknowns
    ``x`` (F12, F23, F34, F14, T); returns the force scale used."""
    scale = np.max(np.abs(x[:8]))
    for k, (fx, fy) in enumerate(pairs):
        close(fx, x[2 * k], scale)
        close(fy, x[2 * k + 1], scale)
    close(q, x[8])
    return scale
