"""Every group kind of the planar engine: closure, finite differences, balances, branches.

Each mechanism is checked against its own joint definitions written out here (coincident
points with equal velocities and accelerations, points on lines, constant relative angles),
against central differences of the positions, and with the power and momentum balances.
"""

from __future__ import annotations

import numpy as np
import pytest
from _mechanisms import BUILDERS, m_linear_driver, m_ps_sine, m_rpr, m_rs_pin_in_known_slot
from _planar_newton_euler import _check_engine

from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Mechanism,
    PointForce,
    Prismatic,
    Revolute,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)


def _check_joints(kin, tol=1e-12):
    """Every joint's constraint, at position, velocity and acceleration level, written out."""
    m = kin.mechanism
    for j in m.joints:
        qa, pb, ang = m.joint_geometry(j)
        Pa, Pb = kin.point(j.a, qa), kin.point(j.b, pb)
        ta = kin.angle(j.a)
        if isinstance(j, Revolute):
            for f in ("x", "y"):
                np.testing.assert_allclose(getattr(Pa, f), getattr(Pb, f), atol=tol)
            scale_v = 1 + np.max(np.abs(Pa.vx))
            np.testing.assert_allclose(Pa.vx, Pb.vx, atol=tol * 10 * scale_v)
            np.testing.assert_allclose(Pa.vy, Pb.vy, atol=tol * 10 * scale_v)
            scale_a = 1 + np.max(np.abs(Pa.ax))
            np.testing.assert_allclose(Pa.ax, Pb.ax, atol=tol * 100 * scale_a)
            np.testing.assert_allclose(Pa.ay, Pb.ay, atol=tol * 100 * scale_a)
        else:
            nx, ny = -np.sin(ta + ang), np.cos(ta + ang)
            np.testing.assert_allclose(nx * (Pb.x - Pa.x) + ny * (Pb.y - Pa.y), 0, atol=tol)
            if isinstance(j, Prismatic):
                np.testing.assert_allclose(kin.angle(j.b) - ta, j.rel_angle, atol=tol)


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda f: f.__name__)
def test_group_kind_and_closure(builder):
    mech, phi, kind = builder()
    kinds = [g.kind for g in mech.structure.groups]
    assert kinds[0] == "driver" and kinds[-1] == kind
    for branch in (1, -1):
        if kind == "newton":
            kin = kinematics(mech, phi, omega1=3.0, eps1=1.5)
        else:
            key = mech.structure.groups[-1].key
            kin = kinematics(mech, phi, omega1=3.0, eps1=1.5, branches={key: branch})
        _check_joints(kin)


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda f: f.__name__)
def test_group_finite_differences(builder):
    mech, phi, kind = builder()
    w, e = 2.0, -1.3
    h = 1e-5 if kind != "newton" else 1e-4
    k = kinematics(mech, phi, omega1=w, eps1=e)
    kp = kinematics(mech, phi + h, omega1=w, eps1=e)
    km = kinematics(mech, phi - h, omega1=w, eps1=e)
    for name, vel, acc in (("x", k.vx, k.ax), ("y", k.vy, k.ay), ("theta", k.omega, k.eps)):
        dp = getattr(kp, name) - getattr(k, name)
        dm = getattr(km, name) - getattr(k, name)
        if name == "theta":  # angles may wrap by 2 pi between neighbouring positions
            dp, dm = np.angle(np.exp(1j * dp)), np.angle(np.exp(1j * dm))
        d1 = (dp - dm) / (2 * h)
        d2 = (dp + dm) / h**2
        np.testing.assert_allclose(vel, d1 * w, atol=1e-7 * (1 + np.max(np.abs(vel))))
        np.testing.assert_allclose(acc, d2 * w * w + d1 * e,
                                   atol=2e-4 * (1 + np.max(np.abs(acc))))


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda f: f.__name__)
def test_group_power_and_momentum(builder):
    mech, phi, _ = builder()
    g = (0.7, -9.81)
    body = mech.bodies[-1].name
    loads = [PointForce(body, "com", 5.0 * np.sin(phi), -3.0), BodyTorque(body, 0.8)]
    k = kinematics(mech, phi, omega1=4.0, eps1=2.0)
    d = inverse_dynamics(k, gravity=g, loads=loads, about=(0.1, 0.2))
    dT, P = np.zeros(k.n), np.zeros(k.n)
    Fx, Fy, M, px, py, dH = (np.zeros(k.n) for _ in range(6))
    for b in mech.bodies:
        i = mech.index[b.name]
        c = k.point(b.name, "com")
        dT += b.mass * (c.vx * c.ax + c.vy * c.ay) + b.inertia * k.omega[i] * k.eps[i]
        P += b.mass * (g[0] * c.vx + g[1] * c.vy)
        Fx += b.mass * g[0]
        Fy += b.mass * g[1]
        M += (c.x - 0.1) * b.mass * g[1] - (c.y - 0.2) * b.mass * g[0]
        px += b.mass * c.ax
        py += b.mass * c.ay
        dH += (c.x - 0.1) * b.mass * c.ay - (c.y - 0.2) * b.mass * c.ax + b.inertia * k.eps[i]
    c = k.point(body, "com")
    fx = 5.0 * np.sin(phi)
    P += fx * c.vx - 3.0 * c.vy + 0.8 * k.omega[mech.index[body]]
    Fx += fx
    Fy += -3.0
    M += (c.x - 0.1) * -3.0 - (c.y - 0.2) * fx + 0.8
    s = np.max(np.abs(dT)) + np.max(np.abs(P))
    np.testing.assert_allclose(d.Q * k.omega1, dT - P, atol=1e-9 * s)
    fs = np.max(np.abs(Fx)) + np.max(np.abs(Fy)) + np.max(np.abs(px)) + np.max(np.abs(py))
    np.testing.assert_allclose(d.shaking_fx, Fx - px, atol=1e-9 * fs)
    np.testing.assert_allclose(d.shaking_fy, Fy - py, atol=1e-9 * fs)
    ms = np.max(np.abs(M)) + np.max(np.abs(dH))
    np.testing.assert_allclose(d.shaking_m, M - dH, atol=1e-9 * ms)


