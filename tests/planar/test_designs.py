"""Designs in batches (linkwork.planar.designs): a batch of m designs evaluated in one call
against the same designs one by one.

Reference: the one-design engine itself, design by design (``mech.design(i)`` and the
mechanisms the batch was stacked from). Blocks of designs are solved on arrays that hold each
element's design values, so the arithmetic per element is the one-design arithmetic: results
are compared bit for bit where the same operations run, else to 1e-12 of each quantity's
scale (rounding of the same formulas).
"""

from __future__ import annotations

import dataclasses
import importlib

import numpy as np
import pytest
from _mechanisms import BUILDERS
from _sketches import drawing_of
from hypothesis import given, settings
from hypothesis import strategies as st

import linkwork.planar as pl
from linkwork.errors import AssemblyError, ParameterError
from linkwork.planar import (
    Body,
    Mechanism,
    crank_slider_mechanism,
    fourbar_mechanism,
    kinematics,
    stack,
)

kin_module = importlib.import_module("linkwork.planar.kinematics")
FIELDS = ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "eps")


def scaled(mech: Mechanism, f: float) -> Mechanism:
    """The mechanism with every length times ``f`` (points, centres of mass, guide points,
    guess positions; inertias times f^2): the same structure, other numbers."""

    def body(b: Body) -> Body:
        g = None if b.guess is None else (b.guess[0] * f, b.guess[1] * f, b.guess[2])
        return Body(b.name, {k: (v[0] * f, v[1] * f) for k, v in b.points.items()},
                    mass=b.mass, com=(b.com[0] * f, b.com[1] * f), inertia=b.inertia * f * f,
                    guess=g)

    joints = []
    for j in mech.joints:
        t = getattr(j, "through", None)
        if isinstance(t, tuple):
            j = dataclasses.replace(j, through=(t[0] * f, t[1] * f))
        joints.append(j)
    return Mechanism(body(mech.frame), tuple(body(b) for b in mech.bodies), tuple(joints),
                     mech.driver, dict(mech.branches))


def driver_positions(mech: Mechanism, q: np.ndarray, f: float) -> np.ndarray:
    """Driver positions of the scaled mechanism: slides times f, crank angles as they are."""
    return q * f if mech.driver.kind == "linear" else q


def assert_same(batch, one, i: int, rtol: float = 0.0) -> None:
    """Design i of a batch result against the one-design result (bit for bit, or to rtol of
    each field's scale)."""
    for name in FIELDS:
        b, o = getattr(batch, name)[:, i], getattr(one, name)
        scale = max(float(np.max(np.abs(o[np.isfinite(o)]), initial=0.0)), 1e-300)
        np.testing.assert_allclose(b, o, rtol=0, atol=rtol * scale, err_msg=name)
    np.testing.assert_array_equal(batch.valid[i], one.valid)


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_batch_equals_designs_one_by_one_for_every_group_kind(builder):
    """Three designs of each group kind (scaled by 1, 1.07, 0.93, a slide driver's positions
    scaled alike: positions per design) in one call, against each alone: bit for bit."""
    mech, q, kind = builder()
    factors = (1.0, 1.07, 0.93)
    ms = [scaled(mech, f) for f in factors]
    batch = stack(ms)
    assert batch.n_designs == 3
    assert batch.structure.groups[-1].kind == kind or kind == "newton"
    qs = np.array([driver_positions(mech, q, f) for f in factors])
    res = kinematics(batch, qs if mech.driver.kind == "linear" else q)
    assert res.x.shape == (len(mech.body_names), 3, q.size)
    assert res.valid.shape == (3, q.size)
    for i, (m, f) in enumerate(zip(ms, factors, strict=True)):
        one = kinematics(m, driver_positions(mech, q, f))
        assert_same(res, one, i)
        d = res.design(i)
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(d, name), getattr(one, name))


