"""Machine dynamics: the periodic solve against time-marching to the same periodicity.

For the bundled examples driven by a motor (the file's ``[drive]`` where it has one, else the
motor named below), the steady state of the machine unit is found two ways from the same
reduced model (:func:`linkwork.machine.machine`: J, dJ/dphi and the reduced moments at the
grid's positions, done once and timed apart as "reduction (shared)"):

``periodic solve``   :func:`linkwork.machine.steady.solve_steady` (Hermite-Simpson collocation
                     over one revolution, Newton with a cyclic sparse LU), ``dynamics=False``;
``solve_ivp``        SciPy's ``solve_ivp`` (DOP853, rtol 1e-10) on y = (phi, omega) in time
                     from the same initial speed (the motor's stable speed at the mean load),
                     revolution after revolution (a terminal event at every turn), until the
                     speed at the start of a revolution changes by less than ``--tol``
                     (1e-8) of itself from the previous one; its right-hand side evaluates the
                     same torque balance with J, dJ/dphi (cubic Hermite) and the moments
                     (Akima, both sides of a load's jump kept) interpolated between the
                     grid's positions.

Both are compared with a reference, the periodic solve on a grid four times finer (its error
estimate ~1e-12): the largest deviation of omega(phi) over the revolution relative to the mean
speed (the periodic solve at the nodes both grids share; solve_ivp at the reference's nodes,
from 50 001 samples of its last revolution). Reported: time (median, min and max of
``--repeat``), right-hand-side evaluations (solve_ivp: calls; periodic solve: Newton steps, each
evaluating all positions at once), revolutions marched, and the speed-up ``solve_ivp /
periodic`` of the medians. Target (issue 15): at least 20x at the same accuracy.

Usage::

    .venv/bin/python benchmarks/machine.py               # plain table
    .venv/bin/python benchmarks/machine.py --markdown --json out.json
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RPM = math.pi / 30


@dataclass
class Case:
    name: str
    build: Callable[[int], Any]   # n -> Machine


def _fourbar(motor: Any, gear: Any, flywheel: float) -> Callable[[int], Any]:
    def build(n: int) -> Any:
        from linkwork import io
        from linkwork.machine import machine

        doc = io.load(EXAMPLES / "fourbar_paper001.toml")
        return machine(doc.mechanism(), motor, loads=doc.loads, gravity=(0.0, -9.81),
                       flywheel=flywheel, gear=gear, n=n)
    return build


def _sixbar(n: int) -> Any:
    from linkwork import io
    from linkwork.machine import machine
    from linkwork.studies.dynamics import breaks_of

    doc = io.load(EXAMPLES / "loom_sixbar.toml")
    d = doc.drive
    return machine(doc.mechanism(), d.motors()[0], loads=doc.loads,
                   gravity=doc.analysis.gravity, flywheel=41.8, gear=d.build_gear(), n=n,
                   breaks=breaks_of(doc))


def _sine_press(n: int) -> Any:
    from linkwork import io
    from linkwork.machine import machine, press_modes
    from linkwork.models.variable_structure import VariableStructureMechanism

    doc = io.load(EXAMPLES / "sine_press.toml")
    press = VariableStructureMechanism(doc.crank.L1, doc.idle.lambda2, doc.idle.lambda_e,
                                       doc.working.alpha, f_slot=doc.working.f_slot,
                                       f_guide=doc.working.f_guide)
    work = list(press_modes(press, **doc.press.masses()).values())[1]
    d = doc.drive
    return machine(work.mechanism, d.motors()[0], loads=work.loads, gravity=work.gravity,
                   flywheel=d.flywheel or 0.0, gear=d.build_gear(), n=n, breaks=work.breaks)


def _sine_press_planar(n: int) -> Any:
    from linkwork import io
    from linkwork.machine import Gear, InductionMotor, machine
    from linkwork.studies.dynamics import breaks_of

    doc = io.load(EXAMPLES / "sine_press_planar.toml")
    motor = InductionMotor(1500.0, 1500 * RPM, 1410 * RPM, 2.6, inertia=0.004)
    return machine(doc.mechanism(), motor, loads=doc.loads, gravity=doc.analysis.gravity,
                   flywheel=1.5, gear=Gear(11.75, 0.95, 0.001), n=n, breaks=breaks_of(doc))


def cases() -> list[Case]:
    from linkwork.machine import DCMotor, Gear, InductionMotor

    return [
        Case("four-bar (paper 001), DC motor, no flywheel",
             _fourbar(DCMotor(20.0, 12.0, inertia=0.01), Gear(), 0.0)),
        Case("four-bar, DC motor, flywheel 1 kg m^2 (slow to settle)",
             _fourbar(DCMotor(20.0, 12.0, inertia=0.01), Gear(), 1.0)),
        Case("four-bar, induction 250 W, gear 14, flywheel 0.05 kg m^2",
             _fourbar(InductionMotor(250.0, 1500 * RPM, 1400 * RPM, 2.4, inertia=5e-4),
                      Gear(14.0, 0.95, 1e-4), 0.05)),
        Case("knuckle six-bar (loom_sixbar [drive]), flywheel 41.8 kg m^2", _sixbar),
        Case("sine press, working mode (sine_press [press], [drive])", _sine_press),
        Case("sine press in the engine (sine_press_planar), 1.5 kW", _sine_press_planar),
    ]


# ---------------------------------------------------------------------------------------------
def time_marching(m: Any, w0: float, tol: float, max_revolutions: int = 5000
                  ) -> tuple[Any, int, int, Callable[[np.ndarray], np.ndarray]]:
    """solve_ivp revolution after revolution from (phi0, w0) until the speed at the start of a
    revolution changes by less than ``tol`` of itself. Returns (last omega0, RHS evaluations,
    revolutions, omega(phi) over the last revolution)."""
    from scipy.integrate import solve_ivp
    from scipy.interpolate import Akima1DInterpolator, CubicHermiteSpline

    g = m.grid
    d = m.drive
    order = np.argsort(g.pts, kind="stable")
    x = g.pts[order]
    P = g.period
    ext = np.concatenate((x[-8:] - P, x, x[:8] + P))

    def periodic(values: np.ndarray) -> np.ndarray:
        v = values[order]
        return np.concatenate((v[-8:], v, v[:8]))

    keep = np.concatenate(([True], np.diff(ext) > 0))
    Jint = CubicHermiteSpline(ext[keep], periodic(m.J + d.J_out)[keep], periodic(m.dJ)[keep])
    dJint = Jint.derivative()
    Mint = Akima1DInterpolator(ext[keep], periodic(m.M_loads + m.M_gravity)[keep])
    Dint = None if m.damping is None else Akima1DInterpolator(ext[keep], periodic(m.damping)[keep])
    phi0 = float(g.nodes[0])
    i, eta, b = d.ratio, d.eta, d.J_in * d.ratio
    mot = d.motor
    count = [0]

    def eps(phi: float, w: float) -> float:
        count[0] += 1
        p = phi0 + (phi - phi0) % P
        J, dJ, M = float(Jint(p)), float(dJint(p)), float(Mint(p))
        a = float(mot.torque(i * w))
        c = 0.5 * dJ * w * w - M + (0.0 if Dint is None else float(Dint(p)) * w)
        k = i * eta if a * J + b * c >= 0 else i / eta
        return (k * a - c) / (k * b + J)

    def rhs(t: float, y: np.ndarray) -> list[float]:
        return [y[1], eps(y[0], y[1])]

    w = w0
    last = None
    for rev in range(1, max_revolutions + 1):
        start = phi0 + 2 * math.pi * (rev - 1)

        def turn(t: float, y: np.ndarray, start: float = start) -> float:
            return y[0] - (start + 2 * math.pi)
        turn.terminal = True  # type: ignore[attr-defined]
        turn.direction = 1  # type: ignore[attr-defined]
        sol = solve_ivp(rhs, (0.0, 1e6), [start, w], method="DOP853", rtol=1e-10,
                        atol=[1e-12, 1e-12 * w], events=turn, dense_output=True)
        w_new = float(sol.y_events[0][0][1])
        last = sol
        if abs(w_new - w) <= tol * abs(w_new):
            w = w_new
            break
        w = w_new
    assert last is not None
    ts = np.linspace(0.0, float(last.t_events[0][0]), 50_001)
    yy = last.sol(ts)

    def omega_of(phi: np.ndarray) -> np.ndarray:
        return np.interp(phi, yy[0] - 2 * math.pi * (rev - 1), yy[1])

    return w, count[0], rev, omega_of


def _timed(fn: Callable[[], Any], repeat: int) -> tuple[list[float], Any]:
    """(min, median, max) of ``repeat`` calls [s] and the last result."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return [min(times), statistics.median(times), max(times)], out


