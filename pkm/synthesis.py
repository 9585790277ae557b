"""Dimensional synthesis with IPOPT (DESIGN.md section 6).

A :class:`Problem` names the mechanism, the design space whose chart holds the variables, the global
index to optimise over a parametrised region, the working mode and the resolutions. :func:`synthesize`
screens a coarse chart grid for starting points, runs IPOPT through ``casadi.nlpsol`` with exact first
derivatives and exact (or, where a problem says so, limited-memory) second derivatives from each start,
and re-verifies the optimum with a quadrature 4x denser and
with the sampled index on a grid of the same region. The baseline (the papers' method: the best node
of a dense atlas grid) runs on the same model, and both are timed and counted.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm import indices, regions
from pkm.batch import evaluate
from pkm.errors import ComputationError, PkmError, UnknownNameError


@dataclass(frozen=True)
class Problem:
    """A synthesis problem: maximise a global index over a parametrised region in a design space."""

    name: str
    mechanism: str
    space: str
    index: str
    region: str
    mode: str
    doc: str
    min_length: float = 0.05
    min_radius: float = 0.3
    resolution: int = 8
    screening_resolution: int = 9
    baseline_resolution: int = 81
    starts: int = 4
    hessian: str = "exact"
    max_iter: int = 500


PROBLEMS: dict[str, Problem] = {
    p.name: p
    for p in (
        Problem(
            "five_bar.max_gci_miw",
            "five_bar",
            "gao1998",
            "gci",
            "miw",
            "out_out",
            "maximise the GCI over the maximum inscribed workspace in Gao's normalised solution space "
            "(2 r1 + 2 r2 + r3 = 4), working mode out_out (OABCD); every link at least min_length and the "
            "MIC radius at least min_radius (both in units of Gao's average link length L): without it "
            "the optimum shrinks the MIW towards a point",
        ),
        Problem(
            "five_bar.max_dynamic_dexterity_miw",
            "five_bar",
            "lara_molina2016",
            "dynamic_dexterity",
            "miw",
            "out_out",
            "maximise the global dynamic dexterity (Lara-Molina eq. 36) over the MIW in the design space "
            "r1 + r2 + r3 = 3 with the paper's non-dimensional dynamics (m1 = 1.2, m2 = 0.8, k = 1, "
            "j = 0.5 m1), working mode out_out; every length at least min_length from the bounds of eq. 32 "
            "and the MIC radius at least min_radius (units of D)",
            baseline_resolution=61,
        ),
        Problem(
            "five_bar.max_lambda_e_miw",
            "five_bar",
            "lara_molina2016",
            "lambda_e",
            "miw",
            "out_out",
            "maximise the elastodynamic index lambda_e (Lara-Molina eq. 38: the smallest non-zero natural "
            "frequency over the MIW, boundary included) in the design space r1 + r2 + r3 = 3 with the "
            "paper's non-dimensional dynamics, working mode out_out; solved in epigraph form (maximise t "
            "subject to S_e - t^2 I positive semidefinite at every node); lengths at least min_length from "
            "the bounds of eq. 32 and the MIC radius at least min_radius (units of D); limited-memory "
            "Hessian (the exact one of the node constraints costs more than it saves)",
            baseline_resolution=61,
            hessian="limited-memory",
        ),
    )
}


@dataclass
class Candidate:
    """A design found by one method: where it is, its objective as optimised and as verified."""

    chart: tuple[float, float]
    normalised: tuple[float, ...]
    design: dict[str, float]
    objective: float
    verified_objective: float = float("nan")
    sampled_objective: float = float("nan")
    sampled_points: int = 0


@dataclass
class Run:
    """One IPOPT run from one start."""

    start: tuple[float, float]
    status: str
    success: bool
    iterations: int
    objective: float
    chart: tuple[float, float]


@dataclass
class SynthesisResult:
    """The optimum, how it was found and checked, and the baseline on the same model."""

    problem: str
    optimum: Candidate
    baseline: Candidate
    status: str
    iterations: int
    runs: list[Run]
    optimizer: dict[str, float] = field(default_factory=dict)
    baseline_cost: dict[str, float] = field(default_factory=dict)
    resolutions: dict[str, int] = field(default_factory=dict)

    @property
    def design(self) -> dict[str, float]:
        return self.optimum.design

    @property
    def objective(self) -> float:
        return self.optimum.objective

    @property
    def verified_objective(self) -> float:
        return self.optimum.verified_objective

    def to_dict(self) -> dict[str, Any]:
        return {
            "problem": self.problem,
            "status": self.status,
            "iterations": self.iterations,
            "design": self.optimum.design,
            "objective": self.optimum.objective,
            "verified_objective": self.optimum.verified_objective,
            "baseline_objective": self.baseline.objective,
            "optimum": asdict(self.optimum),
            "baseline": {**asdict(self.baseline), **self.baseline_cost},
            "optimizer": self.optimizer,
            "runs": [asdict(r) for r in self.runs],
            "resolutions": self.resolutions,
        }


def resolve_options(
    prob: Any, resolution: int | None, baseline_resolution: int | None, starts: int | None
) -> tuple[int, int, int]:
    """The quadrature resolution, baseline resolution and number of starts: the given values or the
    problem's own; :class:`PkmError` unless each is an integer at least 1, 3 and 1."""
    values = (
        ("resolution", prob.resolution if resolution is None else resolution, 1),
        ("baseline_resolution", prob.baseline_resolution if baseline_resolution is None else baseline_resolution, 3),
        ("starts", prob.starts if starts is None else starts, 1),
    )
    for label, value, minimum in values:
        if int(value) != value or value < minimum:
            raise PkmError(f"{label} = {value} violates: an integer >= {minimum}")
    return tuple(int(v) for _, v, _ in values)


