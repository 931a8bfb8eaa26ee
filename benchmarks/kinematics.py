"""Kinematics benchmark: linkwork's closed forms and planar engine, plain NumPy, and pylinkage.

Times, side by side in one run, the complete kinematics (positions, velocities, accelerations)
of two mechanisms over ``n`` crank positions of one revolution:

* the four-bar of paper 001 (a, b, c, d = 0.1, 0.3, 0.2, 0.3 m), omega2 = 10 rad/s;
* an offset crank-slider (crank 0.05 m, rod 0.2 m, guide offset 0.015 m), omega1 = 10 rad/s;

with these contenders:

``closed form``          :func:`linkwork.models.fourbar.fourbar` /
                         :func:`linkwork.models.crank_slider.offset_crank_slider`
``plain NumPy``          a textbook closed form written out in this file (Norton's Eqs. (4.10),
                         (6.18), (7.12) for the four-bar; circle-line intersection for the slider)
``plain NumPy, vector form``  four-bar only: the algorithm of ``fourbar()`` written flat (no
                         checks, no blocks, no result object): the library's own overhead
``plain NumPy, same outputs``  crank-slider only: every output of ``offset_crank_slider``
                         (14 arrays against the textbook version's 6) written flat, likewise
``engine``               :func:`linkwork.planar.kinematics` on the engine model
``engine + reactions``   the same plus :func:`linkwork.planar.inverse_dynamics` (masses on)
``closed form + reactions`` :func:`linkwork.models.fourbar.fourbar_kinetostatics` (four-bar)
``pylinkage (numba)``    ``Linkage.step_fast_with_kinematics`` (numba-compiled loop)
``pylinkage (no numba)`` the same with ``NUMBA_DISABLE_JIT=1`` (run in a subprocess)

Before timing, every contender's output (slider / coupler-rocker joint B: position, velocity,
acceleration) is compared with the plain NumPy one (relative 1e-9); a disagreement aborts.

Usage::

    python benchmarks/kinematics.py                 # n = 360 and 100000, table on stdout
    python benchmarks/kinematics.py --n 360 --markdown
    python benchmarks/kinematics.py --no-pylinkage  # without the optional dependency

Medians of ``--repeat`` samples; each sample loops long enough to take >= 20 ms, and the
contenders of one case are sampled round-robin (one sample of each per round), so that load
from other processes hits all of them alike.  Ratios are
(time of the row) / (time of plain NumPy), and the summary checks the targets of issue 3:
closed forms within 1.2x of plain NumPy; the engine's four-bar kinematics at 100,000 positions
no slower than pylinkage with numba and at least 30x faster than pylinkage without numba.
It also prints, as information, each closed form's time over the same algorithm written flat
(the library's own overhead: argument checks, assembly test, result object).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

FOURBAR = (0.1, 0.3, 0.2, 0.3)          # a, b, c, d [m] (paper 001's example)
SLIDER = (0.05, 0.2, 0.015)             # crank r, rod l, guide offset e [m]; guide x = e
OMEGA = 10.0                            # [rad/s]
MASSES = (1.0, 3.0, 2.0)                # for "engine + reactions" [kg]
RTOL = 1e-9
TARGET_N = 100_000                      # the engine-against-pylinkage targets are set here


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
    written flat: no checks, no blocks, no result object.  Measures the library's overhead."""
    ax, ay = a * np.cos(t2), a * np.sin(t2)
    sx, sy = d - ax, -ay                                  # A -> O4
    f2 = sx * sx + sy * sy
    k = (b * b - c * c + f2) / (2 * f2)
    h = np.sqrt(b * b / f2 - k * k)
    ux, uy = k * sx - h * sy, k * sy + h * sx             # B - A
    vx, vy = ux - sx, uy - sy                             # B - O4
    den = ux * vy - uy * vx
    w3 = w2 * (vx * ay - vy * ax) / den
    w4 = w2 * (ux * ay - uy * ax) / den
    gx = w2 * w2 * ax + w3 * w3 * ux - w4 * w4 * vx
    gy = w2 * w2 * ay + w3 * w3 * uy - w4 * w4 * vy
    al3 = (gx * vx + gy * vy) / den
    al4 = (gx * ux + gy * uy) / den
    return (np.arctan2(uy, ux), np.arctan2(vy, vx), w3, w4, al3, al4, ax, ay, vx + d, vy)


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
# contenders: each returns (position, velocity, acceleration) of the output point for checking
# ---------------------------------------------------------------------------------------------


@dataclass
class Contender:
    name: str
    run: Callable[[], Any]
    output: Callable[[Any], tuple[np.ndarray, ...]]
    times: list[float] = field(default_factory=list)


def _angles(n: int) -> np.ndarray:
    return np.arange(n) * (2 * math.pi / n)


