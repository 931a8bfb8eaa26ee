"""Kinematics of a planar mechanism over all driver positions at once: the public API.

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

The work is split by concern: :mod:`~linkwork.planar.state` (the solver state),
:mod:`~linkwork.planar.positions` (driver, dyads, slot groups, Newton groups),
:mod:`~linkwork.planar.rates` (velocities, accelerations) and
:mod:`~linkwork.planar.extremes` (transmission angles, dead centres); this module holds
:func:`kinematics`, its results :class:`Kinematics` and :class:`PointMotion`, and re-exports the
rest of the public names.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_point
from linkwork.deprecation import renamed_attribute, renamed_keywords
from linkwork.errors import AssemblyError, ParameterError, angle_ranges, format_angle_ranges
from linkwork.planar.compiled import check_backend, check_threads
from linkwork.planar.designs import branch_value, column, design_point, pick
from linkwork.planar.extremes import (
    DeadCentre,
    dead_centres_of_rates,
    output_rates,
    transmission_angles_of,
)
from linkwork.planar.model import Drawing, Mechanism
from linkwork.planar.positions import solve_group
from linkwork.planar.rates import group_rates
from linkwork.planar.state import Arr, State
from linkwork.planar.structure import Group, Plan
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["DeadCentre", "Kinematics", "PointMotion", "dead_centres", "dead_centres_over",
           "kinematics", "require_kinematics", "state_of", "transmission_angles"]


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
    phi1, omega1, eps1 : ndarray (n,), or (n_drivers, n) for several drivers
        Driver position [rad], speed [rad/s], acceleration [rad/s^2] (for a Linear driver: slide
        coordinate [m], speed [m/s], acceleration [m/s^2]); rows in the order of
        ``Mechanism.drivers``.
    bodies : tuple of str
        Body names, frame first.
    x, y, theta : ndarray (nb, n)
        Pose of each body's frame [m, m, rad].
    vx, vy, omega : ndarray (nb, n)
        Velocity of the body point at the body's origin [m/s] and angular velocity [rad/s].
    ax, ay, eps : ndarray (nb, n)
        Acceleration of that point [m/s^2] and angular acceleration [rad/s^2].
    valid : ndarray of bool (n,)
        False where the mechanism cannot be assembled (those positions hold NaN; only with
        ``on_failure="nan"``); also readable as ``assembled`` (deprecated).
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
    valid: Arr
    branches: Mapping[str, int]
    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "omega1": "rad/s", "eps1": "rad/s^2", "x": "m", "y": "m", "theta": "rad",
        "vx": "m/s", "vy": "m/s", "omega": "rad/s", "ax": "m/s^2", "ay": "m/s^2",
        "eps": "rad/s^2", "valid": ""}
    assembled = renamed_attribute("valid", "assembled")

    def __post_init__(self) -> None:
        du = self.mechanism.driver_units  # a linear driver: slide, speed, acceleration
        units = {k: du[k] for k in ("phi1", "omega1", "eps1")}
        if any(self.units[k] != v for k, v in units.items()):
            self._relabel_units(**units)

    @cached_property
    def _cos_sin(self) -> tuple[Arr, Arr]:
        return np.cos(self.theta), np.sin(self.theta)

    @property
    def n(self) -> int:
        """Number of positions."""
        return int(self.phi1.shape[-1])

    def _row(self, body: str) -> int:
        try:
            return self.bodies.index(body)
        except ValueError:
            raise ParameterError("body", body, f"no such body; known: {list(self.bodies)}"
                                 ) from None

    @property
    def n_designs(self) -> int | None:
        """The number of designs of a batch (arrays ``(..., m, n)``), None for one design."""
        return self.mechanism.n_designs

    def design(self, i: int) -> Kinematics:
        """The motion of design ``i`` of a batch, as :func:`kinematics` gives it for that
        design alone (``self`` for one design and ``i = 0``)."""
        mech = self.mechanism.design(i)
        if self.n_designs is None:
            return self
        k = int(i) % self.n_designs
        nd = mech.n_drivers
        q = self.phi1 if self.phi1.ndim == (1 if nd == 1 else 2) else self.phi1[..., k, :]

        def row(a: Arr) -> Arr:
            return np.array(a[..., k, :])

        return Kinematics(mech, np.array(q), row(self.omega1), row(self.eps1), self.bodies,
                          row(self.x), row(self.y), row(self.theta), row(self.vx),
                          row(self.vy), row(self.omega), row(self.ax), row(self.ay),
                          row(self.eps), row(self.valid),
                          {key: int(pick(v, k)) for key, v in self.branches.items()})

    def point(self, body: str, point: str | tuple[float, float] = "com") -> PointMotion:
        """Motion of a point of ``body``: a named point, ``"com"``, or local (x, y) [m] (for a
        batch, numbers or arrays over the designs; fields of shape (m, n))."""
        i = self._row(body)
        p = self.mechanism.body(body).point(point) if isinstance(point, str) else (
            design_point(f"point of {body}", point) if self.n_designs is not None
            else require_point(f"point of {body}", point))
        return PointMotion(self.phi1, *self._motion(i, column(p[0]), column(p[1])))

    def centres_of_mass(self) -> PointMotion:
        """Motion of the centres of mass of the moving bodies, in the mechanism's order: every
        field of shape ``(n_moving_bodies, n)`` (the same numbers as :meth:`point` per body;
        ``(n_moving_bodies, m, n)`` for a batch)."""
        bodies = self.mechanism.bodies
        m = self.n_designs
        if m is not None:
            com = np.array([np.broadcast_to(v, (m,)) for b in bodies for v in b.com])
            cx, cy = com[0::2, :, None], com[1::2, :, None]
            return PointMotion(self.phi1, *self._motion(slice(1, 1 + len(bodies)), cx, cy))
        com = np.array([b.point("com") for b in bodies], dtype=float).reshape(-1, 2)
        # the moving bodies are rows 1.. of the arrays, in order: a slice, so no copies
        return PointMotion(self.phi1, *self._motion(slice(1, 1 + len(bodies)), com[:, :1],
                                                    com[:, 1:]))

    def _motion(self, rows: int | slice, px: Any, py: Any) -> tuple[Arr, ...]:
        """x, y, vx, vy, ax, ay of the body-frame points (px, py) of the bodies in ``rows``."""
        c, s = self._cos_sin[0][rows], self._cos_sin[1][rows]
        rx, ry = c * px - s * py, s * px + c * py
        w, e = self.omega[rows], self.eps[rows]
        return (self.x[rows] + rx, self.y[rows] + ry, self.vx[rows] - w * ry,
                self.vy[rows] + w * rx, self.ax[rows] - e * ry - w * w * rx,
                self.ay[rows] + e * rx - w * w * ry)

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
        if not j.has_line:
            raise ParameterError("joint", joint, "must be prismatic or pin-in-slot")
        qa, pb, ang = m.joint_geometry(j)
        ia = self._row(j.a)
        ta = self.theta[ia]
        ux, uy = np.cos(ta + column(ang)), np.sin(ta + column(ang))
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

    def _scene(self) -> Any:
        """The mechanism drawn over these positions (:func:`linkwork.plot.scene.planar_scene`)."""
        from linkwork.plot.scene import planar_scene

        return planar_scene(self)

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Angles, angular velocities and accelerations of the moving bodies over the driver
        positions: a :class:`linkwork.plot.Figure` with 3 axes
        (:func:`linkwork.plot.planar.plot_skeleton` draws the mechanism itself)."""
        from linkwork.plot.planar import kinematics_figure

        return kinematics_figure(self, axes=axes, **kw)


