"""Each joint type's methods (:mod:`linkwork.planar.joints`) against independent checks: the
constraint rows against finite differences of the closure written out here from the poses, the
reaction components against the constraint rows (virtual work) and against the equilibrium of
simple mechanisms solved by hand."""

from __future__ import annotations

import numpy as np
import pytest

from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    bar,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar.joints import Joint, ResolvedJoint
from linkwork.planar.state import State

RNG = np.random.default_rng(13)
N = 5  # positions
QA, PB, ANG, REL = (0.11, -0.04), (0.07, 0.05), 0.6, 0.3


def _resolved(j: Joint, drive: bool = False) -> ResolvedJoint:
    ang = ANG if j.has_line else 0.0
    return ResolvedJoint(j, 0, 1, 2, QA, PB, ang, (float(np.cos(ang)), float(np.sin(ang))), drive)


def _closure(j: Joint, q: np.ndarray, drive: bool) -> list[np.ndarray]:
    """The constraint functions written out from the poses q = (xa, ya, ta, xb, yb, tb)."""
    xa, ya, ta, xb, yb, tb = q
    Pa = (xa + np.cos(ta) * QA[0] - np.sin(ta) * QA[1],
          ya + np.sin(ta) * QA[0] + np.cos(ta) * QA[1])
    Pb = (xb + np.cos(tb) * PB[0] - np.sin(tb) * PB[1],
          yb + np.sin(tb) * PB[0] + np.cos(tb) * PB[1])
    if isinstance(j, Revolute):
        out = [Pa[0] - Pb[0], Pa[1] - Pb[1]]
        return [*out, tb - ta] if drive else out
    u = (np.cos(ta + ANG), np.sin(ta + ANG))
    d = (Pb[0] - Pa[0], Pb[1] - Pa[1])
    out = [-u[1] * d[0] + u[0] * d[1]]
    if isinstance(j, Prismatic):
        out.append(tb - ta - REL)
        if drive:
            out.append(u[0] * d[0] + u[1] * d[1])
    return out


def _state(q: np.ndarray, qd: np.ndarray) -> State:
    st = State(3, q.shape[1])
    for k, i in enumerate((1, 2)):
        st.X[i], st.Y[i] = q[3 * k], q[3 * k + 1]
        st.set_angle(i, q[3 * k + 2])
        st.VX[i], st.VY[i], st.W[i] = qd[3 * k], qd[3 * k + 1], qd[3 * k + 2]
    return st


JOINTS = [(Revolute("J", "a", "b"), False), (Revolute("J", "a", "b"), True),
          (Prismatic("J", "a", "b", angle=ANG, rel_angle=REL), False),
          (Prismatic("J", "a", "b", angle=ANG, rel_angle=REL), True),
          (PinInSlot("J", "a", "b", angle=ANG), False)]


@pytest.mark.parametrize(("joint", "drive"), JOINTS, ids=lambda v: str(v)[:12])
def test_constraint_rows_are_the_derivatives_of_the_closure(joint, drive):
    """res = closure; (ja, jb) = d closure / d q by central differences (h = 1e-6: error
    ~1e-12 m/m); gam = -d2/dt2 closure(q + qd t) at constant qd (h = 1e-4: ~1e-7 relative)."""
    q = RNG.normal(size=(6, N)) * 0.3
    qd = RNG.normal(size=(6, N))
    r = _resolved(joint, drive)
    rows = joint.constraint_rows(_state(q, qd), r, need_gamma=True)
    assert len(rows) == joint.n_constraints + drive
    flags = [bool(row.get("drive")) for row in rows]
    assert flags == [False] * joint.n_constraints + [drive] * drive
    ref = _closure(joint, q, drive)
    h = 1e-6
    for c, row in enumerate(rows):
        np.testing.assert_allclose(row["res"], ref[c], rtol=0, atol=1e-14)
        jac = np.concatenate([np.broadcast_to(row["ja"][k], (N,))[None] for k in range(3)]
                             + [np.broadcast_to(row["jb"][k], (N,))[None] for k in range(3)])
        for v in range(6):
            dq = np.zeros((6, 1))
            dq[v] = h
            fd = (_closure(joint, q + dq, drive)[c] - _closure(joint, q - dq, drive)[c]) / (2 * h)
            np.testing.assert_allclose(jac[v], fd, rtol=0, atol=1e-8)
        ht = 1e-4
        second = (_closure(joint, q + qd * ht, drive)[c] - 2 * ref[c]
                  + _closure(joint, q - qd * ht, drive)[c]) / ht**2
        np.testing.assert_allclose(np.broadcast_to(row["gam"], (N,)), -second, rtol=0,
                                   atol=1e-5 * (1 + np.max(np.abs(second))))


