"""Pareto fronts by the epsilon-constraint method, each point an IPOPT optimum, verified (DESIGN.md section 6).

A problem's objective f1 is traded against a secondary objective f2 (one of the problem's quantities, or one of
its ``secondaries``). :func:`pareto` solves the two anchors (f1 alone and f2 alone, :func:`pkm.synthesize` from
several starts), then, for epsilon from f2 at the first anchor to f2 at the second,

    optimise f1  subject to  f2 <= epsilon (f2 >= epsilon where larger f2 is better)  and the problem's constraints,

each point by IPOPT from the point before it (a warm start along the front; the anchors where that fails), with
exact derivatives. At its solution the multiplier lambda of the epsilon constraint (IPOPT's, of the NLP that
minimises s1 f1, s1 = +1 to minimise and -1 to maximise) is the front's local slope: d f1* / d epsilon =
-s1 lambda, what a unit of f2 costs in f1. Each point is verified as every synthesis is: f1 and f2 at a
quadrature of twice the resolution, region extremes refined between the nodes, the other constraints held
there. A point is ``optimal`` where IPOPT converged and its verified values hold the constraints and are
dominated by no other point of the front (beyond ``DOMINANCE`` of each objective's span); else ``dominated``,
``infeasible`` or ``failed`` (IPOPT's status kept), and never dropped.

Baselines run on the same model: the grid over the variables' bounds and, where pymoo is installed, NSGA-II
(pymoo's, an optional dependency); each reports its non-dominated feasible points, evaluations and wall time,
and every front its hypervolume from one reference point (the pkm front's nadir moved out by ``REFERENCE_MARGIN``
of its spans).
"""

from __future__ import annotations

import importlib.util
import itertools
import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.errors import ComputationError, PkmError, UnknownNameError, check_integer
from pkm.progress import Progress
from pkm.synthesis.driver import (
    StartTask,
    SynthesisError,
    SynthesisResult,
    ipopt_options,
    nlp_solver,
    solve_from,
    synthesize,
)
from pkm.synthesis.model import ProblemModel
from pkm.synthesis.problem import Constraint, Objective, Problem, grid_points

DOMINANCE = 1e-6  # relative to an objective's span on the front: a point better by less is not better
REFERENCE_MARGIN = 0.1  # the hypervolume's reference point lies this far (of each span) beyond the front's nadir
MAX_POINTS = 1000
GRID = 21  # grid nodes per variable of the grid baseline
NSGA_POPULATION = 40
NSGA_GENERATIONS = 25
NSGA_SEED = 0
NSGA_MISSING = "the nsga2 baseline needs pymoo: pip install pymoo"  # refused before the front is computed
EPSILON = "epsilon"  # the name of the epsilon constraint
COMPASS_STEP = 1e-9  # the anchors' compass search stops at this step, of each variable's span
COMPASS_ITERATIONS = 2000  # moves and halvings at most
COMPASS_GAIN = 1e-14  # a move must improve the objective by this much, relative: round-off never leads it


@dataclass
class FrontPoint:
    """One point of the front: its epsilon, what IPOPT found (``objective`` f1 and ``secondary`` f2 at the
    optimiser's quadrature), the verified values, the epsilon constraint's multiplier and the trade-off rate
    d f1 / d f2, the status (``optimal``, ``dominated``, ``infeasible``, ``failed``) and IPOPT's."""

    epsilon: float
    status: str
    ipopt_status: str
    variables: dict[str, float]
    design: dict[str, float]
    objective: float
    secondary: float
    verified_objective: float
    verified_secondary: float
    multiplier: float
    trade_off: float
    iterations: int
    evaluations: int
    wall_time_s: float


@dataclass
class BaselineFront:
    """A baseline's non-dominated feasible points (f1, f2) on the same model, what they cost and their
    hypervolume."""

    name: str
    doc: str
    objective: list[float]
    secondary: list[float]
    evaluations: int
    wall_time_s: float
    hypervolume: float = float("nan")
    dominating: int = 0  # pkm front points one of its points dominates (beyond DOMINANCE of a span)
    dominating_beyond_accuracy: int = 0  # those it beats in both objectives by more than their verification change


