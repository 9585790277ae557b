"""Throughput of the five-bar's dynamic inertia pipeline: pkm against a hand-written numpy implementation.

Per pose: inverse kinematics -> M_t = Psi^T M Psi (actuated space) and M_w = J^T M_t J (task space)
-> local dynamic dexterity 1/kappa_2(M_w) = lambda_min / lambda_max (Lara-Molina 2016 eqs. 19-29, 35).
The poses are bench/throughput.py's (same sampler, seed and geometry); the design is pkm's default.
Every path is checked against numpy to 1e-9 before timing; figures are best of ``repeats``; nothing
asserts on time. The experiments (not part of pkm) evaluate the same generated graphs without the
elastodynamic output S_e, in three passes and fused into one.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

import pkm
import pkm.batch
import pkm.registry
from bench.throughput import DESIGN, MODE, SEED, SERIAL_MARGIN, Timer, sample_poses
from pkm.indices.local import extreme_singular_values

INDEX = "dynamic_dexterity"
TOL = 1e-9
PARALLEL_MARGIN = 1e-3


def numpy_pipeline(
    X: np.ndarray, design: Mapping[str, float], signs: tuple[float, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """IK, M_t, M_w and 1/kappa_2(M_w) of the 5R in plain vectorised numpy: ((n,2,2), (n,2,2), (n,)).

    Lara-Molina 2016: per chain alpha = I1 + m1 d1^2 + m2 r1^2, beta = I2 + m2 d2^2, gamma = m2 r1 d2
    (eq. 19); M in (theta1, theta2, phi1, phi2) couples theta_i and phi_i by gamma cos(theta_i - phi_i)
    (eq. 21); Psi = [I; P] with P = dphi/dtheta = -H_phi^-1 H_theta from the closure
    O1 + r1 e(theta1) + r2 e(phi1) = O2 + r1 e(theta2) + r2 e(phi2) (eq. 25); M_t = Psi^T M Psi (eq. 29);
    J = A^-1 B (eqs. 6-9, q_a_dot = J x_dot); M_w = J^T M_t J; its eigenvalues in closed form (eq. 35).
    """
    r1, r2, r3 = design["r1"], design["r2"], design["r3"]
    alpha = design["m1"] * r1 * r1 * (design["g1"] + design["c1"] ** 2) + design["m2"] * r1 * r1
    beta = design["m2"] * r2 * r2 * (design["g2"] + design["c2"] ** 2)
    gamma = design["m2"] * r1 * design["c2"] * r2
    x, y = X[:, 0], X[:, 1]
    chains = []
    for ox, sigma in ((-r3, signs[0]), (r3, signs[1])):
        dx = x - ox
        rho2 = dx * dx + y * y
        c = np.clip((r1 * r1 + rho2 - r2 * r2) / (2 * r1 * np.sqrt(rho2)), -1.0, 1.0)
        theta = np.arctan2(y, dx) + sigma * np.arccos(c)
        ct, st = np.cos(theta), np.sin(theta)
        bx, by = dx - r1 * ct, y - r1 * st  # row of B (eq. 8): r2 e(phi_i)
        phi = np.arctan2(by, bx)
        scale = 1.0 / (r1 * (y * ct - dx * st))  # 1 / A_ii (eq. 8)
        chains.append((ct, st, np.cos(phi), np.sin(phi), bx * scale, by * scale))
    (ct1, st1, cp1, sp1, a, b), (ct2, st2, cp2, sp2, c, e) = chains
    # P = -r1 / (r2 sin(phi1 - phi2)) [[sin(t1 - p2), sin(p2 - t2)], [sin(t1 - p1), sin(p1 - t2)]]
    k = -r1 / (r2 * (sp1 * cp2 - cp1 * sp2))
    p00, p01 = k * (st1 * cp2 - ct1 * sp2), k * (sp2 * ct2 - cp2 * st2)
    p10, p11 = k * (st1 * cp1 - ct1 * sp1), k * (sp1 * ct2 - cp1 * st2)
    g1, g2 = gamma * (ct1 * cp1 + st1 * sp1), gamma * (ct2 * cp2 + st2 * sp2)
    t00 = alpha + 2 * g1 * p00 + beta * (p00 * p00 + p10 * p10)
    t01 = g1 * p01 + g2 * p10 + beta * (p00 * p01 + p10 * p11)
    t11 = alpha + 2 * g2 * p11 + beta * (p01 * p01 + p11 * p11)
    u00, u01 = t00 * a + t01 * c, t00 * b + t01 * e  # M_t J, J = [[a, b], [c, e]]
    u10, u11 = t01 * a + t11 * c, t01 * b + t11 * e
    w00, w01, w11 = a * u00 + c * u10, a * u01 + c * u11, b * u01 + e * u11
    # lambda_max = (tr + disc) / 2 and lambda_min = det / lambda_max, so the ratio is det / lambda_max^2
    tr_disc = w00 + w11 + np.sqrt((w00 - w11) ** 2 + 4 * w01 * w01)
    dexterity = 4 * (w00 * w11 - w01 * w01) / (tr_disc * tr_disc)
    M_t = np.stack((t00, t01, t01, t11), axis=1).reshape(-1, 2, 2)
    M_w = np.stack((w00, w01, w01, w11), axis=1).reshape(-1, 2, 2)
    return M_t, M_w, dexterity


def dexterity_function() -> ca.Function:
    """``M_w -> 1/kappa_2(M_w)`` built as pkm.indices.local builds its 2x2 indices (closed-form singular values)."""
    M_w = ca.SX.sym("M_w", 2, 2)
    smax, smin = extreme_singular_values(M_w)
    return ca.Function(INDEX, [M_w], [smin / smax], ["M_w"], [INDEX])


def without_elastodynamics(inertia: ca.Function) -> ca.Function:
    """The generated ``inertia`` with outputs M_t and M_w only: CasADi drops the graph of S_e."""
    args = [ca.SX.sym(inertia.name_in(i), inertia.sparsity_in(i)) for i in range(inertia.n_in())]
    M_t, M_w, _ = inertia(*args)
    return ca.Function("inertia_rigid", args, [M_t, M_w], inertia.name_in(), ["M_t", "M_w"])


@dataclass(frozen=True)
class Pipeline:
    """IK -> inertia -> 1/kappa_2(M_w), one ``pkm.batch.evaluate`` per step as pkm's runtime does it."""

    inverse_kinematics: ca.Function
    inertia: ca.Function
    index: ca.Function
    signs: np.ndarray
    design: np.ndarray

    def joints(self, X: np.ndarray) -> np.ndarray:
        return pkm.batch.evaluate(self.inverse_kinematics, X, self.signs, self.design)[0][:, :, 0]

    def inertias(self, q: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        M_t, M_w = pkm.batch.evaluate(self.inertia, q, X, self.design)[:2]
        return M_t, M_w

    def dexterity(self, M_w: np.ndarray) -> np.ndarray:
        flat = M_w.transpose(0, 2, 1).reshape(len(M_w), 4)  # column-major, as pkm.indices passes matrices
        return pkm.batch.evaluate(self.index, flat)[0][:, 0, 0]

    def __call__(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        M_t, M_w = self.inertias(self.joints(X), X)
        return M_t, M_w, self.dexterity(M_w)


def fused_function(pipeline: Pipeline) -> ca.Function:
    """The experiment's one pass: IK -> (M_t, M_w) -> 1/kappa_2 composed into a single SX graph."""
    x = ca.SX.sym("x", 2)
    mode = ca.SX.sym("mode", len(pipeline.signs))
    d = ca.SX.sym("design", len(pipeline.design))
    q = pipeline.inverse_kinematics(x, mode, d)[0]
    M_t, M_w = without_elastodynamics(pipeline.inertia)(q, x, d)
    return ca.Function("dynamics_fused", [x, mode, d], [M_t, M_w, pipeline.index(M_w)])


def well_conditioned(q: np.ndarray) -> np.ndarray:
    """Poses at least SERIAL_MARGIN from a serial and PARALLEL_MARGIN from a parallel singularity.

    Serial: |sin(phi_i - theta_i)| (elbow i straight), where the IK's acos loses half the digits.
    Parallel: |sin(phi1 - phi2)| (distal links aligned), where Psi grows as 1 / sin(phi1 - phi2) and
    M_w = J^T M_t J is a cancellation of terms of that size squared.
    """
    theta, phi = q[:, :2], q[:, 2:]
    serial = np.min(np.abs(np.sin(phi - theta)), axis=1)
    return (serial >= SERIAL_MARGIN) & (np.abs(np.sin(phi[:, 0] - phi[:, 1])) >= PARALLEL_MARGIN)


def discrepancy(result: tuple[np.ndarray, ...], ref: tuple[np.ndarray, ...], ok: np.ndarray, what: str) -> float:
    """Largest relative difference from the numpy reference at the poses ``ok``; raises above TOL.

    M_t and M_w are compared relative to their largest entry at each pose, 1/kappa_2 relative to itself;
    ``result`` may hold the dexterity alone.
    """
    errs = [float(np.max(np.abs(result[-1][ok] - ref[2][ok]) / ref[2][ok]))]
    for a, b in zip(result[:-1], ref[:2], strict=False):
        errs.append(float(np.max(np.max(np.abs(a[ok] - b[ok]), axis=(1, 2)) / np.max(np.abs(b[ok]), axis=(1, 2)))))
    if not max(errs) <= TOL:
        raise AssertionError(f"{what} differs from the numpy reference by {max(errs):.3g} > {TOL:g}")
    return max(errs)


def run(n: int = 1_000_000, repeats: int = 3, *, log: Callable[[str], None] = print) -> dict[str, Any]:
    """All dynamics throughput figures: rows with poses/s and the ratio to numpy, plus notes."""
    m = pkm.load("five_bar")
    design = m.design(None)
    if any(design[k] != v for k, v in DESIGN.items()):
        raise ValueError(f"the poses are sampled for {DESIGN}; pkm's default design is now {design}")
    signs = m.working_mode(MODE).signs
    pipeline = Pipeline(
        m.functions["inverse_kinematics"],
        m.functions["inertia"],
        dexterity_function(),
        np.asarray(signs, dtype=float),
        design.vector(),
    )
    start = time.perf_counter()
    X = sample_poses(m, n)
    log(f"dynamics: {n} reachable poses sampled in {time.perf_counter() - start:.2f} s")
    ref = numpy_pipeline(X, design, signs)
    q = pipeline.joints(X)
    ok = well_conditioned(q)
    err = discrepancy(pipeline(X), ref, ok, "pkm")
    log(f"  pkm agrees with numpy to {err:.2g} at {int(ok.sum())} well-conditioned poses")
    M_w = ref[1]

    rigid = replace(pipeline, inertia=without_elastodynamics(pipeline.inertia))
    fused = fused_function(pipeline)

    def run_fused() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        M_t, M_w, value = pkm.batch.evaluate(fused, X, pipeline.signs, pipeline.design)
        return M_t, M_w, value[:, 0, 0]

    err_rigid = discrepancy(rigid(X), ref, ok, "inertia without S_e")
    err_fused = discrepancy(run_fused(), ref, ok, "fused graph")
    default = pkm.batch.THREADS
    timer = Timer(n, repeats, log)
    timer.add("numpy, hand-written (IK + M_t + M_w + 1/kappa_2)", 1, lambda: numpy_pipeline(X, design, signs), 0.0)
    public = INDEX in {i.name for i in pkm.registry.local_indices()}
    if public:
        err_public = discrepancy((m.local_index(INDEX, X, design, mode=MODE),), ref, ok, "local_index")
    for t in sorted({default, 1}, reverse=True):
        timer.add("pkm IK -> inertia -> 1/kappa_2 (pkm.batch.evaluate)", t, lambda: pipeline(X), err, batch=t)
        if public and t == default:
            timer.add(
                f'pkm local_index("{INDEX}") (IK, first_order, inertia, index)',
                t,
                lambda: m.local_index(INDEX, X, design, mode=MODE),
                err_public,
                batch=t,
            )
        timer.add("experiment: inertia without S_e, 3 passes", t, lambda: rigid(X), err_rigid, batch=t)
        timer.add("experiment: inertia without S_e, fused into 1 pass", t, run_fused, err_fused, batch=t)
    timer.add("pkm step: inverse_kinematics", 1, lambda: pipeline.joints(X), err, batch=1)
    timer.add("pkm step: inertia (M_t, M_w, S_e)", 1, lambda: pipeline.inertias(q, X), err, batch=1)
    timer.add("pkm step: 1/kappa_2(M_w)", 1, lambda: pipeline.dexterity(M_w), err, batch=1)
    load = os.getloadavg()
    rows = timer.run()
    instructions = {
        "inverse_kinematics": pipeline.inverse_kinematics.n_instructions(),
        "inertia": pipeline.inertia.n_instructions(),
        "inertia without S_e": rigid.inertia.n_instructions(),
        "1/kappa_2": pipeline.index.n_instructions(),
        "fused": fused.n_instructions(),
    }
    notes = [
        f"compared at {int(ok.sum())} poses; {n - int(ok.sum())} within |sin| < {SERIAL_MARGIN:g} of a serial or "
        f"{PARALLEL_MARGIN:g} of a parallel singularity, where both lose digits alike",
        "CasADi instructions per pose: " + ", ".join(f"{k} {v}" for k, v in instructions.items()),
        f"load average (1 min) {load[0]:.2f} before timing, {os.getloadavg()[0]:.2f} after",
    ]
    if not public:
        notes.append(f'pkm.registry has no "{INDEX}" local index: its row was skipped')
    return {
        "poses": n,
        "repeats": repeats,
        "seed": SEED,
        "design": dict(design),
        "mode": MODE,
        "default_threads": default,
        "instructions": instructions,
        "rows": rows,
        "notes": notes,
    }
