"""The structure of a described machine (:mod:`pkm.spec`), leg by leg, each leg walked as its chain of joints.

Every leg is a chain of joints from its base attachment A to its platform attachment C: a chain leg's as described,
a named kind's as :data:`pkm.spec.vocabulary.KINDS` states it (RR: an actuated R, an R; RPR: an R, an actuated P;
PRR: an actuated P, an R; R_parallelogram: an actuated R, a parallelogram; UPS: a U, an actuated P), its joint
values at the reference configuration from the kind's own where they differ from the chain's (an RR's elbow and an
R_parallelogram's rods relative to its arm: :func:`_relative`; a UPS's universal joint: :data:`_VALUES`). One walk
turns each into links and joints: an R or a P one joint, a U two revolutes (its zero at the reference
configuration), a parallelogram the chain its two rods make of it (the rods' plane turning about its first axis, the
rods swinging about its second, the same two turns undone at the rods' end by mimic joints with multiplier -1, so
that the bar there keeps the frame of the body before it), and the platform's revolute (planar) or spherical joint
at C.

The platform hangs from the first leg whose platform joint is not spherical (its joints, then the other legs'
in their order); where every leg ends in a spherical joint the platform floats (a free joint), and a point pose
translates the platform on unactuated slides. Every other leg is cut at its platform joint: a spherical joint as
a point contact, any other joint kept on the leg and welded to the platform. Bodies are those of the description
(masses at their centres, inertias as the kinetic energy of :mod:`symbolic.described` has them): a chain's after
each joint, a kind's on the links of its chain (:data:`_PARTS`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from pkm import expressions
from pkm.errors import ComputationError
from pkm.export.structure import (
    Effector,
    Inertial,
    Joint,
    Link,
    Structure,
    combined,
    planar_effector,
    reference,
    rotation_x,
    rotation_y,
    rotation_z,
    spatial_effector,
    translation_effector,
    unit,
)
from pkm.spec.vocabulary import CHAIN, CHAIN_JOINTS, kind_of

Z = np.array([0.0, 0.0, 1.0])
CLOSURE = 1e-9  # [m] a leg's chain ends this close to its platform joint at the reference configuration, relative


class _Values:
    """The description's expressions evaluated at a design."""

    def __init__(self, design: Mapping[str, float]) -> None:
        self.design = dict(design)

    def scalar(self, tree: expressions.Tree) -> float:
        """The value of one of the description's expressions (:mod:`pkm.expressions`)."""
        return float(expressions.evaluate(tree, self.design))

    def point(self, trees: list[expressions.Tree]) -> np.ndarray:
        values = [self.scalar(t) for t in trees]
        return np.array([*values, *[0.0] * (3 - len(values))])


def _rotation(frame: str, pose: np.ndarray) -> np.ndarray:
    if frame == "planar":
        return rotation_z(pose[2])
    if frame == "spatial":
        return rotation_z(pose[5]) @ rotation_y(pose[4]) @ rotation_x(pose[3])
    return np.eye(3)


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def _bar(values: _Values, body: Mapping[str, Any] | None, start: np.ndarray, direction: np.ndarray
         ) -> list[Inertial]:
    """A body along ``direction`` with its centre ``centre`` from ``start``, its inertia across it."""
    if body is None:
        return []
    u = unit(direction)
    return [Inertial.bar(values.scalar(body["mass"]), start + values.scalar(body["centre"]) * u,
                         values.scalar(body["inertia"]), u)]


def _rotor(values: _Values, bodies: Mapping[str, Any], at: np.ndarray, axis: np.ndarray) -> list[Inertial]:
    """A rotor turning with the actuated revolute: its inertia about the joint's axis (a massless disc)."""
    moment = values.scalar(bodies.get("rotor", 0))
    return [Inertial.lamina(0.0, at, moment, axis)] if moment else []


