"""Units on the command line: lengths and angles given and printed in the user's units (``--units mm,deg``),
SI everywhere else (the API, JSON, CSV, npz)."""

from __future__ import annotations

import math
import reprlib
from collections.abc import Sequence
from dataclasses import dataclass

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

    def to_si(self, values: np.ndarray, units: Sequence[str]) -> np.ndarray:
        return np.asarray(values, dtype=float) * np.array([self.scale(u) for u in units])

    def from_si(self, values: np.ndarray, units: Sequence[str]) -> np.ndarray:
        return np.asarray(values, dtype=float) / np.array([self.scale(u) for u in units])


def hint(value: float, unit: str, lower: float, upper: float) -> str:
    """Where a value out of its bounds lies within them read in mm (a length) or in degrees (an angle): the
    suggestion, else nothing."""
    for scale, given, si in ((LENGTHS["mm"], "mm", "m"), (ANGLES["deg"], "deg", "rad")):
        if unit == si and lower <= value * scale <= upper:
            return f" (given in {given}? {value:g} {given} = {value * scale:g} {si}: give {si}, or --units {given})"
    return ""
