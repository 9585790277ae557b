"""Global indices over parametrised regions by a fixed quadrature, differentiable in the design.

The region's nodes are placed by the design (:mod:`pkm.regions.shapes`), the fused pipeline
(:mod:`pkm.regions.pipeline`) is evaluated at them point by point, and the node values are reduced with
the region's weights (:mod:`pkm.regions.integrand`, compiled where the kernels are built): a CasADi
function of the design with exact gradient and Hessian. A region minimum (``reduce="min"``) is the
minimum over the nodes, which include the region's centre and boundary: piecewise smooth in the design,
with the gradient of the active node. Syntheses maximise it in the smooth epigraph form
(:func:`epigraph_margins`). The values this module reports
(:func:`value_at`, :func:`global_values`) refine the best nodes between the nodes
(:mod:`pkm.regions.extremes`), so that a region extreme is accurate to ``EXTREME_ACCURACY`` relative.

Each function takes the index it evaluates as a :class:`pkm.regions.RegionIndex` (a global index over one
region in one working mode of one mechanism). :func:`node_quadrature`, :func:`parametrised_global`,
:func:`quadrature_function`, :func:`global_value`, :func:`sampled_check` and :func:`admissible` are the same
for a caller that holds the mechanism, the index, the region and the working mode apart.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import cache, lru_cache

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.indices import GlobalIndex, reduce_samples
from pkm.indices.global_indices import EXTREMES_REDUCE
from pkm.kinematics import Branch
from pkm.progress import Progress
from pkm.regions.extremes import Refined, refine, refined_gradient
from pkm.regions.integrand import (
    COMPONENTS,
    Derivatives,
    Smooth,
    batch_rows,
    batch_sums,
    point_rows,
    reduce_gradient,
    reduce_sums,
    region_rows,
    region_sums,
    rows_function,
)
from pkm.regions.pipeline import PipelineModel
from pkm.regions.region import Region, RegionIndex, guard_index, region_guard  # noqa: F401 (pkm.catalogue reads guard_index here)
from pkm.regions.sampled import per_design, sample_values
from pkm.regions.shapes import check_nodes, check_resolution
from pkm.regions.value import GlobalValue

QUADRATURE_RESOLUTION = 8
GUARD_RESOLUTION = 4
GUARD_TOLERANCE = 1e-9
EXTREME_ACCURACY = 1e-5  # relative, of a refined region extreme at the default resolution (tested)
INDEX_ACCURACY = 1e-5  # the accuracy a global index is refined to when no resolution is given (relative above 1)
ADAPTIVE_LIMIT = 256  # the largest resolution the refinement doubles to
ADAPTIVE_POINTS = 1 << 22  # the most nodes the refinement's next resolution may take
ADAPTIVE_SECONDS = 20.0  # the refinement takes no next resolution that would end beyond this, at the last pace


@cache
def _sums(index: RegionIndex, *, resolution: int, smooth: bool = False) -> Smooth:
    """CasADi ``design -> S``: the sums of the reduction's components over the region's nodes
    (:mod:`pkm.regions.integrand`), with exact derivatives; with ``smooth``, of the local index's smooth
    stand-in where it has one."""
    def fn(design: np.ndarray, order: int) -> Derivatives:
        return region_sums(index, design=design, resolution=resolution, order=order, smooth=smooth)

    name = f"{index.region.name}_{index.local.name}_{index.reduce}_{resolution}_sums{'_smooth' if smooth else ''}"
    return Smooth(name, fn, index.design_size, len(COMPONENTS[index.reduce]))


@cache
def _rows(index: RegionIndex, *, resolution: int, epigraph: bool, rows: tuple[int, ...] | None = None) -> Smooth:
    """CasADi ``design -> (values, reached)`` at the nodes of the region's extreme rule, or with
    ``epigraph`` ``(design, t) -> margins`` (:func:`pkm.regions.integrand.region_rows`), only the ``rows``
    of them where given."""
    def fn(z: np.ndarray, order: int) -> Derivatives:
        return region_rows(index, z=z, resolution=resolution, order=order, epigraph=epigraph, rows=rows)

    mech, local, reduce = index.mechanism, index.local, index.reduce
    values = sum(piece.node_count(resolution, reduce) * rows_function(mech, local, piece, reduce if epigraph else None,
                                                                      0)[0].numel_out(0)
                 for piece in index.region.pieces())
    label = "epigraph" if epigraph else "nodes"
    return Smooth(f"{index.region.name}_{local.name}_{reduce}_{resolution}_{label}", fn, index.design_size + epigraph,
                  values if rows is None else len(rows))


def epigraph_margins(
    index: RegionIndex, *, design: ca.MX, bound: ca.MX, resolution: int, rows: tuple[int, ...] | None = None
) -> ca.MX:
    """The constraints g >= 0 that say the local index is at least ``bound`` at every node of the region's
    extreme rule (:func:`pkm.indices.epigraph_function`), or at most it for a region maximum: a column of
    the index's first margin at every node, then its second, and so on (:func:`epigraph_values`); only the
    ``rows`` of it where given."""
    smooth = _rows(index, resolution=check_resolution(resolution, 1), epigraph=True, rows=rows)
    return smooth(ca.vertcat(design, bound))


@lru_cache(maxsize=64)
def _point_rows(index: RegionIndex, *, points: tuple[tuple[int, tuple[float, ...]], ...]) -> Smooth:
    """CasADi ``(design, t) -> margins`` at the given points of the region (:func:`point_rows`)."""
    def fn(z: np.ndarray, order: int) -> Derivatives:
        return point_rows(index, z=z, points=points, order=order)

    piece = index.region.pieces()[0]
    outputs = rows_function(index.mechanism, index.local, piece, index.reduce, 0)[0].numel_out(0)
    return Smooth(f"{index.region.name}_{index.local.name}_{index.reduce}_points", fn, index.design_size + 1,
                  outputs * len(points))


def epigraph_point_margins(
    index: RegionIndex, *, design: ca.MX, bound: ca.MX, points: tuple[tuple[int, tuple[float, ...]], ...]
) -> ca.MX:
    """The constraints g >= 0 of :func:`epigraph_margins` at given points of the region between its nodes,
    each a piece's index and a reference point (where :func:`refined_extremes` finds an extreme): every
    output of each point."""
    return _point_rows(index, points=points)(ca.vertcat(design, bound))


def epigraph_values(index: RegionIndex, *, design: np.ndarray, bound: float, resolution: int) -> np.ndarray:
    """Every row of :func:`epigraph_margins` for one design (n_p,) and bound, numerically."""
    z = np.append(np.asarray(design, dtype=float).ravel(), bound)
    return region_rows(index, z=z, resolution=check_resolution(resolution, 1), order=0, epigraph=True)[0]


def quadrature_value(index: RegionIndex, design: ca.MX, *, resolution: int) -> ca.MX:
    """The global index over the region as a CasADi expression of the design, with exact derivatives:
    the reduction of the sums of :mod:`pkm.regions.integrand` (of the local index's smooth stand-in where it
    has one: this is the optimiser's value), or a region extreme over the nodes (NaN where a node is not
    reached)."""
    resolution = check_resolution(resolution, 1)
    spec = index.spec
    if spec.reduce in EXTREMES_REDUCE:
        rows = _rows(index, resolution=resolution, epigraph=False)(design)
        n = rows.numel() // 2
        values, reached = rows[:n], rows[n:]
        extreme = ca.mmin(values) if spec.reduce == "min" else ca.mmax(values)
        value = ca.if_else(ca.mmin(reached) > 0, extreme, np.nan)
    else:
        sums = _sums(index, resolution=resolution, smooth=True)(design)
        value = reduce_sums(sums, spec.reduce)
    guard = index.guard()
    if guard is not None:
        value = ca.if_else(guard_holds(guard, design) > 0, value, np.nan)
    if spec.per is not None:
        value = value / index.mechanism.functions.require(spec.per, f"the global index {spec.name}")(design)
    return value


def node_values(index: RegionIndex, designs: np.ndarray, *, resolution: int) -> np.ndarray:
    """Values (D,) of the global index for a batch of designs (D, n_p), as :func:`quadrature_value` takes
    them (a region extreme over the nodes), evaluated numerically in batches of designs."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    resolution = check_resolution(resolution, 1)
    if not len(designs):
        return np.zeros(0)
    with np.errstate(invalid="ignore", divide="ignore"):
        if index.reduce in EXTREMES_REDUCE:
            values, reached = batch_rows(index, designs=designs, resolution=resolution)
            extreme = (np.fmin if index.reduce == "min" else np.fmax).reduce(values, axis=1)
            value = np.where(np.all(reached > 0, axis=1), extreme, np.nan)
        else:
            sums = batch_sums(index, designs=designs, resolution=resolution)
            value = reduce_sums(sums.T, index.reduce)
        guard = index.guard()
        if guard is not None:
            value = np.where(admits(guard, designs), value, np.nan)
        return value / _sizes(index, designs)[0]


