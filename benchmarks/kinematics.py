"""Kinematics benchmark: linkwork's closed forms and planar engine against the same algorithms
written flat, fused compiled loops with the same outputs, and pylinkage.

Cases, over ``n`` crank positions of one revolution (four-bar of paper 001, a, b, c, d = 0.1,
0.3, 0.2, 0.3 m; offset crank-slider, crank 0.05 m, rod 0.2 m, offset 0.015 m; 10 rad/s):

``four-bar closed form`` :func:`linkwork.models.fourbar.fourbar` (10 outputs and the mask)
    against ``flat NumPy`` (its algorithm written flat: no checks, no blocks, no result object)
    and ``fused numba loop`` (:mod:`_fused`, the same outputs by the same algorithm: the
    practical limit); ``textbook NumPy`` (Norton's Eqs. (4.10), (6.18), (7.12): ten
    transcendentals per position against five) as information.
``crank-slider closed form`` :func:`linkwork.models.crank_slider.offset_crank_slider` (14
    outputs) against the same three (the textbook form computes 6 outputs: information).
``four-bar engine`` :func:`linkwork.planar.kinematics` on ``fourbar_mechanism`` (pose,
    velocity, acceleration of every body: 9 arrays of (4, n)) against a fused numba loop with
    those outputs; pylinkage's numba loop (``step_fast_with_kinematics``; its own outputs, joint
    positions, velocities, accelerations) and its pure-Python run as anchors.
``four-bar engine + reactions`` the same plus :func:`linkwork.planar.inverse_dynamics` against
    a fused loop that computes both (every reaction, point, the driving torque, shaking force
    and moment, kinetic energy); ``engine + reactions (numba backend)``: the reactions by
    ``backend="numba"``; the reactions alone (the motion solved before the timed call) by
    either backend, and ``closed form + reactions``
    (:func:`linkwork.models.fourbar.fourbar_kinetostatics`) as information.
``crank-slider engine`` (and + reactions), pylinkage: information.
``four-bar designs`` ``--designs`` Grashof crank-rockers x 360 positions: the closed form in one
    broadcast call (dimensions of shape (m, 1)) against the engine's batch call (one
    ``fourbar_mechanism`` of dimensions over the m designs, one ``kinematics``: arrays (nb, m,
    n)), the mechanism built inside the timed call; the loop of one mechanism and one call per
    design as information. ``four-bar, one position`` the engine's fixed cost per call.
``backend=numba`` rows: the engine's compiled backend (:mod:`linkwork.planar.compiled`; numba
    installed) beside the NumPy engine in the engine, designs and fixed-cost cases, judged
    against the same targets; its compilation (first call with an empty numba cache and no
    generated kernel, in a fresh process) and a later process's first call (cache loaded)
    printed once as information. ``..., 2 threads`` rows: the compiled backend with
    ``threads=2`` (numba's threads; information, judged apart: the references run on one
    thread).

Agreement: before timing, at every case and size timed, every output of every contender is
compared with the reference (the first contender of the case; pylinkage on joint B) to 1e-9 of
the largest value of that output (angles modulo 2 pi); a disagreement aborts.

Timing: ``--repeat`` rounds (default 7; ``--long-repeat`` for calls over 1 s), one sample of
every contender of a case per round (each sample looping >= 20 ms), so load from other
processes hits them alike; every time is printed as min / median / max over the rounds, every
ratio as min / median / max of the per-round ratios. The targets (issues 3 and 20) are judged
against that spread: ``met`` (every round), ``met by the median only``, ``missed``.

Usage::

    python benchmarks/kinematics.py                      # n = 360 and 100000, all cases
    python benchmarks/kinematics.py --markdown --json out.json
    python benchmarks/kinematics.py --n 360 --no-numba-off --designs 1000
    python benchmarks/kinematics.py --no-pylinkage --no-fused   # without the bench extra
    python benchmarks/kinematics.py --no-compiled               # without backend="numba"
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import (
    Spread,
    finish,
    fmt_spread,
    load,
    max_rel_diff,
    ratio,
    time_rounds,
    verdict,
)

FOURBAR = (0.1, 0.3, 0.2, 0.3)          # a, b, c, d [m] (paper 001's example)
SLIDER = (0.05, 0.2, 0.015)             # crank r, rod l, guide offset e [m]; guide x = e
OMEGA = 10.0                            # [rad/s]
MASSES = (1.0, 3.0, 2.0)                # for the reactions [kg]
RTOL = 1e-9
TARGET_N = 100_000                      # the engine targets are set at this n


# ---------------------------------------------------------------------------------------------
# plain hand-written NumPy closed forms (the baseline)
# ---------------------------------------------------------------------------------------------


def numpy_fourbar(t2: np.ndarray, a: float, b: float, c: float, d: float,
                  w2: float) -> tuple[np.ndarray, ...]:
    """Norton's textbook four-bar, open circuit: angles, rates, points A and B."""
    k1, k2, k3 = d / a, d / c, (a * a - b * b + c * c + d * d) / (2 * a * c)
    k4, k5 = d / b, (c * c - d * d - a * a - b * b) / (2 * a * b)
    c2, s2 = np.cos(t2), np.sin(t2)
    A = c2 - k1 - k2 * c2 + k3
    B = -2 * s2
    C = k1 - (k2 + 1) * c2 + k3
    D = c2 - k1 + k4 * c2 + k5
    E = -2 * s2
    F = k1 + (k4 - 1) * c2 + k5
    t4 = 2 * np.arctan2(-B - np.sqrt(B * B - 4 * A * C), 2 * A)
    t3 = 2 * np.arctan2(-E - np.sqrt(E * E - 4 * D * F), 2 * D)
    s3, c3, s4, c4 = np.sin(t3), np.cos(t3), np.sin(t4), np.cos(t4)
    w3 = a * w2 / b * np.sin(t4 - t2) / np.sin(t3 - t4)
    w4 = a * w2 / c * np.sin(t2 - t3) / np.sin(t4 - t3)
    aa, bb, dd, ee = c * s4, b * s3, c * c4, b * c3
    cc = a * w2 * w2 * c2 + b * w3 * w3 * c3 - c * w4 * w4 * c4      # alpha2 = 0
    ff = -a * w2 * w2 * s2 - b * w3 * w3 * s3 + c * w4 * w4 * s4
    den = aa * ee - bb * dd
    al3 = (cc * dd - aa * ff) / den
    al4 = (cc * ee - bb * ff) / den
    return t3, t4, w3, w4, al3, al4, a * c2, a * s2, d + c * c4, c * s4


