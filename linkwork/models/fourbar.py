r"""The four-bar linkage in closed form, and its planar kinetostatics.

Notation (Norton [1]_): link 1 is the frame, link 2 the crank ``a = O2A``, link 3 the coupler
``b = AB``, link 4 the rocker ``c = O4B``, ``d = O2O4`` the frame.  The origin is the crank pivot
O2 and the x axis is the frame line O2 -> O4, so ``O4 = (d, 0)``.  Every angle (``phi1``,
``theta3``, ``theta4``) is measured counter-clockwise from that x axis: ``phi1`` is the angle of
O2 -> A, ``theta3`` of A -> B, ``theta4`` of O4 -> B.  Angular velocities and accelerations are
positive counter-clockwise.

Names: the crank is the driver, so its angle, speed and acceleration carry linkwork's driver
names ``phi1``, ``omega1``, ``eps1`` (Norton's theta2, omega2, alpha2); the coupler and rocker
keep Norton's link numbers: ``theta3``, ``omega3``, ``eps3`` (Norton's alpha3) and ``theta4``,
``omega4``, ``eps4``.  The former names (``theta2``, ``omega2``, ``alpha2``..``alpha4``,
``on_fail``, ``assembled``) still work, with a DeprecationWarning (``docs/nomenclature.md``).

Assembly branch: for a crank angle the coupler-rocker joint B lies at one of the two intersections
of the circles (A, b) and (O4, c).  ``branch=+1`` takes the one on the LEFT of the directed line
from the crank pin A to O4 (the usual "open" four-bar when the linkage is drawn above the frame
line), ``branch=-1`` the one on the right ("crossed").

Kinetostatics (:func:`fourbar_kinetostatics`) follows the link-by-link equilibrium of paper 004
[2]_ (its Eqs. (8)-(13)), re-derived here for any centre-of-mass position, gravity and external
loads; :func:`paper004_planar` and ``paper004_eq8`` ... ``paper004_eq13`` evaluate the paper's
printed formulas literally (``printed=True``) or in corrected form, so that every printed formula
can be checked (see ``docs/errata.md`` and ``docs/fourbar.md``).

References
----------
.. [1] R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill, 2012, chapters 2, 4, 6, 7, 11.
.. [2] S. Zh. Abdrashev, D. S. Myrzaliev, "Kinetostatic analysis of planar linkages of the STB
   loom with redundant constraints" (in Russian), paper 004 of ``shared/papers``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import (
    all_finite,
    finite_value,
    positive_value,
    require_branch,
    require_finite,
    require_pair,
    require_positive,
    shapes_error,
)
from linkwork.deprecation import renamed_attribute, renamed_keywords
from linkwork.errors import AssemblyError, ParameterError, angle_ranges
from linkwork.results import Result, all_true

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "FourbarForces",
    "FourbarLimits",
    "FourbarResult",
    "GrashofType",
    "Paper004Planar",
    "TransmissionExtremes",
    "fourbar",
    "fourbar_kinetostatics",
    "grashof",
    "limit_positions",
    "paper004_eq8",
    "paper004_eq9",
    "paper004_eq10",
    "paper004_eq11",
    "paper004_eq12",
    "paper004_eq13",
    "paper004_planar",
    "transmission_angle",
    "transmission_angle_extremes",
]

_TWO_PI = 2.0 * math.pi
_F64 = np.dtype(float)
_INF = math.inf
_min = np.minimum.reduce


# ---------------------------------------------------------------------------------------------
# argument checks (fast for plain Python scalars: fourbar() must stay close to bare NumPy)
# ---------------------------------------------------------------------------------------------





# ---------------------------------------------------------------------------------------------
# kinematics
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FourbarResult(Result):
    """Positions, velocities and accelerations of a four-bar over crank angles.

    Arrays broadcast over designs (leading axes) and crank angles (last axis).  Angles are
    counter-clockwise from the frame line O2 -> O4 [rad]; points in the frame with origin O2 and
    x axis along O2 -> O4 [m].

    Attributes
    ----------
    phi1 : ndarray
        Crank angle (input) [rad].
    theta3, theta4 : ndarray
        Coupler angle (A -> B) and rocker angle (O4 -> B) [rad], in (-pi, pi].
    omega3, omega4 : ndarray
        Angular velocities of the coupler and the rocker [rad/s].
    eps3, eps4 : ndarray
        Angular accelerations of the coupler and the rocker [rad/s^2].
    xA, yA, xB, yB : ndarray
        Crank pin A and coupler-rocker joint B [m].
    xP, yP : ndarray or None
        Coupler point P, when ``coupler_point`` was given [m].
    valid : ndarray of bool
        True where the linkage assembles (always all True unless ``on_failure="nan"``); also
        readable under its former name ``assembled`` (deprecated).
    a, b, c, d : float or ndarray
        Crank, coupler, rocker, frame lengths [m].
    omega1, eps1 : float or ndarray
        Crank angular velocity [rad/s] and acceleration [rad/s^2].
    branch : int
        Assembly branch (+1: B left of the directed line A -> O4).
    """

    phi1: np.ndarray
    theta3: np.ndarray
    theta4: np.ndarray
    omega3: np.ndarray
    omega4: np.ndarray
    eps3: np.ndarray
    eps4: np.ndarray
    xA: np.ndarray
    yA: np.ndarray
    xB: np.ndarray
    yB: np.ndarray
    xP: np.ndarray | None
    yP: np.ndarray | None
    valid: np.ndarray
    a: Any
    b: Any
    c: Any
    d: Any
    omega1: Any
    eps1: Any
    branch: int

    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "theta3": "rad", "theta4": "rad",
        "omega3": "rad/s", "omega4": "rad/s", "eps3": "rad/s^2", "eps4": "rad/s^2",
        "xA": "m", "yA": "m", "xB": "m", "yB": "m", "xP": "m", "yP": "m", "valid": "",
        "a": "m", "b": "m", "c": "m", "d": "m", "omega1": "rad/s", "eps1": "rad/s^2",
        "branch": "", "transmission_angle": "rad",
    }
    position_field: ClassVar[str] = "phi1"
    assembled = renamed_attribute("valid", "assembled")
    theta2 = renamed_attribute("phi1", "theta2")
    omega2 = renamed_attribute("omega1", "omega2")
    alpha2 = renamed_attribute("eps1", "alpha2")
    alpha3 = renamed_attribute("eps3", "alpha3")
    alpha4 = renamed_attribute("eps4", "alpha4")

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Draw the linkage and the path of B (and P): a :class:`linkwork.plot.Figure` with one
        axes (:func:`linkwork.plot.fourbar.plot_fourbar_linkage`)."""
        from linkwork.plot.fourbar import fourbar_figure

        return fourbar_figure(self, ax=ax, **kw)

    @property
    def transmission_angle(self) -> np.ndarray:
        """Angle ABO4 between the coupler and the rocker at B, in [0, pi] [rad]."""
        ux, uy = self.xA - self.xB, self.yA - self.yB
        vx, vy = self.d - self.xB, -self.yB
        cos_mu = (ux * vx + uy * vy) / (self.b * self.c)
        return np.asarray(np.arccos(np.clip(cos_mu, -1.0, 1.0)))

    def point(self, link: str, p: ArrayLike, q: ArrayLike = 0.0) -> tuple[np.ndarray, ...]:
        """Position, velocity and acceleration of a point fixed on a link.

        Parameters
        ----------
        link : {"crank", "coupler", "rocker"}
            The link carrying the point.
        p, q : float or array_like
            Coordinates of the point in the link's own frame [m]: origin at the link's first
            joint (O2 for the crank, A for the coupler, O4 for the rocker), x axis along the
            link (O2 -> A, A -> B, O4 -> B), y axis 90 deg counter-clockwise from it.

        Returns
        -------
        x, y, vx, vy, ax, ay : ndarray
            Position [m], velocity [m/s] and acceleration [m/s^2] in the frame axes.
        """
        p_ = np.asarray(p, dtype=float)
        q_ = np.asarray(q, dtype=float)
        w2, e2 = self.omega1, self.eps1
        ox: Any
        oy: Any
        ovx: Any
        ovy: Any
        oax: Any
        oay: Any
        if link == "crank":
            ex, ey = self.xA / self.a, self.yA / self.a
            ox, oy, ovx, ovy, oax, oay = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            w, e = w2, e2
        elif link == "coupler":
            ex, ey = (self.xB - self.xA) / self.b, (self.yB - self.yA) / self.b
            ox, oy = self.xA, self.yA
            ovx, ovy = -w2 * self.yA, w2 * self.xA
            oax = -e2 * self.yA - w2 * w2 * self.xA
            oay = e2 * self.xA - w2 * w2 * self.yA
            w, e = self.omega3, self.eps3
        elif link == "rocker":
            ex, ey = (self.xB - self.d) / self.c, self.yB / self.c
            ox, oy, ovx, ovy, oax, oay = self.d, 0.0, 0.0, 0.0, 0.0, 0.0
            w, e = self.omega4, self.eps4
        else:
            raise ParameterError("link", link, "must be 'crank', 'coupler' or 'rocker'")
        rx = p_ * ex - q_ * ey
        ry = p_ * ey + q_ * ex
        x, y = ox + rx, oy + ry
        vx, vy = ovx - w * ry, ovy + w * rx
        ax = oax - e * ry - w * w * rx
        ay = oay + e * rx - w * w * ry
        return tuple(np.asarray(t) for t in (x, y, vx, vy, ax, ay))


