"""The Cartesian stiffness of described machines with elastic elements (issue 40), derived twice: pkm's virtual
joint method against a planar frame model by the stiffness method written here (Euler-Bernoulli frame elements,
pins as released rotations, drives as rotational springs to ground, the platform rigid), on the five-bar of RR
legs and the 3-RRR; the drives alone against Gosselin's K = J^T diag(k) J; the 3-RPR of the ALIAS-C++
documentation with unit axial drives, whose K has rational entries."""

from __future__ import annotations

import copy
import math
import re
import tomllib
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from helpers import FIVE_BAR_ELASTIC, FIVE_BAR_OF_CHAINS, FIVE_BAR_OF_RR_LEGS

import pkm
from pkm.errors import PkmError, SingularityWarning
from pkm.models.described import DESCRIPTIONS
from pkm.spec.schema import DescriptionError

STEEL = (210e9, 81e9)
TUBE = (0.02, 0.002)  # outer diameter, wall [m]
DRIVE = 1e4  # [N m/rad]
ELASTIC = {"material": "steel", "section": {"shape": "tube", "d": str(TUBE[0]), "t": str(TUBE[1])},
           "drive": str(DRIVE)}


# the 3-RPR of the ALIAS-C++ documentation at scale s, its drives of unit axial stiffness
ALIAS = {"name": "alias_elastic", "doc": "ALIAS's 3-RPR with unit drives", "frame": "planar", "home": [5, 5, 0],
         "parameters": [{"name": "s", "default": 1.0, "lower": 0.1, "upper": 10, "unit": "m", "doc": "scale"}],
         "legs": {"kind": "RPR", "count": 3, "base": [["0", "0"], ["10 * s", "0"], ["3 * s", "10 * s"]],
                  "platform": [["0", "0"], ["4 * s", "0"], ["2 * s", "2 * s"]], "elastic": {**ELASTIC, "drive": "1"}}}


def _load(raw: dict) -> pkm.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        return pkm.load(raw)


def _elastic(raw: dict, name: str) -> dict:
    raw = copy.deepcopy(raw)
    raw["name"] = name
    raw["legs"]["elastic"] = ELASTIC
    return raw


def _tube() -> tuple[float, float]:
    d, t = TUBE
    inner = d - 2 * t
    return math.pi * (d**2 - inner**2) / 4, math.pi * (d**4 - inner**4) / 64