@dataclass
class ParetoFront:
    """A verified front of ``objective`` against ``secondary`` with its baselines."""

    problem: str
    objective: dict[str, str]
    secondary: dict[str, str]
    points: list[FrontPoint]
    baselines: dict[str, BaselineFront]
    reference: list[float]
    hypervolume: float
    resolution: int
    wall_time_s: float
    evaluations: int
    iterations: int
    anchors: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def optimal(self) -> list[FrontPoint]:
        return [p for p in self.points if p.status == "optimal"]

    def to_dict(self) -> dict[str, Any]:
        return {
            "problem": self.problem, "objective": self.objective, "secondary": self.secondary,
            "resolution": self.resolution, "wall_time_s": self.wall_time_s, "evaluations": self.evaluations,
            "iterations": self.iterations, "hypervolume": self.hypervolume, "reference": self.reference,
            "anchors": self.anchors, "points": [asdict(p) for p in self.points],
            "baselines": {k: asdict(b) for k, b in self.baselines.items()},
        }

    def __str__(self) -> str:
        counts = {s: sum(p.status == s for p in self.points) for s in ("optimal", "dominated", "infeasible", "failed")}
        text = ", ".join(f"{v} {k}" for k, v in counts.items() if v)
        return (f"{self.problem}: front of {self.objective['name']} against {self.secondary['name']}, "
                f"{len(self.points)} points ({text}), hypervolume {self.hypervolume:.6g}, {self.wall_time_s:.1f} s")

    def write(self, folder: str | Path) -> Path:
        """front.json, front.csv, front.png and front.svg (with the baselines) and report.md into ``folder``,
        all or nothing (:func:`pkm.io.staged_folder`)."""
        target = Path(folder)
        with io.staged_folder(target) as stage:
            io.write_text(stage / "front.json", io.to_json(self.to_dict()))
            io.write_text(stage / "front.csv", _csv(self))
            fig = figure(self)
            from pkm.figures import save

            for suffix in ("png", "svg"):
                save(fig, stage / f"front.{suffix}", dpi=150)
            io.write_text(stage / "report.md", report(self))
        return target


def secondary_objective(problem: Problem, secondary: str | Objective) -> tuple[str, Objective, Problem]:
    """The secondary objective by name (one of the problem's quantities or ``secondaries``) or as given, and the
    problem with the quantity it reads (a secondary that is a quantity of its own)."""
    if isinstance(secondary, Objective):
        return secondary.quantity or "secondary", secondary, problem
    known = {**problem.quantities, **problem.secondaries}
    known.pop(problem.objective.quantity, None)
    if secondary not in known:
        raise UnknownNameError(f"secondary objective of {problem.name}", secondary, list(known) or ["none"])
    value = known[secondary]
    if isinstance(value, Objective):
        return secondary, value, problem
    extended = replace(problem, quantities={**problem.quantities, secondary: value})
    return secondary, Objective.of(secondary, value), extended


def front_model(problem: Problem, secondary: str | Objective) -> ProblemModel:
    """The problem's model with the secondary objective as its last, unbounded constraint (the model the front's
    baselines evaluate)."""
    _, second, extended = secondary_objective(problem, secondary)
    return ProblemModel(_with_epsilon(extended, second, None))


def _with_epsilon(problem: Problem, secondary: Objective, epsilon: float | None) -> Problem:
    """The problem with the secondary as its last constraint: at most (at least, where larger is better)
    ``epsilon``, or unbounded (None), a row that reads its value."""
    lower, upper = -math.inf, math.inf
    if epsilon is not None:
        lower, upper = (epsilon, math.inf) if secondary.sense == "max" else (-math.inf, epsilon)
    row = Constraint(EPSILON, secondary.expression, lower, upper)
    return replace(problem, constraints=(*problem.constraints, row), baselines=())


