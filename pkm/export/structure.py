"""A mechanism's kinematic structure as data, and the tree it is cut into for a URDF.

A :class:`Structure` is what a mechanism's structure function builds at a design and a reference
configuration (a pose in a working mode, :class:`Reference`): its links with their inertial data where the
mechanism has bodies, its joints (R, P, U, S, fixed, or free for a platform that floats) with their
points and axes in the base frame, which of them are actuated, mimic couplings and limits, and the frame of
its end effector with the map from a pose to that frame's placement. Everything is in the base frame, SI,
at the reference configuration: a structure is written as the mechanism is drawn.

:func:`cut` turns it into a tree: joints are taken in their order, and a joint whose child link is already
in the tree closes a loop. That joint is cut: a spherical one becomes a point contact (a 3D closure between
a frame on each side at its centre); any other stays in the tree as a joint from its parent to a massless
link (frame A), welded (a 6D closure) to a frame on its child at the same placement (frame B). Every joint's
value is zero at the reference configuration, which therefore closes every loop.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pkm.errors import PoseError


@dataclass(frozen=True)
class AsUrdf:
    """How a joint of a structure becomes URDF: the URDF type of each of its axes (``limited`` for a joint of one
    axis with stated limits), the axes themselves where they are not the joint's own, and how a cut of it closes
    (the closure's contact, 3d or 6d, and whether frame A stays on the joint's axes in the tree or at its origin)."""

    urdf: str
    limited: str
    axes: tuple[tuple[float, float, float], ...] | None
    contact: str
    kept: bool


# the one table of the joint types a structure holds and the URDF joints each becomes
URDF_JOINTS = {
    "R": AsUrdf("continuous", "revolute", None, "6d", kept=True),  # revolute
    "P": AsUrdf("prismatic", "prismatic", None, "6d", kept=True),  # prismatic
    "U": AsUrdf("continuous", "continuous", None, "6d", kept=True),  # universal: two revolutes
    "S": AsUrdf("continuous", "continuous", ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), "3d",
                kept=False),  # spherical: three revolutes in the tree, a point contact where cut
    "fixed": AsUrdf("fixed", "fixed", (), "6d", kept=False),  # rigid
    "free": AsUrdf("floating", "floating", (), "6d", kept=False),  # floating
}
PARALLEL = 1e-9  # a hint direction within this sine of a joint's axis is not used to orient its frame


def unit(vector: np.ndarray) -> np.ndarray:
    v = np.asarray(vector, dtype=float)
    return v / np.linalg.norm(v)


def frame_with_axis(axis: np.ndarray, hint: np.ndarray | None = None) -> np.ndarray:
    """A rotation whose z column is ``axis`` and whose x column is ``hint`` made perpendicular to it (the
    base's x, or y where x is along the axis, without a hint)."""
    z = unit(axis)
    for candidate in (hint, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        if candidate is None:
            continue
        x = np.asarray(candidate, dtype=float) - z * (z @ candidate)
        if np.linalg.norm(x) > PARALLEL * np.linalg.norm(candidate):
            x = unit(x)
            return np.column_stack([x, np.cross(z, x), z])
    raise AssertionError("unreachable: x and y cannot both be along one axis")


def placement(rotation: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """The 4 x 4 homogeneous transform of a rotation and an origin."""
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = origin
    return out


def inverse(transform: np.ndarray) -> np.ndarray:
    rotation, origin = transform[:3, :3], transform[:3, 3]
    return placement(rotation.T, -rotation.T @ origin)


@dataclass(frozen=True)
class Inertial:
    """A body's mass [kg], centre of mass [m] and inertia tensor about it [kg m^2], in the base frame."""

    mass: float
    centre: np.ndarray
    tensor: np.ndarray

    @classmethod
    def point(cls, mass: float, at: np.ndarray) -> Inertial:
        return cls(float(mass), np.asarray(at, dtype=float), np.zeros((3, 3)))

    @classmethod
    def bar(cls, mass: float, centre: np.ndarray, moment: float, direction: np.ndarray) -> Inertial:
        """A slender body along ``direction``: ``moment`` about every axis across it through its centre, none
        about its own axis."""
        u = unit(direction)
        return cls(float(mass), np.asarray(centre, dtype=float), float(moment) * (np.eye(3) - np.outer(u, u)))

    @classmethod
    def lamina(cls, mass: float, centre: np.ndarray, moment: float, normal: np.ndarray) -> Inertial:
        """A flat body across ``normal`` (a disc): ``moment`` about the normal, half of it about the axes in
        its plane."""
        n = unit(normal)
        return cls(float(mass), np.asarray(centre, dtype=float),
                   float(moment) * (np.outer(n, n) + (np.eye(3) - np.outer(n, n)) / 2))

    @classmethod
    def principal(cls, mass: float, centre: np.ndarray, moments: np.ndarray, axes: np.ndarray) -> Inertial:
        """Principal ``moments`` about the columns of the rotation ``axes``."""
        return cls(float(mass), np.asarray(centre, dtype=float), axes @ np.diag(moments) @ axes.T)

    def __add__(self, other: Inertial) -> Inertial:
        mass = self.mass + other.mass
        centre = (self.mass * self.centre + other.mass * other.centre) / mass if mass > 0 else self.centre
        tensor = np.zeros((3, 3))
        for part in (self, other):
            d = part.centre - centre
            tensor += part.tensor + part.mass * (d @ d * np.eye(3) - np.outer(d, d))
        return Inertial(mass, centre, tensor)


def combined(parts: list[Inertial]) -> Inertial | None:
    """The sum of inertial parts; None for none."""
    out = None
    for part in parts:
        out = part if out is None else out + part
    return out


@dataclass(frozen=True)
class Link:
    name: str
    doc: str
    inertial: Inertial | None = None


@dataclass(frozen=True)
class Joint:
    """A joint from ``parent`` to ``child`` at ``origin`` (base frame, reference configuration).

    ``axes``: one unit vector for R and P, two for U (the first fixed in the parent, the second in the
    child), none for S, fixed and free. ``actuator``: pkm's name of the actuated joint it is; ``value`` pkm's
    value of its coordinate at the reference configuration (the URDF's zero); ``limits`` its range in
    pkm's coordinate; ``mimic``: (joint, multiplier), its displacement that of the other joint times the
    multiplier; ``along``: the direction the x axis of its child's frame takes (the link's length)."""

    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray
    axes: tuple[np.ndarray, ...] = ()
    doc: str = ""
    actuator: str | None = None
    value: float = 0.0
    limits: tuple[float, float] | None = None
    mimic: tuple[str, float] | None = None
    along: np.ndarray | None = None


@dataclass(frozen=True)
class Effector:
    """The end effector: a frame fixed on ``link``, its placement in the base frame at a pose
    (``frame(pose) -> 4 x 4``), whether the pose fixes its orientation (``oriented``; else only its origin),
    and ``rates(pose) -> (6, n)``: its twist (linear velocity of its origin, then angular velocity, in the
    base frame) per unit rate of each pose coordinate."""

    link: str
    doc: str
    frame: Callable[[np.ndarray], np.ndarray]
    rates: Callable[[np.ndarray], np.ndarray]
    oriented: bool


@dataclass(frozen=True)
class Reference:
    """The configuration a structure is built at: the design's values by name, the pose, the working mode
    and every joint of pkm's model there (actuated first)."""

    design: Mapping[str, float]
    pose: np.ndarray
    mode: str
    joints: np.ndarray


@dataclass(frozen=True)
class Structure:
    """A mechanism's links and joints at a reference configuration, its end effector, what its export
    says about them (``notes``: what is cut and why, what the URDF leaves out) and its gravity (base frame,
    m/s^2; None where the mechanism states none)."""

    mechanism: str
    doc: str
    reference: Reference
    base: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    effector: Effector
    notes: tuple[str, ...] = ()
    gravity: np.ndarray | None = None


def reference(mech: Any, design: Any, pose: Any, mode: str | None, home: Callable[[np.ndarray], Any]) -> Reference:
    """The reference configuration of a structure: the design validated (its bounds and conditions), the pose
    (``home(design vector)`` without one) and every joint there in the working mode, within the mechanism's
    stated limits; :class:`PoseError` where the pose is out of reach."""
    d = mech.design_vector(design)
    branch = mech.working_mode(mode)
    x = np.asarray(home(d) if pose is None else pose, dtype=float).ravel()
    if x.shape != (mech.n_out,) or not np.all(np.isfinite(x)):
        raise PoseError(f"pose {x.tolist()} violates: {mech.n_out} finite values ({', '.join(mech.pose_names)})")
    q = mech.inverse_kinematics(x, d, mode=branch.name, passive=True)
    if not np.all(np.isfinite(q)):
        raise PoseError(f"pose {x.tolist()} violates: a pose that working mode {branch.name} of {mech.name} reaches "
                        "within its stated limits (the reference configuration of the export)")
    return Reference(mech.design_dict(d), x, branch.name, q)



# the URDF side


@dataclass(frozen=True)
class UrdfLink:
    name: str
    doc: str
    mass: float = 0.0
    centre: np.ndarray = field(default_factory=lambda: np.zeros(3))
    tensor: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    massive: bool = False


@dataclass(frozen=True)
class UrdfJoint:
    """A URDF joint: ``origin`` its placement in its parent link's frame, ``axis`` in its own frame,
    ``limits`` relative to the reference configuration."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray
    doc: str
    axis: np.ndarray | None = None
    limits: tuple[float, float] | None = None
    mimic: tuple[str, float] | None = None


@dataclass(frozen=True)
class Closure:
    """A loop closure: the frames (links) that coincide, the constraint type (``3d``: their origins,
    ``6d``: their placements) and the joint that was cut."""

    frames: tuple[str, str]
    type: str
    joint: str
    doc: str


@dataclass(frozen=True)
class Motor:
    """An actuated joint: its URDF name, pkm's name and pkm's value at the URDF's zero (pkm's coordinate is
    the URDF joint's value plus this offset), and its unit."""

    joint: str
    actuator: str
    offset: float
    unit: str


@dataclass(frozen=True)
class Tree:
    """A structure cut into a tree: the URDF's links and joints, the closures and the motors."""

    structure: Structure
    links: tuple[UrdfLink, ...]
    joints: tuple[UrdfJoint, ...]
    closures: tuple[Closure, ...]
    motors: tuple[Motor, ...]
    effector: str


EFFECTOR = "effector"
ROUNDOFF = 1e-14  # entries of a vector or tensor below this share of its largest are round-off of its rotation


def _clean(values: np.ndarray) -> np.ndarray:
    """``values`` with the round-off of a rotation (entries below ROUNDOFF of the largest) set to zero."""
    scale = np.abs(values).max(initial=0.0)
    return np.where(np.abs(values) <= ROUNDOFF * scale, 0.0, values)


class _Builder:
    """Places links and joints in the base frame as the tree grows."""

    def __init__(self, structure: Structure) -> None:
        self.structure = structure
        self.frames: dict[str, np.ndarray] = {structure.base: np.eye(4)}
        self.path: dict[str, frozenset[str]] = {structure.base: frozenset()}  # joints from the base to a link
        self.links = {link.name: link for link in structure.links}
        self.out_links: list[UrdfLink] = []
        self.out_joints: list[UrdfJoint] = []
        self.closures: list[Closure] = []
        self.extent = max((float(np.linalg.norm(j.origin)) for j in structure.joints), default=1.0) or 1.0

    def add_link(self, name: str, frame: np.ndarray, doc: str) -> None:
        self.frames[name] = frame
        inertial = self.links[name].inertial if name in self.links else None
        if inertial is None:
            self.out_links.append(UrdfLink(name, doc))
            return
        rotation, origin = frame[:3, :3], frame[:3, 3]
        tensor = rotation.T @ inertial.tensor @ rotation
        self.out_links.append(UrdfLink(name, doc, inertial.mass, _clean(rotation.T @ (inertial.centre - origin)),
                                       _clean((tensor + tensor.T) / 2), True))

    def attach(self, name: str, parent: str, child: str, frame: np.ndarray, doc: str, *, link_doc: str = "",
               **extra) -> None:
        """A URDF joint from ``parent`` whose frame (and its child's) is ``frame`` in the base frame; ``link_doc``
        the child's doc where it is not a link of the structure (the joint's by default)."""
        self.out_joints.append(UrdfJoint(name, extra.pop("type", "fixed"), parent, child,
                                         inverse(self.frames[parent]) @ frame, doc, **extra))
        self.add_link(child, frame, self.links[child].doc if child in self.links else link_doc or doc)

    def limits(self, joint: Joint) -> tuple[float, float] | None:
        if joint.limits is not None:
            return joint.limits[0] - joint.value, joint.limits[1] - joint.value
        if joint.kind == "P":  # no stated stroke: twice the machine's size either way
            return -2 * self.extent, 2 * self.extent
        return None

    def chain(self, joint: Joint, child: str, child_doc: str = "") -> np.ndarray:
        """The joint as URDF joints from its parent to ``child``; the frame of ``child``."""
        parent = joint.parent
        if joint.mimic is not None and joint.mimic[0] not in self.path[parent]:
            raise AssertionError(f"joint {joint.name} mimics {joint.mimic[0]}, which is not between it and the base "
                                 "(a parser reads a mimic joint after the joint it mimics)")
        self.path[child] = self.path[parent] | {joint.name}
        kind = URDF_JOINTS[joint.kind]
        if kind.axes == ():
            frame = placement(np.eye(3), joint.origin)
            self.attach(joint.name, parent, child, frame, joint.doc, type=kind.urdf)
            return frame
        axes = joint.axes if kind.axes is None else tuple(np.array(a) for a in kind.axes)
        names = [joint.name] if len(axes) == 1 else [f"{joint.name}_{k + 1}" for k in range(len(axes))]
        urdf = kind.limited if joint.limits is not None and len(axes) == 1 else kind.urdf
        for k, (name, axis) in enumerate(zip(names, axes, strict=True)):
            last = k == len(axes) - 1
            frame = placement(frame_with_axis(axis, joint.along), joint.origin)
            target = child if last else f"{name}_cross"
            doc = joint.doc if len(axes) == 1 else f"{joint.doc} (axis {k + 1} of {len(axes)})"
            self.attach(name, parent, target, frame, doc,
                        link_doc=child_doc if last else f"between the axes of {joint.name}", type=urdf,
                        axis=np.array([0.0, 0.0, 1.0]),
                        limits=self.limits(joint) if len(axes) == 1 else None, mimic=joint.mimic)
            parent = target
        return frame

    def close(self, joint: Joint) -> None:
        """Cut ``joint``, whose child is already in the tree."""
        a, b = f"{joint.name}_A", f"{joint.name}_B"
        kind = URDF_JOINTS[joint.kind]
        if kind.kept:
            frame = self.chain(joint, a, f"closure frame A of {joint.name}, massless, on the side of {joint.parent}")
            why = (f"the {joint.kind} joint stays in the tree on the side of {joint.parent}, its frame A welded to "
                   f"frame B on {joint.child}")
        else:
            frame = placement(np.eye(3), joint.origin)
            self.attach(f"{a}_frame", joint.parent, a, frame, f"closure frame A of {joint.name} on {joint.parent}")
            why = ("a spherical joint, the origins of frames A and B coincide" if kind.contact == "3d" else
                   "a rigid attachment, frames A and B coincide")
        self.attach(f"{b}_frame", joint.child, b, frame, f"closure frame B of {joint.name} on {joint.child}")
        self.closures.append(Closure((a, b), kind.contact, joint.name, f"{joint.doc}: {why}"))


def cut(structure: Structure, actuators: tuple[str, ...]) -> Tree:
    """The tree of a structure (module docstring): its URDF links and joints, closures and motors (in the order
    of pkm's ``actuators``)."""
    builder = _Builder(structure)
    builder.add_link(structure.base, np.eye(4), builder.links[structure.base].doc)
    for joint in structure.joints:
        if joint.kind not in URDF_JOINTS:
            raise AssertionError(f"joint {joint.name}: kind {joint.kind!r} is none of {', '.join(URDF_JOINTS)}")
        if joint.parent not in builder.frames:
            raise AssertionError(f"joint {joint.name}: its parent {joint.parent} is not reached before it")
        if joint.child in builder.frames:
            builder.close(joint)
        else:
            builder.chain(joint, joint.child)
    missing = sorted(set(builder.links) - set(builder.frames))
    if missing:
        raise AssertionError(f"links {', '.join(missing)} are joined to nothing")
    effector = structure.effector
    builder.attach(f"{EFFECTOR}_frame", effector.link, EFFECTOR, effector.frame(structure.reference.pose),
                   f"the end effector: {effector.doc}")
    actuated = {j.actuator: j for j in structure.joints if j.actuator is not None}
    if sorted(actuated) != sorted(actuators):
        raise AssertionError(f"the actuated joints {sorted(actuated)} are not the actuators {list(actuators)}")
    motors = tuple(Motor(actuated[a].name, a, actuated[a].value, "m" if actuated[a].kind == "P" else "rad")
                   for a in actuators)
    return Tree(structure, tuple(builder.out_links), tuple(builder.out_joints), tuple(builder.closures), motors,
                EFFECTOR)


def rpy(rotation: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw of a rotation R = Rz(yaw) Ry(pitch) Rx(roll) (the URDF's convention)."""
    pitch = math.atan2(-rotation[2, 0], math.hypot(rotation[0, 0], rotation[1, 0]))
    if math.hypot(rotation[0, 0], rotation[1, 0]) < 1e-12:  # pitch +-pi/2: yaw and roll share one angle
        return np.array([math.atan2(-rotation[1, 2], rotation[1, 1]), pitch, 0.0])
    return np.array([math.atan2(rotation[2, 1], rotation[2, 2]), pitch, math.atan2(rotation[1, 0], rotation[0, 0])])



def rotation_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotation_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _point(pose: np.ndarray, dim: int) -> np.ndarray:
    return np.concatenate([np.asarray(pose, dtype=float)[:dim], np.zeros(3 - dim)])


def translation_effector(link: str, doc: str, dim: int, *, oriented: bool) -> Effector:
    """An end effector at the pose's first ``dim`` coordinates (x, y and z where given), parallel to the base
    frame at every pose where ``oriented`` (a translating platform), else at the pose's point only."""
    rates = np.zeros((6, dim))
    rates[:dim, :dim] = np.eye(dim)
    return Effector(link, doc, lambda pose: placement(np.eye(3), _point(pose, dim)), lambda _: rates, oriented)


def planar_effector(link: str, doc: str) -> Effector:
    """An end effector at (x, y) turned by phi about z: the pose (x, y, phi)."""
    rates = np.zeros((6, 3))
    rates[0, 0] = rates[1, 1] = rates[5, 2] = 1.0
    return Effector(link, doc, lambda pose: placement(rotation_z(pose[2]), _point(pose, 2)), lambda _: rates, True)


def spatial_effector(link: str, doc: str) -> Effector:
    """An end effector at (x, y, z) turned by R = Rz(yaw) Ry(pitch) Rx(roll): the pose (x, y, z, roll, pitch,
    yaw); its angular velocity is yaw' z + pitch' Rz(yaw) y + roll' Rz(yaw) Ry(pitch) x."""

    def frame(pose: np.ndarray) -> np.ndarray:
        return placement(rotation_z(pose[5]) @ rotation_y(pose[4]) @ rotation_x(pose[3]), _point(pose, 3))

    def rates(pose: np.ndarray) -> np.ndarray:
        out = np.zeros((6, 6))
        out[:3, :3] = np.eye(3)
        rz = rotation_z(pose[5])
        out[3:, 3] = rz @ rotation_y(pose[4])[:, 0]
        out[3:, 4] = rz[:, 1]
        out[3:, 5] = [0.0, 0.0, 1.0]
        return out

    return Effector(link, doc, frame, rates, True)
