"""Figures of the planar engine's results: skeleton, paths, driving torque, reactions, shaking.

Every function takes ``ax=None`` (a new figure is made) and returns what it drew. Angles are
shown in degrees, lengths in mm. The ``*_figure`` functions return a
:class:`~linkwork.plot.Figure` (what ``result.plot()`` gives).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from linkwork.errors import ParameterError
from linkwork.plot._base import (
    Figure,
    axes_or_new,
    figure_title,
    finish,
    pyplot,
    titled,
)

if TYPE_CHECKING:
    from linkwork.planar.dynamics import Dynamics
    from linkwork.planar.kinematics import Kinematics, PointMotion

__all__ = ["dynamics_figure", "kinematics_figure", "plot_driving_torque", "plot_loads",
           "plot_reactions", "plot_shaking", "plot_skeleton", "point_motion_figure"]


def _ax(ax: Any) -> Any:
    return axes_or_new(ax)


def _linear(result: Any) -> bool:
    """A linear driver: its positions are in m (the result relabels ``phi1``'s unit)."""
    return bool(result.units.get("phi1") == "m")


def _several(result: Any) -> bool:
    """Several drivers: their positions are rows of ``phi1``; figures run over the index of
    the position along the drivers' path."""
    return bool(np.ndim(result.phi1) == 2)


def _x(kin: Any) -> tuple[np.ndarray, str]:
    if _several(kin):
        return np.arange(np.shape(kin.phi1)[-1], dtype=float), "position along the drivers' path"
    if not _linear(kin):
        return np.degrees(kin.phi1), "driver angle φ1 [deg]"
    return kin.phi1 * 1e3, "driver position s1 [mm]"


def _angle(kin: Any, x: np.ndarray) -> np.ndarray | None:
    """The degrees drawn on the x axis, or None for a linear driver (mm, not an angle) or
    several drivers (the position's index)."""
    return None if _linear(kin) or _several(kin) else x


#: line styles of the point paths (colours repeat after ten paths, the styles tell them apart)
_PATH_STYLES = ("--", "-.", (0, (1.5, 1.5)), (0, (6.0, 2.0, 1.5, 2.0, 1.5, 2.0)))


def named_point_paths(kin: Any) -> list[tuple[str, str]]:
    """Every named point of every moving body whose path is a curve, each path once: a
    joint's point named on both of its bodies (coupler.B, rocker.B) is kept under its first
    body; points that do not move (a crank's pivot) are left out."""
    kept: list[tuple[str, str]] = []
    seen: list[np.ndarray] = []
    for body in kin.mechanism.bodies:
        for pt in body.points:
            pm = kin.point(body.name, pt)
            xy = np.concatenate([pm.x, pm.y])
            ok = np.isfinite(pm.x) & np.isfinite(pm.y)
            if not ok.any() or (np.ptp(pm.x[ok]) <= 1e-9 and np.ptp(pm.y[ok]) <= 1e-9):
                continue
            if any(np.allclose(xy, other, rtol=0.0, atol=1e-9, equal_nan=True)
                   for other in seen):
                continue
            kept.append((body.name, pt))
            seen.append(xy)
    return kept


def plot_skeleton(kin: Any, positions: Sequence[int] | None = None, *,
                  paths: Sequence[tuple[str, str]] | None = None, ax: Any = None,
                  name: str | None = None) -> dict[str, Any]:
    """Draw the mechanism at some positions (indices into ``kin.phi1``) and point paths.

    Each body is drawn as the polygon of its named points (joint centres); ``paths`` lists
    (body, point) whose paths over the whole cycle are drawn, default (None) the path of every
    named point that moves, each once (:func:`named_point_paths`). ``name`` (of the mechanism)
    heads the title. Returns ``{"ax", "lines", "paths", "guides"}``.
    """
    ax = _ax(ax)
    mech = kin.mechanism
    if positions is None:
        good = np.flatnonzero(kin.valid)
        positions = [int(good[0])] if good.size else []
    lines = []
    colours: dict[str, Any] = {}
    for k, idx in enumerate(positions):
        alpha = 1.0 if k == 0 else 0.35
        for body in mech.bodies:
            pts = list(body.points.values())
            if not pts:
                continue
            i = mech.index[body.name]
            c, s = np.cos(kin.theta[i, idx]), np.sin(kin.theta[i, idx])
            xs = [kin.x[i, idx] + c * p[0] - s * p[1] for p in pts]
            ys = [kin.y[i, idx] + s * p[0] + c * p[1] for p in pts]
            if len(pts) > 2:
                xs.append(xs[0])
                ys.append(ys[0])
            kw = {"color": colours[body.name]} if body.name in colours else {}
            (ln,) = ax.plot(np.array(xs) * 1e3, np.array(ys) * 1e3, "o-", alpha=alpha,
                            label=body.name if k == 0 else None, **kw)
            colours.setdefault(body.name, ln.get_color())
            lines.append(ln)
    fx = [p[0] * 1e3 for p in mech.frame.points.values()]
    fy = [p[1] * 1e3 for p in mech.frame.points.values()]
    ax.plot(fx, fy, "k^", ms=9, label="frame")
    guides = _draw_guides(ax, kin, positions[:1], colours)
    drawn = []
    for k, (body, point) in enumerate(named_point_paths(kin) if paths is None else paths):
        pm = kin.point(body, point)
        (ln,) = ax.plot(pm.x * 1e3, pm.y * 1e3, ls=_PATH_STYLES[k % len(_PATH_STYLES)],
                        lw=1.2, color=pyplot().get_cmap("tab10")((len(colours) + k) % 10),
                        label=f"path {body}.{point}")
        drawn.append(ln)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    shown = len(positions)
    finish(ax, title=titled(name, "Kinematics", f"skeleton at {shown} position"
                            + ("" if shown == 1 else "s") + " and point paths"))
    return {"ax": ax, "lines": lines, "paths": drawn, "guides": guides}


def _draw_guides(ax: Any, kin: Any, positions: Sequence[int], colours: dict[str, Any]
                 ) -> list[Any]:
    """Guides (prismatic joints) and slots (pin-in-slot joints) as wide translucent segments
    on their body, over the stretch the slider point or pin travels (plus a margin)."""
    mech = kin.mechanism
    out = []
    for j in mech.joints:
        if j.code not in ("P", "S"):  # prismatic joints and pin-in-slot joints have a line
            continue
        qa, pb, ang = mech.joint_geometry(j)
        ia = mech.index[j.a]
        pm = kin.point(j.b, pb)
        for idx in positions:
            c, s = np.cos(kin.theta[ia]), np.sin(kin.theta[ia])
            qx = kin.x[ia] + c * qa[0] - s * qa[1]
            qy = kin.y[ia] + s * qa[0] + c * qa[1]
            ux, uy = c * np.cos(ang) - s * np.sin(ang), s * np.cos(ang) + c * np.sin(ang)
            # travel of the slider point along the line, relative to the line's body
            t = (pm.x - qx) * ux + (pm.y - qy) * uy
            t = t[np.isfinite(t)]
            if t.size == 0:
                continue
            lo, hi = float(t.min()), float(t.max())
            pad = 0.15 * max(hi - lo, 1e-3)
            lo, hi = lo - pad, hi + pad
            x0, y0, ex, ey = qx[idx], qy[idx], ux[idx], uy[idx]
            colour = "k" if j.a == mech.frame.name else colours.get(j.a, "0.4")
            kind = "slot" if j.code == "S" else "guide"
            label = kind if j.name.lower() == kind else f"{kind} {j.name}"
            (ln,) = ax.plot([(x0 + lo * ex) * 1e3, (x0 + hi * ex) * 1e3],
                            [(y0 + lo * ey) * 1e3, (y0 + hi * ey) * 1e3], "-", lw=6,
                            alpha=0.18, color=colour, solid_capstyle="butt",
                            label=label)
            out.append(ln)
    return out


def _prefixed(unit: str, *values: Any) -> tuple[float, str]:
    """Divisor and unit for plotting ``values`` [unit]: N below 10 kN, kN below 10 MN, then MN
    (a 300 kN press force read as '3.0' under a '1e5' offset is easy to misread)."""
    peak = max((float(np.nanmax(np.abs(v))) if np.size(v) and not np.all(np.isnan(v)) else 0.0)
               for v in values)
    for div, prefix in ((1e6, "M"), (1e3, "k")):
        if peak >= 10 * div:
            return div, prefix + unit
    return 1.0, unit


def plot_driving_torque(dyn: Any, ax: Any = None, *, name: str | None = None
                        ) -> dict[str, Any]:
    """Driving torque (or force) over the cycle, with its mean. ``name`` (of the mechanism)
    heads the title. With friction in some joint also the driving torque without friction
    (dashed) and the self-locking ranges (shaded). Returns ``{"ax", "line"}`` (and
    ``"frictionless"`` with friction)."""
    ax = _ax(ax)
    x, label = _x(dyn.kinematics)
    if _several(dyn.kinematics):
        return _driving_loads(dyn, ax, x, label, name)
    crank = not _linear(dyn.kinematics)
    friction = bool(getattr(dyn, "has_friction", False))
    div, unit = _prefixed("N·m" if crank else "N", dyn.Q,
                          *((dyn.Q_frictionless,) if friction else ()))
    (ln,) = ax.plot(x, dyn.Q / div, label="Q")
    extra: dict[str, Any] = {}
    if friction:
        (extra["frictionless"],) = ax.plot(x, dyn.Q_frictionless / div, ls="--", lw=1.0,
                                           label="Q without friction")
        sc = 180.0 / np.pi if crank else 1e3  # the x axis: deg or mm
        for k, (a, b) in enumerate(dyn.self_locking_ranges()):
            ax.axvspan(a * sc, b * sc, color="tab:red", alpha=0.2,
                       label="self-locking" if k == 0 else None)
    mean = dyn.Q_mean / div
    peak = float(np.nanmax(np.abs(dyn.Q))) / div if np.isfinite(dyn.Q).any() else 0.0
    shown = 0.0 if abs(mean) <= 1e-9 * peak else mean  # round-off of a zero mean: 0
    if np.isfinite(mean):  # undefined where Q is (self-locking, unassembled positions)
        ax.axhline(mean, color="k", lw=0.8, ls=":",
                   label=f"mean {shown:.4g} {unit} (work / range)")
    ax.set_xlabel(label)
    quantity = "driving torque Q" if crank else "driving force Q"
    ax.set_ylabel(f"{quantity} [{unit}]")
    finish(ax, title=titled(name, "Dynamics", quantity), angle=_angle(dyn.kinematics, x))
    return {"ax": ax, "line": ln, **extra}


def _driving_loads(dyn: Any, ax: Any, x: np.ndarray, label: str, name: str | None
                   ) -> dict[str, Any]:
    """Several drivers: each one's driving torque or force, in its own unit, over the
    position along their path."""
    drivers = dyn.kinematics.mechanism.drivers
    lines = []
    for k, d in enumerate(drivers):
        unit = "N·m" if d.kind == "crank" else "N"
        div, shown = _prefixed(unit, dyn.Q[k])
        (ln,) = ax.plot(x, dyn.Q[k] / div, label=f"Q {d.joint} [{shown}]")
        lines.append(ln)
    ax.set_xlabel(label)
    ax.set_ylabel("driving torque / force Q")
    finish(ax, title=titled(name, "Dynamics", "driving loads Q of the drivers"))
    return {"ax": ax, "line": lines[0], "lines": lines}


def plot_reactions(dyn: Any, joints: Sequence[str] | None = None, ax: Any = None, *,
                   name: str | None = None) -> dict[str, Any]:
    """Magnitudes of joint reactions over the cycle; reactions equal over most of the cycle
    (the two ends of a two-force member) in their own dash pattern and markers. ``name`` (of
    the mechanism) heads the title. Returns ``{"ax", "lines"}``."""
    ax = _ax(ax)
    x, label = _x(dyn.kinematics)
    mags = {j: dyn.reaction_magnitude(j) for j in joints or dyn.joints}
    div, unit = _prefixed("N", *mags.values())
    lines = []
    for j, mag in mags.items():
        (ln,) = ax.plot(x, mag / div, label=j)
        lines.append(ln)
    ax.set_xlabel(label)
    ax.set_ylabel(f"|R| [{unit}]")
    finish(ax, title=titled(name, "Dynamics", "joint reactions |R| (force of a on b)"),
           angle=_angle(dyn.kinematics, x), legend_kw={"title": "joint"})
    return {"ax": ax, "lines": lines}


def plot_loads(dyn: Any, names: Sequence[str] | None = None, axes: Any = None, *,
               name: str | None = None) -> dict[str, Any]:
    """The value of loads over the cycle (``dyn.loads``, or those called ``names``): forces
    [N] (a spring's or damper's tension, a slide force, a drag's magnitude, a diagram's force)
    on the first axes, couples [N m] on the second. ``name`` (of the mechanism) heads the
    title. Returns ``{"axes", "lines"}``."""
    shown = [ap for ap in dyn.loads if names is None or ap.name in names]
    forces = [ap for ap in shown if ap.unit == "N"]
    couples = [ap for ap in shown if ap.unit != "N"]
    groups = [(g, u, q) for g, u, q in ((forces, "N", "force"), (couples, "N·m", "couple"))
              if g]
    if not groups:
        raise ParameterError("names", names, f"no load to draw; known: "
                             f"{[ap.name for ap in dyn.loads]}")
    axes = axes_or_new(axes, len(groups), 1, sharex=True)
    axes = list(np.atleast_1d(axes))
    x, label = _x(dyn.kinematics)
    angle = _angle(dyn.kinematics, x)
    lines = []
    for k, (ax, (group, unit, quantity)) in enumerate(zip(axes, groups, strict=True)):
        div, shown_unit = _prefixed(unit, *(ap.value for ap in group))
        for ap in group:
            lines.append(ax.plot(x, ap.value / div, label=f"{ap.name} ({ap.kind})")[0])
        ax.set_ylabel(f"{quantity} [{shown_unit}]")
        title = (titled(name, "Dynamics", "loads and force elements (springs and dampers: "
                        "tension +)") if k == 0 else None)
        finish(ax, title=title, angle=angle, legend_kw={"title": "load"})
    axes[-1].set_xlabel(label)
    return {"axes": axes, "lines": lines}


def plot_shaking(dyn: Any, axes: Any = None, *, name: str | None = None) -> dict[str, Any]:
    """Shaking force components and shaking moment. ``name`` (of the mechanism) heads the
    title. Returns ``{"axes", "lines"}``."""
    axes = axes_or_new(axes, 2, 1, sharex=True)
    x, label = _x(dyn.kinematics)
    fdiv, funit = _prefixed("N", dyn.shaking_fx, dyn.shaking_fy)
    mdiv, munit = _prefixed("N·m", dyn.shaking_m)
    lines = [axes[0].plot(x, dyn.shaking_fx / fdiv, label="Fx")[0],
             axes[0].plot(x, dyn.shaking_fy / fdiv, label="Fy")[0],
             axes[1].plot(x, dyn.shaking_m / mdiv, label="M about ({:g}, {:g}) mm".format(
                 *(1e3 * np.asarray(dyn.about, dtype=float))))[0]]
    axes[0].set_ylabel(f"shaking force [{funit}]")
    axes[1].set_ylabel(f"shaking moment [{munit}]")
    axes[1].set_xlabel(label)
    angle = _angle(dyn.kinematics, x)
    finish(axes[0], title=titled(name, "Dynamics", "shaking force and moment on the frame"),
           angle=angle)
    finish(axes[1], angle=angle)
    return {"axes": axes, "lines": lines}


def _pva_axes(axes: Any) -> Any:
    return axes_or_new(axes, 3, 1, figsize=(8, 8.5), sharex=True)


def kinematics_figure(kin: Kinematics, bodies: Sequence[str] | None = None, axes: Any = None,
                      *, name: str | None = None) -> Figure:
    """Angles [deg], angular velocities [rad/s] and angular accelerations [rad/s²] of the moving
    bodies over the driver (3 axes, one line per body); ``name`` (of the mechanism) heads the
    title."""
    ax = _pva_axes(axes)
    x, label = _x(kin)
    names = list(kin.bodies[1:]) if bodies is None else list(bodies)
    lines: dict[str, list[Any]] = {}
    for body in names:
        i = kin.bodies.index(body)
        lines[body] = [
            ax[0].plot(x, np.degrees(np.unwrap(kin.theta[i])), label=body)[0],
            ax[1].plot(x, kin.omega[i], label=body)[0],
            ax[2].plot(x, kin.eps[i], label=body)[0]]
    for a, ylab in zip(ax, ("angle θ [deg]", "angular velocity ω [rad/s]",
                            "angular acceleration ε [rad/s²]"), strict=True):
        a.set_ylabel(ylab)
        finish(a, angle=_angle(kin, x), show_legend=a is ax[0])
    ax[-1].set_xlabel(label)
    figure_title(ax[0].figure, titled(name, "Kinematics", "angles, angular velocities and "
                                      "accelerations of the bodies"))
    return Figure.of(ax, lines=lines)


def point_motion_figure(pm: PointMotion, axes: Any = None, *, name: str | None = None
                        ) -> Figure:
    """Position [mm], velocity [m/s] and acceleration [m/s²] components of a point over the
    driver positions (3 axes, x and y in each); ``name`` (of the mechanism) heads the title."""
    ax = _pva_axes(axes)
    x, label = _x(pm)
    for a, (qx, qy, ylab) in zip(ax, ((pm.x * 1e3, pm.y * 1e3, "position [mm]"),
                                      (pm.vx, pm.vy, "velocity [m/s]"),
                                      (pm.ax, pm.ay, "acceleration [m/s²]")), strict=True):
        a.plot(x, qx, label="x")
        a.plot(x, qy, label="y")
        a.set_ylabel(ylab)
        finish(a, angle=_angle(pm, x))
    ax[-1].set_xlabel(label)
    figure_title(ax[0].figure, titled(name, "PointMotion", "motion of a point"))
    return Figure.of(ax)


def dynamics_figure(dyn: Dynamics, joints: Sequence[str] | None = None, axes: Any = None,
                    *, name: str | None = None) -> Figure:
    """Driving torque (or force) with its mean, and the joint reaction magnitudes over the
    driver positions (2 axes): :func:`plot_driving_torque`, :func:`plot_reactions`."""
    ax = axes_or_new(axes, 2, 1, figsize=(8, 7), sharex=True)
    torque = plot_driving_torque(dyn, ax=ax[0], name=name)
    reactions = plot_reactions(dyn, joints, ax=ax[1], name=name)
    return Figure.of(ax, torque=torque, reactions=reactions)
