"""Renamed public names keep working, with a DeprecationWarning that names the new one."""

import numpy as np
import pytest

from linkwork.models import swashplate as sw


def test_swashplate_invalid_keyword_is_the_former_name_of_on_failure() -> None:
    """``invalid=`` (before the one-nomenclature change) gives the same NaN-marked values as
    ``on_failure=``: NaN where the rod of a design cannot reach its disk, the exact position
    (the same numbers) where it can."""
    phi = np.linspace(0.0, 2.0 * np.pi, 73)
    for args in ((phi, 0.1, 0.05, 0.06, np.radians(20.0), 0.0, 0.06),   # never reaches
                 (phi, 0.1, 0.08, 0.10, np.radians(20.0))):             # reaches everywhere
        new = sw.position(*args, on_failure="nan")
        with pytest.warns(DeprecationWarning, match=r"position\(invalid=...\) is deprecated: "
                          r"use on_failure="):
            old = sw.position(*args, invalid="nan")
        np.testing.assert_array_equal(old, new)
    assert np.isfinite(new).all() and np.ptp(new) > 0.01   # the reachable design moves
    with pytest.raises(TypeError, match="both invalid="):
        sw.position(*args, invalid="nan", on_failure="nan")


def test_fourbar_on_fail_and_assembled_are_the_former_names_of_on_failure_and_valid() -> None:
    """A double-rocker over a turn: the former keyword ``on_fail=`` and field ``assembled``
    give the same mask and the same angles as ``on_failure=`` / ``valid``."""
    from linkwork.models.fourbar import fourbar, fourbar_kinetostatics

    t2 = np.linspace(0.0, 2.0 * np.pi, 73)
    new = fourbar(t2, 0.3, 0.1, 0.25, 0.3, on_failure="nan")
    assert 0 < new.valid.sum() < new.valid.size
    with pytest.warns(DeprecationWarning, match=r"fourbar\(on_fail=...\) is deprecated"):
        old = fourbar(t2, 0.3, 0.1, 0.25, 0.3, on_fail="nan")
    with pytest.warns(DeprecationWarning, match=r"FourbarResult.assembled is deprecated: use "
                      r"\.valid"):
        np.testing.assert_array_equal(old.assembled, new.valid)
    np.testing.assert_array_equal(old.theta4, new.theta4)
    with pytest.warns(DeprecationWarning, match=r"fourbar_kinetostatics\(on_fail=...\)"):
        f_old = fourbar_kinetostatics(t2, 0.3, 0.1, 0.25, 0.3, mass=(1.0, 2.0, 3.0),
                                      on_fail="nan")
    f_new = fourbar_kinetostatics(t2, 0.3, 0.1, 0.25, 0.3, mass=(1.0, 2.0, 3.0),
                                  on_failure="nan")
    np.testing.assert_array_equal(f_old.Q, f_new.Q)


def test_plot_force_ratio_is_the_former_name_of_the_force_ratio_curve_figure() -> None:
    """The deprecated plotting function draws the same curve as the model's figure."""
    import matplotlib.pyplot as plt

    from linkwork.models.sine import force_ratio_curve
    from linkwork.plot.sine import plot_force_ratio

    with pytest.warns(DeprecationWarning, match=r"plot_force_ratio\(\) is deprecated"):
        ax = plot_force_ratio(0.1, 0.12, np.radians(60.0))
    fig = force_ratio_curve(0.1, 0.12).plot(np.radians(60.0))
    np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(),
                                  fig.axes[0].get_lines()[0].get_ydata())
    plt.close("all")


def test_fourbar_norton_driver_names_are_the_former_names_of_phi1_omega1_eps1() -> None:
    """The crank's Norton names (theta2, omega2, alpha2) and the alpha3/alpha4 fields give the
    same numbers as the driver names phi1, omega1, eps1 and eps3/eps4."""
    from linkwork.models.fourbar import (
        fourbar,
        limit_positions,
        transmission_angle,
        transmission_angle_extremes,
    )

    t = np.linspace(0.0, 2.0 * np.pi, 37)
    new = fourbar(t, 0.1, 0.3, 0.2, 0.3, omega1=10.0, eps1=-4.0)
    with pytest.warns(DeprecationWarning) as record:
        old = fourbar(theta2=t, a=0.1, b=0.3, c=0.2, d=0.3, omega2=10.0, alpha2=-4.0)
        pairs = [(old.theta2, new.phi1), (old.omega2, new.omega1), (old.alpha2, new.eps1),
                 (old.alpha3, new.eps3), (old.alpha4, new.eps4),
                 (transmission_angle(theta2=t, a=0.1, b=0.3, c=0.2, d=0.3),
                  transmission_angle(t, 0.1, 0.3, 0.2, 0.3))]
    assert len(record) == 3 + 5 + 1 and all("is deprecated: use" in str(w.message)
                                            for w in record)
    for a, b in pairs:
        np.testing.assert_array_equal(a, b)
    lim = limit_positions(0.3, 0.1, 0.25, 0.3)   # a double-rocker: toggles exist
    ext = transmission_angle_extremes(0.1, 0.3, 0.2, 0.3)
    with pytest.warns(DeprecationWarning):
        assert lim.theta2_toggle_extended == lim.phi1_toggle_extended
        assert ext.theta2_at_min == ext.phi1_at_min


def test_engine_on_fail_and_assembled_are_the_former_names_of_on_failure_and_valid() -> None:
    """The planar engine's kinematics(on_fail=) and Kinematics.assembled: same mask, same
    positions as on_failure= and .valid (a double-rocker over a turn)."""
    from linkwork.planar import fourbar_mechanism, kinematics

    mech = fourbar_mechanism(0.3, 0.1, 0.25, 0.3)
    phi = np.linspace(0.0, 2.0 * np.pi, 73)
    new = kinematics(mech, phi, on_failure="nan")
    assert 0 < new.valid.sum() < new.valid.size
    with pytest.warns(DeprecationWarning, match=r"kinematics\(on_fail=...\) is deprecated"):
        old = kinematics(mech, phi, on_fail="nan")
    with pytest.warns(DeprecationWarning, match=r"Kinematics.assembled is deprecated"):
        np.testing.assert_array_equal(old.assembled, new.valid)
    np.testing.assert_array_equal(old.theta, new.theta)


def test_engine_builders_fourbar_and_crank_slider_are_former_names() -> None:
    """planar.fourbar / planar.crank_slider (names shared with the closed forms) build the same
    mechanisms as fourbar_mechanism / crank_slider_mechanism."""
    from linkwork import planar

    with pytest.warns(DeprecationWarning, match=r"linkwork.planar.fourbar\(\) is deprecated"):
        old = planar.fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0))
    assert old == planar.fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0))
    with pytest.warns(DeprecationWarning, match=r"linkwork.planar.crank_slider\(\)"):
        old_cs = planar.crank_slider(0.05, 0.2, 0.025)
    assert old_cs == planar.crank_slider_mechanism(0.05, 0.2, 0.025)