def fourbar_contenders(n: int, with_engine: bool = True) -> list[Contender]:
    from linkwork.models.fourbar import fourbar

    t = _angles(n)
    a, b, c, d = FOURBAR
    out: list[Contender] = []

    def plain_out(r: Any) -> tuple[np.ndarray, ...]:
        w4, al4, xb, yb = r[3], r[5], r[8], r[9]
        return _rocker_point(xb, yb, w4, al4, d)

    out.append(Contender("plain NumPy", lambda: numpy_fourbar(t, a, b, c, d, OMEGA), plain_out))
    out.append(Contender("plain NumPy, vector form",
                         lambda: numpy_fourbar_vector(t, a, b, c, d, OMEGA), plain_out))

    def closed_out(r: Any) -> tuple[np.ndarray, ...]:
        return _rocker_point(r.xB, r.yB, r.omega4, r.eps4, d)

    out.append(Contender("closed form", lambda: fourbar(t, a, b, c, d, OMEGA), closed_out))
    if with_engine:
        from linkwork.models.fourbar import fourbar_kinetostatics

        out.append(Contender("closed form + reactions",
                             lambda: fourbar_kinetostatics(t, a, b, c, d, OMEGA, mass=MASSES,
                                                           inertia=_rod_inertias()),
                             lambda f: closed_out(f.kinematics)))
        from linkwork.planar import fourbar_mechanism as engine_model
        from linkwork.planar import inverse_dynamics, kinematics

        mech = engine_model(a, b, c, d, masses=MASSES, omega1=OMEGA)

        def eng_out(k: Any) -> tuple[np.ndarray, ...]:
            p = k.point("rocker", "B")
            return p.x, p.y, p.vx, p.vy, p.ax, p.ay

        out.append(Contender("engine", lambda: kinematics(mech, t), eng_out))
        out.append(Contender("engine + reactions",
                             lambda: inverse_dynamics(kinematics(mech, t)),
                             lambda dyn: eng_out(dyn.kinematics)))
    return out


def _rod_inertias() -> tuple[float, float, float]:
    """Thin-rod centroidal inertias m l^2 / 12, as the engine's default."""
    return tuple(m * x * x / 12.0 for m, x in zip(MASSES, FOURBAR[:3], strict=True))  # type: ignore[return-value]


def _rocker_point(xb: Any, yb: Any, w4: Any, al4: Any, d: float) -> tuple[np.ndarray, ...]:
    rx, ry = xb - d, yb
    return (xb, yb, -w4 * ry, w4 * rx, -al4 * ry - w4 * w4 * rx, al4 * rx - w4 * w4 * ry)


def slider_contenders(n: int, with_engine: bool = True) -> list[Contender]:
    t = _angles(n)
    r, l, e = SLIDER
    out: list[Contender] = []
    zero = np.zeros(n)

    def plain_out(res: Any) -> tuple[np.ndarray, ...]:
        y, v, acc = res[:3]
        return zero + e, y, zero, v, zero, acc

    out.append(Contender("plain NumPy", lambda: numpy_slider(t, r, l, e, OMEGA), plain_out))

    def same_out(res: Any) -> tuple[np.ndarray, ...]:
        return res[2], res[3], zero, res[11], zero, res[12]

    out.append(Contender("plain NumPy, same outputs",
                         lambda: numpy_slider_same_outputs(t, r, l, e, OMEGA), same_out))
    try:
        from linkwork.models.crank_slider import offset_crank_slider
    except ImportError:  # the closed form is written by another helper
        offset_crank_slider = None
    if offset_crank_slider is not None:
        def closed_out(res: Any) -> tuple[np.ndarray, ...]:
            return zero + e, res.Y_C, zero, res.V_C, zero, res.a_C

        out.append(Contender("closed form",
                             lambda: offset_crank_slider(t, r, l / r, e / r, OMEGA), closed_out))
    if with_engine:
        from linkwork.planar import crank_slider_mechanism as engine_model
        from linkwork.planar import inverse_dynamics, kinematics

        # engine guide: direction (cos ga, sin ga) = +y, offset measured to its left (-x)
        mech = engine_model(r, l, -e, guide_angle=math.pi / 2, masses=MASSES, omega1=OMEGA)

        def eng_out(k: Any) -> tuple[np.ndarray, ...]:
            p = k.point("slider", "B")
            return p.x, p.y, p.vx, p.vy, p.ax, p.ay

        out.append(Contender("engine", lambda: kinematics(mech, t), eng_out))
        out.append(Contender("engine + reactions",
                             lambda: inverse_dynamics(kinematics(mech, t)),
                             lambda dyn: eng_out(dyn.kinematics)))
    return out


# --- pylinkage ---------------------------------------------------------------------------------


