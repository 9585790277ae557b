"""The vocabulary of machines described as data: what a description, a leg of each kind and a joint of each type
hold (each field with what it holds and means), the frames of a pose, the kinds' branches and the chain of joints
each kind is. :mod:`pkm.spec.schema` checks descriptions against these tables and :mod:`pkm.schema_docs` writes
docs/mechanisms.md's reference from them; :mod:`pkm.export.legs` reads a leg's kind here. It imports nothing that
knows a mechanism.

A joint type (:data:`JOINTS`) is the one home of what a joint is: its variables, its fields, the frame of the body
after it; what a joint of the machine adds beyond its motion (its compliance, its tolerance parameters, its
collision geometry) is a field of its type here, which the schema then checks, every kind's chain holds and
docs/mechanisms.md lists."""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from pkm import expressions

FRAMES = {
    "planar_point": (("x", "y"), ("m", "m")),
    "planar": (("x", "y", "phi"), ("m", "m", "rad")),
    "spatial_point": (("x", "y", "z"), ("m", "m", "m")),
    "spatial": (("x", "y", "z", "roll", "pitch", "yaw"), ("m", "m", "m", "rad", "rad", "rad")),
}
RANKS = {"planar_point": 1, "planar": 2, "spatial_point": 1, "spatial": 8}  # solutions of one signature told
# apart by rank, by the pose (a planar 3-DOF machine has up to 6 assemblies, a 6-DOF one up to 40)
FRAME_DOCS = {
    "planar_point": "a point in the plane: the platform translates",
    "planar": "a body in the plane, turned by phi about z",
    "spatial_point": "a point in space: the platform translates",
    "spatial": "a body in space, turned by R = Rz(yaw) Ry(pitch) Rx(roll)",
}
NAME_LENGTH = 64  # the longest name of a machine, a parameter, a region, a mode or a branch
TEXT_LENGTH = 2000  # the longest text of a doc or a unit


@dataclass(frozen=True)
class Field:
    """A field of a table of a description: its name, what it holds (a kind of value, its unit in brackets),
    what it means (with its default where it has one) and whether it must be given. :func:`describe` refuses a
    field that its table does not hold and a required one that is missing, naming it; docs/mechanisms.md lists
    the tables (:mod:`pkm.schema_docs`)."""

    name: str
    holds: str
    doc: str
    required: bool = False


IDENTIFIER = (f"an identifier of at most {NAME_LENGTH} characters: a letter, then letters, digits and single "
              "underscores, not ending in one")
IDENTIFIER_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9]*(_[A-Za-z0-9]+)*")
TEXT = f"text of at most {TEXT_LENGTH} characters"
LENGTH = "an expression [m], positive"
CONE = "an expression [rad], positive"
BODY = "a body {mass, centre, inertia}"
POINT_BODY = "a body {mass}"  # a body without extent: its mass at a point
EACH = "2 in the plane, 3 in space"

