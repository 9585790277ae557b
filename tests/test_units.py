"""Units on the command line: lengths and angles given in mm and deg give the SI results, and with units chosen
every number pkm prints or writes (text, JSON with its units named, CSV headers, the card's report and figure
axes) is in them; round trips are exact to round-off, and a length given in mm where metres go is caught with
the unit suggested."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

import pkm
from pkm.cli import main
from pkm.units import Units


def test_mm_and_deg_round_trip():
    units = Units.parse("mm,deg")
    si = np.array([0.05, -0.02, math.pi / 7])
    given = units.from_si(si, ("m", "m", "rad"))
    np.testing.assert_allclose(given, [50.0, -20.0, 180 / 7], rtol=1e-15)
    np.testing.assert_allclose(units.to_si(given, ("m", "m", "rad")), si, rtol=1e-15)
    assert Units.parse("deg").length == "m"
    with pytest.raises(pkm.PkmError, match="--units item 'inch' violates"):
        Units.parse("inch")


def test_eval_in_mm_and_deg_gives_the_si_results(capsys):
    assert main(["eval", "rrr3", "--pose", "50,-20,10", "--units", "mm,deg", "--design", "r_p=400", "--json"]) == 0
    in_mm = json.loads(capsys.readouterr().out)
    assert main(["eval", "rrr3", "--pose", f"0.05,-0.02,{math.radians(10)!r}", "--design", "r_p=0.4", "--json"]) == 0
    in_si = json.loads(capsys.readouterr().out)
    si_joints = np.array(in_si["poses"][0]["q"][:3])
    np.testing.assert_allclose(list(in_mm["poses"][0]["actuators"].values()), np.degrees(si_joints), rtol=1e-13)
    assert in_mm["units"]["actuators"] == {"q1": "deg", "q2": "deg", "q3": "deg"}
    assert in_mm["design"]["r_p"] == pytest.approx(400.0)
    assert in_mm["poses"][0]["velocity_max"] == pytest.approx(in_si["poses"][0]["velocity_max"] * 1000 * math.pi / 180,
                                                              rel=1e-12)
    assert in_mm["units"]["indices"]["velocity_max"] == "mm/deg"
    assert main(["eval", "rrr3", "--pose", "50,-20,10", "--units", "mm,deg"]) == 0
    text = capsys.readouterr().out
    assert "x = 50 mm" in text
    assert "phi = 10 deg" in text
    assert " deg" in text.split(":")[1]


def test_a_length_given_in_mm_is_caught_with_the_unit_suggested(capsys):
    assert main(["index", "rrr3", "gci", "--design", "r_p=400"]) == 2
    err = capsys.readouterr().err
    assert "given in mm? 400 mm = 0.4 m" in err
    assert main(["eval", "five_bar", "--pose", "0,1500"]) == 0
    assert "y = 1500 m: in mm?" in capsys.readouterr().out


def test_the_five_bars_dynamic_defaults_are_a_physical_machine_and_the_papers_values_a_named_space():
    """The defaults: links of an aluminium tube (0.821 kg/m, the mass following the length), a steel shaft of
    G pi d^4 / (32 l) and a rotor of 0.5 m r^2 times the reduction squared; Lara-Molina's non-dimensional
    values (m1 = 1.2, m2 = 0.8, k = 1, j = 0.5 m1) are the base of its named design space."""
    m = pkm.load("five_bar")
    design = m.design({"r1": 0.3, "r2": 0.4, "r3": 0.1})
    assert design["m1"] == pytest.approx(3.04e-4 * 2700 * 0.3, rel=1e-3)
    assert design["m2"] == pytest.approx(3.04e-4 * 2700 * 0.4, rel=1e-3)
    assert design["k1"] == pytest.approx(79.3e9 * math.pi * 0.02**4 / 32 / 0.1, rel=1e-2)
    assert design["j1"] == pytest.approx(0.5 * 7850 * math.pi * 0.03**2 * 0.06 * 0.03**2 * 10**2, rel=1e-2)
    space = m.design_spaces["lara_molina2016"]
    paper = dict(zip(m.parameter_names(), space.designs(m.parameters, [1.0, 1.0, 1.0]), strict=True))
    assert {k: paper[k] for k in ("m1", "m2", "k1", "k2", "j1", "j2")} == {
        "m1": 1.2, "m2": 0.8, "k1": 1.0, "k2": 1.0, "j1": 0.6, "j2": 0.6}
    gao = dict(zip(m.parameter_names(), m.design_spaces["gao1998"].designs(m.parameters, [1.0, 0.5, 1.0]),
                   strict=True))
    assert gao["m1"] == pytest.approx(0.821 * gao["r1"])
    frequency = m.global_index("lambda_e", design, region="miw", mode="out_out", resolution=4)
    assert math.sqrt(design["k1"] / design["j1"]) < float(frequency) < 1e4  # rad/s, above the rotor on its spring


def test_units_name_every_compound_unit():
    units = Units.parse("mm,deg")
    assert units.convert("(m/rad)^2") == (pytest.approx((1e-3 / math.radians(1)) ** 2), "(mm/deg)^2")
    assert units.convert("N m") == (pytest.approx(1e-3), "N mm")
    assert units.convert("rad/s") == (pytest.approx(math.radians(1)), "deg/s")
    assert units.convert("-") == (1.0, "-")
    assert units.convert("m^3") == (pytest.approx(1e-9), "mm^3")


WORDS = re.compile(r"\b(m|rad)\b")  # an SI length or angle left where the user's units were asked for


def test_show_and_index_in_mm_and_deg_give_every_number_in_them(capsys, tmp_path):
    """``show --units mm,deg``: the design, the region, the global indices, report.json, report.md and the
    figures' axes in mm and deg (they were in metres); ``index`` its value, its gradient per mm and its region;
    no unit of the output names metres or radians."""
    m = pkm.load("five_bar")
    assert main(["show", "five_bar", "--units", "mm,deg", "--design", "r1=1100,r2=900", "--mode", "out_out",
                 "--out", str(tmp_path / "card"), "--json"]) == 0
    card = json.loads(capsys.readouterr().out)
    design = {row["name"]: row for row in card["design"]}
    assert design["r1"]["value"] == pytest.approx(1100.0)
    assert design["r1"]["unit"] == "mm"
    placed = m.region_placement("miw", {"r1": 1.1, "r2": 0.9, "r3": 0.8})
    assert card["placement"]["centre"] == pytest.approx([1000 * c for c in placed["centre"]])
    assert card["placement"]["size"] == pytest.approx([1000 * c for c in placed["size"]])
    si = m.global_index("gamma_max", {"r1": 1.1, "r2": 0.9, "r3": 0.8}, region="miw", mode="out_out")
    gamma = next(r for r in card["global_indices"] if r["index"] == "gamma_max")
    assert gamma["unit"] == "mm/deg"
    assert gamma["value"] == pytest.approx(float(si) * 1000 * math.pi / 180, rel=1e-9)
    report = (tmp_path / "card" / "report.json").read_text()
    assert not WORDS.search(" ".join(r["unit"] for r in json.loads(report)["design"]))
    assert "| r1 | 1100 | mm |" in (tmp_path / "card" / "report.md").read_text()
    svg = (tmp_path / "card" / "workspace_out_out.svg").read_text()
    assert "x [mm]" in svg
    assert "x [m]" not in svg
    assert main(["index", "five_bar", "gci", "--region", "miw", "--units", "mm,deg", "--design", "r1=1100,r2=900",
                 "--gradient", "--json"]) == 0
    index = json.loads(capsys.readouterr().out)
    _, gradient = m.global_index("gci", {"r1": 1.1, "r2": 0.9, "r3": 0.8}, region="miw", gradient=True)
    assert index["gradient"]["r1"] == pytest.approx(gradient["r1"] / 1000, rel=1e-9)
    assert index["placement"]["units"] == {"centre": ["mm", "mm"], "size": ["mm"]}
    assert index["design"]["r3"] == pytest.approx(800.0)
