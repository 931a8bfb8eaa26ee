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

Written for numba's sake: the helpers take and return numbers only (a body's pose ``x, y, cos,
sin``; a body hung on its neighbour as a tuple of 16 numbers that carries the neighbour's state);
the tables are read and the state written only in the two per-group functions inlined into the
kernel, over views that hold no reference (numba adjusted a reference count for every array
handed to a helper: the kernel took twice as long); the result is written once per element.

This module imports numba: it is imported only when ``backend="numba"`` is asked for.
"""

from __future__ import annotations

import math
import weakref
from typing import Any

import numpy as np
from numba import carray, njit, types
from numba.extending import intrinsic

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
# fields of a hung body (RatePar): mode (0 known, 1 turning about a pivot, 2 sliding), the
# pivot A, the guide direction u, the pivot's local vector on the neighbour in frame axes, the
# unknown rate z; then the state of its reference body (the known body, or the neighbour)
_MODE, _PAX, _PAY, _PUX, _PUY, _PRX, _PRY, _PZ = range(8)
_RX, _RY, _RVX, _RVY, _RW, _RAX, _RAY, _RE = range(8, 16)


# ---------------------------------------------------------------------------------------------
# positions: the helpers take and return numbers (a body's pose is x, y, cos, sin), the
# per-group function reads the tables and writes the state
@njit(cache=True, error_model="numpy")
def _rot(c: float, s: float, x: float, y: float) -> tuple[float, float]:
    return c * x - s * y, s * x + c * y


@njit(cache=True, error_model="numpy")
def _wpt(ox: float, oy: float, c: float, s: float, x: float, y: float
         ) -> tuple[float, float]:
    """The world point of the local point (x, y) of a body at (ox, oy) turned by (c, s)."""
    rx, ry = _rot(c, s, x, y)
    return ox + rx, oy + ry


@njit(cache=True, error_model="numpy")
def _origin(c: float, s: float, px: float, py: float, wx: float, wy: float
            ) -> tuple[float, float]:
    """The origin of a body turned by (c, s) whose local point (px, py) is at (wx, wy)."""
    rx, ry = _rot(c, s, px, py)
    return wx - rx, wy - ry


@njit(cache=True, error_model="numpy")
def _angle_of(is_b: bool, ta: float, tb: float, rel: float) -> float:
    """The angle of a body fixed by a prismatic pair (relative angle ``rel``, its bodies' angles
    ``ta, tb``) to its known other body: body b (``is_b``) or a."""
    if is_b:
        return ta + rel
    return tb - rel


@njit(cache=True, error_model="numpy")
def _ends(is_b: bool, qax: float, qay: float, pbx: float, pby: float
          ) -> tuple[float, float, float, float]:
    """A joint's point on the known body, then on the body (b if ``is_b``, else a)."""
    if is_b:
        return qax, qay, pbx, pby
    return pbx, pby, qax, qay


@njit(cache=True, error_model="numpy")
def _line_condition(is_a: bool, xa: float, ya: float, ca: float, sa: float, xb: float,
                    yb: float, cb: float, sb: float, qax: float, qay: float, pbx: float,
                    pby: float, ux: float, uy: float) -> tuple[float, float, float]:
    """The line of a joint (bodies a, b at their poses; direction ``(ux, uy)`` in a) as
    ``n . r_body = c`` for its body a (``is_a``) or b of known angle."""
    ux, uy = _rot(ca, sa, ux, uy)
    nx, ny = -uy, ux
    if is_a:
        px, py = _wpt(xb, yb, cb, sb, pbx, pby)
        wx, wy = _rot(ca, sa, qax, qay)
    else:
        px, py = _wpt(xa, ya, ca, sa, qax, qay)
        wx, wy = _rot(cb, sb, pbx, pby)
    return nx, ny, nx * (px - wx) + ny * (py - wy)


@njit(cache=True, error_model="numpy")
def _two_lines(n1x: float, n1y: float, c1: float, n2x: float, n2y: float, c2: float
               ) -> tuple[float, float, bool]:
    """The origin of a body (angle known) on two line conditions; parallel."""
    den = n1x * n2y - n1y * n2x
    par = abs(den) < 1e-12
    if par:
        den = math.nan
    return (c1 * n2y - c2 * n1y) / den, (n1x * c2 - n2x * c1) / den, par


