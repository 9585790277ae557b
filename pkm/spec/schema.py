"""A machine description checked and normalised (DESIGN.md section 6b): :func:`describe` takes a mapping (or
:func:`read` a TOML file) of the fields of :data:`pkm.spec.vocabulary.DESCRIPTION_FIELDS` and returns a
:class:`Description`, or raises :class:`DescriptionError` naming the field and the violated condition.

Every coordinate and length is an expression of the parameters with ``pi`` and
:data:`pkm.expressions.FUNCTIONS`, read into :mod:`pkm.expressions`' tree (never evaluated as Python; the
normalised description holds the trees)."""

from __future__ import annotations

import hashlib
import json
import math
import os
import reprlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions, io
from pkm.spec.checks import (
    DescriptionError,
    check_fields,
    choice,
    compose,
    convex,
    expression,
    fail,
    identifier,
    number,
    plate_corners,
    plate_order,
    text,
    trees,
)
from pkm.spec.elastic_schema import check_elastic, elastic
from pkm.spec.vocabulary import (
    BODY_FIELDS,
    CHAIN,
    CHAIN_JOINTS,
    CONDITION_FIELDS,
    CONE,
    DESCRIPTION_FIELDS,
    FRAMES,
    IDENTIFIER,
    JOINTS,
    KINDS,
    LENGTH,
    MAX_LAYER,
    PARAMETER_FIELDS,
    PATTERN_FIELDS,
    PLATE_FIELDS,
    PLATES,
    PLATFORM_JOINT,
    POINT_BODY,
    REGION_FIELDS,
    ROTOR,
    SHAPES,
    Field,
    kind_of,
    leg_fields,
)

SUFFIX = ".toml"  # a mechanism name with it is a description file
ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Description:
    """A checked, normalised description: every leg with its attachments and lengths as expressions."""

    data: Mapping[str, Any]

    @property
    def name(self) -> str:
        return self.data["name"]

    @cached_property
    def key(self) -> str:
        """The sha256 of the normalised description (in its order: the first mode is the default), the
        deriving modules and CasADi's version."""
        return hashlib.sha256(json.dumps([self.data, _tool_versions()]).encode()).hexdigest()


def _tool_versions() -> dict[str, str]:
    """CasADi's version and the digest of the modules that derive a description: symbolic/'s shared ones,
    symbolic/described/, the evaluator of its expressions (pkm/expressions.py) and the vocabulary it reads
    (pkm/spec/vocabulary.py)."""
    here = ROOT / "symbolic"
    sources = sorted([*here.glob("*.py"), *(here / "described").glob("*.py"), ROOT / "pkm" / "expressions.py",
                      ROOT / "pkm" / "spec" / "vocabulary.py"])
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sources)).hexdigest()
    return {"casadi": ca.__version__, "symbolic": digest}


def _parameters(raw: Any) -> list[dict[str, Any]]:
    table = f"{{{', '.join(f.name for f in PARAMETER_FIELDS)}}}"
    if not isinstance(raw, list) or not raw:
        raise fail("parameters", f"a non-empty list of {table}")
    out, seen = [], set()
    for k, p in enumerate(raw):
        where = f"parameters[{k}]"
        if not isinstance(p, Mapping):
            raise fail(where, f"a table {table}")
        check_fields(p, PARAMETER_FIELDS, where, "a parameter")
        name = p.get("name")
        if not identifier(name) or name in expressions.RESERVED:
            raise fail(f"{where}.name", f"{IDENTIFIER}, other than "
                                         f"{', '.join(expressions.RESERVED)}")
        if name in seen:
            raise fail(f"{where}.name", f"a name not given before; {name} is")
        seen.add(name)
        lower, upper = number(f"{where}.lower", p["lower"]), number(f"{where}.upper", p["upper"])
        default = number(f"{where}.default", p.get("default"))
        if not lower < upper:
            raise fail(f"{where}", f"lower < upper; got {lower:g}, {upper:g}")
        if not lower <= default < upper:
            raise fail(f"{where}.default", f"{lower:g} <= default < {upper:g}; got {default:g}")
        unit, doc = text(f"{where}.unit", p.get("unit", "-")), text(f"{where}.doc", p.get("doc", ""))
        out.append({"name": name, "default": default, "lower": lower, "upper": upper, "unit": unit, "doc": doc})
    return out