def _element(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """The 6 x 6 stiffness of a planar Euler-Bernoulli frame element in the base frame, its degrees of freedom
    (u, v, theta) at its start, then at its end."""
    area, moment = _tube()
    young = STEEL[0]
    length = float(np.linalg.norm(end - start))
    c, s = (end - start) / length
    a, b = young * area / length, young * moment / length**3
    local = np.array([
        [a, 0, 0, -a, 0, 0],
        [0, 12 * b, 6 * b * length, 0, -12 * b, 6 * b * length],
        [0, 6 * b * length, 4 * b * length**2, 0, -6 * b * length, 2 * b * length**2],
        [-a, 0, 0, a, 0, 0],
        [0, -12 * b, -6 * b * length, 0, 12 * b, -6 * b * length],
        [0, 6 * b * length, 2 * b * length**2, 0, -6 * b * length, 4 * b * length**2]])
    turn = np.zeros((6, 6))
    for k in (0, 3):
        turn[k:k + 2, k:k + 2] = [[c, s], [-s, c]]
        turn[k + 2, k + 2] = 1
    return turn.T @ local @ turn


def frame_stiffness(legs: list[np.ndarray], pose: np.ndarray, *, turning: bool, elbow: float = 0.0,
                    bearing: float | None = None) -> np.ndarray:
    """The stiffness at the platform of RR legs (each its base joint, elbow and platform joint) as a planar frame:
    each link an element, the proximal clamped to its drive's rotation (a spring DRIVE to ground), pins at the
    elbow (with ``elbow`` a rotational spring between its two element ends) and at the platform joint (each
    element end its own rotation), the platform joints moving with the platform's twist (dP, dphi) (``turning``)
    or one point dP; with ``bearing`` each pin's two element ends (or its end and the ground or the platform) have
    translations of their own, tied by translational springs of that stiffness; the internal degrees of freedom
    condensed."""
    masters = 3 if turning else 2
    # per leg: the element ends' translations (base, elbow twice, platform: 8), the drive's rotation and three
    # element-end rotations
    per_leg = 12
    n = masters + per_leg * len(legs)
    K = np.zeros((n, n))
    for k, (base, knee, end) in enumerate(legs):
        first = masters + per_leg * k
        at_base, at_knee, from_knee, at_end = (first + 2 * j for j in range(4))
        drive, ends = first + 8, first + 9
        to_end = np.zeros((2, n))
        to_end[:, :2] = np.eye(2)
        if turning:
            r = end - pose[:2]
            to_end[:, 2] = [-r[1], r[0]]
        base_end, knee_end, end_end = np.eye(2, n, at_base), np.eye(2, n, at_knee), np.eye(2, n, at_end)
        knee_start = np.eye(2, n, from_knee)
        if bearing is None:  # the pins rigid: one translation per pin, none at the base
            base_end, knee_start, end_end = np.zeros((2, n)), knee_end, to_end
        for one, other in ((base_end, 0), (knee_end, knee_start), (end_end, to_end)):
            gap = one - other
            K += (0 if bearing is None else bearing) * gap.T @ gap
        proximal = np.zeros((6, n))
        proximal[0:2] = base_end
        proximal[2, drive] = 1
        proximal[3:5] = knee_end
        proximal[5, ends] = 1
        distal = np.zeros((6, n))
        distal[0:2] = knee_start
        distal[2, ends + 1] = 1
        distal[3:5] = end_end
        distal[5, ends + 2] = 1
        K += proximal.T @ _element(base, knee) @ proximal + distal.T @ _element(knee, end) @ distal
        K[drive, drive] += DRIVE
        K[np.ix_([ends, ends + 1], [ends, ends + 1])] += elbow * np.array([[1, -1], [-1, 1]])
    inner = np.arange(masters, n)
    free = inner[np.abs(np.diag(K)[inner]) > 0]
    m = np.arange(masters)
    return K[np.ix_(m, m)] - K[np.ix_(m, free)] @ np.linalg.solve(K[np.ix_(free, free)], K[np.ix_(free, m)])


@pytest.fixture(scope="module")
def five_bar():
    return _load(FIVE_BAR_ELASTIC)


@pytest.fixture(scope="module")
def rrr3():
    return _load(_elastic(tomllib.loads(DESCRIPTIONS["rrr3"].read_text()), "rrr3_elastic"))


@pytest.mark.parametrize("machine", ["five_bar", "rrr3"])
def test_the_virtual_joint_method_is_the_frame_model(machine, request):
    """At poses across the workspace, every mode: pkm's K equals the frame model's to 1e-9 (relative to its
    largest entry), and the drives' alone is J^T diag(k) J; the links' bending makes the machine softer."""
    m = request.getfixturevalue(machine)
    rng = np.random.default_rng(5)
    home = np.asarray(m.functions["home"](m.design_vector(None))).ravel()
    poses = home + rng.uniform(-0.15, 0.15, (40, m.n_out)) * (1 if machine == "five_bar" else [1, 1, 1.5])
    checked = 0
    for mode in m.modes:
        K = m.stiffness(poses, mode=mode)
        reached = np.all(np.isfinite(K), axis=(1, 2))
        J = m.jacobian(poses[reached], mode=mode)
        drives = m.stiffness(poses[reached], mode=mode, actuators_only=True)
        for pose, K_k, J_k, drives_k in zip(poses[reached], K[reached], J, drives, strict=True):
            want = frame_stiffness(m.linkage(pose, mode=mode), pose, turning=m.n_out == 3)
            np.testing.assert_allclose(K_k, want, rtol=0, atol=1e-9 * np.abs(want).max())
            np.testing.assert_allclose(drives_k, DRIVE * J_k.T @ J_k, rtol=0, atol=1e-9 * np.abs(drives_k).max())
            assert np.linalg.eigvalsh(drives_k - K_k).min() > -1e-9 * np.abs(drives_k).max()
            checked += 1
    assert checked >= 40


FLEXURE = 500.0  # [N m/rad] an elbow's rotational spring


@pytest.mark.parametrize("legs", ["RR", "chain"])
def test_a_passive_joints_spring_is_the_frame_models_spring_at_the_elbow(legs):
    """The five-bar with a rotational spring at each elbow (elastic.passive), of RR legs (whose distal angle is
    measured from the base's frame) and of chain legs (joint by joint): K equals the frame model's with the spring
    between the elbow's two element ends, to 1e-9, at poses across the workspace in both assembly modes; the
    springs stiffen it."""
    def described(elastic: dict, name: str) -> dict:
        if legs == "RR":
            return {**FIVE_BAR_ELASTIC, "name": name, "legs": {**FIVE_BAR_ELASTIC["legs"], "elastic": elastic}}
        return {**FIVE_BAR_OF_CHAINS, "name": name,
                "legs": [{**leg, "elastic": elastic} for leg in FIVE_BAR_OF_CHAINS["legs"]]}

    m = _load(described({**ELASTIC, "passive": [str(FLEXURE)]}, f"five_bar_{legs}_flexures"))
    free = _load(FIVE_BAR_ELASTIC if legs == "RR" else described(ELASTIC, "five_bar_chains_elastic"))
    _assert_the_frame_model(m, free, {"elbow": FLEXURE}, stiffer=True)


def _assert_the_frame_model(m: pkm.Mechanism, other: pkm.Mechanism, frame: dict, *, stiffer: bool) -> None:
    """m's K equals the five-bar's frame model with ``frame``'s springs to 1e-9 at 15 poses about the home pose in
    each mode (at least 20 of them in reach), and is stiffer (or softer) than the ``other`` machine's there."""
    rng = np.random.default_rng(8)
    home = np.asarray(m.functions["home"](m.design_vector(None))).ravel()
    checked = 0
    for mode in m.modes:
        poses = home + rng.uniform(-0.15, 0.15, (15, 2))
        K = m.stiffness(poses, mode=mode)
        in_reach = np.all(np.isfinite(K), axis=(1, 2))
        for pose, K_k, other_k in zip(poses[in_reach], K[in_reach], other.stiffness(poses[in_reach], mode=mode),
                                      strict=True):
            want = frame_stiffness(m.linkage(pose, mode=mode), pose, turning=False, **frame)
            np.testing.assert_allclose(K_k, want, rtol=0, atol=1e-9 * np.abs(want).max())
            gap = K_k - other_k
            assert np.linalg.eigvalsh(gap if stiffer else -gap).min() > 0
            checked += 1
    assert checked >= 20


BEARING = 2e6  # [N/m] each pin's bearing


def test_the_bearings_are_the_frame_models_translational_springs_at_each_pin():
    """The five-bar of RR legs with a bearing at each of its three pins (elastic.bearings): K equals the frame
    model's with the element ends at each pin tied by translational springs, to 1e-9, in both modes; softer than
    rigid bearings. A list of the wrong length is refused by name."""
    m = _load({**FIVE_BAR_ELASTIC, "name": "five_bar_bearings",
               "legs": {**FIVE_BAR_ELASTIC["legs"], "elastic": {**ELASTIC, "bearings": [str(BEARING)] * 3}}})
    _assert_the_frame_model(m, _load(FIVE_BAR_ELASTIC), {"bearing": BEARING}, stiffer=False)
    raw = copy.deepcopy(FIVE_BAR_ELASTIC)
    raw["legs"]["elastic"] = {**ELASTIC, "bearings": ["1e6"] * 2}
    with pytest.raises(DescriptionError, match=re.escape("legs.elastic.bearings violates: a list of 3 expressions")):
        pkm.load(raw)
    raw["legs"]["elastic"]["bearings"] = ["1e6", "0", "1e6"]
    with pytest.raises(DescriptionError, match=re.escape("elastic.bearings[1] violates: a positive value")):
        pkm.load(raw)


HAND_DERIVED = {  # a design away from the defaults, the drives, the region, the parameters of the gradient
    "five_bar": ({"r1": 1.1, "r3": 0.7, "k1": 9e3, "k2": 1.4e4, "w_l": 0.03, "t_l": 0.0025}, ("k1", "k2"), "miw",
                 ("w_l", "r2", "k1")),
    "slider_gantry": ({"l": 0.6, "d2": 0.12, "b_l": 0.15, "t_l": 0.01, "k_s": 5e7}, ("k_s", "k_s"), "task",
                      ("b_l", "l", "k_s")),
    "slider_gantry_symmetric": ({"l": 0.6, "b_l": 0.15, "t_l": 0.012, "k_s": 8e7}, ("k_s", "k_s"), "task",
                                ("t_l", "d1", "k_s")),
}


@pytest.mark.parametrize("name", sorted(HAND_DERIVED))
def test_a_hand_derived_machines_stiffness_is_its_legs_described(name):
    """The hand-derived five-bar's elastic elements (its links the aluminium square tube w_l x t_l, its drives the
    transmissions k1, k2) and the slider gantry's (its links the steel square tube b_l x t_l, the parallelogram's
    two side by side, its sliders' drives k_s) derived twice: K equals the machine of their legs described
    (pkm.models.<name>.legs) at a design away from the defaults, to 1e-12, in every working mode; the drives
    alone are J^T diag(k) J with the machine's own J; the elastic frequency is sqrt(lambda_min(K, M_w)) with its
    own dynamic model's M_w; the region mean of the least stiffness has the design gradient of its central
    differences in the tube, a length and a drive."""
    from scipy.linalg import eigh

    m = pkm.load(name)
    changes, drives, region, varied = HAND_DERIVED[name]
    design = {**m.design(None), **changes}
    twice = _load(m.legs_description())
    poses, _ = m.region(region).sample(m.functions, m.design_vector(design), 12, "mean")
    poses = poses[np.random.default_rng(3).choice(len(poses), 12, replace=False)]
    for mode in m.modes:
        K = m.stiffness(poses, design, mode=mode)
        reached = np.all(np.isfinite(K), axis=(1, 2))
        if mode == m.modes[0]:
            assert reached.sum() >= 6
        if not reached.any():
            continue
        want = twice.stiffness(poses[reached], twice.design({k: design[k] for k in twice.parameter_names()}),
                               mode=mode)
        np.testing.assert_allclose(K[reached], want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
        J = m.jacobian(poses[reached], design, mode=mode)
        alone = np.einsum("nki,k,nkj->nij", J, [design[k] for k in drives], J)
        np.testing.assert_allclose(m.stiffness(poses[reached], design, mode=mode, actuators_only=True), alone,
                                   rtol=1e-10)
    K, M = m.stiffness(poses, design), m.inertia_matrix(poses, design)
    frequency = m.local_index("elastic_frequency", poses, design)
    for k in np.flatnonzero(np.all(np.isfinite(K), axis=(1, 2))):
        assert frequency[k] == pytest.approx(np.sqrt(eigh(K[k], M[k], eigvals_only=True).min()), rel=1e-9)
    value, gradient = m.global_index("stiffness_min_mean", design, region=region, resolution=3, gradient=True)
    assert value > 0
    for parameter in varied:
        step = 1e-6 * design[parameter]
        ahead, behind = (m.global_index("stiffness_min_mean", {**design, parameter: design[parameter] + sign * step},
                                        region=region, resolution=3) for sign in (1, -1))
        assert gradient[parameter] == pytest.approx((ahead - behind) / (2 * step), rel=1e-5)


def test_a_passive_joints_list_has_one_entry_per_passive_joint():
    raw = copy.deepcopy(FIVE_BAR_ELASTIC)
    raw["legs"]["elastic"] = {**ELASTIC, "passive": ["1", "2"]}
    with pytest.raises(DescriptionError, match=re.escape("legs.elastic.passive violates: a list of 1 expressions")):
        pkm.load(raw)
    raw["legs"]["elastic"]["passive"] = ["-5"]
    with pytest.raises(DescriptionError, match=re.escape("a positive value at the default design, or 0 (free)")):
        pkm.load(raw)


def test_the_alias_3rpr_with_unit_drives_has_its_rational_stiffness():
    """Base joints (0,0), (10,0), (3,10), platform points (0,0), (4,0), (2,2), pose (5, 5, 0), unit axial drive
    stiffness: K = sum_i a_i a_i^T / rho_i^2, a_i = (d_i, r_i x d_i), exactly, against pkm to 1e-12."""
    m = _load(ALIAS)
    want = [[Fraction(0)] * 3 for _ in range(3)]
    for base, point in zip([(0, 0), (10, 0), (3, 10)], [(0, 0), (4, 0), (2, 2)], strict=True):
        d = (5 + point[0] - base[0], 5 + point[1] - base[1])
        a = (d[0], d[1], point[0] * d[1] - point[1] * d[0])
        for i in range(3):
            for j in range(3):
                want[i][j] += Fraction(a[i] * a[j], d[0] ** 2 + d[1] ** 2)
    assert want[0][0] == Fraction(383, 325)
    K = m.stiffness([5, 5, 0])
    np.testing.assert_allclose(K, np.array(want, dtype=float), rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.stiffness([5, 5, 0], actuators_only=True), K, rtol=0, atol=1e-12)


def test_the_deflection_under_a_load_is_the_compliance_times_it(rrr3):
    pose = np.array([0.05, -0.03, 0.1])
    wrench = np.array([0.0, -10.0, 0.5])
    K = rrr3.stiffness(pose)
    np.testing.assert_allclose(K @ rrr3.deflection(pose, wrench), wrench, rtol=1e-10, atol=1e-12)
    two = rrr3.deflection(np.stack([pose, pose]), wrench)
    assert two.shape == (2, 3)


def test_without_elastic_elements_there_is_no_stiffness_and_bad_elements_are_refused():
    with pytest.raises(PkmError, match="no elastic elements"):
        pkm.load("rrr3").stiffness([0, 0, 0])
    raw = _elastic(FIVE_BAR_OF_RR_LEGS, "five_bar_bad")
    raw["legs"]["elastic"] = {**ELASTIC, "material": "cheese"}
    with pytest.raises(DescriptionError, match=r"legs.elastic.material violates: one of steel"):
        pkm.load(raw)
    raw["legs"]["elastic"] = {**ELASTIC, "section": {"shape": "tube", "d": "0.02"}}
    with pytest.raises(DescriptionError, match=r"legs.elastic.section violates: a tube section's shape and"):
        pkm.load(raw)


def test_the_blocks_scale_as_their_units_n_per_m_n_per_rad_and_n_m_per_rad():
    """The ALIAS 3-RPR with unit axial drives at twice its size: its translational block (N/m) is the same, its
    coupling (N/rad) twice, its rotational block (N m/rad) four times."""
    m = _load(ALIAS)
    assert m.stiffness_units() == [["N/m", "N/m", "N/rad"], ["N/m", "N/m", "N/rad"], ["N/rad", "N/rad", "N m/rad"]]
    K, twice = m.stiffness([5, 5, 0]), m.stiffness([10, 10, 0], {"s": 2.0})
    scale = np.array([[1, 1, 2], [1, 1, 2], [2, 2, 4]])
    np.testing.assert_allclose(twice, K * scale, rtol=1e-12, atol=1e-12)


@pytest.fixture(scope="module")
def delta():
    return pkm.load(str(Path(__file__).resolve().parents[1] / "examples" / "delta_elastic.toml"))


def test_the_deltas_stiffness_is_symmetric_positive_definite_and_its_frequency_the_generalised_eigenvalue(delta):
    """Inside the task: K symmetric positive definite, softer than its drives alone (J^T k_m J), the least
    translational stiffness its smallest eigenvalue and the elastic frequency sqrt(lambda_min(K, M_w))."""
    from scipy.linalg import eigh

    rng = np.random.default_rng(2)
    radius, angle = 0.15 * np.sqrt(rng.uniform(size=30)), rng.uniform(0, 2 * np.pi, 30)
    poses = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.55, -0.45, 30)])
    K, drives = delta.stiffness(poses), delta.stiffness(poses, actuators_only=True)
    J, M = delta.jacobian(poses), delta.inertia_matrix(poses)
    k_m = delta.design(None)["k_m"]
    least = delta.local_index("stiffness_min", poses)
    frequency = delta.local_index("elastic_frequency", poses)
    for k in range(len(poses)):
        np.testing.assert_allclose(K[k], K[k].T, rtol=0, atol=1e-9 * np.abs(K[k]).max())
        eigenvalues = np.linalg.eigvalsh(K[k])
        assert eigenvalues.min() > 0
        assert least[k] == pytest.approx(eigenvalues.min(), rel=1e-10)
        np.testing.assert_allclose(drives[k], k_m * J[k].T @ J[k], rtol=1e-10)
        assert np.linalg.eigvalsh(drives[k] - K[k]).min() > 0
        assert frequency[k] == pytest.approx(np.sqrt(eigh(K[k], M[k], eigvals_only=True).min()), rel=1e-10)


