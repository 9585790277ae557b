"""Slider gantry dynamics (Wu, Wang, Wang and Shao 2008 sections 5 and 6), each result derived twice.

The virtual-work model of eqs. 40-41 against an independent Lagrange derivation, its mass matrix
against the kinetic energy, its gravity forces against the potential energy, the actuator power
against the energy rate along Wu's Table 3 move, the partial velocity matrices against eqs. 19-26,
and the dynamic manipulability kappa_D of eq. 43 and its global indices.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from helpers import random_design as random_valid_design

import pkm
from pkm.batch import evaluate
from pkm.dynamics import Trajectory
from pkm.errors import PkmError
from pkm.reproduce import wu2008
from pkm.reproduce.wu2008 import _forces

VARIANTS = ("slider_gantry", "slider_gantry_symmetric")
MECHANISMS = {name: pkm.load(name) for name in VARIANTS}
m = MECHANISMS["slider_gantry"]
DEFAULT = m.design()
BODIES = ("slider1", "slider2", "counterweight1", "counterweight2", "link1", "link3", "link2")
MASSES = ("m11", "m21", "m12", "m22", "m13", "m23", "m4", "mN")


def bodies(mech) -> tuple[str, ...]:
    """Bodies in the order of the partial_velocities output."""
    return (*BODIES, "link4", "platform") if mech.name.endswith("symmetric") else (*BODIES, "platform")


def masses(mech) -> tuple[str, ...]:
    return (*MASSES, "m5") if mech.name.endswith("symmetric") else MASSES


def random_design(mech, rng: np.random.Generator) -> pkm.Design:
    """Every parameter within +-20 % of its default, drawn again until the design has a task rectangle."""
    return random_valid_design(mech, rng, spread=0.2, accept=mech.task_rectangle)


def task_poses(mech, design, rng: np.random.Generator, n: int) -> np.ndarray:
    box = mech.task_rectangle(design).box
    return rng.uniform(box[:, 0], box[:, 1], size=(n, 2))


def cases(n_designs: int = 4, n_poses: int = 10):
    """(mechanism, design, poses, rng): both variants, random designs and poses in their task rectangles."""
    for k, name in enumerate(VARIANTS):
        mech = MECHANISMS[name]
        rng = np.random.default_rng(2008 + k)
        for _ in range(n_designs):
            design = random_design(mech, rng)
            yield mech, design, task_poses(mech, design, rng, n_poses), rng


def joints(mech, x: np.ndarray, design) -> np.ndarray:
    q = mech.inverse_kinematics(x, design, passive=True)
    assert np.isfinite(q).all()
    return q


def test_virtual_work_equals_the_lagrange_derivation():
    checked = 0
    for mech, design, x, rng in cases():
        d = design.vector()
        x_dot = rng.normal(size=x.shape)
        x_ddot = 5 * rng.normal(size=x.shape)
        q = joints(mech, x, design)
        tau = mech.inverse_dynamics(x, x_dot, x_ddot, design)
        lagrange, M_t, _, g_t = evaluate(mech.functions["lagrange_dynamics"], q, x, x_dot, x_ddot, d)
        scale = np.abs(lagrange).max()
        np.testing.assert_allclose(tau, lagrange[:, :, 0], rtol=1e-9, atol=1e-9 * scale, err_msg=mech.name)
        # and term by term: the slider-space inertia and the gravity forces at rest
        inertia = mech.inertia_matrix(x, design, space="actuated")
        np.testing.assert_allclose(inertia, M_t, rtol=1e-9, atol=1e-9 * np.abs(M_t).max())
        _, N_rest, _ = evaluate(mech.functions["virtual_work"], q, x, np.zeros(2), d)
        np.testing.assert_allclose(N_rest, g_t, rtol=1e-9, atol=1e-9 * np.abs(g_t).max())
        checked += len(x)
    assert checked == 2 * 4 * 10


def kinetic_energy_hessian(mech) -> ca.Function:
    """(q, x, design) -> d^2 T / d x_dot^2, by CasADi's AD of the generated energy."""
    energy = mech.functions["energy"]
    q, x, x_dot = ca.MX.sym("q", 4), ca.MX.sym("x", 2), ca.MX.sym("x_dot", 2)
    d = ca.MX.sym("design", energy.numel_in(3))
    T = energy(q, x, x_dot, d)[0]
    return ca.Function("hessian_T", [q, x, x_dot, d], [ca.hessian(T, x_dot)[0]])


