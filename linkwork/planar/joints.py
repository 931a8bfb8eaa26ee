"""The joint types of the planar engine, each with everything that depends on its type.

A joint joins a first body ``a`` and a second body ``b``; its reaction is the force (and, for a
prismatic pair, the couple) exerted **by a on b**. Each class holds its description (the
constructor's fields), its validation and local geometry, its constraint equations and their
rows (velocity/acceleration), the closure of a closed-form group through it, the position locus
it allows a dyad's body, the components of the reaction it transmits and how the reaction
unknowns enter the equilibrium. The solvers (:mod:`~linkwork.planar.positions`,
:mod:`~linkwork.planar.rates`, :mod:`~linkwork.planar.dynamics`) call these methods through the
joints of the compiled plan (:class:`ResolvedJoint`: body indices and local geometry as floats),
so a new joint type is one class here plus its tests.

* :class:`Revolute` -- point ``point_a`` of ``a`` coincides with point ``point_b`` of ``b``
  (both default to the joint's name). 2 constraints (x, y).
* :class:`Prismatic` -- ``a`` carries a guide line through its point ``through`` at angle
  ``angle``; point ``point`` of ``b`` stays on the line and ``theta_b - theta_a = rel_angle``.
  2 constraints (normal, angle).
* :class:`PinInSlot` -- ``a`` carries a straight slot, point ``point`` of ``b`` stays on it;
  rotation is free. 1 constraint (normal; a higher pair).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import numpy as np

from linkwork.checks import require_number
from linkwork.errors import AssemblyError, ParameterError, StructureError
from linkwork.planar.designs import design_point, design_value
from linkwork.planar.state import Arr, State, Vec

__all__ = ["GearPair", "Joint", "PinInSlot", "Prismatic", "ResolvedJoint", "Revolute",
           "design_length", "row_entries", "smooth_sign"]

Point = tuple[float, float]
#: a constraint row: ``ja``, ``jb`` (d/dx, d/dy, d/dtheta of bodies a and b), ``gam``
#: (acceleration right-hand side from velocity terms), ``res`` (residual), ``drive``
Row = dict[str, Any]
#: a closure row of a closed-form group: (coefficients of the unknown rates, right-hand side)
ClosureRow = tuple[list[Arr | float], Arr]




class _BodyLike(Protocol):
    """What a joint needs of a body: its name and named points."""

    @property
    def name(self) -> str: ...

    @property
    def points(self) -> Mapping[str, Point]: ...

    def point(self, name: str) -> Point: ...


class Hung(Protocol):
    """A body's motion hung on a known neighbour with one unknown rate
    (:class:`linkwork.planar.rates.RatePar`), as the closure rows use it."""

    idx: int | None
    z: Arr | float

    def d(self, X: Vec) -> Vec: ...

    def cv(self, X: Vec) -> Vec: ...

    def ca(self, X: Vec) -> Vec: ...

    def vel(self, X: Vec) -> Vec: ...

    def w(self) -> tuple[Arr | float, float]: ...

    def e(self) -> tuple[Arr | float, float]: ...


def design_length(dx: Any, dy: Any) -> Any:
    """The length of a local vector: a Python float, or an array over the elements of a batch
    of designs."""
    r = np.hypot(dx, dy)
    return float(r) if r.ndim == 0 else r


@dataclass(frozen=True, eq=False)
class ResolvedJoint:
    """A joint of a compiled plan: the joint, its index in ``Mechanism.joints``, the indices of
    its bodies, its local geometry (point on a, point on b [m], line angle in a [rad] and the
    line's unit direction in a), whether a driver acts on it and which (``drive_index``: its
    place in ``Mechanism.drivers``, -1 for none); a gear pair's carrier index ``ic`` and
    ``params`` (r_a, r_b, s, offset)."""

    joint: Joint
    index: int
    ia: int
    ib: int
    qa: Point
    pb: Point
    ang: float
    u_loc: tuple[float, float]
    drive: bool
    drive_index: int = -1
    ic: int = -1
    params: tuple[float, ...] = ()

    def other(self, body: int) -> int:
        """The index of the joint's other body."""
        return self.ia if body == self.ib else self.ib


def _coefs(n_unk: int, vals: list[tuple[Hung, Any]]) -> list[Arr | float]:
    c: list[Arr | float] = [0.0] * n_unk
    for par, val in vals:
        if par.idx is not None:
            c[par.idx] = c[par.idx] + val
    return c