def numpy_fourbar_vector(t2: np.ndarray, a: float, b: float, c: float, d: float,
                         w2: float) -> tuple[np.ndarray, ...]:
    """The same outputs by the vector (circle-intersection) form that ``fourbar()`` uses,
    written flat: no argument checks, no blocks, no result object; the assembly test (one
    reduction of the Heron term) as the eleventh output. Measures the library's overhead."""
    ax, ay = a * np.cos(t2), a * np.sin(t2)
    sx, sy = d - ax, -ay                                  # A -> O4
    f2 = sx * sx + sy * sy
    k = (b * b - c * c + f2) / (2 * f2)
    h2 = b * b / f2 - k * k
    ok = bool(h2.min() >= 0.0)
    h = np.sqrt(h2)
    ux, uy = k * sx - h * sy, k * sy + h * sx             # B - A
    vx, vy = ux - sx, uy - sy                             # B - O4
    den = ux * vy - uy * vx
    w3 = w2 * (vx * ay - vy * ax) / den
    w4 = w2 * (ux * ay - uy * ax) / den
    gx = w2 * w2 * ax + w3 * w3 * ux - w4 * w4 * vx
    gy = w2 * w2 * ay + w3 * w3 * uy - w4 * w4 * vy
    al3 = (gx * vx + gy * vy) / den
    al4 = (gx * ux + gy * uy) / den
    return (np.arctan2(uy, ux), np.arctan2(vy, vx), w3, w4, al3, al4, ax, ay, vx + d, vy, ok)


def numpy_slider(t: np.ndarray, r: float, l: float, e: float,
                 w: float) -> tuple[np.ndarray, ...]:
    """Crank-slider, guide x = e, slider above the pin: slider y, v, a; rod angle, rate, acc."""
    c1, s1 = np.cos(t), np.sin(t)
    bx, by = r * c1, r * s1
    bvx, bvy = -w * by, w * bx                  # crank pin velocity
    bax, bay = -w * w * bx, -w * w * by         # and acceleration (eps1 = 0)
    dx = e - bx
    dy = np.sqrt(l * l - dx * dx)
    ddy = dx * bvx / dy                          # dx' = -bvx; dy' = -dx dx'/dy
    y = by + dy
    v = bvy + ddy
    dddy = -(bvx * bvx - dx * bax + ddy * ddy) / dy
    acc = bay + dddy
    th = np.arctan2(dy, dx)
    om = (dx * ddy + dy * bvx) / (l * l)
    al = (dx * dddy + dy * bax) / (l * l)
    return y, v, acc, th, om, al


def numpy_slider_same_outputs(t: np.ndarray, r: float, l: float, e: float,
                              w: float) -> tuple[np.ndarray, ...]:
    """Every output of ``offset_crank_slider`` (pin and slider positions, rod angle, transfer
    functions, velocities, accelerations, pressure angle), written flat: no argument checks, no
    assembly check, no result object.  Measures the library's own overhead."""
    lam2, lame = l / r, e / r
    c1, s1 = np.cos(t), np.sin(t)
    s2 = (lame - c1) / lam2
    c2 = np.sqrt(1.0 - s2 * s2)
    phi2 = np.arcsin(s2)
    xb, yb = r * c1, r * s1
    yc = yb + l * c2
    xc = np.full(t.shape, e)
    inv = 1.0 / (lam2 * c2)
    u21 = s1 * inv
    u21sq = u21 * u21
    ls2 = l * s2
    vq = xb - ls2 * u21
    eq2 = (c1 + lam2 * s2 * u21sq) * inv
    aq = -(yb + l * c2 * u21sq + ls2 * eq2)
    return (xb, yb, xc, yc, phi2, u21, vq, eq2, aq, u21 * w, eq2 * (w * w), vq * w,
            aq * (w * w), np.abs(phi2))


# ---------------------------------------------------------------------------------------------
# contenders
# ---------------------------------------------------------------------------------------------


@dataclass
class Contender:
    """One way to compute a case. ``output(result)`` gives its outputs in the case's order;
    ``expect(reference_result, reference_outputs)`` what it must equal (default the reference
    outputs); ``role``:
    ``"ref"`` (the case's reference: the library call), ``"same"`` (same algorithm and outputs),
    ``"limit"`` (fused loop, same outputs), ``"info"`` (another algorithm or other outputs)."""

    name: str
    run: Callable[[], Any]
    output: Callable[[Any], tuple[Any, ...]]
    role: str = "same"
    expect: Callable[[Any, tuple[Any, ...]], tuple[Any, ...]] | None = None
    compiled: bool = False   # numba compiles it at its first call: run once before timing