def _fail(phi1: Any, ok: np.ndarray, a: Any, b: Any, c: Any, d: Any,
          singular: bool = False) -> AssemblyError:
    t = np.asarray(phi1, dtype=float)
    bad = ~ok
    if t.ndim == 0:
        ranges = [(float(t), float(t))]
    elif t.ndim == 1:
        ranges = angle_ranges(t, bad)
    else:  # angles given per design: runs in the flattened order
        tb, mb = np.broadcast_arrays(t, bad)
        ranges = angle_ranges(tb.ravel(), mb.ravel())
    what = ("four-bar is at a singular position (coupler and rocker collinear, or A on O4): "
            "velocities and accelerations are unbounded" if singular else
            "four-bar cannot be assembled: |A O4| leaves [|b - c|, b + c]")
    return AssemblyError(
        f"{what} (a={_show(a)}, b={_show(b)}, c={_show(c)}, d={_show(d)} m)",
        ranges,
        driver="phi1",
    )


def _show(x: Any) -> str:
    arr = np.asarray(x)
    return f"{float(arr):.6g}" if arr.size == 1 else f"array{arr.shape}"


@renamed_keywords(theta2="phi1", omega2="omega1", alpha2="eps1", on_fail="on_failure")
def fourbar(phi1: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike,
            omega1: ArrayLike = 1.0, eps1: ArrayLike = 0.0, branch: int = +1, *,
            coupler_point: tuple[ArrayLike, ArrayLike] | None = None,
            on_failure: str = "raise") -> FourbarResult:
    r"""Closed-form position, velocity and acceleration analysis of a four-bar linkage.

    Parameters
    ----------
    phi1 : array_like
        Crank angle(s) [rad], counter-clockwise from the frame line O2 -> O4; shape ``(n,)``.
    a, b, c, d : float or array_like
        Crank O2A, coupler AB, rocker O4B and frame O2O4 lengths [m], > 0.  Arrays broadcast
        against ``phi1`` (designs of shape ``(m, 1)`` against angles of shape ``(n,)``).
    omega1 : float or array_like, optional
        Crank angular velocity [rad/s], counter-clockwise positive (default 1).
    eps1 : float or array_like, optional
        Crank angular acceleration [rad/s^2] (default 0).
    branch : {+1, -1}, optional
        Assembly branch: +1 puts B on the left of the directed line from A to O4, -1 on the right.
    coupler_point : (p, q), optional
        A coupler point P in the coupler's frame [m]: ``P = A + p e3 + q e3_perp`` with ``e3``
        the unit vector A -> B and ``e3_perp`` it turned 90 deg counter-clockwise.
    on_failure : {"raise", "nan"}, optional
        What to do at crank angles where the linkage cannot be assembled: raise
        :class:`~linkwork.errors.AssemblyError` listing the crank-angle ranges (default), or
        return NaN there with ``result.valid`` False.

    Returns
    -------
    FourbarResult
        ``theta3``, ``theta4``, ``omega3``, ``omega4``, ``eps3``, ``eps4``, points A, B (P).

    Notes
    -----
    With ``A = a (cos phi1, sin phi1)``, ``O4 = (d, 0)``, ``s = O4 - A`` and ``f = |s|``,
    B is the intersection of the circles (A, b) and (O4, c):

    .. math::

        B = A + k\,s + \beta\,h\,s_\perp, \qquad
        k = \frac{b^2 - c^2 + f^2}{2 f^2}, \qquad h = \sqrt{b^2/f^2 - k^2},

    with :math:`s_\perp` the vector ``s`` turned 90 deg counter-clockwise and
    :math:`\beta` = ``branch``.  With ``u = B - A`` (= b e3) and ``v = B - O4`` (= c e4), the
    loop-closure derivatives ``omega1 jA + omega3 ju - omega4 jv = 0`` give

    .. math::

        \omega_3 = -\omega_2 \frac{A \times v}{u \times v}, \qquad
        \omega_4 = -\omega_2 \frac{A \times u}{u \times v}, \qquad
        \alpha_3 = -\frac{K \times v}{u \times v}, \qquad
        \alpha_4 = -\frac{K \times u}{u \times v},

    where :math:`K = \alpha_2 A + j(\omega_2^2 A + \omega_3^2 u - \omega_4^2 v)`, ``j`` turns a
    vector 90 deg counter-clockwise and ``x`` is the planar cross product.  They are the same
    as Norton's Eqs. (6.18) and (7.12) [1]_, written without trigonometric functions of
    theta3 and theta4.  Exactly at a toggle (``u x v = 0``) or with A on O4 the rates are
    unbounded: such positions count as not assembled (AssemblyError, or NaN with ``valid``
    False), as in the planar engine; close to a toggle they are large but finite.  Long
    position arrays (>= 16384) are evaluated in blocks of 8192 positions so
    that the temporaries stay in the cache; the numbers are the same.

    Raises
    ------
    ParameterError
        A length is not finite and > 0, ``branch`` is not +1/-1, or ``on_failure`` is unknown.
    AssemblyError
        The linkage cannot be assembled at some crank angles (``on_failure="raise"``).
    """
    # Each argument is checked once, by the named checks of linkwork.checks; for the common call
    # (one design in Python numbers, a float64 array of angles) they cost plain comparisons and
    # keep Python floats for the kernel (a 0-d array costs ~0.5 us per arithmetic operation).
    a_ = positive_value("a", a)
    b_ = positive_value("b", b)
    c_ = positive_value("c", c)
    d_ = positive_value("d", d)
    w2 = finite_value("omega1", omega1)
    e2 = finite_value("eps1", eps1)
    br = require_branch(branch)
    if on_failure not in ("raise", "nan"):
        raise ParameterError("on_failure", on_failure, "must be 'raise' or 'nan'")
    # a finite float array as is; anything else by the named check (None was NaN, a complex
    # angle lost its imaginary part, True was 1 rad, inf made np.cos warn)
    t2 = phi1 if (type(phi1) is np.ndarray and phi1.dtype is _F64
                    and all_finite(phi1)) else require_finite("phi1", phi1)
    if coupler_point is not None:
        p = finite_value("coupler_point[0]", coupler_point[0])
        q = finite_value("coupler_point[1]", coupler_point[1])
    else:
        p = q = None
    n = t2.shape[-1] if t2.ndim else 1
    try:
        if n >= 2 * _CHUNK:
            res = _chunked(t2, a_, b_, c_, d_, w2, e2, br, p, q)
        else:
            res = _kernel(t2, a_, b_, c_, d_, w2, e2, br, p, q)
    except ValueError as exc:  # operands that do not broadcast (no cost when they do)
        shapes = {k: np.shape(v) for k, v in (("phi1", t2), ("a", a_), ("b", b_), ("c", c_),
                                               ("d", d_), ("omega1", w2), ("eps1", e2))}
        raise shapes_error(shapes) from exc
    th3, th4, w3, w4, al3, al4, ax, ay, xb, yb, xp, yp, ok, clean = res
    if not clean:
        # exactly at a toggle (u x v = 0) or with A on O4 the position "assembles" but the
        # rates divide by zero: never report such non-finite values as assembled
        sing = ok & ~(np.isfinite(w3) & np.isfinite(w4) & np.isfinite(al3)
                      & np.isfinite(al4) & np.isfinite(th3))
        if sing.any():
            ok = ok & ~sing
            if on_failure == "nan":
                th3, th4, w3, w4, al3, al4, xb, yb = (
                    np.where(sing, np.nan, x) for x in (th3, th4, w3, w4, al3, al4, xb, yb))
                if xp is not None:
                    xp, yp = np.where(sing, np.nan, xp), np.where(sing, np.nan, yp)
        if not ok.all() and on_failure == "raise":
            if sing.any():
                raise _fail(t2, ~sing, a_, b_, c_, d_, singular=True)
            raise _fail(t2, ok, a_, b_, c_, d_)
    return _result(t2, (th3, th4, w3, w4, al3, al4, ax, ay, xb, yb, xp, yp, ok), a_, b_, c_,
                   d_, w2, e2, br)


