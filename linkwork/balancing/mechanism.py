"""Counterweights on planar-engine mechanisms: new mechanism descriptions, general force balance.

A counterweight changes only the mass properties of the link that carries it, so the balanced
mechanism is a new :class:`~linkwork.planar.model.Mechanism` with those links' mass, centre of
mass and inertia replaced by the combined values; every other analysis (kinematics, inverse
dynamics, the CLI) runs on it unchanged.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.loads import peak, rms
from linkwork.balancing.partial import periodic_weights
from linkwork.balancing.static import Counterweight, crank_slider_counterweight
from linkwork.checks import require_finite
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.planar.inertia import inertia_wrenches
from linkwork.planar.kinematics import Kinematics, kinematics
from linkwork.planar.model import Body, Crank, Mechanism, Prismatic, Revolute
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "ForceBalance",
    "ShakingLoads",
    "add_counterweights",
    "centre_of_mass_balance",
    "crank_axis",
    "crank_slider_balance",
    "cycle",
    "force_balance",
    "frame_hinge",
    "frame_hinged_links",
    "one_crank_cycle",
    "path_rms",
    "path_weights",
    "shaking_loads",
    "with_counterweight",
]


def crank_axis(mech: Mechanism) -> tuple[str, tuple[float, float]]:
    """The driven crank's name and its axis O in frame coordinates [m].

    Raises
    ------
    ParameterError
        The driver is not a crank hinged to the frame.
    """
    one_crank_cycle(mech, "paper 001's balancing")
    d = mech.driver
    assert not isinstance(d, tuple)  # one_crank_cycle
    j = mech.joint(d.joint)
    if not isinstance(d, Crank) or not isinstance(j, Revolute) or mech.frame.name not in (
            j.a, j.b):
        raise ParameterError("driver", d.joint, "must be a crank turning about a frame joint")
    crank = j.b if j.a == mech.frame.name else j.a
    fp = mech.frame.point(j.pa if j.a == mech.frame.name else j.pb)
    return crank, fp


def one_crank_cycle(mech: Mechanism, what: str) -> None:
    """Refuse a mechanism of several drivers for ``what``, which runs over one turn of one
    crank (ParameterError naming the drivers)."""
    if mech.n_drivers != 1:
        names = [d.joint for d in mech.drivers]
        raise ParameterError("driver", names, f"{what} runs over one turn of one crank, and the "
                             f"mechanism has {len(names)} drivers; its shaking loads over a path "
                             "of its drivers: shaking_loads(kinematics(mech, phi1)), "
                             "counterweights: add_counterweights")


def frame_hinge(mech: Mechanism, link: str) -> tuple[float, float]:
    """Local coordinates [m] of the point where ``link`` is hinged to the frame.

    Raises
    ------
    ParameterError
        ``link`` is the frame, unknown, or has no revolute joint with the frame.
    """
    if link == mech.frame.name:
        raise ParameterError("counterweight.link", link, "must be a moving link, not the frame")
    mech.body(link)
    for j in mech.joints:
        if isinstance(j, Revolute):
            if j.a == mech.frame.name and j.b == link:
                return mech.body(link).point(j.pb)
            if j.b == mech.frame.name and j.a == link:
                return mech.body(link).point(j.pa)
    raise ParameterError("counterweight.link", link,
                         f"must be hinged to the frame by a revolute joint; such links: "
                         f"{list(frame_hinged_links(mech))}")


def frame_hinged_links(mech: Mechanism) -> tuple[str, ...]:
    """Names of the moving links joined to the frame by a revolute joint, in body order."""
    out = []
    for b in mech.bodies:
        for j in mech.joints:
            if isinstance(j, Revolute) and {j.a, j.b} == {mech.frame.name, b.name}:
                out.append(b.name)
                break
    return tuple(out)


def with_counterweight(body: Body, hinge: tuple[float, float], cw: Counterweight) -> Body:
    """``body`` with a counterweight added: combined mass, centre of mass and inertia.

    The counterweight's centre is at ``hinge + radius*(cos angle, sin angle)`` in the body's
    frame, its mass ``S / radius``; the inertia about the new centre follows the parallel-axis
    theorem.
    """
    m_cw = cw.mass()
    r = cw.radius
    assert r is not None  # cw.mass() raised otherwise
    rho = np.array(hinge) + r * np.array([np.cos(cw.angle), np.sin(cw.angle)])
    c0 = np.array(body.com)
    m = body.mass + m_cw
    if m == 0.0:
        return body
    c = (body.mass * c0 + m_cw * rho) / m
    inertia = (body.inertia + body.mass * float(np.sum((c0 - c) ** 2))
               + cw.inertia + m_cw * float(np.sum((rho - c) ** 2)))
    return dataclasses.replace(body, mass=m, com=(float(c[0]), float(c[1])), inertia=inertia)


def add_counterweights(mech: Mechanism, counterweights: Iterable[Counterweight]) -> Mechanism:
    """A new mechanism with the counterweights added to their (frame-hinged) links.

    Parameters
    ----------
    mech : Mechanism
    counterweights : iterable of Counterweight
        Each with ``link`` a frame-hinged link of ``mech`` and a ``radius``; the angle is
        measured from the link body's x axis, the radius from its hinge with the frame.

    Returns
    -------
    Mechanism
        Same frame, joints, driver and branches; the carrying links' mass properties changed.
    """
    bodies = {b.name: b for b in mech.bodies}
    for cw in counterweights:
        hinge = frame_hinge(mech, cw.link)
        bodies[cw.link] = with_counterweight(bodies[cw.link], hinge, cw)
    return dataclasses.replace(mech, bodies=tuple(bodies[b.name] for b in mech.bodies))


def cycle(n: int = 360, start: float = 0.0) -> np.ndarray:
    """``n`` crank angles evenly spaced over one turn from ``start`` [rad], end excluded."""
    if int(n) != n or n < 8:
        raise ParameterError("n", n, "must be an integer >= 8")
    return start + 2.0 * np.pi * np.arange(int(n)) / int(n)


@dataclass(frozen=True)
class ShakingLoads(Result):
    """Shaking force and moment of a mechanism over the driver positions.

    Attributes
    ----------
    phi1 : ndarray (n,)
        Driver positions [rad] ((n_drivers, n) for several drivers: then the cycle statistics
        ``force_rms``/``moment_rms`` are undefined, the peaks are not).
    fx, fy : ndarray (n,)
        Shaking force :math:`-\\sum m_i a_{S_i}` [N] (exerted on the frame).
    moment : ndarray (n,)
        Shaking moment about ``point`` [N·m], counter-clockwise positive:
        :math:`-\\sum [(r_{S_i} - P)\\times m_i a_{S_i} + I_{S_i}\\varepsilon_i]`.
    point : tuple
        Reference point P in frame coordinates [m].
    """

    phi1: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    moment: np.ndarray
    point: tuple[float, float]
    units: ClassVar[dict[str, str]] = {"phi1": "rad", "fx": "N", "fy": "N", "moment": "N*m",
                                       "point": "m"}

    @property
    def force(self) -> np.ndarray:
        """(n, 2) shaking force [N]."""
        return np.stack([self.fx, self.fy], axis=-1)

    def force_rms(self) -> float:
        """Continuous RMS of |F| over the cycle [N] (phi1 must sample one full cycle)."""
        return rms(self.phi1, self.force, vector=True)

    def moment_rms(self) -> float:
        """Continuous RMS of the moment over the cycle [N·m]."""
        return rms(self.phi1, self.moment)

    def force_peak(self) -> float:
        """Largest |F| over the samples [N]."""
        return peak(self.force, vector=True)

    def moment_peak(self) -> float:
        """Largest |M| over the samples [N·m]."""
        return peak(self.moment)

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Shaking-force hodograph and shaking moment: a :class:`linkwork.plot.Figure` with
        2 axes."""
        from linkwork.plot.balancing import shaking_loads_figure

        return shaking_loads_figure(self, axes=axes, **kw)


