"""The general planar mechanism engine.

Describe a mechanism once (:mod:`~linkwork.planar.model`), check its structure
(:mod:`~linkwork.planar.structure`), then get the motion of every body over all driver positions
at once (:mod:`~linkwork.planar.kinematics`) and the joint reactions, driving torque, shaking
force and moment (:mod:`~linkwork.planar.dynamics`).

A four-bar in a few lines (Norton's a, b, c, d = 0.1, 0.3, 0.2, 0.3 m)::

    import numpy as np
    from linkwork.planar import (Body, Crank, Mechanism, Revolute, bar, kinematics,
                                 inverse_dynamics, PointForce)

    mech = Mechanism(
        frame=Body("frame", {"O2": (0.0, 0.0), "O4": (0.3, 0.0)}),
        bodies=(bar("crank", "O2", "A", 0.1, mass=1.0),     # x-axis O2 -> A, com at midpoint
                bar("coupler", "A", "B", 0.3, mass=3.0),
                bar("rocker", "O4", "B", 0.2, mass=2.0)),
        joints=(Revolute("O2", "frame", "crank"), Revolute("A", "crank", "coupler"),
                Revolute("B", "coupler", "rocker"), Revolute("O4", "frame", "rocker")),
        driver=Crank("O2", omega1=10.0),                   # phi1 = theta_crank - theta_frame
        branches={"B": +1},                                # B left of the line A -> O4
    )
    phi1 = np.linspace(0, 2 * np.pi, 361)
    kin = kinematics(mech, phi1, eps1=0.0)                  # all positions at once
    B = kin.point("coupler", "B")                           # B.x, B.vx, B.ax, ... arrays (n,)
    dyn = inverse_dynamics(kin, gravity=(0, -9.81),
                           loads=[PointForce("rocker", "B", fx=0.0, fy=-20.0)])
    dyn.Q                       # driving torque on the crank [N m], power = Q * omega1
    dyn.reaction("O4")          # force of the frame on the rocker (fx, fy) [N]

The same four-bar: ``linkwork.planar.fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2))``;
an offset crank-slider: ``linkwork.planar.crank_slider_mechanism(r, l, e, masses=(m1, m2, m3))``
(``fourbar`` and ``crank_slider`` are their deprecated names).

Conventions
-----------
* SI units, radians; angles counter-clockwise from the fixed x-axis. Each body has its own frame;
  its pose is ``(x, y, theta)`` (arrays ``kin.x, kin.y, kin.theta`` of shape ``(nb, n)``, row 0
  the frame, rows in ``kin.bodies`` order).
* Crank driver on revolute joint ``J(name, a, b)``: ``phi1 = theta_b - theta_a``. Linear
  driver on prismatic ``J``: slide coordinate ``s1 = u . (P_b - Q_a)``; ``phi1, omega1, eps1``
  then hold s1 [m], v1 [m/s], a1 [m/s^2].
* Assembly branch per Assur group (``Mechanism.branches``, key = the joint between the two
  bodies of a dyad; see ``docs/planar.md`` for each dyad's definition).
* Reaction of joint ``J(name, a, b)`` = force exerted **by a on b**, frame axes, at the joint
  centre (revolute), slider point (prismatic, plus couple ``mz``) or pin (pin-in-slot).
* Driving torque ``Q`` = torque exerted on body b of the driver joint through body a (the motor
  torque on the crank); driving power ``Q * omega1``.
* Shaking force/moment = resultant of the forces (and couples, the motor reaction included)
  exerted by the moving bodies on the frame; moment about ``about``.

Also: ``transmission_angles(kin)`` -> {group key: (mu, delta)} [rad]; ``dead_centres(kin)`` ->
[DeadCentre(group, body, phi1, kind)]; ``mech.structure`` -> Structure(mobility, groups with
kind, class, order, key); ``kin.slide(joint)`` -> slide coordinate and its rates; files of
``type = "planar"`` load with ``linkwork.files.load`` (``doc.mechanism()``, ``doc.positions()``,
``doc.loads(phi1)``) and run with ``linkwork analyze``.

Failures: a wrong structure raises :class:`~linkwork.errors.StructureError` (locked,
under-driven, unsolvable group, naming bodies and joints); positions that cannot be assembled
raise :class:`~linkwork.errors.AssemblyError` with the driver ranges, or give NaN and
``kin.valid == False`` with ``on_failure="nan"``.
"""

from linkwork.planar.dynamics import (
    BodyTorque,
    Dynamics,
    PointForce,
    inverse_dynamics,
    kinetic_energy,
)
from linkwork.planar.forces import (
    AppliedLoad,
    Damper,
    Drag,
    LoadDiagram,
    SlideForce,
    Spring,
)
from linkwork.planar.kinematics import (
    DeadCentre,
    Kinematics,
    PointMotion,
    dead_centres,
    kinematics,
    transmission_angles,
)
from linkwork.planar.model import (
    Body,
    Crank,
    Drawing,
    GearPair,
    Joint,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    bar,
    crank_slider,
    crank_slider_mechanism,
    fourbar,
    fourbar_mechanism,
    stack,
)
from linkwork.planar.self_locking import WorkingRange, working_range
from linkwork.planar.sketch import Cylinder, LinkMass, Slider, Slot, sketch
from linkwork.planar.structure import Group, Structure, analyse, mobility

__all__ = [
    "AppliedLoad",
    "Body",
    "BodyTorque",
    "Crank",
    "Cylinder",
    "Damper",
    "DeadCentre",
    "Drag",
    "Drawing",
    "Dynamics",
    "GearPair",
    "Group",
    "Joint",
    "Kinematics",
    "Linear",
    "LinkMass",
    "LoadDiagram",
    "Mechanism",
    "PinInSlot",
    "PointForce",
    "PointMotion",
    "Prismatic",
    "Revolute",
    "SlideForce",
    "Slider",
    "Slot",
    "Spring",
    "Structure",
    "WorkingRange",
    "analyse",
    "bar",
    "crank_slider",
    "crank_slider_mechanism",
    "dead_centres",
    "fourbar",
    "fourbar_mechanism",
    "inverse_dynamics",
    "kinematics",
    "kinetic_energy",
    "mobility",
    "sketch",
    "stack",
    "transmission_angles",
    "working_range",
]
