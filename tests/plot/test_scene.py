"""The mechanism's drawing (linkwork.plot.scene) against the engine and against geometry.

References: the engine's own point motions (``Kinematics.point``, computed by another path than
the scene's transforms), the Aronhold-Kennedy theorem (three instant centres of any three bodies
are collinear), the centres' defining property (the velocity of both bodies there is the same,
checked with ``Kinematics.point`` at the centre's local coordinates), Kennedy's construction of
the four-bar's I13, and the closed forms' own constraints (the rod length of the crank-slider,
the block in the slot of the sine mechanism, the rod length of the swash plate). Tolerances:
1e-9 of the mechanism's size for positions (round-off of a few transforms), 1e-7 for the
instant centres near the limit positions (a division by the relative angular velocity).
"""

from __future__ import annotations

import itertools
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.models import swashplate as sw
from linkwork.planar import crank_slider_mechanism, fourbar_mechanism, kinematics
from linkwork.plot import scene as sc
from linkwork.studies import planar as study_planar
from linkwork.studies import sine_press, swashplate

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def _study(name: str) -> study_planar.PlanarStudy:
    return study_planar.analyze(io.load(EXAMPLES / name))


@pytest.mark.parametrize("name", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                  "sine_press_planar.toml", "loom_fourbar_spatial.toml"])
def test_planar_scene_draws_every_joint_at_the_engine_position(name):
    st = _study(name)
    kin, mech = st.kinematics, st.mechanism
    scene = sc.planar_scene(kin)
    size = max(np.ptp(kin.x), np.ptp(kin.y), 1e-3)
    for j in mech.joints:
        qa, pb, _ = mech.joint_geometry(j)
        on_b = j.b != mech.frame.name
        pm = kin.point(j.b, pb) if on_b else kin.point(j.a, qa)
        shape = scene.shape(f"joint {j.name}") if j.code != "P" else scene.shape(
            f"block {j.name}")
        if j.code == "P":  # the block's centre is the slider point
            drawn = shape.xy.mean(axis=0)
        else:
            drawn = shape.xy[0] if shape.moving else np.broadcast_to(
                shape.xy[0][:, None], (2, kin.n))
        np.testing.assert_allclose(drawn[0], pm.x, rtol=0, atol=1e-9 * size)
        np.testing.assert_allclose(drawn[1], pm.y, rtol=0, atol=1e-9 * size)


def test_planar_scene_links_pass_through_their_bodies_points():
    st = _study("loom_sixbar.toml")
    kin, mech = st.kinematics, st.mechanism
    scene = sc.planar_scene(kin)
    for body in mech.bodies:
        if len(body.points) < 2:
            continue
        link = scene.shape(body.name)
        for pt in body.points:
            pm = kin.point(body.name, pt)
            gap = np.min(np.hypot(link.xy[:, 0] - pm.x, link.xy[:, 1] - pm.y), axis=0)
            assert np.max(gap) < 1e-9  # the point is a vertex of the outline at every frame


def test_coupler_curve_of_any_point_is_the_engine_path():
    st = _study("fourbar_paper001.toml")
    local = (0.1, -0.04)
    scene = sc.planar_scene(st.kinematics, paths=[("coupler", local)])
    path = scene.shape("path coupler.(100, -40) mm")
    pm = st.kinematics.point("coupler", local)
    np.testing.assert_allclose(path.xy, np.stack([pm.x, pm.y], axis=1), atol=1e-12)
    tracer = scene.shape("point coupler.(100, -40) mm")
    np.testing.assert_allclose(tracer.xy[0], np.stack([pm.x, pm.y]), atol=1e-12)


def _collinear(p, q, r) -> np.ndarray:
    """Twice the area of the triangle pqr over the square of its longest side: 0 on a line."""
    area = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    sides = np.max([np.hypot(*(q - p)), np.hypot(*(r - p)), np.hypot(*(r - q))], axis=0)
    # three centres in one point (a joint shared by three bodies) are trivially collinear
    return np.where(sides > 1e-12, np.abs(area) / np.maximum(sides, 1e-12) ** 2, 0.0)


