"""Mechanisms that cannot move, cannot be assembled, or are described wrongly."""

from __future__ import annotations

import numpy as np
import pytest
from _mechanisms import stephenson_sixbar
from _planar_newton_euler import _fb_full

import linkwork.planar as pl
from linkwork.errors import (
    AssemblyError,
    LinkworkError,
    ParameterError,
    StructureError,
    angle_ranges,
)
from linkwork.models import crank_slider as cs_model
from linkwork.models import fourbar as fb
from linkwork.models import fourbar as fourbar_cf
from linkwork.models import sine
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Linear,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    bar,
    crank_slider_mechanism,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
)
from linkwork.planar import fourbar_mechanism as engine_fourbar


def test_locked_triangle_names_bodies_and_joints():
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0)})
    crank = bar("crank", "O", "A", 0.1)
    rod = bar("rod", "A", "C", 0.3)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"))
    with pytest.raises(StructureError, match=r"locked.*W = 3\*2 - 2\*3 - 0 = 0.*crank"):
        Mechanism(frame, (crank, rod), joints, Crank("O")).validate()


def test_under_driven_five_bar():
    frame = Body("frame", {"O": (0, 0), "E": (0.4, 0)})
    bodies = (bar("crank", "O", "A", 0.1), bar("l2", "A", "B", 0.3), bar("l3", "B", "C", 0.3),
              bar("l4", "E", "C", 0.2))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l2"),
              Revolute("B", "l2", "l3"), Revolute("C", "l3", "l4"), Revolute("E", "frame", "l4"))
    with pytest.raises(StructureError, match="under-driven: mobility W = 3\\*4 - 2\\*5 - 0 = 2"):
        kinematics(Mechanism(frame, bodies, joints, Crank("O")), [0.0])


def test_locked_subchain_with_free_body_elsewhere():
    """W = 1 by count, but the driven crank sits in a rigid triangle, and a four-bar elsewhere
    has no driver: the error names the locked sub-chain."""
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0), "E": (0.6, 0.0), "F": (0.9, 0.0)})
    bodies = (bar("crank", "O", "A", 0.1), bar("rod", "A", "C", 0.3),
              bar("p", "E", "G", 0.1), bar("q", "G", "H", 0.3), bar("r", "F", "H", 0.2))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"), Revolute("E", "frame", "p"),
              Revolute("G", "p", "q"), Revolute("H", "q", "r"), Revolute("F", "frame", "r"))
    with pytest.raises(StructureError, match=r"sub-chain is locked: 4 constraints on 3 .*'rod'"):
        Mechanism(frame, bodies, joints, Crank("O")).validate()


def test_redundant_link_is_a_locked_subchain():
    """A parallelogram with a third parallel bar: counted W = 0 -> locked."""
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0), "E": (0.15, 0.0)})
    bodies = (bar("crank", "O", "A", 0.1, points={"M": (0.05, 0.0)}),
              bar("coupler", "A", "B", 0.3, points={"N": (0.15, 0.0)}),
              bar("rocker", "C", "B", 0.1), bar("extra", "E", "N", 0.1))
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "coupler"),
              Revolute("B", "coupler", "rocker"), Revolute("C", "frame", "rocker"),
              Revolute("E", "frame", "extra"), Revolute("N", "coupler", "extra"))
    with pytest.raises(StructureError, match=r"locked: mobility W = 3\*4 - 2\*6 - 0 = 0"):
        Mechanism(frame, bodies, joints, Crank("O")).validate()


def test_cannot_assemble_lists_ranges():
    # non-Grashof: crank 0.25 cannot turn fully with coupler 0.3, rocker 0.2, frame 0.3
    mech = fourbar_mechanism(0.25, 0.3, 0.2, 0.3)
    phi = np.radians(np.arange(0, 360, 1.0))
    with pytest.raises(AssemblyError) as exc:
        kinematics(mech, phi)
    # independent: |b - c| <= |A - O4| <= b + c
    reach = np.hypot(0.3 - 0.25 * np.cos(phi), 0.25 * np.sin(phi))
    bad = (reach > 0.5) | (reach < 0.1)
    assert exc.value.ranges == angle_ranges(phi, bad)
    assert len(exc.value.ranges) == 3
    assert "cannot assemble at phi1 in [" in str(exc.value)