DESCRIPTION_FIELDS = (
    Field("name", IDENTIFIER, "the machine's name", required=True),
    Field("doc", TEXT, "what the machine is; its name by default"),
    Field("frame", f"one of {', '.join(FRAMES)} (Frames)", "the pose: its coordinates and their units",
          required=True),
    Field("parameters", "a non-empty list of tables (Parameters)", "the design's parameters", required=True),
    Field("conditions", "a list of tables (Conditions)", "the design's validity conditions"),
    Field("legs", "a table or a list of tables (Legs)", "the legs, one actuated joint per pose coordinate in all",
          required=True),
    Field("home", "a list of expressions [the pose's units]", "the home pose, a value per pose coordinate: it "
          "assembles at the default design in the first working mode and seeds the forward kinematics; its angles "
          "within a turn", required=True),
    Field("characteristic_length", "an expression [m]", "the length that turns the pose's angles into lengths in "
          "the indices of J"),
    Field("modes", "a table: name = a list of signs (Working modes)", "the working modes by name, the first the "
          "default; every combination of the legs' branches by default"),
    Field("regions", "a list of tables (Regions)", "task regions"),
    Field("platform", f"{BODY} (Bodies)", "the platform's body: its centre a point of the platform frame; its "
          "inertia about z (planar), the principal moments about the platform frame's x, y, z (spatial), none for a "
          "point (planar_point, spatial_point)"),
    Field("gravity", f"a list of expressions ({EACH}) [m/s^2]", "the acceleration of gravity in the base frame, "
          "for the bodies' weight in the inverse dynamics"),
    Field("plates", "a table {platform, base}, each a radius (an expression [m], positive) or a table (Plates)",
          "the platform and the base as plates: each a convex polygon (the legs' attachments to it, or its own "
          "points) rounded by its radius; a leg's capsules that meet one collide (the collision margin), its segments "
          "at the plate's own joints aside; needs the legs' capsules"),
)
PLATES = ("platform", "base")  # the plates a description may state
PLATE_FIELDS = (
    Field("radius", LENGTH, "the plate's rounding: the plate holds every point within it of its polygon",
          required=True),
    Field("points", f"a non-empty list of points, each a list of expressions ({EACH}) [m]", "the plate's own "
          "polygon in its frame (the platform's or the base's): its vertices, taken in their angular order about "
          "their centre at the default design, where they must make it convex; in space in one plane z = const; "
          "one point a disc (in the plane) or a ball (in space), two a rounded bar; the legs' attachments to the "
          "plate by default"),
)
PARAMETER_FIELDS = (
    Field("name", IDENTIFIER, "its name in the expressions, given once, other than "
          f"{', '.join(expressions.RESERVED)}", required=True),
    Field("default", "a number", "its value at the default design, lower <= default < upper", required=True),
    Field("lower", "a number", "its lower bound (every parameter has bounds)", required=True),
    Field("upper", "a number", "its upper bound, above lower", required=True),
    Field("unit", TEXT, "its unit; - by default"),
    Field("doc", TEXT, "what it is"),
)
CONDITION_FIELDS = (
    Field("margin", "an expression", "positive where the design is valid: a design that violates it is refused, "
          "naming it", required=True),
    Field("doc", TEXT, "what the condition is; a valid design by default"),
)
PATTERN_FIELDS = (
    Field("circle", "an expression [m]", "the circle's radius: count points at start + 2 pi i / count",
          required=True),
    Field("start", "an expression [rad]", "the angle of the first point (with pairs, of the first pair's centre); "
          "0 by default"),
    Field("pairs", "an expression [rad]", "legs in pairs (an even count): count / 2 pairs centred at start + 2 pi j "
          "/ (count / 2), their points this angle apart"),
)
BODY_FIELDS = (
    Field("mass", "an expression [kg]", "its mass", required=True),
    Field("centre", "an expression or a point (a list of expressions) [m]", "its centre of mass: along a leg "
          "kind's body from the joint its kind names (a distance), or a point of the frame of a chain joint's body "
          "from the joint or of the platform frame; 0 by default"),
    Field("inertia", "an expression or a list of expressions [kg m^2]", "about its centre of mass: a leg kind's "
          "body's about the axis its kind names; a chain joint's body's and the platform's about z in the plane, "
          "its principal moments about the axes of its frame in space; 0 by default"),
)
ROTOR = Field("rotor", "an expression [kg m^2, kg on a prismatic joint]", "the actuated joint's rotor: its inertia "
              "after the reduction, or a reflected mass on a prismatic joint; 0 by default")
LEG_BODIES = Field("bodies", "a table {rotor, the kind's bodies} (Bodies)", "the leg's rotor and bodies, each "
                   "optional; where a description gives a body, every leg has bodies")
