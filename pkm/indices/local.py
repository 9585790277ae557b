"""Local performance indices of a posture, for n x n matrices.

A local index is a CasADi function of matrices at one pose: the Jacobians J and J_f of the generated
``first_order`` (q_a_dot = J x_dot, x_dot = J_f q_a_dot), or the inertia matrices of ``inertia``. The
same graph serves the batched evaluation and the exact design gradients of the global indices. Gao
1998's [J] is pkm's forward Jacobian J_f.

Singular values and eigenvalues are in closed form for n <= 3: the 2 x 2 formulas of Gao 1998 and, for 3 x 3,
the largest eigenvalue of a symmetric matrix by the trigonometric solution of its cubic (Smith 1961) with the
smallest from the adjugate (sigma_min(A) = |det A| / sigma_max(adj A)). Where both J and J_f enter, the smallest
singular value of one is the inverse of the largest of the other. Those indices raise :class:`PkmError` on
larger matrices (the elastic frequency's up to 6 x 6, below), and a mechanism of more degrees of freedom does
not offer them (``LocalIndex.dimension``); the Frobenius condition number and the determinants hold for any n.
The eigenvalues of a symmetric matrix of 4 to 6 rows (a spatial platform's vibration) come from a fixed number
of cyclic Jacobi sweeps written out (:func:`jacobi_eigenvalues`), differentiable like the closed forms.

A pose mixing metres and radians is normalised by the mechanism's characteristic length before any
index is taken (see :mod:`pkm.regions.pipeline`).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache

import casadi as ca
import numpy as np

from pkm.errors import PkmError

MAX_DIMENSION = 3
JACOBI_DIMENSION = 6  # the largest symmetric matrix whose eigenvalues are taken by Jacobi sweeps
JACOBI_SWEEPS = 8  # cyclic sweeps: each squares the off-diagonal's relative size once it is small
JACOBI_FLOOR = 1e-300  # under a rotation's square root: no rotation, and a finite derivative, where the plane is
# already diagonal with equal entries
ISOTROPIC = 1e-300  # floor of the deviatoric norm of a 3 x 3 matrix: keeps the closed form finite at A = a I


@dataclass(frozen=True)
class LocalIndex:
    """A local index: key, meaning, unit (a template with ``{pose}`` and ``{actuator}``, the units of the mechanism's
    pose and actuator coordinates: :meth:`pkm.Mechanism.index_unit`), documented range, its value where the pose
    is singular, the generated function (``source``; or a function of its own of the joints, the pose and the
    design) and outputs (``arguments``) it is computed from, and its formula on CasADi matrices;
    ``epigraph(*arguments, t)``, where given, is a smooth g with g >= 0 exactly where the index is >= t (value -
    t otherwise), and ``epigraph_upper`` one with g >= 0 exactly where it is <= t (t - value otherwise);
    ``dimension`` the largest matrices its formula takes (the closed forms of singular values and eigenvalues
    stop at 3 x 3, the Jacobi sweeps at 6 x 6; None: any); ``raw`` takes the arguments as generated, in SI,
    where the index is a physical quantity (an actuator effort, a joint angle) rather than a ratio of normalised
    matrices
    (:mod:`pkm.regions.pipeline`); ``smooth``, where given, a smooth stand-in of the formula (same arguments)
    that an optimiser's quadrature integrates instead (a positive part smoothed), while every reported value
    takes the formula; a ``signed`` index (a margin) is defined beyond the reach, negative where a limit or the
    assembly is violated, and is NaN only where its formula is (:mod:`pkm.regions.pipeline`)."""

    name: str
    doc: str
    unit: str
    lower: float
    upper: float
    at_singularity: float
    formula: Callable[..., ca.SX]
    source: str | ca.Function = "first_order"
    arguments: tuple[str, ...] = ("J", "J_f")
    epigraph: Callable[..., ca.SX] | None = None
    epigraph_upper: Callable[..., ca.SX] | None = None
    dimension: int | None = MAX_DIMENSION  # the largest n x n its formula takes (None: any)
    raw: bool = False
    smooth: Callable[..., ca.SX] | None = None
    signed: bool = False


def _check_square(A: ca.SX, largest: int = MAX_DIMENSION) -> int:
    n = A.size1()
    if A.size2() != n or not 1 <= n <= largest:
        raise PkmError(f"local indices need square matrices of size 1 to {largest}; got {A.size1()} x {A.size2()}")
    return n


def jacobi_eigenvalues(S: ca.SX, sweeps: int = JACOBI_SWEEPS) -> list[ca.SX]:
    """The eigenvalues of a symmetric n x n matrix, unordered: ``sweeps`` cyclic Jacobi sweeps (Golub and Van
    Loan, Matrix Computations, section 8.5), each rotation in the plane (p, q) annihilating a_pq with
    t = tan(theta) = 2 a_pq sgn(d) / (|d| + sqrt(d^2 + 4 a_pq^2)), d = a_qq - a_pp, the smaller of the two
    angles that do: a_pp -= t a_pq, a_qq += t a_pq, and rows p and q turned by c = 1 / sqrt(1 + t^2), s = t c.
    The diagonal converges quadratically (its error after a sweep is of the order of the squared off-diagonal
    before it), so a fixed count reaches the rounding of a matrix of a few rows, and its derivative converges
    with it."""
    n = S.size1()
    a = [[S[i, j] for j in range(n)] for i in range(n)]
    for _ in range(sweeps):
        for p, q in itertools.combinations(range(n), 2):
            apq, d = a[p][q], a[q][q] - a[p][p]
            root = ca.sqrt(d**2 + 4 * apq**2 + JACOBI_FLOOR)  # the floor keeps sqrt's derivative finite at 0
            t = 2 * apq * ca.if_else(d >= 0, 1, -1) / (ca.fabs(d) + root)
            c = 1 / ca.sqrt(1 + t**2)
            s = t * c
            a[p][p], a[q][q] = a[p][p] - t * apq, a[q][q] + t * apq
            a[p][q] = a[q][p] = ca.SX(0)
            for r in range(n):
                if r not in (p, q):
                    rp, rq = c * a[r][p] - s * a[r][q], s * a[r][p] + c * a[r][q]
                    a[r][p] = a[p][r] = rp
                    a[r][q] = a[q][r] = rq
    return [a[i][i] for i in range(n)]


def _adjugate(A: ca.SX) -> ca.SX:
    """The adjugate of a 3 x 3 matrix (transposed cofactors): adj(A) A = det(A) I."""
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            r = [k for k in range(3) if k != j]
            c = [k for k in range(3) if k != i]
            minor = A[r[0], c[0]] * A[r[1], c[1]] - A[r[0], c[1]] * A[r[1], c[0]]
            row.append((-1) ** (i + j) * minor)
        rows.append(ca.horzcat(*row))
    return ca.vertcat(*rows)


def _discriminant_3(B: ca.SX) -> ca.SX:
    """prod_{i<j} (lambda_i - lambda_j)^2 of a symmetric 3 x 3 matrix as a sum of squares: the Gram determinant
    of I, B, B^2 in the Frobenius product (Parlett 2002, "The (matrix) discriminant as a determinant") by
    Cauchy-Binet, the sum of the squared 3 x 3 minors of their vectors (the off-diagonal entries once, times
    sqrt 2). Each minor is taken from the entries, so that the sum is accurate to the square of the rounding
    where two eigenvalues meet, where the cubic's coefficients would leave only the rounding's square root."""
    B2 = B @ B
    rows = [[1, B[i, i], B2[i, i]] for i in range(3)]
    rows += [[0, np.sqrt(2) * B[i, j], np.sqrt(2) * B2[i, j]] for i, j in ((0, 1), (0, 2), (1, 2))]
    return sum(ca.det(ca.vertcat(*(ca.horzcat(*rows[k]) for k in triple))) ** 2
               for triple in itertools.combinations(range(6), 3) if min(triple) < 3)


def _largest_symmetric_3(S: ca.SX) -> ca.SX:
    """Largest eigenvalue of a symmetric 3 x 3 matrix by the trigonometric solution of its cubic: with
    B = (S - q I) / p (trace 0, tr B^2 = 6), the eigenvalues are q + 2 p cos((phi + 2 pi k) / 3) where
    cos phi = det(B) / 2 and sin phi = sqrt(disc(B) / 108), the depressed cubic's discriminant 108 (1 - r^2)
    taken as a sum of squares (:func:`_discriminant_3`): phi from both by atan2 is exact where two eigenvalues
    coincide (phi = 0 or pi), where acos(r) lost half the digits."""
    q = ca.trace(S) / 3
    off = S[0, 1] ** 2 + S[0, 2] ** 2 + S[1, 2] ** 2
    p = ca.sqrt(ca.fmax(((S[0, 0] - q) ** 2 + (S[1, 1] - q) ** 2 + (S[2, 2] - q) ** 2 + 2 * off) / 6, ISOTROPIC))
    B = (S - q * ca.SX.eye(3)) / p
    discriminant = _discriminant_3(B)
    sine = ca.if_else(discriminant > 0, ca.sqrt(discriminant / 108), 0)
    return q + 2 * p * ca.cos(ca.atan2(sine, ca.det(B) / 2) / 3)


def symmetric_eigenvalues(S: ca.SX) -> tuple[ca.SX, ca.SX]:
    """Largest and smallest eigenvalue of a symmetric positive semidefinite n x n matrix (n <= 6).

    For n = 3 the smallest is det(S) / lambda_max(adj S) (adj S = det(S) S^-1): the largest eigenvalue
    of a matrix is accurate to its own size, where the smallest of the cubic's roots would lose
    det-sized digits to cancellation. From 4 rows on, by Jacobi sweeps (:func:`jacobi_eigenvalues`).
    """
    n = _check_square(S, JACOBI_DIMENSION)
    if n > 3:
        values = jacobi_eigenvalues(S)
        return ca.mmax(ca.vertcat(*values)), ca.mmin(ca.vertcat(*values))
    if n == 1:
        return S[0, 0], S[0, 0]
    if n == 2:
        mean = (S[0, 0] + S[1, 1]) / 2
        radius = ca.sqrt(((S[0, 0] - S[1, 1]) / 2) ** 2 + S[0, 1] ** 2)
        return mean + radius, mean - radius
    return _largest_symmetric_3(S), ca.det(S) / _largest_symmetric_3(_adjugate(S))


def extreme_singular_values(A: ca.SX) -> tuple[ca.SX, ca.SX]:
    """sigma_max, sigma_min of an n x n matrix (n <= 3); for n = 2 in Gao's closed form
    (sigma_max sigma_min = |det A|)."""
    n = _check_square(A)
    if n == 1:
        return ca.fabs(A[0, 0]), ca.fabs(A[0, 0])
    if n == 2:
        frob2 = ca.sumsqr(A)
        det = ca.fabs(A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0])
        smax = ca.sqrt((frob2 + ca.sqrt(ca.fmax(frob2**2 - 4 * det**2, 0))) / 2)
        return smax, det / smax
    adj = _adjugate(A)
    largest = ca.sqrt(_largest_symmetric_3(A.T @ A))
    return largest, ca.fabs(ca.det(A)) / ca.sqrt(_largest_symmetric_3(adj.T @ adj))


def largest_singular_value(A: ca.SX) -> ca.SX:
    return extreme_singular_values(A)[0]


def _inverse_condition_f(J: ca.SX, J_f: ca.SX) -> ca.SX:
    """1/kappa_f = n / sqrt(tr(J J^T) tr(J^-1 J^-T)) with J^-1 = J_f (Gao eqs. 8-11). For n = 2,
    tr(J^-1 J^-T) = tr(J J^T) / det(J)^2 (the adjugate of a 2 x 2 matrix has its entries), so that
    1/kappa_f = 2 |det J| / tr(J J^T) from J alone, 0 where J is not finite (J_f singular)."""
    if J.shape == (2, 2):
        frob2 = ca.sumsqr(J)
        return ca.if_else(frob2 < np.inf, 2 * ca.fabs(J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]) / frob2, 0)
    return J.size1() / ca.sqrt(ca.sumsqr(J) * ca.sumsqr(J_f))


def _inverse_condition_2(J: ca.SX, J_f: ca.SX) -> ca.SX:
    """1/kappa_2 = sigma_min(J) / sigma_max(J) = 1 / (sigma_max(J) sigma_max(J_f))."""
    return 1 / (largest_singular_value(J) * largest_singular_value(J_f))


def _manipulability(_J: ca.SX, J_f: ca.SX) -> ca.SX:
    """w = sqrt(det(J_f J_f^T)) = |det J_f| (Yoshikawa): output velocity volume per unit actuator rates."""
    return ca.fabs(ca.det(J_f))


def _ratio(M: ca.SX) -> ca.SX:
    """1/kappa_2(M) = sigma_min / sigma_max."""
    smax, smin = extreme_singular_values(M)
    return smin / smax


def _kappa(M: ca.SX) -> ca.SX:
    """kappa_2(M) = sigma_max / sigma_min."""
    smax, smin = extreme_singular_values(M)
    return smax / smin


def _symmetric_ratio(M: ca.SX) -> ca.SX:
    """lambda_min / lambda_max of a symmetric positive definite matrix."""
    if _check_square(M) == 2:
        return _ratio(M)
    largest, smallest = symmetric_eigenvalues(M)
    return smallest / largest


def _frequency_epigraph(S: ca.SX, t: ca.SX) -> ca.SX:
    """sqrt(lambda_min(S_e)) >= t as S_e - t^2 I positive semidefinite: for n = 2 a non-negative trace
    and determinant, polynomial in S_e and t and smooth where the eigenvalues meet."""
    if _check_square(S, JACOBI_DIMENSION) != 2:
        return _lowest_frequency(S) - t
    M = S - t**2 * ca.SX.eye(2)
    return ca.vertcat(M[0, 0] + M[1, 1], M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0])


def _elastic_frequency(S: ca.SX) -> ca.SX:
    """The lowest frequency of S_k, 0 where S_k is not finite: at a type-II singularity the task-space inertia
    and the stiffness both vanish along the singular direction (0/0 in S_k), and the frequency's limit there is 0
    (the machine loses its stiffness), which region extremes see at a node on the singularity too."""
    return ca.if_else(ca.sumsqr(S) < np.inf, _lowest_frequency(S), 0)


def _lowest_frequency(S: ca.SX) -> ca.SX:
    if _check_square(S, JACOBI_DIMENSION) == 2:
        return ca.sqrt(extreme_singular_values(S)[1])
    return ca.sqrt(ca.fmax(symmetric_eigenvalues(S)[1], 0))


DEPENDENT = 1e-30  # the Hadamard ratio's floor per column, relative to its norm
TINY = 1e-300  # the floor of a column's squared part independent of those before it


def hadamard_ratio(A: ca.SX) -> ca.SX:
    """|det A| / prod_j ||a_j||, the columns' Hadamard ratio: 1 where the columns are orthogonal, 0 where A is
    singular, in [0, 1] by Hadamard's inequality, and the same whatever the units of A's columns (a column's
    scale cancels between det A and its norm) and under one scale of all its rows (the closure equations of a
    mechanism, in one unit). Taken as prod_j ||a_j'|| / ||a_j||, a_j' the part of a_j orthogonal to the
    columns before it (Gram-Schmidt, each projection applied twice), in O(n^3) operations where a determinant's
    expansion would take n! (a six-legged chain machine's closure is 18 x 18)."""
    ratio = ca.SX(1)
    basis: list[ca.SX] = []
    for j in range(A.size2()):
        a = A[:, j]
        v = a
        for _ in range(2):
            for u in basis:
                v = v - ca.dot(u, v) * u
        # the norms with floors far below any margin: where a column depends on those before it exactly (or is
        # zero) its factor is 1e-30 (DEPENDENT), not 0/0, and the derivatives are finite
        norm = ca.sqrt(ca.sumsqr(a) + TINY / DEPENDENT**2)
        length = ca.sqrt(ca.sumsqr(v) + DEPENDENT**2 * ca.sumsqr(a) + TINY)
        ratio = ratio * (length / norm)
        basis.append(v / length)
    return ratio - ca.if_else(ratio > 1, ratio - 1, 0)  # at most 1 but for round-off; NaN where A is


def _least(a: ca.SX, b: ca.SX) -> ca.SX:
    """The lesser of two values, NaN where either is (where fmin would give the other)."""
    return ca.if_else(a < b, a, b) + 0 * a


def _serial_margin(H_q: ca.SX, _H_x: ca.SX) -> ca.SX:
    """The type I margin: the Hadamard ratio of d h / d(q_a, q_p), singular where a leg's joints can move with
    the platform held (J unbounded)."""
    return hadamard_ratio(H_q)


def _parallel_margin(H_q: ca.SX, H_x: ca.SX) -> ca.SX:
    """The type II margin: the Hadamard ratio of d h / d(q_p, x), singular where the platform can move with
    the actuators held (J_f unbounded); the first columns of H_q, as many as the pose has coordinates, are the
    actuated joints'."""
    return hadamard_ratio(ca.horzcat(H_q[:, H_x.size2():], H_x))


INVERSE_CONDITION_F = LocalIndex(
    "inverse_condition_f",
    "1/kappa_f, kappa_f = ||J||_N ||J^-1||_N with ||J||_N = sqrt(tr(J J^T / n)) (Gao eqs. 8-11)",
    "-", 0.0, 1.0, 0.0, _inverse_condition_f, dimension=None,
)
INVERSE_CONDITION_2 = LocalIndex(
    "inverse_condition_2", "1/kappa_2 = sigma_min(J) / sigma_max(J)", "-", 0.0, 1.0, 0.0, _inverse_condition_2
)
VELOCITY_MAX = LocalIndex(
    "velocity_max",
    "||V||max = sigma_max(J_f): largest output speed for unit actuator rates (Gao eq. 22)",
    "{pose}/{actuator}", 0.0, np.inf, np.inf, lambda _J, J_f: largest_singular_value(J_f),
)
VELOCITY_MIN = LocalIndex(
    "velocity_min",
    "||V||min = sigma_min(J_f) = 1 / sigma_max(J): smallest output speed for unit actuator rates (Gao eq. 22)",
    "{pose}/{actuator}", 0.0, np.inf, 0.0, lambda J, _J_f: 1 / largest_singular_value(J),
)
MANIPULABILITY = LocalIndex(
    "manipulability",
    "w = |det J_f| = sqrt(det(J_f J_f^T)): volume of the output velocities of unit actuator rates",
    "({pose}/{actuator})^{n}", 0.0, np.inf, 0.0, _manipulability, dimension=None,
)
JACOBIAN_DETERMINANT = LocalIndex(
    "jacobian_determinant",
    "|det J| = 1 / |det J_f|: volume of the actuator rates of unit output velocities",
    "({actuator}/{pose})^{n}", 0.0, np.inf, np.inf, lambda J, _J_f: ca.fabs(ca.det(J)), dimension=None,
)
VELOCITY_RATIO = LocalIndex(
    "velocity_ratio",
    "k_v = |x_dot / q1_dot| at the other outputs' rates 0 = 1 / |J_11|: speed of the first output per unit "
    "rate of the first actuator (Wu eq. 6, i = 1)",
    "-", 0.0, np.inf, np.inf, lambda J, _J_f: 1 / ca.fabs(J[0, 0]), dimension=None,
)
DYNAMIC_DEXTERITY = LocalIndex(
    "dynamic_dexterity",
    "1/kappa_2(M_w) = lambda_min / lambda_max of the task-space inertia M_w = J^T M_t J (Lara-Molina eq. 35)",
    "-", 0.0, 1.0, 0.0, _symmetric_ratio, "inertia", ("M_w",),
)
KAPPA_D = LocalIndex(
    "kappa_d",
    "kappa_D = sigma_max / sigma_min of the inertia matrix M_d = (J^T)^-1 M with tau = M_d x_ddot (Wu eqs. 42-43)",
    "-", 1.0, np.inf, np.inf, _kappa, "inertia", ("M_d",),
)
NATURAL_FREQUENCY = LocalIndex(
    "natural_frequency",
    "smallest non-zero natural frequency of (K_T - lambda^2 M_T) z = 0 (Lara-Molina eq. 37): "
    "sqrt(lambda_min(S_e)), S_e = K^1/2 (M_t^-1 + J_m^-1) K^1/2; the rigid-body modes excluded",
    "rad/s", 0.0, np.inf, np.nan, _lowest_frequency, "inertia", ("S_e",), _frequency_epigraph,
)
ACTUATOR_FORCE = LocalIndex(
    "actuator_force",
    "largest actuator force (absolute) that holds the mechanism's load, from its generated actuator_forces",
    "N", 0.0, np.inf, np.inf, lambda f: ca.mmax(ca.fabs(f)), "actuator_forces", ("f_a",),
    epigraph_upper=lambda f, t: ca.vertcat(t - f, t + f), dimension=None,
)
def defined_margins(m: ca.SX) -> ca.SX:
    """Margins with each undefined one (a joint's range where its leg does not assemble: NaN) replaced by the
    least defined one, so that their least value and each epigraph row stay signed and differentiable
    beyond the reach (a reach margin is negative there); NaN where none is defined."""
    defined = ca.fabs(m) < np.inf
    least = ca.mmin(ca.if_else(defined, m, np.inf, True))
    least = ca.if_else(least < np.inf, least, np.nan, True)
    return ca.if_else(defined, m, least, True)


WORKSPACE_MARGIN = LocalIndex(
    "workspace_margin",
    "least margin of the mechanism's workspace: its inverse kinematics' reach and its stated limits (>= 0 "
    "inside the workspace, < 0 beyond it: a reach margin beyond the assembly, a stroke's or a range's margin "
    "wherever the leg's geometry is defined); its epigraph keeps every margin as its own smooth constraint",
    "-", -np.inf, np.inf, -np.inf, lambda m: ca.mmin(defined_margins(m)), "inverse_kinematics", ("reach",),
    lambda m, t: defined_margins(m) - t, dimension=None, signed=True,
)

SINGULARITY_TYPE1 = LocalIndex(
    "singularity_margin_type1",
    "type I (serial) singularity margin: the columns' Hadamard ratio |det A| / prod ||a_j|| of A = [H_a H_p] = "
    "d h / d(q_a, q_p); 0 where a leg's joints move with the platform held",
    "-", 0.0, 1.0, 0.0, _serial_margin, "constraint", ("H_q", "H_x"), dimension=None, raw=True,
)
SINGULARITY_TYPE2 = LocalIndex(
    "singularity_margin_type2",
    "type II (parallel) singularity margin: the columns' Hadamard ratio |det A| / prod ||a_j|| of A = [H_p H_x] "
    "= d h / d(q_p, x); 0 where the platform moves with the actuators held",
    "-", 0.0, 1.0, 0.0, _parallel_margin, "constraint", ("H_q", "H_x"), dimension=None, raw=True,
)
SINGULARITY = LocalIndex(
    "singularity_margin",
    "singularity margin: the lesser of the type I and type II margins (singularity_margin_type1, _type2)",
    "-", 0.0, 1.0, 0.0, lambda H_q, H_x: _least(_serial_margin(H_q, H_x), _parallel_margin(H_q, H_x)),
    "constraint", ("H_q", "H_x"), dimension=None, raw=True,
)
STIFFNESS_MIN = LocalIndex(
    "stiffness_min",
    "least translational stiffness: the smallest eigenvalue of K_t, the Cartesian stiffness's translational block "
    "with the rotation free (its Schur complement; the virtual joint method, pkm.spec.stiffness)",
    "N/m", 0.0, np.inf, 0.0, lambda K_t: symmetric_eigenvalues(K_t)[1], "stiffness", ("K_t",), dimension=None,
    raw=True,
)
STIFFNESS_ISOTROPY = LocalIndex(
    "stiffness_isotropy",
    "lambda_min / lambda_max of K_t, the translational stiffness with the rotation free: 1 where the platform is "
    "as stiff in every direction",
    "-", 0.0, 1.0, 0.0, _symmetric_ratio, "stiffness", ("K_t",), dimension=None, raw=True,
)
ELASTIC_FREQUENCY = LocalIndex(
    "elastic_frequency",
    "lowest natural frequency of the rigid platform on the elastic structure: sqrt(lambda_min(K_x, M_w)) with "
    "the Cartesian stiffness K_x and the task-space inertia M_w = J^T M_t J in the pose's coordinates",
    "rad/s", 0.0, np.inf, 0.0, _elastic_frequency, "vibration", ("S_k",), dimension=JACOBI_DIMENSION, raw=True,
)
COLLISION_MARGIN = LocalIndex(
    "collision_margin",
    "least distance between two legs' capsules less their radii (>= 0 where no two legs touch): the least of the "
    "margins of every pair of links of two legs; its epigraph keeps each pair's margin as its own constraint",
    "m", -np.inf, np.inf, -np.inf, ca.mmin, "collision", ("margins",), lambda m, t: m - t,
    dimension=None, raw=True, signed=True,
)
SINGULAR = 1e-6  # a pose with a singularity margin below this is singular (pkm.Mechanism.singular_types)
SINGULAR_NEAR = 1e-2  # one below this is near a singularity (a not converged index's note names it)

LOCAL_INDICES: tuple[LocalIndex, ...] = (
    INVERSE_CONDITION_F,
    INVERSE_CONDITION_2,
    VELOCITY_MAX,
    VELOCITY_MIN,
    MANIPULABILITY,
    JACOBIAN_DETERMINANT,
    VELOCITY_RATIO,
    DYNAMIC_DEXTERITY,
    KAPPA_D,
    NATURAL_FREQUENCY,
    ACTUATOR_FORCE,
    WORKSPACE_MARGIN,
    SINGULARITY,
    SINGULARITY_TYPE1,
    SINGULARITY_TYPE2,
    STIFFNESS_MIN,
    STIFFNESS_ISOTROPY,
    ELASTIC_FREQUENCY,
    COLLISION_MARGIN,
)


@cache
def local_function(spec: LocalIndex, n: int, shapes: tuple[tuple[int, int], ...] | None = None) -> ca.Function:
    """CasADi function ``(*arguments) -> value`` of a local index on n x n matrices, or on arguments of
    the given ``shapes``."""
    shapes = shapes or ((n, n),) * len(spec.arguments)
    args = [ca.SX.sym(a, *shape) for a, shape in zip(spec.arguments, shapes, strict=True)]
    return ca.Function(spec.name, args, [spec.formula(*args)], list(spec.arguments), [spec.name])


@cache
def epigraph_function(spec: LocalIndex, shapes: tuple[tuple[int, int], ...], upper: bool = False) -> ca.Function:
    """CasADi function ``(*arguments, t) -> g`` on arguments of the given shapes: g >= 0 if and only
    if the local index is >= t, or with ``upper`` <= t (the index's own smooth form where it has one,
    else value - t or t - value)."""
    args = [ca.SX.sym(a, *shape) for a, shape in zip(spec.arguments, shapes, strict=True)]
    t = ca.SX.sym("t")
    own = spec.epigraph_upper if upper else spec.epigraph
    if own is not None:
        g = own(*args, t)
    else:
        value = local_function(spec, 0, shapes)(*args)
        g = t - value if upper else value - t
    return ca.Function(f"{spec.name}_epigraph", [*args, t], [g], [*spec.arguments, "t"], ["margin"])