def test_nan_and_mask_on_request():
    mech = fourbar_mechanism(0.25, 0.3, 0.2, 0.3)
    phi = np.radians(np.arange(0, 360, 1.0))
    k = kinematics(mech, phi, on_failure="nan")
    Ax = 0.25 * np.cos(phi)
    reach = np.hypot(0.3 - Ax, 0.25 * np.sin(phi))
    expected = (reach <= 0.5) & (reach >= 0.1)
    np.testing.assert_array_equal(k.valid, expected)
    assert np.isnan(k.theta[2][~expected]).all()
    assert np.isfinite(k.theta[2][expected]).all()
    d = inverse_dynamics(k)
    assert np.isnan(d.Q[~expected]).all() and np.isfinite(d.Q[expected]).all()


def test_bad_inputs_name_parameter():
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3)
    with pytest.raises(ParameterError, match="phi1"):
        kinematics(m, [0.0, np.nan])
    with pytest.raises(ParameterError, match="on_failure"):
        kinematics(m, [0.0], on_failure="ignore")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"branches\.B"):
        kinematics(m, [0.0], branches={"B": 2})
    with pytest.raises(ParameterError, match="omega1"):
        kinematics(m, [0.0, 1.0], omega1=[1.0, 2.0, 3.0])
    with pytest.raises(ParameterError, match="mass"):
        bar("x", "A", "B", 0.1, mass=-1.0)
    with pytest.raises(ParameterError, match="length"):
        bar("x", "A", "B", 0.0)
    with pytest.raises(ParameterError, match="no such point"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("Q", "frame", "c"),), Crank("Q"))
    with pytest.raises(ParameterError, match="unknown body"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("O", "frame", "k"),), Crank("O"))
    with pytest.raises(ParameterError, match="Linear driver needs a prismatic"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),),
                  (Revolute("O", "frame", "c"),), Linear("O"))
    with pytest.raises(ParameterError, match="unique"):
        Mechanism(Body("frame", {"O": (0, 0)}), (bar("c", "O", "A", 0.1),
                                                  bar("c", "O", "A", 0.1)),
                  (Revolute("O", "frame", "c"),), Crank("O"))
    k = kinematics(m, [0.0, 1.0])
    with pytest.raises(ParameterError, match=r"loads\[0\]\.body = frame .*moving bodies"):
        inverse_dynamics(k, loads=[PointForce("frame", "O2", 1.0, 0.0)])
    with pytest.raises(ParameterError, match="fx"):
        inverse_dynamics(k, loads=[PointForce("crank", "A", [1.0, 2.0, 3.0], 0.0)])
    with pytest.raises(ParameterError, match=r"loads\[1\]\.fy = \(3,\)"):  # which load
        inverse_dynamics(k, loads=[PointForce("crank", "A", 1.0, 0.0),
                                   PointForce("crank", "A", 0.0, [1.0, 2.0, 3.0])])
    with pytest.raises(ParameterError, match=r"loads\[0\]\.mz"):
        inverse_dynamics(k, loads=[BodyTorque("crank", [np.nan, 1.0])])
    with pytest.raises(ParameterError, match="gravity"):
        inverse_dynamics(k, gravity=(0.0, -9.81, 0.0))


