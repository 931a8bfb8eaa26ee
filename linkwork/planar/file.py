"""The ``planar`` mechanism file: any planar linkage for the general engine.

Example (the four-bar of ``examples/fourbar_paper001.toml``)::

    type = "planar"
    name = "Four-bar"

    [frame]
    points = { O = ["0 mm", "0 mm"], C = ["300 mm", "0 mm"] }

    [[body]]                       # a straight link: x-axis from start to end
    name = "crank"
    start = "O"
    end = "A"
    length = "100 mm"
    mass = "1 kg"                  # com at the midpoint, inertia m L^2/12 unless given

    [[body]]                       # a general body: points in its own frame
    name = "rocker"
    points = { C = [0, 0], B = ["200 mm", 0] }
    mass = "2 kg"
    com = ["100 mm", 0]
    inertia = "0.00567 kg*m^2"

    [[joint]]
    name = "O"                     # revolute: point O of a on point O of b (point_a/point_b)
    type = "revolute"              # "revolute" | "prismatic" | "slot"
    a = "frame"
    b = "crank"
    # prismatic / slot: angle (of the line in a), through (point name or [x, y]), point (of b),
    # rel_angle (prismatic: theta_b - theta_a)

    [driver]
    type = "crank"                 # "crank" (revolute joint) | "linear" (prismatic joint)
    joint = "O"
    omega1 = "10 rad/s"            # or "95.5 rpm"; linear: v1, a1
    eps1 = 0

    [analysis]
    start = "0 deg"                # driver positions (linear driver: metres)
    stop = "360 deg"
    n = 361
    branches = { B = 1 }           # group key -> +1/-1
    gravity = [0, "-9.81 m/s^2"]   # optional, any direction
    about = [0, 0]                 # shaking moment reference point

    [[load]]
    type = "force"                 # "force" at a point (frame axes) | "torque" on a body (mz;
                                   # a key of the other type is an error)
    body = "rocker"
    point = "B"                    # point name, "com" or [x, y] in the body frame
    fx = "0 N"
    fy = "-20 N"
    phi_range = ["200 deg", "340 deg"]   # optional: acts only there (e.g. a working stroke);
                                         # may wrap through 0; a linear driver: slide
                                         # positions, e.g. ["200 mm", "220 mm"]
    from_frame = false             # true: the load comes from the frame (a press's workpiece on
                                   # the bed) and cancels in the shaking force and moment

Plain numbers are SI (metres, radians, kg, N); strings carry units. Unknown keys are errors.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from linkwork.errors import LinkworkError, ParameterError
from linkwork.files import (
    Acceleration,
    Angle,
    AngularAcceleration,
    AngularVelocity,
    FileModel,
    Force,
    Inertia,
    Length,
    Mass,
    Torque,
    Velocity,
    register_schema,
)
from linkwork.planar.dynamics import BodyTorque, PointForce
from linkwork.planar.model import (
    Body,
    Crank,
    Joint,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    bar,
)

__all__ = ["AnalysisSection", "BodySection", "DriverSection", "FrameSection", "JointSection",
           "LoadSection", "PlanarFile"]

XY = tuple[Length, Length]

#: Largest crank angle [rad] of an analysis range: the spacing of floats there is 1.2e-10 rad.
MAX_ANGLE = 1e6


def _refuse_keys(section: LoadSection | JointSection | DriverSection, keys: tuple[str, ...],
                 what: str) -> None:
    """Keys that the section's ``type`` does not use would be ignored silently: refuse them."""
    given = [k for k in keys if k in section.model_fields_set]
    if given:
        raise ParameterError(given[0], getattr(section, given[0]),
                             f"is not used with type = {section.type!r}, which takes {what}")


class FrameSection(FileModel):
    """The fixed link: its named points [m]."""

    name: str = "frame"
    points: dict[str, XY] = Field(default_factory=dict)


class BodySection(FileModel):
    """A moving body: ``points`` in its own frame, or a straight link ``start``/``end``/
    ``length``."""

    name: str
    points: dict[str, XY] = Field(default_factory=dict)
    start: str | None = None
    end: str | None = None
    length: Length | None = None
    mass: Mass = 0.0
    com: XY | Length | None = None
    inertia: Inertia | None = None
    guess: tuple[Length, Length, Angle] | None = None

    def build(self) -> Body:
        if self.length is not None or self.start is not None or self.end is not None:
            if self.length is None or self.start is None or self.end is None:
                raise ParameterError(f"body {self.name}", "start/end/length",
                                     "a straight link needs all of start, end and length")
            b = bar(self.name, self.start, self.end, self.length, mass=self.mass, com=self.com,
                    inertia=self.inertia, points=self.points)
            return Body(b.name, b.points, b.mass, b.com, b.inertia, guess=self.guess)
        com = (0.0, 0.0) if self.com is None else self.com
        if not isinstance(com, tuple):
            raise ParameterError(f"body {self.name}.com", com, "must be [x, y] for a general body")
        return Body(self.name, self.points, mass=self.mass, com=com,
                    inertia=0.0 if self.inertia is None else self.inertia, guess=self.guess)


