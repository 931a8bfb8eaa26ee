"""Gear pairs (linkwork.planar.GearPair): kinematics, the tooth force along the line of
action, the mesh efficiency.

References: the gear ratio (omega_b - omega_c = -s k (omega_a - omega_c), Willis' formula for a
planet in a fixed ring); a pair of massless gears in hand equilibrium (Q = k M, F_t = M / r_b,
|R| = F_t / cos(alpha)); the independent Newton-Euler equations with Lagrange multipliers of
``tests/_planar_newton_euler.py`` (the tooth force a multiplier at the pitch point, the
separating force added and the system solved again: tolerance 1e-6 relative, floor 1e-9 of the
scale); power balances with the mesh loss (1e-9 of the largest term) and the efficiency as the
ratio of the powers the gears exchange through the mesh (1e-9).
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from _mechanisms import planetary
from _planar_newton_euler import _check_engine, energy_rate

from linkwork import io
from linkwork.errors import AssemblyError, ParameterError
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    GearPair,
    Mechanism,
    PointForce,
    Revolute,
    inverse_dynamics,
    kinematics,
    sketch,
)
from linkwork.studies import planar as study


def geared_five_bar(efficiency=1.0, alpha=20.0):
    """Two meshing gears on frame pivots 160 mm apart (30 and 50 teeth: r = 60, 100 mm), each
    with a crank pin, and two couplers to the pin P: mobility 1."""
    pts = {"O1": (0.0, 0.0), "O2": (0.16, 0.0), "A": (0.025, 0.0433), "B": (0.148, 0.069),
           "P": (0.09, 0.24)}
    return sketch(pts, {"g1": ["O1", "A"], "g2": ["O2", "B"], "l1": ["A", "P"],
                        "l2": ["B", "P"]}, ground=["O1", "O2"], drivers="O1",
                  gears={"G": {"a": "g1", "b": "g2", "teeth": (30, 50),
                               "pressure_angle": math.radians(alpha),
                               "efficiency": efficiency}},
                  masses={"g1": {"mass": 1.2, "inertia": 0.004},
                          "g2": {"mass": 2.0, "inertia": 0.011}, "l1": 0.5, "l2": 0.6})


def test_ratio_of_an_external_pair():
    """omega_2 = -(z1/z2) omega_1 and eps likewise, at every position."""
    mech = geared_five_bar()
    phi = mech.drawing.positions[0] + np.linspace(0, 2 * np.pi, 37)
    kin = kinematics(mech, phi, 7.0, 2.0)
    i1, i2 = mech.index["g1"], mech.index["g2"]
    assert np.max(np.abs(kin.omega[i2] + 0.6 * kin.omega[i1])) <= 1e-12
    assert np.max(np.abs(kin.eps[i2] + 0.6 * kin.eps[i1])) <= 1e-12
    turned = np.unwrap(kin.theta[i2]) - kin.theta[i2, 0]
    assert np.max(np.abs(turned + 0.6 * (phi - phi[0]))) <= 1e-12
    assert [g.kind for g in mech.structure.groups] == ["driver", "RG", "RRR"]


def test_planet_in_a_fixed_ring_follows_willis():
    """omega_planet = omega_arm (1 - R / r) = -2 omega_arm; the planet's point T rolls on the
    ring (its distance from O never exceeds R, and equals R once per planet turn)."""
    mech = planetary()
    phi = np.linspace(0, 2 * np.pi, 61)
    kin = kinematics(mech, phi, 5.0, 1.5)
    assert np.max(np.abs(kin.omega[2] - 5.0 * (1 - 3.0))) <= 1e-12
    assert np.max(np.abs(kin.eps[2] - 1.5 * (1 - 3.0))) <= 1e-12
    T = kin.point("planet", "T")
    r = np.hypot(T.x, T.y)
    assert r.max() <= 0.09 + 1e-12
    assert r.max() == pytest.approx(0.09, abs=1e-12)  # T on the ring where it touches it


def test_massless_pair_in_hand_equilibrium():
    """Two massless gears (r_a = 40, r_b = 80 mm, alpha = 20 deg) with a 10 N m load on b:
    Q = k M = 5 N m, the tangential tooth force M / r_b = 125 N, |R| = 125 / cos(20 deg), and
    the force's radial part pushes b away from a."""
    frame = Body("frame", {"Oa": (0.0, 0.0), "Ob": (0.12, 0.0)})
    ga = Body("ga", {"Oa": (0.0, 0.0)})
    gb = Body("gb", {"Ob": (0.0, 0.0)})
    mech = Mechanism(frame, (ga, gb), (Revolute("Oa", "frame", "ga"),
                                       Revolute("Ob", "frame", "gb"),
                                       GearPair("G", "ga", "gb", radii=(0.04, 0.08))),
                     Crank("Oa"))
    kin = kinematics(mech, np.linspace(0.3, 2.0, 5), 3.0)
    dyn = inverse_dynamics(kin, loads=[BodyTorque("gb", 10.0)])
    # b turns clockwise (w_b = -w_a / 2) against the load: Q w_a = -M w_b, Q = M / 2
    assert np.allclose(dyn.Q, 0.5 * 10.0, rtol=1e-13)
    fx, fy = dyn.reaction("G")
    ft = fy  # the tangent at P = (40 mm, 0) is +y
    assert np.allclose(ft, 10.0 / 0.08, rtol=1e-13)  # its moment -r_b F_t balances the load
    assert np.allclose(np.hypot(fx, fy), 125.0 / math.cos(math.radians(20)), rtol=1e-13)
    assert np.all(fx > 0)  # along O_a -> O_b: pushes b away from a
    assert np.allclose(dyn.px[2], 0.04) and np.allclose(dyn.py[2], 0.0)
    # the pivots carry the tooth force: frame on b equals minus the tooth force
    fbx, fby = dyn.reaction("Ob")
    assert np.allclose(fbx, -fx, rtol=1e-13) and np.allclose(fby, -fy, rtol=1e-13)