def run(n: int = 360, repeat: int = 3, tol: float = 1e-8, names: list[str] | None = None
        ) -> list[dict[str, Any]]:
    from linkwork.machine.steady import _guess, check_feasible, solve_steady

    rows = []
    for case in cases():
        if names and not any(s in case.name for s in names):
            continue
        case.build(n)  # warm up: imports, caches
        t_red, m = _timed(lambda case=case: case.build(n), 1)
        ref = solve_steady(case.build(4 * n), dynamics=False)
        t_per, ss = _timed(lambda m=m: solve_steady(m, dynamics=False), repeat)
        w0 = _guess(m, check_feasible(m))[0]
        t_ivp, (_, nfev, revs, omega_of) = _timed(
            lambda m=m, w0=w0: time_marching(m, w0, tol), repeat)
        # at the positions the two grids share (the finer one holds the coarser's nodes but
        # those it moved next to a load's jump)
        k = np.searchsorted(ref.phi1, ss.phi1).clip(0, ref.phi1.size - 1)
        common = np.abs(ref.phi1[k] - ss.phi1) <= 1e-12
        err_per = float(np.max(np.abs(ss.omega[common] - ref.omega[k[common]])))
        err_per /= ref.omega_mean
        err_ivp = float(np.max(np.abs(omega_of(ref.phi1) - ref.omega))) / ref.omega_mean
        points = ss.iterations * 3 * m.grid.n
        rows.append({"case": case.name, "n": m.grid.n, "reduction_s": t_red[1],
                     "periodic_s": t_per, "periodic_newton": ss.iterations,
                     "periodic_points": points, "periodic_error": err_per,
                     "ivp_s": t_ivp, "ivp_rhs": nfev, "ivp_revolutions": revs,
                     "ivp_error": err_ivp, "speedup": t_ivp[1] / t_per[1], "delta": ss.delta})
    return rows


