"""The one synthesis driver: screen, IPOPT from several starts, verify, compare with the baselines.

:func:`synthesize` evaluates the problem on a screening grid over the variables' bounds (plus the
problem's own starting points), runs IPOPT through ``casadi.nlpsol`` with exact first and (unless the
problem says otherwise) second derivatives from the best feasible screening points, verifies every
converged optimum with a quadrature 4x denser and by sampling each quantity on a grid of its region
(runs that end at the same point, within ``SAME_POINT``, share one verification), and reports the best
by its verified objective, never by the optimiser's quadrature. The optimiser's wall time covers the
screening, the starts and these verifications (and the polishing below). At the problem's own
resolution the best optimum is then polished: IPOPT runs again from it at twice the resolution until the
verified objective agrees with the optimised one to ``ACCURACY`` (relative above 1) or POLISH_LIMIT is
reached; the result states the accuracy reached. A problem with region extremes is refined instead by an
exchange over its regions: its constraints drop the node margins that stood in for the points between the
nodes, and each extreme is held at the points between the nodes where the verification finds it, one more
each round, until the optimised objective agrees with the verified one to ``ACCURACY``. Each baseline
(the papers' own search) runs through the same model, timed and counted, and its best point is
verified the same way. The starts and the baselines' chunks of points are tasks of names and numbers
(:mod:`pkm.parallel`): for a registered problem they run where the executor says, with the same results.
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, field, replace
from functools import lru_cache, partial
from typing import Any, NamedTuple

import casadi as ca
import numpy as np

from pkm import parallel, registry
from pkm.catalogue import problem_integrands
from pkm.compiled import build
from pkm.errors import ComputationError, PkmError, check_integer, check_real
from pkm.interrupts import interruptible
from pkm.progress import Progress
from pkm.regions import INDEX_ACCURACY
from pkm.regions.shapes import MAX_RESOLUTION
from pkm.synthesis.model import Candidate, ConstraintValue, Points, ProblemModel
from pkm.synthesis.problem import Problem, grid_points

ACCURACY = INDEX_ACCURACY
POLISH_LIMIT = 64  # the largest quadrature resolution a polishing run uses
REFINE_ROUNDS = 12  # IPOPT solves of the exchange over the regions of a problem with region extremes at most
EXTREME_SEARCH = 16  # the exchange also looks for each extreme from the nodes of this resolution: at coarse
# nodes the refinement between them can settle in another basin than the extreme's
EXCHANGE_ROUNDS = 20  # IPOPT solves of one start of a problem with region extremes at most
SAME_POINT = 1e-8  # runs that end this close (relative to each variable's range) share one verification


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
    multipliers: list[float] = field(default_factory=list)  # IPOPT's of the problem's constraints, in order


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
    settings: dict[str, float] = field(default_factory=dict)
    mode: str = ""
    regions: dict[str, str] = field(default_factory=dict)
    objective_unit: str = ""
    margin: str = ""  # the singularity margin the problem holds over its task, stated

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
    def accuracy(self) -> float:
        """The change of the optimum's objective from the optimiser's quadrature to the verification's."""
        return abs(self.optimum.objective - self.optimum.verified_objective)

    @property
    def baseline(self) -> Candidate | None:
        """The best point of the first baseline (None for a problem without baselines)."""
        first = next(iter(self.baselines.values()), None)
        return None if first is None else first.best

    def __str__(self) -> str:
        o = self.optimum
        design = ", ".join(f"{k} = {v:.6g}" for k, v in o.design.items())
        variables = ", ".join(f"{k} = {v:.6g}" for k, v in o.variables.items())
        return "\n".join([
            f"{self.problem}: {self.status} after {self.iterations} iterations; {self.sense}imum objective "
            f"{o.objective:.6g}, verified {o.verified_objective:.6g} (accuracy {self.accuracy:.1e})"
            f"{'' if o.feasible else ' (infeasible)'} at {variables}; design {design}",
            *([self.margin] if self.margin else []), *constraint_lines(o.constraints)])

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
            "accuracy": self.accuracy,
            "baseline_objective": None if first is None else first.best.objective,
            "optimum": asdict(self.optimum),
            "constraints": [asdict(c) for c in self.optimum.constraints],
            "baseline": None
            if first is None
            else {**asdict(first.best), "wall_time_s": first.wall_time_s, "evaluations": first.evaluations},
            "baselines": {k: asdict(b) for k, b in self.baselines.items()},
            "optimizer": self.optimizer,
            "runs": [asdict(r) for r in self.runs],
            "resolutions": self.resolutions,
            "options": self.options,
            "settings": self.settings,
            "mode": self.mode,
            "regions": self.regions,
            "objective_unit": self.objective_unit,
            "margin": self.margin,
        }