def _angles(pattern: Mapping[str, Any], count: int, field: str, names: set[str]) -> list[expressions.Tree]:
    start = expression(f"{field}.start", pattern.get("start", 0), names)
    if "pairs" not in pattern:
        return [compose(f"{field}.start", f"{{start}} + 2*pi*{i}/{count}", names, start=start) for i in range(count)]
    if count % 2:
        raise fail(f"{field}.pairs", f"an even count of legs; got {count}")
    apart = expression(f"{field}.pairs", pattern["pairs"], names)
    return [compose(f"{field}.pairs", f"{{start}} + 2*pi*{i // 2}/{count // 2} {'-' if i % 2 == 0 else '+'} "
                     "{apart}/2", names, start=start, apart=apart) for i in range(count)]


def _points(raw: Any, count: int, dim: int, field: str, names: set[str]
            ) -> tuple[list[list[expressions.Tree]], list[expressions.Tree] | None]:
    """``count`` points of ``dim`` expressions, and the circle's angles where a pattern gave them."""
    if isinstance(raw, Mapping):
        check_fields(raw, PATTERN_FIELDS, field, "a pattern")
        radius = expression(f"{field}.circle", raw["circle"], names)
        angles = _angles(raw, count, field, names)
        plane = [[compose(f"{field}.circle", f"{{r}}*{f}({{a}})", names, r=radius, a=a) for f in ("cos", "sin")]
                 for a in angles]
        return [p + [0] * (dim - 2) for p in plane], angles
    if not isinstance(raw, list) or len(raw) != count:
        raise fail(field, f"a list of {count} points (one per leg) or a pattern {{circle, start, pairs}}")
    points = []
    for i, point in enumerate(raw):
        if not isinstance(point, list) or len(point) != dim:
            raise fail(f"{field}[{i}]", f"a point of {dim} coordinates")
        points.append([expression(f"{field}[{i}][{j}]", c, names) for j, c in enumerate(point)])
    return points, None


def _body(raw: Any, field: str, names: set[str], *, centre: int, inertia: int) -> dict[str, Any]:
    """A body {mass, centre (``centre`` expressions: 0 for none, 1 a distance, 2 or 3 a point), inertia
    (``inertia`` expressions: 0 for none)}: mass required, the others 0 by default."""
    if not isinstance(raw, Mapping):
        raise fail(field, f"a table {{{', '.join(f.name for f in BODY_FIELDS)}}}")
    counts = {"centre": centre, "inertia": inertia}
    check_fields(raw, [f for f in BODY_FIELDS if counts.get(f.name, 1)], field, "this body")
    out: dict[str, Any] = {"mass": expression(f"{field}.mass", raw["mass"], names)}
    for key, count in (("centre", centre), ("inertia", inertia)):
        if not count:
            continue
        value = raw.get(key, [0] * count if count > 1 else 0)
        if count == 1:
            out[key] = expression(f"{field}.{key}", value, names)
        else:
            if not isinstance(value, list) or len(value) != count:
                raise fail(f"{field}.{key}", f"a list of {count} expressions")
            out[key] = [expression(f"{field}.{key}[{j}]", v, names) for j, v in enumerate(value)]
    return out


def _leg_bodies(raw: Any, kind: str, field: str, names: set[str]) -> dict[str, Any]:
    fields = (ROTOR, *KINDS[kind].bodies)
    if not isinstance(raw, Mapping):
        raise fail(field, f"a table of the {kind} leg's rotor and bodies ({', '.join(f.name for f in fields)})")
    check_fields(raw, fields, field, f"a {kind} leg's bodies")
    out: dict[str, Any] = {"rotor": expression(f"{field}.rotor", raw.get("rotor", 0), names)}
    for body in KINDS[kind].bodies:
        if body.name in raw:
            extent = int(body.holds != POINT_BODY)
            out[body.name] = _body(raw[body.name], f"{field}.{body.name}", names, centre=extent, inertia=extent)
    return out


