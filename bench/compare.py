"""Before/after table of two ``python -m bench.run --json`` runs: ``python -m bench.compare BEFORE AFTER``.

Each row of the pkm public API is given as its ratio against the hand-written numpy baseline measured
in the same run, so that the two runs compare even when the machine's speed drifts between them.
docs/benchmarks.md quotes the table; tests/test_benchmark_docs.py checks that the quote is this
function's output for the committed JSON files.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

SECTIONS = (("throughput", "poses"), ("dynamics", "poses"), ("gantry", "states"))


def _public_rows(section: dict[str, Any]) -> dict[tuple[str, int], dict[str, Any]]:
    """Rows of pkm (not the experiments) by (name, threads)."""
    return {(r["name"], r["threads"]): r for r in section["rows"] if not r["name"].startswith("experiment")}


def table(before: dict[str, Any], after: dict[str, Any]) -> str:
    """Markdown rows: benchmark, threads, ratio vs numpy before and after, throughput before and after."""
    lines = [
        "| benchmark | threads | vs numpy before | vs numpy after | before (M/s) | after (M/s) |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for key, unit in SECTIONS:
        old, new = _public_rows(before[key]), _public_rows(after[key])
        for name, threads in old:
            if (name, threads) not in new:
                continue
            a, b = old[(name, threads)], new[(name, threads)]
            rate = f"{unit}_per_s"
            lines.append(
                f"| {key}: {name} | {threads} | {a['ratio_vs_numpy']:.2f}x | {b['ratio_vs_numpy']:.2f}x "
                f"| {a[rate] / 1e6:.2f} | {b[rate] / 1e6:.2f} |"
            )
    syn_a, syn_b = before.get("synthesis", {}), after.get("synthesis", {})
    if "problem" not in syn_a or "problem" not in syn_b:
        return "\n".join(lines)
    lines.append(
        f"| synthesis {syn_a['problem']}: IPOPT wall time (s) / verified objective | - "
        f"| {syn_a['optimizer']['wall_time_s']:.2f} / {syn_a['optimizer']['verified_objective']:.6f} "
        f"| {syn_b['optimizer']['wall_time_s']:.2f} / {syn_b['optimizer']['verified_objective']:.6f} | - | - |"
    )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.compare", description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    args = parser.parse_args(argv)
    print(table(json.loads(args.before.read_text()), json.loads(args.after.read_text())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