def test_mass_matrix_is_symmetric_positive_definite_and_the_hessian_of_the_kinetic_energy():
    for mech, design, x, rng in cases():
        d = design.vector()
        q = joints(mech, x, design)
        x_dot = rng.normal(size=x.shape)
        M = evaluate(mech.functions["virtual_work"], q, x, x_dot, d)[0]
        scale = np.abs(M).max()
        np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), rtol=0, atol=1e-12 * scale)
        assert np.linalg.eigvalsh(M).min() > 0
        np.testing.assert_allclose(mech.inertia_matrix(x, design), M, rtol=1e-14, atol=1e-12 * scale)
        (hessian,) = evaluate(kinetic_energy_hessian(mech), q, x, x_dot, d)
        np.testing.assert_allclose(hessian, M, rtol=1e-10, atol=1e-10 * scale, err_msg=mech.name)
        T, _ = evaluate(mech.functions["energy"], q, x, x_dot, d)
        np.testing.assert_allclose(T[:, 0, 0], np.einsum("ni,nij,nj->n", x_dot, M, x_dot) / 2, rtol=1e-10)


def potential_energy(mech, x: np.ndarray, design) -> np.ndarray:
    q = joints(mech, x, design)
    return evaluate(mech.functions["energy"], q, x, np.zeros(2), design.vector())[1][:, 0, 0]


def test_n_at_rest_is_the_gravity_force_of_the_potential_energy():
    step = 1e-6
    for mech, design, x, _ in cases():
        d = design.vector()
        q = joints(mech, x, design)
        _, N, n = evaluate(mech.functions["virtual_work"], q, x, np.zeros(2), d)
        gradient = np.stack(
            [
                (potential_energy(mech, x + step * e, design) - potential_energy(mech, x - step * e, design))
                / (2 * step)
                for e in np.eye(2)
            ],
            axis=1,
        )
        scale = np.abs(gradient).max()
        np.testing.assert_allclose(n[:, :, 0], gradient, rtol=0, atol=1e-8 * scale, err_msg=mech.name)
        J_T = np.swapaxes(mech.jacobian(x, design), 1, 2)
        np.testing.assert_allclose(
            N[:, :, 0], np.linalg.solve(J_T, gradient[:, :, None])[:, :, 0], rtol=0, atol=1e-8 * scale
        )
        _, N_free, _ = evaluate(
            mech.functions["virtual_work"], q, x, np.zeros(2), mech.design({**design, "g": 0.0}).vector()
        )
        np.testing.assert_array_equal(N_free, 0.0)


def test_default_counterweights_balance_the_vertical_weight():
    # Wu: each counterweight is half of the moving mass without counterweights, so V does not change
    # with y; the horizontal gravity force comes from the links' tilt.
    x = task_poses(m, DEFAULT, np.random.default_rng(4), 20)
    q = joints(m, x, DEFAULT)
    _, _, n = evaluate(m.functions["virtual_work"], q, x, np.zeros(2), DEFAULT.vector())
    np.testing.assert_allclose(n[:, 1, 0], 0.0, atol=1e-9)
    assert np.abs(n[:, 0, 0]).min() > 1.0


def test_m_yy_is_the_total_mass_and_m_does_not_depend_on_y():
    for mech, design, x, rng in cases():
        M = mech.inertia_matrix(x, design)
        total = sum(design[k] for k in masses(mech))
        np.testing.assert_allclose(M[:, 1, 1], total, rtol=1e-13)
        box = mech.task_rectangle(design).box
        moved = np.stack([x[:, 0], rng.uniform(*box[1], size=len(x))], axis=1)
        np.testing.assert_allclose(mech.inertia_matrix(moved, design), M, rtol=1e-13, atol=1e-10)


