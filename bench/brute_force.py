"""Brute-force optima of the registered synthesis problems, independent of IPOPT and of the driver:
``python -m bench.brute_force [PROBLEM...] [--out PATH]``.

For each problem (all registered ones by default):

1. the resolution: the best feasible points of a screening grid are evaluated at the problem's
   quadrature resolution r, 2r, 4r, ... until two successive resolutions agree to RESOLUTION_AGREEMENT
   (relative); the higher of the two is used below;
2. a dense grid over the variables' bounds (:func:`plan`: 201 x 201 for two variables, 11^5 for five)
   through :meth:`ProblemModel.assess_points` (region extremes over the quadrature nodes);
3. the starts: the best feasible grid points, START_SEPARATION of a variable's range apart, re-evaluated
   with each region extreme refined between the nodes where the problem has region extremes;
4. a search from each start. For one or two variables a zoom: a local grid over a box around the best
   point, along the axes at even levels (a point on a bound, or on the boundary of a constraint on one
   variable, moves along it) and turned by a random rotation at odd ones, so that its directions become
   dense (a grid along the axes alone stalls on a constraint boundary or a ridge oblique to them), with
   the points where the segments to its best infeasible points leave the feasible set
   (:func:`boundary`), the best feasible point kept; the box moves on where that point lies beyond half
   its half-width (the optimum may lie farther: along a ridge, a maximin's, or a constraint's boundary)
   and shrinks otherwise, until it is below BOX_STOP of every variable's range or the best objective
   changed by less than CHANGE_STOP (relative) over the plan's ``stall`` levels. For more variables an
   evolution strategy (:func:`adapt`, CMA-ES) ranked by objective and violation, until its step is below
   BOX_STOP or its best stalls likewise;
5. the objective at the best end point at twice the resolution: where it differs by more than
   RESOLUTION_AGREEMENT, the searches run again from their end points at twice the resolution;
6. the end point verified: the objective at half the resolution, and :meth:`ProblemModel.verify` (what the
   driver states) at half, once and twice the resolution, feasible by the constraints' own bounds (not
   the optimiser's node margins; see below).

A region extreme refined between the nodes (:func:`pkm.regions.parametrised_global`, what ``verify``
states) is a local search from the best nodes: its value is one the local index takes in the region, never
beyond the true extreme, but short of it where every search ends in another basin, and a search over
designs finds the designs where that happens (at the maximin of the five-bar's lambda_e two basins are
equal). Here each extreme is refined from REFINE_STARTS best nodes at the resolution and at three
quarters of it (node sets that are not nested), and the tighter value is kept.

Feasible means within the constraints' bounds up to round-off throughout (ROUND_OFF, also for the
violation of ``assess_points``), not within the problem's feasibility tolerance, which ``verify`` allows:
at lambda_e's optimum a violation of 1e-7 of the MIC radius gains 3e-7 (relative) of the objective.
Batches run on the threads of :mod:`pkm.batch`. The JSON (``{"command": ..., "problems": {name: {...}}}``)
is merged into an existing file, so that one problem can be run again alone; it is written atomically.
"""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple
from unittest import mock

import casadi as ca
import numpy as np

from pkm import registry
from pkm.batch import evaluate
from pkm.io import to_json, write_text
from pkm.regions import extremes, parametrised_global
from pkm.synthesis.model import ProblemModel
from pkm.synthesis.problem import grid_points

OUT = Path("docs/benchmarks/brute_force.json")
SEED = 20260123
RESOLUTION_AGREEMENT = 1e-7  # two successive quadrature resolutions agree this well (relative)
RESOLUTION_LIMIT = 256  # the highest quadrature resolution used
CHECKED_POINTS = 8  # best screening points the resolution is chosen at
REFINE_STARTS = 8  # best nodes each region extreme is refined from (verify's: extremes.REFINE_STARTS, fewer)
BOX_STOP = 1e-9  # a search ends when its box (or largest step) is below this fraction of each variable's range
CHANGE_STOP = 1e-9  # or when its best objective changed by less than this (relative) over the plan's stall levels
MAX_LEVELS = 400  # zoom levels per start at most
MAX_GENERATIONS = 2000  # generations of an evolution strategy at most
TRACE = 10  # last levels (or generations) of the best search recorded
CHUNK = 4096  # points per batch evaluation
CANDIDATES = 64  # grid points refined at a time while looking for starts
CANDIDATE_LIMIT = 4096  # grid points refined at most while looking for starts
START_SEPARATION = 0.05  # starts lie this fraction of some variable's range apart at least
BISECTIONS = 24  # bisections of each such segment
ROUND_OFF = 1e-12  # a constraint holds within this of its bound (the problem's feasibility tolerance is looser)


