"""Pareto fronts by the epsilon-constraint method, each point an IPOPT optimum, verified (DESIGN.md section 6).

A problem's objective f1 is traded against a secondary objective f2 (one of the problem's quantities, or one of
its ``secondaries``). :func:`pareto` solves the two anchors (f1 alone and f2 alone, :func:`pkm.synthesize` from
several starts), then, for epsilons placed by the front's own shape between f2 at the first anchor and f2 at
the second (each new one where two neighbours leave the largest box, :func:`_place`),

    optimise f1  subject to  f2 <= epsilon (f2 >= epsilon where larger f2 is better)  and the problem's constraints,

each point by IPOPT from each of its two neighbours (the anchors where that fails), with exact derivatives, the
better kept; an epsilon whose optimum is a design already found adds no point (a plateau of the front, or a
jump). The points are then polished to one resolution where each is verified to ``ACCURACY``, and each that a
baseline's point dominates beyond its accuracy (verified at the same resolution) is solved again from it. At
its solution the multiplier lambda of the epsilon constraint (IPOPT's, of the NLP that minimises s1 f1, s1 =
+1 to minimise and -1 to maximise) is the front's local slope: d f1* / d epsilon =
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
from collections.abc import Callable, Iterable, Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from pkm.errors import ComputationError, PkmError, UnknownNameError, check_integer
from pkm.progress import Progress
from pkm.synthesis.driver import (
    ACCURACY,
    POLISH_LIMIT,
    StartTask,
    SynthesisError,
    SynthesisResult,
    ipopt_options,
    nlp_solver,
    solve_from,
    synthesize,
)
from pkm.synthesis.front import BaselineFront, FrontPoint, ParetoFront, hypervolume, minimised, non_dominated
from pkm.synthesis.model import ProblemModel
from pkm.synthesis.problem import Constraint, Objective, Problem, grid_points

DOMINANCE = 1e-6  # relative to an objective's span on the front: a point better by less is not better
SAME_DESIGN = 1e-6  # two points whose variables are this close (of each variable's span) are one design
SOLVES_PER_POINT = 3  # epsilon-constraint solves per point asked at most (epsilons on designs already found)
OPEN_BOX = 1e-9  # a gap whose box (scaled by the ends' spans) is this small is closed
REFERENCE_MARGIN = 0.1  # the hypervolume's reference point lies this far (of each span) beyond the front's nadir
MAX_POINTS = 1000
AUTO_POINTS = 64  # the most points of a front whose count is not given
FRONT_TOLERANCE = 5e-3  # a front whose count is not given grows until its open boxes sum to this share of the ends' box
GRID = 21  # grid nodes per variable of the grid baseline
NSGA_POPULATION = 40
NSGA_GENERATIONS = 25
NSGA_SEED = 0
NSGA_MISSING = "the nsga2 baseline needs pymoo: pip install pymoo"  # refused before the front is computed
EPSILON = "epsilon"  # the name of the epsilon constraint
COMPASS_STEP = 1e-9  # the anchors' compass search stops at this step, of each variable's span
COMPASS_ITERATIONS = 2000  # moves and halvings at most
COMPASS_GAIN = 1e-14  # a move must improve the objective by this much, relative: round-off never leads it


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
    n: int | None = None,
    tolerance: float = FRONT_TOLERANCE,
    epsilons: Sequence[float] | None = None,
    resolution: int | None = None,
    baselines: Sequence[str] = ("grid",),
    grid: int = GRID,
    nsga: tuple[int, int] = (NSGA_POPULATION, NSGA_GENERATIONS),
    starts: int | None = None,
    progress: Callable[[int, int], object] | bool | None = None,
) -> ParetoFront:
    """The front of the problem's objective against ``secondary`` by the epsilon-constraint method (module
    docstring): ``n`` distinct designs from one anchor to the other placed by the front's shape, or where ``n``
    is not given as many (at most AUTO_POINTS) as it takes for the boxes the points leave open to sum to
    ``tolerance`` of the anchors' box (the front's ``open_hypervolume``), or at the given ``epsilons``; at the
    problem's resolution, every point then polished to one resolution where both objectives are verified to
    ACCURACY, or at ``resolution`` where it is given, unpolished (verification at twice it); ``baselines``
    among ``"grid"`` (``grid`` nodes per variable) and ``"nsga2"`` (pymoo's NSGA-II, ``nsga`` = (population,
    generations)),
    each on the same model; ``starts`` IPOPT starts of each anchor; ``progress(done, total)`` after each point
    (a bar on a terminal by default, False: nothing)."""
    name, second, problem = secondary_objective(problem, secondary)
    count = check_integer("n", len(epsilons) if epsilons is not None else AUTO_POINTS if n is None else n, 2,
                          MAX_POINTS)
    if not (isinstance(tolerance, int | float) and 0 < tolerance < 1):
        raise PkmError(f"tolerance = {tolerance!r} violates 0 < tolerance < 1 (a share of the anchors' box)")
    unknown = sorted(set(baselines) - set(BASELINES))
    if unknown:
        raise UnknownNameError("baseline of a Pareto front", unknown[0], list(BASELINES))
    if "nsga2" in baselines and importlib.util.find_spec("pymoo") is None:
        raise PkmError(NSGA_MISSING)
    res = check_integer("resolution", problem.resolution if resolution is None else resolution, 1, 1024)
    options = ipopt_options(problem, verbose=False, max_iter=None, tol=None, print_level=None)
    measure = ProblemModel(_with_epsilon(problem, second, None))
    total = 2 + (count - 2 if epsilons is None else count) + len(baselines)
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
        if epsilons is None:
            points, missing = _place(problem, second, ends, g[:, -1], count, res=res, options=options, step=step,
                                     tolerance=tolerance if n is None else 0.0)
        else:
            points, missing = _march(problem, second, np.asarray(epsilons, dtype=float), ends, res=res,
                                     options=options, step=step), float("nan")
        _classify(points, problem.objective.sense, second.sense)
        _repair(problem, second, points, res=res, options=options)
        if resolution is None:
            points = _polished(problem, second, points, options)
        _classify(points, problem.objective.sense, second.sense)
        found = {}
        for kind in baselines:
            found[kind] = BASELINES[kind](measure, res, grid=grid, nsga=nsga, senses=(problem.objective.sense,
                                                                                       second.sense))
            step()
        _repair_from(problem, second, points, found.values(), model=measure, options=options)
        evaluations = sum(a.optimizer["evaluations"] for a in anchors) + sum(p.evaluations for p in points)
        iterations = sum(a.iterations for a in anchors) + sum(p.iterations for p in points)
        wall = time.perf_counter() - t0 - sum(b.wall_time_s for b in found.values())
    front = ParetoFront(
        problem=problem.name,
        objective={"name": problem.objective.quantity or "objective", "sense": problem.objective.sense,
                   "doc": problem.objective.doc},
        secondary={"name": name, "sense": second.sense, "doc": second.doc},
        points=points, baselines=found, reference=[], hypervolume=float("nan"), open_hypervolume=missing,
        resolution=res, wall_time_s=wall,
        evaluations=int(evaluations), iterations=int(iterations),
        anchors={kind: {"objective": float(f1[k]), "secondary": float(g[k, -1]), "status": a.status,
                        "variables": a.variables}
                 for k, (kind, a) in enumerate(zip(("objective", "secondary"), anchors, strict=True))},
    )
    compare_fronts(front, measure)
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
    multiplier = run.multipliers[-1] if run.multipliers else float("nan")
    point = _evaluated(model, epsilon, np.array(list(run.variables.values())), res, run.status,
                       multiplier=float(multiplier))
    if not run.success:
        point.status = "failed"
    point.objective, point.iterations, point.evaluations = run.objective, iterations, evaluations
    point.wall_time_s = time.perf_counter() - t1
    return point


def _evaluated(model: ProblemModel, epsilon: float, point: np.ndarray, res: int, status: str, *,
               multiplier: float = float("nan")) -> FrontPoint:
    """The front's point at the variables ``point`` of the model with the epsilon constraint: its objectives at
    the resolution and verified at twice it, ``optimal`` where the verified values hold the other constraints."""
    problem = model.problem
    design = np.asarray(problem.design(list(point)), dtype=float).ravel()
    f_at, g_at = model.values(point[None], res)
    verified, g = model.verified_values(point, design, 2 * res)
    held = _feasible_except_last(model, g) and np.isfinite(verified)
    sign = 1.0 if problem.objective.sense == "min" else -1.0
    return FrontPoint(
        epsilon=epsilon, status="optimal" if held else "infeasible", ipopt_status=status,
        variables={v.name: float(x) for v, x in zip(problem.variables, point, strict=True)},
        design=problem.mechanism.design_dict(design), objective=float(f_at[0]), secondary=float(g_at[0, -1]),
        verified_objective=float(verified), verified_secondary=float(g[-1]), multiplier=multiplier,
        trade_off=-sign * multiplier, iterations=0, evaluations=0, wall_time_s=0.0, resolution=res,
    )


def _end(problem: Problem, second: Objective, anchor: np.ndarray, epsilon: float, *, res: int,
         options: dict[str, Any]) -> FrontPoint:
    """A front's end: the epsilon-constraint optimum at the anchor's own secondary value, from the anchor; the
    anchor itself where IPOPT ends elsewhere no better (an anchor at a kink, where the feasible set is the
    anchor alone)."""
    point = _point(problem, second, epsilon, [anchor], res=res, options=options)
    own = _evaluated(ProblemModel(_with_epsilon(problem, second, epsilon)), epsilon, anchor, res, "anchor")
    sign = 1.0 if problem.objective.sense == "min" else -1.0
    if point.status == "optimal" and sign * point.verified_objective <= sign * own.verified_objective:
        return point
    own.iterations, own.evaluations = point.iterations, point.evaluations
    return own


def _costs(p: FrontPoint, senses: tuple[str, str]) -> np.ndarray:
    return minimised(np.array([p.verified_objective]), np.array([p.verified_secondary]), senses)[0]


def _same(a: FrontPoint, b: FrontPoint, span: np.ndarray) -> bool:
    """Whether two points are one design (their variables within SAME_DESIGN of each variable's span)."""
    gap = np.abs(np.array(list(a.variables.values())) - np.array(list(b.variables.values())))
    return bool(np.all(gap <= SAME_DESIGN * span))


def _place(problem: Problem, second: Objective, ends: np.ndarray, secondary: np.ndarray, count: int, *, res: int,
           options: dict[str, Any], step: Callable[[], None], tolerance: float) -> tuple[list[FrontPoint], float]:
    """``count`` distinct designs of the front (fewer where the open boxes' sum falls to ``tolerance``, of the
    ends' box) placed by its own shape: the two ends, then each new epsilon in
    the middle of the open part of the gap between two neighbours that leaves the largest box (the product of
    the gaps in the two objectives, both minimised and scaled by the ends' spans: the most hypervolume the
    front can still gain there), solved from each of its two neighbours (the one that the epsilon leaves
    feasible may hold IPOPT on its own plateau) and the better kept. An epsilon whose optimum is a design already
    found closes the part of its gap that design covers (a plateau of the front, or a gap where it jumps) and
    adds no point; at most SOLVES_PER_POINT solves per point asked. The points from the objective's end to the
    secondary's, failed ones among them by their epsilon, and the open boxes' area: the most hypervolume the
    points can miss of the front (where every solve found its epsilon's global optimum)."""
    senses = (problem.objective.sense, second.sense)
    s2 = 1.0 if second.sense == "min" else -1.0
    span = np.array([v.upper - v.lower for v in problem.variables])
    first, last = (_end(problem, second, e, float(g), res=res, options=options) for e, g in zip(ends, secondary,
                                                                                               strict=True))
    points, failed = [last, first], []  # by the secondary's cost, ascending: the secondary's end first
    opened = [s2 * last.epsilon]  # per gap (points[k], points[k + 1]): the least epsilon cost still open
    scale = np.abs(_costs(first, senses) - _costs(last, senses))
    scale = np.where(scale > 0, scale, 1.0)
    solves = 0
    def boxes() -> list[float]:
        return [max(0.0, (_costs(points[k], senses)[0] - _costs(points[k + 1], senses)[0]) / scale[0]
                    * (_costs(points[k + 1], senses)[1] - opened[k]) / scale[1]) for k in range(len(opened))]

    while len(points) < count and solves < SOLVES_PER_POINT * count:
        open_boxes = boxes()
        k = int(np.argmax(open_boxes))
        if not open_boxes[k] > OPEN_BOX or sum(open_boxes) <= tolerance:
            break
        left, right = points[k], points[k + 1]
        cost = (opened[k] + _costs(right, senses)[1]) / 2
        found = _best([_point(problem, second, s2 * cost, [np.array(list(q.variables.values())), *ends], res=res,
                              options=options) for q in (left, right)], problem.objective.sense)
        solves += 1
        if found.status == "failed":
            failed.append(found)
            opened[k] = cost
            continue
        if any(_same(found, q, span) for q in points) or _costs(found, senses)[1] > cost:
            opened[k] = cost
            continue
        points.insert(k + 1, found)
        opened[k:k + 1] = [opened[k], cost]
        step()
    return sorted([*points, *failed], key=lambda p: -s2 * p.epsilon), float(sum(boxes()) * scale[0] * scale[1])


def _best(tries: list[FrontPoint], sense: str) -> FrontPoint:
    """The best of several solves of one epsilon: an optimal one of the best verified objective, else the
    first."""
    sign = 1.0 if sense == "min" else -1.0
    good = [p for p in tries if p.status == "optimal"]
    return min(good, key=lambda p: sign * p.verified_objective) if good else tries[0]


def _polished(problem: Problem, second: Objective, points: list[FrontPoint], options: dict[str, Any]
              ) -> list[FrontPoint]:
    """The front's optimal points solved again at their epsilons, each from itself, at doubled resolutions
    until both objectives of every point change by at most ACCURACY (relative above 1) from the optimiser's
    quadrature to the verification's, or POLISH_LIMIT: one resolution for the whole front, so that neighbours
    and their trade-off rates compare; an end kept as its anchor (where IPOPT ends elsewhere no better, :func:`_end`)
    is evaluated again at each resolution, not solved. A point whose run fails or ends infeasible keeps its last
    good one."""
    resolution = min((p.resolution for p in points if p.status == "optimal"), default=POLISH_LIMIT)
    while 2 * resolution <= POLISH_LIMIT:
        good = [k for k, p in enumerate(points) if p.status == "optimal"]
        scale = [np.maximum(1.0, np.abs([points[k].verified_objective, points[k].verified_secondary])) for k in good]
        if all(np.all(np.array(points[k].accuracy) <= ACCURACY * c) for k, c in zip(good, scale, strict=True)):
            break
        resolution *= 2
        for k in good:
            at = np.array(list(points[k].variables.values()))
            if points[k].ipopt_status == "anchor":  # an end IPOPT does not improve on: evaluated again
                again = _evaluated(ProblemModel(_with_epsilon(problem, second, points[k].epsilon)),
                                   points[k].epsilon, at, resolution, "anchor")
            else:
                again = _point(problem, second, points[k].epsilon, [at], res=resolution, options=options)
            again.iterations += points[k].iterations
            again.evaluations += points[k].evaluations
            if again.status == "optimal":
                points[k] = again
    return points


def _repair_from(problem: Problem, second: Objective, points: list[FrontPoint], baselines: Iterable[BaselineFront],
                 *, model: ProblemModel, options: dict[str, Any]) -> None:
    """Each point that a baseline's point dominates beyond the point's accuracy (verified again at the point's
    verification resolution on the front's ``model``: a local optimum of its epsilon) solved again at its
    epsilon from that baseline's design, kept where it is better, then polished."""
    senses = (problem.objective.sense, second.sense)
    sign = 1.0 if problem.objective.sense == "min" else -1.0
    resolution = 2 * max((p.resolution for p in points if p.status == "optimal"), default=0)
    for base in baselines:
        reverify(model, base, resolution, senses)
        theirs = minimised(np.array(base.objective), np.array(base.secondary), senses).reshape(-1, 2)
        for k, p in enumerate(points):
            if p.status != "optimal":
                continue
            beyond = np.all(theirs < _costs(p, senses) - np.array(p.accuracy), axis=1)
            if not beyond.any():
                continue
            start = np.array(base.variables[int(np.flatnonzero(beyond)[0])])
            again = _point(problem, second, p.epsilon, [start], res=p.resolution, options=options)
            again.iterations += p.iterations
            again.evaluations += p.evaluations
            if again.status == "optimal" and sign * again.verified_objective < sign * p.verified_objective:
                points[k] = again
    _classify(points, problem.objective.sense, second.sense)


def _feasible_except_last(model: ProblemModel, g: np.ndarray) -> bool:
    """Whether the constraint values (m,) hold every constraint but the last (the epsilon constraint)."""
    tol = model.problem.feasibility_tolerance
    with np.errstate(invalid="ignore"):
        return bool(np.all((g[:-1] >= model.lower[:-1] - tol) & (g[:-1] <= model.upper[:-1] + tol)))


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


def compare_fronts(front: ParetoFront, model: ProblemModel | None = None) -> None:
    """Every front's hypervolume from one reference point (the pkm front's nadir moved out by REFERENCE_MARGIN
    of its spans), how many of the pkm front's points each baseline dominates (no worse in both objectives and
    better in one, beyond DOMINANCE of the front's span), and how many it beats in both objectives by more than
    the point's accuracy (in each, the change of the point's value from the optimiser's quadrature to the
    verification's, at least DOMINANCE of the span): the points a baseline shows off the front at the accuracy
    pkm states. With the front's ``model`` (:func:`front_model`), each baseline's points are first verified
    again at the front's verification resolution (:func:`reverify`: the front's points are polished finer than
    a baseline is verified), so that all compare at one accuracy."""
    senses = (front.objective["sense"], front.secondary["sense"])
    good = front.optimal
    if not good:
        return
    if model is not None:
        for base in front.baselines.values():
            reverify(model, base, 2 * max(p.resolution for p in good), senses)
    costs = np.array([_costs(p, senses) for p in good])
    span = np.ptp(costs, axis=0)
    reference = costs.max(axis=0) + REFERENCE_MARGIN * np.where(span > 0, span, np.abs(costs.max(axis=0)) + 1.0)
    front.reference = reference.tolist()
    front.hypervolume = hypervolume(costs, reference)
    tolerance = DOMINANCE * np.where(span > 0, span, 1.0)
    accuracy = np.maximum(tolerance, np.array([p.accuracy for p in good]))
    for base in front.baselines.values():
        theirs = minimised(np.array(base.objective), np.array(base.secondary), senses).reshape(-1, 2)
        base.hypervolume = hypervolume(theirs, reference)
        base.dominating = int(sum(_dominates(theirs, c, tolerance).any() for c in costs))
        base.dominating_beyond_accuracy = int(sum(np.all(theirs < c - a, axis=1).any()
                                                  for c, a in zip(costs, accuracy, strict=True)))


def _dominates(costs: np.ndarray, c: np.ndarray, tolerance: np.ndarray) -> np.ndarray:
    """Mask of the costs (N, 2), both minimised, that dominate c beyond ``tolerance``."""
    return np.all(costs <= c + tolerance, axis=1) & np.any(costs < c - tolerance, axis=1)


def reverify(model: ProblemModel, base: BaselineFront, resolution: int, senses: tuple[str, str]) -> None:
    """A baseline's points verified again at ``resolution`` (where they were verified at another and their
    variables are known), its non-dominated feasible ones kept."""
    if base.resolution == resolution or len(base.variables) != len(base.objective) or not base.variables:
        return
    f1, f2, points = _verified_front(model, np.array(base.variables), resolution, senses)
    base.objective, base.secondary, base.variables = f1.tolist(), f2.tolist(), points.tolist()
    base.resolution = resolution


def _verified_front(model: ProblemModel, points: np.ndarray, resolution: int, senses: tuple[str, str]
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The variable points verified at ``resolution``: the objectives (f1, f2) of those feasible and
    non-dominated there, by f2, and their variables."""
    costs = _verified(model, points, resolution, senses)
    held = np.all(np.isfinite(costs), axis=1)
    costs, points = costs[held], points[held]
    keep = non_dominated(costs)
    signs = np.array([1.0 if sense == "min" else -1.0 for sense in senses])
    f1, f2 = (costs[keep] * signs).T
    order = np.argsort(f2)
    return f1[order], f2[order], points[keep][order]


def _verified(model: ProblemModel, points: np.ndarray, resolution: int, senses: tuple[str, str]) -> np.ndarray:
    """The costs (N, 2), both minimised, of the variable points verified at ``resolution`` (extremes refined);
    infinite where a point is infeasible or undefined there."""
    out = np.full((len(points), 2), np.inf)
    for k, point in enumerate(points):
        design = np.asarray(model.problem.design(list(point)), dtype=float).ravel()
        f, g = model.verified_values(point, design, resolution)
        if np.isfinite(f) and np.isfinite(g[-1]) and _feasible_except_last(model, g):
            out[k] = minimised(np.array([f]), np.array([g[-1]]), senses)[0]
    return out


def _front_of(model: ProblemModel, points: np.ndarray, resolution: int, senses: tuple[str, str]
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The non-dominated feasible (f1, f2) of the variable points (N, n) on the model with the secondary as its
    last, unbounded constraint, and their variables: those at the resolution, verified as the front's points
    are (twice the resolution, extremes refined), those still non-dominated and feasible."""
    f1, g = model.values(points, resolution)
    tol = model.problem.feasibility_tolerance
    with np.errstate(invalid="ignore"):
        ok = np.all((g[:, :-1] >= model.lower[:-1] - tol) & (g[:, :-1] <= model.upper[:-1] + tol), axis=1)
    ok &= np.isfinite(f1) & np.isfinite(g[:, -1])
    points = points[ok][non_dominated(minimised(f1[ok], g[ok, -1], senses))]
    return _verified_front(model, points, 2 * resolution, senses)


def grid_front(model: ProblemModel, resolution: int, *, grid: int, senses: tuple[str, str], **_: Any) -> BaselineFront:
    """The grid baseline: every node of a regular grid over the variables' bounds, its non-dominated feasible
    points."""
    t0 = time.perf_counter()
    points = grid_points(model.problem.variables, check_integer("grid", grid, 2, 10_001))
    f1, f2, variables = _front_of(model, points, resolution, senses)
    return BaselineFront("grid", f"the non-dominated feasible nodes of a {grid}-per-variable grid over the bounds",
                         f1.tolist(), f2.tolist(), len(points), time.perf_counter() - t0, variables.tolist(),
                         2 * resolution)


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
    f1, f2, variables = _front_of(model, final, resolution, senses)
    return BaselineFront("nsga2", f"pymoo's NSGA-II, population {population}, seed {seed}, its last population's "
                         "non-dominated feasible points", f1.tolist(), f2.tolist(), evaluations,
                         time.perf_counter() - t0, variables.tolist(), 2 * resolution)


BASELINES = {"grid": grid_front, "nsga2": nsga2_front}


