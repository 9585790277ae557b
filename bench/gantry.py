"""Throughput of the slider gantry's inverse dynamics (Wu 2008): pkm against a hand-written numpy version.

Per state (pose, velocity, acceleration of the platform): inverse kinematics -> slider forces
tau = (J^T)^-1 (M x_ddot + n) of the rigid virtual-work model (Wu eqs. 1-5, 27-41). The states are
uniform in the task rectangle of pkm's default design (fixed seed), with velocities uniform in
[-1, 1]^2 m/s and accelerations uniform in [-5, 5]^2 m/s^2. Every path is checked against numpy to
1e-9 relative before timing; figures are best of ``repeats``; nothing asserts on time.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

import pkm
import pkm.batch
from bench.throughput import SEED, Timer

MECHANISM = "slider_gantry"
MODE = "below"
SPEED = 1.0  # m/s: each velocity component uniform in [-SPEED, SPEED]
ACCELERATION = 5.0  # m/s^2: each acceleration component uniform in [-ACCELERATION, ACCELERATION]
TOL = 1e-9


def sample_states(m: pkm.Mechanism, design: Any, n: int, seed: int = SEED) -> tuple[np.ndarray, ...]:
    """n poses uniform in the design's task rectangle, with random velocities and accelerations: 3 x (n, 2)."""
    rng = np.random.default_rng(seed)
    box = m.task_rectangle(design).box
    X = rng.uniform(box[:, 0], box[:, 1], size=(n, 2))
    V = rng.uniform(-SPEED, SPEED, size=(n, 2))
    A = rng.uniform(-ACCELERATION, ACCELERATION, size=(n, 2))
    return X, V, A


def numpy_inverse_dynamics(X: np.ndarray, V: np.ndarray, A: np.ndarray, design: Mapping[str, float]) -> np.ndarray:
    """Slider forces (n, 2) of Wu's gantry (mode "below") in plain vectorised numpy, by virtual work.

    Chain i (u_1 = x + d1, u_2 = x - d1): w_i = sqrt(l^2 - u_i^2), q_i = y - l2/2 - w_i, sin(theta_i) =
    u_i/l, cos(theta_i) = w_i/l (theta_i = asin(u_i/l), never needed itself), J row (tan(theta_i), 1),
    theta_dot = x_dot/(l cos), theta_ddot = x_ddot/(l cos) + x_dot^2 sin/(l^2 cos^3) (eq. 27),
    q_ddot = y_ddot + tan x_ddot + x_dot theta_dot/cos^2 (eq. 28). Generalised forces Q in (x, y) of
    the inertia (gravity included) of every body, Newton-Euler about its pivot:

    * slider i at B_i and counterweight i at -q_i, both with partial velocity (tan, 1):
      (tan, 1) [(m_i1 + m_i3) q_ddot_i + (m_i1 - m_i3) g];
    * link at pivot B (A1B1, A3B3 at B1 + (0, l2), A2B2), angle pi/2 - theta, centre s (sin, cos):
      vertical force m (a_cy + g), a_cy = q_ddot - s (theta_ddot sin + theta_dot^2 cos), along (tan, 1),
      and moment about B, I theta_ddot - m s sin (q_ddot + g), along (1/(l cos), 0);
    * platform: m_N (x_ddot, y_ddot + g).

    Then J^T tau = Q (eq. 40), solved in closed form for the 2x2 J^T = [[t1, t2], [1, 1]].
    """
    ell, d1, g = design["l"], design["d1"], design["g"]
    x, x_dot, x_ddot, y_ddot = X[:, 0], V[:, 0], A[:, 0], A[:, 1]
    Qx = design["mN"] * x_ddot
    Qy = design["mN"] * (y_ddot + g)
    chains = (
        (x + d1, design["m11"], design["m13"], (("m12", "I12", "s12"), ("m4", "I4", "s4"))),
        (x - d1, design["m21"], design["m23"], (("m22", "I22", "s22"),)),
    )
    tans = []
    for u, m_slider, m_counter, links in chains:
        w = np.sqrt(ell * ell - u * u)
        sin, cos, tan = u / ell, w / ell, u / w
        l_cos = ell * cos  # = w
        theta_dot = x_dot / l_cos
        theta_ddot = (x_ddot + x_dot * theta_dot * tan) / l_cos
        q_ddot = y_ddot + tan * x_ddot + x_dot * theta_dot / (cos * cos)
        vertical = (m_slider + m_counter) * q_ddot + (m_slider - m_counter) * g
        moment = 0.0
        for mass, inertia, offset in links:
            m, s = design[mass], design[offset]
            vertical = vertical + m * (q_ddot - s * (theta_ddot * sin + theta_dot * theta_dot * cos) + g)
            moment = moment + design[inertia] * theta_ddot - m * s * sin * (q_ddot + g)
        Qx = Qx + tan * vertical + moment / l_cos
        Qy = Qy + vertical
        tans.append(tan)
    t1, t2 = tans
    det = t1 - t2
    return np.stack(((Qx - t2 * Qy) / det, (t1 * Qy - Qx) / det), axis=1)


