"""Inverse dynamics (kinetostatics) of a planar mechanism over all positions.

Given the motion (:func:`~linkwork.planar.kinematics.kinematics`), masses, centroidal inertias,
gravity and external loads, the Newton-Euler equations of every moving body,

.. math:: m_i \\mathbf a_{Ci} = \\sum \\mathbf F, \\qquad I_{Ci} \\varepsilon_i = \\sum M_{C},

are solved for the joint reactions and the driving torque (force) at every position at once
(d'Alembert: the inertia forces ``-m a_C`` and couples ``-I_C eps`` join the applied loads; the
equations are the transposed constraint Jacobian times the Lagrange multipliers).

Sign conventions
----------------
* Joint reaction of joint ``J(name, a, b)``: the force **exerted by body a on body b**, components
  in the fixed frame's axes [N], applied at the joint centre (revolute), at the slider point of
  ``b`` (prismatic) or at the pin (pin-in-slot); a prismatic joint also transmits a couple ``mz``
  [N m] exerted by a on b (counter-clockwise positive). The force on ``a`` is the opposite.
* Driving torque ``Q`` [N m] (Crank): the torque the driver exerts on its joint's body ``b``
  through body ``a`` (for a crank driven from the frame: the motor torque on the crank),
  counter-clockwise positive, so the driving power is ``Q * omega1``. Linear driver: ``Q`` [N]
  is the force on ``b`` along the guide direction through the slider point of ``b`` (not
  included in the joint's ``fx, fy, mz``), power ``Q * v1``.
* Shaking force and moment: the resultant force and moment that the moving bodies exert on the
  frame through all frame joints, the motor's reaction included (the reaction ``-Q`` on the
  frame when the driver's joint is a frame joint), moment about the point ``about``.
  With no loads and no gravity ``F_sh = -sum m_i a_Ci``.  A load marked ``from_frame`` (e.g. a
  press's technological force, which the bed takes back) adds its reaction on the frame, so it
  cancels in ``F_sh`` and ``M_sh``: ``F_sh = sum F_ext + sum m_i (g - a_Ci)`` over the other
  loads.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite
from linkwork.cycles import mean_over_range
from linkwork.errors import ParameterError, angle_ranges, format_angle_ranges
from linkwork.planar import forces, friction
from linkwork.planar.compiled import check_backend, check_threads
from linkwork.planar.designs import pick
from linkwork.planar.forces import AppliedLoad, BodyTorque, Load, PointForce
from linkwork.planar.inertia import inertia_couple, inertia_force, wrenches_of
from linkwork.planar.joints import ResolvedJoint, row_entries
from linkwork.planar.kinematics import Kinematics, PointMotion, require_kinematics, state_of
from linkwork.planar.model import Mechanism
from linkwork.planar.rates import RatePar, batched_solve, closure_rows, cramer, group_pars
from linkwork.planar.state import Arr, State
from linkwork.planar.structure import Plan
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["CHUNK", "BodyTorque", "Dynamics", "PointForce", "inverse_dynamics",
           "kinetic_energy"]


@dataclass(frozen=True)
class Dynamics(Result):
    """Joint reactions, driving torque, shaking force and moment, kinetic energy.

    Attributes
    ----------
    kinematics : Kinematics
        The motion analysed.
    phi1 : ndarray (n,)
        Driver positions.
    joints : tuple of str
        Joint names (row order of the reaction arrays).
    fx, fy : ndarray (n_joints, n)
        Reaction force exerted by the joint's body ``a`` on its body ``b`` [N], frame axes.
    mz : ndarray (n_joints, n)
        Couple exerted by ``a`` on ``b`` [N m] (prismatic joints; zero for the others).
    px, py : ndarray (n_joints, n)
        Point of application of the reaction force [m].
    Q : ndarray (n,), or (n_drivers, n) for several drivers
        Driving torque [N m] (or force [N] for a Linear driver) on the driver joint's body b;
        one row per driver in the order of ``Mechanism.drivers``.
    shaking_fx, shaking_fy : ndarray (n,)
        Force exerted by the moving bodies on the frame [N].
    shaking_m : ndarray (n,)
        Moment of the forces (and couples) on the frame about ``about`` [N m].
    about : tuple of float
        Reference point of the shaking moment [m].
    T : ndarray (n,)
        Kinetic energy [J].
    gravity : tuple of float
        Gravity acceleration vector used [m/s^2].
    Q_frictionless : ndarray (n,)
        The driving torque (force) the same motion and loads need without friction (``Q``
        itself when no joint has friction).
    friction_fx, friction_fy, friction_mz : ndarray (n_joints, n)
        The friction part of each joint's reaction (force [N] at the reaction point, couple
        [N m]), exerted by a on b and included in ``fx, fy, mz`` (zero without friction).
    friction_power : ndarray (n_joints, n)
        Power dissipated by friction in each joint [W], >= 0 (:mod:`linkwork.planar.friction`).
    locked : ndarray of bool (n,)
        Self-locking positions: no finite driving torque (force) moves the mechanism there in
        the given sense; reactions, ``Q`` and ``friction_power`` are NaN (undefined) there.
    kappa : ndarray (n,)
        Self-locking indicator ``det(J^T - dG/dlambda) / det(J^T)`` (1 without friction; <= 0
        or NaN where locked).
    friction_iterations : int
        Newton steps of the friction solve (0 without friction).
    friction_static : bool
        The driver is at rest at every position: friction is not determined and set to zero.
    loads : tuple of AppliedLoad
        Every load as evaluated on the motion, in the order given
        (:class:`~linkwork.planar.forces.AppliedLoad`: name, kind, value, power, energy, the
        forces it exerts); :meth:`load` finds one by name.
    load_power : ndarray (n_loads, n)
        Power of each load on the moving bodies [W] (rows in ``loads`` order; a spring's is
        ``-dV/dt``, a damper's <= 0).
    V : ndarray (n,)
        Energy stored in the springs [J] (zero without springs).
    """

    kinematics: Kinematics
    phi1: Arr
    joints: tuple[str, ...]
    fx: Arr
    fy: Arr
    mz: Arr
    px: Arr
    py: Arr
    Q: Arr
    shaking_fx: Arr
    shaking_fy: Arr
    shaking_m: Arr
    about: tuple[float, float]
    T: Arr
    gravity: tuple[float, float]
    Q_frictionless: Arr
    friction_fx: Arr
    friction_fy: Arr
    friction_mz: Arr
    friction_power: Arr
    locked: Arr
    kappa: Arr
    friction_iterations: int
    friction_static: bool
    loads: tuple[AppliedLoad, ...]
    load_power: Arr
    V: Arr
    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "fx": "N", "fy": "N", "mz": "N*m", "px": "m", "py": "m", "Q": "N*m",
        "shaking_fx": "N", "shaking_fy": "N", "shaking_m": "N*m", "T": "J",
        "Q_frictionless": "N*m", "friction_fx": "N", "friction_fy": "N", "friction_mz": "N*m",
        "friction_power": "W", "locked": "1", "kappa": "", "load_power": "W", "V": "J"}

    def __post_init__(self) -> None:
        du = self.kinematics.mechanism.driver_units  # a linear driver: slide, force
        units = {k: du[k] for k in ("phi1", "Q")}
        units["Q_frictionless"] = du["Q"]
        if any(self.units[k] != v for k, v in units.items()):
            self._relabel_units(**units)

    def reaction(self, joint: str) -> tuple[Arr, Arr]:
        """(fx, fy) of joint ``joint``: force by its body a on its body b [N]."""
        try:
            i = self.joints.index(joint)
        except ValueError:
            raise ParameterError("joint", joint, f"no such joint; known: {list(self.joints)}"
                                 ) from None
        return self.fx[i], self.fy[i]

    def load(self, name: str) -> AppliedLoad:
        """The load called ``name`` as evaluated (value, power, energy, forces)."""
        for ld in self.loads:
            if ld.name == name:
                return ld
        raise ParameterError("load", name, f"no such load; known: {[x.name for x in self.loads]}")

    def reaction_magnitude(self, joint: str) -> Arr:
        """|R| of joint ``joint`` [N]."""
        fx, fy = self.reaction(joint)
        return np.hypot(fx, fy)

    @property
    def power(self) -> Arr:
        """Driving power ``Q * omega1`` [W] (per driver, shape (n_drivers, n), with several)."""
        return self.Q * self.kinematics.omega1

    @property
    def total_power(self) -> Arr:
        """The power of all drivers together [W], shape (n,)."""
        p = self.power
        return p if p.ndim == 1 else np.sum(p, axis=0)

    @property
    def Q_mean(self) -> Any:
        """Mean driving torque (force) over the analysed range: the work of ``Q`` over the
        range of the driver divided by it [N m] ([N]); :func:`linkwork.cycles.mean_over_range`.
        With several drivers an array, one per driver (NaN for a driver that does not move)."""
        phi, Q = self.kinematics.phi1, self.Q
        if Q.ndim == 1:
            return mean_over_range(phi, Q)
        out = np.full(Q.shape[0], np.nan)
        for k in range(Q.shape[0]):
            if phi[k, -1] != phi[k, 0]:
                out[k] = mean_over_range(phi[k], Q[k])
        return out

    @property
    def has_friction(self) -> bool:
        """Some joint of the mechanism has friction."""
        return any(j.has_friction for j in self.kinematics.mechanism.joints)

    @property
    def efficiency(self) -> Arr:
        """Instantaneous efficiency ``1 - sum(friction_power) / (Q omega1)`` [-]: the useful
        power (driving power less the friction losses) over the driving power (of all drivers
        together), where the drivers deliver power (``Q omega1 > 0``); NaN (undefined, written
        empty/null) where they deliver none or take power back, and at self-locking
        positions."""
        p = self.total_power
        loss = np.sum(self.friction_power, axis=0)
        with np.errstate(all="ignore"):
            return np.where(p > 0, 1.0 - loss / np.where(p > 0, p, 1.0), np.nan)

    def _clock(self) -> tuple[Arr, Arr, float]:
        """The driver coordinate and speed that give time along the positions (the first
        driver that moves with a speed of one sign; several drivers), and the order: +1 if the
        positions are listed in the order the driver passes them in time (``omega1 *
        (phi1[-1] - phi1[0]) > 0``), -1 if in the reverse order, 0 if undefined (fewer than 2
        positions, or the driver stops or reverses)."""
        phi = np.atleast_2d(self.phi1)
        w1 = np.broadcast_to(np.atleast_2d(np.asarray(self.kinematics.omega1, dtype=float)),
                             phi.shape)
        for k in range(phi.shape[0]):
            span = float(phi[k, -1] - phi[k, 0]) if phi.shape[1] >= 2 else 0.0
            if span != 0.0 and (np.all(w1[k] > 0) or np.all(w1[k] < 0)):
                return phi[k], w1[k], float(np.sign(w1[k, 0] * span))
        return phi[0], w1[0], 0.0

    @property
    def friction_losses(self) -> Arr:
        """Work dissipated in each joint over the analysed range [J] (n_joints,): the integral
        of ``friction_power`` over time, ``trapezoid(friction_power / omega1, phi1)`` (taken
        in the order the driver passes the positions; with several drivers the time of the
        first that moves); NaN (undefined) if the driver stops or reverses (``omega1`` zero
        or of both signs) or a position is locked or unassembled."""
        phi, w1, order = self._clock()
        nj = len(self.joints)
        if order == 0:
            return np.full(nj, np.nan)
        with np.errstate(all="ignore"):
            return order * np.asarray(np.trapezoid(self.friction_power / w1, phi, axis=-1))

    def _time_order(self) -> float:
        """+1 if the positions are listed in the order the driver passes them in time, -1 if
        in the reverse order, 0 if undefined (see :meth:`_clock`)."""
        return self._clock()[2]

    @property
    def driving_work(self) -> float:
        """Work of the driver over the analysed range, in the order the driver passes the
        positions [J]: ``+-trapezoid(Q, phi1)``, summed over the drivers (NaN if some
        position is locked or unassembled, or the driver stops or reverses)."""
        order = self._time_order()
        if order == 0:
            return float("nan")
        return order * float(np.sum(np.trapezoid(self.Q, self.phi1, axis=-1)))

    @property
    def efficiency_cycle(self) -> float | None:
        """Cycle efficiency ``1 - sum(friction_losses) / driving_work`` [-]: the useful work
        (work of the driver less the friction losses) over the work of the driver, over the
        analysed range. None (undefined) where the driver does no positive work over the range
        (a mechanism that the loads drive, or a conservative one without losses) or the
        losses are undefined (:attr:`friction_losses`)."""
        wd = self.driving_work
        loss = float(np.sum(self.friction_losses))
        if not (np.isfinite(wd) and np.isfinite(loss)) or wd <= 0:
            return None
        return 1.0 - loss / wd

    def self_locking_ranges(self) -> list[tuple[float, float]]:
        """The runs of self-locking positions, as (first, last) driver positions of each run
        [rad, or m] (sampled: the true limits lie within one step outside)."""
        out = []
        lk = np.asarray(self.locked, dtype=bool)
        i = 0
        while i < lk.size:
            if lk[i]:
                j = i
                while j + 1 < lk.size and lk[j + 1]:
                    j += 1
                out.append((float(self.phi1[i]), float(self.phi1[j])))
                i = j + 1
            else:
                i += 1
        return out

    def require_no_self_locking(self, needs: str) -> None:
        """A ParameterError naming the joints' friction coefficients and the self-locking
        ranges if the mechanism self-locks at some position: for a computation that ``needs``
        the driving load everywhere (said in the message)."""
        if not np.any(self.locked):
            return
        mech = self.kinematics.mechanism
        coefs = ", ".join(f"{getattr(j, 'friction', 0.0):g} ({j.name})" for j in mech.joints
                          if j.has_friction)
        name, unit = mech.drivers[0].coordinate    # several drivers: over the first's
        p = np.atleast_2d(np.asarray(self.phi1, dtype=float))[0]
        order = np.argsort(p, kind="stable")  # positions in any order (several grids)
        ranges = angle_ranges(p[order], np.asarray(self.locked)[order])
        raise ParameterError(
            "friction", coefs, f"makes the mechanism self-lock at {name} in "
            f"{format_angle_ranges(ranges, unit)} (no finite driving load moves it there); "
            f"{needs} (linkwork analyze shows the self-locking ranges)")

    def _scene(self) -> Any:
        """The mechanism drawn over the positions of its kinematics."""
        return self.kinematics._scene()

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Driving torque (or force) with its mean and the joint reaction magnitudes: a
        :class:`linkwork.plot.Figure` with 2 axes (:mod:`linkwork.plot.planar` also draws the
        shaking loads and the skeleton)."""
        from linkwork.plot.planar import dynamics_figure

        return dynamics_figure(self, axes=axes, **kw)


def _state_from(kin: Kinematics) -> State:
    return state_of(kin)


def kinetic_energy(kin: Kinematics) -> Arr:
    """Kinetic energy of all moving bodies [J] at every position."""
    return _kinetic_energy(require_kinematics(kin), kin.centres_of_mass())


def _kinetic_energy(kin: Kinematics, com: PointMotion) -> Arr:
    """:func:`kinetic_energy` from the motion of the centres of mass ``com`` (rows in the
    order of the moving bodies, the same numbers as ``kin.point(body, "com")``)."""
    m = kin.mechanism
    T = np.zeros(kin.n)
    for k, b in enumerate(m.bodies):
        T += (0.5 * b.mass * (com.vx[k]**2 + com.vy[k]**2)
              + 0.5 * b.inertia * kin.omega[m.index[b.name]]**2)
    return T



#: Positions per chunk of :func:`inverse_dynamics` of one design, and (design, position)
#: elements per block of a batch of designs (:func:`_blocks`): its temporaries are those of
#: one chunk or block, whatever the cycle and the number of designs (four-bar, 10^6
#: positions: the peak rose by 824 bytes per position unchunked, by the result's 345 in
#: chunks; 7.1 s -> 3.8 s on the loaded machine).
CHUNK = 8192

#: Per-position result fields of :class:`Dynamics` (positions last), filled chunk by chunk.
_PER_POSITION = ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m",
                 "T", "Q_frictionless", "friction_fx", "friction_fy", "friction_mz",
                 "friction_power", "locked", "kappa")
