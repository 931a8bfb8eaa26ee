"""The mechanism drawn to scale, frame by frame: one scene for the HTML report, GIF/MP4 and plots.

A :class:`Scene` is a list of :class:`Shape` (polylines, polygons, circles) in world
coordinates [m], each either static (``xy`` of shape ``(k, 2)``) or moving (``(k, 2, n)``: one
set of vertices per frame, positions last). The scene knows nothing of how it is drawn: the
report's SVG and its viewer script (:mod:`linkwork.plot.html`) and matplotlib (:func:`draw`,
:func:`animate`) render the same shapes, so every picture of a mechanism shows the same thing.

Builders read results by their attributes (no model is imported at run time):

* :func:`planar_scene` -- any mechanism of the planar engine from its
  :class:`~linkwork.planar.Kinematics`: bodies as the polygons of their named points, each joint
  by the shape its type supplies (:data:`JOINT_SHAPES`, or a ``scene_shapes(ctx)`` method of
  the joint class), ground pivots, guides and slots, the paths of the named points (and of any
  other point on request: coupler curves), the instant centres of velocity on request;
* :func:`sine_press_scene` -- paper 000's press in both modes, side by side;
* :func:`swashplate_scene` -- paper 003's drive in a side view and a view along the rotor axis.

Instant centres (:func:`instant_centres`) are found from the bodies' velocities: the centre
``I_ij`` of bodies i and j is the point whose velocity is the same in both,
``P = (-c_y, c_x) / (omega_i - omega_j)`` with ``c`` the difference of the two bodies' velocity
fields at the origin; centres of bodies that translate relative to each other are at infinity
(NaN). The three centres of any three bodies are collinear (Aronhold-Kennedy), which the tests
check independently.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
import subprocess
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from linkwork.errors import ExternalToolError, ParameterError
from linkwork.outputs import atomic_path
from linkwork.plot._base import Figure, axes_or_new, pyplot, text
from linkwork.plot.planar import named_point_paths

if TYPE_CHECKING:
    from linkwork.planar.kinematics import Kinematics

__all__ = ["FORCE_ROLES", "JOINT_SHAPES", "MAX_ANIMATION_FRAMES", "MAX_ANIMATION_PIXELS",
           "DrawContext", "Scene", "Shape", "Timing", "animate", "crank_slider_scene",
           "cylinder_parts", "damper_parts", "draw", "driver_readouts", "force_arrow",
           "gear_shapes", "inclined_slot_scene", "instant_centres", "is_cylinder",
           "load_shapes", "mechanism_figure", "planar_scene", "sine_press_scene",
           "spring_zigzag", "swashplate_scene", "target_shapes", "torque_arrow", "with_shapes"]

#: Roles of shapes (the CSS class in the report; the matplotlib style in :func:`draw`).
ROLES = ("axis", "path", "range", "guide", "slot", "gear", "spring", "damper", "link",
         "ground", "block", "barrel", "rod", "weight", "pin", "mesh", "tracer", "load", "target",
         "centre")

#: Roles of the force elements and loads (one switch in the report's player shows or hides them).
FORCE_ROLES = ("range", "spring", "damper", "load")

TWO_PI = 2.0 * math.pi

#: Most frames an animation file (GIF, MP4) holds, and the largest picture it has [pixels].
MAX_ANIMATION_FRAMES = 180
MAX_ANIMATION_PIXELS = (960, 720)


@dataclass(frozen=True)
class Shape:
    """One drawn element of a scene.

    Attributes
    ----------
    kind : {"polyline", "polygon", "circle"}
        An open line, a closed outline (filled), or circles (one per vertex).
    role : str
        What it shows (:data:`ROLES`): link, pin, ground, guide, slot, block, path, tracer,
        centre, weight, axis; the force elements and loads (:data:`FORCE_ROLES`): spring,
        damper, load (an arrow), range (where a load acts); target (a synthesis task's
        points and poses); gear (pitch circles, spokes, an internal gear's rim), mesh (the
        pitch point); barrel, rod (a hydraulic cylinder).
    name : str
        What it is, for people and tests (``"crank"``, ``"joint A"``, ``"path coupler.P"``,
        ``"I13"``).
    xy : ndarray
        World coordinates [m]: ``(k, 2)`` static, or ``(k, 2, n)`` one set per frame; NaN where
        a vertex is undefined (an unassembled frame, a centre at infinity).
    size : float
        Circle radius, or the width of a wide line (guide, slot) [m]; 0: a thin line.
    label : str
        Text drawn beside the shape (circles: beside the first vertex).
    colour : int
        Palette index (the body's), or -1 for the role's own colour.
    """

    kind: str
    role: str
    name: str
    xy: np.ndarray
    size: float = 0.0
    label: str = ""
    colour: int = -1

    @property
    def moving(self) -> bool:
        """True if the shape has vertices per frame."""
        return bool(self.xy.ndim == 3)

    def at(self, k: int) -> np.ndarray:
        """Vertices ``(k, 2)`` [m] at frame ``k`` (the static ones for a static shape)."""
        return self.xy[:, :, k] if self.moving else self.xy


@dataclass(frozen=True)
class Timing:
    """When the real motion reaches each frame of a scene (machine dynamics: a crank that does
    not turn at a constant speed), for playback in real time.

    Attributes
    ----------
    label : str
        What motion it is (``"1.5 kW induction: δ = 0.1"``).
    t : ndarray (n,)
        Time at each frame from the first frame [s], non-decreasing.
    speed : ndarray (n,)
        Driver speed at each frame [rad/s or m/s].
    span : float
        Time of one loop of the animation [s]: the period of a whole turn, or from the first
        to the last frame.
    unit : str
        SI unit of ``speed`` (``"rad/s"``: shown in rpm, ``"m/s"``); default the scene's.
    """

    label: str
    t: np.ndarray
    speed: np.ndarray
    span: float
    unit: str = ""


@dataclass(frozen=True)
class Scene:
    """A mechanism drawn over the frames of a cycle.

    Attributes
    ----------
    title : str
    positions : ndarray (n,)
        Driver position of each frame [rad, or m for a linear driver].
    coordinate : str
        Name of the driver coordinate (``"φ1"``, ``"s1"``, ``"φ"``).
    unit : str
        Its SI unit (``"rad"`` or ``"m"``); shown in deg or mm.
    valid : ndarray of bool (n,)
        Frames where the mechanism is assembled (others are skipped by the animation).
    shapes : tuple of Shape
    periodic : bool
        The frames cover a whole turn (the animation wraps; diagrams map positions modulo 2 pi).
    speed : float
        Driver speed [rad/s or m/s] (real-time playback); 0 where not known.
    notes : tuple of str
        What the drawing leaves out or where it cannot show the mechanism.
    timings : tuple of Timing
        The real motions the animation can be played at in real time (:meth:`timed`).
    readouts : tuple of (label, unit, values)
        Quantities shown beside the position at every frame, ``values`` ``(n,)`` in the display
        ``unit`` (several drivers: each driver's coordinate, in deg or mm).
    """

    title: str
    positions: np.ndarray
    coordinate: str
    unit: str
    valid: np.ndarray
    shapes: tuple[Shape, ...]
    periodic: bool = False
    speed: float = 0.0
    notes: tuple[str, ...] = ()
    timings: tuple[Timing, ...] = ()
    readouts: tuple[tuple[str, str, np.ndarray], ...] = ()

    @property
    def n(self) -> int:
        """Number of frames."""
        return int(self.positions.shape[0])

    @property
    def display(self) -> tuple[str, float]:
        """Display unit of the driver coordinate and the factor from SI (deg or mm; a
        position's index along several drivers' path: no unit)."""
        if self.unit == "":
            return ("", 1.0)
        return ("deg", 180.0 / math.pi) if self.unit == "rad" else ("mm", 1e3)

    def shape(self, name: str) -> Shape:
        """The shape called ``name`` (KeyError if none)."""
        for s in self.shapes:
            if s.name == name:
                return s
        raise KeyError(name)

    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` [m] over every shape and frame (circles' radii in)."""
        lo = np.array([np.inf, np.inf])
        hi = -lo
        for s in self.shapes:
            pts = s.xy if not s.moving else s.xy[:, :, self.valid]
            if pts.size == 0:
                continue
            p = np.moveaxis(pts, 1, -1).reshape(-1, 2) if s.moving else pts.reshape(-1, 2)
            ok = np.all(np.isfinite(p), axis=1)
            if s.role == "centre" or not ok.any():
                continue  # centres may lie far away: they do not set the scale
            r = s.size if s.kind == "circle" else 0.5 * s.size
            lo = np.minimum(lo, p[ok].min(axis=0) - r)
            hi = np.maximum(hi, p[ok].max(axis=0) + r)
        if not np.all(np.isfinite(lo)):
            return (-1.0, -1.0, 1.0, 1.0)
        return (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))

    def timed(self, label: str, phi: np.ndarray, t: np.ndarray, speed: np.ndarray,
              period: float) -> Scene:
        """The scene with one more real motion to play it at: the crank angles ``phi`` [rad]
        of one turn (increasing, less than 2 pi apart), the time ``t`` [s] and the crank speed
        ``speed`` [rad/s] there, and the ``period`` of the turn [s] (a steady state of
        :mod:`linkwork.machine`). The time and speed of each frame are interpolated over the
        turn (linearly, periodic); times count from the first frame.

        Raises
        ------
        ParameterError
            The scene's driver is not a crank, or ``phi`` does not increase within one turn.
        """
        p = np.asarray(phi, dtype=float)
        tt = np.asarray(t, dtype=float)
        w = np.asarray(speed, dtype=float)
        if self.unit != "rad":
            raise ParameterError("scene", self.coordinate, "a real motion over crank angles "
                                 "needs a crank-driven scene")
        if p.ndim != 1 or p.size < 2 or not (np.all(np.diff(p) > 0)
                                              and p[-1] - p[0] < TWO_PI):
            raise ParameterError("phi", p.size, "must increase over less than one turn")
        rel_p = np.append(p - p[0], TWO_PI)
        t_p = np.append(tt - tt[0], float(period))
        w_p = np.append(w, w[0])
        rel = np.mod(self.positions - p[0], TWO_PI)
        at = np.interp(rel, rel_p, t_p)
        frame_t = np.mod(at - at[0], float(period)) if self.n else at
        if self.n > 1 and not self.periodic:  # a range less than a turn: run through it
            frame_t = np.maximum.accumulate(frame_t)
        span = float(period) if self.periodic else float(frame_t[-1]) + float(
            np.median(np.diff(frame_t)) if self.n > 1 else 0.0)
        timing = Timing(label, frame_t, np.interp(rel, rel_p, w_p), span)
        return replace(self, timings=(*self.timings, timing))

    def take(self, frames: np.ndarray) -> Scene:
        """The scene at the frames ``frames`` (indices) only."""
        idx = np.asarray(frames, dtype=int)
        shapes = tuple(replace(s, xy=s.xy[:, :, idx]) if s.moving else s for s in self.shapes)
        timings = tuple(replace(tm, t=tm.t[idx], speed=tm.speed[idx]) for tm in self.timings)
        readouts = tuple((a, u, v[idx]) for a, u, v in self.readouts)
        return replace(self, positions=self.positions[idx], valid=self.valid[idx],
                       shapes=shapes, timings=timings, readouts=readouts)

    def frames(self, most: int) -> np.ndarray:
        """At most ``most`` frame indices spread evenly over the cycle (all if fewer); a
        periodic scene whose last frame repeats the first leaves that one out."""
        n = self.n
        last = n
        if self.periodic and n > 1 and abs(self.positions[-1] - self.positions[0]
                                           - 2 * math.pi) < 1e-9:
            last = n - 1
        if last <= most:
            return np.arange(last)
        return np.unique(np.round(np.linspace(0, last - 1, most)).astype(int))


# ---------------------------------------------------------------------------------------------
# the planar engine


@dataclass(frozen=True)
class DrawContext:
    """What a joint's shape function needs: the kinematics, the characteristic size of the
    drawing and the body colours.

    Attributes
    ----------
    kin : Kinematics
    size : float
        Extent of the mechanism over the cycle [m]; pins, blocks and guides scale with it.
    colours : dict
        Body name -> palette index (the frame: -1).
    """

    kin: Any
    size: float
    colours: dict[str, int] = field(default_factory=dict)

    @property
    def mechanism(self) -> Any:
        return self.kin.mechanism

    @property
    def pin(self) -> float:
        """Radius of a drawn pin [m]."""
        return 0.012 * self.size

    def world(self, body: str, local: Any) -> np.ndarray:
        """Points ``local`` ``(k, 2)`` of ``body``'s frame in world coordinates: ``(k, 2)`` for
        the frame, ``(k, 2, n)`` for a moving body [m]."""
        pts = np.asarray(local, dtype=float).reshape(-1, 2)
        kin = self.kin
        i = kin.bodies.index(body)
        if i == 0:
            return pts
        c, s = np.cos(kin.theta[i]), np.sin(kin.theta[i])
        px, py = pts[:, :1], pts[:, 1:]
        return np.stack([kin.x[i] + c * px - s * py, kin.y[i] + s * px + c * py], axis=1)

    def full(self, v: np.ndarray) -> np.ndarray:
        """``v`` of shape ``(2,)`` (static) or ``(2, n)`` as ``(2, n)``."""
        return v if v.ndim == 2 else np.broadcast_to(v[:, None], (2, self.kin.n))

    def direction(self, body: str, angle: float) -> np.ndarray:
        """Unit vector at ``angle`` [rad] in ``body``'s frame, in world axes: ``(2,)`` or
        ``(2, n)``."""
        i = self.kin.bodies.index(body)
        if i == 0:
            return np.array([math.cos(angle), math.sin(angle)])
        th = self.kin.theta[i] + angle
        return np.stack([np.cos(th), np.sin(th)])


def _band(ctx: DrawContext, joint: Any, role: str, width: float) -> Shape:
    """The line of a prismatic or pin-in-slot joint on its body a, over the stretch the point
    of b travels along it (plus a margin): a wide line, static on the frame."""
    mech = ctx.mechanism
    qa, pb, ang = mech.joint_geometry(joint)
    q = ctx.full(ctx.world(joint.a, [qa])[0])
    u = ctx.full(ctx.direction(joint.a, ang))
    p = ctx.full(ctx.world(joint.b, [pb])[0])
    t = np.sum((p - q) * u, axis=0)
    t = t[np.isfinite(t)]
    lo, hi = (float(t.min()), float(t.max())) if t.size else (0.0, 0.0)
    pad = max(0.15 * (hi - lo), 0.06 * ctx.size)
    ends = np.array([lo - pad, hi + pad])
    xy = q[None, :, :] + ends[:, None, None] * u[None, :, :]
    if joint.a == mech.frame.name:  # on the frame: static
        xy = xy[:, :, 0]
    kind = "slot" if role == "slot" else "guide"
    return Shape("polyline", role, f"{kind} {joint.name}", xy, size=width,
                 colour=ctx.colours.get(joint.a, -1))


def _revolute_shapes(joint: Any, ctx: DrawContext) -> list[Shape]:
    mech = ctx.mechanism
    qa, pb, _ = mech.joint_geometry(joint)
    frame = mech.frame.name
    on_b = joint.b != frame
    xy = ctx.world(joint.b, [pb]) if on_b else ctx.world(joint.a, [qa])
    out = [Shape("circle", "pin", f"joint {joint.name}", xy, size=ctx.pin,
                 label=joint.name)]
    if frame in (joint.a, joint.b):
        out.insert(0, _ground(ctx.world(frame, [qa if joint.a == frame else pb])[0], ctx,
                              joint.name))
    return out


def _ground(at: np.ndarray, ctx: DrawContext, name: str) -> Shape:
    """A ground pivot: a triangle under the point and the hatched base."""
    h = 2.5 * ctx.pin
    x, y = float(at[0]), float(at[1])
    tri = np.array([[x, y], [x - h, y - 1.6 * h], [x + h, y - 1.6 * h]])
    return Shape("polygon", "ground", f"ground {name}", tri)


def is_cylinder(joint: Any) -> bool:
    """A prismatic joint between the bodies ``<name>_barrel`` and ``<name>_rod`` (a linear
    actuator of :func:`linkwork.planar.sketch`: its slide is the pin-to-pin length)."""
    return (getattr(joint, "code", "") == "P" and joint.a == f"{joint.name}_barrel"
            and joint.b == f"{joint.name}_rod")


def cylinder_parts(start: np.ndarray, end: np.ndarray, width: float
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A hydraulic cylinder between its barrel's pivot ``start`` and its rod's pin ``end``
    ``(2, n)`` [m]: the barrel (a tube from ``start`` along the axis), the rod (from ``end``
    back into the barrel) and the piston (across the axis at the rod's inner end), each
    ``(k, 2, n)``. The barrel's and the rod's lengths are fixed (they are rigid), taken from
    the shortest and longest pin-to-pin length over the positions so that the piston stays
    inside the barrel wherever the cylinder is at least as long closed as its stroke."""
    length, u, v = _along(start, end)
    ok = length[np.isfinite(length)]
    lo, hi = (float(ok.min()), float(ok.max())) if ok.size else (1.0, 1.0)
    barrel, margin = 0.92 * lo, 0.04 * lo
    shortest = hi - barrel + margin   # the piston short of the barrel's end when longest
    longest = lo - margin             # and off its bottom when shortest
    rod = 0.5 * (shortest + longest) if shortest <= longest else longest
    piston = end - rod * u
    return (np.stack([start, start + barrel * u]), np.stack([end, piston]),
            np.stack([piston - 0.42 * width * v, piston + 0.42 * width * v]))


def _cylinder_shapes(joint: Any, ctx: DrawContext) -> list[Shape]:
    """A cylinder drawn as barrel, rod and piston (:func:`cylinder_parts`)."""
    mech = ctx.mechanism
    qa, pb, _ = mech.joint_geometry(joint)
    start = ctx.full(ctx.world(joint.a, [qa])[0])
    end = ctx.full(ctx.world(joint.b, [pb])[0])
    length = np.hypot(*(end - start))
    scale = float(np.nanmin(length)) if np.any(np.isfinite(length)) else ctx.size
    width = min(0.1 * scale, 0.05 * ctx.size)
    barrel, rod, piston = cylinder_parts(start, end, width)
    return [Shape("polyline", "barrel", f"barrel {joint.name}", barrel, size=width,
                  colour=ctx.colours.get(joint.a, -1)),
            Shape("polyline", "rod", f"rod {joint.name}", rod, size=0.38 * width,
                  colour=ctx.colours.get(joint.b, -1)),
            Shape("polyline", "rod", f"piston {joint.name}", piston, size=0.25 * width,
                  colour=ctx.colours.get(joint.b, -1))]


def _prismatic_shapes(joint: Any, ctx: DrawContext) -> list[Shape]:
    if is_cylinder(joint):
        return _cylinder_shapes(joint, ctx)
    mech = ctx.mechanism
    _, pb, ang = mech.joint_geometry(joint)
    guide = _band(ctx, joint, "guide", 0.05 * ctx.size)
    centre = ctx.full(ctx.world(joint.b, [pb])[0])
    u = ctx.full(ctx.direction(joint.a, ang))
    v = np.stack([-u[1], u[0]])
    length = float(getattr(joint, "length", 0.0)) or 0.09 * ctx.size
    half_l, half_w = 0.5 * length, 0.035 * ctx.size
    corners = [centre + sl * half_l * u + sw * half_w * v
               for sl, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    block = Shape("polygon", "block", f"block {joint.name}", np.stack(corners),
                  colour=ctx.colours.get(joint.b, -1))
    return [guide, block]


def _slot_shapes(joint: Any, ctx: DrawContext) -> list[Shape]:
    mech = ctx.mechanism
    _, pb, _ = mech.joint_geometry(joint)
    r = max(float(getattr(joint, "radius", 0.0)), ctx.pin)
    slot = _band(ctx, joint, "slot", 2.6 * r)
    pin = Shape("circle", "pin", f"joint {joint.name}", ctx.world(joint.b, [pb]), size=r,
                label=joint.name)
    return [slot, pin]


def gear_shapes(ctx: DrawContext, name: str, a: str, centre_a: Any, ra: float, b: str,
                centre_b: Any, rb: float, internal: bool = False) -> list[Shape]:
    """A gear pair drawn as in kinematic schemes: each gear's pitch circle (b's named ``joint
    <name>``, a's ``gear <name> <a>``) with two spokes turning with it (``spokes <name>
    <gear>``), an internal gear's rim outside its pitch circle (``rim <name>``), and the pitch
    point where the circles touch (``mesh <name>``, labelled). ``centre_a``, ``centre_b``: the
    gears' centres in their own frames [m]; ``ra``, ``rb``: pitch radii [m]."""
    oa = ctx.full(ctx.world(a, [centre_a])[0])
    ob = ctx.full(ctx.world(b, [centre_b])[0])
    _, e, _ = _along(oa, ob)
    pitch = oa + ra * (-1.0 if internal else 1.0) * e  # on the line of centres, r_a from a's
    out: list[Shape] = []
    for gear, centre, r, label in ((a, oa, ra, f"gear {name} {a}"), (b, ob, rb, f"joint {name}")):
        colour = ctx.colours.get(gear, -1)
        out.append(Shape("circle", "gear", label, _still(ctx, centre[None]), size=r,
                         colour=colour))
        out.append(Shape("polyline", "gear", f"spokes {name} {gear}",
                         _spokes(ctx, gear, centre, 0.85 * r), colour=colour))
    if internal:
        t = np.linspace(0.0, 2 * math.pi, 73)
        ring = ob[None] + 1.1 * rb * np.stack([np.cos(t), np.sin(t)], axis=1)[:, :, None]
        out.append(Shape("polyline", "gear", f"rim {name}", _still(ctx, ring), size=0.2 * rb,
                         colour=ctx.colours.get(b, -1)))
    out.append(Shape("circle", "mesh", f"mesh {name}", _still(ctx, pitch[None]),
                     size=0.5 * ctx.pin, label=name))
    return out


def _still(ctx: DrawContext, xy: np.ndarray) -> np.ndarray:
    """``xy`` ``(k, 2, n)`` as static vertices ``(k, 2)`` where they do not move (a gear on a
    frame pivot), so that the drawing carries them once."""
    finite = xy[:, :, np.all(np.isfinite(xy), axis=(0, 1))]
    if finite.shape[-1] and float(np.max(np.ptp(finite, axis=-1))) <= 1e-12 * ctx.size:
        return finite[:, :, 0]
    return xy


def _spokes(ctx: DrawContext, body: str, centre: np.ndarray, r: float) -> np.ndarray:
    """Two diameters of a gear at right angles, turning with ``body``: (5, 2, n)."""
    u = ctx.full(ctx.direction(body, 0.0))
    w = np.stack([-u[1], u[0]])
    return np.stack([centre + r * u, centre - r * u, centre, centre + r * w, centre - r * w])


#: The shape of each joint type, by its one-letter code (:attr:`Joint.code`): a function
#: ``(joint, ctx: DrawContext) -> list[Shape]``. A joint class may instead supply its own
#: ``scene_shapes(ctx)`` method (used first), so that a new joint type (a gear pair, a cylinder)
#: draws itself without changes here.
JOINT_SHAPES: dict[str, Callable[[Any, DrawContext], list[Shape]]] = {
    "R": _revolute_shapes,
    "P": _prismatic_shapes,
    "S": _slot_shapes,
}


# ---------------------------------------------------------------------------------------------
# force elements and loads (planar.forces), drawn from their evaluation on the motion

#: Drawn size of the force elements, in fractions of the mechanism's extent: a spring's coil
#: half-width and number of zigzags, a damper's half-width, the longest load arrow, its head.
SPRING_WIDTH, SPRING_ZIGS = 0.018, 8
DAMPER_WIDTH = 0.02
ARROW_LENGTH, ARROW_HEAD = 0.16, 0.03


def _ends(ap: Any) -> tuple[np.ndarray, np.ndarray]:
    """The two ends ``(2, n)`` [m] of a spring or damper, on its bodies a and b: the points
    where its forces act (its wrenches, :class:`~linkwork.planar.forces.AppliedLoad`)."""
    by_body = {w.body: np.stack(np.broadcast_arrays(w.px, w.py)).astype(float)
               for w in ap.wrenches}
    return by_body[ap.load.a], by_body[ap.load.b]


def _along(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Length ``(n,)``, unit vector ``(2, n)`` from a to b and its left normal ``(2, n)``."""
    d = b - a
    length = np.hypot(d[0], d[1])
    with np.errstate(invalid="ignore", divide="ignore"):
        u = d / length
    return length, u, np.stack([-u[1], u[0]])


def spring_zigzag(a: np.ndarray, b: np.ndarray, width: float, zigs: int = SPRING_ZIGS
                  ) -> np.ndarray:
    """A spring drawn between the points ``a`` and ``b`` ``(2, n)`` [m]: straight ends of a
    tenth of its length each and ``zigs`` zigzags of half-width ``width`` [m] between them,
    vertices ``(zigs + 3, 2, n)`` (it stretches and shortens with the distance of its ends)."""
    _, _, v = _along(a, b)
    t = np.concatenate([[0.0, 0.1], 0.1 + 0.8 * (np.arange(1, zigs) / zigs), [0.9, 1.0]])
    side = np.concatenate([[0.0, 0.0], np.where(np.arange(1, zigs) % 2, 1.0, -1.0), [0.0, 0.0]])
    return (a[None] + t[:, None, None] * (b - a)[None]
            + (side * width)[:, None, None] * v[None])


def damper_parts(a: np.ndarray, b: np.ndarray, width: float) -> tuple[np.ndarray, np.ndarray]:
    """A dashpot between ``a`` and ``b`` ``(2, n)`` [m]: the cylinder (on a: a stem to its
    bottom and its open walls towards b; rigid, of fixed length) and the piston (on b: its rod
    and plate), each a polyline ``(k, 2, n)``. The plate stays inside the cylinder over the
    positions (the lengths are taken from the shortest and longest distance of the ends)."""
    length, u, v = _along(a, b)
    ok = length[np.isfinite(length)]
    lo, hi = (float(ok.min()), float(ok.max())) if ok.size else (1.0, 1.0)
    stem, rod = 0.1 * lo, 0.8 * lo
    wall = max(hi - 0.8 * lo, 0.3 * lo)               # the plate moves from 0.2 lo to hi - rod
    c0 = a + stem * u
    cyl = np.stack([a, c0, c0 + width * v, c0 + width * v + wall * u, c0 + width * v,
                    c0 - width * v, c0 - width * v + wall * u])
    plate = b - rod * u
    piston = np.stack([b, plate, plate + 0.8 * width * v, plate - 0.8 * width * v])
    return cyl, piston


def force_arrow(at: np.ndarray, f: np.ndarray, longest: float, head: float) -> np.ndarray:
    """Arrows ``(5, 2, n)`` [m] of the forces ``f`` ``(2, n)`` [N] pointing at the points
    ``at`` ``(2, n)`` (where they act), of length ``longest`` [m] at the largest force and in
    proportion below it (tail, tip, one barb, tip, the other barb); NaN where the force is zero
    (the load does not act there)."""
    mag = np.hypot(f[0], f[1])
    top = float(np.nanmax(mag)) if np.any(np.isfinite(mag)) else 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        u = f / mag
        length = longest * mag / top if top > 0 else np.zeros_like(mag)
    off = ~(mag > 1e-12 * top) if top > 0 else np.ones(mag.shape, dtype=bool)
    v = np.stack([-u[1], u[0]])
    h = np.minimum(head, 0.6 * length)
    tail = at - length * u
    xy = np.stack([tail, at, at - h * u + 0.5 * h * v, at, at - h * u - 0.5 * h * v])
    return np.where(off[None, None, :], np.nan, xy)


def torque_arrow(at: np.ndarray, mz: np.ndarray, radius: float, head: float) -> np.ndarray:
    """A couple ``mz`` ``(n,)`` [N m] as a three-quarter circle of ``radius`` [m] around
    ``at`` ``(2, n)`` with its head the way it turns (counter-clockwise positive), vertices
    ``(k, 2, n)``; NaN where the couple is zero."""
    top = float(np.nanmax(np.abs(mz))) if np.any(np.isfinite(mz)) else 0.0
    sign = np.where(mz < 0, -1.0, 1.0)
    t = np.linspace(0.0, 1.5 * math.pi, 19)[:, None] * sign[None, :]      # (k, n)
    arc = at[None] + radius * np.stack([np.cos(t), np.sin(t)], axis=1)   # (k, 2, n)
    end = arc[-1]
    tangent = np.stack([-np.sin(t[-1]), np.cos(t[-1])]) * sign           # along the turn
    normal = np.stack([-tangent[1], tangent[0]])
    barbs = [end - head * tangent + 0.5 * head * normal, end,
             end - head * tangent - 0.5 * head * normal]
    xy = np.concatenate([arc, np.stack(barbs)])
    off = ~(np.abs(mz) > 1e-12 * top) if top > 0 else np.ones(mz.shape, dtype=bool)
    return np.where(off[None, None, :], np.nan, xy)


def _moving_wrench(ap: Any, frame: str) -> Any:
    """The wrench a load exerts on its moving body (not its reaction on the frame)."""
    return next((w for w in ap.wrenches if w.body != frame), None)


def load_shapes(loads: Sequence[Any], ctx: DrawContext) -> tuple[list[Shape], list[Shape],
                                                                  list[str]]:
    """The force elements and loads of a cycle (``Dynamics.loads``, each an
    :class:`~linkwork.planar.forces.AppliedLoad` evaluated on the motion), drawn where they
    act: springs as zigzags and dampers as dashpots between their two points; point forces,
    slide forces and drags as arrows pointing at their point (each scaled to its own largest
    value, hidden where it is zero); couples as curved arrows; and where a load acts over
    part of the cycle only, that stretch of its point's path and, for a crank, the arc of the
    crank's turn over which it acts (role ``range``).

    Returns the shapes drawn under the bodies (springs, dampers, the crank's arcs), those
    drawn over them (the stretches of the paths, faint, and the arrows) and notes for the
    drawing.
    """
    mech = ctx.mechanism
    frame = mech.frame.name
    n = ctx.kin.n
    under: list[Shape] = []
    over: list[Shape] = []
    partial: list[tuple[str, np.ndarray]] = []
    for ap in loads:
        kind = ap.kind
        if kind in ("spring", "damper"):
            a, b = _ends(ap)
            if kind == "spring":
                under.append(Shape("polyline", "spring", f"spring {ap.name}",
                                   spring_zigzag(a, b, SPRING_WIDTH * ctx.size)))
            else:
                cyl, piston = damper_parts(a, b, DAMPER_WIDTH * ctx.size)
                under.append(Shape("polyline", "damper", f"damper {ap.name} cylinder", cyl))
                under.append(Shape("polyline", "damper", f"damper {ap.name} piston", piston))
            continue
        w = _moving_wrench(ap, frame)
        if w is None:
            continue
        value = np.broadcast_to(np.asarray(ap.value, dtype=float), (n,))
        active = np.abs(value) > 1e-12 * (float(np.nanmax(np.abs(value)))
                                          if np.any(np.isfinite(value)) else 0.0)
        at = np.stack(np.broadcast_arrays(w.px, w.py)).astype(float)
        if kind == "torque":
            i = ctx.kin.bodies.index(w.body)
            centre = np.stack([ctx.kin.x[i], ctx.kin.y[i]])
            over.append(Shape("polyline", "load", f"load {ap.name}",
                              torque_arrow(centre, value, 0.06 * ctx.size,
                                           ARROW_HEAD * ctx.size)))
        else:
            f = np.stack(np.broadcast_arrays(w.fx, w.fy)).astype(float)
            over.append(Shape("polyline", "load", f"load {ap.name}",
                              force_arrow(at, f, ARROW_LENGTH * ctx.size,
                                          ARROW_HEAD * ctx.size)))
        valid = np.asarray(ctx.kin.valid, dtype=bool)
        if active[valid].any() and not active[valid].all():
            partial.append((ap.name, active))
            if kind != "torque":  # over the bodies (a guide's block would hide it), faint
                xy = np.where(active[None, :], at, np.nan).T
                over.insert(0, Shape("polyline", "range", f"range {ap.name}", xy,
                                   size=0.035 * ctx.size))
    notes: list[str] = []
    if partial and mech.n_drivers == 1 and mech.driver.kind == "crank":
        under += _crank_arcs(ctx, partial)
    if over:
        notes.append("load arrows point at where the load acts, each scaled to its own largest "
                     "value, and are hidden where it is zero" + (
                         "; the shaded stretches of a path and the arcs at the crank: where a "
                         "load acts over part of the cycle" if partial else ""))
    return under, over, notes


def _crank_arcs(ctx: DrawContext, partial: list[tuple[str, np.ndarray]]) -> list[Shape]:
    """Arcs around the crank's pivot, outside the path of the crank's farthest point, over the
    crank angles where each load of ``partial`` acts (one ring per load)."""
    mech = ctx.mechanism
    joint = mech.joint(mech.driver.joint)
    frame = mech.frame.name
    if frame not in (joint.a, joint.b):
        return []
    crank = joint.b if joint.a == frame else joint.a
    qa, pb, _ = mech.joint_geometry(joint)
    pivot = ctx.world(frame, [qa if joint.a == frame else pb])[0]
    pts = ctx.world(crank, list(mech.body(crank).points.values()))
    if pts.ndim != 3:
        return []
    r = np.hypot(pts[:, 0] - pivot[0, None], pts[:, 1] - pivot[1, None])    # (k, n)
    far = int(np.argmax(np.nanmax(r, axis=1)))
    reach = float(np.nanmax(r[far]))
    if not reach > 0:
        return []
    direction = (pts[far] - pivot[:, None]) / r[far]
    out = []
    for k, (name, active) in enumerate(partial):
        ring = reach + (0.05 + 0.035 * k) * ctx.size
        xy = pivot[:, None] + ring * direction
        out.append(Shape("polyline", "range", f"range {name} (crank angles)",
                         np.where(active[None, :], xy, np.nan).T, size=0.012 * ctx.size))
    return out


def _hull(points: np.ndarray) -> tuple[np.ndarray, bool]:
    """Order of the outline of a body's points: the convex hull (closed: True), or, for points
    on one line, all of them along it (an open polyline: False)."""
    pts = np.asarray(points, dtype=float)
    if len(pts) < 3:
        return np.arange(len(pts)), False
    centre = pts.mean(axis=0)
    d = pts - centre
    span = float(np.max(np.hypot(d[:, 0], d[:, 1]))) or 1.0
    _, sv, vt = np.linalg.svd(d, full_matrices=False)
    if sv[-1] <= 1e-9 * span * math.sqrt(len(pts)):  # collinear: along the line
        return np.argsort(d @ vt[0]), False
    order = sorted(range(len(pts)), key=lambda i: (pts[i, 0], pts[i, 1]))

    def cross(o: int, a: int, b: int) -> float:
        return float((pts[a, 0] - pts[o, 0]) * (pts[b, 1] - pts[o, 1])
                     - (pts[a, 1] - pts[o, 1]) * (pts[b, 0] - pts[o, 0]))

    lower: list[int] = []
    upper: list[int] = []
    for i in order:  # Andrew's monotone chain
        while len(lower) >= 2 and cross(lower[-2], lower[-1], i) <= 0:
            lower.pop()
        lower.append(i)
    for i in reversed(order):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], i) <= 0:
            upper.pop()
        upper.append(i)
    return np.array(lower[:-1] + upper[:-1]), True


def instant_centres(kin: Kinematics) -> dict[tuple[int, int], np.ndarray]:
    """Instant centres of velocity of every pair of bodies over the cycle.

    Bodies are numbered as in ``kin.bodies`` (0 the frame). Returns ``{(i, j): xy}`` for
    ``i < j`` with ``xy`` of shape ``(2, n)`` [m]: the point whose velocity is the same as a
    point of body i and of body j, ``P = (-c_y, c_x) / (omega_i - omega_j)`` where ``c`` is
    the difference of the two velocity fields at the origin. NaN where the two bodies
    translate relative to each other (the centre at infinity) or where the driver does not
    move (all velocities zero), and at unassembled positions. Bodies joined by a revolute
    joint have their primary centre at the joint at every position (also where their relative
    angular velocity passes through zero and the formula is 0/0).
    """
    w = np.asarray(kin.omega, dtype=float)
    ux = kin.vx + w * kin.y  # velocity field of each body at the world origin
    uy = kin.vy - w * kin.x
    scale = np.nanmax(np.abs(w), axis=0, initial=0.0)  # (n,)
    out: dict[tuple[int, int], np.ndarray] = {}
    nb = w.shape[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        for i, j in itertools.combinations(range(nb), 2):
            dw = w[i] - w[j]
            cx, cy = ux[i] - ux[j], uy[i] - uy[j]
            tiny = np.abs(dw) <= 1e-9 * scale
            px = np.where(tiny, np.nan, -cy / dw)
            py = np.where(tiny, np.nan, cx / dw)
            out[(i, j)] = np.stack([px, py])
    mech = kin.mechanism
    for joint in mech.joints:
        if getattr(joint, "code", "") != "R":
            continue
        i, j = sorted((kin.bodies.index(joint.a), kin.bodies.index(joint.b)))
        qa, pb, _ = mech.joint_geometry(joint)
        pm = kin.point(joint.b, pb) if joint.b != mech.frame.name else kin.point(joint.a, qa)
        out[(i, j)] = np.stack([pm.x, pm.y])
    return out


def _centre_name(i: int, j: int) -> str:
    """Kennedy's numbering: the frame is body 1."""
    sep = "," if max(i, j) >= 9 else ""
    return f"I{i + 1}{sep}{j + 1}"


PointSpec = tuple[str, str | tuple[float, float]]


def _whole_turn(phi: np.ndarray) -> bool:
    """The angles cover a whole turn: from start to start + 360 deg, or to one step short of it
    (0, 1, ..., 359 deg)."""
    if phi.size < 3:
        return False
    step = float(np.median(np.abs(np.diff(phi))))
    return bool(phi[-1] - phi[0] >= 2 * math.pi - 1.01 * step - 1e-9)


def planar_scene(kin: Kinematics, *, paths: Sequence[PointSpec] | None = None,
                 centres: bool = False, title: str | None = None,
                 weights: Sequence[tuple[str, tuple[float, float], float, str]] = (),
                 loads: Sequence[Any] = ()) -> Scene:
    """The scene of a planar engine mechanism over the positions of ``kin``.

    Parameters
    ----------
    kin : Kinematics
        The cycle (``on_failure="nan"`` results are drawn where assembled).
    paths : sequence of (body, point), optional
        Points whose paths (coupler curves) are drawn, besides the named points that move:
        a named point or local coordinates (x, y) [m] of the body's frame.
    centres : bool
        Also draw the instant centres of velocity of every pair of bodies
        (:func:`instant_centres`), labelled in Kennedy's numbering (frame = 1).
    title : str, optional
        Default: the mechanism's frame-and-bodies summary.
    weights : sequence of (body, (x, y), radius, label)
        Round masses drawn on bodies (counterweights): centre in the body's frame [m] and
        radius [m].
    loads : sequence of AppliedLoad, optional
        The loads evaluated on this motion (``Dynamics.loads``): springs, dampers, force
        arrows and where each load acts (:func:`load_shapes`).
    """
    mech = kin.mechanism
    valid = np.asarray(kin.valid, dtype=bool)
    colours = {b.name: k for k, b in enumerate(mech.bodies)}
    colours[mech.frame.name] = -1
    # characteristic size: the extent of every named point over the cycle
    pts = [DrawContext(kin, 1.0).world(b.name, list(b.points.values()))
           for b in (mech.frame, *mech.bodies) if b.points]
    flat = np.concatenate([np.moveaxis(p, 1, -1).reshape(-1, 2) if p.ndim == 3 else p
                           for p in pts]) if pts else np.zeros((1, 2))
    flat = flat[np.all(np.isfinite(flat), axis=1)]
    size = float(np.hypot(*np.ptp(flat, axis=0))) if len(flat) else 1.0
    ctx = DrawContext(kin, size or 1.0, colours)
    shapes: list[Shape] = []
    notes: list[str] = []
    # point paths (under everything)
    drawn = named_point_paths(kin)
    extra = [p for p in (paths or ()) if (p[0], p[1]) not in drawn]
    for body, point in [*drawn, *extra]:
        pm = kin.point(body, point)
        label = point if isinstance(point, str) else "({:g}, {:g}) mm".format(
            *(1e3 * np.asarray(point, dtype=float)))
        xy = np.stack([pm.x, pm.y], axis=1)
        shapes.append(Shape("polyline", "path", f"path {body}.{label}", xy,
                            colour=colours.get(body, -1), label=f"{body}.{label}"))
        shapes.append(Shape("circle", "tracer", f"point {body}.{label}",
                            np.stack([pm.x, pm.y])[None], size=0.6 * ctx.pin,
                            colour=colours.get(body, -1)))
    under, over, load_notes = load_shapes(loads, ctx) if loads else ([], [], [])
    shapes += under
    notes += load_notes
    # bodies as the outlines of their named points
    for b in mech.bodies:
        local = np.array(list(b.points.values()), dtype=float).reshape(-1, 2)
        if len(local) < 2:
            continue
        order, closed = _hull(local)
        shapes.append(Shape("polygon" if closed else "polyline", "link", b.name,
                            ctx.world(b.name, local[order]), size=0.0,
                            colour=colours[b.name]))
    for on, centre, radius, label in weights:
        shapes.append(Shape("circle", "weight", f"weight {label}",
                            ctx.world(on, [centre]), size=radius, label=label,
                            colour=colours.get(on, -1)))
    # joints, by the shape their type supplies
    for joint in mech.joints:
        own = getattr(joint, "scene_shapes", None)
        fn = JOINT_SHAPES.get(getattr(joint, "code", ""))
        if callable(own):
            shapes += own(ctx)
        elif fn is not None:
            shapes += fn(joint, ctx)
        else:
            notes.append(f"joint {joint.name} ({type(joint).__name__}) has no drawing; "
                         "not shown")
    shapes += over
    if centres:
        far = 50.0 * ctx.size
        cx, cy = np.mean(flat, axis=0) if len(flat) else (0.0, 0.0)
        infinite: list[str] = []
        for (i, j), xy in instant_centres(kin).items():
            xy = np.where(np.hypot(xy[0] - cx, xy[1] - cy) > far, np.nan, xy)
            name = _centre_name(i, j)
            if not np.isfinite(xy).any():
                infinite.append(name)
            shapes.append(Shape("circle", "centre", name, xy[None], size=0.7 * ctx.pin,
                                label=name))
        legend = ", ".join(f"{k + 1} = {b}" for k, b in enumerate(kin.bodies))
        notes.append(f"instant centres I_ij of bodies {legend} (Aronhold-Kennedy: any three "
                     "are collinear); a centre farther than 50 times the mechanism's size is "
                     "not drawn" + (f" ({', '.join(infinite)} at infinity: relative "
                                    "translation)" if infinite else ""))
    if mech.n_drivers > 1:
        return _several_drivers(kin, title or "mechanism", valid, shapes, notes)
    crank = mech.driver.kind == "crank"
    phi = np.asarray(kin.phi1, dtype=float)
    periodic = crank and _whole_turn(phi)
    speed = float(np.nanmedian(np.abs(np.asarray(kin.omega1, dtype=float)))) if phi.size else 0.0
    return Scene(title=title or "mechanism", positions=phi,
                 coordinate="φ1" if crank else "s1", unit="rad" if crank else "m",
                 valid=valid, shapes=tuple(shapes), periodic=periodic,
                 speed=speed if math.isfinite(speed) else 0.0, notes=tuple(notes))


def driver_readouts(mech: Any, phi1: np.ndarray) -> tuple[tuple[str, str, np.ndarray], ...]:
    """Each driver's coordinate over the positions ``phi1`` ``(n_drivers, n)`` [rad or m] as
    ``(label, display unit, values)``: a crank's angle in deg, a linear driver's slide in mm
    (``"φ O1"``, ``"s boom_cyl"``)."""
    out = []
    for k, d in enumerate(mech.drivers):
        crank = d.kind == "crank"
        out.append((f"{'φ' if crank else 's'} {d.joint}", "deg" if crank else "mm",
                    np.asarray(phi1[k], dtype=float) * (180.0 / math.pi if crank else 1e3)))
    return tuple(out)


def _several_drivers(kin: Kinematics, title: str, valid: np.ndarray, shapes: list[Shape],
                     notes: list[str]) -> Scene:
    """The scene of a mechanism with several drivers: its frames are the positions along the
    drivers' path (numbered from 0), each driver's coordinate read out at every frame, and the
    real time of the path from the first driver that moves (``t = integral of ds / v``)."""
    mech = kin.mechanism
    phi = np.asarray(kin.phi1, dtype=float)
    w = np.broadcast_to(np.asarray(kin.omega1, dtype=float), phi.shape)
    n = phi.shape[-1]
    index = np.arange(n, dtype=float)
    timings: tuple[Timing, ...] = ()
    for k, d in enumerate(mech.drivers):
        ds = np.diff(phi[k])
        if not np.any(ds != 0):
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = ds * 0.5 * (1.0 / w[k, 1:] + 1.0 / w[k, :-1])
        if np.all(np.isfinite(dt)) and np.all(dt > 0):
            t = np.concatenate([[0.0], np.cumsum(dt)])
            step = float(np.median(dt))
            timings = (Timing(f"the drivers' speeds (driver {d.joint})", t, w[k].copy(),
                              float(t[-1] + step), d.field_units["omega1"]),)
        break
    notes.append("several drivers: the frames are the positions along their path, each "
                 "driver's coordinate read out beside the position")
    return Scene(title=title, positions=index, coordinate="position", unit="",
                 valid=valid, shapes=tuple(shapes), notes=tuple(notes), timings=timings,
                 readouts=driver_readouts(mech, phi))


def target_shapes(points: Any, *, size: float, angles: Any = None) -> list[Shape]:
    """A synthesis task's targets, static and numbered from 1: points ``(k, 2)`` [m] drawn as
    rings of radius ``size`` [m]; with ``angles`` ``(k,)`` [rad] they are poses, each with a
    line of length ``6 size`` along the pose's x axis (the coupler's orientation there)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    out: list[Shape] = []
    for i, p in enumerate(pts):
        if angles is not None:
            a = float(np.asarray(angles, dtype=float)[i])
            tip = p + 6.0 * size * np.array([math.cos(a), math.sin(a)])
            out.append(Shape("polyline", "target", f"pose {i + 1} axis", np.stack([p, tip])))
        out.append(Shape("circle", "target", f"target {i + 1}", p[None], size=size,
                         label=str(i + 1)))
    return out


def with_shapes(scene: Scene, shapes: Sequence[Shape], *, first: bool = False) -> Scene:
    """``scene`` with ``shapes`` added (over the others, or under them with ``first``)."""
    new = (*shapes, *scene.shapes) if first else (*scene.shapes, *shapes)
    return replace(scene, shapes=tuple(new))


# ---------------------------------------------------------------------------------------------
# closed forms


def _rect(centre: np.ndarray, u: np.ndarray, half_l: float, half_w: float) -> np.ndarray:
    """Corners ``(4, 2, ...)`` of a rectangle around ``centre`` ``(2, ...)`` along unit
    ``u`` ``(2, ...)``."""
    v = np.stack([-u[1], u[0]])
    return np.stack([centre + a * half_l * u + b * half_w * v
                     for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))])


def _crank_slider_shapes(idle: Any, prefix: str = "") -> tuple[list[Shape], float]:
    """Shapes of the offset crank-slider (crank AB, rod BC, slider C on the guide X = e
    parallel to +Y; crank axis A at the origin) and the drawing's characteristic size [m]."""
    phi = np.asarray(idle.phi1, dtype=float)
    L1 = float(np.asarray(idle.L1).ravel()[0])
    e = float(np.asarray(idle.X_C).ravel()[0])
    lam2 = float(np.asarray(idle.lambda2).ravel()[0])
    size = (lam2 + 2.0) * L1
    pin = 0.018 * size
    B = np.stack([idle.X_B, idle.Y_B])
    C = np.stack(np.broadcast_arrays(np.asarray(idle.X_C, float), np.asarray(idle.Y_C, float)))
    ymin, ymax = float(np.nanmin(idle.Y_C)), float(np.nanmax(idle.Y_C))
    bl = 0.09 * size
    up = np.stack([np.zeros_like(phi), np.ones_like(phi)])
    return [
        Shape("polyline", "guide", f"{prefix}guide", np.array([[e, ymin - bl], [e, ymax + bl]]),
              size=0.05 * size),
        Shape("polygon", "ground", f"{prefix}ground A", _tri(0.0, 0.0, 2.5 * pin)),
        Shape("polyline", "link", f"{prefix}crank", np.stack([np.zeros_like(B), B]), colour=0),
        Shape("polyline", "link", f"{prefix}rod", np.stack([B, C]), colour=1),
        Shape("polygon", "block", f"{prefix}slider C", _rect(C, up, bl / 2, 0.035 * size),
              colour=2),
        Shape("circle", "pin", f"{prefix}joint A", np.zeros((1, 2)), size=pin, label="A"),
        Shape("circle", "pin", f"{prefix}joint B", B[None], size=pin, label="B"),
        Shape("circle", "pin", f"{prefix}joint C", C[None], size=pin, label="C"),
        Shape("polyline", "path", f"path {prefix}C", C.T, colour=2),
    ], size


def _inclined_slot_shapes(working: Any, dx: float, size: float, prefix: str = ""
                          ) -> list[Shape]:
    """Shapes of the sine mechanism with an inclined slot, crank axis at (dx, 0): crank AB,
    the block at B in the ram's slot inclined at alpha, the ram sliding along x (its slot
    crosses the x axis at ``L1 - X3``)."""
    phi = np.asarray(working.phi1, dtype=float)
    L1 = float(np.asarray(working.L1).ravel()[0])
    alpha = float(np.asarray(working.alpha).ravel()[0])
    pin = 0.018 * size
    u = np.array([math.cos(alpha), math.sin(alpha)])
    reach = L1 / max(math.sin(alpha), 1e-3) + 0.08 * size
    Bw = np.stack([np.asarray(working.X_B) + dx, np.asarray(working.Y_B)])
    S = np.stack([L1 - np.asarray(working.X3) + dx, np.zeros_like(phi)])  # slot on the x axis
    slot = np.stack([S - reach * u[:, None], S + reach * u[:, None]])
    stroke = float(np.nanmax(working.X3) - np.nanmin(working.X3))
    ram_len = max(stroke + 2.0 * L1, 0.5 * size)
    ram = np.stack([S, S + np.array([[ram_len], [0.0]])])
    x_lo = float(np.nanmin(S[0])) - 0.05 * size
    return [
        Shape("polyline", "axis", f"{prefix}line of the ram",
              np.array([[x_lo - L1, 0.0], [x_lo + stroke + ram_len + L1, 0.0]])),
        Shape("polyline", "guide", f"{prefix}guide",
              np.array([[float(np.nanmax(S[0])) + 0.5 * L1 + reach * abs(u[0]), 0.0],
                        [float(np.nanmin(S[0])) + ram_len - 0.2 * L1, 0.0]]),
              size=0.05 * size),
        Shape("polygon", "ground", f"{prefix}ground A", _tri(dx, 0.0, 2.5 * pin)),
        Shape("polyline", "link", f"{prefix}ram", ram, colour=3),
        Shape("polyline", "slot", f"{prefix}slot", slot, size=2.6 * pin, colour=3),
        Shape("polyline", "link", f"{prefix}crank", np.stack([np.stack(
            [np.full_like(phi, dx), np.zeros_like(phi)]), Bw]), colour=0),
        Shape("polygon", "block", f"{prefix}block B",
              _rect(Bw, np.broadcast_to(u[:, None], Bw.shape), 0.045 * size, 0.025 * size),
              colour=1),
        Shape("circle", "pin", f"{prefix}joint A", np.array([[dx, 0.0]]), size=pin, label="A"),
        Shape("circle", "pin", f"{prefix}joint B", Bw[None], size=pin, label="B"),
    ]


def _closed_form_scene(title: str, phi: np.ndarray, shapes: list[Shape], valid: Any,
                       speed: float, notes: tuple[str, ...] = ()) -> Scene:
    ok = np.ones(phi.shape, dtype=bool) if valid is None else np.asarray(valid, dtype=bool)
    return Scene(title=title, positions=phi, coordinate="φ1", unit="rad",
                 valid=np.broadcast_to(ok, phi.shape).copy(), shapes=tuple(shapes),
                 periodic=_whole_turn(phi), speed=float(speed), notes=notes)


def crank_slider_scene(idle: Any, *, title: str = "offset crank-slider") -> Scene:
    """An offset crank-slider (:class:`~linkwork.models.crank_slider.CrankSliderResult` of one
    design over crank angles): crank AB, rod BC, slider C on its guide."""
    shapes, _ = _crank_slider_shapes(idle)
    phi = np.asarray(idle.phi1, dtype=float)
    return _closed_form_scene(title, phi, shapes, getattr(idle, "valid", None),
                              float(np.asarray(idle.omega1).ravel()[0]))


def inclined_slot_scene(working: Any, *, title: str = "sine mechanism") -> Scene:
    """A sine mechanism with an inclined slot (:class:`~linkwork.models.sine.InclinedSlotResult`
    of one design over crank angles): crank, block, slotted ram."""
    L1 = float(np.asarray(working.L1).ravel()[0])
    phi = np.asarray(working.phi1, dtype=float)
    return _closed_form_scene(title, phi, _inclined_slot_shapes(working, 0.0, 4.0 * L1), None,
                              float(np.asarray(working.omega1).ravel()[0]))


def sine_press_scene(idle: Any, working: Any, *, title: str = "press drive",
                     speed: float = 0.0) -> Scene:
    """Paper 000's press drive in both modes at the same crank angle, side by side.

    ``idle``: a :class:`~linkwork.models.crank_slider.CrankSliderResult` (left);
    ``working``: an :class:`~linkwork.models.sine.InclinedSlotResult` over the same crank
    angles (right).
    """
    shapes, size = _crank_slider_shapes(idle, "idle ")
    L1 = float(np.asarray(idle.L1).ravel()[0])
    e = float(np.asarray(idle.X_C).ravel()[0])
    alpha = float(np.asarray(working.alpha).ravel()[0])
    reach = L1 / max(math.sin(alpha), 1e-3) + 0.08 * size
    dx = max(L1, e) + 0.15 * size + 2.0 * L1 + reach * abs(math.cos(alpha))
    shapes += _inclined_slot_shapes(working, dx, size, "working ")
    return _closed_form_scene(
        title, np.asarray(idle.phi1, dtype=float), shapes, getattr(idle, "valid", None), speed,
        (f"left: idle mode (offset crank-slider); right: working mode (sine mechanism, slot at "
         f"α = {math.degrees(alpha):.4g} deg); both at the same crank angle φ1",))


def _tri(x: float, y: float, h: float) -> np.ndarray:
    return np.array([[x, y], [x - h, y - 1.6 * h], [x + h, y - 1.6 * h]])


def swashplate_scene(cycle: Any, A: np.ndarray, B: np.ndarray, *,
                     title: str = "swash-plate drive") -> Scene:
    """Paper 003's drive in two views, side by side: along ``x0`` (``y0`` to the right, the
    rotor axis ``z0`` up) and along the rotor axis (``x0`` right, ``y0`` up).

    ``cycle``: a :class:`~linkwork.models.swashplate.KinematicsResult`; ``A``, ``B``: the slide
    and disk points ``(n, 3)`` [m] over its angles (:func:`linkwork.models.swashplate.points`,
    with ``A_z = s``).
    """
    d = cycle.design
    phi = np.asarray(cycle.phi, dtype=float)
    R, r, alpha = float(d.R), float(d.r), float(d.alpha)
    size = 2.0 * max(R, r) + float(d.l)
    pin = 0.012 * size
    Ay, Az, By, Bz = A[:, 1], A[:, 2], B[:, 1], B[:, 2]
    z1 = float(np.mean(Bz + r * math.sin(alpha) * np.cos(phi)))  # disk centre height
    zc = np.array([math.cos(alpha), math.sin(alpha)])
    disk = np.array([[d.b, z1], [d.b, z1]]) + np.array([[-r], [r]]) * zc
    smin, smax = float(np.min(Az)), float(np.max(Az))
    slide_len = 0.35 * size
    drum_lo, drum_hi = smin - 0.05 * size, smax + slide_len
    side = [
        Shape("polyline", "axis", "rotor axis", np.array([[0.0, min(z1 - r, drum_lo) - 0.1 * size],
                                                          [0.0, drum_hi + 0.1 * size]])),
        Shape("polyline", "axis", "disk axis", np.array([[d.b, z1], [d.b, z1]])
              + np.array([[0.0], [0.25 * size]]) * np.array([-math.sin(alpha),
                                                            math.cos(alpha)])),
        Shape("polyline", "link", "disk (edge on)", disk, colour=0),
        Shape("polyline", "guide", "drum guides", np.array([[-R, drum_lo], [-R, drum_hi],
                                                            [R, drum_hi], [R, drum_lo]]),
              size=0.0),
        Shape("polyline", "link", "side rod", np.stack([np.stack([By, Bz]),
                                                        np.stack([Ay, Az])]), colour=1),
        Shape("polygon", "block", "side slide", _rect(
            np.stack([Ay, Az + 0.5 * slide_len]),
            np.stack([np.zeros_like(phi), np.ones_like(phi)]), 0.5 * slide_len, 0.03 * size),
            colour=2),
        Shape("circle", "pin", "side joint B", np.stack([By, Bz])[None], size=pin, label="B"),
        Shape("circle", "pin", "side joint A", np.stack([Ay, Az])[None], size=pin, label="A"),
        Shape("polyline", "path", "path side.A", np.stack([Ay, Az], axis=1), colour=2),
    ]
    dx = R + max(R, r) + 0.45 * size
    dz = 0.5 * (smin + smax)
    t = np.linspace(0.0, 2 * math.pi, 73)
    top = [
        Shape("polyline", "guide", "rotor pitch circle",
              np.stack([dx + R * np.sin(t), dz - R * np.cos(t)], axis=1)),
        Shape("polyline", "link", "disk rim (seen along the rotor axis)",
              np.stack([dx + d.a + r * np.sin(t), dz + d.b - r * math.cos(alpha) * np.cos(t)],
                       axis=1), colour=0),
        Shape("polyline", "link", "top rod", np.stack([
            np.stack([dx + B[:, 0], dz + By]), np.stack([dx + A[:, 0], dz + Ay])]), colour=1),
        Shape("circle", "pin", "top joint B", np.stack([dx + B[:, 0], dz + By])[None],
              size=pin, label="B"),
        Shape("circle", "block", "top slide A", np.stack([dx + A[:, 0], dz + Ay])[None],
              size=2 * pin, label="A", colour=2),
        Shape("circle", "pin", "rotor axis (top)", np.array([[dx, dz]]), size=0.5 * pin),
    ]
    return Scene(title=title, positions=phi, coordinate="φ", unit="rad",
                 valid=np.ones(phi.shape, dtype=bool), shapes=tuple(side + top),
                 periodic=_whole_turn(phi), speed=float(cycle.omega),
                 notes=("left: side view along x0 (y0 to the right, the rotor axis z0 up; the "
                        "disk is seen edge on and the rod foreshortened); right: view along "
                        "the rotor axis (x0 right, y0 up); one slide shown",))


# ---------------------------------------------------------------------------------------------
# matplotlib

#: matplotlib colours of the palette indices (the report's CSS uses the same)
PALETTE = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2",
           "#17becf", "#bcbd22", "#7f7f7f")


def _colour(s: Shape, default: str) -> str:
    return PALETTE[s.colour % len(PALETTE)] if s.colour >= 0 else default


def draw(ax: Any, scene: Scene, k: int, *, centres: bool = True) -> list[Any]:
    """Draw frame ``k`` of ``scene`` into matplotlib axes ``ax`` (lengths in mm); returns the
    artists. The frame's pose is left out (only static shapes) where it is not assembled."""
    from matplotlib.patches import Circle, Polygon

    artists: list[Any] = []
    ok = bool(scene.valid[k])
    for s in scene.shapes:
        if s.moving and not ok:
            continue
        if s.role == "centre" and not centres:
            continue
        xy = s.at(k) * 1e3
        if not np.all(np.isfinite(xy)) and s.kind != "polyline":
            continue
        if s.kind == "circle":
            for p in xy:
                face = {"pin": "white", "tracer": _colour(s, "k"), "weight": _colour(s, "0.3"),
                        "centre": "#ff00aa", "block": _colour(s, "0.5"), "gear": "none",
                        "mesh": "k"}.get(s.role, "white")
                c = Circle((p[0], p[1]), s.size * 1e3, facecolor=face,
                           edgecolor=_colour(s, "k") if s.role != "centre" else "#aa0077",
                           lw=1.0, alpha=0.5 if s.role == "weight" else 1.0, zorder=5)
                ax.add_patch(c)
                artists.append(c)
                if s.label and s.role in ("pin", "centre", "weight", "target", "mesh"):
                    artists.append(ax.annotate(text(s.label), (p[0], p[1]), fontsize=7,
                                               xytext=(4, 4), textcoords="offset points",
                                               zorder=6))
        elif s.kind == "polygon":
            fill = {"ground": "0.55", "block": _colour(s, "0.5"), "link": _colour(s, "0.5")}
            poly = Polygon(xy, closed=True, facecolor=fill.get(s.role, "0.8"),
                           edgecolor=_colour(s, "k") if s.role != "ground" else "0.3",
                           alpha=0.35 if s.role == "link" else 0.8, lw=1.5, zorder=3)
            ax.add_patch(poly)
            artists.append(poly)
        else:
            styles: dict[str, dict[str, Any]] = {
                "path": {"lw": 0.8, "ls": "--", "color": _colour(s, "0.4"), "zorder": 1},
                "axis": {"lw": 0.6, "ls": "-.", "color": "0.5", "zorder": 0},
                "guide": {"lw": 6 if s.size else 1.0, "color": "0.6", "alpha": 0.5,
                          "solid_capstyle": "butt", "zorder": 1},
                "slot": {"lw": 7, "color": _colour(s, "0.5"), "alpha": 0.3,
                         "solid_capstyle": "round", "zorder": 2},
                "range": {"lw": 7 if s.size else 3, "color": "#d97706", "alpha": 0.3,
                          "solid_capstyle": "butt", "zorder": 1},
                "spring": {"lw": 1.1, "color": "#2f6f3e", "zorder": 3},
                "damper": {"lw": 1.3, "color": "#6b4f2a", "zorder": 3},
                "load": {"lw": 1.4, "color": "#c2410c", "zorder": 6},
                "target": {"lw": 1.4, "color": "k", "zorder": 6},
                "gear": {"lw": 1.0, "color": _colour(s, "0.3"), "zorder": 2,
                         "alpha": 0.35 if s.size else 0.9},
                "barrel": {"lw": 8, "color": _colour(s, "0.4"), "alpha": 0.8,
                           "solid_capstyle": "butt", "zorder": 3},
                "rod": {"lw": 3, "color": _colour(s, "0.2"), "solid_capstyle": "butt",
                        "zorder": 4},
            }
            style = styles.get(s.role, {"lw": 3.0, "color": _colour(s, "k"), "zorder": 4,
                                        "solid_capstyle": "round"})
            (ln,) = ax.plot(xy[:, 0], xy[:, 1], **style)
            artists.append(ln)
    return artists


def _limits(ax: Any, scene: Scene) -> None:
    x0, y0, x1, y1 = (v * 1e3 for v in scene.bounds())
    pad = 0.06 * max(x1 - x0, y1 - y0, 1e-9)
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")


def mechanism_figure(scene: Scene, frame: int | None = None, ax: Any = None) -> Any:
    """The scene drawn at ``frame`` (default: the first assembled) into ``ax`` (None: a new
    figure), with its title and position: a :class:`linkwork.plot.Figure`."""
    ax = axes_or_new(ax, figsize=(7, 6))
    good = np.flatnonzero(scene.valid)
    k = int(good[0]) if frame is None and good.size else int(frame or 0)
    artists = draw(ax, scene, k)
    _limits(ax, scene)
    ax.set_title(text(f"{scene.title}: {_caption(scene, k)}"), fontsize=10)
    return Figure.of(ax, artists=artists)


def _caption(scene: Scene, k: int) -> str:
    unit, f = scene.display
    pos = (f"{scene.coordinate} {scene.positions[k]:.0f}" if not unit else
           f"{scene.coordinate} = {scene.positions[k] * f:.1f} {unit}")
    if scene.readouts:  # several drivers: their coordinates on a line of their own
        pos += "\n" + ", ".join(f"{label} = {vals[k]:.1f} {u}"
                                for label, u, vals in scene.readouts)
    return pos if scene.valid[k] else pos + ": not assembled"


def animate(scene: Scene, path: str | Path, *, frames: int = 120, fps: int = 20,
            size: tuple[int, int] = (640, 480), dpi: int = 100) -> Path:
    """Write the scene's animation to ``path``: a GIF (Pillow), or an MP4 (ffmpeg) by the
    suffix. At most :data:`MAX_ANIMATION_FRAMES` frames spread over the cycle (unassembled
    ones left out) and a picture of at most :data:`MAX_ANIMATION_PIXELS`; the file is written
    beside ``path`` and renamed when complete."""
    from matplotlib import animation

    plt = pyplot()
    p = Path(path)
    w = min(int(size[0]), MAX_ANIMATION_PIXELS[0])
    h = min(int(size[1]), MAX_ANIMATION_PIXELS[1])
    idx = scene.frames(max(1, min(int(frames), MAX_ANIMATION_FRAMES)))
    idx = idx[scene.valid[idx]]
    if idx.size == 0:
        idx = np.array([0])
    fig, ax = plt.subplots(figsize=(w / dpi, h / dpi), dpi=dpi)
    try:
        held: list[Any] = []

        def update(k: int) -> list[Any]:
            for a in held:
                a.remove()
            held[:] = draw(ax, scene, int(k))
            ax.set_title(text(f"{scene.title}\n{_caption(scene, int(k))}"), fontsize=9)
            return held

        _limits(ax, scene)
        fig.tight_layout()
        anim = animation.FuncAnimation(fig, update, frames=list(idx), blit=False)
        writer: Any
        if p.suffix.lower() == ".mp4":
            writer = animation.FFMpegWriter(fps=fps, codec="libx264",
                                            extra_args=["-pix_fmt", "yuv420p"])
        else:
            writer = animation.PillowWriter(fps=fps)
        with atomic_path(p) as tmp, _movie_writer_log() as said:
            try:
                anim.save(str(tmp), writer=writer, dpi=dpi)
            except (subprocess.CalledProcessError, OSError) as exc:
                if _interrupted(exc):  # Ctrl-C stops ffmpeg too; the writer's cleanup hid it
                    raise KeyboardInterrupt from None
                if not isinstance(writer, animation.FFMpegWriter):
                    raise
                last = [ln for m in said for ln in m.splitlines()
                        if ln.strip() and not ln.startswith("MovieWriter")]
                why = last[-1].strip() if last else str(exc)
                raise ExternalToolError(f"ffmpeg failed writing {p.name} ({why})") from None
    finally:
        plt.close(fig)
    return p


def _interrupted(exc: BaseException) -> bool:
    """A KeyboardInterrupt among the exceptions ``exc`` was raised while handling."""
    seen: BaseException | None = exc
    while seen is not None:
        if isinstance(seen, KeyboardInterrupt):
            return True
        seen = seen.__context__
    return False


class _Said(logging.Handler):
    """Keeps the messages of a logger (what ffmpeg printed, as matplotlib passes it on)."""

    def __init__(self) -> None:
        super().__init__(logging.DEBUG)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.messages.append(record.getMessage())


@contextlib.contextmanager
def _movie_writer_log() -> Iterator[list[str]]:
    """What matplotlib's movie writers log (ffmpeg's stderr when it fails), kept for the
    error's message instead of printed on the terminal."""
    log = logging.getLogger("matplotlib.animation")
    said = _Said()
    propagate = log.propagate
    log.addHandler(said)
    log.propagate = False
    try:
        yield said.messages
    finally:
        log.removeHandler(said)
        log.propagate = propagate