def guard_holds(guard: RegionIndex, design: ca.MX | np.ndarray) -> ca.MX | float:
    """1 where a region's guard (:meth:`RegionIndex.guard`) holds for the design, else 0 (CasADi in the design,
    or a float).

    The guard's margins are taken at the nodes of the region's extreme rule at GUARD_RESOLUTION, its
    interior, centre and rim (inset from edges that a map may collapse), whatever the resolution of the
    index: every node must be reached and every margin at least -GUARD_TOLERANCE. A margin that
    vanishes on the boundary (a singular corner of the region) is accepted; one that turns negative
    anywhere on the boundary or at a node inside is not.
    """
    if not isinstance(design, ca.MX | ca.SX):
        return float(admits(guard, np.ravel(design)[None])[0])
    rows = _rows(guard, resolution=GUARD_RESOLUTION, epigraph=False)(design)
    n = rows.numel() // 2
    return ca.mmin(rows[n:] * (rows[:n] >= -GUARD_TOLERANCE))


def admits(guard: RegionIndex | None, designs: np.ndarray) -> np.ndarray:
    """Whether a region's guard holds for each design (D, n_p) (:func:`guard_holds`): a boolean mask (D,), all
    True where the region has no guard (``guard`` None)."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    if guard is None:
        return np.ones(len(designs), dtype=bool)
    margins, reached = batch_rows(guard, designs=designs, resolution=GUARD_RESOLUTION)
    with np.errstate(invalid="ignore"):
        return np.all((reached > 0) & (margins >= -GUARD_TOLERANCE), axis=1)


@lru_cache(maxsize=64)
def value_and_gradient(index: RegionIndex, resolution: int) -> Callable[[np.ndarray], tuple[float, np.ndarray]]:
    """``design (n_p,) -> (value, gradient (n_p,))`` of the global index, as :func:`quadrature_value` defines
    it. A mean, deviation or measure is reduced numerically from its sums and their Jacobian
    (:func:`pkm.regions.integrand.region_sums`, one evaluation of the integrands with their gradient); a region
    extreme through the CasADi graph of its nodes."""
    if index.reduce in EXTREMES_REDUCE:
        symbol = ca.MX.sym("design", index.design_size)
        value = quadrature_value(index, symbol, resolution=resolution)
        name = index.spec.name
        graph = ca.Function(f"{name}_{index.region.name}_{index.mode.name}_{resolution}", [symbol],
                            [value, ca.gradient(value, symbol)], ["design"], [name, "gradient"])

        def extreme(design: np.ndarray) -> tuple[float, np.ndarray]:
            value, gradient = graph(np.asarray(design, dtype=float).ravel())
            return float(value), np.asarray(gradient, dtype=float).ravel()

        return extreme
    resolution = check_resolution(resolution, 1)

    def summed(design: np.ndarray) -> tuple[float, np.ndarray]:
        design = np.asarray(design, dtype=float).ravel()
        sums, jacobian, _ = region_sums(index, design=design, resolution=resolution, order=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            value, gradient = float(reduce_sums(sums, index.reduce)), reduce_gradient(sums, jacobian, index.reduce)
        if not admits(index.guard(), design[None])[0]:
            return float("nan"), np.full(len(design), np.nan)
        (size,), (size_gradient,) = _sizes(index, design[None])
        return value / size, gradient / size - value * size_gradient / size**2

    return summed


def refined_extremes(index: RegionIndex, designs: np.ndarray, *, resolution: int) -> Refined:
    """The refined extremes of the local index over the region for a batch of designs (D, n_p)."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    values, _ = batch_rows(index, designs=designs, resolution=resolution)
    return refine(index, designs, values=values, resolution=resolution)


