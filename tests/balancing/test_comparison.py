"""Paper-001 comparison on the engine: consistency, independent checks of its columns."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _balancing_cases import normal_equations
from _balancing_cases import paper_fourbar as paper001_fourbar
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork import balancing as bal
from linkwork.balancing import (
    Counterweight,
    add_counterweights,
    compare_balancing,
    counterweight_axis_offset,
    efficiency,
)
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import crank_slider_mechanism, fourbar_mechanism

PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)
RADII = {"crank": 0.05, "rocker": 0.1}


@pytest.fixture(scope="module")
def comp():
    return compare_balancing(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER), radii=RADII)


def _angles_fd(phi, h=1e-4):
    """Independent plain-trig coupler and rocker angular accelerations (omega1 = 10)."""
    def ang(p):
        A = 0.1 * np.exp(1j * p)
        AC = 0.3 - A
        L = np.abs(AC)
        th2 = np.angle(AC) + np.arccos((0.09 + L**2 - 0.04) / (0.6 * L))
        th3 = np.angle(A + 0.3 * np.exp(1j * th2) - 0.3)
        return th2, th3
    (a2m, a3m), (a20, a30), (a2p, a3p) = ang(phi - 10 * h), ang(phi), ang(phi + 10 * h)

    def dd(m, z, p):
        return (np.angle(np.exp(1j * (p - z))) - np.angle(np.exp(1j * (z - m)))) / h**2
    return dd(a2m, a20, a2p), dd(a3m, a30, a3p)


def test_paper001_residual_moment_of_force_balanced_fourbar(comp):
    """After force balancing with point-mass counterweights the shaking moment is
    -(J_C eps3 + (I_S2 - m2 l_AS2 l_S2B) eps2) (the coupler replaced by statically
    equivalent masses at A and B plus a residual inertia; the crank turns uniformly), with
    J_C = I_S3 + m3 l_CS3^2 + m2 (l_AS2/l_AB) l_CB^2 + m_cw3 r_3^2 = 0.13567 kg m^2. The paper's
    M_0 = -sum I_Si eps_i (its first formula) drops the m r x v part and is wrong here."""
    e2, e3 = _angles_fd(comp.phi1)
    J_C = 0.00567 + 2 * 0.1**2 + 1.5 * 0.2**2 + 5.0 * 0.1**2
    exact = -(J_C * e3 + (0.0225 - 3.0 * 0.15 * 0.15) * e2)
    np.testing.assert_allclose(comp.dM1, exact, atol=1e-5 * np.abs(exact).max())
    paper_m0 = -(0.0225 * e2 + 0.00567 * e3)
    assert np.abs(paper_m0 - comp.dM1).max() > 0.5 * np.abs(comp.dM1).max()


def test_columns_consistent_with_cycle_and_definitions(comp):
    c = comp.cycle
    idx = np.searchsorted(c.phi1, comp.phi1)  # the cycle includes the table angles
    np.testing.assert_allclose(c.phi1[idx], comp.phi1, atol=1e-12)
    for a, b in ((comp.M, c.M), (comp.dM1, c.dM1), (comp.dM2, c.dM2), (comp.dM3, c.dM3)):
        np.testing.assert_allclose(a, b[idx], atol=1e-9)
    assert comp.R2 == pytest.approx(efficiency(comp.dM1, comp.dM2))
    assert comp.R3 == pytest.approx(efficiency(comp.dM1, comp.dM3))
    # constant speed: the continuous-RMS axis is the first-harmonic axis
    assert comp.x_rms == pytest.approx(comp.x2, abs=1e-12)
    assert comp.y_rms == pytest.approx(comp.y2, abs=1e-12)
    # 12 evenly spaced positions: formula (1) = least squares, close to the continuous optimum
    # (they differ only by the 11th/13th harmonics aliased onto the first)
    p1 = counterweight_axis_offset(comp.phi1, comp.dM1, comp.static_moment,
                                   10.0, method="paper")
    assert (p1.x, p1.y) == pytest.approx((comp.x3, comp.y3), abs=1e-12)
    assert np.hypot(comp.x3 - comp.x2, comp.y3 - comp.y2) < 1e-3
    assert np.abs(c.F1).max() <= 1e-9 * np.abs(c.F0).max()


def test_driving_torque_by_power_balance(comp):
    """Q omega1 = dT/dt (no gravity, no loads): T differentiated spectrally over the cycle."""
    c = comp.cycle
    for mech, Q in ((fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER), c.Q0),
                    (comp.balance.mechanism, c.Q1)):
        T = inverse_dynamics(kinematics(mech, c.phi1)).T
        k = np.fft.rfftfreq(c.phi1.size, d=1.0 / c.phi1.size)
        dT = np.fft.irfft(1j * k * np.fft.rfft(T), n=c.phi1.size)  # dT/dphi
        np.testing.assert_allclose(Q, dT, atol=1e-8 * np.abs(Q).max())


def test_moved_axis_bearing_loads(comp):
    """O1 carries S omega^2 = 20 N; the crank bearing then carries what it carries in the
    mechanism balanced by the rocker counterweight alone (built independently)."""
    c = comp.cycle
    np.testing.assert_allclose(c.reactions3["O1"], 0.2 * 100, rtol=1e-12)
    rocker_only = add_counterweights(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER),
                                     [Counterweight("rocker", 0.5, np.pi, 0.1)])
    d = inverse_dynamics(kinematics(rocker_only, c.phi1))
    np.testing.assert_allclose(c.reactions3["O2"], d.reaction_magnitude("O2"), rtol=1e-9)
    np.testing.assert_allclose(c.reactions3["O4"], c.reactions1["O4"], rtol=1e-12)


def test_summary_reports_increases(comp):
    s = comp.summary()
    assert s["shaking force peak [N]"]["static"] < 1e-9 * s["shaking force peak [N]"][
        "unbalanced"]
    inc = comp.increases()
    # static balancing raises the frame-bearing loads at O4 and the driving torque here
    assert any(m.startswith("frame joint O4 peak") for m in inc)
    assert any(m.startswith("driving torque peak") for m in inc)


def test_compare_requires_crank_counterweight():
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)
    with pytest.raises(ParameterError, match="crank"):
        compare_balancing(mech, links=["rocker"], radii=RADII)


def test_compare_on_crank_slider_partial_force_balance():
    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 2.0, 3.0), omega1=10.0)
    c = compare_balancing(mech, n=120)
    assert not c.balance.full
    assert c.balance.ratio < 1.0
    # moving the axis never changes the shaking force
    assert c.summary()["shaking force RMS [N]"]["static"] < c.summary()[
        "shaking force RMS [N]"]["unbalanced"]


def test_first_harmonic_method_removes_first_harmonic(comp):
    h = comp.harmonics(4)
    assert h["dM2"].amplitude[0] < 1e-9 * h["dM1"].amplitude[0]
    # higher harmonics are untouched by moving the axis
    np.testing.assert_allclose(h["dM2"].amplitude[1:], h["dM1"].amplitude[1:], rtol=1e-9)
    assert abs(h["M"].mean) < 1e-9 * h["M"].amplitude.max()


def test_paper001_shaking_moment_is_not_the_driving_torque(comp):
    """The paper's first formula also writes M_0 = M_ab (main moment = driving moment) for a
    statically balanced mechanism. The moment on the frame also has the couple of the bearing
    forces, so they differ: peaks 12.56 vs 5.61 N m for the paper's four-bar."""
    c = comp.cycle
    assert np.abs(c.dM1).max() > 2 * np.abs(c.Q1).max()
    assert np.abs(np.abs(c.dM1) - np.abs(c.Q1)).max() > 5.0


