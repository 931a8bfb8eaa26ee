"""The registry of renderers and the making of a report from a validated file.

:func:`build` runs every renderer that applies to the file (in the order of
:func:`renderers`), takes the page's mechanism drawing from the first that has one, and
collects sections, input tables, notes and warnings into a :class:`~linkwork.plot.html.Page`.
A failure of a primary renderer (the file type's own study) fails the report with its error; a
failure of another (a ``[balance]`` that cannot be balanced) is shown in its section.
"""

from __future__ import annotations

import dataclasses
import datetime
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

from linkwork import __version__
from linkwork.errors import FileFormatError, LinkworkError
from linkwork.outputs import atomic_path
from linkwork.plot.html import Page, Section, Table, page_html
from linkwork.plot.scene import MAX_ANIMATION_FRAMES, Scene, animate
from linkwork.report import (
    balance,
    dynamics,
    planar,
    reactions,
    sine_press,
    swashplate,
    synthesis,
)
from linkwork.report.base import Options, Renderer

__all__ = ["Options", "Renderer", "animation", "build", "html", "register", "renderers",
           "write"]

#: The renderers, in the order of the page's sections.
_RENDERERS: list[Renderer] = [planar.RENDERER, balance.RENDERER, reactions.RENDERER,
                              sine_press.RENDERER, dynamics.RENDERER, swashplate.RENDERER,
                              *synthesis.RENDERERS]


def register(renderer: Renderer, *, before: str | None = None) -> None:
    """Add ``renderer`` (replacing one of the same key), at the end or before the one keyed
    ``before``."""
    _RENDERERS[:] = [r for r in _RENDERERS if r.key != renderer.key]
    keys = [r.key for r in _RENDERERS]
    _RENDERERS.insert(keys.index(before) if before in keys else len(_RENDERERS), renderer)


def renderers(doc: Any = None) -> list[Renderer]:
    """The registered renderers, or those that apply to ``doc``."""
    if doc is None:
        return list(_RENDERERS)
    return [r for r in _RENDERERS if isinstance(doc, r.file_type) and r.applies(doc)]


def _today() -> str:
    """The date on the report: ``SOURCE_DATE_EPOCH`` if set (reproducible builds), else today
    (UTC)."""
    epoch = os.environ.get("SOURCE_DATE_EPOCH")
    if epoch and epoch.isdigit():
        when = datetime.datetime.fromtimestamp(int(epoch), datetime.UTC)
    else:
        when = datetime.datetime.now(datetime.UTC)
    return when.date().isoformat()


def build(doc: Any, *, path: str | Path | None = None, options: Options | None = None,
          step: Callable[[str], None] | None = None) -> Page:
    """The report of the validated file ``doc`` (:func:`linkwork.io.load`) read from ``path``.

    Raises
    ------
    FileFormatError
        No renderer takes the file's type.
    LinkworkError
        The file type's own study failed (e.g. an AssemblyError: the mechanism assembles at no
        position of the range), or every part of the report failed (the first one's error).
    """
    opts = options or Options(file=str(path) if path is not None else "file")
    todo = renderers(doc)
    if not todo:
        known = sorted({t.__name__ for r in _RENDERERS
                        for t in (r.file_type if isinstance(r.file_type, tuple)
                                  else (r.file_type,))})
        raise FileFormatError(str(path or "file"), "type",
                              f"no report for a {type(doc).__name__}; reports exist for "
                              f"{known}")
    scene: Scene | None = None
    sections: list[Section] = []
    inputs: list[Table] = []
    notes: list[tuple[str, str]] = []
    warnings: list[str] = []
    timed: list[tuple[Renderer, Any]] = []
    choices: list[tuple[str, Scene]] = []
    failed: list[LinkworkError] = []
    for r in todo:
        if step is not None:
            step(f"computing {r.title}")
        try:
            study = r.run(doc, opts)
        except LinkworkError as exc:
            if r.primary:
                raise
            failed.append(exc)
            sections.append(Section(title=r.title, key=r.key,
                                    error=f"not computed: {' '.join(str(exc).split())}"))
            continue
        if scene is None and r.scene is not None:
            scene = r.scene(study, opts)
        section = r.section(study, opts)
        if r.scenes is not None:
            if not choices and scene is not None:
                choices.append(("the mechanism", scene))
            section = _shifted(section, len(choices))
            choices += r.scenes(study, opts)
            scene = choices[0][1]
        sections.append(section)
        if r.inputs is not None:
            inputs += r.inputs(doc)
        if r.notes is not None:
            notes += r.notes(study)
        if r.warnings is not None:
            warnings += r.warnings(study)
        if r.timing is not None:
            timed.append((r, study))
    if failed and len(failed) == len(todo):
        raise failed[0]
    for r, study in timed:
        if scene is not None and r.timing is not None and not choices:
            scene = r.timing(study, scene)
    name = getattr(doc, "name", "") or (Path(path).stem if path is not None else "mechanism")
    source = ""
    if path is not None:
        try:
            source = Path(path).read_text(encoding="utf-8", errors="replace")
        except OSError:
            source = ""
    kind = getattr(doc, "type", type(doc).__name__)
    where = f" {Path(path).name}" if path is not None else ""
    return Page(title=name, subtitle=f"linkwork report of the {kind} file{where}",
                scene=scene, sections=sections, inputs=inputs, source=source,
                source_name=Path(path).name if path is not None else "",
                notes=notes, warnings=warnings, version=__version__,
                date=opts.date or _today(), choices=choices)


def _shifted(section: Section, offset: int) -> Section:
    """``section`` with its diagrams' and tables' drawing indices moved by ``offset`` (the
    drawings of the renderers before it)."""
    if offset == 0:
        return section
    return dataclasses.replace(
        section,
        diagrams=[dataclasses.replace(d, scene=d.scene + offset) for d in section.diagrams],
        tables=[dataclasses.replace(t, scene=t.scene + offset, chooses=None if t.chooses is None
                                    else [None if c is None else c + offset
                                          for c in t.chooses])
                for t in section.tables])


def html(doc: Any, *, path: str | Path | None = None, options: Options | None = None,
         step: Callable[[str], None] | None = None) -> str:
    """The report of ``doc`` as one self-contained HTML document (:func:`build`)."""
    return page_html(build(doc, path=path, options=options, step=step))


def write(page: Page, target: str | Path) -> Path:
    """Write ``page`` (:func:`build`) as HTML to ``target``, beside it and renamed when
    complete."""
    p = Path(target)
    with atomic_path(p) as tmp:
        tmp.write_text(page_html(page), encoding="utf-8")
    return p


def animation(page: Page, target: str | Path, *, frames: int = 120, fps: int = 20,
              size: tuple[int, int] = (640, 480)) -> Path:
    """The page's mechanism as a GIF or MP4 (by the suffix of ``target``), at most
    :data:`~linkwork.plot.scene.MAX_ANIMATION_FRAMES` frames
    (:func:`linkwork.plot.scene.animate`)."""
    if page.scene is None:
        raise FileFormatError(str(target), "animation", "this report has no drawing of the "
                              "mechanism to animate")
    return animate(page.scene, target, frames=min(frames, MAX_ANIMATION_FRAMES), fps=fps,
                   size=size)