# ---------------------------------------------------------------------------------------------
_CHUNK = 8192



def _solve_chunk(plan: Plan, branches: dict[str, int], q: Arr, w1: Arr, e1: Arr) -> State:
    """Positions, velocities, accelerations of all bodies for the positions ``q``."""
    st = State(plan.nb, q.shape[-1])
    with np.errstate(all="ignore"):
        for g in plan.groups:
            b = branches[g.key]
            before = st.bad.copy()
            solve_group(plan, st, g, b, q)
            if (st.bad & ~before).any():
                st.failed[g.key] = st.bad & ~before
            if st.parallel:
                st.parallel_groups.add(g.key)
                st.parallel = False
        st.pos_bad = st.bad.copy()
        for g in plan.groups:
            group_rates(plan, st, g, w1, e1)
    return st


#: Largest step of the continuation from a drawing to the first position: crank [rad], slide
#: [fraction of the mechanism's size]; at most 100 steps.
_PATH_STEP = (np.radians(3.0), 0.02)


def _from_drawing(drawing: Drawing, drivers: tuple[Any, ...], plan: Plan,
                  used: dict[str, int], q: Arr) -> Plan:
    """The plan whose Newton groups start at the first position ``q[:, 0]`` from the poses
    continued there from the drawing (the drawn poses if the continuation fails)."""
    ref = np.array(drawing.positions)
    first = q[:, 0]
    crank = np.array([d.kind == "crank" for d in drivers])
    # a crank reaches the first position the short way (the mechanism repeats every turn)
    delta = np.where(crank, np.remainder(first - ref + np.pi, 2 * np.pi) - np.pi, first - ref)
    step = np.where(crank, _PATH_STEP[0], _PATH_STEP[1] * plan.length_scale)
    m = int(min(max(np.max(np.ceil(np.abs(delta) / step)), 1), 100))
    path = ref[:, None] + delta[:, None] * np.linspace(0.0, 1.0, m + 1)[None, :]
    zero = np.zeros_like(path)
    st = _solve_chunk(plan, used, path, zero, zero)
    if st.pos_bad[-1]:
        return plan
    groups = []
    for g in plan.groups:
        if g.kind == "newton":
            g = replace(g, guesses=tuple((float(st.X[b][-1]), float(st.Y[b][-1]),
                                          float(st.T[b][-1])) for b in g.bodies))
        groups.append(g)
    return replace(plan, groups=tuple(groups))


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


