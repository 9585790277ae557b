"""The generic core on mechanisms that exist only here: a spatial 3-DOF tripod (3 x 3 Jacobians, a pose
mixing metres and radians, numerical forward kinematics, box and cylinder regions) and the five-bar
with forward kinematics through polynomial roots and a region between curves (a MappedSquare).

The tripod: base joints B_i on a circle of radius R at 90, 210 and 330 deg, platform joints P_i on a
circle of radius r, pose (z, alpha, beta) with the platform at (0, 0, z) turned by Rx(alpha) Ry(beta),
actuated leg lengths q_i = |z e_z + Rot P_i - B_i|. The loop residual h = q - |...| has no passive
joints, so J = dq/dx and J_f = J^-1.
"""

from __future__ import annotations

import itertools
import math
from functools import cached_property
from typing import ClassVar

import casadi as ca
import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.design import Parameter
from pkm.errors import PkmError
from pkm.indices import GlobalIndex
from pkm.indices.local import extreme_singular_values, jacobi_eigenvalues, symmetric_eigenvalues
from pkm.kinematics import Branch, FunctionTable, PolynomialRoots, Rootfinder
from pkm.mechanism import Mechanism
from pkm.models.five_bar import FiveBar
from pkm.regions import Box, Cylinder, Disc, MappedSquare, quadrature_function, sampled_check

ANGLES = (math.pi / 2, math.pi / 2 + 2 * math.pi / 3, math.pi / 2 + 4 * math.pi / 3)
STEP = 1e-6


def _rotation(alpha, beta):
    ca_, sa, cb, sb = ca.cos(alpha), ca.sin(alpha), ca.cos(beta), ca.sin(beta)
    rx = ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, ca_, -sa), ca.horzcat(0, sa, ca_))
    ry = ca.vertcat(ca.horzcat(cb, 0, sb), ca.horzcat(0, 1, 0), ca.horzcat(-sb, 0, cb))
    return rx @ ry


def _legs(x, design):
    R, r = design[0], design[1]
    rot = _rotation(x[1], x[2])
    out = []
    for a in ANGLES:
        base = ca.vertcat(R * math.cos(a), R * math.sin(a), 0)
        joint = ca.vertcat(0, 0, x[0]) + rot @ ca.vertcat(r * math.cos(a), r * math.sin(a), 0)
        out.append(ca.norm_2(joint - base))
    return ca.vertcat(*out)


def tripod_functions() -> dict[str, ca.Function]:
    x, q, d = ca.SX.sym("x", 3), ca.SX.sym("q", 3), ca.SX.sym("design", 3)
    mode, assembly = ca.SX.sym("mode", 1), ca.SX.sym("assembly", 1)
    legs = _legs(x, d)
    h = q - legs
    H_q, H_x = ca.jacobian(h, q), ca.jacobian(h, x)
    J = -ca.solve(H_q, H_x)
    J_f = ca.inv(J)
    height = d[2]
    seed_height = assembly * ca.sqrt(ca.fmax(ca.sumsqr(q) / 3 - (d[0] - d[1]) ** 2, 0))
    centre = ca.vertcat(height, 0, 0)
    return {
        "inverse_kinematics": ca.Function(
            "inverse_kinematics", [x, mode, d], [legs, mode * x[0] - 0.05], ["x", "mode", "design"], ["q", "reach"]
        ),
        "constraint": ca.Function("constraint", [q, x, d], [h, H_q, H_x], ["q", "x", "design"], ["h", "H_q", "H_x"]),
        "first_order": ca.Function(
            "first_order",
            [q, x, d],
            [J, J_f, ca.SX.eye(3), ca.det(H_q), ca.det(H_x)],
            ["q", "x", "design"],
            ["J", "J_f", "psi", "det_type1", "det_type2"],
        ),
        "forward_seed": ca.Function(
            "forward_seed", [q, assembly, d], [ca.vertcat(seed_height, 0, 0)], ["q_a", "assembly", "design"], ["z0"]
        ),
        "box_region": ca.Function(
            "box_region", [d], [centre, ca.vertcat(0.1 * height, 0.2, 0.15)], ["design"], ["centre", "size"]
        ),
        "cylinder_region": ca.Function(
            "cylinder_region", [d], [centre, ca.vertcat(0.2 * d[1] / 0.3, 0.1 * height)], ["design"], ["centre", "size"]
        ),
    }


