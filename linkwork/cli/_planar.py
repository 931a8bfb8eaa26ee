"""``linkwork analyze`` for ``type = "planar"`` files: the general engine over a cycle.

Prints the structure (mobility, Assur groups), dead centres, and a table at the requested crank
angles: driving torque, every joint reaction's magnitude, shaking force and moment,
transmission angles (the kinetic energy is in the CSV/JSON), and the extremes over the cycle
(largest and smallest driving torque, peak reactions, shaking) with where they occur. Writes
``planar_kinematics.csv`` (every body's pose, velocity, acceleration), ``planar_dynamics.csv``
(every joint's reaction components, driving torque, shaking force and moment, kinetic
energy), ``planar.json`` (both, with units and the structure) and plots (skeleton with point
paths, guides and slots, driving torque, reactions, shaking).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from linkwork.balancing.loads import mean_over_range
from linkwork.errors import AssemblyError, ParameterError
from linkwork.planar.dynamics import Dynamics, inverse_dynamics
from linkwork.planar.file import PlanarFile
from linkwork.planar.kinematics import (
    DeadCentre,
    Kinematics,
    dead_centres,
    kinematics,
    transmission_angles,
)
from linkwork.planar.model import Crank, Mechanism, PinInSlot, Prismatic, Revolute
from linkwork.results import write_csv

__all__ = ["analyze_planar", "cycle_peaks", "dead_centre_label", "named_columns",
           "table_positions_error"]


def table_positions_error(exc: AssemblyError, positions: np.ndarray, linear: bool
                          ) -> ParameterError:
    """The error for table positions (``--angles``) where the mechanism does not assemble,
    although the file's [analysis] range does."""
    vals = np.asarray(positions, dtype=float) * 1e3 if linear else np.degrees(positions)
    shown = ", ".join(f"{v:g}" for v in vals) + (" mm" if linear else " deg")
    return ParameterError("--angles", shown, f"the table positions leave the range where the "
                          f"mechanism assembles ({exc}); give --angles within the file's "
                          "[analysis] range")


def named_columns(kin: Kinematics, dyn: Dynamics) -> dict[str, tuple[np.ndarray, str]]:
    """Readable per-position columns: name -> (values, unit)."""
    mech = kin.mechanism
    crank = isinstance(mech.driver, Crank)
    cols: dict[str, tuple[np.ndarray, str]] = {
        "phi1": (kin.phi1, "rad" if crank else "m"),
        "omega1": (kin.omega1, "rad/s" if crank else "m/s"),
        "eps1": (kin.eps1, "rad/s^2" if crank else "m/s^2"),
    }
    for b in mech.bodies:
        i = mech.index[b.name]
        c = kin.point(b.name, "com")
        for name, arr, unit in (("theta", kin.theta[i], "rad"), ("omega", kin.omega[i], "rad/s"),
                                ("eps", kin.eps[i], "rad/s^2"), ("xS", c.x, "m"),
                                ("yS", c.y, "m"), ("vxS", c.vx, "m/s"), ("vyS", c.vy, "m/s"),
                                ("axS", c.ax, "m/s^2"), ("ayS", c.ay, "m/s^2")):
            cols[f"{b.name}.{name}"] = (arr, unit)
    for k, j in enumerate(dyn.joints):
        cols[f"R_{j}.x"] = (dyn.fx[k], "N")
        cols[f"R_{j}.y"] = (dyn.fy[k], "N")
        if np.any(dyn.mz[k] != 0):
            cols[f"R_{j}.mz"] = (dyn.mz[k], "N*m")
    cols["Q"] = (dyn.Q, "N*m" if crank else "N")
    cols["shaking_fx"] = (dyn.shaking_fx, "N")
    cols["shaking_fy"] = (dyn.shaking_fy, "N")
    cols["shaking_m"] = (dyn.shaking_m, "N*m")
    cols["T"] = (dyn.T, "J")
    for key, (mu, _) in transmission_angles(kin).items():
        cols[f"mu_{key}"] = (mu, "rad")
    return cols


