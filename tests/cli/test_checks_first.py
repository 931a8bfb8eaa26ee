"""Every option and the output folder are checked before any work and before the first file
(issue 19, item 2): a refused option leaves --out without files."""

from __future__ import annotations

import errno
import socket
import tempfile
from pathlib import Path
from typing import Any

import pytest

from linkwork.cli import main
from linkwork.cli._args import output_dir
from linkwork.studies import balance as study_balance
from linkwork.studies import planar as study_planar
from linkwork.studies import swashplate as study_swashplate

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"


def _files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob("*")) if folder.exists() else []


def _no_work(*args: Any, **kwargs: Any) -> Any:
    raise AssertionError("the study ran although an option was refused")


def test_tolerance_study_without_tolerances_writes_nothing(tmp_path, capsys):
    """The issue's case: `reactions fourbar_paper001.toml --tolerance-study 5` refused after
    reactions.csv/.json, reactions_peaks.json and the plot were written."""
    out = tmp_path / "X"
    assert main(["reactions", str(FOURBAR), "--tolerance-study", "5", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "--tolerance-study" in err and "[[spatial.tolerance]]" in err
    assert err.count("\n") == 1
    assert _files(out) == []


def test_balance_bad_angles_are_refused_before_the_output_folder(tmp_path, capsys,
                                                                 monkeypatch):
    monkeypatch.setattr(study_balance, "run", _no_work)
    out = tmp_path / "X"
    assert main(["balance", str(FOURBAR), "--angles", "0,x", "--out", str(out)]) == 2
    assert "--angles" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("option,args", [
    ("--scheme", ["--scheme", "7"]),
    ("--objective", ["--objective", "mass"]),
    ("--candidates", ["--candidates", "0"]),
    ("--delta", ["--delta", "8 kg"]),
    ("--map", ["--map", "alpha,nope"]),
])
def test_synthesis_options_are_refused_before_the_output_folder(option, args, tmp_path, capsys,
                                                                monkeypatch):
    monkeypatch.setattr(study_swashplate, "synthesize", _no_work)
    out = tmp_path / "X"
    rc = main(["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", *args,
               "--out", str(out)])
    assert rc == 2
    assert option in capsys.readouterr().err
    assert not out.exists()


def test_output_folder_that_cannot_be_written_is_refused_before_the_study(
        tmp_path, capsys, monkeypatch):
    """A read-only folder (simulated: the tests may run as root, for whom permissions do not
    apply) is refused naming --out before the analysis runs, not at its first file."""
    def read_only(*args: Any, **kwargs: Any) -> Any:
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(tempfile, "TemporaryFile", read_only)
    monkeypatch.setattr(study_planar, "analyze", _no_work)
    out = tmp_path / "X"
    assert main(["analyze", str(FOURBAR), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == (f"linkwork: error: --out = {out} is invalid: cannot be written "
                           "into (Read-only file system)")


def test_output_folder_probe_leaves_nothing(tmp_path):
    out = output_dir(tmp_path / "new" / "folder")
    assert out.is_dir() and _files(out) == []


def _closed_port() -> int:
    """A local TCP port with nothing listening (bound, then released)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.parametrize("cmd", [
    ["reactions", str(ROOT / "examples" / "loom_fourbar_spatial.toml"), "--no-plots",
     "--tolerance-study", "10"],
    ["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", "--candidates", "256"],
])
def test_unreachable_scheduler_is_refused_before_any_work(cmd, tmp_path, capsys, monkeypatch):
    """A well-formed address nobody answers at was found by dask after 30 s, after
    reactions.csv/.json and the plots were written."""
    monkeypatch.setattr(study_swashplate, "synthesize", _no_work)
    address = f"tcp://127.0.0.1:{_closed_port()}"
    out = tmp_path / "X"
    assert main([*cmd, "--scheduler", address, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkwork: error: --scheduler = {address} is invalid: cannot be "
                          "reached (") and err.count("\n") == 1
    assert not out.exists()