class _Leg:
    """One leg's links and joints, walked as its chain; ``k`` its number, ``q`` its joints' values (actuated
    first, then the passive ones in the chain's order)."""

    def __init__(self, k: int, leg: Mapping[str, Any], values: _Values, *, ends: tuple[np.ndarray, np.ndarray],
                 q: tuple[float, ...], platform_angle: float) -> None:
        self.k, self.leg, self.values, (self.a, self.c) = k, leg, values, ends
        self.turn = platform_angle
        self.bodies = leg.get("bodies")
        self.links: list[Link] = []
        self.joints: list[Joint] = []
        self.platform_parts: list[Inertial] = []
        self.notes: list[str] = []
        self.q = _VALUES[leg["kind"]](self, q) if leg["kind"] in _VALUES else _relative(leg, q)
        self._walk()

    def body(self, name: str) -> Mapping[str, Any] | None:
        return None if self.bodies is None else self.bodies.get(name)

    def link(self, name: str, doc: str, parts: list[Inertial] | None = None) -> str:
        self.links.append(Link(f"{name}{self.k}", f"{doc} of leg {self.k}", combined(parts or [])))
        return f"{name}{self.k}"

    def actuated(self, kind: str, links: tuple[str, str], at: np.ndarray, axis: np.ndarray, doc: str, *,
                 along: np.ndarray | None = None) -> None:
        name = f"q{self.k}"
        limits = None
        if "range" in self.leg:
            limits = (self.values.scalar(self.leg["range"][0]), self.values.scalar(self.leg["range"][1]))
        self.joints.append(Joint(name, kind, *links, at, (axis,), f"actuated joint of leg {self.k}: {doc}",
                                 actuator=name, value=float(self.q[0]), limits=limits, along=along))

    def passive(self, name: str, kind: str, links: tuple[str, str], at: np.ndarray, axes: tuple[np.ndarray, ...],
                *, doc: str, **extra: Any) -> None:
        self.joints.append(Joint(f"{name}{self.k}", kind, *links, at, axes, f"{doc} of leg {self.k}", **extra))

    @property
    def actuated_joint(self) -> Mapping[str, Any]:
        return next(j for j in self.leg["joints"] if j["actuated"])

    @property
    def rotor(self) -> float:
        """Its actuated joint's rotor (a kind's in its bodies, a chain's on the joint); 0 without one."""
        table = (self.bodies or {}) if self.leg["kind"] != CHAIN else self.actuated_joint
        return float(self.values.scalar(table.get("rotor", 0)))

    @property
    def turning_rotor(self) -> bool:
        """Whether its actuated joint is a revolute with a rotor."""
        return self.actuated_joint["type"] == "R" and bool(self.rotor)

    def _walk(self) -> None:
        """The chain's links and joints from A, then the platform's joint at C."""
        if self.actuated_joint["type"] == "P" and self.rotor:
            self.notes.append(f"leg {self.k}: the rotor on its actuated prismatic joint (a reflected mass along the "
                              "joint) has no form in a URDF and is left out")
        planar = len(self.leg["joints"][0]["link"]) == 2
        rotation = rotation_z(self.values.scalar(self.leg.get("turn", 0)))
        point, parent = self.a, "base"
        passive = iter(self.q[1:])
        parts = _PARTS.get(self.leg["kind"])
        for j, joint in enumerate(self.leg["joints"]):
            kind = joint["type"]
            mine = [self.q[0]] if joint["actuated"] else [next(passive) for _ in range(CHAIN_JOINTS[kind])]
            if kind == "parallelogram":
                point, parent = self._parallelogram(j, joint, (point, rotation), mine, parent)
                continue
            at = point
            if kind == "P":
                axes = (rotation @ unit(self.values.point(joint["axis"])),)
                point = point + axes[0] * mine[0]
            else:
                axes = ()
                for text, angle in zip(joint["axes"], mine, strict=True):
                    local = unit(self.values.point(text))
                    axes += (rotation @ local,)
                    rotation = rotation @ _about(local, angle)
            end = point + rotation @ self.values.point(joint["link"])
            own = parts(self, j, (point, end, axes[0])) if parts else self._chain_parts(joint, point, rotation,
                                                                                         axes[0])
            child = self.link(f"body{j + 1}_", f"the body after joint {j + 1}", own)
            along = end - at if np.linalg.norm(end - at) > 1e-12 else None
            if joint["actuated"]:
                self.actuated(kind, (parent, child), at, axes[0], f"joint {j + 1} of the chain", along=along)
            else:
                self.passive(f"joint{j + 1}_", kind, (parent, child), at, axes, doc=f"joint {j + 1} of the chain",
                             value=mine[0] if len(mine) == 1 else 0.0, along=along)
            point, parent = end, child
        gap = float(np.linalg.norm(point - self.c))
        if gap > CLOSURE * max(1.0, float(np.abs(self.a).max()), float(np.abs(self.c).max())):
            raise ComputationError(f"leg {self.k}'s chain ends {gap:.1e} m from its platform joint at the reference "
                                   "configuration")
        if planar:
            self.passive("platform_joint", "R", (parent, "platform"), self.c, (Z,), doc="the platform's revolute",
                         value=self.turn - math.atan2(rotation[1, 0], rotation[0, 0]))
        else:
            self.passive("platform_joint", "S", (parent, "platform"), self.c, (), doc="the platform's spherical joint")

    def _parallelogram(self, j: int, joint: Mapping[str, Any], frame: tuple[np.ndarray, np.ndarray],
                       angles: list[float], parent: str) -> tuple[np.ndarray, str]:
        """A parallelogram as its rods move it: the rods' plane turning about its first axis, the rods swinging
        about its second, then at their end the same two turns undone by mimic joints (multiplier -1), so that
        the bar there keeps the frame of the body before it; its end and its last body."""
        at, rotation = frame
        first, second = (unit(self.values.point(t)) for t in joint["axes"])
        turned = rotation @ _about(first, angles[0])
        end = at + turned @ _about(second, angles[1]) @ self.values.point(joint["link"])
        axes = (rotation @ first, turned @ second)
        names = [f"{part}{j + 1}_" for part in ("plane", "rods", "bar_swing", "bar")]
        docs = ["the plane of its rods turning", "its rods swinging in their plane",
                "its bar's swing undone", "its bar, parallel to the body before it"]
        parts = [[], self._chain_parts(joint, at, turned @ _about(second, angles[1]), axes[1]), [], []]
        links = [self.link(n, f"joint {j + 1}'s parallelogram: {d}", p)
                 for n, d, p in zip(names, docs, parts, strict=True)]
        self.passive(names[0], "R", (parent, links[0]), at, axes[:1], doc=f"joint {j + 1}: {docs[0]}", value=angles[0],
                     along=end - at)
        self.passive(names[1], "R", links[:2], at, axes[1:], doc=f"joint {j + 1}: {docs[1]}", value=angles[1],
                     along=end - at)
        self.passive(names[2], "R", links[1:3], end, axes[1:], doc=f"joint {j + 1}: {docs[2]}",
                     mimic=(f"{names[1]}{self.k}", -1.0))
        self.passive(names[3], "R", links[2:], end, axes[:1], doc=f"joint {j + 1}: {docs[3]}",
                     mimic=(f"{names[0]}{self.k}", -1.0))
        return end, links[3]

    def _chain_parts(self, joint: Mapping[str, Any], origin: np.ndarray, rotation: np.ndarray, axis: np.ndarray
                     ) -> list[Inertial]:
        """The body after a chain's joint (at ``origin``, in the frame ``rotation``) and the actuated joint's
        rotor turning about ``axis`` (a rotor on a prismatic joint has no URDF form: a note says so)."""
        parts = []
        body = joint.get("body")
        if body is not None:
            mass, centre = self.values.scalar(body["mass"]), origin + rotation @ self.values.point(body["centre"])
            if not isinstance(body["inertia"], list) or expressions.is_operation(body["inertia"]):
                parts.append(Inertial.lamina(mass, centre, self.values.scalar(body["inertia"]), Z))
            else:
                moments = np.array([self.values.scalar(t) for t in body["inertia"]])
                parts.append(Inertial.principal(mass, centre, moments, rotation))
        if "rotor" in joint and joint["type"] == "R":
            parts += _rotor(self.values, {"rotor": joint["rotor"]}, origin, axis)
        return parts


