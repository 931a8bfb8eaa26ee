"""The ``[drive]`` table: the motor(s), gear and flywheel that ``linkwork dynamics`` runs a
mechanism with (:mod:`linkwork.machine`). It is an optional section of a ``planar`` file and of
a ``sine_press`` file (there with a ``[press]`` table of masses and the press force)::

    [drive]
    flywheel = "12 kg*m^2"        # on the crank shaft; or instead:
    # delta = 0.05                # size the flywheel for this speed fluctuation
    # max_flywheel = "500 kg*m^2" # the largest acceptable (with delta)
    positions = 360               # over a revolution (the solve's grid)
    start_up = true               # simulate the start from rest
    band = 0.01                   # steady when within 1 % of the mean speed

    [drive.gear]                  # optional: between motor and crank
    ratio = 12.5                  # motor speed / crank speed
    efficiency = 0.95
    inertia = "0.002 kg*m^2"      # referred to the motor shaft

    [[drive.motor]]               # one or more: each is checked (a verdict line each); the
    name = "5.5 kW, 4 poles"      # first is the one the flywheel is sized for and the
    type = "induction"            # transients run with
    rated_power = "5.5 kW"
    synchronous_speed = "1500 rpm"
    rated_speed = "1445 rpm"
    breakdown_ratio = 2.7
    inertia = "0.021 kg*m^2"      # the rotor's

    [[drive.motor]]
    type = "dc"                   # stall_torque + no_load_speed, or rated_power +
    rated_power = "4 kW"          # rated_speed + no_load_speed
    rated_speed = "1500 rpm"
    no_load_speed = "1650 rpm"
    peak_torque = "60 N*m"        # optional (default the stall torque)

    [[drive.motor]]
    type = "constant_speed"       # an ideal servo: speed, optional peak_torque, rated_torque
    speed = "1445 rpm"

    [[drive.schedule]]            # optional (planar files): a duty schedule of the loads
    revolutions = 5               # 5 revolutions without the file's [[load]]s,
    load = 0.0
    [[drive.schedule]]
    revolutions = 3               # then 3 with them
    load = 1.0

``constant_torque`` (``mean_speed``) is the textbooks' constant driving torque. Plain numbers are
SI; strings carry units. Unknown keys, and keys of another motor type, are errors.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, field_validator, model_validator
from pydantic_core import PydanticCustomError

from linkwork.io.toml import (
    Acceleration,
    AngularVelocity,
    Dimensionless,
    FileModel,
    Force,
    Inertia,
    Length,
    Mass,
    Power,
    Torque,
)
from linkwork.machine import (
    ConstantSpeed,
    ConstantTorque,
    DCMotor,
    Gear,
    InductionMotor,
    Motor,
)
from linkwork.machine.flywheel import MAX_FLYWHEEL
from linkwork.machine.transient import MAX_RUN_SAMPLES

__all__ = ["DriveSection", "GearSection", "MotorSection", "PressSection", "ScheduleSection"]

NonNegative = Annotated[Dimensionless, Field(ge=0)]
PositiveSpeed = Annotated[AngularVelocity, Field(gt=0)]

#: The keys each motor type takes (besides ``type``, ``name``, ``inertia``).
MOTOR_KEYS: dict[str, tuple[str, ...]] = {
    "induction": ("rated_power", "synchronous_speed", "rated_speed", "breakdown_ratio"),
    "dc": ("stall_torque", "no_load_speed", "rated_power", "rated_speed", "rated_torque",
           "peak_torque"),
    "constant_speed": ("speed", "peak_torque", "rated_torque"),
    "constant_torque": ("mean_speed",),
}


class MotorSection(FileModel):
    """One ``[[drive.motor]]``: its ``type`` and the data of that type (see the module
    docstring)."""

    type: Literal["induction", "dc", "constant_speed", "constant_torque"]
    name: str = ""
    inertia: Annotated[Inertia, Field(ge=0)] = 0.0
    rated_power: Annotated[Power, Field(gt=0)] | None = None
    synchronous_speed: PositiveSpeed | None = None
    rated_speed: PositiveSpeed | None = None
    breakdown_ratio: Annotated[Dimensionless, Field(gt=1)] | None = None
    stall_torque: Annotated[Torque, Field(gt=0)] | None = None
    no_load_speed: PositiveSpeed | None = None
    rated_torque: Annotated[Torque, Field(gt=0)] | None = None
    peak_torque: Annotated[Torque, Field(gt=0)] | None = None
    speed: PositiveSpeed | None = None
    mean_speed: PositiveSpeed | None = None

    @model_validator(mode="after")
    def _keys_of_type(self) -> MotorSection:
        allowed = MOTOR_KEYS[self.type]
        given = [k for ks in MOTOR_KEYS.values() for k in ks
                 if getattr(self, k) is not None and k in self.model_fields_set]
        wrong = [k for k in dict.fromkeys(given) if k not in allowed]
        if wrong:
            raise PydanticCustomError("motor_keys", "'{k}' is not a key of a {t} motor (it "
                                      "takes {a})", {"k": wrong[0], "t": self.type,
                                                     "a": ", ".join(allowed)})
        need = {"induction": allowed, "constant_speed": ("speed",),
                "constant_torque": ("mean_speed",),
                "dc": (("stall_torque", "no_load_speed") if self.stall_torque is not None else
                       ("rated_power", "rated_speed", "no_load_speed"))}[self.type]
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise PydanticCustomError("motor_keys", "a {t} motor needs '{k}'",
                                      {"t": self.type, "k": missing[0]})
        self.build()  # the motor's own checks (rated below synchronous speed): at the file
        return self

    def build(self, index: int = 0) -> Motor:
        """The motor of :mod:`linkwork.machine` (checked again there: rated below synchronous
        speed, ...)."""
        name = self.name or f"motor {index + 1}"
        if self.type == "induction":
            return InductionMotor(self.rated_power, self.synchronous_speed,  # type: ignore[arg-type]
                                  self.rated_speed, self.breakdown_ratio,  # type: ignore[arg-type]
                                  inertia=self.inertia, name=name)
        if self.type == "dc":
            if self.stall_torque is not None:
                return DCMotor(self.stall_torque, self.no_load_speed,  # type: ignore[arg-type]
                               inertia=self.inertia, rated_torque=self.rated_torque,
                               peak_torque=self.peak_torque, name=name)
            return DCMotor.from_rated(self.rated_power, self.rated_speed,  # type: ignore[arg-type]
                                      self.no_load_speed,  # type: ignore[arg-type]
                                      inertia=self.inertia, peak_torque=self.peak_torque,
                                      name=name)
        if self.type == "constant_speed":
            return ConstantSpeed(self.speed, inertia=self.inertia,  # type: ignore[arg-type]
                                 peak_torque=self.peak_torque, rated_torque=self.rated_torque,
                                 name=name)
        return ConstantTorque(self.mean_speed, inertia=self.inertia,  # type: ignore[arg-type]
                              name=name)


class GearSection(FileModel):
    """``[drive.gear]``: ratio (motor / crank speed) > 0, efficiency in (0, 1], inertia at
    the motor shaft."""

    ratio: Annotated[Dimensionless, Field(gt=0)] = 1.0
    efficiency: Annotated[Dimensionless, Field(gt=0, le=1)] = 1.0
    inertia: Annotated[Inertia, Field(ge=0)] = 0.0

    def build(self) -> Gear:
        return Gear(self.ratio, self.efficiency, self.inertia)


class ScheduleSection(FileModel):
    """One ``[[drive.schedule]]`` entry of a planar file: ``revolutions`` with the file's loads
    times ``load``."""

    revolutions: Annotated[int, Field(ge=1, le=100_000)]
    load: NonNegative = 1.0


class DriveSection(FileModel):
    """``[drive]``: motors, gear, flywheel or the delta to size it, the solve's positions, the
    start-up and (planar files) a schedule of the loads."""

    motor: list[MotorSection]
    gear: GearSection | None = None
    flywheel: Annotated[Inertia, Field(ge=0)] | None = None
    delta: Annotated[Dimensionless, Field(gt=0)] | None = None
    max_flywheel: Annotated[Inertia, Field(gt=0)] = MAX_FLYWHEEL
    positions: Annotated[int, Field(ge=16, le=20_000)] = 360
    start_up: bool = True
    band: Annotated[Dimensionless, Field(gt=0, lt=1)] = 0.01
    max_revolutions: Annotated[int, Field(ge=1)] = 2000
    schedule: list[ScheduleSection] = Field(default_factory=list)

    @field_validator("motor", mode="before")
    @classmethod
    def _one_or_many(cls, v: Any) -> Any:
        return [v] if isinstance(v, dict) else v

    @model_validator(mode="after")
    def _consistent(self) -> DriveSection:
        if not self.motor:
            raise PydanticCustomError("motor", "needs at least one [[drive.motor]]")
        if self.flywheel is not None and self.delta is not None:
            raise PydanticCustomError("flywheel", "give a flywheel or a delta to size one, not "
                                      "both")
        if self.delta is not None and self.motor[0].type == "constant_speed":
            raise PydanticCustomError("delta", "the first motor is an ideal constant-speed drive: "
                                      "its delta is 0 with any flywheel")
        revs = max(self.max_revolutions, sum(s.revolutions for s in self.schedule))
        if revs * self.positions > MAX_RUN_SAMPLES:
            raise PydanticCustomError(
                "too_long", "{r} revolutions x {n} positions exceed {m} positions in all (about "
                "200 bytes each while running); lower max_revolutions, the schedule or positions",
                {"r": revs, "n": self.positions, "m": MAX_RUN_SAMPLES})
        return self

    def motors(self) -> list[Motor]:
        return [m.build(k) for k, m in enumerate(self.motor)]

    def build_gear(self) -> Gear:
        return Gear() if self.gear is None else self.gear.build()


class PressSection(FileModel):
    """``[press]`` of a ``sine_press`` file: the masses and the press force that
    ``linkwork dynamics`` needs (:func:`linkwork.machine.press_modes`)::

        [press]
        crank_mass = "6 kg"
        crank_inertia = "0.02 kg*m^2"
        crank_com = "10 mm"          # from the axis along the crank (0: counterweighted)
        rod_mass = "3 kg"            # idle crank-slider's rod (uniform unless rod_inertia)
        slider_mass = "4 kg"         # its slider C
        ram_mass = "25 kg"           # ram with upper die
        block_mass = "0.5 kg"        # the slot's block, lumped at the crank pin
        press_force = "8 kN"         # over the last working_stroke of the descent
        working_stroke = "20 mm"
        gravity = ["-9.81 m/s^2", 0] # x (the ram's line of motion) up
    """

    crank_mass: Annotated[Mass, Field(ge=0)]
    crank_inertia: Annotated[Inertia, Field(ge=0)]
    crank_com: Length = 0.0
    rod_mass: Annotated[Mass, Field(ge=0)]
    rod_inertia: Annotated[Inertia, Field(ge=0)] | None = None
    slider_mass: Annotated[Mass, Field(ge=0)]
    ram_mass: Annotated[Mass, Field(ge=0)]
    block_mass: Annotated[Mass, Field(ge=0)] = 0.0
    press_force: Annotated[Force, Field(ge=0)] = 0.0
    working_stroke: Annotated[Length, Field(gt=0)]
    gravity: tuple[Acceleration, Acceleration] | None = (-9.81, 0.0)

    def masses(self) -> dict[str, Any]:
        """The keywords of :func:`linkwork.machine.press_modes`."""
        return {k: getattr(self, k) for k in (
            "crank_mass", "crank_inertia", "crank_com", "rod_mass", "rod_inertia",
            "slider_mass", "ram_mass", "block_mass", "press_force", "working_stroke",
            "gravity")}
