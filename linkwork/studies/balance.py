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
from linkwork.balancing.mechanism import (
    ForceBalance,
    ShakingLoads,
    centre_of_mass_balance,
    frame_hinged_links,
    path_rms,
    shaking_loads,
)
from linkwork.balancing.optimal import ParetoSet, pareto_set
from linkwork.cycles import peak
from linkwork.errors import AssemblyError, ParameterError
from linkwork.io.planar import (
    MAX_WHOLE_POSITIONS,
    BalanceSection,
    PlanarFile,
    whole_cycle_limit,
)
from linkwork.planar import Dynamics, Mechanism, inverse_dynamics, kinematics
from linkwork.studies.planar import default_table_positions

__all__ = ["BalanceStudy", "PathBalanceStudy", "check", "compare", "run", "run_path"]

#: what paper 001's comparison computes that several drivers leave undefined, and why
NOT_WITH_SEVERAL = ("paper 001's table (the shaking moment about the crank axis at the table "
                    "angles), its moved crank-counterweight axis (dM2, dM3, R2, R3), the "
                    "harmonics and the Pareto set: they need one crank turning through whole "
                    "cycles, and these drivers run along a path")

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


@dataclass(frozen=True)
class PathBalanceStudy:
    """Force balance of a mechanism of several drivers along their path: what is defined
    without a crank cycle.

    Attributes
    ----------
    mechanism : Mechanism
        The unbalanced mechanism.
    section : BalanceSection
        The options used (links, radii).
    balance : ForceBalance
        :func:`~linkwork.balancing.mechanism.centre_of_mass_balance` over the path: the
        counterweights on the frame-hinged links, the balanced mechanism.
    before, after : ShakingLoads
        Shaking force and moment (inertia forces, about ``[analysis] about``) along the path,
        unbalanced and balanced, at the drivers' speeds.
    dynamics_before, dynamics_after : Dynamics
        Inverse dynamics along the path with the file's gravity and loads (each driver's Q,
        the frame joints' reactions).
    table_positions : ndarray (n_drivers, k)
        The 12 positions along the path of every command's tables.
    table_before, table_after : ShakingLoads
        The shaking loads there; ``table_Q0``, ``table_Q1`` the driving loads (n_drivers, k).
    not_computed : str
        What paper 001's comparison computes that is not defined here, and why.
    """

    mechanism: Mechanism
    section: BalanceSection
    balance: ForceBalance
    before: ShakingLoads
    after: ShakingLoads
    dynamics_before: Dynamics
    dynamics_after: Dynamics
    table_positions: np.ndarray
    table_before: ShakingLoads
    table_after: ShakingLoads
    table_Q0: np.ndarray
    table_Q1: np.ndarray
    not_computed: str = NOT_WITH_SEVERAL

    def frame_joints(self) -> list[str]:
        """The joints of the frame (their reactions are the bearing loads)."""
        fr = self.mechanism.frame.name
        return [j.name for j in self.mechanism.joints if fr in (j.a, j.b)]

    def summary(self) -> dict[str, dict[str, float]]:
        """Peaks and RMS along the path: quantity -> {"unbalanced": v, "balanced": v}."""
        b, a = self.before, self.after
        d0, d1 = self.dynamics_before, self.dynamics_after
        out = {"shaking force peak [N]": {"unbalanced": peak(b.force), "balanced": peak(a.force)},
               "shaking force RMS [N]": {"unbalanced": path_rms(b.force),
                                         "balanced": path_rms(a.force)},
               "shaking moment peak [N*m]": {"unbalanced": peak(b.moment),
                                             "balanced": peak(a.moment)},
               "shaking moment RMS [N*m]": {"unbalanced": path_rms(b.moment),
                                            "balanced": path_rms(a.moment)}}
        for k, d in enumerate(self.mechanism.drivers):
            unit = d.field_units["Q"]
            out[f"Q {d.joint} peak [{unit}]"] = {"unbalanced": peak(d0.Q[k]),
                                                 "balanced": peak(d1.Q[k])}
            out[f"Q {d.joint} RMS [{unit}]"] = {"unbalanced": path_rms(d0.Q[k]),
                                                "balanced": path_rms(d1.Q[k])}
        for name in self.frame_joints():
            out[f"frame joint {name} peak [N]"] = {
                "unbalanced": peak(d0.reaction_magnitude(name)),
                "balanced": peak(d1.reaction_magnitude(name))}
        return out

    def to_dict(self) -> dict[str, Any]:
        """The scalar results as JSON-able values (``balance_summary.json``)."""
        fb = self.balance
        return {"summary": self.summary(), "drivers": [d.joint for d in self.mechanism.drivers],
                "counterweights": [
                    {"link": w.link, "static_moment": w.static_moment, "angle": w.angle,
                     "radius": w.radius, "mass": w.mass()} for w in fb.counterweights],
                "full_force_balance": fb.full, "reason": fb.reason,
                "criterion": "centre of mass of the moving links kept still along the path "
                             "(least squares)",
                "not_computed": self.not_computed}

    def columns(self) -> dict[str, tuple[np.ndarray, str]]:
        """Per-position columns along the path (``balance_path.csv``): each driver's position,
        the shaking force and moment and each driver's load, unbalanced (0) and balanced (1)."""
        kin = self.dynamics_before.kinematics
        cols: dict[str, tuple[np.ndarray, str]] = {}
        for k, d in enumerate(self.mechanism.drivers):
            cols[f"phi1.{d.joint}"] = (kin.phi1[k], d.field_units["phi1"])
        for tag, sl in (("0", self.before), ("1", self.after)):
            cols[f"Fx{tag}"] = (sl.fx, "N")
            cols[f"Fy{tag}"] = (sl.fy, "N")
            cols[f"M{tag}"] = (sl.moment, "N*m")
        for tag, dyn in (("0", self.dynamics_before), ("1", self.dynamics_after)):
            for k, d in enumerate(self.mechanism.drivers):
                cols[f"Q{tag}.{d.joint}"] = (dyn.Q[k], d.field_units["Q"])
        return cols

    def plot(self, axes: Any = None, **kw: Any) -> Any:
        """Shaking force and moment and the driving loads along the path, before and after:
        a :class:`linkwork.plot.Figure`."""
        from linkwork.plot.balancing import path_balance_figure

        return path_balance_figure(self, axes=axes, **kw)