def test_fourbar_builder_takes_arrays_over_the_designs():
    """fourbar_mechanism(a, b, c, d) with arrays: one batch; design i is the four-bar of the
    i-th lengths (bit for bit), and its numbers are those of the closed form
    (linkwork.models.fourbar, an independent algorithm) to 1e-12."""
    from linkwork.models.fourbar import fourbar

    rng = np.random.default_rng(7)
    m = 40
    a = rng.uniform(0.05, 0.09, m)
    b = rng.uniform(0.28, 0.32, m)
    c = rng.uniform(0.18, 0.22, m)
    d = rng.uniform(0.28, 0.31, m)
    br = np.where(rng.random(m) < 0.5, 1, -1)
    phi = np.linspace(0.0, 2 * np.pi, 73)
    mech = fourbar_mechanism(a, b, c, d, masses=(1.0, 2.0, 1.5), branch=br)
    res = kinematics(mech, phi, 10.0, 3.0)
    for i in (0, 7, 39):
        one = kinematics(fourbar_mechanism(a[i], b[i], c[i], d[i], masses=(1.0, 2.0, 1.5),
                                           branch=int(br[i])), phi, 10.0, 3.0)
        assert_same(res, one, i)
    ref = fourbar(phi, a[:, None], b[:, None], c[:, None], d[:, None], 10.0, 3.0)
    for i in range(m):  # the closed form takes one branch per call
        r = fourbar(phi, a[i], b[i], c[i], d[i], 10.0, 3.0, branch=int(br[i]))
        for mine, theirs in ((res.theta[3, i], r.theta4), (res.omega[2, i], r.omega3),
                             (res.eps[3, i], r.eps4)):
            scale = np.abs(theirs).max()
            np.testing.assert_allclose(np.remainder(mine - theirs + np.pi, 2 * np.pi) - np.pi
                                       if mine is res.theta[3, i] else mine - theirs, 0,
                                       atol=1e-12 * max(scale, 1.0))
    assert ref.valid.all()


def test_crank_slider_builder_takes_arrays_and_per_design_speeds():
    """crank_slider_mechanism with per-design crank, rod, offset and guide angle; speeds per
    design (m, 1) and per position (n,) broadcast against each other."""
    r = np.array([0.05, 0.06, 0.04])
    l_ = np.array([0.2, 0.22, 0.19])
    e = np.array([0.01, -0.02, 0.0])
    ga = np.array([0.0, 0.3, -0.2])
    mech = crank_slider_mechanism(r, l_, e, guide_angle=ga, masses=(1, 2, 3))
    phi = np.linspace(0, 2 * np.pi, 37)
    w = np.array([[5.0], [7.0], [-3.0]])
    eps = np.sin(phi)
    res = kinematics(mech, phi, w, eps)
    for i in range(3):
        one = kinematics(crank_slider_mechanism(r[i], l_[i], e[i], guide_angle=ga[i],
                                                masses=(1, 2, 3)), phi, w[i, 0], eps)
        assert_same(res, one, i)
    assert res.omega1.shape == (3, 37)


def test_designs_that_do_not_assemble_have_their_own_masks():
    """A batch with a design that cannot assemble over part of the turn (a crank too long for
    its coupler and rocker) and one that never assembles: on_failure='nan' marks exactly the
    positions of each design that a one-design analysis marks; 'raise' names the designs."""
    a = np.array([0.1, 0.25, 0.1, 0.9])
    mech = fourbar_mechanism(a, 0.3, 0.2, 0.3)
    phi = np.linspace(0, 2 * np.pi, 91)
    res = kinematics(mech, phi, on_failure="nan")
    for i in range(4):
        one = kinematics(fourbar_mechanism(a[i], 0.3, 0.2, 0.3), phi, on_failure="nan")
        np.testing.assert_array_equal(res.valid[i], one.valid)
        assert_same(res, one, i)
    assert res.valid[0].all() and res.valid[2].all()
    assert not res.valid[1].all() and res.valid[1].any()
    assert not res.valid[3].any()
    with pytest.raises(AssemblyError, match=r"in 2 of 4 designs: design 1 at phi1 .*; "
                                            r"design 3 at phi1") as exc:
        kinematics(mech, phi)
    assert exc.value.designs == [1, 3]


def test_per_design_branches_and_branch_overrides():
    """Branches per design in the mechanism and as a kinematics override: each design on its
    own branch, as analysed alone; an override of the wrong length is named."""
    mech = fourbar_mechanism(np.array([0.1, 0.1, 0.1]), 0.3, 0.2, 0.3, branch=[1, -1, 1])
    phi = np.linspace(0, 2 * np.pi, 19)
    res = kinematics(mech, phi)
    over = kinematics(mech, phi, branches={"B": np.array([-1, 1, -1])})
    for i, (b0, b1) in enumerate(((1, -1), (-1, 1), (1, -1))):
        assert_same(res, kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=b0), phi), i)
        assert_same(over, kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=b1), phi), i)
    with pytest.raises(ParameterError, match=r"branches\.B = 2 branches .*one per design"):
        kinematics(mech, phi, branches={"B": np.array([1, -1])})
    with pytest.raises(ParameterError, match=r"branches\.B = 0 .*must be \+1 or -1"):
        fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=np.array([1, 0]))


