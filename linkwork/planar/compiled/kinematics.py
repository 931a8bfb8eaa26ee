"""The engine's kinematics compiled by numba: one pass over the (design, position) elements.

A *plan interpreter*: :func:`encode` turns a mechanism's compiled plan
(:class:`~linkwork.planar.structure.Plan`) once into flat arrays (the joints' kinds and bodies,
the groups' kinds, bodies and joints, and per design the joints' local geometry), and
:func:`kinematics_kernel` runs, for every element (design ``i``, position ``k``), every group in
order: the positions of its bodies, then (all groups again) their velocities and accelerations,
written straight into the result block ``out[quantity, body, i, k]`` (quantities ``X Y T VX VY
W AX AY E``), with the element's masks (``pos_bad``: it does not assemble; ``bad``: that or a
singular rate) and the groups where an element first failed (``failed``) or two lines were
parallel (``parallel``), for the same AssemblyError as the NumPy path.

Same conventions and the same arithmetic as the NumPy path, element by element
(:mod:`~linkwork.planar.positions`: loci circle/line, their intersection, the body's angle from
the circle's radius vector; :mod:`~linkwork.planar.rates`: each body of a group hung on its
known neighbour with one unknown rate, the closure rows of the joint between them, Cramer's rule
with the same singularity tests): the results agree with it to rounding (numba's ``cos``,
``sin``, ``atan2`` may differ from NumPy's in the last bit).

Compiled plans (:func:`covered`): one driver (a crank on a revolute joint or a linear driver on
a prismatic one), then any sequence of the closed-form dyads RRR, RRP, PRR, RPR, RPP, PPR, PRP
and one-body slot groups RS, PS, on revolute, prismatic and pin-in-slot joints. Any other plan
(Newton groups, driven cylinders, gears, several drivers) is left to the NumPy path, which
:func:`linkwork.planar.kinematics` then runs transparently.

This module imports numba: it is imported only when ``backend="numba"`` is asked for.
"""

from __future__ import annotations

import math
import weakref
from typing import Any

import numpy as np
from numba import njit

from linkwork.planar.joints import PinInSlot, Prismatic, ResolvedJoint, Revolute
from linkwork.planar.structure import Plan, PlanGroup

__all__ = ["Encoded", "covered", "encode", "kinematics_kernel", "run"]

# joint kinds
_R, _P, _S = 0, 1, 2
# group kinds: driver on a revolute (crank) or prismatic (linear) joint; a dyad whose internal
# joint is revolute (RRR, RRP, PRR, PRP), the dyad RPR, a dyad with an internal and an external
# prismatic pair (RPP, PPR); the one-body slot groups RS and PS
_DRIVER, _DYAD_R, _DYAD_RPR, _DYAD_PP, _SLOT_R, _SLOT_P = 0, 1, 2, 3, 4, 5
_KINDS = {"RRR": _DYAD_R, "RRP": _DYAD_R, "PRR": _DYAD_R, "PRP": _DYAD_R, "RPR": _DYAD_RPR,
          "RPP": _DYAD_PP, "PPR": _DYAD_PP, "RS": _SLOT_R, "PS": _SLOT_P}
# per-design joint geometry: point on a, point on b, line angle, its direction in a, the
# prismatic pair's relative angle with its cosine and sine, the line's normal in a
_QAX, _QAY, _PBX, _PBY, _ANG, _UX, _UY, _REL, _CREL, _SREL, _NLX, _NLY = range(12)
_NJF = 12
# rows of the element's state
_X, _Y, _T, _C, _SN, _VX, _VY, _W, _AX, _AY, _E = range(11)
#: the state rows of the result block's quantities X Y T VX VY W AX AY E
_OUT_ROWS = (_X, _Y, _T, _VX, _VY, _W, _AX, _AY, _E)
# fields of a hung body (RatePar): mode (0 known, 1 turning about a pivot, 2 sliding), body,
# its known neighbour, the pivot A, the guide direction u, the pivot's local vector on the
# neighbour in frame axes, the unknown rate z
_MODE, _B, _K, _PAX, _PAY, _PUX, _PUY, _PRX, _PRY, _PZ = range(10)


# ---------------------------------------------------------------------------------------------
# the state of one element
@njit(cache=True, error_model="numpy")
def _rot(st: Any, i: int, x: float, y: float) -> tuple[float, float]:
    c, s = st[_C, i], st[_SN, i]
    return c * x - s * y, s * x + c * y


@njit(cache=True, error_model="numpy")
def _wpt(st: Any, i: int, x: float, y: float) -> tuple[float, float]:
    rx, ry = _rot(st, i, x, y)
    return st[_X, i] + rx, st[_Y, i] + ry


@njit(cache=True, error_model="numpy")
def _set_angle(st: Any, i: int, th: float) -> None:
    st[_T, i] = th
    st[_C, i] = math.cos(th)
    st[_SN, i] = math.sin(th)


@njit(cache=True, error_model="numpy")
def _place(st: Any, i: int, px: float, py: float, wx: float, wy: float) -> None:
    rx, ry = _rot(st, i, px, py)
    st[_X, i] = wx - rx
    st[_Y, i] = wy - ry


