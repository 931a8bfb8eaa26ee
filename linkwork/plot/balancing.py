"""Figures for balancing: residual moments, shaking force hodographs, torques, Pareto sets.

The ``plot_*`` functions take arrays and ``ax=None`` and return a dict of what they drew; the
``*_figure`` functions draw a balancing result and return a :class:`~linkwork.plot.Figure`
(what ``result.plot()`` gives).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.plot._base import (
    Figure,
    axes_or_new,
    figure_title,
    finish,
    pyplot,  # noqa: F401  (importable here, as before)
    titled,
)

if TYPE_CHECKING:
    from linkwork.balancing.comparison import BalancingComparison, CycleComparison
    from linkwork.balancing.mechanism import ForceBalance, ShakingLoads
    from linkwork.balancing.optimal import OptimalBalance, ParetoSet
    from linkwork.balancing.partial import AxisOffset
    from linkwork.balancing.static import Counterweight
    from linkwork.cycles import Harmonics
    from linkwork.studies.balance import PathBalanceStudy

__all__ = ["axis_offset_figure", "balancing_comparison_figure", "counterweights_figure",
           "cycle_comparison_figure", "force_balance_figure", "harmonics_figure",
           "optimal_balance_figure", "pareto_figure", "path_balance_figure", "plot_bars",
           "plot_force_hodograph",
           "plot_moments", "plot_pareto", "plot_torques", "shaking_loads_figure"]


def _ax(ax: Any) -> Any:
    return axes_or_new(ax, figsize=(7, 4))


def _quantity(label: str) -> str:
    """An axis label without its unit: ``"shaking moment [N·m]"`` -> ``"shaking moment"``."""
    return label.split(" [")[0]


def plot_moments(phi: ArrayLike, curves: Mapping[str, ArrayLike], ax: Any = None,
                 ylabel: str = "shaking moment [N·m]",
                 markers: Mapping[str, tuple[ArrayLike, ArrayLike]] | None = None,
                 *, name: str | None = None, title: str | None = None) -> dict[str, Any]:
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
    name : str, optional
        Of the mechanism, heads the title (``"<name>: <quantity of ylabel>"``).
    title : str, optional
        The title as given instead ("": none, e.g. under a figure title).

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
    finish(ax, title=titled(name, "Balancing", _quantity(ylabel)) if title is None
           else title or None, angle=deg)
    return out


def plot_torques(phi: ArrayLike, curves: Mapping[str, ArrayLike], ax: Any = None, *,
                 name: str | None = None) -> dict[str, Any]:
    """Driving torque (or bearing-reaction magnitudes) over the crank angle, before/after."""
    return plot_moments(phi, curves, ax=ax, ylabel="driving torque [N·m]", name=name)


def plot_force_hodograph(forces: Mapping[str, ArrayLike], ax: Any = None, *,
                         name: str | None = None) -> dict[str, Any]:
    """Shaking-force hodographs: the tip of (Fx, Fy) over a cycle, per mechanism variant.

    Parameters
    ----------
    forces : mapping label -> array_like of shape (n, 2)
        Shaking force [N].
    name : str, optional
        Of the mechanism, heads the title.
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
    finish(ax, title=titled(name, "Balancing", "shaking-force hodograph over a cycle"))
    return out


def plot_pareto(force_rms: ArrayLike, moment_rms: ArrayLike,
                torque_fluct: ArrayLike, ax: Any = None,
                points: Mapping[str, tuple[float, float]] | None = None,
                dominated: ArrayLike | None = None, *, name: str | None = None
                ) -> dict[str, Any]:
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
    finish(ax, title=titled(name, "Balancing", "optimal counterweights, RMS shaking force and "
                            "moment"), legend_kw={"outside": "below"})
    return out


def plot_bars(values: Mapping[str, float], ax: Any = None, ylabel: str = "",
              fmt: str = "%.4g", *, title: str | None = None) -> dict[str, Any]:
    """One labelled bar per entry of ``values`` (label -> number), values written on the bars,
    ``title`` above.

    Returns ``{"ax": ax, "bars": BarContainer}``.
    """
    ax = _ax(ax)
    bars = ax.bar(list(values), [float(v) for v in values.values()],
                  color=[f"C{i % 10}" for i in range(len(values))])
    ax.bar_label(bars, fmt=fmt, fontsize=8)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_ylabel(ylabel)
    finish(ax, title=title, grid="y")
    return {"ax": ax, "bars": bars}