def test_large_blocks_and_long_cycles_chunk_alike():
    """Many designs in blocks of designs, and designs with more positions than a chunk one at
    a time in chunks of positions: the same numbers as one by one."""
    rng = np.random.default_rng(3)
    m = 9
    a = rng.uniform(0.05, 0.09, m)
    mech = fourbar_mechanism(a, 0.3, 0.2, 0.3)
    long = np.linspace(0, 2 * np.pi, kin_module._CHUNK + 77)
    res = kinematics(mech, long)
    for i in (0, 8):
        assert_same(res, kinematics(fourbar_mechanism(a[i], 0.3, 0.2, 0.3), long), i)
    many = fourbar_mechanism(rng.uniform(0.05, 0.09, 700), 0.3, 0.2, 0.3)
    phi = np.linspace(0, 2 * np.pi, 25)
    res = kinematics(many, phi)
    assert res.x.shape == (4, 700, 25)
    for i in (0, 327, 328, 699):  # both sides of a block boundary (8192 // 25 = 327)
        assert_same(res, kinematics(many.design(i), phi), i)


def test_several_drivers_in_a_batch():
    """A two-crank five-bar, three designs: driver positions (n_drivers, n) shared by the
    designs or (n_drivers, m, n) per design, against each design alone."""
    designs = []
    for f in (1.0, 1.1, 0.9):
        frame = Body("frame", {"O1": (0.0, 0.0), "O2": (0.2 * f, 0.0)})
        bodies = (pl.bar("c1", "O1", "A", 0.08 * f), pl.bar("c2", "O2", "B", 0.08 * f),
                  pl.bar("l1", "A", "P", 0.2 * f), pl.bar("l2", "B", "P", 0.2 * f))
        joints = (pl.Revolute("O1", "frame", "c1"), pl.Revolute("O2", "frame", "c2"),
                  pl.Revolute("A", "c1", "l1"), pl.Revolute("B", "c2", "l2"),
                  pl.Revolute("P", "l1", "l2"))
        designs.append(Mechanism(frame, bodies, joints, (pl.Crank("O1"), pl.Crank("O2"))))
    batch = stack(designs)
    t = np.linspace(0, 1, 11)
    q = np.array([1.2 + 0.5 * t, 2.0 - 0.4 * t])
    res = kinematics(batch, q, [2.0, -1.0], 0.0)
    per = kinematics(batch, np.stack([q] * 3, axis=1))
    for i, m in enumerate(designs):
        one = kinematics(m, q, [2.0, -1.0], 0.0)
        assert_same(res, one, i)
        assert_same(per, kinematics(m, q), i)


def test_stack_and_design_are_inverse():
    """stack(ms).design(i) has the numbers of ms[i]; a one-design mechanism's design(0) is
    itself; structures that differ are named."""
    ms = [fourbar_mechanism(a, 0.3, 0.2, 0.3, masses=(1, m2, 1)) for a, m2 in
          ((0.1, 2.0), (0.11, 2.5))]
    batch = stack(ms)
    for i, m in enumerate(ms):
        d = batch.design(i)
        assert d.n_designs is None
        assert d.body("crank").points == m.body("crank").points
        assert d.body("coupler").mass == m.body("coupler").mass
    assert batch.body("rocker").mass == 1  # equal in every design: kept a number
    assert ms[0].design(0) is ms[0]
    with pytest.raises(ParameterError, match=r"mechanisms\[1\] = .*differs from mechanisms"):
        stack([ms[0], crank_slider_mechanism(0.1, 0.3)])
    with pytest.raises(ParameterError, match=r"i = 2 .*design index in \[0, 2\)"):
        batch.design(2)


def test_per_design_values_of_different_lengths_are_named():
    with pytest.raises(ParameterError, match=r"must hold as many designs as"):
        fourbar_mechanism(np.array([0.1, 0.11]), np.array([0.3, 0.3, 0.3]), 0.2, 0.3)
    with pytest.raises(ParameterError, match=r"phi1 = \(2, 5\) .*shape \(n,\) or \(3, n\)"):
        kinematics(fourbar_mechanism(np.full(3, 0.1), 0.3, 0.2, 0.3), np.zeros((2, 5)))


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(0.03, 0.12), st.floats(0.2, 0.35), st.floats(0.15, 0.3),
                          st.floats(0.2, 0.35), st.sampled_from([1, -1])),
                min_size=1, max_size=6),
       st.integers(1, 40))
