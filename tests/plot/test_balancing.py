"""Balancing plots draw what they are given."""

from __future__ import annotations

import numpy as np

from linkwork.plot import pyplot
from linkwork.plot.balancing import (
    plot_force_hodograph,
    plot_moments,
    plot_pareto,
    plot_torques,
)


def test_plots_draw_their_data():
    plt = pyplot()
    phi = np.linspace(0, 2 * np.pi, 10, endpoint=False)
    out = plot_moments(phi, {"M": np.sin(phi)}, markers={"paper": ([0, 90], [1.0, 2.0])})
    np.testing.assert_allclose(out["M"].get_xdata(), np.degrees(phi))
    np.testing.assert_allclose(out["M"].get_ydata(), np.sin(phi))
    np.testing.assert_allclose(out["paper"].get_ydata(), [1.0, 2.0])
    out = plot_torques(phi, {"Q": np.cos(phi)})
    assert out["ax"].get_ylabel().startswith("driving torque")
    F = np.stack([np.cos(phi), 2 * np.sin(phi)], -1)
    out = plot_force_hodograph({"F": F})
    np.testing.assert_allclose(out["F"].get_xydata(), F)
    out = plot_pareto([1.0, 2.0], [3.0, 1.0], [0.5, 0.7], points={"static": (0.0, 5.0)})
    np.testing.assert_allclose(out["pareto"].get_offsets(), [[1.0, 3.0], [2.0, 1.0]])
    np.testing.assert_allclose(out["static"].get_xydata(), [[0.0, 5.0]])
    plt.close("all")


def test_force_hodograph_shows_the_balanced_variant_and_closes_the_cycle():
    """The statically balanced hodograph (|F| ~ 1e-14 N) was a line of zero length: listed in
    the legend, invisible on the plot; the unbalanced one had a gap between the last sample
    and the first."""
    from linkwork.plot.balancing import plot_force_hodograph

    phi = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    F0 = np.stack([40 * np.cos(phi), 20 * np.sin(phi)], -1)
    F1 = 1e-14 * F0
    out = plot_force_hodograph({"unbalanced": F0, "static": F1})
    ax = out["ax"]
    ends = {(tuple(np.round(ln.get_xydata()[0], 9)), tuple(np.round(ln.get_xydata()[-1], 9)))
            for ln in ax.get_lines()}
    assert ((tuple(np.round(F0[-1], 9)), tuple(np.round(F0[0], 9)))) in ends
    line = out["static"]
    assert line.get_marker() not in ("None", "", None, " ")
    assert "static" in line.get_label()
    import matplotlib.pyplot as plt

    plt.close(out["ax"].figure)


def test_pareto_plot_separates_dominated_designs():
    """balancing_pareto.png drew dominated and non-dominated designs alike (e.g. the design at
    F = 0, M = 5.75 N m beaten by the static one), although pareto_set flags them."""
    from linkwork.plot import pyplot
    from linkwork.plot.balancing import plot_pareto

    out = plot_pareto([0.0, 1.0, 2.0], [2.0, 1.0, 3.0], [1.0, 1.0, 2.0],
                      dominated=[False, False, True])
    assert out["pareto"].get_offsets().shape[0] == 2
    assert np.allclose(out["dominated"].get_offsets(), [[2.0, 3.0]])
    pyplot().close("all")
