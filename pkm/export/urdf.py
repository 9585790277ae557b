"""The Extended URDF of a cut structure (:mod:`pkm.export.structure`): ``robot.urdf`` (the tree),
``robot.yaml`` (the closures and motors, in the format of Gepetto's example-parallel-robots, which Pinocchio's
loaders there read) and ``README.md`` (what was cut and why, frames, units, how to load it), written together
into a folder: into a temporary folder beside it first, then each file moved in by an atomic rename, so that
nothing half-written is ever left there."""

from __future__ import annotations

import json
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from pkm import io
from pkm.errors import PkmError
from pkm.export.structure import Tree, UrdfJoint, UrdfLink, rpy

URDF, YAML, README = "robot.urdf", "robot.yaml", "README.md"
WRITER = "pkm (pkm.export)"
PINOCCHIO_GRAVITY = np.array([0.0, 0.0, -9.81])


def number(value: float) -> str:
    """The shortest text that reads back as the same float (no negative zero)."""
    value = float(value)
    return repr(value + 0.0)


def _vector(values: np.ndarray) -> str:
    return " ".join(number(v) for v in values)


def _comment(text: str, indent: str = "") -> str:
    """An XML comment of ``text`` (a comment cannot hold a double hyphen)."""
    lines = text.replace("--", "- -").splitlines() or [""]
    if len(lines) == 1:
        return f"{indent}<!-- {lines[0]} -->"
    return "\n".join([f"{indent}<!--", *(f"{indent}  {line}".rstrip() for line in lines), f"{indent}-->"])


def _design_lines(parameters: list[tuple[str, float, str, str]]) -> list[str]:
    return [f"{name} = {number(value)} {unit}: {doc}" for name, value, unit, doc in parameters]


def _pose_text(tree: Tree, pose_names: tuple[str, ...], pose_units: tuple[str, ...]) -> str:
    pose = tree.structure.reference.pose
    return ", ".join(f"{n} = {number(v)} {u}" for n, v, u in zip(pose_names, pose, pose_units, strict=True))


def _origin(transform: np.ndarray) -> str:
    return f'<origin xyz="{_vector(transform[:3, 3])}" rpy="{_vector(rpy(transform[:3, :3]))}"/>'


def _link(link: UrdfLink) -> list[str]:
    out = [f"  <link name={quoteattr(link.name)}>", _comment(link.doc, "    ")]
    if link.massive:
        t = link.tensor
        out += [
            "    <inertial>",
            f'      <origin xyz="{_vector(link.centre)}" rpy="0 0 0"/>',
            f'      <mass value="{number(link.mass)}"/>',
            f'      <inertia ixx="{number(t[0, 0])}" ixy="{number(t[0, 1])}" ixz="{number(t[0, 2])}" '
            f'iyy="{number(t[1, 1])}" iyz="{number(t[1, 2])}" izz="{number(t[2, 2])}"/>',
            "    </inertial>",
        ]
    return [*out, "  </link>"]


def _joint(joint: UrdfJoint) -> list[str]:
    out = [f"  <joint name={quoteattr(joint.name)} type={quoteattr(joint.type)}>", _comment(joint.doc, "    "),
           f"    <parent link={quoteattr(joint.parent)}/>", f"    <child link={quoteattr(joint.child)}/>",
           f"    {_origin(joint.origin)}"]
    if joint.axis is not None:
        out.append(f'    <axis xyz="{_vector(joint.axis)}"/>')
    if joint.limits is not None:
        lower, upper = joint.limits
        out.append(f'    <limit lower="{number(lower)}" upper="{number(upper)}" effort="0" velocity="0"/>')
    if joint.mimic is not None:
        other, multiplier = joint.mimic
        out.append(f'    <mimic joint={quoteattr(other)} multiplier="{number(multiplier)}" offset="0"/>')
    return [*out, "  </joint>"]


