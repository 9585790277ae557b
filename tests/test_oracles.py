"""The hand-written oracles of tests/oracles.py (3-RRR, Delta, 6-UPS) checked three ways: each inverse
kinematics by its closure equations (1e-12), each Jacobian against central differences of its inverse
kinematics on every branch (1e-7), and both against robsynth's Maple-generated models, whose numbers
tests/data/robsynth_*.json keeps with the commit and the octave command that produced them (1e-10).

The robsynth fixtures hold inputs in robsynth's conventions (its world frame, leg frames, MDH joint
coordinates qJ, parameter vector pkin, platform points koppelP, pose xP) and what robsynth's code returns
for them: its inverse Jacobian Jinv and, from each leg's forward kinematics at qJ, the leg's end point in
its leg frame. Each fixture's "conventions" text states the map to pkm's conventions that the tests below
apply.
"""

from __future__ import annotations

import itertools
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from oracles import (
    delta_elbows,
    delta_ik,
    delta_jacobian,
    rrr3_elbows,
    rrr3_ik,
    rrr3_jacobian,
    rrr3_leg_angles,
    sgp_angular_rate_map,
    sgp_attachment_angles,
    sgp_ik,
    sgp_jacobian,
    sgp_rotation,
)

DATA = Path(__file__).parent / "data"

RRR3 = {"R_b": 0.5, "r_p": 0.15, "l1": 0.32, "l2": 0.28}
DELTA = {"R": 0.2, "r": 0.05, "L_a": 0.25, "L_b": 0.6}
SGP = {"R_b": 0.5, "r_p": 0.3, "theta_b": 0.35, "theta_p": 0.3}
BRANCHED = {  # machine: (ik, jacobian, design, workspace box low, high)
    "3-RRR": (rrr3_ik, rrr3_jacobian, RRR3, [-0.1, -0.1, -0.5], [0.1, 0.1, 0.5]),
    "Delta": (delta_ik, delta_jacobian, DELTA, [-0.15, -0.15, -0.7], [0.15, 0.15, -0.3]),
}

BRANCHES = [np.array(s) for s in itertools.product((1, -1), repeat=3)]
STEP = 1e-6  # central differences: truncation ~ STEP^2 q''', round-off ~ 1e-16 / STEP
CONDITION = 10.0  # largest |J| entry kept: near singularities the STEP^2 term outgrows 1e-7


def _poses(rng: np.random.Generator, low: list[float], high: list[float], count: int = 400) -> np.ndarray:
    return rng.uniform(low, high, size=(count, len(low)))


def _central_differences(ik: Callable[[np.ndarray], np.ndarray], poses: np.ndarray) -> np.ndarray:
    """(N, m, n) differences of ``ik`` along each pose coordinate; angle jumps of 2 pi are taken out."""
    columns = []
    for j in range(poses.shape[1]):
        step = np.zeros(poses.shape[1])
        step[j] = STEP
        change = ik(poses + step) - ik(poses - step)
        columns.append((change + np.pi) % (2 * np.pi) - np.pi)
    return np.stack(columns, axis=-1) / (2 * STEP)


def _kept(J: np.ndarray, *ik_values: np.ndarray) -> np.ndarray:
    """Poses where every leg closes and J is well conditioned."""
    finite = np.all([np.all(np.isfinite(q), axis=-1) for q in ik_values], axis=0)
    with np.errstate(invalid="ignore"):
        return finite & (np.nanmax(np.abs(J), axis=(1, 2)) < CONDITION)


def _rotation_xyz(phi: np.ndarray) -> np.ndarray:
    """robsynth's eulxyz2r: Rx(phi1) Ry(phi2) Rz(phi3)."""

    def axis(k: int, t: float) -> np.ndarray:
        return _rodrigues(np.eye(3)[k] * t)

    return axis(0, phi[0]) @ axis(1, phi[1]) @ axis(2, phi[2])


def _rodrigues(rotation_vector: np.ndarray) -> np.ndarray:
    """The rotation exp([w]x) by Rodrigues' formula: a route to R independent of the oracles' products."""
    angle = np.linalg.norm(rotation_vector)
    if angle == 0:
        return np.eye(3)
    k = rotation_vector / angle
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _wrapped(angle: np.ndarray) -> np.ndarray:
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi


def _fixture(name: str) -> dict:
    return json.loads((DATA / f"robsynth_{name}.json").read_text())


# --- Inverse kinematics by the closure equations -----------------------------------------------------------


def _reached(seed, machine, ik, design, branch):
    """Random poses of ``machine``'s box (seeded) that the branch reaches, with their joints; more than 100."""
    poses = _poses(np.random.default_rng(seed), *BRANCHED[machine][3:])
    joints = ik(poses, design, branch)
    reached = np.all(np.isfinite(joints), axis=1)
    assert reached.sum() > 100
    return poses[reached], joints[reached]