def global_values(index: RegionIndex, designs: np.ndarray, *, resolution: int) -> np.ndarray:
    """Values (D,) of the global index for a batch of designs (D, n_p); an extreme refined between the nodes."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    values = node_values(index, designs, resolution=resolution)
    if index.reduce not in EXTREMES_REDUCE:
        return values
    defined = np.isfinite(values)
    if defined.any():
        refined = refined_extremes(index, designs[defined], resolution=resolution).values
        values[defined] = refined / _sizes(index, designs[defined])[0]
    return values


def _sizes(index: RegionIndex, designs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What the index's reduction is divided by for each design (D, n_p), its ``per`` function of the
    design (1 without one), and its gradient (D, n_p)."""
    spec = index.spec
    if spec.per is None:
        return np.ones(len(designs)), np.zeros(designs.shape)
    size, gradient = evaluate(per_function(index.mechanism, spec.per, f"the global index {spec.name}"), designs)
    return size[:, 0, 0], gradient[:, :, 0]


@lru_cache(maxsize=16)
def per_function(mech: PipelineModel, name: str, what: str) -> ca.Function:
    """CasADi function ``design -> (size, gradient)`` of the mechanism's function ``name``."""
    design = ca.MX.sym("design", mech.functions["inverse_kinematics"].numel_in(2))
    size = mech.functions.require(name, what)(design)
    return ca.Function(f"{name}_with_gradient", [design], [size, ca.gradient(size, design)])


