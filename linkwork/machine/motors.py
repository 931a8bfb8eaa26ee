r"""Motors and the gear stage of a machine unit: their speed-torque characteristics.

A motor turns at ``omega_m`` [rad/s] (its shaft, positive in the sense that drives the crank
forward) and gives the torque ``torque(omega_m)`` [N m]; ``slope(omega_m)`` is its derivative
[N m s/rad]. Between motor and crank a :class:`Gear` of ratio ``i = omega_m / omega1`` (> 0),
efficiency ``eta`` and inertia (referred to its input, the motor shaft) may sit.

* :class:`DCMotor` -- the linear characteristic of a separately excited (or permanent-magnet)
  DC motor at constant voltage, :math:`M = M_s (1 - \omega_m/\omega_0)` (stall torque
  :math:`M_s`, no-load speed :math:`\omega_0`); also from rated data
  (:meth:`DCMotor.from_rated`).
* :class:`InductionMotor` -- a three-phase cage induction motor by Kloss's formula from its
  catalogue data (rated power and speed, synchronous speed, breakdown-torque ratio):

  .. math:: M(s) = \frac{2 M_k}{s/s_k + s_k/s}, \qquad s = 1 - \omega_m/\omega_s,
     \qquad s_k = s_r\,(\lambda + \sqrt{\lambda^2 - 1}),

  with :math:`M_k = \lambda M_r`, :math:`M_r = P_r/\omega_r`, :math:`s_r = 1 - \omega_r/\omega_s`
  (the root with :math:`s_k > s_r`: the rated point lies on the stable branch
  :math:`0 < s < s_k`, where the torque falls as the speed rises). The formula is used over the
  whole speed range (start-up runs through the unstable branch :math:`s > s_k`); it neglects
  the stator resistance and the current displacement in the rotor bars, so its starting torque
  :math:`2 M_k s_k/(1 + s_k^2)` is below the catalogue value of most cage motors (conservative
  for start-up times).
* :class:`ConstantSpeed` -- an ideal servo drive that holds the motor speed whatever the load
  (the assumption of every constant-speed analysis); its torque follows from the load.
* :class:`ConstantTorque` -- an ideal drive of constant torque whose value keeps a given mean
  speed: the textbooks' assumption for flywheel sizing (energy method, Wittenbauer); a negative
  torque is a constant resistance (an engine driving a machine of constant load).

References
----------
.. [1] Kloss formula: e.g. Fischer, R., *Elektrische Maschinen*, Hanser, ch. on the induction
   machine; Artobolevsky, I. I., *Theory of Mechanisms and Machines*, ch. on the dynamics of
   machine units (mechanical characteristics of motors).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from linkwork.checks import require_number
from linkwork.errors import InfeasibleError, ParameterError

__all__ = ["ConstantSpeed", "ConstantTorque", "DCMotor", "Gear", "InductionMotor", "Motor"]


def _positive(name: str, value: Any, *, allow_zero: bool = False) -> float:
    v = require_number(name, value)
    if v < 0 or (v == 0 and not allow_zero):
        raise ParameterError(name, v, "must be >= 0" if allow_zero else "must be > 0")
    return v


def _optional_positive(name: str, value: Any) -> float | None:
    return None if value is None else _positive(name, value)


class Motor:
    """What every motor has: a name, its rotor inertia, the torque it may give.

    ``kind`` names the model; ``inertia`` [kg m^2] is the rotor's; ``max_torque`` [N m] the
    largest torque on the stable part of the characteristic (the breakdown torque of an
    induction motor, the stall torque of a DC motor; None: not limited); ``rated_torque`` [N m]
    the continuous (thermal) rating, None where not given.
    """

    kind: ClassVar[str] = "motor"
    name: str
    inertia: float
    max_torque: float | None
    rated_torque: float | None

    def torque(self, omega_m: Any) -> Any:
        """Torque [N m] at the shaft speed ``omega_m`` [rad/s] (float or array)."""
        raise NotImplementedError

    def slope(self, omega_m: Any) -> Any:
        """``d torque / d omega_m`` [N m s/rad] (float or array)."""
        raise NotImplementedError

    def speed_at(self, torque: float) -> float:
        """The shaft speed [rad/s] at which the motor gives ``torque`` on its stable branch.

        Raises
        ------
        InfeasibleError
            ``torque`` exceeds what the motor gives at any stable speed.
        """
        raise NotImplementedError

    def describe(self) -> str:
        """One line: the model and its data, for tables and verdicts."""
        raise NotImplementedError


@dataclass(frozen=True)
class DCMotor(Motor):
    """DC motor with the linear characteristic ``M = M_s (1 - omega_m / omega_0)``.

    Parameters
    ----------
    stall_torque : float
        Torque at standstill ``M_s`` [N m], > 0.
    no_load_speed : float
        Speed without load ``omega_0`` [rad/s], > 0.
    inertia : float
        Rotor inertia [kg m^2], >= 0.
    rated_torque : float, optional
        Continuous torque rating [N m] (thermal limit of the RMS torque).
    peak_torque : float, optional
        Largest torque allowed (commutation, current limit) [N m]; default the stall torque.
    name : str
        A label for tables.
    """

    stall_torque: float
    no_load_speed: float
    inertia: float = 0.0
    rated_torque: float | None = None
    peak_torque: float | None = None
    name: str = "DC motor"
    kind: ClassVar[str] = "dc"

    def __post_init__(self) -> None:
        object.__setattr__(self, "stall_torque", _positive("stall_torque", self.stall_torque))
        object.__setattr__(self, "no_load_speed",
                           _positive("no_load_speed", self.no_load_speed))
        object.__setattr__(self, "inertia", _positive("inertia", self.inertia, allow_zero=True))
        object.__setattr__(self, "rated_torque",
                           _optional_positive("rated_torque", self.rated_torque))
        object.__setattr__(self, "peak_torque",
                           _optional_positive("peak_torque", self.peak_torque))

    @classmethod
    def from_rated(cls, rated_power: float, rated_speed: float, no_load_speed: float, *,
                   inertia: float = 0.0, peak_torque: float | None = None,
                   name: str = "DC motor") -> DCMotor:
        """The linear characteristic through the rated point and the no-load speed.

        ``rated_power`` [W] at ``rated_speed`` [rad/s] gives the rated torque
        ``M_r = P_r / omega_r``; the line through ``(omega_r, M_r)`` and ``(omega_0, 0)`` has the
        stall torque ``M_s = M_r omega_0 / (omega_0 - omega_r)``.
        """
        p = _positive("rated_power", rated_power)
        wr = _positive("rated_speed", rated_speed)
        w0 = _positive("no_load_speed", no_load_speed)
        if not wr < w0:
            raise ParameterError("rated_speed", wr, f"must be < no_load_speed = {w0:g} rad/s")
        mr = p / wr
        return cls(mr * w0 / (w0 - wr), w0, inertia, mr, peak_torque, name)

    @property
    def max_torque(self) -> float:  # type: ignore[override]
        return self.stall_torque if self.peak_torque is None else min(self.peak_torque,
                                                                       self.stall_torque)

    def torque(self, omega_m: Any) -> Any:
        return self.stall_torque * (1.0 - omega_m / self.no_load_speed)

    def slope(self, omega_m: Any) -> Any:
        return -self.stall_torque / self.no_load_speed + 0.0 * omega_m

    def speed_at(self, torque: float) -> float:
        if torque >= self.stall_torque:
            raise InfeasibleError(f"a torque of {torque:.4g} N·m from the motor", self.stall_torque,
                                  "the stall torque of the DC motor [N·m]")
        return self.no_load_speed * (1.0 - torque / self.stall_torque)

    def describe(self) -> str:
        return (f"{self.name}: DC, stall torque {self.stall_torque:.4g} N·m, no-load speed "
                f"{self.no_load_speed * 30 / math.pi:.5g} rpm")


@dataclass(frozen=True)
class InductionMotor(Motor):
    """Three-phase induction motor by Kloss's formula from catalogue data.

    Parameters
    ----------
    rated_power : float
        Rated (output) power ``P_r`` [W], > 0.
    synchronous_speed : float
        ``omega_s`` [rad/s] (e.g. 1500 rpm for 4 poles at 50 Hz), > 0.
    rated_speed : float
        ``omega_r`` [rad/s], 0 < omega_r < omega_s.
    breakdown_ratio : float
        ``lambda = M_k / M_r`` > 1 (catalogues: 2 ... 3.5).
    inertia : float
        Rotor inertia [kg m^2] (catalogues give J or the GD^2 = 4 J g).
    name : str
        A label for tables.
    """

    rated_power: float
    synchronous_speed: float
    rated_speed: float
    breakdown_ratio: float
    inertia: float = 0.0
    name: str = "induction motor"
    kind: ClassVar[str] = "induction"

    def __post_init__(self) -> None:
        for attr in ("rated_power", "synchronous_speed", "rated_speed"):
            object.__setattr__(self, attr, _positive(attr, getattr(self, attr)))
        object.__setattr__(self, "inertia", _positive("inertia", self.inertia, allow_zero=True))
        if not self.rated_speed < self.synchronous_speed:
            raise ParameterError("rated_speed", self.rated_speed, "must be < synchronous_speed "
                                 f"= {self.synchronous_speed:g} rad/s (an induction motor "
                                 "runs with slip)")
        lam = require_number("breakdown_ratio", self.breakdown_ratio)
        if not lam > 1.0:
            raise ParameterError("breakdown_ratio", lam, "must be > 1 (breakdown torque over "
                                 "rated torque; catalogues give 2 ... 3.5)")
        object.__setattr__(self, "breakdown_ratio", lam)

    @property
    def rated_torque(self) -> float:  # type: ignore[override]
        """``M_r = P_r / omega_r`` [N m]."""
        return self.rated_power / self.rated_speed

    @property
    def rated_slip(self) -> float:
        """``s_r = 1 - omega_r / omega_s``."""
        return 1.0 - self.rated_speed / self.synchronous_speed

    @property
    def breakdown_slip(self) -> float:
        """``s_k = s_r (lambda + sqrt(lambda^2 - 1))`` (the stable-branch root)."""
        lam = self.breakdown_ratio
        return self.rated_slip * (lam + math.sqrt(lam * lam - 1.0))

    @property
    def breakdown_torque(self) -> float:
        """``M_k = lambda M_r`` [N m]."""
        return self.breakdown_ratio * self.rated_torque

    @property
    def breakdown_speed(self) -> float:
        """Speed of the breakdown torque ``omega_s (1 - s_k)`` [rad/s] (below it: unstable)."""
        return self.synchronous_speed * (1.0 - self.breakdown_slip)

    @property
    def starting_torque(self) -> float:
        """Kloss's torque at standstill ``2 M_k s_k / (1 + s_k^2)`` [N m]."""
        sk = self.breakdown_slip
        return 2.0 * self.breakdown_torque * sk / (1.0 + sk * sk)

    @property
    def max_torque(self) -> float:  # type: ignore[override]
        return self.breakdown_torque

    def torque(self, omega_m: Any) -> Any:
        s = 1.0 - omega_m / self.synchronous_speed
        sk = self.breakdown_slip
        return 2.0 * self.breakdown_torque * sk * s / (s * s + sk * sk)

    def slope(self, omega_m: Any) -> Any:
        s = 1.0 - omega_m / self.synchronous_speed
        sk = self.breakdown_slip
        q = s * s + sk * sk
        dm_ds = 2.0 * self.breakdown_torque * sk * (sk * sk - s * s) / (q * q)
        return -dm_ds / self.synchronous_speed

    def speed_at(self, torque: float) -> float:
        mk = self.breakdown_torque
        if torque > mk:
            raise InfeasibleError(f"a torque of {torque:.4g} N·m from the motor", mk,
                                  "the breakdown torque of the induction motor [N·m]")
        sk = self.breakdown_slip
        if torque == 0.0:
            return self.synchronous_speed
        # torque (s^2 + sk^2) = 2 mk sk s: the stable root s < sk (same sign as the torque),
        # sk (r - sqrt(r^2 - 1)) written without its cancellation at small torques (r >> 1)
        r = mk / torque
        s = sk / (r + math.copysign(math.sqrt(max(r * r - 1.0, 0.0)), r))
        return self.synchronous_speed * (1.0 - s)

    def describe(self) -> str:
        rpm = 30 / math.pi
        return (f"{self.name}: induction, {self.rated_power / 1e3:.4g} kW at "
                f"{self.rated_speed * rpm:.5g} rpm (synchronous {self.synchronous_speed * rpm:.5g}"
                f" rpm), breakdown {self.breakdown_torque:.4g} N·m at "
                f"{self.breakdown_speed * rpm:.5g} rpm")


