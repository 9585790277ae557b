"""Scale-out: ``python -m bench.scale_out [--quick] [--json PATH]``.

One atlas job (the five-bar's GCI over the sampled reachable workspace in Gao's design space, every
distinct working mode, as Gao's Figs. 4-9) run serially, on a local pool of 2 processes and on a Dask LocalCluster of 2
worker processes on the loopback interface, in the same run; the values are checked equal before any
time is taken. Also the cost of a task that does nothing but travel (the per-chunk overhead of each
executor), and the throughput of the serial evaluation per design, from which docs/scale-out.md
projects larger atlases. Figures are best of ``repeats`` (pool and cluster started outside the timing;
their start-up is reported on its own). :func:`markdown` renders the table docs/benchmarks.md quotes
(tests/test_benchmark_docs.py checks it against the committed JSON).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Executor, ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import numpy as np

import pkm
from pkm import parallel, registry
from pkm.atlas import compute_atlas

MECHANISM, INDEX, SPACE, REGION = "five_bar", "gci", "gao1998", "reachable"
WORKERS = 2


def nothing(task: int) -> int:
    """A task that only travels: its cost is the executor's overhead per task."""
    return task


def _atlas(executor: Executor | str, resolution: int, pose_resolution: int, chunk: int):
    m = pkm.load(MECHANISM)
    return compute_atlas(m, registry.global_index(INDEX), space=m.design_spaces[SPACE], region=REGION,
                         resolution=resolution, pose_resolution=pose_resolution, chunk=chunk, executor=executor)


def _best(fn: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    best, out = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def _overhead(pool: Executor, tasks: int, repeats: int) -> float:
    wall, _ = _best(lambda: parallel.run_tasks(pool, nothing, list(range(tasks)), describe=str), repeats)
    return wall / tasks


def run(resolution: int, pose_resolution: int, chunk: int, repeats: int, log: Callable[[str], None]) -> dict:
    from distributed import LocalCluster

    serial_time, reference = _best(lambda: _atlas("serial", resolution, pose_resolution, chunk), repeats)
    designs = int(reference.inside.sum()) * len(reference.modes)
    tasks = sum(-(-int(reference.inside.sum()) // chunk) for _ in reference.modes)
    log(f"serial: {serial_time:.2f} s for {designs} designs in {tasks} tasks")
    rows: dict[str, Any] = {"serial": {"wall_time_s": serial_time, "startup_s": 0.0,
                                       "overhead_per_task_s": _overhead(parallel.SerialExecutor(), 200, repeats)}}
    start = time.perf_counter()
    with ProcessPoolExecutor(WORKERS, mp_context=get_context("spawn")) as pool:
        parallel.run_tasks(pool, nothing, list(range(WORKERS)), describe=str)
        startup = time.perf_counter() - start
        _atlas(pool, resolution, pose_resolution, chunk)  # each worker loads the mechanism once
        wall, atlas = _best(lambda: _atlas(pool, resolution, pose_resolution, chunk), repeats)
        _check(reference, atlas)
        rows["processes"] = {"wall_time_s": wall, "startup_s": startup,
                             "overhead_per_task_s": _overhead(pool, 200, repeats)}
    log(f"2 processes: {wall:.2f} s")
    start = time.perf_counter()
    with LocalCluster(n_workers=WORKERS, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, _DaskExecutor(cluster.scheduler_address) as pool:
        startup = time.perf_counter() - start
        _atlas(pool, resolution, pose_resolution, chunk)
        wall, atlas = _best(lambda: _atlas(pool, resolution, pose_resolution, chunk), repeats)
        _check(reference, atlas)
        rows["dask"] = {"wall_time_s": wall, "startup_s": startup, "overhead_per_task_s": _overhead(pool, 200, repeats)}
    log(f"Dask LocalCluster, 2 workers: {wall:.2f} s")
    return {
        "date": time.strftime("%Y-%m-%d"),
        "job": {"mechanism": MECHANISM, "index": INDEX, "space": SPACE, "region": REGION,
                "resolution": resolution, "pose_resolution": pose_resolution, "modes": list(reference.modes),
                "designs": designs, "chunk": chunk, "tasks": tasks,
                "nodes_per_design": reference.evaluations // designs},
        "workers": WORKERS,
        "executors": rows,
        "serial_seconds_per_design_and_mode": serial_time / designs,
    }


class _DaskExecutor:
    """A Dask client's executor as a context manager (closed at the end)."""

    def __init__(self, address: str) -> None:
        self.client = parallel.connect(address)

    def __enter__(self) -> Executor:
        return self.client.get_executor()

    def __exit__(self, *_exc: Any) -> None:
        self.client.close()


def _check(reference, atlas) -> None:
    for mode in reference.modes:
        if not np.array_equal(reference.values[mode], atlas.values[mode], equal_nan=True):
            raise AssertionError(f"the atlas of mode {mode} differs from the serial one")


def projection(report: Mapping[str, Any], designs: int, workers: int) -> float:
    """Hours for an atlas of ``designs`` design nodes (same modes and pose grid) on ``workers`` Dask
    workers, at the rate the measured Dask run reached per worker (its overhead per task, its transfers
    and its scheduler sharing the cores included): the chunks are independent, so the time divides by
    the number of workers; the cluster's start-up is not counted."""
    job = report["job"]
    measured = report["executors"]["dask"]["wall_time_s"] * report["workers"] / (job["designs"])
    return designs * len(job["modes"]) * measured / workers / 3600


def markdown(report: Mapping[str, Any]) -> str:
    job = report["job"]
    lines = [
        f"| atlas {job['mechanism']} {job['index']} over {job['region']}, {job['designs']} designs x "
        f"{job['nodes_per_design']} nodes, {job['tasks']} tasks of {job['chunk']} | wall time (s) | vs serial | "
        f"start-up (s) | overhead per task (ms) |",
        "|---|---:|---:|---:|---:|",
    ]
    serial = report["executors"]["serial"]["wall_time_s"]
    names = {"serial": "serial (this process)", "processes": f"local process pool, {report['workers']} processes",
             "dask": f"Dask LocalCluster, {report['workers']} worker processes"}
    for key, row in report["executors"].items():
        lines.append(f"| {names[key]} | {row['wall_time_s']:.2f} | {serial / row['wall_time_s']:.2f}x | "
                     f"{row['startup_s']:.2f} | {1e3 * row['overhead_per_task_s']:.3f} |")
    lines += ["", "| projection: 10^3 x 10^3 designs, same modes and quadrature | hours |", "|---|---:|"]
    for workers in (1, 10, 100):
        lines.append(f"| {workers} Dask worker{'s' if workers > 1 else ''} | "
                     f"{projection(report, 1_000_000, workers):.2f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.scale_out", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a 21 x 21 chart instead of 61 x 61")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    args = parser.parse_args(argv)
    resolution = 21 if args.quick else 61
    report = run(resolution, 32, 64, 3, lambda msg: print(msg, file=sys.stderr, flush=True))
    print(markdown(report))
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