@dataclass(frozen=True)
class Joint:
    """Base of the joints: ``name``, first body ``a``, second body ``b``."""

    name: str
    a: str
    b: str

    #: number of scalar constraints the joint imposes
    n_constraints = 2
    #: one-letter type code used in group names (R, P, S)
    code = "?"
    #: the two bodies share a point (a pivot)
    is_pivot: ClassVar[bool] = False
    #: the joint keeps ``theta_b - theta_a`` constant
    keeps_angle: ClassVar[bool] = False
    #: body ``a`` carries a line (guide or slot) on which a point of ``b`` stays
    has_line: ClassVar[bool] = False
    #: the reaction component each constraint row carries (drive rows excepted)
    row_kinds: ClassVar[tuple[str, ...]] = ()
    #: family of the spatial joint it becomes in :mod:`linkwork.redundancy` ("R", "P", "G" a
    #: gear mesh; None: unsupported)
    spatial_family: ClassVar[str | None] = None

    # -- description ------------------------------------------------------------------------
    def check_points(self, ba: _BodyLike, bb: _BodyLike) -> None:
        """Raise ParameterError if a point the joint names is not on its body."""
        raise NotImplementedError

    def local_geometry(self, ba: _BodyLike, bb: _BodyLike) -> tuple[Point, Point, float]:
        """(point on a, point on b, line angle in a [rad]) in the bodies' frames."""
        raise NotImplementedError

    def _has(self, body: _BodyLike, key: str, point: str) -> None:
        if point != "com" and point not in body.points:  # the error names the joint's key
            raise ParameterError(f"joint {self.name}.{key}", point, f"no such point of body "
                                 f"{body.name!r}; known: {sorted(body.points)}")

    def carrier_of(self, frame: str) -> str | None:
        """A third body the joint's constraint involves (a gear pair's carrier), or None."""
        return None

    def resolve(self, mech: Any) -> tuple[Point, Point, float, int, tuple[float, ...]]:
        """Local geometry (point on a, point on b, line angle), a third body's index (-1: none)
        and further parameters, given the whole mechanism (a gear pair finds its centres)."""
        qa, pb, ang = self.local_geometry(mech.body(self.a), mech.body(self.b))
        return qa, pb, ang, -1, ()

    # -- constraints ------------------------------------------------------------------------
    def constraint_rows(self, st: State, r: ResolvedJoint, need_gamma: bool = True
                        ) -> list[Row]:
        """The joint's constraint rows (and the driver's row when ``r.drive``)."""
        raise NotImplementedError

    def equilibrium_rows(self, st: State, r: ResolvedJoint) -> list[Row]:
        """The rows whose multipliers are the joint's reaction components (``J^T lambda``
        = the applied loads): the constraint rows, unless the joint says otherwise (a gear
        pair: the rolling of the pitch circles, whose multiplier is the tooth force)."""
        return self.constraint_rows(st, r, need_gamma=False)

    def reaction_point(self, st: State, r: ResolvedJoint) -> Vec:
        """Where the reaction force acts: the point of b of the joint (a gear pair's pitch
        point)."""
        return st.wpt(r.ib, r.pb)

    @property
    def has_separation(self) -> bool:
        """The reaction has a part that depends on the magnitude of the multiplier but does no
        work (a gear pair's separating force)."""
        return False

    def separation(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr) -> tuple[Arr, Arr]:
        """That part, a force on b at the reaction point, for the constraint force (fx, fy)."""
        z = np.zeros(st.n)
        return z, z

    def closure_rows(self, st: State, r: ResolvedJoint, pa_: Hung, pb_: Hung, n_unk: int,
                     level: str) -> list[ClosureRow]:
        """Closure of a closed-form group through this joint in the unknown rates of its bodies
        (``pa_`` hung body a, ``pb_`` body b): velocity rows (``level="v"``) or acceleration
        rows (``"a"``, the same coefficients, the rates known)."""
        raise NotImplementedError

    def hang(self, par: Any, st: State, r: ResolvedJoint) -> None:
        """Set up ``par`` (a :class:`~linkwork.planar.rates.RatePar` of body ``par.b`` hung on
        the known body ``par.k`` through this joint): its rate parametrisation."""
        raise NotImplementedError

    def driven_rates(self, st: State, r: ResolvedJoint, u: int, w1: Arr, e1: Arr) -> bool:
        """Closed-form velocity and acceleration of the driven body ``u``; False where the
        generic hung-body parametrisation is used instead."""
        return False

    # -- positions ---------------------------------------------------------------------------
    def place_driven(self, st: State, r: ResolvedJoint, u: int, q: Arr) -> None:
        """Pose of the driven body ``u`` for the driver coordinate ``q``."""
        raise StructureError(f"joint {self.name}: a {type(self).__name__} cannot carry the "
                             "driver")

    def locus(self, st: State, r: ResolvedJoint, body: int, p_int: Point, body_name: str
              ) -> tuple[str, Any]:
        """Locus of the point ``p_int`` of ``body`` (a dyad's body whose external joint this
        is): ("circle", (A, radius, p_ext)) or ("line", (B0, u)) with the body's angle set."""
        raise StructureError(f"joint {self.name}: a {type(self).__name__} cannot be the external "
                             "joint of a dyad")

    def pivot(self, st: State, r: ResolvedJoint, body: int) -> tuple[Vec, Point]:
        """World centre of a pivot (from its known side) and its local point on ``body``."""
        raise StructureError(f"joint {self.name}: a {type(self).__name__} has no pivot")

    def angle_of(self, st: State, r: ResolvedJoint, body: int) -> Arr:
        """Angle of ``body`` fixed by the joint to its already-known other body."""
        raise StructureError(f"joint {self.name}: a {type(self).__name__} does not fix the "
                             "relative angle")

    def line_condition(self, st: State, r: ResolvedJoint, body: int) -> tuple[Vec, Arr]:
        """For a body of known angle: the joint's line constraint as ``n . r_body = c``."""
        raise StructureError(f"joint {self.name}: a {type(self).__name__} has no line")

    # -- reactions ---------------------------------------------------------------------------
    def reaction_components(self, st: State, r: ResolvedJoint, kind: str, lam: Arr
                            ) -> dict[str, Arr]:
        """The reaction components (``"fx"``, ``"fy"`` [N], ``"mz"`` [N m], by a on b) that the
        multiplier ``lam`` of the constraint row of this ``kind`` carries (``J^T lam`` = the
        applied forces, J the rows of :meth:`constraint_rows`)."""
        raise NotImplementedError

    def external_reaction(self, st: State, r: ResolvedJoint, par: Any, Fx: Arr, Fy: Arr,
                          M0: Arr) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        """The reaction on body ``par.b`` that balances the resultant (Fx, Fy, M0 about the
        origin) of its other loads: (fx, fy, mz, px, py) acting on ``par.b``."""
        raise NotImplementedError

    def closure_reaction(self, st: State, r: ResolvedJoint, lam: list[Arr]
                         ) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        """The reaction on body b from the multipliers of the closure rows of a closed-form
        group: (fx, fy, mz, px, py)."""
        raise NotImplementedError

    def transmitted_direction(self, st: State, r: ResolvedJoint, first: Any, P: Vec) -> Vec:
        """Direction of the force this joint transmits at ``P`` (no friction, the first body's
        own loads neglected), for the transmission angle."""
        raise NotImplementedError

    # -- friction ----------------------------------------------------------------------------
    @property
    def has_friction(self) -> bool:
        """The joint dissipates (a Coulomb coefficient or a constant friction torque > 0)."""
        return False

    def relative_motion(self, st: State, r: ResolvedJoint) -> tuple[Arr, Arr, Arr]:
        """Velocity of body b's point at the reaction point P relative to body a's point there
        (frame axes) [m/s] and ``omega_b - omega_a`` [rad/s]."""
        P = st.wpt(r.ib, r.pb)
        vb = st.point_vel(r.ib, r.pb)
        wa = st.W[r.ia]
        vax = st.VX[r.ia] - wa * (P[1] - st.Y[r.ia])
        vay = st.VY[r.ia] + wa * (P[0] - st.X[r.ia])
        return vb[0] - vax, vb[1] - vay, st.W[r.ib] - wa

    def friction_wrench(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr,
                        width: tuple[float, float]) -> tuple[Arr, Arr, Arr]:
        """The friction exerted by a on b (force ``Fx, Fy`` [N] at the reaction point P, couple
        ``Mz`` [N m]) given the joint's constraint reaction ``fx, fy, mz`` (by a on b, without
        friction) at the same position. ``width``: the widths (rotation [rad/s], sliding
        [m/s]) of the smooth sign :func:`smooth_sign`. Frictionless joints: zeros."""
        z = np.zeros(st.n)
        return z, z, z

    def check_fit(self, moving: list[_BodyLike]) -> None:
        """Raise ParameterError if the joint's friction geometry does not fit the moving
        bodies it joins (given: the frame is not a link)."""

    def _check_friction(self, f: float, limit_key: str = "friction") -> float:
        """``friction`` as a float in [0, 1)."""
        v = require_number(f"joint {self.name}.{limit_key}", f)
        if v < 0 or v >= 1:
            raise ParameterError(f"joint {self.name}.{limit_key}", v,
                                 "must be a Coulomb coefficient >= 0 and < 1 (a friction angle "
                                 "below 45 deg; the friction circle f*r and the contact model "
                                 "are the small-angle forms; dry and lubricated metal pairs "
                                 "have 0.01 to 0.6)")
        return v


