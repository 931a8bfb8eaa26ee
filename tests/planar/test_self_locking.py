"""``planar.working_range``: the values of a design parameter for which a mechanism runs over
its cycle without self-locking, against paper 000's closed-form jamming range of the inclined
slot (``linkwork.models.sine.working_range``: rho1 + rho2 < alpha < 180 deg - (rho1 + rho2),
derived independently of the engine in ``docs/sine_press.md``)."""

import numpy as np
import pytest
from _mechanisms import sine_mechanism

from linkwork.errors import ParameterError
from linkwork.models import sine
from linkwork.planar import PointForce, working_range

PHI = np.linspace(0.0, 2 * np.pi, 73)[:-1] + 0.01


def _against_ram(kin):
    """A 1 kN technological load against the ram's motion."""
    v = kin.point("slider", "G").vx
    return [PointForce("slider", "G", fx=-1000.0 * np.sign(v))]


@pytest.mark.parametrize(("f1", "f2"), [(0.12, 0.10), (0.2, 0.05)])
def test_slot_angle_working_range_is_paper_000s(f1, f2):
    """Scanning alpha over (1, 179) deg finds one working interval whose limits equal the
    closed form's to 1e-9 rad (the bisection tolerance; the engine's own limit is exact to
    its residual 1e-12)."""
    lo, hi = (float(v) for v in sine.working_range(f1, f2))
    wr = working_range(lambda a: sine_mechanism(a, f1, f2), (np.radians(1), np.radians(179)),
                       PHI, loads=_against_ram, scan=24, tol=1e-10)
    assert len(wr.intervals) == 1
    a, b = wr.intervals[0]
    assert abs(a - lo) < 1e-9 and abs(b - hi) < 1e-9
    assert wr.runs(np.radians(90)) and not wr.runs(lo - 1e-3) and not wr.runs(hi + 1e-3)
    # outside the interval the scan counts locked positions; inside kappa stays positive
    inside = (wr.values > a) & (wr.values < b)
    assert np.all(wr.locked[~inside] > 0) and np.all(wr.locked[inside] == 0)
    assert np.all(wr.kappa_min[inside] > 0) and np.all(np.isnan(wr.kappa_min[~inside]))
    assert wr.evaluations == 24 + 2 * int(np.ceil(np.log2((wr.values[1] - wr.values[0])
                                                          / 1e-10)))


def test_friction_coefficient_working_range():
    """At a fixed slot angle alpha = 30 deg the press runs while rho1 + rho2 < alpha: with
    f_guide = 0.10 the slot's coefficient may rise to tan(30 deg - atan 0.10) (closed form)."""
    alpha, f2 = np.radians(30.0), 0.10
    limit = np.tan(alpha - np.arctan(f2))
    wr = working_range(lambda f: sine_mechanism(alpha, f, f2), (0.0, 0.9), PHI,
                       loads=_against_ram, scan=10, tol=1e-10)
    assert len(wr.intervals) == 1
    a, b = wr.intervals[0]
    assert a == 0.0 and abs(b - limit) < 1e-8


def test_values_that_build_no_mechanism_do_not_run():
    """A parameter value for which ``make`` raises a linkwork error (here: f >= 1) counts as
    not running, with -1 in ``locked``."""
    wr = working_range(lambda f: sine_mechanism(np.radians(60), f, 0.1), (0.5, 1.5), PHI,
                       loads=_against_ram, scan=5, tol=1e-6)
    assert wr.locked[-1] == -1 and wr.locked[0] == 0
    assert len(wr.intervals) == 1 and abs(wr.intervals[0][1] - 1.0) < 1e-6


@pytest.mark.parametrize(("kw", "match"), [
    ({"bounds": (1.0, 1.0)}, "bounds"),
    ({"bounds": (0.0, np.inf)}, "bounds"),
    ({"scan": 1}, "scan"),
    ({"scan": 2.5}, "scan"),
    ({"tol": 0.0}, "tol"),
    ({"phi1": []}, "phi1"),
])
def test_bad_arguments(kw, match):
    args = {"bounds": (0.1, 1.0), "phi1": PHI, "scan": 4}
    args.update(kw)
    with pytest.raises(ParameterError, match=match):
        working_range(lambda a: sine_mechanism(a, 0.1, 0.1), args.pop("bounds"),
                      args.pop("phi1"), **args)


def test_a_tolerance_below_the_float_spacing_ends_at_adjacent_floats():
    """tol = 1e-300 (below the spacing of doubles near the limit, ~3e-17 rad) bisects until the
    two values are adjacent floats, then stops: about 55 steps per limit (it looped for ever:
    the midpoint of adjacent floats is one of them). The limits are paper 000's to 1e-9 rad
    (the engine's own limit is exact to its residual)."""
    calls = [0]

    def make(a):
        calls[0] += 1
        assert calls[0] < 400, "the bisection does not end"
        return sine_mechanism(a, 0.12, 0.10)

    wr = working_range(make, (np.radians(1), np.radians(179)), PHI, loads=_against_ram,
                       scan=4, tol=1e-300)
    (a, b), = wr.intervals
    lo, hi = (float(v) for v in sine.working_range(0.12, 0.10))
    assert abs(a - lo) < 1e-9 and abs(b - hi) < 1e-9
    assert wr.evaluations == calls[0] < 4 + 2 * 60
