"""Optimal balancing: superposition vs the engine, optima vs known solutions, Pareto flags."""

from __future__ import annotations

import numpy as np
import pytest
from _balancing_cases import paper_fourbar as paper001_fourbar

from linkwork import balancing as bal
from linkwork.balancing import add_counterweights, rms
from linkwork.balancing.optimal import (
    BalancingProblem,
    optimal_balance,
    pareto_set,
    weight_grid,
)
from linkwork.errors import ParameterError
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import fourbar_mechanism

PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)


@pytest.fixture(scope="module")
def mech():
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)


@pytest.mark.parametrize("gravity", [None, (0.0, -9.81)])
def test_superposition_equals_engine_resolve(mech, gravity):
    prob = BalancingProblem(mech, n=72, gravity=gravity)
    x = np.array([3.0, 0.07, 2.5, 4.0, 0.12, -2.8])
    F, M, Q = prob.loads(x)
    bal = add_counterweights(mech, prob.counterweights(x))
    kin = kinematics(bal, prob.phi)
    d_in = inverse_dynamics(kin, about=prob.O)
    d_g = inverse_dynamics(kin, about=prob.O, gravity=gravity)
    np.testing.assert_allclose(F[:, 0], d_in.shaking_fx, atol=1e-9 * np.abs(F).max())
    np.testing.assert_allclose(F[:, 1], d_in.shaking_fy, atol=1e-9 * np.abs(F).max())
    np.testing.assert_allclose(M, d_in.shaking_m, atol=1e-9 * np.abs(M).max())
    np.testing.assert_allclose(Q, d_g.Q, atol=1e-9 * np.abs(Q).max())


def test_force_only_optimum_is_full_force_balance(mech):
    r = optimal_balance(mech, (1, 0, 0), n=90, starts=2)
    prob = BalancingProblem(mech, n=90)
    assert r.force_rms <= 1e-6 * prob.ref[0]
    # the static moments of full force balance (Berkof-Lowen; paper 001's 0.2 and 0.5 kg m)
    assert [c.static_moment for c in r.counterweights] == pytest.approx([0.2, 0.5], rel=1e-5)
    phi = np.linspace(0, 2 * np.pi, 90, endpoint=False)
    d = inverse_dynamics(kinematics(r.mechanism, phi))
    assert rms(phi, np.stack([d.shaking_fx, d.shaking_fy], -1)) <= 1e-6 * prob.ref[0]


def test_moment_weighted_optimum_beats_static_and_unbalanced(mech):
    r = optimal_balance(mech, (0, 1, 0), n=90, starts=3, mass=(0.0, 8.0), radius=(0.03, 0.15))
    prob = BalancingProblem(mech, n=90)
    assert r.moment_rms < prob.ref[1]
    # static balance with the paper's radii has a larger RMS shaking moment (5.53 N m)
    assert r.moment_rms < 5.5
    for c in r.counterweights:
        assert 0.03 - 1e-12 <= c.radius <= 0.15 + 1e-12
        assert c.mass() <= 8.0 + 1e-9


def test_pareto_flags_and_comparison_points(mech):
    W = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0], [0.0, 0.0, 1.0]])
    p = pareto_set(mech, W, n=72, starts=2, static_radii={"crank": 0.05, "rocker": 0.1})
    P = np.stack([p.force_rms, p.moment_rms, p.torque_fluct], -1)
    for i, pt in enumerate(P):
        brute = any(np.all(P[j] <= pt) and np.any(P[j] < pt) for j in range(len(P)) if j != i)
        assert p.dominated[i] == brute
    assert p.static[0] < 1e-9 * p.unbalanced[0]
    assert p.static[1] == pytest.approx(5.53, abs=0.01)


def test_weight_grid_and_errors(mech):
    g = weight_grid(3)
    assert g.shape == (6, 3)
    np.testing.assert_allclose(g.sum(axis=1), 1.0)
    with pytest.raises(ParameterError, match="weights"):
        optimal_balance(mech, (0, 0, 0), n=36)
    with pytest.raises(ParameterError, match="radius bounds"):
        optimal_balance(mech, (1, 0, 0), n=36, radius=(0.0, 0.1))