def test_any_batch_of_four_bars_is_its_designs(designs, n):
    """Property: any batch of four-bars (assembling or not, either branch) over any number of
    positions gives, design by design, the one-design results and masks bit for bit."""
    a, b, c, d, br = (np.array(v) for v in zip(*designs, strict=True))
    phi = np.linspace(0.1, 6.0, n)
    res = kinematics(fourbar_mechanism(a, b, c, d, branch=br), phi, 2.0, on_failure="nan")
    for i in range(len(designs)):
        one = kinematics(fourbar_mechanism(a[i], b[i], c[i], d[i], branch=int(br[i])), phi,
                         2.0, on_failure="nan")
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(res, name)[:, i], getattr(one, name))
        np.testing.assert_array_equal(res.valid[i], one.valid)


DYN = ("fx", "fy", "mz", "px", "py", "Q", "shaking_fx", "shaking_fy", "shaking_m", "T",
       "Q_frictionless", "friction_power", "kappa")


def assert_same_dynamics(batch, one, i: int, rtol: float) -> None:
    """Design i of a batch's inverse dynamics against the design's own, to rtol of each
    field's scale (0: bit for bit); moments and the driving load also to rtol of the largest
    force times the largest length (a couple that is zero but for rounding)."""

    def top(a):
        return float(np.max(np.abs(a[np.isfinite(a)]), initial=0.0))

    moment = top(np.array([one.fx, one.fy])) * max(top(np.array([one.px, one.py])), 1.0)
    for name in DYN:
        b, o = getattr(batch, name)[..., i, :], getattr(one, name)
        finite = np.isfinite(o)
        np.testing.assert_array_equal(np.isfinite(b), finite, err_msg=name)
        scale = max(top(o), moment if name in ("mz", "shaking_m", "Q", "Q_frictionless")
                    else 0.0, 1e-300)
        np.testing.assert_allclose(b[finite], o[finite], rtol=0, atol=rtol * scale,
                                   err_msg=name)
    np.testing.assert_array_equal(batch.locked[i], one.locked)


@pytest.mark.parametrize("builder", BUILDERS, ids=lambda b: b.__name__)
def test_batch_inverse_dynamics_equals_designs_one_by_one(builder):
    """Reactions, driving load, shaking loads and kinetic energy of three designs with gravity
    in one call, against each design alone: to 1e-13 of each quantity's scale (the block path
    forms the bodies' moments about their origins from the state's rotated centres of mass,
    the one-design path from the centres' world positions: the same to rounding)."""
    mech, q, _ = builder()
    factors = (1.0, 1.07, 0.93)
    ms = [scaled(mech, f) for f in factors]
    qs = np.array([driver_positions(mech, q, f) for f in factors])
    res = kinematics(stack(ms), qs if mech.driver.kind == "linear" else q, 3.0, 1.5)
    dyn = pl.inverse_dynamics(res, gravity=(0.0, -9.81), about=(0.1, 0.05))
    assert dyn.fx.shape == (len(mech.joints), 3, q.size)
    for i, (m, f) in enumerate(zip(ms, factors, strict=True)):
        one = pl.inverse_dynamics(kinematics(m, driver_positions(mech, q, f), 3.0, 1.5),
                                  gravity=(0.0, -9.81), about=(0.1, 0.05))
        assert_same_dynamics(dyn, one, i, 1e-13)


@pytest.mark.parametrize("builder", BUILDERS[:4], ids=lambda b: b.__name__)
def test_batch_with_friction_and_loads_equals_designs_one_by_one(builder):
    """Friction in every joint and a load (a spring from the frame to the last body): design
    by design inside the call, bit for bit the designs alone."""
    from _mechanisms import with_friction

    mech, q, _ = builder()
    ms = [with_friction(scaled(mech, f)) for f in (1.0, 1.05)]
    body = mech.bodies[-1]
    pt = next(iter(body.points))
    spring = pl.Spring("frame", (0.0, -0.2), body.name, pt, stiffness=300.0, free_length=0.1)
    res = kinematics(stack(ms), q if mech.driver.kind != "linear"
                     else np.array([q, q * 1.05]), 4.0)
    dyn = pl.inverse_dynamics(res, gravity=(0.0, -9.81), loads=[spring])
    for i, m in enumerate(ms):
        one = pl.inverse_dynamics(kinematics(m, res.design(i).phi1, 4.0), gravity=(0.0, -9.81),
                                  loads=[spring])
        assert_same_dynamics(dyn, one, i, 0.0)
        np.testing.assert_array_equal(dyn.load_power[:, i], one.load_power)
        np.testing.assert_array_equal(dyn.loads[0].value[i], one.loads[0].value)


