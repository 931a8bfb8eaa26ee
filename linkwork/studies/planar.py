"""A ``planar`` file over its cycle: kinematics, dynamics, dead centres, extremes, a table.

:func:`analyze` builds the mechanism of a :class:`~linkwork.io.planar.PlanarFile` once (its
structure decomposition is cached with it), solves the file's [analysis] positions and the
table positions, and returns a :class:`PlanarStudy` that carries everything ``linkwork analyze``
prints, writes and plots. Nothing is printed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.loads import mean_over_range
from linkwork.checks import require_finite
from linkwork.errors import AssemblyError, ParameterError, angle_ranges, format_angle_ranges
from linkwork.io.planar import MAX_WHOLE_POSITIONS, PlanarFile, whole_cycle_limit
from linkwork.planar import (
    AppliedLoad,
    Crank,
    DeadCentre,
    Dynamics,
    Kinematics,
    LoadDiagram,
    Mechanism,
    PinInSlot,
    Prismatic,
    Revolute,
    dead_centres,
    inverse_dynamics,
    kinematics,
    transmission_angles,
)
from linkwork.planar.extremes import output_rates
from linkwork.planar.kinematics import dead_centres_over, state_of
from linkwork.planar.structure import Structure
from linkwork.results import json_array

__all__ = ["CHUNK_POSITIONS", "PLOT_POSITIONS", "PlanarStudy", "PlanarSummary", "analyze",
           "analyze_chunked",
           "cycle_peaks", "dead_centre_label", "default_table_positions", "distinct_paths",
           "driver_columns", "dynamics_columns_of", "friction_summary", "kinematics_columns_of",
           "load_summary", "named_columns", "reported_loads", "table_positions_error"]

Transmission = dict[str, tuple[np.ndarray, np.ndarray]]
OnFailure = Literal["raise", "nan"]


def table_positions_error(exc: AssemblyError, positions: np.ndarray, linear: bool
                          ) -> ParameterError:
    """The error for table positions (``--angles``) where the mechanism does not assemble,
    although the file's [analysis] range does."""
    vals = np.asarray(positions, dtype=float) * 1e3 if linear else np.degrees(positions)
    shown = ", ".join(f"{v:g}" for v in vals) + (" mm" if linear else " deg")
    return ParameterError("--angles", shown, f"the table positions leave the range where the "
                          f"mechanism assembles ({exc}); give --angles within the file's "
                          "[analysis] range")


def driver_columns(mech: Mechanism, fields: dict[str, np.ndarray]
                   ) -> dict[str, tuple[np.ndarray, str]]:
    """Columns of driver fields (``phi1, omega1, eps1, Q, Q_frictionless``): the field itself
    for one driver, ``<field>.<driver joint>`` per driver for several, each in its unit."""
    out: dict[str, tuple[np.ndarray, str]] = {}
    drivers = mech.drivers
    for key, arr in fields.items():
        unit_key = "Q" if key.startswith("Q") else key
        if len(drivers) == 1:
            out[key] = (arr, drivers[0].field_units[unit_key])
            continue
        for k, d in enumerate(drivers):
            out[f"{key}.{d.joint}"] = (arr[k], d.field_units[unit_key])
    return out


def named_columns(kin: Kinematics, dyn: Dynamics, transmission: Transmission | None = None
                  ) -> dict[str, tuple[np.ndarray, str]]:
    """Readable per-position columns: name -> (values, unit). ``transmission``: the result of
    :func:`~linkwork.planar.transmission_angles` of ``kin`` if already computed.

    Per moving body: ``<body>.theta/omega/eps`` and its centre of mass ``<body>.xS/yS/vxS/vyS/
    axS/ayS``, then every named point of the body (frame axes, :meth:`Kinematics.point`):
    ``<body>.<point>.x/y`` [m], ``.vx/.vy`` [m/s], ``.ax/.ay`` [m/s^2]; a joint's point named
    on both of its bodies appears under each. Then the dynamics (:func:`dynamics_columns_of`)
    and the transmission angles ``mu_<group>``. Several drivers: ``phi1.<joint>``,
    ``omega1.<joint>``, ``eps1.<joint>``, ``Q.<joint>`` per driver (:func:`driver_columns`)."""
    cols = kinematics_columns_of(kin)
    cols.update({k: v for k, v in dynamics_columns_of(kin, dyn).items() if k != "phi1"})
    trans = transmission_angles(kin) if transmission is None else transmission
    for key, (mu, _) in trans.items():
        cols[f"mu_{key}"] = (mu, "rad")
    return cols


def kinematics_columns_of(kin: Kinematics) -> dict[str, tuple[np.ndarray, str]]:
    """The driver's and every body's and named point's motion (see :func:`named_columns`)."""
    mech = kin.mechanism
    cols = driver_columns(mech, {"phi1": kin.phi1, "omega1": kin.omega1, "eps1": kin.eps1})
    for b in mech.bodies:
        i = mech.index[b.name]
        c = kin.point(b.name, "com")
        for name, arr, unit in (("theta", kin.theta[i], "rad"), ("omega", kin.omega[i], "rad/s"),
                                ("eps", kin.eps[i], "rad/s^2"), ("xS", c.x, "m"),
                                ("yS", c.y, "m"), ("vxS", c.vx, "m/s"), ("vyS", c.vy, "m/s"),
                                ("axS", c.ax, "m/s^2"), ("ayS", c.ay, "m/s^2")):
            cols[f"{b.name}.{name}"] = (arr, unit)
        for pt in b.points:  # every named point (joint centres, coupler points): its path
            p = kin.point(b.name, pt)
            for name, arr, unit in (("x", p.x, "m"), ("y", p.y, "m"), ("vx", p.vx, "m/s"),
                                    ("vy", p.vy, "m/s"), ("ax", p.ax, "m/s^2"),
                                    ("ay", p.ay, "m/s^2")):
                cols[f"{b.name}.{pt}.{name}"] = (arr, unit)
    return cols


