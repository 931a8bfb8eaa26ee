"""The closed-form four-bar (linkwork.models.fourbar) against independent constructions.

References used here: Norton's Freudenstein-type closed form (written out below, independently of
the vector form in the module), scipy root finding, finite differences over time, a full linear
equilibrium system assembled link by link, the power balance, and Norton's Example 4-1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _fourbar_newton_euler import (
    DESIGNS,
    _assembled,
    _fourbar_closed,
    _shaking_ref,
    _speeds,
    body_point,
    check_reactions,
    close,
    e,
    ep,
    fourbar_positions,
    fourbar_rates,
    fourbar_reference,
)
from _planar_newton_euler import PHI7, _angle_close, _close, _fb_full, _motion, _newton, _rot
from _strategies import reals
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, fsolve, minimize_scalar

from linkwork.errors import AssemblyError, LinkworkError, ParameterError
from linkwork.models import fourbar as fb
from linkwork.models import fourbar as fourbar_cf
from linkwork.models.fourbar import (
    FourbarResult,
    fourbar,
    fourbar_kinetostatics,
    grashof,
    limit_positions,
    transmission_angle,
    transmission_angle_extremes,
)
from linkwork.planar import dead_centres, kinematics
from linkwork.planar import fourbar_mechanism as engine_fourbar

# paper 001's example four-bar: l_OA = 0.1, l_AB = 0.3, l_BC = 0.2, l_OC = 0.3 m
A1, B1, C1, D1 = 0.1, 0.3, 0.2, 0.3
CYCLE = np.linspace(0.0, 2 * np.pi, 361)


# --- independent references --------------------------------------------------------------------


def norton_angles(t2, a, b, c, d):
    """Both solutions (theta3, theta4) of Norton's Eqs. (4.10)-(4.13), with B left of A->O4 first.

    Freudenstein: K1 = d/a, K2 = d/c, K3 = (a^2 - b^2 + c^2 + d^2)/(2ac); theta4 from a quadratic
    in tan(theta4/2); theta3 likewise with K4 = d/b, K5 = (c^2 - d^2 - a^2 - b^2)/(2ab).  The two
    roots are then sorted by the side of A->O4 on which B lies (this is the test's own decision,
    made from the points, not from the module's formulas).
    """
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    k4, k5 = d / b, (c * c - d * d - a * a - b * b) / (2 * a * b)
    ca = np.cos(t2) - k1 - k2 * np.cos(t2) + k3
    cb = -2 * np.sin(t2)
    cc = k1 - (k2 + 1) * np.cos(t2) + k3
    cd = np.cos(t2) - k1 + k4 * np.cos(t2) + k5
    ce = -2 * np.sin(t2)
    cf = k1 + (k4 - 1) * np.cos(t2) + k5
    sols = []
    for sgn in (-1.0, 1.0):
        t4 = 2 * np.arctan2(-cb + sgn * np.sqrt(cb * cb - 4 * ca * cc), 2 * ca)
        t3 = 2 * np.arctan2(-ce + sgn * np.sqrt(ce * ce - 4 * cd * cf), 2 * cd)
        sols.append((t3, t4))
    # pair them: for each theta4 root, the coupler angle follows from B - A
    ax, ay = a * np.cos(t2), a * np.sin(t2)
    cand = []
    for _, t4 in sols:
        bx, by = d + c * np.cos(t4), c * np.sin(t4)
        t3 = np.arctan2(by - ay, bx - ax)
        side = (d - ax) * (by - ay) + ay * (bx - ax)
        cand.append((t3, t4, side))
    (t3a, t4a, sa), (t3b, t4b, _) = cand
    left = (np.where(sa > 0, t3a, t3b), np.where(sa > 0, t4a, t4b))
    right = (np.where(sa > 0, t3b, t3a), np.where(sa > 0, t4b, t4a))
    return left, right


def wrap(x):
    return np.angle(np.exp(1j * np.asarray(x)))


def B_by_fsolve(t2, a, b, c, d, guess):
    """B as a root of |B - A| = b, |B - O4| = c (scipy)."""
    ax, ay = a * math.cos(t2), a * math.sin(t2)

    def eqs(p):
        return [(p[0] - ax) ** 2 + (p[1] - ay) ** 2 - b * b, (p[0] - d) ** 2 + p[1] ** 2 - c * c]

    return fsolve(eqs, guess, xtol=1e-13)


# --- positions -----------------------------------------------------------------------------------


def test_norton_example_4_1_open():
    # Norton, Design of Machinery, Example 4-1: a=40, b=120, c=80, d=100, phi1=40 deg:
    """Reference: Norton's example (module docstring). Tolerance: abs=5e-4."""
    # open circuit theta3 = 20.298 deg, theta4 = 57.325 deg.
    r = fourbar(np.radians(40.0), 40.0, 120.0, 80.0, 100.0, branch=+1)
    assert np.degrees(r.theta3) == pytest.approx(20.298, abs=5e-4)
    assert np.degrees(r.theta4) == pytest.approx(57.325, abs=5e-4)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("design", [(A1, B1, C1, D1), (0.05, 0.12, 0.09, 0.1),
                                    (0.2, 0.15, 0.2, 0.1)])
def test_positions_match_freudenstein_closed_form(design, branch):
    a, b, c, d = design
    t2 = np.linspace(0, 2 * np.pi, 721)
    r = fourbar(t2, a, b, c, d, branch=branch)
    left, right = norton_angles(t2, a, b, c, d)
    t3, t4 = left if branch == 1 else right
    np.testing.assert_allclose(wrap(r.theta3 - t3), 0, atol=1e-11)
    np.testing.assert_allclose(wrap(r.theta4 - t4), 0, atol=1e-11)


@pytest.mark.parametrize("branch", [+1, -1])
def test_points_match_scipy_root(branch):
    t2s = np.radians([0, 37, 90, 163, 210, 300])
    r = fourbar(t2s, A1, B1, C1, D1, branch=branch)
    for i, t2 in enumerate(t2s):
        xb, yb = B_by_fsolve(t2, A1, B1, C1, D1, [r.xB[i] + 0.01, r.yB[i] - 0.01])
        assert (xb, yb) == pytest.approx((r.xB[i], r.yB[i]), abs=1e-11)
        assert (r.xA[i], r.yA[i]) == pytest.approx((A1 * math.cos(t2), A1 * math.sin(t2)),
                                                   abs=1e-15)


def test_branch_plus_one_is_left_of_A_to_O4():
    r_p = fourbar(CYCLE, A1, B1, C1, D1, branch=+1)
    r_m = fourbar(CYCLE, A1, B1, C1, D1, branch=-1)
    side = lambda r: (D1 - r.xA) * (r.yB - r.yA) - (0 - r.yA) * (r.xB - r.xA)  # noqa: E731
    assert (side(r_p) > 0).all() and (side(r_m) < 0).all()
    # the two branches are mirror images about the line A O4: the same transmission angle
    np.testing.assert_allclose(r_p.transmission_angle, r_m.transmission_angle, atol=1e-12)


def test_coupler_point():
    p, q = 0.12, -0.07
    r = fourbar(CYCLE, A1, B1, C1, D1, coupler_point=(p, q))
    # P from the two distances |AP| and |BP| and the side of AB it is on
    ap, bp = math.hypot(p, q), math.hypot(B1 - p, q)
    np.testing.assert_allclose(np.hypot(r.xP - r.xA, r.yP - r.yA), ap, atol=1e-14)
    np.testing.assert_allclose(np.hypot(r.xP - r.xB, r.yP - r.yB), bp, atol=1e-14)
    side = (r.xB - r.xA) * (r.yP - r.yA) - (r.yB - r.yA) * (r.xP - r.xA)
    assert (np.sign(side) == np.sign(q)).all()


def test_broadcast_over_designs_equals_separate_calls():
    a = np.array([[0.1], [0.08], [0.12]])
    t2 = np.linspace(0, 2 * np.pi, 50)
    r = fourbar(t2, a, B1, C1, D1, omega1=7.0, eps1=-2.0, branch=-1)
    assert r.theta4.shape == (3, 50)
    for i in range(3):
        ri = fourbar(t2, float(a[i, 0]), B1, C1, D1, omega1=7.0, eps1=-2.0, branch=-1)
        for name in ("theta3", "theta4", "omega3", "omega4", "eps3", "eps4", "xB", "yB"):
            np.testing.assert_allclose(getattr(r, name)[i], getattr(ri, name), rtol=0, atol=0)


def test_scalar_input_gives_scalar_shaped_arrays():
    r = fourbar(0.3, A1, B1, C1, D1)
    assert np.shape(r.theta3) == () and isinstance(r, FourbarResult)


# --- velocities and accelerations -----------------------------------------------------------


def _time_fd(t0, a, b, c, d, w2, e2, branch, dt=1e-5):
    """omega, alpha of coupler and rocker by central differences in time (phi1(t) quadratic)."""
    ts = np.array([-2, -1, 0, 1, 2]) * dt
    th = t0 + w2 * ts + 0.5 * e2 * ts * ts
    out = []
    for name in ("theta3", "theta4"):
        ang = np.unwrap(np.array([getattr(fourbar(x, a, b, c, d, branch=branch), name)
                                  for x in th]))
        w = (ang[0] - 8 * ang[1] + 8 * ang[3] - ang[4]) / (12 * dt)
        al = (-ang[0] + 16 * ang[1] - 30 * ang[2] + 16 * ang[3] - ang[4]) / (12 * dt * dt)
        out += [w, al]
    return out


@pytest.mark.parametrize("branch", [+1, -1])
def test_velocity_acceleration_finite_differences(branch):
    w2, e2 = 10.0, 25.0
    for t0 in np.radians([0, 45, 100, 180, 250, 333]):
        r = fourbar(t0, A1, B1, C1, D1, w2, e2, branch)
        w3, al3, w4, al4 = _time_fd(t0, A1, B1, C1, D1, w2, e2, branch)
        assert float(r.omega3) == pytest.approx(w3, rel=1e-8, abs=1e-8)
        assert float(r.omega4) == pytest.approx(w4, rel=1e-8, abs=1e-8)
        assert float(r.eps3) == pytest.approx(al3, rel=1e-4, abs=2e-3)
        assert float(r.eps4) == pytest.approx(al4, rel=1e-4, abs=2e-3)


def test_point_velocity_acceleration_finite_differences():
    p, q = 0.1, 0.04
    w2, e2, dt = 5.0, -3.0, 1e-5
    t0 = np.radians(np.arange(0, 360, 30.0))
    r = fourbar(t0, A1, B1, C1, D1, w2, e2)
    for link in ("crank", "coupler", "rocker"):
        pos = []
        for k in (-1, 0, 1):
            th = t0 + w2 * k * dt + 0.5 * e2 * (k * dt) ** 2
            x, y, *_ = fourbar(th, A1, B1, C1, D1).point(link, p, q)
            pos.append((x, y))
        x, y, vx, vy, ax, ay = r.point(link, p, q)
        np.testing.assert_allclose(vx, (pos[2][0] - pos[0][0]) / (2 * dt), atol=1e-8)
        np.testing.assert_allclose(vy, (pos[2][1] - pos[0][1]) / (2 * dt), atol=1e-8)
        np.testing.assert_allclose(ax, (pos[2][0] - 2 * pos[1][0] + pos[0][0]) / dt**2,
                                   atol=2e-3)
        np.testing.assert_allclose(ay, (pos[2][1] - 2 * pos[1][1] + pos[0][1]) / dt**2,
                                   atol=2e-3)


lengths = st.floats(0.2, 5.0)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(a=lengths, b=lengths, c=lengths, d=lengths, t2=reals(-np.pi, np.pi),
       branch=st.sampled_from([1, -1]), w2=reals(-20, 20), e2=reals(-50, 50))
def test_property_loop_closure_and_velocity_loop(a, b, c, d, t2, branch, w2, e2):
    r = fourbar(t2, a, b, c, d, w2, e2, branch, on_failure="nan")
    assume(bool(r.valid))
    f = math.hypot(d - a * math.cos(t2), a * math.sin(t2))
    assume(min(b + c - f, f - abs(b - c)) > 1e-3 * (b + c))   # away from toggles
    # loop closure a e2 + b e3 - c e4 - d = 0
    ex = a * math.cos(t2) + b * np.cos(r.theta3) - c * np.cos(r.theta4) - d
    ey = a * math.sin(t2) + b * np.sin(r.theta3) - c * np.sin(r.theta4)
    assert abs(ex) < 1e-12 * (a + b + c + d) and abs(ey) < 1e-12 * (a + b + c + d)
    # the velocity of B computed through the crank/coupler equals that through the rocker
    vbx1 = -a * w2 * math.sin(t2) - b * r.omega3 * np.sin(r.theta3)
    vby1 = a * w2 * math.cos(t2) + b * r.omega3 * np.cos(r.theta3)
    vbx2, vby2 = -c * r.omega4 * np.sin(r.theta4), c * r.omega4 * np.cos(r.theta4)
    scale = abs(w2) * (a + b + c) * (1 + abs(r.omega3) + abs(r.omega4))
    assert abs(vbx1 - vbx2) <= 1e-9 * scale and abs(vby1 - vby2) <= 1e-9 * scale
    # and the acceleration of B likewise
    w3, w4, al3, al4 = r.omega3, r.omega4, r.eps3, r.eps4
    abx1 = (-a * e2 * math.sin(t2) - a * w2 * w2 * math.cos(t2)
            - b * al3 * np.sin(r.theta3) - b * w3 * w3 * np.cos(r.theta3))
    aby1 = (a * e2 * math.cos(t2) - a * w2 * w2 * math.sin(t2)
            + b * al3 * np.cos(r.theta3) - b * w3 * w3 * np.sin(r.theta3))
    abx2 = -c * al4 * np.sin(r.theta4) - c * w4 * w4 * np.cos(r.theta4)
    aby2 = c * al4 * np.cos(r.theta4) - c * w4 * w4 * np.sin(r.theta4)
    ascale = (a + b + c) * (abs(e2) + w2 * w2 + w3 * w3 + w4 * w4 + abs(al3) + abs(al4) + 1)
    assert abs(abx1 - abx2) <= 1e-9 * ascale and abs(aby1 - aby2) <= 1e-9 * ascale


@settings(max_examples=50, deadline=None)
@given(a=lengths, b=lengths, c=lengths, d=lengths, branch=st.sampled_from([1, -1]))
@example(a=4.0, b=0.5, c=0.25, d=4.0, branch=1)
def test_property_omega_is_derivative_of_theta(a, b, c, d, branch):
    # central differences with a small step, evaluated separately at t -/+ h: the truncation
    # error h^2/6 theta''' stays far below the tolerance even where the coupler turns fast
    # near an assembly limit (a grid difference over the cycle did not, with a = d = 4, b = 0.5)
    t2 = np.linspace(-np.pi, np.pi, 2001)
    h = 1e-6
    r = fourbar(t2, a, b, c, d, branch=branch, on_failure="nan")
    rp = fourbar(t2 + h, a, b, c, d, branch=branch, on_failure="nan")
    rm = fourbar(t2 - h, a, b, c, d, branch=branch, on_failure="nan")
    f = np.hypot(d - a * np.cos(t2), a * np.sin(t2))
    good = (r.valid & rp.valid & rm.valid
            & (np.minimum(b + c - f, f - abs(b - c)) > 0.05 * (b + c)))
    assume(good.sum() > 10)
    for th, om, thp, thm in ((r.theta3, r.omega3, rp.theta3, rm.theta3),
                             (r.theta4, r.omega4, rp.theta4, rm.theta4)):
        fd = wrap(thp - thm) / (2 * h)
        np.testing.assert_allclose(om[good], fd[good], rtol=1e-6,
                                   atol=1e-6 * (1 + np.max(np.abs(om[good]))))
        assert np.all(np.isfinite(th[good]))


# --- failure policy -------------------------------------------------------------------------


def test_assembly_error_lists_crank_ranges():
    # non-Grashof: a=0.3, b=0.1, c=0.25, d=0.3 -> |AO4| must stay in [0.15, 0.35]
    t2 = np.radians(np.arange(0.0, 360.0, 1.0))
    with pytest.raises(AssemblyError, match="phi1") as info:
        fourbar(t2, 0.3, 0.1, 0.25, 0.3)
    assert isinstance(info.value, LinkworkError) and isinstance(info.value, ValueError)
    # independent: where |AO4| leaves [|b-c|, b+c]
    f = np.hypot(0.3 - 0.3 * np.cos(t2), 0.3 * np.sin(t2))
    bad = (f > 0.35) | (f < 0.15)
    lo, hi = info.value.ranges[0]
    first = np.flatnonzero(bad)[0]
    assert lo == pytest.approx(t2[first])
    assert all(bad[(t2 >= lo - 1e-12) & (t2 <= hi + 1e-12)])
    r = fourbar(t2, 0.3, 0.1, 0.25, 0.3, on_failure="nan")
    np.testing.assert_array_equal(~r.valid, bad)
    assert np.isnan(r.theta4[bad]).all() and np.isfinite(r.theta4[~bad]).all()


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [({"a": -0.1}, "a"), ({"b": 0.0}, "b"), ({"c": float("nan")}, "c"), ({"d": np.inf}, "d"),
     ({"branch": 0}, "branch"), ({"omega1": np.nan}, "omega1"),
     ({"on_failure": "skip"}, "on_failure"),
     ({"a": np.array([0.1, -0.2])}, "a")],
)
def test_bad_parameters_are_named(kwargs, name):
    args = {"phi1": CYCLE, "a": A1, "b": B1, "c": C1, "d": D1, **kwargs}
    with pytest.raises(ParameterError) as info:
        fourbar(**args)
    assert info.value.parameter == name


