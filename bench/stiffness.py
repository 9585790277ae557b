"""The Delta's Cartesian stiffness at 10^6 poses and a stiffness index over its task (issue 40's speed):
``python -m bench.stiffness [--json PATH]``.

The machine is examples/delta_elastic.toml at its default design, in its working mode elbow_out. pkm's
``m.stiffness`` (its inverse kinematics with the passive joints, then the compiled ``stiffness`` kernel) at POSES
poses uniform in the task's cylinder (radius 0.15 m about the base's axis, z in [-0.55, -0.45] m), on 1 and 2
threads (``pkm.batch.THREADS``), against the virtual joint method written here in vectorised numpy from first
principles (:func:`numpy_vjm`), in the same run. Before any timing the two agree at CHECKED poses to TOL of K's
largest entry, and the numpy VJM agrees with its own closed form (:func:`numpy_rank_one`), which is timed too.
pkm's time is split into its inverse kinematics and its kernel. Figures are best of REPEATS after WARMUP untimed
calls (the first calls of a large batch also pay for the pages of its fresh arrays).

The global index ``stiffness_min_mean`` (the least translational stiffness's mean over the task) with its exact
design gradient against the GCI's (``gci``), both over the region ``task`` at the default design, timed twice:
with the kernels compiled (after CALLS calls, best of the last INDEX_REPEATS: pkm compiles a graph once the work the
interpreter spent on it would have paid for the compile, :mod:`pkm.compiled`, and keeps it in its cache), and on
CasADi's interpreter (a process with ``PKM_COMPILED=0``, from the second call, best of INDEX_REPEATS), which is
what a cold cache gives until then. Nothing asserts on time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

import pkm
import pkm.batch
from bench import json_main
from bench.methods import best_of
from bench.report import machine
from bench.throughput import set_threads
from pkm.batch import evaluate
from tests.oracles import delta_ik

MACHINE = Path(__file__).resolve().parent.parent / "examples" / "delta_elastic.toml"
MODE = "elbow_out"
BRANCH = 1  # tests.oracles.delta_ik's branch of elbow_out
POSES = 1_000_000
CHECKED = 5_000
TOL = 1e-9
REPEATS = 3
WARMUP = 3
CALLS = 50
INDEX_REPEATS = 10  # a global index takes milliseconds: best of more calls
THREADS = (1, 2)
BLOCK = 100_000  # poses per block of the numpy VJM: its 5x5 systems of a block take 60 MB
CYLINDER = (0.15, -0.55, -0.45)  # radius, lowest and highest z [m]
SEED = 20261203
GOAL = 10.0  # issue 40: pkm's K at least 10x the numpy VJM on 2 threads
INDEX_GOAL = 3.0  # issue 40: the stiffness index with its gradient within 3x the GCI's time
INDEX, REFERENCE = "stiffness_min_mean", "gci"

# Young's and shear moduli [Pa] of the description's materials (pkm.spec.vocabulary's table of materials)
ALUMINIUM = (70e9, 26e9)
CARBON_FIBRE = (135e9, 5e9)
ARM_ANGLES = 2 * np.pi * np.arange(3) / 3  # the legs' base joints about the base's axis


def sample_poses(count: int, seed: int = SEED) -> np.ndarray:
    """``count`` poses (count, 3) uniform in the task's cylinder (its area uniform in r^2)."""
    rng = np.random.default_rng(seed)
    radius, low, high = CYLINDER
    rho = radius * np.sqrt(rng.uniform(size=count))
    angle = rng.uniform(0, 2 * np.pi, size=count)
    return np.stack([rho * np.cos(angle), rho * np.sin(angle), rng.uniform(low, high, size=count)], axis=1)


def _cross(v: np.ndarray) -> np.ndarray:
    """[v]x (..., 3, 3) of vectors v (..., 3): [v]x w = v x w."""
    zero = np.zeros(v.shape[:-1])
    return np.stack([np.stack([zero, -v[..., 2], v[..., 1]], -1), np.stack([v[..., 2], zero, -v[..., 0]], -1),
                     np.stack([-v[..., 1], v[..., 0], zero], -1)], -2)


