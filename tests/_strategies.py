"""Hypothesis strategies shared by the property tests."""

from hypothesis import strategies as st


def reals(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Floats in [lo, hi] without subnormals: a speed or load of 5e-324 is not a physical input,
    and relative tolerances scaled by it underflow to zero."""
    return st.floats(lo, hi, allow_subnormal=False)
