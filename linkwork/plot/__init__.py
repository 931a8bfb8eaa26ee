"""Figures, kept apart from the models and imported lazily.

Every plotting function takes ``ax=None`` (or ``axes=None``) through one helper
(:func:`axes_or_new`) and returns what it drew; ``result.plot()`` of every result family returns
one :class:`Figure`. Colours and styles never enter the models. matplotlib is imported on first
use through :func:`pyplot`, with the non-interactive Agg backend when no display is available.
One module per topic (:mod:`linkwork.plot.sine`, ...); the pattern they follow, and what every
figure has (title naming the mechanism and the quantity, angle ticks at multiples of 30 or 90
degrees, grid, legend outside the data past three entries, overlapping curves told apart, only
glyphs the font has), is written down in :mod:`linkwork.plot._base` and applied by its
:func:`finish`.
"""

from __future__ import annotations

from linkwork.plot._base import (
    Figure,
    angle_axis,
    axes_or_new,
    distinguish,
    figure_title,
    finish,
    legend,
    pyplot,
    save,
    text,
    titled,
)

__all__ = ["Figure", "angle_axis", "axes_or_new", "distinguish", "figure_title", "finish",
           "legend", "pyplot", "save", "text", "titled"]
