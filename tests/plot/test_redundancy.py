"""Plots of spatial reactions and tolerance studies draw the data they are given."""

from __future__ import annotations

import numpy as np
from _fourbar_reference import geometry, spatial_model, wrenches

from linkwork.plot import pyplot
from linkwork.plot.redundancy import plot_bending, plot_components, plot_peak_histogram
from linkwork.redundancy import Tolerance, solve_reactions, tolerance_study

PHI = np.linspace(0.0, 2 * np.pi, 24, endpoint=False)


def test_plot_components_and_bending_draw_the_data():
    m = spatial_model(z=(0.0, 0.02, 0.02, 0.0))
    r = solve_reactions(m, geometry(PHI), wrenches(PHI, z_g=(0.0, 0.02, 0.01)), phi1=PHI)
    out = plot_components(r, "bending")
    assert np.allclose(out["B"].get_ydata(), r.bending()[2])
    assert np.allclose(out["B"].get_xdata(), np.degrees(PHI))
    panel = plot_bending(r)
    assert np.allclose(panel["fz"]["C"].get_ydata(), r.fz[3])
    assert np.allclose(panel["Q"].get_ydata(), r.Q)
    pyplot().close("all")


def test_plot_peak_histogram_counts_all_samples():
    m = spatial_model()
    st = tolerance_study(m, geometry(PHI), wrenches(PHI), [Tolerance("C", "a", "tx", 1e-4)], 50)
    out = plot_peak_histogram(st, "B", "bending", bins=10)
    assert int(out["hist"][0].sum()) == 50
    assert np.isclose(out["p95"].get_xdata()[0], np.percentile(st.sample("B"), 95))
    pyplot().close("all")
