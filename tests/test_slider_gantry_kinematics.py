"""Slider gantry kinematics (Wu, Wang, Wang and Shao 2008 sections 3 and 4) as numbers.

The Jacobian against Wu's eqs. 3-5 and against finite differences of the inverse kinematics, the
forward kinematics against the inverse, the reachable workspace against the intersection of the two
chains' sub-workspaces (eqs. 8-9), the task rectangle Q1Q2Q3Q4 of Fig. 2, Table 1 from eqs. 10-16, and
the global velocity ratio k_av of eq. 7 against its closed form.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import pkm
from pkm.batch import evaluate
from pkm.errors import DesignError
from pkm.models.slider_gantry import wu2008
from pkm.regions import grid

DEG = math.pi / 180
m = pkm.load("slider_gantry")
VARIANTS = ("slider_gantry", "slider_gantry_symmetric")
DEFAULT = m.design()
RECTANGLE = m.task_rectangle(DEFAULT)


def random_poses(box: np.ndarray, n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(box[:, 0], box[:, 1], size=(n, 2))


def wu_angles(x: np.ndarray, design) -> tuple[np.ndarray, np.ndarray]:
    """theta_1, theta_2 of Wu's eq. 1: sin(theta_i) = (x - x_Bi) / l with x_B1 = -d1, x_B2 = d1."""
    length, d1 = design["l"], design["d1"]
    return np.arcsin((x[:, 0] + d1) / length), np.arcsin((x[:, 0] - d1) / length)


