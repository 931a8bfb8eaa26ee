"""Force balancing and shaking loads on planar-engine mechanisms."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _balancing_cases import com_positions
from _balancing_cases import paper_fourbar as paper001_fourbar
from _mechanisms import _rates
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork import balancing as bal
from linkwork.balancing import moment_about
from linkwork.balancing.mechanism import (
    add_counterweights,
    cycle,
    force_balance,
    frame_hinged_links,
    shaking_loads,
)
from linkwork.balancing.static import (
    Counterweight,
    crank_slider_counterweight,
    fourbar_counterweights,
)
from linkwork.errors import InfeasibleError, LinkworkError, ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import crank_slider_mechanism, fourbar_mechanism

PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)


def paper_fourbar(branch=1):
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=branch, **PAPER)


def fd_fourbar_shaking(l, masses, coms, inertias, omega, phi, branch):
    """Independent: plain-trig four-bar positions, accelerations by central differences in
    time, shaking force and moment about O summed link by link."""
    l1, l2, l3, l0 = l
    h = 1e-4

    def pose(t):
        th1 = phi + omega * t
        A = l1 * np.exp(1j * th1)
        AC = l0 - A
        L = np.abs(AC)
        th2 = np.angle(AC) + branch * np.arccos((l2**2 + L**2 - l3**2) / (2 * l2 * L))
        B = A + l2 * np.exp(1j * th2)
        th3 = np.angle(B - l0)
        S = [coms[0] * np.exp(1j * th1), A + coms[1] * np.exp(1j * th2),
             l0 + coms[2] * np.exp(1j * th3)]
        return S, [th1, th2, th3]

    (Sm, Tm), (S0, T0), (Sp, Tp) = pose(-h), pose(0.0), pose(h)
    F = np.zeros_like(phi, dtype=complex)
    M = np.zeros_like(phi)
    for k in range(3):
        a = (Sp[k] - 2 * S0[k] + Sm[k]) / h**2
        eps = (np.angle(np.exp(1j * (Tp[k] - T0[k]))) - np.angle(np.exp(1j * (T0[k] - Tm[k])))
               ) / h**2
        f = -masses[k] * a
        F += f
        M += (S0[k].real * f.imag - S0[k].imag * f.real) - inertias[k] * eps
    return F, M


@pytest.mark.parametrize("branch", [1, -1])
def test_shaking_loads_match_independent_finite_differences(branch):
    phi = cycle(24)
    sl = shaking_loads(kinematics(paper_fourbar(branch), phi))
    F, M = fd_fourbar_shaking((0.1, 0.3, 0.2, 0.3), PAPER["masses"], PAPER["coms"],
                              PAPER["inertias"], 10.0, phi, branch)
    scale = np.abs(F).max()
    np.testing.assert_allclose(sl.fx, F.real, atol=1e-5 * scale)
    np.testing.assert_allclose(sl.fy, F.imag, atol=1e-5 * scale)
    np.testing.assert_allclose(sl.moment, M, atol=1e-5 * np.abs(M).max())


def test_shaking_moment_about_any_point_consistent():
    phi = cycle(36)
    kin = kinematics(paper_fourbar(), phi)
    P = (0.15, -0.2)
    a, b = shaking_loads(kin), shaking_loads(kin, P)
    np.testing.assert_allclose(b.moment, moment_about(a.moment, a.force, P), atol=1e-12)
    # mean over the cycle of -dH/dt is zero (steady motion)
    assert abs(a.moment.mean()) < 1e-9 * a.moment_peak()


@pytest.mark.parametrize("branch", [1, -1])
def test_paper001_static_balance_zero_shaking_force(branch):
    """Reference: paper 001. Tolerance: < 1e-9 * before.force_peak(), rel=1e-10, abs=1e-12."""
    mech = paper_fourbar(branch)
    fb = force_balance(mech, radii={"crank": 0.05, "rocker": 0.1})
    assert fb.full
    ref = fourbar_counterweights(0.1, 0.3, 0.2, 1.0, 0.05, 3.0, 0.15, 2.0, 0.1)
    for got, exp in zip(fb.counterweights, ref, strict=True):
        assert got.link == exp.link
        assert got.static_moment == pytest.approx(exp.static_moment, rel=1e-10)
        assert np.cos(got.angle - exp.angle) == pytest.approx(1.0, abs=1e-12)
    assert fb.counterweights[0].mass() == pytest.approx(4.0)
    assert fb.counterweights[1].mass() == pytest.approx(5.0)
    phi = cycle(720, 0.0123)
    before = shaking_loads(kinematics(mech, phi))
    after = shaking_loads(kinematics(fb.mechanism, phi))
    assert after.force_peak() <= 1e-9 * before.force_peak()


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([1, -1]))
def test_general_force_balance_equals_berkof_lowen(seed, branch):
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.05, 0.1)
    b, c, d = rng.uniform(0.25, 0.4, 3)
    masses = tuple(rng.uniform(0.5, 3, 3))
    coms = tuple(tuple(rng.normal(0, 0.08, 2)) for _ in range(3))
    mech = fourbar_mechanism(a, b, c, d, masses=masses, coms=coms, omega1=7.0, branch=branch)
    fb = force_balance(mech, n=90)
    assert fb.full
    ref = fourbar_counterweights(a, b, c, *(v for mk, ck in zip(masses, coms, strict=True)
                                           for v in (mk, complex(*ck))))
    for got, exp in zip(fb.counterweights, ref, strict=True):
        assert abs(got.first_moment - exp.first_moment) < 1e-9 * (1 + abs(exp.first_moment))
    phi = cycle(200, 0.3)
    before = shaking_loads(kinematics(mech, phi))
    after = shaking_loads(kinematics(fb.mechanism, phi))
    assert after.force_peak() <= 1e-9 * before.force_peak()


def test_crank_slider_cannot_be_fully_force_balanced():
    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 2.0, 3.0), omega1=10.0)
    assert frame_hinged_links(mech) == ("crank",)
    fb = force_balance(mech)
    assert not fb.full
    assert "slider" in fb.reason
    # best RMS: rotating masses plus half the reciprocating mass (m3 + m2/2) at the pin
    expected = crank_slider_counterweight(0.05, 0.2, 1.0, 0.025, 2.0, 0.1, 3.0, fraction=0.5)
    assert fb.counterweights[0].static_moment == pytest.approx(expected.static_moment, rel=2e-3)
    with pytest.raises(InfeasibleError, match="frame-hinged"):
        force_balance(mech, require_full=True)


@pytest.mark.parametrize("k", [0.0, 1.0])
def test_crank_slider_fraction_on_engine(k):
    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 2.0, 3.0), omega1=10.0)
    cw = crank_slider_counterweight(0.05, 0.2, 1.0, 0.025, 2.0, 0.1, 3.0, fraction=k)
    bal = add_counterweights(mech, [cw.with_radius(0.04)])
    phi = cycle(360)
    sl = shaking_loads(kinematics(bal, phi))
    m_rec = 3.0 + 2.0 * 0.5
    np.testing.assert_allclose(sl.fy, -k * m_rec * 0.05 * 100 * np.sin(phi), atol=1e-9)
    a1 = 2 * np.mean(sl.fx * np.cos(phi))
    assert a1 == pytest.approx((1 - k) * m_rec * 0.05 * 100, abs=1e-9)


def test_add_counterweights_mass_properties():
    mech = paper_fourbar()
    cw = Counterweight.from_mass("rocker", 5.0, 0.1, np.pi, inertia=0.001)
    bal = add_counterweights(mech, [cw])
    r0, r1 = mech.body("rocker"), bal.body("rocker")
    assert r1.mass == pytest.approx(7.0)
    # first moment about the hinge O4 (local origin): 2*0.1 - 5*0.1 = -0.3
    assert r1.mass * r1.com[0] == pytest.approx(-0.3)
    assert r1.com[1] == pytest.approx(0.0, abs=1e-15)
    # inertia about the hinge: I_S + m*0.1^2 + I_cw + 5*0.1^2
    J_hinge = r1.inertia + r1.mass * (r1.com[0] ** 2 + r1.com[1] ** 2)
    assert J_hinge == pytest.approx(r0.inertia + 2 * 0.01 + 0.001 + 5 * 0.01)
    assert bal.body("coupler") == mech.body("coupler")
    with pytest.raises(ParameterError, match="hinged to the frame"):
        add_counterweights(mech, [Counterweight("coupler", 0.1, 0.0, 0.05)])
    with pytest.raises(ParameterError, match="radius"):
        add_counterweights(mech, [Counterweight("crank", 0.1, 0.0)])


def test_crank_slider_shaking_force_harmonics_classic_series():
    """Slider mass only: F_x = m3 a w^2 [cos p + A2 cos 2p - A4 cos 4p + ...] with
    A2 = l + l^3/4 + 15 l^5/128, A4 = l^3/4 + 3 l^5/16 (l = a/L; series to l^5)."""
    from linkwork.balancing import harmonics

    a, L, m3, w = 0.05, 0.2, 3.0, 10.0
    lam = a / L
    mech = crank_slider_mechanism(a, L, masses=(0.0, 0.0, m3), omega1=w)
    phi = cycle(256)
    sl = shaking_loads(kinematics(mech, phi))
    h = harmonics(phi, sl.fx, 4)
    scale = m3 * a * w**2
    A2 = lam + lam**3 / 4 + 15 * lam**5 / 128
    A4 = lam**3 / 4 + 3 * lam**5 / 16
    np.testing.assert_allclose(h.cos / scale, [1.0, A2, 0.0, -A4], atol=5e-5)
    np.testing.assert_allclose(h.sin / scale, 0.0, atol=1e-12)
    assert abs(h.mean) < 1e-9 * scale
    np.testing.assert_allclose(sl.fy, 0.0, atol=1e-9 * scale)


def watt_sixbar():
    from linkwork.planar.model import Body, Crank, Mechanism, Revolute, bar

    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0), "E": (0.55, 0.25)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    coupler = bar("coupler", "A", "B", 0.3, mass=3.0, com=(0.12, 0.03))
    rocker = Body("rocker", {"C": (0, 0), "B": (0.2, 0), "D": (0.1, 0.12)}, mass=2.5,
                  com=(0.1, 0.04), inertia=0.01)
    link4 = bar("link4", "D", "F", 0.3, mass=1.5)
    output = bar("output", "E", "F", 0.2, mass=1.2)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("C", "frame", "rocker"),
              Revolute("D", "rocker", "link4"), Revolute("F", "link4", "output"),
              Revolute("E", "frame", "output"))
    return Mechanism(frame, (crank, coupler, rocker, link4, output), joints, Crank("O", 10.0))


def test_watt_sixbar_full_force_balance_by_successive_loops():
    """Watt six-bar: eliminating link4 through loop C-D-F-E and the coupler through loop
    O-A-B-C (by hand, complex local first moments) gives the three counterweights; the
    general least squares finds the same and the engine's shaking force vanishes."""
    mech = watt_sixbar()
    d_D = 0.1 + 0.12j
    s2, l2, l3 = 0.12 + 0.03j, 0.3, 0.2
    q1 = -(1.0 * 0.05 + 3.0 * 0.1 * (1 - s2 / l2))
    q3 = -(2.5 * (0.1 + 0.04j) + 3.0 * s2 * l3 / l2 + 1.5 * d_D * (1 - 0.15 / 0.3))
    q5 = -(1.2 * 0.1 + 1.5 * 0.15 * 0.2 / 0.3)
    fb = force_balance(mech, n=120)
    assert fb.full
    got = {c.link: c.first_moment for c in fb.counterweights}
    for link, q in (("crank", q1), ("rocker", q3), ("output", q5)):
        assert abs(got[link] - q) < 1e-9
    phi = cycle(360, 0.01)
    before = shaking_loads(kinematics(mech, phi))
    after = shaking_loads(kinematics(fb.mechanism, phi))
    assert after.force_peak() <= 1e-9 * before.force_peak()


