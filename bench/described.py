"""The machines described as data (issue 24's benchmark): ``python -m bench.described --out PATH [--poses N]
[--repeats K]``.

For each described machine (pkm/models/described: rrr3, delta, stewart):

* **derivation** from an empty cache: a new process with ``PKM_CACHE_DIR`` a new, empty folder imports pkm,
  loads the machine by name (``pkm.load``), asks for its functions (the first use: the derivation of its
  module, ``python -m symbolic.described``, into ``<cache>/descriptions/``, then its CasADi functions built
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

The machines of examples/ whose legs are chains of joints (delta_chains, the Delta of
pkm/models/described/delta.toml given joint by joint, its chains in closed form, and delta_chains_newton,
the same solved by Newton continuation; hexa, a 6-RUS platform, in closed form) get the same derivation and
load figures and the compiled 1/kappa_f on 1 and 2 threads; the Delta's chains against the numpy Delta (the
closed form of the same machine, its mode elbow_out) and against pkm's Delta description in the same run,
hexa without a numpy baseline (its poses' 1/kappa_f, at least bench.methods.CONDITION_MARGIN, is pkm's).

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
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

import pkm
from bench import methods
from bench.numpy_models import MODELS
from bench.report import log, machine, write_json
from bench.throughput import set_threads
from pkm import registry
from pkm.models.described import DESCRIPTIONS

ROOT = Path(__file__).resolve().parent.parent
SEED = 20261126
POSES = 1_000_000
THREADS = (1, 2)
DERIVATION_GOAL_S = {"rrr3": 30.0, "delta": 30.0, "stewart": 120.0, "delta_chains": 30.0, "delta_chains_newton": 30.0,
                     "hexa": 120.0}
# issue 24: 3-DOF machines, Stewart platform (and the 6-DOF hexa)
CHAINS = {"delta_chains": ("delta", "elbow_out"), "delta_chains_newton": ("delta", "elbow_out"),
          "hexa": (None, None)}  # examples/<name>.toml (<name>_newton: its legs with newton = true): the closed-form
# twin among the described machines (the numpy model's and pkm's) and the twin's mode
RATIO_GOAL = 10.0  # issue 24: compiled local_index against numpy on 2 threads

CHILD = """
import json, sys, time
start = time.perf_counter()
import numpy as np
import pkm
out = {"import_s": time.perf_counter() - start}
start = time.perf_counter()
m = pkm.load(json.loads(open(sys.argv[1]).read()) if sys.argv[1].endswith(".json") else sys.argv[1])
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


def _description(name: str) -> dict[str, Any]:
    """A chain machine's description: examples/<name>.toml, or for <name>_newton that file's with every chain
    leg solved by Newton continuation."""
    base = name.removesuffix("_newton")
    raw = tomllib.loads((ROOT / "examples" / f"{base}.toml").read_text())
    if name != base:
        raw["name"] = name
        for table in raw["legs"] if isinstance(raw["legs"], list) else [raw["legs"]]:
            table["newton"] = True
    return raw


def _source(name: str, folder: Path) -> str:
    """What ``pkm.load`` takes for a machine in a child process: its registered name, or its description as a
    JSON file written in ``folder``."""
    if name not in CHAINS:
        return name
    path = folder / f"{name}.json"
    path.write_text(json.dumps(_description(name)))
    return str(path)


