r"""Sine (Scotch-yoke) mechanism with an inclined slot: the working mode of paper 000.

Geometry and conventions (Figs. 3, 4 and Eqs. (14)-(21) in [1]_)
-----------------------------------------------------------------
* Frame with origin at the crank axis ``A``; ``x`` along the slider's line of motion, pointing
  where the crank points at ``phi1 = 0`` ("right horizontal position of the crank"); ``y`` up.
* Crank ``AB`` of length ``L1``; ``phi1`` from ``+x``, counter-clockwise positive:
  ``B = L1 (cos phi1, sin phi1)``.
* The block (link 2, "камень") is pinned to the crank at ``B`` and slides in a straight slot of
  the slider (link 3).  The slider translates along ``x``.
* ``alpha`` [rad], ``0 < alpha < pi``, is the angle between the slider's line of motion and the
  slot, measured counter-clockwise (the sense of ``phi1``) from the line of motion to the slot.
  ``alpha = pi/2`` is the classical sine mechanism (slot perpendicular to the motion).
  The slot direction is ``d = (cos alpha, sin alpha)``.
* ``X3`` is the slider displacement from its position at ``phi1 = 0``, positive **towards the
  crank axis** (along ``-x``), so that ``X3 = L1 (1 - cos phi1)`` at ``alpha = pi/2`` (Eq. (14)).
* ``X32`` is the position of the block in the slot, along ``d``, measured from the point of the
  slot on the line ``y = 0`` through ``A`` (``X32 = 0`` at ``phi1 = 0``; Eq. (14) at
  ``alpha = pi/2``).  ``V32``, ``a32`` are the block's velocity and acceleration relative to
  the slider, along ``d``.

Closed forms (derived; see ``docs/sine_press.md``):

.. math::

    X_3 = L_1\left(1-\cos\varphi_1+\frac{\sin\varphi_1}{\tan\alpha}\right)
        = \frac{L_1}{\sin\alpha}\left[\sin\alpha - \sin(\alpha-\varphi_1)\right], \qquad
    X_{32} = \frac{L_1\sin\varphi_1}{\sin\alpha}

The printed Eq. (19) of [1]_, :math:`X_3 = L_1(1-\cos\varphi_1)/\sin\alpha`, is the
displacement counted from the slider's extreme position with the crank angle counted from
the crank position at that extreme; it does not match the paper's own ``U31`` and ``a3``
(Eqs. (20), (21)), which agree with the form above.  See ``docs/errata.md``.

References
----------
.. [1] Toktakunov, Zh. Sh. Analytic determination of the kinematics of a variable-structure sine
   mechanism (paper 000 of the linkwork seed papers).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import common_shape, require_finite, require_in_range, require_positive
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "ExtremePositions",
    "ForceRatioCurve",
    "InclinedSlotResult",
    "alpha_for_stroke",
    "check_alpha",
    "extreme_positions",
    "force_ratio",
    "force_ratio_curve",
    "friction_angle",
    "inclined_slot",
    "stroke",
    "working_range",
]


@dataclass(frozen=True)
class InclinedSlotResult(Result):
    """Kinematics of the sine mechanism with an inclined slot over crank positions.

    Attributes
    ----------
    phi1 : crank angle [rad] from +x, counter-clockwise.
    L1, alpha, omega1, eps1 : the inputs.
    X_B, Y_B : crank-pin coordinates [m].
    X3 : slider displacement from its ``phi1 = 0`` position, towards the crank axis [m].
    X32 : block position in the slot along ``(cos alpha, sin alpha)`` [m].
    U31 : ``d X3 / d phi1`` [m/rad] (Eq. (20) in [1]_).
    U321 : ``d X32 / d phi1`` [m/rad].
    a_q3 : ``d^2 X3 / d phi1^2`` [m/rad^2].
    a_q32 : ``d^2 X32 / d phi1^2`` [m/rad^2].
    V3, V32 : slider velocity and block velocity relative to the slider [m/s] (Eq. (20)).
    a3, a32 : slider acceleration and relative block acceleration [m/s^2] (Eq. (21), with the
        sign of ``a32`` corrected and the ``eps1`` terms added).
    """

    phi1: np.ndarray
    L1: np.ndarray
    alpha: np.ndarray
    omega1: np.ndarray
    eps1: np.ndarray
    X_B: np.ndarray
    Y_B: np.ndarray
    X3: np.ndarray
    X32: np.ndarray
    U31: np.ndarray
    U321: np.ndarray
    a_q3: np.ndarray
    a_q32: np.ndarray
    V3: np.ndarray
    V32: np.ndarray
    a3: np.ndarray
    a32: np.ndarray

    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "L1": "m", "alpha": "rad", "omega1": "rad/s", "eps1": "rad/s^2",
        "X_B": "m", "Y_B": "m", "X3": "m", "X32": "m", "U31": "m/rad", "U321": "m/rad",
        "a_q3": "m/rad^2", "a_q32": "m/rad^2", "V3": "m/s", "V32": "m/s", "a3": "m/s^2",
        "a32": "m/s^2",
    }

    def _scene(self) -> Any:
        """The mechanism drawn over the crank angles (one design only; None for several)."""
        if np.ndim(self.phi1) != 1 or np.size(self.L1) != 1 or np.size(self.alpha) != 1:
            return None
        from linkwork.plot.scene import inclined_slot_scene

        return inclined_slot_scene(self)

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Ram position, velocity and acceleration over the crank angle (1-D results): a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.sine import inclined_slot_figure

        return inclined_slot_figure(self, axes=axes, **kw)


class ExtremePositions(NamedTuple):
    """Crank angles [rad, in [0, 2 pi)] of the ram's extreme positions."""

    phi1_min: np.ndarray
    """Crank angle where ``X3`` is smallest (``alpha - pi/2``)."""
    phi1_max: np.ndarray
    """Crank angle where ``X3`` is largest (``alpha + pi/2``)."""


