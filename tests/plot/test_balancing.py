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
