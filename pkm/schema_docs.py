"""The reference of docs/mechanisms.md, every field of a description: ``python -m pkm.schema_docs [--check]``
writes the section between its markers from the tables that :func:`pkm.spec.schema.describe` checks descriptions
against (``--check`` compares it with the page instead, as tests/test_description_schema.py does), so that the
page and the checks cannot drift apart."""

from __future__ import annotations

import argparse
import sys
import textwrap
from collections.abc import Sequence
from pathlib import Path

from pkm import expressions
from pkm.indices.local import SINGULAR
from pkm.spec import vocabulary

PAGE = Path(__file__).resolve().parent.parent / "docs" / "mechanisms.md"
OPENING = "<!-- schema: begin"
BEGIN = f"{OPENING} (written by python -m pkm.schema_docs from the tables of pkm.spec: do not edit) -->"
END = "<!-- schema: end -->"
WIDTH = 120  # the page's paragraphs are wrapped at this width, as the rest of it is


def _paragraph(text: str) -> list[str]:
    return [*textwrap.wrap(text, WIDTH, break_long_words=False, break_on_hyphens=False), ""]


def _fields(fields: Sequence[vocabulary.Field], prefix: str = "") -> list[str]:
    return [f"| `{prefix}{f.name}` | {'required' if f.required else 'optional'} | {f.holds} | {f.doc} |"
            for f in fields]


def _table(fields: Sequence[vocabulary.Field]) -> list[str]:
    return ["| field | given | holds | meaning |", "|---|---|---|---|", *_fields(fields), ""]


def _kind(name: str, kind: vocabulary.Kind) -> list[str]:
    branches = (f"its branches `{kind.branches[0]}` (sign +1) and `{kind.branches[1]}` (-1): {kind.meaning}"
                if kind.branched else "one branch")
    fields = {f.name: [f.name] * 3 if f.name in ("axis", "zero") else f.name for f in kind.fields}
    joints = ", ".join(f"{'an actuated' if j.get('actuated') else 'a'} `{j['type']}`" for j in kind.chain(fields))
    return [f"#### `{name}`", "", *_paragraph(f"{kind.space.capitalize()}: {kind.doc}; the actuated joint in "
                                              f"{kind.unit}; {branches}. As a chain (Chain joints): {joints}. Its "
                                              "fields beside every leg's, and in `bodies` its rotor and bodies:"),
            *_table(kind.fields)[:-1], *_fields((vocabulary.ROTOR, *kind.bodies), "bodies."), ""]


def _joint(name: str, joint: vocabulary.JointType) -> list[str]:
    chains = "planar and spatial" if joint.planar else "spatial"
    plural = "" if joint.variables == 1 else "s"
    return [f"#### `{name}`", "", *_paragraph(f"{joint.doc[0].upper()}{joint.doc[1:]}; {joint.variables} joint "
                                              f"variable{plural}; in {chains} chains; the body after it in "
                                              f"{joint.frame}."),
            *_table(joint.fields)]


def _modes() -> list[str]:
    sided = [name for name, kind in vocabulary.KINDS.items() if kind.sided] + [vocabulary.CHAIN]
    single = [name for name, kind in vocabulary.KINDS.items() if not kind.branched]
    left, right = vocabulary.KINDS["RR"].branches
    ranks = ", ".join(f"{frame} {n}" for frame, n in vocabulary.RANKS.items())
    return [*_paragraph(
        "A working mode is a branch of every leg's inverse kinematics. `modes` names some, each a list of one sign "
        "per leg with two branches, in the order of the legs (a table's `count` legs in turn): +1 for the branch its "
        "kind names first, -1 for the second; where no leg has two, one sign and one mode, `single`. Without "
        "`modes` every combination is a mode (the first leg's sign the slowest, +1 before -1), named by its legs' "
        f"words joined by `_` (`{left}_{right}` for two RR legs on +1, -1); those in which the home pose is regular "
        f"at the default design (reached, both singularity margins at least {SINGULAR:g}) come first, so that the "
        "default (the first mode) is not a degenerate one. Named modes keep their order, the first the default."),
        "| kind | +1 | -1 | meaning |",
        "|---|---|---|---|",
        *(f"| `{name}` | `{kind.branches[0]}` | `{kind.branches[1]}` | {kind.meaning} |"
          for name, kind in vocabulary.KINDS.items() if kind.branched),
        f"| `{vocabulary.CHAIN}` | its first seed's name | its second's | {vocabulary.CHAIN_MEANING} (one seed: one "
        "branch) |",
        "",
        *_paragraph(
        f"One branch, no sign: {', '.join(f'`{name}`' for name in single)}. An assembly mode (a branch of the "
        "forward kinematics) is named by the side of each leg whose passive joints have two branches "
        f"({', '.join(f'`{name}`' for name in sided)}: `p` or `n` in the order of the legs), the sign of the "
        "type-II determinant (`positive`, `negative`) and, where a frame has several solutions of one signature "
        f"({ranks}), their rank by the last pose coordinate (`_2` names the second): `pn_negative_2`."),
    ]