@pytest.mark.parametrize(("joint", "drive"), [jd for jd in JOINTS if not jd[1]],
                         ids=lambda v: str(v)[:12])
def test_reaction_components_are_the_transposed_rows(joint, drive):
    """The reaction (fx, fy at the point of b, mz) carried by a row's multiplier lam must do the
    virtual work of -lam times that row on body b: (fx, fy, (P - r_b) x F + mz) = -lam jb."""
    q = RNG.normal(size=(6, N)) * 0.3
    st = _state(q, np.zeros((6, N)))
    r = _resolved(joint)
    rows = joint.constraint_rows(st, r, need_gamma=False)
    P = st.wpt(2, PB)
    for row, kind in zip(rows, joint.row_kinds, strict=True):
        lam = RNG.normal(size=N)
        comp = joint.reaction_components(st, r, kind, lam)
        assert set(comp) <= {"fx", "fy", "mz"}
        fx, fy, mz = (comp.get(k, np.zeros(N)) for k in ("fx", "fy", "mz"))
        moment = (P[0] - st.X[2]) * fy - (P[1] - st.Y[2]) * fx + mz
        for got, jb in zip((fx, fy, moment), row["jb"], strict=True):
            np.testing.assert_allclose(got, -lam * jb, rtol=1e-13, atol=1e-14)


def test_revolute_reaction_holds_a_pendulum():
    """A crank of mass m, centre at distance c on its line, at rest under gravity: the frame's
    pin carries m g upwards and the motor torque is m g c cos(phi) (hand equilibrium)."""
    m, c, g = 2.0, 0.15, 9.81
    crank = bar("crank", "O", "A", 0.4, mass=m, com=c)
    mech = Mechanism(Body("frame", {"O": (0.0, 0.0)}), (crank,),
                     (Revolute("O", "frame", "crank"),), Crank("O", 0.0, 0.0))
    phi = np.linspace(0.1, 6.0, 9)
    dyn = inverse_dynamics(kinematics(mech, phi, 0.0, 0.0), gravity=(0.0, -g))
    fx, fy = dyn.reaction("O")
    np.testing.assert_allclose(fx, 0.0, atol=1e-12)
    np.testing.assert_allclose(fy, m * g, rtol=1e-13)
    np.testing.assert_allclose(dyn.Q, m * g * c * np.cos(phi), rtol=1e-12, atol=1e-12)


def test_prismatic_reaction_holds_a_block_on_an_incline():
    """A block of mass m on a frame guide at angle alpha, driven by a Linear driver, at rest:
    the driving force is m g sin(alpha) up the slope, the guide's normal force m g cos(alpha),
    and its couple balances the moment of the weight about the slider point (the block keeps
    the frame's orientation, rel_angle 0, so its centre is com from the slider point)."""
    m, g, alpha = 3.0, 9.81, 0.4
    com = (0.02, 0.05)
    block = Body("block", {"P": (0.0, 0.0)}, mass=m, com=com)
    mech = Mechanism(Body("frame", {"G": (0.0, 0.0)}), (block,),
                     (Prismatic("G", "frame", "block", angle=alpha, through="G", point="P"),),
                     Linear("G", 0.0, 0.0))
    s = np.linspace(-0.2, 0.3, 5)
    dyn = inverse_dynamics(kinematics(mech, s, 0.0, 0.0), gravity=(0.0, -g))
    np.testing.assert_allclose(dyn.Q, m * g * np.sin(alpha), rtol=1e-13)
    fx, fy = dyn.reaction("G")
    n = np.array([-np.sin(alpha), np.cos(alpha)])
    np.testing.assert_allclose(fx * n[0] + fy * n[1], m * g * np.cos(alpha), rtol=1e-13)
    np.testing.assert_allclose(fx * np.cos(alpha) + fy * np.sin(alpha), 0.0, atol=1e-12)
    weight_moment = com[0] * (-m * g) - com[1] * 0.0  # (C - P) x W
    mz = dyn.mz[dyn.joints.index("G")]
    np.testing.assert_allclose(mz, -weight_moment, rtol=1e-12)  # the couple balances it


