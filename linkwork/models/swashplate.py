r"""Spatial crank (inclined-disk, swash-plate) drive of the tool slides of rotor machines.

A rotor of pitch radius ``R`` turns about its vertical axis and carries slides in guides
parallel to that axis. An inclined disk (the "crank disk") of pitch radius ``r`` turns about its
own axis, tilted by ``alpha`` to the rotor axis, with the same angular speed (gear ratio 1). A
rod of length ``l`` with spherical ends joins a point ``B`` of the disk rim to the slide point
``A``; the slide moves along the rotor axis by ``s(phi)``. This is the drive of paper [1]_
(Kryukov & Preis 2012).

Geometry and conventions (see ``docs/swashplate.md``)
-----------------------------------------------------
Fixed frame ``x0 y0 z0``: ``z0`` is the rotor axis, pointing from the disk towards the slides
(the direction of positive ``s``); ``y0`` lies in the plane in which the disk axis is tilted
(perpendicular to the line where the disk plane cuts a horizontal plane); ``x0 = y0 x z0``.
The rotor angle ``phi`` is counted from the negative ``y0`` direction, counter-clockwise seen
from ``+z0`` (as in [1]_). By homogeneous transforms

.. math::

    A = \mathrm{Rot}_z(\varphi)\,(0, -R, z_A)^T, \qquad
    B = \mathrm{Trans}(a, b, z_1)\,\mathrm{Rot}_x(\alpha)\,\mathrm{Rot}_z(\varphi)\,(0, -r, 0)^T,

so ``A = (R sin(phi), -R cos(phi), z_A)`` and
``B = (a + r sin(phi), b - r cos(alpha) cos(phi), z_1 - r sin(alpha) cos(phi))``. The disk centre
``O1`` has the horizontal coordinates ``(a, b)``: ``a`` along ``x0`` (the direction in which the
slide at ``phi = 0`` moves), ``b`` along ``y0`` (away from the slide at ``phi = 0``). With this
meaning of ``a`` and ``b`` the paper's Eq. (5) holds as printed. The disk point ``B`` is at its
lowest at ``phi = 0``. The rod length constraint ``|A - B| = l`` with the slide on the ``+z0``
side of ``B`` gives

.. math::

    X = (R - r)\sin\varphi - a, \quad Y = (r\cos\alpha - R)\cos\varphi - b, \quad
    \sin\delta_z = \sqrt{X^2 + Y^2}/l,

    s(\varphi) = r\sin\alpha\,(1 - \cos\varphi) + l\,[\cos\delta_z(\varphi) - \cos\delta_z(0)],

which are Eqs. (5) and (4) in [1]_; ``s(0) = 0``. The pressure angle ``delta_z`` in [0, pi/2] is
the angle between the rod and the rotor axis. The derivatives are written with
``h = l cos(delta_z) = sqrt(l**2 - X**2 - Y**2)`` so that they stay finite and exact where
``delta_z = 0`` (the paper's Eq. (10) is 0/0 there).

All lengths in metres, angles in radians. Every function broadcasts its arguments: angles of
shape ``(n,)`` against designs of shape ``(m, 1)`` give ``(m, n)``. The functions are homogeneous
of degree 1 in the lengths, so calling them with ``R = 1`` and lengths over ``R`` gives the
paper's relative units (Eqs. (7)-(12)); see :func:`relative`.

References
----------
.. [1] V. A. Kryukov, V. V. Preis, "Theoretical foundations of the kinematic analysis and
   synthesis of the crank drive of the actuating devices of technological rotors" (in Russian),
   Izvestiya TulGU, 2012.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import common_shape, require_finite, require_in_range, require_positive
from linkwork.deprecation import renamed_keywords
from linkwork.errors import AssemblyError, ParameterError, angle_ranges
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "SCHEMES",
    "Characteristics",
    "Design",
    "DriveForces",
    "KinematicsResult",
    "Scheme",
    "allowed_first_transfer",
    "analyze",
    "axial_size",
    "characteristics",
    "datum_offset",
    "drive_forces",
    "extremes",
    "first_transfer",
    "first_transfer_harmonic",
    "harmonic_coefficients",
    "harmonic_error",
    "max_slide_speed",
    "points",
    "position",
    "position_harmonic",
    "pressure_angle",
    "relative",
    "scheme_1",
    "scheme_2",
    "scheme_3",
    "scheme_4a",
    "scheme_4b",
    "second_transfer",
    "stroke",
    "unimodal",
]

TWO_PI = 2.0 * math.pi
#: Number of grid points per revolution used to locate extremes before exact refinement.
GRID = 720

OnFailure = Literal["raise", "nan"]


# --------------------------------------------------------------------------------------------
# core kinematics
# --------------------------------------------------------------------------------------------

def _params(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike,
            b: ArrayLike) -> tuple[np.ndarray, ...]:
    Rv = require_positive("R", R)
    rv = require_positive("r", r)
    lv = require_positive("l", l)
    av = require_in_range("alpha", alpha, 0.0, math.pi / 2, unit="deg", scale=180 / math.pi)
    out = (Rv, rv, lv, av, require_finite("a", a), require_finite("b", b))
    common_shape(**dict(zip(("R", "r", "l", "alpha", "a", "b"), out, strict=True)))
    return out


def _check_reach(phi: np.ndarray, q: np.ndarray, l: np.ndarray, on_failure: OnFailure,
                 strict: bool) -> np.ndarray:
    """Mask of positions where the rod cannot reach; raise unless ``on_failure == 'nan'``."""
    l2 = l * l
    bad = q >= l2 if strict else q > l2 * (1.0 + 1e-14)
    if on_failure == "nan" or not bad.any():
        return np.asarray(bad)
    worst = float(np.sqrt(np.max(np.where(bad, q / l2, 0.0))))
    msg = (f"rod cannot reach: |sin(delta_z)| = {worst:.6g} "
           f"{'>= 1 (rod at 90 deg to the axis)' if strict else '> 1'}; increase l or reduce "
           "the horizontal distance between slide and disk point (Eq. (5))")
    ph = np.asarray(phi)
    if ph.ndim <= 1 and bad.shape[-1:] == ph.reshape(-1).shape and ph.size > 1:
        order = np.argsort(ph.reshape(-1))
        m = bad.reshape(-1, ph.size)[:, order]
        raise AssemblyError(msg, angle_ranges(ph.reshape(-1)[order], m), driver="phi")
    bad_phi = np.broadcast_to(ph, bad.shape)[bad]
    raise AssemblyError(msg, [(float(bad_phi.min()), float(bad_phi.max()))], driver="phi")


def _kin(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
         a: ArrayLike, b: ArrayLike, order: int, on_failure: OnFailure = "raise",
         check: bool = True) -> dict[str, np.ndarray]:
    """Exact position and derivatives; ``order`` = number of derivatives wanted (0, 1, 2).

    ``check=False`` skips argument validation (internal callers with validated arrays) and
    the pressure angle ``delta``.
    """
    if check:
        ph = require_finite("phi", phi)
        Rv, rv, lv, av, a_, b_ = _params(R, r, l, alpha, a, b)
        common_shape(phi=ph, R=Rv, r=rv, l=lv, alpha=av, a=a_, b=b_)
    else:
        ph = np.asarray(phi, dtype=float)
        Rv, rv, lv, av, a_, b_ = (np.asarray(x, dtype=float) for x in (R, r, l, alpha, a, b))
    sp, cp = np.sin(ph), np.cos(ph)
    ca, sa = np.cos(av), np.sin(av)
    p = Rv - rv
    d = rv * ca - Rv
    X = p * sp - a_
    Y = d * cp - b_
    q = X * X + Y * Y
    Y0 = d - b_
    q0 = a_ * a_ + Y0 * Y0
    l2 = lv * lv
    bad = _check_reach(ph, q, lv, on_failure, strict=order > 0)
    bad0 = _check_reach(np.zeros(()), q0, lv, on_failure, strict=False)
    h = np.sqrt(np.maximum(l2 - q, 0.0))
    h0 = np.sqrt(np.maximum(l2 - q0, 0.0))
    rs = rv * sa
    out: dict[str, np.ndarray] = {"X": X, "Y": Y, "q": q, "h": h, "h0": h0}
    out["s"] = rs * (1.0 - cp) + h - h0
    if check:
        out["delta"] = np.arctan2(np.sqrt(q), h)
    if order >= 1:
        X1, Y1 = p * cp, -d * sp
        g = X * X1 + Y * Y1  # q'/2
        with np.errstate(divide="ignore", invalid="ignore"):
            h1 = -g / h
        out["g"] = g
        out["s1"] = rs * sp + h1
        if order >= 2:
            g1 = X1 * X1 - X * p * sp + Y1 * Y1 - Y * d * cp  # q''/2
            with np.errstate(divide="ignore", invalid="ignore"):
                h2 = (-g1 - h1 * h1) / h
            out["s2"] = rs * cp + h2
    if on_failure == "nan":
        nan_mask = np.asarray(bad) | np.asarray(bad0)
        if nan_mask.any():
            for key in ("s", "delta", "s1", "s2"):
                if key in out:
                    out[key] = np.where(nan_mask, np.nan, out[key])
    return out


def _kp(x: ArrayLike, P: tuple[np.ndarray, ...], order: int,
        on_failure: OnFailure = "nan") -> dict[str, np.ndarray]:
    """:func:`_kin` on a tuple of already validated parameters ``(R, r, l, alpha, a, b)``."""
    return _kin(x, P[0], P[1], P[2], P[3], P[4], P[5], order, on_failure, check=False)


@renamed_keywords(invalid="on_failure")
def position(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
             a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
             on_failure: OnFailure = "raise") -> np.ndarray:
    r"""Exact slide position ``s(phi)`` [m], ``s(0) = 0``, Eq. (4) in [1]_.

    .. math::

        s(\varphi) = r\sin\alpha\,(1 - \cos\varphi) + l\,[\cos\delta_z(\varphi) - \cos\delta_z(0)]

    Parameters
    ----------
    phi : array_like
        Rotor (and disk) angle [rad], counted from the negative ``y0`` axis, counter-clockwise
        seen from the slides' side (``+z0``).
    R : array_like
        Pitch radius of the rotor (radius of the slide point A) [m], > 0.
    r : array_like
        Pitch radius of the disk (radius of the disk point B) [m], > 0.
    l : array_like
        Rod length [m], > 0.
    alpha : array_like
        Tilt of the disk axis to the rotor axis [rad], in the closed range [0, pi/2]: the
        general functions accept the limiting schemes 3 (``alpha = 0``) and 2
        (``alpha = 90 deg``); the constructors :func:`scheme_4a` and :func:`scheme_4b` require
        the open range (0, 90 deg) of the paper's table.
    a, b : array_like
        Horizontal coordinates of the disk centre O1 [m], the paper's offsets in the sense of
        its Eq. (5). ``a`` is along ``x0``: ``a > 0`` points in the direction in which the slide
        at ``phi = 0`` moves as the rotor turns (this physical meaning holds whichever side
        "counter-clockwise" is seen from). ``b`` is along ``y0``: ``b > 0`` points away from
        the slide at ``phi = 0`` (towards the slide at ``phi = pi``). ``a != 0`` makes the
        axes of rotor and disk skew (scheme 1); with ``a = 0`` they intersect.
    on_failure : {"raise", "nan"}
        Where the rod cannot reach (``|sin delta_z| > 1``): raise :class:`AssemblyError` listing
        the rotor-angle ranges (default), or return NaN there.

    Returns
    -------
    ndarray
        ``s`` [m], positive in the ``+z0`` direction, broadcast over all arguments.

    Raises
    ------
    ParameterError
        A length is not positive, ``alpha`` is outside [0, 90 deg], or a value is not finite.
    AssemblyError
        The rod cannot reach at some ``phi`` (or at ``phi = 0``, the datum).
    """
    return _kin(phi, R, r, l, alpha, a, b, 0, on_failure)["s"]


@renamed_keywords(invalid="on_failure")
def pressure_angle(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                   a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
                   on_failure: OnFailure = "raise") -> np.ndarray:
    r"""Pressure angle ``delta_z(phi)`` [rad], in [0, pi/2]: rod angle to the rotor axis, Eq. (5).

    .. math::

        \sin^2\delta_z = \left[\frac{(R - r)\sin\varphi - a}{l}\right]^2
                       + \left[\frac{(r\cos\alpha - R)\cos\varphi - b}{l}\right]^2

    Computed as ``atan2(sqrt(X**2 + Y**2), h)`` (exact near 0 and 90 deg). Parameters as in
    :func:`position`.
    """
    return _kin(phi, R, r, l, alpha, a, b, 0, on_failure)["delta"]


@renamed_keywords(invalid="on_failure")
def first_transfer(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                   a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
                   on_failure: OnFailure = "raise") -> np.ndarray:
    r"""First transfer function ``Pi_v = ds/dphi`` [m/rad], Eq. (10) in [1]_, corrected.

    .. math::

        \Pi_v = r\sin\alpha\sin\varphi - \frac{X X' + Y Y'}{l\cos\delta_z},
        \quad X' = (R - r)\cos\varphi,\ Y' = (R - r\cos\alpha)\sin\varphi.

    The paper prints ``r sin(alpha) cos(phi)`` for the first term and writes the second as
    ``l sin(delta_z) d(delta_z)/dphi`` with a ``0/0`` where ``delta_z = 0``; the form above is
    finite there (see ``docs/errata.md``). Slide speed: ``v = omega * Pi_v``, Eq. (1).
    Parameters as in :func:`position`; the rod must not be at 90 deg to the axis.
    """
    return _kin(phi, R, r, l, alpha, a, b, 1, on_failure)["s1"]


@renamed_keywords(invalid="on_failure")
def second_transfer(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike,
                    alpha: ArrayLike, a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
                    on_failure: OnFailure = "raise") -> np.ndarray:
    r"""Second transfer function ``d2s/dphi2`` [m/rad^2] (exact; not in [1]_).

    .. math::

        \frac{d^2 s}{d\varphi^2} = r\sin\alpha\cos\varphi
            - \frac{X'^2 + X X'' + Y'^2 + Y Y'' + h'^2}{h},
        \quad h = l\cos\delta_z,\ h' = -\frac{X X' + Y Y'}{h}.

    Slide acceleration at constant rotor speed: ``omega**2 * d2s/dphi2``. Parameters as in
    :func:`position`.
    """
    return _kin(phi, R, r, l, alpha, a, b, 2, on_failure)["s2"]


def points(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
           a: ArrayLike = 0.0, b: ArrayLike = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """3-D points A (slide) and B (disk) [m], shape ``(..., 3)``, frame with ``z_A(0) = 0``.

    The origin O lies on the rotor axis at the height of A at ``phi = 0`` (so ``z_A = s``);
    the disk centre is at ``(a, b, -datum_offset(...))``. Used for plots and checks.
    """
    k = _kin(phi, R, r, l, alpha, a, b, 0)
    ph = np.asarray(phi, dtype=float)
    Rv, rv, av = (np.asarray(x, dtype=float) for x in (R, r, alpha))
    z1 = -datum_offset(R, r, l, alpha, a, b)
    A = np.stack(np.broadcast_arrays(Rv * np.sin(ph), -Rv * np.cos(ph), k["s"]), axis=-1)
    B = np.stack(np.broadcast_arrays(np.asarray(a, float) + rv * np.sin(ph),
                                     np.asarray(b, float) - rv * np.cos(av) * np.cos(ph),
                                     z1 - rv * np.sin(av) * np.cos(ph)), axis=-1)
    return A, B


def datum_offset(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike = 0.0,
                 b: ArrayLike = 0.0) -> np.ndarray:
    """Axial offset ``c = z_O - z_O1`` [m] of the origin O (``s = 0``) above the disk centre.

    ``c = l cos(delta_z(0)) - r sin(alpha)``. The paper writes ``c = c(R, r, l, a, b)``; it also
    depends on ``alpha``.
    """
    k = _kin(0.0, R, r, l, alpha, a, b, 0)
    return np.asarray(k["h0"] - np.asarray(r, float) * np.sin(np.asarray(alpha, float)))


# --------------------------------------------------------------------------------------------
# relative units and the harmonic approximation
# --------------------------------------------------------------------------------------------

def relative(R: float, **lengths: ArrayLike) -> dict[str, np.ndarray]:
    """Lengths in the paper's relative units (over the rotor radius ``R``), Eqs. (7) and (12).

    ``relative(R, r=..., l=..., a=..., b=..., H=..., L=...)`` returns the same keys divided by
    ``R``. Every function of this module is homogeneous of degree 1 in the lengths, so
    ``position(phi, 1, r/R, l/R, alpha, a/R, b/R) == position(phi, R, r, l, alpha, a, b) / R``
    and ``first_transfer`` likewise gives the relative ``Pi_v`` of Eq. (10). Velocity limits in
    relative units: Eq. (14), ``allowed_first_transfer(...) / R``.
    """
    Rv = float(require_positive("R", R))
    return {k: np.asarray(v, dtype=float) / Rv for k, v in lengths.items()}


def harmonic_coefficients(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                          a: ArrayLike = 0.0, b: ArrayLike = 0.0
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Coefficients ``A1, A2, A3`` [m] of the approximate position function, Eq. (6) in [1]_.

    .. math::

        A_1 = r\sin\alpha + \frac{b(R - r\cos\alpha)}{l},\quad
        A_2 = \frac{a(R - r)}{l},\quad
        A_3 = \frac{(R - r\cos\alpha)^2 - (R - r)^2}{l}.

    They follow from ``l cos(delta_z) ~ l - (X**2 + Y**2)/(2 l)`` (a small-angle expansion, which
    the paper calls a Fourier expansion). With ``R = 1`` and relative lengths they are the
    ``A~1..A~3`` of Eq. (11).
    """
    Rv, rv, lv, av, a_, b_ = _params(R, r, l, alpha, a, b)
    ca = np.cos(av)
    A1 = rv * np.sin(av) + b_ * (Rv - rv * ca) / lv
    A2 = a_ * (Rv - rv) / lv
    A3 = ((Rv - rv * ca) ** 2 - (Rv - rv) ** 2) / lv
    return A1, A2, A3


def position_harmonic(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike,
                      alpha: ArrayLike, a: ArrayLike = 0.0, b: ArrayLike = 0.0) -> np.ndarray:
    r"""Approximate position [m], Eqs. (6)/(11) in [1]_.

    .. math::

        s \approx A_1(1 - \cos\varphi) + A_2\sin\varphi + \tfrac14 A_3 (1 - \cos 2\varphi)
    """
    A1, A2, A3 = harmonic_coefficients(R, r, l, alpha, a, b)
    ph = require_finite("phi", phi)
    return A1 * (1 - np.cos(ph)) + A2 * np.sin(ph) + 0.25 * A3 * (1 - np.cos(2 * ph))


def first_transfer_harmonic(phi: ArrayLike, R: ArrayLike, r: ArrayLike, l: ArrayLike,
                            alpha: ArrayLike, a: ArrayLike = 0.0,
                            b: ArrayLike = 0.0) -> np.ndarray:
    r"""Approximate first transfer function [m/rad], Eq. (11) in [1]_ (corrected factor 1/2).

    .. math::

        \Pi_v \approx A_1\sin\varphi + A_2\cos\varphi + \tfrac12 A_3\sin 2\varphi
    """
    A1, A2, A3 = harmonic_coefficients(R, r, l, alpha, a, b)
    ph = require_finite("phi", phi)
    return A1 * np.sin(ph) + A2 * np.cos(ph) + 0.5 * A3 * np.sin(2 * ph)


def harmonic_error(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                   a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
                   n: int = GRID) -> dict[str, np.ndarray]:
    """Error of the harmonic form (6) against the exact position over a cycle [m].

    Returns a dict with ``max`` (largest ``|s_approx - s|``), ``rms`` (root mean square over
    ``n`` equally spaced angles) and ``relative_max`` (``max`` over the exact stroke ``H``; for a
    slide that does not move, ``H = 0``, it is 0 if the error is 0 and ``inf`` otherwise), each
    broadcast over the design parameters. The approximation neglects terms of order
    ``l * sin(delta_z)**4``; it is good where the pressure angle stays small.
    """
    Rv, rv, lv, av, a_, b_ = (x[..., None] for x in _params(R, r, l, alpha, a, b))
    ph = np.linspace(0.0, TWO_PI, n, endpoint=False)
    exact = position(ph, Rv, rv, lv, av, a_, b_)
    approx = position_harmonic(ph, Rv, rv, lv, av, a_, b_)
    err = approx - exact
    emax = np.max(np.abs(err), axis=-1)
    H = stroke(R, r, l, alpha, a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(H > 0, emax / np.where(H > 0, H, 1.0), np.where(emax > 0, np.inf, 0.0))
    return {"max": emax, "rms": np.sqrt(np.mean(err * err, axis=-1)), "relative_max": rel}


# --------------------------------------------------------------------------------------------
# extremes and characteristics (vectorised over designs)
# --------------------------------------------------------------------------------------------

def _root(fp: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray,
          iters: int = 40, tol: float = 1e-15) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised Illinois (modified regula falsi) on a sign change of ``fp`` in [lo, hi].

    Returns ``(x, bracketed)``; where ``fp`` has the same sign at both ends ``bracketed`` is
    False and ``x`` is meaningless. Converges superlinearly; stops when every bracket is
    narrower than ``tol`` (relative) or ``fp`` vanishes.
    """
    a, b = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    fa, fb = fp(a), fp(b)
    bracketed = np.sign(fa) * np.sign(fb) <= 0
    fa = np.where(bracketed, fa, -1.0)
    fb = np.where(bracketed, fb, 1.0)
    done = ~bracketed | (fb == 0)
    b = np.where(fa == 0, a, b)
    done |= fa == 0
    for _ in range(iters):
        if np.all(done):
            break
        den = fb - fa
        x = np.where(den != 0, (a * fb - b * fa) / np.where(den != 0, den, 1.0), 0.5 * (a + b))
        lo_, hi_ = np.minimum(a, b), np.maximum(a, b)
        x = np.where((x > lo_) & (x < hi_), x, 0.5 * (a + b))
        fx = fp(x)
        fx = np.where(np.isfinite(fx), fx, 0.0)
        flip = np.sign(fx) * np.sign(fb) < 0
        # converged entries are frozen (a root hit exactly, or a bracket at machine precision)
        a = np.where(done, a, np.where(flip, b, a))
        fa = np.where(done, fa, np.where(flip, fb, 0.5 * fa))
        b = np.where(done, b, x)
        fb = np.where(done, fb, fx)
        done |= (np.abs(b - a) <= tol * (1.0 + np.abs(b))) | (fb == 0)
    return b, bracketed


def _refined_max(f: Callable[[np.ndarray], np.ndarray], fp: Callable[[np.ndarray], np.ndarray],
                 grid: np.ndarray, vals: np.ndarray, lo_lim: np.ndarray | None = None,
                 hi_lim: np.ndarray | None = None, cyclic: bool = True
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Global maximum of ``f`` over the last axis of ``grid`` (values ``vals``), refined.

    The two best grid local maxima are refined by a root of ``fp`` within their neighbouring
    grid points (clipped to [lo_lim, hi_lim] when given); the larger refined value wins.
    Returns (argument, value), shape ``vals.shape[:-1]``.
    """
    n = vals.shape[-1]
    if cyclic:
        prev, nxt = np.roll(vals, 1, axis=-1), np.roll(vals, -1, axis=-1)
    else:
        pad = np.full((*vals.shape[:-1], 1), -np.inf)
        prev = np.concatenate([pad, vals[..., :-1]], axis=-1)
        nxt = np.concatenate([vals[..., 1:], pad], axis=-1)
    peak = (vals >= prev) & (vals > nxt)
    masked = np.where(peak, vals, -np.inf)
    k = min(2, n)
    top = np.argpartition(-masked, k - 1, axis=-1)[..., :k]
    best_x = np.take_along_axis(grid, top[..., :1], axis=-1)[..., 0]
    best_v = np.take_along_axis(vals, top[..., :1], axis=-1)[..., 0]
    for j in range(k):
        idx = top[..., j]
        ok = np.take_along_axis(masked, idx[..., None], axis=-1)[..., 0] > -np.inf
        x0 = np.take_along_axis(grid, idx[..., None], axis=-1)[..., 0]
        if cyclic:
            step = grid[..., 1] - grid[..., 0]
            lo, hi = x0 - step, x0 + step
        else:
            lo = np.take_along_axis(grid, np.maximum(idx - 1, 0)[..., None], axis=-1)[..., 0]
            hi = np.take_along_axis(grid, np.minimum(idx + 1, n - 1)[..., None], axis=-1)[..., 0]
        if lo_lim is not None:
            lo = np.maximum(lo, lo_lim)
        if hi_lim is not None:
            hi = np.minimum(hi, hi_lim)
        x, bracketed = _root(fp, lo, hi)
        v = f(x)
        better = ok & bracketed & (v > best_v)
        best_x = np.where(better, x, best_x)
        best_v = np.where(better, v, best_v)
    return best_x, best_v


def _design(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike,
            b: ArrayLike) -> tuple[np.ndarray, ...]:
    """Validated parameters broadcast to a common design shape."""
    return tuple(np.broadcast_arrays(*_params(R, r, l, alpha, a, b)))


@renamed_keywords(invalid="on_failure")
def extremes(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike = 0.0,
             b: ArrayLike = 0.0, *, on_failure: OnFailure = "raise") -> dict[str, np.ndarray]:
    """True extreme positions of the slide over a revolution.

    Returns a dict with ``phi_min``, ``s_min``, ``phi_max``, ``s_max`` (angles in [0, 2 pi),
    positions [m] with ``s(0) = 0``), broadcast over the design parameters. Found on a grid of
    :data:`GRID` angles and refined to machine precision by a bracketed root of ``ds/dphi``.
    """
    P = _design(R, r, l, alpha, a, b)
    return _extremes(P, on_failure)


def _extremes(P: tuple[np.ndarray, ...], on_failure: OnFailure = "raise",
              n_grid: int = GRID) -> dict[str, np.ndarray]:
    Rv, rv, lv, av, a_, b_ = (x[..., None] for x in P)
    grid = np.broadcast_to(np.linspace(0.0, TWO_PI, n_grid, endpoint=False),
                           (*Rv.shape[:-1], n_grid))
    s = _kin(grid, Rv, rv, lv, av, a_, b_, 0, on_failure, check=False)["s"]

    def ev(key: str, sign: float) -> Callable[[np.ndarray], np.ndarray]:
        return lambda x: sign * _kp(x, P, 1)[key]

    if on_failure == "nan":
        s = np.where(np.isnan(s), 0.0, s)
    xmax, vmax = _refined_max(ev("s", 1.0), ev("s1", 1.0), grid, s)
    xmin, vmin = _refined_max(ev("s", -1.0), ev("s1", -1.0), grid, -s)
    out = {"phi_max": np.mod(xmax, TWO_PI), "s_max": vmax,
           "phi_min": np.mod(xmin, TWO_PI), "s_min": -vmin}
    if on_failure == "nan":
        bad = np.isnan(_kin(grid, Rv, rv, lv, av, a_, b_, 0, "nan", check=False)["s"]).any(-1)
        out = {k: np.where(bad, np.nan, v) for k, v in out.items()}
    return out


@renamed_keywords(invalid="on_failure")
def stroke(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike = 0.0,
           b: ArrayLike = 0.0, *, on_failure: OnFailure = "raise") -> np.ndarray:
    """Stroke ``H = max s - min s`` [m] over a revolution, from the true extremes.

    Not ``s(pi) - s(0)``: with ``a != 0`` (schemes 1 and 3) the extremes are not at 0 and pi.
    Even with ``a = 0`` a large offset ``b`` can give two maxima per revolution (``s`` not
    unimodal, see :func:`unimodal`), and then ``s(pi) - s(0)`` is wrong as well, e.g.
    ``R, r, l, alpha, a, b = 0.1, 0.05, 0.15, 20 deg, 0, -0.045``: ``s(pi) - s(0) = -2.04 mm``
    against ``H = 3.47 mm``. Parameters as in :func:`position`.
    """
    e = extremes(R, r, l, alpha, a, b, on_failure=on_failure)
    return e["s_max"] - e["s_min"]


def unimodal(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike, a: ArrayLike = 0.0,
             b: ArrayLike = 0.0, *, n: int = 4 * GRID) -> np.ndarray:
    """Whether ``s(phi)`` has exactly one maximum and one minimum per revolution (bool array).

    Requirement 3 of [1]_. Counted as sign changes of ``ds/dphi`` on ``n`` equally spaced angles
    (extra extremes narrower than ``2 pi / n`` are not seen).
    """
    Rv, rv, lv, av, a_, b_ = (x[..., None] for x in _design(R, r, l, alpha, a, b))
    ph = np.linspace(0.0, TWO_PI, n, endpoint=False)
    s1 = _kin(ph, Rv, rv, lv, av, a_, b_, 1, check=False)["s1"]
    return _count_maxima(s1) == 1


def _count_maxima(s1: np.ndarray) -> np.ndarray:
    """Number of local maxima of s on a cyclic grid, from the sign pattern of s' (last axis)."""
    sg = np.sign(s1)
    # carry the last non-zero sign over exact zeros (plateaus of one sample)
    sg = np.where(sg == 0, np.roll(sg, 1, axis=-1), sg)
    return np.sum((sg > 0) & (np.roll(sg, -1, axis=-1) < 0), axis=-1)


def axial_size(r: ArrayLike, l: ArrayLike, alpha: ArrayLike) -> np.ndarray:
    r"""Approximate axial size of the drive ``L ~ 2 r sin(alpha) + l`` [m], Eq. (13) in [1]_.

    An upper bound: the exact axial extent from the lowest disk point to the highest slide point
    is ``s_max + l cos(delta_z(0))`` (``Characteristics.L_exact``).
    """
    rv = require_positive("r", r)
    lv = require_positive("l", l)
    av = require_in_range("alpha", alpha, 0.0, math.pi / 2, unit="deg", scale=180 / math.pi)
    return 2.0 * rv * np.sin(av) + lv


def allowed_first_transfer(v_allow: ArrayLike, productivity: ArrayLike,
                           u: ArrayLike) -> np.ndarray:
    r"""Largest admissible ``|Pi_v|`` [m/rad] for a slide-speed limit, Eqs. (1)-(3) in [1]_.

    With ``u`` slides (positions) on the rotor and productivity ``Pi = u n`` the rotor turns at
    ``omega = 2 pi Pi / u``, so

    .. math::

        [\Pi_v] = \frac{[v]}{\omega} = \frac{u\,[v]}{2\pi\,\Pi}
                = \frac{30\,u\,[v]}{\pi\,\Pi_{\min}}  \quad (\Pi_{\min}\ \text{in pieces/min}).

    Parameters
    ----------
    v_allow : array_like
        Allowed slide speed [v] [m/s].
    productivity : array_like
        Theoretical productivity [pieces/s] (``Pi_T / 60`` for the paper's pieces/min).
    u : array_like
        Number of slides (positions) on the rotor.

    Divide by ``R`` for the relative form, Eq. (14).
    """
    v = require_positive("v_allow", v_allow)
    P = require_positive("productivity", productivity)
    uu = require_positive("u", u)
    return uu * v / (TWO_PI * P)


def max_slide_speed(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                    a: ArrayLike = 0.0, b: ArrayLike = 0.0, *, omega: ArrayLike) -> np.ndarray:
    """Largest slide speed ``v_max = omega * max|Pi_v|`` [m/s] at rotor speed ``omega`` [rad/s].

    Eqs. (1)-(2) in [1]_ (there with ``omega = pi n / 30``, ``n`` in rpm).
    """
    c = characteristics(R, r, l, alpha, a, b)
    return np.abs(require_finite("omega", omega)) * c.Pi_v_max


# --------------------------------------------------------------------------------------------
# result objects
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Characteristics(Result):
    """Technological characteristics of a drive (arrays broadcast over designs).

    The forward stroke is the motion from the minimum of ``s`` to its maximum (``s``
    increasing, the rod pushing the slide away from the disk); the return stroke the rest.
    Angles [rad], lengths [m], ``Pi_v_max`` [m/rad].
    """

    H: np.ndarray  #: stroke, max s - min s
    phi_min: np.ndarray  #: rotor angle of the lowest slide position
    phi_max: np.ndarray  #: rotor angle of the highest slide position
    s_min: np.ndarray  #: lowest position (s(0) = 0)
    s_max: np.ndarray  #: highest position
    phi_f: np.ndarray  #: rotor angle of the forward stroke
    phi_r: np.ndarray  #: rotor angle of the return stroke
    delta_f: np.ndarray  #: largest pressure angle on the forward stroke
    delta_r: np.ndarray  #: largest pressure angle on the return stroke
    Pi_v_max: np.ndarray  #: largest |ds/dphi|
    phi_Pi_v_max: np.ndarray  #: where it occurs
    L: np.ndarray  #: approximate axial size 2 r sin(alpha) + l, Eq. (13)
    L_exact: np.ndarray  #: exact axial extent s_max + l cos(delta_z(0))
    unimodal: np.ndarray  #: one maximum and one minimum per revolution

    units: ClassVar[dict[str, str]] = {
        "H": "m", "phi_min": "rad", "phi_max": "rad", "s_min": "m", "s_max": "m",
        "phi_f": "rad", "phi_r": "rad", "delta_f": "rad", "delta_r": "rad", "Pi_v_max": "m/rad",
        "phi_Pi_v_max": "rad", "L": "m", "L_exact": "m", "unimodal": ""}
    position_field: ClassVar[str] = "H"

    def columns(self) -> dict[str, np.ndarray]:
        if np.ndim(self.H) == 0:
            return {}
        return super().columns()

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Stroke, stroke angles and largest pressure angles as bars: a
        :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.swashplate import characteristics_figure

        return characteristics_figure(self, ax=ax, **kw)


@renamed_keywords(invalid="on_failure")
def characteristics(R: ArrayLike, r: ArrayLike, l: ArrayLike, alpha: ArrayLike,
                    a: ArrayLike = 0.0, b: ArrayLike = 0.0, *,
                    on_failure: OnFailure = "raise") -> Characteristics:
    """All technological characteristics of the drive, requirements 1-5 in [1]_.

    Vectorised over designs (parameters broadcast to a design shape ``P``; every field has shape
    ``P``). Extremes and maxima are located on a grid and refined to machine precision. With
    ``on_failure="nan"`` designs whose rod cannot reach somewhere get NaN (``unimodal`` False).
    """
    P = _design(R, r, l, alpha, a, b)
    return _characteristics(P, on_failure)


def _characteristics(P: tuple[np.ndarray, ...], on_failure: OnFailure = "raise",
                     n_grid: int = GRID) -> Characteristics:
    """Characteristics of validated, broadcast parameters; ``n_grid`` angles per revolution
    locate the extremes before refinement (fewer for fast screening)."""
    Rv, rv, lv, av = P[:4]
    e = _extremes(P, on_failure, n_grid)
    phi_f = np.mod(e["phi_max"] - e["phi_min"], TWO_PI)
    phi_r = TWO_PI - phi_f

    def qf(x: np.ndarray) -> np.ndarray:
        return _kp(x, P, 1)["q"]

    def qp(x: np.ndarray) -> np.ndarray:
        return _kp(x, P, 1)["g"]

    def max_delta(start: np.ndarray, span: np.ndarray) -> np.ndarray:
        t = np.linspace(0.0, 1.0, n_grid // 2 + 1)
        grid = start[..., None] + span[..., None] * t
        q = _kp(grid, tuple(x[..., None] for x in P), 1)["q"]
        q = np.where(np.isnan(q), -np.inf, q)
        _, qmax = _refined_max(qf, qp, grid, q, lo_lim=start, hi_lim=start + span, cyclic=False)
        qmax = np.maximum(qmax, np.maximum(qf(start), qf(start + span)))
        return np.arcsin(np.clip(np.sqrt(np.clip(qmax, 0.0, None)) / lv, 0.0, 1.0))

    start_f = np.where(np.isnan(e["phi_min"]), 0.0, e["phi_min"])
    start_r = np.where(np.isnan(e["phi_max"]), 0.0, e["phi_max"])
    span_f = np.where(np.isnan(phi_f), math.pi, phi_f)
    delta_f = max_delta(start_f, span_f)
    delta_r = max_delta(start_r, TWO_PI - span_f)

    grid = np.broadcast_to(np.linspace(0.0, TWO_PI, n_grid, endpoint=False),
                           (*Rv.shape, n_grid))
    k = _kp(grid, tuple(x[..., None] for x in P), 2)
    s1 = k["s1"]
    abs1 = np.where(np.isnan(s1), -np.inf, np.abs(s1))

    def fabs(x: np.ndarray) -> np.ndarray:
        return np.abs(_kp(x, P, 1)["s1"])

    def fabs_p(x: np.ndarray) -> np.ndarray:
        kk = _kp(x, P, 2)
        return np.sign(kk["s1"]) * kk["s2"]

    x_v, v_max = _refined_max(fabs, fabs_p, grid, abs1)
    L = 2.0 * rv * np.sin(av) + lv
    L_exact = e["s_max"] + _kp(0.0, P, 0)["h0"]
    uni = _count_maxima(np.where(np.isnan(s1), 0.0, s1)) == 1
    bad = np.isnan(e["s_max"])
    if bad.any():
        delta_f, delta_r, v_max = (np.where(bad, np.nan, x) for x in (delta_f, delta_r, v_max))
        uni = uni & ~bad
    return Characteristics(
        H=e["s_max"] - e["s_min"], phi_min=e["phi_min"], phi_max=e["phi_max"],
        s_min=e["s_min"], s_max=e["s_max"], phi_f=phi_f, phi_r=phi_r, delta_f=delta_f,
        delta_r=delta_r, Pi_v_max=v_max, phi_Pi_v_max=np.mod(x_v, TWO_PI), L=L,
        L_exact=L_exact, unimodal=uni)


@dataclass(frozen=True)
class KinematicsResult(Result):
    """Position, pressure angle and transfer functions of one design over given rotor angles.

    Per-position arrays [SI]; ``v`` and ``acc`` are the slide speed [m/s] and acceleration
    [m/s^2] at the constant rotor speed ``omega`` [rad/s] (zero when ``omega == 0``, i.e. no
    speed given: then the CSV/JSON exports leave them out rather than write zeros).
    """

    phi: np.ndarray
    s: np.ndarray
    delta_z: np.ndarray
    Pi_v: np.ndarray
    Pi_a: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    omega: float
    design: Design
    characteristics: Characteristics

    units: ClassVar[dict[str, str]] = {
        "phi": "rad", "s": "m", "delta_z": "rad", "Pi_v": "m/rad", "Pi_a": "m/rad^2",
        "v": "m/s", "acc": "m/s^2", "omega": "rad/s"}
    position_field: ClassVar[str] = "phi"

    def columns(self) -> dict[str, np.ndarray]:
        cols = super().columns()
        if self.omega == 0.0:  # no rotor speed: the slide speed is unknown, not zero
            cols.pop("v", None)
            cols.pop("acc", None)
        return cols

    def scalars(self) -> dict[str, Any]:
        out = super().scalars()
        out.update({f"design.{k}": v for k, v in self.design.as_dict().items()})
        out.update({f"characteristics.{k}": v for k, v in
                    self.characteristics.scalars().items()})
        return out

    def _scene(self) -> Any:
        """The drive drawn over the rotor angles (:func:`linkwork.plot.scene.swashplate_scene`
        with the slide and disk points of :func:`points`)."""
        from linkwork.plot.scene import swashplate_scene

        A, B = points(self.phi, *self.design.params)
        return swashplate_scene(self, A, B)

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Position, pressure angle and transfer function over the rotor angle: a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.swashplate import kinematics_figure

        return kinematics_figure(self, axes=axes, **kw)


def analyze(design: Design, phi: ArrayLike | None = None, *, omega: float = 0.0,
            n: int = 361) -> KinematicsResult:
    """Kinematics of ``design`` over ``phi`` [rad] (default ``n`` angles over one revolution)."""
    ph = (np.linspace(0.0, TWO_PI, n) if phi is None
          else require_finite("phi", phi).reshape(-1))
    k = _kin(ph, *design.params, 2)
    w = float(require_finite("omega", omega))
    return KinematicsResult(
        phi=ph, s=k["s"], delta_z=k["delta"], Pi_v=k["s1"], Pi_a=k["s2"], v=w * k["s1"],
        acc=w * w * k["s2"], omega=w, design=design, characteristics=design.characteristics())


# --------------------------------------------------------------------------------------------
# schemes of the paper's table
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Scheme:
    """A scheme variant of the paper's table: what it fixes and what it leaves free."""

    name: str
    gear: str  #: the gear that couples rotor and disk
    free: tuple[str, ...]  #: free geometric parameters besides R
    fixed: dict[str, float] = field(default_factory=dict)  #: fixed values (alpha, a, b) [SI]
    rule: str = ""  #: an extra relation, in words


SCHEMES: dict[str, Scheme] = {
    "1": Scheme("1", "hypoid gear (or synchronous cardan)", ("r", "l", "alpha", "a", "b")),
    "2": Scheme("2", "orthogonal bevel gear", ("r", "l", "b"),
                {"alpha": math.pi / 2, "a": 0.0}),
    "3": Scheme("3", "cylindrical (spur) gear", ("r", "l", "a", "b"), {"alpha": 0.0}),
    "4a": Scheme("4a", "non-orthogonal bevel gear", ("l", "alpha"), {"a": 0.0, "b": 0.0},
                 "r = R / cos(alpha), 0 < alpha < 90 deg"),
    "4b": Scheme("4b", "non-orthogonal bevel gear", ("r", "l", "alpha", "b"), {"a": 0.0},
                 "b != 0, 0 < alpha < 90 deg"),
}


@dataclass(frozen=True)
class Design:
    """One drive: rotor radius ``R``, disk radius ``r``, rod ``l`` [m], tilt ``alpha`` [rad],
    disk-centre offsets ``a``, ``b`` [m], and the scheme it belongs to.

    Build it with :func:`scheme_1` ... :func:`scheme_4b` (which check what the scheme fixes) or
    directly (scheme ``"1"``, the general one). Methods evaluate the module functions.
    """

    R: float
    r: float
    l: float
    alpha: float
    a: float = 0.0
    b: float = 0.0
    scheme: str = "1"

    def __post_init__(self) -> None:
        _params(self.R, self.r, self.l, self.alpha, self.a, self.b)
        if self.scheme not in SCHEMES:
            raise ParameterError("scheme", self.scheme, f"must be one of {sorted(SCHEMES)}")

    @property
    def params(self) -> tuple[float, float, float, float, float, float]:
        """``(R, r, l, alpha, a, b)``."""
        return (self.R, self.r, self.l, self.alpha, self.a, self.b)

    def as_dict(self) -> dict[str, Any]:
        return {"scheme": self.scheme, "R": self.R, "r": self.r, "l": self.l,
                "alpha": self.alpha, "a": self.a, "b": self.b}

    def relative(self) -> dict[str, float]:
        """``r, l, a, b`` over ``R`` (relative units, Eq. (7)) and ``alpha``."""
        return {"r": self.r / self.R, "l": self.l / self.R, "alpha": self.alpha,
                "a": self.a / self.R, "b": self.b / self.R}

    def position(self, phi: ArrayLike) -> np.ndarray:
        return position(phi, *self.params)

    def pressure_angle(self, phi: ArrayLike) -> np.ndarray:
        return pressure_angle(phi, *self.params)

    def first_transfer(self, phi: ArrayLike) -> np.ndarray:
        return first_transfer(phi, *self.params)

    def second_transfer(self, phi: ArrayLike) -> np.ndarray:
        return second_transfer(phi, *self.params)

    def stroke(self) -> float:
        return float(stroke(*self.params))

    def characteristics(self) -> Characteristics:
        return characteristics(*self.params)

    @property
    def free(self) -> dict[str, float]:
        """The scheme's free parameters and their values."""
        return {k: getattr(self, k) for k in SCHEMES[self.scheme].free}


def _alpha_open(alpha: float) -> float:
    return float(require_in_range("alpha", alpha, 0.0, math.pi / 2, lo_open=True, hi_open=True,
                                  unit="deg", scale=180 / math.pi))


def scheme_1(R: float, r: float, l: float, alpha: float, a: float = 0.0,
             b: float = 0.0) -> Design:
    """General scheme 1 (hypoid gear): all of ``r, l, alpha, a, b`` free."""
    return Design(R, r, l, alpha, a, b, scheme="1")


def scheme_2(R: float, r: float, l: float, b: float = 0.0) -> Design:
    """Scheme 2 (orthogonal bevel gear): ``alpha = 90 deg``, ``a = 0``; free ``r, l, b``."""
    return Design(R, r, l, math.pi / 2, 0.0, b, scheme="2")


def scheme_3(R: float, r: float, l: float, a: float = 0.0, b: float = 0.0) -> Design:
    """Scheme 3 (cylindrical gear, parallel axes): ``alpha = 0``; free ``r, l, a, b``.

    Interpretation: the OCR of the paper's table gives the fixed value of scheme 3 as
    "a = 0"; linkwork reads it as ``alpha = 0`` (a cylindrical gear couples parallel axes, and
    the text calls scheme 3 symmetric only after shifting the origin of ``phi``, which fits
    ``alpha = 0`` with an offset in any direction, not ``a = 0``).

    The stroke comes only from the change of the rod's tilt. Rejecting ``a = b = 0`` is a
    package rule, not the paper's: with ``alpha = 0`` and the disk centre on the rotor axis the
    rod keeps its length projection and the slide does not move (``H = 0``). The general
    functions accept that case.
    """
    if a == 0.0 and b == 0.0:
        raise ParameterError("a, b", (a, b), "scheme 3 needs a disk-centre offset (a, b) != 0; "
                             "with alpha = 0 and a = b = 0 the slide does not move")
    return Design(R, r, l, 0.0, a, b, scheme="3")


def scheme_4a(R: float, l: float, alpha: float) -> Design:
    """Scheme 4a (non-orthogonal bevel gear, the classic drive): ``a = b = 0``,
    ``R = r cos(alpha)``; free ``alpha`` (0 < alpha < 90 deg) and ``l``. ``r = R / cos(alpha)``.
    """
    al = _alpha_open(alpha)
    return Design(R, R / math.cos(al), l, al, 0.0, 0.0, scheme="4a")


def scheme_4b(R: float, r: float, l: float, alpha: float, b: float) -> Design:
    """Scheme 4b (non-orthogonal bevel gear, disk centre off the axis): ``a = 0``, ``b != 0``;
    free ``r, l, alpha`` (0 < alpha < 90 deg) and ``b``.

    Interpretation: the table's row for 4b is OCR-damaged; linkwork reads it as leaving ``r``
    free (the row lists ``r~`` among the independent parameters), i.e. scheme 4a's
    ``R = r cos(alpha)`` is *not* imposed.
    """
    al = _alpha_open(alpha)
    if b == 0.0:
        raise ParameterError("b", b, "must be != 0 in scheme 4b (b = 0: use scheme 4a or 1)")
    return Design(R, r, l, al, 0.0, b, scheme="4b")


# --------------------------------------------------------------------------------------------
# kinetostatics
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DriveForces(Result):
    """Kinetostatics of the drive over a cycle (quasi-static, massless rod, constant speed).

    Per-position arrays: ``F`` technological force on one slide [N] (positive against ``+s``),
    ``S`` rod force [N] (positive = compression), ``N`` lateral guide reaction [N], ``M_disk``
    and ``M_rotor`` [N m] the torques the disk and the rotor need for one slide (sum ``M``),
    ``M_total`` the sum over the ``u`` phase-shifted slides, ``eta_inst`` the instantaneous
    efficiency of one slide (``F Pi_v / M``), shape ``(n,)``. Scalars: ``efficiency`` over the
    cycle (``work_useful / work_input``), ``work_useful`` and ``work_input`` per revolution [J]
    (all slides).

    Undefined values: ``eta_inst`` is undefined where the slide carries no load (``F = 0``,
    hence ``M = 0``: 0/0; also wherever ``M`` is exactly 0), ``efficiency`` when the load does
    no net useful work per revolution (no load, or e.g. a constant force, which gives back on
    one stroke what it takes on the other). Both are NaN in the result and are written as an
    empty CSV cell and JSON ``null`` (:func:`linkwork.results.write_csv`,
    :func:`~linkwork.results.write_json`).
    """

    phi: np.ndarray
    F: np.ndarray
    S: np.ndarray
    N: np.ndarray
    M_disk: np.ndarray
    M_rotor: np.ndarray
    M: np.ndarray
    M_total: np.ndarray
    eta_inst: np.ndarray
    efficiency: float
    work_useful: float
    work_input: float
    u: int

    units: ClassVar[dict[str, str]] = {
        "phi": "rad", "F": "N", "S": "N", "N": "N", "M_disk": "N*m", "M_rotor": "N*m",
        "M": "N*m", "M_total": "N*m", "eta_inst": "", "efficiency": "", "work_useful": "J",
        "work_input": "J", "u": ""}
    position_field: ClassVar[str] = "phi"

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """Slide load, rod force and drive torque over the rotor angle: a
        :class:`linkwork.plot.Figure` with 2 axes."""
        from linkwork.plot.swashplate import drive_forces_figure

        return drive_forces_figure(self, ax=ax, **kw)


Load = Callable[[np.ndarray], ArrayLike] | tuple[ArrayLike, ArrayLike] | float


def _load_fn(load: Load) -> Callable[[np.ndarray], np.ndarray]:
    if callable(load):
        fn = load
        return lambda x: np.broadcast_to(np.asarray(fn(x), dtype=float), np.shape(x))
    if isinstance(load, tuple):
        xp = require_finite("load angles", load[0]).reshape(-1)
        fp = require_finite("load forces", load[1]).reshape(-1)
        if xp.size != fp.size or xp.size < 2:
            raise ParameterError("load", f"{xp.size} angles, {fp.size} forces",
                                 "needs equally many (>= 2) angles and forces")
        return lambda x: np.interp(np.mod(x, TWO_PI), xp, fp, period=TWO_PI)
    Fc = float(require_finite("load", load))
    return lambda x: np.full(np.shape(x), Fc)


def _single_slide(phi: np.ndarray, P: tuple[float, float, float, float, float, float],
                  F: np.ndarray, mu: float) -> dict[str, np.ndarray]:
    Rv, rv, lv, av = P[:4]
    k = _kin(phi, P[0], P[1], P[2], P[3], P[4], P[5], 1)
    s1 = k["s1"]
    X, Y, h = k["X"], k["Y"], k["h"]
    cd, sd = h / lv, np.sqrt(k["q"]) / lv
    # friction in the guide opposes the slide's sliding; it adds to the rod force when the rod
    # drives the slide (F * Pi_v > 0) and relieves it when the slide drives back.
    sgn = np.sign(F * s1)
    denom = cd - mu * sd * sgn
    if np.any(denom <= 0):
        # phi is (u, n) for u phase-shifted slides: the ranges are in each slide's own angle
        own = np.mod(np.broadcast_to(phi, denom.shape), TWO_PI).ravel()
        order = np.argsort(own, kind="stable")
        raise AssemblyError("the drive jams: pressure angle + (effective) guide friction "
                            "angle >= 90 deg",
                            angle_ranges(own[order], (denom <= 0).ravel()[order]), driver="phi")
    S = F / denom
    # rod unit vector e = (A - B)/l; force on the slide S e, on the disk -S e.
    ex, ey, ez = X / lv, Y / lv, cd
    sp, cp = np.sin(phi), np.cos(phi)
    Ax, Ay = Rv * sp, -Rv * cp
    # torque the rotor needs = - moment about z of the slide's push on the guide (S e_h at A)
    M_rotor = -S * (Ax * ey - Ay * ex)
    # torque the disk needs about its own axis k = (0, -sin a, cos a) through O1
    bx, by, bz = rv * sp, -rv * np.cos(av) * cp, -rv * np.sin(av) * cp
    kx, ky, kz = 0.0, -np.sin(av), np.cos(av)
    cx, cy, cz = by * ez - bz * ey, bz * ex - bx * ez, bx * ey - by * ex
    M_disk = S * (cx * kx + cy * ky + cz * kz)
    return {"s1": s1, "S": S, "N": S * sd, "M_disk": M_disk, "M_rotor": M_rotor}


def drive_forces(design: Design, load: Load, *, u: int = 1, rho_guide: float = 0.0,
                 guide_length: float | None = None, overhang: float = 0.0,
                 phi: ArrayLike | None = None, n: int = 721) -> DriveForces:
    r"""Rod force, guide reaction and drive torques under a technological load (kinetostatics).

    Quasi-static (inertia neglected), massless rod with spherical ends (a two-force member,
    its force ``S`` acts along the rod), the slide in a guide parallel to the rotor axis with
    friction angle ``rho_guide``. Equilibrium of the slide along the axis:

    .. math::

        S\,(\cos\delta_z - \operatorname{sgn}(F\,\Pi_v)\,k\tan\rho\,\sin\delta_z) = F,
        \qquad k = 1 + 2e/b.

    ``k = 1`` is a slide pressed against its guide at one point. With ``guide_length`` ``b``
    (distance between the two places where the slide bears in its guide) and ``overhang``
    ``e`` (axial distance from the rod joint A to the nearer of them, A outside the guided
    length) the lateral force ``N = S sin(delta_z)`` tilts the slide: the guide pushes back
    with ``N (1 + e/b)`` at the nearer and ``N e/b`` at the farther place, and friction acts on
    both, hence ``k = 1 + 2 e/b``; the drive jams where
    ``tan(delta_z) >= 1 / (k tan(rho))``.

    The torques are the moments of the rod force about the disk axis (disk) and of the guide
    reaction about the rotor axis (rotor); both shafts turn at the same speed (gear ratio 1),
    so without friction ``M_disk + M_rotor = F Pi_v`` (power balance, the test of this
    function). The ``u`` slides are spaced ``2 pi / u`` apart and carry the same load diagram
    shifted by their phase.

    Parameters
    ----------
    design : Design
        The drive.
    load : callable, (angles, forces) or float
        Technological force on a slide [N] as a function of its own rotor angle ``phi`` (load
        diagram), positive when it resists ``+s`` (the forward stroke); a tabulated diagram is
        interpolated periodically; a float is a constant force.
    u : int
        Number of slides on the rotor.
    rho_guide : float
        Friction angle of the slide in its guide [rad], in [0, pi/2).
    guide_length : float, optional
        Distance between the slide's two bearing places in the guide [m], > 0. ``None``: a
        single contact (``k = 1``).
    overhang : float
        Axial distance from the rod joint A to the nearer bearing place [m], >= 0.
    phi : array_like, optional
        Rotor angles [rad]; default ``n`` angles over a revolution (used for the cycle
        integrals, so keep them covering [0, 2 pi] evenly).

    Returns
    -------
    DriveForces

    Raises
    ------
    AssemblyError
        The drive jams (``delta_z + atan(k tan(rho_guide)) >= 90 deg``) or the rod cannot
        reach.
    """
    if isinstance(u, bool) or not float(u).is_integer() or u < 1:
        raise ParameterError("u", u, "must be an integer >= 1")
    uu = int(u)
    rho = float(require_in_range("rho_guide", rho_guide, 0.0, math.pi / 2, hi_open=True,
                                 unit="deg", scale=180 / math.pi))
    mu = math.tan(rho)
    if guide_length is not None:
        bg = float(require_positive("guide_length", guide_length))
        e = float(require_positive("overhang", overhang, allow_zero=True))
        mu *= 1.0 + 2.0 * e / bg
    elif overhang:
        raise ParameterError("overhang", overhang, "needs guide_length")
    if phi is None and (isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2):
        raise ParameterError("n", n, "must be a whole number >= 2 (angles over a revolution)")
    ph = (np.linspace(0.0, TWO_PI, n) if phi is None
          else require_finite("phi", phi).reshape(-1))
    if ph.size < 2:
        raise ParameterError("phi", f"{ph.size} angle(s)", "must hold at least 2 angles (the "
                             "cycle integrals)")
    Ffn = _load_fn(load)
    P = design.params
    shifts = TWO_PI * np.arange(uu)[:, None] / uu
    phk = ph[None, :] + shifts
    Fk = Ffn(phk)
    res = _single_slide(phk, P, Fk, mu)
    M_k = res["M_disk"] + res["M_rotor"]
    useful_k = Fk * res["s1"]
    with np.errstate(divide="ignore", invalid="ignore"):
        eta = np.where(M_k[0] != 0, useful_k[0] / M_k[0], np.nan)
    # cycle integrals by the trapezoidal rule over the given angles (per revolution)
    W_use = float(np.trapezoid(useful_k.sum(0), ph))
    W_in = float(np.trapezoid(M_k.sum(0), ph))
    span = ph[-1] - ph[0]
    if span > 0:
        W_use *= TWO_PI / span
        W_in *= TWO_PI / span
    eff = W_use / W_in if W_in > 0 and W_use > 0 else float("nan")
    return DriveForces(phi=ph, F=Fk[0], S=res["S"][0], N=res["N"][0], M_disk=res["M_disk"][0],
                       M_rotor=res["M_rotor"][0], M=M_k[0], M_total=M_k.sum(0), eta_inst=eta,
                       efficiency=eff, work_useful=W_use, work_input=W_in, u=uu)
