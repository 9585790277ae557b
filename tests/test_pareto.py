"""Pareto fronts by the epsilon-constraint method (pkm.pareto): an analytic front, the multipliers as its slope,
the two mechanisms' fronts verified and non-dominated, the baselines on the same model, bad input."""

from __future__ import annotations

import csv
import importlib.util
import json
import os

import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.errors import PkmError, UnknownNameError
from pkm.synthesis import Objective, Problem, Variable
from pkm.synthesis.front import hypervolume, non_dominated
from pkm.synthesis.pareto import pareto


def _analytic() -> Problem:
    """min f1 = (x - 1)^2 + y^2 against f2 = x^2 + (y - 1)^2: the front is the segment (1 - s, s), s in [0, 1],
    f1 = 2 s^2 and f2 = 2 (1 - s)^2, so f1 = (sqrt(2) - sqrt(f2))^2 and d f1 / d f2 = -s / (1 - s). The
    mechanism only carries the variables (its design stays at the defaults)."""
    mech = pkm.load("five_bar")
    design = mech.design_vector(None)
    return Problem(
        name="analytic", doc="squared distances to (1, 0) and (0, 1)", mechanism=mech,
        variables=(Variable("x", -1.0, 2.0), Variable("y", -1.0, 2.0)), design=lambda _w: design, quantities={},
        objective=Objective(lambda t: (t["x"] - 1) ** 2 + t["y"] ** 2, "min", "squared distance to (1, 0)"),
        secondaries={"f2": Objective(lambda t: t["x"] ** 2 + (t["y"] - 1) ** 2, "min", "squared distance to (0, 1)")},
        starts=2, screening_resolution=5,
    )


def test_analytic_front_points_and_multipliers():
    epsilons = [1.8, 1.2, 0.7, 0.3, 0.05]
    front = pareto(_analytic(), "f2", epsilons=epsilons, baselines=(), progress=False)
    assert [p.status for p in front.points] == ["optimal"] * len(epsilons)
    for p, eps in zip(front.points, epsilons, strict=True):
        s = 1 - np.sqrt(eps / 2)
        assert p.variables["x"] == pytest.approx(1 - s, abs=1e-8)
        assert p.variables["y"] == pytest.approx(s, abs=1e-8)
        assert p.verified_objective == pytest.approx(2 * s**2, abs=1e-8)
        assert p.verified_secondary == pytest.approx(eps, abs=1e-8)
        assert p.trade_off == pytest.approx(-s / (1 - s), abs=1e-6)


def test_the_multiplier_is_the_slope_between_neighbouring_points():
    """The trade-off rate at a point against the central difference of the front through its two neighbours."""
    h = 1e-4
    front = pareto(_analytic(), "f2", epsilons=[1.0 + h, 1.0, 1.0 - h], baselines=(), progress=False)
    before, middle, after = front.points
    central = (after.verified_objective - before.verified_objective) / (after.verified_secondary
                                                                        - before.verified_secondary)
    assert middle.trade_off == pytest.approx(central, rel=1e-6)


def test_anchors_span_the_front_and_the_grid_baseline_lies_behind_it():
    front = pareto(_analytic(), "f2", n=5, grid=11, progress=False)
    # the anchors are IPOPT's optima of each objective alone: (1, 0) and (0, 1) to its tolerance
    assert list(front.anchors["objective"]["variables"].values()) == pytest.approx([1.0, 0.0], abs=1e-5)
    assert list(front.anchors["secondary"]["variables"].values()) == pytest.approx([0.0, 1.0], abs=1e-5)
    assert front.points[0].verified_objective == pytest.approx(0.0, abs=1e-8)
    assert front.points[-1].verified_secondary == pytest.approx(0.0, abs=1e-8)
    grid = front.baselines["grid"]
    assert grid.evaluations == 121
    assert grid.dominating == 0
    exact = (np.sqrt(2) - np.sqrt(np.array(grid.secondary))) ** 2
    assert np.all(np.array(grid.objective) >= exact - 1e-12)
    assert grid.hypervolume > 0
    assert front.hypervolume > 0


