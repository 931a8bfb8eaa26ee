"""Stale outputs (issue 19, item 2): a command records what it wrote in the output folder
(linkwork-run.json); its next run there removes the files of its previous run that it did not
write again, saying so in one line, and never touches a file linkwork did not write."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from _cli_files import run_cli

from linkwork.cli import main
from linkwork.cli import reactions as cli_reactions
from linkwork.cli._args import MANIFEST

ROOT = Path(__file__).resolve().parents[2]
SWASH = ROOT / "examples" / "swashplate_4a.toml"
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"
LOOM = ROOT / "examples" / "loom_fourbar_spatial.toml"
FORCES = ["forces.csv", "forces.json", "forces.png"]


def _without_load(tmp_path: Path) -> Path:
    """swashplate_4a.toml without its [load] section: the analysis writes no forces.*"""
    lines = SWASH.read_text().splitlines(keepends=True)
    start = next(i for i, s in enumerate(lines) if s.startswith("[load]"))
    end = next(i for i in range(start + 1, len(lines)) if lines[i].startswith("["))
    p = tmp_path / "swashplate_no_load.toml"
    p.write_text("".join(lines[:start] + lines[end:]))
    return p


def _names(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir()}


def _recorded(folder: Path) -> dict[str, set[str]]:
    runs = json.loads((folder / MANIFEST).read_text())["runs"]
    return {cmd: {f["name"] for f in run["files"]} for cmd, run in runs.items()}


def test_a_run_writing_fewer_files_removes_the_stale_ones_and_keeps_the_users(tmp_path,
                                                                             capsys):
    out = tmp_path / "out"
    args = ["swashplate", "analyze", "--out", str(out)]
    assert run_cli([*args[:2], str(SWASH), *args[2:]], capsys)[0] == 0
    first = _names(out)
    assert set(FORCES) <= first and MANIFEST in first
    (out / "notes.txt").write_text("my own notes")
    (out / "forces_by_hand.csv").write_text("mine too")
    code, stdout, _ = run_cli([*args[:2], str(_without_load(tmp_path)), *args[2:]], capsys)
    assert code == 0
    assert _names(out) == (first - set(FORCES)) | {"notes.txt", "forces_by_hand.csv"}
    assert (out / "notes.txt").read_text() == "my own notes"
    notice = [ln for ln in stdout.splitlines() if ln.startswith("removed")]
    assert notice == [f"removed 3 stale files of the previous 'analyze' run in {out} "
                      "(not written by this run): " + ", ".join(FORCES)]
    assert _recorded(out) == {"analyze": first - set(FORCES) - {MANIFEST}}
    # the same run again: nothing stale, no notice
    code, stdout, _ = run_cli([*args[:2], str(_without_load(tmp_path)), *args[2:]], capsys)
    assert code == 0 and "removed" not in stdout


def test_the_first_run_prints_what_it_always_printed(tmp_path, capsys):
    """No notice without an earlier run: the printed lines are those of before (the record is
    the one new file)."""
    out = tmp_path / "out"
    code, stdout, err = run_cli(["swashplate", "analyze", str(SWASH), "--out", str(out)],
                                capsys)
    assert code == 0 and err == ""
    assert " ".join(stdout.split()).endswith(  # Rich folds the line at the console width
        f"written: {out}/cycle.csv, cycle.json, characteristics.json, kinematics.png, "
        "forces.csv, forces.json, forces.png")
    assert "removed" not in stdout
    assert _recorded(out)["analyze"] == _names(out) - {MANIFEST}


def test_swashplate_analyze_and_analyze_are_one_command_for_the_record(tmp_path, capsys):
    """`linkwork analyze FILE` runs the same analysis of a swashplate file as `linkwork
    swashplate analyze FILE`: either one finds the other's stale files."""
    out = tmp_path / "out"
    assert run_cli(["analyze", str(SWASH), "--out", str(out)], capsys)[0] == 0
    code, stdout, _ = run_cli(["swashplate", "analyze", str(_without_load(tmp_path)),
                               "--out", str(out)], capsys)
    assert code == 0 and "forces.csv, forces.json, forces.png" in stdout
    assert not any((out / f).exists() for f in FORCES)


