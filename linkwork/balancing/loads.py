"""Shaking loads over a cycle: shaking force, moment about any point (RMS, peak, harmonics and
means: :mod:`linkwork.cycles`, re-exported here).

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

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite

# the cycle statistics moved to linkwork.cycles; importable here as before
from linkwork.cycles import (
    Harmonics,
    harmonics,
    mean_over_range,
    peak,
    rms,
)
from linkwork.planar.inertia import inertia_couple, inertia_force

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