def test_nan_theta2_is_a_parameter_error():
    with pytest.raises(ParameterError, match="phi1"):
        fourbar(np.array([0.1, np.nan]), A1, B1, C1, D1)


# --- Grashof, limit positions, transmission angle -------------------------------------------


@pytest.mark.parametrize(
    ("design", "cls", "motion"),
    [((0.1, 0.3, 0.2, 0.3), "I", "crank-rocker"),      # paper 001's example
     ((0.3, 0.2, 0.3, 0.1), "I", "double-crank"),
     ((0.3, 0.1, 0.3, 0.25), "I", "double-rocker"),
     ((0.3, 0.2, 0.1, 0.3), "I", "rocker-crank"),
     ((0.4, 0.2, 0.25, 0.3), "II", "triple-rocker"),
     ((0.2, 0.3, 0.2, 0.3), "III", "change-point")],   # parallelogram
)
def test_grashof_classification(design, cls, motion):
    g = grashof(*design)
    assert (g.grashof_class, g.motion) == (cls, motion)


@settings(max_examples=80, deadline=None)
@given(a=lengths, b=lengths, c=lengths, d=lengths)
def test_property_grashof_crank_rotates_iff_it_assembles_everywhere(a, b, c, d):
    lo = sorted((a, b, c, d))
    assume(abs(lo[0] + lo[3] - lo[1] - lo[2]) > 1e-3)
    g = grashof(a, b, c, d)
    t2 = np.linspace(0, 2 * np.pi, 3601)
    f = np.hypot(d - a * np.cos(t2), a * np.sin(t2))
    margin = np.minimum(b + c - f, f - abs(b - c))
    assume(np.abs(margin).min() > 1e-4 or margin.min() < -1e-3)
    everywhere = bool(fourbar(t2, a, b, c, d, on_failure="nan").valid.all())
    assert g.crank_rotates == everywhere
    # Grashof's theorem: the crank turns fully iff class I and the crank or the frame is shortest
    assert g.crank_rotates == (g.grashof_class == "I" and g.motion in ("crank-rocker",
                                                                          "double-crank"))


