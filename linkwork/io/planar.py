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
    type = "revolute"              # "revolute" | "prismatic" | "slot" | "gear"
    a = "frame"
    b = "crank"
    # gear: a, b the gears (each hinged to the carrier at its centre), teeth = [30, 50] or
    # radii = ["60 mm", "100 mm"], internal = false, carrier (default the frame),
    # pressure_angle = "20 deg", efficiency = 0.98, offset (b's angle when a's is 0)
    # prismatic / slot: angle (of the line in a), through (point name or [x, y]), point (of b),
    # rel_angle (prismatic: theta_b - theta_a)
    # Coulomb friction (docs/friction.md), all optional, default none: friction = 0.1 (the
    # coefficient, every type); revolute: radius = "15 mm" (journal), friction_torque =
    # "0.5 N*m" (pin/axial); prismatic: length = "60 mm" (block along the guide; 0: point
    # contact); slot: radius = "8 mm" (pin; 0: a sliding block)

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
    # type = "slide": joint (prismatic or slot), force along its line on its body b (reaction
    # on a); type = "drag": body, point, force (constant magnitude), damping [N*s/m], against
    # the point's velocity; name = "..." (optional, default load.<i>)

    [[load]]                       # a load diagram (docs/forces.md)
    name = "drawing"
    type = "slide"
    joint = "guide"
    [load.diagram]                 # also for type = "torque" (mz) and "force" (with angle)
    over = "guide"                 # "driver" or a prismatic/slot joint: its slide s
    when = "decreasing"            # "always" | "increasing" | "decreasing"
    outside = "zero"               # "zero" | "error" (no extrapolation)
    table = [["-450 mm", "100 kN"], ["-440 mm", "200 kN"], ["-430 mm", "0 kN"]]

    [[spring]]                     # between points of any two bodies, the frame included
    a = "frame"
    point_a = "K"                  # name, "com" or [x, y] in the body's frame
    b = "ram"
    point_b = "R"
    stiffness = "5 N/mm"
    free_length = "400 mm"
    preload = "2.5 kN"             # tension at the free length (optional)

    [[damper]]                     # a, point_a, b, point_b as a spring
    damping = "200 N*s/m"

    [balance]                      # optional: read by `linkwork balance` (paper 001)
    links = ["crank", "rocker"]    # counterweighted frame-hinged links
    radii = { crank = "50 mm", rocker = "100 mm" }   # counterweight radii
    angles = [0, 30, 60, 90]       # table [deg]
    n = 360                        # positions of the full cycle

    [drive]                        # optional: read by `linkwork dynamics` (machine dynamics;
    flywheel = "0.5 kg*m^2"        # the table is described in linkwork/io/drive.py)
    [[drive.motor]]
    type = "induction"
    rated_power = "250 W"
    synchronous_speed = "1500 rpm"
    rated_speed = "1400 rpm"
    breakdown_ratio = 2.4
    [drive.gear]
    ratio = 14

    [spatial]                      # optional: read by `linkwork reactions` (paper 004)
    k_bearing = "100 N/um"         # default radial bearing stiffness k_b
    axial_ratio = 1.0              # default axial/radial stiffness ratio
    positions = 360                # optional: resample the file's [analysis] range
    default = { e = "30 mm", z = "0 mm" }   # for joints not listed in [spatial.joints]
    heights = { coupler = "30 mm" }          # heights of the centres of mass [m]

    [spatial.joints.A]
    kind = "revolute"              # cylindrical, spherical, sphere_cylinder, prismatic, ...,
                                   # a gear pair's mesh: spur (default), crowned
    e = "30 mm"                    # axis (bearing) length
    z = "30 mm"                    # height of the joint centre
    # stiffness = ["1e8 N/m", "1e8 N/m", "1e8 N/m", "7.5 kN*m/rad", "7.5 kN*m/rad", 0]

    [[spatial.deviation]]          # manufacturing deviations, in the body's own frame
    joint = "O4"
    body = "frame"
    tx = "0.2 mrad"                # dx, dy, dz [length], tx, ty, tz [angle]

    [[spatial.out_of_plane]]       # out-of-plane loads at the centre of mass
    body = "coupler"
    fz = "5 N"                     # mx, my [torque]

    [[spatial.tolerance]]          # for --tolerance-study
    joint = "O4"
    body = "frame"
    component = "tx"
    limit = "0.3 mrad"             # normal: limit = 3 sigma; uniform: +-limit
    distribution = "normal"
    mean = 0.0

Plain numbers are SI (metres, radians, kg, N); strings carry units. Unknown keys are errors.
The ``[balance]``, ``[drive]`` and ``[spatial]`` tables are optional sections of the one
:class:`PlanarFile` model: the file is read and validated once, whichever command reads it.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal, Self

import numpy as np
import pydantic
from pydantic import Discriminator, Field, PrivateAttr, Tag, field_validator, model_validator

from linkwork.errors import FileFormatError, LinkworkError, ParameterError
from linkwork.io.drive import DriveSection
from linkwork.io.toml import (
    MAGNITUDE_LIMITS,
    Acceleration,
    Angle,
    AngularAcceleration,
    AngularVelocity,
    Damping,
    Dimensionless,
    FileModel,
    Force,
    Inertia,
    Length,
    Mass,
    Stiffness,
    Torque,
    Velocity,
    _validation_error,
    message,
    parameter_error,
    quantity,
)
from linkwork.planar.forces import (
    BodyTorque,
    Damper,
    Drag,
    Load,
    LoadDiagram,
    PointForce,
    SlideForce,
    Spring,
)
from linkwork.planar.model import (
    Body,
    Crank,
    GearPair,
    Joint,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    bar,
)
from linkwork.planar.sketch import sketch
from linkwork.redundancy.core import DEFAULT_BEARING_STIFFNESS, check_tilt
from linkwork.units import to_si

__all__ = ["BYTES_PER_POSITION", "BYTES_PER_SPATIAL_POSITION", "CSV_BYTES_PER_POSITION",
           "MAX_ANGLE", "MAX_POSITIONS", "MAX_SPATIAL_POSITIONS", "MAX_WHOLE_POSITIONS",
           "AnalysisSection", "BalanceSection", "BodySection", "DeviationSpec", "DriverSection",
           "FrameSection", "JointSection", "JointSpec", "LoadSection", "OutOfPlaneSpec",
           "PlanarFile", "SpatialSpec", "ToleranceSpec", "read_spatial", "whole_cycle_limit"]

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


class _GearKeys(FileModel):
    """The keys of a gear pair (:class:`linkwork.planar.GearPair`)."""

    teeth: tuple[int, int] | None = None
    radii: tuple[Length, Length] | None = None
    internal: bool = False
    carrier: str | None = None
    pressure_angle: Angle = math.radians(20.0)
    efficiency: Dimensionless = 1.0