def test_compare_needs_a_running_crank():
    with pytest.raises(ParameterError, match="omega1"):
        compare_balancing(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **{**PAPER, "omega1": 0.0}))


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10_000))
def test_comparison_invariants_random_fourbars(seed):
    """Random crank-rockers with off-line centres (crank counterweight not at 180 deg): force
    balance to 1e-9; dM2 has no first harmonic; dM3 is stationary for the least squares over
    the table (normal equations); both leave the higher harmonics of dM1 unchanged."""
    from linkwork.balancing import counterweight_axis_moment, harmonics

    rng = np.random.default_rng(seed)
    a = rng.uniform(0.05, 0.1)
    b, c, d = rng.uniform(0.25, 0.4, 3)
    coms = tuple(tuple(rng.normal(0, 0.06, 2)) for _ in range(3))
    mech = fourbar_mechanism(a, b, c, d, masses=tuple(rng.uniform(0.5, 3, 3)), coms=coms,
                             omega1=12.0)
    comp = compare_balancing(mech, n=120)
    cyc = comp.cycle
    assert np.abs(cyc.F1).max() <= 1e-9 * np.abs(cyc.F0).max()
    h1, h2 = harmonics(cyc.phi1, cyc.dM1, 4), harmonics(cyc.phi1, cyc.dM2, 4)
    assert h2.amplitude[0] <= 1e-9 * max(h1.amplitude.max(), 1e-12)
    np.testing.assert_allclose(h2.amplitude[1:], h1.amplitude[1:], rtol=1e-9, atol=1e-12)
    crank_cw = comp.counterweights[0]
    p = comp.phi1 + crank_cw.angle - np.pi
    S = comp.static_moment
    for dx, dy in ((1.0, 0.0), (0.0, 1.0)):
        basis = counterweight_axis_moment(p, dx, dy, S, 12.0)
        assert abs(np.sum(comp.dM3 * basis)) <= 1e-9 * np.sum(np.abs(comp.dM1 * basis)) + 1e-12