def _tube(d: float, t: float) -> tuple[float, float, float]:
    """A round tube's area, second moment of area and torsion constant (2 I)."""
    inner = d - 2 * t
    moment = np.pi * (d**4 - inner**4) / 64
    return np.pi * (d**2 - inner**2) / 4, moment, 2 * moment


def _cantilever(along: np.ndarray, length: float, material: tuple[float, float], tube: tuple[float, float],
                count: int = 1) -> np.ndarray:
    """The 6x6 compliance (..., 6, 6) at the free end of ``count`` equal Euler-Bernoulli beams side by side,
    clamped at their start, along the unit vectors ``along`` (..., 3), in the base's axes: (translation,
    rotation) of the end under (force, moment) there. A force F moves the end by L/(EA) along the beam and
    L^3/(3EI) across it and turns it by L^2/(2EI) along x F; a moment M turns it by L/(GJ) about the beam and
    L/(EI) across it and moves it by L^2/(2EI) M x along."""
    young, shear = material
    area, moment, torsion = _tube(*tube)
    bend = young * moment * count
    P = along[..., :, None] * along[..., None, :]
    Q = np.eye(3) - P
    S = _cross(along)
    top = np.concatenate([length / (young * area * count) * P + length**3 / (3 * bend) * Q,
                          -length**2 / (2 * bend) * S], axis=-1)
    bottom = np.concatenate([length**2 / (2 * bend) * S,
                             length / (shear * torsion * count) * P + length / bend * Q], axis=-1)
    return np.concatenate([top, bottom], axis=-2)


def _legs(x: np.ndarray, design: Mapping[str, float]) -> dict[str, np.ndarray]:
    """Each leg's geometry at the poses x (N, 3): its arm's axis a, base joint B, elbow E, platform joint c, the
    arm's direction u and the rods' n (each (N, 3, 3): pose, leg, coordinate)."""
    theta = delta_ik(x, design, BRANCH)[..., None]
    radial = np.stack([np.cos(ARM_ANGLES), np.sin(ARM_ANGLES), np.zeros(3)], axis=-1)
    axis = np.stack([-np.sin(ARM_ANGLES), np.cos(ARM_ANGLES), np.zeros(3)], axis=-1)
    # the arm turns about a = e_z x e_r, from e_r at theta = 0 towards a x e_r = -e_z
    u = np.cos(theta) * radial - np.sin(theta) * np.array([0.0, 0.0, 1.0])
    base = design["R"] * radial
    elbow = base + design["L_a"] * u
    c = x[:, None, :] + design["r"] * radial
    return {"a": np.broadcast_to(axis, u.shape), "B": np.broadcast_to(base, u.shape), "E": elbow, "c": c, "u": u,
            "n": (c - elbow) / design["L_b"]}


def _leg_compliance(legs: Mapping[str, np.ndarray], design: Mapping[str, float]) -> np.ndarray:
    """The compliance S (N, 3, 3, 3) of each leg's chain end c under a force there, the passive joints held: the
    drive's (H_a H_a^T / k_m, H_a = a x (c - B) the motion of c per unit turn of the arm), the arm's cantilever
    seen at c (dc = du + dphi x (c - E)) and the two rods' side by side (clamped at E, their end at c)."""
    a, c, elbow = legs["a"], legs["c"], legs["E"]
    H_a = np.cross(a, c - legs["B"])
    drive = H_a[..., :, None] * H_a[..., None, :] / design["k_m"]
    arm = _cantilever(legs["u"], design["L_a"], ALUMINIUM, (design["d_a"], design["t_a"]))
    motion = np.concatenate([np.broadcast_to(np.eye(3), (*arm.shape[:-2], 3, 3)), -_cross(c - elbow)], axis=-1)
    rods = _cantilever(legs["n"], design["L_b"], CARBON_FIBRE, (design["d_b"], design["t_b"]), count=2)
    return drive + motion @ arm @ np.swapaxes(motion, -1, -2) + rods[..., :3, :3]