def test_grashof_vectorised_over_designs():
    g = grashof(np.array([0.1, 0.4]), np.array([0.3, 0.2]), np.array([0.2, 0.25]), 0.3)
    assert list(g.motion) == ["crank-rocker", "triple-rocker"]


@pytest.mark.parametrize("branch", [+1, -1])
def test_rocker_limit_positions_are_theta4_extremes(branch):
    lim = limit_positions(A1, B1, C1, D1, branch)
    t2 = np.linspace(-np.pi, np.pi, 200001)
    r = fourbar(t2, A1, B1, C1, D1, branch=branch)
    # extremes of theta4 over the cycle (theta4 does not wrap here: B stays on one side)
    t4 = np.unwrap(r.theta4)
    i_max, i_min = np.argmax(t4), np.argmin(t4)
    found = sorted([wrap(t4[i_max]), wrap(t4[i_min])])
    assert sorted([lim.theta4_rocker_extended, lim.theta4_rocker_folded]) == pytest.approx(
        found, abs=1e-8)
    assert lim.rocker_swing == pytest.approx(t4[i_max] - t4[i_min], abs=1e-8)
    # at the limit crank angles, omega4 = 0 and theta4 equals the limit angle
    for t2l, t4l in ((lim.phi1_rocker_extended, lim.theta4_rocker_extended),
                     (lim.phi1_rocker_folded, lim.theta4_rocker_folded)):
        rl = fourbar(t2l, A1, B1, C1, D1, branch=branch)
        assert float(rl.omega4) == pytest.approx(0.0, abs=1e-12)
        assert float(rl.theta4) == pytest.approx(t4l, abs=1e-12)
    # time ratio: crank angle folded -> extended over extended -> folded (omega1 > 0)
    fwd = np.mod(lim.phi1_rocker_extended - lim.phi1_rocker_folded, 2 * np.pi)
    assert lim.time_ratio == pytest.approx(fwd / (2 * np.pi - fwd))
    assert np.isnan(lim.phi1_toggle_extended) and np.isnan(lim.phi1_toggle_folded)


def test_input_toggle_positions_of_a_double_rocker():
    a, b, c, d = 0.3, 0.1, 0.25, 0.3
    lim = limit_positions(a, b, c, d)
    # independent: root of |AO4|(phi1) - (b + c) and - |b - c| with brentq on [0, pi]
    f = lambda t, target: math.hypot(d - a * math.cos(t), a * math.sin(t)) - target  # noqa: E731
    ext = brentq(f, 0.0, np.pi, args=(b + c,), xtol=1e-15)
    fold = brentq(f, 0.0, np.pi, args=(abs(b - c),), xtol=1e-15)
    assert lim.phi1_toggle_extended == pytest.approx(ext, abs=1e-12)
    assert lim.phi1_toggle_folded == pytest.approx(fold, abs=1e-12)
    r = fourbar(np.array([fold + 1e-6, ext - 1e-6, ext + 1e-6]), a, b, c, d, on_failure="nan")
    assert list(r.valid) == [True, True, False]
    mu = transmission_angle(np.array([ext, fold]), a, b, c, d)
    assert mu == pytest.approx([np.pi, 0.0], abs=1e-6)


@pytest.mark.parametrize("design", [(A1, B1, C1, D1), (0.3, 0.1, 0.25, 0.3),
                                    (0.3, 0.2, 0.3, 0.1)])
def test_transmission_angle_extremes_match_a_dense_cycle(design):
    t2 = np.linspace(0, 2 * np.pi, 400001)
    mu = transmission_angle(t2, *design)
    ext = transmission_angle_extremes(*design)
    # the sampled extremes lie inside [mu_min, mu_max] and come close to them (near an input
    # toggle mu changes like sqrt(phi1 - toggle), so the sampled value lags by up to ~1e-2)
    assert ext.mu_min - 1e-12 <= np.nanmin(mu) <= ext.mu_min + 1e-2
    assert ext.mu_max - 1e-2 <= np.nanmax(mu) <= ext.mu_max + 1e-12
    at = transmission_angle(np.array([ext.phi1_at_min, ext.phi1_at_max]), *design)
    assert at == pytest.approx([ext.mu_min, ext.mu_max], abs=1e-7)
    assert ext.max_deviation == pytest.approx(np.nanmax(np.abs(mu - np.pi / 2)), abs=1e-2)
    r = fourbar(t2, *design, on_failure="nan")
    np.testing.assert_allclose(r.transmission_angle[r.valid], mu[r.valid], atol=1e-7)
    # law of cosines on the drawn points (triangle A B O4)
    ab = np.hypot(r.xB - r.xA, r.yB - r.yA)
    bo = np.hypot(r.xB - design[3], r.yB)
    ao = np.hypot(r.xA - design[3], r.yA)
    cos_mu = (ab**2 + bo**2 - ao**2) / (2 * ab * bo)
    ok = r.valid
    np.testing.assert_allclose(np.cos(r.transmission_angle[ok]), cos_mu[ok], atol=1e-9)


def test_transmission_angle_of_paper001_crank_rocker():
    # crank along the frame line: |AO4| = d -+ a = 0.2, 0.4 -> mu = acos((b^2+c^2-f^2)/(2bc))
    ext = transmission_angle_extremes(A1, B1, C1, D1)
    assert ext.mu_min == pytest.approx(math.acos((0.09 + 0.04 - 0.04) / 0.12))
    assert ext.mu_max == pytest.approx(math.acos((0.09 + 0.04 - 0.16) / 0.12))
    assert ext.phi1_at_min == 0.0 and ext.phi1_at_max == pytest.approx(np.pi)


def test_transmission_extremes_raise_when_never_assembled():
    with pytest.raises(AssemblyError):
        transmission_angle_extremes(0.1, 0.1, 0.1, 1.0)


# --- kinetostatics ---------------------------------------------------------------------------

MASS = (1.0, 3.0, 2.0)
INERTIA = (0.004, 0.0225, 0.00567)
COM = ((0.04, 0.01), (0.17, -0.03), (0.08, 0.02))
FORCE = ((2.0, -1.0), (-15.0, 8.0), (5.0, 12.0))
FPOINT = ((0.1, 0.0), (0.25, 0.05), (0.2, -0.02))
MOMENT = (0.4, -1.5, 2.5)
GRAV = (0.0, -9.81)


def _loaded(t2, branch, w2=10.0, e2=-30.0):
    return fourbar_kinetostatics(t2, A1, B1, C1, D1, w2, e2, branch, mass=MASS, inertia=INERTIA,
                                 com=COM, gravity=GRAV, force=FORCE, force_point=FPOINT,
                                 moment=MOMENT)


def _local(ex, ey, p, q):
    return p * ex - q * ey, p * ey + q * ex


@pytest.mark.parametrize("branch", [+1, -1])
def test_kinetostatics_solves_the_full_equilibrium_system(branch):
    """Assemble the 9x9 system (3 equations per link) per position and solve it with numpy."""
    w2, e2 = 10.0, -30.0
    t2 = np.radians(np.arange(0, 360, 15.0))
    res = _loaded(t2, branch, w2, e2)
    k = res.kinematics
    for i in range(t2.size):
        th = (t2[i], k.theta3[i], k.theta4[i])
        om = (w2, k.omega3[i], k.omega4[i])
        al = (e2, k.eps3[i], k.eps4[i])
        origin = ((0.0, 0.0), (k.xA[i], k.yA[i]), (D1, 0.0))
        # accelerations of the link origins (O2, A, O4) from the angles, independently
        acc0 = ((0.0, 0.0),
                (-A1 * (e2 * math.sin(th[0]) + w2**2 * math.cos(th[0])),
                 A1 * (e2 * math.cos(th[0]) - w2**2 * math.sin(th[0]))), (0.0, 0.0))
        # unknowns x = [ROx, ROy, RAx, RAy, RBx, RBy, RCx, RCy, Q]
        M = np.zeros((9, 9))
        rhs = np.zeros(9)
        A = np.array([k.xA[i], k.yA[i]])
        Bp = np.array([k.xB[i], k.yB[i]])
        O4 = np.array([D1, 0.0])
        # joint forces acting on each link: (unknown index, sign, point)
        joints = {0: [(0, +1, np.zeros(2)), (2, -1, A)],
                  1: [(2, +1, A), (4, -1, Bp)],
                  2: [(4, +1, Bp), (6, +1, O4)]}
        for li in range(3):
            ex, ey = math.cos(th[li]), math.sin(th[li])
            sx, sy = _local(ex, ey, *COM[li])
            S = np.array(origin[li]) + np.array([sx, sy])
            aS = np.array(acc0[li]) + np.array([-al[li] * sy - om[li] ** 2 * sx,
                                                al[li] * sx - om[li] ** 2 * sy])
            fx, fy = _local(ex, ey, *FPOINT[li])
            P = np.array(origin[li]) + np.array([fx, fy])
            row = 3 * li
            for idx, sgn, pt in joints[li]:
                M[row, idx] += sgn
                M[row + 1, idx + 1] += sgn
                M[row + 2, idx] += -sgn * pt[1]       # moment about the global origin
                M[row + 2, idx + 1] += sgn * pt[0]
            if li == 0:
                M[2, 8] = 1.0
            inertia_f = -MASS[li] * aS
            rhs[row:row + 2] = -(np.array(FORCE[li]) + MASS[li] * np.array(GRAV) + inertia_f)
            mom = (P[0] * FORCE[li][1] - P[1] * FORCE[li][0]
                   + S[0] * (MASS[li] * GRAV[1] + inertia_f[1])
                   - S[1] * (MASS[li] * GRAV[0] + inertia_f[0])
                   + MOMENT[li] - INERTIA[li] * al[li])
            rhs[row + 2] = -mom
        x = np.linalg.solve(M, rhs)
        got = [res.R_Ox[i], res.R_Oy[i], res.R_Ax[i], res.R_Ay[i], res.R_Bx[i], res.R_By[i],
               res.R_Cx[i], res.R_Cy[i], res.Q[i]]
        np.testing.assert_allclose(got, x, rtol=1e-10, atol=1e-9)