@pytest.mark.parametrize("name", ["fourbar_paper001.toml", "loom_sixbar.toml"])
def test_instant_centres_obey_aronhold_kennedy(name):
    kin = _study(name).kinematics
    ic = sc.instant_centres(kin)
    nb = len(kin.bodies)
    worst = 0.0
    for i, j, k in itertools.combinations(range(nb), 3):
        p, q, r = ic[(i, j)], ic[(j, k)], ic[(i, k)]
        ok = np.all(np.isfinite(p) & np.isfinite(q) & np.isfinite(r), axis=0)
        far = np.max(np.abs(np.stack([p, q, r])), axis=(0, 1))
        ok &= far < 1e3  # a centre near infinity (parallel links) leaves no triangle to test
        worst = max(worst, float(np.max(_collinear(p[:, ok], q[:, ok], r[:, ok]),
                                        initial=0.0)))
    assert worst < 1e-7


def test_instant_centres_have_equal_velocity_in_both_bodies():
    kin = _study("loom_sixbar.toml").kinematics
    ic = sc.instant_centres(kin)
    bodies = kin.bodies
    k = 37
    for (i, j), xy in ic.items():
        if not np.all(np.isfinite(xy[:, k])):
            continue
        v = []
        for b in (i, j):
            if b == 0:
                v.append(np.zeros(2))
                continue
            th = kin.theta[b, k]
            d = xy[:, k] - np.array([kin.x[b, k], kin.y[b, k]])
            local = (math.cos(th) * d[0] + math.sin(th) * d[1],
                     -math.sin(th) * d[0] + math.cos(th) * d[1])
            pm = kin.point(bodies[b], local)
            v.append(np.array([pm.vx[k], pm.vy[k]]))
        scale = np.max(np.abs(kin.vx[:, k])) + np.max(np.abs(kin.vy[:, k]))
        np.testing.assert_allclose(v[0], v[1], rtol=0, atol=1e-9 * scale)


def test_instant_centres_of_joints_and_kennedys_construction_for_a_four_bar():
    """Primary centres: I12 = O2, I23 = A, I34 = B, I14 = O4; I13 and I24 (from the velocities)
    by Kennedy's construction: the intersections of the lines I12 I23 and I14 I34, and of
    I12 I14 and I23 I34."""
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, omega1=10.0)
    kin = kinematics(mech, np.radians(np.arange(0.0, 360.0, 5.0)))
    ic = sc.instant_centres(kin)
    A, B = kin.point("crank", "A"), kin.point("rocker", "B")
    O2 = np.zeros((2, kin.n))
    O4 = np.array([[0.3], [0.0]]) * np.ones(kin.n)
    for key, ref in (((0, 1), O2), ((1, 2), np.stack([A.x, A.y])),
                     ((2, 3), np.stack([B.x, B.y])), ((0, 3), O4)):
        np.testing.assert_allclose(ic[key], ref, rtol=0, atol=1e-12)
    # intersection of O2-A and O4-B
    d1 = np.stack([A.x, A.y]) - O2
    d2 = np.stack([B.x, B.y]) - O4
    den = d1[0] * d2[1] - d1[1] * d2[0]
    t = ((O4 - O2)[0] * d2[1] - (O4 - O2)[1] * d2[0]) / den
    I13 = O2 + t * d1
    good = np.abs(den) > 1e-3
    np.testing.assert_allclose(ic[(0, 2)][:, good], I13[:, good], rtol=1e-9, atol=1e-12)
    # I24: on the frame line O2 O4 (y = 0) and on the coupler line A B
    dAB = np.stack([B.x - A.x, B.y - A.y])
    t = -A.y / dAB[1]
    I24 = np.stack([A.x + t * dAB[0], np.zeros(kin.n)])
    good = np.abs(dAB[1]) > 1e-3
    np.testing.assert_allclose(ic[(1, 3)][:, good], I24[:, good], rtol=1e-9, atol=1e-12)


