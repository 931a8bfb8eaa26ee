"""The pattern every figure of linkwork follows, and the pieces it shares.

Pattern of a plotting function (``linkwork/plot/<topic>.py``)::

    def plot_thing(result: Thing, ax: Any = None, *, name: str | None = None,
                   **options) -> <what it drew>:
        ax = axes_or_new(ax, nrows, ncols, figsize=...)  # given axes, else a new figure's
        ... draw with ax.plot / ax.fill / ...      # SI in the result, display units here
        ... label the axes (quantity [unit]), a label on every curve of the legend
        finish(ax, title=titled(name, "Thing", "the quantity"), angle=degrees_drawn)
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

What a designer prints (every axes goes through :func:`finish`, nothing of it is repeated in the
topic modules):

* a title naming the mechanism and the quantity, :func:`titled` (``name`` of the file where the
  caller has it, else the result type); figures of several axes name the mechanism once
  (:func:`figure_title`) and each axes its quantity;
* angle axes (crank or rotor angle [deg]) with ticks at multiples of 30 deg up to a turn, of
  90 deg up to about three turns (:func:`angle_axis`), limits at the range drawn;
* a grid;
* a legend inside the axes for up to :data:`LEGEND_INSIDE` entries, else outside, right of the
  data (the figure is saved with a tight bounding box, :func:`save`);
* curves that lie on one another (a two-force member's equal reactions, a balanced variant
  equal to the unbalanced one) drawn in different line styles with markers, so that each
  stays visible (:func:`distinguish`);
* text only in glyphs the font has: any other character (a CJK name with DejaVu Sans) is shown
  as "?" instead of a missing-glyph warning (:func:`text`).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from linkwork.outputs import atomic_path

__all__ = ["LEGEND_INSIDE", "Figure", "angle_axis", "axes_or_new", "distinguish", "figure_title",
           "finish", "legend", "pyplot", "save", "text", "titled"]

#: most legend entries drawn inside the axes; more go outside, right of the data
LEGEND_INSIDE = 3

#: tick steps [deg] of an angle axis, the first that gives at most about 12 intervals is taken
_ANGLE_STEPS = (1.0, 5.0, 10.0, 30.0, 90.0, 180.0, 360.0, 720.0, 1800.0, 3600.0, 36000.0)

#: styles given to curves that lie on an earlier one: (dashes, marker)
_OVERLAP_STYLES = (((0, (5.0, 3.0)), "o"), ((0, (1.5, 2.0)), "s"), ((0, (7.0, 2.0, 1.5, 2.0)), "^"),
                   ((0, (3.0, 3.0)), "D"), ((0, (9.0, 3.0)), "v"), ((0, (1.0, 1.0)), "x"))


def pyplot() -> Any:
    """Return ``matplotlib.pyplot``, selecting Agg when there is no display."""
    import matplotlib

    if not os.environ.get("DISPLAY") and not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


@functools.cache
def _font_charmap(families: tuple[str, ...]) -> frozenset[int]:
    """Code points of the fonts matplotlib draws text with (the family list, generic names
    expanded, every font of it found: matplotlib falls back along the list glyph by glyph)."""
    import matplotlib
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    rc: Any = matplotlib.rcParams
    names: list[str] = []
    for f in families:
        generic = f"font.{f}"
        names += list(rc[generic]) if generic in rc else [f]
    points: set[int] = set()
    for name in dict.fromkeys(names):
        try:
            path = font_manager.findfont(font_manager.FontProperties(family=name),
                                         fallback_to_default=False)
        except ValueError:
            continue
        points.update(FT2Font(path).get_charmap())
    return frozenset(points)


def text(s: str) -> str:
    """``s`` with every character the text font has no glyph for replaced by "?" (ASCII and
    line breaks are kept as they are)."""
    if s.isascii():
        return s
    import matplotlib

    have = _font_charmap(tuple(matplotlib.rcParams["font.family"]))
    return "".join(c if c.isascii() or ord(c) in have else "?" for c in s)


#: The longest mechanism name a title shows; a longer one is cut with an ellipsis (a 100 kB name
#: cost about 100 s per figure in savefig's tight bounding box).
TITLE_NAME_MAX = 80


def titled(name: str | None, default: str, quantity: str) -> str:
    """The title of a figure: ``"<name>: <quantity>"``, ``default`` (the result type) when no
    ``name`` is given; a name longer than :data:`TITLE_NAME_MAX` characters is cut."""
    shown = name or default
    if len(shown) > TITLE_NAME_MAX:
        shown = shown[:TITLE_NAME_MAX - 1] + "…"
    return f"{shown}: {quantity}"


def _fit(title: str, width_in: float) -> str:
    """``title`` broken after the mechanism's name when it is wider than ``width_in`` inches
    (about 10 characters an inch at the title's size)."""
    if "\n" not in title and len(title) > 10 * width_in and ": " in title:
        return title.replace(": ", ":\n", 1)
    return title


def figure_title(fig: Any, title: str) -> Any:
    """Title of a figure of several axes, just above the top row (and its axes titles)."""
    top = max(a.get_position().y1 for a in fig.axes)
    titled_row = any(a.get_title() for a in fig.axes if abs(a.get_position().y1 - top) < 1e-9)
    pad = (0.42 if titled_row else 0.12) / fig.get_figheight()
    return fig.suptitle(text(_fit(title, fig.get_figwidth())), y=top + pad, va="bottom")


def angle_axis(ax: Any, degrees: Any, axis: str = "x") -> None:
    """An angle axis over the range of ``degrees`` (the values drawn [deg]): ticks at
    multiples of 30 deg up to a turn, of 90 deg up to about three turns (coarser beyond,
    finer below a third of a turn), limits at the range."""
    from matplotlib.ticker import MultipleLocator

    d = np.asarray(degrees, dtype=float)
    d = d[np.isfinite(d)]
    if d.size == 0:
        return
    lo, hi = float(d.min()), float(d.max())
    if hi <= lo:
        return
    if d.size > 2:  # whole turns sampled without their end (0, h, ..., 360 - h): show to 360
        h = float(np.median(np.abs(np.diff(d))))
        turns = (hi - lo + h) / 360.0
        if h > 0 and round(turns) >= 1 and abs(turns - round(turns)) < 1e-6:
            hi = lo + 360.0 * round(turns)
    step = next((s for s in _ANGLE_STEPS if (hi - lo) / s <= 12.5), _ANGLE_STEPS[-1])
    target = ax.xaxis if axis == "x" else ax.yaxis
    target.set_major_locator(MultipleLocator(step))
    (ax.set_xlim if axis == "x" else ax.set_ylim)(lo, hi)


def _curves(ax: Any) -> list[Any]:
    """The labelled data curves of ``ax`` (reference lines and unlabelled helpers left out)."""
    return [ln for ln in ax.get_lines()
            if not str(ln.get_label()).startswith("_") and np.size(ln.get_xdata()) > 2]


def distinguish(ax: Any, share: float = 0.5, tol: float = 0.01) -> list[Any]:
    """Restyle the curves of ``ax`` that lie on an earlier curve (on at least ``share`` of
    their points within ``tol`` of the axes' value span): a dash pattern and sparse markers
    (staggered, so that neither hides the other) of their own. Returns the curves restyled."""
    curves = _curves(ax)
    if len(curves) < 2:
        return []
    ys = [np.asarray(ln.get_ydata(), dtype=float) for ln in curves]
    xs = [np.asarray(ln.get_xdata(), dtype=float) for ln in curves]
    finite = [y[np.isfinite(y)] for y in ys]
    lo = min((float(y.min()) for y in finite if y.size), default=0.0)
    hi = max((float(y.max()) for y in finite if y.size), default=0.0)
    eps = tol * max(hi - lo, 1e-300)
    restyled: list[Any] = []
    for j in range(1, len(curves)):
        on = [i for i in range(j) if xs[i].shape == xs[j].shape
              and np.allclose(xs[i], xs[j], equal_nan=True)
              and np.mean(np.abs(ys[i] - ys[j]) <= eps) >= share]
        if not on:
            continue
        dashes, marker = _OVERLAP_STYLES[len(restyled) % len(_OVERLAP_STYLES)]
        n = ys[j].size
        every = max(1, n // 12)
        curves[j].set_linestyle(dashes)
        curves[j].set_marker(marker)
        curves[j].set_markersize(4.5)
        curves[j].set_markerfacecolor("none")
        curves[j].set_markevery((((len(restyled) + 1) * every) // 4 % every, every))
        curves[j].set_zorder(curves[on[0]].get_zorder() + 0.1)
        restyled.append(curves[j])
    return restyled


def legend(ax: Any, outside: str = "right", **kw: Any) -> Any:
    """The legend of ``ax``: inside (``loc="best"``) for up to :data:`LEGEND_INSIDE` entries,
    else outside the data, right of the axes (``outside="right"``) or below them
    (``"below"``, e.g. when a colour bar takes the right). ``kw`` go to ``ax.legend``. None
    when nothing is labelled."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return None
    kw.setdefault("fontsize", "small")
    spec = ax.get_subplotspec()
    if spec is not None and spec.colspan.stop < spec.get_gridspec().ncols:
        outside = "below"  # an axes to the right: the legend goes under this one
    if len(handles) > LEGEND_INSIDE and outside == "below":
        kw.update(loc="upper center", bbox_to_anchor=(0.5, -0.14), borderaxespad=0.0)
        kw.setdefault("ncol", 2)
    elif len(handles) > LEGEND_INSIDE:
        kw.update(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    else:
        kw.setdefault("loc", "best")
    if "title" in kw:
        kw["title"] = text(kw["title"])
    return ax.legend(handles, [text(label) for label in labels], **kw)


def _sanitize(artists: Iterable[Any]) -> None:
    for a in artists:
        label = a.get_label()
        if isinstance(label, str) and not label.isascii():
            a.set_label(text(label))


def finish(ax: Any, *, title: str | None = None, angle: Any = None, angle_on: str = "x",
           grid: bool | str = True, legend_kw: dict[str, Any] | None = None,
           show_legend: bool = True) -> Any:
    """Give ``ax`` what every figure of linkwork has (see the module's rules): ``title`` (made
    printable), an angle axis over ``angle`` (the degrees drawn on ``angle_on``, ``"x"`` or
    ``"y"``; None: not an angle axis), a grid (``"y"``: horizontal lines only, for bars),
    overlapping curves told apart, and the legend (``legend_kw`` to :func:`legend`). Returns
    ``ax``."""
    _sanitize([*ax.get_lines(), *ax.collections, *ax.patches, *ax.containers])
    for t in (*ax.texts, ax.xaxis.label, ax.yaxis.label):
        t.set_text(text(t.get_text()))
    if title is not None:
        width = ax.get_position().width * ax.figure.get_figwidth()
        ax.set_title(text(_fit(title, width)))
    if angle is not None:
        angle_axis(ax, angle, angle_on)
    if grid:
        ax.grid(True, axis="both" if grid is True else grid, alpha=0.3)
    distinguish(ax)
    if show_legend:
        legend(ax, **(legend_kw or {}))
    return ax


def save(fig: Any, path: str | Path, dpi: int = 120) -> Path:
    """Save ``fig`` to ``path`` (PNG by suffix), close it, and return the path.

    Written beside ``path`` and renamed when complete (:func:`linkwork.outputs.atomic_path`):
    an interrupted save leaves no partial image. The figure is closed even if saving fails.
    """
    p = Path(path)
    try:
        with atomic_path(p) as tmp:
            fig.savefig(tmp, dpi=dpi, bbox_inches="tight")
    finally:
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
        """``matplotlib.figure.Figure.savefig`` (the figure stays open), with a tight bounding
        box unless ``bbox_inches`` is given (legends outside the axes stay on the page)."""
        kwargs.setdefault("bbox_inches", "tight")
        if not isinstance(path, str | os.PathLike):  # a file object: matplotlib writes to it
            self.figure.savefig(path, **kwargs)
            return
        with atomic_path(path) as tmp:  # beside, renamed when complete
            self.figure.savefig(tmp, **kwargs)

    def save(self, path: str | Path, dpi: int = 120) -> Path:
        """Save as :func:`save` does (tight bounding box), close the figure, return the path."""
        return save(self.figure, path, dpi=dpi)

    def close(self) -> None:
        """Close the figure (free its memory in pyplot)."""
        pyplot().close(self.figure)
