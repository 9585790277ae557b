"""Singularities are never silent (issue "Trust the answer", item 1): the type I and type II margins, a
description whose home pose is singular warned at load, singular poses marked by ``pkm eval`` and refused as
the export's reference."""

from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from helpers import rpr3_text

import pkm
from pkm.cli import main
from pkm.errors import PkmError, SingularityError, SingularityWarning
from pkm.export import export_urdf
from pkm.indices.local import SINGULAR, SINGULAR_NEAR, hadamard_ratio
from pkm.models.described import DESCRIPTIONS

# a 3-RPR whose platform pattern is in line with the base's: at phi = 0 the three legs' lines meet at the
# centre, a type II singularity over the whole plane phi = 0
RPR3 = rpr3_text("rpr3_in_line", R=1.0, r=0.4, stroke=(0.3, 1.5))


@pytest.fixture(scope="module")
def rpr3_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("rpr3") / "rpr3.toml"
    path.write_text(RPR3)
    return path


def test_the_hadamard_ratio_is_scale_free_one_when_orthogonal_and_zero_when_singular():
    A = ca.SX.sym("A", 3, 3)
    f = ca.Function("f", [A], [hadamard_ratio(A)])
    rng = np.random.default_rng(3)
    M = rng.normal(size=(3, 3))
    value = float(f(M))
    assert 0 < value < 1
    assert float(f(M @ np.diag([2.0, 1e-4, 7.0]))) == pytest.approx(value, rel=1e-12)  # columns' units
    assert float(f(1e3 * M)) == pytest.approx(value, rel=1e-12)  # the equations' one unit
    Q, _ = np.linalg.qr(M)
    assert float(f(Q @ np.diag([3.0, 0.5, 9.0]))) == pytest.approx(1.0, rel=1e-12)
    singular = M.copy()
    singular[:, 2] = singular[:, 0] - 2 * singular[:, 1]
    assert float(f(singular)) < 1e-14
    assert float(f(np.zeros((3, 3)))) < 1e-14


def test_the_margins_vanish_at_the_five_bars_stretched_leg_and_the_in_line_3rpr(rpr3_file):
    """Type I where a leg of the five-bar is stretched (its tip at r1 + r2 from its base), type II on the
    3-RPR's plane phi = 0; both positive and at most 1 at a regular pose."""
    five_bar = pkm.load("five_bar")
    stretched = np.array([[0.2, math.sqrt(2.2**2 - 1.0)]])
    assert five_bar.local_index("singularity_margin_type1", stretched)[0] < SINGULAR
    assert five_bar.local_index("singularity_margin_type2", stretched)[0] > 0.1
    assert five_bar.singular_types(stretched) == [["type I"]]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)  # said once, at its first load
        rpr3 = pkm.load(str(rpr3_file))
    poses = np.array([[0.0, 0.0, 0.0], [0.05, -0.02, 0.0], [0.0, 0.0, 0.3]])
    margins = rpr3.local_index("singularity_margin_type2", poses)
    assert np.all(margins[:2] < SINGULAR)
    assert 0.01 < margins[2] <= 1
    assert rpr3.singular_types(poses) == [["type II"], ["type II"], []]


def _delta_type1_by_hand(delta, pose, design=None):
    """The product over the Delta's legs of |cos| of the angle between the arm's tangent (its axis across the
    arm) and the rods, from the drawn joints' points: zero where a leg's arm and rods lie in line."""
    axes = [np.array([-math.sin(t), math.cos(t), 0.0]) for t in 2 * math.pi * np.arange(3) / 3]
    product = 1.0
    for (base, tip, end), axis in zip(delta.linkage(pose, design), axes, strict=True):
        arm, rods = tip - base, end - tip
        assert np.linalg.norm(arm) == pytest.approx(0.25, rel=1e-12)
        assert np.linalg.norm(rods) == pytest.approx(0.6, rel=1e-12)
        product *= abs(np.cross(axis, arm) @ rods) / (np.linalg.norm(arm) * np.linalg.norm(rods))
    return product


