"""The engine's kinematics compiled by numba: one pass over the (design, position) elements.

:func:`encode` turns a mechanism's compiled plan (:class:`~linkwork.planar.structure.Plan`)
once into flat arrays: the joints' kinds and bodies and the groups' kinds, bodies and joints
(the plan's *structure*), and per design the joints' local geometry and the groups' constant
geometry. :func:`kernel_source` writes, for a structure, the kernel that runs every group of
every element (design ``i``, position ``k``) in order: the positions of its bodies, then (all
groups again) their velocities and accelerations, written straight into the result block
``out[quantity, body, i, k]`` (quantities ``X Y T VX VY W AX AY E``), with the element's masks
(``pos_bad``: it does not assemble; ``bad``: that or a singular rate) and the groups where an
element first failed (``failed``) or two lines were parallel (``parallel``), for the same
AssemblyError as the NumPy path. The kernel is generated, compiled and cached once per
structure (:mod:`~linkwork.planar.compiled.codegen`): every four-bar, of any dimensions, alone
or in a batch, runs the same compiled kernel.

Same conventions and the same arithmetic as the NumPy path, element by element
(:mod:`~linkwork.planar.positions`: loci circle/line, their intersection, the body's angle from
the circle's radius vector; :mod:`~linkwork.planar.rates`: each body of a group hung on its
known neighbour with one unknown rate, the closure rows of the joint between them, Cramer's rule
with the same singularity tests): the results agree with it to rounding (numba's ``cos``,
``sin``, ``atan2`` may differ from NumPy's in the last bit).

Compiled plans (:func:`covered`): one or several drivers (each a crank on a revolute joint or a
linear driver on a prismatic one, a group of its own, with its own coordinate, speed and
acceleration) and any sequence of the closed-form dyads RRR, RRP, PRR, RPR, RPP, PPR, PRP and
one-body slot groups RS, PS, on revolute, prismatic and pin-in-slot joints. Any other plan
(Newton groups, driven cylinders, gears) is left to the NumPy path, which
:func:`linkwork.planar.kinematics` then runs transparently.

Written for numba's sake: the helpers below take and return numbers only (a body's pose ``x,
y, cos, sin``; a body hung on its neighbour as a tuple of 16 numbers that carries the
neighbour's state), and the generated kernel calls them with the structure's constants (which
joint, which side, which kind), so that the compiler removes every branch the structure decides
and keeps each body's state in registers. The writers :func:`_write_positions` and
:func:`_write_rates` take those decisions, one group at a time.

This module imports numba: it is imported only when ``backend="numba"`` is asked for.
"""

from __future__ import annotations

import functools
import math
import sys
import weakref
from typing import Any

import numpy as np
from numba import njit

from linkwork.planar.compiled.codegen import (
    Source,
    call,
    decorator,
    fingerprint,
    loop,
    structure_kernel,
)
from linkwork.planar.joints import PinInSlot, Prismatic, ResolvedJoint, Revolute
from linkwork.planar.structure import Plan, PlanGroup

__all__ = ["Encoded", "covered", "encode", "kernel", "kernel_source", "run"]

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
           ) -> tuple[float, float, float, float, float, float, float]:
    """The locus of the point ``(pix, piy)`` of a body allowed by its external joint (revolute
    ``rev`` or a line; the body its b if ``is_b``; the known other body's pose ``ox, oy, oc,
    os`` and angle ``ot``; the joint's points on it ``pk`` and on the body ``ps``): (A, radius
    ``rad``, 0) a circle about the pivot, or (B0, u) a line, then the body's angle, its cosine
    and sine (a line's only)."""
    ax, ay = _wpt(ox, oy, oc, os, pkx, pky)
    if rev:
        return ax, ay, rad, 0.0, 0.0, 1.0, 0.0
    th = _angle_of(is_b, ot, ot, rel)
    c, s = math.cos(th), math.sin(th)
    if is_b:  # the slider on its known guide a
        ux, uy = _rot(oc, os, ux, uy)
    else:  # the guide; the known body's point slides on it
        ux, uy = _rot(c, s, ux, uy)
    rx, ry = _rot(c, s, pix - psx, piy - psy)
    return ax + rx, ay + ry, ux, uy, th, c, s


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
def _finish_circle(ax: float, ay: float, rad: float, phi0: float, c0: float, s0: float,
                   pix: float, piy: float, bx: float, by: float
                   ) -> tuple[float, float, float, float, float, float]:
    """The pose of a body whose point ``(pix, piy)`` is at ``(bx, by)`` on the circle of
    centre ``(ax, ay)`` and radius ``rad`` about its pivot, without its angle: the radius
    vector's direction (ex, ey), whose ``atan2(ey, ex) - phi0`` is the angle (``phi0`` the
    angle of the point seen from the pivot in the body's frame; ``c0, s0`` its cosine and
    sine), then the body's cosine, sine and origin."""
    ex, ey = (bx - ax) / rad, (by - ay) / rad
    if phi0 != 0.0:
        c = ex * c0 + ey * s0
        s = ey * c0 - ex * s0
    else:
        c, s = ex, ey
    x, y = _origin(c, s, pix, piy, bx, by)
    return ex, ey, c, s, x, y


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


