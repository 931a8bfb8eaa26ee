"""Kinematic diagrams of the variable-structure sine press drive (paper 000).

Every function takes ``axes=None`` (or ``ax=None``), draws, and returns what it drew; figures are
created through :func:`linkwork.plot.axes_or_new` only when no axes are given.  Lengths are shown
in mm, angles in degrees; the models stay in SI. The ``*_figure`` functions return a
:class:`~linkwork.plot.Figure` (what ``result.plot()`` gives).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.deprecation import warn_renamed
from linkwork.plot._base import (
    Figure,
    axes_or_new,
    figure_title,
    finish,
    pyplot,  # noqa: F401  (importable here, as before)
    titled,
)

if TYPE_CHECKING:
    from linkwork.models.crank_slider import CrankSliderResult
    from linkwork.models.sine import InclinedSlotResult
    from linkwork.models.variable_structure import ScheduleResult

__all__ = ["crank_slider_figure", "inclined_slot_figure", "plot_cycle", "plot_force_ratio",
           "plot_force_ratio_curve", "plot_schedule", "schedule_figure"]


def _axes3(axes: Any, sharex: bool = True) -> Any:
    return axes_or_new(axes, 3, 1, figsize=(8, 8.5), sharex=sharex)


def plot_cycle(idle: CrankSliderResult | None, working: InclinedSlotResult | None,
               axes: Any = None, *, name: str | None = None) -> Any:
    """Position, velocity and acceleration of the output link against crank angle, both modes;
    ``name`` (of the press) heads the title.

    Idle mode: slider C of the crank-slider (``Y_C``, ``V_C``, ``a_C``); working mode: the ram
    (``X3``, ``V3``, ``a3``).  Both must be 1-D over crank angle.

    Returns
    -------
    axes : array of 3 matplotlib Axes (position [mm], velocity [m/s], acceleration [m/s^2]).
    """
    ax = _axes3(axes)
    drawn = []
    if idle is not None:
        deg = np.degrees(idle.phi1)
        drawn.append(deg)
        ax[0].plot(deg, idle.Y_C * 1e3, label="idle: slider C, $Y_C$")
        ax[1].plot(deg, idle.V_C, label="idle: $V_C$")
        ax[2].plot(deg, idle.a_C, label="idle: $a_C$")
    if working is not None:
        deg = np.degrees(working.phi1)
        drawn.append(deg)
        a = float(np.degrees(np.asarray(working.alpha).reshape(-1)[0]))
        ax[0].plot(deg, working.X3 * 1e3, label=f"working: ram $X_3$ ($\\alpha$ = {a:.4g}°)")
        ax[1].plot(deg, working.V3, label="working: $V_3$")
        ax[2].plot(deg, working.a3, label="working: $a_3$")
    for a_, lab in zip(ax, ("position [mm]", "velocity [m/s]", "acceleration [m/s²]"),
                       strict=True):
        a_.set_ylabel(lab)
        a_.axhline(0.0, color="0.6", lw=0.6)
        finish(a_, angle=np.concatenate(drawn) if drawn else None)
    ax[-1].set_xlabel("crank angle φ1 [deg]")
    kind = ("idle and working modes" if idle is not None and working is not None
            else "idle mode (crank-slider)" if idle is not None else "working mode (sine)")
    default = ("Sine press" if idle is not None and working is not None
               else "CrankSliderResult" if idle is not None else "InclinedSlotResult")
    figure_title(ax[0].figure, titled(name, default, f"output link over one crank revolution, "
                                      f"{kind}"))
    return ax


def plot_schedule(res: ScheduleResult, axes: Any = None, ram: bool = True, *,
                  name: str | None = None) -> Any:
    """Output-link motion over a duty schedule against time, switch points marked; ``name``
    (of the press) heads the title.

    Draws ``s, v, a`` of the active structure's output link and, if ``ram``, the press ram's
    motion (dashed); working segments are shaded and every switch is a vertical line.

    Returns
    -------
    axes : array of 3 matplotlib Axes.
    """
    ax = _axes3(axes)
    seg_breaks = np.flatnonzero(res.switch)
    bounds = np.concatenate([[0], seg_breaks, [res.t.size]])
    for k in range(bounds.size - 1):
        sl = slice(bounds[k], bounds[k + 1])
        working = bool(res.mode[bounds[k]] == 1)
        color = "C1" if working else "C0"
        label_s = ("working: ram $X_3$" if working else "idle: slider C, $Y_C$")
        for a_, y, scale in zip(ax, (res.s, res.v, res.a), (1e3, 1.0, 1.0), strict=True):
            a_.plot(res.t[sl], y[sl] * scale, color=color, lw=1.2,
                    label=label_s if k < 2 else None)
            if working:
                a_.axvspan(res.t[sl][0], res.t[sl][-1], color="C1", alpha=0.07)
    if ram:
        for a_, y, scale in zip(ax, (res.ram_s, res.ram_v, res.ram_a), (1e3, 1.0, 1.0),
                                strict=True):
            a_.plot(res.t, y * scale, color="k", lw=0.8, ls="--", label="press ram")
    for t in res.switch_t:
        for a_ in ax:
            a_.axvline(t, color="C3", lw=1.0, ls=":")
    for a_, lab in zip(ax, ("position [mm]", "velocity [m/s]", "acceleration [m/s²]"),
                       strict=True):
        a_.set_ylabel(lab)
        finish(a_, show_legend=a_ is ax[0])
    ax[-1].set_xlabel("time [s] (dotted: mode switches)")
    ax[-1].set_xlim(float(res.t[0]), float(res.t[-1]))
    figure_title(ax[0].figure, titled(name, "ScheduleResult", "duty schedule, idle and "
                                      "working modes"))
    return ax


def plot_force_ratio(f_slot: float, f_guide: float, alpha: float | None = None,
                     ax: Any = None) -> Any:
    """Deprecated: ``linkwork.models.sine.force_ratio_curve(f_slot, f_guide).plot(alpha)``
    (a plot module does not evaluate a model). Returns the matplotlib Axes, as before."""
    from linkwork.models.sine import force_ratio_curve  # the one deprecated plot -> model edge

    warn_renamed("linkwork.plot.sine.plot_force_ratio()",
                 "linkwork.models.sine.force_ratio_curve(f_slot, f_guide).plot(alpha)")
    return force_ratio_curve(f_slot, f_guide).plot(alpha, ax=ax).axes[0]


def plot_force_ratio_curve(slot_angle: ArrayLike, eta: ArrayLike,
                           working: tuple[float, float], alpha: float | None = None,
                           ax: Any = None, *, name: str | None = None) -> Any:
    """Draw a force-ratio curve ``eta`` [-] over ``slot_angle`` [rad], the working range
    ``working`` = (alpha_min, alpha_max) [rad] shaded and the chosen ``alpha`` [rad] if given.

    Returns
    -------
    ax : matplotlib Axes.
    """
    ax = axes_or_new(ax, figsize=(7, 3.5))
    a = np.asarray(slot_angle, dtype=float)
    ax.plot(np.degrees(a), np.asarray(eta, dtype=float), label="worst-case force ratio η")
    lo, hi = working
    ax.axvspan(float(np.degrees(lo)), float(np.degrees(hi)), color="C2", alpha=0.1,
               label="working range")
    if alpha is not None:
        ax.axvline(float(np.degrees(alpha)), color="C3", ls="--", label="α chosen")
    ax.axhline(0.0, color="0.4", lw=0.8)
    ax.set_ylim(-1.0, 1.05)
    ax.set_xlabel("slot angle α [deg]")
    ax.set_ylabel("η [-]")
    finish(ax, title=titled(name, "ForceRatioCurve", "worst-case force ratio over the slot "
                            "angle"), angle=np.degrees(a), legend_kw={"loc": "lower center"})
    return ax


def crank_slider_figure(result: CrankSliderResult, axes: Any = None, *,
                        name: str | None = None) -> Figure:
    """Slider position, velocity and acceleration over the crank angle (3 axes)."""
    return Figure.of(plot_cycle(result, None, axes=axes, name=name))


def inclined_slot_figure(result: InclinedSlotResult, axes: Any = None, *,
                         name: str | None = None) -> Figure:
    """Ram position, velocity and acceleration of the sine mechanism (3 axes)."""
    return Figure.of(plot_cycle(None, result, axes=axes, name=name))


def schedule_figure(result: ScheduleResult, axes: Any = None, ram: bool = True, *,
                    name: str | None = None) -> Figure:
    """Output-link motion over a duty schedule (3 axes): :func:`plot_schedule`."""
    return Figure.of(plot_schedule(result, axes=axes, ram=ram, name=name))