@njit(cache=True, error_model="numpy")
def _angle_of(st: Any, jt: Any, jf: Any, j: int, body: int) -> float:
    """The angle of ``body`` fixed by the prismatic pair ``j`` to its known other body."""
    if body == jt[j, 2]:
        return st[_T, jt[j, 1]] + jf[j, _REL]
    return st[_T, jt[j, 2]] - jf[j, _REL]


@njit(cache=True, error_model="numpy")
def _pivot(st: Any, jt: Any, jf: Any, j: int, body: int) -> tuple[float, float, float, float]:
    """World centre of the revolute joint ``j`` (from its known side) and its point on
    ``body``."""
    if body == jt[j, 1]:
        wx, wy = _wpt(st, jt[j, 2], jf[j, _PBX], jf[j, _PBY])
        return wx, wy, jf[j, _QAX], jf[j, _QAY]
    wx, wy = _wpt(st, jt[j, 1], jf[j, _QAX], jf[j, _QAY])
    return wx, wy, jf[j, _PBX], jf[j, _PBY]


@njit(cache=True, error_model="numpy")
def _line_condition(st: Any, jt: Any, jf: Any, j: int, body: int
                    ) -> tuple[float, float, float]:
    """The line of joint ``j`` as ``n . r_body = c`` for a body of known angle."""
    ia, ib = jt[j, 1], jt[j, 2]
    ux, uy = _rot(st, ia, jf[j, _UX], jf[j, _UY])
    nx, ny = -uy, ux
    if body == ia:
        px, py = _wpt(st, ib, jf[j, _PBX], jf[j, _PBY])
        wx, wy = _rot(st, ia, jf[j, _QAX], jf[j, _QAY])
    else:
        px, py = _wpt(st, ia, jf[j, _QAX], jf[j, _QAY])
        wx, wy = _rot(st, ib, jf[j, _PBX], jf[j, _PBY])
    return nx, ny, nx * (px - wx) + ny * (py - wy)


@njit(cache=True, error_model="numpy")
def _two_lines(st: Any, jt: Any, jf: Any, body: int, j1: int, j2: int) -> tuple[bool, bool]:
    """Origin of ``body`` (angle known) from two line joints; (failed, parallel)."""
    n1x, n1y, c1 = _line_condition(st, jt, jf, j1, body)
    n2x, n2y, c2 = _line_condition(st, jt, jf, j2, body)
    den = n1x * n2y - n1y * n2x
    par = abs(den) < 1e-12
    if par:
        den = math.nan
    st[_X, body] = (c1 * n2y - c2 * n1y) / den
    st[_Y, body] = (n1x * c2 - n2x * c1) / den
    return par, par


@njit(cache=True, error_model="numpy")
def _sqrt_checked(arg: float, scale: float) -> tuple[float, bool]:
    bad = not arg >= -1e-12 * scale * scale
    if bad:
        return math.nan, True
    return math.sqrt(max(arg, 0.0)), False


@njit(cache=True, error_model="numpy")
def _locus(st: Any, jt: Any, jf: Any, j: int, body: int, pix: float, piy: float, rad: float
           ) -> tuple[int, float, float, float, float]:
    """The locus of the point ``(pix, piy)`` of ``body`` allowed by its external joint ``j``:
    (0, A, radius ``rad``, 0) a circle about the pivot, or (1, B0, u) a line (the body's angle
    then set)."""
    kind, ia, ib = jt[j, 0], jt[j, 1], jt[j, 2]
    if kind == _R:
        if body == ia:
            ax, ay = _wpt(st, ib, jf[j, _PBX], jf[j, _PBY])
        else:
            ax, ay = _wpt(st, ia, jf[j, _QAX], jf[j, _QAY])
        return 0, ax, ay, rad, 0.0
    _set_angle(st, body, _angle_of(st, jt, jf, j, body))
    if body == ib:  # the slider on its known guide a
        qx, qy = _wpt(st, ia, jf[j, _QAX], jf[j, _QAY])
        ux, uy = _rot(st, ia, jf[j, _UX], jf[j, _UY])
        ox, oy = _rot(st, body, pix - jf[j, _PBX], piy - jf[j, _PBY])
    else:  # the guide; the known body's point slides on it
        qx, qy = _wpt(st, ib, jf[j, _PBX], jf[j, _PBY])
        ux, uy = _rot(st, body, jf[j, _UX], jf[j, _UY])
        ox, oy = _rot(st, body, pix - jf[j, _QAX], piy - jf[j, _QAY])
    return 1, qx + ox, qy + oy, ux, uy


