"""Every real assembly (issue 39): the sextic in the platform angle finds each assembly of a planar machine whose legs
put its platform joints on circles, none lost to naming. Anchors: ALIAS's 3-RPR (exactly its two assemblies), a
3-RPR pose with six, the hand-derived five-bar's closed form on the five-bar of RR legs, Dietmaier's 6-6 platform
with 40 (the parameter homotopy); for random poses of the described 3-RRR and a 3-PRR every assembly closes, the
inverse kinematics gives the joints back in one of the working modes, and an independent solve (least squares on the
inverse kinematics from many starts, every working mode; a dense scan of the platform angle) finds no other."""

from __future__ import annotations

import copy
import json
import math
import warnings

import numpy as np
import pytest
from helpers import FIVE_BAR_OF_CHAINS, FIVE_BAR_OF_RR_LEGS, PRR3, delta_of_chains
from scipy.optimize import least_squares

import pkm
from pkm.errors import PkmError, SingularityWarning
from pkm.models.described import DESCRIPTIONS


def _rpr3(name: str, base: list, platform: list, home: list) -> dict:
    return {"name": name, "doc": "a planar 3-RPR, its joints listed", "frame": "planar", "home": home,
            "parameters": [{"name": "s", "default": 1.0, "lower": 0.1, "upper": 10, "unit": "m", "doc": "scale"}],
            "legs": {"kind": "RPR", "count": 3, "base": [[f"{x} * s", f"{y} * s"] for x, y in base],
                     "platform": [[f"{x} * s", f"{y} * s"] for x, y in platform]}}


# ALIAS-C++'s example: base joints (0,0), (10,0), (3,10); platform points (0,0), (4,0), (2,2)
ALIAS = _rpr3("alias_3rpr", [(0, 0), (10, 0), (3, 10)], [(0, 0), (4, 0), (2, 2)], [5, 5, 0])
# a 3-RPR (unit scale) and leg lengths at which it has six real assemblies
SIX = _rpr3("six_3rpr", [(0.068, -0.918), (0.072, 0.26), (-0.823, -0.039)],
            [(0.531, -0.525), (-0.545, -0.476), (0.218, 0.472)], [0, 0, 0])
SIX_LENGTHS = [1.317, 1.0585, 0.9095]


def _load(raw: dict) -> pkm.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        return pkm.load(raw)


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * a))


def _independent(m: pkm.Mechanism, q_a: np.ndarray, box: np.ndarray, starts: int, seed: int) -> list[np.ndarray]:
    """The poses where some working mode's inverse kinematics gives ``q_a``: least squares from random starts
    in ``box`` (2, n) for each mode, the distinct converged ones."""
    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    angles = np.array([u == "rad" for u in m.actuator_units])
    for mode in m.modes:
        def residual(x, mode=mode):
            q = m.inverse_kinematics(x, mode=mode)
            if not np.all(np.isfinite(q)):
                return np.full(len(q_a), 10.0)
            gap = q - q_a
            gap[angles] = _wrapped(gap[angles])
            return gap

        for start in rng.uniform(box[0], box[1], size=(starts, len(box[0]))):
            fit = least_squares(residual, start, xtol=1e-14, ftol=1e-14, gtol=1e-14)
            x = fit.x.copy()
            if m.n_out == 3:
                x[2] = _wrapped(x[2])
            if np.max(np.abs(fit.fun)) < 1e-9 and not any(np.allclose(x, y, atol=1e-6) for y in found):
                found.append(x)
    return found


SCAN = 40_001  # platform angles of the dense scan


