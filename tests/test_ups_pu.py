"""The 2-UPS-PU platform of Zhao, Tang and Zhao 2008: forward kinematics on every assembly, the
paper's closed form at alpha = 90 deg (eq. 6, with its l1 and l2 swapped back), the claim for
alpha = 0, statics by virtual work and by the platform's equilibrium, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import random_design, reachable_poses

import pkm
from pkm.batch import evaluate
from pkm.errors import DesignError, PoseError

DEG = math.pi / 180


@pytest.fixture(scope="module")
def mech():
    return pkm.load("ups_pu")


@pytest.fixture(scope="module", params=[90.0, 30.0, 0.0])
def case(request, mech):
    rng = np.random.default_rng(int(request.param))
    design = random_design(mech, rng, names=("r", "R", "beta"))
    design = mech.design({**design, "alpha": request.param * DEG})
    return design, reachable_poses(mech, design, "legs", rng, count=40)


def test_every_real_root_is_an_assembly_of_the_same_leg_lengths(mech, case):
    design, x = case
    q = mech.inverse_kinematics(x, design)
    found = np.zeros(len(x), dtype=bool)
    for assembly in mech.assemblies:
        pose = mech.forward_kinematics(q, design, assembly=assembly)
        closed = np.all(np.isfinite(pose), axis=1)
        np.testing.assert_allclose(mech.inverse_kinematics(pose[closed], design, limits=False), q[closed], atol=1e-9)
        found |= np.linalg.norm(pose - x, axis=1) < 1e-9
    assert found.all()


def _paper_eq6(l1, l2, l0, r, R, beta, *, as_printed):
    """Zhao eq. 6 for alpha = 90 deg; as printed theta1 reads l2 and a reads l1, swapped back otherwise."""
    first, second = (l2, l1) if as_printed else (l1, l2)
    theta1 = math.asin((first**2 - r**2 - R**2 - l0**2) / (2 * r * math.hypot(l0, R))) + math.atan(R / l0)
    a = (r**2 + R**2 + l0**2 - second**2) / (2 * r)
    b = l0 * math.sin(beta) * math.sin(theta1) - R * math.sin(beta) ** 2 * math.cos(theta1)
    c = l0 * math.cos(beta) * math.cos(theta1) + R * math.cos(beta) * math.sin(beta) * math.sin(theta1)
    d = R * math.cos(beta) ** 2
    theta2 = math.asin((a + b) / math.hypot(c, d)) - math.atan(d / c)
    return theta1, theta2


def test_paper_closed_form_at_alpha_90_holds_with_l1_and_l2_swapped_back(mech):
    design = mech.design()
    d = dict(design)
    rng = np.random.default_rng(6)
    x = np.column_stack([rng.uniform(0.45, 0.65, 20), rng.uniform(-0.5, 0.5, 20), rng.uniform(-0.5, 0.5, 20)])
    q = mech.inverse_kinematics(x, design)
    wrong = 0
    for (l1, l2, l0), pose in zip(q, x, strict=True):
        corrected = _paper_eq6(l1, l2, l0, d["r"], d["R"], d["beta"], as_printed=False)
        np.testing.assert_allclose(corrected, pose[1:], atol=1e-9)
        try:
            printed = _paper_eq6(l1, l2, l0, d["r"], d["R"], d["beta"], as_printed=True)
        except ValueError:  # the arcsine's argument leaves [-1, 1]
            wrong += 1
            continue
        wrong += not np.allclose(printed, pose[1:], atol=1e-6)
    assert wrong == len(x)


def test_at_alpha_0_the_first_leg_depends_on_both_angles(mech):
    """The decoupling behind eq. 6 needs S1 on the second U axis (alpha = 90 deg): at alpha = 0 leg 1
    moves with theta2 as well, so the paper's 'same calculation' does not apply."""
    for alpha, moves in ((90 * DEG, False), (0.0, True)):
        design = mech.design({**mech.design(), "alpha": alpha})
        x = np.array([[0.5, 0.2, -0.3], [0.5, 0.2, 0.3]])
        l1 = mech.inverse_kinematics(x, design)[:, 0]
        assert (abs(l1[0] - l1[1]) > 1e-6) == moves


