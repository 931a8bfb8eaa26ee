r"""The numerical core of machine dynamics: the reduced equation over a cycle of the crank.

With :math:`u = \omega^2` the equation of motion of the machine unit
(:mod:`linkwork.machine.reduction`) is a first-order equation in the crank angle,
:math:`du/d\varphi = 2\varepsilon(\varphi, u)`, where the crank's acceleration
:math:`\varepsilon` solves the torque balance through the drive at every position:

.. math:: g\!\left(M_m(i\omega) - J_{in}\, i\, \varepsilon\right)
          = (J + J_{out})\,\varepsilon + \tfrac12 J' u - M,
   \qquad g(x) = \begin{cases} i\eta x & x \ge 0 \\ i x/\eta & x < 0 \end{cases}

(motor torque :math:`M_m` at the motor speed :math:`i\omega`; rotors on the motor shaft
:math:`J_{in}` (motor, gear input), on the crank shaft :math:`J_{out}` (flywheel); gear ratio
:math:`i`, efficiency :math:`\eta` with the power flowing either way; :math:`M` every other
reduced moment). Both sides are linear in :math:`\varepsilon`, so it is explicit; the branch of
:math:`g` is the sign of :math:`M_m d + J_{in} i\, c` (see :func:`eps_of`).

**Discretisation.** The cycle is cut into intervals; on each, the Hermite-Simpson (Lobatto IIIA,
fourth-order) collocation

.. math:: u_m = \tfrac12 (u_k + u_{k+1}) + \tfrac{h}{8}(F_k - F_{k+1}), \qquad
          u_{k+1} - u_k = \tfrac{h}{6}(F_k + 4 F_m + F_{k+1}), \qquad F = du/d\varphi,

needs the reduced coefficients at the interval's two ends and its middle, evaluated once by the
engine for all positions (vectorised). A load that jumps (a press force switched on over part
of the stroke) gets a node at the jump and one-sided values there (:data:`ONE_SIDED`), so that
no interval straddles it. The time follows from :math:`dt = d\varphi/\omega` by Simpson's rule.

**Periodic solve** (:func:`solve_periodic`): the steady state is the solution with
:math:`u(\varphi + P) = u(\varphi)`; the :math:`N` collocation equations with the periodic wrap
form a cyclic bidiagonal system, solved by Newton's method with a sparse LU (a ConstantTorque
drive adds the unknown torque and the condition on the mean speed). Not "integrate until it
settles": the cost is that of a few cycles whatever the settling time.

**March** (:func:`march`): the same collocation stepped interval by interval from a given state
(start-up from rest, schedules), one scalar Newton solve per interval.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.errors import ConvergenceError, ParameterError
from linkwork.machine.motors import ConstantSpeed, ConstantTorque, Motor
from linkwork.planar.state import Arr

__all__ = ["ONE_SIDED", "Coefficients", "Drive", "FixedTorque", "Grid", "Stall", "extremes",
           "hermite_extremes", "make_grid", "march", "periodic_solution", "solve_periodic"]

#: Distance [rad] inside an interval at which the coefficients are evaluated at a node where the
#: loads jump (so each interval sees the loads of its own side).
ONE_SIDED = 1e-9


@dataclass(frozen=True)
class Drive:
    """The drive reduced for the solver: motor, gear ratio ``i``, efficiency ``eta``, inertia
    on the motor shaft ``J_in`` (rotor, gear) and on the crank shaft ``J_out`` (flywheel)
    [kg m^2]."""

    motor: Motor
    ratio: float = 1.0
    eta: float = 1.0
    J_in: float = 0.0
    J_out: float = 0.0

    @property
    def rotors(self) -> float:
        """The rotors' inertia reduced to the crank, ``J_in i^2 + J_out`` [kg m^2]."""
        return self.J_in * self.ratio**2 + self.J_out


