"""Kernels generated per plan structure (linkwork.planar.compiled.codegen): where they are
written, when they are written again, and which plans share one.

The generated kernels' numbers are tested against the NumPy path in test_kinematics.py."""

from __future__ import annotations

import os
import stat
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("numba")

from _mechanisms import m_rpr, m_rrr

from linkwork.planar import fourbar_mechanism, kinematics
from linkwork.planar.compiled import codegen
from linkwork.planar.compiled import kinematics as ck

SOURCE = "def kernel(x):\n    return 2 * x\n"


def test_the_kernel_directory_follows_the_environment(tmp_path):
    assert codegen.choose_dir({"LINKWORK_CACHE_DIR": str(tmp_path / "a")}) == (
        tmp_path / "a" / "kernels")
    assert codegen.choose_dir({"XDG_CACHE_HOME": str(tmp_path / "x")}) == (
        tmp_path / "x" / "linkwork" / "kernels")
    assert (tmp_path / "x" / "linkwork" / "kernels").is_dir()
    assert codegen.choose_dir({}) == Path.home() / ".cache" / "linkwork" / "kernels"


def test_an_unwritable_kernel_directory_gives_a_temporary_one(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    path = codegen.choose_dir({"LINKWORK_CACHE_DIR": str(blocker)})
    assert path.is_dir() and not path.is_relative_to(blocker)
    assert "linkwork-kernels-" in path.name
    if os.geteuid() != 0:  # root writes anywhere
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(stat.S_IRUSR | stat.S_IXUSR)
        try:
            assert not codegen.choose_dir({"LINKWORK_CACHE_DIR": str(ro)}).is_relative_to(ro)
        finally:
            ro.chmod(stat.S_IRWXU)


def test_load_writes_once_and_imports(tmp_path, monkeypatch):
    monkeypatch.setattr(codegen, "_LOADED", {})
    fn = codegen.load("test", SOURCE, directory=tmp_path)
    assert fn(21) == 42
    (path,) = tmp_path.glob("_linkwork_test_*.py")
    assert path.read_text() == SOURCE
    assert codegen.load("test", SOURCE, directory=tmp_path) is fn  # once per process
    # another process finds the file and does not write it again (numba's cache of a kernel
    # is valid while its file's time stamp is unchanged)
    stamp = path.stat().st_mtime_ns
    monkeypatch.setattr(codegen, "_LOADED", {})
    assert codegen.load("test", SOURCE, directory=tmp_path)(1) == 2
    assert path.stat().st_mtime_ns == stamp
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".tmp"] == []
    sys.modules.pop(path.stem, None)


def test_threads_loading_one_kernel_at_once(tmp_path, monkeypatch):
    """Eight threads load the same new kernel at once: one writes and imports it, every
    thread gets that function, and no temporary file is left (each writer's temporary file
    has a name of its own)."""
    from concurrent.futures import ThreadPoolExecutor

    monkeypatch.setattr(codegen, "_LOADED", {})
    src = "import time\ntime.sleep(0.05)\n\n\ndef kernel(x):\n    return 3 * x\n"
    with ThreadPoolExecutor(8) as ex:
        fns = list(ex.map(lambda _: codegen.load("test", src, directory=tmp_path), range(8)))
    assert len({id(f) for f in fns}) == 1 and fns[0](2) == 6
    (path,) = tmp_path.glob("_linkwork_test_*.py")
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_file()) == [path.name]
    sys.modules.pop(path.stem, None)


def test_a_damaged_kernel_file_is_written_again(tmp_path, monkeypatch):
    monkeypatch.setattr(codegen, "_LOADED", {})
    codegen.load("test", SOURCE, directory=tmp_path)
    (path,) = tmp_path.glob("_linkwork_test_*.py")
    path.write_text("def kernel(x):\n    return 0\n")  # a truncated or edited file
    monkeypatch.setattr(codegen, "_LOADED", {})
    assert codegen.load("test", SOURCE, directory=tmp_path)(5) == 10
    assert path.read_text() == SOURCE
    sys.modules.pop(path.stem, None)


def test_the_fingerprint_follows_the_helpers_source(tmp_path):
    mod = tmp_path / "helpers_mod.py"
    mod.write_text("x = 1\n")

    class M:
        __file__ = str(mod)

    first = codegen.fingerprint(M)  # type: ignore[arg-type]
    assert codegen.fingerprint(M) == first  # type: ignore[arg-type]
    mod.write_text("x = 2\n")
    assert codegen.fingerprint(M) != first  # type: ignore[arg-type]
    enc = ck.encode(m_rrr()[0].plan)
    assert enc is not None
    assert codegen.fingerprint(ck) in ck.kernel_source(enc.jt, enc.gt, enc.nb).splitlines()[0]