def _legs(raw: Any, frame: str, names: set[str]) -> list[dict[str, Any]]:
    tables = [raw] if isinstance(raw, Mapping) else raw
    if not isinstance(tables, list) or not tables:
        raise fail("legs", "a table or a list of tables")
    planar = frame.startswith("planar")
    dim = 2 if planar else 3
    legs = []
    for t, table in enumerate(tables):
        where = "legs" if isinstance(raw, Mapping) else f"legs[{t}]"
        if not isinstance(table, Mapping):
            raise fail(where, "a table")
        kind = choice(f"{where}.kind", table.get("kind"), (*KINDS, CHAIN))
        if kind == CHAIN:
            legs += _chain_legs(table, where, frame, names)
            continue
        space, lengths = KINDS[kind].space, KINDS[kind].lengths
        if (space == "planar") != planar:
            raise fail(f"{where}.kind", f"a {'planar' if planar else 'spatial'} leg in a {frame} frame; {kind} is "
                                          f"{space}")
        count, base, angles, platform = _attachments(table, where, leg_fields(kind), f"a {kind} leg", dim=dim,
                                                      names=names)
        for i in range(count):
            leg = {"kind": kind, "base": base[i], "platform": platform[i],
                   **{n: expression(f"{where}.{n}", table[n], names) for n in lengths}}
            if "range" in table:
                bounds = table["range"]
                if not isinstance(bounds, list) or len(bounds) != 2:
                    raise fail(f"{where}.range", "a pair [lower, upper] of the actuated joint")
                leg["range"] = [expression(f"{where}.range[{j}]", b, names) for j, b in enumerate(bounds)]
            if "cone" in table:
                leg["cone"] = expression(f"{where}.cone", table["cone"], names)
            if "bodies" in table:
                leg["bodies"] = _leg_bodies(table["bodies"], kind, f"{where}.bodies", names)
            if kind == "PRR":
                if not isinstance(table["axis"], list) or len(table["axis"]) != 2:
                    raise fail(f"{where}.axis", "a direction of 2 expressions")
                leg["axis"] = [expression(f"{where}.axis[{j}]", c, names) for j, c in enumerate(table["axis"])]
            if kind == "R_parallelogram":
                if angles is None and ("axis" not in table or "zero" not in table):
                    raise fail(f"{where}.axis", "given with zero where the base is not a circle pattern")
                a = angles[i] if angles is not None else None
                leg["axis"] = [["neg", ["sin", a]], ["cos", a], 0] if table.get("axis", "tangent") == "tangent" \
                    else _vector(table["axis"], 3, f"{where}.axis", names)
                leg["zero"] = [["cos", a], ["sin", a], 0] if table.get("zero", "radial") == "radial" else \
                    _vector(table["zero"], 3, f"{where}.zero", names)
            leg["joints"] = _kind_chain(leg, where, dim, names)
            legs.append(_with_elements(leg, table, where, names))
    for name in ("elastic", "capsule"):
        given = [name in leg for leg in legs]
        if any(given) and not all(given):
            raise fail(f"legs.{name}", f"given on every leg where it is on one; leg {given.index(False) + 1} has none")
    for k, leg in enumerate(legs):
        if "elastic" in leg and leg["elastic"]["drive"] is None and not leg["elastic"]["beams"]:
            raise fail("legs.elastic", f"a drive or a beam on every leg; leg {k + 1} has neither and would be "
                                        "rigid")
    return legs


def _attachments(table: Mapping[str, Any], where: str, fields: Sequence[Field], what: str, *, dim: int,
                 names: set[str]) -> tuple[int, list[list[expressions.Tree]], list[expressions.Tree] | None,
                                           list[list[expressions.Tree]]]:
    """A leg table's fields checked against ``fields``, its count of legs, their base attachments (with the
    circle's angles where a pattern gives them) and their platform attachments."""
    check_fields(table, fields, where, what)
    count = table.get("count", 1)
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 12:
        raise fail(f"{where}.count", "an integer from 1 to 12")
    base, angles = _points(table.get("base"), count, dim, f"{where}.base", names)
    platform, _ = _points(table.get("platform"), count, dim, f"{where}.platform", names)
    return count, base, angles, platform


def _vector(raw: Any, dim: int, field: str, names: set[str]) -> list[expressions.Tree]:
    if not isinstance(raw, list) or len(raw) != dim:
        raise fail(field, f"a vector of {dim} expressions")
    return [expression(f"{field}[{j}]", c, names) for j, c in enumerate(raw)]


