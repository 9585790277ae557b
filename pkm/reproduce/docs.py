"""Numbers in docs/papers/<key>.md that come from the paper's reproduction, never typed by hand.

A number in the markdown is marked by an HTML comment right after it naming its place in report.json:
``0.4138<!--mic_1.2_1_0.8/radius-->``. The path's first part is a claim id (the path then goes on
inside the claim's ``pkm_value``) or a key of the report (``beyond_paper/syntheses/0/objective``); list
items are numbered from 0. The printed text sets the precision: ``0.4138`` four decimals, ``3e-9`` an
exponent form with no decimal, ``2.8%`` a percentage with one decimal, ``264`` an integer.

Between ``<!-- numbers from the report -->`` and ``<!-- end of numbers from the report -->`` every
number is marked, sits in a code span (an input such as `r = (1.2, 1.0, 0.8)`) or names an equation,
figure, table, step or section, so that no hand-typed copy can go stale there.

``python -m pkm.reproduce.docs KEY`` runs the full reproduction (or reads ``--report report.json``),
writes docs/papers/KEY.values.json (the value of every marked path and the report's settings) and
rewrites the marked numbers of docs/papers/KEY.md at their printed precision; ``--check`` compares
only. ``tests/test_paper_docs.py`` checks every snapshot against its markdown.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pkm import io

DOCS = Path(__file__).resolve().parents[2] / "docs" / "papers"
BEGIN = "<!-- numbers from the report -->"
END = "<!-- end of numbers from the report -->"
NUMBER = r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?%?"
MARK = re.compile(rf"(?P<number>{NUMBER})<!--(?P<path>[^\s>]+)-->")
CODE = re.compile(r"`[^`]*`")
REFERENCE = re.compile(
    r"\b(?:[Ee]qs?\.|Figs?\.|[Ss]ections?|Tables?|[Ss]teps?|items?)\s*\(?\d+[\w.]*\)?(?:\s*(?:-|,|and)\s*\(?\d+[\w.]*\)?)*"
)
BARE = re.compile(rf"(?<![\w.^]){NUMBER}(?![\w.])")


@dataclass(frozen=True)
class Mark:
    """A marked number: its report path and the text printed in the markdown."""

    path: str
    text: str


def marks(markdown: str) -> list[Mark]:
    """Every marked number of a markdown text, in order."""
    return [Mark(m["path"], m["number"]) for m in MARK.finditer(markdown)]


def resolve(report: dict[str, Any], path: str) -> Any:
    """The value at ``path`` in a report: a claim id (then inside its pkm_value) or a report key first."""
    head, *rest = path.split("/")
    if head in report and head != "claims":
        node = report[head]
    else:
        claims = {c["id"]: c for c in report.get("claims", [])}
        if head not in claims:
            raise KeyError(f"{path}: {head!r} is neither a claim id nor a key of the {report.get('paper')} report")
        node = claims[head]["pkm_value"]
    for part in rest:
        if isinstance(node, list) and part.isdigit() and int(part) < len(node):
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            raise KeyError(f"{path}: no {part!r} in the {report.get('paper')} report")
    return node


def number(report: dict[str, Any], path: str) -> float:
    """The value at ``path`` as a finite number; a KeyError or ValueError names the path otherwise."""
    value = resolve(report, path)
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"{path}: {value!r} is not a finite number")
    return float(value)


def render(value: float, printed: str) -> str:
    """``value`` at the precision of the printed text ``printed``."""
    mantissa = printed.rstrip("%").split("e")[0]
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    if printed.endswith("%"):
        text = f"{100 * value:.{decimals}f}%"
    elif "e" in printed:
        digits, exponent = f"{value:.{decimals}e}".split("e")
        text = f"{digits}e{int(exponent)}"
    else:
        text = f"{value:.{decimals}f}"
    return text[1:] if text.startswith("-") and not re.search(r"[1-9]", text.split("e")[0]) else text


def checked_text(markdown: str) -> str:
    """The parts of the markdown between the markers of numbers from the report."""
    parts = re.findall(re.escape(BEGIN) + r"(.*?)" + re.escape(END), markdown, flags=re.S)
    return "\n".join(parts)


def unmarked(markdown: str) -> list[str]:
    """Numbers in the checked parts that are neither marked, in a code span nor a reference."""
    text = MARK.sub(" ", checked_text(markdown))
    text = REFERENCE.sub(" ", CODE.sub(" ", text))
    return BARE.findall(text)


def snapshot(report: dict[str, Any], markdown: str) -> dict[str, Any]:
    """The values of every marked path of ``markdown`` in ``report``, with the report's settings."""
    values = {mark.path: number(report, mark.path) for mark in marks(markdown)}
    return {"paper": report["paper"], "settings": report.get("settings", {}), "values": dict(sorted(values.items()))}


