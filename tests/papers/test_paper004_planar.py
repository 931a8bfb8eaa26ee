"""Paper 004 (Abdrashev & Myrzaliev), planar kinetostatics, Eqs. (8)-(13), checked one by one.

Each printed formula is evaluated literally (``printed=True``) and compared with

* the independent derivation in :func:`linkwork.models.fourbar.fourbar_kinetostatics`, itself
  checked against a 9x9 equilibrium solve in ``tests/models/test_fourbar.py``, and
* the power balance  Q omega1 + sum(F_i . v_Si) + sum(M_i omega_i) = 0  of the d'Alembert
  loads (F_i, M_i already contain the inertia forces and couples), computed here.

The paper's symbols: links 1, 2, 3 = crank, coupler, rocker (Norton's 2, 3, 4); phi3 is the angle
of the vector B -> C (its loop equation (1) runs O -> A -> B -> C), i.e. Norton's theta4 + pi.
F_i is the resultant force on link i at the link's midpoint, M_i the resultant couple.
"""

from __future__ import annotations

import numpy as np
import pytest
from _fourbar_newton_euler import DESIGNS, check_reactions, fourbar_positions, fourbar_reference
from _fourbar_newton_euler import GRAV as NE_GRAV
from _fourbar_newton_euler import INERTIA as NE_INERTIA
from _fourbar_newton_euler import LOADS as NE_LOADS
from _fourbar_newton_euler import M_EXT as NE_M_EXT
from _fourbar_newton_euler import MASS as NE_MASS
from _planar_newton_euler import PHI7, _close

from linkwork.models import fourbar as fb
from linkwork.models.fourbar import (
    fourbar_kinetostatics,
    paper004_eq8,
    paper004_eq9,
    paper004_eq10,
    paper004_eq11,
    paper004_eq12,
    paper004_eq13,
    paper004_planar,
)
from linkwork.planar import BodyTorque, inverse_dynamics, kinematics
from linkwork.planar import fourbar_mechanism as engine_fourbar

# paper 001's four-bar as a loom linkage stand-in: l1 = 0.1, l2 = 0.3, l3 = 0.2, frame 0.3 m
L1, L2, L3, D = 0.1, 0.3, 0.2, 0.3
MASS = (1.0, 3.0, 2.0)
INERTIA = (0.0008, 0.0225, 0.00567)
FORCE = ((3.0, -2.0), (-15.0, 8.0), (5.0, 12.0))    # external forces at the midpoints [N]
MOMENT = (0.7, -1.5, 2.5)                           # external couples [N m]
GRAV = (0.0, -9.81)
W1, E1 = 10.0, -30.0
T2 = np.linspace(0.0, 2 * np.pi, 73)


def _case(branch, force=FORCE, moment=MOMENT, inertia=INERTIA):
    """Derivation (fourbar_kinetostatics) and the paper's inputs F_i, M_i for the same state."""
    res = fourbar_kinetostatics(T2, L1, L2, L3, D, W1, E1, branch, mass=MASS, inertia=inertia,
                                gravity=GRAV, force=force, moment=moment)
    k = res.kinematics
    omegas = (W1, k.omega3, k.omega4)
    alphas = (E1, k.eps3, k.eps4)
    F, M, V = [], [], []
    for i, (link, length) in enumerate((("crank", L1), ("coupler", L2), ("rocker", L3))):
        _, _, vx, vy, ax, ay = k.point(link, length / 2)
        F.append((force[i][0] + MASS[i] * (GRAV[0] - ax), force[i][1] + MASS[i] * (GRAV[1] - ay)))
        M.append(moment[i] - inertia[i] * alphas[i])
        V.append((vx, vy))
    phi = (T2, k.theta3, k.theta4 + np.pi)
    return res, phi, F, M, V, omegas


def _power_residual(Q, F, M, V, omegas):
    """Q omega1 + power of all d'Alembert loads; zero for the right Q."""
    p = Q * W1
    for i in range(3):
        p = p + F[i][0] * V[i][0] + F[i][1] * V[i][1] + M[i] * omegas[i]
    return p


def _scale(res):
    return max(np.abs(res.R_Bx).max(), np.abs(res.R_By).max(), np.abs(res.Q).max())


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq8_RBx_as_printed(branch):
    """Reference: paper 004, Eq. (8). Tolerance: rtol=0, atol=1e-10 * _scale(res)."""
    res, phi, F, M, _, _ = _case(branch)
    got = paper004_eq8(phi[1], phi[2], L2, L3, F[1], F[2], M[1], M[2], printed=True)
    np.testing.assert_allclose(got, res.R_Bx, rtol=0, atol=1e-10 * _scale(res))