@pytest.mark.parametrize(("build", "phi", "label"), [
    (geared_five_bar, None, "geared five-bar "),
    (planetary, np.linspace(0.2, 5.5, 7), "planetary "),
])
def test_gears_against_newton_euler(build, phi, label):
    """Poses, rates, every reaction (the tooth force along the line of action), Q, shaking and
    kinetic energy against the independent reference, gravity and loads on."""
    mech = build()
    if phi is None:
        phi = mech.drawing.positions[0] + np.linspace(0.0, 5.8, 7)
    body = mech.bodies[-1].name
    loads = [PointForce(body, "com", fx=4.0, fy=-9.0), BodyTorque(mech.bodies[1].name, -0.7)]
    _check_engine(mech, phi, 9.0, 25.0, (0.0, -9.81), loads, label=label)


def test_mesh_efficiency_is_the_ratio_of_the_mesh_powers():
    """With eta = 0.9 the power gear b receives through the mesh is 0.9 of what gear a gives
    where a drives (and the other way round where b drives), and the drivers' power balances
    the kinetic energy, gravity and the friction loss (each >= 0) to 1e-9."""
    mech = geared_five_bar(efficiency=0.9)
    n = 121
    phi = mech.drawing.positions[0] + np.linspace(0.0, 2 * np.pi, n)
    kin = kinematics(mech, phi, 12.0, 0.0)
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81),
                           loads=[BodyTorque("g2", 1.0)])
    assert not dyn.locked.any()
    k = mech.joints.index(mech.joint("G"))
    i1, i2 = mech.index["g1"], mech.index["g2"]
    fx, fy, mz = dyn.fx[k], dyn.fy[k], dyn.mz[k]
    px, py = dyn.px[k], dyn.py[k]

    def point_velocity(i):  # velocity of body i's material point at P
        return (kin.vx[i] - kin.omega[i] * (py - kin.y[i]),
                kin.vy[i] + kin.omega[i] * (px - kin.x[i]))

    vb, va = point_velocity(i2), point_velocity(i1)
    received_b = fx * vb[0] + fy * vb[1] + mz * kin.omega[i2]
    given_a = fx * va[0] + fy * va[1] + mz * kin.omega[i1]
    scale = float(np.max(np.abs(given_a)))
    a_drives = given_a > 1e-6 * scale
    b_drives = received_b < -1e-6 * scale
    assert a_drives.any() and b_drives.any()
    assert np.max(np.abs(received_b[a_drives] - 0.9 * given_a[a_drives])) <= 1e-9 * scale
    # b drives: a receives -given_a, b gives -received_b, and the first is 0.9 of the second
    assert np.max(np.abs(given_a[b_drives] - 0.9 * received_b[b_drives])) <= 1e-9 * scale
    loss = dyn.friction_power[k]
    assert np.all(loss >= -1e-12 * scale)
    assert np.max(np.abs(loss - (given_a - received_b))) <= 1e-9 * scale
    dT, p_g = energy_rate(mech, kin, (0.0, -9.81))
    p_load = 1.0 * kin.omega[i2]
    tot = dyn.total_power - (dT - p_g - p_load + np.sum(dyn.friction_power, axis=0))
    assert np.max(np.abs(tot)) <= 1e-9 * float(np.max(np.abs(dyn.power)))


