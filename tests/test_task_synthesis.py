"""Task-rectangle synthesis of Wu's slider gantry (Wu 2008 section 4): IPOPT in (l, d1) against Wu's
two-step family, a grid and Wu's Table 1 design, with every constraint recomputed from the design.

Wu's own procedures are pkm.models.slider_gantry.wu2008; the problem is registered by
pkm.models.slider_gantry.problems and solved by the one driver (pkm.synthesis)."""

from __future__ import annotations

import json
import math

import casadi as ca
import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.cli import main
from pkm.models.slider_gantry import wu2008 as wu
from pkm.models.slider_gantry.problems import TWO_STEP_SAMPLES
from pkm.reproduce.report import synthesis_record
from pkm.synthesis import Candidate, ProblemModel

NAME = "slider_gantry.min_kappa_d_task"
DEG = math.pi / 180
B, H, CENTRE_Y = 0.5, 0.4, 0.5  # Wu's task rectangle [m], centred at (0, CENTRE_Y)
RES = 4  # quadrature resolution of the optimised objective
TOL = 1e-7  # feasibility slack (the problem's feasibility_tolerance)
PAPER_POINT = wu.two_step_points(B, H, np.array([10 * DEG]))[0]  # Wu's Table 1 design: theta_1S = 10 deg
FRAME_WIDTH = 3  # the row of the frame-width constraint in the problem's g


@pytest.fixture(scope="module")
def result():
    return pkm.synthesize(NAME, resolution=RES, baseline_resolution=21, starts=2)


@pytest.fixture(scope="module")
def gantry():
    return pkm.load("slider_gantry")


@pytest.fixture(scope="module")
def model():
    return ProblemModel(registry.problem(NAME))


@pytest.fixture(scope="module")
def paper(model) -> Candidate:
    """Wu's Table 1 design on the problem's model at the synthesis's resolution, verified."""
    return model.assess(PAPER_POINT, RES)


def chart(cand: Candidate) -> tuple[float, float]:
    """(l, d1) of a candidate."""
    return cand.variables["l"], cand.variables["d1"]


def rectangle_poses(n: int = 2, centre_y: float = CENTRE_Y) -> np.ndarray:
    """An n x n grid of poses over the B x H rectangle centred at (0, centre_y); n = 2: its corners."""
    X, Y = np.meshgrid(np.linspace(-B / 2, B / 2, n), np.linspace(centre_y - H / 2, centre_y + H / 2, n))
    return np.stack([X.ravel(), Y.ravel()], axis=1)


def test_problem_states_wus_task_and_constraints():
    prob = registry.problem(NAME)
    assert prob.variable_names == ("l", "d1")
    assert prob.mode == "below"
    assert prob.objective.sense == "min"
    assert [c.lower for c in prob.constraints] == [0.0, 0.0, 0.0, 0.0, 1.0]
    assert "frame width" in prob.constraints[FRAME_WIDTH].name
    assert prob.notes["width"] == B
    assert prob.notes["height"] == H
    assert prob.notes["centre_y"] == CENTRE_Y
    assert prob.notes["theta_s"] == pytest.approx(10 * DEG)
    assert [b.name for b in prob.baselines] == ["grid", "two_step"]


def test_synthesis_converges_from_every_start(result):
    assert result.status == "Solve_Succeeded"
    assert result.problem == NAME
    assert result.sense == "min"
    assert len(result.runs) == 2
    assert all(r.success for r in result.runs)
    # the last start is Wu's Table 1 design; both starts reach the same optimum
    assert list(result.runs[-1].start) == ["l", "d1"]
    assert list(result.runs[-1].start.values()) == pytest.approx(PAPER_POINT, abs=1e-12)
    for run in result.runs:
        assert run.variables == pytest.approx(result.optimum.variables, abs=1e-6)
        assert run.objective == pytest.approx(result.objective, abs=1e-9)
        assert run.verified_objective == pytest.approx(result.verified_objective, abs=1e-9)


def test_optimum_value_and_location(result):
    """Regression values at resolution 4: the frame width binds (d1 = 1/2 - d2), l is interior."""
    length, d1 = chart(result.optimum)
    assert length == pytest.approx(0.770984, abs=1e-5)
    assert d1 == pytest.approx(0.4, abs=1e-7)
    assert result.objective == pytest.approx(1.371254, abs=1e-5)
    assert result.design["l"] == length
    assert result.design["d1"] == d1
    assert result.variables == result.optimum.variables


