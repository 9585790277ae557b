"""The dynamic model at runtime: inertia, inverse and forward dynamics, natural frequencies.

Generic over the mechanisms whose generated module emits dynamic functions beside the kinematic ones:

* ``inertia(q, x, design) -> (M_t, M_w, ...)``, with ``S_e`` for a flexible-joint model and ``M_d``
  for a virtual-work model;
* ``inverse_dynamics(q, x, x_dot, x_ddot, design) -> tau``, a rigid model by virtual work (Wu 2008
  eq. 41, see ``symbolic/virtual_work.py``), used as it is; or otherwise the Lagrange chain functions
  (see ``symbolic/lagrange.py``):
* ``second_order(q, x, x_dot, design) -> (q_dot, q_ddot_bias)``;
* ``elastic_dynamics(q, x, z_dot, design) -> (M_T, C_T, K_T, f_t)``, the complete model with flexible
  actuated joints (Lara-Molina 2016 eq. 31) in z = (theta_a, theta_m), the actuated joint angles then
  the rotor angles after the reduction::

      M_T z_ddot + C_T z_dot + f_t + K_T z = u,   u = (0, tau_m),
      M_T = blockdiag(M_t, J_m),   C_T = blockdiag(C_t, 0),   K_T = [[K, -K], [-K, K]],
      f_t = (f_a(theta_a_dot), V theta_m_dot).

M_t = Psi^T M Psi and C_t = Psi^T (M Psi_dot + C Psi) project the chains' model (eq. 21) onto the
actuated joints (eqs. 24-29); Lara-Molina's C_t = Psi^T C Psi omits the Psi_dot term. The plane of the
mechanism is horizontal: the only potential energy is that of the transmission springs (eq. 16).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate
from pkm.errors import ComputationError, PkmError, PoseError, SingularityError, UnknownNameError

if TYPE_CHECKING:
    from pkm.mechanism import DesignLike, Mechanism

SPACES = {"task": "M_w", "actuated": "M_t", "mixed": "M_d"}
METHODS = ("adams", "bdf")
RIGID_TOLERANCE = 1e-9  # eigenvalues of (K_T, M_T) below this fraction of the largest are rigid-body modes
MATCH_TOLERANCE = 1e-8  # [pose units] forward kinematics of a trajectory's joints back onto it


def _function(mech: Mechanism, name: str) -> ca.Function:
    functions = mech.functions
    if name not in functions:
        raise PkmError(
            f"the {mech.name} mechanism has no generated {name!r} function: its dynamic model is not "
            f"derived (it has {', '.join(sorted(functions))})"
        )
    return functions[name]


def _elastic_dynamics(mech: Mechanism) -> ca.Function:
    fn = _function(mech, "elastic_dynamics")
    if fn.numel_in(2) != 2 * mech.n_act:
        raise PkmError(
            f"the {mech.name} elastic_dynamics takes {fn.numel_in(2)} rates; eq. 31 needs the "
            f"{2 * mech.n_act} of (theta_a, theta_m)"
        )
    return fn


def _vector(values: Any, size: int, what: str) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if arr.shape != (size,):
        raise PkmError(f"{what} must have shape ({size},); got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise PkmError(f"{what} contains non-finite values")
    return arr


def _times(times: Any, *, increasing: bool) -> np.ndarray:
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or len(t) < (2 if increasing else 1):
        raise PkmError(f"times must be a 1-D array of {'at least two' if increasing else 'one or more'} values")
    if not np.all(np.isfinite(t)):
        raise PkmError("times contains non-finite values")
    if increasing and not np.all(np.diff(t) > 0):
        raise PkmError("times must be strictly increasing")
    return t


def inertia_matrix(
    mech: Mechanism, pose: Any, design: DesignLike = None, *, mode: str | None = None, space: str = "task"
) -> np.ndarray:
    """Inertia matrix of the mechanism at the poses (Lara-Molina 2016 eqs. 29, 35).

    Parameters
    ----------
    mech : Mechanism
    pose : array_like, shape (N, n_out) or (n_out,)
    design : design-like, optional
    mode : str, optional
        Working mode; the mechanism's first by default.
    space : {"task", "actuated", "mixed"}
        ``"task"``: M_w = J^T M_t J, the inertia seen at the end effector (eq. 35 with pkm's J,
        q_a_dot = J x_dot); ``"actuated"``: M_t = Psi^T M Psi, rotors excluded (eq. 29);
        ``"mixed"``: M_d = (J^T)^-1 M_w, actuator forces per end-effector acceleration (Wu 2008 eq. 42),
        for the mechanisms whose model emits it.

    Returns
    -------
    numpy.ndarray, shape (N, n, n) or (n, n)
        n = n_out for ``"task"`` and n_act for ``"actuated"``; NaN where the pose is out of reach.
    """
    if space not in SPACES:
        raise UnknownNameError("inertia space", space, list(SPACES))
    fn = _function(mech, "inertia")
    if SPACES[space] not in fn.name_out():
        raise PkmError(f"the {mech.name} model has no {space} inertia matrix ({SPACES[space]})")
    x, d, q, ok, single = mech._joints(pose, design, mode, False)
    out = evaluate(fn, q, x, d)[fn.name_out().index(SPACES[space])]
    out[~ok] = np.nan
    return mech._unbatch(out, single)


def _motion_batch(
    mech: Mechanism, pose: Any, velocity: Any, acceleration: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Pose, velocity and acceleration as (N, n_out) arrays; 1-D inputs are shared by the batch."""
    arrays = [
        mech._batch(v, mech.n_out, w)
        for v, w in ((pose, "pose"), (velocity, "velocity"), (acceleration, "acceleration"))
    ]
    n = max(len(a) for a, _ in arrays)
    for (a, single), what in zip(arrays, ("pose", "velocity", "acceleration"), strict=True):
        if len(a) != n and not single:
            raise PoseError(f"{what} has {len(a)} rows; the batch has {n}")
    full = [np.broadcast_to(a, (n, mech.n_out)) for a, _ in arrays]
    return *full, all(single for _, single in arrays)


