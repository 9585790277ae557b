"""Every assembly at a mechanism's actuated joints, each with the working mode that draws it, and the figure of
their linkages: what ``pkm fk``, ``pkm show`` and the explorer draw (:mod:`pkm.assemblies` finds them).

An assembly's linkage is drawn in the working mode whose inverse kinematics gives the joints back at its pose
(to :data:`SAME_JOINTS`, angles wrapped); an assembly in no working mode has no drawing.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pkm.errors import PkmError
from pkm.units import Units

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from pkm.assemblies import Assemblies
    from pkm.mechanism import Mechanism

SAME_JOINTS = 1e-8  # a working mode whose inverse kinematics gives the joints back to this is the assembly's


def working_modes(m: Mechanism, poses: np.ndarray, q_a: np.ndarray, design: Any) -> list[str | None]:
    """For each of ``poses`` (S, n_out), the first working mode whose inverse kinematics gives ``q_a`` (n_act,)
    back there, None where none does."""
    poses = np.asarray(poses, dtype=float).reshape(-1, m.n_out)
    angles = np.array([u == "rad" for u in m.actuator_units])
    tolerance = SAME_JOINTS * max(1.0, float(np.abs(q_a).max()))
    chosen: list[str | None] = [None] * len(poses)
    for mode in m.modes:
        if all(c is not None for c in chosen):
            break
        gap = m.inverse_kinematics(poses, design, mode=mode, limits=False).reshape(len(poses), -1) - q_a
        gap[:, angles] = np.angle(np.exp(1j * gap[:, angles]))
        for k in np.flatnonzero(np.all(np.abs(gap) <= tolerance, axis=1)):
            chosen[k] = chosen[k] or mode
    return chosen


@dataclass(frozen=True)
class AssembliesAtPose:
    """Every assembly at the actuated joints ``joints`` a pose has in working mode ``mode``: ``found`` (None
    where they cannot be listed, ``reason`` saying why), each assembly's pose (``found.poses[0]`` up to its
    count), working mode (``modes``) and linkage (``legs``, empty where it has no drawing), and ``current`` the
    assembly that is the pose itself."""

    mode: str
    joints: np.ndarray
    found: Assemblies | None
    reason: str | None = None
    modes: list[str | None] = field(default_factory=list)
    legs: list[list[np.ndarray]] = field(default_factory=list)
    current: int | None = None

    @property
    def poses(self) -> np.ndarray:
        """The assemblies' poses, (count, n_out)."""
        return np.zeros((0, 0)) if self.found is None else self.found.poses[0, : self.found.counts[0]]

    def summary(self, m: Mechanism, units: Units | None = None) -> dict[str, Any]:
        """The count, bound, failed paths (with what ``failures`` means) and method, the joints and each
        assembly's pose and working mode, in ``units`` (SI by default); null counts and the reason where the
        assemblies cannot be listed."""
        units = units or Units()
        out: dict[str, Any] = {
            "mode": self.mode,
            "joints": dict(zip(m.actuator_names, units.from_si(self.joints, m.actuator_units).tolist(), strict=True)),
            "count": None, "bound": None, "failed": None, "failures": None, "method": None, "reason": self.reason,
            "current": self.current, "assemblies": []}
        if self.found is None:
            return out
        rows = [{"pose": dict(zip(m.pose_names, units.from_si(pose, m.pose_units).tolist(), strict=True)),
                 "mode": mode} for pose, mode in zip(self.poses, self.modes, strict=True)]
        return {**out, "count": int(self.found.counts[0]), "bound": self.found.bound,
                "failed": int(self.found.failed[0]), "failures": self.found.failures, "method": self.found.method,
                "assemblies": rows}

    def text(self) -> str:
        """One line: how many real assemblies there are at the joints, or why they cannot be listed."""
        if self.found is None:
            return f"every assembly at the joints of the linkage's pose (mode {self.mode}): {self.reason}"
        failed = int(self.found.failed[0])
        return (f"{int(self.found.counts[0])} real assemblies at the joints of the linkage's pose (mode {self.mode}; "
                f"at most {self.found.bound}; {self.found.method})"
                + (f"; {failed} {self.found.failures}" if failed else ""))


def assemblies_at_pose(m: Mechanism, pose: Any, design: Any, *, mode: str) -> AssembliesAtPose:
    """Every assembly at the actuated joints of ``pose`` in working mode ``mode``, each with its working mode
    and linkage; where the pose is out of reach in ``mode`` or pkm cannot list the mechanism's assemblies
    (:meth:`pkm.Mechanism.every_assembly` refuses it), none, and the reason."""
    pose = np.asarray(pose, dtype=float)
    joints = m.inverse_kinematics(pose, design, mode=mode)
    if not np.all(np.isfinite(joints)):
        return AssembliesAtPose(mode, joints, None, f"the pose is out of reach in mode {mode}")
    try:
        found = m.every_assembly(joints, design)
    except PkmError as exc:
        return AssembliesAtPose(mode, joints, None, f"not listed ({exc})")
    poses = found.poses[0, : found.counts[0]]
    modes = working_modes(m, poses, joints, design)
    legs = [m.linkage(p, design, mode=k) if k is not None else [] for p, k in zip(poses, modes, strict=True)]
    angles = np.array([u == "rad" for u in m.pose_units])
    gap = poses - pose
    gap[:, angles] = np.angle(np.exp(1j * gap[:, angles]))
    current = int(np.argmin(np.abs(gap).max(axis=1))) if len(poses) else None
    return AssembliesAtPose(mode, joints, found, None, modes, legs, current)


def assemblies_figure(m: Mechanism, design: Any, poses: np.ndarray, modes: list[str | None]) -> Figure:
    """One panel per assembly of ``poses`` (S, n_out) in its working mode of ``modes``: each leg's joints joined
    from the base, the platform's joints joined; in the plane of the linkage, or seen from the side (across the
    first and the third coordinate) where the points span three. A panel is empty where its mode is None."""
    from matplotlib.ticker import MaxNLocator

    from pkm.figures import figure

    fig = figure(3.2 * max(len(poses), 1), 3.4)
    for k, (pose, mode) in enumerate(zip(poses, modes, strict=True), 1):
        ax = fig.add_subplot(1, max(len(poses), 1), k)
        legs = m.linkage(pose, design, mode=mode) if mode is not None else []
        across = (0, 2) if legs and legs[0].shape[1] == 3 and np.ptp(np.concatenate(legs)[:, 2]) > 0 else (0, 1)
        for points in legs:
            ax.plot(points[:, across[0]], points[:, across[1]], "o-", color="C0", lw=1.5, ms=3)
        ends = np.array([points[-1, list(across)] for points in legs]) if legs else np.zeros((0, 2))
        if len(ends) > 2:
            ax.fill(ends[:, 0], ends[:, 1], color="C1", alpha=0.4)
        ax.set_aspect("equal")
        ax.set_title(f"assembly {k}: {mode or 'no working mode'}", fontsize=8)
        names = ("x", "z") if across == (0, 2) else m.pose_names[:2]
        ax.set_xlabel(f"{names[0]} [m]", fontsize=8)
        ax.set_ylabel(f"{names[1]} [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.xaxis.set_major_locator(MaxNLocator(4))
    return fig
