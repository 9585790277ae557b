"""Issue 12's targets against the committed runs: ``python -m bench.targets``.

Reads docs/benchmarks/compiled_on.json (``python -m bench.run --json``: throughput, dynamics and gantry
rows, ratios against hand-written numpy in the same run), docs/benchmarks/integrals.json (``python -m
bench.integrals --json``: global indices with their gradients, syntheses) and
docs/benchmarks/import_time.json (``python -m bench.import_time --json``) and prints one row per target
with the measured figure and whether it is met. docs/benchmarks.md quotes the table;
tests/test_benchmark_docs.py checks the quote against the committed runs.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from bench.import_time import BASELINE

RUNS = Path(__file__).resolve().parent.parent / "docs" / "benchmarks"
ANGLES = "experiment: pkm local_index through the joint angles (IK -> first_order -> 1/kappa_f)"


def _ratio(section: Mapping[str, Any], name: str, threads: int) -> float | None:
    rows = [r for r in section["rows"] if r["name"] == name and r["threads"] == threads]
    return rows[0]["ratio_vs_numpy"] if rows else None


def _row(target: str, measured: str, met: bool | None) -> str:
    return f"| {target} | {measured} | {'-' if met is None else 'yes' if met else 'no'} |"


def _at_least(target: str, value: float | None, bound: float) -> str:
    if value is None:
        return _row(target, "not measured", None)
    return _row(target, f"{value:.1f}x", value >= bound)


def table(throughput: Mapping[str, Any], integrals: Mapping[str, Any], imports: Mapping[str, Any]) -> str:
    """Markdown rows: target, measured, met."""
    lines = ["| target (issue 12) | measured | met |", "|---|---:|---|"]
    kin, dyn, gantry = throughput["throughput"], throughput["dynamics"], throughput["gantry"]
    local = "pkm local_index (IK + J + 1/kappa_f)"
    lines += [
        _at_least("five-bar IK + J + 1/kappa_f through the joint angles, 1 thread: >= 7x numpy",
                  _ratio(kin, ANGLES, 1), 7),
        _at_least("five-bar IK + J + 1/kappa_f through the joint angles, 2 threads: >= 12x numpy",
                  _ratio(kin, ANGLES, 2), 12),
        _at_least("five-bar `local_index` (trigonometry-free), 1 thread: >= 7x numpy", _ratio(kin, local, 1), 7),
        _at_least("five-bar `local_index` (trigonometry-free), 2 threads: >= 20x numpy", _ratio(kin, local, 2), 20),
        _at_least('five-bar dynamics, `local_index("dynamic_dexterity")` (M_t, M_w, 1/kappa_2), 2 threads: '
                  ">= 8x numpy", _ratio(dyn, 'pkm local_index("dynamic_dexterity") (IK, first_order, inertia, index)',
                                        2), 8),
        _at_least("slider gantry `inverse_dynamics` (public API), 2 threads: >= 4x numpy",
                  _ratio(gantry, "pkm inverse_dynamics (public API)", 2), 4),
    ]
    for row in integrals["indices"]:
        ms = row["median_ms"]["pkm value + gradient"]
        lines.append(_row(f"{row['index']} value + exact gradient over {row['nodes']} nodes: "
                          f"<= {row['target_ms']:g} ms", f"{ms:.3f} ms", ms <= row["target_ms"]))
    for syn in integrals["syntheses"]:
        if "error" in syn:
            lines.append(_row(f"`{syn['problem']}` < 1 s with verification", "failed", False))
            continue
        walls = syn["synthesis_wall_time_s"]
        lines.append(_row(f"`{syn['problem']}` < 1 s with verification (first / second call)",
                          " / ".join(f"{w:.2f} s" for w in walls), max(walls) < 1.0))
    baseline = imports["cases"][BASELINE]["median_s"]
    for name, case in imports["cases"].items():
        if name != BASELINE:
            lines.append(_row(f"`{case['code']}` < 0.3 s (`import numpy, casadi` alone: {baseline:.3f} s)",
                              f"{case['median_s']:.3f} s", case["median_s"] < 0.3))
    return "\n".join(lines)


def committed() -> str:
    """The table of the committed runs."""
    runs = [json.loads((RUNS / f"{name}.json").read_text()) for name in ("compiled_on", "integrals", "import_time")]
    return table(*runs)


if __name__ == "__main__":
    print(committed())
    sys.exit(0)
