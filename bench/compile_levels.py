"""What each optimisation level buys a kernel: ``python -m bench.compile_levels [--json PATH]``.

For summing kernels (a region's integrands, :func:`pkm.batch.total`) and row kernels (the batch methods'
pipelines, :func:`pkm.batch.evaluate`) of the five-bar, the 3-RRR and the passive leg, spread over their sizes,
each level in a process of its own with an empty kernel cache: the compile's wall time (pkm's toolchain, its
flags but the level) and the kernel's run over ``ROWS`` rows (a summing kernel's rows summed in one group),
best of ``REPEATS``. pkm compiles a summing kernel at -O1 and a row kernel at -O2 (-O3 below
:data:`pkm.compiled.toolchain.SMALL` instructions): :meth:`pkm.compiled.toolchain.Toolchain.optimisation`.
Nothing asserts on time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from typing import Any

import numpy as np

from bench import json_main

LEVELS = ("-O3", "-O2", "-O1")
MECHANISMS = ("five_bar", "rrr3", "passive_leg")
PER_KIND = 5  # kernels of each kind
ROWS = 65536
REPEATS = 7


def _picks() -> list[Any]:
    import pkm
    from pkm.catalogue import kernels

    picks = []
    for summed, prefix in ((True, "integrand"), (False, "pipeline")):
        chosen = sorted((k for name in MECHANISMS for k in kernels(pkm.load(name))
                         if k.summed == summed and k.label.startswith(prefix)),
                        key=lambda k: k.function.n_instructions())
        picks += [chosen[i] for i in np.linspace(len(chosen) // 4, len(chosen) - 1, PER_KIND).round().astype(int)]
    return picks


def _level(level: str) -> list[dict[str, Any]]:
    """Compile and run the picks at one level (this process's kernel cache must be empty)."""
    from pkm import compiled
    from pkm.batch import evaluate, total
    from pkm.compiled import toolchain

    toolchain.Toolchain.optimisation = staticmethod(lambda _instructions, _summed=False: level)
    rng = np.random.default_rng(0)
    rows = []
    for entry in _picks():
        fn = entry.function
        start = time.perf_counter()
        compiled.build([(fn, entry.summed)])
        compile_s = time.perf_counter() - start
        args = [np.tile(rng.uniform(0.5, 1.0, fn.numel_in(i)), (ROWS, 1)) if fn.name_in(i) in ("design", "mode", "t")
                else rng.uniform(-0.5, 0.5, (ROWS, fn.numel_in(i))) for i in range(fn.n_in())]
        best = np.inf
        for _ in range(REPEATS):
            start = time.perf_counter()
            if entry.summed:
                total(fn, *args, group=ROWS)
            else:
                evaluate(fn, *args)
            best = min(best, time.perf_counter() - start)
        rows.append({"kernel": entry.label, "summed": entry.summed, "instructions": fn.n_instructions(),
                     "compile_s": compile_s, "run_ms": best * 1e3})
    return rows


def run(*, log: Any = print) -> dict[str, Any]:
    from bench.report import machine

    levels = {}
    for level in LEVELS:
        env = {**os.environ, "PKM_CACHE_DIR": os.path.join(tempfile.mkdtemp(), "kernels")}
        out = subprocess.run([sys.executable, "-m", "bench.compile_levels", "--level", level], env=env, check=True,
                             capture_output=True, text=True).stdout
        levels[level] = json.loads(out)
        log(f"{level}: {sum(r['compile_s'] for r in levels[level]):.2f} s of compiles")
    return {"command": "python -m bench.compile_levels --json docs/benchmarks/compile_levels.json",
            "machine": machine(), "rows": ROWS, "levels": levels}


def markdown(data: dict[str, Any]) -> str:
    first = data["levels"][LEVELS[0]]
    lines = [f"Command: `{data['command']}`; each level in a process of its own with an empty kernel cache, a "
             f"kernel's run over {data['rows']:,} rows (a summing kernel's summed in one group), best of "
             f"{REPEATS}.", "",
             "| kernel | kind | instructions | " + " | ".join(f"compile {lv} [s]" for lv in LEVELS) + " | "
             + " | ".join(f"run {lv} [ms]" for lv in LEVELS) + " |",
             "|---|---|---:|" + "---:|" * (2 * len(LEVELS))]
    for k, row in enumerate(first):
        cells = [data["levels"][lv][k] for lv in LEVELS]
        lines.append(f"| {row['kernel']} | {'summing' if row['summed'] else 'rows'} | {row['instructions']} | "
                     + " | ".join(f"{c['compile_s']:.3f}" for c in cells) + " | "
                     + " | ".join(f"{c['run_ms']:.3f}" for c in cells) + " |")
    for summed, kind in ((True, "summing"), (False, "row")):
        compile_s = {lv: sum(r["compile_s"] for r in data["levels"][lv] if r["summed"] == summed) for lv in LEVELS}
        run_ms = {lv: sum(r["run_ms"] for r in data["levels"][lv] if r["summed"] == summed) for lv in LEVELS}
        lines += ["", f"The {kind} kernels together: compile " + ", ".join(f"{compile_s[lv]:.2f} s at {lv}"
                                                                        for lv in LEVELS)
                  + "; run " + ", ".join(f"{run_ms[lv]:.2f} ms at {lv}" for lv in LEVELS) + "."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--level"]:
        print(json.dumps(_level(argv[1])))
        return 0
    return json_main("python -m bench.compile_levels", __doc__, run, markdown, argv)


if __name__ == "__main__":
    raise SystemExit(main())