def dead_centre_label(mech: Mechanism, d: DeadCentre) -> tuple[str, str]:
    """What reaches its extreme at a dead centre, e.g. ``"rocker angle min"`` or ``"ram slide
    max along G (towards -90 deg)"`` (the slide coordinate runs along the guide's direction, so
    "max" is the end of the stroke that way), and the joint it is measured at."""
    g = next(g for g in mech.structure.groups if g.key == d.group)
    j = mech.joint(g.joints[0] if len(g.bodies) == 1 else g.joints[-1])  # the output's hinge
    other = j.a if j.b == d.body else j.b
    if isinstance(j, Revolute):
        rel = "" if other == mech.frame.name else f" relative to {other}"
        return f"{d.body} angle {d.kind}{rel}", j.name
    line = j if isinstance(j, Prismatic | PinInSlot) else None
    towards = (f" (towards {np.degrees(line.angle):g} deg)"
               if line is not None and j.a == mech.frame.name else "")
    return f"{d.body} slide {d.kind} along {j.name}{towards}", j.name


def cycle_peaks(kin: Kinematics, dyn: Dynamics) -> list[dict[str, Any]]:
    """Extremes over the analysed positions, for sizing motor and bearings.

    One entry per quantity: ``{"name", "value", "unit", "phi1"}`` (``phi1`` the driver position
    of the extreme [rad, or m for a linear driver]): the largest and the smallest driving torque
    (force), the peak magnitude of every joint reaction (and of a prismatic joint's couple), of
    the shaking force and of the shaking moment, and the smallest transmission angle of every
    group (its worst position) [rad]. Sampled at the positions analysed (no interpolation
    between them); unassembled positions (NaN) are skipped.
    """
    crank = isinstance(kin.mechanism.driver, Crank)
    unit_q = "N*m" if crank else "N"
    series: list[tuple[str, np.ndarray, str, str]] = [
        ("Q max", dyn.Q, unit_q, "max"), ("Q min", dyn.Q, unit_q, "min")]
    for k, j in enumerate(dyn.joints):
        series.append((f"|R {j}|", np.hypot(dyn.fx[k], dyn.fy[k]), "N", "max"))
        if np.any(dyn.mz[k] != 0):
            series.append((f"|M {j}|", np.abs(dyn.mz[k]), "N*m", "max"))
    series += [("|F_sh|", np.hypot(dyn.shaking_fx, dyn.shaking_fy), "N", "max"),
               ("|M_sh|", np.abs(dyn.shaking_m), "N*m", "max")]
    series += [(f"μ {key} min", mu, "rad", "min")
               for key, (mu, _) in transmission_angles(kin).items()]
    peaks = []
    for name, v, unit, kind in series:
        if not np.any(np.isfinite(v)):
            continue
        i = int(np.nanargmax(v) if kind == "max" else np.nanargmin(v))
        peaks.append({"name": name, "value": float(v[i]), "unit": unit,
                      "phi1": float(kin.phi1[i])})
    return peaks


def _distinct_paths(kin: Kinematics, candidates: list[tuple[str, str]]
                    ) -> list[tuple[str, str]]:
    """The (body, point) pairs whose paths differ: a joint's point named on both of its bodies
    (coupler.B, rocker.B) is drawn once, under its first body."""
    kept: list[tuple[str, str]] = []
    seen: list[np.ndarray] = []
    for body, pt in candidates:
        pm = kin.point(body, pt)
        xy = np.concatenate([pm.x, pm.y])
        if not any(np.allclose(xy, other, rtol=0.0, atol=1e-9, equal_nan=True)
                   for other in seen):
            kept.append((body, pt))
            seen.append(xy)
    return kept


