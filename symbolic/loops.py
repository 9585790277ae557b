"""Closed-loop constraints and their first-order kinematics by implicit differentiation.

A closed-loop mechanism is described by loop-closure equations ``h(q_a, q_p, x) = 0`` in the actuated
joints ``q_a``, the passive joints ``q_p`` and the output (platform) coordinates ``x``, with as many
equations as passive joints plus outputs. Differentiating in time,

    H_a q_a_dot + H_p q_p_dot + H_x x_dot = 0,      H_* = dh/d*,

gives every first-order map of the mechanism:

* inverse kinematics (x given):   [H_a H_p] (q_a_dot, q_p_dot) = -H_x x_dot
* forward kinematics (q_a given): [H_p H_x] (q_p_dot, x_dot) = -H_a q_a_dot

Differentiating once more gives the velocity-product terms: with Phi = d(q_a, q_p)/dx,
q_ddot = Phi x_ddot + Phi_dot x_dot, and with Psi = d(q_a, q_p)/dq_a, q_ddot = Psi q_a_ddot + Psi_dot q_a_dot,
where Phi_dot and Psi_dot are the total time derivatives along the loop.

The determinants of the two square matrices are the type I (serial, ``det [H_a H_p] = 0``) and type II
(parallel, ``det [H_p H_x] = 0``) singularity measures of Gosselin and Angeles.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import sympy as sp


@dataclass(frozen=True)
class LoopClosure:
    """Loop-closure equations and the joint and output coordinates they relate.

    Parameters
    ----------
    h : sympy.Matrix, shape (n_p + n_x, 1)
        Residuals, zero on every assembled configuration.
    q_a, q_p, x : sequences of sympy.Symbol
        Actuated joints (n_a = n_x for a non-redundant mechanism), passive joints, outputs.
    """

    h: sp.Matrix
    q_a: tuple[sp.Symbol, ...]
    q_p: tuple[sp.Symbol, ...]
    x: tuple[sp.Symbol, ...]

    @classmethod
    def of(
        cls, h: Sequence[sp.Expr], q_a: Sequence[sp.Symbol], q_p: Sequence[sp.Symbol], x: Sequence[sp.Symbol]
    ) -> LoopClosure:
        loop = cls(sp.Matrix(h), tuple(q_a), tuple(q_p), tuple(x))
        if loop.h.rows != len(loop.q_p) + len(loop.x):
            raise ValueError(
                f"{loop.h.rows} loop equations for {len(loop.q_p)} passive joints and {len(loop.x)} outputs"
            )
        return loop

    @cached_property
    def H_a(self) -> sp.Matrix:
        return self.h.jacobian(self.q_a)

    @cached_property
    def H_p(self) -> sp.Matrix:
        if not self.q_p:
            return sp.zeros(self.h.rows, 0)
        return self.h.jacobian(self.q_p)

    @cached_property
    def H_x(self) -> sp.Matrix:
        return self.h.jacobian(self.x)

    @cached_property
    def _inverse_map(self) -> sp.Matrix:
        """d(q_a, q_p)/dx, shape (n_a + n_p, n_x)."""
        return _solve(self.H_a.row_join(self.H_p), -self.H_x)

    @cached_property
    def _forward_map(self) -> sp.Matrix:
        """d(q_p, x)/dq_a, shape (n_p + n_x, n_a)."""
        return _solve(self.H_p.row_join(self.H_x), -self.H_a)

    def inverse_map(self) -> sp.Matrix:
        """Phi = d(q_a, q_p)/dx: all joint rates from the output velocity; shape (n_a + n_p, n_x)."""
        return self._inverse_map

    def jacobian(self) -> sp.Matrix:
        """J with q_a_dot = J x_dot (the inverse-kinematic Jacobian), shape (n_a, n_x)."""
        return self._inverse_map[: len(self.q_a), :]

    def forward_jacobian(self) -> sp.Matrix:
        """J_f with x_dot = J_f q_a_dot, the inverse of :meth:`jacobian`; shape (n_x, n_a)."""
        return self._forward_map[len(self.q_p) :, :]

    def psi(self) -> sp.Matrix:
        """Psi = d(q_a, q_p)/d q_a: all joint rates from the actuated rates; shape (n_a + n_p, n_a)."""
        return sp.eye(len(self.q_a)).col_join(self._forward_map[: len(self.q_p), :])

    def _along_loop(self, A: sp.Matrix, rates: sp.Matrix) -> sp.Matrix:
        """Total time derivative of A(q_a, q_p, x) given the rates (q_a, q_p, x)_dot."""
        coords = (*self.q_a, *self.q_p, *self.x)
        out = sp.zeros(*A.shape)
        for c, r in zip(coords, rates, strict=True):
            out += A.diff(c) * r
        return out

    def psi_dot(self, q_a_dot: Sequence[sp.Symbol]) -> sp.Matrix:
        """Psi_dot: the time derivative of :meth:`psi` at actuated rates ``q_a_dot``; shape (n_a + n_p, n_a)."""
        qa_dot = sp.Matrix(q_a_dot)
        rates = self.psi().col_join(self.forward_jacobian()) * qa_dot
        return self._along_loop(self.psi(), rates)

    def inverse_second_order(self, x_dot: Sequence[sp.Symbol]) -> tuple[sp.Matrix, sp.Matrix]:
        """All joint rates Phi x_dot and the velocity-product accelerations Phi_dot x_dot.

        Joint accelerations are Phi x_ddot + Phi_dot x_dot, with Phi = d(q_a, q_p)/dx.
        """
        xd = sp.Matrix(x_dot)
        q_dot = self._inverse_map * xd
        bias = self._along_loop(self._inverse_map, q_dot.col_join(xd)) * xd
        return q_dot, bias

    def det_type1(self) -> sp.Expr:
        """det [H_a H_p]: zero on serial (type I) singularities, where J is unbounded."""
        return _det(self.H_a.row_join(self.H_p))

    def det_type2(self) -> sp.Expr:
        """det [H_p H_x]: zero on parallel (type II) singularities, where J is rank deficient."""
        return _det(self.H_p.row_join(self.H_x))


def _solve(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """A^-1 B by fraction-free elimination, each entry cancelled to a single fraction."""
    X = A.LUsolve(B)
    return X.applyfunc(lambda e: sp.factor_terms(sp.cancel(sp.together(e))))


def _det(A: sp.Matrix) -> sp.Expr:
    return sp.factor_terms(A.det(method="berkowitz").expand())