# ---------------------------------------------------------------------------------------------
# the kernel, generated per plan structure (:mod:`~linkwork.planar.compiled.codegen`): the
# writers below take every decision of the structure (joint kinds, bodies, group kinds) and
# write the helpers' calls with their constants; a body's state is the local variables
# x<b> y<b> t<b> c<b> s<b> vx<b> vy<b> w<b> ax<b> ay<b> e<b>, a joint's geometry j<q>_<field>,
# a group's g<gi>_<column>, read once per design
#: positions of one design per block of the kernel's outer loop (its unit of work on a thread;
#: a call has at most as many threads as blocks)
BLOCK = 512
_JFIELDS = ("qax", "qay", "pbx", "pby", "ang", "ux", "uy", "rel", "crel", "srel", "nlx", "nly")
_STATE = ("x", "y", "t", "c", "s", "vx", "vy", "w", "ax", "ay", "e")
_HELPERS = ("_wpt", "_origin", "_rot", "_locus", "_intersect", "_finish_circle",
            "_rotating_line", "_line_condition", "_two_lines", "_hang", "_known", "_with_z",
            "_velocity", "_acceleration", "_closure", "_cramer")


def _j(q: int, field: str) -> str:
    return f"j{q}_{field}"


def _pose(b: int) -> str:
    """A body's pose as the helpers take it: x, y, cos, sin."""
    return f"x{b}, y{b}, c{b}, s{b}"


def _ends_of(is_b: bool, q: int) -> tuple[str, str, str, str]:
    """``_ends``: the joint's point on the known body, then on the body (b if ``is_b``)."""
    qa, pb = (_j(q, "qax"), _j(q, "qay")), (_j(q, "pbx"), _j(q, "pby"))
    return (*qa, *pb) if is_b else (*pb, *qa)


class _Angles:
    """The bodies' angles as the writers use them: the bodies whose angle another group reads
    (``reads``), the bodies placed on a circle locus (``circles``: body -> (group, column of
    its ``phi0`` in the group geometry)), and those whose angle the kernel leaves to
    :func:`run` (``deferred``: on a circle, read by no group; the kernel writes the radius
    vector's direction, ``ey`` into the angle's row and ``ex`` into ``ang``, and ``run``
    takes ``arctan2(ey, ex) - phi0`` over all elements at once: NumPy's vectorised arctan2
    is about 9x faster than libm's, element by element)."""

    def __init__(self, deferred: frozenset[int] = frozenset()) -> None:
        self.reads: set[int] = set()
        self.circles: dict[int, tuple[int, int]] = {}
        self.deferred = deferred

    def t(self, b: int) -> str:
        self.reads.add(b)
        return f"t{b}"

    def circle(self, src: Source, b: int, gi: int, col: int, args: str) -> None:
        """Body ``b`` placed on the circle of group ``gi`` (``args``: those of
        :func:`_finish_circle`)."""
        self.circles[b] = (gi, col)
        if b in self.deferred:
            src(f"ex{b}, ey{b}, c{b}, s{b}, x{b}, y{b} = _finish_circle({args})")
        else:
            g = f"g{gi}_"
            src(f"ex, ey, c{b}, s{b}, x{b}, y{b} = _finish_circle({args})",
                f"t{b} = math.atan2(ey, ex)",
                f"if {g}{col} != 0.0:",
                f"    t{b} = t{b} - {g}{col}")