class JointSection(FileModel):
    """A joint between bodies ``a`` and ``b`` (reactions: force of a on b)."""

    name: str
    type: Literal["revolute", "prismatic", "slot"]
    a: str
    b: str
    point_a: str | None = None
    point_b: str | None = None
    angle: Angle = 0.0
    through: str | XY | None = None
    point: str | None = None
    rel_angle: Angle = 0.0

    @model_validator(mode="after")
    def _keys_of_type(self) -> JointSection:
        line = ("angle", "through", "point")
        if self.type == "revolute":
            _refuse_keys(self, (*line, "rel_angle"), "point_a and point_b")
        else:
            _refuse_keys(self, ("point_a", "point_b", *(("rel_angle",) if self.type == "slot"
                                                         else ())),
                         "angle, through, point" + (", rel_angle" if self.type == "prismatic"
                                                    else " (the pin turns freely in the slot)"))
        return self

    def build(self) -> Joint:
        if self.type == "revolute":
            return Revolute(self.name, self.a, self.b, self.point_a, self.point_b)
        if self.type == "prismatic":
            return Prismatic(self.name, self.a, self.b, self.angle, self.through, self.point,
                             self.rel_angle)
        return PinInSlot(self.name, self.a, self.b, self.angle, self.through, self.point)


class DriverSection(FileModel):
    """The driver: a crank (revolute joint) or a linear actuator (prismatic joint)."""

    type: Literal["crank", "linear"] = "crank"
    joint: str
    omega1: AngularVelocity = 1.0
    eps1: AngularAcceleration = 0.0
    v1: Velocity = 1.0
    a1: Acceleration = 0.0

    @model_validator(mode="after")
    def _keys_of_type(self) -> DriverSection:
        if self.type == "crank":
            _refuse_keys(self, ("v1", "a1"), "omega1 and eps1 (a linear driver takes v1, a1)")
        else:
            _refuse_keys(self, ("omega1", "eps1"), "v1 and a1 (a crank takes omega1, eps1)")
        return self

    def build(self) -> Crank | Linear:
        if self.type == "crank":
            return Crank(self.joint, self.omega1, self.eps1)
        return Linear(self.joint, self.v1, self.a1)


class AnalysisSection(FileModel):
    """Driver positions, branches, gravity, shaking-moment point."""

    start: float | str = 0.0
    stop: float | str = "360 deg"
    n: Annotated[int, Field(ge=2, le=10_000_000)] = 361
    branches: dict[str, Literal[1, -1]] = Field(default_factory=dict)
    gravity: tuple[Acceleration, Acceleration] | None = None
    about: XY = (0.0, 0.0)


class LoadSection(FileModel):
    """An external force at a point (frame axes) or a couple on a body."""

    type: Literal["force", "torque"]
    body: str
    point: str | XY = "com"
    fx: Force = 0.0
    fy: Force = 0.0
    mz: Torque = 0.0
    phi_range: tuple[float | str, float | str] | None = None
    from_frame: bool = False

    def driver_range(self, i: int, linear: bool) -> tuple[float, float] | None:
        """``phi_range`` in SI: angles [rad] for a crank (the range may wrap through 0), slide
        positions [m] for a linear driver (end > start)."""
        if self.phi_range is None:
            return None
        from linkwork.units import to_si

        key = f"load.{i}.phi_range"
        lo, hi = (to_si(v, "length" if linear else "angle", key) for v in self.phi_range)
        for v, si in zip(self.phi_range, (lo, hi), strict=True):
            if not math.isfinite(si):  # a NaN end would switch the load off everywhere
                raise ParameterError(key, v, "must be finite")
        if linear and not hi > lo:
            raise ParameterError(key, self.phi_range[1], f"the end of a slide range must be "
                                 f"> start = {self.phi_range[0]} (slide positions, no wrap)")
        return lo, hi

    @model_validator(mode="after")
    def _keys_of_type(self) -> LoadSection:
        if self.type == "force":
            _refuse_keys(self, ("mz",), "a force at a point (fx, fy, point); give a couple as "
                         "a separate [[load]] of type = 'torque'")
        else:
            _refuse_keys(self, ("point", "fx", "fy"), "a couple on the body (mz); give a force "
                         "as a separate [[load]] of type = 'force'")
        return self

    def build(self, phi1: np.ndarray, i: int = 0, linear: bool = False
              ) -> PointForce | BodyTorque:
        on: np.ndarray | float = 1.0
        rng = self.driver_range(i, linear)
        if rng is not None and linear:
            on = ((phi1 >= rng[0] - 1e-12) & (phi1 <= rng[1] + 1e-12)).astype(float)
        elif rng is not None:
            lo, hi = rng
            two_pi = 2 * np.pi
            rel = np.mod(phi1 - lo, two_pi)
            on = (rel <= np.mod(hi - lo, two_pi) + 1e-12).astype(float)
        if self.type == "force":
            return PointForce(self.body, self.point, self.fx * on, self.fy * on,
                              self.from_frame)
        return BodyTorque(self.body, self.mz * on, self.from_frame)


