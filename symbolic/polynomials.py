"""Polynomials as coefficient lists (highest degree first) of sympy expressions: products and sums
built without expanding the coefficients, for the forward-kinematics polynomials of the mechanisms."""

from __future__ import annotations

from collections.abc import Sequence

import sympy as sp


def multiply(p: Sequence[sp.Expr], q: Sequence[sp.Expr]) -> list[sp.Expr]:
    """Coefficients of the product of two polynomials."""
    out = [sp.Integer(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return out


def combine(p: Sequence[sp.Expr], q: Sequence[sp.Expr], factor: sp.Expr = 1) -> list[sp.Expr]:
    """Coefficients of p + factor q, the shorter list padded at the high-degree end."""
    n = max(len(p), len(q))
    p = [sp.Integer(0)] * (n - len(p)) + list(p)
    q = [sp.Integer(0)] * (n - len(q)) + list(q)
    return [a + factor * b for a, b in zip(p, q, strict=True)]


def subtract(p: Sequence[sp.Expr], q: Sequence[sp.Expr]) -> list[sp.Expr]:
    """Coefficients of p - q."""
    return combine(p, q, -1)
