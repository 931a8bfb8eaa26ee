"""Inverse dynamics of the planar engine (reactions, driving torque or force, shaking loads)
against Newton-Euler references written from scratch (numpy/scipy only), on both reaction
solvers (group by group, and the global transposed constraint Jacobian).  Tolerance: 1e-9
relative to the largest value of a quantity.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from _fourbar_newton_euler import (
    ABOUT,
    COM,
    DESIGNS,
    F_COUPLER,
    F_CRANK,
    F_ROCKER,
    GRAV,
    INERTIA,
    M_EXT,
    MASS,
    P_COUPLER,
    P_CRANK,
    P_ROCKER,
    _fourbar_closed,
    _shaking_ref,
    body_point,
    check_reactions,
    circle_roots,
    close,
    cross,
    e,
    ep,
    fourbar_positions,
    fourbar_rates,
    fourbar_reference,
    link_points,
    newton_euler,
    pin,
    wrap,
)
from _mechanisms import _angle, _rates, _rot, stephenson_sixbar
from _planar_newton_euler import DEV, PHI7, RTOL, _check_engine

import linkwork.planar as pl
from linkwork.errors import MissingExtraError, ParameterError
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    bar,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar import crank_slider_mechanism as engine_crank_slider
from linkwork.planar import fourbar_mechanism as engine_fourbar


@pytest.fixture(params=["groups", "global"])
def solver_path(request, monkeypatch):
    """The engine's two reaction solvers: group by group (dyads), and the full transposed
    constraint Jacobian that it uses whenever a mechanism has a Newton-solved group."""
    if request.param == "global":
        from linkwork.planar import dynamics

        monkeypatch.setattr(dynamics, "_group_reactions", lambda mech, st, f: dynamics.
                            _global_reactions(mech, st, f, np.ones(st.n, dtype=bool)))
    return request.param


def _fourbar_engine(design, branch, ref):
    mech = engine_fourbar(*design, masses=MASS, inertias=INERTIA, coms=COM, branch=branch)
    kin = kinematics(mech, ref["t2"], omega1=ref["w2"], eps1=ref["e2"])
    loads = [PointForce("crank", P_CRANK, *F_CRANK), PointForce("coupler", P_COUPLER, *F_COUPLER),
             PointForce("rocker", P_ROCKER, *F_ROCKER)]
    loads += [BodyTorque(nm, m) for nm, m in zip(("crank", "coupler", "rocker"), M_EXT,
                                                  strict=True)]
    return inverse_dynamics(kin, gravity=GRAV, loads=loads, about=ABOUT)


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


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_engine_fourbar_dynamics_against_newton_euler(name, branch, solver_path):
    """Reference: the from-scratch four-bar of tests/_fourbar_newton_euler.py (root finding,
    differentiated loop, Newton-Euler). Tolerance: check_reactions (RTOL = 1e-9 relative to
    the largest value), close (RTOL = 1e-9 relative to the largest value)."""
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
    """Reference: Newton-Euler equations written out in this module (slider_reference). Tolerance:
    close (RTOL = 1e-9 relative to the largest value)."""
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
    """Reference: Newton-Euler equations written out in this module (inverted_reference).
    Tolerance: close (RTOL = 1e-9 relative to the largest value)."""
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
    """Reference: Newton-Euler equations written out in this module (sixbar_reference). Tolerance:
    close (RTOL = 1e-9 relative to the largest value)."""
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


PHI = np.linspace(0.0, 2 * np.pi, 13)


# -- loads ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fourbar_kin():
    return kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0)), PHI)


def test_point_force_at_a_non_finite_local_point_is_named(fourbar_kin):
    """Was: Q all NaN, no error."""
    with pytest.raises(ParameterError, match=r"loads\[0\]\.point = \(nan, 0\.0\) .*must be finite"):
        inverse_dynamics(fourbar_kin, loads=[PointForce("rocker", (np.nan, 0.0), 1.0, 0.0)])
    with pytest.raises(ParameterError, match=r"loads\[0\]\.point = \(0, 0, 0\) .*pair of numbers"):
        inverse_dynamics(fourbar_kin, loads=[PointForce("rocker", (0, 0, 0), 1.0, 0.0)])


def test_loads_and_kinematics_of_the_wrong_type_are_named(fourbar_kin):
    one = PointForce("rocker", "B", 1.0, 0.0)
    for loads in (one, None):  # TypeError: not iterable
        with pytest.raises(ParameterError, match=r"^loads = .* must be a sequence"):
            inverse_dynamics(fourbar_kin, loads=loads)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"^loads\[0\] = x is invalid: must be PointForce,"):
        inverse_dynamics(fourbar_kin, loads=["x"])  # type: ignore[list-item]  # AttributeError
    with pytest.raises(ParameterError, match=r"^kin = .*must be the Kinematics result"):
        inverse_dynamics("kin")  # type: ignore[arg-type]
    # the correct call, for comparison: a couple on the rocker changes Q by mz * omega4 / omega1
    d0 = inverse_dynamics(fourbar_kin)
    d1 = inverse_dynamics(fourbar_kin, loads=[BodyTorque("rocker", 2.0)])
    np.testing.assert_allclose(d1.Q - d0.Q, -2.0 * fourbar_kin.omega[3] / fourbar_kin.omega1,
                               atol=1e-12)


def rpr_inverted_slider_crank():
    """Crank O2A 0.1 m, block on the crank pin sliding on a guide bar pivoted at O4; a force
    at the guide's tip T and a couple on the guide, both varying over the cycle."""

    O4 = np.array([0.05, -0.25])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": tuple(O4)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0),
         pl.Body("block", {"A": (0.0, 0.0)}, mass=0.5, inertia=1e-4),
         pl.bar("guide", "O4", "T", 0.6, mass=2.0)),
        (pl.Revolute("O2", "frame", "crank"), pl.Revolute("A", "crank", "block"),
         pl.Prismatic("P", "guide", "block", through="O4", point="A"),
         pl.Revolute("O4", "frame", "guide")), pl.Crank("O2"))

    def poses(p):
        A = 0.1 * np.array([np.cos(p), np.sin(p)])
        th = _angle(A - O4)
        return {"crank": (A / 2, p), "block": (A, th),
                "guide": (O4 + 0.3 * np.array([np.cos(th), np.sin(th)]), th)}

    def loads(ph):
        return [pl.PointForce("guide", "T", fx=10 * np.sin(ph), fy=-30.0),
                pl.BodyTorque("guide", mz=np.cos(ph))]
    return mech, poses, loads


