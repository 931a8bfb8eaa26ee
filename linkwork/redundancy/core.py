"""Spatial kinetostatics of a planar mechanism with redundant constraints: the array core.

A planar mechanism built from real joints is, in space, a system of rigid bodies joined by joints
of class V (a revolute joint with an axis of length ``e`` constrains three translations and two
tilts). The in-plane problem (forces in the plane, moments about z, driving torque) is statically
determinate; the out-of-plane one (axial forces, bending moments about x and y) has ``q`` more
unknowns than equations -- the redundant constraints. They are resolved here by the compliance of
the joints plus the compatibility of their deformations with the manufacturing deviations, to
first order (small deviations, small deformations, equilibrium written on the nominal geometry).

Everything in this module works on plain arrays, so that it can be fed by the planar engine or by
an independent four-bar computation: per position, the joint centres in the plane, the body angles,
the slide directions of prismatic joints and the external + inertia wrench on every body.

Conventions
-----------
* Global frame: x, y in the plane of motion, z = x × y (out of the plane, right-handed).
* Every joint ``j`` joins body ``a`` (may be the ground) to body ``b``. Its reaction is the wrench
  **exerted by body a on body b**, reduced to the joint centre ``(x_j, y_j, z_j)``: forces
  ``fx, fy, fz`` [N] and moments ``mx, my, mz`` [N·m], global components. ``z_j`` is the position
  of the joint centre along its axis (the middle of the bearing of length ``e``).
* Body loads are wrenches (force, moment) reduced to the global origin [N, N·m], i.e. external
  forces + gravity + d'Alembert inertia forces, as in the kinetostatic method.
* The driving torque ``Q`` [N·m] (or force [N] for a prismatic driver) acts on body ``b`` of the
  driver joint from body ``a``, about +z (along the slide).
* Deviations are 6-vectors ``(dx, dy, dz, tx, ty, tz)`` [m, rad] of the joint element carried by a
  body, in that body's frame (x, y rotated with the body angle, z out of the plane): an offset of
  the element's centre and a small rotation (tilt) of its axis about the nominal centre. The misfit
  of joint ``j`` is ``delta_j = R(theta_b) dev_b - R(theta_a) dev_a`` (global components).
* A joint's spring stretch is ``s = C^T (u_b(p_j) - u_a(p_j) + delta_j)`` and its reaction is
  ``r = -K s``: the joints are linear springs in their constrained directions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_positive
from linkwork.errors import ParameterError, StructureError
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "COMPONENTS",
    "DEFAULT_BEARING_STIFFNESS",
    "JOINT_KINDS",
    "Influence",
    "RedundancyCount",
    "SpatialGeometry",
    "SpatialJoint",
    "SpatialModel",
    "SpatialReactions",
    "bearing_stiffness",
    "count_redundancy",
    "equilibrium_matrix",
    "influence",
    "inplane_solution",
    "misfit",
    "solve_reactions",
    "wrench_about_origin",
]

#: Names of the six wrench components, global frame (the reaction arrays' last axis).
COMPONENTS: tuple[str, ...] = ("fx", "fy", "fz", "mx", "my", "mz")

#: Joint kinds in space -> (family, constrained local components). Revolute family: local frame =
#: global (x, y, z). Prismatic family: local frame (d, n, z) with d the slide direction in the
#: plane and n = z × d; components (f_d, f_n, f_z, m_d, m_n, m_z) -> indices 0..5. Gear family
#: (a gear mesh, at the pitch point): local frame (n, t, z) with n the line of action (the
#: direction of the tooth force on b) and t = z × n; components (f_n, f_t, f_z, m_n, m_t, m_z).
#: Spur teeth touch along a line across the face width (parallel to z): they carry the tooth
#: force f_n and the moment m_t that tilts that line in the plane (n, z), i.e. the uneven
#: load across the face; crowned teeth touch at a point and carry f_n only.
JOINT_KINDS: dict[str, tuple[str, tuple[int, ...]]] = {
    "revolute": ("R", (0, 1, 2, 3, 4)),          # class V: pin in a bearing of length e
    "cylindrical": ("R", (0, 1, 3, 4)),          # class IV: free to slide along its axis
    "spherical": ("R", (0, 1, 2)),               # class III: ball joint
    "sphere_cylinder": ("R", (0, 1)),            # class II: ball in a cylinder (in-line)
    "prismatic": ("P", (1, 2, 3, 4, 5)),         # class V: slider in a guide of length e
    "prismatic_round": ("P", (1, 2, 4, 5)),      # class IV: round rod, free to roll about d
    "spur": ("G", (0, 4)),                       # class II: gear teeth in line contact
    "crowned": ("G", (0,)),                      # class I: crowned teeth, point contact
}

_LOCAL_NAMES = {"R": ("fx", "fy", "fz", "mx", "my", "mz"),
                "P": ("fd", "fn", "fz", "md", "mn", "mz"),
                "G": ("fn", "ft", "fz", "mn", "mt", "mz")}

#: Default radial stiffness of a joint [N/m] (a plain bearing of a loom linkage, ~100 N/µm).
DEFAULT_BEARING_STIFFNESS = 1.0e8

#: largest tilt deviation [rad] the first-order theory accepts (a "small rotation"); beyond it
#: the input is most likely a unit slip (a plain number is read as radians)
MAX_TILT = 0.1


def check_tilt(name: str, value: float) -> float:
    """``value`` [rad] if it is a small tilt (``|value| <= MAX_TILT``), else ParameterError."""
    v = float(value)
    if not abs(v) <= MAX_TILT:
        raise ParameterError(name, v, f"must be a small tilt, |t| <= {MAX_TILT} rad (first-"
                             "order theory); a plain number is in radians: write e.g. "
                             "'0.3 mrad'")
    return v


def bearing_stiffness(kind: str, e: float, k_bearing: float = DEFAULT_BEARING_STIFFNESS,
                      axial_ratio: float = 1.0) -> np.ndarray:
    r"""Default stiffnesses of a joint in its local frame, from its axis length.

    The bearing is a journal (or slider) of length ``e`` whose radial stiffness ``k_b`` is spread
    uniformly over its length, centred on the joint centre. Its tilt stiffness is then

    .. math:: k_t = \int_{-e/2}^{e/2} \frac{k_b}{e} \zeta^2\, d\zeta = \frac{k_b e^2}{12},

    the axial stiffness is ``axial_ratio * k_b``, and the radial and tilt springs are uncoupled at
    the centre. A prismatic joint (slide direction d, normal n) gets ``k_b`` for f_n and f_z and
    ``k_b e^2/12`` for the three rotations (for the roll about d a square guide of side e is
    assumed). A gear mesh: ``e`` is the face width, ``k_bearing`` the mesh stiffness along the
    line of action (ISO 6336-1's c_gamma times the face width, about 20 N/(mm·µm) per mm for
    steel spur gears) spread over the face width: ``k_b`` for f_n and ``k_b e^2/12`` for m_t.
    Free directions get 0.

    Parameters
    ----------
    kind : str
        One of :data:`JOINT_KINDS`.
    e : float
        Axis (bearing) length [m], > 0.
    k_bearing : float
        Radial stiffness of the whole bearing [N/m], > 0.
    axial_ratio : float
        Axial over radial stiffness [-], > 0.

    Returns
    -------
    ndarray, shape (6,)
        Stiffnesses of the local components [N/m for forces, N·m/rad for moments].
    """
    family, comps = _kind(kind)
    e = float(require_positive("e", e))
    kb = float(require_positive("k_bearing", k_bearing))
    ax = float(require_positive("axial_ratio", axial_ratio))
    kt = kb * e * e / 12.0
    full = {"R": np.array([kb, kb, ax * kb, kt, kt, 0.0]),
            "P": np.array([0.0, kb, ax * kb, kt, kt, kt]),
            "G": np.array([kb, 0.0, 0.0, 0.0, kt, 0.0])}[family]
    out = np.zeros(6)
    out[list(comps)] = full[list(comps)]
    return out


def _kind(kind: str) -> tuple[str, tuple[int, ...]]:
    if kind not in JOINT_KINDS:
        raise ParameterError("kind", kind, f"must be one of {sorted(JOINT_KINDS)}")
    return JOINT_KINDS[kind]


@dataclass(frozen=True)
class SpatialJoint:
    """A joint of a planar mechanism, seen in space.

    Parameters
    ----------
    name : str
        Joint name (``"O"``, ``"A"``...).
    body_a, body_b : str
        The joined bodies; ``"ground"`` for the frame. The reaction acts on ``body_b``.
    kind : str
        Spatial kind, one of :data:`JOINT_KINDS` (a planar revolute is normally ``"revolute"``,
        class V; ``"spherical"``, ``"cylindrical"``... model self-aligning designs; a gear
        mesh ``"spur"``, class II, or ``"crowned"``, class I).
    e : float
        Axis (bearing) length [m] (a gear mesh: the face width).
    z : float
        Position of the joint centre along its axis (out of the plane) [m] (a gear mesh: the
        middle of the face width).
    stiffness : sequence of 6 floats or None
        Stiffnesses of the local components [N/m, N·m/rad]; None: :func:`bearing_stiffness`
        from ``e``, ``k_bearing`` and ``axial_ratio``. Only constrained components are used;
        they must be > 0.
    k_bearing : float
        Radial bearing stiffness [N/m] for the defaults (a gear mesh: its stiffness along the
        line of action).
    axial_ratio : float
        Axial/radial stiffness ratio for the defaults.
    """

    name: str
    body_a: str
    body_b: str
    kind: str = "revolute"
    e: float = 0.02
    z: float = 0.0
    stiffness: tuple[float, ...] | None = None
    k_bearing: float = DEFAULT_BEARING_STIFFNESS
    axial_ratio: float = 1.0

    def __post_init__(self) -> None:
        _kind(self.kind)
        require_positive(f"{self.name}.e", self.e)
        require_finite(f"{self.name}.z", self.z)
        require_positive(f"{self.name}.k_bearing", self.k_bearing)
        require_positive(f"{self.name}.axial_ratio", self.axial_ratio)
        if self.body_a == self.body_b:
            raise ParameterError(f"{self.name}.body_b", self.body_b, "must differ from body_a")
        if self.stiffness is not None:
            k = require_finite(f"{self.name}.stiffness", self.stiffness)
            if k.shape != (6,):
                raise ParameterError(f"{self.name}.stiffness", k.shape, "must have 6 components")
            comps = list(self.constrained)
            if np.any(k[comps] <= 0):
                bad = float(k[comps][k[comps] <= 0][0])
                raise ParameterError(f"{self.name}.stiffness", bad,
                                     "must be > 0 in the constrained directions")

    @property
    def family(self) -> str:
        """``"R"`` (revolute family), ``"P"`` (prismatic family) or ``"G"`` (gear mesh)."""
        return JOINT_KINDS[self.kind][0]

    @property
    def constrained(self) -> tuple[int, ...]:
        """Indices of the constrained local components."""
        return JOINT_KINDS[self.kind][1]

    @property
    def joint_class(self) -> int:
        """Class of the joint in space (number of constraints it imposes)."""
        return len(self.constrained)

    @property
    def local_names(self) -> tuple[str, ...]:
        """Names of the constrained local components (``fx``... or ``fn``, ``md``...)."""
        names = _LOCAL_NAMES[self.family]
        return tuple(names[i] for i in self.constrained)

    def local_stiffness(self) -> np.ndarray:
        """Stiffnesses of the six local components [N/m, N·m/rad] (0 where free)."""
        comps = list(self.constrained)
        if self.stiffness is None:
            k = bearing_stiffness(self.kind, self.e, self.k_bearing, self.axial_ratio)
            bad = ~(np.isfinite(k[comps]) & (k[comps] > 0.0))
            if np.any(bad):  # e.g. k_b e^2/12 underflows for e = 1e-300 m
                raise ParameterError(f"{self.name}.e", self.e,
                                     f"gives a non-positive or infinite default stiffness "
                                     f"{float(k[comps][bad][0]):.3g} with k_bearing = "
                                     f"{self.k_bearing:.3g} N/m: give e in metres, > 0")
            return k
        k = np.zeros(6)
        k[comps] = np.asarray(self.stiffness, dtype=float)[comps]
        return k


@dataclass(frozen=True)
class SpatialModel:
    """The spatial description of a planar mechanism: bodies, joints, driver.

    Parameters
    ----------
    bodies : sequence of str
        Names of the moving bodies (not the ground).
    joints : sequence of SpatialJoint
    driver : str or tuple of str
        Name of the joint that carries the driving torque (revolute family: a moment about z;
        prismatic family: a force along the slide); several names for a mechanism with several
        drivers (their unknowns come last, in this order).
    """

    bodies: tuple[str, ...]
    joints: tuple[SpatialJoint, ...]
    driver: str | tuple[str, ...]

    def __post_init__(self) -> None:
        object.__setattr__(self, "bodies", tuple(self.bodies))
        object.__setattr__(self, "joints", tuple(self.joints))
        if len(set(self.bodies)) != len(self.bodies) or "ground" in self.bodies:
            raise ParameterError("bodies", list(self.bodies),
                                 "names must be unique and not 'ground'")
        names = [j.name for j in self.joints]
        if len(set(names)) != len(names):
            raise ParameterError("joints", names, "names must be unique")
        known = {*self.bodies, "ground"}
        for j in self.joints:
            for b in (j.body_a, j.body_b):
                if b not in known:
                    raise ParameterError(f"{j.name}.body", b, f"must be one of {sorted(known)}")
        if not isinstance(self.driver, str):
            object.__setattr__(self, "driver", tuple(self.driver))
        for d in self.drivers:
            if d not in names:
                raise ParameterError("driver", d, f"must be one of the joints {names}")
        if len(set(self.drivers)) != len(self.drivers) or not self.drivers:
            raise ParameterError("driver", self.driver, "must name distinct joints")

    @property
    def drivers(self) -> tuple[str, ...]:
        """The driver joints' names, in order."""
        return (self.driver,) if isinstance(self.driver, str) else tuple(self.driver)

    @property
    def n_drivers(self) -> int:
        """Number of drivers (driving unknowns, the last columns)."""
        return len(self.drivers)

    @property
    def driver_indices(self) -> list[int]:
        """Indices of the driver joints, in driver order."""
        names = [j.name for j in self.joints]
        return [names.index(d) for d in self.drivers]

    @property
    def n_bodies(self) -> int:
        """Number of moving bodies."""
        return len(self.bodies)

    def body_index(self, name: str) -> int:
        """Index of a moving body, -1 for the ground."""
        return -1 if name == "ground" else self.bodies.index(name)

    @property
    def driver_index(self) -> int:
        """Index of the (first) driver joint."""
        return self.driver_indices[0]

    def labels(self) -> list[tuple[str, str]]:
        """(joint, component) of every unknown of the equilibrium matrix, drivers last."""
        out = [(j.name, c) for j in self.joints for c in j.local_names]
        out += [(d, "Q") for d in self.drivers]
        return out

    @property
    def n_unknowns(self) -> int:
        """Number of reaction unknowns (all constrained components + the drivers)."""
        return sum(j.joint_class for j in self.joints) + self.n_drivers

    def stiffness_vector(self) -> np.ndarray:
        """Stiffness of every constrained component, in the order of :meth:`labels` (no driver)."""
        return np.concatenate([j.local_stiffness()[list(j.constrained)] for j in self.joints])


