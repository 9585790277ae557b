"""Issue 25's benchmark of the designer's commands (bench/designer.py) as committed: docs/benchmarks.md's section
is the markdown of docs/benchmarks/designer.json, and the run has a card of every mechanism and every example task
file. The benchmark itself is not run here."""

from __future__ import annotations

import json
from pathlib import Path

from helpers import benchmarks_section

import pkm
from bench import designer

ROOT = Path(__file__).resolve().parent.parent
RUN = ROOT / "docs" / "benchmarks" / "designer.json"
HEADING = "## Issue 25: the designer's commands"


def test_docs_section_is_the_markdown_of_the_committed_run():
    report = json.loads(RUN.read_text())
    assert benchmarks_section(HEADING) == designer.markdown(report).strip()


def test_the_run_has_every_mechanism_and_every_task_file():
    report = json.loads(RUN.read_text())
    assert report["command"].startswith("python -m bench.designer")
    assert set(report["cards"]) == set(pkm.mechanisms())
    assert set(report["tasks"]) == {p.name for p in designer.TASKS.glob("*.toml")}
