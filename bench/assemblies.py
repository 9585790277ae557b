"""Every real assembly of a planar machine (issue 39's speed): ``python -m bench.assemblies [--json PATH]``.

The described 3-RRR's complete forward kinematics (``Mechanism.every_assembly``: the sextic in the platform
angle from its compiled ``platform_circles``, the real companion matrices' eigenvalues batched on
``pkm.batch.THREADS`` threads, every root polished)
at the actuated joints of POSES random reachable poses, against the baseline in the same run: numpy's
companion-matrix roots one pose at a time (``numpy.roots`` of the same sextic, whose coefficients pkm's own
function gives, then the same recovery and polish), on POSES_BASELINE of them; the certified count
(``certify=True``, python-flint) on CERTIFIED of them. Both give the same assemblies (checked before timing).
Nothing asserts on time.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

import pkm
from bench import json_main
from bench.report import machine
from pkm import assemblies, batch
from pkm.batch import evaluate
from pkm.models.described import DESCRIPTIONS

POSES = 100_000
POSES_BASELINE = 2_000
CERTIFIED = 2_000
GOAL = 100_000  # poses per second on 2 threads (issue 39)
SEED = 20261129
REPEATS = 3  # pkm's batch is timed as the best of these


def _joints(m: Any, count: int) -> np.ndarray:
    rng = np.random.default_rng(SEED)
    x = rng.uniform([-0.25, -0.25, -0.5], [0.25, 0.25, 0.5], size=(2 * count, 3))
    q = m.inverse_kinematics(x)
    return q[np.isfinite(q).all(axis=1)][:count]


def _one_at_a_time(m: Any, q: np.ndarray) -> np.ndarray:
    """Each pose's assembly count by numpy.roots of its sextic, then pkm's recovery, polish and check."""
    design = m.design().vector()
    counts = np.zeros(len(q), dtype=int)
    (points,) = evaluate(m.functions["platform_points"], design)
    for k, row in enumerate(q):
        centres, radii = evaluate(m.functions["platform_circles"], row[None], design)
        samples = 2 * np.pi * np.arange(assemblies.SAMPLES) / assemblies.SAMPLES
        f, *_ = assemblies._terms(samples[None], centres, radii[:, :, 0], points[0])
        harmonics = np.fft.fft(f[0]) / assemblies.SAMPLES
        z = np.roots(harmonics[[j % assemblies.SAMPLES for j in range(3, -4, -1)]])
        phi = np.angle(z[np.abs(np.abs(z) - 1) <= assemblies.ON_CIRCLE])[None]
        _, num, det, *_ = assemblies._terms(phi, centres, radii[:, :, 0], points[0])
        x = np.concatenate([num / det[..., None], phi[..., None]], axis=-1)
        for _ in range(assemblies.NEWTON_STEPS):
            x = assemblies._newton_step(x, centres, radii[:, :, 0], points[0])
        counts[k] = int(np.sum(assemblies._residual(x, centres, radii[:, :, 0], points[0]) <= assemblies.CLOSURE))
    return counts


def run(*, log: Any = print) -> dict[str, Any]:
    m = pkm.load(str(DESCRIPTIONS["rrr3"]))
    q = _joints(m, POSES)
    m.every_assembly(q[:100])
    pkm_s = np.inf
    for _ in range(REPEATS):
        start = time.perf_counter()
        found = m.every_assembly(q)
        pkm_s = min(pkm_s, time.perf_counter() - start)
    start = time.perf_counter()
    baseline = _one_at_a_time(m, q[:POSES_BASELINE])
    baseline_s = time.perf_counter() - start
    if not np.array_equal(baseline, found.counts[:POSES_BASELINE]):
        raise AssertionError("numpy.roots one pose at a time and every_assembly differ in their counts")
    start = time.perf_counter()
    certified = m.every_assembly(q[:CERTIFIED], certify=True)
    certified_s = time.perf_counter() - start
    rate = len(q) / pkm_s
    log(f"every_assembly: {rate:,.0f} poses/s; numpy.roots one at a time {POSES_BASELINE / baseline_s:,.0f}; "
        f"certified {CERTIFIED / certified_s:,.0f}")
    return {"command": "python -m bench.assemblies --json docs/benchmarks/assemblies.json", "machine": machine(),
            "poses": len(q), "threads": batch.THREADS, "pkm_poses_per_s": rate, "baseline_poses": POSES_BASELINE,
            "baseline_poses_per_s": POSES_BASELINE / baseline_s, "certified_poses": CERTIFIED,
            "certified_poses_per_s": CERTIFIED / certified_s, "certified_all": bool(certified.certified.all()),
            "counts": {str(k): int(v) for k, v in enumerate(np.bincount(found.counts, minlength=7))}}


def markdown(data: dict[str, Any]) -> str:
    counts = ", ".join(f"{v:,} with {k}" for k, v in data["counts"].items() if v)
    return "\n".join([
        f"Command: `{data['command']}` ({data['machine']['date']}, {data['machine']['cpu']}, "
        f"{data['machine']['cores']} cores). The described 3-RRR at the actuated joints of {data['poses']:,} random "
        f"reachable poses: {counts} real assemblies.", "",
        "| method | poses | poses/s |", "|---|---:|---:|",
        f"| pkm `every_assembly` (batched, best of {REPEATS}) | {data['poses']:,} | {data['pkm_poses_per_s']:,.0f} |",
        f"| numpy.roots one pose at a time (baseline) | {data['baseline_poses']:,} | "
        f"{data['baseline_poses_per_s']:,.0f} |",
        f"| pkm `every_assembly(certify=True)` | {data['certified_poses']:,} | {data['certified_poses_per_s']:,.0f} |",
        "",
        f"pkm is {data['pkm_poses_per_s'] / data['baseline_poses_per_s']:.0f}x the baseline; the goal of "
        f"{GOAL:,} poses/s on {data['threads']} threads is {'met' if data['pkm_poses_per_s'] >= GOAL else 'not met'} "
        "(numpy's batched loops and LAPACK, the rows in a block per thread). Every certified count equals the "
        f"sextic's: {'yes' if data['certified_all'] else 'no'}.",
    ]) + "\n"


def main(argv: list[str] | None = None) -> int:
    return json_main("python -m bench.assemblies", __doc__, run, markdown, argv)


if __name__ == "__main__":
    raise SystemExit(main())