def constraint_lines(constraints: list[ConstraintValue]) -> list[str]:
    """One line per constraint: its value, bounds, slack, whether active, IPOPT's multiplier."""
    lines = []
    for c in constraints:
        bounds = " <= ".join([*([f"{c.lower:.6g}"] if math.isfinite(c.lower) else []), "value",
                              *([f"{c.upper:.6g}"] if math.isfinite(c.upper) else [])])
        multiplier = "" if c.multiplier is None else f", multiplier {c.multiplier:.3g}"
        state = "active" if c.active else "inactive"
        violated = " VIOLATED" if c.slack < 0 else ""
        lines.append(f"constraint {c.name}: value {c.value:.6g} ({bounds}), slack {c.slack:.3g}, {state}"
                     f"{multiplier}{violated}")
    return lines


class SynthesisError(ComputationError):
    """A synthesis that failed (IPOPT did not converge from any start, or every converged run is
    infeasible): ``result`` is its record with the last iterate (the run with the best objective) as
    ``optimum``, in variables and design parameters, and the failing status."""

    def __init__(self, message: str, result: SynthesisResult | None) -> None:
        super().__init__(message)
        self.result = result


class InfeasibleError(SynthesisError):
    """No design found that meets the problem's constraints: the message names each constraint that none of
    the designs tried meets, with its best attainable value and the design that attains it (or, where each can
    be met alone, those that the design of least violation violates); ``result`` is the failed synthesis's
    record, None where the screening found nothing to start from. The command line exits with status 3."""


def ipopt_options(
    problem: Problem, *, verbose: bool, max_iter: int | None, tol: float | None, print_level: int | None
) -> dict[str, Any]:
    """IPOPT's options: quiet (no banner) unless ``verbose`` or a ``print_level`` is given; the variables'
    bounds are kept exactly (no relaxation), so that an optimum on a bound is reported on it. Every solve
    stops after ``max_iter`` iterations (the problem's by default, MAX_ITER at most) or MAX_WALL_TIME seconds
    of wall or CPU time, whichever comes first, with IPOPT's status (``Maximum_Iterations_Exceeded``,
    ``Maximum_WallTime_Exceeded``, ``Maximum_CpuTime_Exceeded``) as the run's."""
    max_iter = check_integer("max_iter", problem.max_iter if max_iter is None else max_iter, 0, MAX_ITER)
    tol = problem.tol if tol is None else check_real("tol", tol, "a number > 0")
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
            "max_wall_time": MAX_WALL_TIME,
            "max_cpu_time": MAX_WALL_TIME,
            "bound_relax_factor": 0.0,
        },
    }


def _named(problem: Problem, values: np.ndarray) -> dict[str, float]:
    return dict(zip(problem.variable_names, (float(v) for v in values), strict=True))


BASELINE_CHUNK = 256  # baseline points per task
MAX_ITER = 1_000_000
MAX_WALL_TIME = 300.0  # s of one IPOPT solve at most: a solve of the problems here takes seconds, and one that
# iterates on without converging ends with its status. IPOPT checks it between iterations, so a stall inside one
# step (a bound near 1e308 overflowing in the restoration phase) is kept out by the designer's MAX_BOUND instead
MAX_STARTS = 1000
MAX_BASELINE = 10_001  # grid nodes per variable of a baseline