def test_instant_centre_of_a_slider_is_at_infinity():
    kin = _study("loom_sixbar.toml").kinematics
    ic = sc.instant_centres(kin)
    i = kin.bodies.index("ram")  # the ram only slides in the frame's guide
    assert np.all(np.isnan(ic[(0, i)]))



def test_instant_centres_of_an_offset_crank_slider_by_kennedys_construction():
    """Offset crank-slider (r 50, l 200, e 20 mm; Kennedy: frame 1, crank 2, rod 3, slider
    4): I13 where the crank's line O-A meets the normal to the guide through B (I14 at
    infinity along that normal, I34 at B), I24 where the rod's line A-B meets the normal to
    the guide through O; constructed here, to 1e-12 m."""
    r, l, e = 0.05, 0.2, 0.02
    mech = crank_slider_mechanism(r, l, e)
    phi = np.radians(np.arange(5.0, 360.0, 20.0))
    kin = kinematics(mech, phi)
    ic = sc.instant_centres(kin)
    crank, rod, slider = (kin.bodies.index(b) for b in ("crank", "rod", "slider"))
    A = r * np.stack([np.cos(phi), np.sin(phi)])
    B = kin.point("slider", "B")
    np.testing.assert_allclose(B.y, e, atol=1e-15)
    I13 = np.stack([B.x, B.x * np.tan(phi)])
    I24 = np.stack([np.zeros(phi.size), A[1] - A[0] * (B.y - A[1]) / (B.x - A[0])])
    np.testing.assert_allclose(ic[(0, rod)], I13, atol=1e-12)
    np.testing.assert_allclose(ic[(crank, slider)], I24, atol=1e-12)
    np.testing.assert_allclose(ic[(rod, slider)], np.stack([B.x, B.y]), atol=1e-12)
    assert np.all(np.isnan(ic[(0, slider)]))

def test_sine_press_scene_keeps_the_constraints_of_both_modes():
    st = sine_press.analyze(io.load(EXAMPLES / "sine_press.toml"))
    scene = sc.sine_press_scene(st.idle_cycle, st.working_cycle)
    L1 = st.doc.crank.L1
    L2 = st.doc.idle.lambda2 * L1
    rod = scene.shape("idle rod").xy
    np.testing.assert_allclose(np.hypot(*(rod[1] - rod[0])), L2, rtol=1e-12)
    e = st.doc.idle.lambda_e * L1
    np.testing.assert_allclose(scene.shape("idle joint C").xy[0, 0], e, rtol=1e-12)
    slot = scene.shape("working slot").xy                   # (2, 2, n)
    pin = scene.shape("working joint B").xy[0]              # (2, n)
    u = slot[1] - slot[0]
    cross = u[0] * (pin[1] - slot[0, 1]) - u[1] * (pin[0] - slot[0, 0])
    assert np.max(np.abs(cross) / np.hypot(*u)) < 1e-12    # the block's pin on the slot line
    crank = scene.shape("working crank").xy
    np.testing.assert_allclose(np.hypot(*(crank[1] - crank[0])), L1, rtol=1e-12)


def test_swashplate_scene_uses_the_cycle_and_keeps_the_rod_length():
    st = swashplate.analyze(io.load(EXAMPLES / "swashplate_4a.toml"))
    A, B = sw.points(st.cycle.phi, *st.design.params)
    np.testing.assert_allclose(np.linalg.norm(A - B, axis=1), st.design.l, rtol=1e-12)
    np.testing.assert_allclose(A[:, 2], st.cycle.s, atol=1e-15)
    scene = sc.swashplate_scene(st.cycle, A, B)
    side = scene.shape("side joint A").xy[0]
    np.testing.assert_allclose(side[1], st.cycle.s, atol=1e-15)   # the slide height is s


def test_scene_frames_are_bounded_and_leave_out_the_repeated_end():
    scene = sc.planar_scene(_study("fourbar_paper001.toml").kinematics)
    assert scene.n == 361 and scene.periodic
    assert scene.frames(720).tolist() == list(range(360))   # 360 deg repeats 0 deg
    few = scene.frames(50)
    assert few.size == 50 and few[0] == 0 and few[-1] == 359


