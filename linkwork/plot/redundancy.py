"""Figures for spatial reactions with redundant constraints: components over the cycle, bending
moments, Monte-Carlo histograms of the peaks."""

from __future__ import annotations

from collections.abc import Sequence
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
    from linkwork.redundancy.core import SpatialReactions
    from linkwork.redundancy.tolerance import ToleranceStudy

__all__ = ["plot_bending", "plot_components", "plot_peak_histogram", "reactions_figure",
           "tolerance_figure"]

_UNIT = {"fx": "N", "fy": "N", "fz": "N", "mx": "N·m", "my": "N·m", "mz": "N·m",
         "bending": "N·m", "Q": "N·m"}


_NAME = {"fx": "force fx", "fy": "force fy", "fz": "axial force fz", "mx": "moment mx",
         "my": "moment my", "mz": "moment mz", "bending": "bending moment"}


def _linear(result: Any) -> bool:
    """A linear driver: its results carry ``units["phi1"] == "m"``."""
    return bool(getattr(result, "units", {}).get("phi1") == "m")


def _several(result: Any) -> bool:
    """Several drivers: their positions are rows of ``phi1``."""
    return bool(np.ndim(result.phi1) == 2)


def _driver_axis(result: Any) -> tuple[np.ndarray, str]:
    """x values and label of the driver positions: degrees, or mm for a linear driver; the
    index of the position along the path of several drivers."""
    phi = np.asarray(result.phi1, dtype=float)
    if _several(result):
        return np.arange(phi.shape[-1], dtype=float), "position along the drivers' path"
    if _linear(result):
        return phi * 1e3, "driver position s1 [mm]"
    return np.degrees(phi), "driver position φ1 [deg]"


def _ax(ax: Any) -> Any:
    return axes_or_new(ax, figsize=(7, 4))


def plot_components(result: Any, component: str = "fz", joints: Sequence[str] | None = None,
                    ax: Any = None, *, name: str | None = None, title: str | None = None,
                    legend: bool = True) -> dict[str, Any]:
    """One reaction component of several joints over the driver positions.

    Parameters
    ----------
    result : linkwork.redundancy.SpatialReactions
    component : str
        ``fx, fy, fz, mx, my, mz`` or ``bending`` (sqrt(mx² + my²)).
    joints : sequence of str, optional
        Default all joints.
    ax : matplotlib Axes, optional
    name : str, optional
        Of the mechanism, heads the title.
    title : str, optional
        The title as given instead of ``"<name>: <component>"``.
    legend : bool
        Draw the legend (a panel of components shows it once).

    Returns
    -------
    dict
        ``{"ax": ax, joint: Line2D, ...}``.
    """
    ax = _ax(ax)
    names = list(result.joints) if joints is None else list(joints)
    data = result.bending() if component == "bending" else getattr(result, component)
    deg, xlabel = _driver_axis(result)
    out: dict[str, Any] = {"ax": ax}
    for joint in names:
        (out[joint],) = ax.plot(deg, data[result.joints.index(joint)], label=joint)
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"{component} [{_UNIT.get(component, '')}]")
    quantity = f"{_NAME.get(component, component)} in the joints"
    finish(ax, title=titled(name, "SpatialReactions", quantity) if title is None else title,
           angle=None if _linear(result) or _several(result) else deg,
           legend_kw={"title": "joint"},
           show_legend=legend)
    return out


def plot_bending(result: Any, axes: Any = None, *, name: str | None = None) -> dict[str, Any]:
    """A 2x2 panel: axial forces fz, bending moments mx, my and the driving torque Q; ``name``
    (of the mechanism) heads the figure's title.

    Returns ``{"axes": axes, "fz": {...}, "mx": {...}, "my": {...}, "Q": Line2D}``.
    """
    axes = axes_or_new(axes, 2, 2, figsize=(11, 7), sharex=True)
    ax = np.asarray(axes).ravel()
    out: dict[str, Any] = {"axes": axes}
    for a, comp in zip(ax[:3], ("fz", "mx", "my"), strict=True):
        # one legend for the three panels (same joints, same colours): top right
        out[comp] = plot_components(result, comp, ax=a, title=_NAME[comp], legend=a is ax[1])
    deg, xlabel = _driver_axis(result)
    ax[3].set_xlabel(xlabel)
    if _several(result):  # each driver's torque or force, in its own unit
        units = str(getattr(result, "units", {}).get("Q", "N*m")).split(", ")
        lines = []
        for k, joint in enumerate(result.drivers):
            unit = (units[k] if len(units) > 1 else units[0]).replace("N*m", "N·m")
            (ln,) = ax[3].plot(deg, result.Q[k], label=f"Q {joint} [{unit}]")
            lines.append(ln)
        out["Q"] = lines[0]
        out["Q_lines"] = lines
        ax[3].set_ylabel("driving torque / force Q")
        finish(ax[3], title="driving loads of the drivers")
    else:
        (out["Q"],) = ax[3].plot(deg, result.Q, color="k")
        linear = getattr(result, "units", {}).get("Q") == "N"
        ax[3].set_ylabel("driving force Q [N]" if linear else "driving torque Q [N·m]")
        finish(ax[3], title="driving force" if linear else "driving torque",
               angle=None if _linear(result) else deg)
    for a in ax[:2]:  # the x axis is shared: its label under the bottom row only
        a.set_xlabel("")
    figure_title(ax[0].figure, titled(name, "SpatialReactions", "joint reactions in space"))
    return out