def test_branch_definitions_rpr_and_slot():
    """RPR: branch +1 points the guide from its pivot towards the slider's pivot."""
    mech, phi, _ = m_rpr()
    for br in (1, -1):
        k = kinematics(mech, phi, branches={"S": br})
        lever = k.angle("lever")
        C = k.point("lever", "C")
        A = k.point("block", "A")
        side = np.cos(lever) * (A.x - C.x) + np.sin(lever) * (A.y - C.y)
        assert np.all(np.sign(side) == br)
    mech, phi, _ = m_rs_pin_in_known_slot()
    for br in (1, -1):
        k = kinematics(mech, phi, branches={"S": br})
        s = k.slide("S")[0]
        other = kinematics(mech, phi, branches={"S": -br}).slide("S")[0]
        assert np.all(br * (s - other) > 0)


def test_slide_derivatives_by_finite_differences():
    mech, phi, _ = m_ps_sine()
    h = 1e-5
    s, sd, sdd = kinematics(mech, phi).slide("S")
    sp = kinematics(mech, phi + h).slide("S")[0]
    sm = kinematics(mech, phi - h).slide("S")[0]
    np.testing.assert_allclose(sd, (sp - sm) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(sdd, (sp - 2 * s + sm) / h**2, atol=1e-4)


def test_inverted_joint_roles_give_the_same_motion():
    """A prismatic joint whose line is on the moving slider (frame point on it), a rotated
    slider frame (rel_angle), and a driver joint listed as (crank, frame): same mechanism."""
    base = crank_slider_mechanism(0.1, 0.35, 0.03, guide_angle=0.5, masses=(1, 2, 3))
    phi = np.linspace(0, 2 * np.pi, 37)
    k0 = kinematics(base, phi, omega1=3.0, eps1=1.0)
    d0 = inverse_dynamics(k0, gravity=(0.0, -9.81))
    rel = 0.3
    # slider frame rotated by rel about B; the guide line lies in the slider, through B,
    # at angle -rel in its frame (= 0.5 in the world); the frame's point G stays on it
    slider = Body("slider", {"B": (0.0, 0.0)}, mass=3.0)
    frame = Body("frame", {"O": (0.0, 0.0), "G": (-0.03 * np.sin(0.5), 0.03 * np.cos(0.5))})
    b = {x.name: x for x in base.bodies}
    joints = (Revolute("O", "crank", "frame"), Revolute("A", "crank", "rod"),
              Revolute("B", "rod", "slider"),
              Prismatic("G", "slider", "frame", angle=0.5 - (0.5 + rel), through="B",
                        point="G", rel_angle=-(0.5 + rel)))
    mech = Mechanism(frame, (b["crank"], b["rod"], slider), joints, Crank("O"), {"B": 1})
    k1 = kinematics(mech, -phi, omega1=-3.0, eps1=-1.0)
    np.testing.assert_allclose(k1.angle("crank"), k0.angle("crank"), atol=1e-12)
    _check_joints(k1)
    B0, B1 = k0.point("slider", "B"), k1.point("slider", "B")
    for f in ("x", "y", "vx", "vy", "ax", "ay"):
        np.testing.assert_allclose(getattr(B1, f), getattr(B0, f), atol=1e-11)
    np.testing.assert_allclose(k1.angle("slider"), 0.5 + rel, atol=1e-12)
    d1 = inverse_dynamics(k1, gravity=(0.0, -9.81))
    # the driver joint is (crank, frame): Q is the torque on the frame through the crank
    np.testing.assert_allclose(d1.Q, -d0.Q, atol=1e-9 * np.max(np.abs(d0.Q)))
    np.testing.assert_allclose(d1.reaction("O")[0], -d0.reaction("O")[0], atol=1e-9)
    np.testing.assert_allclose(d1.shaking_fx, d0.shaking_fx, atol=1e-9)
    np.testing.assert_allclose(d1.shaking_m, d0.shaking_m, atol=1e-9)
    # joint G is now (slider, frame): its reaction is the force of the slider on the frame
    np.testing.assert_allclose(d1.reaction("G")[0], -d0.reaction("G")[0], atol=1e-9)
    np.testing.assert_allclose(d1.reaction("G")[1], -d0.reaction("G")[1], atol=1e-9)
    # ... applied at the frame's point G (on the line), not at B: the couple makes up the
    # difference of the moment: m1 = m0 + (B - G) x F0
    F0x, F0y = d0.reaction("G")
    i = d0.joints.index("G")
    arm = (d0.px[i] - d1.px[i]) * F0y - (d0.py[i] - d1.py[i]) * F0x
    np.testing.assert_allclose(-d1.mz[i], d0.mz[i] + arm, atol=1e-9)


def test_driver_between_moving_bodies_solved_by_newton():
    """Driving the coupler-rocker angle of a four-bar: one Newton group holds the driver;
    motion equals the crank-driven four-bar at the same configurations; power balance."""
    base = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2))
    phi = np.linspace(0.5, 1.1, 13)
    k0 = kinematics(base, phi)

    def guess(name):
        i = base.index[name]
        return (float(k0.x[i, 0]), float(k0.y[i, 0]), float(k0.theta[i, 0]))

    bodies = [Body(b.name, b.points, b.mass, b.com, b.inertia, guess=guess(b.name))
              for b in base.bodies]
    mech = Mechanism(base.frame, bodies, base.joints, Crank("B"))
    assert [g.kind for g in mech.structure.groups] == ["newton"]
    rel = k0.theta[3] - k0.theta[2]
    k = kinematics(mech, rel, omega1=2.0, eps1=0.5)
    np.testing.assert_allclose(k.theta, k0.theta, atol=1e-10)
    np.testing.assert_allclose(k.omega[3] - k.omega[2], 2.0, atol=1e-12)
    _check_joints(k)
    d = inverse_dynamics(k, gravity=(0.0, -9.81))
    dT, P = np.zeros(k.n), np.zeros(k.n)
    for b in mech.bodies:
        i = mech.index[b.name]
        c = k.point(b.name, "com")
        dT += b.mass * (c.vx * c.ax + c.vy * c.ay) + b.inertia * k.omega[i] * k.eps[i]
        P += b.mass * -9.81 * c.vy
    np.testing.assert_allclose(d.Q * k.omega1, dT - P, atol=1e-9 * np.max(np.abs(dT)))


