"""The 2-UPS-PU (Zhao 2008): ``python -m bench.ups_pu [--quick] [--json PATH]``.

* IK + J + statics over random poses (Table 1's design, l0 over its stroke, both angles in +-40 deg,
  a wrench per pose): pkm's public API against a hand-written numpy implementation in the same run,
  checked against each other to 1e-9 before timing;
* the workspace volume of section 5.3's example by the paper's ray search and by dense sampling,
  against a reference of dense sampling at twice the resolution (time and error);
* the synthesis ``ups_pu.min_size_force_task`` against its Monte Carlo baseline.

Figures are best of ``repeats``; nothing asserts on time. :func:`markdown` renders the table that
docs/benchmarks.md quotes (tests/test_benchmark_docs.py checks it against the committed JSON).
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
from pkm.batch import REACH_TOLERANCE
from pkm.models.ups_pu.mechanism import SINGULAR_CONDITION
from pkm.models.ups_pu.workspace import PARALLEL, volume

SEED = 20261123
ANGLE = 40 * math.pi / 180
EXAMPLE_53 = {"r": 0.100, "R": 0.120, "beta": 25 * math.pi / 180, "l_min": 0.320, "l_max": 0.578,
              "l0_min": 0.320, "l0_max": 0.570, "theta_s_max": 60 * math.pi / 180}


def numpy_ik_jacobian_statics(x: np.ndarray, wrench: np.ndarray, d: Mapping[str, float]):
    """Leg lengths (n, 3), J (n, 3, 3) and actuator forces (n, 3) of eqs. 2-4, 7 and 8 (physical), numpy."""
    q, J, W = numpy_kinematics(x, d)
    return q, J, np.linalg.solve(W, wrench[:, :, None])[:, :3, 0]


def numpy_kinematics(x: np.ndarray, d: Mapping[str, float]):
    """Leg lengths (n, 3), J (n, 3, 3) and the wrench matrix W (n, 6, 6) of eqs. 2-4, 7 and 8 (physical)."""
    l0, t1, t2 = x.T
    c1, s1, c2, s2 = np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)
    n = len(x)
    rot = np.empty((n, 3, 3))
    rot[:, 0] = np.stack([c2, 0 * c2, s2], axis=1)
    rot[:, 1] = np.stack([s1 * s2, c1, -s1 * c2], axis=1)
    rot[:, 2] = np.stack([-c1 * s2, s1, c1 * c2], axis=1)
    u0 = np.stack([0 * l0, 0 * l0, l0], axis=1)
    J = np.zeros((n, 3, 3))
    J[:, 2, 0] = 1.0
    q = np.empty((n, 3))
    q[:, 2] = l0
    W = np.zeros((n, 6, 6))
    d1 = np.empty_like(rot)
    d1[:, 0] = 0
    d1[:, 1] = np.stack([c1 * s2, -s1, -c1 * c2], axis=1)
    d1[:, 2] = np.stack([s1 * s2, c1, -s1 * c2], axis=1)
    d2 = np.empty_like(rot)
    d2[:, 0] = np.stack([-s2, 0 * s2, c2], axis=1)
    d2[:, 1] = np.stack([s1 * c2, 0 * c2, s1 * s2], axis=1)
    d2[:, 2] = np.stack([-c1 * c2, 0 * c2, -c1 * s2], axis=1)
    for k, a in enumerate((d["alpha"], d["beta"])):
        local = d["r"] * np.array([math.cos(a), math.sin(a), 0.0])
        base = d["R"] * np.array([math.cos(a), math.sin(a), 0.0])
        arm = rot @ local
        v = u0 + arm - base
        length = np.linalg.norm(v, axis=1)
        s = v / length[:, None]
        q[:, k] = length
        J[:, k, 0] = s[:, 2]
        J[:, k, 1] = np.einsum("ni,ni->n", s, d1 @ local)
        J[:, k, 2] = np.einsum("ni,ni->n", s, d2 @ local)
        W[:, :3, k] = s
        W[:, 3:, k] = np.cross(arm, s)
    W[:, 2, 2] = 1.0
    W[:, 0, 3] = 1.0
    W[:, 1, 4] = 1.0
    W[:, 4, 5] = -s1
    W[:, 5, 5] = c1
    return q, J, W


def _segment_distance(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> np.ndarray:
    """Least distance between the segments p1q1 and p2q2 row by row (closest points clamped to the segments,
    Ericson 2005 section 5.1.9, as pkm.models.ups_pu.workspace.segment_distance)."""
    d1, d2, w = q1 - p1, q2 - p2, p1 - p2
    a, e = np.einsum("ni,ni->n", d1, d1), np.einsum("ni,ni->n", d2, d2)
    b, c, f = np.einsum("ni,ni->n", d1, d2), np.einsum("ni,ni->n", d1, w), np.einsum("ni,ni->n", d2, w)
    denominator = a * e - b**2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denominator > PARALLEL, np.clip((b * f - c * e) / denominator, 0, 1), 0.0)
        t = (b * s + f) / e
        s = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0, 1)
    return np.linalg.norm(p1 + s[:, None] * d1 - (p2 + t[:, None] * d2), axis=1)


def _home_jacobian(l0: np.ndarray, d: Mapping[str, float]) -> np.ndarray:
    """J (n, 3, 3) at the home orientation theta1 = theta2 = 0 of each l0: the platform's frame is the base's, so
    each leg's vector is its attachments' fixed offset in the plane and l0 along z."""
    J = np.zeros((len(l0), 3, 3))
    J[:, 2, 0] = 1.0
    for k, a in enumerate((d["alpha"], d["beta"])):
        local = d["r"] * np.array([math.cos(a), math.sin(a), 0.0])
        offset = local - d["R"] * np.array([math.cos(a), math.sin(a), 0.0])
        length = np.sqrt(offset[0] ** 2 + offset[1] ** 2 + l0**2)
        # at R = I, d(R local)/d theta1 = (0, 0, local_y) and d(R local)/d theta2 = (0, 0, -local_x)
        J[:, k, 0] = l0 / length
        J[:, k, 1] = l0 * local[1] / length
        J[:, k, 2] = -l0 * local[0] / length
    return J


def numpy_limits(x: np.ndarray, q: np.ndarray, J: np.ndarray, d: Mapping[str, float]) -> np.ndarray:
    """The 17 margins of pkm.models.ups_pu.workspace.MARGINS (n, 17), numpy: det J's home sign, strokes, the
    joints' ranges, the legs' interference and the angles' range."""
    l0, t1, t2 = x.T
    n = len(x)
    scale = np.array([1.0, 1 / d["r"], 1 / d["r"]])
    det = np.linalg.det(J * scale)
    det_home = np.linalg.det(_home_jacobian(l0, d) * scale)
    c1, s1, c2, s2 = np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)
    rot = np.empty((n, 3, 3))
    rot[:, 0] = np.stack([c2, 0 * c2, s2], axis=1)
    rot[:, 1] = np.stack([s1 * s2, c1, -s1 * c2], axis=1)
    rot[:, 2] = np.stack([-c1 * s2, s1, c1 * c2], axis=1)
    u0 = np.column_stack([0 * l0, 0 * l0, l0])
    z_p = rot[:, :, 2]
    legs = []
    for a in (d["alpha"], d["beta"]):
        s = u0 + rot @ (d["r"] * np.array([math.cos(a), math.sin(a), 0.0]))
        u = np.broadcast_to(d["R"] * np.array([math.cos(a), math.sin(a), 0.0]), s.shape)
        legs.append((u, s, (s - u) / np.linalg.norm(s - u, axis=1)[:, None]))
    (u1, s1_, a1), (u2, s2_, a2) = legs
    origin = np.zeros_like(u0)
    cos_u, cos_s = math.cos(d["theta_u_max"]), math.cos(d["theta_s_max"])
    return np.column_stack([
        det * np.sign(det_home),
        q[:, 0] - d["l_min"], d["l_max"] - q[:, 0], q[:, 1] - d["l_min"], d["l_max"] - q[:, 1],
        l0 - d["l0_min"], d["l0_max"] - l0,
        a1[:, 2] - cos_u, a2[:, 2] - cos_u,
        np.einsum("ni,ni->n", a1, z_p) - cos_s, np.einsum("ni,ni->n", a2, z_p) - cos_s,
        z_p[:, 2] - cos_u,
        _segment_distance(u1, s1_, u2, s2_) - d["D"],
        _segment_distance(u1, s1_, origin, u0) - d["D"],
        _segment_distance(u2, s2_, origin, u0) - d["D"],
        math.pi / 2 - np.abs(t1), math.pi / 2 - np.abs(t2),
    ])