@dataclass(frozen=True)
class FixedTorque(Motor):
    """A motor of one torque ``value`` [N m] at every speed: a ConstantTorque drive marched
    with its torque set (the march needs a characteristic)."""

    value: float
    inertia: float = 0.0
    name: str = "constant torque"

    def torque(self, omega_m: Any) -> Any:
        return self.value + 0.0 * omega_m

    def slope(self, omega_m: Any) -> Any:
        return 0.0 * omega_m


@dataclass(frozen=True)
class Grid:
    """Nodes of a cycle of period ``period`` [rad] and the positions where the coefficients are
    evaluated.

    ``nodes`` (N + 1,) from ``nodes[0]`` to ``nodes[0] + period``; ``pts`` every evaluation
    position; interval k uses ``pts[iL[k]]``, ``pts[iM[k]]``, ``pts[iR[k]]`` (its start, middle
    and end; one-sided at a jump). ``coarse``: the same for every other node (the jumps kept),
    whose middles are the odd nodes (for the error estimate without new evaluations).
    """

    period: float
    nodes: Arr
    pts: Arr
    iL: np.ndarray
    iM: np.ndarray
    iR: np.ndarray
    coarse: tuple[Arr, np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def n(self) -> int:
        return int(self.iL.size)

    @property
    def h(self) -> Arr:
        return np.diff(self.nodes)


def make_grid(start: float, period: float, n: int, breaks: Arr | None = None) -> Grid:
    """A grid of about ``n`` intervals (even) over ``[start, start + period)`` with nodes at the
    ``breaks`` [rad] (taken modulo the period).

    The coarse grid has ``n // 2`` even intervals (the node at ``start`` always kept), less the
    nodes closer than 0.3 of a step to a break, plus the breaks; the fine grid halves each
    coarse interval.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 8:
        raise ParameterError("n", n, "must be a whole number >= 8 (intervals over the cycle)")
    nc = int(n) // 2
    hc = period / nc
    rel = hc * np.arange(nc)
    brk = np.zeros(0)
    if breaks is not None and len(breaks):
        brk = np.sort(np.mod(np.asarray(breaks, dtype=float) - start, period))
        brk = np.where(brk > period - 1e-6 * hc, 0.0, brk)
        brk = np.unique(brk)
        brk = brk[np.concatenate(([True], np.diff(brk) > 1e-6 * hc))]
        dist = np.abs(np.mod(rel[:, None] - brk[None, :] + period / 2, period) - period / 2)
        keep = np.all(dist > 0.3 * hc, axis=1)
        keep[0] = True
        rel = np.concatenate((rel[keep], brk[brk > 1e-6 * hc]))
    order = np.argsort(rel)
    rel = rel[order]
    flag = np.isin(rel, brk)  # the nodes where loads jump (the start too, if one is there)
    cn = start + np.append(rel, period)
    fine = np.empty(2 * rel.size + 1)
    fine[0::2] = cn
    fine[1::2] = 0.5 * (cn[:-1] + cn[1:])
    nf = 2 * rel.size
    mids = 0.5 * (fine[:-1] + fine[1:])
    iL = np.arange(nf)
    iR = np.append(np.arange(1, nf), 0)
    extra: list[float] = []
    for kc in np.flatnonzero(flag):
        k = 2 * kc
        iL[k] = 2 * nf + len(extra)
        extra.append(fine[k] + ONE_SIDED)
        iR[(k - 1) % nf] = 2 * nf + len(extra)
        extra.append((fine[k] if k else fine[-1]) - ONE_SIDED)
    pts = np.concatenate((fine[:-1], mids, np.asarray(extra)))
    iM = nf + np.arange(nf)
    # the coarse grid: fine nodes 0, 2, 4, ...; its middles are the odd fine nodes
    return Grid(period, fine, pts, iL, iM, iR,
                (cn, iL[0::2].copy(), np.arange(1, nf, 2), iR[1::2].copy()))


@dataclass(frozen=True)
class Coefficients:
    """Reduced coefficients at the grid's evaluation positions: the links' ``J``, ``dJ``
    [kg m^2, kg m^2/rad], every reduced moment but the drive's and the dampers', ``M`` [N m]
    (loads, gravity, friction), and the reduced damping ``D`` [N m s/rad] of the
    speed-dependent loads (their moment ``-D omega``; None: none)."""

    J: Arr
    dJ: Arr
    M: Arr
    D: Arr | None = None


class Stall(Exception):
    """The crank stops (the speed reaches zero) at ``phi`` [rad], time ``t`` [s], while
    marching."""

    def __init__(self, phi: float, index: int, t: float = 0.0) -> None:
        self.phi = phi
        self.index = index
        self.t = t
        super().__init__(f"stall at phi = {phi}")


# ---------------------------------------------------------------------------------------------
# the torque balance, vectorised and scalar
def eps_of(co: Coefficients, idx: np.ndarray, u: Arr, d: Drive, torque: Arr | float | None = None
           ) -> tuple[Arr, Arr, Arr, Arr]:
    """Crank acceleration ``eps`` [rad/s^2] at positions ``idx`` for ``u = omega^2``, its
    derivative ``d eps / d u``, the motor torque [N m] and the gear's input torque ``M_in``.

    ``torque``: the motor torque if it is given (ConstantTorque), else the characteristic's.
    """
    i, eta = d.ratio, d.eta
    J = co.J[idx] + d.J_out
    dJ = co.dJ[idx]
    w = np.sqrt(np.maximum(u, 0.0))
    if torque is None:
        a = np.asarray(d.motor.torque(i * w), dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            da = np.where(w > 0, d.motor.slope(i * w) * i / (2.0 * np.where(w > 0, w, 1.0)), 0.0)
    else:
        a = np.broadcast_to(np.asarray(torque, dtype=float), w.shape)
        da = np.zeros(w.shape)
    b = d.J_in * i
    c = 0.5 * dJ * u - co.M[idx]
    dc = 0.5 * dJ
    if co.D is not None:
        D = co.D[idx]
        c = c + D * w
        with np.errstate(divide="ignore", invalid="ignore"):
            dc = dc + np.where(w > 0, D / (2.0 * np.where(w > 0, w, 1.0)), 0.0)
    k = np.where(a * J + b * c >= 0.0, i * eta, i / eta)
    den = k * b + J
    eps = (k * a - c) / den
    deps = (k * da - dc) / den
    m_in = a - b * eps
    return eps, deps, a, m_in


def _gain(d: Drive, co: Coefficients, idx: np.ndarray, a: Arr, u: Arr) -> tuple[Arr, Arr]:
    """``k`` of the branch taken and ``d eps / d torque = k / (k b + J)`` (ConstantTorque)."""
    i, eta = d.ratio, d.eta
    J = co.J[idx] + d.J_out
    b = d.J_in * i
    c = 0.5 * co.dJ[idx] * u - co.M[idx]
    if co.D is not None:
        c = c + co.D[idx] * np.sqrt(np.maximum(u, 0.0))
    k = np.where(a * J + b * c >= 0.0, i * eta, i / eta)
    return k, k / (k * b + J)


@dataclass(frozen=True)
class Solution:
    """A solved cycle on a grid: ``u`` at the nodes (N,), and at every interval the values at
    its start, middle and end (``uL, uM, uR``, ``FL, FM, FR`` = du/dphi), the time steps ``dt``
    [s] and the motor torque (at its shaft) ``aL, aM, aR`` [N m]; ``torque`` the constant
    torque of a ConstantTorque drive; ``iterations`` Newton steps."""

    u: Arr
    uL: Arr
    uM: Arr
    uR: Arr
    FL: Arr
    FM: Arr
    FR: Arr
    aL: Arr
    aM: Arr
    aR: Arr
    dt: Arr
    torque: float | None
    iterations: int


def _evaluate(grid_h: Arr, iL: np.ndarray, iM: np.ndarray, iR: np.ndarray, co: Coefficients,
              d: Drive, u: Arr, torque: float | None) -> tuple[Arr, ...]:
    """Residuals and their derivatives of the collocation equations for nodal ``u``."""
    uL = u
    uR = np.roll(u, -1)
    h = grid_h
    eL, dL, aL, _ = eps_of(co, iL, uL, d, torque)
    eR, dR, aR, _ = eps_of(co, iR, uR, d, torque)
    FL, FR, dFL, dFR = 2 * eL, 2 * eR, 2 * dL, 2 * dR
    um = 0.5 * (uL + uR) + h / 8 * (FL - FR)
    eM, dM, aM, _ = eps_of(co, iM, um, d, torque)
    FM, dFM = 2 * eM, 2 * dM
    r = uR - uL - h / 6 * (FL + 4 * FM + FR)
    dr_L = -1.0 - h / 6 * (dFL + 4 * dFM * (0.5 + h / 8 * dFL))
    dr_R = 1.0 - h / 6 * (dFR + 4 * dFM * (0.5 - h / 8 * dFR))
    return r, dr_L, dr_R, uL, um, uR, FL, FM, FR, dFM, aL, aM, aR


def _dt(h: Arr, uL: Arr, um: Arr, uR: Arr) -> Arr:
    """Time of each interval by Simpson's rule on 1/omega; where the speed is (near) zero at
    an end, the exact time of a u linear in phi, ``2 h / (omega_L + omega_R)``."""
    wL, wm, wR = np.sqrt(np.maximum(uL, 0)), np.sqrt(np.maximum(um, 0)), np.sqrt(np.maximum(uR, 0))
    small = np.minimum(np.minimum(wL, wR), wm) < 1e-3 * np.maximum(np.maximum(wL, wR), wm)
    with np.errstate(divide="ignore", invalid="ignore"):
        simpson = h / 6 * (1 / wL + 4 / wm + 1 / wR)
        linear = 2 * h / (wL + wR)
    return np.where(small, linear, simpson)


def solve_periodic(grid_nodes: Arr, iL: np.ndarray, iM: np.ndarray, iR: np.ndarray,
                   co: Coefficients, d: Drive, u0: Arr, torque0: float | None = None, *,
                   tol: float = 1e-12, max_iter: int = 60) -> Solution:
    """The periodic solution of the collocation equations on the intervals of ``grid_nodes``
    (N + 1 nodes, the last the first plus the period), by damped Newton from ``u0`` (N,).

    A :class:`~linkwork.machine.motors.ConstantTorque` drive also solves for its torque
    (start ``torque0``) with the mean crank speed ``mean_speed / i`` as the extra condition.
    Converged when the largest Newton step is below ``tol`` times the mean of ``u`` (and of the
    torque scale).

    Raises
    ------
    ConvergenceError
        Newton's method did not converge (the caller may retry from a marched state), or an
        iterate could not keep the speed above zero.
    """
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    h = np.diff(grid_nodes)
    period = float(grid_nodes[-1] - grid_nodes[0])
    N = h.size
    ct = isinstance(d.motor, ConstantTorque)
    u = np.array(u0, dtype=float)
    scale = float(np.mean(u))
    torque: float | None = None
    t_target = 1.0
    if ct:
        torque = 0.0 if torque0 is None else float(torque0)
        t_target = period * d.ratio / d.motor.mean_speed  # type: ignore[attr-defined]
    q_scale = float(np.max(np.abs(co.M))) + float(np.max(np.abs(co.dJ))) * scale + 1e-300
    k = np.arange(N)
    kp = (k + 1) % N

    def system(u: Arr, torque: float | None) -> tuple[Arr, tuple[Arr, ...]]:
        with np.errstate(all="ignore"):  # a negative u in the middle of an interval: NaN,
            ev = _evaluate(h, iL, iM, iR, co, d, u, torque)  # refused by the line search
            r = ev[0]
            if ct:
                r = np.append(r, (np.sum(_dt(h, ev[3], ev[4], ev[5])) - t_target) * scale
                              / t_target)
        if np.any(ev[4] < 0):
            r = np.full(r.shape, np.nan)
        return r, ev

    r, ev = system(u, torque)
    norm = float(np.max(np.abs(r)))
    for it in range(1, max_iter + 1):
        dr_L, dr_R = ev[1], ev[2]
        rows, cols, vals = [k, k], [k, kp], [dr_L, dr_R]
        size = N
        if ct:
            size = N + 1
            with np.errstate(all="ignore"):
                more = _border(h, iL, iM, iR, co, d, torque, ev,  # type: ignore[arg-type]
                               scale / t_target)
            rows += more[0]
            cols += more[1]
            vals += more[2]
        jac = csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(size, size))
        if not np.all(np.isfinite(jac.data)):
            raise ConvergenceError("periodic solve: the Jacobian is not finite")
        try:
            step = splu(jac).solve(-r)
        except RuntimeError:  # an exactly singular Jacobian
            raise ConvergenceError("periodic solve: singular Jacobian") from None
        if not np.all(np.isfinite(step)):
            raise ConvergenceError("periodic solve: the Newton step is not finite")
        du = step[:N]
        dtq = float(step[N]) if ct else 0.0
        alpha = 1.0
        neg = du < 0
        if np.any(neg):  # keep u > 0: at most 90 % of the way to zero
            alpha = min(1.0, 0.9 * float(np.min(u[neg] / -du[neg])))
        for _ in range(40):
            un = u + alpha * du
            tn = None if torque is None else torque + alpha * dtq
            rn, evn = system(un, tn)
            nn = float(np.max(np.abs(rn)))
            if np.isfinite(nn) and (nn < norm or nn <= 1e-14 * scale):
                break
            alpha *= 0.5
        else:
            raise ConvergenceError("periodic solve: no Newton step reduces the residual")
        u, torque, r, ev, norm = un, tn, rn, evn, nn
        if (float(np.max(np.abs(alpha * du))) <= tol * float(np.mean(u))
                and abs(alpha * dtq) <= tol * q_scale):
            _, _, _, uL, um, uR, FL, FM, FR, _, aL, aM, aR = ev
            return Solution(u, uL, um, uR, FL, FM, FR, aL, aM, aR, _dt(h, uL, um, uR), torque,
                            it)
    raise ConvergenceError(f"periodic solve: Newton's method did not converge in {max_iter} "
                           "steps")


def _border(h: Arr, iL: np.ndarray, iM: np.ndarray, iR: np.ndarray, co: Coefficients,
            d: Drive, torque: float, ev: tuple[Arr, ...], s: float
            ) -> tuple[list[np.ndarray], list[np.ndarray], list[Arr]]:
    """The extra column (d residual / d torque) and row (the mean-speed condition, scaled by
    ``s``) of the ConstantTorque system, as (rows, cols, values) lists."""
    uL, um, uR, dFM = ev[3], ev[4], ev[5], ev[9]
    N = h.size
    k = np.arange(N)
    tq = np.full(N, torque)
    dFL_t = 2 * _gain(d, co, iL, tq, uL)[1]
    dFR_t = 2 * _gain(d, co, iR, tq, uR)[1]
    dFM_t = 2 * _gain(d, co, iM, tq, um)[1]
    dum_t = h / 8 * (dFL_t - dFR_t)
    col = -h / 6 * (dFL_t + 4 * (dFM_t + dFM * dum_t) + dFR_t)
    # the mean speed: sum(dt) = t_target with dt = h/6 (uL^-1/2 + 4 um^-1/2 + uR^-1/2)
    dL = eps_of(co, iL, uL, d, torque)[1]
    dR = eps_of(co, iR, uR, d, torque)[1]
    dum_L = 0.5 + h / 4 * dL
    dum_R = 0.5 - h / 4 * dR
    g = -h / 12
    row_L = s * g * (uL**-1.5 + 4 * um**-1.5 * dum_L)
    row_R = s * g * (uR**-1.5 + 4 * um**-1.5 * dum_R)
    corner = np.array([s * float(np.sum(g * 4 * um**-1.5 * dum_t))])
    last = np.array([N])
    return ([k, np.full(N, N), np.full(N, N), last], [np.full(N, N), k, (k + 1) % N, last],
            [col, row_L, row_R, corner])


# ---------------------------------------------------------------------------------------------
def periodic_solution(grid: Grid, co: Coefficients, d: Drive, u0: Arr,
                      torque0: float | None = None, *, coarse: bool = False,
                      tol: float = 1e-12) -> Solution:
    """:func:`solve_periodic` on the fine grid (or on its coarse grid, ``u0`` at the coarse
    nodes)."""
    if coarse:
        assert grid.coarse is not None
        cn, cL, cM, cR = grid.coarse
        return solve_periodic(cn, cL, cM, cR, co, d, u0, torque0, tol=tol)
    return solve_periodic(grid.nodes, grid.iL, grid.iM, grid.iR, co, d, u0, torque0, tol=tol)


def constant_speed(grid: Grid, co: Coefficients, d: Drive) -> Solution:
    """The 'solution' of a :class:`~linkwork.machine.motors.ConstantSpeed` drive: the crank at
    ``speed / i``, ``eps = 0``, the motor torque from the torque balance."""
    assert isinstance(d.motor, ConstantSpeed)
    w = d.motor.speed / d.ratio
    N = grid.n
    u = np.full(N, w * w)

    def torque(idx: np.ndarray) -> Arr:
        c = 0.5 * co.dJ[idx] * w * w - co.M[idx]  # the crank side's demand at eps = 0
        if co.D is not None:
            c = c + co.D[idx] * w
        return np.where(c >= 0, c / (d.ratio * d.eta), c * d.eta / d.ratio)

    zeros = np.zeros(N)
    h = grid.h
    return Solution(u, u, u, u, zeros, zeros, zeros, torque(grid.iL), torque(grid.iM),
                    torque(grid.iR), h / w, None, 0)


# ---------------------------------------------------------------------------------------------
def _eps_scalar(J: float, dJ: float, M: float, u: float, d: Drive, i: float, eta: float,
                b: float, D: float = 0.0) -> tuple[float, float, float]:
    """:func:`eps_of` at one position (plain floats): eps, d eps/du, motor torque."""
    w = math.sqrt(u) if u > 0.0 else 0.0
    a = float(d.motor.torque(i * w))
    da = float(d.motor.slope(i * w)) * i / (2.0 * w) if w > 0.0 else 0.0
    c = 0.5 * dJ * u - M + D * w
    dc = 0.5 * dJ + (D / (2.0 * w) if w > 0.0 else 0.0)
    k = i * eta if a * J + b * c >= 0.0 else i / eta
    den = k * b + J
    return (k * a - c) / den, (k * da - dc) / den, a


def march(nodes: Arr, iL: np.ndarray, iM: np.ndarray, iR: np.ndarray, co: Coefficients,
          d: Drive, u_start: float, *, loads_part: Arr | None = None,
          factor: Callable[[float], float] | None = None, t0: float = 0.0) -> Solution:
    """Step the collocation interval by interval over ``nodes`` from ``u = u_start`` at
    ``nodes[0]`` (not periodic): one scalar Newton solve per interval.

    ``factor(t)`` scales the part ``loads_part`` of ``co.M`` (the external loads' reduced
    moment at the grid's positions) over time (``t0`` at ``nodes[0]``): at the start of each
    interval at its time, at its middle and end at the times the trapezoid rule gives from the
    speeds of the iterate (second order in the step; a factor that jumps in time is resolved
    to the step).

    Raises
    ------
    Stall
        The speed reaches zero within an interval (the crank stops: the motor cannot move the
        machine there); its ``t`` is the time at the start of that interval.
    """
    h = np.diff(nodes)
    N = h.size
    i, eta = d.ratio, d.eta
    b = d.J_in * i
    J = (co.J + d.J_out).tolist()
    dJ = co.dJ.tolist()
    M0 = co.M.tolist()
    Dl = co.D.tolist() if co.D is not None else [0.0] * len(M0)
    ML = None if loads_part is None or factor is None else loads_part.tolist()
    out = np.empty((10, N))
    uk = float(u_start)
    t = float(t0)
    L, Mi, R, hh = iL.tolist(), iM.tolist(), iR.tolist(), h.tolist()
    timed = ML is not None and factor is not None
    for k in range(N):
        hk = hh[k]
        l, m, r = L[k], Mi[k], R[k]
        Ml, Mm, Mr = M0[l], M0[m], M0[r]
        if timed:
            Ml += (float(factor(t)) - 1.0) * ML[l]  # type: ignore[index, misc]
        eL, _, aL = _eps_scalar(J[l], dJ[l], Ml, uk, d, i, eta, b, Dl[l])
        FL = 2.0 * eL
        if uk <= 0.0 and FL <= 0.0:
            raise Stall(float(nodes[k]), k, t)

        def res(x: float, hk: float = hk, uk: float = uk, FL: float = FL, m: int = m,
                r: int = r, Mm: float = Mm, Mr: float = Mr, t: float = t
                ) -> tuple[float, float, float, float, float, float, float]:
            if timed:  # the loads' factor at the times of the end and the middle (trapezoid
                wl, wr = math.sqrt(uk), math.sqrt(max(x, 0.0))  # estimates from this x)
                tr = t + 2.0 * hk / (wl + wr) if wl + wr > 0 else t
                tm = t + hk / (wl + math.sqrt(max(0.5 * (uk + x), 0.0)) + 1e-300)
                Mr = M0[r] + (float(factor(tr)) - 1.0) * ML[r]  # type: ignore[index, misc]
                Mm = M0[m] + (float(factor(tm)) - 1.0) * ML[m]  # type: ignore[index, misc]
            eR, dR, _aR = _eps_scalar(J[r], dJ[r], Mr, x, d, i, eta, b, Dl[r])
            FR, dFR = 2.0 * eR, 2.0 * dR
            um = 0.5 * (uk + x) + hk / 8.0 * (FL - FR)
            eM, dM, _aM = _eps_scalar(J[m], dJ[m], Mm, max(um, 0.0), d, i, eta, b, Dl[m])
            FM, dFM = 2.0 * eM, 2.0 * dM
            rr = x - uk - hk / 6.0 * (FL + 4.0 * FM + FR)
            drr = 1.0 - hk / 6.0 * (dFR + 4.0 * dFM * (0.5 - hk / 8.0 * dFR))
            return rr, drr, um, FM, FR, Mm, Mr

        x = max(uk + hk * FL, 0.0)
        ok = False
        for _ in range(50):
            rr, drr, um, FM, FR, _, _ = res(x)
            if drr <= 0.0 or not math.isfinite(drr):
                break
            xn = x - rr / drr
            if xn < 0.0:
                xn = 0.5 * x
            if abs(xn - x) <= 1e-14 * max(abs(xn), abs(uk), 1e-300):
                x = xn
                ok = True
                break
            x = xn
        if not ok:  # bracket the root in [0, big] and bisect (Brent would need scipy here)
            xb = _bisect(res, uk, hk, FL)
            if xb is None:
                raise Stall(float(nodes[k]), k, t)
            x = xb
        rr, drr, um, FM, FR, Mm, Mr = res(x)
        if x <= 0.0 or um < 0.0:
            raise Stall(float(nodes[k]), k, t)
        _eR, _, aR = _eps_scalar(J[r], dJ[r], Mr, x, d, i, eta, b, Dl[r])
        _eM, _, aM = _eps_scalar(J[m], dJ[m], Mm, um, d, i, eta, b, Dl[m])
        out[:, k] = (uk, um, x, FL, FM, FR, aL, aM, aR, hk)
        wl, wm, wr = math.sqrt(uk), math.sqrt(um), math.sqrt(x)
        t += (2.0 * hk / (wl + wr) if min(wl, wm, wr) < 1e-3 * max(wl, wm, wr)
              else hk / 6.0 * (1.0 / wl + 4.0 / wm + 1.0 / wr))
        uk = x
    uL, uM, uR, FL_, FM_, FR_, aL_, aM_, aR_, hs = out
    return Solution(np.append(uL, uR[-1]), uL, uM, uR, FL_, FM_, FR_, aL_, aM_, aR_,
                    _dt(hs, uL, uM, uR), None, 0)


def _bisect(f: Callable[[float], tuple[float, ...]], uk: float, hk: float, FL: float
            ) -> float | None:
    """The root of the interval's residual ``f(x)[0]`` on [0, hi] by bisection, or None (no
    positive root: the speed reaches zero)."""
    lo = 0.0
    if f(lo)[0] >= 0.0:
        return None
    hi = max(2.0 * uk, uk + 2.0 * hk * abs(FL), 1e-12)
    for _ in range(200):
        if f(hi)[0] > 0.0:
            break
        hi *= 2.0
    else:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid)[0] < 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


# ---------------------------------------------------------------------------------------------
def hermite_extremes(nodes: Arr, f0: Arr, f1: Arr, d0: Arr, d1: Arr
                     ) -> tuple[float, float, float, float]:
    """Largest and smallest value of the piecewise cubic Hermite interpolant with values
    ``f0, f1`` and slopes ``d0, d1`` at the start and end of each interval of ``nodes``:
    (max, where [rad], min, where [rad])."""
    h = np.diff(nodes)[: f0.size]
    u0, u1, s0, s1 = f0, f1, d0 * h, d1 * h
    # f(s) = (2s^3-3s^2+1)u0 + (s^3-2s^2+s)s0 + (-2s^3+3s^2)u1 + (s^3-s^2)s1, s in [0, 1]
    A = 3 * (2 * u0 + s0 - 2 * u1 + s1)
    B = 2 * (-3 * u0 - 2 * s0 + 3 * u1 - s1)
    C = s0
    cand_s = [np.zeros_like(u0), np.ones_like(u0)]
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = B * B - 4 * A * C
        sq = np.sqrt(np.maximum(disc, 0.0))
        for sgn in (1.0, -1.0):
            s = np.where(np.abs(A) > 1e-300, (-B + sgn * sq) / (2 * A),
                         np.where(np.abs(B) > 1e-300, -C / B, 0.0))
            cand_s.append(np.where((disc >= 0) & (s > 0) & (s < 1), s, 0.0))
    S = np.stack(cand_s)
    U = ((2 * S**3 - 3 * S**2 + 1) * u0 + (S**3 - 2 * S**2 + S) * s0
         + (-2 * S**3 + 3 * S**2) * u1 + (S**3 - S**2) * s1)
    P = nodes[: u0.size] + S * h
    imax = np.unravel_index(np.argmax(U), U.shape)
    imin = np.unravel_index(np.argmin(U), U.shape)
    return float(U[imax]), float(P[imax]), float(U[imin]), float(P[imin])


def extremes(nodes: Arr, sol: Solution) -> tuple[float, float, float, float]:
    """Largest and smallest ``u`` over the cycle and their positions [rad], from the cubic
    Hermite interpolant of each interval (the collocation's own: values and slopes ``F`` at
    both ends): (u_max, phi_max, u_min, phi_min)."""
    return hermite_extremes(nodes, sol.uL, sol.uR, sol.FL, sol.FR)