def test_paper004_eq8_holds_only_with_phi3_from_B_to_C():
    """phi3 -> phi3 + pi flips every term of (8) but the M3 one: the convention is B -> C."""
    res, phi, F, M, _, _ = _case(+1)
    got = paper004_eq8(phi[1], phi[2] - np.pi, L2, L3, F[1], F[2], M[1], M[2])
    assert np.abs(got - res.R_Bx).max() > 1e-2 * _scale(res)
    # with no couple at all on link 3 (no external moment, no rotary inertia) both agree
    res0, phi0, F0, M0, _, _ = _case(+1, moment=(0.7, -1.5, 0.0), inertia=(0.0008, 0.0225, 0.0))
    got0 = paper004_eq8(phi0[1], phi0[2] - np.pi, L2, L3, F0[1], F0[2], M0[1], M0[2])
    np.testing.assert_allclose(got0, res0.R_Bx, rtol=0, atol=1e-10 * _scale(res0))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq9_RBy_printed_is_wrong(branch):
    res, phi, F, M, _, _ = _case(branch)
    got = paper004_eq9(phi[1], phi[2], L2, L3, F[1], F[2], M[1], M[2], printed=True)
    assert np.abs(got - res.R_By).max() > 0.05 * _scale(res)


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq9_RBy_corrected(branch):
    """Reference: paper 004, Eq. (9). Tolerance: rtol=0, atol=1e-10 * _scale(res)."""
    res, phi, F, M, _, _ = _case(branch)
    got = paper004_eq9(phi[1], phi[2], L2, L3, F[1], F[2], M[1], M[2], printed=False)
    np.testing.assert_allclose(got, res.R_By, rtol=0, atol=1e-10 * _scale(res))


def test_paper004_eq9_each_printed_error_matters():
    """Fixing only the cos->sin of the second term, or only the first term, is not enough."""
    res, phi, F, M, _, _ = _case(+1)
    s2, c2 = np.sin(phi[1]), np.cos(phi[1])
    s3, c3 = np.sin(phi[2]), np.cos(phi[2])
    den = L2 * L3 * np.sin(phi[1] - phi[2])
    t3 = -F[2][0] * L3 / 2 * s3 + F[2][1] * L3 / 2 * c3 - M[2]
    first_printed = -L3 * s3 * (-F[1][0] * L2 / 2 * s2 - F[1][1] * L2 / 2 * c2 - M[1])
    first_fixed = L3 * s3 * (F[1][0] * L2 / 2 * s2 - F[1][1] * L2 / 2 * c2 - M[1])
    only_sin = (first_printed - L2 * s2 * t3) / den
    only_first = (first_fixed - L2 * c2 * t3) / den
    both = (first_fixed - L2 * s2 * t3) / den
    tol = 1e-10 * _scale(res)
    assert np.abs(only_sin - res.R_By).max() > 1e3 * tol
    assert np.abs(only_first - res.R_By).max() > 1e3 * tol
    np.testing.assert_allclose(both, res.R_By, rtol=0, atol=tol)


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq10_RC(branch):
    """Reference: paper 004, Eq. (10). Tolerance: atol=1e-10 * _scale(res)."""
    res, _, F, _, _, _ = _case(branch)
    rcx, rcy = paper004_eq10(F[2], (res.R_Bx, res.R_By))
    np.testing.assert_allclose(rcx, res.R_Cx, atol=1e-10 * _scale(res))
    np.testing.assert_allclose(rcy, res.R_Cy, atol=1e-10 * _scale(res))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq11_RA(branch):
    """Reference: paper 004, Eq. (11). Tolerance: atol=1e-10 * _scale(res)."""
    res, _, F, _, _, _ = _case(branch)
    rax, ray = paper004_eq11(F[1], (res.R_Bx, res.R_By))
    np.testing.assert_allclose(rax, res.R_Ax, atol=1e-10 * _scale(res))
    np.testing.assert_allclose(ray, res.R_Ay, atol=1e-10 * _scale(res))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq12_R0(branch):
    """Reference: paper 004, Eq. (12). Tolerance: atol=1e-10 * _scale(res)."""
    res, _, F, _, _, _ = _case(branch)
    r0x, r0y = paper004_eq12(F[0], (res.R_Ax, res.R_Ay))
    np.testing.assert_allclose(r0x, res.R_Ox, atol=1e-10 * _scale(res))
    np.testing.assert_allclose(r0y, res.R_Oy, atol=1e-10 * _scale(res))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq13_Q_printed_violates_power_balance(branch):
    """Reference: paper 004, Eq. (13). Tolerance: atol=1e-10 * scale."""
    res, phi, F, M, V, om = _case(branch)
    q = paper004_eq13(phi[0], L1, (res.R_Ax, res.R_Ay), F[0], M[0], printed=True)
    scale = np.abs(res.Q * W1).max()
    assert np.abs(_power_residual(q, F, M, V, om)).max() > 1e-2 * scale
    # the error is exactly twice the moment of F1 about O
    mom_f1 = L1 / 2 * (np.cos(phi[0]) * F[0][1] - np.sin(phi[0]) * F[0][0])
    np.testing.assert_allclose(q - res.Q, 2 * mom_f1, atol=1e-10 * scale)


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq13_Q_corrected_satisfies_power_balance(branch):
    """Reference: paper 004, Eq. (13). Tolerance: atol=1e-10 * np.abs(res.Q).max(), atol=1e-10 *
    scale."""
    res, phi, F, M, V, om = _case(branch)
    q = paper004_eq13(phi[0], L1, (res.R_Ax, res.R_Ay), F[0], M[0], printed=False)
    scale = np.abs(res.Q * W1).max()
    np.testing.assert_allclose(q, res.Q, atol=1e-10 * np.abs(res.Q).max())
    np.testing.assert_allclose(_power_residual(q, F, M, V, om), 0, atol=1e-10 * scale)


