"""bench/stiffness.py: its numpy VJM, written from the beams, the drive and the parallelogram's free angles, gives
pkm's K of the elastic Delta, and docs/benchmarks.md quotes the committed run's markdown. No timing is asserted."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import pkm
from bench import stiffness

ROOT = Path(__file__).resolve().parent.parent


def test_the_numpy_vjm_gives_pkms_stiffness_over_the_task():
    m = pkm.load(str(stiffness.MACHINE))
    x = stiffness.sample_poses(500, seed=7)
    errors = stiffness.check(m, x)
    assert errors["pkm_vs_numpy"] <= stiffness.TOL
    assert errors["closed_form_vs_numpy"] <= stiffness.TOL
    assert np.all(np.linalg.eigvalsh(stiffness.numpy_vjm(x, dict(m.design()))) > 0)


def test_docs_quote_the_committed_run():
    report = json.loads((ROOT / "docs" / "benchmarks" / "stiffness.json").read_text())
    assert report["command"] == "python -m bench.stiffness --json docs/benchmarks/stiffness.json"
    assert report["poses"] == stiffness.POSES
    assert report["pkm_vs_numpy"] <= stiffness.TOL
    assert stiffness.markdown(report) in (ROOT / "docs" / "benchmarks.md").read_text()
