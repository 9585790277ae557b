"""Trajectories whose acceleration jumps: the trapezoidal speed profile of Wu 2008 (Table 3, eq. 45)
reports its switch times and the acceleration just before and just after each, exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pkm.dynamics import Trajectory
from pkm.errors import PkmError

A_MAX, V_MAX = 6.67, 1.0
TABLE_3 = Trajectory.trapezoidal([-0.25, 0.5], [0.25, 0.5], V_MAX, A_MAX)
T0 = V_MAX / A_MAX


def test_switch_times_follow_eq_45():
    assert TABLE_3.switch_times == (0.0, T0, TABLE_3.duration - T0, TABLE_3.duration)
    assert TABLE_3.duration == pytest.approx(0.5 / V_MAX + T0, rel=1e-15)  # T0 = T_f - |x1 - x0| / V_max


def test_one_sided_accelerations_at_the_switches_are_exactly_plus_minus_a_max_or_zero():
    switches = TABLE_3.switches()
    np.testing.assert_array_equal(switches.times, TABLE_3.switch_times)
    np.testing.assert_array_equal(switches.acceleration_before[:, 0], [0.0, A_MAX, 0.0, -A_MAX])
    np.testing.assert_array_equal(switches.acceleration_after[:, 0], [A_MAX, 0.0, -A_MAX, 0.0])
    np.testing.assert_array_equal(switches.acceleration_jump[:, 0], [A_MAX, -A_MAX, -A_MAX, A_MAX])
    np.testing.assert_array_equal(switches.acceleration_jump[:, 1], 0.0)  # the move is along x
    np.testing.assert_array_equal(np.abs(switches.acceleration_jump).max(axis=1), A_MAX)


def test_position_and_velocity_are_continuous_at_the_switches():
    switches = TABLE_3.switches()
    x, v, _ = TABLE_3.sample(switches.times, side="before")
    np.testing.assert_allclose(x, switches.position, rtol=0, atol=1e-15)
    np.testing.assert_allclose(v, switches.velocity, rtol=0, atol=1e-14)
    np.testing.assert_allclose(switches.velocity[:, 0], [0.0, V_MAX, V_MAX, 0.0], atol=1e-14)
    np.testing.assert_allclose(switches.position[[0, -1]], [[-0.25, 0.5], [0.25, 0.5]], atol=1e-15)


def test_sampling_at_a_switch_gives_the_value_just_after_and_before_on_request():
    times = np.array(TABLE_3.switch_times)
    switches = TABLE_3.switches()
    np.testing.assert_array_equal(TABLE_3.sample(times)[2], switches.acceleration_after)
    np.testing.assert_array_equal(TABLE_3.sample(times, side="before")[2], switches.acceleration_before)
    for step in (1e-9, 1e-5):  # the phases have constant acceleration: the limits are attained
        np.testing.assert_array_equal(TABLE_3.sample(times + step)[2], switches.acceleration_after)
        np.testing.assert_array_equal(TABLE_3.sample(times - step)[2], switches.acceleration_before)


def test_the_kink_is_not_differentiated_at_the_switches():
    # the derivative of max(u, 0)^2 at its kink gave a_max / 4 at t = 0 and 3 a_max / 4 at T0
    _, _, a = TABLE_3.sample([0.0, T0])
    assert a[0, 0] == A_MAX != A_MAX / 4
    assert a[1, 0] == 0.0 != 3 * A_MAX / 4


def test_a_short_move_is_triangular_with_one_jump_of_two_a_max():
    length = 0.5 * V_MAX**2 / A_MAX  # too short to reach v_max
    move = Trajectory.trapezoidal([0.0, 0.0], [0.0, length], V_MAX, A_MAX)
    t0 = math.sqrt(length / A_MAX)
    assert move.switch_times == (0.0, t0, 2 * t0)
    switches = move.switches()
    np.testing.assert_array_equal(switches.acceleration_jump[:, 1], [A_MAX, -2 * A_MAX, A_MAX])
    assert switches.velocity[1, 1] == pytest.approx(A_MAX * t0, rel=1e-14)
    assert A_MAX * t0 < V_MAX
    np.testing.assert_allclose(switches.position[-1], [0.0, length], atol=1e-16)


@pytest.mark.parametrize(
    "trajectory",
    [Trajectory.point_to_point([0.0, 1.3], [0.1, 1.4], 1.0), Trajectory.circle([0.0, 1.4], 0.2, 2.0)],
    ids=["point to point", "circle"],
)
def test_smooth_trajectories_have_no_switches_and_equal_sides(trajectory):
    switches = trajectory.switches()
    assert switches.times.shape == (0,)
    assert switches.acceleration_jump.shape == (0, 2)
    t = np.linspace(0.0, trajectory.duration, 7)
    for after, before in zip(trajectory.sample(t), trajectory.sample(t, side="before"), strict=True):
        np.testing.assert_array_equal(after, before)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: TABLE_3.sample([0.1], side="middle"), "side"),
        (lambda: Trajectory(TABLE_3.path, 1.0, 2, "", (0.5, 0.2), TABLE_3.path_before), "switch_times"),
        (lambda: Trajectory(TABLE_3.path, 1.0, 2, "", (0.0, 1.5), TABLE_3.path_before), "switch_times"),
        (lambda: Trajectory(TABLE_3.path, 1.0, 2, "", (0.0, math.nan), TABLE_3.path_before), "switch_times"),
        (lambda: Trajectory(TABLE_3.path, 1.0, 2, "", (0.5,)), "path_before"),
        (lambda: Trajectory.trapezoidal([0.0, 0.0], [1.0, 0.0], 1.0, 0.0), "a_max"),
    ],
)
def test_bad_input_is_a_pkm_error_naming_the_parameter(make, match):
    with pytest.raises(PkmError, match=match):
        make()