def derivation(name: str) -> dict[str, Any]:
    """Derivation from an empty cache, then load from the warm cache, each in a new process."""
    with tempfile.TemporaryDirectory(prefix=f"pkm-described-{name}-") as folder:
        cache = Path(folder)
        source = _source(name, cache)
        cold = _child(source, cache)
        derived = sorted(p.name for p in (cache / "descriptions").glob(f"{name}_*.py"))
        warm = _child(source, cache)
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
    """Compiled 1/kappa_f at n reachable poses against numpy, on 1 and 2 threads (module docstring); a chain
    machine against its closed-form twin's numpy model and pkm's closed-form twin where it has one."""
    m = pkm.load(_description(name) if name in CHAINS else name)
    twin, twin_mode = CHAINS.get(name, (name, None))
    design = m.design()
    mode = m.modes[0]
    d = dict(design)
    signs = None if twin is None else pkm.load(twin).working_mode(twin_mode or mode).signs

    def condition(X: np.ndarray) -> np.ndarray:
        if twin is None:
            return m.local_index("inverse_condition_f", X, design, mode=mode)
        return MODELS[twin].inverse_condition_f(X, d, signs)

    X = methods.sample_poses(m, mode, n, rng, condition)

    def ours() -> np.ndarray:
        return m.local_index("inverse_condition_f", X, design, mode=mode)

    timed = {"pkm": ours}
    reference = numpy_s = None
    if twin is not None:

        def theirs() -> np.ndarray:
            return condition(X)

        reference = theirs()
        numpy_s = methods.best_of(theirs, repeats)
        if twin != name:
            closed = pkm.load(twin)
            full = {**dict(closed.design()), **d}
            timed["closed_form"] = lambda: closed.local_index("inverse_condition_f", X, full, mode=twin_mode)
    out: dict[str, Any] = {"mode": mode, "poses": len(X), "numpy_s": numpy_s, "threads": {}, "closed_form": {}}
    default = pkm.batch.THREADS
    try:
        for threads in THREADS:
            set_threads(threads)
            for key, fn in timed.items():
                err = None if reference is None else methods.discrepancy(
                    fn(), reference, f"{name} inverse_condition_f ({key}) on {threads} thread(s)")
                fn()
                seconds = methods.best_of(fn, repeats)
                row = {"seconds": seconds, "ratio_vs_numpy": None if numpy_s is None else numpy_s / seconds,
                       "max_discrepancy": err}
                (out["threads"] if key == "pkm" else out["closed_form"])[str(threads)] = row
                log(f"{name} 1/kappa_f ({key}) on {threads} thread(s): {len(X) / seconds / 1e6:.3g} M/s"
                    + ("" if numpy_s is None else f", {numpy_s / seconds:.3g}x numpy ({len(X) / numpy_s / 1e6:.3g} "
                       "M/s)"))
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
    for name in [*DESCRIPTIONS, *CHAINS]:
        report["machines"][name] = {"derivation": derivation(name), "local_index": local_index(name, n, repeats, rng)}
        for key in sorted(k for k in problems if k.startswith(f"{name}.")):
            report["syntheses"][key] = synthesis(problems[key])
    report["load_average_after"] = list(os.getloadavg())
    report["cores_available_after"] = cores_available()
    return report


def _met(value: float, goal: float, below: bool) -> str:
    return "yes" if (value < goal if below else value >= goal) else "no"


def _rate(poses: int, timing: Mapping[str, Any]) -> str:
    ratio = timing["ratio_vs_numpy"]
    return f"{poses / timing['seconds'] / 1e6:.3g} M" + ("" if ratio is None else f" ({ratio:.3g}x)")


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
        "`pkm.load(name)` and the first use of its functions (the derivation by `python -m symbolic.described` "
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
        cells = [_rate(index["poses"], t) for t in (index["threads"][str(k)] for k in THREADS)]
        ratio = index["threads"][str(max(THREADS))]["ratio_vs_numpy"]
        numpy_rate = "none" if index["numpy_s"] is None else f"{index['poses'] / index['numpy_s'] / 1e6:.3g} M"
        met = "-" if ratio is None else _met(ratio, RATIO_GOAL, False)
        lines.append(f"| {name} | {index['mode']} | {numpy_rate} | {' | '.join(cells)} | {met} |")
    lines += [
        "",
        "The chain machines (examples/; docs/mechanisms.md, section 5): delta_chains and hexa in the closed "
        "form of their chains' subproblem, delta_chains_newton by Newton continuation; numpy for the Delta's "
        "chains is the Delta's closed form (the same machine, elbow_out), and hexa has no numpy baseline. pkm's "
        "Delta description on the same poses, in the same run:",
        "",
        "| machine | the Delta description, 1 thread | 2 threads | chain on 2 threads against it |",
        "|---|---:|---:|---:|",
    ]
    for name, row in report["machines"].items():
        closed = row["local_index"]["closed_form"]
        if closed:
            last = str(max(THREADS))
            cells = [_rate(row["local_index"]["poses"], closed[str(k)]) for k in THREADS]
            lines.append(f"| {name} | {' | '.join(cells)} | "
                         f"{closed[last]['seconds'] / row['local_index']['threads'][last]['seconds']:.2f}x |")
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
