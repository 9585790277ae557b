"""Spatial rigid bodies in the Lagrange and virtual-work derivations (symbolic/bodies.py).

A planar body is the special case R = R_z(phi) of a spatial one, and a spatial body derived twice, by
Lagrange's equations and by virtual work, gives the same mass matrix and the same velocity-product and
gravity terms (DESIGN section 2: derive twice and compare).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from symbolic.bodies import angular_velocity_jacobian, rotation_z, skew, vee
from symbolic.lagrange import Body, Chain, chain_model, rate
from symbolic.virtual_work import Motion, PivotBody, virtual_work

m, g, L, a = sp.symbols("m g L a", positive=True)
Ixx, Iyy, Izz, Ixy, Ixz, Iyz = sp.symbols("Ixx Iyy Izz Ixy Ixz Iyz", real=True)
u, alpha, beta, theta = sp.symbols("u alpha beta theta", real=True)
TENSOR = sp.Matrix([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])


def rotation_x(angle: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])


def open_chain_motion(coordinates: tuple[sp.Symbol, ...]) -> Motion:
    """An open chain as a loop without joints: its coordinates are the platform's, Phi_s = I."""
    n = len(coordinates)
    return Motion.of((), coordinates, sp.zeros(0, n), sp.zeros(0, 1), [rate(c) for c in coordinates])


def numeric_points(exprs: list[sp.Matrix], symbols: list[sp.Symbol], count: int = 5) -> list[list[np.ndarray]]:
    """Each expression evaluated at the same random points (positive inertia and lengths by construction)."""
    rng = np.random.default_rng(7)
    f = sp.lambdify(symbols, exprs, "numpy")
    return [[np.asarray(v, dtype=float) for v in f(*rng.uniform(0.3, 1.7, size=len(symbols)))] for _ in range(count)]


def test_angular_velocity_of_a_rotation_about_z_is_the_angle_rate():
    # Exactly (0, 0, dphi/ds), not an unsimplified cos^2 + sin^2: planar models keep their expressions.
    assert angular_velocity_jacobian(rotation_z(sp.pi / 2 - theta), (u, theta)).tolist() == [[0, 0], [0, 0], [0, -1]]
    R = rotation_z(alpha) * rotation_x(beta)
    omega = angular_velocity_jacobian(R, (alpha, beta)) * sp.Matrix([rate(alpha), rate(beta)])
    R_dot = R.diff(alpha) * rate(alpha) + R.diff(beta) * rate(beta)
    assert vee(skew(omega)) == omega
    # R_dot R^T is the skew matrix of omega because R is orthogonal.
    symbols = [alpha, beta, rate(alpha), rate(beta)]
    for spin, skew_omega in numeric_points([R_dot * R.T, skew(omega)], symbols):
        np.testing.assert_allclose(spin, skew_omega, rtol=1e-14, atol=1e-14)


def test_a_spatial_body_turning_about_z_is_the_planar_body():
    centre = sp.Matrix([u + a * sp.cos(theta), a * sp.sin(theta)])
    planar = Body.planar("link", m, centre=centre, inertia=Izz, angle=theta)
    # Any tensor with the same I_zz: a body turning about z only never feels the others.
    spatial = Body("link", m, sp.Matrix([*centre, 0]), TENSOR, rotation_z(theta))
    T_planar, T_spatial = (Chain("c", (u, theta), (b,)).kinetic_energy() for b in (planar, spatial))
    omega, v = rate(theta), centre.jacobian([u, theta]) * sp.Matrix([rate(u), rate(theta)])
    assert sp.simplify(T_planar - (m * (v.T * v)[0] + Izz * omega**2) / 2) == 0
    assert sp.simplify(T_spatial - T_planar) == 0
    assert chain_model(Chain("c", (u, theta), (planar,))).M == chain_model(Chain("c", (u, theta), (spatial,))).M

    motion = open_chain_motion((u, theta))
    gravity = sp.Matrix([0, -g, 0])
    pivot, offset = sp.Matrix([u, 0]), a * sp.Matrix([sp.cos(theta), sp.sin(theta)])
    flat = PivotBody.planar("link", m, pivot=pivot, angle=theta, centre=offset, inertia=Izz)
    solid = PivotBody("link", m, sp.Matrix([u, 0, 0]), rotation_z(theta), sp.Matrix([*offset, 0]), TENSOR)
    vw_flat, vw_solid = (virtual_work([b], motion, gravity) for b in (flat, solid))
    assert sp.simplify(vw_flat.M - vw_solid.M) == sp.zeros(2, 2)
    assert sp.simplify(vw_flat.n - vw_solid.n) == sp.zeros(2, 1)


def test_spatial_lagrange_and_virtual_work_agree():
    """A body on a spherical joint carried by a slider: R = R_z(alpha) R_x(beta), gravity along -z.

    Lagrange uses the inertia about the centre of mass, virtual work the inertia about the moving
    pivot (parallel axes); both give M, and C q_dot + g equals n.
    """
    q = (u, alpha, beta)
    R = rotation_z(alpha) * rotation_x(beta)
    pivot = sp.Matrix([u, 0, 0])
    c_body = sp.Matrix([a, 0, -L])
    centre_offset = R * c_body
    about_centre = sp.diag(Ixx, Iyy, Izz)
    about_pivot = about_centre + m * ((c_body.T * c_body)[0] * sp.eye(3) - c_body * c_body.T)
    gravity = sp.Matrix([0, 0, -g])

    bob = Body("bob", m, pivot + centre_offset, about_centre, R)
    lagrange = chain_model(Chain("pendulum", q, (bob,), gravity=gravity))
    vw = virtual_work([PivotBody("bob", m, pivot, R, centre_offset, about_pivot)], open_chain_motion(q), gravity)

    rates = sp.Matrix([rate(c) for c in q])
    symbols = [*q, *rates, m, g, L, a, Ixx, Iyy, Izz]
    exprs = [lagrange.M, vw.M, lagrange.C * rates + lagrange.g, vw.n]
    for M_lagrange, M_vw, n_lagrange, n_vw in numeric_points(exprs, symbols):
        np.testing.assert_allclose(M_vw, M_lagrange, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(n_vw, n_lagrange, rtol=1e-12, atol=1e-12)
        assert np.all(np.linalg.eigvalsh(M_vw) > 0)


@pytest.mark.parametrize(
    ("centre", "rigid"),
    [
        (rotation_z(alpha) * rotation_x(beta) * sp.Matrix([a, 0, -L]), True),
        (sp.Matrix([a, 0, -L]), False),
        (rotation_z(alpha) * sp.Matrix([a, 0, -L]), False),
    ],
    ids=["turns_with_the_body", "fixed_in_the_base", "turns_about_one_axis_only"],
)
def test_pivot_body_is_rigid_only_if_its_centre_turns_with_it(centre, rigid):
    R = rotation_z(alpha) * rotation_x(beta)
    body = PivotBody("bob", m, sp.Matrix([u, 0, 0]), R, centre, TENSOR)
    assert body.is_rigid((u, alpha, beta)) is rigid


def test_planar_pivot_body_rigidity_is_the_planar_condition():
    offset = a * sp.Matrix([sp.sin(theta), sp.cos(theta)])
    assert PivotBody.planar("link", m, pivot=[u, 0], angle=sp.pi / 2 - theta, centre=offset, inertia=Izz).is_rigid(
        (u, theta)
    )
    assert not PivotBody.planar("link", m, pivot=[u, 0], angle=theta, centre=offset, inertia=Izz).is_rigid((u, theta))
