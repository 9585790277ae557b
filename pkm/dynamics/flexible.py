"""Flexible-joint dynamics: natural frequencies, the exact motor torques along a trajectory, energy.

The generated ``elastic_dynamics(q, x, z_dot, design) -> (M_T, C_T, K_T, f_t)`` is the complete model
with flexible actuated joints (Lara-Molina 2016 eq. 31) in z = (theta_a, theta_m), the actuated joint
angles then the rotor angles after the reduction::

    M_T z_ddot + C_T z_dot + f_t + K_T z = u,   u = (0, tau_m),
    M_T = blockdiag(M_t, J_m),   C_T = blockdiag(C_t, 0),   K_T = [[K, -K], [-K, K]],
    f_t = (f_a(theta_a_dot), V theta_m_dot).

M_t = Psi^T M Psi and C_t = Psi^T (M Psi_dot + C Psi) project the chains' model (eq. 21) onto the
actuated joints (eqs. 24-29); Lara-Molina's C_t = Psi^T C Psi omits the Psi_dot term. The plane of the
mechanism is horizontal: the only potential energy is that of the transmission springs (eq. 16).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate
from pkm.dynamics.trajectories import Trajectory, as_times
from pkm.errors import PkmError, PoseError, SingularityError
from pkm.kinematics import as_batch, solve_joints, unbatch

if TYPE_CHECKING:
    from pkm.kinematics import DesignLike, KinematicModel

RIGID_TOLERANCE = 1e-9  # eigenvalues of (K_T, M_T) below this fraction of the largest are rigid-body modes
MATCH_TOLERANCE = 1e-8  # [pose units] forward kinematics of a trajectory's joints back onto it


def elastic_dynamics(mech: KinematicModel, purpose: str) -> ca.Function:
    """The generated ``elastic_dynamics`` of eq. 31, checked to take the 2 n_act rates of z; ``purpose``
    names what needs it in the error when the model lacks it."""
    fn = mech.functions.require("elastic_dynamics", purpose)
    if fn.numel_in(2) != 2 * mech.n_act:
        raise PkmError(
            f"the {mech.name} elastic_dynamics takes {fn.numel_in(2)} rates; eq. 31 needs the "
            f"{2 * mech.n_act} of (theta_a, theta_m)"
        )
    return fn


@dataclass(frozen=True)
class NaturalFrequencies:
    """Natural frequencies and mode shapes of (K_T - lambda^2 M_T) z = 0 (Lara-Molina 2016 eq. 37).

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (N, 2 n_act)
        lambda in ascending order [rad/s], exactly 0 for the rigid-body modes (whose computed
        lambda^2 is round-off); NaN where the pose is out of reach or singular.
    shapes : numpy.ndarray, shape (N, 2 n_act, 2 n_act)
        Mode shapes as columns, in z = (theta_a, theta_m), normalised so that
        shapes^T M_T shapes = I, with the largest component of each shape positive.
    rigid : numpy.ndarray of bool, shape (N, 2 n_act)
        The rigid-body modes (lambda = 0): K_T's null space, theta_a = theta_m.
    """

    frequencies: np.ndarray
    shapes: np.ndarray
    rigid: np.ndarray

    @property
    def lowest_elastic(self) -> np.ndarray:
        """The smallest non-zero natural frequency [rad/s], shape (N,).

        This is the local quantity that eq. 38 minimises over a region: the smallest lambda_T, taken
        literally, is always a rigid-body 0.
        """
        return np.where(self.rigid, np.inf, self.frequencies).min(axis=-1)


def _cholesky(M: np.ndarray) -> np.ndarray:
    """Cholesky factors of a batch of symmetric M, NaN where M is not positive definite (at a parallel
    singularity M_t is of order 1/det^2 and its round-off takes either sign). The batch is factored at once;
    only when that fails is it halved, down to the rows that have no factor."""
    try:
        return np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        if len(M) == 1:
            return np.full_like(M, np.nan)
        half = len(M) // 2
        return np.concatenate([_cholesky(M[:half]), _cholesky(M[half:])])


def _modes(L: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenpairs of K v = lambda^2 M v over a batch, given the Cholesky factors L of M = L L^T."""
    L_inv = np.linalg.inv(L)
    A = L_inv @ K @ np.swapaxes(L_inv, 1, 2)
    squared, V = np.linalg.eigh((A + np.swapaxes(A, 1, 2)) / 2)
    shapes = np.swapaxes(L_inv, 1, 2) @ V
    largest = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=1)[:, None, :], axis=1)
    shapes *= np.where(largest < 0, -1.0, 1.0)
    rigid = squared <= RIGID_TOLERANCE * np.abs(squared).max(axis=1, keepdims=True)
    return np.where(rigid, 0.0, np.sqrt(np.clip(squared, 0.0, None))), shapes, rigid