def test_change_point_toggle_is_reported():
    """a + b = c + d: at phi1 = 0 coupler and rocker are collinear, velocities undefined."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.2)
    phi = np.linspace(0, 2 * np.pi, 13)
    with pytest.raises(AssemblyError, match=r"singular \(toggle\).*at phi1 in 0 deg$"):
        kinematics(mech, phi)
    k = kinematics(mech, phi, on_failure="nan")
    np.testing.assert_array_equal(k.valid, [False] + [True] * 11 + [False])
    assert np.isnan(k.omega[3][0]) and np.isfinite(k.omega[3][1:-1]).all()


def test_a_body_without_joints_is_named_as_such():
    """A body left unconnected was reported as 'under-driven: mobility W = 4' (its three free
    coordinates), which sends the user looking for a missing driver."""
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3)
    extra = (bar("lonely", "P", "Q", 0.1), bar("stray", "P", "Q", 0.1))
    with pytest.raises(StructureError, match=r"body 'lonely' has no joints"):
        Mechanism(m.frame, (*m.bodies, extra[0]), m.joints, m.driver).validate()
    with pytest.raises(StructureError, match=r"bodies 'lonely', 'stray' have no joints"):
        Mechanism(m.frame, (*m.bodies, *extra), m.joints, m.driver).validate()


PHI = np.linspace(0.0, 2 * np.pi, 13)


# -- bodies and links ---------------------------------------------------------------------------
@pytest.mark.parametrize("value, words", [
    ("10 kg", "must be a number"),                 # was: bare ValueError from float()
    (None, "must be a number"),                    # bare TypeError
    (1j, "not complex"),                           # bare TypeError
    (True, "not a boolean"),                       # accepted as 1 kg
    (np.ones((2, 2)), "single number or a 1-D array"),  # (a 1-D array: one per design)
])
@pytest.mark.parametrize("attr", ["mass", "inertia"])
def test_body_mass_and_inertia_that_are_not_numbers_are_named(attr, value, words):
    with pytest.raises(ParameterError, match=rf"^b\.{attr} = .*{words}"):
        Body("b", {"A": (0.0, 0.0)}, **{attr: value})


@pytest.mark.parametrize("guess, words", [
    ((np.nan, 0.0, 0.0), "must be finite"),        # was accepted: Newton started from NaN
    (1.0, r"must be \(x \[m\], y \[m\], theta \[rad\]\)"),   # bare TypeError
    ("abc", "must be a number"),                   # bare ValueError
])
def test_body_guess_is_checked(guess, words):
    with pytest.raises(ParameterError, match=rf"^b\.guess = .*{words}"):
        Body("b", {"A": (0.0, 0.0)}, guess=guess)


def test_body_points_none_is_named():
    with pytest.raises(ParameterError, match=r"b\.points = None .*must map point names"):
        Body("b", None)  # type: ignore[arg-type]


@pytest.mark.parametrize("kw, match", [
    ({"length": np.ones((2, 2))}, r"x\.length = .*single number"),   # (1-D: per design)
    ({"length": 0.1, "mass": "1 kg"}, r"x\.mass = 1 kg .*must be a number"),  # bare TypeError
    ({"length": 0.1, "com": "mid"}, r"x\.com = mid .*must be a number"),  # bare ValueError
    ({"length": 0.1, "com": 1j}, r"x\.com = 1j .*not complex"),          # bare TypeError
    # m L^2 / 12 overflows: was a bare OverflowError (34, 'Numerical result out of range')
    ({"length": 1e200, "mass": 1.0}, r"x\.length = 1e\+200 .*rod inertia m L\^2/12 beyond"),
])
def test_bar_arguments_are_named(kw, match):
    with pytest.raises(ParameterError, match=match):
        bar("x", "A", "B", **kw)


def test_shortcut_builders_name_per_link_tuples_and_the_guide_angle():
    with pytest.raises(ParameterError, match=r"masses = \(1, 2\) .*must have 3 entries"):
        fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 2))  # type: ignore[arg-type]  # zip() ValueError
    with pytest.raises(ParameterError, match=r"inertias = \(None,\) .*must have 2 entries"):
        crank_slider_mechanism(0.1, 0.3, inertias=(None,))  # type: ignore[arg-type]  # IndexError
    with pytest.raises(ParameterError, match=r"guide_angle = 30 deg .*must be a number"):
        crank_slider_mechanism(0.1, 0.3, guide_angle="30 deg")  # type: ignore[arg-type]  # bare TypeError


# -- joints and the mechanism ---------------------------------------------------------------------
def _slider_with_guide(**kw):
    base = crank_slider_mechanism(0.1, 0.3)
    guide = Prismatic("G", "frame", "slider", through="G", point="B", **kw)
    return Mechanism(base.frame, base.bodies, (*base.joints[:3], guide), Crank("O"))


@pytest.mark.parametrize("kw, match", [
    ({"angle": np.nan}, r"joint G\.angle = nan .*must be finite"),
    ({"rel_angle": np.inf}, r"joint G\.rel_angle = inf .*must be finite"),
])
def test_non_finite_guide_angle_is_a_parameter_error_not_an_assembly_failure(kw, match):
    """Was: 'mechanism cannot be assembled at 13 of 13 driver positions' (the NaN line of the
    guide meets no circle), which sends the user looking for wrong lengths."""
    with pytest.raises(ParameterError, match=match):
        kinematics(_slider_with_guide(**kw), PHI)


def test_a_correct_guide_for_comparison_assembles():
    k = kinematics(_slider_with_guide(angle=0.0), PHI)
    # slider on the guide y = 0 at x = r cos + sqrt(l^2 - r^2 sin^2): the independent formula
    x = 0.1 * np.cos(PHI) + np.sqrt(0.3**2 - (0.1 * np.sin(PHI)) ** 2)
    np.testing.assert_allclose(k.point("slider", "B").x, x, atol=1e-12)


def test_mechanism_parts_of_the_wrong_type_are_named():
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3)
    cases = [  # each was an AttributeError or TypeError from deep inside
        (dict(frame="frame"), r"^frame = frame is invalid: must be a Body"),
        (dict(bodies=("crank",)), r"^bodies = crank is invalid: must be Body objects"),
        (dict(joints=("O2",)),
         r"^joints = O2 is invalid: must be Revolute, Prismatic, PinInSlot or GearPair"),
        (dict(driver=None), r"^driver = None is invalid: must be Crank or Linear"),
        (dict(driver="O2"), r"^driver = O2 is invalid: must be Crank or Linear"),
        (dict(branches=None), r"^branches = None is invalid: must map group keys"),
        (dict(branches=[("B", 1)]), r"^branches = \[\('B', 1\)\] is invalid: must map"),
    ]
    parts = dict(frame=m.frame, bodies=m.bodies, joints=m.joints, driver=m.driver, branches={})
    for change, match in cases:
        with pytest.raises(ParameterError, match=match):
            Mechanism(**{**parts, **change})  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"^branches = \[1\] is invalid: must map"):
        kinematics(m, PHI, branches=[1])  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"^mech = .* must be a Mechanism"):
        kinematics("fourbar", PHI)  # type: ignore[arg-type]


@pytest.mark.parametrize("kw, match", [
    ({"through": "Z"}, r"^joint G\.through = Z is invalid: no such point of body 'frame'"),
    ({"through": "G", "point": "Z"}, r"^joint G\.point = Z .*no such point of body 'slider'"),
])
def test_missing_joint_point_names_the_joint(kw, match):
    """Was 'frame.points = Z is invalid: no such point': which joint asked for it was not said
    (in a file with many joints on the frame, the user had to search)."""
    base = crank_slider_mechanism(0.1, 0.3)
    with pytest.raises(ParameterError, match=match):
        Mechanism(base.frame, base.bodies,
                  (*base.joints[:3], Prismatic("G", "frame", "slider", **kw)), Crank("O"))


def test_pin_at_the_pivot_of_its_body_is_a_structure_error():
    """A rocker whose pin sits on its own pivot: the crank's slot cannot turn it. Was reported
    as 'cannot be assembled at 10 of 13 driver positions' plus toggles at 0 and 180 deg."""
    frame = Body("frame", {"O": (0.0, 0.0), "C": (0.3, 0.0)})
    crank = bar("crank", "O", "A", 0.1)
    rocker = Body("rocker", {"C": (0.0, 0.0), "P": (0.0, 0.0)})
    joints = (Revolute("O", "frame", "crank"), Revolute("C", "frame", "rocker"),
              PinInSlot("S", "crank", "rocker", angle=0.0, through="A", point="P"))
    with pytest.raises(StructureError, match=r"joint S: the pin of body rocker is at its pivot "
                                             r"\(C\).*not determined"):
        kinematics(Mechanism(frame, (crank, rocker), joints, Crank("O")), PHI)


def _scotch_yoke(slot_angle: float) -> Mechanism:
    """Crank O-A (0.1 m); yoke sliding along the frame's x-axis, the crank pin A in its slot."""
    frame = Body("frame", {"O": (0.0, 0.0)})
    joints = (Revolute("O", "frame", "crank"),
              Prismatic("G", "frame", "yoke", angle=0.0, point="Y"),
              PinInSlot("S", "yoke", "crank", angle=slot_angle, through=(0.0, 0.0), point="A"))
    return Mechanism(frame, (bar("crank", "O", "A", 0.1), Body("yoke", {"Y": (0.0, 0.0)})),
                     joints, Crank("O"))


