"""Every public batch method of every mechanism against numpy: ``python -m bench.methods [--quick] [--json PATH]
[--repeats K]``.

For each mechanism of ``pkm.mechanisms()`` at its default design and first working mode, and each public
batch method it has (inverse and forward kinematics, J, the local index 1/kappa_f and, with dynamics, one
dynamic local index, the statics, the task-space inertia matrix and the inverse dynamics): pkm's public API
over N poses (10^6, ``--quick`` 10^5) on 1 and on 2 threads (``pkm.batch.THREADS``) against the same
mathematics written in vectorised numpy (bench/numpy_models.py), timed once.

Poses are uniform in ``m.workspace_box`` (fixed seed), kept where the working mode reaches them and where
numpy's 1/kappa_f is at least CONDITION_MARGIN: nearer a serial or parallel singularity both implementations
lose digits alike. Velocities and accelerations are drawn as bench/gantry.py draws them, wrenches as
bench/ups_pu.py. The forward kinematics takes the actuated joints of those poses and the assembly mode that
reproduces most of them, on the configurations it reproduces to REPRODUCED (the others belong to another
assembly, or lie within round-off of a forward singularity, where a root is accurate to the square root of
the rounding only); where the forward kinematics is a polynomial's real roots, numpy solves it by
``numpy.roots`` one configuration at a time, on at most ROOTS_N configurations; a machine described as data
(rrr3, delta, stewart) solves it by Newton's method from its seed table, pkm for every assembly mode at once
(:class:`pkm.kinematics.NearestSeeds`), numpy from pkm's seeds of the one assembly mode's signature
(bench/numpy_models.py), also on at most ROOTS_N configurations.

Before any timing each pkm result is checked against numpy: per pose, max |pkm - numpy| / max(1, max |numpy|)
over the pose's entries (relative to its largest, as bench/gantry.py compares forces) at most TOL, and NaN
exactly where the other has NaN; else AssertionError naming the mechanism and the method. Figures are best of
``repeats``; nothing asserts on time. :func:`markdown` renders the table.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

import pkm
import pkm.batch
import pkm.kinematics
from bench.gantry import ACCELERATION, SPEED
from bench.numpy_models import MODELS, ROOTS_PER_POSE, SEEDED
from bench.report import log, machine, write_json
from bench.throughput import set_threads

SEED = 20261125
TOL = 1e-9
CONDITION_MARGIN = 1e-2  # least numpy 1/kappa_f of a sampled pose
REPRODUCED = 1e-12  # [pose units] forward kinematics of a configuration back onto its pose
ROOTS_N = 10_000  # configurations of a forward kinematics by numpy.roots per pose or by Newton's method
WRENCH_SCALE = (100, 100, 1000, 10, 10, 10)  # [N, N m]: each component normal with this deviation
THREADS = (1, 2)
GOAL = 10.0  # issue 22: every public batch method at least 10x numpy on 2 threads

NOTES = {
    ("five_bar", "jacobian"): "numpy: bench.throughput.numpy_index, which also computes 1/kappa_f",
    ("five_bar", 'inertia_matrix(space="task")'): "numpy: bench.dynamics.numpy_pipeline, which also computes "
                                                  "M_t and 1/kappa_2(M_w)",
    ("five_bar", 'local_index("dynamic_dexterity")'): "numpy: bench.dynamics.numpy_pipeline, which also returns "
                                                      "M_t and M_w",
    ("passive_leg", "jacobian"): "numpy: bench.passive_leg.numpy_ik_jacobian_index, which also computes 1/kappa_f",
    ("ups_pu", "statics"): "numpy: bench.ups_pu.numpy_ik_jacobian_statics, which also computes J",
    ("ups_pu", 'local_index("inverse_condition_f")'): "the angles as arc lengths r theta (pkm.regions.pipeline)",
}
LIMITED = ("pkm's reach holds the machine's stated limits (Mechanism.limits: strokes, joint ranges, interference, "
           "det J's sign), which numpy's baseline does not compute")  # the note of a method of a mechanism with limits


@dataclass(frozen=True)
class Case:
    """One (mechanism, method): pkm's public call and numpy's over the same n inputs."""

    mechanism: str
    method: str
    n: int
    pkm: Callable[[], np.ndarray]
    numpy: Callable[[], np.ndarray]
    note: str = ""


def discrepancy(ours: Any, reference: Any, what: str) -> float:
    """Largest over the poses of max |ours - reference| / max(1, max |reference|) over the pose's entries;
    raises AssertionError above TOL, on NaN where the other is not NaN, and on different shapes."""
    a, b = (np.asarray(v, dtype=float) for v in (ours, reference))
    if a.shape != b.shape:
        raise AssertionError(f"{what}: pkm gives shape {a.shape}, numpy {b.shape}")
    a, b = a.reshape(len(a), -1), b.reshape(len(b), -1)
    nan = np.isnan(b)
    if not np.array_equal(np.isnan(a), nan):
        rows = int(np.count_nonzero(np.any(np.isnan(a) != nan, axis=1)))
        raise AssertionError(f"{what}: pkm and numpy have NaN in different places, at {rows} poses")
    with np.errstate(invalid="ignore"):
        diff = np.where(nan, 0.0, np.abs(a - b)).max(axis=1)
    err = float(np.max(diff / np.maximum(1.0, np.where(nan, 0.0, np.abs(b)).max(axis=1)), initial=0.0))
    if not err <= TOL:
        raise AssertionError(f"{what}: pkm differs from numpy by {err:.3g} > {TOL:g}")
    return err


def sample_poses(m: pkm.Mechanism, mode: str, n: int, rng: np.random.Generator,
                 condition: Callable[[np.ndarray], np.ndarray] | None = None) -> np.ndarray:
    """n poses (n, n_out) uniform in the default design's workspace box, reached by the working mode, with
    1/kappa_f at least CONDITION_MARGIN: numpy's, or ``condition``'s where given."""
    design = m.design()
    box, d, signs = m.workspace_box(design.vector()), dict(design), m.working_mode(mode).signs
    if condition is None:
        def condition(X: np.ndarray) -> np.ndarray:
            return MODELS[m.name].inverse_condition_f(X, d, signs)
    kept, total = [], 0
    while total < n:
        X = rng.uniform(box[:, 0], box[:, 1], size=(2 * max(n - total, 1024), m.n_out))
        X = X[m.reachable(X, design, mode=mode)]
        with np.errstate(divide="ignore", invalid="ignore"):
            X = X[condition(X) >= CONDITION_MARGIN]
        kept.append(X)
        total += len(X)
    return np.ascontiguousarray(np.concatenate(kept)[:n])


def forward_case(m: pkm.Mechanism, mode: str, X: np.ndarray) -> Case:
    """The forward kinematics of the joints of poses X on the assembly mode that reproduces most of them."""
    design, model = m.design(), MODELS[m.name]
    per_pose = m.name in ROOTS_PER_POSE | SEEDED
    candidates = X[: 4 * ROOTS_N] if per_pose else X
    q = m.inverse_kinematics(candidates, design, mode=mode)
    hits = {}
    for name in m.assemblies:
        with np.errstate(invalid="ignore"):
            error = np.max(np.abs(m.forward_kinematics(q, design, assembly=name) - candidates), axis=1)
        hits[name] = error <= REPRODUCED
    assembly = max(hits, key=lambda name: int(hits[name].sum()))
    q = np.ascontiguousarray(q[hits[assembly]][:ROOTS_N] if per_pose else q[hits[assembly]])
    signs, d = m.assembly_mode(assembly).signs, dict(design)

    def solve() -> np.ndarray:
        # pkm keeps the roots and the solutions of its last inputs: each call solves afresh
        pkm.kinematics._ROOTS.clear()
        pkm.kinematics._SOLUTIONS.clear()
        return m.forward_kinematics(q, design, assembly=assembly)

    note = (f"assembly {assembly}, on the {int(hits[assembly].sum())} of {len(candidates)} configurations it "
            f"reproduces to {REPRODUCED:g}")
    if m.name in SEEDED:
        *signature, rank = signs
        if rank != 1:
            raise ValueError(f"{m.name}: numpy's forward kinematics gives the first solution of a signature, not "
                             f"solution {rank:g} of {assembly}")
        table = m.forward.seeds.table(m.functions, design.vector())
        seeds = table[tuple(signature)]
        note += (f"; numpy: from pkm's {m.forward.tries} seeds of the assembly's signature (among the {len(seeds[0])} "
                 "of its seed table), Newton's method on the legs' loops in (passive joints, pose) as the "
                 "description states them, continued to the joints in 8 steps of 4 iterations and polished "
                 "(vectorised over configurations and seeds), the first solution of the signature by the last pose "
                 f"coordinate; pkm: the same for every signature of its seed table ({len(table)}), every assembly "
                 "mode at once (its kept solutions cleared before each call)")
        return Case(m.name, "forward_kinematics", len(q), solve, lambda: model.forward_kinematics(q, d, seeds), note)
    if per_pose:
        note += ("; numpy: numpy.roots per configuration (a Python loop) on the polynomial's vectorised "
                 "coefficients, pkm: batched companion eigenvalues (its kept roots cleared before each call)")
    return Case(m.name, "forward_kinematics", len(q), solve, lambda: model.forward_kinematics(q, d, signs[0]), note)


def mechanism_cases(name: str, n: int, rng: np.random.Generator) -> tuple[list[Case], dict[str, Any]]:
    """Every public batch method of one mechanism, and what the cases were drawn on."""
    m, model = pkm.load(name), MODELS[name]
    design = m.design()
    d, mode = dict(design), m.modes[0]
    signs = m.working_mode(mode).signs
    X = sample_poses(m, mode, n, rng)
    pairs: list[tuple[str, Callable[[], Any], Callable[[], Any]]] = [
        ("inverse_kinematics", lambda: m.inverse_kinematics(X, design, mode=mode),
         lambda: model.inverse_kinematics(X, d, signs)),
        ("jacobian", lambda: m.jacobian(X, design, mode=mode), lambda: model.jacobian(X, d, signs)),
        ('local_index("inverse_condition_f")', lambda: m.local_index("inverse_condition_f", X, design, mode=mode),
         lambda: model.inverse_condition_f(X, d, signs)),
    ]
    dynamic = [i for i in m.local_indices() if m.local_spec(i).source == "inertia"]
    if dynamic:
        index = model.dynamic_index
        if index not in dynamic:
            raise ValueError(f"{name} has the dynamic local indices {dynamic}; bench/numpy_models.py has {index}")
        pairs.append((f'local_index("{index}")', lambda: m.local_index(index, X, design, mode=mode),
                      lambda: model.dynamic(X, d, signs)))
    if hasattr(m, "statics"):
        wrench = rng.normal(size=(len(X), 6)) * WRENCH_SCALE
        pairs.append(("statics", lambda: m.statics(X, wrench, design, mode=mode).actuators,
                      lambda: model.statics(X, wrench, d)))
    if "inertia" in m.functions:
        V = rng.uniform(-SPEED, SPEED, X.shape)
        A = rng.uniform(-ACCELERATION, ACCELERATION, X.shape)
        pairs += [
            ('inertia_matrix(space="task")', lambda: m.inertia_matrix(X, design, mode=mode, space="task"),
             lambda: model.inertia_task(X, d, signs)),
            ("inverse_dynamics", lambda: m.inverse_dynamics(X, V, A, design, mode=mode),
             lambda: model.inverse_dynamics(X, V, A, d, signs)),
        ]
    if m.limits:
        pairs.insert(1, ("inverse_kinematics(limits=False)", lambda: m.inverse_kinematics(X, design, mode=mode,
                                                                                           limits=False),
                         lambda: model.inverse_kinematics(X, d, signs)))
    limited = {"inverse_kinematics", 'local_index("inverse_condition_f")', "statics"} if m.limits else set()
    cases = [Case(name, method, len(X), ours, theirs,
                  "; ".join(filter(None, [NOTES.get((name, method), ""), LIMITED if method in limited else ""])))
             for method, ours, theirs in pairs]
    cases.insert(1, forward_case(m, mode, X))
    return cases, {"mode": mode, "poses": len(X)}


def build(n: int, log: Callable[[str], None]) -> tuple[list[Case], dict[str, Any]]:
    """The cases of every registered mechanism (poses drawn with SEED), and what each was drawn on."""
    rng = np.random.default_rng(SEED)
    cases, drawn = [], {}
    for name in pkm.mechanisms():
        start = time.perf_counter()
        more, drawn[name] = mechanism_cases(name, n, rng)
        cases += more
        log(f"{name}: {len(more)} methods on {n} poses drawn in {time.perf_counter() - start:.2f} s")
    return cases, drawn


def check(cases: list[Case]) -> list[dict[str, Any]]:
    """Each case's pkm result (one call, on ``pkm.batch.THREADS`` threads) against numpy: rows without times."""
    return [{"mechanism": c.mechanism, "method": c.method, "threads": pkm.batch.THREADS, "n": c.n,
             "max_discrepancy": discrepancy(c.pkm(), c.numpy(), f"{c.mechanism} {c.method}"), "note": c.note}
            for c in cases]


