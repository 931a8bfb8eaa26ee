"""linkwork.plot.swashplate: the figures draw the model's numbers."""

import math

import numpy as np

from linkwork.models import swashplate as sw
from linkwork.plot import pyplot
from linkwork.plot.swashplate import plot_drive_forces, plot_feasible_region, plot_kinematics
from linkwork.synthesis import swashplate as syn


def test_plot_kinematics_draws_s_delta_pi_v():
    d = sw.scheme_1(0.1, 0.09, 0.2, math.radians(20), 0.02, -0.01)
    res = sw.analyze(d, n=91)
    axes = plot_kinematics(res)
    x, y = axes[0].lines[0].get_data()
    np.testing.assert_allclose(x, np.degrees(res.phi))
    np.testing.assert_allclose(y, res.s * 1e3)
    np.testing.assert_allclose(axes[1].lines[0].get_ydata(), np.degrees(res.delta_z))
    np.testing.assert_allclose(axes[2].lines[0].get_ydata(), res.Pi_v * 1e3)
    pyplot().close("all")


def test_plot_drive_forces_and_feasible_region():
    d = sw.scheme_4a(0.1, 0.2, math.radians(15))
    f = sw.drive_forces(d, 1000.0, u=4, n=73)
    ax = plot_drive_forces(f)
    np.testing.assert_allclose(ax[1].lines[1].get_ydata(), f.M_total)
    req = syn.Request(scheme="4a", R=0.1, H=float(d.stroke()), H_tol=1e-3,
                      delta_f=math.radians(2), delta_r=math.radians(2))
    reg = syn.feasible_region(req, d, "alpha", "l", n=12)
    ax2 = plot_feasible_region(reg, best=d)
    assert ax2.get_xlabel() == "α [deg]" and ax2.get_ylabel() == "l / R"
    star = next(ln for ln in ax2.lines if ln.get_marker() == "*")
    assert abs(star.get_xdata()[0] - 15.0) < 1e-12 and abs(star.get_ydata()[0] - 2.0) < 1e-12
    pyplot().close("all")


DEG = math.pi / 180


def test_feasible_region_plot_names_each_limit_and_says_when_empty():
    from linkwork.plot import pyplot
    from linkwork.plot.swashplate import plot_feasible_region

    req = syn.Request(scheme="4b", R=0.1, H=0.06, H_tol=3e-4, delta_f=8 * DEG,
                      delta_r=8 * DEG, point=(math.pi / 2, 0.03), point_tol=1e-3)
    base = sw.scheme_4b(0.1, 0.105, 0.25, 16 * DEG, 0.01)
    reg = syn.feasible_region(req, base, "r", "l", n=12)
    ax = plot_feasible_region(reg, best=base)
    labels = [h.get_label() for h in ax.get_legend().legend_handles]
    assert "limit: δz on the forward stroke" in labels and "best design" in labels
    empty = syn.FeasibleRegion(**{**reg.__dict__, "feasible": np.zeros_like(reg.feasible)})
    ax2 = plot_feasible_region(empty)
    assert "no feasible grid point" in ax2.get_title()
    pyplot().close("all")
