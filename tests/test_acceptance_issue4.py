"""Acceptance check of issue 4 (balancing, paper 001), as an external checker would do it.

Every expected value is computed here independently of the code under test: finite differences
of the engine's positions (momentum and angular momentum), plain trigonometry, normal equations
written out by hand, the paper's printed table, a brute-force grid, and the command line run on
the bundled example and on broken files.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from linkwork import balancing as bal
from linkwork.cli import main
from linkwork.errors import InfeasibleError, LinkworkError, ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import crank_slider, fourbar

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "fourbar_paper001.toml"

# paper 001's example: OA 0.1, AB 0.3, BC 0.2, OC 0.3 m; centres at mid-links; m 1, 3, 2 kg
PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)

# the paper's printed table (phi [deg], M, dM1, dM2, dM3) [N m]
TABLE = np.array([
    [0, -5.43, -7.23, -4.56, -3.33], [30, -0.96, -5.52, -4.14, -1.50],
    [60, -3.99, -2.39, 0.49, 0.71], [90, -5.55, -0.63, -1.47, 0.67],
    [120, -4.14, 0.50, -2.404, -0.30], [150, -1.92, 1.38, -2.76, -1.32],
    [180, 0.36, 1.94, -2.61, -2.00], [210, 1.71, 2.19, -2.15, -1.87],
    [240, 2.01, 2.59, -2.04, -1.55], [270, 1.71, 2.38, -1.63, 1.01],
    [300, -2.10, 0.22, 0.29, 0.52], [330, -3.99, -3.52, -3.42, -1.22]])


def paper_fourbar(branch=1, eps1=0.0):
    return fourbar(0.1, 0.3, 0.2, 0.3, branch=branch, eps1=eps1, **PAPER)


def com_positions(mech, phi):
    """(b, n, 2) positions of the centres of mass from the engine (positions only)."""
    kin = kinematics(mech, phi)
    return np.stack([np.stack([kin.point(b.name, "com").x, kin.point(b.name, "com").y], -1)
                     for b in mech.bodies]), kin


# ---------------------------------------------------------------------------------------------
# 1. shaking loads against momentum and angular momentum by finite differences


@pytest.mark.parametrize("branch", [1, -1])
def test_shaking_force_and_moment_are_minus_rates_of_momentum(branch):
    """F = -dp/dt and M_P = -dH_P/dt, p and H from the engine's *positions* only, time
    derivatives by central differences (constant omega: d/dt = omega d/dphi)."""
    mech = paper_fourbar(branch)
    w = 10.0
    phi = np.radians(np.arange(0.0, 360.0, 7.5))
    h = 1e-4  # [rad]
    m = np.array([b.mass for b in mech.bodies])
    J = np.array([b.inertia for b in mech.bodies])
    P = np.array([0.03, -0.02])

    def momenta(q):
        r0, kin = com_positions(mech, q)
        rm, km = com_positions(mech, q - h)
        rp, kp = com_positions(mech, q + h)
        v = (rp - rm) / (2 * h) * w
        th = np.stack([kin.angle(b.name) for b in mech.bodies])
        thm = np.stack([km.angle(b.name) for b in mech.bodies])
        thp = np.stack([kp.angle(b.name) for b in mech.bodies])
        om = np.angle(np.exp(1j * (thp - thm))) / (2 * h) * w
        p = np.einsum("b,bnk->nk", m, v)
        d = r0 - P
        H = np.einsum("b,bn->n", m, d[..., 0] * v[..., 1] - d[..., 1] * v[..., 0]) + J @ om
        del th
        return p, H

    H2 = 1e-3
    pp, Hp = momenta(phi + H2)
    pm, Hm = momenta(phi - H2)
    F_ref = -(pp - pm) / (2 * H2) * w
    M_ref = -(Hp - Hm) / (2 * H2) * w
    kin = kinematics(mech, phi)
    sl = bal.shaking_loads(kin, point=P)
    scale = np.max(np.abs(F_ref))
    assert np.max(np.abs(sl.force - F_ref)) <= 2e-5 * scale
    assert np.max(np.abs(sl.moment - M_ref)) <= 2e-5 * np.max(np.abs(M_ref))
    # the engine's inverse dynamics report the same loads (moment about O)
    dyn = inverse_dynamics(kin, about=(0.0, 0.0))
    sl0 = bal.shaking_loads(kin)
    assert np.allclose(dyn.shaking_m, sl0.moment, atol=1e-10 * scale)
    # moment transfer to another point
    assert np.allclose(bal.moment_about(sl0.moment, sl0.force, P), sl.moment, atol=1e-10 * scale)


def test_harmonics_rms_peak_against_a_known_series():
    phi = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    f = 0.5 + 3.0 * np.cos(phi - 0.4) + 1.5 * np.cos(2 * phi + 1.0) - 0.25 * np.sin(4 * phi)
    hm = bal.harmonics(phi, f, 4)
    assert hm.mean == pytest.approx(0.5, abs=1e-12)
    assert np.allclose(hm.amplitude, [3.0, 1.5, 0.0, 0.25], atol=1e-12)
    assert hm.phase[0] == pytest.approx(0.4, abs=1e-12)
    assert hm.phase[1] == pytest.approx(-1.0, abs=1e-12)
    assert hm.phase[3] == pytest.approx(np.arctan2(-0.25, 0.0), abs=1e-12)
    # RMS by Parseval, peak by dense sampling
    assert bal.rms(phi, f) == pytest.approx(np.sqrt(0.25 + (9 + 2.25 + 0.0625) / 2), rel=1e-12)
    assert bal.peak(f) == pytest.approx(np.max(np.abs(f)))
    F = np.stack([3 * np.cos(phi), 4 * np.sin(phi)], -1)
    assert bal.rms(phi, F) == pytest.approx(np.sqrt((9 + 16) / 2), rel=1e-12)
    assert bal.peak(F) == pytest.approx(4.0, rel=1e-12)


# ---------------------------------------------------------------------------------------------
# 2. static balancing


def test_paper_fourbar_counterweights_by_hand_and_stationary_centre_of_mass():
    """Counterweights by the statically equivalent split done by hand; the balanced
    mechanism's total centre of mass (engine positions + counterweight points placed here by
    trigonometry) is stationary, and its engine shaking force is <= 1e-9 of the unbalanced."""
    # hand: crank m1 s1 + m2 (1 - s2/l2) l1 = 0.05 + 0.15 = 0.2; rocker m3 s3 + m2 s2/l2 l3 =
    # 0.2 + 0.3 = 0.5 kg m, both opposite the moving joint
    cw1, cw3 = bal.fourbar_counterweights(0.1, 0.3, 0.2, 1.0, 0.05, 3.0, 0.15, 2.0, 0.1)
    assert (cw1.link, cw3.link) == ("crank", "rocker")
    assert cw1.static_moment == pytest.approx(0.2, rel=1e-12)
    assert cw3.static_moment == pytest.approx(0.5, rel=1e-12)
    assert abs(cw1.angle) == pytest.approx(np.pi, abs=1e-12)
    assert abs(cw3.angle) == pytest.approx(np.pi, abs=1e-12)
    pm = bal.fourbar_counterweights_point_masses(0.1, 0.3, 0.2, 1.0, 0.05, 3.0, 0.15, 2.0, 0.1)
    assert [c.static_moment for c in pm] == pytest.approx([0.2, 0.5], rel=1e-12)

    mech = paper_fourbar()
    fb = bal.force_balance(mech, radii={"crank": 0.05, "rocker": 0.1})
    assert fb.full and fb.reason == ""
    got = {c.link: c for c in fb.counterweights}
    assert got["crank"].static_moment == pytest.approx(0.2, rel=1e-9)
    assert got["rocker"].static_moment == pytest.approx(0.5, rel=1e-9)
    assert got["crank"].mass() == pytest.approx(4.0, rel=1e-9)
    assert got["rocker"].mass() == pytest.approx(5.0, rel=1e-9)

    phi = np.linspace(0, 2 * np.pi, 720, endpoint=False)
    r, kin = com_positions(mech, phi)
    th1, th3 = kin.angle("crank"), kin.angle("rocker")
    cw_crank = 4.0 * 0.05 * np.stack([-np.cos(th1), -np.sin(th1)], -1)
    cw_rocker = 5.0 * (np.array([0.3, 0.0]) + 0.1 * np.stack([-np.cos(th3), -np.sin(th3)], -1))
    first = np.einsum("b,bnk->nk", [1.0, 3.0, 2.0], r) + cw_crank + cw_rocker
    spread = np.max(np.abs(first - first.mean(axis=0)))
    F_unbal = bal.shaking_loads(kinematics(mech, phi, 10.0)).force
    # |F| = omega^2 * |d^2 (first moment)/dphi^2|; stationary to 1e-9 of the unbalanced force
    assert spread * 10.0**2 <= 1e-9 * np.max(np.abs(F_unbal))
    F_bal = bal.shaking_loads(kinematics(fb.mechanism, phi, 10.0)).force
    assert np.max(np.abs(F_bal)) <= 1e-9 * np.max(np.abs(F_unbal))
    # the balanced mechanism is a new description: every analysis runs on it
    assert fb.mechanism.body("crank").mass == pytest.approx(5.0)
    assert mech.body("crank").mass == pytest.approx(1.0)


def test_force_balance_random_fourbars_with_off_line_centres():
    rng = np.random.default_rng(4)
    phi = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    done = 0
    while done < 5:
        a, b, c, d = rng.uniform(0.5, 2.0, 4)
        a = 0.3 * min(b, c, d)  # a Grashof crank
        coms = tuple(complex(*rng.uniform(-0.3, 0.7, 2)) * L for L in (a, b, c))
        try:
            mech = fourbar(a, b, c, d, masses=tuple(rng.uniform(0.5, 3, 3)), coms=tuple(
                (z.real, z.imag) for z in coms), omega1=3.0)
            kinematics(mech, phi)
        except LinkworkError:
            continue
        fb = bal.force_balance(mech, radii=0.1)
        F0 = bal.shaking_loads(kinematics(mech, phi)).force
        F1 = bal.shaking_loads(kinematics(fb.mechanism, phi)).force
        assert fb.full
        assert np.max(np.abs(F1)) <= 1e-9 * np.max(np.abs(F0))
        done += 1


def test_crank_slider_rotating_balance_and_fraction_and_impossible_full_balance():
    m = crank_slider(0.05, 0.2, masses=(1.0, 2.0, 1.5), omega1=20.0)
    phi = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    kin = kinematics(m, phi)
    # independent: the slider position along x by trigonometry; reciprocating mass
    # m3 + m2 s2/l2 = 1.5 + 1 = 2.5 kg; rotating balance leaves F = -m_rec a_B along the guide
    for k in (0.0, 0.5, 1.0):
        mb = bal.crank_slider_balance(m, fraction=k, radius=0.05)
        F = bal.shaking_loads(kinematics(mb, phi)).force
        xB = 0.05 * np.cos(phi) + np.sqrt(0.2**2 - (0.05 * np.sin(phi)) ** 2)
        h = 1e-4
        xBp = 0.05 * np.cos(phi + h) + np.sqrt(0.2**2 - (0.05 * np.sin(phi + h)) ** 2)
        xBm = 0.05 * np.cos(phi - h) + np.sqrt(0.2**2 - (0.05 * np.sin(phi - h)) ** 2)
        aB = (xBp - 2 * xB + xBm) / h**2 * 20.0**2
        # a fraction k of the reciprocating mass at the crank pin, on the crank's extension
        Fk = np.stack([-2.5 * aB, np.zeros_like(aB)], -1) \
            - k * 2.5 * 0.05 * 20.0**2 * np.stack([np.cos(phi), np.sin(phi)], -1)
        assert np.max(np.abs(F - Fk)) <= 1e-5 * np.max(np.abs(Fk))
    fb = bal.force_balance(m, radii=0.05)
    assert not fb.full
    assert "slider" in fb.reason
    with pytest.raises(InfeasibleError) as exc:
        bal.force_balance(m, radii=0.05, require_full=True)
    assert "slider" in str(exc.value)
    del kin


# ---------------------------------------------------------------------------------------------
# 3. partial dynamic balancing (paper 001)


def normal_equations(phi, M, S, w):
    """The paper's two normal equations, written out (with the sin*cos sums kept)."""
    s, c = np.sin(phi), np.cos(phi)
    A = S * w**2 * np.array([[-np.sum(s * c), np.sum(c * c)],
                             [-np.sum(s * s), np.sum(s * c)]])
    b = np.array([-np.sum(M * c), -np.sum(M * s)])
    return np.linalg.lstsq(A, b, rcond=None)[0]


