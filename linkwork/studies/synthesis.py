"""What a ``synthesis`` task file asks for: path, function or motion generation.

:func:`run` dispatches on the task kind and returns a frozen :class:`SynthesisStudy` holding the
task and its result (:class:`~linkwork.synthesis.design.SynthesisResult`,
:class:`~linkwork.synthesis.function.FunctionResult` or
:class:`~linkwork.synthesis.motion.MotionResult`); the command renders it, a report can too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from linkwork.errors import ParameterError
from linkwork.io.synthesis import SynthesisFile
from linkwork.planar import Kinematics, kinematics
from linkwork.plot.numbers import fmt
from linkwork.synthesis import function as fn
from linkwork.synthesis import motion as mo
from linkwork.synthesis import path as pa
from linkwork.synthesis import sixbar

__all__ = ["KINDS", "SynthesisStudy", "design_summary", "design_table", "run"]

#: Task kinds, as the subcommands of ``linkwork synthesize`` name them.
KINDS = ("function", "motion", "path")


@dataclass(frozen=True)
class SynthesisStudy:
    """A synthesis task and its result.

    Attributes
    ----------
    doc : SynthesisFile
    kind : {"function", "motion", "path"}
    result : SynthesisResult, SixbarResult, FunctionResult or MotionResult
        Designs best first, each with ``.mechanism()`` and ``.to_toml(path)``.
    """

    doc: SynthesisFile
    kind: Literal["function", "motion", "path"]
    result: Any

    @property
    def designs(self) -> tuple[Any, ...]:
        return tuple(self.result.designs)

    @property
    def traced_body(self) -> str:
        """The engine body that carries the traced point ``P`` of a path generator: the
        four-bar's ``coupler``, a six-bar's ``link5``."""
        return "coupler" if _fourbar(self) else "link5"

    def crank_angles(self, i: int, n: int = 361) -> np.ndarray:
        """The driver positions [rad] (the engine's ``phi1``) over which design ``i`` runs:
        a four-bar path or motion generator over its crank's range from the first target (a
        full turn when the crank rotates), a function generator over its input range.

        Raises
        ------
        ParameterError
            ``i`` is not the index of a design.
        """
        if not (isinstance(i, int) and 0 <= i < len(self.designs)):
            raise ParameterError("i", i, f"must be a design's index, 0 to "
                                 f"{len(self.designs) - 1}")
        d = self.designs[i]
        if self.kind == "function":
            return np.linspace(float(d.input[0]), float(d.input[-1]), n)
        fb = d.fourbar if self.kind == "motion" else d
        return fb.run_range(n) + float(fb.params["theta0"])

    def motion(self, i: int, n: int = 361) -> Kinematics:
        """The engine's kinematics of design ``i`` (its ``mechanism()``) over the range it runs
        (:meth:`crank_angles`): what ``linkwork analyze design_<i+1>.toml`` computes, for the
        report's drawing of the design."""
        phi = self.crank_angles(i, n)
        return kinematics(self.designs[i].mechanism(), phi, on_failure="nan")

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.doc.name, "kind": self.kind, "result": self.result.to_dict()}


def run(doc: SynthesisFile, kind: str, *, client: Any = None, progress: Any = False,
        seed: int | None = None, n_candidates: int | None = None) -> SynthesisStudy:
    """Run the ``kind`` task of ``doc`` (``seed``/``n_candidates`` override its ``[search]``).

    Raises
    ------
    ParameterError
        The file has no section for ``kind``.
    InfeasibleError
        Nothing meets the task (named, with the closest value reached).
    """
    if kind not in KINDS:
        raise ParameterError("kind", kind, f"must be one of {', '.join(KINDS)}")
    section = getattr(doc, kind)
    if section is None:
        have = [k for k in KINDS if getattr(doc, k) is not None]
        raise ParameterError(f"[{kind}]", "missing", f"the file has no [{kind}] section "
                             f"(it has {', '.join(f'[{k}]' for k in have)})")
    s = doc.search
    if kind == "path" and section.linkage != "fourbar":
        res: Any = sixbar.sixbar_path(
            section.points, kind=section.linkage, timing=section.timing,
            bounds=section.si_bounds() or None, constraints=section.constraint_tuple(),
            closed=section.closed, free_start=section.free_start,
            seed=s.seed if seed is None else seed, client=client, progress=progress,
            n_candidates=n_candidates or s.candidates, n_refine=s.refine, n_designs=s.designs)
    elif kind == "path":
        res = pa.path(
            section.points, timing=section.timing, bounds=section.si_bounds() or None,
            constraints=section.constraint_tuple(), objective=doc.objective.objective(),
            closed=section.closed, free_start=section.free_start,
            seed=s.seed if seed is None else seed, client=client,
            progress=progress, n_candidates=n_candidates or s.candidates,
            n_refine=s.refine, n_designs=s.designs)
    elif kind == "function":
        f = section.function()
        if section.mechanism == "fourbar":
            res = fn.fourbar_function(
                f, section.x_range, (section.input.start, section.input.span),
                (section.output.start, section.output.span), d=section.frame,
                n_points=section.points, n_least_squares=section.least_squares_points)
        else:
            res = fn.crank_slider_function(
                f, section.x_range, (section.input.start or 0.0, section.input.span),
                float(section.stroke), datum=section.datum, n_points=section.points,
                n_least_squares=section.least_squares_points)
    else:
        res = mo.motion(section.poses, fixed_pivots=section.fixed_pivots,
                        moving_pivots=section.moving_pivots, pivot_region=section.pivot_region,
                        grashof=section.grashof, mu_min=section.min_transmission,
                        n_designs=s.designs)
    return SynthesisStudy(doc=doc, kind=kind, result=res)  # type: ignore[arg-type]


