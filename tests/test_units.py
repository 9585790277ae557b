"""Units on the command line: lengths and angles given in mm and deg give the SI results (JSON stays SI, the
text speaks the user's units), round trips are exact to round-off, and a length given in mm where metres go
is caught with the unit suggested."""

from __future__ import annotations

import json
import math

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
    np.testing.assert_allclose(in_mm["poses"][0]["q"], in_si["poses"][0]["q"], rtol=1e-14)
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