@pytest.mark.parametrize("branch", [+1, -1])
def test_kinetostatics_power_balance(branch):
    """Q omega1 + power of weights, external forces and moments = dT/dt, with eps1 != 0."""
    w2, e2 = 10.0, -30.0
    res = _loaded(CYCLE, branch, w2, e2)
    k = res.kinematics
    omegas = (w2, k.omega3, k.omega4)
    alphas = (e2, k.eps3, k.eps4)
    power = res.Q * w2
    dT = np.zeros_like(power)
    for li, link in enumerate(("crank", "coupler", "rocker")):
        _, _, vx, vy, ax, ay = k.point(link, *COM[li])
        dT += MASS[li] * (vx * ax + vy * ay) + INERTIA[li] * omegas[li] * alphas[li]
        power += MASS[li] * (GRAV[0] * vx + GRAV[1] * vy) + MOMENT[li] * omegas[li]
        _, _, vx, vy, _, _ = k.point(link, *FPOINT[li])
        power += FORCE[li][0] * vx + FORCE[li][1] * vy
    np.testing.assert_allclose(power, dT, rtol=0, atol=1e-9 * np.abs(dT).max())


def test_kinetostatics_momentum_balance():
    """Frame's forces on the links = rate of change of momentum minus weights and loads."""
    res = _loaded(CYCLE, +1)
    k = res.kinematics
    fx = res.R_Ox + res.R_Cx
    fy = res.R_Oy + res.R_Cy
    for li, link in enumerate(("crank", "coupler", "rocker")):
        *_, ax, ay = k.point(link, *COM[li])
        fx = fx - MASS[li] * ax + FORCE[li][0] + MASS[li] * GRAV[0]
        fy = fy - MASS[li] * ay + FORCE[li][1] + MASS[li] * GRAV[1]
    np.testing.assert_allclose(fx, 0, atol=1e-10)
    np.testing.assert_allclose(fy, 0, atol=1e-10)
    np.testing.assert_allclose(res.shaking_force_x, -(res.R_Ox + res.R_Cx))


def test_kinetostatics_statics_of_a_weightless_linkage():
    """Static check by virtual work: Q = -M4 * dtheta4/dtheta2 for a moment M4 on the rocker."""
    t2 = np.radians(np.arange(5, 360, 10.0))
    res = fourbar_kinetostatics(t2, A1, B1, C1, D1, omega1=0.0, moment=(0.0, 0.0, 3.0))
    ratio = fourbar(t2, A1, B1, C1, D1, omega1=1.0).omega4
    np.testing.assert_allclose(res.Q, -3.0 * ratio, rtol=1e-12)


def test_kinetostatics_paper001_example_without_loads_is_inertial_only():
    """Paper 001's linkage (masses 1/3/2 kg at midpoints, omega=10 1/s): Q = dT/dt / omega.

    Inertias default to thin rods, m l^2/12, included in T here.
    """
    m = (1.0, 3.0, 2.0)
    res = fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, 10.0, mass=m)
    k = res.kinematics
    T = np.zeros_like(CYCLE)
    for li, link in enumerate(("crank", "coupler", "rocker")):
        length = (A1, B1, C1)[li]
        _, _, vx, vy, _, _ = k.point(link, length / 2)
        w = (10.0, k.omega3, k.omega4)[li]
        T = T + 0.5 * m[li] * (vx * vx + vy * vy) + 0.5 * m[li] * length**2 / 12 * w * w
    dT = np.gradient(T, CYCLE) * 10.0  # dT/dt = dT/dtheta2 * omega1
    np.testing.assert_allclose(res.Q[1:-1] * 10.0, dT[1:-1], atol=2e-3 * np.abs(dT).max())


def test_kinetostatics_bad_loads_are_named():
    with pytest.raises(ParameterError, match=r"mass\[1\]"):
        fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, mass=(1.0, -3.0, 2.0))
    with pytest.raises(ParameterError, match="force"):
        fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, force=((1.0, 2.0), (1.0,), (0, 0)))
    with pytest.raises(ParameterError, match="moment"):
        fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, moment=(1.0, 2.0))


# --- plots -------------------------------------------------------------------------------------


def test_plots_draw_the_computed_curves():
    from linkwork.plot import pyplot
    from linkwork.plot.fourbar import (
        plot_fourbar_forces,
        plot_fourbar_linkage,
        plot_fourbar_motion,
    )

    r = fourbar(CYCLE, A1, B1, C1, D1, 10.0, coupler_point=(0.15, 0.05))
    ax = plot_fourbar_linkage(r)
    labels = [ln.get_label() for ln in ax.get_lines()]
    assert "path of B" in labels and "coupler curve P" in labels
    path = ax.get_lines()[labels.index("path of B")]
    np.testing.assert_array_equal(path.get_ydata(), r.yB)
    axes = plot_fourbar_motion(r)
    np.testing.assert_array_equal(axes[1].get_lines()[1].get_ydata(), r.omega4)
    f = fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, 10.0, mass=(1.0, 3.0, 2.0))
    axes = plot_fourbar_forces(f)
    np.testing.assert_array_equal(axes[1].get_lines()[0].get_ydata(), f.Q)
    # the result objects delegate to the same functions
    assert r.plot().get_lines()[-1].get_label() == "coupler curve P"
    np.testing.assert_array_equal(f.plot()[1].get_lines()[0].get_ydata(), f.Q)
    pyplot().close("all")


# --- blocked evaluation of long arrays ----------------------------------------------------------


def test_blocked_evaluation_equals_small_calls():
    """n >= 16384 positions are evaluated in blocks; the numbers must not change."""
    n = 20000
    t2 = np.linspace(-np.pi, np.pi, n)
    a = np.array([[0.1], [0.12]])
    w2 = 5.0 + np.linspace(0, 1, n)          # per-position crank speed
    e2 = -3.0
    big = fourbar(t2, a, B1, C1, D1, w2, e2, -1, coupler_point=(0.1, 0.02))
    names = ("theta3", "theta4", "omega3", "omega4", "eps3", "eps4", "xA", "yA", "xB",
             "yB", "xP", "yP", "valid")
    for lo in range(0, n, 7000):
        sl = slice(lo, min(lo + 7000, n))
        small = fourbar(t2[sl], a, B1, C1, D1, w2[sl], e2, -1, coupler_point=(0.1, 0.02))
        for name in names:
            np.testing.assert_array_equal(getattr(big, name)[:, sl], getattr(small, name))


def test_blocked_evaluation_reports_assembly_failure():
    t2 = np.linspace(0, 2 * np.pi, 40000)
    with pytest.raises(AssemblyError, match="phi1"):
        fourbar(t2, 0.3, 0.1, 0.25, 0.3)
    r = fourbar(t2, 0.3, 0.1, 0.25, 0.3, on_failure="nan")
    f = np.hypot(0.3 - 0.3 * np.cos(t2), 0.3 * np.sin(t2))
    np.testing.assert_array_equal(r.valid, (f <= 0.35) & (f >= 0.15))


@settings(max_examples=40, deadline=None)
@given(a=lengths, b=lengths, c=lengths, d=lengths, branch=st.sampled_from([1, -1]),
       w2=reals(-20, 20), e2=reals(-50, 50),
       m=st.tuples(reals(0, 5), reals(0, 5), reals(0, 5)),
       f=st.tuples(reals(-50, 50), reals(-50, 50)),
       mz=reals(-10, 10), p=reals(-1, 1), q=reals(-1, 1))
def test_property_kinetostatics_power_balance(a, b, c, d, branch, w2, e2, m, f, mz, p, q):
    t2 = np.linspace(-np.pi, np.pi, 64)
    fd = np.hypot(d - a * np.cos(t2), a * np.sin(t2))
    t2 = t2[np.minimum(b + c - fd, fd - abs(b - c)) > 0.05 * (b + c)]   # away from toggles
    assume(t2.size > 3)
    com = ((p * a, q * a), (p * b, -q * b), (q * c, p * c))
    res = fourbar_kinetostatics(t2, a, b, c, d, w2, e2, branch, mass=m,
                                inertia=(0.1 * m[0], 0.2 * m[1], 0.3 * m[2]), com=com,
                                gravity=(1.0, -9.81), force=((0, 0), f, (f[1], f[0])),
                                force_point=((a, 0), (b / 2, q), (c, p)), moment=(mz, -mz, 2 * mz))
    k = res.kinematics
    omegas = (w2, k.omega3, k.omega4)
    alphas = (e2, k.eps3, k.eps4)
    power = res.Q * w2
    dT = np.zeros_like(power)
    J = (0.1 * m[0], 0.2 * m[1], 0.3 * m[2])
    loads = (((0.0, 0.0), (a, 0.0)), (f, (b / 2, q)), ((f[1], f[0]), (c, p)))
    for i, link in enumerate(("crank", "coupler", "rocker")):
        _, _, vx, vy, ax, ay = k.point(link, *com[i])
        dT += m[i] * (vx * ax + vy * ay) + J[i] * omegas[i] * alphas[i]
        power += m[i] * (1.0 * vx - 9.81 * vy) + (mz, -mz, 2 * mz)[i] * omegas[i]
        _, _, vx, vy, _, _ = k.point(link, *loads[i][1])
        power += loads[i][0][0] * vx + loads[i][0][1] * vy
    scale = np.abs(res.Q * w2).max() + np.abs(dT).max() + 1.0
    np.testing.assert_allclose(power, dT, rtol=0, atol=1e-9 * scale)


