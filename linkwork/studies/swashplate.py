"""The swash-plate drive of paper 003: a ``swashplate`` file analysed, or designs synthesised.

:func:`analyze` takes a :class:`~linkwork.io.swashplate.SwashplateFile` and returns a
:class:`SwashplateStudy` (table, characteristics and the checks against the file's limits, the
cycle, the drive forces under the file's load); :func:`synthesize` takes a
:class:`~linkwork.synthesis.swashplate.Request` and returns a :class:`SwashplateSynthesis`
(ranked designs and the feasible region around the best). Nothing is printed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.io.swashplate import SwashplateFile
from linkwork.models import swashplate as sw
from linkwork.synthesis import swashplate as syn

__all__ = ["DEFAULT_ANGLES", "SwashplateStudy", "SwashplateSynthesis", "analyze", "synthesize"]

#: Rotor angles of the table when none are given [rad]: every 30 deg.
DEFAULT_ANGLES = np.radians(np.arange(0.0, 360.0, 30.0))


@dataclass(frozen=True)
class SwashplateStudy:
    """A swash-plate drive of a file.

    Attributes
    ----------
    doc : SwashplateFile
    design : Design
        The drive (scheme constructor of the file's geometry).
    omega : float
        Rotor speed [rad/s] (0: not given; then no slide speeds).
    angles : ndarray
        The table's rotor angles [rad].
    table : KinematicsResult
        At ``angles``.
    cycle : KinematicsResult
        Over a revolution (``[output].samples`` positions).
    harmonic_error : dict
        ``max`` and ``rms`` error of the harmonic form, Eq. (6) [m].
    forces : DriveForces or None
        Kinetostatics under the file's ``[load]`` (None without one).
    summary : dict
        The scalar characteristics, the checks against the file's limits and the drive's peaks
        (``characteristics.json`` without the design).
    """

    doc: SwashplateFile
    design: sw.Design
    omega: float
    angles: np.ndarray
    table: sw.KinematicsResult
    cycle: sw.KinematicsResult
    harmonic_error: dict[str, float]
    forces: sw.DriveForces | None
    summary: dict[str, Any]

    @property
    def characteristics(self) -> sw.Characteristics:
        """Stroke, extremes, stroke angles, pressure angles, axial size (paper 003, 1-5)."""
        return self.table.characteristics

    @property
    def v_max(self) -> float:
        """Largest slide speed [m/s] (0 without a rotor speed)."""
        return self.omega * float(self.characteristics.Pi_v_max)

    def to_dict(self) -> dict[str, Any]:
        """``characteristics.json``: the design and :attr:`summary`."""
        return {"design": self.design.as_dict(), **self.summary}

    def _repr_html_(self) -> str:
        """A notebook's display: the drive animated in two views, and its characteristics."""
        from linkwork.plot.html import summary_table, view_html

        return view_html(self.scene(), summary_table("characteristics", self.to_dict()))

    def scene(self) -> Any:
        """The drive drawn in two views over the cycle
        (:func:`linkwork.plot.scene.swashplate_scene`)."""
        from linkwork.plot.scene import swashplate_scene

        A, B = sw.points(self.cycle.phi, *self.design.params)
        return swashplate_scene(self.cycle, A, B, title=self.doc.name or "swash-plate drive")

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """Position, pressure angle and transfer function over the rotor angle
        (``cycle.plot()``): a :class:`linkwork.plot.Figure`."""
        return self.cycle.plot(axes=axes, **kw)


def analyze(doc: SwashplateFile, *, angles: ArrayLike | None = None) -> SwashplateStudy:
    """Analyse a validated ``swashplate`` file.

    Parameters
    ----------
    doc : SwashplateFile
    angles : array_like, optional
        Rotor angles of the table [rad]; default :data:`DEFAULT_ANGLES`.
    """
    phi_t = DEFAULT_ANGLES if angles is None else np.asarray(angles, dtype=float)
    d = doc.design()
    op = doc.operation
    omega = op.omega
    table = sw.analyze(d, phi_t, omega=omega)
    c = table.characteristics
    summary: dict[str, Any] = dict(c.scalars())
    err = sw.harmonic_error(*d.params)
    summary["harmonic_error_max"] = float(err["max"])
    summary["harmonic_error_rms"] = float(err["rms"])
    if omega > 0:
        v_max = omega * float(c.Pi_v_max)
        summary["omega"] = omega
        summary["v_max"] = v_max
        if op.v_allow is not None:
            summary["v_allow_met"] = v_max <= op.v_allow
    if op.delta_allow is not None:
        summary["delta_allow_met"] = max(float(c.delta_f), float(c.delta_r)) <= op.delta_allow
    cycle = sw.analyze(d, np.linspace(0.0, 2 * math.pi, doc.output.samples), omega=omega)
    f = doc.drive_forces(c)
    if f is not None:
        summary.update({"efficiency": f.efficiency,
                        "peak_torque_total": float(np.max(np.abs(f.M_total))),
                        "peak_rod_force": float(np.max(np.abs(f.S)))})
    return SwashplateStudy(doc=doc, design=d, omega=omega, angles=phi_t, table=table,
                           cycle=cycle, harmonic_error={k: float(v) for k, v in err.items()},
                           forces=f, summary=summary)


@dataclass(frozen=True)
class SwashplateSynthesis:
    """Designs of a scheme meeting a request, ranked, and the feasible region around the best.

    Attributes
    ----------
    request : Request
    result : SynthesisResult
        The ranked designs (``result.table``), counts of screened and feasible candidates.
    region_names : (str, str)
        The two free parameters of the feasible-region map.
    region : FeasibleRegion
        The map over them around the best design.
    """

    request: syn.Request
    result: syn.SynthesisResult
    region_names: tuple[str, str]
    region: syn.FeasibleRegion


def synthesize(req: syn.Request, *, region: tuple[str, str] | None = None,
               n_candidates: int = 16384, n_best: int = 5, n_refine: int = 4, seed: int = 0,
               client: Any = None, progress: Any = None, region_n: int = 60
               ) -> SwashplateSynthesis:
    """Synthesise designs for ``req`` (:func:`linkwork.synthesis.swashplate.synthesize`) and
    map the feasible region of two free parameters (default the first two) around the best.

    ``progress``: a :func:`~linkwork.sweep.rich_progress` bar for the screening (optional).
    """
    names = tuple(list(req.free)[:2]) if region is None else region
    kw: dict[str, Any] = {} if progress is None else {"progress": progress}
    res = syn.synthesize(req, n_candidates=n_candidates, n_best=n_best, n_refine=n_refine,
                         seed=seed, client=client, **kw)
    reg = syn.feasible_region(req, res.best, names[0], names[1], n=region_n)
    return SwashplateSynthesis(request=req, result=res, region_names=(names[0], names[1]),
                               region=reg)