class Tripod(Mechanism):
    name = "test_tripod"
    doc = "spatial 3-DOF tripod of the tests: pose (z, alpha, beta), three actuated legs"
    parameters = (
        Parameter("R", 0.5, 0.0, math.inf, "m", "base radius"),
        Parameter("r", 0.3, 0.0, math.inf, "m", "platform radius"),
        Parameter("h", 1.0, 0.0, math.inf, "m", "height of the regions' centre"),
    )
    working_modes = (Branch("legs", (1.0,), "platform above the base"),)
    assembly_modes = (Branch("above", (1.0,), "platform above the base"), Branch("below", (-1.0,), "mirror"))
    pose_names = ("z", "alpha", "beta")
    pose_units = ("m", "rad", "rad")
    actuator_names = ("q1", "q2", "q3")
    actuator_units = ("m", "m", "m")
    forward = Rootfinder()
    characteristic_length = staticmethod(lambda d: d["r"])
    regions: ClassVar[dict] = {
        "box": Box("box", "a box about (h, 0, 0)", function="box_region"),
        "cylinder": Cylinder("cylinder", "a cylinder along z about (h, 0, 0)", function="cylinder_region", axis=0),
    }

    @cached_property
    def functions(self) -> FunctionTable:
        return FunctionTable(tripod_functions(), "the test tripod")

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        h = design[2]
        return np.array([[h - 0.2, h + 0.2], [-0.35, 0.35], [-0.35, 0.35]])


class Unscaled(Tripod):
    characteristic_length = None


@pytest.fixture(scope="module")
def tripod() -> Tripod:
    return Tripod()


@pytest.fixture(scope="module")
def poses() -> np.ndarray:
    rng = np.random.default_rng(3)
    return np.column_stack([rng.uniform(0.85, 1.15, 20), rng.uniform(-0.3, 0.3, 20), rng.uniform(-0.3, 0.3, 20)])


def test_jacobian_is_the_derivative_of_the_inverse_kinematics(tripod, poses):
    J = tripod.jacobian(poses)
    assert J.shape == (20, 3, 3)
    for k in range(3):
        step = np.zeros(3)
        step[k] = STEP
        fd = (tripod.inverse_kinematics(poses + step) - tripod.inverse_kinematics(poses - step)) / (2 * STEP)
        np.testing.assert_allclose(J[:, :, k], fd, atol=1e-8)
    np.testing.assert_allclose(tripod.forward_jacobian(poses) @ J, np.broadcast_to(np.eye(3), J.shape), atol=1e-10)


def test_numerical_forward_kinematics_inverts_the_inverse_kinematics(tripod, poses):
    q = tripod.inverse_kinematics(poses)
    np.testing.assert_allclose(tripod.forward_kinematics(q, assembly="above"), poses, atol=1e-10)
    # the mirror image through the base plane: z, alpha and beta change sign, the legs keep their length
    np.testing.assert_allclose(tripod.forward_kinematics(q, assembly="below"), -poses, atol=1e-10)


def _normalised_jacobian(tripod, poses):
    r = tripod.design()["r"]
    return tripod.jacobian(poses) @ np.diag([1.0, 1 / r, 1 / r])


def test_local_indices_on_3x3_jacobians_match_numpy(tripod, poses):
    J = _normalised_jacobian(tripod, poses)
    sigma = np.linalg.svd(J, compute_uv=False)
    np.testing.assert_allclose(tripod.local_index("inverse_condition_2", poses), sigma[:, -1] / sigma[:, 0], rtol=1e-9)
    kappa_f = np.sqrt(np.sum(J**2, axis=(1, 2)) * np.sum(np.linalg.inv(J) ** 2, axis=(1, 2))) / 3
    np.testing.assert_allclose(tripod.local_index("inverse_condition_f", poses), 1 / kappa_f, rtol=1e-12)
    np.testing.assert_allclose(tripod.local_index("manipulability", poses), 1 / np.abs(np.linalg.det(J)), rtol=1e-12)
    np.testing.assert_allclose(tripod.local_index("velocity_max", poses), 1 / sigma[:, -1], rtol=1e-9)