def reported_loads(dyn: Dynamics) -> list[AppliedLoad]:
    """The loads whose value and power the study reports: force elements (springs, dampers,
    drags), slide forces and loads given by a diagram. Constant point forces and couples (all
    the loads of files before them) are not: their effect is in ``Q`` and the reactions, and
    their files keep their columns."""
    return [ap for ap in dyn.loads if ap.kind not in ("force", "torque") or any(
        isinstance(getattr(ap.load, f, None), LoadDiagram) for f in ("fx", "fy", "mz"))]


def dynamics_columns_of(kin: Kinematics, dyn: Dynamics, *, by_structure: bool = False
                        ) -> dict[str, tuple[np.ndarray, str]]:
    """``phi1``, every joint's reaction ``R_<joint>.x/.y`` [N] (``.mz`` [N m] where not zero),
    ``Q``, the shaking force and moment, ``T``; with friction ``Q_frictionless``, the friction
    powers ``Pf_<joint>`` [W], ``efficiency`` and ``locked``; with force elements or load
    diagrams (:func:`reported_loads`) each one's value ``F_<name>`` [N] (a couple ``M_<name>``
    [N m]), a spring's or damper's length ``L_<name>`` [m] and power ``P_<name>`` [W], and the
    energy in the springs ``V`` [J]. ``by_structure``: a joint's couple and friction power are
    columns wherever the joint can carry them (a prismatic pair's couple, a joint with
    friction), not only where they are not zero throughout these positions (the same columns
    for every chunk of a long cycle, :func:`analyze_chunked`)."""
    mech = kin.mechanism
    cols = driver_columns(mech, {"phi1": kin.phi1})
    joints = [mech.joint(j) for j in dyn.joints]
    for k, j in enumerate(dyn.joints):
        cols[f"R_{j}.x"] = (dyn.fx[k], "N")
        cols[f"R_{j}.y"] = (dyn.fy[k], "N")
        if (("t" in joints[k].row_kinds or joints[k].has_friction) if by_structure
                else np.any(dyn.mz[k] != 0)):
            cols[f"R_{j}.mz"] = (dyn.mz[k], "N*m")
    cols.update(driver_columns(mech, {"Q": dyn.Q}))
    cols["shaking_fx"] = (dyn.shaking_fx, "N")
    cols["shaking_fy"] = (dyn.shaking_fy, "N")
    cols["shaking_m"] = (dyn.shaking_m, "N*m")
    cols["T"] = (dyn.T, "J")
    if dyn.has_friction:  # only then: frictionless files keep their columns
        cols.update(driver_columns(mech, {"Q_frictionless": dyn.Q_frictionless}))
        for k, j in enumerate(dyn.joints):
            if (joints[k].has_friction if by_structure
                    else np.any(dyn.friction_power[k] != 0)):
                cols[f"Pf_{j}"] = (dyn.friction_power[k], "W")
        cols["efficiency"] = (dyn.efficiency, "")
        cols["locked"] = (dyn.locked.astype(float), "1")  # a flag, as "valid [1]"
    shown = reported_loads(dyn)
    for ap in shown:
        cols[f"{'M' if ap.unit == 'N*m' else 'F'}_{ap.name}"] = (ap.value, ap.unit)
        if ap.length is not None:
            cols[f"L_{ap.name}"] = (ap.length, "m")
        cols[f"P_{ap.name}"] = (ap.power, "W")
    if any(ap.kind == "spring" for ap in dyn.loads):
        cols["V"] = (dyn.V, "J")
    return cols


def load_summary(dyn: Dynamics) -> list[dict[str, Any]]:
    """What each reported load (:func:`reported_loads`) does over the analysed range: its
    ``name``, ``kind``, the smallest and largest ``value`` (``min``, ``max``, ``unit``, with
    the driver positions ``min_at``, ``max_at``), a spring's or damper's shortest and longest
    ``length`` [m], the ``work`` it does on the mechanism over the range [J] (the time integral
    of its power in the order the driver passes the positions; negative: taken from the
    mechanism; None if the driver stops or reverses), and a diagram's ``diagram``: ``over``,
    ``range`` (first and last position of its table, [rad] or [m]), ``when``, ``outside``."""
    out = []
    order = dyn._time_order()
    w1 = np.broadcast_to(np.asarray(dyn.kinematics.omega1, dtype=float), dyn.phi1.shape)

    def at(v: np.ndarray, pick: Any) -> tuple[float | None, float | None]:
        if not np.any(np.isfinite(v)):
            return None, None
        i = int(pick(v))
        return float(v[i]), float(dyn.phi1[i])

    for ap in reported_loads(dyn):
        with np.errstate(all="ignore"):
            work = order * float(np.trapezoid(ap.power / w1, dyn.phi1)) if order else None
        length = (None if ap.length is None else
                  (float(np.nanmin(ap.length)), float(np.nanmax(ap.length))))
        out.append(_load_record(ap, at(ap.value, np.nanargmin), at(ap.value, np.nanargmax),
                                length, work))
    return out


def _load_record(ap: AppliedLoad, lo: tuple[float | None, float | None],
                 hi: tuple[float | None, float | None], length: tuple[float, float] | None,
                 work: float | None) -> dict[str, Any]:
    """One entry of :func:`load_summary`: ``lo``, ``hi`` the smallest and largest value with
    their positions, ``length`` a spring's or damper's extremes, ``work`` over the range."""
    entry: dict[str, Any] = {"name": ap.name, "kind": ap.kind, "unit": ap.unit, "min": lo[0],
                             "min_at": lo[1], "max": hi[0], "max_at": hi[1],
                             "work": work if work is None or np.isfinite(work) else None}
    if length is not None:
        entry["length"] = list(length)
    diagrams = [d for d in (getattr(ap.load, f, None) for f in ("fx", "fy", "mz", "force"))
                if isinstance(d, LoadDiagram)]
    if diagrams:
        d = diagrams[0]
        entry["diagram"] = {"over": d.over, "range": list(d.table_range), "when": d.when,
                            "outside": d.outside}
    return entry


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


