"""The engine against every closed form over whole cycles, both branches, to 1e-9.

Closed forms: ``linkwork.models.fourbar.fourbar`` (Norton), ``linkwork.models.crank_slider.
offset_crank_slider`` and ``linkwork.models.sine.inclined_slot`` (paper 000).
"""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.models.crank_slider import offset_crank_slider
from linkwork.models.fourbar import fourbar as fourbar_cf
from linkwork.models.sine import inclined_slot
from linkwork.planar import Body, Crank, Mechanism, PinInSlot, Prismatic, Revolute, bar, kinematics
from linkwork.planar import crank_slider_mechanism as cs_engine
from linkwork.planar import fourbar_mechanism as fb_engine

PHI = np.linspace(0.0, 2 * np.pi, 721)


def _wrap(x):
    return np.angle(np.exp(1j * x))


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("dims", [(0.1, 0.3, 0.2, 0.3), (0.04, 0.12, 0.1, 0.11),
                                  (0.3, 0.25, 0.28, 0.1)])
def test_engine_vs_fourbar_closed_form(dims, branch):
    """Reference: the closed-form four-bar ``linkwork.models.fourbar.fourbar`` over a whole
    cycle. Tolerance: angles 1e-9 rad, rates 1e-9 of their peak, points B 1e-12 m."""
    a, b, c, d = dims
    w, e = 7.0, -3.0
    cf = fourbar_cf(PHI, a, b, c, d, omega1=w, eps1=e, branch=branch, on_failure="nan")
    k = kinematics(fb_engine(a, b, c, d, branch=branch), PHI, omega1=w, eps1=e, on_failure="nan")
    np.testing.assert_array_equal(k.valid, cf.valid)
    ok = k.valid
    assert ok.sum() > 100
    np.testing.assert_allclose(_wrap(k.angle("coupler") - cf.theta3)[ok], 0, atol=1e-9)
    np.testing.assert_allclose(_wrap(k.angle("rocker") - cf.theta4)[ok], 0, atol=1e-9)
    scale_w = np.nanmax(np.abs(cf.omega3)) + np.nanmax(np.abs(cf.omega4))
    np.testing.assert_allclose(k.omega[2][ok], cf.omega3[ok], atol=1e-9 * scale_w)
    np.testing.assert_allclose(k.omega[3][ok], cf.omega4[ok], atol=1e-9 * scale_w)
    scale_e = np.nanmax(np.abs(cf.eps3)) + np.nanmax(np.abs(cf.eps4))
    np.testing.assert_allclose(k.eps[2][ok], cf.eps3[ok], atol=1e-9 * scale_e)
    np.testing.assert_allclose(k.eps[3][ok], cf.eps4[ok], atol=1e-9 * scale_e)
    B = k.point("rocker", "B")
    np.testing.assert_allclose(B.x[ok], cf.xB[ok], atol=1e-12)
    np.testing.assert_allclose(B.y[ok], cf.yB[ok], atol=1e-12)


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("lam2, lam_e", [(4.0, 0.5), (3.0, -1.2), (2.5, 0.0)])
def test_engine_vs_paper000_offset_crank_slider(lam2, lam_e, branch):
    """Reference: paper 000's closed form ``offset_crank_slider`` over a whole cycle.
    Tolerance: 1e-9 L1 for positions, 1e-9 of the peak for rates, 1e-9 rad for angles."""
    L1, w, e = 0.05, 12.0, 5.0
    cf = offset_crank_slider(PHI, L1, lam2, lam_e, omega1=w, eps1=e, branch=branch)
    # paper 000: guide along +Y at X = e; engine guide angle 90 deg through (-e', 0) -> e' = -e
    mech = cs_engine(L1, lam2 * L1, -lam_e * L1, guide_angle=np.pi / 2, branch=branch)
    k = kinematics(mech, PHI, omega1=w, eps1=e)
    C = k.point("slider", "B")
    np.testing.assert_allclose(C.x, lam_e * L1, atol=1e-15)
    np.testing.assert_allclose(C.y, cf.Y_C, atol=1e-9 * L1)
    np.testing.assert_allclose(C.vy, cf.V_C, atol=1e-9 * np.max(np.abs(cf.V_C)))
    np.testing.assert_allclose(C.ay, cf.a_C, atol=1e-9 * np.max(np.abs(cf.a_C)))
    # rod angle: paper's phi2 from +Y towards +X; the engine's rod x-axis is at pi/2 - phi2
    np.testing.assert_allclose(_wrap(k.angle("rod") - (np.pi / 2 - cf.phi2)), 0, atol=1e-9)
    np.testing.assert_allclose(-k.omega[2], cf.omega2, atol=1e-9 * np.max(np.abs(cf.omega2)))
    np.testing.assert_allclose(-k.eps[2], cf.eps2, atol=1e-9 * np.max(np.abs(cf.eps2)))


def _sine_engine(L1, alpha):
    frame = Body("frame", {"A": (0.0, 0.0)})
    crank = bar("crank", "A", "B", L1)
    ram = Body("ram", {"S": (0.0, 0.0)})
    joints = (Revolute("A", "frame", "crank"),
              Prismatic("guide", "frame", "ram", angle=0.0, through=(0.0, 0.0), point="S"),
              PinInSlot("slot", "ram", "crank", angle=alpha, through="S", point="B"))
    return Mechanism(frame, (crank, ram), joints, Crank("A"))


@pytest.mark.parametrize("alpha_deg", [30.0, 60.0, 90.0, 135.0])
def test_engine_vs_paper000_inclined_slot(alpha_deg):
    """Reference: paper 000's closed form ``inclined_slot`` over a whole cycle. Tolerance:
    1e-9 L1 for positions, 1e-9 of the peak for velocities and accelerations."""
    L1, w, e = 0.05, 12.566, 4.0
    alpha = np.radians(alpha_deg)
    cf = inclined_slot(PHI, L1, alpha, omega1=w, eps1=e)
    k = kinematics(_sine_engine(L1, alpha), PHI, omega1=w, eps1=e)
    assert [g.kind for g in k.mechanism.structure.groups] == ["driver", "PS"]
    S = k.point("ram", "S")
    # X3: displacement from the phi1 = 0 position towards the crank axis (-x)
    np.testing.assert_allclose(L1 - S.x, cf.X3, atol=1e-9 * L1)
    np.testing.assert_allclose(-S.vx, cf.V3, atol=1e-9 * np.max(np.abs(cf.V3)))
    np.testing.assert_allclose(-S.ax, cf.a3, atol=1e-9 * np.max(np.abs(cf.a3)))
    s, sd, sdd = k.slide("slot")
    np.testing.assert_allclose(s, cf.X32, atol=1e-9 * L1)
    np.testing.assert_allclose(sd, cf.V32, atol=1e-9 * np.max(np.abs(cf.V32)))
    np.testing.assert_allclose(sdd, cf.a32, atol=1e-9 * np.max(np.abs(cf.a32)))
