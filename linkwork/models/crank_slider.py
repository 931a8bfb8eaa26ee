"""Offset crank-slider: the idle mode of the variable-structure sine press drive (paper 000).

Geometry and conventions (Fig. 1 and Eqs. (1)-(13) in [1]_)
------------------------------------------------------------
* Frame ``AXY`` with origin at the crank axis ``A``; ``X`` to the right, ``Y`` up.
* Crank ``AB`` of length ``L1``; the crank angle ``phi1`` is measured from ``+X``,
  counter-clockwise positive: ``B = L1 (cos phi1, sin phi1)``.
* Rod ``BC`` of length ``L2 = lambda2 L1``.
* The slider ``C`` runs in a guide parallel to ``AY`` at ``X = e = lambda_e L1`` (``lambda_e``
  may be negative: guide left of ``A``).  ``Y_C`` is the slider position along ``+Y`` measured from
  the line through ``A`` perpendicular to the guide.
* The rod angle ``phi2`` is the direction of the vector ``BC`` measured **from the guide direction
  +Y towards +X** (clockwise positive in the usual picture), as in Eq. (1):
  ``tan phi2 = (X_C - X_B) / (Y_C - Y_B)``, so ``BC = L2 (sin phi2, cos phi2)``.
* ``branch=+1`` is the ``+`` root of Eq. (2): the slider lies above the crank pin
  (``cos phi2 > 0``, ``phi2`` in (-pi/2, pi/2)); ``branch=-1`` is the mirror assembly
  (``cos phi2 < 0``, ``phi2 = pi - arcsin(sin phi2)`` in (pi/2, 3pi/2), continuous over the
  cycle).

Transfer functions are derivatives with respect to ``phi1`` ("analogues"); actual velocities and
accelerations follow from the crank speed ``omega1`` and the crank acceleration ``eps1``.

References
----------
.. [1] Toktakunov, Zh. Sh. Analytic determination of the kinematics of a variable-structure sine
   mechanism (paper 000 of the linkwork seed papers).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import (
    common_shape,
    finite_value,
    positive_value,
    require_branch,
    require_finite,
    require_positive,
)
from linkwork.errors import AssemblyError, ParameterError, angle_ranges
from linkwork.results import Result, all_true

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "CrankSliderResult",
    "DeadCentres",
    "assembly_limit",
    "dead_centres",
    "max_pressure_angle",
    "offset_crank_slider",
    "pressure_angle",
    "stroke",
]

#: ``|cos phi2|`` at or below this value counts as a locked position (rod perpendicular to the
#: guide): the transfer functions are unbounded there.
COS_PHI2_MIN = 1e-7

_min = np.minimum.reduce


@dataclass(frozen=True)
class CrankSliderResult(Result):
    """Kinematics of the offset crank-slider over crank positions.

    All arrays broadcast to the common shape of the inputs (designs on leading axes, crank
    positions on the last one).  Names follow [1]_; units in :attr:`units`.

    Attributes
    ----------
    phi1 : crank angle [rad], from +X, counter-clockwise.
    L1, lambda2, lambda_e, omega1, eps1, branch : the inputs (Python floats for one design,
        arrays for several).
    X_B, Y_B : crank-pin coordinates [m], Eq. (2).
    X_C, Y_C : slider coordinates [m]; ``X_C = e``; ``Y_C`` is Eq. (5) (for ``branch=+1``).
    phi2 : rod angle [rad] from +Y towards +X, Eqs. (1), (3), (4); in (-pi/2, pi/2) for
        ``branch=+1``, in (pi/2, 3 pi/2) for ``branch=-1``.
    U21 : ``d phi2 / d phi1`` [-], Eq. (6).
    V_qC : ``d Y_C / d phi1`` [m/rad], Eqs. (7), (8).
    eps_q2 : ``d U21 / d phi1`` [1/rad], the angular-acceleration analogue, Eq. (11).
    a_qC : ``d^2 Y_C / d phi1^2`` [m/rad^2], the acceleration analogue of the slider.
    omega2 : rod angular velocity ``d phi2 / dt`` [rad/s] (positive in the sense of ``phi2``).
    eps2 : rod angular acceleration [rad/s^2], Eqs. (10), (12).
    V_C : slider velocity along +Y [m/s].
    a_C : slider acceleration along +Y [m/s^2], Eq. (13) (corrected, see docs/errata.md).
    pressure_angle : acute angle between the rod and the guide [rad], ``arcsin |sin phi2|``.
    valid : False where the mechanism cannot be assembled (only with ``on_failure="nan"``).
    """

    phi1: np.ndarray
    L1: np.ndarray | float
    lambda2: np.ndarray | float
    lambda_e: np.ndarray | float
    omega1: np.ndarray | float
    eps1: np.ndarray | float
    branch: int
    X_B: np.ndarray
    Y_B: np.ndarray
    X_C: np.ndarray
    Y_C: np.ndarray
    phi2: np.ndarray
    U21: np.ndarray
    V_qC: np.ndarray
    eps_q2: np.ndarray
    a_qC: np.ndarray
    omega2: np.ndarray
    eps2: np.ndarray
    V_C: np.ndarray
    a_C: np.ndarray
    pressure_angle: np.ndarray
    valid: np.ndarray

    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "L1": "m", "lambda2": "1", "lambda_e": "1", "omega1": "rad/s",
        "eps1": "rad/s^2", "branch": "1", "X_B": "m", "Y_B": "m", "X_C": "m", "Y_C": "m",
        "phi2": "rad", "U21": "1", "V_qC": "m/rad", "eps_q2": "1/rad", "a_qC": "m/rad^2",
        "omega2": "rad/s", "eps2": "rad/s^2", "V_C": "m/s", "a_C": "m/s^2",
        "pressure_angle": "rad", "valid": "1",
    }

    def _scene(self) -> Any:
        """The crank-slider drawn over the crank angles (one design only; None for several)."""
        if np.ndim(self.phi1) != 1 or np.ndim(self.L1) or np.ndim(self.lambda2) \
                or np.ndim(self.lambda_e):
            return None
        from linkwork.plot.scene import crank_slider_scene

        return crank_slider_scene(self)

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Slider position, velocity and acceleration over the crank angle (1-D results): a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.sine import crank_slider_figure

        return crank_slider_figure(self, axes=axes, **kw)


class DeadCentres(NamedTuple):
    """Crank angles [rad, in [0, 2 pi)] of the slider's extreme positions."""

    phi1_top: np.ndarray
    """Crank angle where ``Y_C`` is largest."""
    phi1_bottom: np.ndarray
    """Crank angle where ``Y_C`` is smallest."""


