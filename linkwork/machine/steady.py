r"""The steady state of a machine unit: the crank's real periodic motion under its motor.

:func:`steady_state` reduces the mechanism to its crank (:mod:`linkwork.machine.reduction`),
adds the drive (motor characteristic, gear, rotors, flywheel) and solves the equation of motion
for its periodic solution over one revolution (:mod:`linkwork.machine.solver`): the real
:math:`\omega(\varphi)` and :math:`\varepsilon(\varphi)`, the coefficient of speed fluctuation

.. math:: \delta = \frac{\omega_{max} - \omega_{min}}{\omega_m}, \qquad
   \omega_m = \frac{2\pi}{T} \ \text{(the time mean: one revolution per period } T),

the motor's torque, speed and power over the cycle, and the engine's kinematics and inverse
dynamics (reactions, driving torque, shaking) recomputed with this real motion, beside the same
at the constant mean speed (the assumption of every constant-speed analysis).

Joint friction (:mod:`linkwork.planar.friction`) depends on the motion itself; it enters by a
fixed-point iteration: the engine's friction moment ``Q0 - Q`` at the motion of the previous
solve, until it changes by less than 1e-10 of the torque scale.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_number, require_pair
from linkwork.errors import ConvergenceError, DriveError, ParameterError, StallError
from linkwork.machine.motors import (
    ConstantSpeed,
    ConstantTorque,
    DCMotor,
    Gear,
    InductionMotor,
    Motor,
)
from linkwork.machine.reduction import (
    Loads,
    check_crank,
    friction_moment,
    load_list,
    reduce,
)
from linkwork.machine.solver import (
    Coefficients,
    Drive,
    FixedTorque,
    Grid,
    Solution,
    Stall,
    constant_speed,
    extremes,
    make_grid,
    march,
    periodic_solution,
)
from linkwork.planar import Dynamics, Kinematics, Mechanism, inverse_dynamics, kinematics
from linkwork.planar.state import Arr
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["Machine", "SteadyState", "machine", "steady_state", "torque_limit"]

TWO_PI = 2.0 * math.pi


def torque_limit(motor: Motor) -> tuple[float, str] | None:
    """The largest torque the motor gives at a stable speed, and its name: the breakdown torque
    of an induction motor, the stall torque of a DC motor; None for the ideal drives."""
    if isinstance(motor, InductionMotor):
        return motor.breakdown_torque, "breakdown torque"
    if isinstance(motor, DCMotor):
        return motor.stall_torque, "stall torque"
    return None


@dataclass(frozen=True)
class Machine:
    """A mechanism with its drive, reduced to the crank on a grid of one cycle.

    Built by :func:`machine`; ``grid`` the positions (:class:`~linkwork.machine.solver.Grid`),
    ``J, dJ, M_loads, M_gravity`` the reduction at ``grid.pts``; ``drive`` the motor, gear and
    rotors; ``loads``, ``gravity`` as given (for the engine's friction and dynamics).
    """

    mechanism: Mechanism
    motor: Motor
    gear: Gear
    flywheel: float
    grid: Grid
    J: Arr
    dJ: Arr
    M_loads: Arr
    M_gravity: Arr
    loads: Loads
    gravity: tuple[float, float] | None
    about: tuple[float, float]
    drive: Drive
    has_friction: bool
    damping: Arr | None = None

    def with_flywheel(self, flywheel: float) -> Machine:
        """The same machine with another flywheel [kg m^2] (no new engine evaluation)."""
        fw = _flywheel(flywheel)
        d = self.drive
        return Machine(self.mechanism, self.motor, self.gear, fw, self.grid, self.J, self.dJ,
                       self.M_loads, self.M_gravity, self.loads, self.gravity, self.about,
                       Drive(d.motor, d.ratio, d.eta, d.J_in, fw), self.has_friction,
                       self.damping)

    def with_motor(self, motor: Motor) -> Machine:
        """The same machine with another motor (no new engine evaluation)."""
        _check_motor(motor)
        d = self.drive
        return Machine(self.mechanism, motor, self.gear, self.flywheel, self.grid, self.J,
                       self.dJ, self.M_loads, self.M_gravity, self.loads, self.gravity,
                       self.about, Drive(motor, d.ratio, d.eta, motor.inertia + self.gear.inertia,
                                         d.J_out), self.has_friction, self.damping)

    def coefficients(self, M_friction: Arr | float = 0.0) -> Coefficients:
        return Coefficients(self.J, self.dJ, self.M_loads + self.M_gravity + M_friction,
                            self.damping)

    def integral(self, values: Arr) -> float:
        """Simpson's integral over the cycle of a quantity given at ``grid.pts`` [its unit x
        rad]."""
        g = self.grid
        return float(np.sum(g.h / 6 * (values[g.iL] + 4 * values[g.iM] + values[g.iR])))

    def mean_load_torque(self, M_friction: Arr | float = 0.0) -> float:
        """The torque the crank needs on average [N m]: ``-(1/P) integral(M) dphi``."""
        m = self.M_loads + self.M_gravity + M_friction
        return -self.integral(np.broadcast_to(m, self.J.shape)) / self.grid.period


def _flywheel(flywheel: Any) -> float:
    fw = require_number("flywheel", flywheel)
    if fw < 0:
        raise ParameterError("flywheel", fw, "must be >= 0 [kg m^2]")
    return fw


def _check_motor(motor: Any) -> None:
    if not isinstance(motor, DCMotor | InductionMotor | ConstantSpeed | ConstantTorque):
        raise ParameterError("motor", motor, "must be DCMotor, InductionMotor, ConstantSpeed "
                             "or ConstantTorque (linkwork.machine)")


def machine(mech: Mechanism, motor: Motor, *, loads: Loads = (), gravity: ArrayLike | None = None,
            flywheel: float = 0.0, gear: Gear | None = None, n: int = 360,
            breaks: ArrayLike = (), start: float = 0.0, about: ArrayLike = (0.0, 0.0)
            ) -> Machine:
    """Reduce ``mech`` with its drive over one revolution from ``start`` [rad] on about ``n``
    intervals (nodes also at the ``breaks`` [rad], where loads jump): the engine's work, done
    once for every solve on this machine (:func:`steady_state`, :func:`flywheel_for`, ...)."""
    check_crank(mech)
    _check_motor(motor)
    g = Gear() if gear is None else gear
    if not isinstance(g, Gear):
        raise ParameterError("gear", g, "must be a linkwork.machine.Gear")
    fw = _flywheel(flywheel)
    br = np.atleast_1d(require_finite("breaks", breaks)).astype(float) if len(
        np.atleast_1d(breaks)) else np.zeros(0)
    grid = make_grid(require_number("start", start), TWO_PI, n, br)
    grav = None if gravity is None else require_pair("gravity", gravity)
    red = reduce(mech, grid.pts, loads=loads, gravity=grav)
    ab = require_pair("about", about)
    drive = Drive(motor, g.ratio, g.efficiency, motor.inertia + g.inertia, fw)
    return Machine(mech, motor, g, fw, grid, red.J, red.dJ, red.M_loads, red.M_gravity, loads,
                   (float(grav[0]), float(grav[1])) if grav is not None else None,
                   (float(ab[0]), float(ab[1])), drive, any(j.has_friction for j in mech.joints),
                   red.damping if np.any(red.damping) else None)


# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SteadyState(Result):
    """The periodic steady state of a machine unit over one revolution of the crank.

    Per-position arrays (at the grid's nodes ``phi1``, about ``n`` over the revolution; at a
    node where the loads jump (``breaks``), every value is the one just after the jump,
    evaluated :data:`~linkwork.machine.solver.ONE_SIDED` past it, as are the dynamics there):

    Attributes
    ----------
    phi1 : crank angle [rad]
    t : time from the first position [s]
    omega, eps : crank speed [rad/s] and acceleration [rad/s^2] (the real motion)
    omega_motor : motor speed [rad/s]
    torque : motor torque at its shaft [N m]
    Q : torque on the mechanism's crank [N m] (the engine's driving torque of the real motion:
        the gear's output less the crank-shaft flywheel's inertia torque)
    power : motor power ``torque * omega_motor`` [W]
    J : reduced moment of inertia of the links [kg m^2] (``J_rotors`` adds the drive's)
    dJ : dJ/dphi1 [kg m^2/rad]
    M_loads, M_gravity, M_friction, M_damping : reduced moments of the external loads
        (position-dependent), gravity, joint friction and the speed-dependent loads (dampers,
        drags: ``-damping omega``) [N m] (positive driving)
    delta : coefficient of speed fluctuation ``(omega_max - omega_min) / omega_mean``
    omega_mean : the time-mean crank speed ``2 pi / period`` [rad/s]
    omega_max, omega_min, phi_max, phi_min : extreme speeds [rad/s] and where [rad] (from the
        collocation's cubic between positions)
    period : time of one revolution [s]
    torque_mean : the motor's mean torque over the crank angle ``(1/2 pi) integral(torque)
        dphi`` [N m] (its work per revolution / (2 pi i))
    torque_rms : the RMS of the motor torque over time [N m] (the thermal equivalent torque)
    torque_peak, phi_torque_peak : the largest motor torque and where [N m, rad]
    power_mean : mean motor power over time [W]
    energy : work per revolution [J]: ``motor``, ``loads`` (done on the external loads,
        dampers and drags included),
        ``gravity``, ``friction`` (dissipated in the joints), ``gear`` (lost in the gear), and
        ``residual`` = motor - the others (the solve's energy error)
    error_estimate : the largest difference of omega between this grid and every other node of
        it, over 15 (Richardson), relative to omega_mean: the solve's discretisation error
    J_rotors : the drive's rotors reduced to the crank ``J_in i^2 + J_flywheel`` [kg m^2]
    """

    phi1: Arr
    t: Arr
    omega: Arr
    eps: Arr
    omega_motor: Arr
    torque: Arr
    Q: Arr
    power: Arr
    J: Arr
    dJ: Arr
    M_loads: Arr
    M_gravity: Arr
    M_friction: Arr
    M_damping: Arr
    delta: float
    omega_mean: float
    omega_max: float
    omega_min: float
    phi_max: float
    phi_min: float
    period: float
    torque_mean: float
    torque_rms: float
    torque_peak: float
    phi_torque_peak: float
    power_mean: float
    error_estimate: float
    J_rotors: float
    flywheel: float
    iterations: int
    friction_iterations: int
    energy: dict[str, float] = field(default_factory=dict)
    motor: Motor | None = None
    gear: Gear | None = None
    kinematics: Kinematics | None = None
    dynamics: Dynamics | None = None
    kinematics_constant: Kinematics | None = None
    dynamics_constant: Dynamics | None = None
    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "t": "s", "omega": "rad/s", "eps": "rad/s^2", "omega_motor": "rad/s",
        "torque": "N*m", "Q": "N*m", "power": "W", "J": "kg*m^2", "dJ": "kg*m^2/rad",
        "M_loads": "N*m", "M_gravity": "N*m", "M_friction": "N*m", "M_damping": "N*m",
        "delta": "",
        "omega_mean": "rad/s", "omega_max": "rad/s", "omega_min": "rad/s", "phi_max": "rad",
        "phi_min": "rad", "period": "s", "torque_mean": "N*m", "torque_rms": "N*m",
        "torque_peak": "N*m", "phi_torque_peak": "rad", "power_mean": "W",
        "error_estimate": "", "J_rotors": "kg*m^2", "flywheel": "kg*m^2"}

    def comparison(self) -> list[dict[str, Any]]:
        """Peaks of the real motion beside those at the constant mean speed: the driving torque,
        every joint reaction, the shaking force and moment; each ``{"name", "unit", "real",
        "constant", "ratio"}`` (``ratio`` real over constant)."""
        dr, dc = self.dynamics, self.dynamics_constant
        if dr is None or dc is None:
            return []
        rows = [("|Q| max", np.abs(dr.Q), np.abs(dc.Q), "N*m")]
        for k, j in enumerate(dr.joints):
            rows.append((f"|R {j}| max", np.hypot(dr.fx[k], dr.fy[k]),
                         np.hypot(dc.fx[k], dc.fy[k]), "N"))
        rows += [("|F_sh| max", np.hypot(dr.shaking_fx, dr.shaking_fy),
                  np.hypot(dc.shaking_fx, dc.shaking_fy), "N"),
                 ("|M_sh| max", np.abs(dr.shaking_m), np.abs(dc.shaking_m), "N*m")]
        out = []
        for name, a, b, unit in rows:
            ra, rb = float(np.nanmax(a)), float(np.nanmax(b))
            out.append({"name": name, "unit": unit, "real": ra, "constant": rb,
                        "ratio": ra / rb if rb > 0 else None})
        return out

    def to_dict(self) -> dict[str, Any]:
        data = super().to_dict()
        data["energy"] = dict(self.energy)
        data["motor"] = None if self.motor is None else self.motor.describe()
        data["gear"] = None if self.gear is None else self.gear.describe()
        data["comparison"] = self.comparison()
        return data

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Crank speed and motor torque over the crank angle: a :class:`linkwork.plot.Figure`
        with 2 axes (:mod:`linkwork.plot.machine`)."""
        from linkwork.plot.machine import steady_figure

        return steady_figure(self, axes=axes, **kw)


# ---------------------------------------------------------------------------------------------
def at_points(m: Machine, sol: Solution) -> tuple[Arr, Arr, Arr]:
    """u, eps and the motor torque at every evaluation position of the grid."""
    g = m.grid
    npts = g.pts.size
    u = np.empty(npts)
    eps = np.empty(npts)
    a = np.empty(npts)
    n = g.n  # the nodes themselves (a node at a jump is no interval's end: its right side)
    u[:n], eps[:n], a[:n] = sol.uL, 0.5 * sol.FL, sol.aL
    for idx, uu, ff, aa in ((g.iL, sol.uL, sol.FL, sol.aL), (g.iM, sol.uM, sol.FM, sol.aM),
                            (g.iR, sol.uR, sol.FR, sol.aR)):
        u[idx], eps[idx], a[idx] = uu, 0.5 * ff, aa
    return u, eps, a


def at_motor(d: Drive, crank_torque: float) -> float:
    """The motor torque that gives ``crank_torque`` [N m] at the crank through the gear
    (efficiency against the power's direction), rotors at rest."""
    if crank_torque >= 0:
        return crank_torque / (d.ratio * d.eta)
    return crank_torque * d.eta / d.ratio


def check_inertia(m: Machine) -> None:
    """The machine must have inertia at every position (links, rotors, flywheel): without it
    the equation of motion has no solution where a load acts (ParameterError naming where)."""
    total = m.J + m.drive.J_out + m.drive.J_in * m.drive.ratio**2 * m.drive.eta
    k = int(np.argmin(total))
    if not total[k] > 1e-300:
        raise ParameterError("inertia", f"{total[k]:.3g} kg·m² at phi1 = "
                             f"{math.degrees(m.grid.pts[k]) % 360:.1f} deg",
                             "must be > 0: the links, the motor's rotor, the gear and the "
                             "flywheel have no moment of inertia about the crank there; give "
                             "the rotor's inertia or a flywheel")


def check_feasible(m: Machine, M_friction: Arr | float = 0.0) -> float:
    """The mean load torque at the crank [N m], after checking that the motor can give it at a
    stable speed through the gear (else :class:`~linkwork.errors.DriveError`)."""
    need = m.mean_load_torque(M_friction)
    d = m.drive
    motor_side = at_motor(d, need)
    lim = torque_limit(m.motor)
    if lim is not None and motor_side >= lim[0]:
        via = ("" if d.ratio == 1.0 and d.eta == 1.0 else
               f" ({motor_side:.4g} N·m at the motor through the gear i = {d.ratio:.4g}, "
               f"efficiency {d.eta:.4g})")
        raise DriveError(f"mean load torque {need:.4g} N·m{via} exceeds the motor's "
                         f"{lim[1]} {lim[0]:.4g} N·m: {m.motor.name} cannot drive the machine at "
                         "any stable speed")
    return need


def _guess(m: Machine, need: float) -> tuple[float, float | None]:
    """Initial crank speed [rad/s] (from the motor's stable speed at the mean load torque) and,
    for a ConstantTorque drive, its torque."""
    d = m.drive
    if isinstance(m.motor, ConstantTorque):
        return m.motor.mean_speed / d.ratio, at_motor(d, need)
    return m.motor.speed_at(at_motor(d, need)) / d.ratio, None


def _stall_error(m: Machine, exc: Stall, what: str) -> StallError:
    lim = torque_limit(m.motor)
    peak = float(-np.min(m.M_loads + m.M_gravity))
    lim_s = "" if lim is None else f" ({lim[1]} {lim[0]:.4g} N·m at the motor)"
    return StallError(f"the crank stops at phi1 = {math.degrees(exc.phi) % 360:.1f} deg ({what}): "
                      f"{m.motor.name}{lim_s} cannot carry the machine over its peak load torque "
                      f"{peak:.4g} N·m at the crank with the rotors' inertia "
                      f"{m.drive.rotors:.4g} kg·m² reduced to the crank; a flywheel or a "
                      "stronger motor is needed")


def solve_cycle(m: Machine, M_friction: Arr | float, u0: Arr | None, torque0: float | None,
                need: float) -> Solution:
    """The periodic solution for a given friction moment: Newton from ``u0`` (or from the
    constant stable speed); if Newton fails, a march over up to 200 revolutions to a state near
    the cycle, and Newton again from there."""
    co = m.coefficients(M_friction)
    if isinstance(m.motor, ConstantSpeed):
        return constant_speed(m.grid, co, m.drive)
    if u0 is None:
        w0, torque0 = _guess(m, need)
        u0 = np.full(m.grid.n, w0 * w0)
    try:
        return periodic_solution(m.grid, co, m.drive, u0, torque0)
    except ConvergenceError:
        pass
    g = m.grid
    u = float(np.mean(u0))
    last = None
    drive = m.drive
    if isinstance(m.motor, ConstantTorque):  # marched with its torque at the mean load's
        d = m.drive
        drive = Drive(FixedTorque(at_motor(d, need)), d.ratio, d.eta, d.J_in, d.J_out)
    for cycle in range(200):
        try:
            sol = march(g.nodes, g.iL, g.iM, g.iR, co, drive, u)
        except Stall as exc:
            raise _stall_error(m, exc, f"revolution {cycle + 1} from the mean speed"
                               ) from None
        u = float(sol.u[-1])
        if last is not None and np.max(np.abs(sol.u[:-1] - last)) <= 1e-4 * u:
            break
        last = sol.u[:-1]
    try:
        return periodic_solution(m.grid, co, m.drive, sol.u[:-1], torque0)
    except ConvergenceError as exc:
        raise ConvergenceError(f"the periodic solve did not converge ({exc}), also from a state "
                               "marched near the steady cycle") from None


def steady_state(mech: Mechanism | Machine, motor: Motor | None = None, *, loads: Loads = (),
                 gravity: ArrayLike | None = None, flywheel: float = 0.0,
                 gear: Gear | None = None, n: int = 360, breaks: ArrayLike = (),
                 about: ArrayLike = (0.0, 0.0), dynamics: bool = True) -> SteadyState:
    """The periodic steady state of a mechanism driven by ``motor`` (a periodic solve).

    Parameters
    ----------
    mech : Mechanism or Machine
        Driven by a :class:`~linkwork.planar.Crank` on a frame joint; or a :func:`machine`
        already reduced (then ``motor`` and the other keywords but ``dynamics`` are its own).
    motor : DCMotor, InductionMotor, ConstantSpeed or ConstantTorque
    loads : sequence of PointForce/BodyTorque or a function of the crank angles returning one
        External loads (:data:`linkwork.machine.reduction.Loads`).
    gravity : (gx, gy), optional
        Gravity [m/s^2].
    flywheel : float
        Flywheel on the crank shaft [kg m^2].
    gear : Gear, optional
        Between motor and crank (default: direct drive).
    n : int
        Positions over the revolution (about; even).
    breaks : array_like
        Crank angles [rad] where loads jump (nodes there, one-sided values).
    about : (x, y)
        Point of the shaking moment [m].
    dynamics : bool
        Also the engine's kinematics and inverse dynamics at the real and at the constant
        speed.

    Returns
    -------
    SteadyState

    Raises
    ------
    DriveError
        The motor cannot carry the mean load at any stable speed (naming the mean load torque
        and the motor's breakdown or stall torque), or the crank stops within the cycle.
    """
    if isinstance(mech, Machine):
        m = mech
    else:
        if motor is None:
            raise ParameterError("motor", None, "must be given (a linkwork.machine motor)")
        m = machine(mech, motor, loads=loads, gravity=gravity, flywheel=flywheel, gear=gear,
                    n=n, breaks=breaks, about=about)
    return solve_steady(m, dynamics=dynamics)


def solve_steady(m: Machine, *, dynamics: bool = True, u0: Arr | None = None,
                 M_friction0: Arr | None = None) -> SteadyState:
    """:func:`steady_state` of a reduced :class:`Machine` (warm start ``u0`` at the nodes and
    ``M_friction0`` at the grid's positions, from a previous solve)."""
    g = m.grid
    Mf: Arr | float = 0.0
    if not isinstance(m.motor, ConstantSpeed):
        check_inertia(m)
    need = check_feasible(m)
    torque0 = None
    if m.has_friction:
        if M_friction0 is not None:
            Mf = M_friction0
        else:
            w0, _ = _guess(m, need)
            Mf = friction_moment(m.mechanism, g.pts, w0, 0.0, loads=m.loads, gravity=m.gravity)
        need = check_feasible(m, Mf)
    sol = solve_cycle(m, Mf, u0, torque0, need)
    fits = 0
    if m.has_friction:
        scale = float(np.max(np.abs(m.M_loads + m.M_gravity)) + np.max(np.abs(m.dJ)) * np.max(
            sol.u) + np.max(np.abs(Mf)) + 1e-300)
        for fits in range(1, 201):  # noqa: B007 (the count is reported)
            u, eps, _ = at_points(m, sol)
            Mf_new = friction_moment(m.mechanism, g.pts, np.sqrt(u), eps, loads=m.loads,
                                     gravity=m.gravity)
            change = float(np.max(np.abs(Mf_new - Mf)))
            Mf = Mf_new
            sol = solve_cycle(m, Mf, sol.u if sol.u.size == g.n else None, sol.torque, need)
            if change <= 1e-10 * scale:
                break
        else:
            raise ConvergenceError("the friction iteration of the steady state did not converge "
                                   "in 200 steps")
    return _result(m, sol, np.broadcast_to(Mf, g.pts.shape).astype(float), fits, dynamics)


def _result(m: Machine, sol: Solution, Mf: Arr, fits: int, dynamics: bool) -> SteadyState:
    g = m.grid
    d = m.drive
    nodes = g.nodes[:-1]
    u = sol.u[: g.n]
    omega = np.sqrt(u)
    eps = 0.5 * sol.FL
    period = float(np.sum(sol.dt))
    t = np.concatenate(([0.0], np.cumsum(sol.dt)[:-1]))
    omega_mean = g.period / period
    u_max, p_max, u_min, p_min = extremes(g.nodes, sol)
    if isinstance(m.motor, ConstantSpeed):
        u_max = u_min = float(u[0])
        p_max = p_min = float(nodes[0])
    if not u_min > 0:  # the collocation's cubic through the nodes dips to zero: a stall
        raise _stall_error(m, Stall(p_min, 0), "within the steady cycle")
    w_max, w_min = math.sqrt(u_max), math.sqrt(u_min)
    torque = sol.aL
    i, eta = d.ratio, d.eta
    m_in = torque - d.J_in * i * eps
    crank = np.where(m_in >= 0, i * eta * m_in, i * m_in / eta) - d.J_out * eps
    # work per revolution by Simpson's rule over the intervals (a at the three points)
    u_p, eps_p, a_p = at_points(m, sol)
    w_motor = i * m.integral(a_p)
    min_p = a_p - d.J_in * i * eps_p
    w_in = i * m.integral(min_p)
    w_out = m.integral(np.where(min_p >= 0, i * eta * min_p, i * min_p / eta))
    w_damp = m.integral(m.damping * np.sqrt(u_p)) if m.damping is not None else 0.0
    energy = {"motor": w_motor, "loads": -m.integral(m.M_loads) + w_damp,
              "gravity": -m.integral(m.M_gravity), "friction": -m.integral(Mf),
              "gear": w_in - w_out}
    energy["residual"] = w_motor - (energy["loads"] + energy["gravity"] + energy["friction"]
                                    + energy["gear"])
    with np.errstate(divide="ignore", invalid="ignore"):
        wL, wM, wR = np.sqrt(sol.uL), np.sqrt(sol.uM), np.sqrt(sol.uR)
        sq = g.h / 6 * (sol.aL**2 / wL + 4 * sol.aM**2 / wM + sol.aR**2 / wR)
    rms = math.sqrt(float(np.sum(sq)) / period)
    peaks = np.concatenate((sol.aL, sol.aM))
    ppos = np.concatenate((nodes, nodes + 0.5 * g.h))
    kpk = int(np.argmax(peaks))
    err = _error_estimate(m, sol, Mf, omega_mean)
    kin = dyn = kin_c = dyn_c = None
    if dynamics:  # at a jump of the loads: just after it, as the reduced arrays
        at = g.pts[g.iL]
        lds = load_list(m.loads, at)
        kin = kinematics(m.mechanism, at, omega, eps)
        dyn = inverse_dynamics(kin, gravity=m.gravity, loads=lds, about=m.about)
        kin_c = kinematics(m.mechanism, at, omega_mean, 0.0)
        dyn_c = inverse_dynamics(kin_c, gravity=m.gravity, loads=lds, about=m.about)
    return SteadyState(
        phi1=nodes, t=t, omega=omega, eps=eps, omega_motor=i * omega, torque=torque, Q=crank,
        power=torque * i * omega, J=m.J[g.iL], dJ=m.dJ[g.iL], M_loads=m.M_loads[g.iL],
        M_gravity=m.M_gravity[g.iL], M_friction=Mf[g.iL],
        M_damping=(np.zeros(g.n) if m.damping is None else -m.damping[g.iL] * omega),
        delta=(w_max - w_min) / omega_mean, omega_mean=omega_mean, omega_max=w_max,
        omega_min=w_min, phi_max=p_max, phi_min=p_min, period=period,
        torque_mean=w_motor / (i * g.period), torque_rms=rms, torque_peak=float(peaks[kpk]),
        phi_torque_peak=float(ppos[kpk]), power_mean=w_motor / period, error_estimate=err,
        J_rotors=d.rotors, flywheel=m.flywheel, iterations=sol.iterations,
        friction_iterations=fits, energy=energy, motor=m.motor, gear=m.gear, kinematics=kin,
        dynamics=dyn, kinematics_constant=kin_c, dynamics_constant=dyn_c)


def _error_estimate(m: Machine, sol: Solution, Mf: Arr, omega_mean: float) -> float:
    """Richardson: the fourth-order solution on every other node against this one."""
    if isinstance(m.motor, ConstantSpeed):
        return 0.0
    try:
        coarse = periodic_solution(m.grid, m.coefficients(Mf), m.drive, sol.u[0::2],
                                   sol.torque, coarse=True)
    except ConvergenceError:
        return float("nan")
    diff = np.abs(np.sqrt(coarse.u) - np.sqrt(sol.u[0::2]))
    return float(np.max(diff)) / 15.0 / omega_mean
