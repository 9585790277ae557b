"""A trajectory as a region: time is its reference coordinate, and each node knows the pose's motion.

A :class:`TrajectoryRegion` plays one or more moves (:class:`pkm.dynamics.trajectories.Trajectory`) one after
another. It is cut into :class:`TimeSegment` pieces at the moves' ends and switch times (where a trapezoidal
profile's acceleration jumps), so that the motion is smooth inside every piece. A piece maps a reference time
u in [-1, 1] to its time t = t_0 + (t_1 - t_0)(u + 1)/2 and gives, beside the pose x(t), its velocity and
acceleration (x_dot, x_ddot) there (``motion``), exact for the velocity profile: CasADi differentiates the
move's own path in t; at the piece's ends the one-sided limits of its own phase. Neither depends on the design,
so the nodes are fixed and a quantity along the trajectory is smooth in the design, and its extremes are
refined between the nodes in time (:mod:`pkm.regions.extremes`).

The measure element is dt/du = (t_1 - t_0)/2: a mean over the region is the time mean, an integral
(``reduce="integral"``) the time integral (an energy from a power). Each piece's rule is Gauss-Legendre with
``2 resolution`` points; for an extreme it adds the piece's ends and middle (zero weight), where a
trapezoidal move's efforts jump.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.dynamics.trajectories import Trajectory
from pkm.errors import PkmError
from pkm.regions.region import Array, Functions
from pkm.regions.shapes import EXTREMES, check_resolution, gauss_legendre

SWITCH_GAP = 1e-12  # [s] switch times closer than this to a piece's end cut no piece of their own


@lru_cache(maxsize=64)
def _motion_function(move: Trajectory) -> ca.Function:
    """``(t, side) -> (x, x_dot, x_ddot)`` of a move, its derivatives at a switch the limits from the right
    (side 1) or from the left (side 0)."""
    t, side = ca.SX.sym("t"), ca.SX.sym("side")
    outputs = []
    for path in (move.path, move.path_before or move.path):
        x = path(t)
        x_dot = ca.jacobian(x, t)
        outputs.append((x, x_dot, ca.jacobian(x_dot, t)))
    chosen = [ca.if_else(side > 0, after, before) for after, before in zip(*outputs, strict=True)]
    return ca.Function("move_motion", [t, side], chosen, ["t", "side"], ["x", "x_dot", "x_ddot"])


@dataclass(frozen=True)
class TimeSegment:
    """The part [start, end] [s] of one move (in the move's own time) in which its motion is smooth, at
    ``offset`` [s] in the trajectory's time."""

    move: Trajectory
    start: float
    end: float
    offset: float = 0.0

    dimension = 1
    refinable = True

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
        t, w = gauss_legendre(2 * check_resolution(resolution, 1))
        if reduce in EXTREMES:
            t, w = np.concatenate([t, [-1.0, 0.0, 1.0]]), np.concatenate([w, [0.0, 0.0, 0.0]])
        return t[:, None], w

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return len(self.reference(resolution, reduce)[1])

    def time(self, u: Array) -> Array:
        """The move's time at the reference time u (CasADi or numpy)."""
        return self.start + (self.end - self.start) * (u + 1) / 2

    def _motion(self, u: Array) -> list[Array]:
        """x, x_dot and x_ddot at the reference time u: the limits from inside the piece at its ends."""
        return _motion_function(self.move).call([self.time(u[0]), u[0] < 0])

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:  # noqa: ARG002
        return self._motion(u)[0]

    def motion(self, u: Array) -> Array:
        """(x_dot, x_ddot) at the reference time u, one column (2 n_out x 1)."""
        _, x_dot, x_ddot = self._motion(u)
        return ca.vertcat(x_dot, x_ddot)

    def element(self, functions: Functions, design: Array, u: Array) -> Array:  # noqa: ARG002
        return ca.SX((self.end - self.start) / 2)

    def project(self, u: np.ndarray) -> np.ndarray:
        return np.clip(u, -1.0, 1.0)

    def states(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Numerically at reference times u (n, 1): the trajectory's times (n,) and x, x_dot, x_ddot (n, n_out)."""
        u = np.asarray(u, dtype=float).reshape(-1, 1)
        x, x_dot, x_ddot = (v[:, :, 0] for v in evaluate(_motion_function(self.move), self.time(u),
                                                          (u < 0).astype(float)))
        return self.offset + self.time(u[:, 0]), x, x_dot, x_ddot


def _segments(move: Trajectory, offset: float) -> list[TimeSegment]:
    cuts = [0.0, *(t for t in move.switch_times if SWITCH_GAP < t < move.duration - SWITCH_GAP), move.duration]
    return [TimeSegment(move, a, b, offset) for a, b in itertools.pairwise(cuts) if b - a > SWITCH_GAP]


@dataclass(frozen=True)
class TrajectoryRegion:
    """Moves played one after another (each from where the last ends, the first at t = 0), a region of one
    reference dimension, time: its pieces are the moves' smooth phases (:class:`TimeSegment`)."""

    name: str
    doc: str
    moves: tuple[Trajectory, ...]
    guard: str | None = None

    dimension = 1
    timed = True

    def __post_init__(self) -> None:
        if not self.moves or not all(isinstance(m, Trajectory) for m in self.moves):
            raise PkmError(f"trajectory {self.name}: moves must be one or more pkm.dynamics.Trajectory")
        if len({m.dimension for m in self.moves}) != 1:
            raise PkmError(f"trajectory {self.name}: every move must have the same pose dimension")

    @property
    def duration(self) -> float:
        return float(sum(m.duration for m in self.moves))

    def pieces(self) -> tuple[TimeSegment, ...]:
        offsets = np.concatenate([[0.0], np.cumsum([m.duration for m in self.moves])])
        return tuple(s for move, offset in zip(self.moves, offsets, strict=False) for s in _segments(move, offset))

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return sum(p.node_count(resolution, reduce) for p in self.pieces())

    def nodes(self, resolution: int, reduce: str = "mean") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The trajectory's times (n,), poses (n, n_out) and weights (n,) [s] at the nodes of its rule."""
        parts = []
        for piece in self.pieces():
            u, w = piece.reference(resolution, reduce)
            times, x, _, _ = piece.states(u)
            parts.append((times, x, w * (piece.end - piece.start) / 2))
        return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):  # noqa: ARG002
        """The poses (n, n_out) at the nodes and their time weights (n,) [s], numerically (fixed in time)."""
        _, poses, weights = self.nodes(resolution, reduce)
        if isinstance(design, ca.MX | ca.SX):
            return ca.DM(poses.T), ca.DM(weights).T
        return poses, weights

    def samples(self, resolution: int, reduce: str) -> list[tuple[int, np.ndarray, np.ndarray]]:
        """Uniform samples in time for a check by sampling: per piece its index, the reference times (m, 1) at
        the midpoints of ``resolution`` equal steps (and its ends for an extreme) and each one's time step [s]."""
        out = []
        for k, piece in enumerate(self.pieces()):
            u = -1 + (2 * np.arange(resolution) + 1) / resolution
            cell = np.full(resolution, (piece.end - piece.start) / resolution)
            if reduce in EXTREMES:
                u, cell = np.concatenate([u, [-1.0, 1.0]]), np.concatenate([cell, [0.0, 0.0]])
            out.append((k, u[:, None], cell))
        return out


def trajectory_region(moves: Trajectory | Sequence[Trajectory], name: str = "trajectory",
                      doc: str | None = None) -> TrajectoryRegion:
    """A region along a move or along moves played one after another."""
    moves = (moves,) if isinstance(moves, Trajectory) else tuple(moves)
    text = doc or "; then ".join(m.description for m in moves)
    return TrajectoryRegion(name, text, moves)
