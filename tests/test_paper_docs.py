"""The numbers of docs/papers/<key>.md come from the snapshot of a full reproduction
(pkm.reproduce.docs): every marked number equals the snapshot's value at its printed precision, and no
unmarked number remains between the markers."""

from __future__ import annotations

import json

import pytest

from pkm.reproduce import docs

SNAPSHOTS = sorted(docs.DOCS.glob("*.values.json"))
KEYS = [p.name.removesuffix(".values.json") for p in SNAPSHOTS]


def test_the_converted_papers_have_snapshots():
    assert {"gao1998", "lara_molina2016", "nam2006", "wu2008", "zhao2008"} <= set(KEYS)


@pytest.mark.parametrize("key", KEYS)
def test_every_marked_number_equals_the_snapshot(key):
    md_path, snap_path = docs.paths(key)
    markdown = md_path.read_text()
    snap = json.loads(snap_path.read_text())
    assert snap["paper"] == key
    assert docs.marks(markdown), f"{md_path.name} marks no number"
    assert docs.BEGIN in markdown
    assert docs.problems(markdown, snap) == []


@pytest.mark.parametrize(
    ("value", "printed", "expected"),
    [
        (0.41380745, "0.0", "0.4"),
        (0.41380745, "0.4138", "0.4138"),
        (263.91, "264", "264"),
        (3.3418e-9, "1e-16", "3e-9"),
        (1.2246e-16, "1.0e-9", "1.2e-16"),
        (0.0284974, "2.8%", "2.8%"),
        (0.5022958, "7%", "50%"),
        (-0.00012, "0.00", "0.00"),
        (-0.007, "0.000", "-0.007"),
    ],
)
def test_render_keeps_the_printed_precision(value, printed, expected):
    assert docs.render(value, printed) == expected


REPORT = {
    "paper": "example",
    "settings": {"quick": False, "atlas_resolution": 41},
    "claims": [{"id": "mic_1.2_1_0.8", "pkm_value": {"radius": 0.41380745, "argmax": [-0.007, 1.957]}},
               {"id": "ratio", "pkm_value": 263.9}],
    "beyond_paper": {"syntheses": [{"objective": 0.7546282}]},
}


def test_paths_name_a_claim_or_a_report_key_and_list_items_by_number():
    assert docs.resolve(REPORT, "mic_1.2_1_0.8/radius") == 0.41380745
    assert docs.resolve(REPORT, "mic_1.2_1_0.8/argmax/1") == 1.957
    assert docs.resolve(REPORT, "beyond_paper/syntheses/0/objective") == 0.7546282
    assert docs.resolve(REPORT, "settings/atlas_resolution") == 41
    for bad in ("no_such_claim", "mic_1.2_1_0.8/centre", "beyond_paper/syntheses/3/objective"):
        with pytest.raises(KeyError, match=bad.split("/")[0] if bad == "no_such_claim" else "no "):
            docs.resolve(REPORT, bad)
    with pytest.raises(ValueError, match="not a finite number"):
        docs.number(REPORT, "mic_1.2_1_0.8/argmax")


MARKDOWN = f"""# Example

Outside the markers 3.14 may stand unmarked; `r = (1.2, 1.0, 0.8)` is an input.

{docs.BEGIN}
| claim | pkm |
|---|---|
| Fig. 2, eqs. (10)-(12) | radius 0.4000<!--mic_1.2_1_0.8/radius--> on 41<!--settings/atlas_resolution--> nodes |
| ratio | 100<!--ratio-->, objective 0.755<!--beyond_paper/syntheses/0/objective--> |
{docs.END}
"""


def test_rewrite_then_check_round_trips_and_finds_stale_and_unmarked_numbers():
    snap = docs.snapshot(REPORT, MARKDOWN)
    assert set(snap["values"]) == {"mic_1.2_1_0.8/radius", "settings/atlas_resolution", "ratio",
                                   "beyond_paper/syntheses/0/objective"}
    assert len(docs.problems(MARKDOWN, snap)) == 2  # 0.4000 and 100 are stale
    new = docs.rewrite(MARKDOWN, snap["values"])
    assert "radius 0.4138<!--mic_1.2_1_0.8/radius-->" in new
    assert "264<!--ratio-->" in new
    assert docs.problems(new, snap) == []
    stale_copy = new.replace("| ratio |", "| ratio 264 |")
    assert docs.problems(stale_copy, snap) == ["unmarked number '264' between the markers"]
    unused = {**snap, "values": {**snap["values"], "gone": 1.0}}
    assert docs.problems(new, unused) == ["gone: in the snapshot, not marked in the markdown"]
    assert docs.problems(new, {**snap, "settings": {"quick": True}}) == ["the snapshot comes from a quick run"]


def test_update_writes_the_snapshot_and_the_markdown(tmp_path):
    (tmp_path / "example.md").write_text(MARKDOWN)
    changed = docs.update("example", REPORT, tmp_path)
    assert changed == ["mic_1.2_1_0.8/radius", "ratio"]
    snap = json.loads((tmp_path / "example.values.json").read_text())
    assert docs.problems((tmp_path / "example.md").read_text(), snap) == []
    assert docs.main(["example", "--docs", str(tmp_path), "--check"]) == 0
