"""Planar-engine mechanisms, one per group kind (RRR, RRP, PRR, RPR, RPP, PPR, PRP, pin in slot,
linear driver, a class-III triad), shared by the planar tests: each builder returns
``(mechanism, driver positions, expected group kind)``; and mechanisms with several drivers
(``five_bar``, ``crank_and_ram``) and a planetary gear train (``planetary``)."""

from __future__ import annotations

import dataclasses

import numpy as np

import linkwork.planar as pl
from linkwork.planar import (
    Body,
    Crank,
    GearPair,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    bar,
    crank_slider_mechanism,
    fourbar_mechanism,
    sketch,
)

FULL = np.linspace(0.0, 2 * np.pi, 25)


def _blk(name, pts, mass=0.5, inertia=2e-4):
    return Body(name, pts, mass=mass, com=(0.01, -0.005), inertia=inertia)


def m_rrr():
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2)), FULL, "RRR"


def m_rrp():
    return crank_slider_mechanism(0.1, 0.35, 0.03, guide_angle=0.5, masses=(1, 2, 3)), FULL, "RRP"


def m_prr():
    base = crank_slider_mechanism(0.1, 0.35, 0.03, guide_angle=0.5, masses=(1, 2, 3))
    b = {x.name: x for x in base.bodies}
    mech = Mechanism(base.frame, (b["crank"], b["slider"], b["rod"]), base.joints,
                     base.driver, {"B": 1})
    return mech, FULL, "PRR"


def m_rpr():
    frame = Body("frame", {"O": (0, 0), "C": (-0.25, 0.02)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    block = _blk("block", {"A": (0, 0)})
    lever = bar("lever", "C", "E", 0.5, mass=2.0)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "block"),
              Prismatic("S", "lever", "block", angle=0.0, through=(0.0, 0.01), point="A"),
              Revolute("C", "frame", "lever"))
    return Mechanism(frame, (crank, block, lever), joints, Crank("O")), FULL, "RPR"


def _yoke(order):
    frame = Body("frame", {"O": (0, 0)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    block = _blk("block", {"A": (0, 0)})
    yoke = Body("yoke", {"Y": (0.0, 0.0)}, mass=3.0, com=(0.05, 0.0), inertia=0.01)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "block"),
              Prismatic("S", "yoke", "block", angle=np.radians(70), through=(0.02, 0.0),
                        point="A"),
              Prismatic("G", "frame", "yoke", angle=0.2, through=(0.0, 0.01), point="Y"))
    bodies = {"block": block, "yoke": yoke}
    return Mechanism(frame, (crank, *(bodies[o] for o in order)), joints, Crank("O"))


def m_rpp():
    return _yoke(("block", "yoke")), FULL, "RPP"


def m_ppr():
    return _yoke(("yoke", "block")), FULL, "PPR"


