"""Immutable description of a planar mechanism: frame, bodies, joints, driver.

A body carries its own Cartesian frame; its named points, centre of mass and the joints' points
are given in that frame [m]. The pose of body ``b`` in the fixed frame is ``(x_b, y_b, theta_b)``:
a point ``p`` of the body is at ``r_b + A(theta_b) p`` with ``A`` the counter-clockwise rotation.
The frame (ground) is a body too, always at pose ``(0, 0, 0)``.

Joints (defined with their behaviour in :mod:`linkwork.planar.joints`, re-exported here; each
joins a first body ``a`` and a second body ``b``; reactions are reported as the force exerted
**by a on b**):

* :class:`Revolute` -- point ``point_a`` of ``a`` coincides with point ``point_b`` of ``b``
  (both default to the joint's name). 2 constraints.
* :class:`Prismatic` -- ``a`` carries a guide line through its point ``through`` (default: the
  joint's name) at angle ``angle`` in ``a``'s frame; point ``point`` of ``b`` (default: the
  joint's name) stays on the line, and ``theta_b - theta_a`` stays equal to ``rel_angle``. The
  slide coordinate is ``s = u . (P_b - Q_a)`` with ``u`` the line's direction. 2 constraints.
* :class:`PinInSlot` -- ``a`` carries a straight slot (line through ``through`` at ``angle``),
  point ``point`` of ``b`` (the pin) stays on it; rotation is free. 1 constraint (a higher pair).

Drivers: :class:`Crank` on a revolute joint, ``phi1 = theta_b - theta_a`` (the angle of ``b``'s
x-axis measured counter-clockwise from ``a``'s x-axis); :class:`Linear` on a prismatic joint,
``s1 = u . (P_b - Q_a)``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from linkwork.checks import (
    per_position,
    require_finite,
)
from linkwork.deprecation import renamed_function
from linkwork.errors import ParameterError, StructureError
from linkwork.planar.designs import (
    branch_value,
    count_designs,
    design_point,
    design_value,
    is_batched,
    pick,
    pick_fields,
)
from linkwork.planar.joints import GearPair, Joint, PinInSlot, Point, Prismatic, Revolute
from linkwork.planar.structure import Plan, Structure, analyse, compile_plan

__all__ = [
    "Body",
    "Crank",
    "Drawing",
    "GearPair",
    "Joint",
    "Linear",
    "Mechanism",
    "PinInSlot",
    "Prismatic",
    "Revolute",
    "bar",
    "crank_slider",
    "fourbar",
]


def _rebuild(cls: type, kwargs: dict[str, Any]) -> Any:
    return cls(**kwargs)


class _PicklesByFields:
    """Pickled as its constructor's arguments (read-only mappings as dicts), so that it
    travels to other processes (Dask workers, multiprocessing); what is worked out on demand
    (structure, compiled plan) is worked out again there."""

    def __reduce__(self) -> tuple[Any, ...]:
        kw = {}
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            if f.init:
                v = getattr(self, f.name)
                kw[f.name] = dict(v) if isinstance(v, MappingProxyType) else v
        return (_rebuild, (type(self), kw))


@dataclass(frozen=True)
class Body(_PicklesByFields):
    """A rigid body (link) with its own frame.

    Parameters
    ----------
    name : str
        Unique name (``"crank"``).
    points : mapping str -> (x, y)
        Named points in the body's frame [m] (joint centres, coupler points).
    mass : float
        Mass [kg], >= 0.
    com : (x, y)
        Centre of mass in the body's frame [m].
    inertia : float
        Centroidal moment of inertia about the z axis [kg m^2], >= 0.
    guess : (x, y, theta), optional
        Initial pose [m, m, rad] for Newton iteration of higher-class groups; it also selects
        their assembly branch. Not used by closed-form (dyad) groups.
    """

    name: str
    points: Mapping[str, Point] = field(default_factory=dict)
    mass: float = 0.0
    com: Point = (0.0, 0.0)
    inertia: float = 0.0
    guess: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ParameterError("Body.name", self.name, "must be a non-empty string")
        try:
            items = dict(self.points).items()
        except (TypeError, ValueError):
            raise ParameterError(f"{self.name}.points", self.points,
                                 "must map point names to (x, y) [m]") from None
        pts = {str(k): design_point(f"{self.name}.points.{k}", v) for k, v in items}
        object.__setattr__(self, "points", MappingProxyType(pts))
        object.__setattr__(self, "com", design_point(f"{self.name}.com", self.com))
        for attr in ("mass", "inertia"):
            v = design_value(f"{self.name}.{attr}", getattr(self, attr))
            if np.any(np.asarray(v) < 0):
                raise ParameterError(f"{self.name}.{attr}", _first(v, np.asarray(v) < 0),
                                     "must be finite and >= 0")
            object.__setattr__(self, attr, v)
        if self.guess is not None:
            if isinstance(self.guess, str):
                require_finite(f"{self.name}.guess", self.guess)  # names what it is not
            try:
                if len(self.guess) != 3:
                    raise TypeError
            except TypeError:
                raise ParameterError(f"{self.name}.guess", self.guess,
                                     "must be (x [m], y [m], theta [rad])") from None
            object.__setattr__(self, "guess", tuple(
                design_value(f"{self.name}.guess", v) for v in self.guess))

    def point(self, name: str) -> Point:
        """Local coordinates [m] of the named point; ``"com"`` is the centre of mass."""
        if name == "com":
            return self.com
        try:
            return self.points[name]
        except KeyError:
            raise ParameterError(f"{self.name}.points", name,
                                 f"no such point; known: {sorted(self.points)}") from None


def _first(value: Any, bad: Any) -> Any:
    """The first offending value of a number or of an array over the designs."""
    return float(np.asarray(value)[bad].flat[0]) if np.ndim(value) else value


def _show(value: Any) -> str:
    """A number, or the range of an array over the designs, for a message."""
    if np.ndim(value):
        return f"{float(np.min(value)):g}..{float(np.max(value)):g} over the designs"
    return f"{value:g}"


def _show_point(p: Any) -> str:
    return "(" + ", ".join(_show(v) for v in p) + ")"


def bar(name: str, start: str, end: str, length: float, *, mass: float = 0.0,
        com: float | Point | None = None, inertia: float | None = None,
        points: Mapping[str, Point] | None = None) -> Body:
    """A straight link whose x-axis runs from point ``start`` (origin) to point ``end``.

    Parameters
    ----------
    name, start, end : str
        Body name and names of its end points (``start`` at the origin, ``end`` at
        ``(length, 0)``).
    length : float
        Distance between the end points [m], > 0.
    mass : float
        Mass [kg].
    com : float or (x, y), optional
        Centre of mass: a distance from ``start`` along the link [m], or local coordinates;
        default the midpoint.
    inertia : float, optional
        Centroidal moment of inertia [kg m^2]; default that of a thin uniform rod,
        ``mass * length**2 / 12``.
    points : mapping, optional
        Further named points in the link's frame.
    """
    length = design_value(f"{name}.length", length)
    if np.any(np.asarray(length) <= 0):
        raise ParameterError(f"{name}.length", _first(length, np.asarray(length) <= 0),
                             "must be > 0")
    if start == end:  # one dict key: the start point would silently move to (length, 0)
        raise ParameterError(f"{name}.end", end, f"must differ from start {start!r}")
    for key, at in ((start, (0.0, 0.0)), (end, (length, 0.0))):
        if key in (points or {}):
            given = design_point(f"{name}.points.{key}", (points or {})[key])
            pairs = [np.broadcast_arrays(np.asarray(g), np.asarray(a))
                     for g, a in zip(given, at, strict=True)]
            if not all(np.array_equal(u, v) for u, v in pairs):
                shown = _show_point(at) if is_batched(at) else str(at)
                raise ParameterError(f"{name}.points.{key}", tuple((points or {})[key]),
                                     f"redefines the link's {'start' if key == start else 'end'}"
                                     f" point, which is at {shown} for length {_show(length)}")
    c: Point = (length / 2, 0.0) if com is None else (
        (design_value(f"{name}.com", com), 0.0) if np.ndim(com) == 0
        else design_point(f"{name}.com", com))
    pts = {start: (0.0, 0.0), end: (length, 0.0)}
    pts.update(dict(points or {}))
    if inertia is None:  # a thin uniform rod
        m = design_value(f"{name}.mass", mass)
        r = length / 12.0**0.5  # products overflow to inf, powers of floats would raise
        with np.errstate(over="ignore"):
            inert = m * r * r
        if not np.all(np.isfinite(inert)):
            raise ParameterError(f"{name}.length", _show(length), f"gives a rod inertia m L^2/12 "
                                 f"beyond the float range with mass = {_show(m)}; give lengths "
                                 "in metres")
    else:
        inert = inertia
    return Body(name, pts, mass=mass, com=c, inertia=inert)


@dataclass(frozen=True)
class Crank:
    """Rotary driver on a revolute joint: ``phi1 = theta_b - theta_a`` [rad].

    ``omega1`` [rad/s] and ``eps1`` [rad/s^2] are the defaults used when a kinematic analysis is
    not given them (scalars, or arrays over the positions passed at analysis time).
    """

    joint: str
    omega1: float = 1.0
    eps1: float = 0.0
    kind = "crank"
    #: the code of the joint type it drives (a revolute joint)
    joint_code = "R"
    #: the driver coordinate's name and unit (messages, tables)
    coordinate: ClassVar[tuple[str, str]] = ("phi1", "rad")
    #: units of the engine's driver fields: position phi1, speed omega1, acceleration eps1,
    #: driving load Q (a torque)
    field_units: ClassVar[Mapping[str, str]] = MappingProxyType(
        {"phi1": "rad", "omega1": "rad/s", "eps1": "rad/s^2", "Q": "N*m"})


@dataclass(frozen=True)
class Linear:
    """Linear driver on a prismatic joint: slide coordinate ``s1`` [m], speed ``v1`` [m/s],
    acceleration ``a1`` [m/s^2] (passed to the analysis as ``phi1, omega1, eps1``)."""

    joint: str
    v1: float = 1.0
    a1: float = 0.0
    kind = "linear"
    #: the code of the joint type it drives (a prismatic joint)
    joint_code = "P"
    #: the driver coordinate's name and unit (messages, tables)
    coordinate: ClassVar[tuple[str, str]] = ("s1", "m")
    #: units of the engine's driver fields (which keep the crank's names phi1, omega1, eps1):
    #: slide, speed, acceleration, driving load Q (a force)
    field_units: ClassVar[Mapping[str, str]] = MappingProxyType(
        {"phi1": "m", "omega1": "m/s", "eps1": "m/s^2", "Q": "N"})

    @property
    def omega1(self) -> float:
        return self.v1

    @property
    def eps1(self) -> float:
        return self.a1


class Drivers(tuple):
    """The drivers of a mechanism with several (``Mechanism.driver`` then holds them): a tuple
    whose one-driver attributes (``joint``, ``kind``, ``omega1``, ...) raise a ParameterError
    naming the drivers, so that code written for one driver refuses several clearly."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise ParameterError("driver", [d.joint for d in self],
                             f"has {len(self)} drivers; this needs one driver (its '{name}'): "
                             "Mechanism.drivers lists them")


