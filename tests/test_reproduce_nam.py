"""`pkm reproduce nam2006` at low resolution: report files, honest statuses, the synthesis."""

from __future__ import annotations

import pytest
from helpers import check_docs_snapshot_paths, check_figures_readable, reproduce_quick


@pytest.fixture(scope="module")
def nam(tmp_path_factory):
    return reproduce_quick(tmp_path_factory, "nam2006")


def test_nam_report_checks_every_printed_equation_against_the_derivation(nam):
    folder, data = nam
    for fig in data["figures"]:
        assert (folder / fig).stat().st_size > 1000
    status = {c["id"]: c["status"] for c in data["claims"]}
    for derived in ("eq6_corrected", "eq12_derived", "eq13_derived", "eq14_condition", "eq15_condition",
                    "eq20_jacobian", "fk_six_solutions"):
        assert status[derived] == "match", derived
    for printed in ("eq6_as_printed", "eq9_as_printed", "eq11_as_printed", "eq12_as_printed", "eq24_as_printed"):
        assert status[printed] == "differs", printed
    assert status["singularity_free"] == "differs"
    assert status["trend_manipulability"] == "differs"
    assert status["trend_space_utilization"] == "match"
    assert status["workspace_area"] == "not_stated"
    crossover = data["readings"]["space_utilization_crossover_at_l_b_1.2"]
    assert crossover["supported"]
    assert not crossover["literal"]
    scale_free = data["readings"]["space_utilization_scale_free"]
    assert scale_free["supported"]
    assert not scale_free["literal"]
    for c in data["claims"]:
        assert c["pkm_value"] != c["paper_value"] or c["status"] == "match"


def test_nam_synthesis_is_verified_and_at_least_the_grid(nam):
    _, data = nam
    run = data["beyond_paper"]["syntheses"][0]
    assert run["status"] == "Solve_Succeeded"
    assert run["verified_objective"] == pytest.approx(run["objective"], rel=1e-2)
    assert run["objective"] >= run["grid_objective"] - 1e-9


def test_every_path_of_the_docs_snapshot_is_in_a_quick_report(nam):
    check_docs_snapshot_paths("nam2006", nam[1])


def test_every_figure_of_the_quick_report_can_be_read(nam):
    check_figures_readable("nam2006", nam[1])