def test_indices_of_a_pose_that_mixes_units_need_a_characteristic_length(poses):
    with pytest.raises(PkmError, match="characteristic_length"):
        Unscaled().local_index("inverse_condition_f", poses)


@pytest.mark.parametrize("region", ["box", "cylinder"])
@pytest.mark.parametrize("index", ["gci", "gci_2", "region_measure"])
def test_global_index_gradient_matches_central_differences(tripod, region, index):
    d = tripod.design().vector()
    value, grad = tripod.global_index(index, region=region, resolution=3, gradient=True)
    assert value.points == tripod.regions[region].node_count(3)
    for k, name in enumerate(tripod.parameter_names()):
        step = np.zeros(3)
        step[k] = 1e-6
        up = tripod.global_index(index, d + step, region=region, resolution=3)
        down = tripod.global_index(index, d - step, region=region, resolution=3)
        assert grad[name] == pytest.approx((up - down) / 2e-6, rel=1e-5, abs=1e-8), name


def test_region_measures_are_exact(tripod):
    assert tripod.global_index("region_measure", region="box", resolution=2) == pytest.approx(8 * 0.1 * 0.2 * 0.15)
    cylinder = math.pi * 0.2**2 * 2 * 0.1
    assert tripod.global_index("region_measure", region="cylinder", resolution=2) == pytest.approx(cylinder)


@pytest.mark.parametrize("region", ["box", "cylinder"])
def test_global_index_converges_with_resolution_and_agrees_with_sampling(tripod, region):
    values = [tripod.global_index("gci", region=region, resolution=n) for n in (1, 2, 4)]
    assert abs(values[2] - values[1]) < abs(values[1] - values[0])
    assert values[2].accuracy == pytest.approx(abs(values[2] - values[1]))
    spec = registry.global_index("gci")
    sampled = sampled_check(
        tripod, spec, tripod.regions[region], tripod.design().vector(), branch=tripod.working_mode(None), resolution=24
    )
    assert float(sampled) == pytest.approx(values[2], rel=1e-3)


def test_region_minimum_is_over_interior_faces_edges_and_corners(tripod):
    spec = registry.global_index("gci")
    minimum = GlobalIndex("gci_min", spec.local, "region minimum of 1/kappa_f", "min")
    branch = tripod.working_mode(None)
    box = tripod.regions["box"]
    d = tripod.design().vector()
    reference, _ = box.reference(3, "min")
    corners = np.array(list(itertools.product((-1.0, 1.0), repeat=3)))
    assert all(np.any(np.all(reference == c, axis=1)) for c in corners)
    assert np.any(np.all(reference == 0, axis=1))
    points, _ = box.quadrature(tripod.functions, d, 3, "min")
    at_nodes = tripod.local_index("inverse_condition_f", points, d)
    value = float(quadrature_function(tripod, minimum, box, branch, 3)(d)[0])
    assert value == pytest.approx(float(np.min(at_nodes)), rel=1e-12)
    interior, _ = box.quadrature(tripod.functions, d, 3, "mean")
    assert value < float(np.min(tripod.local_index("inverse_condition_f", interior, d)))
    sampled = float(sampled_check(tripod, minimum, box, d, branch=branch, resolution=24))
    assert value == pytest.approx(sampled, rel=2e-3)


def test_a_region_out_of_reach_has_no_measure_and_no_mean(tripod):
    below = tripod.regions["box"].at((-5.0, 0.0, 0.0), (0.1, 0.2, 0.15))
    spec = registry.global_index("region_measure")
    d = tripod.design().vector()
    branch = tripod.working_mode(None)
    assert float(quadrature_function(tripod, spec, below, branch, 2)(d)[0]) == 0.0
    mean = float(quadrature_function(tripod, registry.global_index("gci"), below, branch, 2)(d)[0])
    assert np.isnan(mean)


