"""Kinematics of a planar mechanism over all driver positions at once.

Positions: group by group in the order of :mod:`linkwork.planar.structure`; the driver body and
every dyad (RRR, RRP, PRR, RPR, RPP, PPR, PRP) and one-body slot group (RS, PS) in closed form,
as array expressions over the positions, with the branch chosen per group (see ``docs/planar.md``
for the branch definitions); other groups by Newton iteration continued from the previous
position. Velocities and accelerations: for each group the constraint equations, differentiated
once and twice, give a linear system in that group's body velocities (accelerations); the systems
of all positions are solved at once (closed form for the driver body, batched
``numpy.linalg.solve`` otherwise).

Body coordinates: origin ``(x, y)`` [m] and angle ``theta`` [rad] (counter-clockwise from the
fixed x-axis) of each body's own frame; ``vx, vy, ax, ay`` are the velocity [m/s] and
acceleration [m/s^2] of the body point at the body's origin, ``omega`` [rad/s] and ``eps``
[rad/s^2] the angular velocity and acceleration (counter-clockwise positive).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import (
    AssemblyError,
    ParameterError,
    StructureError,
    angle_ranges,
    require_finite,
)
from linkwork.planar.model import (
    Crank,
    Joint,
    Linear,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    _pt,
)
from linkwork.planar.structure import Group
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["DeadCentre", "Kinematics", "PointMotion", "dead_centres", "kinematics",
           "transmission_angles"]

Arr = np.ndarray
Vec = tuple[Arr, Arr]


# ---------------------------------------------------------------------------------------------
# state of all bodies over the positions
class _State:
    def __init__(self, nb: int, n: int) -> None:
        z = np.zeros(n)
        self.n = n
        self.X = [z] * nb
        self.Y = [z] * nb
        self.T = [z] * nb
        self.C = [z + 1.0] * nb
        self.S = [z] * nb
        self.VX = [z] * nb
        self.VY = [z] * nb
        self.W = [z] * nb
        self.AX = [z] * nb
        self.AY = [z] * nb
        self.E = [z] * nb
        self.bad = np.zeros(n, dtype=bool)
        self.pos_bad = self.bad
        self.failed: dict[str, Arr] = {}  # group key -> positions where it does not close
        self.parallel = False  # set when two lines of the group being solved were parallel
        self.parallel_groups: set[str] = set()
        self._rot: dict[tuple[int, float, float], Vec] = {}

    def set_angle(self, i: int, th: Arr, c: Arr | None = None, s: Arr | None = None) -> None:
        """Set body i's angle (with its cosine and sine when already known)."""
        self.T[i] = th
        self.C[i] = np.cos(th) if c is None else c
        self.S[i] = np.sin(th) if s is None else s
        if self._rot:
            self._rot = {k: v for k, v in self._rot.items() if k[0] != i}

    def rot(self, i: int, v: tuple[float, float]) -> Vec:
        """A local vector of body i in frame axes (cached per body and vector)."""
        key = (i, float(v[0]), float(v[1]))
        hit = self._rot.get(key)
        if hit is not None:
            return hit
        c, s = self.C[i], self.S[i]
        if key[2] == 0.0:
            out = (c * key[1], s * key[1])
        elif key[1] == 0.0:
            out = (-s * key[2], c * key[2])
        else:
            out = (c * key[1] - s * key[2], s * key[1] + c * key[2])
        self._rot[key] = out
        return out

    def wpt(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        return self.X[i] + rx, self.Y[i] + ry

    def place(self, i: int, p: tuple[float, float], world: Vec) -> None:
        """Set the origin of body i so that its local point p is at ``world`` (angle known)."""
        rx, ry = self.rot(i, p)
        self.X[i] = world[0] - rx
        self.Y[i] = world[1] - ry

    def point_vel(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        return self.VX[i] - self.W[i] * ry, self.VY[i] + self.W[i] * rx

    def point_acc(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        w2 = self.W[i] ** 2
        return (self.AX[i] - self.E[i] * ry - w2 * rx, self.AY[i] + self.E[i] * rx - w2 * ry)


# ---------------------------------------------------------------------------------------------
# results
@dataclass(frozen=True)
class PointMotion(Result):
    """Position [m], velocity [m/s] and acceleration [m/s^2] of a body point, frame axes."""

    phi1: Arr
    x: Arr
    y: Arr
    vx: Arr
    vy: Arr
    ax: Arr
    ay: Arr
    units: ClassVar[dict[str, str]] = {"phi1": "rad", "x": "m", "y": "m", "vx": "m/s",
                                       "vy": "m/s", "ax": "m/s^2", "ay": "m/s^2"}

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Position, velocity and acceleration components over the driver positions: a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.planar import point_motion_figure

        return point_motion_figure(self, axes=axes, **kw)


@dataclass(frozen=True)
class Kinematics(Result):
    """Positions, velocities and accelerations of every body over the driver positions.

    Arrays of shape ``(n_bodies + 1, n)``: row ``i`` is body ``bodies[i]`` (row 0 the frame,
    always zero), column ``k`` the driver position ``phi1[k]``.

    Attributes
    ----------
    mechanism : Mechanism
        The analysed mechanism.
    phi1, omega1, eps1 : ndarray (n,)
        Driver position [rad], speed [rad/s], acceleration [rad/s^2] (for a Linear driver: slide
        coordinate [m], speed [m/s], acceleration [m/s^2]).
    bodies : tuple of str
        Body names, frame first.
    x, y, theta : ndarray (nb, n)
        Pose of each body's frame [m, m, rad].
    vx, vy, omega : ndarray (nb, n)
        Velocity of the body point at the body's origin [m/s] and angular velocity [rad/s].
    ax, ay, eps : ndarray (nb, n)
        Acceleration of that point [m/s^2] and angular acceleration [rad/s^2].
    assembled : ndarray of bool (n,)
        False where the mechanism cannot be assembled (those positions hold NaN; only with
        ``on_fail="nan"``).
    branches : dict
        Branch used for each group key.
    """

    mechanism: Mechanism
    phi1: Arr
    omega1: Arr
    eps1: Arr
    bodies: tuple[str, ...]
    x: Arr
    y: Arr
    theta: Arr
    vx: Arr
    vy: Arr
    omega: Arr
    ax: Arr
    ay: Arr
    eps: Arr
    assembled: Arr
    branches: Mapping[str, int]
    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "omega1": "rad/s", "eps1": "rad/s^2", "x": "m", "y": "m", "theta": "rad",
        "vx": "m/s", "vy": "m/s", "omega": "rad/s", "ax": "m/s^2", "ay": "m/s^2",
        "eps": "rad/s^2", "assembled": ""}

    def __post_init__(self) -> None:
        if self.mechanism.driver.kind == "linear":  # slide coordinate, speed, acceleration
            self._relabel_units(phi1="m", omega1="m/s", eps1="m/s^2")

    @cached_property
    def _cos_sin(self) -> tuple[Arr, Arr]:
        return np.cos(self.theta), np.sin(self.theta)

    @property
    def n(self) -> int:
        """Number of positions."""
        return int(self.phi1.shape[0])

    def _row(self, body: str) -> int:
        try:
            return self.bodies.index(body)
        except ValueError:
            raise ParameterError("body", body, f"no such body; known: {list(self.bodies)}"
                                 ) from None

    def point(self, body: str, point: str | tuple[float, float] = "com") -> PointMotion:
        """Motion of a point of ``body``: a named point, ``"com"``, or local (x, y) [m]."""
        i = self._row(body)
        p = self.mechanism.body(body).point(point) if isinstance(point, str) else _pt(
            f"point of {body}", point)
        c, s = self._cos_sin[0][i], self._cos_sin[1][i]
        rx, ry = c * p[0] - s * p[1], s * p[0] + c * p[1]
        w, e = self.omega[i], self.eps[i]
        return PointMotion(self.phi1, self.x[i] + rx, self.y[i] + ry,
                           self.vx[i] - w * ry, self.vy[i] + w * rx,
                           self.ax[i] - e * ry - w * w * rx, self.ay[i] + e * rx - w * w * ry)

    def angle(self, body: str) -> Arr:
        """Angle of ``body``'s x-axis [rad] (continuous only where the model is)."""
        return self.theta[self._row(body)]

    def slide(self, joint: str) -> tuple[Arr, Arr, Arr]:
        """Slide coordinate, speed, acceleration of a prismatic or pin-in-slot joint.

        ``s = u . (P_b - Q_a)`` [m] with ``u`` the line's direction; the derivatives are taken
        relative to the guide body ``a`` (the sliding speed and acceleration along the line).
        """
        m = self.mechanism
        j = m.joint(joint)
        if not isinstance(j, Prismatic | PinInSlot):
            raise ParameterError("joint", joint, "must be prismatic or pin-in-slot")
        qa, pb, ang = m.joint_geometry(j)
        ia = self._row(j.a)
        ta = self.theta[ia]
        ux, uy = np.cos(ta + ang), np.sin(ta + ang)
        Q = self.point(j.a, qa)
        P = self.point(j.b, pb)
        dx, dy = P.x - Q.x, P.y - Q.y
        s = ux * dx + uy * dy
        # relative velocity of P w.r.t. the body a point coincident with it
        wa, ea = self.omega[ia], self.eps[ia]
        rvx = P.vx - (Q.vx - wa * dy)
        rvy = P.vy - (Q.vy + wa * dx)
        sd = ux * rvx + uy * rvy
        # relative acceleration: a_P - a_{a@P} - 2 wa k x v_rel
        aax = Q.ax - ea * dy - wa * wa * dx
        aay = Q.ay + ea * dx - wa * wa * dy
        rax = P.ax - aax + 2 * wa * rvy
        ray = P.ay - aay - 2 * wa * rvx
        return s, sd, ux * rax + uy * ray

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Angles, angular velocities and accelerations of the moving bodies over the driver
        positions: a :class:`linkwork.plot.Figure` with 3 axes
        (:func:`linkwork.plot.planar.plot_skeleton` draws the mechanism itself)."""
        from linkwork.plot.planar import kinematics_figure

        return kinematics_figure(self, axes=axes, **kw)


# ---------------------------------------------------------------------------------------------
# joint constraint rows: Jacobian blocks on body a and b, gamma (J qdd = gamma), residual
def _geom(mech: Mechanism, j: Joint) -> tuple[tuple[float, float], tuple[float, float], float]:
    return mech.joint_geometry(j)


def _rows(mech: Mechanism, st: _State, j: Joint, drv: Crank | Linear | None,
          rates: tuple[Arr, Arr] | None, need_gamma: bool = True) -> list[dict[str, Any]]:
    """Constraint rows of joint j (plus the driver row if drv is given).

    Each row: ``ja``, ``jb`` (3-tuples of arrays: d/dx, d/dy, d/dtheta), ``gam`` (acceleration
    right-hand side from velocity terms), ``rv``/``ra`` (driver's velocity/acceleration terms),
    ``res`` (residual, for Newton).
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    qa, pb, ang = _geom(mech, j)
    rows: list[dict[str, Any]] = []
    zero = np.zeros(st.n)
    one = zero + 1.0
    if isinstance(j, Revolute):
        wax, way = st.rot(ia, qa)
        wbx, wby = st.rot(ib, pb)
        wa2, wb2 = st.W[ia] ** 2, st.W[ib] ** 2
        res = (st.X[ia] + wax - st.X[ib] - wbx, st.Y[ia] + way - st.Y[ib] - wby)
        rows.append({"ja": (one, zero, -way), "jb": (-one, zero, wby),
                     "gam": wax * wa2 - wbx * wb2, "res": res[0]})
        rows.append({"ja": (zero, one, wax), "jb": (zero, -one, -wbx),
                     "gam": way * wa2 - wby * wb2, "res": res[1]})
        if drv is not None:
            rows.append({"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                         "drive": True, "res": st.T[ib] - st.T[ia]})
        return rows
    # line joints
    wax, way = st.rot(ia, qa)
    wbx, wby = st.rot(ib, pb)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    dx = st.X[ib] + wbx - st.X[ia] - wax
    dy = st.Y[ib] + wby - st.Y[ia] - way

    def line_row(ex: Arr, ey: Arr) -> dict[str, Any]:
        # Phi = e . d with e rotating with body a; k x e = (-ey, ex)
        kex, key_ = -ey, ex
        th_a = kex * dx + key_ * dy - (ex * -way + ey * wax)
        th_b = ex * -wby + ey * wbx
        row: dict[str, Any] = {"ja": (-ex, -ey, th_a), "jb": (ex, ey, th_b),
                               "res": ex * dx + ey * dy}
        if need_gamma:
            wa, wb = st.W[ia], st.W[ib]
            ddx = st.VX[ib] - wb * wby - st.VX[ia] + wa * way
            ddy = st.VY[ib] + wb * wbx - st.VY[ia] - wa * wax
            quad = (-wa * wa * (ex * dx + ey * dy) + 2 * wa * (kex * ddx + key_ * ddy)
                    + ex * (-wb * wb * wbx + wa * wa * wax) + ey * (-wb * wb * wby + wa * wa * way))
            row["gam"] = -quad
        return row

    rows.append(line_row(nx, ny))
    if isinstance(j, Prismatic):
        rows.append({"ja": (zero, zero, -one), "jb": (zero, zero, one), "gam": zero,
                     "res": st.T[ib] - st.T[ia] - j.rel_angle})
        if drv is not None:
            r = line_row(ux, uy)
            r["drive"] = True
            rows.append(r)
    return rows


# ---------------------------------------------------------------------------------------------
# closed-form position solutions
def _fail(st: _State, bad: Arr) -> None:
    st.bad |= bad


def _sqrt_checked(st: _State, arg: Arr, scale: Arr | float) -> Arr:
    tol = 1e-12 * np.asarray(scale) ** 2
    bad = ~(arg >= -tol)
    _fail(st, bad)
    return np.sqrt(np.where(bad, np.nan, np.maximum(arg, 0.0)))


def _theta_of_prismatic(mech: Mechanism, st: _State, j: Joint, body: int) -> Arr:
    """Angle of ``body`` fixed by prismatic joint j to an already-known body."""
    assert isinstance(j, Prismatic)
    ia, ib = mech.index[j.a], mech.index[j.b]
    return st.T[ia] + j.rel_angle if body == ib else st.T[ib] - j.rel_angle


def _locus(mech: Mechanism, st: _State, j: Joint, body: int, p_int: tuple[float, float]
           ) -> tuple[str, Any]:
    """Locus of the point ``p_int`` of ``body`` allowed by its external joint j.

    Returns ("circle", (A, radius, p_ext)) with A the world centre, or ("line", (B0, u)) with
    the body's angle set in ``st``: points ``B0 + t u``, ``u`` the guide direction.
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    k = ia if body == ib else ib
    qa, pb, ang = _geom(mech, j)
    if isinstance(j, Revolute):
        p_ext = qa if body == ia else pb
        p_known = pb if body == ia else qa
        A = st.wpt(k, p_known)
        rad = float(np.hypot(p_int[0] - p_ext[0], p_int[1] - p_ext[1]))
        if rad == 0.0:
            raise StructureError(f"joint {j.name}: body {mech.body_names[body]} has its two "
                                 "joint centres at the same point; the dyad is not determined")
        return "circle", (A, rad, p_ext)
    st.set_angle(body, _theta_of_prismatic(mech, st, j, body))
    if body == ib:  # body is the slider on known guide k = a
        Q = st.wpt(k, qa)
        u = st.rot(k, (np.cos(ang), np.sin(ang)))
        off = st.rot(body, (p_int[0] - pb[0], p_int[1] - pb[1]))
        return "line", ((Q[0] + off[0], Q[1] + off[1]), u)
    # body is the guide; the known body's point X slides on it: B = X + A(pB - qa) - s u
    X = st.wpt(k, pb)
    u = st.rot(body, (np.cos(ang), np.sin(ang)))
    off = st.rot(body, (p_int[0] - qa[0], p_int[1] - qa[1]))
    return "line", ((X[0] + off[0], X[1] + off[1]), u)


def _finish_side(st: _State, body: int, kind: str, data: Any, p_int: tuple[float, float],
                 B: Vec) -> None:
    if kind == "circle":
        A, rad, p_ext = data
        ex, ey = (B[0] - A[0]) / rad, (B[1] - A[1]) / rad
        phi0 = float(np.arctan2(p_int[1] - p_ext[1], p_int[0] - p_ext[0]))
        c0, s0 = np.cos(phi0), np.sin(phi0)
        th = np.arctan2(ey, ex)
        if phi0 != 0.0:
            st.set_angle(body, th - phi0, ex * c0 + ey * s0, ey * c0 - ex * s0)
        else:
            st.set_angle(body, th, ex, ey)
    st.place(body, p_int, B)


def _intersect(st: _State, l1: tuple[str, Any], l2: tuple[str, Any], branch: int) -> Vec:
    k1, d1 = l1
    k2, d2 = l2
    if k1 == "circle" and k2 == "circle":
        (A, r1, _), (C, r2, _) = d1, d2
        ex, ey = C[0] - A[0], C[1] - A[1]
        dd = np.hypot(ex, ey)
        with np.errstate(invalid="ignore", divide="ignore"):
            a = (r1 * r1 - r2 * r2 + dd * dd) / (2 * dd)
            h = _sqrt_checked(st, r1 * r1 - a * a, r1)
            ux, uy = ex / dd, ey / dd
        return A[0] + a * ux - branch * h * uy, A[1] + a * uy + branch * h * ux
    if k1 == "line" and k2 == "line":
        (P, u), (Q, v) = d1, d2
        den = u[0] * v[1] - u[1] * v[0]
        bad = np.abs(den) < 1e-12
        _fail(st, bad)
        st.parallel |= bool(bad.any())
        with np.errstate(invalid="ignore", divide="ignore"):
            t = ((Q[0] - P[0]) * v[1] - (Q[1] - P[1]) * v[0]) / np.where(bad, np.nan, den)
        return P[0] + t * u[0], P[1] + t * u[1]
    (A, r, _), (B0, u) = (d1, d2) if k1 == "circle" else (d2, d1)
    wx, wy = A[0] - B0[0], A[1] - B0[1]
    t0 = wx * u[0] + wy * u[1]
    perp2 = wx * wx + wy * wy - t0 * t0
    h = _sqrt_checked(st, r * r - perp2, r)
    t = t0 + branch * h
    return B0[0] + t * u[0], B0[1] + t * u[1]


def _solve_driver(mech: Mechanism, st: _State, g: Group, q: Arr) -> None:
    j = mech.joint(g.joints[0])
    ia, ib = mech.index[j.a], mech.index[j.b]
    u = mech.index[g.bodies[0]]
    qa, pb, ang = _geom(mech, j)
    if isinstance(j, Revolute):
        if u == ib:
            st.set_angle(ib, st.T[ia] + q)
            st.place(ib, pb, st.wpt(ia, qa))
        else:
            st.set_angle(ia, st.T[ib] - q)
            st.place(ia, qa, st.wpt(ib, pb))
        return
    assert isinstance(j, Prismatic)
    if u == ib:
        st.set_angle(ib, st.T[ia] + j.rel_angle)
        Q = st.wpt(ia, qa)
        ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
        st.place(ib, pb, (Q[0] + q * ux, Q[1] + q * uy))
    else:
        st.set_angle(ia, st.T[ib] - j.rel_angle)
        P = st.wpt(ib, pb)
        ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
        st.place(ia, qa, (P[0] - q * ux, P[1] - q * uy))


def _line_condition(mech: Mechanism, st: _State, j: Joint, body: int) -> tuple[Vec, Arr]:
    """For a body of known angle: the line constraint of joint j as ``n . r_body = c``."""
    ia, ib = mech.index[j.a], mech.index[j.b]
    qa, pb, ang = _geom(mech, j)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    if body == ia:  # body carries the line; known point X of b
        X = st.wpt(ib, pb)
        w = st.rot(ia, qa)
        return (nx, ny), nx * (X[0] - w[0]) + ny * (X[1] - w[1])
    Q = st.wpt(ia, qa)
    w = st.rot(ib, pb)
    return (nx, ny), nx * (Q[0] - w[0]) + ny * (Q[1] - w[1])


def _solve_two_lines(mech: Mechanism, st: _State, body: int, j1: Joint, j2: Joint) -> None:
    (n1, c1), (n2, c2) = _line_condition(mech, st, j1, body), _line_condition(mech, st, j2, body)
    den = n1[0] * n2[1] - n1[1] * n2[0]
    bad = np.abs(den) < 1e-12
    _fail(st, bad)
    st.parallel |= bool(bad.any())
    den = np.where(bad, np.nan, den)
    st.X[body] = (c1 * n2[1] - c2 * n1[1]) / den
    st.Y[body] = (n1[0] * c2 - n2[0] * c1) / den


def _rotating_line(mech: Mechanism, st: _State, g_body: int, A: Vec, a_loc: tuple[float, float],
                   line_q: tuple[float, float], ang: float, h: Arr | float, X: Vec,
                   branch: int) -> None:
    """Angle of body g pinned at A whose line (through q at angle ang) must pass through X.

    Solves ``(A(theta) n_loc) . (X - A) = h``; ``branch=+1`` makes the line's direction u
    point from A towards X (``u . (X - A) > 0``).
    """
    dx, dy = X[0] - A[0], X[1] - A[1]
    d = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = h / d
    bad = ~(np.abs(c) <= 1.0 + 1e-12)
    _fail(st, bad)
    acos = np.arccos(np.clip(np.where(bad, np.nan, c), -1.0, 1.0))
    th = np.arctan2(dy, dx) + branch * acos - ang - np.pi / 2
    st.set_angle(g_body, th)
    st.place(g_body, a_loc, A)


def _solve_dyad(mech: Mechanism, st: _State, g: Group, branch: int) -> None:
    j1, j2, j3 = (mech.joint(n) for n in g.joints)
    b1, b2 = (mech.index[b] for b in g.bodies)
    i2a, i2b = mech.index[j2.a], mech.index[j2.b]
    qa2, pb2, ang2 = _geom(mech, j2)
    if isinstance(j2, Revolute):
        p1 = qa2 if b1 == i2a else pb2
        p2 = pb2 if b2 == i2b else qa2
        L1 = _locus(mech, st, j1, b1, p1)
        L2 = _locus(mech, st, j3, b2, p2)
        B = _intersect(st, L1, L2, branch)
        _finish_side(st, b1, L1[0], L1[1], p1, B)
        _finish_side(st, b2, L2[0], L2[1], p2, B)
        return
    # internal prismatic: guide body ga, slider body sb
    assert isinstance(j2, Prismatic)
    ga, sb = i2a, i2b
    ext = {b1: j1, b2: j3}
    jg: Joint = ext[ga]
    js: Joint = ext[sb]
    if isinstance(jg, Revolute) and isinstance(js, Revolute):  # RPR
        A, a_loc = _pivot(mech, st, jg, ga)
        C, c_loc = _pivot(mech, st, js, sb)
        rel = j2.rel_angle
        cr, sr = np.cos(rel), np.sin(rel)
        px, py = pb2[0] - c_loc[0], pb2[1] - c_loc[1]
        rpx, rpy = cr * px - sr * py, sr * px + cr * py
        nlx, nly = -np.sin(ang2), np.cos(ang2)
        h = nlx * (qa2[0] - a_loc[0] - rpx) + nly * (qa2[1] - a_loc[1] - rpy)
        _rotating_line(mech, st, ga, A, a_loc, qa2, ang2, h, C, branch)
        st.set_angle(sb, st.T[ga] + rel)
        st.place(sb, c_loc, C)
        return
    # one or both external joints prismatic: both angles known
    if isinstance(jg, Prismatic) and isinstance(js, Prismatic):
        raise StructureError(f"dyad {g.bodies} with three prismatic pairs {g.joints} is not "
                             "determined (the sliding along the common direction is free)")
    jp: Joint
    jf: Joint
    if isinstance(jg, Prismatic):
        st.set_angle(ga, _theta_of_prismatic(mech, st, jg, ga))
        st.set_angle(sb, st.T[ga] + j2.rel_angle)
        pinned, free, jp, jf = sb, ga, js, jg
    else:  # jg is the revolute
        st.set_angle(sb, _theta_of_prismatic(mech, st, js, sb))
        st.set_angle(ga, st.T[sb] - j2.rel_angle)
        pinned, free, jp, jf = ga, sb, jg, js
    P, p_loc = _pivot(mech, st, jp, pinned)
    st.place(pinned, p_loc, P)
    _solve_two_lines(mech, st, free, jf, j2)


def _pivot(mech: Mechanism, st: _State, j: Joint, body: int) -> tuple[Vec, tuple[float, float]]:
    """World centre of revolute j (from its known side) and its local point on ``body``."""
    ia = mech.index[j.a]
    qa, pb, _ = _geom(mech, j)
    if body == ia:
        return st.wpt(mech.index[j.b], pb), qa
    return st.wpt(ia, qa), pb


def _solve_slot_group(mech: Mechanism, st: _State, g: Group, branch: int) -> None:
    jt, js = (mech.joint(n) for n in g.joints)
    b = mech.index[g.bodies[0]]
    ia, ib = mech.index[js.a], mech.index[js.b]
    qa, pb, ang = _geom(mech, js)
    if isinstance(jt, Prismatic):
        st.set_angle(b, _theta_of_prismatic(mech, st, jt, b))
        _solve_two_lines(mech, st, b, jt, js)
        return
    A, a_loc = _pivot(mech, st, jt, b)
    if b == ia:  # the body carries the slot; known pin X
        X = st.wpt(ib, pb)
        nlx, nly = -np.sin(ang), np.cos(ang)
        h = nlx * (qa[0] - a_loc[0]) + nly * (qa[1] - a_loc[1])
        _rotating_line(mech, st, b, A, a_loc, qa, ang, h, X, branch)
        return
    # the body carries the pin; slot in known body a
    rad = float(np.hypot(pb[0] - a_loc[0], pb[1] - a_loc[1]))
    if rad == 0.0:  # as for a dyad whose two joint centres coincide
        raise StructureError(f"joint {js.name}: the pin of body {g.bodies[0]} is at its pivot "
                             f"({jt.name}), so the slot cannot turn it; its angle is not "
                             "determined")
    Q = st.wpt(ia, qa)
    u = st.rot(ia, (np.cos(ang), np.sin(ang)))
    P = _intersect(st, ("circle", (A, rad, a_loc)), ("line", (Q, u)), branch)
    _finish_side(st, b, "circle", (A, rad, a_loc), pb, P)


# ---------------------------------------------------------------------------------------------
# Newton for general groups
def _group_rows(mech: Mechanism, st: _State, g: Group, need_gamma: bool
                ) -> list[tuple[int, int, dict[str, Any]]]:
    out = []
    for name in g.joints:
        j = mech.joint(name)
        drv = mech.driver if name == mech.driver.joint else None
        for r in _rows(mech, st, j, drv, None, need_gamma):
            out.append((mech.index[j.a], mech.index[j.b], r))
    return out


def _assemble(mech: Mechanism, st: _State, g: Group, rows: list[tuple[int, int, dict[str, Any]]]
              ) -> tuple[Arr, list[tuple[int, int, dict[str, Any]]]]:
    cols = {mech.index[b]: 3 * k for k, b in enumerate(g.bodies)}
    m = 3 * len(g.bodies)
    J = np.zeros((st.n, m, m))
    for r, (ia, ib, row) in enumerate(rows):
        for body, key in ((ia, "ja"), (ib, "jb")):
            if body in cols:
                c = cols[body]
                for k in range(3):
                    J[:, r, c + k] += row[key][k]
    return J, rows


def _known_part(mech: Mechanism, st: _State, g: Group, rows: list[tuple[int, int, dict[str, Any]]],
                level: str) -> Arr:
    """Sum over known bodies of J_known * (q_dot or q_ddot) for each row."""
    members = {mech.index[b] for b in g.bodies}
    out = np.zeros((st.n, len(rows)))
    for r, (ia, ib, row) in enumerate(rows):
        for body, key in ((ia, "ja"), (ib, "jb")):
            if body not in members:
                if level == "v":
                    q = (st.VX[body], st.VY[body], st.W[body])
                else:
                    q = (st.AX[body], st.AY[body], st.E[body])
                ja = row[key]
                out[:, r] += ja[0] * q[0] + ja[1] * q[1] + ja[2] * q[2]
    return out


def _newton_state(mech: Mechanism, st: _State, members: list[int], pos: Arr) -> _State:
    """A state holding the known bodies at positions ``pos`` (group members to be set)."""
    sub = _State(len(mech.body_names), pos.shape[0])
    for bi in range(len(mech.body_names)):
        if bi not in members:
            sub.X[bi], sub.Y[bi] = st.X[bi][pos], st.Y[bi][pos]
            sub.set_angle(bi, st.T[bi][pos], st.C[bi][pos], st.S[bi][pos])
    return sub


def _newton_iterate(mech: Mechanism, sub: _State, g: Group, members: list[int], q: Arr,
                    z: Arr, tol: float, max_iter: int) -> tuple[Arr, Arr]:
    """Newton on all positions of ``sub`` at once from ``z`` (n, k, 3); returns (z, converged)."""
    n = sub.n
    done = np.zeros(n, dtype=bool)
    z = z.copy()
    for _ in range(max_iter):
        for k, bi in enumerate(members):
            sub.X[bi], sub.Y[bi] = z[:, k, 0], z[:, k, 1]
            sub.set_angle(bi, z[:, k, 2])
        rows = _group_rows(mech, sub, g, need_gamma=False)
        J, _ = _assemble(mech, sub, g, rows)
        res = np.stack([r["res"] - (q if r.get("drive") else 0.0) for _, _, r in rows], axis=1)
        with np.errstate(invalid="ignore"):
            done = np.max(np.abs(res), axis=1) < tol
        todo = ~done & np.isfinite(res).all(axis=1)
        if not todo.any():
            break
        with np.errstate(all="ignore"):
            det = np.linalg.det(J[todo])
            ok = np.abs(det) > 1e-300
            dz = np.full((int(todo.sum()), res.shape[1]), np.nan)
            if ok.any():
                dz[ok] = np.linalg.solve(J[todo][ok], -res[todo][ok][..., None])[..., 0]
        z[todo] = z[todo] + dz.reshape(-1, *z.shape[1:])
    return z, done


def _solve_newton(mech: Mechanism, st: _State, g: Group, q: Arr, tol: float = 1e-12,
                  max_iter: int = 30) -> None:
    """Newton for a general group, continued over the positions.

    Up to 100 positions are solved one after the other, each from the previous solution (the
    first from the bodies' ``guess`` poses). For longer arrays a coarse subset of about 100
    positions is continued that way, then every position is solved at once (batched Newton)
    starting from the coarse solution just before it; positions that still fail are retried
    one by one from their predecessor.
    """
    members = [mech.index[b] for b in g.bodies]
    n = st.n
    nm = len(members)
    tol = tol * _length_scale(mech)
    z0 = np.empty((nm, 3))
    for k, bname in enumerate(g.bodies):
        gs = mech.body(bname).guess
        z0[k] = gs if gs is not None else (0.0, 0.0, 0.0)

    def sequential(pos: Arr, start: Arr) -> tuple[Arr, Arr]:
        out = np.full((pos.shape[0], nm, 3), np.nan)
        okk = np.zeros(pos.shape[0], dtype=bool)
        z = start
        for t, i in enumerate(pos):
            sub = _newton_state(mech, st, members, np.array([i]))
            zi, conv = _newton_iterate(mech, sub, g, members, q[i:i + 1], z[None], tol,
                                       max_iter)
            if conv[0]:
                out[t], okk[t] = zi[0], True
                z = zi[0]
        return out, okk

    if n <= 100:
        sol, good = sequential(np.arange(n), z0)
    else:
        idx = np.unique(np.r_[np.arange(0, n, int(np.ceil(n / 100))), n - 1])
        zc, okc = sequential(idx, z0)
        idx, zc = idx[okc], zc[okc]
        if idx.size == 0:
            sol, good = np.full((n, nm, 3), np.nan), np.zeros(n, dtype=bool)
        else:
            j = np.clip(np.searchsorted(idx, np.arange(n), side="right") - 1, 0, None)
            sub = _newton_state(mech, st, members, np.arange(n))
            sol, good = _newton_iterate(mech, sub, g, members, q, zc[j], tol, max_iter)
            for i in np.flatnonzero(~good):
                if i > 0 and good[i - 1]:
                    zi, conv = sequential(np.array([i]), sol[i - 1])
                    if conv[0]:
                        sol[i], good[i] = zi[0], True
    sol[~good] = np.nan
    st.bad |= ~good
    for k, bi in enumerate(members):
        st.X[bi], st.Y[bi] = sol[:, k, 0], sol[:, k, 1]
        st.set_angle(bi, sol[:, k, 2])


def _length_scale(mech: Mechanism) -> float:
    pts = [abs(c) for b in (mech.frame, *mech.bodies) for p in b.points.values() for c in p]
    return max(max(pts, default=1.0), 1e-3)


# ---------------------------------------------------------------------------------------------
# velocities and accelerations
def _driver_rates(mech: Mechanism, st: _State, g: Group, w1: Arr, e1: Arr) -> bool:
    """Closed-form velocity/acceleration of a crank body; False if not applicable."""
    j = mech.joint(g.joints[0])
    if not isinstance(j, Revolute):
        return False
    ia, ib = mech.index[j.a], mech.index[j.b]
    u = mech.index[g.bodies[0]]
    k = ia if u == ib else ib
    sign = 1.0 if u == ib else -1.0
    qa, pb, _ = _geom(mech, j)
    pk, pu = (qa, pb) if u == ib else (pb, qa)
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


def _group_rates(mech: Mechanism, st: _State, g: Group, w1: Arr, e1: Arr) -> None:
    if g.kind == "driver":
        if not _driver_rates(mech, st, g, w1, e1):
            _linear_driver_rates(mech, st, g, w1, e1)
        return
    if g.kind != "newton":
        _closed_rates(mech, st, g)
        return
    members = [mech.index[b] for b in g.bodies]
    rows = _group_rows(mech, st, g, need_gamma=False)
    J, _ = _assemble(mech, st, g, rows)
    rhs = -_known_part(mech, st, g, rows, "v")
    for r, (_, _, row) in enumerate(rows):
        if row.get("drive"):
            rhs[:, r] += w1
    good = ~st.bad
    sol = _batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.VX[b], st.VY[b], st.W[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]
    rows = _group_rows(mech, st, g, need_gamma=True)
    rhs = -_known_part(mech, st, g, rows, "a")
    for r, (_, _, row) in enumerate(rows):
        rhs[:, r] += row["gam"]
        if row.get("drive"):
            rhs[:, r] += e1
    sol = _batched_solve(J, rhs, good)
    for k, b in enumerate(members):
        st.AX[b], st.AY[b], st.E[b] = sol[:, 3 * k], sol[:, 3 * k + 1], sol[:, 3 * k + 2]


# ---------------------------------------------------------------------------------------------
# closed-form velocities and accelerations of dyads and one-body slot groups
def _vel_at(st: _State, k: int, X: Vec) -> Vec:
    """Velocity of the material point of body k at world point X."""
    return (st.VX[k] - st.W[k] * (X[1] - st.Y[k]), st.VY[k] + st.W[k] * (X[0] - st.X[k]))


def _acc_at(st: _State, k: int, X: Vec) -> Vec:
    """Acceleration of the material point of body k at world point X."""
    rx, ry = X[0] - st.X[k], X[1] - st.Y[k]
    w2 = st.W[k] ** 2
    return (st.AX[k] - st.E[k] * ry - w2 * rx, st.AY[k] + st.E[k] * rx - w2 * ry)


class _Par:
    """Motion of body b hung on a known body k through joint j, with one unknown rate z.

    Revolute at A: ``z = omega_b``, ``v_b(X) = v_k(A) + z k x (X - A)``,
    ``a_b(X) = a_k(A) + zdot k x (X - A) - z^2 (X - A)``.
    Prismatic with guide direction u: ``z`` = velocity of b relative to k along u,
    ``omega_b = omega_k``, ``v_b(X) = v_k(X) + z u``, ``a_b(X) = a_k(X) + zdot u + 2 omega_k z
    (k x u)``. A known body (``j`` None) has no unknown.
    """

    def __init__(self, mech: Mechanism, st: _State, j: Joint | None, b: int,
                 idx: int | None) -> None:
        self.st, self.b, self.idx = st, b, idx
        self.rev = False
        self.known = j is None
        self.z: Arr | float = 0.0
        if j is None:
            return
        ia, ib = mech.index[j.a], mech.index[j.b]
        self.k = ia if b == ib else ib
        qa, pb, ang = mech.joint_geometry(j)
        if isinstance(j, Revolute):
            self.rev = True
            self.pk = qa if self.k == ia else pb
            self.A = st.wpt(self.k, self.pk)
        else:
            self.u = st.rot(ia, (np.cos(ang), np.sin(ang)))

    def d(self, X: Vec) -> Vec:
        if self.known:
            return 0.0, 0.0  # type: ignore[return-value]
        if self.rev:
            return -(X[1] - self.A[1]), X[0] - self.A[0]
        return self.u

    def cv(self, X: Vec) -> Vec:
        if self.known:
            return _vel_at(self.st, self.b, X)
        if self.rev:
            return self.st.point_vel(self.k, self.pk)
        return _vel_at(self.st, self.k, X)

    def w(self) -> tuple[Arr | float, float]:
        """Angular velocity as (constant part, coefficient of z)."""
        if self.known:
            return self.st.W[self.b], 0.0
        return (0.0, 1.0) if self.rev else (self.st.W[self.k], 0.0)

    def e(self) -> tuple[Arr | float, float]:
        if self.known:
            return self.st.E[self.b], 0.0
        return (0.0, 1.0) if self.rev else (self.st.E[self.k], 0.0)

    def ca(self, X: Vec) -> Vec:
        """Acceleration at X without the zdot term (z already solved)."""
        if self.known:
            return _acc_at(self.st, self.b, X)
        z = self.z
        if self.rev:
            aA = self.st.point_acc(self.k, self.pk)
            return (aA[0] - z * z * (X[0] - self.A[0]), aA[1] - z * z * (X[1] - self.A[1]))
        aK = _acc_at(self.st, self.k, X)
        c = 2 * self.st.W[self.k] * z
        return aK[0] - c * self.u[1], aK[1] + c * self.u[0]

    def vel(self, X: Vec) -> Vec:
        c = self.cv(X)
        if self.known:
            return c
        dd = self.d(X)
        return c[0] + self.z * dd[0], c[1] + self.z * dd[1]

    def set_velocity(self) -> None:
        st, b = self.st, self.b
        r = (st.X[b], st.Y[b])
        st.VX[b], st.VY[b] = self.vel(r)
        c, k = self.w()
        st.W[b] = np.asarray(c + k * self.z, dtype=float)

    def set_acceleration(self, zd: Arr) -> None:
        st, b = self.st, self.b
        r = (st.X[b], st.Y[b])
        c = self.ca(r)
        dd = self.d(r)
        st.AX[b], st.AY[b] = c[0] + zd * dd[0], c[1] + zd * dd[1]
        c0, k = self.e()
        st.E[b] = np.asarray(c0 + k * zd, dtype=float)


def _closure_rows(mech: Mechanism, st: _State, j: Joint, pars: dict[int, _Par], n_unk: int,
                  level: str) -> list[tuple[list[Arr | float], Arr]]:
    """Closure equations of joint j in the unknown rates: rows (coefficients, rhs).

    ``level="v"``: velocity rows; ``"a"``: acceleration rows (the same coefficients, z known).
    Revolute at B: ``v_a(B) = v_b(B)``; prismatic (guide a): ``omega_a = omega_b`` and
    ``n . (v_b(P) - v_a(P)) = 0``; pin-in-slot: the latter only. Accelerations add the Coriolis
    term ``-2 omega_a k x v_rel`` of the relative sliding.
    """
    ia, ib = mech.index[j.a], mech.index[j.b]
    pa_, pb_ = pars[ia], pars[ib]
    _qa, pb, ang = mech.joint_geometry(j)
    rows: list[tuple[list[Arr | float], Arr]] = []

    def coefs(vals: list[tuple[_Par, Any]]) -> list[Arr | float]:
        c: list[Arr | float] = [0.0] * n_unk
        for par, val in vals:
            if par.idx is not None:
                c[par.idx] = c[par.idx] + val
        return c

    if isinstance(j, Revolute):
        B = st.wpt(ib, pb)
        da, db = pa_.d(B), pb_.d(B)
        if level == "v":
            ca, cb = pa_.cv(B), pb_.cv(B)
        else:
            ca, cb = pa_.ca(B), pb_.ca(B)
        for c in range(2):
            rows.append((coefs([(pa_, da[c]), (pb_, -db[c])]), cb[c] - ca[c]))
        return rows
    P = st.wpt(ib, pb)
    ux, uy = st.rot(ia, (np.cos(ang), np.sin(ang)))
    nx, ny = -uy, ux
    da, db = pa_.d(P), pb_.d(P)
    cf = coefs([(pa_, -(nx * da[0] + ny * da[1])), (pb_, nx * db[0] + ny * db[1])])
    if level == "v":
        ca, cb = pa_.cv(P), pb_.cv(P)
        rows.append((cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1]))))
    else:
        ca, cb = pa_.ca(P), pb_.ca(P)
        va, vb = pa_.vel(P), pb_.vel(P)
        wa = pa_.w()[0] + pa_.w()[1] * pa_.z
        rvx, rvy = vb[0] - va[0], vb[1] - va[1]
        cor = 2 * wa * (nx * -rvy + ny * rvx)
        rows.append((cf, -(nx * (cb[0] - ca[0]) + ny * (cb[1] - ca[1])) + cor))
    if isinstance(j, Prismatic):
        (c0a, ka), (c0b, kb) = (pa_.w(), pb_.w()) if level == "v" else (pa_.e(), pb_.e())
        rows.append((coefs([(pa_, ka), (pb_, -kb)]), np.asarray(c0b - c0a) + np.zeros(st.n)))
    return rows


def _cramer(st: _State, rows: list[tuple[list[Arr | float], Arr]], scale: Arr | float
            ) -> list[Arr]:
    """Solve 1x1 or 2x2 systems position by position; singular -> NaN.

    A 2 x 2 system is singular (a toggle) where ``|det|`` is below 1e-7 times the product of its
    column norms (the sine of the angle between the columns); a 1 x 1 one where the coefficient
    is below 1e-7 ``scale`` (a length). Near a toggle rounding alone leaves that sine near
    1e-8, so such positions would otherwise give arbitrary finite rates.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        if len(rows) == 1:
            (a,), r = rows[0]
            a = np.asarray(a) + np.zeros(st.n)
            sing = ~(np.abs(a) > 1e-7 * np.asarray(scale))
            return [np.where(sing, np.nan, r / np.where(sing, 1.0, a))]
        (a11, a12), r1 = rows[0]
        (a21, a22), r2 = rows[1]
        det = np.asarray(a11 * a22 - a12 * a21) + np.zeros(st.n)
        norm = np.hypot(a11, a21) * np.hypot(a12, a22)
        sing = ~(np.abs(det) > 1e-7 * norm)
        inv = 1.0 / np.where(sing, np.nan, det)
        return [(r1 * a22 - r2 * a12) * inv, (a11 * r2 - a21 * r1) * inv]


def _group_pars(mech: Mechanism, st: _State, g: Group) -> tuple[dict[int, _Par], Joint,
                                                                list[_Par]]:
    """Parametrisations of a closed-form group's bodies and its closure joint."""
    nb = len(mech.body_names)
    members = [mech.index[b] for b in g.bodies]
    pars: dict[int, _Par] = {}
    for i in range(nb):
        if i not in members:
            pars[i] = _Par(mech, st, None, i, None)
    if g.kind in ("RS", "PS"):
        jt, js = (mech.joint(n) for n in g.joints)
        b = members[0]
        pars[b] = _Par(mech, st, jt, b, 0)
        return pars, js, [pars[b]]
    j1, j2, j3 = (mech.joint(n) for n in g.joints)
    b1, b2 = members
    pars[b1] = _Par(mech, st, j1, b1, 0)
    pars[b2] = _Par(mech, st, j3, b2, 1)
    return pars, j2, [pars[b1], pars[b2]]


def _closed_rates(mech: Mechanism, st: _State, g: Group) -> None:
    pars, jc, unk = _group_pars(mech, st, g)
    n_unk = len(unk)
    L = _length_scale(mech)
    scale = L ** n_unk
    z = _cramer(st, _closure_rows(mech, st, jc, pars, n_unk, "v"), scale)
    for p, zi in zip(unk, z, strict=True):
        p.z = zi
    for p in unk:
        p.set_velocity()
    zd = _cramer(st, _closure_rows(mech, st, jc, pars, n_unk, "a"), scale)
    for p, zdi in zip(unk, zd, strict=True):
        p.set_acceleration(zdi)


def _linear_driver_rates(mech: Mechanism, st: _State, g: Group, w1: Arr, e1: Arr) -> None:
    j = mech.joint(g.joints[0])
    b = mech.index[g.bodies[0]]
    sign = 1.0 if b == mech.index[j.b] else -1.0
    p = _Par(mech, st, j, b, 0)
    p.z = sign * w1
    p.set_velocity()
    p.set_acceleration(sign * e1)


def _batched_solve(J: Arr, rhs: Arr, good: Arr) -> Arr:
    out = np.full(rhs.shape, np.nan)
    if good.all():
        Jg, rg = J, rhs
    else:
        Jg, rg = J[good], rhs[good]
    with np.errstate(all="ignore"):
        det = np.linalg.det(Jg) if Jg.shape[0] else np.zeros(0)
        sing = ~(np.abs(det) > 1e-300)
        if sing.any():
            Jg = Jg.copy()
            Jg[sing] = np.eye(J.shape[1])
        x = np.linalg.solve(Jg, rg[..., None])[..., 0]
        x[sing] = np.nan
    if good.all():
        return x
    out[good] = x
    return out


# ---------------------------------------------------------------------------------------------
_CHUNK = 8192


def _per_position(name: str, value: ArrayLike, n: int) -> Arr:
    a = require_finite(name, value)
    try:
        return np.broadcast_to(a, (n,)).astype(float)
    except ValueError:
        raise ParameterError(name, a.shape, f"must be a scalar or have shape ({n},)") from None


def _solve_chunk(mech: Mechanism, groups: tuple[Group, ...], branches: dict[str, int], q: Arr,
                 w1: Arr, e1: Arr) -> _State:
    """Positions, velocities, accelerations of all bodies for the positions ``q``."""
    st = _State(len(mech.body_names), q.shape[0])
    with np.errstate(all="ignore"):
        for g in groups:
            b = branches[g.key]
            before = st.bad.copy()
            if g.kind == "driver":
                _solve_driver(mech, st, g, q)
            elif g.kind in ("RS", "PS"):
                _solve_slot_group(mech, st, g, b)
            elif g.kind == "newton":
                _solve_newton(mech, st, g, q)
            else:
                _solve_dyad(mech, st, g, b)
            if (st.bad & ~before).any():
                st.failed[g.key] = st.bad & ~before
            if st.parallel:
                st.parallel_groups.add(g.key)
                st.parallel = False
        st.pos_bad = st.bad.copy()
        for g in groups:
            _group_rates(mech, st, g, w1, e1)
    return st


_PARALLEL = (", whose two lines (guides, slots) are parallel there, so that the place along "
             "them is not determined")


def _newton_hint(mech: Mechanism, g: Group) -> str:
    """What a failed Newton group's message must add: it may assemble where Newton failed."""
    if g.kind != "newton":
        return ""
    missing = [b for b in g.bodies if mech.body(b).guess is None]
    start = (f"; bodies {', '.join(missing)} have no guess pose and started from (0, 0, 0): "
             "give each a guess (x [m], y [m], theta [rad]) near an assembled pose"
             if missing else " from the bodies' guess poses, continued")
    return (f", solved by Newton iteration{start}; the mechanism may assemble where Newton did "
            "not converge")


def kinematics(mech: Mechanism, phi1: ArrayLike, omega1: ArrayLike | None = None,
               eps1: ArrayLike | None = None, *, branches: Mapping[str, int] | None = None,
               on_fail: Literal["raise", "nan"] = "raise") -> Kinematics:
    """Positions, velocities and accelerations of all bodies for all driver positions.

    Parameters
    ----------
    mech : Mechanism
        The mechanism (its structure is analysed first; StructureError if wrong).
    phi1 : array_like (n,)
        Driver positions: crank angle [rad] (``theta_b - theta_a`` of the driver joint) or, for
        a Linear driver, the slide coordinate [m].
    omega1, eps1 : float or array_like (n,), optional
        Driver speed and acceleration per position (default: the driver's ``omega1``,
        ``eps1``; for a Linear driver ``v1``, ``a1``).
    branches : mapping, optional
        Group key -> +1/-1, overriding ``mech.branches``.
    on_fail : {"raise", "nan"}
        Where some positions cannot be assembled: raise AssemblyError listing the driver ranges
        (default), or return NaN there with ``assembled`` False.

    Returns
    -------
    Kinematics
    """
    if not isinstance(mech, Mechanism):
        raise ParameterError("mech", mech, "must be a Mechanism")
    q = np.atleast_1d(require_finite("phi1", phi1)).astype(float)
    if q.ndim != 1:
        raise ParameterError("phi1", q.shape, "must be a 1-D array of driver positions")
    if on_fail not in ("raise", "nan"):
        raise ParameterError("on_fail", on_fail, "must be 'raise' or 'nan'")
    n = q.shape[0]
    drv = mech.driver
    w1 = _per_position("omega1", drv.omega1 if omega1 is None else omega1, n)
    e1 = _per_position("eps1", drv.eps1 if eps1 is None else eps1, n)
    if branches is not None and not isinstance(branches, Mapping):
        raise ParameterError("branches", branches, "must map group keys to +1 or -1")
    br = dict(mech.branches)
    br.update(branches or {})
    for k_, v_ in br.items():
        if isinstance(v_, bool) or v_ not in (1, -1):  # True == 1
            raise ParameterError(f"branches.{k_}", v_, "must be +1 or -1")
    structure = mech.structure
    nb = len(mech.body_names)
    group_keys = [g.key for g in structure.groups if g.kind != "driver"]
    # (the driver's key is accepted too: Kinematics.branches lists every group)
    unknown = sorted(set(br) - {g.key for g in structure.groups})
    if unknown:  # a misspelt key would silently leave that group on branch +1
        raise ParameterError("branches", unknown[0],
                             f"no assembly group has this key; known: {group_keys}")
    used = {g.key: int(br.get(g.key, 1)) for g in structure.groups}
    keys = ("X", "Y", "T", "VX", "VY", "W", "AX", "AY", "E")
    block = np.empty((len(keys), nb, n))  # one allocation: much faster than nine
    pos_bad = np.zeros(n, dtype=bool)
    bad = np.zeros(n, dtype=bool)
    failed: set[str] = set()
    parallel: set[str] = set()
    # chunks keep the temporaries in cache; Newton groups need the whole sequence
    newton = any(g.kind == "newton" for g in structure.groups)
    step = n if newton else _CHUNK
    for lo in range(0, n, step):
        sl = slice(lo, min(lo + step, n))
        st = _solve_chunk(mech, structure.groups, used, q[sl], w1[sl], e1[sl])
        pos_bad[sl] = st.pos_bad
        failed.update(st.failed)
        parallel.update(st.parallel_groups)
        bad[sl] = st.bad
        for i in range(1, nb):
            bad[sl] |= ~np.isfinite(st.W[i])
        for kk, key in enumerate(keys):
            for i, arr in enumerate(getattr(st, key)):
                block[kk, i, sl] = arr
    unit = "rad" if isinstance(drv, Crank) else "m"
    if pos_bad.any() and on_fail == "raise":
        groups = [f"{g.kind}({', '.join(g.bodies)}) with joints {', '.join(g.joints)}"
                  + _newton_hint(mech, g) + (_PARALLEL if g.key in parallel else "")
                  for g in structure.groups if g.key in failed]
        only_newton = bool(failed) and all(g.kind == "newton" for g in structure.groups
                                           if g.key in failed)
        which = (f" (group{'s' if len(groups) > 1 else ''} that "
                 f"{'did not' if only_newton else 'cannot'} close: "
                 f"{'; '.join(groups)})" if groups else "")
        what = ("Newton iteration did not assemble the mechanism" if only_newton
                else "mechanism cannot be assembled")
        raise AssemblyError(f"{what} at {int(pos_bad.sum())} of {n} driver positions{which}",
                            angle_ranges(q, pos_bad),
                            driver="phi1" if unit == "rad" else "s1", unit=unit)
    if bad.any() and on_fail == "raise":
        raise AssemblyError("mechanism is at a singular (toggle) position where velocities are "
                            "undefined", angle_ranges(q, bad),
                            driver="phi1" if unit == "rad" else "s1", unit=unit)
    if bad.any():
        block[:, :, bad] = np.nan
    out = dict(zip(keys, block, strict=True))
    return Kinematics(mech, q, w1.copy(), e1.copy(), mech.body_names, out["X"], out["Y"],
                      out["T"], out["VX"], out["VY"], out["W"], out["AX"], out["AY"], out["E"],
                      ~bad, used)



# ---------------------------------------------------------------------------------------------
# transmission angles and dead centres
@dataclass(frozen=True)
class DeadCentre:
    """A dead-centre (extreme) position of a group's output body.

    ``phi1`` [rad or m] is where the output body's motion relative to its external joint
    reverses (angular velocity relative to the neighbour, or sliding speed, crosses zero),
    located between the samples to ~1e-13 (see :func:`dead_centres`); ``kind`` is ``"min"`` or
    ``"max"`` of its angle or slide.
    """

    group: str
    body: str
    phi1: float
    kind: str


def _require_kinematics(kin: Any) -> Kinematics:
    """``kin`` itself, or a ParameterError if it is not a :class:`Kinematics` result."""
    if not isinstance(kin, Kinematics):
        raise ParameterError("kin", kin, "must be the Kinematics result of kinematics()")
    return kin


def _state_of(kin: Kinematics) -> _State:
    nb, n = kin.x.shape
    st = _State(nb, n)
    cos, sin = kin._cos_sin
    for i in range(nb):
        st.X[i], st.Y[i] = kin.x[i], kin.y[i]
        st.set_angle(i, kin.theta[i], cos[i], sin[i])
        st.VX[i], st.VY[i], st.W[i] = kin.vx[i], kin.vy[i], kin.omega[i]
        st.AX[i], st.AY[i], st.E[i] = kin.ax[i], kin.ay[i], kin.eps[i]
    return st


def transmission_angles(kin: Kinematics) -> dict[str, tuple[Arr, Arr]]:
    """Transmission angle ``mu`` and pressure angle ``delta = pi/2 - mu`` of every closed-form
    group, keyed by the group key [rad].

    ``delta`` is the acute angle between the force that the group's joint J2 (the joint
    between its bodies; the slot of a one-body group) transmits to the output body (the dyad's
    second body, or the one body) and the velocity of its point of application as a point of
    the output body moving about (along) its external joint. The force is taken along the
    first body's joint line for a link with two revolute joints, normal to the guide for
    prismatic pairs and slots (no friction, the first body's own loads neglected). ``mu`` = 90
    deg is the best transmission, 0 the toggle.
    """
    mech = _require_kinematics(kin).mechanism
    st = _state_of(kin)
    out: dict[str, tuple[Arr, Arr]] = {}
    for g in mech.structure.groups:
        if g.kind in ("driver", "newton"):
            continue
        _pars, jc, unk = _group_pars(mech, st, g)
        out_par = unk[-1]
        _qa, pb, ang = mech.joint_geometry(jc)
        P = st.wpt(mech.index[jc.b], pb)
        if isinstance(jc, Revolute):
            first = unk[0]
            if first.rev:
                fx, fy = P[0] - first.A[0], P[1] - first.A[1]
            else:
                fx, fy = -first.u[1], first.u[0]
        else:
            ux, uy = st.rot(mech.index[jc.a], (np.cos(ang), np.sin(ang)))
            fx, fy = -uy, ux
        vx, vy = out_par.d(P)
        # atan2(|f x v|, |f . v|): full precision also near 0 and 90 deg (arccos of the
        # cosine loses half the digits near delta = 0)
        cr, dt = np.abs(fx * vy - fy * vx), np.abs(fx * vx + fy * vy)
        delta = np.where((cr == 0) & (dt == 0), np.nan, np.arctan2(cr, dt))  # NaN: undefined
        out[g.key] = (np.pi / 2 - delta, delta)
    return out


def _group_rate(mech: Mechanism, st: _State, g: Group) -> tuple[int, Arr]:
    """Output body of a closed-form group and its rate relative to its external neighbour:
    angular velocity (revolute) or sliding speed along the guide (prismatic)."""
    _pars, _, unk = _group_pars(mech, st, g)
    p = unk[-1]
    b = p.b
    if p.rev:
        return b, st.W[b] - st.W[p.k]
    # sliding velocity of the output body relative to its neighbour along u
    r = (st.X[b], st.Y[b])
    vb, vk = _vel_at(st, b, r), _vel_at(st, p.k, r)
    return b, (vb[0] - vk[0]) * p.u[0] + (vb[1] - vk[1]) * p.u[1]


def _refine_dead_centre(kin: Kinematics, g: Group, lo: float, hi: float, guess: float) -> float:
    """The zero of the group's rate between driver positions lo and hi, to ~1e-13 [rad or m]:
    Brent's method on single-position analyses (unit driver speed, no acceleration), falling
    back to ``guess`` (linear interpolation) where that is not possible."""
    from scipy.optimize import brentq

    mech = kin.mechanism
    br = dict(kin.branches)

    def rate(x: float) -> float:
        k1 = kinematics(mech, [x], 1.0, 0.0, branches=br, on_fail="nan")
        return float(_group_rate(mech, _state_of(k1), g)[1][0])

    try:
        f_lo, f_hi = rate(lo), rate(hi)
        if not (np.isfinite(f_lo) and np.isfinite(f_hi)) or f_lo * f_hi > 0:
            return guess
        if f_lo == 0.0:
            return lo
        if f_hi == 0.0:
            return hi
        scale = max(abs(lo), abs(hi), 1.0)
        return float(brentq(rate, lo, hi, xtol=1e-14 * scale, rtol=1e-15, maxiter=60))
    except (ValueError, RuntimeError):  # every linkwork error is one of these
        return guess


def dead_centres(kin: Kinematics) -> list[DeadCentre]:
    """Dead-centre positions of the output body of every closed-form group (see DeadCentre).

    For a crank-rocker four-bar these are the rocker's two extreme positions (crank and
    coupler collinear); for a crank-slider, the slider's.  Each sign change of the output's
    rate between two samples is located to ~1e-13 by Brent's method on single-position
    analyses (for mechanisms without Newton-solved groups; with them, linearly interpolated).
    """
    mech = _require_kinematics(kin).mechanism
    st = _state_of(kin)
    found: list[DeadCentre] = []
    q = kin.phi1
    refine = not any(g.kind == "newton" for g in mech.structure.groups)
    for g in mech.structure.groups:
        if g.kind in ("driver", "newton"):
            continue
        b, rate = _group_rate(mech, st, g)
        tiny = 1e-12 * float(np.nanmax(np.abs(rate))) if np.isfinite(rate).any() else 0.0
        rate = np.where(np.abs(rate) <= tiny, 0.0, rate)
        sgn = np.sign(rate)
        name = mech.body_names[b]
        idx = np.flatnonzero((sgn[:-1] * sgn[1:] < 0) & np.isfinite(rate[:-1] + rate[1:]))
        for i in idx:
            t = rate[i] / (rate[i] - rate[i + 1])
            at = float(q[i] + t * (q[i + 1] - q[i]))
            if refine:
                at = _refine_dead_centre(kin, g, float(q[i]), float(q[i + 1]), at)
            found.append(DeadCentre(g.key, name, at, "max" if rate[i] > 0 else "min"))
        for i in np.flatnonzero(sgn == 0):  # a sample exactly at the dead centre
            before = sgn[i - 1] if i > 0 else -sgn[i + 1] if i + 1 < sgn.size else 0
            after = sgn[i + 1] if i + 1 < sgn.size else -before
            if before * after < 0:
                found.append(DeadCentre(g.key, name, float(q[i]), "max" if before > 0 else "min"))
    found.sort(key=lambda d: (d.group, d.phi1))
    return found