def test_paper004_eq13_printed_is_right_when_F1_vanishes():
    """A crank balanced about O with no load on it: F1 = 0 and the printed (13) is exact."""
    res = fourbar_kinetostatics(T2, L1, L2, L3, D, W1, 0.0, +1, mass=(0.0, 3.0, 2.0),
                                inertia=(0.0008, 0.0225, 0.00567), gravity=GRAV,
                                moment=(0.7, 0.0, 0.0))
    q = paper004_eq13(T2, L1, (res.R_Ax, res.R_Ay), (0.0, 0.0), 0.7, printed=True)
    np.testing.assert_allclose(q, res.Q, atol=1e-12 * np.abs(res.Q).max())


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_planar_chain_corrected_equals_derivation(branch):
    """Reference: paper 004. Tolerance: rtol=0, atol=tol."""
    res, phi, F, M, _, _ = _case(branch)
    p = paper004_planar(*phi, L1, L2, L3, *F, *M, printed=False)
    tol = 1e-10 * _scale(res)
    for mine, theirs in ((res.R_Bx, p.R_Bx), (res.R_By, p.R_By), (res.R_Cx, p.R_Cx),
                         (res.R_Cy, p.R_Cy), (res.R_Ax, p.R_Ax), (res.R_Ay, p.R_Ay),
                         (res.R_Ox, p.R_0x), (res.R_Oy, p.R_0y), (res.Q, p.Q)):
        np.testing.assert_allclose(theirs, mine, rtol=0, atol=tol)
    # and the printed chain is not
    pp = paper004_planar(*phi, L1, L2, L3, *F, *M, printed=True)
    assert np.abs(pp.Q - res.Q).max() > 1e-2 * np.abs(res.Q).max()


# --- the planar (third) rows of the moment equations (3), (5), (7) that (8)-(13) come from ---


def _moment_rows(branch):
    res, phi, F, M, _, _ = _case(branch)
    s1, c1 = np.sin(phi[0]), np.cos(phi[0])
    s2, c2 = np.sin(phi[1]), np.cos(phi[1])
    s3, c3 = np.sin(phi[2]), np.cos(phi[2])
    RA, RB = (res.R_Ax, res.R_Ay), (res.R_Bx, res.R_By)
    eq3 = (RB[1] * L3 * c3 - RB[0] * L3 * s3 + F[2][0] * L3 / 2 * s3 - F[2][1] * L3 / 2 * c3
           + M[2])
    eq5 = ((RB[0] * L2 * s2 - RB[1] * L2 * c2) + F[1][1] * L2 / 2 * c2
           - F[1][0] * L2 / 2 * s2 + M[1])
    eq7 = (-RA[1] * L1 * c1 + RA[0] * L1 * s1 + F[0][0] * L1 / 2 * s1 - F[0][1] * L1 / 2 * c1
           - M[0] + res.Q)
    return res, phi, F, M, eq3, eq5, eq7


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq5_third_row_coupler_moments_about_A(branch):
    """Reference: paper 004, Eq. (5). Tolerance: atol=1e-10 * _scale(res)."""
    res, _, _, _, _, eq5, _ = _moment_rows(branch)
    np.testing.assert_allclose(eq5, 0, atol=1e-10 * _scale(res))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq3_third_row_is_inconsistent(branch):
    """Printed: R_B terms fit phi3 = C -> B, the F3 terms phi3 = B -> C; neither closes."""
    res, phi, _, M, eq3, _, _ = _moment_rows(branch)
    assert np.abs(eq3).max() > 1e-2 * np.abs(M[2]).max()
    # residual = 2 x (moment of R_B about C), i.e. the R_B terms have the wrong sign for the
    # paper's phi3 (B -> C) under which (8) holds
    mom_rb = -L3 * (np.cos(phi[2]) * res.R_By - np.sin(phi[2]) * res.R_Bx)
    np.testing.assert_allclose(eq3, -2 * mom_rb, atol=1e-10 * _scale(res))


