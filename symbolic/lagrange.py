"""Lagrange models of open chains and their projection onto the independent coordinates of a loop.

A closed-loop mechanism is cut into open chains. Each chain carries bodies (mass, centre of mass,
inertia tensor, rotation; spatial, with planar bodies as the special case of :mod:`symbolic.bodies`),
springs and joint friction in its own coordinates; with the centre velocity v = (dc/dq) q_dot and the
angular velocity omega = W q_dot, the kinetic energy is

    T = sum over bodies of m |v|^2 / 2 + omega^T (R I_b R^T) omega / 2,

and the Lagrangian L = T - V gives (Lara-Molina 2016 eqs. 14-20)

    M(q) q_ddot + C(q, q_dot) q_dot + dV/dq + f(q_dot) = tau,

with M the Hessian of T in the rates and C in Christoffel form, so that M_dot - 2 C is skew.
:func:`stack` joins the chains (block diagonal, in the loop's joint order) and :func:`project`
eliminates the dependent coordinates with Psi = dq/dz from :mod:`symbolic.loops`: q_dot = Psi z_dot,
q_ddot = Psi z_ddot + Psi_dot z_dot, and by the principle of virtual work (eqs. 24-29)

    M_t = Psi^T M Psi,   C_t = Psi^T (M Psi_dot + C Psi),   g_t = Psi^T dV/dq,   f_t = Psi^T f.

The Psi_dot term of C_t is the centripetal and Coriolis effect of the loop itself; Lara-Molina's
C_t = Psi^T C Psi omits it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from symbolic.bodies import angular_velocity_jacobian, in_plane, planar_inertia, rotation_z


def rate(q: sp.Symbol) -> sp.Symbol:
    """The symbol of the time derivative of a coordinate: ``q`` -> ``q_dot``."""
    return sp.Symbol(f"{q.name}_dot", real=True)


@dataclass(frozen=True)
class Body:
    """A rigid body of an open chain.

    Attributes
    ----------
    name : str
    mass : sympy expression [kg]
    centre : sympy.Matrix, shape (3, 1)
        Centre of mass in the base frame, a function of the chain's coordinates [m].
    inertia : sympy.Matrix, shape (3, 3)
        Inertia tensor about the centre of mass in the body frame [kg m^2].
    rotation : sympy.Matrix, shape (3, 3)
        R(q), body frame to base frame.
    """

    name: str
    mass: sp.Expr
    centre: sp.Matrix
    inertia: sp.Matrix
    rotation: sp.Matrix

    @classmethod
    def planar(cls, name: str, mass: sp.Expr, *, centre: Sequence[sp.Expr], inertia: sp.Expr, angle: sp.Expr) -> Body:
        """A body of the plane z = 0: centre (2-vector), moment of inertia about its centre of mass and
        orientation angle (counter-clockwise), embedded as R = R_z(angle), I_b = diag(0, 0, inertia)."""
        return cls(name, mass, in_plane(centre), planar_inertia(inertia), rotation_z(angle))


@dataclass(frozen=True)
class Spring:
    """A linear spring: potential stiffness * deflection^2 / 2."""

    stiffness: sp.Expr
    deflection: sp.Expr


@dataclass(frozen=True)
class Friction:
    """Joint friction on one coordinate: viscous * q_dot + coulomb * sign(q_dot) (eq. 22)."""

    coordinate: sp.Symbol
    viscous: sp.Expr
    coulomb: sp.Expr = sp.S.Zero


@dataclass(frozen=True)
class Chain:
    """An open chain: its coordinates, bodies, springs, friction and the gravity vector (3, 1) [m/s^2]."""

    name: str
    coordinates: tuple[sp.Symbol, ...]
    bodies: tuple[Body, ...]
    springs: tuple[Spring, ...] = ()
    friction: tuple[Friction, ...] = ()
    gravity: sp.Matrix | None = None

    def rates(self) -> sp.Matrix:
        return sp.Matrix([rate(q) for q in self.coordinates])

    def kinetic_energy(self) -> sp.Expr:
        """T = sum over bodies of m |c_dot|^2 / 2 + omega^T I omega / 2, I = R I_b R^T (eqs. 17-18)."""
        q, qd = sp.Matrix(self.coordinates), self.rates()
        total = sp.Integer(0)
        for body in self.bodies:
            velocity = body.centre.jacobian(q) * qd
            omega = angular_velocity_jacobian(body.rotation, self.coordinates) * qd
            inertia = body.rotation * body.inertia * body.rotation.T
            total += body.mass * (velocity.T * velocity)[0] / 2 + (omega.T * inertia * omega)[0] / 2
        return total

    def potential_energy(self) -> sp.Expr:
        """V = elastic energy of the springs (eq. 16) plus -m g . c of every body."""
        total = sum((s.stiffness * s.deflection**2 / 2 for s in self.springs), sp.Integer(0))
        if self.gravity is not None:
            total -= sum(((self.gravity.T * b.centre)[0] * b.mass for b in self.bodies), sp.Integer(0))
        return total

    def friction_forces(self) -> sp.Matrix:
        f = sp.zeros(len(self.coordinates), 1)
        for fr in self.friction:
            k = self.coordinates.index(fr.coordinate)
            f[k] += fr.viscous * rate(fr.coordinate) + fr.coulomb * sp.sign(rate(fr.coordinate))
        return f


@dataclass(frozen=True)
class Model:
    """M(q) q_ddot + C(q, q_dot) q_dot + g(q) + f(q_dot) = tau in the coordinates ``q``.

    g collects the conservative forces dV/dq (elastic and gravitational), f the friction.
    """

    coordinates: tuple[sp.Symbol, ...]
    M: sp.Matrix
    C: sp.Matrix
    g: sp.Matrix
    f: sp.Matrix
    potential: sp.Expr
    dependent: tuple[sp.Symbol, ...] = ()

    def rates(self) -> sp.Matrix:
        return sp.Matrix([rate(q) for q in self.coordinates])

    def stiffness(self) -> sp.Matrix:
        """Hessian of the potential energy in the coordinates.

        After :func:`project` this is the stiffness only where the potential does not depend on the
        eliminated coordinates (elastic joints between independent coordinates); otherwise it raises.
        """
        stray = sorted(self.potential.free_symbols & set(self.dependent), key=sp.default_sort_key)
        if stray:
            raise ValueError(f"the potential depends on the eliminated coordinates {stray}")
        return sp.hessian(self.potential, self.coordinates)


def christoffel(M: sp.Matrix, q: Sequence[sp.Symbol], qd: sp.Matrix) -> sp.Matrix:
    """C with C_kj = sum_i (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) qd_i / 2 (Christoffel symbols)."""
    n = len(q)
    dM = [M.diff(qi) for qi in q]
    C = sp.zeros(n, n)
    for k in range(n):
        for j in range(n):
            C[k, j] = sum((dM[i][k, j] + dM[j][k, i] - dM[k][i, j]) * qd[i] / 2 for i in range(n))
    return C


def chain_model(chain: Chain) -> Model:
    """The Lagrange equations of one open chain (eqs. 14 and 20)."""
    q, qd = chain.coordinates, chain.rates()
    T = chain.kinetic_energy()
    M = sp.hessian(T, list(qd)).applyfunc(sp.expand)
    V = chain.potential_energy()
    g = sp.Matrix([V]).jacobian(q).T
    return Model(q, M, christoffel(M, q, qd), g, chain.friction_forces(), V)


def stack(models: Sequence[Model], order: Sequence[sp.Symbol]) -> Model:
    """Join chain models into one block-diagonal model with its coordinates in ``order`` (eq. 21)."""
    coords = [q for m in models for q in m.coordinates]
    if sorted(coords, key=sp.default_sort_key) != sorted(order, key=sp.default_sort_key) or len(set(coords)) != len(
        coords
    ):
        raise ValueError(f"the chains' coordinates {coords} are not a permutation of {list(order)}")
    index = {q: k for k, q in enumerate(order)}
    n = len(order)
    M, C, g, f = sp.zeros(n, n), sp.zeros(n, n), sp.zeros(n, 1), sp.zeros(n, 1)
    for m in models:
        rows = [index[q] for q in m.coordinates]
        for a, ra in enumerate(rows):
            g[ra] = m.g[a]
            f[ra] = m.f[a]
            for b, rb in enumerate(rows):
                M[ra, rb] = m.M[a, b]
                C[ra, rb] = m.C[a, b]
    return Model(tuple(order), M, C, g, f, sum((m.potential for m in models), sp.Integer(0)))


def project(model: Model, z: Sequence[sp.Symbol], psi: sp.Matrix, psi_dot: sp.Matrix) -> Model:
    """The model in the independent coordinates z, with q_dot = Psi z_dot (eqs. 24-29, Psi_dot kept).

    ``psi`` and ``psi_dot`` may use the coordinates q and the independent rates z_dot; the model's
    rates q_dot are replaced by Psi z_dot.
    """
    zd = sp.Matrix([rate(s) for s in z])
    qd = psi * zd
    on_loop = dict(zip(model.rates(), qd, strict=True))
    C = model.C.xreplace(on_loop)
    f = model.f.xreplace(on_loop)
    return Model(
        tuple(z),
        psi.T * model.M * psi,
        psi.T * (model.M * psi_dot + C * psi),
        psi.T * model.g,
        psi.T * f,
        model.potential,
        tuple(q for q in model.coordinates if q not in set(z)),
    )
