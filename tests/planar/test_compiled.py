"""The compiled backend's check (linkwork.planar.compiled): a backend is named, and numba is
asked for only when the compiled backend is."""

from __future__ import annotations

import sys

import pytest

from linkwork.errors import MissingExtraError, ParameterError
from linkwork.planar.compiled import BACKENDS, check_backend


@pytest.mark.parametrize("backend", BACKENDS)
def test_known_backends_pass(backend: str) -> None:
    assert check_backend(backend) == backend


@pytest.mark.parametrize("bad", ["NumPy", "cuda", "", None, 1])
def test_unknown_backend_names_the_option(bad: object) -> None:
    with pytest.raises(ParameterError, match="backend") as err:
        check_backend(bad, option="--backend")
    assert "--backend" in str(err.value) and "numba" in str(err.value)


def test_missing_numba_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba raises ImportError
    with pytest.raises(MissingExtraError, match=r"linkwork\[numba\]"):
        check_backend("numba")
    assert check_backend("numpy") == "numpy"  # the default needs nothing


def test_import_linkwork_does_not_import_numba() -> None:
    import subprocess

    code = "import linkwork, linkwork.planar, sys; print('numba' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


def test_kinematics_names_the_missing_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    """kinematics(..., backend="numba") without numba: the MissingExtraError naming the extra,
    before any work; the default backend runs."""
    from linkwork.planar import fourbar_mechanism, kinematics

    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3)
    monkeypatch.setitem(sys.modules, "numba", None)
    with pytest.raises(MissingExtraError, match=r"linkwork\[numba\]"):
        kinematics(mech, [0.5], backend="numba")
    assert kinematics(mech, [0.5]).valid.all()