TABLE_3 = Trajectory.trapezoidal([-0.25, 0.5], [0.25, 0.5], 1.0, 6.67)
SMOOTH = Trajectory.point_to_point([-0.2, 0.4], [0.2, 0.65], 0.8)


def power_and_energy(mech, design, trajectory: Trajectory, t: np.ndarray):
    """Actuator power tau . q_a_dot and total energy T + V at the times t."""
    x, x_dot, x_ddot = trajectory.sample(t)
    q = joints(mech, x, design)
    tau = mech.inverse_dynamics(x, x_dot, x_ddot, design)
    q_a_dot = np.einsum("nij,nj->ni", mech.jacobian(x, design), x_dot)
    T, V = evaluate(mech.functions["energy"], q, x, x_dot, design.vector())
    return (tau * q_a_dot).sum(axis=1), T[:, 0, 0] + V[:, 0, 0]


def energy_rate(mech, design, trajectory: Trajectory, t: np.ndarray, step: float) -> np.ndarray:
    _, plus = power_and_energy(mech, design, trajectory, t + step)
    _, minus = power_and_energy(mech, design, trajectory, t - step)
    return (plus - minus) / (2 * step)


@pytest.mark.parametrize("name", VARIANTS)
@pytest.mark.parametrize("trajectory", [TABLE_3, SMOOTH], ids=["Wu Table 3 trapezoid", "point to point"])
def test_actuator_power_is_the_rate_of_the_total_energy(name, trajectory):
    mech = MECHANISMS[name]
    design = mech.design()
    step = 2e-6
    t = np.linspace(0.0, trajectory.duration, 66)[1:-1]
    t = t[np.abs(t[:, None] - np.array(TABLE_3.switch_times)).min(axis=1) > 10 * step]
    power, _ = power_and_energy(mech, design, trajectory, t)
    scale = np.abs(power).max()
    assert scale > 1e3  # some kW
    np.testing.assert_allclose(power, energy_rate(mech, design, trajectory, t, step), rtol=0, atol=1e-8 * scale)


@pytest.mark.parametrize("name", VARIANTS)
def test_work_of_the_table_3_move_is_the_change_of_potential_energy(name):
    mech = MECHANISMS[name]
    design = mech.design()
    t0, total = 1.0 / 6.67, TABLE_3.duration
    assert total == pytest.approx(0.5 + t0, rel=1e-12)  # Wu eq. 45: T0 = T_f - |q1 - q0| / V_max
    nodes, weights = np.polynomial.legendre.leggauss(20)
    work = effort = 0.0
    for a, b in ((0.0, t0), (t0, total - t0), (total - t0, total)):  # Gauss-Legendre on each smooth phase
        power, _ = power_and_energy(mech, design, TABLE_3, (a + b) / 2 + (b - a) / 2 * nodes)
        work += (b - a) / 2 * weights @ power
        effort += (b - a) / 2 * weights @ np.abs(power)
    _, energy = power_and_energy(mech, design, TABLE_3, np.array([0.0, total]))
    assert effort > 100.0  # J
    assert work == pytest.approx(energy[1] - energy[0], abs=1e-10 * effort)
    if name == "slider_gantry":
        assert energy[1] - energy[0] > 10.0  # J: the asymmetric machine ends higher in potential energy
    else:
        assert abs(energy[1] - energy[0]) < 1e-10 * effort  # the move is mirror symmetric