def _mm(x: float) -> str:
    return fmt(float(x) * 1e3)


def _deg(x: float) -> str:
    return fmt(math.degrees(float(x)))


def _fourbar(study: SynthesisStudy) -> bool:
    return study.doc.path is None or study.doc.path.linkage == "fourbar"


def design_summary(study: SynthesisStudy) -> str:
    """What the search found and did, in one line (the title of :func:`design_table`)."""
    res = study.result
    n = len(res.designs)
    rej = ", ".join(f"{v} {k}" for k, v in getattr(res, "rejected", {}).items() if v) or "none"
    if study.kind == "path":
        what = "four-bars" if _fourbar(study) else f"{res.kind} six-bars"
        return (f"{n} defect-free {what} of {res.n_evaluated} candidates, {res.n_refined} "
                f"refined ({res.time:.3g} s; rejected: {rej})")
    if study.kind == "function":
        return (f"{n} {res.kind.replace('_', '-')} function generators (structural error over "
                "the whole range)")
    return (f"{n} four-bars through {len(res.poses)} poses from {res.n_dyads} dyads, "
            f"{res.n_pairs} pairs checked (rejected: {rej})")


def design_table(study: SynthesisStudy) -> tuple[list[str], list[list[str]]]:
    """The ranked designs as ``linkwork synthesize`` prints them (and the report shows them):
    the column heads with units and one row of formatted values per design (path: the error,
    the largest distance to a target, the literature's parameters, branch, minimum
    transmission angle and the forces when judged by them, or a six-bar's parameters and
    branches; function: the method, the link
    lengths, branch and the structural error; motion: the pivots, link lengths, minimum
    transmission angle and the pose error)."""
    res = study.result
    if study.kind == "path" and not _fourbar(study):
        lengths = ("r1", "r2", "r3", "r4", "x0", "y0", "cx", "cy", "r5", "r6", "x6", "y6",
                   "px", "py")
        return (["#", "error [mm²]", "max dev. [mm]", *(f"{k} [mm]" for k in lengths),
                 "θ0 [deg]", "branches B, D", "μmin [deg]"],
                [[str(i + 1), fmt(d.error * 1e6), _mm(d.checks.get("max_deviation", math.nan)),
                  *(_mm(d.params[k]) for k in lengths), _deg(d.params["theta0"]),
                  f"{d.branches[0]:+d}, {d.branches[1]:+d}",
                  _deg(d.checks.get("min_transmission_angle", math.nan))]
                 for i, d in enumerate(res.designs)])
    if study.kind == "path":
        head = ["#", "error [mm²]", "max dev. [mm]", "r1 [mm]", "r2 [mm]", "r3 [mm]",
                "r4 [mm]", "rcx [mm]", "rcy [mm]", "x0 [mm]", "y0 [mm]", "θ0 [deg]", "branch",
                "μmin [deg]"]
        forces = any(d.forces for d in res.designs)
        if forces:
            head += ["peak Q [N·m]", "peak bearing [N]", "RMS shaking [N]"]
        rows = []
        for i, d in enumerate(res.designs):
            p = d.params
            row = [str(i + 1), fmt(d.error * 1e6), _mm(d.checks.get("max_deviation", math.nan)),
                   *(_mm(p[k]) for k in ("r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0")),
                   _deg(p["theta0"]), f"{d.branch:+d}",
                   _deg(d.checks.get("min_transmission_angle", math.nan))]
            if forces:
                row += [fmt(d.forces.get(k, math.nan)) for k in
                        ("peak_torque", "peak_bearing", "rms_shaking")]
            rows.append(row)
        return head, rows
    if study.kind == "function":
        four = res.kind == "fourbar"
        names = ("a", "b", "c", "d") if four else ("L1", "L2", "e", "Y0")
        unit = "deg" if four else "mm"
        conv = math.degrees if four else (lambda v: v * 1e3)
        return (["#", "method", *(f"{n} [mm]" for n in names), "branch",
                 f"max error [{unit}]", f"RMS error [{unit}]"],
                [[str(i + 1), d.method, *(_mm(d.params[n]) for n in names), f"{d.branch:+d}",
                  fmt(conv(d.max_error)), fmt(conv(d.rms_error))]
                 for i, d in enumerate(res.designs)])
    return (["#", "O2 x [mm]", "O2 y [mm]", "O4 x [mm]", "O4 y [mm]", "r1 [mm]", "r2 [mm]",
             "r3 [mm]", "r4 [mm]", "μmin [deg]", "pose error [mm]"],
            [[str(i + 1), _mm(d.c1[0]), _mm(d.c1[1]), _mm(d.c2[0]), _mm(d.c2[1]),
              *(_mm(d.fourbar.params[k]) for k in ("r1", "r2", "r3", "r4")),
              _deg(d.fourbar.checks.get("min_transmission_angle", math.nan)),
              fmt(d.pose_error * 1e3)] for i, d in enumerate(res.designs)])