@renamed_keywords(on_fail="on_failure")
def kinematics(mech: Mechanism, phi1: ArrayLike, omega1: ArrayLike | None = None,
               eps1: ArrayLike | None = None, *, branches: Mapping[str, int] | None = None,
               on_failure: Literal["raise", "nan"] = "raise",
               backend: Literal["numpy", "numba"] = "numpy", threads: int = 1) -> Kinematics:
    """Positions, velocities and accelerations of all bodies for all driver positions.

    Parameters
    ----------
    mech : Mechanism
        The mechanism (its structure is analysed first; StructureError if wrong).
    phi1 : array_like (n,), or (n_drivers, n) for several drivers
        Driver positions: crank angle [rad] (``theta_b - theta_a`` of the driver joint) or, for
        a Linear driver, the slide coordinate [m]; with several drivers one row per driver in
        the order of ``Mechanism.drivers`` (column k: the drivers' positions at position k).
    omega1, eps1 : float or array_like (n,), optional
        Driver speed and acceleration per position (default: the driver's ``omega1``,
        ``eps1``; for a Linear driver ``v1``, ``a1``); with several drivers a scalar for all,
        one value per driver ``(n_drivers,)`` or ``(n_drivers, n)``.
    branches : mapping, optional
        Group key -> +1/-1, overriding ``mech.branches``.
    on_failure : {"raise", "nan"}
        Where some positions cannot be assembled: raise AssemblyError listing the driver ranges
        (default; with several drivers the ranges of the position index, each driver's values
        named in the message), or return NaN there with ``valid`` False. (``on_fail`` is its
        deprecated name.)
    backend : {"numpy", "numba"}
        ``"numpy"`` (the default and the reference) or ``"numba"``: the compiled kernel of
        :mod:`linkwork.planar.compiled.kinematics` (the optional extra ``numba``), one pass over
        the positions (and designs) for the plans it covers (crank and linear drivers, one or
        several, and closed-form groups: RRR, RRP, PRR, RPR, RPP, PPR, PRP, RS, PS); other
        plans run the NumPy path. The same numbers to rounding (``docs/planar.md``).
    threads : int
        With ``backend="numba"``: the compiled kernel's threads (default 1, the calling
        thread). The designs of a batch and blocks of positions are shared among them; every
        element is computed alone, so the result is the same bit for bit on any number of
        threads. At most numba's thread count (``NUMBA_NUM_THREADS``); a plan the kernel does
        not cover runs the NumPy path on one thread.

    Returns
    -------
    Kinematics

    Notes
    -----
    A batch of m designs (``mech.n_designs``, :mod:`~linkwork.planar.designs`) is evaluated
    in one call: ``phi1`` of shape ``(n,)`` (the same positions for every design) or ``(m, n)``
    (``(n_drivers, n)`` or ``(n_drivers, m, n)`` with several drivers), ``omega1``, ``eps1``
    anything that broadcasts to ``(m, n)`` (per design: ``(m, 1)``), ``branches`` values +1/-1
    or arrays of them over the designs. The result's arrays are ``(nb, m, n)`` and ``valid``
    ``(m, n)``: each design's own assembly mask; with ``on_failure="raise"`` the error names
    the designs that do not assemble (``AssemblyError.designs``). Design i of the result is
    that design's own analysis (``kin.design(i)``).
    """
    if backend != "numpy":
        check_backend(backend)
    threads = check_threads(threads, backend)
    if not isinstance(mech, Mechanism):
        raise ParameterError("mech", mech, "must be a Mechanism")
    if mech.n_designs is not None:
        return _batch_kinematics(mech, phi1, omega1, eps1, branches, on_failure, backend,
                                 threads)
    nd = mech.n_drivers
    q = np.atleast_1d(require_finite("phi1", phi1)).astype(float)
    if nd == 1 and q.ndim != 1:
        raise ParameterError("phi1", q.shape, "must be a 1-D array of driver positions")
    if nd > 1 and (q.ndim != 2 or q.shape[0] != nd):
        raise ParameterError("phi1", q.shape, f"must have shape ({nd}, n): the positions of "
                             f"the {nd} drivers "
                             f"({', '.join(d.joint for d in mech.drivers)}), in order")
    if on_failure not in ("raise", "nan"):
        raise ParameterError("on_failure", on_failure, "must be 'raise' or 'nan'")
    n = q.shape[-1]
    drivers = mech.drivers
    w1 = _driver_default(drivers, "omega1", n) if omega1 is None else None
    if w1 is None:
        w1 = mech.driver_values("omega1", np.array([d.omega1 for d in drivers])
                                if omega1 is None else omega1, n)
    e1 = _driver_default(drivers, "eps1", n) if eps1 is None else None
    if e1 is None:
        e1 = mech.driver_values("eps1", np.array([d.eps1 for d in drivers]) if eps1 is None
                                else eps1, n)
    q2, w2, e2 = q.reshape(nd, n), w1.reshape(nd, n), e1.reshape(nd, n)
    used = _branches_used(mech, branches)
    structure = mech.structure
    plan = mech.plan
    nb = plan.nb
    keys = ("X", "Y", "T", "VX", "VY", "W", "AX", "AY", "E")
    block = np.empty((len(keys), nb, n))  # one allocation: much faster than nine
    pos_bad = np.zeros(n, dtype=bool)
    bad = np.zeros(n, dtype=bool)
    failed: set[str] = set()
    parallel: set[str] = set()
    compiled = _compiled(plan) if backend == "numba" else None
    if compiled is not None:
        run, enc = compiled
        pos_bad, bad, failed, parallel = run(enc, used, q2[:, None], w2[:, None],
                                             e2[:, None], block.reshape(len(keys), nb, 1, n),
                                             threads=threads)
        pos_bad, bad = pos_bad[0], bad[0]
    elif plan.newton and mech.drawing is not None and n:
        plan = _from_drawing(mech.drawing, mech.drivers, plan, used, q2)
    # chunks keep the temporaries in cache; Newton groups need the whole sequence
    step = n if plan.newton else _CHUNK
    for lo in range(0, n if compiled is None else 0, step):
        sl = slice(lo, min(lo + step, n))
        st = _solve_chunk(plan, used, q2[:, sl], w2[:, sl], e2[:, sl])
        pos_bad[sl] = st.pos_bad
        failed.update(st.failed)
        parallel.update(st.parallel_groups)
        bad[sl] = st.bad
        for i in range(1, nb):
            bad[sl] |= ~np.isfinite(st.W[i])
        if step >= n and _stack_into(block, st, keys):
            continue  # (one chunk: one copy of all rows, not 9 x nb)
        for kk, key in enumerate(keys):
            for i, arr in enumerate(getattr(st, key)):
                block[kk, i, sl] = arr
    if pos_bad.any() and on_failure == "raise":
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
        raise _assembly_error(mech, q2, pos_bad, f"{what} at {int(pos_bad.sum())} of {n} "
                              f"driver positions{which}")
    if bad.any() and on_failure == "raise":
        raise _assembly_error(mech, q2, bad, "mechanism is at a singular (toggle) position "
                              "where velocities are undefined")
    if bad.any():
        block[:, :, bad] = np.nan
    out = dict(zip(keys, block, strict=True))
    return Kinematics(mech, q, w1.copy(), e1.copy(), mech.body_names, out["X"], out["Y"],
                      out["T"], out["VX"], out["VY"], out["W"], out["AX"], out["AY"], out["E"],
                      ~bad, used)