MATERIALS = {  # a material by name: Young's modulus E [Pa], shear modulus G [Pa], density [kg/m^3]
    "steel": (210e9, 81e9, 7850.0),
    "aluminium": (70e9, 26e9, 2700.0),
    "titanium": (114e9, 44e9, 4430.0),
    "carbon_fibre": (135e9, 5e9, 1600.0),
}
SECTIONS = {  # a beam's section by shape: its dimensions [m]
    "round": ("d",),  # solid, diameter d
    "tube": ("d", "t"),  # round tube, outer diameter d, wall t
    "rect_tube": ("b", "h", "t"),  # rectangular tube, width b (along y), height h (along z), wall t
    "given": ("A", "I_y", "I_z", "J"),  # area [m^2], second moments about y and z and torsion constant [m^4]
}
ELASTIC_FIELDS = (
    Field("material", f"one of {', '.join(MATERIALS)}, or a table {{E, G, density}} of expressions [Pa, Pa, "
          "kg/m^3]", "the beams' material", required=True),
    Field("section", f"a table {{shape, its dimensions}}: shape one of {', '.join(SECTIONS)} ("
          + "; ".join(f"{k}: {', '.join(v)}" for k, v in SECTIONS.items()) + ") of expressions [m, m^2, m^4]",
          "each beam's section: in the plane I_z bends it in the plane; in space its two second moments equal",
          required=True),
    Field("drive", "an expression [N m/rad, N/m on a prismatic joint], positive", "the actuated joint's "
          "stiffness (the drive and its transmission); rigid where absent"),
    Field("passive", "a list of expressions [N m/rad, N/m on a prismatic joint], one per passive joint variable, "
          "each positive, or 0", "each passive joint's stiffness for its own motion (relative to the link before it: "
          "a flexure's, a spring's), in order from the base (a universal joint's or a parallelogram's two); 0 or "
          "absent: free"),
    Field("bearings", "a list of expressions [N/m], one per joint the leg draws from the base (the platform's "
          "included), each positive", "each joint's bearing as a translational spring at the joint: a revolute's "
          "radial stiffness in the plane, the same in every direction in space (its tilt rigid); rigid where absent"),
    Field("tilts", "a list of expressions [N m/rad], one per joint the leg draws from the base (the platform's "
          "included), each positive, or 0", "in space, each revolute's bearing tilt stiffness: its rotation about "
          "the two axes across its own at the joint, a spring each (a chain's revolutes, a kind's first joint where "
          "it is one); 0, absent, or a joint that is not such a revolute: rigid"),
    Field("beams", "a list of tables {material, section}", "each beam of the leg in order from the base (its links "
          "after a revolute, a universal joint or a parallelogram, whose rods count twice), each field optional: "
          "where given, it replaces the leg's"),
)
BEAM_FIELDS = (Field("material", ELASTIC_FIELDS[0].holds, "the beam's material; the leg's by default"),
               Field("section", ELASTIC_FIELDS[1].holds, "the beam's section; the leg's by default"))
ELASTIC = Field("elastic", "a table {material, section, drive, passive, bearings, tilts, beams} (Elastic elements)",
                "the leg's elastic elements: its links as Euler-Bernoulli beams clamped at their joints, its drive, "
                "its passive joints and its joints' bearings as springs; where one leg has them every leg does")
BEAM_JOINTS = ("R", "U", "parallelogram")  # a chain joint whose non-zero link is a beam
SHAPES = {"disc": (2, 1, "its radius"), "rectangle": (2, 2, "its half extents"), "box": (3, 3, "its half extents"),
          "cylinder": (3, 2, "its radius and half length")}  # a region's dimension, its size's entries, their meaning
REGION_FIELDS = (
    Field("name", IDENTIFIER, "the region's name, given once, other than reachable and assembled", required=True),
    Field("doc", TEXT, "what the region is; its name by default"),
    Field("shape", f"one of {', '.join(SHAPES)}", "its shape: "
          + "; ".join(f"{s} ({d} coordinates)" for s, (d, _, _) in SHAPES.items()), required=True),
    Field("coordinates", "a list of pose coordinates' names", "the distinct pose coordinates it spans, the pose's "
          "first by default; the others stay at the home pose's values"),
    Field("centre", "a list of expressions [the coordinates' units]", "its centre, a value per coordinate",
          required=True),
    Field("size", "a list of expressions [the coordinates' units]", "its size, positive: "
          + "; ".join(f"a {s}'s {meaning.removeprefix('its ')}" for s, (_, _, meaning) in SHAPES.items()),
          required=True),
    Field("axis", "a pose coordinate's name", "a cylinder's axis, one of its coordinates; the last by default"),
)