def ipopt_solver(name: str, nlp: dict, *, verbose: bool, max_iter: int, hessian: str = "exact") -> ca.Function:
    """IPOPT through ``casadi.nlpsol``, quiet (no banner) unless ``verbose``, tolerance 1e-10."""
    options = {
        "print_time": verbose,
        "show_eval_warnings": verbose,
        "ipopt": {
            "print_level": 5 if verbose else 0,
            "sb": "yes",
            "tol": 1e-10,
            "hessian_approximation": hessian,
            "max_iter": max_iter,
        },
    }
    return ca.nlpsol(name, "ipopt", nlp, options)


def solve_from(
    solver: ca.Function,
    starts: list,
    *,
    sense: str,
    axes: str,
    say: Callable[[str], None],
    **bounds: Any,
) -> tuple[list[Run], int, Run]:
    """Run ``solver`` from every start (its first two entries are the chart point) with ``bounds``.

    The NLP's f is the objective (``sense="min"``) or its negative (``"max"``). Returns the runs, the
    number of objective and gradient evaluations and the best converged run; :class:`ComputationError`
    with the last status and iterate (named by ``axes``) if no run converged.
    """
    sign = 1.0 if sense == "min" else -1.0
    runs: list[Run] = []
    calls = 0
    for k, x0 in enumerate(starts):
        say(f"IPOPT from start {k + 1}/{len(starts)}")
        sol = solver(x0=x0, **bounds)
        stats = solver.stats()
        calls += int(stats.get("n_call_nlp_f", 0)) + int(stats.get("n_call_nlp_grad_f", 0))
        w = np.asarray(sol["x"]).ravel()
        runs.append(
            Run(
                (float(x0[0]), float(x0[1])),
                stats["return_status"],
                bool(stats["success"]),
                int(stats["iter_count"]),
                float(sign * sol["f"]),
                (float(w[0]), float(w[1])),
            )
        )
    good = [r for r in runs if r.success]
    if not good:
        last = runs[-1]
        raise ComputationError(
            f"IPOPT did not converge from any of {len(runs)} starts; last status {last.status}, "
            f"last iterate ({axes}) = {last.chart}, objective {last.objective:.6g}"
        )
    return runs, calls, min(good, key=lambda r: sign * r.objective)