def _write_positions(src: Source, jt: np.ndarray, gi: int, row: Any, angles: _Angles
                     ) -> None:
    """The poses of the bodies of group ``gi`` (``_positions`` of the interpreter, its
    branches taken here); sets ``f<gi>, par<gi>`` (failed, parallel)."""
    kind, b1, b2, j1, j2, j3 = (int(v) for v in row)
    g = f"g{gi}_"
    if kind == _DRIVER:  # driver j2 of the drivers (its coordinate qk<j2>)
        ia, ib = int(jt[j1, 1]), int(jt[j1, 2])
        is_b = b1 == ib
        k = ia if is_b else ib
        sign = 1.0 if is_b else -1.0
        pkx, pky, pux, puy = _ends_of(is_b, j1)
        rev = jt[j1, 0] == _R
        src(f"th = {angles.t(k)} + {sign!r} * ({f'qk{j2}' if rev else _j(j1, 'rel')})",
            "cc, ss = math.cos(th), math.sin(th)",
            f"wx, wy = _wpt({_pose(k)}, {pkx}, {pky})")
        if not rev:  # the guide's direction in a, turned by a's angle
            ca = f"c{ia}, s{ia}" if is_b else "cc, ss"
            src(f"ux, uy = _rot({ca}, {_j(j1, 'ux')}, {_j(j1, 'uy')})",
                f"wx, wy = wx + {sign!r} * qk{j2} * ux, wy + {sign!r} * qk{j2} * uy")
        src(f"x, y = _origin(cc, ss, {pux}, {puy}, wx, wy)",
            f"t{b1}, c{b1}, s{b1}, x{b1}, y{b1} = th, cc, ss, x, y",
            f"f{gi} = par{gi} = False")
        return
    if kind == _DYAD_R:
        p1 = (_j(j2, "qax"), _j(j2, "qay")) if b1 == jt[j2, 1] else (_j(j2, "pbx"), _j(j2, "pby"))
        p2 = (_j(j2, "pbx"), _j(j2, "pby")) if b2 == jt[j2, 2] else (_j(j2, "qax"), _j(j2, "qay"))
        ks = []
        for side, (b, jj, p, rad) in enumerate(((b1, j1, p1, 0), (b2, j3, p2, 4)), start=1):
            ia, ib = int(jt[jj, 1]), int(jt[jj, 2])
            o = ia if b == ib else ib
            pkx, pky, psx, psy = _ends_of(b == ib, jj)
            rev = bool(jt[jj, 0] == _R)
            ks.append(0 if rev else 1)
            src(f"lx{side}, ly{side}, lc{side}, ld{side}, lt{side}, lco{side}, lsi{side} = "
                f"_locus({rev}, {b == ib}, {_pose(o)}, {'0.0' if rev else angles.t(o)}, "
                f"{pkx}, {pky}, {psx}, {psy}, "
                f"{_j(jj, 'ux')}, {_j(jj, 'uy')}, {_j(jj, 'rel')}, {p[0]}, {p[1]}, {g}{rad})")
        src(f"bx, by, f{gi}, par{gi} = _intersect({ks[0]}, lx1, ly1, lc1, ld1, {ks[1]}, lx2, "
            f"ly2, lc2, ld2, br{gi})")
        for side, (b, p, col) in enumerate(((b1, p1, 1), (b2, p2, 5)), start=1):
            if ks[side - 1] == 0:
                angles.circle(src, b, gi, col, f"lx{side}, ly{side}, lc{side}, {g}{col}, "
                              f"{g}{col + 1}, {g}{col + 2}, {p[0]}, {p[1]}, bx, by")
            else:  # on a line: the angle the locus gave, the origin from the point
                src(f"t{b}, c{b}, s{b} = lt{side}, lco{side}, lsi{side}",
                    f"x{b}, y{b} = _origin(c{b}, s{b}, {p[0]}, {p[1]}, bx, by)")
        return
    if kind in (_DYAD_RPR, _DYAD_PP):
        ga, sb = int(jt[j2, 1]), int(jt[j2, 2])  # the internal pair's guide and slider bodies
        rg, rs = (j1, j3) if ga == b1 else (j3, j1)
        if kind == _DYAD_RPR:  # the guide pinned at A, the slider at C
            ia, ib = int(jt[rg, 1]), int(jt[rg, 2])
            o = ib if ga == ia else ia
            pkx, pky, alx, aly = _ends_of(ga != ia, rg)
            src(f"ax_, ay_ = _wpt({_pose(o)}, {pkx}, {pky})")
            ia, ib = int(jt[rs, 1]), int(jt[rs, 2])
            o = ib if sb == ia else ia
            pkx, pky, clx, cly = _ends_of(sb != ia, rs)
            src(f"cx, cy = _wpt({_pose(o)}, {pkx}, {pky})",
                f"cr, sr = {_j(j2, 'crel')}, {_j(j2, 'srel')}",
                f"px, py = {_j(j2, 'pbx')} - {clx}, {_j(j2, 'pby')} - {cly}",
                "rpx, rpy = cr * px - sr * py, sr * px + cr * py",
                f"h = ({_j(j2, 'nlx')} * ({_j(j2, 'qax')} - {alx} - rpx) + {_j(j2, 'nly')} * "
                f"({_j(j2, 'qay')} - {aly} - rpy))",
                f"f{gi}, th, cc, ss, x, y = _rotating_line(ax_, ay_, {alx}, {aly}, "
                f"{_j(j2, 'ang')}, h, cx, cy, br{gi})",
                f"t{ga}, c{ga}, s{ga}, x{ga}, y{ga} = th, cc, ss, x, y",
                f"th = th + {_j(j2, 'rel')}",
                "cc, ss = math.cos(th), math.sin(th)",
                f"x, y = _origin(cc, ss, {clx}, {cly}, cx, cy)",
                f"t{sb}, c{sb}, s{sb}, x{sb}, y{sb} = th, cc, ss, x, y",
                f"par{gi} = False")
            return
        if jt[rg, 0] == _P:  # both angles from the prismatic pairs, the slider pinned
            src(f"th = {_angle_expr(ga == jt[rg, 2], jt[rg], rg, angles)}",
                f"t{ga}, c{ga}, s{ga} = th, math.cos(th), math.sin(th)",
                f"th = th + {_j(j2, 'rel')}",
                f"t{sb}, c{sb}, s{sb} = th, math.cos(th), math.sin(th)")
            pinned, free, rp, rf = sb, ga, rs, rg
        else:
            src(f"th = {_angle_expr(sb == jt[rs, 2], jt[rs], rs, angles)}",
                f"t{sb}, c{sb}, s{sb} = th, math.cos(th), math.sin(th)",
                f"th = th - {_j(j2, 'rel')}",
                f"t{ga}, c{ga}, s{ga} = th, math.cos(th), math.sin(th)")
            pinned, free, rp, rf = ga, sb, rg, rs
        ia, ib = int(jt[rp, 1]), int(jt[rp, 2])
        o = ib if pinned == ia else ia
        pkx, pky, plx, ply = _ends_of(pinned != ia, rp)
        src(f"px, py = _wpt({_pose(o)}, {pkx}, {pky})",
            f"x{pinned}, y{pinned} = _origin(c{pinned}, s{pinned}, {plx}, {ply}, px, py)")
        ja, jb = rf, j2
    elif kind == _SLOT_P:  # one body with a prismatic pair j1 and a pin-in-slot j2
        free = b1
        src(f"th = {_angle_expr(b1 == jt[j1, 2], jt[j1], j1, angles)}",
            f"t{b1}, c{b1}, s{b1} = th, math.cos(th), math.sin(th)")
        ja, jb = j1, j2
    else:  # one body with a revolute pair j1 and a pin-in-slot j2
        ia, ib = int(jt[j1, 1]), int(jt[j1, 2])
        o = ib if b1 == ia else ia
        pkx, pky, alx, aly = _ends_of(b1 != ia, j1)
        src(f"ax_, ay_ = _wpt({_pose(o)}, {pkx}, {pky})")
        ia, ib = int(jt[j2, 1]), int(jt[j2, 2])
        if b1 == ia:  # the body carries the slot; the pin X is known
            src(f"xx, xy = _wpt({_pose(ib)}, {_j(j2, 'pbx')}, {_j(j2, 'pby')})",
                f"h = {_j(j2, 'nlx')} * ({_j(j2, 'qax')} - {alx}) + {_j(j2, 'nly')} * "
                f"({_j(j2, 'qay')} - {aly})",
                f"f{gi}, th, cc, ss, x, y = _rotating_line(ax_, ay_, {alx}, {aly}, "
                f"{_j(j2, 'ang')}, h, xx, xy, br{gi})",
                f"t{b1}, c{b1}, s{b1}, x{b1}, y{b1} = th, cc, ss, x, y",
                f"par{gi} = False")
            return
        src(f"qx, qy = _wpt({_pose(ia)}, {_j(j2, 'qax')}, {_j(j2, 'qay')})",
            f"ux, uy = _rot(c{ia}, s{ia}, {_j(j2, 'ux')}, {_j(j2, 'uy')})",
            f"bx, by, f{gi}, par{gi} = _intersect(0, ax_, ay_, {g}0, 0.0, 1, qx, qy, ux, uy, "
            f"br{gi})",
        )
        angles.circle(src, b1, gi, 1, f"ax_, ay_, {g}0, {g}1, {g}2, {g}3, {_j(j2, 'pbx')}, "
                      f"{_j(j2, 'pby')}, bx, by")
        return
    # the free body's origin on the line conditions of joints ja and jb (its angle known)
    for k, jj in enumerate((ja, jb), start=1):
        ia, ib = int(jt[jj, 1]), int(jt[jj, 2])
        src(f"n{k}x, n{k}y, c{k}_ = _line_condition({free == ia}, {_pose(ia)}, {_pose(ib)}, "
            f"{_j(jj, 'qax')}, {_j(jj, 'qay')}, {_j(jj, 'pbx')}, {_j(jj, 'pby')}, "
            f"{_j(jj, 'ux')}, {_j(jj, 'uy')})")
    src(f"x{free}, y{free}, par{gi} = _two_lines(n1x, n1y, c1_, n2x, n2y, c2_)",
        f"f{gi} = par{gi}")


