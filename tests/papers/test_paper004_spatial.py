"""Paper 004, spatial equations (1)-(7) and (14)-(19), checked against linkwork's spatial model.

The paper's geometry, fixed by its own equations: joint centres at heights z_O = 0, z_A = e0
((7a): lever arm e0 of R_A about O), z_B = z_A ((5): no lever arm between A and B), z_C =
z_B - (e_B + e_C) ((3): lever arm e_C + e_B of R_B about C); the crank's centre of mass at z_O
((7) has no moment of F1 about x, y), the coupler's at z_A, the rocker's at z_C + e_C ((3): lever
arm e_C of F3). φ3 is the angle of B->C (loop (1); the convention under which (8) holds, see the
planar errata). The reactions come from linkwork's force method with compliant joints and
deviations, so that every out-of-plane component is non-zero; each printed equation is evaluated
with them, next to the corrected form.
"""

from __future__ import annotations

import numpy as np
import pytest
from _fourbar_reference import L1, L2, L3, geometry, kinematics, loads, spatial_model

from linkwork.redundancy import solve_reactions, wrench_about_origin

E0, EA, EB, EC = 0.03, 0.025, 0.02, 0.035
Z = (0.0, E0, E0, E0 - EB - EC)           # O, A, B, C
ZG = (0.0, E0, E0 - EB - EC + EC)         # centres of mass of links 1, 2, 3
PHI = np.linspace(0.0, 2 * np.pi, 24, endpoint=False)


def _paper_state():
    m = spatial_model(e=(E0, EA, EB, EC), z=Z)
    g = geometry(PHI)
    centres, forces, moments = loads(PHI)
    n = len(PHI)
    p3 = np.concatenate([centres, np.broadcast_to(np.array(ZG), (n, 3))[..., None]], -1)
    f3 = np.concatenate([forces, np.zeros((n, 3, 1))], -1)
    m3 = np.zeros((n, 3, 3))
    m3[..., 2] = moments
    w = wrench_about_origin(f3, m3, p3)
    dev = np.zeros((4, 2, 6))
    dev[0, 0] = (0, 0, 2e-5, 3e-4, -2e-4, 0)
    dev[2, 1] = (0, 0, -1e-5, -2e-4, 4e-4, 0)
    dev[3, 0] = (0, 0, 1e-5, 1e-4, 1e-4, 0)
    r = solve_reactions(m, g, w, dev)
    k = kinematics(PHI)
    phi1, phi2, phi3_cb = k["phi"].T
    s = {"phi1": phi1, "phi2": phi2, "phi3": phi3_cb + np.pi, "Q": r.Q,
         "F1x": forces[:, 0, 0], "F1y": forces[:, 0, 1], "M1": moments[:, 0],
         "F2x": forces[:, 1, 0], "F2y": forces[:, 1, 1], "M2": moments[:, 1],
         "F3x": forces[:, 2, 0], "F3y": forces[:, 2, 1], "M3": moments[:, 2]}
    for j, name in enumerate(("0", "A", "B", "C")):
        s[f"R{name}x"], s[f"R{name}y"], s[f"R{name}z"] = r.fx[j], r.fy[j], r.fz[j]
        s[f"M{name}x"], s[f"M{name}y"] = r.mx[j], r.my[j]
    return s


S = _paper_state()


def _zero(expr, scale):
    return np.max(np.abs(expr)) < 1e-9 * scale


def _nonzero(expr, scale):
    return np.max(np.abs(expr)) > 1e-3 * scale


FSCALE = np.max(np.abs([S["R0x"], S["R0y"], S["RAx"], S["RBx"], S["RCx"]]))
MSCALE = max(FSCALE * 0.1, np.max(np.abs(S["MBx"])))


def test_state_has_all_out_of_plane_components():
    for key in ("R0z", "RBz", "MAx", "MBy", "MCx", "M0y"):
        assert np.max(np.abs(S[key])) > 1e-3


def test_paper004_eq2_rocker_forces():
    s = S
    assert _zero(s["RCx"] + s["F3x"] + s["RBx"], FSCALE)
    assert _zero(s["RCy"] + s["F3y"] + s["RBy"], FSCALE)
    assert _zero(s["RBz"] + s["RCz"], FSCALE)


