"""Every registered synthesis against its brute-force optimum (issue 23 item 2):
``python -m bench.optima [--json PATH] [--label TEXT]``.

For each registered problem, ``pkm.synthesize(problem)`` at its defaults is run twice in the process (the
first call compiles what the kernel cache lacks; the second is reported): the synthesis's wall time as the
result reports it (screening, IPOPT, polishing or the exchange over the regions, and the verification of
every converged run), the quadrature resolution it started from and reached, the verified objective and
the accuracy it states, and the relative difference of the verified objective from the brute-force optimum
of ``docs/benchmarks/brute_force.json`` (:mod:`bench.brute_force`), computed once on the same model
without IPOPT. Run from an older checkout (``PYTHONPATH=<checkout> python <this file>``), it measures
that version against the same brute force: the "before" of docs/benchmarks.md. Nothing asserts on time.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pkm
from pkm import registry

BRUTE_FORCE = Path(__file__).resolve().parent.parent / "docs" / "benchmarks" / "brute_force.json"
TARGET_S = 1.0
AGREEMENT = 1e-5


def _commit() -> str:
    root = Path(pkm.__file__).resolve().parent.parent
    return subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                          check=False).stdout.strip()


def run(*, log: Any = print) -> dict[str, Any]:
    """Every registered synthesis, second call, against the committed brute force."""
    brute = json.loads(BRUTE_FORCE.read_text())["problems"]
    rows = {}
    for name, problem in registry.problems().items():
        pkm.synthesize(problem, progress=False)
        start = time.perf_counter()
        result = pkm.synthesize(problem, progress=False)
        whole = time.perf_counter() - start
        reference = brute.get(name, {}).get("objective")
        difference = None if reference is None else abs(result.verified_objective - reference) / max(1.0,
                                                                                                    abs(reference))
        rows[name] = {
            "doc": problem.doc,
            "status": result.status,
            "wall_time_s": result.optimizer["wall_time_s"],
            "whole_call_s": whole,
            "evaluations": result.optimizer["evaluations"],
            "resolution": result.resolutions.get("quadrature"),
            "polished_from": result.resolutions.get("polished_from"),
            "objective": result.objective,
            "verified_objective": result.verified_objective,
            "accuracy": result.accuracy,
            "brute_force": reference,
            "difference": difference,
        }
        log(f"{name}: {result.optimizer['wall_time_s']:.2f} s, resolution {rows[name]['resolution']}, verified "
            f"{result.verified_objective:.8g} (accuracy {result.accuracy:.1e}), brute force {reference}, relative "
            f"difference {difference}")
    return {"commit": _commit(), "load_average": [round(x, 2) for x in os.getloadavg()], "problems": rows}


def _cells(r: dict[str, Any], doc: str) -> str:
    """A run's verified objective, accuracy, difference from the brute force (of the problem stated by
    ``doc``) and wall time."""
    if not r:
        return "-"
    difference = "another problem" if r["doc"] != doc else "-" if r["difference"] is None else f"{r['difference']:.1e}"
    return f"{r['verified_objective']:.8g} / {r['accuracy']:.1e} / {difference} / {r['wall_time_s']:.2f}"


def markdown(before: dict[str, Any], after: dict[str, Any]) -> str:
    """The table docs/benchmarks.md quotes: each problem before and after, against the brute force (a problem
    whose statement changed between the two runs is another problem: no difference is shown for it)."""
    lines = [
        "| problem | brute force | before: verified / accuracy / difference / s | after: verified / accuracy / "
        "difference / s | resolution after | < 1 s |",
        "|---|---|---|---|---|---|",
    ]
    for name, row in after["problems"].items():
        old = before["problems"].get(name, {})
        reference = "-" if row["brute_force"] is None else f"{row['brute_force']:.8g}"
        resolution = f"{row['polished_from']} -> {row['resolution']}"
        lines.append(f"| {name} | {reference} | {_cells(old, row['doc'])} | {_cells(row, row['doc'])} | {resolution} | "
                     f"{'yes' if row['wall_time_s'] < TARGET_S else 'no'} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.optima", description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write the results here")
    args = parser.parse_args(argv)
    report = run(log=lambda line: print(line, file=sys.stderr))
    text = json.dumps(report, indent=2) + "\n"
    if args.json:
        args.json.write_text(text)
    else:
        print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
