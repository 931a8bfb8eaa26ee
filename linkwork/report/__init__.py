"""The self-contained HTML report of a mechanism file (``linkwork report FILE.toml``).

The report renders the same study objects as the command line (:mod:`linkwork.studies`) and
never recomputes them. It is a registry of :class:`Renderer`: each one says which files it
applies to, runs its study, and turns the study into a :class:`~linkwork.plot.html.Section`
(diagrams, tables, notes); the first applicable one with a drawing supplies the page's animated
mechanism (:mod:`linkwork.plot.scene`). A new command plugs in by adding one renderer
(:func:`register`): the page, the animation, the cursor links and the browser tests come with it.

* :func:`build` -- a validated file -> :class:`~linkwork.plot.html.Page`;
* :func:`html` -- the page as one HTML document (scripts, style and data inlined);
* :func:`write` -- written atomically beside its name;
* :func:`animation` -- the page's mechanism as a GIF or MP4 (:func:`linkwork.plot.scene.animate`).

Renderers: :mod:`~linkwork.report.planar` (``planar`` files: kinematics and dynamics, and the
``[balance]`` and ``[spatial]`` sections through :mod:`~linkwork.report.balance` and
:mod:`~linkwork.report.reactions`), :mod:`~linkwork.report.sine_press`,
:mod:`~linkwork.report.swashplate`.
"""

from __future__ import annotations

from linkwork.report.core import (
    Options,
    Renderer,
    animation,
    build,
    html,
    register,
    renderers,
    write,
)

__all__ = ["Options", "Renderer", "animation", "build", "html", "register", "renderers",
           "write"]
