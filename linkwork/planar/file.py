"""Deprecated location: import from linkwork.io.planar (the ``planar`` file)."""

from linkwork.io.planar import (
    MAX_ANGLE,
    XY,
    AnalysisSection,
    BodySection,
    DriverSection,
    FrameSection,
    JointSection,
    LoadSection,
    PlanarFile,
)

__all__ = ["MAX_ANGLE", "XY", "AnalysisSection", "BodySection", "DriverSection", "FrameSection",
           "JointSection", "LoadSection", "PlanarFile"]
