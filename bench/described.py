"""The machines described as data (issue 24's benchmark): ``python -m bench.described --out PATH [--poses N]
[--repeats K]``.

For each described machine (pkm/models/described: rrr3, delta, stewart):

* **derivation** from an empty cache: a new process with ``PKM_CACHE_DIR`` a new, empty folder imports pkm,
  loads the machine by name (``pkm.load``), asks for its functions (the first use: the derivation of its
  module, ``python -m symbolic.describe``, into ``<cache>/descriptions/``, then its CasADi functions built
  from it) and calls ``inverse_kinematics`` once at its home pose; then **load from the warm cache**: another
  new process with the same folder does the same and finds the module derived;
* **compiled 1/kappa_f**: ``local_index("inverse_condition_f")`` at N reachable poses (10^6; bench.methods'
  sampling: uniform in the default design's workspace box, reached by the first working mode, numpy's
  1/kappa_f at least 1e-2) on 1 and 2 threads (``pkm.batch.THREADS``, as bench.methods sets it) against
  the hand-written numpy baseline of the same maths from the pose (bench/numpy_models.py: tests/oracles.py's
  inverse kinematics and J, J normalised by the characteristic length, 1/kappa_f by the Frobenius norm),
  checked to agree first (bench.methods.discrepancy), one untimed call, then the best of ``repeats``;
* **synthesis**: each registered synthesis of the machine, ``pkm.synthesize`` at its defaults run twice in
  this process (the first compiles what the kernel cache lacks; the second is reported): its wall time
  (screening, IPOPT, polishing, verification; the baselines after it are not included), evaluations and
  verified objective, and its baseline's (the problem's own: a grid or Monte Carlo, run by the driver on
  the same model): wall time, evaluations and best objective.

Nothing asserts on time: :func:`markdown` renders the figures beside the issue's goals.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

import pkm
from bench import methods
from bench.numpy_models import MODELS
from bench.run import log, machine, write_json
from bench.throughput import set_threads
from pkm import registry
from pkm.models.described import DESCRIPTIONS

ROOT = Path(__file__).resolve().parent.parent
SEED = 20261126
POSES = 1_000_000
THREADS = (1, 2)
DERIVATION_GOAL_S = {"rrr3": 30.0, "delta": 30.0, "stewart": 120.0}  # issue 24: 3-DOF machines, Stewart platform
RATIO_GOAL = 10.0  # issue 24: compiled local_index against numpy on 2 threads

CHILD = """
import json, sys, time
start = time.perf_counter()
import numpy as np
import pkm
out = {"import_s": time.perf_counter() - start}
start = time.perf_counter()
m = pkm.load(sys.argv[1])
out["load_s"] = time.perf_counter() - start
start = time.perf_counter()
m.functions["inverse_kinematics"]
out["functions_s"] = time.perf_counter() - start
design = m.design()
home = np.asarray(m.functions["home"](design.vector())).ravel()
start = time.perf_counter()
q = m.inverse_kinematics(home, design)
out["first_inverse_kinematics_s"] = time.perf_counter() - start
out["home"], out["q"] = home.tolist(), np.asarray(q).tolist()
print(json.dumps(out))
"""


SPIN = "import time\nx = 0\nfor i in range(20_000_000):\n    x += i\nprint(time.process_time())"


def cores_available(processes: int = 2) -> float:
    """The CPUs this run gets: ``processes`` busy Python processes started at once, their CPU time over the
    wall time of all (2.0 on an idle 2-core machine; less where other work holds a core)."""
    start = time.perf_counter()
    spinning = [subprocess.Popen([sys.executable, "-c", SPIN], stdout=subprocess.PIPE, text=True)
                for _ in range(processes)]
    cpu = sum(float(p.communicate()[0]) for p in spinning)
    return cpu / (time.perf_counter() - start)


def _child(name: str, cache: Path) -> dict[str, Any]:
    """One new process loading ``name`` with the kernel cache at ``cache``: its timings and its whole wall time."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", CHILD, name], cwd=ROOT, capture_output=True, text=True, check=False,
                          env={**os.environ, "PKM_CACHE_DIR": str(cache)})
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"loading {name} with the cache {cache} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return {**json.loads(done.stdout.strip().splitlines()[-1]), "process_s": wall}


def derivation(name: str) -> dict[str, Any]:
    """Derivation from an empty cache, then load from the warm cache, each in a new process."""
    with tempfile.TemporaryDirectory(prefix=f"pkm-described-{name}-") as folder:
        cache = Path(folder)
        cold = _child(name, cache)
        derived = sorted(p.name for p in (cache / "descriptions").glob(f"{name}_*.py"))
        warm = _child(name, cache)
    log(f"{name}: derived from an empty cache in {_derivation_s(cold):.2f} s (first IK "
        f"{cold['first_inverse_kinematics_s']:.3f} s); from the warm cache {_warm_s(warm):.3f} s")
    return {"empty_cache": cold, "warm_cache": warm, "derived_modules": derived}