def table(rows: list[dict[str, Any]], markdown: bool = False) -> str:
    heads = ["case", "reduction (shared) [ms]", "periodic solve [ms] median (min-max)",
             "Newton steps", "its error", "solve_ivp [ms] median (min-max)", "RHS calls",
             "revolutions", "its error", "speed-up (medians)"]
    lines = []
    def spread(t: list[float], d: int) -> str:
        return f"{1e3 * t[1]:.{d}f} ({1e3 * t[0]:.{d}f}-{1e3 * t[2]:.{d}f})"

    fmt = [lambda r: r["case"], lambda r: f"{1e3 * r['reduction_s']:.1f}",
           lambda r: spread(r["periodic_s"], 1), lambda r: str(r["periodic_newton"]),
           lambda r: f"{r['periodic_error']:.1e}", lambda r: spread(r["ivp_s"], 0),
           lambda r: str(r["ivp_rhs"]), lambda r: str(r["ivp_revolutions"]),
           lambda r: f"{r['ivp_error']:.1e}", lambda r: f"{r['speedup']:.0f}x"]
    if markdown:
        lines.append("| " + " | ".join(heads) + " |")
        lines.append("|" + "---|" * len(heads))
        for r in rows:
            lines.append("| " + " | ".join(f(r) for f in fmt) + " |")
    else:
        for r in rows:
            lines.append("; ".join(f"{h}: {f(r)}" for h, f in zip(heads, fmt, strict=True)))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=360, help="positions a revolution")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tol", type=float, default=1e-8, help="periodicity of time-marching")
    ap.add_argument("--cases", nargs="*", help="substrings of the case names to run")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    rows = run(a.n, a.repeat, a.tol, a.cases)
    print(table(rows, a.markdown))
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