def test_axis_offset_exact_least_squares_for_any_positions():
    rng = np.random.default_rng(1)
    for _ in range(20):
        n = rng.integers(3, 15)
        phi = np.sort(rng.uniform(0, 2 * np.pi, n))
        M = rng.normal(0, 5, n)
        S, w = rng.uniform(0.05, 1), rng.uniform(1, 50)
        x, y = bal.counterweight_axis_offset(phi, M, S, w)
        assert np.allclose([x, y], normal_equations(phi, M, S, w), rtol=1e-9, atol=1e-12)
        # and it is the minimum: no neighbour of (x, y) does better

        def cost(xx, yy, phi=phi, M=M, S=S, w=w):
            return np.sum((M + S * w**2 * (yy * np.cos(phi) - xx * np.sin(phi))) ** 2)

        best = cost(x, y)
        for dx, dy in itertools.product((-1e-4, 0, 1e-4), repeat=2):
            assert cost(x + dx, y + dy) >= best - 1e-12 * max(best, 1.0)


def test_paper_formula_1_holds_only_when_sum_sin_cos_vanishes():
    rng = np.random.default_rng(2)
    M12 = rng.normal(0, 3, 12)
    even = np.radians(np.arange(0, 360, 30.0))
    lsq = bal.counterweight_axis_offset(even, M12, 0.2, 10.0)
    pap = bal.counterweight_axis_offset(even, M12, 0.2, 10.0, method="paper")
    assert np.allclose(lsq.offset, pap.offset, rtol=1e-12, atol=1e-15)
    half = np.radians(np.arange(0, 150, 30.0))[:5]  # 0..120 deg: sum sin cos != 0
    assert abs(np.sum(np.sin(half) * np.cos(half))) > 0.4
    M5 = M12[:5]
    lsq = bal.counterweight_axis_offset(half, M5, 0.2, 10.0)
    pap = bal.counterweight_axis_offset(half, M5, 0.2, 10.0, method="paper")
    assert np.allclose(lsq.offset, normal_equations(half, M5, 0.2, 10.0), rtol=1e-9)
    assert np.hypot(*(np.subtract(lsq.offset, pap.offset))) > 1e-3
    assert np.sum(lsq.residual**2) < np.sum(pap.residual**2)