@njit(cache=True, error_model="numpy")
def _sqrt_checked(arg: float, scale: float) -> tuple[float, bool]:
    bad = not arg >= -1e-12 * scale * scale
    if bad:
        return math.nan, True
    return math.sqrt(max(arg, 0.0)), False


@njit(cache=True, error_model="numpy")
def _locus(rev: bool, is_b: bool, ox: float, oy: float, oc: float, os: float, ot: float,
           pkx: float, pky: float, psx: float, psy: float, ux: float, uy: float, rel: float,
           pix: float, piy: float, rad: float
           ) -> tuple[int, float, float, float, float, float, float, float]:
    """The locus of the point ``(pix, piy)`` of a body allowed by its external joint (revolute
    ``rev`` or a line; the body its b if ``is_b``; the known other body's pose ``ox, oy, oc,
    os`` and angle ``ot``; the joint's points on it ``pk`` and on the body ``ps``): (0, A,
    radius ``rad``, 0) a circle about the pivot, or (1, B0, u) a line, then the body's angle,
    its cosine and sine (a line's only)."""
    ax, ay = _wpt(ox, oy, oc, os, pkx, pky)
    if rev:
        return 0, ax, ay, rad, 0.0, 0.0, 1.0, 0.0
    th = _angle_of(is_b, ot, ot, rel)
    c, s = math.cos(th), math.sin(th)
    if is_b:  # the slider on its known guide a
        ux, uy = _rot(oc, os, ux, uy)
    else:  # the guide; the known body's point slides on it
        ux, uy = _rot(c, s, ux, uy)
    rx, ry = _rot(c, s, pix - psx, piy - psy)
    return 1, ax + rx, ay + ry, ux, uy, th, c, s


@njit(cache=True, error_model="numpy", inline="always")
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
def _finish_side(kind: int, ax: float, ay: float, rad: float, phi0: float, c0: float,
                 s0: float, th: float, c: float, s: float, pix: float, piy: float, bx: float,
                 by: float) -> tuple[float, float, float, float, float]:
    """The body's pose (angle, cosine, sine, origin): on a circle (``kind`` 0) its angle from
    the radius vector (``phi0`` the angle of its point ``(pix, piy)`` seen from its pivot, in
    its frame; ``c0, s0`` its cosine and sine), on a line the given ``th, c, s``; then its
    origin from the point ``(pix, piy)`` at ``(bx, by)``."""
    if kind == 0:
        ex, ey = (bx - ax) / rad, (by - ay) / rad
        th = math.atan2(ey, ex)
        if phi0 != 0.0:
            th = th - phi0
            c = ex * c0 + ey * s0
            s = ey * c0 - ex * s0
        else:
            c, s = ex, ey
    x, y = _origin(c, s, pix, piy, bx, by)
    return th, c, s, x, y


@njit(cache=True, error_model="numpy")
def _rotating_line(ax: float, ay: float, alx: float, aly: float, ang: float, h: float,
                   xx: float, xy: float, branch: float
                   ) -> tuple[bool, float, float, float, float, float]:
    """The pose of a body pinned at A (its point ``(alx, aly)``) whose line at angle ``ang``
    must pass through X at the signed distance ``h``: (cannot, angle, cosine, sine, origin)."""
    dx, dy = xx - ax, xy - ay
    c = h / math.sqrt(dx * dx + dy * dy)
    bad = not abs(c) <= 1.0 + 1e-12
    acos = math.nan if bad else math.acos(min(max(c, -1.0), 1.0))
    th = math.atan2(dy, dx) + branch * acos - ang - math.pi / 2
    co, si = math.cos(th), math.sin(th)
    x, y = _origin(co, si, alx, aly, ax, ay)
    return bad, th, co, si, x, y


