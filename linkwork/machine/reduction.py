r"""Reduction of a mechanism to its crank: reduced moment of inertia and reduced moments.

For a mechanism of one degree of freedom driven by a crank (driver coordinate :math:`\varphi`,
speed :math:`\omega`), the kinetic energy of the links is :math:`T = \tfrac12 J(\varphi)\omega^2`
with the **reduced moment of inertia**

.. math:: J(\varphi) = \sum_i \left[ m_i \left(x_{Si}'^2 + y_{Si}'^2\right)
          + J_{Si}\,\theta_i'^2 \right],

where the primes are the velocity analogues :math:`d/d\varphi` (the engine's velocities at
:math:`\omega = 1`). Its derivative is exact from the acceleration analogues (the engine's
accelerations at :math:`\omega = 1, \varepsilon = 0`):

.. math:: \frac{dJ}{d\varphi} = 2 \sum_i \left[ m_i \left(x_{Si}' x_{Si}'' + y_{Si}' y_{Si}''\right)
          + J_{Si}\,\theta_i' \theta_i'' \right].

The **reduced moment** of a force is its power over :math:`\omega`: of gravity
:math:`M_g = \sum m_i\,\mathbf g\cdot\mathbf r_{Si}'`, of the external loads
:math:`M_L = \sum \mathbf F\cdot\mathbf r_P' + \sum M_z\,\theta_i'` (positive where it drives
the crank; every load of :mod:`linkwork.planar.forces`: point forces and torques with their
load diagrams, slide forces, springs). Dampers and drags depend on the speed: their reduced
moment is :math:`a(\varphi) - c(\varphi)\,\omega` (``damping`` :math:`c`, from their power at
:math:`\omega = 1` and :math:`2`; exact for viscous dampers and for drags). Lagrange's equation
of the crank (the equation of motion of the machine unit) is then

.. math:: J\,\varepsilon + \tfrac12 \frac{dJ}{d\varphi}\,\omega^2 = M_d + M_L + M_g + M_f,

with :math:`M_d` the driving torque on the crank and :math:`M_f` the reduced moment of the joint
friction (:func:`friction_moment`: :math:`Q_0 - Q` of the engine, which depends on
:math:`\omega` and :math:`\varepsilon`). Equivalently the engine's driving torque of a given
motion is :math:`Q = J\varepsilon + \tfrac12 J'\omega^2 - M_L - M_g - M_f`
(``tests/machine/test_reduction.py`` checks this against :func:`linkwork.planar.inverse_dynamics`
at arbitrary :math:`\omega, \varepsilon`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import ParameterError
from linkwork.planar import (
    BodyTorque,
    Crank,
    Mechanism,
    PointForce,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar.forces import Load, LoadDiagram, SlideForce
from linkwork.planar.forces import apply as apply_loads
from linkwork.planar.state import Arr
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["Loads", "Reduction", "check_crank", "friction_moment", "load_list", "reduce",
           "scale_loads"]

#: External loads of a machine: PointForce/BodyTorque objects (constant, or arrays over the
#: positions asked), or a function of the driver positions [rad] returning them (as
#: ``PlanarFile.loads``), evaluated wherever the solver needs them.
LoadList = Sequence[Load]
Loads = LoadList | Callable[[np.ndarray], LoadList]


def check_crank(mech: Mechanism) -> None:
    """A machine unit here is driven by a crank turning about a frame joint (the motor's
    stator on the frame); else ParameterError naming the driver."""
    if not isinstance(mech, Mechanism):
        raise ParameterError("mech", mech, "must be a linkwork.planar.Mechanism")
    drv = mech.driver
    if not isinstance(drv, Crank):
        raise ParameterError("driver", drv.joint, "must be a Crank: machine dynamics reduces to "
                             "a rotating driver (a linear actuator has no motor characteristic "
                             "here)")
    j = mech.joint(drv.joint)
    if mech.frame.name not in (j.a, j.b):
        raise ParameterError("driver.joint", drv.joint, f"must join the frame ({mech.frame.name!r})"
                             " and the crank: the motor's stator sits on the frame")


def load_list(loads: Loads, phi: np.ndarray) -> list[Load]:
    """The loads at the driver positions ``phi``: ``loads(phi)`` for a function, else the
    sequence itself (its arrays must then have one value per position)."""
    if callable(loads):
        out = loads(phi)
    else:
        out = loads
    if isinstance(out, PointForce | BodyTorque) or not isinstance(out, Sequence):
        raise ParameterError("loads", out, "must be a sequence of PointForce and BodyTorque, or "
                             "a function of the driver positions returning one")
    return list(out)


def scale_loads(loads: Sequence[Load], f: float | np.ndarray) -> list[Load]:
    """The applied loads (point forces, torques, slide forces) times ``f`` (a number, or an
    array over the positions; a load diagram takes the mean of an array); the force elements
    (springs, dampers, drags) are part of the machine and stay as they are."""
    fa = np.asarray(f, dtype=float)
    scalar = float(np.mean(fa))

    def times(v: Any) -> Any:
        if isinstance(v, LoadDiagram):
            return dataclasses.replace(v, value=[x * scalar for x in v.value])
        return np.asarray(v, dtype=float) * fa

    out: list[Load] = []
    for ld in loads:
        if isinstance(ld, PointForce):
            out.append(dataclasses.replace(ld, fx=times(ld.fx), fy=times(ld.fy)))
        elif isinstance(ld, BodyTorque):
            out.append(dataclasses.replace(ld, mz=times(ld.mz)))
        elif isinstance(ld, SlideForce):
            out.append(dataclasses.replace(ld, force=times(ld.force)))
        else:
            out.append(ld)
    return out


@dataclass(frozen=True)
class Reduction(Result):
    """The mechanism reduced to its crank over the positions ``phi1``.

    Attributes
    ----------
    phi1 : ndarray (n,)
        Crank positions [rad].
    J : ndarray (n,)
        Reduced moment of inertia of the links [kg m^2].
    dJ : ndarray (n,)
        Its derivative ``dJ/dphi1`` [kg m^2/rad] (exact, from the acceleration analogues).
    M_loads : ndarray (n,)
        Reduced moment of the external loads [N m] (their power over omega1; positive driving).
    M_gravity : ndarray (n,)
        Reduced moment of gravity [N m].
    damping : ndarray (n,)
        Reduced damping of the speed-dependent loads (dampers, drags) [N m s/rad], >= 0: their
        reduced moment is ``-damping * omega1`` (a drag's Coulomb-like part, independent of the
        speed, is in ``M_loads``).
    """

    phi1: Arr
    J: Arr
    dJ: Arr
    M_loads: Arr
    M_gravity: Arr
    damping: Arr | None = None
    units: ClassVar[dict[str, str]] = {"phi1": "rad", "J": "kg*m^2", "dJ": "kg*m^2/rad",
                                       "M_loads": "N*m", "M_gravity": "N*m",
                                       "damping": "N*m*s/rad"}

    def __post_init__(self) -> None:
        if self.damping is None:
            object.__setattr__(self, "damping", np.zeros(np.shape(self.phi1)))

    @property
    def M(self) -> Arr:
        """``M_loads + M_gravity`` [N m]: the reduced moment of the position-dependent loads."""
        return self.M_loads + self.M_gravity

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """J and dJ/dphi1, and the reduced moments, over the crank angle: a
        :class:`linkwork.plot.Figure` with 2 axes (:mod:`linkwork.plot.machine`)."""
        from linkwork.plot.machine import reduction_figure

        return reduction_figure(self, axes=axes, **kw)


def _gravity(gravity: ArrayLike | None) -> tuple[float, float]:
    if gravity is None:
        return (0.0, 0.0)
    g = require_finite("gravity", gravity).ravel()
    if g.shape != (2,):
        raise ParameterError("gravity", gravity, "must be a vector (gx, gy) [m/s^2]")
    return (float(g[0]), float(g[1]))


def reduce(mech: Mechanism, phi1: ArrayLike, *, loads: Loads = (),
           gravity: ArrayLike | None = None) -> Reduction:
    """Reduced moment of inertia, its derivative, and the reduced moments of loads and gravity.

    Parameters
    ----------
    mech : Mechanism
        Driven by a :class:`~linkwork.planar.Crank` on a frame joint.
    phi1 : array_like (n,)
        Crank positions [rad].
    loads : sequence of PointForce/BodyTorque, or a function of the positions returning one
        External loads (see :data:`Loads`).
    gravity : (gx, gy), optional
        Gravity [m/s^2] in frame axes.

    Returns
    -------
    Reduction
    """
    check_crank(mech)
    g = _gravity(gravity)
    phi = np.atleast_1d(require_finite("phi1", phi1)).astype(float)
    kin = kinematics(mech, phi, 1.0, 0.0)  # velocities = velocity analogues, accelerations too
    c = kin.centres_of_mass()
    nm = len(mech.bodies)
    m = np.array([b.mass for b in mech.bodies])[:, None]
    jc = np.array([b.inertia for b in mech.bodies])[:, None]
    w, e = kin.omega[1:1 + nm], kin.eps[1:1 + nm]
    J = np.sum(m * (c.vx**2 + c.vy**2) + jc * w**2, axis=0)
    dJ = 2.0 * np.sum(m * (c.vx * c.ax + c.vy * c.ay) + jc * w * e, axis=0)
    Mg = np.sum(m * (g[0] * c.vx + g[1] * c.vy), axis=0)
    ML = np.zeros(phi.shape)
    damping = np.zeros(phi.shape)
    given = list(load_list(loads, phi))
    speed = []
    for al, ld in zip(apply_loads(kin, given), given, strict=True):
        if al.kind in ("damper", "drag"):  # their moment depends on the speed
            speed.append(ld)
            continue
        ML += al.power  # at omega1 = 1: the reduced moment
    if speed:  # M(omega) = P(omega) / omega = a + b omega: from omega1 = 1 and 2
        m1 = sum(al.power for al in apply_loads(kin, speed))
        kin2 = kinematics(mech, phi, 2.0, 0.0)
        m2 = 0.5 * sum(al.power for al in apply_loads(kin2, speed))
        damping = np.asarray(m1 - m2, dtype=float)
        ML += 2.0 * m1 - m2
    return Reduction(phi, J, dJ, ML, Mg, damping)


def friction_moment(mech: Mechanism, phi1: ArrayLike, omega1: ArrayLike, eps1: ArrayLike, *,
                    loads: Loads = (), gravity: ArrayLike | None = None) -> Arr:
    """Reduced moment of the joints' Coulomb friction ``M_f = Q0 - Q`` [N m] (<= 0 while the
    crank drives) for the motion ``omega1(phi1), eps1(phi1)``: the engine's driving torque with
    friction ``Q`` and without ``Q0`` (:func:`linkwork.planar.inverse_dynamics`); zero where no
    joint has friction. ``M_f omega1`` is minus the power dissipated in all joints."""
    phi = np.atleast_1d(require_finite("phi1", phi1)).astype(float)
    if not any(j.has_friction for j in mech.joints):
        return np.zeros(phi.shape)
    kin = kinematics(mech, phi, omega1, eps1)
    dyn = inverse_dynamics(kin, gravity=gravity, loads=load_list(loads, phi))
    dyn.require_no_self_locking("the machine's motion needs the driving torque at every "
                                "position of the turn")
    return np.asarray(dyn.Q_frictionless - dyn.Q, dtype=float)