def _result(t2: Any, res: tuple[Any, ...], a_: Any, b_: Any, c_: Any, d_: Any, w2: Any,
            e2: Any, br: Any) -> FourbarResult:
    th3, th4, w3, w4, al3, al4, ax, ay, xb, yb, xp, yp, ok = res[:13]
    return FourbarResult._assemble({
        "phi1": t2, "theta3": th3, "theta4": th4, "omega3": w3, "omega4": w4, "eps3": al3,
        "eps4": al4, "xA": ax, "yA": ay, "xB": xb, "yB": yb, "xP": xp, "yP": yp,
        "valid": ok, "a": a_, "b": b_, "c": c_, "d": d_, "omega1": w2, "eps1": e2,
        "branch": int(br)})


#: Positions per block of the blocked evaluation of :func:`fourbar` (temporaries stay in cache
#: and are not re-faulted from the OS at every operation, which costs ~3x at 100,000 positions).
_CHUNK = 8192


def _chunked(t2: np.ndarray, a_: Any, b_: Any, c_: Any, d_: Any, w2: Any, e2: Any, br: float,
             p: Any, q: Any) -> tuple[Any, ...]:
    """Evaluate :func:`_kernel` block by block along the last (positions) axis."""
    args = (t2, a_, b_, c_, d_, w2, e2, p, q)
    shape = np.broadcast_shapes(*(np.shape(x) for x in args if x is not None))
    n = shape[-1]
    outs: list[Any] = [np.empty(shape) for _ in range(12 if p is not None else 10)]
    if p is None:
        outs += [None, None]
    outs.append(np.empty(shape, dtype=bool))
    clean = True
    for lo in range(0, n, _CHUNK):
        sl = slice(lo, min(lo + _CHUNK, n))
        res = _kernel(_part(t2, sl), _part(a_, sl), _part(b_, sl), _part(c_, sl),
                      _part(d_, sl), _part(w2, sl), _part(e2, sl), br, _part(p, sl),
                      _part(q, sl))
        for dst, src in zip(outs, res[:13], strict=True):
            if dst is not None:
                dst[..., sl] = src
        clean = clean and res[13]
    return (*outs, clean)


def _kernel(t2: np.ndarray, a_: Any, b_: Any, c_: Any, d_: Any, w2: Any, e2: Any, br: float,
            p: Any, q: Any) -> tuple[Any, ...]:
    """The closed form itself.

    Returns the 13 results and ``clean``: True when every position assembles away from a toggle
    (then no division by zero or square root of a negative number can occur, and the floating
    point error state need not be touched).
    """
    ax = a_ * np.cos(t2)
    ay = a_ * np.sin(t2)
    sx = d_ - ax          # s = O4 - A = (sx, -ay)
    f2 = sx * sx + ay * ay
    bb = b_ * b_
    qq = f2 + (bb - c_ * c_)
    # H = 4 f^4 (b^2/f^2 - k^2) = 16 (area of the triangle b, c, f)^2; assembles iff H >= 0
    hh = f2 * (4.0 * bb) - qq * qq
    if hh.size and _min(hh, axis=None) > 0.0:  # the usual case: one reduction, no mask
        return (*_kernel_tail(ax, ay, sx, f2, qq, hh, b_, d_, w2, e2, br, p, q),
                all_true(np.shape(hh)), True)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        res = _kernel_tail(ax, ay, sx, f2, qq, hh, b_, d_, w2, e2, br, p, q)
    return (*res, hh >= 0.0, False)  # (NaN is not >= 0)