def pareto(
    problem: Problem,
    secondary: str | Objective,
    *,
    n: int = 9,
    epsilons: Sequence[float] | None = None,
    resolution: int | None = None,
    baselines: Sequence[str] = ("grid",),
    grid: int = GRID,
    nsga: tuple[int, int] = (NSGA_POPULATION, NSGA_GENERATIONS),
    starts: int | None = None,
    progress: Callable[[int, int], object] | bool | None = None,
) -> ParetoFront:
    """The front of the problem's objective against ``secondary`` by the epsilon-constraint method (module
    docstring): ``n`` points from one anchor to the other, or at the given ``epsilons``; at the problem's
    resolution unless ``resolution`` is given (verification at twice it); ``baselines`` among ``"grid"``
    (``grid`` nodes per variable) and ``"nsga2"`` (pymoo's NSGA-II, ``nsga`` = (population, generations)),
    each on the same model; ``starts`` IPOPT starts of each anchor; ``progress(done, total)`` after each point
    (a bar on a terminal by default, False: nothing)."""
    name, second, problem = secondary_objective(problem, secondary)
    count = check_integer("n", n if epsilons is None else len(epsilons), 2, MAX_POINTS)
    unknown = sorted(set(baselines) - set(BASELINES))
    if unknown:
        raise UnknownNameError("baseline of a Pareto front", unknown[0], list(BASELINES))
    if "nsga2" in baselines and importlib.util.find_spec("pymoo") is None:
        raise PkmError(NSGA_MISSING)
    res = check_integer("resolution", problem.resolution if resolution is None else resolution, 1, 1024)
    options = ipopt_options(problem, verbose=False, max_iter=None, tol=None, print_level=None)
    measure = ProblemModel(_with_epsilon(problem, second, None))
    total = count + 2 + len(baselines)
    bar = Progress(total, f"pareto {problem.name}", enabled=None if progress is None else False)
    done = [0]

    def step() -> None:
        done[0] += 1
        bar.advance(1)
        if callable(progress):
            progress(done[0], total)

    t0 = time.perf_counter()
    with bar:
        anchors = []
        for objective in (problem.objective, second):
            anchors.append(_anchor(replace(problem, objective=objective, baselines=()), res, starts, grid))
            step()
        ends = np.array([list(a.variables.values()) for a in anchors])
        f1, g = measure.values(ends, res)
        if not np.all(np.isfinite(g[:, -1])):
            raise ComputationError(f"the secondary {name} of {problem.name} is undefined at an anchor: "
                                   f"{[a.variables for a in anchors]}")
        values = np.linspace(g[0, -1], g[1, -1], count) if epsilons is None else np.asarray(epsilons, dtype=float)
        points = _march(problem, second, values, ends, res=res, options=options, step=step)
        _classify(points, problem.objective.sense, second.sense)
        _repair(problem, second, points, res=res, options=options)
        evaluations = sum(a.optimizer["evaluations"] for a in anchors) + sum(p.evaluations for p in points)
        iterations = sum(a.iterations for a in anchors) + sum(p.iterations for p in points)
        wall = time.perf_counter() - t0
        found = {}
        for kind in baselines:
            found[kind] = BASELINES[kind](measure, res, grid=grid, nsga=nsga, senses=(problem.objective.sense,
                                                                                       second.sense))
            step()
    front = ParetoFront(
        problem=problem.name,
        objective={"name": problem.objective.quantity or "objective", "sense": problem.objective.sense,
                   "doc": problem.objective.doc},
        secondary={"name": name, "sense": second.sense, "doc": second.doc},
        points=points, baselines=found, reference=[], hypervolume=float("nan"), resolution=res, wall_time_s=wall,
        evaluations=int(evaluations), iterations=int(iterations),
        anchors={kind: {"objective": float(f1[k]), "secondary": float(g[k, -1]), "status": a.status,
                        "variables": a.variables}
                 for k, (kind, a) in enumerate(zip(("objective", "secondary"), anchors, strict=True))},
    )
    compare_fronts(front)
    return front