def assembly_limit(lambda_e: ArrayLike) -> np.ndarray:
    """Smallest ``lambda2`` that lets the crank turn fully: ``|lambda_e| + 1`` (exclusive).

    At ``lambda2 = |lambda_e| + 1`` the rod becomes perpendicular to the guide at one crank
    position (a locked position with unbounded transfer functions), so a fully rotating crank
    needs ``lambda2 > |lambda_e| + 1``.
    """
    return np.abs(require_finite("lambda_e", lambda_e)) + 1.0  # None or NaN was a NaN limit



def offset_crank_slider(phi1: ArrayLike, L1: ArrayLike, lambda2: ArrayLike, lambda_e: ArrayLike,
                        omega1: ArrayLike = 1.0, eps1: ArrayLike = 0.0, branch: int = +1, *,
                        on_failure: Literal["raise", "nan"] = "raise") -> CrankSliderResult:
    r"""Positions, transfer functions, velocities and accelerations of the offset crank-slider.

    Parameters
    ----------
    phi1 : array_like
        Crank angle [rad], from +X, counter-clockwise.  Shape ``(n,)`` typically.
    L1 : array_like
        Crank length [m], > 0.  May be ``(m, 1)`` to sweep designs.
    lambda2 : array_like
        Relative rod length ``L2 / L1`` [-], > 0.
    lambda_e : array_like
        Relative guide offset ``e / L1`` [-] (signed; the guide is the line ``X = e``).
    omega1 : array_like, optional
        Crank angular velocity [rad/s] (counter-clockwise positive).  Default 1, which makes
        ``V_C == V_qC`` and ``a_C == a_qC``.
    eps1 : array_like, optional
        Crank angular acceleration [rad/s^2].  Default 0.
    branch : {+1, -1}, optional
        Assembly branch: ``+1`` is the ``+`` root of Eq. (2) in [1]_ (slider above the pin).
    on_failure : {"raise", "nan"}, optional
        What to do at positions where the mechanism cannot be assembled
        (``|lambda_e - cos phi1| >= lambda2``): raise :class:`~linkwork.errors.AssemblyError`
        listing the crank-angle ranges (default), or return NaN there with ``valid`` False.

    Returns
    -------
    CrankSliderResult

    Raises
    ------
    ParameterError
        ``L1 <= 0``, ``lambda2 <= 0``, non-finite input or a branch other than +/-1.
    AssemblyError
        Some positions cannot be assembled (the rod is too short to reach the guide) or the rod
        is perpendicular to the guide (locked position); the message lists the crank-angle
        ranges.  With ``lambda2 > |lambda_e| + 1`` every crank angle assembles.

    Notes
    -----
    With :math:`s_2 = \sin\varphi_2`, :math:`c_2 = \cos\varphi_2` (Eqs. (1)-(4) in [1]_):

    .. math::

        s_2 = \frac{\lambda_e - \cos\varphi_1}{\lambda_2}, \qquad
        c_2 = \pm\sqrt{1 - s_2^2}, \qquad
        Y_C = L_1(\sin\varphi_1 + \lambda_2 c_2)

    Transfer functions (Eqs. (6), (8), (11) in [1]_; the last printed form of
    :math:`\varepsilon_{q2}` lacks a square, see ``docs/errata.md``):

    .. math::

        U_{21} = \frac{\sin\varphi_1}{\lambda_2 c_2}, \qquad
        V_{qC} = L_1\frac{\cos(\varphi_1+\varphi_2)}{c_2}, \qquad
        \varepsilon_{q2} = \frac{\cos\varphi_1 + \lambda_2 s_2 U_{21}^2}{\lambda_2 c_2}

    .. math::

        a_{qC} = \frac{d^2Y_C}{d\varphi_1^2}
               = -\frac{L_1}{c_2}\left[\sin(\varphi_1+\varphi_2)
                 + \frac{\sin^2\varphi_1}{\lambda_2 c_2^2}\right]

    and with the crank speed (Eqs. (10), (12); Eq. (13) corrected):

    .. math::

        \omega_2 = U_{21}\omega_1, \quad
        \varepsilon_2 = U_{21}\varepsilon_1 + \varepsilon_{q2}\omega_1^2, \quad
        V_C = V_{qC}\omega_1, \quad
        a_C = V_{qC}\varepsilon_1 + a_{qC}\omega_1^2

    Eq. (13) of [1]_ prints :math:`\cos(\varphi_2-\varphi_1)`, :math:`+\sin(\varphi_2-\varphi_1)`
    and :math:`+\sin^2\varphi_1/(\lambda_2\cos^2\varphi_2)` in the bracket; the derivation (and
    finite differences) give :math:`\cos(\varphi_1+\varphi_2)`, :math:`-\sin(\varphi_1+\varphi_2)`
    and :math:`-\sin^2\varphi_1/(\lambda_2\cos^2\varphi_2)`.  The corrected form is used here.

    References
    ----------
    .. [1] Toktakunov, Zh. Sh. Analytic determination of the kinematics of a variable-structure
       sine mechanism (paper 000).
    """
    # Each argument is checked once, by the named checks of linkwork.checks; for the common call
    # (one design in Python numbers, a float64 array of angles) they cost plain comparisons
    # (Python floats stay floats: a 0-d array costs ~0.5 us per arithmetic operation).
    branch = require_branch(branch)
    if on_failure not in ("raise", "nan"):
        raise ParameterError("on_failure", on_failure, "must be 'raise' or 'nan'")
    phi1_a = require_finite("phi1", phi1)
    L1_v = positive_value("L1", L1)
    lam2 = positive_value("lambda2", lambda2)
    lame = finite_value("lambda_e", lambda_e)
    w1 = finite_value("omega1", omega1)
    e1 = finite_value("eps1", eps1)
    if type(L1_v) is float and type(lam2) is float and type(lame) is float \
            and type(w1) is float and type(e1) is float:
        shape = phi1_a.shape  # one design: the outputs have the shape of the angles
        phi1_b = phi1_a
    else:
        shape = common_shape(phi1=phi1_a, L1=np.asarray(L1_v), lambda2=np.asarray(lam2),
                             lambda_e=np.asarray(lame), omega1=np.asarray(w1),
                             eps1=np.asarray(e1))
        # Every output depends on phi1, so broadcasting phi1 alone to the common shape makes
        # every output that shape; the parameters broadcast in the arithmetic (no copies).
        phi1_b = phi1_a if phi1_a.shape == shape else np.broadcast_to(phi1_a, shape)

    def fail(bad: np.ndarray) -> None:
        if on_failure == "raise":
            _raise_assembly(phi1_a, bad, lam2, lame)

    res = _evaluate(phi1_b, shape, L1_v, lam2, lame, w1, e1, branch, fail)
    assert res is not None
    return res