def test_sixbar_not_balanceable_without_the_middle_rocker():
    """Without a counterweight on the rocker the coupler's and link4's first moments keep a
    part that rotates with the rocker: no full balance; best RMS and the reason are given."""
    fb = force_balance(watt_sixbar(), links=["crank", "output"], n=120)
    assert not fb.full
    assert 0.01 < fb.ratio < 1.0
    assert "['crank', 'output']" in fb.reason
    assert "without a counterweight: ['rocker']" in fb.reason


@pytest.mark.parametrize("omega1, eps1", [(3.0, 0.0), (25.0, 80.0), (-7.0, -30.0)])
def test_force_balance_holds_at_any_speed_and_acceleration(omega1, eps1):
    """Force balance is a property of the mass distribution (stationary centre of mass), so the
    counterweights found at 10 rad/s also balance at other speeds and crank accelerations."""
    fb = force_balance(paper_fourbar(), radii={"crank": 0.05, "rocker": 0.1})
    phi = cycle(90, 0.2)
    before = shaking_loads(kinematics(paper_fourbar(), phi, omega1, eps1))
    after = shaking_loads(kinematics(fb.mechanism, phi, omega1, eps1))
    assert after.force_peak() <= 1e-9 * before.force_peak()


@pytest.mark.parametrize("guide_angle, e", [(0.0, 0.0), (np.pi / 2, 0.0)])
def test_crank_slider_balance_half_fraction_is_best_rms(guide_angle, e):
    """k = 0.5 of the reciprocating mass is what the general least squares finds (centred
    crank-slider, any guide direction); k = 0 leaves only the reciprocating force along the
    guide."""
    from linkwork.balancing import crank_slider_balance

    mech = crank_slider_mechanism(0.05, 0.2, e, guide_angle=guide_angle, masses=(1.0, 2.0, 3.0),
                        omega1=10.0)
    half = crank_slider_balance(mech, 0.5, radius=0.04)
    ls = force_balance(mech, radii=0.04, n=360)
    assert half.body("crank").com == pytest.approx(ls.mechanism.body("crank").com, abs=1e-12)
    zero = crank_slider_balance(mech, 0.0)
    phi = cycle(180)
    sl = shaking_loads(kinematics(zero, phi))
    u = np.array([np.cos(guide_angle), np.sin(guide_angle)])
    across = sl.force @ np.array([-u[1], u[0]])
    assert np.abs(across).max() < 1e-9 * np.abs(sl.force).max()


