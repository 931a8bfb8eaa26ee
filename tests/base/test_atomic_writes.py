"""No output file is ever left half-written (issue 19, item 2).

write_csv, write_json and plot.save write beside the target and rename when complete
(linkwork.outputs.atomic_path): an interrupt in the middle leaves neither the target nor a
temporary file, and an earlier complete file stays as it was.
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import linkwork.results as results
from linkwork.outputs import atomic_path, recording
from linkwork.plot import pyplot, save
from linkwork.results import write_csv, write_json


def _interrupt_after(monkeypatch: pytest.MonkeyPatch, calls: int) -> None:
    """Make write_csv raise KeyboardInterrupt after ``calls`` cells: its blocks of rows are
    made small (100 rows) and the interrupt comes from the progress report after the block
    that passes ``calls`` cells, so that many rows already went to the file."""
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 100)
    real = results.write_csv

    def interrupting(path: Any, columns: dict[str, tuple[Any, str]], **kw: Any) -> Path:
        def progress(done: int, total: int) -> None:
            if done * len(columns) >= calls:
                raise KeyboardInterrupt

        return real(path, columns, progress=progress)

    monkeypatch.setattr(results, "write_csv", interrupting)


def _columns(n: int = 20000) -> dict[str, tuple[Any, str]]:
    x = np.linspace(0.0, 1.0, n)
    return {"x": (x, "m"), "y": (np.sin(x), "m")}


def test_interrupted_csv_leaves_no_target_and_no_temporary_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _interrupt_after(monkeypatch, 2 * 15000)  # 15000 of 20000 rows: well past a buffer
    with pytest.raises(KeyboardInterrupt):
        results.write_csv(tmp_path / "cycle.csv", _columns())
    assert list(tmp_path.iterdir()) == []


def test_interrupted_csv_keeps_the_earlier_complete_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "cycle.csv"
    write_csv(target, _columns(5))
    before = target.read_bytes()
    _interrupt_after(monkeypatch, 2 * 15000)
    with pytest.raises(KeyboardInterrupt):
        results.write_csv(target, _columns())
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["cycle.csv"]


def test_complete_csv_is_the_whole_file_and_nothing_beside_it(tmp_path: Path) -> None:
    target = write_csv(tmp_path / "cycle.csv", _columns(1000))
    with target.open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["x [m]", "y [m]"] and len(rows) == 1001
    assert float(rows[-1][0]) == 1.0
    assert [p.name for p in tmp_path.iterdir()] == ["cycle.csv"]


def test_interrupted_json_leaves_no_target_and_no_temporary_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real = results._json_lines

    def half_then_interrupt(value: Any, level: int, where: str = "") -> Any:
        if level:  # the nested values, as written
            yield from real(value, level, where)
            return
        pieces = list(real(value, level, where))
        yield from pieces[: len(pieces) // 2]  # half of it goes to the file
        raise KeyboardInterrupt

    monkeypatch.setattr(results, "_json_lines", half_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        write_json(tmp_path / "summary.json", {f"k{i}": list(range(100)) for i in range(100)})
    assert list(tmp_path.iterdir()) == []


def test_complete_json_parses(tmp_path: Path) -> None:
    target = write_json(tmp_path / "summary.json", {"a": [1.5, float("nan")]})
    assert json.loads(target.read_text()) == {"a": [1.5, None]}
    assert [p.name for p in tmp_path.iterdir()] == ["summary.json"]


def test_interrupted_plot_save_leaves_no_target_and_no_temporary_file(
        tmp_path: Path) -> None:
    fig, ax = pyplot().subplots()
    ax.plot([0, 1], [0, 1])
    real = fig.savefig

    def part_then_interrupt(path: Any, **kwargs: Any) -> None:
        real(path, **kwargs)
        Path(path).write_bytes(Path(path).read_bytes()[:2000])  # a PNG cut short
        raise KeyboardInterrupt

    fig.savefig = part_then_interrupt  # type: ignore[method-assign]
    with pytest.raises(KeyboardInterrupt):
        save(fig, tmp_path / "kinematics.png")
    assert list(tmp_path.iterdir()) == []
    assert not pyplot().fignum_exists(fig.number)  # closed all the same


def test_plot_save_writes_a_png_by_the_target_suffix(tmp_path: Path) -> None:
    fig, ax = pyplot().subplots()
    ax.plot([0, 1], [0, 1])
    target = save(fig, tmp_path / "line.png")
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fig, ax = pyplot().subplots()
    target = save(fig, tmp_path / "line.pdf")
    assert target.read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["line.pdf", "line.png"]


def test_atomic_file_has_the_permissions_of_an_ordinary_file(tmp_path: Path) -> None:
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    with atomic_path(tmp_path / "atomic.txt") as tmp:
        tmp.write_text("x")
    assert os.stat(tmp_path / "atomic.txt").st_mode == os.stat(plain).st_mode


def test_recording_lists_the_completed_files_only(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with recording() as written:
        write_json(tmp_path / "a.json", {})
        write_csv(tmp_path / "b.csv", _columns(3))
        _interrupt_after(monkeypatch, 2)
        with pytest.raises(KeyboardInterrupt):
            results.write_csv(tmp_path / "c.csv", _columns(3))
    write_json(tmp_path / "d.json", {})  # after the recording: not in it
    assert written == [tmp_path / "a.json", tmp_path / "b.csv"]
