"""`pkm reproduce zhao2008` at low resolution: report files, honest statuses, the synthesis."""

from __future__ import annotations

import pytest
from helpers import check_docs_snapshot_paths, check_figures_readable, reproduce_quick


@pytest.fixture(scope="module")
def zhao(tmp_path_factory):
    return reproduce_quick(tmp_path_factory, "zhao2008")


def test_zhao_report_checks_the_papers_equations_honestly(zhao):
    folder, data = zhao
    for fig in data["figures"]:
        assert (folder / fig).stat().st_size > 1000
    status = {c["id"]: c["status"] for c in data["claims"]}
    assert status["eq6_corrected"] == "match"
    assert status["eq6_as_printed"] == "differs"
    assert status["eq8_physical"] == "match"
    assert status["eq8_as_printed"] == "differs"
    assert status["eq9_sign_at_home"] == "differs"
    assert status["stroke_rule_section_5.3"] == "differs"
    assert status["stroke_rule_table1"] == "match"
    for c in data["claims"]:
        assert c["pkm_value"] != c["paper_value"] or c["status"] == "match"


def test_zhao_reads_gamma_u_as_the_cones_apex_angle_which_reproduces_section_6(zhao):
    """Table 1's leg lengths by step 5, Table 1 inside section 5.3's joint limits and Fig. 9's containment
    hold with a tilt radius of 30 deg and fail with the literal 60 deg."""
    _, data = zhao
    for statement, by in data["readings"].items():
        assert by == {"apex_angle": True, "literal_radius": False}, statement
    status = {c["id"]: c["status"] for c in data["claims"]}
    assert status["table1_leg_lengths"] == status["table1_holds_task"] == status["fig9_contains"] == "match"
    legs = next(c for c in data["claims"] if c["id"] == "table1_leg_lengths")["pkm_value"]
    assert legs["l_min"] == pytest.approx(396, abs=0.5)
    assert legs["l_max"] == pytest.approx(712, abs=1.0)


def test_zhao_synthesis_beats_monte_carlo_and_table1(zhao):
    _, data = zhao
    run = data["beyond_paper"]["syntheses"][0]
    assert run["dense_margin"] >= 0
    assert run["objective"] < run["monte_carlo_objective"]
    assert run["objective"] < run["table1_objective"]


def test_every_path_of_the_docs_snapshot_is_in_a_quick_report(zhao):
    check_docs_snapshot_paths("zhao2008", zhao[1])


def test_every_figure_of_the_quick_report_can_be_read(zhao):
    check_figures_readable("zhao2008", zhao[1])
