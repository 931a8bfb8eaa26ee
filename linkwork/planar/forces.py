"""Loads of the planar engine: applied forces, force elements and load diagrams.

Everything that :func:`~linkwork.planar.dynamics.inverse_dynamics` takes as ``loads`` is
defined here and evaluated on the solved motion (:func:`apply`): each load becomes the forces
and couples it exerts on the moving bodies (and, where it is anchored to the frame, its
reaction on the frame, which enters the shaking force and moment), its power and, for a
spring, its stored energy. All of them enter the same applied-load vector as gravity and the
inertia loads, so they work with Coulomb friction in the joints (:mod:`~.friction`).

Loads given per position
------------------------
* :class:`PointForce` -- a force at a point of a body, frame axes.
* :class:`BodyTorque` -- a couple on a body.
* :class:`SlideForce` -- a force along the line of a prismatic or pin-in-slot joint, on its
  body ``b`` at the slider point (pin), its reaction on body ``a`` (a cylinder's force, a
  press's technological force between ram and bed).

Each value is a number, an array over the positions or a :class:`LoadDiagram`: a table over the
driver coordinate or over a slide's position, interpolated linearly, acting inside its range
(the table's first to last position; outside it zero, or an error when asked), always or
only while its coordinate increases or decreases (a press's force while the ram moves down).

Force elements (their force follows from the motion)
----------------------------------------------------
* :class:`Spring` -- linear spring between a point of body ``a`` and a point of body ``b``
  (either may be the frame): tension ``F = preload + k (L - L0)`` [N] (positive: it pulls the
  points together), stored energy ``V = preload (L - L0) + k (L - L0)^2 / 2`` [J] (zero at the
  free length ``L0``, so that ``dV/dt`` is the power the spring takes from the mechanism).
* :class:`Damper` -- viscous damper between two such points: tension ``F = c dL/dt``.
* :class:`Drag` -- a force opposing the absolute velocity ``v`` of a point: a Coulomb-like part
  of constant magnitude and a viscous part, ``F = -force v / sqrt(|v|^2 + w^2) - damping v``
  (the direction regularised over a band ``w`` of speeds 1e-9 of the driver's, as joint
  friction is: :data:`linkwork.planar.friction.SIGN_WIDTH`; zero at rest).

Power and energy
----------------
The power of a load is that of all the forces and couples it exerts on the moving bodies (the
frame does not move): ``P = sum F . v_point + M omega``. A spring's is ``-F dL/dt = -dV/dt``, a
damper's ``-c (dL/dt)^2 <= 0``, a drag's ``-(force |v|^2 / sqrt(|v|^2 + w^2) + damping |v|^2)``.
With them the driving power balances (``docs/forces.md``)::

    Q omega1 = dT/dt - sum P_loads - P_gravity + sum P_friction .
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import per_position, require_finite, require_point
from linkwork.errors import ParameterError, angle_ranges, format_angle_ranges
from linkwork.planar.friction import sign_widths
from linkwork.planar.kinematics import Kinematics
from linkwork.planar.model import Crank, Mechanism
from linkwork.planar.state import Arr

__all__ = [
    "AppliedLoad",
    "BodyTorque",
    "Damper",
    "Drag",
    "Load",
    "LoadDiagram",
    "PointForce",
    "SlideForce",
    "Spring",
    "Wrench",
    "apply",
]

PointRef = str | tuple[float, float]
Value = ArrayLike  # a number, an array over the positions, or a LoadDiagram


# ---------------------------------------------------------------------------------------------
# load diagrams
@dataclass(frozen=True)
class LoadDiagram:
    """A load given as a table over the driver coordinate or over a slide's position.

    Parameters
    ----------
    position : sequence of float
        The table's positions, strictly increasing: crank angles [rad] (``over="driver"`` with a
        crank; at most one turn, repeated every turn), a linear driver's slide [m], or the slide
        coordinate ``s`` [m] of the prismatic or pin-in-slot joint named by ``over``
        (:meth:`~linkwork.planar.Kinematics.slide`).
    value : sequence of float
        The load at each position (a force [N] or a couple [N m], by where it is used),
        interpolated linearly between them.
    over : str
        ``"driver"`` or the name of a prismatic or pin-in-slot joint.
    when : {"always", "increasing", "decreasing"}
        Acts at every position, or only where the coordinate does not decrease
        (``"increasing"``) or does not increase (``"decreasing"``: a press's force while the
        ram moves down, its slide coordinate decreasing). The positions where it is at rest
        (a dead centre, to 1e-9 of the driver's speed) count as both, so the force acts at the
        end of the stroke.
    outside : {"zero", "error"}
        Outside the diagram's range (its first to its last position): no load, or a
        :class:`~linkwork.errors.ParameterError` naming the positions where the analysis
        leaves the range while the load would act (no extrapolation).

    Example: a technological force rising from 0 to 8 kN over the last 20 mm of a ram's stroke
    down to ``s = -57.7 mm`` on its guide ``"guide"``, against the descent::

        LoadDiagram([-0.0577, -0.0477, -0.0377], [8e3, 5e3, 0.0], over="guide",
                    when="decreasing")
    """

    position: Sequence[float]
    value: Sequence[float]
    over: str = "driver"
    when: Literal["always", "increasing", "decreasing"] = "always"
    outside: Literal["zero", "error"] = "zero"

    def __post_init__(self) -> None:
        x = _table("position", self.position)
        y = _table("value", self.value)
        if x.size < 2:
            raise ParameterError("position", x.tolist(), "a diagram needs at least 2 positions")
        if y.size != x.size:
            raise ParameterError("value", f"{y.size} values", f"must give one value per "
                                 f"position ({x.size})")
        step = np.diff(x)
        if np.any(step <= 0):
            k = int(np.argmax(step <= 0)) + 1
            raise ParameterError(f"position[{k}]", float(x[k]), f"must increase strictly: "
                                 f"it must be > position[{k - 1}] = {float(x[k - 1]):g}")
        if not isinstance(self.over, str) or not self.over:
            raise ParameterError("over", self.over, "must be 'driver' or the name of a "
                                 "prismatic or pin-in-slot joint")
        if self.when not in ("always", "increasing", "decreasing"):
            raise ParameterError("when", self.when,
                                 "must be 'always', 'increasing' or 'decreasing'")
        if self.outside not in ("zero", "error"):
            raise ParameterError("outside", self.outside, "must be 'zero' (no load outside the "
                                 "diagram's range) or 'error' (no extrapolation)")
        object.__setattr__(self, "position", tuple(float(v) for v in x))
        object.__setattr__(self, "value", tuple(float(v) for v in y))

    @property
    def table_range(self) -> tuple[float, float]:
        """The diagram's range: the first and the last position of its table [rad or m], where
        the load can act."""
        return self.position[0], self.position[-1]

    def times(self, factor: float) -> LoadDiagram:
        """The same diagram with every value multiplied by ``factor`` (e.g. a component)."""
        f = float(require_finite("factor", factor))
        return replace(self, value=tuple(f * v for v in self.value))

    def check(self, mech: Mechanism, key: str = "diagram") -> None:
        """Refuse a coordinate the mechanism does not have (a joint that is not prismatic or
        pin-in-slot) and a crank-angle table longer than one turn; ``key`` prefixes the names."""
        if self.over == "driver":
            if mech.n_drivers > 1:
                raise ParameterError(f"{key}.over", "driver", f"the mechanism has "
                                     f"{mech.n_drivers} drivers: a diagram runs over one "
                                     "coordinate, give a slide (a prismatic joint) instead")
            span = self.position[-1] - self.position[0]
            if isinstance(mech.driver, Crank) and span > 2 * math.pi * (1 + 1e-12):
                raise ParameterError(f"{key}.position", f"{math.degrees(span):.6g} deg span",
                                     "a crank-angle diagram spans at most one turn (360 deg); "
                                     "it repeats every turn")
            return
        names = [j.name for j in mech.joints]
        if self.over not in names:
            raise ParameterError(f"{key}.over", self.over, f"must be 'driver' or a joint; "
                                 f"known: {names}")
        if not mech.joint(self.over).has_line:
            raise ParameterError(f"{key}.over", self.over, "must be a prismatic or pin-in-slot "
                                 "joint (a slide position), or 'driver'; this joint is "
                                 f"{type(mech.joint(self.over)).__name__}")

    def coordinate(self, kin: Kinematics) -> tuple[Arr, Arr, float]:
        """The diagram's coordinate at the positions, its rate, and the band of rates that
        counts as rest (1e-9 of the driver's largest speed, in the coordinate's unit)."""
        mech = kin.mechanism
        w_rot, w_slide = sign_widths(mech.plan, kin.omega1)
        if self.over == "driver":
            crank = isinstance(mech.driver, Crank)
            return kin.phi1, kin.omega1, w_rot if crank else w_slide
        s, sd, _ = kin.slide(self.over)
        return s, sd, w_slide

    def evaluate(self, kin: Kinematics, key: str = "diagram") -> Arr:
        """The load at every position of ``kin`` (NaN where the mechanism is not assembled)."""
        self.check(kin.mechanism, key)
        q, rate, width = self.coordinate(kin)
        x = np.asarray(self.position)
        lo, hi = self.table_range
        tol = 1e-9 * (hi - lo)
        if self.over == "driver" and isinstance(kin.mechanism.driver, Crank):
            q = lo + np.mod(q - lo, 2 * math.pi)  # a crank angle: the same every turn
            q = np.where(q >= lo + 2 * math.pi - tol, q - 2 * math.pi, q)  # lo less round-off
        inside = (q >= lo - tol) & (q <= hi + tol)
        acts = np.ones(q.shape, dtype=bool)
        if self.when == "increasing":
            acts = rate >= -width
        elif self.when == "decreasing":
            acts = rate <= width
        good = np.asarray(kin.valid, dtype=bool)
        if self.outside == "error":
            out = good & acts & ~inside
            if out.any():
                drv, unit = kin.mechanism.driver.coordinate
                of = "driver" if self.over == "driver" else f"slide of {self.over}"
                where = format_angle_ranges(angle_ranges(kin.phi1, out), unit)
                raise ParameterError(
                    f"{key}.position", f"[{lo:g}, {hi:g}] {unit if of == 'driver' else 'm'}",
                    f"the analysis leaves this range of the diagram over the {of} "
                    f"while the load acts, at {drv} in {where} (outside = 'error': no "
                    "extrapolation; give the table over the whole range, or outside = 'zero')")
        values = np.interp(np.clip(q, lo, hi), x, np.asarray(self.value))
        with np.errstate(invalid="ignore"):
            return np.where(good, np.where(inside & acts, values, 0.0), np.nan)


def _table(name: str, value: Any) -> Arr:
    """A 1-D table of finite numbers."""
    if isinstance(value, str) or not isinstance(value, Sequence | np.ndarray):
        raise ParameterError(name, value, "must be a sequence of numbers")
    arr = require_finite(name, value)
    if arr.ndim != 1:
        raise ParameterError(name, value, "must be a 1-D sequence of numbers")
    return arr


def _values(name: str, value: Any, kin: Kinematics, key: str) -> Arr:
    """A number, an array over the positions, or a diagram evaluated there: shape (n,)."""
    if isinstance(value, LoadDiagram):
        return value.evaluate(kin, f"{key}.{name}")
    return per_position(f"{key}.{name}", value, kin.n)


# ---------------------------------------------------------------------------------------------
# the loads
@dataclass(frozen=True)
class PointForce:
    """External force on ``body`` at ``point`` (name, ``"com"`` or local (x, y) [m]).

    ``fx, fy`` [N] in the fixed frame's axes: numbers, arrays over the positions or
    :class:`LoadDiagram`.
    ``from_frame``: the force comes from something held by the frame (the workpiece on a
    press's bed, a spring or cylinder anchored to it), so its reaction acts on the frame at the
    same point and it cancels in the shaking force and moment (default False: the load comes
    from outside the machine, and the frame's bearings carry all of it).
    ``name``: its name in results (default ``"force.<k>"``, k its place in ``loads``).
    """

    body: str
    point: PointRef = "com"
    fx: Value | LoadDiagram = 0.0
    fy: Value | LoadDiagram = 0.0
    from_frame: bool = False
    name: str = ""

    kind = "force"

    def check(self, mech: Mechanism, key: str) -> None:
        _check_at_point(self, mech, key)
        for v, k in ((self.fx, "fx"), (self.fy, "fy")):
            if isinstance(v, LoadDiagram):
                v.check(mech, f"{key}.{k}")

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        fx = _values("fx", self.fx, kin, key)
        fy = _values("fy", self.fy, kin, key)
        pm = _moving_point(kin, self.body, self.point)
        return _Evaluated(np.hypot(fx, fy), "N", _at_point(self, kin, pm, fx, fy))


@dataclass(frozen=True)
class BodyTorque:
    """External couple ``mz`` [N m] on ``body`` (counter-clockwise positive): a number, an
    array over the positions or a :class:`LoadDiagram`.

    ``from_frame``: the couple reacts on the frame (see :class:`PointForce`); ``name``: its name
    in results (default ``"torque.<k>"``)."""

    body: str
    mz: Value | LoadDiagram = 0.0
    from_frame: bool = False
    name: str = ""

    kind = "torque"

    def check(self, mech: Mechanism, key: str) -> None:
        _moving_body(mech, self.body, f"{key}.body")
        _flag(self.from_frame, f"{key}.from_frame")
        if isinstance(self.mz, LoadDiagram):
            self.mz.check(mech, f"{key}.mz")

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        mz = _values("mz", self.mz, kin, key)
        zero = np.zeros(kin.n)
        ws = [Wrench(self.body, zero, zero, zero, zero, mz)]
        if self.from_frame:
            ws.append(Wrench(kin.mechanism.frame.name, zero, zero, zero, zero, -mz))
        return _Evaluated(mz, "N*m", ws)


@dataclass(frozen=True)
class SlideForce:
    """A force ``force`` [N] along the line of the prismatic or pin-in-slot joint ``joint``:
    on its body ``b`` at the slider point (the pin), positive along the line's direction ``u``
    (which turns with body ``a``), and its reaction ``-force u`` on body ``a`` at the same point
    (on the frame when ``a`` is the frame: it cancels in the shaking force and moment).

    ``force``: a number, an array over the positions or a :class:`LoadDiagram` (a press's
    technological force over the ram's stroke). Its power is ``force * ds/dt`` with ``ds/dt``
    the sliding speed relative to ``a``. ``name``: default ``"slide.<k>"``.
    """

    joint: str
    force: Value | LoadDiagram = 0.0
    name: str = ""

    kind = "slide"

    def check(self, mech: Mechanism, key: str) -> None:
        names = [j.name for j in mech.joints]
        if self.joint not in names:
            raise ParameterError(f"{key}.joint", self.joint, f"no such joint; known: {names}")
        j = mech.joint(self.joint)
        if not j.has_line:
            raise ParameterError(f"{key}.joint", self.joint, "must be a prismatic or "
                                 f"pin-in-slot joint (a line to act along); this joint is "
                                 f"{type(j).__name__}")
        if isinstance(self.force, LoadDiagram):
            self.force.check(mech, f"{key}.force")

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        mech = kin.mechanism
        F = _values("force", self.force, kin, key)
        j = mech.joint(self.joint)
        _, pb, ang = mech.joint_geometry(j)
        ta = kin.angle(j.a)
        ux, uy = np.cos(ta + ang), np.sin(ta + ang)
        P = _moving_point(kin, j.b, pb)
        return _Evaluated(F, "N", [Wrench(j.b, F * ux, F * uy, P.x, P.y),
                                   Wrench(j.a, -F * ux, -F * uy, P.x, P.y)])


@dataclass(frozen=True)
class _TwoPoint:
    """An element between point ``point_a`` of body ``a`` and point ``point_b`` of body ``b``
    (names, ``"com"`` or local (x, y) [m]; either body may be the frame)."""

    a: str
    point_a: PointRef
    b: str
    point_b: PointRef

    def _check_ends(self, mech: Mechanism, key: str) -> None:
        for side, pt in (("a", self.point_a), ("b", self.point_b)):
            body = getattr(self, side)
            if body not in mech.index:
                raise ParameterError(f"{key}.{side}", body,
                                     f"no such body; known: {list(mech.body_names)}")
            _point(mech, body, pt, f"{key}.point_{side}")
        if self.a == self.b:
            raise ParameterError(f"{key}.b", self.b, "must differ from a: an element within "
                                 "one rigid body does nothing")

    def _geometry(self, kin: Kinematics) -> tuple[Any, Any, Arr, Arr, Arr, Arr]:
        """Both ends' motions, the vector d from a's point to b's, its length L and dL/dt."""
        pa = _moving_point(kin, self.a, self.point_a)
        pb = _moving_point(kin, self.b, self.point_b)
        dx, dy = pb.x - pa.x, pb.y - pa.y
        L = np.hypot(dx, dy)
        with np.errstate(invalid="ignore", divide="ignore"):
            Ld = (dx * (pb.vx - pa.vx) + dy * (pb.vy - pa.vy)) / L
        return pa, pb, dx, dy, L, Ld

    def _coincident(self, kin: Kinematics, L: Arr, key: str, what: str) -> None:
        """Refuse positions where the two points coincide and the force needs a direction."""
        small = np.asarray(kin.valid, dtype=bool) & (L <= 1e-12 * kin.mechanism.plan.length_scale)
        if small.any():
            drv, unit = kin.mechanism.driver.coordinate
            where = format_angle_ranges(angle_ranges(kin.phi1, small), unit)
            raise ParameterError(key, self.label(key), f"its points {self.point_a!r} of "
                                 f"{self.a!r} and {self.point_b!r} of {self.b!r} coincide at "
                                 f"{drv} in {where}, where the direction of its {what} is "
                                 "undefined")

    def label(self, key: str) -> str:
        return getattr(self, "name", "") or key

    def _pair(self, kin: Kinematics, pa: Any, pb: Any, gx: Arr, gy: Arr) -> list[Wrench]:
        """The force (gx, gy) on b at its point and its opposite on a at its point."""
        return [Wrench(self.b, gx, gy, pb.x, pb.y), Wrench(self.a, -gx, -gy, pa.x, pa.y)]


@dataclass(frozen=True)
class Spring(_TwoPoint):
    """Linear spring between point ``point_a`` of body ``a`` and point ``point_b`` of body ``b``.

    Tension ``F = preload + stiffness (L - free_length)`` [N] at the distance ``L`` between
    the points (positive: it pulls them together); energy stored
    ``V = preload (L - free_length) + stiffness (L - free_length)^2 / 2`` [J].

    Parameters
    ----------
    a, point_a, b, point_b
        The bodies (either may be the frame) and their points (names, ``"com"`` or local
        (x, y) [m]).
    stiffness : float
        Rate ``k`` [N/m], >= 0.
    free_length : float
        Length ``L0`` at which the force is the preload [m], >= 0 (0: a zero-free-length
        spring, whose force ``-k d`` is defined even where the points meet).
    preload : float
        Tension at the free length [N] (the initial tension of a close-wound extension
        spring; negative: a push, e.g. a gas spring's force ``-F0`` with a small rate).
    name : str
        Its name in results (default ``"spring.<k>"``).
    """

    stiffness: float = 0.0
    free_length: float = 0.0
    preload: float = 0.0
    name: str = ""

    kind = "spring"

    def __post_init__(self) -> None:
        _number(self, "stiffness", minimum=0.0)
        _number(self, "free_length", minimum=0.0)
        _number(self, "preload")

    def check(self, mech: Mechanism, key: str) -> None:
        self._check_ends(mech, key)

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        pa, pb, dx, dy, L, _ = self._geometry(kin)
        k, L0, F0 = self.stiffness, self.free_length, self.preload
        ext = L - L0
        F = F0 + k * ext
        if L0 == 0.0 and F0 == 0.0:  # -k d: defined where the points meet too
            gx, gy = -k * dx, -k * dy
        else:
            self._coincident(kin, L, key, "force")
            with np.errstate(invalid="ignore", divide="ignore"):
                gx, gy = -F * dx / L, -F * dy / L
        V = F0 * ext + 0.5 * k * ext * ext
        return _Evaluated(F, "N", self._pair(kin, pa, pb, gx, gy), energy=V, length=L)


@dataclass(frozen=True)
class Damper(_TwoPoint):
    """Viscous damper between point ``point_a`` of body ``a`` and point ``point_b`` of body
    ``b`` (either body may be the frame): tension ``F = damping * dL/dt`` [N] along the line of
    the points (it resists their separation and approach), power ``-damping (dL/dt)^2``.

    ``damping`` c [N s/m] >= 0; ``name`` default ``"damper.<k>"``.
    """

    damping: float = 0.0
    name: str = ""

    kind = "damper"

    def __post_init__(self) -> None:
        _number(self, "damping", minimum=0.0)

    def check(self, mech: Mechanism, key: str) -> None:
        self._check_ends(mech, key)

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        pa, pb, dx, dy, L, Ld = self._geometry(kin)
        self._coincident(kin, L, key, "force")
        F = self.damping * Ld
        with np.errstate(invalid="ignore", divide="ignore"):
            gx, gy = -F * dx / L, -F * dy / L
        return _Evaluated(F, "N", self._pair(kin, pa, pb, gx, gy), length=L)


@dataclass(frozen=True)
class Drag:
    """A force opposing the velocity ``v`` (absolute, frame axes) of ``point`` of ``body``:

    ``F = -force * v / sqrt(|v|^2 + w^2) - damping * v``

    with a Coulomb-like part of constant magnitude ``force`` [N] >= 0 (its direction
    regularised over speeds ``w`` of 1e-9 of the driver's, as the friction in the joints; zero
    at rest) and a viscous part ``damping`` [N s/m] >= 0. ``from_frame``: the resisting medium
    is held by the frame (material on a bed, oil in the machine's casing), so the reaction
    acts on the frame (see :class:`PointForce`). ``name`` default ``"drag.<k>"``.
    """

    body: str
    point: PointRef = "com"
    force: float = 0.0
    damping: float = 0.0
    from_frame: bool = False
    name: str = ""

    kind = "drag"

    def __post_init__(self) -> None:
        _number(self, "force", minimum=0.0)
        _number(self, "damping", minimum=0.0)

    def check(self, mech: Mechanism, key: str) -> None:
        _check_at_point(self, mech, key)

    def evaluate(self, kin: Kinematics, key: str) -> _Evaluated:
        pm = _moving_point(kin, self.body, self.point)
        _, w = sign_widths(kin.mechanism.plan, kin.omega1)
        speed = np.hypot(pm.vx, pm.vy)
        # w = 0 only if the driver is at rest at every position: then so is every point
        unit = 1.0 / np.sqrt(speed * speed + w * w) if w > 0 else np.zeros(kin.n)
        c = self.force * unit + self.damping
        return _Evaluated(c * speed, "N", _at_point(self, kin, pm, -c * pm.vx, -c * pm.vy))


Load = PointForce | BodyTorque | SlideForce | Spring | Damper | Drag
_LOAD_TYPES = (PointForce, BodyTorque, SlideForce, Spring, Damper, Drag)


# ---------------------------------------------------------------------------------------------
# evaluation
@dataclass(frozen=True)
class Wrench:
    """A force ``(fx, fy)`` [N] at the world point ``(px, py)`` [m] and a couple ``mz`` [N m]
    on body ``body`` (the frame: a reaction on it), arrays over the positions."""

    body: str
    fx: Arr
    fy: Arr
    px: Arr
    py: Arr
    mz: Arr | float = 0.0


@dataclass(frozen=True)
class _Evaluated:
    value: Arr
    unit: str
    wrenches: list[Wrench]
    energy: Arr | None = None
    length: Arr | None = None


@dataclass(frozen=True)
class AppliedLoad:
    """A load evaluated on the motion: what it does to the bodies, its power and energy.

    Attributes
    ----------
    name : str
        Its name (given, or ``"<kind>.<k>"`` with ``k`` its place in ``loads``).
    kind : str
        ``"force"``, ``"torque"``, ``"slide"``, ``"spring"``, ``"damper"`` or ``"drag"``.
    load : Load
        The load as given.
    value : ndarray (n,)
        Its size at each position: the tension of a spring or damper [N] (positive: pulling its
        points together), the force along the line of a slide force [N], the magnitude of a
        drag or of a point force [N], the couple of a torque [N m].
    unit : str
        Unit of ``value``.
    power : ndarray (n,)
        Power of the load on the moving bodies [W] (a spring's is ``-dV/dt``, a damper's and a
        drag's <= 0).
    energy : ndarray (n,)
        Energy stored in a spring [J] (zero for the other kinds).
    length : ndarray (n,) or None
        Distance between the points of a spring or damper [m].
    wrenches : tuple of Wrench
        The forces and couples it exerts, on moving bodies and (its reactions) on the frame.
    """

    name: str
    kind: str
    load: Any
    value: Arr
    unit: str
    power: Arr
    energy: Arr
    length: Arr | None
    wrenches: tuple[Wrench, ...]


def _power(kin: Kinematics, ws: Sequence[Wrench]) -> Arr:
    """Power of the wrenches on the moving bodies: F . v of the body's point there + M omega."""
    mech = kin.mechanism
    p = np.zeros(kin.n)
    for w in ws:
        i = mech.index[w.body]
        if i == 0:
            continue
        om = kin.omega[i]
        vx = kin.vx[i] - om * (w.py - kin.y[i])
        vy = kin.vy[i] + om * (w.px - kin.x[i])
        p = p + w.fx * vx + w.fy * vy + w.mz * om
    return p


def apply(kin: Kinematics, loads: Sequence[Load]) -> tuple[AppliedLoad, ...]:
    """Every load of ``loads`` checked against the mechanism and evaluated over the motion.

    Raises
    ------
    ParameterError
        ``loads`` is not a sequence of loads, a load names no body, point or joint of the
        mechanism (or a joint of the wrong type), a value has the wrong shape, two loads have
        the same name, or a spring's or damper's points meet where its direction is needed.
        The parameter is named ``loads[k].<field>``.
    """
    if isinstance(loads, _LOAD_TYPES) or not isinstance(loads, Sequence):
        raise ParameterError("loads", loads, "must be a sequence (list or tuple) of "
                             + ", ".join(t.__name__ for t in _LOAD_TYPES))
    mech = kin.mechanism
    out: list[AppliedLoad] = []
    names: set[str] = set()
    for k, ld in enumerate(loads):
        if not isinstance(ld, _LOAD_TYPES):
            raise ParameterError(f"loads[{k}]", ld, "must be "
                                 + ", ".join(t.__name__ for t in _LOAD_TYPES))
        key = f"loads[{k}]"
        ld.check(mech, key)
        name = ld.name or f"{ld.kind}.{k}"
        if not isinstance(name, str):
            raise ParameterError(f"{key}.name", name, "must be a string")
        if name in names:
            raise ParameterError(f"{key}.name", name, "must be unique among the loads")
        names.add(name)
        ev = ld.evaluate(kin, key)
        zero = np.zeros(kin.n)
        out.append(AppliedLoad(name, ld.kind, ld, ev.value, ev.unit, _power(kin, ev.wrenches),
                               zero if ev.energy is None else ev.energy, ev.length,
                               tuple(ev.wrenches)))
    return tuple(out)


@dataclass(frozen=True)
class _PointRates:
    """Position [m] and velocity [m/s] of a body point, frame axes."""

    x: Arr
    y: Arr
    vx: Arr
    vy: Arr


def _moving_point(kin: Kinematics, body: str, point: PointRef) -> _PointRates:
    """Where a body point is and how fast it moves (:meth:`Kinematics.point` without the
    accelerations, which no load needs: half the work)."""
    i = kin.mechanism.index[body]
    p = kin.mechanism.body(body).point(point) if isinstance(point, str) else point
    c, s = kin._cos_sin[0][i], kin._cos_sin[1][i]
    rx, ry = c * p[0] - s * p[1], s * p[0] + c * p[1]
    w = kin.omega[i]
    return _PointRates(kin.x[i] + rx, kin.y[i] + ry, kin.vx[i] - w * ry, kin.vy[i] + w * rx)


def _at_point(load: PointForce | Drag, kin: Kinematics, pm: Any, fx: Arr, fy: Arr
              ) -> list[Wrench]:
    """The force (fx, fy) on the load's body at the point ``pm`` and, if it comes from the
    frame, its reaction -F on the frame at the same point."""
    ws = [Wrench(load.body, fx, fy, pm.x, pm.y)]
    if load.from_frame:
        ws.append(Wrench(kin.mechanism.frame.name, -fx, -fy, pm.x, pm.y))
    return ws


# ---------------------------------------------------------------------------------------------
# checks
def _check_at_point(load: PointForce | Drag, mech: Mechanism, key: str) -> None:
    """A load at a point of a moving body: the body, the point and ``from_frame``."""
    _moving_body(mech, load.body, f"{key}.body")
    _point(mech, load.body, load.point, f"{key}.point")
    _flag(load.from_frame, f"{key}.from_frame")


def _number(obj: Any, attr: str, minimum: float | None = None) -> None:
    """``obj.attr`` as a finite Python float (>= minimum), named by the attribute."""
    v = getattr(obj, attr)
    arr = require_finite(attr, v)
    if arr.ndim:
        raise ParameterError(attr, v, "must be a single number")
    x = float(arr)
    if minimum is not None and x < minimum:
        raise ParameterError(attr, x, f"must be >= {minimum:g}")
    object.__setattr__(obj, attr, x)


def _moving_body(mech: Mechanism, body: str, key: str) -> None:
    if body == mech.frame.name:
        raise ParameterError(key, body, "loads must act on moving bodies")
    if body not in mech.index:
        raise ParameterError(key, body, f"no such body; known: {list(mech.body_names[1:])}")


def _point(mech: Mechanism, body: str, point: Any, key: str) -> None:
    if isinstance(point, str):
        if point != "com" and point not in mech.body(body).points:
            raise ParameterError(key, point, f"no such point of body {body!r}; known: "
                                 f"{[*mech.body(body).points, 'com']}")
    else:
        require_point(key, point)


def _flag(value: Any, key: str) -> None:
    if not isinstance(value, bool | np.bool_):
        raise ParameterError(key, value, "must be True or False")
