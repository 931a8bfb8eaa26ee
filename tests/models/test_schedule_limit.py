"""``VariableStructureMechanism.run`` refuses a schedule of more than ``MAX_SAMPLES`` samples
before any work (10^7 revolutions asked for 26.8 GiB)."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from linkwork.errors import ParameterError
from linkwork.models.variable_structure import (
    MAX_SAMPLES,
    VariableStructureMechanism,
    schedule_samples,
)


def _mech() -> VariableStructureMechanism:
    return VariableStructureMechanism(0.1, 4.0, 0.0, np.radians(60))


def test_schedule_samples_counts_what_run_returns():
    sched = [("idle", 3), ("working", 2, np.radians(50)), ("idle", 1)]
    res = _mech().run(sched, 10.0, samples_per_revolution=24)
    assert schedule_samples([3, 2, 1], 24) == res.phi1.size == 6 * 24 + 3


def test_run_refuses_1e7_revolutions_before_allocating():
    tracemalloc.start()
    try:
        with pytest.raises(ParameterError) as exc:
            _mech().run([("idle", 10**7)], 10.0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 10**6
    msg = str(exc.value)
    assert msg.startswith("schedule = 10000000 revolutions x 360 samples is invalid")
    assert f"at most {MAX_SAMPLES} samples in all (got 3600000001)" in msg and "GiB" in msg


def test_run_limit_boundary():
    # 624999 revolutions at 8 samples: 4999993 samples, under the limit (not run here: 0.8 GB);
    # one revolution more is refused
    rev, spr = (MAX_SAMPLES - 1) // 8, 8
    assert schedule_samples([rev], spr) <= MAX_SAMPLES < schedule_samples([rev + 1], spr)
    with pytest.raises(ParameterError, match="at most 5000000 samples in all"):
        _mech().run([("idle", rev + 1)], 10.0, samples_per_revolution=spr)
