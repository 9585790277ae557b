"""Global indices over parametrised regions by a fixed quadrature, differentiable in the design.

The region's nodes are placed by the design (:mod:`pkm.regions.shapes`), the fused pipeline
(:mod:`pkm.regions.pipeline`) is mapped over them, and the node values are reduced with the region's
weights: one CasADi graph from the design to the index, with an exact gradient. A region minimum
(``reduce="min"``) in that graph is the minimum over the nodes, which include the region's centre and
boundary: piecewise smooth in the design, with the gradient of the active node. Syntheses maximise it in
the smooth epigraph form (:func:`node_values` with ``epigraph``). The values this module reports
(:func:`global_value`, :func:`parametrised_global`) refine the best nodes between the nodes
(:mod:`pkm.regions.extremes`), so that a region extreme is accurate to ``EXTREME_ACCURACY`` relative.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.indices import GlobalIndex, LocalIndex, epigraph_function, reduce_nodes, reduce_samples
from pkm.indices.global_indices import EXTREMES_REDUCE
from pkm.indices.local import WORKSPACE_MARGIN
from pkm.regions.extremes import Refined, refine, refined_gradient
from pkm.regions.pipeline import pipeline
from pkm.regions.sampled import per_design, sample_values
from pkm.regions.shapes import check_resolution
from pkm.regions.value import GlobalValue

QUADRATURE_RESOLUTION = 8
GUARD_RESOLUTION = 4
GUARD_TOLERANCE = 1e-9
EXTREME_ACCURACY = 1e-5  # relative, of a refined region extreme at the default resolution (tested)
INDEX_ACCURACY = 1e-5  # the accuracy a global index is refined to when no resolution is given (relative above 1)
ADAPTIVE_LIMIT = 256  # the largest resolution the refinement doubles to


def node_values(
    mech: Any,
    spec: GlobalIndex,
    region: Any,
    branch: Any,
    design: ca.MX,
    *,
    resolution: int,
    epigraph: ca.MX | None = None,
) -> tuple[ca.MX, ca.MX, ca.MX]:
    """The local index at the region's nodes (a 1 x n row, CasADi in the design, NaN where a node is
    out of reach), their weights and whether each node is reached (1 or 0).

    With ``epigraph`` t, instead of the values the constraints g >= 0 (one column per node) that say
    the local index is at least t at every node (:func:`pkm.indices.epigraph_function`), or at most t
    for a region maximum.
    """
    points, weights = region.quadrature(mech.functions, design, resolution, spec.reduce)
    n = points.size2()
    fn = pipeline(mech, (spec.local,), matrices=epigraph is not None).map(n)
    outputs = fn(points, ca.DM(branch.signs), design)
    if epigraph is not None:
        matrices = outputs[4:]
        shapes = tuple((m.size1(), m.size2() // n) for m in matrices)
        g = epigraph_function(spec.local, shapes, spec.reduce == "max").map(n)(*matrices, epigraph)
        return g, weights, outputs[2]
    return outputs[3], weights, outputs[2]


def quadrature_value(
    mech: Any, spec: GlobalIndex, region: Any, branch: Any, design: ca.MX, *, resolution: int
) -> ca.MX:
    """The global index over the region as a CasADi expression of the design (no gradient attached)."""
    values, weights, valid = node_values(
        mech, spec, region, branch, design, resolution=check_resolution(resolution, 1)
    )
    value = reduce_nodes(values, weights, spec.reduce, valid)
    if region.guard is not None:
        value = ca.if_else(guard_holds(mech, region, branch, design) > 0, value, np.nan)
    if spec.per is not None:
        value = value / mech.functions.require(spec.per, f"the global index {spec.name}")(design)
    return value


def guard_holds(mech: Any, region: Any, branch: Any, design: Any) -> Any:
    """1 where the region's guard holds for the design, else 0 (CasADi in the design, or a float).

    The guard's margins are taken at the nodes of the region's extreme rule at GUARD_RESOLUTION, its
    interior, centre and rim (inset from edges that a map may collapse), whatever the resolution of the
    index: every node must be reached and every margin at least -GUARD_TOLERANCE. A margin that
    vanishes on the boundary (a singular corner of the region) is accepted; one that turns negative
    anywhere on the boundary or at a node inside is not.
    """
    numeric = not isinstance(design, ca.MX | ca.SX)
    d = ca.DM(design) if numeric else design
    points, _ = region.quadrature(mech.functions, d, GUARD_RESOLUTION, "min")
    n = points.size2()
    _, _, valid, margin = pipeline(mech, (guard_index(region),)).map(n)(points, ca.DM(branch.signs), d)
    holds = ca.mmin(valid * (margin >= -GUARD_TOLERANCE))
    return float(holds) if numeric else holds


@lru_cache(maxsize=32)
def guard_function(mech: Any, region: Any, branch: Any) -> ca.Function:
    """CasADi function ``design -> holds`` of :func:`guard_holds` (1 or 0), for batches of designs."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    return ca.Function(f"{region.name}_{branch.name}_guard", [design],
                       [guard_holds(mech, region, branch, design)], ["design"], ["holds"])