def _generalised_force(x: np.ndarray, wrench: np.ndarray) -> np.ndarray:
    """Virtual work of a wrench (F, M) at U0 per unit pose rate: U0 moves along Z with l0, the platform
    turns about X with theta1 and about Rx(theta1) Y with theta2."""
    t1 = x[:, 1]
    axis2 = np.stack([np.zeros_like(t1), np.cos(t1), np.sin(t1)], axis=1)
    return np.stack([wrench[:, 2], wrench[:, 3], np.einsum("ni,ni->n", wrench[:, 3:], axis2)], axis=1)


def test_actuator_forces_satisfy_virtual_work(mech, case):
    design, x = case
    rng = np.random.default_rng(3)
    wrench = rng.normal(size=(len(x), 6)) * [100, 100, 1000, 10, 10, 10]
    forces = mech.statics(x, wrench, design).actuators
    J = mech.jacobian(x, design)
    np.testing.assert_allclose(np.einsum("nij,ni->nj", J, forces), _generalised_force(x, wrench), rtol=1e-9,
                               atol=1e-9 * np.abs(wrench).max())


def test_forces_balance_the_platform(mech, case):
    design, x = case
    rng = np.random.default_rng(4)
    wrench = rng.normal(size=(len(x), 6)) * [100, 100, 1000, 10, 10, 10]
    result = mech.statics(x, wrench, design)
    U0, S1, S2, U1, U2, _ = (v[:, :, 0] for v in evaluate(mech.functions["joint_positions"], x, design.vector()))
    s1 = (S1 - U1) / np.linalg.norm(S1 - U1, axis=1, keepdims=True)
    s2 = (S2 - U2) / np.linalg.norm(S2 - U2, axis=1, keepdims=True)
    f1, f2, f0 = result.actuators.T
    fx, fy, mc = result.constraint.T
    ez = np.array([0.0, 0.0, 1.0])
    force = f1[:, None] * s1 + f2[:, None] * s2 + f0[:, None] * ez + np.stack([fx, fy, 0 * fx], axis=1)
    normal = np.stack([0 * mc, -np.sin(x[:, 1]), np.cos(x[:, 1])], axis=1)
    moment = (f1[:, None] * np.cross(S1 - U0, s1) + f2[:, None] * np.cross(S2 - U0, s2) + mc[:, None] * normal)
    np.testing.assert_allclose(np.hstack([force, moment]), wrench, atol=1e-9 * np.abs(wrench).max())


def test_printed_statics_differs_from_the_physical_one_where_theta1_is_not_zero(mech):
    x = np.array([[0.5, 0.3, 0.2]])
    wrench = np.array([10.0, -20.0, -500.0, 3.0, -4.0, 5.0])
    physical = mech.statics(x, wrench)
    printed = mech.statics(x, wrench, printed=True)
    assert not np.allclose(physical.actuators, printed.actuators, rtol=1e-3)


def test_bad_input(mech):
    with pytest.raises(DesignError, match="sin\\(beta - alpha\\)"):
        mech.design({**mech.design(), "beta": mech.design()["alpha"]})
    with pytest.raises(DesignError, match=r"D = -0\.001"):
        mech.design({**mech.design(), "D": -0.001})
    with pytest.raises(DesignError, match="alpha"):
        mech.design({**mech.design(), "alpha": 4.0})
    with pytest.raises(DesignError, match="l_min < l_max"):
        mech.design({**mech.design(), "l_max": 0.3})
    with pytest.raises(PoseError, match="wrench"):
        mech.statics([0.5, 0.0, 0.0], [1.0, 2.0])


