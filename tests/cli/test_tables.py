"""Tables that fit (issue 19, part 4): every table of every command printed at 80 columns holds
every column header and every number of the same table printed at full width (400 columns,
where Rich needs neither to crop nor to split), column for column; nothing is cropped."""

from __future__ import annotations

import re
from collections import Counter
from io import StringIO
from pathlib import Path

import pytest
from rich.cells import cell_len
from rich.console import Console
from rich.table import Table
from rich.text import Text

from linkwork import io
from linkwork.cli import _console, main
from linkwork.cli._planar import analyze_planar
from linkwork.cli._tables import print_table, split_table

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
WIDE = 400  # wider than any table of the examples: Rich prints them whole

Column = tuple[str, tuple[str, ...]]


def _cells(line: str) -> list[str]:
    return [c.strip() for c in re.split("[┃│]", line.strip())[1:-1]]


def _tables(text: str) -> list[tuple[list[str], list[list[str]]]]:
    """The tables of Rich's box drawing in ``text``: (header cells or [], rows of cells)."""
    tables: list[tuple[list[str], list[list[str]]]] = []
    head: list[str] = []
    rows: list[list[str]] = []
    for line in text.splitlines():
        s = line.strip()
        if s.startswith(("┏", "┌")):
            head, rows = [], []
        elif s.startswith("┃"):
            assert not head, f"a header of two lines (wrapped): {s}"
            head = _cells(s)
        elif s.startswith("│"):
            rows.append(_cells(s))
        elif s.startswith("└"):
            tables.append((head, rows))
    return tables


def _columns(text: str) -> list[Column]:
    """Every column of every table of at least three columns (their cells are numbers or
    short names, printed on one line): (header, cells top to bottom)."""
    return [(head[j] if head else "", tuple(r[j] for r in rows))
            for head, rows in _tables(text) if rows and len(rows[0]) >= 3
            for j in range(len(rows[0]))]


def _cell_words(text: str) -> Counter[str]:
    """The words of the table cells (the lines of the box drawing, between the rules)."""
    words: Counter[str] = Counter()
    for line in text.splitlines():
        if line.strip().startswith(("┃", "│")):
            words.update(w for c in _cells(line) for w in c.split())
    return words


def _assert_same_tables(narrow: str, wide: str, width: int) -> None:
    wide_columns, narrow_columns = _columns(wide), set(_columns(narrow))
    assert wide_columns
    missing = [c for c in wide_columns if c not in narrow_columns]
    assert not missing, f"columns lost or changed at {width} columns: {missing}"
    have = _cell_words(narrow)
    lost = {w: k for w, k in _cell_words(wide).items() if have[w] < k}
    assert not lost, f"cell contents lost at {width} columns: {lost}"
    assert max(cell_len(line) for line in narrow.splitlines()) <= width


def _analyze_text(example: str, width: int, out: Path) -> str:
    console = Console(width=width, record=True, file=StringIO())
    out.mkdir()
    analyze_planar(io.load(EXAMPLES / example), out=out, angles=None, console=console)
    return console.export_text()


@pytest.mark.parametrize(("example", "columns"), [("fourbar_paper001.toml", 9),
                                                  ("loom_sixbar.toml", 13)])
def test_planar_table_split_at_80_columns_keeps_every_column(example, columns, tmp_path):
    """The issue: at 80 columns Rich cut the four-bar's table after |R O4| (the shaking force,
    moment and transmission angle were lost) and the six-bar's after 6 of its 13 columns."""
    wide = _analyze_text(example, WIDE, tmp_path / "wide")
    narrow = _analyze_text(example, 80, tmp_path / "narrow")
    head, _ = _tables(wide)[0]
    assert len(head) == columns  # the whole table, one piece, at full width
    assert "(columns" not in wide
    _assert_same_tables(narrow, wide, 80)
    assert "(columns 1-" in narrow and f" of {columns})" in narrow
    # Rich alone, at 80 columns, loses columns: the split is what keeps them
    table = Table(title="t")
    for h in head:
        table.add_column(h, no_wrap=True)
    plain = Console(width=80, record=True, file=StringIO())
    plain.print(table)
    assert _tables(plain.export_text())[0][0] != head


