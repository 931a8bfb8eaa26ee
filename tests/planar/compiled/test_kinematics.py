"""The compiled kinematics (linkwork.planar.compiled.kinematics, ``backend="numba"``) against the
NumPy path of :func:`linkwork.planar.kinematics`, the reference.

Reference: the NumPy path, an independent implementation of the same conventions (array
expressions over the positions against the kernel's scalar code per element) whose own tests
check it against finite differences, loop closure and published numbers
(tests/planar/test_core.py, test_crossval*.py, test_published.py). Tolerance: 1e-12 of each
quantity's scale (its largest magnitude over the positions compared): the kernel does the same
operations, but numba's ``cos``, ``sin``, ``atan2`` and its ``sqrt`` of a sum of squares (where
NumPy takes ``hypot``) may differ in the last bit, and the difference grows through the rates
by the condition of each group's closure (measured: at most 2e-15 of scale over the
mechanisms of tests/_mechanisms.py). Masks are compared exactly. A batch of designs through
the kernel equals each design through the kernel alone bit for bit (the same kernel, the same
operations, per element). Skipped without numba (CI installs it: the ``test`` extra).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

pytest.importorskip("numba")

from _mechanisms import BUILDERS, crank_and_ram, five_bar, m_rrr, m_triad
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork.errors import AssemblyError, ParameterError
from linkwork.planar import (
    Body,
    Kinematics,
    Mechanism,
    crank_slider_mechanism,
    fourbar_mechanism,
    kinematics,
    stack,
)
from linkwork.planar.compiled.kinematics import covered

FIELDS = ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps")
RTOL = 1e-12
COVERED = [b for b in BUILDERS if b()[2] != "newton"]


def assert_agree(ref: Kinematics, got: Kinematics, rtol: float = RTOL) -> None:
    """Every array of ``got`` equals ``ref`` to ``rtol`` of its scale (NaN where ``ref`` has
    NaN; angles modulo 2 pi: a body at theta = pi may come out as -pi on one path, the sign of
    a zero at atan2's cut); the masks and branches exactly. The scale of a quantity is its
    largest magnitude, at least that of its kind: the length scale L [m] for positions, 1 rad
    for angles, L w, w, L w^2, w^2 for the rates (w the largest angular speed, or the linear
    driver's speed over L), so that a quantity that is zero up to rounding (a parallelogram's
    coupler turns not at all) is judged on the motion's scale, not on its rounding."""
    np.testing.assert_array_equal(got.valid, ref.valid)
    assert set(got.branches) == set(ref.branches)
    assert all(np.array_equal(got.branches[k], ref.branches[k]) for k in ref.branches)
    length = float(np.max(ref.mechanism.plan.length_scale))
    w = max(float(np.max(np.abs(ref.omega[np.isfinite(ref.omega)]), initial=0.0)),
            float(np.max(np.abs(ref.vx[np.isfinite(ref.vx)]), initial=0.0)) / length, 1e-300)
    floor = {"x": length, "y": length, "theta": 1.0, "vx": length * w, "vy": length * w,
             "omega": w, "ax": length * w * w, "ay": length * w * w, "eps": w * w}
    for name in FIELDS:
        a, b = getattr(ref, name), getattr(got, name)
        assert a.shape == b.shape, name
        np.testing.assert_array_equal(np.isnan(b), np.isnan(a), err_msg=name)
        fin = np.isfinite(a)
        if name == "theta":
            b = a + np.remainder(b - a + np.pi, 2 * np.pi) - np.pi
        scale = max(float(np.max(np.abs(a[fin]), initial=0.0)), floor[name])
        np.testing.assert_allclose(b[fin], a[fin], rtol=0, atol=rtol * scale, err_msg=name)


def both(mech: Mechanism, q: np.ndarray, **kw: object) -> tuple[Kinematics, Kinematics]:
    return kinematics(mech, q, **kw), kinematics(mech, q, backend="numba", **kw)


def same_error(mech: Mechanism, q: np.ndarray) -> AssemblyError:
    """The AssemblyError of the compiled backend, after checking that it says what the NumPy
    path's says (and lists the same designs, for a batch)."""
    with pytest.raises(AssemblyError) as e_np:
        kinematics(mech, q)
    with pytest.raises(AssemblyError) as e_nb:
        kinematics(mech, q, backend="numba")
    assert str(e_nb.value) == str(e_np.value)
    assert getattr(e_nb.value, "designs", None) == getattr(e_np.value, "designs", None)
    return e_nb.value


def group_branches(mech: Mechanism, b: int) -> dict[str, int]:
    return {g.key: b for g in mech.structure.groups if g.kind != "driver"}


@pytest.mark.parametrize("builder", COVERED, ids=lambda b: b.__name__)
@pytest.mark.parametrize("branch", [1, -1])
def test_every_covered_group_kind_agrees_with_numpy(builder, branch):
    """Every group kind of tests/_mechanisms.py the kernel covers (RRR, RRP, PRR, RPR, RPP,
    PPR, PRP, RS with the slot on either body, PS, a linear driver), on both branches, over
    its driver range at 4x the builder's positions: all nine arrays and the masks."""
    mech, q, kind = builder()
    assert covered(mech.plan)
    assert any(g.kind == kind for g in mech.structure.groups)
    q = np.linspace(q[0], q[-1], 4 * q.size + 1)
    ref, got = both(mech, q, branches=group_branches(mech, branch), on_failure="nan")
    assert_agree(ref, got)


def test_full_turn_of_a_four_bar_with_nonzero_crank_acceleration():
    """Paper 001's four-bar (a, b, c, d = 0.1, 0.3, 0.2, 0.3 m) over a full turn, with crank
    speeds and accelerations varying per position (the driver's rates enter every row)."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, omega1=10.0)
    q = np.linspace(0.0, 2 * np.pi, 721)
    w = 10.0 + 3.0 * np.sin(q)
    e = 3.0 * np.cos(q) * w
    assert_agree(kinematics(mech, q, w, e), kinematics(mech, q, w, e, backend="numba"))


def test_positions_that_do_not_assemble_give_the_same_masks_and_error():
    """A four-bar that assembles on part of the turn only (a = 0.25 > the Grashof limit): the
    same AssemblyError message (driver ranges, the group that cannot close), and with
    on_failure="nan" the same valid mask with NaN at every quantity there."""
    mech = fourbar_mechanism(0.25, 0.3, 0.2, 0.3)
    q = np.linspace(0.0, 2 * np.pi, 361)
    assert "RRR" in str(same_error(mech, q))
    ref, got = both(mech, q, on_failure="nan")
    assert 0 < ref.valid.sum() < q.size
    assert_agree(ref, got)
    assert np.isnan(got.x[:, ~got.valid]).all() and np.isfinite(got.x[:, got.valid]).all()


def test_parallel_lines_name_the_group_as_numpy_does():
    """A PS group whose slot turns parallel to its guide (slot angle 0 against the guide's 0):
    the lines are parallel at every position; the message says so as on the NumPy path."""
    import dataclasses

    mech, q, _ = BUILDERS[9]()  # m_ps_sine
    joints = tuple(dataclasses.replace(j, angle=0.0) if j.name == "S" else j
                   for j in mech.joints)
    mech = Mechanism(mech.frame, mech.bodies, joints, mech.driver)
    assert "parallel" in str(same_error(mech, q))


def test_toggle_positions_are_singular_as_on_numpy():
    """A parallelogram four-bar (a = c, b = d): every link collinear at phi1 = 0 and pi, where
    the dyad's rates are undefined: the same ``valid`` mask and the same message."""
    mech = fourbar_mechanism(0.1, 0.3, 0.1, 0.3)
    q = np.linspace(0.0, 2 * np.pi, 9)
    ref, got = both(mech, q, on_failure="nan")
    assert not ref.valid.all()
    assert_agree(ref, got)
    same_error(mech, q)


def _four_bars(m: int, seed: int) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    return (rng.uniform(0.05, 0.12, m), rng.uniform(0.25, 0.4, m), rng.uniform(0.15, 0.3, m),
            rng.uniform(0.2, 0.35, m))


def test_batch_equals_each_design_compiled_alone_and_the_numpy_batch():
    """40 four-bar designs (some do not assemble over the whole turn) with per-design branches:
    each design of the compiled batch equals that design through the kernel alone bit for
    bit, and the batch equals the NumPy batch to 1e-12 (masks exactly)."""
    a, b, c, d = _four_bars(40, 5)
    a[3] = 0.3  # a design that does not assemble over the whole turn
    mech = fourbar_mechanism(a, b, c, d, omega1=7.0)
    br = np.where(np.arange(40) % 3 == 0, -1, 1)
    q = np.linspace(0.0, 2 * np.pi, 73)
    ref, got = both(mech, q, branches={"B": br}, on_failure="nan")
    assert not got.valid[3].all() and got.valid[0].all()
    assert_agree(ref, got)
    for i in (0, 3, 7, 39):
        one = kinematics(mech.design(i), q, branches={"B": int(br[i])}, on_failure="nan",
                         backend="numba")
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(got, name)[:, i], getattr(one, name))
        np.testing.assert_array_equal(got.valid[i], one.valid)


@pytest.mark.parametrize("builder", COVERED, ids=lambda b: b.__name__)
def test_batch_of_every_covered_kind(builder):
    """Every covered kind as a batch of three designs (its own, mirrored in y and a copy with
    its branches flipped): the compiled batch equals the NumPy batch, and design 1 of it the
    one-design compiled run bit for bit."""
    mech, q, _ = builder()
    flipped = Mechanism(mech.frame, mech.bodies, mech.joints, mech.driver,
                        {**dict(mech.branches), **group_branches(mech, -1)})
    batch = stack([mech, flipped, mech])
    ref, got = both(batch, q, on_failure="nan")
    assert_agree(ref, got)
    one = kinematics(flipped, q, on_failure="nan", backend="numba")
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(got, name)[:, 1], getattr(one, name))