def test_workspace_margins_against_independent_computations(mech):
    """Every margin recomputed from the joint positions with numpy: strokes, joint misalignments, the
    least distance between legs by brute force over the segments, and the sign of det J."""
    from pkm.models.ups_pu.workspace import MARGINS

    rng = np.random.default_rng(9)
    design = mech.design()
    d = dict(design)
    x = np.column_stack([rng.uniform(0.4, 0.7, 30), rng.uniform(-1.2, 1.2, 30), rng.uniform(-1.2, 1.2, 30)])
    margins = mech.workspace_margins(x, design)
    assert list(margins) == list(MARGINS)
    q = mech.inverse_kinematics(x, design, limits=False)
    _, S1, S2, U1, U2, z_p = (v[:, :, 0] for v in evaluate(mech.functions["joint_positions"], x, design.vector()))
    np.testing.assert_allclose(margins["l1_min"], q[:, 0] - d["l_min"], atol=1e-12)
    np.testing.assert_allclose(margins["l2_max"], d["l_max"] - q[:, 1], atol=1e-12)
    np.testing.assert_allclose(margins["l0_min"], x[:, 0] - d["l0_min"], atol=1e-12)
    leg1 = (S1 - U1) / np.linalg.norm(S1 - U1, axis=1, keepdims=True)
    angle_u1 = np.arccos(leg1[:, 2])
    assert np.array_equal(margins["u1_range"] >= 0, angle_u1 <= d["theta_u_max"])
    angle_s1 = np.arccos(np.einsum("ni,ni->n", leg1, z_p))
    assert np.array_equal(margins["s1_range"] >= 0, angle_s1 <= d["theta_s_max"])
    s = np.linspace(0, 1, 401)
    for k in range(len(x)):
        a = U1[k] + s[:, None] * (S1[k] - U1[k])
        b = U2[k] + s[:, None] * (S2[k] - U2[k])
        brute = np.min(np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2))
        assert margins["legs_1_2"][k] + d["D"] == pytest.approx(brute, abs=2e-3 * np.linalg.norm(S1[k] - U1[k]))
        assert margins["legs_1_2"][k] + d["D"] <= brute + 1e-12
    r = d["r"]
    det = np.linalg.det(mech.jacobian(x, design) @ np.diag([1, 1 / r, 1 / r]))
    home = np.linalg.det(mech.jacobian(np.column_stack([x[:, 0], 0 * x[:, :2]]), design) @ np.diag([1, 1 / r, 1 / r]))
    np.testing.assert_allclose(margins["jacobian_sign"], det * np.sign(home), rtol=1e-10)
    assert np.all(home < 0)


def test_ray_search_area_agrees_with_sampling_where_the_section_is_star_shaped(mech):
    from pkm.models.ups_pu.workspace import section

    d = mech.design().vector()
    for l0 in (0.45, 0.55, 0.65):
        cut = section(mech, d, l0, resolution=160, rays=360, step=0.25 * DEG)
        assert cut.reentrant_rays == 0
        assert cut.sampled_area == pytest.approx(cut.ray_area, rel=1.5e-2)
        assert cut.mask.any()


@pytest.fixture(scope="module")
def synthesis():
    return pkm.synthesize("ups_pu.min_size_force_task", resolution=2, starts=1, baseline_resolution=60)


def test_synthesis_optimum_is_feasible_on_dense_sampling_and_beats_monte_carlo(synthesis):
    from pkm.models.ups_pu.problems import TASK_MARGIN_MIN
    from pkm.regions import sampled_check

    mech = pkm.load("ups_pu")
    design = np.array(list(synthesis.design.values()))
    dense = sampled_check(mech, TASK_MARGIN_MIN, mech.regions["task"], design, branch=mech.working_mode(None),
                          resolution=30)
    assert dense.points > 10_000
    assert float(dense) >= 0
    assert synthesis.design["l_max"] == pytest.approx(1.8 * synthesis.design["l_min"])
    assert synthesis.design["alpha"] == pytest.approx(math.pi / 2)
    monte_carlo = synthesis.baselines["monte_carlo"].best
    assert monte_carlo.feasible
    assert synthesis.verified_objective < monte_carlo.verified_objective


def test_table1_is_evaluated_on_the_same_model_and_violates_the_leg_strokes_by_its_rounding(synthesis):
    """Table 1's l_{1,2 min} = 396 mm rounds step 5's 395.9 mm up: its legs are 0.1 mm too long for the
    cylinder's bottom rim, so pkm reports it infeasible by that much; its objective is far above the
    optimum's."""
    table1 = synthesis.baselines["table1"].best
    assert not table1.feasible
    mech = pkm.load("ups_pu")
    d = np.array(list(table1.design.values()))
    points, _ = mech.regions["task"].quadrature(mech.functions, d, 3, "min")
    margins = mech.workspace_margins(points, d)
    assert -2e-4 < margins["l1_min"].min() < 0
    assert table1.objective > 10 * synthesis.objective


