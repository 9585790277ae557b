"""bench/certify.py: docs/benchmarks.md quotes the committed run's markdown, whose cases are the module's. No timing
is asserted."""

from __future__ import annotations

import json
from pathlib import Path

from bench import certify

ROOT = Path(__file__).resolve().parent.parent


def test_docs_quote_the_committed_run():
    report = json.loads((ROOT / "docs" / "benchmarks" / "certify.json").read_text())
    assert report["command"] == "python -m bench.certify --json docs/benchmarks/certify.json"
    assert [row["case"] for row in report["rows"]] == [case[0] for case in certify.CASES]
    assert all(row["serial"]["verdict"] == row.get("pieces", row["serial"])["verdict"] for row in report["rows"])
    assert certify.markdown(report) in (ROOT / "docs" / "benchmarks.md").read_text()
