"""Synthesis judged by forces (linkwork.synthesis.forces, path(objective=...)).

* The closed-form inverse dynamics the search uses (``fourbar_dynamics``) against the planar
  engine (``planar.dynamics.inverse_dynamics`` on the design's ``mechanism()``): driving
  torque, every joint's reaction and the shaking force, with gravity, a tool force on the
  coupler point and given or estimated masses, both branches: to 1e-9 of the largest value.
  ``force_metrics`` against ``evaluate_forces`` (the engine's numbers the results report) to
  1e-12 relative, for a crank-rocker (a full turn) and a rocker (the range it runs).
* Weighted objective in the refinement: eight points of a known crank-rocker with timing (one
  exact design); with a weight on the peak driving torque the search returns designs that
  are less accurate and drive with less torque, the more so the larger the weight, with a
  smaller weighted score than the exact design's - the weight moves the optimum, it does not
  only re-rank. Every reported force is the engine's.
* Pareto set: no returned design is dominated by another; their forces are the engine's; the
  set runs from the exact design to less accurate, lower-torque ones.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from linkwork.errors import ParameterError
from linkwork.planar.dynamics import PointForce, inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis.design import PARAMS, FourbarDesign, coupler_point
from linkwork.synthesis.forces import (
    ForceModel,
    Objective,
    estimate_masses,
    evaluate_forces,
    force_metrics,
    fourbar_dynamics,
    pareto_front,
    weighted_score,
)
from linkwork.synthesis.path import path

PLANT = dict(r1=0.4, r2=0.1, r3=0.35, r4=0.3, rcx=0.15, rcy=0.12, x0=0.05, y0=-0.03, theta0=0.3)
MODELS = (ForceModel(omega1=7.0, force=(30.0, -50.0), gravity=(0.0, -9.81)),
          ForceModel(masses=(0.5, 1.2, 0.8), omega1=3.0, force=(-20.0, 0.0)))


def _design(p: dict, branch: int = 1, th=(0.2, 1.0, 2.0), rotates: bool = True) -> FourbarDesign:
    return FourbarDesign(params=dict(p, theta2=list(th)), branch=branch, error=0.0,
                         points=np.zeros((len(th), 2)), checks={"crank_rotates": rotates})


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("branch", [1, -1])
def test_closed_form_dynamics_equals_the_engine(model, branch):
    d = _design(PLANT, branch)
    phi = np.linspace(0.0, 2 * math.pi, 73)
    mech = d.mechanism(estimate_masses(d.params, model), omega1=model.omega1)
    kin = kinematics(mech, phi + PLANT["theta0"])
    dyn = inverse_dynamics(kin, gravity=model.gravity,
                           loads=[PointForce("coupler", "P", *model.force)])
    X = np.array([[PLANT[k] for k in PARAMS]])
    ours = fourbar_dynamics(X, np.array([branch]), phi[None, :], model)
    bearing = np.max([dyn.reaction_magnitude(j) for j in dyn.joints], axis=0)
    for mine, ref in ((ours["Q"][0], dyn.Q), (ours["bearing"][0], bearing),
                      (ours["shaking"][0], np.hypot(dyn.shaking_fx, dyn.shaking_fy))):
        assert np.allclose(mine, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


@pytest.mark.parametrize("model", MODELS)
def test_force_metrics_equal_the_engines_numbers(model):
    rocker = dict(r1=2.0, r2=1.5, r3=1.2, r4=1.4, rcx=0.5, rcy=0.3, x0=0.1, y0=0.2, theta0=0.4)
    for p, th, rot in ((PLANT, (0.2, 1.0, 2.0), True), (rocker, (-0.8, -0.3, 0.8), False)):
        ref = evaluate_forces(_design(p, 1, th, rot), model)
        X = np.array([[p[k] for k in PARAMS]])
        m = force_metrics(X, np.array([1]), np.array([th]), np.array([rot]), model)
        for k, v in ref.items():
            assert m[k][0] == pytest.approx(v, rel=1e-12)


def _planted(n: int = 8):
    th = np.linspace(0.2, 5.5, n)
    x, y, _ = coupler_point(th, PLANT, 1)
    return np.c_[x, y], th


MODEL = ForceModel(omega1=20.0, force=(0.0, -200.0))
SEARCH = dict(progress=False, n_candidates=2**11, n_refine=6, seed=3)


def test_weighted_objective_trades_accuracy_for_torque():
    pts, th = _planted()
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    exact = path(pts, timing=th, **SEARCH).best
    assert exact.error < 1e-20 * L * L
    exact = replace(exact, forces=evaluate_forces(exact, MODEL))
    found = []
    for w in (0.1, 1.0):
        obj = Objective(kind="weighted", weights={"error": 1.0, "peak_torque": w},
                        forces=MODEL)
        res = path(pts, timing=th, objective=obj, **SEARCH)
        d = res.best
        assert d.forces == evaluate_forces(d, MODEL)  # the engine's numbers
        assert weighted_score(d, obj, res.scales) < weighted_score(exact, obj, res.scales)
        found.append(d)
    (a, b) = found
    assert exact.error < a.error < b.error
    assert exact.error < 1e-3 * a.error  # the weight moved the refinement off the exact design
    assert exact.forces["peak_torque"] > a.forces["peak_torque"] > b.forces["peak_torque"]


def test_pareto_set_is_non_dominated_and_re_solved_by_the_engine():
    pts, th = _planted()
    L = float(np.hypot(*np.ptp(pts, axis=0)))
    res = path(pts, timing=th, objective=Objective(kind="pareto", forces=MODEL), **SEARCH)
    ds = res.designs
    assert len(ds) >= 3 and res.pareto == tuple(range(len(ds)))
    v = np.array([[d.error, d.forces["peak_torque"]] for d in ds])
    for i in range(len(v)):
        others = np.delete(v, i, axis=0)
        assert not np.any(np.all(others <= v[i], axis=1) & np.any(others < v[i], axis=1))
    for d in ds:
        assert d.forces == evaluate_forces(d, MODEL)
    order = np.argsort(v[:, 0])
    assert v[order[0], 0] < 1e-20 * L * L  # from the exact design ...
    assert np.all(np.diff(v[order, 1]) < 0)  # ... to less accurate, lower-torque ones


def test_pareto_front_equals_brute_force():
    rng = np.random.default_rng(1)
    v = rng.integers(0, 6, size=(60, 3)).astype(float)
    brute = [i for i in range(len(v))
             if not any(np.all(v[j] <= v[i]) and np.any(v[j] < v[i]) for j in range(len(v)))]
    assert list(pareto_front(v)) == brute


def test_weighted_objective_needs_a_positive_error_weight():
    with pytest.raises(ParameterError, match=r"weights\.error"):
        Objective(kind="weighted", weights={"error": 0.0, "peak_torque": 1.0})
