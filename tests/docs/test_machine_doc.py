"""The Python example of ``docs/machine.md`` runs as printed and gives the numbers the page
quotes (the knuckle press's flywheel: 41.8 kg m^2 exact, 108.8 by both classical methods)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[2] / "docs" / "machine.md"


@pytest.mark.slow
def test_machine_page_example_runs_and_matches_its_numbers(capsys, monkeypatch):
    monkeypatch.chdir(DOC.parents[1])
    code = re.findall(r"```python\n(.*?)```", DOC.read_text(), re.S)[0]
    scope: dict = {}
    exec(compile(code, str(DOC), "exec"), scope)  # the page's own example
    sizing, ss = scope["sizing"], scope["ss"]
    assert sizing.flywheel == pytest.approx(41.8, abs=0.05)
    assert sizing.energy_method == pytest.approx(108.8, abs=0.05)
    assert sizing.wittenbauer_flywheel == pytest.approx(108.8, abs=0.05)
    assert ss.delta == pytest.approx(0.10, rel=1e-8)
    text = DOC.read_text()
    assert "41.8 kg·m² | 108.8 (+160 %)" in text