@njit(cache=True, error_model="numpy")
def _intersect(k1: int, a1: float, b1: float, c1: float, d1: float, k2: int, a2: float,
               b2: float, c2: float, d2: float, branch: float
               ) -> tuple[float, float, bool, bool]:
    """The intersection of two loci (circle: centre (a, b), radius c; line: point (a, b),
    direction (c, d)) on ``branch``: (x, y, failed, parallel)."""
    if k1 == 0 and k2 == 0:
        ex, ey = a2 - a1, b2 - b1
        dd = math.sqrt(ex * ex + ey * ey)
        a = (c1 * c1 - c2 * c2 + dd * dd) / (2 * dd)
        h, bad = _sqrt_checked(c1 * c1 - a * a, c1)
        ux, uy = ex / dd, ey / dd
        return a1 + a * ux - branch * h * uy, b1 + a * uy + branch * h * ux, bad, False
    if k1 == 1 and k2 == 1:
        den = c1 * d2 - d1 * c2
        par = abs(den) < 1e-12
        if par:
            den = math.nan
        t = ((a2 - a1) * d2 - (b2 - b1) * c2) / den
        return a1 + t * c1, b1 + t * d1, par, par
    if k1 == 0:
        ax, ay, r, bx, by, ux, uy = a1, b1, c1, a2, b2, c2, d2
    else:
        ax, ay, r, bx, by, ux, uy = a2, b2, c2, a1, b1, c1, d1
    wx, wy = ax - bx, ay - by
    t0 = wx * ux + wy * uy
    perp2 = wx * wx + wy * wy - t0 * t0
    h, bad = _sqrt_checked(r * r - perp2, r)
    t = t0 + branch * h
    return bx + t * ux, by + t * uy, bad, False


@njit(cache=True, error_model="numpy")
def _finish_side(st: Any, body: int, kind: int, ax: float, ay: float, rad: float,
                 phi0: float, c0: float, s0: float, pix: float, piy: float, bx: float,
                 by: float) -> None:
    """The body's angle from a circle's radius vector (``phi0`` the angle of its point
    ``(pix, piy)`` seen from its pivot, in its frame; ``c0, s0`` its cosine and sine), then its
    origin from the point ``(pix, piy)`` at ``(bx, by)``."""
    if kind == 0:
        ex, ey = (bx - ax) / rad, (by - ay) / rad
        th = math.atan2(ey, ex)
        if phi0 != 0.0:
            st[_T, body] = th - phi0
            st[_C, body] = ex * c0 + ey * s0
            st[_SN, body] = ey * c0 - ex * s0
        else:
            st[_T, body] = th
            st[_C, body] = ex
            st[_SN, body] = ey
    _place(st, body, pix, piy, bx, by)


@njit(cache=True, error_model="numpy")
def _rotating_line(st: Any, body: int, ax: float, ay: float, alx: float, aly: float,
                   ang: float, h: float, xx: float, xy: float, branch: float) -> bool:
    """The angle of ``body`` pinned at A (its point ``(alx, aly)``) whose line at angle ``ang``
    must pass through X at the signed distance ``h``; True where it cannot."""
    dx, dy = xx - ax, xy - ay
    c = h / math.sqrt(dx * dx + dy * dy)
    bad = not abs(c) <= 1.0 + 1e-12
    acos = math.nan if bad else math.acos(min(max(c, -1.0), 1.0))
    _set_angle(st, body, math.atan2(dy, dx) + branch * acos - ang - math.pi / 2)
    _place(st, body, alx, aly, ax, ay)
    return bad