def _anchor(problem: Problem, resolution: int, starts: int | None, grid: int) -> SynthesisResult:
    """The optimum of one objective alone (:func:`pkm.synthesize` at the resolution, without polishing); where
    IPOPT converges from no start (an objective with kinks: a largest inscribed circle) the best feasible of its
    last iterate and the nodes of a grid of ``grid`` nodes per variable, improved by a compass search
    (:func:`_compass`), its status saying so."""
    try:
        return synthesize(problem, resolution=resolution, starts=starts, progress=False)
    except SynthesisError as exc:
        if exc.result is None:
            raise
        result = exc.result
    model = ProblemModel(problem)
    points = grid_points(problem.variables, grid)
    if problem.starting_points is not None:
        points = np.concatenate([points, np.atleast_2d(problem.starting_points())])
    points = np.concatenate([points, [list(result.optimum.variables.values())]])
    objective, ok = model.evaluate(points, resolution)
    best = model.best(objective, ok)
    if not len(best):
        raise ComputationError(f"no feasible point for {problem.objective.doc} of {problem.name}: IPOPT ended with "
                               f"{result.status} and no node of a {grid}-per-variable grid is feasible")
    point, value = _compass(model, points[best[0]], float(objective[best[0]]), resolution, 1.0 / (grid - 1))
    result.optimum = model.candidate(point, value, resolution)
    result.status = (f"{result.status}; the best feasible of its last iterate and a {grid}-per-variable grid, "
                     f"then a compass search to steps of {COMPASS_STEP:g} of each variable's span")
    return result


def _stencil(count: int) -> np.ndarray:
    """The compass's directions in ``count`` variables: every neighbour of a cube's centre (26 in three
    variables), or the axes both ways beyond three."""
    if count > 3:
        return np.concatenate([np.eye(count), -np.eye(count)])
    steps = np.array(list(itertools.product((-1.0, 0.0, 1.0), repeat=count)))
    return steps[np.any(steps != 0, axis=1)]


def _compass(model: ProblemModel, point: np.ndarray, value: float, resolution: int, step: float
             ) -> tuple[np.ndarray, float]:
    """A feasible point improved by compass search: the stencil's neighbours at ``step`` of each variable's span
    (clipped to the bounds) evaluated in one batch, the best feasible improvement taken, the step halved where
    there is none, down to COMPASS_STEP. It needs no derivative, so it climbs an objective with kinks (a maximum
    where two smooth pieces meet) where IPOPT stops."""
    lower = np.array([v.lower for v in model.problem.variables])
    upper = np.array([v.upper for v in model.problem.variables])
    directions = _stencil(len(lower)) * (upper - lower)
    score = model.sign * value
    for _ in range(COMPASS_ITERATIONS):
        if step <= COMPASS_STEP:
            break
        trial = np.clip(point + step * directions, lower, upper)
        objective, ok = model.evaluate(trial, resolution)
        scores = np.where(ok & np.isfinite(objective), model.sign * objective, np.inf)
        k = int(np.argmin(scores))
        if scores[k] < score - COMPASS_GAIN * max(1.0, abs(score)):
            point, score = trial[k], float(scores[k])
        else:
            step /= 2
    return point, model.sign * score


def _march(problem: Problem, second: Objective, epsilons: np.ndarray, ends: np.ndarray, *, res: int,
           options: dict[str, Any], step: Callable[[], None]) -> list[FrontPoint]:
    """The epsilon-constraint optimum at each epsilon in turn, each from the one before it (the first from the
    objective's anchor), else from the anchors."""
    points: list[FrontPoint] = []
    previous = ends[0]
    for epsilon in epsilons:
        point = _point(problem, second, float(epsilon), [previous, ends[0], ends[1]], res=res, options=options)
        if point.status != "failed":
            previous = np.array(list(point.variables.values()))
        points.append(point)
        step()
    return points