#: the friction arrays of a chunk without friction: all this value
_NO_FRICTION = {"friction_fx": 0.0, "friction_fy": 0.0, "friction_mz": 0.0,
                "friction_power": 0.0, "locked": False, "kappa": 1.0}


def inverse_dynamics(kin: Kinematics, *, gravity: ArrayLike | None = None,
                     loads: Sequence[Load] = (),
                     about: ArrayLike = (0.0, 0.0), backend: str = "numpy",
                     threads: int = 1) -> Dynamics:
    """Joint reactions, driving torque, shaking force/moment and kinetic energy.

    Parameters
    ----------
    kin : Kinematics
        Result of :func:`~linkwork.planar.kinematics.kinematics`.
    gravity : (gx, gy), optional
        Gravity acceleration [m/s^2] in frame axes, e.g. ``(0, -9.81)``; default none.
    loads : sequence of loads
        External loads and force elements (:mod:`linkwork.planar.forces`): PointForce,
        BodyTorque, SlideForce (numbers, arrays over the positions or LoadDiagram), Spring,
        Damper, Drag.
    about : (x, y)
        Point about which the shaking moment is taken [m] (default the frame origin).
    backend : {"numpy", "numba"}
        ``"numpy"`` (the default and the reference) or ``"numba"``: the plans that
        :mod:`linkwork.planar.compiled.reactions` covers (revolute, prismatic and pin-in-slot
        joints without friction; drivers, dyads and slot groups) through one compiled pass
        over the positions (needs ``pip install 'linkwork[numba]'``); any other plan through
        the NumPy path, the same result.
    threads : int
        With ``backend="numba"``: the compiled kernel's threads (default 1, the calling
        thread), the (design, position) elements shared among them; the same result bit for
        bit on any number of threads. At most numba's thread count (``NUMBA_NUM_THREADS``).

    Returns
    -------
    Dynamics
        See the module docstring for the sign conventions. For a batch of designs
        (:mod:`~linkwork.planar.designs`) every per-position array has the designs before the
        positions: ``fx`` (n_joints, m, n), ``Q`` (m, n), ``shaking_fx`` (m, n), ...; the
        loads are the same for every design.

    Notes
    -----
    Positions are independent of one another, so the work runs in chunks of :data:`CHUNK`
    positions into the result's arrays: memory beyond the result stays that of one chunk (a
    long cycle that must not be held at all goes through
    :func:`linkwork.studies.planar.analyze_chunked`). The friction law's sign width is taken
    from the driver speed over all positions, as without chunks.

    A batch of designs without loads, friction and gear pairs' separating forces is solved in
    blocks of :data:`CHUNK` (design, position) elements flattened together (several designs
    of a short cycle, or chunks of one design's positions), on the plan picked there; with
    them, design by design (each in chunks of positions). Either way the temporaries are those
    of at most :data:`CHUNK` elements.
    """
    require_kinematics(kin)
    g = (0.0, 0.0) if gravity is None else tuple(float(v) for v in require_finite(
        "gravity", gravity).ravel())
    if len(g) != 2:
        raise ParameterError("gravity", gravity, "must be a vector (gx, gy) [m/s^2]")
    ab = tuple(float(v) for v in require_finite("about", about).ravel())
    if len(ab) != 2:
        raise ParameterError("about", about, "must be a point (x, y) [m]")
    backend = check_backend(backend)
    threads = check_threads(threads, backend)
    if kin.n_designs is not None:
        return _batch_dynamics(kin, (g[0], g[1]), (ab[0], ab[1]), loads, backend, threads)
    # the loads are checked and evaluated over the whole cycle (a load diagram's rest band,
    # a spring's length), once; the chunks take their slices
    applied = forces.apply(kin, loads)
    enc = _compiled_plan(kin.mechanism) if backend == "numba" else None
    if enc is not None:
        return _compiled_dynamics(kin, enc, (g[0], g[1]), (ab[0], ab[1]), applied, threads)
    n = kin.n
    plan = kin.mechanism.plan
    width = friction.sign_widths(plan, kin.omega1) if friction.has_friction(plan) else None
    if n <= CHUNK:
        return _inverse_dynamics(kin, (g[0], g[1]), (ab[0], ab[1]), applied, width)
    parts: dict[str, Arr] = {}
    iterations = 0
    first: Dynamics | None = None
    # without friction its arrays are constants (no joint dissipates): made whole, not copied
    copied = _PER_POSITION if width is not None else tuple(
        k for k in _PER_POSITION if k not in _NO_FRICTION)
    for lo in range(0, n, CHUNK):
        sl = slice(lo, min(lo + CHUNK, n))
        d = _inverse_dynamics(_kinematics_slice(kin, sl), (g[0], g[1]), (ab[0], ab[1]),
                              [_applied_slice(ap, sl) for ap in applied], width)
        if first is None:
            first = d
            parts = {k: (np.empty if k in copied else np.zeros if not _NO_FRICTION[k]
                         else np.ones)((*getattr(d, k).shape[:-1], n), dtype=getattr(d, k).dtype)
                     for k in _PER_POSITION}
        for k in copied:
            parts[k][..., sl] = getattr(d, k)
        iterations = max(iterations, d.friction_iterations)
    assert first is not None
    return Dynamics(kin, kin.phi1, first.joints, about=first.about, gravity=first.gravity,
                    friction_iterations=iterations, friction_static=first.friction_static,
                    loads=applied, load_power=_load_power(applied, n),
                    V=sum((ap.energy for ap in applied), np.zeros(n)), **parts)