def slot_drive():
    """Crank pin A in the slot of a rocker pivoted at O4 (RS group), rod T-E to a ram on a
    frame guide at 170 deg through (0, 0.4) with the ram's body turned by 0.3 rad; a press
    force on the ram over half the turn."""

    O4, G, gam = np.array([0.0, -0.3]), np.array([0.0, 0.4]), np.radians(170.0)
    u = np.array([np.cos(gam), np.sin(gam)])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": tuple(O4), "G": tuple(G)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0), pl.bar("rocker", "O4", "T", 0.6, mass=3.0),
         pl.bar("rod", "T", "E", 0.35, mass=1.0),
         pl.Body("ram", {"E": (0.0, 0.0)}, mass=4.0, com=(0.02, -0.01), inertia=0.02)),
        (pl.Revolute("O2", "frame", "crank"),
         pl.PinInSlot("S", "rocker", "crank", through="O4", point="A"),
         pl.Revolute("O4", "frame", "rocker"), pl.Revolute("T", "rocker", "rod"),
         pl.Revolute("E", "rod", "ram"),
         pl.Prismatic("G", "frame", "ram", angle=gam, through="G", point="E", rel_angle=0.3)),
        pl.Crank("O2"), {"S": 1, "E": 1})

    def poses(p):
        A = 0.1 * np.array([np.cos(p), np.sin(p)])
        th = _angle(A - O4)
        T = O4 + 0.6 * np.array([np.cos(th), np.sin(th)])
        b = (G - T) @ u
        s = -b + np.sqrt(b * b - ((G - T) @ (G - T) - 0.35**2))  # further along u
        E = G + s * u
        return {"crank": (A / 2, p), "rocker": ((O4 + T) / 2, th),
                "rod": ((T + E) / 2, _angle(E - T)),
                "ram": (E + _rot(0.3) @ np.array([0.02, -0.01]), 0.3)}

    def loads(ph):
        return [pl.PointForce("ram", "com", fx=np.where(np.sin(ph) > 0, -200.0, 0.0))]
    return mech, poses, loads


