"""`pkm reproduce gao1998`, `lara_molina2016` and `wu2008` at low resolution: report files, claim schema,
honest statuses (zhao2008 and nam2006: tests/test_reproduce_zhao.py and tests/test_reproduce_nam.py)."""

from __future__ import annotations

import pytest
from helpers import check_docs_snapshot_paths, check_figures_readable, reproduce_quick


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    return reproduce_quick(tmp_path_factory, "gao1998")


def test_writes_report_and_figures_and_nothing_half_done(report):
    folder, data = report
    assert (folder / "report.md").read_text().startswith("# Gao")
    for fig in data["figures"]:
        assert (folder / fig).stat().st_size > 1000
    assert not [p for p in folder.parent.iterdir() if p.name.startswith(".")]


def test_claims_follow_the_schema(report):
    _, data = report
    keys = {"id", "description", "paper_value", "pkm_value", "unit", "status", "note"}
    for c in data["claims"]:
        assert set(c) == keys
        assert c["status"] in {"match", "differs", "not_stated"}


def test_checked_equalities_match(report):
    _, data = report
    status = {c["id"]: c["status"] for c in data["claims"]}
    for cid in ("eq11", "eq18_corrected", "symmetry_y_axis", "eq26_gci", "eq27_gci", "eq26_gamma_max",
                "eq27_gamma_min", "distinct_gci"):
        assert status[cid] == "match", cid
    assert status["eq18_as_printed"] == "differs"


def test_synthesis_beyond_the_paper_beats_its_baseline(report):
    _, data = report
    beyond = data["beyond_paper"]
    assert beyond["objective"] >= beyond["baseline_objective"]
    assert beyond["verified_objective"] > 0
    assert beyond["grid_objective"] == beyond["baseline_objective"]
    assert list(beyond["variables"]) == ["u", "v"]
    for key in ("design_normalised", "baseline_design_normalised"):
        r = beyond[key]
        assert list(r) == ["r1", "r2", "base"]  # Gao's full base is never called r3 (pkm's half base)
        assert 2 * r["r1"] + 2 * r["r2"] + r["base"] == pytest.approx(4.0)  # Gao's solution space
    d, r = beyond["design"], beyond["design_normalised"]
    assert d["r3"] / d["r1"] == pytest.approx(r["base"] / 2 / r["r1"])  # r3 stays pkm's half base


@pytest.fixture(scope="module")
def lara(tmp_path_factory):
    return reproduce_quick(tmp_path_factory, "lara_molina2016")


def test_lara_molina_report_has_its_figures_and_schema(lara):
    folder, data = lara
    assert (folder / "report.md").read_text().startswith("# Lara-Molina")
    assert len(data["figures"]) == 4
    for fig in data["figures"]:
        assert (folder / fig).stat().st_size > 1000
    for c in data["claims"]:
        assert c["status"] in {"match", "differs", "not_stated"}


def test_lara_molina_derivation_claims(lara):
    _, data = lara
    claims = {c["id"]: c for c in data["claims"]}
    coriolis = claims["eq29_coriolis"]["pkm_value"]
    assert claims["eq29_coriolis"]["status"] == "differs"
    assert coriolis["skew_residual_pkm"] < 1e-6 < coriolis["skew_residual_paper"]
    frequencies = claims["eq38_rigid_modes"]["pkm_value"]["all"]
    assert frequencies[1] < 1e-6 < frequencies[2]
    assert claims["mic_1.2_1_0.8"]["status"] == "match"
    assert claims["fig6_discontinuity"]["status"] == "match"
    plateau = claims["lambda_e_plateau"]["pkm_value"]
    assert plateau["sqrt_k_over_j"] == pytest.approx((1 / 0.6) ** 0.5)
    assert plateau["touching_within_tolerance"] > 0.9
    unequal = claims["lambda_e_plateau_unequal_ratios"]["pkm_value"]
    low, high = unequal["unequal_ratios_bounds"]
    assert low * 1.01 < unequal["unequal_ratios_min"] < unequal["unequal_ratios_max"] < high


