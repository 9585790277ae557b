"""Descriptions are data (issue 35): their expressions are parsed into pkm's own trees and never evaluated as
Python, their text fields never become code, and every bad input is refused naming its field.

The payloads of the issue run through the real ``pkm`` command in a folder of their own, which must hold no
file afterwards; the other causes are refused in-process by :func:`pkm.schema.describe`."""

from __future__ import annotations

import ast
import copy
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from helpers import EXAMPLES, FIVE_BAR_OF_CHAINS, rrr3_of_chains

from pkm import expressions
from pkm.models.described import DESCRIPTIONS
from pkm.spec import machine, schema, vocabulary
from pkm.spec.schema import DescriptionError
from symbolic import codegen

PKM = Path(sys.executable).with_name("pkm")
RRR3 = DESCRIPTIONS["rrr3"].read_text()
SHELL = "__import__('os').system('id > PWNED') or 0"


def run_in(folder: Path, description: str) -> subprocess.CompletedProcess:
    (folder / "z.toml").write_text(description)
    return subprocess.run([str(PKM), "eval", "z.toml", "--pose=0,0,0"], cwd=folder, capture_output=True, text=True,
                          timeout=120, check=False)


@pytest.mark.parametrize("proximal", [
    f'l1 + 0*cos("{SHELL}")',
    f'l1 + 0*sqrt("{SHELL}")',
    "l1 + 0*9**9**9**9",
    "l1 + 0*10**10**8",
], ids=["cos_of_text", "sqrt_of_text", "tower_of_powers", "huge_power"])
def test_an_expression_that_would_run_code_or_hang_is_refused_cleanly(tmp_path, proximal):
    done = run_in(tmp_path, RRR3.replace('proximal = "l1"', f"proximal = '''{proximal}'''"))
    assert done.returncode == 2, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1
    assert "Traceback" not in done.stderr
    assert "legs.proximal" in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["z.toml"]


def test_a_doc_that_closes_its_docstring_is_text_and_runs_nothing(tmp_path):
    doc = 'x"""; __import__("os").system("id > PWNED"); """ and a lone \\ backslash'
    text = RRR3.replace('name = "rrr3"', 'name = "rrr3_doc"')
    text = text.replace(text.splitlines()[1], f"doc = '''{doc}'''")
    text = text.replace('unit = "m"\ndoc = "length of the distal links"', "unit = '''m\"\"\"\\\\'''\ndoc = \"x\"")
    done = run_in(tmp_path, text)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["z.toml"]
    mech = schema.read(tmp_path / "z.toml")
    module = ast.parse(machine.module_path(mech).read_text())
    assert ast.get_docstring(module, clean=False) == doc


def test_a_derivation_that_meets_an_undefined_value_is_a_description_error():
    raw = tomllib.loads(RRR3)
    raw["name"] = "rrr3_tan"
    raw["legs"]["proximal"] = "l1 + 0*tan(pi/2)"
    with pytest.raises(DescriptionError, match=r"tan\(pi/2\) has no finite value"):
        machine.load(raw)


def changed(path: str, value) -> dict:
    """The 3-RRR description with the field at ``path`` (keys and indices joined by dots) set to ``value``, or
    removed where ``value`` is None."""
    raw = tomllib.loads(RRR3)
    *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
    target = raw
    for key in parents:
        target = target[key]
    if value is None:
        del target[last]
    else:
        target[last] = value
    return raw


