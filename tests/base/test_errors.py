"""The exception hierarchy and the driver-range messages (argument checks: test_checks.py)."""

import numpy as np
import pytest

from linkwork.checks import require_positive
from linkwork.errors import (
    AssemblyError,
    FileFormatError,
    InfeasibleError,
    LinkworkError,
    ParameterError,
    angle_ranges,
)


@pytest.mark.parametrize("cls", [ParameterError, AssemblyError, FileFormatError, InfeasibleError])
def test_errors_are_linkwork_and_value_errors(cls):
    assert issubclass(cls, LinkworkError)
    assert issubclass(cls, ValueError)


def test_parameter_error_names_parameter_value_and_limit():
    with pytest.raises(ParameterError, match=r"L1 = -0\.1 is invalid: must be > 0") as info:
        require_positive("L1", [0.2, -0.1])
    assert info.value.parameter == "L1"
    assert info.value.value == pytest.approx(-0.1)


def test_angle_ranges_finds_contiguous_runs():
    a = np.radians(np.arange(0, 360, 10.0))
    mask = (np.degrees(a) >= 50) & (np.degrees(a) <= 80) | (np.degrees(a) >= 340)
    r = angle_ranges(a, mask)
    assert np.degrees(r).round(6).tolist() == [[50, 80], [340, 350]]
    # designs on leading axes: a position is bad if bad for any design
    m2 = np.zeros((3, a.size), bool)
    m2[1, 3] = True
    assert angle_ranges(a, m2) == [(a[3], a[3])]


def test_assembly_error_lists_ranges_in_degrees():
    err = AssemblyError("rod too short", [(np.radians(10), np.radians(20))])
    assert "phi1 in [10, 20 deg]" in str(err)
    assert err.ranges[0][0] == pytest.approx(np.radians(10))


def test_format_angle_ranges_single_positions_and_the_wrap_at_360():
    from linkwork.errors import format_angle_ranges
    a = np.radians(np.arange(0, 361, 10.0))        # a full turn, 0 and 360 both present
    assert format_angle_ranges(angle_ranges(a, np.isclose(a, np.pi))) == "180 deg"
    wrap = (np.degrees(a) <= 30) | (np.degrees(a) >= 330)
    assert format_angle_ranges(angle_ranges(a, wrap)) == "[-30, 30 deg]"
    ends = np.isclose(a, 0) | np.isclose(a, 2 * np.pi)   # one locked angle seen twice
    assert format_angle_ranges(angle_ranges(a, ends)) == "0 deg"
    two = (np.degrees(a) >= 50) & (np.degrees(a) <= 80) | np.isclose(a, 2 * np.pi)
    assert format_angle_ranges(angle_ranges(a, two)) == "[50, 80 deg], 360 deg"
    assert format_angle_ranges([(0.1, 0.1)], unit="m") == "0.1 m"
