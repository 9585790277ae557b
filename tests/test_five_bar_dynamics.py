"""Five-bar dynamics (Lara-Molina 2016 section II.B, eqs. 13-31 and 37), each result derived twice.

M_t against the kinetic energy of the bodies, the chain matrices against the paper's eq. 21, the
projected Coriolis matrix against the skew-symmetry of M_t_dot - 2 C_t (which the paper's C_t fails),
inverse against forward dynamics, the simulation against conservation of energy, the natural
frequencies against the eigenvalues of S_e, and rigid inverse dynamics against the energy rate.
"""

from __future__ import annotations

import math
from typing import ClassVar

import casadi as ca
import numpy as np
import pytest
from helpers import random_design as random_geometry
from helpers import reachable_poses

import pkm
from pkm.batch import evaluate
from pkm.dynamics import Trajectory, energy, flexible_inverse_dynamics
from pkm.errors import ComputationError, DesignError, PkmError, PoseError
from pkm.kinematics import FunctionTable
from pkm.mechanism import Mechanism

m = pkm.load("five_bar")
GEOMETRY = {"r1": 1.2, "r2": 1.0, "r3": 0.8}
CENTRE = np.array([0.0, 1.6])  # the MIC centre of the default geometry (out_out), 0.41 from its boundary
MAX_CONDITION = 30.0  # cond(J): away from serial (J unbounded) and parallel (J singular) singularities
SEEDS = (0, 1, 2)


def random_design(rng: np.random.Generator) -> pkm.Design:
    """Geometry within 15 % of the default, any positive inertia, stiffness and friction."""
    geometry = random_geometry(m, rng, spread=0.15, names=GEOMETRY)
    values = {k: geometry[k] for k in GEOMETRY}
    values |= {
        "m1": rng.uniform(0.5, 2.0),
        "m2": rng.uniform(0.5, 2.0),
        "c1": rng.uniform(0.3, 0.7),
        "c2": rng.uniform(0.3, 0.7),
        "g1": rng.uniform(0.05, 0.15),
        "g2": rng.uniform(0.05, 0.15),
        "k1": rng.uniform(5.0, 50.0),
        "k2": rng.uniform(5.0, 50.0),
        "j1": rng.uniform(0.1, 1.0),
        "j2": rng.uniform(0.1, 1.0),
        "fv": rng.uniform(0.0, 0.5),
        "fc": rng.uniform(0.0, 0.5),
        "vm": rng.uniform(0.0, 0.5),
    }
    return m.design(values)


def regular_poses(design: pkm.Design, mode: str, rng: np.random.Generator, n: int = 8) -> np.ndarray:
    """Reachable poses of the mode with cond(J) < MAX_CONDITION."""
    return reachable_poses(
        m, design, mode, rng, count=n, draws=400,
        where=lambda x: np.linalg.cond(m.jacobian(x, design, mode=mode)) < MAX_CONDITION,
    )


def cases():
    for seed in SEEDS:
        rng = np.random.default_rng(seed)
        design = random_design(rng)
        for mode in m.modes:
            yield design, mode, regular_poses(design, mode, rng), rng


def matching_assemblies(theta_a: np.ndarray, x: np.ndarray, design: pkm.Design) -> list[str]:
    """Per pose, the assembly mode in which the forward kinematics of theta_a gives back x."""
    errors = np.stack(
        [np.linalg.norm(m.forward_kinematics(theta_a, design, assembly=a) - x, axis=-1) for a in m.assemblies], axis=-1
    )
    errors = np.atleast_2d(np.where(np.isnan(errors), np.inf, errors))
    assert errors.min(axis=1).max() < 1e-9
    return [m.assemblies[k] for k in errors.argmin(axis=1)]


def bodies(q: np.ndarray, d: np.ndarray):
    """(mass, inertia about the centre, centre (N, 2), angle (N,)) of the four links, from q directly."""
    r1, r2, r3, m1, m2, c1, c2, g1, g2 = d[:9]
    out = []
    for base, theta, phi in ((-r3, q[:, 0], q[:, 2]), (r3, q[:, 1], q[:, 3])):
        e_theta = np.stack([np.cos(theta), np.sin(theta)], axis=1)
        e_phi = np.stack([np.cos(phi), np.sin(phi)], axis=1)
        elbow = np.array([base, 0.0]) + r1 * e_theta
        out.append((m1, g1 * m1 * r1**2, np.array([base, 0.0]) + c1 * r1 * e_theta, theta))
        out.append((m2, g2 * m2 * r2**2, elbow + c2 * r2 * e_phi, phi))
    return out


