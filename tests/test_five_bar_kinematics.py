"""Five-bar specifics: Gao 1998 eqs. (1)-(11), (26)-(27) and Lara-Molina 2016 eqs. (10)-(12) as numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import pkm
from pkm.regions import QUADRATURE_RESOLUTION
from pkm.regions.shapes import disc_quadrature

m = pkm.load("five_bar")
GAO1998 = m.design_spaces["gao1998"]
DEFAULT = {"r1": 1.2, "r2": 1.0, "r3": 0.8}
DESIGNS = (DEFAULT, {"r1": 1.0, "r2": 1.0, "r3": 0.5}, {"r1": 0.8, "r2": 1.3, "r3": 0.6})
GLOBAL_NAMES = ("gci", "gamma_max", "gamma_min")


def design_dict(vector) -> dict[str, float]:
    return dict(zip(("r1", "r2", "r3"), (float(v) for v in vector), strict=True))


def test_inverse_condition_is_gao_eq_11():
    rng = np.random.default_rng(11)
    box = m.workspace_box(np.array(list(DEFAULT.values())))
    x = rng.uniform(box[:, 0], box[:, 1], size=(4000, 2))
    checked = 0
    for mode in m.modes:
        xs = x[m.reachable(x, DEFAULT, mode=mode)]
        theta1, theta2, phi1, phi2 = m.inverse_kinematics(xs, DEFAULT, mode=mode, passive=True).T
        # Gao's phi1, phi5 are the actuated angles, phi2, phi4 the distal (coupler) angles.
        s12, s54, s24 = np.sin(theta1 - phi1), np.sin(theta2 - phi2), np.sin(phi1 - phi2)
        gao = 2 * np.abs(s12 * s54 * s24) / (s12**2 + s54**2)
        pkm_value = m.local_index("inverse_condition_f", xs, DEFAULT, mode=mode)
        np.testing.assert_allclose(pkm_value, gao, rtol=1e-9, atol=1e-12, err_msg=mode)
        checked += len(xs)
    assert checked > 4000


def _inverse_condition(x: float, y: float, mode: str) -> float:
    return float(m.local_index("inverse_condition_f", [x, y], DEFAULT, mode=mode))


@settings(max_examples=150, deadline=None)
@given(st.floats(-1.4, 1.4), st.floats(-2.05, 2.05))
def test_inverse_condition_is_symmetric_about_the_y_axis(x, y):
    assume(bool(m.reachable([x, y], DEFAULT, mode="out_out")))
    assume(bool(m.reachable([-x, y], DEFAULT, mode="out_out")))
    for mode in ("out_out", "in_in"):
        assert _inverse_condition(x, y, mode) == pytest.approx(_inverse_condition(-x, y, mode), abs=1e-12)
    assert _inverse_condition(x, y, "out_in") == pytest.approx(_inverse_condition(-x, y, "in_out"), abs=1e-12)


def test_out_in_alone_is_not_mirror_symmetric():
    # so that the symmetry test above can fail
    assert abs(_inverse_condition(0.4, 1.2, "out_in") - _inverse_condition(-0.4, 1.2, "out_in")) > 1e-2


@pytest.mark.parametrize("design", DESIGNS, ids=lambda d: "-".join(f"{v:g}" for v in d.values()))
@pytest.mark.parametrize("name", GLOBAL_NAMES)
def test_global_indices_agree_between_gao_configurations_eqs_26_27(design, name):
    value = {gao: m.global_index(name, design, mode=gao) for gao in ("OABCD", "OABC'D", "OA'BCD", "OA'BC'D")}
    assert value["OABCD"] == pytest.approx(value["OA'BC'D"], rel=1e-9)
    assert value["OABC'D"] == pytest.approx(value["OA'BCD"], rel=1e-9)
    assert abs(value["OABCD"] - value["OABC'D"]) > 1e-3 * abs(value["OABCD"])


def lara_molina_mic(r1: float, r2: float, r3: float) -> tuple[float, float]:
    """Centre height and radius of the MIC, Lara-Molina 2016 eqs. (11)-(12), r3 the half base."""
    if r1 + r3 < r2:
        return math.sqrt((r1 + r2 + abs(r1 - r2)) ** 2 / 4 - r3**2), (r1 + r2 - abs(r1 - r2)) / 2
    y_col = math.sqrt(r1**2 - (r2 - r3) ** 2)
    s = r1 + r2 + y_col
    y_mic = (s**2 - r3**2) / (2 * s)
    return y_mic, abs(y_mic) - y_col


@pytest.mark.parametrize("r", [(1.2, 1.0, 0.8), (0.5, 1.6, 0.9)])
def test_maximum_inscribed_circle_is_lara_molina_eqs_10_12(r):
    y_mic, r_mic = lara_molina_mic(*r)
    centre, radius = m.maximum_inscribed_circle(design_dict(r))
    np.testing.assert_allclose(centre, [0.0, y_mic], rtol=1e-14, atol=1e-15)
    assert radius == pytest.approx(r_mic, rel=1e-14)


def test_maximum_inscribed_circle_of_the_lara_molina_design_touches_reach_and_parallel_singularity():
    r1, r2, r3 = 1.2, 1.0, 0.8
    centre, radius = m.maximum_inscribed_circle(DEFAULT)
    assert (centre[1], radius) == pytest.approx((1.5970234, 0.4138075), abs=1e-7)
    assert math.hypot(centre[0] + r3, centre[1]) + radius == pytest.approx(r1 + r2, rel=1e-14)
    assert centre[1] - radius == pytest.approx(math.sqrt(r1**2 - (r2 - r3) ** 2), rel=1e-14)


def random_chart_designs(n: int, seed: int) -> list[dict[str, float]]:
    """Designs (L = 1) drawn uniformly in the interior of Gao's trapezoid, 0.05 from its edges."""
    rng = np.random.default_rng(seed)
    poly = np.array(GAO1998.polygon)
    out = []
    while len(out) < n:
        u, v = rng.uniform(poly.min(axis=0), poly.max(axis=0))
        r = GAO1998.from_chart(u, v)
        if min(r) > 0.05 and max(r[:2]) < 1.95 and r[2] < 1.95:
            out.append(design_dict(GAO1998.to_design(r, 1.0)))
    return out