def problem(name: str) -> Problem:
    if name not in PROBLEMS:
        from pkm.task_synthesis import TASK_PROBLEMS

        raise UnknownNameError("synthesis problem", name, sorted([*PROBLEMS, *TASK_PROBLEMS]))
    return PROBLEMS[name]


class _Model:
    """The problem's objective as a function of the chart coordinates, numeric and symbolic."""

    def __init__(self, prob: Problem) -> None:
        import pkm

        self.prob = prob
        self.mech = pkm.load(prob.mechanism)
        if prob.space not in self.mech.design_spaces:
            raise UnknownNameError(f"{self.mech.name} design space", prob.space, sorted(self.mech.design_spaces))
        self.space = self.mech.design_spaces[prob.space]
        self.spec = indices.global_spec(prob.index)
        self.branch = self.mech.working_mode(prob.mode)
        self.region = self.mech.parametrised_regions()[prob.region]

    def design(self, u, v):
        return self.space.designs(self.mech.parameters, self.space.from_chart(u, v), check=False)

    def values(self, u: np.ndarray, v: np.ndarray, resolution: int, *, feasible: bool = True) -> np.ndarray:
        """The objective at chart points; with ``feasible``, NaN where the region is too small."""
        designs = self.design(u, v)
        values = regions.parametrised_global(
            self.mech, self.spec, self.region, designs, branch=self.branch, resolution=resolution
        )
        if not feasible:
            return values
        radius = evaluate(self.mech.functions[self.region.function], designs)[1][:, 0, 0]
        return np.where(radius >= self.prob.min_radius, values, np.nan)

    def candidate(self, u: float, v: float, objective: float) -> Candidate:
        normalised = tuple(float(c) for c in self.space.from_chart(u, v))
        design = self.mech.design_dict(self.design(u, v))
        return Candidate((float(u), float(v)), normalised, design, float(objective))

    def verify(self, cand: Candidate, resolution: int) -> None:
        """Objective at a 4x denser quadrature and as the sampled index on a grid of the region."""
        d = np.array(list(cand.design.values()))
        u, v = (np.array([c]) for c in cand.chart)
        cand.verified_objective = float(self.values(u, v, 2 * resolution, feasible=False)[0])
        sampled = regions.sampled_region_global(
            self.mech, self.spec, self.region, d, branch=self.branch, resolution=16 * resolution
        )
        cand.sampled_objective, cand.sampled_points = float(sampled), sampled.points

    @property
    def epigraph(self) -> bool:
        """A region minimum is maximised in epigraph form: max t subject to index >= t at every node."""
        return self.spec.reduce == "min"

    def nlp(self, resolution: int) -> tuple[dict[str, ca.MX], np.ndarray, np.ndarray]:
        """The NLP in the chart (and t for an epigraph) with its constraint bounds (lower, upper)."""
        prob = self.prob
        w = ca.MX.sym("w", 3 if self.epigraph else 2)
        design = self.design(w[0], w[1])
        normalised = ca.vertcat(*self.space.from_chart(w[0], w[1]))
        radius = self.mech.functions[self.region.function](design)[1]
        box = np.array(self.space.bounds)
        lower = [*(box[:, 0] + prob.min_length), prob.min_radius]
        upper = [*(box[:, 1] - prob.min_length), np.inf]
        g = [normalised, radius]
        if self.epigraph:
            nodes, _ = regions.node_values(
                self.mech, self.spec, self.region, self.branch, design, resolution=resolution, epigraph=w[2]
            )
            g.append(ca.vec(nodes))
            lower += [0.0] * nodes.numel()
            upper += [np.inf] * nodes.numel()
            f = -w[2]
        else:
            fn = regions.parametrised_global_function(self.mech, self.spec, self.region, self.branch, resolution)
            f = -fn(design)[0]
        return {"x": w, "f": f, "g": ca.vertcat(*g)}, np.array(lower), np.array(upper)