def _ups_values(leg: _Leg, q: tuple[float, ...]) -> tuple[float, ...]:
    """A UPS's length, then its universal joint (about x, then y) pointing its prismatic joint's z at C."""
    d = unit(leg.c - leg.a)
    return q[0], math.atan2(-d[1], d[2]), math.asin(float(np.clip(d[0], -1.0, 1.0)))


def _relative(leg: Mapping[str, Any], q: tuple[float, ...]) -> tuple[float, ...]:
    """A kind's joint values (actuated first) as its chain's: each passive angle the kind measures from the base's
    frame (:attr:`pkm.spec.vocabulary.Kind.follows`: an RR's distal angle, an R_parallelogram's rods' angle about
    the axis) less the actuated joint's."""
    follows = kind_of(leg).follows
    return tuple(v - q[0] if i - 1 in follows else v for i, v in enumerate(q))


# a named kind's joint values (actuated first) as its chain's, where its chain's coordinates are not its own
_VALUES = {"UPS": _ups_values}


Frame = tuple[np.ndarray, np.ndarray, np.ndarray]  # the body's origin after a joint, its link's end, the joint's axis


def _rr_parts(leg: _Leg, j: int, frame: Frame) -> list[Inertial]:
    """An RR's proximal link with its rotor, its distal link."""
    origin, end, axis = frame
    name = ("proximal", "distal")[j]
    rotor = _rotor(leg.values, leg.bodies or {}, origin, axis) if j == 0 else []
    return [*_bar(leg.values, leg.body(name), origin, end - origin), *rotor]


