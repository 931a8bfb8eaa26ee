"""Figures of machine dynamics (:mod:`linkwork.machine`): the crank's real speed, the motor's
torque, the energy-mass (Wittenbauer) diagram, transients over time with their switches.

Speeds are drawn in rpm (the unit of motor and press catalogues), angles in degrees; results
are read by their attributes (SI), imported for type checking only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from linkwork.plot._base import Figure, axes_or_new, figure_title, finish, titled

if TYPE_CHECKING:
    from linkwork.machine.flywheel import FlywheelSizing
    from linkwork.machine.steady import SteadyState
    from linkwork.machine.transient import Run

__all__ = ["plot_energy_mass", "plot_speed", "plot_torque", "plot_transient",
           "reduction_figure", "steady_figure", "transient_figure"]

RPM = 30.0 / math.pi


def _runs(results: Any, labels: Sequence[str] | None) -> list[tuple[Any, str, np.ndarray]]:
    """(steady state, label, crank angles [deg] closed over the turn) of each result."""
    runs = [results] if not isinstance(results, Sequence) else list(results)
    out = []
    for k, ss in enumerate(runs):
        motor = getattr(ss, "motor", None)
        lab = labels[k] if labels is not None else (getattr(motor, "name", None)
                                                     or f"motor {k + 1}")
        out.append((ss, lab, np.degrees(np.append(ss.phi1, ss.phi1[0] + 2 * np.pi))))
    return out


def _closed(values: np.ndarray) -> np.ndarray:
    return np.append(values, values[0])


def plot_speed(results: SteadyState | Sequence[SteadyState], ax: Any = None, *,
               name: str | None = None, labels: Sequence[str] | None = None) -> dict[str, Any]:
    """Crank speed over the crank angle [rpm] of one steady state or several (one motor each),
    with each one's mean speed and delta in the legend. Returns ``{"ax", "lines"}``."""
    ax = axes_or_new(ax)
    runs = _runs(results, labels)
    lines = []
    for ss, lab, x in runs:
        (ln,) = ax.plot(x, _closed(ss.omega) * RPM, label=f"{lab}: mean "
                        f"{ss.omega_mean * RPM:.4g} rpm, δ = {ss.delta:.3g}")
        ax.axhline(ss.omega_mean * RPM, color=ln.get_color(), lw=0.7, ls=":")
        lines.append(ln)
    ax.set_xlabel("crank angle φ1 [deg]")
    ax.set_ylabel("crank speed ω [rpm]")
    finish(ax, title=titled(name, "SteadyState", "crank speed in the steady state"),
           angle=runs[0][2])
    return {"ax": ax, "lines": lines}


def plot_torque(results: SteadyState | Sequence[SteadyState], ax: Any = None, *,
                name: str | None = None, labels: Sequence[str] | None = None
                ) -> dict[str, Any]:
    """Motor torque at its shaft over the crank angle [N m], with each motor's limit (the
    breakdown or stall torque, or the drive's peak torque) dashed and its RMS dotted. Returns
    ``{"ax", "lines"}``."""
    ax = axes_or_new(ax)
    runs = _runs(results, labels)
    lines = []
    for ss, lab, x in runs:
        (ln,) = ax.plot(x, _closed(ss.torque), label=lab)
        c = ln.get_color()
        ax.axhline(ss.torque_rms, color=c, lw=0.7, ls=":")
        limit = getattr(ss.motor, "max_torque", None)
        if limit is not None:
            ax.axhline(limit, color=c, lw=1.0, ls="--", label=f"{lab}: limit {limit:.4g} N·m")
        lines.append(ln)
    ax.set_xlabel("crank angle φ1 [deg]")
    ax.set_ylabel("motor torque at its shaft [N·m]")
    finish(ax, title=titled(name, "SteadyState", "motor torque (RMS dotted, limit dashed)"),
           angle=runs[0][2])
    return {"ax": ax, "lines": lines}


def steady_figure(ss: SteadyState, axes: Any = None, *, name: str | None = None) -> Figure:
    """Crank speed and motor torque of a steady state over the crank angle (2 axes)."""
    ax = axes_or_new(axes, 2, 1, figsize=(8, 7), sharex=True)
    speed = plot_speed(ss, ax=ax[0], name=name)
    torque = plot_torque(ss, ax=ax[1], name=name)
    return Figure.of(ax, speed=speed, torque=torque)