def test_results_export_their_columns(tmp_path):
    r = fourbar(CYCLE, A1, B1, C1, D1, 10.0)
    data = r.to_dict()
    np.testing.assert_array_equal(data["columns"]["theta4"], r.theta4)
    assert data["units"]["omega4"] == "rad/s" and data["branch"] == 1
    f = fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, 10.0, mass=(1.0, 3.0, 2.0))
    path = f.to_csv(tmp_path / "forces.csv")
    header = path.read_text().splitlines()[0]
    assert "Q [N*m]" in header and "R_Bx [N]" in header


def test_fast_result_construction_sets_every_field():
    import dataclasses

    r = fourbar(CYCLE, A1, B1, C1, D1, coupler_point=(0.1, 0.0))
    assert set(vars(r)) == {f.name for f in dataclasses.fields(FourbarResult)}
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.theta3 = r.theta4  # type: ignore[misc]


def test_kinetostatics_scalar_points_mean_points_on_the_link_line():
    kw = {"mass": MASS, "inertia": INERTIA, "gravity": GRAV, "moment": MOMENT}
    r1 = fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, 10.0, com=(0.03, 0.2, 0.05),
                               force=FORCE, force_point=(0.1, 0.0, 0.2), **kw)
    r2 = fourbar_kinetostatics(CYCLE, A1, B1, C1, D1, 10.0, com=((0.03, 0), (0.2, 0), (0.05, 0)),
                               force=FORCE, force_point=((0.1, 0), (0.0, 0), (0.2, 0)), **kw)
    np.testing.assert_array_equal(r1.Q, r2.Q)
    np.testing.assert_array_equal(r1.R_By, r2.R_By)


def test_blocked_kinetostatics_equals_small_calls():
    n = 20000
    t2 = np.linspace(-np.pi, np.pi, n)
    press = -100.0 * (1 + np.sin(t2))                  # a force given per position
    kw = {"mass": MASS, "inertia": INERTIA, "com": COM, "gravity": GRAV, "moment": MOMENT,
          "force_point": FPOINT}
    big = fourbar_kinetostatics(t2, A1, B1, C1, D1, 10.0, -30.0, -1,
                                force=((0, 0), (0, 0), (0.0, press)), **kw)
    for lo in range(0, n, 6000):
        sl = slice(lo, min(lo + 6000, n))
        small = fourbar_kinetostatics(t2[sl], A1, B1, C1, D1, 10.0, -30.0, -1,
                                      force=((0, 0), (0, 0), (0.0, press[sl])), **kw)
        for name in ("R_Ox", "R_Oy", "R_Ax", "R_Ay", "R_Bx", "R_By", "R_Cx", "R_Cy", "Q",
                     "shaking_force_x", "shaking_force_y", "shaking_moment"):
            np.testing.assert_allclose(getattr(big, name)[sl], getattr(small, name),
                                       rtol=1e-14, atol=1e-12)


def test_limit_positions_absent_where_the_geometry_forbids_them():
    # double-crank: crank and coupler never collinear, coupler and rocker never collinear
    lim = limit_positions(0.3, 0.2, 0.3, 0.1)
    assert np.isnan([lim.phi1_rocker_extended, lim.phi1_rocker_folded,
                     lim.phi1_toggle_extended, lim.phi1_toggle_folded]).all()
    r = fourbar(np.linspace(0, 2 * np.pi, 3601), 0.3, 0.2, 0.3, 0.1)
    assert (np.abs(r.omega4) > 1e-3).all()          # the output never stops
    # vectorised over designs
    lims = limit_positions(np.array([0.1, 0.3]), np.array([0.3, 0.2]), np.array([0.2, 0.3]),
                           np.array([0.3, 0.1]))
    assert np.isfinite(lims.theta4_rocker_extended[0]) and np.isnan(lims.theta4_rocker_extended[1])


def test_assembly_error_with_angles_per_design():
    t2 = np.array([[0.0, 1.0, 2.0], [0.5, 1.5, 3.0]])
    with pytest.raises(AssemblyError, match="phi1") as info:
        fourbar(t2, np.array([[0.3], [0.3]]), 0.1, 0.25, 0.3)
    assert info.value.ranges
    r = fourbar(t2, np.array([[0.3], [0.3]]), 0.1, 0.25, 0.3, on_failure="nan")
    f = np.hypot(0.3 - 0.3 * np.cos(t2), 0.3 * np.sin(t2))
    np.testing.assert_array_equal(r.valid, (f <= 0.35) & (f >= 0.15))


@settings(max_examples=50, deadline=None)
@given(a=lengths, b=lengths, c=lengths, d=lengths, branch=st.sampled_from([1, -1]))
def test_property_rocker_limits_are_stationary_points_of_theta4(a, b, c, d, branch):
    lim = limit_positions(a, b, c, d, branch)
    for t2l, t4l in ((lim.phi1_rocker_extended, lim.theta4_rocker_extended),
                     (lim.phi1_rocker_folded, lim.theta4_rocker_folded)):
        if np.isnan(t2l):
            continue
        r = fourbar(t2l, a, b, c, d, branch=branch, on_failure="nan")
        f = math.hypot(d - a * math.cos(t2l), a * math.sin(t2l))
        assume(min(b + c - f, f - abs(b - c)) > 1e-6 * (b + c))   # not also an input toggle
        assert bool(r.valid)
        assert abs(float(r.omega4)) < 1e-8 * (1 + a / c)
        assert abs(wrap(float(r.theta4) - t4l)) < 1e-9
    # crank-rockers: the sampled theta4 range lies within the limits and reaches them
    g = grashof(a, b, c, d)
    if g.motion == "crank-rocker":
        t2 = np.linspace(-np.pi, np.pi, 20001)
        t4 = np.unwrap(fourbar(t2, a, b, c, d, branch=branch).theta4)
        assert t4.max() - t4.min() <= lim.rocker_swing + 1e-9
        assert t4.max() - t4.min() >= lim.rocker_swing - 1e-5


@pytest.mark.parametrize("branch", [1, -1])
def test_python_numbers_and_numpy_arguments_give_identical_results(branch, monkeypatch):
    """One design in Python floats over a float64 array reaches the kernel as Python floats (the
    checks keep them); the same call with numpy scalars and a list of angles as 0-d arrays.
    Both run the same kernel: every field bit-identical.  Blocked evaluation (>= 16384
    positions) gives the same numbers as one call."""
    from linkwork.models import fourbar as fb

    calls = []
    kernel = fb._kernel

    def spy(*args):
        calls.append(type(args[1]))
        return kernel(*args)

    monkeypatch.setattr(fb, "_kernel", spy)
    fast = fourbar(CYCLE, 0.1, 0.3, 0.2, 0.3, 10.0, -3.0, branch)
    checked = fourbar(list(CYCLE), np.float64(0.1), np.float64(0.3), np.float64(0.2),
                      np.float64(0.3), np.float64(10.0), np.float64(-3.0), branch)
    assert calls == [float, np.ndarray]          # the checked path keeps 0-d arrays
    for name, val in vars(fast).items():
        np.testing.assert_array_equal(np.asarray(val), np.asarray(getattr(checked, name)),
                                      err_msg=name)
    t2 = np.linspace(0.0, 2 * np.pi, 20001)
    big = fourbar(t2, 0.1, 0.3, 0.2, 0.3, 10.0, -3.0, branch)
    part = fourbar(t2[:7001], 0.1, 0.3, 0.2, 0.3, 10.0, -3.0, branch)
    for name in ("theta3", "theta4", "omega3", "omega4", "eps3", "eps4", "xB", "yB"):
        np.testing.assert_array_equal(getattr(big, name)[:7001], getattr(part, name))
    assert big.valid.all()


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_crank_angle_is_named_without_warnings(bad):
    """pytest turns warnings into errors here: np.cos(inf) must never run (it warned
    'invalid value encountered in cos' before the ParameterError)."""
    t2 = CYCLE.copy()
    t2[7] = bad
    for kw in ({}, {"coupler_point": (0.1, 0.0)}):
        with pytest.raises(ParameterError) as ei:
            fourbar(t2, 0.1, 0.3, 0.2, 0.3, **kw)
        assert ei.value.parameter == "phi1"


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_fourbar_kinematics_against_root_finding_and_differentiated_loop(name, branch):
    """Reference: the from-scratch four-bar of tests/_fourbar_newton_euler.py (root finding,
    differentiated loop, Newton-Euler). Tolerance: close (RTOL = 1e-9 relative to the largest
    value)."""
    design = DESIGNS[name]
    a, b, c, d = design
    t2, th3, th4 = _assembled(design, branch)
    w2, e2 = _speeds(t2)
    w3, w4, al3, al4 = fourbar_rates(t2, th3, th4, a, b, c, w2, e2)
    r = fourbar(t2, a, b, c, d, w2, e2, branch)
    close(wrap(r.theta3 - th3), 0.0, 1.0)
    close(wrap(r.theta4 - th4), 0.0, 1.0)
    B = np.array([d, 0.0])[:, None] + c * e(th4)
    close(r.xB, B[0], a + b + c + d)
    close(r.yB, B[1], a + b + c + d)
    close(r.omega3, w3)
    close(r.omega4, w4)
    close(r.eps3, al3)
    close(r.eps4, al4)
    # a coupler point off the line
    p, q = 0.13, -0.06
    x, y, vx, vy, ax, ay = r.point("coupler", p, q)
    A, vA, aA = a * e(t2), a * w2 * ep(t2), a * (e2 * ep(t2) - w2**2 * e(t2))
    P, vP, aP = body_point(A, vA, aA, th3, w3, al3, (p, q))
    for got, want in ((x, P[0]), (y, P[1]), (vx, vP[0]), (vy, vP[1]), (ax, aP[0]),
                      (ay, aP[1])):
        close(got, want)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "non-Grashof"])
