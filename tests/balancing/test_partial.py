"""Partial dynamic balancing (moved counterweight axis), efficiency, shaking-load helpers."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from _balancing_cases import normal_equations
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, optimize

from linkwork import balancing as bal
from linkwork.balancing import (
    counterweight_axis_moment,
    counterweight_axis_offset,
    efficiency,
    first_harmonic_offset,
    harmonics,
    moment_about,
    peak,
    periodic_weights,
    rms,
    rms_offset,
    shaking_force,
    shaking_moment,
)
from linkwork.errors import LinkworkError, ParameterError


def _cw_moment_by_finite_differences(phi0, x, y, m, r, omega, eps, h=1e-4):
    """Moment about O of the inertia force of a point counterweight turning with the crank
    about O1(x, y), minus the same with O1 = O; positions differentiated numerically."""
    t = np.array([-h, 0.0, h])[:, None]
    phi = phi0[None, :] + omega * t + 0.5 * eps * t**2
    out = []
    for ox, oy in ((x, y), (0.0, 0.0)):
        px = ox - r * np.cos(phi)
        py = oy - r * np.sin(phi)
        ax = (px[2] - 2 * px[1] + px[0]) / h**2
        ay = (py[2] - 2 * py[1] + py[0]) / h**2
        fx, fy = -m * ax, -m * ay
        out.append(px[1] * fy - py[1] * fx)
    return out[0] - out[1]


@pytest.mark.parametrize("eps", [0.0, 7.0, -25.0])
def test_paper001_myp_derivation_matches_finite_differences(eps):
    """Reference: paper 001. Tolerance: atol=1e-5 * np.abs(ref).max()."""
    phi = np.linspace(0, 2 * np.pi, 13)
    m, r, omega, x, y = 4.0, 0.05, 10.0, -0.07, 0.19
    ref = _cw_moment_by_finite_differences(phi, x, y, m, r, omega, eps)
    got = counterweight_axis_moment(phi, x, y, m * r, omega, eps)
    np.testing.assert_allclose(got, ref, atol=1e-5 * np.abs(ref).max())


def _objective(xy, phi, M, S, w, e):
    return np.sum((M + counterweight_axis_moment(phi, xy[0], xy[1], S, w, e)) ** 2)


@settings(max_examples=50, deadline=None)
@given(st.integers(min_value=0, max_value=10_000), st.booleans())
def test_lsq_offset_is_the_minimum_of_I(seed, accelerating):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 20))
    phi = np.sort(rng.uniform(0, 2 * np.pi, n))
    M = rng.normal(0, 5, n)
    w = rng.uniform(5, 15, n) if accelerating else 10.0
    e = rng.normal(0, 30, n) if accelerating else 0.0
    S = 0.2
    got = counterweight_axis_offset(phi, M, S, w, e)
    ref = optimize.minimize(_objective, [0.0, 0.0], args=(phi, M, S, w, e), method="BFGS",
                            options={"gtol": 1e-10})
    # gradient of I vanishes at our solution and I is not larger than the optimiser's
    I_got = _objective([got.x, got.y], phi, M, S, w, e)
    assert I_got <= ref.fun * (1 + 1e-9) + 1e-12
    np.testing.assert_allclose([got.x, got.y], ref.x, atol=1e-5)


@pytest.mark.parametrize("n", [3, 7, 12, 36])
@pytest.mark.parametrize("phase", [0.0, 0.3])
def test_paper001_eq1_exact_for_uniform_full_cycle(n, phase):
    """Reference: paper 001, Eq. (1). Tolerance: < 1e-12, rtol=1e-12, atol=1e-15."""
    rng = np.random.default_rng(n)
    phi = phase + 2 * np.pi * np.arange(n) / n
    M = rng.normal(0, 3, n)
    assert abs(np.sum(np.sin(phi) * np.cos(phi))) < 1e-12
    lsq = counterweight_axis_offset(phi, M, 0.2, 10.0)
    paper = counterweight_axis_offset(phi, M, 0.2, 10.0, method="paper")
    np.testing.assert_allclose([paper.x, paper.y], [lsq.x, lsq.y], rtol=1e-12, atol=1e-15)


def test_paper001_eq1_exact_for_symmetric_non_uniform_set():
    """Reference: paper 001, Eq. (1). Tolerance: < 1e-12, rtol=1e-12."""
    # sum sin*cos = 0 without even spacing: {10, 80, 100, 170} deg (sin 2phi cancels in pairs)
    phi = np.radians([10.0, 80.0, 190.0, 200.0])
    assert abs(np.sum(np.sin(2 * phi))) > 0.1  # this one does not cancel ...
    phi = np.radians([10.0, 80.0, 100.0, 170.0])
    assert abs(np.sum(np.sin(2 * phi))) < 1e-12  # ... this one does
    M = np.array([1.0, -2.0, 0.5, 3.0])
    lsq = counterweight_axis_offset(phi, M, 0.3, 8.0)
    paper = counterweight_axis_offset(phi, M, 0.3, 8.0, method="paper")
    np.testing.assert_allclose([paper.x, paper.y], [lsq.x, lsq.y], rtol=1e-12)


def test_paper001_eq1_not_optimal_on_half_cycle():
    # 0..120 deg (a working stroke): sum sin cos != 0.  (0..150 deg in 30 deg steps would
    """Reference: paper 001, Eq. (1). Tolerance: < I_paper * (1 - 1e-3)."""
    # still satisfy (1): sin 2phi then runs over a full cycle.)
    phi = np.radians(np.arange(0.0, 150.0, 30.0))
    assert abs(np.sum(np.sin(phi) * np.cos(phi))) > 0.1
    M = np.array([-5.0, -1.0, -4.0, -5.5, -4.1])
    lsq = counterweight_axis_offset(phi, M, 0.2, 10.0)
    paper = counterweight_axis_offset(phi, M, 0.2, 10.0, method="paper")
    assert np.hypot(paper.x - lsq.x, paper.y - lsq.y) > 1e-3
    I_lsq = np.sum(lsq.residual**2)
    I_paper = np.sum(paper.residual**2)
    assert I_lsq < I_paper * (1 - 1e-3)


def test_paper_method_refuses_accelerating_crank():
    with pytest.raises(ParameterError, match="method"):
        counterweight_axis_offset([0, 1, 2], [1, 2, 3], 0.2, 10.0, 5.0, method="paper")


def _trig_moment(phi):
    # a1 = 2, b1 = -1.5, plus 2nd and 3rd harmonics and a mean
    return 0.4 + 2.0 * np.cos(phi) - 1.5 * np.sin(phi) + 3.0 * np.cos(2 * phi + 0.3) \
        - 0.7 * np.sin(3 * phi)


def test_first_harmonic_offset_closed_form():
    phi = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    S, w = 0.2, 10.0
    r = first_harmonic_offset(phi, _trig_moment(phi), S, w)
    np.testing.assert_allclose([r.x, r.y], [-1.5 / (S * w**2), -2.0 / (S * w**2)], rtol=1e-12)
    h = harmonics(phi, r.residual, 3)
    assert h.amplitude[0] < 1e-12


def test_rms_equals_first_harmonic_at_constant_speed():
    phi = np.sort(np.random.default_rng(1).uniform(0, 2 * np.pi, 400))
    M = _trig_moment(phi)
    a = rms_offset(phi, M, 0.2, 10.0)
    b = first_harmonic_offset(phi, M, 0.2, 10.0)
    np.testing.assert_allclose([a.x, a.y], [b.x, b.y], rtol=1e-9)


def test_rms_offset_with_variable_speed_matches_quadrature_optimum():
    def omega(p):
        return 10.0 * (1 + 0.2 * np.cos(p))

    def eps(p):  # eps = omega * d omega / d phi
        return omega(p) * (-2.0 * np.sin(p))

    S = 0.2

    def integral(xy):
        def f(p):
            return (_trig_moment(p) + counterweight_axis_moment(p, xy[0], xy[1], S, omega(p),
                                                                eps(p))) ** 2
        return integrate.quad(f, 0, 2 * np.pi, limit=200)[0]

    ref = optimize.minimize(integral, [0.0, 0.0], method="Nelder-Mead",
                            options={"xatol": 1e-9, "fatol": 1e-12, "maxiter": 2000})
    phi = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    got = rms_offset(phi, _trig_moment(phi), S, omega(phi), eps(phi))
    np.testing.assert_allclose([got.x, got.y], ref.x, atol=1e-6)
    fh = first_harmonic_offset(phi, _trig_moment(phi), S, omega(phi), eps(phi))
    assert np.hypot(fh.x - got.x, fh.y - got.y) > 1e-3  # the two methods differ now


def test_offset_input_errors():
    with pytest.raises(ParameterError, match="static_moment"):
        counterweight_axis_offset([0, 1], [1, 2], -0.2, 10.0)
    with pytest.raises(ParameterError, match="moment"):
        counterweight_axis_offset([0, 1, 2], [1, 2], 0.2, 10.0)
    with pytest.raises(ParameterError, match="phi"):
        counterweight_axis_offset([0.5], [1.0], 0.2, 10.0)
    with pytest.raises(ParameterError, match="method"):
        counterweight_axis_offset([0, 1], [1, 2], 0.2, 10.0, method="magic")
    with pytest.raises(LinkworkError, match="moment"):
        counterweight_axis_offset([0, 1], [1, np.nan], 0.2, 10.0)
    with pytest.raises(ParameterError, match="2\\*pi"):
        rms_offset(np.linspace(0, 2 * np.pi, 10), np.ones(10), 0.2, 10.0)


def test_efficiency_definition():
    assert efficiency([-4.0, 2.0], [1.0, -3.0]) == pytest.approx(25.0)
    assert efficiency([1.0, -2.0], [3.0, 0.0]) == pytest.approx(-50.0)
    with pytest.raises(ParameterError, match="before"):
        efficiency([0.0, 0.0], [1.0])


def test_harmonics_recover_known_series_on_uneven_samples():
    phi = np.sort(np.random.default_rng(3).uniform(0, 2 * np.pi, 2000))
    h = harmonics(phi, _trig_moment(phi), 4)
    # cos(2p + 0.3) = cos0.3 cos2p - sin0.3 sin2p
    np.testing.assert_allclose(h.mean, 0.4, atol=2e-4)
    np.testing.assert_allclose(h.cos, [2.0, 3 * np.cos(0.3), 0, 0], atol=2e-4)
    np.testing.assert_allclose(h.sin, [-1.5, -3 * np.sin(0.3), -0.7, 0], atol=2e-4)
    np.testing.assert_allclose(h.amplitude[:3], [2.5, 3.0, 0.7], atol=2e-4)
    np.testing.assert_allclose(h.phase[1], -0.3, atol=1e-4)  # A cos(2p - psi), psi = -0.3
    np.testing.assert_allclose(h.evaluate(phi), _trig_moment(phi), atol=1e-3)


def test_harmonics_uniform_equals_fft():
    n = 24
    phi = 2 * np.pi * np.arange(n) / n
    f = np.random.default_rng(5).normal(size=n)
    h = harmonics(phi, f, 5)
    F = np.fft.rfft(f) / n
    np.testing.assert_allclose(h.cos, 2 * F.real[1:6], atol=1e-12)
    np.testing.assert_allclose(h.sin, -2 * F.imag[1:6], atol=1e-12)
    with pytest.raises(ParameterError, match="k"):
        harmonics(phi, f, 12)


def test_rms_and_peak():
    phi = np.linspace(0, 2 * np.pi, 100, endpoint=False)
    assert rms(phi, 3.0 * np.sin(phi)) == pytest.approx(3.0 / np.sqrt(2), rel=1e-12)
    vec = np.stack([3 * np.cos(phi), 3 * np.sin(phi)], axis=-1)  # |F| = 3 everywhere
    assert rms(phi, vec) == pytest.approx(3.0, rel=1e-12)
    assert peak(vec) == pytest.approx(3.0)
    assert peak([-4.0, 2.0]) == 4.0
    w = periodic_weights(np.sort(np.random.default_rng(0).uniform(0, 6, 30)))
    assert w.sum() == pytest.approx(2 * np.pi)


def test_shaking_moment_about_any_point_by_transfer():
    rng = np.random.default_rng(2)
    b, n = 3, 10
    m, J = rng.uniform(1, 3, b), rng.uniform(0.01, 0.1, b)
    pos, acc = rng.normal(size=(b, n, 2)), rng.normal(size=(b, n, 2))
    eps = rng.normal(size=(b, n))
    P = np.array([0.4, -0.25])
    MO = shaking_moment(m, J, pos, acc, eps)
    F = shaking_force(m, acc)
    direct = shaking_moment(m, J, pos, acc, eps, P)
    # independent: sum of moments of each inertia force written out
    ref = np.zeros(n)
    for i in range(b):
        Fi = -m[i] * acc[i]
        d = pos[i] - P
        ref += d[:, 0] * Fi[:, 1] - d[:, 1] * Fi[:, 0] - J[i] * eps[i]
    np.testing.assert_allclose(direct, ref, rtol=1e-12)
    np.testing.assert_allclose(moment_about(MO, F, P), ref, rtol=1e-12)


def test_myp_for_counterweight_at_any_angle_uses_opposite_direction():
    """A counterweight at angle alpha on the crank: the paper's phi is theta + alpha - pi."""
    theta = np.linspace(0, 2 * np.pi, 11)
    alpha, m, r, omega, eps, x, y = 2.2, 3.0, 0.07, 9.0, 4.0, 0.05, -0.12
    h = 1e-4
    t = np.array([-h, 0.0, h])[:, None]
    th = theta[None, :] + omega * t + 0.5 * eps * t**2
    res = []
    for ox, oy in ((x, y), (0.0, 0.0)):
        px = ox + r * np.cos(th + alpha)
        py = oy + r * np.sin(th + alpha)
        ax = (px[2] - 2 * px[1] + px[0]) / h**2
        ay = (py[2] - 2 * py[1] + py[0]) / h**2
        res.append(px[1] * (-m * ay) - py[1] * (-m * ax))
    ref = res[0] - res[1]
    got = counterweight_axis_moment(theta + alpha - np.pi, x, y, m * r, omega, eps)
    np.testing.assert_allclose(got, ref, atol=1e-5 * np.abs(ref).max())


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
    """Reference: paper 001's data and hand-written normal equations
    (tests/_balancing_cases.py). Tolerance: rtol=1e-12, atol=1e-15, rtol=1e-9."""
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
