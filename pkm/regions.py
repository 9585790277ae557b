"""Regions over which global indices are averaged (DESIGN.md section 5).

* The sampled region ``reachable``: a grid of cell centres over the bounding box of a working mode's
  workspace with a mask (reachable and at least ``singularity_margin`` away from singularity in
  1/kappa_f). For atlases and for checking; not differentiable.
* Parametrised regions, a disc or a rectangle whose centre and size are functions of the design (the
  maximum inscribed workspace of the five-bar, the task rectangle of the slider gantry): a fixed
  product quadrature on the reference shape (on the unit disc Gauss-Legendre in the radius with weight
  rho and the periodic trapezoidal rule in the angle; on the square [-1, 1]^2 Gauss-Legendre in both
  axes) mapped into the design's region. The global index is then a smooth CasADi expression of the
  design with an exact gradient.

A global index is a region mean, a region standard deviation (Wu 2008's companion of eq. 44) or a
region minimum. A global index that is a region minimum (``reduce="min"``, e.g. lambda_e) is the minimum over the
quadrature nodes plus a ring of nodes on the boundary circle and the centre: piecewise smooth in the
design, its gradient is that of the active node. The synthesis uses the smooth epigraph form instead.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from pkm import indices
from pkm.batch import evaluate, reached
from pkm.errors import PkmError

if TYPE_CHECKING:
    from pkm.mechanism import Branch, Mechanism

SAMPLED_RESOLUTION = 64
DISC_RESOLUTION = 8
SINGULARITY_MARGIN = 0.01
DESIGNS_PER_BATCH = 32


class GlobalValue(float):
    """A global index value that also reports the region and how many points it used."""

    points: int
    region: str
    resolution: int

    def __new__(cls, value: float, *, points: int, region: str, resolution: int) -> GlobalValue:
        obj = super().__new__(cls, value)
        obj.points, obj.region, obj.resolution = points, region, resolution
        return obj


@dataclass(frozen=True)
class ParametrisedRegion:
    """A design-dependent region: ``function`` is the generated CasADi function design -> (centre,
    size), the size being the radius of a ``"disc"`` or the half width and half height of a
    ``"rectangle"``."""

    name: str
    function: str
    doc: str
    shape: str = "disc"

    def nodes(self, resolution: int, reduce: str = "mean") -> tuple[np.ndarray, np.ndarray]:
        """Nodes on the reference shape (unit disc or [-1, 1]^2) and their weights."""
        if self.shape == "rectangle":
            return rectangle_nodes(resolution, reduce)
        return disc_nodes(resolution, reduce)

    def place(self, centre, size, nodes: np.ndarray):
        """The reference nodes (n, 2) mapped into the region of centre (2,) and size; numpy or CasADi."""
        if isinstance(centre, ca.MX | ca.SX | ca.DM):
            scale = ca.repmat(size, 2, 1) if self.shape == "disc" else size
            return ca.repmat(centre, 1, len(nodes)) + ca.diag(scale) @ ca.DM(nodes.T)
        scale = np.broadcast_to(np.ravel(size), (2,))
        return np.ravel(centre) + nodes * scale

    def contains(self, x: np.ndarray, centre: np.ndarray, size: np.ndarray) -> np.ndarray:
        """Mask of the points (N, 2) strictly inside the region."""
        d = x - np.ravel(centre)
        if self.shape == "rectangle":
            return np.all(np.abs(d) < np.ravel(size), axis=1)
        return np.sum(d**2, axis=1) < float(np.ravel(size)[0]) ** 2

    def box(self, centre: np.ndarray, size: np.ndarray) -> np.ndarray:
        """Bounding box (2, 2) of the region."""
        half = np.broadcast_to(np.ravel(size), (2,))
        return np.stack([np.ravel(centre) - half, np.ravel(centre) + half], axis=1)

    def boundary(self, centre: np.ndarray, size: np.ndarray, count: int) -> np.ndarray:
        """``count`` points on the region's boundary."""
        return self.place(centre, size, _unit_boundary(self.shape, count))


