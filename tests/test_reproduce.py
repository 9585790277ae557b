"""`pkm reproduce gao1998` at low resolution: report files, claim schema, honest statuses."""

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