def numpy_vjm(x: np.ndarray, design: Mapping[str, float]) -> np.ndarray:
    """K (N, 3, 3) [N/m] of the Delta at the poses x (N, 3) by the virtual joint method (Pashkevich, Klimchik and
    Chablat, MMT 44, 2009, eq. 20), in blocks of BLOCK poses: per leg the compliance S of its chain end
    (:func:`_leg_compliance`) and the motions H_p (3, 2) of c under the parallelogram's two free angles (its hinge
    along the arm's axis a at the elbow, its swing about the normal a x n of its plane), K_i the first block of
    [[S, H_p], [H_p^T, 0]]^-1 (the chain's end is c, the spherical joint leaves its rotation free) and
    K = sum_i K_i (the platform translates)."""
    out = np.empty((len(x), 3, 3))
    for start in range(0, len(x), BLOCK):
        legs = _legs(x[start:start + BLOCK], design)
        S = _leg_compliance(legs, design)
        arm = legs["c"] - legs["E"]
        H_p = np.stack([np.cross(legs["a"], arm), np.cross(np.cross(legs["a"], legs["n"]), arm)], axis=-1)
        system = np.zeros((*S.shape[:-2], 5, 5))
        system[..., :3, :3] = S
        system[..., :3, 3:] = H_p
        system[..., 3:, :3] = np.swapaxes(H_p, -1, -2)
        unit = np.zeros((5, 3))
        unit[:3] = np.eye(3)
        G = np.linalg.solve(system, np.broadcast_to(unit, (*S.shape[:-2], 5, 3)))[..., :3, :]
        out[start:start + BLOCK] = G.sum(axis=1)
    return out


def numpy_rank_one(x: np.ndarray, design: Mapping[str, float]) -> np.ndarray:
    """K (N, 3, 3) in closed form: the parallelogram's angles move c across the rods' direction n, so each leg
    resists along n alone, K_i = n n^T / (n^T S n), the same as :func:`numpy_vjm`'s first block."""
    out = np.empty((len(x), 3, 3))
    for start in range(0, len(x), BLOCK):
        legs = _legs(x[start:start + BLOCK], design)
        n = legs["n"]
        s = np.einsum("nki,nkij,nkj->nk", n, _leg_compliance(legs, design), n)
        out[start:start + BLOCK] = np.einsum("nki,nkj->nij", n / s[..., None], n)
    return out


def discrepancy(ours: np.ndarray, reference: np.ndarray) -> float:
    """Largest over the poses of max |ours - reference| / max |reference| over the pose's entries."""
    scale = np.abs(reference).reshape(len(reference), -1).max(axis=1)
    return float(np.max(np.abs(ours - reference).reshape(len(ours), -1).max(axis=1) / scale))


def _best_of(fn: Callable[[], Any], warmup: int = WARMUP, repeats: int = REPEATS) -> float:
    """The least wall time [s] of ``repeats`` calls of ``fn`` after ``warmup`` untimed ones."""
    for _ in range(warmup):
        fn()
    return best_of(fn, repeats)


def check(m: pkm.Mechanism, x: np.ndarray) -> dict[str, float]:
    """pkm's K against the numpy VJM and the VJM against its closed form at the poses x; AssertionError beyond
    TOL or where any K is not finite."""
    design = m.design()
    ours, reference, closed = m.stiffness(x, design, mode=MODE), numpy_vjm(x, dict(design)), \
        numpy_rank_one(x, dict(design))
    if not (np.isfinite(ours).all() and np.isfinite(reference).all()):
        raise AssertionError("a pose of the task is out of reach of pkm's or numpy's inverse kinematics")
    errors = {"pkm_vs_numpy": discrepancy(ours, reference), "closed_form_vs_numpy": discrepancy(closed, reference)}
    for what, err in errors.items():
        if not err <= TOL:
            raise AssertionError(f"{what}: K differs by {err:.3g} of its largest entry > {TOL:g}")
    return errors


