"""The contract by capability: every mechanism with an inertia model gets the SPD and energy checks,
every parametrised global index its gradient against central differences and its convergence with
resolution, every mechanism with two dynamic derivations their comparison, and every registered
synthesis problem a run against its baselines. A new mechanism or problem gets these for free."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import random_design, reachable_poses

import pkm
from pkm import registry
from pkm.batch import evaluate
from pkm.errors import PkmError

SEED = 11
STEP = 1e-6  # relative step of the directional central difference


def _with(capability: str) -> list[str]:
    return [n for n in pkm.mechanisms() if capability in pkm.load(n).functions]


@pytest.mark.parametrize("name", _with("inertia"))
def test_inertia_matrices_are_symmetric_positive_definite(name):
    m = pkm.load(name)
    rng = np.random.default_rng(SEED)
    design = random_design(m, rng)
    x = reachable_poses(m, design, m.modes[0], rng, count=16)
    for space in ("task", "actuated"):
        M = m.inertia_matrix(x, design, space=space)
        np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), rtol=1e-10, atol=1e-12)
        assert np.all(np.linalg.eigvalsh(M) > 0), space


@pytest.mark.parametrize("name", _with("inertia"))
def test_kinetic_energy_of_the_task_inertia_equals_the_bodies(name):
    """1/2 x_dot^T M_w x_dot against the kinetic energy summed over the bodies (``energy``) or over the
    joints (1/2 q_dot^T M q_dot with q_dot = Psi J x_dot, ``joint_dynamics``)."""
    m = pkm.load(name)
    rng = np.random.default_rng(SEED)
    design = random_design(m, rng)
    x = reachable_poses(m, design, m.modes[0], rng, count=16)
    x_dot = rng.normal(size=x.shape)
    task = 0.5 * np.einsum("ni,nij,nj->n", x_dot, m.inertia_matrix(x, design, space="task"), x_dot)
    q = m.inverse_kinematics(x, design, passive=True)
    d = m.design_vector(design)
    if "energy" in m.functions:
        (bodies, _) = evaluate(m.functions["energy"], q, x, x_dot, d)
        bodies = bodies[:, 0, 0]
    else:
        q_dot = np.einsum("nij,njk,nk->ni", m.psi(x, design), m.jacobian(x, design), x_dot)
        (M, _) = evaluate(m.functions["joint_dynamics"], q, q_dot, d)
        bodies = 0.5 * np.einsum("ni,nij,nj->n", q_dot, M, q_dot)
    np.testing.assert_allclose(task, bodies, rtol=1e-9)


@pytest.mark.parametrize("name", _with("lagrange_dynamics"))
def test_virtual_work_equals_lagrange(name):
    m = pkm.load(name)
    rng = np.random.default_rng(SEED)
    design = random_design(m, rng)
    x = reachable_poses(m, design, m.modes[0], rng, count=16)
    x_dot, x_ddot = rng.normal(size=x.shape), rng.normal(size=x.shape)
    q = m.inverse_kinematics(x, design, passive=True)
    d = m.design_vector(design)
    (tau_vw,) = evaluate(m.functions["inverse_dynamics"], q, x, x_dot, x_ddot, d)
    tau_l = evaluate(m.functions["lagrange_dynamics"], q, x, x_dot, x_ddot, d)[0]
    np.testing.assert_allclose(tau_vw, tau_l, rtol=1e-9, atol=1e-9 * np.abs(tau_l).max())


def _parametrised_cases() -> list[tuple[str, str, str]]:
    cases = []
    for name in pkm.mechanisms():
        m = pkm.load(name)
        for region in m.regions:
            cases += [(name, region, index) for index in m.global_indices()]
    return cases


def _round_off(m: pkm.Mechanism, region: str, index: str) -> float:
    """1e-12 of the local index's size at the region's centre, where the region is placed in the pose's
    coordinates; else (a region that is not a placed shape, or one in other coordinates) 0."""
    try:
        placed = m.region_placement(region)
    except PkmError:
        return 0.0
    if placed["mapped"] or len(placed["centre"]) != m.n_out:
        return 0.0
    return 1e-12 * abs(float(m.local_index(registry.global_index(index).local.name, placed["centre"])))


@pytest.mark.parametrize(("name", "region", "index"), _parametrised_cases())
def test_parametrised_global_index_gradient_matches_central_differences(name, region, index):
    """The exact gradient along a random direction of the design against a central difference. A region
    minimum is piecewise smooth (two mirror nodes tie at a symmetric design): its gradient is that of
    an active node, so it lies between the one-sided differences (Danskin)."""
    m = pkm.load(name)
    rng = np.random.default_rng(SEED)
    d = m.design().vector()
    direction = rng.uniform(-1, 1, size=d.shape) * np.abs(d)
    value, grad = m.global_index(index, d, region=region, resolution=3, gradient=True)
    assert np.isfinite(value)
    h = STEP
    up = m.global_index(index, d + h * direction, region=region, resolution=3)
    down = m.global_index(index, d - h * direction, region=region, resolution=3)
    exact = float(np.dot(list(grad.values()), direction))
    tol = 2e-5 * abs(exact) + 1e-7 * max(1.0, abs(value))
    if registry.global_index(index).reduce == "min":
        # a minimum at round-off of the index's size (0 on a singularity the region's rim touches) has
        # differences of round-off over the step
        tol += _round_off(m, region, index) / h
        forward, backward = (up - value) / h, (value - down) / h
        assert forward - tol <= exact <= backward + tol
    else:
        assert exact == pytest.approx((up - down) / (2 * h), abs=tol)


@pytest.mark.parametrize(("name", "region", "index"), _parametrised_cases())
def test_parametrised_global_index_converges_with_resolution(name, region, index):
    m = pkm.load(name)
    values = [m.global_index(index, region=region, resolution=n) for n in (2, 4, 8)]
    spec = registry.global_index(index)
    if spec.reduce == "min":
        # a minimum of 0 at a node every resolution has (the MIW's rim on the singularity, where the stiffness
        # vanishes) differs by round-off alone: of the index's size at the region's centre
        gap = abs(values[2] - values[1])
        if gap > 1e-2 * abs(values[2]):
            assert gap <= _round_off(m, region, index)
    else:
        assert abs(values[2] - values[1]) <= abs(values[1] - values[0]) + 1e-12 * abs(values[2])
    assert values[2].accuracy == pytest.approx(abs(values[2] - values[1]))


@pytest.mark.parametrize("name", sorted(registry.problems()))
def test_every_problem_beats_or_equals_its_baselines(name):
    problem = registry.problem(name)
    # a region extreme over a coarse quadrature is first-order accurate, a mean far better
    extreme = any(q.index.reduce in ("min", "max") for q in problem.quantities.values())
    result = pkm.synthesize(problem, resolution=2 if extreme else 3, baseline_resolution=9, starts=1)
    assert result.status == "Solve_Succeeded"
    assert result.optimum.feasible
    assert set(result.variables) == set(problem.variable_names)
    sign = 1.0 if result.sense == "min" else -1.0
    for base in result.baselines.values():
        assert base.evaluations > 0
        if base.best.feasible:
            assert sign * result.objective <= sign * base.best.objective + 1e-9, base.name
    assert result.verified_objective == pytest.approx(result.objective, rel=0.15 if extreme else 2e-2)