def shaking_loads(kin: Kinematics, point: ArrayLike = (0.0, 0.0)) -> ShakingLoads:
    """Shaking force and moment about ``point`` from a kinematic solution and mass properties.

    Parameters
    ----------
    kin : Kinematics
        From :func:`linkwork.planar.kinematics.kinematics`; the mass properties are those of
        ``kin.mechanism``.
    point : (x, y)
        Reference point of the moment [m], frame coordinates.
    """
    P = require_finite("point", point)
    if P.shape != (2,):
        raise ParameterError("point", P.tolist(), "must be (x, y)")
    # the resultant of the inertia forces and couples (no gravity)
    fx, fy, mz = inertia_wrenches(kin).resultant((P[0], P[1]))
    return ShakingLoads(kin.phi1, fx, fy, mz, (float(P[0]), float(P[1])))


@dataclass(frozen=True)
class ForceBalance(Result):
    """Counterweights for (the best possible) force balance of a mechanism.

    Attributes
    ----------
    counterweights : tuple of Counterweight
        One per frame-hinged link used (static moment, angle on the link, radius).
    mechanism : Mechanism
        The balanced mechanism (a new description).
    full : bool
        True when the shaking force vanishes (residual RMS <= ``tol`` times the unbalanced).
    force_rms_before, force_rms_after : float
        RMS of |F| over the cycle [N] at the driver's constant speed ``omega1``.
    ratio : float
        force_rms_after / force_rms_before.
    reason : str
        Why full force balance is impossible (empty when ``full``).
    """

    counterweights: tuple[Counterweight, ...]
    mechanism: Mechanism
    full: bool
    force_rms_before: float
    force_rms_after: float
    ratio: float
    reason: str
    units: ClassVar[dict[str, str]] = {"force_rms_before": "N", "force_rms_after": "N"}
    position_field: ClassVar[str] = "force_rms_before"

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """RMS shaking force before and after, as bars: a :class:`linkwork.plot.Figure` with
        1 axes."""
        from linkwork.plot.balancing import force_balance_figure

        return force_balance_figure(self, ax=ax, **kw)


