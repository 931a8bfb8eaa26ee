"""Paper 001's four-bar (its data and printed table), centre-of-mass positions and the least-
squares normal equations of the moved counterweight axis, written out independently of
``linkwork.balancing`` and shared by the balancing tests."""

from __future__ import annotations

import numpy as np

from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import fourbar_mechanism

# paper 001's example: OA 0.1, AB 0.3, BC 0.2, OC 0.3 m; centres at mid-links; m 1, 3, 2 kg
PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)


def paper_fourbar(branch=1, eps1=0.0):
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=branch, eps1=eps1, **PAPER)


def com_positions(mech, phi):
    """(b, n, 2) positions of the centres of mass from the engine (positions only)."""
    kin = kinematics(mech, phi)
    return np.stack([np.stack([kin.point(b.name, "com").x, kin.point(b.name, "com").y], -1)
                     for b in mech.bodies]), kin


def normal_equations(phi, M, S, w):
    """The paper's two normal equations, written out (with the sin*cos sums kept)."""
    s, c = np.sin(phi), np.cos(phi)
    A = S * w**2 * np.array([[-np.sum(s * c), np.sum(c * c)],
                             [-np.sum(s * s), np.sum(s * c)]])
    b = np.array([-np.sum(M * c), -np.sum(M * s)])
    return np.linalg.lstsq(A, b, rcond=None)[0]