def test_newton_euler_reference_rates_equal_finite_differences_in_time(name, branch):
    """The hand-differentiated loop (the reference) against central differences in time of
    positions solved by root finding, phi1(t) = theta0 + w t + eps t^2 / 2."""
    design = DESIGNS[name]
    a, b, c, _d = design
    t2, _th3, _th4 = _assembled(design, branch)
    w, eps, h = 6.0, -40.0, 1e-4
    checked = 0
    for t0 in t2[:: max(1, len(t2) // 6)]:
        ts = np.arange(-3, 4) * h
        th2 = t0 + w * ts + eps * ts**2 / 2
        p3, p4 = fourbar_positions(th2, *design, branch)
        if not np.all(np.isfinite(p3)):
            continue
        p3, p4 = np.unwrap(p3), np.unwrap(p4)
        c1 = np.array([-1, 9, -45, 0, 45, -9, 1]) / (60 * h)
        c2 = np.array([2, -27, 270, -490, 270, -27, 2]) / (180 * h * h)
        w3, w4, al3, al4 = fourbar_rates(np.array([t0]), p3[3:4], p4[3:4], a, b, c, w, eps)
        np.testing.assert_allclose([c1 @ p3, c1 @ p4], [w3[0], w4[0]], rtol=1e-7, atol=1e-7 * w)
        np.testing.assert_allclose([c2 @ p3, c2 @ p4], [al3[0], al4[0]], rtol=1e-4,
                                   atol=1e-4 * w * w)
        checked += 1
    assert checked >= 5


def _omega4(t, design, branch):
    th3, th4 = fourbar_positions(np.array([t]), *design, branch)
    return fourbar_rates(np.array([t]), th3, th4, *design[:3], 1.0, 0.0)[1][0]


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", ["crank-rocker", "general", "non-Grashof"])
def test_limit_positions_and_transmission_angle_against_the_reference(name, branch):
    """Rocker limits = zeros of the reference's omega4(phi1); input toggles = ends of the
    assembled range; mu = angle ABO4 of the solved positions."""
    design = DESIGNS[name]
    a, b, c, d = design
    lim = limit_positions(*design, branch=branch)
    t2 = np.linspace(-np.pi, np.pi, 721)
    th3, th4 = fourbar_positions(t2, *design, branch)
    ok = np.isfinite(th3)
    # rocker limits: omega4 changes sign between assembled neighbours
    zeros = []
    for k in np.nonzero(ok[:-1] & ok[1:])[0]:
        w_lo, w_hi = _omega4(t2[k], design, branch), _omega4(t2[k + 1], design, branch)
        if w_lo * w_hi < 0:
            zeros.append(brentq(_omega4, t2[k], t2[k + 1], args=(design, branch), xtol=1e-14))
    got = [t for t in (lim.phi1_rocker_extended, lim.phi1_rocker_folded) if np.isfinite(t)]
    assert len(zeros) == len(got) >= 1
    for t in got:
        assert np.min(np.abs(wrap(np.array(zeros) - t))) < 1e-10
    for t2l, t4l in ((lim.phi1_rocker_extended, lim.theta4_rocker_extended),
                     (lim.phi1_rocker_folded, lim.theta4_rocker_folded)):
        if np.isfinite(t2l):
            assert abs(wrap(fourbar_positions(np.array([t2l]), *design, branch)[1][0] - t4l)
                       ) < 1e-9
    # input toggles: the crank's assembled range ends there (or the crank turns fully)
    if ok.all():
        assert np.isnan(lim.phi1_toggle_extended) or np.isnan(lim.phi1_toggle_folded)
    else:
        ends = t2[np.nonzero(ok[:-1] != ok[1:])[0]]
        toggles = [t for t in (lim.phi1_toggle_extended, lim.phi1_toggle_folded)
                   if np.isfinite(t)]
        for t in ends:
            assert min(abs(abs(t) - tt) for tt in toggles) < 2 * np.pi / 720
    # transmission angle: angle ABO4 of the solved positions
    A = a * e(t2[ok])
    B = np.array([d, 0.0])[:, None] + c * e(th4[ok])
    ba, bo = A - B, np.array([d, 0.0])[:, None] - B
    mu = np.arccos(np.sum(ba * bo, 0) / (b * c))
    close(transmission_angle(t2[ok], *design), mu, 1.0)
    close(fourbar(t2[ok], *design, 1.0, 0.0, branch).transmission_angle, mu, 1.0)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_fourbar_kinetostatics_against_newton_euler(name, branch):
    """Reference: the from-scratch four-bar of tests/_fourbar_newton_euler.py (root finding,
    differentiated loop, Newton-Euler). Tolerance: check_reactions (RTOL = 1e-9 relative to
    the largest value), close (RTOL = 1e-9 relative to the largest value)."""
    design = DESIGNS[name]
    ref = fourbar_reference(design, branch)
    f = _fourbar_closed(design, branch, ref)
    scale = check_reactions(((f.R_Ox, f.R_Oy), (f.R_Ax, f.R_Ay), (f.R_Bx, f.R_By),
                             (f.R_Cx, f.R_Cy)), f.Q, ref["x"])
    sf, sm_o2 = _shaking_ref(ref, (0.0, 0.0))
    close(f.shaking_force_x, sf[0], scale)
    close(f.shaking_force_y, sf[1], scale)
    close(f.shaking_moment, sm_o2)


@pytest.mark.parametrize("branch", [+1, -1])
@pytest.mark.parametrize("name", list(DESIGNS))
def test_assembly_and_dead_centres_against_the_reference(name, branch):
    """Where the four-bar assembles (closed form and engine, on_failure="nan") and the engine's
    dead centres (rocker reversals) against root finding."""
    design = DESIGNS[name]
    t2 = np.linspace(0.0, 2 * np.pi, 361) + 0.001
    ok = np.isfinite(fourbar_positions(t2, *design, branch)[0])
    r = fourbar(t2, *design, 1.0, 0.0, branch, on_failure="nan")
    kin = kinematics(engine_fourbar(*design, branch=branch), t2, on_failure="nan")
    np.testing.assert_array_equal(r.valid, ok)
    np.testing.assert_array_equal(kin.valid, ok)
    assert np.all(np.isnan(r.theta4[~ok])) and np.all(np.isfinite(r.theta4[ok]))
    if not ok.all():
        return
    zeros = [brentq(_omega4, t2[k], t2[k + 1], args=(design, branch), xtol=1e-14)
             for k in range(len(t2) - 1)
             if _omega4(t2[k], design, branch) * _omega4(t2[k + 1], design, branch) < 0]
    got = sorted(dc.phi1 for dc in dead_centres(kin) if dc.body == "rocker")
    assert len(got) == len(zeros) == (0 if name == "double-crank" else 2)
    if zeros:
        close(wrap(np.array(got) - np.array(zeros)), 0.0, 1.0)


def test_kinetostatics_load_array_of_the_wrong_length_is_named():
    """A per-position load whose length does not match the positions raised numpy's bare
    broadcast ValueError ('shape mismatch: objects cannot be broadcast ... arg 8'), naming
    neither the load nor the positions."""
    from linkwork.errors import ParameterError

    t2 = np.linspace(0.0, 2 * np.pi, 13)
    with pytest.raises(ParameterError, match=r"'positions': \(13,\), 'force\[1\]\[0\]': \(5,\)"):
        fourbar_kinetostatics(t2, *DESIGNS["crank-rocker"], 10.0, 0.0, 1,
                              force=((0, 0), (np.ones(5), 0.0), (0, 0)))
    with pytest.raises(ParameterError, match=r"'moment\[2\]': \(4,\)"):
        fourbar_kinetostatics(t2, *DESIGNS["crank-rocker"], 10.0, 0.0, 1,
                              moment=(0.0, 0.0, np.ones(4)))


# -- closed forms and result helpers --------------------------------------------------------------
@pytest.mark.parametrize("phi1, match", [
    (None, r"^phi1 = None is invalid: must be a number"),        # was 'phi1 = nan'
    (np.array([1.0 + 2.0j]), r"^phi1 = .*not complex"),         # ComplexWarning, result for 1
    (True, r"^phi1 = True .*not a boolean"),                     # computed at 1 rad
])
def test_fourbar_closed_form_crank_angle_is_checked(phi1, match):
    with pytest.raises(ParameterError, match=match):
        fourbar_cf.fourbar(phi1, 0.1, 0.3, 0.2, 0.3)


def test_fourbar_that_never_assembles_names_its_lengths_and_intervals():
    """The message had neither the lengths nor the intervals: '(|d - a|, d + a) does not meet
    (|b - c|, b + c)'. Here |A O4| in [0.9, 1.1] m and the dyad reaches [0.25, 0.35] m."""
    with pytest.raises(AssemblyError, match=r"\[\|d - a\|, d \+ a\] = \[0\.9, 1\.1\], which "
                                            r"does not meet \[\|b - c\|, b \+ c\] = \[0\.25, "
                                            r"0\.35\] \(a=0\.1, b=0\.3, c=0\.05, d=1 m\)"):
        fourbar_cf.transmission_angle_extremes(0.1, 0.3, 0.05, 1.0)


def _fourbar_solutions(a, b, c, d, t2):
    """All assemblies (theta3, theta4) at real t2 from the loop equation."""
    def res(q, t):
        return np.array([a * np.cos(t2) + b * np.cos(q[0]) - c * np.cos(q[1]) - d,
                         a * np.sin(t2) + b * np.sin(q[0]) - c * np.sin(q[1])])
    sols = []
    for s3 in np.linspace(-np.pi, np.pi, 8, endpoint=False):
        for s4 in np.linspace(-np.pi, np.pi, 8, endpoint=False):
            q = np.array([s3, s4])
            for _ in range(80):
                r = res(q, 0)
                J = np.array([[-b * np.sin(q[0]), c * np.sin(q[1])],
                              [b * np.cos(q[0]), -c * np.cos(q[1])]])
                if abs(np.linalg.det(J)) < 1e-14:
                    break
                q = q - np.linalg.solve(J, r)
            if np.max(np.abs(res(q, 0))) < 1e-13:
                q = np.remainder(q + np.pi, 2 * np.pi) - np.pi
                if not any(np.allclose(q, s, atol=1e-8) for s in sols):
                    sols.append(q)
    return sols


def _fourbar_reference(a, b, c, d, w2, e2, branch, t20, pq=(0.0, 0.0), step=2e-3):
    """theta3, theta4, points and their rates; branch = side of B w.r.t. A -> O4."""
    sols = _fourbar_solutions(a, b, c, d, t20)
    A = np.array([a * math.cos(t20), a * math.sin(t20)])
    chosen = None
    for q in sols:
        B = A + b * np.array([math.cos(q[0]), math.sin(q[0])])
        u = np.array([d, 0.0]) - A
        cross = u[0] * (B - A)[1] - u[1] * (B - A)[0]
        if np.sign(cross) == branch:
            chosen = q
    assert chosen is not None, "no assembly on the requested branch"

    def res(q, t):
        t2 = t20 + w2 * t + 0.5 * e2 * t * t
        return np.array([a * np.cos(t2) + b * np.cos(q[0]) - c * np.cos(q[1]) - d,
                         a * np.sin(t2) + b * np.sin(q[0]) - c * np.sin(q[1])])

    def position(t):
        q = _newton(res, chosen, np.asarray(t, dtype=complex))
        t2 = t20 + w2 * t + 0.5 * e2 * t * t
        xa, ya = a * np.cos(t2), a * np.sin(t2)
        xb, yb = xa + b * np.cos(q[0]), ya + b * np.sin(q[0])
        p, qq = pq
        xp = xa + p * np.cos(q[0]) - qq * np.sin(q[0])
        yp = ya + p * np.sin(q[0]) + qq * np.cos(q[0])
        # a rocker point (0.07, 0.03) in the rocker's frame (origin O4, x along O4 -> B)
        xr = d + 0.07 * np.cos(q[1]) - 0.03 * np.sin(q[1])
        yr = 0.07 * np.sin(q[1]) + 0.03 * np.cos(q[1])
        return np.array([q[0], q[1], xa, ya, xb, yb, xp, yp, xr, yr])

    x, v, acc = _motion(position, hd=step / max(abs(w2), 1.0))
    return x, v, acc


FOURBARS = [  # a, b, c, d, omega1, eps1, angles
    (0.1, 0.3, 0.2, 0.3, 10.0, 0.0, None),                     # paper 001 (crank-rocker)
    (0.1, 0.3, 0.2, 0.3, -7.0, 25.0, None),
    (0.3, 0.25, 0.28, 0.1, 5.0, -12.0, None),                  # double-crank
    (0.2, 0.2, 0.2, 0.45, 3.0, 4.0, "triple"),                 # non-Grashof triple rocker
]


def _angles_for(a, b, c, d, kind):
    if kind == "triple":
        # assembles for cos t2 >= ((a^2 + d^2) - (b + c)^2) / (2 a d); toggles at +-t
        tg = math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d))
        return np.array([-tg + 1e-3, -0.8, -0.3, 0.0, 0.4, 0.9, tg - 1e-3])
    lim = fb.limit_positions(a, b, c, d)
    return np.array([lim.phi1_rocker_extended + 1e-4, lim.phi1_rocker_folded - 1e-4,
                     0.2, 1.3, 2.5, 3.8, 5.2]) if not math.isnan(lim.phi1_rocker_extended) \
        else np.array([0.0, 0.7, 1.5, 2.5, 3.3, 4.4, 5.6])


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("a,b,c,d,w2,e2,kind", FOURBARS)
def test_fourbar_against_loop_equation(a, b, c, d, w2, e2, kind, branch):
    """Reference: the loop equations solved in this module (_fourbar_reference, Newton + time
    differences). Tolerance: _angle_close (1e-9 rad), _close (RTOL = 1e-6 relative, floor 1e-9
    of the scale)."""
    angles = _angles_for(a, b, c, d, kind)
    pq = (0.12, -0.05)
    res = fb.fourbar(angles, a, b, c, d, w2, e2, branch, coupler_point=pq)
    L = max(a, b, c, d)
    W = max(abs(w2), 1.0) * 3
    for k, t2 in enumerate(angles):
        step = 1e-5 if kind == "triple" else 2e-3
        x, v, acc = _fourbar_reference(a, b, c, d, w2, e2, branch, float(t2), pq, step)
        _angle_close(res.theta3[k], x[0], "theta3")
        _angle_close(res.theta4[k], x[1], "theta4")
        _close(res.omega3[k], v[0], W, "omega3")
        _close(res.omega4[k], v[1], W, "omega4")
        _close(res.eps3[k], acc[0], W * W + abs(e2), "eps3")
        _close(res.eps4[k], acc[1], W * W + abs(e2), "eps4")
        for name, i in (("xA", 2), ("yA", 3), ("xB", 4), ("yB", 5), ("xP", 6), ("yP", 7)):
            _close(getattr(res, name)[k], x[i], L, "points")
        for link, (p_, q_), i in (("coupler", pq, 6), ("rocker", (0.07, 0.03), 8)):
            px, py, pvx, pvy, pax, pay = (np.asarray(z)[k] for z in res.point(link, p_, q_))
            _close([px, py], x[i:i + 2], L, "point()")
            _close([pvx, pvy], v[i:i + 2], L * W, "point() velocity")
            _close([pax, pay], acc[i:i + 2], L * (W * W + abs(e2)), "point() acceleration")
        # transmission angle: angle A-B-O4 between coupler and rocker at B
        BA = x[2:4] - x[4:6]
        BO = np.array([d, 0.0]) - x[4:6]
        mu = math.acos(np.dot(BA, BO) / np.linalg.norm(BA) / np.linalg.norm(BO))
        _close(fb.transmission_angle(t2, a, b, c, d), mu, 1.0, "transmission_angle")
        _close(fb.transmission_angle(t2, a, b, c, d, acute=True), min(mu, np.pi - mu), 1.0,
               "transmission_angle")
    # theta3/theta4 in (-pi, pi] as documented
    assert np.all(res.theta3 > -np.pi) and np.all(res.theta3 <= np.pi)


