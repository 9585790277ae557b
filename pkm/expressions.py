"""Arithmetic expressions of named values as designers write them in files (a coordinate that follows a
design parameter, a frame size, a stroke that follows a link length), parsed into pkm's own tree and never
evaluated as Python.

The tree is plain data, JSON as it is: a number (a finite int or float), a name (a string: a parameter, or
``pi``), or a list ``[operator, operand, ...]`` with the operator one of ``+ - * / **`` (two operands), ``neg``
(one) or a function of :data:`FUNCTIONS` (its arguments). :func:`parse` accepts the numbers, names, those
operators (unary ``+`` dropped) and calls of those functions only, within :data:`LIMITS` (the text's length,
the tree's size and depth, a constant exponent's magnitude), and every constant part of an expression must
have a finite real value (``1/0``, ``1e999``, ``sqrt(-1)`` and ``10**10**8`` are refused). :func:`evaluate`
builds a value from a tree with the functions of a backend (numpy for numbers and arrays, CasADi for
symbols, sympy in the derivation, which reads the same trees), so that nothing a file holds reaches Python's
evaluator; :func:`text` prints a tree back.
"""

from __future__ import annotations

import ast
import math
import warnings
from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from pkm.errors import PkmError

BINARY = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
FUNCTIONS = ("cos", "sin", "tan", "sqrt", "asin", "acos", "atan")
CONSTANTS = {"pi": math.pi}
RESERVED = (*CONSTANTS, *FUNCTIONS, "neg")  # names a parameter may not take
LIMITS = {"characters": 1000, "nodes": 400, "depth": 40, "exponent": 64.0}


@dataclass(frozen=True)
class Backend:
    """What :func:`evaluate` builds a tree's value with: the functions of :data:`FUNCTIONS`, a number of the tree
    as a value, the constants by name, and a check of each operation's value (raising where it must not stand)."""

    functions: Mapping[str, Callable[..., Any]]
    number: Callable[[int | float], Any] = float
    constants: Mapping[str, Any] = field(default_factory=lambda: CONSTANTS)
    check: Callable[[str, list[Any], Any], None] | None = None


NUMPY = Backend({"cos": np.cos, "sin": np.sin, "tan": np.tan, "sqrt": np.sqrt, "asin": np.arcsin,
                 "acos": np.arccos, "atan": np.arctan}, number=np.float64)
CASADI = Backend({"cos": ca.cos, "sin": ca.sin, "tan": ca.tan, "sqrt": ca.sqrt, "asin": ca.asin, "acos": ca.acos,
                  "atan": ca.atan})

Tree = int | float | str | list


class ExpressionError(PkmError):
    """Text that is not an expression pkm reads: the reason, without the field (the caller names it)."""


def parse(text: str) -> Tree:
    """The tree of ``text``: :class:`ExpressionError` where it is not arithmetic of names, numbers and
    :data:`FUNCTIONS` within :data:`LIMITS`, or a constant part of it has no finite real value. A text's tree is
    kept (the last PARSED texts' trees; each call gets a copy of its own)."""
    if not isinstance(text, str):
        raise ExpressionError("text")
    return _copied(_parsed(text))


PARSED = 4096  # texts whose trees parse keeps


def _copied(tree: Tree) -> Tree:
    return [tree[0], *map(_copied, tree[1:])] if isinstance(tree, list) else tree


@lru_cache(maxsize=PARSED)
def _parsed(text: str) -> Tree:
    if len(text) > LIMITS["characters"]:
        raise ExpressionError(f"at most {LIMITS['characters']} characters (this has {len(text)})")
    try:
        node = ast.parse(text.strip(), mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise ExpressionError("arithmetic (numbers, names, + - * / **, and "
                              f"{', '.join(FUNCTIONS)}); it is not") from None
    count = [0]
    tree = _tree(node, 0, count)
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        _constant(tree)
    return tree


def _tree(node: ast.AST, depth: int, count: list[int]) -> Tree:
    count[0] += 1
    if count[0] > LIMITS["nodes"] or depth > LIMITS["depth"]:
        raise ExpressionError(f"at most {LIMITS['nodes']} terms nested at most {LIMITS['depth']} deep")
    if isinstance(node, ast.Constant):
        value = node.value
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ExpressionError(f"numbers and names only; {type(value).__name__} constants are not")
        if isinstance(value, int) and abs(value) < 2**53:
            return value
        number = float(value) if isinstance(value, float) or abs(value) < 2**1024 else math.inf
        if not math.isfinite(number):
            raise ExpressionError("finite numbers; a number beyond 1.8e308 is not")
        return number
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.UAdd | ast.USub):
        operand = _tree(node.operand, depth + 1, count)
        return operand if isinstance(node.op, ast.UAdd) else ["neg", operand]
    if isinstance(node, ast.BinOp) and type(node.op) in BINARY:
        return [BINARY[type(node.op)], _tree(node.left, depth + 1, count), _tree(node.right, depth + 1, count)]
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS:
        if node.keywords or len(node.args) != 1:
            raise ExpressionError(f"{node.func.id} of one argument")
        return [node.func.id, _tree(node.args[0], depth + 1, count)]
    if isinstance(node, ast.Call):
        raise ExpressionError(f"calls of {', '.join(FUNCTIONS)} only")
    raise ExpressionError(f"arithmetic (numbers, names, + - * / **, and {', '.join(FUNCTIONS)}); "
                          f"{type(node).__name__} is not")