def test_paper004_eq3_rocker_moments_printed_vs_corrected():
    """(3a), (3b): the F3 terms are printed as +F3x e_C and -F3y e_C (components swapped); the
    moment of F3 (at height e_C above C) is -F3y e_C about x and +F3x e_C about y. Also, with
    φ3 = B->C, the R_Bz terms change sign (as the R_B terms of the third row, see the planar
    errata)."""
    s = S
    c3, s3 = np.cos(s["phi3"]), np.sin(s["phi3"])
    lev = EC + EB
    printed_a = s["MBx"] + s["RBz"] * L3 * s3 - s["RBy"] * lev + s["F3x"] * EC + s["MCx"]
    printed_b = s["MBy"] + s["RBx"] * lev - s["RBz"] * L3 * c3 - s["F3y"] * EC + s["MCy"]
    fixed_a = s["MBx"] - s["RBz"] * L3 * s3 - s["RBy"] * lev - s["F3y"] * EC + s["MCx"]
    fixed_b = s["MBy"] + s["RBx"] * lev + s["RBz"] * L3 * c3 + s["F3x"] * EC + s["MCy"]
    assert _zero(fixed_a, MSCALE) and _zero(fixed_b, MSCALE)
    assert _nonzero(printed_a, MSCALE) and _nonzero(printed_b, MSCALE)
    # with phi3 = C->B (the other convention) the R_Bz terms are as printed, the F3 terms not
    s3cb = -s3
    mixed_a = s["MBx"] + s["RBz"] * L3 * s3cb - s["RBy"] * lev + s["F3x"] * EC + s["MCx"]
    assert _nonzero(mixed_a, MSCALE)
    only_f3_fixed = s["MBx"] + s["RBz"] * L3 * s3cb - s["RBy"] * lev - s["F3y"] * EC + s["MCx"]
    assert _zero(only_f3_fixed, MSCALE)


def test_paper004_eq4_coupler_forces_with_typo():
    """(4): printed F_B^y in the y row is F_2^y (a typo; F_B is not defined)."""
    s = S
    assert _zero(s["RAx"] - s["RBx"] + s["F2x"], FSCALE)
    assert _zero(s["RAy"] - s["RBy"] + s["F2y"], FSCALE)
    assert _zero(s["RAz"] - s["RBz"], FSCALE)


def test_paper004_eq5_coupler_moments_rows_1_2():
    s = S
    c2, s2 = np.cos(s["phi2"]), np.sin(s["phi2"])
    assert _zero(s["MAx"] - s["RBz"] * L2 * s2 - s["MBx"], MSCALE)
    assert _zero(s["MAy"] + s["RBz"] * L2 * c2 - s["MBy"], MSCALE)


def test_paper004_eq6_crank_forces():
    s = S
    assert _zero(s["R0x"] - s["RAx"] + s["F1x"], FSCALE)
    assert _zero(s["R0y"] - s["RAy"] + s["F1y"], FSCALE)
    assert _zero(s["R0z"] - s["RAz"], FSCALE)


def test_paper004_eq7_crank_moments_rows_1_2():
    """(7a) holds with lever arm e0; (7b) is printed with e_A and M_Cy: the same lever arm e0 and
    the moment of the joint at the crank's other end, M_Ay, belong there."""
    s = S
    c1, s1 = np.cos(s["phi1"]), np.sin(s["phi1"])
    assert _zero(s["M0x"] - s["RAz"] * L1 * s1 + s["RAy"] * E0 - s["MAx"], MSCALE)
    printed_b = s["M0y"] - s["RAx"] * EA + s["RAz"] * L1 * c1 - s["MCy"]
    fixed_b = s["M0y"] - s["RAx"] * E0 + s["RAz"] * L1 * c1 - s["MAy"]
    assert _zero(fixed_b, MSCALE)
    assert _nonzero(printed_b, MSCALE)
    # each of the two printed errors alone breaks the equation
    assert _nonzero(s["M0y"] - s["RAx"] * E0 + s["RAz"] * L1 * c1 - s["MCy"], MSCALE)
    assert _nonzero(s["M0y"] - s["RAx"] * EA + s["RAz"] * L1 * c1 - s["MAy"], MSCALE)