def test_force_balance_does_not_depend_on_driver_speed():
    a = force_balance(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **{**PAPER, "omega1": 0.0}))
    b = force_balance(paper_fourbar())
    assert a.full and b.full
    for ca, cb in zip(a.counterweights, b.counterweights, strict=True):
        assert ca.first_moment == pytest.approx(cb.first_moment, abs=1e-12)


def test_shaking_loads_equal_engine_inverse_dynamics():
    """Inertia-force sums (shaking_loads) = frame-joint reactions plus motor reaction summed by
    the engine's inverse dynamics (a different route: Lagrange multipliers)."""
    from linkwork.planar.dynamics import inverse_dynamics

    for mech in (paper_fourbar(-1), watt_sixbar(),
                 crank_slider_mechanism(0.05, 0.2, 0.01, masses=(1.0, 2.0, 3.0), omega1=10.0)):
        kin = kinematics(mech, cycle(60))
        P = (0.07, -0.03)
        sl = shaking_loads(kin, P)
        d = inverse_dynamics(kin, about=P)
        scale = np.abs(sl.force).max()
        np.testing.assert_allclose(sl.fx, d.shaking_fx, atol=1e-9 * scale)
        np.testing.assert_allclose(sl.fy, d.shaking_fy, atol=1e-9 * scale)
        np.testing.assert_allclose(sl.moment, d.shaking_m, atol=1e-9 * np.abs(sl.moment).max())


