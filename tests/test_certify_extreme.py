"""A local index's extreme over a region certified from both sides (pkm.certify_extreme): the value found at a pose
of the region, a bound proved everywhere in it within the gap, both against a dense grid of the same region; the
linearised worst-case pose error (issue 42) certified where the enclosures allow."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import pkm
from pkm import certify_extreme, regions
from pkm.cli import main
from pkm.errors import PkmError

CENTRE = (0.0, 1.6)


def _disc(radius: float) -> regions.Disc:
    return regions.Disc("probe", "a disc above the five-bar's base", fixed=(CENTRE, (radius,)))


def _grid(m: pkm.Mechanism, index, radius: float, n: int = 121) -> np.ndarray:
    """The index at the poses of an n x n grid within the disc."""
    u = np.linspace(-1, 1, n)
    points = np.array([(a, b) for a in u for b in u if a * a + b * b <= 1.0]) * radius + CENTRE
    return np.asarray(m.local_index(index, points), dtype=float)


@pytest.fixture(scope="module")
def five_bar():
    return pkm.load("five_bar")


def test_the_least_conditioning_over_a_disc_is_found_at_a_pose_and_proved_below_every_grid_value(five_bar):
    found = five_bar.certified_extreme("inverse_condition_f", _disc(0.2), sense="min", gap=0.02)
    at = np.array([found.pose[n] for n in five_bar.pose_names])
    assert np.linalg.norm(at - CENTRE) <= 0.2 + 1e-12
    assert five_bar.local_index("inverse_condition_f", at) == pytest.approx(found.found, rel=1e-12)
    assert found.proved == pytest.approx(found.found * (1 - 0.02), rel=1e-12)
    assert found.steps[-1]["verdict"] == "proved"
    assert np.all(_grid(five_bar, "inverse_condition_f", 0.2) >= found.proved)


def test_a_bound_beyond_the_first_sample_is_refuted_and_the_witness_carries_the_search_on(five_bar, monkeypatch):
    """Sampled at the disc's centre alone, the first bound is refuted; the witnesses raise the value found until a
    bound is proved, at least the dense grid's largest value."""
    monkeypatch.setattr(certify_extreme, "SAMPLES", 0)
    found = five_bar.certified_extreme("inverse_condition_f", _disc(0.2), sense="max", gap=0.02)
    verdicts = [s["verdict"] for s in found.steps]
    assert (verdicts[0], verdicts[-1]) == ("refuted", "proved")
    assert found.found > five_bar.local_index("inverse_condition_f", np.array(CENTRE))
    assert _grid(five_bar, "inverse_condition_f", 0.2).max() <= found.proved


def test_the_worst_case_pose_error_is_certified_over_a_small_disc(five_bar):
    """The error model's linearised worst case under 10 um tolerances: found at a pose (the index there), proved
    within 10 % above it, and no grid pose beyond the bound (a disc of 3 cm); over one of 20 cm a budget of 500
    boxes proves none and says so."""
    model = five_bar.error_model()
    found = model.certified_worst_case(_disc(0.03), 10e-6, gap=0.1, depth=24, max_boxes=100_000)
    assert found.steps[-1]["verdict"] == "proved"
    index = model.index(10e-6)
    at = np.array([found.pose[n] for n in five_bar.pose_names])
    assert five_bar.local_index(index, at) == pytest.approx(found.found, rel=1e-12)
    assert found.found <= found.proved <= found.found * 1.1 * (1 + 1e-12)
    assert _grid(five_bar, index, 0.03, 61).max() <= found.proved
    wide = model.certified_worst_case(_disc(0.2), 10e-6, gap=0.1, max_boxes=500)
    assert (wide.proved, wide.steps[-1]["verdict"]) == (None, "undecided")


@pytest.mark.parametrize(("options", "condition"), [
    ({"sense": "mean"}, "sense violates: max or min"),
    ({"gap": 0}, "gap violates: a relative gap in (0, 1)"),
    ({"gap": 1.5}, "gap violates: a relative gap in (0, 1)"),
])
def test_bad_options_are_refused_naming_them(five_bar, options, condition):
    with pytest.raises(PkmError, match=re.escape(condition)):
        five_bar.certified_extreme("inverse_condition_f", _disc(0.1), **options)


def test_pkm_certify_prints_the_extreme_and_writes_it(tmp_path, capsys):
    assert main(["certify", "five_bar", "--region", "miw", "--extreme", "workspace_margin", "--gap", "0.1", "--out",
                 str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert re.search(r"the largest workspace_margin over miw in mode out_out: [\d.]+ \S+ at x = .*; proved <= [\d.]+",
                     out)
    data = json.loads((tmp_path / "certify.json").read_text())
    assert data["proved"] == pytest.approx(data["found"] * 1.1, rel=1e-12)
    assert main(["certify", "five_bar", "--extreme", "pose_error", "--region", "miw"]) == 2
    assert "--tolerances violates" in capsys.readouterr().err
