"""The structure of a described machine (:mod:`pkm.spec`), leg by leg from its legs' kinds.

Each kind of leg (:data:`pkm.spec.vocabulary.KINDS`) is a chain of joints from its base attachment A to its platform
attachment C (:mod:`symbolic.described` states their coordinates):

* ``RR``: the actuated revolute at A (the proximal link's angle theta about z), the elbow (phi - theta) and a
  revolute at C;
* ``RPR``: a revolute at A (the leg's angle phi), the actuated prismatic joint along the leg (rho) and a
  revolute at C;
* ``PRR``: the actuated prismatic joint along the leg's axis from A (s), a revolute at the slider (phi) and a
  revolute at C;
* ``R_parallelogram``: the actuated revolute at A about the leg's axis (the arm's theta), then the
  parallelogram as the chain its two rods make of it: at the arm's tip a revolute about the axis (the plane of
  the rods turning), a revolute across that plane (the rods swinging in it), the rod, a revolute across the
  plane that mimics the swing with multiplier -1 (the platform's bar stays parallel to the arm's) and a
  revolute about the axis at C (the bar turning about its own line);
* ``UPS``: a universal joint at A (its first axis horizontal and across the leg, its second across both), the
  actuated prismatic joint along the leg (its length) and a spherical joint at C;
* ``chain``: its joints as the description gives them (a universal joint's zero at the reference
  configuration; a parallelogram as the R_parallelogram's, its two turns undone at the rods' end by mimic
  joints), a body after each, and the platform's revolute (planar) or spherical joint at C.

The platform hangs from the first leg whose platform joint is not spherical (its joints, then the other legs'
in their order); where every leg ends in a spherical joint the platform floats (a free joint). Every other
leg is cut at its platform joint: a spherical joint as a point contact, any other joint kept on the leg and
welded to the platform. Bodies are those of the description (masses at their centres, inertias as the
kinetic energy of :mod:`symbolic.described` has them).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from pkm import expressions
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
from pkm.spec.vocabulary import CHAIN_JOINTS, kind_of

Z = np.array([0.0, 0.0, 1.0])
SPHERICAL = ("UPS",)  # kinds whose platform joint is spherical (and chains in space)


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
    """One leg's links and joints; ``k`` its number, ``q`` its actuated and passive joints' values."""

    def __init__(self, k: int, leg: Mapping[str, Any], values: _Values, *, ends: tuple[np.ndarray, np.ndarray],
                 q: tuple[float, ...], platform_angle: float) -> None:
        self.k, self.leg, self.values, (self.a, self.c) = k, leg, values, ends
        self.q, self.turn = q, platform_angle
        self.bodies = leg.get("bodies")
        self.links: list[Link] = []
        self.joints: list[Joint] = []
        self.platform_parts: list[Inertial] = []
        self.notes: list[str] = []
        getattr(self, "_" + leg["kind"].lower())()

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

    def rotor_note(self) -> None:
        if self.bodies is not None and self.values.scalar(self.bodies.get("rotor", 0)):
            self.notes.append(f"leg {self.k}: the rotor on its actuated prismatic joint (a reflected mass along the "
                              "joint) has no form in a URDF and is left out")

    def _rr(self) -> None:
        theta, phi = self.q
        elbow = self.a + self.values.scalar(self.leg["proximal"]) * _e(theta)
        proximal = self.link("proximal", "the proximal link", [
            *_bar(self.values, self.body("proximal"), self.a, _e(theta)), *_rotor(self.values, self.bodies or {},
                                                                                  self.a, Z)])
        distal = self.link("distal", "the distal link", _bar(self.values, self.body("distal"), elbow, _e(phi)))
        self.actuated("R", ("base", proximal), self.a, Z, "theta, the proximal link's angle", along=_e(theta))
        self.passive("elbow", "R", (proximal, distal), elbow, (Z,), doc="the elbow: phi - theta", value=phi - theta,
                     along=_e(phi))
        self.passive("platform_joint", "R", (distal, "platform"), self.c, (Z,), doc="the platform's revolute",
                     value=self.turn - phi)

    def _rpr(self) -> None:
        phi = self.q[1]
        cylinder = self.link("cylinder", "the cylinder", _bar(self.values, self.body("cylinder"), self.a, _e(phi)))
        piston = self.link("piston", "the piston", _bar(self.values, self.body("piston"), self.c, -_e(phi)))
        self.passive("base_joint", "R", ("base", cylinder), self.a, (Z,), doc="the base revolute: phi", value=phi,
                     along=_e(phi))
        self.actuated("P", (cylinder, piston), self.a, _e(phi), "rho, the leg's length")
        self.passive("platform_joint", "R", (piston, "platform"), self.c, (Z,), doc="the platform's revolute",
                     value=self.turn - phi)
        self.rotor_note()

    def _prr(self) -> None:
        s, phi = self.q
        u = unit(self.values.point(self.leg["axis"]))
        joint = self.a + s * u
        slider = self.link("slider", "the slider", [] if self.body("slider") is None else
                           [Inertial.point(self.values.scalar(self.body("slider")["mass"]), joint)])
        distal = self.link("distal", "the distal link", _bar(self.values, self.body("distal"), joint, _e(phi)))
        self.actuated("P", ("base", slider), joint, u, "s, the slider's travel from A")
        self.passive("slider_joint", "R", (slider, distal), joint, (Z,), doc="the slider's revolute: phi", value=phi,
                     along=_e(phi))
        self.passive("platform_joint", "R", (distal, "platform"), self.c, (Z,), doc="the platform's revolute",
                     value=self.turn - phi)
        self.rotor_note()

    def _r_parallelogram(self) -> None:
        theta = self.q[0]
        axis, zero = unit(self.values.point(self.leg["axis"])), unit(self.values.point(self.leg["zero"]))
        along = math.cos(theta) * zero + math.sin(theta) * np.cross(axis, zero)
        tip = self.a + self.values.scalar(self.leg["arm"]) * along
        rod = self.body("rod")
        half = [] if rod is None else [Inertial.point(self.values.scalar(rod["mass"]) / 2, tip)]
        if rod is not None:
            self.platform_parts.append(Inertial.point(self.values.scalar(rod["mass"]) / 2, self.c))
        arm = self.link("arm", "the arm", [*_bar(self.values, self.body("arm"), self.a, along), *half,
                                           *_rotor(self.values, self.bodies or {}, self.a, axis)])
        across = unit(np.cross(axis, self.c - tip))
        plane = self.link("rods_plane", "the plane of the parallelogram's rods, turning about the arm's axis")
        rods = self.link("rods", "the parallelogram's rods, swinging in their plane (massless: their mass is half at "
                         "the arm's tip, half at the platform)")
        bar = self.link("platform_bar", "the parallelogram's bar on the platform's side, parallel to the arm's")
        self.actuated("R", ("base", arm), self.a, axis, "theta, the arm's angle", along=along)
        self.passive("rods_plane", "R", (arm, plane), tip, (axis,), doc="the plane of the rods turning about the arm's "
                     "axis",
                     along=self.c - tip)
        self.passive("rods_swing", "R", (plane, rods), tip, (across,), doc="the rods swinging in their plane",
                     along=self.c - tip)
        self.passive("bar_swing", "R", (rods, bar), self.c, (across,), doc="the platform's bar kept parallel to the "
                     "arm's",
                     mimic=(f"rods_swing{self.k}", -1.0))
        self.passive("platform_joint", "R", (bar, "platform"), self.c, (axis,), doc="the platform turning about its "
                     "bar's "
                     "line")

    def _ups(self) -> None:
        length = self.q[0]
        d = unit(self.c - self.a)
        first = np.cross(Z, d)
        first = unit(first if np.linalg.norm(first) > 1e-9 else np.array([1.0, 0.0, 0.0]))
        cylinder = self.link("cylinder", "the cylinder", _bar(self.values, self.body("cylinder"), self.a, d))
        piston = self.link("piston", "the piston", _bar(self.values, self.body("piston"), self.c, -d))
        self.passive("universal", "U", ("base", cylinder), self.a, (first, np.cross(d, first)),
                     doc="the base universal joint", along=d)
        self.actuated("P", (cylinder, piston), self.a, d, f"its length ({length:.6g} m at the reference)")
        self.passive("spherical", "S", (piston, "platform"), self.c, (), doc="the platform's spherical joint")
        self.rotor_note()

    def _chain(self) -> None:
        planar = len(self.leg["joints"][0]["link"]) == 2
        rotation = rotation_z(self.values.scalar(self.leg["turn"]))
        point, parent = self.a, "base"
        passive = iter(self.q[1:])
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
            child = self.link(f"body{j + 1}_", f"the body after joint {j + 1}",
                              self._chain_parts(joint, point, rotation, axes[0]))
            end = point + rotation @ self.values.point(joint["link"])
            along = end - at if np.linalg.norm(end - at) > 1e-12 else None
            if joint["actuated"]:
                self.actuated(kind, (parent, child), at, axes[0], f"joint {j + 1} of the chain", along=along)
            else:
                self.passive(f"joint{j + 1}_", kind, (parent, child), at, axes, doc=f"joint {j + 1} of the chain",
                             value=mine[0] if len(mine) == 1 else 0.0, along=along)
            point, parent = end, child
        if planar:
            self.passive("platform_joint", "R", (parent, "platform"), self.c, (Z,), doc="the platform's revolute",
                         value=self.turn - math.atan2(rotation[1, 0], rotation[0, 0]))
        else:
            self.passive("platform_joint", "S", (parent, "platform"), self.c, (), doc="the platform's spherical joint")

    def _parallelogram(self, j: int, joint: Mapping[str, Any], frame: tuple[np.ndarray, np.ndarray],
                       angles: list[float], parent: str) -> tuple[np.ndarray, str]:
        """A chain's parallelogram as its rods move it: the rods' plane turning about its first axis, the rods
        swinging about its second, then at their end the same two turns undone by mimic joints (multiplier
        -1), so that the bar there keeps the frame of the body before it; its end and its last body."""
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
        elif "rotor" in joint and self.values.scalar(joint["rotor"]):
            self.notes.append(f"leg {self.k}: the rotor on its actuated prismatic joint (a reflected mass along the "
                              "joint) has no form in a URDF and is left out")
        return parts


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
    translating = frame == "planar_point" or (frame.endswith("point") and any(leg.leg["kind"] == "chain"
                                                                              for leg in legs))
    carrier = None if translating else next((leg for leg in legs if leg.leg["kind"] not in SPHERICAL
                                             and not (leg.leg["kind"] == "chain" and frame.startswith("spatial"))),
                                            None)
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
        *(f"{kind} legs: {_KIND_NOTES[kind]}" for kind in kinds),
        *(note for leg in legs for note in leg.notes),
    ]
    turning = [leg for leg in legs if leg.leg["kind"] in ("RR", "R_parallelogram") and leg.bodies is not None]
    if any(values.scalar(leg.bodies.get("rotor", 0)) for leg in turning):
        notes.append("A rotor's inertia after its reduction is a massless disc about the actuated revolute's axis, "
                     "on the link it turns.")
    if frame.endswith("point"):
        notes.append("The pose fixes the platform's position only; pkm's model has the platform translate.")
    effector = _effector(frame)
    gravity = None if data.get("gravity") is None else values.point(data["gravity"])
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, tuple(notes), gravity)


_KIND_NOTES = {
    "RR": "the actuated revolute at A, the elbow and the platform's revolute, all about z.",
    "RPR": "a revolute at A, the actuated prismatic joint along the leg and the platform's revolute.",
    "PRR": "the actuated prismatic joint along the leg's axis, the slider's revolute and the platform's revolute.",
    "R_parallelogram": "the actuated arm, then the parallelogram as its rods move it: the rods' plane turning about "
                       "the arm's axis at its tip, the rods swinging in that plane, the platform's bar kept parallel "
                       "to the arm's by a mimic joint (multiplier -1) and turning about its own line; its two rods as "
                       "one massless rod on the parallelogram's centre line (their spacing does not enter the "
                       "kinematics).",
    "UPS": "the universal joint at A (first axis horizontal and across the leg at the reference configuration), the "
           "actuated prismatic joint along the leg and the spherical joint at C.",
    "chain": "its joints as described, a universal joint's zero at the reference configuration (pkm's coordinates "
             "of it are offset by their values there), a massless body after each, and the platform's point joint.",
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