class StartTask(NamedTuple):
    """One IPOPT run of a registered problem: its name, the start (variables), the quadrature resolution,
    IPOPT's options as JSON and the problem's settings as JSON."""

    problem: str
    start: np.ndarray
    resolution: int
    options: str
    settings: str = "{}"

    def describe(self) -> str:
        return f"IPOPT on {self.problem} from {self.start.tolist()} at resolution {self.resolution}"


class PointsTask(NamedTuple):
    """The objective and feasibility of a registered problem at points (n, n_vars)."""

    problem: str
    points: np.ndarray
    resolution: int
    settings: str = "{}"

    def describe(self) -> str:
        return f"{self.problem} at {len(self.points)} points from {self.points[0].tolist()}"


@lru_cache(maxsize=8)
def _model(name: str, settings: str) -> ProblemModel:
    return ProblemModel(registry.problem(name).configure(**json.loads(settings)))


@lru_cache(maxsize=8)
def _solver(name: str, settings: str, resolution: int, options: str) -> tuple[Any, dict[str, Any]]:
    return nlp_solver(_model(name, settings), resolution, json.loads(options))


def _settings(problem: Problem) -> str:
    """The problem's settings as JSON, which a task carries, with the singularity margin it was asked to hold."""
    margin = {} if problem.margin is None or not problem.margin.value else {
        "singularity_margin": problem.margin.value}
    return json.dumps({**problem.values, **margin}, sort_keys=True)


def _where(problem: Problem) -> dict[str, Any]:
    """The working mode, the region of each quantity a result of ``problem`` belongs to and the objective's
    unit (its quantity's where it is one quantity, else the objective's statement)."""
    m, quantity = problem.mechanism, problem.objective.quantity
    unit = m.index_unit(problem.quantities[quantity].index) if quantity is not None else problem.objective.doc
    margin = "singularity margin not stated by the problem" if problem.margin is None else str(problem.margin)
    return {"mode": m.working_mode(problem.mode).name, "objective_unit": unit, "margin": margin,
            "regions": {name: q.region.name for name, q in problem.quantities.items()}}


def _registered(problem: Problem) -> bool:
    """Whether a worker rebuilds ``problem`` from its name and settings: a registered problem, as
    registered or configured."""
    known = registry.problems().get(problem.name)
    return known is problem or (known is not None and known.build is not None and known.build is problem.build)


def nlp_solver(
    model: ProblemModel, resolution: int, options: dict[str, Any], rows: dict[str, tuple[int, ...]] | None = None,
    points: Points | None = None,
) -> tuple[Any, dict[str, Any]]:
    """IPOPT's solver of the problem at a resolution (with ``rows``, of those epigraph rows only; with
    ``points``, holding the extremes at those points between the nodes too, :meth:`ProblemModel.nlp`) and
    the bounds of its variables and constraints."""
    problem = model.problem
    nlp, lower, upper = model.nlp(resolution, rows, points)
    extra = len(model.extremes)
    solver = ca.nlpsol(problem.name.replace(".", "_"), "ipopt", nlp, options)
    bounds = {
        "lbx": [v.lower for v in problem.variables] + [-np.inf] * extra,
        "ubx": [v.upper for v in problem.variables] + [np.inf] * extra,
        "lbg": lower,
        "ubg": upper,
    }
    return solver, bounds


