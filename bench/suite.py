"""The test suite's own time (issue 36): ``python -m bench.suite [--root CHECKOUT] [--json PATH]``.

Runs the suite as ``make test`` runs it (ruff, then ``pytest -n 2 --dist loadfile`` with ``--durations``,
OpenBLAS on one thread, bytecode written) in the checkout ``--root`` (this one by default) twice in a row:

* **cold**: an empty kernel cache (``PKM_CACHE_DIR`` a new folder) and an empty user cache
  (``XDG_CACHE_HOME`` a new folder: no derived descriptions, no fresh derivation of generated/), as on a
  fresh clone;
* **warm**: the same folders again, filled by the cold run.

It records each run's wall time, its test counts, the kernels the cold run compiled (the cache's entries)
and the compile share, (cold - warm) / cold: what a fresh clone pays for compiling kernels and deriving
descriptions, and the 20 slowest tests of the warm run. The virtual environment is this checkout's; a run
of another checkout (``--root``) imports that checkout's pkm, tests and symbolic from its folder, so that the
numbers before and after a change come from one machine. Nothing asserts on time.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from bench.report import log, machine

ROOT = Path(__file__).resolve().parent.parent
SLOWEST = 20
GOALS_S = {"cold": 180.0, "warm": 60.0}  # issue 36, on 2 cores
DURATION = re.compile(r"^([0-9.]+)s (call|setup|teardown)\s+(\S+)")
COUNTS = re.compile(r"(\d+) (passed|failed|skipped|errors?)")


def run_suite(root: Path, env: dict[str, str]) -> dict[str, Any]:
    """One run of ruff and the suite in ``root``: wall time, counts and the slowest tests."""
    python = str(ROOT / ".venv" / "bin" / "python")
    start = time.perf_counter()
    lint = subprocess.run([str(ROOT / ".venv" / "bin" / "ruff"), "check", "."], cwd=root, env=env,
                          capture_output=True, text=True, check=False)
    done = subprocess.run([python, "-m", "pytest", "-n", "2", "--dist", "loadfile", "-p", "no:cacheprovider",
                           f"--durations={SLOWEST}"], cwd=root,
                          env={**env, "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "", "OPENBLAS_NUM_THREADS": "1"},
                          capture_output=True, text=True, check=False)
    wall = time.perf_counter() - start
    lines = done.stdout.splitlines()
    slowest = [{"seconds": float(m[1]), "phase": m[2], "test": m[3]}
               for m in map(DURATION.match, lines) if m]
    summary = next((line for line in reversed(lines) if COUNTS.search(line) and " in " in line), "")
    counts = {kind.rstrip("s"): int(n) for n, kind in COUNTS.findall(summary)}
    return {"wall_s": wall, "ruff_ok": lint.returncode == 0, "exit": done.returncode, "counts": counts,
            "slowest": slowest[:SLOWEST]}


def run(root: Path, *, log=log) -> dict[str, Any]:
    with tempfile.TemporaryDirectory() as tmp:
        kernels = Path(tmp) / "kernels"
        env = {**os.environ, "PKM_CACHE_DIR": str(kernels), "XDG_CACHE_HOME": str(Path(tmp) / "cache")}
        env.pop("PYTHONPATH", None)
        log(f"cold run of {root} (empty caches in {tmp})")
        cold = run_suite(root, env)
        kernels_compiled = sum(1 for _ in kernels.rglob("*.so")) if kernels.exists() else 0
        log(f"cold {cold['wall_s']:.0f} s; warm run")
        warm = run_suite(root, env)
        log(f"warm {warm['wall_s']:.0f} s")
    return {"machine": machine(), "root": str(root), "commit": _commit(root), "cold": cold, "warm": warm,
            "kernels_compiled": kernels_compiled,
            "compile_share": max(0.0, (cold["wall_s"] - warm["wall_s"]) / cold["wall_s"]), "goals_s": GOALS_S}


def _commit(root: Path) -> str:
    done = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                          check=False)
    return done.stdout.strip()


def markdown(data: dict[str, Any]) -> str:
    """The run as a table of the two runs and a list of the slowest tests."""
    lines = [f"Commit {data['commit']}, {data['machine']['cores']} cores, {data['machine']['date']}.", "",
             "| Run | Wall time | Goal | Result |", "|---|---|---|---|"]
    for name in ("cold", "warm"):
        r = data[name]
        counts = ", ".join(f"{n} {kind}" for kind, n in r["counts"].items())
        result = ("all passed" if r["exit"] == 0 else f"exit status {r['exit']}") + (f" ({counts})" if counts else "")
        lines.append(f"| {name} | {r['wall_s']:.0f} s | {data['goals_s'][name]:.0f} s | {result} |")
    lines += ["", f"Kernels compiled by the cold run: {data['kernels_compiled']}; compile and derivation share of "
                  f"the cold run: {data['compile_share']:.0%}.", "",
              f"The {SLOWEST} slowest tests of the warm run:", ""]
    lines += [f"- {t['seconds']:.2f} s {t['phase']} `{t['test']}`" for t in data["warm"]["slowest"]]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.suite", description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", type=Path, default=ROOT, help="the checkout whose suite runs (default: this one)")
    parser.add_argument("--json", help="write the run here (default: print only)")
    args = parser.parse_args(argv)
    data = run(args.root.resolve())
    if args.json:
        Path(args.json).write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    print(markdown(data))
    return 0


if __name__ == "__main__":
    sys.exit(main())