def test_lara_molina_syntheses_beat_their_baselines(lara):
    _, data = lara
    for run in data["beyond_paper"]["syntheses"]:
        assert run["status"] == "Solve_Succeeded"
        assert run["objective"] >= run["baseline_objective"] - 1e-9
        assert run["verified_objective"] == pytest.approx(run["objective"], rel=2e-2)
        assert list(run["variables"]) == ["s", "t"]
        r = run["design_normalised"]
        assert r["r1"] + r["r2"] + r["r3"] == pytest.approx(3.0)  # Lara-Molina's eq. 2
        assert run["variables"]["t"] == pytest.approx(r["r3"])  # eq. 34


@pytest.fixture(scope="module")
def wu(tmp_path_factory):
    return reproduce_quick(tmp_path_factory, "wu2008")


def test_wu_report_has_its_figures_and_table1(wu):
    folder, data = wu
    assert (folder / "report.md").read_text().startswith("# Wu")
    assert len(data["figures"]) == 3
    for fig in data["figures"]:
        assert (folder / fig).stat().st_size > 1000
    claims = {c["id"]: c for c in data["claims"]}
    for angle, values in ((15, {"d1": 433.0, "l": 707.1, "stroke": 900.0}), (10, {"l": 616.4, "d1": 357.0})):
        for key, paper in values.items():
            c = claims[f"table1_theta{angle}_{key}"]
            assert c["status"] == "match"
            assert c["paper_value"] == paper
            assert c["pkm_value"] == pytest.approx(paper, abs=0.5)


def test_wu_claims_are_honest(wu):
    _, data = wu
    claims = {c["id"]: c for c in data["claims"]}
    k_av = claims["table1_k_av"]
    assert k_av["status"] == "differs"
    assert k_av["pkm_value"]["eq7_closed_form"] == pytest.approx(k_av["pkm_value"]["eq7_quadrature"], rel=1e-6)
    assert k_av["pkm_value"]["eq7_closed_form"] != pytest.approx(k_av["paper_value"], abs=0.05)
    assert claims["eq41_virtual_work_vs_lagrange"]["pkm_value"]["max_relative_difference_to_lagrange"] < 1e-10
    assert claims["fig6_asymmetric"]["status"] == claims["fig7_symmetric"]["status"] == "match"
    assert claims["fig6_centre_isotropic"]["status"] == "match"


def test_wu_synthesis_beats_the_papers_design(wu):
    _, data = wu
    run = data["beyond_paper"]["syntheses"][0]
    assert run["status"] == "Solve_Succeeded"
    assert run["sense"] == "min"
    assert run["objective"] <= min(run["grid_objective"], run["two_step_objective"]) + 1e-9
    assert run["objective"] < run["paper_design_objective"] - 0.05
    assert run["verified_objective"] == pytest.approx(run["objective"], rel=1e-3)
    assert list(run["variables"]) == ["l", "d1"]
    paper = run["paper_design_variables"]
    assert (paper["l"], paper["d1"]) == pytest.approx((0.6164, 0.357), abs=1e-4)  # Wu's Table 1
    assert 10 <= run["two_step_theta_1s_deg"] <= 44.9
    assert set(run["baselines"]) == {"grid", "two_step"}


@pytest.mark.parametrize(("key", "fixture"), [("gao1998", "report"), ("lara_molina2016", "lara"), ("wu2008", "wu")])
def test_every_path_of_the_docs_snapshot_is_in_a_quick_report(key, fixture, request):
    check_docs_snapshot_paths(key, request.getfixturevalue(fixture)[1])


@pytest.mark.parametrize(("key", "fixture"), [("gao1998", "report"), ("lara_molina2016", "lara"), ("wu2008", "wu")])
def test_every_figure_of_a_quick_report_can_be_read(key, fixture, request):
    check_figures_readable(key, request.getfixturevalue(fixture)[1])
