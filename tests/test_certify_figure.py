"""A certification's boxes (issue 41, item 7): each box proved or left undecided kept in its reference coordinates,
their undecided volume the certificate's, together covering the region; the same boxes from pieces in parallel as
from one search; drawn over the workspace by `pkm certify --out` (certify.png and .svg), every text readable."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pkm
from pkm import certify_pieces, figures
from pkm.certify import plot_certificate
from pkm.cli import main


@pytest.fixture(scope="module")
def miw():
    m = pkm.load("five_bar")
    return m, m.certify("miw", properties=("singularity", "limits"))


def test_the_boxes_proved_and_undecided_cover_the_region_and_hold_its_undecided_volume(miw):
    """The MIW of the five-bar touches its workspace's rim and its parallel singularity: some boxes are left
    undecided there. Their volume (in the reference square's halves) is the certificate's; random points of the
    unit disc each lie in a box, proved or undecided; no two boxes overlap."""
    _, found = miw
    proved, undecided = (np.asarray(found.cells[s], dtype=float) for s in ("proved", "undecided"))
    assert len(proved) > 100
    assert len(undecided) > 0
    assert np.prod((undecided[:, 1] - undecided[:, 0]) / 2, axis=1).sum() == pytest.approx(found.undecided,
                                                                                            rel=1e-12)
    boxes = np.concatenate([proved, undecided])
    assert np.all(boxes[:, 0] >= -1)
    assert np.all(boxes[:, 1] <= 1)
    rng = np.random.default_rng(9)
    radius, angle = np.sqrt(rng.uniform(size=2000)), rng.uniform(0, 2 * np.pi, 2000)
    points = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    inside = (boxes[None, :, 0] <= points[:, None]) & (points[:, None] <= boxes[None, :, 1])
    assert np.all(np.any(np.all(inside, axis=2), axis=1))
    overlap = np.minimum(boxes[:, None, 1], boxes[None, :, 1]) - np.maximum(boxes[:, None, 0], boxes[None, :, 0])
    overlapping = np.all(overlap > 1e-12, axis=2)
    np.fill_diagonal(overlapping, False)
    assert not overlapping.any()
    assert found.as_dict()["cells"] == {"proved": len(proved), "undecided": len(undecided)}


def test_pieces_in_parallel_give_the_boxes_of_one_search(miw):
    m, found = miw
    pieces = certify_pieces.certify(m, "miw", properties=("singularity", "limits"), executor="serial")
    for state in ("proved", "undecided"):
        assert sorted(map(str, pieces.cells[state])) == sorted(map(str, found.cells[state]))


def test_pkm_certify_out_draws_the_boxes_over_the_workspace(tmp_path, monkeypatch, miw):
    assert main(["certify", "five_bar", "--region", "miw", "--out", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["certify.json", "certify.png", "certify.svg"]
    assert json.loads((tmp_path / "certify.json").read_text())["cells"]["undecided"] > 0
    problems = []
    save = figures.save
    monkeypatch.setattr(figures, "save", lambda fig, path, *, dpi: problems.extend(figures.text_problems(fig))
                        or save(fig, path, dpi=dpi))
    m, found = miw
    assert plot_certificate(m, "miw", found, tmp_path / "again.png") == Path(tmp_path / "again.png")
    assert problems == []


def test_pkm_show_certify_draws_the_boxes_over_each_modes_map(tmp_path, capsys, monkeypatch, miw):
    """The card certifies its region in each mode, as pkm certify does, reports each verdict and draws the boxes
    over the mode's map, every text readable; a sampled region is refused by name."""
    m, found = miw
    problems = []
    save = figures.save
    monkeypatch.setattr(figures, "save", lambda fig, path, *, dpi: problems.extend(figures.text_problems(fig))
                        or save(fig, path, dpi=dpi))
    assert main(["show", "five_bar", "--region", "miw", "--mode", "out_out", "--certify", "--resolution", "41",
                 "--out", str(tmp_path)]) == 0
    assert (f"certified over miw in mode out_out: UNDECIDED ({found.boxes} boxes; {found.undecided:.3g} of the "
            "region's box undecided)") in capsys.readouterr().out
    report = json.loads((tmp_path / "report.json").read_text())["certified"]["out_out"]
    assert (report["verdict"], report["boxes"], report["cells"]) == ("undecided", found.boxes,
                                                                      {s: len(b) for s, b in found.cells.items()})
    assert "## Certified over miw" in (tmp_path / "report.md").read_text()
    assert problems == []
    from pkm.card import design_card

    card = design_card(m, region="miw", modes=["out_out"], resolution=21, certify=True)
    drawn = card.maps["out_out"].certified
    assert {s: len(p) for s, p in drawn.cells.items()} == {s: len(b) for s, b in found.cells.items()}
    with pytest.raises(pkm.errors.PkmError, match="region reachable violates: a parametrised region to certify"):
        design_card(m, region="reachable", modes=["out_out"], resolution=21, certify=True)