def test_3x3_singular_values_keep_their_relative_accuracy_when_ill_conditioned():
    rng = np.random.default_rng(8)
    A = ca.SX.sym("A", 3, 3)
    f = ca.Function("f", [A], list(extreme_singular_values(A)))
    for condition in (1e2, 1e6, 1e10):
        U, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        V, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        sigma = np.array([1.0, 0.3, 1 / condition])
        largest, smallest = (float(v) for v in f(U @ np.diag(sigma) @ V.T))
        assert largest == pytest.approx(1.0, rel=1e-14)
        assert smallest == pytest.approx(1 / condition, rel=1e-15 * condition)


@pytest.mark.parametrize("sigma", [(2.0, 2.0, 0.5), (2.0, 0.5, 0.5), (1.0, 1.0, 1.0 - 1e-9), (3.0, 1.0 + 1e-7, 1.0),
                                   (1.0, 1.0, 1.0)])
def test_3x3_singular_values_are_exact_where_two_coincide(sigma):
    """Where two singular values meet (the 3-RRR's centred pose), the largest and smallest keep the full
    precision (the cubic's angle from its discriminant as a sum of squares, not from acos near +-1, which lost
    half the digits: 2e-9)."""
    rng = np.random.default_rng(11)
    A = ca.SX.sym("A", 3, 3)
    f = ca.Function("f", [A], list(extreme_singular_values(A)))
    for _ in range(20):
        U, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        V, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        largest, smallest = (float(v) for v in f(U @ np.diag(sigma) @ V.T))
        assert largest == pytest.approx(max(sigma), rel=3e-15, abs=0)
        assert smallest == pytest.approx(min(sigma), rel=3e-15, abs=0)


@pytest.mark.parametrize("n", [4, 6])
def test_jacobi_sweeps_give_the_eigenvalues_of_a_symmetric_matrix_and_their_derivative(n):
    """The written-out Jacobi sweeps of a symmetric 4 x 4 or 6 x 6 matrix (a spatial platform's vibration):
    numpy's eigenvalues to the rounding of the largest, where the eigenvalues spread over 8 decades and where
    two meet; the smallest's derivative along a direction dS is v^T dS v, v its unit eigenvector."""
    rng = np.random.default_rng(n)
    S, dS = ca.SX.sym("S", n, n), ca.SX.sym("dS", n, n)
    values = ca.Function("values", [S], [ca.vertcat(*jacobi_eigenvalues(S))])
    largest, smallest = symmetric_eigenvalues(S)
    extremes = ca.Function("extremes", [S, dS], [largest, smallest, ca.jtimes(smallest, S, dS)])
    for k in range(30):
        Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
        lam = 10 ** rng.uniform(-6, 2, n)
        if k % 3 == 0:
            lam[1] = lam[0]
        A = Q @ np.diag(lam) @ Q.T
        A = (A + A.T) / 2
        reference = np.linalg.eigvalsh(A)
        np.testing.assert_allclose(np.sort(np.ravel(values(A))), reference, rtol=0, atol=1e-14 * reference[-1])
        direction = rng.normal(size=(n, n))
        direction = direction + direction.T
        top, bottom, rate = (float(v) for v in extremes(A, direction))
        assert top == pytest.approx(reference[-1], rel=1e-14)
        assert bottom == pytest.approx(reference[0], rel=0, abs=1e-14 * reference[-1])
        if reference[1] - reference[0] > 1e-3 * reference[-1]:
            v = np.linalg.eigh(A)[1][:, 0]
            assert rate == pytest.approx(v @ direction @ v, rel=1e-8, abs=1e-12 * np.abs(direction).max())
    # already diagonal with equal entries in a plane (no rotation there, sqrt's argument 0): the smallest simple
    # eigenvalue's derivative is its own, and where all coincide it is finite
    direction = np.diag(np.arange(1.0, n + 1))
    _, bottom, rate = (float(v) for v in extremes(np.diag([1.0, 2.0, 2.0, 4.0, 5.0, 6.0][:n]), direction))
    assert (bottom, rate) == (1.0, 1.0)
    assert np.isfinite(float(extremes(np.eye(n), direction)[2]))


