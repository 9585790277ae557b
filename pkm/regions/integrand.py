"""Global indices over parametrised regions as sums of point integrands, with exact gradients and
Hessians in the design, evaluated by the compiled kernels where they are built.

A region's pieces (:mod:`pkm.regions.shapes`) carry a reference point u to the pose x(u, d) with the
measure element e(u, d); a node's weight is its reference weight w times e. With the local index f at
the pose (NaN where the node is out of reach) and ``valid`` (1 where it is reached, else 0), a global
index is a function of sums over the nodes of every piece:

    mean      S = sum w (e f, e)           value = S_0 / S_1
    std       S = sum w (e f, e f^2, e)    value = sqrt(max(0, S_1 / S_2 - (S_0 / S_2)^2))
    measure   S = sum w (e valid)          value = S_0
    integral  S = sum w (e f)              value = S_0
    rms       S = sum w (e f, e)           value = sqrt(S_0 / S_1)   (f a square)

A local index that reads the pose's motion (:func:`pkm.regions.pipeline.reads_motion`) takes it from the
piece (``piece.motion(u)``: a trajectory's velocity and acceleration at the reference time u). A local index
with a ``smooth`` stand-in integrates it instead of its formula where ``smooth`` is asked (the optimiser's
quadrature, :func:`pkm.regions.quadrature.quadrature_value`); every reported value takes the formula.

:func:`sum_function` is the integrand w c(u, d) of these components as one SX function of
``(u, w, mode, design)``, with (``order`` 1) its Jacobian and (``order`` 2) the lower triangle of its
Hessian in the design entries it depends on: :mod:`pkm.compiled` compiles each as a C kernel that sums
it over a block of nodes, so that one compiled function serves every resolution. :func:`rows_function` is
the same with one value per node: the local index itself, or for a region extreme the epigraph margin
g(u, d, t) >= 0 (:func:`pkm.indices.epigraph_function`).

:class:`Smooth` wraps a numeric evaluation of such sums or rows (values, Jacobian, Hessians) as a CasADi
function with exact first and second derivatives: the syntheses' NLP and the global indices compose it,
so that IPOPT's objective, constraints, gradient and Hessian are evaluated by the kernels.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate, total
from pkm.errors import PkmError
from pkm.indices import LocalIndex, epigraph_function
from pkm.regions.pipeline import PipelineModel, pipeline
from pkm.regions.region import Array, Piece, RegionIndex

COMPONENTS = {"mean": ("e f", "e"), "std": ("e f", "e f^2", "e"), "measure": ("e valid",), "integral": ("e f",),
              "rms": ("e f", "e")}
SUMMED = tuple(COMPONENTS)

Derivatives = tuple[np.ndarray, np.ndarray | None, np.ndarray | None]


def _name(mech: PipelineModel, local: LocalIndex, what: str, order: int) -> str:
    return f"{mech.name}_{local.name}_{what}_{order}"


def _cheaper_jacobian(inputs: list[ca.SX], values: ca.SX, za: ca.SX) -> ca.SX:
    """The Jacobian of ``values`` in ``za`` by forward or by reverse mode, whichever graph has fewer
    instructions (casadi.jacobian's own choice goes by the sizes alone)."""
    forward = ca.jacobian(values, za)
    reverse = ca.jtimes(values, za, ca.SX.eye(values.numel()), True).T
    size = [ca.Function("j", inputs, [values, ca.densify(j)]).n_instructions() for j in (forward, reverse)]
    return forward if size[0] <= size[1] else reverse


def _with_derivatives(
    name: str, inputs: dict[str, ca.SX], values: ca.SX, z: ca.SX, *, order: int
) -> tuple[ca.Function, tuple[int, ...]]:
    """``values`` (m x 1) as a function of ``inputs`` (by name), with its Jacobian (m x a) and the lower triangles
    of its Hessians (m x a(a+1)/2, row by row) in the ``a`` entries of ``z`` it depends on, up to
    ``order``; and the positions of those entries in z."""
    active = tuple(k for k, depends in enumerate(ca.which_depends(values, z, 1, False)) if depends)
    za = ca.vertcat(*[z[k] for k in active])
    outputs, out_names = [values], ["value"]
    if order >= 1:
        jacobian = _cheaper_jacobian(list(inputs.values()), values, za)
        outputs.append(ca.densify(jacobian))
        out_names.append("jacobian")
    if order >= 2:
        m = values.numel()
        second = ca.jacobian(ca.vec(jacobian), za)
        pairs = [(j, k) for j in range(len(active)) for k in range(j + 1)]
        rows = [ca.horzcat(*[second[i + m * j, k] for j, k in pairs]) for i in range(m)]
        outputs.append(ca.densify(ca.vertcat(*rows)))
        out_names.append("hessian")
    return ca.Function(name, list(inputs.values()), outputs, list(inputs), out_names), active


def _symbols(mech: PipelineModel, piece: Piece) -> tuple[ca.SX, ca.SX, ca.SX]:
    ik = mech.functions["inverse_kinematics"]
    return (ca.SX.sym("u", piece.dimension), ca.SX.sym("mode", ik.numel_in(1)), ca.SX.sym("design", ik.numel_in(2)))


def fused(mech: PipelineModel, locals_: tuple[LocalIndex, ...], piece: Piece, *, design: ca.SX, u: ca.SX, mode: ca.SX,
          **options: bool) -> list[ca.SX]:
    """The outputs of :func:`pkm.regions.pipeline.pipeline` (reached where the mechanism assembles) at the
    piece's reference point u, with the piece's motion there where an index reads it."""
    fn = pipeline(mech, locals_, assembled=True, **options)
    args = [piece.to_pose(mech.functions, design, u), mode, design]
    if fn.n_in() == 4:
        motion = getattr(piece, "motion", None)
        if motion is None:
            raise PkmError(f"the local index {locals_[0].name} reads the motion, which a region has only along a "
                           "trajectory (pkm.regions.TrajectoryRegion)")
        args.append(motion(u))
    return fn(*args)


@lru_cache(maxsize=512)
def sum_function(
    mech: PipelineModel, local: LocalIndex, piece: Piece, reduce: str, order: int, *, smooth: bool = False
) -> tuple[ca.Function, tuple[int, ...]]:
    """SX ``(u, w, mode, design) -> (value, jacobian, hessian)`` of the integrand w c(u, d) of the
    reduction ``reduce`` (module docstring) up to ``order``, and the design entries it depends on; with
    ``smooth``, of the local index's smooth stand-in where it has one."""
    u, mode, design = _symbols(mech, piece)
    w = ca.SX.sym("w")
    e = piece.element(mech.functions, design, u)
    _, _, valid, f = fused(mech, (local,), piece, design=design, u=u, mode=mode, smooth=smooth)
    components = {"mean": [e * f, e], "std": [e * f, e * f * f, e], "measure": [e * valid], "integral": [e * f],
                  "rms": [e * f, e]}[reduce]
    return _with_derivatives(_name(mech, local, f"{reduce}_integrand{'_smooth' if smooth else ''}", order),
                             {"u": u, "w": w, "mode": mode, "design": design}, w * ca.vertcat(*components), design,
                             order=order)


@lru_cache(maxsize=512)
def rows_function(
    mech: PipelineModel, local: LocalIndex, piece: Piece, epigraph: str | None, order: int
) -> tuple[ca.Function, tuple[int, ...]]:
    """SX ``(u, mode, design) -> (value, jacobian, hessian)`` of the local index at a node and whether the
    node is reached (1 or 0), or with
    ``epigraph`` (the region's reduction, ``"min"`` or ``"max"``) SX ``(u, mode, design, t) -> ...`` of
    the node's epigraph margin, >= 0 where the index is at least t (at most t for a maximum); the
    derivatives are in (design, t)."""
    u, mode, design = _symbols(mech, piece)
    if epigraph is None:
        _, _, valid, f = fused(mech, (local,), piece, design=design, u=u, mode=mode)
        return _with_derivatives(_name(mech, local, "node", order), {"u": u, "mode": mode, "design": design},
                                 ca.vertcat(f, valid), design, order=order)
    t = ca.SX.sym("t")
    _, _, _, _, *matrices = fused(mech, (local,), piece, design=design, u=u, mode=mode, matrices=True)
    shapes = tuple(m.shape for m in matrices)
    g = epigraph_function(local, shapes, epigraph == "max")(*matrices, t)
    return _with_derivatives(_name(mech, local, f"{epigraph}_epigraph", order),
                             {"u": u, "mode": mode, "design": design, "t": t}, g, ca.vertcat(design, t), order=order)


def _unpack(lower: np.ndarray, active: tuple[int, ...], size: int) -> np.ndarray:
    """Hessians (m, size, size) from their lower triangles (m, a(a+1)/2) in the active entries."""
    rows, cols = np.tril_indices(len(active))
    idx = np.asarray(active, dtype=int)
    full = np.zeros((len(lower), size, size))
    full[:, idx[rows], idx[cols]] = lower
    full[:, idx[cols], idx[rows]] = lower
    return full


@lru_cache(maxsize=256)
def reference(piece: Piece, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
    """A region piece's reference nodes (n, d) and weights (n,) for a reduction's rule, computed once (read
    only): a solver asks for them at every evaluation."""
    nodes, weights = piece.reference(resolution, reduce)
    for array in (nodes, weights):
        array.setflags(write=False)
    return nodes, weights


def region_sums(
    index: RegionIndex, *, design: np.ndarray, resolution: int, order: int, smooth: bool = False
) -> Derivatives:
    """The sums S (k,) of the index's reduction over the region's nodes for one design (n_p,), with
    their Jacobian (k, n_p) and Hessians (k, n_p, n_p) up to ``order`` (with ``smooth``, of the local
    index's smooth stand-in, :func:`sum_function`)."""
    k, p = len(COMPONENTS[index.reduce]), len(design)
    sums = np.zeros(k)
    jacobian = np.zeros((k, p)) if order >= 1 else None
    hessian = np.zeros((k, p, p)) if order >= 2 else None
    for piece in index.region.pieces():
        nodes, weights = reference(piece, resolution, index.reduce)
        fn, active = sum_function(index.mechanism, index.local, piece, index.reduce, order, smooth=smooth)
        out = total(fn, nodes, weights[:, None], index.signs, design)
        sums += out[0][:, 0]
        if order >= 1:
            jacobian[:, list(active)] += out[1]
        if order >= 2:
            hessian += _unpack(out[2], active, p)
    return sums, jacobian, hessian


def region_rows(
    index: RegionIndex, *, z: np.ndarray, resolution: int, order: int, epigraph: bool,
    rows: Sequence[int] | None = None,
) -> Derivatives:
    """At every node of the region's rule for the index's reduction, in node order: the local index and then
    whether the node is reached (2n values), or with ``epigraph`` the epigraph margins (n values, z = (design,
    t)); with the Jacobian (values, len(z)) and the Hessians (values, len(z), len(z)) up to ``order``.
    With ``rows``, only those values, evaluated at their nodes alone."""
    mech, local, reduce, signs = index.mechanism, index.local, index.reduce, index.signs
    pieces = [(piece, reference(piece, resolution, reduce)[0]) for piece in index.region.pieces()]
    count = sum(len(nodes) for _, nodes in pieces)
    m = rows_function(mech, local, pieces[0][0], reduce if epigraph else None, 0)[0].numel_out(0)
    wanted = np.arange(m * count) if rows is None else np.asarray(rows, dtype=int)
    node, output = wanted % count, wanted // count
    taken = np.unique(node)
    values, jacobians, hessians = [], [], []
    offset = 0
    for piece, nodes in pieces:
        local_nodes = taken[(taken >= offset) & (taken < offset + len(nodes))] - offset
        offset += len(nodes)
        if not len(local_nodes):
            continue
        fn, active = rows_function(mech, local, piece, reduce if epigraph else None, order)
        at = nodes[local_nodes]
        out = evaluate(fn, *((at, signs, z[:-1], z[-1:]) if epigraph else (at, signs, z)))
        values.append(out[0][:, :, 0])
        if order >= 1:
            jacobian = np.zeros((*out[1].shape[:2], len(z)))
            jacobian[:, :, list(active)] = out[1]
            jacobians.append(jacobian)
        if order >= 2:
            n, k, t = out[2].shape
            hessians.append(_unpack(out[2].reshape(n * k, t), active, len(z)).reshape(n, k, len(z), len(z)))
    position = np.searchsorted(taken, node)

    def picked(parts: list[np.ndarray]) -> np.ndarray:
        return np.concatenate(parts)[position, output]

    return (picked(values), picked(jacobians) if order >= 1 else None, picked(hessians) if order >= 2 else None)


def point_rows(
    index: RegionIndex, *, z: np.ndarray, points: Sequence[tuple[int, tuple[float, ...]]], order: int
) -> Derivatives:
    """The epigraph margins (z = (design, t)) at given points of the region, each a piece's index and a
    reference point (the reference domain does not depend on the design): every output of the first
    point, then of the second, and so on; with the Jacobian and the Hessians in z up to ``order``."""
    pieces = index.region.pieces()
    owner = np.array([k for k, _ in points], dtype=int)
    at = np.array([u for _, u in points], dtype=float)
    values: list[np.ndarray] = [np.empty(0)] * len(points)
    jacobians: list[np.ndarray] = [np.empty(0)] * len(points)
    hessians: list[np.ndarray] = [np.empty(0)] * len(points)
    for k in np.unique(owner):
        fn, active = rows_function(index.mechanism, index.local, pieces[k], index.reduce, order)
        mine = np.flatnonzero(owner == k)
        out = evaluate(fn, at[mine], index.signs, z[:-1], z[-1:])
        for j, row in enumerate(mine):
            values[row] = out[0][j, :, 0]
            if order >= 1:
                jacobian = np.zeros((out[1].shape[1], len(z)))
                jacobian[:, list(active)] = out[1][j]
                jacobians[row] = jacobian
            if order >= 2:
                hessians[row] = _unpack(out[2][j], active, len(z))
    return (np.concatenate(values), np.concatenate(jacobians) if order >= 1 else None,
            np.concatenate(hessians) if order >= 2 else None)


def point_values(
    index: RegionIndex, design: np.ndarray, points: Sequence[tuple[int, tuple[float, ...]]]
) -> np.ndarray:
    """The local index (n,) at given points of the region for one design (n_p,), each a piece's index and a
    reference point: NaN where a point is out of reach."""
    pieces = index.region.pieces()
    values = []
    for k, u in points:
        fn = rows_function(index.mechanism, index.local, pieces[k], None, 0)[0]
        value, reached = np.asarray(fn(np.array(u), index.signs, design)).ravel()
        values.append(value if reached > 0 else np.nan)
    return np.array(values)


BATCH_ROWS = 1 << 16  # rows (nodes times designs) per evaluation of a batch of designs


def _design_batches(designs: np.ndarray, nodes: int) -> list[np.ndarray]:
    return np.array_split(designs, -(-len(designs) * nodes // BATCH_ROWS)) if len(designs) else []


def batch_sums(index: RegionIndex, *, designs: np.ndarray, resolution: int) -> np.ndarray:
    """The sums (D, k) of the index's reduction over the region's nodes for each of the designs (D, n_p):
    the nodes of each design are one group of the summing kernel (one design is shared by the nodes)."""
    if len(designs) == 1:
        return region_sums(index, design=designs[0], resolution=resolution, order=0)[0][None]
    sums = np.zeros((len(designs), len(COMPONENTS[index.reduce])))
    for piece in index.region.pieces():
        nodes, weights = reference(piece, resolution, index.reduce)
        fn, _ = sum_function(index.mechanism, index.local, piece, index.reduce, 0)
        parts = []
        for batch in _design_batches(designs, len(nodes)):
            (value,) = total(fn, np.tile(nodes, (len(batch), 1)), np.tile(weights, len(batch))[:, None],
                             index.signs, np.repeat(batch, len(nodes), axis=0), group=len(nodes))
            parts.append(value[:, :, 0])
        sums += np.concatenate(parts)
    return sums


def batch_rows(index: RegionIndex, *, designs: np.ndarray, resolution: int) -> tuple[np.ndarray, np.ndarray]:
    """The local index (D, n) at the nodes of the region's rule for the index's reduction and whether each is
    reached (D, n), for each of the designs (D, n_p)."""
    values, reached = [], []
    for piece in index.region.pieces():
        nodes, _ = reference(piece, resolution, index.reduce)
        fn, _ = rows_function(index.mechanism, index.local, piece, None, 0)
        parts = [evaluate(fn, np.tile(nodes, (len(batch), 1)), index.signs, np.repeat(batch, len(nodes), axis=0))[0]
                 .reshape(len(batch), len(nodes), 2) for batch in _design_batches(designs, len(nodes))]
        out = np.concatenate(parts)
        values.append(out[:, :, 0])
        reached.append(out[:, :, 1])
    return np.concatenate(values, axis=1), np.concatenate(reached, axis=1)


def reduce_sums(sums: Array, reduce: str) -> Array:
    """A global index from the sums of its reduction's components (module docstring): CasADi, or numpy
    arrays (k, ...)."""
    if reduce == "mean":
        return sums[0] / sums[1]
    sqrt, fmax = (np.sqrt, np.fmax) if isinstance(sums, np.ndarray) else (ca.sqrt, ca.fmax)
    if reduce == "std":
        return sqrt(fmax(0, sums[1] / sums[2] - (sums[0] / sums[2]) ** 2))
    if reduce == "rms":
        return sqrt(sums[0] / sums[1])
    return sums[0]


def reduce_gradient(sums: np.ndarray, jacobian: np.ndarray, reduce: str) -> np.ndarray:
    """The gradient (n_p,) of :func:`reduce_sums` from the sums (k,) and their Jacobian (k, n_p) in the
    design (the deviation's gradient 0 where its variance is clipped at 0, as CasADi's fmax gives it)."""
    if reduce in ("mean", "rms"):
        gradient = (jacobian[0] - sums[0] / sums[1] * jacobian[1]) / sums[1]
        if reduce == "mean":
            return gradient
        root = np.sqrt(sums[0] / sums[1])
        return gradient / (2 * root) if root > 0 else np.zeros_like(gradient)
    if reduce == "std":
        mean = sums[0] / sums[2]
        d_mean = (jacobian[0] - mean * jacobian[2]) / sums[2]
        variance = sums[1] / sums[2] - mean**2
        d_variance = (jacobian[1] - sums[1] / sums[2] * jacobian[2]) / sums[2] - 2 * mean * d_mean
        return d_variance / (2 * np.sqrt(variance)) if variance > 0 else np.zeros_like(d_variance)
    return jacobian[0]


class _Cached:
    """The last evaluation of a numeric function ``(z, order) -> Derivatives``, reused by lower orders."""

    def __init__(self, fn: Callable[[np.ndarray, int], Derivatives]) -> None:
        self.fn = fn
        self.key: bytes | None = None
        self.order = -1
        self.result: Derivatives | None = None

    def __call__(self, z: np.ndarray, order: int) -> Derivatives:
        key = z.tobytes()
        if key != self.key or order > self.order:
            self.result = self.fn(z, order)
            self.key, self.order = key, order
        return self.result


class Smooth(ca.Callback):
    """A CasADi function z (n x 1) -> y (m x 1) evaluated by ``fn(z, order) -> (y (m,), J (m, n),
    H (m, n, n))``, whose Jacobian (``level`` 1) and the Jacobian of that (``level`` 2, the Hessians) are
    Smooth functions of their own, so that CasADi and IPOPT use its exact derivatives."""

    def __init__(self, name: str, fn: Callable[[np.ndarray, int], Derivatives] | _Cached, n: int, m: int,
                 level: int = 0) -> None:
        ca.Callback.__init__(self)
        self.fn = fn if isinstance(fn, _Cached) else _Cached(fn)
        self.n, self.m, self.level = n, m, level
        self.derivative: Smooth | None = None
        self.construct(f"{name}_d{level}" if level else name, {})

    def get_n_in(self) -> int:
        return 1 + self.level

    def get_n_out(self) -> int:
        return max(1, self.level)

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return [ca.Sparsity.dense(self.n, 1), ca.Sparsity.dense(self.m, 1), ca.Sparsity.dense(self.m, self.n)][i]

    def get_sparsity_out(self, j: int) -> ca.Sparsity:
        if self.level == 0:
            return ca.Sparsity.dense(self.m, 1)
        if self.level == 1:
            return ca.Sparsity.dense(self.m, self.n)
        return ca.Sparsity.dense(self.m * self.n, self.n) if j == 0 else ca.Sparsity(self.m * self.n, self.m)

    def has_eval_buffer(self) -> bool:
        return True

    def eval_buffer(self, arg: list[memoryview], res: list[memoryview]) -> int:
        """The outputs written into CasADi's buffers (column-major), without a DM between."""
        y, jacobian, hessian = self.fn(np.frombuffer(arg[0], dtype=float).copy(), self.level)
        out = None if res[0] is None else np.frombuffer(res[0], dtype=float)
        if out is None or not out.size:
            return 0
        if self.level == 0:
            out[:] = y
        elif self.level == 1:
            out[:] = jacobian.T.ravel()
        else:
            out[:] = hessian.transpose(1, 0, 2).reshape(self.m * self.n, self.n).T.ravel()
        return 0

    def has_jacobian(self) -> bool:
        return self.level < 2

    def get_jacobian(self, *_: Any) -> ca.Function:
        if self.derivative is None:
            self.derivative = Smooth(self.name().removesuffix(f"_d{self.level}"), self.fn, self.n, self.m,
                                     self.level + 1)
        return self.derivative