@pytest.mark.parametrize(("path", "value", "field"), [
    ("legs.proximal", "0", "proximal"),
    ("legs.proximal", "1/0", "legs.proximal"),
    ("legs.proximal", "1e999", "legs.proximal"),
    ("legs.proximal", 1e999, "legs.proximal"),
    ("legs.proximal", "l1 + sqrt(-1)", "legs.proximal"),
    ("legs.proximal", "~l1", "legs.proximal"),
    ("legs.proximal", "l1.real", "legs.proximal"),
    ("legs.proximal", "open(l1)", "legs.proximal"),
    ("legs.proximal", "+".join(["l1"] * 20000), "legs.proximal"),
    ("legs.proximal", "-" * 5000 + "l1", "legs.proximal"),
    ("legs.proximal", "(" * 300 + "l1" + ")" * 300, "legs.proximal"),
    ("legs.proximal", "l1 + 2**(3**4)", "legs.proximal"),
    ("frame", [], "frame"),
    ("legs.kind", [], "legs.kind"),
    ("legs.kind", {"a": 1}, "legs.kind"),
    ("regions.0.shape", [], "regions[0].shape"),
    ("regions.0.coordinates", [["x"], "y", "phi"], "regions[0].coordinates"),
    ("regions.0.size", [-0.15, "pi/12"], "regions[0].size[0]"),
    ("regions.0.size", [0, "pi/12"], "regions[0].size[0]"),
    ("regions.0.size", ["sqrt(-l1)", "pi/12"], "regions[0].size[0]"),
    ("regions.0.size", ["1e300*1e300 - 1e300*1e300", "pi/12"], "regions[0].size[0]"),
    ("regions.0.shape", "rectangle", "regions[0].axis"),
    ("name", "a" * 5000, "name"),
    ("modes", {"m": [True, 1, 1]}, "modes"),
    ("parameters.2.name", "neg", "parameters[2].name"),
    ("parameters.0.unit", ["m"], "parameters[0].unit"),
    ("home", [0, 0, "1/0"], "home[2]"),
], ids=lambda v: str(v)[:24])
def test_a_bad_field_is_refused_naming_it(path, value, field):
    raw = changed(path, value)
    if path == "regions.0.shape":
        raw["regions"][0]["size"] = [0.1, 0.1] if value == "rectangle" else raw["regions"][0]["size"]
        raw["regions"][0]["coordinates"] = ["x", "y"] if value == "rectangle" else raw["regions"][0]["coordinates"]
        raw["regions"][0]["centre"] = [0, 0] if value == "rectangle" else raw["regions"][0]["centre"]
    with pytest.raises(DescriptionError) as error:
        schema.describe(raw)
    assert field in str(error.value)
    assert len(str(error.value)) < 600


def test_a_condition_undefined_at_the_default_design_is_refused():
    raw = tomllib.loads(RRR3)
    raw["conditions"] = [{"margin": "1/(l1 - 0.6)", "doc": "a margin that divides by zero"}]
    with pytest.raises(DescriptionError, match=r"conditions\[0\]\.margin"):
        schema.describe(raw)


def test_zero_directions_are_refused():
    raw = copy.deepcopy(FIVE_BAR_OF_CHAINS)
    raw["legs"][0]["joints"][0] = {"type": "P", "actuated": True, "axis": [0, 0], "link": ["r1", 0]}
    with pytest.raises(DescriptionError, match=r"legs \(leg 1\)\.joints\[0\]\.axis"):
        schema.describe(raw)


def test_a_text_file_that_is_not_utf8_is_refused(tmp_path):
    path = tmp_path / "latin.toml"
    path.write_bytes(RRR3.replace("symmetric", "sym\xe9tric").encode("latin-1"))
    with pytest.raises(DescriptionError, match="UTF-8"):
        schema.read(path)


def test_a_parameter_named_like_a_pose_coordinate_stays_a_parameter():
    """The Delta of chains with its base radius ``r`` renamed ``x``: the same machine, not one whose arm
    follows the platform's x."""
    text = (EXAMPLES / "delta_chains.toml").read_text()
    original = tomllib.loads(text)
    renamed = tomllib.loads(text.replace('"r"', '"x"').replace("r_", "x_"))
    assert any(p["name"] == "x" for p in renamed["parameters"])
    renamed["name"] = "delta_chains_x"
    first, second = machine.load(original), machine.load(renamed)
    poses = np.array([[0.0, 0.0, -0.9], [0.05, -0.03, -0.85], [-0.08, 0.04, -0.95]])
    np.testing.assert_allclose(second.inverse_kinematics(poses), first.inverse_kinematics(poses), atol=1e-12)


