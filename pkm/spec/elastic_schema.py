"""A leg's elastic elements checked and normalised (the ``elastic`` table of a leg, docs/stiffness.md): its
material, section, drive, passive joints, bearings and tilts, and per beam its material and section."""

from __future__ import annotations

import reprlib
from collections.abc import Mapping
from typing import Any

from pkm import expressions
from pkm.spec.checks import check_fields, expression, fail, trees
from pkm.spec.vocabulary import (
    BEAM_FIELDS,
    ELASTIC_FIELDS,
    MATERIALS,
    SECTIONS,
    beams,
    is_free,
    kind_of,
    passive_angles,
)


def elastic(raw: Any, where: str, names: set[str], leg: Mapping[str, Any]) -> dict[str, Any]:
    """A leg's elastic elements: its material ({E, G, density} trees), section ({shape, its dimensions}), drive
    stiffness (or None: rigid) and per beam its material and section, each the leg's where not given."""
    if not isinstance(raw, Mapping):
        raise fail(where, "a table {material, section, drive, passive, bearings, tilts, beams}")
    check_fields(raw, ELASTIC_FIELDS, where, "a leg's elastic elements")
    spatial = len(leg["joints"][0]["link"]) == 3
    material = _material(raw["material"], f"{where}.material", names)
    section = _section(raw["section"], f"{where}.section", names, spatial=spatial)
    given = raw.get("beams", [])
    count = len(beams(leg))
    if not isinstance(given, list) or len(given) > count:
        raise fail(f"{where}.beams", f"a list of at most {count} tables {{material, section}}, one per beam of the "
                                      "leg in order")
    per_beam = []
    for b in range(count):
        table = given[b] if b < len(given) else {}
        field = f"{where}.beams[{b}]"
        if not isinstance(table, Mapping):
            raise fail(field, "a table {material, section}")
        check_fields(table, BEAM_FIELDS, field, "a beam")
        per_beam.append({"material": _material(table["material"], f"{field}.material", names)
                         if "material" in table else material,
                         "section": _section(table["section"], f"{field}.section", names, spatial=spatial)
                         if "section" in table else section})
    drive = expression(f"{where}.drive", raw["drive"], names) if "drive" in raw else None
    out = {"beams": per_beam, "drive": drive}
    if "passive" in raw:
        count = len(passive_angles(leg))
        given = raw["passive"]
        if not isinstance(given, list) or len(given) != count:
            raise fail(f"{where}.passive", f"a list of {count} expressions, one per passive joint variable of the "
                                            "leg in order (0 for a free one)")
        out["passive"] = [expression(f"{where}.passive[{j}]", t, names) for j, t in enumerate(given)]
    for name, allowed in (("bearings", True), ("tilts", spatial)):  # tilts in space alone
        if name in raw:
            count, given = kind_of(leg).points, raw[name]
            if not allowed or not isinstance(given, list) or len(given) != count:
                raise fail(f"{where}.{name}", f"{'' if name == 'bearings' else 'in space, '}a list of {count} "
                                               "expressions, one per joint the leg draws from the base, the "
                                               "platform's included")
            out[name] = [expression(f"{where}.{name}[{j}]", t, names) for j, t in enumerate(given)]
    return out


def _material(raw: Any, where: str, names: set[str]) -> dict[str, expressions.Tree]:
    if isinstance(raw, str):
        if raw not in MATERIALS:
            raise fail(where, f"one of {', '.join(MATERIALS)}, or a table {{E, G, density}}; got {reprlib.repr(raw)}")
        return dict(zip(("E", "G", "density"), MATERIALS[raw], strict=True))
    if not isinstance(raw, Mapping) or set(raw) != {"E", "G", "density"}:
        raise fail(where, f"one of {', '.join(MATERIALS)}, or a table {{E, G, density}}")
    return {k: expression(f"{where}.{k}", raw[k], names) for k in ("E", "G", "density")}


def _section(raw: Any, where: str, names: set[str], *, spatial: bool) -> dict[str, Any]:
    if not isinstance(raw, Mapping) or raw.get("shape") not in SECTIONS:
        raise fail(f"{where}.shape", f"one of {', '.join(SECTIONS)}")
    shape = raw["shape"]
    dimensions = SECTIONS[shape]
    if set(raw) != {"shape", *dimensions}:
        raise fail(where, f"a {shape} section's shape and dimensions {', '.join(dimensions)}")
    out = {"shape": shape, **{k: expression(f"{where}.{k}", raw[k], names) for k in dimensions}}
    pair = {"rect_tube": ("b", "h"), "given": ("I_y", "I_z")}.get(shape)
    if spatial and pair and out[pair[0]] != out[pair[1]]:
        raise fail(where, f"in space a section whose bending does not depend on its orientation: {pair[0]} the "
                           f"same as {pair[1]}")
    return out


def check_elastic(elastic: Mapping[str, Any], where: str, value: Any) -> None:
    """Every number of a leg's elastic elements positive at the default design, a tube's wall within its
    section."""
    free = {f"{where}.{name}[{j}]" for name in ("passive", "tilts") for j, t in enumerate(elastic.get(name, []))
            if is_free(t)}
    for field, tree in trees(elastic, where):
        if field not in free and not value(field, tree) > 0:
            raise fail(field, "a positive value at the default design" + (
                ", or 0 (free)" if ".passive[" in field else ", or 0 (rigid)" if ".tilts[" in field else ""))
    for b, beam in enumerate(elastic["beams"]):
        section = beam["section"]
        if "t" in section:
            sides = [value(f"{where}.beams[{b}].section.{k}", section[k]) for k in ("d", "b", "h") if k in section]
            wall = value(f"{where}.beams[{b}].section.t", section["t"])
            if not 2 * wall < min(sides):
                raise fail(f"{where}.beams[{b}].section.t", f"a wall thinner than half the section ({min(sides):g} "
                                                              f"m); got {wall:g} m")
