"""Quantities along a trajectory (pkm.dynamics.quantities): against numpy from Mechanism.inverse_dynamics at the
same nodes, their design gradients against central differences, and bad input."""

from __future__ import annotations

import numpy as np
import pytest

import pkm
from pkm.dynamics import Trajectory
from pkm.dynamics.quantities import trajectory_indices, trajectory_values
from pkm.errors import PkmError, PoseError, UnknownNameError
from pkm.regions import trajectory_region
from pkm.reproduce.wu2008 import TABLE3

RESOLUTION = 4


@pytest.fixture(scope="module")
def gantry():
    return pkm.load("slider_gantry")


@pytest.fixture(scope="module")
def move():
    return Trajectory.trapezoidal(TABLE3["x0"], TABLE3["x1"], TABLE3["v_max"], TABLE3["a_s"])


def _nodes(region, reduce):
    """Times, weights [s] and the one-sided motion at the nodes of the region's rule, by numpy: each piece's
    node at its start takes the phase after, at its end the phase before."""
    times, weights, states = [], [], []
    for piece in region.pieces():
        u, w = piece.reference(RESOLUTION, reduce)
        t = piece.time(u[:, 0])
        after = piece.move.sample(t, side="after")
        before = piece.move.sample(t, side="before")
        pick = (u[:, 0] < 0)[:, None]
        states.append([np.where(pick, a, b) for a, b in zip(after, before, strict=True)])
        times.append(t)
        weights.append(w * (piece.end - piece.start) / 2)
    x, x_dot, x_ddot = (np.concatenate([s[k] for s in states]) for k in range(3))
    return np.concatenate(times), np.concatenate(weights), x, x_dot, x_ddot


def _numpy_quantities(mech, region, design, mode):
    """Every dynamic quantity from Mechanism.inverse_dynamics and Mechanism.jacobian, reduced by numpy with the
    region's own nodes and weights (node extremes: the maxima are checked against dense samples below)."""
    _, w, x, x_dot, x_ddot = _nodes(region, "mean")
    tau = mech.inverse_dynamics(x, x_dot, x_ddot, design, mode=mode)
    q_dot = np.einsum("nij,nj->ni", mech.jacobian(x, design, mode=mode), x_dot)
    power = tau * q_dot
    return {
        "effort_rms": np.sqrt(np.sum(w * np.sum(tau**2, axis=1) / mech.n_act) / np.sum(w)),
        "energy": np.sum(w * power.sum(axis=1)),
        "energy_no_regeneration": np.sum(w * np.maximum(power, 0).sum(axis=1)),
    }


def _dense_maxima(mech, move, design, mode):
    """Peak effort, power and actuator rate over 20,001 samples and both sides of every switch."""
    t = np.linspace(0, move.duration, 20_001)
    states = [move.sample(t)]
    switches = move.switches()
    states += [(switches.position, switches.velocity, a) for a in (switches.acceleration_before,
                                                                   switches.acceleration_after)]
    peaks = {"effort_peak": 0.0, "power_peak": 0.0, "actuator_speed_peak": 0.0}
    for x, x_dot, x_ddot in states:
        tau = mech.inverse_dynamics(x, x_dot, x_ddot, design, mode=mode)
        q_dot = np.einsum("nij,nj->ni", mech.jacobian(x, design, mode=mode), x_dot)
        peaks["effort_peak"] = max(peaks["effort_peak"], np.abs(tau).max())
        peaks["power_peak"] = max(peaks["power_peak"], np.abs(np.sum(tau * q_dot, axis=1)).max())
        peaks["actuator_speed_peak"] = max(peaks["actuator_speed_peak"], np.abs(q_dot).max())
    return peaks


def test_gantry_quantities_match_numpy_at_the_nodes_and_the_dense_extremes(gantry, move):
    region = trajectory_region(move)
    values = trajectory_values(gantry, region, mode="below", resolution=RESOLUTION)
    expected = _numpy_quantities(gantry, region, None, "below")
    for name, value in expected.items():
        assert float(values[name]) == pytest.approx(value, rel=1e-10, abs=1e-10), name
    for name, value in _dense_maxima(gantry, move, None, "below").items():
        # refined between the nodes: at least the dense samples' largest (they include the switches, where a
        # trapezoidal move's efforts jump), above it by no more than a sampling step's error
        assert value * (1 - 1e-12) <= float(values[name]) <= value * (1 + 1e-6), name
    x = move.sample(np.linspace(0, move.duration, 2001))[0]
    q = gantry.inverse_kinematics(x, mode="below")
    for k, name in enumerate(gantry.actuator_names):
        assert float(values[f"joint_range_{name}"]) == pytest.approx(np.ptp(q[:, k]), rel=1e-9)