@njit(cache=True, error_model="numpy", inline="always")
def _positions(st: Any, jt: Any, jf: Any, gf: Any, gi: int, kind: int, b1: int, b2: int,
               j1: int, j2: int, j3: int, branch: float, q: float) -> tuple[bool, bool]:
    """The poses of the bodies of group ``gi``; (failed, parallel)."""
    if kind == _DRIVER:
        ia, ib = jt[j1, 1], jt[j1, 2]
        if jt[j1, 0] == _R:
            if b1 == ib:
                _set_angle(st, ib, st[_T, ia] + q)
                wx, wy = _wpt(st, ia, jf[j1, _QAX], jf[j1, _QAY])
                _place(st, ib, jf[j1, _PBX], jf[j1, _PBY], wx, wy)
            else:
                _set_angle(st, ia, st[_T, ib] - q)
                wx, wy = _wpt(st, ib, jf[j1, _PBX], jf[j1, _PBY])
                _place(st, ia, jf[j1, _QAX], jf[j1, _QAY], wx, wy)
        elif b1 == ib:
            _set_angle(st, ib, st[_T, ia] + jf[j1, _REL])
            wx, wy = _wpt(st, ia, jf[j1, _QAX], jf[j1, _QAY])
            ux, uy = _rot(st, ia, jf[j1, _UX], jf[j1, _UY])
            _place(st, ib, jf[j1, _PBX], jf[j1, _PBY], wx + q * ux, wy + q * uy)
        else:
            _set_angle(st, ia, st[_T, ib] - jf[j1, _REL])
            wx, wy = _wpt(st, ib, jf[j1, _PBX], jf[j1, _PBY])
            ux, uy = _rot(st, ia, jf[j1, _UX], jf[j1, _UY])
            _place(st, ia, jf[j1, _QAX], jf[j1, _QAY], wx - q * ux, wy - q * uy)
        return False, False
    if kind == _DYAD_R:
        ia2, ib2 = jt[j2, 1], jt[j2, 2]
        qax, qay, pbx, pby = jf[j2, _QAX], jf[j2, _QAY], jf[j2, _PBX], jf[j2, _PBY]
        p1x, p1y = (qax, qay) if b1 == ia2 else (pbx, pby)
        p2x, p2y = (pbx, pby) if b2 == ib2 else (qax, qay)
        k1, x1, y1, c1, d1 = _locus(st, jt, jf, j1, b1, p1x, p1y, gf[gi, 0])
        k2, x2, y2, c2, d2 = _locus(st, jt, jf, j3, b2, p2x, p2y, gf[gi, 4])
        bx, by, bad, par = _intersect(k1, x1, y1, c1, d1, k2, x2, y2, c2, d2, branch)
        _finish_side(st, b1, k1, x1, y1, c1, gf[gi, 1], gf[gi, 2], gf[gi, 3], p1x, p1y, bx,
                     by)
        _finish_side(st, b2, k2, x2, y2, c2, gf[gi, 5], gf[gi, 6], gf[gi, 7], p2x, p2y, bx,
                     by)
        return bad, par
    if kind == _DYAD_RPR or kind == _DYAD_PP:
        ga, sb = jt[j2, 1], jt[j2, 2]  # the internal pair's guide and slider bodies
        rg, rs = (j1, j3) if ga == b1 else (j3, j1)
        if kind == _DYAD_RPR:
            ax, ay, alx, aly = _pivot(st, jt, jf, rg, ga)
            cx, cy, clx, cly = _pivot(st, jt, jf, rs, sb)
            cr, sr = jf[j2, _CREL], jf[j2, _SREL]
            px, py = jf[j2, _PBX] - clx, jf[j2, _PBY] - cly
            rpx, rpy = cr * px - sr * py, sr * px + cr * py
            h = (jf[j2, _NLX] * (jf[j2, _QAX] - alx - rpx)
                 + jf[j2, _NLY] * (jf[j2, _QAY] - aly - rpy))
            bad = _rotating_line(st, ga, ax, ay, alx, aly, jf[j2, _ANG], h, cx, cy, branch)
            _set_angle(st, sb, _angle_of(st, jt, jf, j2, sb))
            _place(st, sb, clx, cly, cx, cy)
            return bad, False
        if jt[rg, 0] == _P:
            _set_angle(st, ga, _angle_of(st, jt, jf, rg, ga))
            _set_angle(st, sb, _angle_of(st, jt, jf, j2, sb))
            pinned, free, rp, rf = sb, ga, rs, rg
        else:
            _set_angle(st, sb, _angle_of(st, jt, jf, rs, sb))
            _set_angle(st, ga, _angle_of(st, jt, jf, j2, ga))
            pinned, free, rp, rf = ga, sb, rg, rs
        px, py, plx, ply = _pivot(st, jt, jf, rp, pinned)
        _place(st, pinned, plx, ply, px, py)
        return _two_lines(st, jt, jf, free, rf, j2)
    # one body with a revolute (RS) or prismatic (PS) pair j1 and a pin-in-slot j2
    if kind == _SLOT_P:
        _set_angle(st, b1, _angle_of(st, jt, jf, j1, b1))
        return _two_lines(st, jt, jf, b1, j1, j2)
    ax, ay, alx, aly = _pivot(st, jt, jf, j1, b1)
    ia, ib = jt[j2, 1], jt[j2, 2]
    if b1 == ia:  # the body carries the slot; the pin X is known
        xx, xy = _wpt(st, ib, jf[j2, _PBX], jf[j2, _PBY])
        h = jf[j2, _NLX] * (jf[j2, _QAX] - alx) + jf[j2, _NLY] * (jf[j2, _QAY] - aly)
        return _rotating_line(st, b1, ax, ay, alx, aly, jf[j2, _ANG], h, xx, xy, branch), False
    rad = gf[gi, 0]
    qx, qy = _wpt(st, ia, jf[j2, _QAX], jf[j2, _QAY])
    ux, uy = _rot(st, ia, jf[j2, _UX], jf[j2, _UY])
    bx, by, bad, par = _intersect(0, ax, ay, rad, 0.0, 1, qx, qy, ux, uy, branch)
    _finish_side(st, b1, 0, ax, ay, rad, gf[gi, 1], gf[gi, 2], gf[gi, 3], jf[j2, _PBX],
                 jf[j2, _PBY], bx, by)
    return bad, par


# ---------------------------------------------------------------------------------------------
# rates: each body of a group hung on its known neighbour with one unknown rate
@njit(cache=True, error_model="numpy")
def _vel_at(st: Any, k: int, x: float, y: float) -> tuple[float, float]:
    return st[_VX, k] - st[_W, k] * (y - st[_Y, k]), st[_VY, k] + st[_W, k] * (x - st[_X, k])


@njit(cache=True, error_model="numpy")
def _acc_at(st: Any, k: int, x: float, y: float) -> tuple[float, float]:
    rx, ry = x - st[_X, k], y - st[_Y, k]
    w2 = st[_W, k] * st[_W, k]
    return (st[_AX, k] - st[_E, k] * ry - w2 * rx, st[_AY, k] + st[_E, k] * rx - w2 * ry)


@njit(cache=True, error_model="numpy")
def _hang(st: Any, jt: Any, jf: Any, j: int, b: int) -> Any:
    """Body ``b`` hung on its known neighbour through joint ``j``, a tuple (mode: 1 turning
    about the pivot A with ``z = omega_b``, 2 sliding along the guide u with ``z`` the slide
    rate; body; neighbour k; A; u; the pivot's vector from k's origin; z = 0)."""
    ia, ib = jt[j, 1], jt[j, 2]
    k = ia if b == ib else ib
    if jt[j, 0] == _R:
        px, py = (jf[j, _QAX], jf[j, _QAY]) if k == ia else (jf[j, _PBX], jf[j, _PBY])
        rx, ry = _rot(st, k, px, py)
        return (1, b, k, st[_X, k] + rx, st[_Y, k] + ry, 0.0, 0.0, rx, ry, 0.0)
    ux, uy = _rot(st, ia, jf[j, _UX], jf[j, _UY])
    return (2, b, k, 0.0, 0.0, ux, uy, 0.0, 0.0, 0.0)


