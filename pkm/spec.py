"""Machines as data (DESIGN.md section 6b): a description, checked, derived on first use, loaded as a
:class:`pkm.mechanism.Mechanism`.

A description is a mapping (or a TOML file) of the fields of :data:`DESCRIPTION_FIELDS`: its parameters'
(:data:`PARAMETER_FIELDS`), its conditions' (:data:`CONDITION_FIELDS`), its regions' (:data:`REGION_FIELDS`), its
bodies' (:data:`BODY_FIELDS`) and its legs', each leg table those of :func:`leg_fields`: every leg's
(:data:`LEG_FIELDS`, its attachments lists of points or patterns of :data:`PATTERN_FIELDS`) and its kind's, a
known subproblem's (:data:`KINDS`, derived by :mod:`symbolic.describe`) or a chain's (:data:`CHAIN_FIELDS`, its
joints' types :data:`JOINTS`). Each :class:`Field` says what it holds and means, and docs/mechanisms.md lists them
all (:mod:`pkm.schema_docs` writes that section from these tables). Every coordinate and length is an expression
of the parameters with ``pi`` and :data:`pkm.expressions.FUNCTIONS`, read into :mod:`pkm.expressions`' tree
(never evaluated as Python; the normalised description holds the trees). The working modes are the named sign
combinations of the legs with two branches or, unnamed, every combination, those in which the home pose is
regular first (:func:`_modes`, :func:`working_modes`).

:func:`describe` checks a description and returns a :class:`Description` (errors name the field and the
violated condition); :func:`load` derives it once into the user's cache (``descriptions/`` of the kernel cache,
content-addressed by the normalised description and the tools' versions: ``python -m symbolic.describe``
in a subprocess, for pkm never imports sympy) and returns the mechanism.
"""

from __future__ import annotations

import hashlib
import importlib.util
import itertools
import json
import math
import os
import reprlib
import subprocess
import sys
import tempfile
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions, io, registry
from pkm.batch import evaluate
from pkm.compiled.cache import location
from pkm.design import Condition, Parameter
from pkm.errors import ComputationError, PkmError, SingularityWarning
from pkm.indices.local import SINGULAR, SINGULARITY_TYPE1, SINGULARITY_TYPE2
from pkm.kinematics import Branch, FunctionTable, NearestSeeds, within_limits
from pkm.mechanism import Mechanism
from pkm.progress import Progress
from pkm.regions import Box, Cylinder, Disc, Mapped, Rectangle, index_values
from pkm.vocabulary import (
    BODY_FIELDS,
    CHAIN,
    CHAIN_JOINTS,
    CONDITION_FIELDS,
    CONE,
    DESCRIPTION_FIELDS,
    FRAMES,
    JOINTS,
    KINDS,
    LENGTH,
    NAME_LENGTH,
    PARAMETER_FIELDS,
    PATTERN_FIELDS,
    PLATFORM_JOINT,
    POINT_BODY,
    REGION_FIELDS,
    ROTOR,
    SHAPES,
    TEXT_LENGTH,
    Field,
    kind_of,
    leg_fields,
    passive_angles,
)

SUFFIX = ".toml"  # a mechanism name with it is a description file
ROOT = Path(__file__).resolve().parent.parent
CLOSURE_TOLERANCE = 1e-9  # [m] the home pose closes every leg to this, relative to the largest length
DERIVATION_SECONDS = 120.0  # the time limit of a description's derivation
UNDEFINED = 3  # the derivation's exit status where an expression has no finite value (symbolic.describe)
RANK_TOLERANCE = 1e-9  # relative singular value below which the closure's Jacobian loses rank


class DescriptionError(PkmError):
    """A machine description that names an unknown field or violates a condition."""


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
    sources = sorted((ROOT / "symbolic").glob("*.py"))
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sources)).hexdigest()
    return {"casadi": ca.__version__, "symbolic": digest}


def _fail(field: str, condition: str) -> DescriptionError:
    return DescriptionError(f"description field {field} violates: {condition}")


def _check_fields(table: Mapping[str, Any], fields: Sequence[Field], where: str, what: str) -> None:
    """A field of ``table`` that ``fields`` does not hold, or a required one that it lacks, refused by name."""
    names = [f.name for f in fields]
    extra = sorted(set(table) - set(names), key=str)
    if extra:
        raise _fail(f"{where}.{extra[0]}" if where else str(extra[0]), f"a known field of {what} ({', '.join(names)})")
    for f in fields:
        if f.required and f.name not in table:
            raise _fail(f"{where}.{f.name}" if where else f.name, f"given ({f.doc})")


def _expression(field: str, text: Any, names: set[str]) -> expressions.Tree:
    """An expression of the parameters (and pi and :data:`pkm.expressions.FUNCTIONS`), as its tree."""
    if isinstance(text, bool) or not isinstance(text, int | float | str):
        raise _fail(field, "a number or an expression of the parameters")
    if not isinstance(text, str):
        if not math.isfinite(text):
            raise _fail(field, f"a finite number; got {text!r}")
        return float(text)
    try:
        tree = expressions.parse(text)
    except expressions.ExpressionError as exc:
        raise _fail(field, f"{exc}; got {reprlib.repr(text)}") from None
    unknown = expressions.unknown_names(tree, names)
    if unknown:
        raise _fail(field, f"an expression of the parameters ({', '.join(sorted(names))}); it names "
                           f"{reprlib.repr(unknown)}")
    return tree


def _compose(field: str, template: str, names: set[str], **parts: expressions.Tree) -> expressions.Tree:
    """The tree of ``template`` with the trees ``parts`` put in for their names in braces."""
    return _expression(field, template.format(**{k: f"({expressions.text(v)})" for k, v in parts.items()}), names)


def _choice(field: str, value: Any, options: Sequence[str]) -> str:
    """``value`` where it is one of ``options`` (text), else :class:`DescriptionError` naming ``field``."""
    if not isinstance(value, str) or value not in options:
        raise _fail(field, f"one of {', '.join(options)}; got {reprlib.repr(value)}")
    return value


def _text(field: str, value: Any) -> str:
    """A text field (a doc, a unit): text of at most :data:`TEXT_LENGTH` characters."""
    if not isinstance(value, str) or len(value) > TEXT_LENGTH:
        raise _fail(field, f"text of at most {TEXT_LENGTH} characters")
    return value


def _identifier(name: Any) -> bool:
    return isinstance(name, str) and name.isidentifier() and len(name) <= NAME_LENGTH