@dataclass(frozen=True)
class Drawing(_PicklesByFields):
    """The drawn position a mechanism was described from (:func:`linkwork.planar.sketch`).

    Attributes
    ----------
    points : mapping str -> (x, y)
        Every drawn point in world coordinates [m], as given.
    poses : mapping str -> (x, y, theta)
        The pose of every moving body's frame in the drawing [m, m, rad].
    positions : tuple of float
        The driver positions of the drawing, one per driver (crank angle [rad], slide [m]).
    """

    points: Mapping[str, Point]
    poses: Mapping[str, tuple[float, float, float]]
    positions: tuple[float, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", MappingProxyType(dict(self.points)))
        object.__setattr__(self, "poses", MappingProxyType(dict(self.poses)))
        object.__setattr__(self, "positions", tuple(
            design_value("drawing.positions", v) for v in self.positions))

    @property
    def batched(self) -> bool:
        """Some drawn number varies over the designs of a batch."""
        return any(is_batched(v) for v in (*self.points.values(), *self.poses.values(),
                                            self.positions))

    def design(self, i: int) -> Drawing:
        """The drawing of design ``i`` of a batch."""
        return Drawing({k: pick(v, i) for k, v in self.points.items()},
                       {k: pick(v, i) for k, v in self.poses.items()},
                       pick(self.positions, i))


@dataclass(frozen=True)
class Mechanism(_PicklesByFields):
    """A planar mechanism: frame, moving bodies, joints, one driver, assembly branches.

    Parameters
    ----------
    frame : Body
        The fixed link; its points are the ground pivots and guide points.
    bodies : sequence of Body
        The moving links.
    joints : sequence of Revolute, Prismatic, PinInSlot
        The kinematic pairs.
    driver : Crank, Linear or a sequence of them
        The input; several drivers (cranks and linear actuators) for a mechanism of mobility
        W > 1, one per degree of freedom (``Mechanism.drivers`` always gives the tuple). With
        several drivers the driver positions, speeds and accelerations of an analysis have
        shape ``(n_drivers, n)``, in this order.
    branches : mapping str -> +1/-1
        Assembly branch of each Assur group, keyed by the group's key (see
        :mod:`linkwork.planar.structure`; for a dyad the name of the joint between its two bodies).
        Missing keys mean +1.
    drawing : Drawing, optional
        The drawn position the mechanism was described from (set by
        :func:`~linkwork.planar.sketch`): Newton-solved groups are continued from it.
    """

    frame: Body
    bodies: tuple[Body, ...]
    joints: tuple[Joint, ...]
    if TYPE_CHECKING:  # one driver for the code written for one (several: a Drivers tuple)
        driver: Crank | Linear
    else:
        driver: Crank | Linear | tuple[Crank | Linear, ...]
    branches: Mapping[str, Any] = field(default_factory=dict)
    drawing: Drawing | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.frame, Body):
            raise ParameterError("frame", self.frame, "must be a Body")
        for attr, kind in (("bodies", "Body"), ("joints", "Revolute, Prismatic or PinInSlot")):
            try:
                object.__setattr__(self, attr, tuple(getattr(self, attr)))
            except TypeError:
                raise ParameterError(attr, getattr(self, attr), f"must be a sequence of {kind}"
                                     ) from None
        for b in self.bodies:
            if not isinstance(b, Body):
                raise ParameterError("bodies", b, "must be Body objects")
        if not isinstance(self.branches, Mapping):
            raise ParameterError("branches", self.branches, "must map group keys to +1 or -1")
        object.__setattr__(self, "branches", MappingProxyType(dict(self.branches)))
        if self.drawing is not None and not isinstance(self.drawing, Drawing):
            raise ParameterError("drawing", self.drawing, "must be a Drawing or None")
        if isinstance(self.driver, Sequence) and not isinstance(self.driver, str):
            drivers = tuple(self.driver)
            if not drivers:
                raise ParameterError("driver", self.driver, "must name at least one driver")
            object.__setattr__(self, "driver",
                               drivers[0] if len(drivers) == 1 else Drivers(drivers))
        for d in self.drivers:
            if not isinstance(d, Crank | Linear):
                raise ParameterError("driver", d, "must be Crank or Linear (or a sequence of "
                                     "them)")
        names = [self.frame.name] + [b.name for b in self.bodies]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ParameterError("bodies", sorted(dup)[0], "body names must be unique")
        for j in self.joints:  # a concrete joint type (the base class has no behaviour)
            if not isinstance(j, Joint) or j.code == Joint.code:
                raise ParameterError("joints", j, "must be Revolute, Prismatic, PinInSlot or "
                                     "GearPair")
        jn = [j.name for j in self.joints]
        dupj = {n for n in jn if jn.count(n) > 1}
        if dupj:
            raise ParameterError("joints", sorted(dupj)[0], "joint names must be unique")
        for j in self.joints:
            for side in (j.a, j.b):
                if side not in names:
                    raise ParameterError(f"joint {j.name}", side, f"unknown body; known: {names}")
            if j.a == j.b:
                raise ParameterError(f"joint {j.name}", j.a, "must join two different bodies")
            self._check_joint_points(j)
        object.__setattr__(self, "branches", MappingProxyType(
            {k: branch_value(f"branches.{k}", v) for k, v in self.branches.items()}))
        jmap = {j.name: j for j in self.joints}
        driven = [d.joint for d in self.drivers]
        for d in self.drivers:
            if d.joint not in jmap:
                raise ParameterError("driver.joint", d.joint, f"no such joint; known: {jn}")
            if jmap[d.joint].code != d.joint_code:
                raise ParameterError("driver.joint", d.joint,
                                     "a Crank driver needs a revolute joint"
                                     if isinstance(d, Crank)
                                     else "a Linear driver needs a prismatic joint")
            if driven.count(d.joint) > 1:
                raise ParameterError("driver.joint", d.joint, "is driven twice")
        object.__setattr__(self, "_n_designs", count_designs(self._design_values()))

    def _check_joint_points(self, j: Joint) -> None:
        if j.carrier_of(self.frame.name) is not None:
            j.resolve(self)  # a gear pair: its pivots on the carrier, its radii
            return
        j.check_points(self.body(j.a), self.body(j.b))
        j.check_fit([self.body(s) for s in (j.a, j.b) if s != self.frame.name])

    # -- look-ups ---------------------------------------------------------------------------
    @property
    def drivers(self) -> tuple[Crank | Linear, ...]:
        """The drivers, in order (one or more)."""
        d: Any = self.driver
        return tuple(d) if isinstance(d, tuple) else (d,)

    @property
    def n_drivers(self) -> int:
        """Number of drivers (the mobility the mechanism must have)."""
        return len(self.drivers)

    @property
    def driver_units(self) -> Mapping[str, str]:
        """Units of the driver fields ``phi1, omega1, eps1, Q``: those of the driver, or of
        all drivers when they are of one kind; else each key's units in driver order, joined
        by ``", "`` (``"rad, m"``)."""
        return MappingProxyType(self._driver_units)

    @cached_property
    def _driver_units(self) -> dict[str, str]:
        """:attr:`driver_units`, worked out once (a dict: the mechanism stays picklable)."""
        units = [d.field_units for d in self.drivers]
        out = {}
        for k in units[0]:
            vals = [u[k] for u in units]
            out[k] = vals[0] if len(set(vals)) == 1 else ", ".join(vals)
        return out

    @cached_property
    def body_names(self) -> tuple[str, ...]:
        """Names of all bodies, the frame first (index 0)."""
        return (self.frame.name, *(b.name for b in self.bodies))

    @cached_property
    def index(self) -> dict[str, int]:
        """Body name -> index (frame 0, moving bodies 1..N in the given order)."""
        return {n: i for i, n in enumerate(self.body_names)}

    def body(self, name: str) -> Body:
        """The body called ``name`` (the frame included)."""
        if name == self.frame.name:
            return self.frame
        for b in self.bodies:
            if b.name == name:
                return b
        raise ParameterError("body", name, f"no such body; known: {list(self.body_names)}")

    def joint(self, name: str) -> Joint:
        """The joint called ``name``."""
        for j in self.joints:
            if j.name == name:
                return j
        raise ParameterError("joint", name,
                             f"no such joint; known: {[j.name for j in self.joints]}")

    def joint_geometry(self, j: Joint) -> tuple[Point, Point, float]:
        """Local geometry of a joint: (point on a, point on b, line angle in a [rad]).

        Revolute: the two coincident points and 0. Prismatic/PinInSlot: the line's point on
        ``a``, the slider/pin point on ``b`` and the line's angle in ``a``.
        """
        return j.resolve(self)[:3]

    def branch(self, key: str) -> Any:
        """Assembly branch of the group with this key (+1 unless set in ``branches``): +1 or
        -1, or an int array of them over the designs of a batch."""
        v = self.branches.get(key, 1)
        return v if isinstance(v, np.ndarray) else int(v)

    # -- designs in batches (linkwork.planar.designs) ---------------------------------------
    @property
    def n_designs(self) -> int | None:
        """The number of designs of a batch (some dimension, mass property or branch given
        as an array over the designs), or None for one design."""
        return self._n_designs  # type: ignore[attr-defined]

    def _design_values(self) -> list[tuple[str, Any]]:
        """Every value that may vary over the designs, named as in messages."""
        out: list[tuple[str, Any]] = []
        for b in (self.frame, *self.bodies):
            out += [(f"{b.name}.points.{k}", v) for k, v in b.points.items()]
            out += [(f"{b.name}.{k}", getattr(b, k)) for k in ("com", "mass", "inertia", "guess")]
        for j in self.joints:
            out += [(f"joint {j.name}.{f.name}", getattr(j, f.name))
                    for f in dataclasses.fields(j)]
        out += [(f"branches.{k}", v) for k, v in self.branches.items()]
        return out


    def design(self, i: int) -> Mechanism:
        """Design ``i`` of a batch as a mechanism of its own (every array over the designs
        replaced by its value at ``i``); a one-design mechanism itself (i = 0)."""
        m = self.n_designs
        if m is None:
            if i not in (0, -1):
                raise ParameterError("i", i, "must be 0: the mechanism is one design")
            return self
        if isinstance(i, bool) or not isinstance(i, int | np.integer) or not -m <= i < m:
            raise ParameterError("i", i, f"must be a design index in [0, {m})")
        k = int(i) % m

        def body(b: Body) -> Body:
            return Body(b.name, {p: pick(v, k) for p, v in b.points.items()},
                        mass=pick(b.mass, k), com=pick(b.com, k), inertia=pick(b.inertia, k),
                        guess=pick(b.guess, k))

        return Mechanism(body(self.frame), tuple(body(b) for b in self.bodies),
                         tuple(pick_fields(j, k) for j in self.joints), self.driver,
                         {key: int(pick(v, k)) for key, v in self.branches.items()},
                         self.drawing if self.drawing is None or not self.drawing.batched
                         else self.drawing.design(k))

    def with_branches(self, **branches: int) -> Mechanism:
        """A copy with some group branches changed (``m.with_branches(B=-1)``)."""
        new = dict(self.branches)
        new.update(branches)
        return Mechanism(self.frame, self.bodies, self.joints, self.driver, new, self.drawing)

    def driver_values(self, name: str, value: Any, n: int) -> np.ndarray:
        """A driver speed or acceleration given per position, as an array: shape ``(n,)`` for
        one driver (a scalar or ``n`` values), ``(n_drivers, n)`` for several (a scalar for
        all, one value per driver ``(n_drivers,)``, or ``(n_drivers, n)``)."""
        nd = self.n_drivers
        if nd == 1:
            return per_position(name, value, n)
        a = require_finite(name, value)
        if a.ndim == 1 and a.shape[0] == nd:
            a = a[:, None]
        try:
            return np.broadcast_to(a, (nd, n)).astype(float)
        except ValueError:
            raise ParameterError(name, a.shape, f"must be a scalar, one value per driver "
                                 f"({nd},) or have shape ({nd}, {n})") from None

    @cached_property
    def structure(self) -> Structure:
        """Structural analysis (mobility, Assur groups); raises StructureError if wrong."""
        return analyse(self)

    @cached_property
    def plan(self) -> Plan:
        """The compiled plan the solvers use (groups with resolved joints, body indices and
        local geometry); raises StructureError if the structure is wrong."""
        return compile_plan(self)

    def validate(self) -> Mechanism:
        """Run the structural analysis now (raises StructureError); return self."""
        _ = self.structure
        return self