def test_gear_errors():
    pts = {"O1": (0.0, 0.0), "O2": (0.16, 0.0), "A": (0.025, 0.0433), "B": (0.148, 0.069),
           "P": (0.09, 0.24)}
    links = {"g1": ["O1", "A"], "g2": ["O2", "B"], "l1": ["A", "P"], "l2": ["B", "P"]}
    with pytest.raises(AssemblyError, match=r"joint G: the gears are not assembled: their "
                       r"centres are 160 mm apart .* need 150 mm"):
        sketch(pts, links, ground=["O1", "O2"], drivers="O1",
               gears={"G": {"a": "g1", "b": "g2", "radii": (0.05, 0.1)}})
    with pytest.raises(ParameterError, match="either by teeth"):
        GearPair("G", "a", "b")
    with pytest.raises(ParameterError, match=r"ring .b. must be larger"):
        GearPair("G", "a", "b", teeth=(60, 20), internal=True)
    with pytest.raises(ParameterError, match=r"efficiency = 1\.2"):
        GearPair("G", "a", "b", teeth=(20, 30), efficiency=1.2)
    with pytest.raises(ParameterError, match="must be hinged to the carrier"):
        sketch(pts, links, ground=["O1", "O2"], drivers="O1",
               gears={"G": {"a": "g1", "b": "l1", "teeth": (20, 30)}})


def test_geared_five_bar_example_is_the_drawn_mechanism():
    """examples/geared_five_bar.toml ([sketch.gears]) and the same gear pair as a [[joint]]
    of type 'gear' in body frames give the engine's numbers for the drawing built here."""
    doc = io.load(Path(__file__).resolve().parents[2] / "examples" / "geared_five_bar.toml")
    mech = doc.mechanism()
    ref = geared_five_bar(efficiency=0.98)
    phi = doc.positions()[::60]
    k1 = kinematics(mech, phi, 4 * np.pi)
    k2 = kinematics(ref, phi, 4 * np.pi)
    assert np.max(np.abs(k1.omega[1:] - k2.omega[1:])) <= 1e-12 * 4 * np.pi
    s = study.analyze(doc)
    assert s.structure.formula() == "I(gear1) -> II RG(gear2) -> II RRR(coupler1, coupler2)"
    assert s.friction is not None and 0.9 < s.friction["efficiency_cycle"] < 1.0
    # the same pair written as a [[joint]]: the phase (offset) the sketch took from the drawing
    g = mech.joint("G")
    text = f"""type = "planar"
[frame]
points = {{ O1 = [0, 0], O2 = [0.16, 0] }}
[[body]]
name = "ga"
points = {{ O1 = [0, 0] }}
[[body]]
name = "gb"
points = {{ O2 = [0, 0] }}
[[joint]]
name = "O1"
type = "revolute"
a = "frame"
b = "ga"
[[joint]]
name = "O2"
type = "revolute"
a = "frame"
b = "gb"
[[joint]]
name = "G"
type = "gear"
a = "ga"
b = "gb"
teeth = [30, 50]
offset = {g.offset!r}
efficiency = 0.98
[driver]
joint = "O1"
"""
    with tempfile.TemporaryDirectory() as tmp:
        p = Path(tmp) / "pair.toml"
        p.write_text(text)
        pair = io.load(p).mechanism()
    assert isinstance(pair.joint("G"), GearPair) and pair.joint("G").offset == g.offset
    kp = kinematics(pair, [0.3], 2.0)
    assert kp.omega[2, 0] == pytest.approx(-1.2, abs=1e-14)


@pytest.mark.parametrize("build", [planetary, geared_five_bar])
def test_gear_groups_by_newton_equal_the_closed_form(build):
    """The gear groups (RG) handed to the engine's Newton solver instead (their angle rows with
    the carrier's column in the group Jacobian and in the known rates): the same poses, rates
    and driving torque to 1e-9."""
    mech = build()
    plan = mech.plan
    groups = tuple(dataclasses.replace(g, kind="newton") if g.kind == "RG" else g
                   for g in plan.groups)
    other = dataclasses.replace(mech)
    other.__dict__["plan"] = dataclasses.replace(plan, groups=groups, newton=True)
    start = mech.drawing.positions[0] if mech.drawing is not None else 0.0
    phi = start + np.linspace(0.0, 2 * np.pi, 25)
    k1, k2 = kinematics(mech, phi, 6.0, 2.0), kinematics(other, phi, 6.0, 2.0)
    for f in ("x", "y", "theta", "vx", "omega", "ax", "eps"):
        assert np.max(np.abs(getattr(k1, f) - getattr(k2, f))) <= 1e-9 * 10, f
    d1, d2 = inverse_dynamics(k1), inverse_dynamics(k2)
    assert np.max(np.abs(d1.Q - d2.Q)) <= 1e-9 * np.max(np.abs(d1.Q))
