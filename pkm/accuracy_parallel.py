"""A Monte Carlo run of an error model in parallel (:meth:`pkm.accuracy.ErrorModel.monte_carlo`): each batch of
MONTE_CARLO_ROWS machines a task of :mod:`pkm.parallel` (local processes or a Dask cluster), the mechanism
carried by its reference and loaded in the worker. Each batch draws from its own stream (the seed, the pose and
the batch), so that the summed squares, joined in the batches' order, are the serial run's: the same machines,
to round-off (a batch may run on the interpreter in one process and compiled in another)."""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

import numpy as np

from pkm import parallel, registry
from pkm.accuracy import ErrorModel, batches, error_model
from pkm.errors import PkmError
from pkm.kinematics import as_batch
from pkm.spec.machine import resolve


def monte_carlo(model: ErrorModel, pose: Any, deviations: Any, design: Any = None, *, mode: str | None = None,
                samples: int = 200, seed: int = 0, executor: str | Executor | None = None) -> dict[str, np.ndarray]:
    """:meth:`pkm.accuracy.ErrorModel.monte_carlo` with its batches on ``executor`` (:func:`pkm.parallel.executor`:
    a Dask cluster where a scheduler is set, else local processes; "serial" in this process)."""
    m = model.nominal
    reference = registry.reference(m)
    if reference is None:
        raise PkmError(f"mechanism {m.name} violates: a registered or described machine, which a worker can load, "
                       "for a Monte Carlo run in parallel")
    x, _ = as_batch(pose, m.n_out, "pose")
    widths = dict(zip(model.names, model.deviations(deviations).tolist(), strict=True))
    tasks = [Draws(reference, model.attachments, model.axes, x.tolist(), widths, m.design_vector(design).tolist(),
                   m.working_mode(mode).name, samples, seed, b) for b in range(batches(samples))]
    with parallel.executor("processes" if executor is None and parallel.scheduler() is None else executor,
                           tasks=len(tasks)) as pool:
        parts = parallel.run_tasks(pool, draw, tasks, describe=Draws.describe)
    return model.sampled(x, sum(parts, np.zeros(x.shape)), deviations, design, mode=mode, samples=samples)


@dataclass(frozen=True)
class Draws:
    """One batch of a Monte Carlo run, as a worker takes it: the mechanism by its reference
    (:func:`pkm.registry.reference`), the error model's attachments and axes, the poses, the deviations by name, the
    nominal design vector, the working mode, the run's samples and seed, and the batch."""

    mechanism: str
    attachments: str
    axes: bool
    poses: list[list[float]]
    deviations: dict[str, float]
    design: list[float]
    mode: str
    samples: int
    seed: int
    batch: int

    def describe(self) -> str:
        return f"the Monte Carlo batch {self.batch} of {self.samples} machines per pose"


def draw(task: Draws) -> np.ndarray:
    """A worker's batch: its summed squared pose errors (N, n_out)."""
    model = error_model(resolve(task.mechanism), task.attachments, task.axes)
    return model.squares(np.array(task.poses), task.deviations, np.array(task.design), mode=task.mode,
                         batch=task.batch, samples=task.samples, seed=task.seed)
