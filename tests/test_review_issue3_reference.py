"""Review of issue 3: four-bar and planar kinetostatics against a reference written from scratch.

The reference uses only numpy/scipy, never linkwork's closed forms or engine:

* positions: the loop-closure equations solved numerically (``scipy.optimize.brentq`` on the
  output angle, both roots bracketed on a grid, the branch picked by the side of the line
  A -> O4 on which B lies);
* velocities and accelerations: the loop-closure equations differentiated once and twice by
  hand and solved per position (``numpy.linalg.solve``), checked in turn against central
  finite differences in time of the numerically solved positions for a crank motion
  ``theta2(t) = theta0 + w t + eps t^2 / 2``;
* inverse dynamics: Newton-Euler free-body equations of every moving link (force balance and
  moment balance about its centre of mass) assembled into one 9 x 9 system per position,
  with the unknowns in the documented sign conventions (``docs/fourbar.md``,
  ``docs/planar.md``): reaction of joint J(a, b) = force by a on b; driving torque = motor on
  the crank (driving force on the slider along the guide for a linear driver).

Mechanisms: four-bar designs (crank-rocker, double-crank, non-Grashof triple-rocker, a general
one), both branches, variable crank speed (``alpha2 != 0``), centres of mass off the link lines,
gravity in an oblique direction, a force at a coupler point, forces and couples on the other
links; a crank-slider driven by a linear driver on an inclined guide (prismatic joint with the
frame, the couple of the guide included); an inverted crank-slider (the prismatic joint between
two moving bodies, RPR group).  Tolerance: 1e-9 relative to the largest value of a quantity.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from linkwork.models.fourbar import (
    fourbar,
    fourbar_kinetostatics,
    limit_positions,
    paper004_planar,
    transmission_angle,
)
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PointForce,
    Prismatic,
    Revolute,
    bar,
    dead_centres,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar import fourbar as engine_fourbar

RTOL = 1e-9


@pytest.fixture(params=["groups", "global"])
def solver_path(request, monkeypatch):
    """The engine's two reaction solvers: group by group (dyads), and the full transposed
    constraint Jacobian that it uses whenever a mechanism has a Newton-solved group."""
    if request.param == "global":
        from linkwork.planar import dynamics

        monkeypatch.setattr(dynamics, "_group_reactions", lambda mech, st, f: dynamics.
                            _global_reactions(mech, st, f, np.ones(st.n, dtype=bool)))
    return request.param

# ---------------------------------------------------------------------------------------------
# reference helpers (numpy / scipy only)
# ---------------------------------------------------------------------------------------------


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


# ---------------------------------------------------------------------------------------------
# 1. four-bar kinematics
# ---------------------------------------------------------------------------------------------

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


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_fourbar_kinematics_against_root_finding_and_differentiated_loop(name, branch):
    design = DESIGNS[name]
    a, b, c, d = design
    t2, th3, th4 = _assembled(design, branch)
    w2, e2 = _speeds(t2)
    w3, w4, al3, al4 = fourbar_rates(t2, th3, th4, a, b, c, w2, e2)
    r = fourbar(t2, a, b, c, d, w2, e2, branch)
    close(wrap(r.theta3 - th3), 0.0, 1.0)
    close(wrap(r.theta4 - th4), 0.0, 1.0)
    B = np.array([d, 0.0])[:, None] + c * e(th4)
    close(r.xB, B[0], a + b + c + d)
    close(r.yB, B[1], a + b + c + d)
    close(r.omega3, w3)
    close(r.omega4, w4)
    close(r.alpha3, al3)
    close(r.alpha4, al4)
    # a coupler point off the line
    p, q = 0.13, -0.06
    x, y, vx, vy, ax, ay = r.point("coupler", p, q)
    A, vA, aA = a * e(t2), a * w2 * ep(t2), a * (e2 * ep(t2) - w2**2 * e(t2))
    P, vP, aP = body_point(A, vA, aA, th3, w3, al3, (p, q))
    for got, want in ((x, P[0]), (y, P[1]), (vx, vP[0]), (vy, vP[1]), (ax, aP[0]),
                      (ay, aP[1])):
        close(got, want)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "non-Grashof"])
def test_reference_rates_equal_finite_differences_in_time(name, branch):
    """The hand-differentiated loop (the reference) against central differences in time of
    positions solved by root finding, theta2(t) = theta0 + w t + eps t^2 / 2."""
    design = DESIGNS[name]
    a, b, c, _d = design
    t2, _th3, _th4 = _assembled(design, branch)
    w, eps, h = 6.0, -40.0, 1e-4
    checked = 0
    for t0 in t2[:: max(1, len(t2) // 6)]:
        ts = np.arange(-3, 4) * h
        th2 = t0 + w * ts + eps * ts**2 / 2
        p3, p4 = fourbar_positions(th2, *design, branch)
        if not np.all(np.isfinite(p3)):
            continue
        p3, p4 = np.unwrap(p3), np.unwrap(p4)
        c1 = np.array([-1, 9, -45, 0, 45, -9, 1]) / (60 * h)
        c2 = np.array([2, -27, 270, -490, 270, -27, 2]) / (180 * h * h)
        w3, w4, al3, al4 = fourbar_rates(np.array([t0]), p3[3:4], p4[3:4], a, b, c, w, eps)
        np.testing.assert_allclose([c1 @ p3, c1 @ p4], [w3[0], w4[0]], rtol=1e-7, atol=1e-7 * w)
        np.testing.assert_allclose([c2 @ p3, c2 @ p4], [al3[0], al4[0]], rtol=1e-4,
                                   atol=1e-4 * w * w)
        checked += 1
    assert checked >= 5


def _omega4(t, design, branch):
    th3, th4 = fourbar_positions(np.array([t]), *design, branch)
    return fourbar_rates(np.array([t]), th3, th4, *design[:3], 1.0, 0.0)[1][0]


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "general", "non-Grashof"])
def test_limit_positions_and_transmission_angle_against_the_reference(name, branch):
    """Rocker limits = zeros of the reference's omega4(theta2); input toggles = ends of the
    assembled range; mu = angle ABO4 of the solved positions."""
    design = DESIGNS[name]
    a, b, c, d = design
    lim = limit_positions(*design, branch=branch)
    t2 = np.linspace(-np.pi, np.pi, 721)
    th3, th4 = fourbar_positions(t2, *design, branch)
    ok = np.isfinite(th3)
    # rocker limits: omega4 changes sign between assembled neighbours
    zeros = []
    for k in np.nonzero(ok[:-1] & ok[1:])[0]:
        w_lo, w_hi = _omega4(t2[k], design, branch), _omega4(t2[k + 1], design, branch)
        if w_lo * w_hi < 0:
            zeros.append(brentq(_omega4, t2[k], t2[k + 1], args=(design, branch), xtol=1e-14))
    got = [t for t in (lim.theta2_rocker_extended, lim.theta2_rocker_folded) if np.isfinite(t)]
    assert len(zeros) == len(got) >= 1
    for t in got:
        assert np.min(np.abs(wrap(np.array(zeros) - t))) < 1e-10
    for t2l, t4l in ((lim.theta2_rocker_extended, lim.theta4_rocker_extended),
                     (lim.theta2_rocker_folded, lim.theta4_rocker_folded)):
        if np.isfinite(t2l):
            assert abs(wrap(fourbar_positions(np.array([t2l]), *design, branch)[1][0] - t4l)
                       ) < 1e-9
    # input toggles: the crank's assembled range ends there (or the crank turns fully)
    if ok.all():
        assert np.isnan(lim.theta2_toggle_extended) or np.isnan(lim.theta2_toggle_folded)
    else:
        ends = t2[np.nonzero(ok[:-1] != ok[1:])[0]]
        toggles = [t for t in (lim.theta2_toggle_extended, lim.theta2_toggle_folded)
                   if np.isfinite(t)]
        for t in ends:
            assert min(abs(abs(t) - tt) for tt in toggles) < 2 * np.pi / 720
    # transmission angle: angle ABO4 of the solved positions
    A = a * e(t2[ok])
    B = np.array([d, 0.0])[:, None] + c * e(th4[ok])
    ba, bo = A - B, np.array([d, 0.0])[:, None] - B
    mu = np.arccos(np.sum(ba * bo, 0) / (b * c))
    close(transmission_angle(t2[ok], *design), mu, 1.0)
    close(fourbar(t2[ok], *design, 1.0, 0.0, branch).transmission_angle, mu, 1.0)


# ---------------------------------------------------------------------------------------------
# 2. four-bar inverse dynamics: Newton-Euler by hand
# ---------------------------------------------------------------------------------------------

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


def _fourbar_engine(design, branch, ref):
    mech = engine_fourbar(*design, masses=MASS, inertias=INERTIA, coms=COM, branch=branch)
    kin = kinematics(mech, ref["t2"], omega1=ref["w2"], eps1=ref["e2"])
    loads = [PointForce("crank", P_CRANK, *F_CRANK), PointForce("coupler", P_COUPLER, *F_COUPLER),
             PointForce("rocker", P_ROCKER, *F_ROCKER)]
    loads += [BodyTorque(nm, m) for nm, m in zip(("crank", "coupler", "rocker"), M_EXT,
                                                  strict=True)]
    return inverse_dynamics(kin, gravity=GRAV, loads=loads, about=ABOUT)


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


def _loads_power_and_moment(ref, about):
    """Power of the applied loads and their moment about ``about`` (gravity included)."""
    g = np.array(GRAV)[:, None]
    ext_f, ext_m = ref["loads"]["force"], ref["loads"]["moment"]
    pw = np.zeros_like(ref["T"])
    mo = np.zeros_like(ref["T"])
    fsum = np.zeros((2, len(pw)))
    ab = np.asarray(about, float)[:, None]
    for i in range(3):
        fe = np.array(ext_f[i])[:, None]
        pw += (MASS[i] * g * ref["vG"][i]).sum(0) + (fe * ref["vP"][i]).sum(0) \
            + ext_m[i] * ref["om"][i]
        mo += cross(ref["G"][i] - ab, MASS[i] * g) + cross(ref["P"][i] - ab, fe) + ext_m[i]
        fsum += MASS[i] * g + fe
    return pw, mo, fsum


def check_reactions(pairs, q, x):
    """Four pin reactions (fx, fy) and the driving torque against the reference's unknowns
    ``x`` (F12, F23, F34, F14, T); returns the force scale used."""
    scale = np.max(np.abs(x[:8]))
    for k, (fx, fy) in enumerate(pairs):
        close(fx, x[2 * k], scale)
        close(fy, x[2 * k + 1], scale)
    close(q, x[8])
    return scale


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_fourbar_kinetostatics_against_newton_euler(name, branch):
    design = DESIGNS[name]
    ref = fourbar_reference(design, branch)
    f = _fourbar_closed(design, branch, ref)
    scale = check_reactions(((f.R_Ox, f.R_Oy), (f.R_Ax, f.R_Ay), (f.R_Bx, f.R_By),
                             (f.R_Cx, f.R_Cy)), f.Q, ref["x"])
    sf, sm_o2 = _shaking_ref(ref, (0.0, 0.0))
    close(f.shaking_force_x, sf[0], scale)
    close(f.shaking_force_y, sf[1], scale)
    close(f.shaking_moment, sm_o2)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_engine_fourbar_dynamics_against_newton_euler(name, branch, solver_path):
    design = DESIGNS[name]
    ref = fourbar_reference(design, branch)
    dyn = _fourbar_engine(design, branch, ref)
    scale = check_reactions([dyn.reaction(j) for j in ("O2", "A", "B", "O4")], dyn.Q, ref["x"])
    sf, sm = _shaking_ref(ref, ABOUT)
    close(dyn.shaking_fx, sf[0], scale)
    close(dyn.shaking_fy, sf[1], scale)
    close(dyn.shaking_m, sm)
    close(dyn.T, ref["T"])
    assert dyn.about == ABOUT


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_fourbar_power_and_momentum_balances_of_linkwork_results(name, branch):
    """Q omega2 + P_loads = dT/dt; d(sum m v)/dt = loads - shaking; dH/dt = M(loads) - M_sh,
    with linkwork's Q and shaking loads and the reference's motion."""
    design = DESIGNS[name]
    ref = fourbar_reference(design, branch)
    pw, mo, fsum = _loads_power_and_moment(ref, ABOUT)
    dH = sum(cross(ref["G"][i] - np.array(ABOUT)[:, None], MASS[i] * ref["aG"][i])
             + INERTIA[i] * ref["al"][i] for i in range(3))
    dP = sum(MASS[i] * ref["aG"][i] for i in range(3))
    dyn = _fourbar_engine(design, branch, ref)
    f = _fourbar_closed(design, branch, ref)
    pscale = np.max(np.abs(ref["dT"])) + np.max(np.abs(pw))
    for q in (dyn.Q, f.Q):
        close(q * ref["w2"] + pw, ref["dT"], pscale)
    close(fsum - np.array([dyn.shaking_fx, dyn.shaking_fy]), dP, np.max(np.abs(fsum)))
    close(mo - dyn.shaking_m, dH, np.max(np.abs(mo)))
    # the closed form's shaking moment is about O2
    _pw0, mo0, _ = _loads_power_and_moment(ref, (0.0, 0.0))
    dH0 = sum(cross(ref["G"][i], MASS[i] * ref["aG"][i]) + INERTIA[i] * ref["al"][i]
              for i in range(3))
    close(mo0 - f.shaking_moment, dH0, np.max(np.abs(mo0)))


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "general"])
def test_paper004_corrected_equations_against_newton_euler(name, branch):
    """Paper 004's Eqs. (8)-(13) as corrected (printed=False), centres of mass and forces at
    the link midpoints: F_i = m_i (g - a_Si) + F_ext, M_i = M_ext - J_i eps_i."""
    design = DESIGNS[name]
    mids = tuple((length / 2, 0.0) for length in design[:3])
    loads = {"force": LOADS["force"], "point": mids, "moment": M_EXT}
    ref = fourbar_reference(design, branch, loads=loads, coms=mids)
    g = np.array(GRAV)[:, None]
    F = [MASS[i] * (g - ref["aG"][i]) + np.array(LOADS["force"][i])[:, None] for i in range(3)]
    Mz = [M_EXT[i] - INERTIA[i] * ref["al"][i] for i in range(3)]
    th3, th4 = fourbar_positions(ref["t2"], *design, branch)
    r = paper004_planar(ref["t2"], th3, th4 + np.pi, *design[:3], tuple(F[0]), tuple(F[1]),
                        tuple(F[2]), *Mz, printed=False)
    check_reactions(((r.R_0x, r.R_0y), (r.R_Ax, r.R_Ay), (r.R_Bx, r.R_By), (r.R_Cx, r.R_Cy)),
                    r.Q, ref["x"])


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_assembly_and_dead_centres_against_the_reference(name, branch):
    """Where the four-bar assembles (closed form and engine, on_fail="nan") and the engine's
    dead centres (rocker reversals) against root finding."""
    design = DESIGNS[name]
    t2 = np.linspace(0.0, 2 * np.pi, 361) + 0.001
    ok = np.isfinite(fourbar_positions(t2, *design, branch)[0])
    r = fourbar(t2, *design, 1.0, 0.0, branch, on_fail="nan")
    kin = kinematics(engine_fourbar(*design, branch=branch), t2, on_fail="nan")
    np.testing.assert_array_equal(r.assembled, ok)
    np.testing.assert_array_equal(kin.assembled, ok)
    assert np.all(np.isnan(r.theta4[~ok])) and np.all(np.isfinite(r.theta4[ok]))
    if not ok.all():
        return
    zeros = [brentq(_omega4, t2[k], t2[k + 1], args=(design, branch), xtol=1e-14)
             for k in range(len(t2) - 1)
             if _omega4(t2[k], design, branch) * _omega4(t2[k + 1], design, branch) < 0]
    got = sorted(dc.phi1 for dc in dead_centres(kin) if dc.body == "rocker")
    assert len(got) == len(zeros) == (0 if name == "double-crank" else 2)
    if zeros:
        close(wrap(np.array(got) - np.array(zeros)), 0.0, 1.0)


# ---------------------------------------------------------------------------------------------
# 3. prismatic joints: crank-slider with a linear driver, inverted crank-slider (RPR)
# ---------------------------------------------------------------------------------------------

R_CS, L_CS = 0.08, 0.25
BETA = np.radians(20.0)                       # guide direction
G0 = np.array([0.03, -0.05])                  # a point of the guide line
U = e(BETA)
NRM = ep(BETA)
CS_MASS = (0.9, 2.2, 4.0)                     # crank, rod, slider
CS_INERTIA = (0.002, 0.014, 0.006)
CS_COM = ((0.035, 0.012), (0.1, -0.02), (0.015, 0.03))
CS_F = ((0.0, 0.0), (12.0, -7.0), (-300.0, 55.0))
CS_P = ((0.0, 0.0), (0.2, 0.03), (0.02, -0.01))
CS_M = (-4.0, 0.8, 1.1)
CS_GRAV = (-3.0, -9.0)


def slider_reference(branch, s, v1, a1):
    """Crank-slider driven at the slider along the guide; Newton-Euler by hand."""
    n = len(s)
    Bp = G0[:, None] + U[:, None] * s
    vB, aB = U[:, None] * v1, U[:, None] * a1
    tc = np.full(n, np.nan)
    for k in range(n):
        roots = circle_roots(np.zeros(2), R_CS, Bp[:, k], L_CS)
        assert roots is not None
        for phi in roots:  # the crank pin A on the left of O -> B for branch +1
            if branch * cross(Bp[:, k], R_CS * e(phi)) > 0:
                tc[k] = phi
    A = R_CS * e(tc)
    tr = np.arctan2(Bp[1] - A[1], Bp[0] - A[0])
    out = np.empty((4, n))
    for k in range(n):
        J = np.column_stack([R_CS * ep(tc[k]), L_CS * ep(tr[k])])
        w = np.linalg.solve(J, vB[:, k])
        al = np.linalg.solve(J, aB[:, k] + R_CS * e(tc[k]) * w[0] ** 2
                             + L_CS * e(tr[k]) * w[1] ** 2)
        out[:, k] = (w[0], w[1], al[0], al[1])
    wc, wr, ac, ar = out
    z = np.zeros((2, n))
    vA, aA = R_CS * wc * ep(tc), R_CS * (ac * ep(tc) - wc**2 * e(tc))
    links = [(z, z, z, tc, wc, ac), (A, vA, aA, tr, wr, ar),
             (Bp, vB, aB, np.full(n, BETA), np.zeros(n), np.zeros(n))]
    G, vG, aG, P, _ = link_points(links, CS_COM, CS_P)
    # unknowns: F_O (frame on crank), F_A (crank on rod), F_B (rod on slider),
    # N (frame on slider along the guide normal, at B), Mz (frame couple on slider),
    # Qd (driving force on the slider along U, at B)
    def unknowns(k):
        return (pin(0, 0, None, np.zeros(2)) + pin(2, 1, 0, A[:, k]) + pin(4, 2, 1, Bp[:, k])
                + [(2, 6, NRM, Bp[:, k]), (2, 7, 1.0, None), (2, 8, U, Bp[:, k])])

    alphas = [lk[5] for lk in links]
    x = newton_euler(G, aG, alphas, P, CS_MASS, CS_INERTIA, CS_GRAV, CS_F, CS_M, unknowns)
    T = sum(0.5 * CS_MASS[i] * (vG[i] ** 2).sum(0) + 0.5 * CS_INERTIA[i] * links[i][4] ** 2
            for i in range(3))
    return dict(x=x, T=T, Bp=Bp, tc=tc, tr=tr, wc=wc, wr=wr, ac=ac, ar=ar)


def slider_engine(branch, s, v1, a1):
    frame = Body("frame", {"O": (0.0, 0.0), "G": tuple(G0)})
    crank = bar("crank", "O", "A", R_CS, mass=CS_MASS[0], inertia=CS_INERTIA[0], com=CS_COM[0])
    rod = bar("rod", "A", "B", L_CS, mass=CS_MASS[1], inertia=CS_INERTIA[1], com=CS_COM[1])
    slider = Body("slider", {"B": (0.0, 0.0)}, mass=CS_MASS[2], com=CS_COM[2],
                  inertia=CS_INERTIA[2])
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("B", "rod", "slider"),
              Prismatic("G", "frame", "slider", angle=BETA, through="G", point="B",
                        rel_angle=BETA))
    mech = Mechanism(frame, (crank, rod, slider), joints, Linear("G"), {"A": branch})
    kin = kinematics(mech, s, omega1=v1, eps1=a1)
    loads = [PointForce(nm, CS_P[i], *CS_F[i]) for i, nm in enumerate(("crank", "rod", "slider"))]
    loads += [BodyTorque(nm, CS_M[i]) for i, nm in enumerate(("crank", "rod", "slider"))]
    return kin, inverse_dynamics(kin, gravity=CS_GRAV, loads=loads, about=ABOUT)


@pytest.mark.parametrize("branch", [+1, -1])
def test_linear_driver_crank_slider_against_newton_euler(branch, solver_path):
    # slide positions where |O B| stays inside [l - r, l + r] = [0.17, 0.33] m
    s = np.linspace(0.16, 0.31, 31)
    v1 = 0.6 + 0.5 * s
    a1 = -2.0 + 4.0 * s
    ref = slider_reference(branch, s, v1, a1)
    kin, dyn = slider_engine(branch, s, v1, a1)
    close(wrap(kin.angle("crank") - ref["tc"]), 0.0, 1.0)
    close(wrap(kin.angle("rod") - ref["tr"]), 0.0, 1.0)
    for body, w, al in (("crank", "wc", "ac"), ("rod", "wr", "ar")):
        i = kin.bodies.index(body)
        close(kin.omega[i], ref[w])
        close(kin.eps[i], ref[al])
    x = ref["x"]
    scale = np.max(np.abs(x[:8]))
    for k, joint in enumerate(("O", "A", "B")):
        fx, fy = dyn.reaction(joint)
        close(fx, x[2 * k], scale)
        close(fy, x[2 * k + 1], scale)
    fx, fy = dyn.reaction("G")
    close(fx, x[6] * NRM[0], scale)
    close(fy, x[6] * NRM[1], scale)
    mz = dyn.mz[dyn.joints.index("G")]
    close(mz, x[7])
    close(dyn.Q, x[8])
    # forces on the frame: -F_O at O, -(N n + Qd u) at B and the couple -Mz
    fo = x[0:2]
    fg = x[6] * NRM[:, None] + x[8] * U[:, None]
    ab = np.array(ABOUT)[:, None]
    close(dyn.shaking_fx, -(fo + fg)[0], scale)
    close(dyn.shaking_fy, -(fo + fg)[1], scale)
    close(dyn.shaking_m, cross(-ab, -fo) + cross(ref["Bp"] - ab, -fg) - x[7])
    close(dyn.T, ref["T"])


IC_A, IC_D = 0.12, 0.3            # crank O2A, frame O2O4
IC_MASS = (0.8, 0.5, 2.5)         # crank, block, guide (rocker)
IC_INERTIA = (0.0015, 0.0004, 0.04)
IC_COM = ((0.05, 0.01), (0.01, -0.015), (0.2, 0.03))
IC_F = ((0.0, 0.0), (5.0, 3.0), (-20.0, 14.0))
IC_P = ((0.0, 0.0), (0.0, 0.02), (0.3, -0.02))
IC_M = (0.0, -0.6, 2.2)
IC_GRAV = (1.5, -9.7)


def inverted_reference(t2, w2, e2):
    """Crank O2A, block pinned at A sliding on a guide (rocker) turning about O4."""
    n = len(t2)
    O4 = np.array([IC_D, 0.0])
    A = IC_A * e(t2)
    r = A - O4[:, None]
    s = np.hypot(r[0], r[1])
    tg = np.arctan2(r[1], r[0])           # guide direction from O4 towards A (branch +1)
    out = np.empty((4, n))
    for k in range(n):
        J = np.column_stack([e(tg[k]), s[k] * ep(tg[k])])       # unknowns sdot, omega_g
        sd, wg = np.linalg.solve(J, IC_A * ep(t2[k]) * w2[k])
        rhs = (IC_A * (ep(t2[k]) * e2[k] - e(t2[k]) * w2[k] ** 2)
               - 2 * sd * wg * ep(tg[k]) + s[k] * wg**2 * e(tg[k]))
        sdd, ag = np.linalg.solve(J, rhs)
        out[:, k] = (sd, wg, sdd, ag)
    _sd, wg, _sdd, ag = out
    z = np.zeros((2, n))
    vA, aA = IC_A * w2 * ep(t2), IC_A * (e2 * ep(t2) - w2**2 * e(t2))
    links = [(z, z, z, t2, w2, e2), (A, vA, aA, tg, wg, ag),
             (O4[:, None] + z, z, z, tg, wg, ag)]
    G, vG, aG, P, _ = link_points(links, IC_COM, IC_P)
    # unknowns: F_O2 (frame on crank), F_A (crank on block), N (guide on block along the
    # guide normal, at A), Mz (guide couple on block), F_O4 (frame on guide), T (motor)
    def unknowns(k):
        nrm = ep(tg[k])
        return (pin(0, 0, None, np.zeros(2)) + pin(2, 1, 0, A[:, k]) + pin(6, 2, None, O4)
                + [(1, 4, nrm, A[:, k]), (2, 4, -nrm, A[:, k]), (1, 5, 1.0, None),
                   (2, 5, -1.0, None), (0, 8, 1.0, None)])

    alphas = [lk[5] for lk in links]
    x = newton_euler(G, aG, alphas, P, IC_MASS, IC_INERTIA, IC_GRAV, IC_F, IC_M, unknowns)
    om = (w2, wg, wg)
    T = sum(0.5 * IC_MASS[i] * (vG[i] ** 2).sum(0) + 0.5 * IC_INERTIA[i] * om[i] ** 2
            for i in range(3))
    return dict(x=x, T=T, tg=tg, wg=wg, ag=ag, A=A)


def test_inverted_crank_slider_prismatic_between_moving_bodies_against_newton_euler(
        solver_path):
    t2 = np.linspace(0.0, 2 * np.pi, 37)[:-1] + 0.05
    w2, e2 = 9.0 - 2.0 * np.cos(t2), 30.0 + 5.0 * np.sin(t2)
    ref = inverted_reference(t2, w2, e2)
    frame = Body("frame", {"O2": (0.0, 0.0), "O4": (IC_D, 0.0)})
    crank = bar("crank", "O2", "A", IC_A, mass=IC_MASS[0], inertia=IC_INERTIA[0],
                com=IC_COM[0])
    block = Body("block", {"A": (0.0, 0.0)}, mass=IC_MASS[1], com=IC_COM[1],
                 inertia=IC_INERTIA[1])
    guide = Body("guide", {"O4": (0.0, 0.0)}, mass=IC_MASS[2], com=IC_COM[2],
                 inertia=IC_INERTIA[2])
    joints = (Revolute("O2", "frame", "crank"), Revolute("A", "crank", "block"),
              Prismatic("P", "guide", "block", angle=0.0, through="O4", point="A"),
              Revolute("O4", "frame", "guide"))
    mech = Mechanism(frame, (crank, block, guide), joints, Crank("O2"), {"P": +1})
    kin = kinematics(mech, t2, omega1=w2, eps1=e2)
    names = ("crank", "block", "guide")
    loads = [PointForce(nm, IC_P[i], *IC_F[i]) for i, nm in enumerate(names)]
    loads += [BodyTorque(nm, IC_M[i]) for i, nm in enumerate(names)]
    dyn = inverse_dynamics(kin, gravity=IC_GRAV, loads=loads, about=ABOUT)
    i = kin.bodies.index("guide")
    close(wrap(kin.theta[i] - ref["tg"]), 0.0, 1.0)
    close(kin.omega[i], ref["wg"])
    close(kin.eps[i], ref["ag"])
    x = ref["x"]
    scale = np.max(np.abs(x[[0, 1, 2, 3, 4, 6, 7]]))
    for joint, k in (("O2", 0), ("A", 2), ("O4", 6)):
        fx, fy = dyn.reaction(joint)
        close(fx, x[k], scale)
        close(fy, x[k + 1], scale)
    fx, fy = dyn.reaction("P")
    nrm = ep(ref["tg"])
    close(fx, x[4] * nrm[0], scale)
    close(fy, x[4] * nrm[1], scale)
    close(dyn.mz[dyn.joints.index("P")], x[5])
    close(dyn.Q, x[8])
    ab = np.array(ABOUT)[:, None]
    f12, f14 = x[0:2], x[6:8]
    close(dyn.shaking_fx, -(f12 + f14)[0], scale)
    close(dyn.shaking_fy, -(f12 + f14)[1], scale)
    o4 = np.array([IC_D, 0.0])[:, None]
    close(dyn.shaking_m, cross(-ab, -f12) + cross(o4 - ab, -f14) - x[8])
    close(dyn.T, ref["T"])


def planar_file(design, branch, rpm, eps):
    """The four-bar of the kinetostatic tests as a planar file, lengths in mm, loads in kN."""
    a, b, c, d = design
    lines = ['type = "planar"', "[frame]",
             f'points = {{ O2 = [0, 0], O4 = ["{1e3 * d} mm", 0] }}']
    for i, (name, start, end, length) in enumerate(
            (("crank", "O2", "A", a), ("coupler", "A", "B", b), ("rocker", "O4", "B", c))):
        lines += ["[[body]]", f'name = "{name}"', f'start = "{start}"', f'end = "{end}"',
                  f'length = "{1e3 * length} mm"', f'mass = "{MASS[i]} kg"',
                  f'inertia = "{INERTIA[i]} kg*m^2"',
                  f'com = ["{1e3 * COM[i][0]} mm", "{1e3 * COM[i][1]} mm"]']
    for name, ja, jb in (("O2", "frame", "crank"), ("A", "crank", "coupler"),
                         ("B", "coupler", "rocker"), ("O4", "frame", "rocker")):
        lines += ["[[joint]]", f'name = "{name}"', 'type = "revolute"', f'a = "{ja}"',
                  f'b = "{jb}"']
    lines += ["[driver]", 'joint = "O2"', f'omega1 = "{rpm} rpm"', f'eps1 = "{eps} rad/s^2"',
              "[analysis]", 'start = "0 deg"', 'stop = "360 deg"', "n = 25",
              f"branches = {{ B = {branch} }}",
              f'gravity = ["{GRAV[0]} m/s^2", "{GRAV[1]} m/s^2"]',
              f'about = ["{1e3 * ABOUT[0]} mm", "{1e3 * ABOUT[1]} mm"]',
              "[[load]]", 'type = "force"', 'body = "coupler"',
              f'point = ["{1e3 * P_COUPLER[0]} mm", "{1e3 * P_COUPLER[1]} mm"]',
              f'fx = "{1e-3 * F_COUPLER[0]} kN"', f'fy = "{1e-3 * F_COUPLER[1]} kN"',
              "[[load]]", 'type = "torque"', 'body = "rocker"', f'mz = "{M_EXT[2]} N*m"']
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("branch", [+1, -1])
def test_planar_file_and_cli_against_newton_euler(tmp_path, branch):
    """End to end: a file with units (mm, rpm, kN), oblique gravity, a force at a coupler
    point, a couple on the rocker and eps1 != 0, run by ``linkwork analyze``; the CSV columns
    against the reference."""
    import csv

    from linkwork.cli import main

    design = DESIGNS["general"]
    rpm, eps = 75.0, -18.0
    path = tmp_path / "fourbar.toml"
    path.write_text(planar_file(design, branch, rpm, eps))
    assert main(["analyze", str(path), "--out", str(tmp_path / "out")]) == 0
    with (tmp_path / "out" / "planar_dynamics.csv").open() as fh:
        rows = list(csv.reader(fh))
    cols = {h.split(" [")[0]: np.array([float(r[k]) for r in rows[1:]])
            for k, h in enumerate(rows[0])}
    t2 = np.linspace(0.0, 2 * np.pi, 25)
    close(cols["phi1"], t2, 1.0)
    # only the coupler force and the rocker couple act in the file
    loads = {"force": ((0.0, 0.0), F_COUPLER, (0.0, 0.0)), "point": LOADS["point"],
             "moment": (0.0, 0.0, M_EXT[2])}
    ref = fourbar_reference(design, branch, t2, (rpm * np.pi / 30, eps), loads)
    scale = check_reactions([(cols[f"R_{j}.x"], cols[f"R_{j}.y"]) for j in ("O2", "A", "B", "O4")],
                            cols["Q"], ref["x"])
    sf, sm = _shaking_ref(ref, ABOUT)
    close(cols["shaking_fx"], sf[0], scale)
    close(cols["shaking_fy"], sf[1], scale)
    close(cols["shaking_m"], sm)
    close(cols["T"], ref["T"])



def test_kinetostatics_load_array_of_the_wrong_length_is_named():
    """A per-position load whose length does not match the positions raised numpy's bare
    broadcast ValueError ('shape mismatch: objects cannot be broadcast ... arg 8'), naming
    neither the load nor the positions."""
    from linkwork.errors import ParameterError

    t2 = np.linspace(0.0, 2 * np.pi, 13)
    with pytest.raises(ParameterError, match=r"'positions': \(13,\), 'force\[1\]\[0\]': \(5,\)"):
        fourbar_kinetostatics(t2, *DESIGNS["crank-rocker"], 10.0, 0.0, 1,
                              force=((0, 0), (np.ones(5), 0.0), (0, 0)))
    with pytest.raises(ParameterError, match=r"'moment\[2\]': \(4,\)"):
        fourbar_kinetostatics(t2, *DESIGNS["crank-rocker"], 10.0, 0.0, 1,
                              moment=(0.0, 0.0, np.ones(4)))


# six-bar: the four-bar "general" with a rod from rocker point C to a slider D on an inclined
# guide (crank -> RRR dyad -> RRP dyad, reactions passed back through two groups)
SB_C = (0.11, 0.04)                          # C in the rocker's frame
SB_L = 0.32                                  # rod CD
SB_BETA = np.radians(-15.0)
SB_G = np.array([0.05, 0.2])                 # a point of the guide line
SB_MASS = (*MASS, 1.4, 2.8)                  # crank, coupler, rocker, rod, slider
SB_INERTIA = (*INERTIA, 0.006, 0.003)
SB_COM = (*COM, (0.09, 0.012), (0.01, -0.02))
SB_F = ((0.0, 0.0), F_COUPLER, (0.0, 0.0), (4.0, -6.0), (-150.0, 40.0))
SB_P = ((0.0, 0.0), P_COUPLER, (0.0, 0.0), (0.05, 0.01), (0.0, 0.01))
SB_M = (0.0, 0.0, M_EXT[2], -0.9, 0.4)


def sixbar_reference(branch_b, branch_d):
    design = DESIGNS["general"]
    ref = fourbar_reference(design, branch_b)
    t2, w2, e2 = ref["t2"], ref["w2"], ref["e2"]
    n = len(t2)
    th3, th4 = fourbar_positions(t2, *design, branch_b)
    w3, w4, al3, al4 = fourbar_rates(t2, th3, th4, *design[:3], w2, e2)
    z = np.zeros((2, n))
    O4 = ref["O4"]
    C, vC, aC = body_point(O4, z, z, th4, w4, al4, SB_C)
    u, nrm = e(SB_BETA), ep(SB_BETA)
    # D = G + s u with |D - C| = L: the larger root for branch +1
    h = SB_G[:, None] - C
    bq = 2 * (u @ h)
    cq = np.sum(h * h, 0) - SB_L**2
    s = (-bq + branch_d * np.sqrt(bq * bq - 4 * cq)) / 2
    D = SB_G[:, None] + u[:, None] * s
    th5 = np.arctan2(D[1] - C[1], D[0] - C[0])
    out = np.empty((4, n))
    for k in range(n):   # D - C = L e5, D = G + s u: [u, -L e5'] (sdot, w5) = vC
        J = np.column_stack([u, -SB_L * ep(th5[k])])
        sd, w5 = np.linalg.solve(J, vC[:, k])
        sdd, al5 = np.linalg.solve(J, aC[:, k] - SB_L * w5**2 * e(th5[k]))
        out[:, k] = (sd, w5, sdd, al5)
    sd, w5, sdd, al5 = out
    A, vA, aA = ref["A"], design[0] * w2 * ep(t2), design[0] * (e2 * ep(t2) - w2**2 * e(t2))
    links = [(z, z, z, t2, w2, e2), (A, vA, aA, th3, w3, al3), (O4, z, z, th4, w4, al4),
             (C, vC, aC, th5, w5, al5),
             (D, u[:, None] * sd, u[:, None] * sdd, np.full(n, SB_BETA), 0 * sd, 0 * sd)]
    G, vG, aG, P, _ = link_points(links, SB_COM, SB_P)
    B = ref["B"]

    # F12, F23, F34, F14 as in the four-bar; F45 (rocker on rod, C), F56 (rod on slider, D),
    # N (frame on slider along the guide normal, at D), Mz (frame couple on slider), T
    def unknowns(k):
        return (pin(0, 0, None, np.zeros(2)) + pin(2, 1, 0, A[:, k]) + pin(4, 2, 1, B[:, k])
                + pin(6, 2, None, O4[:, k]) + pin(8, 3, 2, C[:, k]) + pin(10, 4, 3, D[:, k])
                + [(4, 12, nrm, D[:, k]), (4, 13, 1.0, None), (0, 14, 1.0, None)])

    alphas = [lk[5] for lk in links]
    x = newton_euler(G, aG, alphas, P, SB_MASS, SB_INERTIA, GRAV, SB_F, SB_M, unknowns)
    T = sum(0.5 * SB_MASS[i] * (vG[i] ** 2).sum(0) + 0.5 * SB_INERTIA[i] * links[i][4] ** 2
            for i in range(5))
    return dict(t2=t2, w2=w2, e2=e2, x=x, T=T, s=s, sd=sd, sdd=sdd, th5=th5, w5=w5, al5=al5,
                O4=O4, D=D, nrm=nrm)


@pytest.mark.parametrize("branch_d", [+1, -1])
@pytest.mark.parametrize("branch_b", [+1, -1])
def test_sixbar_with_slider_against_newton_euler(branch_b, branch_d, solver_path):
    ref = sixbar_reference(branch_b, branch_d)
    a, b, c, d = DESIGNS["general"]
    frame = Body("frame", {"O2": (0.0, 0.0), "O4": (d, 0.0), "G": tuple(SB_G)})
    links = (("crank", "O2", "A", a, None), ("coupler", "A", "B", b, None),
             ("rocker", "O4", "B", c, {"C": SB_C}), ("rod", "C", "D", SB_L, None))
    bodies = [bar(nm, st, en, length, mass=SB_MASS[i], inertia=SB_INERTIA[i], com=SB_COM[i],
                  points=pts) for i, (nm, st, en, length, pts) in enumerate(links)]
    bodies.append(Body("slider", {"D": (0.0, 0.0)}, mass=SB_MASS[4], com=SB_COM[4],
                       inertia=SB_INERTIA[4]))
    joints = (Revolute("O2", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("O4", "frame", "rocker"),
              Revolute("C", "rocker", "rod"), Revolute("D", "rod", "slider"),
              Prismatic("G", "frame", "slider", angle=SB_BETA, through="G", point="D",
                        rel_angle=SB_BETA))
    mech = Mechanism(frame, tuple(bodies), joints, Crank("O2"), {"B": branch_b, "D": branch_d})
    kin = kinematics(mech, ref["t2"], omega1=ref["w2"], eps1=ref["e2"])
    names = [body.name for body in bodies]
    loads = [PointForce(nm, SB_P[i], *SB_F[i]) for i, nm in enumerate(names)]
    loads += [BodyTorque(nm, SB_M[i]) for i, nm in enumerate(names)]
    dyn = inverse_dynamics(kin, gravity=GRAV, loads=loads, about=ABOUT)
    s, sd, sdd = kin.slide("G")
    close(s, ref["s"])
    close(sd, ref["sd"])
    close(sdd, ref["sdd"])
    i = kin.bodies.index("rod")
    close(wrap(kin.theta[i] - ref["th5"]), 0.0, 1.0)
    close(kin.omega[i], ref["w5"])
    close(kin.eps[i], ref["al5"])
    x = ref["x"]
    scale = np.max(np.abs(x[:12]))
    for k, joint in enumerate(("O2", "A", "B", "O4", "C", "D")):
        fx, fy = dyn.reaction(joint)
        close(fx, x[2 * k], scale)
        close(fy, x[2 * k + 1], scale)
    fx, fy = dyn.reaction("G")
    close(fx, x[12] * ref["nrm"][0], scale)
    close(fy, x[12] * ref["nrm"][1], scale)
    close(dyn.mz[dyn.joints.index("G")], x[13])
    close(dyn.Q, x[14])
    ab = np.array(ABOUT)[:, None]
    f12, f14, fg = x[0:2], x[6:8], x[12] * ref["nrm"][:, None]
    close(dyn.shaking_fx, -(f12 + f14 + fg)[0], scale)
    close(dyn.shaking_fy, -(f12 + f14 + fg)[1], scale)
    close(dyn.shaking_m, cross(-ab, -f12) + cross(ref["O4"] - ab, -f14)
          + cross(ref["D"] - ab, -fg) - x[13] - x[14])
    close(dyn.T, ref["T"])