def rewrite(markdown: str, values: dict[str, float]) -> str:
    """The markdown with every marked number rewritten from ``values`` at its printed precision."""
    return MARK.sub(lambda m: f"{render(values[m['path']], m['number'])}<!--{m['path']}-->", markdown)


def problems(markdown: str, snap: dict[str, Any]) -> list[str]:
    """What disagrees between a markdown and its snapshot: missing or stale numbers, unmarked numbers in
    the checked parts, snapshot values no longer marked, a snapshot of a quick run."""
    out = []
    values = snap["values"]
    found = marks(markdown)
    for mark in found:
        if mark.path not in values:
            out.append(f"{mark.path}: marked in the markdown, not in the snapshot")
        elif render(values[mark.path], mark.text) != mark.text:
            out.append(f"{mark.path}: the markdown prints {mark.text}, the snapshot gives "
                       f"{render(values[mark.path], mark.text)}")
    out += [f"{path}: in the snapshot, not marked in the markdown" for path in values.keys() - {m.path for m in found}]
    out += [f"unmarked number {text!r} between the markers" for text in unmarked(markdown)]
    if snap.get("settings", {}).get("quick"):
        out.append("the snapshot comes from a quick run")
    if BEGIN in markdown and not checked_text(markdown):
        out.append(f"{BEGIN!r} without {END!r}")
    return out


def paths(key: str, docs: Path = DOCS) -> tuple[Path, Path]:
    """The markdown of paper ``key`` and its snapshot."""
    return docs / f"{key}.md", docs / f"{key}.values.json"


def update(key: str, report: dict[str, Any], docs: Path = DOCS) -> list[str]:
    """Write the snapshot of ``report`` and rewrite the marked numbers of the paper's markdown; returns
    the marked paths whose printed text changed."""
    md_path, snap_path = paths(key, docs)
    markdown = md_path.read_text()
    snap = snapshot(report, markdown)
    new = rewrite(markdown, snap["values"])
    changed = [a.path for a, b in zip(marks(markdown), marks(new), strict=True) if a.text != b.text]
    io.write_text(snap_path, io.to_json(snap))
    io.write_text(md_path, new)
    return changed


def _full_report(key: str) -> dict[str, Any]:
    from pkm.reproduce import reproduce

    with tempfile.TemporaryDirectory() as tmp:
        reproduce(key, Path(tmp))
        return json.loads((Path(tmp) / key / "report.json").read_text())


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pkm.reproduce.docs", description=__doc__.split("\n\n")[0])
    parser.add_argument("paper", help="a paper key, e.g. gao1998")
    parser.add_argument("--report", type=Path, help="read this report.json of a full run instead of running it")
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"folder of the papers' markdown (default {DOCS})")
    parser.add_argument("--check", action="store_true", help="compare the markdown with its snapshot, write nothing")
    args = parser.parse_args(argv)
    md_path, snap_path = paths(args.paper, args.docs)
    if args.check:
        found = problems(md_path.read_text(), json.loads(snap_path.read_text()))
        print("\n".join(found) or f"{md_path.name}: every marked number equals {snap_path.name}")
        return 1 if found else 0
    report = json.loads(args.report.read_text()) if args.report else _full_report(args.paper)
    if report.get("settings", {}).get("quick"):
        print(f"{args.report} comes from a quick run; the docs need a full one", file=sys.stderr)
        return 2
    changed = update(args.paper, report, args.docs)
    print(f"{snap_path.name} written; {len(changed)} printed numbers changed" + "".join(f"\n  {p}" for p in changed))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
