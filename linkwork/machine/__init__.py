"""Machine dynamics: the mechanism with its motor, gear and flywheel, and its real motion.

* :mod:`linkwork.machine.reduction` -- reduced moment of inertia J(phi1), dJ/dphi1 (exact) and
  reduced moments of loads, gravity and friction;
* :mod:`linkwork.machine.motors` -- DC and induction motors, ideal constant-speed and
  constant-torque drives, the gear stage;
* :mod:`linkwork.machine.solver` -- the reduced equation over a cycle: collocation, the
  periodic solve, the march;
* :mod:`linkwork.machine.steady` -- the periodic steady state;
* :mod:`linkwork.machine.flywheel` -- the flywheel for a coefficient of speed fluctuation,
  exact and by the energy method and Wittenbauer's energy-mass diagram.
"""

from linkwork.machine.flywheel import FlywheelSizing, energy_method, flywheel_for, wittenbauer
from linkwork.machine.motors import (
    ConstantSpeed,
    ConstantTorque,
    DCMotor,
    Gear,
    InductionMotor,
    Motor,
)
from linkwork.machine.reduction import Reduction, friction_moment, reduce
from linkwork.machine.steady import Machine, SteadyState, machine, steady_state

__all__ = [
    "ConstantSpeed",
    "ConstantTorque",
    "DCMotor",
    "FlywheelSizing",
    "Gear",
    "InductionMotor",
    "Machine",
    "Motor",
    "Reduction",
    "SteadyState",
    "energy_method",
    "flywheel_for",
    "friction_moment",
    "machine",
    "reduce",
    "steady_state",
    "wittenbauer",
]
