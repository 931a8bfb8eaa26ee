"""Deprecated location: import from linkwork.io (the registry of file types and :func:`load`)
and linkwork.io.toml (reading, validation, unit-aware field types, FileModel)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from pydantic import BaseModel

from linkwork.io import FILE_TYPES, load
from linkwork.io.toml import (
    Acceleration,
    Angle,
    AngularAcceleration,
    AngularVelocity,
    Dimensionless,
    FileModel,
    Force,
    Frequency,
    Inertia,
    Length,
    Mass,
    Stiffness,
    Time,
    Torque,
    Velocity,
    _key,
    _validation_error,
    read_toml,
    validate,
)

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
    "_key",
    "_validation_error",
    "load",
    "read_toml",
    "register_schema",
    "schemas",
    "validate",
]

M = TypeVar("M", bound=type[BaseModel])

#: Deprecated: the modules that defined the file classes (the classes are found through
#: :data:`linkwork.io.FILE_TYPES` now, not through these names).
SCHEMA_MODULES: tuple[str, ...] = ("linkwork.sine_press_file", "linkwork.planar.file",
                                   "linkwork.swashplate_file")


def register_schema(type_name: str) -> Callable[[M], M]:
    """Class decorator: add a file class for ``type = type_name`` to
    :data:`linkwork.io.FILE_TYPES` (deprecated: add the class there)."""

    def deco(cls: M) -> M:
        FILE_TYPES[type_name] = cls  # type: ignore[assignment]
        return cls

    return deco


def schemas() -> dict[str, type[BaseModel]]:
    """The registered file types (a copy of :data:`linkwork.io.FILE_TYPES`)."""
    return dict(FILE_TYPES)
