"""``linkwork analyze`` of a long planar cycle: above MAX_WHOLE_POSITIONS positions of one driver
the cycle is solved chunk by chunk, its CSV files streamed, its JSON a summary without
per-position arrays; several drivers (held whole) and the other whole-cycle commands refuse such
an ``[analysis] n`` in one line before any output.

Reference: the whole-cycle path of the same command (``studies.planar.analyze``, every position
held at once, a different code path) on the same file, with the chunk threshold lowered so that
the bundled examples take the long path. Tolerance: 1e-9 relative to each column's largest value
(the means, losses and work are trapezoid sums continued from chunk to chunk: round-off).
"""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np
import pytest
from _cli_files import run_cli

import linkwork.cli._planar as cli_planar
from linkwork import io
from linkwork.errors import FileFormatError, ParameterError
from linkwork.io.planar import MAX_POSITIONS, MAX_WHOLE_POSITIONS
from linkwork.outputs import TEMP_MARK
from linkwork.results import CsvRows
from linkwork.studies import planar as study_planar

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
ROOT_DATA = Path(__file__).resolve().parents[1] / "data"


def _with_n(tmp_path: Path, example: str, n: int) -> Path:
    text, count = re.subn(r"^n = \d+", f"n = {n}", (EXAMPLES / example).read_text(), count=1,
                          flags=re.MULTILINE)
    assert count == 1
    p = tmp_path / example
    p.write_text(text)
    return p