def test_the_deltas_type1_margin_is_the_angle_of_its_arms_and_rods_and_vanishes_where_a_leg_stretches():
    """The Delta's legs carry their parallelograms' two angles as passive joints, so its type I margin is
    the angle of each arm's tangent to its rods (it was 1 everywhere but exactly at the singularity, when the
    closure eliminated the rods' directions): the same as by hand at random poses, and falling to zero as
    the platform goes down to where every leg stretches (its rods in line with its arm)."""
    delta = pkm.load("delta")
    rng = np.random.default_rng(7)
    poses = np.column_stack([rng.uniform(-0.15, 0.15, (20, 2)), rng.uniform(-0.6, -0.35, 20)])
    margins = delta.local_index("singularity_margin_type1", poses)
    assert np.all((margins > 0.01) & (margins < 1))
    assert margins.std() > 0.01
    for pose, margin in zip(poses, margins, strict=True):
        assert margin == pytest.approx(_delta_type1_by_hand(delta, pose), rel=1e-9)
    # the platform's joints outside the arms': every arm stretches within its range
    wide = delta.design({"R": 0.05, "r": 0.2}, partial=True)
    stretched = math.sqrt((0.25 + 0.6) ** 2 - (0.2 - 0.05) ** 2)  # below the centre, every leg in line
    toward = []
    for short in (1e-1, 1e-2, 1e-4, 1e-8):
        pose = np.array([0.0, 0.0, -stretched * (1 - short)])
        toward.append(delta.local_index("singularity_margin_type1", pose, wide))
        assert toward[-1] == pytest.approx(_delta_type1_by_hand(delta, pose, wide), rel=1e-6, abs=1e-12)
    assert toward == sorted(toward, reverse=True)
    assert toward[-1] < SINGULAR
    assert delta.singular_types(pose, wide) == [["type I"]]


def test_a_description_singular_at_home_is_warned_at_load_naming_its_margin(rpr3_file):
    text = RPR3.replace('name = "rpr3_in_line"', 'name = "rpr3_warned"')
    with pytest.warns(SingularityWarning, match=r"description rpr3_warned: its home pose \[0\.0, 0\.0, 0\.0\] is "
                                                r"a type II singularity .*singularity_margin_type2 = [0-9.e-]+ < "
                                                r"1e-06"):
        pkm.load(__import__("tomllib").loads(text))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pkm.load("five_bar")  # a regular home: nothing said