def test_batch_that_does_not_assemble_raises_the_numpy_message():
    """on_failure="raise" on a batch: the same AssemblyError (the designs that fail, their
    driver ranges) and the same AssemblyError.designs."""
    a, b, c, d = _four_bars(6, 2)
    a[[1, 4]] = 0.3
    mech = fourbar_mechanism(a, b, c, d)
    q = np.linspace(0.0, 2 * np.pi, 37)
    assert same_error(mech, q).designs == [1, 4]  # type: ignore[attr-defined]


def test_batch_per_design_positions_and_speeds():
    """Driver positions (m, n) and speeds (m, 1) per design, on the batch path."""
    a, b, c, d = _four_bars(5, 9)
    mech = fourbar_mechanism(a, b, c, d)
    q = np.linspace(0.0, 2 * np.pi, 31)[None, :] + np.arange(5)[:, None] * 0.1
    w = np.arange(1.0, 6.0)[:, None]
    ref = kinematics(mech, q, w, 0.5, on_failure="nan")
    got = kinematics(mech, q, w, 0.5, on_failure="nan", backend="numba")
    assert_agree(ref, got)


@settings(max_examples=60, deadline=None)
@given(a=st.floats(0.02, 0.3), b=st.floats(0.05, 0.4), c=st.floats(0.05, 0.4),
       d=st.floats(0.05, 0.4), branch=st.sampled_from([1, -1]))