@dataclass(frozen=True)
class Kind:
    """A kind of leg: the space it moves in, what it is, its own fields (beside :data:`LEG_FIELDS`), the words
    for the two branches of its inverse kinematics (sign +1, then -1; none where it has one), what they mean,
    its actuated joint's unit, its passive angles, whether its passive joints have two branches too (their side
    names the assembly modes), its bodies, the joints drawn, and the chain of joints a leg of it is: ``chain``
    takes the leg's own fields as expression texts (a direction a list of them) and gives the joints as a chain
    leg's ``joints`` table states them, in the base's frame (``turn`` 0); None for a chain, whose joints are its
    own. ``follows``: the passive angles that the kind measures from the base's frame, not from the link before
    them (an RR's distal angle): each is its chain joint's own angle plus the actuated joint's."""

    space: str
    doc: str
    fields: tuple[Field, ...]
    branches: tuple[str, ...]
    meaning: str
    unit: str
    passive: int
    sided: bool
    bodies: tuple[Field, ...]
    points: int  # joints drawn, from the base's to the platform's
    chain: Callable[[Mapping[str, Any]], list[dict[str, Any]]] | None = None
    follows: tuple[int, ...] = ()  # passive angles measured from the base's frame: they turn with the actuated joint

    @property
    def branched(self) -> bool:
        return bool(self.branches)

    @property
    def lengths(self) -> tuple[str, ...]:
        """Its lengths: the fields that are positive lengths."""
        return tuple(f.name for f in self.fields if f.holds == LENGTH)


ZEROS = ("0", "0.0")  # expression texts of zero


def _product(a: str, b: str) -> str:
    """The expression text a times b, zero where either is."""
    return "0" if a in ZEROS or b in ZEROS else f"({a}) * ({b})"


def _difference(a: str, b: str) -> str:
    """The expression text a less b, without a zero term."""
    return a if b in ZEROS else f"-({b})" if a in ZEROS else f"{a} - {b}"


def _times(length: str, direction: list[str]) -> list[str]:
    """The vector ``length`` times ``direction``, each coordinate an expression text."""
    return [_product(length, c) for c in direction]


def _cross(u: list[str], v: list[str]) -> list[str]:
    """The cross product u x v of two directions of three expression texts."""
    return [_difference(_product(u[(i + 1) % 3], v[(i + 2) % 3]), _product(u[(i + 2) % 3], v[(i + 1) % 3]))
            for i in range(3)]