@njit(cache=True, error_model="numpy", inline="always")
def _positions(st: Any, jt: Any, jf: Any, gf: Any, gi: int, kind: int, b1: int, b2: int,
               j1: int, j2: int, j3: int, branch: float, q: float) -> tuple[bool, bool]:
    """The poses of the bodies of group ``gi``; (failed, parallel)."""
    if kind == _DRIVER:
        ia, ib = jt[j1, 1], jt[j1, 2]
        k = ia if b1 == ib else ib
        sign = 1.0 if b1 == ib else -1.0
        pkx, pky, pux, puy = _ends(b1 == ib, jf[j1, _QAX], jf[j1, _QAY], jf[j1, _PBX],
                                   jf[j1, _PBY])
        rev = jt[j1, 0] == _R
        th = st[_T, k] + sign * (q if rev else jf[j1, _REL])
        c, s = math.cos(th), math.sin(th)
        wx, wy = _wpt(st[_X, k], st[_Y, k], st[_C, k], st[_SN, k], pkx, pky)
        if not rev:  # the guide's direction in a, turned by a's angle (the one just set if b1
            # is a)
            ca, sa = (st[_C, ia], st[_SN, ia]) if b1 == ib else (c, s)
            ux, uy = _rot(ca, sa, jf[j1, _UX], jf[j1, _UY])
            wx, wy = wx + sign * q * ux, wy + sign * q * uy
        x, y = _origin(c, s, pux, puy, wx, wy)
        st[_T, b1], st[_C, b1], st[_SN, b1], st[_X, b1], st[_Y, b1] = th, c, s, x, y
        return False, False
    if kind == _DYAD_R:
        ia2, ib2 = jt[j2, 1], jt[j2, 2]
        qax, qay, pbx, pby = jf[j2, _QAX], jf[j2, _QAY], jf[j2, _PBX], jf[j2, _PBY]
        p1x, p1y = (qax, qay) if b1 == ia2 else (pbx, pby)
        p2x, p2y = (pbx, pby) if b2 == ib2 else (qax, qay)
        ia, ib = jt[j1, 1], jt[j1, 2]
        o = ia if b1 == ib else ib
        pkx, pky, psx, psy = _ends(b1 == ib, jf[j1, _QAX], jf[j1, _QAY], jf[j1, _PBX],
                                   jf[j1, _PBY])
        k1, x1, y1, c1, d1, t1, co1, si1 = _locus(
            jt[j1, 0] == _R, b1 == ib, st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], st[_T, o],
            pkx, pky, psx, psy, jf[j1, _UX], jf[j1, _UY], jf[j1, _REL], p1x, p1y, gf[gi, 0])
        ia, ib = jt[j3, 1], jt[j3, 2]
        o = ia if b2 == ib else ib
        pkx, pky, psx, psy = _ends(b2 == ib, jf[j3, _QAX], jf[j3, _QAY], jf[j3, _PBX],
                                   jf[j3, _PBY])
        k2, x2, y2, c2, d2, t2, co2, si2 = _locus(
            jt[j3, 0] == _R, b2 == ib, st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], st[_T, o],
            pkx, pky, psx, psy, jf[j3, _UX], jf[j3, _UY], jf[j3, _REL], p2x, p2y, gf[gi, 4])
        bx, by, bad, par = _intersect(k1, x1, y1, c1, d1, k2, x2, y2, c2, d2, branch)
        st[_T, b1], st[_C, b1], st[_SN, b1], st[_X, b1], st[_Y, b1] = _finish_side(
            k1, x1, y1, c1, gf[gi, 1], gf[gi, 2], gf[gi, 3], t1, co1, si1, p1x, p1y, bx, by)
        st[_T, b2], st[_C, b2], st[_SN, b2], st[_X, b2], st[_Y, b2] = _finish_side(
            k2, x2, y2, c2, gf[gi, 5], gf[gi, 6], gf[gi, 7], t2, co2, si2, p2x, p2y, bx, by)
        return bad, par
    if kind == _DYAD_RPR or kind == _DYAD_PP:
        ga, sb = jt[j2, 1], jt[j2, 2]  # the internal pair's guide and slider bodies
        rg, rs = (j1, j3) if ga == b1 else (j3, j1)
        if kind == _DYAD_RPR:  # the guide pinned at A, the slider at C
            ia, ib = jt[rg, 1], jt[rg, 2]
            o = ib if ga == ia else ia
            pkx, pky, alx, aly = _ends(ga != ia, jf[rg, _QAX], jf[rg, _QAY], jf[rg, _PBX],
                                       jf[rg, _PBY])
            ax, ay = _wpt(st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], pkx, pky)
            ia, ib = jt[rs, 1], jt[rs, 2]
            o = ib if sb == ia else ia
            pkx, pky, clx, cly = _ends(sb != ia, jf[rs, _QAX], jf[rs, _QAY], jf[rs, _PBX],
                                       jf[rs, _PBY])
            cx, cy = _wpt(st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], pkx, pky)
            cr, sr = jf[j2, _CREL], jf[j2, _SREL]
            px, py = jf[j2, _PBX] - clx, jf[j2, _PBY] - cly
            rpx, rpy = cr * px - sr * py, sr * px + cr * py
            h = (jf[j2, _NLX] * (jf[j2, _QAX] - alx - rpx)
                 + jf[j2, _NLY] * (jf[j2, _QAY] - aly - rpy))
            bad, th, c, s, x, y = _rotating_line(ax, ay, alx, aly, jf[j2, _ANG], h, cx, cy,
                                                 branch)
            st[_T, ga], st[_C, ga], st[_SN, ga], st[_X, ga], st[_Y, ga] = th, c, s, x, y
            th = _angle_of(True, th, th, jf[j2, _REL])
            c, s = math.cos(th), math.sin(th)
            x, y = _origin(c, s, clx, cly, cx, cy)
            st[_T, sb], st[_C, sb], st[_SN, sb], st[_X, sb], st[_Y, sb] = th, c, s, x, y
            return bad, False
        if jt[rg, 0] == _P:  # both angles from the prismatic pairs, the slider pinned
            th = _angle_of(ga == jt[rg, 2], st[_T, jt[rg, 1]], st[_T, jt[rg, 2]], jf[rg, _REL])
            st[_T, ga], st[_C, ga], st[_SN, ga] = th, math.cos(th), math.sin(th)
            th = _angle_of(True, th, th, jf[j2, _REL])
            st[_T, sb], st[_C, sb], st[_SN, sb] = th, math.cos(th), math.sin(th)
            pinned, free, rp, rf = sb, ga, rs, rg
        else:
            th = _angle_of(sb == jt[rs, 2], st[_T, jt[rs, 1]], st[_T, jt[rs, 2]], jf[rs, _REL])
            st[_T, sb], st[_C, sb], st[_SN, sb] = th, math.cos(th), math.sin(th)
            th = _angle_of(False, th, th, jf[j2, _REL])
            st[_T, ga], st[_C, ga], st[_SN, ga] = th, math.cos(th), math.sin(th)
            pinned, free, rp, rf = ga, sb, rg, rs
        ia, ib = jt[rp, 1], jt[rp, 2]
        o = ib if pinned == ia else ia
        pkx, pky, plx, ply = _ends(pinned != ia, jf[rp, _QAX], jf[rp, _QAY], jf[rp, _PBX],
                                   jf[rp, _PBY])
        px, py = _wpt(st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], pkx, pky)
        st[_X, pinned], st[_Y, pinned] = _origin(st[_C, pinned], st[_SN, pinned], plx, ply,
                                                 px, py)
        ja, jb = rf, j2
    elif kind == _SLOT_P:  # one body with a prismatic pair j1 and a pin-in-slot j2
        free = b1
        th = _angle_of(b1 == jt[j1, 2], st[_T, jt[j1, 1]], st[_T, jt[j1, 2]], jf[j1, _REL])
        st[_T, b1], st[_C, b1], st[_SN, b1] = th, math.cos(th), math.sin(th)
        ja, jb = j1, j2
    else:  # one body with a revolute pair j1 and a pin-in-slot j2
        ia, ib = jt[j1, 1], jt[j1, 2]
        o = ib if b1 == ia else ia
        pkx, pky, alx, aly = _ends(b1 != ia, jf[j1, _QAX], jf[j1, _QAY], jf[j1, _PBX],
                                   jf[j1, _PBY])
        ax, ay = _wpt(st[_X, o], st[_Y, o], st[_C, o], st[_SN, o], pkx, pky)
        ia, ib = jt[j2, 1], jt[j2, 2]
        if b1 == ia:  # the body carries the slot; the pin X is known
            xx, xy = _wpt(st[_X, ib], st[_Y, ib], st[_C, ib], st[_SN, ib], jf[j2, _PBX],
                          jf[j2, _PBY])
            h = jf[j2, _NLX] * (jf[j2, _QAX] - alx) + jf[j2, _NLY] * (jf[j2, _QAY] - aly)
            bad, th, c, s, x, y = _rotating_line(ax, ay, alx, aly, jf[j2, _ANG], h, xx, xy,
                                                 branch)
            st[_T, b1], st[_C, b1], st[_SN, b1], st[_X, b1], st[_Y, b1] = th, c, s, x, y
            return bad, False
        rad = gf[gi, 0]
        qx, qy = _wpt(st[_X, ia], st[_Y, ia], st[_C, ia], st[_SN, ia], jf[j2, _QAX],
                      jf[j2, _QAY])
        ux, uy = _rot(st[_C, ia], st[_SN, ia], jf[j2, _UX], jf[j2, _UY])
        bx, by, bad, par = _intersect(0, ax, ay, rad, 0.0, 1, qx, qy, ux, uy, branch)
        st[_T, b1], st[_C, b1], st[_SN, b1], st[_X, b1], st[_Y, b1] = _finish_side(
            0, ax, ay, rad, gf[gi, 1], gf[gi, 2], gf[gi, 3], 0.0, 1.0, 0.0, jf[j2, _PBX],
            jf[j2, _PBY], bx, by)
        return bad, par
    # the free body's origin on the line conditions of joints ja and jb (its angle known)
    ia, ib = jt[ja, 1], jt[ja, 2]
    n1x, n1y, c1 = _line_condition(
        free == ia, st[_X, ia], st[_Y, ia], st[_C, ia], st[_SN, ia], st[_X, ib], st[_Y, ib],
        st[_C, ib], st[_SN, ib], jf[ja, _QAX], jf[ja, _QAY], jf[ja, _PBX], jf[ja, _PBY],
        jf[ja, _UX], jf[ja, _UY])
    ia, ib = jt[jb, 1], jt[jb, 2]
    n2x, n2y, c2 = _line_condition(
        free == ia, st[_X, ia], st[_Y, ia], st[_C, ia], st[_SN, ia], st[_X, ib], st[_Y, ib],
        st[_C, ib], st[_SN, ib], jf[jb, _QAX], jf[jb, _QAY], jf[jb, _PBX], jf[jb, _PBY],
        jf[jb, _UX], jf[jb, _UY])
    st[_X, free], st[_Y, free], par = _two_lines(n1x, n1y, c1, n2x, n2y, c2)
    return par, par