def test_hypervolume_and_dominance():
    costs = np.array([[0.0, 2.0], [1.0, 1.0], [2.0, 0.0], [1.5, 1.5]])
    assert non_dominated(costs).tolist() == [True, True, True, False]
    assert hypervolume(costs, np.array([3.0, 3.0])) == pytest.approx(3 * 1 + 2 * 1 + 1 * 1)


def test_bad_input():
    problem = _analytic()
    with pytest.raises(PkmError, match="n = 1"):
        pareto(problem, "f2", n=1)
    with pytest.raises(UnknownNameError, match="kappa_d_mean"):
        pareto(problem, "kappa_d_mean")
    with pytest.raises(UnknownNameError, match="annealing"):
        pareto(problem, "f2", baselines=("annealing",))
    with pytest.raises(UnknownNameError, match="gci"):
        pareto(registry.problem("five_bar.max_gci_miw"), "gci")


def test_the_nsga2_baseline_without_pymoo_is_refused_before_any_work(monkeypatch):
    """Nothing computed is lost to a missing optional dependency: the front is not solved at all."""
    find = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pymoo" else find(name, *a))
    started = []
    monkeypatch.setattr("pkm.synthesis.pareto._anchor", lambda *a, **_: started.append(a))
    with pytest.raises(PkmError, match="pip install pymoo"):
        pareto(_analytic(), "f2", baselines=("nsga2",))
    assert started == []


def _non_dominated_and_verified(front, tolerance):
    good = front.optimal
    assert len(good) >= 2
    signs = np.array([1.0 if front.objective["sense"] == "min" else -1.0,
                      1.0 if front.secondary["sense"] == "min" else -1.0])
    costs = np.array([[p.verified_objective, p.verified_secondary] for p in good]) * signs
    assert non_dominated(costs, tolerance * np.ptp(costs, axis=0)).all()
    for p in front.points:
        assert p.status in ("optimal", "dominated", "failed", "infeasible")
        assert abs(p.verified_objective - p.objective) <= 1e-2 * max(1.0, abs(p.objective))
    return costs


def _pymoo() -> bool:
    """Whether pymoo is there; PKM_REQUIRE_PYMOO=1 makes its absence a failure instead of a skip."""
    if os.environ.get("PKM_REQUIRE_PYMOO") == "1":
        import pymoo  # noqa: F401
        return True
    return importlib.util.find_spec("pymoo") is not None


