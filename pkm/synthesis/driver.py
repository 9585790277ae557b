"""The one synthesis driver: screen, IPOPT from several starts, verify, compare with the baselines.

:func:`synthesize` evaluates the problem on a screening grid over the variables' bounds (plus the
problem's own starting points), runs IPOPT through ``casadi.nlpsol`` with exact first and (unless the
problem says otherwise) second derivatives from the best feasible screening points, verifies every
converged optimum with a quadrature 4x denser and by sampling each quantity on a grid of its region,
and reports the best by its verified objective, never by the optimiser's quadrature. Each baseline
(the papers' own search) runs through the same model, timed and counted, and its best point is
verified the same way.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm.errors import ComputationError, PkmError, check_integer
from pkm.synthesis.model import Candidate, ProblemModel
from pkm.synthesis.problem import Problem, grid_points


@dataclass
class Run:
    """One IPOPT run from one start."""

    start: dict[str, float]
    status: str
    success: bool
    iterations: int
    evaluations: int
    objective: float
    variables: dict[str, float]
    verified_objective: float = float("nan")


@dataclass
class BaselineResult:
    """A baseline's best point on the same model, verified, with what the search cost."""

    name: str
    doc: str
    best: Candidate
    wall_time_s: float
    evaluations: int
    resolution: int


@dataclass
class SynthesisResult:
    """The optimum, how it was found and checked, and each baseline on the same model."""

    problem: str
    sense: str
    optimum: Candidate
    status: str
    iterations: int
    runs: list[Run]
    baselines: dict[str, BaselineResult]
    optimizer: dict[str, float] = field(default_factory=dict)
    resolutions: dict[str, int] = field(default_factory=dict)
    options: dict[str, Any] = field(default_factory=dict)

    @property
    def design(self) -> dict[str, float]:
        return self.optimum.design

    @property
    def variables(self) -> dict[str, float]:
        return self.optimum.variables

    @property
    def objective(self) -> float:
        return self.optimum.objective

    @property
    def verified_objective(self) -> float:
        return self.optimum.verified_objective

    @property
    def baseline(self) -> Candidate | None:
        """The best point of the first baseline (None for a problem without baselines)."""
        first = next(iter(self.baselines.values()), None)
        return None if first is None else first.best

    def to_dict(self) -> dict[str, Any]:
        first = next(iter(self.baselines.values()), None)
        return {
            "problem": self.problem,
            "sense": self.sense,
            "status": self.status,
            "iterations": self.iterations,
            "variables": self.optimum.variables,
            "design": self.optimum.design,
            "objective": self.optimum.objective,
            "verified_objective": self.optimum.verified_objective,
            "baseline_objective": None if first is None else first.best.objective,
            "optimum": asdict(self.optimum),
            "baseline": None
            if first is None
            else {**asdict(first.best), "wall_time_s": first.wall_time_s, "evaluations": first.evaluations},
            "baselines": {k: asdict(b) for k, b in self.baselines.items()},
            "optimizer": self.optimizer,
            "runs": [asdict(r) for r in self.runs],
            "resolutions": self.resolutions,
            "options": self.options,
        }


def ipopt_options(
    problem: Problem, *, verbose: bool, max_iter: int | None, tol: float | None, print_level: int | None
) -> dict[str, Any]:
    """IPOPT's options: quiet (no banner) unless ``verbose`` or a ``print_level`` is given; the variables'
    bounds are kept exactly (no relaxation), so that an optimum on a bound is reported on it."""
    max_iter = check_integer("max_iter", problem.max_iter if max_iter is None else max_iter, 0)
    tol = problem.tol if tol is None else float(tol)
    if not tol > 0:
        raise PkmError(f"tol = {tol} violates tol > 0")
    level = (5 if verbose else 0) if print_level is None else check_integer("print_level", print_level, 0)
    if level > 12:
        raise PkmError(f"print_level = {level} violates print_level <= 12")
    return {
        "print_time": verbose,
        "show_eval_warnings": verbose,
        "ipopt": {
            "print_level": level,
            "sb": "yes",
            "tol": tol,
            "hessian_approximation": problem.hessian,
            "max_iter": max_iter,
            "bound_relax_factor": 0.0,
        },
    }


def _named(problem: Problem, values: np.ndarray) -> dict[str, float]:
    return dict(zip(problem.variable_names, (float(v) for v in values), strict=True))


def _screen(model: ProblemModel, resolution: int, screening: int, starts: int) -> tuple[np.ndarray, np.ndarray]:
    """The screening points and the indices of the starts: the best feasible points, or where none is
    feasible the least infeasible (IPOPT starts from infeasible points too)."""
    prob = model.problem
    points = grid_points(prob.variables, screening)
    if prob.starting_points is not None:
        points = np.concatenate([points, np.atleast_2d(prob.starting_points())])
    objective, ok, violation = model.assess_points(points, resolution)
    order = model.best(objective, ok, starts)
    if len(order) == 0:
        finite = np.isfinite(violation)
        order = np.argsort(np.where(finite, violation, np.inf), kind="stable")[: min(starts, int(finite.sum()))]
    if len(order) == 0:
        raise ComputationError(f"the model of {prob.name} is undefined at all {len(points)} screening points")
    return points, order


def _rank(model: ProblemModel, cand: Candidate) -> tuple[bool, float]:
    """Sort key: feasible candidates first, then by the verified objective in the problem's sense."""
    value = cand.verified_objective
    return not cand.feasible, model.sign * value if np.isfinite(value) else np.inf


