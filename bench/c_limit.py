"""The C limit of the five-bar's 1/kappa_f: ``python -m bench.c_limit [--quick] [--json PATH] [--repeats K]``.

pkm's public ``local_index("inverse_condition_f", X, DESIGN, mode=MODE)`` of the five-bar over 10^6
reachable poses (``--quick``: 10^5; DESIGN, MODE and the poses of bench/throughput.py) against a
hand-written C loop over the poses that computes the same maths without trigonometric calls
(symbolic/mechanisms/five_bar.py, :class:`ChainSolution`): for chain i, with d = P - O_i,

    k = (r1^2 + |d|^2 - r2^2) / 2,   h^2 = r1^2 |d|^2 - k^2,   margin = h^2 / (r1^2 |d|^2),
    h = sqrt(h^2) where margin > 2^-50, else 0,   v = k d + sigma_i h perp(d),   w = |d|^2 d - v,
    row i of J = |d|^2 w^T / (v x w),

then 1/kappa_f = 2 |det J| / ||J||_F^2: NaN where a margin is below -REACH_TOLERANCE (the smaller margin
as C's fmin takes it, as pkm does), 0 where the value is not finite (J not finite at a serial
singularity), as pkm defines the index (pkm/indices/local.py, pkm/regions/pipeline.py). The loop is
compiled in the same run by the compiler, with the flags and libraries pkm compiles its kernels with
(:func:`pkm.compiled.toolchain.find`), into a temporary folder, and called through ctypes; on two threads
the rows are split in two halves and the second half runs on a second Python thread while the calling
thread runs the first (ctypes releases the GIL). Its products and sums are those of pkm's graph, in the
same order up to signs and commutation (exact in IEEE arithmetic), so the two agree to the last bit but
for the margin (one division instead of pkm's two), which decides only which side of a threshold a pose
falls on; agreement to 1e-12 relative, with the same NaN pattern, is checked before any time is taken,
on the sampled poses and on singular and unreachable ones (:func:`special_poses`).

Figures are best of ``repeats``, interleaved: each round runs every task once, in alternating order.
Three overheads of pkm's call are reported on their own: the wall time of one call on 16 poses (median
of 2000 calls: the fixed cost per call), the time of ``numpy.isfinite(X).all()`` on the poses (a serial
input check) and pkm's speed-up from 1 to 2 threads against the limit's. Nothing asserts on time; the
goals (pkm / limit >= 0.95 on one thread, >= 0.85 on two) are reported.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

import pkm
import pkm.batch
import pkm.compiled
from bench.report import log, machine, write_json
from bench.throughput import DESIGN, INDEX, MODE, SEED, sample_poses, set_threads
from pkm.compiled.toolchain import Toolchain, find
from pkm.regions.pipeline import index_pipeline

TOL = 1e-12  # relative, where pkm's value is not 0; equal where it is
SMALL, CALLS = 16, 2000  # poses and calls of the fixed cost per call
GOALS = {1: 0.95, 2: 0.85}  # pkm / limit, by threads

SOURCE = r"""#include <math.h>

/* chain i of the five-bar at the pose: d = (dx, y), ky the part of k common to both chains; its reach
   margin and row i of J. Every product and sum is pkm's (symbolic/mechanisms/five_bar.py), in its order */
static inline void chain(double dx, double y, double y2, double ky, double r1s, double sigma,
                         double *margin, double *jx, double *jy)
{
  const double dx2 = dx * dx;
  const double rho = dx2 + y2;
  const double k = 0.5 * dx2 + ky;
  const double h2 = r1s * rho - k * k;
  *margin = h2 / (r1s * rho);
  const double h = *margin > 0x1p-50 ? sigma * sqrt(h2) : 0.0;
  const double vx = k * dx - h * y, vy = k * y + h * dx;
  const double wx = rho * dx - vx, wy = rho * y - vy;
  const double s = rho / (vx * wy - vy * wx);
  *jx = s * wx;
  *jy = s * wy;
}