def test_paper004_eq1_z_row_only_the_signed_loop_sum_of_dz_matters():
    """(1), third row, corrected: the axial misfit of the loop is the sum of the axial offsets of
    the mating elements taken around the loop O->A->B->C->O (joint C is traversed from the rocker
    to the ground, hence its sign). Two sets of dz with the same loop sum give the same reactions;
    the nominal axis lengths e do not enter (the printed row, e0 + eA + eB + sum dz + z_C = z_C,
    cannot hold for positive e and small deviations)."""
    m = spatial_model(e=(E0, EA, EB, EC), z=Z)
    g = geometry(PHI)
    w0 = np.zeros((len(PHI), 3, 6))

    def gap_dev(vals):
        d = np.zeros((4, 2, 6))
        d[0, 1, 2], d[1, 1, 2], d[2, 0, 2], d[3, 0, 2] = vals   # various elements
        return d

    # misfit delta_j = dev_b - dev_a; loop sum = delta_O + delta_A + delta_B - delta_C
    def loop_sum(vals):
        return vals[0] + vals[1] - vals[2] + vals[3]

    v1 = (1e-5, 0.0, 0.0, 0.0)
    v2 = (3e-6, 4e-6, -2e-6, 1e-6)
    assert np.isclose(loop_sum(v1), loop_sum(v2))
    r1 = solve_reactions(m, g, w0, gap_dev(v1)).components()
    r2 = solve_reactions(m, g, w0, gap_dev(v2)).components()
    assert np.max(np.abs(r1)) > 0.01
    assert np.max(np.abs(r1 - r2)) < 1e-9 * np.max(np.abs(r1))
    v3 = (2e-6, 2e-6, 2e-6, 4e-6)    # loop sum 6e-6 instead of 1e-5
    r3 = solve_reactions(m, g, w0, gap_dev(v3)).components()
    assert np.max(np.abs(r3 - r1)) > 1e-3 * np.max(np.abs(r1))


def test_paper004_eq1_is_incomplete_tilts_stress_the_loop():
    """(1) has no rotational closure, yet axis tilts with zero axial misfit stress the loop (two of
    the q = 3 compatibility conditions are rotational)."""
    m = spatial_model(e=(E0, EA, EB, EC), z=Z)
    d = np.zeros((4, 2, 6))
    d[3, 0, 3] = 1e-4
    r = solve_reactions(m, geometry(PHI), np.zeros((len(PHI), 3, 6)), d)
    assert np.max(r.bending()) > 0.05


# ------------------------------------------------------------------------------------------------
# (14)-(19): the elimination algebra, with the coefficients the paper never defines drawn at
# random. The systems implied by the K definitions are solved directly.


@pytest.fixture
def coeffs():
    rng = np.random.default_rng(7)
    return {k: rng.uniform(0.5, 2.0) * rng.choice([-1, 1]) for k in (
        "a13", "a14", "a22", "a23", "a31", "a32", "a41", "a42", "a43", "a44", "b1", "b2", "b3",
        "b4", "a52", "a55", "a57", "a73", "a77", "a79", "a93", "a99", "a9_11", "a11_5", "a11_7",
        "a11_9", "a11_11", "b5", "b7", "b9", "b11", "RAz", "RBz")}


