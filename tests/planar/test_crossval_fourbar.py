"""The closed-form four-bar and its kinetostatics against the general planar engine.

Whole cycles, both assembly branches, several designs, with crank acceleration, gravity, external
forces at off-axis points, couples and off-axis centres of mass; agreement to 1e-9 relative.
Paper 004's Eqs. (8)-(13) are checked against the engine too (printed and corrected).
"""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.models.fourbar import (
    fourbar,
    fourbar_kinetostatics,
    paper004_eq10,
    paper004_eq11,
    paper004_eq12,
    paper004_eq13,
    paper004_planar,
)
from linkwork.planar import BodyTorque, PointForce, inverse_dynamics, kinematics
from linkwork.planar import fourbar_mechanism as engine_fourbar

DESIGNS = {
    "crank-rocker (paper 001)": (0.1, 0.3, 0.2, 0.3),
    "double-crank": (0.3, 0.2, 0.3, 0.1),
    "crank-rocker, long coupler": (0.05, 0.4, 0.25, 0.35),
}
W2, E2 = 10.0, -30.0
MASS = (1.0, 3.0, 2.0)
INERTIA = (0.004, 0.0225, 0.00567)
COM = ((0.04, 0.01), (0.17, -0.03), (0.08, 0.02))
FORCE = ((2.0, -1.0), (-15.0, 8.0), (5.0, 12.0))
FPOINT = ((0.03, -0.02), (0.25, 0.05), (0.1, -0.02))
MOMENT = (0.4, -1.5, 2.5)
GRAV = (0.0, -9.81)
NAMES = ("crank", "coupler", "rocker")


def wrap(x):
    return np.angle(np.exp(1j * x))


def _engine(design, branch, t2):
    mech = engine_fourbar(*design, masses=MASS, inertias=INERTIA, coms=COM, omega1=W2, eps1=E2,
                          branch=branch)
    kin = kinematics(mech, t2)
    loads = [PointForce(n, FPOINT[i], fx=FORCE[i][0], fy=FORCE[i][1]) for i, n in enumerate(NAMES)]
    loads += [BodyTorque(n, MOMENT[i]) for i, n in enumerate(NAMES)]
    dyn = inverse_dynamics(kin, gravity=GRAV, loads=loads)
    return kin, dyn


def _close(got, want, scale):
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * scale)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("design", list(DESIGNS.values()), ids=list(DESIGNS))
def test_fourbar_kinematics_equals_engine(design, branch):
    t2 = np.linspace(0.0, 2 * np.pi, 721)
    kin, _ = _engine(design, branch, t2)
    r = fourbar(t2, *design, W2, E2, branch)
    a, b, c, d = design
    scale_l = a + b + c + d
    _close(wrap(r.theta3 - kin.angle("coupler")), 0, 1.0)
    _close(wrap(r.theta4 - kin.angle("rocker")), 0, 1.0)
    w = kin.omega
    e = kin.eps
    i3, i4 = kin.bodies.index("coupler"), kin.bodies.index("rocker")
    _close(r.omega3, w[i3], np.abs(w[i3]).max())
    _close(r.omega4, w[i4], np.abs(w[i4]).max())
    _close(r.eps3, e[i3], np.abs(e[i3]).max())
    _close(r.eps4, e[i4], np.abs(e[i4]).max())
    B = kin.point("coupler", "B")
    _close(r.xB, B.x, scale_l)
    _close(r.yB, B.y, scale_l)
    A = kin.point("crank", "A")
    _close(r.xA, A.x, scale_l)
    _close(r.yA, A.y, scale_l)
    # a coupler point's full motion
    P = kin.point("coupler", (0.12, -0.07))
    got = r.point("coupler", 0.12, -0.07)
    for g, want in zip(got, (P.x, P.y, P.vx, P.vy, P.ax, P.ay), strict=True):
        _close(g, want, np.abs(want).max() + 1e-3)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("design", list(DESIGNS.values()), ids=list(DESIGNS))