def test_paper001_axis_offset_and_efficiency_from_the_printed_table():
    phi = np.radians(TABLE[:, 0])
    dM1 = TABLE[:, 2]
    # S = 0.2 kg m (the crank counterweight by hand above), omega = 10 1/s
    for method in ("lsq", "paper"):
        x, y = bal.counterweight_axis_offset(phi, dM1, 0.2, 10.0, method=method)
        assert round(x, 3) == -0.071
        assert round(y, 3) == 0.189
    assert round(bal.efficiency(TABLE[:, 2], TABLE[:, 3]), 1) == 36.9
    assert round(bal.efficiency(TABLE[:, 2], TABLE[:, 4]), 1) == 53.9
    # the printed formula (max|dM1| + max|dM2|)/max|dMj| does not give the printed numbers
    p1, p2 = (np.max(np.abs(TABLE[:, k])) for k in (2, 3))
    assert abs((p1 + p2) / p2 * 100 - 36.9) > 100


def test_moved_axis_moment_with_angular_acceleration_by_finite_differences():
    """The counterweight centre O1 + r(-cos phi, -sin phi) with phi(t) = phi0 + w t + e t^2/2:
    its inertia force by central differences in time, moment about O minus that with O1 = O,
    against counterweight_axis_moment (the eps term included)."""
    m_cw, r = 4.0, 0.05
    x, y = -0.07, 0.19
    phi0 = np.linspace(0, 2 * np.pi, 37)
    for w, e in ((10.0, 0.0), (10.0, 35.0), (-6.0, -80.0)):
        h = 1e-4

        def centre(t, ox, oy, w=w, e=e):
            p = phi0 + w * t + 0.5 * e * t * t
            return ox - r * np.cos(p), oy - r * np.sin(p)

        def moment(ox, oy, h=h):
            (xm, ym), (x0, y0), (xp, yp) = (centre(t, ox, oy) for t in (-h, 0.0, h))
            fx = -m_cw * (xp - 2 * x0 + xm) / h**2
            fy = -m_cw * (yp - 2 * y0 + ym) / h**2
            return x0 * fy - y0 * fx

        ref = moment(x, y) - moment(0.0, 0.0)
        got = bal.counterweight_axis_moment(phi0, x, y, m_cw * r, w, e)
        assert np.max(np.abs(got - ref)) <= 1e-5 * np.max(np.abs(ref))
        # and the least squares with eps != 0 still solves the normal equations exactly
        M = np.cos(2 * phi0) + 0.3 * np.sin(phi0)
        fit = bal.counterweight_axis_offset(phi0, M, m_cw * r, w, e)
        Bx = bal.counterweight_axis_moment(phi0, 1.0, 0.0, m_cw * r, w, e)
        By = bal.counterweight_axis_moment(phi0, 0.0, 1.0, m_cw * r, w, e)
        A = np.stack([Bx, By], -1)
        ref_xy = np.linalg.solve(A.T @ A, -A.T @ M)
        assert np.allclose(fit.offset, ref_xy, rtol=1e-9, atol=1e-12)