def synthesize(
    name: str,
    *,
    resolution: int | None = None,
    baseline_resolution: int | None = None,
    starts: int | None = None,
    verbose: bool = False,
    progress: Callable[[str], None] | None = None,
) -> SynthesisResult:
    """Solve a registered synthesis problem (see :data:`PROBLEMS`) and verify the optimum.

    Parameters
    ----------
    name : problem key, e.g. ``"five_bar.max_gci_miw"``; the slider gantry's task-rectangle problems
        (:data:`pkm.task_synthesis.TASK_PROBLEMS`) are solved by :func:`pkm.task_synthesis.synthesize_task`.
    resolution : quadrature resolution of the optimised objective (verification uses twice it: 4x
        the points).
    baseline_resolution : chart grid of the atlas baseline (nodes per axis).
    starts : number of IPOPT starts, the best nodes of the screening grid.
    verbose : print IPOPT's iterations.
    """
    from pkm.task_synthesis import TASK_PROBLEMS, synthesize_task

    if name in TASK_PROBLEMS:
        return synthesize_task(
            name,
            resolution=resolution,
            baseline_resolution=baseline_resolution,
            starts=starts,
            verbose=verbose,
            progress=progress,
        )
    prob = problem(name)
    res, base_res, n_starts = resolve_options(prob, resolution, baseline_resolution, starts)
    model = _Model(prob)
    say = progress or (lambda _msg: None)

    say("screening")
    t0 = time.perf_counter()
    u, v, inside = model.space.chart_grid(prob.screening_resolution, inset=prob.min_length)
    U, V = np.meshgrid(u, v, indexing="ij")
    su, sv = U[inside], V[inside]
    screen = model.values(su, sv, res)
    order = np.argsort(-np.nan_to_num(screen, nan=-np.inf))[:n_starts]

    nlp, lower, upper = model.nlp(res)
    solver = ipopt_solver("synthesis", nlp, verbose=verbose, max_iter=prob.max_iter, hessian=prob.hessian)
    starts_at = [[su[k], sv[k], 0.999 * screen[k]] if model.epigraph else [su[k], sv[k]] for k in order]
    runs, calls, best = solve_from(
        solver, starts_at, sense="max", axes="u, v", say=say, lbg=lower, ubg=upper, lbx=-np.inf, ubx=np.inf
    )
    calls += len(screen)
    opt_time = time.perf_counter() - t0
    optimum = model.candidate(*best.chart, best.objective)

    say("baseline atlas grid")
    t0 = time.perf_counter()
    bu, bv, binside = model.space.chart_grid(base_res, inset=prob.min_length)
    BU, BV = np.meshgrid(bu, bv, indexing="ij")
    grid_values = model.values(BU[binside], BV[binside], res)
    k = int(np.nanargmax(grid_values))
    baseline = model.candidate(BU[binside][k], BV[binside][k], grid_values[k])
    base_time = time.perf_counter() - t0

    say("verification")
    model.verify(optimum, res)
    model.verify(baseline, res)
    return SynthesisResult(
        problem=prob.name,
        optimum=optimum,
        baseline=baseline,
        status=best.status,
        iterations=sum(r.iterations for r in runs),
        runs=runs,
        optimizer={"wall_time_s": opt_time, "evaluations": calls},
        baseline_cost={"wall_time_s": base_time, "evaluations": len(grid_values)},
        resolutions={
            "quadrature": res,
            "quadrature_points": len(model.region.nodes(res, model.spec.reduce)[1]),
            "verification_points": len(model.region.nodes(2 * res, model.spec.reduce)[1]),
            "baseline_grid": base_res,
        },
    )
