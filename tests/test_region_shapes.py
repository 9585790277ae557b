"""The generic region pieces on their own: shapes side by side (Union), graded domains between curves,
shapes mapped to the pose with and without their area element, per-point sample cells, polished
polynomial roots."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

from pkm.indices import reduce_samples
from pkm.kinematics import PolynomialRoots
from pkm.regions import Mapped, MappedSquare, Rectangle, Union

A = ca.SX.sym("a")
D = ca.SX.sym("design", 1)
Y = ca.SX.sym("y", 2)
FUNCTIONS = {
    "quarter": ca.Function("quarter", [D], [0, math.pi / 2]),
    "unit": ca.Function("unit", [A, D], [0 * A, 1 + 0 * A]),
    "polar": ca.Function("polar", [Y, D], [Y[1] * ca.vertcat(ca.cos(Y[0]), ca.sin(Y[0]))]),
    "radius": ca.Function("radius", [Y, D], [Y[1]]),
}
DESIGN = np.array([1.0])


def integrate(region, f, resolution: int) -> float:
    points, weights = region.quadrature(FUNCTIONS, DESIGN, resolution)
    return float(np.sum(weights * f(points)))


def test_union_adds_the_parts_nodes_and_weights():
    left = Rectangle("left", "", fixed=((-1.0, 0.0), (1.0, 1.0)))
    right = Rectangle("right", "", fixed=((1.5, 0.0), (0.5, 1.0)))
    both = Union("both", "", (left, right))
    assert both.node_count(3) == left.node_count(3) + right.node_count(3)
    assert integrate(both, lambda p: np.ones(len(p)), 3) == pytest.approx(4.0 + 2.0, rel=1e-14)
    # x^2 over [-2, 0] x [-1, 1] and [1, 2] x [-1, 1], exact for Gauss-Legendre
    assert integrate(both, lambda p: p[:, 0] ** 2, 3) == pytest.approx(2 * 8 / 3 + 2 * 7 / 3, rel=1e-13)
    points, cells = both.sample(FUNCTIONS, DESIGN, 10)
    assert cells.shape == (len(points),)
    assert cells.sum() == pytest.approx(6.0, rel=1e-12)


def test_grading_makes_a_square_root_at_the_upper_curve_smooth():
    """The integral of sqrt(1 - b) over the unit square is 2/3; graded nodes (p = 2) make the integrand
    smooth in the reference coordinate, so the rule is exact where the plain one is not."""
    plain = MappedSquare("plain", "", "quarter", "unit")
    graded = MappedSquare("graded", "", "quarter", "unit", grading=2)
    exact = math.pi / 2 * 2 / 3
    f = lambda p: np.sqrt(np.clip(1 - p[:, 1], 0, None))  # noqa: E731
    plain_error = abs(integrate(plain, f, 4) - exact)
    assert abs(integrate(graded, f, 4) - exact) < 1e-13
    assert plain_error > 1e-5
    assert integrate(graded, lambda p: np.ones(len(p)), 4) == pytest.approx(math.pi / 2, rel=1e-14)


def test_graded_rim_nodes_lie_inside_the_curves():
    graded = MappedSquare("graded", "", "quarter", "unit", grading=2)
    points, _ = graded.quadrature(FUNCTIONS, DESIGN, 3, "min")
    assert np.all(points[:, 1] > 0)
    assert np.all(points[:, 1] < 1)
    assert points[:, 1].max() > 1 - 1e-8


def test_a_mapped_region_is_measured_in_its_own_coordinates_or_with_its_area_element_in_the_pose():
    polar = MappedSquare("polar", "", "quarter", "unit", grading=2)
    own = Mapped("own", "", polar, "polar")
    plane = Mapped("plane", "", polar, "polar", element="radius")
    ones = lambda p: np.ones(len(p))  # noqa: E731
    assert integrate(own, ones, 4) == pytest.approx(math.pi / 2, rel=1e-13)
    assert integrate(plane, ones, 4) == pytest.approx(math.pi / 4, rel=1e-13)
    # the second moment x^2 + y^2 over the quarter disc: pi / 8
    assert integrate(plane, lambda p: np.sum(p**2, axis=1), 4) == pytest.approx(math.pi / 8, rel=1e-13)
    points, cells = plane.sample(FUNCTIONS, DESIGN, 200)
    assert np.all(np.hypot(points[:, 0], points[:, 1]) < 1)
    assert cells.sum() == pytest.approx(math.pi / 4, rel=1e-3)


def test_reduce_samples_weighs_each_point_by_its_cell():
    values = np.array([1.0, 2.0, 3.0, 100.0])
    keep = np.array([True, True, True, False])
    cells = np.array([1.0, 1.0, 2.0, 5.0])
    assert reduce_samples(values, keep, cells, "mean") == pytest.approx(9 / 4)
    assert reduce_samples(values, keep, cells, "measure") == pytest.approx(4.0)
    assert reduce_samples(values, keep, cells, "std") == pytest.approx(math.sqrt((1.5625 + 0.0625 + 2 * 0.5625) / 4))
    assert reduce_samples(values, keep, 0.5, "mean") == pytest.approx(2.0)


@pytest.mark.parametrize("size", [1e-3, 1.0, 1e3])
def test_polynomial_roots_are_found_and_polished_at_any_scale(size):
    """(t + s)(t - 0.2 s)(t - 0.2 s - 1e-4 s)(t^2 + s^2): three real roots, two of them close, at the
    scale s of the root variable; the same relative accuracy at every scale."""
    roots_true = size * np.array([-1.0, 0.2, 0.2 + 1e-4])
    coefficients = np.polymul(np.poly(roots_true), [1.0, 0.0, size**2])
    q = ca.SX.sym("q_a", 1)
    d = ca.SX.sym("design", 1)
    functions = {
        "forward_polynomial": ca.Function("forward_polynomial", [q, d], [ca.DM(coefficients)]),
        "size": ca.Function("size", [d], [d[0]]),
    }
    found = PolynomialRoots(scale="size").roots(functions, np.zeros((1, 1)), np.array([size]))
    assert np.sum(np.isfinite(found)) == 3
    np.testing.assert_allclose(found[0, :3], roots_true, rtol=0, atol=1e-11 * size)


def _registered_regions():
    import pkm

    for name in pkm.mechanisms():
        mech = pkm.load(name)
        for key, region in mech.regions.items():
            yield pytest.param(mech, region, id=f"{name}-{key}")


@pytest.mark.parametrize(("mech", "region"), list(_registered_regions()))
def test_each_piece_maps_its_reference_nodes_to_the_regions_nodes(mech, region):
    design = mech.design_vector(None)
    points, _ = region.quadrature(mech.functions, design, 2, "min")
    u = ca.SX.sym("u", region.dimension)
    mapped = []
    for piece in region.pieces():
        to_pose = ca.Function("to_pose", [u], [piece.to_pose(mech.functions, ca.DM(design), u)])
        nodes, _ = piece.reference(2, "min")
        assert np.array_equal(piece.project(nodes), nodes)
        mapped.append(np.asarray(to_pose.map(len(nodes))(nodes.T)).T)
    np.testing.assert_allclose(np.concatenate(mapped), points, rtol=1e-13, atol=1e-13)


def test_projection_puts_points_on_the_closed_reference_domain():
    from pkm.regions import Cylinder, Disc
    from pkm.regions.shapes import RIM_INSET

    far = np.array([[3.0, 4.0], [0.1, 0.2]])
    np.testing.assert_allclose(Disc("d", "disc").project(far), [[0.6 * (1 - RIM_INSET), 0.8 * (1 - RIM_INSET)],
                                                                [0.1, 0.2]])
    np.testing.assert_array_equal(Rectangle("r", "rectangle").project(np.array([[2.0, -0.5]])), [[1.0, -0.5]])
    cylinder = Cylinder("c", "cylinder", axis=0).project(np.array([[-7.0, 3.0, 4.0]]))
    np.testing.assert_allclose(cylinder, [[-1.0, 0.6 * (1 - RIM_INSET), 0.8 * (1 - RIM_INSET)]])
