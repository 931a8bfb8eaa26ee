"""Figures, kept apart from the models and imported lazily.

Every plotting function takes ``ax=None`` (or ``axes=None``) through one helper
(:func:`axes_or_new`) and returns what it drew; ``result.plot()`` of every result family returns
one :class:`Figure`. Colours and styles never enter the models. matplotlib is imported on first
use through :func:`pyplot`, with the non-interactive Agg backend when no display is available.
One module per topic (:mod:`linkwork.plot.sine`, ...); the pattern they follow is written down in
:mod:`linkwork.plot._base`.
"""

from __future__ import annotations

from linkwork.plot._base import Figure, axes_or_new, pyplot, save

__all__ = ["Figure", "axes_or_new", "pyplot", "save"]