def _angle_expr(is_b: bool, jrow: Any, q: int, angles: _Angles) -> str:
    """``_angle_of``: the angle of a body fixed by the prismatic pair ``q`` to its other body
    (the body is b if ``is_b``: a's angle plus the relative angle; else b's minus it)."""
    if is_b:
        return f"{angles.t(int(jrow[1]))} + {_j(q, 'rel')}"
    return f"{angles.t(int(jrow[2]))} - {_j(q, 'rel')}"


def _write_rates(src: Source, jt: np.ndarray, row: Any) -> None:
    """Velocities and accelerations of the bodies of a group (``_rates`` of the interpreter,
    its branches taken here)."""
    kind, b1, b2, j1, j2, j3 = (int(v) for v in row)
    ia, ib = int(jt[j1, 1]), int(jt[j1, 2])
    k = ia if b1 == ib else ib
    sign = 1.0 if b1 == ib else -1.0
    if kind == _DRIVER and jt[j1, 0] == _R:  # the crank: closed form
        pkx, pky, pux, puy = _ends_of(b1 == ib, j1)
        src(f"w_ = w{k} + {sign!r} * wk{j2}",
            f"e_ = e{k} + {sign!r} * ek{j2}",
            f"w{b1}, e{b1} = w_, e_",
            f"rx, ry = _rot(c{k}, s{k}, {pkx}, {pky})",
            f"vpx, vpy = vx{k} - w{k} * ry, vy{k} + w{k} * rx",
            f"apx = ax{k} - e{k} * ry - w{k} * w{k} * rx",
            f"apy = ay{k} + e{k} * rx - w{k} * w{k} * ry",
            f"rx, ry = _rot(c{b1}, s{b1}, {pux}, {puy})",
            f"vx{b1}, vy{b1} = vpx + w_ * ry, vpy - w_ * rx",
            f"ax{b1} = apx + e_ * ry + w_ * w_ * rx",
            f"ay{b1} = apy - e_ * rx + w_ * w_ * ry")
        return

    def hang(name: str, jj: int, b: int) -> None:
        ia, ib = int(jt[jj, 1]), int(jt[jj, 2])
        k = ia if b == ib else ib
        pkx, pky = (_j(jj, "qax"), _j(jj, "qay")) if k == ia else (_j(jj, "pbx"), _j(jj, "pby"))
        src(f"{name} = _hang({bool(jt[jj, 0] == _R)}, {_pose(k)}, vx{k}, vy{k}, w{k}, ax{k}, "
            f"ay{k}, e{k}, {pkx}, {pky}, c{ia}, s{ia}, {_j(jj, 'ux')}, {_j(jj, 'uy')})")

    hang("p0", j1, b1)
    if kind == _DRIVER:  # a linear driver: hung
        src(f"p0 = _with_z(p0, {sign!r} * wk{j2})",
            f"vx{b1}, vy{b1}, w{b1} = _velocity(p0, x{b1}, y{b1})",
            f"ax{b1}, ay{b1}, e{b1} = _acceleration(p0, {sign!r} * ek{j2}, x{b1}, y{b1})")
        return
    n_unk = 1 if kind >= _SLOT_R else 2
    if n_unk == 2:
        hang("p1", j3, b2)
    else:
        src("p1 = p0")
    ia, ib = int(jt[j2, 1]), int(jt[j2, 2])  # the closure joint j2: the unknowns of its bodies
    sa = 0 if ia == b1 else (1 if n_unk == 2 and ia == b2 else 2)
    sb = 0 if ib == b1 else (1 if n_unk == 2 and ib == b2 else 2)
    for name, s, body in (("pa", sa, ia), ("pb", sb, ib)):
        src(f"{name} = " + (f"p{s}" if s < 2 else
                            f"_known(x{body}, y{body}, vx{body}, vy{body}, w{body}, ax{body}, "
                            f"ay{body}, e{body})"))
    jk = int(jt[j2, 0])
    src(f"px, py = _wpt({_pose(ib)}, {_j(j2, 'pbx')}, {_j(j2, 'pby')})",
        f"ux, uy = _rot(c{ia}, s{ia}, {_j(j2, 'ux')}, {_j(j2, 'uy')})",
        f"a11, a12, r1, a21, a22, r2 = _closure({jk}, px, py, ux, uy, pa, {sa}, pb, {sb}, "
        "False)",
        f"z0, z1 = _cramer(a11, a12, r1, a21, a22, r2, {n_unk}, L)",
        "p0 = _with_z(p0, z0)",
        f"vx{b1}, vy{b1}, w{b1} = _velocity(p0, x{b1}, y{b1})")
    if n_unk == 2:
        src("p1 = _with_z(p1, z1)",
            f"vx{b2}, vy{b2}, w{b2} = _velocity(p1, x{b2}, y{b2})")
    if sa < 2:
        src(f"pa = p{sa}")
    if sb < 2:
        src(f"pb = p{sb}")
    src(f"a11, a12, r1, a21, a22, r2 = _closure({jk}, px, py, ux, uy, pa, {sa}, pb, {sb}, "
        "True)",
        f"zd0, zd1 = _cramer(a11, a12, r1, a21, a22, r2, {n_unk}, L)",
        f"ax{b1}, ay{b1}, e{b1} = _acceleration(p0, zd0, x{b1}, y{b1})")
    if n_unk == 2:
        src(f"ax{b2}, ay{b2}, e{b2} = _acceleration(p1, zd1, x{b2}, y{b2})")


