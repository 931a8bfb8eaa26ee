"""What ``linkwork dynamics`` computes from a file's ``[drive]`` table (:mod:`linkwork.machine`).

A ``planar`` file: the mechanism with its [[load]]s and gravity, driven through the gear by
each motor of ``[[drive.motor]]``; the flywheel given, or sized for ``delta`` with the first
motor (exact, energy method, Wittenbauer); per motor the steady state (real speed against the
constant-speed assumption), the start from rest and a verdict line; with ``[[drive.schedule]]``
the loads switched on and off over revolutions, run with the first motor.

A ``sine_press`` file (paper 000) with a ``[press]`` table of masses and the press force: the
same for the working structure at the file's ``alpha`` (continuous working strokes, the case
the motor and the flywheel are chosen for), and the file's duty schedule (idle revolutions,
working strokes, the switches) run with the first motor.

Nothing is printed: :func:`run` returns a frozen :class:`DynamicsStudy` that the command line
renders and the report reads.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.errors import DriveError, ParameterError
from linkwork.io.drive import DriveSection
from linkwork.io.planar import PlanarFile
from linkwork.io.sine_press import SinePressFile
from linkwork.machine import (
    ConstantSpeed,
    ConstantTorque,
    FlywheelSizing,
    Machine,
    Mode,
    MotorChoice,
    Run,
    SteadyState,
    flywheel_for,
    machine,
    press_schedule,
    run_schedule,
)
from linkwork.machine.reduction import scale_loads
from linkwork.machine.selection import motor_choice
from linkwork.machine.steady import check_feasible
from linkwork.models.variable_structure import VariableStructureMechanism
from linkwork.planar import Crank
from linkwork.results import json_array

__all__ = ["DynamicsStudy", "breaks_of", "run", "steady_columns"]


@dataclass(frozen=True)
class DynamicsStudy:
    """Machine dynamics of a file (see the module docstring).

    Attributes
    ----------
    name : str
        The mechanism's name.
    kind : str
        ``"planar"`` or ``"sine_press"``.
    machine : Machine
        The mechanism reduced with the first motor and the flywheel used.
    flywheel : float
        The flywheel used [kg m^2] (given, or sized).
    sizing : FlywheelSizing or None
        The sizing for ``[drive] delta``.
    choices : list of MotorChoice
        Per motor: steady state, start-up, figures, verdict.
    schedule : Run or None
        The schedule run with the first motor.
    notes : list of str
        What was not computed and why (e.g. no schedule with an ideal drive).
    """

    name: str
    kind: str
    machine: Machine
    flywheel: float
    sizing: FlywheelSizing | None
    choices: list[MotorChoice]
    schedule: Run | None
    notes: list[str]

    @property
    def steady(self) -> SteadyState | None:
        """The first motor's steady state."""
        return self.choices[0].steady

    def to_dict(self) -> dict[str, Any]:
        """Everything as JSON-able values (``dynamics.json``)."""
        d = self.machine.drive
        out: dict[str, Any] = {
            "name": self.name, "kind": self.kind, "flywheel": self.flywheel,
            "gear": {"ratio": d.ratio, "efficiency": d.eta,
                     "inertia": self.machine.gear.inertia},
            "motors": [c.to_dict() for c in self.choices],
            "sizing": None if self.sizing is None else self.sizing.to_dict(),
            "notes": list(self.notes),
            "units": {"flywheel": "kg*m^2", "gear.inertia": "kg*m^2"},
        }
        for c, entry in zip(self.choices, out["motors"], strict=True):
            if c.steady is not None:
                ss = c.steady
                entry["steady"] = {
                    "delta": ss.delta, "omega_mean": ss.omega_mean, "omega_max": ss.omega_max,
                    "omega_min": ss.omega_min, "phi_max": ss.phi_max, "phi_min": ss.phi_min,
                    "period": ss.period, "torque_mean": ss.torque_mean,
                    "error_estimate": ss.error_estimate, "energy": dict(ss.energy),
                    "comparison": ss.comparison(),
                    "columns": {k: json_array(v) for k, (v, _) in steady_columns(ss).items()},
                    "units": {k: u for k, (_, u) in steady_columns(ss).items()},
                }
        if self.schedule is not None:
            sd = self.schedule.to_dict()
            out["schedule"] = {k: sd[k] for k in ("modes", "switches", "revolutions",
                                                  "recovery", "mode_omega_mean")}
        return out


def steady_columns(ss: SteadyState) -> dict[str, tuple[np.ndarray, str]]:
    """The per-position columns of a steady state (``dynamics_<motor>.csv``): name -> (values,
    unit); ``Q_constant`` is the driving torque at the constant mean speed."""
    cols = {k: (getattr(ss, k), ss.units[k]) for k in (
        "phi1", "t", "omega", "eps", "omega_motor", "torque", "power", "Q", "J", "dJ",
        "M_loads", "M_gravity", "M_friction", "M_damping")}
    if ss.dynamics_constant is not None:
        cols["Q_constant"] = (ss.dynamics_constant.Q, "N*m")
    return cols