def _legged_parts(leg: _Leg, j: int, _frame: Frame) -> list[Inertial]:
    """An RPR's or a UPS's cylinder on its base joint and piston on its platform joint, along the leg."""
    if j == 0:
        return _bar(leg.values, leg.body("cylinder"), leg.a, leg.c - leg.a)
    return _bar(leg.values, leg.body("piston"), leg.c, leg.a - leg.c)


def _prr_parts(leg: _Leg, j: int, frame: Frame) -> list[Inertial]:
    """A PRR's slider, its mass at its joint, and its distal link."""
    origin, end, _ = frame
    if j == 1:
        return _bar(leg.values, leg.body("distal"), origin, end - origin)
    slider = leg.body("slider")
    return [] if slider is None else [Inertial.point(leg.values.scalar(slider["mass"]), origin)]


def _parallelogram_parts(leg: _Leg, _j: int, frame: Frame) -> list[Inertial]:
    """The arm with its rotor and half the rods' mass at its tip; the other half at the platform joint (the
    parallelogram's rods, the chain's second joint, are massless)."""
    origin, end, axis = frame
    rod = leg.body("rod")
    half = [] if rod is None else [Inertial.point(leg.values.scalar(rod["mass"]) / 2, end)]
    if rod is not None:
        leg.platform_parts.append(Inertial.point(leg.values.scalar(rod["mass"]) / 2, leg.c))
    return [*_bar(leg.values, leg.body("arm"), origin, end - origin), *half,
            *_rotor(leg.values, leg.bodies or {}, origin, axis)]


# a named kind's bodies on the links of its chain (the link after joint j; the parallelogram's rods massless)
_PARTS = {"RR": _rr_parts, "RPR": _legged_parts, "UPS": _legged_parts, "PRR": _prr_parts,
          "R_parallelogram": _parallelogram_parts}


def _slides(origin: np.ndarray, pose: np.ndarray) -> list[Joint]:
    """The platform of a point pose on prismatic joints along the base's axes, one per pose coordinate, their
    values the pose's."""
    names = ["platform_slide_x", "platform_slide_y", "platform_slide_z"][: len(pose)]
    children = [*(f"{name}_carriage" for name in names[:-1]), "platform"]
    parents = ["base", *children[:-1]]
    return [Joint(name, "P", parent, child, origin, (np.eye(3)[k],), f"the platform's slide along {name[-1]} "
                  "(unactuated)", value=float(pose[k]))
            for k, (name, parent, child) in enumerate(zip(names, parents, children, strict=True))]