def inverse_dynamics(
    mech: Mechanism,
    pose: Any,
    velocity: Any,
    acceleration: Any,
    design: DesignLike = None,
    *,
    mode: str | None = None,
    joint_torques: bool = False,
) -> np.ndarray:
    """Motor torques that produce an end-effector motion with rigid transmissions.

    The transmissions are taken as rigid (theta_m = theta_a, the limit of eq. 30 for K -> infinity),
    so the rotors move with the actuated joints and the motor torques are::

        tau_m = (M_t + J_m) theta_a_ddot + C_t theta_a_dot + f_a + V theta_a_dot,

    with theta_a_dot = J x_dot and theta_a_ddot = J x_ddot + Phi_dot x_dot (the actuated rows of the
    joint accelerations, eq. 28 written in the end-effector coordinates), M_t and C_t of eq. 29 with
    the Psi_dot term, f_a the joint friction of eq. 22, J_m and V the rotor inertia and viscous
    friction of eq. 23. Use :func:`flexible_inverse_dynamics` for the flexible transmissions.

    Parameters
    ----------
    mech : Mechanism
    pose, velocity, acceleration : array_like, shape (N, n_out) or (n_out,)
        End-effector position, velocity and acceleration; a 1-D array is shared by the batch.
    design : design-like, optional
    mode : str, optional
        Working mode; the mechanism's first by default.
    joint_torques : bool
        Return instead the torques tau_a = M_t theta_a_ddot + C_t theta_a_dot + f_a that the
        transmissions apply to the actuated joints (eq. 29).

    Returns
    -------
    numpy.ndarray, shape (N, n_act) or (n_act,)
        NaN where the pose is out of reach.

    A mechanism with a rigid virtual-work model (``inverse_dynamics`` generated, e.g. the slider
    gantry: tau = (J^T)^-1 M x_ddot + N, Wu 2008 eq. 41) uses it; it has no transmissions, so
    ``joint_torques`` returns the same forces.
    """
    if "inverse_dynamics" in mech.functions:
        pose, x_dot, x_ddot, single = _motion_batch(mech, pose, velocity, acceleration)
        x, d, q, ok, _ = mech._joints(pose, design, mode, False)
        (tau,) = evaluate(mech.functions["inverse_dynamics"], q, x, x_dot, x_ddot, d)
        tau = tau[:, :, 0]
        tau[~ok] = np.nan
        return mech._unbatch(tau, single)
    first, second, elastic = (
        _function(mech, "first_order"),
        _function(mech, "second_order"),
        _elastic_dynamics(mech),
    )
    pose, x_dot, x_ddot, single = _motion_batch(mech, pose, velocity, acceleration)
    x, d, q, _, _ = mech._joints(pose, design, mode, False)
    n = mech.n_act
    J = evaluate(first, q, x, d)[0]
    q_dot, bias = evaluate(second, q, x, x_dot, d)
    rate = q_dot[:, :n, 0]
    accel = np.einsum("nij,nj->ni", J, x_ddot) + bias[:, :n, 0]
    M_T, C_T, _, f_t = evaluate(elastic, q, x, np.hstack([rate, rate]), d)
    tau_a = (
        np.einsum("nij,nj->ni", M_T[:, :n, :n], accel) + np.einsum("nij,nj->ni", C_T[:, :n, :n], rate) + f_t[:, :n, 0]
    )
    if joint_torques:
        return mech._unbatch(tau_a, single)
    tau_m = tau_a + np.einsum("nij,nj->ni", M_T[:, n:, n:], accel) + f_t[:, n:, 0]
    return mech._unbatch(tau_m, single)


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

        This is the local quantity that eq. 38 minimises over the MIW: the smallest lambda_T, taken
        literally, is always a rigid-body 0.
        """
        return np.where(self.rigid, np.inf, self.frequencies).min(axis=-1)


def _modes(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenpairs of K v = lambda^2 M v over a batch of symmetric positive definite M."""
    L_inv = np.linalg.inv(np.linalg.cholesky(M))
    A = L_inv @ K @ np.swapaxes(L_inv, 1, 2)
    squared, V = np.linalg.eigh((A + np.swapaxes(A, 1, 2)) / 2)
    shapes = np.swapaxes(L_inv, 1, 2) @ V
    largest = np.take_along_axis(shapes, np.abs(shapes).argmax(axis=1)[:, None, :], axis=1)
    shapes *= np.where(largest < 0, -1.0, 1.0)
    rigid = squared <= RIGID_TOLERANCE * np.abs(squared).max(axis=1, keepdims=True)
    return np.where(rigid, 0.0, np.sqrt(np.clip(squared, 0.0, None))), shapes, rigid


