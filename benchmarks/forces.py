"""Force-element benchmark: what springs, dampers, drags and load diagrams add to inverse dynamics.

Times, side by side in one run, :func:`linkwork.planar.inverse_dynamics` of a crank press (crank
50 mm, rod 400 mm, ram 250 kg on a vertical guide; the mechanism of
``examples/crank_press.toml`` without friction) over ``n`` crank positions of one revolution:

``no loads``               inertia and gravity only
``point force``            plus one constant point force on the ram (the loads of earlier files)
``elements``               plus a spring and a damper to the frame, a drag on the rod and the
                           drawing force as a load diagram over the ram's slide
``elements, flat NumPy``   the same four elements' forces written out flat in this file (the
                           spring's, damper's and drag's vectors, the diagram by ``np.interp``):
                           the cost of evaluating them without the library's checks and records

Before timing, the flat forces are checked against the engine's (relative 1e-12).

Usage::

    python benchmarks/forces.py                 # n = 360 and 100000
    python benchmarks/forces.py --n 3600 --repeat 9

Each sample loops long enough to take >= 20 ms; the contenders are sampled round-robin, so
that load from other processes hits all of them alike. The table gives min, median and max of
the ``--repeat`` samples per call.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from linkwork.planar import (
    Damper,
    Drag,
    LoadDiagram,
    PointForce,
    SlideForce,
    Spring,
    crank_slider_mechanism,
    inverse_dynamics,
    kinematics,
)

TABLE = ([-0.450, -0.446, -0.442, -0.438, -0.434, -0.430],
         [100e3, 150e3, 190e3, 200e3, 140e3, 0.0])


def press(n: int):
    """The press's kinematics over n positions, and its elements."""
    mech = crank_slider_mechanism(0.05, 0.4, guide_angle=np.pi / 2, masses=(40.0, 30.0, 250.0),
                                  branch=-1, omega1=2 * np.pi)
    kin = kinematics(mech, np.linspace(0.0, 2 * np.pi, n, endpoint=False))
    elements = [Spring("frame", (0.25, 0.0), "slider", (0.25, 0.0), stiffness=5e3,
                       free_length=0.4, preload=2.5e3),
                Damper("frame", (0.0, -0.6), "slider", "B", damping=200.0),
                Drag("rod", "com", force=30.0, damping=5.0),
                SlideForce("G", LoadDiagram(*TABLE, over="G", when="decreasing"))]
    return kin, elements


def flat(kin) -> list[tuple[np.ndarray, np.ndarray]]:
    """The four elements' forces (x, y) written out (world axes, on the moving body)."""
    B = kin.point("slider", "B")
    R = kin.point("slider", (0.25, 0.0))
    dx, dy = R.x - 0.25, R.y
    L = np.hypot(dx, dy)
    T = 2.5e3 + 5e3 * (L - 0.4)
    spring = (-T * dx / L, -T * dy / L)
    ex, ey = B.x, B.y + 0.6
    Ld = np.hypot(ex, ey)
    c = 200.0 * (ex * B.vx + ey * B.vy) / Ld
    damper = (-c * ex / Ld, -c * ey / Ld)
    C = kin.point("rod", "com")
    w = 1e-9 * 2 * np.pi * 0.4
    sp = np.hypot(C.vx, C.vy)
    k = 30.0 / np.sqrt(sp * sp + w * w) + 5.0
    drag = (-k * C.vx, -k * C.vy)
    s, sd = B.y, B.vy
    inside = (s >= TABLE[0][0] - 2e-11) & (s <= TABLE[0][-1] + 2e-11)
    F = np.where(inside & (sd <= 1e-9 * 2 * np.pi * 0.4), np.interp(s, *TABLE), 0.0)
    return [spring, damper, drag, (np.zeros_like(F), F)]


def check(kin, elements) -> None:
    dyn = inverse_dynamics(kin, loads=elements)
    for ap, (fx, fy) in zip(dyn.loads, flat(kin), strict=True):
        w = ap.wrenches[0]  # the force on the element's moving body
        scale = float(np.max(np.hypot(fx, fy)))
        if max(np.max(np.abs(w.fx - fx)), np.max(np.abs(w.fy - fy))) > 1e-12 * scale:
            raise SystemExit(f"the flat forces of {ap.name} disagree with the engine's")


def sample(fn: Callable[[], object]) -> float:
    """Seconds per call, looping for at least 20 ms."""
    k, t = 1, 0.0
    while True:
        t0 = time.perf_counter()
        for _ in range(k):
            fn()
        t = time.perf_counter() - t0
        if t >= 0.02:
            return t / k
        k *= 2


G = (0.0, -9.81)


def run(sizes=(360, 100_000), repeat: int = 7) -> list[dict[str, Any]]:
    rows = []
    for n in sizes:
        kin, elements = press(n)
        check(kin, elements)
        contenders = {
            "no loads": lambda kin=kin: inverse_dynamics(kin, gravity=G),
            "point force": lambda kin=kin: inverse_dynamics(
                kin, gravity=G, loads=[PointForce("slider", "B", 0.0, 1e3)]),
            "elements": lambda kin=kin, el=elements: inverse_dynamics(kin, gravity=G,
                                                                        loads=el),
            "elements, flat NumPy": lambda kin=kin: flat(kin),
        }
        times: dict[str, list[float]] = {k: [] for k in contenders}
        for _ in range(repeat):
            for name, fn in contenders.items():
                times[name].append(sample(fn))
        for name, ts in times.items():
            rows.append({"n": n, "contender": name, "min": min(ts),
                         "median": statistics.median(ts), "max": max(ts)})
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    out = ["| n | contender | min [ms] | median [ms] | max [ms] |", "|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['n']} | {r['contender']} | {1e3 * r['min']:.3g} | "
                   f"{1e3 * r['median']:.3g} | {1e3 * r['max']:.3g} |")
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="*", default=[360, 100_000])
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    print(table(run(tuple(args.n), args.repeat)))


if __name__ == "__main__":
    main()