def _batch_of(drawings):
    """Per-design drawings as one mapping of point -> (xs, ys) arrays over the designs."""
    return {p: (np.array([d[p][0] for d in drawings]), np.array([d[p][1] for d in drawings]))
            for p in drawings[0]}


def test_sketch_takes_drawings_of_many_designs():
    """sketch() with every drawn coordinate an array over the designs: one batch whose design
    i is sketch() of drawing i, with each design's branch taken from its own drawing (the
    Stephenson III six-bar drawn at five crank angles on branches (B, D) = (+1, -1), two more
    drawn crossed (-1, +1)). The batch takes the drawing's angles by NumPy's trigonometric
    functions, one design by Python's math module: the local coordinates agree to 1e-15 m and
    the motion to 1e-12 of each quantity's scale (both are rounding)."""
    from _mechanisms import stephenson_sixbar

    ref = stephenson_sixbar()[0]
    crossed = ref.with_branches(B=-1, D=1)
    drawings = [drawing_of(ref, a) for a in (0.3, 1.1, 2.0, 3.5, 5.2)]
    drawings += [drawing_of(crossed, a) for a in (0.7, 4.0)]
    links = {b.name: list(b.points) for b in ref.bodies}
    batch = pl.sketch(_batch_of(drawings), links, ground=list(ref.frame.points),
                      drivers="O2", masses={"crank": 1.0, "link5": 1.5})
    assert batch.n_designs == 7
    np.testing.assert_array_equal(batch.branches["B"], [1, 1, 1, 1, 1, -1, -1])
    np.testing.assert_array_equal(batch.branches["D"], [-1, -1, -1, -1, -1, 1, 1])
    phi = np.linspace(0.0, 2 * np.pi, 49)
    res = kinematics(batch, phi, 3.0)
    for i, d in enumerate(drawings):
        one = pl.sketch(d, links, ground=list(ref.frame.points), drivers="O2",
                        masses={"crank": 1.0, "link5": 1.5})
        mine = batch.design(i)
        assert mine.branches == one.branches
        for b1, b2 in zip(mine.bodies, one.bodies, strict=True):
            assert (b1.mass, b1.inertia) == (b2.mass, b2.inertia)
            for p in b1.points:
                np.testing.assert_allclose(b1.points[p], b2.points[p], rtol=0, atol=1e-15)
            np.testing.assert_allclose(b1.guess, b2.guess, rtol=0, atol=1e-15)
        assert_same(res, kinematics(one, phi, 3.0), i, 1e-12)
    # every design is the same mechanism (or its crossed assembly): the same coupler point C
    for i in range(5):
        c, c0 = res.design(i).point("coupler", "C"), kinematics(ref, phi, 3.0).point(
            "coupler", "C")
        np.testing.assert_allclose(c.x, c0.x, rtol=0, atol=1e-12)
        np.testing.assert_allclose(c.ay, c0.ay, rtol=0, atol=1e-9)