def _compiled(plan: Plan) -> tuple[Any, Any] | None:
    """The compiled kernel's runner and the plan encoded for it, or None where the kernel does
    not cover the plan (the NumPy path then runs)."""
    import linkwork.planar.compiled.kinematics as compiled  # imports numba: only when asked

    enc = compiled.encode(plan)
    return None if enc is None else (compiled.run, enc)


def _driver_default(drivers: tuple[Any, ...], name: str, n: int) -> Arr | None:
    """The one driver's own speed or acceleration ``name`` at the ``n`` positions when it is a
    finite Python float (what :meth:`Mechanism.driver_values` gives for it, without its
    checks); None otherwise (several drivers, or a value for the checks to judge)."""
    if len(drivers) != 1:
        return None
    v = getattr(drivers[0], name)
    return np.full(n, v) if type(v) is float and math.isfinite(v) else None


def _stack_into(block: Arr, st: State, keys: tuple[str, ...]) -> bool:
    """Copy the rows of ``st`` (each of the arrays ``keys`` of every body, over all of the
    positions of ``block``) into ``block`` in one assignment; False (nothing copied) where a
    row is not an array over those positions."""
    try:
        rows = np.array([arr for key in keys for arr in getattr(st, key)], dtype=float)
    except ValueError:  # rows of different shapes
        return False
    if rows.shape != (block.shape[0] * block.shape[1], block.shape[2]):
        return False
    block[...] = rows.reshape(block.shape)
    return True


