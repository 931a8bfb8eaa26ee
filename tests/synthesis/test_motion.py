"""Motion generation (linkwork.synthesis.motion): Burmester theory for 3, 4 and 5 poses.

Planted problems: poses taken from a known four-bar (the planar engine) must give back its
two dyads among the Burmester points of 5 poses (to 1e-9 of the size of the poses) and on the
centre-point curve of 4 poses; every returned four-bar reaches every pose, recomputed through
the engine from its mechanism(): the coupler frame's origin and angle to 1e-9 (of the size of
the poses), in order, on one circuit (the independent model of tests/_synthesis_reference.py).
"""

from __future__ import annotations

import math

import _synthesis_reference as ref
import numpy as np
import pytest

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis import motion as M
from linkwork.synthesis.design import FourbarDesign

PLANT = dict(r1=4.0, r2=1.0, r3=3.5, r4=3.0, rcx=1.5, rcy=1.2, x0=0.5, y0=-0.3, theta0=0.3)
TH = np.array([0.3, 1.2, 2.0, 3.1, 4.4])


def _poses(th=TH):
    fb = FourbarDesign(params=dict(PLANT, theta2=[0.0]), branch=1, error=0.0,
                       points=np.zeros((1, 2)))
    kin = kinematics(fb.mechanism(), np.asarray(th) + PLANT["theta0"])
    P = kin.point("coupler", "P")
    # the coupler frame: origin at P, x axis along the coupler A -> B
    return np.c_[P.x, P.y, kin.angle("coupler")], fb


def _reaches(res, poses):
    L = float(np.hypot(*np.ptp(poses[:, :2], axis=0)))
    for d in res.designs:
        kin = kinematics(d.mechanism(), np.asarray(d.fourbar.params["theta2"])
                         + d.fourbar.params["theta0"])
        P = kin.point("coupler", "P")
        assert np.allclose(P.x, poses[:, 0], atol=1e-9 * L)
        assert np.allclose(P.y, poses[:, 1], atol=1e-9 * L)
        # the pose angle: the coupler's angle differs from the pose's by one constant
        off = np.mod(kin.angle("coupler") - poses[:, 2], 2 * math.pi)
        assert np.ptp(np.unwrap(off)) < 1e-9
        p = dict(d.fourbar.params)
        assert ref.ordered(p["theta2"])[0]
        assert ref.one_circuit(p, d.fourbar.branch, closed=False)


def test_poles_are_fixed_points_of_the_displacements():
    poses, _ = _poses()
    for (i, j), p in M.poles(poses).items():
        m = np.linalg.solve(np.array([[math.cos(poses[i, 2]), -math.sin(poses[i, 2])],
                                      [math.sin(poses[i, 2]), math.cos(poses[i, 2])]]),
                            p - poses[i, :2])  # the pole in the coupler frame of pose i
        assert np.allclose(M.place(poses[[j]], m)[0], p, atol=1e-12)


def test_five_planted_poses_give_back_the_planted_dyads():
    poses, fb = _poses()
    L = float(np.hypot(*np.ptp(poses[:, :2], axis=0)))
    dyads = M.burmester_points(poses)
    assert 2 <= len(dyads) <= 4
    o2, o4 = fb.pivots()
    for c in (o2, o4):
        assert min(np.hypot(*(d.c - c)) for d in dyads) < 1e-9 * L
    # every Burmester point is a dyad: its moving pivot stays at one distance from its centre
    for d in dyads:
        r = np.hypot(*(M.place(poses, d.m) - d.c).T)
        assert np.ptp(r) < 1e-9 * L
    res = M.motion(poses)
    _reaches(res, poses)
    assert any(np.hypot(*(d.c1 - o2)) < 1e-9 * L and np.hypot(*(d.c2 - o4)) < 1e-9 * L
               for d in res.designs)


def test_four_poses_centre_point_curve_and_four_bars():
    poses, fb = _poses(TH[:4])
    L = float(np.hypot(*np.ptp(poses[:, :2], axis=0)))
    C, Mc = M.centre_point_curve(poses, 360)
    for c, m in zip(C[::17], Mc[::17], strict=True):  # each centre point with its circle point
        r = np.hypot(*(M.place(poses, m) - c).T)
        assert np.ptp(r) < 1e-8 * max(L, float(r.mean()))
    o2, _ = fb.pivots()
    # the planted fixed pivot lies on the curve: the 3 x 3 determinant vanishes there
    rows = M._rows(poses, o2, (1, 2, 3))
    assert abs(np.linalg.det(rows)) < 1e-9 * np.abs(rows).max() ** 3
    res = M.motion(poses, grashof=True, n_designs=3)
    _reaches(res, poses)
    for d in res.designs:
        assert ref.crank_rocker(dict(d.fourbar.params))


def test_three_poses_with_given_fixed_pivots():
    poses, fb = _poses(TH[:3])
    o2, o4 = fb.pivots()
    res = M.motion(poses, fixed_pivots=[o2, o4])
    _reaches(res, poses)
    assert np.allclose(res.best.m1, [-PLANT["rcx"], -PLANT["rcy"]], atol=1e-9)


def test_pivot_region_keeps_fixed_pivots_inside():
    poses, _ = _poses(TH[:4])
    region = ((-2.0, 6.0), (-3.0, 3.0))
    res = M.motion(poses, pivot_region=region, n_designs=3)
    for d in res.designs:
        for c in (d.c1, d.c2):
            assert -2.0 <= c[0] <= 6.0 and -3.0 <= c[1] <= 3.0


def test_five_poses_without_a_real_burmester_pair_say_so():
    """Poses with no real Burmester point; confirmed independently by Newton's method on the
    four dyad equations from 400 random starts, none of which ends on a dyad other than a
    pole (the poles satisfy the equations trivially)."""
    from scipy.optimize import least_squares

    rng = np.random.default_rng(2)
    poses = np.c_[rng.uniform(-1, 1, (5, 2)), rng.uniform(-1.5, 1.5, 5)]
    assert M.burmester_points(poses) == []
    starts = np.random.default_rng(7).uniform(-5, 5, (400, 4))

    def eqs(v):
        Q = M.place(poses, v[2:])
        r2 = np.sum((Q - v[:2]) ** 2, axis=1)
        return r2[1:] - r2[0]

    poles = list(M.poles(poses).values())
    for v0 in starts:
        sol = least_squares(eqs, v0, xtol=1e-14, ftol=1e-14, gtol=1e-14, method="lm")
        if np.max(np.abs(eqs(sol.x))) < 1e-9:  # converged: a pole (degenerate dyad) only
            assert min(np.hypot(*(sol.x[:2] - p)) for p in poles) < 1e-5 or np.hypot(
                *(M.place(poses[:1], sol.x[2:])[0] - sol.x[:2])) < 1e-5
    with pytest.raises(InfeasibleError, match="the 5 poses have no real Burmester pair"):
        M.motion(poses)


def test_bad_pose_counts_are_named():
    poses, _ = _poses()
    with pytest.raises(ParameterError, match="too few"):
        M.motion(poses[:2])
    with pytest.raises(ParameterError, match="too many"):
        M.motion(np.vstack([poses, poses[:1] + 1]))
    with pytest.raises(ParameterError, match="3 poses leave the pivots free"):
        M.motion(poses[:3])