def synthesize(
    problem: Problem,
    *,
    resolution: int | None = None,
    baseline_resolution: int | None = None,
    starts: int | None = None,
    max_iter: int | None = None,
    tol: float | None = None,
    print_level: int | None = None,
    verbose: bool = False,
    progress: Callable[[str], None] | None = None,
) -> SynthesisResult:
    """Solve a synthesis problem with IPOPT from several starts and verify the optimum.

    Parameters
    ----------
    problem : Problem
    resolution : quadrature resolution of the optimised objective (verification uses twice it).
    baseline_resolution : grid nodes per variable of the baselines (their own resolution by default).
    starts : number of IPOPT starts, the best feasible screening points.
    max_iter, tol, print_level : IPOPT's options (the problem's by default; print level 0, or 5 with
        ``verbose``).
    verbose : print IPOPT's iterations and timing.
    progress : called with a short message at each stage.
    """
    res = check_integer("resolution", problem.resolution if resolution is None else resolution, 1)
    n_starts = check_integer("starts", problem.starts if starts is None else starts, 1)
    if baseline_resolution is not None:
        check_integer("baseline_resolution", baseline_resolution, 3)
    options = ipopt_options(problem, verbose=verbose, max_iter=max_iter, tol=tol, print_level=print_level)
    model = ProblemModel(problem)
    say = progress or (lambda _msg: None)

    say("screening")
    t0 = time.perf_counter()
    points, order = _screen(model, res, problem.screening_resolution, n_starts)
    nlp, lower, upper = model.nlp(res)
    extra = len(model.extremes)
    solver = ca.nlpsol(problem.name.replace(".", "_"), "ipopt", nlp, options)
    bounds = {
        "lbx": [v.lower for v in problem.variables] + [-np.inf] * extra,
        "ubx": [v.upper for v in problem.variables] + [np.inf] * extra,
        "lbg": lower,
        "ubg": upper,
    }
    runs: list[Run] = []
    evaluations = len(points)
    for k, index in enumerate(order):
        say(f"IPOPT from start {k + 1}/{len(order)}")
        x0 = model.start(points[index], res)
        sol = solver(x0=x0, **bounds)
        stats = solver.stats()
        calls = int(stats.get("n_call_nlp_f", 0)) + int(stats.get("n_call_nlp_grad_f", 0))
        evaluations += calls
        x = np.asarray(sol["x"]).ravel()
        w = x[: len(problem.variables)]
        value = model.sign * float(sol["f"])
        status, success = stats["return_status"], bool(stats["success"])
        if success and not model.tight(w, x[len(problem.variables) :], res):
            status, success = "Epigraph_Not_Tight", False
        runs.append(Run(_named(problem, points[index]), status, success, int(stats["iter_count"]), calls, value,
                        _named(problem, w)))
    opt_time = time.perf_counter() - t0
    good = [r for r in runs if r.success]
    if not good:
        last = runs[-1]
        raise ComputationError(
            f"IPOPT did not converge from any of {len(runs)} starts of {problem.name}; last status {last.status}, "
            f"last iterate {last.variables}, objective {last.objective:.6g}"
        )

    say("verification")
    candidates = []
    for run in good:
        cand = model.candidate(np.array(list(run.variables.values())), run.objective, res)
        run.verified_objective = cand.verified_objective
        candidates.append((run, cand))
    best_run, optimum = min(candidates, key=lambda rc: _rank(model, rc[1]))
    if not optimum.feasible:
        raise ComputationError(
            f"every converged run of {problem.name} violates a constraint by more than "
            f"{problem.feasibility_tolerance:g} at verification; best {optimum.variables}"
        )

    baselines = {}
    for base in problem.baselines:
        say(f"baseline {base.name}")
        t1 = time.perf_counter()
        n = baseline_resolution if baseline_resolution is not None and base.follows_resolution else base.resolution
        candidates_at = np.atleast_2d(base.points(n))
        values, feasible = model.evaluate(candidates_at, res)
        wall = time.perf_counter() - t1
        pick = model.best(values, feasible)
        if len(pick) == 0:
            # nothing feasible: report the point with the best objective, marked infeasible
            pick = model.best(values, np.isfinite(values))
        if len(pick) == 0:
            raise ComputationError(f"no point of the {base.name} baseline of {problem.name} has an objective")
        best = model.candidate(candidates_at[pick[0]], values[pick[0]], res)
        baselines[base.name] = BaselineResult(base.name, base.doc, best, wall, len(candidates_at), n)

    region_points = {
        name: q.region.node_count(res, q.index.reduce) for name, q in problem.quantities.items()
    }
    dense_points = {
        name: q.region.node_count(2 * res, q.index.reduce) for name, q in problem.quantities.items()
    }
    return SynthesisResult(
        problem=problem.name,
        sense=problem.objective.sense,
        optimum=optimum,
        status=best_run.status,
        iterations=sum(r.iterations for r in runs),
        runs=runs,
        baselines=baselines,
        optimizer={"wall_time_s": opt_time, "evaluations": evaluations},
        resolutions={
            "quadrature": res,
            "quadrature_points": sum(region_points.values()),
            "verification_points": sum(dense_points.values()),
            "baseline_grid": baseline_resolution or (problem.baselines[0].resolution if problem.baselines else 0),
        },
        options={k: v for k, v in options["ipopt"].items() if k != "sb"},
    )