def _batch_inputs(mech: Mechanism, phi1: ArrayLike, omega1: ArrayLike | None,
                  eps1: ArrayLike | None) -> tuple[Arr, Arr, Arr, Arr, Arr]:
    """The driver positions, speeds and accelerations of a batch, as given (``q``) and as
    read-only views of shape ``(n_drivers, m, n)``."""
    nd = mech.n_drivers
    m = mech.n_designs
    assert m is not None
    q = np.atleast_1d(require_finite("phi1", phi1)).astype(float)
    shapes = f"(n,) or ({m}, n)" if nd == 1 else f"({nd}, n) or ({nd}, {m}, n)"
    lead = q[None] if nd == 1 else q
    if (lead.ndim not in (2, 3) or lead.shape[0] != nd
            or (lead.ndim == 3 and lead.shape[1] != m)):
        raise ParameterError("phi1", q.shape, f"must have shape {shapes}: the driver "
                             f"positions, the same for the {m} designs or per design")
    n = lead.shape[-1]
    qv = np.broadcast_to(lead[:, None, :] if lead.ndim == 2 else lead, (nd, m, n))
    drivers = mech.drivers
    out = []
    for name, value, default in (("omega1", omega1, [d.omega1 for d in drivers]),
                                 ("eps1", eps1, [d.eps1 for d in drivers])):
        a = require_finite(name, np.array(default) if value is None else value)
        given = a.shape
        if nd > 1 and a.ndim == 1 and a.shape[0] == nd:
            a = a[:, None, None]  # one value per driver
        elif nd > 1 and a.ndim >= 2 and a.shape[0] == nd:
            a = a[:, None, :] if a.ndim == 2 else a
        elif nd == 1:
            a = a[None]
        else:
            a = a[None] if a.ndim == 0 else a
        try:
            out.append(np.broadcast_to(a, (nd, m, n)))
        except ValueError:
            raise ParameterError(name, given, f"must broadcast to the driver "
                                 f"positions {shapes}: a scalar, per position (n,), per "
                                 f"design ({m}, 1) or both ({m}, n)"
                                 + (f", each with the {nd} drivers first" if nd > 1 else "")
                                 ) from None
    return q, qv, out[0], out[1], np.zeros(0)