def _rotates(a, b, c, d, which):
    """Brute force: can link 'a' (crank) or 'c' (rocker) turn a full circle?"""
    t = np.linspace(0, 2 * np.pi, 20001)
    if which == "crank":
        f = np.sqrt(a * a + d * d - 2 * a * d * np.cos(t))
        return bool(np.all((f <= b + c + 1e-12) & (f >= abs(b - c) - 1e-12)))
    f = np.sqrt(c * c + d * d - 2 * c * d * np.cos(t))
    return bool(np.all((f <= a + b + 1e-12) & (f >= abs(a - b) - 1e-12)))


@pytest.mark.parametrize("abcd,motion", [
    ((0.1, 0.3, 0.2, 0.3), "crank-rocker"),
    ((0.3, 0.25, 0.28, 0.1), "double-crank"),
    ((0.28, 0.1, 0.22, 0.25), "double-rocker"),
    ((0.22, 0.25, 0.15, 0.3), "rocker-crank"),
    ((0.2, 0.2, 0.2, 0.45), "triple-rocker"),
    ((0.1, 0.3, 0.2, 0.2), "change-point"),
])
def test_grashof_type_against_brute_force(abcd, motion):
    g = fb.grashof(*abcd)
    assert g.motion == motion
    assert bool(g.crank_rotates) == _rotates(*abcd, "crank")
    assert bool(g.rocker_rotates) == _rotates(*abcd, "rocker")
    s, l = min(abcd), max(abcd)
    rest = sorted(abcd)[1:3]
    expected_class = "I" if s + l < sum(rest) - 1e-12 else ("II" if s + l > sum(rest) + 1e-12
                                                          else "III")
    assert g.grashof_class == expected_class


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("abcd", [(0.1, 0.3, 0.2, 0.3), (0.05, 0.2, 0.12, 0.18)])
def test_fourbar_limit_positions_by_search(abcd, branch):
    """Reference: tests/_planar_newton_euler.py (Newton on the loop equations, complex-step
    rates, free-body equations); scipy minimize_scalar. Tolerance: _angle_close (1e-9 rad),
    tol=1e-5, tol=1e-9, _close (RTOL = 1e-6 relative, floor 1e-9 of the scale), < 1e-6."""
    a, b, c, d = abcd
    lim = fb.limit_positions(a, b, c, d, branch)

    def t4(t2):
        return float(fb.fourbar(t2, a, b, c, d, branch=branch).theta4)
    grid = np.linspace(0, 2 * np.pi, 721)
    vals = np.unwrap([t4(t) for t in grid])
    found = []
    for sgn in (1.0, -1.0):
        i = int(np.argmax(sgn * vals))
        ref0 = vals[i]
        r = minimize_scalar(
            lambda t, sgn=sgn, ref0=ref0: -sgn * (ref0 + math.remainder(t4(t) - ref0, 2 * np.pi)),
            bounds=(grid[i] - 0.02, grid[i] + 0.02), method="bounded", options={"xatol": 1e-11})
        found.append((r.x, t4(r.x)))
    # which extreme is 'extended': |O2 B| = a + b there
    for t2_, t4_ in found:
        B = np.array([d + c * math.cos(t4_), c * math.sin(t4_)])
        if abs(np.linalg.norm(B) - (a + b)) < 1e-6:
            ext = (t2_, t4_)
        else:
            assert abs(np.linalg.norm(B) - abs(a - b)) < 1e-6
            fold = (t2_, t4_)
    _angle_close(lim.phi1_rocker_extended, ext[0], "limit phi1", tol=1e-5)
    _angle_close(lim.theta4_rocker_extended, ext[1], "limit theta4", tol=1e-9)
    _angle_close(lim.phi1_rocker_folded, fold[0], "limit phi1", tol=1e-5)
    _angle_close(lim.theta4_rocker_folded, fold[1], "limit theta4", tol=1e-9)
    swing = abs(math.remainder(ext[1] - fold[1], 2 * np.pi))
    _close(lim.rocker_swing, swing, 1.0, "rocker_swing")
    fwd = (ext[0] - fold[0]) % (2 * np.pi)
    _close(lim.time_ratio, fwd / (2 * np.pi - fwd), 1.0, "time_ratio")