/* 1/kappa_f at n poses x (n, 2), C order; design r1, r2, r3, ...; mode sigma1, sigma2 */
void limit(long n, const double *restrict x, const double *restrict design, const double *restrict mode,
           double *restrict out)
{
  const double r1s = design[0] * design[0], half_r1s = 0.5 * r1s, half_r2s = 0.5 * (design[1] * design[1]);
  const double r3 = design[2], sigma1 = mode[0], sigma2 = mode[1];
  for (long p = 0; p < n; ++p) {
    const double px = x[2 * p], y = x[2 * p + 1], y2 = y * y;
    const double ky = (half_r1s + 0.5 * y2) - half_r2s;
    double m1, m2, a, b, c, e;
    chain(px + r3, y, y2, ky, r1s, sigma1, &m1, &a, &b);
    chain(px - r3, y, y2, ky, r1s, sigma2, &m2, &c, &e);
    const double lowest = m2 != m2 || m1 < m2 ? m1 : m2; /* fmin: a NaN margin gives way to the other */
    const double value = 2.0 * fabs(a * e - b * c) / (((a * a + c * c) + b * b) + e * e);
    const double finite = fabs(value) < INFINITY ? value : 0.0;
    out[p] = lowest >= -0x1.19799812dea11p-40 ? finite : NAN; /* -REACH_TOLERANCE, exactly */
  }
}
"""


class Limit:
    """The C loop of :data:`SOURCE` compiled by ``toolchain`` into ``folder`` and loaded with ctypes."""

    def __init__(self, toolchain: Toolchain, folder: Path) -> None:
        source, library = folder / "limit.c", folder / "limit.so"
        source.write_text(SOURCE)
        report = ["-fopt-info-vec-optimized"] if toolchain.gcc else []  # a report only: the same code
        command = [toolchain.compiler, *toolchain.kernel_flags(0), *report, str(source), "-o", str(library),
                   *toolchain.libraries]
        done = subprocess.run(command, check=True, capture_output=True, text=True)
        self.vectorised = "loop vectorized" in done.stderr if toolchain.gcc else None
        self._fn = ctypes.CDLL(str(library)).limit
        self._fn.argtypes = [ctypes.c_long, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
        self._fn.restype = None
        self._pool = ThreadPoolExecutor(1, thread_name_prefix="c-limit")

    def close(self) -> None:
        self._pool.shutdown()

    def __call__(self, X: np.ndarray, design: np.ndarray, signs: np.ndarray, threads: int = 1) -> np.ndarray:
        """1/kappa_f (N,) at the poses X (N, 2), C-contiguous float64: on two threads the second half of
        the rows on the kept thread while this one computes the first."""
        n, out = len(X), np.empty(len(X))
        d, s = design.ctypes.data, signs.ctypes.data
        if threads == 1 or n < 2:
            self._fn(n, X.ctypes.data, d, s, out.ctypes.data)
            return out
        half = n // 2
        second = self._pool.submit(self._fn, n - half, X[half:].ctypes.data, d, s, out[half:].ctypes.data)
        self._fn(half, X.ctypes.data, d, s, out.ctypes.data)
        second.result()
        return out


def special_poses(design: dict[str, float]) -> np.ndarray:
    """Poses where pkm's value is NaN, 0 or near 0: out of reach, at a base joint, on the outer and inner
    boundaries of chain 1 (serial singular: J not finite), at the parallel singularity with both distal
    links horizontal (Lara-Molina eq. 12's y_col), on the base line."""
    r1, r2, r3 = design["r1"], design["r2"], design["r3"]
    y_col = np.sqrt(r1**2 - (r2 - r3) ** 2)
    outer, inner = r1 + r2, abs(r1 - r2)
    return np.array([
        [5.0, 5.0], [0.0, -4.0], [-r3, 0.0], [r3, 0.0], [0.0, 0.0],
        [-r3 + outer, 0.0], [-r3, outer], [-r3 + 0.6 * inner, 0.8 * inner], [-r3 + 0.6 * outer, 0.8 * outer],
        [0.0, y_col], [0.0, -y_col], [0.0, 1.0], [0.3, 0.5], [-0.5, 1.5],
    ])


def discrepancy(got: np.ndarray, want: np.ndarray, what: str) -> float:
    """Largest relative difference from pkm's values (``got`` must equal ``want`` where pkm's is 0);
    raises where it exceeds TOL or the NaN patterns differ."""
    nan = np.isnan(want)
    if not np.array_equal(nan, np.isnan(got)):
        raise AssertionError(f"{what}: NaN at {np.count_nonzero(np.isnan(got) != nan)} poses where pkm differs")
    g, w = got[~nan], want[~nan]
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(g == w, 0.0, np.abs(g - w) / np.abs(w))
    err = float(relative.max(initial=0.0))
    if not err <= TOL:
        raise AssertionError(f"{what} differs from pkm by {err:.3g} relative > {TOL:g}")
    return err


def _best(tasks: dict[str, tuple[int, Callable[[], Any]]], repeats: int) -> dict[str, float]:
    """Best time of each task (name -> (pkm.batch.THREADS, function)) over ``repeats`` interleaved rounds,
    each task's first call untimed."""
    best = dict.fromkeys(tasks, np.inf)
    names, default = list(tasks), pkm.batch.THREADS
    try:
        for i in range(repeats + 1):
            for name in names if i % 2 == 0 else names[::-1]:
                threads, fn = tasks[name]
                set_threads(threads)
                start = time.perf_counter()
                fn()
                if i:
                    best[name] = min(best[name], time.perf_counter() - start)
    finally:
        set_threads(default)
    return best


def _median_call(fn: Callable[[], Any], calls: int) -> float:
    times = []
    for _ in range(calls):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def overheads(m: pkm.Mechanism, limit: Limit, X: np.ndarray, args: tuple[np.ndarray, np.ndarray],
              repeats: int) -> dict[str, Any]:
    """The fixed cost of one call on SMALL poses (pkm's and the limit's, median of CALLS calls, at the
    default pkm.batch.THREADS) and the time of numpy's serial finiteness check of the poses (best of
    ``repeats``)."""
    small = np.ascontiguousarray(X[:SMALL])
    m.local_index(INDEX, small, DESIGN, mode=MODE)
    isfinite = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        np.isfinite(X).all()
        isfinite = min(isfinite, time.perf_counter() - start)
    return {
        "call_16_poses_s": _median_call(lambda: m.local_index(INDEX, small, DESIGN, mode=MODE), CALLS),
        "limit_call_16_poses_s": _median_call(lambda: limit(small, *args), CALLS),
        "call_16_poses_threads": pkm.batch.THREADS,
        "isfinite_all_s": isfinite,
    }


def run(n: int = 1_000_000, repeats: int = 15, log: Callable[[str], None] = log) -> dict[str, Any]:
    """Check the C limit against pkm, then time both on 1 and 2 threads; the report (module docstring)."""
    toolchain = find()
    if isinstance(toolchain, str):
        raise RuntimeError(f"the C limit needs a C compiler: {toolchain}")
    m = pkm.load("five_bar")
    X = sample_poses(m, n)
    design, signs = m.design(DESIGN).vector(), np.asarray(m.working_mode(MODE).signs, dtype=float)
    spec = m.local_spec(INDEX)
    pkm.compiled.build([(index_pipeline(m, (spec,), reach=False), False)])
    with tempfile.TemporaryDirectory(prefix="pkm-c-limit-") as folder:
        limit = Limit(toolchain, Path(folder))
        try:
            special = special_poses(DESIGN)
            want = m.local_index(INDEX, X, DESIGN, mode=MODE)
            errors = [discrepancy(limit(special, design, signs), m.local_index(INDEX, special, DESIGN, mode=MODE),
                                  "the C limit at singular and unreachable poses")]
            errors += [discrepancy(limit(X, design, signs, t), want, f"the C limit on {t} thread(s)") for t in (1, 2)]
            log(f"c_limit: {n} poses; the C limit agrees with pkm to {max(errors):.2g} relative")
            before = os.getloadavg()
            compiled_before = pkm.compiled.status()["evaluations"]["compiled"]
            tasks = {f"{who} {t}": (t, fn) for t in (1, 2) for who, fn in (
                ("limit", lambda t=t: limit(X, design, signs, t)),
                ("pkm", lambda: m.local_index(INDEX, X, DESIGN, mode=MODE)))}
            best = _best(tasks, repeats)
            compiled = pkm.compiled.status()["evaluations"]["compiled"] - compiled_before
            extra = overheads(m, limit, X, (design, signs), repeats)
            after = os.getloadavg()
        finally:
            limit.close()
    rows = [{"name": "C limit (hand-written, ctypes)" if who == "limit" else "pkm local_index", "threads": t,
             "seconds": best[f"{who} {t}"], "poses_per_s": n / best[f"{who} {t}"],
             "note": _note(who, t)} for who in ("limit", "pkm") for t in (1, 2)]
    ratios = {t: best[f"limit {t}"] / best[f"pkm {t}"] for t in (1, 2)}
    speedup = {who: best[f"{who} 1"] / best[f"{who} 2"] for who in ("limit", "pkm")}
    for row in rows:
        log(f"  {row['name']} ({row['threads']} thread(s)): {row['poses_per_s'] / 1e6:.1f} M poses/s")
    return {
        "command": "python -m bench.c_limit " + " ".join(sys.argv[1:]),
        "machine": machine(),
        "poses": n, "repeats": repeats, "seed": SEED, "design": DESIGN, "mode": MODE, "index": INDEX,
        "load_average_before": before, "load_average_after": after,
        "compiler": toolchain.identity, "instruction_set": toolchain.instruction_set,
        "flags": list(toolchain.kernel_flags(0)), "libraries": list(toolchain.libraries),
        "limit_vectorised": limit.vectorised,
        "pkm_compiled_evaluations": compiled, "pkm_timed_evaluations": 2 * (repeats + 1),
        "max_relative_discrepancy": max(errors), "special_poses": len(special),
        "rows": rows,
        "ratio_pkm_over_limit": {str(t): r for t, r in ratios.items()},
        "goals": {str(t): g for t, g in GOALS.items()},
        "overheads": {
            **extra,
            "isfinite_share_of_pkm_1_thread": extra["isfinite_all_s"] / best["pkm 1"],
            "speedup_1_to_2_threads": {"pkm": speedup["pkm"], "limit": speedup["limit"],
                                       "pkm_over_limit": speedup["pkm"] / speedup["limit"]},
        },
    }


def _note(who: str, threads: int) -> str:
    if who == "pkm":
        return f"pkm.batch.THREADS = {threads}, compiled kernel"
    if threads == 1:
        return "one C call on the calling thread"
    return "rows in two halves: one C call on a kept Python thread, one on the calling thread (ctypes drops the GIL)"


def markdown(report: dict[str, Any]) -> str:
    """One table: the four timings with pkm / limit, then the overheads and the conditions in one paragraph."""
    ratio, over = report["ratio_pkm_over_limit"], report["overheads"]
    lines = ["| implementation | threads | poses/s | time (ms) | pkm / limit (goal) |", "|---|---:|---:|---:|---:|"]
    for row in report["rows"]:
        key = str(row["threads"])
        versus = f"{ratio[key]:.2f} (>= {report['goals'][key]:.2f})" if row["name"].startswith("pkm") else ""
        lines.append(f"| {row['name']} | {row['threads']} | {row['poses_per_s'] / 1e6:.1f} M | "
                     f"{row['seconds'] * 1e3:.2f} | {versus} |")
    speed = over["speedup_1_to_2_threads"]
    lines += ["", f"{report['poses']:,} reachable poses, best of {report['repeats']}; agreement "
              f"{report['max_relative_discrepancy']:.1g} relative, NaN pattern equal. Overheads of pkm's call: "
              f"{over['call_16_poses_s'] * 1e6:.1f} us per call on {SMALL} poses (the C limit through ctypes: "
              f"{over['limit_call_16_poses_s'] * 1e6:.1f} us); numpy.isfinite(X).all() "
              f"{over['isfinite_all_s'] * 1e3:.2f} ms ({over['isfinite_share_of_pkm_1_thread']:.0%} of pkm on one "
              f"thread); speed-up from 1 to 2 threads {speed['pkm']:.2f}x for pkm, {speed['limit']:.2f}x for the "
              f"limit. Load average {report['load_average_before'][0]:.2f} before, "
              f"{report['load_average_after'][0]:.2f} after; {report['compiler']}, {' '.join(report['flags'])}."]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.c_limit", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^5 poses instead of 10^6")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    parser.add_argument("--repeats", type=int, default=15, metavar="K", help="best of K rounds (default 15)")
    args = parser.parse_args(argv)
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    report = run(100_000 if args.quick else 1_000_000, args.repeats)
    print(markdown(report))
    if args.json:
        write_json(Path(args.json), report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