def test_other_commands_files_in_the_same_folder_stay(tmp_path, capsys):
    """analyze, then reactions into the same (e.g. the default) folder: reactions removes none
    of the files of analyze, and each command's record lists its own."""
    out = tmp_path / "out"
    assert run_cli(["analyze", str(FOURBAR), "--out", str(out)], capsys)[0] == 0
    analyzed = _names(out) - {MANIFEST}
    code, stdout, _ = run_cli(["reactions", str(FOURBAR), "--no-plots", "--out", str(out)],
                              capsys)
    assert code == 0 and "removed" not in stdout
    assert analyzed < _names(out)
    rec = _recorded(out)
    assert rec["analyze"] == analyzed
    assert rec["reactions"] == {"reactions.csv", "reactions.json", "reactions_peaks.json"}


def test_a_tolerance_study_and_plots_left_out_later_are_removed(tmp_path, capsys):
    out = tmp_path / "out"
    assert run_cli(["reactions", str(LOOM), "--tolerance-study", "20", "--out", str(out)],
                   capsys)[0] == 0
    first = _names(out)
    code, stdout, _ = run_cli(["reactions", str(LOOM), "--no-plots", "--out", str(out)], capsys)
    assert code == 0
    stale = sorted(n for n in first if n.startswith("tolerance") or n.endswith(".png"))
    assert "tolerance.json" in stale and "reactions_bending.png" in stale
    assert _names(out) == first - set(stale)
    notice = [ln for ln in stdout.splitlines() if ln.startswith("removed")]
    assert len(notice) == 1
    assert sorted(notice[0].split("(not written by this run): ")[1].split(", ")) == stale


def test_a_file_changed_since_linkwork_wrote_it_is_not_removed(tmp_path, capsys):
    out = tmp_path / "out"
    assert run_cli(["swashplate", "analyze", str(SWASH), "--out", str(out)], capsys)[0] == 0
    (out / "forces.csv").write_text("edited by hand\n")
    code, stdout, _ = run_cli(["swashplate", "analyze", str(_without_load(tmp_path)),
                               "--out", str(out)], capsys)
    assert code == 0
    assert (out / "forces.csv").read_text() == "edited by hand\n"
    assert not (out / "forces.json").exists() and "forces.json, forces.png" in stdout
    assert "forces.csv" not in _recorded(out)["analyze"]  # the user's now


def test_an_interrupted_run_removes_nothing_and_keeps_the_record(tmp_path, capsys,
                                                                monkeypatch):
    out = tmp_path / "out"
    assert run_cli(["reactions", str(FOURBAR), "--out", str(out)], capsys)[0] == 0
    first = _names(out)
    real = cli_reactions.write_json

    def interrupted(path: Any, data: Any) -> Any:
        raise KeyboardInterrupt  # after reactions.csv and reactions.json

    monkeypatch.setattr(cli_reactions, "write_json", interrupted)
    assert main(["reactions", str(FOURBAR), "--no-plots", "--out", str(out)]) == 130
    assert _names(out) == first  # nothing removed
    assert _recorded(out)["reactions"] == first - {MANIFEST}
    monkeypatch.setattr(cli_reactions, "write_json", real)
    assert run_cli(["reactions", str(FOURBAR), "--no-plots", "--out", str(out)],
                   capsys)[0] == 0
    assert _names(out) == first - {"reactions_bending.png"}


def _hostile(tmp_path: Path) -> str:
    """A record naming files out of the folder, with their true size and mtime."""
    files = []
    for name, path in (("../outside.txt", tmp_path / "outside.txt"),
                       (str(tmp_path / "outside.txt"), tmp_path / "outside.txt")):
        st = path.stat()
        files.append({"name": name, "bytes": st.st_size, "mtime_ns": st.st_mtime_ns})
    return json.dumps({"runs": {"analyze": {"files": files}}})


@pytest.mark.parametrize("record", [
    "not json",
    json.dumps({"runs": {"analyze": {"files": "forces.csv"}}}),
    "hostile",
])
def test_a_damaged_or_hostile_record_removes_nothing(record, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "outside.txt").write_text("keep")
    (out / "forces.csv").write_text("keep")
    (out / MANIFEST).write_text(_hostile(tmp_path) if record == "hostile" else record)
    code, stdout, _ = run_cli(["swashplate", "analyze", str(_without_load(tmp_path)),
                               "--out", str(out)], capsys)
    assert code == 0 and "removed" not in stdout
    assert (tmp_path / "outside.txt").read_text() == "keep"
    assert (out / "forces.csv").read_text() == "keep"
    assert "forces.csv" not in _recorded(out)["analyze"]