def _chain_joint(raw: Any, field: str, dim: int, names: set[str]) -> dict[str, Any]:
    types = tuple(t for t in CHAIN_JOINTS if dim == 3 or JOINTS[t].planar)
    if not isinstance(raw, Mapping):
        raise fail(field, "a table {type, axis or axes, link, actuated}")
    kind = choice(f"{field}.type", raw.get("type"), types)
    check_fields(raw, JOINTS[kind].fields, field, f"a chain's {kind} joint")
    actuated = raw.get("actuated", False)
    if not isinstance(actuated, bool):
        raise fail(f"{field}.actuated", "true or false")
    if actuated and kind not in ("R", "P"):
        raise fail(f"{field}.actuated", f"an actuated R or P joint; a {kind} joint is passive")
    if "rotor" in raw and not actuated:
        raise fail(f"{field}.rotor", "on the actuated joint only (its rotor)")
    out = {"type": kind, "actuated": actuated,
           "link": _vector(raw.get("link", [0] * dim), dim, f"{field}.link", names)}
    if kind == "P":
        out["axis"] = _vector(raw["axis"], dim, f"{field}.axis", names)
    elif kind == "R":
        out["axes"] = [[0, 0, 1] if dim == 2 else _vector(raw.get("axis", [0, 0, 1]), 3, f"{field}.axis", names)]
        if dim == 2 and "axis" in raw:
            raise fail(f"{field}.axis", "absent: a planar revolute turns about z")
    else:
        axes = raw.get("axes")
        if not isinstance(axes, list) or len(axes) != 2:
            raise fail(f"{field}.axes", f"the {kind} joint's two axes, the second in the frame the first turns")
        out["axes"] = [_vector(axis, 3, f"{field}.axes[{j}]", names) for j, axis in enumerate(axes)]
    if "body" in raw:
        out["body"] = _body(raw["body"], f"{field}.body", names, centre=dim, inertia=1 if dim == 2 else 3)
    if "rotor" in raw:
        out["rotor"] = expression(f"{field}.rotor", raw["rotor"], names)
    return out


def _conditions(raw: Any, names: set[str]) -> list[dict[str, Any]]:
    """Validity conditions of the design: each {margin, doc}, the margin an expression of the parameters that is
    positive where the condition holds."""
    if not isinstance(raw, list):
        raise fail("conditions", "a list of {margin, doc}")
    out = []
    for k, condition in enumerate(raw):
        if not isinstance(condition, Mapping):
            raise fail(f"conditions[{k}]", "a table {margin, doc}: the margin positive where the design is valid")
        check_fields(condition, CONDITION_FIELDS, f"conditions[{k}]", "a condition")
        doc = text(f"conditions[{k}].doc", condition.get("doc", "a valid design"))
        out.append({"margin": expression(f"conditions[{k}].margin", condition["margin"], names), "doc": doc})
    return out


def _has_bodies(leg: Mapping[str, Any]) -> bool:
    """Whether a normalised leg has bodies: a kind's table of them, or a chain's joint with a body or a rotor."""
    if leg["kind"] == CHAIN:
        return any("body" in joint or "rotor" in joint for joint in leg["joints"])
    return "bodies" in leg


def _chain_joints(raw: Any, where: str, dim: int, names: set[str]) -> list[dict[str, Any]]:
    """A chain's joints from the base checked and normalised (the one check of a chain, a named kind's too): each
    joint's type and fields, the platform's spherical joint ending a spatial chain (dropped), exactly one actuated
    joint, and as many joint variables as the closure at the platform's point joint has equations."""
    if not isinstance(raw, list) or not raw:
        raise fail(where, "a list of the chain's joints from the base")
    if dim == 3 and isinstance(raw[-1], Mapping) and raw[-1].get("type") == PLATFORM_JOINT:
        last = f"{where}[{len(raw) - 1}]"
        check_fields(raw[-1], JOINTS[PLATFORM_JOINT].fields, last, "the platform's spherical joint")
        if raw[-1].get("actuated", False) is not False:
            raise fail(last, "the platform's spherical joint: passive")
        raw = raw[:-1]
    joints = [_chain_joint(j, f"{where}[{i}]", dim, names) for i, j in enumerate(raw)]
    actuated = sum(j["actuated"] for j in joints)
    if actuated != 1:
        raise fail(where, f"exactly one actuated joint; got {actuated}")
    variables = sum(CHAIN_JOINTS[j["type"]] for j in joints)
    if variables != dim:
        raise fail(where, f"{dim} joint variables (R and P one each, U two), as many as the closure at the "
                           f"platform's point joint has equations; got {variables}")
    return joints


def _kind_chain(leg: Mapping[str, Any], where: str, dim: int, names: set[str]) -> list[dict[str, Any]]:
    """The chain of joints a normalised leg of a named kind is (:attr:`pkm.spec.vocabulary.Kind.chain`), checked
    as a chain's joints are."""
    texts = {k: expressions.text(v) if not isinstance(v, list) or expressions.is_operation(v)
             else [expressions.text(c) for c in v] for k, v in leg.items() if k not in ("kind", "range", "bodies")}
    return _chain_joints(KINDS[leg["kind"]].chain(texts), f"{where} (its chain's joints)", dim, names)