@dataclass(frozen=True)
class ConstantSpeed(Motor):
    """An ideal servo drive holding the motor speed ``speed`` [rad/s] whatever the load.

    ``peak_torque`` [N m] (optional) is the drive's torque limit, ``rated_torque`` [N m]
    (optional) its continuous rating; they enter the verdicts of motor selection only.
    """

    speed: float
    inertia: float = 0.0
    peak_torque: float | None = None
    rated_torque: float | None = None
    name: str = "constant speed"
    kind: ClassVar[str] = "constant_speed"

    def __post_init__(self) -> None:
        object.__setattr__(self, "speed", _positive("speed", self.speed))
        object.__setattr__(self, "inertia", _positive("inertia", self.inertia, allow_zero=True))
        object.__setattr__(self, "peak_torque",
                           _optional_positive("peak_torque", self.peak_torque))
        object.__setattr__(self, "rated_torque",
                           _optional_positive("rated_torque", self.rated_torque))

    @property
    def max_torque(self) -> float | None:  # type: ignore[override]
        return self.peak_torque

    def speed_at(self, torque: float) -> float:
        return self.speed

    def describe(self) -> str:
        return f"{self.name}: ideal servo at {self.speed * 30 / math.pi:.5g} rpm"


@dataclass(frozen=True)
class ConstantTorque(Motor):
    """An ideal drive of constant torque whose value keeps the mean motor speed ``mean_speed``
    [rad/s] (the driving assumption of the classical flywheel methods); the torque may come out
    negative (a constant resisting torque)."""

    mean_speed: float
    inertia: float = 0.0
    name: str = "constant torque"
    kind: ClassVar[str] = "constant_torque"

    def __post_init__(self) -> None:
        object.__setattr__(self, "mean_speed", _positive("mean_speed", self.mean_speed))
        object.__setattr__(self, "inertia", _positive("inertia", self.inertia, allow_zero=True))

    max_torque = None
    rated_torque = None

    def speed_at(self, torque: float) -> float:
        return self.mean_speed

    def describe(self) -> str:
        return f"{self.name}: constant torque at a mean {self.mean_speed * 30 / math.pi:.5g} rpm"


@dataclass(frozen=True)
class Gear:
    """A gear stage (or belt, or a gearbox as a whole) between motor and crank.

    Parameters
    ----------
    ratio : float
        ``i = omega_m / omega1`` > 0 (a reduction has i > 1).
    efficiency : float
        ``eta`` in (0, 1]: the output torque is ``i eta M_in`` while the motor drives, and
        ``i M_in / eta`` while the crank drives the motor back (power flowing back).
    inertia : float
        Inertia of the gear's rotating parts referred to its input (motor) shaft [kg m^2].
    """

    ratio: float = 1.0
    efficiency: float = 1.0
    inertia: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "ratio", _positive("gear.ratio", self.ratio))
        eta = require_number("gear.efficiency", self.efficiency)
        if not 0.0 < eta <= 1.0:
            raise ParameterError("gear.efficiency", eta, "must lie in (0, 1]")
        object.__setattr__(self, "efficiency", eta)
        object.__setattr__(self, "inertia",
                           _positive("gear.inertia", self.inertia, allow_zero=True))

    def describe(self) -> str:
        return (f"gear i = {self.ratio:.5g}, efficiency {self.efficiency:.4g}, inertia "
                f"{self.inertia:.4g} kg·m² at the motor shaft")