# ---------------------------------------------------------------------------------------------
# rates: each body of a group hung on its known neighbour with one unknown rate. A hung body is
# a tuple of numbers (fields _MODE.._PZ) with the state of its reference body (the known body
# itself, or its neighbour): X Y VX VY W AX AY E (fields _RX.._RE), read when it is hung
@njit(cache=True, error_model="numpy")
def _hang(rev: bool, kx: float, ky: float, kc: float, ks: float, kvx: float, kvy: float,
          kw: float, kax: float, kay: float, ke: float, px: float, py: float, ca: float,
          sa: float, ux: float, uy: float) -> Any:
    """A body hung on its known neighbour k (its pose and rates) through a joint: turning about
    the pivot A (``rev``; the pivot's local point ``(px, py)`` on k) with ``z = omega``, or
    sliding along the guide u (direction ``(ux, uy)`` in the joint's body a turned by ``(ca,
    sa)``) with ``z`` the slide rate; z = 0."""
    if rev:
        rx, ry = _rot(kc, ks, px, py)
        return (1.0, kx + rx, ky + ry, 0.0, 0.0, rx, ry, 0.0, kx, ky, kvx, kvy, kw, kax, kay,
                ke)
    ux, uy = _rot(ca, sa, ux, uy)
    return (2.0, 0.0, 0.0, ux, uy, 0.0, 0.0, 0.0, kx, ky, kvx, kvy, kw, kax, kay, ke)


