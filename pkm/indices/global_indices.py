"""Global indices: a local index reduced over a region, with the sense in which it is better.

A global index is the region mean of its local index (Gao eqs. 6-7, Lara-Molina eq. 36, Wu eqs. 7 and
44), its standard deviation (Wu section 6.1), its minimum (Lara-Molina eq. 38) or maximum, or a region measure:
the area or volume of the points where the local index is defined; or its integral over the region (over a
trajectory, whose measure is time: an energy from a power), or the square root of its mean (``"rms"``: of a
local index that is a square, a root mean square). Each carries its sense: larger
(``"max"``) or smaller (``"min"``) is better.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pkm.errors import PkmError
from pkm.indices import local
from pkm.indices.local import LocalIndex

REDUCTIONS = ("mean", "std", "min", "max", "measure", "integral", "rms")
EXTREMES_REDUCE = ("min", "max")
SENSES = ("max", "min")


@dataclass(frozen=True)
class GlobalIndex:
    """A global index: its key, local index, meaning, reduction and sense; with ``per`` the reduction
    is divided by the mechanism's function of that name (design -> a size, e.g. a footprint area)."""

    name: str
    local: LocalIndex
    doc: str
    reduce: str = "mean"
    sense: str = "max"
    per: str | None = None

    def __post_init__(self) -> None:
        if self.reduce not in REDUCTIONS or self.sense not in SENSES:
            raise PkmError(f"global index {self.name}: reduce in {REDUCTIONS} and sense in {SENSES}")

    @property
    def unit(self) -> str:
        """The unit as a template: ``{pose}``, ``{actuator}``, ``{n}`` (the pose's dimension) and ``{volume}``
        (the product of the pose's units, a region's measure) are the mechanism's
        (:meth:`pkm.Mechanism.index_unit`)."""
        unit = "{volume}" if self.reduce == "measure" else self.local.unit
        return f"{unit} per {self.per}" if self.per is not None else unit

    def better(self, a: float, b: float) -> bool:
        """Whether ``a`` is strictly better than ``b`` in this index's sense (NaN is never better)."""
        if not np.isfinite(a):
            return False
        if not np.isfinite(b):
            return True
        return a > b if self.sense == "max" else a < b


def reduce_samples(values: np.ndarray, keep: np.ndarray, cell: float | np.ndarray, reduce: str) -> float:
    """The reduction of sampled values (n,) over the kept points, each of measure ``cell`` (one for all,
    or one per point)."""
    cells = np.broadcast_to(np.asarray(cell, dtype=float), np.shape(values))
    if reduce == "measure":
        return float(cells[keep].sum())
    if not keep.any():
        return float("nan")
    kept, w = values[keep], cells[keep]
    if reduce in EXTREMES_REDUCE:
        return float(np.min(kept) if reduce == "min" else np.max(kept))
    mean = float(np.average(kept, weights=w))
    if reduce == "std":
        return float(np.sqrt(np.average((kept - mean) ** 2, weights=w)))
    if reduce == "integral":
        return float(np.sum(kept * w)) if keep.all() else float("nan")
    if reduce == "rms":
        return float(np.sqrt(mean))
    return mean


GLOBAL_INDICES: tuple[GlobalIndex, ...] = (
    GlobalIndex("gci", local.INVERSE_CONDITION_F, "global conditioning index eta (Gao eqs. 6-7)"),
    GlobalIndex("gci_2", local.INVERSE_CONDITION_2, "region mean of 1/kappa_2"),
    GlobalIndex("gamma_max", local.VELOCITY_MAX, "global maximum velocity index (Gao eqs. 23, 25)"),
    GlobalIndex("gamma_min", local.VELOCITY_MIN, "global minimum velocity index (Gao eqs. 24, 25)"),
    GlobalIndex("manipulability", local.MANIPULABILITY, "region mean of the manipulability |det J_f|"),
    GlobalIndex("jacobian_determinant", local.JACOBIAN_DETERMINANT, "region mean of |det J| (J: output to actuator "
                "rates)", sense="min"),
    GlobalIndex(
        "dynamic_dexterity", local.DYNAMIC_DEXTERITY,
        "global dynamic dexterity: region mean of 1/kappa_2(M_w) (Lara-Molina eq. 36)",
    ),
    GlobalIndex(
        "lambda_e", local.NATURAL_FREQUENCY,
        "elastodynamic index: region minimum of the smallest non-zero natural frequency (Lara-Molina eq. 38)",
        "min",
    ),
    GlobalIndex("k_av", local.VELOCITY_RATIO, "global velocity output ratio: region mean of k_v (Wu eq. 7)"),
    GlobalIndex("kappa_d_mean", local.KAPPA_D, "region mean of kappa_D (Wu eq. 44)", sense="min"),
    GlobalIndex(
        "kappa_d_std", local.KAPPA_D, "region standard deviation of kappa_D (Wu section 6.1)", "std", "min"
    ),
    GlobalIndex(
        "actuator_force_max", local.ACTUATOR_FORCE, "region maximum of the largest actuator force under the load",
        "max", "min",
    ),
    GlobalIndex("stiffness_min_mean", local.STIFFNESS_MIN, "region mean of the least translational stiffness"),
    GlobalIndex("stiffness_min_min", local.STIFFNESS_MIN, "region minimum of the least translational stiffness: "
                "the softest pose's", "min"),
    GlobalIndex("stiffness_isotropy_mean", local.STIFFNESS_ISOTROPY, "region mean of the stiffness's isotropy"),
    GlobalIndex("elastic_frequency_min", local.ELASTIC_FREQUENCY, "region minimum of the lowest natural frequency of "
                "the platform on the elastic structure", "min"),
    GlobalIndex("collision_margin_min", local.COLLISION_MARGIN, "region minimum of the collision margin: >= 0 "
                "where no two legs touch anywhere in the region", "min"),
    GlobalIndex(
        "workspace_margin_min", local.WORKSPACE_MARGIN,
        "region minimum of the least workspace-constraint margin: >= 0 where the region lies in the workspace",
        "min",
    ),
    GlobalIndex(
        "region_measure", local.INVERSE_CONDITION_F,
        "area (2-D) or volume (3-D) of the region's poses that the working mode reaches (over the sampled "
        "workspace: also at least the singularity margin from singularity)",
        "measure",
    ),
    GlobalIndex(
        "space_utilization", local.INVERSE_CONDITION_F,
        "area (2-D) or volume (3-D) of the region's reached poses per the mechanism's footprint (its function "
        "footprint: design -> the size the mechanism occupies)",
        "measure", per="footprint",
    ),
)