def _repair(problem: Problem, second: Objective, points: list[FrontPoint], *, res: int,
            options: dict[str, Any]) -> None:
    """Each dominated point solved again from a point that dominates it (feasible for its epsilon: a warm start
    that left the basin of the front), kept where IPOPT converges to a better objective; then classified again."""
    sign = 1.0 if problem.objective.sense == "min" else -1.0
    senses = (problem.objective.sense, second.sense)
    for k, p in enumerate(points):
        if p.status != "dominated":
            continue
        mine = minimised(np.array([p.verified_objective]), np.array([p.verified_secondary]), senses)[0]
        better = [q for q in points if q.status == "optimal" and np.all(
            minimised(np.array([q.verified_objective]), np.array([q.verified_secondary]), senses)[0] <= mine)]
        start = min(better, key=lambda q: abs(q.verified_secondary - p.epsilon), default=None)
        if start is None:
            continue
        again = _point(problem, second, p.epsilon, [np.array(list(start.variables.values()))], res=res,
                       options=options)
        again.iterations += p.iterations
        again.evaluations += p.evaluations
        if again.status == "optimal" and sign * again.objective < sign * p.objective:
            points[k] = again
    for p in points:
        if p.status == "dominated":
            p.status = "optimal"
    _classify(points, problem.objective.sense, second.sense)


def _point(problem: Problem, second: Objective, epsilon: float, starts: list[np.ndarray], *, res: int,
           options: dict[str, Any]) -> FrontPoint:
    """IPOPT at one epsilon from the first of the starts it converges from, verified at twice the resolution."""
    t1 = time.perf_counter()
    model = ProblemModel(_with_epsilon(problem, second, epsilon))
    solver, bounds = nlp_solver(model, res, options)
    text = json.dumps(options, sort_keys=True)
    iterations = evaluations = 0
    for start in starts:
        run = solve_from(model, solver, bounds, StartTask(problem.name, np.array(start), res, text))
        iterations += run.iterations
        evaluations += run.evaluations
        if run.success:
            break
    point = np.array(list(run.variables.values()))
    design = np.asarray(problem.design(list(point)), dtype=float).ravel()
    _, g_at = model.values(point[None], res)
    verified, g = model.verified_values(point, design, 2 * res)
    held = _feasible_except_last(model, g) and np.isfinite(verified)
    status = "failed" if not run.success else "optimal" if held else "infeasible"
    multiplier = run.multipliers[-1] if run.multipliers else float("nan")
    sign = 1.0 if problem.objective.sense == "min" else -1.0
    return FrontPoint(
        epsilon=epsilon, status=status, ipopt_status=run.status, variables=run.variables,
        design=problem.mechanism.design_dict(design), objective=run.objective, secondary=float(g_at[0, -1]),
        verified_objective=float(verified), verified_secondary=float(g[-1]), multiplier=float(multiplier),
        trade_off=-sign * float(multiplier), iterations=iterations, evaluations=evaluations,
        wall_time_s=time.perf_counter() - t1,
    )


def _feasible_except_last(model: ProblemModel, g: np.ndarray) -> bool:
    """Whether the constraint values (m,) hold every constraint but the last (the epsilon constraint)."""
    tol = model.problem.feasibility_tolerance
    with np.errstate(invalid="ignore"):
        return bool(np.all((g[:-1] >= model.lower[:-1] - tol) & (g[:-1] <= model.upper[:-1] + tol)))


def minimised(f1: np.ndarray, f2: np.ndarray, senses: tuple[str, str]) -> np.ndarray:
    """The objectives (N, 2) as both minimised."""
    return np.stack([f1 if senses[0] == "min" else -f1, f2 if senses[1] == "min" else -f2], axis=1)


def non_dominated(costs: np.ndarray, tolerance: np.ndarray | float = 0.0) -> np.ndarray:
    """Mask of the rows of ``costs`` (N, 2), both minimised, that no other row dominates: no worse in both by more
    than ``tolerance`` and better in one by more than it."""
    costs = np.asarray(costs, dtype=float)
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), (2,))
    keep = np.ones(len(costs), dtype=bool)
    for i, c in enumerate(costs):
        no_worse = np.all(costs <= c + tol, axis=1)
        better = np.any(costs < c - tol, axis=1)
        keep[i] = not np.any(no_worse & better)
    return keep


def _classify(points: list[FrontPoint], sense1: str, sense2: str) -> None:
    """Mark the optimal points that another optimal point dominates (beyond DOMINANCE of each span)."""
    good = [p for p in points if p.status == "optimal"]
    if len(good) < 2:
        return
    costs = minimised(np.array([p.verified_objective for p in good]), np.array([p.verified_secondary for p in good]),
                       (sense1, sense2))
    span = np.ptp(costs, axis=0)
    keep = non_dominated(costs, DOMINANCE * np.where(span > 0, span, 1.0))
    for p, kept in zip(good, keep, strict=True):
        if not kept:
            p.status = "dominated"