def _pylinkage_fourbar(n: int) -> Contender:
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

    con = Contender("pylinkage", run, output)
    con.build = build  # type: ignore[attr-defined]
    con.state = state  # type: ignore[attr-defined]
    return con


def _pylinkage_slider(n: int) -> Contender:
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

    con = Contender("pylinkage", run, output)
    con.build = build  # type: ignore[attr-defined]
    con.state = state  # type: ignore[attr-defined]
    return con


def pylinkage_contender(mechanism: str, n: int) -> Contender:
    return _pylinkage_fourbar(n) if mechanism == "four-bar" else _pylinkage_slider(n)


# ---------------------------------------------------------------------------------------------
# checking and timing
# ---------------------------------------------------------------------------------------------


def check(contenders: list[Contender], reference: tuple[np.ndarray, ...], label: str) -> None:
    """Compare each contender's output point with the reference; raise on disagreement."""
    for con in contenders:
        res = con.run()
        if hasattr(con, "build"):      # pylinkage: check a fresh linkage from the start angle
            con.state["lk"] = con.build()   # type: ignore[attr-defined]
            res = con.run()
            con.state["lk"] = con.build()   # type: ignore[attr-defined]
        got = con.output(res)
        for i, (what, g, r) in enumerate(zip(("x", "y", "vx", "vy", "ax", "ay"), got, reference,
                                             strict=True)):
            pair = reference[2 * (i // 2): 2 * (i // 2) + 2]     # (x, y), (vx, vy), (ax, ay)
            scale = max(float(np.abs(pair[0]).max()), float(np.abs(pair[1]).max()))
            err = float(np.abs(np.asarray(g) - r).max()) / scale
            if not err <= RTOL:
                raise AssertionError(f"{label}: {con.name} disagrees with plain NumPy in {what}: "
                                     f"max relative difference {err:.3g} > {RTOL:g}")


def time_it(fn: Callable[[], Any], repeat: int, min_time: float = 0.02) -> float:
    """Median time of one call [s] over ``repeat`` samples of >= ``min_time`` each."""
    t0 = time.perf_counter()
    fn()
    single = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(min_time / single))
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        samples.append((time.perf_counter() - t0) / number)
    return statistics.median(samples)


def time_interleaved(fns: list[Callable[[], Any]], repeat: int,
                     min_time: float = 0.02) -> list[float]:
    """Median time of one call [s] of each function, sampled round-robin.

    Each round takes one sample (>= ``min_time``) of every function in turn, so a burst of load
    from other processes affects all contenders alike and the ratios stay meaningful.
    """
    numbers = []
    for fn in fns:
        t0 = time.perf_counter()
        fn()
        numbers.append(max(1, int(min_time / max(time.perf_counter() - t0, 1e-7))))
    samples: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for i, fn in enumerate(fns):
            t0 = time.perf_counter()
            for _ in range(numbers[i]):
                fn()
            samples[i].append((time.perf_counter() - t0) / numbers[i])
    return [statistics.median(x) for x in samples]


def _no_numba_times(mechanism: str, n: int, repeat: int) -> float:
    """pylinkage with NUMBA_DISABLE_JIT=1, in a subprocess; returns the median time [s]."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    cmd = [sys.executable, os.path.abspath(__file__), "--pylinkage-only", mechanism,
           "--n", str(n), "--repeat", str(repeat)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return float(json.loads(out.stdout.strip().splitlines()[-1])["median"])


def _pylinkage_only(mechanism: str, n: int, repeat: int) -> None:
    con = pylinkage_contender(mechanism, n)
    ref_con = (fourbar_contenders if mechanism == "four-bar" else slider_contenders)(
        n, with_engine=False)[0]
    check([con], ref_con.output(ref_con.run()), f"{mechanism}, n={n}, no numba")
    print(json.dumps({"median": time_it(con.run, repeat, min_time=0.0)}))


def have_pylinkage() -> bool:
    try:
        import pylinkage  # noqa: F401
    except ImportError:
        return False
    return True


def run(sizes: tuple[int, ...] = (360, 100_000), repeat: int = 7, pylinkage: bool = True,
        no_numba: bool = True, no_numba_repeat: int = 3) -> list[dict[str, Any]]:
    """Check and time every contender; return rows (mechanism, n, contender, median [s])."""
    rows: list[dict[str, Any]] = []
    for mechanism, make in (("four-bar", fourbar_contenders), ("crank-slider", slider_contenders)):
        for n in sizes:
            cons = make(n)
            if pylinkage:
                pc = pylinkage_contender(mechanism, n)
                pc.name = "pylinkage (numba)"
                cons.append(pc)
            ref = cons[0].output(cons[0].run())
            check(cons, ref, f"{mechanism}, n={n}")
            times = time_interleaved([con.run for con in cons], repeat)
            for con, t in zip(cons, times, strict=True):
                rows.append({"mechanism": mechanism, "n": n, "contender": con.name,
                             "median_s": t})
            if pylinkage and no_numba:
                t = _no_numba_times(mechanism, n, no_numba_repeat)
                rows.append({"mechanism": mechanism, "n": n, "contender": "pylinkage (no numba)",
                             "median_s": t})
    return rows


def _fmt_time(s: float) -> str:
    if s < 1e-3:
        return f"{s * 1e6:.1f} us"
    if s < 1.0:
        return f"{s * 1e3:.2f} ms"
    return f"{s:.2f} s"


def table(rows: list[dict[str, Any]], markdown: bool = False) -> str:
    """Render the rows with ratios to plain NumPy, plus the target summary."""
    lines = []
    if markdown:
        lines += ["| mechanism | n | contender | median | x plain NumPy | ns/position |",
                  "|---|---:|---|---:|---:|---:|"]
    else:
        lines.append(f"{'mechanism':13s} {'n':>7s}  {'contender':24s} {'median':>10s} "
                     f"{'x NumPy':>8s} {'ns/pos':>9s}")
    for r in rows:
        base = next(x["median_s"] for x in rows if x["mechanism"] == r["mechanism"]
                    and x["n"] == r["n"] and x["contender"] == "plain NumPy")
        ratio = r["median_s"] / base
        per = r["median_s"] / r["n"] * 1e9
        if markdown:
            lines.append(f"| {r['mechanism']} | {r['n']} | {r['contender']} | "
                         f"{_fmt_time(r['median_s'])} | {ratio:.2f} | {per:.0f} |")
        else:
            lines.append(f"{r['mechanism']:13s} {r['n']:7d}  {r['contender']:24s} "
                         f"{_fmt_time(r['median_s']):>10s} {ratio:8.2f} {per:9.0f}")
    lines.append("")
    lines += summary(rows)
    return "\n".join(lines)


def summary(rows: list[dict[str, Any]]) -> list[str]:
    """The targets of issue 3, checked against the measured medians."""
    def get(mech: str, n: int, who: str) -> float | None:
        for r in rows:
            if r["mechanism"] == mech and r["n"] == n and r["contender"] == who:
                return float(r["median_s"])
        return None

    out = ["targets (issue 3):"]
    info = []
    for r in rows:
        if r["contender"] != "closed form":
            continue
        base = get(r["mechanism"], r["n"], "plain NumPy")
        if base is not None:
            ratio = r["median_s"] / base
            out.append(f"  {r['mechanism']:13s} n={r['n']:<7d} closed form / plain NumPy = "
                       f"{ratio:5.2f}  (target <= 1.2: {'met' if ratio <= 1.2 else 'MISSED'})")
        for flat in ("plain NumPy, vector form", "plain NumPy, same outputs"):
            base = get(r["mechanism"], r["n"], flat)
            if base is not None:
                info.append(f"  {r['mechanism']:13s} n={r['n']:<7d} closed form / {flat:25s} = "
                            f"{r['median_s'] / base:5.2f}")
    eng = get("four-bar", TARGET_N, "engine")
    pn = get("four-bar", TARGET_N, "pylinkage (numba)")
    pp = get("four-bar", TARGET_N, "pylinkage (no numba)")
    if eng is None or (pn is None and pp is None):
        out.append(f"  engine against pylinkage: set at n = {TARGET_N}, not measured in this "
                   "run (needs that n and pylinkage installed)")
    if eng is not None and pn is not None:
        out.append(f"  four-bar n={TARGET_N}: engine / pylinkage(numba) = {eng / pn:.2f}  "
                   f"(target <= 1: {'met' if eng <= pn else 'MISSED'})")
    if eng is not None and pp is not None:
        out.append(f"  four-bar n={TARGET_N}: pylinkage(no numba) / engine = {pp / eng:.1f}  "
                   f"(target >= 30: {'met' if pp / eng >= 30 else 'MISSED'})")
    if info:
        out += ["library overhead over the same algorithm written flat (no checks, no result "
                "object; information, not a target):", *info]
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, nargs="+", default=[360, 100_000], help="positions")
    ap.add_argument("--repeat", type=int, default=7, help="samples per median")
    ap.add_argument("--no-pylinkage", action="store_true", help="skip pylinkage")
    ap.add_argument("--no-numba-off", action="store_true",
                    help="skip the (slow) pylinkage run without numba")
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
    rows = run(tuple(args.n), args.repeat, pylinkage=use_pl, no_numba=not args.no_numba_off)
    import numpy
    print(f"numpy {numpy.__version__}, python {sys.version.split()[0]}, "
          f"{os.cpu_count()} CPUs; medians of {args.repeat} samples")
    print(table(rows, markdown=args.markdown))
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