def smooth_sign(v: Arr, width: float) -> Arr:
    """The regularised sign ``v / sqrt(v^2 + width^2)`` of a relative velocity: +-1 to within
    ``width^2 / (2 v^2)`` once ``|v| >> width``, 0 at ``v = 0`` (a joint at rest relative to its
    neighbour transmits no friction: its static friction is not determined by Coulomb's law);
    ``width = 0``: the exact sign."""
    if width == 0.0:
        return np.sign(v)
    return v / np.sqrt(v * v + width * width)


@dataclass(frozen=True)
class Revolute(Joint):
    """Revolute joint (turning pair): point ``point_a`` of ``a`` on point ``point_b`` of ``b``.

    Reaction: force (fx, fy) exerted by ``a`` on ``b`` at the joint centre, in frame axes [N];
    with friction also the friction couple ``mz`` [N m] exerted by ``a`` on ``b``.

    Friction (``docs/friction.md``): ``friction`` f (Coulomb coefficient, 0 <= f < 1) and
    ``radius`` r [m] of the journal (> 0 when f > 0; smaller than the links it joins): the
    friction circle of radius ``f * r``, i.e. a couple ``-(f r |R| + friction_torque)
    sign(omega_b - omega_a)`` on b; ``friction_torque`` [N m] >= 0 a constant pin or axial
    (thrust-collar, seal) friction torque independent of the load.
    """

    point_a: str | None = None
    point_b: str | None = None
    friction: float = 0.0
    radius: float = 0.0
    friction_torque: float = 0.0
    n_constraints = 2
    code = "R"
    is_pivot: ClassVar[bool] = True
    row_kinds: ClassVar[tuple[str, ...]] = ("x", "y")
    spatial_family: ClassVar[str | None] = "R"

    def __post_init__(self) -> None:
        f = self._check_friction(self.friction)
        r = require_number(f"joint {self.name}.radius", self.radius)
        if r < 0 or (f > 0 and r == 0):
            raise ParameterError(f"joint {self.name}.radius", r,
                                 "must be > 0 [m] (the journal radius of a joint with friction)"
                                 if f > 0 else "must be >= 0 [m]")
        t = require_number(f"joint {self.name}.friction_torque", self.friction_torque)
        if t < 0:
            raise ParameterError(f"joint {self.name}.friction_torque", t, "must be >= 0 [N m]")
        for k, v in (("friction", f), ("radius", r), ("friction_torque", t)):
            object.__setattr__(self, k, v)

    @property
    def has_friction(self) -> bool:
        return self.friction > 0 or self.friction_torque > 0

    def friction_wrench(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr,
                        width: tuple[float, float]) -> tuple[Arr, Arr, Arr]:
        """The friction circle: a couple ``-(f r |R| + M0) sign(omega_b - omega_a)``."""
        z = np.zeros(st.n)
        dw = st.W[r.ib] - st.W[r.ia]
        m = -(self.friction * self.radius * np.hypot(fx, fy) + self.friction_torque
              ) * smooth_sign(dw, width[0])
        return z, z, m

    @property
    def pa(self) -> str:
        return self.point_a or self.name

    @property
    def pb(self) -> str:
        return self.point_b or self.name

    def check_points(self, ba: _BodyLike, bb: _BodyLike) -> None:
        self._has(ba, "point_a", self.pa)
        self._has(bb, "point_b", self.pb)

    def check_fit(self, moving: list[_BodyLike]) -> None:
        """The journal must fit the moving links it joins: its radius below the longer link's
        length from the joint (the largest distance to another of its points). Below the
        longer one only: an eccentric's sheave is larger than its eccentricity (the crank)
        but not than its rod."""
        if self.radius <= 0:
            return
        sizes = []
        for body in moving:
            p = body.point(self.pa if body.name == self.a else self.pb)
            dist = [np.hypot(q[0] - p[0], q[1] - p[1]) for q in body.points.values()]
            # the smallest over the designs of a batch
            size = float(np.min(np.max(np.broadcast_arrays(*dist), axis=0))) if dist else 0.0
            if size > 0:
                sizes.append((size, body.name))
        if sizes and self.radius >= max(sizes)[0]:
            size, name = max(sizes)
            raise ParameterError(f"joint {self.name}.radius", self.radius,
                                 f"must be < {size:g} m, the length of link {name!r} from the "
                                 "joint (a journal larger than the links it joins)")

    def local_geometry(self, ba: _BodyLike, bb: _BodyLike) -> tuple[Point, Point, float]:
        return ba.point(self.pa), bb.point(self.pb), 0.0

    def constraint_rows(self, st: State, r: ResolvedJoint, need_gamma: bool = True
                        ) -> list[Row]:
        ia, ib = r.ia, r.ib
        zero = np.zeros(st.n)
        one = zero + 1.0
        wax, way = st.rot(ia, r.qa)
        wbx, wby = st.rot(ib, r.pb)
        wa2, wb2 = st.W[ia] ** 2, st.W[ib] ** 2
        res = (st.X[ia] + wax - st.X[ib] - wbx, st.Y[ia] + way - st.Y[ib] - wby)
        rows: list[Row] = [
            {"ja": (one, zero, -way), "jb": (-one, zero, wby), "gam": wax * wa2 - wbx * wb2,
             "res": res[0]},
            {"ja": (zero, one, wax), "jb": (zero, -one, -wbx), "gam": way * wa2 - wby * wb2,
             "res": res[1]}]
        if r.drive:
            rows.append({"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                         "drive": True, "drive_index": r.drive_index,
                         "res": st.T[ib] - st.T[ia]})
        return rows

    def closure_rows(self, st: State, r: ResolvedJoint, pa_: Hung, pb_: Hung, n_unk: int,
                     level: str) -> list[ClosureRow]:
        """``v_a(B) = v_b(B)`` (and the same for accelerations)."""
        B = st.wpt(r.ib, r.pb)
        da, db = pa_.d(B), pb_.d(B)
        if level == "v":
            ca, cb = pa_.cv(B), pb_.cv(B)
        else:
            ca, cb = pa_.ca(B), pb_.ca(B)
        return [(_coefs(n_unk, [(pa_, da[c]), (pb_, -db[c])]), cb[c] - ca[c]) for c in range(2)]

    def hang(self, par: Any, st: State, r: ResolvedJoint) -> None:
        """Rotation about the pivot A: ``z = omega_b``."""
        par.rev = True
        par.pk = r.qa if par.k == r.ia else r.pb
        par.A = st.wpt(par.k, par.pk)

    def driven_rates(self, st: State, r: ResolvedJoint, u: int, w1: Arr, e1: Arr) -> bool:
        ia, ib = r.ia, r.ib
        k = ia if u == ib else ib
        sign = 1.0 if u == ib else -1.0
        pk, pu = (r.qa, r.pb) if u == ib else (r.pb, r.qa)
        st.W[u] = st.W[k] + sign * w1
        st.E[u] = st.E[k] + sign * e1
        vP = st.point_vel(k, pk)
        aP = st.point_acc(k, pk)
        rx, ry = st.rot(u, pu)
        w, e = st.W[u], st.E[u]
        st.VX[u], st.VY[u] = vP[0] + w * ry, vP[1] - w * rx
        st.AX[u] = aP[0] + e * ry + w * w * rx
        st.AY[u] = aP[1] - e * rx + w * w * ry
        return True

    def place_driven(self, st: State, r: ResolvedJoint, u: int, q: Arr) -> None:
        """Crank: ``theta_b - theta_a = q``, the two points coincide."""
        ia, ib = r.ia, r.ib
        if u == ib:
            st.set_angle(ib, st.T[ia] + q)
            st.place(ib, r.pb, st.wpt(ia, r.qa))
        else:
            st.set_angle(ia, st.T[ib] - q)
            st.place(ia, r.qa, st.wpt(ib, r.pb))

    def locus(self, st: State, r: ResolvedJoint, body: int, p_int: Point, body_name: str
              ) -> tuple[str, Any]:
        """A circle about the pivot (known from the other body)."""
        p_ext = r.qa if body == r.ia else r.pb
        p_known = r.pb if body == r.ia else r.qa
        A = st.wpt(r.other(body), p_known)
        rad = design_length(p_int[0] - p_ext[0], p_int[1] - p_ext[1])
        if np.any(rad == 0.0):
            raise StructureError(f"joint {self.name}: body {body_name} has its two "
                                 "joint centres at the same point; the dyad is not determined")
        return "circle", (A, rad, p_ext)

    def pivot(self, st: State, r: ResolvedJoint, body: int) -> tuple[Vec, Point]:
        """World centre of the joint (from its known side) and its local point on ``body``."""
        if body == r.ia:
            return st.wpt(r.ib, r.pb), r.qa
        return st.wpt(r.ia, r.qa), r.pb

    def reaction_components(self, st: State, r: ResolvedJoint, kind: str, lam: Arr
                            ) -> dict[str, Arr]:
        return {"fx": lam} if kind == "x" else {"fy": lam}

    def external_reaction(self, st: State, r: ResolvedJoint, par: Any, Fx: Arr, Fy: Arr,
                          M0: Arr) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        """A force through the pivot balancing the body's other forces."""
        A = par.A
        return -Fx, -Fy, 0.0, A[0], A[1]

    def closure_reaction(self, st: State, r: ResolvedJoint, lam: list[Arr]
                         ) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        P = st.wpt(r.ib, r.pb)
        return lam[0], lam[1], 0.0, P[0], P[1]

    def transmitted_direction(self, st: State, r: ResolvedJoint, first: Any, P: Vec) -> Vec:
        """Along the first body's joint line (a two-pivot link), or normal to its guide."""
        if first.rev:
            return P[0] - first.A[0], P[1] - first.A[1]
        return -first.u[1], first.u[0]