KINDS = {
    "RR": Kind(
        space="planar",
        doc="an actuated revolute at the base attachment, a link of length proximal to a passive revolute (the "
            "elbow), a link of length distal to the platform's revolute",
        fields=(Field("proximal", LENGTH, "the actuated link, from the base joint to the elbow", required=True),
                Field("distal", LENGTH, "the passive link, from the elbow to the platform joint", required=True),
                LEG_BODIES),
        branches=("left", "right"),
        meaning="the elbow left or right of the line from the base joint to the platform joint, seen from +z",
        unit="rad", passive=1, sided=True,
        bodies=(Field("proximal", BODY, "the actuated link, its centre from the base joint, its inertia about z"),
                Field("distal", BODY, "the passive link, its centre from the elbow, its inertia about z")),
        points=3,
        chain=lambda leg: [{"type": "R", "actuated": True, "link": [leg["proximal"], "0"]},
                           {"type": "R", "link": [leg["distal"], "0"]}],
        follows=(0,)),
    "RPR": Kind(
        space="planar",
        doc="a passive revolute at the base attachment, an actuated prismatic joint along the leg (its length, to "
            "the platform joint), a passive revolute at the platform attachment",
        fields=(LEG_BODIES,), branches=(), meaning="", unit="m", passive=1, sided=False,
        bodies=(Field("cylinder", BODY, "the part on the base joint, its centre from it, its inertia about z"),
                Field("piston", BODY, "the part on the platform joint, its centre from it, its inertia about z")),
        points=2,
        chain=lambda _leg: [{"type": "R"}, {"type": "P", "actuated": True, "axis": ["1", "0"]}]),
    "PRR": Kind(
        space="planar",
        doc="an actuated prismatic joint (a slider) along axis (its position from the base attachment), a passive "
            "revolute on it, a "
            "link of length distal to the platform's revolute",
        fields=(Field("distal", LENGTH, "the link, from the slider's joint to the platform joint", required=True),
                Field("axis", "a direction: a list of 2 expressions", "the slide's direction", required=True),
                LEG_BODIES),
        branches=("ahead", "behind"),
        meaning="the slider ahead of or behind the platform joint's foot on the slide's axis",
        unit="m", passive=1, sided=True,
        bodies=(Field("slider", POINT_BODY, "the slider, its mass at its joint"),
                Field("distal", BODY, "the link, its centre from the slider's joint, its inertia about z")),
        points=3,
        chain=lambda leg: [{"type": "P", "actuated": True, "axis": leg["axis"]},
                           {"type": "R", "link": [leg["distal"], "0"]}]),
    "R_parallelogram": Kind(
        space="spatial",
        doc="an actuated revolute at the base attachment about axis, turning an arm of length arm from the "
            "direction zero (its angle 0) towards axis x zero, and a parallelogram of rods of length rod from the "
            "arm's tip to the platform joint",
        fields=(Field("arm", LENGTH, "the arm, from the motor's axis to the rods' joints", required=True),
                Field("rod", LENGTH, "the parallelogram's rods", required=True),
                Field("axis", "tangent, or a unit direction: a list of 3 expressions",
                      "the motor's axis; tangent to the base's circle by default, given with zero where the base is "
                      "not a pattern"),
                Field("zero", "radial, or a unit direction across axis: a list of 3 expressions",
                      "the arm's direction at its angle 0; radial to the base's circle by default"),
                LEG_BODIES),
        branches=("ccw", "cw"),
        meaning="the arm turned counter-clockwise or clockwise about its axis from the plane of the axis and the "
                "platform joint",
        unit="rad", passive=2, sided=False,
        bodies=(Field("arm", BODY, "the arm, its centre from the motor's axis, its inertia about that axis"),
                Field("rod", POINT_BODY, "both rods of the parallelogram: half the mass at the arm's tip, half at "
                      "the platform joint")),
        points=3,
        chain=lambda leg: [{"type": "R", "actuated": True, "axis": leg["axis"],
                            "link": _times(leg["arm"], leg["zero"])},
                           {"type": "parallelogram", "axes": [leg["axis"], _cross(leg["zero"], leg["axis"])],
                            "link": _times(leg["rod"], leg["zero"])},
                           {"type": "S"}],
        follows=(0,)),
    "UPS": Kind(
        space="spatial",
        doc="a universal joint at the base attachment, an actuated prismatic joint along the leg (its length), a "
            "spherical joint at the platform attachment",
        fields=(Field("cone", CONE, "the joints' range: the largest angle of the leg from the base's normal at its "
                      "universal joint and from the platform's at its spherical joint, a stated limit beside its "
                      "reach"),
                LEG_BODIES),
        branches=(), meaning="", unit="m", passive=0, sided=False,
        bodies=(Field("cylinder", BODY, "the part on the base joint, its centre from it, its inertia about an axis "
                      "across the leg"),
                Field("piston", BODY, "the part on the platform joint, its centre from it, its inertia about an axis "
                      "across the leg")),
        points=2,
        chain=lambda _leg: [{"type": "U", "axes": [["1", "0", "0"], ["0", "1", "0"]]},
                           {"type": "P", "actuated": True, "axis": ["0", "0", "1"]}, {"type": "S"}]),
}
CHAIN = "chain"  # the kind of a leg given as a serial chain of joints, solved by continuation
CHAIN_DOC = ("a serial chain of joints from the base attachment to the platform's point joint (a revolute in the "
             "plane, a spherical joint in space), in closed form where its joints match a known subproblem, else by "
             "Newton continuation from its branches' seeds")