def _columns(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as fh:
        rows = list(csv.reader(fh))
    return {h: np.array([float(r[i]) if r[i] else np.nan for r in rows[1:]])
            for i, h in enumerate(rows[0])}


def _same_numbers(a: object, b: object, where: str = "") -> None:
    """JSON values equal, numbers to 1e-9 of their size (1e-9 absolute near zero)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), where
        for k in a:
            _same_numbers(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _same_numbers(x, y, f"{where}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert b == pytest.approx(a, rel=1e-9, abs=1e-9), where
    else:
        assert a == b, where


@pytest.mark.parametrize("example", ["crank_press.toml", "fourbar_paper001.toml",
                                     "sine_press_planar.toml"])
def test_long_path_gives_the_whole_cycles_files(example, tmp_path, capsys, monkeypatch):
    """crank_press (friction, springs, a drawing-force diagram, a linear-load window),
    the paper-001 four-bar and the sine press (a slot: a couple column) in chunks of 100
    positions: every CSV column and every JSON number but the per-position arrays equal those
    of the whole cycle; a couple column the long path adds (decided by the joint's kind, the
    same in every chunk) is one the whole cycle leaves out because it is zero throughout."""
    whole, long = tmp_path / "whole", tmp_path / "long"
    src = EXAMPLES / example
    code, text_whole, _ = run_cli(["analyze", str(src), "--out", str(whole)], capsys)
    assert code == 0
    monkeypatch.setattr(cli_planar, "MAX_WHOLE_POSITIONS", 100)
    monkeypatch.setattr(study_planar, "CHUNK_POSITIONS", 100)
    code, text_long, _ = run_cli(["analyze", str(src), "--out", str(long)], capsys)
    assert code == 0
    assert "a long cycle" in text_long and "a long cycle" not in text_whole
    for name in ("planar_kinematics.csv", "planar_dynamics.csv"):
        a, b = _columns(whole / name), _columns(long / name)
        assert set(a) <= set(b), name
        for k in set(b) - set(a):
            assert np.all(b[k] == 0.0), k  # by the joint's kind; zero in this file
        for k, col in a.items():
            size = float(np.nanmax(np.abs(col))) if np.any(np.isfinite(col)) else 1.0
            np.testing.assert_allclose(b[k], col, rtol=0, atol=1e-9 * max(size, 1e-300),
                                       err_msg=k)
            assert np.array_equal(np.isnan(b[k]), np.isnan(col)), k
    ja = json.loads((whole / "planar.json").read_text())
    jb = json.loads((long / "planar.json").read_text())
    n = len(ja["columns"]["phi1"])
    assert "columns" not in jb and jb["n"] == n and jb["chunk"] == 100
    assert (jb["first"], jb["last"]) == (ja["columns"]["phi1"][0], ja["columns"]["phi1"][-1])
    for name in ("planar_kinematics.csv", "planar_dynamics.csv"):  # heads "name [unit]"
        assert [f"{k} [{jb['units'][k]}]" for k in jb["columns_in"][name]] == list(
            _columns(long / name))
    for key in ja:
        if key not in ("columns", "units"):
            _same_numbers(ja[key], jb[key], key)
    assert {k: u for k, u in jb["units"].items() if k in ja["units"]} == ja["units"]
    # the tables printed: the same numbers (the titles say how many positions either way)
    def tables(text: str) -> list[str]:
        return [ln for ln in text.splitlines() if ln.startswith("│")]
    assert tables(text_long) == tables(text_whole)
    # the plots, drawn at PLOT_POSITIONS (here all the positions)
    for png in ("planar_skeleton.png", "planar_driving_torque.png", "planar_reactions.png",
                "planar_shaking.png"):
        assert (long / png).stat().st_size > 0


def _no_json_array_longer_than(value: object, n: int) -> None:
    if isinstance(value, dict):
        for v in value.values():
            _no_json_array_longer_than(v, n)
    elif isinstance(value, list):
        assert len(value) < n
        for v in value:
            _no_json_array_longer_than(v, n)


def test_above_the_threshold_the_long_path_runs(tmp_path, capsys):
    """At MAX_WHOLE_POSITIONS + 1 positions (no patching) the paper-001 four-bar goes chunk by
    chunk: every position a CSV row, a JSON without per-position arrays, extremes equal to the
    chunked study's own (and the dead centres where the rocker's rate changes sign)."""
    n = MAX_WHOLE_POSITIONS + 1
    p = _with_n(tmp_path, "fourbar_paper001.toml", n)
    out = tmp_path / "out"
    code, _, err = run_cli(["analyze", str(p), "--out", str(out)], capsys)
    assert code == 0, err
    data = json.loads((out / "planar.json").read_text())
    assert data["n"] == n and "columns" not in data
    _no_json_array_longer_than(data, 100)
    with (out / "planar_dynamics.csv").open() as fh:
        assert sum(1 for _ in fh) == n + 1
    kin = _columns(out / "planar_kinematics.csv")
    assert kin["phi1 [rad]"].size == n
    np.testing.assert_array_equal(kin["phi1 [rad]"], io.load(p).positions())
    dyn = _columns(out / "planar_dynamics.csv")
    q = dyn["Q [N*m]"]
    peaks = {pk["name"]: pk for pk in data["peaks"]}
    assert peaks["Q max"]["value"] == float(q.max())
    assert peaks["Q max"]["phi1"] == float(kin["phi1 [rad]"][int(np.argmax(q))])
    for d in data["dead_centres"]:  # the rocker's angular rate changes sign there
        i = int(np.searchsorted(kin["phi1 [rad]"], d["phi1"]))
        w = kin["rocker.omega [rad/s]"]
        assert w[i - 1] * w[i + 1] <= 0.0
    assert not list(out.glob(f"*{TEMP_MARK}*"))


def test_interrupt_leaves_no_csv(tmp_path, capsys, monkeypatch):
    """Ctrl-C in the middle of the streamed rows: exit 130, neither CSV file nor a temporary
    file left."""
    monkeypatch.setattr(cli_planar, "MAX_WHOLE_POSITIONS", 100)
    monkeypatch.setattr(study_planar, "CHUNK_POSITIONS", 100)
    calls = [0]
    real = CsvRows.append

    def append(self, columns, progress=None):
        calls[0] += 1
        if calls[0] == 5:  # the third chunk's kinematic rows
            raise KeyboardInterrupt
        real(self, columns, progress)

    monkeypatch.setattr(CsvRows, "append", append)
    out = tmp_path / "out"
    code, _, err = run_cli(["analyze", str(EXAMPLES / "fourbar_paper001.toml"), "--out",
                            str(out)], capsys)
    assert code == 130 and err.count("\n") == 1
    assert not list(out.glob("planar*")) and not list(out.glob(".*"))


def test_analysis_n_at_the_new_limit_loads_and_above_is_refused(tmp_path):
    p = _with_n(tmp_path, "fourbar_paper001.toml", MAX_POSITIONS)
    assert io.load(p).analysis.n == MAX_POSITIONS
    p = _with_n(tmp_path, "fourbar_paper001.toml", MAX_POSITIONS + 1)
    with pytest.raises(FileFormatError, match=rf"analysis\.n.*at most {MAX_POSITIONS}.*GB"):
        io.load(p)


@pytest.mark.parametrize("command", [["analyze"], ["balance"], ["report"]])
def test_whole_cycle_commands_refuse_a_long_cycle_before_any_output(command, tmp_path, capsys):
    """Several drivers (excavator) are held whole by analyze and balance, every file by the
    report: above MAX_WHOLE_POSITIONS one line naming the file, analysis.n, the value and the
    limit, exit 2, no output folder."""
    p = _with_n(tmp_path, "excavator_boom.toml", MAX_WHOLE_POSITIONS + 1)
    out = tmp_path / "out"
    code, _, err = run_cli([*command, str(p), "--out", str(out)], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert "excavator_boom.toml" in err and "analysis.n" in err
    assert f"at most {MAX_WHOLE_POSITIONS}" in err and f"got {MAX_WHOLE_POSITIONS + 1}" in err
    assert not out.exists()


def test_report_refuses_a_long_cycle_of_one_driver(tmp_path, capsys):
    p = _with_n(tmp_path, "fourbar_paper001.toml", MAX_WHOLE_POSITIONS + 1)
    code, _, err = run_cli(["report", str(p), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and "analysis.n" in err and "`linkwork report`" in err


def test_the_whole_cycle_study_refuses_a_long_cycle(tmp_path):
    """The Python API: analyze() holds the whole cycle and names analyze_chunked()."""
    doc = io.load(_with_n(tmp_path, "fourbar_paper001.toml", MAX_WHOLE_POSITIONS + 1))
    with pytest.raises(ParameterError, match="analyze_chunked") as exc:
        study_planar.analyze(doc)
    assert exc.value.parameter == "analysis.n"


def test_table_positions_outside_the_range_are_refused_before_the_cycle(tmp_path, capsys,
                                                                        monkeypatch):
    """--angles where the mechanism does not assemble: refused before any chunk is solved or
    streamed (a long cycle takes minutes), one line, no CSV."""
    monkeypatch.setattr(cli_planar, "MAX_WHOLE_POSITIONS", 10)  # the file has 41
    solved = []
    real = study_planar._solve

    def solve(doc, mech, phi, *a):
        solved.append(np.size(phi))
        return real(doc, mech, phi, *a)

    monkeypatch.setattr(study_planar, "_solve", solve)
    out = tmp_path / "out"
    code, _, err = run_cli(["analyze", str(ROOT_DATA / "slider_driven_crank.toml"), "--angles",
                            "100", "--out", str(out)], capsys)
    assert code == 2 and err.count("\n") == 1 and "--angles" in err, err
    assert solved == [1]  # the table alone
    assert not list(out.glob("planar*"))
