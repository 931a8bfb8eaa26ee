"""``linkwork report``: one HTML file per run, GIF/MP4 on request, bad input as one line."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from linkwork.cli import main

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"


def test_report_writes_one_html_file(tmp_path, capsys):
    assert main(["report", str(FOURBAR), "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    html = tmp_path / "fourbar_paper001.html"
    assert html.is_file() and "wrote" in out and "kB" in out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fourbar_paper001.html",
                                                         "linkwork-run.json"]


def test_report_with_paths_centres_and_animation(tmp_path):
    args = ["report", str(FOURBAR), "-o", str(tmp_path), "--animate", "--frames", "3",
            "--path", "coupler.P", "--path", "coupler:100,-40", "--centres"]
    assert main(args) == 0
    assert (tmp_path / "fourbar_paper001.gif").stat().st_size > 0
    assert (tmp_path / "fourbar_paper001.mp4").is_file() == bool(shutil.which("ffmpeg"))
    html = (tmp_path / "fourbar_paper001.html").read_text()
    assert "path coupler.(100, -40) mm" in html and "I13" in html



def test_an_ffmpeg_that_fails_costs_only_the_mp4(tmp_path, capsys, monkeypatch):
    """An ffmpeg that fails (here a stand-in that prints one line and exits 1, as a build
    without libx264 does): the HTML and the GIF are written, one note says what ffmpeg said
    and that there is no MP4, exit 0, no partial file left (it was a 60-line traceback and
    exit code 1, matplotlib's 'MovieWriter stderr' on the terminal)."""
    fake = tmp_path / "bin"
    fake.mkdir()
    (fake / "ffmpeg").write_text("#!/bin/sh\necho 'Unknown encoder libx264' >&2\nexit 1\n")
    (fake / "ffmpeg").chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake}{os.pathsep}{os.environ['PATH']}")
    out = tmp_path / "out"
    assert main(["report", str(FOURBAR), "-o", str(out), "--animate", "--frames", "3"]) == 0
    io = capsys.readouterr()
    assert io.err.count("\n") <= 1 and "Traceback" not in io.err and "MovieWriter" not in io.err
    assert ("note: ffmpeg failed writing fourbar_paper001.mp4 (Unknown encoder libx264): no "
            "MP4 (the GIF is written)") in io.out
    assert sorted(p.name for p in out.iterdir()) == [
        "fourbar_paper001.gif", "fourbar_paper001.html", "linkwork-run.json"]

@pytest.mark.parametrize(("args", "message"), [
    (["--path", "nobody.P"], "--path = nobody.P is invalid: no moving body"),
    (["--path", "coupler.Q"], "no point 'Q' on coupler"),
    (["--path", "coupler:1,x"], "must be BODY:X,Y"),
    (["--frames", "0"], "--frames = 0 is invalid: must be 1 to 180"),
    # a path point beyond double precision or not a number: was a numerical overflow or
    # 'point of coupler = (nan, 0.0) is invalid', neither naming --path
    (["--path", "coupler:1e308,1e308"], "--path = coupler:1e308,1e308 is invalid: X, Y must "
     "be finite and within +-1e+07 mm"),
    (["--path", "coupler:nan,0"], "--path = coupler:nan,0 is invalid: X, Y must be finite"),
])
def test_bad_options_are_one_line_and_write_nothing(tmp_path, capsys, args, message):
    assert main(["report", str(FOURBAR), "-o", str(tmp_path), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not list(tmp_path.glob("*.html"))


def test_a_file_that_fails_validation_writes_no_report(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(FOURBAR.read_text().replace('length = "100 mm"', 'length = "-100 mm"'))
    out = tmp_path / "out"
    assert main(["report", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkwork: error: ") and err.count("\n") == 1
    assert "body.0.length" in err
    assert not list(out.glob("*.html")) if out.exists() else True


def test_a_load_that_fails_while_analysing_names_the_file(tmp_path, capsys):
    """The crank press's drawing diagram with outside = "error" is left by the analysis: the
    report names the file and the diagram's key as analyze does (it named the key only),
    one line, no report written."""
    text = (ROOT / "examples" / "crank_press.toml").read_text()
    bad = tmp_path / "press.toml"
    bad.write_text(text.replace('when = "decreasing"', 'when = "decreasing"\noutside = "error"'))
    out = tmp_path / "out"
    assert main(["report", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkwork: error: {bad}: load.0.diagram.table: ") and \
        err.count("\n") == 1, err
    assert not list(out.glob("*.html"))


def test_partly_assembled_mechanism_is_reported_with_a_note(tmp_path, capsys):
    path = ROOT / "tests" / "data" / "partial" / "fourbar_partial.toml"
    assert main(["report", str(path), "-o", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "cannot be assembled at 157 of 361 positions: [102, 258 deg]" in " ".join(out.split())
