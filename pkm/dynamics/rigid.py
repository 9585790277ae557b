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

from pkm.batch import REACH_TOLERANCE, evaluate_finite
from pkm.dynamics.flexible import elastic_dynamics
from pkm.errors import PkmError, PoseError, UnknownNameError, check_name
from pkm.kinematics import as_batch, closed, from_pose, nan_unless, require_finite, unbatch

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
    x, single = as_batch(pose, mech.n_out, "pose", finite=False)
    signs = np.array(mech.working_mode(mode).signs, dtype=float)
    (_, matrix), finite = evaluate_finite(inertia_pipeline(mech, SPACES[space]), x, signs, mech.design_vector(design))
    if not finite:
        require_finite(x, "pose")
    return unbatch(matrix, single)


@lru_cache(maxsize=64)
def inertia_pipeline(mech: KinematicModel, output: str) -> ca.Function:
    """``(x, mode, design) -> (valid, M)``: the inverse kinematics and the output ``output`` of the
    generated ``inertia`` in one SX graph (from ``inertia_from_pose`` where the mechanism has it), M NaN
    where the pose is not reached."""
    fns = mech.functions
    ik = fns["inverse_kinematics"]
    x = ca.SX.sym("x", mech.n_out)
    mode = ca.SX.sym("mode", ik.numel_in(1))
    design = ca.SX.sym("design", ik.numel_in(2))
    twin = fns.get(from_pose("inertia"))
    if twin is None:
        q, reach = ik(x, mode, design)
        out = dict(zip(fns["inertia"].name_out(), fns["inertia"].call([q, x, design]), strict=True))
    else:
        out = dict(zip(twin.name_out(), twin.call([x, mode, design]), strict=True))
        q, reach = out["q"], out["reach"]
    valid = closed(reach, q)
    return ca.Function(f"{mech.name}_{output}_pipeline", [x, mode, design], [valid, nan_unless(valid, out[output])],
                       ["x", "mode", "design"], ["valid", output])


@lru_cache(maxsize=64)
def inverse_dynamics_pipeline(mech: KinematicModel, joint_torques: bool = False) -> ca.Function:
    """``(x, x_dot, x_ddot, mode, design) -> (valid, tau)``: the rigid inverse dynamics fused with the
    inverse kinematics into one SX graph.

    ``valid`` (1 x 1) is 1 where the pose is reached on the working mode's branch (every reach margin
    >= -``REACH_TOLERANCE``) and 0 elsewhere; ``tau`` (n_act x 1) is NaN where the pose is not reached.
    A virtual-work model gives tau = (J^T)^-1 (M x_ddot + n) (Wu 2008 eq. 41), the generated
    ``inverse_dynamics(q, x, x_dot, x_ddot, design)`` at q = IK(x), or ``inverse_dynamics_from_pose``
    where the mechanism has it, with no joint angle and no trigonometric call. A Lagrange chain model
    gives the motor torques of :func:`inverse_dynamics` from ``first_order``, ``second_order`` and
    ``elastic_dynamics`` (with ``joint_torques``, the torques on the actuated joints).
    """
    fns = mech.functions
    ik = fns["inverse_kinematics"]
    x, x_dot, x_ddot = (ca.SX.sym(name, mech.n_out) for name in ("x", "x_dot", "x_ddot"))
    mode = ca.SX.sym("mode", ik.numel_in(1))
    design = ca.SX.sym("design", ik.numel_in(2))
    twin = fns.get(from_pose("inverse_dynamics"))
    if twin is not None:
        out = dict(zip(twin.name_out(), twin.call([x, mode, x_dot, x_ddot, design]), strict=True))
        reach, tau = out["reach"], out["tau"]
    elif "inverse_dynamics" in fns:
        q, reach = ik(x, mode, design)
        (tau,) = fns["inverse_dynamics"].call([q, x, x_dot, x_ddot, design])
    else:
        q, reach = ik(x, mode, design)
        tau = _chain_torques(mech, q, (x, x_dot, x_ddot), design, joint_torques=joint_torques)
    valid = ca.mmin(reach) >= -REACH_TOLERANCE
    return ca.Function(
        f"{mech.name}_inverse_dynamics_pipeline" + ("_joints" if joint_torques else ""),
        [x, x_dot, x_ddot, mode, design],
        [valid, nan_unless(valid, tau)],
        ["x", "x_dot", "x_ddot", "mode", "design"],
        ["valid", "tau"],
    )


def _chain_torques(mech: KinematicModel, q: ca.SX, motion: tuple[ca.SX, ca.SX, ca.SX], design: ca.SX, *,
                   joint_torques: bool) -> ca.SX:
    """The torques of a Lagrange chain model with rigid transmissions (:func:`inverse_dynamics`) at the
    joints q and the motion (x, x_dot, x_ddot)."""
    x, x_dot, x_ddot = motion
    purpose = f"the inverse dynamics of the {mech.name}"
    first = mech.functions.require("first_order", purpose)
    second = mech.functions.require("second_order", purpose)
    elastic = elastic_dynamics(mech, purpose)
    n = mech.n_act
    J = first.call([q, x, design])[0]
    q_dot, bias = second.call([q, x, x_dot, design])
    rate = q_dot[:n]
    accel = ca.mtimes(J, x_ddot) + bias[:n]
    M_T, C_T, _, f_t = elastic.call([q, x, ca.vertcat(rate, rate), design])
    tau_a = ca.mtimes(M_T[:n, :n], accel) + ca.mtimes(C_T[:n, :n], rate) + f_t[:n]
    if joint_torques:
        return tau_a
    return tau_a + ca.mtimes(M_T[n:, n:], accel) + f_t[n:]


MOTION = ("pose", "velocity", "acceleration")


def _motion_batch(
    mech: KinematicModel, pose: Any, velocity: Any, acceleration: Any
) -> tuple[list[np.ndarray], bool]:
    """Pose, velocity and acceleration as (N, n_out) arrays, or (n_out,) where one is shared by the batch
    (the pose stays (N, n_out), N = 1 when every input is 1-D, and may be 0), and whether every input was
    one row. The inputs given per pose are checked for non-finite values after the kernel has read them
    (:func:`_require_finite_motion`), the shared ones here."""
    arrays = [as_batch(v, mech.n_out, w, finite=False) for v, w in zip((pose, velocity, acceleration), MOTION,
                                                                         strict=True)]
    rows = {len(a) for a, single in arrays if not single}
    n = rows.pop() if len(rows) == 1 else max(rows, default=1)
    for (a, single), what in zip(arrays, MOTION, strict=True):
        if len(a) != n and not single:
            raise PoseError(f"{what} has {len(a)} rows; the batch has {n}")
        if single:
            require_finite(a, what)
    motion = [np.broadcast_to(a, (n, mech.n_out)) if k == 0 and single else a[0] if single else a
              for k, (a, single) in enumerate(arrays)]
    return motion, all(single for _, single in arrays)


def _require_finite_motion(motion: list[np.ndarray]) -> None:
    for values, what in zip(motion, MOTION, strict=True):
        require_finite(values, what)


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
    motion, single = _motion_batch(mech, pose, velocity, acceleration)
    d = mech.design_vector(design)
    signs = np.array(mech.working_mode(mode).signs, dtype=float)
    chain = "inverse_dynamics" not in mech.functions and from_pose("inverse_dynamics") not in mech.functions
    fused = inverse_dynamics_pipeline(mech, joint_torques and chain)
    (_, tau), finite = evaluate_finite(fused, *motion, signs, d)
    if not finite:
        _require_finite_motion(motion)
    return unbatch(tau[:, :, 0], single)