def test_five_bar_gci_against_the_miw_radius(tmp_path):
    """The verified front and its files; NSGA-II on the same model, verified alike, beats no point of it in
    both objectives by more than the point's verification change, and the anchor of the largest MIW radius
    (a maximum where two pieces of the radius meet, where IPOPT stops) is polished by compass search to at
    least NSGA-II's largest radius."""
    baselines = ("grid", "nsga2") if _pymoo() else ("grid",)
    front = pareto(registry.problem("five_bar.max_gci_miw"), "miw_radius", n=4, resolution=4, grid=9, starts=1,
                   baselines=baselines, progress=False)
    _non_dominated_and_verified(front, 1e-6)
    radius = [p.verified_secondary for p in front.optimal]
    assert min(radius) == pytest.approx(0.3, abs=1e-6)
    front.write(tmp_path / "front")
    saved = json.loads((tmp_path / "front" / "front.json").read_text())
    assert len(saved["points"]) == 4
    assert "grid" in saved["baselines"]
    assert {"front.csv", "front.png", "front.svg", "report.md"} <= {p.name for p in (tmp_path / "front").iterdir()}
    with open(tmp_path / "front" / "front.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    parameters = registry.mechanism("five_bar").parameter_names()
    assert set(parameters) <= set(rows[0])  # every design parameter a column, the variables and the rest
    for row, point in zip(rows, front.points, strict=True):
        assert {n: float(row[n]) for n in parameters} == pytest.approx(point.design, rel=1e-12)
    if "nsga2" not in baselines:
        pytest.skip("pymoo is not installed: the NSGA-II comparison is left out")
    nsga = front.baselines["nsga2"]
    assert nsga.evaluations >= 1000
    assert nsga.dominating_beyond_accuracy == 0
    assert front.anchors["secondary"]["secondary"] >= max(nsga.secondary) - 1e-9


def test_gantry_kappa_d_against_the_peak_force_along_the_move():
    front = pareto(registry.problem("slider_gantry.min_kappa_d_task"), "effort_peak", n=3, resolution=4,
                   baselines=(), progress=False)
    costs = _non_dominated_and_verified(front, 1e-6)
    assert np.all(np.diff(costs[np.argsort(costs[:, 1]), 0]) <= 0)
    assert front.points[1].trade_off < 0


def test_nsga2_baseline_does_not_dominate_the_front():
    if os.environ.get("PKM_REQUIRE_PYMOO") != "1":
        pytest.importorskip("pymoo")
    front = pareto(_analytic(), "f2", n=6, baselines=("nsga2",), nsga=(20, 10), progress=False)
    nsga = front.baselines["nsga2"]
    assert nsga.evaluations == 200
    assert len(nsga.objective) > 0
    assert nsga.dominating == 0
    exact = (np.sqrt(2) - np.sqrt(np.array(nsga.secondary))) ** 2
    assert np.all(np.array(nsga.objective) >= exact - 1e-12)


def test_a_five_bar_trade_off_rate_is_the_slope_between_its_neighbours():
    """The epsilon constraint's multiplier at a point against the central difference of the objective through
    two points 1e-3 either side of it."""
    h, epsilon = 1e-3, 0.83
    front = pareto(registry.problem("five_bar.max_gci_miw"), "miw_radius", epsilons=[epsilon - h, epsilon, epsilon + h],
                   resolution=4, baselines=(), starts=1, progress=False)
    before, point, after = front.points
    assert [p.status for p in front.points] == ["optimal"] * 3
    slope = (after.objective - before.objective) / (after.secondary - before.secondary)
    assert point.trade_off == pytest.approx(slope, rel=1e-3)


def test_the_five_bar_front_is_a_front_against_a_dense_grid():
    """The GCI against the MIW radius, its count not given: the points placed by the front's own shape until
    the boxes they leave open sum to 2% of the anchors' box (it returned 9 points, 4 of them one design on a
    plateau, the last failed at the secondary's anchor, none beyond a radius of 0.891), each a distinct design,
    both anchors reached, every point polished so that no node of a 101-per-variable grid, verified at the
    point's resolution, dominates it beyond its accuracy, and the front's hypervolume at least the grid's
    (0.006037 against 0.006663 for a 201-per-variable grid from the issue's reference point). The default
    tolerance against the 601-per-variable grid: docs/benchmarks.md and tests/test_bench_pareto.py."""
    front = pareto(registry.problem("five_bar.max_gci_miw"), "miw_radius", tolerance=2e-2, grid=101, progress=False)
    good = front.optimal
    designs = np.array([list(p.variables.values()) for p in good])
    gaps = np.abs(designs[:, None, :] - designs[None, :, :]).max(axis=2) + np.eye(len(good))
    assert gaps.min() > 1e-9
    radius = [p.verified_secondary for p in good]
    assert min(radius) == pytest.approx(front.anchors["objective"]["secondary"], abs=1e-6)
    assert max(radius) >= front.anchors["secondary"]["secondary"] - 1e-6
    assert max(radius) > 0.95
    grid = front.baselines["grid"]
    assert grid.dominating_beyond_accuracy == 0
    assert front.hypervolume >= grid.hypervolume
    assert np.isfinite(front.open_hypervolume)
    assert front.open_hypervolume < front.hypervolume
