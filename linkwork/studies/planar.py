"""A ``planar`` file over its cycle: kinematics, dynamics, dead centres, extremes, a table.

:func:`analyze` builds the mechanism of a :class:`~linkwork.io.planar.PlanarFile` once (its
structure decomposition is cached with it), solves the file's [analysis] positions and the
table positions, and returns a :class:`PlanarStudy` that carries everything ``linkwork analyze``
prints, writes and plots. Nothing is printed.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.balancing.loads import mean_over_range
from linkwork.checks import require_finite
from linkwork.errors import AssemblyError, ParameterError
from linkwork.io.planar import PlanarFile
from linkwork.planar import (
    Crank,
    DeadCentre,
    Dynamics,
    Kinematics,
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

__all__ = ["CHUNK_POSITIONS", "PlanarStudy", "PlanarSummary", "analyze", "analyze_chunked",
           "cycle_peaks", "dead_centre_label", "default_table_positions", "distinct_paths",
           "friction_summary", "named_columns", "split_columns", "table_positions_error"]

#: Columns of ``planar_dynamics.csv`` besides the reactions ``R_*`` and the friction powers
#: ``Pf_*`` (the rest is kinematics); the last three only with friction.
DYNAMICS_COLUMNS = ("Q", "shaking_fx", "shaking_fy", "shaking_m", "T", "Q_frictionless",
                    "efficiency", "locked")
#: Prefixes of the per-joint columns of ``planar_dynamics.csv``.
DYNAMICS_PREFIXES = ("R_", "Pf_")

Transmission = dict[str, tuple[np.ndarray, np.ndarray]]


def table_positions_error(exc: AssemblyError, positions: np.ndarray, linear: bool
                          ) -> ParameterError:
    """The error for table positions (``--angles``) where the mechanism does not assemble,
    although the file's [analysis] range does."""
    vals = np.asarray(positions, dtype=float) * 1e3 if linear else np.degrees(positions)
    shown = ", ".join(f"{v:g}" for v in vals) + (" mm" if linear else " deg")
    return ParameterError("--angles", shown, f"the table positions leave the range where the "
                          f"mechanism assembles ({exc}); give --angles within the file's "
                          "[analysis] range")


def named_columns(kin: Kinematics, dyn: Dynamics, transmission: Transmission | None = None,
                  *, by_structure: bool = False) -> dict[str, tuple[np.ndarray, str]]:
    """Readable per-position columns: name -> (values, unit). ``transmission``: the result of
    :func:`~linkwork.planar.transmission_angles` of ``kin`` if already computed.
    ``by_structure``: a joint's couple ``R_<j>.mz`` and friction power ``Pf_<j>`` are columns
    wherever the joint can carry them (a prismatic pair's couple, a joint with friction), not
    only where they are not zero throughout these positions (the same columns for every chunk
    of a long cycle, :func:`analyze_chunked`).

    Per moving body: ``<body>.theta/omega/eps`` and its centre of mass ``<body>.xS/yS/vxS/vyS/
    axS/ayS``, then every named point of the body (frame axes, :meth:`Kinematics.point`):
    ``<body>.<point>.x/y`` [m], ``.vx/.vy`` [m/s], ``.ax/.ay`` [m/s^2]; a joint's point named
    on both of its bodies appears under each."""
    mech = kin.mechanism
    units = mech.driver.field_units  # rad, rad/s, rad/s^2, N*m of a crank; m, m/s, m/s^2, N
    cols: dict[str, tuple[np.ndarray, str]] = {
        "phi1": (kin.phi1, units["phi1"]),
        "omega1": (kin.omega1, units["omega1"]),
        "eps1": (kin.eps1, units["eps1"]),
    }
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
    joints = [mech.joint(j) for j in dyn.joints]
    for k, j in enumerate(dyn.joints):
        cols[f"R_{j}.x"] = (dyn.fx[k], "N")
        cols[f"R_{j}.y"] = (dyn.fy[k], "N")
        if (("t" in joints[k].row_kinds or joints[k].has_friction) if by_structure
                else np.any(dyn.mz[k] != 0)):
            cols[f"R_{j}.mz"] = (dyn.mz[k], "N*m")
    cols["Q"] = (dyn.Q, units["Q"])
    cols["shaking_fx"] = (dyn.shaking_fx, "N")
    cols["shaking_fy"] = (dyn.shaking_fy, "N")
    cols["shaking_m"] = (dyn.shaking_m, "N*m")
    cols["T"] = (dyn.T, "J")
    if dyn.has_friction:  # only then: frictionless files keep their columns
        cols["Q_frictionless"] = (dyn.Q_frictionless, units["Q"])
        for k, j in enumerate(dyn.joints):
            if (joints[k].has_friction if by_structure
                    else np.any(dyn.friction_power[k] != 0)):
                cols[f"Pf_{j}"] = (dyn.friction_power[k], "W")
        cols["efficiency"] = (dyn.efficiency, "")
        cols["locked"] = (dyn.locked.astype(float), "1")  # a flag, as "valid [1]"
    trans = transmission_angles(kin) if transmission is None else transmission
    for key, (mu, _) in trans.items():
        cols[f"mu_{key}"] = (mu, "rad")
    return cols


