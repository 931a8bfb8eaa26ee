"""The README's Python example runs as printed, and its numbers are right."""

import math
import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert len(blocks) == 2
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "README.md", "exec"), {})
    out = capsys.readouterr().out
    # independent numbers: stroke 2*L1/sin(alpha); alpha = asin(2*L1/H) and its supplement
    assert f"{2 * 0.05 / math.sin(math.radians(60)) * 1e3:.1f} mm" in out
    a = math.degrees(math.asin(2 * 0.05 / 0.150))
    assert f"{a:.4f}"[:6] in out and f"{180 - a:.4f}"[:6] in out
    assert (tmp_path / "idle.csv").read_text().startswith("phi1 [rad]")


def test_readme_study_example_matches_the_closed_form_kinetostatics(tmp_path, monkeypatch, capsys):
    """The second example (a study of examples/fourbar_paper001.toml) prints the peak driving
    torque and crank-bearing load of the closed-form four-bar kinetostatics (Norton's free-body
    equations in linkwork.models.fourbar, independent of the engine) for the file's data:
    0.1/0.3/0.2/0.3 m, masses 1/3/2 kg, inertias 0.000833/0.0225/0.00567 kg m^2 about the
    centres, 10 rad/s, no gravity. Tolerance: the printed digits."""
    import numpy as np

    from linkwork.models.fourbar import fourbar_kinetostatics

    block = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)[1]
    (tmp_path / "examples").symlink_to(README.parent / "examples")
    monkeypatch.chdir(tmp_path)
    exec(compile(block, "README.md", "exec"), {})
    out = capsys.readouterr().out
    phi = np.radians(np.linspace(0.0, 360.0, 361))
    ref = fourbar_kinetostatics(phi, 0.1, 0.3, 0.2, 0.3, 10.0, mass=(1.0, 3.0, 2.0),
                                inertia=(0.000833, 0.0225, 0.00567))
    peak, load = re.search(r"peak driving torque ([0-9.]+) N m, peak load of bearing O "
                           r"([0-9.]+) N", out).groups()
    assert float(peak) == round(float(np.abs(ref.Q).max()), 3)
    assert float(load) == round(float(np.hypot(ref.R_Ox, ref.R_Oy).max()), 2)
    assert (tmp_path / "torque.png").stat().st_size > 1000


def _readme_commands() -> list[list[str]]:
    """The `linkwork ...` lines of the README's command-line section, as argument lists."""
    import shlex

    text = README.read_text().split("## Command line", 1)[1].split("\n## ", 1)[0]
    cmds = []
    for line in text.splitlines():
        line = line.strip()
        if line.startswith("linkwork "):
            cmds.append(shlex.split(line.split("#", 1)[0])[1:])
    return cmds


def test_readme_commands_run_as_printed(tmp_path, monkeypatch, capsys):
    from linkwork.cli import main

    (tmp_path / "examples").symlink_to(README.parent / "examples")
    monkeypatch.chdir(tmp_path)  # the commands' relative paths, outputs inside tmp_path
    cmds = _readme_commands()
    assert len(cmds) >= 6
    for argv in cmds:
        writes = argv[0] in ("analyze", "balance", "reactions", "swashplate")
        if writes and "--help" not in argv and "--out" not in argv and "-o" not in argv:
            argv = [*argv, "--out", argv[0]]
        rc = main(argv)
        err = capsys.readouterr().err
        assert rc == 0, (argv, err)
