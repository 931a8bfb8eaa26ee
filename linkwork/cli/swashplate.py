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

import json
import math
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from linkwork.cli._args import output_dir
from linkwork.errors import ParameterError
from linkwork.units import to_si

__all__ = ["analyze_swashplate", "register", "sub"]

sub = typer.Typer(name="swashplate", no_args_is_help=True, add_completion=False,
                  help="Swash-plate (inclined-disk) drive of rotor machines (paper 003).")


def _deg(x: Any) -> str:
    return f"{math.degrees(float(x)):.4g}"


def _mm(x: Any) -> str:
    return f"{float(x) * 1e3:.4g}"


def analyze_swashplate(doc: Any, out: Path, angles: np.ndarray, console: Any) -> None:
    """Analyse a validated ``swashplate`` document; see the module docstring for the outputs."""
    from rich.markup import escape
    from rich.table import Table

    from linkwork.models import swashplate as sw
    from linkwork.plot import save
    from linkwork.plot.swashplate import plot_drive_forces, plot_kinematics

    d = doc.design()
    omega = doc.operation.omega
    res_t = sw.analyze(d, angles, omega=omega)
    t = Table(title=escape(f"{doc.name}: scheme {d.scheme}, R = {_mm(d.R)} mm, r = {_mm(d.r)} mm,"
                           f" l = {_mm(d.l)} mm, alpha = {_deg(d.alpha)} deg, a = {_mm(d.a)} mm,"
                           f" b = {_mm(d.b)} mm"))
    # without a rotor speed the slide speed is unknown: no columns of zeros that look measured
    speeds = omega > 0
    cols = ["φ [deg]", "s [mm]", "δz [deg]", "Πv [mm/rad]", "d²s/dφ² [mm/rad²]"]
    for col in cols + (["slide v [m/s]", "slide acc. [m/s²]"] if speeds else []):
        t.add_column(escape(col), justify="right")
    if not speeds:
        t.caption = "no rotor speed in [operation] (speed or productivity): slide speeds omitted"
    for i, p in enumerate(angles):
        row = [_deg(p), f"{res_t.s[i] * 1e3:.4f}", f"{math.degrees(res_t.delta_z[i]):.4f}",
               f"{res_t.Pi_v[i] * 1e3:.4f}", f"{res_t.Pi_a[i] * 1e3:.4f}"]
        if speeds:
            row += [f"{res_t.v[i]:.4f}", f"{res_t.acc[i]:.4f}"]
        t.add_row(*row)
    console.print(t)
    c = res_t.characteristics
    summary: dict[str, Any] = {k: v for k, v in c.scalars().items()}
    rows = [("stroke H", f"{_mm(c.H)} mm"),
            ("extremes", f"s_min = {_mm(c.s_min)} mm at {_deg(c.phi_min)} deg, "
                         f"s_max = {_mm(c.s_max)} mm at {_deg(c.phi_max)} deg"),
            ("forward / return stroke angle", f"{_deg(c.phi_f)} / {_deg(c.phi_r)} deg"),
            ("max pressure angle fwd / ret", f"{_deg(c.delta_f)} / {_deg(c.delta_r)} deg"),
            ("max |Πv|", f"{_mm(c.Pi_v_max)} mm/rad at {_deg(c.phi_Pi_v_max)} deg"),
            ("axial size L ≈ 2 r sin α + l (exact)", f"{_mm(c.L)} ({_mm(c.L_exact)}) mm"),
            ("unimodal s(φ)", "yes" if bool(c.unimodal) else "NO")]
    err = sw.harmonic_error(*d.params)
    rows.append(("harmonic form (6): max / RMS error", f"{_mm(err['max'])} / {_mm(err['rms'])} mm"))
    summary["harmonic_error_max"] = float(err["max"])
    summary["harmonic_error_rms"] = float(err["rms"])
    op = doc.operation
    if omega > 0:
        v_max = omega * float(c.Pi_v_max)
        rows.append(("rotor speed / max slide speed",
                     f"{omega * 30 / math.pi:.4g} rpm / {v_max:.4g} m/s"))
        summary["omega"] = omega
        summary["v_max"] = v_max
        if op.v_allow is not None:
            ok = v_max <= op.v_allow
            rows.append(("speed limit [v]", f"{op.v_allow:.4g} m/s: {'met' if ok else 'EXCEEDED'}"))
            summary["v_allow_met"] = ok
    if op.delta_allow is not None:
        ok = max(float(c.delta_f), float(c.delta_r)) <= op.delta_allow
        rows.append(("pressure-angle limit [δz]",
                     f"{_deg(op.delta_allow)} deg: {'met' if ok else 'EXCEEDED'}"))
        summary["delta_allow_met"] = ok
    ts = Table(title="characteristics (paper 003, requirements 1-5)")
    ts.add_column("quantity")
    ts.add_column("value", justify="right")
    for k, v in rows:
        ts.add_row(escape(k), escape(v))
    console.print(ts)

    full = sw.analyze(d, np.linspace(0.0, 2 * math.pi, doc.output.samples), omega=omega)
    full.to_csv(out / "cycle.csv")
    full.to_json(out / "cycle.json")
    save(plot_kinematics(full)[0].figure, out / "kinematics.png")
    f = doc.drive_forces(c)
    if f is not None:
        f.to_csv(out / "forces.csv")
        f.to_json(out / "forces.json")
        save(plot_drive_forces(f)[0].figure, out / "forces.png")
        summary.update({"efficiency": f.efficiency, "peak_torque_total": float(
            np.max(np.abs(f.M_total))), "peak_rod_force": float(np.max(np.abs(f.S)))})
        slides = f"{op.positions} slide" + ("" if op.positions == 1 else "s")
        console.print(f"drive: peak rod force {np.max(np.abs(f.S)) * 1e-3:.4g} kN, peak torque "
                      f"{np.max(np.abs(f.M_total)):.4g} N·m ({slides}), "
                      f"efficiency {f.efficiency:.4f}")
    (out / "characteristics.json").write_text(json.dumps(
        {"design": d.as_dict(), **summary}, indent=1, default=float))
    console.print(f"written: {out}/cycle.csv, cycle.json, characteristics.json, kinematics.png"
                  + (", forces.csv, forces.json, forces.png" if doc.load is not None else ""))


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
    from linkwork import files
    from linkwork.cli._console import console as make_console
    from linkwork.cli.analyze import parse_angles
    from linkwork.errors import FileFormatError

    doc = files.load(file)
    if getattr(doc, "type", None) != "swashplate":
        raise FileFormatError(str(file), "type", f"is {doc.type!r}, expected 'swashplate'")
    table_angles = parse_angles(angles)
    output_dir(out)
    analyze_swashplate(doc, out=out, angles=table_angles, console=make_console())


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
    from rich.markup import escape
    from rich.table import Table

    from linkwork.cli._console import console as make_console
    from linkwork.models import swashplate as sw
    from linkwork.plot import save
    from linkwork.plot.swashplate import plot_feasible_region
    from linkwork.sweep import rich_progress
    from linkwork.synthesis import swashplate as syn

    output_dir(out)  # before the search: an unusable --out must not cost a synthesis
    if scheme not in sw.SCHEMES:
        raise ParameterError("--scheme", scheme, f"must be one of {', '.join(sw.SCHEMES)}")
    if objective not in ("L", "torque"):
        raise ParameterError("--objective", objective, "must be 'L' or 'torque'")
    for opt, val, least in (("--positions", positions, 1), ("--candidates", candidates, 1),
                            ("--best", best, 1), ("--refine", refine, 0)):
        if val < least:
            raise ParameterError(opt, val, f"must be an integer >= {least}")
    R = to_si(rotor_radius, "length", "--rotor-radius")
    H = to_si(stroke, "length", "--stroke")
    H_tol = _q(stroke_tol, "length", "--stroke-tol")
    d_all = to_si(delta, "angle", "--delta")
    omega = None
    if speed is not None and productivity is not None:
        raise ParameterError("--speed", speed, "give --speed or --productivity, not both")
    if speed is not None:
        omega = to_si(speed, "angular_velocity", "--speed")
        if not omega > 0:
            raise ParameterError("--speed", speed, "must be > 0")
    elif productivity is not None:
        P = to_si(productivity, "frequency", "--productivity")
        if not P > 0:
            raise ParameterError("--productivity", productivity, "must be > 0")
        omega = 2 * math.pi * P / positions
    lim = _q(pi_v_max, "length", "--pi-v-max")
    if v_allow is not None:
        if omega is None or omega <= 0:
            raise ParameterError("--v-allow", v_allow, "needs --productivity or --speed")
        lv = to_si(v_allow, "velocity", "--v-allow") / omega
        lim = lv if lim is None else min(lim, lv)
    # the Request names its own fields in SI; add the option the user typed, as typed
    given: dict[str, tuple[str, str | None]] = {
             "R": ("--rotor-radius", rotor_radius), "H": ("--stroke", stroke),
             "H_tol": ("--stroke-tol", stroke_tol),
             "delta_f": ("--delta-f", delta_f) if delta_f is not None else ("--delta", delta),
             "delta_r": ("--delta-r", delta_r) if delta_r is not None else ("--delta", delta),
             "phi_f": ("--phi-f", phi_f), "phi_f_tol": ("--phi-f-tol", phi_f_tol),
             "point": ("--point", point), "point_tol": ("--point-tol", point_tol),
             "Pi_v_max": ("--pi-v-max or --v-allow", pi_v_max or v_allow)}
    try:
        req = syn.Request(
            scheme=scheme, R=R, H=H, H_tol=0.005 * H if H_tol is None else H_tol,
            delta_f=d_all if delta_f is None else to_si(delta_f, "angle", "--delta-f"),
            delta_r=d_all if delta_r is None else to_si(delta_r, "angle", "--delta-r"),
            Pi_v_max=lim,
            point=None if point is None else _pair(point, "--point"),
            point_tol=to_si(point_tol, "length", "--point-tol"),
            phi_f=_q(phi_f, "angle", "--phi-f"),
            phi_f_tol=to_si(phi_f_tol, "angle", "--phi-f-tol"),
            objective=objective, u=positions)  # type: ignore[arg-type]
    except ParameterError as exc:
        opt, text = given.get(exc.parameter, ("", None))
        if text is None:
            raise
        hint = f"from {opt} {text!r}"
        if exc.parameter.startswith(("delta", "phi")):
            try:
                float(text)
                hint += '; a plain number is in radians: write e.g. "8 deg"'
            except ValueError:
                pass
        raise ParameterError(exc.parameter, exc.value, exc.limit, hint) from None
    free = list(req.free)
    names = free[:2] if region is None else [s.strip() for s in region.split(",")]
    if len(names) != 2 or any(n not in free for n in names) or names[0] == names[1]:
        raise ParameterError("--map", region, f"must name two free parameters of scheme "
                             f"{scheme}: {', '.join(free)}")
    console = make_console()
    err_console = make_console(stderr=True)
    if err_console.is_terminal:  # a live bar, erased afterwards: stderr keeps one error line
        with rich_progress("screening candidates", console=err_console,
                           transient=True) as progress:
            res = syn.synthesize(req, n_candidates=candidates, n_best=best, n_refine=refine,
                                 seed=seed, client=scheduler, progress=progress)
    else:
        res = syn.synthesize(req, n_candidates=candidates, n_best=best, n_refine=refine,
                             seed=seed, client=scheduler)
    tab = res.table
    t = Table(title=escape(f"scheme {scheme}: {len(res.designs)} best of {res.n_feasible} "
                           f"feasible / {res.n_evaluated} screened (objective {objective})"))
    cols = ["#", "r [mm]", "l [mm]", "α [deg]", "a [mm]", "b [mm]", "H [mm]", "δf [deg]",
            "δr [deg]", "max Πv [mm/rad]", "φf [deg]", "L [mm]"]
    if req.point is not None:
        cols.insert(-1, f"s({_deg(req.point[0])}°) [mm]")
    if objective != "L":  # the objective column would repeat L
        cols.append("peak M / (F R)")  # the torque objective: peak drive torque per unit load
    for col in cols:
        t.add_column(escape(col), justify="right")
    for i in range(len(res.designs)):
        row = [str(i + 1), _mm(tab["r"][i]), _mm(tab["l"][i]), _deg(tab["alpha"][i]),
               _mm(tab["a"][i]), _mm(tab["b"][i]), _mm(tab["H"][i]),
               _deg(tab["delta_f"][i]), _deg(tab["delta_r"][i]), _mm(tab["Pi_v_max"][i]),
               _deg(tab["phi_f"][i]), _mm(tab["L"][i])]
        if req.point is not None:
            row.insert(-1, _mm(tab["s_point"][i]))
        if objective != "L":
            row.append(f"{tab['objective'][i]:.5g}")
        t.add_row(*row)
    console.print(t)
    on_bound = [f"{n} at its {side} bound ({_deg(b)} deg)" if n == "alpha"
                else f"{n} at its {side} bound ({b:.4g} R = {_mm(b * req.R)} mm)"
                for n, side, b in res.at_bounds(0)]
    if on_bound:
        console.print("note: design 1 lies on the search box: " + ", ".join(on_bound)
                      + "; a better design may lie beyond it (widen the bound with "
                      "linkwork.synthesis.swashplate.Request(bounds=...))")
    res.to_csv(out / "synthesis.csv")
    res.to_json(out / "synthesis.json")
    reg = syn.feasible_region(req, res.best, names[0], names[1], n=60)
    save(plot_feasible_region(reg, best=res.best).figure, out / "feasible_region.png")
    console.print(f"written: {out}/synthesis.csv, synthesis.json, feasible_region.png")


def register(app: typer.Typer) -> None:
    """Add the ``swashplate`` command group to ``app``."""
    app.add_typer(sub, name="swashplate")
