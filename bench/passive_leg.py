"""The passive-leg manipulator (Nam 2006): ``python -m bench.passive_leg [--quick] [--json PATH]``.

* IK + J + 1/kappa_f over random poses of the workspace at the default design on working mode
  ``out_out`` (Fig. 1): pkm's fused ``local_index("inverse_condition_f")`` and ``jacobian`` against a
  hand-written numpy implementation of eqs. 5-6, 19-20 and Gao's 1/kappa_f in the same run, checked
  against each other to 1e-9 before timing;
* the forward kinematics of actuator angles of such poses: the real roots of the degree-6 polynomial
  (eq. 11 as derived) by pkm's batched companion matrices, against ``numpy.roots`` in a Python loop over
  a subset of the same coefficients; every real solution's loop residual, and the pose each
  configuration came from found among its solutions;
* the synthesis ``passive_leg.max_composed`` against its 61 x 61 grid, after the normalisation extremes
  of eq. 31 (computed once per session, timed on their own).

Figures are best of ``repeats`` on ``pkm.batch.THREADS`` threads; nothing asserts on time.
:func:`markdown` renders the tables that docs/benchmarks.md quotes (tests/test_benchmark_docs.py checks
them against the committed JSON).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

import pkm
import pkm.batch
from pkm.batch import evaluate
from pkm.kinematics import IMAGINARY_TOLERANCE
from pkm.models.passive_leg import nam2006

SEED = 20261124
MODE = "out_out"
THETA = 1.3  # |theta| of the drawn poses [rad], inside theta_max = 85 deg
FRACTION = (0.05, 0.95)  # l_c of the drawn poses as a fraction of l_CM(theta)
PROBLEM = "passive_leg.max_composed"


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max(1, |b|)."""
    return float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(b))))


def _best(fn: Callable[[], Any], repeats: int) -> float:
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def workspace_poses(m: pkm.Mechanism, design: np.ndarray, n: int, rng: np.random.Generator) -> np.ndarray:
    """Poses (n, 2) C = l_c (-sin theta, cos theta) (eq. 7), theta uniform in +-THETA and l_c uniform in
    FRACTION of the outer boundary l_CM(theta) (eq. 12; the default design has no inner boundary)."""
    theta = rng.uniform(-THETA, THETA, n)
    length = rng.uniform(*FRACTION, n) * m.workspace_boundary(theta, design)["l_CM"]
    return np.column_stack([-length * np.sin(theta), length * np.cos(theta)])