@njit(cache=True, error_model="numpy")
def _known(b: int) -> Any:
    """A known body as a hung one with no unknown (mode 0)."""
    return (0, b, b, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@njit(cache=True, error_model="numpy")
def _with_z(p: Any, z: float) -> Any:
    return (p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], z)


@njit(cache=True, error_model="numpy")
def _d(p: Any, x: float, y: float) -> tuple[float, float]:
    """The velocity at (x, y) per unit of the unknown rate."""
    if p[0] == 0:
        return 0.0, 0.0
    if p[0] == 1:
        return -(y - p[4]), x - p[3]
    return p[5], p[6]


@njit(cache=True, error_model="numpy")
def _cv(st: Any, p: Any, x: float, y: float) -> tuple[float, float]:
    """The velocity at (x, y) without the unknown's term."""
    if p[0] == 0:
        return _vel_at(st, p[1], x, y)
    k = p[2]
    if p[0] == 1:
        return st[_VX, k] - st[_W, k] * p[8], st[_VY, k] + st[_W, k] * p[7]
    return _vel_at(st, k, x, y)


@njit(cache=True, error_model="numpy")
def _ca(st: Any, p: Any, x: float, y: float) -> tuple[float, float]:
    """The acceleration at (x, y) without the term of the rate's derivative."""
    if p[0] == 0:
        return _acc_at(st, p[1], x, y)
    k, z = p[2], p[9]
    if p[0] == 1:
        w2 = st[_W, k] * st[_W, k]
        rx, ry = p[7], p[8]
        aax = st[_AX, k] - st[_E, k] * ry - w2 * rx
        aay = st[_AY, k] + st[_E, k] * rx - w2 * ry
        return aax - z * z * (x - p[3]), aay - z * z * (y - p[4])
    akx, aky = _acc_at(st, k, x, y)
    c = 2 * st[_W, k] * z
    return akx - c * p[6], aky + c * p[5]


@njit(cache=True, error_model="numpy")
def _wpart(st: Any, p: Any, row: int) -> tuple[float, float]:
    """The angular velocity (``row`` _W) or acceleration (_E) as (constant, coefficient of
    the unknown)."""
    if p[0] == 0:
        return st[row, p[1]], 0.0
    if p[0] == 1:
        return 0.0, 1.0
    return st[row, p[2]], 0.0


@njit(cache=True, error_model="numpy")
def _vel(st: Any, p: Any, x: float, y: float) -> tuple[float, float]:
    cx, cy = _cv(st, p, x, y)
    if p[0] == 0:
        return cx, cy
    dx, dy = _d(p, x, y)
    return cx + p[9] * dx, cy + p[9] * dy


@njit(cache=True, error_model="numpy")
def _set_velocity(st: Any, p: Any) -> None:
    b = p[1]
    st[_VX, b], st[_VY, b] = _vel(st, p, st[_X, b], st[_Y, b])
    c, k = _wpart(st, p, _W)
    st[_W, b] = c + k * p[9]


@njit(cache=True, error_model="numpy")
def _set_acceleration(st: Any, p: Any, zd: float) -> None:
    b = p[1]
    x, y = st[_X, b], st[_Y, b]
    cx, cy = _ca(st, p, x, y)
    dx, dy = _d(p, x, y)
    st[_AX, b], st[_AY, b] = cx + zd * dx, cy + zd * dy
    c, k = _wpart(st, p, _E)
    st[_E, b] = c + k * zd


