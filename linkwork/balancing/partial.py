"""Partial dynamic balancing by moving the crank counterweight's axis (paper 001).

A force-balanced mechanism (:mod:`linkwork.balancing.static`) still shakes its frame with a
moment. Dzhavakhyan and Arakelyan [1]_ keep the crank counterweight (static moment
:math:`S = m_{cw} r_{cw}`, on the crank's extension opposite the crank pin, turning with the crank
at the same angle :math:`\\varphi`) but move its rotation axis from the crank axis O to a point
:math:`O_1(x, y)` fixed to the frame (the counterweight is then driven at the crank's angle, e.g.
by a 1:1 gear pair or a parallel crank). The total centre of mass only shifts by the constant
:math:`m_{cw}(x, y)`, so force balance is kept, and the counterweight's inertia force adds the
moment about O

.. math::

    M_{yp} = S\\,[\\omega^2 (y\\cos\\varphi - x\\sin\\varphi)
             + \\varepsilon (x\\cos\\varphi + y\\sin\\varphi)],

which is linear in :math:`(x, y)`. The second term (crank angular acceleration
:math:`\\varepsilon \\ne 0`) is not in [1]_ and is derived here. ``(x, y)`` is then chosen to
cancel the residual shaking moment :math:`M(\\varphi)` as well as possible:

* :func:`counterweight_axis_offset` -- least squares over a given set of positions (the paper's
  criterion, minimum of :math:`\\sum (M_i + M_{yp,i})^2`), solved exactly for any positions;
  ``method="paper"`` evaluates the paper's closed form (1), which drops
  :math:`\\sum \\sin\\varphi_i\\cos\\varphi_i` and is exact only when that sum is zero;
* :func:`first_harmonic_offset` -- cancel the first harmonic of the residual moment over a cycle
  (the method of Shengelyakyan, ref. [7] of [1]_);
* :func:`rms_offset` -- minimise the continuous RMS over a full cycle.

Convention: x, y in the frame's coordinates with origin at the crank axis O, angles
counter-clockwise from the x axis, :math:`\\varphi` the crank angle whose counterweight points
along :math:`\\varphi + \\pi`, moments counter-clockwise positive. The moment is the moment of the
inertia forces (the shaking moment exerted on the frame), as in the paper's table.

References
----------
.. [1] Dzhavakhyan R. P., Arakelyan V. G. Partial dynamic balancing of mechanisms (in Russian).
   Izv. AN ArmSSR, ser. III (Mashinostroenie), 1988, vol. XLII, no. 1.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_positive
from linkwork.cycles import periodic_weights  # moved to linkwork.cycles; importable here
from linkwork.errors import ParameterError
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "AxisOffset",
    "counterweight_axis_moment",
    "counterweight_axis_offset",
    "efficiency",
    "first_harmonic_offset",
    "periodic_weights",
    "rms_offset",
]

TWO_PI = 2.0 * np.pi


@dataclass(frozen=True)
class AxisOffset(Result):
    """Position of the moved counterweight axis O1 and the residual moment it leaves.

    Attributes
    ----------
    x, y : float
        Coordinates of O1 relative to the crank axis O [m].
    phi1 : ndarray
        Crank angles used [rad].
    moment : ndarray
        Residual moment before the axis is moved [N·m].
    residual : ndarray
        Residual moment after: ``moment + M_yp`` [N·m].
    method : str
        ``"lsq"``, ``"paper"``, ``"first_harmonic"`` or ``"rms"``.
    """

    x: float
    y: float
    phi1: np.ndarray
    moment: np.ndarray
    residual: np.ndarray
    method: str
    units: ClassVar[dict[str, str]] = {"x": "m", "y": "m", "phi1": "rad", "moment": "N*m",
                                       "residual": "N*m"}

    @property
    def offset(self) -> tuple[float, float]:
        """``(x, y)`` [m]."""
        return (self.x, self.y)

    def __iter__(self) -> Iterator[float]:
        """Unpack as ``x, y = counterweight_axis_offset(...)``."""
        return iter((self.x, self.y))

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Residual moment before and after moving the axis: a :class:`linkwork.plot.Figure`
        with 1 axes."""
        from linkwork.plot.balancing import axis_offset_figure

        return axis_offset_figure(self, ax=ax, **kw)


