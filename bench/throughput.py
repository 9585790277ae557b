"""Throughput of IK + J + 1/kappa_f on the five-bar: pkm against a hand-written numpy implementation.

Poses: uniform in the workspace box of the default design (fixed seed), kept where the working mode
reaches them. Every path is checked against numpy to 1e-9 before timing; figures are best of
``repeats``; nothing asserts on time. The experiments (not part of pkm) evaluate the same CasADi graph
in one pass: on CasADi's VM, JIT-compiled per pose, and as a whole mapped chunk compiled to C; and pkm's
local-index pipeline as it is built without the five-bar's ``first_order_from_pose`` (through the joint
angles: acos and atan2 in the inverse kinematics, cos and sin in ``first_order``), compiled at first use
like any graph pkm evaluates, so that the gain of the derivation without
trigonometric calls is measured in the same run.
"""

from __future__ import annotations

import copy
import os
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable
from typing import Any

import casadi as ca
import numpy as np

import pkm
import pkm.batch
import pkm.compiled
from pkm.indices import local_function
from pkm.kinematics import FunctionTable
from pkm.regions.pipeline import FROM_POSE, index_pipeline
from pkm.registry import local_index

DESIGN = {"r1": 1.2, "r2": 1.0, "r3": 0.8}
MODE = "out_out"
INDEX = "inverse_condition_f"
SEED = 20261121
TOL = 1e-9
SERIAL_MARGIN = 1e-3
CC = shutil.which("gcc") or shutil.which("cc")