def _point_path(mech, poses, body, point):
    """World path phi -> position of a body point, from the written-out poses."""
    b = mech.body(body)
    local = np.array(b.point(point) if isinstance(point, str) else point) - np.array(b.com)

    def f(p):
        c, th = poses(p)[body]
        return c + _rot(th) @ local
    return f


@pytest.mark.parametrize("builder", [rpr_inverted_slider_crank, stephenson_sixbar, slot_drive])
def test_power_balance_and_momentum_against_written_out_positions(builder):
    """Q omega1 = dT/dt - P(loads, gravity); F_sh = F_ext + sum m g - dp/dt;
    M_sh,P = M_P(ext, gravity) - dH_P/dt: p, H, T and the powers from positions written out
    here by trigonometry, time derivatives by finite differences; variable omega1, eps1 != 0,
    gravity pointing 200 deg from +x."""
    from linkwork.planar import BodyTorque, inverse_dynamics, kinematics

    mech, poses, loads = builder()
    phi = np.radians(np.arange(3.0, 360.0, 15.0))
    w, e = 6.0 + np.cos(phi), -4.0 + 3 * np.sin(2 * phi)
    g = 9.81 * np.array([np.cos(np.radians(200)), np.sin(np.radians(200))])
    P = np.array([0.1, 0.2])
    kin = kinematics(mech, phi, w, e)
    lds = loads(phi)
    dyn = inverse_dynamics(kin, gravity=tuple(g), loads=lds, about=tuple(P))
    names = [b.name for b in mech.bodies]
    m = np.array([mech.body(n).mass for n in names])
    J = np.array([mech.body(n).inertia for n in names])
    for k, p in enumerate(phi):
        def q(x):
            d = poses(x)
            return np.array([[*d[n][0], d[n][1]] for n in names])
        q0, d1, d2 = _rates(q, p)
        v, a = d1 * w[k], d2 * w[k] ** 2 + d1 * e[k]
        # engine positions and accelerations of the centres
        for i, n in enumerate(names):
            c = kin.point(n, "com")
            assert np.hypot(c.x[k] - q0[i, 0], c.y[k] - q0[i, 1]) < 1e-12
            assert np.hypot(c.ax[k] - a[i, 0], c.ay[k] - a[i, 1]) < 1e-6 * (1 + abs(a).max())
        # power of the loads and gravity, resultant and moment about P
        power = float(np.sum(m * (v[:, :2] @ g)))
        F = m.sum() * g
        MP = float(np.sum(m * ((q0[:, 0] - P[0]) * g[1] - (q0[:, 1] - P[1]) * g[0])))
        for ld in lds:
            if isinstance(ld, BodyTorque):
                mz = float(np.broadcast_to(ld.mz, phi.shape)[k])
                power += mz * v[names.index(ld.body), 2]
                MP += mz
                continue
            f = np.array([np.broadcast_to(ld.fx, phi.shape)[k],
                          np.broadcast_to(ld.fy, phi.shape)[k]], dtype=float)
            r, dr, _ = _rates(_point_path(mech, poses, ld.body, ld.point), p)
            power += float(f @ dr) * w[k]
            F = F + f
            MP += (r[0] - P[0]) * f[1] - (r[1] - P[1]) * f[0]
        # dT/dt = sum m v.a + J omega eps
        dT = float(np.sum(m * np.sum(v[:, :2] * a[:, :2], 1)) + np.sum(J * v[:, 2] * a[:, 2]))
        scale = abs(dT) + abs(power) + 1.0
        assert abs(dyn.Q[k] * w[k] - (dT - power)) < 1e-6 * scale
        dp = (m[:, None] * a[:, :2]).sum(0)
        Fsh = F - dp
        assert np.hypot(dyn.shaking_fx[k] - Fsh[0], dyn.shaking_fy[k] - Fsh[1]) < (
            1e-6 * (1 + np.abs(dp).max() + np.abs(F).max()))
        dH = float(np.sum(m * ((q0[:, 0] - P[0]) * a[:, 1] - (q0[:, 1] - P[1]) * a[:, 0]))
                   + np.sum(J * a[:, 2]))
        assert abs(dyn.shaking_m[k] - (MP - dH)) < 1e-6 * (1 + abs(MP) + abs(dH))


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_fourbar_inverse_dynamics_gravity_loads_eps(branch):
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    mech = engine_fourbar(a, b, c, d, masses=(1.0, 3.0, 2.0), inertias=(0.004, 0.03, 0.01),
                          coms=((0.04, 0.01), 0.12, (0.09, -0.02)), branch=branch)
    mech = Mechanism(mech.frame, (
        mech.bodies[0], Body("coupler", {"A": (0, 0), "B": (b, 0), "P": (0.1, 0.05)}, mass=3.0,
                             com=(0.12, 0.0), inertia=0.03), mech.bodies[2]),
        mech.joints, mech.driver, mech.branches)
    loads = [PointForce("coupler", "P", fx=15.0, fy=-40.0), PointForce("rocker", "B", fx=-8.0,
                                                                       fy=5.0),
             BodyTorque("rocker", 3.5), BodyTorque("crank", -1.2)]
    _check_engine(mech, PHI7, 8.0, 30.0, (0.0, -9.81), loads, about=(0.05, -0.02),
                  label="fourbar ")