def test_optimum_satisfies_every_constraint(result, gantry):
    d = result.design
    corners = rectangle_poses(2)
    q = gantry.inverse_kinematics(corners, d, passive=True)
    assert np.all(np.isfinite(q))
    theta = np.abs(q[:, 2:])
    assert np.all(theta >= 10 * DEG - 1e-9)
    assert np.all(theta <= 80 * DEG + 1e-9)
    # the sliders stay within [qs, ql]; the rectangle needs at most Wu's 900 mm of stroke
    sliders = q[:, :2]
    assert np.all(sliders >= d["qs"] - 1e-9)
    assert np.all(sliders <= d["ql"] + 1e-9)
    stroke = sliders.max() - sliders.min()
    assert stroke == pytest.approx(d["ql"] - d["qs"], abs=1e-9)  # the placement uses the whole stroke
    assert stroke == pytest.approx(float(wu.required_stroke(d["l"], d["d1"], B, H)), abs=1e-12)
    assert stroke <= 0.9 + TOL
    assert 2 * (d["d1"] + d["d2"]) <= 1.0 + TOL
    assert (d["d2"], d["l2"]) == (0.1, 0.2)
    # the design's own margins are its extreme link angles over the rectangle, inside the problem's
    assert 10 * DEG <= d["theta_s"] < d["theta_l"] <= 80 * DEG
    assert d["theta_s"] == pytest.approx(np.arcsin((d["d1"] - B / 2) / d["l"]), abs=1e-12)
    assert d["theta_l"] == pytest.approx(np.arcsin((d["d1"] + B / 2) / d["l"]), abs=1e-12)
    own = gantry.task_rectangle(d)
    assert (own.width, own.height) == pytest.approx((B, 0.4), abs=1e-9)
    gantry.fit_task(B, 0.4, d)
    k_av = wu.k_av_closed_form(d["l"], d["d1"], B)
    assert k_av >= 1.0
    assert k_av == pytest.approx(1.968224, abs=1e-5)


def test_whole_rectangle_is_reachable_within_the_angle_margins(result, gantry):
    poses = rectangle_poses(11)
    assert gantry.reachable(poses, result.design).all()
    assert gantry.reachable(rectangle_poses(2), result.design).all()
    theta = np.abs(gantry.inverse_kinematics(poses, result.design, passive=True)[:, 2:])
    assert theta.min() >= 10 * DEG - 1e-9
    assert theta.max() <= 80 * DEG + 1e-9
    # the link with the smallest angle is at the rectangle's corners (both margins are slack: 11.2, 57.5 deg)
    assert theta.min() / DEG == pytest.approx(11.2188, abs=1e-3)
    assert theta.max() / DEG == pytest.approx(57.4667, abs=1e-3)


def test_optimum_beats_grid_two_step_family_and_wu(result, paper):
    grid, family = result.baselines["grid"], result.baselines["two_step"]
    assert result.baseline is grid.best
    assert result.objective <= grid.best.objective + 1e-6
    assert result.objective <= family.best.objective + 1e-6
    assert result.objective <= paper.objective + 1e-6
    assert paper.objective - result.objective > 0.05
    assert grid.best.objective == pytest.approx(1.371601, abs=1e-5)
    assert family.best.objective == pytest.approx(1.498125, abs=1e-5)
    assert paper.objective == pytest.approx(1.555334, abs=1e-5)
    assert (grid.resolution, grid.evaluations) == (21, 21**2)
    assert grid.wall_time_s > 0
    assert family.evaluations == TWO_STEP_SAMPLES  # its own sampling, whatever the grid's resolution
    # the two-step best is a member of Wu's family: eqs. 14-15 at its theta_1S = asin((d1 - b/2) / l)
    length, d1 = chart(family.best)
    theta_1s = math.asin((d1 - B / 2) / length)
    assert 10 <= theta_1s / DEG <= 44.9
    assert wu.two_step_points(B, H, np.array([theta_1s]))[0] == pytest.approx([length, d1], abs=1e-12)


def test_baselines_satisfy_the_constraints(result, paper):
    for cand in (result.baselines["grid"].best, result.baselines["two_step"].best, paper):
        assert cand.feasible
        length, d1 = chart(cand)
        assert d1 - B / 2 - length * math.sin(10 * DEG) >= -TOL
        assert length * math.sin(80 * DEG) - d1 - B / 2 >= -TOL
        assert float(wu.required_stroke(length, d1, B, H)) <= 0.9 + TOL
        assert 2 * (d1 + 0.1) <= 1.0 + TOL
        assert wu.k_av_closed_form(length, d1, B) >= 1.0