def test_the_stiffness_index_has_the_design_gradient_of_its_finite_differences(delta):
    """The task mean of the least translational stiffness at a fixed quadrature: its exact gradient in the arm
    length, the arm tube's diameter and the drive stiffness equals central differences."""
    d = delta.design(None)
    value, gradient = delta.global_index("stiffness_min_mean", d, region="task", mode="elbow_out", resolution=4,
                                         gradient=True)
    for name in ("L_a", "d_a", "k_m"):
        step = 1e-6 * d[name]
        ahead = delta.global_index("stiffness_min_mean", {**d, name: d[name] + step}, region="task",
                                   mode="elbow_out", resolution=4)
        behind = delta.global_index("stiffness_min_mean", {**d, name: d[name] - step}, region="task",
                                    mode="elbow_out", resolution=4)
        assert gradient[name] == pytest.approx((ahead - behind) / (2 * step), rel=1e-5)
    assert value > 0


def _stewart_on_springs() -> pkm.Mechanism:
    """The shipped Stewart-Gough platform with a 20 kg platform on steel legs of diameter d and drives of axial
    stiffness k."""
    raw = tomllib.loads(DESCRIPTIONS["stewart"].read_text())
    raw["name"] = "stewart_on_springs"
    raw["parameters"] += [{"name": "d", "default": 0.03, "lower": 0.005, "upper": 0.1, "unit": "m", "doc": "legs"},
                          {"name": "k", "default": 2e7, "lower": 1e5, "upper": 1e9, "unit": "N/m", "doc": "drives"}]
    raw["platform"] = {"mass": "20", "centre": ["0", "0", "0.05"], "inertia": ["1.2", "1.4", "2.0"]}
    raw["legs"]["bodies"] = {"cylinder": {"mass": "2", "centre": "0.3", "inertia": "0.05"},
                             "piston": {"mass": "1", "centre": "0.3", "inertia": "0.03"}}
    raw["legs"]["elastic"] = {"material": "steel", "section": {"shape": "round", "d": "d"}, "drive": "k"}
    return _load(raw)


