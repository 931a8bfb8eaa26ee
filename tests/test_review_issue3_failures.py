"""Review of issue 3's acceptance check: mechanisms that cannot move, cannot be assembled, or are
described wrongly, fed to the planar engine, the closed forms and ``linkwork analyze``.

Each test is an input that gave a bare traceback, a silent NaN, a silently ignored value or a
wrong diagnosis before the fix; the expected behaviour is a named error (the parameter, its value
and the limit) and, on the command line, one line on stderr with exit code 2.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from linkwork.cli import main
from linkwork.errors import AssemblyError, ParameterError, StructureError
from linkwork.models import crank_slider as cs_model
from linkwork.models import fourbar as fourbar_cf
from linkwork.models import sine
from linkwork.planar import (
    Body,
    BodyTorque,
    Crank,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    analyse,
    bar,
    crank_slider,
    dead_centres,
    fourbar,
    inverse_dynamics,
    kinematics,
    kinetic_energy,
    transmission_angles,
)

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
PHI = np.linspace(0.0, 2 * np.pi, 13)


# -- bodies and links ---------------------------------------------------------------------------
@pytest.mark.parametrize("value, words", [
    ("10 kg", "must be a number"),                 # was: bare ValueError from float()
    (None, "must be a number"),                    # bare TypeError
    (1j, "not complex"),                           # bare TypeError
    (True, "not a boolean"),                       # accepted as 1 kg
    (np.array([1.0, 2.0]), "single number"),       # bare TypeError
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
    ({"length": np.array([0.1, 0.2])}, r"x\.length = .*single number"),   # bare TypeError
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
        fourbar(0.1, 0.3, 0.2, 0.3, masses=(1, 2))  # type: ignore[arg-type]  # zip() ValueError
    with pytest.raises(ParameterError, match=r"inertias = \(None,\) .*must have 2 entries"):
        crank_slider(0.1, 0.3, inertias=(None,))  # type: ignore[arg-type]  # IndexError
    with pytest.raises(ParameterError, match=r"guide_angle = 30 deg .*must be a number"):
        crank_slider(0.1, 0.3, guide_angle="30 deg")  # type: ignore[arg-type]  # bare TypeError


# -- joints and the mechanism ---------------------------------------------------------------------
def _slider_with_guide(**kw):
    base = crank_slider(0.1, 0.3)
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
    m = fourbar(0.1, 0.3, 0.2, 0.3)
    cases = [  # each was an AttributeError or TypeError from deep inside
        (dict(frame="frame"), r"^frame = frame is invalid: must be a Body"),
        (dict(bodies=("crank",)), r"^bodies = crank is invalid: must be Body objects"),
        (dict(joints=("O2",)), r"^joints = O2 is invalid: must be Revolute, Prismatic or"),
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
    base = crank_slider(0.1, 0.3)
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


# -- loads ----------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fourbar_kin():
    return kinematics(fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0)), PHI)


def test_point_force_at_a_non_finite_local_point_is_named(fourbar_kin):
    """Was: Q all NaN, no error."""
    with pytest.raises(ParameterError, match=r"point of rocker = \(nan, 0\.0\) .*must be finite"):
        inverse_dynamics(fourbar_kin, loads=[PointForce("rocker", (np.nan, 0.0), 1.0, 0.0)])
    with pytest.raises(ParameterError, match=r"point of rocker = \(0, 0, 0\) .*pair of numbers"):
        inverse_dynamics(fourbar_kin, loads=[PointForce("rocker", (0, 0, 0), 1.0, 0.0)])


def test_loads_and_kinematics_of_the_wrong_type_are_named(fourbar_kin):
    one = PointForce("rocker", "B", 1.0, 0.0)
    for loads in (one, None):  # TypeError: not iterable
        with pytest.raises(ParameterError, match=r"^loads = .* must be a sequence"):
            inverse_dynamics(fourbar_kin, loads=loads)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match=r"^loads = x is invalid: must be PointForce or"):
        inverse_dynamics(fourbar_kin, loads=["x"])  # type: ignore[list-item]  # AttributeError
    with pytest.raises(ParameterError, match=r"^kin = .*must be the Kinematics result"):
        inverse_dynamics("kin")  # type: ignore[arg-type]
    # the correct call, for comparison: a couple on the rocker changes Q by mz * omega4 / omega1
    d0 = inverse_dynamics(fourbar_kin)
    d1 = inverse_dynamics(fourbar_kin, loads=[BodyTorque("rocker", 2.0)])
    np.testing.assert_allclose(d1.Q - d0.Q, -2.0 * fourbar_kin.omega[3] / fourbar_kin.omega1,
                               atol=1e-12)


# -- real numbers only ---------------------------------------------------------------------------
def test_complex_and_boolean_arguments_are_refused():
    """A complex array lost its imaginary part with only a ComplexWarning; True was 1."""
    with pytest.raises(ParameterError, match=r"phi1 = .*not complex"):
        cs_model.offset_crank_slider(np.array([1.0 + 2.0j]), 0.05, 4.0, 0.5)
    with pytest.raises(ParameterError, match=r"L1 = True .*not a boolean"):
        sine.inclined_slot(PHI, True, 1.0)
    with pytest.raises(ParameterError, match=r"phi1 = \[True, False\] .*not a boolean"):
        kinematics(fourbar(0.1, 0.3, 0.2, 0.3), [True, False])


# -- files on the command line ------------------------------------------------------------------
def _cli(tmp_path, capsys, text: str) -> str:
    f = tmp_path / "m.toml"
    f.write_text(text)
    rc = main(["analyze", str(f), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1, err
    return err


def _replace(src: str, old: str, new: str) -> str:
    assert old in src
    return src.replace(old, new, 1)


FOURBAR = (EXAMPLES / "fourbar_paper001.toml").read_text()
SIXBAR = (EXAMPLES / "loom_sixbar.toml").read_text()
LOAD = '\n[[load]]\ntype = "{}"\nbody = "rocker"\n{}\n'


@pytest.mark.parametrize("text, words", [
    # a huge length: was a traceback (OverflowError in the rate solve) and exit code 1
    (_replace(FOURBAR, 'length = "100 mm"', "length = 1e300"), "numerical overflow"),
    # keys of another type of load, joint or driver were ignored silently (exit 0, no load
    # applied, the joint's default points used, the linear driver at its default 1 m/s)
    (FOURBAR + LOAD.format("force", 'mz = "10 N*m"'),
     "load.0.mz: 10 is invalid: is not used with type = 'force'"),
    (FOURBAR + LOAD.format("torque", 'fx = "10 N"'),
     "load.0.fx: 10 is invalid: is not used with type = 'torque'"),
    (_replace(FOURBAR, 'a = "crank"\nb = "coupler"', 'a = "crank"\nb = "coupler"\npoint = "B"'),
     "joint.1.point: B is invalid: is not used with type = 'revolute', which takes point_a"),
    (_replace(_replace(SIXBAR, 'through = "G"', 'through = "G"\nrel_angle = 0.1'),
              'type = "prismatic"', 'type = "slot"'),
     "joint.6.rel_angle: 0.1 is invalid: is not used with type = 'slot'"),
    (_replace(FOURBAR, "eps1 = 0", 'eps1 = 0\nv1 = "2 m/s"'),
     "driver.v1: 2 is invalid: is not used with type = 'crank', which takes omega1 and eps1"),
    # a NaN end of the load range switched the load off everywhere (exit 0)
    (FOURBAR + LOAD.format("force", 'fy = "10 N"\nphi_range = [nan, "20 deg"]'),
     "load.0.phi_range: nan is invalid: must be finite"),
    # 1e300 rad: exit 0 with dead centres printed as 300-digit angles
    (_replace(FOURBAR, 'stop = "360 deg"', "stop = 1e300"),
     "analysis.stop: 1e+300 is invalid: must lie within +-1e+06 rad"),
    # a revolute's missing point: the joint was not named ('frame.points: Z is invalid')
    (_replace(FOURBAR, 'name = "C"\ntype = "revolute"', 'name = "C"\ntype = "revolute"\n'
              'point_a = "Z"'), "joint C.point_a: Z is invalid: no such point of body 'frame'"),
    # a union (point name or [x, y]) reported its string member: 'Input should be a valid
    # string (got [nan, 0])'; now the member that reads [x, y] says what is wrong
    (_replace(SIXBAR, 'through = "G"', "through = [nan, 0]"),
     "joint.6.through.0: must be a finite number (got nan)"),
])
def test_cli_described_wrongly_one_line_exit_2(tmp_path, capsys, text, words):
    assert words in _cli(tmp_path, capsys, text)


def test_cli_load_keys_of_its_own_type_still_work(tmp_path, capsys):
    """For comparison: the same loads with their own keys run (exit 0)."""
    f = tmp_path / "ok.toml"
    f.write_text(FOURBAR + LOAD.format("force", 'fy = "10 N"\nphi_range = ["10 deg", "20 deg"]')
                 + LOAD.format("torque", 'mz = "1 N*m"'))
    assert main(["analyze", str(f), "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()


# -- closed forms and result helpers --------------------------------------------------------------
@pytest.mark.parametrize("theta2, match", [
    (None, r"^theta2 = None is invalid: must be a number"),        # was 'theta2 = nan'
    (np.array([1.0 + 2.0j]), r"^theta2 = .*not complex"),         # ComplexWarning, result for 1
    (True, r"^theta2 = True .*not a boolean"),                     # computed at 1 rad
])
def test_fourbar_closed_form_crank_angle_is_checked(theta2, match):
    with pytest.raises(ParameterError, match=match):
        fourbar_cf.fourbar(theta2, 0.1, 0.3, 0.2, 0.3)


def test_fourbar_that_never_assembles_names_its_lengths_and_intervals():
    """The message had neither the lengths nor the intervals: '(|d - a|, d + a) does not meet
    (|b - c|, b + c)'. Here |A O4| in [0.9, 1.1] m and the dyad reaches [0.25, 0.35] m."""
    with pytest.raises(AssemblyError, match=r"\[\|d - a\|, d \+ a\] = \[0\.9, 1\.1\], which "
                                            r"does not meet \[\|b - c\|, b \+ c\] = \[0\.25, "
                                            r"0\.35\] \(a=0\.1, b=0\.3, c=0\.05, d=1 m\)"):
        fourbar_cf.transmission_angle_extremes(0.1, 0.3, 0.05, 1.0)


