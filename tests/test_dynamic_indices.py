"""Dynamic global indices of Lara-Molina 2016 over the MIW: exact gradients against central differences,
convergence with the quadrature, the sampled check, the design space of eqs. 2 and 32-34."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pkm
from pkm import regions
from pkm.errors import DesignError, PkmError

m = pkm.load("five_bar")
SPACE = m.design_spaces["lara_molina2016"]
MIW = m.region("miw")

# (r1, r2, r3) in units of D: two designs with r1 + r3 > r2 (eq. 12) and two with r1 + r3 < r2 (eq. 11)
DESIGNS = ((1.2, 1.0, 0.8), (1.0, 1.3, 0.7), (0.4, 1.8, 0.8), (0.6, 1.9, 0.5))


def design(r) -> dict[str, float]:
    return m.design_dict(SPACE.designs(m.parameters, list(r)))


@pytest.mark.parametrize("name", ["dynamic_dexterity", "lambda_e"])
@pytest.mark.parametrize("r", DESIGNS)
def test_gradient_matches_central_differences(name, r):
    d = design(r)
    value, grad = m.global_index(name, d, region="miw", gradient=True, resolution=6)
    assert value == m.global_index(name, d, region="miw", resolution=6)
    step = 1e-6
    scale = max(abs(g) for g in grad.values())
    # lambda_e is a minimum: at a symmetric design it is attained at two mirror nodes, and a parameter of
    # one chain only (k1, j1) moves them apart, a kink; the parameters of both chains keep it smooth.
    keys = ("r1", "r2", "r3", "m1", "m2") if name == "lambda_e" else ("r1", "r2", "r3", "m1", "m2", "k1", "j1")
    for key in keys:
        plus, minus = dict(d), dict(d)
        plus[key] += step
        minus[key] -= step
        fd = (m.global_index(name, plus, region="miw", resolution=6)
              - m.global_index(name, minus, region="miw", resolution=6)) / (2 * step)
        assert grad[key] == pytest.approx(fd, rel=1e-4, abs=1e-6 * scale), (r, key)


@pytest.mark.parametrize("name", ["dynamic_dexterity", "lambda_e"])
def test_quadrature_converges_and_agrees_with_the_sampled_disc(name):
    d = SPACE.designs(m.parameters, [1.0, 1.3, 0.7])
    v8, v16, v32 = (m.global_index(name, d, region="miw", resolution=n) for n in (8, 16, 32))
    assert abs(v32 - v16) < abs(v16 - v8) + 1e-12
    assert abs(v32 - v16) < 2e-3 * abs(v32)
    sampled = regions.sampled_check(m, m.global_spec(name), MIW, d, branch=m.working_mode(None), resolution=128)
    assert float(sampled) == pytest.approx(float(v32), rel=5e-3)


def test_lambda_e_is_sqrt_k_over_j_where_the_mic_touches_the_parallel_singularity():
    for r in DESIGNS[:2]:
        value = m.global_index("lambda_e", design(r), region="miw", resolution=16)
        assert value == pytest.approx(math.sqrt(1 / 0.6), rel=1e-4)
    for r in DESIGNS[2:]:
        assert m.global_index("lambda_e", design(r), region="miw", resolution=16) > 1.3


def test_dynamic_dexterity_local_index_is_the_inverse_condition_of_m_w():
    d = design(DESIGNS[0])
    x = np.array([[0.0, 1.5], [0.2, 1.7], [-0.1, 1.4]])
    M_w = m.inertia_matrix(x, d, mode="out_out")
    eig = np.linalg.eigvalsh(M_w)
    np.testing.assert_allclose(m.local_index("dynamic_dexterity", x, d), eig[:, 0] / eig[:, 1], rtol=1e-12)
    freq = m.natural_frequencies(x, d, mode="out_out").lowest_elastic
    np.testing.assert_allclose(m.local_index("natural_frequency", x, d), freq, rtol=1e-8)


def test_chart_is_eqs_33_34_and_round_trips():
    rng = np.random.default_rng(3)
    for _ in range(20):
        r3 = rng.uniform(0, 1.5)
        r1 = rng.uniform(0.01, 3 - r3 - 0.01)
        c = [r1, 3 - r1 - r3, r3]
        s, t = SPACE.to_chart(c)
        assert s == pytest.approx((2 * r1 + r3) / math.sqrt(3))
        assert t == r3
        np.testing.assert_allclose(SPACE.from_chart(s, t), c, atol=1e-14)
        d = SPACE.designs(m.parameters, c, 2.0)
        back, scale = SPACE.from_design(d[:3])
        np.testing.assert_allclose(back, c, atol=1e-14)
        assert scale == pytest.approx(2.0)


def test_space_uses_the_papers_non_dimensional_dynamics():
    d = design(DESIGNS[0])
    assert (d["m1"], d["m2"], d["k1"], d["k2"]) == (1.2, 0.8, 1.0, 1.0)
    assert d["j1"] == d["j2"] == pytest.approx(0.5 * 1.2)


@pytest.mark.parametrize(
    ("c", "violated"),
    [
        ([1.0, 0.4, 1.6], "r3 <= 1.5"),
        ([-0.1, 2.6, 0.5], "0 < r1"),
        ([1.0, 1.0, 0.5], r"r1 \+ r2 \+ r3 = 3"),
    ],
)
def test_designs_outside_eq_32_are_design_errors(c, violated):
    with pytest.raises(DesignError, match=violated):
        SPACE.designs(m.parameters, c)


@pytest.mark.parametrize(("key", "value"), [("m1", -1.0), ("k2", 0.0), ("j1", -0.1), ("fv", -0.5)])
def test_non_physical_dynamic_parameters_are_design_errors(key, value):
    with pytest.raises(DesignError, match=key):
        m.design({"r1": 1.2, "r2": 1.0, "r3": 0.8, key: value})


def test_gradient_on_the_sampled_region_is_refused():
    with pytest.raises(PkmError, match="parametrised region"):
        m.global_index("lambda_e", None, region="reachable", gradient=True)