def _as_bodies(bodies: Iterable[Body]) -> tuple[Body, ...]:
    out = tuple(bodies)
    for b in out:
        if not isinstance(b, Body):
            raise StructureError(f"not a Body: {b!r}")
    return out


def _per_link(n: int, **values: Any) -> None:
    """Per-link tuples of a shortcut builder must have one entry per link."""
    for key, v in values.items():
        if isinstance(v, str) or not isinstance(v, Sequence | np.ndarray) or len(v) != n:
            raise ParameterError(key, v, f"must have {n} entries, one per link")


def fourbar_mechanism(a: float, b: float, c: float, d: float, *,
                      masses: tuple[float, float, float] = (0.0, 0.0, 0.0),
                      inertias: tuple[float | None, float | None, float | None] = (
                          None, None, None),
                      coms: tuple[Any, Any, Any] = (None, None, None), omega1: float = 1.0,
                      eps1: float = 0.0, branch: int = 1) -> Mechanism:
    """The four-bar O2-A-B-O4 in Norton's notation, as an engine model.

    Frame line O2 -> O4 along +x (``O2 = (0, 0)``, ``O4 = (d, 0)``); crank ``a`` = O2A (body
    ``"crank"``, driven by ``Crank("O2")`` so ``phi1`` is Norton's theta2), coupler ``b`` = AB
    (``"coupler"``), rocker ``c`` = O4B (``"rocker"``, x-axis from O4 to B). ``branch=+1`` puts B
    on the left of the directed line A -> O4 (the dyad's key is ``"B"``). Masses, centroidal
    inertias (default thin rods) and centres of mass per link crank, coupler, rocker; a centre
    of mass is a distance along the link from its first point or a point ``(x, y)`` in the link's
    frame (x along the link), as in :func:`bar`; default the midpoint.
    """
    _per_link(masses=masses, inertias=inertias, coms=coms, n=3)
    links = [("crank", "O2", "A", a), ("coupler", "A", "B", b), ("rocker", "O4", "B", c)]
    bodies = [bar(n, s, e, L, mass=m, inertia=i, com=cm)
              for (n, s, e, L), m, i, cm in zip(links, masses, inertias, coms, strict=True)]
    frame = Body("frame", {"O2": (0.0, 0.0), "O4": (design_value("d", d), 0.0)})
    joints = (Revolute("O2", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("O4", "frame", "rocker"))
    return Mechanism(frame, _as_bodies(bodies), joints, Crank("O2", omega1, eps1), {"B": branch})


def crank_slider_mechanism(r: float, l: float, e: float = 0.0, *, guide_angle: float = 0.0,
                 masses: tuple[float, float, float] = (0.0, 0.0, 0.0),
                 inertias: tuple[float | None, float | None] = (None, None),
                 coms: tuple[Any, Any] = (None, None), omega1: float = 1.0, eps1: float = 0.0,
                 branch: int = 1) -> Mechanism:
    """The offset crank-slider O-A-B as an engine model.

    Crank ``r`` = OA (``"crank"``, ``Crank("O")``), rod ``l`` = AB (``"rod"``), slider
    (``"slider"``, point ``"B"`` at its origin) on a guide of the frame through ``(0, e)``
    rotated by ``guide_angle`` about O (i.e. offset ``e`` measured normal to the guide,
    positive to its left), direction ``(cos guide_angle, sin guide_angle)``. ``branch=+1`` puts
    B on the positive side of the guide (further along its direction); the key is ``"B"``.
    ``masses`` = (crank, rod, slider).
    """
    _per_link(masses=masses, n=3)
    _per_link(inertias=inertias, coms=coms, n=2)
    guide_angle = design_value("guide_angle", guide_angle)
    e = design_value("e", e)
    if is_batched(guide_angle):
        ca, sa = np.cos(guide_angle), np.sin(guide_angle)
    else:
        ca, sa = math.cos(guide_angle), math.sin(guide_angle)
    through = (-e * sa, e * ca)
    frame = Body("frame", {"O": (0.0, 0.0), "G": through})
    crank = bar("crank", "O", "A", r, mass=masses[0], inertia=inertias[0], com=coms[0])
    rod = bar("rod", "A", "B", l, mass=masses[1], inertia=inertias[1], com=coms[1])
    slider = Body("slider", {"B": (0.0, 0.0)}, mass=masses[2])
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("B", "rod", "slider"),
              Prismatic("G", "frame", "slider", angle=guide_angle, through="G", point="B"))
    return Mechanism(frame, (crank, rod, slider), joints, Crank("O", omega1, eps1),
                     {"B": branch})