def kernel_source(jt: np.ndarray, gt: np.ndarray, nb: int, parallel: bool = False) -> str:
    """The source of the kernel of a plan structure (joint table ``jt``, group table ``gt``,
    ``nb`` bodies): ``kernel(jf, gf, br, scale, q, w, e, out, ang, frame, pos_bad, bad,
    failed, parallel_lines)`` with the arguments of :func:`run`'s call (``ang``: the ``ex`` of
    the angles left to :func:`run`, :func:`deferred_angles`; ``frame``: write the frame's
    rows, zeros). The elements go in blocks of :data:`BLOCK` positions of one design (each
    design's geometry read once per block), shared among numba's threads if ``parallel``."""
    src = Source()
    src(f"# generated by linkwork.planar.compiled.kinematics; helpers {_helpers_hash()}",
        "import math",
        "from numba import njit, prange",
        f"from linkwork.planar.compiled.kinematics import {', '.join(_HELPERS)}",
        "",
        "",
        decorator(parallel),
        "def kernel(jf, gf, br, scale, q, w, e, out, ang, frame, pos_bad, bad, failed,",
        "           parallel_lines):")
    src.indent()
    src("m, n = q.shape[1], q.shape[2]",
        f"nblk = (n + {BLOCK - 1}) // {BLOCK}",
        f"for job in {loop(parallel)}(m * nblk):")
    src.indent()
    src("i = job // nblk",
        f"k0 = (job - i * nblk) * {BLOCK}")
    for q in range(jt.shape[0]):
        src(", ".join(_j(q, f) for f in _JFIELDS) + " = "
            + ", ".join(f"jf[i, {q}, {c}]" for c in range(_NJF)))
    for gi in range(gt.shape[0]):
        src(", ".join(f"g{gi}_{c}" for c in range(8)) + " = "
            + ", ".join(f"gf[i, {gi}, {c}]" for c in range(8)),
            f"br{gi} = float(br[i, {gi}])")
    src("L = scale[i]",
        f"for k in range(k0, min(k0 + {BLOCK}, n)):")
    src.indent()
    for d in sorted({int(row[4]) for row in gt if row[0] == _DRIVER}):
        src(f"qk{d}, wk{d}, ek{d} = q[{d}, i, k], w[{d}, i, k], e[{d}, i, k]")
    # every body's state starts at the frame's (the frame: at rest at the origin); a body's
    # rows are set by its group before they are read, except the unknown position of a body
    # on two lines, handed to _line_condition, which does not read it
    for b in range(nb):
        src(" = ".join(f"{f}{b}" for f in _STATE if f != "c") + " = 0.0", f"c{b} = 1.0")
    src("fail = False")
    deferred = deferred_angles(jt, gt)
    angles = _Angles(frozenset(b for b, _, _ in deferred))
    for gi, row in enumerate(gt):
        _write_positions(src, jt, gi, row, angles)
        src(f"if par{gi}:", f"    parallel_lines[{gi}] = True",
            f"if f{gi} and not fail:", f"    failed[{gi}] = True", "    fail = True")
    for row in gt:
        _write_rates(src, jt, row)
    src("b = fail" + "".join(f" or not math.isfinite(w{b})" for b in range(1, nb)),
        "pos_bad[i, k] = fail",
        "bad[i, k] = b",
        "if b:",
        "    out[:, :, i, k] = math.nan",
        "else:")
    src.indent()
    src("if frame:  # the frame at rest at the origin: zeros (not written into a zeroed block)")
    src(*(f"    out[{r}, 0, i, k] = 0.0" for r in range(9)))
    for b in range(1, nb):
        src(*(f"out[{r}, {b}, i, k] = {f}{b}" for r, f in enumerate(
            ("x", "y", "ey" if b in angles.deferred else "t", "vx", "vy", "w", "ax", "ay",
             "e"))))
    for j, (b, _, _) in enumerate(deferred):
        src(f"ang[{j}, i, k] = ex{b}")
    return src.text()


