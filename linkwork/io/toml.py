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
import re
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, Self

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict

from linkwork.errors import FileFormatError, LinkworkError, ParameterError
from linkwork.units import KINDS, expressed_like, to_si

__all__ = [
    "Acceleration",
    "Angle",
    "AngularAcceleration",
    "AngularVelocity",
    "Damping",
    "Dimensionless",
    "FileModel",
    "Force",
    "Frequency",
    "Inertia",
    "Length",
    "Mass",
    "Power",
    "Stiffness",
    "Time",
    "Torque",
    "Velocity",
    "message",
    "quantity",
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
    "acceleration": 1e8, "mass": 1e9, "inertia": 1e12, "force": 1e12, "torque": 1e12, "power": 1e12,
    "time": 1e9, "frequency": 1e6, "stiffness": 1e15, "rotational_stiffness": 1e15,
    "damping": 1e12,
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
        if abs(si) > limit:  # the limit also in the unit the value is written in
            shown = expressed_like(limit, value)
            within = (f"+-{limit:g} {KINDS[kind]}" if shown is None
                      or float(shown.split()[0]) == float(f"{limit:.6g}") else
                      f"+-{shown} ({limit:g} {KINDS[kind]})")
            raise ValueError(f"{_written(value) or repr(value)} is invalid: must lie within "
                             f"{within}, far beyond any machine mechanism (check the number "
                             "and its unit)")
        return si

    return convert


def quantity(value: Any, kind: str, key: str) -> float:
    """``value`` (a number, SI, or a string with a unit) in the SI unit of ``kind``, checked as
    the file's quantity types check it (finite, within :data:`MAGNITUDE_LIMITS`), for values
    whose kind a file knows only from other keys (a load diagram's table); a
    :class:`~linkwork.errors.ParameterError` naming ``key`` otherwise."""
    try:
        return _quantity(kind)(value)
    except ValueError as exc:  # the ParameterError says "<value> is invalid: " itself
        limit = str(exc).removeprefix(f"{_written(value) or repr(value)} is invalid: ")
        raise ParameterError(key, value, limit) from None


def _key(loc: tuple[Any, ...]) -> str | None:
    """The dotted key of a pydantic error location, without the tags pydantic inserts for the
    members of a union or a validator (``str``, ``list[...]``, ``function-before[...]``)."""
    parts = [str(x) for x in loc
             if isinstance(x, int) or not (x in _TYPE_TAGS or "[" in str(x))]
    return ".".join(parts) or None


#: pydantic's bound constraints (``Field(gt=0)``): the bound's key in the error's context and
#: how a message writes it.
_BOUNDS = {"gt": ">", "ge": ">=", "lt": "<", "le": "<="}
_BOUNDS.update({"greater_than": ">", "greater_than_equal": ">=", "less_than": "<",
                "less_than_equal": "<="})

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
Power = Annotated[float, BeforeValidator(_quantity("power"))]
Time = Annotated[float, BeforeValidator(_quantity("time"))]
Stiffness = Annotated[float, BeforeValidator(_quantity("stiffness"))]
Damping = Annotated[float, BeforeValidator(_quantity("damping"))]
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


def _validation_error(path: str, exc: pydantic.ValidationError,
                      data: dict[str, Any] | None = None) -> FileFormatError:
    errs = exc.errors()
    err = errs[0]
    if err["type"].endswith("_type"):  # the wrong type for one member of a union (a point
        # name or [x, y]): a member that accepted the type says what is wrong with the value
        k0 = _key(err["loc"])
        err = next((e for e in errs[1:] if k0 and not e["type"].endswith("_type")
                    and f"{_key(e['loc'])}.".startswith(f"{k0}.")), err)
    key = _key(err["loc"])
    msg = message(err)
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, ParameterError):
        # raised by a validator that builds the mechanism: its parameter is the key, its
        # message already names the value and the limit (never append the whole document)
        key = ".".join(x for x in (key, cause.parameter) if x)
        msg = str(cause).removeprefix(f"{cause.parameter} = ")
    elif isinstance(cause, LinkworkError):
        msg = str(cause)
    elif err["type"] in _BOUNDS and key is not None:  # Field(gt=0, ...): the entry's name
        cause = ParameterError(key, err.get("input"), _bound(err))
    extra = f" (+{len(errs) - 1} more problems)" if len(errs) > 1 else ""
    out = FileFormatError(path, key, msg)
    if isinstance(cause, ParameterError) and data is not None:
        out = _as_written(out, data, cause)
    return FileFormatError(out.file, out.key, out.problem + extra)


def _bound(err: Any) -> str:
    """The limit of a pydantic bound error (``Field(gt=0)``): ``must be > 0``, a bound that is
    not zero also in the unit the value is written in."""
    op, bound = next((_BOUNDS[k], v) for k, v in (err.get("ctx") or {}).items()
                     if k in _BOUNDS)
    shown = "0" if bound == 0 else (expressed_like(bound, err.get("input")) or f"{bound:g}")
    return f"must be {op} {shown}"


def message(err: Any) -> str:
    """What a pydantic error says of its value, as the file writes it: ``unknown key``,
    ``missing required key``, ``-100 mm is invalid: must be > 0``, or pydantic's message with
    the value given (``(got '90 mm')``, short values only)."""
    msg = str(err["msg"]).removeprefix("Value error, ")
    written = _written(err.get("input"))
    if err["type"] == "extra_forbidden":
        return "unknown key"
    if err["type"] == "missing":
        return "missing required key"
    if err["type"] in _BOUNDS:
        return f"{written or repr(err.get('input'))} is invalid: {_bound(err)}"
    if ("input" in err and len(repr(err["input"])) <= 80 and "(got " not in msg
            and not msg.startswith(f"{written} is invalid")):  # not said already
        return f"{msg} (got {err['input']!r})"
    return msg