@dataclass(frozen=True)
class Plan:
    """The search in n variables: ``grid`` nodes per axis of the dense grid and ``starts`` searches from
    it, each ended when ``stall`` levels (or generations) improve its objective by less than CHANGE_STOP;
    a zoom (:func:`zoom`) with ``local`` nodes per axis of each level, the box's half-width times ``shrink``
    from one level to the next and ``boundary`` segments bisected at each level, or where ``population``
    is set, an evolution strategy (:func:`adapt`) with that many points a generation."""

    grid: int
    starts: int
    stall: int
    local: int = 0
    shrink: float = 0.0
    boundary: int = 0
    population: int = 0


def plan(n: int) -> Plan:
    """The search in n variables: for one or two a dense grid of 201^2 nodes and zooms over a 21-node
    local grid (a new half-width of 2.5 of its spacings); for more a grid of about 11^5 nodes and an
    evolution strategy of 32 points a generation: a zoom's grid in five variables (3^5 points a level)
    stalls in the narrow wedge where the 2-UPS-PU's task margin holds (0.6% above its optimum)."""
    if n <= 2:
        return Plan(round(201 ** (2 / n)), 3, 3, local=21, shrink=0.25, boundary=8)
    return Plan(max(3, round(11 ** (5 / n))), 2, 30, population=32)


class Assessed(NamedTuple):
    """Objective (N,) and total constraint violation (N,; inf where the model is undefined)."""

    objective: np.ndarray
    violation: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """Mask (N,) of a defined objective with every constraint within its bounds up to ROUND_OFF."""
        return np.isfinite(self.objective) & (self.violation <= ROUND_OFF)