@njit(cache=True, error_model="numpy")
def _closure(st: Any, jt: Any, jf: Any, pa: Any, sa: int, pb: Any, sb: int, j: int,
             acc: bool) -> tuple[float, float, float, float, float, float]:
    """The closure rows of joint ``j`` (its body a hung as ``pa``, the unknown number ``sa``,
    b as ``pb``, ``sb``; 2: a known body): ``(a11, a12, r1, a21, a22, r2)``, the coefficients
    of the unknowns and the right-hand side of each row; velocity rows, or acceleration rows
    (``acc``, the rates known)."""
    kind = jt[j, 0]
    a11 = a12 = a21 = a22 = 0.0
    if kind == _R:
        bx, by = _wpt(st, jt[j, 2], jf[j, _PBX], jf[j, _PBY])
        dax, day = _d(pa, bx, by)
        dbx, dby = _d(pb, bx, by)
        if acc:
            cax, cay = _ca(st, pa, bx, by)
            cbx, cby = _ca(st, pb, bx, by)
        else:
            cax, cay = _cv(st, pa, bx, by)
            cbx, cby = _cv(st, pb, bx, by)
        if sa == 0:
            a11, a21 = dax, day
        elif sa == 1:
            a12, a22 = dax, day
        if sb == 0:
            a11, a21 = -dbx, -dby
        elif sb == 1:
            a12, a22 = -dbx, -dby
        return a11, a12, cbx - cax, a21, a22, cby - cay
    px, py = _wpt(st, jt[j, 2], jf[j, _PBX], jf[j, _PBY])
    ux, uy = _rot(st, jt[j, 1], jf[j, _UX], jf[j, _UY])
    nx, ny = -uy, ux
    dax, day = _d(pa, px, py)
    dbx, dby = _d(pb, px, py)
    if sa == 0:
        a11 = -(nx * dax + ny * day)
    elif sa == 1:
        a12 = -(nx * dax + ny * day)
    if sb == 0:
        a11 = nx * dbx + ny * dby
    elif sb == 1:
        a12 = nx * dbx + ny * dby
    if acc:
        cax, cay = _ca(st, pa, px, py)
        cbx, cby = _ca(st, pb, px, py)
        vax, vay = _vel(st, pa, px, py)
        vbx, vby = _vel(st, pb, px, py)
        c0, k0 = _wpart(st, pa, _W)
        wa = c0 + k0 * pa[9]
        rvx, rvy = vbx - vax, vby - vay
        r1 = -(nx * (cbx - cax) + ny * (cby - cay)) + 2 * wa * (nx * -rvy + ny * rvx)
    else:
        cax, cay = _cv(st, pa, px, py)
        cbx, cby = _cv(st, pb, px, py)
        r1 = -(nx * (cbx - cax) + ny * (cby - cay))
    r2 = 0.0
    if kind == _P:  # and omega_a = omega_b (eps_a = eps_b)
        c0a, ka = _wpart(st, pa, _E if acc else _W)
        c0b, kb = _wpart(st, pb, _E if acc else _W)
        if sa == 0:
            a21 = ka
        elif sa == 1:
            a22 = ka
        if sb == 0:
            a21 = -kb
        elif sb == 1:
            a22 = -kb
        r2 = c0b - c0a
    return a11, a12, r1, a21, a22, r2


@njit(cache=True, error_model="numpy")
def _cramer(a11: float, a12: float, r1: float, a21: float, a22: float, r2: float,
            n_unk: int, scale: float) -> tuple[float, float]:
    """The 1 x 1 or 2 x 2 system; NaN where singular (the NumPy path's tests: a coefficient
    below 1e-7 ``scale``; a determinant below 1e-7 times the product of the column norms)."""
    if n_unk == 1:
        if not abs(a11) > 1e-7 * scale:
            return math.nan, math.nan
        return r1 / a11, math.nan
    det = a11 * a22 - a12 * a21
    norm = math.sqrt((a11 * a11 + a21 * a21) * (a12 * a12 + a22 * a22))
    inv = 1.0 / det if abs(det) > 1e-7 * norm else math.nan
    return (r1 * a22 - r2 * a12) * inv, (a11 * r2 - a21 * r1) * inv


@njit(cache=True, error_model="numpy", inline="always")
def _rates(st: Any, jt: Any, jf: Any, kind: int, b1: int, b2: int, j1: int, j2: int,
           j3: int, w1: float, e1: float, scale: float) -> None:
    """Velocities and accelerations of the bodies of a group (those before it known)."""
    if kind == _DRIVER:
        ia, ib = jt[j1, 1], jt[j1, 2]
        sign = 1.0 if b1 == ib else -1.0
        if jt[j1, 0] == _R:  # the crank: closed form
            k = ia if b1 == ib else ib
            if b1 == ib:
                pkx, pky, pux, puy = jf[j1, _QAX], jf[j1, _QAY], jf[j1, _PBX], jf[j1, _PBY]
            else:
                pkx, pky, pux, puy = jf[j1, _PBX], jf[j1, _PBY], jf[j1, _QAX], jf[j1, _QAY]
            w = st[_W, k] + sign * w1
            e = st[_E, k] + sign * e1
            st[_W, b1], st[_E, b1] = w, e
            rx, ry = _rot(st, k, pkx, pky)
            wk, ek = st[_W, k], st[_E, k]
            vpx, vpy = st[_VX, k] - wk * ry, st[_VY, k] + wk * rx
            apx = st[_AX, k] - ek * ry - wk * wk * rx
            apy = st[_AY, k] + ek * rx - wk * wk * ry
            rx, ry = _rot(st, b1, pux, puy)
            st[_VX, b1], st[_VY, b1] = vpx + w * ry, vpy - w * rx
            st[_AX, b1] = apx + e * ry + w * w * rx
            st[_AY, b1] = apy - e * rx + w * w * ry
            return
        p = _with_z(_hang(st, jt, jf, j1, b1), sign * w1)  # a linear driver: hung
        _set_velocity(st, p)
        _set_acceleration(st, p, sign * e1)
        return
    n_unk = 1 if kind >= _SLOT_R else 2
    p0 = _hang(st, jt, jf, j1, b1)
    p1 = _hang(st, jt, jf, j3, b2) if n_unk == 2 else p0
    ia, ib = jt[j2, 1], jt[j2, 2]  # the closure joint j2: the unknowns of its bodies
    sa = 0 if ia == b1 else (1 if n_unk == 2 and ia == b2 else 2)
    sb = 0 if ib == b1 else (1 if n_unk == 2 and ib == b2 else 2)
    pa = p0 if sa == 0 else (p1 if sa == 1 else _known(ia))
    pb = p0 if sb == 0 else (p1 if sb == 1 else _known(ib))
    a11, a12, r1, a21, a22, r2 = _closure(st, jt, jf, pa, sa, pb, sb, j2, False)
    z0, z1 = _cramer(a11, a12, r1, a21, a22, r2, n_unk, scale)
    p0 = _with_z(p0, z0)
    _set_velocity(st, p0)
    if n_unk == 2:
        p1 = _with_z(p1, z1)
        _set_velocity(st, p1)
    pa = p0 if sa == 0 else (p1 if sa == 1 else pa)
    pb = p0 if sb == 0 else (p1 if sb == 1 else pb)
    a11, a12, r1, a21, a22, r2 = _closure(st, jt, jf, pa, sa, pb, sb, j2, True)
    zd0, zd1 = _cramer(a11, a12, r1, a21, a22, r2, n_unk, scale)
    _set_acceleration(st, p0, zd0)
    if n_unk == 2:
        _set_acceleration(st, p1, zd1)