def split_columns(cols: dict[str, tuple[np.ndarray, str]]
                  ) -> tuple[dict[str, tuple[np.ndarray, str]], dict[str, tuple[np.ndarray, str]]]:
    """:func:`named_columns` split into those of ``planar_kinematics.csv`` (poses, velocities,
    accelerations, transmission angles) and of ``planar_dynamics.csv`` (``phi1``, then
    reactions, driving torque, shaking, kinetic energy, friction)."""
    dynamic = {k: v for k, v in cols.items()
               if k.startswith(DYNAMICS_PREFIXES) or k in DYNAMICS_COLUMNS}
    kinematic = {k: v for k, v in cols.items() if k not in dynamic}
    return kinematic, {"phi1": cols["phi1"], **dynamic}


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
        peaks.append({"name": name, "value": float(v[i]), "unit": unit,
                      "phi1": float(kin.phi1[i])})
    return peaks


#: A quantity of :func:`cycle_peaks`: name, values, unit, "max" or "min", and for the couple
#: of a joint the joint's index (kept only where the joint carries a couple), else None.
PeakSeries = tuple[str, np.ndarray, str, str, int | None]


def _peak_series(kin: Kinematics, dyn: Dynamics, trans: Transmission) -> list[PeakSeries]:
    """The quantities of :func:`cycle_peaks`, the couple ``|M j|`` of every joint included."""
    unit_q = kin.mechanism.driver.field_units["Q"]
    series: list[PeakSeries] = [("Q max", dyn.Q, unit_q, "max", None),
                                ("Q min", dyn.Q, unit_q, "min", None)]
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
        ``Q_mean`` (work / range) [N m or N] and ``power_mean`` [W] over the cycle.
    friction : dict or None
        :func:`friction_summary` of the cycle (None: no joint has friction).
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
    means: dict[str, float]
    friction: dict[str, Any] | None = None

    @property
    def crank(self) -> bool:
        """True for a crank driver (angles [rad]), False for a linear one (slides [m])."""
        return isinstance(self.mechanism.driver, Crank)

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
        return split_columns(self.columns())[0]

    def dynamics_columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """The columns of ``planar_dynamics.csv``: reactions, driving torque, shaking, kinetic
        energy (after ``phi1``)."""
        return split_columns(self.columns())[1]

    def to_dict(self) -> dict[str, Any]:
        """Everything of the study as JSON-able values (``planar.json``)."""
        mech, s, kin, dyn = self.mechanism, self.structure, self.kinematics, self.dynamics
        crank = self.crank
        cols = self.columns()
        a_x, a_y = (float(v) for v in dyn.about)
        drv = mech.joint(mech.driver.joint)
        extra = {} if self.friction is None else {"friction": self.friction}
        return {
            "name": self.doc.name, "mobility": s.mobility, "structure": s.formula(),
            "groups": [{"kind": g.kind, "bodies": list(g.bodies), "joints": list(g.joints),
                        "class": g.cls, "order": g.order, "key": g.key,
                        "branch": kin.branches.get(g.key, 1)} for g in s.groups],
            "reaction_sign": "force exerted by joint body a on joint body b, frame axes",
            "torque_sign": (f"Q: {'torque' if crank else 'force along the guide'} on body "
                            f"{drv.b!r} of driver joint {mech.driver.joint!r} through body "
                            f"{drv.a!r}{', counter-clockwise +' if crank else ''}; driving "
                            "power Q*omega1"),
            "shaking_sign": ("force and moment exerted by the moving bodies on the frame "
                             "(motor reaction included), moment counter-clockwise + about "
                             f"({a_x:g}, {a_y:g}) m"),
            "positions_unit": mech.driver.field_units["phi1"],
            "dead_centres": [{"group": d.group, "body": d.body, "phi1": d.phi1, "kind": d.kind,
                              "of": lab[0], "joint": lab[1]}
                             for d, lab in zip(self.dead_centres, self.dead_centre_labels,
                                               strict=True)],
            "peaks": self.peaks,
            "means": {**self.means, "units": {"Q_mean": mech.driver.field_units["Q"],
                                              "power_mean": "W"}},
            "units": {k: u for k, (_, u) in cols.items()},
            "columns": {k: json_array(v) for k, (v, _) in cols.items()},
            **extra,
        }