def numpy_within_limits(x: np.ndarray, wrench: np.ndarray, d: Mapping[str, float]):
    """:func:`numpy_ik_jacobian_statics` as pkm's inverse_kinematics, jacobian and statics answer: the joints
    and the forces NaN where a margin of :func:`numpy_limits` is below -REACH_TOLERANCE, the forces also where
    the wrench matrix is singular (its Frobenius condition number at least SINGULAR_CONDITION); J, the
    kinematics, beyond the limits too."""
    q, J, W = numpy_kinematics(x, d)
    inside = np.all(numpy_limits(x, q, J, d) >= -REACH_TOLERANCE, axis=1)
    inverse = np.linalg.inv(W)
    regular = np.linalg.norm(W, axis=(1, 2)) * np.linalg.norm(inverse, axis=(1, 2)) < SINGULAR_CONDITION
    forces = np.einsum("nij,nj->ni", inverse[:, :3], wrench)
    return (np.where(inside[:, None], q, np.nan), J, np.where((inside & regular)[:, None], forces, np.nan))


def _best(fn: Callable[[], Any], repeats: int) -> float:
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def throughput(n: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    m = pkm.load("ups_pu")
    design = m.design()
    d = dict(design)
    rng = np.random.default_rng(SEED)
    x = np.column_stack([rng.uniform(d["l0_min"], d["l0_max"], n), rng.uniform(-ANGLE, ANGLE, (n, 2))])
    wrench = rng.normal(size=(n, 6)) * [100, 100, 1000, 10, 10, 10]

    def with_pkm():
        return m.inverse_kinematics(x, design), m.jacobian(x, design), m.statics(x, wrench, design).actuators

    reference = numpy_within_limits(x, wrench, d)
    ours = with_pkm()
    for a, b in zip(ours, reference, strict=True):
        if not np.array_equal(np.isnan(a), np.isnan(b)):
            differ = int(np.sum(np.isnan(a) != np.isnan(b)))
            raise AssertionError(f"pkm and numpy hold the limits at different poses ({differ} entries)")
    error = max(float(np.nanmax(np.abs(a - b) / np.maximum(1.0, np.abs(b)))) for a, b in zip(ours, reference,
                                                                                               strict=True))
    if not error <= 1e-9:
        raise AssertionError(f"pkm and numpy differ by {error:.3g}")
    inside = float(np.mean(~np.isnan(reference[0][:, 0])))
    log(f"ups_pu throughput: pkm agrees with numpy to {error:.2g}; {inside:.0%} of the poses within the limits")
    rows = []
    for name, fn in (("numpy, hand-written (IK + J + statics, limits held)",
                      lambda: numpy_within_limits(x, wrench, d)),
                     ("numpy, hand-written (IK + J + statics, no limits)",
                      lambda: numpy_ik_jacobian_statics(x, wrench, d)),
                     ("pkm inverse_kinematics + jacobian + statics (limits held)", with_pkm)):
        seconds = _best(fn, repeats)
        rows.append({"name": name, "seconds": seconds, "poses_per_s": n / seconds})
        log(f"  {name}: {n / seconds:.3g} poses/s")
    for row in rows:
        row["ratio_vs_numpy"] = row["poses_per_s"] / rows[0]["poses_per_s"]
    return {"poses": n, "repeats": repeats, "seed": SEED, "max_discrepancy": error, "within_limits": inside,
            "rows": rows}


def volume_bench(resolution: int, rays: int, planes: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Workspace volume [m rad^2] of section 5.3's example over its l0 stroke (midpoint rule): dense
    sampling and the ray search against dense sampling at twice the resolution."""
    m = pkm.load("ups_pu")
    design = m.design({**m.design(), **EXAMPLE_53}).vector()
    out = {}
    for key, res, method in (("reference", 2 * resolution, "sampled"), ("sampled", resolution, "sampled"),
                             ("ray_search", 2, "ray_search")):
        start = time.perf_counter()
        result = volume(m, design, planes=planes, resolution=res, rays=rays)
        seconds = time.perf_counter() - start
        out[key] = {"volume": result[method], "seconds": seconds, "reentrant_rays": result["reentrant_rays"]}
        log(f"  volume {key}: {out[key]['volume']:.5g} m rad^2 in {seconds:.2f} s")
    for key in ("sampled", "ray_search"):
        out[key]["relative_error"] = abs(out[key]["volume"] / out["reference"]["volume"] - 1)
    return {"planes": planes, "resolution": resolution, "rays": rays, **out}


def synthesis(log: Callable[[str], None]) -> dict[str, Any]:
    start = time.perf_counter()
    result = pkm.synthesize("ups_pu.min_size_force_task")
    log(f"  synthesis in {time.perf_counter() - start:.1f} s")
    mc = result.baselines["monte_carlo"]
    return {
        "optimizer": {**result.optimizer, "objective": result.objective, "verified": result.verified_objective},
        "monte_carlo": {"wall_time_s": mc.wall_time_s, "evaluations": mc.evaluations,
                        "objective": mc.best.objective, "verified": mc.best.verified_objective},
        "table1": {"objective": result.baselines["table1"].best.objective,
                   "feasible": result.baselines["table1"].best.feasible},
    }


def run(n: int, repeats: int, log: Callable[[str], None]) -> dict[str, Any]:
    return {
        "throughput": throughput(n, repeats, log),
        "volume": volume_bench(120, 360, 10, log),
        "synthesis": synthesis(log),
    }


def markdown(report: Mapping[str, Any]) -> str:
    tp, vol, syn = report["throughput"], report["volume"], report["synthesis"]
    lines = [
        "| IK + J + statics, 2-UPS-PU | poses/s | vs numpy | time (s) |",
        "|---|---:|---:|---:|",
    ]
    lines += [f"| {r['name']} | {r['poses_per_s'] / 1e6:.2f} M | {r['ratio_vs_numpy']:.2f}x | {r['seconds']:.3f} |"
              for r in tp["rows"]]
    lines += [
        "",
        "| workspace volume, section 5.3 example | volume (m rad^2) | error vs reference | time (s) |",
        "|---|---:|---:|---:|",
        f"| dense sampling {2 * vol['resolution']}^2 per plane (reference) | {vol['reference']['volume']:.5f} | - "
        f"| {vol['reference']['seconds']:.2f} |",
        f"| dense sampling {vol['resolution']}^2 per plane | {vol['sampled']['volume']:.5f} "
        f"| {vol['sampled']['relative_error']:.2%} | {vol['sampled']['seconds']:.2f} |",
        f"| ray search, {vol['rays']} rays per plane ({vol['ray_search']['reentrant_rays']} rays re-enter) "
        f"| {vol['ray_search']['volume']:.5f} | {vol['ray_search']['relative_error']:.2%} "
        f"| {vol['ray_search']['seconds']:.2f} |",
        "",
        "| synthesis ups_pu.min_size_force_task | wall time (s) | evaluations | objective | verified |",
        "|---|---:|---:|---:|---:|",
        f"| IPOPT (pkm.synthesize) | {syn['optimizer']['wall_time_s']:.2f} | {syn['optimizer']['evaluations']} "
        f"| {syn['optimizer']['objective']:.4g} | {syn['optimizer']['verified']:.4g} |",
        f"| Monte Carlo (the paper's search) | {syn['monte_carlo']['wall_time_s']:.2f} "
        f"| {syn['monte_carlo']['evaluations']} | {syn['monte_carlo']['objective']:.4g} "
        f"| {syn['monte_carlo']['verified']:.4g} |",
        f"| Table 1 on the same model | - | 1 | {syn['table1']['objective']:.4g} "
        f"| {'feasible' if syn['table1']['feasible'] else 'infeasible'} |",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.ups_pu", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^5 poses instead of 10^6")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    args = parser.parse_args(argv)
    report = run(100_000 if args.quick else 1_000_000, 3, lambda msg: print(msg, file=sys.stderr, flush=True))
    print(markdown(report))
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
