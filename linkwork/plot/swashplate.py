"""Figures of the swash-plate (inclined-disk) drive of rotor machines (paper 003).

Every function takes ``axes=None`` (or ``ax=None``), draws, and returns what it drew; figures are
created through :func:`linkwork.plot.axes_or_new` only when no axes are given. Lengths in mm,
angles in degrees on the figures; the models stay in SI. The ``*_figure`` functions return a
:class:`~linkwork.plot.Figure` (what ``result.plot()`` gives).
"""

from __future__ import annotations

import math
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
    from linkwork.models.swashplate import Characteristics, DriveForces, KinematicsResult
    from linkwork.synthesis.swashplate import FeasibleRegion

__all__ = ["characteristics_figure", "drive_forces_figure", "feasible_region_figure",
           "kinematics_figure", "plot_drive_forces", "plot_feasible_region", "plot_kinematics"]


def plot_kinematics(res: KinematicsResult, axes: Any = None, label: str | None = None, *,
                    name: str | None = None) -> Any:
    """Position ``s``, pressure angle ``delta_z`` and first transfer function ``Pi_v`` against
    the rotor angle, with the extremes and the allowed pressure angle marked if given;
    ``name`` (of the drive) heads the figure's title.

    Returns
    -------
    axes : array of 3 matplotlib Axes (s [mm], delta_z [deg], Pi_v [mm/rad]).
    """
    axes = axes_or_new(axes, 3, 1, figsize=(8, 8.5), sharex=True)
    deg = np.degrees(res.phi)
    c = res.characteristics
    lab = label or f"scheme {res.design.scheme}"
    axes[0].plot(deg, res.s * 1e3, label=lab)
    for phi_e, s_e, extreme in ((c.phi_min, c.s_min, "min"), (c.phi_max, c.s_max, "max")):
        axes[0].plot(math.degrees(float(phi_e)), float(s_e) * 1e3, "o", ms=4)
        axes[0].annotate(extreme, (math.degrees(float(phi_e)), float(s_e) * 1e3), fontsize=8,
                         xytext=(4, 4), textcoords="offset points")
    axes[1].plot(deg, np.degrees(res.delta_z), label=lab)
    axes[2].plot(deg, res.Pi_v * 1e3, label=lab)
    axes[2].axhline(0.0, color="0.6", lw=0.6)
    H = float(c.H) * 1e3
    for a_, ylab in zip(axes, ("s [mm]", "δz [deg]", "Πv = ds/dφ [mm/rad]"), strict=True):
        a_.set_ylabel(ylab)
        finish(a_, angle=deg)
    axes[-1].set_xlabel("rotor angle φ [deg] (from −y0, counter-clockwise)")
    axes[0].set_title(f"H = {H:.4g} mm, φf = {math.degrees(float(c.phi_f)):.4g}°, "
                      f"max δz fwd/ret = {math.degrees(float(c.delta_f)):.3g}°/"
                      f"{math.degrees(float(c.delta_r)):.3g}°", fontsize=9)
    figure_title(axes[0].figure, titled(name, "Swash-plate drive", "slide position s, "
                                        "pressure angle δz, transfer function Πv"))
    return axes


def plot_drive_forces(f: DriveForces, ax: Any = None, *, name: str | None = None) -> Any:
    """Load on one slide, rod force and the drive torque (one slide and all ``u`` slides);
    ``name`` (of the drive) heads the figure's title."""
    ax = axes_or_new(ax, 2, 1, figsize=(8, 6), sharex=True)
    deg = np.degrees(f.phi)
    ax[0].plot(deg, f.F * 1e-3, label="technological force F [kN]")
    ax[0].plot(deg, f.S * 1e-3, label="rod force S [kN]")
    ax[1].plot(deg, f.M, label="torque, one slide [N·m]")
    ax[1].plot(deg, f.M_total, label=f"torque, {f.u} slides [N·m]")
    for a_ in ax:
        finish(a_, angle=deg)
    eff = f"{f.efficiency:.3f}" if math.isfinite(f.efficiency) else "n/a"
    ax[0].set_title(f"efficiency over a cycle: {eff}", fontsize=9)
    ax[0].set_ylabel("force [kN]")
    ax[1].set_ylabel("drive torque [N·m]")
    ax[1].set_xlabel("rotor angle φ [deg]")
    figure_title(ax[0].figure, titled(name, "Swash-plate drive", "slide load, rod force and "
                                      "drive torque"))
    return ax


def _label(name: str) -> tuple[str, float]:
    if name == "alpha":
        return "α [deg]", 180 / math.pi
    return f"{name} / R", 1.0