def _solve(doc: PlanarFile, phi: np.ndarray) -> tuple[Kinematics, Dynamics]:
    mech = doc.mechanism()
    kin = kinematics(mech, phi)
    a = doc.analysis
    dyn = inverse_dynamics(kin, gravity=a.gravity, loads=doc.loads(phi), about=a.about)
    return kin, dyn


def analyze_planar(doc: PlanarFile, *, out: Path, angles: np.ndarray | None, console: Any
                   ) -> None:
    """Analyse a planar mechanism file: table on ``console``, CSV/JSON/PNG into ``out``.

    ``angles``: the table's driver positions [rad, or m for a linear driver]; None: 12 evenly
    spaced over the file's [analysis] range.
    """
    from rich.markup import escape
    from rich.table import Table

    from linkwork.plot import planar as pplot
    from linkwork.plot import save

    mech = doc.mechanism()
    crank = isinstance(mech.driver, Crank)
    phi = doc.positions()
    kin, dyn = _solve(doc, phi)
    s = mech.structure
    title = escape(doc.name or "planar mechanism")
    console.print(f"[bold]{title}[/bold]: mobility W = {s.mobility}; structure {s.formula()}")
    dcs = dead_centres(kin)
    if dcs:
        unit = "deg" if crank else "mm"
        conv = np.degrees if crank else (lambda v: v * 1e3)
        console.print("dead centres:")
        for d in dcs:
            console.print(f"  {escape(dead_centre_label(mech, d)[0])} at {conv(d.phi1):.2f} {unit}")
    # table at the requested positions, else at 12 evenly spaced ones
    tphi = np.linspace(phi[0], phi[-1], 12) if angles is None else np.asarray(angles, float)
    try:
        tk, td = _solve(doc, tphi)
    except AssemblyError as exc:
        raise table_positions_error(exc, tphi, not crank) from None
    trans = transmission_angles(tk)
    ab = np.asarray(dyn.about, dtype=float) * 1e3
    table = Table(title=escape(
        f"{'driving torque' if crank else 'driving force'}, joint reactions |R| (force of a on "
        f"b), shaking force and moment (about ({ab[0]:g}, {ab[1]:g}) mm)"))
    heads = ["φ1 [deg]" if crank else "s1 [mm]", "Q [N·m]" if crank else "Q [N]"]
    heads += [f"|R {j}| [N]" for j in td.joints]
    heads += ["|F_sh| [N]", "M_sh [N·m]"] + [f"μ {key} [deg]" for key in trans]
    for h in heads:  # escape: "[mm]", "[deg]" would be read as Rich markup
        table.add_column(escape(h), justify="right", min_width=len(h), no_wrap=True)
    for i in range(tk.n):
        row = [f"{np.degrees(tphi[i]) if crank else tphi[i] * 1e3:.1f}", f"{td.Q[i]:.4g}"]
        row += [f"{td.reaction_magnitude(j)[i]:.4g}" for j in td.joints]
        row += [f"{np.hypot(td.shaking_fx[i], td.shaking_fy[i]):.4g}", f"{td.shaking_m[i]:.4g}"]
        row += [f"{np.degrees(mu[i]):.1f}" for mu, _ in trans.values()]
        table.add_row(*row)
    console.print(table)
    peaks = cycle_peaks(kin, dyn)
    where = "φ1 [deg]" if crank else "s1 [mm]"
    ptab = Table(title=escape(f"extremes over the cycle ({kin.n} positions of [analysis])"))
    ptab.add_column("quantity", no_wrap=True)
    for h in ("value", where):
        ptab.add_column(escape(h), justify="right", no_wrap=True)
    for pk in peaks:
        pos = np.degrees(pk["phi1"]) if crank else pk["phi1"] * 1e3
        value, unit = pk["value"], pk["unit"].replace("*", "·")
        if unit == "rad":  # transmission angles: shown in degrees, as in the table above
            value, unit = np.degrees(value), "deg"
        ptab.add_row(escape(f"{pk['name']} [{unit}]"), f"{value:.4g}", f"{pos:.1f}")
    means = {"Q_mean": mean_over_range(kin.phi1, dyn.Q),
             "power_mean": mean_over_range(kin.phi1, dyn.power)}
    ptab.add_row(escape(f"Q mean (work / range) [{'N·m' if crank else 'N'}]"),
                 f"{means['Q_mean']:.4g}", "")
    ptab.add_row("driving power, mean [W]", f"{means['power_mean']:.4g}", "")
    console.print(ptab)
    # files
    cols = named_columns(kin, dyn)
    kin_cols = {k: v for k, v in cols.items() if not (k.startswith("R_") or k in (
        "Q", "shaking_fx", "shaking_fy", "shaking_m", "T"))}
    dyn_cols = {"phi1": cols["phi1"]}
    dyn_cols.update({k: v for k, v in cols.items() if k.startswith("R_") or k in (
        "Q", "shaking_fx", "shaking_fy", "shaking_m", "T")})
    written = [write_csv(out / "planar_kinematics.csv", kin_cols),
               write_csv(out / "planar_dynamics.csv", dyn_cols)]
    a_x, a_y = (float(v) for v in dyn.about)
    data = {
        "name": doc.name, "mobility": s.mobility, "structure": s.formula(),
        "groups": [{"kind": g.kind, "bodies": list(g.bodies), "joints": list(g.joints),
                    "class": g.cls, "order": g.order, "key": g.key,
                    "branch": kin.branches.get(g.key, 1)} for g in s.groups],
        "reaction_sign": "force exerted by joint body a on joint body b, frame axes",
        "torque_sign": (f"Q: {'torque' if crank else 'force along the guide'} on body "
                        f"{mech.joint(mech.driver.joint).b!r} of driver joint "
                        f"{mech.driver.joint!r} through body {mech.joint(mech.driver.joint).a!r}"
                        f"{', counter-clockwise +' if crank else ''}; driving power Q*omega1"),
        "shaking_sign": ("force and moment exerted by the moving bodies on the frame (motor "
                         "reaction included), moment counter-clockwise + about "
                         f"({a_x:g}, {a_y:g}) m"),
        "positions_unit": "rad" if crank else "m",
        "dead_centres": [{"group": d.group, "body": d.body, "phi1": d.phi1, "kind": d.kind,
                          "of": dead_centre_label(mech, d)[0],
                          "joint": dead_centre_label(mech, d)[1]} for d in dcs],
        "peaks": peaks,
        "means": {**means, "units": {"Q_mean": "N*m" if crank else "N", "power_mean": "W"}},
        "units": {k: u for k, (_, u) in cols.items()},
        "columns": {k: [None if not np.isfinite(x) else float(x) for x in v]
                    for k, (v, _) in cols.items()},
    }
    p = out / "planar.json"
    p.write_text(json.dumps(data, indent=1))
    written.append(p)
    # plots
    plt = pplot.pyplot()
    fig, ax = plt.subplots(figsize=(7, 6))
    good = np.flatnonzero(kin.assembled)
    picks = [int(good[k]) for k in np.linspace(0, good.size - 1, 4, endpoint=False).astype(int)]
    paths = _distinct_paths(kin, [(b.name, pt) for b in mech.bodies
                                  for pt in list(b.points)[1:2]])
    pplot.plot_skeleton(kin, picks, paths=paths, ax=ax)
    written.append(save(fig, out / "planar_skeleton.png"))
    fig, ax = plt.subplots()
    pplot.plot_driving_torque(dyn, ax=ax)
    written.append(save(fig, out / "planar_driving_torque.png"))
    fig, ax = plt.subplots()
    pplot.plot_reactions(dyn, ax=ax)
    written.append(save(fig, out / "planar_reactions.png"))
    fig, axes = plt.subplots(2, 1, sharex=True)
    pplot.plot_shaking(dyn, axes=axes)
    written.append(save(fig, out / "planar_shaking.png"))
    console.print("wrote " + ", ".join(str(w) for w in written))
