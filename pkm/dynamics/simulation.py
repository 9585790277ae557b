"""Forward dynamics of the flexible-joint model, M_T z_ddot + C_T z_dot + f_t + K_T z = u (Lara-Molina
2016 eq. 31, see :mod:`pkm.dynamics.flexible`), integrated by CVODES through CasADi.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate
from pkm.dynamics.flexible import elastic_dynamics
from pkm.dynamics.trajectories import as_positive, as_times, as_vector
from pkm.errors import ComputationError, PkmError, PoseError, UnknownNameError, check_name

if TYPE_CHECKING:
    from pkm.kinematics import DesignLike, KinematicModel

METHODS = ("adams", "bdf")


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
    mech: KinematicModel,
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
    mech : KinematicModel
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
        a planar 5R it conserves energy some 20 times better than BDF at the same tolerances, in a
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
    if check_name("integration method", method, METHODS) not in METHODS:
        raise UnknownNameError("integration method", method, METHODS)
    purpose = f"the simulation of the {mech.name}"
    fk, elastic = mech.functions.require("forward_kinematics", purpose), elastic_dynamics(mech, purpose)
    n = mech.n_act
    z0 = as_vector(z0, 2 * n, "z0")
    z_dot0 = as_vector(z_dot0, 2 * n, "z_dot0")
    t_out = as_times(times, increasing=True)
    rtol, atol = as_positive(rtol, "rtol"), as_positive(atol, "atol")
    d = mech.design_vector(design)
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
    if not callable(torque):
        raise PkmError(f"torque = {torque!r} violates: a function t -> {n} motor torques (a casadi SX scalar to "
                       "an SX vector, such as FlexibleMotion.torque), or None for zero torques")
    value = torque(t)
    if not isinstance(value, ca.SX):
        raise PkmError(f"torque(t) must return a casadi SX expression for an SX time; got {type(value).__name__}")
    if value.numel() != n:
        raise PkmError(f"torque(t) must give {n} motor torques; got shape {value.shape}")
    return ca.reshape(value, n, 1)