@dataclass(frozen=True)
class Pipeline:
    """IK -> inverse_dynamics, one ``pkm.batch.evaluate`` per step as pkm's runtime does it."""

    inverse_kinematics: ca.Function
    inverse_dynamics: ca.Function
    signs: np.ndarray
    design: np.ndarray

    def joints(self, X: np.ndarray) -> np.ndarray:
        return pkm.batch.evaluate(self.inverse_kinematics, X, self.signs, self.design)[0][:, :, 0]

    def forces(self, q: np.ndarray, X: np.ndarray, V: np.ndarray, A: np.ndarray) -> np.ndarray:
        return pkm.batch.evaluate(self.inverse_dynamics, q, X, V, A, self.design)[0][:, :, 0]

    def __call__(self, X: np.ndarray, V: np.ndarray, A: np.ndarray) -> np.ndarray:
        return self.forces(self.joints(X), X, V, A)


def discrepancy(tau: np.ndarray, ref: np.ndarray, what: str) -> float:
    """Largest difference from the numpy reference, relative to the largest |force| of each state; raises
    above TOL (and on any non-finite force: every state of the task rectangle is reachable)."""
    err = float(np.max(np.max(np.abs(tau - ref), axis=1) / np.max(np.abs(ref), axis=1)))
    if not err <= TOL:
        raise AssertionError(f"{what} differs from the numpy reference by {err:.3g} > {TOL:g}")
    return err


def run(n: int = 1_000_000, repeats: int = 3, *, log: Callable[[str], None] = print) -> dict[str, Any]:
    """All gantry inverse-dynamics figures: rows with states/s and the ratio to numpy, plus notes."""
    m = pkm.load(MECHANISM)
    design = m.design()
    params = dict(design)
    pipeline = Pipeline(
        m.functions["inverse_kinematics"],
        m.functions["inverse_dynamics"],
        np.asarray(m.working_mode(MODE).signs, dtype=float),
        design.vector(),
    )
    start = time.perf_counter()
    X, V, A = sample_states(m, design, n)
    log(f"gantry: {n} states sampled in {time.perf_counter() - start:.2f} s")
    ref = numpy_inverse_dynamics(X, V, A, params)
    err = discrepancy(m.inverse_dynamics(X, V, A, design, mode=MODE), ref, "pkm inverse_dynamics")
    err_pipeline = discrepancy(pipeline(X, V, A), ref, "pkm IK -> inverse_dynamics")
    log(f"  pkm agrees with numpy to {max(err, err_pipeline):.2g}")
    q = pipeline.joints(X)
    default = pkm.batch.THREADS
    timer = Timer(n, repeats, log)
    timer.add("numpy, hand-written (IK + inverse dynamics)", 1, lambda: numpy_inverse_dynamics(X, V, A, params), 0.0)
    for t in sorted({default, 1}, reverse=True):
        timer.add(
            "pkm inverse_dynamics (public API)", t, lambda: m.inverse_dynamics(X, V, A, design, mode=MODE), err, batch=t
        )
        name = "pkm IK -> inverse_dynamics (pkm.batch.evaluate)"
        timer.add(name, t, lambda: pipeline(X, V, A), err_pipeline, batch=t)
        timer.add("pkm step: inverse_kinematics", t, lambda: pipeline.joints(X), err_pipeline, batch=t)
        timer.add("pkm step: inverse_dynamics", t, lambda: pipeline.forces(q, X, V, A), err_pipeline, batch=t)
    load = os.getloadavg()
    rows = timer.run()
    for row in rows:
        row["states_per_s"] = row.pop("poses_per_s")
    instructions = {
        "inverse_kinematics": pipeline.inverse_kinematics.n_instructions(),
        "inverse_dynamics": pipeline.inverse_dynamics.n_instructions(),
    }
    rel = np.max(np.abs(ref), axis=1)
    notes = [
        f"max relative difference pkm - numpy {max(err, err_pipeline):.2g} (per state, relative to its largest "
        f"|force|; |force| up to {float(rel.max()):.3g} N, median {float(np.median(rel)):.3g} N)",
        "CasADi instructions per state: " + ", ".join(f"{k} {v}" for k, v in instructions.items()),
        f"load average (1 min) {load[0]:.2f} before timing, {os.getloadavg()[0]:.2f} after",
    ]
    return {
        "states": n,
        "repeats": repeats,
        "seed": SEED,
        "mechanism": MECHANISM,
        "mode": MODE,
        "design": params,
        "task_rectangle": m.task_rectangle(design).box.tolist(),
        "speed": SPEED,
        "acceleration": ACCELERATION,
        "default_threads": default,
        "max_discrepancy": max(err, err_pipeline),
        "instructions": instructions,
        "rows": rows,
        "notes": notes,
    }
