"""Figures of the closed-form four-bar: the linkage drawn at some positions, its motion and loads.

Every function takes ``ax=None`` (a new figure then) and returns what it drew; the
``*_figure`` functions return a :class:`~linkwork.plot.Figure` (what ``result.plot()`` gives).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from linkwork.plot._base import (
    Figure,
    axes_or_new,
    figure_title,
    finish,
    pyplot,  # noqa: F401  (importable here, as before)
    titled,
)

if TYPE_CHECKING:
    from linkwork.models.fourbar import FourbarForces, FourbarResult

__all__ = ["fourbar_figure", "fourbar_forces_figure", "plot_fourbar_forces",
           "plot_fourbar_linkage", "plot_fourbar_motion"]


def _axes(ax: Any, ncols: int = 1) -> Any:
    return axes_or_new(ax, 1, ncols, figsize=(6 * ncols, 4.5))


def plot_fourbar_linkage(result: FourbarResult, indices: Any = None, ax: Any = None, *,
                         name: str | None = None) -> Any:
    """Draw the linkage (frame, crank, coupler, rocker) at some positions of a 1-D result.

    Parameters
    ----------
    result : FourbarResult
        From :func:`linkwork.models.fourbar.fourbar` for one design (1-D arrays).
    indices : sequence of int, optional
        Positions to draw (default: 8 evenly spaced ones). The path of B (and of P, if present)
        is drawn over the whole result.
    ax : matplotlib Axes, optional
    name : str, optional
        Of the mechanism, heads the title.

    Returns
    -------
    Axes
    """
    ax = _axes(ax)
    n = np.shape(result.xB)[-1] if np.ndim(result.xB) else 1
    if indices is None:
        indices = np.linspace(0, n - 1, min(n, 8)).astype(int)
    d = float(np.asarray(result.d))
    ax.plot([0.0, d], [0.0, 0.0], "k-", lw=3, label="frame")
    for i in np.atleast_1d(indices):
        xa, ya = np.atleast_1d(result.xA)[i], np.atleast_1d(result.yA)[i]
        xb, yb = np.atleast_1d(result.xB)[i], np.atleast_1d(result.yB)[i]
        ax.plot([0.0, xa, xb, d], [0.0, ya, yb, 0.0], "o-", color="0.5", lw=1, ms=3)
    ax.plot(result.xB, result.yB, "-", lw=1.5, label="path of B")
    if result.xP is not None:
        ax.plot(result.xP, result.yP, "-", lw=1.5, label="coupler curve P")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    finish(ax, title=titled(name, "Four-bar", "linkage at "
                            f"{np.size(np.atleast_1d(indices))} positions and point paths"))
    return ax


def plot_fourbar_motion(result: FourbarResult, axes: Any = None, *, name: str | None = None
                        ) -> Any:
    """Angles, angular velocities and accelerations of coupler and rocker over the crank angle
    phi1 [deg]; ``name`` (of the mechanism) heads the title."""
    axes = _axes(axes, ncols=3)
    t = np.degrees(result.phi1)
    for ax, (q3, q4, label) in zip(axes, (
            (np.degrees(np.unwrap(result.theta3)), np.degrees(np.unwrap(result.theta4)),
             "angle [deg]"),
            (result.omega3, result.omega4, "angular velocity [rad/s]"),
            (result.eps3, result.eps4, "angular acceleration [rad/s^2]")), strict=True):
        ax.plot(t, q3, label="coupler")
        ax.plot(t, q4, label="rocker")
        ax.set_xlabel("crank angle φ1 [deg]")
        ax.set_ylabel(label)
        finish(ax, angle=t)
    figure_title(axes[0].figure, titled(name, "Four-bar", "motion of coupler and rocker"))
    return axes


def plot_fourbar_forces(forces: FourbarForces, axes: Any = None, *, name: str | None = None
                        ) -> Any:
    """Joint reaction magnitudes [N] and the driving moment Q [N m] over the crank angle phi1
    [deg]; ``name`` (of the mechanism) heads the title."""
    axes = _axes(axes, ncols=2)
    t = np.degrees(forces.phi1)
    for joint, fx, fy in (("O2", forces.R_Ox, forces.R_Oy), ("A", forces.R_Ax, forces.R_Ay),
                          ("B", forces.R_Bx, forces.R_By), ("O4", forces.R_Cx, forces.R_Cy)):
        axes[0].plot(t, np.hypot(fx, fy), label=f"|R| at {joint}")
    axes[0].set_xlabel("crank angle φ1 [deg]")
    axes[0].set_ylabel("joint reaction [N]")
    finish(axes[0], title="joint reactions", angle=t)
    axes[1].plot(t, forces.Q)
    axes[1].set_xlabel("crank angle φ1 [deg]")
    axes[1].set_ylabel("driving moment Q [N·m]")
    finish(axes[1], title="driving moment", angle=t)
    figure_title(axes[0].figure, titled(name, "Four-bar", "joint reactions and driving moment"))
    return axes


def fourbar_figure(result: FourbarResult, ax: Any = None, **kw: Any) -> Figure:
    """The linkage at some positions with the path of B (and P): :func:`plot_fourbar_linkage`."""
    return Figure.of(plot_fourbar_linkage(result, ax=ax, **kw))


def fourbar_forces_figure(forces: FourbarForces, axes: Any = None, **kw: Any) -> Figure:
    """Joint reactions and driving moment: :func:`plot_fourbar_forces` (2 axes)."""
    return Figure.of(plot_fourbar_forces(forces, axes=axes, **kw))