def test_joint_type_supplies_its_own_shape():
    """A joint class with a scene_shapes(ctx) method draws itself (how a new joint type, a gear
    pair, plugs in); a joint type without a shape is noted, not an error."""
    st = _study("fourbar_paper001.toml")
    kin = st.kinematics
    old = sc.JOINT_SHAPES.pop("R")
    try:
        scene = sc.planar_scene(kin)
        assert any("has no drawing" in n for n in scene.notes)
        with pytest.raises(KeyError):
            scene.shape("joint A")
    finally:
        sc.JOINT_SHAPES["R"] = old


def test_animation_files_are_bounded(tmp_path):
    from PIL import Image

    scene = sc.planar_scene(_study("fourbar_paper001.toml").kinematics)
    gif = sc.animate(scene, tmp_path / "m.gif", frames=5, size=(5000, 5000), dpi=50)
    with Image.open(gif) as im:
        assert im.n_frames == 5
        assert im.size[0] <= sc.MAX_ANIMATION_PIXELS[0]
        assert im.size[1] <= sc.MAX_ANIMATION_PIXELS[1]
        first = np.asarray(im.convert("RGB"))
        im.seek(3)
        later = np.asarray(im.convert("RGB"))
    assert np.any(first != later)   # the mechanism moves between frames
    big = sc.animate(scene, tmp_path / "n.gif", frames=10_000, dpi=20, size=(100, 80))
    with Image.open(big) as im:
        assert im.n_frames == sc.MAX_ANIMATION_FRAMES


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not installed")
def test_mp4_animation(tmp_path):
    scene = sc.planar_scene(_study("fourbar_paper001.toml").kinematics)
    mp4 = sc.animate(scene, tmp_path / "m.mp4", frames=4, dpi=40, size=(320, 240))
    head = mp4.read_bytes()[:12]
    assert head[4:8] == b"ftyp"   # an MP4 (ISO base media) file
    assert not list(tmp_path.glob(".*part*"))


# ---------------------------------------------------------------------------------------------
# force elements and loads drawn where they act
#
# References: the engine's own point motions (Kinematics.point), the file's frame points, the
# study's load values (Dynamics.load(name).value); positions to 1e-12 m (a few products).


def _press_scene() -> tuple[study_planar.PlanarStudy, sc.Scene]:
    st = _study("crank_press.toml")
    return st, st.scene()


def test_spring_is_a_zigzag_between_the_engine_points_of_its_ends():
    """crank_press's counterbalance: from the frame point K (250, 0) mm to the ram's point R;
    its zigzag spans exactly the distance of its ends, with the coil's half-width on both
    sides of their line."""
    st, scene = _press_scene()
    zig = scene.shape("spring counterbalance").xy                  # (k, 2, n)
    R = st.kinematics.point("ram", "R")
    np.testing.assert_allclose(zig[0], np.broadcast_to([[0.25], [0.0]], (2, R.x.size)),
                               atol=1e-12)
    np.testing.assert_allclose(zig[-1], np.stack([R.x, R.y]), atol=1e-12)
    d = np.stack([R.x - 0.25, R.y])
    L = np.hypot(*d)
    u = d / L
    rel = zig - zig[0][None]
    along = np.einsum("kin,in->kn", rel, u)
    across = rel[:, 0] * -u[1][None] + rel[:, 1] * u[0][None]
    assert np.all(np.diff(along, axis=0) >= -1e-12)               # it runs from K to R
    np.testing.assert_allclose(across[[0, 1, -2, -1]], 0.0, atol=1e-12)  # straight ends
    assert np.all(np.abs(np.abs(across[2:-2]) - np.abs(across[2])) < 1e-12)  # one width
    assert np.all(across[2:-3] * across[3:-2] < 0)                # zig, zag
    assert 0 < np.abs(across[2]).max() < 0.1 * L.min()            # a coil, not a bar
    np.testing.assert_allclose(np.linalg.norm(zig[-1] - zig[0], axis=0), L, rtol=1e-12)