def test_linear_driver_results_export_slide_and_force_units(tmp_path):
    """A linear driver's position is a slide coordinate [m] and its driving load a force [N]:
    the CSV headers and JSON units of the engine's results say so (they said rad and N*m)."""
    import json

    from linkwork.planar import inverse_dynamics, kinematics
    mech, s, _ = m_linear_driver()
    kin = kinematics(mech, s)
    dyn = inverse_dynamics(kin)
    head = (kin.to_csv(tmp_path / "k.csv")).read_text().splitlines()[0].split(",")
    assert {"phi1 [m]", "omega1 [m/s]", "eps1 [m/s^2]"} <= set(head), head
    head = (dyn.to_csv(tmp_path / "d.csv")).read_text().splitlines()[0].split(",")
    assert "phi1 [m]" in head and "Q [N]" in head, head
    units = json.loads((dyn.to_json(tmp_path / "d.json")).read_text())["units"]
    assert units["Q"] == "N" and units["T"] == "J"
    # a crank keeps the class's units
    crank = kinematics(crank_slider_mechanism(0.1, 0.35, 0.03, masses=(1, 2, 3)),
                       np.linspace(0, 1, 5))
    assert crank.units["phi1"] == "rad" and inverse_dynamics(crank).units["Q"] == "N*m"


def _group_builders():
    import _mechanisms as tg
    return [(b.__name__, b) for b in tg.BUILDERS]


@pytest.mark.parametrize("name,builder", _group_builders())
def test_engine_every_group_kind_against_newton_euler(name, builder):
    """Every group kind of the engine (the seven dyads, both slot groups, a linear driver and a
    triad; mechanisms as built in test_planar_groups) against the raw-constraint reference and
    Newton-Euler, with gravity, a point force, a couple and eps1 != 0."""
    mech, positions, _kind = builder()
    idx = np.linspace(0, len(positions) - 1, 7).round().astype(int)
    phi = np.asarray(positions)[idx]
    last = mech.bodies[-1].name
    loads = [PointForce(last, "com", fx=12.0, fy=-7.0), BodyTorque(mech.bodies[0].name, 0.8)]
    crank = isinstance(mech.driver, Crank)
    _check_engine(mech, phi, 6.0 if crank else 0.7, 15.0 if crank else 0.4, (0.0, -9.81),
                  loads, about=(0.02, 0.01), label="groups ", step=2e-4)
