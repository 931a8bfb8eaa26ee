"""Figures, kept apart from the models and imported lazily.

Every plotting function takes ``ax=None`` (or ``axes=None``) and returns what it drew; colours and
styles never enter the models. matplotlib is imported on first use through :func:`pyplot`, with the
non-interactive Agg backend when no display is available. One module per topic
(:mod:`linkwork.plot.sine`, ...).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

__all__ = ["pyplot", "save"]


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