@dataclass(frozen=True)
class SpatialGeometry:
    """Per-position geometry of the mechanism (from the planar kinematics).

    Parameters
    ----------
    points : array, shape (n, n_joints, 2)
        Joint centres in the plane [m].
    body_angles : array, shape (n, n_bodies)
        Angles of the body frames from the global x axis, counter-clockwise [rad].
    slide_angles : array, shape (n, n_joints), optional
        Direction of the slide of each prismatic-family joint, of the line of action (the
        tooth force on b) of each gear mesh [rad] (ignored for the others).
    """

    points: np.ndarray
    body_angles: np.ndarray
    slide_angles: np.ndarray | None = None

    def __post_init__(self) -> None:
        p = require_finite("points", self.points)
        if p.ndim != 3 or p.shape[-1] != 2:
            raise ParameterError("points", p.shape, "must have shape (n, n_joints, 2)")
        th = require_finite("body_angles", self.body_angles)
        if th.ndim != 2 or th.shape[0] != p.shape[0]:
            raise ParameterError("body_angles", th.shape, f"must have shape ({p.shape[0]}, nb)")
        sa = (np.zeros(p.shape[:2]) if self.slide_angles is None
              else require_finite("slide_angles", self.slide_angles))
        if sa.shape != p.shape[:2]:
            raise ParameterError("slide_angles", sa.shape, f"must have shape {p.shape[:2]}")
        object.__setattr__(self, "points", p)
        object.__setattr__(self, "body_angles", th)
        object.__setattr__(self, "slide_angles", sa)

    @property
    def n(self) -> int:
        """Number of positions."""
        return int(self.points.shape[0])


