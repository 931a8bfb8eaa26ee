"""Deprecated location: import from linkwork.io.swashplate (the ``swashplate`` file)."""

from linkwork.io.swashplate import (
    GeometrySection,
    LoadSection,
    OperationSection,
    OutputSection,
    PositiveLength,
    SwashplateFile,
)

__all__ = ["GeometrySection", "LoadSection", "OperationSection", "OutputSection",
           "PositiveLength", "SwashplateFile"]