@pytest.mark.parametrize("lambda_e, words", [(np.nan, "must be finite"),
                                             (None, "must be a number")])
def test_crank_slider_assembly_limit_refuses_non_numbers(lambda_e, words):
    """Was NaN, returned silently; the limit of a real offset is |lambda_e| + 1."""
    with pytest.raises(ParameterError, match=rf"^lambda_e = .*{words}"):
        cs_model.assembly_limit(lambda_e)
    assert cs_model.assembly_limit(-0.5) == 1.5


def test_result_helpers_name_a_wrong_argument():
    """AttributeError ('str' object has no attribute 'mechanism' / 'bodies') before."""
    for f in (transmission_angles, dead_centres, kinetic_energy):
        with pytest.raises(ParameterError, match=r"^kin = k is invalid: must be the Kinematics"):
            f("k")
    with pytest.raises(ParameterError, match=r"^mech = m is invalid: must be a Mechanism"):
        analyse("m")  # type: ignore[arg-type]


def test_cli_table_angles_beyond_float_precision_are_refused(tmp_path, capsys):
    """--angles -1e300 printed a 300-digit crank angle with 'results' for it (exit 0)."""
    rc = main(["analyze", str(EXAMPLES / "fourbar_paper001.toml"), "--out", str(tmp_path),
               "--angles", "-1e300"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1
    assert "--angles = -1e+300 is invalid: must lie within +-5.72958e+07 deg" in err


def test_boolean_branch_is_refused_like_in_the_four_bar_closed_form():
    """fourbar() (closed form) refused branch=True; the engine (Mechanism, kinematics) and the
    crank-slider closed form took True for +1."""
    with pytest.raises(ParameterError, match=r"^branches\.B = True is invalid: must be \+1 or -1"):
        fourbar(0.1, 0.3, 0.2, 0.3, branch=True)
    with pytest.raises(ParameterError, match=r"^branches\.B = True is invalid"):
        kinematics(fourbar(0.1, 0.3, 0.2, 0.3), PHI, branches={"B": True})
    with pytest.raises(ParameterError, match=r"^branch = True is invalid: must be \+1 or -1"):
        cs_model.offset_crank_slider(PHI, 0.05, 4.0, 0.5, branch=True)
    with pytest.raises(ParameterError, match=r"^branch = True is invalid"):
        fourbar_cf.fourbar(PHI, 0.1, 0.3, 0.2, 0.3, branch=True)