@pytest.mark.parametrize("name", VARIANTS)
def test_force_jumps_at_the_switches_are_the_inertia_times_the_acceleration_jump(name):
    # eq. 41: x and x_dot are continuous at a switch, N with them, so tau jumps by (J^T)^-1 M times
    # the acceleration jump; the one-sided forces are the limits of the inverse dynamics at t_k -+ eps
    mech = MECHANISMS[name]
    switches = TABLE_3.switches()
    before = mech.inverse_dynamics(switches.position, switches.velocity, switches.acceleration_before)
    after = mech.inverse_dynamics(switches.position, switches.velocity, switches.acceleration_after)
    mixed = mech.inertia_matrix(switches.position, space="mixed")
    scale = np.abs(after - before).max()
    assert scale > 2e4  # N: the end switches carry a link at 80 deg
    np.testing.assert_allclose(
        after - before, np.einsum("kij,kj->ki", mixed, switches.acceleration_jump), rtol=0, atol=1e-12 * scale
    )
    errors = []
    for eps in (1e-5, 1e-6):
        limits = [mech.inverse_dynamics(*TABLE_3.sample(switches.times + s * eps)) for s in (-1, 1)]
        np.testing.assert_allclose(limits[0], before, rtol=0, atol=eps * 1e6)
        np.testing.assert_allclose(limits[1], after, rtol=0, atol=eps * 1e6)
        errors.append(np.abs(limits[1] - limits[0] - (after - before)).max())
    assert errors[1] < errors[0] / 5  # the one-sided values are the limits, not values near them


def test_wu_fig4_reports_the_force_jumps_of_the_one_sided_limits(tmp_path):
    forces, _ = _forces(m, tmp_path / "fig4.png", 40)
    switches = TABLE_3.switches()
    np.testing.assert_array_equal(forces["switch_times_s"], switches.times)
    np.testing.assert_array_equal(forces["acceleration_jump_m_s2"], [6.67, -6.67, -6.67, 6.67])
    eps = 1e-7
    limits = [m.inverse_dynamics(*TABLE_3.sample(switches.times + s * eps)) for s in (-1, 1)]
    jumps = np.array(forces["force_jumps_N"])
    np.testing.assert_allclose(jumps, limits[1] - limits[0], rtol=0, atol=1e-6 * np.abs(jumps).max())
    np.testing.assert_allclose(forces["jump_at_switches_N"], np.abs(jumps).max(axis=1), rtol=1e-15)
    # sampled at a switch, the force is the one just after (the derivative at the kink of the ramp gave
    # a_max / 4 at t = 0, and a reported jump there of three quarters of the limits' difference)
    np.testing.assert_allclose(m.inverse_dynamics(*TABLE_3.sample([0.0]))[0], forces["forces_after_N"][0], rtol=1e-14)
    assert forces["force_jump_identity_residual_N"] < 1e-9 * np.abs(jumps).max()


def test_wu_report_values_are_pkms_model(tmp_path):
    values = wu2008.run(tmp_path, quick=True)["values"]
    symmetric = MECHANISMS["slider_gantry_symmetric"]
    assert values["fig7_M_yy_kg"] == pytest.approx(sum(symmetric.design()[k] for k in masses(symmetric)))
    assert values["fig7_M_yy_kg"] == pytest.approx(2112.0)  # not the 2004 kg the docs once gave
    centre = [0.0, m.task_rectangle().centre[1]]
    assert values["fig6_kappa_d_centre"] == pytest.approx(float(m.local_index("kappa_d", centre)), rel=1e-14)
    assert values["fig6_kappa_d_centre"] < values["fig6_kappa_d_min"] * 1.03
    box = m.task_rectangle().box
    edges = m.local_index("kappa_d", [[box[0, 0], centre[1]], [box[0, 1], centre[1]]])
    assert (values["fig6_kappa_d_left_edge"], values["fig6_kappa_d_right_edge"]) == pytest.approx(edges, rel=1e-12)
    M_d = symmetric.inertia_matrix(centre, space="mixed")
    easiest_x = 1e3 / np.linalg.norm(M_d @ [1.0, 0.0])
    easiest_y = 1e3 / np.linalg.norm(M_d @ [0.0, 1.0])
    assert values["fig7_acceleration_along_x_per_kN_m_s2"] == pytest.approx(easiest_x, rel=1e-12)
    assert values["fig7_acceleration_along_y_per_kN_m_s2"] == pytest.approx(easiest_y, rel=1e-12)
    assert values["fig4_force_jump_max_N"] == max(
        values[f"fig4_force_jump_{k}_N"] for k in ("start", "end_of_acceleration", "start_of_deceleration", "end")
    )
    assert all(isinstance(v, float) for v in values.values())