def test_actuated_inertia_equals_the_kinetic_energy_of_the_bodies():
    step = 1e-6
    fk = m.functions["forward_kinematics"]
    checked = 0
    for design, mode, x, rng in cases():
        d = design.vector()
        theta_a = m.inverse_kinematics(x, design, mode=mode)
        rate = rng.normal(size=theta_a.shape)
        signs = np.array([m.assembly_mode(a).signs for a in matching_assemblies(theta_a, x, design)])
        (_, q_plus, _), (_, q_minus, _) = (evaluate(fk, theta_a + s * step * rate, signs, d) for s in (1, -1))
        kinetic = 0.0
        for (mass, inertia, c_plus, a_plus), (_, _, c_minus, a_minus) in zip(
            bodies(q_plus[:, :, 0], d), bodies(q_minus[:, :, 0], d), strict=True
        ):
            velocity = (c_plus - c_minus) / (2 * step)
            omega = (np.mod(a_plus - a_minus + np.pi, 2 * np.pi) - np.pi) / (2 * step)
            kinetic = kinetic + mass * (velocity**2).sum(axis=1) / 2 + inertia * omega**2 / 2
        M_t = m.inertia_matrix(x, design, mode=mode, space="actuated")
        np.testing.assert_allclose(np.einsum("ni,nij,nj->n", rate, M_t, rate) / 2, kinetic, rtol=1e-7)
        checked += len(x)
    assert checked == len(SEEDS) * len(m.modes) * 8


@pytest.mark.parametrize("slender", [True, False], ids=["slender bars", "any links"])
def test_joint_dynamics_are_the_papers_eq_21(slender):
    rng = np.random.default_rng(21)
    design = m.design(GEOMETRY) if slender else random_design(rng)
    r1, r2, _, m1, m2, c1, c2, g1, g2 = design.vector()[:9]
    n = 50
    q = rng.uniform(-np.pi, np.pi, size=(n, 4))
    q_dot = rng.normal(size=(n, 4))
    M, C = evaluate(m.functions["joint_dynamics"], q, q_dot, design.vector())
    d1, d2 = c1 * r1, c2 * r2  # the paper's d_1i = r1/2, d_2i = r2/2 for slender bars
    alpha = g1 * m1 * r1**2 + m1 * d1**2 + m2 * r1**2
    beta = g2 * m2 * r2**2 + m2 * d2**2
    gamma = m2 * r1 * d2
    if slender:
        assert (alpha, beta, gamma) == pytest.approx((m1 * r1**2 / 3 + m2 * r1**2, m2 * r2**2 / 3, m2 * r1 * r2 / 2))
    paper_M = np.zeros((n, 4, 4))
    paper_C = np.zeros((n, 4, 4))
    for i in range(2):
        a, p = i, i + 2
        c_ap, s_ap = np.cos(q[:, a] - q[:, p]), np.sin(q[:, a] - q[:, p])
        paper_M[:, a, a], paper_M[:, p, p] = alpha, beta
        paper_M[:, a, p] = paper_M[:, p, a] = gamma * c_ap
        paper_C[:, a, p] = gamma * q_dot[:, p] * s_ap
        paper_C[:, p, a] = -gamma * q_dot[:, a] * s_ap
    np.testing.assert_allclose(M, paper_M, rtol=0, atol=1e-13)
    np.testing.assert_allclose(C, paper_C, rtol=0, atol=1e-13)


def assert_symmetric_positive_definite(A: np.ndarray, what: str) -> None:
    scale = np.abs(A).max(axis=(1, 2), keepdims=True)
    np.testing.assert_allclose(A, np.swapaxes(A, 1, 2), rtol=0, atol=1e-12 * scale.max(), err_msg=what)
    assert np.linalg.eigvalsh(A).min(axis=1).min() > 0, what