@njit(cache=True, error_model="numpy")
def _known(x: float, y: float, vx: float, vy: float, w: float, ax: float, ay: float,
           e: float) -> Any:
    """A known body (its state) as a hung one with no unknown (mode 0)."""
    return (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, x, y, vx, vy, w, ax, ay, e)


@njit(cache=True, error_model="numpy")
def _with_z(p: Any, z: float) -> Any:
    return (p[0], p[1], p[2], p[3], p[4], p[5], p[6], z, p[8], p[9], p[10], p[11], p[12],
            p[13], p[14], p[15])


@njit(cache=True, error_model="numpy")
def _vel_at(p: Any, x: float, y: float) -> tuple[float, float]:
    """The velocity at (x, y) of the reference body of ``p``."""
    return p[_RVX] - p[_RW] * (y - p[_RY]), p[_RVY] + p[_RW] * (x - p[_RX])


@njit(cache=True, error_model="numpy")
def _acc_at(p: Any, x: float, y: float) -> tuple[float, float]:
    """The acceleration at (x, y) of the reference body of ``p``."""
    rx, ry = x - p[_RX], y - p[_RY]
    w2 = p[_RW] * p[_RW]
    return p[_RAX] - p[_RE] * ry - w2 * rx, p[_RAY] + p[_RE] * rx - w2 * ry


