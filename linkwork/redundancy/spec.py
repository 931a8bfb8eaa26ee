"""The optional ``[spatial]`` table of a ``planar`` mechanism file (read by ``linkwork
reactions``).

The mechanism itself is described by the engine's ``planar`` file format; the spatial data live
in an extra table that this module validates (the engine's schema never sees it). Example::

    [spatial]
    k_bearing = "100 N/um"        # default radial bearing stiffness k_b
    axial_ratio = 1.0             # default axial/radial stiffness ratio
    positions = 360               # optional: resample the file's [analysis] range
    default = { e = "30 mm", z = "0 mm" }   # for joints not listed in [spatial.joints]
    heights = { coupler = "30 mm" }          # heights of the centres of mass [m]

    [spatial.joints.A]
    kind = "revolute"             # cylindrical, spherical, sphere_cylinder, prismatic, ...
    e = "30 mm"                   # axis (bearing) length
    z = "30 mm"                   # height of the joint centre
    # stiffness = ["1e8 N/m", "1e8 N/m", "1e8 N/m", "7.5 kN*m/rad", "7.5 kN*m/rad", 0]

    [[spatial.deviation]]         # manufacturing deviations, in the body's own frame
    joint = "O4"
    body = "frame"
    tx = "0.2 mrad"               # dx, dy, dz [length], tx, ty, tz [angle]

    [[spatial.out_of_plane]]      # out-of-plane loads at the centre of mass
    body = "coupler"
    fz = "5 N"                    # mx, my [torque]

    [[spatial.tolerance]]         # for --tolerance-study
    joint = "O4"
    body = "frame"
    component = "tx"
    limit = "0.3 mrad"            # normal: limit = 3 sigma; uniform: +-limit
    distribution = "normal"
    mean = 0.0

Plain numbers are SI; strings carry units. Unknown keys are errors.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import pydantic
from pydantic import Field, field_validator

from linkwork.errors import FileFormatError, ParameterError
from linkwork.files import Angle, FileModel, Force, Length, Stiffness, Torque
from linkwork.redundancy.core import DEFAULT_BEARING_STIFFNESS, check_tilt
from linkwork.units import to_si

__all__ = ["DeviationSpec", "JointSpec", "OutOfPlaneSpec", "SpatialSpec", "ToleranceSpec",
           "read_spatial"]

PositiveLength = Annotated[Length, Field(gt=0)]
_KIND = Literal["revolute", "cylindrical", "spherical", "sphere_cylinder", "prismatic",
                "prismatic_round"]
_COMPONENT = Literal["dx", "dy", "dz", "tx", "ty", "tz"]


def _quantity(value: Any, kind: str) -> float:
    try:
        return to_si(value, kind)
    except ParameterError as exc:
        raise ValueError(exc.limit) from None


class JointSpec(FileModel):
    """``[spatial.joints.<name>]`` (and ``[spatial] default``)."""

    kind: _KIND | None = None
    e: PositiveLength | None = None
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
        out = [_quantity(x, "stiffness") for x in v[:3]]
        out += [_quantity(x, "rotational_stiffness") for x in v[3:]]
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
        value = _quantity(v, "length" if str(comp).startswith("d") else "angle")
        if info.field_name == "limit" and value < 0:
            raise ValueError("must be >= 0")
        if str(comp).startswith("t"):
            try:
                check_tilt(str(info.field_name), value)
            except ParameterError as exc:
                raise ValueError(f"{exc.limit}") from None
        return value


class SpatialSpec(FileModel):
    """The ``[spatial]`` table."""

    k_bearing: Annotated[Stiffness, Field(gt=0)] = DEFAULT_BEARING_STIFFNESS
    axial_ratio: Annotated[float, Field(gt=0)] = 1.0
    positions: Annotated[int, Field(ge=8, le=100_000)] | None = None
    default: JointSpec = JointSpec()
    joints: dict[str, JointSpec] = Field(default_factory=dict)
    heights: dict[str, Length] = Field(default_factory=dict)
    deviation: list[DeviationSpec] = Field(default_factory=list)
    out_of_plane: list[OutOfPlaneSpec] = Field(default_factory=list)
    tolerance: list[ToleranceSpec] = Field(default_factory=list)

    def default_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for joints not listed (bearing defaults included)."""
        return {"k_bearing": self.k_bearing, "axial_ratio": self.axial_ratio,
                **self.default.kwargs()}

    def joint_kwargs(self) -> dict[str, dict[str, Any]]:
        """Per-joint keyword arguments (over the defaults)."""
        return {name: {**self.default_kwargs(), **spec.kwargs()}
                for name, spec in self.joints.items()}


def read_spatial(path: str | Path, raw: dict[str, Any]) -> SpatialSpec:
    """Validate the ``spatial`` table of a file already read with ``files.read_toml``.

    A missing table gives the defaults. Problems raise FileFormatError naming the file and the
    dotted key (``spatial.joints.A.e``).
    """
    data = raw.get("spatial", {})
    if not isinstance(data, dict):
        raise FileFormatError(str(path), "spatial", "must be a table")
    try:
        return SpatialSpec.model_validate(data)
    except pydantic.ValidationError as exc:
        err = exc.errors()[0]
        key = ".".join(["spatial", *(str(x) for x in err["loc"])])
        msg = err["msg"]
        if err["type"] == "extra_forbidden":
            msg = "unknown key"
        elif err["type"] == "missing":
            msg = "missing required key"
        elif "input" in err:
            msg = f"{msg} (got {err['input']!r})"
        raise FileFormatError(str(path), key, msg) from None
