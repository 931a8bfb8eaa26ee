"""Structure of a planar mechanism: mobility and decomposition into the driver and Assur groups.

Mobility by the Chebyshev-Gruebler formula for planar chains,

.. math:: W = 3 n - 2 p_5 - p_4,

with ``n`` moving bodies, ``p_5`` lower pairs (revolute, prismatic: 2 constraints each) and
``p_4`` higher pairs (pin-in-slot: 1 constraint). ``W`` must equal the number of drivers (one
per degree of freedom: cranks and linear actuators).

The decomposition repeatedly takes the smallest set of not-yet-solved bodies whose joints to
each other and to solved bodies impose exactly ``3 k`` constraints (the driver adds one to its
joint): that set is the next group (the driver's own body first, then Assur groups), solvable
once the bodies before it are known. Group kinds:

* ``"driver"`` -- the driven body (1 body, driver joint).
* dyads (class II, order 2), named by the pair types along the chain
  ``external joint of the first body - joint between the bodies - external joint of the second``:
  ``"RRR", "RRP", "PRR", "RPR", "RPP", "PPR", "PRP"``; solved in closed form.
* one body with a pin-in-slot pair (the pin-in-slot variants of the RPR/RRP/RPP dyads with
  the slider block removed): ``"RS"`` (revolute + slot), ``"PS"`` (prismatic + slot); closed
  form.
* a gear turning on its carrier and meshing with a known gear: ``"RG"``; closed form (its
  angle from the gear ratio).
* a driven cylinder (a linear driver on the prismatic pair between two moving bodies, each
  hinged at one pivot) with the body it moves: ``"cyl-RRR"`` (that body hinged to a known body:
  the cylinder triangle, circle about the cylinder's pivot with the cylinder's length as radius
  intersected with the body's circle) or ``"cyl-RRP"`` (the body sliding on a known guide);
  closed form, its branch keyed by the joint between the cylinder and the body.
* anything else (class III and higher, groups with several slots): ``"newton"``, solved by
  Newton's method continued from the previous position. A driver placed on a joint between two
  moving bodies ends up inside such a group (it is then not an Assur group; its class is
  nominal).

Each group has a ``key`` for its assembly branch (``Mechanism.branches``): the joint between the
two bodies of a dyad, the slot joint of an ``RS``/``PS`` group, the first body's name for a
Newton group (whose branch is set by the bodies' ``guess`` poses).

:func:`compile_plan` turns the decomposition into what the solvers use (``Mechanism.plan``):
groups holding resolved joints (:class:`~linkwork.planar.joints.ResolvedJoint`: the joint, its
body indices and local geometry as floats), body indices and guess poses, so that the solvers
never look joints or bodies up by name.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any, Protocol

import numpy as np

from linkwork.errors import ParameterError, StructureError
from linkwork.planar.designs import Index, is_batched, pick, pick_fields
from linkwork.planar.joints import Joint, Point, ResolvedJoint

__all__ = ["CYLINDER", "HUNG", "Group", "Plan", "PlanGroup", "Structure", "analyse",
           "compile_plan", "length_scale", "mobility"]

_CLOSED = {"RRR", "RRP", "PRR", "RPR", "RPP", "PPR", "PRP"}
#: the group kinds whose rates and reactions the hung-body closure (Cramer) solves
HUNG = _CLOSED | {"RS", "PS"}
#: the driven-cylinder groups (closed-form positions, rates and reactions by the Jacobian)
CYLINDER = {"cyl-RRR", "cyl-RRP"}


class _BodyLike(Protocol):
    @property
    def name(self) -> str: ...

    @property
    def points(self) -> Mapping[str, Point]: ...

    @property
    def guess(self) -> tuple[float, float, float] | None: ...

    def point(self, name: str) -> Point: ...


class Mechanism(Protocol):
    """What the structure analysis reads of a :class:`linkwork.planar.model.Mechanism` (which
    imports this module for its ``structure`` and ``plan``; a protocol keeps the import one way).
    """

    @property
    def frame(self) -> Any: ...

    @property
    def bodies(self) -> Sequence[Any]: ...

    @property
    def joints(self) -> Sequence[Joint]: ...

    @property
    def driver(self) -> Any: ...

    @property
    def drivers(self) -> tuple[Any, ...]: ...

    @property
    def body_names(self) -> tuple[str, ...]: ...

    @property
    def index(self) -> dict[str, int]: ...

    @property
    def structure(self) -> Structure: ...

    def body(self, name: str) -> Any: ...


@dataclass(frozen=True)
class Group:
    """One group of the decomposition.

    Attributes
    ----------
    kind : str
        ``"driver"``, a dyad code (``"RRR"``, ...), ``"RS"``, ``"PS"`` or ``"newton"``.
    bodies : tuple of str
        Its bodies (for a dyad: first body = the one listed first in the mechanism).
    joints : tuple of str
        All its joints: for a dyad (J1, J2, J3) = (external of the first body, internal,
        external of the second body).
    external : tuple of str
        Joints to bodies solved before (the group's order is their number).
    cls : int
        Assur class (1 for the driver, 2 for dyads and one-body slot groups, >= 3 above).
    order : int
        Number of external joints.
    key : str
        Branch key (see the module docstring).
    """

    kind: str
    bodies: tuple[str, ...]
    joints: tuple[str, ...]
    external: tuple[str, ...]
    cls: int
    order: int
    key: str


@dataclass(frozen=True)
class Structure:
    """Result of :func:`analyse`: mobility and groups in solution order."""

    n_bodies: int
    n_lower: int
    n_higher: int
    mobility: int
    groups: tuple[Group, ...]

    def formula(self) -> str:
        """The structural formula, e.g. ``"I(crank) -> II RRR(coupler, rocker)"``."""
        roman = {1: "I", 2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI"}
        parts = []
        for g in self.groups:
            label = "I" if g.kind == "driver" else f"{roman.get(g.cls, g.cls)} {g.kind}"
            parts.append(f"{label}({', '.join(g.bodies)})")
        return " -> ".join(parts)


def _driven(mech: Mechanism) -> set[str]:
    return {d.joint for d in mech.drivers}


def _cons(mech: Mechanism, j: Joint) -> int:
    return j.n_constraints + (1 if j.name in _driven(mech) else 0)


def mobility(mech: Mechanism) -> int:
    """Chebyshev-Gruebler mobility ``3 n - 2 p5 - p4`` (the driver not counted)."""
    return 3 * len(mech.bodies) - sum(j.n_constraints for j in mech.joints)


def _largest_cycle(bodies: tuple[str, ...], joints: list[Joint]) -> int:
    adj: dict[str, set[str]] = {b: set() for b in bodies}
    for j in joints:
        if j.a in adj and j.b in adj:
            adj[j.a].add(j.b)
            adj[j.b].add(j.a)
    best = 0

    def dfs(start: str, node: str, seen: list[str]) -> None:
        nonlocal best
        for nb in adj[node]:
            if nb == start and len(seen) >= 3:
                best = max(best, len(seen))
            elif nb not in seen:
                dfs(start, nb, [*seen, nb])

    for b in bodies:
        dfs(b, b, [b])
    return best


def _describe(mech: Mechanism, bodies: set[str]) -> str:
    js = [j.name for j in mech.joints if j.a in bodies or j.b in bodies]
    return f"bodies {sorted(bodies)}, joints {js}"


def analyse(mech: Mechanism) -> Structure:
    """Mobility and Assur-group decomposition of ``mech``.

    Raises
    ------
    StructureError
        The mechanism is locked (mobility < 1), under-driven (mobility > 1), has a sub-chain
        with more constraints than coordinates, or a set of bodies that no group order can
        solve; the message names the bodies and joints involved.
    """
    if not all(hasattr(mech, a) for a in ("frame", "bodies", "joints", "driver", "body_names")):
        raise ParameterError("mech", mech, "must be a Mechanism")
    n = len(mech.bodies)
    p5 = sum(1 for j in mech.joints if j.n_constraints == 2)
    p4 = sum(1 for j in mech.joints if j.n_constraints == 1)
    w = mobility(mech)
    everything = set(mech.body_names[1:])
    jointless = [b for b in mech.body_names[1:]
                 if not any(b in (j.a, j.b) for j in mech.joints)]
    if jointless:  # its 3 free coordinates would only show as "under-driven (W = 4)"
        raise StructureError(
            f"bod{'ies' if len(jointless) > 1 else 'y'} {', '.join(map(repr, jointless))} "
            f"{'have' if len(jointless) > 1 else 'has'} no joints: connect "
            f"{'them' if len(jointless) > 1 else 'it'} to the frame or another body, or "
            f"leave {'them' if len(jointless) > 1 else 'it'} out")
    nd = len(mech.drivers)
    given = ", ".join(d.joint for d in mech.drivers)
    drivers = f"one driver ({given}) is" if nd == 1 else f"{nd} drivers ({given}) are"
    if w < 1:
        raise StructureError(
            f"mechanism is locked: mobility W = 3*{n} - 2*{p5} - {p4} = {w} < 1 "
            f"({_describe(mech, everything)})")
    if w > nd:
        raise StructureError(
            f"mechanism is under-driven: mobility W = 3*{n} - 2*{p5} - {p4} = {w} but "
            f"{drivers} given: give {w} drivers, one per degree of freedom "
            f"({_describe(mech, everything)})")
    if w < nd:
        raise StructureError(
            f"mechanism is over-driven: mobility W = 3*{n} - 2*{p5} - {p4} = {w} but "
            f"{drivers} given: give {w} driver{'s' if w > 1 else ''} "
            f"({_describe(mech, everything)})")
    known = {mech.frame.name}
    unknown = list(mech.body_names[1:])
    groups: list[Group] = []
    while unknown:
        found = None
        for k in range(1, min(len(unknown), 8) + 1):
            for combo in itertools.combinations(unknown, k):
                s = set(combo)
                js = [j for j in mech.joints
                      if (j.a in s or j.b in s) and j.a in s | known and j.b in s | known
                      and _carrier(mech, j) in s | known]
                c = sum(_cons(mech, j) for j in js)
                if c > 3 * k:
                    raise StructureError(
                        f"sub-chain is locked: {c} constraints on {3 * k} coordinates "
                        f"({_describe(mech, s)})")
                if c == 3 * k and (k == 1 or _connected(combo, js)):
                    found = (combo, js)
                    break
            if found:
                break
        if found is None:
            raise StructureError(
                f"no Assur group can be solved among {_describe(mech, set(unknown))}: "
                "they are not determined by the bodies solved before (under-driven part or "
                "a joint missing)")
        combo, js = found
        groups.append(_make_group(mech, combo, js, known))
        known |= set(combo)
        unknown = [u for u in unknown if u not in combo]
    return Structure(n, p5, p4, w, tuple(groups))


def _carrier(mech: Mechanism, j: Joint) -> str:
    """The third body a joint involves (a gear pair's carrier), else its body a."""
    c = j.carrier_of(mech.frame.name)
    return j.a if c is None else c


def _connected(bodies: tuple[str, ...], joints: list[Joint]) -> bool:
    seen = {bodies[0]}
    changed = True
    while changed:
        changed = False
        for j in joints:
            if j.a in bodies and j.b in bodies and (j.a in seen) != (j.b in seen):
                seen |= {j.a, j.b}
                changed = True
    return len(seen) == len(bodies)


def _make_group(mech: Mechanism, combo: tuple[str, ...], js: list[Joint],
                known: set[str]) -> Group:
    order = [b for b in mech.body_names if b in combo]
    ext = [j for j in js if not (j.a in combo and j.b in combo)]
    internal = [j for j in js if j.a in combo and j.b in combo]
    driven = _driven(mech)
    if len(order) == 1 and any(j.name in driven for j in js) and len(js) == 1:
        return Group("driver", tuple(order), (js[0].name,), (js[0].name,), 1, 1, js[0].name)
    kind = "newton"
    key = order[0]
    joints = [j.name for j in js]
    drv = any(j.name in driven for j in js)
    if len(order) == 2 and len(js) == 3 and len(internal) == 1 and not drv:
        b1, b2 = order
        e1 = [j for j in ext if b1 in (j.a, j.b)]
        e2 = [j for j in ext if b2 in (j.a, j.b)]
        if len(e1) == 1 and len(e2) == 1 and all(j.n_constraints == 2 for j in js):
            code = e1[0].code + internal[0].code + e2[0].code
            if code in _CLOSED:
                kind, key = code, internal[0].name
                joints = [e1[0].name, internal[0].name, e2[0].name]
    elif len(order) == 1 and len(js) == 2 and not drv:
        two = [j for j in js if j.n_constraints == 2]
        one = [j for j in js if j.n_constraints == 1]
        if len(two) == 1 and len(one) == 1 and one[0].code == "G":
            if two[0].is_pivot and _carrier(mech, one[0]) in (two[0].a, two[0].b):
                kind, key = "RG", one[0].name  # a gear turning on its carrier
                joints = [two[0].name, one[0].name]
        elif len(two) == 1 and len(one) == 1:
            kind, key = two[0].code + "S", one[0].name
            joints = [two[0].name, one[0].name]
    if kind == "newton" and len(order) == 3 and len(js) == 4 and drv:
        cyl = _cylinder(order, js, driven, mech.frame.name)
        if cyl is not None:
            kind, key, joints = cyl
    if kind == "newton":
        cyc = _largest_cycle(tuple(order), js)
        deg = max(sum(1 for j in js if b in (j.a, j.b)) for b in order)
        cls = max(3, cyc, deg) if len(order) > 2 else 2
    else:
        cls = 2
    return Group(kind, tuple(order), tuple(joints), tuple(j.name for j in ext), cls, len(ext),
                 key)


def _cylinder(order: list[str], js: list[Joint], driven: set[str], frame: str
              ) -> tuple[str, str, list[str]] | None:
    """A driven cylinder and the body it moves: (kind, key, joints (A, cylinder, C, X's
    external joint)), or None for another group of three bodies."""
    cyl = [j for j in js if j.name in driven and j.code == "P" and j.a in order and j.b in order]
    if len(cyl) != 1:
        return None
    d = cyl[0]
    x = next(b for b in order if b not in (d.a, d.b))
    rest = [j for j in js if j is not d]
    to_x = [j for j in rest if x in (j.a, j.b) and ({j.a, j.b} & {d.a, d.b})]
    ext_x = [j for j in rest if x in (j.a, j.b) and not ({j.a, j.b} & {d.a, d.b})]
    ext_c = [j for j in rest if x not in (j.a, j.b)]
    if (len(to_x), len(ext_x), len(ext_c)) != (1, 1, 1):
        return None
    jc, jx, ja = to_x[0], ext_x[0], ext_c[0]
    if not (ja.is_pivot and jc.is_pivot and jx.n_constraints == 2):
        return None
    if ({ja.a, ja.b} & {d.a, d.b}) == ({jc.a, jc.b} & {d.a, d.b}):
        return None  # both pivots on one cylinder body: the other one is not held
    kind = "cyl-RRR" if jx.is_pivot else "cyl-RRP"
    return kind, jc.name, [ja.name, d.name, jc.name, jx.name]


# ---------------------------------------------------------------------------------------------
# the compiled plan
@dataclass(frozen=True, eq=False)
class PlanGroup:
    """A group of the plan: its :class:`Group`, body indices, resolved joints (in the order of
    ``Group.joints``) and the bodies' guess poses (Newton groups)."""

    group: Group
    kind: str
    key: str
    bodies: tuple[int, ...]
    joints: tuple[ResolvedJoint, ...]
    guesses: tuple[tuple[float, float, float] | None, ...]


@dataclass(frozen=True, eq=False)
class Plan:
    """What the solvers of a mechanism need, resolved once (``Mechanism.plan``).

    Attributes
    ----------
    body_names : tuple of str
        Body names, frame first (index 0).
    joints : tuple of ResolvedJoint
        All joints in the mechanism's order.
    groups : tuple of PlanGroup
        The groups in solution order.
    driver : ResolvedJoint
        The (first) driver's joint.
    driver_kind : str
        ``"crank"`` (a torque about a pivot) or ``"linear"`` (a force along a guide): the first
        driver's.
    drivers : tuple of ResolvedJoint
        Every driver's joint, in the order of ``Mechanism.drivers`` (``drive_index`` 0, 1, ...).
    driver_kinds : tuple of str
        Their kinds.
    length_scale : float
        The largest point coordinate [m] (at least 1 mm): the scale of Newton's tolerance and
        of the singularity tests.
    newton : bool
        Some group is solved by Newton iteration (positions are then solved as one sequence).
    global_reactions : bool
        Some group is not a hung-body group (Newton, driven cylinder): the reactions are solved
        with the whole constraint Jacobian.
    """

    body_names: tuple[str, ...]
    joints: tuple[ResolvedJoint, ...]
    groups: tuple[PlanGroup, ...]
    driver: ResolvedJoint
    driver_kind: str
    length_scale: float
    newton: bool
    drivers: tuple[ResolvedJoint, ...] = ()
    driver_kinds: tuple[str, ...] = ()

    @property
    def global_reactions(self) -> bool:
        return any(g.kind not in HUNG and g.kind != "driver" for g in self.groups)

    @property
    def nb(self) -> int:
        """Number of bodies, the frame included."""
        return len(self.body_names)

    def pick(self, index: Index) -> Plan:
        """The plan of the designs ``index`` of a batch (:func:`linkwork.planar.designs.pick`):
        a design (an int: every value a Python float, the one-design plan) or the designs of
        a block of flattened (design, position) elements (an index array)."""
        joints = {id(r): _pick_joint(r, index) for r in self.joints}
        groups = tuple(PlanGroup(g.group, g.kind, g.key, g.bodies,
                                 tuple(joints[id(r)] for r in g.joints),
                                 tuple(pick(gs, index) for gs in g.guesses))
                       for g in self.groups)
        return Plan(self.body_names, tuple(joints[id(r)] for r in self.joints), groups,
                    joints[id(self.driver)], self.driver_kind, pick(self.length_scale, index),
                    self.newton, tuple(joints[id(r)] for r in self.drivers), self.driver_kinds)


def _pick_joint(r: ResolvedJoint, index: Index) -> ResolvedJoint:
    """A resolved joint at the designs ``index`` (its joint's fields too)."""
    if not (is_batched((r.qa, r.pb, r.ang, r.u_loc, r.params))
            or any(is_batched(getattr(r.joint, f.name)) for f in fields(r.joint))):
        return r
    return ResolvedJoint(pick_fields(r.joint, index), r.index, r.ia, r.ib, pick(r.qa, index),
                         pick(r.pb, index), pick(r.ang, index), pick(r.u_loc, index), r.drive,
                         r.drive_index, r.ic, pick(r.params, index))


def length_scale(mech: Mechanism) -> Any:
    """The largest absolute point coordinate of the mechanism's bodies [m], at least 1 mm
    (per design, an array over the designs, for a batch)."""
    pts = [abs(c) for b in (mech.frame, *mech.bodies) for p in b.points.values() for c in p]
    if any(isinstance(c, np.ndarray) for c in pts):
        out = np.maximum(np.max(np.broadcast_arrays(*pts), axis=0), 1e-3)
        out.flags.writeable = False
        return out
    return max(max(pts, default=1.0), 1e-3)


def compile_plan(mech: Mechanism) -> Plan:
    """The plan of ``mech``: its structure with joints and bodies resolved to indices and local
    geometry (raises StructureError as :func:`analyse`)."""
    index = mech.index
    drive_index = {d.joint: i for i, d in enumerate(mech.drivers)}
    resolved: dict[str, ResolvedJoint] = {}
    for k, j in enumerate(mech.joints):
        qa, pb, ang, ic, params = j.resolve(mech)
        u_loc = ((np.cos(ang), np.sin(ang)) if isinstance(ang, np.ndarray)
                 else (float(np.cos(ang)), float(np.sin(ang))))
        resolved[j.name] = ResolvedJoint(j, k, index[j.a], index[j.b], qa, pb, ang, u_loc,
                                         j.name in drive_index, drive_index.get(j.name, -1),
                                         ic, params)
    groups = tuple(
        PlanGroup(g, g.kind, g.key, tuple(index[b] for b in g.bodies),
                  tuple(resolved[n] for n in g.joints),
                  tuple(mech.body(b).guess for b in g.bodies))
        for g in mech.structure.groups)
    first = mech.drivers[0]
    return Plan(mech.body_names, tuple(resolved[j.name] for j in mech.joints), groups,
                resolved[first.joint], first.kind, length_scale(mech),
                any(g.kind == "newton" for g in groups),
                tuple(resolved[d.joint] for d in mech.drivers),
                tuple(d.kind for d in mech.drivers))
