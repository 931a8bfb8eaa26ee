"""Deprecated location: import from linkwork.io.planar (the ``[spatial]`` section of a planar
file)."""

from linkwork.io.planar import (
    DeviationSpec,
    JointSpec,
    OutOfPlaneSpec,
    SpatialSpec,
    ToleranceSpec,
    read_spatial,
)

__all__ = ["DeviationSpec", "JointSpec", "OutOfPlaneSpec", "SpatialSpec", "ToleranceSpec",
           "read_spatial"]
