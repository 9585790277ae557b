"""Named design parameters with units, bounds and meanings, and their validation."""

from __future__ import annotations

import math
import reprlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from pkm import units
from pkm.errors import DesignError, PkmError

MAX_MAGNITUDE = 1e12  # of a design value in SI units: beyond it the models overflow, not the mechanism


@dataclass(frozen=True)
class Parameter:
    """One design parameter. Values must lie in (lower, upper), or [lower, upper) if ``closed_lower``.

    A parameter that is not ``required`` may be left out of a design: it then takes its default, or
    ``factor * design[name]`` when ``default_from = (name, factor)``.
    """

    name: str
    default: float
    lower: float
    upper: float
    unit: str
    doc: str
    closed_lower: bool = False
    required: bool = True
    default_from: tuple[str, float] | None = None

    def default_in(self, values: Mapping[str, Any]) -> Any:
        """The default of this parameter given the other values of a design (numbers or CasADi
        expressions)."""
        if self.default_from is None:
            return self.default
        name, factor = self.default_from
        return factor * values[name]

    def table(self) -> dict[str, Any]:
        """This parameter as a description's table (:mod:`pkm.spec.schema`), whose bounds are finite: an unbounded
        side 1000 times the default's magnitude (and one) beyond it."""
        reach = 1e3 * abs(self.default) + 1.0
        return {"name": self.name, "default": self.default,
                "lower": self.lower if math.isfinite(self.lower) else self.default - reach,
                "upper": self.upper if math.isfinite(self.upper) else self.default + reach,
                "unit": self.unit, "doc": self.doc}

    def check(self, value: float) -> None:
        if not math.isfinite(value):
            raise DesignError(f"design parameter {self.name} = {value} is not finite")
        if abs(value) > MAX_MAGNITUDE:
            raise DesignError(f"design parameter {self.name} = {value:g} {self.unit} violates |{self.name}| <= "
                              f"{MAX_MAGNITUDE:g}")
        low_ok = value >= self.lower if self.closed_lower else value > self.lower
        if not low_ok or not value < self.upper:
            left = "[" if self.closed_lower else "("
            raise DesignError(
                f"design parameter {self.name} = {value:g} {self.unit} violates "
                f"{self.name} in {left}{self.lower:g}, {self.upper:g})"
                + units.hint(value, self.unit, self.lower, self.upper)
            )


@dataclass(frozen=True)
class Condition:
    """A validity condition of a design: ``holds(values) > 0`` where it is satisfied."""

    text: str
    margin: Callable[[Mapping[str, float]], float]


class Design(Mapping[str, float]):
    """A complete, validated set of named design parameter values."""

    def __init__(self, parameters: Sequence[Parameter], values: Mapping[str, float]) -> None:
        self._names = tuple(p.name for p in parameters)
        self._values = {name: float(values[name]) for name in self._names}

    def __getitem__(self, name: str) -> float:
        return self._values[name]

    def __iter__(self):
        return iter(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __repr__(self) -> str:
        return "Design(" + ", ".join(f"{k}={v:.6g}" for k, v in self._values.items()) + ")"

    def vector(self) -> np.ndarray:
        """Values in the mechanism's parameter order."""
        return np.array([self._values[n] for n in self._names])


def stack_design(values: Sequence[Any]) -> Any:
    """Design vectors from per-parameter values in parameter order (floats, arrays or CasADi): a CasADi
    column where any value is symbolic, else a numpy array (..., n_p) of the values broadcast together."""
    if any(isinstance(v, ca.MX | ca.SX) for v in values):
        return ca.vertcat(*values)
    arrays = [np.asarray(v, dtype=float) for v in values]
    shape = np.broadcast_shapes(*(a.shape for a in arrays))
    return np.stack([np.broadcast_to(a, shape) for a in arrays], axis=-1)


def parse_design(text: str, what: str = "design", entry: str = "design parameter",
                 error: type[PkmError] = DesignError) -> dict[str, float]:
    """Parse ``"r1=1.2,r2=1.0"`` into a dict; raise ``error`` naming ``what`` (the text) or ``entry`` (one of
    its names) on malformed items."""
    if not isinstance(text, str):
        raise error(f"{what} text = {reprlib.repr(text)} violates: a string name=value,name=value,...")
    out: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in text.split(","))):
        name, sep, value = item.partition("=")
        if not sep:
            raise error(f"{what} item {reprlib.repr(item)} is not of the form name=value")
        name = name.strip()
        shown = name if name.isidentifier() else repr(name)
        if name in out:
            raise error(f"{entry} {shown} is given twice")
        try:
            out[name] = float(value)
        except ValueError:
            raise error(f"{entry} {shown} = {reprlib.repr(value)} is not a number") from None
    return out


