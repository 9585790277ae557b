"""Issue 27's benchmark of Pareto fronts (bench/pareto.py) as committed: docs/benchmarks.md's section opens with
the markdown of docs/benchmarks/pareto.json, and the run has both fronts with NSGA-II at equal evaluations and at
equal time, every method's hypervolume from one reference point. The benchmark itself is not run here."""

from __future__ import annotations

import json
from pathlib import Path

from bench import pareto

ROOT = Path(__file__).resolve().parent.parent
RUN = ROOT / "docs" / "benchmarks" / "pareto.json"
HEADING = "## Issue 27: verified Pareto fronts"


def test_docs_section_opens_with_the_markdown_of_the_committed_run():
    text = (ROOT / "docs" / "benchmarks.md").read_text()
    start = text.index(HEADING + "\n") + len(HEADING)
    assert text[start:].strip().startswith(pareto.markdown(json.loads(RUN.read_text())).strip())


def test_the_run_has_both_fronts_and_every_baseline():
    report = json.loads(RUN.read_text())
    assert report["command"].startswith("python -m bench.pareto")
    assert set(report["fronts"]) == {f"{name}/{secondary}" for name, secondary in pareto.FRONTS}
    for key, front in report["fronts"].items():
        dense = [f"grid_{n}" for name, n in report["dense"].items() if key.startswith(f"{name}/")]
        assert set(front["baselines"]) == {"grid", "nsga2_equal_evaluations", "nsga2_equal_time", *dense}
        assert front["pkm"]["points"] + front["pkm"]["dominated"] + front["pkm"]["failed"] == len(front["front"])
        assert front["pkm"]["open_hypervolume"] < front["pkm"]["hypervolume"]
        assert len(front["reference"]) == 2
        for grid in dense:  # the front's hypervolume at least the dense grid's, no node beyond its accuracy
            assert front["pkm"]["hypervolume"] >= front["baselines"][grid]["hypervolume"]
            assert front["baselines"][grid]["dominating_beyond_accuracy"] == 0