def _header(tree: Tree, mech: object, parameters: list[tuple[str, float, str, str]]) -> list[str]:
    s = tree.structure
    return [
        f"{s.mechanism}: {s.doc}",
        f"Written by {WRITER}: a tree cut from the mechanism's loops; {YAML} names the closures and the motors "
        f"(Gepetto's Extended URDF), {README} says what was cut and why.",
        "Units: SI (m, rad, kg, kg m^2). Frames: the base link's frame is the frame of the mechanism's pose; every "
        "joint is zero at the reference configuration below, where every loop closes.",
        f"Reference configuration: {_pose_text(tree, mech.pose_names, mech.pose_units)}; working mode "
        f"{s.reference.mode}.",
        "Limits are relative to the reference configuration; effort and velocity limits are not stated (0).",
        "Design parameters:",
        *(f"  {line}" for line in _design_lines(parameters)),
    ]


def urdf_text(tree: Tree, mech: object, parameters: list[tuple[str, float, str, str]]) -> str:
    lines = ['<?xml version="1.0"?>', _comment("\n".join(_header(tree, mech, parameters))),
             f"<robot name={quoteattr(tree.structure.mechanism)}>"]
    for link in tree.links:
        lines += _link(link)
    for joint in tree.joints:
        lines += _joint(joint)
    return "\n".join([*lines, "</robot>", ""])


def _yaml_value(value: object) -> str:
    """A value in YAML's flow style that YAML 1.1 readers (PyYAML) read back as it is: floats always with a
    decimal point."""
    if isinstance(value, float):
        text = number(value)
        mantissa, e, exponent = text.partition("e")
        return text if "." in mantissa or not e else f"{mantissa}.0e{exponent}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_yaml_value(v) for v in value) + "]"
    return json.dumps(value)


def yaml_text(tree: Tree, mech: object, parameters: list[tuple[str, float, str, str]]) -> str:
    s = tree.structure
    comments = [*_header(tree, mech, parameters), "",
                "closed_loop: the frame pairs that coincide (3d: origins, 6d: placements); name_mot: the motors.",
                "pkm: pkm's actuators of the motors in order; pkm's value of each is the URDF joint's plus its offset."]
    lines = [f"# {line}".rstrip() for line in comments]
    lines += [
        f"closed_loop: {_yaml_value([list(c.frames) for c in tree.closures])}",
        f"type: {_yaml_value([c.type for c in tree.closures])}",
        f"name_mot: {_yaml_value([m.joint for m in tree.motors])}",
        "pkm:",
        f"  mechanism: {_yaml_value(s.mechanism)}",
        f"  mode: {_yaml_value(s.reference.mode)}",
        f"  pose: {_yaml_value([float(v) for v in s.reference.pose])}",
        f"  pose_names: {_yaml_value(list(mech.pose_names))}",
        f"  actuators: {_yaml_value([m.actuator for m in tree.motors])}",
        f"  offset: {_yaml_value([float(m.offset) for m in tree.motors])}",
        f"  effector: {_yaml_value(tree.effector)}",
    ]
    if s.gravity is not None:
        lines.append(f"  gravity: {_yaml_value([float(g) for g in s.gravity])}")
    return "\n".join([*lines, ""])


def _table(rows: list[list[str]]) -> list[str]:
    head, *body = rows
    return ["| " + " | ".join(head) + " |", "|" + "---|" * len(head), *("| " + " | ".join(r) + " |" for r in body)]