def solve_from(model: ProblemModel, solver: Any, bounds: dict[str, Any], task: StartTask,
           points: Points | None = None) -> Run:
    """IPOPT from the task's start. A problem with many epigraph rows (region extremes) is solved by
    exchange: IPOPT holds the rows of least margin at the start, then again from its solution with the rows
    that solution violates most added, until it violates none (:meth:`ProblemModel.exchange_rows`). Where
    a step fails (a relaxation too loose to be bounded) or the exchange takes more than EXCHANGE_ROUNDS
    steps, ``solver``, the NLP with every row, solves from the start. The extremes' variables are scaled
    by their start's :meth:`ProblemModel.scale` in every step. ``points`` are those the NLP of ``solver``
    holds between the nodes (:meth:`ProblemModel.nlp`)."""
    problem, res = model.problem, task.resolution
    start = np.asarray(model.start(task.start, res), dtype=float)
    nv, scale = len(problem.variables), model.scale(start)
    given = {"p": scale} if model.extremes else {}
    x0, rows = start, (model.exchange_rows(start, res) if model.extremes else None)
    iterations = calls = 0
    for round_ in range(EXCHANGE_ROUNDS + 1):
        if round_ == EXCHANGE_ROUNDS:
            rows, x0 = None, start
        step = (solver, bounds) if rows is None else nlp_solver(model, res, json.loads(task.options), rows, points)
        with interruptible():
            sol = step[0](x0=np.concatenate([x0[:nv], x0[nv:] / scale]), **given, **step[1])
        stats = step[0].stats()
        iterations += int(stats["iter_count"])
        calls += int(stats.get("n_call_nlp_f", 0)) + int(stats.get("n_call_nlp_grad_f", 0))
        x = np.asarray(sol["x"]).ravel()
        x[nv:] *= scale
        if rows is None:
            break
        rows = model.exchange_rows(x, res, rows) if stats["success"] else None
        x0 = x if rows is not None else start
        if rows is None and stats["success"]:
            break
    w = x[: len(problem.variables)]
    value = model.sign * float(sol["f"])
    status, success = stats["return_status"], bool(stats["success"])
    if success and not model.tight(w, x[len(problem.variables) :], res, points):
        status, success = "Epigraph_Not_Tight", False
    multipliers = np.asarray(sol["lam_g"], dtype=float).ravel()[: len(problem.constraints)].tolist()
    return Run(_named(problem, task.start), status, success, iterations, calls, value, _named(problem, w),
               multipliers=multipliers)


def solve_start(task: StartTask) -> Run:
    """One start of a registered problem in a worker (the model and solver built once per process)."""
    parallel.as_worker()
    solver, bounds = _solver(task.problem, task.settings, task.resolution, task.options)
    return solve_from(_model(task.problem, task.settings), solver, bounds, task)


def _points(model: ProblemModel, task: PointsTask) -> tuple[np.ndarray, np.ndarray]:
    return model.evaluate(task.points, task.resolution)


def evaluate_points(task: PointsTask) -> tuple[np.ndarray, np.ndarray]:
    """A chunk of a registered problem's baseline in a worker."""
    parallel.as_worker()
    return _points(_model(task.problem, task.settings), task)


def _screen(model: ProblemModel, resolution: int, screening: int, starts: int) -> tuple[np.ndarray, np.ndarray]:
    """The screening points and the indices of the starts: the best feasible points, or where none is
    feasible the least infeasible (IPOPT starts from infeasible points too); none where the model is undefined
    at every point."""
    prob = model.problem
    points = grid_points(prob.variables, screening)
    if prob.starting_points is not None:
        points = np.concatenate([points, np.atleast_2d(prob.starting_points())])
    objective, ok, violation = model.assess_points(points, resolution)
    order = model.best(objective, ok, starts)
    if len(order) == 0:
        finite = np.isfinite(violation)
        order = np.argsort(np.where(finite, violation, np.inf), kind="stable")[: min(starts, int(finite.sum()))]
    return points, order