def _batch_kinematics(mech: Mechanism, phi1: ArrayLike, omega1: ArrayLike | None,
                      eps1: ArrayLike | None, branches: Mapping[str, Any] | None,
                      on_failure: str, backend: str = "numpy", threads: int = 1
                      ) -> Kinematics:
    """:func:`kinematics` of a batch of designs (``mech.n_designs`` not None): each block of
    designs flattened with its positions and solved on the plan picked there; one design at a
    time (in chunks of positions) when the positions alone fill a chunk or a Newton group
    continues along them, exactly as that design alone."""
    q, qv, wv, ev, _ = _batch_inputs(mech, phi1, omega1, eps1)
    if on_failure not in ("raise", "nan"):
        raise ParameterError("on_failure", on_failure, "must be 'raise' or 'nan'")
    used = _branches_used(mech, branches)
    structure = mech.structure
    plan = mech.plan
    nd, m, n = qv.shape
    nb = plan.nb
    keys = ("X", "Y", "T", "VX", "VY", "W", "AX", "AY", "E")
    block = np.zeros((len(keys), nb, m, n))
    pos_bad = np.zeros((m, n), dtype=bool)
    bad = np.zeros((m, n), dtype=bool)
    failed: set[str] = set()
    parallel: set[str] = set()
    compiled = _compiled(plan) if backend == "numba" else None
    if compiled is not None:
        run, enc = compiled
        pos_bad, bad, failed, parallel = run(enc, used, qv, wv, ev, block, zeroed=True,
                                             threads=threads)
    per_design = plan.newton or n >= _CHUNK
    k = 1 if per_design else max(1, _CHUNK // max(n, 1))
    step = n if plan.newton else _CHUNK
    for d0 in range(0, m if n and compiled is None else 0, k):
        d1 = min(d0 + k, m)
        if per_design:
            sub = plan.pick(d0)
            br = {key: int(pick(v, d0)) for key, v in used.items()}
            if plan.newton and mech.drawing is not None:
                sub = _from_drawing(mech.drawing.design(d0) if mech.drawing.batched
                                    else mech.drawing, mech.drivers, sub, br, qv[:, d0])
            parts = [(slice(d0, d1), slice(lo, min(lo + step, n))) for lo in range(0, n, step)]
        else:
            index = np.repeat(np.arange(d0, d1), n)
            sub = plan.pick(index)
            br = {key: pick(v, index) for key, v in used.items()}
            parts = [(slice(d0, d1), slice(0, n))]
        for ds, ps in parts:
            shape = (d1 - d0, ps.stop - ps.start)
            st = _solve_chunk(sub, br, qv[:, ds, ps].reshape(nd, -1),
                              wv[:, ds, ps].reshape(nd, -1), ev[:, ds, ps].reshape(nd, -1))
            pos_bad[ds, ps] = st.pos_bad.reshape(shape)
            failed.update(st.failed)
            parallel.update(st.parallel_groups)
            b = st.bad.copy()
            for i in range(1, nb):
                b |= ~np.isfinite(st.W[i])
            bad[ds, ps] = b.reshape(shape)
            for kk, key in enumerate(keys):
                for i, arr in enumerate(getattr(st, key)):
                    if i:
                        block[kk, i, ds, ps] = arr.reshape(shape)
    if on_failure == "raise" and bad.any():
        raise _batch_assembly_error(mech, structure, qv, pos_bad, bad, failed, parallel)
    if bad.any():
        block[:, :, bad] = np.nan
    out = dict(zip(keys, block, strict=True))
    w1 = wv[0] if nd == 1 else wv
    e1 = ev[0] if nd == 1 else ev
    return Kinematics(mech, q, w1, e1, mech.body_names, out["X"], out["Y"], out["T"],
                      out["VX"], out["VY"], out["W"], out["AX"], out["AY"], out["E"], ~bad, used)


def _batch_assembly_error(mech: Mechanism, structure: Any, qv: Arr, pos_bad: Arr, bad: Arr,
                          failed: set[str], parallel: set[str]) -> AssemblyError:
    """The AssemblyError of a batch: how many designs fail, the first of them with their
    ranges of the driver coordinate (of the position index, with several drivers)."""
    designs = np.flatnonzero(bad.any(axis=-1))
    m, n = bad.shape
    if pos_bad.any():
        groups = [f"{g.kind}({', '.join(g.bodies)}) with joints {', '.join(g.joints)}"
                  + _newton_hint(mech, g) + (_PARALLEL if g.key in parallel else "")
                  for g in structure.groups if g.key in failed]
        which = (f" (group{'s' if len(groups) > 1 else ''} that cannot close: "
                 f"{'; '.join(groups)})" if groups else "")
        what = f"mechanism cannot be assembled{which}"
    else:
        what = "mechanism is at a singular (toggle) position where velocities are undefined"
    one = mech.n_drivers == 1
    coordinate, unit = mech.driver.coordinate if one else ("position index", "")
    shown = []
    for d in designs[:5]:
        x = qv[0, d] if one else np.arange(n)
        shown.append(f"design {d} at {coordinate} "
                     f"{format_angle_ranges(angle_ranges(x, bad[d]), unit)}")
    more = f" and {designs.size - 5} more designs" if designs.size > 5 else ""
    err = AssemblyError(f"{what} in {designs.size} of {m} designs: {'; '.join(shown)}{more} "
                        "(on_failure='nan' gives every design, with valid (m, n) False "
                        "where it does not assemble)")
    err.designs = [int(d) for d in designs]  # type: ignore[attr-defined]
    return err


def _branches_used(mech: Mechanism, branches: Mapping[str, Any] | None) -> dict[str, Any]:
    """The branch of every group: ``mech.branches`` updated by ``branches`` (+1 or -1, or an
    array of them over the designs of a batch), +1 where not given."""
    if branches is not None and not isinstance(branches, Mapping):
        raise ParameterError("branches", branches, "must map group keys to +1 or -1")
    br = dict(mech.branches)
    m = mech.n_designs
    for k_, v_ in (branches or {}).items():
        v_ = branch_value(f"branches.{k_}", v_)
        if isinstance(v_, np.ndarray) and v_.shape != (m,):
            raise ParameterError(f"branches.{k_}", f"{v_.shape[0]} branches",
                                 "must be one branch, or one per design of a batch "
                                 f"({m or 'not a batch'})")
        br[k_] = v_
    structure = mech.structure
    group_keys = [g.key for g in structure.groups if g.kind != "driver"]
    # (the driver's key is accepted too: Kinematics.branches lists every group)
    unknown = sorted(set(br) - {g.key for g in structure.groups})
    if unknown:  # a misspelt key would silently leave that group on branch +1
        raise ParameterError("branches", unknown[0],
                             f"no assembly group has this key; known: {group_keys}")
    return {g.key: br[g.key] if isinstance(br.get(g.key), np.ndarray) else int(br.get(g.key, 1))
            for g in structure.groups}


def _assembly_error(mech: Mechanism, q2: Arr, mask: Arr, what: str) -> AssemblyError:
    """The AssemblyError for the positions ``mask``: its ranges of the driver coordinate (one
    driver), or of the position index with each driver's values there (several drivers)."""
    if mech.n_drivers == 1:
        coordinate, unit = mech.driver.coordinate
        return AssemblyError(what, angle_ranges(q2[0], mask), driver=coordinate, unit=unit)
    ranges = angle_ranges(np.arange(q2.shape[1]), mask)
    parts = []
    for lo, hi in ranges[:8]:
        i, j = int(lo), int(hi)
        vals = "; ".join(
            f"{d.joint} {format_angle_ranges([(q2[k, i], q2[k, j])], d.coordinate[1])}"
            for k, d in enumerate(mech.drivers))
        parts.append(f"{i}" + (f"-{j}" if j > i else "") + f" ({vals})")
    more = f" and {len(ranges) - 8} more" if len(ranges) > 8 else ""
    err = AssemblyError(f"{what}; cannot assemble at positions {', '.join(parts)}{more}")
    err.ranges = [(float(a), float(b)) for a, b in ranges]
    err.driver = "position index"
    return err


# ---------------------------------------------------------------------------------------------
# derived quantities (the algorithms live in linkwork.planar.extremes)
def require_kinematics(kin: Any) -> Kinematics:
    """``kin`` itself, or a ParameterError if it is not a :class:`Kinematics` result."""
    if not isinstance(kin, Kinematics):
        raise ParameterError("kin", kin, "must be the Kinematics result of kinematics()")
    return kin


def state_of(kin: Kinematics) -> State:
    """The solver state holding the solved motion ``kin`` (to derive further quantities)."""
    nb, n = kin.x.shape
    st = State(nb, n)
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
    kin = require_kinematics(kin)
    return transmission_angles_of(kin.mechanism.plan, state_of(kin))


def dead_centres(kin: Kinematics) -> list[DeadCentre]:
    """Dead-centre positions of the output body of every closed-form group (see DeadCentre).

    For a crank-rocker four-bar these are the rocker's two extreme positions (crank and
    coupler collinear); for a crank-slider, the slider's.  Each sign change of the output's
    rate between two samples is located to ~1e-13 by Brent's method on single-position
    analyses (for mechanisms without Newton-solved groups; with them, linearly interpolated).
    Defined for one driver (a position where the output reverses as the driver advances);
    with several drivers the list is empty.
    """
    kin = require_kinematics(kin)
    if kin.mechanism.n_drivers > 1:
        return []
    return dead_centres_over(kin.mechanism, kin.phi1,
                             output_rates(kin.mechanism.plan, state_of(kin)), kin.branches)


def dead_centres_over(mech: Mechanism, phi1: Arr, rates: dict[str, tuple[int, Arr]],
                      branches: Mapping[str, int]) -> list[DeadCentre]:
    """:func:`dead_centres` of a motion kept only as the output rates of its groups
    (:func:`linkwork.planar.extremes.output_rates` of each chunk of a long cycle, joined) over
    the driver positions ``phi1``, solved on ``branches``; empty for several drivers."""
    if mech.n_drivers > 1:
        return []
    refine = not mech.plan.newton
    br = dict(branches)

    def resolve(x: float) -> State:
        return state_of(kinematics(mech, [x], 1.0, 0.0, branches=br, on_failure="nan"))

    return dead_centres_of_rates(mech.plan, rates, phi1, resolve if refine else None)
