"""The compiled inverse dynamics (linkwork.planar.compiled.reactions, ``inverse_dynamics(...,
backend="numba")``) against the NumPy path and against physical invariants.

References:

* the NumPy path (``backend="numpy"``, the default), which the kernel must reproduce: every
  per-position array to 1e-12 of its quantity's scale (forces: the largest reaction, shaking
  or load force; moments: that force times the mechanism's length scale; points: the length
  scale; energy: the largest T); NaN exactly where NumPy gives NaN. The kernel runs the same
  formulas in the same order, so the two agree to rounding (numba's cos/sin may differ from
  NumPy's in the last bit: that is what the tolerance allows);
* independent invariants on the compiled results alone: the power balance
  ``sum Q omega1 + sum load power + gravity power = dT/dt`` with ``dT/dt = sum m a_C . v_C + I
  omega eps`` written out from the kinematics (tests/_mechanisms.kinetic_energy_rate), and the
  momentum balance of the moving bodies: the shaking force (moment about ``about``) equals
  the loads' forces (moments) plus ``sum m (g - a_C)`` (their moments and ``-I eps``), loads'
  reactions on the frame included. Both to 1e-9 of the largest sum of the magnitudes of the
  terms over the cycle;
* plans the kernel does not cover (friction, gear pairs, a Newton group) run the NumPy path:
  bit for bit equal.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

pytest.importorskip("numba")

from _mechanisms import (
    BUILDERS,
    crank_and_ram,
    five_bar,
    kinetic_energy_rate,
    m_ps_sine,
    m_rpr,
    m_rrr,
    m_triad,
    planetary,
    with_friction,
)
from hypothesis import given, settings
from hypothesis import strategies as st

import linkwork.planar.dynamics as dynamics
from linkwork.errors import ParameterError
from linkwork.planar import (
    Body,
    BodyTorque,
    Damper,
    Mechanism,
    PointForce,
    Spring,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
    stack,
)
from linkwork.planar.compiled import reactions

GRAVITY = (0.3, -9.81)
ABOUT = (0.04, -0.07)
COVERED = [b for b in BUILDERS if b is not m_triad]
ARRAYS = (*dynamics._PER_POSITION, "load_power", "V")


def loads_for(mech: Mechanism, phi: np.ndarray) -> list:
    """A point force varying over the positions and a constant one held by the frame (a
    press's force) on the last body, a couple on the first, a spring from the frame to the
    last body's centre of mass and a damper between the first two bodies."""
    first, last = mech.bodies[0].name, mech.bodies[-1].name
    second = mech.bodies[1].name
    return [PointForce(last, "com", fx=40.0 * np.cos(phi), fy=-25.0, name="F"),
            PointForce(last, (0.01, 0.02), fx=-12.0, fy=7.0, from_frame=True, name="press"),
            BodyTorque(first, mz=1.5, name="M"),
            Spring(mech.frame.name, (0.05, 0.45), last, "com", stiffness=400.0,
                   free_length=0.2, preload=5.0, name="k"),
            Damper(first, "com", second, "com", damping=3.0, name="c")]


def scales(d0) -> dict[str, float]:
    """The scale of each compared array of the NumPy result ``d0`` (see the module
    docstring)."""

    def big(*arrays) -> float:
        return max(float(np.max(np.abs(a[np.isfinite(a)]), initial=0.0)) for a in arrays)

    L = d0.kinematics.mechanism.plan.length_scale + float(np.hypot(*d0.about))
    L = float(np.max(L))
    F = big(d0.fx, d0.fy, d0.shaking_fx, d0.shaking_fy,
            *[w.fx for ld in d0.loads for w in ld.wrenches],
            *[w.fy for ld in d0.loads for w in ld.wrenches]) + 1.0
    M = F * L + big(d0.mz, d0.shaking_m)
    Q = F * L + big(d0.Q)
    return {"fx": F, "fy": F, "shaking_fx": F, "shaking_fy": F, "mz": M, "shaking_m": M,
            "Q": Q, "Q_frictionless": Q, "px": L, "py": L, "T": big(d0.T) + 1e-12}


def assert_agree(d0, d1) -> None:
    """The compiled result ``d1`` against the NumPy result ``d0``: the same structure, every
    array to 1e-12 of its scale, NaN at the same places; the arrays the kernel does not
    compute (friction, loads' power and energy) equal."""
    assert type(d1) is type(d0)
    assert d1.joints == d0.joints and d1.about == d0.about and d1.gravity == d0.gravity
    assert (d1.friction_iterations, d1.friction_static) == (d0.friction_iterations,
                                                            d0.friction_static)
    assert [ld.name for ld in d1.loads] == [ld.name for ld in d0.loads]
    assert d1.units == d0.units
    sc = scales(d0)
    for name in ARRAYS:
        a, b = getattr(d0, name), getattr(d1, name)
        assert a.shape == b.shape and a.dtype == b.dtype, name
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=name)
        if name in sc:
            np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * sc[name], err_msg=name)
        else:
            np.testing.assert_array_equal(b, a, err_msg=name)