def m_prp():
    frame = Body("frame", {"O": (0, 0)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    collar = _blk("collar", {"P": (0, 0)})
    slider = _blk("slider", {"P": (0, 0)}, mass=1.5)
    joints = (Revolute("O", "frame", "crank"),
              Prismatic("G1", "crank", "collar", angle=0.0, through="O", point="P"),
              Revolute("P", "collar", "slider"),
              Prismatic("G2", "frame", "slider", angle=0.1, through=(0.0, 0.2), point="P"))
    return (Mechanism(frame, (crank, collar, slider), joints, Crank("O")),
            np.linspace(0.6, 2.4, 19), "PRP")


def m_rs_slot_in_body():
    frame = Body("frame", {"O": (0, 0), "C": (-0.25, 0.0)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    lever = bar("lever", "C", "E", 0.5, mass=2.0)
    joints = (Revolute("O", "frame", "crank"), Revolute("C", "frame", "lever"),
              PinInSlot("S", "lever", "crank", angle=0.0, through=(0.0, 0.015), point="A"))
    return Mechanism(frame, (crank, lever), joints, Crank("O")), FULL, "RS"


def m_rs_pin_in_known_slot():
    frame = Body("frame", {"O": (0, 0), "C": (0.25, 0.0)})
    crank = bar("crank", "O", "A", 0.4, mass=1.0)
    lever = bar("lever", "C", "P", 0.3, mass=2.0)
    joints = (Revolute("O", "frame", "crank"), Revolute("C", "frame", "lever"),
              PinInSlot("S", "crank", "lever", angle=0.0, through="O", point="P"))
    return Mechanism(frame, (crank, lever), joints, Crank("O")), FULL, "RS"


def m_ps_sine():
    frame = Body("frame", {"O": (0, 0)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    yoke = Body("yoke", {"Y": (0.0, 0.0)}, mass=3.0, com=(0.05, 0.02), inertia=0.01)
    joints = (Revolute("O", "frame", "crank"),
              Prismatic("G", "frame", "yoke", angle=0.0, point="Y"),
              PinInSlot("S", "yoke", "crank", angle=np.radians(60), through=(0.01, 0.0),
                        point="A"))
    return Mechanism(frame, (crank, yoke), joints, Crank("O")), FULL, "PS"


def m_linear_driver():
    base = crank_slider_mechanism(0.1, 0.35, 0.03, masses=(1, 2, 3))
    mech = Mechanism(base.frame, base.bodies, base.joints, Linear("G", v1=0.7, a1=0.4),
                     {"A": 1})
    return mech, np.linspace(0.27, 0.43, 17), "RRR"


def m_triad():
    """A class III group (ternary link on three binary links), solved by Newton."""
    phi0 = 0.3
    A = np.array([0.1 * np.cos(phi0), 0.1 * np.sin(phi0)])
    P1, P2, P3 = np.array([0.25, 0.15]), np.array([0.35, 0.05]), np.array([0.3, 0.25])
    F2, F3 = np.array([0.45, -0.1]), np.array([0.5, 0.35])

    def link(name, s, e, S, E, mass):
        L = float(np.hypot(*(E - S)))
        b = bar(name, s, e, L, mass=mass)
        th = float(np.arctan2(*(E - S)[::-1]))
        return Body(b.name, b.points, b.mass, b.com, b.inertia, guess=(S[0], S[1], th))

    frame = Body("frame", {"O": (0, 0), "F2": tuple(F2), "F3": tuple(F3)})
    crank = bar("crank", "O", "A", 0.1, mass=1.0)
    tern = Body("tern", {"P1": (0, 0), "P2": tuple(P2 - P1), "P3": tuple(P3 - P1)}, mass=2.0,
                com=tuple((P2 + P3 - 2 * P1) / 3), inertia=0.004, guess=(P1[0], P1[1], 0.0))
    l1 = link("l1", "A", "P1", A, P1, 0.8)
    l2 = link("l2", "F2", "P2", F2, P2, 0.6)
    l3 = link("l3", "F3", "P3", F3, P3, 0.7)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l1"),
              Revolute("P1", "l1", "tern"), Revolute("P2", "l2", "tern"),
              Revolute("P3", "l3", "tern"), Revolute("F2", "frame", "l2"),
              Revolute("F3", "frame", "l3"))
    mech = Mechanism(frame, (crank, l1, l2, l3, tern), joints, Crank("O"))
    return mech, np.linspace(phi0, phi0 + 0.55, 12), "newton"


BUILDERS = [m_rrr, m_rrp, m_prr, m_rpr, m_rpp, m_ppr, m_prp, m_rs_slot_in_body,
            m_rs_pin_in_known_slot, m_ps_sine, m_linear_driver, m_triad]


def _rot(t):
    return np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])


def _circles(P, rp, Q, rq, branch):
    """Intersection of circles (P, rp), (Q, rq); branch +1 on the left of P -> Q."""
    d = Q - P
    L = np.hypot(*d)
    a = (rp**2 - rq**2 + L**2) / (2 * L)
    ex = d / L
    return P + a * ex + branch * np.sqrt(rp**2 - a**2) * np.array([-ex[1], ex[0]])


def _angle(v):
    return np.arctan2(v[1], v[0])


def stephenson_sixbar():
    """Stephenson III: four-bar O2-A-B-O4 with a ternary coupler (A, B, C), dyad C-D-O6 on
    its coupler point C (branch -1: D right of C -> O6)."""

    O6, Cl, S3 = np.array([0.5, 0.35]), np.array([0.12, 0.1]), np.array([0.14, 0.03])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": (0.3, 0.0), "O6": tuple(O6)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0),
         pl.Body("coupler", {"A": (0.0, 0.0), "B": (0.3, 0.0), "C": tuple(Cl)}, mass=3.0,
              com=tuple(S3), inertia=0.03),
         pl.bar("rocker", "O4", "B", 0.25, mass=2.0), pl.bar("link5", "C", "D", 0.45, mass=1.5),
         pl.bar("link6", "O6", "D", 0.25, mass=1.2, com=0.05)),
        (pl.Revolute("O2", "frame", "crank"), pl.Revolute("A", "crank", "coupler"),
         pl.Revolute("B", "coupler", "rocker"), pl.Revolute("O4", "frame", "rocker"),
         pl.Revolute("C", "coupler", "link5"), pl.Revolute("D", "link5", "link6"),
         pl.Revolute("O6", "frame", "link6")), pl.Crank("O2"), {"B": 1, "D": -1})

    def poses(p):
        A, O4 = 0.1 * np.array([np.cos(p), np.sin(p)]), np.array([0.3, 0.0])
        B = _circles(A, 0.3, O4, 0.25, 1)
        t3, t4 = _angle(B - A), _angle(B - O4)
        C = A + _rot(t3) @ Cl
        D = _circles(C, 0.45, O6, 0.25, -1)
        t6 = _angle(D - O6)
        return {"crank": (A / 2, p), "coupler": (A + _rot(t3) @ S3, t3),
                "rocker": ((O4 + B) / 2, t4), "link5": ((C + D) / 2, _angle(D - C)),
                "link6": (O6 + 0.05 * np.array([np.cos(t6), np.sin(t6)]), t6)}

    def loads(ph):
        return [pl.PointForce("link6", "D", fx=50 * np.cos(2 * ph), fy=20.0),
                pl.PointForce("coupler", (0.05, 0.05), fx=-5.0, fy=np.sin(ph))]
    return mech, poses, loads


def _rates(f, p, h=2e-3):
    """f, df/dphi, d2f/dphi2 by fourth-order central differences (angles unwrapped)."""
    v = [np.asarray(f(p + k * h), dtype=float) for k in (-2, -1, 0, 1, 2)]
    d1 = (v[0] - 8 * v[1] + 8 * v[3] - v[4]) / (12 * h)
    d2 = (-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h * h)
    return v[2], d1, d2


def sine_mechanism(alpha: float, f_slot: float, f_guide: float, L1: float = 0.1) -> Mechanism:
    """Paper 000's working mechanism: crank AB about the frame's A, the crank pin B in a
    straight slot at ``alpha`` to the guide, cut in the slider (ram), which moves along x on
    the frame's guide; pin friction neglected (a sliding block, radius 0), guide a point
    contact (length 0), as in the closed form's model."""
    frame = Body("frame", {"A": (0.0, 0.0)})
    crank = bar("crank", "A", "B", L1)
    slider = Body("slider", {"G": (0.0, 0.0)})
    joints = (Revolute("A", "frame", "crank"),
              PinInSlot("S", "slider", "crank", angle=alpha, through=(0.0, 0.0), point="B",
                        friction=f_slot),
              Prismatic("G", "frame", "slider", angle=0.0, through="A", point="G",
                        friction=f_guide))
    return Mechanism(frame, (crank, slider), joints, Crank("A", 1.0))


def five_bar():
    """A two-crank five-bar O1-A-P-B-O2 drawn with both cranks up."""
    pts = {"O1": (0.0, 0.0), "O2": (0.2, 0.0), "A": (0.02, 0.08), "B": (0.19, 0.1),
           "P": (0.12, 0.28), "E": (0.05, 0.22)}
    return sketch(pts, {"c1": ["O1", "A"], "c2": ["O2", "B"], "l1": ["A", "P", "E"],
                        "l2": ["B", "P"]},
                  ground=["O1", "O2"], drivers=["O1", "O2"],
                  masses={"c1": 1.0, "c2": 1.2, "l1": {"mass": 2.0, "inertia": 0.01},
                          "l2": 1.5})


def crank_and_ram():
    """A crank O-A and a ram B on a horizontal frame guide, driven linearly, joined by two
    links A-P-B: one crank and one linear actuator."""
    pts = {"O": (0.0, 0.0), "A": (0.05, 0.03), "P": (0.2, 0.22), "B": (0.35, 0.05)}
    return sketch(pts, {"crank": ["O", "A"], "l1": ["A", "P"], "l2": ["P", "B"]},
                  ground=["O"], drivers=["O", "ram"],
                  sliders={"ram": {"point": "B", "guide": "frame", "angle": 0.0}},
                  masses={"crank": 1.0, "l1": 2.0, "l2": 1.5, "ram": 4.0})


def planetary():
    """An arm driven about O carrying a planet (r = 30 mm) in a fixed internal ring (R = 90
    mm): the frame is the ring (gear b of an internal pair), the arm the carrier."""
    frame = Body("frame", {"O": (0.0, 0.0)})
    arm = bar("arm", "O", "Q", 0.06, mass=0.8)
    planet = Body("planet", {"Q": (0.0, 0.0), "T": (0.03, 0.0)}, mass=0.4, inertia=2e-4)
    joints = (Revolute("O", "frame", "arm"), Revolute("Q", "arm", "planet"),
              GearPair("M", "planet", "frame", radii=(0.03, 0.09), internal=True,
                       carrier="arm"))
    return Mechanism(frame, (arm, planet), joints, Crank("O"))



def with_friction(mech: Mechanism, f_rev: float = 0.08, r: float = 0.004, f_line: float = 0.12,
                  length: float = 0.3, pin: float = 0.003, torque: float = 0.0) -> Mechanism:
    """``mech`` with friction in every joint."""
    js = []
    for j in mech.joints:
        if isinstance(j, Revolute):
            js.append(dataclasses.replace(j, friction=f_rev, radius=r, friction_torque=torque))
        elif isinstance(j, Prismatic):
            js.append(dataclasses.replace(j, friction=f_line, length=length))
        else:
            js.append(dataclasses.replace(j, friction=f_line, radius=pin))
    return Mechanism(mech.frame, mech.bodies, tuple(js), mech.driver, mech.branches)


def kinetic_energy_rate(mech: Mechanism, kin, g=(0.0, 0.0)):
    """dT/dt = sum m a_C . v_C + I omega eps, and the power of gravity sum m g . v_C, written
    out from the kinematics (positions last)."""
    dT = np.zeros(kin.n)
    pg = np.zeros(kin.n)
    for b in mech.bodies:
        i = mech.index[b.name]
        c = kin.point(b.name, "com")
        dT += b.mass * (c.ax * c.vx + c.ay * c.vy) + b.inertia * kin.omega[i] * kin.eps[i]
        pg += b.mass * (g[0] * c.vx + g[1] * c.vy)
    return dT, pg