def test_the_synthesis_keeps_section_5_3s_joint_limits_and_reads_gamma_u_as_the_apex_angle():
    from pkm import registry

    problem = registry.problem("ups_pu.min_size_force_task")
    design = dict(zip(problem.mechanism.parameter_names(), np.ravel(problem.design([0.5, 0.1, 0.2, 0.4, 0.3])),
                      strict=True))
    assert design["theta_s_max"] == pytest.approx(math.radians(60))
    assert design["theta_u_max"] == pytest.approx(math.radians(90))
    assert design["task_tilt"] == pytest.approx(math.radians(30))
    assert design["l0_max"] == pytest.approx(0.4 + 0.1)


def test_the_problems_settings_choose_the_task_the_joint_limits_and_the_load():
    from pkm import registry
    from pkm.errors import PkmError, UnknownNameError

    problem = registry.problem("ups_pu.min_size_force_task")
    literal = problem.configure(task_tilt=math.pi / 3, task_height=0.2, theta_s_max=math.pi / 2, payload=10.0)
    design = dict(zip(problem.mechanism.parameter_names(), np.ravel(literal.design([0.5, 0.1, 0.2, 0.4, 0.3])),
                      strict=True))
    assert (design["task_tilt"], design["task_height"], design["l0_max"]) == pytest.approx((math.pi / 3, 0.2, 0.6))
    assert (design["theta_s_max"], design["payload"]) == pytest.approx((math.pi / 2, 10.0))
    assert literal.values["theta_u_max"] == problem.values["theta_u_max"]
    assert "tilt <= 60 deg" in literal.doc
    assert problem.configure() is problem
    with pytest.raises(UnknownNameError, match="tilt"):
        problem.configure(tilt=0.5)
    with pytest.raises(PkmError, match="task_tilt = 30 violates"):
        problem.configure(task_tilt=30)
    with pytest.raises(PkmError, match="payload"):
        problem.configure(payload="heavy")


def test_a_configured_problem_runs_in_workers_with_its_settings():
    """A task names the problem and carries its settings: a worker rebuilds the configured problem."""
    import json

    from pkm import registry
    from pkm.synthesis import driver

    configured = registry.problem("ups_pu.min_size_force_task").configure(task_tilt=0.4)
    assert driver._registered(configured)
    model = driver._model(configured.name, driver._settings(configured))
    assert model.problem.values["task_tilt"] == 0.4
    assert json.loads(driver._settings(configured))["task_tilt"] == 0.4


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["eval", "ups_pu", "--pose", "0.5,0,0", "--design", "D=-0.001"], "D = -0.001"),
        (["eval", "ups_pu", "--pose", "0.5,0,0", "--design", "alpha=4"], "alpha"),
        (["eval", "ups_pu", "--pose", "0.5,0,0", "--design", "beta=-1.5707963267948966"], "sin(beta - alpha)"),
        (["index", "ups_pu", "gci", "--region", "task", "--design", "task_tilt=1.7"], "task_tilt"),
        (["atlas", "ups_pu", "gci", "--region", "task", "--axes", "R=0.3:0.1,beta=0.2:1"], "lower < upper"),
        (["synth", "ups_pu.min_size_force_task", "--set", "tilt=1"], "unknown setting"),
        (["synth", "ups_pu.min_size_force_task", "--set", "task_tilt=30"], "task_tilt = 30 violates"),
        (["synth", "ups_pu.min_size_force_task", "--set", "payload=heavy"], "setting payload"),
    ],
)
def test_bad_input_exits_2_with_one_line(capfd, argv, message):
    from pkm.cli import main

    assert main(argv) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert message in err[0]


def test_atlas_over_two_design_parameters_of_the_users_choice(tmp_path):
    from pkm.atlas import compute_atlas
    from pkm.design_space import parameter_plane

    mech = pkm.load("ups_pu")
    space = parameter_plane(mech.parameters, (("r", 0.08, 0.16), ("R", 0.12, 0.24)))
    atlas = compute_atlas(mech, mech.global_spec("gci"), space=space, region="task", resolution=5, pose_resolution=2)
    assert atlas.inside[1:-1, 1:-1].all()  # the chart grid leaves out the plane's edges
    best = atlas.best()
    design = space.designs(mech.parameters, [best.u, best.v])
    assert mech.global_index("gci", design, region="task", resolution=2) == pytest.approx(best.value, rel=1e-12)
    assert atlas.plot(tmp_path / "atlas.png").stat().st_size > 1000