def test_external_loads_enter_torque_not_table(comp):
    """A resisting couple of -5 N m on the rocker adds 5*omega3/omega1 to the driving torque
    (virtual power) and leaves the shaking-moment table unchanged."""
    from linkwork.planar.dynamics import BodyTorque

    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)
    loaded = compare_balancing(mech, radii=RADII,
                               loads=lambda phi: [BodyTorque("rocker", -5.0)])
    np.testing.assert_allclose(loaded.dM1, comp.dM1, atol=1e-12)
    w3 = kinematics(mech, comp.cycle.phi1).omega[3]
    np.testing.assert_allclose(loaded.cycle.Q0 - comp.cycle.Q0, 5.0 * w3 / 10.0, atol=1e-9)
    np.testing.assert_allclose(loaded.cycle.Q1 - comp.cycle.Q1, 5.0 * w3 / 10.0, atol=1e-9)


def test_comparison_of_a_mechanism_without_shaking_moment_reports_no_round_off():
    """Only the crank has mass (an eccentric on a shaft driving massless links): the shaking
    moment about O is zero at constant speed, yet the comparison reported R2 = 29.4 % and
    'balancing raises: shaking moment peak static 4.7e-17 vs unbalanced 2.8e-17 (+69.4 %)'."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 0.0, 0.0), omega1=10.0)
    comp = bal.compare_balancing(mech)
    # hand: the crank's centre turns about O at 0.05 m: inertia force m r w^2 = 5 N through O
    assert comp.summary()["shaking force peak [N]"]["unbalanced"] == pytest.approx(5.0)
    assert np.max(np.abs(comp.M)) < 1e-12 and np.max(np.abs(comp.dM1)) < 1e-12
    assert comp.R2 == 0.0 and comp.R3 == 0.0
    assert not [m for m in comp.increases() if "moment" in m or "torque" in m]


ROOT = Path(__file__).resolve().parents[2]


def test_compare_balancing_on_the_paper_fourbar_is_consistent():
    """Reference: paper 001's data and hand-written normal equations
    (tests/_balancing_cases.py). Tolerance: atol=1e-9, atol=1e-9 * np.max(np.abs(ref)),
    rtol=1e-9, rel=1e-12."""
    comp = bal.compare_balancing(paper001_fourbar(), radii={"crank": 0.05, "rocker": 0.1})
    phi = np.radians(np.arange(0, 360, 30.0))
    assert np.allclose(comp.phi1, phi)
    # M: the engine's moment of the unbalanced mechanism about O
    d0 = inverse_dynamics(kinematics(paper001_fourbar(), phi), about=(0, 0))
    assert np.allclose(comp.M, d0.shaking_m, atol=1e-9)
    # dM1: independent closed form of the force-balanced four-bar's moment (errata):
    # -[J_C eps3 + (I_S2 - m2 a b) eps2], J_C = I_S3 + m3 s3^2 + m_cw3 r3^2 + (m2 s2/l2) l3^2
    kin = kinematics(paper001_fourbar(), phi)
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


def test_zero_speed_comparison_is_refused():
    with pytest.raises(ParameterError, match="omega"):
        bal.compare_balancing(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2), omega1=0.0))


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
    comp = bal.compare_balancing(paper001_fourbar(), radii={"crank": 0.05, "rocker": 0.1}, n=72)
    assert [m for m in comp.increases() if m.startswith("shaking moment peak")]


def peak_of(comp, key):
    return max(comp.summary()[key].values())
