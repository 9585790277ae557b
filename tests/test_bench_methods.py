"""bench/methods.py at a tiny size: every public batch method of every mechanism agrees with its hand-written
numpy baseline, and the markdown table lists every (mechanism, method). No timing is asserted."""

from __future__ import annotations

import numpy as np
import pytest

import pkm
from bench import methods

POSES = 600


@pytest.fixture(scope="module")
def checked() -> tuple[list[methods.Case], list[dict]]:
    cases, _ = methods.build(POSES, lambda _: None)
    return cases, methods.check(cases)


def test_every_mechanism_has_its_kinematic_methods(checked):
    cases, _ = checked
    by_mechanism = {}
    for case in cases:
        by_mechanism.setdefault(case.mechanism, set()).add(case.method)
    assert set(by_mechanism) == set(pkm.mechanisms())
    kinematic = {"inverse_kinematics", "forward_kinematics", "jacobian", 'local_index("inverse_condition_f")'}
    assert all(kinematic <= found for found in by_mechanism.values())
    assert "statics" in by_mechanism["ups_pu"]
    assert {"inverse_dynamics", 'local_index("dynamic_dexterity")'} <= by_mechanism["five_bar"]
    assert 'local_index("kappa_d")' in by_mechanism["slider_gantry_symmetric"]


def test_every_row_agrees_with_numpy(checked):
    cases, rows = checked
    assert len(rows) == len(cases)
    for row in rows:
        assert 0 <= row["max_discrepancy"] <= methods.TOL, row
        assert row["n"] > POSES // 4, row


def test_markdown_lists_every_row(checked):
    _, rows = checked
    lines = methods.markdown({"rows": rows}).splitlines()
    for row in rows:
        assert sum(line.startswith(f"| {row['mechanism']} | {row['method']} |") for line in lines) == 1, row


def test_discrepancy_names_the_method_and_flags_nan():
    reference = np.array([[1.0, 2.0], [np.nan, np.nan]])
    assert methods.discrepancy(reference, reference, "m f") == 0
    with pytest.raises(AssertionError, match="m f: pkm differs"):
        methods.discrepancy(reference + 1e-6, reference, "m f")
    with pytest.raises(AssertionError, match="m f: pkm and numpy have NaN in different places, at 1 poses"):
        methods.discrepancy(np.array([[1.0, 2.0], [0.0, np.nan]]), reference, "m f")
