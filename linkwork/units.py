"""SI units inside, other units only at the edges.

Inside linkwork every length is metres, every angle radians, every angular speed rad/s, every
mass kg, force N, torque N·m. Files and the command line accept quantities with units
("100 mm", "30 deg", "120 rpm"); :func:`to_si` converts them. A plain number in a file is taken
as already being in the SI unit of its kind (radians for angles) -- see ``docs/conventions.md``.

pint is imported lazily, on the first conversion of a string, so importing linkwork stays fast.
"""

from __future__ import annotations

import math
import re
from functools import lru_cache
from typing import Any

from linkwork.errors import ParameterError

__all__ = ["KINDS", "deg", "expressed_like", "rpm", "to_deg", "to_si"]

#: SI unit of each kind of quantity that files and the CLI accept.
KINDS: dict[str, str] = {
    "length": "m",
    "angle": "rad",
    "angular_velocity": "rad/s",
    "angular_acceleration": "rad/s**2",
    "velocity": "m/s",
    "acceleration": "m/s**2",
    "mass": "kg",
    "inertia": "kg*m**2",
    "force": "N",
    "torque": "N*m",
    "power": "W",
    "time": "s",
    "frequency": "1/s",
    "stiffness": "N/m",
    "rotational_stiffness": "N*m/rad",
    "damping": "N*s/m",
    "dimensionless": "",
}


#: Kinds whose SI unit carries an angle. pint treats the radian as dimensionless, so without a
#: check "2 Hz" would pass as 2 rad/s and "600 rpm" as a frequency of 62.8 /s (a silent 2 pi).
_ANGULAR = ("angle", "angular_velocity", "angular_acceleration", "rotational_stiffness")


def _angle_mismatch(q: Any, kind: str) -> str:
    """Why ``q`` is ambiguous or wrong for ``kind`` because of the angle ('' if it is not)."""
    units = dict(q.unit_items())
    if kind in _ANGULAR:
        if any("hertz" in u for u in units):
            return ("Hz is ambiguous for an angular quantity (cycles or radians per second): "
                    "write e.g. '120 rpm', '2 rps' or '12.57 rad/s'")
        return ""
    if dict(q.to_root_units().unit_items()).get("radian", 0):
        if kind == "dimensionless":  # pint takes "60 deg" for the number 1.047
            return "it carries an angle unit (deg, rad, turn)"
        return "it carries an angle unit (rpm, deg, rad, turn); write e.g. '600 1/min'"
    return ""



@lru_cache(maxsize=1)
def _registry() -> Any:
    import pint

    ureg: Any = pint.UnitRegistry()
    ureg.define("rpm = revolution / minute")  # pint knows rpm; this keeps the meaning explicit
    return ureg


def to_si(value: Any, kind: str, name: str = "value") -> float:
    """Convert ``value`` to the SI unit of ``kind`` and return a float.

    Parameters
    ----------
    value : float or str
        A number (taken as SI) or a string with a unit, e.g. ``"100 mm"``, ``"30 deg"``,
        ``"120 rpm"``.
    kind : str
        One of :data:`KINDS`.
    name : str
        Parameter name used in error messages.

    Raises
    ------
    ParameterError
        The string cannot be parsed or has the wrong dimension.
    """
    if kind not in KINDS:
        raise ParameterError("kind", kind, f"must be one of {sorted(KINDS)}")
    if isinstance(value, bool):
        raise ParameterError(name, value, f"must be a number or a quantity in {KINDS[kind] or '1'}")
    if isinstance(value, int | float):
        return float(value)
    if not isinstance(value, str):
        raise ParameterError(name, value, "must be a number or a string such as '100 mm'")
    ureg = _registry()
    try:
        q = ureg.Quantity(value.strip())
    except Exception as exc:  # pint raises several unrelated types
        raise ParameterError(name, value, f"cannot be read as a quantity ({exc})") from None
    unit = KINDS[kind]
    try:
        if not hasattr(q, "to"):
            return float(q)
        si = float(q.to(unit).magnitude) if unit else float(q.to("").magnitude)
    except Exception:
        limit = f"must have the dimension of {kind} ({unit or '1'})"
        raise ParameterError(name, value, limit) from None
    why = _angle_mismatch(q, kind)
    if why and kind == "dimensionless":
        raise ParameterError(name, value, f"must be a plain number (a ratio): {why}")
    if why:
        article = "an" if kind[0] in "aeiou" else "a"
        raise ParameterError(name, value, f"must be {article} {kind.replace('_', ' ')} in "
                             f"{unit}: {why}")
    return si


_NUMBER_THEN_UNIT = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\s*(?P<unit>\S.*?)\s*")


def expressed_like(si: float, written: Any) -> str | None:
    """The SI value ``si`` written in the unit of ``written`` (a file's value such as
    ``"1500 rpm"``): ``expressed_like(157.0796, "1500 rpm") == "1500 rpm"``, so that a limit
    reads in the user's unit. None if ``written`` is not a number with a unit, or its unit is
    not of the value's kind (pint's base units of the unit are taken as the SI unit: rad/s for
    rpm, m for mm, kg*m**2 for g*m^2)."""
    if not isinstance(written, str):
        return None
    m = _NUMBER_THEN_UNIT.fullmatch(written)
    if m is None:
        return None
    try:
        ureg = _registry()
        unit = ureg.Unit(m["unit"])
        value = float(ureg.Quantity(float(si), ureg.Quantity(1.0, unit).to_base_units().units)
                      .to(unit).magnitude)
    except Exception:  # pint raises several unrelated types
        return None
    return f"{value:.6g} {m['unit']}"


def deg(x: float) -> float:
    """``x`` degrees, in radians (``deg(90) == pi/2``)."""
    return math.radians(x)


def to_deg(x: float) -> float:
    """Radians to degrees (``to_deg(pi/2) == 90``)."""
    return math.degrees(x)


def rpm(n: float) -> float:
    """``n`` revolutions per minute, in rad/s."""
    return n * 2.0 * math.pi / 60.0