def test_rest_to_rest_energy_of_a_conservative_mechanism_vanishes():
    """The five-bar in its horizontal plane without friction: the actuators' work over a move from rest to rest
    is the kinetic energy's change, zero; without regeneration it is not."""
    bar = pkm.load("five_bar")
    move = Trajectory.point_to_point([0.0, 0.25], [0.05, 0.3], 0.5)
    values = trajectory_values(bar, move, names=["energy", "energy_no_regeneration"], resolution=16)
    assert float(values["energy_no_regeneration"]) > 1e-3
    assert abs(float(values["energy"])) < 1e-12 * float(values["energy_no_regeneration"]) + 1e-15


@pytest.mark.parametrize("name", ["effort_peak", "effort_rms", "energy", "energy_no_regeneration", "power_peak",
                                  "positioning_error", "joint_range_q1"])
def test_design_gradients_match_central_differences(gantry, move, name):
    design = gantry.design_vector(None)
    (value, grad), = trajectory_values(gantry, move, design, mode="below", names=[name], resolution=RESOLUTION,
                                       gradient=True).values()
    names = gantry.parameter_names()
    for parameter in ("l", "d1", "l2"):
        k = names.index(parameter)
        h = 1e-6 * max(1.0, abs(design[k]))
        shifted = []
        for sign in (1, -1):
            d = design.copy()
            d[k] += sign * h
            shifted.append(float(trajectory_values(gantry, move, d, mode="below", names=[name],
                                                   resolution=RESOLUTION)[name]))
        central = (shifted[0] - shifted[1]) / (2 * h)
        assert grad[k] == pytest.approx(central, rel=1e-5, abs=1e-7 * max(1.0, abs(float(value)))), parameter


def test_kinematic_quantities_without_dynamics():
    """A mechanism without a dynamic model offers the kinematic quantities; the positioning error is the largest
    sum_i |J_f[j, i]| delta_i over the nodes, by numpy from Mechanism.forward_jacobian."""
    leg = pkm.load("passive_leg")
    assert set(trajectory_indices(leg)) == {"actuator_speed_peak", "positioning_error", "velocity_amplification"}
    move = Trajectory.trapezoidal([0.0, 1.2], [0.2, 1.35], 0.5, 2.0)
    region = trajectory_region(move)
    encoder = [1e-4, 2e-4]
    values = trajectory_values(leg, region, names=["positioning_error"], resolution=RESOLUTION, encoder=encoder)
    _, _, x, _, _ = _nodes(region, "max")
    error = np.max(np.abs(leg.forward_jacobian(x)) @ np.array(encoder))
    assert float(values["positioning_error"]) >= error - 1e-15
    dense = move.sample(np.linspace(0, move.duration, 4001))[0]
    assert float(values["positioning_error"]) == pytest.approx(np.max(np.abs(leg.forward_jacobian(dense)) @ encoder),
                                                               rel=1e-6)
    with pytest.raises(UnknownNameError, match="effort_peak"):
        trajectory_values(leg, region, names=["effort_peak"])


def test_a_trajectory_out_of_the_workspace_is_named(gantry):
    move = Trajectory.trapezoidal([0.0, 0.5], [3.0, 0.5], 1.0, 5.0)
    with pytest.raises(PoseError, match=r"leaves the workspace of the slider_gantry .* t = [0-9.]+ s at \[[-0-9.]+, "
                                        r"0\.5\]"):
        trajectory_values(gantry, move, mode="below")