def _at_resolution(
    index: RegionIndex, design: np.ndarray, *, resolution: int, gradient: bool
) -> tuple[float, np.ndarray | None]:
    """The index of one design (n_p,) at one resolution, a region extreme refined between the nodes (NaN
    where the quadrature's is), with its gradient in the design when asked."""
    if index.reduce not in EXTREMES_REDUCE:
        if not gradient:
            return float(node_values(index, design, resolution=resolution)[0]), None
        value, grad = value_and_gradient(index, resolution)(design)
        return float(value), np.asarray(grad).ravel()
    if not np.isfinite(node_values(index, design, resolution=resolution)[0]):
        return float("nan"), (np.full(len(design), np.nan) if gradient else None)
    refined = refined_extremes(index, design[None], resolution=resolution)
    (size,), (size_gradient,) = _sizes(index, design[None])
    value = float(refined.values[0])
    if not gradient:
        return value / size, None
    grad = refined_gradient(index, design, refined=refined)
    return value / size, grad / size - value * size_gradient / size**2


def _result(index: RegionIndex, value: float, *, resolution: int, accuracy: float) -> GlobalValue:
    return GlobalValue(value, points=index.node_count(resolution), region=index.region.name, resolution=resolution,
                       accuracy=accuracy)


def _node_count(index: RegionIndex, resolution: int) -> int:
    """The nodes of the region's rule at a resolution, from its rules at resolutions 1 and 2 (a rule of a
    d-dimensional region has c resolution^d nodes), without building it."""
    one, two = index.node_count(1), index.node_count(2)
    return round(one * resolution ** np.log2(two / one))