def validate(path: str | Path, data: dict[str, Any], schema: type[BaseModel]) -> Any:
    """Validate ``data`` (read from ``path``) against ``schema``; errors name file and key."""
    try:
        return schema.model_validate(data)
    except pydantic.ValidationError as exc:
        raise _validation_error(str(path), exc, data) from None
    except ParameterError as exc:  # raised by model validators that build mechanisms
        raise parameter_error(path, exc, data) from None


def parameter_error(path: str | Path, exc: ParameterError,
                    data: dict[str, Any]) -> FileFormatError:
    """The FileFormatError of a ParameterError raised while a validated file builds its model
    (a mechanism): the key and the value as they are written in the file where they can be
    found there."""
    err = FileFormatError(str(path), exc.parameter, str(exc).removeprefix(f"{exc.parameter} = "))
    return _as_written(err, data, exc)


def _lookup(data: Any, parts: list[str]) -> Any:
    """The value at the dotted path ``parts`` of ``data`` (list indices as digits), or KeyError."""
    for part in parts:
        if isinstance(data, list) and part.isdigit() and int(part) < len(data):
            data = data[int(part)]
        elif isinstance(data, dict) and part in data:
            data = data[part]
        else:
            raise KeyError(part)
    return data


def _file_key(data: dict[str, Any], key: str) -> tuple[str, Any] | None:
    """The key as it is in the file and the value written there, for a key that is either a
    dotted path of the file (``analysis.stop``, ``body.0.length``) or starts with the name of an
    entry of an array of tables (``crank.length``: the ``[[body]]`` named crank)."""
    parts = key.split(".")
    try:
        return key, _lookup(data, parts)
    except KeyError:
        pass
    tables: list[str] = list(data)
    if " " in parts[0]:  # "joint Q.point_a": the [[joint]] named Q
        table, parts[0] = parts[0].split(" ", 1)
        tables = [table]
    for table in tables:
        entries = data.get(table)
        if not isinstance(entries, list):
            continue
        for i, entry in enumerate(entries):
            if isinstance(entry, dict) and entry.get("name") == parts[0] and len(parts) > 1:
                try:
                    return f"{table}.{i}.{'.'.join(parts[1:])}", _lookup(entry, parts[1:])
                except KeyError:  # a key the entry leaves out (a default that is wrong here)
                    return (f"{table}.{i}.{'.'.join(parts[1:])}", _ABSENT) if len(parts) == 2 \
                        else None
    return None


#: The value of a key an entry of the file does not give (:func:`_file_key`).
_ABSENT = object()


def _written(raw: Any) -> str | None:
    """A value as the file writes it (``-100 mm``, ``["250 mm", 0]``), for numbers, strings
    and short lists of them; None for anything else."""
    if isinstance(raw, bool):
        return None
    if isinstance(raw, str | int | float):
        return str(raw)
    if isinstance(raw, list) and len(raw) <= 6:
        items = [_written(x) for x in raw]
        if all(x is not None for x in items):
            return "[" + ", ".join(f'"{x}"' if isinstance(r, str) else str(x)
                                   for x, r in zip(items, raw, strict=True)) + "]"
    return None


def _as_written(err: FileFormatError, data: dict[str, Any],
                cause: ParameterError) -> FileFormatError:
    """``err`` with the value as the user wrote it (``-100 mm``, not the SI ``-0.1``) and the
    key as it is in the file (``body.0.length (crank)``), where the key can be found there."""
    if err.key is None:
        return err
    found = _file_key(data, err.key)
    if found is None:
        return err
    file_key, raw = found
    if file_key != err.key:  # the entry's name: body.0.length (crank)
        file_key = f"{file_key} ({err.key.split('.')[0].split(' ')[-1]})"
    msg = err.problem
    if raw is _ABSENT:  # its default does not do here: "required", not "0 is invalid"
        return FileFormatError(err.file, file_key, f"is required here: {cause.limit}")
    written = _written(raw)
    if isinstance(raw, list) and not isinstance(cause.value, list | tuple):
        written = None  # the key names a list and the message one of its items: keep it
    if written is not None:
        msg = f"{written} is invalid: {_siblings_as_written(cause.limit, data, file_key)}"
    return FileFormatError(err.file, file_key, msg)


_SIBLING = re.compile(r"\b(?P<key>[A-Za-z_]\w*) = (?P<value>[-+]?[0-9.]+(?:e[-+]?\d+)?)"
                      r"(?: (?P<unit>[A-Za-z*/^0-9]+))?")


def _siblings_as_written(limit: str, data: dict[str, Any], file_key: str) -> str:
    """``limit`` with the values of other keys of the same entry it quotes in SI
    (``must be < synchronous_speed = 157.08 rad/s``) as the file writes them
    (``synchronous_speed = 1500 rpm``)."""
    parent = file_key.split(" ")[0].split(".")[:-1]
    try:
        entry = _lookup(data, parent)
    except KeyError:
        return limit
    if not isinstance(entry, dict):
        return limit

    def sub(m: re.Match[str]) -> str:
        raw = entry.get(m["key"])
        if not isinstance(raw, str | int | float) or isinstance(raw, bool):
            return m[0]
        return f"{m['key']} = {raw}"

    return _SIBLING.sub(sub, limit)