def _infeasibility(model: ProblemModel, points: np.ndarray, resolution: int) -> str:
    """Why no design of ``points`` (the screening grid and IPOPT's last iterates) meets the constraints, or ""
    where one does: each constraint none of them meets, with its best attainable value (least violation) and the
    design that attains it; else the constraints that the design of least total violation violates; a quantity
    undefined at every point (its region out of reach) named as such."""
    prob, tol = model.problem, model.problem.feasibility_tolerance
    objective, g = model.values(points, resolution)
    with np.errstate(invalid="ignore"):
        violation = np.maximum(np.maximum(model.lower - g, g - model.upper), 0.0)
    violation = np.where(np.isnan(violation), np.inf, violation)
    if np.any(np.all(violation <= tol, axis=1) & np.isfinite(objective)):
        return ""

    def at(k: int) -> str:
        return ", ".join(f"{n} = {v:.6g}" for n, v in zip(prob.variable_names, points[k], strict=True))

    reasons = []
    for i, c in enumerate(prob.constraints):
        if np.all(np.isnan(g[:, i])):
            reasons.append(f"{c.name} is undefined at every design tried (out of reach)")
            continue
        k = int(np.argmin(violation[:, i]))
        if violation[k, i] > tol:
            bound = c.lower if g[k, i] < c.lower else c.upper
            reasons.append(f"{c.name} cannot be met: at best {g[k, i]:.6g} against the bound {bound:.6g}, at {at(k)}")
    if not reasons and np.all(np.isnan(objective)):
        reasons.append("the objective is undefined at every design tried (its region out of reach)")
    if not reasons:
        k = int(np.argmin(violation.sum(axis=1)))
        broken = [f"{c.name} (value {g[k, i]:.6g})" for i, c in enumerate(prob.constraints) if violation[k, i] > tol]
        reasons.append(f"the constraints cannot be met together: the design of least violation, at {at(k)}, "
                       f"violates {', '.join(broken)}")
    return f"no design of {prob.name} meets its constraints among {len(points)} tried: " + "; ".join(reasons)


def _polish(
    model: ProblemModel, run: Run, optimum: Candidate, res: int, options: dict[str, Any]
) -> tuple[Run, Candidate, int, list[Run]]:
    """IPOPT again from the optimum at doubled resolutions until its verified objective agrees with the
    optimised one to ACCURACY or POLISH_LIMIT is reached; a polishing run that fails or turns infeasible
    ends the polish and the last good optimum stands."""
    extra = []
    while 2 * res <= POLISH_LIMIT:
        scale = max(1.0, abs(optimum.verified_objective))
        if abs(optimum.objective - optimum.verified_objective) <= ACCURACY * scale:
            break
        task = StartTask(model.problem.name, np.array(list(run.variables.values())), 2 * res,
                         json.dumps(options, sort_keys=True), _settings(model.problem))
        polished = solve_from(model, *nlp_solver(model, 2 * res, options), task)
        extra.append(polished)
        if not polished.success:
            break
        cand = model.candidate(np.array(list(polished.variables.values())), polished.objective, 2 * res)
        if not cand.feasible:
            break
        polished.verified_objective = cand.verified_objective
        run, optimum, res = polished, cand, 2 * res
    return run, optimum, res, extra


def _refine(
    model: ProblemModel, run: Run, optimum: Candidate, res: int, options: dict[str, Any]
) -> tuple[Run, Candidate, int, list[Run]]:
    """A problem with region extremes, solved by exchange over its regions: IPOPT again from the optimum with
    the constraints at their exact bounds instead of the node margins, and each extreme held, beside the
    nodes, at the points between them where the verification finds it (:meth:`ProblemModel.extreme_points`,
    from the verification's nodes and from those of EXTREME_SEARCH), more points each round, until the
    optimised objective agrees with the verified one to ACCURACY (relative above 1) at a design where every
    constraint holds exactly (a bound that the verification finds missed by less than the feasibility tolerance
    is moved inside by twice the miss for the next round), or REFINE_ROUNDS. The last feasible optimum stands
    (an infeasible one where none was: a run that the verification found violating a limit between the
    nodes is exchanged from it, too)."""
    extra: list[Run] = []
    points: Points = dict.fromkeys(model.extremes, ())
    point = np.array(list(run.variables.values()))
    m = len(model.problem.constraints)
    raised, lowered = np.zeros(m), np.zeros(m)
    for _ in range(REFINE_ROUNDS):
        scale = max(1.0, abs(optimum.verified_objective))
        if optimum.feasible and _exact(optimum) and \
                abs(optimum.objective - optimum.verified_objective) <= ACCURACY * scale:
            break
        if optimum.feasible:
            for i, c in enumerate(optimum.constraints):
                if c.value < c.lower:
                    raised[i] += 2 * (c.lower - c.value)
                elif c.value > c.upper:
                    lowered[i] += 2 * (c.value - c.upper)
        found = [model.extreme_points(point, r) for r in (2 * res, max(2 * res, EXTREME_SEARCH))]
        points = {name: tuple(dict.fromkeys(points[name] + found[0][name] + found[1][name])) for name in points}
        task = StartTask(model.problem.name, point, res, json.dumps(options, sort_keys=True), _settings(model.problem))
        solver, bounds = nlp_solver(model, res, options, points=points)
        bounds["lbg"][:m] += raised
        bounds["ubg"][:m] -= lowered
        refined = solve_from(model, solver, bounds, task, points)
        extra.append(refined)
        if not refined.success:
            break
        point = np.array(list(refined.variables.values()))
        cand = model.candidate(point, refined.objective, res)
        refined.verified_objective = cand.verified_objective
        if cand.feasible:
            run, optimum = refined, cand
    return run, optimum, res, extra