def readme_text(tree: Tree, mech: object, parameters: list[tuple[str, float, str, str]]) -> str:
    s = tree.structure
    motors = {m.joint: m for m in tree.motors}
    joint_rows = [["joint", "type", "parent -> child", "pkm's coordinate at zero", "what it is"]]
    for joint in tree.joints:
        if joint.type == "fixed":
            continue
        motor = motors.get(joint.name)
        zero = f"{motor.actuator} = {number(motor.offset)} {motor.unit}" if motor else ""
        if joint.mimic is not None:
            zero = f"mimics {joint.mimic[0]} x {number(joint.mimic[1])}"
        joint_rows.append([f"`{joint.name}`", joint.type, f"{joint.parent} -> {joint.child}", zero, joint.doc])
    closure_rows = [["frames", "type", "cut joint", "why"]]
    closure_rows += [[f"`{c.frames[0]}`, `{c.frames[1]}`", c.type, f"`{c.joint}`", c.doc] for c in tree.closures]
    if s.gravity is None:
        gravity = "The mechanism states no gravity."
    else:
        gravity = f"Gravity in the base frame: ({_vector(s.gravity)}) m/s^2" + (
            ", Pinocchio's default." if np.allclose(s.gravity, PINOCCHIO_GRAVITY, rtol=0, atol=1e-12) else
            f"; Pinocchio's default is ({_vector(PINOCCHIO_GRAVITY)}): set `model.gravity.linear` to it.")
    mimic = [] if not any(j.mimic for j in tree.joints) else [
        "",
        "Mimic joints: load with `mimic=True`. In Pinocchio 4.1, `RigidConstraintModel.jacobian` misplaces the "
        "columns after a mimic joint and `crba` is wrong where a mimic joint has bodies below it: take the "
        "closures' Jacobians from the frames' (`getFrameJacobian`) and the mass matrix as the sum of J_i^T I_i J_i "
        "over the joints (`getJointJacobian` in LOCAL), as pkm's tests do.",
    ]
    lines = [
        f"# {s.mechanism}: Extended URDF",
        "",
        f"{s.doc}. Written by {WRITER}.",
        "",
        f"- `{URDF}`: the mechanism cut open into a tree (links with their masses and inertias where the mechanism has "
        "bodies, joints with their axes and limits).",
        f"- `{YAML}`: the loop closures (`closed_loop`: pairs of frames, `type`: `3d` where their origins coincide, "
        "`6d` where their placements do) and the motors (`name_mot`), as Gepetto's example-parallel-robots reads "
        "them; `pkm` holds pkm's names of the motors and the offsets from the URDF's zero to pkm's coordinates.",
        "",
        "## Units and frames",
        "",
        "SI throughout: metres, radians, kilograms, kg m^2. The base link's frame is the frame of pkm's pose "
        f"({', '.join(f'{n} [{u}]' for n, u in zip(mech.pose_names, mech.pose_units, strict=True))}). Every joint is "
        "zero at the reference configuration, where every loop closes:",
        "",
        f"- pose: {_pose_text(tree, mech.pose_names, mech.pose_units)}",
        f"- working mode: {s.reference.mode}",
        "",
        f"The frame `{tree.effector}` is the end effector: {s.effector.doc}.",
        "A motor's pkm coordinate is its URDF joint's value plus the offset below. Joint limits are relative to the "
        "reference configuration; effort and velocity limits are not stated (written as 0).",
        "",
        gravity,
        "",
        "## Design",
        "",
        *(f"- {line}" for line in _design_lines(parameters)),
        "",
        "## What was cut and why",
        "",
        *(f"- {note}" for note in s.notes),
        "",
        *_table(closure_rows),
        "",
        "## Joints",
        "",
        *_table(joint_rows),
        "",
        "## Loading it in Pinocchio",
        "",
        "```python",
        "import pinocchio as pin",
        "import yaml",
        "",
        f'model = pin.buildModelFromUrdf("{URDF}", mimic=True)  # mimic=True reads the coupled joints',
        f'closures = yaml.safe_load(open("{YAML}"))',
        "constraints = []",
        'for (a, b), kind in zip(closures["closed_loop"], closures["type"]):',
        "    fa, fb = (model.frames[model.getFrameId(name)] for name in (a, b))",
        '    contact = pin.ContactType.CONTACT_3D if kind == "3d" else pin.ContactType.CONTACT_6D',
        "    constraints.append(pin.RigidConstraintModel(contact, model, fa.parentJoint, fa.placement,",
        "                                                fb.parentJoint, fb.placement, pin.ReferenceFrame.LOCAL))",
        "```",
        "",
        "`pin.neutral(model)` is the reference configuration and closes every loop. Gepetto's "
        "`example_parallel_robots.loader_tools.completeRobotLoader` reads the same two files.",
        *mimic,
        "",
    ]
    return "\n".join(lines)


def write(tree: Tree, mech: object, parameters: list[tuple[str, float, str, str]], folder: Path) -> Path:
    """Write the three files into ``folder`` (created if need be) together; :class:`PkmError` naming the folder
    where it cannot be written."""
    folder = Path(folder)
    texts = {URDF: urdf_text(tree, mech, parameters), YAML: yaml_text(tree, mech, parameters),
             README: readme_text(tree, mech, parameters)}
    try:
        with io.staged_folder(folder) as stage:
            for name, text in texts.items():
                (stage / name).write_text(text)
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise PkmError(f"folder {str(folder)!r} violates: a folder that can be written ({reason})") from None
    return folder

