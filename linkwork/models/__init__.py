"""Closed-form models from the literature: pure, vectorised functions."""
