"""Compiled global indices and syntheses (issue 12): ``python -m bench.integrals [--quick] [--json PATH]``.

* A global index over 10^4 quadrature nodes (the five-bar's MIW disc at resolution 50, 4 x 50^2 nodes)
  at the default design, for ``gci`` and ``dynamic_dexterity``: the value alone
  (:func:`pkm.regions.node_quadrature`) and the value with its exact gradient
  (:func:`pkm.regions.quadrature_function`), evaluated by the point integrands
  (:mod:`pkm.regions.integrand`, C kernels when ``pkm.compiled.status()`` says so), against the same index
  as the CasADi graph of the region's nodes: the region's quadrature mapped through the fused pipeline and
  reduced in CasADi, an MX function of the design with ``casadi.gradient`` (what pkm evaluated before the
  integrands; :func:`node_graph`, which tests/test_integrand.py uses). Both are built once and checked against each
  other to 1e-10 relative (value and gradient) before timing; each figure is the median of ``repeats``
  calls, the four cases interleaved call by call (so that each pkm call follows tens of milliseconds of
  other work: cold caches, the kernels' kept threads asleep), and then the value with its gradient again
  ``repeats`` times back to back, as a solver calls it. Each call takes a different design (the default
  one scaled by 1 + k 1e-9).
* Every registered synthesis, run first, ``pkm.synthesize(name)`` at its defaults, at its first call in the
  process and at a second call: the synthesis's wall time as the result reports it (screening, IPOPT,
  polishing and the verification of every converged run, the issue's "< 1 s including verification"),
  the wall time of the whole call (with the baselines, which run in the same call), the evaluations,
  status, objective and verified objective, and the first baseline's wall time, evaluations and verified
  objective.

The issue's targets: value + gradient of the GCI <= 0.5 ms and of the dynamic dexterity <= 1 ms, every
synthesis < 1 s including verification. Nothing asserts on time. :func:`markdown` renders the tables that
docs/benchmarks.md quotes (tests/test_benchmark_docs.py checks them against the committed JSON).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

import pkm
import pkm.batch
from bench.report import machine, write_json
from pkm import compiled
from pkm.regions import node_quadrature, quadrature_function
from pkm.regions.pipeline import pipeline

MECHANISM = "five_bar"
REGION = "miw"
RESOLUTION = 50  # 4 x 50^2 = 10^4 nodes on the disc
INDICES = ("gci", "dynamic_dexterity")
TARGETS_MS = {"gci": 0.5, "dynamic_dexterity": 1.0}  # value + gradient, issue 12
SYNTHESIS_TARGET_S = 1.0
AGREEMENT = 1e-10
STEP = 1e-9  # relative change of the design from one timed call to the next
ROOT = Path(__file__).resolve().parent.parent
CASES = ("graph value", "graph value + gradient", "pkm value", "pkm value + gradient")
BACK_TO_BACK = "pkm value + gradient, back to back"


def _load() -> list[float]:
    return [round(x, 2) for x in os.getloadavg()]


def node_graph(mech: Any, spec: Any, region: Any, branch: Any, *, design: ca.MX, resolution: int) -> ca.MX:
    """The global index as the reduction of the local index at the region's quadrature nodes, in CasADi."""
    points, weights = region.quadrature(mech.functions, design, resolution, spec.reduce)
    n = points.size2()
    _, _, valid, values = pipeline(mech, (spec.local,)).map(n)(points, ca.DM(branch.signs), design)
    w = ca.vec(weights)
    if spec.reduce == "measure":
        return ca.mtimes(valid, w)
    mean = ca.mtimes(values, w) / ca.sum1(w)
    if spec.reduce == "std":
        return ca.sqrt(ca.mtimes((values - mean) ** 2, w) / ca.sum1(w))
    return mean


def _relative(got: np.ndarray, want: np.ndarray) -> float:
    return float(np.max(np.abs(got - want)) / max(1e-300, float(np.max(np.abs(want)))))