def deferred_angles(jt: np.ndarray, gt: np.ndarray) -> list[tuple[int, int, int]]:
    """The bodies whose angle the kernel of this structure leaves to :func:`run` (see
    :class:`_Angles`): (body, group, column of its ``phi0`` in the group geometry), in the
    order of the kernel's ``ang`` rows; worked out once per structure."""
    return list(_deferred(jt.tobytes(), gt.tobytes()))


@functools.cache
def _deferred(jt_bytes: bytes, gt_bytes: bytes) -> tuple[tuple[int, int, int], ...]:
    jt = np.frombuffer(jt_bytes, dtype=np.int64).reshape(-1, 3)
    gt = np.frombuffer(gt_bytes, dtype=np.int64).reshape(-1, 6)
    angles = _Angles()
    scratch = Source()
    for gi, row in enumerate(gt):
        _write_positions(scratch, jt, gi, row, angles)
    return tuple((b, gi, col) for b, (gi, col) in sorted(angles.circles.items())
                 if b not in angles.reads)


@functools.cache
def _helpers_hash() -> str:
    return fingerprint(sys.modules[__name__])


def kernel(enc: Encoded, parallel: bool = False) -> Any:
    """The compiled kernel of ``enc``'s plan structure, serial or ``parallel`` (generated,
    compiled and cached once per structure: :mod:`~linkwork.planar.compiled.codegen`)."""
    return structure_kernel("kinematics", (enc.jt.tobytes(), enc.gt.tobytes(), enc.nb, parallel),
                            lambda: kernel_source(enc.jt, enc.gt, enc.nb, parallel))