def _cw_force_basis(kin: Kinematics, link: str) -> np.ndarray:
    """Shaking force per unit local first moment q of a counterweight on a frame-hinged link.

    F = (omega^2 I - eps J) A(theta) q; returns shape (n, 2, 2).
    """
    i = kin.bodies.index(link)
    th, w, e = kin.theta[i], kin.omega[i], kin.eps[i]
    c, s = np.cos(th), np.sin(th)
    A = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)  # (n, 2, 2)
    w2 = w**2
    K = np.stack([np.stack([w2, e], -1), np.stack([-e, w2], -1)], -2)  # w2*I - e*J
    return np.asarray(np.einsum("nij,njk->nik", K, A))


def _default_radius(mech: Mechanism, link: str) -> float:
    h = np.array(frame_hinge(mech, link))
    d = [float(np.hypot(*(np.array(p) - h))) for p in mech.body(link).points.values()]
    d = [x for x in d if x > 0]
    return 0.5 * max(d) if d else 0.1


def _counterweighted(mech: Mechanism, links: Sequence[str] | None,
                     radii: float | Mapping[str, float] | None) -> tuple[str, ...]:
    """The links to carry counterweights (default every frame-hinged link), checked."""
    use = tuple(frame_hinged_links(mech) if links is None else links)
    if not use:
        raise ParameterError("links", list(use), "no link hinged to the frame to carry a "
                             "counterweight")
    for link in use:
        frame_hinge(mech, link)
    if isinstance(radii, Mapping):  # a misspelt link would silently get the default radius
        for key in radii:
            if key not in use:
                raise ParameterError("radii", key, f"names no counterweighted link; links: "
                                     f"{list(use)}")
    return use


def _counterweights(mech: Mechanism, use: Sequence[str], q: np.ndarray,
                    radii: float | Mapping[str, float] | None
                    ) -> tuple[list[Counterweight], Mechanism]:
    """The counterweights of local first moments ``q`` (two per link of ``use``) at their
    radii, and the mechanism carrying them."""
    cws = []
    for k, link in enumerate(use):
        if isinstance(radii, Mapping):
            r = float(radii[link]) if link in radii else _default_radius(mech, link)
        elif radii is None:
            r = _default_radius(mech, link)
        else:
            r = float(radii)
        cws.append(Counterweight.from_first_moment(link, complex(q[2 * k], q[2 * k + 1]), r))
    return cws, add_counterweights(mech, [c for c in cws if c.static_moment > 0])