def test_random_four_bars_grashof_or_not(a, b, c, d, branch):
    """Random four-bars, Grashof and not (most do not assemble over the whole turn): the same
    masks, and every quantity to 1e-12 of its scale where both assemble. Near a toggle (the
    coupler and rocker within 1e-3 rad of collinear; a change-point linkage, s + l = p + q to
    1e-3 of its size, passes through one) the rates grow like 1/sin(transmission angle) and
    with them the rounding of both paths: compared to 1e-9 there."""
    mech = fourbar_mechanism(a, b, c, d, omega1=5.0)
    q = np.linspace(0.0, 2 * np.pi, 91)
    ref, got = both(mech, q, branches={"B": branch}, on_failure="nan")
    np.testing.assert_array_equal(got.valid, ref.valid)
    s, p_, q_, l_ = sorted((a, b, c, d))
    change_point = abs(s + l_ - p_ - q_) < 1e-3 * l_
    assert_agree(ref, got, rtol=RTOL if _far_from_toggle(ref) and not change_point else 1e-9)


def _far_from_toggle(k: Kinematics) -> bool:
    """The coupler and rocker are not within 1e-3 rad of collinear at any valid position."""
    mu = k.theta[2] - k.theta[3]
    return bool(np.all(np.abs(np.sin(mu[k.valid])) > 1e-3))