def plot_peak_histogram(study: Any, joint: str, quantity: str = "bending", ax: Any = None,
                        bins: int = 40, percentiles: Sequence[float] = (50.0, 95.0, 99.0),
                        reference: dict[str, float] | None = None, *,
                        name: str | None = None) -> dict[str, Any]:
    """Histogram of the peak over the cycle of one quantity of one joint, over the samples.

    Parameters
    ----------
    study : linkwork.redundancy.ToleranceStudy
    joint, quantity : str
        As for :meth:`ToleranceStudy.sample`.
    ax : matplotlib Axes, optional
    bins : int
    percentiles : sequence of float
        Drawn as vertical lines, each in its own colour and style; the nominal (no deviation)
        peak as a black dashed line.
    reference : mapping label -> value, optional
        Further peaks drawn as dash-dotted lines (e.g. the file's systematic deviations, around
        which the samples are drawn).
    name : str, optional
        Of the mechanism, heads the title.

    Returns
    -------
    dict
        ``{"ax": ax, "hist": (counts, edges, patches), "p50": Line2D, ..., "nominal": Line2D,
        <reference label>: Line2D}``.
    """
    ax = _ax(ax)
    vals = study.sample(joint, quantity)
    out: dict[str, Any] = {"ax": ax}
    out["hist"] = ax.hist(vals, bins=bins, color="0.7", edgecolor="0.4")
    styles = [("C0", ":"), ("C1", "-"), ("C3", "-"), ("C4", "-."), ("C5", ":")]
    for i, q in enumerate(percentiles):
        v = float(np.percentile(vals, q))
        color, ls = styles[i % len(styles)]
        out[f"p{q:g}"] = ax.axvline(v, color=color, ls=ls, lw=1.2 + 0.3 * i,
                                    label=f"p{q:g} = {v:.4g}")
    nom = float(study.nominal[study.joints.index(joint), study.quantities.index(quantity)])
    out["nominal"] = ax.axvline(nom, color="k", ls="--", lw=1.0, label=f"no deviation = {nom:.4g}")
    for label, v in (reference or {}).items():
        out[label] = ax.axvline(float(v), color="C2", ls="-.", lw=1.2,
                                label=f"{label} = {float(v):.4g}")
    ax.set_xlabel(f"peak {quantity} at joint {joint} over the cycle "
                  f"[{_UNIT.get(quantity, '')}]")
    ax.set_ylabel(f"samples (N = {study.n_samples})")
    finish(ax, title=titled(name, "ToleranceStudy", f"peak {_NAME.get(quantity, quantity)} at "
                            f"joint {joint}, {study.n_samples} samples"))
    return out


def reactions_figure(result: SpatialReactions, axes: Any = None, *, name: str | None = None
                     ) -> Figure:
    """Axial forces, bending moments and the driving torque (4 axes): :func:`plot_bending`."""
    return Figure.of(plot_bending(result, axes=axes, name=name))


def tolerance_figure(study: ToleranceStudy, quantity: str = "bending", axes: Any = None,
                     **kw: Any) -> Figure:
    """Histograms of the peak ``quantity`` over the samples, one axes per joint:
    :func:`plot_peak_histogram`."""
    n = len(study.joints)
    ax = np.atleast_1d(axes_or_new(axes, n, 1, figsize=(7, 3.2 * n), squeeze=False)).ravel()
    hists = {name: plot_peak_histogram(study, name, quantity, ax=a, **kw)
             for a, name in zip(ax, study.joints, strict=True)}
    return Figure.of(ax, histograms=hists)