def plot_feasible_region(region: FeasibleRegion, ax: Any = None, best: Any = None, *,
                         name: str | None = None) -> Any:
    """The feasible set of a :class:`~linkwork.synthesis.swashplate.FeasibleRegion` over its two
    parameters (shaded), objective contours inside it, the failing constraint elsewhere, and
    the ``best`` design (a Design) if given; ``name`` heads the title (default: the scheme)."""
    ax = axes_or_new(ax, figsize=(7, 5.5))
    xl, xs = _label(region.x_name)
    yl, ys = _label(region.y_name)
    X, Y = np.meshgrid(region.x * xs, region.y * ys)
    ax.contourf(X, Y, region.feasible.astype(float), levels=[0.5, 1.5], colors=["#9fd39f"])
    obj = np.where(region.feasible, region.objective, np.nan)
    if np.isfinite(obj).any():
        cs = ax.contour(X, Y, obj, levels=8, colors="k", linewidths=0.6)
        ax.clabel(cs, fontsize=7)
    from matplotlib.lines import Line2D

    handles: list[Any] = []
    colours = {"H": "C0", "delta_f": "C1", "delta_r": "C4", "Pi_v": "C3", "point": "C5",
               "phi_f": "C6"}
    for key, v in region.violations.items():
        if key in ("reach", "unimodal"):
            continue
        vv = np.where(np.isfinite(v), v, np.nan)
        if np.isfinite(vv).any() and np.nanmin(vv) < 0 < np.nanmax(vv):
            col = colours.get(key, "0.3")
            # each limit its own dash pattern: limits that coincide (forward and return stroke
            # of a symmetric drive) stay visible, both colours alternating
            dash = _DASHES[len(handles) % len(_DASHES)]
            ax.contour(X, Y, vv, levels=[0.0], colors=[col], linewidths=1.4,
                       linestyles=[dash])
            handles.append(Line2D([], [], color=col, ls=dash, lw=1.4,
                                  label=f"limit: {_CONSTRAINT_LABEL.get(key, key)}"))
    if best is not None:
        rel = best.relative()
        (star,) = ax.plot(rel[region.x_name] * xs, rel[region.y_name] * ys, "r*", ms=12,
                          label="best design", clip_on=False, zorder=5)
        handles.append(star)
    for h in handles:
        if h not in ax.get_lines():
            ax.add_line(h)  # a legend proxy (no data): listed, not drawn
    ax.set_xlabel(xl)
    ax.set_ylabel(yl)
    obj_name = "L / R" if region.request.objective == "L" else "peak torque / (F R)"
    title = titled(name, f"Swash-plate scheme {region.request.scheme}", "feasible region "
                   f"(green), contours: {obj_name}; dashed: constraint limits")
    if not np.any(region.feasible):
        title += ("\nno feasible grid point in this slice: the feasible set is narrower than "
                  "the grid step here")
    finish(ax, title=title, angle=region.x * xs if region.x_name == "alpha" else None)
    if region.y_name == "alpha":
        finish(ax, angle=region.y * ys, angle_on="y", show_legend=False)
    ax.title.set_fontsize(9)
    return ax


#: dash patterns of the constraint limits, in the order drawn
_DASHES = ((0, (6.0, 4.0)), (3.0, (6.0, 4.0)), (0, (1.5, 2.5)), (0, (8.0, 2.0, 1.5, 2.0)),
           (0, (3.0, 3.0)), (0, (10.0, 3.0)))

_CONSTRAINT_LABEL = {"H": "stroke H", "delta_f": "δz on the forward stroke",
                     "delta_r": "δz on the return stroke", "Pi_v": "max |Πv|",
                     "point": "s(φp) = sp", "phi_f": "forward-stroke angle φf"}


def kinematics_figure(res: KinematicsResult, axes: Any = None, label: str | None = None, *,
                      name: str | None = None) -> Figure:
    """Position, pressure angle and transfer function over the rotor angle (3 axes)."""
    return Figure.of(plot_kinematics(res, axes=axes, label=label, name=name))


def drive_forces_figure(f: DriveForces, ax: Any = None, *, name: str | None = None) -> Figure:
    """Slide load, rod force and drive torque over the rotor angle (2 axes)."""
    return Figure.of(plot_drive_forces(f, ax=ax, name=name))


def feasible_region_figure(region: FeasibleRegion, ax: Any = None, best: Any = None, *,
                           name: str | None = None) -> Figure:
    """The feasible region of a synthesis slice (1 axes): :func:`plot_feasible_region`."""
    return Figure.of(plot_feasible_region(region, ax=ax, best=best, name=name))


def characteristics_figure(c: Characteristics, ax: Any = None, *, name: str | None = None
                           ) -> Figure:
    """The characteristics of a design as bars: stroke H [mm], forward- and return-stroke angles
    and the largest pressure angles on each stroke [deg] (1 axes; of the first design when the
    characteristics cover several)."""
    ax = axes_or_new(ax, figsize=(7, 3.5))
    first = {k: float(np.ravel(getattr(c, k))[0]) for k in
             ("H", "phi_f", "phi_r", "delta_f", "delta_r")}
    names = ["H [mm]", "φf [deg]", "φr [deg]", "max δz fwd [deg]", "max δz ret [deg]"]
    vals = [first["H"] * 1e3, *(math.degrees(first[k])
                                for k in ("phi_f", "phi_r", "delta_f", "delta_r"))]
    bars = ax.bar(names, vals, color=["C0", "C1", "C4", "C2", "C3"])
    ax.bar_label(bars, fmt="%.4g", fontsize=8)
    n = int(np.size(c.H))
    finish(ax, title=titled(name, "Characteristics", "stroke, stroke angles and largest "
                            "pressure angles" + (f" of design 1 of {n}" if n > 1 else "")),
           grid="y")
    return Figure.of(ax, bars=bars)