def _chain_legs(table: Mapping[str, Any], where: str, frame: str, names: set[str]) -> list[dict[str, Any]]:
    """The legs of a ``chain`` table: its joints from the base attachment, each with its type (R, P, U,
    parallelogram), axis (axes of a U or a parallelogram), link (the vector to the next joint, fixed in the
    frame the joint turns or slides), whether it is the actuated one, optionally the ``body`` after it ({mass,
    centre: a point of the body's frame from the joint, inertia: planar the moment about z, spatial the
    principal moments about the axes of the body's frame}; a parallelogram's body is its rods, turning with
    them) and on the actuated joint its ``rotor`` (its inertia after the reduction, or a reflected mass on a
    P); the platform's point joint (a revolute in the plane, a spherical joint in
    space) ends it. ``branches`` names one or two seeds, the joints' values at the home pose and the default
    design, each where a branch of the leg is continued from (or, where the chain is a known subproblem, the
    closed form's candidate nearest it); ``turn`` (each leg's frame turned about z from the base's) is the
    circle's angle where the base is a circle pattern, else 0; ``newton = true`` solves the leg by Newton
    continuation even where a closed form matches it."""
    dim = 2 if frame.startswith("planar") else 3
    count, base, angles, platform = _attachments(table, where, leg_fields(CHAIN), "a chain leg", dim=dim, names=names)
    joints = _chain_joints(table.get("joints"), f"{where}.joints", dim, names)
    branches = table.get("branches")
    if not isinstance(branches, Mapping) or not 1 <= len(branches) <= 2:
        raise fail(f"{where}.branches", "one or two seeds by name, each the joints' values at the home pose")
    seeds = []
    for name, values in branches.items():
        if not identifier(name):
            raise fail(f"{where}.branches.{reprlib.repr(name)}", IDENTIFIER)
        if not isinstance(values, list) or len(values) != dim:
            raise fail(f"{where}.branches.{name}", f"a list of {dim} joint values (the U's two in order)")
        seeds.append([name, [number(f"{where}.branches.{name}[{j}]", v) for j, v in enumerate(values)]])
    turns = table.get("turn")
    if turns is None:
        turns = angles if angles is not None else [0] * count
    elif not isinstance(turns, list) or len(turns) != count:
        raise fail(f"{where}.turn", f"a list of {count} angles, one per leg")
    else:
        turns = [expression(f"{where}.turn[{i}]", t, names) for i, t in enumerate(turns)]
    newton = table.get("newton", False)
    if not isinstance(newton, bool):
        raise fail(f"{where}.newton", "true or false")
    legs = []
    for i in range(count):
        leg = {"kind": CHAIN, "base": base[i], "platform": platform[i], "joints": joints, "branches": seeds,
               "turn": turns[i], **({"newton": True} if newton else {})}
        if "range" in table:
            bounds = table["range"]
            if not isinstance(bounds, list) or len(bounds) != 2:
                raise fail(f"{where}.range", "a pair [lower, upper] of the actuated joint")
            leg["range"] = [expression(f"{where}.range[{j}]", b, names) for j, b in enumerate(bounds)]
        legs.append(_with_elements(leg, table, where, names))
    return legs


def _with_elements(leg: dict[str, Any], table: Mapping[str, Any], where: str, names: set[str]) -> dict[str, Any]:
    """A normalised leg (its chain's joints known) with its table's elastic elements and capsule, where given."""
    if "elastic" in table:
        leg["elastic"] = elastic(table["elastic"], f"{where}.elastic", names, leg)
    if "capsule" in table:
        leg["capsule"] = expression(f"{where}.capsule", table["capsule"], names)
    if "layers" in table:
        segments, given = kind_of(leg).points - 1, table["layers"]
        if "capsule" not in table:
            raise fail(f"{where}.layers", "given with the leg's capsule")
        if not isinstance(given, list) or len(given) != segments or not all(
                isinstance(n, int) and not isinstance(n, bool) and 0 <= n <= MAX_LAYER for n in given):
            raise fail(f"{where}.layers", f"a list of {segments} integers from 0 to {MAX_LAYER}, one per segment of "
                                          "the leg's drawing")
        leg["layers"] = list(given)
    return leg