def natural_frequencies(
    mech: KinematicModel, pose: Any, design: DesignLike = None, *, mode: str | None = None
) -> NaturalFrequencies:
    """Natural frequencies and mode shapes of the flexible-joint model at fixed postures (eq. 37).

    The undamped model at rest, M_T z_ddot + K_T z = 0, is solved as the generalised symmetric
    eigenproblem (K_T - lambda^2 M_T) z = 0 through the Cholesky factor of M_T. K_T is singular: its
    null space theta_a = theta_m holds n_act rigid-body modes with lambda = 0, and the elastodynamic
    index is the smallest non-zero frequency (:attr:`NaturalFrequencies.lowest_elastic`). A pose whose M_T
    has no Cholesky factor (not positive definite, at or beside a parallel singularity) gets a NaN row, the
    other rows of the batch being what they are alone.

    Parameters
    ----------
    mech : KinematicModel
    pose : array_like, shape (N, n_out) or (n_out,)
    design : design-like, optional
    mode : str, optional
        Working mode; the mechanism's first by default.

    Returns
    -------
    NaturalFrequencies
        Arrays over the batch, without the leading axis for a single 1-D pose.
    """
    elastic = elastic_dynamics(mech, f"the natural frequencies of the {mech.name}")
    joints = solve_joints(mech, pose, design, mode)
    x, d, q, ok = joints.x, joints.design, joints.q, joints.reachable
    size = 2 * mech.n_act
    M_T, _, K_T, _ = evaluate(elastic, q, x, np.zeros(size), d)
    valid = ok & np.isfinite(M_T).all(axis=(1, 2))
    L = np.full_like(M_T, np.nan)
    L[valid] = _cholesky(M_T[valid])
    valid &= np.isfinite(L).all(axis=(1, 2))
    frequencies = np.full((len(x), size), np.nan)
    shapes = np.full((len(x), size, size), np.nan)
    rigid = np.zeros((len(x), size), dtype=bool)
    if valid.any():
        frequencies[valid], shapes[valid], rigid[valid] = _modes(L[valid], K_T[valid])
    return NaturalFrequencies(*(joints.unbatch(a) for a in (frequencies, shapes, rigid)))


@dataclass(frozen=True)
class FlexibleMotion:
    """Joint and rotor motion and the motor torques that drive a trajectory through flexible joints.

    Arrays are over the sample times, N = len(t).

    Attributes
    ----------
    t : numpy.ndarray, shape (N,)
    x : numpy.ndarray, shape (N, n_out)
        End-effector positions.
    theta_a, theta_a_dot : numpy.ndarray, shape (N, n_act)
        Actuated joint angles and rates.
    theta_m, theta_m_dot : numpy.ndarray, shape (N, n_act)
        Rotor angles and rates after the reduction.
    tau_m : numpy.ndarray, shape (N, n_act)
        Motor torques after the reduction (eq. 30).
    torque : casadi.Function
        t -> tau_m(t), exact at any time; called on a casadi SX scalar it returns the expression, as
        :func:`simulate` expects of its ``torque``.
    assembly : str
        The assembly mode in which the forward kinematics of theta_a gives back x.
    """

    t: np.ndarray
    x: np.ndarray
    theta_a: np.ndarray
    theta_a_dot: np.ndarray
    theta_m: np.ndarray
    theta_m_dot: np.ndarray
    tau_m: np.ndarray
    torque: ca.Function
    assembly: str

    @property
    def z(self) -> np.ndarray:
        """(theta_a, theta_m), shape (N, 2 n_act): the coordinates of eq. 31."""
        return np.hstack([self.theta_a, self.theta_m])

    @property
    def z_dot(self) -> np.ndarray:
        """(theta_a_dot, theta_m_dot), shape (N, 2 n_act)."""
        return np.hstack([self.theta_a_dot, self.theta_m_dot])


