r"""Flywheel sizing for a coefficient of speed fluctuation: exact, and the two classical ways.

**Exact** (:func:`flywheel_for`): the flywheel :math:`J_F` on the crank shaft for which the
periodic steady state (:func:`~linkwork.machine.steady.steady_state`, with the motor's real
characteristic, the variable reduced inertia, the gear and friction) has
:math:`\delta(J_F) = \delta`; :math:`1/\delta` is nearly linear in :math:`J_F`, so a
safeguarded secant method on it finds :math:`J_F` in a few periodic solves (no new engine
evaluation: the reduction is done once), to :math:`|\delta/\delta_{asked} - 1| < 10^{-9}`.

**Energy method with constant inertia** (:func:`energy_method`; Norton, *Design of Machinery*,
ch. 11; Shigley): the torque the crank needs at the constant mean speed :math:`\omega_m`
(kinetostatics, :math:`Q_c = \tfrac12 J'\omega_m^2 - M`, the links' inertia torques included)
against a constant driving torque equal to its mean; the largest swing of the excess work
:math:`\Delta E_{max} = \max - \min \int (\bar Q_c - Q_c)\,d\varphi` must be taken by a constant
inertia: :math:`J_F = \Delta E_{max}/(\delta\omega_m^2) - \bar J - J_{rotors}` (the mean reduced
inertia of the links and the drive's rotors already turn with the crank; Norton's form omits
them, which is larger by that much).

**Wittenbauer's energy-mass diagram** (:func:`wittenbauer`; Artobolevsky, *Theory of
Mechanisms and Machines*, the dynamics of machine units): the change of kinetic energy
:math:`\Delta E(\varphi) = \int (M_d + M)\,d\varphi` (constant driving torque :math:`M_d`, the
loads' reduced moment :math:`M`, no inertia torques) against the variable reduced inertia
:math:`J(\varphi)`; the tangents to this curve of slopes :math:`\omega_{max}^2/2` and
:math:`\omega_{min}^2/2` (:math:`\omega_{max,min} = \omega_m(1 \pm \delta/2)`) meet at the
origin of the kinetic energy and inertia axes, at :math:`J = -J_F`:

.. math:: J_F = \frac{b_{max} - b_{min}}{(\omega_{max}^2 - \omega_{min}^2)/2}, \quad
   b_{max} = \max_\varphi\left(\Delta E - \tfrac{\omega_{max}^2}{2} J\right), \quad
   b_{min} = \min_\varphi\left(\Delta E - \tfrac{\omega_{min}^2}{2} J\right).

It takes the variable inertia exactly; it assumes a constant driving torque (no motor slope)
and the mean speed as :math:`(\omega_{max} + \omega_{min})/2`. With a
:class:`~linkwork.machine.motors.ConstantTorque` drive and those definitions it is exact, which
``tests/machine/test_flywheel.py`` uses to check the exact solve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_number
from linkwork.errors import DriveError, ParameterError, StallError
from linkwork.machine.motors import ConstantSpeed, ConstantTorque, Gear, Motor
from linkwork.machine.reduction import Loads, friction_moment
from linkwork.machine.solver import hermite_extremes
from linkwork.machine.steady import (
    Machine,
    SteadyState,
    at_motor,
    check_feasible,
    machine,
    solve_steady,
)
from linkwork.planar import Mechanism
from linkwork.planar.state import Arr

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["DELTA_MIN", "MAX_FLYWHEEL", "FlywheelSizing", "energy_method", "flywheel_for",
           "nominal_speed", "wittenbauer"]

#: The smallest coefficient of speed fluctuation sized: below it the fluctuation is within the
#: periodic solve's resolution (its Newton steps stop at 1e-12 of omega^2), so that delta
#: itself, not the flywheel, would be uncertain by 1e-4.
DELTA_MIN = 1e-6

#: The largest flywheel searched [kg m^2] (the file layer's limit of any inertia).
MAX_FLYWHEEL = 1e12


def nominal_speed(m: Machine, M_friction: Arr | float = 0.0) -> float:
    """The crank speed the classical methods take as the mean [rad/s]: the motor's stable speed
    at the mean load torque (through the gear), or a ConstantTorque drive's mean speed."""
    d = m.drive
    if isinstance(m.motor, ConstantTorque):
        return m.motor.mean_speed / d.ratio
    return m.motor.speed_at(at_motor(d, m.mean_load_torque(M_friction))) / d.ratio