def axis_offset_figure(r: AxisOffset, ax: Any = None, *, name: str | None = None) -> Figure:
    """Residual moment before and after moving the counterweight axis to O1 (1 axes)."""
    out = plot_moments(r.phi1, {"before": r.moment,
                                f"after ({r.method}), O1 = ({r.x * 1e3:.4g}, {r.y * 1e3:.4g})"
                                " mm": r.residual}, ax=ax, ylabel="residual moment [N·m]",
                       title=titled(name, "AxisOffset", "residual moment"))
    return Figure.of(out)


def counterweights_figure(counterweights: Sequence[Counterweight], ax: Any = None, *,
                          name: str | None = None) -> Figure:
    """Each counterweight as its first moment of mass S [kg·m], drawn as a vector at its angle
    in the frame of its link, from the link's hinge (1 axes)."""
    ax = axes_or_new(ax, figsize=(5, 5))
    arrows = {}
    for i, cw in enumerate(counterweights):
        sx, sy = cw.static_moment * np.cos(cw.angle), cw.static_moment * np.sin(cw.angle)
        r = f", r = {cw.radius * 1e3:.4g} mm" if cw.radius is not None else ""
        (arrows[cw.link],) = ax.plot([0.0, sx], [0.0, sy], "-o", color=f"C{i % 10}",
                                     markevery=[1], label=f"{cw.link}: S = "
                                     f"{cw.static_moment:.4g} kg·m at "
                                     f"{np.degrees(cw.angle):.4g}°{r}")
    ax.plot([0], [0], "k+")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("S along the link [kg·m]")
    ax.set_ylabel("S normal to the link [kg·m]")
    finish(ax, title=titled(name, "Counterweight", "first moments of mass S of the "
                            "counterweights"))
    return Figure.of(ax, lines=arrows)


def force_balance_figure(fb: ForceBalance, ax: Any = None, *, name: str | None = None
                         ) -> Figure:
    """RMS shaking force before and after the counterweights (1 axes, bars)."""
    out = plot_bars({"unbalanced": fb.force_rms_before, "balanced": fb.force_rms_after}, ax=ax,
                    ylabel="RMS shaking force [N]",
                    title=titled(name, "ForceBalance", "RMS shaking force, " + (
                        "full force balance" if fb.full else "partial force balance")))
    return Figure.of(out)


def optimal_balance_figure(ob: OptimalBalance, ax: Any = None, *, name: str | None = None
                           ) -> Figure:
    """The three criteria of an optimal design (1 axes, bars): RMS shaking force [N], RMS
    shaking moment [N·m], driving-torque fluctuation [N·m]."""
    out = plot_bars({"force RMS [N]": ob.force_rms, "moment RMS [N·m]": ob.moment_rms,
                     "torque fluct. [N·m]": ob.torque_fluct}, ax=ax, ylabel="criterion",
                    title=titled(name, "OptimalBalance", "criteria at weights (w_F, w_M, w_Q)"
                                 " = ({:g}, {:g}, {:g})".format(*ob.weights)))
    return Figure.of(out)


def pareto_figure(ps: ParetoSet, ax: Any = None, *, name: str | None = None) -> Figure:
    """The trade-off of a Pareto set (1 axes): :func:`plot_pareto` with the unbalanced and the
    statically balanced mechanism as reference points."""
    return Figure.of(plot_pareto(ps.force_rms, ps.moment_rms, ps.torque_fluct, ax=ax,
                                 points={"unbalanced": ps.unbalanced[:2],
                                         "static": ps.static[:2]},
                                 dominated=ps.dominated, name=name or "ParetoSet"))


def shaking_loads_figure(sl: ShakingLoads, axes: Any = None, *, name: str | None = None
                         ) -> Figure:
    """Shaking-force hodograph and shaking moment over the crank angle (2 axes)."""
    ax = axes_or_new(axes, 1, 2, figsize=(12, 4.5))
    force = plot_force_hodograph({"shaking force": sl.force}, ax=ax[0],
                                 name=name or "ShakingLoads")
    moment = plot_moments(sl.phi1, {"M": sl.moment}, ax=ax[1],
                          ylabel="shaking moment about ({:g}, {:g}) mm [N·m]".format(
                              *(1e3 * np.asarray(sl.point, dtype=float))),
                          name=name or "ShakingLoads")
    return Figure.of(ax, force=force, moment=moment)