CHAIN_MEANING = "the leg's joints continued from the branch's seed at the home pose"
CHAIN_FIELDS = (
    Field("joints", "a list of joint tables (Chain joints)", "the chain's joints from the base attachment, with as "
          "many joint variables as the closure at the platform's point joint has equations (2 in the plane, 3 in "
          "space), exactly one actuated", required=True),
    Field("branches", "a table: name = a list of numbers", "one or two seeds by name, each the joints' values (a U's "
          "two in order) at the home pose and the default design, roughly: where the branch is continued from (the "
          "first sign +1)", required=True),
    Field("turn", "a list of count expressions [rad]", "each leg's frame turned about z from the base's; the "
          "circle's angle where the base is a pattern, else 0, by default"),
    Field("newton", "true or false", "solved by Newton continuation even where a closed form matches the chain; "
          "false by default"),
)
MAX_LAYER = 15  # a link's layer at most
LEG_FIELDS = (
    Field("kind", "a leg kind (Leg kinds)", f"one of {', '.join((*KINDS, CHAIN))}", required=True),
    Field("count", "an integer from 1 to 12", "the legs of the table; 1 by default"),
    Field("base", "a list of points or a pattern (Attachment patterns)", "each leg's base attachment in the base "
          f"frame: a list of count points, each a list of expressions ({EACH}) [m], or a pattern, in space in the "
          "plane z = 0", required=True),
    Field("platform", "a list of points or a pattern (Attachment patterns)", "each leg's platform attachment in the "
          "platform frame", required=True),
    Field("range", "a list [lower, upper] of expressions [the actuated joint's unit]", "the actuated joint's stated "
          "range (a stroke, an arm's sweep): outside it a pose is out of reach; a revolute's within a turn, spanning "
          "at most one"),
    ELASTIC,
    Field("capsule", LENGTH, "the radius of the capsules around the leg's links (each segment of its drawing, "
          "from joint to joint): two legs' capsules that meet collide (the collision margin, docs/certify.md); "
          "where one leg has it every leg does"),
    Field("layers", f"a list of integers from 0 to {MAX_LAYER}, one per segment of the leg's drawing from the base",
          "the layer each link is built in: two legs' segments collide only in one layer (in the plane, links built "
          "one above another pass over each other), a plate meets every layer; all 0 by default; needs the capsule"),
)


def leg_fields(kind: str) -> tuple[Field, ...]:
    """The fields of a leg table of a kind: those of every leg, then the kind's own."""
    return (*LEG_FIELDS, *(CHAIN_FIELDS if kind == CHAIN else KINDS[kind].fields))


@dataclass(frozen=True)
class JointType:
    """A type of a chain's joints: what it is, its joint variables, whether a planar chain may hold it, its
    fields and the frame of the body after it."""

    doc: str
    variables: int
    planar: bool
    fields: tuple[Field, ...]
    frame: str


JOINT_FIELD = Field("type", "a joint type (Chain joints)", "the joint's type", required=True)
LINK = Field("link", f"a vector: a list of expressions ({EACH}) [m]", "to the next joint (the last's to the "
             "platform joint), fixed in the frame the joint turns or slides; zero by default")
ACTUATED = Field("actuated", "true or false", "whether it is the leg's actuated joint (one per leg, an R or a P); "
                 "false by default")
JOINT_BODY = Field("body", f"{BODY} (Bodies)", "the body after it, its centre a point of its frame from the joint")
AXES = Field("axes", "two directions: lists of 3 expressions", "the axes it turns about, the first in the frame of "
             "the body before it, the second in the frame the first turns", required=True)
