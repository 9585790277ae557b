"""Local performance indices of a posture, and the global indices built from them.

Local indices are CasADi functions of matrices at one pose (the Jacobians J and J_f from the
generated ``first_order``, or the inertia matrices from ``inertia``), so the same graph serves the
batched numeric evaluation and the exact gradients of the global indices in the design. pkm's J maps
output velocities to actuator rates (q_a_dot = J x_dot); Gao 1998's [J] is pkm's forward Jacobian J_f.

A global index is the region mean of its local index (Gao eqs. 6-7, Lara-Molina eq. 36, Wu eqs. 7
and 44), its standard deviation over the region (Wu 2008) or its minimum over the region
(Lara-Molina eq. 38).
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
    """A local index: its key, meaning, unit, range, its value where the pose is singular, and the
    generated function (``source``) whose outputs (``arguments``) it is computed from."""

    name: str
    doc: str
    unit: str
    lower: float
    upper: float
    at_singularity: float
    source: str = "first_order"
    arguments: tuple[str, ...] = ("J", "J_f")


@dataclass(frozen=True)
class GlobalIndex:
    """A global index: the region mean (``reduce="mean"``), standard deviation (``"std"``) or minimum
    (``"min"``) of a local index."""

    name: str
    local: str
    doc: str
    reduce: str = "mean"


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
        LocalIndex(
            "dynamic_dexterity",
            "1/kappa_2(M_w) = lambda_min / lambda_max of the task-space inertia M_w = J^T M_t J "
            "(Lara-Molina eq. 35)",
            "-",
            0.0,
            1.0,
            0.0,
            "inertia",
            ("M_w",),
        ),
        LocalIndex(
            "velocity_ratio",
            "k_v = |x_dot / q1_dot| at y_dot = 0 = 1 / |J_11|: platform speed along x per unit rate of the "
            "first actuator (Wu eq. 6, i = 1)",
            "-",
            0.0,
            np.inf,
            np.inf,
        ),
        LocalIndex(
            "kappa_d",
            "kappa_D = sigma_max / sigma_min of the inertia matrix M_d = (J^T)^-1 M with tau = M_d x_ddot "
            "(Wu eqs. 42-43)",
            "-",
            1.0,
            np.inf,
            np.inf,
            "inertia",
            ("M_d",),
        ),
        LocalIndex(
            "natural_frequency",
            "smallest non-zero natural frequency of (K_T - lambda^2 M_T) z = 0 (Lara-Molina eq. 37): "
            "sqrt(lambda_min(S_e)), S_e = K^1/2 (M_t^-1 + J_m^-1) K^1/2; the two rigid-body modes excluded",
            "rad/s",
            0.0,
            np.inf,
            np.nan,
            "inertia",
            ("S_e",),
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
        GlobalIndex(
            "dynamic_dexterity", "dynamic_dexterity", "global dynamic dexterity: region mean of 1/kappa_2(M_w) (eq. 36)"
        ),
        GlobalIndex(
            "lambda_e",
            "natural_frequency",
            "elastodynamic index: region minimum of the smallest non-zero natural frequency (eq. 38)",
            "min",
        ),
        GlobalIndex("k_av", "velocity_ratio", "global velocity output ratio: region mean of k_v (Wu eq. 7)"),
        GlobalIndex("kappa_d_mean", "kappa_d", "region mean of kappa_D (Wu eq. 44)"),
        GlobalIndex("kappa_d_std", "kappa_d", "region standard deviation of kappa_D (Wu section 6.1)", "std"),
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
    """CasADi function ``(*arguments) -> value`` of a local index for n x n matrices."""
    if n != 2:
        raise PkmError(f"local index {name} is implemented for 2 x 2 matrices; got {n} x {n}")
    spec = local_spec(name)
    args = [ca.SX.sym(a, n, n) for a in spec.arguments]
    if spec.source == "inertia":
        smax, smin = _singular_values_2x2(args[0])
        value = {"dynamic_dexterity": smin / smax, "kappa_d": smax / smin}.get(name, ca.sqrt(smin))
        return ca.Function(name, args, [value], list(spec.arguments), [name])
    J, J_f = args
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
    elif name == "velocity_ratio":
        value = 1 / ca.fabs(J[0, 0])
    else:
        raise UnknownNameError("local index", name, sorted(LOCAL))
    return ca.Function(name, [J, J_f], [value], ["J", "J_f"], [name])


@cache
def epigraph_function(name: str, n: int) -> ca.Function:
    """CasADi function ``(*arguments, t) -> g``: g >= 0 if and only if the local index is >= t.

    For the natural frequency, sqrt(lambda_min(S_e)) >= t is S_e - t^2 I positive semidefinite:
    trace and determinant non-negative, polynomial in S_e and t, smooth where the eigenvalues meet
    (the closed-form lambda_min is not). Other indices use value - t.
    """
    spec = local_spec(name)
    args = [ca.SX.sym(a, n, n) for a in spec.arguments]
    t = ca.SX.sym("t")
    if name == "natural_frequency" and n == 2:
        S = args[0] - t**2 * ca.SX.eye(2)
        g = ca.vertcat(S[0, 0] + S[1, 1], S[0, 0] * S[1, 1] - S[0, 1] * S[1, 0])
    else:
        g = local_function(name, n)(*args) - t
    return ca.Function(f"{name}_epigraph", [*args, t], [g], [*spec.arguments, "t"], ["g"])


def _run(fn: ca.Function, *matrices: np.ndarray) -> np.ndarray:
    n = matrices[0].shape[1]
    flat = [A.transpose(0, 2, 1).reshape(len(A), n * n) for A in matrices]
    return evaluate(fn, *flat)[0][:, 0, 0]


def evaluate_local(spec: LocalIndex, matrices: dict[str, np.ndarray]) -> np.ndarray:
    """Batched local index (N,) from the matrices (N, n, n) named by ``spec.arguments``.

    At a singular pose one of J, J_f is unbounded; 1/kappa, the same for J and J_f, is then taken
    from the other, and the other indices take their limiting value ``spec.at_singularity``.
    """
    args = [matrices[a] for a in spec.arguments]
    fn = local_function(spec.name, args[0].shape[1])
    with np.errstate(invalid="ignore"):
        value = _run(fn, *args)
        singular = ~np.isfinite(value)
        if spec.name.startswith("inverse_condition") and singular.any():
            value[singular] = _run(fn, *(a[singular] for a in args[::-1]))
    return np.where(np.isfinite(value), value, spec.at_singularity)