@pytest.mark.parametrize("signs", BRANCHES, ids=str)
def test_rrr3_ik_closes_each_leg_on_the_side_of_its_sign(signs: np.ndarray) -> None:
    poses, theta = _reached(1, "3-RRR", rrr3_ik, RRR3, signs)
    a = rrr3_leg_angles()
    base = RRR3["R_b"] * np.stack([np.cos(a), np.sin(a)], axis=-1)
    turn = poses[:, 2:3] + a
    platform = poses[:, None, :2] + RRR3["r_p"] * np.stack([np.cos(turn), np.sin(turn)], axis=-1)
    elbows = rrr3_elbows(poses, RRR3, theta)
    assert np.abs(np.linalg.norm(elbows - base, axis=-1) - RRR3["l1"]).max() < 1e-12
    assert np.abs(np.linalg.norm(platform - elbows, axis=-1) - RRR3["l2"]).max() < 1e-12
    d, e = platform - base, elbows - base
    assert np.all(np.sign(d[..., 0] * e[..., 1] - d[..., 1] * e[..., 0]) == signs)


@pytest.mark.parametrize("branch", BRANCHES, ids=str)
def test_delta_ik_closes_each_arm_and_branch_one_is_elbow_out(branch: np.ndarray) -> None:
    poses, theta = _reached(2, "Delta", delta_ik, DELTA, branch)
    psi = 2 * np.pi * np.arange(3) / 3
    radial = np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
    elbows = delta_elbows(poses, DELTA, theta)
    arm = elbows - DELTA["R"] * radial
    axis = np.stack([-np.sin(psi), np.cos(psi), np.zeros(3)], axis=-1)
    assert np.abs(np.linalg.norm(arm, axis=-1) - DELTA["L_a"]).max() < 1e-12
    assert np.abs(np.einsum("nij,ij->ni", arm, axis)).max() < 1e-12  # the arm turns about its axis
    platform = poses[:, None, :] + DELTA["r"] * radial
    assert np.abs(np.linalg.norm(platform - elbows, axis=-1) - DELTA["L_b"]).max() < 1e-12
    other = delta_ik(poses, DELTA, -branch)
    assert np.all((theta < other) == (branch > 0))
    knee_out = np.cos(np.where(branch > 0, theta, other)) > 0
    assert np.all(knee_out)


def test_sgp_ik_is_the_distance_between_the_documented_attachments() -> None:
    poses = _poses(np.random.default_rng(3), [-0.1, -0.1, 0.4, -0.4, -0.4, -0.4], [0.1, 0.1, 0.7, 0.4, 0.4, 0.4], 50)
    lengths = sgp_ik(poses, SGP)
    u, v = sgp_attachment_angles(SGP)
    for pose, length in zip(poses, lengths, strict=True):
        alpha, beta, gamma = pose[3:]
        R = (
            _rodrigues(np.array([0, 0, gamma]))
            @ _rodrigues(np.array([0, beta, 0]))
            @ _rodrigues(np.array([alpha, 0, 0]))
        )
        assert np.abs(sgp_rotation(pose[3:]) - R).max() < 1e-15
        for k in range(6):
            b = SGP["R_b"] * np.array([np.cos(u[k]), np.sin(u[k]), 0])
            p = SGP["r_p"] * np.array([np.cos(v[k]), np.sin(v[k]), 0])
            assert abs(np.linalg.norm(pose[:3] + R @ p - b) - length[k]) < 1e-12


def test_sgp_pairs_are_the_classic_six_six_arrangement() -> None:
    u, v = np.degrees(sgp_attachment_angles(SGP))
    half_b, half_p = np.degrees(SGP["theta_b"]) / 2, np.degrees(SGP["theta_p"]) / 2
    np.testing.assert_allclose(u, [-half_b, half_b, 120 - half_b, 120 + half_b, 240 - half_b, 240 + half_b])
    np.testing.assert_allclose(v, [-60 + half_p, 60 - half_p, 60 + half_p, 180 - half_p, 180 + half_p, 300 - half_p])
    platform_pairs = [(5, 0), (1, 2), (3, 4)]  # centred at 300, 60 and 180 deg
    for first, second in platform_pairs:
        assert first // 2 != second // 2  # their legs come from two different base pairs


def test_symmetric_poses_give_equal_legs() -> None:
    assert np.ptp(sgp_ik([0, 0, 0.6, 0, 0, 0], SGP)) < 1e-15
    assert np.ptp(delta_ik([0, 0, -0.5], DELTA, 1)) < 1e-15
    J = rrr3_jacobian([0, 0, 0], RRR3, 1)
    turn = _rodrigues(np.array([0, 0, 2 * np.pi / 3]))[:2, :2]
    np.testing.assert_allclose(J[1, :2], turn @ J[0, :2], atol=1e-14)
    np.testing.assert_allclose(J[:, 2], J[0, 2], atol=1e-14)