def _load_power(applied: Sequence[AppliedLoad], n: int) -> Arr:
    return np.array([ap.power for ap in applied], dtype=float).reshape(len(applied), n)


def _part(v: Any, sl: slice) -> Any:
    """The positions ``sl`` of an array over the positions (a number as it is)."""
    return v[sl] if np.ndim(v) else v


def _applied_slice(ap: AppliedLoad, sl: slice) -> AppliedLoad:
    """The positions ``sl`` of a load evaluated over the cycle: its value, power, energy,
    length and wrenches."""
    return replace(ap, value=_part(ap.value, sl), power=_part(ap.power, sl),
                   energy=_part(ap.energy, sl),
                   length=None if ap.length is None else _part(ap.length, sl),
                   wrenches=tuple(replace(w, fx=_part(w.fx, sl), fy=_part(w.fy, sl),
                                          px=_part(w.px, sl), py=_part(w.py, sl),
                                          mz=_part(w.mz, sl)) for w in ap.wrenches))


def _kinematics_slice(kin: Kinematics, sl: slice) -> Kinematics:
    """The positions ``sl`` of a solved motion (views, no copies)."""
    return Kinematics(kin.mechanism, kin.phi1[..., sl], kin.omega1[..., sl], kin.eps1[..., sl],
                      kin.bodies,
                      kin.x[:, sl], kin.y[:, sl], kin.theta[:, sl], kin.vx[:, sl],
                      kin.vy[:, sl], kin.omega[:, sl], kin.ax[:, sl], kin.ay[:, sl],
                      kin.eps[:, sl], kin.valid[sl], kin.branches)