# ---------------------------------------------------------------------------------------------
# the kernel
@njit(cache=True, error_model="numpy")
def kinematics_kernel(jt: Any, jf: Any, gt: Any, gf: Any, br: Any, scale: Any, q: Any,
                      w: Any, e: Any, out: Any, pos_bad: Any, bad: Any, failed: Any,
                      parallel: Any) -> None:
    """Positions, velocities and accelerations of every (design ``i``, position ``k``)
    element.

    ``jt`` (nj, 3) joints' kind, body a, body b; ``jf`` (m, nj, 12) their geometry per design;
    ``gt`` (ng, 6) groups' kind, bodies, joints; ``gf`` (m, ng, 8) the groups' constant
    geometry per design (:func:`_group_geometry`); ``br`` (m, ng) branches; ``scale`` (m,)
    length scales; ``q, w, e`` (m, n) the driver's coordinate, speed, acceleration; written:
    ``out`` (9, nb, m, n), ``pos_bad, bad`` (m, n), ``failed, parallel`` (ng,) flags."""
    nb = out.shape[1]
    m, n = q.shape
    ng = gt.shape[0]
    st = np.zeros((11, nb))
    for i in range(m):
        jfi = jf[i]
        gfi = gf[i]
        L = scale[i]
        for k in range(n):
            st[_C, 0] = 1.0
            fail = False
            for gi in range(ng):
                f, par = _positions(st, jt, jfi, gfi, gi, gt[gi, 0], gt[gi, 1], gt[gi, 2],
                                    gt[gi, 3], gt[gi, 4], gt[gi, 5], float(br[i, gi]),
                                    q[i, k])
                if par:
                    parallel[gi] = True
                if f and not fail:
                    failed[gi] = True
                    fail = True
            for gi in range(ng):
                kind = gt[gi, 0]
                _rates(st, jt, jfi, kind, gt[gi, 1], gt[gi, 2], gt[gi, 3], gt[gi, 4],
                       gt[gi, 5], w[i, k], e[i, k], L)
            b = fail
            for body in range(1, nb):
                if not math.isfinite(st[_W, body]):
                    b = True
            pos_bad[i, k] = fail
            bad[i, k] = b
            for r in range(9):
                row = _OUT_ROWS[r]
                for body in range(nb):
                    out[r, body, i, k] = math.nan if b else st[row, body]


# ---------------------------------------------------------------------------------------------
# the plan encoded
class Encoded:
    """A plan as the kernel reads it: joint table ``jt`` (nj, 3), joint geometry ``jf`` (m,
    nj, 12), group table ``gt`` (ng, 6), group geometry ``gf`` (m, ng, 8), length scales (m,),
    the groups' keys in order."""

    __slots__ = ("gf", "gt", "jf", "jt", "keys", "m", "scale")

    def __init__(self, jt: np.ndarray, jf: np.ndarray, gt: np.ndarray, gf: np.ndarray,
                 scale: np.ndarray, keys: tuple[str, ...]) -> None:
        self.jt, self.jf, self.gt, self.gf, self.scale = jt, jf, gt, gf, scale
        self.keys = keys
        self.m = jf.shape[0]


_CACHE: weakref.WeakKeyDictionary[Plan, Encoded | None] = weakref.WeakKeyDictionary()


def covered(plan: Plan) -> bool:
    """Whether the kernel runs ``plan`` (see the module docstring); the NumPy path runs the
    others."""
    return encode(plan) is not None


def _joint_kind(r: ResolvedJoint) -> int | None:
    t = type(r.joint)
    return {Revolute: _R, Prismatic: _P, PinInSlot: _S}.get(t)


def _group_row(g: PlanGroup, joints: dict[int, int]) -> list[int] | None:
    if g.kind == "driver":
        r = g.joints[0]
        if _joint_kind(r) not in (_R, _P):
            return None
        return [_DRIVER, g.bodies[0], -1, joints[id(r)], -1, -1]
    kind = _KINDS.get(g.kind)
    if kind is None:
        return None
    b = [*g.bodies, -1][:2]
    j = [joints[id(r)] for r in g.joints] + [-1] * (3 - len(g.joints))
    return [kind, *b, *j]