def test_first_harmonic_and_rms_offsets_over_a_cycle():
    phi = np.linspace(0, 2 * np.pi, 360, endpoint=False)
    M = 2.0 * np.cos(phi) - 1.0 * np.sin(phi) + 0.7 * np.cos(3 * phi)
    S, w = 0.2, 10.0
    fh = bal.first_harmonic_offset(phi, M, S, w)
    rm = bal.rms_offset(phi, M, S, w)
    # by hand: M_yp = S w^2 (y cos - x sin) cancels a1 cos + b1 sin: y = -a1/(Sw2), x = b1/(Sw2)
    assert np.allclose(fh.offset, (-1.0 / 20.0, -2.0 / 20.0), atol=1e-12)
    assert np.allclose(rm.offset, fh.offset, atol=1e-12)
    assert np.allclose(fh.residual, 0.7 * np.cos(3 * phi), atol=1e-12)


def test_compare_balancing_on_the_paper_fourbar_is_consistent():
    comp = bal.compare_balancing(paper_fourbar(), radii={"crank": 0.05, "rocker": 0.1})
    phi = np.radians(np.arange(0, 360, 30.0))
    assert np.allclose(comp.phi1, phi)
    # M: the engine's moment of the unbalanced mechanism about O
    d0 = inverse_dynamics(kinematics(paper_fourbar(), phi), about=(0, 0))
    assert np.allclose(comp.M, d0.shaking_m, atol=1e-9)
    # dM1: independent closed form of the force-balanced four-bar's moment (errata):
    # -[J_C eps3 + (I_S2 - m2 a b) eps2], J_C = I_S3 + m3 s3^2 + m_cw3 r3^2 + (m2 s2/l2) l3^2
    kin = kinematics(paper_fourbar(), phi)
    e2, e3 = kin.eps[kin.bodies.index("coupler")], kin.eps[kin.bodies.index("rocker")]
    JC = 0.00567 + 2 * 0.1**2 + 5 * 0.1**2 + 1.5 * 0.2**2
    ref = -(JC * e3 + (0.0225 - 3 * 0.15 * 0.15) * e2)
    assert np.allclose(comp.dM1, ref, atol=1e-9 * np.max(np.abs(ref)))
    # dM3 = dM1 + M_yp at the least-squares axis over the table (normal equations here)
    xy = normal_equations(phi, comp.dM1, 0.2, 10.0)
    assert np.allclose((comp.x3, comp.y3), xy, rtol=1e-9)
    myp = 0.2 * 100 * (xy[1] * np.cos(phi) - xy[0] * np.sin(phi))
    assert np.allclose(comp.dM3, comp.dM1 + myp, atol=1e-9)
    R3 = (np.max(np.abs(comp.dM1)) - np.max(np.abs(comp.dM3))) / np.max(np.abs(comp.dM1)) * 100
    assert comp.R3 == pytest.approx(R3, rel=1e-12)
    # balancing raises the driving torque and the bearing loads: reported
    inc = " ".join(comp.increases())
    assert "driving torque" in inc and "frame joint" in inc