def hypervolume(costs: np.ndarray, reference: np.ndarray) -> float:
    """The area (both objectives minimised) that the points (N, 2) dominate up to the reference point."""
    costs = np.asarray(costs, dtype=float).reshape(-1, 2)
    costs = costs[np.all(np.isfinite(costs), axis=1) & np.all(costs < reference, axis=1)]
    if not len(costs):
        return 0.0
    costs = costs[non_dominated(costs)]
    costs = costs[np.argsort(costs[:, 0])]
    heights = reference[1] - costs[:, 1]
    widths = np.diff(np.append(costs[:, 0], reference[0]))
    return float(np.sum(widths * np.maximum.accumulate(heights)))


def compare_fronts(front: ParetoFront) -> None:
    """Every front's hypervolume from one reference point (the pkm front's nadir moved out by REFERENCE_MARGIN
    of its spans), how many of the pkm front's points each baseline dominates (no worse in both objectives and
    better in one, beyond DOMINANCE of the front's span), and how many it beats in both objectives by more than
    the point's accuracy (in each, the change of the point's value from the optimiser's quadrature to the
    verification's, at least DOMINANCE of the span): the points a baseline shows off the front at the accuracy
    pkm states."""
    senses = (front.objective["sense"], front.secondary["sense"])
    good = front.optimal
    if not good:
        return
    costs = minimised(np.array([p.verified_objective for p in good]), np.array([p.verified_secondary for p in good]),
                       senses)
    span = np.ptp(costs, axis=0)
    reference = costs.max(axis=0) + REFERENCE_MARGIN * np.where(span > 0, span, np.abs(costs.max(axis=0)) + 1.0)
    front.reference = reference.tolist()
    front.hypervolume = hypervolume(costs, reference)
    tolerance = DOMINANCE * np.where(span > 0, span, 1.0)
    changes = np.array([[abs(p.verified_objective - p.objective), abs(p.verified_secondary - p.secondary)]
                        for p in good])
    accuracy = np.maximum(tolerance, changes)
    for base in front.baselines.values():
        theirs = minimised(np.array(base.objective), np.array(base.secondary), senses).reshape(-1, 2)
        base.hypervolume = hypervolume(theirs, reference)
        base.dominating = int(sum(np.any(np.all(theirs <= c + tolerance, axis=1) & np.any(theirs < c - tolerance,
                                                                                         axis=1)) for c in costs))
        base.dominating_beyond_accuracy = int(sum(np.any(np.all(theirs < c - a, axis=1))
                                                  for c, a in zip(costs, accuracy, strict=True)))


def _front_of(model: ProblemModel, points: np.ndarray, resolution: int, senses: tuple[str, str]
              ) -> tuple[np.ndarray, np.ndarray]:
    """The non-dominated feasible (f1, f2) of the variable points (N, n) on the model with the secondary as its
    last, unbounded constraint: those at the resolution, verified as the front's points are (twice the
    resolution, extremes refined), those still non-dominated and feasible."""
    f1, g = model.values(points, resolution)
    tol = model.problem.feasibility_tolerance
    with np.errstate(invalid="ignore"):
        ok = np.all((g[:, :-1] >= model.lower[:-1] - tol) & (g[:, :-1] <= model.upper[:-1] + tol), axis=1)
    ok &= np.isfinite(f1) & np.isfinite(g[:, -1])
    points = points[ok][non_dominated(minimised(f1[ok], g[ok, -1], senses))]
    verified = []
    for point in points:
        design = np.asarray(model.problem.design(list(point)), dtype=float).ravel()
        f, g_at = model.verified_values(point, design, 2 * resolution)
        if np.isfinite(f) and np.isfinite(g_at[-1]) and _feasible_except_last(model, g_at):
            verified.append((f, g_at[-1]))
    if not verified:
        return np.zeros(0), np.zeros(0)
    f1, f2 = np.array(verified).T
    keep = non_dominated(minimised(f1, f2, senses))
    order = np.argsort(f2[keep])
    return f1[keep][order], f2[keep][order]


