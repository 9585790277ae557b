"""Descriptions documented by their schema (issue 37, item 9): the reference of docs/mechanisms.md (section 7) is
the one pkm.schema_docs writes from the tables pkm.spec checks descriptions against, and the checks agree with
it field by field: four descriptions that give every field it lists, in every table, are accepted; a field it
does not list is refused in every table, naming it; a field it lists as required is refused where missing,
naming it."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator

import pytest

from pkm import schema_docs
from pkm.spec.schema import DescriptionError, describe

PARAMETERS = [
    {"name": "R", "default": 1.0, "lower": 0.1, "upper": 5, "unit": "m", "doc": "base circle"},
    {"name": "r", "default": 0.3, "lower": 0.05, "upper": 5, "unit": "m", "doc": "platform circle"},
    {"name": "l", "default": 0.8, "lower": 0.05, "upper": 5},
]
BODY = {"mass": 1.0, "centre": 0.2, "inertia": 0.01}
PLANAR_BODY = {"mass": 0.5, "centre": [0.1, 0], "inertia": 0.002}
SPATIAL_BODY = {"mass": 0.5, "centre": [0.1, 0, 0], "inertia": [1e-3, 1e-3, 2e-3]}
RR_BODIES = {"rotor": 1e-4, "proximal": BODY, "distal": BODY}
ELASTIC = {"material": "steel", "section": {"shape": "tube", "d": 0.02, "t": 0.002}, "drive": "1e4"}
EXAMPLES = {
    "elbows": {
        "name": "elbows", "doc": "a planar 3-RR, every field of the description", "frame": "planar",
        "home": [0, 0, 0], "characteristic_length": "r", "modes": {"first": [1, 1, 1], "second": [1, 1, -1]},
        "gravity": [0, -9.81], "platform": {"mass": 2.0, "centre": [0, 0], "inertia": 0.05},
        "plates": {"platform": 0.01},
        "parameters": PARAMETERS, "conditions": [{"margin": "R - r", "doc": "the base larger than the platform"}],
        "regions": [{"name": "task", "doc": "a cylinder", "shape": "cylinder", "coordinates": ["x", "y", "phi"],
                     "centre": [0, 0, 0], "size": [0.1, 0.2], "axis": "phi"}],
        "legs": [
            {"kind": "RR", "count": 2, "base": {"circle": "R", "start": "pi/2", "pairs": "pi/6"},
             "platform": [["r", 0], [0, "r"]], "proximal": "l", "distal": "l", "range": [-3, 3], "bodies": RR_BODIES,
             "elastic": ELASTIC, "capsule": 0.02, "layers": [0, 1]},
            {"kind": "RR", "base": [[0, "-R"]], "platform": {"circle": "r", "start": "-pi/2"}, "proximal": "l",
             "distal": "l", "bodies": RR_BODIES, "capsule": 0.02, "layers": [0, 0],
             "elastic": {**ELASTIC, "passive": ["200"], "bearings": ["1e7", "2e7", "1e7"]}},
        ],
    },
    "sliders": {
        "name": "sliders", "frame": "planar", "home": [0, 0, 0], "parameters": PARAMETERS,
        "legs": [
            {"kind": "RPR", "count": 1, "base": [["R", 0]], "platform": [["r", 0]], "range": [0.1, 2],
             "bodies": {"rotor": 0.1, "cylinder": BODY, "piston": BODY}, "elastic": ELASTIC, "capsule": 0.02,
             "layers": [0]},
            {"kind": "PRR", "count": 1, "base": [[0, "-R"]], "platform": [[0, "-r"]], "distal": "l", "axis": [1, 0],
             "range": [-1, 1], "bodies": {"rotor": 0.1, "slider": {"mass": 1.0}, "distal": BODY},
             "elastic": {**ELASTIC, "beams": [{"material": {"E": "7e10", "G": "2.6e10", "density": 2700},
                                               "section": {"shape": "rect_tube", "b": 0.02, "h": 0.03, "t": 0.002}}]},
             "capsule": 0.02, "layers": [0, 1]},
            {"kind": "chain", "base": [[0, "R"]], "platform": [[0, "r"]], "turn": [0], "range": [-1, 1],
             "newton": True, "branches": {"left": [0.0, 0.0], "right": [0.0, 3.0]},
             "joints": [{"type": "P", "axis": [1, 0], "link": [0, 0], "actuated": True, "body": PLANAR_BODY,
                         "rotor": 0.1},
                        {"type": "R", "link": [0, "-l"], "body": PLANAR_BODY}], "elastic": ELASTIC, "capsule": 0.02,
             "layers": [0, 1]},
        ],
    },
    "arms": {
        "name": "arms", "frame": "spatial_point", "home": [0, 0, -0.5], "parameters": PARAMETERS,
        "plates": {"base": 0.01, "platform": {"radius": 0.01, "points": [["r", 0, 0], [0, "r", 0], ["-r", 0, 0]]}},
        "legs": [
            {"kind": "R_parallelogram", "count": 1, "base": [["R", 0, 0]], "platform": [["r", 0, 0]], "arm": "l",
             "rod": "2*l", "axis": [0, 1, 0], "zero": [1, 0, 0], "range": [-1, 1],
             "bodies": {"rotor": 1e-4, "arm": BODY, "rod": {"mass": 0.1}},
             "elastic": {**ELASTIC, "tilts": ["5e3", 0, 0]}, "capsule": 0.02, "layers": [0, 0]},
            {"kind": "UPS", "count": 1, "base": [[0, "R", 0]], "platform": [[0, "r", 0]], "cone": "pi/4",
             "range": [0.1, 2],
             "bodies": {"rotor": 0.1, "cylinder": BODY, "piston": BODY}, "elastic": ELASTIC, "capsule": 0.02,
             "layers": [1]},
            {"kind": "chain", "base": [["-R", 0, 0]], "platform": [["-r", 0, 0]], "branches": {"up": [0, 0, 0]},
             "joints": [{"type": "R", "axis": [0, 1, 0], "link": ["l", 0, 0], "actuated": True,
                         "body": SPATIAL_BODY, "rotor": 1e-4},
                        {"type": "U", "axes": [[0, 1, 0], [1, 0, 0]], "link": [0, 0, "2*l"], "actuated": False,
                         "body": SPATIAL_BODY},
                        {"type": "S", "actuated": False}], "elastic": ELASTIC, "capsule": 0.02,
             "layers": [0, 0]},
        ],
    },
    "rods": {
        "name": "rods", "frame": "spatial_point", "home": [0, 0, -0.5], "parameters": PARAMETERS,
        "legs": {"kind": "chain", "count": 3, "base": {"circle": "R"}, "platform": {"circle": "r"},
                 "branches": {"down": [0, 0, 0]},
                 "joints": [{"type": "P", "axis": [0, 0, 1], "actuated": True},
                            {"type": "parallelogram", "axes": [[0, 1, 0], [1, 0, 0]], "link": [0, 0, "-2*l"],
                             "actuated": False, "body": {"mass": 0.2}}], "elastic": ELASTIC, "capsule": 0.02},
    },
}
LEG_KINDS, LEGS = "Leg kinds", ("Legs", None)


def _reference() -> dict[tuple[str, str | None], dict[str, bool]]:
    """Each table of the page's reference by its headings: its fields, each whether it is required (a kind's
    ``bodies.<name>`` rows are the table of its bodies, under "<kind> bodies")."""
    text = schema_docs.PAGE.read_text()
    out: dict[tuple[str, str | None], dict[str, bool]] = {}
    heading = sub = None
    for line in text[text.index(schema_docs.OPENING) : text.index(schema_docs.END)].splitlines():
        if line.startswith("### "):
            heading, sub = line[4:], None
        elif line.startswith("#### "):
            sub = line[5:]
        elif row := re.match(r"\| `([\w.]+)` \| (required|optional) \|", line):
            table, name = ((heading, f"{sub} bodies"), row[1].removeprefix("bodies.")) if "." in row[1] \
                else ((heading, sub), row[1])
            out.setdefault(table, {})[name] = row[2] == "required"
    for table in [t for t in out if t[0] == LEG_KINDS and not t[1].endswith("bodies")]:
        out[table] = {**out[LEGS], **out[table]}
    del out[LEGS]
    return out


def _tables(raw: dict) -> Iterator[tuple[tuple[str, str | None], str, dict]]:
    """Every table of a description: its reference's headings, its field's name and the table."""
    yield ("The description", None), "", raw
    for key, heading in (("parameters", "Parameters"), ("conditions", "Conditions"), ("regions", "Regions")):
        for k, table in enumerate(raw.get(key, [])):
            yield (heading, None), f"{key}[{k}]", table
    if "platform" in raw:
        yield ("Bodies", None), "platform", raw["platform"]
    for name, plate in raw.get("plates", {}).items():
        if isinstance(plate, dict):
            yield ("Plates", None), f"plates.{name}", plate
    legs = raw["legs"]
    for t, leg in enumerate([legs] if isinstance(legs, dict) else legs):
        where = "legs" if isinstance(legs, dict) else f"legs[{t}]"
        yield (LEG_KINDS, f"`{leg['kind']}`"), where, leg
        for end in ("base", "platform"):
            if isinstance(leg[end], dict):
                yield ("Legs", "Attachment patterns"), f"{where}.{end}", leg[end]
        if "bodies" in leg:
            yield (LEG_KINDS, f"`{leg['kind']}` bodies"), f"{where}.bodies", leg["bodies"]
            for name, body in leg["bodies"].items():
                if isinstance(body, dict):
                    yield ("Bodies", None), f"{where}.bodies.{name}", body
        if "elastic" in leg:
            yield ("Elastic elements", None), f"{where}.elastic", leg["elastic"]
            for b, beam in enumerate(leg["elastic"].get("beams", [])):
                yield ("Elastic elements", "Beams"), f"{where}.elastic.beams[{b}]", beam
        for j, joint in enumerate(leg.get("joints", [])):
            yield ("Chain joints", f"`{joint['type']}`"), f"{where}.joints[{j}]", joint
            if "body" in joint:
                yield ("Bodies", None), f"{where}.joints[{j}].body", joint["body"]


def _spots() -> list[tuple[str, tuple[str, str | None], str, int]]:
    """(example, table headings, field of the table, the table's index in the example's walk)."""
    return [(name, headings, where, k) for name, raw in EXAMPLES.items()
            for k, (headings, where, _) in enumerate(_tables(raw))]


def _changed(name: str, k: int, change) -> dict:
    raw = json.loads(json.dumps(EXAMPLES[name]))  # a copy whose bodies are not one another
    change(list(_tables(raw))[k][2])
    return raw


def test_the_reference_of_the_page_is_what_the_tables_of_the_checks_give():
    text = schema_docs.PAGE.read_text()
    assert schema_docs.render(text) == text, "run python -m pkm.schema_docs"
    assert schema_docs.main(["--check"]) == 0
    assert text.count(schema_docs.BEGIN) == 1


def test_every_field_the_reference_lists_is_accepted_in_its_table():
    """The examples, accepted, give every field of every table of the reference and no other."""
    given: dict[tuple[str, str | None], set[str]] = {}
    for raw in EXAMPLES.values():
        describe(raw)
        for headings, _, table in _tables(raw):
            given.setdefault(headings, set()).update(table)
    reference = _reference()
    assert given.keys() == reference.keys()
    for headings, fields in reference.items():
        assert given[headings] == set(fields), headings


@pytest.mark.parametrize(("name", "headings", "where", "k"), _spots())
def test_a_field_the_reference_does_not_list_is_refused_naming_it(name, headings, where, k):
    field = f"{where}.colour" if where else "colour"
    with pytest.raises(DescriptionError, match=re.escape(f"description field {field} violates: a known field of")):
        describe(_changed(name, k, lambda table: table.update(colour="red")))


@pytest.mark.parametrize(("name", "headings", "where", "k"), _spots())
def test_a_field_the_reference_lists_as_required_is_refused_where_missing_naming_it(name, headings, where, k):
    required = [f for f, needed in _reference()[headings].items() if needed]
    assert required or headings[1].endswith(("bodies", "Beams"))
    for field in required:
        missing = f"{where}.{field}" if where else field
        with pytest.raises(DescriptionError, match=re.escape(f"description field {missing} violates")):
            describe(_changed(name, k, lambda table, field=field: table.pop(field)))


def test_an_arms_axis_and_zero_are_unit_and_perpendicular():
    """An R_parallelogram's arm turns from zero towards axis x zero at its length: a longer axis or a zero not
    across it is refused naming the field (it failed at the home pose with a closure residual)."""
    import tomllib

    from pkm.models.described import DESCRIPTIONS

    raw = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    for axis, zero, field, condition in (([0, 2, 0], [1, 0, 0], "axis", "a unit direction"),
                                         ([0, 1, 0], [1, 0.1, 0], "zero", "a unit direction"),
                                         ([0, 1, 0], [0.8, 0.6, 0], "zero", "perpendicular to axis")):
        raw["legs"]["axis"], raw["legs"]["zero"] = axis, zero
        with pytest.raises(DescriptionError, match=rf"legs \(leg 1\)\.{field} violates: {condition}"):
            describe(raw)
    raw["legs"]["axis"], raw["legs"]["zero"] = [0, 1, 0], [1, 0, 0]
    assert describe(raw).data["legs"][0]["axis"] == [0, 1, 0]