def test_inertia_matrices_are_symmetric_positive_definite():
    for design, mode, x, _ in cases():
        d = design.vector()
        q = m.inverse_kinematics(x, design, mode=mode, passive=True)
        M, _ = evaluate(m.functions["joint_dynamics"], q, np.zeros(4), d)
        M_T, *_ = evaluate(m.functions["elastic_dynamics"], q, x, np.zeros(4), d)
        for name, A in (
            ("M", M),
            ("M_t", m.inertia_matrix(x, design, mode=mode, space="actuated")),
            ("M_w", m.inertia_matrix(x, design, mode=mode)),
            ("M_T", M_T),
        ):
            assert_symmetric_positive_definite(A, f"{name}, mode {mode}")


def skew_defect(M_t_dot: np.ndarray, C: np.ndarray) -> float:
    """Largest |N + N^T| / (|M_t_dot| + 2 |C|) over the batch, N = M_t_dot - 2 C (Frobenius norms)."""
    N = M_t_dot - 2 * C
    scale = np.linalg.norm(M_t_dot, axis=(1, 2)) + 2 * np.linalg.norm(C, axis=(1, 2))
    return float((np.linalg.norm(N + np.swapaxes(N, 1, 2), axis=(1, 2)) / scale).max())


def test_m_t_dot_minus_2_c_t_is_skew_only_with_the_psi_dot_term():
    step = 1e-6
    correct, paper = [], []
    for design, mode, x, rng in cases():
        d = design.vector()
        x_dot = rng.normal(size=x.shape)
        q = m.inverse_kinematics(x, design, mode=mode, passive=True)
        rate = np.einsum("nij,nj->ni", m.jacobian(x, design, mode=mode), x_dot)
        C_t, C_t_paper, *_ = evaluate(m.functions["actuated_dynamics"], q, x, rate, d)[1:]
        plus, minus = (m.inertia_matrix(x + s * step * x_dot, design, mode=mode, space="actuated") for s in (1, -1))
        M_t_dot = (plus - minus) / (2 * step)
        correct.append(skew_defect(M_t_dot, C_t))
        paper.append(skew_defect(M_t_dot, C_t_paper))
    assert max(correct) < 1e-7
    assert min(paper) > 0.5


STIFF = {**GEOMETRY, "k1": 40.0, "k2": 60.0, "j1": 0.3, "j2": 0.5}
SOFT = {**GEOMETRY, "k1": 1.0, "k2": 1.0}
TRAJECTORIES = {
    "point to point": Trajectory.point_to_point(CENTRE - np.array([0.15, 0.1]), CENTRE + np.array([0.2, 0.1]), 1.5),
    "circle": Trajectory.circle(CENTRE, 0.2, 2.0),
}


@pytest.mark.parametrize("name", TRAJECTORIES)
@pytest.mark.parametrize(
    "design", [SOFT, {**STIFF, "fv": 0.3, "vm": 0.2}], ids=["soft, no friction", "stiff, viscous friction"]
)
def test_flexible_inverse_then_forward_dynamics_returns_the_trajectory(name, design):
    trajectory = TRAJECTORIES[name]
    times = np.linspace(0.0, trajectory.duration, 31)
    motion = flexible_inverse_dynamics(m, trajectory, times, design, mode="out_out")
    np.testing.assert_allclose(motion.x, trajectory.position(times), atol=1e-14)
    np.testing.assert_allclose(motion.theta_a, m.inverse_kinematics(motion.x, design, mode="out_out"), atol=1e-12)
    deflection = motion.theta_m - motion.theta_a
    assert np.abs(deflection).max() > 1e-2  # the springs carry the load: theta_m differs from theta_a
    sim = m.simulate(
        design,
        z0=motion.z[0],
        z_dot0=motion.z_dot[0],
        times=times,
        torque=motion.torque,
        assembly=motion.assembly,
    )
    np.testing.assert_allclose(sim.z[:, :2], motion.theta_a, rtol=0, atol=1e-6)
    np.testing.assert_allclose(sim.x, motion.x, rtol=0, atol=1e-6)
    np.testing.assert_allclose(sim.z[:, 2:], motion.theta_m, rtol=0, atol=1e-6)