def _inverse_dynamics(kin: Kinematics, g: tuple[float, float], ab: tuple[float, float],
                      applied: Sequence[AppliedLoad], width: tuple[float, float] | None
                      ) -> Dynamics:
    """:func:`inverse_dynamics` of one chunk of positions: ``applied`` the loads evaluated
    there (:func:`linkwork.planar.forces.apply`), ``width`` the friction law's sign width over
    the whole cycle (None without friction)."""
    mech: Mechanism = kin.mechanism
    n = kin.n
    st = _state_from(kin)
    nb = len(mech.body_names)
    # generalised applied-minus-inertia forces on each moving body (about its origin)
    f = np.zeros((n, 3 * (nb - 1)))
    com = kin.centres_of_mass()  # (bodies, positions): the wrenches and the kinetic energy
    iw = wrenches_of(kin, g, com)  # weight + inertia force at C, inertia couple
    for k, b in enumerate(mech.bodies):
        i = mech.index[b.name]
        rx, ry = iw.cx[k] - kin.x[i], iw.cy[k] - kin.y[i]
        f[:, 3 * i - 3] += iw.fx[k]
        f[:, 3 * i - 2] += iw.fy[k]
        f[:, 3 * i - 1] += rx * iw.fy[k] - ry * iw.fx[k] + iw.mz[k]
    on_frame: list[forces.Wrench] = []  # the loads' reactions on the frame
    for ap in applied:
        for w in ap.wrenches:
            i = mech.index[w.body]
            if i == 0:
                on_frame.append(w)
                continue
            f[:, 3 * i - 3] += w.fx
            f[:, 3 * i - 2] += w.fy
            f[:, 3 * i - 1] += (w.px - kin.x[i]) * w.fy - (w.py - kin.y[i]) * w.fx + w.mz
    nj = len(mech.joints)
    pxr = np.zeros((nj, n))
    pyr = np.zeros((nj, n))
    plan = mech.plan
    for ji, rj in enumerate(plan.joints):
        pxr[ji], pyr[ji] = rj.joint.reaction_point(st, rj)
    if friction.has_separation(plan) and not friction.has_friction(plan):
        fxr, fyr, mzr, Q = _separated_reactions(plan, st, f, kin.valid)
    elif plan.global_reactions:
        fxr, fyr, mzr, Q = _global_reactions(plan, st, f, kin.valid)
    else:
        with np.errstate(all="ignore"):
            fxr, fyr, mzr, Q = _group_reactions(plan, st, f)
    fric = _with_friction(plan, st, f, kin, Q, width) if width is not None else None
    sfx, sfy, sm = _shaking(plan, st, mech.frame.name, (fxr, fyr, mzr, Q), pxr, pyr, ab,
                            on_frame)
    if fric is not None:
        fxr, fyr, mzr, Q = fric.reactions
        # friction is internal to the machine: the shaking loads equal the frictionless ones,
        # which stay defined where it self-locks (reactions and Q undefined there)
        with_f = _shaking(plan, st, mech.frame.name, fric.reactions, pxr, pyr, ab, on_frame)
        sfx, sfy, sm = (np.where(fric.locked, s0, s1)
                        for s0, s1 in zip((sfx, sfy, sm), with_f, strict=True))
    T = _kinetic_energy(kin, com)
    one = mech.n_drivers == 1  # one driver: Q of shape (n,), as always
    if fric is None:  # no joint dissipates
        zeros = np.zeros((nj, n))
        fric = _Friction((fxr, fyr, mzr, Q), Q, friction.FrictionSolution(
            np.zeros((n, 0)), zeros, zeros, zeros, np.ones(n, dtype=bool), np.ones(n), 0),
            zeros, np.zeros(n, dtype=bool), False)
    return Dynamics(kin, kin.phi1, tuple(j.name for j in mech.joints), fxr, fyr, mzr, pxr, pyr,
                    Q[0] if one else Q, sfx, sfy, sm, (ab[0], ab[1]), T, (g[0], g[1]),
                    Q_frictionless=fric.Q0[0] if one else fric.Q0, friction_fx=fric.sol.ffx,
                    friction_fy=fric.sol.ffy, friction_mz=fric.sol.fmz,
                    friction_power=fric.power, locked=fric.locked, kappa=fric.sol.kappa,
                    friction_iterations=fric.sol.iterations,
                    friction_static=fric.static, loads=tuple(applied),
                    load_power=_load_power(applied, n),
                    V=sum((ap.energy for ap in applied), np.zeros(n)))