def flexible_inverse_dynamics(
    mech: KinematicModel, trajectory: Trajectory, times: Any, design: DesignLike = None, *, mode: str | None = None
) -> FlexibleMotion:
    """Exact motor torques that make the end effector follow a trajectory through flexible joints.

    Everything is a CasADi expression of the time t: x(t) gives q(t) by the generated inverse
    kinematics, its time derivatives by automatic differentiation in t. From eq. 30 (with the Psi_dot
    term in C_t)::

        tau_a   = M_t theta_a_ddot + C_t theta_a_dot + f_a          (torque the springs transmit)
        theta_m = theta_a + K^-1 tau_a
        tau_m   = J_m theta_m_ddot + V theta_m_dot + K (theta_m - theta_a)

    theta_m_ddot needs the fourth derivative of theta_a, hence of x: use a trajectory of class C^4,
    such as :meth:`Trajectory.point_to_point`. A Coulomb friction (fc > 0) makes tau_a jump where a
    joint rate changes sign; its derivative is taken as zero there, so tau_m misses the impulse.

    Parameters
    ----------
    mech : KinematicModel
    trajectory : Trajectory
    times : array_like, shape (N,)
        Sample times [s].
    design : design-like, optional
    mode : str, optional
        Working mode of the inverse kinematics; the mechanism's first by default.

    Returns
    -------
    FlexibleMotion

    Raises
    ------
    PoseError
        If the trajectory leaves the working mode's workspace at a sample time.
    SingularityError
        If a torque is not finite (a serial or parallel singularity on the path).
    """
    if trajectory.dimension != mech.n_out:
        raise PkmError(f"the trajectory has {trajectory.dimension} coordinates; the {mech.name} has {mech.n_out}")
    purpose = f"the flexible inverse dynamics of the {mech.name}"
    ik, elastic = mech.functions.require("inverse_kinematics", purpose), elastic_dynamics(mech, purpose)
    t_samples = as_times(times, increasing=False)
    d = ca.DM(mech.design_vector(design))
    n = mech.n_act
    t = ca.SX.sym("t")
    x = trajectory.position(t)
    q, reach = ik(x, ca.DM(mech.working_mode(mode).signs), d)
    theta_a = q[:n]
    a_dot = ca.jacobian(theta_a, t)
    a_ddot = ca.jacobian(a_dot, t)
    M_T, C_T, K_T, f_t = elastic(q, x, ca.vertcat(a_dot, ca.DM.zeros(n)), d)
    tau_a = M_T[:n, :n] @ a_ddot + C_T[:n, :n] @ a_dot + f_t[:n]
    K = K_T[:n, :n]
    theta_m = theta_a + ca.solve(K, tau_a)
    m_dot = ca.jacobian(theta_m, t)
    m_ddot = ca.jacobian(m_dot, t)
    z, z_dot = ca.vertcat(theta_a, theta_m), ca.vertcat(a_dot, m_dot)
    M_T, C_T, K_T, f_t = elastic(q, x, z_dot, d)
    # The rotor rows of eq. 31; its joint rows vanish by the choice of theta_m.
    tau_m = (M_T @ ca.vertcat(a_ddot, m_ddot) + C_T @ z_dot + f_t + K_T @ z)[n:]
    torque = ca.Function("tau_m", [t], [tau_m], ["t"], ["tau_m"])
    samples = ca.Function(
        "flexible_motion",
        [t],
        [x, theta_a, a_dot, theta_m, m_dot, tau_m, reach],
        ["t"],
        ["x", "theta_a", "theta_a_dot", "theta_m", "theta_m_dot", "tau_m", "reach"],
    )
    *values, margins = (v[:, :, 0] for v in evaluate(samples, t_samples[:, None]))
    out = (margins < -REACH_TOLERANCE).any(axis=1)
    if out.any():
        k = int(np.flatnonzero(out)[0])
        raise PoseError(
            f"the trajectory leaves the {mech.working_mode(mode).name} workspace of the {mech.name} at "
            f"t = {t_samples[k]:g} s, x = {values[0][k].tolist()}"
        )
    bad = ~np.isfinite(np.hstack(values)).all(axis=1)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise SingularityError(
            f"the motor torques are unbounded at t = {t_samples[k]:g} s, x = {values[0][k].tolist()}"
        )
    assembly = _matching_assembly(mech, values[1], values[0], np.asarray(d).ravel())
    return FlexibleMotion(t_samples, *values, torque=torque, assembly=assembly)