def _not_balanceable(mech: Mechanism, links: Sequence[str]) -> str:
    sliders = []
    for j in mech.joints:
        if isinstance(j, Prismatic) and mech.frame.name in (j.a, j.b):
            b = j.b if j.a == mech.frame.name else j.a
            if mech.body(b).mass > 0:
                sliders.append(b)
    why = (f"the total first moment of mass contains terms that do not rotate rigidly with the "
           f"counterweighted links {list(links)}")
    others = [b for b in frame_hinged_links(mech) if b not in links]
    if others:
        why += f"; frame-hinged links without a counterweight: {others}"
    if sliders:
        why += (f"; {sliders} translate on the frame (reciprocating mass: its first moment "
                "follows the slide coordinate, with all its harmonics, which no rotating "
                "counterweight can cancel)")
    return why


def force_balance(mech: Mechanism, links: Sequence[str] | None = None,
                  radii: float | Mapping[str, float] | None = None, *, n: int = 360,
                  tol: float = 1e-9, require_full: bool = False) -> ForceBalance:
    """Counterweights on frame-hinged links that make the shaking force vanish, or least.

    The shaking force is linear in the counterweights' local first moments
    :math:`q_k = m_k \\rho_k`: a counterweight on link k (hinged to the frame, angle
    :math:`\\theta_k`) adds :math:`(\\omega_k^2 I - \\varepsilon_k J) A(\\theta_k) q_k`. The
    :math:`q_k` minimising the cycle RMS of the total shaking force (weighted linear least
    squares over ``n`` positions of one turn, at constant crank speed; the result does not
    depend on the speed) are returned. When the
    mechanism can be fully force balanced by counterweights on these links (the method of
    linearly independent vectors succeeds: four-bar, any coupler centre), the residual is zero
    to rounding and this is the classical solution; otherwise (e.g. a slider's reciprocating
    mass) ``full`` is False, ``reason`` says why, and the counterweights are the best in the
    RMS sense (for a centred crank-slider: half of the reciprocating mass on the crank).

    Parameters
    ----------
    mech : Mechanism
        A crank-driven mechanism with mass properties.
    links : sequence of str, optional
        Links to carry counterweights (each hinged to the frame by a revolute joint); default
        all such links.
    radii : float or mapping link -> float, optional
        Counterweight radius from the hinge [m] (sets its mass S/r and inertia m r^2 in the new
        mechanism); default half the distance from the hinge to the link's farthest point.
        A mapping's keys must be links that carry a counterweight (``ParameterError``
        otherwise: a misspelt name would silently leave that link on the default).
    n : int
        Positions over one turn.
    tol : float
        Relative residual (RMS after / before) under which the balance counts as full.
    require_full : bool
        Raise :class:`~linkwork.errors.InfeasibleError` instead of returning a partial balance.

    Returns
    -------
    ForceBalance
    """
    use = _counterweighted(mech, links, radii)
    one_crank_cycle(mech, "force_balance")
    phi = cycle(n)
    kin = kinematics(mech, phi, 1.0, 0.0)  # unit constant speed: F scales with omega^2
    base = shaking_loads(kin)
    F0 = base.force.reshape(-1)
    w = np.repeat(periodic_weights(phi), 2)
    B = np.concatenate([_cw_force_basis(kin, link).reshape(-1, 2) for link in use], axis=1)
    sw = np.sqrt(w)
    q = np.linalg.lstsq(B * sw[:, None], -F0 * sw, rcond=None)[0]
    unit_before = base.force_rms()
    unit_after = rms(phi, (F0 + B @ q).reshape(-1, 2), vector=True)
    ratio = unit_after / unit_before if unit_before > 0 else 0.0
    w2 = float(mech.drivers[0].omega1) ** 2  # reported at the driver's speed
    rms_before, rms_after = unit_before * w2, unit_after * w2
    full = ratio <= tol
    reason = "" if full else _not_balanceable(mech, use)
    if not full and require_full:
        raise InfeasibleError("full force balance by counterweights on frame-hinged links",
                              f"RMS shaking force {rms_after:.6g} N ({ratio:.3g} of unbalanced)",
                              reason)
    cws, balanced = _counterweights(mech, use, q, radii)
    return ForceBalance(tuple(cws), balanced, bool(full), rms_before, rms_after, ratio, reason)