def _evaluate(phi1: np.ndarray, shape: tuple[int, ...], L1: Any, lam2: Any, lame: Any, w1: Any,
              e1: Any, branch: int,
              fail: Callable[[np.ndarray], None] | None) -> CrankSliderResult | None:
    """The kinematics proper, on checked arguments (floats, or arrays broadcasting to ``shape``).

    Positions that do not assemble: with ``fail`` None return None (the caller re-checks on the
    general path); otherwise ``fail(bad)`` raises, or they become NaN with ``valid`` False.
    """
    c1 = np.cos(phi1)
    s1 = np.sin(phi1)
    rl2 = 1.0 / lam2
    d = lame - c1                                    # lambda2 sin(phi2)
    s2 = d * rl2
    c2sq = 1.0 - s2 * s2
    # one reduction is cheaper than a mask when every position assembles (the usual case)
    if c2sq.size == 0 or _min(c2sq, axis=None) > COS_PHI2_MIN**2:
        valid = all_true(shape)
    elif fail is None:
        return None
    else:
        bad = c2sq <= COS_PHI2_MIN**2
        fail(bad)
        d = np.where(bad, np.nan, d)
        s2 = np.where(bad, np.nan, s2)
        c2sq = np.where(bad, np.nan, c2sq)
        valid = ~bad
    c2 = np.sqrt(c2sq)
    phi2 = np.arcsin(s2)
    mu = np.abs(phi2)                                # arcsin |s2|: the same on both branches
    if branch == -1:
        c2 = -c2
        phi2 = np.pi - phi2
    # The transfer functions are evaluated as the derivatives of Y_C = L1 sin(phi1) + L2 c2,
    # X_C - X_B = L2 s2 (algebraically the paper's Eqs. (6), (8), (11) and corrected (13), see
    # the Notes), in fewer array operations (and multiplications rather than divisions).
    X_B = L1 * c1
    Y_B = L1 * s1
    L2c2 = (L1 * lam2) * c2
    Y_C = Y_B + L2c2
    X_C = np.empty(shape)
    X_C[...] = L1 * lame
    inv = rl2 / c2                                   # 1 / (lambda2 cos(phi2))
    U21 = s1 * inv
    U21sq = U21 * U21
    nL2s2 = (-L1) * d                                # -L2 sin(phi2)
    V_qC = nL2s2 * U21                               # L1 cos(phi1+phi2) / c2
    V_qC += X_B
    eps_q2 = d * U21sq
    eps_q2 += c1
    eps_q2 *= inv
    a_qC = nL2s2 * eps_q2                            # d V_qC / d phi1
    t = L2c2 * U21sq
    t += Y_B
    a_qC -= t
    w1sq = w1 * w1
    omega2 = U21 * w1
    V_C = V_qC * w1
    eps2 = eps_q2 * w1sq
    a_C = a_qC * w1sq
    if not (type(e1) is float and e1 == 0.0):
        eps2 += U21 * e1
        a_C += V_qC * e1
    return CrankSliderResult._assemble({
        "phi1": phi1, "L1": L1, "lambda2": lam2, "lambda_e": lame, "omega1": w1, "eps1": e1,
        "branch": branch, "X_B": X_B, "Y_B": Y_B, "X_C": X_C, "Y_C": Y_C, "phi2": phi2,
        "U21": U21, "V_qC": V_qC, "eps_q2": eps_q2, "a_qC": a_qC, "omega2": omega2,
        "eps2": eps2, "V_C": V_C, "a_C": a_C, "pressure_angle": mu, "valid": valid,
    })