def _scanned(m: pkm.Mechanism, q_a: np.ndarray, design: np.ndarray) -> np.ndarray:
    """The platform angles of a planar machine's assemblies by a dense scan: at each angle the platform's
    position from the first curve's equation less each other's (alpha |P_i|^2 + beta_i . P_i + gamma_i: a 2 x 2
    solve, the first curve a circle where there is one), the first equation there times the solve's determinant
    squared, its sign changes refined by bisection; in order."""
    alpha, beta, gamma = (np.asarray(v, dtype=float) for v in m.functions["platform_loci"](q_a, design))
    points = np.asarray(m.functions["platform_points"](design), dtype=float)
    order = np.argsort(-alpha.ravel(), kind="stable")
    alpha, gamma, beta, points = alpha.ravel()[order], gamma.ravel()[order], beta[order], points[order]

    def first(phi: np.ndarray) -> np.ndarray:
        rotation = np.stack([np.cos(phi), -np.sin(phi), np.sin(phi), np.cos(phi)], axis=-1).reshape(-1, 2, 2)
        w = np.einsum("nij,kj->nki", rotation, points)
        const = alpha * np.sum(w**2, axis=2) + np.sum(beta * w, axis=2) + gamma
        grad = 2 * alpha[:, None] * w + beta
        system = grad[:, 1:] - alpha[1:, None] * grad[:, :1]
        det = np.linalg.det(system)
        position = np.linalg.solve(system, -(const[:, 1:] - alpha[1:] * const[:, :1])[..., None])[..., 0]
        return (alpha[0] * np.sum(position**2, axis=1) + np.sum(position * grad[:, 0], axis=1) + const[:, 0]) * det**2

    phi = np.linspace(-np.pi, np.pi, SCAN)
    values = first(phi)
    lo, hi = phi[:-1][np.sign(values[:-1]) * np.sign(values[1:]) < 0], phi[1:][np.sign(values[:-1]) * np.sign(
        values[1:]) < 0]
    for _ in range(45):
        mid = (lo + hi) / 2
        left = np.sign(first(lo)) * np.sign(first(mid)) <= 0
        lo, hi = np.where(left, lo, mid), np.where(left, mid, hi)
    return np.sort((lo + hi) / 2)


def _gives_back_the_joints(m: pkm.Mechanism, found: np.ndarray, q_a: np.ndarray, angles: np.ndarray) -> None:
    """Each assembly's pose gives back the actuated joints by the inverse kinematics of some working mode, to
    1e-8 (angles wrapped)."""
    for pose in found:
        back = np.array([m.inverse_kinematics(pose, mode=mode) for mode in m.modes])
        gap = back - q_a
        gap[:, angles] = _wrapped(gap[:, angles])
        assert np.nanmin(np.max(np.abs(gap), axis=1)) < 1e-8


def _poses(a, row: int = 0) -> np.ndarray:
    return a.poses[row, : a.counts[row]]


def test_alias_3rpr_has_exactly_its_two_assemblies():
    a = _load(ALIAS).every_assembly(np.sqrt([50.0, 26.0, 25.0]), certify=True)
    assert a.counts.tolist() == [2]
    assert a.certified.tolist() == [True]
    assert a.bound == 6
    assert a.failed.tolist() == [0]
    np.testing.assert_allclose(_poses(a), [[3.369707132, 6.216516219, -0.8067834380], [5, 5, 0]], atol=1e-9)
    assert np.nanmax(a.residuals) < 1e-12


def test_a_3rpr_pose_with_six_assemblies_has_all_six():
    m = _load(SIX)
    a = m.every_assembly(SIX_LENGTHS, certify=True)
    assert a.counts.tolist() == [6]
    assert a.certified.tolist() == [True]
    independent = _independent(m, np.array(SIX_LENGTHS), np.array([[-2, -2, -np.pi], [2, 2, np.pi]]), 60, 1)
    assert len(independent) == 6
    for x in independent:
        assert np.min(np.max(np.abs(np.c_[_poses(a)[:, :2] - x[:2], _wrapped(_poses(a)[:, 2] - x[2])]), axis=1)) < 1e-7


@pytest.mark.parametrize("source", ["rrr3", "prr3"])
def test_every_assembly_closes_gives_the_joints_back_and_none_is_missed(source):
    """At 20 random poses of random working modes: the pose the joints came from is among the assemblies, each
    assembly's inverse kinematics gives the joints back in some working mode (FK then IK), and a dense scan of
    the platform angle finds the same angles, none missed."""
    m = pkm.load(str(DESCRIPTIONS["rrr3"])) if source == "rrr3" else _load(PRR3)
    rng = np.random.default_rng(21)
    x = rng.uniform([-0.25, -0.25, -0.5], [0.25, 0.25, 0.5], size=(60, 3))
    modes = [m.modes[k] for k in rng.integers(len(m.modes), size=60)]
    q = np.array([m.inverse_kinematics(p, mode=mode) for p, mode in zip(x, modes, strict=True)])
    keep = np.flatnonzero(np.isfinite(q).all(axis=1))[:20]
    assert len(keep) == 20
    a = m.every_assembly(q[keep], certify=True)
    assert a.certified.all()
    angles = np.array([u == "rad" for u in m.actuator_units])
    for row, k in enumerate(keep):
        found = _poses(a, row)
        assert np.min(np.max(np.abs(np.c_[found[:, :2] - x[k, :2], _wrapped(found[:, 2] - x[k, 2])]), axis=1)) < 1e-8
        assert np.nanmax(a.residuals[row]) < 1e-10
        _gives_back_the_joints(m, found, q[k], angles)
    design = m.design().vector()
    for row, k in enumerate(keep):
        angles = _scanned(m, q[k], design)
        np.testing.assert_allclose(np.sort(_poses(a, row)[:, 2]), angles, atol=1e-7)


