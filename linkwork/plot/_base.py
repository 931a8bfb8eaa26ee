"""The pattern every figure of linkwork follows, and the pieces it shares.

Pattern of a plotting function (``linkwork/plot/<topic>.py``)::

    def plot_thing(result: Thing, ax: Any = None, **options) -> <what it drew>:
        ax = axes_or_new(ax, nrows, ncols, figsize=...)  # given axes, else a new figure's
        ... draw with ax.plot / ax.fill / ...      # SI in the result, display units here
        ... label the axes (quantity [unit]), legend
        return ax   (or a dict of the artists drawn, as the function documents)

and of the figure of a result family (what ``result.plot()`` returns)::

    def thing_figure(result: Thing, ax: Any = None, **options) -> Figure:
        return Figure.of(plot_thing(result, ax=ax, **options))

Rules:

* matplotlib is imported lazily (:func:`pyplot`, inside functions), so that ``import linkwork``
  never imports it; with no display and no ``MPLBACKEND`` the Agg backend is selected.
* Axes come from :func:`axes_or_new` only: ``ax=None`` (or ``axes=None``) makes a new figure
  with the function's layout, given axes are drawn into (to compose figures).
* Plot modules read results by their attributes; they import result and model classes only
  for type checking (``if TYPE_CHECKING:``), never ``linkwork.models``, ``planar``,
  ``balancing``, ``redundancy`` or ``synthesis`` at run time. The results import
  :mod:`linkwork.plot` lazily in their ``.plot()`` method, so there is no import circle.
* Colours and styles live here, never in the models.
* The figure of a result family is one :class:`Figure` (the matplotlib figure, its data axes
  and what was drawn), whatever the family: it saves, closes, and indexes like the axes array
  the older functions returned.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["Figure", "axes_or_new", "pyplot", "save"]


def pyplot() -> Any:
    """Return ``matplotlib.pyplot``, selecting Agg when there is no display."""
    import matplotlib

    if not os.environ.get("DISPLAY") and not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig: Any, path: str | Path, dpi: int = 120) -> Path:
    """Save ``fig`` to ``path`` (PNG by suffix), close it, and return the path."""
    p = Path(path)
    fig.savefig(p, dpi=dpi, bbox_inches="tight")
    pyplot().close(fig)
    return p


def axes_or_new(ax: Any, nrows: int = 1, ncols: int = 1, **subplots: Any) -> Any:
    """The ``ax=None`` pattern: ``ax`` itself if given, else the axes of a new figure.

    Parameters
    ----------
    ax : matplotlib Axes, array of Axes, or None
        Axes to draw into (returned unchanged).
    nrows, ncols : int
        Layout of the new figure.
    **subplots
        Passed to ``pyplot().subplots`` (``figsize``, ``sharex``, ...).

    Returns
    -------
    Axes or ndarray of Axes
        As ``plt.subplots`` gives them (one Axes for a 1 x 1 layout).
    """
    if ax is not None:
        return ax
    _, new = pyplot().subplots(nrows, ncols, **subplots)
    return new


def _flat_axes(drawn: Any) -> list[Any]:
    """The data axes in what a plotting function returned: an Axes, an array of Axes, or a
    dict with ``"ax"`` / ``"axes"`` entries."""
    if isinstance(drawn, dict):
        found = [drawn[k] for k in ("axes", "ax") if k in drawn]
        return [a for f in found for a in _flat_axes(f)]
    if isinstance(drawn, np.ndarray | list | tuple):
        return [a for d in drawn for a in _flat_axes(d)]
    return [drawn]


@dataclass
class Figure:
    """What the figure of a result gives back: one type for every result family.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
        The figure drawn on.
    axes : ndarray of Axes, shape (k,)
        The data axes, in reading order (colour bars not included).
    artists : dict
        What the plotting function returned, by name (lines, the histogram, ...); the older
        functions' own return value is under ``"drawn"``.

    ``fig[i]`` is ``fig.axes[i]`` and ``len(fig)`` the number of axes, as for the array of axes
    the older plotting functions returned.
    """

    figure: Any
    axes: np.ndarray
    artists: dict[str, Any] = field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, drawn: Any, **artists: Any) -> Figure:
        """Wrap the return value of a plotting function (Axes, array of Axes or a dict of
        artists with ``"ax"``/``"axes"``); ``artists`` are added by name."""
        flat = _flat_axes(drawn)
        arr = np.empty(len(flat), dtype=object)
        arr[:] = flat
        named = dict(drawn) if isinstance(drawn, dict) else {}
        named.setdefault("drawn", drawn)
        named.update(artists)
        return cls(flat[0].figure, arr, named)

    def __getitem__(self, i: int) -> Any:
        return self.axes[i]

    def __len__(self) -> int:
        return len(self.axes)

    def __iter__(self) -> Iterator[Any]:
        return iter(self.axes)

    def get_lines(self) -> list[Any]:
        """Every Line2D of the data axes, axes in order (one axes: its ``get_lines()``)."""
        return [ln for a in self.axes for ln in a.get_lines()]

    def savefig(self, path: str | Path, **kwargs: Any) -> None:
        """``matplotlib.figure.Figure.savefig`` (the figure stays open)."""
        self.figure.savefig(path, **kwargs)

    def save(self, path: str | Path, dpi: int = 120) -> Path:
        """Save as :func:`save` does (tight bounding box), close the figure, return the path."""
        return save(self.figure, path, dpi=dpi)

    def close(self) -> None:
        """Close the figure (free its memory in pyplot)."""
        pyplot().close(self.figure)
