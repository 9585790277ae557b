"""The Cartesian stiffness of a mechanism and the platform's deflection under a load (:meth:`pkm.Mechanism.stiffness`,
:meth:`pkm.Mechanism.deflection`), where its model has elastic elements: a described machine whose legs state
them (its ``stiffness`` function, :mod:`pkm.spec.stiffness`).

K is in the pose's twist coordinates: a point pose's translation; else the translation and the small rotation
(the platform angle in the plane, the rotation vector about the base's axes in space). Its blocks are in N/m
(translation), N/rad (coupling) and N m/rad (rotation); a wrench is the force [N] and, where the platform turns,
the moment [N m] about the pose's origin, in the base frame."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError
from pkm.kinematics import as_batch, unbatch

if TYPE_CHECKING:
    from pkm.kinematics import DesignLike, KinematicModel


def stiffness(mech: KinematicModel, pose: Any, design: DesignLike = None, *, mode: str | None = None,
              actuators_only: bool = False) -> np.ndarray:
    """The Cartesian stiffness matrices K (N, n, n) or (n, n) at the poses in the working mode, n the pose's
    coordinates; with ``actuators_only`` the drives' alone (the links rigid: J^T diag(k) J); NaN where the pose
    is out of reach."""
    fn = mech.functions.get("stiffness")
    if fn is None:
        raise PkmError(f"the {mech.name} has no elastic elements (a description states them per leg: elastic = "
                       "{material, section, drive}), so no stiffness")
    x, single = as_batch(pose, mech.n_out, "pose", finite=False)
    d = mech.design_vector(design)
    q = mech.inverse_kinematics(x, d, mode=mode, passive=True)
    K, K_drives, _ = evaluate(fn, q, x, d)
    return unbatch(K_drives if actuators_only else K, single)


def deflection(mech: KinematicModel, pose: Any, wrench: Any, design: DesignLike = None, *, mode: str | None = None,
               actuators_only: bool = False) -> np.ndarray:
    """The platform's displacement K^-1 w (N, n) or (n,) under the wrench w (n,) or (N, n) at each pose, in the
    pose's twist coordinates [m, rad]; NaN where the pose is out of reach or K singular (a mechanism free to move
    under the load)."""
    K = stiffness(mech, np.atleast_2d(pose), design, mode=mode, actuators_only=actuators_only)
    w, _ = as_batch(wrench, mech.n_out, "wrench")
    if len(w) not in (1, len(K)) and len(K) != 1:
        raise PkmError(f"wrench violates: one wrench or one per pose ({len(K)}); got {len(w)}")
    single = np.ndim(pose) == 1 and np.ndim(wrench) == 1
    n = max(len(K), len(w))
    K, w = np.broadcast_to(K, (n, *K.shape[1:])), np.broadcast_to(w, (n, w.shape[1]))
    stiff = np.all(np.isfinite(K), axis=(1, 2)) & (np.abs(np.linalg.det(np.where(np.isfinite(K), K, 0))) > 0)
    out = np.full((n, K.shape[-1]), np.nan)
    out[stiff] = np.linalg.solve(K[stiff], w[stiff][..., None])[..., 0]
    return unbatch(out, single)


def stiffness_units(mech: KinematicModel) -> list[list[str]]:
    """The unit of each entry of K: N/m between two translations, N/rad between a translation and a rotation,
    N m/rad between two rotations."""
    units = {("m", "m"): "N/m", ("m", "rad"): "N/rad", ("rad", "m"): "N/rad", ("rad", "rad"): "N m/rad"}
    return [[units[a, b] for b in mech.pose_units] for a in mech.pose_units]
