"""Balancing of planar mechanisms: shaking loads, counterweights, partial dynamic balancing.

* :mod:`linkwork.balancing.loads` -- shaking force and moment, moment about any point, harmonic
  content, RMS and peak over a cycle;
* :mod:`linkwork.balancing.partial` -- partial dynamic balancing after paper 001: the crank
  counterweight's axis moved to O1(x, y) (least squares, the paper's formula (1), first
  harmonic, continuous RMS), and the paper's efficiency R_j;
* :mod:`linkwork.balancing.static` -- counterweights in closed form (four-bar by linearly
  independent vectors, crank-slider with a fraction of the reciprocating mass);
* :mod:`linkwork.balancing.mechanism` -- counterweights on planar-engine mechanisms (a new
  mechanism description), shaking loads from a kinematic solution, general force balancing;
* :mod:`linkwork.balancing.comparison` -- paper 001's table for any crank-driven mechanism,
  with the driving torque and frame-bearing reactions before and after.
"""

from linkwork.balancing.comparison import (
    BalancingComparison,
    CycleComparison,
    compare_balancing,
    crank_axis,
)
from linkwork.balancing.loads import (
    Harmonics,
    harmonics,
    moment_about,
    peak,
    rms,
    shaking_force,
    shaking_moment,
)
from linkwork.balancing.mechanism import (
    ForceBalance,
    ShakingLoads,
    add_counterweights,
    crank_slider_balance,
    cycle,
    force_balance,
    frame_hinge,
    frame_hinged_links,
    shaking_loads,
)
from linkwork.balancing.partial import (
    AxisOffset,
    counterweight_axis_moment,
    counterweight_axis_offset,
    efficiency,
    first_harmonic_offset,
    periodic_weights,
    rms_offset,
)
from linkwork.balancing.static import (
    Counterweight,
    crank_slider_counterweight,
    fourbar_counterweights,
    fourbar_counterweights_point_masses,
    statically_equivalent_masses,
)

__all__ = [
    "AxisOffset",
    "BalancingComparison",
    "Counterweight",
    "CycleComparison",
    "ForceBalance",
    "Harmonics",
    "ShakingLoads",
    "add_counterweights",
    "compare_balancing",
    "counterweight_axis_moment",
    "counterweight_axis_offset",
    "crank_axis",
    "crank_slider_balance",
    "crank_slider_counterweight",
    "cycle",
    "efficiency",
    "first_harmonic_offset",
    "force_balance",
    "fourbar_counterweights",
    "fourbar_counterweights_point_masses",
    "frame_hinge",
    "frame_hinged_links",
    "harmonics",
    "moment_about",
    "peak",
    "periodic_weights",
    "rms",
    "rms_offset",
    "shaking_force",
    "shaking_loads",
    "shaking_moment",
    "statically_equivalent_masses",
]