def _exact(cand: Candidate) -> bool:
    """Whether every constraint holds at the candidate as verified, without the feasibility tolerance."""
    return all(c.lower <= c.value <= c.upper for c in cand.constraints)


def _exchanged(model: ProblemModel, candidates: list[tuple[Run, Candidate]], res: int, options: dict[str, Any]
               ) -> tuple[list[tuple[Run, Candidate]], list[Run]]:
    """The candidates with each one that the verification found violating a constraint (a limit between
    the nodes) and whose optimised objective beats every feasible candidate's verified one exchanged over
    its regions (:func:`_refine`): the optimum next to it that holds the limit everywhere, where there is
    one. Candidates shared by several runs are exchanged once."""
    feasible = [model.sign * c.verified_objective for _, c in candidates if c.feasible]
    bar = min(feasible, default=np.inf)
    out, extra, done = [], [], {}
    for run, cand in candidates:
        if cand.feasible or model.sign * run.objective >= bar:
            out.append((run, cand))
            continue
        if id(cand) not in done:
            done[id(cand)] = _refine(model, run, cand, res, options)
            extra += done[id(cand)][3]
        out.append(done[id(cand)][:2])
    return out, extra


def _with_multipliers(cand: Candidate, run: Run) -> Candidate:
    """``cand`` with IPOPT's multiplier of each constraint from the run that found it."""
    if len(run.multipliers) != len(cand.constraints):
        return cand
    return replace(cand, constraints=[replace(c, multiplier=float(m))
                                      for c, m in zip(cand.constraints, run.multipliers, strict=True)])


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
    progress: Callable[[int, int], object] | bool | None = None,
    executor: str | Executor | None = None,
) -> SynthesisResult:
    """Solve a synthesis problem with IPOPT from several starts and verify the optimum.

    Parameters
    ----------
    problem : Problem
    resolution : quadrature resolution of the optimised objective (verification uses twice it); by default
        the problem's, and the optimum is then polished at doubled resolutions until it is verified to
        ``ACCURACY`` (or POLISH_LIMIT is reached).
    baseline_resolution : grid nodes per variable of the baselines (their own resolution by default).
    starts : number of IPOPT starts, the best feasible screening points.
    max_iter, tol, print_level : IPOPT's options (the problem's by default; print level 0, or 5 with
        ``verbose``).
    verbose : print IPOPT's iterations and timing.
    progress : ``progress(done, total)`` after each step (the screening, each start, the verification, each
        baseline: ``total`` = starts + 2 + baselines); by default (None) a progress bar on standard error
        when it is a terminal, nothing otherwise; False: nothing.
    executor : where the starts and the baselines' chunks run (:func:`pkm.parallel.executor`): by default
        a Dask cluster when a scheduler is set, else this process; a problem outside the registry runs
        in this process.
    """
    res = check_integer("resolution", problem.resolution if resolution is None else resolution, 1, MAX_RESOLUTION)
    n_starts = check_integer("starts", problem.starts if starts is None else starts, 1, MAX_STARTS)
    if baseline_resolution is not None:
        check_integer("baseline_resolution", baseline_resolution, 3, MAX_BASELINE)
    options = ipopt_options(problem, verbose=verbose, max_iter=max_iter, tol=tol, print_level=print_level)
    model = ProblemModel(problem)
    # the point integrands the solver evaluates, compiled together (one compiler per core) where the kernel
    # cache does not have them yet, instead of one at a time as the solver meets each a second time
    build([(k.function, k.summed) for k in problem_integrands(problem)])
    total = n_starts + 2 + len(problem.baselines)
    bar = Progress(total, f"synthesis {problem.name}", enabled=None if progress is None else False)
    steps = [0]

    def step(n: int = 1) -> None:
        steps[0] = min(total, steps[0] + n)
        bar.advance(n)
        if callable(progress):
            progress(steps[0], total)

    with bar:
        return _synthesize(problem, model, res=res, n_starts=n_starts, baseline_resolution=baseline_resolution,
                           options=options, executor=executor, step=step, polish=resolution is None)