@pytest.mark.parametrize("branch", [+1, -1])
def test_paper004_eq7_third_row_signs_of_F1_and_M1(branch):
    """Printed (7): F1 terms and M1 carry the wrong sign (residual 2(-mom F1 - M1))."""
    res, phi, F, M, _, _, eq7 = _moment_rows(branch)
    mom_f1 = L1 / 2 * (np.cos(phi[0]) * F[0][1] - np.sin(phi[0]) * F[0][0])
    np.testing.assert_allclose(eq7, -2 * mom_f1 - 2 * M[0], atol=1e-10 * _scale(res))
    assert np.abs(eq7).max() > 1e-2 * np.abs(res.Q).max()


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "general"])
def test_paper004_corrected_equations_against_newton_euler(name, branch):
    """Paper 004's Eqs. (8)-(13) as corrected (printed=False), centres of mass and forces at
    the link midpoints: F_i = m_i (g - a_Si) + F_ext, M_i = M_ext - J_i eps_i."""
    design = DESIGNS[name]
    mids = tuple((length / 2, 0.0) for length in design[:3])
    loads = {"force": NE_LOADS["force"], "point": mids, "moment": NE_M_EXT}
    ref = fourbar_reference(design, branch, loads=loads, coms=mids)
    g = np.array(NE_GRAV)[:, None]
    F = [NE_MASS[i] * (g - ref["aG"][i]) + np.array(NE_LOADS["force"][i])[:, None]
         for i in range(3)]
    Mz = [NE_M_EXT[i] - NE_INERTIA[i] * ref["al"][i] for i in range(3)]
    th3, th4 = fourbar_positions(ref["t2"], *design, branch)
    r = paper004_planar(ref["t2"], th3, th4 + np.pi, *design[:3], tuple(F[0]), tuple(F[1]),
                        tuple(F[2]), *Mz, printed=False)
    check_reactions(((r.R_0x, r.R_0y), (r.R_Ax, r.R_Ay), (r.R_Bx, r.R_By), (r.R_Cx, r.R_Cy)),
                    r.Q, ref["x"])


@pytest.mark.parametrize("branch", [1, -1])
def test_paper004_eqs_8_to_13_against_the_engine(branch):
    """Paper 004's chained planar kinetostatics (8)-(13), corrected, equal the engine's
    reactions and driving moment (paper 001's four-bar, gravity, couples, eps1 != 0); as
    printed, (8) is right and (9), (13) are not (docs/errata.md)."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    masses, inert = (1.0, 3.0, 2.0), (0.002, 0.03, 0.008)
    mech = engine_fourbar(a, b, c, d, masses=masses, inertias=inert, branch=branch)
    g = np.array([0.0, -9.81])
    couples = (0.5, -1.5, 2.0)
    kin = kinematics(mech, PHI7, 10.0, 25.0)
    dyn = inverse_dynamics(kin, gravity=g, loads=[BodyTorque(n, m) for n, m in zip(
        ("crank", "coupler", "rocker"), couples, strict=True)])
    F, M = [], []
    for i, name in enumerate(("crank", "coupler", "rocker")):
        s = kin.point(name, "com")                    # the midpoint (bar default)
        F.append((masses[i] * (g[0] - s.ax), masses[i] * (g[1] - s.ay)))
        M.append(-inert[i] * kin.eps[i + 1] + couples[i])
    phi1, phi2 = kin.angle("crank"), kin.angle("coupler")
    phi3 = kin.angle("rocker") + np.pi                # paper 004: phi3 is B -> C
    for printed in (False, True):
        p = fb.paper004_planar(phi1, phi2, phi3, a, b, c, *F, *M, printed=printed)
        scale = np.max(np.abs(dyn.fx))
        got = {"R_B": (p.R_Bx, p.R_By), "R_C": (p.R_Cx, p.R_Cy), "R_A": (p.R_Ax, p.R_Ay),
               "R_0": (p.R_0x, p.R_0y)}
        want = {"R_B": dyn.reaction("B"), "R_C": dyn.reaction("O4"), "R_A": dyn.reaction("A"),
                "R_0": dyn.reaction("O2")}
        if not printed:
            for k in got:
                _close(got[k][0], want[k][0], scale, "paper004 corrected vs engine")
                _close(got[k][1], want[k][1], scale, "paper004 corrected vs engine")
            _close(p.Q, dyn.Q, scale * a, "paper004 corrected vs engine")
        else:
            _close(p.R_Bx, want["R_B"][0], scale, "paper004 printed (8) vs engine")
            assert np.max(np.abs(p.R_By - want["R_B"][1])) > 1e-3 * scale     # (9) wrong
            assert np.max(np.abs(p.Q - dyn.Q)) > 1e-3 * scale * a             # (13) wrong