SLIDE = [{"type": "R", "actuated": True, "link": [0, "e"]}, {"type": "P", "axis": [1, 0]}]  # on a line it turns
SLIDE_BRANCHES = {"plus": [2.852, 0.671], "minus": [0.2896, -0.671]}  # at C - A = (-0.7, 0) in the leg's frame
LENGTHS = [{"name": "R", "default": 1.0, "lower": 0.1, "upper": 5, "unit": "m", "doc": "base circle"},
           {"name": "r", "default": 0.3, "lower": 0.05, "upper": 5, "unit": "m", "doc": "platform circle"},
           {"name": "e", "default": 0.2, "lower": 0.0, "upper": 5, "unit": "m",
            "doc": "a slide's offset from its arm's joint"}]
LINES3 = {"name": "slides3", "doc": "a planar 3-RPR with actuated base revolutes: each platform joint on a line its "
          "arm turns", "frame": "planar", "home": [0, 0, 0], "characteristic_length": "r", "parameters": LENGTHS,
          "legs": {"kind": "chain", "count": 3, "base": {"circle": "R", "start": "pi/2"},
                   "platform": {"circle": "r", "start": "pi/2"}, "joints": SLIDE, "branches": SLIDE_BRANCHES}}
MIXED3 = {"name": "rr2_slide", "doc": "two RR legs and a slide", "frame": "planar", "home": [0, 0, 0],
          "characteristic_length": "r", "parameters": [*LENGTHS, {"name": "l", "default": 0.6, "lower": 0.1,
                                                                 "upper": 5, "unit": "m", "doc": "RR links"}],
          "legs": [{"kind": "RR", "count": 2, "base": {"circle": "R", "start": "pi/2"},
                    "platform": {"circle": "r", "start": "pi/2"}, "proximal": "l", "distal": "l"},
                   {"kind": "chain", "base": [["R*cos(-pi/6)", "R*sin(-pi/6)"]],
                    "platform": [["r*cos(-pi/6)", "r*sin(-pi/6)"]], "turn": ["-pi/6"], "joints": SLIDE,
                    "branches": SLIDE_BRANCHES}]}
POINT_SLIDE = {"name": "rr_slide", "doc": "a planar point on an RR leg and a slide", "frame": "planar_point",
               "home": [0, 0.8], "parameters": LENGTHS[2:],
               "legs": [{"kind": "RR", "base": [[-0.5, 0]], "platform": [[0, 0]], "proximal": 0.6, "distal": 0.6},
                        {"kind": "chain", "base": [[0.5, 0]], "platform": [[0, 0]], "joints": SLIDE,
                         "branches": {"plus": [1.915, 0.922], "minus": [-0.799, -0.922]}}]}


def _scanned_on_the_line(m: pkm.Mechanism, q_a: np.ndarray, design: np.ndarray) -> np.ndarray:
    """A planar point's assemblies whose second leg is a slide, by a dense scan along the slide's line: the first
    leg's curve's equation at each of its points, its sign changes refined by bisection; in the order of x."""
    alpha, beta, gamma = (np.asarray(v, dtype=float) for v in m.functions["platform_loci"](q_a, design))
    alpha, gamma = alpha.ravel(), gamma.ravel()
    foot, along = -gamma[1] * beta[1], np.array([-beta[1, 1], beta[1, 0]])

    def first(t: np.ndarray) -> np.ndarray:
        p = foot + t[:, None] * along
        return alpha[0] * np.sum(p**2, axis=1) + p @ beta[0] + gamma[0]

    t = np.linspace(-5, 5, SCAN)
    values = first(t)
    change = np.sign(values[:-1]) * np.sign(values[1:]) < 0
    lo, hi = t[:-1][change], t[1:][change]
    for _ in range(50):
        mid = (lo + hi) / 2
        left = np.sign(first(lo)) * np.sign(first(mid)) <= 0
        lo, hi = np.where(left, lo, mid), np.where(left, mid, hi)
    points = foot + ((lo + hi) / 2)[:, None] * along
    return points[np.argsort(points[:, 0])]


