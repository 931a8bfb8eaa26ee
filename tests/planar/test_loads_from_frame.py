"""Loads that come from the frame (a press's workpiece on the bed): they load the bearings and
the driver but cancel in the shaking force and moment, by the equilibrium of the whole machine."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from linkwork import files
from linkwork.errors import FileFormatError, ParameterError
from linkwork.planar import (
    BodyTorque,
    PointForce,
    crank_slider_mechanism,
    inverse_dynamics,
    kinematics,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
G = (1.5, -9.81)
ABOUT = (0.03, -0.07)


def _press():
    mech = crank_slider_mechanism(0.05, 0.2, 0.01, guide_angle=-np.pi / 2, masses=(1.2, 2.5, 8.0),
                        omega1=15.0, eps1=4.0)
    phi = np.linspace(0.0, 2 * np.pi, 73)
    return mech, kinematics(mech, phi)


def _loads(n, from_frame):
    press = -3000.0 * (1 + 0.5 * np.sin(np.linspace(0, 3, n)))    # on the ram, per position
    return [PointForce("slider", "com", 200.0, press, from_frame=from_frame),
            PointForce("rod", (0.05, 0.01), -40.0, 25.0),               # from outside
            BodyTorque("rod", 7.5, from_frame=from_frame)]


def test_from_frame_loads_cancel_in_the_shaking_loads_by_whole_machine_equilibrium():
    """F_sh = sum of the outside loads + sum m (g - a_C); M_sh about ABOUT likewise, with the
    inertia couples -I eps: written out from the motion, not from the reaction solver."""
    mech, kin = _press()
    dyn = inverse_dynamics(kin, gravity=G, loads=_loads(kin.n, True), about=ABOUT)
    fx = np.full(kin.n, -40.0)
    fy = np.full(kin.n, 25.0)
    p = kin.point("rod", (0.05, 0.01))
    m = (p.x - ABOUT[0]) * 25.0 - (p.y - ABOUT[1]) * (-40.0)
    for b in mech.bodies:
        c = kin.point(b.name, "com")
        gx, gy = b.mass * (G[0] - c.ax), b.mass * (G[1] - c.ay)
        fx, fy = fx + gx, fy + gy
        m = m + (c.x - ABOUT[0]) * gy - (c.y - ABOUT[1]) * gx - b.inertia * kin.eps[
            mech.index[b.name]]
    scale = 3000.0
    assert np.max(np.abs(dyn.shaking_fx - fx)) < 1e-9 * scale
    assert np.max(np.abs(dyn.shaking_fy - fy)) < 1e-9 * scale
    assert np.max(np.abs(dyn.shaking_m - m)) < 1e-9 * scale * 0.25


def test_from_frame_changes_nothing_but_the_shaking_loads():
    """The flag says where the load's reaction goes, not what the mechanism carries: every joint
    reaction and the driving torque are the same; the shaking loads differ by the loads."""
    _, kin = _press()
    outside = inverse_dynamics(kin, gravity=G, loads=_loads(kin.n, False), about=ABOUT)
    frame = inverse_dynamics(kin, gravity=G, loads=_loads(kin.n, True), about=ABOUT)
    for name in ("fx", "fy", "mz", "Q"):
        np.testing.assert_array_equal(getattr(outside, name), getattr(frame, name))
    press = _loads(kin.n, True)[0]
    np.testing.assert_allclose(outside.shaking_fy - frame.shaking_fy, press.fy, rtol=1e-12)
    np.testing.assert_allclose(outside.shaking_fx - frame.shaking_fx, 200.0, rtol=1e-12)


def test_from_frame_must_be_a_bool():
    _, kin = _press()
    with pytest.raises(ParameterError, match="from_frame"):
        inverse_dynamics(kin, loads=[PointForce("slider", fy=-1.0, from_frame="yes please")])


def test_file_key_from_frame(tmp_path):
    text = (EXAMPLES / "fourbar_paper001.toml").read_text()
    load = ('\n[[load]]\ntype = "force"\nbody = "rocker"\npoint = "com"\nfy = "-50 N"\n'
            'from_frame = true\n')
    f = tmp_path / "ff.toml"
    f.write_text(text + load)
    doc = files.load(f)
    (ld,) = [x for x in doc.loads(np.array([0.0, 1.0])) if x.body == "rocker" and x.from_frame]
    np.testing.assert_allclose(ld.fy, -50.0)
    f.write_text(text + load.replace("true", '"sometimes"'))
    with pytest.raises(FileFormatError, match="from_frame"):
        files.load(f)