def _matching_assembly(mech: KinematicModel, theta_a: np.ndarray, x: np.ndarray, d: np.ndarray) -> str:
    """The assembly mode whose forward kinematics of theta_a gives back x at every sample."""
    fk = mech.functions.require("forward_kinematics", f"the assembly mode of the {mech.name} along a trajectory")
    errors = []
    for branch in mech.assembly_modes:
        x_fk = evaluate(fk, theta_a, np.array(branch.signs), d)[0][:, :, 0]
        errors.append(np.nanmax(np.where(np.isnan(x_fk), np.inf, np.abs(x_fk - x))))
    best = int(np.argmin(errors))
    scale = max(1.0, float(np.abs(x).max()))
    if errors[best] > MATCH_TOLERANCE * scale:
        raise SingularityError(
            f"no assembly mode of the {mech.name} follows the trajectory (closest: "
            f"{mech.assembly_modes[best].name}, off by {errors[best]:.3g}): it crosses a parallel singularity"
        )
    return mech.assembly_modes[best].name


def energy(
    mech: KinematicModel, z: Any, z_dot: Any, design: DesignLike = None, *, assembly: str | None = None
) -> np.ndarray | float:
    """Total mechanical energy of the flexible-joint model along a motion.

    E = 1/2 z_dot^T M_T z_dot + 1/2 z^T K_T z
      = 1/2 theta_a_dot^T M_t theta_a_dot + 1/2 theta_m_dot^T J_m theta_m_dot
        + 1/2 (theta_a - theta_m)^T K (theta_a - theta_m)        (eqs. 16-18, 23).

    Parameters
    ----------
    mech : KinematicModel
    z, z_dot : array_like, shape (N, 2 n_act) or (2 n_act,)
        (theta_a, theta_m) and their rates, e.g. :attr:`Simulation.z` and :attr:`Simulation.z_dot`.
    design : design-like, optional
    assembly : str, optional
        Assembly mode of the forward kinematics of theta_a; the mechanism's first by default.

    Returns
    -------
    numpy.ndarray, shape (N,), or float
        [J]; NaN where theta_a cannot be assembled.
    """
    purpose = f"the energy of the {mech.name}"
    fk, elastic = mech.functions.require("forward_kinematics", purpose), elastic_dynamics(mech, purpose)
    n = mech.n_act
    z, single = as_batch(z, 2 * n, "z")
    z_dot, single_dot = as_batch(z_dot, 2 * n, "z_dot")
    if len(z) != len(z_dot):
        raise PoseError(f"z has {len(z)} rows and z_dot {len(z_dot)}")
    d = mech.design_vector(design)
    x, q, margins = evaluate(fk, z[:, :n], np.array(mech.assembly_mode(assembly).signs), d)
    M_T, _, K_T, _ = evaluate(elastic, q[:, :, 0], x[:, :, 0], z_dot, d)
    total = 0.5 * np.einsum("ni,nij,nj->n", z_dot, M_T, z_dot) + 0.5 * np.einsum("ni,nij,nj->n", z, K_T, z)
    total[margins.min(axis=(1, 2)) < -REACH_TOLERANCE] = np.nan
    out = unbatch(total, single and single_dot)
    return float(out) if np.ndim(out) == 0 else out
