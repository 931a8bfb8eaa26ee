"""A mechanism from its drawing: points in world coordinates, links as lists of points.

:func:`sketch` builds a :class:`~linkwork.planar.model.Mechanism` the way an engineer draws one:
every joint centre, coupler point and guide point is a named point at its world coordinates
[m] in the drawn position; a link is the list of its points; a point on two links is a revolute
joint between them, a point in ``ground`` and on a link a revolute to the frame. Sliders
(prismatic pairs) and slots (pin-in-slot pairs) are declared by their point and the direction
of their guide as drawn. From the drawing alone it takes

* every body's frame (origin at its first point, x-axis towards its second; a crank's origin at
  its driven frame pivot) and the local coordinates of its points;
* every joint's local geometry (guide lines through the drawn slider point, the relative angle
  of a prismatic pair as drawn);
* the drawn driver positions (:class:`~linkwork.planar.model.Drawing`), and
* the **assembly branch of every group**: each closed-form group is solved at the drawn driver
  positions on both branches and keeps the one that reproduces the drawing; Newton-solved groups
  start from the drawn poses (and :func:`~linkwork.planar.kinematics.kinematics` continues them
  from the drawn driver positions).

So the mechanism at its drawn driver positions reproduces every drawn point (checked before it
is returned, to 1e-9 of the mechanism's size), and a wrong ``+1``/``-1`` cannot happen.

Conventions
-----------
* A link's frame: origin at its first listed point, x-axis towards the next listed point at
  another place; a link driven by a crank has its origin at the driven frame pivot, so the
  crank angle ``phi1`` is the direction of the link's next point seen from the pivot.
* A slider's (or slot's) line passes through its drawn point in the given direction; its point
  on the guide body is the foot of the perpendicular from the guide body's origin, so the slide
  coordinate ``s1`` of a linear driver is the position of the slider point along the guide
  measured from that foot (on a frame guide: from the projection of the world origin).
* A block made for a slider (``Slider.body`` not given) is a body named like the slider, with
  its origin at the slider point and its x-axis along the guide; it is pinned at the point to
  the links that hold the point.
* Joints at a point are named after the point: the first pair of bodies holding it (the frame
  first, then the links in the order of ``links``) ``P``, each further body's revolute with the
  first ``P:<body>``. Sliders and slots are named by their keys.

Mass properties per link (``masses``): a mass [kg], or a :class:`LinkMass` (mass, centre of mass
as a drawn point's name or world coordinates as drawn [m], centroidal inertia [kg m^2]).
Defaults: a two-point link is a thin uniform rod (centre of mass at the midpoint, inertia
``m L^2 / 12``); a link of three or more points has its centre of mass at the centroid of its
points and no inertia unless given; a slider block its centre of mass at its point.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.errors import AssemblyError, ParameterError, StructureError
from linkwork.planar.designs import design_point, design_value
from linkwork.planar.joints import GearPair, Joint, PinInSlot, Prismatic, Revolute
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import Body, Crank, Drawing, Linear, Mechanism
from linkwork.planar.positions import solve_group
from linkwork.planar.state import State

__all__ = ["BRANCH_TOLERANCE", "Cylinder", "LinkMass", "Slider", "Slot", "drawn_state", "sketch"]

Point = tuple[float, float]

#: The two assemblies of a group closer than this fraction of the mechanism's size at the
#: drawn position: the drawing is at a toggle and cannot tell its branch.
BRANCH_TOLERANCE = 1e-6
#: Largest miss of a drawn point by the mechanism solved at the drawn driver positions,
#: relative to the mechanism's size (a round-trip check; rounding gives ~1e-15).
ROUND_TRIP_TOLERANCE = 1e-9
#: Largest distance of a slider's point from the guide line drawn through two points,
#: relative to the mechanism's size.
ON_LINE_TOLERANCE = 1e-6

#: Groups whose solution is unique (no branch to choose).
_UNIQUE = {"driver", "newton", "PRP", "RPP", "PPR", "PS", "RG"}


@dataclass(frozen=True)
class Slider:
    """A prismatic pair as drawn: ``point`` slides along a guide of body ``guide``.

    Parameters
    ----------
    point : str
        The slider point (a drawn point).
    guide : str
        The body carrying the guide: the frame's name or a link.
    angle : float, optional
        Direction of the guide in the drawing [rad], counter-clockwise from the world x-axis;
        also the positive direction of the slide coordinate.
    along : (str, str), optional
        Or the guide as the line through two drawn points, directed from the first to the
        second; the slider point must lie on it.
    body : str, optional
        The sliding body: a link holding ``point``. Default: a block named like the slider,
        pinned at ``point`` to the links that hold it.
    """

    point: str
    guide: str
    angle: float | None = None
    along: tuple[str, str] | None = None
    body: str | None = None


@dataclass(frozen=True)
class Slot:
    """A pin-in-slot pair as drawn: the pin ``point`` (of the links holding it) runs in a
    straight slot of body ``guide`` (the frame or a link not holding the point), in the
    direction ``angle`` [rad] or ``along`` two drawn points (see :class:`Slider`)."""

    point: str
    guide: str
    angle: float | None = None
    along: tuple[str, str] | None = None


@dataclass(frozen=True)
class Cylinder:
    """A linear actuator as drawn between two pivots: its barrel hinged at ``start``, its rod
    at ``end`` (each a drawn point held by a link or the frame). It makes the bodies
    ``<name>_barrel`` (origin at ``start``, x-axis towards ``end``) and ``<name>_rod`` and the
    prismatic pair ``<name>`` between them, whose slide coordinate is the pin-to-pin length
    |start end| [m]; named in ``drivers`` it is driven by that length (a closed-form
    ``cyl-RRR``/``cyl-RRP`` group when it moves one hinged or sliding body)."""

    start: str
    end: str


@dataclass(frozen=True)
class LinkMass:
    """Mass properties of a drawn link: ``mass`` [kg]; ``com`` a drawn point's name or world
    coordinates as drawn [m] (default: see :mod:`linkwork.planar.sketch`); ``inertia``
    centroidal [kg m^2] (default: a thin rod for a two-point link, else 0)."""

    mass: float = 0.0
    com: str | Point | None = None
    inertia: float | None = None


def _batched(*values: Any) -> bool:
    return any(isinstance(v, np.ndarray) for v in values)


def _cos(x: Any) -> Any:
    return np.cos(x) if _batched(x) else math.cos(x)


def _sin(x: Any) -> Any:
    return np.sin(x) if _batched(x) else math.sin(x)


def _atan2(y: Any, x: Any) -> Any:
    return np.arctan2(y, x) if _batched(y, x) else math.atan2(y, x)


def _hypot(x: Any, y: Any) -> Any:
    return np.hypot(x, y) if _batched(x, y) else math.hypot(x, y)


def _design(value: Any) -> str:
    """Where a per-design test fails: '' for one design, else ' (design i)'."""
    if isinstance(value, np.ndarray) and value.ndim:
        return f" (design {int(np.flatnonzero(value)[0])})"
    return ""


def _rot(th: float, v: Point) -> Point:
    c, s = _cos(th), _sin(th)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _local(pose: tuple[float, float, float], p: Point) -> Point:
    """World point ``p`` in the frame of a body at ``pose``."""
    x, y, th = pose
    return _rot(-th, (p[0] - x, p[1] - y))


def _names(kind: str, value: Any) -> list[str]:
    if isinstance(value, str) or not isinstance(value, Sequence):
        raise ParameterError(kind, value, "must be a list of point names")
    out = [str(v) for v in value]
    return out


def _direction(key: str, spec: Slider | Slot, pts: Mapping[str, Point], scale: float) -> float:
    """World angle of a slider's or slot's line [rad] (checking the point lies on a line drawn
    through two points)."""
    if (spec.angle is None) == (spec.along is None):
        raise ParameterError(f"{key}.angle", spec.angle,
                             "give the guide's direction either as angle or as along (two "
                             "points), not both or neither")
    if spec.angle is not None:
        return design_value(f"{key}.angle", spec.angle)
    along = spec.along
    if isinstance(along, str) or not isinstance(along, Sequence) or len(along) != 2:
        raise ParameterError(f"{key}.along", along, "must be two point names")
    for p in along:
        if p not in pts:
            raise ParameterError(f"{key}.along", p, f"no such point; known: {sorted(pts)}")
    (ax, ay), (bx, by) = pts[along[0]], pts[along[1]]
    length = _hypot(bx - ax, by - ay)
    if np.any(length == 0.0):
        raise ParameterError(f"{key}.along", list(along), "the two points coincide: no direction"
                             + _design(length == 0.0))
    ux, uy = (bx - ax) / length, (by - ay) / length
    px, py = pts[spec.point]
    off = abs(-uy * (px - ax) + ux * (py - ay))
    far = off > ON_LINE_TOLERANCE * scale
    if np.any(far):
        k = int(np.flatnonzero(far)[0]) if _batched(far) else None
        shown = off if k is None else off[k]
        raise AssemblyError(f"drawing is not assembled: point {spec.point!r} of {key} is "
                            f"{shown * 1e3:.6g} mm off the line through {along[0]!r} and "
                            f"{along[1]!r} that guides it" + _design(far))
    return _atan2(uy, ux)


def _line_geometry(pose: tuple[float, float, float], P: Point, angle: float
                   ) -> tuple[Point, float]:
    """A line through world point P at world angle ``angle``, on a body at ``pose``: the foot
    of the perpendicular from the body's origin (local) and the line's local angle."""
    ux, uy = _cos(angle), _sin(angle)
    t = (pose[0] - P[0]) * ux + (pose[1] - P[1]) * uy
    foot = (P[0] + t * ux, P[1] + t * uy)
    return _local(pose, foot), angle - pose[2]


def _frame_pose(name: str, order: list[str], pts: Mapping[str, Point], origin: str
                ) -> tuple[float, float, float]:
    """Pose of a link's frame: origin at ``origin``, x-axis towards the next listed point at
    another place (a gear of one point: along the world x-axis)."""
    ox, oy = pts[origin]
    if len(order) == 1:
        return ox, oy, 0.0
    rest = order[order.index(origin) + 1:] + order[:order.index(origin)]
    for p in rest:
        dx, dy = pts[p][0] - ox, pts[p][1] - oy
        apart = _hypot(dx, dy) > 0.0
        if np.all(apart):
            return ox, oy, _atan2(dy, dx)
        if np.any(apart):
            raise ParameterError(f"links.{name}", order, f"point {p!r} coincides with "
                                 f"{origin!r} in some designs only: the link's direction is "
                                 "drawn differently (not batched)" + _design(~apart))
    raise ParameterError(f"links.{name}", order, "its points all coincide: the link's "
                         "direction is not drawn")


def _mass_of(name: str, spec: Any, local: dict[str, Point], pose: tuple[float, float, float],
             pts: Mapping[str, Point], default_com: Point, rod: float | None
             ) -> tuple[float, Point, float]:
    """(mass, local centre of mass, inertia) of a link from its ``masses`` entry."""
    if spec is None:
        spec = LinkMass()
    elif not isinstance(spec, LinkMass):
        if isinstance(spec, Mapping):
            unknown = set(spec) - {"mass", "com", "inertia"}
            if unknown:
                raise ParameterError(f"masses.{name}", sorted(unknown)[0],
                                     "unknown key; known: mass, com, inertia")
            spec = LinkMass(**dict(spec))
        else:
            spec = LinkMass(mass=spec)
    m = design_value(f"masses.{name}.mass", spec.mass)
    if np.any(np.asarray(m) < 0):
        raise ParameterError(f"masses.{name}.mass", m, "must be >= 0 [kg]")
    if spec.com is None:
        com = default_com
    elif isinstance(spec.com, str):
        if spec.com not in pts:
            raise ParameterError(f"masses.{name}.com", spec.com,
                                 f"no such point; known: {sorted(pts)}")
        com = _local(pose, pts[spec.com])
    else:
        com = _local(pose, design_point(f"masses.{name}.com", spec.com))
    if spec.inertia is not None:
        inertia = design_value(f"masses.{name}.inertia", spec.inertia)
        if np.any(np.asarray(inertia) < 0):
            raise ParameterError(f"masses.{name}.inertia", inertia, "must be >= 0 [kg m^2]")
    else:
        inertia = m * rod * rod / 12.0 if rod is not None else 0.0
    return m, com, inertia


def drawn_state(mech: Mechanism) -> State:
    """A solver state holding the drawn poses of ``mech`` (one position; for a batch of
    designs, one element per design)."""
    if mech.drawing is None:
        raise ParameterError("mech", mech.frame.name, "has no drawing (not built by sketch)")
    n = mech.n_designs or 1
    st = State(len(mech.body_names), n)
    for i, name in enumerate(mech.body_names[1:], start=1):
        x, y, th = (np.broadcast_to(v, (n,)).astype(float) for v in mech.drawing.poses[name])
        st.X[i], st.Y[i] = x, y
        st.set_angle(i, th)
    return st


def _branches(mech: Mechanism, scale: Any) -> dict[str, Any]:
    """The branch of every closed-form group that reproduces the drawing (for a batch, per
    design: an array over the designs where they differ)."""
    assert mech.drawing is not None
    m = mech.n_designs
    n = m or 1
    plan = mech.plan if m is None else mech.plan.pick(np.arange(m))
    q = np.array([np.broadcast_to(v, (n,)) for v in mech.drawing.positions], dtype=float)
    tol = BRANCH_TOLERANCE * np.asarray(scale)
    out: dict[str, Any] = {}
    for g in plan.groups:
        if g.kind in _UNIQUE:
            continue
        found = {}
        for b in (1, -1):
            st = drawn_state(mech)
            with np.errstate(all="ignore"):
                solve_group(plan, st, g, b, q)
            found[b] = np.array([[st.X[i], st.Y[i], st.T[i]] for i in g.bodies])
        drawn = np.array([[np.broadcast_to(v, (n,)) for v in mech.drawing.poses[
            plan.body_names[i]]] for i in g.bodies], dtype=float)

        def gap(a: np.ndarray, c: np.ndarray) -> np.ndarray:
            d = a - c
            d[:, 2] = (np.remainder(d[:, 2] + np.pi, 2 * np.pi) - np.pi) * scale
            return np.where(np.all(np.isfinite(d), axis=(0, 1)), np.max(np.abs(d), axis=(0, 1)),
                            math.inf)

        what = (f"group {g.kind}({', '.join(g.group.bodies)}) with joints "
                f"{', '.join(g.group.joints)}")
        toggle = gap(found[1], found[-1]) <= tol
        if toggle.any():
            raise AssemblyError(f"drawing is at a toggle of joint {g.key!r}: its two assemblies "
                                f"coincide in the drawn position ({what}), so the branch cannot "
                                "be taken from the drawing; draw the mechanism in another "
                                "position" + (_design(toggle) if m else ""))
        plus, minus = gap(found[1], drawn) <= tol, gap(found[-1], drawn) <= tol
        neither = ~(plus | minus)
        if neither.any():
            raise AssemblyError(f"drawing is not assembled at joint {g.key!r}: neither "
                                f"assembly of {what} reproduces the drawn points"
                                + (_design(neither) if m else ""))
        br = np.where(plus, 1, -1)
        out[g.key] = int(br[0]) if m is None or (br == br[0]).all() else br
    return out


def _round_trip(mech: Mechanism, scale: Any) -> None:
    """The mechanism at the drawn driver positions reproduces every drawn point."""
    assert mech.drawing is not None
    m = mech.n_designs
    nd = len(mech.drawing.positions)
    if m is None:
        q = np.array(mech.drawing.positions)
        phi = q[0] if q.size == 1 else q[:, None]
        speed: Any = 0.0 if q.size == 1 else np.zeros((q.size, 1))
    else:  # one position per design
        q = np.array([np.broadcast_to(v, (m,)) for v in mech.drawing.positions], dtype=float)
        phi = q[0][:, None] if nd == 1 else q[:, :, None]
        speed = 0.0
    kin = kinematics(mech, phi, speed, None, on_failure="nan")
    for b in mech.bodies:
        for p in b.points:
            if p not in mech.drawing.points:
                continue
            pm = kin.point(b.name, p)
            miss = np.hypot(pm.x[..., 0] - mech.drawing.points[p][0],
                            pm.y[..., 0] - mech.drawing.points[p][1])
            bad = ~(miss <= ROUND_TRIP_TOLERANCE * np.asarray(scale))
            if bad.any():
                k = int(np.flatnonzero(bad)[0]) if m else 0
                raise AssemblyError(f"drawing is not assembled: the mechanism solved at the "
                                    f"drawn driver positions misses point {p!r} of link "
                                    f"{b.name!r} by {float(np.ravel(miss)[k]) * 1e3:.6g} mm"
                                    + (f" (design {k})" if m else ""))


def _driver_specs(drivers: Any) -> list[Any]:
    if isinstance(drivers, str | tuple) and not (
            isinstance(drivers, tuple) and drivers and isinstance(drivers[0], tuple)):
        return [drivers]
    if not isinstance(drivers, Sequence) or not drivers:
        raise ParameterError("drivers", drivers, "must name at least one driver (a frame pivot "
                             "point or a slider)")
    return list(drivers)


def sketch(points: Mapping[str, Any], links: Mapping[str, Sequence[str]], *,
           ground: Sequence[str], drivers: Any, sliders: Mapping[str, Any] | None = None,
           slots: Mapping[str, Any] | None = None, masses: Mapping[str, Any] | None = None,
           frame: str = "frame", speeds: Mapping[str, tuple[float, float]] | None = None,
           cylinders: Mapping[str, Any] | None = None, gears: Mapping[str, Any] | None = None
           ) -> Mechanism:
    """A mechanism from its drawing (see the module docstring for the conventions).

    Parameters
    ----------
    points : mapping str -> (x, y)
        Every named point at its world coordinates in the drawn position [m].
    links : mapping str -> sequence of str
        Each moving link's name and its points (at least two): a point on two links is a
        revolute joint between them.
    ground : sequence of str
        The points fixed to the frame; such a point on a link is a revolute to the frame.
    drivers : str, tuple or sequence of them
        The driving joints: a frame pivot's point name (a crank: the link hinged there; if
        several links are, ``(point, link)``) or a slider's name (a linear driver).
    sliders : mapping str -> Slider (or a mapping of its fields), optional
        Prismatic pairs by name.
    slots : mapping str -> Slot (or a mapping of its fields), optional
        Pin-in-slot pairs by name.
    masses : mapping str -> mass [kg] or LinkMass (or a mapping of its fields), optional
        Mass properties per link (and per slider block).
    frame : str
        Name of the frame body.
    speeds : mapping str -> (speed, acceleration), optional
        The default speed and acceleration of a driver, by its name as in ``drivers`` (a
        crank's [rad/s, rad/s^2], a slider's [m/s, m/s^2]); default (1, 0).
    cylinders : mapping str -> Cylinder (or (start, end), or a mapping of its fields), optional
        Linear actuators between two pivots, by name (a driver by that name drives its
        length).
    gears : mapping str -> mapping, optional
        Gear pairs by name: ``a``, ``b`` (two links, each hinged to the carrier at its
        centre; a gear link may hold that one point), ``teeth=(z_a, z_b)`` or ``radii=(r_a,
        r_b)``, ``internal``, ``carrier`` (a link; default the frame), ``pressure_angle``,
        ``efficiency`` (:class:`~linkwork.planar.GearPair`); the relative phase of the gears
        is taken from the drawing, and drawn centres that do not fit given radii are
        refused.

    Returns
    -------
    Mechanism
        With its ``drawing`` (drawn points, poses and driver positions) and the branches that
        reproduce it. Drawn coordinates (and slider or slot angles, masses) given as 1-D arrays
        over m designs make a batch of m designs (:mod:`~linkwork.planar.designs`): every
        design's frames, local points and branches are taken from its own drawing, at once
        (an error names the first design whose drawing is not assembled).

    Raises
    ------
    ParameterError
        A point on no link, a link with fewer than two points or an unknown point, a driver
        on a point that is not a frame pivot, a bad slider or slot (naming it).
    AssemblyError
        The drawing is not assembled (a slider's point off its drawn guide line) or is at a
        toggle of some group (its branch cannot be taken from the drawing).
    StructureError
        The drawn mechanism's mobility differs from the number of drivers, or a group cannot
        be solved.
    """
    if not isinstance(points, Mapping) or not points:
        raise ParameterError("points", points, "must map point names to (x, y) [m]")
    pts: dict[str, Point] = {str(k): design_point(f"points.{k}", v) for k, v in points.items()}
    if not isinstance(links, Mapping) or not links:
        raise ParameterError("links", links, "must map link names to lists of point names")
    link_pts: dict[str, list[str]] = {}
    for name, lp in links.items():
        name = str(name)
        if name == frame:
            raise ParameterError(f"links.{name}", name, "is the frame's name; links are the "
                                 "moving bodies (ground points go in ground)")
        order = _names(f"links.{name}", lp)
        for p in order:
            if p not in pts:
                raise ParameterError(f"links.{name}", p, f"no such point; known: {sorted(pts)}")
        dup = sorted({p for p in order if order.count(p) > 1})
        if dup:
            raise ParameterError(f"links.{name}", dup[0], "listed twice on the link")
        if len(order) < 2 and not any(name in (g.get("a"), g.get("b"))
                                       for g in dict(gears or {}).values()
                                       if isinstance(g, Mapping)):
            raise ParameterError(f"links.{name}", order, "a link needs at least two points (its "
                                 "direction is taken from the drawing); only a gear may hold "
                                 "just its centre")
        link_pts[name] = order
    gnd = _names("ground", ground)
    for p in gnd:
        if p not in pts:
            raise ParameterError("ground", p, f"no such point; known: {sorted(pts)}")
    coords = [abs(c) for p in pts.values() for c in p]
    scale: Any = (np.maximum(np.max(np.broadcast_arrays(*coords), axis=0), 1e-3)
                  if _batched(*coords) else max(max(coords), 1e-3))
    sliders = dict(sliders or {})
    slots = dict(slots or {})
    sl: dict[str, Slider] = {}
    for key, spec in sliders.items():
        sl[str(key)] = spec if isinstance(spec, Slider) else Slider(**dict(spec))
    so: dict[str, Slot] = {}
    for key, spec in slots.items():
        so[str(key)] = spec if isinstance(spec, Slot) else Slot(**dict(spec))
    cy: dict[str, Cylinder] = {}
    for key, spec in dict(cylinders or {}).items():
        if isinstance(spec, Cylinder):
            cy[str(key)] = spec
        elif isinstance(spec, Mapping):
            cy[str(key)] = Cylinder(**dict(spec))
        else:
            try:
                if isinstance(spec, str):
                    raise TypeError(spec)
                a, b = spec
            except (TypeError, ValueError):
                raise ParameterError(f"cylinders.{key}", spec, "must be (start, end): the "
                                     "points of its two pivots") from None
            cy[str(key)] = Cylinder(str(a), str(b))
    for key, c in cy.items():
        for end in ("start", "end"):
            if getattr(c, end) not in pts:
                raise ParameterError(f"cylinders.{key}.{end}", getattr(c, end),
                                     f"no such point; known: {sorted(pts)}")
        if np.any((np.asarray(pts[c.start][0]) == pts[c.end][0])
                  & (np.asarray(pts[c.start][1]) == pts[c.end][1])):
            raise ParameterError(f"cylinders.{key}", [c.start, c.end], "its pivots coincide: "
                                 "a cylinder has a length")
        taken = {*link_pts, frame, *sl, *so}
        for name in (key, f"{key}_barrel", f"{key}_rod"):
            if name in taken:
                raise ParameterError("cylinders", key, f"the name {name!r} is taken by a link, "
                                     "a slider or a slot")
    bodies_known = {frame, *link_pts, *(k for k, v in sl.items() if v.body is None)}
    for kind, table in (("sliders", sl), ("slots", so)):
        for key, spec in table.items():
            if spec.point not in pts:
                raise ParameterError(f"{kind}.{key}.point", spec.point,
                                     f"no such point; known: {sorted(pts)}")
            if spec.guide not in bodies_known:
                raise ParameterError(f"{kind}.{key}.guide", spec.guide,
                                     f"no such body; known: {sorted(bodies_known)}")
            if key in link_pts or key == frame or (kind == "slots" and key in sl):
                raise ParameterError(kind, key, "a slider's or slot's name must differ from the "
                                     "links' and the frame's")
    blocks = [k for k, s in sl.items() if s.body is None]
    for key, s in sl.items():
        if s.body is not None:
            if s.body not in link_pts:
                raise ParameterError(f"sliders.{key}.body", s.body,
                                     f"no such link; known: {sorted(link_pts)}")
            if s.point not in link_pts[s.body]:
                raise ParameterError(f"sliders.{key}.point", s.point,
                                     f"is not a point of its sliding link {s.body!r} "
                                     f"({link_pts[s.body]})")
        if s.guide == (s.body or key):
            raise ParameterError(f"sliders.{key}.guide", s.guide, "must differ from the "
                                 "sliding body")
    # the bodies holding each point (frame first, then links, then slider blocks)
    holders: dict[str, list[str]] = {p: [] for p in pts}
    for p in gnd:
        holders[p].append(frame)
    for name, order in link_pts.items():
        for p in order:
            holders[p].append(name)
    for key in blocks:
        holders[sl[key].point].append(key)
    for key, c in cy.items():
        for end, part in ((c.start, "barrel"), (c.end, "rod")):
            if not holders[end]:
                raise ParameterError(f"cylinders.{key}", end, f"no link (nor the frame) holds "
                                     f"this point, so the cylinder's {part} is hinged to "
                                     "nothing")
            holders[end].append(f"{key}_{part}")
    for key, t in so.items():
        if t.guide in holders[t.point]:
            raise ParameterError(f"slots.{key}.guide", t.guide,
                                 f"holds the pin {t.point!r} itself; the slot must be in "
                                 "another body than the pin's")
        if not holders[t.point]:
            raise ParameterError(f"slots.{key}.point", t.point, "no link holds this pin")
    for p, hs in holders.items():
        if not hs:
            raise ParameterError(f"points.{p}", list(pts[p]), "the point is on no link and not "
                                 "in ground; put it on a link or remove it")
    # drivers: which joint, and which link a crank turns (its origin at the pivot)
    specs = _driver_specs(drivers)
    driven_origin: dict[str, str] = {}
    driver_joints: list[tuple[str, str, str]] = []  # (name as given, kind, joint)
    for spec in specs:
        link = None
        if isinstance(spec, tuple):
            if len(spec) != 2:
                raise ParameterError("drivers", spec, "must be a point, a slider, or "
                                     "(point, link)")
            spec, link = str(spec[0]), str(spec[1])
        spec = str(spec)
        if spec in sl or spec in cy:
            driver_joints.append((spec, "linear", spec))
            continue
        if spec not in pts:
            raise ParameterError("drivers", spec, f"is neither a point nor a slider or cylinder; "
                                 f"points: {sorted(pts)}, sliders: {sorted(sl)}, cylinders: "
                                 f"{sorted(cy)}")
        if spec not in gnd:
            raise ParameterError("drivers", spec, "is not a frame pivot (not in ground): a crank "
                                 "turns about a point of the frame")
        on = [h for h in holders[spec] if h in link_pts]
        if link is None:
            if len(on) != 1:
                raise ParameterError("drivers", spec,
                                     f"is the frame pivot of {len(on)} links {on}: name the "
                                     f"driven one as ({spec!r}, link)" if on else
                                     "no link is hinged to the frame at this point")
            link = on[0]
        elif link not in on:
            raise ParameterError("drivers", (spec, link), f"link {link!r} is not hinged to the "
                                 f"frame at {spec!r}; hinged there: {on}")
        if link in driven_origin:
            raise ParameterError("drivers", (spec, link), "the link is driven twice")
        driven_origin[link] = spec
        driver_joints.append((spec, "crank", ""))
    # body frames as drawn
    poses: dict[str, tuple[float, float, float]] = {}
    for name, order in link_pts.items():
        poses[name] = _frame_pose(name, order, pts, driven_origin.get(name, order[0]))
    for key in blocks:
        s = sl[key]
        poses[key] = (*pts[s.point], _direction(f"sliders.{key}", s, pts, scale))
    for key, c in cy.items():
        axis = _atan2(pts[c.end][1] - pts[c.start][1], pts[c.end][0] - pts[c.start][0])
        poses[f"{key}_barrel"] = (*pts[c.start], axis)
        poses[f"{key}_rod"] = (*pts[c.end], axis)
    frame_pose = (0.0, 0.0, 0.0)

    def pose_of(body: str) -> tuple[float, float, float]:
        return frame_pose if body == frame else poses[body]

    # joints
    joints: list[Joint] = []
    for p, hs in holders.items():
        for k, h in enumerate(hs[1:], start=1):
            joints.append(Revolute(p if k == 1 else f"{p}:{h}", hs[0], h, point_a=p,
                                   point_b=p))
    for key, s in sl.items():
        ang = _direction(f"sliders.{key}", s, pts, scale)
        through, local_angle = _line_geometry(pose_of(s.guide), pts[s.point], ang)
        body = s.body or key
        rel = pose_of(body)[2] - pose_of(s.guide)[2]
        joints.append(Prismatic(key, s.guide, body, angle=local_angle, through=through,
                                point=s.point, rel_angle=rel))
    for key, c in cy.items():  # s = u . (end - start) = the pin-to-pin length
        joints.append(Prismatic(key, f"{key}_barrel", f"{key}_rod", angle=0.0,
                                through=(0.0, 0.0), point=c.end, rel_angle=0.0))
    for key, t in so.items():
        ang = _direction(f"slots.{key}", t, pts, scale)
        through, local_angle = _line_geometry(pose_of(t.guide), pts[t.point], ang)
        pin = next(h for h in holders[t.point] if h != t.guide)
        joints.append(PinInSlot(key, t.guide, pin, angle=local_angle, through=through,
                                point=t.point))
    joints += _gear_pairs(dict(gears or {}), frame, pose_of, set(link_pts))
    names = [j.name for j in joints]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ParameterError("joints", dup[0], "two joints have this name (a point and a "
                             "slider or slot named alike); rename one")
    # the driver joints
    drv: list[Crank | Linear] = []
    spd = dict(speeds or {})
    for (given, kind, joint), spec in zip(driver_joints, specs, strict=True):
        w, e = spd.get(given, (1.0, 0.0))
        if kind == "linear":
            drv.append(Linear(joint, w, e))
            continue
        link = next(k for k, v in driven_origin.items() if v == given and (
            not isinstance(spec, tuple) or spec[1] == k))
        jn = next(j.name for j in joints if isinstance(j, Revolute) and j.a == frame
                  and j.b == link and (j.name == given or j.name == f"{given}:{link}"))
        drv.append(Crank(jn, w, e))
    # bodies
    masses = dict(masses or {})
    for name in masses:
        if name not in poses:
            raise ParameterError("masses", name, f"no such link; known: {sorted(poses)}")
    bodies = []
    ends = {f"{k}_{part}": getattr(c, end) for k, c in cy.items()
            for part, end in (("barrel", "start"), ("rod", "end"))}
    for name, pose in poses.items():
        order = link_pts.get(name, [sl[name].point] if name in sl else [ends[name]]
                             if name in ends else [])
        local = {p: _local(pose, pts[p]) for p in order}
        if name in link_pts and len(order) == 2:
            a, b = local[order[0]], local[order[1]]
            default_com: Point = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
            rod: float | None = _hypot(b[0] - a[0], b[1] - a[1])
        else:
            default_com = (sum(v[0] for v in local.values()) / len(local),
                           sum(v[1] for v in local.values()) / len(local))
            rod = None
        m, com, inertia = _mass_of(name, masses.get(name), local, pose, pts, default_com, rod)
        bodies.append(Body(name, local, mass=m, com=com, inertia=inertia, guess=pose))
    frame_body = Body(frame, {p: pts[p] for p in gnd})
    single: Any = drv[0] if len(drv) == 1 else tuple(drv)
    try:
        mech0 = Mechanism(frame_body, tuple(bodies), tuple(joints), single)
        positions = tuple(_drawn_position(mech0, d, pose_of) for d in drv)
        drawing = Drawing(pts, poses, positions)
        mech = Mechanism(frame_body, tuple(bodies), tuple(joints), single, drawing=drawing)
        mech.validate()
    except StructureError as exc:
        raise StructureError(f"drawn mechanism: {exc}") from None
    mech = mech.with_branches(**_branches(mech, scale))
    _round_trip(mech, scale)
    return mech


def _gear_pairs(gears: dict[str, Any], frame: str, pose_of: Any, links: set[str]
                ) -> list[Joint]:
    """The gear pairs, their phase taken from the drawn angles of the gears and carrier."""
    out: list[Joint] = []
    for key, spec in gears.items():
        if not isinstance(spec, Mapping):
            raise ParameterError(f"gears.{key}", spec, "must be a mapping (a, b, teeth or "
                                 "radii, ...)")
        spec = dict(spec)
        for side in ("a", "b"):
            if spec.get(side) not in links:
                raise ParameterError(f"gears.{key}.{side}", spec.get(side),
                                     f"must be a link; known: {sorted(links)}")
        carrier = spec.get("carrier") or frame
        if carrier != frame and carrier not in links:
            raise ParameterError(f"gears.{key}.carrier", carrier,
                                 f"must be a link or the frame; links: {sorted(links)}")
        try:
            pair = GearPair(str(key), **{**spec, "carrier": carrier})
        except TypeError as exc:
            raise ParameterError(f"gears.{key}", sorted(spec), f"unknown key ({exc})") from None
        va, vb = pair.teeth if pair.teeth is not None else pair.radii  # type: ignore[misc]
        s = -1.0 if pair.internal else 1.0
        tc = pose_of(carrier)[2]
        offset = (pose_of(pair.b)[2] - tc) + s * va / vb * (pose_of(pair.a)[2] - tc)
        out.append(dataclasses.replace(pair, offset=offset))
    return out


def _drawn_position(mech: Mechanism, d: Crank | Linear, pose_of: Any) -> float:
    """The driver coordinate of ``d`` in the drawing (crank angle [rad] or slide [m])."""
    j = mech.joint(d.joint)
    pa, pb = pose_of(j.a), pose_of(j.b)
    if isinstance(d, Crank):
        return pb[2] - pa[2]
    qa, pbl, ang = mech.joint_geometry(j)
    Q = _rot(pa[2], qa)
    P = _rot(pb[2], pbl)
    u = (_cos(pa[2] + ang), _sin(pa[2] + ang))
    return (pb[0] + P[0] - pa[0] - Q[0]) * u[0] + (pb[1] + P[1] - pa[1] - Q[1]) * u[1]

