"""Rigorous enclosures of a CasADi SX graph over a box of its inputs: each instruction of the graph evaluated in ball
arithmetic (python-flint's ``arb``: every operation rounded outward, so that the ball it returns holds every value
the operation takes over its arguments' balls), for :mod:`pkm.certify`.

python-flint rather than an interval emitter of pkm's own: its arb balls are kept, documented and rigorous for every
elementary function the kinematic graphs use (sqrt, the trigonometric functions and their inverses, atan2, powers),
which a home-made emitter would have to prove again. The graph is walked once into a list of steps
(:func:`enclosure`); comparisons give 0, 1 or the ball [0, 1] where the order is not decided over the box, a truth
is CasADi's (a nonzero value), a choice (``if_else``) the union of its branches where its condition is not decided,
a product of a value with itself its square (non-negative). A ball that is not finite (a square root of a ball
reaching below 0: a pose out of reach somewhere in the box; an infinity) decides nothing, and a minimum, a maximum
or an undecided choice with one is not finite either.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Sequence
from typing import Any

import casadi as ca

from pkm.errors import PkmError


def _flint() -> Any:
    try:
        import flint
    except ImportError as exc:
        raise PkmError("certification violates: python-flint installed (pip install python-flint), whose ball "
                       "arithmetic it runs on") from exc
    return flint


def ball(lower: float, upper: float) -> Any:
    """The ball holding [lower, upper] (the union of its ends' exact balls)."""
    arb = _flint().arb
    return arb(lower).union(arb(upper))


def span(lower: Any, upper: Any) -> Any:
    """The ball holding the balls ``lower`` and ``upper`` and every value between."""
    return lower.union(upper)


def _ends(x: Any) -> tuple[Any, Any]:
    return x.lower(), x.upper()


def _truth(certain_true: bool, certain_false: bool) -> Any:
    arb = _flint().arb
    if certain_true:
        return arb(1)
    if certain_false:
        return arb(0)
    return ball(0.0, 1.0)


def _less(a: Any, b: Any, strict: bool) -> Any:
    return _truth(a < b if strict else a <= b, a >= b if strict else a > b)


def _undecided() -> Any:
    """A ball that decides nothing (not finite)."""
    return _flint().arb("nan")


def _truth_of(a: Any) -> Any:
    """CasADi's truth of a value (nonzero), as 0, 1 or [0, 1]."""
    return _truth(a != 0, a == 0)


def _choice(condition: Any, value: Any) -> Any:
    """if_else_zero: ``value`` where the condition (a nonzero value) holds, else 0; their union where the box does
    not decide it, and nothing decided where that union holds a value that is not finite."""
    arb = _flint().arb
    truth = _truth_of(condition)
    if truth > 0.5:
        return value
    if truth < 0.5:
        return arb(0)
    return span(value, arb(0)) if value.is_finite() else _undecided()


def _extreme(a: Any, b: Any, least: bool) -> Any:
    """The least (or the largest) of two balls' values: from their ends; nothing decided where either is not
    finite."""
    if not (a.is_finite() and b.is_finite()):
        return _undecided()
    pick = (lambda u, v: u if u < v else v) if least else (lambda u, v: u if u > v else v)
    return span(pick(a.lower(), b.lower()), pick(a.upper(), b.upper()))


def _minimum(a: Any, b: Any) -> Any:
    return _extreme(a, b, True)


def _maximum(a: Any, b: Any) -> Any:
    return _extreme(a, b, False)


def _sign(a: Any) -> Any:
    """-1, 0 or 1 where the box decides it (0 only for an exact 0), else [-1, 1]."""
    arb = _flint().arb
    if a > 0:
        return arb(1)
    if a < 0:
        return arb(-1)
    if a == 0:
        return arb(0)
    return ball(-1.0, 1.0)


def _copysign(a: Any, b: Any) -> Any:
    """|a| with b's sign, or both where the box does not decide it (b's ball holds 0: its sign unknown)."""
    if b > 0:
        return abs(a)
    if b < 0:
        return -abs(a)
    return span(-abs(a), abs(a))


def _square(a: Any) -> Any:
    """a^2 from |a|'s ends: non-negative, and finite where a is."""
    if not a.is_finite():
        return _undecided()
    return span(a.abs_lower() ** 2, a.abs_upper() ** 2)


def _operations() -> dict[int, Callable[..., Any]]:
    arb = _flint().arb
    return {
        ca.OP_ASSIGN: lambda a: a, ca.OP_ADD: operator.add, ca.OP_SUB: operator.sub, ca.OP_MUL: operator.mul,
        ca.OP_DIV: operator.truediv, ca.OP_NEG: operator.neg, ca.OP_EXP: arb.exp, ca.OP_LOG: arb.log,
        ca.OP_POW: operator.pow, ca.OP_CONSTPOW: operator.pow, ca.OP_SQRT: arb.sqrt, ca.OP_SQ: _square,
        ca.OP_TWICE: lambda a: 2 * a, ca.OP_SIN: arb.sin, ca.OP_COS: arb.cos, ca.OP_TAN: arb.tan, ca.OP_ASIN: arb.asin,
        ca.OP_ACOS: arb.acos, ca.OP_ATAN: arb.atan, ca.OP_ATAN2: arb.atan2, ca.OP_SINH: arb.sinh, ca.OP_COSH: arb.cosh,
        ca.OP_TANH: arb.tanh,
        ca.OP_LT: lambda a, b: _less(a, b, True), ca.OP_LE: lambda a, b: _less(a, b, False),
        ca.OP_EQ: lambda a, b: _truth(a == b, a != b), ca.OP_NE: lambda a, b: _truth(a != b, a == b),
        ca.OP_NOT: lambda a: 1 - _truth_of(a), ca.OP_AND: lambda a, b: _minimum(_truth_of(a), _truth_of(b)),
        ca.OP_OR: lambda a, b: _maximum(_truth_of(a), _truth_of(b)),
        ca.OP_FABS: abs, ca.OP_SIGN: _sign, ca.OP_IF_ELSE_ZERO: _choice, ca.OP_FMIN: _minimum,
        ca.OP_FMAX: _maximum, ca.OP_INV: lambda a: 1 / a, ca.OP_HYPOT: lambda a, b: (_square(a) + _square(b)).sqrt(),
        ca.OP_COPYSIGN: _copysign,
    }


def enclosure(fn: ca.Function) -> Callable[[Sequence[Sequence[Any]]], list[list[Any]]]:
    """The enclosure of an SX function: called with one list of balls per input (its nonzeros), it gives one list
    of balls per output holding every value the function takes over them."""
    if not fn.is_a("SXFunction"):
        raise PkmError(f"certification violates: an SX graph; {fn.name()} is not one")
    operations = _operations()
    arb = _flint().arb
    # every value in a register of its own, so that the constants and the inputs are placed before the first step
    fn = ca.Function(fn.name(), fn.sx_in(), fn.call(fn.sx_in()), {"live_variables": False})
    size = 1
    constants, reads, writes, steps = [], [], [], []
    for k in range(fn.n_instructions()):
        op, ins, out = fn.instruction_id(k), fn.instruction_input(k), fn.instruction_output(k)
        if op != ca.OP_OUTPUT:
            size = max(size, out[0] + 1)
        if op == ca.OP_CONST:
            constants.append((out[0], arb(float(fn.instruction_constant(k)))))
        elif op == ca.OP_INPUT:
            reads.append((out[0], ins[0], ins[1]))
        elif op == ca.OP_OUTPUT:
            writes.append((out[0], out[1], ins[0]))
        elif op == ca.OP_MUL and ins[0] == ins[1]:  # a square: one ball, not two independent ones
            steps.append((_square, ins[0], -1, out[0]))
        elif op in operations:
            steps.append((operations[op], ins[0], ins[1] if op in _BINARY else -1, out[0]))
        else:
            raise PkmError(f"certification violates: operations ball arithmetic encloses; {fn.name()} holds "
                           f"CasADi's operation {op}")
    template: list[Any] = [None] * size
    for at, value in constants:
        template[at] = value
    shapes = [fn.nnz_out(i) for i in range(fn.n_out())]

    def evaluate(inputs: Sequence[Sequence[Any]]) -> list[list[Any]]:
        work = list(template)
        for at, port, entry in reads:
            work[at] = inputs[port][entry]
        for function, a, b, at in steps:
            work[at] = function(work[a], work[b]) if b >= 0 else function(work[a])
        outputs = [[arb(0)] * n for n in shapes]
        for port, entry, at in writes:
            outputs[port][entry] = work[at]
        return outputs

    return evaluate


_BINARY = {ca.OP_ADD, ca.OP_SUB, ca.OP_MUL, ca.OP_DIV, ca.OP_POW, ca.OP_CONSTPOW, ca.OP_ATAN2, ca.OP_LT, ca.OP_LE,
           ca.OP_EQ, ca.OP_NE, ca.OP_AND, ca.OP_OR, ca.OP_IF_ELSE_ZERO, ca.OP_FMIN, ca.OP_FMAX, ca.OP_HYPOT,
           ca.OP_COPYSIGN}
