"""Local performance indices of a Jacobian, and the global indices built from them.

Local indices are CasADi functions of the Jacobian at one pose, so the same graph serves the batched
numeric evaluation and the exact gradients of the global indices in the design. pkm's J maps output
velocities to actuator rates (q_a_dot = J x_dot); Gao 1998's [J] is pkm's forward Jacobian J_f.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError, UnknownNameError


@dataclass(frozen=True)
class LocalIndex:
    """A local index: its key, meaning, unit, range, and its value where the pose is singular."""

    name: str
    doc: str
    unit: str
    lower: float
    upper: float
    at_singularity: float


@dataclass(frozen=True)
class GlobalIndex:
    """A global index: the region mean of a local index (Gao eqs. 6-7 and 23-25)."""

    name: str
    local: str
    doc: str


LOCAL: dict[str, LocalIndex] = {
    i.name: i
    for i in (
        LocalIndex(
            "inverse_condition_f",
            "1/kappa_f, kappa_f = ||J||_N ||J^-1||_N with ||J||_N = sqrt(tr(J J^T / n)) (Gao eqs. 8-11)",
            "-",
            0.0,
            1.0,
            0.0,
        ),
        LocalIndex("inverse_condition_2", "1/kappa_2 = sigma_min(J) / sigma_max(J)", "-", 0.0, 1.0, 0.0),
        LocalIndex(
            "velocity_max",
            "||V||max = sigma_max(J_f): largest output speed for unit actuator rates (Gao eq. 22)",
            "m/rad",
            0.0,
            np.inf,
            np.inf,
        ),
        LocalIndex(
            "velocity_min",
            "||V||min = sigma_min(J_f): smallest output speed for unit actuator rates (Gao eq. 22)",
            "m/rad",
            0.0,
            np.inf,
            0.0,
        ),
    )
}

GLOBAL: dict[str, GlobalIndex] = {
    i.name: i
    for i in (
        GlobalIndex("gci", "inverse_condition_f", "global conditioning index eta (Gao eqs. 6-7)"),
        GlobalIndex("gci_2", "inverse_condition_2", "region mean of 1/kappa_2"),
        GlobalIndex("gamma_max", "velocity_max", "global maximum velocity index (Gao eqs. 23, 25)"),
        GlobalIndex("gamma_min", "velocity_min", "global minimum velocity index (Gao eqs. 24, 25)"),
    )
}


def local_spec(name: str) -> LocalIndex:
    if name not in LOCAL:
        raise UnknownNameError("local index", name, sorted(LOCAL))
    return LOCAL[name]


def global_spec(name: str) -> GlobalIndex:
    if name not in GLOBAL:
        raise UnknownNameError("index", name, sorted(GLOBAL))
    return GLOBAL[name]


def _singular_values_2x2(A: ca.SX) -> tuple[ca.SX, ca.SX]:
    """sigma_max, sigma_min of a 2x2 matrix in closed form (sigma_max sigma_min = |det A|)."""
    frob2 = ca.sumsqr(A)
    det = ca.fabs(A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0])
    smax = ca.sqrt((frob2 + ca.sqrt(ca.fmax(frob2**2 - 4 * det**2, 0))) / 2)
    return smax, det / smax


@cache
def local_function(name: str, n: int) -> ca.Function:
    """CasADi function ``(J, J_f) -> value`` of a local index for n x n Jacobians."""
    if n != 2:
        raise PkmError(f"local index {name} is implemented for 2 x 2 Jacobians; got {n} x {n}")
    J = ca.SX.sym("J", n, n)
    J_f = ca.SX.sym("J_f", n, n)
    if name == "inverse_condition_f":
        det = ca.fabs(J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0])
        value = n * det / ca.sumsqr(J)
    elif name == "inverse_condition_2":
        smax, smin = _singular_values_2x2(J)
        value = smin / smax
    elif name == "velocity_max":
        value = _singular_values_2x2(J_f)[0]
    elif name == "velocity_min":
        value = _singular_values_2x2(J_f)[1]
    else:
        raise UnknownNameError("local index", name, sorted(LOCAL))
    return ca.Function(name, [J, J_f], [value], ["J", "J_f"], [name])


def _run(fn: ca.Function, J: np.ndarray, J_f: np.ndarray) -> np.ndarray:
    n = J.shape[1]
    flat = [A.transpose(0, 2, 1).reshape(len(A), n * n) for A in (J, J_f)]
    return evaluate(fn, *flat)[0][:, 0, 0]


def evaluate_local(spec: LocalIndex, J: np.ndarray, J_f: np.ndarray) -> np.ndarray:
    """Batched local index (N,) from J and J_f (N, n, n).

    At a singular pose one of J, J_f is unbounded; 1/kappa, the same for J and J_f, is then taken
    from the other, and the other indices take their limiting value ``spec.at_singularity``.
    """
    fn = local_function(spec.name, J.shape[1])
    with np.errstate(invalid="ignore"):
        value = _run(fn, J, J_f)
        singular = ~np.isfinite(value)
        if spec.name.startswith("inverse_condition") and singular.any():
            value[singular] = _run(fn, J_f[singular], J[singular])
    return np.where(np.isfinite(value), value, spec.at_singularity)
