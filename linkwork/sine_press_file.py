"""Deprecated location: import from linkwork.io.sine_press (the ``sine_press`` file)."""

from linkwork.io.sine_press import (
    CrankSection,
    IdleSection,
    NonNegative,
    OutputSection,
    PositiveLength,
    PositiveSpeed,
    ScheduleEntry,
    SinePressFile,
    WorkingSection,
)

__all__ = ["CrankSection", "IdleSection", "NonNegative", "OutputSection", "PositiveLength",
           "PositiveSpeed", "ScheduleEntry", "SinePressFile", "WorkingSection"]