@njit(cache=True, error_model="numpy")
def _d(p: Any, x: float, y: float) -> tuple[float, float]:
    """The velocity at (x, y) per unit of the unknown rate."""
    if p[_MODE] == 0:
        return 0.0, 0.0
    if p[_MODE] == 1:
        return -(y - p[_PAY]), x - p[_PAX]
    return p[_PUX], p[_PUY]


@njit(cache=True, error_model="numpy")
def _cv(p: Any, x: float, y: float) -> tuple[float, float]:
    """The velocity at (x, y) without the unknown's term."""
    if p[_MODE] == 1:
        return p[_RVX] - p[_RW] * p[_PRY], p[_RVY] + p[_RW] * p[_PRX]
    return _vel_at(p, x, y)


@njit(cache=True, error_model="numpy")
def _ca(p: Any, x: float, y: float) -> tuple[float, float]:
    """The acceleration at (x, y) without the term of the rate's derivative."""
    if p[_MODE] == 0:
        return _acc_at(p, x, y)
    z = p[_PZ]
    if p[_MODE] == 1:
        w2 = p[_RW] * p[_RW]
        rx, ry = p[_PRX], p[_PRY]
        aax = p[_RAX] - p[_RE] * ry - w2 * rx
        aay = p[_RAY] + p[_RE] * rx - w2 * ry
        return aax - z * z * (x - p[_PAX]), aay - z * z * (y - p[_PAY])
    akx, aky = _acc_at(p, x, y)
    c = 2 * p[_RW] * z
    return akx - c * p[_PUY], aky + c * p[_PUX]


@njit(cache=True, error_model="numpy")
def _wpart(p: Any, acc: bool) -> tuple[float, float]:
    """The angular velocity (or acceleration: ``acc``) as (constant, coefficient of the
    unknown)."""
    if p[_MODE] == 1:
        return 0.0, 1.0
    return (p[_RE] if acc else p[_RW]), 0.0


@njit(cache=True, error_model="numpy")
def _vel(p: Any, x: float, y: float) -> tuple[float, float]:
    cx, cy = _cv(p, x, y)
    if p[_MODE] == 0:
        return cx, cy
    dx, dy = _d(p, x, y)
    return cx + p[_PZ] * dx, cy + p[_PZ] * dy


@njit(cache=True, error_model="numpy")
def _velocity(p: Any, x: float, y: float) -> tuple[float, float, float]:
    """The hung body's velocity (of its origin at (x, y)) and angular velocity."""
    vx, vy = _vel(p, x, y)
    c, k = _wpart(p, False)
    return vx, vy, c + k * p[_PZ]


@njit(cache=True, error_model="numpy")
def _acceleration(p: Any, zd: float, x: float, y: float) -> tuple[float, float, float]:
    """The hung body's acceleration (of its origin at (x, y)) and angular acceleration, the
    unknown's derivative ``zd``."""
    cx, cy = _ca(p, x, y)
    dx, dy = _d(p, x, y)
    c, k = _wpart(p, True)
    return cx + zd * dx, cy + zd * dy, c + k * zd