def test_one_kernel_per_structure_not_per_geometry():
    """Two four-bars of different dimensions (and a batch) share one generated kernel; a
    plan of another structure has its own."""
    encs = [ck.encode(fourbar_mechanism(*dims, omega1=10.0).plan) for dims in (
        (0.1, 0.3, 0.2, 0.3), (0.05, 0.4, 0.3, 0.35),
        (np.array([0.1, 0.12]), 0.3, 0.2, np.array([0.3, 0.31])))]
    assert all(e is not None for e in encs)
    sources = {ck.kernel_source(e.jt, e.gt, e.nb) for e in encs}  # type: ignore[union-attr]
    assert len(sources) == 1
    assert len({id(ck.kernel(e)) for e in encs}) == 1  # type: ignore[arg-type]
    other = ck.encode(m_rpr()[0].plan)
    assert other is not None
    assert ck.kernel_source(other.jt, other.gt, other.nb) not in sources


def test_the_generated_kernel_takes_the_structure_not_the_values():
    """The source holds no dimension: every design's geometry is read from the tables, so a
    design whose dimensions change gives new numbers through the same kernel."""
    a = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, omega1=10.0)
    b = fourbar_mechanism(0.1, 0.3, 0.25, 0.3, omega1=10.0)
    enc = ck.encode(a.plan)
    assert enc is not None
    src = ck.kernel_source(enc.jt, enc.gt, enc.nb)
    assert "0.3" not in src and "0.2" not in src
    q = np.linspace(0.0, 6.0, 7)
    ka, kb = kinematics(a, q, backend="numba"), kinematics(b, q, backend="numba")
    assert not np.allclose(ka.theta, kb.theta)
    np.testing.assert_allclose(kb.theta, kinematics(b, q).theta, rtol=0, atol=1e-14)


def test_one_reactions_kernel_per_structure():
    """Four-bars of other dimensions and masses share the generated reactions kernel; its
    source holds no dimension or mass; a two-driver plan has its own."""
    from _mechanisms import five_bar

    from linkwork.planar.compiled import reactions

    mechs = [fourbar_mechanism(0.1, 0.3, 0.2, 0.3, omega1=10.0, masses=(1.0, 2.0, 1.5)),
             fourbar_mechanism(0.05, 0.4, 0.3, 0.35, omega1=3.0, masses=(0.7, 2.5, 1.1))]
    encs = [reactions.encode(m) for m in mechs]
    sources = {reactions.kernel_source(e) for e in encs}  # type: ignore[arg-type]
    assert len(sources) == 1
    (src,) = sources
    assert "0.3" not in src and "1.5" not in src and "2.5" not in src
    assert reactions.kernel(encs[0]) is reactions.kernel(encs[1])  # type: ignore[arg-type]
    other = reactions.encode(five_bar())
    assert other is not None and reactions.kernel_source(other) not in sources


def test_a_new_mechanism_of_a_known_structure_writes_no_source(monkeypatch):
    """Once a structure's kernels exist, a new mechanism of that structure (a design changed by
    a solver, a loop over designs) neither writes the source again nor works out its
    deferred angles again: both are looked up by the structure's tables."""
    from linkwork.planar import inverse_dynamics
    from linkwork.planar.compiled import reactions

    q = np.linspace(0.0, 6.0, 5)
    inverse_dynamics(kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 2.0, 1.5)),
                                q, backend="numba"), backend="numba")
    written: list[str] = []
    monkeypatch.setattr(ck, "kernel_source", lambda *a: written.append("kinematics") or "")
    monkeypatch.setattr(reactions, "kernel_source", lambda *a: written.append("reactions") or "")
    for a in (0.09, 0.11):
        mech = fourbar_mechanism(a, 0.3, 0.2, 0.3, masses=(1.0, 2.0, a * 10))
        ref = inverse_dynamics(kinematics(mech, q), backend="numpy")
        got = inverse_dynamics(kinematics(mech, q, backend="numba"), backend="numba")
        np.testing.assert_allclose(got.Q, ref.Q, rtol=0, atol=1e-12 * np.max(np.abs(ref.Q)))
    assert written == []