def test_a_designer_problem_takes_trajectory_quantities(gantry):
    """design_problem with a trajectory: the objective along its waypoints' moves, verified as
    trajectory_values gives it at the optimum; without a trajectory the name is refused."""
    from pkm.synthesis.designer import ProblemError, design_problem

    trajectory = {"waypoints": [[-0.2, 0.5], [0.2, 0.5], [0.0, 0.45]], "v_max": 1.0, "a_max": 5.0}
    # l up to 0.75 m: the links' centres of mass follow l (l / 2), and beyond 0.75 m the default inertia I12
    # is less than m12 s12^2
    problem = design_problem(gantry, task="task", variables={"l": [0.65, 0.75]}, objective="effort_peak",
                             trajectory=trajectory, mode="below", constraints=[], resolution=RESOLUTION,
                             baseline=("grid", 3))
    result = pkm.synthesize(problem, resolution=RESOLUTION, progress=False)
    moves = [Trajectory.trapezoidal(a, b, 1.0, 5.0) for a, b in zip(trajectory["waypoints"][:-1],
                                                                     trajectory["waypoints"][1:], strict=True)]
    expected = trajectory_values(gantry, moves, result.design, mode="below", names=["effort_peak"],
                                 resolution=2 * RESOLUTION)["effort_peak"]
    assert result.verified_objective == pytest.approx(float(expected), rel=1e-12)
    with pytest.raises(ProblemError, match="effort_peak is taken along a trajectory"):
        design_problem(gantry, task="task", variables={"l": [0.7, 0.8]}, objective="effort_peak", mode="below")


def test_a_task_file_trajectory_may_be_smooth_moves_of_given_durations(gantry):
    """{waypoints, durations}: one rest-to-rest move of the degree-9 profile per segment, the same region as
    Trajectory.point_to_point gives; a count of durations other than the segments' is refused naming it."""
    from pkm.synthesis.designer import ProblemError, design_problem

    waypoints = [[-0.2, 0.5], [0.2, 0.5], [0.0, 0.45]]
    problem = design_problem(gantry, task="task", variables={"l": [0.7, 0.8]}, objective="energy", mode="below",
                             trajectory={"waypoints": waypoints, "durations": [0.6, 0.4]}, constraints=[],
                             resolution=RESOLUTION, baseline=("grid", 3))
    design = problem.design([0.75])
    moves = [Trajectory.point_to_point(waypoints[0], waypoints[1], 0.6),
             Trajectory.point_to_point(waypoints[1], waypoints[2], 0.4)]
    expected = trajectory_values(gantry, moves, design, mode="below", names=["energy"], resolution=RESOLUTION)
    region = problem.quantities["energy"].region
    assert region.duration == pytest.approx(1.0)
    assert float(expected["energy"]) == pytest.approx(float(trajectory_values(
        gantry, region, design, mode="below", names=["energy"], resolution=RESOLUTION)["energy"]), rel=1e-12)
    with pytest.raises(ProblemError, match=r"trajectory\.durations"):
        design_problem(gantry, task="task", variables={"l": [0.7, 0.8]}, objective="energy", mode="below",
                       trajectory={"waypoints": waypoints, "durations": [0.6]})


def test_a_trajectory_quantity_is_a_global_index_of_the_mechanism_over_its_named_move(gantry):
    """The gantry's Table 3 move is a region of it: Mechanism.global_index takes a trajectory quantity by name
    over it (the value trajectory_values gives), refuses one over a region that is not a trajectory, and an
    atlas charts it (a node equals global_index there, its best design found over the fixed move)."""
    from pkm.atlas import compute_atlas
    from pkm.design_space import parameter_plane, parse_axes

    design = gantry.design()
    value = gantry.global_index("effort_peak", design, region="table3_move", mode="below", resolution=RESOLUTION)
    expected = trajectory_values(gantry, gantry.region("table3_move"), design, mode="below", names=["effort_peak"],
                                 resolution=RESOLUTION)["effort_peak"]
    assert float(value) == pytest.approx(float(expected), rel=1e-12)
    assert gantry.index_unit("effort_peak") == "N"
    with pytest.raises(PkmError, match="effort_peak is taken along a trajectory: region task is not one"):
        gantry.global_index("effort_peak", design, region="task", mode="below")
    space = parameter_plane(gantry.parameters, parse_axes("l=0.7:0.8,d1=0.2:0.3", "--axes"))
    atlas = compute_atlas(gantry, gantry.global_spec("effort_peak"), space=space, region="table3_move",
                          modes="below", resolution=3, pose_resolution=RESOLUTION, executor="serial", progress=False)
    i, j = np.argwhere(np.isfinite(atlas.values["below"]))[-1]
    node = space.designs(gantry.parameters, space.from_chart(atlas.u[i], atlas.v[j]))
    assert atlas.values["below"][i, j] == pytest.approx(float(gantry.global_index(
        "effort_peak", node, region="table3_move", mode="below", resolution=RESOLUTION)), rel=1e-12)
    assert atlas.checked["below"].found