def test_slot_parallel_to_its_guide_is_named_as_such():
    """A yoke whose slot runs along its own guide is not determined (it may slide freely); the
    message said only 'cannot be assembled at 13 of 13 driver positions'."""
    with pytest.raises(AssemblyError, match=r"PS\(yoke\) with joints G, S, whose two lines "
                                            r"\(guides, slots\) are parallel there"):
        kinematics(_scotch_yoke(0.0), PHI)
    # the slot across the guide: the Scotch yoke, x = r cos(phi1)
    k = kinematics(_scotch_yoke(np.pi / 2), PHI)
    np.testing.assert_allclose(k.point("yoke", "Y").x, 0.1 * np.cos(PHI), atol=1e-12)


# -- a class III group without starting poses --------------------------------------------------
def _triad(with_guesses: bool) -> Mechanism:
    """Crank O-A, binary links A-P1, F2-P2, F3-P3 and a ternary link P1-P2-P3 (class III),
    drawn at phi1 = 0.3; the guesses are the poses of that drawing."""
    phi0 = 0.3
    pts = {"A": np.array([0.1 * np.cos(phi0), 0.1 * np.sin(phi0)]),
           "P1": np.array([0.25, 0.15]), "P2": np.array([0.35, 0.05]),
           "P3": np.array([0.3, 0.25]), "F2": np.array([0.45, -0.1]),
           "F3": np.array([0.5, 0.35])}

    def link(name, s, e):
        d = pts[e] - pts[s]
        b = bar(name, s, e, float(np.hypot(*d)), mass=0.5)
        g = (*pts[s], float(np.arctan2(d[1], d[0]))) if with_guesses else None
        return Body(b.name, b.points, b.mass, b.com, b.inertia, guess=g)

    P1, P2, P3 = pts["P1"], pts["P2"], pts["P3"]
    tern = Body("tern", {"P1": (0.0, 0.0), "P2": tuple(P2 - P1), "P3": tuple(P3 - P1)},
                mass=1.0, guess=(P1[0], P1[1], 0.0) if with_guesses else None)
    frame = Body("frame", {"O": (0.0, 0.0), "F2": tuple(pts["F2"]), "F3": tuple(pts["F3"])})
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "l1"),
              Revolute("P1", "l1", "tern"), Revolute("P2", "l2", "tern"),
              Revolute("P3", "l3", "tern"), Revolute("F2", "frame", "l2"),
              Revolute("F3", "frame", "l3"))
    bodies = (bar("crank", "O", "A", 0.1), link("l1", "A", "P1"), link("l2", "F2", "P2"),
              link("l3", "F3", "P3"), tern)
    return Mechanism(frame, bodies, joints, Crank("O"))