def _kernel_tail(ax: Any, ay: Any, sx: Any, f2: Any, qq: Any, hh: Any, b_: Any,
                 d_: Any, w2: Any, e2: Any, br: float, p: Any, q: Any) -> tuple[Any, ...]:
    inv = 0.5 / f2
    k = qq * inv
    root = np.sqrt(hh)
    h = root * inv if br > 0.0 else root * -inv
    ux = k * sx + h * ay  # u = B - A = k s + h s_perp, s = (sx, -ay), s_perp = (ay, sx)
    uy = h * sx - k * ay
    vx = ux - sx          # v = B - O4 = u - s
    vy = uy + ay
    # omega: n3 = -(A x v), n4 = -(A x u); A x v = A x u - A x s and A x s = d ay
    n4 = ux * ay - uy * ax
    n3 = n4 - d_ * ay
    den = root * (0.5 * br)          # u x v = h f^2
    rden = w2 / den
    w3 = n3 * rden
    w4 = n4 * rden
    # alpha: with K = eps1 A + jG, G = omega1^2 A + omega3^2 u - omega4^2 v,
    # -(K x v) = G.v + eps1 n3 and -(K x u) = G.u + eps1 n4
    w22 = w2 * w2
    w33 = w3 * w3
    w44 = w4 * w4
    gx = w22 * ax + w33 * ux - w44 * vx
    gy = w22 * ay + w33 * uy - w44 * vy
    num3 = gx * vx + gy * vy
    num4 = gx * ux + gy * uy
    if type(e2) is not float or e2 != 0.0:
        num3 = num3 + e2 * n3  # (not in place: eps1 may broadcast to more designs)
        num4 = num4 + e2 * n4
    xp = yp = None
    if p is not None:
        xp = ax + (p * ux - q * uy) / b_
        yp = ay + (p * uy + q * ux) / b_
    return (np.arctan2(uy, ux), np.arctan2(vy, vx), w3, w4, num3 / den, num4 / den, ax, ay,
            vx + d_, vy, xp, yp)


# ---------------------------------------------------------------------------------------------
# Grashof type, limit positions, transmission angle
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class GrashofType:
    """Grashof classification of a four-bar (Norton [1]_, Sec. 2.12).

    Attributes
    ----------
    grashof_class : str or ndarray of str
        ``"I"`` (S + L < P + Q, Grashof), ``"II"`` (S + L > P + Q, non-Grashof) or ``"III"``
        (S + L = P + Q within ``rtol``, special Grashof).
    motion : str or ndarray of str
        With the crank ``a`` as input: ``"crank-rocker"`` (shortest link is the crank),
        ``"rocker-crank"`` (shortest is the rocker: the input rocks, the output turns fully),
        ``"double-crank"`` (shortest is the frame), ``"double-rocker"`` (Grashof, shortest is
        the coupler), ``"triple-rocker"`` (class II) or ``"change-point"`` (class III).
    crank_rotates, rocker_rotates : bool or ndarray of bool
        Whether the crank (the rocker) can make full turns relative to the frame, from the
        assembly condition over a whole turn (includes class III).
    s, l, p, q : float or ndarray
        Shortest, longest and the two other lengths [m].
    """

    grashof_class: Any
    motion: Any
    crank_rotates: Any
    rocker_rotates: Any
    s: Any
    l: Any
    p: Any
    q: Any


def grashof(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike,
            rtol: float = 1e-12) -> GrashofType:
    """Grashof class and motion type of the four-bar (a crank, b coupler, c rocker, d frame).

    Parameters
    ----------
    a, b, c, d : float or array_like
        Link lengths [m], > 0; arrays broadcast (one classification per design).
    rtol : float, optional
        Relative tolerance (on the longest link) within which S + L = P + Q counts as class III.

    Returns
    -------
    GrashofType
        Scalars (``str``, ``bool``, ``float``) for scalar input, arrays otherwise.

    Notes
    -----
    Grashof's condition: with S the shortest, L the longest and P, Q the other links, some link
    can turn fully relative to another iff S + L <= P + Q.  Which one depends on where the
    shortest link is (Norton [1]_, Table 2-4).
    """
    arrs = np.broadcast_arrays(*(require_positive(n, x) for n, x in zip("abcd", (a, b, c, d),
                                                                 strict=True)))
    lengths = np.stack(arrs, axis=-1)
    srt = np.sort(lengths, axis=-1)
    s, p, q, lo = srt[..., 0], srt[..., 1], srt[..., 2], srt[..., 3]
    diff = s + lo - (p + q)
    tol = rtol * lo
    cls = np.where(diff < -tol, "I", np.where(diff > tol, "II", "III"))
    shortest = np.argmin(lengths, axis=-1)  # 0 crank, 1 coupler, 2 rocker, 3 frame
    names = np.array(["crank-rocker", "double-rocker", "rocker-crank", "double-crank"])
    motion = np.where(cls == "I", names[shortest],
                      np.where(cls == "II", "triple-rocker", "change-point"))
    aa, bb, cc, dd = arrs
    slack = tol
    crank_rotates = (aa + dd <= bb + cc + slack) & (np.abs(dd - aa) + slack >= np.abs(bb - cc))
    rocker_rotates = (cc + dd <= aa + bb + slack) & (np.abs(dd - cc) + slack >= np.abs(aa - bb))

    def out(x: np.ndarray) -> Any:
        return x.item() if x.ndim == 0 else x

    return GrashofType(out(cls), out(motion), out(crank_rotates), out(rocker_rotates),
                       out(s), out(lo), out(p), out(q))



@dataclass(frozen=True)
class FourbarLimits:
    """Limit (toggle) positions of a four-bar.

    Attributes
    ----------
    phi1_toggle_extended, phi1_toggle_folded : ndarray
        Crank angles in [0, pi] at which coupler and rocker are collinear, extended
        (``|AO4| = b + c``) or folded (``|AO4| = |b - c|``) [rad]; the mirror angles ``-theta``
        are toggles too.  These are the limit positions of the INPUT (transmission angle 180 or
        0 deg; the crank cannot pass them).  NaN where that toggle does not exist (e.g. for a
        crank that turns fully).
    phi1_rocker_extended, theta4_rocker_extended : ndarray
        Crank and rocker angles [rad] where crank and coupler are collinear and extended
        (``|O2B| = a + b``) on the chosen branch: a limit position of the rocker (omega4 = 0).
    phi1_rocker_folded, theta4_rocker_folded : ndarray
        The same with crank and coupler overlapping (``|O2B| = |a - b|``).
    rocker_swing : ndarray
        ``|theta4_rocker_extended - theta4_rocker_folded|`` wrapped to [0, pi] [rad].
    time_ratio : ndarray
        For a turning crank (omega1 > 0): crank angle from the folded to the extended limit,
        divided by the angle from the extended back to the folded one (Norton's time ratio).
    branch : int
        Assembly branch used for the rocker limits.
    """

    phi1_toggle_extended: Any
    phi1_toggle_folded: Any
    phi1_rocker_extended: Any
    theta4_rocker_extended: Any
    phi1_rocker_folded: Any
    theta4_rocker_folded: Any
    rocker_swing: Any
    time_ratio: Any
    branch: int

    theta2_toggle_extended = renamed_attribute("phi1_toggle_extended", "theta2_toggle_extended")
    theta2_toggle_folded = renamed_attribute("phi1_toggle_folded", "theta2_toggle_folded")
    theta2_rocker_extended = renamed_attribute("phi1_rocker_extended", "theta2_rocker_extended")
    theta2_rocker_folded = renamed_attribute("phi1_rocker_folded", "theta2_rocker_folded")


