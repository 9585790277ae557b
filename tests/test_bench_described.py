"""Issue 24's benchmark of the described machines (bench/described.py) as committed: docs/benchmarks.md's section
is the markdown of docs/benchmarks/described.json, and the run has every described machine and every synthesis
registered for them, and the chain machines of examples/. The benchmark itself is not run here."""

from __future__ import annotations

import json
from pathlib import Path

from helpers import benchmarks_section

from bench import described
from pkm import registry
from pkm.models.described import DESCRIPTIONS

ROOT = Path(__file__).resolve().parent.parent
RUN = ROOT / "docs" / "benchmarks" / "described.json"
HEADING = "## Issue 24: described machines"


def test_docs_section_is_the_markdown_of_the_committed_run():
    report = json.loads(RUN.read_text())
    assert benchmarks_section(HEADING) == described.markdown(report).strip()


def test_the_run_has_every_described_machine_and_its_syntheses():
    report = json.loads(RUN.read_text())
    assert report["command"].startswith("python -m bench.described")
    assert list(report["machines"]) == [*DESCRIPTIONS, *described.CHAINS]
    problems = {name for name in registry.problems() if name.split(".")[0] in DESCRIPTIONS}
    assert set(report["syntheses"]) == problems
    for row in report["machines"].values():
        assert {"empty_cache", "warm_cache"} <= set(row["derivation"])
        assert set(row["local_index"]["threads"]) == {str(k) for k in described.THREADS}
        assert row["local_index"]["poses"] == report["poses"]
