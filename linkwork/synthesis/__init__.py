"""Dimensional synthesis."""