def test_class_three_group_without_guesses_is_not_called_unassemblable():
    """Without guess poses Newton starts every body at (0, 0, 0) and fails everywhere; the
    message said 'mechanism cannot be assembled at 12 of 12 driver positions', but the same
    linkage assembles at all of them (shown with guesses: every revolute closes)."""
    phi = np.linspace(0.3, 0.85, 12)
    k = kinematics(_triad(True), phi)
    m = k.mechanism
    for j in m.joints:  # independent closure check: the two points of every revolute coincide
        pa, pb, _ = m.joint_geometry(j)
        A, B = k.point(j.a, pa), k.point(j.b, pb)
        assert np.hypot(A.x - B.x, A.y - B.y).max() < 1e-10
    with pytest.raises(AssemblyError) as exc:
        kinematics(_triad(False), phi)
    msg = str(exc.value)
    assert msg.startswith("Newton iteration did not assemble the mechanism at 12 of 12")
    assert "cannot be assembled" not in msg
    assert "bodies l1, l2, l3, tern have no guess pose" in msg and "give each a guess" in msg


# -- real numbers only ---------------------------------------------------------------------------
def test_complex_and_boolean_arguments_are_refused():
    """A complex array lost its imaginary part with only a ComplexWarning; True was 1."""
    with pytest.raises(ParameterError, match=r"phi1 = .*not complex"):
        cs_model.offset_crank_slider(np.array([1.0 + 2.0j]), 0.05, 4.0, 0.5)
    with pytest.raises(ParameterError, match=r"L1 = True .*not a boolean"):
        sine.inclined_slot(PHI, True, 1.0)
    with pytest.raises(ParameterError, match=r"phi1 = \[True, False\] .*not a boolean"):
        kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3), [True, False])