def test_paper004_eq14_17_elimination(coeffs):
    """Rows 1-4: a13 R_Bz + a14 R_Cz = b1; a22 R_Az + a23 R_Bz = b2; a31 R_Oz + a32 R_Az = b3;
    a41 R_Oz + a42 R_Az + a43 R_Bz + a44 R_Cz = b4 (the form implied by K1..K4). (14)-(16) and
    K1..K4 check out; the denominator of (17) is printed divided by itself and with a41 in its
    second term where a43 belongs."""
    c = coeffs
    A = np.array([[0, 0, c["a13"], c["a14"]], [0, c["a22"], c["a23"], 0],
                  [c["a31"], c["a32"], 0, 0], [c["a41"], c["a42"], c["a43"], c["a44"]]])
    R0z, RAz, RBz, RCz = np.linalg.solve(A, [c["b1"], c["b2"], c["b3"], c["b4"]])
    K1 = c["b1"] / c["a13"]
    K2 = (c["b2"] - c["a23"] * K1) / c["a22"]
    K3 = (c["b3"] - c["a32"] * K2) / c["a31"]
    K4 = c["b4"] - c["a41"] * K3 - c["a42"] * K2 - c["a43"] * K1
    assert np.isclose(RBz, K1 - c["a14"] / c["a13"] * RCz)                              # (14)
    assert np.isclose(RAz, K2 + c["a23"] * c["a14"] / (c["a22"] * c["a13"]) * RCz)      # (15)
    chain = c["a32"] * c["a23"] * c["a14"] / (c["a31"] * c["a22"] * c["a13"])
    assert np.isclose(R0z, K3 - chain * RCz)                                             # (16)

    def den(first):
        return (c["a44"] - c[first] * c["a14"] / c["a13"]
                + c["a42"] * c["a23"] * c["a14"] / (c["a22"] * c["a13"]) - c["a41"] * chain)

    assert np.isclose(RCz, K4 / den("a43"))                                  # (17) corrected
    assert not np.isclose(RCz, K4 / den("a41"))                              # (17) index as printed
    assert not np.isclose(RCz, K4 / (den("a41") / den("a41")))               # (17) as typeset


def test_paper004_eq18_19_elimination(coeffs):
    """Rows 5, 7, 9, 11: a57 M_Ax + a55 M_Ox + a52 R_Az = b5; a79 M_Bx + a77 M_Ax + a73 R_Bz =
    b7; a9,11 M_Cx + a99 M_Bx + a93 R_Bz = b9; a11,5 M_Ox + a11,7 M_Ax + a11,9 M_Bx + a11,11 M_Cx
    = b11 (implied by K5, K7, K9, K11). The third line of (18) must read K7 (printed K5), the
    fourth line's inner bracket K7 + ... (printed K7 - ...), and (19)'s denominator is printed
    with an extra division by a57 (and its left side as M_Ox^z)."""
    c = coeffs
    A = np.array([[c["a55"], c["a57"], 0, 0], [0, c["a77"], c["a79"], 0],
                  [0, 0, c["a99"], c["a9_11"]],
                  [c["a11_5"], c["a11_7"], c["a11_9"], c["a11_11"]]])
    rhs = [c["b5"] - c["a52"] * c["RAz"], c["b7"] - c["a73"] * c["RBz"],
           c["b9"] - c["a93"] * c["RBz"], c["b11"]]
    MOx, MAx, MBx, MCx = np.linalg.solve(A, rhs)
    K5 = (c["b5"] - c["a52"] * c["RAz"]) / c["a57"]
    K7 = (c["b7"] - c["a73"] * c["RBz"] - c["a77"] * K5) / c["a79"]
    K9 = (c["b9"] - c["a93"] * c["RBz"] - c["a99"] * K7) / c["a9_11"]
    g = c["a77"] * c["a55"] / (c["a79"] * c["a57"])
    assert np.isclose(MAx, K5 - c["a55"] / c["a57"] * MOx)                     # (18) line 1
    assert np.isclose(MBx, K7 + g * MOx)                                        # line 3, fixed
    assert not np.isclose(MBx, K5 + g * MOx)                                    # line 3 printed
    inner_fixed = (c["b9"] - c["a93"] * c["RBz"] - c["a99"] * (K7 + g * MOx)) / c["a9_11"]
    inner_printed = (c["b9"] - c["a93"] * c["RBz"] - c["a99"] * (K7 - g * MOx)) / c["a9_11"]
    assert np.isclose(MCx, inner_fixed) and not np.isclose(MCx, inner_printed)  # line 4
    assert np.isclose(MCx, K9 - c["a99"] / c["a9_11"] * g * MOx)                # line 5
    K11 = c["b11"] - c["a11_7"] * K5 - c["a11_9"] * K7 - c["a11_11"] * K9
    den = (c["a11_5"] - c["a11_7"] * c["a55"] / c["a57"] + c["a11_9"] * g
           - c["a11_11"] * c["a99"] / c["a9_11"] * g)
    assert np.isclose(MOx, K11 / den)                                           # (19) corrected
    assert not np.isclose(MOx, K11 / (den / c["a57"]))                          # (19) as printed