# ---------------------------------------------------------------------------------------------
# the plan encoded
class Encoded:
    """A plan as the kernel reads it: joint table ``jt`` (nj, 3), joint geometry ``jf`` (m,
    nj, 12), group table ``gt`` (ng, 6), group geometry ``gf`` (m, ng, 8), length scales (m,),
    the groups' keys in order."""

    __slots__ = ("deferred", "gf", "gt", "jf", "jt", "keys", "m", "nb", "scale")

    def __init__(self, jt: np.ndarray, jf: np.ndarray, gt: np.ndarray, gf: np.ndarray,
                 scale: np.ndarray, keys: tuple[str, ...], nb: int) -> None:
        self.jt, self.jf, self.gt, self.gf, self.scale = jt, jf, gt, gf, scale
        self.keys = keys
        self.m = jf.shape[0]
        self.nb = nb
        self.deferred: list[tuple[int, Any]] | None = None  # the angles left to :func:`run`


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
        return [_DRIVER, g.bodies[0], -1, joints[id(r)], r.drive_index, -1]
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
    if plan.newton:
        return None
    joints = {id(r): k for k, r in enumerate(plan.joints)}
    kinds = [_joint_kind(r) for r in plan.joints]
    if any(k is None for k in kinds):
        return None
    rows: list[list[int]] = []
    for g in plan.groups:
        row = _group_row(g, joints)
        if row is None:
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
    return Encoded(jt, jf, gt, gf, scale, tuple(g.key for g in plan.groups), plan.nb)