@pytest.mark.parametrize("name", VARIANTS)
def test_partial_velocities_are_wus_eqs_19_to_26(name):
    mech = MECHANISMS[name]
    rng = np.random.default_rng(19)
    design = random_design(mech, rng)
    x = task_poses(mech, design, rng, 30)
    q = joints(mech, x, design)
    H, G = evaluate(mech.functions["partial_velocities"], q, x, design.vector())
    names = bodies(mech)
    H = {b: H[:, 2 * k : 2 * k + 2] for k, b in enumerate(names)}
    G = {b: G[:, k : k + 1] for k, b in enumerate(names)}
    J = mech.jacobian(x, design)
    e_y = np.array([[0.0], [1.0]])
    zero = np.zeros((len(x), 1, 2))
    for i in (1, 2):
        J_i = J[:, i - 1 : i]
        link = f"link{i}"
        np.testing.assert_allclose(H[f"slider{i}"], e_y @ J_i, atol=1e-14)  # eq. 20
        np.testing.assert_allclose(H[link], H[f"slider{i}"], atol=1e-14)  # eq. 22: links pivot at B_i
        np.testing.assert_allclose(H[f"counterweight{i}"], -e_y @ J_i, atol=1e-14)  # eq. 23
        np.testing.assert_array_equal(G[f"slider{i}"], zero)  # eq. 19
        np.testing.assert_array_equal(G[f"counterweight{i}"], zero)
        # eq. 3 and Wu's G_i2 of eq. 21: theta_i_dot = x_dot / (l cos theta_i); pkm's angle is the
        # counter-clockwise phi = pi/2 - theta, hence the sign
        l_cos = design["l"] * np.cos(q[:, 1 + i])
        np.testing.assert_allclose(G[link][:, 0], np.stack([-1 / l_cos, 0 * l_cos], axis=1), rtol=1e-13)
    for extra, copied in (("link3", "link1"), ("link4", "link2")):  # eq. 24 and Wu section 6.3
        if extra in names:
            np.testing.assert_allclose(H[extra], H[copied], atol=1e-14)
            np.testing.assert_allclose(G[extra], G[copied], rtol=1e-14)
    np.testing.assert_array_equal(G["platform"], zero)  # eq. 25
    np.testing.assert_array_equal(H["platform"], np.broadcast_to(np.eye(2), (len(x), 2, 2)))  # eq. 26


def kappa_grid(mech, n: int = 21) -> np.ndarray:
    box = mech.task_rectangle().box
    axes = [np.linspace(lo, hi, n) for lo, hi in box]
    return np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)


@pytest.mark.parametrize("name", VARIANTS)
def test_kappa_d_is_the_condition_number_of_wus_inertia_matrix_and_independent_of_y(name):
    mech = MECHANISMS[name]
    x = kappa_grid(mech)
    kappa = mech.local_index("kappa_d", x)
    assert kappa.min() >= 1.0
    np.testing.assert_allclose(kappa, np.linalg.cond(mech.inertia_matrix(x, space="mixed")), rtol=1e-10)
    per_x = kappa.reshape(21, 21)  # rows: x, columns: y
    np.testing.assert_allclose(per_x, per_x[:, :1].repeat(21, axis=1), rtol=1e-12)


def test_kappa_d_is_mirror_symmetric_only_for_the_symmetric_variant():
    symmetric = MECHANISMS["slider_gantry_symmetric"]
    x = kappa_grid(symmetric)
    mirrored = x * [-1.0, 1.0]
    np.testing.assert_allclose(
        symmetric.local_index("kappa_d", x), symmetric.local_index("kappa_d", mirrored), rtol=1e-10
    )
    difference = np.abs(m.local_index("kappa_d", x) - m.local_index("kappa_d", mirrored))
    assert difference.max() > 0.05  # Wu section 6.3: eta_D of Fig. 6 is not symmetric about the y axis


