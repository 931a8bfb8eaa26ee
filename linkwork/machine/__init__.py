"""Machine dynamics: the mechanism with its motor, gear and flywheel, and its real motion.

* :mod:`linkwork.machine.reduction` -- reduced moment of inertia J(phi1), dJ/dphi1 (exact) and
  reduced moments of loads, gravity and friction;
* :mod:`linkwork.machine.motors` -- DC and induction motors, ideal constant-speed and
  constant-torque drives, the gear stage;
* :mod:`linkwork.machine.solver` -- the reduced equation over a cycle: collocation, the
  periodic solve, the march;
* :mod:`linkwork.machine.steady` -- the periodic steady state;
* :mod:`linkwork.machine.flywheel` -- the flywheel for a coefficient of speed fluctuation,
  exact and by the energy method and Wittenbauer's energy-mass diagram;
* :mod:`linkwork.machine.transient` -- start-up from rest, loads changing over time, duty
  schedules of several structures (modes) with the switches;
* :mod:`linkwork.machine.press` -- paper 000's variable-structure press as machine modes;
* :mod:`linkwork.machine.selection` -- motor selection: figures and a verdict line per motor.
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
from linkwork.machine.press import press_modes, press_schedule
from linkwork.machine.reduction import Reduction, friction_moment, reduce
from linkwork.machine.selection import MotorChoice, select_motors
from linkwork.machine.steady import Machine, SteadyState, machine, steady_state
from linkwork.machine.transient import Mode, Run, StartUp, run_schedule, start_up

__all__ = [
    "ConstantSpeed",
    "ConstantTorque",
    "DCMotor",
    "FlywheelSizing",
    "Gear",
    "InductionMotor",
    "Machine",
    "Mode",
    "Motor",
    "MotorChoice",
    "Reduction",
    "Run",
    "StartUp",
    "SteadyState",
    "energy_method",
    "flywheel_for",
    "friction_moment",
    "machine",
    "press_modes",
    "press_schedule",
    "reduce",
    "run_schedule",
    "select_motors",
    "start_up",
    "steady_state",
    "wittenbauer",
]