def test_boolean_branch_is_refused_like_in_the_four_bar_closed_form():
    """fourbar() (closed form) refused branch=True; the engine (Mechanism, kinematics) and the
    crank-slider closed form took True for +1."""
    with pytest.raises(ParameterError, match=r"^branches\.B = True is invalid: must be \+1 or -1"):
        fourbar_mechanism(0.1, 0.3, 0.2, 0.3, branch=True)
    with pytest.raises(ParameterError, match=r"^branches\.B = True is invalid"):
        kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3), PHI, branches={"B": True})
    with pytest.raises(ParameterError, match=r"^branch = True is invalid: must be \+1 or -1"):
        cs_model.offset_crank_slider(PHI, 0.05, 4.0, 0.5, branch=True)
    with pytest.raises(ParameterError, match=r"^branch = True is invalid"):
        fourbar_cf.fourbar(PHI, 0.1, 0.3, 0.2, 0.3, branch=True)


def test_assembly_error_names_the_group_that_cannot_close():
    """A six-bar whose second dyad cannot close over part of the cycle: the error listed only
    the driver ranges, not which of the two dyads fails (the user cannot tell which link to
    lengthen)."""
    from linkwork.errors import AssemblyError

    mech, _, _ = stephenson_sixbar()
    short = tuple(pl.bar("link5", "C", "D", 0.3, mass=1.5) if b.name == "link5" else b
                  for b in mech.bodies)  # |C O6| reaches 0.635 m > 0.3 + 0.25
    broken = pl.Mechanism(mech.frame, short, mech.joints, mech.driver, mech.branches)
    with pytest.raises(AssemblyError) as err:
        pl.kinematics(broken, np.radians(np.arange(0.0, 360.0, 10.0)))
    msg = str(err.value)
    assert "RRR(link5, link6)" in msg and "C, D, O6" in msg
    assert "coupler, rocker" not in msg  # the four-bar loop itself closes everywhere
    # NaN mode: the first dyad's bodies are assembled where only the second fails
    kin = pl.kinematics(broken, np.radians(np.arange(0.0, 360.0, 10.0)), on_failure="nan")
    assert (~kin.valid).any() and kin.valid.any()


@pytest.mark.parametrize("kw, words", [
    (dict(start="O", end="O"), ["crank.end", "O", "start"]),
    (dict(start="O", end="A", points={"A": (0.2, 0.0)}), ["crank.points.A", "length"]),
])
def test_bar_with_inconsistent_end_points_is_named(kw, words):
    """bar() silently overwrote: start == end kept one point at (length, 0) (the pivot moved to
    the far end), and a 'points' entry named like an end replaced it (length 0.1 m, A at 0.2)."""
    with pytest.raises(ParameterError) as err:
        pl.bar("crank", length=0.1, **kw)
    for w in words:
        assert w in str(err.value)