def _group_geometry(jf: np.ndarray, gt: np.ndarray, jt: np.ndarray) -> np.ndarray | None:
    """Per design and group the constant geometry of its circle loci (side 1: the first body,
    side 2: the second): radius, the angle ``phi0`` of the point on the circle seen from the
    pivot in the body's frame, its cosine and sine (as :func:`~linkwork.planar.positions`
    computes them at every position); None where a body's two joint centres coincide (the
    NumPy path raises StructureError there)."""
    m = jf.shape[0]
    gf = np.zeros((m, gt.shape[0], 8))
    for gi, (kind, b1, b2, j1, j2, j3) in enumerate(gt):
        sides = []
        if kind == _DYAD_R:
            p1 = (_QAX, _QAY) if b1 == jt[j2, 1] else (_PBX, _PBY)
            p2 = (_PBX, _PBY) if b2 == jt[j2, 2] else (_QAX, _QAY)
            sides = [(0, j1, b1, j2, p1), (4, j3, b2, j2, p2)]
        elif kind == _SLOT_R and b1 != jt[j2, 1]:
            sides = [(0, j1, b1, j2, (_PBX, _PBY))]
        for off, j, b, jp, p in sides:
            if jt[j, 0] != _R:
                continue
            e = (_QAX, _QAY) if b == jt[j, 1] else (_PBX, _PBY)
            dx, dy = jf[:, jp, p[0]] - jf[:, j, e[0]], jf[:, jp, p[1]] - jf[:, j, e[1]]
            rad = np.hypot(dx, dy)
            if np.any(rad == 0.0):
                return None
            phi0 = np.arctan2(dy, dx)
            gf[:, gi, off:off + 4] = np.stack([rad, phi0, np.cos(phi0), np.sin(phi0)], axis=1)
    return gf


def encode(plan: Plan) -> Encoded | None:
    """The plan as the kernel reads it (cached per plan), or None where it is not covered."""
    try:
        return _CACHE[plan]
    except KeyError:
        pass
    enc = _encode(plan)
    _CACHE[plan] = enc
    return enc


def _encode(plan: Plan) -> Encoded | None:
    if len(plan.drivers) > 1 or plan.newton:
        return None
    joints = {id(r): k for k, r in enumerate(plan.joints)}
    kinds = [_joint_kind(r) for r in plan.joints]
    if any(k is None for k in kinds):
        return None
    rows: list[list[int]] = []
    for g in plan.groups:
        row = _group_row(g, joints)
        if row is None or (row[0] == _DRIVER) != (not rows):  # the driver first, only
            return None
        rows.append(row)
    jt = np.array([[k, r.ia, r.ib] for k, r in zip(kinds, plan.joints, strict=True)],
                  dtype=np.int64)
    gt = np.array(rows, dtype=np.int64)
    m = int(np.size(plan.length_scale))
    cols = []
    for r in plan.joints:
        rel = getattr(r.joint, "rel_angle", 0.0)
        ang = r.ang
        vals = (r.qa[0], r.qa[1], r.pb[0], r.pb[1], ang, r.u_loc[0], r.u_loc[1], rel,
                np.cos(rel), np.sin(rel), -np.sin(ang), np.cos(ang))
        cols.append(vals)
        for v in vals:
            if isinstance(v, np.ndarray):
                m = max(m, v.shape[0])
    jf = np.empty((m, len(plan.joints), _NJF))
    for k, vals in enumerate(cols):
        for c, v in enumerate(vals):
            jf[:, k, c] = v
    scale = np.broadcast_to(np.asarray(plan.length_scale, dtype=float), (m,)).copy()
    gf = _group_geometry(jf, gt, jt)
    if gf is None:
        return None
    return Encoded(jt, jf, gt, gf, scale, tuple(g.key for g in plan.groups))


def run(enc: Encoded, branches: dict[str, Any], q: np.ndarray, w: np.ndarray, e: np.ndarray,
        out: np.ndarray) -> tuple[np.ndarray, np.ndarray, set[str], set[str]]:
    """The kernel over the elements of ``q, w, e`` (m, n) into ``out`` (9, nb, m, n):
    ``(pos_bad, bad, failed, parallel)`` (masks (m, n), sets of group keys)."""
    m, n = q.shape
    ng = len(enc.keys)
    br = np.empty((m, ng), dtype=np.int64)
    for c, key in enumerate(enc.keys):
        br[:, c] = branches[key]
    pos_bad = np.empty((m, n), dtype=np.bool_)
    bad = np.empty((m, n), dtype=np.bool_)
    failed = np.zeros(ng, dtype=np.bool_)
    parallel = np.zeros(ng, dtype=np.bool_)
    jf, gf, scale = enc.jf, enc.gf, enc.scale
    if enc.m != m:  # geometry the same for every design of a batch
        jf = np.broadcast_to(jf, (m, *jf.shape[1:]))
        gf = np.broadcast_to(gf, (m, *gf.shape[1:]))
        scale = np.broadcast_to(scale, (m,))
    kinematics_kernel(enc.jt, jf, enc.gt, gf, br, scale, q, w, e, out, pos_bad, bad, failed,
                      parallel)
    return (pos_bad, bad, {k for k, f in zip(enc.keys, failed, strict=True) if f},
            {k for k, f in zip(enc.keys, parallel, strict=True) if f})