def assert_identical(d0, d1) -> None:
    """Every array of the two results bit for bit (NaN where the other has NaN)."""
    for name in ARRAYS:
        a, b = getattr(d0, name), getattr(d1, name)
        assert a.shape == b.shape and a.dtype == b.dtype, name
        np.testing.assert_array_equal(b, a, err_msg=name)
    assert d1.joints == d0.joints and d1.friction_iterations == d0.friction_iterations


def assert_balances(dyn, g: tuple[float, float]) -> None:
    """Power and momentum balances of the compiled result ``dyn`` (module docstring)."""
    kin = dyn.kinematics
    mech = kin.mechanism
    dT, pg = kinetic_energy_rate(mech, kin, g)
    driving = dyn.total_power
    loads = np.sum(dyn.load_power, axis=0)
    scale = np.abs(dT) + np.abs(driving) + np.sum(np.abs(dyn.load_power), axis=0) + np.abs(pg)
    assert np.all(np.abs(driving + loads + pg - dT) <= 1e-9 * np.nanmax(scale))
    # momentum: shaking = loads (on moving bodies and their reactions on the frame) + m(g - a)
    c = kin.centres_of_mass()
    ax, ay = dyn.about
    fx, fy, m = np.zeros(kin.n), np.zeros(kin.n), np.zeros(kin.n)
    size = np.zeros(kin.n)
    for ld in dyn.loads:
        for w in ld.wrenches:
            mw = (w.px - ax) * w.fy - (w.py - ay) * w.fx + w.mz
            fx, fy, m = fx + w.fx, fy + w.fy, m + mw
            size = size + np.abs(w.fx) + np.abs(w.fy) + np.abs(mw)
    for k, b in enumerate(mech.bodies):
        gx, gy = b.mass * (g[0] - c.ax[k]), b.mass * (g[1] - c.ay[k])
        mi = (c.x[k] - ax) * gy - (c.y[k] - ay) * gx - b.inertia * kin.eps[k + 1]
        fx, fy, m = fx + gx, fy + gy, m + mi
        size = size + np.abs(gx) + np.abs(gy) + np.abs(mi)
    tol = 1e-9 * np.nanmax(size + np.abs(dyn.shaking_fx) + np.abs(dyn.shaking_fy)
                           + np.abs(dyn.shaking_m))
    assert np.all(np.abs(dyn.shaking_fx - fx) <= tol)
    assert np.all(np.abs(dyn.shaking_fy - fy) <= tol)
    assert np.all(np.abs(dyn.shaking_m - m) <= tol)


@pytest.mark.parametrize("builder", COVERED, ids=lambda b: b.__name__)
def test_every_covered_group_kind_with_gravity_and_loads(builder):
    """Each group kind of tests/_mechanisms (dyads RRR ... PRP, slot groups RS, PS, the crank
    and the linear driver) is compiled; with gravity and every kind of load (point forces,
    one from the frame, a couple, a spring, a damper), shaking moment about a point off the
    origin: the NumPy path's numbers to 1e-12 of scale, and the power and momentum balances
    hold on the compiled numbers."""
    mech, phi, kind = builder()
    assert mech.structure.groups[-1].kind == kind
    assert reactions.encode(mech) is not None
    kin = kinematics(mech, phi)
    ld = loads_for(mech, phi)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
    assert "_cos_sin" in kin.__dict__  # the loads' cos, sin of the bodies: the kernel's too
    d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
    assert_agree(d0, d1)
    assert_balances(d1, GRAVITY)


@pytest.mark.parametrize("builder", COVERED, ids=lambda b: b.__name__)
def test_every_covered_group_kind_without_loads(builder):
    """No loads and no gravity (the kernel's path without load resultants, its own cos and
    sin of the bodies' angles): the NumPy numbers, and the balances (the shaking force is
    then -sum m a_C)."""
    mech, phi, _ = builder()
    kin = kinematics(mech, phi)
    d1 = inverse_dynamics(kin, backend="numba")
    assert "_cos_sin" not in kin.__dict__
    d0 = inverse_dynamics(kin)
    assert_agree(d0, d1)
    assert_balances(d1, (0.0, 0.0))