def index_bench(name: str, *, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Median milliseconds of the four cases (:data:`CASES`) for one global index, after the agreement check."""
    mech = pkm.load(MECHANISM)
    spec, region, branch = mech.global_spec(name), mech.region(REGION), mech.working_mode(None)
    design = mech.design_vector(mech.design())
    symbol = ca.MX.sym("design", len(design))
    value = node_graph(mech, spec, region, branch, design=symbol, resolution=RESOLUTION)
    graph_value = ca.Function("graph_value", [symbol], [value], ["design"], [name])
    graph_both = ca.Function(
        "graph_gradient", [symbol], [value, ca.gradient(value, symbol)], ["design"], [name, "gradient"]
    )
    both = quadrature_function(mech, spec, region, branch, RESOLUTION)

    def pkm_value(d: np.ndarray) -> Any:
        return node_quadrature(mech, spec, region, d, branch=branch, resolution=RESOLUTION)

    cases = dict(zip(CASES, (graph_value, graph_both, pkm_value, both), strict=True))
    want_value, want_gradient = (np.asarray(v, dtype=float).ravel() for v in graph_both(design))
    got_value, got_gradient = (np.asarray(v, dtype=float).ravel() for v in both(design))
    agreement = {
        "value": _relative(got_value, want_value),
        "node_quadrature": _relative(np.asarray(pkm_value(design)), want_value),
        "graph_value": _relative(np.asarray(graph_value(design), dtype=float).ravel(), want_value),
        "gradient": _relative(got_gradient, want_gradient),
    }
    if not max(agreement.values()) <= AGREEMENT:
        raise AssertionError(f"{name}: pkm and the node graph differ: {agreement}")
    log(f"{name}: value {float(want_value[0]):.12g}, pkm agrees with the node graph to {max(agreement.values()):.1e}")
    designs = [design * (1 + STEP * (k + 1)) for k in range(repeats)]
    times: dict[str, list[float]] = {case: [] for case in (*CASES, BACK_TO_BACK)}
    for d in designs:
        for case, fn in cases.items():
            start = time.perf_counter()
            fn(d)
            times[case].append(time.perf_counter() - start)
    for d in designs:  # the same calls back to back, as a solver makes them
        start = time.perf_counter()
        both(d * (1 + STEP))
        times[BACK_TO_BACK].append(time.perf_counter() - start)
    medians = {case: 1e3 * statistics.median(t) for case, t in times.items()}
    log("  " + ", ".join(f"{case} {ms:.3f} ms" for case, ms in medians.items()))
    return {
        "index": name,
        "reduce": spec.reduce,
        "nodes": region.node_count(RESOLUTION, spec.reduce),
        "value": float(want_value[0]),
        "gradient_norm": float(np.linalg.norm(want_gradient)),
        "agreement": agreement,
        "median_ms": medians,
        "min_ms": {case: 1e3 * min(t) for case, t in times.items()},
        "target_ms": TARGETS_MS[name],
    }


def synthesis_bench(name: str, *, calls: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Wall time of ``pkm.synthesize(name)`` (first and later calls) and the first call's record."""
    walls, synthesis, result = [], [], None
    for _ in range(calls):
        start = time.perf_counter()
        try:
            record = pkm.synthesize(name, progress=False).to_dict()
        except Exception as exc:  # report the failure with the other figures
            return {"problem": name, "error": f"{type(exc).__name__}: {exc}", "wall_time_s": walls}
        walls.append(time.perf_counter() - start)
        synthesis.append(record["optimizer"]["wall_time_s"])
        result = result or record
    opt, base = result["optimizer"], result["baseline"]
    log(f"{name}: {', '.join(f'{w:.2f}' for w in walls)} s, {result['status']}")
    return {
        "problem": name,
        "wall_time_s": walls,
        "synthesis_wall_time_s": synthesis,
        "status": result["status"],
        "iterations": result["iterations"],
        "objective": result["objective"],
        "verified_objective": result["verified_objective"],
        "optimizer": {"wall_time_s": opt["wall_time_s"], "evaluations": opt["evaluations"]},
        "baseline": None
        if base is None
        else {
            "name": next(iter(result["baselines"])),
            "wall_time_s": base["wall_time_s"],
            "evaluations": base["evaluations"],
            "objective": result["baseline_objective"],
            "verified_objective": base.get("verified_objective"),
        },
    }


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=False).stdout.rstrip()


def run(*, quick: bool, log: Callable[[str], None]) -> dict[str, Any]:

    repeats = 5 if quick else 100
    report: dict[str, Any] = {
        "machine": machine(),
        "commit": _git("rev-parse", "--short", "HEAD"),
        "uncommitted": sorted(line[3:] for line in _git("status", "--porcelain", "--untracked-files=no").splitlines()),
        "compiled": compiled.status(),
        "threads": pkm.batch.THREADS,
        "repeats": repeats,
        "resolution": RESOLUTION,
        "load_average": {"start": _load()},
    }
    # the syntheses first, so that their first calls build what they need themselves
    report["syntheses"] = [synthesis_bench(name, calls=1 if quick else 2, log=log) for name in pkm.registry.problems()]
    report["load_average"]["indices"] = _load()
    report["indices"] = [index_bench(name, repeats=repeats, log=log) for name in INDICES]
    report["load_average"]["end"] = _load()
    return report


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def _met(ms: float, target: float) -> str:
    return "met" if ms <= target else "not met"