@dataclass(frozen=True)
class _LineJoint(Joint):
    """A joint whose body ``a`` carries a straight line (guide or slot) through ``through`` at
    ``angle``, on which point ``point`` of ``b`` stays."""

    angle: float = 0.0
    through: str | Point | None = None
    point: str | None = None
    has_line: ClassVar[bool] = True

    def __post_init__(self) -> None:
        # a NaN angle would only surface as 'cannot be assembled' at every position; angles
        # and points may vary over the designs of a batch (linkwork.planar.designs)
        object.__setattr__(self, "angle", design_value(f"joint {self.name}.angle", self.angle))
        if self.through is not None and not isinstance(self.through, str):
            object.__setattr__(self, "through",
                               design_point(f"joint {self.name}.through", self.through))

    def check_points(self, ba: _BodyLike, bb: _BodyLike) -> None:
        if isinstance(self.through, str):
            self._has(ba, "through", self.through)
        if self.point is not None:
            self._has(bb, "point", self.point)

    def local_geometry(self, ba: _BodyLike, bb: _BodyLike) -> tuple[Point, Point, float]:
        if self.through is None:
            qa = ba.points.get(self.name, (0.0, 0.0))
        elif isinstance(self.through, str):
            qa = ba.point(self.through)
        else:
            qa = self.through  # checked by __post_init__
        pb = (bb.point(self.point) if self.point is not None
              else bb.points.get(self.name, (0.0, 0.0)))
        return qa, pb, self.angle

    def _line_rows(self, st: State, r: ResolvedJoint, need_gamma: bool) -> tuple[Row, Row | None]:
        """The normal row (and the row along the line, for a driver) of ``e . (P_b - Q_a)``."""
        ia, ib = r.ia, r.ib
        wax, way = st.rot(ia, r.qa)
        wbx, wby = st.rot(ib, r.pb)
        ux, uy = st.rot(ia, r.u_loc)
        nx, ny = -uy, ux
        dx = st.X[ib] + wbx - st.X[ia] - wax
        dy = st.Y[ib] + wby - st.Y[ia] - way

        def line_row(ex: Arr, ey: Arr) -> Row:
            # Phi = e . d with e rotating with body a; k x e = (-ey, ex)
            kex, key_ = -ey, ex
            th_a = kex * dx + key_ * dy - (ex * -way + ey * wax)
            th_b = ex * -wby + ey * wbx
            row: Row = {"ja": (-ex, -ey, th_a), "jb": (ex, ey, th_b), "res": ex * dx + ey * dy}
            if need_gamma:
                wa, wb = st.W[ia], st.W[ib]
                ddx = st.VX[ib] - wb * wby - st.VX[ia] + wa * way
                ddy = st.VY[ib] + wb * wbx - st.VY[ia] - wa * wax
                quad = (-wa * wa * (ex * dx + ey * dy) + 2 * wa * (kex * ddx + key_ * ddy)
                        + ex * (-wb * wb * wbx + wa * wa * wax)
                        + ey * (-wb * wb * wby + wa * wa * way))
                row["gam"] = -quad
            return row

        drive = None
        if r.drive:
            drive = line_row(ux, uy)
            drive["drive"] = True
            drive["drive_index"] = r.drive_index
        return line_row(nx, ny), drive

    def constraint_rows(self, st: State, r: ResolvedJoint, need_gamma: bool = True
                        ) -> list[Row]:
        return [self._line_rows(st, r, need_gamma)[0]]

    def closure_rows(self, st: State, r: ResolvedJoint, pa_: Hung, pb_: Hung, n_unk: int,
                     level: str) -> list[ClosureRow]:
        """``n . (v_b(P) - v_a(P)) = 0``; accelerations add the Coriolis term
        ``-2 omega_a k x v_rel`` of the relative sliding."""
        P = st.wpt(r.ib, r.pb)
        ux, uy = st.rot(r.ia, r.u_loc)
        nx, ny = -uy, ux
        da, db = pa_.d(P), pb_.d(P)
        cf = _coefs(n_unk, [(pa_, -(nx * da[0] + ny * da[1])), (pb_, nx * db[0] + ny * db[1])])
        if level == "v":
            ca, cb = pa_.cv(P), pb_.cv(P)
            return [(cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1])))]
        ca, cb = pa_.ca(P), pb_.ca(P)
        va, vb = pa_.vel(P), pb_.vel(P)
        wa = pa_.w()[0] + pa_.w()[1] * pa_.z
        rvx, rvy = vb[0] - va[0], vb[1] - va[1]
        cor = 2 * wa * (nx * -rvy + ny * rvx)
        return [(cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1])) + cor)]

    def hang(self, par: Any, st: State, r: ResolvedJoint) -> None:
        """Sliding along the guide direction u: ``z`` = velocity of b relative to k along u."""
        par.u = st.rot(r.ia, r.u_loc)

    def line_condition(self, st: State, r: ResolvedJoint, body: int) -> tuple[Vec, Arr]:
        """For a body of known angle: the line constraint as ``n . r_body = c``."""
        ia, ib = r.ia, r.ib
        ux, uy = st.rot(ia, r.u_loc)
        nx, ny = -uy, ux
        if body == ia:  # body carries the line; known point X of b
            X = st.wpt(ib, r.pb)
            w = st.rot(ia, r.qa)
            return (nx, ny), nx * (X[0] - w[0]) + ny * (X[1] - w[1])
        Q = st.wpt(ia, r.qa)
        w = st.rot(ib, r.pb)
        return (nx, ny), nx * (Q[0] - w[0]) + ny * (Q[1] - w[1])

    def reaction_components(self, st: State, r: ResolvedJoint, kind: str, lam: Arr
                            ) -> dict[str, Arr]:
        if kind == "t":  # the angle row: a couple
            return {"mz": -lam}
        ux, uy = st.rot(r.ia, r.u_loc)  # the normal row: a force along the normal
        ex, ey = -uy, ux
        return {"fx": -lam * ex, "fy": -lam * ey}

    def closure_reaction(self, st: State, r: ResolvedJoint, lam: list[Arr]
                         ) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        """Normal to the line (and the couple, for a prismatic pair)."""
        P = st.wpt(r.ib, r.pb)
        ux, uy = st.rot(r.ia, r.u_loc)
        N = -lam[0]
        m = lam[1] if self.keeps_angle else 0.0
        return N * -uy, N * ux, m, P[0], P[1]

    def transmitted_direction(self, st: State, r: ResolvedJoint, first: Any, P: Vec) -> Vec:
        """Normal to the guide or slot."""
        ux, uy = st.rot(r.ia, r.u_loc)
        return -uy, ux


