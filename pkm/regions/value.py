"""The value of a global index with what it rests on."""

from __future__ import annotations


class GlobalValue(float):
    """A global index value that also reports the region, the resolution, how many points it used and
    the accuracy reached: the change from the same rule at half the resolution (NaN when not estimated);
    ``converged`` is False where a refinement stopped at its largest resolution short of the accuracy asked,
    and ``note`` says what a caller should know of it (not converged and why, a one-sided gradient)."""

    points: int
    region: str
    resolution: int
    accuracy: float
    note: str = ""
    converged: bool = True

    def __new__(
        cls, value: float, *, points: int, region: str, resolution: int, accuracy: float = float("nan")
    ) -> GlobalValue:
        obj = super().__new__(cls, value)
        obj.points, obj.region, obj.resolution, obj.accuracy = points, region, resolution, float(accuracy)
        return obj

    def __repr__(self) -> str:
        accuracy = "" if self.accuracy != self.accuracy else f", accuracy {self.accuracy:.1e}"
        return (f"GlobalValue({float(self)!r} over {self.region}, resolution {self.resolution}, "
                f"{self.points} points{accuracy})")