@pytest.mark.parametrize("name", VARIANTS)
def test_inertia_matrix_spaces(name):
    mech = MECHANISMS[name]
    rng = np.random.default_rng(42)
    design = random_design(mech, rng)
    x = task_poses(mech, design, rng, 20)
    task = mech.inertia_matrix(x, design, space="task")
    J = mech.jacobian(x, design)
    J_T_inv = np.linalg.inv(np.swapaxes(J, 1, 2))
    np.testing.assert_allclose(mech.inertia_matrix(x, design, space="mixed"), J_T_inv @ task, rtol=1e-10)
    actuated = mech.inertia_matrix(x, design, space="actuated")
    np.testing.assert_allclose(actuated, J_T_inv @ task @ np.linalg.inv(J), rtol=1e-10)
    np.testing.assert_allclose(actuated, np.swapaxes(actuated, 1, 2), rtol=1e-12)


def test_mixed_inertia_of_a_lagrange_model_is_a_pkm_error():
    with pytest.raises(PkmError, match="mixed"):
        pkm.load("five_bar").inertia_matrix([0.0, 1.6], space="mixed")


def test_inverse_dynamics_batches_and_nan_out_of_reach():
    rng = np.random.default_rng(8)
    x = task_poses(m, DEFAULT, rng, 5)
    x_dot, x_ddot = rng.normal(size=(2, 5, 2))
    batch = m.inverse_dynamics(x, x_dot, x_ddot)
    assert batch.shape == (5, 2)
    single = m.inverse_dynamics(x[2], x_dot[2], x_ddot[2])
    assert single.shape == (2,)
    np.testing.assert_allclose(single, batch[2], rtol=1e-14)
    shared = m.inverse_dynamics(x, x_dot[0], x_ddot[0])
    assert shared.shape == (5, 2)
    np.testing.assert_allclose(shared[0], batch[0], rtol=1e-14)
    out = m.inverse_dynamics(np.array([x[0], [0.0, 3.0]]), x_dot[0], x_ddot[0])  # y = 3 m: beyond the strokes
    np.testing.assert_allclose(out[0], batch[0], rtol=1e-14)
    assert np.isnan(out[1]).all()
    assert np.isnan(m.inertia_matrix([0.0, 3.0], space="mixed")).all()


@pytest.mark.parametrize("name", ["kappa_d_mean", "kappa_d_std", "k_av"])
def test_global_index_gradient_over_the_task_rectangle_matches_central_differences(name):
    design = dict(DEFAULT)
    value, gradient = m.global_index(name, design, region="task", gradient=True)
    assert value == pytest.approx(m.global_index(name, design, region="task"), rel=1e-14)
    # The default design lies 3.6e-5 m in d1 (6.2e-5 m in l) from a kink of the rectangle's half width
    # min(l sin(theta_l) - d1, d1 - l sin(theta_s)): the steps stay well short of it.
    for parameter in ("l", "d1", "mN"):
        step = 1e-6 * max(1.0, design[parameter])
        plus, minus = ({**design, parameter: design[parameter] + s * step} for s in (1, -1))
        numeric = (m.global_index(name, plus, region="task") - m.global_index(name, minus, region="task")) / (2 * step)
        assert gradient[parameter] == pytest.approx(numeric, rel=1e-6, abs=1e-12), parameter
    assert abs(gradient["l"]) > 0.1
    assert abs(gradient["d1"]) > 0.1
    if name == "k_av":
        assert gradient["mN"] == 0.0  # kinematic


def test_kappa_d_mean_over_the_task_rectangle_converges_with_resolution():
    values = [m.global_index("kappa_d_mean", region="task", resolution=r) for r in (1, 2, 4, 8, 16)]
    differences = np.abs(np.diff(values))
    assert np.all(differences[1:] < differences[:-1] / 3), differences
    assert differences[-1] < 1e-4 * values[-1]
    assert 1.0 < values[-1] < 2.0