def sample_poses(m: pkm.Mechanism, n: int, seed: int = SEED) -> np.ndarray:
    """n poses (n, 2) uniform in the workspace box, kept where the working mode reaches them."""
    rng = np.random.default_rng(seed)
    box = m.workspace_box(m.design(DESIGN).vector())
    kept, total = [], 0
    while total < n:
        X = rng.uniform(box[:, 0], box[:, 1], size=(max(n - total, 1024) * 3 // 2, 2))
        X = X[m.reachable(X, DESIGN, mode=MODE)]
        kept.append(X)
        total += len(X)
    return np.ascontiguousarray(np.concatenate(kept)[:n])


def numpy_index(X: np.ndarray, design: dict[str, float], signs: tuple[float, ...]):
    """IK, J (q_a_dot = J x_dot) and 1/kappa_f of the 5R in plain vectorised numpy: (J (n,2,2), (n,))."""
    r1, r2, r3 = design["r1"], design["r2"], design["r3"]
    x, y = X[:, 0], X[:, 1]
    rows = []
    for ox, sigma in ((-r3, signs[0]), (r3, signs[1])):
        dx = x - ox
        rho2 = dx * dx + y * y
        theta = np.arctan2(y, dx) + sigma * np.arccos((r1 * r1 + rho2 - r2 * r2) / (2 * r1 * np.sqrt(rho2)))
        phi = np.arctan2(y - r1 * np.sin(theta), dx - r1 * np.cos(theta))
        scale = 1.0 / (r1 * np.sin(phi - theta))
        rows.append((np.cos(phi) * scale, np.sin(phi) * scale))
    (a, b), (c, e) = rows
    J = np.stack((a, b, c, e), axis=1).reshape(-1, 2, 2)
    return J, 2 * np.abs(a * e - b * c) / (a * a + b * b + c * c + e * e)


def conditioned(J_ref: np.ndarray) -> np.ndarray:
    """Poses whose elbows are both at least SERIAL_MARGIN (|sin| of the elbow angle) from straight.

    A row of J is e(phi)^T / (r1 sin(phi - theta)), so its norm is 1 / (r1 |sin(phi - theta)|).
    """
    return np.max(np.linalg.norm(J_ref, axis=2), axis=1) * DESIGN["r1"] * SERIAL_MARGIN < 1


def discrepancy(J: np.ndarray, value: np.ndarray, ref: tuple[np.ndarray, np.ndarray], what: str) -> float:
    """Largest difference from the numpy reference; raises above TOL.

    1/kappa_f is compared (absolute) at every pose, J (relative to max(1, |J|)) where :func:`conditioned`:
    nearer a serial singularity the IK itself is ill-conditioned (acos near +-1) and both implementations
    lose digits alike (at the worst pose of the default sample both are ~3e-8 from a 40-digit reference).
    """
    J_ref, value_ref = ref
    ok = conditioned(J_ref)
    err = max(
        float(np.max(np.abs(J[ok] - J_ref[ok]) / np.maximum(1.0, np.abs(J_ref[ok])))),
        float(np.max(np.abs(value - value_ref))),
    )
    if not err <= TOL:
        raise AssertionError(f"{what} differs from the numpy reference by {err:.3g} > {TOL:g}")
    return err


def set_threads(n: int) -> None:
    """Set ``pkm.batch.THREADS`` and drop the mapped functions cached with the old value."""
    pkm.batch.THREADS = n
    getattr(getattr(pkm.batch, "_mapped", None), "cache_clear", lambda: None)()


def fused_graph(m: pkm.Mechanism, signs: tuple[float, ...]) -> tuple[list[ca.SX], list[ca.SX]]:
    """Inputs and outputs (J, 1/kappa_f) of IK -> first order -> index composed into one SX graph."""
    x = ca.SX.sym("x", m.n_out)
    s = ca.SX.sym("mode", len(signs))
    d = ca.SX.sym("design", len(m.parameters))
    q = m.functions["inverse_kinematics"](x, s, d)[0]
    J, J_f = m.functions["first_order"](q, x, d)[:2]
    return [x, s, d], [J, local_function(local_index(INDEX), m.n_act)(J, J_f)]


def compile_mapped(fn: ca.Function, chunk: int, threads: int, workdir: str) -> ca.Function:
    """``fn.map(chunk)`` emitted as C by CasADi, built with gcc -O3 and loaded with casadi.external."""
    mapped = fn.map(chunk, "thread", threads) if threads > 1 else fn.map(chunk, "serial")
    gen = ca.CodeGenerator(f"{mapped.name()}.c", {"with_header": False})
    gen.add(mapped)
    gen.generate(workdir + "/")
    lib = f"{workdir}/{mapped.name()}.so"
    cmd = [CC, "-O3", "-shared", "-fPIC", "-pthread", f"{workdir}/{mapped.name()}.c", "-o", lib, "-lm"]
    subprocess.run(cmd, check=True, capture_output=True)
    return ca.external(mapped.name(), lib)


def run_compiled(exts: dict[int, ca.Function], X: np.ndarray, shared: list[np.ndarray]):
    """Evaluate compiled mapped functions (by chunk size) over X in chunks, as pkm.batch does."""
    n, chunk = len(X), max(exts)
    outs = [np.empty((n, exts[chunk].numel_out(j) // chunk)) for j in range(exts[chunk].n_out())]
    for start in range(0, n, chunk):
        size = min(chunk, n - start)
        buf, run = exts[size].buffer()
        consts = [np.ascontiguousarray(np.broadcast_to(a, (size, a.size))) for a in shared]
        for i, a in enumerate([X[start : start + size], *consts]):
            buf.set_arg(i, memoryview(a))
        for j, o in enumerate(outs):
            buf.set_res(j, memoryview(o[start : start + size]))
        run()
    return outs[0].reshape(n, 2, 2).transpose(0, 2, 1), outs[1][:, 0]


def through_angles(m: pkm.Mechanism) -> ca.Function:
    """The local index's pipeline ``(x, mode, design) -> (valid, value)`` built from the mechanism's
    functions without ``first_order_from_pose``: the inverse kinematics' joint angles into
    ``first_order``, as pkm composed them before the derivation from the pose."""
    angles = copy.copy(m)
    angles.functions = FunctionTable({k: f for k, f in m.functions.items() if k != FROM_POSE},
                                     f"the {m.name} without {FROM_POSE}")
    return index_pipeline(angles, (m.local_spec(INDEX),))


def angle_route(m: pkm.Mechanism, X: np.ndarray, ref, timer: Timer) -> list[str]:
    """The rows of :func:`through_angles`, compiled at first use like any graph (module docstring)."""
    fn = through_angles(m)
    status = pkm.compiled.status()
    if status["path"] != "compiled":
        return [f"the local index through the joint angles was not timed: {status['reason']}"]
    start = time.perf_counter()
    pkm.compiled.build([(fn, False)])
    notes = [f"the local index through the joint angles compiled in {time.perf_counter() - start:.2f} s"]
    sig, d = np.asarray(m.working_mode(MODE).signs, dtype=float), m.design(DESIGN).vector()

    def value() -> np.ndarray:
        return pkm.batch.evaluate(fn, X, sig, d)[1][:, 0, 0]

    err = float(np.max(np.abs(value() - ref[1])))
    if not err <= TOL:
        raise AssertionError(f"the local index through the joint angles differs from numpy by {err:.3g} > {TOL:g}")
    for t in sorted({pkm.batch.THREADS, 1}, reverse=True):
        timer.add("experiment: pkm local_index through the joint angles (IK -> first_order -> 1/kappa_f)", t, value,
                  err, "the pipeline without first_order_from_pose, same emitter and flags", batch=t)
    return notes


class Timer:
    """Best-of-``repeats`` timings over ``n`` poses, interleaved: each round runs every task once (in
    alternating order), so load from other processes falls on all alike. Tasks through pkm.batch name
    the ``pkm.batch.THREADS`` they need; after a switch (which drops the cached mapped functions) their
    first call rebuilds the maps and is not timed."""

    def __init__(self, n: int, repeats: int, log: Callable[[str], None]) -> None:
        self.n, self.repeats, self.log, self.tasks = n, repeats, log, []

    def add(self, name: str, threads: int, fn: Callable[[], Any], err: float, note: str = "", *, batch=None):
        row = {"name": name, "threads": threads, "max_discrepancy": err, "note": note, "seconds": np.inf}
        self.tasks.append((row, fn, batch))

    def run(self) -> list[dict[str, Any]]:
        order = sorted(range(len(self.tasks)), key=lambda k: -(self.tasks[k][2] or 0))
        current, warm, default = None, set(), pkm.batch.THREADS
        try:
            for i in range(self.repeats):
                for k in order if i % 2 == 0 else order[::-1]:
                    row, fn, batch = self.tasks[k]
                    if batch is not None and batch != current:
                        current, warm = batch, set()
                        set_threads(batch)
                    if batch is not None and k not in warm:
                        fn()
                        warm.add(k)
                    start = time.perf_counter()
                    fn()
                    row["seconds"] = min(row["seconds"], time.perf_counter() - start)
        finally:
            set_threads(default)
        rows = [row for row, _, _ in self.tasks]
        for row in rows:
            row["poses_per_s"] = self.n / row["seconds"]
            row["ratio_vs_numpy"] = row["poses_per_s"] / rows[0]["poses_per_s"]
            self.log(f"  {row['name']} ({row['threads']} thread(s)): {row['poses_per_s']:.3g} poses/s")
        return rows


def experiments(m: pkm.Mechanism, X: np.ndarray, ref, timer: Timer, tmp: str | None) -> list[str]:
    """The same graph evaluated in one pass: CasADi VM, per-pose JIT, and the mapped chunk in C."""
    signs = m.working_mode(MODE).signs
    ins, outs = fused_graph(m, signs)
    d, sig, threads = m.design(DESIGN).vector(), np.asarray(signs, dtype=float), pkm.batch.THREADS

    def batch(fn: ca.Function):
        J, v = pkm.batch.evaluate(fn, X, sig, d)
        return J, v[:, 0, 0]

    vm = ca.Function("fused", ins, outs)
    candidates, notes = [("CasADi VM", vm, "one pass")], []
    if CC is None or tmp is None:
        notes = ["no C compiler found: the compiled experiments were skipped"] if tmp else []
    else:
        start = time.perf_counter()
        jit_options = {"flags": ["-O3"], "directory": tmp + "/", "cleanup": False}
        options = {"jit": True, "compiler": "shell", "jit_options": jit_options, "jit_cleanup": False}
        candidates.append(("per-pose JIT, CasADi map", ca.Function("fused_jit", ins, outs, options), "{'jit': True}"))
        notes.append(f"per-pose JIT (gcc -O3) built in {time.perf_counter() - start:.2f} s")
    for label, fn, note in candidates:
        err = discrepancy(*batch(fn), ref, f"fused graph, {label}")
        for t in sorted({threads, 1}, reverse=True):
            timer.add(f"experiment: fused graph, {label}", t, lambda f=fn: batch(f), err, note, batch=t)
    if len(candidates) == 1:
        return notes
    sizes = {min(pkm.batch.CHUNK, len(X)), len(X) % pkm.batch.CHUNK} - {0}
    for t in sorted({1, threads}):
        start = time.perf_counter()
        ext = {size: compile_mapped(vm, size, t, tmp) for size in sizes}
        notes.append(f"mapped chunk in C ({t} thread(s)) generated and built in {time.perf_counter() - start:.2f} s")
        err = discrepancy(*run_compiled(ext, X, [sig, d]), ref, "compiled mapped graph")
        name = "experiment: fused graph, mapped chunk compiled to C"
        timer.add(name, t, lambda e=ext: run_compiled(e, X, [sig, d]), err, "CasADi codegen + gcc -O3")
    return notes


def run(n: int = 1_000_000, repeats: int = 3, *, compiled: bool = True, log=print) -> dict[str, Any]:
    """All throughput figures: rows with poses/s and the ratio to numpy, plus notes."""
    m = pkm.load("five_bar")
    signs = m.working_mode(MODE).signs
    start = time.perf_counter()
    X = sample_poses(m, n)
    log(f"throughput: {n} reachable poses sampled in {time.perf_counter() - start:.2f} s")
    ref = numpy_index(X, DESIGN, signs)
    J, value = m.jacobian(X, DESIGN, mode=MODE), m.local_index(INDEX, X, DESIGN, mode=MODE)
    err = discrepancy(J, value, ref, "pkm")
    near = int(np.count_nonzero(~conditioned(ref[0])))
    log(f"  pkm agrees with numpy to {err:.2g}")
    default = pkm.batch.THREADS
    timer = Timer(n, repeats, log)
    timer.add("numpy, hand-written (IK + J + 1/kappa_f)", 1, lambda: numpy_index(X, DESIGN, signs), 0.0, "reference")
    for t in sorted({default, 1}, reverse=True):
        timer.add(
            "pkm local_index (IK + J + 1/kappa_f)", t, lambda: m.local_index(INDEX, X, DESIGN, mode=MODE), err, batch=t
        )
        timer.add("pkm jacobian (IK + J)", t, lambda: m.jacobian(X, DESIGN, mode=MODE), err, batch=t)
        timer.add(
            "pkm inverse_kinematics (IK only)", t, lambda: m.inverse_kinematics(X, DESIGN, mode=MODE), err, batch=t
        )
    with tempfile.TemporaryDirectory(prefix="pkm-bench-") as tmp:
        notes = experiments(m, X, ref, timer, tmp if compiled else None)
        if compiled:
            notes += angle_route(m, X, ref, timer)
        load = os.getloadavg()
        rows = timer.run()
    notes.append(f"J compared at {n - near} poses; {near} close to a serial singularity: 1/kappa_f only")
    notes.append(f"load average (1 min) {load[0]:.2f} before timing, {os.getloadavg()[0]:.2f} after")
    return {
        "poses": n,
        "repeats": repeats,
        "seed": SEED,
        "design": DESIGN,
        "mode": MODE,
        "default_threads": default,
        "rows": rows,
        "notes": notes,
    }