def numpy_ik_jacobian_index(
    x: np.ndarray, d: Mapping[str, float], signs: tuple[float, float] = (1.0, -1.0)
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """phi (n, 2), J = J_q^-1 J_x (n, 2, 2) and 1/kappa_f (n,) at poses (n, 2), numpy.

    theta = atan2(-x_c, y_c) (eq. 1); b_i = C +- r u; phi_i from eq. 5's alpha_i, beta_i, gamma_i in the
    atan2 form of eq. 6 with the signs s_i; J_q, J_x of eqs. 19-20; 1/kappa_f = 2 / sqrt(||J||_F^2
    ||J^-1||_F^2) = 2 |det J| / ||J||_F^2 for a 2 x 2 J.
    """
    R, r, la, lb = d["R"], d["r"], d["l_a"], d["l_b"]
    xc, yc = x[:, 0], x[:, 1]
    theta = np.arctan2(-xc, yc)
    c, s = np.cos(theta), np.sin(theta)
    phis, X, Y, Jq = [], [], [], []
    for side, sign in ((1.0, signs[0]), (-1.0, signs[1])):
        px, py = xc + side * (r * c - R), yc + side * r * s  # b_i - B_i
        alpha, beta = 2 * la * px, 2 * la * py
        gamma = -(alpha**2 + beta**2) / (4 * la**2) + lb**2 - la**2
        root = np.sqrt(alpha**2 + beta**2 - gamma**2)
        phi = np.arctan2(-beta * gamma - sign * alpha * root, -alpha * gamma + sign * beta * root)
        cp, sp = np.cos(phi), np.sin(phi)
        Xi, Yi = px - la * cp, py - la * sp  # b_i - d_i
        phis.append(phi)
        X.append(Xi)
        Y.append(Yi)
        Jq.append(la * (-Xi * sp + Yi * cp))
    den = xc * s - yc * c
    Z = [r * (-X[i] * s + Y[i] * c) / den for i in range(2)]
    J = np.empty((len(x), 2, 2))
    J[:, 0, 0] = (X[0] + Z[0] * c) / Jq[0]
    J[:, 0, 1] = (Y[0] + Z[0] * s) / Jq[0]
    J[:, 1, 0] = (X[1] - Z[1] * c) / Jq[1]
    J[:, 1, 1] = (Y[1] - Z[1] * s) / Jq[1]
    frobenius2 = np.einsum("nij,nij->n", J, J)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    return np.column_stack(phis), J, 2 * np.abs(det) / frobenius2


def throughput(n: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    m = pkm.load("passive_leg")
    design = m.design_vector(None)
    d = dict(m.design())
    x = workspace_poses(m, design, n, np.random.default_rng(SEED))

    def fused():
        return m.local_index("inverse_condition_f", x, design, mode=MODE)

    def jacobian():
        return m.jacobian(x, design, mode=MODE)

    phi, J, index = numpy_ik_jacobian_index(x, d)
    discrepancy = {
        "phi": _relative(m.inverse_kinematics(x, design, mode=MODE), phi),
        "J": _relative(jacobian(), J),
        "inverse_condition_f": _relative(fused(), index),
    }
    error = max(discrepancy.values())
    if not error <= 1e-9:
        raise AssertionError(f"pkm and numpy differ by {error:.3g}: {discrepancy}")
    log(f"passive_leg throughput: pkm agrees with numpy to {error:.2g}")
    rows = []
    for name, fn in (
        ("numpy, hand-written (IK + J + 1/kappa_f)", lambda: numpy_ik_jacobian_index(x, d)),
        ('pkm local_index("inverse_condition_f") (IK + J + 1/kappa_f, fused)', fused),
        ("pkm jacobian (IK + J)", jacobian),
    ):
        seconds = _best(fn, repeats)
        rows.append({"name": name, "seconds": seconds, "poses_per_s": n / seconds})
        log(f"  {name}: {n / seconds:.3g} poses/s")
    for row in rows:
        row["ratio_vs_numpy"] = row["poses_per_s"] / rows[0]["poses_per_s"]
    return {
        "poses": n,
        "repeats": repeats,
        "seed": SEED,
        "mode": MODE,
        "threads": pkm.batch.THREADS,
        "index_range": [float(index.min()), float(index.max())],
        "max_discrepancy": error,
        "discrepancy": discrepancy,
        "rows": rows,
    }


def numpy_real_roots(c: np.ndarray) -> np.ndarray:
    """Real roots (N, degree) of each row of c (highest degree first), ascending, NaN-padded, by
    ``numpy.roots`` one row at a time; real by the tolerance pkm uses."""
    out = np.full((len(c), c.shape[1] - 1), np.nan)
    for k, row in enumerate(c):
        roots = np.roots(row)
        real = np.sort(roots[np.abs(roots.imag) <= IMAGINARY_TOLERANCE * np.maximum(1.0, np.abs(roots))].real)
        out[k, : len(real)] = real
    return out


def loop_residual(phi: np.ndarray, pose: np.ndarray, theta: np.ndarray, d: Mapping[str, float]) -> np.ndarray:
    """| |b_i - d_i| - l_b | (eqs. 2-3) of each solution, legs stacked last: phi (N, 2), pose (N, k, 2),
    theta (N, k) -> (N, k, 2) [m]."""
    u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
    out = []
    for k, side in enumerate((1.0, -1.0)):
        elbow = np.stack([side * d["R"] + d["l_a"] * np.cos(phi[:, k]), d["l_a"] * np.sin(phi[:, k])], axis=-1)
        platform = pose + side * d["r"] * u
        out.append(np.abs(np.linalg.norm(platform - elbow[:, None, :], axis=-1) - d["l_b"]))
    return np.stack(out, axis=-1)


def forward(n: int, subset: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    m = pkm.load("passive_leg")
    design = m.design_vector(None)
    d = dict(m.design())
    x = workspace_poses(m, design, n, np.random.default_rng(SEED + 1))
    q = m.inverse_kinematics(x, design, mode=MODE)
    (c,) = evaluate(m.functions["forward_polynomial"], q, design)
    c = c.reshape(n, -1)

    solutions = m.forward_solutions(q, design)
    residual = loop_residual(q, solutions.pose, solutions.theta, d).max(axis=-1)
    found = np.isfinite(solutions.l_c)
    distance = np.linalg.norm(solutions.pose - x[:, None, :], axis=-1)
    recovered = np.nanmin(distance, axis=1)
    generating = np.nanargmin(distance, axis=1)
    worst = np.unravel_index(np.argmax(np.where(found, residual, -1.0)), residual.shape)
    gaps = np.abs(solutions.l_c[worst[0]] - solutions.l_c[worst])
    gaps[worst[1]] = np.nan
    on_mode = solutions.modes[np.arange(n), generating] == MODE
    reference = numpy_real_roots(c[:subset])
    ours = solutions.l_c[:subset]
    same_count = np.sum(np.isfinite(reference), axis=1) == solutions.count[:subset]
    both = np.isfinite(reference) & np.isfinite(ours) & same_count[:, None]
    checks = {
        "mean_solutions": float(solutions.count.mean()),
        "solutions_histogram": np.bincount(solutions.count, minlength=7).tolist(),
        "max_loop_residual": float(residual[found].max()),
        "loop_residual_p9999": float(np.percentile(residual[found], 99.99)),
        "worst_residual_root_gap": float(np.nanmin(gaps)),
        "max_loop_residual_generating": float(residual[np.arange(n), generating].max()),
        "max_pose_recovery": float(recovered.max()),
        "pose_on_its_mode": int(on_mode.sum()),
        "subset_count_agreement": int(same_count.sum()),
        "subset_max_root_difference": _relative(ours[both], reference[both]),
    }
    log(f"passive_leg forward: {checks}")

    rows = []
    for name, size, fn in (
        ("numpy.roots in a Python loop (real roots only)", subset, lambda: numpy_real_roots(c[:subset])),
        (
            "pkm forward.compute (coefficients + batched companion eigenvalues + polish)",
            n,
            lambda: m.forward.compute(m.functions, q, design),
        ),
        ("pkm forward_solutions (+ poses, joints, working modes)", n, lambda: m.forward_solutions(q, design)),
    ):
        seconds = _best(fn, repeats)
        rows.append({"name": name, "configurations": size, "seconds": seconds, "per_configuration_s": seconds / size})
        log(f"  {name}: {seconds / size * 1e6:.3g} us per configuration")
    for row in rows:
        row["ratio_vs_numpy"] = rows[0]["per_configuration_s"] / row["per_configuration_s"]
    return {
        "configurations": n,
        "subset": subset,
        "repeats": repeats,
        "seed": SEED + 1,
        "mode": MODE,
        "threads": pkm.batch.THREADS,
        **checks,
        "rows": rows,
    }


def _candidate(best, wall_time_s: float, evaluations: int) -> dict[str, Any]:
    return {
        "wall_time_s": wall_time_s,
        "evaluations": evaluations,
        "objective": best.objective,
        "verified": best.verified_objective,
        "variables": dict(best.variables),
    }


def synthesis(log: Callable[[str], None]) -> dict[str, Any]:
    start = time.perf_counter()
    bounds = nam2006.extremes(nam2006.SUPPORTED)
    extremes_s = time.perf_counter() - start
    log(f"  extremes in {extremes_s:.1f} s")
    start = time.perf_counter()
    result = pkm.synthesize(pkm.registry.problem(PROBLEM))
    total = time.perf_counter() - start
    log(f"  synthesis in {total:.1f} s")
    grid = result.baselines["grid"]
    return {
        "problem": PROBLEM,
        "extremes": {
            "seconds": extremes_s,
            "grid": nam2006.EXTREMES_GRID,
            "resolution": nam2006.RESOLUTION,
            "designs": nam2006.EXTREMES_GRID**2,
            "bounds": [list(b) for b in bounds],
        },
        "total_wall_time_s": total,
        "status": result.status,
        "optimizer": _candidate(result.optimum, result.optimizer["wall_time_s"], result.optimizer["evaluations"]),
        "grid": _candidate(grid.best, grid.wall_time_s, grid.evaluations),
    }


def run(n: int, fk: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    return {
        "throughput": throughput(n, repeats, log),
        "forward": forward(fk, min(2000, fk), repeats, log),
        "synthesis": synthesis(log),
    }


def markdown(report: Mapping[str, Any]) -> str:
    tp, fk, syn = report["throughput"], report["forward"], report["synthesis"]
    lines = [
        f"| IK + J + 1/kappa_f, passive_leg {tp['mode']}, {tp['threads']} threads | poses/s | vs numpy | time (s) |",
        "|---|---:|---:|---:|",
    ]
    lines += [
        f"| {r['name']} | {r['poses_per_s'] / 1e6:.2f} M | {r['ratio_vs_numpy']:.2f}x | {r['seconds']:.3f} |"
        for r in tp["rows"]
    ]
    lines += [
        "",
        "| forward kinematics, degree-6 polynomial | configurations | per configuration (us) | vs numpy.roots "
        "| time (s) |",
        "|---|---:|---:|---:|---:|",
    ]
    lines += [
        f"| {r['name']} | {r['configurations']} | {r['per_configuration_s'] * 1e6:.2f} "
        f"| {r['ratio_vs_numpy']:.1f}x | {r['seconds']:.3f} |"
        for r in fk["rows"]
    ]
    hist = ", ".join(f"{k}: {v}" for k, v in enumerate(fk["solutions_histogram"]) if v)
    lines += [
        "",
        f"| forward kinematics, {fk['configurations']} configurations | value |",
        "|---|---:|",
        f"| mean number of real solutions (count: configurations) | {fk['mean_solutions']:.3f} ({hist}) |",
        f"| max loop residual abs(abs(b_i - d_i) - l_b) of the generating pose's solution (m) "
        f"| {fk['max_loop_residual_generating']:.1e} |",
        f"| max loop residual of every real solution (m) | {fk['max_loop_residual']:.1e} |",
        f"| distance of that solution's l_c to the nearest other root (a near-double root) (m) "
        f"| {fk['worst_residual_root_gap']:.1e} |",
        f"| 99.99th percentile of the loop residual of every real solution (m) | {fk['loop_residual_p9999']:.1e} |",
        f"| max distance of the generating pose to its nearest solution (m) | {fk['max_pose_recovery']:.1e} |",
        f"| configurations whose solution at the generating pose is on {fk['mode']} | {fk['pose_on_its_mode']} |",
        f"| same number of real roots as numpy.roots (of {fk['subset']}) | {fk['subset_count_agreement']} |",
        f"| max difference of the real roots to numpy.roots (relative) | {fk['subset_max_root_difference']:.1e} |",
    ]
    ext, opt, grid = syn["extremes"], syn["optimizer"], syn["grid"]
    lines += [
        "",
        f"| synthesis {syn['problem']} | wall time (s) | evaluations | objective | verified | r/R | l_b/R |",
        "|---|---:|---:|---:|---:|---:|---:|",
        f"| normalisation extremes (nam2006.extremes, {ext['grid']} x {ext['grid']} designs, once per session) "
        f"| {ext['seconds']:.2f} | {ext['designs']} | - | - | - | - |",
        f"| IPOPT (pkm.synthesize, status {syn['status']}) | {opt['wall_time_s']:.2f} | {opt['evaluations']} "
        f"| {opt['objective']:.6f} | {opt['verified']:.6f} | {opt['variables']['r']:.4f} "
        f"| {opt['variables']['l_b']:.4f} |",
        f"| grid baseline (Nam Figs. 4-7) | {grid['wall_time_s']:.2f} | {grid['evaluations']} "
        f"| {grid['objective']:.6f} | {grid['verified']:.6f} | {grid['variables']['r']:.4f} "
        f"| {grid['variables']['l_b']:.4f} |",
        f"| pkm.synthesize in all (screening, IPOPT, grid, verification) | {syn['total_wall_time_s']:.2f} | - | - "
        "| - | - | - |",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.passive_leg", description=__doc__.splitlines()[0])
    parser.add_argument(
        "--quick", action="store_true", help="10^5 poses and 10^4 configurations instead of 10^6 and 10^5"
    )
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    args = parser.parse_args(argv)
    n, fk = (100_000, 10_000) if args.quick else (1_000_000, 100_000)
    report = run(n, fk, 3, lambda msg: print(msg, file=sys.stderr, flush=True))
    print(markdown(report))
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