def path_weights(n: int) -> np.ndarray:
    """Trapezoid weights of ``n`` samples along a path (its ends half), summing to 1: the mean
    over a path of a quantity sampled evenly along it."""
    w = np.ones(n)
    w[[0, -1]] = 0.5
    return w / w.sum()


def path_rms(values: ArrayLike) -> float:
    """RMS along a path (trapezoid weights, :func:`path_weights`) of a scalar (n,) or the
    magnitude of a vector (n, 2)."""
    v = np.asarray(values, dtype=float)
    sq = np.sum(v * v, axis=-1) if v.ndim == 2 else v * v
    return float(np.sqrt(np.sum(path_weights(len(sq)) * sq)))


def centre_of_mass_balance(kin: Kinematics, links: Sequence[str] | None = None,
                           radii: float | Mapping[str, float] | None = None, *,
                           tol: float = 1e-9) -> ForceBalance:
    r"""Counterweights on frame-hinged links that keep the total centre of mass of the moving
    links still over the positions of ``kin``, or as still as possible: force balance for a
    mechanism of any number of drivers.

    A counterweight of local first moment :math:`q_k` (about its hinge :math:`O_k`) on link k
    adds :math:`m_k O_k + A(\theta_k) q_k` to the first moment of mass :math:`\sum m_i
    r_{S_i}`; the :math:`q_k` and a constant c minimising :math:`\sum_j w_j |\sum m_i r_{S_i}
    + \sum_k A(\theta_k) q_k - c|^2` over the positions (trapezoid weights along the path,
    :func:`path_weights`) are returned. When the first moment is then constant (its excursion
    at most ``tol`` times the unbalanced one: ``full``) the shaking force vanishes at any speeds
    of the drivers and gravity does no work on the moving links (no driver carries their
    weight); otherwise the counterweights are the least-squares ones and ``reason`` says what
    cannot be balanced. Unlike :func:`force_balance` (one crank turning at constant speed: the
    RMS of the shaking force over its turn) the result does not depend on the drivers' speeds.

    Parameters
    ----------
    kin : Kinematics
        The positions (any number of drivers, e.g. along their path); their speeds give the
        reported shaking forces before and after.
    links, radii
        As for :func:`force_balance`.
    tol : float
        Relative excursion under which the balance counts as full.

    Returns
    -------
    ForceBalance
        ``force_rms_before``, ``force_rms_after``: RMS along the positions of the shaking force
        at the motion of ``kin``; ``ratio`` their ratio.

    Raises
    ------
    ParameterError
        A counterweighted link does not turn over the positions (its counterweight is not
        determined), or a link is not hinged to the frame.
    """
    mech = kin.mechanism
    use = _counterweighted(mech, links, radii)
    n = kin.theta.shape[-1]
    w = path_weights(n)
    m0 = np.zeros((n, 2))
    for b in mech.bodies:
        c = kin.point(b.name, "com")
        m0 += b.mass * np.stack([c.x, c.y], axis=-1)
    cols = []
    for link in use:
        th = kin.theta[kin.bodies.index(link)]
        if np.ptp(np.unwrap(th)) <= 1e-9:
            raise ParameterError("links", link, "does not turn over the positions: its "
                                 "counterweight is not determined (leave it out of "
                                 "[balance] links, or give a path along which it turns)")
        c, s_ = np.cos(th), np.sin(th)
        cols.append(np.stack([np.stack([c, s_], -1), np.stack([-s_, c], -1)], -1))  # (n,2,2)
    basis = np.concatenate(cols, axis=-1)                      # (n, 2, 2 n_links)
    const = np.broadcast_to(-np.eye(2), (n, 2, 2))
    a = np.concatenate([basis, const], axis=-1).reshape(2 * n, -1)
    sw = np.sqrt(np.repeat(w, 2))
    sol = np.linalg.lstsq(a * sw[:, None], -m0.reshape(-1) * sw, rcond=None)[0]
    q = sol[:-2]
    before = m0 - np.sum(w[:, None] * m0, axis=0)
    after = m0 + (basis @ q)
    after = after - np.sum(w[:, None] * after, axis=0)
    excursion = path_rms(before)
    full = path_rms(after) <= tol * excursion if excursion > 0 else True
    reason = "" if full else _not_balanceable(mech, use)
    cws, balanced = _counterweights(mech, use, q, radii)
    kb = kinematics(balanced, kin.phi1, kin.omega1, kin.eps1)
    f0 = shaking_loads(kin).force
    f1 = shaking_loads(kb).force
    rb, ra = path_rms(f0), path_rms(f1)
    return ForceBalance(tuple(cws), balanced, bool(full), rb, ra, ra / rb if rb > 0 else 0.0,
                        reason)