def cycle_peaks(kin: Kinematics, dyn: Dynamics, transmission: Transmission | None = None
                ) -> list[dict[str, Any]]:
    """Extremes over the analysed positions, for sizing motor and bearings.

    One entry per quantity: ``{"name", "value", "unit", "phi1"}`` (``phi1`` the driver position
    of the extreme [rad, or m for a linear driver]): the largest and the smallest driving torque
    (force), the peak magnitude of every joint reaction (and of a prismatic joint's couple), of
    the shaking force and of the shaking moment, and the smallest transmission angle of every
    group (its worst position) [rad]. Sampled at the positions analysed (no interpolation
    between them); unassembled positions (NaN) are skipped. ``transmission``: the result of
    :func:`~linkwork.planar.transmission_angles` of ``kin`` if already computed.
    """
    trans = transmission_angles(kin) if transmission is None else transmission
    peaks = []
    for name, v, unit, kind, couple in _peak_series(kin, dyn, trans):
        if couple is not None and not np.any(dyn.mz[couple] != 0):
            continue  # a joint that carries no couple
        if not np.any(np.isfinite(v)):
            continue
        i = int(np.nanargmax(v) if kind == "max" else np.nanargmin(v))
        at: Any = (float(kin.phi1[i]) if kin.phi1.ndim == 1  # several drivers: each one's, and
                   else [float(x) for x in kin.phi1[:, i]])  # the position's index
        peaks.append({"name": name, "value": float(v[i]), "unit": unit, "phi1": at,
                      **({} if kin.phi1.ndim == 1 else {"position": i})})
    return peaks


#: A quantity of :func:`cycle_peaks`: name, values, unit, "max" or "min", and for the couple
#: of a joint the joint's index (kept only where the joint carries a couple), else None.
PeakSeries = tuple[str, np.ndarray, str, str, int | None]


def _peak_series(kin: Kinematics, dyn: Dynamics, trans: Transmission) -> list[PeakSeries]:
    """The quantities of :func:`cycle_peaks`, the couple ``|M j|`` of every joint included."""
    series: list[PeakSeries] = []
    for name, (q, unit_q) in driver_columns(kin.mechanism, {"Q": dyn.Q}).items():
        label = name.replace(".", " ")  # several drivers: "Q O1 max"
        series += [(f"{label} max", q, unit_q, "max", None),
                   (f"{label} min", q, unit_q, "min", None)]
    for k, j in enumerate(dyn.joints):
        series.append((f"|R {j}|", np.hypot(dyn.fx[k], dyn.fy[k]), "N", "max", None))
        series.append((f"|M {j}|", np.abs(dyn.mz[k]), "N*m", "max", k))
    series += [("|F_sh|", np.hypot(dyn.shaking_fx, dyn.shaking_fy), "N", "max", None),
               ("|M_sh|", np.abs(dyn.shaking_m), "N*m", "max", None)]
    series += [(f"μ {key} min", mu, "rad", "min", None) for key, (mu, _) in trans.items()]
    return series


def friction_summary(dyn: Dynamics) -> dict[str, Any] | None:
    """Efficiency and friction losses over the analysed range; None without friction.

    ``efficiency_cycle`` (useful work over the driver's work, :attr:`Dynamics.efficiency_cycle`;
    None where undefined), ``driving_work`` [J] (None if some position is locked),
    ``losses`` (joint -> work dissipated [J], None if undefined), ``loss_share`` (joint ->
    fraction of the driver's work, None if undefined), ``self_locking`` (list of [first,
    last] driver positions [rad, or m] of the locked runs), ``locked_positions`` (count) and
    ``newton_iterations`` of the friction solve."""
    if not dyn.has_friction:
        return None
    return _friction_record(dyn.joints, dyn.driving_work, dyn.friction_losses,
                            dyn.self_locking_ranges(), int(np.sum(dyn.locked)),
                            dyn.friction_iterations)


def _friction_record(joints: tuple[str, ...], wd: float, losses: np.ndarray,
                     runs: list[tuple[float, float]], locked: int, iterations: int
                     ) -> dict[str, Any]:
    """The dict of :func:`friction_summary` from the driver's work ``wd`` [J] and the losses
    per joint [J] over the range (NaN where undefined), the self-locking runs, their number of
    positions and the friction solve's Newton steps."""
    loss = float(np.sum(losses))
    wd_ok = bool(np.isfinite(wd) and wd > 0)

    def num(v: float) -> float | None:
        return float(v) if np.isfinite(v) else None

    return {
        "efficiency_cycle": 1.0 - loss / wd if wd_ok and np.isfinite(loss) else None,
        "driving_work": num(wd),
        "losses": {j: num(v) for j, v in zip(joints, losses, strict=True)},
        "loss_share": {j: (num(v / wd) if wd_ok else None)
                       for j, v in zip(joints, losses, strict=True)},
        "self_locking": [[a, b] for a, b in runs],
        "locked_positions": locked,
        "newton_iterations": iterations,
    }


