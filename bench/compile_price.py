"""What a compile costs against the interpreter: ``python -m bench.compile_price [--json PATH] [--kernels K]``.

The compiled path compiles a graph once the work the interpreter has done for it (instructions times rows,
summed) reaches the work its compile costs (:func:`pkm.compiled.price`, the rule of renting until the rent
reaches the price). This measures both sides on the catalogue's kernels (``--kernels`` of them, spread over
the catalogue's sizes, every mechanism's):

* the compile: the wall time of pkm's toolchain compiling the kernel's translation unit (its flags and
  optimisation level for the size), best of two, on an otherwise idle machine;
* the interpreter: CasADi's interpreter over 20,000 rows of random inputs (:func:`pkm.batch.interpreted`),
  in ns per instruction and row, best of three.

It fits the compile's seconds as ``fixed + per_instruction * instructions`` by least squares and turns both
terms into interpreter work at the median ns per instruction and row: the fixed term is the price's
:data:`pkm.compiled.COMPILE_WORK`, the per-instruction term its :data:`pkm.compiled.COMPILE_ROWS`; the
report sets the fitted values beside the constants. Nothing asserts on time.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

from bench.report import log, machine, write_json

ROWS = 20_000


def _spread(kernels: list, count: int) -> list:
    """``count`` kernels spread evenly over the sorted sizes."""
    ordered = sorted(kernels, key=lambda k: k.function.n_instructions())
    picks = np.unique(np.linspace(0, len(ordered) - 1, count).round().astype(int))
    return [ordered[i] for i in picks]


def measure(count: int, *, log=log) -> dict[str, Any]:
    import pkm
    from pkm import compiled
    from pkm.batch import interpreted
    from pkm.catalogue import kernels
    from pkm.compiled import emit
    from pkm.compiled.toolchain import find

    toolchain = find()
    if toolchain is None:
        raise SystemExit("no C compiler: nothing to measure")
    catalogue = [k for name in pkm.mechanisms() for k in kernels(pkm.load(name))]
    rng = np.random.default_rng(0)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for entry in _spread(catalogue, count):
            fn, instructions = entry.function, entry.function.n_instructions()
            source = Path(tmp) / "kernel.c"
            source.write_text(emit.source(fn, entry.summed))
            seconds = []
            for _ in range(2):
                start = time.perf_counter()
                toolchain.compile_kernel(source, Path(tmp) / "kernel.so", instructions, entry.summed)
                seconds.append(time.perf_counter() - start)
            args = [rng.uniform(-1, 1, (ROWS, fn.numel_in(i))) for i in range(fn.n_in())]
            interpreting = []
            for _ in range(3):
                start = time.perf_counter()
                interpreted(fn, *args)
                interpreting.append(time.perf_counter() - start)
            row = {"kernel": entry.label, "instructions": instructions,
                   "level": toolchain.optimisation(instructions, entry.summed),
                   "compile_s": min(seconds), "interpreter_ns": min(interpreting) / (ROWS * instructions) * 1e9}
            log(f"{row['kernel']}: {instructions} instructions, compile {row['compile_s']:.3f} s, "
                f"interpreter {row['interpreter_ns']:.1f} ns per instruction and row")
            rows.append(row)
    sizes = np.array([r["instructions"] for r in rows], dtype=float)
    fixed, per_instruction = np.linalg.lstsq(np.column_stack([np.ones_like(sizes), sizes]),
                                             np.array([r["compile_s"] for r in rows]), rcond=None)[0]
    ns = float(np.median([r["interpreter_ns"] for r in rows]))
    return {
        "machine": machine(), "compiler": toolchain.identity, "rows": rows,
        "fit": {"fixed_s": float(fixed), "per_instruction_ms": float(per_instruction) * 1e3,
                "interpreter_ns_median": ns, "compile_work": float(fixed) / (ns * 1e-9),
                "compile_rows": float(per_instruction) / (ns * 1e-9)},
        "constants": {"COMPILE_WORK": compiled.COMPILE_WORK, "COMPILE_ROWS": compiled.COMPILE_ROWS},
    }


def markdown(report: dict[str, Any]) -> str:
    fit, constants = report["fit"], report["constants"]
    lines = [
        "| kernel | instructions | level | compile [s] | interpreter [ns / instruction / row] |",
        "|---|---:|---|---:|---:|",
        *(f"| {r['kernel']} | {r['instructions']} | {r['level']} | {r['compile_s']:.3f} | {r['interpreter_ns']:.1f} |"
          for r in report["rows"]),
        "",
        f"Fit: a compile takes {fit['fixed_s']:.3f} s + {fit['per_instruction_ms']:.3f} ms per instruction; the "
        f"interpreter {fit['interpreter_ns_median']:.1f} ns per instruction and row (median). In interpreter work: "
        f"{fit['compile_work']:.3g} instructions times rows fixed (COMPILE_WORK = 2^"
        f"{constants['COMPILE_WORK'].bit_length() - 1}) and {fit['compile_rows']:.3g} rows per instruction "
        f"(COMPILE_ROWS = 2^{constants['COMPILE_ROWS'].bit_length() - 1}).",
    ]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, default=Path("docs/benchmarks/compile_price.json"))
    parser.add_argument("--kernels", type=int, default=16)
    args = parser.parse_args()
    report = measure(args.kernels)
    write_json(args.json, report)
    print(markdown(report))


if __name__ == "__main__":
    main()
