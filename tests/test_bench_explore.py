"""Issue 26's benchmark of ``pkm explore`` (bench/explore.py) as committed: docs/benchmarks.md's section is the
markdown of docs/benchmarks/explore.json, and the run has every request kind, on the compiled path and the
interpreter, and the clicks in the browser. The benchmark itself is not run here."""

from __future__ import annotations

import json
from pathlib import Path

from helpers import benchmarks_section

from bench import explore

ROOT = Path(__file__).resolve().parent.parent
RUN = ROOT / "docs" / "benchmarks" / "explore.json"
HEADING = "## Issue 26: pkm explore"


def test_docs_section_is_the_markdown_of_the_committed_run():
    report = json.loads(RUN.read_text())
    assert benchmarks_section(HEADING) == explore.markdown(report).strip()


def test_the_run_has_every_request_kind_both_paths_and_the_clicks():
    report = json.loads(RUN.read_text())
    assert report["command"].startswith("python -m bench.explore")
    assert set(report["server"]) == {"atlas", "card", "map_128", "map_256"}
    assert set(report["interpreter"]) == {"map_128", "map_256"}
    assert all(r["requests"] == 100 for r in [*report["server"].values(), *report["interpreter"].values()])
    assert report["browser"]["map_resolution"] == 128
    assert report["browser"]["clicks"] >= 20