def test_force_balance_radius_for_an_unknown_link_is_named():
    """A radius keyed by a misspelt link was silently ignored (the default radius was used)."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    with pytest.raises(ParameterError) as err:
        bal.force_balance(mech, radii={"crnk": 0.05, "rocker": 0.1})
    assert "radii" in str(err.value) and "crnk" in str(err.value)
    assert "crank" in str(err.value)  # the links that do carry counterweights
    # the correctly spelt table is used as given
    fb = bal.force_balance(mech, radii={"crank": 0.05, "rocker": 0.1})
    assert [c.radius for c in fb.counterweights] == [0.05, 0.1]


def test_inclined_offset_crank_slider_rotating_balance_leaves_only_the_guide_force():
    """Crank-slider with a guide at 35 deg and 30 mm offset, crank centre off its line: after
    crank_slider_balance(k) only the reciprocating mass m3 + m2 s2/l2 (slider acceleration a_B
    from its position written out here) and the over-balance k of it rotating with the crank
    remain: across the guide -k r w^2 m_rec sin(phi - gamma) (0 for k = 0, to 1e-9 of the
    unbalanced force)."""
    from linkwork.planar import inverse_dynamics, kinematics
    from linkwork.planar.model import crank_slider_mechanism

    r, l, ecc, gam, w = 0.05, 0.2, 0.03, np.radians(35.0), 30.0
    m = crank_slider_mechanism(r, l, ecc, guide_angle=gam, masses=(2.0, 3.0, 4.0),
                     coms=((0.02, 0.01), 0.08), omega1=w)
    u, nrm = np.array([np.cos(gam), np.sin(gam)]), np.array([-np.sin(gam), np.cos(gam)])
    phi = bal.cycle(72)
    F0 = inverse_dynamics(kinematics(m, phi)).shaking_fx
    m_rec = 4.0 + 3.0 * 0.08 / l

    def slide(p):  # slider position along the guide, B = ecc n + s u, |B - A| = l
        A = r * np.array([np.cos(p), np.sin(p)])
        b = (ecc * nrm - A) @ u
        return -b + np.sqrt(b * b - ((ecc * nrm - A) @ (ecc * nrm - A) - l * l))

    aB = np.array([_rates(slide, p)[2] * w**2 for p in phi])
    for k in (0.0, 0.5, 1.0):
        d = inverse_dynamics(kinematics(bal.crank_slider_balance(m, k, radius=0.04), phi))
        F = np.stack([d.shaking_fx, d.shaking_fy], -1)
        # the counterweight's extra first moment -k l1 m_rec e^(i phi) adds the rotating force
        # -k r w^2 m_rec e^(i phi): across the guide it is all there is
        across_expected = -k * r * w**2 * m_rec * np.sin(phi - gam)
        assert np.max(np.abs(F @ nrm - across_expected)) <= 1e-9 * np.max(np.abs(F0))
        along_expected = -m_rec * aB - k * r * w**2 * m_rec * np.cos(phi - gam)
        assert np.max(np.abs(F @ u - along_expected)) <= 1e-5 * np.max(np.abs(F0))


def test_force_balance_of_a_fourbar_whose_body_frames_are_off_the_links():
    """Bodies given by arbitrary local points (origins off the hinges, x axes not along the
    links), frame not along x: full force balance, the shaking force of the balanced
    mechanism <= 1e-9 of the unbalanced one under a varying crank speed with eps1 != 0."""
    from linkwork.planar import Body, Crank, Mechanism, Revolute, inverse_dynamics, kinematics

    m = Mechanism(
        Body("ground", {"P": (0.1, 0.2), "Q": (0.35, 0.05)}),
        (Body("crank", {"P": (0.01, 0.02), "A": (0.06, 0.1)}, mass=1.2, com=(0.0, 0.05),
              inertia=0.002),
         Body("coupler", {"A": (0.0, 0.0), "B": (-0.05, 0.3)}, mass=2.5, com=(0.03, 0.12),
              inertia=0.02),
         Body("rocker", {"B": (0.1, -0.2), "Q": (0.0, 0.0)}, mass=1.7, com=(0.07, -0.05),
              inertia=0.01)),
        (Revolute("P", "ground", "crank"), Revolute("A", "crank", "coupler"),
         Revolute("B", "rocker", "coupler"), Revolute("Q", "rocker", "ground")),
        Crank("P", omega1=12.0))
    fb = bal.force_balance(m)
    assert fb.full and fb.reason == ""
    phi = bal.cycle(360)
    w, e = 12 * (1 + 0.3 * np.cos(phi)), 5.0 * np.sin(phi)
    before = inverse_dynamics(kinematics(m, phi, w, e))
    after = inverse_dynamics(kinematics(fb.mechanism, phi, w, e))
    f0 = np.hypot(before.shaking_fx, before.shaking_fy).max()
    assert f0 > 10.0
    assert np.hypot(after.shaking_fx, after.shaking_fy).max() <= 1e-9 * f0


@pytest.mark.parametrize("branch", [1, -1])
def test_shaking_force_and_moment_are_minus_rates_of_momentum(branch):
    """F = -dp/dt and M_P = -dH_P/dt, p and H from the engine's *positions* only, time
    derivatives by central differences (constant omega: d/dt = omega d/dphi)."""
    mech = paper001_fourbar(branch)
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


def test_force_balance_random_fourbars_with_off_line_centres():
    rng = np.random.default_rng(4)
    phi = np.linspace(0, 2 * np.pi, 180, endpoint=False)
    done = 0
    while done < 5:
        a, b, c, d = rng.uniform(0.5, 2.0, 4)
        a = 0.3 * min(b, c, d)  # a Grashof crank
        coms = tuple(complex(*rng.uniform(-0.3, 0.7, 2)) * L for L in (a, b, c))
        try:
            mech = fourbar_mechanism(a, b, c, d, masses=tuple(rng.uniform(0.5, 3, 3)), coms=tuple(
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
    m = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 2.0, 1.5), omega1=20.0)
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
    (lambda: bal.force_balance(paper001_fourbar(), links=["coupler"]), "counterweight.link"),
    (lambda: bal.force_balance(paper001_fourbar(), links=["nope"]), "nope"),
])
def test_bad_inputs_are_named(call, name):
    with pytest.raises(LinkworkError) as exc:
        call()
    assert name in str(exc.value)


# -- several drivers: the centre of mass kept still along the drivers' path --------------------

FIVE_BAR = Path(__file__).resolve().parents[1] / "data" / "drivers" / "five_bar_two_cranks.toml"


def _five_bar(massless_couplers=False):
    import dataclasses

    from linkwork import io

    doc = io.load(FIVE_BAR)
    mech = doc.mechanism()
    if massless_couplers:
        mech = dataclasses.replace(mech, bodies=tuple(
            dataclasses.replace(b, mass=0.0, inertia=0.0) if b.name in ("l1", "l2") else b
            for b in mech.bodies))
    return doc, mech


def _first_moment(mech, kin):
    return sum(b.mass * np.stack([kin.point(b.name, "com").x, kin.point(b.name, "com").y])
               for b in mech.bodies)


def test_centre_of_mass_balance_of_two_cranks_by_hand():
    """Two cranks (1 kg, centres at their midpoints) with massless couplers: each crank's
    counterweight is its own static moment m r opposite its centre (S = 1 kg x 41.2 mm and
    50.2 mm at 180 deg), the balance is full; the balanced mechanism's shaking force vanishes
    at the path's speeds (1e-9 of the unbalanced) and, the centre of mass being still, gravity
    loads neither driver: Q with and without gravity equal (1e-9)."""
    from linkwork.balancing.mechanism import centre_of_mass_balance

    doc, mech = _five_bar(massless_couplers=True)
    phi = doc.positions()
    kin = kinematics(mech, phi)
    fb = centre_of_mass_balance(kin)
    assert fb.full and fb.ratio <= 1e-9
    for cw, body in zip(fb.counterweights, ("c1", "c2"), strict=True):
        b = mech.body(body)
        assert cw.link == body
        assert cw.static_moment == pytest.approx(b.mass * np.hypot(*b.com), rel=1e-12)
        assert abs(np.cos(cw.angle) + 1.0) <= 1e-12  # opposite the crank's centre
    kb = kinematics(fb.mechanism, phi)
    d0 = inverse_dynamics(kb)
    dg = inverse_dynamics(kb, gravity=(0.0, -9.81))
    before = inverse_dynamics(kin)
    assert np.max(np.hypot(d0.shaking_fx, d0.shaking_fy)) <= 1e-9 * np.max(
        np.hypot(before.shaking_fx, before.shaking_fy))
    assert np.max(np.abs(dg.Q - d0.Q)) <= 1e-9 * 9.81 * 0.5
    m = _first_moment(fb.mechanism, kb)
    assert np.max(np.abs(m - m[:, :1])) <= 1e-12


def test_centre_of_mass_balance_is_the_least_squares_one():
    """With massive couplers the centre of mass cannot be kept still (partial): the balanced
    mechanism's own first moment of mass (summed from its bodies, independently of the solver)
    has the least excursion along the path: changing any counterweight's first moment by 1 %
    of its size in any direction makes it larger; its mass properties are the old plus the
    counterweights'."""
    from linkwork.balancing.mechanism import (
        add_counterweights,
        centre_of_mass_balance,
        path_weights,
    )
    from linkwork.balancing.static import Counterweight

    doc, mech = _five_bar()
    phi = doc.positions()
    kin = kinematics(mech, phi)
    fb = centre_of_mass_balance(kin, radii=0.05)
    assert not fb.full and "do not rotate rigidly" in fb.reason
    w = path_weights(phi.shape[1])

    def excursion(cws):
        m2 = add_counterweights(mech, cws)
        m = _first_moment(m2, kinematics(m2, phi))
        dm = m - np.sum(w * m, axis=1, keepdims=True)
        return float(np.sum(w * np.sum(dm * dm, axis=0)))

    best = excursion(fb.counterweights)
    assert best < 0.05 * excursion([])
    for k, cw in enumerate(fb.counterweights):
        q = cw.static_moment * np.exp(1j * cw.angle)
        for turn in (1, 1j, -1, -1j):
            moved = list(fb.counterweights)
            moved[k] = Counterweight.from_first_moment(cw.link, q + 0.01 * abs(q) * turn, 0.05)
            assert excursion(moved) > best
    for b in mech.bodies:
        nb = fb.mechanism.body(b.name)
        cw = next((c for c in fb.counterweights if c.link == b.name), None)
        assert nb.mass == pytest.approx(b.mass + (cw.static_moment / 0.05 if cw else 0.0))


def test_centre_of_mass_balance_refuses_a_link_that_does_not_turn():
    """A path along which crank c2 stays put: its counterweight is not determined."""
    from linkwork.balancing.mechanism import centre_of_mass_balance
    from linkwork.errors import ParameterError

    doc, mech = _five_bar()
    phi = doc.positions().copy()
    phi[1] = phi[1, 0]
    with pytest.raises(ParameterError, match=r"links = c2 .*does not turn"):
        centre_of_mass_balance(kinematics(mech, phi))
