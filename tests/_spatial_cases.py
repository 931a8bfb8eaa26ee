"""The loom four-bar of paper 004 built in the planar engine with its spatial data (joint
eccentricities, heights, stiffnesses, deviations, tolerances), shared by the spatial-reaction
tests."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from linkwork import redundancy as rd
from linkwork.cli.reactions import load_problem
from linkwork.planar import BodyTorque, kinematics

ROOT = Path(__file__).resolve().parents[1]


EXAMPLE = ROOT / "examples" / "loom_fourbar_spatial.toml"


G = (0.0, -9.81)


def loom():
    mech, _, _ = load_problem(EXAMPLE)
    return mech


def loads_ext(phi):
    return [BodyTorque("rocker", 4.0 + 0 * phi)]


JOINTS = {"O": dict(e=0.03, z=0.0), "A": dict(e=0.02, z=0.03), "B": dict(e=0.04, z=0.03),
          "C": dict(e=0.025, z=-0.03)}


HEIGHTS = {"crank": 0.0, "coupler": 0.03, "rocker": 0.01}


DEVS = [rd.Deviation("C", "frame", tx=2e-4, ty=-1e-4), rd.Deviation("A", "crank", ty=-1e-4,
                                                                     dz=1e-5),
        rd.Deviation("B", "rocker", dz=2e-5, tx=5e-5), rd.Deviation("O", "crank", dx=1e-5)]


PHI = np.radians(np.arange(0.0, 360.0, 15.0))


def spatial(mech=None, joints=JOINTS, devs=DEVS, method="force", oop=(), phi=PHI, **kw):
    mech = mech or loom()
    return rd.spatial_reactions(mech, phi, gravity=G, loads=loads_ext(phi), joints=joints,
                                heights=HEIGHTS, deviations=devs, method=method,
                                out_of_plane=oop, **kw)


def _problem(nphi=36):
    mech = loom()
    phi = np.linspace(0, 2 * np.pi, nphi, endpoint=False)
    kin = kinematics(mech, phi)
    model = rd.spatial_model(mech, JOINTS)
    geom = rd.geometry(mech, kin)
    w = rd.body_wrenches(mech, kin, gravity=G, loads=loads_ext(phi), heights=HEIGHTS)
    return model, geom, w


TOLS = [rd.Tolerance("C", "a", "tx", 3e-4), rd.Tolerance("O", "a", "ty", 3e-4),
        rd.Tolerance("B", "b", "dz", 3e-5, "uniform"), rd.Tolerance("A", "a", "tx", 2e-4,
                                                                    mean=1e-4)]