@pytest.mark.parametrize("build", [five_bar, crank_and_ram], ids=lambda b: b.__name__)
def test_several_drivers(build):
    """Two drivers (two cranks; a crank and a linear actuator), each a group of its own: Q of
    shape (2, n) as the NumPy path gives it, and the balances with both drivers' power."""
    mech = build()
    assert reactions.encode(mech) is not None
    t = np.linspace(0.0, 1.0, 21)
    q = np.array(mech.drawing.positions)[:, None] + np.array([0.4, -0.3])[:, None] * t
    if build is crank_and_ram:
        q[1] = mech.drawing.positions[1] + 0.02 * t
    kin = kinematics(mech, q, [[8.0], [-5.0]] if build is five_bar else [[8.0], [0.3]],
                     [[2.0], [1.0]])
    ld = loads_for(mech, t)
    d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
    assert d1.Q.shape == (2, t.size)
    assert_agree(d0, d1)
    assert_balances(d1, GRAVITY)


def varied(mech: Mechanism, f: float) -> Mechanism:
    """Another design of ``mech``: the frame's points moved by ``f - 1`` of their distance
    from the origin, the moving bodies' masses, inertias and centres of mass scaled by f."""
    frame = dataclasses.replace(mech.frame, points={k: (v[0] * f, v[1] * f)
                                                    for k, v in mech.frame.points.items()})
    bodies = tuple(Body(b.name, b.points, mass=b.mass * f, com=(b.com[0] * f, b.com[1] / f),
                        inertia=b.inertia * f) for b in mech.bodies)
    return Mechanism(frame, bodies, mech.joints, mech.driver, dict(mech.branches))


@pytest.mark.parametrize("builder", [m_rrr, m_rpr, m_ps_sine], ids=lambda b: b.__name__)
def test_batch_of_designs(builder):
    """Three designs in one batch (frame points, masses, inertias, centres of mass per
    design) in one compiled pass: each design as the compiled one-design call gives it (bit
    for bit: the same kernel on the same numbers), and the NumPy batch to 1e-12 of scale;
    with loads (design by design, as the NumPy path does) likewise."""
    mech, phi, _ = builder()
    ms = [varied(mech, f) for f in (1.0, 1.04, 0.97)]
    batch = stack(ms)
    kin = kinematics(batch, phi)
    for ld in ([], loads_for(mech, phi)):
        d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
        d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
        assert d1.fx.shape == (len(mech.joints), 3, phi.size)
        assert_agree(d0, d1)
        for i in range(3):
            one = inverse_dynamics(kin.design(i), gravity=GRAVITY, loads=ld, about=ABOUT,
                                   backend="numba")
            for name in ARRAYS:
                np.testing.assert_array_equal(getattr(d1, name)[..., i, :],
                                              getattr(one, name), err_msg=name)


def test_batch_of_fourbars_with_branches_per_design():
    """fourbar_mechanism with arrays over 30 designs (lengths, branches): the per-design
    geometry read by the kernel, against the NumPy batch."""
    rng = np.random.default_rng(11)
    m = 30
    mech = fourbar_mechanism(rng.uniform(0.05, 0.09, m), rng.uniform(0.28, 0.32, m),
                             rng.uniform(0.18, 0.22, m), rng.uniform(0.28, 0.31, m),
                             masses=(1.0, 2.0, 1.5), branch=np.where(rng.random(m) < 0.5, 1, -1))
    kin = kinematics(mech, np.linspace(0.0, 2 * np.pi, 37), 10.0, 3.0)
    d0 = inverse_dynamics(kin, gravity=GRAVITY, about=ABOUT)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, about=ABOUT, backend="numba")
    assert_agree(d0, d1)


def test_chunks_of_positions(monkeypatch):
    """More positions than CHUNK: with loads the compiled path takes their resultants chunk
    by chunk; against the NumPy path (which chunks too), with CHUNK = 7 over 25 positions and
    with the real CHUNK over 20,000 positions."""
    mech, _, _ = m_rrr()
    for n, chunk in ((25, 7), (20_000, dynamics.CHUNK)):
        monkeypatch.setattr(dynamics, "CHUNK", chunk)
        phi = np.linspace(0.0, 2 * np.pi, n)
        kin = kinematics(mech, phi)
        ld = loads_for(mech, phi)
        assert n > dynamics.CHUNK
        d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
        d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
        assert_agree(d0, d1)



@pytest.mark.parametrize("case", ["friction", "gears", "newton", "friction batch"])
def test_uncovered_plans_fall_back_to_the_numpy_path(case):
    """Friction (every joint), a gear pair, a class-III group solved by Newton: not compiled
    (encode gives None), and backend="numba" gives the NumPy result bit for bit."""
    if case == "gears":
        mech, phi = planetary(), np.linspace(0.0, 2 * np.pi, 13)
    elif case == "newton":
        mech, phi, _ = m_triad()
    else:
        mech, phi, _ = m_rrr()
        mech = with_friction(mech)
        if case == "friction batch":
            mech = stack([varied(mech, f) for f in (1.0, 1.05)])
    assert reactions.encode(mech) is None
    kin = kinematics(mech, phi)
    ld = [] if case == "friction batch" else loads_for(mech, phi)
    d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
    assert_identical(d0, d1)