def counterweight_axis_moment(phi: ArrayLike, x: ArrayLike, y: ArrayLike,
                              static_moment: ArrayLike, omega: ArrayLike,
                              eps: ArrayLike = 0.0) -> np.ndarray:
    """Extra moment about O of the crank counterweight whose axis is moved to O1(x, y).

    .. math::

        M_{yp} = S\\,[\\omega^2 (y\\cos\\varphi - x\\sin\\varphi)
                 + \\varepsilon (x\\cos\\varphi + y\\sin\\varphi)]

    Derivation: the counterweight's centre is at :math:`O_1 + r\\,u`, with
    :math:`u = -(\\cos\\varphi, \\sin\\varphi)`; its inertia force is
    :math:`-m\\,r(\\varepsilon\\,k\\times u - \\omega^2 u)`. The moment of that force about O minus
    its moment when O1 = O is :math:`O_1 \\times F`, which is the expression above. The first
    term is the paper's :math:`M_{yp}` (its printed form
    :math:`S r_{cp}(\\dot\\varphi\\cos\\varphi - \\ddot\\varphi\\sin\\varphi)` is damaged; see
    ``docs/errata.md``), the second is new.

    Parameters
    ----------
    phi : array_like
        Crank angle [rad], counter-clockwise from the x axis.
    x, y : array_like
        Axis O1 relative to O [m].
    static_moment : array_like
        :math:`S = m_{cw} r_{cw}` of the counterweight about its own axis [kg·m].
    omega, eps : array_like
        Crank angular velocity [rad/s] and acceleration [rad/s²], counter-clockwise positive.

    Returns
    -------
    ndarray
        Moment of the counterweight's inertia force about O added by the shift [N·m],
        counter-clockwise positive; broadcast shape of the inputs.
    """
    p = np.asarray(phi, dtype=float)
    c, s = np.cos(p), np.sin(p)
    w2 = np.asarray(omega, dtype=float) ** 2
    e = np.asarray(eps, dtype=float)
    xa, ya = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    S = np.asarray(static_moment, dtype=float)
    return S * (w2 * (ya * c - xa * s) + e * (xa * c + ya * s))


def _basis(phi: np.ndarray, static_moment: float, omega: np.ndarray,
           eps: np.ndarray) -> np.ndarray:
    """Columns d M_yp / dx, d M_yp / dy at each position, shape (n, 2)."""
    c, s = np.cos(phi), np.sin(phi)
    w2 = omega**2
    return static_moment * np.stack([-w2 * s + eps * c, w2 * c + eps * s], axis=-1)


def _check(phi: ArrayLike, moment: ArrayLike, static_moment: float, omega: ArrayLike,
           eps: ArrayLike) -> tuple[np.ndarray, np.ndarray, float, np.ndarray, np.ndarray]:
    p = require_finite("phi", phi)
    m = require_finite("moment", moment)
    if p.ndim != 1:
        raise ParameterError("phi", f"array of shape {p.shape}", "must be one-dimensional")
    if m.shape != p.shape:
        raise ParameterError("moment", f"array of shape {m.shape}",
                             f"must have the shape of phi {p.shape}")
    S = float(require_positive("static_moment", static_moment))
    w = np.broadcast_to(require_finite("omega", omega), p.shape).astype(float)
    e = np.broadcast_to(require_finite("eps", eps), p.shape).astype(float)
    if p.size and not (np.any(w != 0.0) or np.any(e != 0.0)):
        raise ParameterError("omega", 0.0, "must be non-zero (or eps non-zero): a counterweight "
                             "that does not move adds no moment, whatever its axis")
    return p, m, S, w, e