def value_at(
    index: RegionIndex, design: np.ndarray, *, resolution: int, gradient: bool = False
) -> tuple[GlobalValue, np.ndarray | None]:
    """The index of one design, with its exact gradient (n_p,) when asked; the accuracy is the change
    from the quadrature at half the resolution (from resolution 2 on)."""
    nodes = _node_count(index, check_resolution(resolution, 1))
    check_nodes(resolution, nodes, f"the region {index.region.name}")
    design = np.asarray(design, dtype=float).ravel()
    value, grad = _at_resolution(index, design, resolution=resolution, gradient=gradient)
    accuracy = float("nan")
    if resolution >= 2:
        coarse, _ = _at_resolution(index, design, resolution=resolution // 2, gradient=False)
        accuracy = abs(value - coarse)
    return _result(index, value, resolution=resolution, accuracy=accuracy), grad


def adaptive_value(
    index: RegionIndex, design: np.ndarray, *, gradient: bool = False, tolerance: float = INDEX_ACCURACY
) -> tuple[GlobalValue, np.ndarray | None]:
    """The index of one design at the resolution it needs: from QUADRATURE_RESOLUTION the resolution
    doubles until the change from half of it is at most ``tolerance`` (times the value where it exceeds 1),
    or ADAPTIVE_LIMIT is reached, or the next resolution would take more than ADAPTIVE_POINTS nodes or, at the
    pace of the last one, end beyond ADAPTIVE_SECONDS; the value reports the accuracy it reached either way,
    and why it stopped where it did not converge. Each resolution is evaluated once; a progress bar on a
    terminal shows the resolutions done."""
    design = np.asarray(design, dtype=float).ravel()
    resolution = QUADRATURE_RESOLUTION
    planned = int(np.log2(ADAPTIVE_LIMIT // QUADRATURE_RESOLUTION)) + 2
    bar = Progress(planned, f"{index.spec.name} over {index.region.name}")
    start = time.perf_counter()

    def at(n: int) -> float:
        out = _at_resolution(index, design, resolution=n, gradient=False)[0]
        bar.advance()
        return out

    previous, value = at(resolution // 2), at(resolution)
    stopped = ""
    while np.isfinite(value) and abs(value - previous) > tolerance * max(1.0, abs(value)):
        if 2 * resolution > ADAPTIVE_LIMIT:
            stopped = f"at resolution {resolution}, the largest the refinement takes"
            break
        nodes = _node_count(index, 2 * resolution)
        last = _node_count(index, resolution)
        elapsed = time.perf_counter() - start
        if nodes > ADAPTIVE_POINTS:
            stopped = (f"at resolution {resolution}: the next would take {nodes} nodes, beyond the budget of "
                       f"{ADAPTIVE_POINTS}")
            break
        if elapsed * (1 + nodes / last) > ADAPTIVE_SECONDS:
            stopped = (f"at resolution {resolution} after {elapsed:.1f} s: the next would end beyond the budget of "
                       f"{ADAPTIVE_SECONDS:g} s")
            break
        resolution *= 2
        previous, value = value, at(resolution)
    bar.close()
    grad = None
    if gradient:
        value, grad = _at_resolution(index, design, resolution=resolution, gradient=True)
    result = _result(index, value, resolution=resolution, accuracy=abs(value - previous))
    if np.isfinite(value) and result.accuracy > tolerance * max(1.0, abs(value)):
        result.converged = False
        result.note = (f"not converged: stopped {stopped or f'at resolution {resolution}'}, where the value still "
                       f"changes by {result.accuracy:.1e} from half of it, more than the {tolerance:g} asked "
                       "(relative above 1): the index is not smooth over the region")
    return result, grad


def sampled_value(index: RegionIndex, design: np.ndarray, *, resolution: int) -> GlobalValue:
    """The global index by sampling: cell centres of a grid inside the region (and its boundary for a
    minimum). An independent check of the quadrature; singular poses are kept (margin 0), as in the
    quadrature."""
    design = np.asarray(design, dtype=float)
    if getattr(index.region, "timed", False):
        return _sampled_in_time(index, design, resolution=resolution)
    mech, spec, region = index.mechanism, index.spec, index.region
    x, cell = region.sample(mech.functions, design, resolution, spec.reduce)
    d = np.broadcast_to(design, (len(x), len(design)))
    value, keep = sample_values(mech, spec, x, d, signs=index.signs, margin=0.0, assembled=True)
    guard = index.guard()
    if guard is not None:
        margin, inside = sample_values(mech, guard.spec, x, d, signs=index.signs, margin=0.0, assembled=True)
        if not (guard_holds(guard, design) and np.all(inside & (margin >= -GUARD_TOLERANCE))):
            return GlobalValue(np.nan, points=0, region=region.name, resolution=resolution)
    result = reduce_samples(value, keep, cell, spec.reduce) / per_design(mech, spec, design)
    return GlobalValue(result, points=int(keep.sum()), region=region.name, resolution=resolution)


def _sampled_in_time(index: RegionIndex, design: np.ndarray, *, resolution: int) -> GlobalValue:
    """A trajectory's global index by sampling: the local index at the midpoints of equal time steps of every
    piece (and the pieces' ends for an extreme), reduced with the steps as weights; NaN where a sample is out
    of reach. The midpoint rule beside the quadrature's Gauss-Legendre rule, an independent check."""
    pieces = index.region.pieces()
    values, reached, cells = [], [], []
    for k, u, cell in index.region.samples(resolution, index.reduce):
        fn = rows_function(index.mechanism, index.local, pieces[k], None, 0)[0]
        out = evaluate(fn, u, index.signs, design)[0]
        values.append(out[:, 0, 0])
        reached.append(out[:, 1, 0] > 0)
        cells.append(cell)
    value, keep, cell = (np.concatenate(a) for a in (values, reached, cells))
    if not keep.all():
        return GlobalValue(np.nan, points=0, region=index.region.name, resolution=resolution)
    result = reduce_samples(value, keep, cell, index.reduce) / per_design(index.mechanism, index.spec, design)
    return GlobalValue(result, points=len(value), region=index.region.name, resolution=resolution)


def node_quadrature(
    mech: PipelineModel, spec: GlobalIndex, region: Region, designs: np.ndarray, *, branch: Branch, resolution: int
) -> np.ndarray:
    """:func:`node_values` of the global index ``spec`` over ``region`` in the working mode ``branch``."""
    return node_values(RegionIndex(mech, spec, region, branch), designs, resolution=resolution)


def parametrised_global(
    mech: PipelineModel, spec: GlobalIndex, region: Region, designs: np.ndarray, *, branch: Branch, resolution: int
) -> np.ndarray:
    """:func:`global_values` of the global index ``spec`` over ``region`` in the working mode ``branch``."""
    return global_values(RegionIndex(mech, spec, region, branch), designs, resolution=resolution)


def quadrature_function(
    mech: PipelineModel, spec: GlobalIndex, region: Region, branch: Branch, resolution: int
) -> Callable[[np.ndarray], tuple[float, np.ndarray]]:
    """:func:`value_and_gradient` of the global index ``spec`` over ``region`` in the working mode ``branch``."""
    return value_and_gradient(RegionIndex(mech, spec, region, branch), resolution)


def global_value(
    mech: PipelineModel, spec: GlobalIndex, region: Region, design: np.ndarray, *, branch: Branch, resolution: int,
    gradient: bool = False,
) -> tuple[GlobalValue, np.ndarray | None]:
    """:func:`value_at` of the global index ``spec`` over ``region`` in the working mode ``branch``."""
    return value_at(RegionIndex(mech, spec, region, branch), design, resolution=resolution, gradient=gradient)


def sampled_check(
    mech: PipelineModel, spec: GlobalIndex, region: Region, design: np.ndarray, *, branch: Branch, resolution: int
) -> GlobalValue:
    """:func:`sampled_value` of the global index ``spec`` over ``region`` in the working mode ``branch``."""
    return sampled_value(RegionIndex(mech, spec, region, branch), design, resolution=resolution)


def admissible(mech: PipelineModel, region: Region, designs: np.ndarray, *, branch: Branch) -> np.ndarray:
    """Whether the region's guard in the working mode ``branch`` holds for each design (D, n_p) (:func:`admits`)."""
    return admits(region_guard(mech, region, branch), designs)
