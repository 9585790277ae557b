"""Import time: ``python -m bench.import_time [--runs N] [--bytecode] [--json PATH]``.

The wall time of a fresh process that runs ``import pkm; pkm.load(name)``, for every registered
mechanism, against a process that runs ``import numpy, casadi`` (pkm's floor) in the same run. Each
figure is the median of ``runs`` processes, started round robin over the cases after one warm-up
process each, so that a drift of the machine's load reaches every case alike.

By default the processes write no bytecode (``PYTHONDONTWRITEBYTECODE``), so that Python compiles pkm's
modules at each start unless a ``__pycache__`` is already there, as in a fresh or read-only checkout;
``--bytecode`` measures what an installed package sees instead: the processes share a fresh bytecode
cache, written by the warm-up.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pkm

BASELINE = "numpy + casadi"
ROOT = Path(__file__).resolve().parent.parent


def cases() -> dict[str, str]:
    """The code each case runs, by case name: the baseline first, then one per mechanism."""
    return {BASELINE: "import numpy, casadi", **{name: f"import pkm; pkm.load({name!r})" for name in pkm.mechanisms()}}


def _wall(code: str, env: dict[str, str]) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, check=True)
    return time.perf_counter() - start


def run(runs: int, *, bytecode: bool) -> dict[str, Any]:
    """Median, minimum and maximum wall time [s] per case over ``runs`` fresh processes."""
    with tempfile.TemporaryDirectory() as cache:
        env = {key: value for key, value in os.environ.items() if key != "PYTHONDONTWRITEBYTECODE"}
        if bytecode:
            env["PYTHONPYCACHEPREFIX"] = cache
        else:
            env["PYTHONDONTWRITEBYTECODE"] = "1"
        code = cases()
        for text in code.values():
            _wall(text, env)
        walls: dict[str, list[float]] = {name: [] for name in code}
        for _ in range(runs):
            for name, text in code.items():
                walls[name].append(_wall(text, env))
    return {
        "command": "python -m bench.import_time " + " ".join(sys.argv[1:]),
        "runs": runs,
        "bytecode_cache": bytecode,
        "cores": os.cpu_count(),
        "python": sys.version.split()[0],
        "cases": {
            name: {"code": code[name], "median_s": statistics.median(w), "min_s": min(w), "max_s": max(w)}
            for name, w in walls.items()
        },
    }


def markdown(report: dict[str, Any]) -> str:
    """The report as a markdown table, with each case's excess over the baseline."""
    floor = report["cases"][BASELINE]["median_s"]
    cache = "a bytecode cache" if report["bytecode_cache"] else "no bytecode cache"
    lines = [
        f"Median of {report['runs']} fresh processes, {report['cores']} cores, Python {report['python']}, {cache}.",
        "",
        "| process runs | median wall [s] | min [s] | max [s] | over the baseline [s] |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, row in report["cases"].items():
        excess = "" if name == BASELINE else f"{row['median_s'] - floor:+.3f}"
        times = " | ".join(f"{row[key]:.3f}" for key in ("median_s", "min_s", "max_s"))
        lines.append(f"| `{row['code']}` | {times} | {excess} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.import_time", description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=10, help="fresh processes per case (default 10)")
    parser.add_argument("--bytecode", action="store_true", help="share a bytecode cache, as an installed package")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    args = parser.parse_args(argv)
    if args.runs < 1:
        parser.error(f"--runs {args.runs} violates: an integer >= 1")
    report = run(args.runs, bytecode=args.bytecode)
    print(markdown(report))
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