class JointSection(_GearKeys):
    """A joint between bodies ``a`` and ``b`` (reactions: force of a on b)."""

    name: str
    type: Literal["revolute", "prismatic", "slot", "gear"]
    a: str
    b: str
    offset: Angle = 0.0
    point_a: str | None = None
    point_b: str | None = None
    angle: Angle = 0.0
    through: str | XY | None = None
    point: str | None = None
    rel_angle: Angle = 0.0
    friction: Dimensionless = 0.0
    radius: Length = 0.0
    friction_torque: Torque = 0.0
    length: Length = 0.0

    @model_validator(mode="after")
    def _friction_keys_of_type(self) -> JointSection:
        """Friction keys of another joint type are refused (see :mod:`linkwork.planar.joints`)."""
        takes = {"revolute": "friction, radius, friction_torque",
                 "prismatic": "friction, length", "slot": "friction, radius",
                 "gear": "efficiency"}
        unused = {"revolute": ("length",), "prismatic": ("radius", "friction_torque"),
                  "slot": ("length", "friction_torque"),
                  "gear": ("friction", "radius", "friction_torque", "length")}
        _refuse_keys(self, unused[self.type], f"the friction keys {takes[self.type]}")
        return self

    def _friction(self) -> dict[str, float]:
        """The friction keyword arguments of the joint (only those given)."""
        keys = {"revolute": ("friction", "radius", "friction_torque"),
                "prismatic": ("friction", "length"), "slot": ("friction", "radius"),
                "gear": ("efficiency",)}
        return {k: getattr(self, k) for k in keys[self.type] if k in self.model_fields_set}

    @model_validator(mode="after")
    def _keys_of_type(self) -> JointSection:
        line = ("angle", "through", "point")
        gear = ("teeth", "radii", "internal", "carrier", "pressure_angle", "offset")
        if self.type == "gear":
            _refuse_keys(self, (*line, "rel_angle", "point_a", "point_b"),
                         "teeth or radii, internal, carrier, pressure_angle, efficiency, offset")
            return self
        _refuse_keys(self, (*gear, "efficiency"), f"the keys of a {self.type} joint (the gear "
                     "keys belong to type = 'gear')")
        if self.type == "revolute":
            _refuse_keys(self, (*line, "rel_angle"), "point_a and point_b")
        else:
            _refuse_keys(self, ("point_a", "point_b", *(("rel_angle",) if self.type == "slot"
                                                         else ())),
                         "angle, through, point" + (", rel_angle" if self.type == "prismatic"
                                                    else " (the pin turns freely in the slot)"))
        return self

    def build(self) -> Joint:
        fr = self._friction()
        if self.type == "revolute":
            return Revolute(self.name, self.a, self.b, self.point_a, self.point_b, **fr)
        if self.type == "prismatic":
            return Prismatic(self.name, self.a, self.b, self.angle, self.through, self.point,
                             self.rel_angle, **fr)
        if self.type == "gear":
            return GearPair(self.name, self.a, self.b, teeth=self.teeth, radii=self.radii,
                            internal=self.internal, carrier=self.carrier,
                            pressure_angle=self.pressure_angle, offset=self.offset, **fr)
        return PinInSlot(self.name, self.a, self.b, self.angle, self.through, self.point, **fr)


class DriverSection(FileModel):
    """The driver: a crank (revolute joint) or a linear actuator (prismatic joint). In a file
    with a ``[sketch]``, ``joint`` names a frame pivot's point (a crank; ``link``: which link,
    if several are hinged there) or a slider (a linear driver)."""

    type: Literal["crank", "linear"] = "crank"
    joint: str
    link: str | None = None
    omega1: AngularVelocity = 1.0
    eps1: AngularAcceleration = 0.0
    v1: Velocity = 1.0
    a1: Acceleration = 0.0
    start: float | str | None = None
    stop: float | str | None = None

    @model_validator(mode="after")
    def _keys_of_type(self) -> DriverSection:
        if self.type == "crank":
            _refuse_keys(self, ("v1", "a1"), "omega1 and eps1 (a linear driver takes v1, a1)")
        else:
            _refuse_keys(self, ("omega1", "eps1"), "v1 and a1 (a crank takes omega1, eps1)")
        return self

    def build(self) -> Crank | Linear:
        if self.link is not None:
            raise ParameterError("driver.link", self.link, "names the driven link of a frame "
                                 "pivot in a [sketch]; with [[joint]] the joint says it")
        if self.type == "crank":
            return Crank(self.joint, self.omega1, self.eps1)
        return Linear(self.joint, self.v1, self.a1)

    def span(self, key: str) -> tuple[float, float]:
        """``start`` and ``stop`` of one of several drivers in SI [rad or m] (required)."""
        kind = "angle" if self.type == "crank" else "length"
        out = []
        for name in ("start", "stop"):
            v = getattr(self, name)
            if v is None:
                raise ParameterError(f"{key}.{name}", "missing", "each of several [[driver]] "
                                     "gives its own start and stop (its positions run from "
                                     "start to stop over the [analysis] n positions)")
            si = to_si(v, kind, f"{key}.{name}")
            if not math.isfinite(si) or (kind == "angle" and not abs(si) <= MAX_ANGLE):
                raise ParameterError(f"{key}.{name}", v, "must be finite" + (
                    f" and within +-{MAX_ANGLE:g} rad" if kind == "angle" else ""))
            out.append(si)
        return out[0], out[1]

    def sketch_spec(self) -> str | tuple[str, str]:
        """The driver as :func:`linkwork.planar.sketch` names it."""
        return self.joint if self.link is None else (self.joint, self.link)

    def speeds(self) -> tuple[float, float]:
        """(speed, acceleration) of the driver [rad/s, rad/s^2, or m/s, m/s^2]."""
        return (self.omega1, self.eps1) if self.type == "crank" else (self.v1, self.a1)