def test_positions_that_do_not_assemble():
    """A non-Grashof four-bar over a whole turn with on_failure="nan": the compiled result
    has NaN where the NumPy result has (the unassembled positions; a revolute joint's couple
    stays 0 there, as NumPy gives it) and its numbers elsewhere."""
    mech = fourbar_mechanism(0.25, 0.2, 0.15, 0.3, masses=(1.0, 2.0, 1.5))
    phi = np.linspace(0.0, 2 * np.pi, 73)
    kin = kinematics(mech, phi, on_failure="nan")
    assert 0 < np.count_nonzero(~kin.valid) < phi.size
    ld = loads_for(mech, phi)[2:3]  # a couple: defined where the mechanism does not assemble
    d0 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
    assert np.isnan(d1.Q[~kin.valid]).all() and np.isfinite(d1.Q[kin.valid]).all()
    assert_agree(d0, d1)


@pytest.mark.parametrize("builder", [m_rrr, m_rpr, m_ps_sine, five_bar],
                         ids=lambda b: b.__name__)
def test_threads_give_the_same_result_bit_for_bit(builder):
    """threads = 2 or 3 against 1 (the elements shared among numba's threads): every array
    equal bit for bit, one design with loads and gravity over several chunks of positions,
    and a batch of designs in one pass."""
    import numba

    threads = min(3, int(numba.config.NUMBA_NUM_THREADS))
    if threads < 2:
        pytest.skip("numba has one thread here (NUMBA_NUM_THREADS)")
    if builder is five_bar:
        mech = five_bar()
        t = np.linspace(0.0, 1.0, 3001)
        kin = kinematics(mech, np.array(mech.drawing.positions)[:, None]
                         + np.array([0.4, -0.3])[:, None] * t, on_failure="nan")
        cases = [(kin, [])]
    else:
        mech, phi, _ = builder()
        phi = np.linspace(phi[0], phi[-1], 3 * dynamics.CHUNK // 2)
        kin = kinematics(mech, phi, on_failure="nan")
        batch = kinematics(stack([varied(mech, f) for f in (1.0, 1.04, 0.97)]), phi,
                           on_failure="nan")
        cases = [(kin, loads_for(mech, phi)), (batch, [])]
    for k, ld in cases:
        one = inverse_dynamics(k, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba")
        many = inverse_dynamics(k, gravity=GRAVITY, loads=ld, about=ABOUT, backend="numba",
                                threads=threads)
        for name in ARRAYS:
            np.testing.assert_array_equal(getattr(many, name), getattr(one, name), name)


def test_threads_are_checked():
    mech, phi, _ = m_rrr()
    kin = kinematics(mech, phi)
    with pytest.raises(ParameterError, match="threads = 0 is invalid"):
        inverse_dynamics(kin, backend="numba", threads=0)
    with pytest.raises(ParameterError, match="needs backend='numba'"):
        inverse_dynamics(kin, threads=2)


def test_backend_is_checked():
    """An unknown backend is a ParameterError naming the option and the known ones."""
    mech, phi, _ = m_rrr()
    kin = kinematics(mech, phi)
    with pytest.raises(ParameterError, match=r"backend.*numba"):
        inverse_dynamics(kin, backend="cuda")


@settings(max_examples=30, deadline=None)
@given(a=st.floats(0.03, 0.2), b=st.floats(0.15, 0.45), c=st.floats(0.1, 0.4),
       d=st.floats(0.15, 0.45), masses=st.tuples(*[st.floats(0.0, 5.0)] * 3),
       branch=st.sampled_from([1, -1]), w=st.floats(-50.0, 50.0), e=st.floats(-200.0, 200.0))
def test_random_fourbars(a, b, c, d, masses, branch, w, e):
    """Random four-bars (Grashof or not: NaN where they do not assemble), masses (massless
    links included), driver speeds and accelerations: the NumPy numbers to 1e-12 of
    scale."""
    mech = fourbar_mechanism(a, b, c, d, masses=masses, branch=branch)
    kin = kinematics(mech, np.linspace(0.0, 2 * np.pi, 19), w, e, on_failure="nan")
    d0 = inverse_dynamics(kin, gravity=GRAVITY, about=ABOUT)
    d1 = inverse_dynamics(kin, gravity=GRAVITY, about=ABOUT, backend="numba")
    assert_agree(d0, d1)
