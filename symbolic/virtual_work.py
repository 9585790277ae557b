"""Dynamics of a closed-loop mechanism by the principle of virtual work (Wu 2008 section 5; Zhang and
Song 1993).

Every moving body is described in the configuration coordinates s = (q, x) of the loop (all joints,
then the platform coordinates x) by a pivot point p(s), its orientation angle phi(s) (counter-clockwise)
and the vector c(s) from the pivot to its centre of mass, which turns with the body. Along the loop
the configuration moves with the platform:

    s_dot = Phi_s x_dot,   s_ddot = Phi_s x_ddot + b_s,   Phi_s = (Phi, I),   b_s = (Phi_dot x_dot, 0),

with Phi = d(q)/dx and Phi_dot x_dot from :meth:`symbolic.loops.LoopClosure.inverse_second_order`.
The partial velocity matrix of the pivot and the partial angular velocity matrix of the body
(Wu eqs. 19-26) are

    H = (dp/ds) Phi_s   (2 x n),      G = (dphi/ds) Phi_s   (1 x n),

so that the pivot velocity is H x_dot and the angular velocity G x_dot. With a_P = H x_ddot + H_dot x_dot
and alpha = G x_ddot + G_dot x_dot, the inertia force (gravity included) and the inertia moment about
the pivot are (Newton-Euler; Wu eqs. 30-39 written once for any body)

    F   = -m (a_P + alpha E c - omega^2 c - g),
    M_P = -I_P alpha - m c x (a_P - g),                    E = [[0, -1], [1, 0]],

with I_P the moment of inertia about the pivot. Each splits into a part linear in the platform
acceleration and the rest: F = F_a x_ddot + F~, M_P = M_a x_ddot + M~. The principle of virtual work
(eq. 40) with the actuator forces tau doing work on q_a_dot = J x_dot,

    J^T tau + sum over bodies (H^T F + G^T M_P) = 0,

gives eq. 41, tau = (J^T)^-1 M x_ddot + N, with

    M = -sum (H^T F_a + G^T M_a),      N = -(J^T)^-1 sum (H^T F~ + G^T M~).

M is symmetric: it is the task-space mass matrix of the kinetic energy T = x_dot^T M x_dot / 2.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

E = sp.Matrix([[0, -1], [1, 0]])


@dataclass(frozen=True)
class PivotBody:
    """A planar rigid body for the virtual-work model.

    Attributes
    ----------
    name : str
    mass : sympy expression [kg]
    pivot : sympy.Matrix (2, 1)
        The pivot point p(s) in the base frame [m]: the point whose velocity is simplest (Wu 5.1).
    angle : sympy expression
        Orientation phi(s), counter-clockwise [rad]; a constant for a translating body.
    centre : sympy.Matrix (2, 1)
        The vector c(s) from the pivot to the centre of mass in the base frame [m]; it must turn with
        the body (dc/ds = E c dphi/ds), which :meth:`is_rigid` checks.
    inertia : sympy expression
        Moment of inertia I_P about the pivot [kg m^2].
    """

    name: str
    mass: sp.Expr
    pivot: sp.Matrix
    angle: sp.Expr
    centre: sp.Matrix
    inertia: sp.Expr

    def is_rigid(self, coordinates: Sequence[sp.Symbol]) -> bool:
        """Whether c turns with the body: dc/ds - E c dphi/ds vanishes identically."""
        s = sp.Matrix(coordinates)
        residual = self.centre.jacobian(s) - E * self.centre * sp.Matrix([self.angle]).jacobian(s)
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

    def partial(self, f: sp.Matrix) -> sp.Matrix:
        """d(f)/d(x) along the loop: (df/ds) Phi_s, the partial velocity matrix of f."""
        return f.jacobian(self.coordinates) * self.phi

    def velocity_product(self, f: sp.Matrix) -> sp.Matrix:
        """The part of f_ddot that is not linear in x_ddot: (df/ds) b_s + s_dot^T (d2f/ds2) s_dot."""
        s_dot = self.rates
        grad = f.jacobian(self.coordinates)
        out = grad * self.bias
        for k in range(f.rows):
            out[k] += (s_dot.T * sp.hessian(f[k], self.coordinates) * s_dot)[0]
        return out


@dataclass(frozen=True)
class Wrench:
    """Inertia force (gravity included) and moment of one body about its pivot, split as
    F = F_a x_ddot + F_rest and M = M_a x_ddot + M_rest; H and G are its partial (angular) velocity
    matrices."""

    H: sp.Matrix
    G: sp.Matrix
    F_a: sp.Matrix
    F_rest: sp.Matrix
    M_a: sp.Matrix
    M_rest: sp.Expr


def _cross(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[1] - a[1] * b[0]


def inertia_wrench(body: PivotBody, motion: Motion, gravity: sp.Matrix) -> Wrench:
    """The inertia wrench of ``body`` about its pivot (module docstring), split by x_ddot."""
    angle = sp.Matrix([body.angle])
    H = motion.partial(body.pivot)
    G = motion.partial(angle)
    a_rest = motion.velocity_product(body.pivot)
    alpha_rest = motion.velocity_product(angle)[0]
    omega = (G * sp.Matrix(motion.x_dot))[0]
    c, m = body.centre, body.mass
    Ec = E * c
    F_a = -m * (H + Ec * G)
    F_rest = -m * (a_rest + alpha_rest * Ec - omega**2 * c - gravity)
    M_a = -body.inertia * G - m * (c[0] * H[1, :] - c[1] * H[0, :])
    M_rest = -body.inertia * alpha_rest - m * _cross(c, a_rest - gravity)
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
