"""A task of given poses (pkm.regions.Poses) and the constraints a designer states in physical terms: an
actuated joint within its range over the task, a joint's travel, the actuator effort that holds a payload.
Each binds at its limit where it is active, checked against the mechanism's own inverse kinematics and
forward Jacobian at the poses, and the optimum is at least as good as the grid over the same model."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pkm
from pkm.cli import main
from pkm.regions import Poses
from pkm.synthesis.designer import ProblemError, read_problem

PATH = np.array([[x, 1.4] for x in np.linspace(-0.3, 0.3, 7)])
WRENCH = np.array([0.0, -50.0])


@pytest.fixture(scope="module")
def five_bar():
    return pkm.load("five_bar")


def test_an_index_over_given_poses_is_their_mean_and_extreme_with_its_exact_gradient(five_bar):
    poses = Poses("path", "a path", tuple(map(tuple, PATH)))
    local = five_bar.local_index("inverse_condition_f", PATH, mode="out_out")
    value, gradient = five_bar.global_index("gci", region=poses, mode="out_out", gradient=True)
    assert float(value) == pytest.approx(local.mean(), abs=1e-14)
    assert value.points == len(PATH)
    design = dict(five_bar.design())
    h = 1e-6
    for name in ("r1", "r2", "r3"):
        up, down = ({**design, name: design[name] + s * h} for s in (1, -1))
        slope = (five_bar.local_index("inverse_condition_f", PATH, up, mode="out_out").mean()
                 - five_bar.local_index("inverse_condition_f", PATH, down, mode="out_out").mean()) / (2 * h)
        assert gradient[name] == pytest.approx(slope, abs=1e-7)


def _solve(constraint):
    problem = pkm.design_problem(
        "five_bar", task={"poses": PATH.tolist()}, variables={"r1": (1.0, 1.4), "r2": (0.8, 1.2)}, fixed={"r3": 0.8},
        objective="gci", mode="out_out", constraints=[("inverse_condition_f_min", 0.05, math.inf), constraint],
        baseline=("grid", 9), resolution=4)
    result = pkm.synthesize(problem, progress=False, starts=2)
    assert result.optimum.feasible
    assert result.verified_objective >= result.baselines["grid"].best.verified_objective - 1e-9
    return result.design


def test_an_effort_limit_binds_where_the_payloads_torque_reaches_it(five_bar):
    design = _solve(({"effort": WRENCH.tolist()}, -math.inf, 45.0))
    torques = np.einsum("nij,i->nj", five_bar.forward_jacobian(PATH, design, mode="out_out"), WRENCH)
    assert np.abs(torques).max() == pytest.approx(45.0, abs=1e-6)


def test_a_joint_limit_binds_at_its_bound(five_bar):
    design = _solve(({"joint": "theta1"}, -0.5, 1.78))
    joints = five_bar.inverse_kinematics(PATH, design, mode="out_out")
    assert joints[:, 0].max() == pytest.approx(1.78, abs=1e-7)
    assert joints[:, 0].min() >= -0.5


def test_a_joint_travel_limit_binds_at_its_bound(five_bar):
    design = _solve(({"joint_range": "theta2"}, -math.inf, 0.62))
    joints = five_bar.inverse_kinematics(PATH, design, mode="out_out")
    assert np.ptp(joints[:, 1]) == pytest.approx(0.62, abs=1e-7)


TASK = """
mechanism = "five_bar"
name = "five_bar.path"
task = {{file = "path.csv"}}
variables = {{r1 = [1.0, 1.4], r2 = [0.8, 1.2]}}
fixed = {{r3 = 0.8}}
constraints = [{constraints}]
mode = "out_out"
baseline = {{kind = "grid", size = 5}}
resolution = 4
"""


def _file(tmp_path, constraints):
    (tmp_path / "path.csv").write_text("x [m],y [m]\n" + "\n".join(f"{x},{y}" for x, y in PATH))
    path = tmp_path / "task.toml"
    path.write_text(TASK.format(constraints=constraints))
    return path


def test_a_task_file_reads_its_poses_from_a_csv_beside_it_and_states_physical_limits(tmp_path):
    problem = read_problem(_file(tmp_path, '{joint = "theta1", lower = -0.5, upper = 1.9}, {effort = [0.0, -50.0], '
                                           'upper = 60.0}, {joint_range = "theta2", upper = 1}'))
    (region,) = {q.region for q in problem.quantities.values()}
    assert np.array_equal(np.array(region.poses), PATH)
    assert {"theta1_least", "theta1_largest", "theta2_least", "theta2_largest", "effort"} <= set(problem.quantities)
    assert problem.mechanism.index_unit(problem.quantities["effort"].index) == "N m"


@pytest.mark.parametrize(("constraints", "field"), [
    ('{joint = "theta9", upper = 1.0}', r"constraints\[0\].joint"),
    ('{effort = [1.0, 2.0, 3.0], upper = 1.0}', r"constraints\[0\].effort"),
    ('{joint = "theta1", effort = [1.0, 2.0], upper = 1.0}', r"constraints\[0\]"),
])
def test_a_bad_physical_constraint_names_its_field(tmp_path, capsys, constraints, field):
    path = _file(tmp_path, constraints)
    with pytest.raises(ProblemError, match=f"problem field {field} violates"):
        read_problem(path)
    assert main(["design", str(path)]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


@pytest.mark.parametrize(("task", "field"), [
    ({"poses": [[0.0, 1.4], [0.1]]}, "task.poses"),
    ({"poses": []}, "task.poses"),
    ({"file": "missing.csv"}, "task.file"),
    ({"poses": [[0.0, 1.4]], "file": "path.csv"}, "task"),
])
def test_a_bad_list_of_poses_names_its_field(task, field):
    with pytest.raises(ProblemError, match=f"problem field {field} violates"):
        pkm.design_problem("five_bar", task=task, variables={"r1": (1.0, 1.4)})
