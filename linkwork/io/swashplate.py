"""The ``swashplate`` file: a spatial crank (inclined-disk) drive of a rotor machine (paper 003).

Example (``examples/swashplate_4a.toml``)::

    type = "swashplate"
    name = "Drawing rotor, classic inclined disk"
    scheme = "4a"            # 1, 2, 3, 4a, 4b (the paper's table)

    [geometry]
    R = "100 mm"             # rotor pitch radius
    l = "200 mm"             # rod length
    alpha = "15 deg"         # disk tilt
    # r, a, b: as the scheme leaves them free (4a: r = R / cos(alpha), a = b = 0)

    [operation]
    speed = "30 rpm"         # rotor speed; or productivity + positions
    positions = 12           # slides u on the rotor
    v_allow = "0.3 m/s"      # optional slide-speed limit (checked)
    delta_allow = "8 deg"    # optional allowed pressure angle (checked)

    [load]                   # optional: technological force on a slide (load diagram)
    angles = ["0 deg", "90 deg", "180 deg", "270 deg"]
    forces = ["0 kN", "20 kN", "0 kN", "0 kN"]
    rho_guide = "5 deg"      # friction angle of the slide in its guide
    guide_length = "80 mm"   # optional: slide's bearing length in the guide
    overhang = "30 mm"       # optional: rod joint below the guided length

    [output]
    samples = 361

Plain numbers are SI (metres, radians); strings carry units. Unknown keys are errors; a parameter
the scheme fixes (e.g. ``a`` in scheme 4a) is an error too.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from linkwork.errors import LinkworkError, ParameterError
from linkwork.io.toml import (
    Angle,
    AngularVelocity,
    FileModel,
    Force,
    Frequency,
    Length,
    Velocity,
)
from linkwork.models import swashplate as sw

__all__ = ["GeometrySection", "LoadSection", "OperationSection", "OutputSection",
           "SwashplateFile"]


PositiveLength = Annotated[Length, Field(gt=0)]


class GeometrySection(FileModel):
    """``[geometry]``: ``R``, ``l`` and what the scheme leaves free of ``r``, ``alpha``, ``a``,
    ``b`` (lengths [m], ``alpha`` [rad])."""

    R: PositiveLength
    l: PositiveLength
    r: PositiveLength | None = None
    alpha: Angle | None = None
    a: Length | None = None
    b: Length | None = None


class OperationSection(FileModel):
    """``[operation]``: rotor ``speed`` [rad/s] or ``productivity`` [1/s] with ``positions``;
    optional limits ``v_allow`` [m/s] and ``delta_allow`` [rad] that the analysis checks."""

    speed: Annotated[AngularVelocity, Field(gt=0)] | None = None
    productivity: Annotated[Frequency, Field(gt=0)] | None = None
    positions: Annotated[int, Field(ge=1, le=1000)] = 1
    v_allow: Annotated[Velocity, Field(gt=0)] | None = None
    delta_allow: Annotated[Angle, Field(gt=0, lt=1.5707963267948966)] | None = None

    @model_validator(mode="after")
    def _one_speed(self) -> OperationSection:
        if self.speed is not None and self.productivity is not None:
            raise PydanticCustomError("speed", "give 'speed' or 'productivity', not both")
        return self

    @property
    def omega(self) -> float:
        """Rotor speed [rad/s] (0 if neither speed nor productivity is given)."""
        if self.speed is not None:
            return self.speed
        if self.productivity is not None:
            return 2 * 3.141592653589793 * self.productivity / self.positions
        return 0.0


class LoadSection(FileModel):
    """``[load]``: load diagram of one slide (``angles`` [rad] and ``forces`` [N], periodic
    linear interpolation; or a constant ``force`` on the forward stroke), the guide friction
    angle ``rho_guide`` [rad] and, optionally, the slide's ``guide_length`` and the rod joint's
    ``overhang`` [m] (two-point guide, see :func:`linkwork.models.swashplate.drive_forces`)."""

    angles: list[Angle] | None = None
    forces: list[Force] | None = None
    force: Force | None = None
    rho_guide: Annotated[Angle, Field(ge=0, lt=1.5707963267948966)] = 0.0
    guide_length: Annotated[Length, Field(gt=0)] | None = None
    overhang: Annotated[Length, Field(ge=0)] = 0.0

    @model_validator(mode="after")
    def _diagram(self) -> LoadSection:
        table = self.angles is not None or self.forces is not None
        if table and self.force is not None:
            raise PydanticCustomError("load", "give 'angles' + 'forces' or 'force', not both")
        if table:
            if self.angles is None or self.forces is None:
                raise PydanticCustomError("load", "'angles' and 'forces' go together")
            if len(self.angles) != len(self.forces) or len(self.angles) < 2:
                raise PydanticCustomError("load", "'angles' and 'forces' need the same length "
                                          "(>= 2)")
        elif self.force is None:
            raise PydanticCustomError("load", "needs 'angles' + 'forces' or 'force'")
        if self.overhang and self.guide_length is None:
            raise PydanticCustomError("load", "'overhang' needs 'guide_length'")
        return self


class OutputSection(FileModel):
    """``[output]``: ``samples`` per revolution of the cycle files and plots (8 ... 100000)."""

    samples: Annotated[int, Field(ge=8, le=100_000)] = 361


_FREE = {"1": ("r", "alpha", "a", "b"), "2": ("r", "b"), "3": ("r", "a", "b"),
         "4a": ("alpha",), "4b": ("r", "alpha", "b")}
_REQUIRED = {"1": ("r", "alpha"), "2": ("r",), "3": ("r",), "4a": ("alpha",),
             "4b": ("r", "alpha", "b")}


class SwashplateFile(FileModel):
    """A swash-plate drive of the paper's table (scheme 1, 2, 3, 4a, 4b)."""

    type: Literal["swashplate"]
    name: str = "swash-plate drive"
    scheme: Literal["1", "2", "3", "4a", "4b"] = "1"
    geometry: GeometrySection
    operation: OperationSection = OperationSection()
    load: LoadSection | None = None
    output: OutputSection = OutputSection()

    @model_validator(mode="after")
    def _scheme(self) -> SwashplateFile:
        g = self.geometry
        for key in ("r", "alpha", "a", "b"):
            if getattr(g, key) is not None and key not in _FREE[self.scheme]:
                fixed = sw.SCHEMES[self.scheme]
                raise PydanticCustomError(
                    "scheme", "geometry.{key}: scheme {s} fixes it ({rule})",
                    {"key": key, "s": self.scheme,
                     "rule": fixed.rule or ", ".join(f"{k} = {v:.6g}"
                                                     for k, v in fixed.fixed.items())})
        for key in _REQUIRED[self.scheme]:
            if getattr(g, key) is None:
                raise PydanticCustomError("scheme", "geometry.{key}: missing, scheme {s} "
                                          "needs it", {"key": key, "s": self.scheme})
        try:
            d = self.design()
        except ParameterError as exc:
            msg = f"geometry.{exc}"
            if exc.parameter == "alpha" and g.alpha is not None and abs(g.alpha) > math.pi:
                msg += ' (a plain number is in radians: write e.g. "15 deg")'
            raise PydanticCustomError("scheme", "{msg}", {"msg": msg}) from None
        # the rod must reach at every angle, the loaded drive must not jam: say so here, where
        # the message names the file (not halfway through the analysis)
        try:
            c = sw.characteristics(*d.params)
        except LinkworkError as exc:
            raise PydanticCustomError("reach", "geometry: {msg}", {"msg": str(exc)}) from None
        try:
            self.drive_forces(c)
        except LinkworkError as exc:
            raise PydanticCustomError("jam", "load: {msg}", {"msg": str(exc)}) from None
        return self

    def drive_forces(self, c: sw.Characteristics | None = None) -> sw.DriveForces | None:
        """Kinetostatics under the ``[load]`` section (``None`` without one); ``c`` the
        drive's characteristics (a constant ``force`` acts on the forward stroke)."""
        ld = self.load
        if ld is None:
            return None
        d = self.design()
        load: Any
        if ld.angles is not None:
            load = (np.array(ld.angles), np.array(ld.forces))
        else:
            c = sw.characteristics(*d.params) if c is None else c
            start, span, F = float(c.phi_min), float(c.phi_f), float(ld.force or 0.0)

            def load(phi: np.ndarray) -> np.ndarray:
                return np.where(np.mod(phi - start, 2 * math.pi) < span, F, 0.0)

        return sw.drive_forces(d, load, u=self.operation.positions, rho_guide=ld.rho_guide,
                               guide_length=ld.guide_length, overhang=ld.overhang,
                               n=self.output.samples)

    def design(self) -> sw.Design:
        """The drive as a :class:`~linkwork.models.swashplate.Design` (scheme constructor)."""
        g = self.geometry
        a = g.a or 0.0
        b = g.b or 0.0
        if self.scheme == "1":
            return sw.scheme_1(g.R, g.r or 0.0, g.l, g.alpha or 0.0, a, b)
        if self.scheme == "2":
            return sw.scheme_2(g.R, g.r or 0.0, g.l, b)
        if self.scheme == "3":
            return sw.scheme_3(g.R, g.r or 0.0, g.l, a, b)
        if self.scheme == "4a":
            return sw.scheme_4a(g.R, g.l, g.alpha or 0.0)
        return sw.scheme_4b(g.R, g.r or 0.0, g.l, g.alpha or 0.0, b)