def _candidates(problem: Problem, model: ProblemModel, good: list[Run], res: int) -> list[tuple[Run, Candidate]]:
    """Each converged run with its verified candidate, best first; runs that ended at one point (within
    SAME_POINT of the variables' spans) share one verification."""
    candidates: list[tuple[Run, Candidate]] = []
    span = np.array([v.upper - v.lower for v in problem.variables])
    for run in sorted(good, key=lambda r: model.sign * r.objective):
        point = np.array(list(run.variables.values()))
        same = [cand for _, cand in candidates
                if np.all(np.abs(point - np.array(list(cand.variables.values()))) <= SAME_POINT * span)]
        cand = same[0] if same else model.candidate(point, run.objective, res)
        run.verified_objective = cand.verified_objective
        candidates.append((run, cand))
    return candidates


def _baselines(problem: Problem, model: ProblemModel, *, where: str | Executor | None, settings: Any,
               resolution: int, baseline_resolution: int | None, step: Callable[..., None]
               ) -> dict[str, BaselineResult]:
    """Each baseline's best point, its designs evaluated in chunks at the quadrature ``resolution`` (the one the
    starts were solved at), calling ``step`` after each baseline."""
    baselines = {}
    for base in problem.baselines:
        t1 = time.perf_counter()
        n = baseline_resolution if baseline_resolution is not None and base.follows_resolution else base.resolution
        candidates_at = np.atleast_2d(base.points(n))
        chunks = [PointsTask(problem.name, candidates_at[k : k + BASELINE_CHUNK], resolution, settings)
                  for k in range(0, len(candidates_at), BASELINE_CHUNK)]
        with parallel.executor(where, tasks=len(chunks)) as pool:
            local = isinstance(pool, parallel.SerialExecutor)
            evaluate = partial(_points, model) if local else evaluate_points
            parts = parallel.run_tasks(pool, evaluate, chunks, describe=PointsTask.describe)
        values = np.concatenate([v for v, _ in parts])
        feasible = np.concatenate([f for _, f in parts])
        wall = time.perf_counter() - t1
        pick = model.best(values, feasible)
        if len(pick) == 0:
            # nothing feasible: report the point with the best objective, marked infeasible
            pick = model.best(values, np.isfinite(values))
        if len(pick) == 0:
            raise ComputationError(f"no point of the {base.name} baseline of {problem.name} has an objective")
        best = model.candidate(candidates_at[pick[0]], values[pick[0]], resolution)
        baselines[base.name] = BaselineResult(base.name, base.doc, best, wall, len(candidates_at), n)
        step()
    return baselines