def plot_energy_mass(sizing: FlywheelSizing, ax: Any = None, *, name: str | None = None
                     ) -> dict[str, Any]:
    """Wittenbauer's energy-mass diagram: the change of kinetic energy against the reduced
    moment of inertia over the cycle, with the two tangents of slopes omega_max^2/2 and
    omega_min^2/2 and their intersection, whose distance from the energy axis is the flywheel
    (:class:`~linkwork.machine.flywheel.FlywheelSizing`). Returns ``{"ax", "curve"}``."""
    ax = axes_or_new(ax)
    w = sizing.wittenbauer
    J, E = w["J"], w["dE"]
    (curve,) = ax.plot(np.append(J, J[0]), np.append(E, E[0]) / 1e3, label="ΔE(J) over the cycle")
    xs = np.array([-w["flywheel"], float(np.max(J))])
    for slope, b, lab in ((w["k_max"], w["b_max"], "ω_max²/2"), (w["k_min"], w["b_min"],
                                                                  "ω_min²/2")):
        ax.plot(xs, (slope * xs + b) / 1e3, lw=0.9, ls="--", label=f"tangent, slope {lab}")
    ax.plot([-w["flywheel"]], [(w["k_max"] * -w["flywheel"] + w["b_max"]) / 1e3], "ko", ms=4)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.annotate(f"flywheel {w['flywheel']:.4g} kg·m²", (-w["flywheel"], 0.0),
                textcoords="offset points", xytext=(4, 6), fontsize="small")
    ax.set_xlabel("reduced moment of inertia J(φ1) [kg·m²] (flywheel to the left)")
    ax.set_ylabel("change of kinetic energy ΔE [kJ]")
    finish(ax, title=titled(name, "FlywheelSizing", f"energy-mass diagram, δ = "
                            f"{sizing.delta:.3g}"))
    return {"ax": ax, "curve": curve}


def plot_transient(run: Run, axes: Any = None, *, name: str | None = None) -> dict[str, Any]:
    """Crank speed [rpm] and motor torque [N m] over time, the switches of a schedule marked
    (vertical lines, the mode entered written at each). Returns ``{"axes", "lines"}``."""
    axes = axes_or_new(axes, 2, 1, figsize=(9, 7), sharex=True)
    (l1,) = axes[0].plot(run.t, run.omega * RPM, lw=0.9, label="crank speed")
    (l2,) = axes[1].plot(run.t, run.torque, lw=0.9, label="motor torque")
    for k, (ts, to) in enumerate(zip(run.switch_t, run.switch_to, strict=True)):
        for a in axes:
            a.axvline(ts, color="tab:red", lw=0.7, ls="--", label="switch" if k == 0 else None)
        axes[0].annotate(str(run.modes[int(to)]), (ts, 1.0), xycoords=("data", "axes fraction"),
                         textcoords="offset points", xytext=(2, -10), fontsize="x-small")
    axes[0].set_ylabel("crank speed ω [rpm]")
    axes[1].set_ylabel("motor torque [N·m]")
    axes[1].set_xlabel("time t [s]")
    finish(axes[0])
    finish(axes[1])
    figure_title(axes[0].figure, titled(name, "Run", "speed and motor torque over time"))
    return {"axes": axes, "lines": [l1, l2]}


def transient_figure(run: Run, axes: Any = None, *, name: str | None = None) -> Figure:
    """:func:`plot_transient` as a :class:`Figure` (2 axes)."""
    return Figure.of(plot_transient(run, axes, name=name))


def reduction_figure(red: Any, axes: Any = None, *, name: str | None = None) -> Figure:
    """The mechanism reduced to its crank (:class:`linkwork.machine.reduction.Reduction`): the
    reduced moment of inertia J and its derivative dJ/dphi1 (top), the reduced moments of the
    loads and of gravity (bottom), over the crank angle (2 axes)."""
    ax = axes_or_new(axes, 2, 1, figsize=(8, 7), sharex=True)
    x = np.degrees(red.phi1)
    (j,) = ax[0].plot(x, red.J, label="J [kg·m²]")
    (dj,) = ax[0].plot(x, red.dJ, ls="--", label="dJ/dφ1 [kg·m²/rad]")
    ax[0].set_ylabel("reduced inertia")
    finish(ax[0], title=titled(name, "Reduction", "reduced moment of inertia"), angle=x)
    (ml,) = ax[1].plot(x, red.M_loads, label="loads")
    (mg,) = ax[1].plot(x, red.M_gravity, ls="--", label="gravity")
    ax[1].set_xlabel("crank angle φ1 [deg]")
    ax[1].set_ylabel("reduced moment [N·m]")
    finish(ax[1], title=titled(name, "Reduction", "reduced moments (positive: driving)"),
           angle=x)
    return Figure.of(ax, inertia={"ax": ax[0], "lines": [j, dj]},
                     moments={"ax": ax[1], "lines": [ml, mg]})
