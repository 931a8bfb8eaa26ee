"""Spatial reactions of planar mechanisms with redundant constraints (paper 004).

See :mod:`linkwork.redundancy.core` for the model and its conventions and ``docs/redundancy.md``
for the theory, the defaults and the mapping to the equations of paper 004.
"""

from linkwork.redundancy.core import (
    COMPONENTS,
    DEFAULT_BEARING_STIFFNESS,
    JOINT_KINDS,
    Influence,
    RedundancyCount,
    SpatialGeometry,
    SpatialJoint,
    SpatialModel,
    SpatialReactions,
    bearing_stiffness,
    count_redundancy,
    equilibrium_matrix,
    influence,
    misfit,
    solve_reactions,
    wrench_about_origin,
)
from linkwork.redundancy.mechanism import (
    Deviation,
    OutOfPlaneLoad,
    body_wrenches,
    deviation_array,
    geometry,
    spatial_model,
    spatial_reactions,
)
from linkwork.redundancy.tolerance import (
    PEAK_QUANTITIES,
    Tolerance,
    ToleranceStudy,
    tolerance_study,
)

__all__ = [
    "COMPONENTS",
    "DEFAULT_BEARING_STIFFNESS",
    "JOINT_KINDS",
    "PEAK_QUANTITIES",
    "Deviation",
    "Influence",
    "OutOfPlaneLoad",
    "RedundancyCount",
    "SpatialGeometry",
    "SpatialJoint",
    "SpatialModel",
    "SpatialReactions",
    "Tolerance",
    "ToleranceStudy",
    "bearing_stiffness",
    "body_wrenches",
    "count_redundancy",
    "deviation_array",
    "equilibrium_matrix",
    "geometry",
    "influence",
    "misfit",
    "solve_reactions",
    "spatial_model",
    "spatial_reactions",
    "tolerance_study",
    "wrench_about_origin",
]