def counterweight_axis_offset(phi: ArrayLike, moment: ArrayLike, static_moment: float,
                              omega: ArrayLike, eps: ArrayLike = 0.0, *,
                              weights: ArrayLike | None = None,
                              method: str = "lsq") -> AxisOffset:
    """Axis O1(x, y) of the crank counterweight minimising the residual shaking moment.

    Minimises :math:`I = \\sum_i w_i (M_i + M_{yp,i})^2` over the given positions (Eq. before
    (1) in [1]_, with weights :math:`w_i = 1`), where :math:`M_{yp}` is
    :func:`counterweight_axis_moment`. ``I`` is quadratic in (x, y), so the minimum is the
    linear least-squares solution, exact for any set of positions (also when
    :math:`\\varepsilon \\ne 0` or :math:`\\omega` varies).

    ``method="paper"`` evaluates the closed form (1) of [1]_,

    .. math::

        x = \\frac{\\sum M_i \\sin\\varphi_i}{S\\omega^2 \\sum \\sin^2\\varphi_i},\\qquad
        y = -\\frac{\\sum M_i \\cos\\varphi_i}{S\\omega^2 \\sum \\cos^2\\varphi_i},

    derived from the normal equations by assuming :math:`\\sum\\sin\\varphi_i\\cos\\varphi_i = 0`
    (true for N >= 3 positions evenly spaced over a full turn, false in general) and
    :math:`\\varepsilon = 0`, constant :math:`\\omega`; it is offered to reproduce the paper.

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angles of the positions [rad].
    moment : array_like, shape (n,)
        Residual shaking moment at those positions before the shift (after force balancing)
        [N·m], counter-clockwise positive.
    static_moment : float
        S of the crank counterweight [kg·m], > 0.
    omega : array_like
        Crank angular velocity [rad/s], scalar or shape (n,).
    eps : array_like, optional
        Crank angular acceleration [rad/s²], scalar or shape (n,); default 0.
    weights : array_like, optional
        Non-negative weights :math:`w_i` (e.g. quadrature weights); default all 1.
    method : {"lsq", "paper"}
        Exact least squares (default) or the paper's formula (1).

    Returns
    -------
    AxisOffset

    Raises
    ------
    ParameterError
        Bad shapes or values, or positions that do not determine (x, y) (e.g. fewer than two
        independent positions).

    References
    ----------
    .. [1] Dzhavakhyan R. P., Arakelyan V. G. Partial dynamic balancing of mechanisms. Izv. AN
       ArmSSR, ser. III, 1988, vol. XLII, no. 1, formula (1).
    """
    p, m, S, w, e = _check(phi, moment, static_moment, omega, eps)
    if weights is None:
        wt = np.ones_like(p)
    else:
        wt = np.broadcast_to(require_positive("weights", weights, allow_zero=True), p.shape)
    if method == "paper":
        if np.any(e != 0.0) or np.ptp(w) > 0.0 or w[0] == 0.0:
            raise ParameterError("method", "paper",
                                 "formula (1) assumes eps = 0 and a constant omega != 0; "
                                 "use 'lsq'")
        s, c = np.sin(p), np.cos(p)
        ss, cc = np.sum(wt * s * s), np.sum(wt * c * c)
        if ss == 0.0 or cc == 0.0:
            raise ParameterError("phi", "positions", "sum of sin^2 and cos^2 must be > 0")
        sw2 = S * w[0] ** 2
        x = float(np.sum(wt * m * s) / (sw2 * ss))
        y = float(-np.sum(wt * m * c) / (sw2 * cc))
    elif method == "lsq":
        A = _basis(p, S, w, e) * np.sqrt(wt)[:, None]
        b = -m * np.sqrt(wt)
        sv = np.linalg.svd(A, compute_uv=False)
        if sv.size < 2 or sv[-1] <= 1e-12 * max(sv[0], 1e-300):
            raise ParameterError("phi", f"{p.size} positions",
                                 "must include at least two positions that determine (x, y)")
        sol = np.linalg.lstsq(A, b, rcond=None)[0]
        x, y = float(sol[0]), float(sol[1])
    else:
        raise ParameterError("method", method, "must be 'lsq' or 'paper'")
    res = m + counterweight_axis_moment(p, x, y, S, w, e)
    return AxisOffset(x, y, p, m, res, method)