@settings(max_examples=40, deadline=None)
@given(r=st.floats(0.02, 0.2), ratio=st.floats(1.05, 5.0), e=st.floats(-0.1, 0.1),
       guide=st.floats(-1.0, 1.0))
def test_random_offset_crank_sliders(r, ratio, e, guide):
    """Random offset crank-sliders (rod r x ratio, offset e, inclined guide): as the
    four-bars."""
    mech = crank_slider_mechanism(r, r * ratio, e, guide_angle=guide)
    q = np.linspace(0.0, 2 * np.pi, 91)
    ref, got = both(mech, q, on_failure="nan")
    assert_agree(ref, got, rtol=1e-12 if math.fabs(e) + r < 0.99 * r * ratio else 1e-9)


def test_uncovered_plan_falls_back_to_the_numpy_numbers_exactly():
    """A class-III triad (a Newton group) is not compiled: backend="numba" gives the NumPy
    path's numbers bit for bit (it runs that path)."""
    mech, q, _ = m_triad()
    assert not covered(mech.plan)
    ref, got = both(mech, q)
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(got, name), getattr(ref, name))


def _two_driver_motion(mech: Mechanism, n: int, out_of_range: bool = False
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both drivers moving from the drawing's positions (the second driver a crank or a ram):
    positions (2, n), speeds and accelerations varying per driver and position;
    ``out_of_range``: so far that some positions do not assemble."""
    t = np.linspace(0.0, 1.0, n)
    lin = mech.plan.driver_kinds[1] == "linear"
    step = np.array([0.6, 0.02 if lin else -0.4] if not out_of_range else
                    [3.8, 0.13] if lin else [2 * np.pi, -2 * np.pi])[:, None]
    q = np.array(mech.drawing.positions)[:, None] + step * t
    w = np.array([[8.0], [0.3 if lin else -5.0]]) * (1.0 + 0.5 * np.sin(3.0 * t))
    e = np.array([[2.0], [1.0]]) * np.cos(2.0 * t)
    return q, w, e


def _scaled(mech: Mechanism, f: float) -> Mechanism:
    """Another design of ``mech``: every body's points moved to ``f`` times their place."""
    def body(b: Body) -> Body:
        return dataclasses.replace(b, points={k: (v[0] * f, v[1] * f)
                                              for k, v in b.points.items()})

    return Mechanism(body(mech.frame), tuple(body(b) for b in mech.bodies), mech.joints,
                     mech.drivers, dict(mech.branches))


@pytest.mark.parametrize("build", [five_bar, crank_and_ram], ids=lambda b: b.__name__)
def test_several_drivers(build):
    """Two drivers (two cranks; a crank and a linear actuator), each a group of its own with
    its own positions, speeds and accelerations: compiled, and the NumPy path's numbers; out
    of range, the same masks and the same AssemblyError."""
    mech = build()
    assert covered(mech.plan) and len(mech.drivers) == 2
    q, w, e = _two_driver_motion(mech, 41)
    ref = kinematics(mech, q, w, e)
    got = kinematics(mech, q, w, e, backend="numba")
    assert_agree(ref, got)
    q, w, e = _two_driver_motion(mech, 41, out_of_range=True)
    ref = kinematics(mech, q, w, e, on_failure="nan")
    got = kinematics(mech, q, w, e, on_failure="nan", backend="numba")
    assert 0 < np.count_nonzero(~ref.valid) < q.shape[1]
    assert_agree(ref, got)
    same_error(mech, q)


@pytest.mark.parametrize("build", [five_bar, crank_and_ram], ids=lambda b: b.__name__)
def test_several_drivers_in_a_batch(build):
    """Three designs of a two-driver mechanism (scaled, per-design driver positions, speeds
    and accelerations per driver and position): the compiled batch against the NumPy batch,
    design 1 against itself alone bit for bit, and on threads bit for bit."""
    mech = build()
    q, w, e = _two_driver_motion(mech, 31)
    batch = stack([_scaled(mech, f) for f in (1.0, 1.03, 0.98)])
    mech = _scaled(mech, 1.03)
    qb = np.stack([q, q + 0.01, q - 0.01], axis=1)  # (2, 3, n)
    ref = kinematics(batch, qb, w, e, on_failure="nan")
    got = kinematics(batch, qb, w, e, on_failure="nan", backend="numba")
    assert_agree(ref, got)
    one = kinematics(mech, qb[:, 1], w, e, on_failure="nan", backend="numba")
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(got, name)[:, 1], getattr(one, name))
    if _threads() > 1:
        many = kinematics(batch, qb, w, e, on_failure="nan", backend="numba",
                          threads=_threads())
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(many, name), getattr(got, name))


