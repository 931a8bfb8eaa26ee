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
from linkwork.planar import fourbar_mechanism, kinematics
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