def grid_front(model: ProblemModel, resolution: int, *, grid: int, senses: tuple[str, str], **_: Any) -> BaselineFront:
    """The grid baseline: every node of a regular grid over the variables' bounds, its non-dominated feasible
    points."""
    t0 = time.perf_counter()
    points = grid_points(model.problem.variables, check_integer("grid", grid, 2, 10_001))
    f1, f2 = _front_of(model, points, resolution, senses)
    return BaselineFront("grid", f"the non-dominated feasible nodes of a {grid}-per-variable grid over the bounds",
                         f1.tolist(), f2.tolist(), len(points), time.perf_counter() - t0)


def nsga2_front(model: ProblemModel, resolution: int, *, nsga: tuple[int, int], senses: tuple[str, str],
                seed: int = NSGA_SEED, budget: float | None = None, **_: Any) -> BaselineFront:
    """pymoo's NSGA-II on the same model (its objectives both minimised, the constraints as g <= 0 violations,
    an undefined model as a large violation): population and generations ``nsga``, or with ``budget`` as many
    generations as fit in that many seconds; its last population's non-dominated feasible points."""
    try:
        from pymoo.algorithms.moo.nsga2 import NSGA2
        from pymoo.core.problem import Problem as PymooProblem
    except ImportError:
        raise PkmError(NSGA_MISSING) from None
    population, generations = nsga
    prob = model.problem
    lower = np.array([v.lower for v in prob.variables])
    upper = np.array([v.upper for v in prob.variables])
    bounded = [(k, lo, hi) for k, (lo, hi) in enumerate(zip(model.lower[:-1], model.upper[:-1], strict=True))]

    class Wrapped(PymooProblem):
        def __init__(self) -> None:
            super().__init__(n_var=len(lower), n_obj=2, n_ieq_constr=max(1, 2 * len(bounded)), xl=lower, xu=upper)

        def _evaluate(self, x: np.ndarray, out: dict[str, Any], *_: Any, **__: Any) -> None:
            f1, g = model.values(x, resolution)
            costs = minimised(f1, g[:, -1], senses)
            undefined = ~np.all(np.isfinite(costs), axis=1) | ~np.all(np.isfinite(g), axis=1)
            rows = [col for k, lo, hi in bounded for col in (lo - g[:, k], g[:, k] - hi)] or [np.zeros(len(x))]
            violation = np.stack(rows, axis=1)
            violation = np.where(np.isfinite(violation), violation, 0.0)
            violation[undefined] = 1e6
            out["F"] = np.where(undefined[:, None], 1e12, costs)
            out["G"] = violation

    t0 = time.perf_counter()
    algorithm = NSGA2(pop_size=population)
    algorithm.setup(Wrapped(), termination=("n_gen", generations if budget is None else 10**9), seed=seed,
                    verbose=False)
    while algorithm.has_next():
        algorithm.next()
        if budget is not None and time.perf_counter() - t0 >= budget:
            break
    evaluations = int(algorithm.evaluator.n_eval)
    final = algorithm.pop.get("X")
    f1, f2 = _front_of(model, final, resolution, senses)
    return BaselineFront("nsga2", f"pymoo's NSGA-II, population {population}, seed {seed}, its last population's "
                         "non-dominated feasible points", f1.tolist(), f2.tolist(), evaluations,
                         time.perf_counter() - t0)


BASELINES = {"grid": grid_front, "nsga2": nsga2_front}


def _csv(front: ParetoFront) -> str:
    """One row per point: its values, its variables, then the rest of its design (every parameter)."""
    names = list(front.points[0].variables) if front.points else []
    held = [n for n in (front.points[0].design if front.points else {}) if n not in names]
    columns = ["epsilon", "status", "ipopt_status", "objective", "secondary", "verified_objective",
               "verified_secondary", "multiplier", "trade_off", "iterations", "evaluations", "wall_time_s", *names,
               *held]
    rows = [[p.epsilon, p.status, p.ipopt_status, p.objective, p.secondary, p.verified_objective,
             p.verified_secondary, p.multiplier, p.trade_off, p.iterations, p.evaluations, p.wall_time_s,
             *p.variables.values(), *(p.design.get(n, float("nan")) for n in held)] for p in front.points]
    return io.csv_text(columns, rows)