def test_flexible_inverse_dynamics_transmit_the_rigid_joint_torques_and_tend_to_the_rigid_motor_torques():
    trajectory = TRAJECTORIES["circle"]
    times = np.linspace(0.0, trajectory.duration, 13)
    x, x_dot, x_ddot = trajectory.sample(times)
    design = {**STIFF, "fv": 0.3, "vm": 0.2}
    motion = flexible_inverse_dynamics(m, trajectory, times, design)
    np.testing.assert_allclose(
        motion.theta_a_dot, np.einsum("nij,nj->ni", m.jacobian(x, design), x_dot), rtol=1e-12, atol=1e-12
    )
    spring = np.array([design["k1"], design["k2"]]) * (motion.theta_m - motion.theta_a)
    tau_a = m.inverse_dynamics(x, x_dot, x_ddot, design, joint_torques=True)
    np.testing.assert_allclose(spring, tau_a, rtol=0, atol=1e-10 * np.abs(tau_a).max())
    rigid = {**design, "k1": 1e7, "k2": 1e7}
    tau_m = m.inverse_dynamics(x, x_dot, x_ddot, rigid)
    flexible = flexible_inverse_dynamics(m, trajectory, times, rigid).tau_m
    assert np.abs(flexible - tau_m).max() < 1e-5 * np.abs(tau_m).max()
    assert np.abs(motion.tau_m - tau_m).max() > 1e-2 * np.abs(tau_m).max()


def test_point_to_point_is_at_rest_to_the_fourth_derivative_at_both_ends():
    trajectory = TRAJECTORIES["point to point"]
    t = ca.SX.sym("t")
    x = trajectory.position(t)
    derivatives = []
    for _ in range(4):
        x = ca.jacobian(x, t)
        derivatives.append(x)
    ends = ca.Function("ends", [t], derivatives)
    for end in (0.0, trajectory.duration):
        for value in ends(end):
            np.testing.assert_allclose(np.asarray(value), 0.0, atol=1e-12)
    motion = flexible_inverse_dynamics(m, trajectory, [0.0, trajectory.duration], STIFF)
    np.testing.assert_allclose(motion.tau_m, 0.0, atol=1e-10)
    np.testing.assert_allclose(motion.theta_m, motion.theta_a, atol=1e-12)


def test_energy_is_conserved_in_a_free_undamped_motion():
    design = {**GEOMETRY, "k1": 10.0, "k2": 25.0}
    theta_a = m.inverse_kinematics(CENTRE, design, mode="out_out")
    z0 = np.concatenate([theta_a, theta_a + np.array([0.05, -0.03])])
    z_dot0 = np.array([0.1, 0.05, -0.1, -0.1])
    (assembly,) = matching_assemblies(theta_a, CENTRE, m.design(design))
    sim = m.simulate(design, z0=z0, z_dot0=z_dot0, times=np.linspace(0.0, 3.0, 61), assembly=assembly)
    E = energy(m, sim.z, sim.z_dot, design, assembly=assembly)
    assert np.abs(sim.x - CENTRE).max() > 0.05  # the mechanism moves
    assert np.abs(E - E[0]).max() / E[0] < 1e-7
    with_friction = m.simulate(
        {**design, "fv": 0.2, "vm": 0.1}, z0=z0, z_dot0=z_dot0, times=[0.0, 3.0], assembly=assembly
    )
    dissipated = energy(m, with_friction.z, with_friction.z_dot, design, assembly=assembly)
    assert dissipated[1] < 0.9 * dissipated[0]


def test_natural_frequencies_are_two_rigid_modes_and_the_roots_of_eig_s_e():
    for design, mode, x, _ in cases():
        d = design.vector()
        result = m.natural_frequencies(x, design, mode=mode)
        assert result.frequencies.shape == (len(x), 4)
        assert result.shapes.shape == (len(x), 4, 4)
        np.testing.assert_array_equal(result.rigid, np.tile([True, True, False, False], (len(x), 1)))
        np.testing.assert_array_equal(result.frequencies[:, :2], 0.0)
        rigid_shapes = result.shapes[:, :, :2]
        np.testing.assert_allclose(rigid_shapes[:, :2], rigid_shapes[:, 2:], atol=1e-10)  # theta_a = theta_m
        q = m.inverse_kinematics(x, design, mode=mode, passive=True)
        _, _, S_e = evaluate(m.functions["inertia"], q, x, d)
        np.testing.assert_allclose(result.frequencies[:, 2:], np.sqrt(np.linalg.eigvalsh(S_e)), rtol=1e-10)
        np.testing.assert_allclose(result.lowest_elastic, result.frequencies[:, 2])
        M_T, _, K_T, _ = evaluate(m.functions["elastic_dynamics"], q, x, np.zeros(4), d)
        phi = result.shapes
        np.testing.assert_allclose(
            np.swapaxes(phi, 1, 2) @ M_T @ phi, np.broadcast_to(np.eye(4), M_T.shape), atol=1e-10
        )
        np.testing.assert_allclose(
            K_T @ phi, M_T @ phi * result.frequencies[:, None, :] ** 2, atol=1e-9 * np.abs(K_T).max()
        )