def best_of(fn: Callable[[], Any], repeats: int) -> float:
    """The least wall time [s] of ``repeats`` calls of ``fn``."""
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return float(best)


def measure(cases: list[Case], repeats: int, log: Callable[[str], None]) -> list[dict[str, Any]]:
    """Rows per case and thread count: checked against numpy on that thread count, then best of ``repeats``
    after one untimed call (a graph compiles at its second evaluation, :mod:`pkm.compiled`)."""
    rows, default = [], pkm.batch.THREADS
    try:
        for c in cases:
            what = f"{c.mechanism} {c.method}"
            reference = c.numpy()
            numpy_seconds = best_of(c.numpy, repeats)
            for threads in THREADS:
                set_threads(threads)
                err = discrepancy(c.pkm(), reference, f"{what} on {threads} thread(s)")
                c.pkm()
                seconds = best_of(c.pkm, repeats)
                rows.append({"mechanism": c.mechanism, "method": c.method, "threads": threads, "n": c.n,
                             "seconds": seconds, "per_second": c.n / seconds, "numpy_seconds": numpy_seconds,
                             "ratio_vs_numpy": numpy_seconds / seconds, "max_discrepancy": err, "note": c.note})
                log(f"  {what}, {threads} thread(s): {c.n / seconds:.3g} per s, {numpy_seconds / seconds:.3g}x numpy")
    finally:
        set_threads(default)
    return rows


