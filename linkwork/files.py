"""Mechanism and study files (TOML), validated with pydantic, with units.

A file is a TOML document whose top-level ``type`` key says what it describes
(``"sine_press"``, ``"planar"``, ``"swashplate"``, ...). Each type has a pydantic schema
registered with :func:`register_schema`; :func:`load` reads the file, picks the schema and
returns the validated model. Quantities may carry units (``"100 mm"``, ``"60 deg"``,
``"120 rpm"``); the field types :data:`Length`, :data:`Angle`, ... convert them to SI on load.
Every problem raises :class:`~linkwork.errors.FileFormatError` naming the file, the key and the
problem.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, TypeVar

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict

from linkwork.errors import FileFormatError, LinkworkError, ParameterError
from linkwork.units import to_si

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
    "load",
    "read_toml",
    "register_schema",
    "schemas",
]


def _quantity(kind: str) -> Callable[[Any], float]:
    def convert(value: Any) -> float:
        try:
            si = to_si(value, kind)
        except ParameterError as exc:
            raise ValueError(exc.limit) from None
        if not math.isfinite(si):  # "1e400 rpm", nan: never let them reach the models
            raise ValueError("must be a finite number")
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

    model_config = ConfigDict(extra="forbid", frozen=True)


M = TypeVar("M", bound=type[BaseModel])
_SCHEMAS: dict[str, type[BaseModel]] = {}


def register_schema(type_name: str) -> Callable[[M], M]:
    """Class decorator: register a pydantic schema for files with ``type = type_name``."""

    def deco(cls: M) -> M:
        _SCHEMAS[type_name] = cls
        return cls

    return deco


def schemas() -> dict[str, type[BaseModel]]:
    """The registered file types (importing the modules that define them first)."""
    _import_schema_modules()
    return dict(_SCHEMAS)


def _import_schema_modules() -> None:
    import importlib

    for mod in SCHEMA_MODULES:
        importlib.import_module(mod)


#: Modules that define and register file schemas.
SCHEMA_MODULES: tuple[str, ...] = ("linkwork.sine_press_file", "linkwork.planar.file",
                                   "linkwork.swashplate_file")


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; missing, unreadable or invalid files raise FileFormatError."""
    p = Path(path)
    if not p.exists():
        raise FileFormatError(str(p), None, "file not found")
    if p.is_dir():
        raise FileFormatError(str(p), None, "is a directory, not a file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise FileFormatError(str(p), None, f"cannot be read ({exc})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(str(p), None, f"invalid TOML: {exc}") from None


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


def load(path: str | Path) -> Any:
    """Read and validate a linkwork file; dispatch on its top-level ``type`` key."""
    data = read_toml(path)
    known = schemas()
    kind = data.get("type")
    if kind is None:
        raise FileFormatError(str(path), "type", f"missing required key; one of {sorted(known)}")
    if kind not in known:
        raise FileFormatError(str(path), "type", f"unknown type {kind!r}; one of {sorted(known)}")
    return validate(path, data, known[kind])
