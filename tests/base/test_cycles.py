"""Cycle statistics of :mod:`linkwork.cycles` against analytic values.

Every reference here is a closed-form integral of a known signal (no number produced by
linkwork): RMS of A sin(phi) is A/sqrt(2), the Fourier coefficients of a finite trigonometric
series are its own coefficients, the mean of a polynomial over a range is its integral over the
range's length. Tolerances: the periodic trapezoid rule is exact (to round-off, rtol 1e-12) for
trigonometric polynomials of degree < n on evenly spaced samples; on uneven samples or for
non-periodic integrands it has the trapezoid error O(h^2), bounded per test.
"""

from __future__ import annotations

import numpy as np
import pytest

from linkwork import cycles
from linkwork.balancing import loads, partial
from linkwork.errors import ParameterError


def _even(n: int) -> np.ndarray:
    return 2.0 * np.pi * np.arange(n) / n


def test_periodic_weights_sum_to_a_turn_and_integrate_cos_squared() -> None:
    """Weights sum to 2 pi; on uneven samples they integrate a smooth periodic function to
    O(h^2): int_0^2pi cos^2 = pi (h ~ 0.02 rad -> error < 1e-3 relative)."""
    rng = np.random.default_rng(1)
    phi = np.sort(rng.uniform(0.0, 2 * np.pi, 400))
    w = cycles.periodic_weights(phi)
    assert w.sum() == pytest.approx(2 * np.pi, rel=1e-14)
    assert np.sum(w * np.cos(phi) ** 2) == pytest.approx(np.pi, rel=1e-3)
    even = _even(36)
    np.testing.assert_allclose(cycles.periodic_weights(even), np.full(36, 2 * np.pi / 36),
                               rtol=1e-13)


def test_periodic_weights_refuses_a_repeated_first_sample() -> None:
    with pytest.raises(ParameterError, match="2\\*pi"):
        cycles.periodic_weights(np.linspace(0.0, 2 * np.pi, 10))
    with pytest.raises(ParameterError, match="increasing"):
        cycles.periodic_weights([0.0, 2.0, 1.0])


@pytest.mark.parametrize("n", [7, 36, 360])
def test_rms_of_a_sine_is_amplitude_over_sqrt2(n: int) -> None:
    """sqrt(1/2pi int (A sin(phi + c))^2) = A / sqrt(2), exact for n >= 3 even samples."""
    phi = _even(n)
    A = 3.7
    assert cycles.rms(phi, A * np.sin(phi + 0.3)) == pytest.approx(A / np.sqrt(2), rel=1e-12)


def test_rms_of_a_rotating_vector_is_its_length() -> None:
    """|(R cos, R sin)| = R everywhere, so the RMS of the vector magnitude is R."""
    phi = _even(50)
    F = 2.5 * np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    assert cycles.rms(phi, F) == pytest.approx(2.5, rel=1e-13)
    # and a constant plus a first harmonic: sqrt(a0^2 + A^2 / 2)
    assert cycles.rms(phi, 1.0 + 2.0 * np.cos(phi)) == pytest.approx(np.sqrt(3.0), rel=1e-12)


def test_peak_and_its_position() -> None:
    """max |f| of f = -5 cos(phi - 1) sampled at 1 rad exactly: 5 at phi = 1 (and at pi + 1,
    which is not a sample)."""
    phi = np.linspace(0.0, 2.0, 201)  # contains 1.0 exactly (index 100)
    f = -5.0 * np.cos(phi - 1.0)
    assert cycles.peak(f) == pytest.approx(5.0, rel=1e-15)
    value, where = cycles.peak_at(phi, f)
    assert value == pytest.approx(5.0, rel=1e-15)
    assert where == pytest.approx(1.0, abs=1e-15)
    # a vector: |(3, 4)| = 5 at the only place it occurs
    v = np.zeros((5, 2))
    v[3] = (3.0, -4.0)
    assert cycles.peak_at(np.arange(5.0), v) == (5.0, 3.0)


def test_harmonics_of_a_known_fourier_series() -> None:
    """f = 0.5 + 2 cos(phi) - 1 sin(phi) + 0.25 cos(3 phi - 0.7): a0 = 0.5, (a1, b1) = (2, -1),
    A3 = 0.25 with phase 0.7, A2 = A4 = 0 (exact on 64 even samples)."""
    phi = _even(64)
    f = 0.5 + 2.0 * np.cos(phi) - np.sin(phi) + 0.25 * np.cos(3 * phi - 0.7)
    h = cycles.harmonics(phi, f, 4)
    assert h.mean == pytest.approx(0.5, rel=1e-12)
    np.testing.assert_allclose(h.cos[:1], [2.0], rtol=1e-12)
    np.testing.assert_allclose(h.sin[:1], [-1.0], rtol=1e-12)
    np.testing.assert_allclose(h.amplitude, [np.sqrt(5.0), 0.0, 0.25, 0.0], atol=1e-12)
    assert h.phase[2] == pytest.approx(0.7, rel=1e-12)
    np.testing.assert_allclose(h.evaluate(phi), f, atol=1e-12)


def test_harmonics_on_uneven_samples_are_the_continuous_projections() -> None:
    """The weighted fit reproduces a band-limited series on uneven samples (the basis spans f,
    so the least-squares fit is exact whatever the weights)."""
    rng = np.random.default_rng(3)
    phi = np.sort(rng.uniform(0.0, 2 * np.pi, 90))
    f = -1.0 + 0.3 * np.sin(2 * phi) + 4.0 * np.cos(phi)
    h = cycles.harmonics(phi, f, 3)
    np.testing.assert_allclose([h.mean, h.cos[0], h.sin[1]], [-1.0, 4.0, 0.3], atol=1e-10)


def test_mean_over_range_of_a_polynomial_is_its_integral_over_the_length() -> None:
    """mean of 3 x^2 over [1, 2] = (2^3 - 1^3) / 1 = 7; the trapezoid rule errs by
    (b - a) h^2 f''/12 = 6 h^2 / 12 (h = 1e-3 -> 5e-7), the bound used here."""
    x = np.linspace(1.0, 2.0, 1001)
    assert cycles.mean_over_range(x, 3 * x**2) == pytest.approx(7.0, abs=6e-7)
    # linear functions are exact: mean of 2x + 1 over [0, 4] is 5
    x = np.array([0.0, 0.5, 3.0, 4.0])
    assert cycles.mean_over_range(x, 2 * x + 1) == pytest.approx(5.0, rel=1e-15)
    # a single position: its value
    assert cycles.mean_over_range([0.5], [4.0]) == 4.0


def test_mean_over_range_with_an_undefined_sample_is_undefined() -> None:
    """A NaN sample (a self-locking or unassembled position) makes the work over the range,
    and so the mean, undefined: NaN, without a warning (also when no sample is finite); the
    mean of the other samples (2.0 here) would be another quantity."""
    assert np.isnan(cycles.mean_over_range([0.0, 1.0, 2.0], [1.0, np.nan, 3.0]))
    assert np.isnan(cycles.mean_over_range([0.0, 1.0, 2.0], [np.nan] * 3))
    assert np.isnan(cycles.mean_over_range([0.0], [np.nan]))


def test_old_names_are_the_moved_functions() -> None:
    """The old places re-export the same objects (no copies left behind)."""
    assert loads.rms is cycles.rms
    assert loads.peak is cycles.peak
    assert loads.harmonics is cycles.harmonics
    assert loads.Harmonics is cycles.Harmonics
    assert loads.mean_over_range is cycles.mean_over_range
    assert partial.periodic_weights is cycles.periodic_weights
