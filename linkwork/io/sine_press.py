"""The ``sine_press`` file: the variable-structure sine press drive of paper 000.

Example (``examples/sine_press.toml``)::

    type = "sine_press"
    name = "Adjustable-stroke press drive"

    [crank]
    L1 = "50 mm"          # crank length
    speed = "120 rpm"     # crank speed omega1 (counter-clockwise positive)
    eps1 = "0 rad/s^2"    # crank angular acceleration (optional)

    [idle]                # idle mode: offset crank-slider
    lambda2 = 4.0         # rod length L2 / L1, > |lambda_e| + 1
    lambda_e = 0.5        # guide offset e / L1
    branch = 1            # +1: the + root of Eq. (2) (slider above the crank pin)

    [working]             # working mode: sine mechanism with the slot inclined at alpha
    alpha = "60 deg"      # must lie in the friction working range
    f_slot = 0.1          # Coulomb friction, block in the slot
    f_guide = 0.1         # Coulomb friction, slider in its guides

    [[schedule]]          # duty schedule (optional)
    mode = "idle"
    revolutions = 5
    [[schedule]]
    mode = "working"
    strokes = 3           # one working stroke = one crank revolution
    alpha = "60 deg"      # optional; default working.alpha

    [output]
    samples_per_revolution = 360

Plain numbers are SI (metres, radians, rad/s); strings carry units.  Unknown keys are errors.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, ValidationInfo, field_validator, model_validator
from pydantic_core import PydanticCustomError

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.io.drive import DriveSection, PressSection
from linkwork.io.toml import (
    Angle,
    AngularAcceleration,
    AngularVelocity,
    Dimensionless,
    FileModel,
    Length,
)
from linkwork.models import sine
from linkwork.models.crank_slider import assembly_limit
from linkwork.models.variable_structure import schedule_samples

__all__ = ["BYTES_PER_SCHEDULE_SAMPLE", "MAX_SCHEDULE_SAMPLES", "CrankSection", "IdleSection",
           "OutputSection", "ScheduleEntry", "SinePressFile", "WorkingSection"]

PositiveLength = Annotated[Length, Field(gt=0)]
PositiveSpeed = Annotated[AngularVelocity, Field(gt=0)]
NonNegative = Annotated[Dimensionless, Field(ge=0)]


def _alpha_error(key: str, alpha: float, f_slot: float, f_guide: float) -> None:
    try:
        sine.check_alpha(alpha, f_slot, f_guide, name=key)
    except (ParameterError, InfeasibleError) as exc:
        msg = str(exc)
        if abs(alpha) > math.pi:  # most likely degrees written as a plain number (radians)
            msg += ' (a plain number is in radians: write e.g. "60 deg")'
        raise PydanticCustomError("working_range", "{msg}", {"msg": msg}) from None


class CrankSection(FileModel):
    """``[crank]``: crank length ``L1`` [m], speed ``speed`` [rad/s] > 0, ``eps1`` [rad/s^2]."""

    L1: PositiveLength
    speed: PositiveSpeed
    eps1: AngularAcceleration = 0.0


class IdleSection(FileModel):
    """``[idle]``: the offset crank-slider, ``lambda2 > |lambda_e| + 1``, ``branch`` +1 or -1."""

    lambda_e: Dimensionless = 0.0
    lambda2: Annotated[Dimensionless, Field(gt=0)]
    branch: Literal[1, -1] = 1

    @field_validator("lambda2")
    @classmethod
    def _full_rotation(cls, v: float, info: ValidationInfo) -> float:
        lame = info.data.get("lambda_e")
        if lame is not None and v <= float(assembly_limit(lame)):
            raise PydanticCustomError(
                "assembly", "lambda2 = {v} must be > |lambda_e| + 1 = {lim} for a fully "
                "rotating crank (the rod cannot reach the guide at some crank angles)",
                {"v": f"{v:.6g}", "lim": f"{float(assembly_limit(lame)):.6g}"})
        return v


class WorkingSection(FileModel):
    """``[working]``: slot angle ``alpha`` inside the working range set by the friction
    coefficients ``f_slot`` (block in slot) and ``f_guide`` (slider in guides)."""

    f_slot: NonNegative = 0.1
    f_guide: NonNegative = 0.1
    alpha: Angle

    @field_validator("alpha")
    @classmethod
    def _in_working_range(cls, v: float, info: ValidationInfo) -> float:
        if "f_slot" in info.data and "f_guide" in info.data:
            _alpha_error("alpha", v, info.data["f_slot"], info.data["f_guide"])
        return v


class ScheduleEntry(FileModel):
    """One ``[[schedule]]`` entry: ``mode`` and ``revolutions`` (idle) or ``strokes`` (working;
    ``revolutions`` accepted too), optional ``alpha`` for working entries."""

    mode: Literal["idle", "working"]
    revolutions: Annotated[int, Field(ge=1, le=10_000)] | None = None
    strokes: Annotated[int, Field(ge=1, le=10_000)] | None = None
    alpha: Angle | None = None

    @model_validator(mode="after")
    def _count(self) -> ScheduleEntry:
        if self.revolutions is None and self.strokes is None:
            raise PydanticCustomError("count", "needs 'revolutions' (idle) or 'strokes' (working)")
        if self.revolutions is not None and self.strokes is not None:
            raise PydanticCustomError("count", "give 'revolutions' or 'strokes', not both")
        if self.mode == "idle" and self.strokes is not None:
            raise PydanticCustomError("count", "an idle entry counts 'revolutions', not 'strokes'")
        if self.mode == "idle" and self.alpha is not None:
            raise PydanticCustomError("alpha", "'alpha' applies to working entries only")
        return self

    @property
    def count(self) -> int:
        """Crank revolutions of this entry."""
        return int(self.revolutions if self.revolutions is not None else self.strokes or 0)


#: The most samples of a file's duty schedule (all entries, ``revolutions x
#: samples_per_revolution + 1`` each): ``linkwork analyze`` peaked at 1.8 GB resident for 10^6
#: samples (:data:`BYTES_PER_SCHEDULE_SAMPLE` each: the schedule's CSV/JSON columns and plot).
#: The Python API's :meth:`~linkwork.models.variable_structure.VariableStructureMechanism.run`
#: alone allows :data:`~linkwork.models.variable_structure.MAX_SAMPLES`.
MAX_SCHEDULE_SAMPLES = 1_000_000

#: Peak memory of ``linkwork analyze`` per schedule sample [bytes] (measured, rounded up).
BYTES_PER_SCHEDULE_SAMPLE = 1_800


class OutputSection(FileModel):
    """``[output]``: ``samples_per_revolution`` of the cycle files and plots (8 ... 100000)."""

    samples_per_revolution: Annotated[int, Field(ge=8, le=100_000)] = 360


class SinePressFile(FileModel):
    """A variable-structure sine press drive (paper 000): crank, idle and working structures,
    optional duty schedule."""

    type: Literal["sine_press"]
    name: str = "sine press"
    crank: CrankSection
    idle: IdleSection
    working: WorkingSection
    schedule: list[ScheduleEntry] = Field(default_factory=list)
    output: OutputSection = OutputSection()
    press: PressSection | None = None
    drive: DriveSection | None = None

    @field_validator("schedule")
    @classmethod
    def _schedule_alphas(cls, v: list[ScheduleEntry], info: ValidationInfo
                         ) -> list[ScheduleEntry]:
        w = info.data.get("working")
        if w is None:
            return v
        for i, e in enumerate(v):
            if e.alpha is not None:
                _alpha_error(f"schedule.{i}.alpha", e.alpha, w.f_slot, w.f_guide)
        if sum(e.count for e in v) > 100_000:
            raise PydanticCustomError("too_long", "more than 100000 revolutions in total")
        return v

    @model_validator(mode="after")
    def _schedule_bounded(self) -> SinePressFile:
        counts = [e.count for e in self.schedule]
        spr = self.output.samples_per_revolution
        total = schedule_samples(counts, spr)
        if total > MAX_SCHEDULE_SAMPLES:
            raise ParameterError(
                "schedule", f"{sum(counts)} revolutions x {spr} samples_per_revolution",
                f"at most {MAX_SCHEDULE_SAMPLES} samples in all (got {total}): `linkwork "
                f"analyze` keeps about {BYTES_PER_SCHEDULE_SAMPLE} bytes per sample "
                f"(its CSV/JSON and plots), {total * BYTES_PER_SCHEDULE_SAMPLE / 1e9:.3g} GB "
                "asked; shorten the schedule or lower [output] samples_per_revolution")
        return self

    def segments(self) -> list[tuple[str, int, float | None]]:
        """The schedule as ``(mode, revolutions, alpha [rad] or None)`` tuples."""
        return [(e.mode, e.count, e.alpha) for e in self.schedule]

    @property
    def alpha_deg(self) -> float:
        """The working slot angle in degrees (for display)."""
        return math.degrees(self.working.alpha)