def run_path(doc: PlanarFile) -> PathBalanceStudy:
    """Force balance of a file of several drivers along their path (each ``[[driver]]`` from
    its start to its stop), with its ``[balance]`` links and radii, its gravity and loads.

    Raises
    ------
    ParameterError
        ``[balance] angles`` or ``n`` given (a crank cycle's), no frame-hinged link, or a
        counterweighted link that does not turn along the path.
    """
    mech, section = doc.mechanism(), doc.balance
    for key in ("angles", "n"):
        if key in section.model_fields_set:
            raise ParameterError(f"balance.{key}", getattr(section, key),
                                 "is a crank cycle's; several drivers are balanced along "
                                 "their path ([analysis] n positions, tables at 12 of them)")
    if doc.analysis.n > MAX_WHOLE_POSITIONS:
        raise ParameterError("analysis.n", doc.analysis.n,
                             whole_cycle_limit(doc.analysis.n, "run_path()"))
    phi = doc.positions()
    about = doc.analysis.about
    kin = kinematics(mech, phi)
    fb = centre_of_mass_balance(kin, section.links, section.radii)
    kb = kinematics(fb.mechanism, phi)
    g = doc.analysis.gravity

    def dyn(k: Any, at: np.ndarray) -> Dynamics:
        return inverse_dynamics(k, gravity=g, loads=doc.loads(at), about=about)

    tphi = default_table_positions(doc)
    kt0, kt1 = kinematics(mech, tphi), kinematics(fb.mechanism, tphi)
    return PathBalanceStudy(
        mechanism=mech, section=section, balance=fb, before=shaking_loads(kin, about),
        after=shaking_loads(kb, about), dynamics_before=dyn(kin, phi),
        dynamics_after=dyn(kb, phi), table_positions=tphi,
        table_before=shaking_loads(kt0, about), table_after=shaking_loads(kt1, about),
        table_Q0=dyn(kt0, tphi).Q, table_Q1=dyn(kt1, tphi).Q)


def check(doc: PlanarFile) -> None:
    """Refuse, before any work, a file that the balancing cannot take: one driver must be a
    crank turning about a frame joint (paper 001); several drivers need a link hinged to the
    frame to carry a counterweight (ParameterError naming ``driver``)."""
    drivers = doc.drivers
    if len(drivers) > 1:
        if not frame_hinged_links(doc.mechanism()):
            raise ParameterError("driver", f"{len(drivers)} drivers ("
                                 f"{', '.join(d.joint for d in drivers)})",
                                 "force balancing needs a link hinged to the frame to carry a "
                                 "counterweight; this mechanism has none")
        return
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