def _cumulative(m: Machine, values: Arr) -> Arr:
    """The integral from the first node of a quantity given at the grid's positions, at every
    node (Simpson per interval), (N + 1,)."""
    g = m.grid
    inc = g.h / 6 * (values[g.iL] + 4 * values[g.iM] + values[g.iR])
    return np.concatenate(([0.0], np.cumsum(inc)))


def _friction_at(m: Machine, omega: float) -> Arr:
    if not m.has_friction:
        return np.zeros(m.grid.pts.shape)
    return friction_moment(m.mechanism, m.grid.pts, omega, 0.0, loads=m.loads, gravity=m.gravity)


def energy_method(m: Machine, delta: float, omega_mean: float | None = None) -> dict[str, Any]:
    """The energy method with constant inertia (see the module docstring): ``{"flywheel",
    "dE_max" [J], "omega_mean" [rad/s], "J_mean" [kg m^2]}``; the flywheel is 0 where the
    mean inertia alone suffices."""
    w = nominal_speed(m) if omega_mean is None else omega_mean
    mf = _friction_at(m, w)
    qc = 0.5 * m.dJ * w * w - (m.M_loads + m.M_gravity + mf)
    mean = m.integral(qc) / m.grid.period
    excess = _cumulative(m, mean - qc)
    de = float(np.max(excess) - np.min(excess))
    j_mean = m.integral(m.J) / m.grid.period
    total = de / (delta * w * w)
    return {"flywheel": max(total - j_mean - m.drive.rotors, 0.0), "dE_max": de,
            "omega_mean": w, "J_mean": j_mean}


def wittenbauer(m: Machine, delta: float, omega_mean: float | None = None) -> dict[str, Any]:
    """Wittenbauer's energy-mass diagram (see the module docstring): ``{"flywheel", "J"
    (reduced inertia of links and rotors at the nodes), "dE" (change of kinetic energy at the
    nodes [J]), "k_max", "k_min" (the tangents' slopes omega^2/2), "b_max", "b_min" (their
    intercepts [J]), "omega_mean"}``; the flywheel is 0 where none is needed."""
    w = nominal_speed(m) if omega_mean is None else omega_mean
    mc = m.M_loads + m.M_gravity + _friction_at(m, w)
    md = -m.integral(mc) / m.grid.period
    g = m.grid
    dE = _cumulative(m, md + mc)
    jt = m.J + m.drive.rotors  # links and the rotors there are (a flywheel given included)
    k_max, k_min = 0.5 * (w * (1 + delta / 2)) ** 2, 0.5 * (w * (1 - delta / 2)) ** 2
    J_nodes = np.append(jt[g.iL], jt[g.iR[-1]])
    slope = md + mc  # d(dE)/dphi
    out: dict[str, Any] = {"J": J_nodes[:-1], "dE": dE[:-1], "k_max": k_max, "k_min": k_min,
                           "omega_mean": w}
    for k, key, pick in ((k_max, "b_max", 0), (k_min, "b_min", 2)):
        f = dE - k * J_nodes
        ext = hermite_extremes(g.nodes, f[:-1], f[1:], slope[g.iL] - k * m.dJ[g.iL],
                               slope[g.iR] - k * m.dJ[g.iR])
        out[key] = ext[pick]
    out["flywheel"] = max((out["b_max"] - out["b_min"]) / (k_max - k_min), 0.0)
    return out