def breaks_of(doc: PlanarFile) -> list[float]:
    """The crank angles [rad] where a [[load]] of a planar file switches on or off (its
    ``phi_range``)."""
    out: list[float] = []
    for i, ld in enumerate(doc.load):
        rng = ld.driver_range(i, False)
        if rng is not None:
            out += [rng[0], rng[1]]
    return out


def _scaled_loads(doc: PlanarFile, f: float) -> Callable[[np.ndarray], list[Any]]:
    """The file's loads times ``f`` (the applied loads; springs and other force elements are
    part of the machine, not of its duty)."""
    def loads(phi: np.ndarray) -> list[Any]:
        return scale_loads(doc.loads(phi), f)
    return loads


def run(doc: PlanarFile | SinePressFile, *,
        progress: Callable[[int, int], None] | None = None) -> DynamicsStudy:
    """Machine dynamics of a planar or sine press file with a ``[drive]`` table.

    Raises
    ------
    ParameterError
        The file has no ``[drive]`` table (``drive``), a sine press file no ``[press]`` table
        (``press``), a planar file's driver is not a crank (``driver``).
    DriveError
        The first motor cannot carry the mean load at any stable speed (the others get a
        verdict line), or a ``delta`` no flywheel up to ``max_flywheel`` reaches.
    """
    drive = doc.drive
    if drive is None:
        raise ParameterError("drive", "missing", "linkwork dynamics needs a [drive] table with "
                             "at least one [[drive.motor]] (see linkwork/io/drive.py)")
    motors = drive.motors()
    gear = drive.build_gear()
    fw = drive.flywheel or 0.0
    notes: list[str] = []
    modes: list[Mode] = []
    segs: list[tuple[str, int]] = []
    if isinstance(doc, SinePressFile):
        if doc.press is None:
            raise ParameterError("press", "missing", "linkwork dynamics of a sine_press file "
                                 "needs a [press] table of masses and the press force")
        press = VariableStructureMechanism(doc.crank.L1, doc.idle.lambda2, doc.idle.lambda_e,
                                           doc.working.alpha, branch=doc.idle.branch,
                                           f_slot=doc.working.f_slot,
                                           f_guide=doc.working.f_guide)
        sched = doc.segments() or [("working", 1, None)]
        md, sg = press_schedule(press, sched, **doc.press.masses())
        work = md[f"working {math.degrees(press.alpha):.4g} deg"]
        modes, segs = list(md.values()), (sg if doc.segments() else [])
        mech, loads, gravity, breaks = work.mechanism, work.loads, work.gravity, work.breaks
        about: Any = (0.0, 0.0)
        kind = "sine_press"
    else:
        mech = doc.mechanism()
        if not isinstance(mech.driver, Crank):
            raise ParameterError("driver", doc.driver.type, "linkwork dynamics needs a crank "
                                 "driver (a motor turning the crank); this file's driver is "
                                 "linear")
        loads, gravity, about = doc.loads, doc.analysis.gravity, doc.analysis.about
        breaks = tuple(breaks_of(doc))
        kind = "planar"
        if drive.schedule:
            for s in drive.schedule:
                name = f"loads x {s.load:g}"
                if name not in {x.name for x in modes}:
                    modes.append(Mode(name, mech, _scaled_loads(doc, s.load), gravity, breaks))
                segs.append((name, s.revolutions))
    m = machine(mech, motors[0], loads=loads, gravity=gravity, flywheel=fw, gear=gear,
                n=drive.positions, breaks=breaks, about=about)
    check_feasible(m)  # the first motor must carry the mean load (the others get a verdict)
    sizing = None
    if drive.delta is not None:
        sizing = flywheel_for(m, delta=drive.delta, max_flywheel=drive.max_flywheel)
        fw = sizing.flywheel
        m = m.with_flywheel(fw)
    choices = [motor_choice(m.with_motor(mot), start=drive.start_up, band=drive.band)
               for mot in motors]
    schedule = _schedule(drive, modes, segs, motors[0], gear, fw, choices[0], notes, progress)
    return DynamicsStudy(doc.name or "", kind, m, fw, sizing, choices, schedule, notes)


def _schedule(drive: DriveSection, modes: list[Mode], segs: list[tuple[str, int]], motor: Any,
              gear: Any, fw: float, first: MotorChoice, notes: list[str],
              progress: Callable[[int, int], None] | None) -> Run | None:
    if not segs:
        return None
    if isinstance(motor, ConstantSpeed | ConstantTorque):
        notes.append(f"the schedule is not run: {motor.name} is an ideal drive (no speed-torque "
                     "characteristic)")
        return None
    start = "steady" if first.steady is not None else "rest"
    try:
        return run_schedule(modes, segs, motor, gear=gear, flywheel=fw, n=drive.positions,
                            start=start, progress=progress)
    except DriveError as exc:
        notes.append(f"the schedule stops: {exc}")
        return None