def _number(field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise _fail(field, "a finite number")
    return float(value)


def _parameters(raw: Any) -> list[dict[str, Any]]:
    table = f"{{{', '.join(f.name for f in PARAMETER_FIELDS)}}}"
    if not isinstance(raw, list) or not raw:
        raise _fail("parameters", f"a non-empty list of {table}")
    out, seen = [], set()
    for k, p in enumerate(raw):
        where = f"parameters[{k}]"
        if not isinstance(p, Mapping):
            raise _fail(where, f"a table {table}")
        _check_fields(p, PARAMETER_FIELDS, where, "a parameter")
        name = p.get("name")
        if not _identifier(name) or name in expressions.RESERVED:
            raise _fail(f"{where}.name", f"an identifier of at most {NAME_LENGTH} characters other than "
                                         f"{', '.join(expressions.RESERVED)}")
        if name in seen:
            raise _fail(f"{where}.name", f"a name not given before; {name} is")
        seen.add(name)
        lower, upper = _number(f"{where}.lower", p["lower"]), _number(f"{where}.upper", p["upper"])
        default = _number(f"{where}.default", p.get("default"))
        if not lower < upper:
            raise _fail(f"{where}", f"lower < upper; got {lower:g}, {upper:g}")
        if not lower <= default < upper:
            raise _fail(f"{where}.default", f"{lower:g} <= default < {upper:g}; got {default:g}")
        unit, doc = _text(f"{where}.unit", p.get("unit", "-")), _text(f"{where}.doc", p.get("doc", ""))
        out.append({"name": name, "default": default, "lower": lower, "upper": upper, "unit": unit, "doc": doc})
    return out


def _angles(pattern: Mapping[str, Any], count: int, field: str, names: set[str]) -> list[expressions.Tree]:
    start = _expression(f"{field}.start", pattern.get("start", 0), names)
    if "pairs" not in pattern:
        return [_compose(f"{field}.start", f"{{start}} + 2*pi*{i}/{count}", names, start=start) for i in range(count)]
    if count % 2:
        raise _fail(f"{field}.pairs", f"an even count of legs; got {count}")
    apart = _expression(f"{field}.pairs", pattern["pairs"], names)
    return [_compose(f"{field}.pairs", f"{{start}} + 2*pi*{i // 2}/{count // 2} {'-' if i % 2 == 0 else '+'} "
                     "{apart}/2", names, start=start, apart=apart) for i in range(count)]


def _points(raw: Any, count: int, dim: int, field: str, names: set[str]
            ) -> tuple[list[list[expressions.Tree]], list[expressions.Tree] | None]:
    """``count`` points of ``dim`` expressions, and the circle's angles where a pattern gave them."""
    if isinstance(raw, Mapping):
        _check_fields(raw, PATTERN_FIELDS, field, "a pattern")
        radius = _expression(f"{field}.circle", raw["circle"], names)
        angles = _angles(raw, count, field, names)
        plane = [[_compose(f"{field}.circle", f"{{r}}*{f}({{a}})", names, r=radius, a=a) for f in ("cos", "sin")]
                 for a in angles]
        return [p + [0] * (dim - 2) for p in plane], angles
    if not isinstance(raw, list) or len(raw) != count:
        raise _fail(field, f"a list of {count} points (one per leg) or a pattern {{circle, start, pairs}}")
    points = []
    for i, point in enumerate(raw):
        if not isinstance(point, list) or len(point) != dim:
            raise _fail(f"{field}[{i}]", f"a point of {dim} coordinates")
        points.append([_expression(f"{field}[{i}][{j}]", c, names) for j, c in enumerate(point)])
    return points, None


def _body(raw: Any, field: str, names: set[str], *, centre: int, inertia: int) -> dict[str, Any]:
    """A body {mass, centre (``centre`` expressions: 0 for none, 1 a distance, 2 or 3 a point), inertia
    (``inertia`` expressions: 0 for none)}: mass required, the others 0 by default."""
    if not isinstance(raw, Mapping):
        raise _fail(field, f"a table {{{', '.join(f.name for f in BODY_FIELDS)}}}")
    counts = {"centre": centre, "inertia": inertia}
    _check_fields(raw, [f for f in BODY_FIELDS if counts.get(f.name, 1)], field, "this body")
    out: dict[str, Any] = {"mass": _expression(f"{field}.mass", raw["mass"], names)}
    for key, count in (("centre", centre), ("inertia", inertia)):
        if not count:
            continue
        value = raw.get(key, [0] * count if count > 1 else 0)
        if count == 1:
            out[key] = _expression(f"{field}.{key}", value, names)
        else:
            if not isinstance(value, list) or len(value) != count:
                raise _fail(f"{field}.{key}", f"a list of {count} expressions")
            out[key] = [_expression(f"{field}.{key}[{j}]", v, names) for j, v in enumerate(value)]
    return out


def _leg_bodies(raw: Any, kind: str, field: str, names: set[str]) -> dict[str, Any]:
    fields = (ROTOR, *KINDS[kind].bodies)
    if not isinstance(raw, Mapping):
        raise _fail(field, f"a table of the {kind} leg's rotor and bodies ({', '.join(f.name for f in fields)})")
    _check_fields(raw, fields, field, f"a {kind} leg's bodies")
    out: dict[str, Any] = {"rotor": _expression(f"{field}.rotor", raw.get("rotor", 0), names)}
    for body in KINDS[kind].bodies:
        if body.name in raw:
            extent = int(body.holds != POINT_BODY)
            out[body.name] = _body(raw[body.name], f"{field}.{body.name}", names, centre=extent, inertia=extent)
    return out


def _legs(raw: Any, frame: str, names: set[str]) -> list[dict[str, Any]]:
    tables = [raw] if isinstance(raw, Mapping) else raw
    if not isinstance(tables, list) or not tables:
        raise _fail("legs", "a table or a list of tables")
    planar = frame.startswith("planar")
    dim = 2 if planar else 3
    legs = []
    for t, table in enumerate(tables):
        where = "legs" if isinstance(raw, Mapping) else f"legs[{t}]"
        if not isinstance(table, Mapping):
            raise _fail(where, "a table")
        kind = _choice(f"{where}.kind", table.get("kind"), (*KINDS, CHAIN))
        if kind == CHAIN:
            legs += _chain_legs(table, where, frame, names)
            continue
        space, lengths = KINDS[kind].space, KINDS[kind].lengths
        if (space == "planar") != planar:
            raise _fail(f"{where}.kind", f"a {'planar' if planar else 'spatial'} leg in a {frame} frame; {kind} is "
                                          f"{space}")
        count, base, angles, platform = _attachments(table, where, leg_fields(kind), f"a {kind} leg", dim=dim,
                                                      names=names)
        for i in range(count):
            leg = {"kind": kind, "base": base[i], "platform": platform[i],
                   **{n: _expression(f"{where}.{n}", table[n], names) for n in lengths}}
            if "range" in table:
                bounds = table["range"]
                if not isinstance(bounds, list) or len(bounds) != 2:
                    raise _fail(f"{where}.range", "a pair [lower, upper] of the actuated joint")
                leg["range"] = [_expression(f"{where}.range[{j}]", b, names) for j, b in enumerate(bounds)]
            if "cone" in table:
                leg["cone"] = _expression(f"{where}.cone", table["cone"], names)
            if "bodies" in table:
                leg["bodies"] = _leg_bodies(table["bodies"], kind, f"{where}.bodies", names)
            if kind == "PRR":
                if not isinstance(table["axis"], list) or len(table["axis"]) != 2:
                    raise _fail(f"{where}.axis", "a direction of 2 expressions")
                leg["axis"] = [_expression(f"{where}.axis[{j}]", c, names) for j, c in enumerate(table["axis"])]
            if kind == "R_parallelogram":
                if angles is None and ("axis" not in table or "zero" not in table):
                    raise _fail(f"{where}.axis", "given with zero where the base is not a circle pattern")
                a = angles[i] if angles is not None else None
                leg["axis"] = [["neg", ["sin", a]], ["cos", a], 0] if table.get("axis", "tangent") == "tangent" \
                    else _vector(table["axis"], 3, f"{where}.axis", names)
                leg["zero"] = [["cos", a], ["sin", a], 0] if table.get("zero", "radial") == "radial" else \
                    _vector(table["zero"], 3, f"{where}.zero", names)
            legs.append(leg)
    return legs


def _attachments(table: Mapping[str, Any], where: str, fields: Sequence[Field], what: str, *, dim: int,
                 names: set[str]) -> tuple[int, list[list[expressions.Tree]], list[expressions.Tree] | None,
                                           list[list[expressions.Tree]]]:
    """A leg table's fields checked against ``fields``, its count of legs, their base attachments (with the
    circle's angles where a pattern gives them) and their platform attachments."""
    _check_fields(table, fields, where, what)
    count = table.get("count", 1)
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 12:
        raise _fail(f"{where}.count", "an integer from 1 to 12")
    base, angles = _points(table.get("base"), count, dim, f"{where}.base", names)
    platform, _ = _points(table.get("platform"), count, dim, f"{where}.platform", names)
    return count, base, angles, platform


def _vector(raw: Any, dim: int, field: str, names: set[str]) -> list[expressions.Tree]:
    if not isinstance(raw, list) or len(raw) != dim:
        raise _fail(field, f"a vector of {dim} expressions")
    return [_expression(f"{field}[{j}]", c, names) for j, c in enumerate(raw)]


def _chain_joint(raw: Any, field: str, dim: int, names: set[str]) -> dict[str, Any]:
    types = tuple(t for t in CHAIN_JOINTS if dim == 3 or JOINTS[t].planar)
    if not isinstance(raw, Mapping):
        raise _fail(field, "a table {type, axis or axes, link, actuated}")
    kind = _choice(f"{field}.type", raw.get("type"), types)
    _check_fields(raw, JOINTS[kind].fields, field, f"a chain's {kind} joint")
    actuated = raw.get("actuated", False)
    if not isinstance(actuated, bool):
        raise _fail(f"{field}.actuated", "true or false")
    if actuated and kind not in ("R", "P"):
        raise _fail(f"{field}.actuated", f"an actuated R or P joint; a {kind} joint is passive")
    if "rotor" in raw and not actuated:
        raise _fail(f"{field}.rotor", "on the actuated joint only (its rotor)")
    out = {"type": kind, "actuated": actuated,
           "link": _vector(raw.get("link", [0] * dim), dim, f"{field}.link", names)}
    if kind == "P":
        out["axis"] = _vector(raw["axis"], dim, f"{field}.axis", names)
    elif kind == "R":
        out["axes"] = [[0, 0, 1] if dim == 2 else _vector(raw.get("axis", [0, 0, 1]), 3, f"{field}.axis", names)]
        if dim == 2 and "axis" in raw:
            raise _fail(f"{field}.axis", "absent: a planar revolute turns about z")
    else:
        axes = raw.get("axes")
        if not isinstance(axes, list) or len(axes) != 2:
            raise _fail(f"{field}.axes", f"the {kind} joint's two axes, the second in the frame the first turns")
        out["axes"] = [_vector(axis, 3, f"{field}.axes[{j}]", names) for j, axis in enumerate(axes)]
    if "body" in raw:
        out["body"] = _body(raw["body"], f"{field}.body", names, centre=dim, inertia=1 if dim == 2 else 3)
    if "rotor" in raw:
        out["rotor"] = _expression(f"{field}.rotor", raw["rotor"], names)
    return out


def _conditions(raw: Any, names: set[str]) -> list[dict[str, Any]]:
    """Validity conditions of the design: each {margin, doc}, the margin an expression of the parameters that is
    positive where the condition holds."""
    if not isinstance(raw, list):
        raise _fail("conditions", "a list of {margin, doc}")
    out = []
    for k, condition in enumerate(raw):
        if not isinstance(condition, Mapping):
            raise _fail(f"conditions[{k}]", "a table {margin, doc}: the margin positive where the design is valid")
        _check_fields(condition, CONDITION_FIELDS, f"conditions[{k}]", "a condition")
        doc = _text(f"conditions[{k}].doc", condition.get("doc", "a valid design"))
        out.append({"margin": _expression(f"conditions[{k}].margin", condition["margin"], names), "doc": doc})
    return out


def _has_bodies(leg: Mapping[str, Any]) -> bool:
    """Whether a normalised leg has bodies: a kind's table of them, or a chain's joint with a body or a rotor."""
    if leg["kind"] == CHAIN:
        return any("body" in joint or "rotor" in joint for joint in leg["joints"])
    return "bodies" in leg


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
    raw = table.get("joints")
    if not isinstance(raw, list) or not raw:
        raise _fail(f"{where}.joints", "a list of the chain's joints from the base")
    if dim == 3 and isinstance(raw[-1], Mapping) and raw[-1].get("type") == PLATFORM_JOINT:
        last = f"{where}.joints[{len(raw) - 1}]"
        _check_fields(raw[-1], JOINTS[PLATFORM_JOINT].fields, last, "the platform's spherical joint")
        if raw[-1].get("actuated", False) is not False:
            raise _fail(last, "the platform's spherical joint: passive")
        raw = raw[:-1]
    joints = [_chain_joint(j, f"{where}.joints[{i}]", dim, names) for i, j in enumerate(raw)]
    actuated = sum(j["actuated"] for j in joints)
    if actuated != 1:
        raise _fail(f"{where}.joints", f"exactly one actuated joint; got {actuated}")
    variables = sum(CHAIN_JOINTS[j["type"]] for j in joints)
    if variables != dim:
        raise _fail(f"{where}.joints", f"{dim} joint variables (R and P one each, U two), as many as the closure at "
                                       f"the platform's point joint has equations; got {variables}")
    branches = table.get("branches")
    if not isinstance(branches, Mapping) or not 1 <= len(branches) <= 2:
        raise _fail(f"{where}.branches", "one or two seeds by name, each the joints' values at the home pose")
    seeds = []
    for name, values in branches.items():
        if not _identifier(name):
            raise _fail(f"{where}.branches.{reprlib.repr(name)}", f"an identifier of at most {NAME_LENGTH} "
                                                                  "characters")
        if not isinstance(values, list) or len(values) != variables:
            raise _fail(f"{where}.branches.{name}", f"a list of {variables} joint values (the U's two in order)")
        seeds.append([name, [_number(f"{where}.branches.{name}[{j}]", v) for j, v in enumerate(values)]])
    turns = table.get("turn")
    if turns is None:
        turns = angles if angles is not None else [0] * count
    elif not isinstance(turns, list) or len(turns) != count:
        raise _fail(f"{where}.turn", f"a list of {count} angles, one per leg")
    else:
        turns = [_expression(f"{where}.turn[{i}]", t, names) for i, t in enumerate(turns)]
    newton = table.get("newton", False)
    if not isinstance(newton, bool):
        raise _fail(f"{where}.newton", "true or false")
    legs = []
    for i in range(count):
        leg = {"kind": CHAIN, "base": base[i], "platform": platform[i], "joints": joints, "branches": seeds,
               "turn": turns[i], **({"newton": True} if newton else {})}
        if "range" in table:
            bounds = table["range"]
            if not isinstance(bounds, list) or len(bounds) != 2:
                raise _fail(f"{where}.range", "a pair [lower, upper] of the actuated joint")
            leg["range"] = [_expression(f"{where}.range[{j}]", b, names) for j, b in enumerate(bounds)]
        legs.append(leg)
    return legs


def _regions(raw: Any, pose_names: tuple[str, ...], names: set[str]) -> list[dict[str, Any]]:
    """Task regions: a shape spanning some pose coordinates, placed by expressions of the parameters; the
    other coordinates stay at the home pose's values."""
    if raw is None:
        return []
    table = f"{{{', '.join(f.name for f in REGION_FIELDS)}}}"
    if not isinstance(raw, list):
        raise _fail("regions", f"a list of tables {table}")
    out, seen = [], set()
    for k, region in enumerate(raw):
        where = f"regions[{k}]"
        if not isinstance(region, Mapping):
            raise _fail(where, f"a table {table}")
        _check_fields(region, REGION_FIELDS, where, "a region")
        name = region.get("name")
        if not _identifier(name) or name in seen or name in ("reachable", "assembled"):
            raise _fail(f"{where}.name", f"an identifier of at most {NAME_LENGTH} characters not given before, other "
                                         "than reachable and assembled")
        seen.add(name)
        shape = _choice(f"{where}.shape", region.get("shape"), tuple(SHAPES))
        dimension, sizes, _ = SHAPES[shape]
        coordinates = region.get("coordinates", list(pose_names[:dimension]))
        if (not isinstance(coordinates, list) or len(coordinates) != dimension
                or not all(isinstance(c, str) and c in pose_names for c in coordinates)
                or len(set(coordinates)) != dimension):
            raise _fail(f"{where}.coordinates", f"{dimension} distinct pose coordinates ({', '.join(pose_names)})")
        for field, count in (("centre", dimension), ("size", sizes)):
            if not isinstance(region.get(field), list) or len(region[field]) != count:
                raise _fail(f"{where}.{field}", f"a list of {count} expressions of the parameters")
        if "axis" in region and shape != "cylinder":
            raise _fail(f"{where}.axis", f"absent: only a cylinder has an axis; this region is a {shape}")
        axis = _choice(f"{where}.axis", region.get("axis", coordinates[-1]), coordinates) if shape == "cylinder" \
            else None
        doc = _text(f"{where}.doc", region.get("doc", name))
        out.append({
            "name": name, "doc": doc, "shape": shape,
            "coordinates": [pose_names.index(c) for c in coordinates],
            "centre": [_expression(f"{where}.centre[{j}]", c, names) for j, c in enumerate(region["centre"])],
            "size": [_expression(f"{where}.size[{j}]", c, names) for j, c in enumerate(region["size"])],
            "axis": None if axis is None else coordinates.index(axis),
        })
    return out


def describe(raw: Mapping[str, Any] | Description) -> Description:
    """Check a description (a mapping) and normalise it; :class:`DescriptionError` names the field."""
    if isinstance(raw, Description):
        return raw
    if not isinstance(raw, Mapping):
        raise _fail("(the description)", "a mapping or a TOML file")
    _check_fields(raw, DESCRIPTION_FIELDS, "", "a description")
    name = raw.get("name")
    if not _identifier(name):
        raise _fail("name", f"an identifier of at most {NAME_LENGTH} characters")
    frame = _choice("frame", raw.get("frame"), tuple(FRAMES))
    parameters = _parameters(raw.get("parameters"))
    names = {p["name"] for p in parameters}
    legs = _legs(raw.get("legs"), frame, names)
    pose_names, units = FRAMES[frame]
    actuated = len(legs)
    if actuated != len(pose_names):
        raise _fail("legs", f"one actuated joint per pose coordinate: {len(pose_names)} legs for the {frame} frame; "
                            f"got {actuated}")
    home = raw.get("home")
    if not isinstance(home, list) or len(home) != len(pose_names):
        raise _fail("home", f"a pose of {len(pose_names)} values ({', '.join(pose_names)})")
    branched = sum(kind_of(leg).branched for leg in legs)
    modes = raw.get("modes", {})
    if not isinstance(modes, Mapping):
        raise _fail("modes", "a table of names -> sign lists")
    for mode, signs in modes.items():
        if not (_identifier(mode) and isinstance(signs, list) and len(signs) == max(branched, 1)
                and all(type(s) is int and s in (1, -1) for s in signs)):
            raise _fail(f"modes.{reprlib.repr(mode)}", f"a name (an identifier of at most {NAME_LENGTH} characters) "
                                                       f"of a list of {max(branched, 1)} signs, each 1 or -1")
    length = raw.get("characteristic_length")
    planar_frame = frame.startswith("planar")
    data = {
        "name": name,
        "doc": _text("doc", raw.get("doc", name)),
        "pose": {"frame": frame, "units": list(units)},
        "parameters": parameters,
        "legs": legs,
        "home": [_expression(f"home[{k}]", h, names) for k, h in enumerate(home)],
        "characteristic_length": None if length is None else _expression("characteristic_length", length, names),
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
            raise _fail("gravity", f"a vector of {2 if planar_frame else 3} expressions (the acceleration of "
                                   "gravity in the base frame, m/s^2)")
        data["gravity"] = [_expression(f"gravity[{k}]", g, names) for k, g in enumerate(gravity)]
    if data["platform"] is not None or any(map(_has_bodies, legs)) or gravity is not None:
        missing = [k for k, leg in enumerate(legs) if not _has_bodies(leg)]
        if missing:
            raise _fail(f"legs (leg {missing[0] + 1})", "bodies for every leg where any body is given")
    _check_values(data)
    return Description(data)


NOT_EXPRESSIONS = ("kind", "type", "branches", "actuated", "newton")  # a normalised leg's fields of other data
# a leg's lengths and angles that must be positive
POSITIVE = tuple(dict.fromkeys(f.name for kind in KINDS.values() for f in kind.fields if f.holds in (LENGTH, CONE)))
DIRECTIONS = ("axis", "zero", "axes")  # a leg's or a joint's directions, which must not vanish


def _trees(value: Any, field: str) -> list[tuple[str, Any]]:
    """Every expression of a normalised leg (or a part of one) with its field, its other data left out."""
    if isinstance(value, Mapping):
        return [t for k, v in value.items() if k not in NOT_EXPRESSIONS for t in _trees(v, f"{field}.{k}")]
    if isinstance(value, list) and not expressions.is_operation(value):
        return [t for j, v in enumerate(value) for t in _trees(v, f"{field}[{j}]")]
    return [(field, value)]


def _within_a_turn(field: str, name: str, angle: float) -> None:
    """An angle of a description within a turn either way, else the error asks whether it is in degrees."""
    if abs(angle) > 2 * math.pi:
        raise _fail(field, f"an angle in radians within a turn (|{name}| <= 2 pi); {angle:g} rad is beyond it: in "
                           f"degrees? ({angle:g} deg = {math.radians(angle):.6g} rad)")


def _check_values(data: Mapping[str, Any]) -> None:
    """At the default design, every expression has a finite value, the legs' lengths are positive, their
    directions do not vanish, a range's lower end lies below its upper, the regions' sizes are positive and
    every validity condition holds."""
    design = {p["name"]: p["default"] for p in data["parameters"]}

    def value(field: str, tree: Any) -> float:
        number = float(expressions.evaluate(tree, design))
        if not math.isfinite(number):
            raise _fail(field, f"a finite value at the default design; {expressions.text(tree)} is {number}")
        return number

    fields = [("home", data["home"]), ("characteristic_length", data["characteristic_length"]),
              ("gravity", data.get("gravity")), ("platform", data["platform"]),
              *((f"legs (leg {k + 1})", leg) for k, leg in enumerate(data["legs"]))]
    for field, part in fields:
        for where, tree in ([] if part is None else _trees(part, field)):
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
                raise _fail(f"{where}.range", f"a revolute joint's range of a turn at most; [{low:g}, {high:g}] rad "
                                              f"spans {high - low:g} rad: in degrees?")
        for name in POSITIVE:
            if name in leg and not value(f"{where}.{name}", leg[name]) > 0:
                raise _fail(f"{where}.{name}", "a positive value at the default design")
        if "range" in leg and not value(f"{where}.range[0]", leg["range"][0]) < value(f"{where}.range[1]",
                                                                                      leg["range"][1]):
            raise _fail(f"{where}.range", "lower < upper at the default design")
        parts = [(where, leg), *((f"{where}.joints[{j}]", joint) for j, joint in enumerate(leg.get("joints", ())))]
        for at, part in parts:
            for name in DIRECTIONS:
                directions = part.get(name, ())
                for d, direction in enumerate(directions if name == "axes" else [directions] if directions else []):
                    vector = [value(f"{at}.{name}", c) for c in direction]
                    if not any(vector):
                        raise _fail(f"{at}.{name}" + (f"[{d}]" if name == "axes" else ""),
                                    "a direction (not zero) at the default design")
    for k, region in enumerate(data["regions"]):
        for j, size in enumerate(region["size"]):
            if not value(f"regions[{k}].size[{j}]", size) > 0:
                raise _fail(f"regions[{k}].size[{j}]", "a positive size at the default design")
        for j, centre in enumerate(region["centre"]):
            value(f"regions[{k}].centre[{j}]", centre)
    for k, condition in enumerate(data.get("conditions", ())):
        if not value(f"conditions[{k}].margin", condition["margin"]) > 0:
            raise _fail(f"conditions[{k}].margin", f"positive at the default design ({condition['doc']})")


def read(path: str | os.PathLike) -> Description:
    """A description from a TOML file."""
    return describe(io.read_toml(path, DescriptionError, "description file"))


def module_path(description: Description) -> Path:
    """The derived module of a description in the user's cache, derived now where it is not there yet (a
    progress bar on a terminal meanwhile)."""
    folder = location() / "descriptions"
    target = folder / f"{description.name}_{description.key[:16]}.py"
    if target.exists():
        return target
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        source = Path(tmp) / "description.json"
        source.write_text(json.dumps({**description.data, "key": description.key}, sort_keys=True))
        out = Path(tmp) / "module.py"
        with Progress(1, f"deriving {description.name} (first use, into {folder})") as bar:
            try:
                done = subprocess.run([sys.executable, "-m", "symbolic.describe", str(source), str(out)], cwd=ROOT,
                                      capture_output=True, text=True, check=False, stdin=subprocess.DEVNULL,
                                      timeout=DERIVATION_SECONDS)
            except subprocess.TimeoutExpired:
                raise ComputationError(f"deriving {description.name} took longer than its limit of "
                                       f"{DERIVATION_SECONDS:g} s") from None
            bar.advance()
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        if done.returncode == UNDEFINED:
            raise DescriptionError(f"description {description.name}: {last.removeprefix('undefined: ')} (a zero "
                                   "length or axis, or a function outside its domain, in the description?)")
        if done.returncode != 0:
            raise ComputationError(f"deriving {description.name} failed: {reprlib.repr(last)}")
        io.atomic_write(target, lambda path: path.write_bytes(out.read_bytes()))
    return target


def _legs_layout(description: Description) -> list[tuple[list[int], list[int], int | None]]:
    """Each leg's closure rows, its passive joints' columns among the passive joints, and the mode sign that
    chooses its branch (None where it has one)."""
    row = column = sign = 0
    out = []
    for leg in description.data["legs"]:
        kind = kind_of(leg)
        rows = kind.passive + 1
        out.append((list(range(row, row + rows)), list(range(column, column + kind.passive)),
                    sign if kind.branched else None))
        row, column, sign = row + rows, column + kind.passive, sign + kind.branched
    return out


def _normal(A: ca.SX) -> ca.SX:
    """The vector w with w.v = det([A v]) for every v, of an r x (r - 1) matrix A (its cofactors)."""
    r = A.size1()
    if r == 1:
        return ca.SX.ones(1)
    return ca.vertcat(*[(-1) ** (j + r - 1) * ca.det(A[[i for i in range(r) if i != j], :]) for j in range(r)])


def _reduced_det(H_p: ca.SX, B: ca.SX, legs: list[tuple[list[int], list[int], int | None]]) -> ca.SX:
    """det [H_p B] up to a constant sign, where each leg's rows hold its passive columns of H_p and nothing
    else there (one more row than columns): by the Laplace expansion along the passive columns, the
    determinant of the square matrix whose row k is w_k^T B_k, w_k the normal of leg k's block of H_p
    (:func:`_normal`), so that no determinant larger than a leg's or the pose's is expanded."""
    return ca.det(ca.vertcat(*[_normal(H_p[rows, columns]).T @ B[rows, :] for rows, columns, _ in legs]))


def composed_first_order(constraint: ca.Function, n_act: int,
                         legs: list[tuple[list[int], list[int], int | None]]) -> ca.Function:
    """``first_order(q, x, design) -> (J, J_f, psi, det_type1, det_type2)`` composed in CasADi from the loop
    closure's Jacobians (:mod:`symbolic.loops`), leg by leg: each leg's joint rates dq_k = -B_k^-1 H_x,k
    x_dot with B_k its block of [H_a H_p] (its rows, its actuated and passive columns; the legs share no
    joint), J their actuated rows, J_f = J^-1, Psi from the passive rows times J_f; the determinants of
    [H_a H_p] and [H_p H_x] reduced leg by leg (:func:`_reduced_det`, their signs those of the full
    determinants, found once at random entries)."""
    q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
    _, H_q, H_x = constraint(q, x, d)
    H_a, H_p = H_q[:, :n_act], H_q[:, n_act:]
    inverse = ca.SX.zeros(H_q.size2(), H_x.size2())
    for k, (rows, passive, _) in enumerate(legs):
        columns = [k, *(n_act + p for p in passive)]
        inverse[columns, :] = ca.solve(H_q[rows, columns], -H_x[rows, :])
    J = inverse[:n_act, :]
    J_f = ca.solve(J, ca.SX.eye(n_act))
    psi = ca.vertcat(ca.SX.eye(n_act), inverse[n_act:, :] @ J_f)
    dets = []
    for B, full in ((H_a, H_q), (H_x, ca.horzcat(H_p, H_x))):
        reduced = _reduced_det(H_p, B, legs)
        probe = ca.Function("probe", [q, x, d], [reduced, full])
        values = np.random.default_rng(0).uniform(0.5, 1.5, size=(3, max(q.numel(), x.numel(), d.numel())))
        small, matrix = probe(values[0, : q.numel()], values[1, : x.numel()], values[2, : d.numel()])
        dets.append(float(np.sign(np.linalg.det(np.asarray(matrix, dtype=float)) * float(small))) * reduced)
    return ca.Function("first_order", [q, x, d], [J, J_f, psi, *dets],
                       ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


CONTINUATION_STEPS = 12  # Newton steps along the path from the home pose at the default design
NEWTON_STEPS = 12  # Newton steps at the pose asked for, after the path (8 left one pose in 10^6 of the
# benchmark 4e-10 rad from its root, near a universal joint's own singularity)
START_STEPS = 30  # Newton steps that close a chain's seed at the home pose, at most
CHAIN_TOLERANCE = 1e-13  # [m] a chain leg closes to this where its pose is reached


def _path(a0: Any, c0: Any, a1: Any, c1: Any, t: float, *, straight: bool) -> Any:
    """The platform attachment at t on the path from c0 to c1 (c1 itself at t = 1): straight, or about the base
    attachment (from a0 to a1), with the distance from it interpolated and its direction turned at a constant
    rate in the plane of the two (slerp), so that a leg whose reach is a shell about its base stays in it."""
    if straight or t == 1.0:
        return (1 - t) * c0 + t * c1
    a = (1 - t) * a0 + t * a1
    d0, d1 = c0 - a0, c1 - a1
    r0, r1 = ca.norm_2(d0), ca.norm_2(d1)
    u0, u1 = d0 / r0, d1 / r1
    if u0.numel() == 2:
        angle = t * ca.atan2(u0[0] * u1[1] - u0[1] * u1[0], ca.dot(u0, u1))
        u = ca.vertcat(ca.cos(angle) * u0[0] - ca.sin(angle) * u0[1], ca.sin(angle) * u0[0] + ca.cos(angle) * u0[1])
    else:
        across = u1 - ca.dot(u0, u1) * u0
        sine = ca.norm_2(across)
        angle = t * ca.atan2(sine, ca.dot(u0, u1))
        u = ca.cos(angle) * u0 + ca.sin(angle) * across / ca.if_else(sine > 0, sine, 1)
    return a + ((1 - t) * r0 + t * r1) * u


def _closed_seed(leg: ca.Function, seed: np.ndarray, x: np.ndarray, design: np.ndarray, where: str) -> np.ndarray:
    """A chain leg's seed closed by Newton at the home pose and the default design, each step halved until
    the residual falls, until it falls no more: closed where it is then below CHAIN_TOLERANCE."""
    q = seed.copy()
    h, H = (np.asarray(v, dtype=float) for v in leg(q, x, design))
    for _ in range(START_STEPS):
        if not np.abs(h).max():
            break
        try:
            step = np.linalg.lstsq(H, h, rcond=None)[0].ravel()
        except np.linalg.LinAlgError:
            break
        for _ in range(START_STEPS):
            trial = q - step
            h_trial, H_trial = (np.asarray(v, dtype=float) for v in leg(trial, x, design))
            if np.abs(h_trial).max() < np.abs(h).max():
                q, h, H = trial, h_trial, H_trial
                break
            step = step / 2
        else:
            break
    if np.abs(h).max() < CHAIN_TOLERANCE:
        return q
    raise DescriptionError(f"description field {where} violates: a seed the leg closes from at the home pose "
                           f"(Newton from it stops at the residual {np.abs(h).max():.1e})")


def composed_inverse_kinematics(description: Description, functions: Mapping[str, ca.Function]) -> ca.Function:
    """``inverse_kinematics(x, mode, design) -> (q, reach)`` of a description with chain legs: the closed-form
    legs' joints from ``continuation_start``; each chain leg's by Newton from its branch's seed (closed at the
    home pose and the default design) along a path of its platform attachment (:func:`_path`: about the base
    attachment, straight where the chain starts with a prismatic joint) to the pose and design asked for, one
    step at each of CONTINUATION_STEPS points, then NEWTON_STEPS there; NaN where it does not close to
    CHAIN_TOLERANCE (so that no value depends on the rounding of iterations that diverge). Its reach: the
    closed-form legs', then per chain leg its closure's Jacobian's determinant in its joints with the sign of
    the seed's (the branch not left; 0 at the leg's singularity, the edge of its reach); the legs' ranges are
    the description's stated limits (:func:`pkm.kinematics.within_limits`), not its reach. The joints are
    differentiable in the pose and the design: at a converged Newton step the derivative is the implicit
    function's."""
    start = functions["continuation_start"]
    d0 = np.array([p["default"] for p in description.data["parameters"]])
    (x0,) = evaluate(functions["home"], d0)
    x0 = x0[0, :, 0]
    n_mode = start.numel_in(1)
    x, mode, d = (ca.SX.sym(start.name_in(i), start.size_in(i)) for i in range(3))
    q_start, reach = start(x, mode, d)
    q = ca.vertsplit(q_start)
    margins = [reach]
    n_act = len(description.data["legs"])
    for k, (_, passive, sign) in enumerate(_legs_layout(description)):
        if f"chain{k + 1}" not in functions:
            continue
        columns = [k, *(n_act + p for p in passive)]
        leg, ends = functions[f"chain{k + 1}"], functions[f"chain{k + 1}_ends"]
        a0, c0 = (np.asarray(v, dtype=float).ravel() for v in ends(x0, d0))
        seeds, sides = [], []
        names = [name for name, _ in description.data["legs"][k]["branches"]]
        angles = np.array([kind_of(description.data["legs"][k]).unit == "rad",
                           *passive_angles(description.data["legs"][k])])
        for s in (1.0, -1.0):
            q_s = np.asarray(start(x0, np.full(n_mode, s), d0)[0], dtype=float).ravel()[columns]
            where = f"legs (leg {k + 1}) branches.{names[0 if s > 0 or sign is None else 1]}"
            closed = _closed_seed(leg, q_s, c0, d0, where)
            closed[angles] = np.angle(np.exp(1j * closed[angles]))
            seeds.append(closed)
            sides.append(float(np.sign(np.linalg.det(np.asarray(leg(closed, c0, d0)[1], dtype=float)))))
        weight = 1.0 if sign is None else (1 + mode[sign]) / 2
        q_leg = weight * ca.DM(seeds[0]) + (1 - weight) * ca.DM(seeds[1])
        side = weight * sides[0] + (1 - weight) * sides[1]
        a1, c1 = ends(x, d)
        straight = description.data["legs"][k]["joints"][0]["type"] == "P"
        for t in [*np.linspace(1.0 / CONTINUATION_STEPS, 1.0, CONTINUATION_STEPS), *[1.0] * NEWTON_STEPS]:
            h, H = leg(q_leg, _path(a0, c0, a1, c1, t, straight=straight), d0 + t * (d - d0))
            q_leg = q_leg - ca.solve(H, h)
        h, _ = leg(q_leg, c1, d)
        q_leg = ca.if_else(ca.norm_inf(h) <= CHAIN_TOLERANCE, q_leg, np.nan)
        margins.append(side * ca.det(leg(q_leg, c1, d)[1]))
        for j, c in enumerate(columns):
            q[c] = q_leg[j]
    return ca.Function("inverse_kinematics", [x, mode, d], [ca.vertcat(*q), ca.vertcat(*margins)],
                       start.name_in(), start.name_out())


SEED_SAMPLES = 16384  # random poses per round of the search for seeds (and per box size of the workspace box)
SEED_COUNT = 32768  # configurations that seed the forward kinematics, at least (unless SEED_ROUNDS run out)
SEED_ROUNDS = 32
SEED_STEP = 1 / 32  # after the first round, half the poses are found ones moved by this share of the box
SEEDS_KEPT = 8  # seed tables kept (one per design)
BOX_MARGIN = 0.05  # an estimated workspace box grows by this share of its width on each side
BOX_SCALES = 4  # sizes of the boxes about the home pose where the workspace box is looked for


@dataclass(frozen=True)
class Seeds:
    """The configurations that seed a description's forward kinematics (:class:`pkm.kinematics.NearestSeeds`)
    and the signature that names its assembly modes: the side of each leg whose passive joints have two
    branches (``branch_sides``: an RR leg's elbow, sin(phi - theta); a chain's det of its closure's Jacobian
    in its joints) and the sign of the type-II determinant det [H_p H_x]. The configurations are those of every
    branch of the legs where they assemble at random poses in the workspace box (:meth:`box`; a fixed
    seed), half of them, after the first round, found ones moved at random (so that a thin workspace fills
    too), until there are SEED_COUNT; one table per design."""

    data: Mapping[str, Any]

    @property
    def periodic(self) -> tuple[bool, ...]:
        return tuple(kind_of(leg).unit == "rad" for leg in self.data["legs"])

    @property
    def angles(self) -> tuple[bool, ...]:
        passive = tuple(a for leg in self.data["legs"] for a in passive_angles(leg))
        return passive + tuple(unit == "rad" for unit in self.data["pose"]["units"])

    def signature(self, functions: FunctionTable, q: np.ndarray, x: np.ndarray, design: np.ndarray) -> np.ndarray:
        *_, det = evaluate(functions["first_order"], q, x, design)
        if "branch_sides" not in functions:
            return np.sign(det[:, 0, 0])[:, None]
        (sides,) = evaluate(functions["branch_sides"], q, x, design)
        return np.column_stack([np.sign(sides[:, :, 0]), np.sign(det[:, 0, 0])])

    def table(self, functions: FunctionTable, design: np.ndarray) -> dict[tuple[float, ...], tuple[np.ndarray, ...]]:
        return self._pooled(functions, np.asarray(design, dtype=float))

    def _pooled(self, functions: FunctionTable, design: np.ndarray) -> dict[tuple[float, ...], tuple[np.ndarray, ...]]:
        key = (id(functions), design.tobytes())
        if key not in _SEED_TABLES:
            if len(_SEED_TABLES) >= SEEDS_KEPT:
                _SEED_TABLES.pop(next(iter(_SEED_TABLES)))
            q, x, signatures = self._configurations(functions, design)
            n_act = len(self.data["legs"])
            groups = {}
            for signature in sorted(set(map(tuple, signatures.tolist()))):
                mine = np.all(signatures == signature, axis=1)
                groups[signature] = (q[mine, :n_act], np.hstack([q[mine, n_act:], x[mine]]))
            _SEED_TABLES[key] = (functions, groups)
        return _SEED_TABLES[key][1]

    def _assembled(self, functions: FunctionTable, x: np.ndarray, design: np.ndarray) -> tuple[np.ndarray, ...]:
        """The configurations (q, x) of every branch of the legs at the poses x where they assemble."""
        branched = sum(kind_of(leg).branched for leg in self.data["legs"])
        qs, xs = [], []
        for signs in itertools.product((1.0, -1.0), repeat=branched) if branched else [(1.0,)]:
            with np.errstate(invalid="ignore"):
                q, reach = evaluate(functions["inverse_kinematics"], x, np.array(signs), design)
                ok = np.all(reach[:, :, 0] >= 0.0, axis=1) & np.all(np.isfinite(q[:, :, 0]), axis=1)
            qs.append(q[ok, :, 0])
            xs.append(x[ok])
        return np.concatenate(qs), np.concatenate(xs)

    def _sample(self, box: np.ndarray) -> np.ndarray:
        rng = np.random.default_rng(0)
        return rng.uniform(box[:, 0], box[:, 1], size=(SEED_SAMPLES, len(box)))

    def box(self, functions: FunctionTable, design: np.ndarray) -> np.ndarray:
        """The box of the poses where some branch of the legs assembles, estimated from random poses about
        the home pose (in boxes of BOX_SCALES sizes, halving, so that a small workspace is found in a large
        box), grown by BOX_MARGIN of its width on each side; kept for the last SEEDS_KEPT designs."""
        design = np.asarray(design, dtype=float)
        key = (id(functions), design.tobytes())
        if key not in _BOXES:
            if len(_BOXES) >= SEEDS_KEPT:
                _BOXES.pop(next(iter(_BOXES)))
            _BOXES[key] = (functions, self._box(functions, design))
        return _BOXES[key][1].copy()

    def _box(self, functions: FunctionTable, design: np.ndarray) -> np.ndarray:
        units = self.data["pose"]["units"]
        (home,) = evaluate(functions["home"], design)
        lengths = [abs(v) for p, v in zip(self.data["parameters"], design, strict=True) if p["unit"] == "m"]
        half = np.array([math.pi / 2 if unit == "rad" else (sum(lengths) or 1.0) for unit in units])
        centre = home[0, :, 0]
        around = np.column_stack([centre - half, centre + half])
        scales = 2.0 ** -np.arange(BOX_SCALES)
        x = np.concatenate([centre + scale * (self._sample(around) - centre) for scale in scales])
        _, inside = self._assembled(functions, x, design)
        if len(inside) == 0:
            return around
        lo, hi = inside.min(axis=0), inside.max(axis=0)
        grow = BOX_MARGIN * np.maximum(hi - lo, 1e-9)
        return np.column_stack([np.maximum(lo - grow, around[:, 0]), np.minimum(hi + grow, around[:, 1])])

    def _configurations(self, functions: FunctionTable, design: np.ndarray) -> tuple[np.ndarray, ...]:
        box = self.box(functions, design)
        rng = np.random.default_rng(1)
        qs, xs = [], []
        width = box[:, 1] - box[:, 0]
        for _ in range(SEED_ROUNDS):
            x = rng.uniform(box[:, 0], box[:, 1], size=(SEED_SAMPLES, len(box)))
            if xs:
                found = np.concatenate(xs)
                x[SEED_SAMPLES // 2 :] = found[rng.integers(len(found), size=SEED_SAMPLES - SEED_SAMPLES // 2)] \
                    + SEED_STEP * width * rng.standard_normal((SEED_SAMPLES - SEED_SAMPLES // 2, len(box)))
            q, x = self._assembled(functions, x, design)
            qs.append(q)
            xs.append(x)
            if sum(map(len, qs)) >= SEED_COUNT:
                break
        q, x = np.concatenate(qs), np.concatenate(xs)
        with np.errstate(invalid="ignore"):
            signature = self.signature(functions, q, x, design)
        regular = np.all(signature != 0.0, axis=1)
        return q[regular], x[regular], signature[regular]


_SEED_TABLES: dict[tuple, tuple[FunctionTable, dict[tuple[float, ...], tuple[np.ndarray, ...]]]] = {}
_BOXES: dict[tuple, tuple[FunctionTable, np.ndarray]] = {}


def composed_inertia(mass_matrix: ca.Function, first_order: ca.Function) -> ca.Function:
    """``inertia(q, x, design) -> (M_t, M_w)``: the mass matrix M of the kinetic energy in (q, x) projected
    onto the actuated rates, M_t = P^T M P with P = d(q, x)/d(q_a) = [Psi; J_f], and onto the pose rates,
    M_w = J^T M_t J (q_dot = J x_dot)."""
    q, x, d = (ca.SX.sym(mass_matrix.name_in(i), mass_matrix.size_in(i)) for i in range(3))
    M = mass_matrix(q, x, d)
    J, J_f, psi, *_ = first_order(q, x, d)
    P = ca.vertcat(psi, J_f)
    M_t = P.T @ M @ P
    return ca.Function("inertia", [q, x, d], [M_t, J.T @ M_t @ J], ["q", "x", "design"], ["M_t", "M_w"])


def composed_energy(mass_matrix: ca.Function, first_order: ca.Function, gravity: ca.Function | None) -> ca.Function:
    """``energy(q, x, x_dot, design) -> (T, V)``: the bodies' kinetic energy z_dot^T M z_dot / 2 at the rates
    z_dot = (q_dot, x_dot) of all the joints (q_dot = Psi J x_dot) and the pose, and their potential energy in
    the description's gravity (0 without)."""
    q, x, d = (ca.SX.sym(mass_matrix.name_in(i), mass_matrix.size_in(i)) for i in range(3))
    x_dot = ca.SX.sym("x_dot", x.numel())
    J, _, psi, *_ = first_order(q, x, d)
    z_dot = ca.vertcat(psi @ (J @ x_dot), x_dot)
    T = 0.5 * z_dot.T @ mass_matrix(q, x, d) @ z_dot
    V = gravity(q, x, d)[1] if gravity is not None else ca.SX(1, 1)
    return ca.Function("energy", [q, x, x_dot, d], [T, V], ["q", "x", "x_dot", "design"], ["T", "V"])


def composed_inverse_dynamics(constraint: ca.Function, mass_matrix: ca.Function, first_order: ca.Function,
                              gravity: ca.Function | None) -> ca.Function:
    """``inverse_dynamics(q, x, x_dot, x_ddot, design) -> tau``: Lagrange's equations of the bodies in all
    coordinates z = (q, x), Q = M z_ddot + M_dot z_dot - (d/dz)(z_dot^T M z_dot) / 2 + dV/dz, projected onto
    the actuated joints by virtual work, tau = P^T Q with P = dz/dq_a = [Psi; J_f] (the loop's constraint
    forces do no work along P). The rates: q_dot = Psi J x_dot; the accelerations from the loop's second
    order, H_q q_ddot + H_x x_ddot + (dH_q/dt) q_dot + (dH_x/dt) x_dot = 0."""
    q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
    x_dot, x_ddot = ca.SX.sym("x_dot", x.numel()), ca.SX.sym("x_ddot", x.numel())
    _, H_q, H_x = constraint(q, x, d)
    J, J_f, psi, *_ = first_order(q, x, d)
    z = ca.vertcat(q, x)
    q_dot = psi @ (J @ x_dot)
    rates = ca.SX.sym("rates", z.numel())
    z_dot = ca.vertcat(q_dot, x_dot)
    bias = ca.substitute(ca.jtimes(H_q @ rates[: q.numel()] + H_x @ rates[q.numel() :], z, rates), rates, z_dot)
    q_ddot = ca.solve(H_q, -(H_x @ x_ddot + bias))
    M = mass_matrix(q, x, d)
    coriolis = ca.jtimes(M @ rates, z, rates) - ca.gradient(0.5 * rates.T @ M @ rates, z)
    Q = M @ ca.vertcat(q_ddot, x_ddot) + ca.substitute(coriolis, rates, z_dot)
    if gravity is not None:
        Q = Q + gravity(q, x, d)[0]
    tau = ca.vertcat(psi, J_f).T @ Q
    return ca.Function("inverse_dynamics", [q, x, x_dot, x_ddot, d], [tau],
                       ["q", "x", "x_dot", "x_ddot", "design"], ["tau"])


class DescribedFunctions(FunctionTable):
    """The functions of a description's derived module and those composed from them."""

    def __init__(self, description: Description) -> None:
        super().__init__({}, f"the description {description.name}")
        self.description = description

    @cached_property
    def _functions(self) -> dict[str, ca.Function]:
        path = module_path(self.description)
        spec = importlib.util.spec_from_file_location(f"pkm_description_{self.description.name}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        functions = module.build()
        n_act = len(module.ACTUATORS)
        functions["first_order"] = composed_first_order(functions["constraint"], n_act, _legs_layout(self.description))
        if "continuation_start" in functions:
            functions["inverse_kinematics"] = composed_inverse_kinematics(self.description, functions)
        if limited(self.description.data):
            functions.update(within_limits(functions, LIMITS))
        self._limit_names = tuple(getattr(module, "LIMITS", ()))
        if "mass_matrix" in functions:
            functions["inertia"] = composed_inertia(functions["mass_matrix"], functions["first_order"])
            functions["energy"] = composed_energy(functions["mass_matrix"], functions["first_order"],
                                                  functions.get("gravity"))
            functions["inverse_dynamics"] = composed_inverse_dynamics(
                functions["constraint"], functions["mass_matrix"], functions["first_order"], functions.get("gravity"))
        return functions

    def _load(self) -> dict[str, ca.Function]:
        return self._functions

    @property
    def limit_names(self) -> tuple[str, ...]:
        """The names of the margins of ``workspace_margins``, leg by leg (``leg 1 reach``, ``leg 1 range
        upper``, ...)."""
        self._load()
        return self._limit_names

    @property
    def source_hash(self) -> str:
        """The description's key: the hash of its normalised form and of the tools that derive it."""
        return self.description.key[:16]


LIMITS = "workspace_margins"  # a description's stated limits: its legs' ranges and cones, beside their reach


def limited(data: Mapping[str, Any]) -> bool:
    """Whether a normalised description states limits beyond its legs' reach (a range, a cone)."""
    return any("range" in leg or "cone" in leg for leg in data["legs"])


def _mode_name(signs: Sequence[int]) -> str:
    return "".join("p" if s > 0 else "n" for s in signs)


def _modes(data: Mapping[str, Any]) -> tuple[Branch, ...]:
    """The working modes: the named sign combinations of the branched legs where the description names
    some, else every combination (the first leg's sign the slowest, +1 before -1), named by the words of each
    leg's branch in order (``left_left_right``)."""
    kinds = [kind_of(leg) for leg in data["legs"] if kind_of(leg).branched]
    named = {tuple(float(s) for s in v): k for k, v in data["modes"].items()}
    combos = list(named) or (list(itertools.product((1.0, -1.0), repeat=len(kinds))) if kinds else [(1.0,)])
    meanings = "; ".join(dict.fromkeys(f"{'/'.join(k.branches)}: {k.meaning}" for k in kinds))

    def words(combo: tuple[float, ...]) -> list[str]:
        return [k.branches[0 if s > 0 else 1] for k, s in zip(kinds, combo, strict=True)]

    if not kinds:
        return tuple(Branch(named.get(c, "single"), tuple(c), "every leg has one branch") for c in combos)
    return tuple(Branch(named.get(c, "_".join(words(c))), tuple(c),
                        f"legs {', '.join(words(c))} ({meanings}); branch signs {', '.join(f'{s:+.0f}' for s in c)}")
                 for c in combos)


def working_modes(mech: Mechanism) -> tuple[Branch, ...]:
    """A described mechanism's working modes (:func:`_modes`): those its description names, in its order, else
    every combination, those in which the home pose is regular at the default design (reached, both
    singularity margins at least :data:`pkm.indices.local.SINGULAR`) first, each part in the combinations' order:
    the default mode is not a degenerate one where another is regular (a 2-PRR's with both sliders at one
    point, where the platform turns about them with the sliders held)."""
    modes = _modes(mech.description.data)
    if mech.description.data["modes"] or len(modes) == 1:
        return modes
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)

    def singular(mode: Branch) -> bool:
        margins = [index_values(mech, (index,), home[:, :, 0], np.array(mode.signs), design)[0][0]
                   for index in (SINGULARITY_TYPE1, SINGULARITY_TYPE2)]
        return not np.all(np.concatenate(margins) >= SINGULAR)

    return tuple(sorted(modes, key=singular))


RANKS = {"planar_point": 1, "planar": 2, "spatial_point": 1, "spatial": 8}  # solutions of one signature told
# apart by rank, by the pose (a planar 3-DOF machine has up to 6 assemblies, a 6-DOF one up to 40)


def _assemblies(data: Mapping[str, Any]) -> tuple[Branch, ...]:
    """The assembly modes: the side of each two-branched leg, the sign of the type-II determinant (the
    signature of :class:`Seeds`) and the rank among the signature's solutions by the last pose coordinate
    (:class:`pkm.kinematics.NearestSeeds`; ``_2`` names the second) where a frame has several (RANKS)."""
    elbows = sum(kind_of(leg).sided for leg in data["legs"])
    last = FRAMES[data["pose"]["frame"]][0][-1]
    out = []
    for combo in itertools.product((1.0, -1.0), repeat=elbows):
        for det, label in ((1.0, "positive"), (-1.0, "negative")):
            for rank in range(1, RANKS[data["pose"]["frame"]] + 1):
                name = "_".join(filter(None, [_mode_name(combo), label, "" if rank == 1 else str(rank)]))
                sides = f"elbow sides {', '.join(f'{s:+.0f}' for s in combo)}, " if combo else ""
                out.append(Branch(name, (*combo, det, float(rank)),
                                  f"{sides}type-II determinant {label}, solution {rank} by {last}"))
    return tuple(out)


def mechanism_class(description: Description) -> type[Mechanism]:
    """The :class:`Mechanism` subclass of a description."""
    data = description.data
    pose_names, _ = FRAMES[data["pose"]["frame"]]
    seeds = Seeds(data)
    parameters = tuple(Parameter(p["name"], p["default"], p["lower"], p["upper"], p["unit"], p["doc"],
                                 closed_lower=True) for p in data["parameters"])
    conditions = tuple(Condition(f"{c['doc']} ({expressions.text(c['margin'])} > 0)", expressions.function(c["margin"]))
                       for c in data.get("conditions", []))
    length = data["characteristic_length"]
    attributes = {
        "name": data["name"],
        "doc": data["doc"],
        "parameters": parameters,
        "conditions": conditions,
        "working_modes": cached_property(working_modes),
        "assembly_modes": _assemblies(data),
        "pose_names": pose_names,
        "pose_units": tuple(data["pose"]["units"]),
        "actuator_names": tuple(f"q{k + 1}" for k in range(len(data["legs"]))),
        "actuator_units": tuple(kind_of(leg).unit for leg in data["legs"]),
        "skeleton_legs": tuple(kind_of(leg).points for leg in data["legs"]),
        "forward": NearestSeeds(seeds),
        "description": description,
        "functions": cached_property(lambda self: DescribedFunctions(self.description)),
        "workspace_box": _workspace_box,
        "regions": {r["name"]: _region(r, len(pose_names)) for r in data["regions"]},
        "limits": LIMITS if limited(data) else None,
        "limit_names": property(lambda self: self.functions.limit_names),
    }
    if length is not None:
        attributes["characteristic_length"] = staticmethod(expressions.function(length))
    cls = type(f"Described_{data['name']}", (Mechanism,), attributes)
    cls.functions.__set_name__(cls, "functions")
    return cls


SHAPE_CLASSES = {"disc": Disc, "rectangle": Rectangle, "box": Box, "cylinder": Cylinder}


def _region(region: Mapping[str, Any], n_out: int) -> Any:
    """The parametrised region of a description's region: placed by the derived ``region_<name>(design) ->
    (centre, size)``, and mapped into the pose by ``region_<name>_pose(y, design) -> x`` where it spans
    other coordinates than the pose's own, in order."""
    name, doc = region["name"], region["doc"]
    extra = {"axis": region["axis"]} if region["shape"] == "cylinder" else {}
    shape = SHAPE_CLASSES[region["shape"]](name, doc, function=f"region_{name}", **extra)
    if region["coordinates"] == list(range(n_out)):
        return shape
    return Mapped(name, doc, shape, to_pose=f"region_{name}_pose")



def _workspace_box(self: Mechanism, design: np.ndarray) -> np.ndarray:
    """The box the sampled workspace grids: that of the poses where some branch of the legs assembles
    (:meth:`Seeds.box`)."""
    return self.forward.seeds.box(self.functions, np.asarray(design, dtype=float))


_INSTANCES: dict[str, Mechanism] = {}


def _instance(description: Description) -> Mechanism:
    """One mechanism per description (by its key), checked once."""
    if description.key not in _INSTANCES:
        mech = mechanism_class(description)()
        check_mobility(mech)
        warn_singular_home(mech)
        _INSTANCES[description.key] = mech
    return _INSTANCES[description.key]


def load(source: Mapping[str, Any] | Description | str | os.PathLike) -> Mechanism:
    """The mechanism of a description (a mapping, a :class:`Description` or a TOML file's path), derived on
    first use and checked (:func:`check_mobility`)."""
    description = read(source) if isinstance(source, str | os.PathLike) else describe(source)
    return _instance(description)


def resolve(text: str) -> Mechanism:
    """The mechanism a :func:`pkm.registry.reference` names: a described machine derived (once) into this
    process's cache, or the registered one."""
    if text.startswith(registry.DESCRIBED):
        return load(Description(json.loads(text[len(registry.DESCRIBED) :])))
    return registry.mechanism(text)


def resolve_name(name: str) -> Mechanism:
    """The mechanism of a name: a description file (``.toml``) derived on first use, or a registered one."""
    return load(name) if name.endswith(SUFFIX) else registry.mechanism(name)


def warn_singular_home(mech: Mechanism) -> None:
    """A :class:`pkm.errors.SingularityWarning` for each working mode in which the home pose is singular at the
    default design, naming the singularity and its margin (an index there is its limit, not the machine's)."""
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)
    for mode in mech.modes:
        note = mech.singularity_note(home[0, :, 0], design, mode=mode)
        if note:
            warnings.warn(SingularityWarning(f"description {mech.name}: its home {note}"), stacklevel=3)


def _unreached(mech: Mechanism, x: np.ndarray, design: np.ndarray) -> list[str]:
    """Why a pose is out of reach in the first working mode: each margin of ``workspace_margins`` below 0 at
    the joints without the stated limits (a range by its leg's actuated joint, its value and the range; a reach
    or a cone by its margin), and each leg whose joints do not close there otherwise; else a chain leg's reach
    (the sign of its Jacobian's determinant, which ``workspace_margins`` does not hold)."""
    data = mech.description.data
    q = mech.inverse_kinematics(x, design, passive=True, limits=False)
    (margins,) = evaluate(mech.functions["workspace_margins"], q, x, design)
    values = dict(zip(mech.parameter_names(), design, strict=True))
    reasons, named = [], set()
    for name, margin in zip(mech.limit_names, margins[0, :, 0], strict=True):
        if not margin < 0:
            continue
        leg, what = name.removeprefix("leg ").split(" ", 1)
        k = int(leg) - 1
        named.add(k)
        if what.startswith("range"):
            unit = mech.actuator_units[k]
            low, high = (expressions.evaluate(b, values) for b in data["legs"][k]["range"])
            reasons.append(f"leg {leg}'s actuated joint {mech.actuator_names[k]} = {q[k]:.6g} {unit} lies outside "
                           f"its range [{low:.6g}, {high:.6g}] {unit} ({name} = {margin:.3g})")
        else:
            reasons.append(f"{name} = {margin:.3g} < 0")
    for k, (_, passive, _) in enumerate(_legs_layout(mech.description)):
        joints = q[[k, *(len(data["legs"]) + p for p in passive)]]
        if k not in named and not np.all(np.isfinite(joints)):
            reasons.append(f"leg {k + 1}'s joints do not close at the pose")
    return reasons or ["a chain leg crosses its own singularity on the way from its seed"]


def check_mobility(mech: Mechanism) -> None:
    """The home pose assembles at the default design in the first mode, closing every leg, and the closure's
    Jacobian [H_q H_x] has full row rank there with as many degrees of freedom as actuated joints:
    :class:`DescriptionError` otherwise."""
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)
    x = home[0, :, 0]
    q = mech.inverse_kinematics(x, design, passive=True)
    if not np.all(np.isfinite(q)):
        raise DescriptionError(f"description {mech.name}: the home pose {x.tolist()} does not assemble at the "
                               f"default design in its first working mode {mech.working_modes[0].name}: "
                               f"{'; '.join(_unreached(mech, x, design))}")
    h, H_q, H_x = (v[0] for v in evaluate(mech.functions["constraint"], q, x, design))
    scale = max(1.0, float(np.abs(design).max()))
    if np.abs(h).max() > CLOSURE_TOLERANCE * scale**2:
        raise DescriptionError(f"description {mech.name}: the legs do not close at the home pose (residual "
                               f"{np.abs(h).max():.1e})")
    full = np.hstack([H_q, H_x])
    singular = np.linalg.svd(full, compute_uv=False)
    rank = int(np.sum(singular > RANK_TOLERANCE * singular.max()))
    freedom = full.shape[1] - rank
    if rank < full.shape[0] or freedom != mech.n_out:
        raise DescriptionError(f"description {mech.name}: mobility {freedom} at the home pose, not the {mech.n_out} "
                               f"of its pose ({full.shape[0]} closure equations of rank {rank} in {full.shape[1]} "
                               "coordinates)")