def test_load_arrow_points_at_its_point_along_the_force_where_it_acts():
    """The drawing force (a diagram over the ram's slide, while it moves down) is drawn at the
    wrist pin B along the guide (+y), its length in proportion to the study's value, and not
    at all where the value is zero."""
    st, scene = _press_scene()
    value = st.dynamics.load("drawing").value
    arrow = scene.shape("load drawing").xy                        # (5, 2, n)
    acts = value != 0
    assert 0 < acts.sum() < value.size
    assert np.all(np.isnan(arrow[:, :, ~acts]))
    B = st.kinematics.point("ram", "B")
    np.testing.assert_allclose(arrow[1][:, acts], np.stack([B.x, B.y])[:, acts], atol=1e-12)
    shaft = arrow[1] - arrow[0]
    np.testing.assert_allclose(shaft[0][acts], 0.0, atol=1e-12)  # along the guide, upwards
    lengths = shaft[1][acts]
    assert np.all(lengths > 0)
    np.testing.assert_allclose(lengths / lengths.max(), value[acts] / value[acts].max(),
                               rtol=1e-12)


def test_where_a_load_acts_is_marked_on_its_path_and_at_the_crank():
    """The loom's 300 kN coining force acts for 145 <= phi1 <= 184.7 deg: the marked stretch
    of the ram's path and the arc at the crank hold those positions and no other."""
    st = _study("loom_sixbar.toml")
    scene = st.scene()
    phi = np.degrees(st.kinematics.phi1)
    inside = (phi >= 145 - 1e-9) & (phi <= 184.7 + 1e-9)
    stretch = scene.shape("range load.0").xy                      # (n, 2), NaN outside
    assert np.array_equal(np.isfinite(stretch[:, 0]), inside)
    R = st.kinematics.point("ram", "R")
    np.testing.assert_allclose(stretch[inside], np.stack([R.x, R.y], axis=1)[inside],
                               atol=1e-12)
    arc = scene.shape("range load.0 (crank angles)").xy
    assert np.array_equal(np.isfinite(arc[:, 0]), inside)
    O = np.array([0.61, -0.3])                                    # the crank's pivot
    A = st.kinematics.point("crank", "A")
    rel = arc[inside] - O
    np.testing.assert_allclose(np.arctan2(rel[:, 1], rel[:, 0]),
                               np.arctan2(A.y - O[1], A.x - O[0])[inside], atol=1e-12)
    assert np.ptp(np.hypot(rel[:, 0], rel[:, 1])) < 1e-12         # one radius, outside A
    assert np.hypot(rel[0, 0], rel[0, 1]) > 0.06


def test_damper_and_couple_drawn_with_the_motion():
    """A damper from the frame to the slider of a crank-slider: the cylinder starts at its
    frame point, the piston rod ends at the slider's point, and the plate stays between the
    cylinder's bottom and its open end at every position; a couple that changes sign turns its
    arrow with it."""
    from linkwork.planar import BodyTorque, Damper, crank_slider_mechanism, inverse_dynamics

    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 1.0, 1.0))
    kin = kinematics(mech, np.radians(np.arange(0.0, 360.0, 5.0)))
    phi = kin.phi1
    dyn = inverse_dynamics(kin, loads=[
        Damper("frame", (-0.2, 0.0), "slider", "B", damping=50.0, name="d"),
        BodyTorque("rod", np.sin(phi), name="m")])
    scene = sc.planar_scene(kin, loads=dyn.loads)
    cyl = scene.shape("damper d cylinder").xy
    piston = scene.shape("damper d piston").xy
    B = kin.point("slider", "B")
    np.testing.assert_allclose(cyl[0], np.broadcast_to([[-0.2], [0.0]], (2, phi.size)),
                               atol=1e-12)
    np.testing.assert_allclose(piston[0], np.stack([B.x, B.y]), atol=1e-12)
    bottom = cyl[1][0] + 0.2
    open_end = cyl[3][0] + 0.2
    plate = piston[1][0] + 0.2                                    # along x from the anchor
    assert np.all((bottom < plate) & (plate < open_end))
    arrow = scene.shape("load m").xy                              # (k, 2, n)
    i = kin.bodies.index("rod")
    centre = np.stack([kin.x[i], kin.y[i]])
    on = np.abs(np.sin(phi)) > 1e-9
    r0, r1 = arrow[0] - centre, arrow[1] - centre
    turn = r0[0] * r1[1] - r0[1] * r1[0]                          # + counter-clockwise
    assert np.array_equal(np.sign(turn[on]), np.sign(np.sin(phi[on])))
    assert np.all(np.isnan(arrow[:, :, ~on]))


