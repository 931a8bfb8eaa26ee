"""A ``sine_press`` file (paper 000): both modes at table angles, over a revolution, the
characteristics and the duty schedule (what ``linkwork analyze`` shows of a press file).

:func:`analyze` returns a :class:`SinePressStudy`; nothing is printed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.io.sine_press import SinePressFile
from linkwork.models import crank_slider, sine
from linkwork.models.crank_slider import CrankSliderResult
from linkwork.models.sine import ForceRatioCurve, InclinedSlotResult, force_ratio_curve
from linkwork.models.variable_structure import ScheduleResult, VariableStructureMechanism

__all__ = ["DEFAULT_ANGLES", "SinePressStudy", "analyze"]

#: Crank angles of the table when none are given [rad]: every 30 deg.
DEFAULT_ANGLES = np.radians(np.arange(0.0, 360.0, 30.0))


@dataclass(frozen=True)
class SinePressStudy:
    """Paper 000's press drive of a file.

    Attributes
    ----------
    doc : SinePressFile
    mechanism : VariableStructureMechanism
    angles : ndarray
        The table's crank angles [rad].
    table_idle, table_working : results
        The offset crank-slider (idle mode) and the inclined-slot sine mechanism (working mode)
        at ``angles``.
    idle_cycle, working_cycle : results
        Both over one revolution (``[output].samples_per_revolution`` + 1 positions).
    schedule : ScheduleResult or None
        The duty schedule over time (None without a ``[[schedule]]``).
    force_ratio : ForceRatioCurve
        The worst-case force ratio over slot angles with the working range (where the drive
        jams by friction), for the file's friction coefficients.
    summary : dict
        The scalar characteristics (``summary.json``): ``idle``, ``working`` and, with a
        schedule, ``schedule`` (duration, switches).
    """

    doc: SinePressFile
    mechanism: VariableStructureMechanism
    angles: np.ndarray
    table_idle: CrankSliderResult
    table_working: InclinedSlotResult
    idle_cycle: CrankSliderResult
    working_cycle: InclinedSlotResult
    schedule: ScheduleResult | None
    summary: dict[str, Any]
    force_ratio: ForceRatioCurve

    def scene(self) -> Any:
        """Both modes drawn side by side over a revolution
        (:func:`linkwork.plot.scene.sine_press_scene`)."""
        from linkwork.plot.scene import sine_press_scene

        return sine_press_scene(self.idle_cycle, self.working_cycle,
                                title=self.doc.name or "press drive",
                                speed=float(self.doc.crank.speed))

    def _repr_html_(self) -> str:
        """A notebook's display: both modes animated side by side, and the characteristics."""
        from linkwork.plot.html import summary_table, view_html

        return view_html(self.scene(), summary_table("characteristics", self.summary))

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """Both modes drawn at the first crank angle: a :class:`linkwork.plot.Figure`
        (``idle_cycle.plot()``, ``working_cycle.plot()`` draw the outputs' motion)."""
        from linkwork.plot.scene import mechanism_figure

        return mechanism_figure(self.scene(), ax=axes, **kw)


def _characteristics(doc: SinePressFile) -> dict[str, Any]:
    L1, idle, work = doc.crank.L1, doc.idle, doc.working
    top, bottom = crank_slider.dead_centres(idle.lambda2, idle.lambda_e, idle.branch)
    x_min, x_max = sine.extreme_positions(work.alpha)
    lo, hi = sine.working_range(work.f_slot, work.f_guide)
    si: dict[str, Any] = {
        "L2_m": idle.lambda2 * L1, "e_m": idle.lambda_e * L1, "branch": idle.branch,
        "stroke_m": float(crank_slider.stroke(L1, idle.lambda2, idle.lambda_e)),
        "phi1_top_dead_centre_deg": float(np.degrees(top)),
        "phi1_bottom_dead_centre_deg": float(np.degrees(bottom)),
        "max_pressure_angle_deg": float(np.degrees(
            crank_slider.max_pressure_angle(idle.lambda2, idle.lambda_e))),
    }
    sw: dict[str, Any] = {
        "alpha_deg": float(np.degrees(work.alpha)),
        "stroke_m": float(sine.stroke(L1, work.alpha)),
        "phi1_X3_min_deg": float(np.degrees(x_min)),
        "phi1_X3_max_deg": float(np.degrees(x_max)),
        "working_range_deg": [float(np.degrees(lo)), float(np.degrees(hi))],
        "worst_case_force_ratio": float(sine.force_ratio(work.alpha, work.f_slot,
                                                         work.f_guide)),
    }
    return {"name": doc.name, "L1_m": L1, "omega1_rad_s": doc.crank.speed,
            "eps1_rad_s2": doc.crank.eps1, "idle": si, "working": sw}


def analyze(doc: SinePressFile, *, angles: ArrayLike | None = None) -> SinePressStudy:
    """Analyse a validated ``sine_press`` file.

    Parameters
    ----------
    doc : SinePressFile
    angles : array_like, optional
        Crank angles of the table [rad]; default :data:`DEFAULT_ANGLES`.
    """
    phi_t = DEFAULT_ANGLES if angles is None else np.asarray(angles, dtype=float)
    L1, w1, e1 = doc.crank.L1, doc.crank.speed, doc.crank.eps1
    idle, work = doc.idle, doc.working
    mech = VariableStructureMechanism(L1=L1, lambda2=idle.lambda2, lambda_e=idle.lambda_e,
                                      alpha=work.alpha, branch=idle.branch, f_slot=work.f_slot,
                                      f_guide=work.f_guide)
    n = doc.output.samples_per_revolution
    phi = np.linspace(0.0, 2 * np.pi, n + 1)
    summary = _characteristics(doc)
    sched = mech.run(doc.segments(), w1, samples_per_revolution=n) if doc.schedule else None
    if sched is not None:
        summary["schedule"] = {"duration_s": float(sched.t[-1]),
                               "switches": sched.to_dict()["switches"]}
    return SinePressStudy(
        doc=doc, mechanism=mech, angles=phi_t,
        force_ratio=force_ratio_curve(work.f_slot, work.f_guide),
        table_idle=crank_slider.offset_crank_slider(phi_t, L1, idle.lambda2, idle.lambda_e,
                                                    w1, e1, idle.branch),
        table_working=sine.inclined_slot(phi_t, L1, work.alpha, w1, e1),
        idle_cycle=crank_slider.offset_crank_slider(phi, L1, idle.lambda2, idle.lambda_e, w1,
                                                    e1, idle.branch),
        working_cycle=sine.inclined_slot(phi, L1, work.alpha, w1, e1),
        schedule=sched, summary=summary)

