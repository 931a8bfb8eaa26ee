"""Unit conversion at the edges."""

import math

import pytest

from linkwork.errors import ParameterError
from linkwork.units import deg, expressed_like, rpm, to_deg, to_si


@pytest.mark.parametrize(
    ("value", "kind", "expected"),
    [
        ("100 mm", "length", 0.1),
        ("30 deg", "angle", math.pi / 6),
        ("120 rpm", "angular_velocity", 4 * math.pi),
        ("2 kg", "mass", 2.0),
        ("1.5 kN", "force", 1500.0),
        ("3 N*m", "torque", 3.0),
        (0.25, "length", 0.25),
        (1, "angle", 1.0),
        ("0.5", "dimensionless", 0.5),
        ("50 %", "dimensionless", 0.5),
        ("3 mm/m", "dimensionless", 0.003),
    ],
)
def test_to_si(value, kind, expected):
    assert to_si(value, kind) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("value", "kind", "match"),
    [
        ("100 kg", "length", "dimension of length"),
        ("ten mm", "length", "cannot be read"),
        (True, "length", "must be a number"),
        ([1, 2], "length", "must be a number"),
        # pint takes the radian for the number 1: "60 deg" would be the ratio 1.047
        ("60 deg", "dimensionless", r"must be a plain number \(a ratio\): it carries an angle"),
        ("1 rad", "dimensionless", "a ratio"),
        ("2 turn", "dimensionless", "a ratio"),
    ],
)
def test_to_si_rejects(value, kind, match):
    with pytest.raises(ParameterError, match=match):
        to_si(value, kind, name="L1")


def test_helpers():
    assert deg(180) == pytest.approx(math.pi)
    assert to_deg(math.pi / 2) == pytest.approx(90)
    assert rpm(60) == pytest.approx(2 * math.pi)


def test_unit_conversions_keep_their_angle():
    from linkwork.units import to_si
    # independent values: 1 rev = 2 pi rad
    assert to_si("120 rpm", "angular_velocity") == pytest.approx(120 * 2 * math.pi / 60)
    assert to_si("2 rps", "angular_velocity") == pytest.approx(4 * math.pi)
    assert to_si("720 deg/s", "angular_velocity") == pytest.approx(4 * math.pi)
    assert to_si("2 1/s", "angular_velocity") == 2.0  # SI: omega in 1/s is rad/s
    assert to_si("600 1/min", "frequency") == pytest.approx(10.0)
    assert to_si("10 Hz", "frequency") == 10.0
    assert to_si("0.5", "angle") == 0.5
    with pytest.raises(ParameterError, match="ambiguous"):
        to_si("2 Hz", "angular_velocity", "speed")
    with pytest.raises(ParameterError, match="angle unit"):
        to_si("600 rpm", "frequency", "productivity")


@pytest.mark.parametrize(("si", "written", "shown"), [
    (157.07963267948966, "1500 rpm", "1500 rpm"),
    (-0.1, "5 mm", "-100 mm"),
    (1e8, "100 N/um", "100 N/um"),
    (math.pi / 2, "30 deg", "90 deg"),
    (0.002, "2 g*m^2", "2 g*m^2"),
    (1500.0, "1.5 kW", "1.5 kW"),
    (9.81, "1 m/s^2", "9.81 m/s^2"),
])
def test_expressed_like_writes_si_in_the_unit_written(si, written, shown):
    """SI values back in the unit a file wrote (the limits of its error messages): each pair
    converted by hand (1500 rpm = 1500 * 2 pi / 60 rad/s, 1 N/um = 1e6 N/m, ...)."""
    assert expressed_like(si, written) == shown


@pytest.mark.parametrize("written", [3.0, "3", "kg", "3 parsecs of nothing", None])
def test_expressed_like_without_a_unit_is_none(written):
    assert expressed_like(1.0, written) is None
