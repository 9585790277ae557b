"""Region extremes to a stated accuracy: the best nodes of the quadrature refined between the nodes.

A minimum (or maximum) over fixed nodes is biased: the nodes seldom lie where the extreme sits, and the
node extreme is higher (lower) than the region's by the local index's change over a node spacing. Here
the ``REFINE_STARTS`` best nodes of each design are refined by a compass search in the reference
coordinates of the region piece they belong to (``pieces()`` of :mod:`pkm.regions.shapes`): the
3^d - 1 neighbours at a step h are evaluated in one batch, the best improvement (by more than
``REFINE_GAIN`` relative, so that round-off on a plateau never leads the search) is taken, and the step
halves where there is none, down to ``REFINE_STEP``. Points that leave the reference domain are
projected back onto it (a disc's onto its rim inset, :data:`pkm.regions.shapes.RIM_INSET`), so an
extreme on the boundary is found on it. The search needs no derivative and converges to extremes at
kinks of the local index (an eigenvalue crossing) as well.

The reference domain does not depend on the design, so by the envelope theorem the extreme's gradient
in the design is the local index's at the refined reference point held fixed: one row of the node function's
Jacobian (:func:`pkm.regions.integrand.rows_function`, compiled where its kernel is built).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.regions.integrand import rows_function
from pkm.regions.region import Refinable, RegionIndex

REFINE_STARTS = 4  # best nodes refined per design
REFINE_STEP = 1e-8  # the compass search stops at this step in reference coordinates
REFINE_ITERATIONS = 400  # moves and halvings at most per start
REFINE_GAIN = 1e-12  # a move must improve the value by this much, relative: round-off never leads the search


@dataclass(frozen=True)
class Refined:
    """Refined extremes of a batch of designs: the value (D,) of the local index's extreme (NaN where the
    node extreme is undefined), and where it lies: the piece index (D,) and the reference point (D, d)."""

    values: np.ndarray
    piece: np.ndarray
    point: np.ndarray


@lru_cache(maxsize=8)
def _stencil(dimension: int) -> np.ndarray:
    steps = np.array(list(itertools.product((-1.0, 0.0, 1.0), repeat=dimension)))
    return steps[np.any(steps != 0, axis=1)]


def _starts(scores: np.ndarray, count: int) -> np.ndarray:
    """Indices (D, count) of the best nodes (smallest scores) of each design."""
    order = np.argsort(scores, axis=1, kind="stable")
    return order[:, : min(count, scores.shape[1])]


def refine(index: RegionIndex, designs: np.ndarray, *, values: np.ndarray, resolution: int) -> Refined:
    """The extreme (the index's reduction, "min" or "max") of the local index over the region for each design
    (D, n_p), refined from the best of its ``values`` (D, n) at the nodes of the extreme rule at
    ``resolution`` (NaN where a node is out of reach)."""
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    sign = 1.0 if index.reduce == "min" else -1.0
    defined = np.all(np.isfinite(values), axis=1)
    scores = np.where(np.isfinite(values), sign * values, np.inf)
    pieces = index.region.pieces()
    references = [p.reference(resolution, index.reduce)[0] for p in pieces]
    owner = np.concatenate([np.full(len(r), k) for k, r in enumerate(references)])
    offset = np.concatenate([[0], np.cumsum([len(r) for r in references])])
    dimension = references[0].shape[1]
    best = np.where(defined, scores.min(axis=1, initial=np.inf), np.nan)
    where_piece = np.zeros(len(designs), dtype=int)
    where_point = np.zeros((len(designs), dimension))
    first = np.argmin(scores, axis=1)
    for d in np.flatnonzero(defined):
        k = owner[first[d]]
        where_piece[d], where_point[d] = k, references[k][first[d] - offset[k]]
    starts = _starts(scores, REFINE_STARTS)
    step = 1.0 / (2 * resolution)
    for k, piece in enumerate(pieces):
        rows, cols = np.nonzero((owner[starts] == k) & defined[:, None])
        if not len(rows) or not getattr(piece, "refinable", True):
            continue
        nodes = starts[rows, cols]
        u = references[k][nodes - offset[k]].copy()
        f = scores[rows, nodes].copy()
        u, f = _compass(rows_function(index.mechanism, index.local, piece, None, 0)[0], piece, designs[rows],
                        signs=index.signs, sign=sign, u=u, f=f, step=step)
        for j, d in enumerate(rows):
            if f[j] < best[d]:
                best[d], where_piece[d], where_point[d] = f[j], k, u[j]
    return Refined(sign * best, where_piece, where_point)


def _compass(
    fn: ca.Function, piece: Refinable, designs: np.ndarray, *, signs: np.ndarray, sign: float, u: np.ndarray,
    f: np.ndarray, step: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Compass search from the points u (B, d) with scores f (B,) for the designs (B, n_p), ``fn`` the
    local index at the nodes (:func:`pkm.regions.integrand.rows_function`) with the working mode's ``signs``."""
    stencil = _stencil(u.shape[1])
    h = np.full(len(u), step)
    for _ in range(REFINE_ITERATIONS):
        active = np.flatnonzero(h > REFINE_STEP)
        if not len(active):
            break
        trial = u[active, None, :] + h[active, None, None] * stencil[None]
        trial = piece.project(trial.reshape(-1, u.shape[1]))
        score = sign * _padded(fn, trial, signs, np.repeat(designs[active], len(stencil), axis=0))
        score = score.reshape(len(active), len(stencil))
        score = np.where(np.isfinite(score), score, np.inf)
        pick = np.argmin(score, axis=1)
        gain = score[np.arange(len(active)), pick] < f[active] - REFINE_GAIN * np.maximum(1.0, np.abs(f[active]))
        moved, stay = active[gain], active[~gain]
        u[moved] = trial.reshape(len(active), len(stencil), -1)[np.flatnonzero(gain), pick[gain]]
        f[moved] = score[gain, pick[gain]]
        h[stay] /= 2
    return u, f


def _padded(fn: ca.Function, u: np.ndarray, signs: np.ndarray, designs: np.ndarray) -> np.ndarray:
    """The local index of ``fn`` over a batch padded to a power of two (where the interpreter evaluates,
    a few mapped functions serve every search)."""
    n = len(u)
    size = 1 << max(0, (n - 1).bit_length())
    value = evaluate(fn, np.concatenate([u, np.repeat(u[-1:], size - n, axis=0)]), signs,
                     np.concatenate([designs, np.repeat(designs[-1:], size - n, axis=0)]))[0]
    return value[:n, 0, 0]


def refined_gradient(index: RegionIndex, design: np.ndarray, *, refined: Refined) -> np.ndarray:
    """The gradient (n_p,) in the design of the refined extreme of one design (the first of ``refined``)."""
    piece = index.region.pieces()[int(refined.piece[0])]
    fn, active = rows_function(index.mechanism, index.local, piece, None, 1)
    _, jacobian = evaluate(fn, refined.point[0], index.signs, design)
    grad = np.zeros(len(design))
    grad[list(active)] = jacobian[0, 0]
    return grad