def test_fourbar_input_toggles_by_root_finding():
    """Reference: tests/_planar_newton_euler.py (Newton on the loop equations, complex-step
    rates, free-body equations); scipy brentq. Tolerance: _close (RTOL = 1e-6 relative, floor
    1e-9 of the scale)."""
    a, b, c, d = 0.2, 0.2, 0.2, 0.45
    lim = fb.limit_positions(a, b, c, d)

    def f(t, L):
        return math.hypot(a * math.cos(t) - d, a * math.sin(t)) - L
    t_ext = brentq(f, 0.0, np.pi, args=(b + c,), xtol=1e-15)
    _close(lim.phi1_toggle_extended, t_ext, 1.0, "toggle")
    assert math.isnan(lim.phi1_toggle_folded)  # |b - c| = 0 is never reached (d - a > 0)
    ext = fb.transmission_angle_extremes(a, b, c, d)
    t = np.linspace(-t_ext, t_ext, 20001)
    mus = fb.transmission_angle(t, a, b, c, d)
    _close(ext.mu_min, np.nanmin(mus), 1.0, "transmission extremes")
    _close(ext.mu_max, np.nanmax(mus), 1.0, "transmission extremes")


@pytest.mark.parametrize("branch", [1, -1])
def test_fourbar_kinetostatics_against_free_body_equations(branch):
    """Reference: the loop equations solved in this module (_fourbar_reference, Newton + time
    differences). Tolerance: < 1e-9 * np.max(np.abs(rhs)), _close (RTOL = 1e-6 relative, floor
    1e-9 of the scale)."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    w2, e2 = -9.0, 35.0
    masses = (1.0, 3.0, 2.0)
    inert = (0.004, 0.03, 0.01)
    coms = ((0.04, 0.01), (0.12, -0.03), (0.09, 0.02))
    forces = ((3.0, -2.0), (15.0, -40.0), (-8.0, 5.0))
    fpts = ((0.1, 0.0), (0.2, 0.05), (0.2, 0.0))
    moments = (-1.2, 0.7, 3.5)
    g = (0.0, -9.81)
    res = fb.fourbar_kinetostatics(PHI7, a, b, c, d, w2, e2, branch, mass=masses,
                                   inertia=inert, com=coms, gravity=g, force=forces,
                                   force_point=fpts, moment=moments)
    for k, t2 in enumerate(PHI7):
        x, v, acc = _fourbar_reference(a, b, c, d, w2, e2, branch, float(t2))
        th = (float(t2), x[0], x[1])
        om = (w2, v[0], v[1])
        al = (e2, acc[0], acc[1])
        origin = [np.zeros(2), x[2:4], np.array([d, 0.0])]
        aorig = [np.zeros(2), acc[2:4], np.zeros(2)]
        # unknowns: R_O(2), R_A(2), R_B(2), R_C(2), Q: by frame on crank at O2, crank on
        # coupler at A, coupler on rocker at B, frame on rocker at O4; Q motor on crank
        M = np.zeros((9, 9))
        rhs = np.zeros(9)
        O2, A, B, O4 = np.zeros(2), x[2:4], x[4:6], np.array([d, 0.0])

        def put(body, col, f, P, m=0.0, M=M):
            M[3 * body:3 * body + 3, col] += [f[0], f[1], P[0] * f[1] - P[1] * f[0] + m]
        ex, ey = np.array([1.0, 0.0]), np.array([0.0, 1.0])
        for base, P, on, by in ((0, O2, 0, None), (2, A, 1, 0), (4, B, 2, 1), (6, O4, 2, None)):
            for col, e_ in ((base, ex), (base + 1, ey)):
                put(on, col, e_, P)
                if by is not None:
                    put(by, col, -e_, P)
        put(0, 8, (0, 0), (0, 0), 1.0)
        for i in range(3):
            p = coms[i]
            r = _rot(th[i], p)
            C = origin[i] + r
            ac = aorig[i] + al[i] * np.array([-r[1], r[0]]) - om[i] ** 2 * r
            m = masses[i]
            W = m * np.array(g)
            fp = origin[i] + _rot(th[i], fpts[i])
            Fe = np.array(forces[i])
            rhs[3 * i:3 * i + 3] = [m * ac[0] - W[0] - Fe[0], m * ac[1] - W[1] - Fe[1],
                                    C[0] * m * ac[1] - C[1] * m * ac[0] + inert[i] * al[i]
                                    - (C[0] * W[1] - C[1] * W[0])
                                    - (fp[0] * Fe[1] - fp[1] * Fe[0]) - moments[i]]
        sol = np.linalg.lstsq(M, rhs, rcond=None)[0]
        assert np.max(np.abs(M @ sol - rhs)) < 1e-9 * np.max(np.abs(rhs))
        F = np.max(np.abs(sol[:8]))
        for name, val in zip(("R_Ox", "R_Oy", "R_Ax", "R_Ay", "R_Bx", "R_By", "R_Cx", "R_Cy"),
                             sol[:8], strict=True):
            _close(getattr(res, name)[k], val, F, "fourbar_kinetostatics R")
        _close(res.Q[k], sol[8], F * d, "fourbar_kinetostatics Q")
        # shaking: force of the moving links on the frame, moment about O2
        sf = -(sol[0:2] + sol[6:8])
        sm = -sol[8] - (O4[0] * sol[7] - O4[1] * sol[6])
        _close(res.shaking_force_x[k], sf[0], F, "fourbar_kinetostatics shaking")
        _close(res.shaking_force_y[k], sf[1], F, "fourbar_kinetostatics shaking")
        _close(res.shaking_moment[k], sm, F * d, "fourbar_kinetostatics shaking")


def test_non_grashof_full_rotation_lists_the_ranges():
    a, b, c, d = 0.2, 0.2, 0.2, 0.45
    with pytest.raises(AssemblyError) as ei:
        fb.fourbar(_fb_full(), a, b, c, d)
    tg = math.degrees(math.acos((a * a + d * d - (b + c) ** 2) / (2 * a * d)))
    lo, hi = (math.degrees(v) for v in ei.value.ranges[0])
    assert lo == pytest.approx(tg, abs=1.01) and hi == pytest.approx(360 - tg, abs=1.01)
    r = fb.fourbar(_fb_full(), a, b, c, d, on_failure="nan")
    assert np.all(np.isnan(r.theta3[~r.valid])) and np.all(np.isfinite(r.theta3[r.valid]))


def test_fourbar_singular_position_is_never_silent_nan():
    """a = d, b = c (a kite): at phi1 = 0 the crank pin A lies on O4 and B is undetermined.
    The closed form returned NaN there with ``assembled`` True and no error."""
    t = np.array([0.0, 1.0, np.pi])
    with pytest.raises(AssemblyError) as ei:
        fb.fourbar(t, 0.1, 0.2, 0.2, 0.1)
    assert "singular" in str(ei.value) and ei.value.ranges == [(0.0, 0.0)]
    r = fb.fourbar(t, 0.1, 0.2, 0.2, 0.1, on_failure="nan", coupler_point=(0.1, 0.02))
    assert list(r.valid) == [False, True, True]
    for name in ("theta3", "theta4", "omega3", "omega4", "eps3", "eps4", "xB", "yB", "xP"):
        v = getattr(r, name)
        assert np.isnan(v[0]) and np.all(np.isfinite(v[1:])), name
    with pytest.raises(AssemblyError):
        fb.fourbar_kinetostatics(0.0, 0.1, 0.2, 0.2, 0.1, mass=(1, 1, 1))
    # the engine agrees: the same position is refused
    with pytest.raises(AssemblyError):
        kinematics(engine_fourbar(0.1, 0.2, 0.2, 0.1), t)


def test_fourbar_empty_and_non_broadcasting_inputs():
    """An empty phi1 raised NumPy's 'zero-size array to reduction operation'; lengths that
    do not broadcast against the angles raised NumPy's broadcast error."""
    r = fb.fourbar(np.array([]), 0.1, 0.3, 0.2, 0.3)
    assert r.theta3.shape == (0,) and r.valid.shape == (0,)
    assert fb.fourbar_kinetostatics(np.array([]), 0.1, 0.3, 0.2, 0.3).Q.shape == (0,)
    for n in (2, 20000):
        with pytest.raises(ParameterError, match=r"shapes.*'a': \(3,\)"):
            fb.fourbar(np.zeros(n), np.array([0.1, 0.2, 0.3]), 0.3, 0.2, 0.3)