@dataclass(frozen=True)
class FlywheelSizing:
    """The flywheel for a coefficient of speed fluctuation, exact and by the classical methods.

    Attributes
    ----------
    delta : float
        The coefficient asked.
    flywheel : float
        Exact flywheel on the crank shaft [kg m^2] (0: the machine meets ``delta`` without one).
    energy_method, wittenbauer_flywheel : float
        The classical approximations [kg m^2].
    deviation_energy, deviation_wittenbauer : float or None
        Their relative deviations from the exact flywheel ``(approx - exact) / exact`` (None
        where the exact one is 0).
    omega_nominal : float
        The mean speed the classical methods took [rad/s].
    delta_without : float
        delta with no flywheel.
    steady : SteadyState
        The steady state with the exact flywheel.
    wittenbauer : dict
        The energy-mass diagram (:func:`wittenbauer`).
    energy : dict
        The energy method's figures (:func:`energy_method`).
    iterations : int
        Periodic solves of the search.
    """

    delta: float
    flywheel: float
    energy_method: float
    wittenbauer_flywheel: float
    deviation_energy: float | None
    deviation_wittenbauer: float | None
    omega_nominal: float
    delta_without: float
    steady: SteadyState
    wittenbauer: dict[str, Any] = field(repr=False)
    energy: dict[str, Any] = field(repr=False)
    iterations: int = 0

    def to_dict(self) -> dict[str, Any]:
        """The sizing as JSON-able values (the diagram's arrays as lists)."""
        w = self.wittenbauer
        return {
            "delta": self.delta, "flywheel": self.flywheel, "energy_method": self.energy_method,
            "wittenbauer": self.wittenbauer_flywheel,
            "deviation_energy": self.deviation_energy,
            "deviation_wittenbauer": self.deviation_wittenbauer,
            "omega_nominal": self.omega_nominal, "delta_without": self.delta_without,
            "delta_reached": self.steady.delta, "iterations": self.iterations,
            "dE_max": self.energy["dE_max"], "J_mean": self.energy["J_mean"],
            "energy_mass": {"J": w["J"].tolist(), "dE": w["dE"].tolist(), "k_max": w["k_max"],
                            "k_min": w["k_min"], "b_max": w["b_max"], "b_min": w["b_min"]},
            "units": {"flywheel": "kg*m^2", "omega_nominal": "rad/s", "dE_max": "J",
                      "J_mean": "kg*m^2", "J": "kg*m^2", "dE": "J", "k_max": "J/(kg*m^2)",
                      "b_max": "J"},
        }

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The energy-mass diagram with its tangents (:mod:`linkwork.plot.machine`)."""
        from linkwork.plot import Figure
        from linkwork.plot.machine import plot_energy_mass

        return Figure.of(plot_energy_mass(self, ax=ax, **kw))


def _delta_arg(delta: Any) -> float:
    d = require_number("delta", delta)
    if not d > 0.0:
        raise ParameterError("delta", d, "must be > 0: (omega_max - omega_min) / omega_mean")
    if d < DELTA_MIN:
        raise DriveError(f"delta {d:.3g} cannot be sized: it is below {DELTA_MIN:g}, the "
                         "resolution of the periodic solve (a speed fluctuation that small is "
                         "not determined, nor therefore the flywheel)")
    return d


def flywheel_for(mech: Mechanism | Machine, motor: Motor | None = None, delta: float = 0.05, *,
                 loads: Loads = (), gravity: ArrayLike | None = None, gear: Gear | None = None,
                 n: int = 360, breaks: ArrayLike = (), about: ArrayLike = (0.0, 0.0),
                 max_flywheel: float = MAX_FLYWHEEL) -> FlywheelSizing:
    """The flywheel on the crank shaft [kg m^2] for the coefficient of speed fluctuation
    ``delta``: exact (by the periodic solve) and by the energy method and Wittenbauer's
    diagram, with how far each is from the exact value.

    Parameters
    ----------
    mech, motor : Mechanism and motor, or a reduced :func:`~linkwork.machine.steady.machine`
        (its flywheel, if any, counts as already there: the result is the one to add).
    delta : float
        ``(omega_max - omega_min) / omega_mean`` asked, >= :data:`DELTA_MIN` (it may exceed 2
        where the crank crawls through a load: the time mean is then low).
    loads, gravity, gear, n, breaks, about
        As :func:`~linkwork.machine.steady.steady_state`.
    max_flywheel : float
        The largest flywheel acceptable [kg m^2].

    Raises
    ------
    DriveError
        A ConstantSpeed drive (its delta is 0 with any flywheel); the motor cannot drive the
        machine; ``delta`` is not reached with a flywheel up to ``max_flywheel`` (naming the
        delta left); ``delta`` below :data:`DELTA_MIN`.
    """
    d = _delta_arg(delta)
    fmax = require_number("max_flywheel", max_flywheel)
    if not fmax > 0:
        raise ParameterError("max_flywheel", fmax, "must be > 0 [kg m^2]")
    if isinstance(mech, Machine):
        m = mech
    else:
        if motor is None:
            raise ParameterError("motor", None, "must be given (a linkwork.machine motor)")
        m = machine(mech, motor, loads=loads, gravity=gravity, gear=gear, n=n, breaks=breaks,
                    about=about)
    if isinstance(m.motor, ConstantSpeed):
        raise DriveError(f"{m.motor.name} holds the speed: delta is 0 with any flywheel; "
                         "size a flywheel for a motor with a speed-torque characteristic")
    base = m.flywheel
    check_feasible(m)
    s0: SteadyState | None
    try:
        s0 = solve_steady(m, dynamics=False)
    except (StallError, ParameterError):  # without a flywheel the crank stops (or the
        s0 = None                          # machine has no inertia): delta "infinite"
    mf = s0.M_friction.mean() if (s0 is not None and m.has_friction) else 0.0
    w_nom = nominal_speed(m, mf)
    em = energy_method(m, d, w_nom)
    wb = wittenbauer(m, d, w_nom)
    iterations = 1
    if s0 is not None and s0.delta <= d:
        exact, ss = 0.0, solve_steady(m)
    else:
        exact, ss, iterations = _search(m, d, s0, fmax - base, em["flywheel"])
    dev = None if exact <= 0 else (em["flywheel"] - exact) / exact
    dvw = None if exact <= 0 else (wb["flywheel"] - exact) / exact
    return FlywheelSizing(d, exact, em["flywheel"], wb["flywheel"], dev, dvw, w_nom,
                          math.inf if s0 is None else s0.delta, ss, wb, em, iterations)


def _search(m: Machine, d: float, s0: SteadyState | None, fmax: float, guess: float
            ) -> tuple[float, SteadyState, int]:
    """The flywheel (added to ``m``'s) that gives ``delta = d``: the secant method on
    ``g(J) = 1/delta(J) - 1/d`` (nearly linear in J), kept inside the bracket found so far
    (bisection where the secant leaves it). A flywheel with which the crank stops counts as
    too small (delta infinite)."""
    base = m.flywheel
    scale = max(m.drive.rotors + m.integral(m.J) / m.grid.period, 1e-12)
    lo, hi = 0.0, math.inf
    x_prev, g_prev = 0.0, (-1.0 / d if s0 is None else 1.0 / s0.delta - 1.0 / d)
    x = min(guess if guess > 0 else scale, fmax)
    best = s0
    s: SteadyState | None = None
    for count in range(2, 200):
        try:
            s = solve_steady(m.with_flywheel(base + x), dynamics=False,
                             u0=None if best is None else best.omega**2)
        except StallError:
            s = None
        gx = -1.0 / d if s is None else 1.0 / s.delta - 1.0 / d
        if s is not None and abs(s.delta / d - 1.0) <= 1e-9:
            return x, solve_steady(m.with_flywheel(base + x), u0=s.omega**2), count
        if gx < 0:
            lo = x
            if x >= fmax:
                left = "the crank stops" if s is None else f"it leaves delta = {s.delta:.4g}"
                raise DriveError(f"delta {d:.4g} cannot be reached with a flywheel up to "
                                 f"{fmax + base:.4g} kg·m² (max_flywheel): {left}")
        else:
            hi = x
        best = s if s is not None else best
        xn = x - gx * (x - x_prev) / (gx - g_prev) if gx != g_prev else math.nan
        x_prev, g_prev = x, gx
        upper = min(hi, fmax, 10 * max(x, scale))
        if not (lo < xn < upper) or not math.isfinite(xn):
            xn = 0.5 * (lo + hi) if math.isfinite(hi) else upper
        x = xn
    raise DriveError(f"the flywheel search for delta {d:.4g} did not converge in 200 solves "
                     f"(bracket {lo:.6g} .. {hi:.6g} kg·m²)")