@dataclass(frozen=True)
class Prismatic(_LineJoint):
    """Prismatic joint (sliding pair): ``b`` slides along a line fixed in ``a``.

    Parameters
    ----------
    name, a, b : str
        Joint name, guide body, slider body.
    angle : float
        Direction of the guide line in ``a``'s frame [rad], counter-clockwise from its x-axis;
        it is also the positive direction of the slide coordinate.
    through : str or (x, y), optional
        A point of the line: a named point of ``a`` or local coordinates [m]; default the point
        of ``a`` named like the joint, else ``a``'s origin.
    point : str, optional
        Point of ``b`` that stays on the line (default: the joint's name, else ``b``'s origin).
    rel_angle : float
        Constant ``theta_b - theta_a`` [rad].

    Reaction: force (fx, fy) exerted by ``a`` on ``b`` (normal to the guide, plus the friction
    along it) applied at the slider point, plus a couple ``mz`` [N m] exerted by ``a`` on ``b``.

    Friction (``docs/friction.md``): ``friction`` f (0 <= f < 1) and the block's ``length`` l
    [m] along the guide, centred on the slider point. With l > 0 the guide's normal force N and
    couple m are carried by two contact forces at the block's ends, ``N1 = N/2 - m/l`` and
    ``N2 = N/2 + m/l``, each with its own friction: the friction force is ``-f (|N1| + |N2|)
    sign(v)`` along the guide (v the slide rate of b on a). With l = 0 (default) the block is a
    point contact: the friction force is ``-f |N| sign(v)`` and the couple m carries no
    friction (a long guide whose tilting is neglected, as in paper 000).
    """

    rel_angle: float = 0.0
    friction: float = 0.0
    length: float = 0.0
    n_constraints = 2
    code = "P"
    keeps_angle: ClassVar[bool] = True
    row_kinds: ClassVar[tuple[str, ...]] = ("n", "t")
    spatial_family: ClassVar[str | None] = "P"

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "rel_angle",
                           design_value(f"joint {self.name}.rel_angle", self.rel_angle))
        f = self._check_friction(self.friction)
        ln = require_number(f"joint {self.name}.length", self.length)
        if ln < 0:
            raise ParameterError(f"joint {self.name}.length", ln,
                                 "must be >= 0 [m] (the block's length along the guide; 0: a "
                                 "point contact)")
        object.__setattr__(self, "friction", f)
        object.__setattr__(self, "length", ln)

    @property
    def has_friction(self) -> bool:
        return self.friction > 0

    def normal_forces(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr
                      ) -> tuple[Arr, Arr]:
        """The two contact forces ``N1, N2`` [N] (along the guide's normal ``k x u``) at the
        block's rear and front ends (``N1 = N2 = N/2`` with the whole couple ignored when the
        length is 0)."""
        ux, uy = st.rot(r.ia, r.u_loc)
        N = -uy * fx + ux * fy
        if self.length == 0.0:
            return 0.5 * N, 0.5 * N
        return 0.5 * N - mz / self.length, 0.5 * N + mz / self.length

    def friction_wrench(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr,
                        width: tuple[float, float]) -> tuple[Arr, Arr, Arr]:
        """``-f (|N1| + |N2|) sign(v)`` along the guide at the slider point (l = 0:
        ``-f |N| sign(v)``)."""
        ux, uy = st.rot(r.ia, r.u_loc)
        n1, n2 = self.normal_forces(st, r, fx, fy, mz)
        vx, vy, _ = self.relative_motion(st, r)
        ft = -self.friction * (np.abs(n1) + np.abs(n2)) * smooth_sign(ux * vx + uy * vy,
                                                                      width[1])
        return ft * ux, ft * uy, np.zeros(st.n)

    def constraint_rows(self, st: State, r: ResolvedJoint, need_gamma: bool = True
                        ) -> list[Row]:
        normal, drive = self._line_rows(st, r, need_gamma)
        zero = np.zeros(st.n)
        one = zero + 1.0
        rows = [normal, {"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                         "res": st.T[r.ib] - st.T[r.ia] - self.rel_angle}]
        if drive is not None:
            rows.append(drive)
        return rows

    def closure_rows(self, st: State, r: ResolvedJoint, pa_: Hung, pb_: Hung, n_unk: int,
                     level: str) -> list[ClosureRow]:
        """The line's row and ``omega_a = omega_b`` (``eps_a = eps_b``)."""
        rows = super().closure_rows(st, r, pa_, pb_, n_unk, level)
        (c0a, ka), (c0b, kb) = (pa_.w(), pb_.w()) if level == "v" else (pa_.e(), pb_.e())
        rows.append((_coefs(n_unk, [(pa_, ka), (pb_, -kb)]),
                     np.asarray(c0b - c0a) + np.zeros(st.n)))
        return rows

    def angle_of(self, st: State, r: ResolvedJoint, body: int) -> Arr:
        """Angle of ``body`` fixed by the joint to its already-known other body."""
        return st.T[r.ia] + self.rel_angle if body == r.ib else st.T[r.ib] - self.rel_angle

    def place_driven(self, st: State, r: ResolvedJoint, u: int, q: Arr) -> None:
        """Linear driver: the slide coordinate ``u . (P_b - Q_a) = q``."""
        ia, ib = r.ia, r.ib
        if u == ib:
            st.set_angle(ib, st.T[ia] + self.rel_angle)
            Q = st.wpt(ia, r.qa)
            ux, uy = st.rot(ia, r.u_loc)
            st.place(ib, r.pb, (Q[0] + q * ux, Q[1] + q * uy))
        else:
            st.set_angle(ia, st.T[ib] - self.rel_angle)
            P = st.wpt(ib, r.pb)
            ux, uy = st.rot(ia, r.u_loc)
            st.place(ia, r.qa, (P[0] - q * ux, P[1] - q * uy))

    def locus(self, st: State, r: ResolvedJoint, body: int, p_int: Point, body_name: str
              ) -> tuple[str, Any]:
        """A line parallel to the guide, with the body's angle set."""
        k = r.other(body)
        st.set_angle(body, self.angle_of(st, r, body))
        if body == r.ib:  # body is the slider on known guide k = a
            Q = st.wpt(k, r.qa)
            u = st.rot(k, r.u_loc)
            off = st.rot(body, (p_int[0] - r.pb[0], p_int[1] - r.pb[1]))
            return "line", ((Q[0] + off[0], Q[1] + off[1]), u)
        # body is the guide; the known body's point X slides on it: B = X + A(pB - qa) - s u
        X = st.wpt(k, r.pb)
        u = st.rot(body, r.u_loc)
        off = st.rot(body, (p_int[0] - r.qa[0], p_int[1] - r.qa[1]))
        return "line", ((X[0] + off[0], X[1] + off[1]), u)

    def external_reaction(self, st: State, r: ResolvedJoint, par: Any, Fx: Arr, Fy: Arr,
                          M0: Arr) -> tuple[Arr, Arr, Arr | float, Arr, Arr]:
        """A force normal to the guide at the slider point and a couple."""
        P = st.wpt(r.ib, r.pb)
        nx, ny = -par.u[1], par.u[0]
        N = -(Fx * nx + Fy * ny)
        m = -(M0 - (P[0] * Fy - P[1] * Fx))
        return N * nx, N * ny, m, P[0], P[1]


@dataclass(frozen=True)
class PinInSlot(_LineJoint):
    """Pin-in-slot (higher pair): point ``point`` of ``b`` stays on a straight slot of ``a``.

    ``angle`` and ``through`` define the slot's line in ``a`` as for :class:`Prismatic`;
    ``theta_b - theta_a`` is free. Reaction: force exerted by ``a`` on ``b`` (normal to the slot,
    plus the friction along it) at the pin, and with a pin of radius r > 0 the friction's
    couple ``mz`` about the pin's centre.

    Friction (``docs/friction.md``): ``friction`` f (0 <= f < 1) and the pin's ``radius`` r
    [m] >= 0. The pin touches the slot's wall on the side the normal force N pushes it from,
    at ``C = P - r sign(N) n``; the material of b slips there at ``s = u . v_rel + r sign(N)
    (omega_b - omega_a)`` along the slot, and the friction ``-f |N| sign(s)`` along the slot
    acts at C: at the pin's centre a force and the couple ``-r f N sign(s)``. r = 0: a block
    pinned to b without friction slides in the slot (paper 000's stone).
    """

    friction: float = 0.0
    radius: float = 0.0
    n_constraints = 1
    code = "S"
    row_kinds: ClassVar[tuple[str, ...]] = ("n",)

    def __post_init__(self) -> None:
        super().__post_init__()
        f = self._check_friction(self.friction)
        r = require_number(f"joint {self.name}.radius", self.radius)
        if r < 0:
            raise ParameterError(f"joint {self.name}.radius", r,
                                 "must be >= 0 [m] (the pin's radius; 0: a sliding block)")
        object.__setattr__(self, "friction", f)
        object.__setattr__(self, "radius", r)

    @property
    def has_friction(self) -> bool:
        return self.friction > 0

    def friction_wrench(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr,
                        width: tuple[float, float]) -> tuple[Arr, Arr, Arr]:
        """``-f |N| sign(s)`` along the slot at the contact point, moved to the pin's centre."""
        ux, uy = st.rot(r.ia, r.u_loc)
        N = -uy * fx + ux * fy
        vx, vy, dw = self.relative_motion(st, r)
        slip = ux * vx + uy * vy
        if self.radius > 0:
            slip = slip + self.radius * np.sign(N) * dw
        sg = smooth_sign(slip, width[1])
        ft = -self.friction * np.abs(N) * sg
        return ft * ux, ft * uy, -self.radius * self.friction * N * sg


def row_entries(ia: int, ib: int, row: Row) -> list[tuple[int, Any]]:
    """The (body index, (d/dx, d/dy, d/dtheta)) entries of a constraint row: its bodies a and b
    and, for a gear pair, its carrier (``"jc"``: (index, coefficients))."""
    out = [(ia, row["ja"]), (ib, row["jb"])]
    if "jc" in row:
        out.append(row["jc"])
    return out


@dataclass(frozen=True)
class GearPair(Joint):
    """Gear pair (higher pair): gear ``b`` meshes with gear ``a``, both turning on ``carrier``.

    Both gears are hinged to the carrier by revolute joints (their centres); ``carrier`` is a
    moving arm (a planetary train) or, by default (None), the frame. The pair keeps the pitch
    circles rolling: relative to the carrier, ``omega_b' = -s k omega_a'`` with ``k = r_a /
    r_b`` and ``s = +1`` for an external pair (opposite senses), ``-1`` for an internal one
    (``b`` the ring with internal teeth, ``a`` the pinion inside it: the same sense);
    positions ``theta_b' = offset - s k theta_a'`` (angles relative to the carrier; ``offset``
    the angle of b when a's is 0, taken from the drawing by :func:`~linkwork.planar.sketch`).

    Parameters
    ----------
    name, a, b : str
        Joint name, first gear, second gear (the ring of an internal pair).
    teeth : (int, int), optional
        Tooth numbers of a and b: the ratio; the pitch radii then follow from the distance of
        the centres (``r_a + r_b`` or ``r_b - r_a``).
    radii : (float, float), optional
        Or the pitch radii [m]; the distance of the centres must equal their sum (difference).
    internal : bool
        An internal pair (b the ring).
    carrier : str, optional
        The body carrying both gears' pivots; default the frame.
    pressure_angle : float
        Pressure angle alpha [rad] of the teeth (default 20 deg): the tooth force acts along
        the line of action, its radial (separating) part ``|F_t| tan(alpha)`` pushing the
        gears apart, carried by their pivots.
    efficiency : float
        Mesh efficiency eta (0 < eta <= 1; 1: no losses): the power the driven gear receives
        through the mesh is eta times what the driving gear gives (relative to the carrier);
        the loss is a couple pair on the gears opposing their relative rotation
        (``docs/friction.md``).
    offset : float
        Angle of b relative to the carrier when a's is 0 [rad].

    Reaction (by a on b) at the pitch point P: the tangential tooth force ``F_t`` along the
    common tangent t (the constraint's multiplier) plus the separating force ``|F_t|
    tan(alpha)`` along the line of centres, i.e. the force along the line of action; with
    eta < 1 also the loss couple ``mz``.
    """

    teeth: tuple[int, int] | None = None
    radii: tuple[float, float] | None = None
    internal: bool = False
    carrier: str | None = None
    pressure_angle: float = math.radians(20.0)
    efficiency: float = 1.0
    offset: float = 0.0
    n_constraints = 1
    code = "G"
    row_kinds: ClassVar[tuple[str, ...]] = ("t",)
    spatial_family: ClassVar[str | None] = "G"

    def __post_init__(self) -> None:
        if (self.teeth is None) == (self.radii is None):
            raise ParameterError(f"joint {self.name}.teeth", self.teeth,
                                 "give the ratio either by teeth (z_a, z_b) or by radii "
                                 "(r_a, r_b) [m], not both or neither")
        pair = self.teeth if self.teeth is not None else self.radii
        key = "teeth" if self.teeth is not None else "radii"
        try:
            va, vb = (require_number(f"joint {self.name}.{key}", v) for v in pair)  # type: ignore[union-attr]
        except (TypeError, ValueError):
            raise ParameterError(f"joint {self.name}.{key}", pair, "must be a pair") from None
        for v in (va, vb):
            if not v > 0 or (key == "teeth" and v != int(v)):
                raise ParameterError(f"joint {self.name}.{key}", pair, "must be two positive "
                                     + ("whole numbers" if key == "teeth" else "radii [m]"))
        if self.internal and not va < vb:
            raise ParameterError(f"joint {self.name}.{key}", pair, "an internal pair's ring "
                                 "(b) must be larger than its pinion (a)")
        alpha = require_number(f"joint {self.name}.pressure_angle", self.pressure_angle)
        if not 0.0 <= alpha < math.radians(45.0):
            raise ParameterError(f"joint {self.name}.pressure_angle", alpha,
                                 "must lie in [0, 45 deg) [rad] (20 deg is usual)")
        eta = require_number(f"joint {self.name}.efficiency", self.efficiency)
        if not 0.0 < eta <= 1.0:
            raise ParameterError(f"joint {self.name}.efficiency", eta, "must lie in (0, 1]")
        if self.internal and eta < 1.0 and va / vb >= eta:
            raise ParameterError(f"joint {self.name}.efficiency", eta, f"must exceed the "
                                 f"internal pair's ratio r_a/r_b = {va / vb:g} (a pinion "
                                 "nearly as large as its ring)")
        require_number(f"joint {self.name}.offset", self.offset)
        object.__setattr__(self, "pressure_angle", alpha)
        object.__setattr__(self, "efficiency", eta)

    # -- description ------------------------------------------------------------------------
    def carrier_of(self, frame: str) -> str:
        """The body carrying both gears' pivots."""
        return self.carrier if self.carrier is not None else frame

    def check_points(self, ba: _BodyLike, bb: _BodyLike) -> None:
        pass  # the centres are the pivots on the carrier (checked by resolve)

    def local_geometry(self, ba: _BodyLike, bb: _BodyLike) -> tuple[Point, Point, float]:
        raise NotImplementedError("a gear pair's geometry needs its mechanism: resolve()")

    def resolve(self, mech: Any) -> tuple[Point, Point, float, int, tuple[float, ...]]:
        """Centres of the gears on a and b (their pivots on the carrier), the carrier's index
        and (r_a, r_b, s, offset); raises ParameterError when a gear is not hinged to the
        carrier or the radii do not fit the distance of the centres."""
        carrier = self.carrier_of(mech.frame.name)
        if carrier not in mech.body_names:
            raise ParameterError(f"joint {self.name}.carrier", carrier,
                                 f"no such body; known: {list(mech.body_names)}")
        if carrier in (self.a, self.b):
            raise ParameterError(f"joint {self.name}.carrier", carrier, "must differ from the "
                                 "two gears (the body both are hinged to)")
        centres = []
        for gear in (self.a, self.b):
            pivot = next((j for j in mech.joints if j.is_pivot and {j.a, j.b} == {gear, carrier}),
                         None)
            if pivot is None:
                raise ParameterError(f"joint {self.name}", gear, f"gear {gear!r} must be hinged "
                                     f"to the carrier {carrier!r} by a revolute joint (its "
                                     "centre)")
            qa, pb, _ = pivot.local_geometry(mech.body(pivot.a), mech.body(pivot.b))
            on_gear, on_carrier = (qa, pb) if pivot.a == gear else (pb, qa)
            centres.append((on_gear, on_carrier))
        (ca, oa), (cb, ob) = centres
        if any(isinstance(v, np.ndarray) for c in centres for p in c for v in p):
            raise ParameterError(f"joint {self.name}", "gear centres per design",
                                 "a gear pair whose centres vary over the designs is not "
                                 "batched yet: analyse such designs one at a time")
        d = math.hypot(ob[0] - oa[0], ob[1] - oa[1])
        s = -1.0 if self.internal else 1.0
        if self.teeth is not None:
            za, zb = self.teeth
            if d == 0.0:
                raise ParameterError(f"joint {self.name}", "centres", "the gears' centres "
                                     "coincide on the carrier")
            ra = d * za / (zb - za) if self.internal else d * za / (za + zb)
            rb = ra * zb / za
        else:
            ra, rb = self.radii  # type: ignore[misc]
            want = rb - ra if self.internal else ra + rb
            if abs(d - want) > 1e-6 * max(d, want):
                raise AssemblyError(f"joint {self.name}: the gears are not assembled: their "
                                    f"centres are {d * 1e3:.6g} mm apart on the carrier, the "
                                    f"pitch radii ({ra * 1e3:g}, {rb * 1e3:g} mm) need "
                                    f"{want * 1e3:.6g} mm")
        return ca, cb, 0.0, mech.index[carrier], (float(ra), float(rb), s, float(self.offset))

    # -- constraints ------------------------------------------------------------------------
    def _frame(self, st: State, r: ResolvedJoint) -> tuple[Vec, Vec, Vec]:
        """Pitch point P, unit e along the line of centres (from a's centre towards b's for an
        external pair, from b's towards a's for an internal one) and the tangent t = k x e."""
        ra, _, s, _ = r.params
        Oa, Ob = st.wpt(r.ia, r.qa), st.wpt(r.ib, r.pb)
        dx, dy = Ob[0] - Oa[0], Ob[1] - Oa[1]
        d = np.hypot(dx, dy)
        ex, ey = s * dx / d, s * dy / d
        return (Oa[0] + ra * ex, Oa[1] + ra * ey), (ex, ey), (-ey, ex)

    def constraint_rows(self, st: State, r: ResolvedJoint, need_gamma: bool = True
                        ) -> list[Row]:
        """``theta_b' + s k theta_a' - offset = 0`` (angles relative to the carrier)."""
        ra, rb, s, off = r.params
        k = s * ra / rb
        zero = np.zeros(st.n)
        res = st.T[r.ib] - st.T[r.ic] + k * (st.T[r.ia] - st.T[r.ic]) - off
        return [{"ja": (zero, zero, zero + k), "jb": (zero, zero, zero + 1.0),
                 "jc": (r.ic, (zero, zero, zero - 1.0 - k)), "gam": zero, "res": res}]

    def equilibrium_rows(self, st: State, r: ResolvedJoint) -> list[Row]:
        """The rolling of the pitch circles, ``t . (v_b(P) - v_a(P)) = 0``: its multiplier is
        the tangential tooth force at P (equal to ``-r_b`` times the angle row on the motions
        the pivots allow)."""
        P, _, (tx, ty) = self._frame(st, r)
        rax, ray = P[0] - st.X[r.ia], P[1] - st.Y[r.ia]
        rbx, rby = P[0] - st.X[r.ib], P[1] - st.Y[r.ib]
        return [{"ja": (-tx, -ty, -(rax * ty - ray * tx)), "jb": (tx, ty, rbx * ty - rby * tx),
                 "res": np.zeros(st.n)}]

    def reaction_point(self, st: State, r: ResolvedJoint) -> Vec:
        """The pitch point P."""
        return self._frame(st, r)[0]

    def reaction_components(self, st: State, r: ResolvedJoint, kind: str, lam: Arr
                            ) -> dict[str, Arr]:
        """The tangential tooth force ``-lam t`` on b at P."""
        _, _, (tx, ty) = self._frame(st, r)
        return {"fx": -lam * tx, "fy": -lam * ty}

    @property
    def has_separation(self) -> bool:
        return self.pressure_angle > 0.0

    def separation(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr) -> tuple[Arr, Arr]:
        """The separating force ``|F_t| tan(alpha) e`` on b (along the line of centres, so the
        same at P and at the centres) for the tangential force (fx, fy) on b."""
        _, (ex, ey), (tx, ty) = self._frame(st, r)
        fr = np.abs(fx * tx + fy * ty) * math.tan(self.pressure_angle)
        return fr * ex, fr * ey

    # -- friction: the mesh efficiency ------------------------------------------------------
    @property
    def has_friction(self) -> bool:
        return self.efficiency < 1.0

    def friction_wrench(self, st: State, r: ResolvedJoint, fx: Arr, fy: Arr, mz: Arr,
                        width: tuple[float, float]) -> tuple[Arr, Arr, Arr]:
        """The loss couple M on b (-M on a): with the tangential force F_t on b and a's
        rotation w_a' relative to the carrier, the mesh passes Pi = F_t r_a w_a' to b; when a
        drives (Pi > 0) ``M = (1 - eta) F_t r_a / (s k + eta)``, when b drives ``M = -(1 -
        eta) F_t r_a / (1 + eta s k)``: then the driven gear receives eta times the power the
        driving one gives (relative to the carrier), and M opposes the relative rotation."""
        ra, rb, s, _ = r.params
        k = ra / rb
        eta = self.efficiency
        _, _, (tx, ty) = self._frame(st, r)
        ft = fx * tx + fy * ty
        wa = st.W[r.ia] - st.W[r.ic]
        sg = smooth_sign(wa, width[0])
        drive = ft * sg  # > 0: a drives b
        m = np.where(drive >= 0.0, (1 - eta) * ft * ra / (s * k + eta),
                     -(1 - eta) * ft * ra / (1 + eta * s * k)) * np.abs(sg)
        z = np.zeros(st.n)
        return z, z, m

    def transmitted_direction(self, st: State, r: ResolvedJoint, first: Any, P: Vec) -> Vec:
        _, _, t = self._frame(st, r)
        return t

    def scene_shapes(self, ctx: Any) -> list[Any]:
        """The drawing of the pair (:func:`linkwork.plot.scene.gear_shapes`): the two pitch
        circles (b's named ``joint <name>``, a's ``gear <name> <a>``) with spokes turning with
        the gears, an internal gear's rim, and the pitch point."""
        from linkwork.plot.scene import gear_shapes  # drawing only: the plot layer, lazily

        qa, pb, _, _, params = self.resolve(ctx.mechanism)
        return gear_shapes(ctx, self.name, self.a, qa, params[0], self.b, pb, params[1],
                           internal=self.internal)
