"""Ctrl-C during a command: one line on stderr, exit code 130, no traceback, no partial file
(issue 19, item 2). The interrupt is simulated in-process: a study (or the CSV writer) raises
KeyboardInterrupt, as Python does on SIGINT, and linkwork.cli.main is called."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import linkwork.results as results
from linkwork.cli import main
from linkwork.studies import planar as study_planar
from linkwork.studies import reactions as study_reactions
from linkwork.studies import swashplate as study_swashplate

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"


def _ctrl_c(*args: Any, **kwargs: Any) -> Any:
    raise KeyboardInterrupt


def _one_line(err: str, doing: str) -> None:
    assert err.count("\n") == 1, err
    assert err.startswith("linkwork: interrupted") and f"'{doing}'" in err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err


def test_interrupted_analysis_prints_one_line_and_exits_130(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(study_planar, "analyze", _ctrl_c)
    out = tmp_path / "o"
    assert main(["analyze", str(FOURBAR), "--out", str(out)]) == 130
    cap = capsys.readouterr()
    _one_line(cap.err, f"analyze {FOURBAR}")
    assert not list(out.glob("*"))  # interrupted before any output


def test_interrupted_reactions_and_synthesis_name_their_command(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(study_reactions, "run", _ctrl_c)
    monkeypatch.setattr(study_swashplate, "synthesize", _ctrl_c)
    assert main(["reactions", str(FOURBAR), "--out", str(tmp_path / "r")]) == 130
    _one_line(capsys.readouterr().err, f"reactions {FOURBAR}")
    assert main(["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm",
                 "--out", str(tmp_path / "s")]) == 130
    _one_line(capsys.readouterr().err, "swashplate synthesize")


def test_interrupt_while_writing_leaves_no_partial_file(tmp_path, capsys, monkeypatch):
    """Ctrl-C in the middle of writing planar_dynamics.csv (the second file): the first file is
    complete, the second neither present nor half-written, no temporary file remains."""
    calls = {"files": 0}
    real_write = results.write_csv
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 50)  # 361 rows: 8 blocks

    def write_csv(path: Any, columns: Any) -> Any:
        calls["files"] += 1

        def progress(done: int, total: int) -> None:
            if calls["files"] == 2 and done >= 200:  # 4 blocks of the second file written
                raise KeyboardInterrupt

        return real_write(path, columns, progress=progress)

    monkeypatch.setattr("linkwork.cli._planar.write_csv", write_csv)
    out = tmp_path / "o"
    assert main(["analyze", str(FOURBAR), "--out", str(out)]) == 130
    _one_line(capsys.readouterr().err, f"analyze {FOURBAR}")
    names = sorted(p.name for p in out.iterdir())
    assert "planar_dynamics.csv" not in names and not [n for n in names if ".part" in n]
    kin = (out / "planar_kinematics.csv").read_text().splitlines()
    assert len(kin) == 1 + 361 and kin[-1].count(",") == kin[0].count(",")  # complete


def test_interrupted_examples_copy_leaves_no_partial_example(tmp_path, capsys, monkeypatch):
    real, calls = shutil.copyfile, {"n": 0}

    def copy_then_interrupt(src: Any, dst: Any) -> Any:
        calls["n"] += 1
        if calls["n"] == 2:  # the second example: half of it on disk, then Ctrl-C
            Path(dst).write_bytes(Path(src).read_bytes()[:100])
            raise KeyboardInterrupt
        return real(src, dst)

    monkeypatch.setattr(shutil, "copyfile", copy_then_interrupt)
    dest = tmp_path / "ex"
    assert main(["examples", "--copy", str(dest)]) == 130
    _one_line(capsys.readouterr().err, "examples")
    (first,) = dest.iterdir()
    assert first.read_bytes() == (ROOT / "examples" / first.name).read_bytes()


def test_ctrl_c_while_ffmpeg_writes_the_mp4(tmp_path):
    """Ctrl-C in a terminal reaches ffmpeg too: it stops (exit 255) and matplotlib's writer,
    cleaning up, raises its CalledProcessError over the KeyboardInterrupt. The command still
    says it was interrupted (one line, exit 130), not that ffmpeg failed, and leaves no
    partial MP4. Run as a process: a stand-in ffmpeg sends SIGINT to its parent, as the
    terminal does to the whole process group."""
    fake = tmp_path / "bin"
    fake.mkdir()
    (fake / "ffmpeg").write_text("#!/bin/sh\nkill -INT $PPID\nsleep 1\nexit 255\n")
    (fake / "ffmpeg").chmod(0o755)
    out = tmp_path / "out"
    env = dict(os.environ, PATH=f"{fake}{os.pathsep}{os.environ['PATH']}")
    run = subprocess.run([sys.executable, "-m", "linkwork", "report", str(FOURBAR), "-o",
                          str(out), "--animate", "--frames", "3"],
                         capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 130, run.stderr
    _one_line(run.stderr, f"report {FOURBAR}")
    assert "ffmpeg failed" not in run.stdout
    assert sorted(p.name for p in out.iterdir()) == [
        "fourbar_paper001.gif", "fourbar_paper001.html", "linkwork-run.json"]
