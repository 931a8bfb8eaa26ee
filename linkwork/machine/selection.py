r"""Motor selection: the figures a designer checks a motor with, and one verdict line per motor.

For each candidate motor (with the machine's gear and flywheel) :func:`select_motors` solves the
steady state and, if asked, the start from rest, and reports:

* the mean power over time and the **RMS (equivalent) torque**
  :math:`\sqrt{\frac1T\int M^2\,dt}` against the rated torque (the thermal check of continuous
  duty S1);
* the **peak torque** and where it occurs against the motor's limit (an induction motor's
  breakdown torque, a DC motor's stall or peak torque, a servo's peak torque);
* for an induction motor the lowest motor speed against its breakdown speed: below it the motor
  runs on the unstable branch of its characteristic (it pulls out);
* the start-up time and its peak torque.

Where the motor is **overloaded** (it cannot carry the mean load, the crank stops within the
cycle, or an induction motor runs below its breakdown speed) the verdict says by how much: the
factor :math:`k` on the motor's torque characteristic (the same speeds, :math:`k` times the
torques: a larger motor of the same type) for which the machine runs on the stable branch,
found by bisection to 1e-3, and where the cycle is critical, e.g. ``"overloaded at 212 deg:
needs 1.35 x the breakdown torque"``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from numpy.typing import ArrayLike

from linkwork.errors import ConvergenceError, DriveError, ParameterError, StallError
from linkwork.machine.motors import (
    ConstantSpeed,
    ConstantTorque,
    DCMotor,
    Gear,
    InductionMotor,
    Motor,
)
from linkwork.machine.reduction import Loads
from linkwork.machine.steady import Machine, SteadyState, machine, solve_steady
from linkwork.machine.transient import StartUp, start_up
from linkwork.planar import Mechanism

__all__ = ["MotorChoice", "motor_choice", "scaled", "select_motors"]


def scaled(motor: Motor, k: float) -> Motor:
    """The motor with ``k`` times the torques at the same speeds (a larger motor of the same
    type): an induction motor of ``k`` times the rated power, a DC motor of ``k`` times the
    stall torque."""
    if isinstance(motor, InductionMotor):
        return dataclasses.replace(motor, rated_power=motor.rated_power * k)
    if isinstance(motor, DCMotor):
        return dataclasses.replace(motor, stall_torque=motor.stall_torque * k,
                                   peak_torque=None if motor.peak_torque is None else
                                   motor.peak_torque * k)
    raise ParameterError("motor", motor, "has no torque characteristic to scale")


@dataclass(frozen=True)
class MotorChoice:
    """One motor checked on the machine.

    Attributes
    ----------
    motor : Motor
    ok : bool
        Whether it drives the machine within its limits (stable branch, peak and RMS torque).
    verdict : str
        One line: ``"OK: ..."`` or what is wrong and by how much.
    steady : SteadyState or None
        None where the motor cannot run the machine.
    start : StartUp or None
        The start from rest (when asked and possible).
    power_mean, torque_rms, torque_peak, phi_torque_peak : float
        Mean power over time [W], RMS torque [N m], largest torque [N m] and where [rad] (NaN
        without a steady state).
    limit, limit_name : float or None, str
        The torque limit the peak is compared with and its name.
    peak_ratio, rms_ratio : float or None
        Peak torque over the limit, RMS torque over the rated torque.
    needs : float or None
        The factor on the motor's torques for which the machine runs (overloaded motors).
    critical_phi : float or None
        Where the cycle is critical [rad]: the lowest speed of the (scaled) steady state.
    """

    motor: Motor
    ok: bool
    verdict: str
    steady: SteadyState | None
    start: StartUp | None
    power_mean: float
    torque_rms: float
    torque_peak: float
    phi_torque_peak: float
    limit: float | None
    limit_name: str
    peak_ratio: float | None
    rms_ratio: float | None
    needs: float | None
    critical_phi: float | None

    def to_dict(self) -> dict[str, Any]:
        def num(v: float | None) -> float | None:
            return None if v is None or not math.isfinite(v) else float(v)

        out = {"motor": self.motor.describe(), "name": self.motor.name, "ok": self.ok,
               "verdict": self.verdict, "power_mean": num(self.power_mean),
               "torque_rms": num(self.torque_rms), "torque_peak": num(self.torque_peak),
               "phi_torque_peak": num(self.phi_torque_peak), "limit": num(self.limit),
               "limit_name": self.limit_name, "peak_ratio": num(self.peak_ratio),
               "rms_ratio": num(self.rms_ratio), "needs": num(self.needs),
               "critical_phi": num(self.critical_phi),
               "delta": None if self.steady is None else self.steady.delta,
               "omega_mean": None if self.steady is None else self.steady.omega_mean,
               "units": {"power_mean": "W", "torque_rms": "N*m", "torque_peak": "N*m",
                         "phi_torque_peak": "rad", "limit": "N*m", "critical_phi": "rad",
                         "omega_mean": "rad/s"}}
        if self.start is not None:
            out["start"] = self.start.to_dict()
        return out


def _limit(motor: Motor) -> tuple[float | None, str]:
    if isinstance(motor, InductionMotor):
        return motor.breakdown_torque, "breakdown torque"
    if isinstance(motor, DCMotor):
        if motor.peak_torque is not None and motor.peak_torque < motor.stall_torque:
            return motor.peak_torque, "peak torque"
        return motor.stall_torque, "stall torque"
    if isinstance(motor, ConstantSpeed):
        return motor.peak_torque, "peak torque"
    return None, ""


def _runs(m: Machine) -> SteadyState | None:
    """The steady state if the motor runs the machine on its stable branch, else None."""
    try:
        ss = solve_steady(m, dynamics=False)
    except (DriveError, ConvergenceError):
        return None
    mot = m.motor
    if isinstance(mot, InductionMotor) and ss.omega_min * m.drive.ratio < mot.breakdown_speed:
        return None
    return ss


def _needs(m: Machine) -> tuple[float | None, float | None]:
    """The factor on the motor's torques for which the machine runs (bisection to 1e-3) and
    the critical crank angle there."""
    lo, hi = 1.0, 2.0
    s_hi = None
    while hi <= 1e3:
        s_hi = _runs(m.with_motor(scaled(m.motor, hi)))
        if s_hi is not None:
            break
        lo, hi = hi, 2 * hi
    if s_hi is None:
        return None, None
    while hi - lo > 1e-3 * hi:
        mid = 0.5 * (lo + hi)
        s = _runs(m.with_motor(scaled(m.motor, mid)))
        if s is None:
            lo = mid
        else:
            hi, s_hi = mid, s
    return hi, s_hi.phi_min


def motor_choice(m: Machine, *, start: bool = True, band: float = 0.01) -> MotorChoice:
    """The figures and the verdict of the motor of the reduced machine ``m`` (see the module
    docstring)."""
    mot = m.motor
    limit, lname = _limit(mot)
    nan = math.nan
    try:
        ss: SteadyState | None = solve_steady(m)
        why = ""
    except StallError:
        ss, why = None, "the crank stops there with this motor"
    except DriveError as exc:
        ss, why = None, str(exc).split(":")[0]
    pull_out = (ss is not None and isinstance(mot, InductionMotor)
                and ss.omega_min * m.drive.ratio < mot.breakdown_speed)
    if ss is None or pull_out:
        if isinstance(mot, ConstantSpeed | ConstantTorque):
            return MotorChoice(mot, False, f"cannot drive the machine: {why}", ss, None, nan, nan,
                               nan, nan, limit, lname, None, None, None, None)
        k, phi = _needs(m)
        where = "" if phi is None else f" at {math.degrees(phi) % 360:.0f} deg"
        what = lname or "torque"
        if k is None:
            line = f"overloaded{where}: no motor of this type up to 1000 x its {what} drives it"
        else:
            line = f"overloaded{where}: needs {k:.3g} x the {what}"
        if pull_out and isinstance(mot, InductionMotor):
            line += (f" (runs below its breakdown speed "
                     f"{mot.breakdown_speed * 30 / math.pi:.5g} rpm)")
        elif why:
            line += f" ({why})"
        figs = (ss.power_mean, ss.torque_rms, ss.torque_peak, ss.phi_torque_peak) if ss else (
            nan, nan, nan, nan)
        return MotorChoice(mot, False, line, ss, None, *figs, limit, lname,
                           None if (ss is None or limit is None) else ss.torque_peak / limit,
                           None if (ss is None or mot.rated_torque is None) else
                           ss.torque_rms / mot.rated_torque, k, phi)
    peak_ratio = None if limit is None else ss.torque_peak / limit
    rated = mot.rated_torque
    rms_ratio = None if not rated else ss.torque_rms / rated
    problems = []
    if peak_ratio is not None and peak_ratio > 1.0:
        problems.append(f"peak torque {peak_ratio:.3g} x the {lname} at "
                        f"{math.degrees(ss.phi_torque_peak) % 360:.0f} deg")
    if rms_ratio is not None and rms_ratio > 1.0:
        problems.append(f"overheats: RMS torque {rms_ratio:.3g} x the rated torque "
                        f"{rated:.4g} N·m")
    su = None
    if start and not isinstance(mot, ConstantSpeed | ConstantTorque):
        try:
            su = start_up(m.mechanism, mot, loads=m.loads, gravity=m.gravity,
                          flywheel=m.flywheel, gear=m.gear, n=m.grid.n,
                          breaks=_breaks(m), band=band)
        except (DriveError, ConvergenceError) as exc:
            problems.append(f"cannot start: {exc}")
    figures = [f"RMS torque {rms_ratio:.3g} x rated" if rms_ratio is not None else
               f"RMS torque {ss.torque_rms:.4g} N·m",
               (f"peak {peak_ratio:.3g} x the {lname}" if peak_ratio is not None else
                f"peak {ss.torque_peak:.4g} N·m")
               + f" at {math.degrees(ss.phi_torque_peak) % 360:.0f} deg",
               f"delta {ss.delta:.3g}"]
    if su is not None:
        figures.append(f"start-up {su.t_steady:.3g} s")
    ok = not problems
    line = ("OK: " + ", ".join(figures)) if ok else "; ".join(problems)
    return MotorChoice(mot, ok, line, ss, su, ss.power_mean, ss.torque_rms, ss.torque_peak,
                       ss.phi_torque_peak, limit, lname, peak_ratio, rms_ratio, None,
                       ss.phi_min)


def _breaks(m: Machine) -> list[float]:
    """The jump positions of the machine's grid (its one-sided nodes)."""
    g = m.grid
    n = g.n
    return [float(g.nodes[k]) for k in range(0, n, 2) if g.iL[k] >= 2 * n]


def select_motors(mech: Mechanism, motors: Sequence[Motor], *, loads: Loads = (),
                  gravity: ArrayLike | None = None, flywheel: float = 0.0,
                  gear: Gear | None = None, n: int = 360, breaks: ArrayLike = (),
                  start: bool = True, band: float = 0.01) -> list[MotorChoice]:
    """Check every motor of ``motors`` on the mechanism (reduced once): figures and a verdict
    line each (:class:`MotorChoice`)."""
    if isinstance(motors, Motor) or not isinstance(motors, Sequence) or not motors:
        raise ParameterError("motors", motors, "must be a non-empty sequence of motors")
    base = machine(mech, motors[0], loads=loads, gravity=gravity, flywheel=flywheel, gear=gear,
                   n=n, breaks=breaks)
    return [motor_choice(base.with_motor(mot), start=start, band=band) for mot in motors]
