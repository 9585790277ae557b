"""Rigid-body kinematics shared by the Lagrange and virtual-work models: rotations, angular velocity,
inertia tensors, and the embedding of a planar body into space.

A body's orientation is a rotation matrix R(s) (3 x 3, body frame to base frame) in the coordinates s.
Its angular velocity in the base frame is omega = vee(R_dot R^T), where R_dot R^T is skew-symmetric
because R R^T = I. Since R_dot = sum_k (dR/ds_k) s_dot_k, omega is linear in the rates,

    omega = W s_dot,   W = [vee((dR/ds_1) R^T) ... vee((dR/ds_n) R^T)]   (3 x n),

the angular velocity Jacobian. An inertia tensor I_b given in the body frame is I = R I_b R^T in the
base frame. A planar body moving in the plane z = 0 with orientation angle phi is the special case
R = R_z(phi), whose W has the single non-zero row dphi/ds; only the I_zz entry of its tensor matters.
"""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp


def skew(v: sp.Matrix) -> sp.Matrix:
    """The cross-product matrix of a 3-vector: skew(v) u = v x u; shape (3, 3)."""
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def vee(S: sp.Matrix) -> sp.Matrix:
    """The 3-vector of a skew-symmetric matrix, the inverse of :func:`skew`; shape (3, 1)."""
    return sp.Matrix([S[2, 1], S[0, 2], S[1, 0]])


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """a x b of two 3-vectors; shape (3, 1)."""
    return skew(a) * b


def rotation_z(angle: sp.Expr) -> sp.Matrix:
    """R_z(angle): rotation about the z axis, counter-clockwise in the xy plane; shape (3, 3)."""
    c, s = sp.cos(angle), sp.sin(angle)
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def in_plane(v: Sequence[sp.Expr]) -> sp.Matrix:
    """A 2-vector of the plane as the 3-vector (v_x, v_y, 0)."""
    return sp.Matrix([v[0], v[1], 0])


def planar_inertia(moment: sp.Expr) -> sp.Matrix:
    """The tensor diag(0, 0, moment) of a planar body: a body turning about z only feels I_zz."""
    return sp.diag(0, 0, moment)


def angular_velocity_jacobian(rotation: sp.Matrix, coordinates: Sequence[sp.Symbol]) -> sp.Matrix:
    """W with omega = W s_dot in the base frame, from R(s); shape (3, n).

    Column k is vee((dR/ds_k) R^T). Its entries contain sums such as cos^2 + sin^2, which only
    trigonometric simplification reduces; simplified, R = R_z(phi) gives exactly (0, 0, dphi/ds_k),
    so that a planar body yields the expressions of the planar formulas.
    """
    columns = [vee(rotation.diff(s) * rotation.T).applyfunc(sp.trigsimp) for s in coordinates]
    return sp.Matrix.hstack(*columns) if columns else sp.zeros(3, 0)