def _raise_assembly(phi1: np.ndarray, bad: np.ndarray, lam2: Any, lame: Any) -> None:
    if phi1.ndim <= 1 and phi1.size > 1:
        order = np.argsort(phi1)
        per_angle = np.asarray(bad.reshape(-1, bad.shape[-1]).any(axis=0))
        ranges = angle_ranges(phi1[order], per_angle[order])
    else:
        vals = np.unique(np.broadcast_to(phi1, bad.shape)[bad])
        ranges = [(v, v) for v in vals[:8]]
    lam2, lame = np.asarray(lam2), np.asarray(lame)  # Python floats for one design
    shape = np.broadcast_shapes(lam2.shape, lame.shape)
    l2_all = np.broadcast_to(lam2, shape)
    lim_all = np.broadcast_to(assembly_limit(lame), shape)
    worst = np.unravel_index(np.argmin(l2_all - lim_all), shape)
    l2, lim = float(l2_all[worst]), float(lim_all[worst])
    raise AssemblyError(
        f"offset crank-slider cannot be assembled (rod does not reach the guide, or is "
        f"perpendicular to it): lambda2 = {l2:.6g}, a fully rotating crank needs "
        f"lambda2 > |lambda_e| + 1 = {lim:.6g}", ranges)


def _check_full_rotation(lambda2: ArrayLike, lambda_e: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    lam2 = require_positive("lambda2", lambda2)
    lame = require_finite("lambda_e", lambda_e)
    limit = assembly_limit(lame)
    bad = np.broadcast_to(lam2 <= limit, np.broadcast_shapes(lam2.shape, limit.shape))
    if bad.any():
        i = np.unravel_index(np.argmax(bad), bad.shape)
        raise ParameterError("lambda2", float(np.broadcast_to(lam2, bad.shape)[i]),
                             f"must be > |lambda_e| + 1 = "
                             f"{float(np.broadcast_to(limit, bad.shape)[i]):.6g} for a fully "
                             f"rotating crank")
    return lam2, lame


def stroke(L1: ArrayLike, lambda2: ArrayLike, lambda_e: ArrayLike) -> np.ndarray:
    r"""Slider stroke [m] of the offset crank-slider (the same for both branches).

    .. math::

        H = L_1\left[\sqrt{(\lambda_2+1)^2-\lambda_e^2} - \sqrt{(\lambda_2-1)^2-\lambda_e^2}\right]

    The extreme positions are the two dead centres where crank and rod are collinear
    (extended, ``|AC| = L2 + L1``, and folded, ``|AC| = L2 - L1``).

    Raises
    ------
    ParameterError
        ``L1 <= 0`` or ``lambda2 <= |lambda_e| + 1`` (no full crank rotation).
    """
    L1_a = require_positive("L1", L1)
    lam2, lame = _check_full_rotation(lambda2, lambda_e)
    return L1_a * (np.sqrt((lam2 + 1.0) ** 2 - lame**2) - np.sqrt((lam2 - 1.0) ** 2 - lame**2))


def dead_centres(lambda2: ArrayLike, lambda_e: ArrayLike, branch: int = +1) -> DeadCentres:
    """Crank angles [rad, in [0, 2 pi)] of the slider's extreme positions.

    Returns
    -------
    DeadCentres
        Named tuple ``(phi1_top, phi1_bottom)``: crank angles where ``Y_C`` is largest and
        smallest.  For ``branch=+1`` the top dead centre is the extended position (B between A
        and C) and the bottom one the folded position; for ``branch=-1`` the reverse.
        ``V_qC = 0`` at both (``cos(phi1 + phi2) = 0``).
    """
    branch = require_branch(branch)
    lam2, lame = _check_full_rotation(lambda2, lambda_e)
    y_ext = branch * np.sqrt((lam2 + 1.0) ** 2 - lame**2)  # C / L1 when extended
    y_fold = branch * np.sqrt((lam2 - 1.0) ** 2 - lame**2)  # C / L1 when folded
    phi_ext = np.mod(np.arctan2(y_ext, lame), 2 * np.pi)  # B along +AC
    phi_fold = np.mod(np.arctan2(-y_fold, -lame), 2 * np.pi)  # B along -AC
    if branch == 1:
        return DeadCentres(phi_ext, phi_fold)
    return DeadCentres(phi_fold, phi_ext)


def pressure_angle(phi1: ArrayLike, lambda2: ArrayLike, lambda_e: ArrayLike) -> np.ndarray:
    """Pressure angle [rad] at the slider: acute angle between the rod and the guide.

    The rod force acts along ``BC`` and the slider moves along the guide, so the pressure angle
    is ``arcsin |sin phi2| = arcsin(|lambda_e - cos phi1| / lambda2)``; it is the same on both
    branches.  Raises :class:`~linkwork.errors.AssemblyError` where the rod cannot reach the guide.
    """
    res = offset_crank_slider(phi1, 1.0, lambda2, lambda_e)
    return res.pressure_angle


def max_pressure_angle(lambda2: ArrayLike, lambda_e: ArrayLike) -> np.ndarray:
    """Largest pressure angle over a revolution [rad]: ``arcsin((|lambda_e| + 1) / lambda2)``.

    Reached at ``phi1 = pi`` for ``lambda_e >= 0`` and at ``phi1 = 0`` for ``lambda_e < 0``.
    """
    lam2, lame = _check_full_rotation(lambda2, lambda_e)
    return np.arcsin((np.abs(lame) + 1.0) / lam2)