# --- Jacobians against central differences ------------------------------------------------------------------


@pytest.mark.parametrize("branch", BRANCHES, ids=str)
@pytest.mark.parametrize("machine", sorted(BRANCHED))
def test_jacobian_matches_central_differences_on_every_branch(machine: str, branch: np.ndarray) -> None:
    inverse_kinematics, jacobian, design, low, high = BRANCHED[machine]
    poses = _poses(np.random.default_rng(4), low, high)
    J = jacobian(poses, design, branch)

    def ik(x: np.ndarray) -> np.ndarray:
        return inverse_kinematics(x, design, branch)

    kept = _kept(J, ik(poses + STEP), ik(poses - STEP))
    assert kept.sum() > 50
    assert np.abs(J[kept] - _central_differences(ik, poses[kept])).max() < 1e-7


def test_sgp_jacobian_matches_central_differences() -> None:
    poses = _poses(np.random.default_rng(6), [-0.1, -0.1, 0.4, -0.6, -0.6, -0.6], [0.1, 0.1, 0.7, 0.6, 0.6, 0.6])
    J = sgp_jacobian(poses, SGP)
    assert np.abs(J - _central_differences(lambda x: sgp_ik(x, SGP), poses)).max() < 1e-7


def test_one_pose_gives_the_row_of_the_batch() -> None:
    rng = np.random.default_rng(7)
    cases = [
        (rrr3_ik, rrr3_jacobian, RRR3, (1, -1, 1), _poses(rng, [-0.05, -0.05, -0.2], [0.05, 0.05, 0.2], 4)),
        (delta_ik, delta_jacobian, DELTA, (1, 1, -1), _poses(rng, [-0.1, -0.1, -0.6], [0.1, 0.1, -0.4], 4)),
    ]
    for ik, jacobian, design, signs, poses in cases:
        for pose, q, J in zip(poses, ik(poses, design, signs), jacobian(poses, design, signs), strict=True):
            np.testing.assert_array_equal(ik(pose, design, signs), q)
            np.testing.assert_array_equal(jacobian(pose, design, signs), J)
    poses = _poses(rng, [-0.1, -0.1, 0.4, -0.3, -0.3, -0.3], [0.1, 0.1, 0.7, 0.3, 0.3, 0.3], 4)
    for pose, q, J in zip(poses, sgp_ik(poses, SGP), sgp_jacobian(poses, SGP), strict=True):
        np.testing.assert_array_equal(sgp_ik(pose, SGP), q)
        np.testing.assert_array_equal(sgp_jacobian(pose, SGP), J)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: rrr3_ik([0.0, 0.0], RRR3, 1), "pose must be"),
        (lambda: delta_ik([0.0, 0.0, -0.5], DELTA, 0), "branch signs"),
        (lambda: sgp_ik(np.zeros((2, 3, 6)), SGP), "pose must be"),
    ],
)
def test_bad_arguments_are_named(call: Callable[[], object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        call()


# --- robsynth -------------------------------------------------------------------------------------------


def _leg_ends_in_world(inputs: dict, leg_end: np.ndarray) -> np.ndarray:
    """robsynth's leg end points (leg frames) in its world frame: r_0_A + eulxyz2r(legFrame) leg_end."""
    frames = np.asarray(inputs["legFrame"])
    origins = np.asarray(inputs["r_0_A"])
    return np.array([o + _rotation_xyz(f) @ e for o, f, e in zip(origins, frames, leg_end, strict=True)])


def _platform_points(inputs: dict, rotation: np.ndarray) -> np.ndarray:
    """robsynth's platform coupling points relative to the platform's origin, R koppelP, in its world frame."""
    return np.asarray(inputs["koppelP"]) @ rotation.T


def test_rrr3_agrees_with_robsynth_p3rrr1() -> None:
    fixture = _fixture("rrr3")
    design = fixture["pkm_design"]
    beta = 2 * np.pi * np.arange(3) / 3
    circle = np.stack([np.cos(beta), np.sin(beta), np.zeros(3)], axis=-1)
    swap = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # d xP / d(x, y, phi)
    for case in fixture["cases"]:
        inputs, out = case["inputs"], case["robsynth"]
        assert inputs["pkin"] == [design["l1"], design["l2"], 0.0, 0.0, 0.0]
        np.testing.assert_allclose(inputs["r_0_A"], design["R_b"] * circle, atol=1e-15)
        np.testing.assert_allclose(inputs["koppelP"], design["r_p"] * circle, atol=1e-15)
        np.testing.assert_allclose(np.asarray(inputs["legFrame"])[:, 2], np.pi / 2 + beta, atol=1e-15)
        xP = np.asarray(inputs["xP"])
        pose = swap.T @ xP  # pkm's frame is robsynth's turned by +pi/2 about z
        np.testing.assert_allclose(pose, case["pkm"]["pose"], atol=1e-15)
        signs = case["pkm"]["signs"]

        qJ = np.asarray(inputs["qJ"])
        theta = rrr3_ik(pose, design, signs)
        assert np.abs(_wrapped(theta - np.pi / 2 - (np.pi / 2 + beta) - qJ[0])).max() < 1e-10
        phi = xP[2]
        turn = np.array([[np.cos(phi), -np.sin(phi), 0], [np.sin(phi), np.cos(phi), 0], [0, 0, 1]])
        platform = np.append(xP[:2], 0.0) + _platform_points(inputs, turn)
        assert np.abs(_leg_ends_in_world(inputs, np.asarray(out["leg_end"])) - platform).max() < 1e-10

        assert np.abs(rrr3_jacobian(pose, design, signs) - np.asarray(out["Jinv"]) @ swap).max() < 1e-10


def test_delta_agrees_with_robsynth_3_ruu_p3rrrrr2() -> None:
    fixture = _fixture("delta")
    design = fixture["pkm_design"]
    psi = 2 * np.pi * np.arange(3) / 3
    radial = np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
    for case in fixture["cases"]:
        inputs, out = case["inputs"], case["robsynth"]
        assert inputs["pkin"] == [design["L_a"], design["L_b"]]
        np.testing.assert_allclose(inputs["r_0_A"], design["R"] * radial, atol=1e-15)
        np.testing.assert_allclose(inputs["koppelP"], design["r"] * radial, atol=1e-15)
        frames = np.asarray(inputs["legFrame"])
        np.testing.assert_allclose(frames, np.stack([-np.pi / 2 + 0 * psi, -psi, -np.pi / 2 + 0 * psi], axis=-1))
        for frame, angle in zip(frames, psi, strict=True):  # its z axis is pkm's actuator axis
            np.testing.assert_allclose(_rotation_xyz(frame)[:, 2], [-np.sin(angle), np.cos(angle), 0], atol=1e-15)
        pose = np.asarray(inputs["xP"])
        np.testing.assert_allclose(pose, case["pkm"]["pose"], atol=0)
        branch = case["pkm"]["branch"]

        qJ = np.asarray(inputs["qJ"])
        assert np.abs(_wrapped(delta_ik(pose, design, branch) + np.pi / 2 - qJ[0])).max() < 1e-10
        platform = pose + _platform_points(inputs, np.eye(3))
        assert np.abs(_leg_ends_in_world(inputs, np.asarray(out["leg_end"])) - platform).max() < 1e-10

        assert np.abs(delta_jacobian(pose, design, branch) - np.asarray(out["Jinv"])).max() < 1e-10


def test_sgp_agrees_with_robsynth_6_ups_p6rrprrr14v3() -> None:
    fixture = _fixture("sgp")
    design = fixture["pkm_design"]
    u, v = sgp_attachment_angles(design)
    pair = 2 * np.pi * (np.arange(6) // 2) / 3
    for case in fixture["cases"]:
        inputs, out = case["inputs"], case["robsynth"]
        np.testing.assert_allclose(
            inputs["r_0_A"], design["R_b"] * np.stack([np.cos(u), np.sin(u), 0 * u], -1), atol=1e-15
        )
        np.testing.assert_allclose(
            inputs["koppelP"], design["r_p"] * np.stack([np.cos(v), np.sin(v), 0 * v], -1), atol=1e-15
        )
        np.testing.assert_allclose(np.asarray(inputs["legFrame"])[:, 2], np.pi / 2 + pair, atol=1e-15)
        xP = np.asarray(inputs["xP"])
        R = _rotation_xyz(xP[3:])
        angles = np.array([np.arctan2(R[2, 1], R[2, 2]), -np.arcsin(R[2, 0]), np.arctan2(R[1, 0], R[0, 0])])
        pose = np.concatenate([xP[:3], angles])
        np.testing.assert_allclose(pose, case["pkm"]["pose"], atol=1e-14)

        assert np.abs(sgp_ik(pose, design) - np.asarray(inputs["qJ"])[2]).max() < 1e-10
        platform = xP[:3] + _platform_points(inputs, R)
        assert np.abs(_leg_ends_in_world(inputs, np.asarray(out["leg_end"])) - platform).max() < 1e-10

        twist_from_rates = np.eye(6)  # robsynth's Jinv takes (v, omega), pkm's J the angles' rates
        twist_from_rates[3:, 3:] = sgp_angular_rate_map(angles)
        assert np.abs(sgp_jacobian(pose, design) - np.asarray(out["Jinv"]) @ twist_from_rates).max() < 1e-10