def admissible(mech: Any, region: Any, designs: np.ndarray, *, branch: Any) -> np.ndarray:
    """Whether the region's guard holds for each design (D, n_p): a boolean mask (D,), all True for a
    region without a guard."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    if region.guard is None:
        return np.ones(len(designs), dtype=bool)
    return evaluate(guard_function(mech, region, branch), designs)[0][:, 0, 0] > 0


def guard_index(region: Any) -> LocalIndex | None:
    """The least of the region's guard margins as a local index (None for a region without a guard)."""
    if region.guard is None:
        return None
    return replace(WORKSPACE_MARGIN, name=f"{region.guard}_min", source=region.guard,
                   doc=f"least of the margins {region.guard} that the region {region.name} needs at every node")


@lru_cache(maxsize=64)
def quadrature_function(mech: Any, spec: GlobalIndex, region: Any, branch: Any, resolution: int) -> ca.Function:
    """CasADi function ``design -> (value, gradient)`` of a global index over a parametrised region."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    value = quadrature_value(mech, spec, region, branch, design, resolution=resolution)
    return ca.Function(
        f"{spec.name}_{region.name}_{branch.name}_{resolution}",
        [design],
        [value, ca.gradient(value, design)],
        ["design"],
        [spec.name, "gradient"],
    )


@lru_cache(maxsize=64)
def nodes_function(mech: Any, spec: GlobalIndex, region: Any, branch: Any, resolution: int) -> ca.Function:
    """CasADi function ``design -> values``: the local index at every node of the region's extreme rule
    (a 1 x n row, NaN where a node is out of reach)."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    values, _, _ = node_values(mech, spec, region, branch, design, resolution=resolution)
    return ca.Function(f"{spec.name}_{region.name}_{branch.name}_{resolution}_nodes", [design], [values],
                       ["design"], ["values"])


def refined_extremes(
    mech: Any, spec: GlobalIndex, region: Any, branch: Any, designs: np.ndarray, *, resolution: int
) -> Refined:
    """The refined extremes of the local index over the region for a batch of designs (D, n_p)."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    (values,) = evaluate(nodes_function(mech, spec, region, branch, resolution), designs)
    return refine(mech, spec, region, branch, designs, values=values[:, 0, :], resolution=resolution)


@lru_cache(maxsize=64)
def value_function(mech: Any, spec: GlobalIndex, region: Any, branch: Any, resolution: int) -> ca.Function:
    """CasADi function ``design -> value`` of a global index over a parametrised region."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    value = quadrature_value(mech, spec, region, branch, design, resolution=resolution)
    return ca.Function(
        f"{spec.name}_{region.name}_{branch.name}_{resolution}_value", [design], [value], ["design"], [spec.name]
    )


def parametrised_global(
    mech: Any, spec: GlobalIndex, region: Any, designs: np.ndarray, *, branch: Any, resolution: int
) -> np.ndarray:
    """Values (D,) of a global index over a parametrised region for a batch of designs (D, n_p); an
    extreme refined between the nodes."""
    values = evaluate(value_function(mech, spec, region, branch, resolution), designs)[0][:, 0, 0]
    if spec.reduce not in EXTREMES_REDUCE:
        return values
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    defined = np.isfinite(values)
    if defined.any():
        refined = refined_extremes(mech, spec, region, branch, designs[defined], resolution=resolution).values
        values[defined] = refined / _sizes(mech, spec, designs[defined])[0]
    return values