def _poses(m: pkm.Mechanism, x: np.ndarray, log: Callable[[str], None]) -> dict[str, Any]:
    design = m.design()
    d = dict(design)
    fn, vector = m.functions["stiffness"], m.design_vector(design)
    numpy_s = _best_of(lambda: numpy_vjm(x, d))
    closed_s = _best_of(lambda: numpy_rank_one(x, d))
    log(f"numpy VJM {len(x) / numpy_s:,.0f} poses/s, its closed form {len(x) / closed_s:,.0f}")
    rows, default = [], pkm.batch.THREADS
    try:
        for threads in THREADS:
            set_threads(threads)
            seconds = _best_of(lambda: m.stiffness(x, design, mode=MODE))
            q = m.inverse_kinematics(x, design, mode=MODE, passive=True)
            ik_s = _best_of(lambda: m.inverse_kinematics(x, design, mode=MODE, passive=True))
            kernel_s = _best_of(lambda: evaluate(fn, q, x, vector))  # noqa: B023
            rows.append({"threads": threads, "seconds": seconds, "poses_per_s": len(x) / seconds,
                         "ratio_vs_numpy": numpy_s / seconds, "inverse_kinematics_seconds": ik_s,
                         "kernel_seconds": kernel_s})
            log(f"pkm on {threads} thread(s): {len(x) / seconds:,.0f} poses/s ({numpy_s / seconds:.2f}x numpy; "
                f"inverse kinematics {ik_s:.3f} s, kernel {kernel_s:.3f} s)")
    finally:
        set_threads(default)
    return {"numpy_seconds": numpy_s, "numpy_poses_per_s": len(x) / numpy_s, "closed_form_seconds": closed_s,
            "closed_form_poses_per_s": len(x) / closed_s, "pkm": rows}


def index_times(calls: int) -> dict[str, Any]:
    """Each global index with its gradient over the task: the best of the last INDEX_REPEATS of ``calls`` calls [s],
    its value and its quadrature's points."""
    m = pkm.load(str(MACHINE))
    design = m.design()
    out = {}
    for name in (INDEX, REFERENCE):
        def call(name: str = name) -> Any:
            return m.global_index(name, design, region="task", mode=MODE, gradient=True)

        value, _ = call()
        seconds = _best_of(call, warmup=calls - 1 - INDEX_REPEATS, repeats=INDEX_REPEATS)
        out[name] = {"seconds": seconds, "value": float(value), "points": int(value.points)}
    return out


def _interpreted_index_times() -> dict[str, Any]:
    """:func:`index_times` from the second call in a process on CasADi's interpreter (``PKM_COMPILED=0``)."""
    code = f"import json; from bench.stiffness import index_times; print(json.dumps(index_times({1 + INDEX_REPEATS})))"
    done = subprocess.run([sys.executable, "-c", code], env={**os.environ, "PKM_COMPILED": "0"}, check=True,
                          capture_output=True, text=True, cwd=Path(__file__).resolve().parent.parent)
    return json.loads(done.stdout)


def _global(log: Callable[[str], None]) -> dict[str, Any]:
    out = {}
    for path, times in (("compiled", index_times(CALLS)), ("interpreter", _interpreted_index_times())):
        times["ratio"] = times[INDEX]["seconds"] / times[REFERENCE]["seconds"]
        out[path] = times
        log(f"{path}: {INDEX} {1e3 * times[INDEX]['seconds']:.1f} ms, {REFERENCE} "
            f"{1e3 * times[REFERENCE]['seconds']:.1f} ms with their gradients ({times['ratio']:.2f}x)")
    return out


def run(*, log: Callable[[str], None] = print, poses: int = POSES, checked: int = CHECKED) -> dict[str, Any]:
    m = pkm.load(str(MACHINE))
    x = sample_poses(poses)
    errors = check(m, x[:checked])
    log(f"pkm and numpy agree at {checked} poses to {errors['pkm_vs_numpy']:.2g}")
    load = os.getloadavg()
    timed = _poses(m, x, log)
    return {"command": "python -m bench.stiffness --json docs/benchmarks/stiffness.json", "machine": machine(),
            "load_average_before": list(load), "load_average_after": list(os.getloadavg()), "poses": poses,
            "checked": checked, "tolerance": TOL, "repeats": REPEATS, "warmup": WARMUP,
            "index_calls": CALLS, "index_repeats": INDEX_REPEATS, "seed": SEED, **errors, **timed,
            "global": _global(log)}


def _verdict(compiled: bool, interpreter: bool) -> str:
    if compiled and interpreter:
        return "met on both"
    if compiled:
        return "met with compiled kernels, not on the interpreter"
    return "met on the interpreter only" if interpreter else "not met"