def _number(parameter: Parameter, value: object) -> float:
    """A design value as a float; DesignError naming the parameter for what is not a real number."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise DesignError(f"design parameter {parameter.name} = {reprlib.repr(value)} violates: a real number")
    try:
        return float(value)
    except OverflowError:
        raise DesignError(f"design parameter {parameter.name} = an integer of {len(str(abs(value)))} digits "
                          f"violates |{parameter.name}| <= {MAX_MAGNITUDE:g}") from None


def design_mapping(parameters: Sequence[Parameter], values: Any) -> Mapping[str, Any] | None:
    """``values`` as a mapping by parameter name: a mapping or None as given, a sequence or array taken in
    parameter order; :class:`DesignError` for anything else or a sequence of the wrong length. The values
    themselves are checked by :func:`make_design`."""
    if values is None or isinstance(values, Mapping):
        return values
    names = [p.name for p in parameters]
    if isinstance(values, np.ndarray) and values.dtype == np.float64 and values.shape == (len(names),):
        return dict(zip(names, values.tolist(), strict=True))
    violated = DesignError(f"design = {reprlib.repr(values)} violates: a mapping name -> value, a sequence of "
                           f"{len(names)} values in parameter order ({', '.join(names)}), or None for the defaults")
    if isinstance(values, str | bytes | set | frozenset):
        raise violated
    try:
        array = np.asarray(values, dtype=object)
    except (TypeError, ValueError):
        raise violated from None
    if array.ndim == 0:
        raise violated
    flat = array.ravel()
    if flat.size != len(names):
        raise DesignError(f"a design vector needs {len(names)} values ({', '.join(names)}); got {flat.size}")
    return dict(zip(names, flat.tolist(), strict=True))


def completed(parameters: Sequence[Parameter], given: Mapping[str, Any]) -> dict[str, Any]:
    """Every parameter's value in order: those ``given`` (numbers or CasADi expressions), the others at their
    defaults, a default that follows another parameter (``default_from``) from that parameter's value in this
    design. Every path that completes a design (a design given by name, a design space's points, a task's
    synthesis) completes it here, so that one design is one machine whichever path made it."""
    full = dict(given)
    for p in parameters:
        if p.name not in full and p.default_from is None:
            full[p.name] = p.default
    for p in parameters:
        if p.name not in full:
            full[p.name] = p.default_in(full)
    return {p.name: full[p.name] for p in parameters}


def make_design(
    parameters: Sequence[Parameter],
    conditions: Sequence[Condition],
    values: Mapping[str, float] | None,
    *,
    partial: bool = False,
) -> Design:
    """Validate ``values`` (a mapping, or None for the defaults) into a :class:`Design`.

    Parameters that are not required may always be left out; with ``partial`` the required ones may
    be too. Left-out parameters take their defaults.
    """
    names = [p.name for p in parameters]
    given = {} if values is None else dict(values)
    extra = sorted((k for k in given if k not in names), key=repr)
    if extra:
        shown = ", ".join(k if isinstance(k, str) and k.isidentifier() and len(k) <= 64 else reprlib.repr(k)
                          for k in extra[:8]) + (", ..." if len(extra) > 8 else "")
        raise DesignError(f"unknown design parameter(s) {shown}; expected {', '.join(names)}")
    missing = [p.name for p in parameters if p.required and p.name not in given]
    if missing and values is not None and not partial:
        raise DesignError(f"missing design parameter(s) {', '.join(missing)}")
    full = completed(parameters, {p.name: _number(p, given[p.name]) for p in parameters if p.name in given})
    for p in parameters:
        p.check(full[p.name])
    for c in conditions:
        margin = float(c.margin(full))
        if not (math.isfinite(margin) and margin > 0):
            shown = ", ".join(f"{k}={v:g}" for k, v in full.items())
            raise DesignError(f"design ({shown}) cannot be assembled: violates {c.text}")
    return Design(parameters, full)