def markdown(report: Mapping[str, Any]) -> str:
    env, status, load = report["machine"], report["compiled"], report["load_average"]
    path = status["path"] if status["path"] != "compiled" else f"compiled ({status['instruction_set']})"
    lines = [
        f"pkm at {report['commit']}, {env['date']}; {env['cores']} cores, pkm.batch.THREADS = {report['threads']}, "
        f"evaluation path: {path}; 1-minute load average {load['start'][0]:.2f} at the start, "
        f"{load['indices'][0]:.2f} after the syntheses, {load['end'][0]:.2f} at the end.",
        "",
        f"| global index over the {MECHANISM} {REGION}, resolution {report['resolution']} | nodes | value (ms) "
        "| value + gradient (ms) | speed-up (value / value + gradient) | target (value + gradient) |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for row in report["indices"]:
        ms, name = row["median_ms"], row["index"]
        base = ms["graph value"], ms["graph value + gradient"]
        lines += [
            f"| {name}: node graph in CasADi (MX map of the fused pipeline, before) | {row['nodes']} "
            f"| {base[0]:.3f} | {base[1]:.3f} | 1.0x / 1.0x | - |",
            f"| {name}: pkm point integrands (node_quadrature / quadrature_function) | {row['nodes']} "
            f"| {ms['pkm value']:.3f} | {ms['pkm value + gradient']:.3f} "
            f"| {base[0] / ms['pkm value']:.1f}x / {base[1] / ms['pkm value + gradient']:.1f}x "
            f"| <= {row['target_ms']:g} ms: {_met(ms['pkm value + gradient'], row['target_ms'])} |",
            f"| {name}: pkm, the same calls back to back (no other work between them) | {row['nodes']} | - "
            f"| {ms[BACK_TO_BACK]:.3f} | - / {base[1] / ms[BACK_TO_BACK]:.1f}x "
            f"| <= {row['target_ms']:g} ms: {_met(ms[BACK_TO_BACK], row['target_ms'])} |",
        ]
    worst = max(max(row["agreement"].values()) for row in report["indices"])
    lines += [
        "",
        f"Median of {report['repeats']} calls per case, the cases interleaved, a different design per call; pkm "
        f"and the node graph agree to {worst:.1e} (relative, value and gradient) before timing.",
        "",
        "| synthesis | status | synthesis with verification, first / second call (s) "
        f"| < {SYNTHESIS_TARGET_S:g} s | evaluations | objective | verified | whole call with the baselines, first / "
        "second (s) | baseline | baseline (s) | baseline evaluations | baseline verified |",
        "|---|---|---:|---|---:|---:|---:|---:|---|---:|---:|---:|",
    ]
    for syn in report["syntheses"]:
        if "error" in syn:
            lines.append(f"| {syn['problem']} | failed: {syn['error']} |" + " - |" * 10)
            continue
        own = syn["synthesis_wall_time_s"]
        met = " / ".join("yes" if w < SYNTHESIS_TARGET_S else "no" for w in own)
        base = syn["baseline"] or {}
        lines.append(
            f"| {syn['problem']} | {syn['status']} | {' / '.join(f'{w:.2f}' for w in own)} | {met} "
            f"| {syn['optimizer']['evaluations']} | {syn['objective']:.6g} | {_fmt(syn['verified_objective'], '.6g')} "
            f"| {' / '.join(f'{w:.2f}' for w in syn['wall_time_s'])} | {base.get('name', '-')} "
            f"| {_fmt(base.get('wall_time_s'), '.2f')} | {_fmt(base.get('evaluations'), 'd')} "
            f"| {_fmt(base.get('verified_objective'), '.6g')} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.integrals", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="5 calls per index case and one call per synthesis")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    args = parser.parse_args(argv)
    report = run(quick=args.quick, log=lambda msg: print(msg, file=sys.stderr, flush=True))
    report["command"] = "python -m bench.integrals " + " ".join(sys.argv[1:] if argv is None else argv)
    print(markdown(report))
    if args.json:

        write_json(Path(args.json), report)
    return 1 if any("error" in syn for syn in report["syntheses"]) else 0


if __name__ == "__main__":
    sys.exit(main())
