"""Export a design as an Extended URDF: the mechanism cut open into a tree (``robot.urdf``) and its loop
closures and motors (``robot.yaml``, Gepetto's format, which Pinocchio's closed-loop loaders read), with a
README of what was cut and why.

A mechanism knows its structure through its ``structure`` function ``(mechanism, reference) ->``
:class:`~pkm.export.structure.Structure` (the hand-derived ones in their package), or, for a described
machine, through its description's legs (:mod:`pkm.export.legs`).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from pkm.errors import PkmError, PoseError, SingularityError
from pkm.export.structure import Reference, Structure, Tree, cut
from pkm.export.urdf import write

__all__ = ["Reference", "Structure", "Tree", "export_urdf", "linkage", "structure", "tree"]


def _builder(mech: Any) -> Callable[[Any, Reference], Structure]:
    if mech.structure is not None:
        return mech.structure
    if getattr(mech, "description", None) is not None:
        from pkm.export.legs import structure as described

        return described
    raise PkmError(f"mechanism {mech.name} violates: a mechanism whose structure (links, joints, axes) pkm knows, "
                   "to be exported")


def structure(mech: Any, design: Any = None, *, pose: Any = None, mode: str | None = None) -> Structure:
    """The mechanism's structure at a design, with the reference configuration at ``pose`` in working mode
    ``mode`` (the mechanism's own reference pose and first mode by default)."""
    return _builder(mech)(mech, design, pose, mode)


def tree(mech: Any, design: Any = None, *, pose: Any = None, mode: str | None = None) -> Tree:
    """The structure cut into a tree (:func:`pkm.export.structure.cut`)."""
    return cut(structure(mech, design, pose=pose, mode=mode), mech.actuator_names)


def export_urdf(mech: Any, design: Any, folder: str | Path, *, pose: Any = None, mode: str | None = None) -> Path:
    """Write the Extended URDF of a design into ``folder``: ``robot.urdf``, ``robot.yaml`` and ``README.md``.

    The reference configuration (where every joint of the URDF is zero and every loop closes) is ``pose`` in
    working mode ``mode`` (by default the mechanism's reference pose and its first working mode). Raises
    :class:`~pkm.errors.PkmError` for a mechanism whose structure pkm does not know, a design outside its
    bounds, a pose out of reach or singular (where the loops' closure is not unique, a multibody tool may close
    them on another assembly) or a folder that cannot be written. Returns the folder.
    """
    cut_tree = tree(mech, design, pose=pose, mode=mode)
    ref = cut_tree.structure.reference
    note = mech.singularity_note(ref.pose, ref.design, mode=ref.mode)
    if note:
        raise SingularityError(f"the export's reference {note}: give another pose")
    parameters = [(p.name, cut_tree.structure.reference.design[p.name], p.unit, p.doc) for p in mech.parameters]
    return write(cut_tree, mech, parameters, Path(folder))


def linkage(mech: Any, pose: Any, design: Any = None, *, mode: str | None = None) -> list[np.ndarray]:
    """The joints' points of each chain of a mechanism that pkm knows the structure of, at one pose, for
    drawing (:meth:`pkm.Mechanism.linkage` where the mechanism has no generated skeleton): from each joint on the
    base, the joints along its chain (a mimic joint's branch left out) up to the end effector's link, where the
    end effector's origin closes the chain; points (k, 3) in the base frame. Empty where the pose is out of
    reach."""
    try:
        built = structure(mech, design, pose=pose, mode=mode)
    except PoseError:
        return []
    incident: dict[str, list[Any]] = {}
    for joint in built.joints:
        if joint.mimic is None:
            incident.setdefault(joint.parent, []).append(joint)
            incident.setdefault(joint.child, []).append(joint)
    end = built.effector.frame(np.asarray(built.reference.pose, dtype=float))[:3, 3]
    chains = []
    for first in [j for j in incident.get(built.base, []) if j.parent == built.base]:
        points, used, link = [first.origin], {first.name}, first.child
        while link != built.base:
            if link == built.effector.link:
                if not np.allclose(points[-1], end):
                    points.append(end)
                break
            following = [j for j in incident.get(link, []) if j.name not in used]
            if not following:
                break
            joint = following[0]
            points.append(joint.origin)
            used.add(joint.name)
            link = joint.child if joint.parent == link else joint.parent
        chains.append(np.array(points, dtype=float))
    return chains