@njit(cache=True, error_model="numpy", inline="always")
def _closure(kind: int, px: float, py: float, ux: float, uy: float, pa: Any, sa: int,
             pb: Any, sb: int, acc: bool) -> tuple[float, float, float, float, float, float]:
    """The closure rows of a joint (``kind``; ``(px, py)`` its centre on body b, ``(ux, uy)``
    its line's direction; its body a hung as ``pa``, the unknown number ``sa``, b as ``pb``,
    ``sb``; 2: a known body): ``(a11, a12, r1, a21, a22, r2)``, the coefficients of the
    unknowns and the right-hand side of each row; velocity rows, or acceleration rows
    (``acc``, the rates known)."""
    a11 = a12 = a21 = a22 = 0.0
    if kind == _R:
        dax, day = _d(pa, px, py)
        dbx, dby = _d(pb, px, py)
        if acc:
            cax, cay = _ca(pa, px, py)
            cbx, cby = _ca(pb, px, py)
        else:
            cax, cay = _cv(pa, px, py)
            cbx, cby = _cv(pb, px, py)
        if sa == 0:
            a11, a21 = dax, day
        elif sa == 1:
            a12, a22 = dax, day
        if sb == 0:
            a11, a21 = -dbx, -dby
        elif sb == 1:
            a12, a22 = -dbx, -dby
        return a11, a12, cbx - cax, a21, a22, cby - cay
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
        cax, cay = _ca(pa, px, py)
        cbx, cby = _ca(pb, px, py)
        vax, vay = _vel(pa, px, py)
        vbx, vby = _vel(pb, px, py)
        c0, k0 = _wpart(pa, False)
        wa = c0 + k0 * pa[_PZ]
        rvx, rvy = vbx - vax, vby - vay
        r1 = -(nx * (cbx - cax) + ny * (cby - cay)) + 2 * wa * (nx * -rvy + ny * rvx)
    else:
        cax, cay = _cv(pa, px, py)
        cbx, cby = _cv(pb, px, py)
        r1 = -(nx * (cbx - cax) + ny * (cby - cay))
    r2 = 0.0
    if kind == _P:  # and omega_a = omega_b (eps_a = eps_b)
        c0a, ka = _wpart(pa, acc)
        c0b, kb = _wpart(pb, acc)
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
    ia, ib = jt[j1, 1], jt[j1, 2]
    k = ia if b1 == ib else ib
    if kind == _DRIVER and jt[j1, 0] == _R:  # the crank: closed form
        sign = 1.0 if b1 == ib else -1.0
        pkx, pky, pux, puy = _ends(b1 == ib, jf[j1, _QAX], jf[j1, _QAY], jf[j1, _PBX],
                                   jf[j1, _PBY])
        w = st[_W, k] + sign * w1
        e = st[_E, k] + sign * e1
        st[_W, b1], st[_E, b1] = w, e
        rx, ry = _rot(st[_C, k], st[_SN, k], pkx, pky)
        wk, ek = st[_W, k], st[_E, k]
        vpx, vpy = st[_VX, k] - wk * ry, st[_VY, k] + wk * rx
        apx = st[_AX, k] - ek * ry - wk * wk * rx
        apy = st[_AY, k] + ek * rx - wk * wk * ry
        rx, ry = _rot(st[_C, b1], st[_SN, b1], pux, puy)
        st[_VX, b1], st[_VY, b1] = vpx + w * ry, vpy - w * rx
        st[_AX, b1] = apx + e * ry + w * w * rx
        st[_AY, b1] = apy - e * rx + w * w * ry
        return
    pkx, pky = (jf[j1, _QAX], jf[j1, _QAY]) if k == ia else (jf[j1, _PBX], jf[j1, _PBY])
    p0 = _hang(jt[j1, 0] == _R, st[_X, k], st[_Y, k], st[_C, k], st[_SN, k], st[_VX, k],
               st[_VY, k], st[_W, k], st[_AX, k], st[_AY, k], st[_E, k], pkx, pky,
               st[_C, ia], st[_SN, ia], jf[j1, _UX], jf[j1, _UY])
    x1, y1 = st[_X, b1], st[_Y, b1]
    if kind == _DRIVER:  # a linear driver: hung
        sign = 1.0 if b1 == ib else -1.0
        p0 = _with_z(p0, sign * w1)
        st[_VX, b1], st[_VY, b1], st[_W, b1] = _velocity(p0, x1, y1)
        st[_AX, b1], st[_AY, b1], st[_E, b1] = _acceleration(p0, sign * e1, x1, y1)
        return
    n_unk = 1 if kind >= _SLOT_R else 2
    p1 = p0
    if n_unk == 2:
        ia, ib = jt[j3, 1], jt[j3, 2]
        k = ia if b2 == ib else ib
        pkx, pky = (jf[j3, _QAX], jf[j3, _QAY]) if k == ia else (jf[j3, _PBX], jf[j3, _PBY])
        p1 = _hang(jt[j3, 0] == _R, st[_X, k], st[_Y, k], st[_C, k], st[_SN, k], st[_VX, k],
                   st[_VY, k], st[_W, k], st[_AX, k], st[_AY, k], st[_E, k], pkx, pky,
                   st[_C, ia], st[_SN, ia], jf[j3, _UX], jf[j3, _UY])
    ia, ib = jt[j2, 1], jt[j2, 2]  # the closure joint j2: the unknowns of its bodies
    sa = 0 if ia == b1 else (1 if n_unk == 2 and ia == b2 else 2)
    sb = 0 if ib == b1 else (1 if n_unk == 2 and ib == b2 else 2)
    pa = p0 if sa == 0 else (p1 if sa == 1 else _known(
        st[_X, ia], st[_Y, ia], st[_VX, ia], st[_VY, ia], st[_W, ia], st[_AX, ia],
        st[_AY, ia], st[_E, ia]))
    pb = p0 if sb == 0 else (p1 if sb == 1 else _known(
        st[_X, ib], st[_Y, ib], st[_VX, ib], st[_VY, ib], st[_W, ib], st[_AX, ib],
        st[_AY, ib], st[_E, ib]))
    jk = jt[j2, 0]
    px, py = _wpt(st[_X, ib], st[_Y, ib], st[_C, ib], st[_SN, ib], jf[j2, _PBX], jf[j2, _PBY])
    ux, uy = _rot(st[_C, ia], st[_SN, ia], jf[j2, _UX], jf[j2, _UY])
    a11, a12, r1, a21, a22, r2 = _closure(jk, px, py, ux, uy, pa, sa, pb, sb, False)
    z0, z1 = _cramer(a11, a12, r1, a21, a22, r2, n_unk, scale)
    p0 = _with_z(p0, z0)
    st[_VX, b1], st[_VY, b1], st[_W, b1] = _velocity(p0, x1, y1)
    if n_unk == 2:
        p1 = _with_z(p1, z1)
        st[_VX, b2], st[_VY, b2], st[_W, b2] = _velocity(p1, st[_X, b2], st[_Y, b2])
    pa = p0 if sa == 0 else (p1 if sa == 1 else pa)
    pb = p0 if sb == 0 else (p1 if sb == 1 else pb)
    a11, a12, r1, a21, a22, r2 = _closure(jk, px, py, ux, uy, pa, sa, pb, sb, True)
    zd0, zd1 = _cramer(a11, a12, r1, a21, a22, r2, n_unk, scale)
    st[_AX, b1], st[_AY, b1], st[_E, b1] = _acceleration(p0, zd0, x1, y1)
    if n_unk == 2:
        st[_AX, b2], st[_AY, b2], st[_E, b2] = _acceleration(p1, zd1, st[_X, b2], st[_Y, b2])