def _sizes(mech: Any, spec: GlobalIndex, designs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What an index's reduction is divided by for each design (D, n_p), its ``per`` function of the
    design (1 without one), and its gradient (D, n_p)."""
    if spec.per is None:
        return np.ones(len(designs)), np.zeros(designs.shape)
    size, gradient = evaluate(per_function(mech, spec.per, f"the global index {spec.name}"), designs)
    return size[:, 0, 0], gradient[:, :, 0]


@lru_cache(maxsize=16)
def per_function(mech: Any, name: str, what: str) -> ca.Function:
    """CasADi function ``design -> (size, gradient)`` of the mechanism's function ``name``."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    size = mech.functions.require(name, what)(design)
    return ca.Function(f"{name}_with_gradient", [design], [size, ca.gradient(size, design)])


def _at_resolution(
    mech: Any, spec: GlobalIndex, region: Any, design: np.ndarray, *, branch: Any, resolution: int, gradient: bool
) -> tuple[float, np.ndarray | None]:
    """The index of one design (n_p,) at one resolution, a region extreme refined between the nodes (NaN
    where the quadrature's is), with its gradient in the design when asked."""
    if spec.reduce not in EXTREMES_REDUCE:
        if not gradient:
            return float(value_function(mech, spec, region, branch, resolution)(design)), None
        value, grad = quadrature_function(mech, spec, region, branch, resolution)(design)
        return float(value), np.asarray(grad).ravel()
    if not np.isfinite(float(value_function(mech, spec, region, branch, resolution)(design))):
        return float("nan"), (np.full(len(design), np.nan) if gradient else None)
    refined = refined_extremes(mech, spec, region, branch, design[None], resolution=resolution)
    (size,), (size_gradient,) = _sizes(mech, spec, design[None])
    value = float(refined.values[0])
    if not gradient:
        return value / size, None
    grad = refined_gradient(mech, spec, region, design, branch=branch, refined=refined)
    return value / size, grad / size - value * size_gradient / size**2


def _result(spec: GlobalIndex, region: Any, value: float, *, resolution: int, accuracy: float) -> GlobalValue:
    return GlobalValue(value, points=region.node_count(resolution, spec.reduce), region=region.name,
                       resolution=resolution, accuracy=accuracy)


def global_value(
    mech: Any,
    spec: GlobalIndex,
    region: Any,
    design: np.ndarray,
    *,
    branch: Any,
    resolution: int,
    gradient: bool = False,
) -> tuple[GlobalValue, np.ndarray | None]:
    """The index of one design, with its exact gradient (n_p,) when asked; the accuracy is the change
    from the quadrature at half the resolution (from resolution 2 on)."""
    design = np.asarray(design, dtype=float).ravel()
    value, grad = _at_resolution(mech, spec, region, design, branch=branch, resolution=resolution, gradient=gradient)
    accuracy = float("nan")
    if resolution >= 2:
        coarse, _ = _at_resolution(mech, spec, region, design, branch=branch, resolution=resolution // 2,
                                   gradient=False)
        accuracy = abs(value - coarse)
    return _result(spec, region, value, resolution=resolution, accuracy=accuracy), grad


def adaptive_value(
    mech: Any, spec: GlobalIndex, region: Any, design: np.ndarray, *, branch: Any, gradient: bool = False,
    tolerance: float = INDEX_ACCURACY,
) -> tuple[GlobalValue, np.ndarray | None]:
    """The index of one design at the resolution it needs: from QUADRATURE_RESOLUTION the resolution
    doubles until the change from half of it is at most ``tolerance`` (times the value where it exceeds 1)
    or ADAPTIVE_LIMIT is reached; the value reports the accuracy it reached either way. Each resolution
    is evaluated once."""
    design = np.asarray(design, dtype=float).ravel()
    resolution = QUADRATURE_RESOLUTION

    def at(n: int) -> float:
        return _at_resolution(mech, spec, region, design, branch=branch, resolution=n, gradient=False)[0]

    previous, value = at(resolution // 2), at(resolution)
    while np.isfinite(value) and abs(value - previous) > tolerance * max(1.0, abs(value)) \
            and 2 * resolution <= ADAPTIVE_LIMIT:
        resolution *= 2
        previous, value = value, at(resolution)
    grad = None
    if gradient:
        value, grad = _at_resolution(mech, spec, region, design, branch=branch, resolution=resolution, gradient=True)
    return _result(spec, region, value, resolution=resolution, accuracy=abs(value - previous)), grad


def sampled_check(
    mech: Any, spec: GlobalIndex, region: Any, design: np.ndarray, *, branch: Any, resolution: int
) -> GlobalValue:
    """A parametrised region's global index by sampling: cell centres of a grid inside the region
    (and its boundary for a minimum). An independent check of the quadrature; singular poses are kept
    (margin 0), as in the quadrature."""
    design = np.asarray(design, dtype=float)
    x, cell = region.sample(mech.functions, design, resolution, spec.reduce)
    d = np.broadcast_to(design, (len(x), len(design)))
    value, keep = sample_values(mech, spec, x, d, signs=np.array(branch.signs), margin=0.0)
    guard = guard_index(region)
    if guard is not None:
        margin, inside = sample_values(mech, replace(spec, local=guard), x, d, signs=np.array(branch.signs),
                                       margin=0.0)
        if not (guard_holds(mech, region, branch, design) and np.all(inside & (margin >= -GUARD_TOLERANCE))):
            return GlobalValue(np.nan, points=0, region=region.name, resolution=resolution)
    result = reduce_samples(value, keep, cell, spec.reduce) / per_design(mech, spec, design)
    return GlobalValue(result, points=int(keep.sum()), region=region.name, resolution=resolution)