# ------------------------------------------------------------------------------------------------
# the "5-25 %" of the paper: influence of redundancy on the bending moment in B vs e, deviation

_PHI72 = np.linspace(0.0, 2 * np.pi, 72, endpoint=False)


def _influence_ratio(e, tilt):
    """peak |M_B| / peak |Q| for the stacked loom four-bar, all axes of length e, a tilt of the
    frame's bore at C about x."""
    centres, forces, moments = loads(_PHI72)
    n = len(_PHI72)
    m = spatial_model(e=(e,) * 4, z=(0.0, e, e, -e))
    p3 = np.concatenate([centres, np.broadcast_to(np.array([0.0, e, 0.0]), (n, 3))[..., None]],
                        -1)
    f3 = np.concatenate([forces, np.zeros((n, 3, 1))], -1)
    m3 = np.zeros((n, 3, 3))
    m3[..., 2] = moments
    d = np.zeros((4, 2, 6))
    d[3, 0, 3] = tilt
    r = solve_reactions(m, geometry(_PHI72), wrench_about_origin(f3, m3, p3), d)
    return np.max(r.bending()[2]) / np.max(np.abs(r.Q))


def test_paper004_influence_of_redundancy_table():
    """The table of docs/redundancy.md (ratios in %, to 0.01): without deviation the ratio
    grows in proportion to e (lever arms of the in-plane forces), to 0.5 %."""
    table = {0.005: (3.16, 3.13, 3.08, 2.95), 0.01: (6.32, 6.20, 6.02, 5.92),
             0.02: (12.63, 12.21, 11.75, 14.05), 0.04: (25.25, 23.80, 24.15, 48.11),
             0.06: (37.82, 35.18, 40.29, 102.78)}
    for e, row in table.items():
        got = [100 * _influence_ratio(e, t) for t in (0.0, 1e-4, 3e-4, 1e-3)]
        assert np.allclose(got, row, atol=0.006), (e, got)
    base = _influence_ratio(0.01, 0.0)
    for e in (0.005, 0.02, 0.04):
        assert np.isclose(_influence_ratio(e, 0.0) / base, e / 0.01, rtol=5e-3)


def test_dropping_redundant_constraints_is_not_unique():
    """What a multibody code that drops the q = 3 redundant constraints reports depends on which
    ones it drops: releasing them as R-R-S-C or S-C-R-R joints (both q = 0, statically
    determinate) gives the same in-plane reactions and Q as the compliant model but different
    bending moments (docs/redundancy.md, 'Dropping the redundant constraints')."""
    e = 0.03
    centres, forces, moments = loads(_PHI72)
    n = len(_PHI72)
    p3 = np.concatenate([centres, np.broadcast_to(np.array([0.0, e, 0.0]), (n, 3))[..., None]],
                        -1)
    f3 = np.concatenate([forces, np.zeros((n, 3, 1))], -1)
    m3 = np.zeros((n, 3, 3))
    m3[..., 2] = moments
    w = wrench_about_origin(f3, m3, p3)
    out = {}
    for kinds in [("revolute",) * 4, ("revolute", "revolute", "spherical", "cylindrical"),
                  ("spherical", "cylindrical", "revolute", "revolute")]:
        m = spatial_model(e=(e,) * 4, z=(0.0, e, e, -e), kinds=kinds)
        out[kinds[0] + kinds[2]] = solve_reactions(m, geometry(_PHI72), w)
    full, rrsc, scrr = out["revoluterevolute"], out["revolutespherical"], out["sphericalrevolute"]
    for r in (rrsc, scrr):
        assert np.allclose(r.fx, full.fx, rtol=1e-9, atol=1e-9)
        assert np.allclose(r.Q, full.Q, rtol=1e-9, atol=1e-9)
    peaks = {k: np.round(np.max(v.bending(), axis=1), 2) for k, v in
             (("full", full), ("rrsc", rrsc), ("scrr", scrr))}
    assert np.allclose(peaks["full"], [1.62, 1.13, 1.22, 1.89])
    assert np.allclose(peaks["rrsc"], [2.36, 0.0, 0.0, 2.93])
    assert np.allclose(peaks["scrr"], [0.0, 2.36, 2.36, 3.30])
