"""Mechanisms travel between processes (Dask workers, multiprocessing): a Mechanism, its
bodies and its drawing pickle as their constructor's arguments, and the copy analyses to the
same numbers bit for bit (the structure and compiled plan are worked out again there)."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest
from _mechanisms import BUILDERS, with_friction

from linkwork import io
from linkwork.planar import Mechanism, fourbar_mechanism, inverse_dynamics, kinematics

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PLANAR = sorted(p.name for p in EXAMPLES.glob("*.toml")
                if getattr(io.load(p), "mechanism", None) is not None)


def _same_analysis(a: Mechanism, b: Mechanism, phi: np.ndarray) -> None:
    ka, kb = kinematics(a, phi, on_failure="nan"), kinematics(b, phi, on_failure="nan")
    for key in ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps", "valid"):
        np.testing.assert_array_equal(getattr(ka, key), getattr(kb, key), err_msg=key)
    da, db = inverse_dynamics(ka), inverse_dynamics(kb)
    for key in ("fx", "fy", "mz", "Q", "shaking_fx", "shaking_m"):
        np.testing.assert_array_equal(getattr(da, key), getattr(db, key), err_msg=key)


@pytest.mark.parametrize("name", PLANAR)
def test_every_planar_example_pickles_and_analyses_the_same(name: str) -> None:
    mech = io.load(EXAMPLES / name).mechanism()
    mech.plan  # noqa: B018  (cached: the copy must work it out again)
    copy = pickle.loads(pickle.dumps(mech))
    assert copy == mech and copy is not mech
    q = np.linspace(0.2, 1.0, 7) if mech.n_drivers == 1 else None
    if q is not None:
        _same_analysis(mech, copy, q)


@pytest.mark.parametrize("build", BUILDERS, ids=lambda b: b.__name__)
def test_every_group_kind_pickles(build) -> None:  # type: ignore[no-untyped-def]
    mech, phi, _ = build()
    copy = pickle.loads(pickle.dumps(mech))
    assert copy == mech
    _same_analysis(mech, copy, phi)


def test_friction_and_a_batch_of_designs_pickle() -> None:
    """Joint friction and design values given as arrays over m designs survive the trip."""
    fr = with_friction(BUILDERS[0]()[0])
    assert pickle.loads(pickle.dumps(fr)) == fr
    batch = fourbar_mechanism(np.array([0.1, 0.11]), 0.3, 0.2, 0.3, omega1=10.0)
    copy = pickle.loads(pickle.dumps(batch))
    assert copy.n_designs == 2
    q = np.linspace(0.0, 6.0, 9)
    np.testing.assert_array_equal(kinematics(copy, q).theta, kinematics(batch, q).theta)