def run(enc: Encoded, branches: dict[str, Any], q: np.ndarray, w: np.ndarray, e: np.ndarray,
        out: np.ndarray, zeroed: bool = False, threads: int = 1
        ) -> tuple[np.ndarray, np.ndarray, set[str], set[str]]:
    """The kernel over the elements of ``q, w, e`` (n_drivers, m, n) into ``out`` (9, nb, m,
    n):
    ``(pos_bad, bad, failed, parallel)`` (masks (m, n), sets of group keys). ``zeroed``: out
    holds zeros already, so the frame's rows are not written (a large block from
    ``np.zeros`` is memory the system maps on first write: those pages are never touched).
    ``threads`` > 1: the parallel kernel on that many of numba's threads."""
    m, n = q.shape[1:]
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
    if enc.deferred is None:  # (body, its phi0 per design or None where all are 0)
        enc.deferred = [(b, None if not enc.gf[:, gi, col].any() else enc.gf[:, gi, col, None])
                        for b, gi, col in deferred_angles(enc.jt, enc.gt)]
    ang = np.empty((len(enc.deferred), m, n))
    threads = max(1, min(threads, m * -(-n // BLOCK)))  # no more threads than blocks
    call(kernel(enc, threads > 1), threads, jf, gf, br, scale, q, w, e, out, ang, not zeroed,
         pos_bad, bad, failed, parallel)
    # the angles: arctan2(ey, ex) - phi0 (NaN where the element failed: the kernel wrote NaN
    # as ey and left ex unwritten, so no warning for what is there)
    with np.errstate(invalid="ignore"):
        for j, (b, phi0) in enumerate(enc.deferred):
            t = out[2, b]
            np.arctan2(t, ang[j], out=t)
            if phi0 is not None:
                np.subtract(t, phi0, out=t)
    return (pos_bad, bad, {k for k, f in zip(enc.keys, failed, strict=True) if f},
            {k for k, f in zip(enc.keys, parallel, strict=True) if f})
