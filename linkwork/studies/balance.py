"""Paper 001's balancing comparison of a ``planar`` file (what ``linkwork balance`` shows).

:func:`run` takes a :class:`~linkwork.io.planar.PlanarFile` and its ``[balance]`` section,
:func:`compare` an engine Mechanism and a :class:`~linkwork.io.planar.BalanceSection`; both
return a :class:`BalanceStudy` (the comparison, its harmonics, what balancing raises and, if
asked, the Pareto set of counterweights). Nothing is printed.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from linkwork.balancing import compare_balancing, crank_axis, rms
from linkwork.balancing.comparison import BalancingComparison
from linkwork.balancing.loads import Harmonics
from linkwork.balancing.optimal import ParetoSet, pareto_set
from linkwork.errors import AssemblyError, ParameterError
from linkwork.io.planar import BalanceSection, PlanarFile
from linkwork.planar import Mechanism

__all__ = ["BalanceStudy", "check", "compare", "run"]

#: Harmonics listed in the table and in ``balance_summary.json``.
HARMONICS = 4


@dataclass(frozen=True)
class BalanceStudy:
    """The balancing comparison of a mechanism.

    Attributes
    ----------
    mechanism : Mechanism
        The unbalanced mechanism.
    section : BalanceSection
        The options used (links, radii, table angles [deg], n).
    comparison : BalancingComparison
        The paper's table and the cycle before and after balancing.
    harmonics : dict of Harmonics
        The first :data:`HARMONICS` harmonics of every quantity of the cycle.
    increases : list of str
        What balancing raises (peak or RMS), worded for the reader.
    pareto : ParetoSet or None
        Optimal counterweights (when asked).
    """

    mechanism: Mechanism
    section: BalanceSection
    comparison: BalancingComparison
    harmonics: dict[str, Harmonics]
    increases: list[str]
    pareto: ParetoSet | None = None

    def _repr_html_(self) -> str:
        """A notebook's display: R2, R3, the counterweights and the peaks and RMS before and
        after balancing."""
        from linkwork.plot.html import summary_table, view_html

        comp = self.comparison
        data = {"R2 [%]": comp.R2, "R3 [%]": comp.R3,
                "counterweights": {w.link: {"S [kg*m]": w.static_moment,
                                            "angle [deg]": float(np.degrees(w.angle))}
                                   for w in comp.counterweights},
                **comp.summary()}
        return view_html(None, summary_table("balancing (paper 001)", data))

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """Shaking moments, force hodographs and driving torques before and after balancing
        over the cycle (``comparison.cycle.plot()``): a :class:`linkwork.plot.Figure`."""
        return self.comparison.cycle.plot(axes=axes, **kw)

    def summary(self) -> dict[str, Any]:
        """The scalar results as JSON-able values (``balance_summary.json``)."""
        comp, fb = self.comparison, self.comparison.balance
        return {"summary": comp.summary(), "increases": self.increases,
                "R2": comp.R2, "R3": comp.R3,
                "axis_first_harmonic": [comp.x2, comp.y2],
                "axis_least_squares": [comp.x3, comp.y3],
                "counterweights": [
                    {"link": w.link, "static_moment": w.static_moment,
                     "angle": w.angle, "radius": w.radius, "mass": w.mass()}
                    for w in comp.counterweights],
                "full_force_balance": fb.full, "reason": fb.reason,
                "harmonics": {n: {"mean": hv.mean, "amplitude": hv.amplitude.tolist(),
                                  "phase": hv.phase.tolist()}
                              for n, hv in self.harmonics.items()}}

    def pareto_points(self) -> dict[str, tuple[float, float]]:
        """Reference designs of the Pareto plot: (RMS shaking force [N], RMS shaking moment
        [N m]) of the unbalanced, the statically balanced and paper 001's design."""
        if self.pareto is None:
            return {}
        c = self.comparison.cycle
        return {"unbalanced": self.pareto.unbalanced[:2], "static": self.pareto.static[:2],
                "paper 001 (moved axis)": (rms(c.phi1, c.F1), rms(c.phi1, c.dM3))}

    def pareto_dict(self) -> dict[str, Any]:
        """The Pareto set as JSON-able values (``balance_pareto.json``); empty without one."""
        p = self.pareto
        if p is None:
            return {}
        return {"weights": p.weights.tolist(), "force_rms": p.force_rms.tolist(),
                "moment_rms": p.moment_rms.tolist(), "torque_fluct": p.torque_fluct.tolist(),
                "dominated": p.dominated.tolist(), "unbalanced": list(p.unbalanced),
                "static": list(p.static)}


def compare(mech: Mechanism, section: BalanceSection, *, pareto: bool = False,
            gravity: Sequence[float] | None = None,
            loads: Callable[[np.ndarray], Any] | None = None) -> BalanceStudy:
    """Paper 001's comparison on ``mech`` with the options of ``section``.

    ``gravity`` (gx, gy) [m/s²] and ``loads`` (callable phi1 -> external loads) enter the
    driving torque and bearing reactions only. ``pareto``: also the Pareto set of optimal
    counterweights (over at most 180 positions).
    """
    angles = None if section.angles is None else np.radians(np.asarray(section.angles, float))
    comp = compare_balancing(mech, angles, links=section.links, radii=section.radii,
                             n=section.n, gravity=gravity, loads=loads)
    harm = comp.harmonics(HARMONICS)
    inc = comp.increases()
    p = (pareto_set(mech, links=section.links, static_radii=section.radii,
                    n=min(section.n, 180)) if pareto else None)
    return BalanceStudy(mechanism=mech, section=section, comparison=comp, harmonics=harm,
                        increases=inc, pareto=p)


def check(doc: PlanarFile) -> None:
    """Refuse, before any work, a file that paper 001's balancing cannot take: its driver must
    be a crank turning about a frame joint (ParameterError naming ``driver``)."""
    drivers = doc.drivers
    if len(drivers) > 1:
        raise ParameterError("driver", f"{len(drivers)} drivers ("
                             f"{', '.join(d.joint for d in drivers)})",
                             "balancing (paper 001) needs one crank turning about a frame joint")
    try:
        crank_axis(doc.mechanism())
    except ParameterError as exc:
        raise ParameterError("driver", f"{drivers[0].type} driver on joint {exc.value}",
                             "balancing (paper 001) needs a crank turning about a frame joint"
                             ) from None


def run(doc: PlanarFile, *, angles: Sequence[float] | None = None, pareto: bool = False
        ) -> BalanceStudy:
    """Balance the mechanism of a planar file with its ``[balance]`` section.

    Parameters
    ----------
    doc : PlanarFile
        The validated file; its gravity and external loads enter the driving torque and the
        bearing reactions (not the shaking-moment table).
    angles : sequence of float, optional
        Table crank angles [deg], instead of ``[balance].angles``.
    pareto : bool
        Also optimise the counterweights (Pareto set).

    Raises
    ------
    AssemblyError
        The mechanism does not assemble over a full turn of the crank.
    """
    section = doc.balance
    if angles is not None:
        section = section.model_copy(update={"angles": list(angles)})
    try:
        return compare(doc.mechanism(), section, pareto=pareto, gravity=doc.analysis.gravity,
                       loads=doc.loads if doc.load else None)
    except AssemblyError as exc:
        raise AssemblyError(f"balancing works on a full turn of the crank (the file's "
                            f"[analysis] range is not used): {exc}") from None