def assert_miw_inside_out_out_workspace(design: dict[str, float]) -> None:
    centre, radius = m.maximum_inscribed_circle(design)
    x = centre + radius * disc_quadrature(QUADRATURE_RESOLUTION)[0]
    reach = m.reachable(x, design, mode="out_out")
    assert reach.all(), f"{design}: {np.mean(~reach):.1%} of the MIW quadrature is out of reach"
    assert np.all(m.local_index("inverse_condition_f", x, design, mode="out_out") > 0), design


def test_miw_quadrature_is_reachable_and_regular_for_random_gao_designs():
    for design in random_chart_designs(300, seed=1998):
        assert_miw_inside_out_out_workspace(design)


def test_miw_of_a_design_with_r1_shorter_than_r2_avoids_the_annulus_hole():
    # r1 + r3 > r2 selects eq. (12), whose disc ignores the inner circles |P - O_i| = |r1 - r2|.
    design = {"r1": 0.5, "r2": 1.0, "r3": 0.55}
    assert_miw_inside_out_out_workspace(design)
    assert math.isfinite(m.global_index("gci", design, region="miw"))


positive = st.floats(0.05, 3.0)


@settings(max_examples=200, deadline=None)
@given(positive, positive, st.floats(0.0, 1.0), st.floats(0.1, 10.0))
def test_gao1998_from_design_and_to_design_round_trip(r1, r2, base_fraction, scale):
    d = [scale * r1, scale * r2, scale * base_fraction * (r1 + r2) * 0.99]
    c, length = GAO1998.from_design(d)
    assert 2 * c[0] + 2 * c[1] + c[2] == pytest.approx(4.0, rel=1e-14)
    assert 0 < c[0] < 2
    assert 0 < c[1] < 2
    assert 0 <= c[2] < 2
    np.testing.assert_allclose(GAO1998.to_design(c, length), d, rtol=1e-13, atol=1e-15)


gao_r1 = st.floats(0.01, 1.99)


@settings(max_examples=200, deadline=None)
@given(gao_r1, st.floats(0.0, 1.0), gao_r1, st.floats(0.0, 1.0))
def test_gao1998_chart_round_trips_and_is_isometric(a1, t1, b1, t2):
    def on_plane(r1: float, t: float) -> np.ndarray:
        r3 = t * min(2.0, 4 - 2 * r1) * 0.999  # r3 < 2 and r2 = (4 - r3)/2 - r1 > 0
        return np.array([r1, (4 - r3) / 2 - r1, r3])

    c1, c2 = on_plane(a1, t1), on_plane(b1, t2)
    assume(c1[1] > 0 and c2[1] > 0)
    for c in (c1, c2):
        back = GAO1998.from_chart(*GAO1998.to_chart(c))
        np.testing.assert_allclose(back, c, rtol=1e-13, atol=1e-14)
        assert 2 * back[0] + 2 * back[1] + back[2] == pytest.approx(4.0, rel=1e-14)
    chart_distance = math.dist(GAO1998.to_chart(c1), GAO1998.to_chart(c2))
    assert chart_distance == pytest.approx(float(np.linalg.norm(c1 - c2)), rel=1e-12, abs=1e-14)


def test_gao1998_polygon_is_the_trapezoid_of_eq_5():
    corners = [GAO1998.from_chart(u, v) for u, v in GAO1998.polygon]
    np.testing.assert_allclose(corners, [[0, 2, 0], [2, 0, 0], [1, 0, 2], [0, 1, 2]], atol=1e-14)