def _constant(tree: Tree) -> float | None:
    """The value of a tree without names (None where it has names), every constant part checked finite and
    real, a constant exponent within the limit (numpy's warnings silenced by the caller)."""
    if isinstance(tree, int | float):
        return float(tree)
    if isinstance(tree, str):
        return CONSTANTS.get(tree)
    op, *operands = tree
    values = [_constant(t) for t in operands]
    if op == "**" and values[1] is not None and abs(values[1]) > LIMITS["exponent"]:
        raise ExpressionError(f"exponents of at most {LIMITS['exponent']:g} in magnitude; {values[1]:g} is not")
    if any(v is None for v in values):
        return None
    value = float(_apply(op, [np.float64(v) for v in values], NUMPY.functions))
    if not math.isfinite(value):
        raise ExpressionError(f"a finite real value in every constant part; {text(tree)} has none")
    return value


OPERATORS: dict[str, Callable[..., Any]] = {
    "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b, "/": lambda a, b: a / b,
    "**": lambda a, b: a**b, "neg": lambda a: -a,
}


def _apply(op: str, values: list[Any], functions: Mapping[str, Callable[..., Any]]) -> Any:
    return OPERATORS[op](*values) if op in OPERATORS else functions[op](*values)


def evaluate(tree: Tree, values: Mapping[str, Any], backend: Backend = NUMPY) -> Any:
    """The value of a tree, the one evaluator of descriptions, task files and exports: its names from ``values``
    (or the backend's constants), its numbers and functions the backend's (:data:`NUMPY` by default,
    :data:`CASADI` for symbols; sympy's in the derivation, :mod:`symbolic.described`), each operation's value
    checked where the backend checks. With numpy, numbers give numpy's results, overflow and division by zero
    included (inf or nan, no warning)."""
    if isinstance(tree, int | float):
        return backend.number(tree)
    if isinstance(tree, str):
        return values[tree] if tree in values else backend.constants[tree]
    op, *operands = tree
    args = [evaluate(t, values, backend) for t in operands]
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        value = _apply(op, args, backend.functions)
    if backend.check is not None:
        backend.check(op, args, value)
    return value


def function(tree: Tree) -> Callable[[Mapping[str, Any]], Any]:
    """The tree as a function of the values of its names: numpy's functions on numbers and arrays, CasADi's
    where a value is a CasADi symbol or expression."""

    def value(values: Mapping[str, Any]) -> Any:
        symbolic = any(isinstance(v, ca.SX | ca.MX | ca.DM) for v in values.values())
        return evaluate(tree, values, CASADI if symbolic else NUMPY)

    return value


def is_operation(value: Any) -> bool:
    """Whether ``value`` is a tree's operation ``[operator, operand, ...]`` rather than a list of trees."""
    return isinstance(value, list) and bool(value) and isinstance(value[0], str) and (
        value[0] in OPERATORS or value[0] in FUNCTIONS)


def names(tree: Tree) -> set[str]:
    """The names a tree reads, its constants included."""
    if isinstance(tree, str):
        return {tree}
    if isinstance(tree, list):
        return set().union(*(names(t) for t in tree[1:]))
    return set()


def unknown_names(tree: Tree, known: Collection[str]) -> list[str]:
    """The names the tree reads that are neither among ``known`` nor constants, sorted."""
    return sorted(names(tree) - set(known) - set(CONSTANTS))


PRECEDENCE = {"+": 1, "-": 1, "*": 2, "/": 2, "neg": 3, "**": 4}


def text(tree: Tree) -> str:
    """A tree printed as arithmetic that :func:`parse` reads back to the same tree."""
    return _text(tree, 0)


def _text(tree: Tree, outer: int) -> str:
    if isinstance(tree, str):
        return tree
    if isinstance(tree, int | float):
        number = repr(tree)
        return f"({number})" if tree < 0 and outer else number
    op, *operands = tree
    if op in FUNCTIONS:
        return f"{op}({_text(operands[0], 0)})"
    level = PRECEDENCE[op]
    if op == "neg":
        body = "-" + _text(operands[0], level + 1)
    elif op == "**":
        body = f"{_text(operands[0], level + 1)}**{_text(operands[1], level)}"
    else:
        body = f"{_text(operands[0], level)} {op} {_text(operands[1], level + 1)}"
    return f"({body})" if level < outer or (op == "neg" and outer) else body
