"""bench/accuracy.py: its numpy forward kinematics of the linear Delta, written from the three spheres of the rods'
ends, gives pkm's poses and, by central differences, pkm's pose error Jacobian on the printer's twelve errors; and
docs/benchmarks.md quotes the committed run's markdown. No timing is asserted."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import pkm
from bench import accuracy

ROOT = Path(__file__).resolve().parent.parent


def test_the_numpy_finite_differences_give_pkms_pose_error_jacobian():
    m = pkm.load(str(accuracy.MACHINE))
    x = accuracy.sample_poses(300, seed=3)
    design = dict(m.design())
    np.testing.assert_allclose(accuracy.numpy_ik(x, design), m.inverse_kinematics(x), atol=1e-14)
    np.testing.assert_allclose(accuracy.numpy_pose(accuracy.numpy_ik(x, design), design, np.zeros(12)), x, atol=1e-14)
    assert accuracy.check(m.error_model(attachments="polar"), x) <= accuracy.TOL


def test_docs_quote_the_committed_run():
    report = json.loads((ROOT / "docs" / "benchmarks" / "accuracy.json").read_text())
    assert report["command"] == "python -m bench.accuracy --json docs/benchmarks/accuracy.json"
    assert report["poses"] == accuracy.POSES
    assert report["agreement"] <= accuracy.TOL
    assert accuracy.markdown(report) in (ROOT / "docs" / "benchmarks.md").read_text()