def wrench_about_origin(force: ArrayLike, moment: ArrayLike, point: ArrayLike) -> np.ndarray:
    r"""Reduce a force applied at ``point`` plus a moment to the global origin.

    .. math:: \mathbf{w} = (\mathbf{F},\ \mathbf{M} + \mathbf{r} \times \mathbf{F})

    Parameters
    ----------
    force, moment, point : array, shape (..., 3)
        [N], [N·m], [m]; broadcast together.

    Returns
    -------
    ndarray, shape (..., 6)
    """
    f, m, p = np.broadcast_arrays(np.asarray(force, float), np.asarray(moment, float),
                                  np.asarray(point, float))
    return np.concatenate([f, m + np.cross(p, f)], axis=-1)


# ------------------------------------------------------------------------------------------------
# assembly


def _rot6(angle: np.ndarray) -> np.ndarray:
    """Block rotation about z, shape (..., 6, 6), applied to (translation, rotation) 6-vectors."""
    c, s = np.cos(angle), np.sin(angle)
    r = np.zeros((*np.shape(angle), 6, 6))
    for o in (0, 3):
        r[..., o, o], r[..., o, o + 1] = c, -s
        r[..., o + 1, o], r[..., o + 1, o + 1] = s, c
        r[..., o + 2, o + 2] = 1.0
    return r