def test_sketch_batch_with_sliders_and_newton_groups():
    """A crank-slider drawn with its guide (per-design angles and offsets) and the class-III
    triad (Newton, continued from each design's drawing): each design as sketched alone, to
    1e-12 of each quantity's scale (see the test above)."""
    from _mechanisms import m_triad

    ref, phi, _ = m_triad()
    drawings = [drawing_of(scaled(ref, f), phi[3]) for f in (1.0, 1.02, 0.99)]
    links = {b.name: list(b.points) for b in ref.bodies}
    batch = pl.sketch(_batch_of(drawings), links, ground=list(ref.frame.points), drivers="O")
    res = kinematics(batch, phi)
    for i, d in enumerate(drawings):
        one = pl.sketch(d, links, ground=list(ref.frame.points), drivers="O")
        assert_same(res, kinematics(one, phi), i, 1e-12)
    cs = [crank_slider_mechanism(0.05, 0.2, e, guide_angle=g) for e, g in
          ((0.01, 0.0), (-0.02, 0.3), (0.0, -0.2))]
    drawings = [{p: v for p, v in drawing_of(m, 0.9).items() if p in "OAB"} for m in cs]
    ang = np.array([0.0, 0.3, -0.2])
    batch = pl.sketch(_batch_of(drawings), {"crank": ["O", "A"], "rod": ["A", "B"]},
                      ground=["O"], drivers="O", sliders={"s": pl.Slider("B", "frame", ang)})
    phi = np.linspace(0, 2 * np.pi, 31)
    res = kinematics(batch, phi)
    for i, d in enumerate(drawings):
        one = pl.sketch(d, {"crank": ["O", "A"], "rod": ["A", "B"]}, ground=["O"],
                        drivers="O", sliders={"s": pl.Slider("B", "frame", float(ang[i]))})
        assert_same(res, kinematics(one, phi), i, 1e-12)


def test_sketch_batch_names_the_design_that_is_not_drawn_assembled():
    """A slider point drawn off its guide line (through two ground points) in one design of
    three: the error names that design."""
    ms = [crank_slider_mechanism(0.05, 0.2, 0.0, guide_angle=0.0) for _ in range(3)]
    drawings = [{p: v for p, v in drawing_of(m, a).items() if p in "OAB"}
                for m, a in zip(ms, (0.5, 1.5, 2.5), strict=True)]
    drawings[2]["B"] = (drawings[2]["B"][0], 0.003)
    for d in drawings:
        d.update(G1=(-1.0, 0.0), G2=(1.0, 0.0))
    with pytest.raises(AssemblyError, match=r"'B' of sliders\.s is 3 mm off .*\(design 2\)"):
        pl.sketch(_batch_of(drawings), {"crank": ["O", "A"], "rod": ["A", "B"]},
                  ground=["O", "G1", "G2"], drivers="O",
                  sliders={"s": pl.Slider("B", "frame", along=("G1", "G2"))})


def test_batch_inverse_dynamics_in_blocks_and_chunks_equals_designs_one_by_one():
    """The batch's blocks and the one-design chunks of inverse_dynamics compose under one bound
    (planar.dynamics.CHUNK elements): designs with more positions than a chunk (one design's
    positions per block) and many designs of a short cycle (blocks across designs, both sides
    of a block boundary) against each design alone, which is solved in chunks of positions
    (to 1e-13 of each quantity's scale, as above); with a load, design by design inside the
    call and each design chunked: bit for bit."""
    chunk = importlib.import_module("linkwork.planar.dynamics").CHUNK
    a = np.array([0.08, 0.1])
    masses = (1.0, 3.0, 2.0)
    long = np.linspace(0, 2 * np.pi, chunk + 77)
    mech = fourbar_mechanism(a, 0.3, 0.2, 0.3, masses=masses)
    dyn = pl.inverse_dynamics(kinematics(mech, long, 5.0), gravity=(0.0, -9.81))
    for i in range(2):
        one = pl.inverse_dynamics(kinematics(mech.design(i), long, 5.0), gravity=(0.0, -9.81))
        assert_same_dynamics(dyn, one, i, 1e-13)
    spring = pl.Spring("frame", (0.0, -0.2), "rocker", "B", stiffness=300.0, free_length=0.1)
    dyn = pl.inverse_dynamics(kinematics(mech, long, 5.0), loads=[spring])
    for i in range(2):
        one = pl.inverse_dynamics(kinematics(mech.design(i), long, 5.0), loads=[spring])
        assert_same_dynamics(dyn, one, i, 0.0)
    many = fourbar_mechanism(np.linspace(0.06, 0.1, 700), 0.3, 0.2, 0.3, masses=masses)
    phi = np.linspace(0, 2 * np.pi, 25)
    dyn = pl.inverse_dynamics(kinematics(many, phi, 5.0), gravity=(0.0, -9.81))
    assert dyn.fx.shape == (4, 700, 25)
    for i in (0, 327, 328, 699):  # both sides of a block boundary (8192 // 25 = 327)
        one = pl.inverse_dynamics(kinematics(many.design(i), phi, 5.0), gravity=(0.0, -9.81))
        assert_same_dynamics(dyn, one, i, 1e-13)