@register_schema("planar")
class PlanarFile(FileModel):
    """A planar mechanism for the general engine (see the module docstring)."""

    type: Literal["planar"]
    name: str = ""
    description: str = ""
    source: str = ""
    frame: FrameSection
    body: list[BodySection]
    joint: list[JointSection]
    driver: DriverSection
    analysis: AnalysisSection = Field(default_factory=lambda: AnalysisSection())
    load: list[LoadSection] = Field(default_factory=list)

    @model_validator(mode="after")
    def _check(self) -> PlanarFile:
        mech = self.mechanism()
        try:
            mech.validate()
        except LinkworkError as exc:
            raise ParameterError("structure", "[[body]] and [[joint]] as written",
                                 str(exc)) from None
        keys = [g.key for g in mech.structure.groups if g.kind != "driver"]
        unknown = sorted(set(self.analysis.branches) - {g.key for g in mech.structure.groups})
        if unknown:  # a misspelt key would leave its group on branch +1
            raise ParameterError("analysis.branches", unknown[0],
                                 f"no assembly group has this key; known: {keys}")
        self.positions()
        self._check_loads()
        for i, ld in enumerate(self.load):
            ld.driver_range(i, self.driver.type == "linear")
        return self

    def mechanism(self) -> Mechanism:
        """The engine model described by the file."""
        frame = Body(self.frame.name, self.frame.points)
        bodies = tuple(b.build() for b in self.body)
        joints = tuple(j.build() for j in self.joint)
        return Mechanism(frame, bodies, joints, self.driver.build(),
                         dict(self.analysis.branches))

    def positions(self) -> np.ndarray:
        """Driver positions [rad, or m for a linear driver]."""
        from linkwork.units import to_si

        kind = "angle" if self.driver.type == "crank" else "length"
        lo = to_si(self.analysis.start, kind, "analysis.start")
        hi = to_si(self.analysis.stop, kind, "analysis.stop")
        for key, v, si in (("analysis.start", self.analysis.start, lo),
                           ("analysis.stop", self.analysis.stop, hi)):
            if kind == "angle" and not abs(si) <= MAX_ANGLE:  # NaN too
                raise ParameterError(key, v, f"must lie within +-{MAX_ANGLE:g} rad (about "
                                     f"{MAX_ANGLE / (2 * np.pi):.0f} turns): beyond it the "
                                     "float spacing of angles exceeds 1e-10 rad")
            if not math.isfinite(si):
                raise ParameterError(key, v, "must be finite")
        if not hi > lo:
            raise ParameterError("analysis.stop", hi, f"must be > analysis.start = {lo:.6g}")
        return np.linspace(lo, hi, self.analysis.n)

    def loads(self, phi1: np.ndarray) -> list[PointForce | BodyTorque]:
        """External loads evaluated at the driver positions ``phi1``.

        Raises
        ------
        ParameterError
            A load names no moving body (``load.<i>.body``) or no point of its body
            (``load.<i>.point``).
        """
        self._check_loads()
        linear = self.driver.type == "linear"
        return [ld.build(phi1, i, linear) for i, ld in enumerate(self.load)]

    def _check_loads(self) -> None:
        """Every load names a moving body and a point of it (checked when the file loads, so
        that the error carries the file's name)."""
        moving = {b.name: b for b in self.body}
        for i, ld in enumerate(self.load):
            if ld.body not in moving:
                why = ("loads act on moving bodies, not on the frame"
                       if ld.body == self.frame.name else "no such moving body")
                raise ParameterError(f"load.{i}.body", ld.body, f"{why}; known: {list(moving)}")
            if isinstance(ld.point, str) and ld.point != "com":
                known = list(moving[ld.body].build().points)
                if ld.point not in known:
                    raise ParameterError(f"load.{i}.point", ld.point,
                                         f"no such point of body {ld.body!r}; known: "
                                         f"{[*known, 'com']}")