def test_rigid_inverse_dynamics_supply_the_kinetic_energy_rate_and_the_friction_power():
    design = m.design({**STIFF, "fv": 0.3, "fc": 0.2, "vm": 0.4})
    j1, j2, fv, fc, vm = (design[k] for k in ("j1", "j2", "fv", "fc", "vm"))
    trajectory = TRAJECTORIES["circle"]
    times = np.linspace(0.1, 1.9, 19)
    step = 1e-4

    def rates_and_kinetic_energy(t):
        x, x_dot, _ = trajectory.sample(t)
        rate = np.einsum("nij,nj->ni", m.jacobian(x, design, mode="out_out"), x_dot)
        M_t = m.inertia_matrix(x, design, mode="out_out", space="actuated")
        links = np.einsum("ni,nij,nj->n", rate, M_t, rate) / 2
        return rate, links, links + (j1 * rate[:, 0] ** 2 + j2 * rate[:, 1] ** 2) / 2

    rate, _, _ = rates_and_kinetic_energy(times)
    _, links_plus, total_plus = rates_and_kinetic_energy(times + step)
    _, links_minus, total_minus = rates_and_kinetic_energy(times - step)
    x, x_dot, x_ddot = trajectory.sample(times)
    joint_friction = (fv * rate**2 + fc * np.abs(rate)).sum(axis=1)
    tau_m = m.inverse_dynamics(x, x_dot, x_ddot, design, mode="out_out")
    tau_a = m.inverse_dynamics(x, x_dot, x_ddot, design, mode="out_out", joint_torques=True)
    motor_power = (tau_m * rate).sum(axis=1)
    joint_power = (tau_a * rate).sum(axis=1)
    scale = np.abs(motor_power).max()
    np.testing.assert_allclose(
        motor_power,
        (total_plus - total_minus) / (2 * step) + joint_friction + vm * (rate**2).sum(axis=1),
        rtol=0,
        atol=1e-7 * scale,
    )
    np.testing.assert_allclose(joint_power, (links_plus - links_minus) / (2 * step) + joint_friction, atol=1e-7 * scale)


def test_single_poses_give_unbatched_results_equal_to_the_batch():
    rng = np.random.default_rng(5)
    design = random_design(rng)
    x = regular_poses(design, "out_in", rng, n=3)
    x_dot, x_ddot = rng.normal(size=(2, 3, 2))
    batch = m.inverse_dynamics(x, x_dot, x_ddot, design, mode="out_in")
    frequencies = m.natural_frequencies(x, design, mode="out_in")
    for k in range(3):
        single = m.inverse_dynamics(x[k], x_dot[k], x_ddot[k], design, mode="out_in")
        assert single.shape == (2,)
        np.testing.assert_allclose(single, batch[k], rtol=1e-14)
        one = m.natural_frequencies(x[k], design, mode="out_in")
        assert one.frequencies.shape == (4,)
        assert one.lowest_elastic.shape == ()
        np.testing.assert_allclose(one.frequencies, frequencies.frequencies[k], rtol=1e-12)
        assert m.inertia_matrix(x[k], design, mode="out_in").shape == (2, 2)
    shared = m.inverse_dynamics(x, x_dot[0], x_ddot[0], design, mode="out_in")
    np.testing.assert_allclose(shared[0], batch[0], rtol=1e-14)


def test_out_of_reach_poses_give_nan_rows():
    x = np.array([CENTRE, [3.0, 3.0]])
    for result in (
        m.inertia_matrix(x, GEOMETRY),
        m.inertia_matrix(x, GEOMETRY, space="actuated"),
        m.inverse_dynamics(x, [0.1, 0.0], [0.0, 0.1], GEOMETRY),
        m.natural_frequencies(x, GEOMETRY).frequencies,
        m.natural_frequencies(x, GEOMETRY).lowest_elastic,
    ):
        assert np.all(np.isfinite(result[0]))
        assert np.all(np.isnan(result[1]))