MARKERS = {"optimal": ("o", "C0"), "dominated": ("s", "C3"), "infeasible": ("x", "C3"), "failed": ("X", "k")}


def figure(front: ParetoFront) -> Any:
    """The front (f2 across, f1 up) by status, with each baseline's points."""
    from pkm.figures import figure as new_figure

    fig = new_figure(6.4, 4.6)
    ax = fig.add_subplot()
    for kind, base in front.baselines.items():
        ax.plot(base.secondary, base.objective, ".", ms=5, alpha=0.6,
                label=f"{kind}: {base.evaluations} evaluations, {base.wall_time_s:.1f} s")
    good = [p for p in front.points if p.status in ("optimal", "dominated")]
    ax.plot([p.verified_secondary for p in good], [p.verified_objective for p in good], "-", color="C0", lw=1)
    for status, (marker, colour) in MARKERS.items():
        mine = [p for p in front.points if p.status == status and np.isfinite(p.verified_objective)]
        if mine:
            ax.plot([p.verified_secondary for p in mine], [p.verified_objective for p in mine], marker, color=colour,
                    ms=7, mfc="none" if status != "optimal" else colour,
                    label=f"pkm {status}" + (f": {front.evaluations} evaluations, {front.wall_time_s:.1f} s"
                                             if status == "optimal" else ""))
    ax.set_xlabel(f"{front.secondary['name']} ({'larger' if front.secondary['sense'] == 'max' else 'smaller'} "
                  "is better)")
    ax.set_ylabel(f"{front.objective['name']} ({'larger' if front.objective['sense'] == 'max' else 'smaller'} "
                  "is better)")
    ax.set_title(f"{front.problem}: verified epsilon-constraint front", fontsize=10)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def report(front: ParetoFront) -> str:
    """A reproduction-style report: the problem, the front point by point, the baselines."""
    lines = [f"# Pareto front of {front.problem}", "",
             f"{front.objective['name']} ({front.objective['sense']}imised: {front.objective['doc']}) against "
             f"{front.secondary['name']} ({front.secondary['sense']}imised: {front.secondary['doc']}), by the "
             f"epsilon-constraint method at quadrature resolution {front.resolution}, each point verified at "
             f"{2 * front.resolution} (region extremes refined between the nodes).", "",
             f"{len(front.points)} points, {len(front.optimal)} optimal; {front.iterations} IPOPT iterations, "
             f"{front.evaluations} evaluations, {front.wall_time_s:.2f} s; hypervolume {front.hypervolume:.6g} from "
             f"the reference point {[float(f'{v:.6g}') for v in front.reference]} (both objectives as minimised).",
             "", "![front](front.png)", "",
             "| epsilon | verified objective | verified secondary | trade-off d f1/d f2 | status | IPOPT "
             "| iterations |",
             "|---|---|---|---|---|---|---|"]
    for p in front.points:
        lines.append(f"| {p.epsilon:.6g} | {p.verified_objective:.8g} | {p.verified_secondary:.8g} | "
                     f"{p.trade_off:.6g} | {p.status} | {p.ipopt_status} | {p.iterations} |")
    if front.baselines:
        lines += ["", "| method | points on its front | evaluations | wall time [s] | hypervolume | pkm points it "
                  "dominates | beyond their accuracy in both |", "|---|---|---|---|---|---|---|",
                  f"| pkm (IPOPT) | {len(front.optimal)} | {front.evaluations} | {front.wall_time_s:.2f} | "
                  f"{front.hypervolume:.6g} | - | - |"]
        lines += [f"| {b.name} | {len(b.objective)} | {b.evaluations} | {b.wall_time_s:.2f} | {b.hypervolume:.6g} | "
                  f"{b.dominating} | {b.dominating_beyond_accuracy} |" for b in front.baselines.values()]
    return "\n".join(lines) + "\n"