def test_the_3rrr_at_its_centred_pose_has_1_over_kappa_2_of_its_singular_values():
    """The centred pose of the symmetric 3-RRR, where two singular values of J (its angle column times the
    characteristic length's inverse) coincide."""
    m = pkm.load("rrr3")
    x = np.zeros((1, 3))
    length = float(m.characteristic_length(dict(m.design())))
    for mode in m.modes:
        J = m.jacobian(x, mode=mode)[0] @ np.diag([1, 1, 1 / length])
        s = np.linalg.svd(J, compute_uv=False)
        if mode == m.modes[0]:  # the symmetric assembly: its two smallest coincide
            assert s[1] == pytest.approx(s[2], rel=1e-14)
        assert m.local_index("inverse_condition_2", x, mode=mode)[0] == pytest.approx(s[-1] / s[0], rel=1e-14, abs=0)


def test_inverse_condition_f_of_a_2x2_jacobian_from_j_alone_is_gaos_formula():
    """1/kappa_f of a 2 x 2 J is taken as 2 |det J| / ||J||_F^2, without J^-1: it equals
    n / sqrt(tr(J J^T) tr(J^-1 J^-T)) of Gao's eqs. 8-11, and is 0 where J is singular or not finite."""
    from pkm.indices.local import INVERSE_CONDITION_F

    J, J_f = ca.SX.sym("J", 2, 2), ca.SX.sym("J_f", 2, 2)
    f = ca.Function("f", [J, J_f], [INVERSE_CONDITION_F.formula(J, J_f)])
    rng = np.random.default_rng(2)
    for _ in range(200):
        A = rng.normal(size=(2, 2)) * rng.uniform(0.01, 100)
        inverse = np.linalg.inv(A)
        want = 2 / math.sqrt(np.sum(A**2) * np.sum(inverse**2))
        assert float(f(A, inverse)) == pytest.approx(want, rel=1e-13)
    assert float(f(np.array([[1.0, 2.0], [2.0, 4.0]]), np.full((2, 2), np.inf))) == 0.0
    assert float(f(np.array([[np.inf, 1.0], [0.0, 1.0]]), np.zeros((2, 2)))) == 0.0


def test_polynomial_roots_drop_vanishing_leading_coefficients():
    """q t^2 + t - 1 = 0: two roots for q != 0, the one root t = 1 at q = 0, none out at infinity."""
    q, d = ca.SX.sym("q_a", 1), ca.SX.sym("design", 1)
    table = FunctionTable({"forward_polynomial": ca.Function("p", [q, d], [ca.vertcat(q, 1, -1)])}, "a test")
    roots = PolynomialRoots().roots(table, np.array([[0.0], [0.25], [1e-30]]), np.zeros(1))
    np.testing.assert_allclose(roots[0], [1.0, np.nan])
    np.testing.assert_allclose(roots[1], [-2 - 2 * np.sqrt(2), -2 + 2 * np.sqrt(2)])
    np.testing.assert_allclose(roots[2], [1.0, np.nan])


def test_sampled_reachable_index_is_n_dimensional(tripod):
    value = tripod.global_index("gci", resolution=8)
    assert 0 < value < 1
    assert value.points == 8**3


def _mic_curves() -> dict[str, ca.Function]:
    mic = registry.mechanism("five_bar").functions["maximum_inscribed_circle"]
    d = ca.SX.sym("design", mic.numel_in(0))
    a = ca.SX.sym("a")
    centre, radius = mic(d)
    half = ca.sqrt(ca.fmax(radius**2 - (a - centre[0]) ** 2, 0))
    return {
        "mic_bounds": ca.Function("mic_bounds", [d], [centre[0] - radius, centre[0] + radius]),
        "mic_curves": ca.Function("mic_curves", [a, d], [centre[1] - half, centre[1] + half]),
        "forward_polynomial": _polynomial(),
        "forward_from_root": _from_root(),
    }


def _elbows(q_a, d):
    a1 = ca.vertcat(-d[2] + d[0] * ca.cos(q_a[0]), d[0] * ca.sin(q_a[0]))
    a2 = ca.vertcat(d[2] + d[0] * ca.cos(q_a[1]), d[0] * ca.sin(q_a[1]))
    return a1, a2