@dataclass
class Case:
    name: str
    n: int
    contenders: list[Contender]
    angles: tuple[int, ...] = ()     # indices of the reference outputs that are angles
    per: int = 0                     # positions per call (for ns/position); default n
    groups: tuple[tuple[int, ...], ...] = ()  # outputs that share a scale (vectors)


def _angles(n: int) -> np.ndarray:
    return np.arange(n) * (2 * math.pi / n)


def _fused() -> Any:
    """The fused loops (numba), or None when numba is not installed."""
    try:
        import _fused
    except ImportError:
        return None
    return _fused


def _have_numba() -> bool:
    """Whether numba is installed (the engine's compiled backend, backend="numba")."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _compiled_engine(name: str, run: Callable[[], Any], output: Callable[[Any], Any]
                     ) -> Contender:
    return Contender(name, run, output, compiled=True)


def threads() -> int:
    """The threads of the compiled backend's threaded rows: 2, or numba's thread count if
    lower (1: no threaded rows)."""
    import numba

    return min(2, int(numba.config.NUMBA_NUM_THREADS))


def fourbar_case(n: int, fused: bool = True) -> Case:
    from linkwork.models.fourbar import fourbar

    t = _angles(n)
    a, b, c, d = FOURBAR
    cons = [Contender("closed form", lambda: fourbar(t, a, b, c, d, OMEGA),
                      lambda r: (r.theta3, r.theta4, r.omega3, r.omega4, r.eps3, r.eps4,
                                 r.xA, r.yA, r.xB, r.yB), "ref"),
            Contender("flat NumPy, same algorithm", lambda: numpy_fourbar_vector(t, a, b, c, d,
                                                                                  OMEGA),
                      lambda r: r[:10])]
    fz = _fused() if fused else None
    if fz is not None:
        cons.append(Contender("fused numba loop", lambda: fz.fourbar(t, a, b, c, d, OMEGA),
                              lambda r: tuple(r[0]), "limit"))
    cons.append(Contender("textbook NumPy (Norton)", lambda: numpy_fourbar(t, a, b, c, d, OMEGA),
                          lambda r: r[:10], "info"))
    return Case("four-bar closed form", n, cons, angles=(0, 1))


def slider_case(n: int, fused: bool = True) -> Case:
    from linkwork.models.crank_slider import offset_crank_slider

    t = _angles(n)
    r_, l_, e_ = SLIDER
    cons = [Contender("closed form", lambda: offset_crank_slider(t, r_, l_ / r_, e_ / r_, OMEGA),
                      lambda r: (r.X_B, r.Y_B, r.X_C, r.Y_C, r.phi2, r.U21, r.V_qC, r.eps_q2,
                                 r.a_qC, r.omega2, r.eps2, r.V_C, r.a_C, r.pressure_angle),
                      "ref"),
            Contender("flat NumPy, same algorithm",
                      lambda: numpy_slider_same_outputs(t, r_, l_, e_, OMEGA), lambda r: r)]
    fz = _fused() if fused else None
    if fz is not None:
        cons.append(Contender("fused numba loop", lambda: fz.crank_slider(t, r_, l_, e_, OMEGA),
                              lambda r: tuple(r[0]), "limit"))
    cons.append(Contender("textbook NumPy (6 outputs)",
                          lambda: numpy_slider(t, r_, l_, e_, OMEGA),
                          lambda r: (r[0], r[1], r[2]), "info",
                          lambda _, ref: (ref[3], ref[11], ref[12])))
    return Case("crank-slider closed form", n, cons)


_KIN = ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps")
_DYN = ("fx", "fy", "px", "py")
_SCALARS = ("Q", "shaking_fx", "shaking_fy", "shaking_m", "T")


def engine_case(n: int, reactions: bool, fused: bool = True, pylinkage: bool = False,
                compiled: bool = True) -> Case:
    from linkwork.planar import fourbar_mechanism, inverse_dynamics, kinematics

    t = _angles(n)
    a, b, c, d = FOURBAR
    mech = fourbar_mechanism(a, b, c, d, masses=MASSES, omega1=OMEGA)

    def kin_out(k: Any) -> tuple[Any, ...]:
        return tuple(getattr(k, q) for q in _KIN)

    if reactions:
        def eng(_: Any = None) -> Any:
            return inverse_dynamics(kinematics(mech, t))

        def eng_out(dyn: Any) -> tuple[Any, ...]:
            return (*kin_out(dyn.kinematics), *(getattr(dyn, q) for q in _DYN),
                    *(getattr(dyn, q) for q in _SCALARS))
    else:
        def eng(_: Any = None) -> Any:
            return kinematics(mech, t)

        eng_out = kin_out
    cons = [Contender("engine + reactions" if reactions else "engine", eng, eng_out, "ref")]
    if compiled and not reactions and _have_numba():
        cons.append(_compiled_engine("engine, backend=numba",
                                     lambda: kinematics(mech, t, backend="numba"), kin_out))
        if (k := threads()) > 1:
            cons.append(Contender(f"engine, backend=numba, {k} threads",
                                  lambda: kinematics(mech, t, backend="numba", threads=k),
                                  kin_out, "info", compiled=True))
    fz = _fused() if fused else None
    if fz is not None:
        def fused_out(r: Any) -> tuple[Any, ...]:
            kin, dyn, sc, _ = r
            return (*kin, *dyn, *sc) if reactions else tuple(kin)

        cons.append(Contender("fused numba loop", lambda: fz.engine_fourbar(
            t, a, b, c, d, OMEGA, MASSES, reactions), fused_out, "limit"))
        if reactions:
            cons += reaction_backends(mech, t, eng_out)
    if reactions:
        from linkwork.models.fourbar import fourbar_kinetostatics

        inert = tuple(m * x * x / 12.0 for m, x in zip(MASSES, FOURBAR[:3], strict=True))
        cons.append(Contender("closed form + reactions (Q checked)",
                              lambda: fourbar_kinetostatics(t, a, b, c, d, OMEGA, mass=MASSES,
                                                            inertia=inert),
                              lambda f: (f.Q,), "info",
                              lambda _, ref: (ref[len(_KIN) + len(_DYN)],)))
    if pylinkage:
        def joint_b(res: Any, _: Any) -> tuple[Any, ...]:
            p = (res.kinematics if reactions else res).point("rocker", "B")
            return p.x, p.y, p.vx, p.vy, p.ax, p.ay

        cons.append(_pylinkage_fourbar(n, joint_b))
    groups = ((0, 1), (3, 4), (6, 7)) + (((9, 10), (11, 12), (14, 15)) if reactions else ())
    return Case("four-bar engine + reactions" if reactions else "four-bar engine", n, cons,
                angles=(2,), groups=groups)


def reaction_backends(mech: Any, t: np.ndarray, out: Callable[[Any], tuple[Any, ...]]
                      ) -> list[Contender]:
    """The compiled backend of :func:`linkwork.planar.inverse_dynamics` beside the NumPy engine
    (issue 20 item 2): the engine with its reactions by ``backend="numba"`` (the kinematics by
    the NumPy engine), both by ``backend="numba"``, and the reactions alone on a motion solved
    before the timed call, by each backend: the two parts apart. Compiled (and loaded from
    numba's cache) here, before the check and the timing."""
    from linkwork.planar import inverse_dynamics, kinematics

    kin = kinematics(mech, t)
    inverse_dynamics(kin, backend="numba")
    inverse_dynamics(kinematics(mech, t, backend="numba"), backend="numba")
    k = threads()
    threaded = [] if k < 2 else [Contender(
        f"engine + reactions, both by numba, {k} threads",
        lambda: inverse_dynamics(kinematics(mech, t, backend="numba", threads=k),
                                 backend="numba", threads=k), out, "info", compiled=True)]
    cons = [Contender("engine + reactions (numba backend)",
                      lambda: inverse_dynamics(kinematics(mech, t), backend="numba"), out),
            Contender("engine + reactions, both by numba",
                      lambda: inverse_dynamics(kinematics(mech, t, backend="numba"),
                                               backend="numba"), out),
            Contender("reactions alone, NumPy backend", lambda: inverse_dynamics(kin), out,
                      "info"),
            Contender("reactions alone, numba backend",
                      lambda: inverse_dynamics(kin, backend="numba"), out, "info")]
    return cons + threaded


def slider_engine_case(n: int, reactions: bool, pylinkage: bool = False) -> Case:
    from linkwork.models.crank_slider import offset_crank_slider
    from linkwork.planar import crank_slider_mechanism, inverse_dynamics, kinematics

    t = _angles(n)
    r_, l_, e_ = SLIDER
    # engine guide: direction (cos ga, sin ga) = +y, offset measured to its left (-x)
    mech = crank_slider_mechanism(r_, l_, -e_, guide_angle=math.pi / 2, masses=MASSES,
                                  omega1=OMEGA)

    def slider(k: Any) -> tuple[Any, ...]:
        p = k.point("slider", "B")
        return p.x, p.y, p.vx, p.vy, p.ax, p.ay

    if reactions:
        cons = [Contender("engine + reactions", lambda: inverse_dynamics(kinematics(mech, t)),
                          lambda dyn: slider(dyn.kinematics), "ref")]
    else:
        cons = [Contender("engine", lambda: kinematics(mech, t), slider, "ref")]
    zero = np.zeros(n)
    cons.append(Contender("closed form", lambda: offset_crank_slider(t, r_, l_ / r_, e_ / r_,
                                                                     OMEGA),
                          lambda r: (zero + e_, r.Y_C, zero, r.V_C, zero, r.a_C), "info"))
    if pylinkage:
        cons.append(_pylinkage_slider(n))
    return Case("crank-slider engine + reactions" if reactions else "crank-slider engine", n,
                cons, groups=_PAIRS)


def designs(m: int, seed: int = 3) -> tuple[np.ndarray, ...]:
    """``m`` Grashof crank-rockers around paper 001's (crank the shortest link, every one
    turns fully, none passes a toggle): a, b, c, d [m], shape (m,)."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.08, 0.11, m)
    b = rng.uniform(0.28, 0.34, m)
    c = rng.uniform(0.18, 0.24, m)
    d = rng.uniform(0.27, 0.32, m)
    return a, b, c, d


def designs_case(m: int, n: int = 360, compiled: bool = True) -> Case:
    from linkwork.models.fourbar import fourbar
    from linkwork.planar import fourbar_mechanism, kinematics

    t = _angles(n)
    a, b, c, d = designs(m)
    col = (a[:, None], b[:, None], c[:, None], d[:, None])

    def closed() -> Any:
        return fourbar(t, *col, OMEGA)

    def closed_out(r: Any) -> tuple[Any, ...]:
        return r.theta3, r.theta4, r.omega3, r.omega4, r.eps3, r.eps4

    def loop() -> list[Any]:
        return [kinematics(fourbar_mechanism(a[i], b[i], c[i], d[i], omega1=OMEGA), t)
                for i in range(m)]

    def loop_out(ks: list[Any]) -> tuple[Any, ...]:
        return tuple(np.stack([getattr(k, q)[row] for k in ks])
                     for q, row in (("theta", 2), ("theta", 3), ("omega", 2), ("omega", 3),
                                    ("eps", 2), ("eps", 3)))

    def batch() -> Any:
        return kinematics(fourbar_mechanism(a, b, c, d, omega1=OMEGA), t)

    def batch_out(k: Any) -> tuple[Any, ...]:
        return tuple(getattr(k, q)[row] for q, row in (
            ("theta", 2), ("theta", 3), ("omega", 2), ("omega", 3), ("eps", 2), ("eps", 3)))

    def batch_numba() -> Any:
        return kinematics(fourbar_mechanism(a, b, c, d, omega1=OMEGA), t, backend="numba")

    cons = [Contender("closed form, one broadcast call", closed, closed_out, "ref"),
            Contender("engine, one batch call", batch, batch_out)]
    if compiled and _have_numba():
        cons.append(_compiled_engine("engine, one batch call, backend=numba", batch_numba,
                                     batch_out))
        if (k := threads()) > 1:
            cons.append(Contender(f"engine, one batch call, backend=numba, {k} threads",
                                  lambda: kinematics(fourbar_mechanism(a, b, c, d, omega1=OMEGA),
                                                     t, backend="numba", threads=k),
                                  batch_out, "info", compiled=True))
    cons.append(Contender("engine, one call per design", loop, loop_out, "info"))
    return Case(f"four-bar designs ({m} x {n})", n, cons, angles=(0, 1), per=m * n)


def fixed_cost_case(compiled: bool = True) -> Case:
    from linkwork.models.fourbar import fourbar
    from linkwork.planar import fourbar_mechanism, kinematics

    t = np.array([0.7])
    a, b, c, d = FOURBAR
    mech = fourbar_mechanism(a, b, c, d, omega1=OMEGA)
    def out(k: Any) -> tuple[Any, ...]:
        return k.theta[3], k.omega[3], k.eps[3]

    cons = [Contender("closed form", lambda: fourbar(t, a, b, c, d, OMEGA),
                      lambda r: (r.theta4, r.omega4, r.eps4), "ref"),
            Contender("engine", lambda: kinematics(mech, t), out, "info")]
    if compiled and _have_numba():
        cons.append(Contender("engine, backend=numba",
                              lambda: kinematics(mech, t, backend="numba"), out, "info",
                              compiled=True))
    return Case("four-bar, one position (fixed cost)", 1, cons, angles=(0,))


def compile_time() -> dict[str, float]:
    """numba's compilation of the compiled kinematics, once: the first call of a fresh
    process with an empty cache (``NUMBA_CACHE_DIR`` a new directory), and the first call of
    a second process that loads that cache [s] (information, not timed in rounds)."""
    code = ("import time, numpy as np\n"
            "from linkwork.planar import fourbar_mechanism, kinematics\n"
            "m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3)\n"
            "t = np.linspace(0.0, 1.0, 5)\n"
            "t0 = time.perf_counter(); kinematics(m, t, backend='numba')\n"
            "print(time.perf_counter() - t0)\n")
    out = {}
    with tempfile.TemporaryDirectory() as cache:
        # numba's cache and linkwork's generated kernels (their files and numba's cache of
        # them) both empty
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, LINKWORK_CACHE_DIR=cache)
        for key in ("cold cache", "cache loaded"):
            res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                 text=True, check=True)
            out[key] = float(res.stdout.strip().splitlines()[-1])
    return out


# --- pylinkage ---------------------------------------------------------------------------------


def _pylinkage_fourbar(n: int, expect: Any = None) -> Contender:
    import pylinkage as pl

    a, b, c, d = FOURBAR
    step = 2 * math.pi / n
    ref = numpy_fourbar(np.array([0.0]), a, b, c, d, OMEGA)

    def build() -> Any:
        o2, o4 = pl.Ground(0.0, 0.0, name="O2"), pl.Ground(d, 0.0, name="O4")
        crank = pl.Crank(anchor=o2, radius=a, angular_velocity=step, initial_angle=-step,
                         name="crank")
        joint_b = pl.RRRDyad(anchor1=crank.output, anchor2=o4, distance1=b, distance2=c,
                             x=float(ref[8][0]), y=float(ref[9][0]), name="B")
        lk = pl.Linkage([o2, o4, crank, joint_b])
        lk.set_input_velocity(crank, omega=OMEGA, alpha=0.0)
        return lk

    state = {"lk": build()}

    def run() -> Any:
        return state["lk"].step_fast_with_kinematics(iterations=n)

    def output(res: Any) -> tuple[np.ndarray, ...]:
        pos, vel, acc = res
        return pos[:, 3, 0], pos[:, 3, 1], vel[:, 3, 0], vel[:, 3, 1], acc[:, 3, 0], acc[:, 3, 1]

    con = Contender("pylinkage (numba)", run, output, "info", expect)
    con.build = build  # type: ignore[attr-defined]
    con.state = state  # type: ignore[attr-defined]
    return con


def _pylinkage_slider(n: int, expect: Any = None) -> Contender:
    import pylinkage as pl

    r, l, e = SLIDER
    step = 2 * math.pi / n
    y0 = float(numpy_slider(np.array([0.0]), r, l, e, OMEGA)[0][0])

    def build() -> Any:
        o = pl.Ground(0.0, 0.0, name="O")
        g1, g2 = pl.Ground(e, 0.0, name="G1"), pl.Ground(e, 1.0, name="G2")
        crank = pl.Crank(anchor=o, radius=r, angular_velocity=step, initial_angle=-step,
                         name="crank")
        slider = pl.RRPDyad(revolute_anchor=crank.output, line_anchor1=g1, line_anchor2=g2,
                            distance=l, x=e, y=y0, name="slider")
        lk = pl.Linkage([o, g1, g2, crank, slider])
        lk.set_input_velocity(crank, omega=OMEGA, alpha=0.0)
        return lk

    state = {"lk": build()}

    def run() -> Any:
        return state["lk"].step_fast_with_kinematics(iterations=n)

    def output(res: Any) -> tuple[np.ndarray, ...]:
        pos, vel, acc = res
        return pos[:, 4, 0], pos[:, 4, 1], vel[:, 4, 0], vel[:, 4, 1], acc[:, 4, 0], acc[:, 4, 1]

    con = Contender("pylinkage (numba)", run, output, "info", expect)
    con.build = build  # type: ignore[attr-defined]
    con.state = state  # type: ignore[attr-defined]
    return con


def pylinkage_contender(mechanism: str, n: int) -> Contender:
    return _pylinkage_fourbar(n) if mechanism == "four-bar" else _pylinkage_slider(n)


def have_pylinkage() -> bool:
    try:
        import pylinkage  # noqa: F401
    except ImportError:
        return False
    return True


# ---------------------------------------------------------------------------------------------
# checking and timing
# ---------------------------------------------------------------------------------------------


#: x, y / vx, vy / ax, ay of a point share a scale
_PAIRS = ((0, 1), (2, 3), (4, 5))


def check(case: Case) -> tuple[dict[str, float], list[float]]:
    """One call of every contender (also its warm-up and, for numba, its compilation); each
    one's outputs against the reference's (relative to the largest value of each output,
    angles modulo 2 pi). Returns the differences and the time of each first call (numba's
    compilation excluded: that call is repeated); raises on a disagreement."""
    results, firsts = [], []
    for con in case.contenders:
        if con.role == "limit" or con.compiled:
            con.run()                    # compile
        t0 = time.perf_counter()
        res = con.run()
        firsts.append(time.perf_counter() - t0)
        if hasattr(con, "build"):        # pylinkage: a fresh linkage from the start angle
            con.state["lk"] = con.build()   # type: ignore[attr-defined]
            res = con.run()
            con.state["lk"] = con.build()   # type: ignore[attr-defined]
        results.append(res)
    ref_res = results[0]
    ref = case.contenders[0].output(ref_res)
    errs = {}
    for con, res in zip(case.contenders[1:], results[1:], strict=True):
        want = con.expect(ref_res, ref) if con.expect is not None else ref
        if con.expect is None:
            err = max_rel_diff(con.output(res), want, case.angles, case.groups)
        else:   # a point's x, y, vx, vy, ax, ay, or a few outputs
            err = max_rel_diff(con.output(res), want, (), _PAIRS if len(want) == 6 else ())
        errs[con.name] = err
        if not err <= RTOL:
            raise AssertionError(f"{case.name}, n={case.n}: {con.name} disagrees with "
                                 f"{case.contenders[0].name}: max relative difference "
                                 f"{err:.3g} > {RTOL:g}")
    return errs, firsts


def _no_numba_time(mechanism: str, n: int, repeat: int) -> Spread:
    """pylinkage with NUMBA_DISABLE_JIT=1, in a subprocess (checked there against the closed
    form's joint B); its times [s]."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    cmd = [sys.executable, os.path.abspath(__file__), "--pylinkage-only", mechanism,
           "--n", str(n), "--repeat", str(repeat)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return Spread(json.loads(out.stdout.strip().splitlines()[-1])["samples"])


def _pylinkage_only(mechanism: str, n: int, repeat: int) -> None:
    con = pylinkage_contender(mechanism, n)
    if mechanism == "four-bar":
        ref_case = fourbar_case(n, fused=False)

        def b_point(_: Any, out: tuple[Any, ...]) -> tuple[Any, ...]:
            return _rocker_point(out[8], out[9], out[3], out[5], FOURBAR[3])
    else:
        ref_case = slider_case(n, fused=False)

        def b_point(_: Any, out: tuple[Any, ...]) -> tuple[Any, ...]:
            z = np.zeros(n)
            return z + SLIDER[2], out[3], z, out[11], z, out[12]
    con.expect = b_point
    check(Case(ref_case.name, n, [ref_case.contenders[0], con]))
    print(json.dumps({"samples": time_rounds([con.run], repeat, min_time=0.0)[0].samples}))


def _rocker_point(xb: Any, yb: Any, w4: Any, al4: Any, d: float) -> tuple[np.ndarray, ...]:
    rx, ry = xb - d, yb
    return (xb, yb, -w4 * ry, w4 * rx, -al4 * ry - w4 * w4 * rx, al4 * rx - w4 * w4 * ry)


def cases(sizes: tuple[int, ...], pylinkage: bool, fused: bool, n_designs: int,
          compiled: bool = True) -> list[Case]:
    out: list[Case] = []
    for n in sizes:
        out += [fourbar_case(n, fused), slider_case(n, fused),
                engine_case(n, False, fused, pylinkage, compiled), engine_case(n, True, fused),
                slider_engine_case(n, False, pylinkage), slider_engine_case(n, True)]
    out.append(fixed_cost_case(compiled))
    if n_designs:
        out.append(designs_case(n_designs, compiled=compiled))
    return out


def run(sizes: tuple[int, ...] = (360, 100_000), repeat: int = 7, pylinkage: bool = True,
        no_numba: bool = True, no_numba_repeat: int = 3, fused: bool = True,
        n_designs: int = 10_000, long_repeat: int = 3, compiled: bool = True
        ) -> dict[str, Any]:
    """Check and time every case; return the rows (case, n, contender, role, times), the
    agreement reached and the compiled backend's compilation time (``compile``)."""
    rows: list[dict[str, Any]] = []
    agreement: dict[str, float] = {}
    compiled = compiled and _have_numba()
    compile_s = compile_time() if compiled else {}
    for case in cases(tuple(sizes), pylinkage, fused, n_designs, compiled):
        errs, firsts = check(case)
        for who, err in errs.items():
            agreement[f"{case.name}, n={case.n}: {who}"] = err
        times = time_rounds([c.run for c in case.contenders], repeat, first=firsts,
                            long_repeat=long_repeat)
        for con, sp in zip(case.contenders, times, strict=True):
            rows.append({"case": case.name, "n": case.n, "per": case.per or case.n,
                         "contender": con.name, "role": con.role, "times": sp.samples})
        if pylinkage and no_numba and case.name in ("four-bar engine", "crank-slider engine"):
            mech = case.name.split()[0]
            sp = _no_numba_time(mech, case.n, no_numba_repeat)
            rows.append({"case": case.name, "n": case.n, "per": case.n,
                         "contender": "pylinkage (no numba)", "role": "info",
                         "times": sp.samples})
    return {"rows": rows, "agreement": agreement, "compile": compile_s}


def _get(rows: list[dict[str, Any]], case: str, n: int, who: str) -> Spread | None:
    for r in rows:
        if r["case"] == case and r["n"] == n and r["contender"] == who:
            return Spread(list(r["times"]))
    return None


def table(result: dict[str, Any], markdown: bool = False) -> str:
    """Every row with min / median / max, its ratio to the case's reference (per round), and
    ns per position; then the targets judged against the spread."""
    rows = result["rows"]
    lines = []
    if markdown:
        lines += ["| case | n | contender | min / median / max | x reference (min / median / "
                  "max) | ns/position (median) |", "|---|---:|---|---:|---:|---:|"]
    else:
        lines.append(f"{'case':36s} {'n':>7s}  {'contender':38s} {'min / median / max':>34s} "
                     f"{'x reference':>20s} {'ns/pos':>8s}")
    for r in rows:
        sp = Spread(list(r["times"]))
        ref_row = next(x for x in rows if x["case"] == r["case"] and x["n"] == r["n"])
        rt = ratio(sp, Spread(list(ref_row["times"])))
        per = sp.median / r["per"] * 1e9
        name = r["contender"] + (" (info)" if r["role"] == "info" else "")
        if markdown:
            lines.append(f"| {r['case']} | {r['n']} | {name} | {fmt_spread(sp)} | "
                         f"{fmt_spread(rt, 'ratio')} | {per:.0f} |")
        else:
            lines.append(f"{r['case']:36s} {r['n']:7d}  {name:38s} {fmt_spread(sp):>34s} "
                         f"{fmt_spread(rt, 'ratio'):>20s} {per:8.0f}")
    lines += ["", *summary(rows)]
    if result.get("compile"):
        c = result["compile"]
        lines.append(f"  compiled backend (backend=\"numba\"): first call {c['cold cache']:.1f} s "
                     f"with numba's cache empty (compilation), {c['cache loaded']:.2f} s in a "
                     "later process (import and cache load; information)")
    lines += ["", "agreement (max relative difference, checked before timing at every case and "
              "size):"]
    lines += [f"  {k}: {v:.2g}" for k, v in result["agreement"].items()]
    return "\n".join(lines)


def summary(rows: list[dict[str, Any]]) -> list[str]:
    """The targets of issues 3 and 20, judged against the per-round spread of each ratio."""
    out = ["targets (ratio min / median / max over the rounds; met = every round):"]

    def judge(label: str, num: Spread | None, den: Spread | None, target: float,
              better: str = "below") -> None:
        if num is None or den is None:
            out.append(f"  {label}: not measured in this run")
            return
        r = ratio(num, den)
        sign = "<=" if better == "below" else ">="
        out.append(f"  {label} = {fmt_spread(r, 'ratio')} (target {sign} {target:g}: "
                   f"{verdict(r, target, better)})")

    sizes = sorted({r["n"] for r in rows if r["case"] == "four-bar closed form"})
    for n in sizes:
        for case in ("four-bar closed form", "crank-slider closed form"):
            lib = _get(rows, case, n, "closed form")
            judge(f"{case}, n={n}: library / flat NumPy (same algorithm, same outputs)",
                  lib, _get(rows, case, n, "flat NumPy, same algorithm"), 1.2)
            judge(f"{case}, n={n}: library / fused numba loop (information)",
                  lib, _get(rows, case, n, "fused numba loop"), math.inf)
    n = TARGET_N
    judge(f"four-bar engine kinematics, n={n}: engine / fused loop (issue 20 item 2)",
          _get(rows, "four-bar engine", n, "engine"),
          _get(rows, "four-bar engine", n, "fused numba loop"), 2.0)
    judge(f"four-bar engine kinematics, n={n}: engine (backend=numba) / fused loop (issue 20 "
          "item 2)", _get(rows, "four-bar engine", n, "engine, backend=numba"),
          _get(rows, "four-bar engine", n, "fused numba loop"), 2.0)
    judge(f"four-bar engine + reactions, n={n}: engine / fused loop (issue 20 item 2)",
          _get(rows, "four-bar engine + reactions", n, "engine + reactions"),
          _get(rows, "four-bar engine + reactions", n, "fused numba loop"), 3.0)
    rx = "four-bar engine + reactions"
    judge(f"{rx}, n={n}: engine + reactions (numba backend) / fused loop (issue 20 item 2)",
          _get(rows, rx, n, "engine + reactions (numba backend)"),
          _get(rows, rx, n, "fused numba loop"), 3.0)
    judge(f"{rx}, n={n}: kinematics and reactions both by numba / fused loop (issue 20 item 2)",
          _get(rows, rx, n, "engine + reactions, both by numba"),
          _get(rows, rx, n, "fused numba loop"), 3.0)
    k = threads() if _have_numba() else 1
    judge(f"four-bar engine kinematics, n={n}: engine (backend=numba, {k} threads) / fused loop "
          "(one thread; information)",
          _get(rows, "four-bar engine", n, f"engine, backend=numba, {k} threads"),
          _get(rows, "four-bar engine", n, "fused numba loop"), math.inf)
    judge(f"{rx}, n={n}: both by numba on {k} threads / fused loop (one thread; information)",
          _get(rows, rx, n, f"engine + reactions, both by numba, {k} threads"),
          _get(rows, rx, n, "fused numba loop"), math.inf)
    judge(f"{rx}, n={n}: reactions alone, numba / NumPy backend (information)",
          _get(rows, rx, n, "reactions alone, numba backend"),
          _get(rows, rx, n, "reactions alone, NumPy backend"), math.inf)
    judge(f"four-bar engine kinematics, n={n}: engine / pylinkage (numba) (issue 3)",
          _get(rows, "four-bar engine", n, "engine"),
          _get(rows, "four-bar engine", n, "pylinkage (numba)"), 1.0)
    judge(f"four-bar, n={n}: pylinkage (no numba) / engine (issue 3)",
          _get(rows, "four-bar engine", n, "pylinkage (no numba)"),
          _get(rows, "four-bar engine", n, "engine"), 30.0, "above")
    des = [r for r in rows if r["case"].startswith("four-bar designs")]
    if des:
        case = des[0]["case"]
        ref = _get(rows, case, des[0]["n"], "closed form, one broadcast call")
        judge(f"{case}: engine batch / closed form broadcast (issue 20 item 1)",
              _get(rows, case, des[0]["n"], "engine, one batch call"), ref, 3.0)
        judge(f"{case}: engine batch (backend=numba) / closed form broadcast (issue 20 item 1)",
              _get(rows, case, des[0]["n"], "engine, one batch call, backend=numba"), ref, 3.0)
        judge(f"{case}: engine batch (backend=numba, {k} threads) / closed form broadcast "
              "(one thread) (issue 20 item 1, on threads)",
              _get(rows, case, des[0]["n"], f"engine, one batch call, backend=numba, {k} threads"),
              ref, 3.0)
        judge(f"{case}: engine loop / closed form broadcast (information)",
              _get(rows, case, des[0]["n"], "engine, one call per design"), ref, math.inf)
    for label, case, n1, who in (
            ("engine fixed cost (one position)", "four-bar, one position (fixed cost)", 1,
             "engine"),
            ("engine (backend=numba) fixed cost (one position)",
             "four-bar, one position (fixed cost)", 1, "engine, backend=numba"),
            ("engine at 360 positions", "four-bar engine", 360, "engine"),
            ("engine (backend=numba) at 360 positions", "four-bar engine", 360,
             "engine, backend=numba")):
        sp = _get(rows, case, n1, who)
        if sp is not None:
            ok = ("met" if sp.max < 100e-6 else "met by the median only"
                  if sp.median < 100e-6 else "missed")
            out.append(f"  {label} = {fmt_spread(sp)} (target < 100 us: {ok}; issue 20 "
                       "item 1)")
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    ap.add_argument("--n", type=int, nargs="+", default=[360, 100_000], help="positions")
    ap.add_argument("--repeat", type=int, default=7, help="rounds (samples per contender)")
    ap.add_argument("--long-repeat", type=int, default=3,
                    help="rounds of calls longer than 1 s")
    ap.add_argument("--designs", type=int, default=10_000,
                    help="four-bar designs of the batch case (0: none)")
    ap.add_argument("--no-pylinkage", action="store_true", help="skip pylinkage")
    ap.add_argument("--no-numba-off", action="store_true",
                    help="skip the (slow) pylinkage run without numba")
    ap.add_argument("--no-fused", action="store_true", help="skip the fused numba loops")
    ap.add_argument("--no-compiled", action="store_true",
                    help="skip the engine's compiled backend (backend=\"numba\")")
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table")
    ap.add_argument("--json", help="also write the rows to this JSON file")
    ap.add_argument("--pylinkage-only", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.pylinkage_only:
        _pylinkage_only(args.pylinkage_only, args.n[0], args.repeat)
        return 0
    use_pl = not args.no_pylinkage and have_pylinkage()
    if not args.no_pylinkage and not use_pl:
        print("pylinkage not installed: skipped (pip install '.[bench]')", file=sys.stderr)
    fused = not args.no_fused and _fused() is not None
    if not args.no_fused and not fused:
        print("numba not installed: no fused loops (pip install '.[bench]')", file=sys.stderr)
    t0, load0 = time.perf_counter(), load()
    result = run(tuple(args.n), args.repeat, pylinkage=use_pl, no_numba=not args.no_numba_off,
                 fused=fused, n_designs=args.designs, long_repeat=args.long_repeat,
                 compiled=not args.no_compiled)
    finish(result, table(result, markdown=args.markdown),
           f"{args.repeat} rounds ({args.long_repeat} for calls > 1 s)", load0, t0, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