@pytest.mark.parametrize("raw", [LINES3, MIXED3, POINT_SLIDE], ids=lambda raw: raw["name"])
def test_legs_on_lines_have_every_assembly_and_none_is_missed(raw):
    """A leg whose passive joint is a prismatic puts its platform joint on a line (the derived platform_loci): at
    random poses of random working modes the assemblies contain the pose, close, give the joints back through the
    inverse kinematics in some mode, and are those a dense scan of the platform angle finds (in the plane; for a
    point, of the slide's line), the count certified."""
    m = _load(raw)
    home = np.asarray(m.functions["home"](m.design().vector()), dtype=float).ravel()
    alpha, *_ = m.functions["platform_loci"](m.inverse_kinematics(home), m.design().vector())
    assert 0 in np.asarray(alpha).ravel()
    rng = np.random.default_rng(8)
    box = np.array([[-0.15, -0.15, -0.3], [0.15, 0.15, 0.3]])[:, : m.n_out] + ([0, 0.8] if m.n_out == 2 else 0)
    x = rng.uniform(box[0], box[1], size=(60, m.n_out))
    modes = [m.modes[k] for k in rng.integers(len(m.modes), size=60)]
    q = np.array([m.inverse_kinematics(p, mode=mode) for p, mode in zip(x, modes, strict=True)])
    keep = np.flatnonzero(np.isfinite(q).all(axis=1))[:12]
    assert len(keep) == 12
    a = m.every_assembly(q[keep], certify=m.n_out == 3)
    if m.n_out == 3:
        assert a.certified.all()
    angles = np.array([u == "rad" for u in m.actuator_units])
    design = m.design().vector()
    for row, k in enumerate(keep):
        found = _poses(a, row)
        gap = found - x[k]
        gap[:, 2:] = _wrapped(gap[:, 2:])
        assert np.min(np.max(np.abs(gap), axis=1)) < 1e-8
        assert np.nanmax(a.residuals[row]) < 1e-10
        _gives_back_the_joints(m, found, q[k], angles)
        if m.n_out == 3:
            np.testing.assert_allclose(np.sort(found[:, 2]), _scanned(m, q[k], design), atol=1e-7)
        else:
            np.testing.assert_allclose(found[np.argsort(found[:, 0])], _scanned_on_the_line(m, q[k], design),
                                       atol=1e-7)


def test_the_five_bar_of_rr_legs_has_the_hand_derived_five_bars_assemblies():
    described = _load(copy.deepcopy(FIVE_BAR_OF_RR_LEGS))
    hand = pkm.load("five_bar")
    rng = np.random.default_rng(4)
    q = rng.uniform(-math.pi, math.pi, size=(200, 2))
    mine, theirs = described.every_assembly(q), hand.every_assembly(q, hand.design())
    assert mine.bound == theirs.bound == 2
    np.testing.assert_array_equal(mine.counts, theirs.counts)
    assert 20 < mine.counts.sum() < 400
    for row in np.flatnonzero(mine.counts):
        a, b = _poses(mine, row), _poses(theirs, row)
        assert np.max(np.min(np.linalg.norm(a[:, None] - b[None], axis=2), axis=1)) < 1e-10


# Dietmaier's 6-6 geometry with 40 real assemblies (ARK 1998), as tabulated in martyushev/fkSGP (MIT): base
# joints, platform joints, leg lengths, and one of its poses
DIETMAIER_BASE = [[0, 0, 0], [1.107915, 0, 0], [0.549094, 0.756063, 0], [0.735077, -0.223935, 0.525991],
                  [0.514188, -0.526063, -0.368418], [0.590473, 0.094733, -0.205018]]
DIETMAIER_PLATFORM = [[0, 0, 0], [0.542805, 0, 0], [0.956919, -0.528915, 0], [0.665885, -0.353482, 1.402538],
                      [0.478359, 1.158742, 0.107672], [-0.137087, -0.235121, 0.353913]]
DIETMAIER_LENGTHS = [1, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]
DIETMAIER_ROTATION = [[-0.040450357031281, -0.932229494397471, 0.359599691867884],
                      [0.983337493748685, 0.026695523074364, 0.179818582009314],
                      [-0.177231887661606, 0.360881585597300, 0.915616371179918]]
