"""Arithmetic expressions of named values as designers write them in files (a coordinate that follows a
design parameter, a frame size, a stroke that follows a link length): numbers, names, the operators and
calls of a few functions; no other Python is accepted, so evaluating one runs nothing else."""

from __future__ import annotations

import ast
from collections.abc import Collection

ALLOWED = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Constant, ast.Load, ast.operator,
           ast.unaryop)


def parse(text: str) -> ast.Expression | None:
    """The expression's tree, or None where ``text`` is not Python's syntax or uses more than arithmetic and
    calls."""
    try:
        tree = ast.parse(text, mode="eval")
    except SyntaxError:
        return None
    return tree if all(isinstance(n, ALLOWED) for n in ast.walk(tree)) else None


def unknown_names(tree: ast.Expression, names: Collection[str]) -> list[str]:
    """The names the expression reads that are not among ``names``, sorted."""
    return sorted({n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} - set(names))