def run(n: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    cases, drawn = build(n, log)
    load = os.getloadavg()
    rows = measure(cases, repeats, log)
    return {
        "machine": machine(),
        "load_average_before": list(load),
        "load_average_after": list(os.getloadavg()),
        "poses": n,
        "roots_n": ROOTS_N,
        "repeats": repeats,
        "seed": SEED,
        "tolerance": TOL,
        "condition_margin": CONDITION_MARGIN,
        "default_threads": pkm.batch.THREADS,
        "mechanisms": drawn,
        "rows": rows,
    }


def _rate(per_second: float) -> str:
    for unit, size in (("M", 1e6), ("k", 1e3)):
        if per_second >= size:
            return f"{per_second / size:.3g} {unit}"
    return f"{per_second:.3g}"


def _cell(row: Mapping[str, Any] | None) -> str:
    if row is None or row.get("seconds") is None:
        return "-"
    return f"{_rate(row['per_second'])} ({row['ratio_vs_numpy']:.3g}x)"


def markdown(report: Mapping[str, Any]) -> str:
    """One table: per (mechanism, method) numpy's poses per second and pkm's on 1 and 2 threads with the ratio
    to numpy ("-" where the report has no timing, as :func:`check` gives it); notes below."""
    groups: dict[tuple[str, str], dict[int, Mapping[str, Any]]] = {}
    for row in report["rows"]:
        groups.setdefault((row["mechanism"], row["method"]), {})[row["threads"]] = row
    lines = []
    if "load_average_before" in report:
        before, after = report["load_average_before"][0], report["load_average_after"][0]
        lines += [f"{report['poses']:,} poses ({report['roots_n']:,} configurations where numpy solves a polynomial "
                  f"per pose), best of {report['repeats']}; load average (1 min) {before:.2f} before timing, "
                  f"{after:.2f} after. Default designs; working modes: "
                  + ", ".join(f"{k} {v['mode']}" for k, v in report["mechanisms"].items()) + ".", ""]
    lines += ["| mechanism | method | numpy per s | pkm 1 thread | pkm 2 threads |", "|---|---|---:|---:|---:|"]
    notes = []
    for (mechanism, method), by_threads in groups.items():
        first = next(iter(by_threads.values()))
        numpy = _rate(first["n"] / first["numpy_seconds"]) if first.get("numpy_seconds") else "-"
        lines.append(f"| {mechanism} | {method} | {numpy} | {_cell(by_threads.get(1))} | {_cell(by_threads.get(2))} |")
        if first["note"]:
            notes.append(f"- {mechanism} {method} ({first['n']:,}): {first['note']}")
    timed = [r for r in report["rows"] if r["threads"] == max(THREADS) and r.get("ratio_vs_numpy")]
    if timed:
        met = sum(r["ratio_vs_numpy"] >= GOAL for r in timed)
        lines += ["", f"{met} of the {len(timed)} (mechanism, method) pairs reach {GOAL:g}x numpy on "
                      f"{max(THREADS)} threads."]
    return "\n".join(lines + (["", *notes] if notes else []))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.methods", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^5 poses instead of 10^6")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    parser.add_argument("--repeats", type=int, default=3, metavar="K", help="best of K timed calls (default 3)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    report = run(100_000 if args.quick else 1_000_000, args.repeats, log)
    report["command"] = "python -m bench.methods " + " ".join(sys.argv[1:] if argv is None else argv)
    print(markdown(report))
    if args.json:
        write_json(Path(args.json), report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
