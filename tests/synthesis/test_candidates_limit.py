"""``swashplate synthesize --candidates`` / ``synthesize(n_candidates=)`` and the feasible
region's grid are refused above a stated limit before anything is sampled."""

from __future__ import annotations

import math

import pytest
from _cli_files import run_cli

from linkwork.errors import ParameterError
from linkwork.models import swashplate as sw
from linkwork.synthesis import swashplate as syn

DEG = math.pi / 180


def _req() -> syn.Request:
    return syn.Request(scheme="4a", R=0.1, H=0.06, H_tol=1e-4, delta_f=30 * DEG,
                       delta_r=30 * DEG)


def test_check_candidates_accepts_the_limit_and_names_it_above():
    assert syn.MAX_CANDIDATES == 2**20
    assert syn.check_candidates(2**20) == 2**20
    with pytest.raises(ParameterError, match=r"n_candidates = 1048577 is invalid: must be at "
                       r"most 1048576 \(2\^20\) candidates"):
        syn.check_candidates(2**20 + 1)


def test_synthesize_refuses_1e12_before_sampling():
    with pytest.raises(ParameterError, match=r"n_candidates = 1e\+12 is invalid: must be at "
                       "most 1048576"):
        syn.synthesize(_req(), n_candidates=1e12)


def test_feasible_region_grid_is_bounded():
    base = sw.Design(scheme="4a", R=0.1, r=0.02, l=0.05, alpha=20 * DEG)
    with pytest.raises(ParameterError, match=r"n = 1001 is invalid: must be an integer from 2 "
                       "to 1000"):
        syn.feasible_region(_req(), base, "alpha", "l", n=1001)


def test_cli_refuses_candidates_in_one_line(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, err = run_cli(["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm",
                                 "--candidates", str(10**12), "--out", str(out)], capsys)
    assert code == 2 and stdout == ""
    assert err.count("\n") == 1
    assert "--candidates = 1000000000000 is invalid: must be at most 1048576" in err