def crank_slider_balance(mech: Mechanism, fraction: float = 0.0,
                         radius: float | None = None) -> Mechanism:
    """A crank-slider with its crank counterweight for rotating balance plus a fraction of the
    reciprocating mass (:func:`~linkwork.balancing.static.crank_slider_counterweight`).

    ``mech`` is a crank-slider of the engine: a driven crank hinged to the frame, a rod
    joined to the crank and to a slider, the slider on a prismatic joint of the frame (as
    :func:`linkwork.planar.model.crank_slider` builds it; any guide offset and direction). The
    rod's and crank's centres may lie off their lines.

    Parameters
    ----------
    mech : Mechanism
    fraction : float
        Share k in [0, 1] of the reciprocating mass (slider plus the rod's share at B).
    radius : float, optional
        Counterweight radius [m]; default half the crank length.

    Returns
    -------
    Mechanism
        The balanced mechanism (a new description).
    """
    crank, _ = crank_axis(mech)
    fr = mech.frame.name
    h = np.array(frame_hinge(mech, crank))
    revs = [j for j in mech.joints if isinstance(j, Revolute) and crank in (j.a, j.b)
            and fr not in (j.a, j.b)]
    if len(revs) != 1:
        raise ParameterError("mechanism", crank, "the crank must be joined to exactly one rod")
    jA = revs[0]
    rod = jA.b if jA.a == crank else jA.a
    A_crank = np.array(mech.body(crank).point(jA.pa if jA.a == crank else jA.pb))
    A_rod = np.array(mech.body(rod).point(jA.pb if jA.a == crank else jA.pa))
    others = [j for j in mech.joints if isinstance(j, Revolute) and rod in (j.a, j.b)
              and j is not jA]
    if len(others) != 1:
        raise ParameterError("mechanism", rod, "the rod must join the crank and one slider")
    jB = others[0]
    slider = jB.b if jB.a == rod else jB.a
    B_rod = np.array(mech.body(rod).point(jB.pa if jB.a == rod else jB.pb))
    if not any(isinstance(j, Prismatic) and {j.a, j.b} == {fr, slider} for j in mech.joints):
        raise ParameterError("mechanism", slider, "must slide on a prismatic joint of the frame")

    def local(v: np.ndarray, axis: np.ndarray) -> complex:
        """v in the coordinates of a line with direction ``axis`` (complex)."""
        z = complex(v[0], v[1]) / complex(axis[0], axis[1]) * abs(complex(axis[0], axis[1]))
        return z

    ca = A_crank - h
    l1 = float(np.hypot(*ca))
    ab = B_rod - A_rod
    l2 = float(np.hypot(*ab))
    cb, rb, sb = mech.body(crank), mech.body(rod), mech.body(slider)
    s1 = local(np.array(cb.com) - h, ca)
    s2 = local(np.array(rb.com) - A_rod, ab)
    cw = crank_slider_counterweight(l1, l2, cb.mass, s1, rb.mass, s2, sb.mass, fraction)
    line = float(np.arctan2(ca[1], ca[0]))  # the crank line's angle in the crank body frame
    r = 0.5 * l1 if radius is None else float(radius)
    return add_counterweights(mech, [Counterweight(crank, cw.static_moment, cw.angle + line, r)])
