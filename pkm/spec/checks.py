"""The checks of a description's fields that the schema's parts share (:mod:`pkm.spec.schema`,
:mod:`pkm.spec.elastic_schema`): each refuses a field with :class:`DescriptionError`, naming it and the violated
condition."""

from __future__ import annotations

import math
import reprlib
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from pkm import expressions
from pkm.errors import PkmError
from pkm.spec.vocabulary import IDENTIFIER_PATTERN, NAME_LENGTH, TEXT_LENGTH, Field

NOT_EXPRESSIONS = ("kind", "type", "branches", "actuated", "newton", "shape", "layers")  # a leg's fields of other data


class DescriptionError(PkmError):
    """A machine description that names an unknown field or violates a condition."""


def fail(field: str, condition: str) -> DescriptionError:
    return DescriptionError(f"description field {field} violates: {condition}")


def check_fields(table: Mapping[str, Any], fields: Sequence[Field], where: str, what: str) -> None:
    """A field of ``table`` that ``fields`` does not hold, or a required one that it lacks, refused by name."""
    names = [f.name for f in fields]
    extra = sorted(set(table) - set(names), key=str)
    if extra:
        raise fail(f"{where}.{extra[0]}" if where else str(extra[0]), f"a known field of {what} ({', '.join(names)})")
    for f in fields:
        if f.required and f.name not in table:
            raise fail(f"{where}.{f.name}" if where else f.name, f"given ({f.doc})")


def expression(field: str, given: Any, names: set[str]) -> expressions.Tree:
    """An expression of the parameters (and pi and :data:`pkm.expressions.FUNCTIONS`), as its tree."""
    if isinstance(given, bool) or not isinstance(given, int | float | str):
        raise fail(field, "a number or an expression of the parameters")
    if not isinstance(given, str):
        if not math.isfinite(given):
            raise fail(field, f"a finite number; got {given!r}")
        return float(given)
    try:
        tree = expressions.parse(given)
    except expressions.ExpressionError as exc:
        raise fail(field, f"{exc}; got {reprlib.repr(given)}") from None
    unknown = expressions.unknown_names(tree, names)
    if unknown:
        raise fail(field, f"an expression of the parameters ({', '.join(sorted(names))}); it names "
                           f"{reprlib.repr(unknown)}")
    return tree


def compose(field: str, template: str, names: set[str], **parts: expressions.Tree) -> expressions.Tree:
    """The tree of ``template`` with the trees ``parts`` put in for their names in braces."""
    return expression(field, template.format(**{k: f"({expressions.text(v)})" for k, v in parts.items()}), names)


def choice(field: str, value: Any, options: Sequence[str]) -> str:
    """``value`` where it is one of ``options`` (text), else :class:`DescriptionError` naming ``field``."""
    if not isinstance(value, str) or value not in options:
        raise fail(field, f"one of {', '.join(options)}; got {reprlib.repr(value)}")
    return value


def text(field: str, value: Any) -> str:
    """A text field (a doc, a unit): text of at most :data:`TEXT_LENGTH` characters."""
    if not isinstance(value, str) or len(value) > TEXT_LENGTH:
        raise fail(field, f"text of at most {TEXT_LENGTH} characters")
    return value


def identifier(name: Any) -> bool:
    """Whether ``name`` is a name a derived module's functions can carry (CasADi's rule): a letter, then letters,
    digits and single underscores, not ending in one."""
    return isinstance(name, str) and len(name) <= NAME_LENGTH and IDENTIFIER_PATTERN.fullmatch(name) is not None


def number(field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise fail(field, "a finite number")
    return float(value)


def trees(value: Any, field: str) -> list[tuple[str, Any]]:
    """Every expression of a normalised leg (or a part of one) with its field, its other data left out."""
    if value is None:
        return []
    if isinstance(value, Mapping):
        return [t for k, v in value.items() if k not in NOT_EXPRESSIONS for t in trees(v, f"{field}.{k}")]
    if isinstance(value, list) and not expressions.is_operation(value):
        return [t for j, v in enumerate(value) for t in trees(v, f"{field}[{j}]")]
    return [(field, value)]


DISTINCT = 1e-9  # relative: two of a plate's points this close are one vertex


def plate_corners(data: Mapping[str, Any], plate: str) -> list[list[Any]]:
    """A normalised description's plate's points (trees): its own where it states them, else each leg's attachment
    to it."""
    table = data["plates"][plate]
    return table["points"] if "points" in table else [leg[plate] for leg in data["legs"]]


def plate_order(points: np.ndarray) -> list[int]:
    """The vertices of a plate's polygon among its points (their first two coordinates, at the default design): in
    their angular order about their centre (anticlockwise), one per distinct point, none where the polygon goes
    straight on; points all on one line give the segment between the two farthest apart (a bar), whose inside in
    the plane is no area."""
    centre = np.mean(points, axis=0)
    order = sorted(range(len(points)), key=lambda k: math.atan2(*(points[k] - centre)[::-1]))
    distinct: list[int] = []
    for k in order:
        if all(np.linalg.norm(points[k] - points[j]) > DISTINCT * (1 + np.linalg.norm(points[k])) for j in distinct):
            distinct.append(k)
    if len(distinct) < 3:
        return distinct
    spread = points[distinct] - centre
    _, singular, rows = np.linalg.svd(spread)
    if singular[1] <= DISTINCT * singular[0]:  # on one line: its two ends
        along = spread @ rows[0]
        ends = sorted((distinct[int(np.argmin(along))], distinct[int(np.argmax(along))]))
        return [k for k in distinct if k in ends]
    kept = list(distinct)
    while len(kept) > 3:
        straight = [k for i, k in enumerate(kept) if _turn(points[kept[i - 1]], points[k],
                                                            points[kept[(i + 1) % len(kept)]]) == 0.0]
        if not straight:
            break
        kept.remove(straight[0])
    return kept


def _turn(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    """The turn at b from a to c: positive left, negative right, 0.0 where it goes straight on (within round-off
    of the edges' lengths)."""
    u, v = b - a, c - b
    cross = float(u[0] * v[1] - u[1] * v[0])
    return 0.0 if abs(cross) <= DISTINCT * np.linalg.norm(u) * np.linalg.norm(v) else cross


def convex(points: np.ndarray) -> bool:
    """Whether the polygon of ``points`` (in order, anticlockwise) is convex: no turn to the right."""
    m = len(points)
    return all(_turn(points[k], points[(k + 1) % m], points[(k + 2) % m]) >= 0 for k in range(m if m > 2 else 0))
