"""The HTML report: time to make it and its size, per bundled example, side by side.

For every example file: ``study`` (the file type's studies alone, what ``linkwork analyze``
computes), ``report`` (the same studies turned into the page: :func:`linkwork.report.build` and
the HTML text, :func:`linkwork.plot.html.page_html`), and the page's size; plus ``GIF`` (the
animation file, 60 frames at 640 x 480, on the four-bar). Times min / median / max over
``--repeat`` runs (seconds). ``python benchmarks/report.py [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from linkwork import io, report
from linkwork.plot.html import page_html

ROOT = Path(__file__).resolve().parents[1]


def _times(fn: Callable[[], Any], repeat: int) -> tuple[list[float], Any]:
    out = []
    value = None
    for _ in range(repeat):
        t = time.perf_counter()
        value = fn()
        out.append(time.perf_counter() - t)
    return out, value


def run(files: list[Path] | None = None, repeat: int = 3, gif_frames: int = 60
        ) -> list[dict[str, Any]]:
    """One row per example: study and report times [s], page size [bytes]; and a GIF row."""
    rows = []
    for path in files or sorted((ROOT / "examples").glob("*.toml")):
        doc = io.load(path)
        todo = report.renderers(doc)
        opts = report.Options(file=str(path))
        study_t, _ = _times(lambda d=doc, o=opts, t=todo: [r.run(d, o) for r in t], repeat)
        report_t, html = _times(lambda d=doc, p=path: page_html(report.build(d, path=p)),
                                repeat)
        rows.append({"file": path.name, "study": study_t, "report": report_t,
                     "bytes": len(html.encode()), "positions": _positions(doc)})
    if gif_frames:
        path = ROOT / "examples" / "fourbar_paper001.toml"
        page = report.build(io.load(path), path=path)
        with tempfile.TemporaryDirectory() as tmp:
            gif_t, gif = _times(lambda: report.animation(page, Path(tmp) / "m.gif",
                                                         frames=gif_frames), 1)
            rows.append({"file": f"GIF of {path.name}, {gif_frames} frames", "study": [],
                         "report": gif_t, "bytes": gif.stat().st_size, "positions": 0})
    return rows


def _positions(doc: Any) -> int:
    if hasattr(doc, "analysis"):
        return int(doc.analysis.n)
    out = getattr(doc, "output", None)
    if out is None:  # a synthesis task: no positions of its own
        return 0
    return int(getattr(out, "samples", 0) or getattr(out, "samples_per_revolution", 0) + 1)


def _mmm(ts: list[float]) -> str:
    if not ts:
        return "-"
    return f"{min(ts):.2f} / {statistics.median(ts):.2f} / {max(ts):.2f}"


def table(rows: list[dict[str, Any]]) -> str:
    head = f"{'file':42} {'positions':>9} {'study [s]':>20} {'report [s]':>20} {'size':>9}"
    lines = [head, "-" * len(head)]
    for r in rows:
        lines.append(f"{r['file']:42} {r['positions'] or '':>9} {_mmm(r['study']):>20} "
                     f"{_mmm(r['report']):>20} {r['bytes'] / 1e3:>6.0f} kB")
    lines.append("times: min / median / max; report = the studies + the page")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--gif-frames", type=int, default=60)
    a = ap.parse_args()
    print(table(run(repeat=a.repeat, gif_frames=a.gif_frames)))


if __name__ == "__main__":
    main()
