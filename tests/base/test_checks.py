"""The argument checks of linkwork.checks: names, values and limits in the messages."""

import numpy as np
import pytest

import linkwork.errors
from linkwork.checks import (
    finite_value,
    per_position,
    positive_value,
    require_branch,
    require_finite,
    require_in_range,
    require_pair,
    require_point,
    require_positive,
)
from linkwork.errors import ParameterError


def test_require_in_range_reports_scaled_value_and_interval():
    with pytest.raises(ParameterError, match=r"alpha = 200 deg.*\(0, 180\) deg"):
        require_in_range("alpha", np.radians(200.0), 0.0, np.pi, lo_open=True, hi_open=True,
                         unit="deg", scale=180 / np.pi)
    ok = require_in_range("alpha", np.radians(60.0), 0.0, np.pi)
    assert ok == pytest.approx(np.radians(60.0))


def test_require_finite_rejects_nan():
    with pytest.raises(ParameterError, match="must be finite"):
        require_positive("L1", float("nan"))


@pytest.mark.parametrize("value", ["abc", "1.5 m", [1.0, "x"], {"a": 1}, None])
def test_require_finite_names_non_numeric_input(value):
    with pytest.raises(ParameterError, match=r"^L1 = .*must be a number or an array of numbers"):
        require_finite("L1", value)
    with pytest.raises(ParameterError, match="L1"):
        require_positive("L1", value)


def test_require_finite_python_ints_in_and_beyond_the_float_range():
    assert require_finite("n", 3) == 3.0 and require_positive("n", 2**60) == float(2**60)
    for big in (10**400, -10**400):
        with pytest.raises(ParameterError, match=r"n = .*beyond the float range"):
            require_finite("n", big)
    with pytest.raises(ParameterError, match="must be > 0"):
        require_positive("n", 0)


@pytest.mark.parametrize("bad", [0, 2, -2, 1.5, True, "1", np.array([1, -1]), None])
def test_require_branch_names_anything_but_one_sign(bad):
    with pytest.raises(ParameterError, match=r"branch = .* must be \+1 or -1"):
        require_branch(bad)
    assert require_branch(1) == 1 and require_branch(-1.0) == -1


def test_scalar_keeping_checks_give_python_floats_for_python_numbers():
    """The fast kernels of closed forms take Python floats: finite_value / positive_value keep
    them, and give float arrays otherwise, with the same messages as require_*."""
    assert type(finite_value("x", 2)) is float and type(positive_value("a", 0.3)) is float
    assert isinstance(positive_value("a", [0.1, 0.2]), np.ndarray)
    for check, bad, limit in ((positive_value, -1.0, "must be > 0"),
                              (positive_value, np.inf, "must be finite"),
                              (finite_value, np.nan, "must be finite"),
                              (positive_value, [0.1, 0.0], "must be > 0")):
        with pytest.raises(ParameterError, match=limit):
            check("a", bad)


def test_points_pairs_and_per_position_values():
    assert require_point("P", [1, 2.5]) == (1.0, 2.5)
    for bad, limit in (((1.0,), "pair of numbers"), ((1.0, np.nan), "must be finite")):
        with pytest.raises(ParameterError, match=limit):
            require_point("P", bad)
    with pytest.raises(ParameterError, match=r"force\[1\] = nan .*finite"):
        require_pair("force", (1.0, np.nan))
    np.testing.assert_array_equal(per_position("omega1", 3.0, 4), [3.0] * 4)
    with pytest.raises(ParameterError, match=r"omega1 = \(3,\) .*shape \(4,\)"):
        per_position("omega1", [1.0, 2.0, 3.0], 4)


def test_checks_at_their_former_place_in_errors_warn_and_work():
    with pytest.warns(DeprecationWarning, match="linkwork.errors.require_finite is deprecated: "
                      "use linkwork.checks.require_finite"):
        fn = linkwork.errors.require_finite
    assert fn is require_finite
    with pytest.raises(AttributeError):
        linkwork.errors.no_such_name  # noqa: B018
