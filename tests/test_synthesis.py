"""IPOPT synthesis: converges, is verified, and is at least as good as the atlas grid on the same model."""

from __future__ import annotations

import numpy as np
import pytest

import pkm
from pkm.errors import PkmError, UnknownNameError
from pkm.synthesis import synthesize


@pytest.fixture(scope="module")
def result():
    return synthesize("five_bar.max_gci_miw", resolution=6, baseline_resolution=41)


def test_optimum_is_at_least_as_good_as_the_atlas_grid(result):
    assert result.status == "Solve_Succeeded"
    assert result.objective >= result.baseline.objective


def test_optimum_is_verified_at_higher_density_and_by_sampling(result):
    assert result.resolutions["verification_points"] == 4 * result.resolutions["quadrature_points"]
    assert result.verified_objective == pytest.approx(result.objective, rel=2e-3)
    assert result.optimum.sampled_objective == pytest.approx(result.objective, rel=5e-3)
    assert result.optimum.sampled_points > 1000


def test_optimum_satisfies_the_problem_constraints(result):
    m = pkm.load("five_bar")
    normalised = np.array(result.optimum.normalised)
    assert 2 * normalised[0] + 2 * normalised[1] + normalised[2] == pytest.approx(4.0)
    assert np.all(normalised >= 0.05 - 1e-6)
    _, radius = m.maximum_inscribed_circle(result.design)
    assert radius >= 0.3 - 1e-6


def test_optimum_is_a_local_maximum_on_the_feasible_set(result):
    """No feasible neighbour in the chart improves the objective as optimised."""
    m = pkm.load("five_bar")
    space = m.design_spaces["gao1998"]
    u, v = result.optimum.chart
    for du, dv in [(1e-3, 0), (-1e-3, 0), (0, 1e-3), (0, -1e-3)]:
        d = space.designs(m.parameters, space.from_chart(u + du, v + dv), check=False)
        if min(d[:3]) < 0.05 or m.maximum_inscribed_circle(d)[1] < 0.3:
            continue
        assert m.global_index("gci", d, region="miw", resolution=6) <= result.objective + 1e-9


def test_reports_costs_of_both_methods(result):
    data = result.to_dict()
    for key in ("optimizer", "baseline"):
        assert data[key]["wall_time_s"] > 0
        assert data[key]["evaluations"] > 0


def test_bad_synthesis_input():
    with pytest.raises(UnknownNameError, match="unknown synthesis problem"):
        synthesize("five_bar.nothing")
    with pytest.raises(PkmError, match="starts = 0"):
        synthesize("five_bar.max_gci_miw", starts=0)


def test_public_entry_point_rejects_unknown_options():
    with pytest.raises(TypeError):
        pkm.synthesize("five_bar.max_gci_miw", bogus=1)
