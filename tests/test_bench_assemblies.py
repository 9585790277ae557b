"""bench/assemblies.py: its baseline (numpy.roots one pose at a time) agrees with every_assembly at a small size,
and docs/benchmarks.md quotes the committed run's markdown. No timing is asserted."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import pkm
from bench import assemblies
from pkm.models.described import DESCRIPTIONS

ROOT = Path(__file__).resolve().parent.parent


def test_the_baseline_counts_what_every_assembly_counts():
    m = pkm.load(str(DESCRIPTIONS["rrr3"]))
    q = assemblies._joints(m, 300)
    np.testing.assert_array_equal(assemblies._one_at_a_time(m, q), m.every_assembly(q).counts)


def test_docs_quote_the_committed_run():
    report = json.loads((ROOT / "docs" / "benchmarks" / "assemblies.json").read_text())
    assert report["command"] == "python -m bench.assemblies --json docs/benchmarks/assemblies.json"
    assert report["certified_all"] is True
    assert assemblies.markdown(report) in (ROOT / "docs" / "benchmarks.md").read_text()