def test_eval_marks_a_singular_pose_in_its_text_and_json(rpr3_file, capsys):
    assert main(["eval", str(rpr3_file), "--pose", "0,0,0"]) == 0
    out = capsys.readouterr().out
    assert "singularity_margin_type2 = " in out
    assert "SINGULAR (type II): the values at a singular pose are its limits, not a machine's" in out
    capsys.readouterr()
    assert main(["eval", "five_bar", "--pose", "0,1.4", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)["poses"]
    assert row["singular"] == []
    assert 0 < row["singularity_margin_type2"] <= 1


def test_the_export_refuses_a_singular_reference_pose(rpr3_file, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)  # said once, at its first load
        rpr3 = pkm.load(str(rpr3_file))
    with pytest.raises(SingularityError, match=r"the export's reference pose \[0\.0, 0\.0, 0\.0\] is a type II "
                                               r"singularity .*: give another pose"):
        export_urdf(rpr3, None, tmp_path / "singular")
    assert not (tmp_path / "singular").exists()
    export_urdf(rpr3, None, tmp_path / "regular", pose=[0.0, 0.0, 0.2])
    assert (tmp_path / "regular" / "robot.urdf").is_file()


def test_the_designers_page_states_the_singular_threshold():
    from pathlib import Path

    text = " ".join((Path(__file__).parent.parent / "docs" / "designer.md").read_text().split())
    assert f"A pose with a margin below {SINGULAR:g} (`pkm.indices.local.SINGULAR`) is singular" in text
    assert f"naming a pose of the region within {SINGULAR_NEAR:g} of a singularity" in text
    from pkm.synthesis.problem import SINGULARITY_MARGIN

    assert f"`singularity_margin_min >= {SINGULARITY_MARGIN:g}` over the task by default" in text


def test_an_index_refined_to_its_cap_short_of_its_accuracy_says_not_converged(monkeypatch, capsys):
    """The five-bar's k_av over its MIW in mode in_out (1/|J_11|, unbounded inside the region) changes by
    more than its value from one resolution to the next up to the refinement's cap: the value says it did not
    converge and the command line prints so (it printed the row as a result, "accuracy 17" beside 26.9)."""
    from pkm.regions import quadrature

    monkeypatch.setattr(quadrature, "ADAPTIVE_LIMIT", 32)  # the cap, low: the same stop, sooner
    five_bar = pkm.load("five_bar")
    value = five_bar.global_index("k_av", region="miw", mode="in_out")
    assert not value.converged
    assert value.note.startswith("not converged: stopped at resolution 32, the largest the refinement takes")
    assert five_bar.global_index("gci", region="miw").converged
    assert main(["index", "five_bar", "k_av", "--region", "miw", "--mode", "in_out"]) == 0
    assert "\nNOT CONVERGED: stopped at resolution 32" in capsys.readouterr().out
    assert main(["index", "five_bar", "k_av", "--region", "miw", "--mode", "in_out", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["converged"] is False
    assert data["note"].startswith("not converged")


def test_the_refinement_stops_at_its_budget_of_points_and_seconds_and_says_so(monkeypatch, rpr3_file):
    """The in-line 3-RPR's velocity ratio over a box across its singular plane phi = 0 does not converge: the
    refinement doubled to resolution 256 (134 M nodes of a 3-D box, a minute); it stops where the next
    resolution would exceed its budget of nodes, or of seconds at the last resolution's pace, and the note says
    which."""
    from pkm.regions import Box, quadrature

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        rpr3 = pkm.load(str(rpr3_file))
    docs = (Path(__file__).resolve().parent.parent / "docs" / "designer.md").read_text()
    assert f"{quadrature.ADAPTIVE_POINTS:,} nodes" in docs
    assert f"beyond {quadrature.ADAPTIVE_SECONDS:g} s" in docs
    across = Box("across", "a box across the singular plane", fixed=((0.0, 0.0, 0.0), (0.05, 0.05, 0.2)))
    monkeypatch.setattr(quadrature, "ADAPTIVE_POINTS", 40_000)
    value = rpr3.global_index("k_av", region=across)
    assert not value.converged
    assert "beyond the budget of 40000" in value.note
    assert value.points <= 40_000
    monkeypatch.setattr(quadrature, "ADAPTIVE_POINTS", 1 << 40)
    monkeypatch.setattr(quadrature, "ADAPTIVE_SECONDS", 1e-9)
    value = rpr3.global_index("k_av", region=across)
    assert not value.converged
    assert "beyond the budget of 1e-09 s" in value.note
    assert value.resolution == quadrature.QUADRATURE_RESOLUTION


def test_a_region_near_a_singularity_is_named_in_the_note():
    """A disc beside the five-bar's stretched left leg holds poses of type I margin below 1e-2: the note of a
    not converged index there names the pose and both margins."""
    five_bar = pkm.load("five_bar")
    region = five_bar.regions["miw"].at((0.2, math.sqrt(2.2**2 - 1.0) - 0.03), (0.05,))
    note = five_bar._singular_in(region, five_bar.design().vector(), "out_out", "mean")
    assert re.search(r"the region holds poses near a singularity, .* the singularity margins are type I "
                     r"[0-9.]+e-0[3-9], type II [0-9.]+e-01", note)
    clear = five_bar.regions["miw"].at((0.0, 1.6), (0.05,))
    assert five_bar._singular_in(clear, five_bar.design().vector(), "out_out", "mean") == ""


RPR3_TURNED = rpr3_text("rpr3_turned", R=1.0, r=0.4, stroke=(0.3, 1.5), alpha=(0.5, -3.2, 3.2))


def test_a_design_over_a_singular_region_is_held_off_it_by_the_default_margin(tmp_path):
    """The 3-RPR with its platform pattern turned by alpha is type II singular over phi = 0 at alpha = 0, where
    its manipulability |det J_f| grows without bound: maximised over a box of poses about phi = 0 it pulls
    alpha to 0. The default singularity margin holds every pose of the task 0.01 from singularity (active at the
    optimum, stated in the report); singularity_margin = 0 leaves it out, and IPOPT runs into the singular
    design."""
    from pkm.synthesis import SynthesisError
    from pkm.synthesis.designer import design_problem

    (tmp_path / "rpr3.toml").write_text(RPR3_TURNED)
    task = {"shape": "box", "centre": [0.0, 0.0, 0.0], "size": [0.04, 0.04, 0.2]}

    def problem(**options):
        return design_problem(str(tmp_path / "rpr3.toml"), task=task, variables={"alpha": [0.0, 1.2]},
                              objective="manipulability", constraints=[], resolution=4, baseline=("grid", 5),
                              **options)

    held = pkm.synthesize(problem(), progress=False, starts=2)
    (default,) = held.optimum.constraints
    assert default.name == "singularity_margin_min over task >= 0.01 (the default margin)"
    assert "singularity margin held at 0.01 over task (the default margin)" in str(held).splitlines()
    assert held.to_dict()["margin"] == "singularity margin held at 0.01 over task (the default margin)"
    assert default.value == pytest.approx(0.01, abs=1e-6)
    assert default.active
    assert held.variables["alpha"] > 0.1
    assert problem(singularity_margin=0).constraints == ()
    assert str(problem(singularity_margin=0).margin) == "singularity margin off over task (as asked)"
    with pytest.raises(SynthesisError) as failed:
        pkm.synthesize(problem(singularity_margin=0), progress=False, starts=2)
    assert failed.value.result.variables["alpha"] < held.variables["alpha"]


def test_an_angle_beyond_a_turn_in_a_description_asks_whether_it_is_in_degrees():
    """The home pose's angle and a revolute actuator's range beyond a turn are refused naming the field and
    asking "in degrees?", as a pose beyond a turn on the command line is."""
    import tomllib

    from pkm.spec.schema import DescriptionError, describe

    raw = tomllib.loads(RPR3.replace("home = [0, 0, 0]", "home = [0, 0, 30]"))
    with pytest.raises(DescriptionError, match=r"home\[2\] violates: an angle in radians within a turn "
                                               r"\(\|phi\| <= 2 pi\); 30 rad is beyond it: in degrees\? "
                                               r"\(30 deg = 0\.523599 rad\)"):
        describe(raw)
    rrr3 = tomllib.loads((Path(pkm.__file__).parent / "models" / "described" / "rrr3.toml").read_text())
    rrr3["legs"]["range"] = [-180, 180]
    with pytest.raises(DescriptionError, match=r"legs \(leg 1\)\.range\[0\] violates: an angle in radians within a "
                                               r"turn .*-180 rad is beyond it: in degrees\?"):
        describe(rrr3)
    rrr3["legs"]["range"] = [-4, 4]
    with pytest.raises(DescriptionError, match=r"legs \(leg 1\)\.range violates: a revolute joint's range of a turn "
                                               r"at most; \[-4, 4\] rad spans 8 rad: in degrees\?"):
        describe(rrr3)


def test_show_and_the_explorer_mark_a_singular_pose(tmp_path, capsys, rpr3_file):
    """The in-line 3-RPR's card is drawn at its region's centre, a type II singularity: pkm show says SINGULAR,
    and so do its report and the explorer's linkage answer for that pose."""
    from pkm.explore import Explorer

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        assert main(["show", str(rpr3_file), "--out", str(tmp_path / "card"), "--region", "reachable",
                     "--plane", "x,y", "--held", "phi=0"]) == 0
        text = capsys.readouterr().out
        rpr3 = pkm.load(str(rpr3_file))
    assert "SINGULAR: the linkage's pose" in text
    assert "type II" in text
    report = json.loads((tmp_path / "card" / "report.json").read_text())
    assert report["singular"] == {"single": ["type II"]}
    assert "SINGULAR" in (tmp_path / "card" / "report.md").read_text()
    explorer = Explorer(rpr3, axes="R=0.8:1.2,r=0.3:0.5", resolution=3, region="reachable")
    answer = explorer.handle("linkage", {"pose": "0,0,0", "plane": "x,y"})
    assert answer["singular"] == ["type II"]
    assert explorer.handle("linkage", {"pose": "0,0,0.3", "plane": "x,y"})["singular"] == []


def test_every_registered_problem_states_its_margin_and_holds_one_when_asked():
    """A paper's problem holds no singularity margin as the paper states it, and says why; a described
    machine's holds the default; every one holds a margin when asked (``configure(singularity_margin=...)``,
    ``pkm synth --set``), which the tasks of its worker processes carry."""
    from pkm import registry
    from pkm.synthesis.driver import _settings
    from pkm.synthesis.problem import MARGIN, SINGULARITY_MARGIN

    for name, problem in registry.problems().items():
        assert problem.margin is not None, name
        paper = name.split(".")[0] not in DESCRIPTIONS
        assert problem.margin.value == (0.0 if paper else SINGULARITY_MARGIN), name
        assert (MARGIN in problem.quantities) == (not paper), name
        assert problem.margin.why.startswith("as " if paper else "the default margin"), name
    asked = registry.problem("ups_pu.min_size_force_task").configure(singularity_margin=0.02, task_tilt=0.4)
    assert asked.values["task_tilt"] == 0.4
    assert asked.quantities[MARGIN].region is asked.quantities["force"].region
    held = [c for c in asked.constraints if c.name.startswith(MARGIN)]
    assert [(c.lower, c.name) for c in held] == [(0.02, "singularity_margin_min over task >= 0.02 (as asked)")]
    assert asked.hessian == "limited-memory"
    rebuilt = registry.problem(asked.name).configure(**json.loads(_settings(asked)))
    assert rebuilt.margin.value == 0.02
    assert rebuilt.values["task_tilt"] == 0.4
    again = asked.configure(task_tilt=0.3)
    assert (again.margin.value, again.values["task_tilt"]) == (0.02, 0.3)
    with pytest.raises(PkmError, match=r"singularity_margin violates: 0 <= singularity_margin < 1"):
        registry.problem("five_bar.max_gci_miw").configure(singularity_margin=1.5)