def section() -> str:
    """The reference section of docs/mechanisms.md, its markers included."""
    lines = [
        BEGIN,
        "",
        "## 7. Every field of a description",
        "",
        *_paragraph(
        "Every table of a description holds the fields below and no other: a field its table does not list is "
        "refused, naming it, as is a required one that is missing. An expression is a number or a text of the "
        f"parameters' names, numbers, `+`, `-`, `*`, `/`, `**`, `pi` and "
        f"{', '.join(f'`{f}`' for f in expressions.FUNCTIONS)} "
        "(section 1). This section is written from the tables that pkm.spec checks descriptions against "
        "(`python -m pkm.schema_docs`), and a test fails where the two differ."),
        "### The description",
        "",
        *_table(vocabulary.DESCRIPTION_FIELDS),
        "### Frames",
        "",
        "| frame | pose coordinates | the pose |",
        "|---|---|---|",
        *(f"| `{frame}` | {', '.join(f'{n} [{u}]' for n, u in zip(names, units, strict=True))} | "
          f"{vocabulary.FRAME_DOCS[frame]} |" for frame, (names, units) in vocabulary.FRAMES.items()),
        "",
        "### Parameters",
        "",
        *_table(vocabulary.PARAMETER_FIELDS),
        "### Conditions",
        "",
        *_table(vocabulary.CONDITION_FIELDS),
        "### Legs",
        "",
        *_paragraph(f"`legs` is one table or a list of them (`[legs]` or `[[legs]]`), each of `count` legs of one "
                    f"kind. Every leg table, of any kind (`{vocabulary.CHAIN}` too), holds:"),
        *_table(vocabulary.LEG_FIELDS),
        "#### Attachment patterns",
        "",
        *_table(vocabulary.PATTERN_FIELDS),
        "### Leg kinds",
        "",
        *(line for name, kind in vocabulary.KINDS.items() for line in _kind(name, kind)),
        f"#### `{vocabulary.CHAIN}`",
        "",
        *_paragraph(f"Planar or spatial: {vocabulary.CHAIN_DOC}; the actuated joint in rad (an R) or m (a P); its "
                    "branches its seeds in `branches`, the first sign +1, the second -1. Its fields beside every "
                    "leg's (its bodies are on its joints):"),
        *_table(vocabulary.CHAIN_FIELDS),
        "### Chain joints",
        "",
        *(line for name, joint in vocabulary.JOINTS.items() for line in _joint(name, joint)),
        "### Bodies",
        "",
        *_paragraph("A body (the platform's, a leg kind's in `bodies`, a chain joint's `body`); a body without "
                    "extent holds its mass alone:"),
        *_table(vocabulary.BODY_FIELDS),
        "### Elastic elements",
        "",
        *_paragraph("A leg's `elastic` table (every leg's where one leg has it): its links as Euler-Bernoulli beams "
                    "clamped at their joints (the beams: each non-zero link after a "
                    f"{', '.join(vocabulary.BEAM_JOINTS)} joint, a parallelogram's rods two beams side by side), its "
                    "drive as a spring in its actuated joint, its passive joints free; the stiffness they give "
                    "(`m.stiffness`, `m.deflection`) is docs/stiffness.md's. Materials by name (E, G [Pa], density "
                    "[kg/m^3]): " + "; ".join(f"`{k}` ({e:.3g}, {g:.3g}, {rho:g})"
                                              for k, (e, g, rho) in vocabulary.MATERIALS.items()) + "."),
        *_table(vocabulary.ELASTIC_FIELDS),
        "#### Beams",
        "",
        *_paragraph("Each table of `beams`:"),
        *_table(vocabulary.BEAM_FIELDS),
        "### Plates",
        "",
        *_paragraph("A plate of `plates` (the platform's, the base's) is its radius alone, the polygon of the legs' "
                    "attachments to it rounded by that radius, or a table:"),
        *_table(vocabulary.PLATE_FIELDS),
        "### Regions",
        "",
        *_table(vocabulary.REGION_FIELDS),
        "### Working modes",
        "",
        *_modes(),
        END,
    ]
    return "\n".join(lines)


def render(page: str) -> str:
    """``page`` with its reference section (from its opening marker to its end marker) written anew;
    :class:`ValueError` where it lacks the markers."""
    start, end = page.find(OPENING), page.find(END)
    if start < 0 or end < start:
        raise ValueError(f"the page has no section between {BEGIN} and {END}")
    return page[:start] + section() + page[end + len(END):]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pkm.schema_docs", description=__doc__)
    parser.add_argument("--check", action="store_true", help="compare with the committed page, write nothing")
    args = parser.parse_args(argv)
    text = PAGE.read_text()
    if args.check:
        if render(text) != text:
            print("docs/mechanisms.md differs from the tables of pkm.spec: run python -m pkm.schema_docs")
            return 1
        return 0
    PAGE.write_text(render(text))
    return 0


if __name__ == "__main__":
    sys.exit(main())
