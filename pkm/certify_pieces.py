"""A certification in parallel (:mod:`pkm.certify`): the searched box cut into PIECES boxes by the search's own
halvings (the largest first, across its widest side), each searched by a worker of :mod:`pkm.parallel` (a local
process pool or a Dask cluster), and the verdicts joined: refuted where any box is, with every witness found;
proved where every one is; otherwise undecided with the boxes' undecided volumes summed. A box proved, or left
undecided at the depth, is the same box of the same halvings as in one search, so the verdict and the undecided
volume are one search's (up to the budget, shared by the boxes: max_boxes / PIECES each, the seconds each)."""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np

from pkm import parallel, registry
from pkm.certify import DEPTH, MAX_BOXES, SECONDS, Certificate, checked, halves, prepared, search
from pkm.errors import PkmError
from pkm.spec.machine import resolve

PIECES = 16  # boxes a parallel certification starts from, each a task


def certify(mech: Any, region: Any, design: Any = None, *, properties: Sequence[str] = ("singularity", "limits"),
            mode: str | None = None, threshold: float | None = None, depth: int = DEPTH, max_boxes: int = MAX_BOXES,
            seconds: float = SECONDS, designs: Mapping[str, Sequence[float]] | None = None,
            executor: str | Executor | None = None) -> Certificate:
    """:func:`pkm.certify.certify` over PIECES boxes on ``executor`` (:func:`pkm.parallel.executor`: a Dask
    cluster where a scheduler is set, else local processes; "serial" in this process)."""
    task = checked(mech, region, design, properties=properties, mode=mode, threshold=threshold, designs=designs)
    reference = registry.reference(mech)
    if reference is None:
        raise PkmError(f"mechanism {mech.name} violates: a registered or described machine, which a worker can "
                       "load, to certify in parallel")
    pieces = [Piece(reference, task.region, task.design.tolist(), task.properties, task.threshold, task.mode,
                    task.spans, depth, max(1, max_boxes // PIECES), seconds, lo, hi, level)
              for lo, hi, level in cut(task.dimension)]
    started = time.perf_counter()
    with parallel.executor("processes" if executor is None and parallel.scheduler() is None else executor,
                           tasks=len(pieces)) as pool:
        parts = parallel.run_tasks(pool, certify_piece, pieces, describe=Piece.describe)
    return task.certificate(mech, joined(parts, started))


def cut(dim: int) -> list[tuple[tuple[float, ...], tuple[float, ...], int]]:
    """[-1, 1]^dim cut into PIECES boxes as the search halves them, with their levels."""
    boxes = [(np.full(dim, -1.0), np.full(dim, 1.0), 0)]
    while len(boxes) < PIECES:
        lo, hi, level = boxes.pop(0)
        boxes += [(*part, level + 1) for part in halves(lo, hi)]
    return [(tuple(lo.tolist()), tuple(hi.tolist()), level) for lo, hi, level in boxes]


@dataclass(frozen=True)
class Piece:
    """One box of a parallel certification, as a worker takes it: the mechanism by its reference
    (:func:`pkm.registry.reference`), the region as given, the design, the properties and the search's budget."""

    mechanism: str
    region: Any
    design: list[float]
    properties: tuple[str, ...]
    threshold: float | None
    mode: str
    spans: dict[str, tuple[float, float]]
    depth: int
    max_boxes: int
    seconds: float
    lo: tuple[float, ...]
    hi: tuple[float, ...]
    level: int

    def describe(self) -> str:
        return f"certify the box {list(self.lo)} to {list(self.hi)}"


def certify_piece(piece: Piece) -> dict[str, Any]:
    """A worker's search of one box."""
    parallel.as_worker()
    mech = resolve(piece.mechanism)
    task = checked(mech, piece.region, np.asarray(piece.design), properties=piece.properties, mode=piece.mode,
                   threshold=piece.threshold, designs=piece.spans or None)
    return search(mech, prepared(mech, task), depth=piece.depth, max_boxes=piece.max_boxes, seconds=piece.seconds,
                  start=(np.array(piece.lo), np.array(piece.hi), piece.level))


def joined(parts: list[dict[str, Any]], started: float) -> dict[str, Any]:
    """The boxes' searches as one (their cells together)."""
    witnesses = [w for part in parts for w in part["witnesses"]]
    undecided = sum(part["undecided"] for part in parts)
    stopped = sorted({part["stopped"] for part in parts if part["stopped"]})
    return {"verdict": "refuted" if witnesses else ("proved" if undecided == 0.0 else "undecided"),
            "witnesses": witnesses, "undecided": undecided, "boxes": sum(part["boxes"] for part in parts),
            "depth": max(part["depth"] for part in parts), "seconds": time.perf_counter() - started,
            "stopped": "; ".join(stopped),
            "cells": {state: [box for part in parts for box in part["cells"][state]]
                      for state in ("proved", "undecided")}}
