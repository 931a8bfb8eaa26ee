"""d'Alembert (inertia) loads of the bodies of a planar mechanism.

The inertia wrench of a moving body ``i`` at its centre of mass ``C_i``: the force

.. math:: \\mathbf F_i = m_i (\\mathbf g - \\mathbf a_{C_i})

(its weight plus its inertia force; ``g = 0`` unless gravity is given) and the couple

.. math:: M_i = -J_{C_i} \\varepsilon_i .

Inverse dynamics adds them to the applied loads (d'Alembert's principle); without gravity and
external loads their resultant is the shaking force and moment on the frame,
``F_sh = -sum m_i a_Ci``, ``M_sh = -sum [(r_Ci - P) x m_i a_Ci + J_Ci eps_i]``. One function
computes them for the engine (:func:`inertia_wrenches`, used by :mod:`linkwork.planar.dynamics`,
:mod:`linkwork.balancing` and :mod:`linkwork.redundancy`); the two kernels
:func:`inertia_force` and :func:`inertia_couple` are the formulas themselves, also used on plain
arrays (:func:`linkwork.balancing.loads.shaking_force`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import ParameterError
from linkwork.planar.kinematics import Kinematics, PointMotion, require_kinematics
from linkwork.planar.state import Arr

__all__ = ["InertiaWrenches", "inertia_couple", "inertia_force", "inertia_wrenches",
           "wrenches_of"]


def inertia_force(mass: ArrayLike, ax: ArrayLike, ay: ArrayLike, gx: float = 0.0,
                  gy: float = 0.0) -> tuple[Arr, Arr]:
    """Weight plus inertia force ``m (g - a_C)`` [N] of a body (or of bodies, broadcast).

    ``mass`` [kg], ``ax, ay`` acceleration of the centre of mass [m/s^2], ``gx, gy`` gravity
    [m/s^2]."""
    m = np.asarray(mass)
    return m * (gx - np.asarray(ax)), m * (gy - np.asarray(ay))


def inertia_couple(inertia: ArrayLike, eps: ArrayLike) -> Arr:
    """Inertia couple ``-J_C eps`` [N m] (counter-clockwise positive) of a body (or bodies)."""
    return np.asarray(-(np.asarray(inertia) * np.asarray(eps)))


@dataclass(frozen=True)
class InertiaWrenches:
    """The d'Alembert loads of every moving body over the positions (positions last).

    Attributes
    ----------
    bodies : tuple of str
        The moving bodies, in the mechanism's order (row ``k`` is ``bodies[k]``; the frame is
        not included, so its kinematics row is ``k + 1``).
    mass, inertia : ndarray (nm,)
        Masses [kg] and centroidal moments of inertia [kg m^2].
    cx, cy : ndarray (nm, n)
        Centres of mass [m], frame axes.
    fx, fy : ndarray (nm, n)
        ``m (g - a_C)`` [N] applied at the centre of mass.
    mz : ndarray (nm, n)
        ``-J_C eps`` [N m].
    gravity : (gx, gy)
        Gravity used [m/s^2].
    """

    bodies: tuple[str, ...]
    mass: Arr
    inertia: Arr
    cx: Arr
    cy: Arr
    fx: Arr
    fy: Arr
    mz: Arr
    gravity: tuple[float, float]

    def moment(self, about: tuple[float, float] = (0.0, 0.0)) -> Arr:
        """Moment of each body's wrench about the point ``about`` [N m], shape (nm, n)."""
        return (self.cx - about[0]) * self.fy - (self.cy - about[1]) * self.fx + self.mz

    def resultant(self, about: tuple[float, float] = (0.0, 0.0)) -> tuple[Arr, Arr, Arr]:
        """Sum over the bodies (those with mass or inertia) of the forces [N] and of their
        moments about ``about`` [N m]: without gravity the shaking force and moment."""
        n = self.fx.shape[-1]
        fx, fy, mz = np.zeros(n), np.zeros(n), np.zeros(n)
        for k in range(len(self.bodies)):
            if self.mass[k] == 0.0 and self.inertia[k] == 0.0:
                continue  # a massless body adds nothing (not even its NaN where unassembled)
            fx += self.fx[k]
            fy += self.fy[k]
            mz += ((self.cx[k] - about[0]) * self.fy[k] - (self.cy[k] - about[1]) * self.fx[k]
                   + self.mz[k])
        return fx, fy, mz


def inertia_wrenches(kin: Kinematics, gravity: ArrayLike | None = None) -> InertiaWrenches:
    """The d'Alembert loads of every moving body of ``kin.mechanism`` over ``kin``'s positions.

    Parameters
    ----------
    kin : Kinematics
        The solved motion (:func:`~linkwork.planar.kinematics.kinematics`).
    gravity : (gx, gy), optional
        Gravity acceleration [m/s^2] in frame axes; default none.

    Returns
    -------
    InertiaWrenches
        ``fx, fy = m (g - a_C)`` at the centre of mass and ``mz = -J_C eps`` per body and
        position.
    """
    require_kinematics(kin)
    if gravity is None:
        g = (0.0, 0.0)
    else:
        gv = require_finite("gravity", gravity).ravel()
        if gv.shape != (2,):
            raise ParameterError("gravity", gravity, "must be a vector (gx, gy) [m/s^2]")
        g = (float(gv[0]), float(gv[1]))
    return wrenches_of(kin, g, kin.centres_of_mass())


def wrenches_of(kin: Kinematics, g: tuple[float, float], c: PointMotion) -> InertiaWrenches:
    """:func:`inertia_wrenches` (checked arguments) from the motion ``c`` of the centres of
    mass (:meth:`~linkwork.planar.kinematics.Kinematics.centres_of_mass`), which the inverse
    dynamics also takes the kinetic energy from."""
    mech = kin.mechanism
    mass = np.array([b.mass for b in mech.bodies], dtype=float)
    inertia = np.array([b.inertia for b in mech.bodies], dtype=float)
    fx, fy = inertia_force(mass[:, None], c.ax, c.ay, g[0], g[1])
    mz = inertia_couple(inertia[:, None], kin.eps[1:1 + len(mech.bodies)])
    cx, cy = c.x, c.y
    return InertiaWrenches(tuple(b.name for b in mech.bodies), mass, inertia,
                           cx, cy, fx, fy, mz, g)