def _cli_text(args: list[str], width: int, out: Path, monkeypatch, capsys) -> str:
    monkeypatch.setattr(_console, "PIPE_WIDTH", width)
    assert main([*args, "--out", str(out)]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("args", [
    ["analyze", str(EXAMPLES / "loom_sixbar.toml")],
    ["analyze", str(EXAMPLES / "sine_press.toml")],
    ["analyze", str(EXAMPLES / "swashplate_4a.toml")],
    ["balance", str(EXAMPLES / "loom_sixbar.toml")],
    ["reactions", str(EXAMPLES / "loom_fourbar_spatial.toml"), "--no-plots",
     "--tolerance-study", "20"],
    ["reactions", str(EXAMPLES / "loom_sixbar.toml"), "--no-plots"],
    ["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", "--scheme", "4a",
     "--objective", "torque", "--candidates", "512", "--point", "90 deg,30 mm"],
], ids=["analyze-sixbar", "analyze-sine-press", "analyze-swashplate", "balance",
        "reactions-tolerance", "reactions-sixbar", "swashplate-synthesize"])
def test_every_command_prints_its_tables_whole_into_a_narrow_pipe(args, tmp_path, monkeypatch,
                                                                  capsys):
    """Into a pipe the console is PIPE_WIDTH wide: set to 80, every command's tables keep all
    their columns and cells (against the same command at 400 columns)."""
    wide = _cli_text(args, WIDE, tmp_path / "wide", monkeypatch, capsys)
    narrow = _cli_text(args, 80, tmp_path / "narrow", monkeypatch, capsys)
    _assert_same_tables(narrow, wide, 80)


def _numbers_table(n_columns: int, caption: str | None = None) -> Table:
    table = Table(title=Text("forces [N]"), caption=caption)
    for j in range(n_columns):
        table.add_column(f"col {j}", justify="right", no_wrap=True)
    for i in range(3):
        table.add_row(*(f"{1.2345e5 * (i + 1) * (j + 1):.6g}" for j in range(n_columns)))
    return table


def test_split_parts_repeat_the_first_column_and_name_their_columns():
    console = Console(width=60, file=StringIO())
    parts = split_table(console, _numbers_table(10, caption="Q = 3 N·m"))
    assert len(parts) > 1
    shown = [[str(c.header) for c in p.columns] for p in parts]
    assert all(s[0] == "col 0" for s in shown)
    assert [h for s in shown for h in s[1:]] == [f"col {j}" for j in range(1, 10)]
    first = len(shown[0])
    assert str(parts[0].title) == f"forces [N] (columns 1-{first} of 10)"
    assert str(parts[1].title).startswith(f"forces [N] (columns 1, {first + 1}-")
    assert [p.caption for p in parts] == [None] * (len(parts) - 1) + ["Q = 3 N·m"]


def test_a_column_too_wide_for_the_console_is_folded_not_cropped():
    """Below the width of the first column and one more, nothing can be split off: the cells
    wrap or fold, and every character is still printed."""
    console = Console(width=20, record=True, file=StringIO())
    table = Table(title="t")
    table.add_column("joint", no_wrap=True)
    table.add_column("value", no_wrap=True)
    table.add_row("K2", "123456789012345678901234")
    print_table(console, table)
    cells = [_cells(line) for line in console.export_text().splitlines()
             if line.strip().startswith("│")]
    assert [c[0] for c in cells if c[0]] == ["K2"]
    assert "".join(c[1] for c in cells) == "123456789012345678901234"


def test_into_a_pipe_the_console_is_160_columns_and_wider_tables_are_split(capsys):
    """Into a pipe (pytest captures stdout) a command's console is PIPE_WIDTH = 160 columns;
    a table of 20 number columns (about 250 wide) prints as two tables, every column kept."""
    console = _console.console()
    assert not console.is_terminal and console.width == _console.PIPE_WIDTH == 160
    table = _numbers_table(20)
    print_table(console, table)
    narrow = capsys.readouterr().out
    wide = Console(width=WIDE, record=True, file=StringIO())
    wide.print(table)
    assert narrow.count("(columns 1") == 2
    _assert_same_tables(narrow, wide.export_text(), 160)
