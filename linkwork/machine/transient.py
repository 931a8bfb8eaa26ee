r"""Transients of a machine unit: start-up from rest, loads that change, duty schedules.

The equation of motion (:mod:`linkwork.machine.solver`) is marched revolution by revolution
over the crank angle; time follows from :math:`dt = d\varphi/\omega`. A **schedule** is a list of
segments, each a whole number of revolutions of one **mode** (:class:`Mode`: a mechanism with its
loads; a variable-structure machine has one per structure, e.g. paper 000's press idle and
working), starting at :math:`\varphi = 0 \pmod{2\pi}`. At a switch the structure changes
instantly with the crank angle: the links of the new structure that were at rest are engaged
by an impact (plastic, through ideal couplings) and those left are disengaged and stopped
without acting on the crank; the generalised momentum of the links common to both and of the
drive's rotors is kept,

.. math:: \bigl(J_B(\varphi_s) + J_{rot}\bigr)\,\omega^+ =
   \Bigl(\sum_{common} m\,\mathbf v_{SA}'\cdot\mathbf v_{SB}' + J_S\,\theta_A'\theta_B'
   + J_{rot}\Bigr)\,\omega^-,

(primes: velocity analogues of structures A before and B after), and the kinetic energy lost at
the switch is reported. A load that changes over time is a factor ``load_factor(t)`` on the
external loads, taken at the start of each interval (a jump in time lands on the next node).

Joint friction depends on the motion: each revolution is marched again with the friction moment
of its previous march until it changes by less than 1e-9 of the torque scale.

:func:`start_up` runs from rest until the motion stays within a band of the steady state
(:func:`~linkwork.machine.steady.steady_state`), and reports the time it takes and the peak motor
torque; :func:`run_schedule` runs a schedule from the steady state of its first mode (or from rest,
or a given speed) and reports per revolution the speed drop, the mean speed, the energy of the
motor and of the loads, and the switches.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_number
from linkwork.errors import ConvergenceError, DriveError, ParameterError, StallError
from linkwork.machine.motors import ConstantSpeed, Gear, Motor
from linkwork.machine.reduction import Loads, friction_moment, load_list
from linkwork.machine.solver import Solution, Stall, hermite_extremes, march
from linkwork.machine.steady import (
    Machine,
    SteadyState,
    at_points,
    check_inertia,
    machine,
    solve_steady,
    torque_limit,
)
from linkwork.planar import BodyTorque, Mechanism, PointForce, kinematics
from linkwork.planar.state import Arr
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["MAX_RUN_SAMPLES", "Mode", "Run", "StartUp", "run_schedule", "start_up"]

TWO_PI = 2.0 * math.pi

#: The most positions of a run (revolutions x positions per revolution): its arrays and the
#: marching state take about 200 bytes a position; refused above before any work.
MAX_RUN_SAMPLES = 5_000_000


@dataclass(frozen=True)
class Mode:
    """One structure of a machine: a mechanism with its loads (see
    :func:`~linkwork.machine.steady.steady_state` for ``loads``, ``gravity``, ``breaks``)."""

    name: str
    mechanism: Mechanism
    loads: Loads = ()
    gravity: ArrayLike | None = None
    breaks: tuple[float, ...] = ()


@dataclass(frozen=True)
class Run(Result):
    """A transient over time, position by position (about ``n`` a revolution).

    Attributes
    ----------
    t : time [s]
    phi1 : crank angle [rad], unwrapped (2 pi per revolution from the start)
    omega, eps : crank speed [rad/s] and acceleration [rad/s^2]
    torque : motor torque at its shaft [N m]
    mode, segment, revolution : the mode (index into ``modes``), schedule segment and revolution
        of each position; a switch instant appears twice (end of the old segment, start of the
        new one, ``switch`` True at the second)
    modes : the modes' names
    switch_t, switch_phi1 : switch instants [s] and crank angles [rad]
    switch_to : the mode entered at each switch (index)
    switch_omega_before, switch_omega_after : crank speed just before and after [rad/s]
    switch_energy_loss : kinetic energy lost at each switch [J] (the engagement's impact and the
        disengaged links' energy)
    rev_* : per revolution (arrays of the revolutions): ``rev_mode``, ``rev_segment``,
        ``rev_t`` (start [s]), ``rev_omega_start``, ``rev_omega_min``, ``rev_omega_max`` and
        ``rev_omega_mean`` (2 pi over its time) [rad/s], ``rev_drop`` (``(omega_start -
        omega_min) / omega_start``), ``rev_torque_peak`` [N m], ``rev_work_motor``,
        ``rev_work_loads`` (work done on the external loads), ``rev_work_friction`` [J]
    mode_omega_mean : each mode's steady mean speed [rad/s] (NaN where it has none)
    """

    t: Arr
    phi1: Arr
    omega: Arr
    eps: Arr
    torque: Arr
    mode: Arr
    segment: Arr
    revolution: Arr
    switch: Arr
    modes: tuple[str, ...]
    switch_t: Arr
    switch_phi1: Arr
    switch_to: Arr
    switch_omega_before: Arr
    switch_omega_after: Arr
    switch_energy_loss: Arr
    rev_mode: Arr
    rev_segment: Arr
    rev_t: Arr
    rev_omega_start: Arr
    rev_omega_min: Arr
    rev_omega_max: Arr
    rev_omega_mean: Arr
    rev_drop: Arr
    rev_torque_peak: Arr
    rev_work_motor: Arr
    rev_work_loads: Arr
    rev_work_friction: Arr
    mode_omega_mean: tuple[float, ...] = ()
    position_field: ClassVar[str] = "t"
    units: ClassVar[dict[str, str]] = {
        "t": "s", "phi1": "rad", "omega": "rad/s", "eps": "rad/s^2", "torque": "N*m",
        "mode": "1", "segment": "1", "revolution": "1", "switch": "1", "switch_t": "s",
        "switch_phi1": "rad", "switch_to": "1", "switch_omega_before": "rad/s",
        "switch_omega_after": "rad/s", "switch_energy_loss": "J", "rev_t": "s",
        "rev_omega_start": "rad/s", "rev_omega_min": "rad/s", "rev_omega_max": "rad/s",
        "rev_omega_mean": "rad/s", "rev_drop": "1", "rev_torque_peak": "N*m",
        "rev_work_motor": "J", "rev_work_loads": "J", "rev_work_friction": "J"}

    @property
    def switch_names(self) -> list[str]:
        """The mode entered at each switch, by name."""
        return [self.modes[int(k)] for k in self.switch_to]

    def revolutions(self) -> dict[str, np.ndarray]:
        """The per-revolution arrays by name (without the ``rev_`` prefix)."""
        return {f.removeprefix("rev_"): np.asarray(getattr(self, f)) for f in (
            "rev_mode", "rev_segment", "rev_t", "rev_omega_start", "rev_omega_min",
            "rev_omega_max", "rev_omega_mean", "rev_drop", "rev_torque_peak", "rev_work_motor",
            "rev_work_loads", "rev_work_friction")}

    def recovery(self, band: float = 0.01) -> list[dict[str, Any]]:
        """After each switch: the revolutions and time until a revolution's mean speed is
        within ``band`` of the steady mean speed of the mode entered (None if not within the
        run, or if that mode has no steady state)."""
        out = []
        for k in range(self.switch_t.size):
            to = int(self.switch_to[k])
            ref = self.mode_omega_mean[to] if to < len(self.mode_omega_mean) else math.nan
            after = np.flatnonzero(self.rev_t >= self.switch_t[k] - 1e-12)
            seg = int(self.rev_segment[after[0]]) if after.size else -1
            rec: dict[str, Any] = {"switch": k, "to": self.modes[to], "t": float(
                self.switch_t[k]), "revolutions": None, "time": None}
            if math.isfinite(ref) and after.size:
                for j, r in enumerate(after):
                    if int(self.rev_segment[r]) != seg:
                        break
                    if abs(self.rev_omega_mean[r] - ref) <= band * ref:
                        rec["revolutions"] = j + 1
                        end = self.rev_t[r + 1] if r + 1 < self.rev_t.size else self.t[-1]
                        rec["time"] = float(end - self.switch_t[k])
                        break
            out.append(rec)
        return out

    def to_dict(self) -> dict[str, Any]:
        data = super().to_dict()
        data["modes"] = list(self.modes)
        data["switches"] = [
            {"t": float(a), "phi1": float(b), "to": self.modes[int(c)], "omega_before":
             float(d), "omega_after": float(e), "energy_loss": float(f)}
            for a, b, c, d, e, f in zip(self.switch_t, self.switch_phi1, self.switch_to,
                                        self.switch_omega_before, self.switch_omega_after,
                                        self.switch_energy_loss, strict=True)]
        revs = self.revolutions()
        data["revolutions"] = {k: v.tolist() for k, v in revs.items()}
        data["mode_omega_mean"] = [None if not math.isfinite(v) else v
                                   for v in self.mode_omega_mean]
        data["recovery"] = self.recovery()
        return data

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Speed and motor torque over time with the switches (:mod:`linkwork.plot.machine`)."""
        from linkwork.plot.machine import transient_figure

        return transient_figure(self, axes=axes, **kw)


@dataclass(frozen=True)
class StartUp:
    """A start from rest to the steady state.

    Attributes
    ----------
    run : Run
        The motion from rest over the revolutions simulated.
    steady : SteadyState
        The steady state reached.
    band : float
        The band (relative to the steady mean speed) within which the motion counts as steady.
    t_steady, revolutions_steady : float, int
        Time [s] and revolutions until the speed stays within the band of the steady state's
        omega(phi).
    t_mean_speed : float
        Time [s] until the crank first reaches the steady mean speed.
    torque_peak, t_torque_peak : float
        The largest motor torque during the start [N m] and the start of its revolution [s].
    work_motor : float
        The motor's work over the revolutions until ``t_steady`` [J].
    """

    run: Run
    steady: SteadyState
    band: float
    t_steady: float
    revolutions_steady: int
    t_mean_speed: float
    torque_peak: float
    t_torque_peak: float
    work_motor: float

    def to_dict(self) -> dict[str, Any]:
        return {"band": self.band, "t_steady": self.t_steady,
                "revolutions_steady": self.revolutions_steady,
                "t_mean_speed": self.t_mean_speed, "torque_peak": self.torque_peak,
                "t_torque_peak": self.t_torque_peak, "work_motor": self.work_motor,
                "units": {"t_steady": "s", "t_mean_speed": "s", "torque_peak": "N*m",
                          "t_torque_peak": "s", "work_motor": "J"}}

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        return self.run.plot(axes, **kw)


# ---------------------------------------------------------------------------------------------
def _scaled(loads: Sequence[PointForce | BodyTorque], f: Arr) -> list[PointForce | BodyTorque]:
    out: list[PointForce | BodyTorque] = []
    for ld in loads:
        if isinstance(ld, PointForce):
            out.append(PointForce(ld.body, ld.point, np.asarray(ld.fx) * f,
                                  np.asarray(ld.fy) * f, ld.from_frame))
        else:
            out.append(BodyTorque(ld.body, np.asarray(ld.mz) * f, ld.from_frame))
    return out


def _revolution(m: Machine, Mf: Arr, u0: float, t0: float,
                factor: Callable[[float], float] | None) -> tuple[Solution, Arr]:
    """One revolution marched from ``u0`` at time ``t0``; with friction, marched again with
    the friction moment of the previous march until it settles."""
    g = m.grid
    co = m.coefficients(Mf)
    sol = march(g.nodes, g.iL, g.iM, g.iR, co, m.drive, u0, loads_part=m.M_loads,
                factor=factor, t0=t0)
    if not m.has_friction:
        return sol, Mf
    scale = float(np.max(np.abs(m.M_loads)) + np.max(np.abs(m.M_gravity))
                  + np.max(np.abs(m.dJ)) * float(np.max(sol.u)) + 1e-300)
    for _ in range(60):
        u, eps, _ = at_points(m, sol)
        lds = load_list(m.loads, g.pts)
        if factor is not None:
            tk = t0 + np.concatenate(([0.0], np.cumsum(sol.dt)[:-1]))
            f = np.empty(g.pts.size)
            f[: g.n] = [factor(x) for x in tk]
            for idx in (g.iL, g.iM, g.iR):  # the interval's start time for all three
                f[idx] = f[: g.n]
            lds = _scaled(lds, f)
        Mf_new = friction_moment(m.mechanism, g.pts, np.sqrt(u), eps, loads=lds,
                                 gravity=m.gravity)
        change = float(np.max(np.abs(Mf_new - Mf)))
        Mf = Mf_new
        sol = march(g.nodes, g.iL, g.iM, g.iR, m.coefficients(Mf), m.drive, u0,
                    loads_part=m.M_loads, factor=factor, t0=t0)
        if change <= 1e-9 * scale:
            return sol, Mf
    raise ConvergenceError("the friction iteration of a revolution did not converge in 60 "
                           "marches")


def _analogue_momentum(ma: Machine, mb: Machine, phi: float) -> tuple[float, float, float]:
    """(sum over the links of both of m v_A'.v_B' + J theta_A' theta_B', J_A(phi), J_B(phi))
    at the crank angle ``phi``."""
    ka = kinematics(ma.mechanism, [phi], 1.0, 0.0)
    kb = kinematics(mb.mechanism, [phi], 1.0, 0.0)
    names_a = {b.name: b for b in ma.mechanism.bodies}
    common = 0.0
    for b in mb.mechanism.bodies:
        if b.name not in names_a:
            continue
        a = names_a[b.name]
        if (a.mass, a.inertia, tuple(a.com)) != (b.mass, b.inertia, tuple(b.com)):
            raise ParameterError("modes", b.name, "a body of two modes must be the same body "
                                 "(mass, inertia and centre of mass) in both")
        pa, pb = ka.point(b.name, "com"), kb.point(b.name, "com")
        wa = ka.omega[ka.bodies.index(b.name), 0]
        wb = kb.omega[kb.bodies.index(b.name), 0]
        common += b.mass * (pa.vx[0] * pb.vx[0] + pa.vy[0] * pb.vy[0]) + b.inertia * wa * wb

    def jj(k: Any, mech: Mechanism) -> float:
        return sum(b.mass * (k.point(b.name, "com").vx[0] ** 2 + k.point(b.name, "com").vy[0] ** 2)
                   + b.inertia * k.omega[k.bodies.index(b.name), 0] ** 2 for b in mech.bodies)

    return common, jj(ka, ma.mechanism), jj(kb, mb.mechanism)


def _modes(modes: Mode | Sequence[Mode] | Mapping[str, Mode]) -> list[Mode]:
    if isinstance(modes, Mode):
        out = [modes]
    elif isinstance(modes, Mapping):
        out = list(modes.values())
    else:
        out = list(modes)
    if not out or not all(isinstance(x, Mode) for x in out):
        raise ParameterError("modes", modes, "must be one Mode or a sequence of Mode")
    names = [x.name for x in out]
    if len(set(names)) != len(names):
        raise ParameterError("modes", names, "mode names must be unique")
    return out


def _schedule(schedule: Sequence[Any] | None, modes: list[Mode]) -> list[tuple[int, int]]:
    names = [x.name for x in modes]
    if schedule is None:
        raise ParameterError("schedule", None, "must list (mode, revolutions) segments")
    out = []
    for k, seg in enumerate(schedule):
        if isinstance(seg, str) or not isinstance(seg, Sequence) or len(seg) != 2:
            raise ParameterError(f"schedule[{k}]", seg, "must be (mode name, revolutions)")
        name, revs = seg
        if name not in names:
            raise ParameterError(f"schedule[{k}]", name, f"no such mode; known: {names}")
        if isinstance(revs, bool) or not isinstance(revs, int | np.integer) or revs < 1:
            raise ParameterError(f"schedule[{k}].revolutions", revs, "must be a whole number "
                                 ">= 1")
        out.append((names.index(name), int(revs)))
    if not out:
        raise ParameterError("schedule", "[]", "must have at least one segment")
    return out


def _start_speed(start: str | float, steady: SteadyState | None) -> float:
    if isinstance(start, str):
        if start == "rest":
            return 0.0
        if start == "steady":
            if steady is None:
                raise DriveError("the first mode has no steady state to start from (its crank "
                                 "stops within a cycle); start from rest or a given speed")
            return float(steady.omega[0])
        raise ParameterError("start", start, "must be 'rest', 'steady' or a crank speed [rad/s]")
    w = require_number("start", start)
    if w < 0:
        raise ParameterError("start", w, "must be >= 0 [rad/s]")
    return w


def _stall(m: Machine, exc: Stall, mode: str, start_up: bool) -> StallError:
    lim = torque_limit(m.motor)
    lim_s = "" if lim is None else f" ({lim[1]} {lim[0]:.4g} N·m at the motor)"
    phi = math.degrees(exc.phi) % 360
    if start_up and exc.t == 0.0:
        need = float(-(m.M_loads + m.M_gravity)[m.grid.iL[exc.index]])
        start = float(m.motor.torque(0.0))
        d = m.drive
        return StallError(f"{m.motor.name} cannot start the machine at phi1 = {phi:.1f} deg: "
                          f"its starting torque {start:.4g} N·m gives "
                          f"{start * d.ratio * d.eta:.4g} N·m at the crank, below the load "
                          f"torque {need:.4g} N·m there")
    return StallError(f"the crank stops at phi1 = {phi:.1f} deg, t = {exc.t:.4g} s "
                      f"({'during start-up' if start_up else 'in mode ' + repr(mode)}): "
                      f"{m.motor.name}{lim_s} with the rotors' inertia {m.drive.rotors:.4g} "
                      "kg·m² at the crank cannot carry the machine over its load there")


def _check_motor(motor: Motor) -> None:
    if isinstance(motor, ConstantSpeed):
        raise DriveError(f"{motor.name} holds the speed: a transient needs a motor with a "
                         "speed-torque characteristic")
    if not hasattr(motor, "torque") or not callable(motor.torque):
        raise ParameterError("motor", motor, "must be a DCMotor or an InductionMotor")


def run_schedule(modes: Mode | Sequence[Mode] | Mapping[str, Mode], schedule: Sequence[Any],
                 motor: Motor, *, gear: Gear | None = None, flywheel: float = 0.0, n: int = 360,
                 start: str | float = "steady",
                 load_factor: Callable[[float], float] | None = None,
                 progress: Callable[[int, int], None] | None = None) -> Run:
    """Run a schedule of modes with the real motor and flywheel (see the module docstring).

    Parameters
    ----------
    modes : Mode, or a sequence (or mapping) of Mode
        The structures of the machine (one crank, the same crank joint in all).
    schedule : sequence of (mode name, revolutions)
        E.g. ``[("idle", 5), ("working", 3), ("idle", 4)]``.
    motor : DCMotor or InductionMotor
    gear, flywheel, n
        As :func:`~linkwork.machine.steady.steady_state` (the flywheel on the crank shaft).
    start : "steady", "rest" or a crank speed [rad/s]
        The state at the start: the first mode's steady state at phi1 = 0 (default), rest, or
        the given speed.
    load_factor : callable t -> factor, optional
        Scales the external loads over time [s] (e.g. a load switched on at 2 s).
    progress : callable (revolutions done, revolutions in all), optional

    Returns
    -------
    Run

    Raises
    ------
    StallError
        The crank stops (naming where and when).
    """
    _check_motor(motor)
    ms = _modes(modes)
    segs = _schedule(schedule, ms)
    total = sum(r for _, r in segs)
    if total * n > MAX_RUN_SAMPLES:
        raise ParameterError("schedule", f"{total} revolutions x {n} positions", f"at most "
                             f"{MAX_RUN_SAMPLES} positions in all (about 200 bytes each); run "
                             "fewer revolutions or positions")
    machines = [machine(x.mechanism, motor, loads=x.loads, gravity=x.gravity,
                        flywheel=flywheel, gear=gear, n=n, breaks=x.breaks) for x in ms]
    for mm in machines:
        check_inertia(mm)
    steadies: list[SteadyState | None] = []
    for mm in machines:
        try:
            steadies.append(solve_steady(mm, dynamics=False))
        except DriveError:
            steadies.append(None)
    first = segs[0][0]
    u0 = _start_speed(start, steadies[first]) ** 2
    return _run(machines, [x.name for x in ms], segs, u0, steadies, load_factor, progress,
                start == "rest")


def _run(machines: list[Machine], names: list[str], segs: list[tuple[int, int]], u0: float,
         steadies: list[SteadyState | None], factor: Callable[[float], float] | None,
         progress: Callable[[int, int], None] | None, from_rest: bool,
         stop: Callable[[Arr, Solution], bool] | None = None,
         first: Machine | None = None) -> Run:
    """March ``segs`` (mode index, revolutions) from ``u0``; ``first``: the machine of the
    very first revolution (the first mode's on a grid refined at a start from rest)."""
    total = sum(r for _, r in segs)
    cols: dict[str, list[Any]] = {k: [] for k in ("t", "phi1", "omega", "eps", "torque", "mode",
                                                  "segment", "revolution", "switch")}
    sw: dict[str, list[float]] = {k: [] for k in ("t", "phi1", "to", "before", "after", "loss")}
    revs: dict[str, list[float]] = {k: [] for k in (
        "mode", "segment", "t", "omega_start", "omega_min", "omega_max", "omega_mean", "drop",
        "torque_peak", "work_motor", "work_loads", "work_friction")}
    t = 0.0
    rev = 0
    u = u0
    prev: Machine | None = None
    Mfs = [np.zeros(mm.grid.pts.shape) if s is None or not mm.has_friction else
           _friction_points(mm, s) for mm, s in zip(machines, steadies, strict=True)]
    last_end: tuple[float, float] | None = None
    done = False
    for si, (mi, count) in enumerate(segs):
        m = machines[mi]
        if prev is not None and last_end is not None:  # the switch: momentum kept
            phi_s = TWO_PI * rev
            common, ja, jb = _analogue_momentum(prev, m, 0.0)
            jr = m.drive.rotors
            w_before = math.sqrt(u)
            w_after = w_before * (common + jr) / (jb + jr)
            loss = 0.5 * (ja + jr) * w_before**2 - 0.5 * (jb + jr) * w_after**2
            u = w_after**2
            for key, val in (("t", t), ("phi1", phi_s), ("to", mi), ("before", w_before),
                             ("after", w_after), ("loss", loss)):
                sw[key].append(val)
        for j in range(count):
            mr = first if (first is not None and rev == 0) else m
            try:
                sol, Mf = _revolution(mr, Mfs[mi] if mr is m else _zeros_or(mr, Mfs[mi], m),
                                      u, t, factor)
            except Stall as exc:
                raise _stall(mr, exc, names[mi], from_rest and rev == 0) from None
            if mr is m:
                Mfs[mi] = Mf
            m_rev = mr
            g = m_rev.grid
            tk = t + np.concatenate(([0.0], np.cumsum(sol.dt)[:-1]))
            entered = si > 0 and j == 0
            cols["t"].append(tk)
            cols["phi1"].append(g.nodes[:-1] + TWO_PI * rev)
            cols["omega"].append(np.sqrt(sol.uL))
            cols["eps"].append(0.5 * sol.FL)
            cols["torque"].append(sol.aL)
            nn = g.n
            for key, val in (("mode", mi), ("segment", si), ("revolution", rev)):
                cols[key].append(np.full(nn, val))
            flag = np.zeros(nn, dtype=bool)
            flag[0] = entered
            cols["switch"].append(flag)
            period = float(np.sum(sol.dt))
            umax, _p1, umin, _p2 = hermite_extremes(g.nodes, sol.uL, sol.uR, sol.FL, sol.FR)
            w0 = math.sqrt(u)
            a_p = at_points(m_rev, sol)[2]
            f_rev = 1.0 if factor is None else float(factor(t))
            for key, val in (("mode", mi), ("segment", si), ("t", t), ("omega_start", w0),
                             ("omega_min", math.sqrt(umin)), ("omega_max", math.sqrt(umax)),
                             ("omega_mean", TWO_PI / period),
                             ("drop", (w0 - math.sqrt(umin)) / w0 if w0 > 0 else math.nan),
                             ("torque_peak", float(max(np.max(sol.aL), np.max(sol.aM)))),
                             ("work_motor", m_rev.drive.ratio * m_rev.integral(a_p)),
                             ("work_loads", -f_rev * m_rev.integral(m_rev.M_loads) + (
                                 0.0 if m_rev.damping is None else m_rev.integral(
                                     m_rev.damping * np.sqrt(at_points(m_rev, sol)[0])))),
                             ("work_friction", -m_rev.integral(Mf))):
                revs[key].append(val)
            t += period
            rev += 1
            u = float(sol.uR[-1])
            last_end = (float(sol.aR[-1]), float(0.5 * sol.FR[-1]))
            if progress is not None:
                progress(rev, total)
            if stop is not None and stop(g.nodes, sol):
                done = True
                break
        prev = m
        if done:
            break
        if si + 1 < len(segs):  # the end of the segment: its last state, before the switch
            _append_end(cols, t, rev, u, last_end, mi, si)
    _append_end(cols, t, rev, u, last_end, mi, si)
    arr = {k: np.concatenate([np.atleast_1d(np.asarray(v)) for v in vals])
           for k, vals in cols.items()}
    omega_means = tuple(math.nan if s is None else s.omega_mean for s in steadies)
    return Run(
        t=arr["t"].astype(float), phi1=arr["phi1"].astype(float),
        omega=arr["omega"].astype(float), eps=arr["eps"].astype(float),
        torque=arr["torque"].astype(float), mode=arr["mode"].astype(int),
        segment=arr["segment"].astype(int), revolution=arr["revolution"].astype(int),
        switch=arr["switch"].astype(bool), modes=tuple(names),
        switch_t=np.asarray(sw["t"], float), switch_phi1=np.asarray(sw["phi1"], float),
        switch_to=np.asarray(sw["to"], int), switch_omega_before=np.asarray(sw["before"], float),
        switch_omega_after=np.asarray(sw["after"], float),
        switch_energy_loss=np.asarray(sw["loss"], float),
        rev_mode=np.asarray(revs["mode"], int), rev_segment=np.asarray(revs["segment"], int),
        **{f"rev_{k}": np.asarray(revs[k], float) for k in (
            "t", "omega_start", "omega_min", "omega_max", "omega_mean", "drop", "torque_peak",
            "work_motor", "work_loads", "work_friction")},
        mode_omega_mean=omega_means)


def _zeros_or(mr: Machine, Mf: Arr, m: Machine) -> Arr:
    """The friction moment to start a revolution on another grid of the same mode with."""
    if not m.has_friction:
        return np.zeros(mr.grid.pts.shape)
    return np.interp(np.mod(mr.grid.pts, TWO_PI), np.mod(m.grid.pts, TWO_PI), Mf,
                     period=TWO_PI)


def _append_end(cols: dict[str, list[Any]], t: float, rev: int, u: float,
                last_end: tuple[float, float] | None, mi: int, si: int) -> None:
    """The state at the end of a segment (the switch instant's first sample) or of the run."""
    torque, eps = last_end if last_end is not None else (math.nan, math.nan)
    for key, val in (("t", t), ("phi1", TWO_PI * rev), ("omega", math.sqrt(u)), ("eps", eps),
                     ("torque", torque), ("mode", mi), ("segment", si),
                     ("revolution", rev - 1), ("switch", False)):
        cols[key].append(np.array([val]))


def _friction_points(m: Machine, s: SteadyState) -> Arr:
    """The friction moment of a steady state at the machine's grid positions."""
    g = m.grid
    return friction_moment(m.mechanism, g.pts, s.omega_mean, 0.0, loads=m.loads,
                           gravity=m.gravity)


def start_up(mech: Mechanism, motor: Motor, *, loads: Loads = (),
             gravity: ArrayLike | None = None, flywheel: float = 0.0, gear: Gear | None = None,
             n: int = 360, breaks: ArrayLike = (), band: float = 0.01,
             max_revolutions: int = 2000,
             progress: Callable[[int, int], None] | None = None) -> StartUp:
    """Start the machine from rest and run it until its speed stays within ``band`` (relative
    to the steady mean speed) of the steady state's omega(phi) for a whole revolution.

    Returns
    -------
    StartUp
        Time and revolutions to the steady state, the time to the mean speed, the peak motor
        torque and when, the run itself.

    Raises
    ------
    StallError
        The motor cannot start the machine (its starting torque below the load at the start),
        or the crank stops during the start.
    ConvergenceError
        Not within the band after ``max_revolutions``.
    """
    _check_motor(motor)
    b = require_number("band", band)
    if not 0 < b < 1:
        raise ParameterError("band", b, "must lie in (0, 1): relative to the mean speed")
    if isinstance(max_revolutions, bool) or not isinstance(max_revolutions, int) or (
            max_revolutions < 1):
        raise ParameterError("max_revolutions", max_revolutions, "must be a whole number >= 1")
    if max_revolutions * n > MAX_RUN_SAMPLES:
        raise ParameterError("max_revolutions", max_revolutions, f"at most "
                             f"{MAX_RUN_SAMPLES // n} at {n} positions a revolution")
    m = machine(mech, motor, loads=loads, gravity=gravity, flywheel=flywheel, gear=gear, n=n,
                breaks=breaks)
    check_inertia(m)
    ss = solve_steady(m)
    # from rest the speed grows as the square root of the angle: the first revolution on a grid
    # refined geometrically towards the start (nodes at h / 2, h / 4, ... h / 2^24)
    h = TWO_PI / n
    br = np.atleast_1d(np.asarray(breaks, dtype=float)) if np.size(breaks) else np.zeros(0)
    m0 = machine(mech, motor, loads=loads, gravity=gravity, flywheel=flywheel, gear=gear, n=n,
                 breaks=np.concatenate((br, 8.0 * h * (3 / 4) ** np.arange(0, 70))))
    ref = ss.omega
    wm = ss.omega_mean
    settled = [0]

    def stop(nodes: Arr, sol: Solution) -> bool:
        w_ss = np.interp(np.mod(nodes, TWO_PI), ss.phi1, ref, period=TWO_PI)
        dev = float(np.max(np.abs(np.sqrt(sol.u) - w_ss)))
        settled[0] = settled[0] + 1 if dev <= b * wm else 0
        return settled[0] >= 2

    run = _run([m], ["start"], [(0, max_revolutions)], 0.0, [ss], None, progress, True, stop,
               first=m0)
    if settled[0] < 2:
        raise ConvergenceError(f"the start-up is not within {b:g} of the steady state after "
                               f"{max_revolutions} revolutions (max_revolutions)")
    # the last position outside the band, against the steady omega at the same angle
    phase = np.mod(run.phi1, TWO_PI)
    w_ss = np.interp(phase, np.append(ss.phi1, TWO_PI), np.append(ref, ref[0]))
    outside = np.flatnonzero(np.abs(run.omega - w_ss) > b * wm)
    k = int(outside[-1]) + 1 if outside.size else 0
    t_steady = float(run.t[min(k, run.t.size - 1)])
    reach = np.flatnonzero(run.omega >= wm)
    kp = int(np.nanargmax(run.rev_torque_peak))
    revs = int(run.revolution[min(k, run.t.size - 1)]) + 1
    return StartUp(run, ss, b, t_steady, revs,
                   float(run.t[reach[0]]) if reach.size else math.nan,
                   float(run.rev_torque_peak[kp]), float(run.rev_t[kp]),
                   float(np.sum(run.rev_work_motor[:revs])))