def _rotation(angles: np.ndarray) -> np.ndarray:
    roll, pitch, yaw = angles
    c, s = np.cos, np.sin
    Rx = np.array([[1, 0, 0], [0, c(roll), -s(roll)], [0, s(roll), c(roll)]])
    Ry = np.array([[c(pitch), 0, s(pitch)], [0, 1, 0], [-s(pitch), 0, c(pitch)]])
    Rz = np.array([[c(yaw), -s(yaw), 0], [s(yaw), c(yaw), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def test_a_spatial_platforms_lowest_frequency_is_the_generalised_eigenvalue_of_its_six_coordinates():
    """A 6-UPS on elastic legs: the elastic frequency is sqrt(lambda_min(E^T K E, M_w)) in the pose's six
    coordinates, E the twist's rates of the angles' (here by central differences of the rotation matrix:
    [omega]x = R_dot R^T), and the global minimum over the task has the design gradient of its central
    differences in the legs' diameter and the drives' stiffness."""
    from scipy.linalg import eigh

    m = _stewart_on_springs()
    rng = np.random.default_rng(5)
    poses = np.array([0, 0, 1.0, 0, 0, 0]) + rng.uniform(-1, 1, (12, 6)) * [0.05, 0.05, 0.03, 0.15, 0.15, 0.15]
    K, M = m.stiffness(poses), m.inertia_matrix(poses)
    frequency = m.local_index("elastic_frequency", poses)
    for k, x in enumerate(poses):
        E = np.eye(6)
        R = _rotation(x[3:])
        for j in range(3):
            step = np.zeros(3)
            step[j] = 1e-6
            W = (_rotation(x[3:] + step) - _rotation(x[3:] - step)) / 2e-6 @ R.T
            E[3:, 3 + j] = [W[2, 1], W[0, 2], W[1, 0]]
        assert frequency[k] == pytest.approx(np.sqrt(eigh(E.T @ K[k] @ E, M[k], eigvals_only=True).min()),
                                             rel=1e-8)
    d = m.design(None)
    value, gradient = m.global_index("elastic_frequency_min", d, region="task", resolution=2, gradient=True)
    assert value > 0
    for name in ("d", "k"):
        step = 1e-6 * d[name]
        ahead, behind = (m.global_index("elastic_frequency_min", {**d, name: d[name] + sign * step}, region="task",
                                        resolution=2) for sign in (1, -1))
        assert gradient[name] == pytest.approx((ahead - behind) / (2 * step), rel=1e-5)


def test_a_deflection_constraint_binds_exactly_where_active():
    """docs/tasks/delta_stiff.toml: the GCI maximised with the platform moving at most 50 um under 10 N
    downwards over the task; at the optimum the constraint is active, held to its bound, and the deflection at
    sampled task poses stays within it."""
    from pkm.synthesis.designer import read_problem

    problem = read_problem(Path(__file__).resolve().parents[1] / "docs" / "tasks" / "delta_stiff.toml")
    result = pkm.synthesize(problem, progress=False, starts=2)
    assert result.optimum.feasible
    row = next(c for c in result.optimum.constraints if c.name.startswith("deflection"))
    assert row.active
    assert row.value == pytest.approx(50e-6, rel=1e-7)
    m = problem.mechanism
    rng = np.random.default_rng(4)
    radius, angle = 0.15 * np.sqrt(rng.uniform(size=200)), rng.uniform(0, 2 * np.pi, 200)
    poses = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.55, -0.45, 200)])
    moved = m.deflection(poses, [0, 0, -10], result.design, mode="elbow_out")
    assert np.linalg.norm(moved, axis=1).max() <= 50e-6 * (1 + 1e-7)
