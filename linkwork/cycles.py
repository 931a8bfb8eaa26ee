"""Statistics of a quantity sampled over one cycle of the driver: RMS, peak, harmonics, means.

Every function works on arrays sampled over the driver positions, whatever produced them (the
planar engine, a closed-form model, measurements); positions are the last (for vectors, the
first) axis as documented per function. Integrals over a full cycle use the periodic trapezoid
rule (:func:`periodic_weights`), which is exact for trigonometric polynomials of degree < n on
evenly spaced samples; a mean over an open driver range (a linear driver, a part of a
revolution) uses the ordinary trapezoid rule (:func:`mean_over_range`).

The functions were gathered here from :mod:`linkwork.balancing.loads` (``rms``, ``peak``,
``harmonics``, ``Harmonics``, ``mean_over_range``) and :mod:`linkwork.balancing.partial`
(``periodic_weights``); those names stay importable there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import ParameterError
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "Harmonics",
    "harmonics",
    "mean_over_range",
    "peak",
    "peak_at",
    "periodic_weights",
    "rms",
]

TWO_PI = 2.0 * np.pi


def periodic_weights(phi: ArrayLike) -> np.ndarray:
    """Trapezoid weights [rad] of a periodic function sampled once over a full cycle.

    ``phi`` must be strictly increasing and span less than one turn (the last sample is not the
    first one repeated); the weight of sample i is half the distance to its neighbours, with
    the wrap-around from the last back to the first. The weights sum to :math:`2\\pi`. For
    evenly spaced samples this is the rectangle rule, exact for trigonometric polynomials of
    degree < n.
    """
    p = require_finite("phi", phi)
    if p.ndim != 1 or p.size < 3:
        raise ParameterError("phi", f"{p.size} samples", "must be >= 3 samples of one cycle")
    d = np.diff(p)
    if np.any(d <= 0.0):
        raise ParameterError("phi", "samples", "must be strictly increasing")
    span = p[-1] - p[0]
    if span >= TWO_PI - 1e-12:
        raise ParameterError("phi", f"span {span:.6g} rad",
                             "must be < 2*pi (do not repeat the first sample at the end)")
    gaps = np.append(d, TWO_PI - span)
    return 0.5 * (gaps + np.roll(gaps, 1))


def _magnitude(values: np.ndarray, vector: bool | None) -> np.ndarray:
    """|f|: the norm of (n, 2) vectors (``vector`` True, or None and that shape), else f."""
    if vector is None:
        vector = values.ndim == 2 and values.shape[-1] == 2
    return np.hypot(values[..., 0], values[..., 1]) if vector else values


def rms(phi: ArrayLike, values: ArrayLike, *, vector: bool | None = None) -> float:
    """Continuous RMS over one full cycle of the crank angle.

    :math:`\\sqrt{\\frac{1}{2\\pi}\\int_0^{2\\pi} f^2\\,d\\varphi}` by the periodic trapezoid rule
    (:func:`periodic_weights`); for a vector quantity (shape (n, 2), e.g. the shaking force) f
    is its magnitude.

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
    closed cycle sampled with its end repeating its start counts that position once; the
    sample itself if there is a single position. NaN (undefined) if a sample is NaN: the work
    over a range where the value is undefined somewhere (a self-locking or unassembled
    position) is undefined, and the mean of the other samples would be another quantity (a
    press's driving torque without its locked phase can even average negative)."""
    q, p = np.asarray(values, dtype=float), np.asarray(phi1, dtype=float)
    if not np.all(np.isfinite(q)) or q.size == 0:
        return float("nan")
    if q.size > 1 and p[-1] != p[0]:
        return float(np.trapezoid(q, p) / (p[-1] - p[0]))
    return float(np.mean(q))


def peak(values: ArrayLike, *, vector: bool | None = None) -> float:
    """Largest magnitude over the samples (|f| or the vector norm) [unit of ``values``]."""
    f = _magnitude(require_finite("values", values), vector)
    if f.size == 0:
        raise ParameterError("values", "empty", "must contain at least one value")
    return float(np.max(np.abs(f)))


def peak_at(phi: ArrayLike, values: ArrayLike, *, vector: bool | None = None
            ) -> tuple[float, float]:
    """The peak of :func:`peak` and the driver position where it occurs (the first, if several).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Driver positions [rad or m].
    values : array_like, shape (n,) or (n, 2)
    vector : bool, optional
        As for :func:`rms`.

    Returns
    -------
    value, position : float
        Largest |f| [unit of ``values``] and ``phi`` at that sample.
    """
    p = require_finite("phi", phi)
    f = np.abs(_magnitude(require_finite("values", values), vector))
    if f.size == 0:
        raise ParameterError("values", "empty", "must contain at least one value")
    if f.shape != p.shape:
        raise ParameterError("values", f"array of shape {f.shape}",
                             f"must have {p.size} positions like phi")
    i = int(np.argmax(f))
    return float(f[i]), float(p[i])


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

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Amplitudes over the harmonic order, the mean as a line: a
        :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.balancing import harmonics_figure

        return harmonics_figure(self, ax=ax, **kw)


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