def markdown(data: Mapping[str, Any]) -> str:
    """The run's table of poses per second, its split of pkm's time and its global indices' times."""
    by_threads = {row["threads"]: row for row in data["pkm"]}
    two = by_threads[max(THREADS)]
    speed_met = two["ratio_vs_numpy"] >= GOAL
    compiled, interpreter = data["global"]["compiled"], data["global"]["interpreter"]
    lines = [
        f"Command: `{data['command']}` ({data['machine']['date']}, {data['machine']['cpu']}, "
        f"{data['machine']['cores']} cores; load average (1 min) {data['load_average_before'][0]:.2f} before timing, "
        f"{data['load_average_after'][0]:.2f} after). examples/delta_elastic.toml at its default design, {MODE}, at "
        f"{data['poses']:,} poses uniform in its task's cylinder (radius 0.15 m, z in [-0.55, -0.45] m); best of "
        f"{data['repeats']} after {data['warmup']} untimed calls. The numpy VJM (bench/stiffness.py, written from "
        "the beams, the drive and the parallelogram's free angles, not from pkm's code) and pkm's K agree at "
        f"{data['checked']:,} of the poses to {data['pkm_vs_numpy']:.1e} of K's largest entry, its closed form to "
        f"{data['closed_form_vs_numpy']:.1e}, checked before timing.", "",
        "| method | poses/s | vs the numpy VJM | inverse kinematics [s] | kernel [s] |", "|---|---:|---:|---:|---:|",
        f"| numpy VJM, a 5x5 augmented system per leg ([[S, H_p], [H_p^T, 0]]) | {data['numpy_poses_per_s']:,.0f} "
        "| 1.00x | | |",
        f"| numpy closed form, K_i = n n^T / (n^T S n) | {data['closed_form_poses_per_s']:,.0f} | "
        f"{data['numpy_seconds'] / data['closed_form_seconds']:.2f}x | | |",
    ]
    for threads, row in sorted(by_threads.items()):
        lines.append(f"| pkm `m.stiffness`, {threads} thread{'s' if threads > 1 else ''} | {row['poses_per_s']:,.0f} "
                     f"| {row['ratio_vs_numpy']:.2f}x | {row['inverse_kinematics_seconds']:.3f} | "
                     f"{row['kernel_seconds']:.3f} |")
    lines += [
        "",
        "The last two columns time pkm's two steps alone: `m.inverse_kinematics(..., passive=True)` and the "
        f"compiled `stiffness` kernel through `pkm.batch.evaluate`; on {max(THREADS)} threads the kernel takes "
        f"{two['kernel_seconds'] / (two['kernel_seconds'] + two['inverse_kinematics_seconds']):.0%} of their sum.", "",
        f"Issue 40's goal of {GOAL:g}x the numpy VJM on {max(THREADS)} threads is "
        f"{'met' if speed_met else 'not met'} ({two['ratio_vs_numpy']:.2f}x; "
        f"{data['closed_form_seconds'] / two['seconds']:.2f}x the closed form; 2 threads ran at "
        f"{by_threads[min(THREADS)]['seconds'] / two['seconds']:.2f}x 1 thread's rate, with the load average above "
        "on the 2 cores).", "",
        "| global index over the task, with its design gradient | points | compiled kernels [ms] | "
        "interpreter [ms] |", "|---|---:|---:|---:|",
        *(f"| `{name}` | {compiled[name]['points']:,} | {1e3 * compiled[name]['seconds']:.1f} | "
          f"{1e3 * interpreter[name]['seconds']:.1f} |" for name in (INDEX, REFERENCE)),
        "",
        f"Compiled kernels: after {data['index_calls']} calls of each, best of the last {data['index_repeats']} "
        "(pkm compiles a graph once the interpreter's work on it would have paid for the compile, and keeps the "
        "kernel in its cache). Interpreter: a process with `PKM_COMPILED=0`, from the second call, best of "
        f"{data['index_repeats']}: what a cold "
        f"cache gives until the compile. `{INDEX}` takes {compiled['ratio']:.2f}x the GCI's time with compiled "
        f"kernels and {interpreter['ratio']:.2f}x on the interpreter; issue 40's goal of at most {INDEX_GOAL:g}x is "
        f"{_verdict(compiled['ratio'] <= INDEX_GOAL, interpreter['ratio'] <= INDEX_GOAL)}.",
    ]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    return json_main("python -m bench.stiffness", __doc__, run, markdown, argv)


if __name__ == "__main__":
    raise SystemExit(main())