# ---------------------------------------------------------------------------------------------
# 6. optimal balancing against a brute-force grid


def test_optimal_balance_not_worse_than_a_brute_force_grid():
    """Tiny problem: one counterweight (mass, radius, angle) on the crank only. The objective
    of a design is recomputed here with the engine (add_counterweights + inverse dynamics);
    the optimiser's design must be at least as good as the best of a grid."""
    from linkwork.balancing.optimal import BalancingProblem, optimal_balance

    mech = paper_fourbar()
    n = 72
    prob = BalancingProblem(mech, links=["crank"], n=n)
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    d0 = inverse_dynamics(kinematics(mech, phi), about=(0, 0))

    def engine_values(m, r, a):
        mb = bal.add_counterweights(mech, [bal.Counterweight.from_mass("crank", m, r, a)]) \
            if m > 0 else mech
        d = inverse_dynamics(kinematics(mb, phi), about=(0, 0))
        F = np.hypot(d.shaking_fx, d.shaking_fy)
        Q = d.Q - d.Q.mean()
        return np.sqrt(np.mean(F**2)), np.sqrt(np.mean(d.shaking_m**2)), np.sqrt(np.mean(Q**2))

    ref = np.array(engine_values(0.0, 0.1, 0.0))
    assert np.allclose(ref, [np.sqrt(np.mean(d0.shaking_fx**2 + d0.shaking_fy**2)),
                             np.sqrt(np.mean(d0.shaking_m**2)),
                             np.sqrt(np.mean((d0.Q - d0.Q.mean()) ** 2))])
    # the superposition used by the optimiser equals the engine at a few designs
    for des in ((2.0, 0.1, 3.0), (6.0, 0.04, -1.0)):
        assert np.allclose(prob.evaluate(des), engine_values(*des), rtol=1e-9)
    wts = np.array([1.0, 1.0, 1.0])
    opt = optimal_balance(prob, wts, mass=(0.0, 8.0), radius=(0.02, 0.15))
    cw = opt.counterweights[0]
    got = wts @ (np.array(engine_values(cw.mass(), cw.radius, cw.angle)) / ref)
    assert got == pytest.approx(opt.objective, rel=1e-9)
    best = np.inf
    for m in np.linspace(0.0, 8.0, 17):
        for r in np.linspace(0.02, 0.15, 6):
            for a in np.linspace(-np.pi, np.pi, 24, endpoint=False):
                best = min(best, wts @ (np.array(prob.evaluate((m, r, a))) / ref))
    assert got <= best + 1e-9