DIETMAIER_TRANSLATION = [0.955868038233880, -0.046995628998516, -0.290013283037649]


def _pose(rotation, translation) -> np.ndarray:
    """(x, y, z, roll, pitch, yaw) with R = Rz(yaw) Ry(pitch) Rx(roll), as the spatial frame states it."""
    r = np.asarray(rotation)
    return np.array([*translation, math.atan2(r[2, 1], r[2, 2]), math.asin(-r[2, 0]), math.atan2(r[1, 0], r[0, 0])])


def test_dietmaiers_stewart_gough_platform_has_all_40_real_assemblies():
    """Every one of the 40 paths arrives at a real assembly that closes every leg, the tabulated pose among
    them; the inverse kinematics gives the legs' lengths back at each."""
    raw = {"name": "dietmaier", "doc": "Dietmaier's 6-6 platform", "frame": "spatial",
           "home": _pose(DIETMAIER_ROTATION, DIETMAIER_TRANSLATION).tolist(),
           "parameters": [{"name": "s", "default": 1.0, "lower": 0.1, "upper": 10, "unit": "m", "doc": "scale"}],
           "legs": {"kind": "UPS", "count": 6, "base": [[f"{v} * s" for v in b] for b in DIETMAIER_BASE],
                    "platform": [[f"{v} * s" for v in c] for c in DIETMAIER_PLATFORM]}}
    m = _load(raw)
    lengths = np.array(DIETMAIER_LENGTHS)
    found = m.every_assembly(lengths)
    assert found.bound == 40
    assert found.failed.tolist() == [0]
    assert found.counts.tolist() == [40]
    assert np.nanmax(found.residuals) < 1e-10
    poses = found.poses[0]
    gap = np.abs(poses - _pose(DIETMAIER_ROTATION, DIETMAIER_TRANSLATION))
    gap[:, 3:] = np.abs(_wrapped(gap[:, 3:]))
    assert np.min(np.max(gap, axis=1)) < 1e-9
    assert np.max(np.abs(m.inverse_kinematics(poses) - lengths)) < 1e-9


def test_the_stewart_platforms_assemblies_close_give_the_joints_back_and_come_in_an_even_number():
    """At random poses of the shipped 6-UPS (its joints in pairs on two circles: a special geometry, whose paths
    that do not arrive are as many at every pose, their ends not finite there), the real assemblies (an even
    number: the other finite solutions are complex conjugate pairs) close every leg, the pose the joints came
    from is among them, and the inverse kinematics gives the joints back at each within the machine's limits."""
    m = pkm.load("stewart")
    rng = np.random.default_rng(11)
    poses = np.column_stack([rng.uniform(-0.1, 0.1, (20, 2)), rng.uniform(0.9, 1.1, 20),
                             rng.uniform(-0.2, 0.2, (20, 3))])
    q = m.inverse_kinematics(poses)
    inside = np.all(np.isfinite(q), axis=1)
    assert inside.sum() >= 10
    poses, q = poses[inside], q[inside]
    found = m.every_assembly(q)
    assert np.all(found.failed == found.failed[0])
    assert found.failed[0] % 2 == 0
    assert np.all(found.counts % 2 == 0)
    assert np.all(found.counts >= 2)
    for row, pose in enumerate(poses):
        closed = found.poses[row, : found.counts[row]]
        assert np.max(found.residuals[row, : found.counts[row]]) < 1e-10
        gap = np.abs(closed - pose)
        gap[:, 3:] = np.abs(_wrapped(gap[:, 3:]))
        assert np.min(np.max(gap, axis=1)) < 1e-9
        back = m.inverse_kinematics(closed)  # NaN beyond the legs' strokes and the joints' cones
        reached = np.all(np.isfinite(back), axis=1)
        assert reached.any()
        assert np.max(np.abs(back[reached] - q[row])) < 1e-9