@pytest.mark.parametrize("call,words", [
    (lambda: fb.fourbar(_fb_full(), 0.2, 0.2, 0.2, 0.45), ["assembl", "deg"]),
    (lambda: fb.fourbar(0.3, -0.1, 0.3, 0.2, 0.3), ["a", "-0.1", "> 0"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.0, 0.2, 0.3), ["b", "0", "> 0"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, np.nan, 0.3), ["c", "nan"]),
    (lambda: fb.fourbar(np.nan, 0.1, 0.3, 0.2, 0.3), ["phi1", "nan"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, omega1=np.inf), ["omega1", "inf"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, branch=2), ["branch", "2"]),
    (lambda: fb.fourbar(0.3, 0.1, 0.3, 0.2, 0.3, on_failure="ignore"),
     ["on_failure", "ignore"]),
    (lambda: fb.grashof(0.1, -0.3, 0.2, 0.3), ["b", "-0.3"]),
    (lambda: fb.limit_positions(0.1, 0.3, 0.2, np.nan), ["d", "nan"]),
    (lambda: fb.transmission_angle_extremes(0.1, 0.1, 0.1, 1.0), ["assembled"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, mass=(1, -2, 1)),
     ["mass[1]", "-2"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, mass=(1, 2)), ["mass"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, gravity=(0, np.nan)),
     ["gravity", "nan"]),
    (lambda: fb.fourbar_kinetostatics(0.3, 0.1, 0.3, 0.2, 0.3, moment=(0, 0, np.nan)),
     ["moment[2]", "nan"]),
    (lambda: bar("crank", "O", "A", -0.1), ["crank.length", "-0.1"]),
    (lambda: Body("crank", {"A": (0, 0)}, mass=-1.0), ["crank.mass", "-1"]),
    (lambda: Body("crank", {"A": (0, np.nan)}), ["crank.points.A", "nan"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("O", "frame", "krank"),), Crank("O")), ["krank", "unknown"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("O", "frame", "crank"),), Crank("X")), ["driver.joint", "X"]),
    (lambda: Mechanism(Body("frame", {"O": (0, 0)}), (bar("crank", "O", "A", 0.1),),
                       (Revolute("Z", "frame", "crank"),), Crank("Z")), ["Z", "no such point"]),
    (lambda: kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.0, np.nan]), ["phi1", "nan"]),
    (lambda: kinematics(engine_fourbar(0.2, 0.2, 0.2, 0.45), _fb_full()), ["assembl", "deg"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              loads=[PointForce("rokker", "B", fx=1.0)]), ["rokker"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              loads=[PointForce("rocker", "Q", fx=1.0)]), ["Q", "no such point"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1]),
                              gravity=(0, np.nan)), ["gravity", "nan"]),
    (lambda: inverse_dynamics(kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3), [0.1, 0.2]),
                              loads=[PointForce("rocker", "B", fx=[1.0, 2.0, 3.0])]), ["fx"]),
])
def test_impossible_parameters_give_clear_errors(call, words):
    with pytest.raises(LinkworkError) as ei:
        call()
    msg = str(ei.value).lower()
    for w in words:
        assert w.lower() in msg, (w, msg)


def test_structure_errors_name_bodies_and_joints():
    frame = Body("frame", {"O": (0, 0), "C": (0.3, 0)})
    crank = bar("crank", "O", "A", 0.1)
    rod = bar("rod", "A", "C", 0.3)
    joints = (Revolute("O", "frame", "crank"), Revolute("A", "crank", "rod"),
              Revolute("C", "rod", "frame"))
    with pytest.raises(StructureError) as ei:
        kinematics(Mechanism(frame, (crank, rod), joints, Crank("O")), [0.0])
    assert "locked" in str(ei.value) and "rod" in str(ei.value)
    # a body with no joint at all: under-driven
    frame = Body("frame", {"O": (0, 0), "O4": (0.3, 0)})
    m = engine_fourbar(0.1, 0.3, 0.2, 0.3)
    lonely = Body("lonely", {"X": (0, 0)})
    with pytest.raises(StructureError) as ei:
        Mechanism(m.frame, (*m.bodies, lonely), m.joints, m.driver).validate()
    assert "lonely" in str(ei.value)


def test_misspelt_branch_key_is_an_error_not_ignored():
    """branches={"Z": -1} (no such group) used to be ignored silently: the linkage stayed on
    branch +1 although the user asked for the other assembly."""
    m = engine_fourbar(0.1, 0.3, 0.2, 0.3)
    with pytest.raises(ParameterError) as ei:
        kinematics(m, [0.1], branches={"Z": -1})
    assert "'Z'" in str(ei.value) or "Z " in str(ei.value)
    assert "['B']" in str(ei.value)
    with pytest.raises(ParameterError, match="branches"):
        kinematics(m.with_branches(b=-1), [0.1])
