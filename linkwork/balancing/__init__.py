"""Balancing of planar mechanisms: shaking loads, counterweights, partial dynamic balancing.

* :mod:`linkwork.balancing.loads` -- shaking force and moment, moment about any point, harmonic
  content, RMS and peak over a cycle;
* :mod:`linkwork.balancing.partial` -- partial dynamic balancing after paper 001: the crank
  counterweight's axis moved to O1(x, y) (least squares, the paper's formula (1), first
  harmonic, continuous RMS), and the paper's efficiency R_j.
"""

from linkwork.balancing.loads import (
    Harmonics,
    harmonics,
    moment_about,
    peak,
    rms,
    shaking_force,
    shaking_moment,
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

__all__ = [
    "AxisOffset",
    "Harmonics",
    "counterweight_axis_moment",
    "counterweight_axis_offset",
    "efficiency",
    "first_harmonic_offset",
    "harmonics",
    "moment_about",
    "peak",
    "periodic_weights",
    "rms",
    "rms_offset",
    "shaking_force",
    "shaking_moment",
]