@pytest.mark.parametrize("name", VARIANTS)
def test_jacobian_rows_are_tan_theta_and_one_wu_eqs_3_to_5(name):
    mech = pkm.load(name)
    design = mech.design()
    x = random_poses(mech.task_rectangle(design).box, 200, seed=3)
    q = mech.inverse_kinematics(x, design, passive=True)
    theta1, theta2 = wu_angles(x, design)
    np.testing.assert_allclose(q[:, 2], theta1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(q[:, 3], theta2, rtol=0, atol=1e-13)
    # eq. 2 with '-': the sliders below their platform joints
    y_b = x[:, 1] - design["l2"] / 2
    np.testing.assert_allclose(q[:, 0], y_b - design["l"] * np.cos(theta1), rtol=0, atol=1e-13)
    np.testing.assert_allclose(q[:, 1], y_b - design["l"] * np.cos(theta2), rtol=0, atol=1e-13)
    ones = np.ones(len(x))
    wu_J = np.stack([np.stack([np.tan(theta1), ones], -1), np.stack([np.tan(theta2), ones], -1)], 1)
    np.testing.assert_allclose(mech.jacobian(x, design), wu_J, rtol=1e-12, atol=1e-14)
    # eq. 3: theta_i_dot = x_dot / (l cos theta_i), whatever y_dot
    theta_rates = (mech.psi(x, design) @ wu_J)[:, 2:]
    expected = np.zeros_like(theta_rates)
    expected[:, 0, 0] = 1 / (design["l"] * np.cos(theta1))
    expected[:, 1, 0] = 1 / (design["l"] * np.cos(theta2))
    np.testing.assert_allclose(theta_rates, expected, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("mode", ["below", "above"])
def test_jacobian_is_the_derivative_of_the_inverse_kinematics(mode):
    step = 1e-6
    d = DEFAULT.vector()
    x = random_poses(m.workspace_box(d), 4000, seed=7)
    # reachable in this mode and 0.05 m short of full reach (J is unbounded at |x +- d1| = l)
    far = np.abs(np.abs(x[:, :1] + [DEFAULT["d1"], -DEFAULT["d1"]]) - DEFAULT["l"]).min(axis=1) > 0.05
    x = x[m.reachable(x, DEFAULT, mode=mode) & far][:50]
    assert len(x) == 50
    plus = [m.inverse_kinematics(x + step * e, DEFAULT, mode=mode) for e in np.eye(2)]
    minus = [m.inverse_kinematics(x - step * e, DEFAULT, mode=mode) for e in np.eye(2)]
    numeric = np.stack([(p - n) / (2 * step) for p, n in zip(plus, minus, strict=True)], axis=-1)
    J = m.jacobian(x, DEFAULT, mode=mode)
    np.testing.assert_allclose(J, numeric, rtol=1e-7, atol=1e-7)
    np.testing.assert_array_equal(J[:, :, 1], 1.0)  # q_i_dot = y_dot for x_dot = 0 (Wu 3.3), both modes


def test_forward_kinematics_inverts_the_inverse_kinematics_below_up():
    x = random_poses(m.workspace_box(DEFAULT.vector()), 4000, seed=11)
    x = x[m.reachable(x, DEFAULT, mode="below")]
    assert len(x) > 1000
    q = m.inverse_kinematics(x, DEFAULT, mode="below")
    np.testing.assert_allclose(m.forward_kinematics(q, DEFAULT, assembly="up"), x, rtol=0, atol=1e-12)
    # the other assembly mode is another pose
    assert np.nanmin(np.linalg.norm(m.forward_kinematics(q, DEFAULT, assembly="down") - x, axis=1)) > 1e-3


@pytest.mark.parametrize(("mode", "sigma"), [("below", 1.0), ("above", -1.0)])
def test_reachable_workspace_is_the_intersection_of_the_chains_sub_workspaces_eqs_8_9(mode, sigma):
    d = DEFAULT
    box = m.workspace_box(d.vector())
    x, _ = grid(box, 120)
    margins = []
    for offset in (d["d1"], -d["d1"]):
        u = x[:, 0] + offset
        reach = d["l"] ** 2 - u**2
        q = x[:, 1] - d["l2"] / 2 - sigma * np.sqrt(np.clip(reach, 0, None))
        margins += [d["l"] - np.abs(u), q - d["qs"], d["ql"] - q]
    margins = np.stack(margins, axis=1)
    clear = np.abs(margins).min(axis=1) > 1e-9  # leave out the grid points on a boundary
    analytic = (margins >= 0).all(axis=1)
    np.testing.assert_array_equal(m.reachable(x[clear], d, mode=mode), analytic[clear])
    assert 0.1 < analytic.mean() < 0.9
    assert clear.mean() > 0.99


def test_default_task_rectangle_is_wus_500_by_400_mm_centred_on_x_0():
    assert RECTANGLE.width == pytest.approx(0.5, abs=1e-3)
    assert RECTANGLE.height == pytest.approx(0.4, abs=1e-3)
    assert RECTANGLE.centre[0] == 0.0
    centre, half = (v.ravel() for v in evaluate(m.functions["task_rectangle"], DEFAULT.vector()))
    np.testing.assert_allclose(RECTANGLE.box, np.stack([centre - half, centre + half], axis=1), rtol=1e-15)


def angle_and_stroke_margins(x: np.ndarray, design) -> np.ndarray:
    """Per pose: |theta_i| - theta_s, theta_l - |theta_i|, q_i - qs, ql - q_i (8 columns, mode below),
    also where a slider leaves its stroke (the generated function, not the masked public one)."""
    q, reach = evaluate(m.functions["inverse_kinematics"], x, np.ones(2), design.vector())
    q = q[:, :, 0]
    assert reach[:, :2].min() > 0  # the links reach: only the margins and strokes are in question
    angle = np.abs(q[:, 2:])
    return np.hstack(
        [angle - design["theta_s"], design["theta_l"] - angle, q[:, :2] - design["qs"], design["ql"] - q[:, :2]]
    )


def test_task_rectangle_keeps_the_angle_margins_and_strokes_and_is_tight():
    lo, hi = RECTANGLE.box.T
    axes = [np.linspace(a, b, 41) for a, b in zip(lo, hi, strict=True)]
    x = np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)
    assert m.reachable(x, DEFAULT).all()
    assert angle_and_stroke_margins(x, DEFAULT).min() > -1e-12
    # Just outside the sides a link leaves its angle margins; just below (above) the bottom (top)
    # corners Q2, Q3 (Q1, Q4) a slider leaves its stroke. (The middle of the bottom and top edges is
    # not tight: the rectangle is the largest centred one whose corners fit.)
    eps = 1e-5
    y = np.linspace(lo[1], hi[1], 21)[1:-1]
    sides = np.concatenate([np.stack([np.full_like(y, s * (hi[0] + eps)), y], 1) for s in (-1, 1)])
    corners = np.array([[s * hi[0], v] for s in (-1, 1) for v in (lo[1] - eps, hi[1] + eps)])
    margins = angle_and_stroke_margins(sides, DEFAULT)
    assert (margins[:, :4].min(axis=1) < 0).all()
    assert margins[:, 4:].min() > 0
    margins = angle_and_stroke_margins(corners, DEFAULT)
    assert (margins[:, 4:].min(axis=1) < 0).all()
    assert margins[:, :4].min() > -1e-12


DESIGN_ERRORS = [
    ({"l": 0.0}, "design parameter l = 0"),
    ({"d1": -0.1}, "design parameter d1 = -0.1"),
    ({"l2": 0.0}, "design parameter l2 = 0"),
    ({"m12": 0.0}, "design parameter m12 = 0"),
    ({"mN": -1.0}, "design parameter mN = -1"),
    ({"I12": 0.0}, "design parameter I12 = 0"),
    ({"l": 0.3}, "violates l > d1"),
    ({"l": 0.357}, "violates l > d1"),
    ({"qs": 0.5}, "violates qs < ql"),
    ({"qs": 0.6}, "violates qs < ql"),
]


@pytest.mark.parametrize(("change", "match"), DESIGN_ERRORS, ids=[str(c) for c, _ in DESIGN_ERRORS])
def test_bad_design_is_a_design_error_naming_it(change, match):
    values = {**DEFAULT, **change}
    with pytest.raises(DesignError, match=match):
        m.design(values)
    with pytest.raises(DesignError, match=match):
        m.jacobian([0.0, 0.5], values)


@pytest.mark.parametrize(
    ("width", "height", "match"),
    [
        (0.6, 0.4, "width b = 0.6 m exceeds"),
        (0.45, 0.5, "height h = 0.5 m exceeds"),
        (0.5, 0.5, "0.5 m x 0.5 m task rectangle cannot fit"),
        (0.0, 0.4, "width = 0 m violates width > 0"),
        (-0.5, 0.4, "width = -0.5 m violates width > 0"),
        (0.4, 0.0, "height = 0 m violates height > 0"),
    ],
)
def test_task_rectangle_that_cannot_fit_is_a_design_error(width, height, match):
    with pytest.raises(DesignError, match=match):
        m.fit_task(width, height)


def test_task_rectangle_that_fits_is_centred_in_the_designs():
    fitted = m.fit_task(0.4, 0.3)
    assert (fitted.centre, fitted.width, fitted.height) == (RECTANGLE.centre, 0.4, 0.3)


def test_design_without_a_task_rectangle_is_a_design_error():
    # the angle margins leave no width: d1 - l sin(theta_s) < 0
    with pytest.raises(DesignError, match="no task rectangle"):
        m.task_rectangle({**DEFAULT, "theta_s": 40 * DEG})


@pytest.mark.parametrize(
    ("b", "theta_1s", "match"),
    [
        (0.5, 0.0, "theta_1S"),
        (0.5, 45 * DEG, "theta_1S"),
        (0.5, 50 * DEG, "theta_1S"),
        (0.5, -5 * DEG, "theta_1S"),
        (0.0, 10 * DEG, "b = 0 m violates b > 0"),
        (-0.5, 10 * DEG, "b = -0.5 m violates b > 0"),
    ],
)
def test_workspace_synthesis_outside_its_domain_is_a_design_error(b, theta_1s, match):
    with pytest.raises(DesignError, match=match):
        wu2008.workspace_synthesis(b, 0.4, theta_1s)


@pytest.mark.parametrize(
    ("theta_1s", "d1_mm", "l_mm"),
    [(15, 433.0, 707.1), (10, 357.0, 616.4)],
    ids=["section 4.2", "Table 1"],
)
def test_workspace_synthesis_gives_wus_section_4_values(theta_1s, d1_mm, l_mm):
    first = wu2008.workspace_synthesis(0.5, 0.4, theta_1s * DEG)
    assert first.d1 * 1e3 == pytest.approx(d1_mm, abs=0.05)
    assert first.length * 1e3 == pytest.approx(l_mm, abs=0.05)
    assert first.stroke * 1e3 == pytest.approx(900.0, abs=0.05)
    assert first.y_d1 == pytest.approx(first.b, rel=1e-12)  # eq. 13
    assert first.theta_2l == pytest.approx(math.pi / 2 - theta_1s * DEG, rel=1e-15)
    # eqs. 10 and 11: the link angles at Q2 are theta_1S and theta_2L
    assert math.sin(first.theta_1s) == pytest.approx(first.d / first.length, rel=1e-12)
    assert math.sin(first.theta_2l) == pytest.approx((first.b + first.d) / first.length, rel=1e-12)


def test_k_av_over_the_task_rectangle_is_the_closed_form_of_eq_7():
    closed = wu2008.k_av_closed_form(DEFAULT["l"], DEFAULT["d1"], RECTANGLE.width)
    assert m.global_index("k_av", DEFAULT, region="task") == pytest.approx(closed, rel=1e-7)
    errors = [abs(m.global_index("k_av", DEFAULT, region="task", resolution=r) - closed) for r in (1, 2, 4, 8, 16)]
    assert all(b < a / 20 for a, b in itertools.pairwise(errors)), errors
    assert errors[-1] < 1e-10 * closed
    # the local index is Wu's k_v = |x_dot / q1_dot| at y_dot = 0 = cot(theta_1) (eq. 6)
    x = random_poses(RECTANGLE.box, 50, seed=6)
    theta1, _ = wu_angles(x, DEFAULT)
    np.testing.assert_allclose(m.local_index("velocity_ratio", x, DEFAULT), 1 / np.tan(theta1), rtol=1e-12)