def _synthesize(problem: Problem, model: ProblemModel, *, res: int, n_starts: int, baseline_resolution: int | None,
                options: dict[str, Any], executor: str | Executor | None, step: Callable[..., None],
                polish: bool) -> SynthesisResult:
    """The driver's stages (see :func:`synthesize`), calling ``step`` after each."""
    t0 = time.perf_counter()
    points, order = _screen(model, res, problem.screening_resolution, n_starts)
    if len(order) == 0:
        reason = _infeasibility(model, points, res) or f"the model of {problem.name} is undefined at all " \
                                                       f"{len(points)} screening points"
        raise InfeasibleError(reason, None)
    step(1 + n_starts - len(order))
    where = executor if _registered(problem) else "serial"
    settings = _settings(problem)
    tasks = [StartTask(problem.name, points[index], res, json.dumps(options, sort_keys=True), settings)
             for index in order]
    with parallel.executor(where, tasks=len(tasks)) as pool:
        local = isinstance(pool, parallel.SerialExecutor)
        solve = partial(solve_from, model, *nlp_solver(model, res, options)) if local else solve_start
        runs = parallel.run_tasks(pool, solve, tasks, describe=StartTask.describe, done=lambda _k, _run: step())
    evaluations = len(points) + sum(r.evaluations for r in runs)
    opt_time = time.perf_counter() - t0
    good = [r for r in runs if r.success]
    tol = problem.feasibility_tolerance

    def failed(message: str, run: Run, cand: Candidate, kind: type[SynthesisError] = SynthesisError) -> SynthesisError:
        return kind(message, SynthesisResult(
            problem=problem.name, sense=problem.objective.sense, optimum=cand, status=run.status,
            iterations=sum(r.iterations for r in runs), runs=runs, baselines={},
            optimizer={"wall_time_s": opt_time, "evaluations": evaluations},
            resolutions={"quadrature": res}, options={k: v for k, v in options["ipopt"].items() if k != "sb"},
            settings=dict(problem.values), **_where(problem),
        ))

    tried = np.concatenate([points, [list(r.variables.values()) for r in runs]])
    if not good:
        finite = [r for r in runs if np.isfinite(r.objective)]
        last = min(finite, key=lambda r: model.sign * r.objective) if finite else runs[-1]
        cand = _with_multipliers(model.candidate(np.array(list(last.variables.values())), last.objective, res), last)
        reason = _infeasibility(model, tried, res)
        if reason:
            raise failed(reason, last, cand, kind=InfeasibleError)
        raise failed(
            f"IPOPT did not converge from any of {len(runs)} starts of {problem.name}; status {last.status}, "
            f"last iterate {last.variables}, design {cand.design}, objective {last.objective:.6g}", last, cand)

    candidates = _candidates(problem, model, good, res)
    if polish and model.extremes:
        candidates, exchanged = _exchanged(model, candidates, res, options)
        runs.extend(exchanged)
        evaluations += sum(r.evaluations for r in exchanged)
    best_run, optimum = min(candidates, key=lambda rc: _rank(model, rc[1]))
    optimum = _with_multipliers(optimum, best_run)
    opt_time = time.perf_counter() - t0
    step()
    if not optimum.feasible:
        reason = _infeasibility(model, tried, res)
        broken = "; ".join(f"{c.name} is {c.value:.6g}" for c in optimum.constraints if not c.slack >= -tol)
        raise failed(reason or (
            f"every converged run of {problem.name} violates a constraint by more than {tol:g} at verification "
            f"({broken or 'the objective is undefined'}); best {optimum.variables}, design {optimum.design}"),
            best_run, optimum, kind=InfeasibleError if reason else SynthesisError)
    start_resolution = res
    if polish:
        best_run, optimum, res, extra = (_refine if model.extremes else _polish)(model, best_run, optimum, res, options)
        optimum = _with_multipliers(optimum, best_run)
        runs.extend(extra)
        evaluations += sum(r.evaluations for r in extra)
        opt_time = time.perf_counter() - t0

    baselines = _baselines(problem, model, where=where, settings=settings, resolution=start_resolution,
                           baseline_resolution=baseline_resolution, step=step)
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
            "polished_from": start_resolution,
            "quadrature_points": sum(region_points.values()),
            "verification_points": sum(dense_points.values()),
            "baseline_grid": baseline_resolution or (problem.baselines[0].resolution if problem.baselines else 0),
        },
        options={k: v for k, v in options["ipopt"].items() if k != "sb"},
        settings=dict(problem.values), **_where(problem),
    )
