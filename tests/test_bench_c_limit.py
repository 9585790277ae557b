"""bench/c_limit.py's hand-written C loop computes pkm's 1/kappa_f of the five-bar: the same values to
1e-12 relative and the same NaN pattern, at sampled reachable poses and at singular and unreachable ones."""

from __future__ import annotations

import numpy as np
import pytest

import pkm
from bench.c_limit import Limit, discrepancy, markdown, special_poses
from bench.throughput import DESIGN, INDEX, MODE, sample_poses
from pkm.compiled.toolchain import find

TOOLCHAIN = find()
pytestmark = pytest.mark.skipif(isinstance(TOOLCHAIN, str), reason=f"no C compiler: {TOOLCHAIN}")


@pytest.fixture(scope="module")
def limit(tmp_path_factory: pytest.TempPathFactory):
    built = Limit(TOOLCHAIN, tmp_path_factory.mktemp("c-limit"))
    yield built
    built.close()


@pytest.fixture(scope="module")
def five_bar() -> pkm.Mechanism:
    return pkm.load("five_bar")


def _arguments(m: pkm.Mechanism) -> tuple[np.ndarray, np.ndarray]:
    return m.design(DESIGN).vector(), np.asarray(m.working_mode(MODE).signs, dtype=float)


@pytest.mark.parametrize("threads", [1, 2])
def test_limit_agrees_with_pkm_at_reachable_poses(limit, five_bar, threads):
    X = sample_poses(five_bar, 10_000, seed=7)
    want = five_bar.local_index(INDEX, X, DESIGN, mode=MODE)
    got = limit(X, *_arguments(five_bar), threads)
    assert np.all(np.isfinite(want))
    assert discrepancy(got, want, "the C limit") <= 1e-12


def test_limit_matches_pkm_at_singular_and_unreachable_poses(limit, five_bar):
    X = special_poses(DESIGN)
    want = five_bar.local_index(INDEX, X, DESIGN, mode=MODE)
    got = limit(X, *_arguments(five_bar))
    assert discrepancy(got, want, "the C limit") <= 1e-12
    assert np.isnan(got[:2]).all(), "out of reach: NaN"
    assert got[5] == 0.0, "on the outer boundary of chain 1 J is not finite: 0"


def test_discrepancy_rejects_another_nan_pattern_and_a_nonzero_where_pkm_has_zero():
    with pytest.raises(AssertionError, match="NaN"):
        discrepancy(np.array([np.nan, 1.0]), np.array([0.5, 1.0]), "x")
    with pytest.raises(AssertionError, match="relative"):
        discrepancy(np.array([1e-17, 1.0]), np.array([0.0, 1.0]), "x")


def test_markdown_renders_one_table():
    rows = [{"name": f"{who}", "threads": t, "seconds": 0.01, "poses_per_s": 1e8}
            for who in ("C limit (hand-written, ctypes)", "pkm local_index") for t in (1, 2)]
    report = {
        "rows": rows, "poses": 10**6, "repeats": 3, "max_relative_discrepancy": 0.0,
        "ratio_pkm_over_limit": {"1": 1.0, "2": 0.9}, "goals": {"1": 0.95, "2": 0.85},
        "overheads": {"call_16_poses_s": 2e-5, "limit_call_16_poses_s": 1e-6, "isfinite_all_s": 1e-3,
                      "isfinite_share_of_pkm_1_thread": 0.1,
                      "speedup_1_to_2_threads": {"pkm": 1.8, "limit": 1.9, "pkm_over_limit": 0.95}},
        "load_average_before": [0.1, 0.1, 0.1], "load_average_after": [0.2, 0.1, 0.1],
        "compiler": "cc", "flags": ["-O3"],
    }
    text = markdown(report)
    assert text.count("| pkm local_index |") == 2
    assert "0.90 (>= 0.85)" in text
