"""Shaking loads over a cycle: moment about any point, harmonic content, RMS, mean and peak.

The shaking force is the resultant of the inertia forces of all moving links,
:math:`F = -\\sum m_i a_{S_i} = -\\dot p` (minus the rate of total linear momentum); it is what
the mechanism exerts on its frame besides gravity and external loads. The shaking moment about a
frame point P is the resultant moment of the inertia forces and inertia couples about P,
:math:`M_P = -\\sum [(r_{S_i} - P) \\times m_i a_{S_i} + I_{S_i}\\varepsilon_i]`, which is also the
moment the mechanism exerts on the frame including the reaction of the driving motor. Moments
are counter-clockwise positive.

These helpers work on arrays sampled over a cycle, whatever produced them (the planar engine, a
closed-form model, measurements).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.partial import periodic_weights
from linkwork.errors import ParameterError, require_finite
from linkwork.planar.inertia import inertia_couple, inertia_force
from linkwork.results import Result

__all__ = [
    "Harmonics",
    "harmonics",
    "mean_over_range",
    "moment_about",
    "peak",
    "rms",
    "shaking_force",
    "shaking_moment",
]


def shaking_force(masses: ArrayLike, acc: ArrayLike) -> np.ndarray:
    """Shaking force :math:`F = -\\sum_i m_i a_{S_i}` [N].

    Parameters
    ----------
    masses : array_like, shape (b,)
        Link masses [kg].
    acc : array_like, shape (b, n, 2)
        Accelerations of the centres of mass [m/s²] at n positions.

    Returns
    -------
    ndarray, shape (n, 2)
    """
    m = require_finite("masses", masses)
    a = require_finite("acc", acc)
    fx, fy = inertia_force(m[:, None], a[..., 0], a[..., 1])  # -m a per link, (b, n)
    return np.stack([fx.sum(axis=0), fy.sum(axis=0)], axis=-1)


def shaking_moment(masses: ArrayLike, inertias: ArrayLike, pos: ArrayLike, acc: ArrayLike,
                   eps: ArrayLike, point: ArrayLike = (0.0, 0.0)) -> np.ndarray:
    """Shaking moment about a frame point P [N·m], counter-clockwise positive.

    .. math::

        M_P = -\\sum_i \\left[(r_{S_i} - P) \\times m_i a_{S_i} + I_{S_i} \\varepsilon_i\\right]

    Parameters
    ----------
    masses, inertias : array_like, shape (b,)
        Masses [kg] and central moments of inertia [kg·m²].
    pos, acc : array_like, shape (b, n, 2)
        Positions [m] and accelerations [m/s²] of the centres of mass.
    eps : array_like, shape (b, n)
        Angular accelerations [rad/s²].
    point : array_like, shape (2,)
        P [m].

    Returns
    -------
    ndarray, shape (n,)
    """
    m = require_finite("masses", masses)
    J = require_finite("inertias", inertias)
    r = require_finite("pos", pos) - require_finite("point", point)
    a = require_finite("acc", acc)
    e = require_finite("eps", eps)
    fx, fy = inertia_force(m[:, None], a[..., 0], a[..., 1])  # -m a per link, (b, n)
    return np.sum(r[..., 0] * fy - r[..., 1] * fx + inertia_couple(J[:, None], e), axis=0)


def moment_about(moment: ArrayLike, force: ArrayLike, point: ArrayLike,
                 origin: ArrayLike = (0.0, 0.0)) -> np.ndarray:
    """Shaking moment about ``point`` from the moment about ``origin`` and the shaking force.

    .. math:: M_P = M_O - (P - O) \\times F

    Parameters
    ----------
    moment : array_like, shape (n,)
        Moment about ``origin`` [N·m].
    force : array_like, shape (n, 2)
        Shaking force [N].
    point, origin : array_like, shape (2,)
        New and old reference points [m].
    """
    M = require_finite("moment", moment)
    F = require_finite("force", force)
    d = require_finite("point", point) - require_finite("origin", origin)
    return M - (d[0] * F[..., 1] - d[1] * F[..., 0])


def _magnitude(values: np.ndarray, vector: bool | None) -> np.ndarray:
    if vector is None:
        vector = values.ndim == 2 and values.shape[-1] == 2
    return np.hypot(values[..., 0], values[..., 1]) if vector else values


def rms(phi: ArrayLike, values: ArrayLike, *, vector: bool | None = None) -> float:
    """Continuous RMS over one full cycle of the crank angle.

    :math:`\\sqrt{\\frac{1}{2\\pi}\\int_0^{2\\pi} f^2\\,d\\varphi}` by the periodic trapezoid rule
    (:func:`~linkwork.balancing.partial.periodic_weights`); for a vector quantity (shape (n, 2),
    e.g. the shaking force) f is its magnitude.

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angles covering one cycle, strictly increasing, first sample not repeated [rad].
    values : array_like, shape (n,) or (n, 2)
    vector : bool, optional
        Treat ``values`` as (n, 2) vectors; default: guessed from the shape.
    """
    w = periodic_weights(phi)
    f = _magnitude(require_finite("values", values), vector)
    if f.shape != w.shape:
        raise ParameterError("values", f"array of shape {f.shape}",
                             f"must have {w.size} positions like phi")
    return float(np.sqrt(np.sum(w * f**2) / (2.0 * np.pi)))


def mean_over_range(phi1: ArrayLike, values: ArrayLike) -> float:
    """Mean of ``values`` over the driver range: the trapezoid integral over ``phi1`` divided by
    the range (for the driving torque: the work per cycle over the angle turned), so that a
    closed cycle sampled with its end repeating its start counts that position once; the mean
    of the finite samples if some are NaN or there is a single position."""
    q, p = np.asarray(values, dtype=float), np.asarray(phi1, dtype=float)
    if q.size > 1 and p[-1] != p[0] and np.all(np.isfinite(q)):
        return float(np.trapezoid(q, p) / (p[-1] - p[0]))
    return float(np.nanmean(q))


def peak(values: ArrayLike, *, vector: bool | None = None) -> float:
    """Largest magnitude over the samples (|f| or the vector norm) [unit of ``values``]."""
    f = _magnitude(require_finite("values", values), vector)
    if f.size == 0:
        raise ParameterError("values", "empty", "must contain at least one value")
    return float(np.max(np.abs(f)))


@dataclass(frozen=True)
class Harmonics(Result):
    """Fourier content of a periodic quantity in the crank angle.

    :math:`f(\\varphi) \\approx a_0 + \\sum_{j=1}^{k} [a_j \\cos j\\varphi + b_j \\sin j\\varphi]
    = a_0 + \\sum_j A_j \\cos(j\\varphi - \\psi_j)`, with :math:`A_j = \\sqrt{a_j^2 + b_j^2}`
    and :math:`\\psi_j = \\operatorname{atan2}(b_j, a_j)`.

    Attributes
    ----------
    order : ndarray, shape (k,)
        1 .. k.
    mean : float
        :math:`a_0` [unit of f].
    cos, sin : ndarray, shape (k,)
        :math:`a_j, b_j`.
    amplitude : ndarray, shape (k,)
        :math:`A_j`.
    phase : ndarray, shape (k,)
        :math:`\\psi_j` [rad], in (-pi, pi].
    """

    order: np.ndarray
    mean: float
    cos: np.ndarray
    sin: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    units: ClassVar[dict[str, str]] = {"phase": "rad"}
    position_field: ClassVar[str] = "order"

    def evaluate(self, phi: ArrayLike) -> np.ndarray:
        """The truncated series at ``phi`` [rad]."""
        p = np.asarray(phi, dtype=float)[..., None]
        j = self.order
        return self.mean + np.sum(self.cos * np.cos(j * p) + self.sin * np.sin(j * p), axis=-1)


def harmonics(phi: ArrayLike, values: ArrayLike, k: int = 4) -> Harmonics:
    """Amplitudes and phases of the first k harmonics of a quantity sampled over one cycle.

    The coefficients are the continuous Fourier projections
    :math:`a_j = \\frac{1}{\\pi}\\int f\\cos j\\varphi\\,d\\varphi` evaluated as a weighted least
    squares fit with the periodic trapezoid weights; for evenly spaced samples this equals the
    discrete Fourier transform (and is exact for band-limited f of degree < n/2).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angles covering one cycle [rad] (see :func:`rms`).
    values : array_like, shape (n,)
    k : int
        Number of harmonics, ``2k + 1 <= n``.
    """
    p = require_finite("phi", phi)
    f = require_finite("values", values)
    w = periodic_weights(p)
    if f.shape != p.shape:
        raise ParameterError("values", f"array of shape {f.shape}",
                             f"must have the shape of phi {p.shape}")
    if int(k) != k or k < 1 or 2 * k + 1 > p.size:
        raise ParameterError("k", k, f"must be an integer in [1, {(p.size - 1) // 2}]")
    j = np.arange(1, int(k) + 1)
    cols = [np.ones_like(p)]
    cols += [np.cos(jj * p) for jj in j] + [np.sin(jj * p) for jj in j]
    A = np.stack(cols, axis=-1) * np.sqrt(w)[:, None]
    coef = np.linalg.lstsq(A, f * np.sqrt(w), rcond=None)[0]
    a, b = coef[1:k + 1], coef[k + 1:]
    return Harmonics(j, float(coef[0]), a, b, np.hypot(a, b), np.arctan2(b, a))