def test_a_base_no_wider_than_the_platform_still_assembles(mech):
    """R <= r breaks nothing in this geometry (U0 stays above the base, so no leg shrinks to zero): such a
    design is valid, and IK and FK still invert each other."""
    design = mech.design({**mech.design(), "r": 0.2, "R": 0.15})
    x = np.array([[0.5, 0.3, -0.2], [0.6, -0.4, 0.1]])
    q = mech.inverse_kinematics(x, design)
    assert np.all(q > 0.3)
    poses = np.stack([mech.forward_kinematics(q, design, assembly=a) for a in mech.assemblies])
    distance = np.linalg.norm(poses - x, axis=2)
    assert np.nanmin(np.where(np.isnan(distance), np.inf, distance), axis=0).max() < 1e-9


def test_a_pose_is_reached_within_the_stated_limits_and_the_assembled_set_keeps_its_own_name(mech):
    """A 500 m leg and a tilt typed in degrees assemble but break the strokes and joint ranges: out of
    reach, and strict raises; without limits (and in the region "assembled") they are reached."""
    from pkm.errors import PoseError

    poses = np.array([[0.5, 0.0, 0.0], [500.0, 0.0, 0.0], [0.5, 30.0, 0.0]])
    assert mech.reachable(poses).tolist() == [True, False, False]
    assert mech.reachable(poses, limits=False).all()
    assert np.isnan(mech.inverse_kinematics(poses)[1:]).all()
    assert np.isfinite(mech.inverse_kinematics(poses, limits=False)).all()
    with pytest.raises(PoseError):
        mech.inverse_kinematics(poses[1], strict=True)
    margins = mech.limit_margins(poses)
    assert margins["l1_max"][1] < 0
    assert margins["theta1_range"][2] < 0
    assert "assembled" in mech.region_names()


def test_indices_over_the_sampled_workspace_average_over_poses_the_machine_reaches(mech):
    """Over the reachable workspace the least workspace margin is >= 0 and the forces are those of poses
    within the limits; over the assembled set (the issue's -0.97 and 91,801 N) they are not."""
    within = mech.global_index("workspace_margin_min", resolution=24)
    assembled = mech.global_index("workspace_margin_min", region="assembled", resolution=24)
    assert float(within) >= -1e-9 > float(assembled)
    assert within.points < assembled.points
    forces = mech.global_index("actuator_force_max", resolution=24)
    assert float(forces) < float(mech.global_index("actuator_force_max", region="assembled", resolution=24))


def test_actuator_forces_are_infinite_where_the_wrench_matrix_is_singular(mech):
    """At a parallel singularity (det J = 0, found by bisection) the largest force is its limit, not a
    finite 1e13 N; a millimetre away it is finite."""
    from pkm.batch import evaluate

    design = mech.design()

    def det(theta2):
        return np.linalg.det(mech.jacobian([0.55, 0.0, theta2], design))

    lo, hi = 1.0, 1.5
    assert det(lo) * det(hi) < 0
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if det(mid) * det(lo) > 0 else (lo, mid)
    x = np.array([[0.55, 0.0, lo], [0.55, 0.0, lo - 1e-2]])
    q = mech.inverse_kinematics(x, design, limits=False)
    (forces,) = evaluate(mech.functions["actuator_forces"], q, x, design.vector())
    assert np.isinf(forces[0]).all()
    assert np.isfinite(forces[1]).all()


def test_eval_says_which_limit_a_pose_breaks_and_suspects_degrees(capfd):
    from pkm.cli import main

    assert main(["eval", "ups_pu", "--pose", "0.5,30,0"]) == 0
    out = capfd.readouterr().out
    assert "out of reach" in out
    assert "theta1_range" in out
    assert "theta1 = 30 rad: in degrees?" in out


def test_synth_takes_the_problems_settings_from_the_command_line(capfd):
    import json

    from pkm.cli import main

    assert main(["synth", "ups_pu.min_size_force_task", "--set", "payload=20,task_tilt=0.6", "--starts", "1",
                 "--json"]) == 0
    data = json.loads(capfd.readouterr().out)
    assert data["settings"]["payload"] == 20.0
    assert data["settings"]["task_tilt"] == 0.6
    assert data["design"]["payload"] == 20.0
    assert data["design"]["task_tilt"] == 0.6