def test_pareto_set_flags_dominated_designs_correctly():
    from linkwork.balancing.optimal import pareto_set

    p = pareto_set(paper_fourbar(), n=72, weights=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1],
                                                            [1, 1, 1], [1, 1, 0]], float))
    V = np.stack([p.force_rms, p.moment_rms, p.torque_fluct], -1)
    for i in range(len(V)):
        dom = any(np.all(V[j] <= V[i] + 1e-12) and np.any(V[j] < V[i] - 1e-9)
                  for j in range(len(V)) if j != i)
        assert bool(p.dominated[i]) == dom


# ---------------------------------------------------------------------------------------------
# failure policy: functions


@pytest.mark.parametrize("call, name", [
    (lambda: bal.fourbar_counterweights(0.1, 0.3, 0.2, -1.0, 0.05, 3, 0.15, 2, 0.1), "m1"),
    (lambda: bal.fourbar_counterweights(0.0, 0.3, 0.2, 1.0, 0.05, 3, 0.15, 2, 0.1), "l1"),
    (lambda: bal.crank_slider_counterweight(0.05, 0.2, 1, 0.02, 2, 0.1, 1, fraction=1.5),
     "fraction"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, 2, 3], 0.0, 10.0), "static_moment"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, 2, 3], -0.2, 10.0), "static_moment"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, 2], 0.2, 10.0), "moment"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, np.nan, 3], 0.2, 10.0), "moment"),
    (lambda: bal.counterweight_axis_offset([0.5], [1.0], 0.2, 10.0), "phi"),
    (lambda: bal.counterweight_axis_offset([0.5, 0.5 + np.pi], [1.0, 2.0], 0.2, 10.0), "phi"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, 2, 3], 0.2, 10.0, method="x"),
     "method"),
    (lambda: bal.counterweight_axis_offset([0, 1, 2], [1, 2, 3], 0.2, 0.0), "omega"),
    (lambda: bal.efficiency([0.0, 0.0], [1.0, 2.0]), "before"),
    (lambda: bal.efficiency([], [1.0]), "before"),
    (lambda: bal.Counterweight.from_mass("crank", -1.0, 0.05, 0.0), "mass"),
    (lambda: bal.Counterweight("crank", 0.2, 0.0, radius=0.0), "radius"),
    (lambda: bal.harmonics(np.linspace(0, 6, 10), np.ones(10), k=0), "k"),
    (lambda: bal.force_balance(paper_fourbar(), links=["coupler"]), "counterweight.link"),
    (lambda: bal.force_balance(paper_fourbar(), links=["nope"]), "nope"),
])
def test_bad_inputs_are_named(call, name):
    with pytest.raises(LinkworkError) as exc:
        call()
    assert name in str(exc.value)


def test_zero_speed_comparison_is_refused():
    with pytest.raises(ParameterError, match="omega"):
        bal.compare_balancing(fourbar(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2), omega1=0.0))


# ---------------------------------------------------------------------------------------------
# 4. command line


