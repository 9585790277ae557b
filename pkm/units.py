"""Units on the command line: lengths and angles given and printed in the user's units (``--units mm,deg``),
SI everywhere else (the API, JSON, CSV, npz)."""

from __future__ import annotations

import math
import re
import reprlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from pkm.errors import PkmError

LENGTHS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}  # SI metres per unit
ANGLES = {"rad": 1.0, "deg": math.pi / 180}  # SI radians per unit


@dataclass(frozen=True)
class Units:
    """The user's unit of length and of angle; a quantity in another SI unit stays SI."""

    length: str = "m"
    angle: str = "rad"

    @classmethod
    def parse(cls, text: str | None) -> Units:
        """``"mm,deg"`` (either or both, in any order); SI for a missing one."""
        if not text:
            return cls()
        length, angle = "m", "rad"
        for item in filter(None, (t.strip() for t in text.split(","))):
            if item in LENGTHS:
                length = item
            elif item in ANGLES:
                angle = item
            else:
                raise PkmError(f"--units item {reprlib.repr(item)} violates: one of {', '.join([*LENGTHS, *ANGLES])}")
        return cls(length, angle)

    def scale(self, unit: str) -> float:
        """SI per user unit of a quantity whose SI unit is ``unit``."""
        return LENGTHS[self.length] if unit == "m" else ANGLES[self.angle] if unit == "rad" else 1.0

    def name(self, unit: str) -> str:
        """The user's name of a quantity's SI ``unit``."""
        return self.length if unit == "m" else self.angle if unit == "rad" else unit

    def convert(self, unit: str) -> tuple[float, str]:
        """SI per user unit of a quantity whose SI unit is ``unit``, a product and quotient of named units with
        integer powers and parentheses (``m/rad``, ``(m/rad)^2``, ``N m``, ``m^3``), and the unit's name in the
        user's units (metres and radians renamed; every other unit stays SI, and a unit pkm cannot read stays
        as it is, its factor 1)."""
        try:
            powers = _powers(unit)
        except ValueError:
            return 1.0, unit
        factor = LENGTHS[self.length] ** powers.get("m", 0) * ANGLES[self.angle] ** powers.get("rad", 0)
        name = re.sub(r"\brad\b", self.angle, re.sub(r"\bm\b", self.length, unit))
        return factor, name

    def value(self, value: float, unit: str) -> float:
        """A value of SI ``unit`` in the user's units."""
        return value / self.convert(unit)[0]

    def to_si(self, values: np.ndarray, units: Sequence[str]) -> np.ndarray:
        return np.asarray(values, dtype=float) * np.array([self.scale(u) for u in units])

    def from_si(self, values: np.ndarray, units: Sequence[str]) -> np.ndarray:
        return np.asarray(values, dtype=float) / np.array([self.scale(u) for u in units])


_TOKEN = re.compile(r"\s*(?:(?P<name>[A-Za-z]+)|(?P<power>\^-?\d+)|(?P<op>[()/*])|(?P<number>\d+))")


def _powers(unit: str) -> dict[str, int]:
    """The powers of the named units in a unit's text: ``(m/rad)^2`` -> {m: 2, rad: -2}; ``-`` and numbers (a
    ``1/s``'s 1) have none; ValueError where the text is not such a unit."""
    tokens = []
    position, text = 0, unit.strip()
    if text in ("", "-"):
        return {}
    while position < len(text):
        match = _TOKEN.match(text, position)
        if match is None or match.end() == position:
            raise ValueError(unit)
        tokens.append((match.lastgroup, match.group(match.lastgroup)))
        position = match.end()
    stack: list[dict[str, int]] = [{}]
    last: list[dict[str, int]] = [{}]
    sign = [1]
    for kind, token in tokens:
        if kind == "name":
            last[-1] = {token: 1}
            _add(stack[-1], last[-1], sign[-1])
        elif kind == "number":
            last[-1] = {}
        elif kind == "power":
            exponent = int(token[1:])
            _add(stack[-1], last[-1], sign[-1] * (exponent - 1))
            last[-1] = {k: v * exponent for k, v in last[-1].items()}
        elif token == "/":
            sign[-1] = -1
        elif token == "*":
            sign[-1] = 1
        elif token == "(":
            stack.append({})
            last.append({})
            sign.append(1)
        elif token == ")":
            if len(stack) == 1:
                raise ValueError(unit)
            inner = stack.pop()
            last.pop()
            sign.pop()
            last[-1] = inner
            _add(stack[-1], inner, sign[-1])
    if len(stack) != 1:
        raise ValueError(unit)
    return {k: v for k, v in stack[0].items() if v}


def _add(into: dict[str, int], powers: dict[str, int], times: int) -> None:
    for k, v in powers.items():
        into[k] = into.get(k, 0) + times * v


def hint(value: float, unit: str, lower: float, upper: float) -> str:
    """Where a value out of its bounds lies within them read in mm (a length) or in degrees (an angle): the
    suggestion, else nothing."""
    for scale, given, si in ((LENGTHS["mm"], "mm", "m"), (ANGLES["deg"], "deg", "rad")):
        if unit == si and lower <= value * scale <= upper:
            return f" (given in {given}? {value:g} {given} = {value * scale:g} {si}: give {si}, or --units {given})"
    return ""


def placement_in(mech: Any, region: Any, placed: dict[str, Any], units: Units) -> dict[str, Any]:
    """A region's placement (:meth:`pkm.Mechanism.region_placement`) in the user's units: its centre in the
    pose's and each size in the unit of the pose coordinate it extends along, with ``units`` naming both; a
    region mapped from coordinates of its own stays as it is."""
    if placed["mapped"]:
        return placed
    size = np.asarray(placed["size"], dtype=float)
    marks = np.asarray(mech.region(region).scale(ca.DM(np.arange(1.0, len(size) + 1))), dtype=float).ravel()
    along = [mech.pose_units[int(np.flatnonzero(marks == k + 1)[0])] for k in range(len(size))]
    return {**placed, "centre": units.from_si(placed["centre"], mech.pose_units).tolist(),
            "size": units.from_si(size, along).tolist(),
            "units": {"centre": [units.name(u) for u in mech.pose_units], "size": [units.name(u) for u in along]}}


def placement_text(placed: dict[str, Any]) -> str:
    """``disc at (0 mm, 1400 mm), size (250 mm)``: a placement with the units it is in."""
    names = placed.get("units", {})

    def listed(key: str) -> str:
        unit = names.get(key, [""] * len(placed[key]))
        return "(" + ", ".join(f"{v:.6g}{'' if not u or u == '-' else ' ' + u}" for v, u in
                               zip(placed[key], unit, strict=True)) + ")"

    return (f"{placed['shape']} at {listed('centre')}, size {listed('size')}"
            + (" (in its own coordinates)" if placed["mapped"] else ""))
