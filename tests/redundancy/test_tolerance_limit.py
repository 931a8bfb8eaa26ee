"""``--tolerance-study N`` / ``tolerance_study(n_samples=N)``: N is refused above the number of
samples whose draws and peaks fit in the stated memory budget, before anything is drawn."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from _cli_files import run_cli

from linkwork import io
from linkwork.errors import ParameterError
from linkwork.redundancy.tolerance import (
    MEMORY_BUDGET,
    check_samples,
    max_samples,
    sample_bytes,
)
from linkwork.studies import reactions as study_reactions

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "loom_fourbar_spatial.toml"


def test_limit_is_the_budget_over_the_bytes_of_a_sample():
    # 4 joints x 7 peaks + 9 deviations, 8 bytes each, kept twice
    assert sample_bytes(4, 9) == 2 * 8 * (4 * 7 + 9)
    assert max_samples(4, 9) == 2**30 // 592 == MEMORY_BUDGET // 592
    assert check_samples(max_samples(4, 9), 4, 9) == max_samples(4, 9)  # the limit itself
    with pytest.raises(ParameterError, match=r"at most 1813753 samples for 4 joints and 9 "):
        check_samples(max_samples(4, 9) + 1, 4, 9, parameter="--tolerance-study")


def test_api_refuses_before_drawing():
    doc = io.load(EXAMPLE)
    study = study_reactions.run(doc, angles=np.radians([0.0, 90.0]))
    tols = study_reactions.tolerances(study, 1)
    limit = max_samples(len(study.model.joints), len(tols))
    tracemalloc.start()
    try:
        with pytest.raises(ParameterError) as exc:
            study_reactions.tolerance(study, 10**12, tols=tols)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 10**6  # nothing of the 10^12 samples was allocated
    msg = str(exc.value)
    assert msg.startswith("n_samples = 1000000000000 is invalid")
    assert f"at most {limit} samples" in msg
    assert "GiB" in msg


def test_cli_refuses_in_one_line_before_any_output(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, err = run_cli(["reactions", str(EXAMPLE), "--tolerance-study",
                                 str(10**12), "--out", str(out)], capsys)
    assert code == 2 and stdout == ""
    assert err.count("\n") == 1
    assert "--tolerance-study" in err and "1000000000000" in err
    assert "at most 1813753 samples for 4 joints and 9 deviations" in err
    assert not out.exists()
