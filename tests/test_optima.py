"""Every registered synthesis reaches the optimum a brute force finds on the same model (issue 23 item 2).

The brute-force optima were computed once without IPOPT (a dense grid over the bounds, then zoomed grids
about the best feasible point, the objective verified with each region extreme refined between the nodes)
and committed with the command that made them: docs/benchmarks/brute_force.json (bench/brute_force.py)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

import pkm
from pkm import registry

BRUTE_FORCE = json.loads((Path(__file__).resolve().parent.parent / "docs" / "benchmarks" / "brute_force.json")
                         .read_text())
AGREEMENT = 1e-5  # relative, above 1


def test_the_brute_force_was_committed_with_its_command():
    assert BRUTE_FORCE["command"].startswith("python -m bench.brute_force")


@pytest.mark.parametrize("name", sorted(registry.problems()))
def test_a_synthesis_reaches_the_brute_force_optimum(name):
    reference = BRUTE_FORCE["problems"][name]
    assert reference["feasible"]
    # without its baselines, which run after the optimum is found and do not change it:
    # tests/test_capabilities.py compares the optima with them
    result = pkm.synthesize(replace(registry.problem(name), baselines=()), progress=False)
    assert result.optimum.feasible
    scale = max(1.0, abs(reference["objective"]))
    assert abs(result.verified_objective - reference["objective"]) <= AGREEMENT * scale, (
        f"{name}: verified {result.verified_objective:.10g}, brute force {reference['objective']:.10g}")
    assert result.accuracy <= AGREEMENT * max(1.0, abs(result.verified_objective))
