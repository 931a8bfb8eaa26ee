"""The README's Python example runs as printed, and its numbers are right."""

import math
import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    exec(compile(blocks[0], "README.md", "exec"), {})
    out = capsys.readouterr().out
    # independent numbers: stroke 2*L1/sin(alpha); alpha = asin(2*L1/H) and its supplement
    assert f"{2 * 0.05 / math.sin(math.radians(60)) * 1e3:.1f} mm" in out
    a = math.degrees(math.asin(2 * 0.05 / 0.150))
    assert f"{a:.4f}"[:6] in out and f"{180 - a:.4f}"[:6] in out
    assert (tmp_path / "idle.csv").read_text().startswith("phi1 [rad]")