def _polynomial() -> ca.Function:
    """t^2 - (r2^2 - |A1 A2|^2 / 4) = 0: P = M + t n on the bisector of the elbows."""
    q_a, d = ca.SX.sym("q_a", 2), ca.SX.sym("design", len(FiveBar.parameters))
    a1, a2 = _elbows(q_a, d)
    return ca.Function("forward_polynomial", [q_a, d], [ca.vertcat(1, 0, -(d[1] ** 2 - ca.sumsqr(a2 - a1) / 4))])


def _from_root() -> ca.Function:
    t, q_a, d = ca.SX.sym("t"), ca.SX.sym("q_a", 2), ca.SX.sym("design", len(FiveBar.parameters))
    a1, a2 = _elbows(q_a, d)
    u = a2 - a1
    p = (a1 + a2) / 2 + t * ca.vertcat(-u[1], u[0]) / ca.norm_2(u)
    q = ca.vertcat(q_a, ca.atan2(p[1] - a1[1], p[0] - a1[0]), ca.atan2(p[1] - a2[1], p[0] - a2[0]))
    return ca.Function("forward_from_root", [t, q_a, d], [p, q, d[1] ** 2 - ca.sumsqr(u) / 4])


class PolynomialFiveBar(FiveBar):
    name = "test_polynomial_five_bar"
    forward = PolynomialRoots()
    assembly_modes = (Branch("root0", (0.0,), "the smaller real root"), Branch("root1", (1.0,), "the larger"))
    regions: ClassVar[dict] = {
        **FiveBar.regions,
        "mic_between_curves": MappedSquare("mic_between_curves", "the MIC disc as a domain between curves",
                                           bounds="mic_bounds", curves="mic_curves"),
    }

    @cached_property
    def functions(self) -> FunctionTable:
        return FunctionTable({**registry.mechanism("five_bar").functions, **_mic_curves()}, "the test five-bar")


@pytest.fixture(scope="module")
def polynomial() -> PolynomialFiveBar:
    return PolynomialFiveBar()


def test_polynomial_roots_forward_kinematics_equals_the_closed_form(polynomial):
    five_bar = pkm.load("five_bar")
    rng = np.random.default_rng(5)
    x = np.column_stack([rng.uniform(-0.5, 0.5, 30), rng.uniform(0.8, 1.8, 30)])
    q = five_bar.inverse_kinematics(x)
    for root, side in (("root0", "down"), ("root1", "up")):
        np.testing.assert_allclose(
            polynomial.forward_kinematics(q, assembly=root),
            five_bar.forward_kinematics(q, assembly=side),
            atol=1e-10,
        )


def test_domain_between_curves_converges_to_the_disc(polynomial):
    area = math.pi * polynomial.maximum_inscribed_circle()[1] ** 2
    measures = [polynomial.global_index("region_measure", region="mic_between_curves", resolution=n) for n in (4, 16)]
    assert abs(measures[1] - area) < abs(measures[0] - area) < 1e-2 * area
    disc = polynomial.global_index("gci", region="miw", resolution=16)
    mapped = polynomial.global_index("gci", region="mic_between_curves", resolution=16)
    assert mapped == pytest.approx(disc, rel=1e-4)


def test_domain_between_curves_gradient_matches_central_differences(polynomial):
    d = polynomial.design().vector()
    _, grad = polynomial.global_index("gci", region="mic_between_curves", resolution=4, gradient=True)
    for k, name in enumerate(("r1", "r2", "r3")):
        step = np.zeros(len(d))
        step[k] = 1e-6
        up = polynomial.global_index("gci", d + step, region="mic_between_curves", resolution=4)
        down = polynomial.global_index("gci", d - step, region="mic_between_curves", resolution=4)
        assert grad[name] == pytest.approx((up - down) / 2e-6, rel=1e-5, abs=1e-9), name


def test_disc_and_mapped_square_share_the_protocol(polynomial):
    for region in (polynomial.regions["miw"], polynomial.regions["mic_between_curves"]):
        points, weights = region.quadrature(polynomial.functions, polynomial.design().vector(), 2)
        assert points.shape == (region.node_count(2), 2)
        assert weights.shape == (region.node_count(2),)
    assert isinstance(polynomial.regions["miw"], Disc)