def _regions(raw: Any, pose_names: tuple[str, ...], names: set[str]) -> list[dict[str, Any]]:
    """Task regions: a shape spanning some pose coordinates, placed by expressions of the parameters; the
    other coordinates stay at the home pose's values."""
    if raw is None:
        return []
    table = f"{{{', '.join(f.name for f in REGION_FIELDS)}}}"
    if not isinstance(raw, list):
        raise fail("regions", f"a list of tables {table}")
    out, seen = [], set()
    for k, region in enumerate(raw):
        where = f"regions[{k}]"
        if not isinstance(region, Mapping):
            raise fail(where, f"a table {table}")
        check_fields(region, REGION_FIELDS, where, "a region")
        name = region.get("name")
        if not identifier(name) or name in seen or name in ("reachable", "assembled"):
            raise fail(f"{where}.name", f"{IDENTIFIER}, not given before, other "
                                         "than reachable and assembled")
        seen.add(name)
        shape = choice(f"{where}.shape", region.get("shape"), tuple(SHAPES))
        dimension, sizes, _ = SHAPES[shape]
        coordinates = region.get("coordinates", list(pose_names[:dimension]))
        if (not isinstance(coordinates, list) or len(coordinates) != dimension
                or not all(isinstance(c, str) and c in pose_names for c in coordinates)
                or len(set(coordinates)) != dimension):
            raise fail(f"{where}.coordinates", f"{dimension} distinct pose coordinates ({', '.join(pose_names)})")
        for field, count in (("centre", dimension), ("size", sizes)):
            if not isinstance(region.get(field), list) or len(region[field]) != count:
                raise fail(f"{where}.{field}", f"a list of {count} expressions of the parameters")
        if "axis" in region and shape != "cylinder":
            raise fail(f"{where}.axis", f"absent: only a cylinder has an axis; this region is a {shape}")
        axis = choice(f"{where}.axis", region.get("axis", coordinates[-1]), coordinates) if shape == "cylinder" \
            else None
        doc = text(f"{where}.doc", region.get("doc", name))
        out.append({
            "name": name, "doc": doc, "shape": shape,
            "coordinates": [pose_names.index(c) for c in coordinates],
            "centre": [expression(f"{where}.centre[{j}]", c, names) for j, c in enumerate(region["centre"])],
            "size": [expression(f"{where}.size[{j}]", c, names) for j, c in enumerate(region["size"])],
            "axis": None if axis is None else coordinates.index(axis),
        })
    return out


def describe(raw: Mapping[str, Any] | Description) -> Description:
    """Check a description (a mapping) and normalise it; :class:`DescriptionError` names the field."""
    if isinstance(raw, Description):
        return raw
    if not isinstance(raw, Mapping):
        raise fail("(the description)", "a mapping or a TOML file")
    check_fields(raw, DESCRIPTION_FIELDS, "", "a description")
    name = raw.get("name")
    if not identifier(name):
        raise fail("name", IDENTIFIER)
    frame = choice("frame", raw.get("frame"), tuple(FRAMES))
    parameters = _parameters(raw.get("parameters"))
    names = {p["name"] for p in parameters}
    legs = _legs(raw.get("legs"), frame, names)
    pose_names, units = FRAMES[frame]
    actuated = len(legs)
    if actuated != len(pose_names):
        raise fail("legs", f"one actuated joint per pose coordinate: {len(pose_names)} legs for the {frame} frame; "
                            f"got {actuated}")
    home = raw.get("home")
    if not isinstance(home, list) or len(home) != len(pose_names):
        raise fail("home", f"a pose of {len(pose_names)} values ({', '.join(pose_names)})")
    branched = sum(kind_of(leg).branched for leg in legs)
    modes = raw.get("modes", {})
    if not isinstance(modes, Mapping):
        raise fail("modes", "a table of names -> sign lists")
    for mode, signs in modes.items():
        if not (identifier(mode) and isinstance(signs, list) and len(signs) == max(branched, 1)
                and all(type(s) is int and s in (1, -1) for s in signs)):
            raise fail(f"modes.{reprlib.repr(mode)}", f"a name ({IDENTIFIER}) "
                                                       f"of a list of {max(branched, 1)} signs, each 1 or -1")
    length = raw.get("characteristic_length")
    planar_frame = frame.startswith("planar")
    data = {
        "name": name,
        "doc": text("doc", raw.get("doc", name)),
        "pose": {"frame": frame, "units": list(units)},
        "parameters": parameters,
        "legs": legs,
        "home": [expression(f"home[{k}]", h, names) for k, h in enumerate(home)],
        "characteristic_length": None if length is None else expression("characteristic_length", length, names),
        "modes": {k: list(v) for k, v in modes.items()},
        "regions": _regions(raw.get("regions"), pose_names, names),
        "platform": None if "platform" not in raw else _body(
            raw["platform"], "platform", names, centre=2 if planar_frame else 3,
            inertia={"planar_point": 0, "planar": 1, "spatial_point": 0, "spatial": 3}[frame]),
    }
    if "conditions" in raw:
        data["conditions"] = _conditions(raw["conditions"], names)
    gravity = raw.get("gravity")
    if gravity is not None:
        if not isinstance(gravity, list) or len(gravity) != (2 if planar_frame else 3):
            raise fail("gravity", f"a vector of {2 if planar_frame else 3} expressions (the acceleration of "
                                   "gravity in the base frame, m/s^2)")
        data["gravity"] = [expression(f"gravity[{k}]", g, names) for k, g in enumerate(gravity)]
    if "plates" in raw:
        data["plates"] = _plates(raw["plates"], names, legs)
    if data["platform"] is not None or any(map(_has_bodies, legs)) or gravity is not None:
        missing = [k for k, leg in enumerate(legs) if not _has_bodies(leg)]
        if missing:
            raise fail(f"legs (leg {missing[0] + 1})", "bodies for every leg where any body is given")
    _check_values(data)
    return Description(data)