def natural_frequencies(
    mech: Mechanism, pose: Any, design: DesignLike = None, *, mode: str | None = None
) -> NaturalFrequencies:
    """Natural frequencies and mode shapes of the flexible-joint model at fixed postures (eq. 37).

    The undamped model at rest, M_T z_ddot + K_T z = 0, is solved as the generalised symmetric
    eigenproblem (K_T - lambda^2 M_T) z = 0 through the Cholesky factor of M_T. K_T is singular: its
    null space theta_a = theta_m holds n_act rigid-body modes with lambda = 0, and the elastodynamic
    index is the smallest non-zero frequency (:attr:`NaturalFrequencies.lowest_elastic`).

    Parameters
    ----------
    mech : Mechanism
    pose : array_like, shape (N, n_out) or (n_out,)
    design : design-like, optional
    mode : str, optional
        Working mode; the mechanism's first by default.

    Returns
    -------
    NaturalFrequencies
        Arrays over the batch, without the leading axis for a single 1-D pose.
    """
    elastic = _elastic_dynamics(mech)
    x, d, q, ok, single = mech._joints(pose, design, mode, False)
    size = 2 * mech.n_act
    M_T, _, K_T, _ = evaluate(elastic, q, x, np.zeros(size), d)
    valid = ok & np.isfinite(M_T).all(axis=(1, 2))
    frequencies = np.full((len(x), size), np.nan)
    shapes = np.full((len(x), size, size), np.nan)
    rigid = np.zeros((len(x), size), dtype=bool)
    if valid.any():
        frequencies[valid], shapes[valid], rigid[valid] = _modes(M_T[valid], K_T[valid])
    return NaturalFrequencies(*(mech._unbatch(a, single) for a in (frequencies, shapes, rigid)))


@dataclass(frozen=True)
class _Operations:
    cos: Callable[[Any], Any]
    sin: Callable[[Any], Any]
    clip: Callable[[Any], Any]
    ramp: Callable[[Any], Any]
    stack: Callable[[list[Any]], Any]


_NUMERIC = _Operations(
    np.cos, np.sin, lambda u: np.clip(u, 0.0, 1.0), lambda u: np.maximum(u, 0.0), lambda c: np.stack(c, axis=-1)
)
_SYMBOLIC = _Operations(
    ca.cos, ca.sin, lambda u: ca.fmin(ca.fmax(u, 0), 1), lambda u: ca.fmax(u, 0), lambda c: ca.vertcat(*c)
)


def _operations(t: Any) -> tuple[Any, _Operations]:
    if isinstance(t, ca.SX | ca.MX | ca.DM):
        return t, _SYMBOLIC
    return np.asarray(t, dtype=float), _NUMERIC


