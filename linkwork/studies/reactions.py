"""Spatial joint reactions of a ``planar`` file with redundant constraints (paper 004).

:func:`run` takes a :class:`~linkwork.io.planar.PlanarFile` and its ``[spatial]`` section,
:func:`solve` an engine Mechanism and a :class:`~linkwork.io.planar.SpatialSpec`; both return a
:class:`ReactionsStudy` (the structural count, the reactions over the cycle and at the table
positions, their peaks). :func:`tolerance` adds the Monte-Carlo study of the peaks. The
kinematics of the cycle is solved once and shared by the reactions, the count and the tolerance
study. Nothing is printed.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import AssemblyError, ParameterError
from linkwork.io.planar import PlanarFile, SpatialSpec
from linkwork.planar import Kinematics, Mechanism, kinematics
from linkwork.redundancy import (
    Deviation,
    OutOfPlaneLoad,
    RedundancyCount,
    SpatialGeometry,
    SpatialModel,
    SpatialReactions,
    Tolerance,
    ToleranceStudy,
    body_wrenches,
    count_redundancy,
    deviation_array,
    geometry,
    solve_reactions,
    spatial_model,
    tolerance_study,
)
from linkwork.redundancy.tolerance import CHUNK_SAMPLES
from linkwork.studies.planar import default_table_positions, table_positions_error

__all__ = ["ReactionsStudy", "model_inputs", "run", "solve", "tolerance", "tolerances"]

Loads = Sequence[Any] | Callable[[np.ndarray], Sequence[Any]]


def model_inputs(spec: SpatialSpec) -> dict[str, Any]:
    """The keyword arguments of :func:`~linkwork.redundancy.spatial_reactions` that a
    ``[spatial]`` section gives: joints, default, heights, out_of_plane, deviations."""
    return {
        "joints": spec.joint_kwargs(),
        "default": spec.default_kwargs(),
        "heights": dict(spec.heights),
        "out_of_plane": [OutOfPlaneLoad(o.body, o.fz, o.mx, o.my) for o in spec.out_of_plane],
        "deviations": [Deviation(d.joint, d.body, d.dx, d.dy, d.dz, d.tx, d.ty, d.tz)
                       for d in spec.deviation],
    }


@dataclass(frozen=True)
class ReactionsStudy:
    """Spatial reactions of a mechanism over its cycle and at table positions.

    Attributes
    ----------
    mechanism : Mechanism
    spec : SpatialSpec
        The ``[spatial]`` data used.
    inputs : dict
        :func:`model_inputs` of ``spec``.
    model : SpatialModel
        The spatial joints.
    kinematics : Kinematics
        The cycle's kinematics (positions last).
    geometry : SpatialGeometry
        The cycle's joint geometry.
    wrenches : ndarray
        The body wrenches over the cycle (gravity, inertia, external and out-of-plane loads).
    reactions : SpatialReactions
        Over the cycle.
    table_positions : ndarray
        [rad, or m for a linear driver].
    table : SpatialReactions
        At the table positions.
    count : RedundancyCount
        Somov-Malyshev count, rank, redundant constraints.
    peaks : dict
        :meth:`SpatialReactions.peaks` of the cycle.
    method : str
        ``"force"`` or ``"displacement"``.
    """

    mechanism: Mechanism
    spec: SpatialSpec
    inputs: dict[str, Any]
    model: SpatialModel
    kinematics: Kinematics
    geometry: SpatialGeometry
    wrenches: np.ndarray
    reactions: SpatialReactions
    table_positions: np.ndarray
    table: SpatialReactions
    count: RedundancyCount
    peaks: dict[str, dict[str, float]]
    method: str

    @property
    def linear(self) -> bool:
        """True for a linear driver (positions are slides [m], Q a force [N]); with several
        drivers, for the first (:attr:`linear_drivers`: each one's)."""
        return bool(self.mechanism.drivers[0].kind == "linear")

    @property
    def linear_drivers(self) -> tuple[bool, ...]:
        """Per driver: True for a linear one (its positions slides [m], its Q a force [N])."""
        return tuple(d.kind == "linear" for d in self.mechanism.drivers)

    @property
    def cycle(self) -> np.ndarray:
        """The cycle's driver positions: (n,), or (n_drivers, n) for several drivers (their
        path)."""
        return np.asarray(self.kinematics.phi1)

    def _repr_html_(self) -> str:
        """A notebook's display: the mechanism animated over the cycle, the count of redundant
        constraints and the peak reactions per joint."""
        from linkwork.plot.html import summary_table, view_html

        return view_html(self.kinematics._scene(),
                         summary_table("spatial reactions (paper 004)", self.peaks_dict()))

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """Axial forces, bending moments and the driving torque over the cycle
        (``reactions.plot()``): a :class:`linkwork.plot.Figure`."""
        return self.reactions.plot(axes=axes, **kw)

    def peaks_dict(self) -> dict[str, Any]:
        """The peaks and the count as JSON-able values (``reactions_peaks.json``)."""
        count = self.count
        return {"units": {"f*": "N", "m*": "N*m", "bending": "N*m",
                          "Q": self.reactions.units["Q"]},
                "peaks": self.peaks,
                "redundant_constraints": count.redundant,
                "mobility_somov_malyshev": count.mobility_formula, "mobility": count.mobility}


def _reactions(mech: Mechanism, kin: Kinematics, model: SpatialModel, inputs: dict[str, Any],
               gravity: Any, loads: Sequence[Any], method: str
               ) -> tuple[np.ndarray, SpatialGeometry, SpatialReactions]:
    """As :func:`~linkwork.redundancy.spatial_reactions`, on a kinematics already solved:
    (body wrenches, geometry, reactions)."""
    w = body_wrenches(mech, kin, gravity=gravity, loads=loads, heights=inputs["heights"],
                      out_of_plane=inputs["out_of_plane"])
    geom = geometry(mech, kin, w)  # (gear meshes: on the flank their tooth force presses)
    dev = deviation_array(model, inputs["deviations"], mech.frame.name)
    res = solve_reactions(model, geom, w, dev, method=method, phi1=kin.phi1)
    du = mech.driver_units  # a linear driver: positions are slides [m], the driving force N
    if du["phi1"] != "rad" or du["Q"] != "N*m":
        res._relabel_units(phi1=du["phi1"], Q=du["Q"])
    return w, geom, res


def solve(mech: Mechanism, spec: SpatialSpec, *, angles: ArrayLike,
          cycle: ArrayLike | None = None, gravity: Sequence[float] | None = None,
          loads: Loads = (), method: str = "force") -> ReactionsStudy:
    """Spatial reactions of ``mech`` with the spatial data ``spec``.

    Parameters
    ----------
    mech : Mechanism
    spec : SpatialSpec
    angles : array_like
        Driver positions of the table [rad, or m for a linear driver]; several drivers:
        shape (n_drivers, k), column j where every driver is at table position j.
    cycle : array_like, optional
        Driver positions of the cycle; default ``spec.positions`` (or 360) over one turn of one
        driver (several drivers: their path, shape (n_drivers, n), is required);
        ``spec.positions``, when set, resamples the cycle's range (each driver's).
    gravity : (gx, gy), optional
        Gravity [m/s^2].
    loads : sequence or callable
        External loads of the engine (PointForce, BodyTorque), or a function of the driver
        positions returning them.
    method : {"force", "displacement"}

    Raises
    ------
    ParameterError
        The table positions leave the range where the mechanism assembles (``--angles``);
        several drivers without their path or with table positions of another shape.
    """
    inputs = model_inputs(spec)
    nd = mech.n_drivers
    if cycle is None:
        if nd > 1:
            raise ParameterError("cycle", None, f"must be the path of the {nd} drivers "
                                 f"{[d.joint for d in mech.drivers]}, shape (n_drivers, n): "
                                 "several drivers have no default cycle")
        cyc = np.linspace(0.0, 2 * np.pi, spec.positions or 360, endpoint=False)
    else:
        c = np.asarray(cycle, dtype=float)
        cyc = (np.linspace(c[..., 0], c[..., -1], spec.positions, axis=-1) if spec.positions
               else c)
    tphi = np.asarray(angles, dtype=float)
    for what, arr in (("cycle", cyc), ("angles", tphi)):
        if nd > 1 and (arr.ndim != 2 or arr.shape[0] != nd):
            raise ParameterError(what, f"shape {arr.shape}", f"must have shape ({nd}, n): one "
                                 f"row per driver {[d.joint for d in mech.drivers]}")

    def loads_at(phi: np.ndarray) -> list[Any]:
        return list(loads(phi)) if callable(loads) else list(loads)

    kin = kinematics(mech, cyc)
    model = spatial_model(mech, inputs["joints"], inputs["default"])
    w, geom, res = _reactions(mech, kin, model, inputs, gravity, loads_at(cyc), method)
    try:
        kin_t = kinematics(mech, tphi)
    except AssemblyError as exc:
        if nd > 1:
            raise
        raise table_positions_error(exc, tphi, mech.drivers[0].kind == "linear") from None
    _, _, at = _reactions(mech, kin_t, model, inputs, gravity, loads_at(tphi), method)
    count = count_redundancy(model, geom, position=cyc.shape[-1] // 7)
    return ReactionsStudy(mechanism=mech, spec=spec, inputs=inputs, model=model, kinematics=kin,
                          geometry=geom, wrenches=w, reactions=res, table_positions=tphi,
                          table=at, count=count, peaks=res.peaks(), method=method)


def run(doc: PlanarFile, *, angles: ArrayLike | None = None, method: str = "force"
        ) -> ReactionsStudy:
    """Spatial reactions of a planar file with its ``[spatial]`` section, over the file's
    [analysis] positions (resampled to ``[spatial].positions`` when given), with its gravity
    and external loads; the table at ``angles`` [rad, or m for a linear driver] (default: the
    positions of every command's tables, :func:`~linkwork.studies.planar.default_table_positions`).
    """
    gravity = doc.analysis.gravity
    table = default_table_positions(doc) if angles is None else angles
    return solve(doc.mechanism(), doc.spatial, angles=table, cycle=doc.positions(),
                 gravity=None if gravity is None else tuple(gravity), loads=doc.loads,
                 method=method)


def tolerances(study: ReactionsStudy, n: int) -> list[Tolerance]:
    """The random deviations of the ``[[spatial.tolerance]]`` of the study's spec, and its
    systematic deviations as fixed means (``n``: the samples asked for, named in the error).

    Raises
    ------
    ParameterError
        The spec has no tolerances, or one names no joint of the model or a body not of its
        joint.
    """
    spec, model, mech = study.spec, study.model, study.mechanism
    if not spec.tolerance:
        raise ParameterError("--tolerance-study", n,
                             "needs at least one [[spatial.tolerance]] in the file")
    tols: list[Tolerance] = []
    for tspec in spec.tolerance:
        jt = next((j for j in model.joints if j.name == tspec.joint), None)
        if jt is None:
            raise ParameterError("spatial.tolerance.joint", tspec.joint,
                                 f"no such joint; known: {[j.name for j in model.joints]}")
        body = "ground" if tspec.body == mech.frame.name else tspec.body
        if body not in (jt.body_a, jt.body_b):
            raise ParameterError(f"spatial.tolerance {tspec.joint}.body", tspec.body,
                                 "must be one of the joint's bodies")
        tols.append(Tolerance(tspec.joint, "a" if body == jt.body_a else "b",
                              tspec.component, tspec.limit, tspec.distribution, tspec.mean))
    # systematic deviations of the file are added as fixed means
    fixed = deviation_array(model, study.inputs["deviations"], mech.frame.name)
    for j, jt in enumerate(model.joints):
        for side in (0, 1):
            for c, cname in enumerate(("dx", "dy", "dz", "tx", "ty", "tz")):
                if fixed[j, side, c] != 0.0:
                    tols.append(Tolerance(jt.name, "ab"[side], cname, 0.0, "uniform",
                                          float(fixed[j, side, c])))
    return tols


def tolerance(study: ReactionsStudy, n: int, *, tols: Sequence[Tolerance] | None = None,
              seed: int = 0, scheduler: Any = None, chunk_size: int = CHUNK_SAMPLES,
              progress: Any = None) -> ToleranceStudy:
    """Monte-Carlo study of the peak reactions over the study's cycle under ``tols`` (default
    :func:`tolerances` of the study: the file's tolerances around its systematic deviations).

    ``n`` samples, ``seed``, ``chunk_size``, ``scheduler`` (a dask.distributed address or
    Client) and ``progress`` (a :func:`~linkwork.sweep.rich_progress` bar) as in
    :func:`~linkwork.redundancy.tolerance_study`. Raises ParameterError as :func:`tolerances`.
    """
    tols = tolerances(study, n) if tols is None else tols
    return tolerance_study(study.model, study.geometry, study.wrenches, tols, n, seed=seed,
                           chunk_size=chunk_size, client=scheduler, progress=progress)