def test_engine_crank_slider_with_press_force():
    mech = engine_crank_slider(0.05, 0.2, 0.03, guide_angle=math.radians(90), masses=(2, 3, 10),
                               branch=1)
    load = np.where((PHI7 > 1) & (PHI7 < 3), -2000.0, 0.0)
    loads = [PointForce("slider", "B", fx=0.0, fy=load), BodyTorque("rod", 2.0)]
    _check_engine(mech, PHI7, 12.0, -40.0, (0.0, -9.81), loads, label="crank-slider ")


def test_engine_sine_press_pin_in_slot():
    alpha = math.radians(60)
    frame = Body("frame", {"A": (0, 0)})
    crank = Body("crank", {"A": (0, 0), "B": (0.05, 0)}, mass=6, com=(0.01, 0), inertia=0.02)
    ram = Body("ram", {"S": (0, 0)}, mass=25, com=(-0.15, 0.01), inertia=0.5)
    joints = (Revolute("A", "frame", "crank"),
              Prismatic("guide", "frame", "ram", angle=0.0, through=(0, 0), point="S"),
              PinInSlot("slot", "ram", "crank", angle=alpha, through="S", point="B"))
    mech = Mechanism(frame, (crank, ram), joints, Crank("A"))
    loads = [PointForce("ram", "S", fx=8000.0, fy=0.0), BodyTorque("ram", 4.0)]
    _check_engine(mech, PHI7, 12.566, 50.0, (-9.81, 0.0), loads, label="sine press ")


def test_engine_sixbar_example_file():
    from linkwork.files import load
    doc = load("examples/loom_sixbar.toml")
    mech = doc.mechanism()
    phi = PHI7
    _check_engine(mech, phi, 9.0, 20.0, (0.0, -9.81), [BodyTorque(mech.bodies[-1].name, 5.0)],
                  label="six-bar ")