def rest_to_rest(u: Any) -> Any:
    """s(u) = 126 u^5 - 420 u^6 + 540 u^7 - 315 u^8 + 70 u^9: s(0) = 0, s(1) = 1, and its derivatives
    of orders 1 to 4 vanish at u = 0 and u = 1.
    """
    return u**5 * (126 + u * (-420 + u * (540 + u * (-315 + 70 * u))))


def _positive(value: float, what: str) -> float:
    value = float(value)
    if not (np.isfinite(value) and value > 0):
        raise PkmError(f"{what} = {value:g} must be positive and finite")
    return value


@dataclass(frozen=True)
class Trajectory:
    """An end-effector motion x(t).

    Attributes
    ----------
    path : callable
        t -> x(t) for a float (returns shape (n_out,)), a numpy array of times (shape t.shape + (n_out,))
        or a casadi scalar (an n_out x 1 expression); built from arithmetic that CasADi differentiates.
    duration : float
        The time the motion lasts [s], from t = 0.
    dimension : int
        n_out, the number of end-effector coordinates.
    description : str
    """

    path: Callable[[Any], Any]
    duration: float
    dimension: int
    description: str

    @classmethod
    def point_to_point(cls, start: Any, end: Any, duration: float) -> Trajectory:
        """A straight rest-to-rest motion x = start + (end - start) s(t / duration).

        s is the degree-9 polynomial of :func:`rest_to_rest`: velocity, acceleration, jerk and snap
        vanish at both ends, so the motor torques of the flexible model (which need the fourth
        derivative of x) start and end continuously. The position holds outside [0, duration].
        """
        a = _vector(start, np.size(start), "start")
        b = _vector(end, a.size, "end")
        duration = _positive(duration, "duration")

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            s = rest_to_rest(ops.clip(t / duration))
            return ops.stack([float(a_k) + float(b_k - a_k) * s for a_k, b_k in zip(a, b, strict=True)])

        return cls(path, duration, a.size, f"rest-to-rest from {a.tolist()} to {b.tolist()} in {duration:g} s")

    @classmethod
    def trapezoidal(cls, start: Any, end: Any, v_max: float, a_max: float) -> Trajectory:
        """A straight move with a trapezoidal speed profile (Wu 2008 section 6.2, Table 3).

        Equal accelerating and decelerating times T0 = v_max / a_max at +-a_max, cruising at v_max in
        between; the total time T_f satisfies Wu's eq. 45, T0 = T_f - |x1 - x0| / v_max. A move too
        short to reach v_max is triangular (T0 = sqrt(|x1 - x0| / a_max)). The arc length is
        s(t) = a_max / 2 (r(t)^2 - r(t - T0)^2 - r(t - T_f + T0)^2 + r(t - T_f)^2), r(u) = max(u, 0);
        the acceleration jumps at the phase changes.
        """
        a = _vector(start, np.size(start), "start")
        b = _vector(end, a.size, "end")
        v_max = _positive(v_max, "v_max")
        a_max = _positive(a_max, "a_max")
        length = float(np.linalg.norm(b - a))
        if length == 0:
            raise PkmError("start and end of a trapezoidal move coincide")
        t0 = min(v_max / a_max, math.sqrt(length / a_max))
        total = length / (a_max * t0) + t0
        direction = (b - a) / length

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            r = ops.ramp
            s = a_max / 2 * (r(t) ** 2 - r(t - t0) ** 2 - r(t - total + t0) ** 2 + r(t - total) ** 2)
            return ops.stack([float(a_k) + float(e_k) * s for a_k, e_k in zip(a, direction, strict=True)])

        return cls(
            path,
            total,
            a.size,
            f"trapezoidal move from {a.tolist()} to {b.tolist()}: v_max {v_max:g}, a_max {a_max:g}, "
            f"T0 {t0:.4g} s, T_f {total:.4g} s",
        )

    @classmethod
    def circle(cls, centre: Any, radius: float, period: float, turns: float = 1.0) -> Trajectory:
        """A planar circle at constant speed, x = centre + radius (cos w t, sin w t) with w = 2 pi / period.

        It starts at centre + (radius, 0) and lasts ``turns`` periods; the motion continues outside
        [0, duration] (it has no rest at its ends).
        """
        c = _vector(centre, 2, "centre")
        radius = _positive(radius, "radius")
        period = _positive(period, "period")
        turns = _positive(turns, "turns")
        omega = 2 * np.pi / period

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            angle = omega * t
            return ops.stack([c[0] + radius * ops.cos(angle), c[1] + radius * ops.sin(angle)])

        return cls(path, turns * period, 2, f"circle about {c.tolist()}, radius {radius:g}, period {period:g} s")

    def position(self, t: Any) -> Any:
        """x(t) for a float, a numpy array of times or a casadi scalar (see :attr:`path`)."""
        return self.path(t)

    @cached_property
    def _derivatives(self) -> ca.Function:
        t = ca.SX.sym("t")
        x = self.path(t)
        x_dot = ca.jacobian(x, t)
        return ca.Function("trajectory", [t], [x, x_dot, ca.jacobian(x_dot, t)], ["t"], ["x", "x_dot", "x_ddot"])

    def sample(self, times: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration, each (N, n_out), at the times (N,), by CasADi's AD."""
        t = _times(times, increasing=False)
        return tuple(v[:, :, 0] for v in evaluate(self._derivatives, t[:, None]))


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
    mech: Mechanism, trajectory: Trajectory, times: Any, design: DesignLike = None, *, mode: str | None = None
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
    mech : Mechanism
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
    ik, elastic = _function(mech, "inverse_kinematics"), _elastic_dynamics(mech)
    t_samples = _times(times, increasing=False)
    d = ca.DM(mech._design_vector(design))
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


def _matching_assembly(mech: Mechanism, theta_a: np.ndarray, x: np.ndarray, d: np.ndarray) -> str:
    """The assembly mode whose forward kinematics of theta_a gives back x at every sample."""
    fk = _function(mech, "forward_kinematics")
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


@dataclass(frozen=True)
class Simulation:
    """A motion of the flexible-joint model (eq. 31) sampled at the output times.

    Attributes
    ----------
    t : numpy.ndarray, shape (N,)
    z, z_dot : numpy.ndarray, shape (N, 2 n_act)
        (theta_a, theta_m) and their rates.
    x : numpy.ndarray, shape (N, n_out)
        End-effector positions by forward kinematics of theta_a.
    assembly : str
        The assembly mode of the forward kinematics.
    """

    t: np.ndarray
    z: np.ndarray
    z_dot: np.ndarray
    x: np.ndarray
    assembly: str


def simulate(
    mech: Mechanism,
    design: DesignLike = None,
    *,
    z0: Any,
    z_dot0: Any,
    times: Any,
    torque: Callable[[ca.SX], ca.SX] | None = None,
    assembly: str | None = None,
    method: str = "adams",
    rtol: float = 1e-10,
    atol: float = 1e-12,
) -> Simulation:
    """Forward dynamics of the flexible-joint model, M_T z_ddot + C_T z_dot + f_t + K_T z = u (eq. 31).

    The state (theta_a, theta_m, theta_a_dot, theta_m_dot) is integrated by CVODES (variable step and
    order) through CasADi from ``times[0]``; the passive joints and the end effector come from the
    generated forward kinematics of theta_a in the assembly mode, inside the ODE.

    Parameters
    ----------
    mech : Mechanism
    design : design-like, optional
    z0, z_dot0 : array_like, shape (2 n_act,)
        Initial (theta_a, theta_m) [rad] and their rates [rad/s].
    times : array_like, shape (N,)
        Strictly increasing output times [s]; the first is the initial time.
    torque : callable, optional
        t -> tau_m(t), a casadi SX scalar to an SX n_act-vector of motor torques, such as
        :attr:`FlexibleMotion.torque`; zero torques when None.
    assembly : str, optional
        Assembly mode; the mechanism's first by default.
    method : {"adams", "bdf"}
        CVODES' linear multistep method. Adams-Moulton suits the undamped oscillations of eq. 31 (on
        the five-bar it conserves energy some 20 times better than BDF at the same tolerances, in a
        third of the steps); BDF suits transmissions much stiffer than the motion is fast.
    rtol, atol : float
        Relative and absolute tolerances of CVODES.

    Returns
    -------
    Simulation

    Raises
    ------
    PoseError
        If theta_a of ``z0`` cannot be assembled.
    ComputationError
        If CVODES fails (with its flag) or the motion leaves the assembled configurations.
    """
    if method not in METHODS:
        raise UnknownNameError("integration method", method, METHODS)
    fk, elastic = _function(mech, "forward_kinematics"), _elastic_dynamics(mech)
    n = mech.n_act
    z0 = _vector(z0, 2 * n, "z0")
    z_dot0 = _vector(z_dot0, 2 * n, "z_dot0")
    t_out = _times(times, increasing=True)
    rtol, atol = _positive(rtol, "rtol"), _positive(atol, "atol")
    d = mech._design_vector(design)
    branch = mech.assembly_mode(assembly)
    signs = np.array(branch.signs)
    if not evaluate(fk, z0[:n], signs, d)[2].min() >= -REACH_TOLERANCE:
        raise PoseError(f"theta_a = {z0[:n].tolist()} of z0 cannot be assembled by the {mech.name}")

    t = ca.SX.sym("t")
    state = ca.SX.sym("state", 4 * n)
    z, z_dot = state[: 2 * n], state[2 * n :]
    x, q, _ = fk(z[:n], ca.DM(signs), ca.DM(d))
    M_T, C_T, K_T, f_t = elastic(q, x, z_dot, ca.DM(d))
    u = ca.vertcat(ca.DM.zeros(n), ca.DM.zeros(n) if torque is None else _torque_expression(torque, t, n))
    rhs = ca.vertcat(z_dot, ca.solve(M_T, u - C_T @ z_dot - f_t - K_T @ z))
    options = {
        "reltol": rtol,
        "abstol": atol,
        "linear_multistep_method": method,
        "disable_internal_warnings": True,
    }
    try:
        integrator = ca.integrator(
            f"{mech.name}_simulate", "cvodes", {"x": state, "t": t, "ode": rhs}, t_out[0], t_out.tolist(), options
        )
        states = np.asarray(integrator(x0=np.concatenate([z0, z_dot0]))["xf"]).T
    except RuntimeError as error:
        flag = re.search(r'returned "(\w+)"', str(error))
        reason = flag.group(1) if flag else str(error).strip().splitlines()[-1]
        raise ComputationError(
            f"CVODES failed ({reason}) integrating the {mech.name} from t = {t_out[0]:g} to {t_out[-1]:g} s "
            "(a parallel singularity on the way, or a torque too stiff for the tolerances)"
        ) from None
    x_out, _, margins = evaluate(fk, states[:, :n], signs, d)
    off = ~(margins.min(axis=(1, 2)) >= -REACH_TOLERANCE)
    if off.any():
        raise ComputationError(
            f"the {mech.name} cannot be assembled in mode {branch.name} at t = {t_out[np.flatnonzero(off)[0]]:g} s"
        )
    return Simulation(t_out, states[:, : 2 * n], states[:, 2 * n :], x_out[:, :, 0], branch.name)


def _torque_expression(torque: Callable[[ca.SX], ca.SX], t: ca.SX, n: int) -> ca.SX:
    value = torque(t)
    if not isinstance(value, ca.SX):
        raise PkmError(f"torque(t) must return a casadi SX expression for an SX time; got {type(value).__name__}")
    if value.numel() != n:
        raise PkmError(f"torque(t) must give {n} motor torques; got shape {value.shape}")
    return ca.reshape(value, n, 1)


def energy(
    mech: Mechanism, z: Any, z_dot: Any, design: DesignLike = None, *, assembly: str | None = None
) -> np.ndarray | float:
    """Total mechanical energy of the flexible-joint model along a motion.

    E = 1/2 z_dot^T M_T z_dot + 1/2 z^T K_T z
      = 1/2 theta_a_dot^T M_t theta_a_dot + 1/2 theta_m_dot^T J_m theta_m_dot
        + 1/2 (theta_a - theta_m)^T K (theta_a - theta_m)        (eqs. 16-18, 23).

    Parameters
    ----------
    mech : Mechanism
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
    fk, elastic = _function(mech, "forward_kinematics"), _elastic_dynamics(mech)
    n = mech.n_act
    z, single = mech._batch(z, 2 * n, "z")
    z_dot, single_dot = mech._batch(z_dot, 2 * n, "z_dot")
    if len(z) != len(z_dot):
        raise PoseError(f"z has {len(z)} rows and z_dot {len(z_dot)}")
    d = mech._design_vector(design)
    x, q, margins = evaluate(fk, z[:, :n], np.array(mech.assembly_mode(assembly).signs), d)
    M_T, _, K_T, _ = evaluate(elastic, q[:, :, 0], x[:, :, 0], z_dot, d)
    total = 0.5 * np.einsum("ni,nij,nj->n", z_dot, M_T, z_dot) + 0.5 * np.einsum("ni,nij,nj->n", z, K_T, z)
    total[margins.min(axis=(1, 2)) < -REACH_TOLERANCE] = np.nan
    out = mech._unbatch(total, single and single_dot)
    return float(out) if np.ndim(out) == 0 else out
