"""Checks of the independent four-bar reference of ``tests/_fourbar_reference.py`` itself: loop
closure, finite differences of its rates, its power balance."""

from __future__ import annotations

import numpy as np
from _fourbar_reference import L2, L3, OMEGA1, kinematics, loads, planar_reactions


def test_reference_loop_closure():
    """Reference: the independent four-bar of tests/_fourbar_reference.py. Tolerance:
    atol=1e-12."""
    phi = np.linspace(0, 2 * np.pi, 37)
    k = kinematics(phi)
    assert np.allclose(np.linalg.norm(k["B"] - k["A"], axis=-1), L2, atol=1e-12)
    assert np.allclose(np.linalg.norm(k["B"] - k["C"], axis=-1), L3, atol=1e-12)


def test_reference_velocities_and_accelerations_by_finite_differences():
    """Reference: the independent four-bar of tests/_fourbar_reference.py; central finite
    differences. Tolerance: rtol=1e-7, atol=1e-7, rtol=1e-6, atol=1e-5."""
    phi = np.linspace(0.1, 6.0, 25)
    h = 1e-5
    kp, km, k0 = kinematics(phi + h), kinematics(phi - h), kinematics(phi)
    dphi = (np.unwrap(np.stack([km["phi"], kp["phi"]]), axis=0)[1]
            - np.unwrap(np.stack([km["phi"], kp["phi"]]), axis=0)[0]) / (2 * h)
    assert np.allclose(dphi * OMEGA1, k0["omega"], rtol=1e-7, atol=1e-7)
    dw = (kp["omega"] - km["omega"]) / (2 * h)
    assert np.allclose(dw * OMEGA1, k0["eps"], rtol=1e-6, atol=1e-5)


def test_reference_power_balance():
    """Q omega1 + power of all loads = 0 (the reactions do no work in a rigid mechanism)."""
    phi = np.linspace(0, 2 * np.pi, 19)
    _, q = planar_reactions(phi)
    k = kinematics(phi)
    _, forces, moments = loads(phi)
    # velocities of centres by finite differences of positions
    h = 1e-6
    cp, _, _ = loads(phi + h)
    cm, _, _ = loads(phi - h)
    v = (cp - cm) / (2 * h) * OMEGA1
    power = np.sum(forces * v, axis=(1, 2)) + np.sum(moments * k["omega"], axis=1)
    assert np.allclose(q * OMEGA1 + power, 0.0, atol=1e-6 * np.max(np.abs(q * OMEGA1)))
