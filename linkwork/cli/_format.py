"""The number format of the printed tables: :mod:`linkwork.plot.numbers` (shared with the
HTML report and the notebook displays), under the name the commands import."""

from __future__ import annotations

from linkwork.plot.numbers import ROUND_OFF, UNDEFINED, fmt, scale_of, unit_label

__all__ = ["ROUND_OFF", "UNDEFINED", "fmt", "scale_of", "unit_label"]