def test_default_backend_is_numpy_and_bad_names_are_refused():
    mech, q, _ = m_rrr()
    ref = kinematics(mech, q)
    again = kinematics(mech, q, backend="numpy")
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(again, name), getattr(ref, name))
    with pytest.raises(ParameterError, match="backend"):
        kinematics(mech, q, backend="cuda")  # type: ignore[arg-type]


def test_empty_and_single_positions():
    mech, _, _ = m_rrr()
    for q in (np.zeros(0), np.array([0.7])):
        ref, got = both(mech, q)
        assert_agree(ref, got)


# --- threads: the parallel kernel (designs and blocks of positions shared among threads) ---
def _threads() -> int:
    import numba

    return min(3, int(numba.config.NUMBA_NUM_THREADS))


def test_long_cycles_of_a_batch_run_in_blocks_as_numpy_does():
    """Three designs (one that does not assemble over the whole turn) x 2.5 blocks of
    positions (BLOCK each: the kernel's unit of work): the compiled batch against the NumPy
    batch, and each design against itself alone."""
    from linkwork.planar.compiled.kinematics import BLOCK

    a, b, c, d = _four_bars(3, 11)
    a[1] = 0.3
    mech = fourbar_mechanism(a, b, c, d, omega1=4.0)
    q = np.linspace(0.0, 2 * np.pi, 5 * BLOCK // 2 + 3)
    ref, got = both(mech, q, on_failure="nan")
    assert not got.valid[1].all()
    assert_agree(ref, got)
    one = kinematics(mech.design(2), q, on_failure="nan", backend="numba")
    np.testing.assert_array_equal(got.eps[:, 2], one.eps)


@pytest.mark.parametrize("builder", [m_rrr, m_triad, *COVERED[1::3]], ids=lambda b: b.__name__)
def test_threads_give_the_same_result_bit_for_bit(builder):
    """threads = 2 or 3 against 1: every array and mask equal bit for bit, for one design over
    several blocks of positions (out of range at both ends: elements that do not assemble)
    and for a batch of three designs; a plan that runs the NumPy path (the triad) too."""
    if _threads() < 2:
        pytest.skip("numba has one thread here (NUMBA_NUM_THREADS)")
    mech, q, _ = builder()
    span = q[-1] - q[0]
    q = np.linspace(q[0] - 0.2 * span, q[-1] + 0.2 * span, 4500)
    for m in (mech, stack([mech, mech, mech])):
        one = kinematics(m, q, on_failure="nan", backend="numba")
        many = kinematics(m, q, on_failure="nan", backend="numba", threads=_threads())
        for name in (*FIELDS, "valid"):
            np.testing.assert_array_equal(getattr(many, name), getattr(one, name), name)


def test_threads_raise_the_same_assembly_error():
    if _threads() < 2:
        pytest.skip("numba has one thread here (NUMBA_NUM_THREADS)")
    a, b, c, d = _four_bars(6, 2)
    a[[1, 4]] = 0.3
    mech = fourbar_mechanism(a, b, c, d)
    q = np.linspace(0.0, 2 * np.pi, 37)
    with pytest.raises(AssemblyError) as one:
        kinematics(mech, q, backend="numba")
    with pytest.raises(AssemblyError) as many:
        kinematics(mech, q, backend="numba", threads=2)
    assert str(many.value) == str(one.value)


def test_parallel_kernels_called_from_several_python_threads():
    """Four Python threads each running the parallel kernel (one launch at a time in the
    process: numba's fallback threading layer aborts on concurrent launches): every result
    equals the serial one."""
    from concurrent.futures import ThreadPoolExecutor

    if _threads() < 2:
        pytest.skip("numba has one thread here (NUMBA_NUM_THREADS)")
    a, b, c, d = _four_bars(20, 4)
    mech = fourbar_mechanism(a, b, c, d)
    q = np.linspace(0.0, 2 * np.pi, 361)
    ref = kinematics(mech, q, backend="numba", on_failure="nan")
    with ThreadPoolExecutor(4) as ex:
        outs = list(ex.map(lambda _: kinematics(mech, q, backend="numba", threads=2,
                                                on_failure="nan"), range(8)))
    for k in outs:
        np.testing.assert_array_equal(k.eps, ref.eps)


@pytest.mark.parametrize(("threads", "backend", "match"), [
    (0, "numba", "threads = 0 is invalid: must be an integer >= 1"),
    (-2, "numba", "must be an integer >= 1"),
    (1.5, "numba", "must be an integer >= 1"),
    (True, "numba", "must be an integer >= 1"),
    ("2", "numba", "must be an integer >= 1"),
    (2, "numpy", "threads = 2 is invalid: needs backend='numba'"),
    (10**6, "numba", r"must be at most \d+, numba's thread count \(NUMBA_NUM_THREADS\)"),
])
def test_bad_threads_are_refused(threads, backend, match):
    mech, q, _ = m_rrr()
    with pytest.raises(ParameterError, match=match):
        kinematics(mech, q, backend=backend, threads=threads)


def test_angles_on_circles_per_design_frames():
    """The coupler's and rocker's local frames turned by a different angle in each design
    (phi0 = 0, 0.3, -1.0 rad: their angles taken after the kernel, arctan2 - phi0 per
    design): the compiled batch against the NumPy batch, each design against itself alone
    bit for bit, and the angles shifted by exactly the turn against design 0."""
    from linkwork.planar.compiled.kinematics import deferred_angles, encode

    mech, q, _ = m_rrr()

    def turned(alpha: float) -> Mechanism:
        c, s = math.cos(alpha), math.sin(alpha)
        bodies = tuple(b if b.name == "crank" else dataclasses.replace(
            b, points={k: (c * x - s * y, s * x + c * y) for k, (x, y) in b.points.items()})
            for b in mech.bodies)
        return Mechanism(mech.frame, bodies, mech.joints, mech.driver, dict(mech.branches))

    turns = (0.0, 0.3, -1.0)
    batch = stack([turned(a) for a in turns])
    enc = encode(batch.plan)
    assert enc is not None
    assert {b for b, _, _ in deferred_angles(enc.jt, enc.gt)} == {2, 3}
    ref, got = both(batch, q, on_failure="nan")
    assert_agree(ref, got)
    for i, alpha in enumerate(turns):
        one = kinematics(turned(alpha), q, on_failure="nan", backend="numba")
        np.testing.assert_array_equal(got.theta[:, i], one.theta)
        shift = np.remainder(got.theta[2:, i] - got.theta[2:, 0] + alpha + np.pi,
                             2 * np.pi) - np.pi
        np.testing.assert_allclose(shift, 0.0, atol=1e-12)


def test_no_more_threads_than_blocks(monkeypatch):
    """A call runs on at most as many threads as it has blocks of positions (BLOCK per design):
    one design of 360 positions on the calling thread, three designs on 3 (or numba's
    count), one design of 2.5 blocks on 3; the numbers are the same either way."""
    import linkwork.planar.compiled.kinematics as ck

    if _threads() < 2:
        pytest.skip("numba has one thread here (NUMBA_NUM_THREADS)")
    used: list[int] = []
    real = ck.call

    def spy(fn, threads, *args):
        used.append(threads)
        return real(fn, threads, *args)

    monkeypatch.setattr(ck, "call", spy)
    a, b, c, d = _four_bars(3, 5)
    k = _threads()
    one = fourbar_mechanism(a[0], b[0], c[0], d[0])
    q = np.linspace(0.0, 2 * np.pi, 360)
    ref = kinematics(one, q, backend="numba", on_failure="nan")
    got = kinematics(one, q, backend="numba", threads=k, on_failure="nan")
    kinematics(fourbar_mechanism(a, b, c, d), q, backend="numba", threads=k, on_failure="nan")
    kinematics(one, np.linspace(0.0, 2 * np.pi, 5 * ck.BLOCK // 2), backend="numba",
               threads=k, on_failure="nan")
    assert used == [1, 1, min(k, 3), min(k, 3)]
    np.testing.assert_array_equal(got.eps, ref.eps)