def test_engine_class_three_group_by_newton():
    """A crank driving a class-III Assur group (triad: ternary body c and three binary links,
    two of them pivoted in the frame), solved by the engine's Newton continuation.  The triad
    locks near phi1 = 0.164 rad (checked with an independent continuation), so 7 positions in
    [-0.5, 0.12] rad; a finer reference step near that singular position."""
    P, R = np.array([0.7, -0.1]), np.array([0.3, 0.6])
    A, X = np.array([0.1, 0.0]), np.array([0.35, 0.25])
    Y, Z = np.array([0.55, 0.2]), np.array([0.45, 0.45])

    def link(name, s, e, S, E):
        d = E - S
        ln = float(np.hypot(*d))
        return Body(name, {s: (0.0, 0.0), e: (ln, 0.0)}, mass=1.0, com=(ln / 2, 0.0),
                    inertia=0.01, guess=(S[0], S[1], math.atan2(d[1], d[0])))
    frame = Body("frame", {"O": (0.0, 0.0), "P": tuple(P), "R": tuple(R)})
    bodies = (bar("crank", "O", "A", 0.1, mass=1.0), link("l1", "A", "X", A, X),
              link("l2", "P", "Y", P, Y), link("l3", "R", "Z", R, Z),
              Body("c", {"X": (0, 0), "Y": tuple(Y - X), "Z": tuple(Z - X)}, mass=2.0,
                   com=(0.1, 0.05), inertia=0.02, guess=(X[0], X[1], 0.0)))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l1"),
              Revolute("X", "l1", "c"), Revolute("Y", "c", "l2"), Revolute("P", "frame", "l2"),
              Revolute("Z", "c", "l3"), Revolute("R", "frame", "l3"))
    mech = Mechanism(frame, bodies, joints, Crank("O"))
    assert [g.cls for g in mech.structure.groups] == [1, 3]
    loads = [PointForce("c", "Z", fx=10.0, fy=3.0), BodyTorque("l2", 1.0)]
    _check_engine(mech, np.linspace(-0.5, 0.12, 7), 5.0, 10.0, (0.0, -9.81), loads,
                  label="class III ", step=1e-4)


ENGINE_QUANTITIES = {"engine x,y", "engine theta", "engine v", "engine omega", "engine a",
                     "engine eps", "kinetic energy", "reactions", "reactions mz", "Q",
                     "shaking force", "shaking moment"}


def test_engine_check_compares_every_quantity_with_the_free_body_reference():
    """What the old report (it only printed the largest deviation per quantity) showed, asserted:
    one run of ``_check_engine`` on the four-bar with gravity, loads and eps1 != 0 compares every
    quantity of the engine's kinematics and inverse dynamics (positions, angles, velocities,
    accelerations, kinetic energy, reactions, driving torque, shaking loads) with the Newton-Euler
    reference of tests/_planar_newton_euler.py, and the largest relative deviation of each is
    within RTOL = 1e-6 (measured: <= 2.2e-9).  Runs the comparison itself, so it does not depend
    on the order of the tests."""
    DEV.clear()
    test_engine_fourbar_inverse_dynamics_gravity_loads_eps(1)
    assert {k.removeprefix("fourbar ") for k in DEV} == ENGINE_QUANTITIES
    assert max(DEV.values()) <= RTOL, DEV


def test_mean_driving_torque_over_a_closed_cycle_is_zero_without_loads():
    """Physical invariant: at constant crank speed, without gravity and loads, the work of the
    driving torque over a closed cycle equals the change of kinetic energy, zero; so the mean
    torque Q_mean (trapezoid work / 2 pi) is zero to the trapezoid rule's error on a smooth
    periodic integrand (spectral: 1e-9 of the peak torque here), while the peak torque is not."""
    mech = engine_fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    phi = np.linspace(0.0, 2 * np.pi, 721)
    dyn = inverse_dynamics(pl.kinematics(mech, phi))
    peak_q = np.abs(dyn.Q).max()
    assert peak_q > 1.0
    assert abs(dyn.Q_mean) < 1e-9 * peak_q
    # and with gravity on a closed cycle the potential energy returns too: the mean is zero
    dyn_g = inverse_dynamics(pl.kinematics(mech, phi), gravity=(0.0, -9.81))
    assert abs(dyn_g.Q_mean) < 1e-9 * np.abs(dyn_g.Q).max()
    # on a part of the cycle Q = dT/dphi1 (Q omega1 = dT/dt), so the mean is the change of
    # kinetic energy over the angle turned; the trapezoid rule's error on an open range is
    # O(h^2) = 7.6e-5 relative at 0.5 deg steps
    part = inverse_dynamics(pl.kinematics(mech, phi[:181]))
    dT = part.T[-1] - part.T[0]
    assert part.Q_mean == pytest.approx(dT / (phi[180] - phi[0]), rel=2e-4)


