"""``linkwork dynamics FILE.toml``: the machine unit with its motor(s), gear and flywheel.

Reads a ``planar`` or ``sine_press`` file with a ``[drive]`` table (:mod:`linkwork.io.drive`;
a sine press also a ``[press]`` table), runs :func:`linkwork.studies.dynamics.run` and prints:
the motors with their steady-state figures (mean speed, delta, mean power, RMS and peak torque
and where, limit, start-up time) and one verdict line each; the flywheel sizing for a ``delta``
(exact, energy method, Wittenbauer, with their deviations); the real motion of the first motor
against the constant-speed assumption (peaks of driving torque, reactions, shaking); the energy
per cycle; the schedule revolution by revolution with its switches. Writes into ``--out``:
``dynamics.json`` (everything), ``dynamics_motor<k>.csv`` (the steady state of motor k over the
crank angle), ``dynamics_startup.csv``, ``dynamics_schedule.csv``, and the plots
``dynamics_speed.png`` (omega(phi) of every motor), ``dynamics_torque.png`` (their torques with
limits), ``dynamics_energy_mass.png`` (Wittenbauer's diagram, with ``delta``),
``dynamics_startup.png`` and ``dynamics_schedule.png`` (omega(t) and torque(t), switches
marked). Long transients show a progress bar on a terminal.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import output_run
from linkwork.cli._console import console as make_console
from linkwork.cli._console import counting, steps
from linkwork.cli._format import fmt, scale_of
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.results import write_csv, write_json
from linkwork.studies import dynamics as study_dynamics
from linkwork.studies.dynamics import DynamicsStudy, steady_columns

__all__ = ["load_dynamics_file", "register", "render"]

RPM = 30.0 / math.pi


def load_dynamics_file(path: Path) -> Any:
    """A planar or sine press file with a ``[drive]`` table (FileFormatError naming the file
    and the key otherwise)."""
    doc = io.load(path, types={"planar": io.PlanarFile, "sine_press": io.SinePressFile})
    if doc.drive is None:
        raise FileFormatError(str(path), "drive", "missing: linkwork dynamics needs a [drive] "
                              "table with at least one [[drive.motor]] (the table is described "
                              "in linkwork/io/drive.py)")
    if isinstance(doc, io.SinePressFile) and doc.press is None:
        raise FileFormatError(str(path), "press", "missing: linkwork dynamics of a sine_press "
                              "file needs a [press] table of masses and the press force")
    if isinstance(doc, io.PlanarFile) and doc.driver.type != "crank":
        raise FileFormatError(str(path), "driver.type", f"{doc.driver.type!r}: linkwork dynamics "
                              "needs a crank driver (a motor turning the crank)")
    return doc


def _motors(study: DynamicsStudy, console: Any) -> None:
    t = Table(title="motors: steady state over a revolution, start from rest")
    heads = ["motor", "mean speed [rpm]", "δ", "mean power [kW]", "RMS torque [N·m]",
             "peak torque [N·m]", "at φ1 [deg]", "limit [N·m]", "start-up [s]"]
    for h in heads:
        t.add_column(escape(h), justify="left" if h == "motor" else "right", no_wrap=True)
    for c in study.choices:
        ss = c.steady
        t.add_row(escape(c.motor.name),
                  "-" if ss is None else fmt(ss.omega_mean * RPM),
                  "-" if ss is None else fmt(ss.delta, digits=3),
                  fmt(c.power_mean / 1e3), fmt(c.torque_rms), fmt(c.torque_peak),
                  "-" if not math.isfinite(c.phi_torque_peak) else
                  fmt(math.degrees(c.phi_torque_peak) % 360, decimals=0),
                  "-" if c.limit is None else fmt(c.limit),
                  "-" if c.start is None else fmt(c.start.t_steady, digits=3))
    print_table(console, t)
    for c in study.choices:
        console.print(escape(f"  {c.motor.name}: {c.verdict}"), highlight=False)


def _sizing(study: DynamicsStudy, console: Any) -> None:
    s = study.sizing
    if s is None:
        return
    t = Table(title=escape(f"flywheel on the crank shaft for δ = {s.delta:g} (without one: "
                           f"δ = {s.delta_without:.4g})"))
    for h in ("method", "flywheel [kg·m²]", "deviation from exact [%]"):
        t.add_column(escape(h), justify="left" if h == "method" else "right", no_wrap=True)
    t.add_row("exact (periodic solve)", fmt(s.flywheel), "")
    for name, value, dev in (("energy method, constant inertia", s.energy_method,
                              s.deviation_energy),
                             ("Wittenbauer's energy-mass diagram", s.wittenbauer_flywheel,
                              s.deviation_wittenbauer)):
        t.add_row(name, fmt(value), "-" if dev is None else fmt(100 * dev, decimals=2))
    print_table(console, t)
    if s.flywheel == 0.0:
        console.print(escape(
            f"  the machine meets δ = {s.delta:g} without a flywheel (δ = {s.delta_without:.4g}"
            f" with {study.choices[0].motor.name}'s characteristic); the classical methods, "
            "which take a constant driving torque, would ask for the flywheels above"),
            highlight=False)


def _comparison(study: DynamicsStudy, console: Any) -> None:
    ss = study.steady
    if ss is None:
        return
    rows = ss.comparison()
    t = Table(title=escape(f"{study.choices[0].motor.name}: the real motion against the "
                           f"constant mean speed {ss.omega_mean * RPM:.4g} rpm (peaks over the "
                           "cycle)"))
    for h in ("quantity", "real", "constant speed", "real / constant"):
        t.add_column(escape(h), justify="left" if h == "quantity" else "right", no_wrap=True)
    scales = {u: scale_of([r["real"] for r in rows if r["unit"] == u] +
                          [r["constant"] for r in rows if r["unit"] == u]) for u in ("N", "N*m")}
    for r in rows:
        unit = r["unit"].replace("*", "·")
        t.add_row(escape(f"{r['name']} [{unit}]"), fmt(r["real"], scales[r["unit"]]),
                  fmt(r["constant"], scales[r["unit"]]),
                  "-" if r["ratio"] is None else fmt(r["ratio"], decimals=3))
    print_table(console, t)
    e = ss.energy
    console.print(escape(
        f"energy per revolution [J]: motor {fmt(e['motor'])}, loads {fmt(e['loads'])}, "
        f"friction {fmt(e['friction'])}, gear {fmt(e['gear'])}, gravity "
        f"{fmt(e['gravity'], e['motor'])} (balance {fmt(e['residual'], e['motor'])}); "
        f"solve error estimate {ss.error_estimate:.1g} of the mean speed"), highlight=False)


def _schedule(study: DynamicsStudy, console: Any) -> None:
    run = study.schedule
    for note in study.notes:
        console.print(escape(f"note: {note}"), highlight=False)
    if run is None:
        return
    t = Table(title=escape(f"schedule with {study.choices[0].motor.name}, revolution by "
                           "revolution"))
    for h in ("rev", "mode", "t [s]", "ω start [rpm]", "ω min [rpm]", "drop [%]",
              "work on loads [J]", "motor work [J]"):
        t.add_column(escape(h), justify="left" if h == "mode" else "right", no_wrap=True)
    r = run.revolutions()
    for k in range(r["t"].size):
        t.add_row(str(k + 1), escape(run.modes[int(r["mode"][k])]), fmt(r["t"][k], digits=4),
                  fmt(r["omega_start"][k] * RPM), fmt(r["omega_min"][k] * RPM),
                  fmt(100 * r["drop"][k], decimals=2),
                  fmt(r["work_loads"][k], scale_of(r["work_motor"])),
                  fmt(r["work_motor"][k]))
    print_table(console, t)
    for k, rec in enumerate(run.recovery()):
        back = ("not within 1 % of its steady mean speed in the segment" if rec["time"] is None
                else f"within 1 % of its steady mean speed after {rec['revolutions']} "
                     f"revolution(s), {rec['time']:.3g} s")
        console.print(escape(
            f"  switch at t = {run.switch_t[k]:.4g} s to {rec['to']}: "
            f"{run.switch_omega_before[k] * RPM:.4g} -> {run.switch_omega_after[k] * RPM:.4g} "
            f"rpm, {run.switch_energy_loss[k]:.3g} J lost; {back}"), highlight=False)


#: The files :func:`render` may write, in order.
FILES = ("dynamics.json", "dynamics_motor<k>.csv", "dynamics_startup.csv",
         "dynamics_schedule.csv", "dynamics_speed.png", "dynamics_torque.png",
         "dynamics_energy_mass.png", "dynamics_startup.png", "dynamics_schedule.png")


def _run_columns(run: Any) -> dict[str, tuple[np.ndarray, str]]:
    return {k: (np.asarray(getattr(run, k), dtype=float), run.units[k]) for k in (
        "t", "phi1", "omega", "eps", "torque", "mode", "segment", "revolution", "switch")}


def _plots(study: DynamicsStudy, out: Path, step: Callable[[str], None]) -> list[Path]:
    from linkwork.plot import machine as mplot
    from linkwork.plot import pyplot, save

    name = study.name or None
    written = []
    runs = [c.steady for c in study.choices if c.steady is not None]
    plt = pyplot()
    if runs:
        step("drawing dynamics_speed.png")
        fig, ax = plt.subplots(figsize=(8, 4.5))
        mplot.plot_speed(runs, ax=ax, name=name)
        written.append(save(fig, out / "dynamics_speed.png"))
        step("drawing dynamics_torque.png")
        fig, ax = plt.subplots(figsize=(8, 4.5))
        mplot.plot_torque(runs, ax=ax, name=name)
        written.append(save(fig, out / "dynamics_torque.png"))
    if study.sizing is not None:
        step("drawing dynamics_energy_mass.png")
        fig, ax = plt.subplots(figsize=(7, 5))
        mplot.plot_energy_mass(study.sizing, ax=ax, name=name)
        written.append(save(fig, out / "dynamics_energy_mass.png"))
    start = study.choices[0].start
    if start is not None:
        step("drawing dynamics_startup.png")
        drawn = mplot.plot_transient(start.run, name=name)
        written.append(save(drawn["axes"][0].figure, out / "dynamics_startup.png"))
    if study.schedule is not None:
        step("drawing dynamics_schedule.png")
        drawn = mplot.plot_transient(study.schedule, name=name)
        written.append(save(drawn["axes"][0].figure, out / "dynamics_schedule.png"))
    return written


def render(study: DynamicsStudy, *, out: Path, console: Any) -> None:
    """Print a :class:`~linkwork.studies.dynamics.DynamicsStudy` on ``console`` and write its
    files into ``out``."""
    m = study.machine
    d = m.drive
    console.print(escape(
        f"{study.name or 'mechanism'}: gear i = {d.ratio:.4g}, efficiency {d.eta:.4g}; "
        f"flywheel {study.flywheel:.4g} kg·m² on the crank shaft"
        f"{' (sized)' if study.sizing is not None else ''}; {m.grid.n} positions a revolution"),
        highlight=False)
    _motors(study, console)
    _sizing(study, console)
    _comparison(study, console)
    _schedule(study, console)
    with steps(8, console=make_console(stderr=True)) as step:
        step("writing dynamics.json")
        written = [write_json(out / "dynamics.json", study.to_dict())]
        for k, c in enumerate(study.choices):
            if c.steady is not None:
                step(f"writing dynamics_motor{k + 1}.csv")
                written.append(write_csv(out / f"dynamics_motor{k + 1}.csv",
                                         steady_columns(c.steady)))
        start = study.choices[0].start
        if start is not None:
            step("writing dynamics_startup.csv")
            written.append(write_csv(out / "dynamics_startup.csv", _run_columns(start.run)))
        if study.schedule is not None:
            step("writing dynamics_schedule.csv")
            written.append(write_csv(out / "dynamics_schedule.csv",
                                     _run_columns(study.schedule)))
        written += _plots(study, out, step)
    console.print(escape("wrote " + ", ".join(str(w) for w in written)), highlight=False)


def register(app: typer.Typer) -> None:
    """Add the ``dynamics`` command to ``app``."""

    @app.command()
    def dynamics(
        file: Annotated[Path, typer.Argument(help="planar or sine_press file with a \\[drive] "
                                             "table (TOML)")],
        out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
            "linkwork-output"),
    ) -> None:
        """Machine dynamics: the crank's real motion under its motor, flywheel, start-up, motor
        verdicts."""
        doc = load_dynamics_file(file)
        with output_run(out, command="dynamics", file=file):
            with counting("revolutions", console=make_console(stderr=True)) as progress:
                try:
                    study = study_dynamics.run(doc, progress=progress)
                except ParameterError as exc:
                    if exc.parameter in ("drive", "press", "driver"):
                        raise FileFormatError(str(file), exc.parameter, str(exc)) from None
                    if exc.parameter == "friction":  # the joints' friction locks it
                        raise FileFormatError(str(file), "joint friction", str(exc).removeprefix(
                            "friction = ")) from None
                    raise
            render(study, out=out, console=make_console())