def test_the_delta_has_its_two_assemblies_where_three_spheres_meet():
    """Each Delta leg puts the platform's joint on the sphere about its elbow (the rods' length its radius):
    its assemblies are where the three spheres meet, both that its named assembly modes find where they close,
    and the Delta of chains (an actuated R, then a parallelogram) has the same; each gives every leg's joint
    back on one of its branches."""
    delta = pkm.load("delta")
    chains = _load(delta_of_chains())
    design = {p.name: delta.design()[p.name] for p in chains.parameters}
    x = np.random.default_rng(8).uniform([-0.3, -0.3, -0.8], [0.3, 0.3, -0.2], size=(300, 3))
    q = delta.inverse_kinematics(x, mode="elbow_out")
    q = q[np.isfinite(q).all(axis=1)]
    assert len(q) > 100
    a = delta.every_assembly(q)
    assert a.bound == 2
    named = np.stack([delta.forward_kinematics(q, assembly=name) for name in delta.assemblies], axis=1)
    for row in range(len(q)):
        found = _poses(a, row)
        for pose in named[row][np.isfinite(named[row]).all(axis=1)]:
            assert np.min(np.max(np.abs(found - pose), axis=1)) < 1e-9
        for pose in found:  # each leg's joint back on one of its two branches
            back = np.array([delta.inverse_kinematics(pose, mode=mode, limits=False) for mode in delta.modes])
            assert np.max(np.nanmin(np.abs(_wrapped(back - q[row])), axis=0)) < 1e-9
    theirs = chains.every_assembly(q, design)
    np.testing.assert_array_equal(theirs.counts, a.counts)
    np.testing.assert_allclose(np.nan_to_num(theirs.poses, nan=9.0), np.nan_to_num(a.poses, nan=9.0), atol=1e-10)


def test_pkm_fk_out_writes_the_json_and_each_assemblys_linkage_drawn(tmp_path, capsys):
    from PIL import Image

    from pkm.cli import main

    out = tmp_path / "fk"
    assert main(["fk", str(DESCRIPTIONS["rrr3"]), "--joints=-0.48915,1.442464,3.545811", "--out", str(out)]) == 0
    assert "wrote " in capsys.readouterr().out
    data = json.loads((out / "fk.json").read_text())
    assert data["count"] == 2
    assert sorted(p.name for p in out.iterdir()) == ["fk.json", "fk.png", "fk.svg"]
    width, height = Image.open(out / "fk.png").size
    assert width > height > 100


