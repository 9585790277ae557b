"""One definition of an admissible design for atlases and syntheses (issue 23, consistent bests), and a
design gradient that is never silently NaN."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.atlas import compute_atlas


@pytest.fixture(scope="module")
def five_bar():
    return pkm.load("five_bar")


def test_an_atlas_best_is_an_admissible_design_as_the_synthesis_admits_it(five_bar):
    """Over the reachable workspace lambda_e grows as a crank shrinks: the grid's raw best is a crank of
    0.025 L; the checked best meets the space's requirements (every length 0.05 L inside its bounds, the
    MIC radius at least 0.3 L), which the synthesis over the space holds as its constraints."""
    space = five_bar.design_spaces["gao1998"]
    atlas = compute_atlas(five_bar, registry.global_index("lambda_e"), space=space, modes=("out_out",),
                          resolution=21, progress=False)
    raw = atlas.best("out_out")
    assert min(raw.coordinates) < 0.05
    best = atlas.checked["out_out"]
    assert best.found
    c = space.normalised(np.array([best.design[n] for n in ("r1", "r2", "r3")]))
    assert min(c.values()) >= 0.05 - 1e-12
    radius = five_bar.maximum_inscribed_circle(best.design)[1]
    assert radius >= 0.3 - 1e-12
    assert not atlas.admissible[atlas.inside].all()
    assert atlas.admissible.any()
    problem = registry.problem("five_bar.max_gci_miw")
    assert [c.name for c in problem.constraints] == [r.name for r in space.requirements]


def test_lambda_e_has_one_best_over_the_miw_the_grids_and_the_optimisers(five_bar):
    """The atlas over the MIW in Lara-Molina's space admits what the synthesis admits: its best grid node
    is below the synthesis's verified optimum and within a grid step of it; the result names its region
    and mode."""
    space = five_bar.design_spaces["lara_molina2016"]
    atlas = compute_atlas(five_bar, registry.global_index("lambda_e"), space=space, region="miw",
                          modes=("out_out",), resolution=41, progress=False)
    result = pkm.synthesize(registry.problem("five_bar.max_lambda_e_miw"), progress=False)
    best = atlas.checked["out_out"]
    assert best.found
    assert best.value <= result.verified_objective + 1e-9
    assert best.value >= 0.9 * result.verified_objective
    assert result.mode == "out_out"
    assert result.regions == {"lambda_e": "miw"}
    assert result.to_dict()["regions"] == {"lambda_e": "miw"}


def test_a_gradient_where_the_miws_placement_switches_says_why_it_is_nan(five_bar):
    """At r2 = r1 + r3 the MIC switches between eqs. 11 and 12: the index jumps on one side and its slope
    grows without bound on the other. The gradient is NaN with a note that says so; beside it, finite
    and without a note."""
    design = {**five_bar.design(), "r1": 1.0, "r2": 1.8, "r3": 0.8}
    value, gradient = five_bar.global_index("gci", design, region="miw", gradient=True, resolution=8)
    assert math.isfinite(value)
    assert math.isnan(gradient["r2"])
    assert "no one-sided derivative in r1, r2, r3" in value.note
    value, gradient = five_bar.global_index("gci", {**design, "r2": 1.7}, region="miw", gradient=True,
                                            resolution=8)
    assert np.isfinite(list(gradient.values())).all()
    assert value.note == ""
