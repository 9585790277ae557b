"""Normalised (non-dimensional) design spaces and their planar charts (DESIGN.md section 3).

A design space maps normalised link lengths (and a length scale L in metres) to a mechanism's SI
design, and a planar chart maps the normalised lengths to two coordinates for atlases and for
synthesis. The maps use arithmetic only, so they accept floats, numpy arrays and CasADi expressions.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.design import Condition, Parameter, completed, stack_design
from pkm.errors import DesignError

CLOSED = 1e-12
SUM_TOLERANCE = 1e-9


def interval(name: str, lower: float, upper: float, *, closed: bool = False, source: str = "") -> tuple[Condition, ...]:
    """Conditions lower < name < upper (both ends closed with ``closed``) on normalised coordinates."""
    slack = CLOSED if closed else 0.0
    text = f"{lower:g} {'<=' if closed else '<'} {name} {'<=' if closed else '<'} {upper:g}{source}"
    return (
        Condition(text, lambda c: c[name] - lower + slack),
        Condition(text, lambda c: upper - c[name] + slack),
    )


def fixed_sum(weights: Mapping[str, float], total: float, *, source: str = "") -> Condition:
    """The condition sum(weight * coordinate) = total (to SUM_TOLERANCE)."""
    text = " + ".join(f"{w:g} {n}" if w != 1 else n for n, w in weights.items()) + f" = {total:g}{source}"
    return Condition(text, lambda c: SUM_TOLERANCE - abs(sum(w * c[n] for n, w in weights.items()) - total))


@dataclass(frozen=True)
class Requirement:
    """What an admissible design of a space satisfies beyond the space's own conditions, so that atlases
    and syntheses admit the same designs: lower <= value(c, call) <= upper, with c the normalised
    coordinates by name and ``call(function, output)`` an output of the mechanism's generated design
    function at the design (numpy arrays over a batch of designs, or CasADi expressions)."""

    name: str
    value: Callable[[Mapping[str, Any], Callable[[str, str], Any]], Any]
    lower: float = 0.0
    upper: float = math.inf


def within_bounds(space_bounds: Sequence[tuple[float, float]], coordinates: Sequence[str], inset: float,
                  unit: str) -> tuple[Requirement, ...]:
    """Each normalised coordinate at least ``inset`` inside its bounds (a link of length zero, or a base
    as long as the reach, is a degenerate design)."""
    return tuple(
        Requirement(f"{c} within ({lo:g} + {inset:g}, {hi:g} - {inset:g}) [{unit}]",
                    lambda values, _call, c=c: values[c], lo + inset, hi - inset)
        for c, (lo, hi) in zip(coordinates, space_bounds, strict=True)
    )


@dataclass(frozen=True)
class DesignSpace:
    """A normalised design space with a planar chart.

    ``to_design(c, scale)`` and ``from_design(d) -> (c, scale)`` convert normalised coordinates c
    (last axis) to SI designs; ``to_chart(c)`` and ``from_chart(u, v)`` convert to and from the chart.
    ``chart_labels`` say what each chart axis is in the normalised coordinates and ``note`` what the
    coordinates are, for figures. ``polygon`` is the closure of the space in the chart (its vertices,
    counter-clockwise).
    ``parameters`` names the design parameters ``to_design`` returns, in its order; the others take
    the values of ``base`` (the paper's non-dimensional values) or the mechanism's defaults.
    ``conditions`` are the paper's constraints on the normalised coordinates (by name), ``bounds``
    their box (lower, upper) per coordinate, used as constraints by the synthesis. ``requirements`` say
    which designs of the space are admissible (:class:`Requirement`): an atlas reports its best among
    them and a synthesis over the space holds them as constraints.
    """

    name: str
    doc: str
    coordinates: tuple[str, ...]
    chart_axes: tuple[str, str]
    chart_labels: tuple[str, str]
    note: str
    to_design: Callable
    from_design: Callable
    to_chart: Callable
    from_chart: Callable
    polygon: tuple[tuple[float, float], ...]
    parameters: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...] = ()
    base: Mapping[str, float] = field(default_factory=dict)
    conditions: tuple[Condition, ...] = ()
    requirements: tuple[Requirement, ...] = ()

    def admissible(self, functions: Mapping[str, ca.Function], c: Sequence[np.ndarray], designs: np.ndarray
                   ) -> tuple[np.ndarray, list[str]]:
        """Which of the designs (D, n_p), with normalised coordinates c (one (D,) array per coordinate), meet
        every requirement, and the names of the requirements some design fails."""
        values = dict(zip(self.coordinates, (np.asarray(a, dtype=float) for a in c), strict=True))

        def call(function: str, output: str) -> np.ndarray:
            fn = functions[function]
            return evaluate(fn, designs)[fn.name_out().index(output)][:, 0, 0]

        ok = np.ones(len(designs), dtype=bool)
        failed = []
        for requirement in self.requirements:
            value = np.broadcast_to(requirement.value(values, call), ok.shape)
            with np.errstate(invalid="ignore"):
                meets = (value >= requirement.lower) & (value <= requirement.upper)
            if not meets.all():
                failed.append(requirement.name)
            ok &= meets
        return ok, failed

    def check(self, c: Sequence) -> None:
        """Raise :class:`DesignError` if normalised coordinates c (last axis) violate a condition."""
        arrays = [np.asarray(a, dtype=float) for a in c]
        values = dict(zip(self.coordinates, arrays, strict=True))
        for cond in self.conditions:
            margin = np.asarray(cond.margin(values))
            if not np.all(margin > 0):
                k = int(np.flatnonzero(~(margin.ravel() > 0))[0])
                shown = ", ".join(f"{n}={np.ravel(a)[k if np.size(a) > 1 else 0]:g}" for n, a in values.items())
                raise DesignError(f"{self.name} design ({shown}) violates {cond.text}")

    def designs(self, parameters: Sequence[Parameter], c: Sequence, scale=1.0, *, check: bool = True):
        """Complete design vectors from normalised coordinates c: an (..., n_p) array, or a CasADi
        column when c holds CasADi expressions (for synthesis)."""
        values = dict(zip(self.parameters, self.to_design(c, scale), strict=True))
        symbolic = any(isinstance(v, ca.MX | ca.SX) for v in values.values())
        if check and not symbolic:
            self.check(c)
        given = {**{n: v for n, v in self.base.items() if n in {p.name for p in parameters}}, **values}
        return stack_design(list(completed(parameters, given).values()))

    def normalised(self, design: Sequence[float]) -> dict[str, float]:
        """The normalised coordinates of an SI design vector, by name."""
        c, _ = self.from_design(np.asarray(design, dtype=float))
        return {n: float(v) for n, v in zip(self.coordinates, c, strict=True)}

    def chart_grid(self, resolution: int, *, inset: float = 1e-3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A regular chart grid: axes u (n,), v (n,) and a mask (n, n) of the nodes inside the space.

        Nodes closer than ``inset`` (chart units) to the boundary are left out: the boundary holds the
        degenerate designs (a zero length, or a base as long as the reach).
        """
        poly = np.array(self.polygon)
        u = np.linspace(poly[:, 0].min(), poly[:, 0].max(), resolution)
        v = np.linspace(poly[:, 1].min(), poly[:, 1].max(), resolution)
        U, V = np.meshgrid(u, v, indexing="ij")
        from matplotlib.path import Path as PolygonPath

        path = PolygonPath(poly)
        inside = path.contains_points(np.stack([U.ravel(), V.ravel()], 1), radius=-2 * inset)
        return u, v, inside.reshape(U.shape)


def parse_axes(text: str, what: str = "axes") -> list[tuple[str, float, float]]:
    """``"R=0.1:0.3,beta=0.2:1.2"`` -> [("R", 0.1, 0.3), ("beta", 0.2, 1.2)]; :class:`DesignError` naming ``what``
    (the option or field that gave the text) for an item of another form or a parameter given twice."""
    out = []
    for item in filter(None, (t.strip() for t in text.split(","))):
        name, sep, bounds = item.partition("=")
        lower, colon, upper = bounds.partition(":")
        try:
            if not (sep and colon):
                raise ValueError
            out.append((name.strip(), float(lower), float(upper)))
        except ValueError:
            raise DesignError(f"{what} item {reprlib.repr(item)} is not of the form name=lower:upper") from None
        if [name for name, *_ in out].count(out[-1][0]) > 1:
            raise DesignError(f"{what} {text} violates: each parameter once; {out[-1][0]} is given twice")
    return out


def parameter_plane(
    parameters: Sequence[Parameter], axes: Sequence[tuple[str, float, float]], *, name: str | None = None,
    base: Mapping[str, float] | None = None,
) -> DesignSpace:
    """A design space of two of a mechanism's parameters with bounds, charted as they are: for atlases
    over design variables of the user's choice. The other parameters keep the values of ``base`` (a design)
    or their defaults."""
    known = {p.name: p for p in parameters}
    if len(axes) != 2:
        raise DesignError(f"a parameter plane needs two axes; got {len(axes)}")
    if axes[0][0] == axes[1][0]:
        raise DesignError(f"axes {axes[0][0]}, {axes[1][0]} violate: two distinct design parameters")
    for axis, lower, upper in axes:
        if axis not in known:
            raise DesignError(f"unknown design parameter {reprlib.repr(axis)}; expected one of {', '.join(known)}")
        if not (np.isfinite(lower) and np.isfinite(upper) and lower < upper):
            raise DesignError(f"axis {axis}: bounds {lower:g}, {upper:g} violate lower < upper, both finite")
        p = known[axis]
        if lower < p.lower or upper > p.upper:
            raise DesignError(f"axis {axis}: bounds {lower:g}, {upper:g} violate: within the parameter's bounds "
                              f"[{p.lower:g}, {p.upper:g}]")
    (a, a_lo, a_hi), (b, b_lo, b_hi) = axes
    held = {k: float(v) for k, v in (base or {}).items() if k not in (a, b)}
    others = "at the given design" if held else "at their defaults"
    index = [list(known).index(a), list(known).index(b)]
    return DesignSpace(
        name=name or f"{a}-{b}",
        doc=f"{a} in [{a_lo:g}, {a_hi:g}] {known[a].unit}, {b} in [{b_lo:g}, {b_hi:g}] {known[b].unit}; "
        f"the other parameters {others}",
        coordinates=(a, b),
        chart_axes=(a, b),
        chart_labels=(f"{a} [{known[a].unit}]", f"{b} [{known[b].unit}]"),
        note=f"{known[a].doc}; {known[b].doc}" + (
            "; held: " + ", ".join(f"{k} = {v:.4g}" for k, v in held.items()) if held else ""),
        to_design=lambda c, _scale=1.0: [c[0], c[1]],
        from_design=lambda d: ([d[index[0]], d[index[1]]], 1.0),
        to_chart=lambda c: (c[0], c[1]),
        from_chart=lambda u, v: [u, v],
        polygon=((a_lo, b_lo), (a_hi, b_lo), (a_hi, b_hi), (a_lo, b_hi)),
        parameters=(a, b),
        bounds=((a_lo, a_hi), (b_lo, b_hi)),
        base=held,
    )
