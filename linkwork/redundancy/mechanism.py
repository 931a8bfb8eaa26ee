"""Spatial reactions of a mechanism of the planar engine (:mod:`linkwork.planar`).

Feeds the array core (:mod:`linkwork.redundancy.core`) from a
:class:`~linkwork.planar.Mechanism` and its :func:`~linkwork.planar.kinematics`: joint centres,
body angles, slide directions and the body wrenches (gravity, d'Alembert inertia forces and
moments, external loads, optional out-of-plane loads and heights of the centres of mass).

Joints: a planar :class:`~linkwork.planar.Revolute` becomes a revolute-family spatial joint
centred on its point; a :class:`~linkwork.planar.Prismatic` a prismatic-family joint centred on
the slider point with the slide direction ``theta_a + angle``; a
:class:`~linkwork.planar.GearPair` a gear mesh (kind ``"spur"``: the teeth in line contact
across the face width carry the tooth force along the line of action and the moment that would
tilt the contact line; ``"crowned"``: the force only) centred on the pitch point, its line of
action the one the tooth force acts along (the flank in contact, from the sign of the
tangential tooth force). Pin-in-slot joints are not supported: a pin in a straight slot, seen in
space, is a line or a point contact whose class depends on the pin's and slot's shapes, which
the planar description does not give.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.errors import ParameterError, StructureError
from linkwork.planar import forces
from linkwork.planar.inertia import inertia_wrenches
from linkwork.planar.kinematics import kinematics
from linkwork.redundancy.core import (
    JOINT_KINDS,
    SpatialGeometry,
    SpatialJoint,
    SpatialModel,
    SpatialReactions,
    check_tilt,
    inplane_solution,
    solve_reactions,
)

__all__ = [
    "Deviation",
    "OutOfPlaneLoad",
    "body_wrenches",
    "deviation_array",
    "geometry",
    "spatial_model",
    "spatial_reactions",
]


@dataclass(frozen=True)
class Deviation:
    """Manufacturing deviation of the element of ``joint`` carried by ``body``.

    Offsets ``dx, dy, dz`` [m] of the element's centre and small rotations (tilts) ``tx, ty``
    (and ``tz``, which only matters for prismatic joints) [rad] of its axis about the nominal
    centre, in ``body``'s own frame (the engine's body frame; the ground's is the fixed frame).
    """

    joint: str
    body: str
    dx: float = 0.0
    dy: float = 0.0
    dz: float = 0.0
    tx: float = 0.0
    ty: float = 0.0
    tz: float = 0.0

    def vector(self) -> np.ndarray:
        """(dx, dy, dz, tx, ty, tz) [m, rad]; tilts beyond ``MAX_TILT`` are a ParameterError."""
        v = require_finite(f"deviation {self.joint}/{self.body}",
                           [self.dx, self.dy, self.dz, self.tx, self.ty, self.tz])
        for c, x in zip(("tx", "ty", "tz"), v[3:], strict=True):
            check_tilt(f"deviation {self.joint}/{self.body}.{c}", x)
        return v


@dataclass(frozen=True)
class OutOfPlaneLoad:
    """External out-of-plane load on ``body``: force ``fz`` [N] at the centre of mass (at the
    body's height) and moments ``mx``, ``my`` [N·m] about the fixed x, y axes."""

    body: str
    fz: float = 0.0
    mx: float = 0.0
    my: float = 0.0


#: the spatial kind a planar joint becomes by default, per family
_DEFAULT_KIND = {"R": "revolute", "P": "prismatic", "G": "spur"}
_FAMILY_NAME = {"R": "revolute", "P": "prismatic", "G": "gear mesh"}


def _ground(mech: Any) -> str:
    return str(mech.frame.name)


def spatial_model(mech: Any, joints: Mapping[str, Mapping[str, Any]] | None = None,
                  default: Mapping[str, Any] | None = None) -> SpatialModel:
    """The spatial model of an engine mechanism.

    Parameters
    ----------
    mech : linkwork.planar.Mechanism
    joints : mapping joint name -> mapping, optional
        Per-joint keyword arguments of :class:`~linkwork.redundancy.SpatialJoint` (``kind``,
        ``e``, ``z``, ``stiffness``, ``k_bearing``, ``axial_ratio``).
    default : mapping, optional
        Keyword arguments used for joints not in ``joints`` (and under theirs).

    Returns
    -------
    SpatialModel
        Bodies in the mechanism's order, the frame renamed ``"ground"``.
    """
    joints = dict(joints or {})
    known = {j.name for j in mech.joints}
    for name in joints:
        if name not in known:
            raise ParameterError("joints", name, f"no such joint; known: {sorted(known)}")
    ground = _ground(mech)
    out = []
    for j in mech.joints:
        family = j.spatial_family  # "R" revolute-like, "P" prismatic-like, "G" gear mesh
        if family is None:
            raise StructureError(f"joint {j.name}: pin-in-slot joints are not supported by the "
                                 "spatial (redundancy) analysis: in space a pin in a slot is a "
                                 "line or point contact whose class the planar description "
                                 "does not give; model it as a slider block (a revolute and a "
                                 "prismatic joint)")
        base = dict(default or {})
        if base.get("kind") in JOINT_KINDS and JOINT_KINDS[base["kind"]][0] != family:
            del base["kind"]  # the default kind is for the joints of its own family
        kw = {**base, **dict(joints.get(j.name, {}))}
        kw.setdefault("kind", _DEFAULT_KIND[family])
        if kw["kind"] in JOINT_KINDS and JOINT_KINDS[kw["kind"]][0] != family:
            kinds = sorted(k for k, v in JOINT_KINDS.items() if v[0] == family)
            raise ParameterError(f"{j.name}.kind", kw["kind"],
                                 f"must be one of {kinds} for a planar {type(j).__name__} "
                                 f"joint ({_FAMILY_NAME[family]} family)")
        a = "ground" if j.a == ground else j.a
        b = "ground" if j.b == ground else j.b
        out.append(SpatialJoint(j.name, a, b, **kw))
    drivers = tuple(d.joint for d in mech.drivers)
    return SpatialModel(tuple(b.name for b in mech.bodies), tuple(out),
                        drivers[0] if len(drivers) == 1 else drivers)


def _mesh(mech: Any, kin: Any, j: Any) -> tuple[Any, Any, np.ndarray, np.ndarray]:
    """A gear pair's pitch point (x, y) and the angles of its two lines of action over the
    positions [rad]: for a tangential tooth force on b along +t (t = z x e, e along the line of
    centres from a's centre outwards) and along -t; each line tilts from +-t by the pressure
    angle towards e (the separating part pushes b away from a)."""
    ca, cb, _, _, params = j.resolve(mech)
    ra, s = params[0], params[2]
    oa, ob = kin.point(j.a, ca), kin.point(j.b, cb)
    dx, dy = ob.x - oa.x, ob.y - oa.y
    d = np.hypot(dx, dy)
    ex, ey = s * dx / d, s * dy / d
    t = np.arctan2(ex, -ey)  # the direction of t = (-ey, ex)
    alpha = j.pressure_angle
    return oa.x + ra * ex, oa.y + ra * ey, t - alpha, t + np.pi + alpha


def geometry(mech: Any, kin: Any, wrenches: ArrayLike | None = None) -> SpatialGeometry:
    """Joint centres, body angles and slide directions from the engine's kinematics.

    A gear pair's centre is its pitch point, its line the line of action the tooth force acts
    along at each position: given the body ``wrenches`` (:func:`body_wrenches`), the one of the
    sign of the tangential tooth force they cause (the flank in contact: the in-plane problem
    alone, :func:`~linkwork.redundancy.inplane_solution`); without them the line for a
    tangential force on b along +t.
    """
    n = kin.n
    pts = np.zeros((n, len(mech.joints), 2))
    slide = np.zeros((n, len(mech.joints)))
    flip: dict[int, np.ndarray] = {}
    for k, j in enumerate(mech.joints):
        if j.spatial_family == "G":
            pts[:, k, 0], pts[:, k, 1], slide[:, k], flip[k] = _mesh(mech, kin, j)
            continue
        _, pb, ang = mech.joint_geometry(j)
        pm = kin.point(j.b, pb)
        pts[:, k, 0], pts[:, k, 1] = pm.x, pm.y
        if j.spatial_family == "P":  # the slide direction of a prismatic joint
            slide[:, k] = kin.angle(j.a) + ang
    angles = np.stack([kin.angle(b.name) for b in mech.bodies], axis=1)
    if not np.all(np.isfinite(pts)):
        raise ParameterError("kinematics", "NaN", "must be assembled at every position")
    geom = SpatialGeometry(pts, angles, slide)
    if flip and wrenches is not None:  # each mesh on the flank its tooth force presses
        labels, r = inplane_solution(spatial_model(mech), geom, wrenches)
        for k, other in flip.items():
            fn = r[:, labels.index((mech.joints[k].name, "fn"))]
            slide[:, k] = np.where(fn < 0.0, other, slide[:, k])
        geom = SpatialGeometry(pts, angles, slide)
    return geom


def body_wrenches(mech: Any, kin: Any, *, gravity: ArrayLike | None = None,
                  loads: Sequence[Any] = (), heights: Mapping[str, float] | None = None,
                  out_of_plane: Sequence[OutOfPlaneLoad] = ()) -> np.ndarray:
    r"""Wrench about the origin on every moving body: gravity + inertia + external loads.

    .. math:: \mathbf{F} = m(\mathbf{g} - \mathbf{a}_S) + \sum \mathbf{F}_{ext},\quad
              M_z = -I_S \varepsilon + \sum M_{ext},

    the force of each body applied at its centre of mass lifted to the height ``heights[body]``
    [m] (default 0, the plane of the joints' z = 0), the forces of the loads (every kind of
    :mod:`linkwork.planar.forces`: point forces, springs, dampers, ...) at their points at the
    same height; then :class:`OutOfPlaneLoad` terms.

    Returns
    -------
    ndarray, shape (n, n_bodies, 6)
    """
    n = kin.n
    g = np.zeros(2) if gravity is None else require_finite("gravity", gravity).ravel()
    if g.shape != (2,):
        raise ParameterError("gravity", g.shape, "must be a vector (gx, gy) [m/s^2]")
    h = dict(heights or {})
    names = [b.name for b in mech.bodies]
    for name in h:
        if name not in names:
            raise ParameterError("heights", name, f"no such moving body; known: {names}")
    force = np.zeros((n, len(names), 3))
    moment = np.zeros((n, len(names), 3))

    def add(i: int, fx: Any, fy: Any, fz: Any, x: Any, y: Any, z: float) -> None:
        f = np.stack(np.broadcast_arrays(fx, fy, fz, np.zeros(n)), -1)[:, :3]
        p = np.stack(np.broadcast_arrays(x, y, z, np.zeros(n)), -1)[:, :3]
        force[:, i] += f
        moment[:, i] += np.cross(p, f)

    iw = inertia_wrenches(kin, g)  # weight + inertia force at C, inertia couple
    for i, b in enumerate(mech.bodies):
        add(i, iw.fx[i], iw.fy[i], 0.0, iw.cx[i], iw.cy[i], h.get(b.name, 0.0))
        moment[:, i, 2] += iw.mz[i]
    for ap in forces.apply(kin, loads):  # every load's forces and couples on moving bodies
        for wr in ap.wrenches:
            if wr.body not in names:  # its reaction on the frame
                continue
            i = names.index(wr.body)
            add(i, wr.fx, wr.fy, 0.0, wr.px, wr.py, h.get(wr.body, 0.0))
            moment[:, i, 2] += wr.mz
    for op in out_of_plane:
        if op.body not in names:
            raise ParameterError("out_of_plane.body", op.body,
                                 f"no such moving body; known: {names}")
        i = names.index(op.body)
        c = kin.point(op.body, "com")
        add(i, 0.0, 0.0, float(op.fz), c.x, c.y, h.get(op.body, 0.0))
        moment[:, i, 0] += float(op.mx)
        moment[:, i, 1] += float(op.my)
    return np.concatenate([force, moment], axis=-1)


def deviation_array(model: SpatialModel, deviations: Iterable[Deviation],
                    ground: str = "ground") -> np.ndarray:
    """Deviations as the core's array, shape (n_joints, 2, 6) (element on body a, on body b).

    ``ground`` is the name the caller uses for the frame (``"ground"`` is accepted too).
    """
    out = np.zeros((len(model.joints), 2, 6))
    names = [j.name for j in model.joints]
    for d in deviations:
        if d.joint not in names:
            raise ParameterError("deviation.joint", d.joint, f"no such joint; known: {names}")
        jt = model.joints[names.index(d.joint)]
        body = "ground" if d.body == ground else d.body
        if body == jt.body_a:
            side = 0
        elif body == jt.body_b:
            side = 1
        else:
            raise ParameterError(f"deviation {d.joint}.body", d.body,
                                 f"must be one of the joint's bodies {jt.body_a!r}, "
                                 f"{jt.body_b!r}")
        out[names.index(d.joint), side] += d.vector()
    return out


def spatial_reactions(mech: Any, phi1: ArrayLike, *, omega1: ArrayLike | None = None,
                      eps1: ArrayLike | None = None, gravity: ArrayLike | None = None,
                      loads: Sequence[Any] = (),
                      joints: Mapping[str, Mapping[str, Any]] | None = None,
                      default: Mapping[str, Any] | None = None,
                      heights: Mapping[str, float] | None = None,
                      out_of_plane: Sequence[OutOfPlaneLoad] = (),
                      deviations: Iterable[Deviation] = (),
                      method: str = "force") -> SpatialReactions:
    """Spatial joint reactions of an engine mechanism over the driver positions ``phi1``.

    Runs :func:`linkwork.planar.kinematics`, builds :func:`spatial_model`, :func:`geometry`,
    :func:`body_wrenches` and :func:`deviation_array`, and calls
    :func:`~linkwork.redundancy.solve_reactions`. Parameters as in those functions; ``phi1``,
    ``omega1``, ``eps1`` as in :func:`linkwork.planar.kinematics` [rad, rad/s, rad/s^2; for a
    linear driver m, m/s, m/s^2, and then the result's ``units`` give ``phi1`` in m and the
    driving force ``Q`` in N].
    """
    kin = kinematics(mech, phi1, omega1, eps1)
    model = spatial_model(mech, joints, default)
    w = body_wrenches(mech, kin, gravity=gravity, loads=loads, heights=heights,
                      out_of_plane=out_of_plane)
    geom = geometry(mech, kin, w)
    dev = deviation_array(model, deviations, _ground(mech))
    res = solve_reactions(model, geom, w, dev, method=method, phi1=kin.phi1)
    du = mech.driver_units  # a linear driver: positions are slides [m], Q a force [N]
    units = {k: du[k] for k in ("phi1", "Q")}
    if any(res.units.get(k) != v for k, v in units.items()):
        res._relabel_units(**units)
    return res