def _transfer(p: np.ndarray) -> np.ndarray:
    """T(p), shape (..., 6, 6): wrench (f, m) at p -> wrench (f, m + p × f) at the origin."""
    t = np.zeros((*p.shape[:-1], 6, 6))
    t[..., :3, :3] = np.eye(3)
    t[..., 3:, 3:] = np.eye(3)
    x, y, z = p[..., 0], p[..., 1], p[..., 2]
    t[..., 3, 1], t[..., 3, 2] = -z, y
    t[..., 4, 0], t[..., 4, 2] = z, -x
    t[..., 5, 0], t[..., 5, 1] = -y, x
    return t


def _joint_frames(model: SpatialModel, geom: SpatialGeometry) -> list[np.ndarray]:
    """Local -> global rotation (n, 6, 6) of every joint."""
    out = []
    for j, jt in enumerate(model.joints):
        if jt.family == "R":
            out.append(np.broadcast_to(np.eye(6), (geom.n, 6, 6)))
        else:
            assert geom.slide_angles is not None
            out.append(_rot6(geom.slide_angles[:, j]))
    return out


def _check_geometry(model: SpatialModel, geom: SpatialGeometry) -> None:
    if geom.points.shape[1] != len(model.joints):
        raise ParameterError("points", geom.points.shape,
                             f"must have {len(model.joints)} joints on axis 1")
    if geom.body_angles.shape[1] != model.n_bodies:
        raise ParameterError("body_angles", geom.body_angles.shape,
                             f"must have {model.n_bodies} bodies on axis 1")


def equilibrium_matrix(model: SpatialModel, geom: SpatialGeometry, *, driver: bool = True
                       ) -> np.ndarray:
    r"""The spatial equilibrium matrix A of the moving bodies, for every position.

    Equilibrium of all moving bodies is :math:`A\,r + w = 0` with ``w`` the body wrenches about
    the origin (shape (n, 6 n_bodies)) and ``r`` the unknowns of :meth:`SpatialModel.labels`. The
    transpose is the compatibility operator: the stretches of the joints caused by small body
    displacements ``u`` (translation of the origin point and rotation, per body) are
    :math:`A^T u`.

    Parameters
    ----------
    model : SpatialModel
    geom : SpatialGeometry
    driver : bool
        Include the drivers' columns (last, in driver order).

    Returns
    -------
    ndarray, shape (n, 6 n_bodies, n_unknowns) (n_drivers columns less without them)
    """
    _check_geometry(model, geom)
    n, nb = geom.n, model.n_bodies
    frames = _joint_frames(model, geom)
    cols = []
    driven = model.driver_indices
    drive_cols = []
    k = 0
    for j, jt in enumerate(model.joints):
        p3 = np.concatenate([geom.points[:, j, :], np.full((n, 1), jt.z)], axis=-1)
        b = _transfer(p3) @ frames[j]                       # (n, 6, 6) local -> wrench at origin
        ia, ib = model.body_index(jt.body_a), model.body_index(jt.body_b)
        sel = list(jt.constrained)
        k += len(sel)
        if driver and j in driven:
            sel = [*sel, 5 if jt.family == "R" else 0]
            drive_cols.append((driven.index(j), k))
            k += 1
        block = np.zeros((n, 6 * nb, len(sel)))
        if ib >= 0:
            block[:, 6 * ib:6 * ib + 6, :] += b[:, :, sel]
        if ia >= 0:
            block[:, 6 * ia:6 * ia + 6, :] -= b[:, :, sel]
        cols.append(block)
    a = np.concatenate(cols, axis=-1)
    if driver:  # move the drivers' columns to the end, in driver order
        last = [c for _, c in sorted(drive_cols)]
        order = [i for i in range(a.shape[-1]) if i not in last] + last
        a = a[..., order]
    return a


def inplane_solution(model: SpatialModel, geom: SpatialGeometry, wrenches: ArrayLike
                     ) -> tuple[list[tuple[str, str]], np.ndarray]:
    r"""The in-plane reactions alone: the rows fx, fy, mz of every body's equilibrium in the
    in-plane unknowns (the local components 0, 1, 5 that a joint constrains, and the drivers).

    The in-plane equations of the spatial problem contain no out-of-plane unknown, and they are
    as many as the in-plane unknowns (the planar mobility equals the number of drivers), so
    this square system is the planar kinetostatics on the spatial model's joint frames; the
    self-stress states have no in-plane part, so these values are those of any solution.

    Returns
    -------
    labels : list of (joint, component)
        The in-plane unknowns, drivers last (``(driver joint, "Q")``).
    values : ndarray, shape (n, len(labels))
    """
    a = equilibrium_matrix(model, geom)
    w = require_finite("wrenches", wrenches)
    nb = model.n_bodies
    if w.shape != (geom.n, nb, 6):
        raise ParameterError("wrenches", w.shape, f"must have shape ({geom.n}, {nb}, 6)")
    rows = [6 * i + c for i in range(nb) for c in (0, 1, 5)]
    cols, labels = [], []
    k = 0
    for jt in model.joints:
        for c, name in zip(jt.constrained, jt.local_names, strict=True):
            if c in (0, 1, 5):
                cols.append(k)
                labels.append((jt.name, name))
            k += 1
    cols += list(range(k, k + model.n_drivers))
    labels += [(d, "Q") for d in model.drivers]
    _, rs, cs = _scales(model, geom)
    sub = rs[rows][:, None] * a[:, rows][:, :, cols] * cs[cols][None, :]
    if sub.shape[-1] != sub.shape[-2]:
        raise StructureError(f"the in-plane problem has {sub.shape[-1]} unknowns for "
                             f"{sub.shape[-2]} equations: the planar mobility differs from the "
                             f"{model.n_drivers} driver(s)")
    rhs = -(rs[rows] * w.reshape(geom.n, 6 * nb)[:, rows])
    return labels, cs[cols] * np.linalg.solve(sub, rhs[..., None])[..., 0]