def _about(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation by ``angle`` about the unit ``axis`` (Rodrigues)."""
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * cross + (1 - math.cos(angle)) * cross @ cross


def structure(mech: Any, design: Any, pose: Any, mode: str | None) -> Structure:
    """The structure of a described machine at a design, with the reference configuration at ``pose`` (its
    home pose by default) in working mode ``mode``."""
    data = mech.description.data

    def home(d: np.ndarray) -> np.ndarray:
        return np.asarray(mech.functions["home"](d), dtype=float).ravel()

    ref = reference(mech, design, pose, mode, home)
    values = _Values(ref.design)
    frame = data["pose"]["frame"]
    x = ref.pose
    rotation = _rotation(frame, x)
    origin = np.array([*x[: 2 if frame.startswith("planar") else 3], *([0.0] if frame.startswith("planar") else [])])
    turn = float(x[2]) if frame == "planar" else 0.0
    n_act = len(data["legs"])
    passive = iter(ref.joints[n_act:])
    legs = []
    for k, leg in enumerate(data["legs"]):
        q = (float(ref.joints[k]), *(float(next(passive)) for _ in range(kind_of(leg).passive)))
        a = values.point(leg["base"])
        c = origin + rotation @ values.point(leg["platform"])
        legs.append(_Leg(k + 1, leg, values, ends=(a, c), q=q, platform_angle=turn))
    platform_parts = [part for leg in legs for part in leg.platform_parts]
    body = data.get("platform")
    if body is not None:
        centre = origin + rotation @ values.point(body["centre"])
        mass = values.scalar(body["mass"])
        if frame == "planar":
            platform_parts.append(Inertial.lamina(mass, centre, values.scalar(body["inertia"]), Z))
        elif frame == "spatial":
            moments = np.array([values.scalar(t) for t in body["inertia"]])
            platform_parts.append(Inertial.principal(mass, centre, moments, rotation))
        else:
            platform_parts.append(Inertial.point(mass, centre))
    translating = frame.endswith("point")
    carrier = legs[0] if frame == "planar" else None
    links = [Link("base", "the base: the frame of the pose"),
             Link("platform", "the platform: its frame the pose's at the reference configuration",
                  combined(platform_parts))]
    if translating:
        slides = _slides(origin, x)
        links += [Link(j.child, f"the carriage of the platform's slide along {j.name[-1]}") for j in slides[:-1]]
        joints = slides
    else:
        joints = [] if carrier is not None else [
            Joint("platform", "free", "base", "platform", origin, (), "the platform, floating: every leg meets it in "
                  "a spherical joint")]
    order = ([carrier] if carrier is not None else []) + [leg for leg in legs if leg is not carrier]
    for leg in order:
        links += leg.links
        joints += leg.joints
    kinds = sorted({leg.leg["kind"] for leg in legs})
    hung = (f"The platform hangs from leg {carrier.k}; every other leg is cut at its platform joint" if carrier
            is not None else "The platform translates on unactuated prismatic joints along the pose's axes, as "
            "pkm's model of a point pose has it: every leg is cut at its platform joint" if translating else
            "The platform floats (a free joint): every leg is cut at its spherical platform joint")
    notes = [
        f"{hung}: a spherical joint becomes a point contact (3d), any other stays on the leg, welded to the platform "
        "(6d).",
        "Every leg is its chain of joints (a kind's as docs/mechanisms.md states it): a universal joint's zero at "
        "the reference configuration (pkm's two angles of it are offset by their values there), every other joint's "
        "zero pkm's value there; a parallelogram as its rods move it, its two turns undone at their end by mimic "
        "joints (multiplier -1).",
        *(f"{kind} legs: {_KIND_NOTES[kind]}" for kind in kinds if kind in _KIND_NOTES),
        *(note for leg in legs for note in leg.notes),
    ]
    if any(leg.turning_rotor for leg in legs):
        notes.append("A rotor's inertia after its reduction is a massless disc about the actuated revolute's axis, "
                     "on the link it turns.")
    if frame.endswith("point"):
        notes.append("The pose fixes the platform's position only; pkm's model has the platform translate.")
    effector = _effector(frame)
    gravity = None if data.get("gravity") is None else values.point(data["gravity"])
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, tuple(notes), gravity)


_KIND_NOTES = {
    "R_parallelogram": "its two rods as one massless rod on the parallelogram's centre line, their mass half at the "
                       "arm's tip and half at the platform, as pkm's model has it (their spacing does not enter the "
                       "kinematics).",
}


def _effector(frame: str) -> Effector:
    if frame == "planar":
        return planar_effector("platform", "the platform's frame: at (x, y, 0), turned by phi about z")
    if frame == "spatial":
        return spatial_effector("platform", "the platform's frame: at (x, y, z), turned by R = Rz(yaw) Ry(pitch) "
                                "Rx(roll)")
    dim = 2 if frame.startswith("planar") else 3
    return translation_effector("platform", "the platform's reference point, at the pose's coordinates", dim,
                                oriented=False)