def test_chunks_without_friction_give_every_array_of_the_whole_cycle(monkeypatch):
    """inverse_dynamics in chunks (positions > CHUNK) of a frictionless four-bar with gravity
    against the same cycle in one piece: every per-position array, the friction fields too
    (zeros, kappa 1, locked False: made whole, not copied chunk by chunk), bit for bit, with
    the same shapes and dtypes; and T is kinetic_energy(kin) bit for bit (taken from the
    centres' motion computed for the inertia wrenches)."""
    import linkwork.planar.dynamics as dynamics
    from linkwork.planar import kinetic_energy

    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    kin = kinematics(mech, np.linspace(0.1, 2 * np.pi + 0.1, 61)[:-1])
    whole = inverse_dynamics(kin, gravity=(0.0, -9.81), about=(0.05, -0.02))
    monkeypatch.setattr(dynamics, "CHUNK", 7)
    chunked = inverse_dynamics(kin, gravity=(0.0, -9.81), about=(0.05, -0.02))
    for name in dynamics._PER_POSITION:
        a, b = getattr(whole, name), getattr(chunked, name)
        assert a.shape == b.shape and a.dtype == b.dtype, name
        assert a.tobytes() == b.tobytes(), name
    assert not chunked.locked.any() and np.all(chunked.kappa == 1.0)
    assert not np.any(chunked.friction_fx) and not np.any(chunked.friction_power)
    assert whole.T.tobytes() == kinetic_energy(kin).tobytes()


def test_backend_is_checked_before_any_work(monkeypatch):
    """inverse_dynamics(backend=...): a name other than 'numpy' or 'numba' is a ParameterError
    naming the option; 'numba' without numba installed is a MissingExtraError naming the
    extra (the compiled backend itself: tests/planar/compiled/test_reactions.py); the default
    needs nothing."""
    kin = kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0)),
                     np.linspace(0.0, 1.0, 5))
    with pytest.raises(ParameterError, match="backend"):
        inverse_dynamics(kin, backend="NumPy")
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba raises ImportError
    with pytest.raises(MissingExtraError, match=r"linkwork\[numba\]"):
        inverse_dynamics(kin, backend="numba")
    assert inverse_dynamics(kin).Q.shape == (5,)


def test_a_motion_of_no_positions_has_dynamics_of_no_positions() -> None:
    """An empty cycle (kinematics of 0 driver positions) gives arrays with 0 positions, for
    one design and a batch, with and without loads (it raised a bare reshape ValueError)."""
    one = engine_fourbar(0.1, 0.3, 0.2, 0.3, omega1=10.0, masses=(1.0, 2.0, 3.0))
    dyn = inverse_dynamics(kinematics(one, np.array([])),
                           loads=[pl.PointForce("rocker", (0.1, 0.0), fy=-5.0)])
    assert dyn.Q.shape == (0,) and dyn.fx.shape == (4, 0) and dyn.load_power.shape == (1, 0)
    assert inverse_dynamics(kinematics(one, np.array([]))).load_power.shape == (0, 0)
    batch = engine_fourbar(np.array([0.1, 0.11]), 0.3, 0.2, 0.3, omega1=10.0,
                           masses=(1.0, 2.0, 3.0))
    assert inverse_dynamics(kinematics(batch, np.array([]))).fx.shape == (4, 2, 0)