@pytest.mark.parametrize("gravity", [None, (0.3, -9.81)])
def test_analytic_gradient_matches_finite_differences(mech, gravity):
    """Reference: central finite differences. Tolerance: rtol=1e-12, rtol=1e-5, atol=1e-7."""
    prob = BalancingProblem(mech, n=48, gravity=gravity)
    x = np.array([2.0, 0.06, 2.9, 3.0, 0.09, -2.5])
    vals, grad = prob.evaluate_with_gradient(x)
    np.testing.assert_allclose(vals, prob.evaluate(x), rtol=1e-12)
    h = 1e-6
    for j in range(x.size):
        e = np.zeros_like(x)
        e[j] = h
        fd = (np.array(prob.evaluate(x + e)) - np.array(prob.evaluate(x - e))) / (2 * h)
        np.testing.assert_allclose(grad[:, j], fd, rtol=1e-5, atol=1e-7)


def test_optimal_balance_not_worse_than_a_brute_force_grid():
    """Tiny problem: one counterweight (mass, radius, angle) on the crank only. The objective
    of a design is recomputed here with the engine (add_counterweights + inverse dynamics);
    the optimiser's design must be at least as good as the best of a grid."""
    from linkwork.balancing.optimal import BalancingProblem, optimal_balance

    mech = paper001_fourbar()
    n = 72
    prob = BalancingProblem(mech, links=["crank"], n=n)
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    d0 = inverse_dynamics(kinematics(mech, phi), about=(0, 0))

    def engine_values(m, r, a):
        mb = bal.add_counterweights(mech, [bal.Counterweight.from_mass("crank", m, r, a)]) \
            if m > 0 else mech
        d = inverse_dynamics(kinematics(mb, phi), about=(0, 0))
        F = np.hypot(d.shaking_fx, d.shaking_fy)
        Q = d.Q - d.Q.mean()
        return np.sqrt(np.mean(F**2)), np.sqrt(np.mean(d.shaking_m**2)), np.sqrt(np.mean(Q**2))

    ref = np.array(engine_values(0.0, 0.1, 0.0))
    assert np.allclose(ref, [np.sqrt(np.mean(d0.shaking_fx**2 + d0.shaking_fy**2)),
                             np.sqrt(np.mean(d0.shaking_m**2)),
                             np.sqrt(np.mean((d0.Q - d0.Q.mean()) ** 2))])
    # the superposition used by the optimiser equals the engine at a few designs
    for des in ((2.0, 0.1, 3.0), (6.0, 0.04, -1.0)):
        assert np.allclose(prob.evaluate(des), engine_values(*des), rtol=1e-9)
    wts = np.array([1.0, 1.0, 1.0])
    opt = optimal_balance(prob, wts, mass=(0.0, 8.0), radius=(0.02, 0.15))
    cw = opt.counterweights[0]
    got = wts @ (np.array(engine_values(cw.mass(), cw.radius, cw.angle)) / ref)
    assert got == pytest.approx(opt.objective, rel=1e-9)
    best = np.inf
    for m in np.linspace(0.0, 8.0, 17):
        for r in np.linspace(0.02, 0.15, 6):
            for a in np.linspace(-np.pi, np.pi, 24, endpoint=False):
                best = min(best, wts @ (np.array(prob.evaluate((m, r, a))) / ref))
    assert got <= best + 1e-9


def test_pareto_set_flags_dominated_designs_correctly():
    from linkwork.balancing.optimal import pareto_set

    p = pareto_set(paper001_fourbar(), n=72, weights=np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1],
                                                            [1, 1, 1], [1, 1, 0]], float))
    V = np.stack([p.force_rms, p.moment_rms, p.torque_fluct], -1)
    for i in range(len(V)):
        dom = any(np.all(V[j] <= V[i] + 1e-12) and np.any(V[j] < V[i] - 1e-9)
                  for j in range(len(V)) if j != i)
        assert bool(p.dominated[i]) == dom