class DriverTables(list):
    """Several ``[[driver]]`` tables (``PlanarFile.driver`` then holds them): a list whose
    one-driver keys (``type``, ``joint``, ``omega1``, ...) raise a ParameterError naming the
    drivers, so that code written for one driver refuses several clearly."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise ParameterError("driver", [d.joint for d in self],
                             f"the file has {len(self)} [[driver]] tables; this needs one "
                             f"driver (its '{name}')")


def _driver_tables(value: Any) -> str:
    """``[[driver]]`` (several drivers, a list) or ``[driver]`` (one): validated as that one
    member of the union only, so that its errors are not doubled (the tags, with brackets,
    are left out of the error's key)."""
    return "[[driver]]" if isinstance(value, list) else "[driver]"


class SliderSection(FileModel):
    """``[sketch.sliders.NAME]``: a prismatic pair as drawn (:class:`linkwork.planar.Slider`)."""

    point: str
    guide: str
    angle: Angle | None = None
    along: tuple[str, str] | None = None
    body: str | None = None


class SlotSection(FileModel):
    """``[sketch.slots.NAME]``: a pin-in-slot pair as drawn (:class:`linkwork.planar.Slot`)."""

    point: str
    guide: str
    angle: Angle | None = None
    along: tuple[str, str] | None = None


class CylinderSection(FileModel):
    """``[sketch.cylinders.NAME]``: a linear actuator between two drawn pivots
    (:class:`linkwork.planar.Cylinder`): bodies ``NAME_barrel``, ``NAME_rod``, its length the
    slide of the prismatic pair ``NAME``."""

    start: str
    end: str


class GearSection(_GearKeys):
    """``[sketch.gears.NAME]``: a gear pair between two drawn links (their centres: their
    pivots on the carrier), ratio by ``teeth`` or ``radii``, phase from the drawing
    (:class:`linkwork.planar.GearPair`)."""

    a: str
    b: str


class LinkMassSection(FileModel):
    """``[sketch.masses.LINK]``: mass, centre of mass (a drawn point's name or world [x, y] as
    drawn), centroidal inertia (:class:`linkwork.planar.LinkMass`)."""

    mass: Mass = 0.0
    com: str | XY | None = None
    inertia: Inertia | None = None


class SketchSection(FileModel):
    """``[sketch]``: the mechanism as drawn (:func:`linkwork.planar.sketch`): world coordinates
    of its points in the drawn position, links as lists of points, ground points; the drivers
    are the ``[driver]`` table's ``joint`` (a frame pivot's point or a slider's name)."""

    frame: str = "frame"
    points: dict[str, XY]
    ground: list[str]
    links: dict[str, list[str]]
    sliders: dict[str, SliderSection] = Field(default_factory=dict)
    slots: dict[str, SlotSection] = Field(default_factory=dict)
    cylinders: dict[str, CylinderSection] = Field(default_factory=dict)
    gears: dict[str, GearSection] = Field(default_factory=dict)
    masses: dict[str, LinkMassSection | Mass] = Field(default_factory=dict)

    def build(self, drivers: list[DriverSection]) -> Mechanism:
        """The mechanism of the drawing (errors name the ``sketch.`` key)."""
        linear = {*self.sliders, *self.cylinders}
        for i, d in enumerate(drivers):
            key = "driver" if len(drivers) == 1 else f"driver.{i}"
            if (d.type == "linear") != (d.joint in linear):
                raise ParameterError(f"{key}.type", d.type,
                                     f"must be {'linear' if d.joint in linear else 'crank'}"
                                     f" for joint {d.joint!r}, " + (
                                         "a slider or cylinder of the sketch"
                                         if d.joint in linear else "which is not a slider or "
                                         "cylinder of the sketch (a linear driver drives a "
                                         "[sketch.sliders] or [sketch.cylinders] entry)"))
        masses = {k: (v.model_dump() if isinstance(v, LinkMassSection) else v)
                  for k, v in self.masses.items()}
        try:
            return sketch(dict(self.points), self.links, ground=self.ground,
                          drivers=[d.sketch_spec() for d in drivers],
                          sliders={k: v.model_dump() for k, v in self.sliders.items()},
                          slots={k: v.model_dump() for k, v in self.slots.items()},
                          cylinders={k: v.model_dump() for k, v in self.cylinders.items()},
                          gears={k: v.model_dump(exclude_defaults=True)
                                 for k, v in self.gears.items()},
                          masses=masses, frame=self.frame,
                          speeds={d.joint: d.speeds() for d in drivers})
        except ParameterError as exc:
            raise ParameterError(f"sketch.{exc.parameter}", exc.value, exc.limit) from None
        except LinkworkError as exc:
            raise ParameterError("sketch", "the drawing", str(exc)) from None


#: The most driver positions of ``[analysis] n``. ``linkwork analyze`` on a file of one driver
#: works through a cycle longer than :data:`MAX_WHOLE_POSITIONS` chunk by chunk in bounded
#: memory (:func:`linkwork.studies.planar.analyze_chunked`), but its two CSV files grow with
#: the positions: about :data:`CSV_BYTES_PER_POSITION` for the largest example
#: (``loom_sixbar``: 2.1 GB at the limit, some three minutes on this machine). Beyond it (the
#: schema allowed 10^7: 11 GB of memory and 8 GB of CSV) a file is refused before any work;
#: a finer step over part of the cycle is a narrower ``start``/``stop``.
MAX_POSITIONS = 1_000_000

#: The most positions of a cycle held whole in memory: ``linkwork analyze`` up to it (above it
#: a file of one driver goes chunk by chunk), and every command that holds the whole cycle
#: (``analyze`` with several drivers, ``balance`` along several drivers' path, ``report``):
#: about :data:`BYTES_PER_POSITION` per position (kinematics, dynamics, the CSV/JSON columns
#: of every body and named point, the plots), so the largest example peaks near 0.3 GB here.
MAX_WHOLE_POSITIONS = 50_000

#: Peak memory per position of ``linkwork analyze examples/loom_sixbar.toml`` over the whole
#: cycle [bytes], stated in the message: resident set size 296 MB at 5*10^4 positions (457 MB
#: before ``planar.json`` was written from the arrays, 1.10 GB before the dynamics were solved
#: in chunks), rounded up.
BYTES_PER_POSITION = 6_000

#: Bytes of ``planar_kinematics.csv`` and ``planar_dynamics.csv`` per position for
#: ``examples/loom_sixbar.toml`` (213 MB at 10^5 positions), rounded up.
CSV_BYTES_PER_POSITION = 2_200


def whole_cycle_limit(n: int, needs: str) -> str:
    """The message for a cycle of ``n`` positions above :data:`MAX_WHOLE_POSITIONS` where
    ``needs`` (e.g. ``"linkwork report"``) holds the whole cycle."""
    return (f"must be at most {MAX_WHOLE_POSITIONS} positions for {needs}, which holds the "
            f"whole cycle (got {n}): about {BYTES_PER_POSITION // 1000} kB of memory per "
            f"position, {n * BYTES_PER_POSITION / 1e9:.3g} GB asked; for a finer step "
            "analyse part of the range (start, stop)")


class AnalysisSection(FileModel):
    """Driver positions, branches, gravity, shaking-moment point."""

    start: float | str = 0.0
    stop: float | str = "360 deg"
    n: Annotated[int, Field(ge=2)] = 361
    branches: dict[str, Literal[1, -1]] = Field(default_factory=dict)
    gravity: tuple[Acceleration, Acceleration] | None = None
    about: XY = (0.0, 0.0)

    @field_validator("n")
    @classmethod
    def _bounded(cls, v: int) -> int:
        if v > MAX_POSITIONS:
            raise ValueError(
                f"must be at most {MAX_POSITIONS} positions (got {v}): above "
                f"{MAX_WHOLE_POSITIONS} `linkwork analyze` works chunk by chunk in bounded "
                f"memory, but its CSV files take about {CSV_BYTES_PER_POSITION / 1000:g} kB "
                f"per position ({v * CSV_BYTES_PER_POSITION / 1e9:.3g} GB asked, "
                f"{MAX_POSITIONS * CSV_BYTES_PER_POSITION / 1e9:.2g} GB at the limit); for a "
                "finer step analyse part of the range (start, stop)")
        return v


class DiagramSection(FileModel):
    """``[load.diagram]``: the load's value as a table over the driver or a slide's position
    (:class:`~linkwork.planar.forces.LoadDiagram`)."""

    over: str = "driver"
    table: list[tuple[float | str, float | str]]
    when: Literal["always", "increasing", "decreasing"] = "always"
    outside: Literal["zero", "error"] = "zero"

    _diagrams: dict[tuple[str, bool, str], LoadDiagram] = PrivateAttr(default_factory=dict)

    def build(self, key: str, linear: bool, value_kind: str) -> LoadDiagram:
        """The diagram in SI: positions are crank angles (a plain number in radians) when it is
        over a crank, slides [m] otherwise; values of ``value_kind``. ``key``: the dotted key of
        this table (``load.2.diagram``), which every error names (a row: ``table.3``). Built
        once per (key, driver, kind): the file's check and every analysis share it."""
        done = self._diagrams.get((key, linear, value_kind))
        if done is None:
            done = self._diagrams[key, linear, value_kind] = self._build(key, linear, value_kind)
        return done

    def _column(self, col: int, kind: str, key: str) -> np.ndarray:
        """Column ``col`` of the table in SI, checked as :func:`quantity` checks a value: plain
        numbers at once (a measured curve of 10^6 rows took 8 s a column one by one), strings
        with their units one by one; an error names the first bad row."""
        raw = [row[col] for row in self.table]
        plain = np.array([isinstance(v, int | float) and not isinstance(v, bool) for v in raw],
                         dtype=bool)
        out = np.zeros(len(raw))
        out[plain] = [v for v, p in zip(raw, plain, strict=True) if p]
        bad = plain & ~(np.abs(out) <= MAGNITUDE_LIMITS.get(kind, math.inf))  # NaN too
        first_bad = int(np.argmax(bad)) if bad.any() else len(raw)
        for r in np.flatnonzero(~plain[:first_bad]):  # the rows before it, in order
            out[r] = quantity(raw[r], kind, f"{key}.table.{r}.{col}")
        if first_bad < len(raw):  # its error, worded as quantity() words it
            quantity(raw[first_bad], kind, f"{key}.table.{first_bad}.{col}")
        return out

    def _build(self, key: str, linear: bool, value_kind: str) -> LoadDiagram:
        kind = "angle" if self.over == "driver" and not linear else "length"
        xs = self._column(0, kind, key)
        ys = self._column(1, value_kind, key)
        far = ~(np.abs(xs) <= MAX_ANGLE) if kind == "angle" else np.zeros(xs.size, bool)
        back = np.concatenate([[False], ~(xs[1:] > xs[:-1])])
        if far.any() or back.any():
            r = int(np.argmax(far | back))
            if far[r]:
                raise ParameterError(f"{key}.table.{r}.0", self.table[r][0],
                                     f"must lie within +-{MAX_ANGLE:g} rad")
            raise ParameterError(f"{key}.table.{r}.0", self.table[r][0], (
                f"the table's positions must increase strictly: it must be > "
                f"{self.table[r - 1][0]} (row {r - 1})"))
        try:
            return LoadDiagram(xs.tolist(), ys.tolist(), self.over, self.when, self.outside)
        except ParameterError as exc:
            row = exc.parameter.removeprefix("position[").removesuffix("]")
            where = f"table.{row}.0" if row.isdigit() else "table"
            raise ParameterError(f"{key}.{where}", exc.value, exc.limit) from None


#: The keys each ``[[load]]`` type takes (besides ``type`` and ``name``).
_LOAD_KEYS = {
    "force": ("body", "point", "fx", "fy", "phi_range", "from_frame", "diagram", "angle"),
    "torque": ("body", "mz", "phi_range", "from_frame", "diagram"),
    "slide": ("joint", "force", "phi_range", "diagram"),
    "drag": ("body", "point", "force", "damping", "from_frame"),
}


class LoadSection(FileModel):
    """An external load: a force at a point (frame axes), a couple on a body, a force along
    a prismatic or slot joint's line, or a drag opposing a point's velocity; the value of the
    first three constant, over ``phi_range``, or a diagram."""

    type: Literal["force", "torque", "slide", "drag"]
    name: str = ""
    body: str | None = None
    point: str | XY = "com"
    fx: Force = 0.0
    fy: Force = 0.0
    mz: Torque = 0.0
    joint: str | None = None
    force: Force = 0.0
    damping: Damping = 0.0
    angle: Angle = 0.0
    diagram: DiagramSection | None = None
    phi_range: tuple[float | str, float | str] | None = None
    from_frame: bool = False

    def driver_range(self, i: int, linear: bool) -> tuple[float, float] | None:
        """``phi_range`` in SI: angles [rad] for a crank (the range may wrap through 0), slide
        positions [m] for a linear driver (end > start)."""
        if self.phi_range is None:
            return None
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
        takes = _LOAD_KEYS[self.type]
        unused = tuple(k for keys in _LOAD_KEYS.values() for k in keys if k not in takes)
        what = {"force": "a force at a point (fx, fy, point, or a diagram along angle); give a "
                         "couple as a separate [[load]] of type = 'torque'",
                "torque": "a couple on the body (mz, or a diagram); give a force as a separate "
                          "[[load]] of type = 'force'",
                "slide": "a force along a prismatic or slot joint's line (joint, force, or a "
                         "diagram)",
                "drag": "a force against a point's velocity (body, point, force, damping)"}
        _refuse_keys(self, tuple(dict.fromkeys(unused)), what[self.type])
        need = "joint" if self.type == "slide" else "body"
        if getattr(self, need) is None:
            raise ParameterError(need, None, f"is required by type = {self.type!r}")
        if self.diagram is not None:
            value = {"force": ("fx", "fy"), "torque": ("mz",), "slide": ("force",)}[self.type]
            _refuse_keys(self, (*value, "phi_range"), "its value from the diagram (and its "
                         "range from the diagram's table)")
            if self.type == "force" and "angle" not in self.model_fields_set:
                raise ParameterError("angle", None, "is required by a force given by a "
                                     "diagram: its direction in the frame's axes")
        elif "angle" in self.model_fields_set:
            raise ParameterError("angle", self.angle, "is the direction of a force given by a "
                                 "diagram: give [load.diagram], or fx and fy")
        return self

    def build(self, phi1: np.ndarray, i: int = 0, linear: bool = False) -> Load:
        """The load as the engine takes it (its name: ``name`` or ``load.<i>``); a constant
        value acts over ``phi_range`` (evaluated at ``phi1``), a diagram as its table says."""
        name = self.name or f"load.{i}"
        if self.type == "drag":
            return Drag(str(self.body), self.point, self.force, self.damping, self.from_frame,
                        name)
        if self.diagram is not None:
            key = f"load.{i}.diagram"
            d = self.diagram.build(key, linear, "torque" if self.type == "torque" else "force")
            if self.type == "force":
                return PointForce(str(self.body), self.point, d.times(math.cos(self.angle)),
                                  d.times(math.sin(self.angle)), self.from_frame, name)
            if self.type == "torque":
                return BodyTorque(str(self.body), d, self.from_frame, name)
            return SlideForce(str(self.joint), d, name)
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
            return PointForce(str(self.body), self.point, self.fx * on, self.fy * on,
                              self.from_frame, name)
        if self.type == "torque":
            return BodyTorque(str(self.body), self.mz * on, self.from_frame, name)
        return SlideForce(str(self.joint), self.force * on, name)


class _TwoPointSection(FileModel):
    """An element between a point of body ``a`` and a point of body ``b`` (either may be the
    frame): a point name, ``"com"`` or [x, y] in the body's frame."""

    name: str = ""
    a: str
    point_a: str | XY
    b: str
    point_b: str | XY


class SpringSection(_TwoPointSection):
    """``[[spring]]``: a linear spring (:class:`~linkwork.planar.forces.Spring`)."""

    stiffness: Stiffness
    free_length: Length
    preload: Force = 0.0

    def build(self, i: int) -> Spring:
        return Spring(self.a, self.point_a, self.b, self.point_b, self.stiffness,
                      self.free_length, self.preload, self.name or f"spring.{i}")


class DamperSection(_TwoPointSection):
    """``[[damper]]``: a viscous damper (:class:`~linkwork.planar.forces.Damper`)."""

    damping: Damping

    def build(self, i: int) -> Damper:
        return Damper(self.a, self.point_a, self.b, self.point_b, self.damping,
                      self.name or f"damper.{i}")


class BalanceSection(FileModel):
    """The optional ``[balance]`` table of a planar mechanism file."""

    links: list[str] | None = None
    radii: dict[str, float] | float | None = None
    angles: list[float] | None = None
    n: int = Field(default=360, ge=12, le=20000)

    @field_validator("angles", mode="before")
    @classmethod
    def _angles(cls, v: Any) -> list[float] | None:
        """Table positions in degrees: plain numbers are degrees (as ``--angles``); strings
        carry their unit ("30 deg", "0.5 rad")."""
        max_deg = math.degrees(MAX_ANGLE)
        if v is None:
            return None
        if not isinstance(v, list) or not v:
            raise ValueError("must be a non-empty list of angles, e.g. [0, 30, 60] (degrees) "
                             "or [\"0 deg\", \"0.5 rad\"]")
        out = []
        for x in v:
            if isinstance(x, bool) or not isinstance(x, (int, float, str)):
                raise ValueError(f"must be numbers in degrees or angles with a unit (got {x!r})")
            try:
                deg = float(np.degrees(to_si(x, "angle"))) if isinstance(x, str) else float(x)
            except LinkworkError as exc:
                raise ValueError(f"{getattr(exc, 'limit', exc)} (got {x!r})") from None
            if not np.isfinite(deg):
                raise ValueError(f"must be finite (got {x!r})")
            if abs(deg) > max_deg:  # as --angles: no 300-digit angles in the table
                raise ValueError(f"must lie within +-{max_deg:.6g} deg (got {x!r})")
            out.append(deg)
        return out

    @field_validator("radii", mode="before")
    @classmethod
    def _radii(cls, v: Any) -> dict[str, float] | float | None:
        """One length for every link or a table link -> length, each > 0 [m].

        Validated here rather than by a union of pydantic types, whose error locations named
        the union's internal types (``balance.radii.dict[str,function-before[...]].crank``).
        """
        def one(key: str, x: Any) -> float:
            got = "" if key == "radius" else f" (got {x!r})"  # the file's value is quoted after
            if isinstance(x, bool) or not isinstance(x, (int, float, str)):
                raise ValueError(f"{key} must be a length, e.g. '50 mm'{got}")
            try:
                r = to_si(x, "length", key)
            except LinkworkError as exc:
                raise ValueError(f"{key}: {getattr(exc, 'limit', exc)}{got}") from None
            if not (np.isfinite(r) and r > 0.0):
                raise ValueError(f"{key} must be > 0{got}")
            return r

        if v is None:
            return None
        if isinstance(v, dict):
            return {str(k): one(f"radius of {k}", x) for k, x in v.items()}
        return one("radius", v)


_KIND = Literal["revolute", "cylindrical", "spherical", "sphere_cylinder", "prismatic",
                "prismatic_round", "spur", "crowned"]
_COMPONENT = Literal["dx", "dy", "dz", "tx", "ty", "tz"]


def _spatial_quantity(value: Any, kind: str) -> float:
    try:
        return to_si(value, kind)
    except ParameterError as exc:
        raise ValueError(exc.limit) from None


class JointSpec(FileModel):
    """``[spatial.joints.<name>]`` (and ``[spatial] default``)."""

    kind: _KIND | None = None
    e: Annotated[Length, Field(gt=0)] | None = None
    z: Length | None = None
    stiffness: list[Any] | None = None
    k_bearing: Annotated[Stiffness, Field(gt=0)] | None = None
    axial_ratio: Annotated[float, Field(gt=0)] | None = None

    @field_validator("stiffness")
    @classmethod
    def _stiffness(cls, v: list[Any] | None) -> list[float] | None:
        if v is None:
            return None
        if len(v) != 6:
            raise ValueError("must list 6 values (3 forces [N/m], 3 moments [N*m/rad])")
        out = [_spatial_quantity(x, "stiffness") for x in v[:3]]
        out += [_spatial_quantity(x, "rotational_stiffness") for x in v[3:]]
        return out

    def kwargs(self) -> dict[str, Any]:
        """The set fields as keyword arguments of :class:`~linkwork.redundancy.SpatialJoint`."""
        out = {k: v for k, v in self.model_dump().items() if v is not None}
        if "stiffness" in out:
            out["stiffness"] = tuple(out["stiffness"])
        return out


class DeviationSpec(FileModel):
    """``[[spatial.deviation]]``: deviation of the element of ``joint`` carried by ``body``."""

    joint: str
    body: str
    dx: Length = 0.0
    dy: Length = 0.0
    dz: Length = 0.0
    tx: Angle = 0.0
    ty: Angle = 0.0
    tz: Angle = 0.0

    @field_validator("tx", "ty", "tz")
    @classmethod
    def _small_tilt(cls, v: float) -> float:
        try:
            return check_tilt("tilt", v)
        except ParameterError as exc:
            raise ValueError(f"{exc.limit}") from None


class OutOfPlaneSpec(FileModel):
    """``[[spatial.out_of_plane]]``: fz [N] at the centre of mass, mx, my [N m]."""

    body: str
    fz: Force = 0.0
    mx: Torque = 0.0
    my: Torque = 0.0


class ToleranceSpec(FileModel):
    """``[[spatial.tolerance]]``: tolerance of one deviation component."""

    joint: str
    body: str
    component: _COMPONENT
    limit: Any
    distribution: Literal["normal", "uniform"] = "normal"
    mean: Any = 0.0

    @field_validator("limit", "mean")
    @classmethod
    def _to_si(cls, v: Any, info: pydantic.ValidationInfo) -> float:
        comp = info.data.get("component", "dx")
        value = _spatial_quantity(v, "length" if str(comp).startswith("d") else "angle")
        if info.field_name == "limit" and value < 0:
            raise ValueError("must be >= 0")
        if str(comp).startswith("t"):
            try:
                check_tilt(str(info.field_name), value)
            except ParameterError as exc:
                raise ValueError(f"{exc.limit}") from None
        return value


#: The most positions of the cycle of ``linkwork reactions`` (``[spatial] positions``, or the
#: ``[analysis] n`` positions when it is not set): the spatial model keeps matrices per position;
#: measured 1.41 GB resident for ``loom_sixbar`` (7 joints) with its plots at 20 000 positions,
#: 0.55 GB for ``loom_fourbar_spatial`` (4 joints) without plots. (The schema allowed 10^5.)
MAX_SPATIAL_POSITIONS = 20_000

#: Peak memory of ``linkwork reactions`` per cycle position for the six-bar [bytes], rounded up.
BYTES_PER_SPATIAL_POSITION = 70_000


def spatial_positions_limit(n: int) -> str:
    """The message for ``n`` reactions positions above :data:`MAX_SPATIAL_POSITIONS`."""
    return (f"must be at most {MAX_SPATIAL_POSITIONS} positions for the spatial reactions "
            f"(about {BYTES_PER_SPATIAL_POSITION // 1000} kB of memory per position for a "
            f"seven-joint mechanism: {n * BYTES_PER_SPATIAL_POSITION / 1e9:.3g} GB asked)")


class SpatialSpec(FileModel):
    """The ``[spatial]`` table."""

    k_bearing: Annotated[Stiffness, Field(gt=0)] = DEFAULT_BEARING_STIFFNESS
    axial_ratio: Annotated[float, Field(gt=0)] = 1.0
    positions: Annotated[int, Field(ge=8)] | None = None
    default: JointSpec = JointSpec()
    joints: dict[str, JointSpec] = Field(default_factory=dict)
    heights: dict[str, Length] = Field(default_factory=dict)
    deviation: list[DeviationSpec] = Field(default_factory=list)
    out_of_plane: list[OutOfPlaneSpec] = Field(default_factory=list)
    tolerance: list[ToleranceSpec] = Field(default_factory=list)

    @field_validator("positions")
    @classmethod
    def _positions_bounded(cls, v: int | None) -> int | None:
        if v is not None and v > MAX_SPATIAL_POSITIONS:
            raise ValueError(spatial_positions_limit(v))
        return v

    def n_deviations(self) -> int:
        """The deviations a tolerance study draws or holds fixed: one per
        ``[[spatial.tolerance]]`` and one per non-zero component of a joint element's
        ``[[spatial.deviation]]`` (the count that bounds ``--tolerance-study``)."""
        fixed = {(d.joint, d.body, c) for d in self.deviation
                 for c in ("dx", "dy", "dz", "tx", "ty", "tz") if getattr(d, c) != 0.0}
        return len(self.tolerance) + len(fixed)

    def default_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for joints not listed (bearing defaults included)."""
        return {"k_bearing": self.k_bearing, "axial_ratio": self.axial_ratio,
                **self.default.kwargs()}

    def joint_kwargs(self) -> dict[str, dict[str, Any]]:
        """Per-joint keyword arguments (over the defaults)."""
        return {name: {**self.default_kwargs(), **spec.kwargs()}
                for name, spec in self.joints.items()}


def _spatial_error(path: str | Path, err: Any) -> FileFormatError:
    """The error of the ``[spatial]`` table, worded as ``linkwork reactions`` words it: the
    dotted key from ``spatial``, pydantic's message with the value given."""
    key = ".".join(["spatial", *(str(x) for x in err["loc"])])
    return FileFormatError(str(path), key, message(err))


def read_spatial(path: str | Path, raw: dict[str, Any]) -> SpatialSpec:
    """Validate the ``spatial`` table of a file already read with :func:`~linkwork.io.toml.
    read_toml` (a :class:`PlanarFile` reads it as its ``spatial`` section).

    A missing table gives the defaults. Problems raise FileFormatError naming the file and the
    dotted key (``spatial.joints.A.e``).
    """
    data = raw.get("spatial", {})
    if not isinstance(data, dict):
        raise FileFormatError(str(path), "spatial", "must be a table")
    try:
        return SpatialSpec.model_validate(data)
    except pydantic.ValidationError as exc:
        raise _spatial_error(path, exc.errors()[0]) from None


class PlanarFile(FileModel):
    """A planar mechanism for the general engine (see the module docstring)."""

    type: Literal["planar"]
    name: str = ""
    description: str = ""
    source: str = ""
    frame: FrameSection | None = None
    body: list[BodySection] = Field(default_factory=list)
    joint: list[JointSection] = Field(default_factory=list)
    sketch: SketchSection | None = None
    if TYPE_CHECKING:  # the one [driver] for the code written for one (several: DriverTables)
        driver: DriverSection
    else:
        driver: Annotated[Annotated[DriverSection, Tag("[driver]")]
                          | Annotated[list[DriverSection], Tag("[[driver]]")],
                          Discriminator(_driver_tables)]
    analysis: AnalysisSection = Field(default_factory=lambda: AnalysisSection())
    load: list[LoadSection] = Field(default_factory=list)
    spring: list[SpringSection] = Field(default_factory=list)
    damper: list[DamperSection] = Field(default_factory=list)
    balance: BalanceSection = Field(default_factory=lambda: BalanceSection())
    spatial: SpatialSpec = Field(default_factory=lambda: SpatialSpec())
    drive: DriveSection | None = None
    #: The Mechanism built (and decomposed) when the file was validated, with the sections it
    #: was built from: :meth:`mechanism` returns it while they are the same objects.
    _built: tuple[tuple[Any, ...], Mechanism] | None = PrivateAttr(default=None)

    @classmethod
    def from_data(cls, path: str | Path, data: dict[str, Any]) -> Self:
        """Validate a planar file read from ``path``: the mechanism, its loads and the optional
        ``[balance]`` and ``[spatial]`` sections, once; errors name the file and the key."""
        for table in ("spatial", "balance"):
            if table in data and not isinstance(data[table], dict):
                raise FileFormatError(str(path), table, "must be a table")
        if "sketch" not in data:
            for key in ("frame", "body", "joint"):
                if key not in data:  # as pydantic words it, and the way out
                    raise FileFormatError(str(path), key, "missing required key (or describe "
                                          "the mechanism by its drawing in a [sketch])")
        try:
            doc = cls.model_validate(data)
        except pydantic.ValidationError as exc:
            spatial = [e for e in exc.errors() if e["loc"][:1] == ("spatial",)]
            if spatial and len(spatial) == exc.error_count():  # as `reactions` words them
                err = spatial[0]
                raise _spatial_error(path, {**err, "loc": err["loc"][1:]}) from None
            raise _validation_error(str(path), exc, data) from None
        except ParameterError as exc:  # raised by model validators that build mechanisms
            raise parameter_error(path, exc, data) from None
        doc._check_spatial_names(path)
        return doc

    def check_spatial_positions(self, path: str | Path) -> None:
        """Refuse a cycle of more than :data:`MAX_SPATIAL_POSITIONS` for ``linkwork reactions``
        before any work: ``[analysis] n`` when ``[spatial] positions`` does not resample it
        (``[spatial] positions`` itself is checked when the file is read)."""
        n = self.analysis.n
        if self.spatial.positions is None and n > MAX_SPATIAL_POSITIONS:
            raise FileFormatError(str(path), "analysis.n", spatial_positions_limit(n)
                                  + f" (got {n}); set [spatial] positions to resample the "
                                  "range for the reactions")

    def check_whole_cycle(self, path: str | Path, needs: str) -> None:
        """Refuse ``[analysis] n`` above :data:`MAX_WHOLE_POSITIONS` for ``needs`` (a command
        that holds the whole cycle: ``"linkwork report"``), before any work."""
        n = self.analysis.n
        if n > MAX_WHOLE_POSITIONS:
            raise FileFormatError(str(path), "analysis.n", whole_cycle_limit(n, needs))

    @model_validator(mode="after")
    def _as_driver_tables(self) -> PlanarFile:
        """Several ``[[driver]]``: a :class:`DriverTables` list (one-driver keys refused by
        name)."""
        d: Any = self.driver
        if isinstance(d, list):
            self.__dict__["driver"] = DriverTables(d)
        return self

    @model_validator(mode="after")
    def _one_description(self) -> PlanarFile:
        """The mechanism is described either by ``[frame]``, ``[[body]]``, ``[[joint]]`` or by
        a ``[sketch]`` (its drawing), not both."""
        if self.sketch is not None:
            given = [k for k in ("frame", "body", "joint") if k in self.model_fields_set]
            if given:
                raise ParameterError(given[0], f"[{given[0]}]", "a [sketch] describes the "
                                     f"mechanism by its drawing: leave out [{given[0]}] (or "
                                     "describe it by [frame], [[body]], [[joint]] without "
                                     "[sketch])")
        else:
            missing = [k for k in ("frame", "body", "joint") if k not in self.model_fields_set]
            if missing:
                raise ParameterError(missing[0], "missing", "a required key (or describe the "
                                     "mechanism by its drawing in a [sketch])")
        return self

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
        return self

    @property
    def drivers(self) -> list[DriverSection]:
        """The ``[driver]`` table, or each ``[[driver]]`` of several, in order."""
        d: Any = self.driver
        return list(d) if isinstance(d, list) else [d]

    def mechanism(self) -> Mechanism:
        """The engine model described by the file (built once: an immutable Mechanism whose
        structure analysis is cached with it)."""
        sources = (self.frame, self.body, self.joint, self.sketch, self.driver, self.analysis)
        if self._built is not None and all(
                a is b for a, b in zip(self._built[0], sources, strict=True)):
            return self._built[1]
        if self.sketch is not None:
            mech = self.sketch.build(self.drivers)
            if self.analysis.branches:  # explicit branches override the drawing's
                mech = mech.with_branches(**self.analysis.branches)
            self._built = (sources, mech)
            return mech
        assert self.frame is not None  # _one_description
        frame = Body(self.frame.name, self.frame.points)
        bodies = tuple(b.build() for b in self.body)
        joints = tuple(j.build() for j in self.joint)
        drivers: Any = tuple(d.build() for d in self.drivers)
        mech = Mechanism(frame, bodies, joints, drivers[0] if len(drivers) == 1 else drivers,
                         dict(self.analysis.branches))
        self._built = (sources, mech)
        return mech

    def positions(self) -> np.ndarray:
        """Driver positions [rad, or m for a linear driver]: shape (n,) for one driver (from
        ``[analysis] start`` to ``stop``); (n_drivers, n) for several, each driver from its
        own ``start`` to ``stop``."""
        drivers = self.drivers
        if len(drivers) > 1:
            given = [k for k in ("start", "stop") if k in self.analysis.model_fields_set]
            if given:
                raise ParameterError(f"analysis.{given[0]}", getattr(self.analysis, given[0]),
                                     "is the one driver's; with several drivers each "
                                     "[[driver]] gives its own start and stop")
            spans = [d.span(f"driver.{i}") for i, d in enumerate(drivers)]
            return np.array([np.linspace(a, b, self.analysis.n) for a, b in spans])
        for key in ("start", "stop"):
            if getattr(drivers[0], key) is not None:
                raise ParameterError(f"driver.{key}", getattr(drivers[0], key),
                                     "give the one driver's range as [analysis] start, stop")
        kind = "angle" if drivers[0].type == "crank" else "length"
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
            raise ParameterError("analysis.stop", self.analysis.stop,
                                 f"must be > analysis.start = {self.analysis.start}")
        return np.linspace(lo, hi, self.analysis.n)

    def loads(self, phi1: np.ndarray) -> list[Load]:
        """External loads and force elements at the driver positions ``phi1``: the
        ``[[load]]`` tables (constant values evaluated over ``phi_range``), then the
        ``[[spring]]`` and ``[[damper]]`` tables; named as written or ``load.<i>``,
        ``spring.<i>``, ``damper.<i>`` (:meth:`load_keys` gives their file keys).

        Raises
        ------
        ParameterError
            A load names no moving body (``load.<i>.body``) or no point of its body
            (``load.<i>.point``), ... (checked when the file is read).
        """
        self._check_loads()
        linear = self.drivers[0].type == "linear"
        return [*(ld.build(phi1, i, linear) for i, ld in enumerate(self.load)),
                *(sp.build(i) for i, sp in enumerate(self.spring)),
                *(dp.build(i) for i, dp in enumerate(self.damper))]

    def load_keys(self) -> list[str]:
        """The file key of each entry of :meth:`loads`, in its order (``load.2``,
        ``spring.0``)."""
        return [*(f"load.{i}" for i in range(len(self.load))),
                *(f"spring.{i}" for i in range(len(self.spring))),
                *(f"damper.{i}" for i in range(len(self.damper)))]

    def file_error(self, exc: ParameterError) -> ParameterError:
        """``exc`` with a load's parameter as the file writes it: ``loads[3].point_a`` (the
        engine's name, by the place in :meth:`loads`) becomes ``spring.0.point_a``, a diagram's
        ``loads[1].force.position`` becomes ``load.1.diagram.table``. Other errors are
        returned as they are."""
        m = re.fullmatch(r"loads\[(\d+)\](.*)", exc.parameter)
        keys = self.load_keys()
        if m is None or int(m[1]) >= len(keys):
            return exc
        rest = m[2]
        d = re.fullmatch(r"\.(fx|fy|mz|force)\.(position|value|over)(.*)", rest)
        if d is not None and keys[int(m[1])].startswith("load."):
            rest = ".diagram." + ("over" if d[2] == "over" else "table") + d[3]
        return ParameterError(keys[int(m[1])] + rest, exc.value, exc.limit)

    def _check_loads(self) -> None:
        """Every load and force element fits the mechanism (bodies, points, joints, values,
        diagrams; checked when the file loads, so that the error carries the file's name and
        its keys); names are unique."""
        mech = self.mechanism()
        linear = self.drivers[0].type == "linear"
        moving = {b.name: b for b in mech.bodies}
        for i, ld in enumerate(self.load):
            if ld.phi_range is not None and len(self.drivers) > 1:
                raise ParameterError(f"load.{i}.phi_range", list(ld.phi_range),
                                     "is a range of the one driver's positions; with several "
                                     "drivers a load acts over the whole path")
            if ld.body is not None and ld.body not in moving:
                why = ("loads act on moving bodies, not on the frame"
                       if ld.body == mech.frame.name else "no such moving body")
                raise ParameterError(f"load.{i}.body", ld.body, f"{why}; known: {list(moving)}")
            if ld.body is not None and isinstance(ld.point, str) and ld.point != "com":
                known = list(moving[ld.body].points)
                if ld.point not in known:
                    raise ParameterError(f"load.{i}.point", ld.point,
                                         f"no such point of body {ld.body!r}; known: "
                                         f"{[*known, 'com']}")
            ld.driver_range(i, linear)
            if ld.diagram is not None:
                ld.diagram.build(f"load.{i}.diagram", linear, "torque" if ld.type == "torque"
                                 else "force").check(mech, f"load.{i}.diagram")
        sections: list[tuple[str, LoadSection | SpringSection | DamperSection]] = [
            *((f"load.{i}", ld) for i, ld in enumerate(self.load)),
            *((f"spring.{i}", sp) for i, sp in enumerate(self.spring)),
            *((f"damper.{i}", dp) for i, dp in enumerate(self.damper))]
        built: list[tuple[str, Load]] = []
        for key, sec in sections:
            i = int(key.rsplit(".", 1)[1])
            try:
                built.append((key, sec.build(np.zeros(1), i, linear)
                              if isinstance(sec, LoadSection) else sec.build(i)))
            except ParameterError as exc:  # a value the element refuses (stiffness < 0)
                if exc.parameter.startswith(f"{key}."):  # already the file's key
                    raise
                raise ParameterError(f"{key}.{exc.parameter}", exc.value, exc.limit) from None
        names: dict[str, str] = {}
        for key, el in built:
            el.check(mech, key)  # names its keys under ``key`` (the diagrams: checked above)
            if el.name in names:
                raise ParameterError(f"{key}.name", el.name, f"must be unique among the "
                                     f"loads, springs and dampers (also {names[el.name]})")
            names[el.name] = key

    def _check_spatial_names(self, path: str | Path) -> None:
        """Every joint and body the ``[spatial]`` table names exists in the mechanism.

        Raises FileFormatError naming the file, the dotted key, the unknown name and the known
        ones (the model layer would name only its own parameter, e.g. ``joints = Z``).
        """
        mech = self.mechanism()
        spec = self.spatial
        joints = {j.name: j for j in mech.joints}
        moving = [b.name for b in mech.bodies]

        def known_joint(key: str, name: str) -> Any:
            if name not in joints:
                raise FileFormatError(str(path), key, f"no joint {name!r}; known: "
                                      f"{list(joints)}")
            return joints[name]

        for name in spec.joints:
            known_joint(f"spatial.joints.{name}", name)
        for key, body in [*((f"spatial.heights.{b}", b) for b in spec.heights),
                          *((f"spatial.out_of_plane.{i}.body", o.body)
                            for i, o in enumerate(spec.out_of_plane))]:
            if body not in moving:
                raise FileFormatError(str(path), key, f"no moving body {body!r}; known: "
                                      f"{moving}")
        named: list[tuple[str, list[DeviationSpec | ToleranceSpec]]] = [
            ("deviation", [*spec.deviation]), ("tolerance", [*spec.tolerance])]
        for table, items in named:
            for i, item in enumerate(items):
                j = known_joint(f"spatial.{table}.{i}.joint", item.joint)
                if item.body not in (j.a, j.b):
                    raise FileFormatError(str(path), f"spatial.{table}.{i}.body",
                                          f"{item.body!r} is not a body of joint "
                                          f"{item.joint!r}: must be {j.a!r} or {j.b!r}")