def _check_alpha_open(alpha: ArrayLike, name: str = "alpha") -> np.ndarray:
    return require_in_range(name, alpha, 0.0, np.pi, lo_open=True, hi_open=True, unit="deg",
                            scale=180.0 / np.pi)


def inclined_slot(phi1: ArrayLike, L1: ArrayLike, alpha: ArrayLike, omega1: ArrayLike = 1.0,
                  eps1: ArrayLike = 0.0) -> InclinedSlotResult:
    r"""Kinematics of the sine mechanism whose slot is inclined at ``alpha`` to the motion.

    Parameters
    ----------
    phi1 : array_like
        Crank angle [rad], from the right horizontal position (+x, along the slider's line of
        motion), counter-clockwise.  Shape ``(n,)`` typically.
    L1 : array_like
        Crank length [m], > 0.  May be ``(m, 1)`` to sweep designs.
    alpha : array_like
        Slot angle [rad], ``0 < alpha < pi``, from the slider's line of motion to the slot,
        counter-clockwise.  ``pi/2`` is the classical sine mechanism.
    omega1 : array_like, optional
        Crank angular velocity [rad/s], counter-clockwise positive.  Default 1.
    eps1 : array_like, optional
        Crank angular acceleration [rad/s^2].  Default 0 (the paper's case).

    Returns
    -------
    InclinedSlotResult

    Raises
    ------
    ParameterError
        ``L1 <= 0``, ``alpha`` outside ``(0, pi)`` or non-finite input.

    Notes
    -----
    .. math::

        U_{31} = L_1\left(\sin\varphi_1 + \frac{\cos\varphi_1}{\tan\alpha}\right), \quad
        U_{321} = \frac{L_1\cos\varphi_1}{\sin\alpha}

    .. math::

        V_3 = \omega_1 U_{31}, \quad V_{32} = \omega_1 U_{321}, \quad
        a_3 = \varepsilon_1 U_{31} + \omega_1^2 L_1\left(\cos\varphi_1 -
              \frac{\sin\varphi_1}{\tan\alpha}\right), \quad
        a_{32} = \varepsilon_1 U_{321} - \omega_1^2\frac{L_1\sin\varphi_1}{\sin\alpha}

    ``U31``, ``V3``, ``V32`` and ``a3`` (for ``eps1 = 0``) are Eqs. (20), (21) in [1]_ as
    printed.  The printed ``a32`` of Eq. (21) (and of Eq. (18)) has the wrong sign; the printed
    ``X3`` of Eq. (19) is inconsistent with ``U31`` -- both corrected here (``docs/errata.md``).

    References
    ----------
    .. [1] Toktakunov, Zh. Sh. Analytic determination of the kinematics of a variable-structure
       sine mechanism (paper 000).
    """
    phi1_a = require_finite("phi1", phi1)
    L1_a = require_positive("L1", L1)
    al = _check_alpha_open(alpha)
    w1 = require_finite("omega1", omega1)
    e1 = require_finite("eps1", eps1)
    common_shape(phi1=phi1_a, L1=L1_a, alpha=al, omega1=w1, eps1=e1)
    phi1_b, L1_b, al_b, w1_b, e1_b = np.broadcast_arrays(phi1_a, L1_a, al, w1, e1)

    c1, s1 = np.cos(phi1_b), np.sin(phi1_b)
    cot = np.cos(al_b) / np.sin(al_b)
    csc = 1.0 / np.sin(al_b)
    X3 = L1_b * (1.0 - c1 + s1 * cot)
    X32 = L1_b * s1 * csc
    U31 = L1_b * (s1 + c1 * cot)
    U321 = L1_b * c1 * csc
    a_q3 = L1_b * (c1 - s1 * cot)
    a_q32 = -L1_b * s1 * csc
    w2 = w1_b * w1_b
    return InclinedSlotResult(
        phi1=phi1_b, L1=L1_a, alpha=al, omega1=w1, eps1=e1, X_B=L1_b * c1, Y_B=L1_b * s1,
        X3=X3, X32=X32, U31=U31, U321=U321, a_q3=a_q3, a_q32=a_q32,
        V3=w1_b * U31, V32=w1_b * U321, a3=e1_b * U31 + w2 * a_q3,
        a32=e1_b * U321 + w2 * a_q32,
    )


