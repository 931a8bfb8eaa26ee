"""Sizes a file can set are refused above a stated limit, before any work: ``[analysis] n`` of a
planar file and the samples of a sine press's duty schedule (issue 19, bounded work)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from _cli_files import run_cli

from linkwork import io
from linkwork.errors import FileFormatError
from linkwork.io.planar import MAX_POSITIONS, MAX_SPATIAL_POSITIONS
from linkwork.io.sine_press import MAX_SCHEDULE_SAMPLES

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _with(tmp_path: Path, example: str, pattern: str, line: str) -> Path:
    text = (EXAMPLES / example).read_text()
    new, count = re.subn(pattern, line, text, count=1, flags=re.MULTILINE)
    assert count == 1
    p = tmp_path / example
    p.write_text(new)
    return p


def test_analysis_n_above_the_limit_names_key_value_and_limit(tmp_path):
    p = _with(tmp_path, "fourbar_paper001.toml", r"^n = \d+", "n = 10000000")
    with pytest.raises(FileFormatError) as exc:
        io.load(p)
    msg = str(exc.value)
    assert exc.value.key == "analysis.n"
    assert "10000000" in msg and f"at most {MAX_POSITIONS} positions" in msg
    assert "GB" in msg  # the memory it stands for


def test_analysis_n_at_the_limit_is_accepted(tmp_path):
    p = _with(tmp_path, "loom_sixbar.toml", r"^n = \d+", f"n = {MAX_POSITIONS}")
    assert len(io.load(p).positions()) == MAX_POSITIONS  # validation only: no study here


def test_analyze_refuses_analysis_n_in_one_line_before_any_output(tmp_path, capsys):
    p = _with(tmp_path, "fourbar_paper001.toml", r"^n = \d+", f"n = {MAX_POSITIONS + 1}")
    out = tmp_path / "out"
    code, _, err = run_cli(["analyze", str(p), "--out", str(out)], capsys)
    assert code == 2
    assert err.count("\n") == 1 and "analysis.n" in err
    assert f"got {MAX_POSITIONS + 1}" in err and f"at most {MAX_POSITIONS}" in err
    assert not out.exists()


def test_sine_press_schedule_above_the_limit(tmp_path, capsys):
    # 5 + 3 + 2 + 2 revolutions of the example; the first entry made long enough to pass 10^6
    # samples at 360 per revolution: 2800 + 7 revolutions -> 2807 * 360 + 4 samples
    p = _with(tmp_path, "sine_press.toml", r"^revolutions = 5$", "revolutions = 2800")
    with pytest.raises(FileFormatError) as exc:
        io.load(p)
    msg = str(exc.value)
    assert exc.value.key == "schedule"
    assert "2807 revolutions x 360" in msg and f"got {2807 * 360 + 4}" in msg
    assert f"at most {MAX_SCHEDULE_SAMPLES} samples" in msg
    code, _, err = run_cli(["analyze", str(p), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and err.count("\n") == 1 and "schedule" in err


def test_sine_press_schedule_at_the_limit_is_accepted(tmp_path):
    # the example's 12 revolutions in 4 entries at 83333 samples per revolution:
    # 12 * 83333 + 4 = 1000000 samples, exactly the limit; one more per revolution is refused
    p = _with(tmp_path, "sine_press.toml", r"^samples_per_revolution = \d+",
              "samples_per_revolution = 83333")
    doc = io.load(p)
    assert sum(c for _, c, _ in doc.segments()) * 83333 + len(doc.segments()) == (
        MAX_SCHEDULE_SAMPLES)
    p.write_text(p.read_text().replace("83333", "83334"))
    with pytest.raises(FileFormatError, match="got 1000012"):
        io.load(p)


def test_reactions_positions_above_the_limit(tmp_path, capsys):
    # [spatial] positions itself, when the file is read
    p = _with(tmp_path, "loom_fourbar_spatial.toml", r"^\[spatial\]$",
              f"[spatial]\npositions = {MAX_SPATIAL_POSITIONS + 1}")
    with pytest.raises(FileFormatError) as exc:
        io.load(p)
    assert exc.value.key == "spatial.positions"
    assert f"at most {MAX_SPATIAL_POSITIONS} positions" in str(exc.value)
    assert f"(got {MAX_SPATIAL_POSITIONS + 1})" in str(exc.value)
    # the [analysis] positions that reactions would use without [spatial] positions: the file
    # is fine for analyze, refused by reactions before any output
    q = _with(tmp_path, "loom_fourbar_spatial.toml", r"^n = \d+",
              f"n = {MAX_SPATIAL_POSITIONS + 1}")
    out = tmp_path / "out"
    code, stdout, err = run_cli(["reactions", str(q), "--out", str(out)], capsys)
    assert code == 2 and stdout == "" and err.count("\n") == 1
    assert "analysis.n" in err and f"(got {MAX_SPATIAL_POSITIONS + 1})" in err
    assert "[spatial] positions" in err and not out.exists()


def test_reactions_positions_at_the_limit_are_accepted(tmp_path):
    p = _with(tmp_path, "loom_fourbar_spatial.toml", r"^\[spatial\]$",
              f"[spatial]\npositions = {MAX_SPATIAL_POSITIONS}")
    assert io.load(p).spatial.positions == MAX_SPATIAL_POSITIONS
    q = _with(tmp_path, "loom_fourbar_spatial.toml", r"^n = \d+",
              f"n = {MAX_SPATIAL_POSITIONS}")
    io.load(q).check_spatial_positions(q)  # no error
