"""TOML files with units, validated with pydantic: the machinery every file class shares.

:func:`read_toml` reads a file; :class:`FileModel` is the base of every file class (unknown keys
are errors, models are immutable) and :meth:`FileModel.from_data` validates a document read from
a file. Quantities may carry units (``"100 mm"``, ``"60 deg"``, ``"120 rpm"``); the field types
:data:`Length`, :data:`Angle`, ... convert them to SI on load. Every problem raises
:class:`~linkwork.errors.FileFormatError` naming the file, the key and the problem. The file
classes themselves and the registry of file types are in :mod:`linkwork.io`.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, Self

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict

from linkwork.errors import FileFormatError, LinkworkError, ParameterError
from linkwork.units import KINDS, to_si

__all__ = [
    "Acceleration",
    "Angle",
    "AngularAcceleration",
    "AngularVelocity",
    "Dimensionless",
    "FileModel",
    "Force",
    "Frequency",
    "Inertia",
    "Length",
    "Mass",
    "Stiffness",
    "Time",
    "Torque",
    "Velocity",
    "read_toml",
    "validate",
]


#: The sanity layer of files: the largest magnitude of each kind of quantity that a machine
#: mechanism can have, in SI, far beyond any real one (a 10 km link, a 10^6 rad/s crank, a 10^12
#: N force). A value beyond it is a wrong number or unit; refused here, it cannot turn into
#: overflowing products (omega^2 r m) and NaN tables further on. Angles have their own limits
#: where they are read (the float spacing of large angles), dimensionless values none.
MAGNITUDE_LIMITS: dict[str, float] = {
    "length": 1e4, "angular_velocity": 1e6, "angular_acceleration": 1e9, "velocity": 1e4,
    "acceleration": 1e8, "mass": 1e9, "inertia": 1e12, "force": 1e12, "torque": 1e12,
    "time": 1e9, "frequency": 1e6, "stiffness": 1e15, "rotational_stiffness": 1e15,
}


def _quantity(kind: str) -> Callable[[Any], float]:
    limit = MAGNITUDE_LIMITS.get(kind, math.inf)

    def convert(value: Any) -> float:
        try:
            si = to_si(value, kind)
        except ParameterError as exc:
            raise ValueError(exc.limit) from None
        if not math.isfinite(si):  # "1e400 rpm", nan: never let them reach the models
            raise ValueError("must be a finite number")
        if abs(si) > limit:
            raise ValueError(f"must lie within +-{limit:g} {KINDS[kind]}, far beyond any machine "
                             "mechanism (check the number and its unit)")
        return si

    return convert


def _key(loc: tuple[Any, ...]) -> str | None:
    """The dotted key of a pydantic error location, without the tags pydantic inserts for the
    members of a union or a validator (``str``, ``list[...]``, ``function-before[...]``)."""
    parts = [str(x) for x in loc
             if isinstance(x, int) or not (x in _TYPE_TAGS or "[" in str(x))]
    return ".".join(parts) or None


_TYPE_TAGS = frozenset({"str", "int", "float", "bool", "list", "dict", "tuple", "none",
                        "is-instance", "literal", "tagged-union"})


Length = Annotated[float, BeforeValidator(_quantity("length"))]
Angle = Annotated[float, BeforeValidator(_quantity("angle"))]
AngularVelocity = Annotated[float, BeforeValidator(_quantity("angular_velocity"))]
AngularAcceleration = Annotated[float, BeforeValidator(_quantity("angular_acceleration"))]
Velocity = Annotated[float, BeforeValidator(_quantity("velocity"))]
Acceleration = Annotated[float, BeforeValidator(_quantity("acceleration"))]
Mass = Annotated[float, BeforeValidator(_quantity("mass"))]
Inertia = Annotated[float, BeforeValidator(_quantity("inertia"))]
Force = Annotated[float, BeforeValidator(_quantity("force"))]
Torque = Annotated[float, BeforeValidator(_quantity("torque"))]
Time = Annotated[float, BeforeValidator(_quantity("time"))]
Stiffness = Annotated[float, BeforeValidator(_quantity("stiffness"))]
Dimensionless = Annotated[float, BeforeValidator(_quantity("dimensionless"))]
Frequency = Annotated[float, BeforeValidator(_quantity("frequency"))]


class FileModel(BaseModel):
    """Base of every file schema: unknown keys are errors, models are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)

    @classmethod
    def from_data(cls, path: str | Path, data: dict[str, Any]) -> Self:
        """Validate ``data`` read from the file ``path``; errors name the file and the key."""
        doc: Self = validate(path, data, cls)
        return doc


MAX_FILE_BYTES = 16 * 2**20
"""Largest input file read [bytes]: a mechanism with its tables is a few kB; anything larger is
not an input file (``/dev/zero`` is refused after reading this much, not read for ever)."""


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; missing, unreadable, oversized or invalid files raise FileFormatError.

    Pipes work (``linkwork analyze <(generate)``); at most :data:`MAX_FILE_BYTES` are read, and
    a document nested deeper than the parser can follow is refused, not a RecursionError.
    """
    p = Path(path)
    if not p.exists():
        raise FileFormatError(str(p), None, "file not found")
    if p.is_dir():
        raise FileFormatError(str(p), None, "is a directory, not a file")
    try:
        with p.open("rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise FileFormatError(str(p), None, f"is larger than {MAX_FILE_BYTES // 2**20} MiB, "
                                  "the limit of an input file")
        text = raw.decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise FileFormatError(str(p), None, f"cannot be read ({exc})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(str(p), None, f"invalid TOML: {exc}") from None
    except RecursionError:
        raise FileFormatError(str(p), None, "invalid TOML: arrays or tables nested too deeply "
                              "for the parser (a mechanism needs at most a few levels)") from None


def _validation_error(path: str, exc: pydantic.ValidationError) -> FileFormatError:
    errs = exc.errors()
    err = errs[0]
    if err["type"].endswith("_type"):  # the wrong type for one member of a union (a point
        # name or [x, y]): a member that accepted the type says what is wrong with the value
        k0 = _key(err["loc"])
        err = next((e for e in errs[1:] if k0 and not e["type"].endswith("_type")
                    and f"{_key(e['loc'])}.".startswith(f"{k0}.")), err)
    key = _key(err["loc"])
    msg = err["msg"].removeprefix("Value error, ")
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, ParameterError):
        # raised by a validator that builds the mechanism: its parameter is the key, its
        # message already names the value and the limit (never append the whole document)
        key = ".".join(x for x in (key, cause.parameter) if x)
        msg = str(cause).removeprefix(f"{cause.parameter} = ")
    elif isinstance(cause, LinkworkError):
        msg = str(cause)
    elif err["type"] == "extra_forbidden":
        msg = "unknown key"
    elif err["type"] == "missing":
        msg = "missing required key"
    elif "input" in err and len(repr(err["input"])) <= 80 and "(got " not in msg:  # short only
        msg = f"{msg} (got {err['input']!r})"
    extra = f" (+{len(errs) - 1} more problems)" if len(errs) > 1 else ""
    return FileFormatError(path, key, msg + extra)


def validate(path: str | Path, data: dict[str, Any], schema: type[BaseModel]) -> Any:
    """Validate ``data`` (read from ``path``) against ``schema``; errors name file and key."""
    try:
        return schema.model_validate(data)
    except pydantic.ValidationError as exc:
        raise _validation_error(str(path), exc) from None
    except ParameterError as exc:  # raised by model validators that build mechanisms
        raise FileFormatError(str(path), exc.parameter,
                              str(exc).removeprefix(f"{exc.parameter} = ")) from None