def _derivation_s(child: Mapping[str, Any]) -> float:
    """``pkm.load`` and the first use of the functions (the derivation where the cache is empty)."""
    return child["load_s"] + child["functions_s"]


def _warm_s(child: Mapping[str, Any]) -> float:
    """``pkm.load``, the functions and the first inverse kinematics."""
    return _derivation_s(child) + child["first_inverse_kinematics_s"]


def local_index(name: str, n: int, repeats: int, rng: np.random.Generator) -> dict[str, Any]:
    """Compiled 1/kappa_f at n reachable poses against numpy, on 1 and 2 threads (module docstring)."""
    m, model = pkm.load(name), MODELS[name]
    design = m.design()
    mode = m.modes[0]
    d, signs = dict(design), m.working_mode(mode).signs
    X = methods.sample_poses(m, mode, n, rng)

    def ours() -> np.ndarray:
        return m.local_index("inverse_condition_f", X, design, mode=mode)

    def theirs() -> np.ndarray:
        return model.inverse_condition_f(X, d, signs)

    reference = theirs()
    numpy_s = methods.best_of(theirs, repeats)
    out: dict[str, Any] = {"mode": mode, "poses": len(X), "numpy_s": numpy_s, "threads": {}}
    default = pkm.batch.THREADS
    try:
        for threads in THREADS:
            set_threads(threads)
            err = methods.discrepancy(ours(), reference, f"{name} inverse_condition_f on {threads} thread(s)")
            ours()
            seconds = methods.best_of(ours, repeats)
            out["threads"][str(threads)] = {"seconds": seconds, "ratio_vs_numpy": numpy_s / seconds,
                                            "max_discrepancy": err}
            log(f"{name} 1/kappa_f on {threads} thread(s): {len(X) / seconds / 1e6:.3g} M/s, "
                f"{numpy_s / seconds:.3g}x numpy ({len(X) / numpy_s / 1e6:.3g} M/s)")
    finally:
        set_threads(default)
    return out


def synthesis(problem: Any) -> dict[str, Any]:
    """A registered synthesis, second call in the process, with its baseline."""
    start = time.perf_counter()
    pkm.synthesize(problem, progress=False)
    first = time.perf_counter() - start
    start = time.perf_counter()
    result = pkm.synthesize(problem, progress=False)
    whole = time.perf_counter() - start
    base = next(iter(result.baselines.values()))
    out = {
        "doc": problem.doc,
        "status": result.status,
        "first_call_s": first,
        "whole_call_s": whole,
        "wall_time_s": result.optimizer["wall_time_s"],
        "evaluations": result.optimizer["evaluations"],
        "objective": result.objective,
        "verified_objective": result.verified_objective,
        "accuracy": result.accuracy,
        "feasible": result.optimum.feasible,
        "variables": result.variables,
        "baseline": {
            "name": base.name,
            "doc": base.doc,
            "resolution": base.resolution,
            "wall_time_s": base.wall_time_s,
            "evaluations": base.evaluations,
            "objective": base.best.objective,
            "verified_objective": base.best.verified_objective,
            "feasible": base.best.feasible,
            "variables": base.best.variables,
        },
    }
    log(f"{problem.name}: {out['wall_time_s']:.2f} s, {out['evaluations']} evaluations, verified "
        f"{out['verified_objective']:.8g}; {base.name} ({base.evaluations} points) {base.wall_time_s:.2f} s, best "
        f"{base.best.objective:.8g}")
    return out


def _commit() -> str:
    return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                          check=False).stdout.strip()


def run(n: int, repeats: int) -> dict[str, Any]:
    """Every figure of the module docstring, machine by machine."""
    rng = np.random.default_rng(SEED)
    report: dict[str, Any] = {"machine": machine(), "commit": _commit(), "load_average_before": list(os.getloadavg()),
                              "cores_available_before": cores_available(), "poses": n, "repeats": repeats,
                              "seed": SEED, "machines": {}, "syntheses": {}}
    problems = registry.problems()
    for name in DESCRIPTIONS:
        report["machines"][name] = {"derivation": derivation(name), "local_index": local_index(name, n, repeats, rng)}
        for key in sorted(k for k in problems if k.startswith(f"{name}.")):
            report["syntheses"][key] = synthesis(problems[key])
    report["load_average_after"] = list(os.getloadavg())
    report["cores_available_after"] = cores_available()
    return report


def _met(value: float, goal: float, below: bool) -> str:
    return "yes" if (value < goal if below else value >= goal) else "no"


def _objective(r: Mapping[str, Any]) -> str:
    return f"{r['verified_objective']:.6g}" + ("" if r["feasible"] else " (infeasible)")


