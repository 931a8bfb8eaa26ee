"""Plots of spatial reactions and tolerance studies draw the data they are given."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from _fourbar_reference import geometry, spatial_model, wrenches
from _spatial_cases import TOLS as LOOM_TOLS
from _spatial_cases import _problem

from linkwork import redundancy as rd
from linkwork.cli import main
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


ROOT = Path(__file__).resolve().parents[2]


EXAMPLE = ROOT / "examples" / "loom_fourbar_spatial.toml"


def test_tolerance_histogram_and_table_tell_the_lines_apart(tmp_path, capsys):
    """p50/p95/p99 were three lines of one colour; the samples are drawn around the file's
    systematic deviations but only the 'no deviation' peak was shown, so the whole histogram
    looked shifted by the tolerances alone."""
    from linkwork.plot import pyplot
    from linkwork.plot.redundancy import plot_peak_histogram

    model, geom, w = _problem(24)
    st = rd.tolerance_study(model, geom, w, LOOM_TOLS, 40, seed=1)
    out = plot_peak_histogram(st, "B", reference={"file's deviations": 1.0})
    styles = {(out[k].get_color(), out[k].get_linestyle()) for k in ("p50", "p95", "p99")}
    assert len(styles) == 3
    assert out["file's deviations"].get_xdata()[0] == 1.0
    pyplot().close("all")
    rc = main(["reactions", str(EXAMPLE), "--out", str(tmp_path / "o"), "--no-plots",
               "--tolerance-study", "20"])
    text = capsys.readouterr().out
    assert rc == 0 and "file's deviations" in text
