"""Figures for balancing: residual moments, shaking force hodographs, torques, Pareto sets."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.plot import pyplot

__all__ = ["plot_force_hodograph", "plot_moments", "plot_pareto", "plot_torques"]


def _ax(ax: Any) -> Any:
    if ax is None:
        _, ax = pyplot().subplots(figsize=(7, 4))
    return ax


def plot_moments(phi: ArrayLike, curves: Mapping[str, ArrayLike], ax: Any = None,
                 ylabel: str = "shaking moment [N·m]",
                 markers: Mapping[str, tuple[ArrayLike, ArrayLike]] | None = None,
                 ) -> dict[str, Any]:
    """Curves over the crank angle (e.g. M, dM1, dM2, dM3 of paper 001's table).

    Parameters
    ----------
    phi : array_like
        Crank angle [rad] (drawn in degrees).
    curves : mapping label -> array_like
        Values at ``phi``.
    ax : matplotlib Axes, optional
    markers : mapping label -> (phi_deg, values), optional
        Extra points drawn as markers (e.g. the paper's printed table).

    Returns
    -------
    dict
        ``{"ax": ax, label: Line2D, ...}``.
    """
    ax = _ax(ax)
    deg = np.degrees(np.asarray(phi, dtype=float))
    out: dict[str, Any] = {"ax": ax}
    styles = ["-", "--", "-.", ":"]
    for i, (label, y) in enumerate(curves.items()):
        (out[label],) = ax.plot(deg, np.asarray(y, dtype=float), styles[i % 4], label=label)
    for label, pts in (markers or {}).items():
        x, y = pts
        (out[label],) = ax.plot(np.asarray(x), np.asarray(y), "o", ms=4, label=label)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("crank angle φ1 [deg]")
    ax.set_ylabel(ylabel)
    ax.set_xlim(deg.min(), deg.max())
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return out


def plot_torques(phi: ArrayLike, curves: Mapping[str, ArrayLike], ax: Any = None) -> dict[str, Any]:
    """Driving torque (or bearing-reaction magnitudes) over the crank angle, before/after."""
    return plot_moments(phi, curves, ax=ax, ylabel="driving torque [N·m]")


def plot_force_hodograph(forces: Mapping[str, ArrayLike], ax: Any = None) -> dict[str, Any]:
    """Shaking-force hodographs: the tip of (Fx, Fy) over a cycle, per mechanism variant.

    Parameters
    ----------
    forces : mapping label -> array_like of shape (n, 2)
        Shaking force [N].
    """
    ax = _ax(ax)
    out: dict[str, Any] = {"ax": ax}
    arrays = {label: np.asarray(F, dtype=float) for label, F in forces.items()}
    largest = max((float(np.max(np.abs(f))) for f in arrays.values() if f.size), default=0.0)
    for label, f in arrays.items():
        size = float(np.max(np.abs(f))) if f.size else 0.0
        if size <= 1e-6 * largest:
            # a balanced variant: its hodograph is a dot at the origin, invisible as a line
            (out[label],) = ax.plot(f[:, 0], f[:, 1], "o", ms=7, markerfacecolor="none",
                                    markevery=[0], label=f"{label} (|F| ≤ {size:.1g} N)")
            continue
        (out[label],) = ax.plot(f[:, 0], f[:, 1], label=label)
        # one cycle: join the last sample to the first (no gap in the closed curve)
        ax.plot(f[[-1, 0], 0], f[[-1, 0], 1], color=out[label].get_color(), lw=out[
            label].get_linewidth())
    ax.plot([0], [0], "k+")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("Fx [N]")
    ax.set_ylabel("Fy [N]")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return out


def plot_pareto(force_rms: Sequence[float], moment_rms: Sequence[float],
                torque_fluct: Sequence[float], ax: Any = None,
                points: Mapping[str, tuple[float, float]] | None = None,
                dominated: Sequence[bool] | None = None) -> dict[str, Any]:
    """Trade-off of optimal balancing: RMS shaking force vs RMS shaking moment.

    Colour = driving-torque fluctuation. ``points`` adds labelled comparison designs
    (e.g. the unbalanced, static and paper-001 solutions) as ``label -> (F_rms, M_rms)``.
    ``dominated`` (one flag per design, e.g. ``ParetoSet.dominated``) draws the designs that
    another design beats in all three criteria as grey crosses, apart from the trade-off set.
    """
    ax = _ax(ax)
    out: dict[str, Any] = {"ax": ax}
    f = np.asarray(force_rms, dtype=float)
    m = np.asarray(moment_rms, dtype=float)
    q = np.asarray(torque_fluct, dtype=float)
    dom = np.zeros(f.shape, bool) if dominated is None else np.asarray(dominated, bool)
    keep = ~dom
    sc = ax.scatter(f[keep], m[keep], c=q[keep], cmap="viridis", s=25,
                    vmin=float(q.min()) if q.size else None,
                    vmax=float(q.max()) if q.size else None,
                    label="optimal, non-dominated" if dom.any() else "optimal (weights)")
    out["pareto"] = sc
    if dom.any():
        out["dominated"] = ax.scatter(f[dom], m[dom], marker="x", color="0.6", s=20,
                                      label="optimal, dominated")
    cb = ax.figure.colorbar(sc, ax=ax)
    cb.set_label("driving-torque fluctuation (RMS) [N·m]")
    marks = ["s", "^", "D", "v", "P", "X"]
    for i, (label, (pf, pm)) in enumerate((points or {}).items()):
        (out[label],) = ax.plot([pf], [pm], marks[i % len(marks)], ms=8, label=label,
                                markerfacecolor="none", markeredgewidth=1.5)
    ax.set_xlabel("RMS shaking force [N]")
    ax.set_ylabel("RMS shaking moment [N·m]")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return out
