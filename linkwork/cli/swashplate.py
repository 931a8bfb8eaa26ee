"""``linkwork swashplate``: analysis and synthesis of the swash-plate drive (paper 003).

* ``linkwork swashplate analyze FILE.toml`` -- table at chosen rotor angles, the
  characteristics (stroke, extremes, forward/return angles, pressure angles, speeds, axial size,
  checks against the file's limits), ``cycle.csv/.json``, ``characteristics.json``,
  ``kinematics.png`` (s, delta_z, Pi_v against phi) and, with a ``[load]`` section,
  ``forces.csv/.json`` and ``forces.png`` (rod force, drive torque of one and of all slides,
  efficiency). Also reachable as ``linkwork analyze FILE.toml``.
* ``linkwork swashplate synthesize --scheme 4b -R "100 mm" --stroke "60 mm" ...`` -- ranked
  designs meeting the limits (table, ``synthesis.csv/.json``) and ``feasible_region.png``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from linkwork import io
from linkwork.cli._args import output_run, parse_angles, reach_scheduler
from linkwork.cli._console import console as make_console
from linkwork.cli._console import steps
from linkwork.cli._format import fmt
from linkwork.cli._tables import print_table
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.swashplate import SwashplateFile
from linkwork.models import swashplate as sw
from linkwork.results import write_json
from linkwork.studies import swashplate as study_swashplate
from linkwork.studies.swashplate import SwashplateStudy, SwashplateSynthesis
from linkwork.sweep import check_client, rich_progress
from linkwork.synthesis import swashplate as syn
from linkwork.units import to_si

__all__ = ["analyze_swashplate", "register", "render", "render_synthesis", "sub"]

sub = typer.Typer(name="swashplate", no_args_is_help=True, add_completion=False,
                  help="Swash-plate (inclined-disk) drive of rotor machines (paper 003).")


def _deg(x: Any) -> str:
    return fmt(math.degrees(float(x)))


def _mm(x: Any, scale: Any = 0.0) -> str:
    """A length [m] in mm; round-off against the length ``scale`` [m] as 0 (:func:`fmt`)."""
    return fmt(float(x) * 1e3, float(scale) * 1e3)


def analyze_swashplate(doc: SwashplateFile, out: Path, angles: np.ndarray, console: Any
                       ) -> SwashplateStudy:
    """Analyse a validated ``swashplate`` document; see the module docstring for the outputs."""
    with steps(1, console=make_console(stderr=True)) as step:
        step(f"solving {doc.output.samples} rotor angles")
        study = study_swashplate.analyze(doc, angles=angles)
    render(study, out=out, console=console)
    return study


def _table(study: SwashplateStudy) -> Table:
    d, res_t = study.design, study.table
    t = Table(title=escape(f"{study.doc.name}: scheme {d.scheme}, R = {_mm(d.R)} mm, r = "
                           f"{_mm(d.r)} mm, l = {_mm(d.l)} mm, alpha = {_deg(d.alpha)} deg, "
                           f"a = {_mm(d.a, d.R)} mm, b = {_mm(d.b, d.R)} mm"))
    # without a rotor speed the slide speed is unknown: no columns of zeros that look measured
    speeds = study.omega > 0
    cols = ["φ [deg]", "s [mm]", "δz [deg]", "Πv [mm/rad]", "d²s/dφ² [mm/rad²]"]
    for col in cols + (["slide v [m/s]", "slide acc. [m/s²]"] if speeds else []):
        t.add_column(escape(col), justify="right")
    if not speeds:
        t.caption = "no rotor speed in [operation] (speed or productivity): slide speeds omitted"
    for i, p in enumerate(study.angles):
        row = [_deg(p), fmt(res_t.s[i] * 1e3, decimals=4),
               fmt(math.degrees(res_t.delta_z[i]), decimals=4),
               fmt(res_t.Pi_v[i] * 1e3, decimals=4), fmt(res_t.Pi_a[i] * 1e3, decimals=4)]
        if speeds:
            row += [fmt(res_t.v[i], decimals=4), fmt(res_t.acc[i], decimals=4)]
        t.add_row(*row)
    return t


def _characteristics(study: SwashplateStudy) -> Table:
    c, op, omega, err = study.characteristics, study.doc.operation, study.omega, study.summary
    rows = [("stroke H", f"{_mm(c.H)} mm"),
            ("extremes", f"s_min = {_mm(c.s_min)} mm at {_deg(c.phi_min)} deg, "
                         f"s_max = {_mm(c.s_max)} mm at {_deg(c.phi_max)} deg"),
            ("forward / return stroke angle", f"{_deg(c.phi_f)} / {_deg(c.phi_r)} deg"),
            ("max pressure angle fwd / ret", f"{_deg(c.delta_f)} / {_deg(c.delta_r)} deg"),
            ("max |Πv|", f"{_mm(c.Pi_v_max)} mm/rad at {_deg(c.phi_Pi_v_max)} deg"),
            ("axial size L ≈ 2 r sin α + l (exact)", f"{_mm(c.L)} ({_mm(c.L_exact)}) mm"),
            ("unimodal s(φ)", "yes" if bool(c.unimodal) else "NO"),
            ("harmonic form (6): max / RMS error",
             f"{_mm(err['harmonic_error_max'], c.H)} / {_mm(err['harmonic_error_rms'], c.H)} "
             "mm")]
    if omega > 0:
        rows.append(("rotor speed / max slide speed",
                     f"{omega * 30 / math.pi:.4g} rpm / {study.v_max:.4g} m/s"))
        if op.v_allow is not None:
            ok = study.summary["v_allow_met"]
            rows.append(("speed limit [v]", f"{op.v_allow:.4g} m/s: "
                         f"{'met' if ok else 'EXCEEDED'}"))
    if op.delta_allow is not None:
        ok = study.summary["delta_allow_met"]
        rows.append(("pressure-angle limit [δz]",
                     f"{_deg(op.delta_allow)} deg: {'met' if ok else 'EXCEEDED'}"))
    ts = Table(title="characteristics (paper 003, requirements 1-5)")
    ts.add_column("quantity")
    ts.add_column("value", justify="right")
    for k, v in rows:
        ts.add_row(escape(k), escape(v))
    return ts


def _json_values(data: Any) -> Any:
    """Plain floats for numpy scalars (as ``json.dumps(default=float)`` wrote them)."""
    if isinstance(data, dict):
        return {k: _json_values(v) for k, v in data.items()}
    if isinstance(data, list | tuple):
        return [_json_values(v) for v in data]
    if isinstance(data, np.generic):
        return float(data)
    return data


def render(study: SwashplateStudy, *, out: Path, console: Any) -> None:
    """Print a :class:`~linkwork.studies.swashplate.SwashplateStudy` on ``console`` and write
    its cycle, forces, characteristics and plots into ``out``."""
    from linkwork.plot import save
    from linkwork.plot.swashplate import plot_drive_forces, plot_kinematics

    print_table(console, _table(study))
    print_table(console, _characteristics(study))
    f = study.forces
    if f is not None:
        u = study.doc.operation.positions
        slides = f"{u} slide" + ("" if u == 1 else "s")
        eff = (fmt(f.efficiency, decimals=4) if math.isfinite(f.efficiency) else
               "undefined (the load does no net work per revolution)")
        console.print(f"drive: peak rod force {np.max(np.abs(f.S)) * 1e-3:.4g} kN, peak torque "
                      f"{np.max(np.abs(f.M_total)):.4g} N·m ({slides}), efficiency {eff}",
                      highlight=False)
    with steps(3 if f is None else 5, console=make_console(stderr=True)) as step:
        step("writing cycle.csv, cycle.json")
        study.cycle.to_csv(out / "cycle.csv")
        study.cycle.to_json(out / "cycle.json")
        step("drawing kinematics.png")
        save(plot_kinematics(study.cycle, name=study.doc.name)[0].figure,
             out / "kinematics.png")
        if f is not None:
            step("writing forces.csv, forces.json")
            f.to_csv(out / "forces.csv")
            f.to_json(out / "forces.json")
            step("drawing forces.png")
            save(plot_drive_forces(f, name=study.doc.name)[0].figure, out / "forces.png")
        step("writing characteristics.json")
        write_json(out / "characteristics.json", _json_values(study.to_dict()))
    console.print(escape(f"written: {out}/cycle.csv, cycle.json, characteristics.json, "
                         "kinematics.png" + (", forces.csv, forces.json, forces.png"
                                             if f is not None else "")), highlight=False)


def _q(value: str | None, kind: str, name: str) -> float | None:
    return None if value is None else to_si(value, kind, name)


def _pair(text: str, name: str) -> tuple[float, float]:
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2:
        raise ParameterError(name, text, "must be 'ANGLE,LENGTH', e.g. '90 deg,20 mm'")
    return to_si(parts[0], "angle", name), to_si(parts[1], "length", name)


@sub.command("analyze")
def analyze_cmd(
    file: Annotated[Path, typer.Argument(help="swashplate file (TOML)")],
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "linkwork-output"),
    angles: Annotated[str, typer.Option(help="rotor angles for the table, deg, comma-separated")
                      ] = "0,30,60,90,120,150,180,210,240,270,300,330",
) -> None:
    """Analyse a swash-plate drive file: table, characteristics, CSV/JSON and plots."""
    doc = io.load(file)
    if not isinstance(doc, SwashplateFile):
        raise FileFormatError(str(file), "type", f"is {doc.type!r}, expected 'swashplate'")
    table_angles = parse_angles(angles)
    # recorded as `analyze`, which runs the same analysis of a swashplate file
    with output_run(out, command="analyze", file=file):
        analyze_swashplate(doc, out=out, angles=table_angles, console=make_console())


def _speed(speed: str | None, productivity: str | None, positions: int) -> float | None:
    """Rotor speed [rad/s] from ``--speed`` or ``--productivity`` (None: neither)."""
    if speed is not None and productivity is not None:
        raise ParameterError("--speed", speed, "give --speed or --productivity, not both")
    if speed is not None:
        omega = to_si(speed, "angular_velocity", "--speed")
        if not omega > 0:
            raise ParameterError("--speed", speed, "must be > 0")
        return omega
    if productivity is not None:
        P = to_si(productivity, "frequency", "--productivity")
        if not P > 0:
            raise ParameterError("--productivity", productivity, "must be > 0")
        return 2 * math.pi * P / positions
    return None


def _request(opts: dict[str, Any]) -> syn.Request:
    """The synthesis request of the command's options (strings as typed); a ParameterError of
    the Request names the option the user typed, as typed."""
    H = to_si(opts["stroke"], "length", "--stroke")
    H_tol = _q(opts["stroke_tol"], "length", "--stroke-tol")
    d_all = to_si(opts["delta"], "angle", "--delta")
    omega = _speed(opts["speed"], opts["productivity"], opts["positions"])
    lim = _q(opts["pi_v_max"], "length", "--pi-v-max")
    if opts["v_allow"] is not None:
        if omega is None or omega <= 0:
            raise ParameterError("--v-allow", opts["v_allow"], "needs --productivity or --speed")
        lv = to_si(opts["v_allow"], "velocity", "--v-allow") / omega
        lim = lv if lim is None else min(lim, lv)
    delta_f, delta_r, point = opts["delta_f"], opts["delta_r"], opts["point"]
    # the Request names its own fields in SI; add the option the user typed, as typed
    given: dict[str, tuple[str, str | None]] = {
        "R": ("--rotor-radius", opts["rotor_radius"]), "H": ("--stroke", opts["stroke"]),
        "H_tol": ("--stroke-tol", opts["stroke_tol"]),
        "delta_f": ("--delta-f", delta_f) if delta_f is not None else ("--delta", opts["delta"]),
        "delta_r": ("--delta-r", delta_r) if delta_r is not None else ("--delta", opts["delta"]),
        "phi_f": ("--phi-f", opts["phi_f"]), "phi_f_tol": ("--phi-f-tol", opts["phi_f_tol"]),
        "point": ("--point", point), "point_tol": ("--point-tol", opts["point_tol"]),
        "Pi_v_max": ("--pi-v-max or --v-allow", opts["pi_v_max"] or opts["v_allow"])}
    try:
        return syn.Request(
            scheme=opts["scheme"], R=opts["R"], H=H,
            H_tol=0.005 * H if H_tol is None else H_tol,
            delta_f=d_all if delta_f is None else to_si(delta_f, "angle", "--delta-f"),
            delta_r=d_all if delta_r is None else to_si(delta_r, "angle", "--delta-r"),
            Pi_v_max=lim,
            point=None if point is None else _pair(point, "--point"),
            point_tol=to_si(opts["point_tol"], "length", "--point-tol"),
            phi_f=_q(opts["phi_f"], "angle", "--phi-f"),
            phi_f_tol=to_si(opts["phi_f_tol"], "angle", "--phi-f-tol"),
            objective=opts["objective"], u=opts["positions"])
    except ParameterError as exc:
        opt, text = given.get(exc.parameter, ("", None))
        if text is None:
            raise
        # the option and its value as typed (the Request's field and SI value only in the
        # detail, where they say what a plain number was read as)
        hint = ""
        if exc.parameter.startswith(("delta", "phi")):
            try:
                float(text)
                hint = (f"read as {exc.parameter} = {exc.value}: a plain number is in "
                        'radians; write e.g. "8 deg"')
            except ValueError:
                pass
        raise ParameterError(opt, text, exc.limit, hint) from None


def render_synthesis(study: SwashplateSynthesis, *, out: Path, console: Any) -> None:
    """Print the ranked designs of a :class:`~linkwork.studies.swashplate.SwashplateSynthesis`
    and write ``synthesis.csv/.json`` and ``feasible_region.png`` into ``out``."""
    from linkwork.plot import save
    from linkwork.plot.swashplate import plot_feasible_region

    req, res = study.request, study.result
    tab = res.table
    t = Table(title=escape(f"scheme {req.scheme}: {len(res.designs)} best of {res.n_feasible} "
                           f"feasible / {res.n_evaluated} screened (objective {req.objective})"))
    cols = ["#", "r [mm]", "l [mm]", "α [deg]", "a [mm]", "b [mm]", "H [mm]", "δf [deg]",
            "δr [deg]", "max Πv [mm/rad]", "φf [deg]", "L [mm]"]
    if req.point is not None:
        cols.insert(-1, f"s({_deg(req.point[0])}°) [mm]")
    if req.objective != "L":  # the objective column would repeat L
        cols.append("peak M / (F R)")  # the torque objective: peak drive torque per unit load
    for col in cols:
        t.add_column(escape(col), justify="right")
    for i in range(len(res.designs)):
        row = [str(i + 1), _mm(tab["r"][i]), _mm(tab["l"][i]), _deg(tab["alpha"][i]),
               _mm(tab["a"][i], req.R), _mm(tab["b"][i], req.R), _mm(tab["H"][i]),
               _deg(tab["delta_f"][i]), _deg(tab["delta_r"][i]), _mm(tab["Pi_v_max"][i]),
               _deg(tab["phi_f"][i]), _mm(tab["L"][i])]
        if req.point is not None:
            row.insert(-1, _mm(tab["s_point"][i]))
        if req.objective != "L":
            row.append(fmt(tab["objective"][i], digits=5))
        t.add_row(*row)
    print_table(console, t)
    on_bound = [f"{n} at its {side} bound ({_deg(b)} deg)" if n == "alpha"
                else f"{n} at its {side} bound ({b:.4g} R = {_mm(b * req.R)} mm)"
                for n, side, b in res.at_bounds(0)]
    if on_bound:
        console.print("note: design 1 lies on the search box: " + ", ".join(on_bound)
                      + "; a better design may lie beyond it (widen the bound with "
                      "linkwork.synthesis.swashplate.Request(bounds=...))", highlight=False)
    res.to_csv(out / "synthesis.csv")
    res.to_json(out / "synthesis.json")
    save(plot_feasible_region(study.region, best=res.best).figure, out / "feasible_region.png")
    console.print(escape(f"written: {out}/synthesis.csv, synthesis.json, feasible_region.png"),
                  highlight=False)


@sub.command("synthesize")
def synthesize_cmd(
    stroke: Annotated[str, typer.Option("--stroke", "-H", help="wanted stroke H, e.g. '60 mm'")],
    rotor_radius: Annotated[str, typer.Option("--rotor-radius", "-R",
                                              help="rotor pitch radius R, e.g. '100 mm'")],
    scheme: Annotated[str, typer.Option(help="scheme: 1, 2, 3, 4a, 4b")] = "1",
    stroke_tol: Annotated[str | None, typer.Option(
        help="stroke tolerance (default 0.5 % of H), e.g. '0.2 mm'")] = None,
    delta: Annotated[str, typer.Option(help="allowed pressure angle, both strokes")] = "8 deg",
    delta_f: Annotated[str | None, typer.Option(help="allowed pressure angle, forward stroke"
                                                )] = None,
    delta_r: Annotated[str | None, typer.Option(help="allowed pressure angle, return stroke")
                       ] = None,
    pi_v_max: Annotated[str | None, typer.Option(
        help="allowed max |ds/dphi|, e.g. '40 mm' (per rad)")] = None,
    v_allow: Annotated[str | None, typer.Option(help="allowed slide speed, e.g. '0.3 m/s' "
                                                "(needs --productivity or --speed)")] = None,
    productivity: Annotated[str | None, typer.Option(help="productivity, e.g. '600 1/min'")
                            ] = None,
    positions: Annotated[int, typer.Option(help="slides u on the rotor")] = 1,
    speed: Annotated[str | None, typer.Option(help="rotor speed, e.g. '50 rpm'")] = None,
    point: Annotated[str | None, typer.Option(
        help="point the position function passes through, 'PHI,S', e.g. '90 deg,20 mm'")
    ] = None,
    point_tol: Annotated[str, typer.Option(help="tolerance of --point")] = "0.5 mm",
    phi_f: Annotated[str | None, typer.Option(help="wanted forward-stroke angle, e.g. '200 deg'"
                                              )] = None,
    phi_f_tol: Annotated[str, typer.Option(help="tolerance of --phi-f")] = "2 deg",
    objective: Annotated[str, typer.Option(help="L (axial size) or torque (peak drive torque)")
                         ] = "L",
    candidates: Annotated[int, typer.Option(help="Sobol candidates screened")] = 16384,
    best: Annotated[int, typer.Option(help="designs listed")] = 5,
    refine: Annotated[int, typer.Option(help="SLSQP refinements")] = 4,
    seed: Annotated[int, typer.Option(help="seed of the sample")] = 0,
    scheduler: Annotated[str | None, typer.Option(help="dask scheduler address (optional)")
                         ] = None,
    region: Annotated[str | None, typer.Option(
        "--map", help="two free parameters of the feasible-region plot, e.g. 'alpha,l'")
    ] = None,
    out: Annotated[Path, typer.Option("--out", "-o", help="output folder")] = Path(
        "linkwork-output"),
) -> None:
    """Find designs of a scheme meeting the stroke, pressure-angle and speed limits (ranked)."""
    check_client(scheduler, option="--scheduler")  # address and dask, before any output
    if scheme not in sw.SCHEMES:
        raise ParameterError("--scheme", scheme, f"must be one of {', '.join(sw.SCHEMES)}")
    if objective not in ("L", "torque"):
        raise ParameterError("--objective", objective, "must be 'L' or 'torque'")
    for opt, val, least in (("--positions", positions, 1), ("--best", best, 1),
                            ("--refine", refine, 0)):
        if val < least:
            raise ParameterError(opt, val, f"must be an integer >= {least}")
    syn.check_candidates(candidates, "--candidates")
    R = to_si(rotor_radius, "length", "--rotor-radius")
    req = _request({
        "R": R, "rotor_radius": rotor_radius, "stroke": stroke, "stroke_tol": stroke_tol,
        "scheme": scheme, "delta": delta, "delta_f": delta_f, "delta_r": delta_r,
        "pi_v_max": pi_v_max, "v_allow": v_allow, "productivity": productivity,
        "positions": positions, "speed": speed, "point": point, "point_tol": point_tol,
        "phi_f": phi_f, "phi_f_tol": phi_f_tol, "objective": objective})
    free = list(req.free)
    names = free[:2] if region is None else [s.strip() for s in region.split(",")]
    if len(names) != 2 or any(n not in free for n in names) or names[0] == names[1]:
        raise ParameterError("--map", region, f"must name two free parameters of scheme "
                             f"{scheme}: {', '.join(free)}")
    console = make_console()
    err_console = make_console(stderr=True)
    kw: dict[str, Any] = {"region": (names[0], names[1]), "n_candidates": candidates,
                          "n_best": best, "n_refine": refine, "seed": seed,
                          "client": scheduler}
    reach_scheduler(scheduler)
    # --out checked after the options, before the search: it must not cost a synthesis
    with output_run(out, command="swashplate synthesize"):
        if err_console.is_terminal:  # a live bar, erased afterwards: stderr keeps one line
            with rich_progress("screening candidates", console=err_console,
                               transient=True) as progress:
                study = study_swashplate.synthesize(req, progress=progress, **kw)
        else:
            study = study_swashplate.synthesize(req, **kw)
        render_synthesis(study, out=out, console=console)


def register(app: typer.Typer) -> None:
    """Add the ``swashplate`` command group to ``app``."""
    app.add_typer(sub, name="swashplate")
