"""The installed package, as a pip user gets it: build the wheel, install it into a fresh venv
(its dependencies from the package index; pip's cache keeps this quick) and run the README's
first commands in an empty folder, outside the checkout."""

import os
import shlex
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _readme_commands() -> list[list[str]]:
    """The `linkwork ...` lines of the README's command-line section, as argument lists."""
    text = (ROOT / "README.md").read_text().split("## Command line", 1)[1].split("\n## ", 1)[0]
    return [shlex.split(line.strip().split("#", 1)[0])[1:] for line in text.splitlines()
            if line.strip().startswith("linkwork ")]


def _run(cmd: list[str | Path], cwd: Path, timeout: float = 900.0) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["MPLBACKEND"] = "Agg"
    r = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True,
                       timeout=timeout)
    assert r.returncode == 0, (f"{cmd} exited {r.returncode}:\n{r.stdout[-2000:]}\n"
                               f"{r.stderr[-4000:]}")
    return r


@pytest.mark.slow
def test_wheel_installs_and_runs_the_readme_commands_in_an_empty_folder(tmp_path):
    dist, env_dir, work = tmp_path / "dist", tmp_path / "venv", tmp_path / "work"
    work.mkdir()
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", "-w", dist, ROOT],
         cwd=tmp_path)
    wheels = list(dist.glob("linkwork-*.whl"))
    assert len(wheels) == 1
    venv.create(env_dir, with_pip=True)
    py = env_dir / "bin" / "python"
    _run([py, "-m", "pip", "install", "--quiet", "--disable-pip-version-check", wheels[0]],
         cwd=tmp_path)
    linkwork = env_dir / "bin" / "linkwork"
    version = _run([linkwork, "--version"], cwd=work).stdout
    assert version.startswith("linkwork ") and version.split()[1][0].isdigit()
    listed = _run([linkwork, "examples"], cwd=work).stdout
    assert "sine_press.toml" in listed and str(env_dir) in listed  # the wheel's own copy
    _run([linkwork, "examples", "--copy", "ex"], cwd=work)
    assert sorted(p.name for p in (work / "ex").iterdir()) == sorted(
        p.name for p in (ROOT / "examples").glob("*.toml"))
    _run([linkwork, "analyze", "ex/sine_press.toml", "--out", "out"], cwd=work)
    assert (work / "out").is_dir() and any((work / "out").glob("*.csv"))
    assert any((work / "out").glob("*.png"))
    _run([py, "-m", "linkwork", "-h"], cwd=work)
    # the README's set-up, then its command-line section as printed, in that folder
    _run([linkwork, "examples", "--copy", "examples"], cwd=work)
    cmds = _readme_commands()
    assert len(cmds) >= 6
    for argv in cmds:
        _run([linkwork, *argv], cwd=work)
    assert any((work / "linkwork-output").glob("*.csv"))  # the default folder
    # the installed package is the one imported, not the checkout
    where = _run([py, "-c", "import linkwork; print(linkwork.__file__)"], cwd=work).stdout
    assert str(env_dir) in where