def test_timed_scene_takes_a_turn_of_real_motion_and_refuses_others():
    """Scene.timed over a uniform motion gives t = (phi - phi_0) / omega at every frame (the
    constant-speed limit), and a linear driver's scene or angles that do not increase within a
    turn are refused by name."""
    from linkwork.errors import ParameterError

    scene = sc.planar_scene(_study("fourbar_paper001.toml").kinematics)
    nodes = np.radians(np.arange(0.0, 360.0, 7.5))
    w = 3.0
    timed = scene.timed("uniform", nodes, nodes / w, np.full(nodes.size, w), 2 * np.pi / w)
    tm = timed.timings[0]
    frames = scene.frames(720)
    np.testing.assert_allclose(tm.t[frames], (scene.positions[frames] - scene.positions[0]) / w,
                               atol=1e-12)
    assert tm.span == pytest.approx(2 * np.pi / w) and np.all(tm.speed == w)
    assert timed.take(frames[:10]).timings[0].t.size == 10
    with pytest.raises(ParameterError, match="phi"):
        scene.timed("x", nodes[::-1], nodes, nodes, 1.0)
    linear = sc.Scene("s", np.array([0.0, 0.1]), "s1", "m", np.ones(2, bool), ())
    with pytest.raises(ParameterError, match="crank"):
        linear.timed("x", nodes, nodes, nodes, 1.0)


# ---------------------------------------------------------------------------------------------
# gears, cylinders and several drivers
#
# References: the gear law (30 and 50 teeth: the second gear turns -30/50 of the first; pitch
# radii 60 and 100 mm from the teeth and the 160 mm between the pivots), the planetary train's
# geometry (planet of 30 mm rolling in a 90 mm ring), the engine's pivots of the excavator's
# cylinders (Kinematics.point) and its drivers' coordinates (phi1), and their constant speeds
# (t = (s - s0) / v). Positions to 1e-12 m, angles to 1e-12 rad.


def test_gear_pair_pitch_circles_mesh_point_and_spokes():
    st = _study("geared_five_bar.toml")
    scene = st.scene()
    assert scene.shape("gear G gear1").size == pytest.approx(0.06, abs=1e-15)
    assert scene.shape("joint G").size == pytest.approx(0.10, abs=1e-15)
    mesh = scene.shape("mesh G")
    assert not mesh.moving                                    # both gears on frame pivots
    P = mesh.xy[0]
    assert np.hypot(*P) == pytest.approx(0.06, abs=1e-12)
    assert np.hypot(P[0] - 0.16, P[1]) == pytest.approx(0.10, abs=1e-12)
    turned = []
    for gear in ("gear1", "gear2"):
        sp = scene.shape(f"spokes G {gear}").xy             # (5, 2, n): a diameter first
        a = np.unwrap(np.arctan2(sp[0, 1] - sp[2, 1], sp[0, 0] - sp[2, 0]))
        turned.append(a - a[0])
    np.testing.assert_allclose(turned[1], -30 / 50 * turned[0], atol=1e-12)
    assert np.ptp(turned[0]) == pytest.approx(np.ptp(st.kinematics.phi1), abs=1e-9)