@pytest.mark.parametrize(("name", "value"), [("m1", -1.0), ("m2", -0.5), ("k1", -10.0), ("j2", 0.0)])
def test_negative_inertia_or_stiffness_is_a_design_error(name, value):
    design = {**GEOMETRY, name: value}
    with pytest.raises(DesignError, match=name):
        m.design(design)
    with pytest.raises(DesignError, match=name):
        m.inverse_dynamics(CENTRE, [0.0, 0.0], [0.0, 0.0], design)
    with pytest.raises(DesignError, match=name):
        m.natural_frequencies(CENTRE, design)


THETA_A = m.inverse_kinematics(CENTRE, GEOMETRY)
Z0 = np.concatenate([THETA_A, THETA_A])


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (lambda: m.inertia_matrix(CENTRE, space="joint"), PkmError, "joint"),
        (lambda: m.inertia_matrix([0.0, 1.4, 0.0]), PoseError, "pose"),
        (lambda: m.inverse_dynamics(CENTRE, [1.0, 2.0, 3.0], [0.0, 0.0]), PoseError, "velocity"),
        (lambda: m.inverse_dynamics(CENTRE, [0.0, 0.0], [np.nan, 0.0]), PoseError, "acceleration"),
        (lambda: m.inverse_dynamics(np.zeros((3, 2)), np.zeros((2, 2)), [0.0, 0.0]), PoseError, "velocity"),
        (lambda: m.natural_frequencies(np.zeros((2, 3))), PoseError, "pose"),
        (lambda: m.simulate(z0=Z0[:3], z_dot0=np.zeros(4), times=[0.0, 1.0]), PkmError, "z0"),
        (lambda: m.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0, 1.0]), PkmError, "increasing"),
        (lambda: m.simulate(z0=Z0, z_dot0=[0.0, 0.0, np.inf, 0.0], times=[0.0, 1.0]), PkmError, "z_dot0"),
        (lambda: m.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0], rtol=-1.0), PkmError, "rtol"),
        (
            lambda: m.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0], torque=lambda t: ca.vertcat(t, t, t)),
            PkmError,
            "2 motor torques",
        ),
        (lambda: m.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0], torque="a"), PkmError, "torque = 'a'"),
        (lambda: m.simulate(z0=[np.pi, 0.0, np.pi, 0.0], z_dot0=np.zeros(4), times=[0.0, 1.0]), PoseError, "assembled"),
        (lambda: m.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0], method="euler"), PkmError, "euler"),
        (lambda: Trajectory.point_to_point([0.0, 1.3], [0.1, 1.4], -1.0), PkmError, "duration"),
        (lambda: Trajectory.circle([0.0, 1.4], 0.0, 1.0), PkmError, "radius"),
        (lambda: Trajectory.circle([0.0, 1.4, 0.0], 0.1, 1.0), PkmError, "centre"),
        (
            lambda: flexible_inverse_dynamics(m, Trajectory.circle(CENTRE, 1.5, 1.0), np.linspace(0, 1, 9), GEOMETRY),
            PoseError,
            "leaves the out_out workspace",
        ),
        (
            lambda: flexible_inverse_dynamics(m, Trajectory.point_to_point([0.0], [1.0], 1.0), [0.0], GEOMETRY),
            PkmError,
            "1 coordinates",
        ),
    ],
    ids=[
        "space",
        "pose width",
        "velocity width",
        "non-finite acceleration",
        "batch sizes",
        "frequencies pose width",
        "z0 width",
        "times not increasing",
        "non-finite z_dot0",
        "tolerance",
        "torque width",
        "torque not a function",
        "z0 not assembled",
        "method",
        "duration",
        "radius",
        "centre",
        "out of reach",
        "trajectory dimension",
    ],
)
def test_bad_input_is_a_pkm_error_naming_it(call, error, match):
    with pytest.raises(error, match=match):
        call()


def test_integrator_failure_is_a_computation_error():
    push = ca.DM([50.0, -50.0])
    with pytest.raises(ComputationError, match="CVODES failed"):
        m.simulate(z0=Z0, z_dot0=np.zeros(4), times=np.linspace(0.0, 5.0, 6), torque=lambda t: push + 0 * t)