# ---------------------------------------------------------------------------------------------
# the kernel
def _data_typing(typingctx: Any, arr: Any) -> Any:
    """The data pointer of an array (for a :func:`numba.carray` view over it: a view that
    holds no reference, so numba adjusts no reference count where it is handed on)."""
    sig = types.CPointer(arr.dtype)(arr)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        ary = context.make_array(signature.args[0])(context, builder, value=args[0])
        return ary.data
    return sig, codegen


_data: Any = intrinsic(_data_typing)


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
    ``out`` (9, nb, m, n), ``pos_bad, bad`` (m, n), ``failed, parallel`` (ng,) flags. ``jt``
    and each design's block of ``jf`` and ``gf`` are C-contiguous (read through their data
    pointers)."""
    nb = out.shape[1]
    m, n = q.shape
    ng = gt.shape[0]
    # the state and the tables as views that hold no reference: numba adjusts the reference
    # count of every array handed to the inlined per-group functions otherwise (measured: ~10%
    # of the kernel's time); ``state`` is kept alive by its use after the loops
    state = np.zeros((11, nb))
    st = carray(_data(state), (11, nb))
    jt = carray(_data(jt), jt.shape)
    nj = jf.shape[1]
    for i in range(m):
        jfi = carray(_data(jf[i]), (nj, _NJF))
        gfi = carray(_data(gf[i]), (ng, 8))
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
            if b:
                out[:, :, i, k] = math.nan
            else:
                for body in range(nb):
                    out[0, body, i, k] = st[_X, body]
                    out[1, body, i, k] = st[_Y, body]
                    out[2, body, i, k] = st[_T, body]
                    out[3, body, i, k] = st[_VX, body]
                    out[4, body, i, k] = st[_VY, body]
                    out[5, body, i, k] = st[_W, body]
                    out[6, body, i, k] = st[_AX, body]
                    out[7, body, i, k] = st[_AY, body]
                    out[8, body, i, k] = st[_E, body]
    state[_C, 0] = 1.0  # the state's buffer alive until here (``st`` holds no reference)


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