def stroke(L1: ArrayLike, alpha: ArrayLike) -> np.ndarray:
    r"""Slider stroke [m]: :math:`H = 2 L_1 / \sin\alpha` (``2 L1`` at ``alpha = pi/2``).

    Raises
    ------
    ParameterError
        ``L1 <= 0`` or ``alpha`` outside ``(0, pi)``.
    """
    L1_a = require_positive("L1", L1)
    al = _check_alpha_open(alpha)
    return 2.0 * L1_a / np.sin(al)


def extreme_positions(alpha: ArrayLike) -> ExtremePositions:
    r"""Crank angles [rad, in [0, 2 pi)] of the two extreme slider positions.

    ``U31 = 0`` gives :math:`\cos(\varphi_1-\alpha) = 0`.

    Returns
    -------
    ExtremePositions
        Named tuple ``(phi1_min, phi1_max)``: ``alpha - pi/2`` (``X3`` smallest,
        ``X3 = L1 (1 - 1/sin alpha)``) and ``alpha + pi/2``
        (``X3`` largest, ``X3 = L1 (1 + 1/sin alpha)``), wrapped to [0, 2 pi).  At these crank
        angles the crank is perpendicular to the slot.
    """
    al = _check_alpha_open(alpha)
    return ExtremePositions(np.mod(al - np.pi / 2, 2 * np.pi), np.mod(al + np.pi / 2, 2 * np.pi))