def _shaking(plan: Plan, st: State, fr: str, reactions: tuple[Arr, Arr, Arr, Arr],
             pxr: Arr, pyr: Arr, ab: tuple[float, ...], on_frame: list[forces.Wrench]
             ) -> tuple[Arr, Arr, Arr]:
    """Shaking force (x, y) and moment about ``ab`` on the frame ``fr``: the frame joints'
    reactions (by the moving bodies on the frame), the motors' reactions (``Q`` of shape
    (n_drivers, n)) and the loads' reactions on the frame."""
    fxr, fyr, mzr, Q = reactions
    kinds = plan.driver_kinds
    sfx = np.zeros(st.n)
    sfy = np.zeros(st.n)
    sm = np.zeros(st.n)
    for ji, rj in enumerate(plan.joints):
        j = rj.joint
        if fr not in (j.a, j.b):
            continue
        sgn = -1.0 if j.a == fr else 1.0
        fx, fy, mz = sgn * fxr[ji], sgn * fyr[ji], sgn * mzr[ji]
        linear = rj.drive and kinds[rj.drive_index] == "linear"
        if linear:  # the driving force along the guide
            ux, uy = st.rot(rj.ia, rj.u_loc)
            fx = fx + sgn * Q[rj.drive_index] * ux
            fy = fy + sgn * Q[rj.drive_index] * uy
        sfx += fx
        sfy += fy
        sm += (pxr[ji] - ab[0]) * fy - (pyr[ji] - ab[1]) * fx + mz
        if rj.drive and not linear:  # the motor's reaction torque
            sm += sgn * Q[rj.drive_index]
    for w in on_frame:
        sfx += w.fx
        sfy += w.fy
        sm += (w.px - ab[0]) * w.fy - (w.py - ab[1]) * w.fx + w.mz
    return sfx, sfy, sm


