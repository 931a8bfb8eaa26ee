"""Closed-form static balancing (four-bar, crank-slider) checked on independently solved cycles."""

from __future__ import annotations

import numpy as np
import pytest
from _balancing_cases import com_positions, paper_fourbar
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork import balancing as bal
from linkwork.balancing.static import (
    Counterweight,
    crank_slider_counterweight,
    fourbar_counterweights,
)
from linkwork.errors import ParameterError
from linkwork.planar.kinematics import kinematics


def fourbar_angles(l0, l1, l2, l3, th1, branch):
    """Coupler and rocker angles by plain trigonometry (circle intersection), frame O->C on x."""
    A = l1 * np.exp(1j * th1)
    C = l0 + 0j
    AC = C - A
    L = np.abs(AC)
    cos_g = (l2**2 + L**2 - l3**2) / (2 * l2 * L)
    th2 = np.angle(AC) + branch * np.arccos(cos_g)
    B = A + l2 * np.exp(1j * th2)
    th3 = np.angle(B - C)
    return th2, th3


def fourbar_first_moment(geom, masses, th1, branch, extra=(0j, 0j)):
    l0, l1, l2, l3 = geom
    (m1, s1), (m2, s2), (m3, s3) = masses
    th2, th3 = fourbar_angles(l0, l1, l2, l3, th1, branch)
    e1, e2, e3 = np.exp(1j * th1), np.exp(1j * th2), np.exp(1j * th3)
    q1, q3 = extra
    return (m1 * s1 * e1 + m2 * (l1 * e1 + s2 * e2) + m3 * (l0 + s3 * e3)
            + q1 * e1 + q3 * e3)


def test_paper001_counterweights():
    """Paper 001 four-bar: S1 = 0.2 kg*m and S3 = 0.5 kg*m, both opposite the moving joint;
    with r = 0.05 m and 0.1 m these are 4 kg and 5 kg."""
    cw1, cw3 = fourbar_counterweights(0.1, 0.3, 0.2, 1.0, 0.05, 3.0, 0.15, 2.0, 0.1)
    assert cw1.static_moment == pytest.approx(0.2, rel=1e-12)
    assert cw3.static_moment == pytest.approx(0.5, rel=1e-12)
    assert abs(cw1.angle) == pytest.approx(np.pi)
    assert abs(cw3.angle) == pytest.approx(np.pi)
    assert cw1.mass(0.05) == pytest.approx(4.0)
    assert cw3.mass(0.1) == pytest.approx(5.0)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 100_000), st.sampled_from([1, -1]))
def test_berkof_lowen_counterweights_make_centre_of_mass_stationary(seed, branch):
    rng = np.random.default_rng(seed)
    # a Grashof crank-rocker: crank 0.05..0.1 m, others 0.25..0.4 m (s + l <= p + q always)
    l1 = rng.uniform(0.05, 0.1)
    l0, l2, l3 = rng.uniform(0.25, 0.4, 3)
    masses = [(rng.uniform(0.5, 3), complex(*rng.normal(0, 0.1, 2))) for _ in range(3)]
    th1 = np.linspace(0, 2 * np.pi, 73)
    th2, _ = fourbar_angles(l0, l1, l2, l3, th1, branch)
    assert not np.isnan(th2).any()
    cw1, cw3 = fourbar_counterweights(l1, l2, l3, *[v for ms in masses for v in ms])
    before = fourbar_first_moment((l0, l1, l2, l3), masses, th1, branch)
    after = fourbar_first_moment((l0, l1, l2, l3), masses, th1, branch,
                                 (cw1.first_moment, cw3.first_moment))
    assert np.ptp(before.real) + np.ptp(before.imag) > 1e-3
    assert np.abs(after - after[0]).max() <= 1e-12 * np.abs(before - before[0]).max() + 1e-15


def crank_slider_x(l1, l2, th1):
    """Centred crank-slider, guide along x through O: slider position by trigonometry."""
    return l1 * np.cos(th1) + np.sqrt(l2**2 - (l1 * np.sin(th1)) ** 2)


@pytest.mark.parametrize("k", [0.0, 0.5, 1.0])
def test_crank_slider_counterweight_fraction(k):
    l1, l2, m1, m2, m3 = 0.05, 0.2, 1.0, 2.0, 3.0
    s1, s2 = 0.02, 0.07
    omega = 10.0
    th = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    cw = crank_slider_counterweight(l1, l2, m1, s1, m2, s2, m3, fraction=k)

    def first_moment(t):
        A = l1 * np.exp(1j * t)
        B = crank_slider_x(l1, l2, t) + 0j
        e2 = (B - A) / l2
        return m1 * s1 * np.exp(1j * t) + m2 * (A + s2 * e2) + m3 * B \
            + cw.first_moment * np.exp(1j * t)

    h = 1e-4
    acc = (first_moment(th + h) - 2 * first_moment(th) + first_moment(th - h)) / h**2 * omega**2
    F = -acc
    m_rec = m3 + m2 * s2 / l2
    # across the guide: -k * m_rec * l1 * omega^2 * sin(th) (the counterweight's extra part)
    np.testing.assert_allclose(F.imag, -k * m_rec * l1 * omega**2 * np.sin(th), atol=1e-4)
    # along the guide: first harmonic of the reciprocating force reduced to (1 - k)
    a1 = 2 * np.mean(F.real * np.cos(th))
    scale = m_rec * l1 * omega**2
    np.testing.assert_allclose(a1, (1 - k) * scale, atol=1e-6 * scale)


def test_counterweight_constructors_and_errors():
    cw = Counterweight.from_mass("crank", 4.0, 0.05, np.pi)
    assert cw.static_moment == pytest.approx(0.2)
    assert cw.first_moment == pytest.approx(-0.2 + 0j)
    with pytest.raises(ParameterError, match="radius"):
        cw.mass(0.0)
    with pytest.raises(ParameterError, match="fraction"):
        crank_slider_counterweight(0.05, 0.2, 1, 0.02, 2, 0.07, 3, fraction=1.5)
    with pytest.raises(ParameterError, match="l2"):
        fourbar_counterweights(0.1, -0.3, 0.2, 1, 0.05, 3, 0.15, 2, 0.1)


def test_point_mass_method_equals_linearly_independent_vectors():
    from linkwork.balancing.static import (
        fourbar_counterweights_point_masses,
        statically_equivalent_masses,
    )

    mA, mB, dI = statically_equivalent_masses(3.0, 0.3, 0.15)
    assert (mA, mB) == pytest.approx((1.5, 1.5))
    assert dI == pytest.approx(-3.0 * 0.15 * 0.15)
    rng = np.random.default_rng(7)
    for _ in range(20):
        l1, l2, l3 = rng.uniform(0.05, 0.4, 3)
        m1, m2, m3 = rng.uniform(0.5, 3, 3)
        s1, s2, s3 = rng.uniform(-0.3, 1.0) * l1, rng.uniform(0, 1) * l2, rng.uniform(0, 1) * l3
        a = fourbar_counterweights_point_masses(l1, l2, l3, m1, s1, m2, s2, m3, s3)
        b = fourbar_counterweights(l1, l2, l3, m1, s1, m2, s2, m3, s3)
        for x, y in zip(a, b, strict=True):
            assert abs(x.first_moment - y.first_moment) < 1e-12
    with pytest.raises(ParameterError, match="com"):
        statically_equivalent_masses(1.0, 0.3, 0.4)


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