def test_paper_design_objective_matches_the_mechanism_global_index(paper, gantry):
    """Wu's design has exactly the 0.5 x 0.4 rectangle as its own task region, so the fixed-placement
    objective and k_av equal the mechanism's global indices over region "task"."""
    d = paper.design
    own = gantry.task_rectangle(d)
    assert (own.width, own.height) == pytest.approx((B, H), abs=1e-9)
    assert own.centre == pytest.approx((0.0, CENTRE_Y), abs=1e-9)
    value = gantry.global_index("kappa_d_mean", d, region="task", resolution=RES)
    assert float(value) == pytest.approx(paper.objective, rel=1e-10)
    k_av = gantry.global_index("k_av", d, region="task", resolution=8)
    assert float(k_av) == pytest.approx(wu.k_av_closed_form(*chart(paper), B), rel=1e-6)


def test_optimum_is_verified_by_denser_quadrature_and_sampling(result):
    o = result.optimum
    assert result.resolutions["quadrature"] == RES
    assert result.resolutions["verification_points"] == 4 * result.resolutions["quadrature_points"]
    assert o.verified_objective == pytest.approx(o.objective, rel=1e-3)
    assert o.sampled_objective == pytest.approx(o.objective, rel=1e-3)
    assert o.sampled_points == (16 * RES) ** 2


def test_optimum_is_stationary_along_the_active_frame_width(result, model):
    length, d1 = chart(result.optimum)
    assert 2 * (d1 + 0.1) == pytest.approx(1.0, abs=1e-6)  # the frame width binds
    feasible = 0
    for dl in (1e-3, -1e-3):
        obj, ok = model.evaluate(np.array([[length + dl, d1]]), RES)
        if ok[0]:
            feasible += 1
            assert obj[0] >= result.objective - 1e-7
    assert feasible == 2
    # the constraint binds: a narrower frame (d1 - 1e-3, feasible) is worse
    obj, ok = model.evaluate(np.array([[length, d1 - 1e-3]]), RES)
    assert ok[0]
    assert obj[0] > result.objective + 1e-4


def test_model_objective_and_k_av_at_the_optimum(result, model):
    fn = model.function(RES)
    assert fn.n_out() == 4  # objective, g in the order of problem.constraints, then the quantities
    assert fn.name_out()[2:] == ["kappa_d_mean", "k_av"]
    objective, g, kappa_d_mean, k_av = (np.asarray(v).ravel() for v in fn(np.array(chart(result.optimum))))
    assert objective[0] == pytest.approx(result.objective, rel=1e-12)
    assert kappa_d_mean[0] == objective[0]
    assert k_av[0] == pytest.approx(wu.k_av_closed_form(*chart(result.optimum), B), rel=1e-4)
    assert g[-1] == k_av[0]  # k_av >= min_k_av is the last row, with lower bound 1
    margins = g - model.lower  # every upper bound is infinite: the margins are g - lower
    assert np.all(np.isinf(model.upper))
    assert np.all(margins >= -TOL)
    assert margins[FRAME_WIDTH] == pytest.approx(0.0, abs=1e-7)  # frame width active, the others slack
    assert np.all(np.delete(margins, FRAME_WIDTH) > 1e-3)


@pytest.mark.parametrize("point", [(0.7, 0.375), (0.6164, 0.357), None])
def test_objective_gradient_matches_central_differences(result, model, point):
    w0 = np.array(chart(result.optimum) if point is None else point)
    fn = model.function(RES)
    w = ca.MX.sym("w", 2)
    grad = ca.Function("grad", [w], [ca.gradient(fn(w)[0], w)])
    exact = np.asarray(grad(w0)).ravel()
    step = 1e-6
    central = np.array([(float(fn(w0 + step * e)[0]) - float(fn(w0 - step * e)[0])) / (2 * step) for e in np.eye(2)])
    assert exact == pytest.approx(central, rel=1e-5, abs=1e-6)


def test_first_two_step_member_is_wus_table_1(paper):
    length, d1 = chart(paper)
    assert length == pytest.approx(0.6164, abs=1e-4)
    assert d1 == pytest.approx(0.357, abs=1e-4)
    first = wu.workspace_synthesis(B, H, 10 * DEG)
    assert (first.length, first.d1) == pytest.approx((length, d1), abs=1e-12)
    assert first.theta_2l == pytest.approx(80 * DEG)
    assert first.y_d1 == pytest.approx(B)  # eq. 13: y_d1 : b = 1 : 1
    assert first.stroke == pytest.approx(0.9)  # Table 1: 900 mm
    family = next(b for b in registry.problem(NAME).baselines if b.name == "two_step")
    assert family.points(family.resolution)[0] == pytest.approx([length, d1], abs=1e-12)