def _batch_dynamics(kin: Kinematics, g: tuple[float, float], ab: tuple[float, float],
                    loads: Sequence[Load], backend: str = "numpy", threads: int = 1
                    ) -> Dynamics:
    """:func:`inverse_dynamics` of a batch of designs (arrays ``(..., m, n)``): without loads,
    friction and gear pairs' separating forces, blocks of designs flattened with their
    positions and solved on the plan picked there (as :func:`kinematics` does), or all of
    them in one compiled pass (``backend="numba"``, a plan it covers); with them, design by
    design (the loads the same for every design)."""
    mech = kin.mechanism
    plan = mech.plan
    m = kin.n_designs
    assert m is not None
    if loads or friction.has_friction(plan) or friction.has_separation(plan):
        return _stacked(kin, [inverse_dynamics(kin.design(i), gravity=g, loads=loads, about=ab,
                                               backend=backend, threads=threads)
                              for i in range(m)])
    enc = _compiled_plan(mech) if backend == "numba" else None
    if enc is not None:
        return _compiled_dynamics(kin, enc, g, ab, (), threads)
    n = kin.n
    nb, nj, nd = plan.nb, len(plan.joints), len(plan.drivers)
    react = np.empty((5, nj, m, n))  # fx, fy, mz, px, py
    Q = np.empty((nd, m, n))
    shake = np.empty((4, m, n))  # shaking fx, fy, m; kinetic energy
    keys = ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps")
    for ds, ps, index in _blocks(m, n):
        sub = plan.pick(index)
        shape = (ds.stop - ds.start, ps.stop - ps.start)
        st = State(nb, shape[0] * shape[1])
        rows = {key: getattr(kin, key)[:, ds, ps].reshape(nb, -1) for key in keys}
        for i in range(1, nb):
            st.X[i], st.Y[i], st.VX[i], st.VY[i], st.W[i], st.AX[i], st.AY[i], st.E[i] = (
                rows[key][i] for key in ("x", "y", "vx", "vy", "omega", "ax", "ay", "eps"))
            st.set_angle(i, rows["theta"][i])
        bodies = [(pick(b.mass, index), pick(b.com, index), pick(b.inertia, index))
                  for b in mech.bodies]
        with np.errstate(all="ignore"):
            f, T = _body_forces(st, bodies, g)
            points = [rj.joint.reaction_point(st, rj) for rj in sub.joints]
            if sub.global_reactions:
                fxr, fyr, mzr, q = _global_reactions(sub, st, f, kin.valid[ds, ps].reshape(-1))
            else:
                fxr, fyr, mzr, q = _group_reactions(sub, st, f)
            pxr = np.array([p[0] + np.zeros(st.n) for p in points]).reshape(nj, -1)
            pyr = np.array([p[1] + np.zeros(st.n) for p in points]).reshape(nj, -1)
            sh = _shaking(sub, st, mech.frame.name, (fxr, fyr, mzr, q), pxr, pyr, ab, [])
        for k, arr in enumerate((fxr, fyr, mzr, pxr, pyr)):
            react[k, :, ds, ps] = arr.reshape(nj, *shape)
        Q[:, ds, ps] = q.reshape(nd, *shape)
        for k, arr in enumerate((*sh, T)):
            shake[k, ds, ps] = arr.reshape(shape)
    one = nd == 1
    zeros = np.zeros((nj, m, n))
    return Dynamics(kin, kin.phi1, tuple(j.name for j in mech.joints), react[0], react[1],
                    react[2], react[3], react[4], Q[0] if one else Q, shake[0], shake[1],
                    shake[2], ab, shake[3], g,
                    Q_frictionless=Q[0] if one else Q, friction_fx=zeros, friction_fy=zeros,
                    friction_mz=zeros, friction_power=zeros,
                    locked=np.zeros((m, n), dtype=bool),
                    kappa=np.ones((m, n)), friction_iterations=0,
                    friction_static=False, loads=(), load_power=np.zeros((0, m, n)),
                    V=np.zeros((m, n)))


def _compiled_plan(mech: Mechanism) -> Any:
    """The plan of ``mech`` encoded for the compiled kernel, None if it does not cover it
    (:mod:`linkwork.planar.compiled.reactions`, which imports numba: only for that backend)."""
    from linkwork.planar.compiled.reactions import encode

    return encode(mech)


def _compiled_dynamics(kin: Kinematics, enc: Any, g: tuple[float, float],
                       ab: tuple[float, float], applied: Sequence[AppliedLoad],
                       threads: int = 1) -> Dynamics:
    """:func:`inverse_dynamics` through the compiled kernel (``enc``: the encoded plan), for
    one design (``applied``: its loads, evaluated) or a batch of designs (no loads)."""
    from linkwork.planar.compiled.reactions import solve

    mech = kin.mechanism
    r = solve(enc, kin, g, ab, applied, CHUNK, threads)
    shape = kin.x.shape[1:]
    nj = len(mech.joints)
    Q = r["Q"][0] if mech.n_drivers == 1 else r["Q"]
    return Dynamics(kin, kin.phi1, tuple(j.name for j in mech.joints), r["fx"], r["fy"],
                    r["mz"], r["px"], r["py"], Q, r["shaking_fx"], r["shaking_fy"],
                    r["shaking_m"], ab, r["T"], g, Q_frictionless=Q,
                    friction_fx=np.zeros((nj, *shape)), friction_fy=np.zeros((nj, *shape)),
                    friction_mz=np.zeros((nj, *shape)),
                    friction_power=np.zeros((nj, *shape)),
                    locked=np.zeros(shape, dtype=bool), kappa=np.ones(shape),
                    friction_iterations=0, friction_static=False, loads=tuple(applied),
                    load_power=(_load_power(applied, kin.n) if applied
                                else np.zeros((0, *shape))),
                    V=sum((ap.energy for ap in applied), np.zeros(shape)))