def test_pkm_fk_lists_every_assembly_with_its_residual_mode_and_margins(capsys):
    from pkm.cli import main

    assert main(["fk", "five_bar", "--joints", "1.5,1.2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["count"], data["bound"], data["failed"]) == (2, 2, 0)
    hand = pkm.load("five_bar")
    for row in data["assemblies"]:
        assert row["residual"] < 1e-12
        pose = [row["pose"][n] for n in hand.pose_names]
        np.testing.assert_allclose(hand.inverse_kinematics(pose, mode=row["mode"]), [1.5, 1.2], atol=1e-10)
        assert 0 < row["singularity_margin_type1"] <= 1
        assert 0 < row["singularity_margin_type2"] <= 1
    assert main(["fk", "five_bar", "--joints", "86,69", "--units", "mm,deg"]) == 0
    text = capsys.readouterr().out
    assert text.startswith("five_bar: 2 real assemblies (at most 2")
    assert " mm, y = " in text
    assert main(["fk", str(DESCRIPTIONS["rrr3"]), "--joints=-0.48915,1.442464,3.545811", "--certify",
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["count"], data["certified"]) == (2, True)
    assert main(["fk", "five_bar", "--joints", "1,x"]) == 2
    assert "--joints '1,x' violates: 2 numbers, comma-separated" in capsys.readouterr().err
    assert main(["fk", "five_bar", "--joints", "1,nan"]) == 2
    assert "--joints violates: finite numbers; theta2 = nan" in capsys.readouterr().err
    assert main(["fk", "stewart", "--joints", "0.8,0.8,0.8,0.8,0.8,0.8", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["bound"], data["count"] % 2) == (40, 0)
    assert data["count"] >= 2
    assert max(row["residual"] for row in data["assemblies"]) < 1e-10


def test_a_double_root_at_a_singularity_is_not_certified():
    """The in-line 3-RPR (its platform a scaled copy of its base) is type II singular over phi = 0: at its home
    pose two assemblies meet there, the sextic's root is double, and the count is not certified (rather than
    certified wrong); a pose off the singular plane is."""
    rpr3 = _rpr3("inline_3rpr", [(0, 1), (-0.866, -0.5), (0.866, -0.5)], [(0, 0.4), (-0.3464, -0.2), (0.3464, -0.2)],
                 [0, 0, 0])
    m = _load(rpr3)
    q = m.inverse_kinematics([[0.0, 0.0, 0.0], [0.05, 0.02, 0.3]])
    a = m.every_assembly(q, certify=True)
    assert a.certified.tolist() == [False, True]


def test_along_a_path_of_the_joints_each_column_follows_one_assembly():
    """The 3-RRR's joints along a closed path of poses (one working mode, 400 steps) where the machine has 2, 4
    and 6 assemblies in turn: followed, the column that holds the first pose holds every pose of the path, and
    every column moves by small steps; sorted by the platform angle instead, the path's pose changes columns."""
    m = pkm.load(str(DESCRIPTIONS["rrr3"]))
    t = np.linspace(0, 2 * np.pi, 400)
    x = np.c_[0.25 * np.cos(t), 0.2 * np.sin(t), 1.2 * np.sin(2 * t)]
    q = m.inverse_kinematics(x, mode="left_left_left")
    assert np.isfinite(q).all()
    a = m.every_assembly(q, follow=True)
    first = np.flatnonzero(np.all(np.abs(a.poses[0] - x[0]) < 1e-8, axis=1))
    assert len(first) == 1
    np.testing.assert_allclose(a.poses[:, first[0]], x, atol=1e-8)
    steps = np.abs(np.diff(a.poses, axis=0))
    steps[..., 2] = np.abs(_wrapped(np.diff(a.poses[..., 2], axis=0)))
    assert np.nanmax(steps) < 0.2
    ranked = m.every_assembly(q)
    assert set(ranked.counts.tolist()) == {2, 4, 6}
    gaps = np.nanmax(np.abs(ranked.poses - x[:, None, :]), axis=2, initial=0.0, where=np.isfinite(ranked.poses))
    column = np.argmin(np.where(np.isfinite(ranked.poses).all(axis=2), gaps, np.inf), axis=1)
    assert len(set(column.tolist())) > 1


def test_along_a_path_of_the_design_each_column_follows_one_assembly():
    """The 3-RRR at fixed joints while its platform's radius grows from 70 % to 130 % of its default (121 designs),
    where it has 2, 4 and 6 assemblies in turn: followed, the column of the pose at the default design holds one
    configuration that moves by small steps, every column does, and the joints are its inverse kinematics at
    each design; ranked (unfollowed), that configuration changes columns. A path gives one design per row, not a
    design as well."""
    m = pkm.load(str(DESCRIPTIONS["rrr3"]))
    x0 = np.array([0.15, -0.1, 0.8])
    q = m.inverse_kinematics(x0, mode="left_left_left")
    default = m.design(None)
    designs = [{**default, "r_p": v} for v in default["r_p"] * np.linspace(0.7, 1.3, 121)]
    a = m.every_assembly(q, designs=designs, follow=True)
    assert set(a.counts.tolist()) == {2, 4, 6}
    (column,) = np.flatnonzero(np.all(np.abs(a.poses[60] - x0) < 1e-8, axis=1))
    steps = np.abs(np.diff(a.poses, axis=0))
    steps[..., 2] = np.abs(_wrapped(np.diff(a.poses[..., 2], axis=0)))
    assert np.nanmax(steps) < 0.05
    path = a.poses[:, column]
    assert np.isfinite(path).all()
    for k in range(0, 121, 12):
        np.testing.assert_allclose(m.inverse_kinematics(path[k], designs[k], mode="left_left_left"), q, atol=1e-8)
    ranked = m.every_assembly(q, designs=designs)
    gaps = np.abs(ranked.poses - path[:, None, :]).max(axis=2)
    assert len(set(np.argmin(np.where(np.isfinite(gaps), gaps, np.inf), axis=1).tolist())) > 1
    with pytest.raises(PkmError, match="design and designs violate"):
        m.every_assembly(q, default, designs=designs)
    with pytest.raises(PkmError, match="designs violate: a design per row"):
        m.every_assembly(np.stack([q, q]), designs=designs)


POINT_RPR2 = {"name": "point_rpr2", "doc": "two RPR legs meeting at the platform's point", "frame": "planar_point",
              "home": [1, 1],
              "parameters": [{"name": "s", "default": 1.0, "lower": 0.001, "upper": 10, "unit": "m", "doc": "scale"}],
              "legs": {"kind": "RPR", "count": 2, "base": [[0, 0], ["2 * s", 0]], "platform": [[0, 0], [0, 0]]}}


def test_the_degenerate_cases_keep_every_assembly():
    """An angle at pi, where the sextic's degree drops; two mirror assemblies at one angle, where the two lines
    of the circles' differences are parallel; tangent circles; a negative prismatic length; a tiny machine
    beside a large one in one batch; certify asked where it does not apply."""
    alias = _load(ALIAS)
    for gap in (1e-10, 1e-12, 0.0):
        q = alias.inverse_kinematics([5.0, 5.0, np.pi - gap])
        found = _poses(alias.every_assembly(q))
        assert np.min(np.max(np.abs(np.c_[found[:, :2] - 5.0, _wrapped(found[:, 2] - np.pi + gap)]), axis=1)) < 1e-8
    # the centres B_i - R(phi) c_i on one line at phi = 0.3: P and its mirror in that line assemble at that angle
    c = np.array([[0.3, -0.2], [-0.25, -0.1], [0.05, 0.35]])
    rotation = np.array([[np.cos(0.3), -np.sin(0.3)], [np.sin(0.3), np.cos(0.3)]])
    centres = np.array([[-1.0, -0.4], [0.2, 0.1], [-1.0 + 1.7 * 1.2, -0.4 + 1.7 * 0.5]])
    base = centres + c @ rotation.T
    raw = _rpr3("mirror_3rpr", [tuple(b) for b in base.round(12)], [tuple(p) for p in c], [0.1, 0.6, 0.3])
    m = _load(raw)
    pose = np.array([0.1, 0.6, 0.3])
    direction = (centres[1] - centres[0]) / np.linalg.norm(centres[1] - centres[0])
    foot = centres[0] + np.dot(pose[:2] - centres[0], direction) * direction
    mirror = np.r_[2 * foot - pose[:2], 0.3]
    q = m.inverse_kinematics(pose)
    a = m.every_assembly(q, certify=True)
    for want in (pose, mirror):
        assert np.min(np.max(np.abs(_poses(a) - want), axis=1)) < 1e-8
    assert a.failed.tolist() == [0]
    two = _load(POINT_RPR2)
    assert two.every_assembly([1.0, 1.0]).counts.tolist() == [1]
    np.testing.assert_allclose(_poses(two.every_assembly([-1.0, 1.0])), [[1.0, 0.0]], atol=1e-9)
    tiny = two.every_assembly([[1e-3, 1e-3 * np.sqrt(4 + 1e-8)], [1.0, 1.0]], {"s": 1e-3 / 2 * 2})
    alone = two.every_assembly([1e-3, 1e-3 * np.sqrt(4 + 1e-8)], {"s": 1e-3})
    assert tiny.counts[0] == alone.counts[0] == 2
    with pytest.raises(PkmError, match=r"certify violates: a planar machine of three legs on circles"):
        pkm.load("five_bar").every_assembly([1.5, 1.2], certify=True)


def test_chains_of_both_circle_shapes_have_their_kinds_assemblies():
    """A two-joint chain puts its platform joint on a circle in two shapes: an actuated joint then a passive R
    (the five-bar of chains: its assemblies are the five-bar of RR legs'), and a passive R then an actuated P
    without links (the 3-RPR of chains: ALIAS's two)."""
    chains = _load(copy.deepcopy(FIVE_BAR_OF_CHAINS))
    legs = _load(copy.deepcopy(FIVE_BAR_OF_RR_LEGS))
    q = np.random.default_rng(6).uniform(-math.pi, math.pi, size=(100, 2))
    mine, theirs = chains.every_assembly(q), legs.every_assembly(q)
    np.testing.assert_array_equal(mine.counts, theirs.counts)
    assert mine.counts.sum() > 10
    np.testing.assert_allclose(np.nan_to_num(mine.poses, nan=9.0), np.nan_to_num(theirs.poses, nan=9.0), atol=1e-10)
    rp = copy.deepcopy(ALIAS)
    rp["name"] = "alias_rp_chains"
    rp["legs"] = {**{k: v for k, v in rp["legs"].items() if k != "kind"}, "kind": "chain",
                  "joints": [{"type": "R"}, {"type": "P", "axis": [1, 0], "actuated": True}],
                  "branches": {"single": [0.0, 5.0]}}
    a = _load(rp).every_assembly(np.sqrt([50.0, 26.0, 25.0]))
    np.testing.assert_allclose(_poses(a), [[3.369707132, 6.216516219, -0.8067834380], [5, 5, 0]], atol=1e-9)