def misfit(model: SpatialModel, geom: SpatialGeometry, deviations: ArrayLike) -> np.ndarray:
    r"""Misfit of every constrained component caused by manufacturing deviations.

    .. math:: \delta_j = R(\theta_b)\,d_{j,b} - R(\theta_a)\,d_{j,a},\qquad
              \delta_{c,j} = C_j^T \delta_j

    Parameters
    ----------
    model, geom
        As for :func:`equilibrium_matrix`.
    deviations : array, shape (..., n_joints, 2, 6)
        ``(dx, dy, dz, tx, ty, tz)`` [m, rad] of the element of each joint carried by body a
        (index 0 on axis -2) and by body b (index 1), in that body's frame. Leading axes (e.g.
        Monte-Carlo samples) broadcast.

    Returns
    -------
    ndarray, shape (..., n, n_unknowns - n_drivers)
        Misfits [m, rad] in the order of :meth:`SpatialModel.labels` (without the drivers).
    """
    _check_geometry(model, geom)
    d = require_finite("deviations", deviations)
    if d.shape[-3:] != (len(model.joints), 2, 6):
        raise ParameterError("deviations", d.shape,
                             f"must end with ({len(model.joints)}, 2, 6)")
    lead = d.shape[:-3]
    zeros = np.zeros((geom.n, 1))
    angles = np.concatenate([geom.body_angles, zeros], axis=1)   # index -1 -> ground (0 rad)
    rot = _rot6(angles)                                            # (n, nb+1, 6, 6)
    frames = _joint_frames(model, geom)
    out = []
    for j, jt in enumerate(model.joints):
        ia, ib = model.body_index(jt.body_a), model.body_index(jt.body_b)
        da = d[..., j, 0, :][..., None, :]      # (..., 1, 6)
        db = d[..., j, 1, :][..., None, :]
        glob = (np.einsum("nij,...nj->...ni", rot[:, ib], db)
                - np.einsum("nij,...nj->...ni", rot[:, ia], da))       # (..., n, 6)
        loc = np.einsum("nji,...nj->...ni", frames[j], glob)          # C^T: global -> local
        out.append(loc[..., list(jt.constrained)])
    res = np.concatenate(out, axis=-1)
    return np.broadcast_to(res, (*lead, geom.n, res.shape[-1])).copy()


def _scales(model: SpatialModel, geom: SpatialGeometry) -> tuple[float, np.ndarray, np.ndarray]:
    """Length scale L, row scaling (6 nb,) and column scaling (n_unknowns,)."""
    zs = np.array([j.z for j in model.joints])
    length = float(max(np.max(np.abs(geom.points)), np.max(np.abs(zs)), 1e-6))
    rows = np.tile(np.array([1, 1, 1, 1 / length, 1 / length, 1 / length]), model.n_bodies)
    cols = []
    for j in model.joints:
        loc = np.array([1, 1, 1, length, length, length])
        cols.append(loc[list(j.constrained)])
    for i in model.driver_indices:
        cols.append(np.array([length if model.joints[i].family == "R" else 1.0]))
    return length, rows, np.concatenate(cols)


@dataclass(frozen=True)
class Influence:
    """Reactions without deviations and their influence matrix: ``r = r0 + h @ misfit``.

    Attributes
    ----------
    r0 : ndarray (n, n_unknowns)
        Unknowns (constrained components, driver last) without deviations [N, N·m].
    h : ndarray (n, n_unknowns, n_unknowns - n_drivers)
        Change of the unknowns per unit misfit [N/m, N·m/rad, ...].
    rank : int
        Rank of the equilibrium matrix.
    selfstress : ndarray (n, n_unknowns, q)
        Self-stress basis (physical units; orthonormal in units scaled by the mechanism size).
    """

    r0: np.ndarray
    h: np.ndarray
    rank: int
    selfstress: np.ndarray


