"""``pkm reproduce <key>``: each paper's checkable claims, figures and pkm's design beyond it.

A reproduction writes ``<out>/<key>/report.json``, ``report.md`` and figures, staged in a temporary
folder that replaces ``<out>/<key>`` only when everything is written. report.json holds ``claims``:
``{"id", "description", "paper_value", "pkm_value", "unit", "status", "note"}`` with status one of
"match", "differs", "not_stated"; a paper's value is never copied into ``pkm_value``.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any

from pkm import io, registry
from pkm.reproduce.report import write_report


def reproduce(key: str, out: Path, *, quick: bool = False) -> dict[str, Any]:
    """Run one paper's reproduction into ``out/key``; returns a summary."""
    paper = registry.paper(key)
    target = Path(out) / key
    with io.staged_folder(target) as stage:
        report = paper.run(stage, quick=quick)
        write_report(stage, report)
    counts = Counter(c["status"] for c in report["claims"])
    return {"paper": key, "folder": str(target), "counts": dict(sorted(counts.items()))}