def test_workspace_synthesis_reproduces_wus_15_degree_example():
    """Section 4.2: theta_1S = 15 deg gives d1 = 433 mm, l = 707.1 mm and a 900 mm stroke."""
    w = wu.workspace_synthesis(B, H, 15 * DEG)
    assert w.d1 == pytest.approx(0.433, abs=5e-4)
    assert w.length == pytest.approx(0.7071, abs=5e-5)
    assert w.stroke == pytest.approx(0.9)
    assert math.sin(w.theta_1s) == pytest.approx(w.d / w.length)  # eq. 10
    assert math.sin(w.theta_2l) == pytest.approx((B + w.d) / w.length)  # eq. 11


@pytest.mark.parametrize("centre_y", [0.3, 0.5, 0.8])
def test_two_step_design_places_the_rectangle(gantry, centre_y):
    d = wu.two_step_design(B, H, 10 * DEG, d2=0.1, l2=0.2, centre_y=centre_y)
    own = gantry.task_rectangle(d)
    assert own.width == pytest.approx(B, abs=1e-9)
    assert own.height == pytest.approx(H, abs=1e-9)
    assert own.centre == pytest.approx((0.0, centre_y), abs=1e-9)
    qs, ql = wu.placement(d["l"], d["d1"], B, H, l2=0.2, centre_y=centre_y)
    assert (d["qs"], d["ql"]) == (qs, ql)
    assert ql - qs == pytest.approx(0.9, abs=1e-12)
    assert gantry.reachable(rectangle_poses(2, centre_y), d).all()


def test_bad_input():
    with pytest.raises(pkm.UnknownNameError, match="unknown synthesis problem"):
        pkm.synthesize("slider_gantry.nope")
    with pytest.raises(pkm.PkmError, match="resolution = 0"):
        pkm.synthesize(NAME, resolution=0)
    with pytest.raises(pkm.PkmError, match="starts = 0"):
        pkm.synthesize(NAME, starts=0)
    with pytest.raises(pkm.DesignError, match="theta_1S"):
        wu.two_step_design(B, H, 50 * DEG, d2=0.1, l2=0.2)
    with pytest.raises(pkm.DesignError, match="b = 0"):
        wu.workspace_synthesis(0.0, H, 10 * DEG)
    with pytest.raises(pkm.DesignError, match="k_av needs"):
        wu.k_av_closed_form(0.6, 0.2, B)  # d1 - b/2 < 0: a link would pass the vertical


def test_result_to_dict_is_json_ready(result):
    data = json.loads(json.dumps(result.to_dict()))
    assert data["sense"] == "min"
    assert data["objective"] == result.objective
    assert data["variables"] == result.optimum.variables
    assert list(data["baselines"]) == ["grid", "two_step"]
    for name, base in result.baselines.items():
        assert data["baselines"][name]["best"]["variables"] == base.best.variables
        assert data["baselines"][name]["best"]["objective"] == base.best.objective
        assert data["baselines"][name]["evaluations"] == base.evaluations
    assert data["baseline_objective"] == result.baselines["grid"].best.objective
    record = json.loads(json.dumps(synthesis_record(result)))
    assert record["two_step_objective"] == result.baselines["two_step"].best.objective
    assert record["grid_objective"] == record["baseline_objective"] == result.baselines["grid"].best.objective


def test_cli_synth_writes_the_task_result(tmp_path, capsys, paper):
    args = ["synth", NAME, "--resolution", str(RES), "--starts", "2", "--out", str(tmp_path), "--json"]
    assert main(args) == 0
    data = json.loads((tmp_path / f"{NAME}.json").read_text())
    assert data == json.loads(capsys.readouterr().out)
    assert data["status"] == "Solve_Succeeded"
    assert data["objective"] <= data["baseline_objective"] + 1e-6
    assert data["objective"] < paper.objective - 0.05
    assert data["design"]["d1"] == pytest.approx(0.4, abs=1e-7)


def test_two_step_design_of_a_wide_task_scales_the_links_as_the_synthesis_does():
    """A 1 m task rectangle needs links of 3.8 m: Table 2's inertias (at l = 0.6164 m) would put each
    link's inertia about its pivot below m s^2 (no such link); they follow the length as in the problems."""
    from pkm.models.slider_gantry.problems import task_design

    d = wu.two_step_design(1.0, 0.3, 0.6, d2=0.1, l2=0.3)
    assert d["l"] > 0.75
    g = pkm.load("slider_gantry")
    scaled = dict(zip(g.parameter_names(), task_design(g, d["l"], d["d1"]), strict=True))
    for name in ("I12", "I22", "I4", "s12", "s22", "s4"):
        assert d[name] == pytest.approx(scaled[name], rel=1e-12), name