def markdown(report: Mapping[str, Any]) -> str:
    """docs/benchmarks.md's section of issue 24, below its heading: the command, the run's conditions and three
    tables (derivation and load, compiled 1/kappa_f against numpy, syntheses against their baselines)."""
    before, after = report["load_average_before"][0], report["load_average_after"][0]
    lines = [
        f"`{report['command']}` (bench/described.py), {report['machine']['date']} at {report['commit']}, on "
        f"{report['machine']['cores']} cores; load average (1 min) {before:.2f} before, {after:.2f} after; cores "
        f"available to two busy processes (`cores_available`) {report['cores_available_before']:.2f} "
        f"before, {report['cores_available_after']:.2f} after. Each "
        "derivation runs in a new process with an empty kernel cache (`PKM_CACHE_DIR` a new folder): "
        "`pkm.load(name)` and the first use of its functions (the derivation by `python -m symbolic.describe` "
        "into the cache, then the CasADi functions built from it), then the first `inverse_kinematics` at the "
        "home pose; the warm load is the same in a second new process on the same cache; a process's wall time "
        "includes Python's start and `import pkm`. Goals (issue 24): derivation under 30 s for the 3-DOF "
        "machines and 2 min for the Stewart platform; the compiled local index at least "
        f"{RATIO_GOAL:g}x numpy on 2 threads.",
        "",
        "| machine | derivation, empty cache (s) | goal met | first IK then (s) | process (s) | warm cache: load + "
        "first IK (s) | process (s) |",
        "|---|---:|---|---:|---:|---:|---:|",
    ]
    for name, row in report["machines"].items():
        cold, warm = row["derivation"]["empty_cache"], row["derivation"]["warm_cache"]
        goal = DERIVATION_GOAL_S[name]
        lines.append(f"| {name} | {_derivation_s(cold):.2f} | < {goal:g} s: {_met(_derivation_s(cold), goal, True)} | "
                     f"{cold['first_inverse_kinematics_s']:.3f} | {cold['process_s']:.2f} | {_warm_s(warm):.3f} | "
                     f"{warm['process_s']:.2f} |")
    lines += [
        "",
        f"`local_index(\"inverse_condition_f\")` at {report['poses']:,} reachable poses of the default design, "
        f"best of {report['repeats']}, against the hand-written numpy of the same maths from the pose "
        "(bench/numpy_models.py: inverse kinematics and J of tests/oracles.py, J normalised by the characteristic "
        "length, n / sqrt(tr(J J^T) tr(J^-1 J^-T))); rates in poses per second:",
        "",
        "| machine | mode | numpy | pkm, 1 thread | pkm, 2 threads | >= 10x on 2 threads |",
        "|---|---|---:|---:|---:|---|",
    ]
    for name, row in report["machines"].items():
        index = row["local_index"]
        cells = [f"{index['poses'] / t['seconds'] / 1e6:.3g} M ({t['ratio_vs_numpy']:.3g}x)"
                 for t in (index["threads"][str(k)] for k in THREADS)]
        ratio = index["threads"][str(max(THREADS))]["ratio_vs_numpy"]
        lines.append(f"| {name} | {index['mode']} | {index['poses'] / index['numpy_s'] / 1e6:.3g} M | "
                     f"{' | '.join(cells)} | {_met(ratio, RATIO_GOAL, False)} |")
    lines += [
        "",
        "Each registered synthesis at its defaults, second call in the process: its wall time (screening, IPOPT, "
        "polishing and verification), evaluations and verified objective; its baseline (the problem's own, run "
        "by the driver on the same model after it): points evaluated, wall time and best objective.",
        "",
        "| problem | pkm: wall (s) | evaluations | verified objective | baseline | points | wall (s) | its best, "
        "verified |",
        "|---|---:|---:|---:|---|---:|---:|---:|",
    ]
    for name, r in report["syntheses"].items():
        base = r["baseline"]
        lines.append(f"| {name} | {r['wall_time_s']:.2f} | {r['evaluations']} | {_objective(r)} | {base['name']} | "
                     f"{base['evaluations']} | {base['wall_time_s']:.2f} | {_objective(base)} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.described", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write every figure as JSON here")
    parser.add_argument("--poses", type=int, default=POSES, metavar="N", help=f"poses of the local index ({POSES:,})")
    parser.add_argument("--repeats", type=int, default=3, metavar="K", help="best of K timed calls (default 3)")
    args = parser.parse_args(argv)
    if args.poses < 1 or args.repeats < 1:
        parser.error("--poses and --repeats must be at least 1")
    report = run(args.poses, args.repeats)
    report["command"] = "python -m bench.described " + " ".join(sys.argv[1:] if argv is None else argv)
    print(markdown(report))
    if args.out:
        write_json(args.out, report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
