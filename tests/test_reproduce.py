"""`pkm reproduce gao1998` and `lara_molina2016` at low resolution: report files, claim schema, honest
statuses."""

from __future__ import annotations

import json

import pytest

from pkm.cli import main


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    assert main(["reproduce", "gao1998", "--out", str(out), "--quick"]) == 0
    folder = out / "gao1998"
    return folder, json.loads((folder / "report.json").read_text())


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


@pytest.fixture(scope="module")
def lara(tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    assert main(["reproduce", "lara_molina2016", "--out", str(out), "--quick"]) == 0
    folder = out / "lara_molina2016"
    return folder, json.loads((folder / "report.json").read_text())


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
    plateau = claims["lambda_e_plateau"]["pkm_value"]["plateau_min"]
    assert plateau == pytest.approx((1 / 0.6) ** 0.5, rel=1e-3)


def test_lara_molina_syntheses_beat_their_baselines(lara):
    _, data = lara
    for run in data["beyond_paper"]["syntheses"]:
        assert run["status"] == "Solve_Succeeded"
        assert run["objective"] >= run["baseline_objective"] - 1e-9
        assert run["verified_objective"] == pytest.approx(run["objective"], rel=2e-2)
