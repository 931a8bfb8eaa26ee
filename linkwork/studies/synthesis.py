"""What a ``synthesis`` task file asks for: path, function or motion generation.

:func:`run` dispatches on the task kind and returns a frozen :class:`SynthesisStudy` holding the
task and its result (:class:`~linkwork.synthesis.design.SynthesisResult`,
:class:`~linkwork.synthesis.function.FunctionResult` or
:class:`~linkwork.synthesis.motion.MotionResult`); the command renders it, a report can too.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from linkwork.errors import ParameterError
from linkwork.io.synthesis import SynthesisFile
from linkwork.synthesis import function as fn
from linkwork.synthesis import motion as mo
from linkwork.synthesis import path as pa
from linkwork.synthesis import sixbar

__all__ = ["KINDS", "SynthesisStudy", "run"]

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