def distinct_paths(kin: Kinematics, candidates: list[tuple[str, str]]
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


@dataclass(frozen=True)
class PlanarStudy:
    """A planar mechanism over its cycle (what ``linkwork analyze`` shows of a planar file).

    Attributes
    ----------
    doc : PlanarFile
        The validated file.
    mechanism : Mechanism
        The engine model (built once; its structure decomposition is cached with it).
    kinematics, dynamics : Kinematics, Dynamics
        The file's [analysis] positions (driver positions last axis).
    transmission : dict
        Transmission angles over the cycle: group key -> (mu [rad], ...).
    table_positions : ndarray
        The table's driver positions [rad, or m for a linear driver].
    table_kinematics, table_dynamics : Kinematics, Dynamics
        At the table positions.
    table_transmission : dict
        Transmission angles at the table positions.
    dead_centres : list of DeadCentre
        Over the cycle; ``dead_centre_labels`` (what reaches its extreme, the joint) beside.
    peaks : list of dict
        :func:`cycle_peaks` of the cycle.
    means : dict
        ``Q_mean`` (work / range) [N m or N] and ``power_mean`` [W] over the cycle (several
        drivers: ``Q_mean`` per driver joint).
    friction : dict or None
        :func:`friction_summary` of the cycle (None: no joint has friction).
    loads : list of dict
        :func:`load_summary` of the cycle: the force elements and load diagrams (empty
        without them).
    """

    doc: PlanarFile
    mechanism: Mechanism
    kinematics: Kinematics
    dynamics: Dynamics
    transmission: Transmission
    table_positions: np.ndarray
    table_kinematics: Kinematics
    table_dynamics: Dynamics
    table_transmission: Transmission
    dead_centres: list[DeadCentre]
    dead_centre_labels: list[tuple[str, str]]
    peaks: list[dict[str, Any]]
    means: dict[str, Any]
    friction: dict[str, Any] | None = None
    loads: list[dict[str, Any]] = field(default_factory=list)

    @property
    def crank(self) -> bool:
        """True for a crank driver (angles [rad]), False for a linear one (slides [m]) or
        several drivers."""
        return isinstance(self.mechanism.driver, Crank)

    @property
    def unassembled(self) -> list[tuple[float, float]]:
        """Ranges ``[(first, last), ...]`` of the analysed driver positions [rad, or m] where the
        mechanism does not assemble (empty unless analysed with ``on_failure="nan"``); with
        several drivers, of the positions' indices along their path."""
        kin = self.kinematics
        along = kin.phi1 if np.ndim(kin.phi1) == 1 else np.arange(kin.n, dtype=float)
        return angle_ranges(along, ~np.asarray(kin.valid, bool))

    @property
    def structure(self) -> Structure:
        """Mobility and Assur groups of the mechanism."""
        return self.mechanism.structure

    @property
    def positions(self) -> np.ndarray:
        """The file's [analysis] driver positions [rad, or m for a linear driver]."""
        return np.asarray(self.kinematics.phi1)

    def columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """Readable per-position columns of the cycle: name -> (values, unit)."""
        return named_columns(self.kinematics, self.dynamics, self.transmission)

    def kinematics_columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """The columns of ``planar_kinematics.csv``: poses, velocities, accelerations (of every
        body, its centre of mass and its named points), transmission angles."""
        cols = kinematics_columns_of(self.kinematics)
        cols.update({f"mu_{key}": (mu, "rad") for key, (mu, _) in self.transmission.items()})
        return cols

    def dynamics_columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """The columns of ``planar_dynamics.csv``: reactions, driving torque, shaking, kinetic
        energy, friction, loads (after ``phi1``; :func:`dynamics_columns_of`)."""
        return dynamics_columns_of(self.kinematics, self.dynamics)

    def scene(self, *, paths: Any = None, centres: bool = False) -> Any:
        """The mechanism drawn over the cycle (:func:`linkwork.plot.scene.planar_scene`) with
        its force elements and loads where they act: ``paths`` of further points (coupler
        curves), ``centres`` the instant centres."""
        from linkwork.plot.scene import planar_scene

        return planar_scene(self.kinematics, paths=paths, centres=centres,
                            title=self.doc.name or "planar mechanism",
                            loads=self.dynamics.loads)

    def _repr_html_(self) -> str:
        """A notebook's display: the animated mechanism and the extremes over the cycle (a row
        shows its position)."""
        from linkwork.plot.html import peaks_table, view_html

        unit = self.mechanism.driver_units["phi1"]
        title = self.doc.name or "planar mechanism"
        return view_html(self.scene(), peaks_table(
            f"{title}: extremes over {self.kinematics.n} positions", self.peaks, unit))

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """The mechanism at its first assembled position with its point paths, and the driving
        torque (force) over the cycle: a :class:`linkwork.plot.Figure` with 2 axes (``kw``:
        ``paths``, ``centres`` of :meth:`scene`)."""
        from linkwork.plot import Figure, axes_or_new
        from linkwork.plot.planar import plot_driving_torque
        from linkwork.plot.scene import mechanism_figure

        ax = axes_or_new(axes, 1, 2, figsize=(13, 5))
        name = self.doc.name or None
        mechanism_figure(self.scene(**kw), ax=ax[0])
        plot_driving_torque(self.dynamics, ax=ax[1], name=name)
        return Figure.of(ax)

    @property
    def n(self) -> int:
        """Number of positions analysed."""
        return int(self.kinematics.n)

    def to_dict(self, *, lists: bool = True) -> dict[str, Any]:
        """Everything of the study as JSON-able values (``planar.json``). ``lists=False``: the
        per-position columns as float arrays, which :func:`~linkwork.results.write_json` writes
        as the same JSON without making lists of them (32 bytes a value: 197 MB for the
        six-bar's 123 columns at 50 000 positions)."""
        cols = self.columns()
        return {
            **_summary_dict(self.doc, self.mechanism, self.kinematics.branches,
                            self.dynamics.about, self.dead_centres, self.dead_centre_labels,
                            self.peaks, self.means),
            "units": {k: u for k, (_, u) in cols.items()},
            "columns": {k: (json_array(v) if lists else np.asarray(v, dtype=float))
                        for k, (v, _) in cols.items()},
            **_friction_and_loads(self.friction, self.loads),
        }


def _friction_and_loads(friction: dict[str, Any] | None, loads: list[dict[str, Any]]
                        ) -> dict[str, Any]:
    """The ``friction`` and ``loads`` entries of ``planar.json`` (each only if there is one)."""
    extra: dict[str, Any] = {} if friction is None else {"friction": friction}
    if loads:
        extra["loads"] = loads
    return extra


def _summary_dict(doc: PlanarFile, mech: Mechanism, branches: Mapping[str, int], about: Any,
                  dcs: list[DeadCentre], labels: list[tuple[str, str]],
                  peaks: list[dict[str, Any]], means: dict[str, Any]) -> dict[str, Any]:
    """What ``planar.json`` says of a cycle besides its per-position columns: the structure
    with the branches, the sign conventions, the dead centres, extremes and means."""
    s = mech.structure
    a_x, a_y = (float(v) for v in about)
    signs = []
    for d in mech.drivers:
        drv = mech.joint(d.joint)
        turn = d.kind == "crank"
        signs.append(f"{'torque' if turn else 'force along the guide'} on body {drv.b!r} "
                     f"of driver joint {d.joint!r} through body {drv.a!r}"
                     f"{', counter-clockwise +' if turn else ''}")
    torque_sign = (f"Q: {signs[0]}; driving power Q*omega1" if len(signs) == 1 else
                   "Q.<driver joint>: " + "; ".join(signs) + "; driving power of each "
                   "Q*omega1")
    return {
        "name": doc.name, "mobility": s.mobility, "structure": s.formula(),
        "groups": [{"kind": g.kind, "bodies": list(g.bodies), "joints": list(g.joints),
                    "class": g.cls, "order": g.order, "key": g.key,
                    "branch": branches.get(g.key, 1)} for g in s.groups],
        "reaction_sign": "force exerted by joint body a on joint body b, frame axes",
        "torque_sign": torque_sign,
        "shaking_sign": ("force and moment exerted by the moving bodies on the frame "
                         "(motor reaction included), moment counter-clockwise + about "
                         f"({a_x:g}, {a_y:g}) m"),
        "positions_unit": mech.driver_units["phi1"],
        "dead_centres": [{"group": d.group, "body": d.body, "phi1": d.phi1, "kind": d.kind,
                          "of": lab[0], "joint": lab[1]}
                         for d, lab in zip(dcs, labels, strict=True)],
        "peaks": peaks,
        "means": {**means, "units": {"Q_mean": mech.driver_units["Q"], "power_mean": "W"}},
    }


def _solve(doc: PlanarFile, mech: Mechanism, phi: np.ndarray, on_failure: OnFailure = "raise"
           ) -> tuple[Kinematics, Dynamics]:
    kin = kinematics(mech, phi, on_failure=on_failure)
    a = doc.analysis
    try:
        dyn = inverse_dynamics(kin, gravity=a.gravity, loads=doc.loads(phi), about=a.about)
    except ParameterError as exc:  # a load at these positions (a diagram left, a spring...)
        raise doc.file_error(exc) from None
    return kin, dyn


def _range_text(phi: np.ndarray, crank: bool) -> str:
    return format_angle_ranges([(float(phi[0]), float(phi[-1]))], "rad" if crank else "m")


#: Spacing of the default table positions of a crank [rad]: every 30 deg.
TABLE_STEP = np.pi / 6
#: Positions of the default table when the crank's range holds too few multiples of 30 deg,
#: and of a linear driver.
TABLE_COUNT = 12


def default_table_positions(doc: PlanarFile) -> np.ndarray:
    """The driver positions of the tables of every command when none are given [rad or m].

    A crank: the multiples of 30 deg inside the file's [analysis] range (0, 30, ..., 330 deg on
    a full turn: the end of a full turn is its start again); a range that holds fewer than 4 of
    them, and a linear driver: 12 positions evenly spaced over the range, both ends included.
    So every command (analyze, reactions, ...) tables the same positions, inside the range where
    the file says the mechanism works, for either kind of driver.
    """
    phi = doc.positions()
    if phi.ndim == 2:  # several drivers: 12 positions along their path, both ends included
        return np.linspace(phi[:, 0], phi[:, -1], TABLE_COUNT, axis=1)
    lo, hi = float(phi[0]), float(phi[-1])
    if doc.driver.type == "crank":
        tol = 1e-9 * max(1.0, abs(lo), abs(hi))
        k = np.arange(np.ceil((lo - tol) / TABLE_STEP), np.floor((hi + tol) / TABLE_STEP) + 1)
        steps = k * TABLE_STEP + 0.0  # no -0
        if hi - lo >= 2 * np.pi - tol:  # a whole turn: its end is its start
            steps = steps[steps < lo + 2 * np.pi - tol]
        if len(steps) >= 4:
            return np.asarray(steps, float)
    return np.linspace(lo, hi, TABLE_COUNT)


def _means(mech: Mechanism, kin: Kinematics, dyn: Dynamics) -> dict[str, Any]:
    """``Q_mean`` (work / range) and ``power_mean`` over the cycle; several drivers: ``Q_mean``
    per driver joint (None for a driver that does not move) and the mean of their total power
    over the range of the first driver that moves."""
    if mech.n_drivers == 1:
        return {"Q_mean": dyn.Q_mean, "power_mean": mean_over_range(kin.phi1, dyn.power)}
    qm = dyn.Q_mean
    moving = [k for k in range(mech.n_drivers) if kin.phi1[k, -1] != kin.phi1[k, 0]]
    power = (mean_over_range(kin.phi1[moving[0]], dyn.total_power) if moving
             else float(np.mean(dyn.total_power)))
    return {"Q_mean": {d.joint: (float(qm[k]) if np.isfinite(qm[k]) else None)
                       for k, d in enumerate(mech.drivers)}, "power_mean": power}


def analyze(doc: PlanarFile, *, angles: ArrayLike | None = None,
            on_failure: OnFailure = "raise") -> PlanarStudy:
    """Analyse a planar mechanism file over its [analysis] positions and at table positions.

    Parameters
    ----------
    doc : PlanarFile
        The validated file (:func:`linkwork.io.load`).
    angles : array_like, optional
        The table's driver positions [rad, or m for a linear driver]; default
        :func:`default_table_positions`.
    on_failure : {"raise", "nan"}
        Where the mechanism does not assemble over part of the range: raise (default), or
        solve the rest and leave NaN there (``study.kinematics.valid`` says where; the table
        positions likewise; :attr:`PlanarStudy.unassembled` lists the ranges).

    Returns
    -------
    PlanarStudy

    Raises
    ------
    AssemblyError
        The mechanism does not assemble over the file's range (with ``on_failure="nan"``:
        at no position of it).
    ParameterError
        The table positions leave the range where the mechanism assembles (``--angles``), or
        ``[analysis] n`` exceeds :data:`~linkwork.io.planar.MAX_WHOLE_POSITIONS` (a longer
        cycle of one driver: :func:`analyze_chunked`).
    """
    if doc.analysis.n > MAX_WHOLE_POSITIONS:
        raise ParameterError("analysis.n", doc.analysis.n, whole_cycle_limit(
            doc.analysis.n, "analyze(), which holds the whole cycle") +
            "; a cycle of one driver: analyze_chunked()")
    mech = doc.mechanism()
    crank = isinstance(mech.driver, Crank)
    phi = doc.positions()
    kin, dyn = _solve(doc, mech, phi, on_failure)
    if not np.any(kin.valid):
        raise AssemblyError(f"the mechanism assembles at no position of the [analysis] range "
                            f"({_range_text(phi, crank)})")
    dcs = dead_centres(kin)
    tphi = default_table_positions(doc) if angles is None else np.asarray(angles, float)
    if mech.n_drivers > 1 and (tphi.ndim != 2 or tphi.shape[0] != mech.n_drivers):
        raise ParameterError("--angles", tphi.shape, f"must give the positions of the "
                             f"{mech.n_drivers} drivers, one row each")
    try:
        tk, td = _solve(doc, mech, tphi, on_failure)
    except AssemblyError as exc:
        raise table_positions_error(exc, tphi, not crank) from None
    trans = transmission_angles(kin)
    return PlanarStudy(
        doc=doc, mechanism=mech, kinematics=kin, dynamics=dyn, transmission=trans,
        table_positions=tphi, table_kinematics=tk, table_dynamics=td,
        table_transmission=transmission_angles(tk), dead_centres=dcs,
        dead_centre_labels=[dead_centre_label(mech, d) for d in dcs],
        peaks=cycle_peaks(kin, dyn, trans),
        means=_means(mech, kin, dyn),
        friction=friction_summary(dyn), loads=load_summary(dyn))


# ---------------------------------------------------------------------------------------------
# long cycles: chunk by chunk, in bounded memory

#: Positions per chunk of :func:`analyze_chunked`: a chunk of the four-bar of paper 001 with its
#: columns takes some 4 kB per position (measured: 141 MiB peak resident for 10^6 positions in
#: chunks of 8192, 162 MiB in chunks of 32768, the same time), besides the positions and 8
#: bytes per position and group kept for the dead centres.
CHUNK_POSITIONS = 16_384

#: Positions of :meth:`PlanarSummary.sample`: what the plots of a long cycle draw (a step of
#: 0.036 deg over a turn, finer than a plot's pixels).
PLOT_POSITIONS = 10_001

#: What receives the per-position columns of one chunk: ``sink(kinematic, dynamic)``, two
#: mappings name -> values, those of ``planar_kinematics.csv`` and ``planar_dynamics.csv`` in
#: their order (the same names every chunk).
ColumnSink = Callable[[dict[str, np.ndarray], dict[str, np.ndarray]], None]


class _Trapezoid:
    """The trapezoid integral of values over the positions, fed chunk by chunk (each chunk's
    first segment starts at the previous chunk's last sample), with what
    :func:`~linkwork.cycles.mean_over_range` needs when a value is not finite."""

    def __init__(self, width: int = 0) -> None:
        shape = (width,) if width else ()
        self.total = np.zeros(shape)
        self.finite = True
        self.nansum = np.zeros(shape)
        self.count = np.zeros(shape)
        self.last: tuple[float, np.ndarray] | None = None

    def add(self, phi: np.ndarray, values: np.ndarray) -> None:
        v = np.asarray(values, dtype=float)
        x = phi
        if self.last is not None:
            x = np.concatenate([[self.last[0]], phi])
            v = np.concatenate([self.last[1][..., None], v], axis=-1)
        self.total = self.total + np.trapezoid(v, x, axis=-1)
        tail = np.asarray(values, dtype=float)
        self.finite = self.finite and bool(np.all(np.isfinite(tail)))
        self.nansum = self.nansum + np.nansum(tail, axis=-1)
        self.count = self.count + np.sum(np.isfinite(tail), axis=-1)
        self.last = (float(phi[-1]), tail[..., -1].copy())

    def mean(self, first: float, last: float, n: int) -> float:
        """:func:`~linkwork.cycles.mean_over_range` of the values fed (NaN if one is not
        finite: the work over a range where the value is undefined somewhere is undefined)."""
        if not self.finite or n == 0:
            return float("nan")
        if n > 1 and last != first:
            return float(self.total / (last - first))
        return float(self.nansum / self.count)


class _ChunkStats:
    """The running statistics of :func:`analyze_chunked` over the chunks of a cycle."""

    def __init__(self, mech: Mechanism, phi: np.ndarray) -> None:
        self.mech = mech
        self.phi = phi
        self.rates: dict[str, tuple[int, np.ndarray]] = {}
        self.branches: dict[str, int] = {}
        # name -> [value, phi1, unit, kind, couple joint]; couples seen not zero
        self.best: dict[str, list[Any]] = {}
        self.couples: set[int] = set()
        self.q = _Trapezoid()
        self.power = _Trapezoid()
        nj = len(mech.joints)
        self.has_friction = any(j.has_friction for j in mech.joints)
        self.losses = _Trapezoid(nj)      # friction power / omega1 over phi1
        self.w1_pos = self.w1_neg = True  # the driver turns one way throughout
        self.w1_first = 0.0
        # reported loads by name: [load, (min, at), (max, at), [shortest, longest], work]
        self.loads: dict[str, list[Any]] = {}
        self.runs: list[tuple[float, float]] = []
        self.locked = 0
        self.iterations = 0
        self.last_locked = False

    def add(self, lo: int, kin: Kinematics, dyn: Dynamics, trans: Transmission) -> None:
        q, n = kin.phi1, self.phi.size
        if not self.branches:
            self.branches = dict(kin.branches)
        for key, (b, rate) in output_rates(self.mech.plan, state_of(kin)).items():
            if key not in self.rates:
                self.rates[key] = (b, np.empty(n))
            self.rates[key][1][lo:lo + q.size] = rate
        for name, v, unit, kind, couple in _peak_series(kin, dyn, trans):
            if couple is not None and np.any(dyn.mz[couple] != 0):
                self.couples.add(couple)
            entry = self.best.setdefault(name, [None, None, unit, kind, couple])
            if not np.any(np.isfinite(v)):
                continue
            i = int(np.nanargmax(v) if kind == "max" else np.nanargmin(v))
            val = float(v[i])
            if entry[0] is None or (val > entry[0] if kind == "max" else val < entry[0]):
                entry[0], entry[1] = val, float(q[i])  # strict: the first position wins
        self.q.add(q, dyn.Q)
        self.power.add(q, dyn.power)
        w1 = np.broadcast_to(np.asarray(kin.omega1, dtype=float), q.shape)
        if lo == 0:
            self.w1_first = float(w1[0])
        self.w1_pos = self.w1_pos and bool(np.all(w1 > 0))
        self.w1_neg = self.w1_neg and bool(np.all(w1 < 0))
        for ap in reported_loads(dyn):
            self._add_load(ap, q, w1)
        if self.has_friction:
            with np.errstate(all="ignore"):
                self.losses.add(q, dyn.friction_power / w1)
            lk = np.asarray(dyn.locked, dtype=bool)
            self.locked += int(lk.sum())
            self.iterations = max(self.iterations, dyn.friction_iterations)
            for start, end in dyn.self_locking_ranges():  # runs continue across chunks
                if self.runs and self.last_locked and start == float(q[0]):
                    self.runs[-1] = (self.runs[-1][0], end)
                else:
                    self.runs.append((start, end))
            self.last_locked = bool(lk[-1])

    def _add_load(self, ap: AppliedLoad, q: np.ndarray, w1: np.ndarray) -> None:
        """A reported load's extremes (first position of a tie), length and work so far."""
        entry = self.loads.setdefault(ap.name, [ap, (None, None), (None, None), None,
                                                _Trapezoid()])
        v = ap.value
        if np.any(np.isfinite(v)):
            i, j = int(np.nanargmin(v)), int(np.nanargmax(v))
            if entry[1][0] is None or v[i] < entry[1][0]:
                entry[1] = (float(v[i]), float(q[i]))
            if entry[2][0] is None or v[j] > entry[2][0]:
                entry[2] = (float(v[j]), float(q[j]))
        if ap.length is not None and np.any(np.isfinite(ap.length)):
            lo, hi = float(np.nanmin(ap.length)), float(np.nanmax(ap.length))
            entry[3] = (lo, hi) if entry[3] is None else (min(entry[3][0], lo),
                                                          max(entry[3][1], hi))
        with np.errstate(all="ignore"):
            entry[4].add(q, ap.power / w1)

    def _order(self) -> float:
        """+1 / -1: the positions in the order the driver passes them, or against it; 0:
        undefined (as :meth:`Dynamics._time_order`)."""
        span = float(self.phi[-1] - self.phi[0]) if self.phi.size >= 2 else 0.0
        return (float(np.sign(self.w1_first * span))
                if span != 0.0 and (self.w1_pos or self.w1_neg) else 0.0)

    def load_records(self) -> list[dict[str, Any]]:
        """:func:`load_summary` of the whole cycle."""
        order = self._order()
        return [_load_record(ap, lo, hi, length,
                             order * float(work.total) if order else None)
                for ap, lo, hi, length, work in self.loads.values()]

    def peaks(self) -> list[dict[str, Any]]:
        """:func:`cycle_peaks` of the whole cycle."""
        return [{"name": name, "value": val, "unit": unit, "phi1": at}
                for name, (val, at, unit, _kind, couple) in self.best.items()
                if val is not None and (couple is None or couple in self.couples)]

    def means(self) -> dict[str, float]:
        first, last, n = float(self.phi[0]), float(self.phi[-1]), self.phi.size
        return {"Q_mean": self.q.mean(first, last, n),
                "power_mean": self.power.mean(first, last, n)}

    def friction(self) -> dict[str, Any] | None:
        """:func:`friction_summary` of the whole cycle."""
        if not self.has_friction:
            return None
        order = self._order()
        joints = tuple(j.name for j in self.mech.joints)
        nan = float("nan")
        wd = order * float(self.q.total) if order else nan
        losses = order * np.asarray(self.losses.total) if order else np.full(len(joints), nan)
        return _friction_record(joints, wd, losses, self.runs, self.locked, self.iterations)


@dataclass(frozen=True)
class PlanarSummary:
    """What :func:`analyze_chunked` keeps of a long cycle: everything of
    :class:`PlanarStudy` but the per-position arrays, which went to the sink chunk by chunk.

    Attributes
    ----------
    doc, mechanism
        The file and its engine model.
    n : int
        Number of positions analysed; ``first``, ``last`` the first and last driver position
        [rad, or m].
    branches : dict
        Branch used for each group key.
    dead_centres, dead_centre_labels, peaks, means, friction, loads
        As in :class:`PlanarStudy` (the same numbers as the whole cycle held at once, to
        round-off in the means, losses and work, which are summed chunk by chunk).
    table_positions, table_kinematics, table_dynamics, table_transmission
        The table, as in :class:`PlanarStudy`.
    chunk : int
        Positions per chunk.
    kinematic_units, dynamic_units : dict
        The unit of every per-position column the sink received, in order (those of
        ``planar_kinematics.csv`` and of ``planar_dynamics.csv``).
    """

    doc: PlanarFile
    mechanism: Mechanism
    n: int
    first: float
    last: float
    branches: dict[str, int]
    dead_centres: list[DeadCentre]
    dead_centre_labels: list[tuple[str, str]]
    peaks: list[dict[str, Any]]
    means: dict[str, Any]
    friction: dict[str, Any] | None
    table_positions: np.ndarray
    table_kinematics: Kinematics
    table_dynamics: Dynamics
    table_transmission: Transmission
    chunk: int
    loads: list[dict[str, Any]] = field(default_factory=list)
    kinematic_units: dict[str, str] = field(default_factory=dict)
    dynamic_units: dict[str, str] = field(default_factory=dict)

    @property
    def crank(self) -> bool:
        """True for a crank driver (angles [rad]), False for a linear one (slides [m])."""
        return isinstance(self.mechanism.driver, Crank)

    @property
    def structure(self) -> Structure:
        """Mobility and Assur groups of the mechanism."""
        return self.mechanism.structure

    def sample(self, n: int = PLOT_POSITIONS) -> tuple[Kinematics, Dynamics]:
        """Kinematics and dynamics at ``n`` positions evenly spaced from the first position
        to the last (fewer if the cycle has fewer): what the plots of a long cycle draw."""
        phi = np.linspace(self.first, self.last, max(2, min(int(n), self.n)))
        return _solve(self.doc, self.mechanism, phi)

    def to_dict(self, files: tuple[str, str] | None = None) -> dict[str, Any]:
        """What ``planar.json`` holds of a long cycle: everything of :meth:`PlanarStudy.to_dict`
        but the per-position arrays (``columns``), which went to the sink; ``n``, ``first``,
        ``last`` and ``chunk`` instead, and with ``files`` (the names of the kinematic and the
        dynamic CSV file) ``columns_in``: each file's columns, in order."""
        return {
            **_summary_dict(self.doc, self.mechanism, self.branches, self.table_dynamics.about,
                            self.dead_centres, self.dead_centre_labels, self.peaks,
                            self.means),
            "n": self.n, "first": self.first, "last": self.last, "chunk": self.chunk,
            "units": {**self.kinematic_units, **self.dynamic_units},
            **({} if files is None else
               {"columns_in": {files[0]: list(self.kinematic_units),
                               files[1]: list(self.dynamic_units)}}),
            **_friction_and_loads(self.friction, self.loads),
        }


def analyze_chunked(doc: PlanarFile, *, positions: ArrayLike | None = None,
                    angles: ArrayLike | None = None, chunk: int = CHUNK_POSITIONS,
                    sink: ColumnSink | None = None,
                    progress: Callable[[int, int], None] | None = None,
                    units: bool = False) -> PlanarSummary:
    """:func:`analyze` of a cycle too long to hold, chunk by chunk, in bounded memory.

    Each chunk of ``chunk`` positions is solved (kinematics, inverse dynamics, transmission
    angles), its per-position columns (:func:`kinematics_columns_of` with the transmission
    angles, :func:`dynamics_columns_of` with ``by_structure=True``: the same columns for every
    chunk) go to ``sink`` (e.g. two :class:`~linkwork.results.CsvRows` of
    ``planar_kinematics.csv`` and ``planar_dynamics.csv``), and what the study reports is
    kept as running statistics: the extremes with their positions (:func:`cycle_peaks`: the
    first position of an extreme, as over the whole cycle), the means (trapezoid integrals
    continued across chunks), the friction losses, work and self-locking runs, the loads'
    extremes, lengths and work (:func:`load_summary`), and the output
    rate of every group (8 bytes per position and group) from which the dead centres are found
    at the end. Memory: that of one chunk plus those rates and the positions themselves; the
    numbers are those of :func:`analyze` (means and losses to round-off).

    Parameters
    ----------
    doc : PlanarFile
        The validated file.
    positions : array_like, optional
        The driver positions [rad, or m] (any number, increasing as the file's are); default
        the file's [analysis] positions.
    angles : array_like, optional
        The table's driver positions (as for :func:`analyze`).
    chunk : int
        Positions per chunk (>= 2).
    sink : callable, optional
        ``sink(kinematic_columns, dynamic_columns)`` per chunk, in order.
    progress : callable, optional
        ``progress(done, n)`` after each chunk.
    units : bool
        The sink receives each column as ``(values, unit)`` (to head a CSV file with the
        first chunk's); default the values alone. The units are also in the summary
        (``kinematic_units``, ``dynamic_units``) either way.

    Returns
    -------
    PlanarSummary
    """
    mech = doc.mechanism()
    if mech.n_drivers > 1:
        raise ParameterError("drivers", mech.n_drivers, "must be 1 for a cycle analysed chunk "
                             "by chunk (several drivers: analyze, which holds the whole path)")
    crank = isinstance(mech.driver, Crank)
    phi = doc.positions() if positions is None else np.asarray(
        require_finite("positions", positions), dtype=float).reshape(-1)
    n = phi.size
    if n < 1:
        raise ParameterError("positions", "[]", "must hold at least one driver position")
    if isinstance(chunk, bool) or int(chunk) != chunk or chunk < 2:
        raise ParameterError("chunk", chunk, "must be an integer >= 2 (positions per chunk)")
    tphi = default_table_positions(doc) if angles is None else np.asarray(angles, float)

    def table() -> tuple[Kinematics, Dynamics]:
        try:
            return _solve(doc, mech, tphi)
        except AssemblyError as exc:
            raise table_positions_error(exc, tphi, not crank) from None

    # given table positions first: where the mechanism does not assemble there (--angles) is
    # refused before the chunks are solved and streamed (minutes for 10^6 positions); the
    # default ones lie in the file's range, which the chunks check with their own error
    given = table() if angles is not None else None
    stats = _ChunkStats(mech, phi)
    for lo in range(0, n, int(chunk)):
        q = phi[lo:lo + int(chunk)]
        # (the driver's speed is the same at every position: the friction law's sign width
        # and a load diagram's band of rest, relative to its largest value, are those of the
        # whole cycle in every chunk)
        try:
            kin, dyn = _solve(doc, mech, q)
        except AssemblyError as exc:
            err = AssemblyError(f"{exc} (the cycle is analysed chunk by chunk: positions "
                                f"{lo + 1}-{lo + q.size} of {n}; later ones not checked)")
            err.ranges, err.driver = exc.ranges, exc.driver
            raise err from None
        trans = transmission_angles(kin)
        stats.add(lo, kin, dyn, trans)
        if sink is not None or lo == 0:
            kc = kinematics_columns_of(kin)
            kc.update({f"mu_{key}": (mu, "rad") for key, (mu, _) in trans.items()})
            dc = dynamics_columns_of(kin, dyn, by_structure=True)
            if lo == 0:
                heads = ({k: u for k, (_, u) in kc.items()}, {k: u for k, (_, u) in dc.items()})
            if sink is not None:
                sink(*((kc, dc) if units else ({k: v for k, (v, _) in kc.items()},
                                              {k: v for k, (v, _) in dc.items()})))
        if progress is not None:
            progress(lo + q.size, n)
    dcs = dead_centres_over(mech, phi, stats.rates, stats.branches)
    tk, td = table() if given is None else given
    return PlanarSummary(
        doc=doc, mechanism=mech, n=n, first=float(phi[0]), last=float(phi[-1]),
        branches=stats.branches, dead_centres=dcs,
        dead_centre_labels=[dead_centre_label(mech, d) for d in dcs], peaks=stats.peaks(),
        means=stats.means(), friction=stats.friction(), table_positions=tphi,
        table_kinematics=tk, table_dynamics=td, table_transmission=transmission_angles(tk),
        chunk=int(chunk), loads=stats.load_records(), kinematic_units=heads[0],
        dynamic_units=heads[1])