def test_pin_in_slot_reaction_is_normal_to_the_slot_and_balances_the_rocker():
    """Oscillating-slot drive: crank O-A, pin A in a slot of a rocker pivoted at C, torque T on
    the rocker, at rest. The slot's force is normal to the slot, and the rocker's moments about
    C balance: (A - C) x F_on_rocker + T = 0 (hand equilibrium of one body)."""
    T = 5.0
    crank = bar("crank", "O", "A", 0.1)
    rocker = Body("rocker", {"C": (0.0, 0.0)})
    mech = Mechanism(Body("frame", {"O": (0.0, 0.0), "C": (0.0, -0.25)}), (crank, rocker),
                     (Revolute("O", "frame", "crank"), Revolute("C", "frame", "rocker"),
                      PinInSlot("S", "rocker", "crank", angle=0.0, through="C", point="A")),
                     Crank("O", 0.0, 0.0))
    phi = np.linspace(0.2, 6.0, 7)
    kin = kinematics(mech, phi, 0.0, 0.0)
    dyn = inverse_dynamics(kin, loads=[BodyTorque("rocker", T)])
    fx, fy = dyn.reaction("S")  # by the rocker on the crank, at the pin
    th = kin.angle("rocker")
    np.testing.assert_allclose(fx * np.cos(th) + fy * np.sin(th), 0.0, atol=1e-10)
    A = kin.point("crank", "A")
    C = kin.point("rocker", "C")
    moment = (A.x - C.x) * (-fy) - (A.y - C.y) * (-fx)  # the pin's force on the rocker
    np.testing.assert_allclose(moment + T, 0.0, atol=1e-10)
    assert dyn.mz[dyn.joints.index("S")] == pytest.approx(np.zeros(7))


def test_joint_capabilities_and_driver_codes():
    """Flags the solvers use instead of the type, and the driver's joint type check."""
    R, P, S = Revolute("J", "a", "b"), Prismatic("J", "a", "b"), PinInSlot("J", "a", "b")
    assert (R.is_pivot, P.is_pivot, S.is_pivot) == (True, False, False)
    assert (R.keeps_angle, P.keeps_angle, S.keeps_angle) == (False, True, False)
    assert (R.has_line, P.has_line, S.has_line) == (False, True, True)
    assert [j.n_constraints for j in (R, P, S)] == [2, 2, 1]
    assert [len(j.row_kinds) for j in (R, P, S)] == [2, 2, 1]
    assert (R.spatial_family, P.spatial_family, S.spatial_family) == ("R", "P", None)
    assert (Crank("J").joint_code, Linear("J").joint_code) == (R.code, P.code)


def test_driver_coordinate_names_and_units():
    """A crank's coordinate is phi1 [rad] with a torque Q [N*m]; a linear driver's is s1 [m]
    with a force Q [N]: the results and messages take them from the driver."""
    assert Crank("J").coordinate == ("phi1", "rad")
    assert Linear("J").coordinate == ("s1", "m")
    assert dict(Crank("J").field_units) == {"phi1": "rad", "omega1": "rad/s",
                                            "eps1": "rad/s^2", "Q": "N*m"}
    assert dict(Linear("J").field_units) == {"phi1": "m", "omega1": "m/s", "eps1": "m/s^2",
                                             "Q": "N"}
    block = Body("block", {"P": (0.0, 0.0)}, mass=1.0)
    mech = Mechanism(Body("frame", {"G": (0.0, 0.0)}), (block,),
                     (Prismatic("G", "frame", "block", through="G", point="P"),),
                     Linear("G", 0.5, 0.0))
    dyn = inverse_dynamics(kinematics(mech, [0.1, 0.2]))
    assert (dyn.kinematics.units["phi1"], dyn.kinematics.units["omega1"]) == ("m", "m/s")
    assert (dyn.units["phi1"], dyn.units["Q"]) == ("m", "N")