def _rank(s: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    return np.sum(s > tol * s[..., :1], axis=-1)


def influence(model: SpatialModel, geom: SpatialGeometry, wrenches: ArrayLike) -> Influence:
    r"""Force method: reactions without deviations and their influence matrix for misfits.

    The reactions are a particular equilibrium solution plus a combination of the self-stress
    states ``S`` (the null space of A): :math:`r = r_p + S x`. Compatibility of the joint
    stretches :math:`s = -F r` (``F = K^{-1}``) with the misfits :math:`\delta_c` requires
    :math:`S^T (s - \delta_c) = 0`, hence

    .. math:: x = -(S^T F S)^{-1} S^T (F r_p + \delta_c).

    Returns ``r0`` (for :math:`\delta_c = 0`) and ``H = -S (S^T F S)^{-1} S^T`` so that
    :math:`r = r_0 + H \delta_c`.
    """
    a = equilibrium_matrix(model, geom)
    w = require_finite("wrenches", wrenches)
    nb = model.n_bodies
    if w.shape != (geom.n, nb, 6):
        raise ParameterError("wrenches", w.shape, f"must have shape ({geom.n}, {nb}, 6)")
    w = w.reshape(geom.n, 6 * nb)
    _, rows, cols = _scales(model, geom)
    at = rows[:, None] * a * cols[None, :]
    wt = rows * w
    u, s, vh = np.linalg.svd(at)
    ranks = _rank(s)
    rank = int(ranks[0])
    if np.any(ranks != rank):
        bad = int(np.argmax(ranks != rank))
        raise StructureError(f"the rank of the spatial equilibrium matrix changes over the cycle "
                             f"({rank} at position 0, {int(ranks[bad])} at position {bad}): "
                             f"a singular (dead-centre) position")
    if rank < 6 * nb:
        raise StructureError(f"the mechanism is movable in space: rank of the equilibrium matrix "
                             f"{rank} < 6 x {nb} bodies; loads out of the plane cannot be carried "
                             f"(use joints of higher class)")
    ur, sr, vr = u[:, :, :rank], s[:, :rank], np.swapaxes(vh[:, :rank, :], 1, 2)
    rp_t = -(vr @ ((np.swapaxes(ur, 1, 2) @ wt[..., None])[..., 0] / sr)[..., None])[..., 0]
    sst = np.swapaxes(vh[:, rank:, :], 1, 2)                       # (n, m+nd, q) scaled
    nd = model.n_drivers
    m = a.shape[-1] - nd
    kvec = model.stiffness_vector()
    # flexibility in scaled units: r = D_c r~, s~ = D_c s -> F~ = D_c^-1 F D_c^-1... with
    # r = -K s: r~ = -(D_c^-1 K D_c^-1) s~, F~ = D_c F D_c
    fl = np.concatenate([cols[:m] ** 2 / kvec, np.zeros(nd)])
    q = sst.shape[-1]
    if q:
        sst_t = np.swapaxes(sst, 1, 2)
        g = sst_t @ (fl[:, None] * sst)                             # S^T F S, (n, q, q)
        _check_conditioning(g, "self-stress compliance")
        ginv = np.linalg.inv(g)
        ht = -(sst @ ginv @ sst_t)                                  # (n, m+1, m+1) scaled
        r0_t = rp_t + (ht @ (fl * rp_t)[..., None])[..., 0]
    else:
        ht = np.zeros((geom.n, m + nd, m + nd))
        r0_t = rp_t
    # back to physical: r = D_c r~; misfit delta~ = D_c delta
    r0 = cols * r0_t
    h = cols[None, :, None] * ht[:, :, :m] * cols[None, None, :m]
    return Influence(r0=r0, h=h, rank=rank, selfstress=cols[None, :, None] * sst)


#: Largest condition number of the scaled linear systems accepted (about 4 correct digits left).
MAX_CONDITION = 1e12


def _check_conditioning(mat: np.ndarray, what: str) -> None:
    """Raise ParameterError when a batch of (scaled) matrices is too ill-conditioned to solve.

    The matrices are symmetric (a compliance S^T F S or a stiffness A K A^T), so the 2-norm
    condition number is the ratio of the extreme eigenvalue magnitudes (``eigvalsh``, ~30 %
    cheaper than the SVD behind ``np.linalg.cond``).
    """
    with np.errstate(all="ignore"):
        lam = np.abs(np.linalg.eigvalsh(mat))
        cond = lam.max(axis=-1) / lam.min(axis=-1)
    bad = ~np.isfinite(cond) | (cond > MAX_CONDITION)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ParameterError("stiffness", f"condition number {float(cond[i]):.3g} of the {what} "
                             f"at position {i}",
                             f"must be <= {MAX_CONDITION:.0e}: the joint stiffnesses (or axis "
                             "lengths) differ by too many orders of magnitude; model a "
                             "near-free direction by the joint kind (e.g. spherical) instead")


def _displacement(model: SpatialModel, geom: SpatialGeometry, w: np.ndarray,
                  dc: np.ndarray) -> np.ndarray:
    r"""Displacement method: :math:`(A K A^T) u = w - A K \delta_c`, :math:`r = -K(A^T u +
    \delta_c)`; the driver is a stiff rotational (or axial) spring."""
    a = equilibrium_matrix(model, geom)
    _, rows, cols = _scales(model, geom)
    at = rows[:, None] * a * cols[None, :]
    nd = model.n_drivers
    m = a.shape[-1] - nd
    kvec = model.stiffness_vector()
    kt = kvec / cols[:m] ** 2
    kt = np.concatenate([kt, np.full(nd, np.exp(np.mean(np.log(kt))))])
    kt = kt / np.max(kt)                  # reactions do not depend on a common factor
    kfac = np.max(kvec / cols[:m] ** 2)
    wt = rows * w.reshape(w.shape[0], -1)
    dt = np.concatenate([cols[:m] * dc, np.zeros((*dc.shape[:-1], nd))], axis=-1)
    # batched matmul, not 3-operand einsum (which loops without BLAS)
    at_k = at * kt
    stiff = at_k @ np.swapaxes(at, -1, -2)                        # A K A^T
    rhs = wt / kfac - (at_k @ dt[..., None])[..., 0]
    # symmetric diagonal scaling for conditioning
    dsc = 1.0 / np.sqrt(np.einsum("nii->ni", stiff))
    ks = dsc[:, :, None] * stiff * dsc[:, None, :]
    _check_conditioning(ks, "assembled joint stiffness")
    u = dsc * np.linalg.solve(ks, (dsc * rhs)[..., None])[..., 0]
    rt = -kfac * kt * ((np.swapaxes(at, -1, -2) @ u[..., None])[..., 0] + dt)
    return cols * rt


@dataclass(frozen=True)
class SpatialReactions(Result):
    """Spatial joint reactions of a planar mechanism over a cycle.

    Every component array has shape (n_joints, n): the wrench exerted by ``body_a`` on ``body_b``
    of each joint, reduced to the joint centre, global components. ``Q`` is the driving torque
    [N·m] (force [N] for a prismatic driver), shape (n,); it is also contained in the driver
    joint's components (``mz`` of a revolute driver, the force along the slide of a prismatic
    one), so that every joint's wrench is the whole action of body a on body b.

    Attributes
    ----------
    phi1 : ndarray (n,), or (n_drivers, n) for several drivers
        Driver positions [rad] (or [m]), as passed by the caller.
    joints : tuple of str
        Joint names (axis 0 of the component arrays).
    fx, fy, fz : ndarray (n_joints, n)
        Reaction forces [N].
    mx, my, mz : ndarray (n_joints, n)
        Reaction moments [N·m]; mx, my are the bending moments of the joint.
    Q : ndarray (n,), or (n_drivers, n) for several drivers
        Driving torque [N·m] (force [N] of a prismatic driver).
    redundant : int
        Number of redundant constraints q (self-stress states).
    method : str
        ``"force"`` or ``"displacement"``.
    """

    phi1: np.ndarray
    joints: tuple[str, ...]
    fx: np.ndarray
    fy: np.ndarray
    fz: np.ndarray
    mx: np.ndarray
    my: np.ndarray
    mz: np.ndarray
    Q: np.ndarray
    redundant: int
    method: str
    drivers: tuple[str, ...] = ()

    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "fx": "N", "fy": "N", "fz": "N", "mx": "N*m", "my": "N*m", "mz": "N*m",
        "Q": "N*m", "bending": "N*m"}

    def components(self) -> np.ndarray:
        """All components stacked, shape (n_joints, 6, n) in the order of :data:`COMPONENTS`."""
        return np.stack([getattr(self, c) for c in COMPONENTS], axis=1)

    def bending(self) -> np.ndarray:
        """Bending moment magnitude sqrt(mx² + my²) of every joint [N·m], (n_joints, n)."""
        return np.hypot(self.mx, self.my)

    def peaks(self) -> dict[str, dict[str, float]]:
        """Peak |value| over the cycle of every component and the bending moment, per joint."""
        out: dict[str, dict[str, float]] = {}
        comp = self.components()
        for j, name in enumerate(self.joints):
            row = {c: float(np.max(np.abs(comp[j, i]))) for i, c in enumerate(COMPONENTS)}
            row["bending"] = float(np.max(self.bending()[j]))
            out[name] = row
        out["driver"] = {"Q": float(np.max(np.abs(self.Q)))}
        if np.ndim(self.Q) == 2:  # several drivers: each one's peak too
            for k, name in enumerate(self.drivers):
                out["driver"][f"Q {name}"] = float(np.max(np.abs(self.Q[k])))
        return out

    def columns(self) -> dict[str, np.ndarray]:
        """Per-position columns named ``<component>_<joint>`` (``fz_B``, ``mx_O``...) and Q;
        several drivers: ``phi1_<joint>`` first and ``Q_<joint>`` last, one per driver."""
        phi = np.asarray(self.phi1)
        cols: dict[str, np.ndarray] = (
            {f"phi1_{name}": phi[k] for k, name in enumerate(self.drivers)} if phi.ndim == 2
            else {"phi1": phi})
        comp = self.components()
        for j, name in enumerate(self.joints):
            for i, c in enumerate(COMPONENTS):
                cols[f"{c}_{name}"] = comp[j, i]
        if np.ndim(self.Q) == 2:
            for k, name in enumerate(self.drivers):
                cols[f"Q_{name}"] = np.asarray(self.Q[k])
        else:
            cols["Q"] = np.asarray(self.Q)
        return cols

    def _unit_of(self, column: str) -> str:
        """Unit of a CSV column: that of its component (``fz_B`` -> ``fz``); the CSV (written by
        :meth:`Result.to_csv`) has the columns of :meth:`columns`."""
        head = column.split("_")[0]
        if head in ("Q", "phi1") and column != head:  # one driver's of several: its own unit
            units = self.units.get(head, "").split(", ")
            k = list(self.drivers).index(column[len(head) + 1:])
            return units[k] if len(units) > 1 else units[0]
        return self.units.get(head, "")

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Axial forces fz, bending moments mx, my of every joint and the driving torque over
        the driver positions: a :class:`linkwork.plot.Figure` with 4 axes."""
        from linkwork.plot.redundancy import reactions_figure

        return reactions_figure(self, axes=axes, **kw)


def _to_result(model: SpatialModel, geom: SpatialGeometry, r: np.ndarray, phi1: np.ndarray,
               q: int, method: str) -> SpatialReactions:
    """Local constrained components (n, m+1) -> global wrenches per joint."""
    frames = _joint_frames(model, geom)
    comp = np.zeros((len(model.joints), 6, geom.n))
    k = 0
    nd = model.n_drivers
    m = r.shape[-1] - nd
    driven = model.driver_indices
    for j, jt in enumerate(model.joints):
        loc = np.zeros((geom.n, 6))
        sel = list(jt.constrained)
        loc[:, sel] = r[:, k:k + len(sel)]
        k += len(sel)
        if j in driven:
            loc[:, 5 if jt.family == "R" else 0] += r[:, m + driven.index(j)]
        comp[j] = np.einsum("nij,nj->in", frames[j], loc)
    Q = r[:, -1].copy() if nd == 1 else r[:, m:].T.copy()
    return SpatialReactions(
        phi1=phi1, joints=tuple(j.name for j in model.joints),
        fx=comp[:, 0], fy=comp[:, 1], fz=comp[:, 2], mx=comp[:, 3], my=comp[:, 4],
        mz=comp[:, 5], Q=Q, redundant=q, method=method, drivers=model.drivers)


def solve_reactions(model: SpatialModel, geom: SpatialGeometry, wrenches: ArrayLike,
                    deviations: ArrayLike | None = None, *, method: str = "force",
                    phi1: ArrayLike | None = None) -> SpatialReactions:
    """Spatial joint reactions and driving torque for all positions of a cycle.

    Solves equilibrium of every moving body in space plus compatibility of the joint
    deformations with the manufacturing deviations (first-order theory, see the module
    docstring), batched over positions.

    Parameters
    ----------
    model : SpatialModel
    geom : SpatialGeometry
        n positions.
    wrenches : array, shape (n, n_bodies, 6)
        External + gravity + inertia (d'Alembert) wrench on every body about the origin [N, N·m]
        (:func:`wrench_about_origin`).
    deviations : array, shape (n_joints, 2, 6), optional
        Manufacturing deviations (see :func:`misfit`); None = a perfect mechanism.
    method : {"force", "displacement"}
        Force method (self-stress states + compatibility) or displacement method (assembled
        joint stiffness); they agree to round-off.
    phi1 : array (n,), optional
        Driver positions to store in the result (default: 0..n-1).

    Returns
    -------
    SpatialReactions

    Raises
    ------
    StructureError
        The mechanism can move in space (some loads cannot be carried) or passes a singular
        position.
    """
    n = geom.n
    ph = np.arange(n, dtype=float) if phi1 is None else require_finite("phi1", phi1)
    nd = model.n_drivers
    m = model.n_unknowns - nd
    dc = (np.zeros((n, m)) if deviations is None else misfit(model, geom, deviations))
    if dc.ndim != 2:
        raise ParameterError("deviations", dc.shape[:-2],
                             f"must have shape ({len(model.joints)}, 2, 6)")
    if method == "force":
        inf = influence(model, geom, wrenches)
        r = inf.r0 + np.einsum("nij,nj->ni", inf.h, dc)
        q = m + nd - inf.rank
    elif method == "displacement":
        w = require_finite("wrenches", wrenches)
        if w.shape != (n, model.n_bodies, 6):
            raise ParameterError("wrenches", w.shape, f"must have shape ({n}, {model.n_bodies}, 6)")
        a = equilibrium_matrix(model, geom)
        _, rows, cols = _scales(model, geom)
        # the rank at the first position gives q; a position where the rank drops makes the
        # assembled stiffness singular, which _displacement's conditioning check names
        s = np.linalg.svd(rows[:, None] * a[:1] * cols[None, :], compute_uv=False)
        rank = int(_rank(s)[0])
        if rank < 6 * model.n_bodies:
            raise StructureError(f"the mechanism is movable in space: rank of the equilibrium "
                                 f"matrix {rank} < 6 x {model.n_bodies} bodies")
        r = _displacement(model, geom, w, dc)
        q = m + nd - rank
    else:
        raise ParameterError("method", method, "must be 'force' or 'displacement'")
    return _to_result(model, geom, r, ph, q, method)


# ------------------------------------------------------------------------------------------------
# counting


@dataclass(frozen=True)
class RedundancyCount:
    """Structural count of a planar mechanism considered in space.

    Attributes
    ----------
    n_bodies : int
        Moving bodies n.
    classes : dict
        Joint name -> class k (number of constraints) in space.
    p : dict
        Class k -> number of joints p_k.
    mobility_formula : int
        Somov-Malyshev count :math:`W_0 = 6n - \\sum_k k p_k` (without redundancy).
    mobility : int
        Actual (instantaneous) mobility :math:`W = 6n - \\mathrm{rank}\\,A_c` (A_c: equilibrium
        matrix without the driver), local mobilities included.
    redundant : int
        Redundant constraints :math:`q = W - W_0` = number of self-stress states.
    labels : list of (joint, component)
        The reaction unknowns (driver last).
    determinate : ndarray of bool
        True where a reaction component is statically determinate (the same in every
        equilibrium solution; zero in every self-stress state).
    selfstress : ndarray, shape (n_unknowns, q)
        A basis of the self-stress states at the checked position (physical units, columns
        normalised to unit length in units scaled by the mechanism size).
    """

    n_bodies: int
    classes: dict[str, int]
    p: dict[int, int]
    mobility_formula: int
    mobility: int
    redundant: int
    labels: list[tuple[str, str]]
    determinate: np.ndarray
    selfstress: np.ndarray = field(repr=False)

    def indeterminate_labels(self) -> list[tuple[str, str]]:
        """The components that are not statically determinate."""
        return [lab for lab, d in zip(self.labels, self.determinate, strict=True) if not d]

    def summary(self) -> str:
        """A few lines for a report."""
        pk = ", ".join(f"p{k}={v}" for k, v in sorted(self.p.items(), reverse=True))
        ind = ", ".join(f"{c}_{j}" for j, c in self.indeterminate_labels()) or "none"
        return (f"n = {self.n_bodies} moving bodies; {pk}\n"
                f"Somov-Malyshev W0 = 6n - sum k p_k = {self.mobility_formula}; "
                f"actual mobility W = {self.mobility}; redundant constraints q = W - W0 = "
                f"{self.redundant}\nstatically indeterminate components: {ind}")


def count_redundancy(model: SpatialModel, geom: SpatialGeometry, position: int = 0
                     ) -> RedundancyCount:
    r"""Somov-Malyshev count and rank analysis of the spatial equilibrium matrix.

    .. math:: W = 6n - \sum_{k=1}^{5} k\,p_k + q

    ``W`` (actual mobility) and ``q`` come from the rank of the equilibrium matrix at
    ``position``: :math:`W = 6n - \mathrm{rank}\,A_c`, :math:`q = m - \mathrm{rank}\,A_c` with
    ``m`` the number of constraint components. A reaction component is statically determinate
    iff it vanishes in every self-stress state (the null space of A including the driver).

    Parameters
    ----------
    model, geom
        As for :func:`equilibrium_matrix`; only ``position`` of ``geom`` is used (pick a generic
        one, not a dead centre).
    position : int
        Index of the position checked.
    """
    if not 0 <= position < geom.n:
        raise ParameterError("position", position, f"must lie in [0, {geom.n - 1}]")
    g1 = SpatialGeometry(geom.points[position:position + 1],
                         geom.body_angles[position:position + 1],
                         None if geom.slide_angles is None
                         else geom.slide_angles[position:position + 1])
    a = equilibrium_matrix(model, g1)[0]
    _, rows, cols = _scales(model, g1)
    at = rows[:, None] * a * cols[None, :]
    m = at.shape[1] - model.n_drivers
    s_c = np.linalg.svd(at[:, :m], compute_uv=False)
    rank_c = int(_rank(s_c[None, :])[0]) if s_c.size else 0
    _, s, vh = np.linalg.svd(at)
    rank = int(_rank(s[None, :])[0])
    null = vh[rank:, :].T
    nb = model.n_bodies
    classes = {j.name: j.joint_class for j in model.joints}
    p: dict[int, int] = {}
    for k in classes.values():
        p[k] = p.get(k, 0) + 1
    w0 = 6 * nb - sum(k * v for k, v in p.items())
    w = 6 * nb - rank_c
    det = np.linalg.norm(null, axis=1) < 1e-8
    return RedundancyCount(n_bodies=nb, classes=classes, p=p, mobility_formula=w0, mobility=w,
                           redundant=w - w0, labels=model.labels(), determinate=det,
                           selfstress=cols[:, None] * null)
