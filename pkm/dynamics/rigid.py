"""Rigid-body dynamics: inertia matrices and inverse dynamics with rigid transmissions.

Generic over the mechanisms whose generated module emits dynamic functions beside the kinematic ones:

* ``inertia(q, x, design) -> (M_t, M_w, ...)``, with ``S_e`` for a flexible-joint model and ``M_d``
  for a virtual-work model;
* ``inverse_dynamics(q, x, x_dot, x_ddot, design) -> tau``, a rigid model by virtual work (Wu 2008
  eq. 41, see ``symbolic/virtual_work.py``), fused with the inverse kinematics into one function of the
  pose (:func:`inverse_dynamics_pipeline`; from ``inverse_dynamics_from_pose`` where the mechanism has
  it, without trigonometric calls); or otherwise the Lagrange chain functions
  (see ``symbolic/lagrange.py``): ``second_order(q, x, x_dot, design) -> (q_dot, q_ddot_bias)`` and the
  flexible-joint model ``elastic_dynamics`` (eq. 31 of Lara-Molina 2016, see :mod:`pkm.dynamics.flexible`)
  with the rotors moving with the actuated joints.
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate
from pkm.dynamics.flexible import elastic_dynamics
from pkm.errors import PkmError, PoseError, UnknownNameError, check_name
from pkm.kinematics import as_batch, from_pose, solve_joints, unbatch

if TYPE_CHECKING:
    from pkm.kinematics import DesignLike, KinematicModel

SPACES = {"task": "M_w", "actuated": "M_t", "mixed": "M_d"}


def inertia_matrix(
    mech: KinematicModel, pose: Any, design: DesignLike = None, *, mode: str | None = None, space: str = "task"
) -> np.ndarray:
    """Inertia matrix of the mechanism at the poses (Lara-Molina 2016 eqs. 29, 35).

    Parameters
    ----------
    mech : KinematicModel
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
    if check_name("inertia space", space, list(SPACES)) not in SPACES:
        raise UnknownNameError("inertia space", space, list(SPACES))
    fn = mech.functions.require("inertia", f"the {space} inertia matrix of the {mech.name}")
    if SPACES[space] not in fn.name_out():
        raise PkmError(f"the {mech.name} model has no {space} inertia matrix ({SPACES[space]})")
    joints = solve_joints(mech, pose, design, mode)
    out = evaluate(fn, joints.q, joints.x, joints.design)[fn.name_out().index(SPACES[space])]
    out[~joints.reachable] = np.nan
    return joints.unbatch(out)


@lru_cache(maxsize=64)
def inverse_dynamics_pipeline(mech: KinematicModel) -> ca.Function:
    """``(x, x_dot, x_ddot, mode, design) -> (valid, tau)``: the rigid virtual-work model fused with the
    inverse kinematics into one SX graph.

    ``valid`` (1 x 1) is 1 where the pose is reached on the working mode's branch (every reach margin
    >= -``REACH_TOLERANCE``) and 0 elsewhere; ``tau`` (n_act x 1) is the generated
    ``inverse_dynamics(q, x, x_dot, x_ddot, design)`` at q = IK(x) (Wu 2008 eq. 41,
    tau = (J^T)^-1 (M x_ddot + n)), NaN where the pose is not reached. Where the mechanism has
    ``inverse_dynamics_from_pose`` the forces come from it, with no joint angle and no trigonometric call.
    """
    fns = mech.functions
    ik = fns["inverse_kinematics"]
    x, x_dot, x_ddot = (ca.SX.sym(name, mech.n_out) for name in ("x", "x_dot", "x_ddot"))
    mode = ca.SX.sym("mode", ik.numel_in(1))
    design = ca.SX.sym("design", ik.numel_in(2))
    twin = fns.get(from_pose("inverse_dynamics"))
    if twin is None:
        q, reach = ik(x, mode, design)
        (tau,) = fns["inverse_dynamics"].call([q, x, x_dot, x_ddot, design])
    else:
        out = dict(zip(twin.name_out(), twin.call([x, mode, x_dot, x_ddot, design]), strict=True))
        reach, tau = out["reach"], out["tau"]
    valid = ca.mmin(reach) >= -REACH_TOLERANCE
    return ca.Function(
        f"{mech.name}_inverse_dynamics_pipeline",
        [x, x_dot, x_ddot, mode, design],
        [valid, ca.if_else(valid, tau, ca.DM.nan(tau.shape))],
        ["x", "x_dot", "x_ddot", "mode", "design"],
        ["valid", "tau"],
    )


def _motion_batch(
    mech: KinematicModel, pose: Any, velocity: Any, acceleration: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Pose, velocity and acceleration as (N, n_out) arrays; 1-D inputs are shared by the batch (N is 1
    when every input is 1-D, and may be 0)."""
    arrays = [
        as_batch(v, mech.n_out, w) for v, w in ((pose, "pose"), (velocity, "velocity"), (acceleration, "acceleration"))
    ]
    rows = {len(a) for a, single in arrays if not single}
    n = rows.pop() if len(rows) == 1 else max(rows, default=1)
    for (a, single), what in zip(arrays, ("pose", "velocity", "acceleration"), strict=True):
        if len(a) != n and not single:
            raise PoseError(f"{what} has {len(a)} rows; the batch has {n}")
    full = [np.broadcast_to(a, (n, mech.n_out)) for a, _ in arrays]
    return *full, all(single for _, single in arrays)


def inverse_dynamics(
    mech: KinematicModel,
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
    mech : KinematicModel
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

    A mechanism with a rigid virtual-work model (``inverse_dynamics`` generated:
    tau = (J^T)^-1 M x_ddot + N, Wu 2008 eq. 41) uses it, in one pass of
    :func:`inverse_dynamics_pipeline` over the batch; it has no transmissions, so ``joint_torques``
    returns the same forces.
    """
    if "inverse_dynamics" in mech.functions:
        pose, x_dot, x_ddot, single = _motion_batch(mech, pose, velocity, acceleration)
        d = mech.design_vector(design)
        signs = np.array(mech.working_mode(mode).signs, dtype=float)
        _, tau = evaluate(inverse_dynamics_pipeline(mech), pose, x_dot, x_ddot, signs, d)
        return unbatch(tau[:, :, 0], single)
    purpose = f"the inverse dynamics of the {mech.name}"
    first, second, elastic = (
        mech.functions.require("first_order", purpose),
        mech.functions.require("second_order", purpose),
        elastic_dynamics(mech, purpose),
    )
    pose, x_dot, x_ddot, single = _motion_batch(mech, pose, velocity, acceleration)
    joints = solve_joints(mech, pose, design, mode)
    x, d, q = joints.x, joints.design, joints.q
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
        return unbatch(tau_a, single)
    tau_m = tau_a + np.einsum("nij,nj->ni", M_T[:, n:, n:], accel) + f_t[:, n:, 0]
    return unbatch(tau_m, single)