def cycle_comparison_figure(c: CycleComparison, axes: Any = None, *, name: str | None = None
                            ) -> Figure:
    """The paper-001 comparison over a cycle (3 axes): shaking moments M, dM1, dM2, dM3; the
    shaking-force hodographs unbalanced and static; the driving torques."""
    ax = axes_or_new(axes, 1, 3, figsize=(17, 4.5))
    moments = plot_moments(c.phi1, {"M unbalanced": c.M, "ΔM1 static": c.dM1,
                                    "ΔM2 1st harmonic": c.dM2, "ΔM3 least sq.": c.dM3},
                           ax=ax[0], title="shaking moment")
    force = plot_force_hodograph({"unbalanced": c.F0, "static": c.F1}, ax=ax[1])
    ax[1].set_title("shaking-force hodograph")
    torque = plot_torques(c.phi1, {"unbalanced": c.Q0, "balanced": c.Q1}, ax=ax[2])
    ax[2].set_title("driving torque")
    figure_title(ax[0].figure, titled(name, "CycleComparison", "balancing over a cycle"))
    return Figure.of(ax, moments=moments, force=force, torque=torque)


def balancing_comparison_figure(bc: BalancingComparison, ax: Any = None, *,
                                name: str | None = None) -> Figure:
    """The paper-001 table as grouped bars (1 axes): M, dM1, dM2, dM3 at the table positions,
    with R2 and R3 in the title."""
    ax = _ax(ax)
    deg = np.degrees(np.asarray(bc.phi1, dtype=float))
    cols = {"M unbalanced": bc.M, "ΔM1 static": bc.dM1, "ΔM2 1st harmonic": bc.dM2,
            "ΔM3 least sq.": bc.dM3}
    width = 0.8 / len(cols)
    pos = np.arange(deg.size)
    bars = {}
    for i, (label, v) in enumerate(cols.items()):
        bars[label] = ax.bar(pos + (i - 1.5) * width, np.asarray(v, dtype=float), width,
                             label=label)
    ax.set_xticks(pos, [f"{d:.0f}" for d in deg])
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("crank angle φ1 [deg]")
    ax.set_ylabel("shaking moment [N·m]")
    finish(ax, title=titled(name, "BalancingComparison", "shaking moment at the table "
                            f"positions, R2 = {bc.R2:.1f} %, R3 = {bc.R3:.1f} %"), grid="y")
    return Figure.of(ax, bars=bars)


def harmonics_figure(h: Harmonics, ax: Any = None, *, name: str | None = None) -> Figure:
    """Amplitudes A_j of the harmonics as bars over their order j, the mean a0 as a line
    (1 axes)."""
    ax = _ax(ax)
    bars = ax.bar(np.asarray(h.order), np.asarray(h.amplitude), color="C0", label="A_j")
    line = ax.axhline(h.mean, color="C1", ls="--", label=f"mean a0 = {h.mean:.4g}")
    ax.set_xticks(np.asarray(h.order))
    ax.set_xlabel("harmonic order j")
    ax.set_ylabel("amplitude A_j [unit of the quantity]")
    finish(ax, title=titled(name, "Harmonics", "amplitudes of the harmonics"), grid="y")
    return Figure.of(ax, bars=bars, mean=line)


def path_balance_figure(study: PathBalanceStudy, axes: Any = None, *,
                        name: str | None = None) -> Figure:
    """Force balance of several drivers along their path (3 axes, over the position's index
    along the path): shaking force |F| and shaking moment before and after, and each driver's
    load before (solid) and after (dashed)."""
    ax = axes_or_new(axes, 1, 3, figsize=(17, 4.5))
    b, a = study.before, study.after
    x = np.arange(np.shape(b.fx)[-1], dtype=float)
    out: dict[str, Any] = {}
    for k, (key, f0, f1, unit) in enumerate((
            ("force", np.hypot(b.fx, b.fy), np.hypot(a.fx, a.fy), "N"),
            ("moment", b.moment, a.moment, "N·m"))):
        (l0,) = ax[k].plot(x, f0, label="unbalanced")
        (l1,) = ax[k].plot(x, f1, label="balanced")
        out[key] = (l0, l1)
        ax[k].set_xlabel("position along the drivers' path")
        ax[k].set_ylabel(f"shaking {key}{' |F|' if key == 'force' else ''} [{unit}]")
        finish(ax[k], title=f"shaking {key}")
    lines = []
    q0, q1 = study.dynamics_before.Q, study.dynamics_after.Q
    for k, d in enumerate(study.mechanism.drivers):
        unit = d.field_units["Q"].replace("N*m", "N·m")
        (l0,) = ax[2].plot(x, q0[k], label=f"Q {d.joint} [{unit}]")
        (l1,) = ax[2].plot(x, q1[k], ls="--", color=l0.get_color(),
                           label=f"Q {d.joint} balanced")
        lines += [l0, l1]
    out["Q"] = lines
    ax[2].set_xlabel("position along the drivers' path")
    ax[2].set_ylabel("driving torque / force Q")
    finish(ax[2], title="driving loads")
    figure_title(ax[0].figure, titled(name, "PathBalanceStudy",
                                      "force balance along the drivers' path"))
    return Figure.of(ax, **out)
