"""Figures of linkage synthesis: coupler curves against the targets, Pareto sets, function
generation errors.

Every function takes ``ax=None``, draws, and returns what it drew; the ``*_figure`` functions
return a :class:`~linkwork.plot.Figure` (what ``result.plot()`` gives). Lengths are drawn in
the task's unit as given in SI (m) scaled to mm; angles in degrees.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from linkwork.plot._base import Figure, axes_or_new, finish, titled

if TYPE_CHECKING:
    from linkwork.synthesis.design import SynthesisResult
    from linkwork.synthesis.function import FunctionResult
    from linkwork.synthesis.motion import MotionResult
    from linkwork.synthesis.sixbar import SixbarResult

__all__ = ["function_figure", "motion_figure", "pareto_figure", "path_figure",
           "plot_function_error", "plot_motion", "plot_pareto", "plot_path"]


def plot_path(res: SynthesisResult | SixbarResult, ax: Any = None, n_designs: int = 1, *,
              name: str | None = None) -> Any:
    """Target points and the coupler curves of the first ``n_designs`` designs (with the first
    design's linkage at the first point, four-bar or six-bar): returns the axes."""
    ax = axes_or_new(ax, figsize=(7, 6))
    pts = np.asarray(res.points) * 1e3
    designs: list[Any] = list(res.designs[:n_designs])
    for i, d in enumerate(designs):
        _, x, y = d.coupler_curve(721)
        ax.plot(x * 1e3, y * 1e3, lw=1.4 if i == 0 else 0.9,
                label=f"design {i + 1}: error {d.error:.3g} m²")
        if i == 0:  # the linkage at the first point
            lines, pivots = d.skeleton(float(d.theta2[0]))
            for k, line in enumerate(lines):
                g = np.asarray(line) * 1e3
                ax.plot(g[:, 0], g[:, 1], "-", color="0.35", lw=1.0 if k == 0 else 0.8)
            pv = np.asarray(pivots) * 1e3
            ax.plot(pv[:, 0], pv[:, 1], "^", color="0.2", ms=8, label="fixed pivots")
    ax.plot(pts[:, 0], pts[:, 1], "o", mfc="none", mec="k", ms=7, label="targets")
    for i, (x, y) in enumerate(pts):
        ax.annotate(str(i + 1), (x, y), fontsize=8, xytext=(4, 4), textcoords="offset points")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    finish(ax, title=titled(name, "path synthesis", "coupler curves and targets"))
    return ax


def path_figure(res: SynthesisResult | SixbarResult, ax: Any = None, n_designs: int = 1,
                **kw: Any) -> Figure:
    """:func:`plot_path` as a :class:`Figure` (1 axes)."""
    a = plot_path(res, ax=ax, n_designs=n_designs, **kw)
    return Figure(a.figure, np.array([a]))


def plot_pareto(res: SynthesisResult, ax: Any = None, x: str = "error",
                y: str = "peak_torque", *, name: str | None = None) -> Any:
    """The judged designs in the plane of two metrics (error against a force), the Pareto
    set joined: returns the axes."""
    ax = axes_or_new(ax, figsize=(7, 5))

    def val(d: Any, k: str) -> float:
        if k == "error":
            return float(d.error)
        if k == "min_transmission_angle":
            return math.degrees(float(d.checks.get(k, math.nan)))
        return float(d.forces.get(k, math.nan))

    xs = np.array([val(d, x) for d in res.designs])
    ys = np.array([val(d, y) for d in res.designs])
    ax.plot(xs, ys, "o", label="defect-free designs")
    if res.pareto:
        idx = np.array(res.pareto)
        o = idx[np.argsort(xs[idx])]
        ax.plot(xs[o], ys[o], "-", lw=1.2, label="Pareto set")
    for i, (a, b) in enumerate(zip(xs, ys, strict=True)):
        ax.annotate(str(i + 1), (a, b), fontsize=8, xytext=(3, 3), textcoords="offset points")
    units = {"error": "m²", "peak_torque": "N·m", "peak_bearing": "N", "rms_shaking": "N",
             "min_transmission_angle": "deg"}
    ax.set_xlabel(f"{x} [{units[x]}]")
    ax.set_ylabel(f"{y} [{units[y]}]")
    if x == "error" and np.all(xs > 0):
        ax.set_xscale("log")
    finish(ax, title=titled(name, "path synthesis", "accuracy against dynamics"))
    return ax


def pareto_figure(res: SynthesisResult, ax: Any = None, **kw: Any) -> Figure:
    """:func:`plot_pareto` as a :class:`Figure` (1 axes)."""
    a = plot_pareto(res, ax=ax, **kw)
    return Figure(a.figure, np.array([a]))


def plot_function_error(res: FunctionResult, ax: Any = None, *, name: str | None = None) -> Any:
    """Structural error (output minus wanted output) over the input range of each design, the
    precision points marked: returns the axes."""
    ax = axes_or_new(ax, figsize=(8, 4.5))
    deg = res.kind == "fourbar"
    for i, d in enumerate(res.designs):
        x = np.degrees(d.input)
        err = np.degrees(d.structural_error) if deg else d.structural_error * 1e3
        ax.plot(x, err, label=f"{d.method}: max {np.nanmax(np.abs(err)):.3g} "
                f"{'deg' if deg else 'mm'}", lw=1.3 if i == 0 else 0.9)
        if d.precision_inputs is not None:
            ax.plot(np.degrees(d.precision_inputs), np.zeros(len(d.precision_inputs)), "k.")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("input crank angle [deg]")
    ax.set_ylabel("structural error [deg]" if deg else "structural error [mm]")
    finish(ax, title=titled(name, "function generation", "structural error"),
           angle=np.degrees(res.designs[0].input))
    return ax


def function_figure(res: FunctionResult, ax: Any = None, **kw: Any) -> Figure:
    """:func:`plot_function_error` as a :class:`Figure` (1 axes)."""
    a = plot_function_error(res, ax=ax, **kw)
    return Figure(a.figure, np.array([a]))


def plot_motion(res: MotionResult, ax: Any = None, n_designs: int = 1, *,
                name: str | None = None) -> Any:
    """The poses (a short line along each pose's x axis), the centre points and circle points
    found, and the first four-bar at the first pose: returns the axes."""
    ax = axes_or_new(ax, figsize=(7, 6))
    poses = np.asarray(res.poses)
    scale = float(np.hypot(*np.ptp(poses[:, :2], axis=0))) or 1.0
    for i, (x, y, t) in enumerate(poses):
        ax.plot([x * 1e3, (x + 0.1 * scale * math.cos(t)) * 1e3],
                [y * 1e3, (y + 0.1 * scale * math.sin(t)) * 1e3], "k-", lw=2)
        ax.annotate(str(i + 1), (x * 1e3, y * 1e3), fontsize=8, xytext=(4, 4),
                    textcoords="offset points")
    if res.centre_points is not None and len(res.centre_points):
        c = np.asarray(res.centre_points) * 1e3
        ax.plot(c[:, 0], c[:, 1], ".", ms=2, color="C0", label="centre points")
    if res.circle_points is not None and len(res.circle_points):
        m = np.asarray(res.circle_points) * 1e3
        ax.plot(m[:, 0], m[:, 1], ".", ms=2, color="C1", label="circle points (pose 1)")
    for i, d in enumerate(res.designs[:n_designs]):
        j = d.fourbar.joints_at(float(d.fourbar.theta2[0]))
        g = np.array([j["O2"], j["A"], j["B"], j["O4"]]) * 1e3
        ax.plot(g[:, 0], g[:, 1], "-o", lw=1.2, ms=4, label=f"four-bar {i + 1}")
    # the view: the poses and the four-bars drawn, with a margin (the curves run to infinity)
    box = [poses[:, :2]] + [np.array([d.c1, d.c2]) for d in res.designs[:n_designs]]
    pts = np.concatenate(box) * 1e3
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.3 * float(max(hi - lo)) + 1e-9
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    finish(ax, title=titled(name, "motion generation", "poses, Burmester points, four-bars"))
    return ax


def motion_figure(res: MotionResult, ax: Any = None, **kw: Any) -> Figure:
    """:func:`plot_motion` as a :class:`Figure` (1 axes)."""
    a = plot_motion(res, ax=ax, **kw)
    return Figure(a.figure, np.array([a]))
