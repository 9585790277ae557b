"""Global indices: convergence with resolution on both regions, exact MIW gradients, reported points.

The MIW disc of Lara-Molina eq. (12) touches the reach boundary (where the inverse kinematics has a
square-root singularity) and the parallel singularity (where ||V||max = sigma_max(J_f) is unbounded).
So the product Gauss quadrature converges algebraically, not spectrally: about fourth order for gci and
gamma_min, first order for gamma_max, whose integrand is unbounded at the point of contact.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import random_design

import pkm

m = pkm.load("five_bar")
DEFAULT = m.design()
NAMES = ("gci", "gamma_max", "gamma_min")


def values(name: str, region: str, resolutions) -> list:
    return [m.global_index(name, DEFAULT, region=region, resolution=n) for n in resolutions]


@pytest.mark.parametrize("name", NAMES)
def test_reachable_region_index_converges_as_the_grid_doubles(name):
    v32, v64, v128, v256, v512 = values(name, "reachable", (32, 64, 128, 256, 512))
    assert abs(v256 - v128) < abs(v64 - v32)
    assert abs(v512 - v256) < 1e-2 * abs(v512)


# finest-pair tolerance (16 -> 32) and the ratio of successive differences (its convergence order)
MIW_CONVERGENCE = {"gci": (2e-5, 0.2), "gamma_min": (2e-5, 0.5), "gamma_max": (3e-2, 0.6)}


@pytest.mark.parametrize("name", NAMES)
def test_miw_index_converges_as_the_quadrature_doubles(name):
    tolerance, ratio = MIW_CONVERGENCE[name]
    v4, v8, v16, v32 = values(name, "miw", (4, 8, 16, 32))
    assert abs(v32 - v16) < ratio * abs(v16 - v8) < ratio**2 * abs(v8 - v4)
    assert abs(v32 - v16) < tolerance * abs(v32)


@pytest.mark.parametrize("name", ["gci", "gamma_min"])
def test_smooth_miw_indices_agree_to_1e_6_at_resolution_32_and_64(name):
    v32, v64 = values(name, "miw", (32, 64))
    assert v64 == pytest.approx(v32, rel=1e-6)


def test_miw_gamma_max_converges_at_first_order():
    v8, v16, v32, v64 = values("gamma_max", "miw", (8, 16, 32, 64))
    assert (v64 - v32) / (v32 - v16) == pytest.approx(0.5, abs=0.05)
    assert (v32 - v16) / (v16 - v8) == pytest.approx(0.5, abs=0.05)


def random_designs(n: int, seed: int) -> list[dict[str, float]]:
    """Designs with the required parameters (the geometry) within 15 % of the defaults, the others left out."""
    rng = np.random.default_rng(seed)
    required = [p.name for p in m.parameters if p.required]
    designs = [random_design(m, rng, spread=0.15, names=required) for _ in range(n)]
    return [{k: d[k] for k in required} for d in designs]


@pytest.mark.parametrize("name", NAMES)
def test_miw_gradient_matches_central_differences(name):
    step = 1e-6
    for design in random_designs(5, seed=7):
        value, grad = m.global_index(name, design, region="miw", resolution=8, gradient=True)
        assert value == m.global_index(name, design, region="miw", resolution=8)
        assert list(grad) == [p.name for p in m.parameters]
        fd = {}
        for key in design:
            plus, minus = dict(design), dict(design)
            plus[key] += step
            minus[key] -= step
            fd[key] = (m.global_index(name, plus, region="miw", resolution=8)
                       - m.global_index(name, minus, region="miw", resolution=8)) / (
                2 * step
            )
        scale = max(abs(g) for g in grad.values())
        assert all(grad[p.name] == 0 for p in m.parameters if not p.required)
        for key in design:
            assert grad[key] == pytest.approx(fd[key], rel=1e-5, abs=1e-5 * scale), (design, key)


@pytest.mark.parametrize("region", ["reachable", "miw"])
def test_global_value_reports_points_that_grow_with_resolution(region):
    results = values("gci", region, (8, 16, 32))
    points = [r.points for r in results]
    assert all(isinstance(r, pkm.regions.GlobalValue) for r in results)
    assert [r.region for r in results] == [region] * 3
    assert [r.resolution for r in results] == [8, 16, 32]
    assert points[0] < points[1] < points[2]
    assert all(np.isfinite(r.accuracy) and r.accuracy > 0 for r in results)
    if region == "miw":
        assert points == [4 * n**2 for n in (8, 16, 32)]
        # the accuracy is the change from the quadrature at half the resolution
        assert [r.accuracy for r in results[1:]] == [abs(results[1] - results[0]), abs(results[2] - results[1])]
    else:
        assert all(0 < p <= n**2 for p, n in zip(points, (8, 16, 32), strict=True))


def test_reachable_points_are_the_masked_grid_cells():
    value = m.global_index("gci", DEFAULT, region="reachable", resolution=64)
    box = m.workspace_box(DEFAULT.vector())
    axes = [lo + (hi - lo) * (np.arange(64) + 0.5) / 64 for lo, hi in box]
    x = np.stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")], axis=1)
    local = m.local_index("inverse_condition_f", x, DEFAULT, mode="out_out")
    kept = local[np.nan_to_num(local, nan=-1.0) >= pkm.regions.SINGULARITY_MARGIN]
    assert value.points == len(kept)
    assert value == pytest.approx(kept.mean(), rel=1e-12)


LM = m.design_spaces["lara_molina2016"]
# chart points (s, t) of the Lara-Molina space: where the node minimum of lambda_e is biased most, on
# the plateau sqrt(k/j), on its edge, and inside
EXTREME_DESIGNS = ((0.30, 0.10), (1.0, 0.5), (2.2, 0.4))


def lm_design(s: float, t: float) -> dict:
    return m.design_dict(m.design_vector(LM.designs(m.parameters, LM.from_chart(s, t))))


@pytest.mark.parametrize(("s", "t"), EXTREME_DESIGNS)
def test_a_region_minimum_is_accurate_to_1e_5_at_the_default_resolution(s, t):
    from pkm.regions import sampled_check

    design = lm_design(s, t)
    value = m.global_index("lambda_e", design, region="miw")
    converged = m.global_index("lambda_e", design, region="miw", resolution=64)
    assert abs(value - converged) <= 1e-5 * abs(converged)
    assert value.accuracy <= 1e-5 * abs(value)
    dense = sampled_check(m, m.global_spec("lambda_e"), m.region("miw"), m.design_vector(design),
                          branch=m.working_mode("out_out"), resolution=128)
    assert value <= dense + 1e-12


def test_the_refinement_finds_minima_that_the_nodes_miss():
    from pkm.regions import node_quadrature

    spec, region, branch = m.global_spec("lambda_e"), m.region("miw"), m.working_mode("out_out")
    biased = 0.0
    for s, t in EXTREME_DESIGNS:
        d = m.design_vector(lm_design(s, t))
        node = float(node_quadrature(m, spec, region, d, branch=branch, resolution=8)[0])
        refined = m.global_index("lambda_e", d, region="miw", resolution=8)
        assert refined <= node
        biased = max(biased, (node - refined) / refined)
    assert biased > 1e-4


@pytest.mark.parametrize(("s", "t"), [(1.0, 0.5), (0.3, 0.1)])
def test_a_refined_minimum_has_the_gradient_of_central_differences(s, t):
    design = lm_design(s, t)
    _, grad = m.global_index("lambda_e", design, region="miw", gradient=True)
    # parameters that keep the design symmetric: its two mirror minima stay tied, the minimum smooth
    for name in ("r1", "r2", "r3", "m2"):
        h = 1e-5
        up = m.global_index("lambda_e", {**design, name: design[name] + h}, region="miw")
        down = m.global_index("lambda_e", {**design, name: design[name] - h}, region="miw")
        assert grad[name] == pytest.approx((up - down) / (2 * h), rel=1e-4, abs=1e-6)


# designs the Lara-Molina syntheses visit: a dexterity ridge near r3 = 0 and the optimum near r3 = 1
SYNTHESIS_DESIGNS = ((2.53, 0.26), (0.92, 1.0))


@pytest.mark.parametrize("name", ["gci", "gamma_min", "dynamic_dexterity", "lambda_e"])
def test_a_global_index_without_a_resolution_is_within_1e_5_of_its_converged_value(name):
    from pkm.regions import INDEX_ACCURACY

    for s, t in SYNTHESIS_DESIGNS:
        design = lm_design(s, t)
        value = m.global_index(name, design, region="miw")
        converged = m.global_index(name, design, region="miw", resolution=64 if name == "lambda_e" else 256)
        assert value.accuracy <= INDEX_ACCURACY * max(1.0, abs(value))
        assert abs(value - converged) <= INDEX_ACCURACY * max(1.0, abs(converged)), (s, t, value.resolution)


def test_a_global_value_prints_what_it_rests_on():
    value = m.global_index("gci", DEFAULT, region="miw", resolution=4)
    assert repr(value) == (f"GlobalValue({float(value)!r} over miw, resolution 4, {value.points} points, "
                           f"accuracy {value.accuracy:.1e})")
    assert f"{value:.3f}" == f"{float(value):.3f}"
    import json

    assert json.loads(json.dumps(value)) == float(value)