def _solve(doc: PlanarFile, mech: Mechanism, phi: np.ndarray) -> tuple[Kinematics, Dynamics]:
    kin = kinematics(mech, phi)
    a = doc.analysis
    dyn = inverse_dynamics(kin, gravity=a.gravity, loads=doc.loads(phi), about=a.about)
    return kin, dyn


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


def analyze(doc: PlanarFile, *, angles: ArrayLike | None = None) -> PlanarStudy:
    """Analyse a planar mechanism file over its [analysis] positions and at table positions.

    Parameters
    ----------
    doc : PlanarFile
        The validated file (:func:`linkwork.io.load`).
    angles : array_like, optional
        The table's driver positions [rad, or m for a linear driver]; default
        :func:`default_table_positions`.

    Returns
    -------
    PlanarStudy

    Raises
    ------
    AssemblyError
        The mechanism does not assemble over the file's range.
    ParameterError
        The table positions leave the range where the mechanism assembles (``--angles``).
    """
    mech = doc.mechanism()
    crank = isinstance(mech.driver, Crank)
    phi = doc.positions()
    kin, dyn = _solve(doc, mech, phi)
    dcs = dead_centres(kin)
    tphi = default_table_positions(doc) if angles is None else np.asarray(angles, float)
    try:
        tk, td = _solve(doc, mech, tphi)
    except AssemblyError as exc:
        raise table_positions_error(exc, tphi, not crank) from None
    trans = transmission_angles(kin)
    return PlanarStudy(
        doc=doc, mechanism=mech, kinematics=kin, dynamics=dyn, transmission=trans,
        table_positions=tphi, table_kinematics=tk, table_dynamics=td,
        table_transmission=transmission_angles(tk), dead_centres=dcs,
        dead_centre_labels=[dead_centre_label(mech, d) for d in dcs],
        peaks=cycle_peaks(kin, dyn, trans),
        means={"Q_mean": dyn.Q_mean,
               "power_mean": mean_over_range(kin.phi1, dyn.power)},
        friction=friction_summary(dyn))


# ---------------------------------------------------------------------------------------------
# long cycles: chunk by chunk, in bounded memory

#: Positions per chunk of :func:`analyze_chunked`: a chunk of the four-bar of paper 001 with its
#: columns takes some 4 kB per position (measured: 141 MiB peak resident for 10^6 positions in
#: chunks of 8192, 162 MiB in chunks of 32768, the same time), besides the positions and 8
#: bytes per position and group kept for the dead centres.
CHUNK_POSITIONS = 16_384

#: What receives the per-position columns of one chunk: ``sink(kinematic, dynamic)``, two
#: mappings name -> values as :func:`split_columns` orders them (the same names every chunk).
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
        """:func:`~linkwork.cycles.mean_over_range` of the values fed."""
        if n > 1 and last != first and self.finite:
            return float(self.total / (last - first))
        with np.errstate(all="ignore"):
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
        if self.has_friction:
            w1 = np.broadcast_to(np.asarray(kin.omega1, dtype=float), q.shape)
            if lo == 0:
                self.w1_first = float(w1[0])
            self.w1_pos = self.w1_pos and bool(np.all(w1 > 0))
            self.w1_neg = self.w1_neg and bool(np.all(w1 < 0))
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
        span = float(self.phi[-1] - self.phi[0]) if self.phi.size >= 2 else 0.0
        order = (float(np.sign(self.w1_first * span))
                 if span != 0.0 and (self.w1_pos or self.w1_neg) else 0.0)
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
    dead_centres, dead_centre_labels, peaks, means, friction
        As in :class:`PlanarStudy` (the same numbers as the whole cycle held at once, to
        round-off in the means and losses, which are summed chunk by chunk).
    table_positions, table_kinematics, table_dynamics, table_transmission
        The table, as in :class:`PlanarStudy`.
    chunk : int
        Positions per chunk.
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
    means: dict[str, float]
    friction: dict[str, Any] | None
    table_positions: np.ndarray
    table_kinematics: Kinematics
    table_dynamics: Dynamics
    table_transmission: Transmission
    chunk: int