def test_fourbar_kinetostatics_equals_engine(design, branch):
    t2 = np.linspace(0.0, 2 * np.pi, 721)
    _, dyn = _engine(design, branch, t2)
    res = fourbar_kinetostatics(t2, *design, W2, E2, branch, mass=MASS, inertia=INERTIA,
                                com=COM, gravity=GRAV, force=FORCE, force_point=FPOINT,
                                moment=MOMENT)
    scale = max(np.abs(dyn.fx).max(), np.abs(dyn.fy).max())
    for joint, (fx, fy) in {"O2": (res.R_Ox, res.R_Oy), "A": (res.R_Ax, res.R_Ay),
                            "B": (res.R_Bx, res.R_By), "O4": (res.R_Cx, res.R_Cy)}.items():
        efx, efy = dyn.reaction(joint)
        _close(fx, efx, scale)
        _close(fy, efy, scale)
    _close(res.Q, dyn.Q, np.abs(dyn.Q).max())
    _close(res.shaking_force_x, dyn.shaking_fx, scale)
    _close(res.shaking_force_y, dyn.shaking_fy, scale)
    _close(res.shaking_moment, dyn.shaking_m, np.abs(dyn.shaking_m).max())


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eqs8_to_13_against_engine(branch):
    """Paper 004's setting (centres of mass at midpoints), its formulas vs the engine."""
    design = DESIGNS["crank-rocker (paper 001)"]
    a, b, c, _ = design
    t2 = np.linspace(0.0, 2 * np.pi, 361)
    mech = engine_fourbar(*design, masses=MASS, inertias=INERTIA, omega1=W2, eps1=E2,
                          branch=branch)
    kin = kinematics(mech, t2)
    loads = [PointForce(n, "com", fx=FORCE[i][0], fy=FORCE[i][1]) for i, n in enumerate(NAMES)]
    loads += [BodyTorque(n, MOMENT[i]) for i, n in enumerate(NAMES)]
    dyn = inverse_dynamics(kin, gravity=GRAV, loads=loads)
    # the paper's inputs: resultant force at each midpoint and resultant couple, from the engine
    F, M = [], []
    for i, n in enumerate(NAMES):
        com = kin.point(n, "com")
        F.append((FORCE[i][0] + MASS[i] * (GRAV[0] - com.ax),
                  FORCE[i][1] + MASS[i] * (GRAV[1] - com.ay)))
        M.append(MOMENT[i] - INERTIA[i] * kin.eps[kin.bodies.index(n)])
    phi = (t2, kin.angle("coupler"), kin.angle("rocker") + np.pi)
    want = {"R_B": dyn.reaction("B"), "R_C": dyn.reaction("O4"), "R_A": dyn.reaction("A"),
            "R_0": dyn.reaction("O2")}
    scale = max(np.abs(dyn.fx).max(), np.abs(dyn.fy).max())
    fixed = paper004_planar(*phi, a, b, c, *F, *M, printed=False)
    printed = paper004_planar(*phi, a, b, c, *F, *M, printed=True)
    for key, (fx, fy) in want.items():
        _close(getattr(fixed, key + "x"), fx, scale)
        _close(getattr(fixed, key + "y"), fy, scale)
    _close(fixed.Q, dyn.Q, np.abs(dyn.Q).max())
    # printed: (8) right; (9) wrong (and so are (10)-(12) downstream of it in y); (13) wrong
    _close(printed.R_Bx, want["R_B"][0], scale)
    for key in ("R_C", "R_A", "R_0"):      # x rows of (10)-(12) only depend on (8)
        _close(getattr(printed, key + "x"), want[key][0], scale)
    # (10)-(12) each, fed with the engine's own reactions, reproduce the engine's
    rb, ra = want["R_B"], want["R_A"]
    for got, ref in ((paper004_eq10(F[2], rb), want["R_C"]), (paper004_eq11(F[1], rb), ra),
                     (paper004_eq12(F[0], ra), want["R_0"])):
        _close(got[0], ref[0], scale)
        _close(got[1], ref[1], scale)
    _close(paper004_eq13(t2, a, ra, F[0], M[0], printed=False), dyn.Q, np.abs(dyn.Q).max())
    assert np.abs(printed.R_By - want["R_B"][1]).max() > 0.05 * scale
    assert np.abs(printed.Q - dyn.Q).max() > 0.05 * np.abs(dyn.Q).max()


@pytest.mark.parametrize("branch", [+1, -1])
def test_fourbar_assembly_failure_matches_engine(branch):
    """A double-rocker over a whole turn: the same positions fail, the rest agree."""
    design = (0.3, 0.1, 0.25, 0.3)
    t2 = np.linspace(0.0, 2 * np.pi, 721)
    kin = kinematics(engine_fourbar(*design, omega1=W2, eps1=E2, branch=branch), t2,
                     on_failure="nan")
    r = fourbar(t2, *design, W2, E2, branch, on_failure="nan")
    ok = r.valid
    assert 0 < ok.sum() < ok.size
    # the masks may differ only at a sample lying exactly on a toggle
    f = np.hypot(design[3] - design[0] * np.cos(t2), design[0] * np.sin(t2))
    margin = np.minimum(design[1] + design[2] - f, f - abs(design[1] - design[2]))
    clear = np.abs(margin) > 1e-12
    np.testing.assert_array_equal(ok[clear], kin.valid[clear])
    good = ok & kin.valid & (margin > 1e-3)
    _close(wrap(r.theta4[good] - kin.angle("rocker")[good]), 0, 1.0)
    i4 = kin.bodies.index("rocker")
    _close(r.omega4[good], kin.omega[i4][good], np.abs(kin.omega[i4][good]).max())
    _close(r.eps4[good], kin.eps[i4][good], np.abs(kin.eps[i4][good]).max())


def test_fourbar_kinetostatics_defaults_equal_engine_defaults():
    """Masses only: thin-rod inertias and midpoint centres of mass on both sides; gravity."""
    design = DESIGNS["crank-rocker (paper 001)"]
    t2 = np.linspace(0.0, 2 * np.pi, 361)
    kin = kinematics(engine_fourbar(*design, masses=MASS, omega1=W2, eps1=E2), t2)
    dyn = inverse_dynamics(kin, gravity=GRAV)
    res = fourbar_kinetostatics(t2, *design, W2, E2, mass=MASS, gravity=GRAV)
    _close(res.Q, dyn.Q, np.abs(dyn.Q).max())
    fx, fy = dyn.reaction("A")
    _close(res.R_Ax, fx, np.abs(dyn.fx).max())
    _close(res.R_Ay, fy, np.abs(dyn.fy).max())