def _plates(raw: Any, names: set[str], legs: list[dict[str, Any]]) -> dict[str, Any]:
    """The plates {platform, base}: each {radius} (the legs' attachments' polygon) or {radius, points} (its own),
    the legs' capsules given."""
    if not isinstance(raw, Mapping) or not raw or set(raw) - set(PLATES):
        raise fail("plates", f"a table of {' and/or '.join(PLATES)} plates")
    if not all("capsule" in leg for leg in legs):
        raise fail("plates", "the legs' capsules (each leg's capsule radius), which meet the plates")
    dim = len(legs[0]["base"])
    out = {}
    for name in (k for k in PLATES if k in raw):
        field, given = f"plates.{name}", raw[name]
        if not isinstance(given, Mapping):
            out[name] = {"radius": expression(field, given, names)}
            continue
        check_fields(given, PLATE_FIELDS, field, "a plate")
        out[name] = {"radius": expression(f"{field}.radius", given["radius"], names)}
        if "points" in given:
            points = given["points"]
            if not isinstance(points, list) or not points or len(points) > MAX_PLATE_POINTS:
                raise fail(f"{field}.points", f"a list of 1 to {MAX_PLATE_POINTS} points")
            out[name]["points"] = [_vector(point, dim, f"{field}.points[{k}]", names) for k, point in enumerate(points)]
    return out


MAX_PLATE_POINTS = 64  # a plate's own points at most


def _check_plates(data: Mapping[str, Any], value: Any) -> None:
    """Each plate's radius positive at the default design, its polygon (its points, or the legs' attachments)
    convex there and, in space, in one plane z = const."""
    for plate, table in data.get("plates", {}).items():
        field, given = f"plates.{plate}", "points" in table
        radius = f"{field}.radius" if given else field
        if not value(radius, table["radius"]) > 0:
            raise fail(radius, "a positive radius at the default design")
        where = [f"{field}.points[{k}]" for k in range(len(table["points"]))] if given else \
            [f"legs (leg {k + 1}).{plate}" for k in range(len(data["legs"]))]
        points = np.array([[value(f"{w}[{c}]", t) for c, t in enumerate(point)]
                           for w, point in zip(where, plate_corners(data, plate), strict=True)])
        what = "the plate's points" if given else f"the legs' {plate} attachments"
        if points.shape[1] == 3:
            heights = points[:, 2]
            if np.ptp(heights) > PLANE * (1 + np.max(np.abs(heights))):
                raise fail(field, f"{what} in one plane z = const (the plate's); their z spans {heights.min():g} to "
                                  f"{heights.max():g} m")
        if not convex(points[plate_order(points[:, :2])][:, :2]):
            raise fail(field, f"{what} the vertices of a convex polygon (in their angular order about their centre)")


PLANE = 1e-9  # relative: attachments whose z agree to this lie in one plane
# a leg's lengths and angles that must be positive
POSITIVE = tuple(dict.fromkeys([*(f.name for kind in KINDS.values() for f in kind.fields if f.holds in (LENGTH, CONE)),
                                 "capsule"]))
DIRECTIONS = ("axis", "zero", "axes")  # a leg's or a joint's directions, which must not vanish


def _within_a_turn(field: str, name: str, angle: float) -> None:
    """An angle of a description within a turn either way, else the error asks whether it is in degrees."""
    if abs(angle) > 2 * math.pi:
        raise fail(field, f"an angle in radians within a turn (|{name}| <= 2 pi); {angle:g} rad is beyond it: in "
                           f"degrees? ({angle:g} deg = {math.radians(angle):.6g} rad)")


FRAME_TOLERANCE = 1e-9  # an arm's axis and zero direction are unit and perpendicular to this