def _blocks(m: int, n: int) -> list[tuple[slice, slice, Any]]:
    """The blocks of a batch's (design, position) elements solved at once: (designs,
    positions, index) with index the design of each flattened element, or the one design
    (an int) of a block of positions."""
    if n >= CHUNK:
        return [(slice(d, d + 1), slice(lo, min(lo + CHUNK, n)), d)
                for d in range(m) for lo in range(0, n, CHUNK)]
    k = max(1, CHUNK // max(n, 1))
    return [(slice(d0, min(d0 + k, m)), slice(0, n),
             np.repeat(np.arange(d0, min(d0 + k, m)), n)) for d0 in range(0, m if n else 0, k)]


def _body_forces(st: State, bodies: Sequence[tuple[Any, Any, Any]], g: tuple[float, float]
                 ) -> tuple[Arr, Arr]:
    """The generalised applied-minus-inertia forces on every moving body about its origin
    (columns x, y, theta of each; :mod:`~linkwork.planar.inertia`) and the kinetic energy,
    from the solver state and each body's (mass, centre of mass, inertia)."""
    n = st.n
    f = np.zeros((n, 3 * len(bodies)))
    T = np.zeros(n)
    for k, (mass, com, inertia) in enumerate(bodies):
        i = k + 1
        rx, ry = st.rot(i, com)
        vx, vy = st.point_vel(i, com)
        ax, ay = st.point_acc(i, com)
        fx, fy = inertia_force(mass, ax, ay, g[0], g[1])
        f[:, 3 * k] += fx
        f[:, 3 * k + 1] += fy
        f[:, 3 * k + 2] += rx * fy - ry * fx + inertia_couple(inertia, st.E[i])
        T += 0.5 * mass * (vx**2 + vy**2) + 0.5 * inertia * st.W[i]**2
    return f, T


def _stacked(kin: Kinematics, parts: Sequence[Dynamics]) -> Dynamics:
    """The designs' results ``parts`` as one result of the batch ``kin`` (arrays (..., m, n))."""

    def stack(values: Sequence[Any]) -> Any:
        if isinstance(values[0], np.ndarray):
            return np.stack(values, axis=-2)
        return values[0]

    def load(k: int) -> AppliedLoad:
        aps = [p.loads[k] for p in parts]
        ws = tuple(replace(w, **{a: stack([getattr(x.wrenches[j], a) for x in aps])
                                 for a in ("fx", "fy", "px", "py", "mz")})
                   for j, w in enumerate(aps[0].wrenches))
        return replace(aps[0], value=stack([a.value for a in aps]),
                       power=stack([a.power for a in aps]), energy=stack([a.energy for a in aps]),
                       length=None if aps[0].length is None else stack([a.length for a in aps]),
                       wrenches=ws)

    arrays = {name: stack([getattr(p, name) for p in parts])
              for name in (*_PER_POSITION, "load_power", "V")}
    first = parts[0]
    return Dynamics(kin, kin.phi1, first.joints, about=first.about, gravity=first.gravity,
                    friction_iterations=max(p.friction_iterations for p in parts),
                    friction_static=all(p.friction_static for p in parts),
                    loads=tuple(load(k) for k in range(len(first.loads))), **arrays)


@dataclass(frozen=True)
class _Friction:
    """What the friction solve gives :func:`inverse_dynamics`."""

    reactions: tuple[Arr, Arr, Arr, Arr]
    Q0: Arr
    sol: friction.FrictionSolution
    power: Arr
    locked: Arr
    static: bool


def _with_friction(plan: Plan, st: State, f: Arr, kin: Kinematics, Q0: Arr,
                   width: tuple[float, float]) -> _Friction:
    """The reactions and driving load with Coulomb friction (:mod:`linkwork.planar.friction`),
    the friction power of every joint and the self-locking positions; ``width``: the sign
    width of the friction law (:func:`~linkwork.planar.friction.sign_widths`)."""
    J, meta = _constraint_jacobian(plan, st)
    JT = np.swapaxes(J, 1, 2)
    good = np.asarray(kin.valid, dtype=bool)
    lam0 = batched_solve(JT, f, good)
    static = width == (0.0, 0.0)
    sol = friction.solve(plan, st, JT, f, lam0, good, meta, width)
    fxr, fyr, mzr, Q = _split(plan, st, sol.lam, meta)
    sx, sy = friction.separating_forces(plan, st, sol.lam, meta)
    fxr, fyr, mzr = fxr + sol.ffx + sx, fyr + sol.ffy + sy, mzr + sol.fmz
    locked = good & ~(sol.converged & (sol.kappa > 0))
    for arr in (fxr, fyr, mzr):
        arr[:, locked] = np.nan
    Q = np.where(locked[None, :], np.nan, Q)
    power = np.zeros((len(plan.joints), st.n))
    for rj in plan.joints:
        if rj.joint.has_friction:
            vx, vy, dw = rj.joint.relative_motion(st, rj)
            k = rj.index
            power[k] = -(sol.ffx[k] * vx + sol.ffy[k] * vy + sol.fmz[k] * dw)
    power[:, locked] = np.nan
    return _Friction((fxr, fyr, mzr, Q), Q0, sol, power, locked, static)


def _constraint_jacobian(plan: Plan, st: State) -> tuple[Arr, list[tuple[ResolvedJoint, str]]]:
    """The constraint Jacobian J (n, size, size), the driver's row included, and each row's
    (joint, row kind or ``"drive"``)."""
    n = st.n
    size = 3 * (plan.nb - 1)
    J = np.zeros((n, size, size))
    meta: list[tuple[ResolvedJoint, str]] = []  # (joint, row kind)
    r = 0
    for rj in plan.joints:
        rows = rj.joint.equilibrium_rows(st, rj)
        ia, ib = rj.ia, rj.ib
        for k, row in enumerate(rows):
            for body, coef in row_entries(ia, ib, row):
                if body > 0:
                    for comp in range(3):
                        J[:, r, 3 * body - 3 + comp] += coef[comp]
            meta.append((rj, "drive" if row.get("drive") else rj.joint.row_kinds[k]))
            r += 1
    return J, meta


def _global_reactions(plan: Plan, st: State, f: Arr, good: Arr
                      ) -> tuple[Arr, Arr, Arr, Arr]:
    """All multipliers at once: J^T lambda = f with the full constraint Jacobian."""
    J, meta = _constraint_jacobian(plan, st)
    lam = batched_solve(np.swapaxes(J, 1, 2), f, good)
    return _split(plan, st, lam, meta)


def _separated_reactions(plan: Plan, st: State, f: Arr, good: Arr
                         ) -> tuple[Arr, Arr, Arr, Arr]:
    """The reactions with the separating forces of gear pairs (no friction): the tooth force
    along the line of action."""
    J, meta = _constraint_jacobian(plan, st)
    JT = np.swapaxes(J, 1, 2)
    lam0 = batched_solve(JT, f, good)
    lam = friction.separated(plan, st, JT, f, lam0, good, meta)
    fxr, fyr, mzr, Q = _split(plan, st, lam, meta)
    sx, sy = friction.separating_forces(plan, st, lam, meta)
    return fxr + sx, fyr + sy, mzr, Q


def _split(plan: Plan, st: State, lam: Arr, meta: list[tuple[ResolvedJoint, str]]
           ) -> tuple[Arr, Arr, Arr, Arr]:
    """The reactions (fx, fy, mz by a on b) and the driving loads Q (n_drivers, n) the
    multipliers carry."""
    n = st.n
    nj = len(plan.joints)
    out = {"fx": np.zeros((nj, n)), "fy": np.zeros((nj, n)), "mz": np.zeros((nj, n))}
    Q = np.zeros((len(plan.drivers), n))
    for r, (rj, kind) in enumerate(meta):
        lr = lam[:, r]
        if kind == "drive":  # the driver's row: its torque (force) on body b
            Q[rj.drive_index] = -lr
            continue
        for key, v in rj.joint.reaction_components(st, rj, kind, lr).items():
            out[key][rj.index] += v
    return out["fx"], out["fy"], out["mz"], Q


def _group_reactions(plan: Plan, st: State, f: Arr) -> tuple[Arr, Arr, Arr, Arr]:
    """Reactions group by group, last group first (each Assur group is statically determinate).

    For a dyad the virtual motion of each body allowed by its external joint (rotation about
    the pivot, or sliding along the guide) gives one equation free of that joint's reaction:
    the transposed velocity-closure system (2 x 2, Cramer) yields the reaction of the joint
    between the bodies; each body's own balance then gives its external reaction, whose
    opposite is added to the known body it acts on. The driver (a crank's torque about its
    pivot, a linear driver's force along its guide) balances its body's motion along the joint.
    """
    n = st.n
    nb = plan.nb
    nj = len(plan.joints)
    fxr = np.zeros((nj, n))
    fyr = np.zeros((nj, n))
    mzr = np.zeros((nj, n))
    Q = np.zeros((len(plan.drivers), n))
    # generalised forces with moments about the world origin
    Fx = [np.zeros(n)] + [f[:, 3 * i - 3].copy() for i in range(1, nb)]
    Fy = [np.zeros(n)] + [f[:, 3 * i - 2].copy() for i in range(1, nb)]
    M0 = [np.zeros(n)] + [f[:, 3 * i - 1] + st.X[i] * f[:, 3 * i - 2] - st.Y[i] * f[:, 3 * i - 3]
                          for i in range(1, nb)]

    def apply(i: int, fx: Arr, fy: Arr, px: Arr, py: Arr, mz: Arr | float = 0.0) -> None:
        if i == 0:
            return  # the frame's own balance is never needed
        Fx[i] = Fx[i] + fx
        Fy[i] = Fy[i] + fy
        M0[i] = M0[i] + px * fy - py * fx + mz

    def record(rj: ResolvedJoint, on: int, fx: Arr, fy: Arr, mz: Arr | float, px: Arr,
               py: Arr) -> None:
        """Store the reaction acting on body ``on``; apply its opposite to the other body."""
        other = rj.ib if on == rj.ia else rj.ia
        sgn = 1.0 if on == rj.ib else -1.0
        k = rj.index
        fxr[k] += sgn * fx
        fyr[k] += sgn * fy
        mzr[k] += sgn * mz
        apply(on, fx, fy, px, py, mz)
        apply(other, -fx, -fy, px, py, -mz)

    def ext_reaction(par: RatePar, rj: ResolvedJoint) -> None:
        """Balance body par.b with the reaction of its external joint."""
        b = par.b
        record(rj, b, *rj.joint.external_reaction(st, rj, par, Fx[b], Fy[b], M0[b]))

    for g in reversed(plan.groups):
        if g.kind == "driver":
            rj = g.joints[0]
            b = g.bodies[0]
            sgn = 1.0 if b == rj.ib else -1.0
            par = RatePar(st, rj, b, 0)
            other = rj.ia if sgn > 0 else rj.ib
            k = rj.drive_index
            if plan.driver_kinds[k] != "linear":  # a torque about the pivot
                A = par.A
                torque = -(M0[b] - (A[0] * Fy[b] - A[1] * Fx[b]))
                Q[k] = sgn * torque
                M0[b] = M0[b] + torque
                if other:
                    M0[other] = M0[other] - torque
                record(rj, b, -Fx[b], -Fy[b], 0.0, A[0], A[1])
            else:  # a force along the guide at the slider point
                P = st.wpt(rj.ib, rj.pb)
                ux, uy = par.u
                drive = -(Fx[b] * ux + Fy[b] * uy)
                Q[k] = sgn * drive
                apply(b, drive * ux, drive * uy, P[0], P[1])
                apply(other, -drive * ux, -drive * uy, P[0], P[1])
                ext_reaction(par, rj)
            continue
        pars, rc, unk = group_pars(st, g, nb)
        rows = closure_rows(st, rc, pars, len(unk), "v")
        # transposed system: sum_r C[r][beta] lambda_r = power of beta's forces
        pw = []
        for par in unk:
            b = par.b
            if par.rev:
                pw.append(M0[b] - (par.A[0] * Fy[b] - par.A[1] * Fx[b]))
            else:
                pw.append(Fx[b] * par.u[0] + Fy[b] * par.u[1])
        trows = [([rows[r][0][beta] for r in range(len(rows))], pw[beta])
                 for beta in range(len(unk))]
        lam = cramer(st, trows, plan.length_scale ** len(unk))
        record(rc, rc.ib, *rc.joint.closure_reaction(st, rc, lam))
        rext = [g.joints[0]] if len(unk) == 1 else [g.joints[0], g.joints[2]]
        for par, rj in zip(unk, rext, strict=True):
            ext_reaction(par, rj)
    return fxr, fyr, mzr, Q