#: Former names of the builders (they shared their names with linkwork.models.fourbar.fourbar and
#: the linkwork.models.crank_slider module); they call the new ones and warn.
fourbar = renamed_function(fourbar_mechanism, "linkwork.planar.fourbar")
crank_slider = renamed_function(crank_slider_mechanism, "linkwork.planar.crank_slider")


def stack(mechanisms: Sequence[Mechanism]) -> Mechanism:
    """One batch of designs from one-design mechanisms of the same structure.

    The mechanisms must have the same bodies, points, joints (types, names, bodies) and
    drivers; every number that differs between them (a point, a centre of mass, a mass, an
    inertia, a guess pose, a guide's angle or point, a relative angle, a branch) becomes an
    array over the designs, in the given order (``stack(ms).design(i)`` has the numbers of
    ``ms[i]``). A joint's friction data and a driver's default speed must be equal (not
    batched).
    """
    ms = list(mechanisms) if not isinstance(mechanisms, Mechanism) else []
    if not ms or not all(isinstance(x, Mechanism) for x in ms):
        raise ParameterError("mechanisms", mechanisms, "must be a non-empty sequence of "
                             "Mechanism")
    for k, x in enumerate(ms):
        if x.n_designs is not None:
            raise ParameterError(f"mechanisms[{k}]", f"{x.n_designs} designs",
                                 "must be one design (Mechanism.design(i) takes one of a "
                                 "batch)")
    t = ms[0]

    def same(what: str, values: list[Any]) -> Any:
        if any(v != values[0] for v in values[1:]):
            k = next(i for i, v in enumerate(values) if v != values[0])
            raise ParameterError(f"mechanisms[{k}]", what, "differs from mechanisms[0]: "
                                 "stack designs of one structure")
        return values[0]

    def merge(values: list[Any]) -> Any:
        if isinstance(values[0], tuple):
            return tuple(merge([v[i] for v in values]) for i in range(len(values[0])))
        if values[0] is None or isinstance(values[0], str):
            return same("a name or an unset value", values)
        if all(v == values[0] for v in values[1:]):
            return values[0]
        return np.array(values, dtype=float)

    def bodies(get: Any) -> list[Body]:
        out = []
        for k, b in enumerate(get(t)):
            group: list[Any] = [get(x)[k] if len(get(x)) > k else None for x in ms]
            same(f"body {b.name!r}", [None if g is None else (g.name, tuple(g.points))
                                       for g in group])
            out.append(Body(b.name, {p: merge([g.points[p] for g in group]) for p in b.points},
                            mass=merge([g.mass for g in group]),
                            com=merge([g.com for g in group]),
                            inertia=merge([g.inertia for g in group]),
                            guess=merge([g.guess for g in group])))
        return out

    for x in ms:
        same("the number of bodies and joints", [(len(y.bodies), len(y.joints)) for y in (t, x)])
    frame = bodies(lambda x: [x.frame])[0]
    joints = []
    batched = {"angle", "through", "rel_angle"}
    for k, j in enumerate(t.joints):
        group = [x.joints[k] for x in ms]
        same(f"joint {j.name!r}", [(type(g), g.name, g.a, g.b) for g in group])
        values = {}
        for f in dataclasses.fields(j):
            vals = [getattr(g, f.name) for g in group]
            values[f.name] = merge(vals) if f.name in batched else same(
                f"joint {j.name}.{f.name} (not batched)", vals)
        joints.append(dataclasses.replace(j, **values))
    driver = same("the drivers", [x.drivers for x in ms])
    keys = sorted({k for x in ms for k in x.branches})
    branches = {}
    for key in keys:
        v = merge([x.branch(key) for x in ms])
        branches[key] = v.astype(np.int64) if isinstance(v, np.ndarray) else v
    drawing = None
    if all(x.drawing is not None for x in ms):
        ds = [x.drawing for x in ms]
        drawing = Drawing({p: merge([d.points[p] for d in ds]) for p in ds[0].points},  # type: ignore[union-attr]
                          {p: merge([d.poses[p] for d in ds]) for p in ds[0].poses},  # type: ignore[union-attr]
                          merge([tuple(d.positions) for d in ds]))  # type: ignore[union-attr]
    return Mechanism(frame, tuple(bodies(lambda x: x.bodies)), tuple(joints),
                     driver[0] if len(driver) == 1 else driver, branches, drawing)