def _check_resolution(resolution: int, minimum: int) -> int:
    if int(resolution) != resolution or resolution < minimum:
        raise PkmError(f"resolution = {resolution} violates: an integer >= {minimum}")
    return int(resolution)


@lru_cache(maxsize=32)
def disc_quadrature(resolution: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (n, 2) and weights (n,) on the unit disc; n = 4 resolution^2; exact area pi.

    Gauss-Legendre in rho on [0, 1] with the Jacobian rho, ``4 * resolution`` equally spaced angles.
    """
    resolution = _check_resolution(resolution, 1)
    t, w = np.polynomial.legendre.leggauss(resolution)
    rho, w_rho = (t + 1) / 2, w / 2 * (t + 1) / 2
    m = 4 * resolution
    angle = 2 * np.pi * (np.arange(m) + 0.5) / m
    nodes = np.stack([np.outer(rho, np.cos(angle)).ravel(), np.outer(rho, np.sin(angle)).ravel()], axis=1)
    weights = np.outer(w_rho, np.full(m, 2 * np.pi / m)).ravel()
    return nodes, weights


@lru_cache(maxsize=32)
def disc_nodes(resolution: int, reduce: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of a global index on the unit disc: the quadrature for a mean; for a
    minimum, the quadrature nodes, the centre and 4 resolution nodes on the boundary circle."""
    nodes, weights = disc_quadrature(resolution)
    if reduce != "min":
        return nodes, weights
    nodes = np.concatenate([np.zeros((1, 2)), nodes, _unit_boundary("disc", 4 * resolution)])
    return nodes, np.ones(len(nodes))


def _unit_boundary(shape: str, count: int) -> np.ndarray:
    """``count`` points on the boundary of the unit disc or of the square [-1, 1]^2."""
    t = (np.arange(count) + 0.5) / count
    if shape == "disc":
        angle = 2 * np.pi * t
        return np.stack([np.cos(angle), np.sin(angle)], axis=1)
    side, u = np.divmod(4 * t, 1.0)
    u = 2 * u - 1
    corners = {0: (u, -np.ones_like(u)), 1: (np.ones_like(u), u), 2: (-u, np.ones_like(u)), 3: (-np.ones_like(u), -u)}
    out = np.zeros((count, 2))
    for k, (a, b) in corners.items():
        on = side == k
        out[on] = np.stack([a[on], b[on]], axis=1)
    return out


@lru_cache(maxsize=32)
def rectangle_nodes(resolution: int, reduce: str = "mean") -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights on [-1, 1]^2: the Gauss-Legendre product rule of 2 resolution points per
    axis (4 resolution^2 nodes, as on the disc); for a minimum, the nodes, the centre and 8 resolution
    nodes on the boundary, with unit weights."""
    resolution = _check_resolution(resolution, 1)
    t, w = np.polynomial.legendre.leggauss(2 * resolution)
    X, Y = np.meshgrid(t, t, indexing="ij")
    nodes = np.stack([X.ravel(), Y.ravel()], axis=1)
    weights = np.outer(w, w).ravel()
    if reduce != "min":
        return nodes, weights
    nodes = np.concatenate([np.zeros((1, 2)), nodes, _unit_boundary("rectangle", 8 * resolution)])
    return nodes, np.ones(len(nodes))


def grid(box: np.ndarray, resolution: int) -> tuple[np.ndarray, float]:
    """Cell centres (resolution^2, 2) of a 2-D box and the cell area."""
    resolution = _check_resolution(resolution, 2)
    axes = [lo + (hi - lo) * (np.arange(resolution) + 0.5) / resolution for lo, hi in box]
    X, Y = np.meshgrid(*axes, indexing="ij")
    area = float(np.prod([(hi - lo) / resolution for lo, hi in box]))
    return np.stack([X.ravel(), Y.ravel()], axis=1), area


def sampled_global(
    mech: Mechanism,
    spec: indices.GlobalIndex,
    designs: np.ndarray,
    branch: Branch,
    *,
    resolution: int | None = None,
    singularity_margin: float = SINGULARITY_MARGIN,
    progress=None,
) -> list[GlobalValue]:
    """Global index over the sampled reachable workspace of each design (D, n_p), vectorised."""
    resolution = _check_resolution(SAMPLED_RESOLUTION if resolution is None else resolution, 2)
    if not 0 <= singularity_margin < 1:
        raise PkmError(f"singularity_margin = {singularity_margin} violates 0 <= singularity_margin < 1")
    signs = np.array(branch.signs)
    out: list[GlobalValue] = []
    for start in range(0, len(designs), DESIGNS_PER_BATCH):
        chunk = designs[start : start + DESIGNS_PER_BATCH]
        poses = [grid(mech.workspace_box(d), resolution)[0] for d in chunk]
        value, mask = _sample(
            mech,
            spec,
            np.concatenate(poses),
            np.repeat(chunk, len(poses[0]), axis=0),
            signs=signs,
            margin=singularity_margin,
        )
        out += _reduce(
            value.reshape(len(chunk), -1), mask.reshape(len(chunk), -1), "reachable", resolution, spec.reduce
        )
        if progress is not None:
            progress(len(chunk))
    return out


def _sample(
    mech: Mechanism, spec: indices.GlobalIndex, x: np.ndarray, d: np.ndarray, *, signs: np.ndarray, margin: float
) -> tuple[np.ndarray, np.ndarray]:
    """Local index of ``spec`` at poses x (N, 2) of designs d (N, n_p), and the mask of the poses kept."""
    local = mech.local_spec(spec.local)
    condition = indices.local_spec("inverse_condition_f")
    q, reach = evaluate(mech.functions["inverse_kinematics"], x, signs, d)
    q = q[:, :, 0]
    ok = reached(q, reach)
    q[~ok] = 0.0
    J, J_f, *_ = evaluate(mech.functions["first_order"], q, x, d)
    matrices = {"J": J, "J_f": J_f}
    if local.source != "first_order":
        fn = mech.functions[local.source]
        matrices.update(zip(fn.name_out(), evaluate(fn, q, x, d), strict=True))
    value = indices.evaluate_local(local, matrices)
    kappa = value if local is condition else indices.evaluate_local(condition, matrices)
    return value, ok & (kappa >= margin) & np.isfinite(value)


def _reduce(value: np.ndarray, mask: np.ndarray, region: str, resolution: int, reduce: str) -> list[GlobalValue]:
    out = []
    for row, keep in zip(value, mask, strict=True):
        count = int(keep.sum())
        result = float("nan")
        if count:
            result = float({"min": np.min, "std": np.std}.get(reduce, np.mean)(row[keep]))
        out.append(GlobalValue(result, points=count, region=region, resolution=resolution))
    return out


def sampled_region_global(
    mech: Mechanism,
    spec: indices.GlobalIndex,
    region: ParametrisedRegion,
    design: np.ndarray,
    *,
    branch: Branch,
    resolution: int,
    placement: tuple[np.ndarray, np.ndarray] | None = None,
) -> GlobalValue:
    """A parametrised region's global index by sampling: cell centres of a grid inside the region.

    An independent check of the quadrature of :func:`parametrised_global_function`; singular poses
    are kept (margin 0), as in the quadrature. With ``placement`` (centre, size) the region is fixed
    there instead of following the design.
    """
    resolution = _check_resolution(resolution, 2)
    if placement is None:
        placement = mech.functions[region.function](design)
    centre, size = (np.asarray(a, dtype=float).ravel() for a in placement)
    x, _ = grid(region.box(centre, size), resolution)
    x = x[region.contains(x, centre, size)]
    if spec.reduce == "min":
        x = np.concatenate([x, region.boundary(centre, size, 4 * resolution)])
    d = np.broadcast_to(design, (len(x), len(design)))
    value, mask = _sample(mech, spec, x, d, signs=np.array(branch.signs), margin=0.0)
    return _reduce(value[None], mask[None], region.name, resolution, spec.reduce)[0]


@lru_cache(maxsize=64)
def parametrised_global_function(
    mech: Mechanism,
    spec: indices.GlobalIndex,
    region: ParametrisedRegion,
    branch: Branch,
    resolution: int = DISC_RESOLUTION,
) -> ca.Function:
    """CasADi function ``design -> (value, gradient)`` of a global index over a parametrised disc.

    The region's quadrature nodes are mapped into the design's disc and the inverse kinematics, the
    Jacobians and the local index are evaluated on them by ``map``: one graph, exact derivatives.
    """
    resolution = _check_resolution(resolution, 1)
    design = ca.MX.sym("design", len(mech.parameters))
    values, weights = node_values(mech, spec, region, branch, design, resolution=resolution)
    value = reduce_nodes(values, weights, spec.reduce)
    return ca.Function(
        f"{spec.name}_{region.name}_{branch.name}_{resolution}",
        [design],
        [value, ca.gradient(value, design)],
        ["design"],
        [spec.name, "gradient"],
    )


def reduce_nodes(values: ca.MX, weights: np.ndarray, reduce: str) -> ca.MX:
    """The weighted mean, standard deviation or minimum of a 1 x n row of node values."""
    w = ca.DM(weights / weights.sum())
    mean = ca.mtimes(values, w)
    if reduce == "min":
        return ca.mmin(values)
    if reduce == "std":
        return ca.sqrt(ca.mtimes((values - mean) ** 2, w))
    return mean


def node_values(
    mech: Mechanism,
    spec: indices.GlobalIndex,
    region: ParametrisedRegion,
    branch: Branch,
    design: ca.MX,
    *,
    resolution: int,
    epigraph: ca.MX | None = None,
    placement: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[ca.MX, np.ndarray]:
    """The local index at the region's nodes (a 1 x n row, CasADi in the design) and their weights.

    With ``epigraph`` t, the constraints g >= 0 (one column per node) that say the local index is at
    least t at every node (:func:`pkm.indices.epigraph_function`) instead of the values. With
    ``placement`` (centre, size) the region is fixed there instead of following the design.
    """
    local = mech.local_spec(spec.local)
    nodes, weights = region.nodes(resolution, spec.reduce)
    n = len(weights)
    if placement is None:
        centre, size = mech.functions[region.function](design)
    else:
        centre, size = (ca.DM(np.asarray(a, dtype=float).reshape(-1, 1)) for a in placement)
    x = region.place(centre, size, nodes)
    q, _ = mech.functions["inverse_kinematics"].map(n)(x, ca.DM(branch.signs), design)
    source = mech.functions[local.source]
    outs = dict(zip(source.name_out(), source.map(n)(q, x, design), strict=True))
    args = [outs[a] for a in local.arguments]
    if epigraph is not None:
        return indices.epigraph_function(local.name, mech.n_act).map(n)(*args, epigraph), weights
    values = indices.local_function(local.name, mech.n_act).map(n)(*args)
    return values, weights


@lru_cache(maxsize=64)
def _value_function(fn: ca.Function) -> ca.Function:
    design = fn.mx_in(0)
    return ca.Function(f"{fn.name()}_value", [design], [fn(design)[0]], ["design"], [fn.name_out(0)])


def parametrised_global(
    mech: Mechanism,
    spec: indices.GlobalIndex,
    region: ParametrisedRegion,
    designs: np.ndarray,
    *,
    branch: Branch,
    resolution: int,
) -> np.ndarray:
    """Values (D,) of a global index over a parametrised region for a batch of designs (D, n_p)."""
    fn = parametrised_global_function(mech, spec, region, branch, resolution)
    return evaluate(_value_function(fn), designs)[0][:, 0, 0]
