"""A designer's synthesis from data (pkm.synthesis.designer): a task placed in SI over any mechanism, the
variables, objective and constraints from Python or a TOML file (`pkm design`), solved and at least as good
as its baseline on the same model; bad problems name the field (exit 2, one line)."""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import pkm
from pkm.cli import main
from pkm.synthesis.designer import ProblemError, design_problem, read_problem

TASK = """
mechanism = "delta"
name = "my_delta_cell"
task = {shape = "cylinder", centre = [0.0, 0.0, -0.55], size = [0.12, 0.04], axis = "z"}
variables = {L_a = [0.2, 0.45], L_b = [0.5, 0.9]}
fixed = {R = 0.18}
objective = "gci"
constraints = [{index = "workspace_margin_min", lower = 0.0}]
mode = "elbow_out"
baseline = {kind = "grid", size = 9}
resolution = 6
"""


@pytest.fixture(scope="module")
def designed(tmp_path_factory):
    """The task file TASK, what ``pkm design --json`` printed for it and the folder its --out wrote: one
    synthesis that both tests below read (``pkm design`` is read_problem, then pkm.synthesize)."""
    folder = tmp_path_factory.mktemp("designed")
    path = folder / "task.toml"
    path.write_text(TASK)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(["design", str(path), "--json", "--starts", "2", "--out", str(folder / "out")]) == 0
    return path, json.loads(printed.getvalue()), folder / "out"


def test_a_task_placed_in_si_gives_a_synthesis_at_least_as_good_as_its_grid(designed):
    path, result, _ = designed
    problem = read_problem(path)
    assert problem.variable_names == ("L_a", "L_b")
    assert problem.design([0.3, 0.6])[problem.mechanism.parameter_names().index("R")] == 0.18
    assert result["optimum"]["feasible"]
    grid = result["baselines"]["grid"]["best"]
    assert result["verified_objective"] >= grid["verified_objective"] - 1e-9
    assert math.isfinite(result["verified_objective"])


def test_pkm_design_reports_the_optimum_as_json(designed):
    _, data, out = designed
    assert data["problem"] == "my_delta_cell"
    assert json.loads((out / "my_delta_cell.json").read_text()) == data