class Assessor:
    """The problem's objective and feasibility at batches of variable points, counted: at the quadrature
    nodes (:meth:`ProblemModel.assess_points`) or with each region extreme refined between the nodes
    from REFINE_STARTS best nodes at the resolution and at three quarters of it, the tighter kept."""

    def __init__(self, model: ProblemModel) -> None:
        self.model = model
        self.evaluations = 0
        problem = model.problem
        w = ca.MX.sym("w", len(problem.variables))
        values = {name: ca.MX.sym(name) for name in problem.quantities}
        f, g = model.expressions(w, values)
        self._design = ca.Function("design", [w], [model.design(w)])
        self._with_quantities = ca.Function("with_quantities", [w, *values.values()], [f, g])

    def nodes(self, points: np.ndarray, resolution: int) -> Assessed:
        """The points (N, n) with region extremes over the nodes."""
        parts = [self.model.assess_points(points[k : k + CHUNK], resolution) for k in range(0, len(points), CHUNK)]
        self.evaluations += len(points)
        return Assessed(np.concatenate([p[0] for p in parts]), np.concatenate([p[2] for p in parts]))

    def refined(self, points: np.ndarray, resolution: int) -> Assessed:
        """The points (N, n) with region extremes refined between the nodes (the same as :meth:`nodes`
        for a problem without region extremes)."""
        if not self.model.extremes:
            return self.nodes(points, resolution)
        parts = [self.values(points[k : k + CHUNK], resolution) for k in range(0, len(points), CHUNK)]
        objective = np.concatenate([p[0] for p in parts])
        return Assessed(objective, self.violation(objective, np.concatenate([p[1] for p in parts])))

    def violation(self, objective: np.ndarray, g: np.ndarray) -> np.ndarray:
        """The total violation (N,) of the constraint rows (N, m), as :meth:`ProblemModel.assess_points`."""
        model = self.model
        with np.errstate(invalid="ignore"):
            total = np.sum(np.maximum(model.lower - g, 0) + np.maximum(g - model.upper, 0), axis=1)
        return np.where(np.isfinite(objective) & np.isfinite(total), total, np.inf)

    def values(self, points: np.ndarray, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        """Objective (N,) and constraint values (N, m), region extremes refined between the nodes."""
        model = self.model
        designs = evaluate(self._design, points)[0][:, :, 0]
        values = []
        with mock.patch.object(extremes, "REFINE_STARTS", REFINE_STARTS):
            for name, q in model.problem.quantities.items():
                def at(r: int, q: Any = q) -> np.ndarray:
                    return parametrised_global(model.mech, q.index, q.region, designs, branch=model.branch,
                                               resolution=r)

                value = at(resolution)
                if name in model.extremes and resolution >= 2:
                    value = (np.minimum if q.index.reduce == "min" else np.maximum)(value, at(3 * resolution // 4))
                values.append(value)
        f, g = evaluate(self._with_quantities, points, *(v[:, None] for v in values))
        self.evaluations += len(points)
        return f[:, 0, 0], g[:, :, 0]


def _relative(a: Any, b: Any) -> Any:
    return np.abs(a - b) / np.maximum(1.0, np.abs(b))


def _bounds(model: ProblemModel) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([v.lower for v in model.problem.variables])
    upper = np.array([v.upper for v in model.problem.variables])
    return lower, upper


def choose_resolution(assess: Assessor) -> tuple[int, float]:
    """The quadrature resolution at which the objectives of the best points of a screening grid (at the
    problem's resolution, region extremes over the nodes) agree with those at half of it to
    RESOLUTION_AGREEMENT (or RESOLUTION_LIMIT), and that agreement."""
    model = assess.model
    problem = model.problem
    points = grid_points(problem.variables, 21 if len(problem.variables) <= 2 else 5)
    screened = assess.nodes(points, problem.resolution)
    pick = model.best(screened.objective, screened.ok, CHECKED_POINTS)
    if not len(pick):
        pick = model.best(screened.objective, np.isfinite(screened.objective), CHECKED_POINTS)
    checked = points[pick]
    resolution, before = problem.resolution, assess.refined(checked, problem.resolution).objective
    while True:
        after = assess.refined(checked, 2 * resolution).objective
        change = float(np.nanmax(_relative(before, after)))
        resolution, before = 2 * resolution, after
        if change <= RESOLUTION_AGREEMENT or 2 * resolution > RESOLUTION_LIMIT:
            return resolution, change


def find_starts(assess: Assessor, search: Plan, resolution: int) -> tuple[list[tuple[np.ndarray, float]], int]:
    """The zooms' starts (point, objective with refined extremes) from the dense grid, and its size: the
    best feasible nodes, START_SEPARATION of some variable's range apart at least."""
    model = assess.model
    points = grid_points(model.problem.variables, search.grid)
    grid = assess.nodes(points, resolution)
    objective, ok = grid.objective, grid.ok
    if not ok.any():
        raise RuntimeError(f"no node of the {search.grid}^{points.shape[1]} grid of {model.problem.name} is feasible")
    order = model.best(objective, ok, CANDIDATE_LIMIT)
    lower, upper = _bounds(model)
    starts: list[tuple[np.ndarray, float]] = []
    for k in range(0, len(order), CANDIDATES):
        rows = order[k : k + CANDIDATES]
        chunk = points[rows]
        value, good = (objective[rows], ok[rows])
        if model.extremes:
            refined = assess.refined(chunk, resolution)
            value, good = refined.objective, refined.ok
        for j in model.best(value, good, len(chunk)):
            if all(np.max(np.abs(chunk[j] - p) / (upper - lower)) >= START_SEPARATION for p, _ in starts):
                starts.append((chunk[j], float(value[j])))
        if len(starts) >= search.starts:
            break
    if not starts:
        raise RuntimeError(f"none of the best {len(order)} grid nodes of {model.problem.name} is feasible with its "
                           "region extremes refined between the nodes")
    starts.sort(key=lambda pv: model.sign * pv[1])
    return starts[: search.starts], len(points)


def _rotation(rng: np.random.Generator, n: int) -> np.ndarray:
    """A random rotation (n, n), uniform over the orthogonal group."""
    q, r = np.linalg.qr(rng.normal(size=(n, n)))
    return q * np.sign(np.diag(r))


def boundary(
    assess: Assessor, resolution: int, inside: np.ndarray, outside: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The last feasible points (K, n) and their objectives (K,; NaN where none but ``inside`` is) of
    BISECTIONS bisections of the segments from the feasible points ``inside`` (K, n) to the infeasible
    ``outside`` (K, n): points on the feasible set's boundary, which no grid holds."""
    low, high = np.zeros(len(outside)), np.ones(len(outside))
    value = np.full(len(outside), np.nan)
    for _ in range(BISECTIONS):
        t = (low + high) / 2
        at = assess.refined(inside + t[:, None] * (outside - inside), resolution)
        low, high, value = np.where(at.ok, t, low), np.where(at.ok, high, t), np.where(at.ok, at.objective, value)
    return inside + low[:, None] * (outside - inside), value


def zoom(
    assess: Assessor, search: Plan, resolution: int, start: tuple[np.ndarray, float], *, half_width: float
) -> tuple[np.ndarray, float, list[dict[str, float]]]:
    """The best feasible point of the zoom from ``start`` (a point and its objective) with a box of
    ``half_width`` (a fraction of each variable's range), and each level's box and best objective. Each
    level adds to its grid the points where the segments from its ``search.boundary`` least infeasible
    points that are better than the best feasible one to the feasible points nearest them leave the
    feasible set: an optimum on a constraint's boundary oblique to the grid is approached along that
    boundary, where the grid's own points lie off it."""
    model = assess.model
    lower, upper = _bounds(model)
    span = upper - lower
    n = len(span)
    axes = np.linspace(-1.0, 1.0, search.local)
    offsets = np.stack([m.ravel() for m in np.meshgrid(*[axes] * n, indexing="ij")], axis=1)
    rng = np.random.default_rng(SEED)
    point, best = start[0].copy(), start[1]
    history, levels, h = [best], [], half_width
    for level in range(MAX_LEVELS):
        if h <= BOX_STOP:
            break
        turn = _rotation(rng, n) if level % 2 else np.eye(n)
        local = np.clip(point + h * (offsets @ turn.T) * span, lower, upper)
        at = assess.refined(local, resolution)
        objective, ok = at.objective, at.ok
        better = np.flatnonzero(~ok & np.isfinite(at.violation) & (model.sign * objective < model.sign * best))
        beyond = better[np.argsort(at.violation[better], kind="stable")][: search.boundary]
        if len(beyond) and ok.any():
            inside = local[ok]
            nearest = np.argmin(np.linalg.norm((inside[None] - local[beyond, None]) / span, axis=2), axis=1)
            edge, value = boundary(assess, resolution, inside[nearest], local[beyond])
            local, objective = np.concatenate([local, edge]), np.concatenate([objective, value])
            ok = np.concatenate([ok, np.isfinite(value)])
        pick = model.best(objective, ok)
        moved = len(pick) > 0 and model.sign * objective[pick[0]] < model.sign * best
        far = moved and np.linalg.norm((local[pick[0]] - point) / span) > h / 2
        if moved:
            point, best = local[pick[0]], float(objective[pick[0]])
        if not far:
            h *= search.shrink
        levels.append({"box": h, "objective": best})
        history.append(best)
        if len(history) > search.stall and _relative(best, history[-1 - search.stall]) < CHANGE_STOP:
            break
    return point, best, levels


def adapt(
    assess: Assessor, search: Plan, resolution: int, start: tuple[np.ndarray, float], *, sigma: float
) -> tuple[np.ndarray, float, list[dict[str, float]]]:
    """The best feasible point of an evolution strategy with covariance matrix adaptation (CMA-ES, Hansen's
    default parameters) from ``start`` (a point and its objective) with step ``sigma`` (a fraction of each
    variable's range), and each generation's largest step and best objective. Points are clipped to the
    bounds; a generation is ranked feasible points first by objective, then the others by violation (no
    penalty, no tolerance), so that the distribution learns the shape of a narrow feasible wedge."""
    model = assess.model
    lower, upper = _bounds(model)
    span = upper - lower
    n, count = len(span), search.population
    mu = count // 2
    weights = np.log(mu + 0.5) - np.log(np.arange(1, mu + 1))
    weights /= weights.sum()
    mueff = 1 / np.sum(weights**2)
    cc, cs = (4 + mueff / n) / (n + 4 + 2 * mueff / n), (mueff + 2) / (n + mueff + 5)
    c1 = 2 / ((n + 1.3) ** 2 + mueff)
    cmu = min(1 - c1, 2 * (mueff - 2 + 1 / mueff) / ((n + 2) ** 2 + mueff))
    damps = 1 + 2 * max(0.0, np.sqrt((mueff - 1) / (n + 1)) - 1) + cs
    chi = np.sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n**2))
    rng = np.random.default_rng(SEED)
    mean = (start[0] - lower) / span
    point, best = start[0].copy(), start[1]
    cov, basis, scale = np.eye(n), np.eye(n), np.ones(n)
    path_c, path_s = np.zeros(n), np.zeros(n)
    history, levels = [best], []
    for generation in range(1, MAX_GENERATIONS + 1):
        x = np.clip(mean + sigma * (rng.normal(size=(count, n)) * scale) @ basis.T, 0.0, 1.0)
        y = (x - mean) / sigma
        at = assess.refined(lower + x * span, resolution)
        order = np.lexsort((np.where(at.ok, 0.0, at.violation), np.where(at.ok, model.sign * at.objective, np.inf)))
        if at.ok[order[0]] and model.sign * at.objective[order[0]] < model.sign * best:
            point, best = lower + x[order[0]] * span, float(at.objective[order[0]])
        chosen = y[order[:mu]]
        step = weights @ chosen
        mean = mean + sigma * step
        path_s = (1 - cs) * path_s + np.sqrt(cs * (2 - cs) * mueff) * (basis @ ((basis.T @ step) / scale))
        held = np.linalg.norm(path_s) / np.sqrt(1 - (1 - cs) ** (2 * generation)) / chi < 1.4 + 2 / (n + 1)
        path_c = (1 - cc) * path_c + held * np.sqrt(cc * (2 - cc) * mueff) * step
        cov = ((1 - c1 - cmu) * cov + c1 * (np.outer(path_c, path_c) + (1 - held) * cc * (2 - cc) * cov)
               + cmu * (chosen.T * weights) @ chosen)
        sigma *= np.exp((cs / damps) * (np.linalg.norm(path_s) / chi - 1))
        eigenvalues, basis = np.linalg.eigh((cov + cov.T) / 2)
        scale = np.sqrt(np.maximum(eigenvalues, np.finfo(float).tiny))
        levels.append({"box": float(sigma * scale.max()), "objective": best})
        history.append(best)
        if sigma * scale.max() <= BOX_STOP:
            break
        if len(history) > search.stall and _relative(best, history[-1 - search.stall]) < CHANGE_STOP:
            break
    return point, best, levels


def _searches(
    assess: Assessor, search: Plan, resolution: int, starts: list[tuple[np.ndarray, float]], log: Callable[[str], None]
) -> list[tuple[np.ndarray, float, list[dict[str, float]], np.ndarray, float]]:
    """A zoom with a box of two grid spacings, or an evolution strategy with a step of one, from each
    start: (end, objective, levels, start, start's objective), best first."""
    ends = []
    for point, value in starts:
        if search.population:
            end, best, levels = adapt(assess, search, resolution, (point, value), sigma=1 / (search.grid - 1))
        else:
            end, best, levels = zoom(assess, search, resolution, (point, value), half_width=2 / (search.grid - 1))
        ends.append((end, best, levels, point, value))
        log(f"  from {point.tolist()} ({value:.12g}): {best:.12g} at {end.tolist()} in {len(levels)} levels")
    return sorted(ends, key=lambda e: assess.model.sign * e[1])


def _commit() -> dict[str, Any]:
    """The commit of the working tree and whether pkm/ differs from it."""
    def git(*args: str) -> str:
        return subprocess.run(["git", *args], capture_output=True, text=True, check=False).stdout.strip()

    return {"commit": git("rev-parse", "HEAD"), "pkm_modified": bool(git("status", "--porcelain", "--", "pkm"))}


def solve(name: str, command: str, log: Callable[[str], None]) -> dict[str, Any]:
    """The brute-force optimum of one registered problem, verified, with what it cost."""
    t0 = time.perf_counter()
    problem = registry.problem(name)
    model = ProblemModel(problem)
    assess = Assessor(model)
    n = len(problem.variables)
    search = plan(n)
    resolution, agreement = choose_resolution(assess)
    log(f"{name}: resolution {resolution} (agrees with {resolution // 2} to {agreement:.1e})")
    starts, grid_size = find_starts(assess, search, resolution)
    log(f"  {grid_size} grid points, {len(starts)} starts, best {starts[0][1]:.12g}")
    while True:
        ends = _searches(assess, search, resolution, starts, log)
        end, best, levels = ends[0][:3]
        doubled = float(assess.values(end[None], 2 * resolution)[0][0])
        change = float(_relative(doubled, best))
        if change <= RESOLUTION_AGREEMENT or 4 * resolution > RESOLUTION_LIMIT:
            break
        resolution *= 2
        log(f"  at resolution {resolution} the objective is {doubled:.12g} ({change:.1e}): the zooms again at it")
        points = np.array([e[0] for e in ends])
        again = assess.refined(points, resolution)
        starts = [(points[k], float(again.objective[k])) for k in model.best(again.objective, again.ok, len(points))]
    f, g = assess.values(end[None], resolution)
    feasible = bool(Assessed(f, assess.violation(f, g)).ok[0])
    half = float(assess.values(end[None], resolution // 2)[0][0])
    design = np.asarray(problem.design(list(end)), dtype=float).ravel()
    verified = {str(r): model.verify(end, design, r) for r in (resolution // 2, resolution, 2 * resolution)}
    if not model.extremes and _relative(verified[str(resolution)][0], best) > 1e-9:
        raise RuntimeError(f"{name}: the zoom's objective {best!r} and verify's {verified[str(resolution)][0]!r} "
                           "differ")
    wall = time.perf_counter() - t0
    log(f"  {best:.12g} ({'feasible' if feasible else 'INFEASIBLE'}) at resolution {resolution}, {half:.12g} at "
        f"{resolution // 2}, {doubled:.12g} at {2 * resolution}; verify {verified}; {assess.evaluations} "
        f"evaluations in {wall:.0f} s")
    return {
        "sense": problem.objective.sense,
        "variables": dict(zip(problem.variable_names, end.tolist(), strict=True)),
        "design": model.mech.design_dict(design),
        "objective": best,
        "feasible": feasible,
        "constraints": {c.name: {"value": float(v), "lower": c.lower, "upper": c.upper}
                        for c, v in zip(problem.constraints, g[0], strict=True)},
        "resolution": resolution,
        "objective_half_resolution": half,
        "objective_double_resolution": doubled,
        "verify": {r: {"objective": v, "feasible": ok} for r, (v, ok) in verified.items()},
        "region_extremes": (f"refined from the {REFINE_STARTS} best nodes at the resolution and at three quarters "
                            "of it, the tighter kept" if model.extremes else "none"),
        "grid": f"{search.grid}^{n}",
        "search": (f"CMA-ES, {search.population} points a generation" if search.population else
                   f"zoom over a {search.local}^{n} grid, along the axes and turned at random at alternate levels, "
                   f"shrinking by {search.shrink}, {search.boundary} segments to the boundary bisected a level"),
        "starts": [{"start": p.tolist(), "start_objective": v, "end": e.tolist(), "objective": b, "levels": len(lv)}
                   for e, b, lv, p, v in ends],
        "levels": len(levels),
        "last_levels": levels[-TRACE:],
        "evaluations": assess.evaluations,
        "wall_time_s": wall,
        "command": command,
        **_commit(),
    }


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.brute_force", description=__doc__.splitlines()[0])
    parser.add_argument("problems", nargs="*", metavar="PROBLEM", help="registered problems (all by default)")
    parser.add_argument("--out", type=Path, default=OUT, help=f"JSON the optima are merged into (default {OUT})")
    args = parser.parse_args(argv)
    names = args.problems or sorted(registry.problems())
    for name in names:
        registry.problem(name)
    command = shlex.join(["python", "-m", "bench.brute_force", *(sys.argv[1:] if argv is None else argv)])
    for name in names:
        result = solve(name, command, lambda msg: print(msg, file=sys.stderr, flush=True))
        report = json.loads(args.out.read_text()) if args.out.exists() else {}
        problems = dict(sorted({**report.get("problems", {}), name: result}.items()))
        report = {"command": f"python -m bench.brute_force --out {args.out}", "problems": problems}
        write_text(args.out, to_json(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())