V = {"a": 0.7, "b": 1.3, "c": -0.4, "x": 0.2, "l1": 0.6}
ARITHMETIC = {
    "l1 + 0*cos(x)": V["l1"] + 0 * math.cos(V["x"]), "-a**2": -V["a"] ** 2, "(-a)**2": (-V["a"]) ** 2, "2**-1": 0.5,
    "a - (b - c)": V["a"] - (V["b"] - V["c"]), "a/(b*c)": V["a"] / (V["b"] * V["c"]), "-(-x)": V["x"],
    "sqrt(2)*pi": math.sqrt(2) * math.pi, "1e-3": 1e-3, "3": 3.0, "a**b**c": V["a"] ** V["b"] ** V["c"],
    "atan(a/b) - asin(0.5)": math.atan(V["a"] / V["b"]) - math.asin(0.5), "+a": V["a"],
}


@pytest.mark.parametrize("text", ARITHMETIC)
def test_a_tree_prints_back_to_itself_and_evaluates_as_arithmetic(text):
    tree = expressions.parse(text)
    assert expressions.parse(expressions.text(tree)) == tree
    assert float(expressions.evaluate(tree, V)) == pytest.approx(ARITHMETIC[text], rel=1e-15)


@pytest.mark.parametrize("doc", ['x"""; import os', "a \\ b", 'ends in a quote"', "tab\tand\x00nul", "plain"])
def test_a_docstring_is_always_a_literal_of_its_text(doc):
    literal = codegen.docstring(doc)
    assert ast.literal_eval(literal) == doc
    assert isinstance(ast.parse(literal).body[0], ast.Expr)


def test_the_description_page_states_the_expressions_limits():
    text = " ".join((Path(expressions.__file__).resolve().parent.parent / "docs" / "mechanisms.md").read_text().split())
    limits = expressions.LIMITS
    assert (f"at most {limits['characters']} characters, {limits['nodes']} terms nested at most {limits['depth']} "
            f"deep, a constant exponent of at most {limits['exponent']:g} in magnitude") in text
    assert (f"identifiers of at most {vocabulary.NAME_LENGTH} characters; texts (docs, units) at most "
            f"{vocabulary.TEXT_LENGTH}") in text
    assert ", ".join(f"`{f}`" for f in expressions.FUNCTIONS[:-1]) in text


def test_a_chain_actuated_at_its_last_joint_is_evaluated(tmp_path, capsys):
    """The 3-RRR's legs as chains actuated at the elbow: no leg has a closed-form reach margin or a range, and
    the workspace margin is the chain legs' branch margins (the closure's Jacobian determinant in the leg's
    joints, with its seed's sign; an index of an empty margin vector raised IndexError in pkm eval)."""
    from pkm.cli import main

    raw = rrr3_of_chains()
    raw["name"] = "rrr3_actuated_last"
    raw["legs"]["joints"] = [{"type": "R", "link": ["l1", 0]}, {"type": "R", "actuated": True, "link": ["l2", 0]}]
    mech = machine.load(raw)
    assert mech.functions["inverse_kinematics"].numel_out(1) == 3
    assert "workspace_margin" in mech.local_indices()
    path = tmp_path / "last.toml"
    path.write_text(RRR3.replace('name = "rrr3"', 'name = "rrr3_actuated_last"').replace(
        'kind = "RR"', 'kind = "chain"').replace(
        'proximal = "l1"\ndistal = "l2"',
        'joints = [{type = "R", link = ["l1", 0]}, {type = "R", actuated = true, link = ["l2", 0]}]\n'
        'branches = {left = [-2.1, -2.1], right = [2.1, 2.1]}'))
    assert main(["eval", str(path), "--pose=0.01,0.02,0.05"]) == 0
    assert "inverse_condition_f = 0.24" in capsys.readouterr().out
    assert mech.local_index("workspace_margin", [0.01, 0.02, 0.05]) > 0