JOINTS = {
    "R": JointType("a revolute joint, turning about its axis", 1, True, (
        JOINT_FIELD, Field("axis", "a direction: a list of 3 expressions", "in space, the axis it turns about in the "
                           "frame of the body before it, [0, 0, 1] by default; absent in the plane (about z)"),
        LINK, ACTUATED, JOINT_BODY, ROTOR), "the frame before it turned by its angle about its axis"),
    "P": JointType("a prismatic joint, sliding along its axis", 1, True, (
        JOINT_FIELD, Field("axis", f"a direction: a list of expressions ({EACH})", "the direction it slides along in "
                           "the frame of the body before it", required=True),
        LINK, ACTUATED, JOINT_BODY, ROTOR), "the frame before it, its origin slid by its value along its axis"),
    "U": JointType("a universal joint, turning about its two axes, the second turned by the first", 2, False,
                   (JOINT_FIELD, AXES, LINK, ACTUATED, JOINT_BODY),
                   "the frame before it turned by its first angle about its first axis, then by its second about its "
                   "second"),
    "parallelogram": JointType("a parallelogram: its rods (its link) turned like a universal joint's link, the body "
                               "after it keeping the frame of the body before it; its body is its rods", 2, False,
                               (JOINT_FIELD, AXES, LINK, ACTUATED, JOINT_BODY),
                               "the frame before it, moved to its link's end (its rods turned as a universal joint's "
                               "link)"),
    "S": JointType("the platform's spherical joint, passive: last in a spatial chain, which ends there without it "
                   "too", 0, False, (JOINT_FIELD, ACTUATED), "the platform's"),
}
PLATFORM_JOINT = "S"  # the joint type that only ends a spatial chain
# the types of a chain's joints with joint variables, and how many each has
CHAIN_JOINTS = {name: joint.variables for name, joint in JOINTS.items() if joint.variables}


def kind_of(leg: Mapping[str, Any]) -> Kind:
    """The kind of a normalised leg: a known subproblem's (:data:`KINDS`), or a chain's from its joints (its
    branches named by its seeds, sided by the sign of its closure's Jacobian in its joints)."""
    if leg["kind"] != CHAIN:
        return KINDS[leg["kind"]]
    actuated = next(j for j in leg["joints"] if j["actuated"])
    branches = tuple(name for name, _ in leg["branches"]) if len(leg["branches"]) == 2 else ()
    return Kind(space="planar" if len(leg["joints"][0]["link"]) == 2 else "spatial", doc=CHAIN_DOC,
                fields=CHAIN_FIELDS, branches=branches, meaning=CHAIN_MEANING,
                unit="rad" if actuated["type"] == "R" else "m",
                passive=sum(CHAIN_JOINTS[j["type"]] for j in leg["joints"]) - 1, sided=True, bodies=(),
                points=len(leg["joints"]) + 1)


def passive_angles(leg: Mapping[str, Any]) -> tuple[bool, ...]:
    """Whether each of a normalised leg's passive joints is an angle."""
    if leg["kind"] != CHAIN:
        return (True,) * KINDS[leg["kind"]].passive
    return tuple(j["type"] != "P" for j in leg["joints"] if not j["actuated"] for _ in range(CHAIN_JOINTS[j["type"]]))


def is_free(tree: Any) -> bool:
    """Whether a passive joint's stiffness (an expression tree) is the literal 0 of a free joint."""
    return isinstance(tree, int | float) and not isinstance(tree, bool) and tree == 0


def passive_stiffness(leg: Mapping[str, Any]) -> list[Any]:
    """A normalised leg's passive joints' stiffness expressions in order, None for a free one (0, or not given)."""
    given = leg.get("elastic", {}).get("passive")
    if given is None:
        return [None] * len(passive_angles(leg))
    return [None if is_free(t) else t for t in given]


def beams(leg: Mapping[str, Any]) -> list[int]:
    """The chain joints (indices) of a normalised leg whose link is a beam: a non-zero link after a revolute, a
    universal joint or a parallelogram (a prismatic joint's link moves with its slide: not a beam)."""
    return [j for j, joint in enumerate(leg["joints"]) if joint["type"] in BEAM_JOINTS
            and any(not (isinstance(c, int | float) and c == 0) for c in joint.get("link", []))]


def rods(leg: Mapping[str, Any], j: int) -> int:
    """How many parallel beams chain joint j's link is: a parallelogram's two rods, else one."""
    return 2 if leg["joints"][j]["type"] == "parallelogram" else 1