def rms_offset(phi: ArrayLike, moment: ArrayLike, static_moment: float, omega: ArrayLike,
               eps: ArrayLike = 0.0) -> AxisOffset:
    """Axis O1(x, y) minimising the continuous RMS of the residual moment over a full cycle.

    Minimises :math:`\\int_0^{2\\pi} (M + M_{yp})^2\\,d\\varphi`, evaluated with
    :func:`periodic_weights` from samples covering one cycle. With :math:`\\varepsilon = 0` and
    constant :math:`\\omega`, :math:`M_{yp}` is a pure first harmonic, so by orthogonality this
    coincides with :func:`first_harmonic_offset` (tested); they differ when the crank speed
    varies.

    Parameters are those of :func:`counterweight_axis_offset`; ``phi`` must sample one full
    cycle (strictly increasing, without repeating the first sample).
    """
    p, m, S, w, e = _check(phi, moment, static_moment, omega, eps)
    r = counterweight_axis_offset(p, m, S, w, e, weights=periodic_weights(p))
    return AxisOffset(r.x, r.y, r.phi1, r.moment, r.residual, "rms")


def first_harmonic_offset(phi: ArrayLike, moment: ArrayLike, static_moment: float,
                          omega: ArrayLike, eps: ArrayLike = 0.0) -> AxisOffset:
    """Axis O1(x, y) that cancels the first harmonic of the residual moment over a cycle.

    The first Fourier coefficients of :math:`M + M_{yp}` in the crank angle are set to zero:

    .. math::

        \\int_0^{2\\pi} (M + M_{yp}) \\cos\\varphi\\,d\\varphi = 0, \\qquad
        \\int_0^{2\\pi} (M + M_{yp}) \\sin\\varphi\\,d\\varphi = 0,

    a 2x2 linear system in (x, y). At constant :math:`\\omega` and :math:`\\varepsilon = 0` it
    reduces to :math:`x = b_1/(S\\omega^2)`, :math:`y = -a_1/(S\\omega^2)` with
    :math:`M \\approx a_1\\cos\\varphi + b_1\\sin\\varphi + \\dots` (the method of ref. [7] of
    paper 001 as the paper describes it).

    Parameters are those of :func:`rms_offset` (samples of one full cycle).
    """
    p, m, S, w, e = _check(phi, moment, static_moment, omega, eps)
    q = periodic_weights(p)
    B = _basis(p, S, w, e)
    H = np.stack([np.cos(p), np.sin(p)], axis=-1) * q[:, None]
    lhs = H.T @ B
    rhs = -H.T @ m
    if abs(np.linalg.det(lhs)) <= 1e-12 * max(np.abs(lhs).max() ** 2, 1e-300):
        raise ParameterError("omega", "samples", "the first harmonic of M_yp is degenerate")
    x, y = np.linalg.solve(lhs, rhs)
    res = m + counterweight_axis_moment(p, x, y, S, w, e)
    return AxisOffset(float(x), float(y), p, m, res, "first_harmonic")


def efficiency(before: ArrayLike, after: ArrayLike) -> float:
    """Balancing efficiency R_j of paper 001: reduction of the peak residual moment [%].

    .. math::

        R_j = \\frac{\\max|\\Delta M_1(\\varphi)| - \\max|\\Delta M_j(\\varphi)|}
                   {\\max|\\Delta M_1(\\varphi)|}\\cdot 100\\,\\%

    with :math:`\\Delta M_1` the residual moment after static balancing (``before``) and
    :math:`\\Delta M_j` after the moment balancing j (``after``). The printed formula of [1]_ is
    garbled (a "+" between the maxima and the wrong denominator); this form reproduces both
    printed values of the paper's table (36.9 % and 53.9 %) from the table's own columns, see
    ``docs/errata.md``. Negative when balancing raises the peak.

    Parameters
    ----------
    before, after : array_like
        Moments at the same positions [N·m] (any shape; the maxima are over all elements).

    Returns
    -------
    float
        R_j [%].
    """
    b = require_finite("before", before)
    a = require_finite("after", after)
    if b.size == 0 or a.size == 0:
        raise ParameterError("before", "empty", "must contain at least one value")
    peak = float(np.max(np.abs(b)))
    if peak == 0.0:
        raise ParameterError("before", 0.0, "peak |moment| must be > 0")
    return (peak - float(np.max(np.abs(a)))) / peak * 100.0