class Kinematic(Mechanism):
    """A mechanism whose generated module has no dynamic model."""

    name = "kinematic_five_bar"
    parameters = m.parameters
    actuator_names = m.actuator_names
    pose_names = m.pose_names
    working_modes = m.working_modes
    assembly_modes = m.assembly_modes
    functions: ClassVar[FunctionTable] = FunctionTable(
        {k: v for k, v in m.functions.items() if k in ("inverse_kinematics", "forward_kinematics")},
        "the kinematic_five_bar model",
    )


@pytest.mark.parametrize(
    "call",
    [
        lambda k: k.inertia_matrix(CENTRE),
        lambda k: k.inverse_dynamics(CENTRE, [0.0, 0.0], [0.0, 0.0]),
        lambda k: k.natural_frequencies(CENTRE),
        lambda k: k.simulate(z0=Z0, z_dot0=np.zeros(4), times=[0.0, 1.0]),
    ],
    ids=["inertia_matrix", "inverse_dynamics", "natural_frequencies", "simulate"],
)
def test_a_mechanism_without_a_dynamic_model_is_named(call):
    with pytest.raises(PkmError, match="kinematic_five_bar"):
        call(Kinematic())


@pytest.mark.parametrize(
    ("method", "args"),
    [
        ("inertia_matrix", (CENTRE,)),
        ("inverse_dynamics", (CENTRE, [0.0, 0.0], [0.0, 0.0])),
        ("natural_frequencies", (CENTRE,)),
        ("simulate", ()),
    ],
)
def test_unknown_keyword_argument_is_a_type_error(method, args):
    options = {"z0": Z0, "z_dot0": np.zeros(4), "times": [0.0, 1.0]} if method == "simulate" else {}
    with pytest.raises(TypeError, match="bogus"):
        getattr(m, method)(*args, **options, bogus=1)


def test_circle_has_its_radius_and_speed():
    trajectory = Trajectory.circle(CENTRE, 0.2, 2.0, turns=2)
    assert trajectory.duration == 4.0
    t = np.linspace(0.0, trajectory.duration, 17)
    x, x_dot, x_ddot = trajectory.sample(t)
    np.testing.assert_allclose(np.linalg.norm(x - CENTRE, axis=1), 0.2, rtol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(x_dot, axis=1), 0.2 * math.pi, rtol=1e-14)
    np.testing.assert_allclose(x_ddot, -((math.pi) ** 2) * (x - CENTRE), atol=1e-13)
    assert trajectory.position(0.0).shape == (2,)


def positive_definite(M: np.ndarray) -> bool:
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        return False
    return True


def test_a_pose_at_a_parallel_singularity_is_a_nan_row_and_the_others_are_as_alone():
    """On the axis x = 0 of the default geometry det_type2 has a root in out_out; beside it M_t, of order
    1/det^2, is positive definite only up to a round-off of either sign. One pose there, where M_T has no
    Cholesky factor, makes its own row NaN and no other."""
    design = m.design(GEOMETRY)

    def det(y: float) -> float:
        return m.singularity(np.array([0.0, y]), design, mode="out_out")["det_type2"]

    low, high = 1.0, 1.4
    assert det(low) * det(high) < 0
    for _ in range(60):
        low, high = ((low + high) / 2, high) if det((low + high) / 2) * det(low) > 0 else (low, (low + high) / 2)
    axis = np.stack([np.zeros(41), low + 1e-10 * np.arange(-20, 21)], axis=1)
    q = m.inverse_kinematics(axis, design, mode="out_out", passive=True)
    M_T = evaluate(m.functions["elastic_dynamics"], q, axis, np.zeros(4), design.vector())[0]
    singular = [k for k in range(len(axis)) if not positive_definite(M_T[k])]
    assert singular
    x = np.array([CENTRE, axis[singular[0]], [0.1, 1.5]])
    result = m.natural_frequencies(x, design, mode="out_out")
    assert np.isnan(result.frequencies[1]).all()
    assert np.isnan(result.shapes[1]).all()
    assert not result.rigid[1].any()
    assert np.isnan(result.lowest_elastic[1])
    for k in (0, 2):
        alone = m.natural_frequencies(x[k], design, mode="out_out")
        np.testing.assert_allclose(result.frequencies[k], alone.frequencies, rtol=1e-12)
        np.testing.assert_allclose(result.shapes[k], alone.shapes, rtol=1e-12)
        np.testing.assert_array_equal(result.rigid[k], alone.rigid)
