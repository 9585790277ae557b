"""Dynamics of a closed-loop mechanism by the principle of virtual work (Wu 2008 section 5; Zhang and
Song 1993).

Every moving body is described in the configuration coordinates s = (q, x) of the loop (all joints,
then the platform coordinates x) by a pivot point p(s), its rotation R(s) and the vector c(s) from the
pivot to its centre of mass, which turns with the body; all in the base frame, 3-D (a planar body is
embedded in z = 0 with R = R_z(phi), :mod:`symbolic.bodies`). Along the loop the configuration moves
with the platform:

    s_dot = Phi_s x_dot,   s_ddot = Phi_s x_ddot + b_s,   Phi_s = (Phi, I),   b_s = (Phi_dot x_dot, 0),

with Phi = d(q)/dx and Phi_dot x_dot from :meth:`symbolic.loops.LoopClosure.inverse_second_order`.
The partial velocity matrix of the pivot and the partial angular velocity matrix of the body
(Wu eqs. 19-26) are

    H = (dp/ds) Phi_s   (3 x n),      G = W Phi_s   (3 x n),

with W the angular velocity Jacobian of R (omega = W s_dot), so that the pivot velocity is H x_dot
and the angular velocity omega = G x_dot. With a_P = H x_ddot + H_dot x_dot and
alpha = G x_ddot + G_dot x_dot, the inertia force (gravity included) and the inertia moment about the
pivot are (Newton-Euler; Wu eqs. 30-39 written once for any body)

    F   = -m (a_P + alpha x c + omega x (omega x c) - g),
    M_P = -(I_P alpha + omega x I_P omega) - m c x (a_P - g),

with I_P = R I_b R^T the inertia tensor about the pivot in the base frame (I_b in the body frame).
In the plane, alpha x c = alpha E c, omega x (omega x c) = -omega^2 c with E = [[0, -1], [1, 0]],
omega x I_P omega = 0, and M_P reduces to its z component -I_P alpha - m c x (a_P - g).
Each splits into a part linear in the platform acceleration and the rest: F = F_a x_ddot + F~,
M_P = M_a x_ddot + M~. The principle of virtual work (eq. 40) with the actuator forces tau doing
work on q_a_dot = J x_dot,

    J^T tau + sum over bodies (H^T F + G^T M_P) = 0,

gives eq. 41, tau = (J^T)^-1 M x_ddot + N, with

    M = -sum (H^T F_a + G^T M_a),      N = -(J^T)^-1 sum (H^T F~ + G^T M~).

M is symmetric: it is the task-space mass matrix of the kinetic energy T = x_dot^T M x_dot / 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symbolic.bodies import angular_velocity_jacobian, cross, in_plane, planar_inertia, rotation_z, skew


@dataclass(frozen=True)
class PivotBody:
    """A rigid body for the virtual-work model.

    Attributes
    ----------
    name : str
    mass : sympy expression [kg]
    pivot : sympy.Matrix, shape (3, 1)
        The pivot point p(s) in the base frame [m]: the point whose velocity is simplest (Wu 5.1).
    rotation : sympy.Matrix, shape (3, 3)
        R(s), body frame to base frame; constant for a translating body.
    centre : sympy.Matrix, shape (3, 1)
        The vector c(s) from the pivot to the centre of mass in the base frame [m]; it must turn with
        the body (dc/ds_k = w_k x c with w_k the columns of the angular velocity Jacobian), which
        :meth:`is_rigid` checks.
    inertia : sympy.Matrix, shape (3, 3)
        Inertia tensor I_b about the pivot in the body frame [kg m^2].
    """

    name: str
    mass: sp.Expr
    pivot: sp.Matrix
    rotation: sp.Matrix
    centre: sp.Matrix
    inertia: sp.Matrix

    @classmethod
    def planar(
        cls,
        name: str,
        mass: sp.Expr,
        *,
        pivot: Sequence[sp.Expr],
        angle: sp.Expr,
        centre: Sequence[sp.Expr],
        inertia: sp.Expr,
    ) -> PivotBody:
        """A body of the plane z = 0: pivot and centre offset (2-vectors), orientation angle phi
        (counter-clockwise) and moment of inertia I_P about the pivot, embedded as R = R_z(phi),
        I_b = diag(0, 0, I_P)."""
        return cls(name, mass, in_plane(pivot), rotation_z(angle), in_plane(centre), planar_inertia(inertia))

    def is_rigid(self, coordinates: Sequence[sp.Symbol]) -> bool:
        """Whether c turns with the body: dc/ds_k - w_k x c, i.e. dc/ds + skew(c) W, vanishes identically."""
        W = angular_velocity_jacobian(self.rotation, coordinates)
        residual = self.centre.jacobian(sp.Matrix(coordinates)) + skew(self.centre) * W
        return all(sp.simplify(e) == 0 for e in residual)


@dataclass(frozen=True)
class Motion:
    """How the configuration s = (q, x) moves with the platform: s_dot = Phi_s x_dot, s_ddot = Phi_s
    x_ddot + b_s (``bias``), for platform velocity symbols ``x_dot``."""

    coordinates: tuple[sp.Symbol, ...]
    phi: sp.Matrix
    bias: sp.Matrix
    x_dot: tuple[sp.Symbol, ...]

    @classmethod
    def of(
        cls,
        joints: Sequence[sp.Symbol],
        platform: Sequence[sp.Symbol],
        joint_map: sp.Matrix,
        joint_bias: sp.Matrix,
        x_dot: Sequence[sp.Symbol],
    ) -> Motion:
        """From the joint map Phi = dq/dx (n_q x n) and the joint bias Phi_dot x_dot (n_q x 1)."""
        n = len(platform)
        return cls(
            (*joints, *platform),
            joint_map.col_join(sp.eye(n)),
            joint_bias.col_join(sp.zeros(n, 1)),
            tuple(x_dot),
        )

    @property
    def rates(self) -> sp.Matrix:
        """s_dot = Phi_s x_dot."""
        return self.phi * sp.Matrix(self.x_dot)

    def partial(self, W: sp.Matrix) -> sp.Matrix:
        """W Phi_s: the partial velocity matrix of a velocity v = W(s) s_dot along the loop; shape (k, n)."""
        return W * self.phi

    def velocity_product(self, W: sp.Matrix) -> sp.Matrix:
        """The part of d(W s_dot)/dt not linear in x_ddot: W b_s + W_dot s_dot; shape (k, 1).

        W_dot s_dot has the entries s_dot^T (dW_k/ds) s_dot of the rows W_k; for the velocity of a point
        p, W = dp/ds and dW_k/ds is the Hessian of p_k.
        """
        s_dot = self.rates
        out = W * self.bias
        for k in range(W.rows):
            out[k] += (s_dot.T * W[k, :].jacobian(self.coordinates) * s_dot)[0]
        return out


@dataclass(frozen=True)
class Wrench:
    """Inertia force (gravity included) and moment of one body about its pivot, split as
    F = F_a x_ddot + F_rest and M = M_a x_ddot + M_rest (3 x n and 3 x 1 each); H and G (3 x n) are its
    partial velocity and angular velocity matrices."""

    H: sp.Matrix
    G: sp.Matrix
    F_a: sp.Matrix
    F_rest: sp.Matrix
    M_a: sp.Matrix
    M_rest: sp.Matrix


def inertia_wrench(body: PivotBody, motion: Motion, gravity: sp.Matrix) -> Wrench:
    """The inertia wrench of ``body`` about its pivot (module docstring), split by x_ddot.

    ``gravity`` is the 3-vector g of the base frame [m/s^2].
    """
    dp = body.pivot.jacobian(motion.coordinates)
    W = angular_velocity_jacobian(body.rotation, motion.coordinates)
    H, G = motion.partial(dp), motion.partial(W)
    a_rest = motion.velocity_product(dp)
    alpha_rest = motion.velocity_product(W)
    omega = G * sp.Matrix(motion.x_dot)
    c, m = body.centre, body.mass
    inertia = body.rotation * body.inertia * body.rotation.T
    # alpha x c = -c x alpha: the part linear in x_ddot is -skew(c) G x_ddot.
    F_a = -m * (H - skew(c) * G)
    F_rest = -m * (a_rest + cross(alpha_rest, c) + cross(omega, cross(omega, c)) - gravity)
    M_a = -inertia * G - m * (skew(c) * H)
    M_rest = -inertia * alpha_rest - cross(omega, inertia * omega) - m * cross(c, a_rest - gravity)
    return Wrench(H, G, F_a, F_rest, M_a, M_rest)


@dataclass(frozen=True)
class VirtualWorkModel:
    """J^T tau = M x_ddot + n, i.e. tau = (J^T)^-1 M x_ddot + N with N = (J^T)^-1 n (Wu eq. 41)."""

    M: sp.Matrix
    n: sp.Matrix
    wrenches: tuple[Wrench, ...]


def virtual_work(bodies: Sequence[PivotBody], motion: Motion, gravity: sp.Matrix) -> VirtualWorkModel:
    """Sum the bodies' virtual work of eq. 40: M = -sum(H^T F_a + G^T M_a), n = -sum(H^T F~ + G^T M~)."""
    k = len(motion.x_dot)
    M, n = sp.zeros(k, k), sp.zeros(k, 1)
    wrenches = []
    for body in bodies:
        w = inertia_wrench(body, motion, gravity)
        M -= w.H.T * w.F_a + w.G.T * w.M_a
        n -= w.H.T * w.F_rest + w.G.T * w.M_rest
        wrenches.append(w)
    return VirtualWorkModel(M, n, tuple(wrenches))