def limit_positions(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike,
                    branch: int = +1) -> FourbarLimits:
    """Limit (toggle) positions of the input and of the rocker.

    Parameters
    ----------
    a, b, c, d : float or array_like
        Crank, coupler, rocker, frame lengths [m] (broadcast).
    branch : {+1, -1}
        Assembly branch (see :func:`fourbar`) for the rocker limit positions.

    Returns
    -------
    FourbarLimits

    Notes
    -----
    Input toggles: ``|AO4|^2 = a^2 + d^2 - 2ad cos phi1 = (b +- c)^2``.  Rocker limits
    (omega4 = 0, i.e. crank and coupler collinear): B is the intersection of the circles
    (O2, a + b) or (O2, |a - b|) and (O4, c) lying on the requested branch.
    """
    br = require_branch(branch)
    aa, bb, cc, dd = np.broadcast_arrays(*(require_positive(n, x)
                                           for n, x in zip("abcd", (a, b, c, d), strict=True)))

    def crank_at(f: np.ndarray) -> np.ndarray:
        cos_t = (aa * aa + dd * dd - f * f) / (2.0 * aa * dd)
        with np.errstate(invalid="ignore"):
            return np.where(np.abs(cos_t) <= 1.0 + 1e-12, np.arccos(np.clip(cos_t, -1, 1)),
                            np.nan)

    tog_ext = crank_at(bb + cc)
    tog_fold = crank_at(np.abs(bb - cc))

    def rocker_limit(g: np.ndarray, sgn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # B on circle (O2, g) and (O4, c); A = sgn * a * B / g  (sgn=-1: B on the other side)
        xb = (g * g - cc * cc + dd * dd) / (2.0 * dd)
        with np.errstate(invalid="ignore"):
            yb0 = np.sqrt(g * g - xb * xb)
        best_t2 = np.full(xb.shape, np.nan)
        best_t4 = np.full(xb.shape, np.nan)
        for yb in (yb0, -yb0):
            with np.errstate(invalid="ignore", divide="ignore"):
                xa = sgn * aa * xb / g
                ya = sgn * aa * yb / g
                cross = (dd - xa) * (yb - ya) - (0.0 - ya) * (xb - xa)
                hit = np.sign(cross) == br
            best_t2 = np.where(hit, np.arctan2(ya, xa), best_t2)
            best_t4 = np.where(hit, np.arctan2(yb, xb - dd), best_t4)
        return best_t2, best_t4

    one = np.ones_like(aa)
    t2e, t4e = rocker_limit(aa + bb, one)
    t2f, t4f = rocker_limit(np.abs(aa - bb), np.where(bb >= aa, -one, one))
    swing = np.abs(np.angle(np.exp(1j * (t4e - t4f))))
    fwd = np.mod(t2e - t2f, _TWO_PI)
    with np.errstate(invalid="ignore", divide="ignore"):
        tr = fwd / (_TWO_PI - fwd)

    def out(x: np.ndarray) -> Any:
        return float(x) if x.ndim == 0 else x

    return FourbarLimits(out(tog_ext), out(tog_fold), out(t2e), out(t4e), out(t2f), out(t4f),
                         out(swing), out(tr), int(br))


@renamed_keywords(theta2="phi1")
def transmission_angle(phi1: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike,
                       d: ArrayLike, acute: bool = False) -> np.ndarray:
    r"""Transmission angle mu, the angle ABO4 between coupler and rocker [rad].

    .. math:: \cos\mu = \frac{b^2 + c^2 - a^2 - d^2 + 2ad\cos\theta_2}{2bc}

    It does not depend on the branch.  ``acute=True`` returns ``min(mu, pi - mu)`` (Norton's
    convention of reporting the acute angle).  NaN where the linkage cannot be assembled.
    """
    t2 = require_finite("phi1", phi1)
    aa, bb, cc, dd = (require_positive(n, x) for n, x in zip("abcd", (a, b, c, d), strict=True))
    cos_mu = (bb * bb + cc * cc - aa * aa - dd * dd + 2.0 * aa * dd * np.cos(t2)) / (2 * bb * cc)
    with np.errstate(invalid="ignore"):
        mu = np.where(np.abs(cos_mu) <= 1.0 + 1e-12, np.arccos(np.clip(cos_mu, -1, 1)), np.nan)
    return np.minimum(mu, np.pi - mu) if acute else mu


@dataclass(frozen=True)
class TransmissionExtremes:
    """Extremes of the transmission angle over the crank's range of motion.

    Attributes
    ----------
    mu_min, mu_max : float or ndarray
        Smallest and largest transmission angle [rad] (0 or pi at an input toggle).
    phi1_at_min, phi1_at_max : float or ndarray
        Crank angles in [0, pi] where they occur [rad] (also at their negatives).
    max_deviation : float or ndarray
        ``max(|mu - pi/2|)`` over the motion [rad]; small is good.
    """

    mu_min: Any
    mu_max: Any
    phi1_at_min: Any
    phi1_at_max: Any
    max_deviation: Any

    theta2_at_min = renamed_attribute("phi1_at_min", "theta2_at_min")
    theta2_at_max = renamed_attribute("phi1_at_max", "theta2_at_max")


def transmission_angle_extremes(a: ArrayLike, b: ArrayLike, c: ArrayLike,
                                d: ArrayLike) -> TransmissionExtremes:
    """Extremes of the transmission angle over all crank angles where the linkage assembles.

    ``mu`` grows with ``f = |AO4|``, which runs over ``[|d - a|, d + a]`` as the crank turns;
    clipped to the assembly interval ``[|b - c|, b + c]``.

    Raises
    ------
    AssemblyError
        The linkage cannot be assembled at any crank angle.
    """
    aa, bb, cc, dd = np.broadcast_arrays(*(require_positive(n, x)
                                           for n, x in zip("abcd", (a, b, c, d), strict=True)))
    fmin = np.maximum(np.abs(dd - aa), np.abs(bb - cc))
    fmax = np.minimum(dd + aa, bb + cc)
    bad = fmin > fmax
    if bad.any():
        i = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise AssemblyError(
            "four-bar cannot be assembled at any crank angle: |A O4| runs over [|d - a|, d + a] "
            f"= [{abs(dd[i] - aa[i]):.6g}, {dd[i] + aa[i]:.6g}], which does not meet "
            f"[|b - c|, b + c] = [{abs(bb[i] - cc[i]):.6g}, {bb[i] + cc[i]:.6g}] "
            f"(a={aa[i]:.6g}, b={bb[i]:.6g}, c={cc[i]:.6g}, d={dd[i]:.6g} m)")

    def mu(f: np.ndarray) -> np.ndarray:
        return np.arccos(np.clip((bb * bb + cc * cc - f * f) / (2 * bb * cc), -1.0, 1.0))

    def t2(f: np.ndarray) -> np.ndarray:
        return np.arccos(np.clip((aa * aa + dd * dd - f * f) / (2 * aa * dd), -1.0, 1.0))

    mn, mx = mu(fmin), mu(fmax)
    dev = np.maximum(np.abs(mn - np.pi / 2), np.abs(mx - np.pi / 2))

    def out(x: np.ndarray) -> Any:
        return float(x) if x.ndim == 0 else x

    return TransmissionExtremes(out(mn), out(mx), out(t2(fmin)), out(t2(fmax)), out(dev))


# ---------------------------------------------------------------------------------------------
# kinetostatics
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FourbarForces(Result):
    """Joint reactions and driving moment of a four-bar (inverse dynamics, closed form).

    Sign convention: ``R_X`` is the force that one link exerts on the next at joint X, in the
    frame axes [N], following paper 004 [2]_:

    * ``R_O`` at O2: frame on crank (Norton's F12),
    * ``R_A`` at A: crank on coupler (Norton's F23 = -F32),
    * ``R_B`` at B: coupler on rocker (Norton's F34 = -F43),
    * ``R_C`` at O4: frame on rocker (Norton's F14).

    ``Q`` is the driving (balancing) moment the frame's motor applies to the crank [N m],
    counter-clockwise positive (Norton's T12).  ``shaking_force`` is the force of the moving
    links on the frame ``-(R_O + R_C)`` [N]; ``shaking_moment`` their moment on the frame about
    O2 ``-Q - d R_C^y`` [N m].
    """

    phi1: np.ndarray
    R_Ox: np.ndarray
    R_Oy: np.ndarray
    R_Ax: np.ndarray
    R_Ay: np.ndarray
    R_Bx: np.ndarray
    R_By: np.ndarray
    R_Cx: np.ndarray
    R_Cy: np.ndarray
    Q: np.ndarray
    shaking_force_x: np.ndarray
    shaking_force_y: np.ndarray
    shaking_moment: np.ndarray
    kinematics: FourbarResult

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Joint reactions and driving moment over phi1: a :class:`linkwork.plot.Figure` with
        two axes (:func:`linkwork.plot.fourbar.plot_fourbar_forces`)."""
        from linkwork.plot.fourbar import fourbar_forces_figure

        return fourbar_forces_figure(self, axes=axes, **kw)

    units: ClassVar[dict[str, str]] = {
        "phi1": "rad", "R_Ox": "N", "R_Oy": "N", "R_Ax": "N", "R_Ay": "N", "R_Bx": "N",
        "R_By": "N", "R_Cx": "N", "R_Cy": "N", "Q": "N*m", "shaking_force_x": "N",
        "shaking_force_y": "N", "shaking_moment": "N*m",
    }
    position_field: ClassVar[str] = "phi1"
    theta2 = renamed_attribute("phi1", "theta2")


def _triple(name: str, x: Any, default: Any) -> tuple[Any, Any, Any]:
    if x is None:
        return default
    if len(x) != 3:
        raise ParameterError(name, x, "must give 3 values: (crank, coupler, rocker)")
    return (x[0], x[1], x[2])



def _local_point(name: str, x: Any) -> tuple[Any, Any]:
    """A point in a link's frame: a pair (p, q), or a float p meaning (p, 0)."""
    if isinstance(x, int | float | np.floating | np.integer) or (
            isinstance(x, np.ndarray) and x.ndim == 0):
        return finite_value(name, float(x)), 0.0
    return require_pair(name, x)


@renamed_keywords(theta2="phi1", omega2="omega1", alpha2="eps1", on_fail="on_failure")
def fourbar_kinetostatics(
    phi1: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike,
    omega1: ArrayLike = 1.0, eps1: ArrayLike = 0.0, branch: int = +1, *,
    mass: tuple[ArrayLike, ArrayLike, ArrayLike] = (0.0, 0.0, 0.0),
    inertia: tuple[ArrayLike | None, ArrayLike | None, ArrayLike | None] = (None, None, None),
    com: tuple[Any, Any, Any] | None = None,
    gravity: tuple[ArrayLike, ArrayLike] = (0.0, 0.0),
    force: tuple[tuple[ArrayLike, ArrayLike], ...] | None = None,
    force_point: tuple[Any, Any, Any] | None = None,
    moment: tuple[ArrayLike, ArrayLike, ArrayLike] = (0.0, 0.0, 0.0),
    on_failure: str = "raise",
) -> FourbarForces:
    r"""Joint reactions and driving moment of a four-bar, in closed form (inverse dynamics).

    Every tuple below is ``(crank, coupler, rocker)`` = Norton's links 2, 3, 4 = paper 004's
    links 1, 2, 3.  Each value may be a scalar or an array broadcasting against ``phi1``
    (e.g. a technological force given per position).

    Parameters
    ----------
    phi1, a, b, c, d, omega1, eps1, branch
        As in :func:`fourbar`.
    mass : 3 floats, optional
        Link masses [kg] (default 0).
    inertia : 3 floats or None, optional
        Centroidal moments of inertia [kg m^2]; ``None`` (the default) is a thin uniform rod,
        ``m l^2 / 12`` with the link's length l (as :func:`linkwork.planar.fourbar`); give 0
        for none.
    com : 3 pairs (p, q) or 3 floats, optional
        Centre of mass of each link in its own frame [m] (see :meth:`FourbarResult.point`:
        origin at O2, A, O4; x along O2 -> A, A -> B, O4 -> B); a float p means ``(p, 0)``, a
        point on the link's line at distance p from its first joint.  Default: link midpoints
        ``(a/2, 0), (b/2, 0), (c/2, 0)`` as in paper 004.
    gravity : (gx, gy), optional
        Gravitational acceleration in the frame axes [m/s^2]; default ``(0, 0)`` (off); e.g.
        ``(0, -9.81)`` when the frame line is horizontal and y points up.
    force : 3 pairs (Fx, Fy), optional
        External force on each link, in the frame axes [N] (default none).
    force_point : 3 pairs (p, q) or 3 floats, optional
        Point of application of each external force, in the link's own frame [m] (a float p
        means ``(p, 0)``); default: the centre of mass.
    moment : 3 floats, optional
        External moment (couple) on each link [N m], counter-clockwise positive.
    on_failure : {"raise", "nan"}
        As in :func:`fourbar`.

    Returns
    -------
    FourbarForces
        Reactions ``R_O, R_A, R_B, R_C`` (sign convention in :class:`FourbarForces`), driving
        moment ``Q``, shaking force and moment, and the kinematics.

    Notes
    -----
    With d'Alembert's principle, link i carries the resultant force
    :math:`\Phi_i = F_i + m_i(g - a_{S_i})` and, about its reference joint (O2, A, O4), the
    moment :math:`T_i = r_{S_i}\times m_i(g - a_{S_i}) + \rho_i \times F_i + M_i - J_i\alpha_i`.
    Moments about A on the coupler and about O4 on the rocker give, with ``u = B - A``,
    ``v = B - O4``,

    .. math::

        R_B = \frac{T_3\,v + T_4\,u}{u \times v}, \quad R_C = -\Phi_4 - R_B, \quad
        R_A = R_B - \Phi_3, \quad R_O = R_A - \Phi_2, \quad Q = A \times R_A - T_2 .

    These are Eqs. (8)-(13) of paper 004 [2]_ generalised to any centre of mass and external
    load; the paper's printed (9) and (13) contain errors (``docs/errata.md``).
    """
    kin = fourbar(phi1, a, b, c, d, omega1, eps1, branch, on_failure=on_failure)
    m2, m3, m4 = (finite_value(f"mass[{i}]", x) for i, x in enumerate(_triple("mass", mass, None)))
    lengths = (kin.a, kin.b, kin.c)
    j2, j3, j4 = (finite_value(f"inertia[{i}]", x) if x is not None
                  else (m2, m3, m4)[i] * lengths[i] * lengths[i] / 12.0
                  for i, x in enumerate(_triple("inertia", inertia, None)))
    for nm, mm in (("mass", (m2, m3, m4)), ("inertia", (j2, j3, j4))):
        for i, x in enumerate(mm):
            if np.any(np.asarray(x) < 0):
                raise ParameterError(f"{nm}[{i}]", np.min(x), "must be >= 0")
    com_ = _triple("com", com, ((kin.a / 2, 0.0), (kin.b / 2, 0.0), (kin.c / 2, 0.0)))
    coms = [_local_point(f"com[{i}]", x) for i, x in enumerate(com_)]
    frc = [require_pair(f"force[{i}]", x)
           for i, x in enumerate(_triple("force", force, ((0.0, 0.0),) * 3))]
    fpt_ = _triple("force_point", force_point, com_)
    fpts = [_local_point(f"force_point[{i}]", x) for i, x in enumerate(fpt_)]
    mom = [finite_value(f"moment[{i}]", x) for i, x in enumerate(_triple("moment", moment, None))]
    gx, gy = require_pair("gravity", gravity)

    k = kin
    flat_loads = (m2, m3, m4, j2, j3, j4, *coms[0], *coms[1], *coms[2], *fpts[0], *fpts[1],
                  *fpts[2], *frc[0], *frc[1], *frc[2], *mom, gx, gy)
    kin_arrays = (k.xA, k.yA, k.xB, k.yB, k.omega3, k.omega4, k.eps3, k.eps4, k.a, k.b, k.c,
                  k.d, k.omega1, k.eps1)
    try:
        shape = np.broadcast_shapes(*(np.shape(x) for x in (*kin_arrays, *flat_loads)
                                      if type(x) is not float))
    except ValueError:  # a load array that does not fit the positions: name it
        names = [f"{k}[{i}]" for k in ("mass", "inertia") for i in range(3)]
        names += [f"{k}[{i}][{c}]" for k in ("com", "force_point", "force") for i in range(3)
                  for c in range(2)]
        names += [f"moment[{i}]" for i in range(3)] + ["gravity[0]", "gravity[1]"]
        shapes = {"positions": np.shape(k.xA)}
        shapes.update((nm, np.shape(x)) for nm, x in zip(names, flat_loads, strict=True)
                      if np.ndim(x))
        raise shapes_error(shapes) from None
    n = shape[-1] if shape else 1
    if n >= 2 * _CHUNK:   # blocks keep the temporaries in the cache (see fourbar())
        outs = [np.empty(shape) for _ in range(12)]
        for lo in range(0, n, _CHUNK):
            sl = slice(lo, min(lo + _CHUNK, n))
            vals = _reactions(*(_part(x, sl) for x in kin_arrays),
                              *(_part(x, sl) for x in flat_loads))
            for o, v in zip(outs, vals, strict=True):
                o[..., sl] = v
    else:
        outs = [v if type(v) is np.ndarray and v.shape == shape
                else np.broadcast_to(np.asarray(v, dtype=float), shape)
                for v in _reactions(*kin_arrays, *flat_loads)]
    rox, roy, rax, ray, rbx, rby, rcx, rcy, q_drive, sfx, sfy, smz = outs
    return FourbarForces(
        phi1=k.phi1, R_Ox=rox, R_Oy=roy, R_Ax=rax, R_Ay=ray, R_Bx=rbx, R_By=rby, R_Cx=rcx,
        R_Cy=rcy, Q=q_drive, shaking_force_x=sfx, shaking_force_y=sfy, shaking_moment=smz,
        kinematics=kin,
    )


def _part(x: Any, sl: slice) -> Any:
    """``x[..., sl]`` for arrays running over the positions; scalars and (m, 1) as they are."""
    if x is None or type(x) is float or np.ndim(x) == 0 or np.shape(x)[-1] == 1:
        return x
    return x[..., sl]


def _reactions(xa: Any, ya: Any, xb: Any, yb: Any, w3: Any, w4: Any, al3: Any, al4: Any,
               a: Any, b: Any, c: Any, d: Any, w2: Any, e2: Any,
               *loads: Any) -> tuple[Any, ...]:
    """The kinetostatic closed form on (a block of) positions; see fourbar_kinetostatics."""
    masses, inertias = loads[0:3], loads[3:6]
    coms = (loads[6:8], loads[8:10], loads[10:12])
    fpts = (loads[12:14], loads[14:16], loads[16:18])
    frc = (loads[18:20], loads[20:22], loads[22:24])
    mom = loads[24:27]
    gx, gy = loads[27], loads[28]
    ux, uy = xb - xa, yb - ya
    vx, vy = xb - d, yb
    den = ux * vy - uy * vx
    # unit vectors of the links' own x axes
    frames = ((xa / a, ya / a), (ux / b, uy / b), (vx / c, vy / c))
    omegas = (w2, w3, w4)
    alphas = (e2, al3, al4)
    # acceleration of each link's reference joint: O2, A, O4
    a_ref = ((0.0, 0.0), (-e2 * ya - w2 * w2 * xa, e2 * xa - w2 * w2 * ya), (0.0, 0.0))
    phi: list[tuple[Any, Any]] = []
    torque: list[Any] = []
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(3):
            ex, ey = frames[i]
            (p, q), (fp, fq) = coms[i], fpts[i]
            rx, ry = p * ex - q * ey, p * ey + q * ex          # S - reference joint
            w, e = omegas[i], alphas[i]
            asx = a_ref[i][0] - e * ry - w * w * rx           # acceleration of S
            asy = a_ref[i][1] + e * rx - w * w * ry
            gxi, gyi = masses[i] * (gx - asx), masses[i] * (gy - asy)   # weight + inertia
            fx, fy = frc[i]
            px, py = fp * ex - fq * ey, fp * ey + fq * ex      # force point - reference joint
            phi.append((fx + gxi, fy + gyi))
            torque.append(rx * gyi - ry * gxi + px * fy - py * fx + mom[i] - inertias[i] * e)
        t3, t4 = torque[1], torque[2]
        rbx = (t3 * vx + t4 * ux) / den
        rby = (t3 * vy + t4 * uy) / den
    rcx, rcy = -phi[2][0] - rbx, -phi[2][1] - rby
    rax, ray = rbx - phi[1][0], rby - phi[1][1]
    rox, roy = rax - phi[0][0], ray - phi[0][1]
    q_drive = xa * ray - ya * rax - torque[0]
    return (rox, roy, rax, ray, rbx, rby, rcx, rcy, q_drive, -(rox + rcx), -(roy + rcy),
            -q_drive - d * rcy)


# ---------------------------------------------------------------------------------------------
# paper 004, Eqs. (8)-(13), printed and corrected
# ---------------------------------------------------------------------------------------------
#
# Paper 004's symbols: links 1 (crank O-A, l1, phi1), 2 (coupler A-B, l2, phi2), 3 (rocker,
# l3, phi3), frame pivots O and C.  Its loop equation (1) runs O -> A -> B -> C, so phi3 is the
# angle of the vector B -> C (= Norton's theta4 + pi).  F_i = (F_i^x, F_i^y) is the resultant
# force on link i (weight, inertia force, external force) acting at the link's midpoint, M_i
# the resultant couple (inertia couple and external moment), counter-clockwise positive.


def paper004_eq8(phi2: Any, phi3: Any, l2: Any, l3: Any,
                 F2: Any, F3: Any,
                 M2: Any, M3: Any, printed: bool = True) -> np.ndarray:
    r"""Eq. (8) of paper 004: ``R_B^x``, force of the coupler on the rocker at B, x [N].

    .. math::

        R_B^x = \frac{1}{l_2 l_3 \sin(\varphi_2-\varphi_3)}\Big[-l_2\cos\varphi_2
        \big(-F_3^x\tfrac{l_3}{2}\sin\varphi_3 + F_3^y\tfrac{l_3}{2}\cos\varphi_3 - M_3^z\big)
        + l_3\cos\varphi_3\big(F_2^x\tfrac{l_2}{2}\sin\varphi_2
        - F_2^y\tfrac{l_2}{2}\cos\varphi_2 - M_2^z\big)\Big]

    Printed form checks out (with phi3 the angle of B -> C); ``printed`` has no effect.
    """
    p2, p3 = np.asarray(phi2, dtype=float), np.asarray(phi3, dtype=float)
    s2, c2, s3, c3 = np.sin(p2), np.cos(p2), np.sin(p3), np.cos(p3)
    (f2x, f2y), (f3x, f3y) = F2, F3
    t3 = -f3x * l3 / 2 * s3 + f3y * l3 / 2 * c3 - M3
    t2 = f2x * l2 / 2 * s2 - f2y * l2 / 2 * c2 - M2
    return np.asarray((-l2 * c2 * t3 + l3 * c3 * t2) / (l2 * l3 * np.sin(p2 - p3)))


def paper004_eq9(phi2: Any, phi3: Any, l2: Any, l3: Any,
                 F2: Any, F3: Any,
                 M2: Any, M3: Any, printed: bool = True) -> np.ndarray:
    r"""Eq. (9) of paper 004: ``R_B^y`` [N], as printed or corrected.

    Printed:

    .. math::

        R_B^y = \frac{1}{l_2 l_3 \sin(\varphi_2-\varphi_3)}\Big[-l_3\sin\varphi_3
        \big(-F_2^x\tfrac{l_2}{2}\sin\varphi_2 - F_2^y\tfrac{l_2}{2}\cos\varphi_2 - M_2^z\big)
        - l_2\cos\varphi_2\big(-F_3^x\tfrac{l_3}{2}\sin\varphi_3
        + F_3^y\tfrac{l_3}{2}\cos\varphi_3 - M_3^z\big)\Big]

    Corrected (``printed=False``): the first term is
    :math:`+l_3\sin\varphi_3(F_2^x\tfrac{l_2}{2}\sin\varphi_2 - F_2^y\tfrac{l_2}{2}\cos\varphi_2
    - M_2^z)` (as in Eq. (8) with cos -> sin) and the second has :math:`\sin\varphi_2` in place
    of :math:`\cos\varphi_2`.
    """
    p2, p3 = np.asarray(phi2, dtype=float), np.asarray(phi3, dtype=float)
    s2, c2, s3, c3 = np.sin(p2), np.cos(p2), np.sin(p3), np.cos(p3)
    (f2x, f2y), (f3x, f3y) = F2, F3
    t3 = -f3x * l3 / 2 * s3 + f3y * l3 / 2 * c3 - M3
    if printed:
        first = -l3 * s3 * (-f2x * l2 / 2 * s2 - f2y * l2 / 2 * c2 - M2)
        second = -l2 * c2 * t3
    else:
        first = l3 * s3 * (f2x * l2 / 2 * s2 - f2y * l2 / 2 * c2 - M2)
        second = -l2 * s2 * t3
    return np.asarray((first + second) / (l2 * l3 * np.sin(p2 - p3)))


def paper004_eq10(F3: Any,
                  RB: Any) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (10) of paper 004: ``R_C = -F_3 - R_B`` (frame on rocker at C) [N]."""
    return np.negative(F3[0]) - RB[0], np.negative(F3[1]) - RB[1]


def paper004_eq11(F2: Any,
                  RB: Any) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (11) of paper 004: ``R_A = R_B - F_2`` (crank on coupler at A) [N]."""
    return np.subtract(RB[0], F2[0]), np.subtract(RB[1], F2[1])


def paper004_eq12(F1: Any,
                  RA: Any) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (12) of paper 004: ``R_O = R_A - F_1`` (frame on crank at O) [N]."""
    return np.subtract(RA[0], F1[0]), np.subtract(RA[1], F1[1])


def paper004_eq13(phi1: Any, l1: Any, RA: Any,
                  F1: Any, M1: Any,
                  printed: bool = True) -> np.ndarray:
    r"""Eq. (13) of paper 004: the balancing (driving) moment Q on the crank [N m].

    Printed:

    .. math::

        Q = R_A^y l_1\cos\varphi_1 - R_A^x l_1\sin\varphi_1 - F_1^x\tfrac{l_1}{2}\sin\varphi_1
        + F_1^y\tfrac{l_1}{2}\cos\varphi_1 - M_1^z

    Corrected (``printed=False``): the two F_1 terms change sign,
    :math:`+F_1^x\tfrac{l_1}{2}\sin\varphi_1 - F_1^y\tfrac{l_1}{2}\cos\varphi_1` (the moment of
    F_1 about O must be subtracted, not added).
    """
    p1 = np.asarray(phi1, dtype=float)
    s1, c1 = np.sin(p1), np.cos(p1)
    rax, ray = RA
    f1x, f1y = F1
    sign = 1.0 if printed else -1.0
    return np.asarray(ray * l1 * c1 - rax * l1 * s1
                      + sign * (-f1x * l1 / 2 * s1 + f1y * l1 / 2 * c1) - M1)


@dataclass(frozen=True)
class Paper004Planar:
    """Reactions and balancing moment from paper 004's Eqs. (8)-(13) (paper's names) [N, N m]."""

    R_Bx: np.ndarray
    R_By: np.ndarray
    R_Cx: np.ndarray
    R_Cy: np.ndarray
    R_Ax: np.ndarray
    R_Ay: np.ndarray
    R_0x: np.ndarray
    R_0y: np.ndarray
    Q: np.ndarray


def paper004_planar(phi1: Any, phi2: Any, phi3: Any, l1: Any,
                    l2: Any, l3: Any, F1: Any,
                    F2: Any, F3: Any,
                    M1: Any, M2: Any, M3: Any,
                    printed: bool = True) -> Paper004Planar:
    """Paper 004's planar kinetostatics, Eqs. (8)-(13) chained, printed or corrected.

    Parameters
    ----------
    phi1, phi2, phi3 : array_like
        Angles of O -> A, A -> B and B -> C [rad] (paper's Eq. (1); phi3 = Norton's
        theta4 + pi).
    l1, l2, l3 : float
        Crank, coupler, rocker lengths [m].
    F1, F2, F3 : pairs of array_like
        Resultant force on each link at its midpoint (weight + inertia + external) [N].
    M1, M2, M3 : array_like
        Resultant couple on each link (inertia couple + external) [N m], counter-clockwise.
    printed : bool
        True: the formulas exactly as printed (as far as the OCR allows); False: corrected.
    """
    rbx = paper004_eq8(phi2, phi3, l2, l3, F2, F3, M2, M3, printed)
    rby = paper004_eq9(phi2, phi3, l2, l3, F2, F3, M2, M3, printed)
    rcx, rcy = paper004_eq10(F3, (rbx, rby))
    rax, ray = paper004_eq11(F2, (rbx, rby))
    r0x, r0y = paper004_eq12(F1, (rax, ray))
    q = paper004_eq13(phi1, l1, (rax, ray), F1, M1, printed)
    return Paper004Planar(rbx, rby, np.asarray(rcx), np.asarray(rcy), np.asarray(rax),
                          np.asarray(ray), np.asarray(r0x), np.asarray(r0y), q)
