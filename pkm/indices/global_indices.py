"""Global indices: a local index reduced over a region, with the sense in which it is better.

A global index is the region mean of its local index (Gao eqs. 6-7, Lara-Molina eq. 36, Wu eqs. 7 and
44), its standard deviation (Wu section 6.1), its minimum (Lara-Molina eq. 38), or a region measure:
the area or volume of the points where the local index is defined. Each carries its sense: larger
(``"max"``) or smaller (``"min"``) is better.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from pkm.errors import PkmError
from pkm.indices.local import LOCAL_INDICES, LocalIndex

REDUCTIONS = ("mean", "std", "min", "measure")
SENSES = ("max", "min")


@dataclass(frozen=True)
class GlobalIndex:
    """A global index: its key, local index, meaning, reduction and sense."""

    name: str
    local: LocalIndex
    doc: str
    reduce: str = "mean"
    sense: str = "max"

    def __post_init__(self) -> None:
        if self.reduce not in REDUCTIONS or self.sense not in SENSES:
            raise PkmError(f"global index {self.name}: reduce in {REDUCTIONS} and sense in {SENSES}")

    @property
    def unit(self) -> str:
        return "pose units^n" if self.reduce == "measure" else self.local.unit

    def better(self, a: float, b: float) -> bool:
        """Whether ``a`` is strictly better than ``b`` in this index's sense (NaN is never better)."""
        if not np.isfinite(a):
            return False
        if not np.isfinite(b):
            return True
        return a > b if self.sense == "max" else a < b


def reduce_nodes(values: ca.MX, weights: ca.MX | np.ndarray, reduce: str) -> ca.MX:
    """The weighted mean, standard deviation, minimum or measure (sum of weights) of a 1 x n row of
    node values with absolute weights (area or volume elements); numpy weights or CasADi."""
    w = ca.DM(np.reshape(weights, (-1, 1))) if isinstance(weights, np.ndarray) else ca.vec(weights)
    total = ca.sum1(w)
    if reduce == "measure":
        return total
    if reduce == "min":
        return ca.mmin(values)
    mean = ca.mtimes(values, w) / total
    if reduce == "std":
        return ca.sqrt(ca.mtimes((values - mean) ** 2, w) / total)
    return mean


def reduce_samples(values: np.ndarray, keep: np.ndarray, cell: float, reduce: str) -> float:
    """The reduction of sampled values (n,) over the kept points, each of measure ``cell``."""
    if not keep.any():
        return float("nan")
    kept = values[keep]
    if reduce == "measure":
        return float(keep.sum() * cell)
    return float({"min": np.min, "std": np.std}.get(reduce, np.mean)(kept))


def _local(name: str) -> LocalIndex:
    return next(i for i in LOCAL_INDICES if i.name == name)


GLOBAL_INDICES: tuple[GlobalIndex, ...] = (
    GlobalIndex("gci", _local("inverse_condition_f"), "global conditioning index eta (Gao eqs. 6-7)"),
    GlobalIndex("gci_2", _local("inverse_condition_2"), "region mean of 1/kappa_2"),
    GlobalIndex("gamma_max", _local("velocity_max"), "global maximum velocity index (Gao eqs. 23, 25)"),
    GlobalIndex("gamma_min", _local("velocity_min"), "global minimum velocity index (Gao eqs. 24, 25)"),
    GlobalIndex("manipulability", _local("manipulability"), "region mean of the manipulability |det J_f|"),
    GlobalIndex(
        "dynamic_dexterity", _local("dynamic_dexterity"),
        "global dynamic dexterity: region mean of 1/kappa_2(M_w) (Lara-Molina eq. 36)",
    ),
    GlobalIndex(
        "lambda_e", _local("natural_frequency"),
        "elastodynamic index: region minimum of the smallest non-zero natural frequency (Lara-Molina eq. 38)",
        "min",
    ),
    GlobalIndex("k_av", _local("velocity_ratio"), "global velocity output ratio: region mean of k_v (Wu eq. 7)"),
    GlobalIndex("kappa_d_mean", _local("kappa_d"), "region mean of kappa_D (Wu eq. 44)", sense="min"),
    GlobalIndex(
        "kappa_d_std", _local("kappa_d"), "region standard deviation of kappa_D (Wu section 6.1)", "std", "min"
    ),
    GlobalIndex(
        "region_measure", _local("inverse_condition_f"),
        "area (2-D) or volume (3-D) of the region's poses where the mechanism is reachable and regular",
        "measure",
    ),
)