def analyze_chunked(doc: PlanarFile, *, positions: ArrayLike | None = None,
                    angles: ArrayLike | None = None, chunk: int = CHUNK_POSITIONS,
                    sink: ColumnSink | None = None,
                    progress: Callable[[int, int], None] | None = None) -> PlanarSummary:
    """:func:`analyze` of a cycle too long to hold, chunk by chunk, in bounded memory.

    Each chunk of ``chunk`` positions is solved (kinematics, inverse dynamics, transmission
    angles), its per-position columns (:func:`named_columns`, the same columns for every
    chunk: ``by_structure=True``) go to ``sink`` (e.g. two :class:`~linkwork.results.CsvRows`
    of ``planar_kinematics.csv`` and ``planar_dynamics.csv``), and what the study reports is
    kept as running statistics: the extremes with their positions (:func:`cycle_peaks`: the
    first position of an extreme, as over the whole cycle), the means (trapezoid integrals
    continued across chunks), the friction losses, work and self-locking runs, and the output
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

    Returns
    -------
    PlanarSummary
    """
    mech = doc.mechanism()
    crank = isinstance(mech.driver, Crank)
    phi = doc.positions() if positions is None else np.asarray(
        require_finite("positions", positions), dtype=float).reshape(-1)
    n = phi.size
    if n < 1:
        raise ParameterError("positions", "[]", "must hold at least one driver position")
    if isinstance(chunk, bool) or int(chunk) != chunk or chunk < 2:
        raise ParameterError("chunk", chunk, "must be an integer >= 2 (positions per chunk)")
    a = doc.analysis
    stats = _ChunkStats(mech, phi)
    for lo in range(0, n, int(chunk)):
        q = phi[lo:lo + int(chunk)]
        try:
            kin = kinematics(mech, q)
        except AssemblyError as exc:
            err = AssemblyError(f"{exc} (the cycle is analysed chunk by chunk: positions "
                                f"{lo + 1}-{lo + q.size} of {n}; later ones not checked)")
            err.ranges, err.driver = exc.ranges, exc.driver
            raise err from None
        # (the driver's speed is the same at every position: the friction law's sign width,
        # relative to its largest value, is that of the whole cycle in every chunk)
        dyn = inverse_dynamics(kin, gravity=a.gravity, loads=doc.loads(q), about=a.about)
        trans = transmission_angles(kin)
        stats.add(lo, kin, dyn, trans)
        if sink is not None:
            kc, dc = split_columns(named_columns(kin, dyn, trans, by_structure=True))
            sink({k: v for k, (v, _) in kc.items()}, {k: v for k, (v, _) in dc.items()})
        if progress is not None:
            progress(lo + q.size, n)
    dcs = dead_centres_over(mech, phi, stats.rates, stats.branches)
    tphi = default_table_positions(doc) if angles is None else np.asarray(angles, float)
    try:
        tk, td = _solve(doc, mech, tphi)
    except AssemblyError as exc:
        raise table_positions_error(exc, tphi, not crank) from None
    return PlanarSummary(
        doc=doc, mechanism=mech, n=n, first=float(phi[0]), last=float(phi[-1]),
        branches=stats.branches, dead_centres=dcs,
        dead_centre_labels=[dead_centre_label(mech, d) for d in dcs], peaks=stats.peaks(),
        means=stats.means(), friction=stats.friction(), table_positions=tphi,
        table_kinematics=tk, table_dynamics=td, table_transmission=transmission_angles(tk),
        chunk=int(chunk))
