"""pkm's exceptions. Bad input raises a subclass of :class:`PkmError` (itself a ``ValueError``)."""

from __future__ import annotations

import math
import reprlib
from collections.abc import Sequence


class PkmError(ValueError):
    """Bad input to pkm: the message names the parameter and the violated condition."""


_PATHS = reprlib.Repr()
_PATHS.maxstring = 200


def shown_path(path: object) -> str:
    """A path quoted for an error line, shortened where it is longer than an ordinary path."""
    return _PATHS.repr(str(path))


class UnknownNameError(PkmError):
    """An unknown mechanism, index, region, mode, design space or problem, or a name that is not a string."""

    def __init__(self, kind: str, name: object, known: Sequence[str]) -> None:
        if isinstance(name, str):
            super().__init__(f"unknown {kind} {reprlib.repr(name)}; known: {', '.join(known)}")
        else:
            super().__init__(f"{kind} = {reprlib.repr(name)} violates: a name (a string); known: {', '.join(known)}")


def check_name(kind: str, name: object, known: Sequence[str]) -> str:
    """``name`` if it is a string; :class:`UnknownNameError` naming ``kind`` otherwise (a list or a dict
    given as a name would fail as unhashable in a lookup, an array as ambiguous in a comparison)."""
    if not isinstance(name, str):
        raise UnknownNameError(kind, name, known)
    return name


class DesignError(PkmError):
    """A design that is incomplete, non-finite, out of bounds or cannot be assembled."""


class PoseError(PkmError):
    """A pose out of reach (raised in strict mode; batches otherwise get NaN and a mask)."""


class SingularityError(PkmError):
    """A configuration at which the requested quantity does not exist (raised in strict mode)."""


class SingularityWarning(UserWarning):
    """A pose that pkm takes as a reference (a description's home pose) is singular."""


class ComputationError(RuntimeError):
    """A computation that failed on valid input (for instance IPOPT did not converge)."""


def check_integer(name: str, value: object, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int; :class:`PkmError` naming ``name`` unless it is an integer >= ``minimum`` (and
    <= ``maximum`` where one is given: a bound on the memory and time a call may take)."""
    condition = f"an integer >= {minimum}" + (f" and <= {maximum}" if maximum is not None else "")
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or (isinstance(value, float) and not math.isfinite(value))
        or int(value) != value
        or value < minimum
        or (maximum is not None and value > maximum)
    ):
        raise PkmError(f"{name} = {reprlib.repr(value)} violates: {condition}")
    return int(value)


def check_real(name: str, value: object, condition: str = "a finite number", error: type[PkmError] | None = None
               ) -> float:
    """``value`` as a finite float; :class:`PkmError` (or ``error``) naming ``name`` and ``condition`` for a
    string, None, a sequence, an integer too large for a float, or a value that is not finite."""
    try:
        number = float(value) if not isinstance(value, bool | str | bytes) else math.nan
    except (TypeError, ValueError, OverflowError):
        number = math.nan
    if not math.isfinite(number):
        raise (error or PkmError)(f"{name} = {reprlib.repr(value)} violates: {condition}")
    return number
