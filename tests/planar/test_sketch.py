"""linkwork.planar.sketch: a mechanism from its drawing.

References: each mechanism is also built by hand in the engine (local frames, joints and
branches written out, as ``tests/_mechanisms.py`` does); its kinematics at a drawn position gives
the world coordinates of every point, the drawing. The sketched mechanism must reproduce every
drawn point at the drawn driver position (round trip, to 1e-9 of the mechanism's size: rounding
alone gives ~1e-16) and the hand-built one's positions, velocities, accelerations and driving
torque over a whole range (1e-9 of their scale), whichever branch the drawing shows.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _mechanisms import m_ps_sine, m_rrr, m_triad, stephenson_sixbar
from _sketches import drawing_of
from hypothesis import given, settings
from hypothesis import strategies as st

from linkwork.errors import AssemblyError, ParameterError, StructureError
from linkwork.planar import (
    LinkMass,
    Slider,
    Slot,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
    sketch,
)


def assert_same_motion(k1, k2, bodies_points, scale):
    """Positions, velocities and accelerations of every (body, point) agree to 1e-9 of their
    scale (lengths ``scale``, speeds scale*max|omega|, ...)."""
    w = max(float(np.max(np.abs(k2.omega))), 1.0)
    e = max(float(np.max(np.abs(k2.eps))), w * w)
    for body, p in bodies_points:
        a, b = k1.point(body, p), k2.point(body, p)
        for f, s in (("x", 1), ("y", 1), ("vx", w), ("vy", w), ("ax", e), ("ay", e)):
            err = np.max(np.abs(getattr(a, f) - getattr(b, f)))
            assert err <= 1e-9 * scale * s, (body, p, f, err)


def links_of(mech):
    return {b.name: list(b.points) for b in mech.bodies}


@pytest.mark.parametrize("branch", [1, -1])
def test_fourbar_branch_taken_from_the_drawing(branch):
    """Norton's four-bar drawn on either circuit: the sketch takes that circuit (the drawing's
    B on the left or right of A -> O4) and moves as fourbar_mechanism(..., branch)."""
    ref = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), branch=branch)
    pts = drawing_of(ref, math.radians(40.0))
    mech = sketch(pts, links_of(ref), ground=["O2", "O4"], drivers="O2",
                  masses={"crank": 1.0, "coupler": 3.0, "rocker": 2.0})
    assert dict(mech.branches) == {"B": branch}
    assert mech.drawing.positions == pytest.approx((math.radians(40.0),), abs=1e-15)
    phi = np.linspace(0.0, 2 * np.pi, 37)
    k1, k2 = kinematics(mech, phi, 7.0, 3.0), kinematics(ref, phi, 7.0, 3.0)
    assert_same_motion(k1, k2, [("coupler", "B"), ("rocker", "B"), ("crank", "A"),
                                ("coupler", "com"), ("rocker", "com")], 0.3)
    d1, d2 = inverse_dynamics(k1, gravity=(0, -9.81)), inverse_dynamics(k2, gravity=(0, -9.81))
    scale = float(np.max(np.abs(d2.Q)))
    assert np.max(np.abs(d1.Q - d2.Q)) <= 1e-9 * scale


@pytest.mark.parametrize("build", [m_rrr, m_triad, stephenson_sixbar])
def test_revolute_mechanisms_round_trip(build):
    """Revolute mechanisms (a four-bar, a class-III triad solved by Newton, a Stephenson III
    six-bar on branches +1 and -1) drawn at a middle position: every drawn point reproduced at
    the drawn driver position, and the motion over the range equals the hand-built one's (the
    triad continued by Newton from the drawing back to the range's start)."""
    out = build()
    ref, phi = out[0], np.asarray(out[1]) if len(out) > 1 and np.ndim(out[1]) else None
    if phi is None:
        phi = np.linspace(0.0, 2 * np.pi, 25)
    at = float(phi[len(phi) // 2])
    pts = drawing_of(ref, at)
    mech = sketch(pts, links_of(ref), ground=list(ref.frame.points), drivers=ref.driver.joint)
    for key, b in ref.branches.items():
        assert mech.branches.get(key, 1) == b
    k0 = kinematics(mech, [at])
    for b in mech.bodies:
        for p in b.points:
            pm = k0.point(b.name, p)
            assert math.hypot(pm.x[0] - pts[p][0], pm.y[0] - pts[p][1]) <= 1e-12
    pairs = [(b.name, p) for b in ref.bodies for p in b.points]
    assert_same_motion(kinematics(mech, phi, 2.0, 0.5), kinematics(ref, phi, 2.0, 0.5), pairs,
                       1.0)


def test_crank_slider_with_a_drawn_slider():
    """An offset crank-slider whose guide is drawn at 30 deg through the slider's point: the
    same motion and driving torque as crank_slider_mechanism (offset 25 mm, guide 30 deg)."""
    g = math.radians(30.0)
    ref = crank_slider_mechanism(0.05, 0.2, 0.025, guide_angle=g, masses=(1.0, 2.0, 3.0),
                                 branch=-1)
    pts = drawing_of(ref, 1.0)
    del pts["G"]
    mech = sketch(pts, {"crank": ["O", "A"], "rod": ["A", "B"]}, ground=["O"], drivers="O",
                  sliders={"slider": Slider("B", "frame", angle=g)},
                  masses={"crank": 1.0, "rod": 2.0, "slider": 3.0})
    assert dict(mech.branches) == {"B": -1}
    phi = np.linspace(0.0, 2 * np.pi, 49)
    k1, k2 = kinematics(mech, phi, 12.0, -4.0), kinematics(ref, phi, 12.0, -4.0)
    assert_same_motion(k1, k2, [("slider", "B"), ("rod", "com"), ("crank", "A")], 0.25)
    d1, d2 = inverse_dynamics(k1), inverse_dynamics(k2)
    assert np.max(np.abs(d1.Q - d2.Q)) <= 1e-9 * np.max(np.abs(d2.Q))
    assert np.max(np.abs(d1.reaction_magnitude("slider") - d2.reaction_magnitude("G"))) <= (
        1e-9 * np.max(d2.reaction_magnitude("G")))


def test_linear_driver_slide_is_measured_from_the_foot_of_the_origin():
    """A slider driven along a horizontal frame guide at y = 40 mm: its slide coordinate is the
    slider point's x (measured from the projection of the world origin on the guide), and the
    crank it drives turns as the inverse crank-slider (x_B = r cos(phi) + sqrt(l^2 - (e - r
    sin phi)^2))."""
    r, l, e = 0.05, 0.2, 0.04
    phi0 = 0.7
    A = (r * math.cos(phi0), r * math.sin(phi0))
    xb = A[0] + math.sqrt(l * l - (e - A[1]) ** 2)
    mech = sketch({"O": (0, 0), "A": A, "B": (xb, e)}, {"crank": ["O", "A"], "rod": ["A", "B"]},
                  ground=["O"], drivers="ram", sliders={"ram": {"point": "B", "guide": "frame",
                                                                 "angle": 0.0}})
    assert mech.drawing.positions[0] == pytest.approx(xb, abs=1e-15)
    s = np.linspace(0.2, 0.23, 7)
    kin = kinematics(mech, s)
    th = kin.angle("crank")
    # the crank's pin satisfies |B - A| = l with B = (s, e)
    assert np.max(np.abs(np.hypot(s - r * np.cos(th), e - r * np.sin(th)) - l)) <= 1e-14


def test_sine_mechanism_with_a_drawn_slot():
    """Paper 000's sine mechanism (crank pin in a 60 deg slot of a yoke sliding along x): the
    slot declared by its direction as drawn gives the same motion and driving torque as the
    hand-built m_ps_sine."""
    ref, phi, _ = m_ps_sine()
    pts = drawing_of(ref, 0.4)
    mech = sketch(pts, {"crank": ["O", "A"]}, ground=["O"], drivers="O",
                  sliders={"G": Slider("Y", "frame", angle=0.0)},
                  slots={"S": Slot("A", "G", angle=math.radians(60))},
                  masses={"crank": 1.0, "G": LinkMass(3.0, com=tuple(
                      np.add(pts["Y"], (0.05, 0.02))), inertia=0.01)})
    k1, k2 = kinematics(mech, phi, 3.0), kinematics(ref, phi, 3.0)
    assert np.max(np.abs(k1.point("G", "Y").x - k2.point("yoke", "Y").x)) <= 1e-12
    d1, d2 = inverse_dynamics(k1), inverse_dynamics(k2)
    assert np.max(np.abs(d1.Q - d2.Q)) <= 1e-9 * np.max(np.abs(d2.Q))


def test_masses_from_the_drawing():
    """A centre of mass given as a drawn point or as world coordinates lands there in the
    drawing; a two-point link defaults to a thin rod (midpoint, m L^2/12); a three-point link
    to the centroid of its points."""
    pts = {"O": (0, 0), "A": (0.0, 0.1), "B": (0.3, 0.25), "C": (0.35, 0.0), "P": (0.2, 0.3)}
    mech = sketch(pts, {"crank": ["O", "A"], "coupler": ["A", "B", "P"], "rocker": ["C", "B"]},
                  ground=["O", "C"], drivers="O",
                  masses={"crank": 2.0, "coupler": {"mass": 1.0},
                          "rocker": LinkMass(1.5, com=(0.34, 0.1), inertia=0.02)})
    kin = kinematics(mech, mech.drawing.positions)
    crank = mech.body("crank")
    assert crank.inertia == pytest.approx(2.0 * 0.1**2 / 12, rel=1e-14)
    for body, expect in (("crank", (0.0, 0.05)), ("rocker", (0.34, 0.1)),
                         ("coupler", ((0 + 0.3 + 0.2) / 3, (0.1 + 0.25 + 0.3) / 3))):
        c = kin.point(body, "com")
        assert (c.x[0], c.y[0]) == pytest.approx(expect, abs=1e-15)
    assert mech.body("coupler").inertia == 0.0
    assert mech.body("rocker").inertia == 0.02


@settings(max_examples=30, deadline=None)
@given(st.floats(0.05, 0.15), st.floats(0.25, 0.4), st.floats(0.2, 0.35),
       st.floats(0.0, 2 * math.pi), st.sampled_from([1, -1]))
def test_any_drawn_fourbar_round_trips(a, b, c, at, branch):
    """Any assemblable Grashof crank-rocker (d = 0.3 m) drawn at any crank angle on either
    branch: the sketch reproduces the drawing and the hand-built branch."""
    d = 0.3
    if not (a + max(b, c, d) < sum((b, c, d)) - max(b, c, d) - 1e-3):
        return
    ref = fourbar_mechanism(a, b, c, d, branch=branch)
    pts = drawing_of(ref, at)
    mech = sketch(pts, links_of(ref), ground=["O2", "O4"], drivers="O2")
    assert dict(mech.branches) == {"B": branch}


# -- bad drawings -------------------------------------------------------------------------------
PTS = {"O": (0.0, 0.0), "A": (0.0, 0.1), "B": (0.3, 0.25), "C": (0.35, 0.0)}
LINKS = {"crank": ["O", "A"], "coupler": ["A", "B"], "rocker": ["C", "B"]}


@pytest.mark.parametrize(("points", "links", "ground", "drivers", "error", "words"), [
    ({**PTS, "X": (1, 1)}, LINKS, ["O", "C"], "O", ParameterError, "points.X = .* on no link"),
    (PTS, {**LINKS, "stub": ["A"]}, ["O", "C"], "O", ParameterError, "links.stub"),
    (PTS, {**LINKS, "crank": ["O", "Z"]}, ["O", "C"], "O", ParameterError,
     "links.crank = Z .*no such point"),
    (PTS, LINKS, ["O", "C"], "A", ParameterError, "drivers = A .*not a frame pivot"),
    (PTS, LINKS, ["O", "C"], "nope", ParameterError, "neither a point nor a slider"),
    (PTS, {**LINKS, "crank": ["O", "O"]}, ["O", "C"], "O", ParameterError, "listed twice"),
    (PTS, {"crank": ["O", "A"], "coupler": ["A", "B"], "rocker": ["C", "B"]}, ["O"], "O",
     StructureError, "mobility"),
])
def test_bad_drawings_name_the_point_link_or_driver(points, links, ground, drivers, error,
                                                    words):
    """A point on no link, a one-point link, an unknown point, a driver on a point that is not
    a frame pivot, a name that is nothing, a point listed twice, a drawing whose mobility is
    not its number of drivers: one error naming the culprit."""
    with pytest.raises(error, match=words.replace("(", r"\(")):
        sketch(points, links, ground=ground, drivers=drivers)


def test_a_drawing_at_a_toggle_is_refused_naming_the_joint():
    """Coupler and rocker drawn collinear (B on the line A -> C): both assemblies of the RRR
    dyad coincide; the branch cannot be taken from the drawing."""
    pts = {"O": (0.0, 0.0), "A": (0.0, 0.1), "B": (0.2, 0.05), "C": (0.4, 0.0)}
    with pytest.raises(AssemblyError, match="toggle of joint 'B'"):
        sketch(pts, LINKS, ground=["O", "C"], drivers="O")


def test_a_slider_off_its_drawn_guide_is_not_assembled():
    """A guide drawn through two frame points that the slider's point is not on."""
    pts = {"O": (0, 0), "A": (0.03, 0.04), "B": (0.25, 0.002), "G1": (0.0, 0.0),
           "G2": (1.0, 0.0)}
    with pytest.raises(AssemblyError, match=r"point 'B' of sliders\.S is 2 mm off the line"):
        sketch(pts, {"crank": ["O", "A"], "rod": ["A", "B"]}, ground=["O", "G1", "G2"],
               drivers="O", sliders={"S": Slider("B", "frame", along=("G1", "G2"))})


def test_two_cranks_on_one_pivot_must_say_which():
    """Two links hinged to the frame at O: a driver 'O' alone is ambiguous; ('O', link) is
    not (the other link needs its own driver: mobility 2 here)."""
    pts = {"O": (0, 0), "A": (0.1, 0.0), "B": (0.0, 0.1), "P": (0.15, 0.15)}
    links = {"c1": ["O", "A"], "c2": ["O", "B"], "l1": ["A", "P"], "l2": ["B", "P"]}
    with pytest.raises(ParameterError, match="frame pivot of 2 links"):
        sketch(pts, links, ground=["O"], drivers="O")