def _check_frame(where: str, axis: list[float], zero: list[float]) -> None:
    """An arm's axis and its angle's zero direction unit and perpendicular at the default design (its tip
    turns from zero towards axis x zero at the arm's length)."""
    for name, direction in (("axis", axis), ("zero", zero)):
        length = math.hypot(*direction)
        if abs(length - 1) > FRAME_TOLERANCE:
            raise fail(f"{where}.{name}", f"a unit direction at the default design; its length is {length:.6g}: "
                                           "divide it by that")
    dot = sum(a * z for a, z in zip(axis, zero, strict=True))
    if abs(dot) > FRAME_TOLERANCE:
        raise fail(f"{where}.zero", f"perpendicular to axis at the default design; axis . zero = {dot:.6g}")


def _check_values(data: Mapping[str, Any]) -> None:
    """At the default design, every expression has a finite value, the legs' lengths are positive, their
    directions do not vanish (an arm's axis and zero direction are unit and perpendicular), a range's lower end
    lies below its upper, the regions' sizes are positive and every validity condition holds."""
    design = {p["name"]: p["default"] for p in data["parameters"]}

    def value(field: str, tree: Any) -> float:
        got = float(expressions.evaluate(tree, design))
        if not math.isfinite(got):
            raise fail(field, f"a finite value at the default design; {expressions.text(tree)} is {got}")
        return got

    _check_plates(data, value)
    fields = [("home", data["home"]), ("characteristic_length", data["characteristic_length"]),
              ("gravity", data.get("gravity")), ("platform", data["platform"]),
              *((f"legs (leg {k + 1})", leg) for k, leg in enumerate(data["legs"]))]
    for field, part in fields:
        for where, tree in ([] if part is None else trees(part, field)):
            value(where, tree)
    names = FRAMES[data["pose"]["frame"]][0]
    for j, (name, unit) in enumerate(zip(names, data["pose"]["units"], strict=True)):
        if unit == "rad":
            _within_a_turn(f"home[{j}]", name, value(f"home[{j}]", data["home"][j]))
    for k, leg in enumerate(data["legs"]):
        where = f"legs (leg {k + 1})"
        if "range" in leg and kind_of(leg).unit == "rad":
            low, high = (value(f"{where}.range[{j}]", leg["range"][j]) for j in range(2))
            for j, bound in enumerate((low, high)):
                _within_a_turn(f"{where}.range[{j}]", "the actuated joint's bound", bound)
            if high - low > 2 * math.pi:
                raise fail(f"{where}.range", f"a revolute joint's range of a turn at most; [{low:g}, {high:g}] rad "
                                              f"spans {high - low:g} rad: in degrees?")
        for name in POSITIVE:
            if name in leg and not value(f"{where}.{name}", leg[name]) > 0:
                raise fail(f"{where}.{name}", "a positive value at the default design")
        if "elastic" in leg:
            check_elastic(leg["elastic"], f"{where}.elastic", value)
        if "range" in leg and not value(f"{where}.range[0]", leg["range"][0]) < value(f"{where}.range[1]",
                                                                                      leg["range"][1]):
            raise fail(f"{where}.range", "lower < upper at the default design")
        parts = [(where, leg), *((f"{where}.joints[{j}]", joint) for j, joint in enumerate(leg.get("joints", ())))]
        for at, part in parts:
            for name in DIRECTIONS:
                directions = part.get(name, ())
                for d, direction in enumerate(directions if name == "axes" else [directions] if directions else []):
                    vector = [value(f"{at}.{name}", c) for c in direction]
                    if not any(vector):
                        raise fail(f"{at}.{name}" + (f"[{d}]" if name == "axes" else ""),
                                    "a direction (not zero) at the default design")
        if leg["kind"] == "R_parallelogram":
            _check_frame(where, [value(f"{where}.axis", c) for c in leg["axis"]],
                         [value(f"{where}.zero", c) for c in leg["zero"]])
    for k, region in enumerate(data["regions"]):
        for j, size in enumerate(region["size"]):
            if not value(f"regions[{k}].size[{j}]", size) > 0:
                raise fail(f"regions[{k}].size[{j}]", "a positive size at the default design")
        for j, centre in enumerate(region["centre"]):
            value(f"regions[{k}].centre[{j}]", centre)
    for k, condition in enumerate(data.get("conditions", ())):
        if not value(f"conditions[{k}].margin", condition["margin"]) > 0:
            raise fail(f"conditions[{k}].margin", f"positive at the default design ({condition['doc']})")


def read(path: str | os.PathLike) -> Description:
    """A description from a TOML file."""
    return describe(io.read_toml(path, DescriptionError, "description file"))