def test_internal_gear_rim_and_mesh_point_travel_with_the_arm():
    """A planet (30 mm) on an arm rolling in a fixed ring (90 mm, the frame): the ring's rim
    outside its pitch circle, the pitch point on both pitch circles and on the line from the
    ring's centre through the planet's."""
    from linkwork.planar import Body, Crank, GearPair, Mechanism, Revolute, bar

    frame = Body("frame", {"O": (0.0, 0.0)})
    arm = bar("arm", "O", "Q", 0.06)
    planet = Body("planet", {"Q": (0.0, 0.0), "T": (0.03, 0.0)})
    mech = Mechanism(frame, (arm, planet), (
        Revolute("O", "frame", "arm"), Revolute("Q", "arm", "planet"),
        GearPair("M", "planet", "frame", radii=(0.03, 0.09), internal=True, carrier="arm")),
        Crank("O"))
    kin = kinematics(mech, np.linspace(0, 2 * np.pi, 73))
    scene = sc.planar_scene(kin)
    rim = scene.shape("rim M")
    assert not rim.moving and rim.size == pytest.approx(0.018)
    np.testing.assert_allclose(np.hypot(rim.xy[:, 0], rim.xy[:, 1]), 0.099, atol=1e-12)
    P = scene.shape("mesh M").xy[0]                           # (2, n): it moves with the arm
    Q = kin.point("planet", "Q")
    np.testing.assert_allclose(np.hypot(*P), 0.09, atol=1e-12)
    np.testing.assert_allclose(np.hypot(P[0] - Q.x, P[1] - Q.y), 0.03, atol=1e-12)
    np.testing.assert_allclose(P, np.stack([Q.x, Q.y]) * 0.09 / 0.06, atol=1e-12)


def test_cylinders_are_barrel_rod_and_piston_on_the_engine_pivots():
    st = _study("excavator_boom.toml")
    scene = st.scene()
    kin = st.kinematics
    for cyl, start, end in (("boom_cyl", "A1", "C1"), ("arm_cyl", "A2", "C2"),
                            ("bucket_cyl", "A3", "C3")):
        a = kin.point(f"{cyl}_barrel", start)
        b = kin.point(f"{cyl}_rod", end)
        A, B = np.stack([a.x, a.y]), np.stack([b.x, b.y])
        length = np.hypot(*(B - A))
        np.testing.assert_allclose(length, kin.phi1[["boom_cyl", "arm_cyl",
                                                     "bucket_cyl"].index(cyl)], atol=1e-12)
        barrel = scene.shape(f"barrel {cyl}").xy
        rod = scene.shape(f"rod {cyl}").xy
        np.testing.assert_allclose(barrel[0], A, atol=1e-12)
        np.testing.assert_allclose(rod[0], B, atol=1e-12)
        u = (B - A) / length
        lb = np.sum((barrel[1] - A) * u, axis=0)
        piston = np.sum((rod[1] - A) * u, axis=0)
        assert np.ptp(lb) < 1e-12 and np.ptp(np.hypot(*(rod[1] - rod[0]))) < 1e-12  # rigid
        assert np.all((piston > 0.0) & (piston < lb))         # the piston inside the barrel
        off = barrel[1] - A                                    # along the axis: no normal
        np.testing.assert_allclose(off[0] * u[1] - off[1] * u[0], 0.0, atol=1e-12)


def test_several_drivers_number_the_frames_and_read_out_every_driver():
    st = _study("excavator_boom.toml")
    scene = st.scene()
    kin = st.kinematics
    assert scene.unit == "" and np.array_equal(scene.positions, np.arange(kin.n))
    assert [r[0] for r in scene.readouts] == ["s boom_cyl", "s arm_cyl", "s bucket_cyl"]
    for k, (_, unit, v) in enumerate(scene.readouts):
        assert unit == "mm"
        np.testing.assert_allclose(v, kin.phi1[k] * 1e3, rtol=1e-15)
    (tm,) = scene.timings                                      # the drivers' own speeds
    np.testing.assert_allclose(tm.t, (kin.phi1[0] - 1.3) / 0.045, atol=1e-12)
    assert tm.span == pytest.approx(4.0 + 4.0 / 80)            # and one step back to the start
    assert sc._caption(scene, 40).startswith("position 40\ns boom_cyl = 1390.0 mm, ")
