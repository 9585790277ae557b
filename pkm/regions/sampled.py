"""The sampled region ``reachable``: a working mode's workspace as an n-D grid with a mask.

The cell centres of a regular grid over the bounding box of the workspace are kept where the working
mode reaches them and at least ``singularity_margin`` away from singularity in 1/kappa_f. For atlases
and for checking; not differentiable in the design. The accuracy reported is the change of the
index from the grid of every other cell along each axis to the full grid.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from pkm.errors import PkmError, check_real
from pkm.indices import GlobalIndex, reduce_samples
from pkm.indices.local import INVERSE_CONDITION_F
from pkm.kinematics import Branch
from pkm.regions.pipeline import PipelineModel, evaluate_at
from pkm.regions.region import REACHABLE_WORKSPACE, SampledWorkspace
from pkm.regions.shapes import check_nodes, check_resolution, grid
from pkm.regions.value import GlobalValue

SAMPLED_RESOLUTION = 64
SINGULARITY_MARGIN = 0.01
DESIGNS_PER_BATCH = 32
CONDITION = INVERSE_CONDITION_F


class SampledModel(PipelineModel, Protocol):
    """What the sampled workspace reads of a mechanism beside the pipeline's: the box its grid covers."""

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """Bounding box ((lo, hi) per pose coordinate) of the reachable workspace, shape (n_out, 2)."""


def check_margin(singularity_margin: float) -> float:
    singularity_margin = check_real("singularity_margin", singularity_margin, "a number in [0, 1)")
    if not 0 <= singularity_margin < 1:
        raise PkmError(f"singularity_margin = {singularity_margin} violates 0 <= singularity_margin < 1")
    return float(singularity_margin)


def coarse_mask(resolution: int, dimension: int) -> np.ndarray:
    """The cells of a resolution^d grid with every index even: a grid of half the resolution."""
    index = np.indices((resolution,) * dimension).reshape(dimension, -1)
    return np.all(index % 2 == 0, axis=0)


def sample_values(
    mech: PipelineModel, spec: GlobalIndex, x: np.ndarray, d: np.ndarray, *, signs: np.ndarray, margin: float,
    assembled: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """The local index of ``spec`` at poses x (N, n) of designs d, and the mask of the poses kept:
    reachable (with ``assembled``, assembled whatever the stated limits), 1/kappa_f at least ``margin`` and
    the value finite."""
    locals_ = (spec.local,) if spec.local is CONDITION else (spec.local, CONDITION)
    result = evaluate_at(mech, locals_, x, signs, d, assembled=assembled)
    value = result.values[0]
    kappa = result.values[-1]
    with np.errstate(invalid="ignore"):
        keep = result.reachable & (kappa >= margin) & np.isfinite(value)
    return value, keep


def per_design(mech: PipelineModel, spec: GlobalIndex, design: np.ndarray) -> float:
    """The size an index's reduction is divided by (its ``per`` function of the design), else 1."""
    if spec.per is None:
        return 1.0
    return float(mech.functions.require(spec.per, f"the global index {spec.name}")(np.asarray(design, dtype=float)))


def sampled_global(
    mech: SampledModel,
    spec: GlobalIndex,
    designs: np.ndarray,
    branch: Branch,
    *,
    resolution: int | None = None,
    singularity_margin: float = SINGULARITY_MARGIN,
    progress: Callable[[int], object] | None = None,
    region: SampledWorkspace = REACHABLE_WORKSPACE,
) -> list[GlobalValue]:
    """Global index over the sampled workspace ``region`` (the reachable one by default) of each design
    (D, n_p), vectorised."""
    resolution = check_resolution(SAMPLED_RESOLUTION if resolution is None else resolution, 2)
    check_nodes(resolution, resolution**mech.n_out, f"the {mech.n_out}-D sampled workspace")
    margin = check_margin(singularity_margin)
    coarse = coarse_mask(resolution, mech.n_out)
    signs = np.array(branch.signs)
    out: list[GlobalValue] = []
    for start in range(0, len(designs), DESIGNS_PER_BATCH):
        chunk = designs[start : start + DESIGNS_PER_BATCH]
        grids = [grid(mech.workspace_box(d), resolution) for d in chunk]
        value, keep = sample_values(
            mech, spec, np.concatenate([g[0] for g in grids]), np.repeat(chunk, len(grids[0][0]), axis=0),
            signs=signs, margin=margin, assembled=region.assembled,
        )
        value, keep = value.reshape(len(chunk), -1), keep.reshape(len(chunk), -1)
        for row, mask, (_, cell), d in zip(value, keep, grids, chunk, strict=True):
            size = per_design(mech, spec, d)
            full = reduce_samples(row, mask, cell, spec.reduce) / size
            half = reduce_samples(row[coarse], mask[coarse], cell * 2**mech.n_out, spec.reduce) / size
            out.append(
                GlobalValue(full, points=int(mask.sum()), region=region.name, resolution=resolution,
                            accuracy=abs(full - half))
            )
        if progress is not None:
            progress(len(chunk))
    return out