def alpha_for_stroke(L1: ArrayLike, H: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    r"""Slot angles [rad] that give the stroke ``H``: both solutions of ``2 L1 / sin(alpha) = H``.

    Returns
    -------
    alpha_low, alpha_high : ndarray
        ``arcsin(2 L1 / H)`` (in (0, pi/2]) and ``pi - arcsin(2 L1 / H)`` (in [pi/2, pi));
        equal (``pi/2``) when ``H == 2 L1``.

    Raises
    ------
    ParameterError
        ``L1 <= 0``, ``H <= 0`` or ``H < 2 L1`` (the stroke cannot be shorter than the crank
        diameter: ``sin(alpha) <= 1``).
    """
    L1_a = require_positive("L1", L1)
    H_a = require_positive("H", H)
    common_shape(L1=L1_a, H=H_a)
    L1_b, H_b = np.broadcast_arrays(L1_a, H_a)
    ratio = 2.0 * L1_b / H_b
    bad = ratio > 1.0 + 1e-12
    if bad.any():
        i = np.unravel_index(np.argmax(bad), bad.shape)
        raise ParameterError("H", float(H_b[i]), f"must be >= 2*L1 = {2 * float(L1_b[i]):.6g} m "
                             "(the stroke 2*L1/sin(alpha) is never shorter than the crank "
                             "diameter)")
    a = np.arcsin(np.minimum(ratio, 1.0))
    return a, np.pi - a


def friction_angle(f: ArrayLike, name: str = "f") -> np.ndarray:
    """Friction angle [rad] ``rho = arctan(f)`` of a Coulomb coefficient ``f >= 0``."""
    return np.arctan(require_positive(name, f, allow_zero=True))


def working_range(f_slot: ArrayLike, f_guide: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    r"""Slot angles [rad] between which the mechanism runs without jamming (open interval).

    Model (see ``docs/sine_press.md``): quasi-static slider 3 (inertia neglected), Coulomb
    friction with coefficient ``f_slot`` between block 2 and the slot and ``f_guide`` between
    slider 3 and its guides, the guide reaction one force normal to the guide (tilting of the
    slider in its guides neglected), a technological load along the guide opposing the motion,
    crank-pin friction neglected.  Over a revolution the block slides along the slot against the
    slider's motion in some phases; there the load the block can overcome with a normal force
    ``N`` is

    .. math::

        F = N\,\frac{\sin(\alpha-\rho_1-\rho_2)}{\cos\rho_1\cos\rho_2},\qquad
        \rho_1=\arctan f_\text{slot},\ \rho_2=\arctan f_\text{guide}

    and mirror-symmetrically near 180 deg.  The slider jams when this is <= 0, so the working
    range is

    .. math::

        \rho_1 + \rho_2 < \alpha < \pi - (\rho_1 + \rho_2).

    Returns
    -------
    alpha_min, alpha_max : ndarray
        ``rho1 + rho2`` and ``pi - rho1 - rho2``.

    Raises
    ------
    InfeasibleError
        ``rho1 + rho2 >= pi/2`` (``f_slot * f_guide >= 1``): the mechanism jams at every slot
        angle.
    """
    f1 = require_positive("f_slot", f_slot, allow_zero=True)
    f2 = require_positive("f_guide", f_guide, allow_zero=True)
    rho = np.arctan(f1) + np.arctan(f2)
    bad = np.broadcast_to(rho >= np.pi / 2, np.shape(rho))
    if np.any(bad):
        i = np.unravel_index(np.argmax(bad), bad.shape)
        v1 = float(np.broadcast_to(f1, bad.shape)[i])
        v2 = float(np.broadcast_to(f2, bad.shape)[i])
        raise InfeasibleError("a slot angle free of jamming", "none",
                              f"f_slot = {v1:.6g}, f_guide = {v2:.6g}: f_slot*f_guide = "
                              f"{v1 * v2:.6g} must be < 1 (friction angles "
                              f"{np.degrees(np.arctan(v1)):.4g} + {np.degrees(np.arctan(v2)):.4g}"
                              " deg add to >= 90 deg, the slider jams at every slot angle)")
    return rho, np.pi - rho


def check_alpha(alpha: ArrayLike, f_slot: ArrayLike, f_guide: ArrayLike,
                name: str = "alpha") -> np.ndarray:
    """Return ``alpha`` [rad] if it lies inside :func:`working_range`, else raise.

    Raises
    ------
    ParameterError
        ``alpha`` outside ``(rho1 + rho2, pi - rho1 - rho2)`` (the slider jams by friction);
        the message names the value and the range in degrees.
    """
    lo, hi = working_range(f_slot, f_guide)
    al = require_finite(name, alpha)
    bad = (al <= lo) | (al >= hi)
    if np.any(bad):
        i = np.unravel_index(np.argmax(np.broadcast_to(bad, np.shape(bad))), np.shape(bad))
        v = float(np.broadcast_to(al, np.shape(bad))[i])
        lo_d = float(np.degrees(np.broadcast_to(lo, np.shape(bad))[i]))
        hi_d = float(np.degrees(np.broadcast_to(hi, np.shape(bad))[i]))
        raise ParameterError(name, f"{np.degrees(v):.6g} deg",
                             f"must lie in the working range ({lo_d:.4g}, {hi_d:.4g}) deg, "
                             "outside it the slider jams by friction in the slot and guides")
    return al


def force_ratio(alpha: ArrayLike, f_slot: ArrayLike, f_guide: ArrayLike) -> np.ndarray:
    r"""Worst-case ratio of the load overcome to the frictionless one, over a revolution [-].

    In the model of :func:`working_range`, a normal force ``N`` of the block on the slot
    overcomes a load ``F = N sin(alpha) * eta`` along the guide; without friction ``eta = 1``.
    ``eta`` depends on the relative sliding direction in the slot; this returns the smallest
    value over the four sliding states met in a revolution:

    .. math::

        \eta = \min_{\sigma=\pm1}\frac{\sin\alpha + \sigma f_1\cos\alpha
               - f_2\,|\cos\alpha - \sigma f_1 \sin\alpha|}{\sin\alpha}

    ``eta <= 0`` means jamming; ``eta > 0`` exactly inside :func:`working_range`.
    """
    al = _check_alpha_open(alpha)
    f1 = require_positive("f_slot", f_slot, allow_zero=True)
    f2 = require_positive("f_guide", f_guide, allow_zero=True)
    sa, ca = np.sin(al), np.cos(al)
    etas = [(sa + sg * f1 * ca - f2 * np.abs(ca - sg * f1 * sa)) / sa for sg in (1.0, -1.0)]
    return np.minimum(*etas)


@dataclass(frozen=True)
class ForceRatioCurve(Result):
    """The worst-case force ratio over slot angles, with the working range (the jamming limits).

    Attributes
    ----------
    slot_angle : ndarray
        Slot angles alpha [rad], open interval (0, pi).
    eta : ndarray
        :func:`force_ratio` at each angle [-].
    working : tuple of float
        :func:`working_range`: (alpha_min, alpha_max) [rad].
    f_slot, f_guide : float
        The friction coefficients.
    """

    slot_angle: np.ndarray
    eta: np.ndarray
    working: tuple[float, float]
    f_slot: float
    f_guide: float

    units: ClassVar[dict[str, str]] = {"slot_angle": "rad", "eta": "", "f_slot": "",
                                       "f_guide": ""}
    position_field: ClassVar[str] = "slot_angle"

    def plot(self, alpha: float | None = None, ax: Any = None, **kw: Any) -> Figure:
        """The curve, the working range shaded and the chosen ``alpha`` [rad] if given: a
        :class:`linkwork.plot.Figure` with one axes."""
        from linkwork.plot import Figure
        from linkwork.plot.sine import plot_force_ratio_curve

        return Figure.of(plot_force_ratio_curve(self.slot_angle, self.eta, self.working,
                                                alpha=alpha, ax=ax, **kw))


def force_ratio_curve(f_slot: float, f_guide: float, n: int = 721) -> ForceRatioCurve:
    """:func:`force_ratio` over ``n`` slot angles in [1e-3, pi - 1e-3] rad and the
    :func:`working_range`, for a diagram of where the mechanism jams."""
    a = np.linspace(1e-3, np.pi - 1e-3, n)
    lo, hi = working_range(f_slot, f_guide)
    return ForceRatioCurve(a, force_ratio(a, f_slot, f_guide), (float(lo), float(hi)),
                           float(f_slot), float(f_guide))