@pytest.mark.parametrize(("change", "field"), [
    ('task = {shape = "hexagon", centre = [0.0, 0.0, -0.5], size = [0.1]}', "task.shape"),
    ('task = {shape = "disc", centre = [0.0, -0.5], size = [0.1]}', "task.shape"),
    ('task = {shape = "box", centre = [0.0], size = [0.1, 0.1, 0.1]}', "task.centre"),
    ('task = {shape = "box", centre = [0.0, 0.0, -0.5], size = [0.1, -0.1, 0.1]}', "task.size"),
    ("variables = {L_a = [0.4, 0.2]}", "variables.L_a"),
    ('objective = "speed"', "objective"),
    ('colour = "red"', "colour"),
])
def test_a_bad_problem_file_names_its_field(tmp_path, capsys, change, field):
    key = change.split(" = ")[0]
    text = "\n".join(line for line in TASK.splitlines() if not line.startswith(f"{key} ="))
    path = tmp_path / "task.toml"
    path.write_text(f"{text}\n{change}\n")
    with pytest.raises(ProblemError, match=f"problem field {field} violates"):
        read_problem(path)
    assert main(["design", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"problem field {field} violates" in err
    assert len(err.strip().splitlines()) == 1


def test_a_monte_carlo_baseline_draws_the_same_designs_each_time():
    problem = design_problem("delta", task="task", variables={"L_a": (0.2, 0.4)}, baseline=("monte_carlo", 50))
    (baseline,) = problem.baselines
    first, again = baseline.points(50), baseline.points(50)
    assert first.shape == (50, 1)
    assert (first == again).all()
    assert ((first >= 0.2) & (first <= 0.4)).all()


def test_a_weighted_objective_a_singularity_margin_and_a_frame_size_hold_at_the_optimum():
    """Maximise GCI + 0.5 x dynamic dexterity over the Delta's task with 1/kappa_f >= 0.5 everywhere on it
    and the frame R + L_a at most 0.55 m: the verified optimum holds every constraint and beats its grid."""
    problem = pkm.design_problem("delta", task="task", variables={"L_a": (0.2, 0.45), "L_b": (0.5, 0.9)},
                                 objective={"gci": 1.0, "dynamic_dexterity": 0.5},
                                 constraints=[("workspace_margin_min", 0.0, math.inf),
                                              ("inverse_condition_f_min", 0.5, math.inf),
                                              ("R + L_a", 0.0, 0.55)],
                                 baseline=("grid", 7), resolution=6)
    result = pkm.synthesize(problem, progress=False, starts=2)
    assert result.optimum.feasible
    assert result.optimum.variables["L_a"] <= 0.55 - 0.2 + 1e-7
    m = problem.mechanism
    design = m.design(result.optimum.design)
    nodes, _ = m.region("task").quadrature(m.functions, design.vector(), 12)
    assert m.local_index("inverse_condition_f", nodes, design).min() >= 0.5 - 1e-6
    assert result.verified_objective >= result.baselines["grid"].best.verified_objective - 1e-9


def test_a_constraint_on_an_unknown_name_or_expression_names_its_field():
    with pytest.raises(ProblemError, match=r"problem field constraints\[0\] violates"):
        pkm.design_problem("delta", task="task", variables={"L_a": (0.2, 0.4)}, constraints=[("speed_min", 0, 1)])
    with pytest.raises(ProblemError, match=r"problem field constraints\[0\] violates: arithmetic"):
        pkm.design_problem("delta", task="task", variables={"L_a": (0.2, 0.4)}, constraints=[("R + Q", 0, 1)])


TASKS = Path(__file__).resolve().parent.parent / "docs" / "tasks"
EXAMPLES = TASKS.parent.parent / "examples"


def test_every_mechanism_has_an_example_task_file():
    """Every registered mechanism has one; a task of a machine described in examples/ is one more."""
    named = {read_problem(p).mechanism.name for p in TASKS.glob("*.toml")}
    assert set(pkm.mechanisms()) <= named
    assert named - set(pkm.mechanisms()) <= {p.stem for p in EXAMPLES.glob("*.toml")}


def _at_least_as_good_as_its_baseline(result) -> None:
    assert result.optimum.feasible
    assert math.isfinite(result.verified_objective)
    (baseline,) = result.baselines.values()
    sign = 1.0 if result.sense == "max" else -1.0
    assert sign * (result.verified_objective - baseline.best.verified_objective) >= -1e-9


# wu2008.toml's synthesis is the one below, which checks its baseline too
@pytest.mark.parametrize("path", [p for p in sorted(TASKS.glob("*.toml")) if p.stem != "wu2008"], ids=lambda p: p.stem)
def test_an_example_task_file_gives_a_verified_optimum_at_least_as_good_as_its_baseline(path):
    _at_least_as_good_as_its_baseline(pkm.synthesize(read_problem(path), progress=False, starts=1))


def test_wu2008s_synthesis_restated_as_a_task_file_reaches_the_registered_problems_optimum():
    """docs/tasks/wu2008.toml states slider_gantry.min_kappa_d_task with derived parameters (the strokes,
    the angle margins and the links' inertias follow l and d1) and expressions as constraints: its verified
    optimum is the registered problem's brute-force optimum (docs/benchmarks/brute_force.json) to 1e-6, and at
    least as good as its baseline, as every example task file's."""
    reference = json.loads((TASKS.parent / "benchmarks" / "brute_force.json").read_text())["problems"][
        "slider_gantry.min_kappa_d_task"]
    result = pkm.synthesize(read_problem(TASKS / "wu2008.toml"), progress=False)
    _at_least_as_good_as_its_baseline(result)
    assert abs(result.verified_objective - reference["objective"]) <= 1e-6 * abs(reference["objective"])
    for name, value in reference["variables"].items():
        assert abs(result.variables[name] - value) <= 1e-4


def test_a_parameter_that_follows_another_follows_it_in_a_tasks_design():
    """The five-bar's link masses default to 0.821 kg/m times their lengths: a task over r1 and r2 gives each
    design the masses of its own lengths, as the design given by name does (show, explore, the export), where
    it kept the masses of the default lengths (m1 = 0.9852 kg for r1 = 1 m)."""
    problem = read_problem(TASKS / "five_bar.toml")
    mech = problem.mechanism
    got = dict(zip(mech.parameter_names(), np.ravel(problem.design([1.0, 0.9])), strict=True))
    assert got == pytest.approx(dict(mech.design({"r1": 1.0, "r2": 0.9, "r3": 0.8})), rel=1e-15)
    assert got["m1"] == pytest.approx(0.821)
    assert got["m2"] == pytest.approx(0.821 * 0.9)


@pytest.mark.parametrize("name", pkm.mechanisms())
def test_every_design_space_completes_its_points_as_a_design_given_by_name(name):
    """A design space's points and the designs given by name take one function for the parameters left out:
    a parameter that follows another (``default_from``) follows the point's value of it."""
    mech = pkm.load(name)
    followers = [p for p in mech.parameters if p.default_from is not None]
    for space in mech.design_spaces.values():
        c = np.asarray(space.from_design(mech.design().vector())[0]) * 0.97
        vector = np.ravel(space.designs(mech.parameters, c, check=False))
        values = dict(zip(mech.parameter_names(), vector, strict=True))
        given = {n: values[n] for n in space.parameters} | dict(space.base)
        want = mech.design(given, partial=True)
        for p in followers:
            assert values[p.name] == pytest.approx(want[p.name], rel=1e-15), (space.name, p.name)


def test_the_result_lists_every_constraint_with_its_value_slack_activity_and_multiplier(tmp_path, capsys):
    """The text, the JSON and --out's record list each constraint at the optimum: its value, bounds, slack,
    whether active and IPOPT's multiplier; a bound the optimum sits on is active with a multiplier, a
    constraint with room is inactive with a multiplier of nothing."""
    task = tmp_path / "task.toml"
    task.write_text((TASKS / "five_bar.toml").read_text().replace(
        'constraints = [{index = "inverse_condition_f_min", lower = 0.05}]',
        'constraints = [{index = "inverse_condition_f_min", lower = 0.05}, {expression = "r1", lower = 1.05}]'))
    assert main(["design", str(task), "--starts", "1", "--resolution", "4", "--out", str(tmp_path / "out")]) == 0
    text = capsys.readouterr().out
    saved = json.loads((tmp_path / "out" / "five_bar.my_disc.json").read_text())
    margin, length, default = saved["constraints"]
    assert default["name"] == "singularity_margin_min over task >= 0.01 (the default margin)"
    assert default["value"] > 0.01
    assert saved["optimum"]["constraints"] == saved["constraints"]
    assert length["lower"] == 1.05
    assert length["value"] == pytest.approx(1.05, abs=1e-7)
    assert length["slack"] == pytest.approx(length["value"] - 1.05, abs=1e-15)
    assert length["active"]
    assert abs(length["multiplier"]) > 1e-3
    assert margin["value"] > 0.1
    assert margin["slack"] == pytest.approx(margin["value"] - 0.05)
    assert not margin["active"]
    assert abs(margin["multiplier"]) < 1e-6
    assert f"constraint {length['name']}: value 1.05 (1.05 <= value), slack" in text
    assert "active, multiplier" in text
    assert "inactive, multiplier" in text


@pytest.mark.parametrize(("change", "said"), [
    ('lower = 0.05}', "lower = 0.99}"),
    ("centre = [0.0, 1.4]", "centre = [0.0, 9.0]"),
], ids=["a margin no design meets", "a task no design reaches"])
def test_an_infeasible_task_names_its_constraint_and_exits_3(tmp_path, capsys, change, said):
    """A constraint no design can meet is named with its best attainable value and the design that attains it
    (where IPOPT said Invalid_Number_Detected and "did not converge from any of 4 starts"); a task out of every
    design's reach names the quantity undefined everywhere (where it said "undefined at all 81 screening
    points"); both exit with status 3, and the API raises InfeasibleError."""
    from pkm.synthesis import InfeasibleError

    task = tmp_path / "task.toml"
    task.write_text((TASKS / "five_bar.toml").read_text().replace(change, said))
    assert main(["design", str(task), "--starts", "2", "--resolution", "4"]) == 3
    (line,) = capsys.readouterr().err.splitlines()
    assert line.startswith("pkm: infeasible: no design of five_bar.my_disc meets its constraints")
    if "0.99" in said:
        assert re.search(r"inverse_condition_f_min over task <= inf cannot be met: at best 0\.3\d+ against the bound "
                         r"0\.99, at r1 = [0-9.]+, r2 = [0-9.]+", line)
    else:
        assert "inverse_condition_f_min over task <= inf is undefined at every design tried (out of reach)" in line
    with pytest.raises(InfeasibleError, match="meets its constraints"):
        pkm.synthesize(read_problem(task), progress=False, starts=1, resolution=4)


def test_the_designers_page_states_when_a_constraint_is_active():
    from pkm.synthesis.model import ACTIVE

    text = " ".join((TASKS.parent / "designer.md").read_text().split())
    assert f"within its margin plus {ACTIVE:g} of its bound" in text