def test_cli_balance_bundled_example(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["balance", str(EXAMPLE), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    for f in ("balance_table.csv", "balance_table.json", "balance_cycle.csv",
              "balance_summary.json", "balancing_moments.png", "balancing_force.png",
              "balancing_torque.png", "balancing_bearings.png"):
        assert (out / f).stat().st_size > 0
    assert "R_j" in text and "φ1 [deg]" in text
    assert "S = 0.2 kg*m" in text and "S = 0.5 kg*m" in text


def _write(tmp_path, text, name="m.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


BROKEN_BALANCE = {
    "unknown_key": "[balance]\nlinx = ['crank']\n",
    "radius_units": "[balance]\nradii = { crank = '50 kg' }\n",
    "radius_negative": "[balance]\nradii = { crank = '-50 mm' }\n",
    "radius_zero": "[balance]\nradii = '0 mm'\n",
    "not_hinged": "[balance]\nlinks = ['coupler']\n",
    "unknown_link": "[balance]\nlinks = ['crnak']\n",
    "no_crank": "[balance]\nlinks = ['rocker']\n",
    "n_small": "[balance]\nn = 5\n",
    "angles_text": "[balance]\nangles = ['a']\n",
    "angles_nan": "[balance]\nangles = [nan]\n",
    "balance_not_table": "balance = 3\n",
}


@pytest.mark.parametrize("case", sorted(BROKEN_BALANCE))
def test_cli_balance_broken_files_one_line_exit_2(tmp_path, capsys, case):
    text = EXAMPLE.read_text() + "\n" + BROKEN_BALANCE[case]
    f = _write(tmp_path, text)
    rc = main(["balance", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err


@pytest.mark.parametrize("args", [
    ["balance", "/nonexistent/x.toml"],
    ["balance", str(EXAMPLE), "--angles", "a,b"],
    ["balance", str(EXAMPLE), "--angles", ","],
    ["balance", str(EXAMPLE), "--bogus"],
])
def test_cli_balance_bad_arguments_one_line_exit_2(tmp_path, capsys, args):
    rc = main([*args, "--out", str(tmp_path / "o")] if "--bogus" not in args else args)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("text", [
    "type = 'planar'\n[frame\n",                                     # invalid TOML
    "type = 'sine'\nname = 'x'\n",                                   # not a planar file
])
def test_cli_balance_broken_toml_one_line_exit_2(tmp_path, capsys, text):
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err


def test_cli_balance_wrong_units_in_the_mechanism(tmp_path, capsys):
    text = EXAMPLE.read_text().replace('mass = "3 kg"', 'mass = "3 m"')
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "mass" in err


def test_axis_offset_at_zero_speed_names_omega():
    """omega = 0 (and eps = 0): the lsq path named 'phi' ('positions that determine (x, y)'),
    the paper's formula divided by zero (RuntimeWarning, inf)."""
    for method in ("lsq", "paper"):
        with pytest.raises(ParameterError) as exc:
            bal.counterweight_axis_offset([0.0, 1.0, 2.0], [1.0, 2.0, 3.0], 0.2, 0.0,
                                          method=method)
        assert exc.value.parameter == "omega"
    with pytest.raises(ParameterError) as exc:
        bal.first_harmonic_offset(np.linspace(0, 6, 12), np.ones(12), 0.2, 0.0)
    assert exc.value.parameter == "omega"
    # eps alone determines the axis: accepted
    r = bal.counterweight_axis_offset([0.0, 1.0, 2.0], [1.0, 2.0, 3.0], 0.2, 0.0, 5.0)
    assert np.all(np.isfinite(r.offset))


@pytest.mark.parametrize("radii, words", [
    ("{ crank = '50 kg' }", ["balance.radii", "crank", "length"]),
    ("'0 mm'", ["balance.radii", "> 0"]),
    ("{ crank = '-5 mm', rocker = 0.1 }", ["balance.radii", "crank", "> 0"]),
    ("true", ["balance.radii", "length"]),
])
def test_cli_balance_bad_radii_named_plainly(tmp_path, capsys, radii, words):
    """The error named pydantic's internal union types
    ('balance.radii.dict[str,function-before[convert(), float]].crank'), a zero radius was
    reported without the file or key ('radius = 0 is invalid'), 'true' was taken as 1 m."""
    text = EXAMPLE.read_text() + f"\n[balance]\nradii = {radii}\n"
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "function-before" not in err and "dict[" not in err
    for w in words:
        assert w in err


@pytest.mark.parametrize("angles", ["90", "30,210"])
def test_cli_balance_table_positions_that_cannot_fit_the_axis(tmp_path, capsys, angles):
    """One table angle (or two half a turn apart) cannot determine (x, y): the error named
    'phi = 1 positions', a parameter the user never gave; now it names the positions."""
    rc = main(["balance", str(EXAMPLE), "--angles", angles, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "positions" in err and "phi =" not in err


def test_force_hodograph_shows_the_balanced_variant_and_closes_the_cycle():
    """The statically balanced hodograph (|F| ~ 1e-14 N) was a line of zero length: listed in
    the legend, invisible on the plot; the unbalanced one had a gap between the last sample
    and the first."""
    from linkwork.plot.balancing import plot_force_hodograph

    phi = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    F0 = np.stack([40 * np.cos(phi), 20 * np.sin(phi)], -1)
    F1 = 1e-14 * F0
    out = plot_force_hodograph({"unbalanced": F0, "static": F1})
    ax = out["ax"]
    ends = {(tuple(np.round(ln.get_xydata()[0], 9)), tuple(np.round(ln.get_xydata()[-1], 9)))
            for ln in ax.get_lines()}
    assert ((tuple(np.round(F0[-1], 9)), tuple(np.round(F0[0], 9)))) in ends
    line = out["static"]
    assert line.get_marker() not in ("None", "", None, " ")
    assert "static" in line.get_label()
    import matplotlib.pyplot as plt

    plt.close(out["ax"].figure)


def test_pareto_plot_separates_dominated_designs():
    """balancing_pareto.png drew dominated and non-dominated designs alike (e.g. the design at
    F = 0, M = 5.75 N m beaten by the static one), although pareto_set flags them."""
    from linkwork.plot import pyplot
    from linkwork.plot.balancing import plot_pareto

    out = plot_pareto([0.0, 1.0, 2.0], [2.0, 1.0, 3.0], [1.0, 1.0, 2.0],
                      dominated=[False, False, True])
    assert out["pareto"].get_offsets().shape[0] == 2
    assert np.allclose(out["dominated"].get_offsets(), [[2.0, 3.0]])
    pyplot().close("all")


def test_increases_ignore_round_off():
    """On a mechanism whose shaking moment about O vanishes (the sine press: every centre on a
    line through O or on the guide), 'balancing raises: shaking moment peak: static 1.776e-15 vs
    unbalanced 8.882e-16 (+100.0 %)' was reported."""
    from linkwork.cli.balance import load_balance_file

    mech, _, _ = load_balance_file(ROOT / "examples" / "sine_press_planar.toml")
    comp = bal.compare_balancing(mech, n=72)
    assert peak_of(comp, "shaking moment peak [N*m]") < 1e-12
    assert not [m for m in comp.increases() if "shaking moment" in m]
    # a real increase is still reported (paper four-bar: the moment grows by static balancing)
    comp = bal.compare_balancing(paper_fourbar(), radii={"crank": 0.05, "rocker": 0.1}, n=72)
    assert [m for m in comp.increases() if m.startswith("shaking moment peak")]


def peak_of(comp, key):
    return max(comp.summary()[key].values())


def test_cli_cycle_csv_has_shaking_force_and_bearing_reactions(tmp_path, capsys):
    """balance_cycle.csv had only M, dM1..3, Q0, Q1: the shaking force before/after and the
    frame-bearing reactions (which the command reports as raised) were in no output file."""
    import csv

    out = tmp_path / "o"
    assert main(["balance", str(EXAMPLE), "--out", str(out)]) == 0
    capsys.readouterr()
    with (out / "balance_cycle.csv").open() as fh:
        rows = list(csv.reader(fh))
    head, data = rows[0], np.array(rows[1:], float)
    for col in ("Fx0 [N]", "Fy0 [N]", "Fx1 [N]", "Fy1 [N]", "R0_O [N]", "R1_C [N]", "R3_O [N]",
                "R3_O1 [N]", "Q1 [N*m]", "phi1 [rad]"):
        assert col in head, head
    # independent: the engine's shaking force and reaction at C of the unbalanced mechanism
    phi = data[:, head.index("phi1 [rad]")]
    mech = paper_fourbar()
    d = inverse_dynamics(kinematics(mech, phi), about=(0, 0))
    assert np.allclose(data[:, head.index("Fx0 [N]")], d.shaking_fx, rtol=1e-9, atol=1e-9)
    i = [j.name for j in mech.joints][3]  # O4 = C of the example
    assert np.allclose(data[:, head.index("R0_C [N]")], d.reaction_magnitude(i), rtol=1e-9)
    assert np.max(np.abs(data[:, head.index("Fx1 [N]")])) < 1e-9


def test_cli_balance_negative_mass_is_short_and_keyed(tmp_path, capsys):
    text = EXAMPLE.read_text().replace('mass = "3 kg"', 'mass = "-3 kg"')
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1
    assert "coupler.mass" in err and len(err) < 300
