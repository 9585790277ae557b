"""Workspace-based synthesis of the slider gantry (Wu 2008 section 4) and pkm's IPOPT synthesis beyond it.

Wu's two steps: for a task rectangle b x h and the smallest link angle theta_1S, eqs. 10-16 give the
link length l, the half distance d1 and the slider stroke with the input/output ratio y_d1 : b = 1 : 1
of eq. 13 (theta_1S + theta_2L = 90 deg); then theta_1S is chosen for the velocity ratio k_av
(eqs. 6-7). :func:`workspace_synthesis` is the first step, :func:`two_step_design` turns its result into
a complete pkm design with the task rectangle at a chosen height.

:class:`TaskProblem` is pkm's synthesis over the same model: the link length l and the half distance
d1 are free, the task rectangle must lie in the workspace with the angle margins theta_s <= |theta_i|
<= theta_l (singularity margins) and within the slider stroke, and a global index over the rectangle
is optimised with IPOPT and exact derivatives. It is compared with Wu's two-step family (theta_1S swept)
and with a grid over (l, d1), all on the same model, and its optimum is re-verified on a denser grid.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm import indices, regions
from pkm.batch import evaluate
from pkm.errors import ComputationError, DesignError
from pkm.synthesis import Candidate, SynthesisResult, ipopt_solver, resolve_options, solve_from

DEG = math.pi / 180
FEASIBILITY_TOLERANCE = 1e-7  # [m, or -] slack on g >= 0 (IPOPT relaxes its bounds by 1e-8 relative)


def _positive(name: str, value: float, unit: str = "m", *, closed: bool = False) -> float:
    value = float(value)
    ok = value >= 0 if closed else value > 0
    if not (math.isfinite(value) and ok):
        raise DesignError(f"{name} = {value:g} {unit} violates {name} {'>=' if closed else '>'} 0")
    return value


@dataclass(frozen=True)
class WorkspaceSynthesis:
    """Wu's first step (eqs. 10-16) for a task rectangle b x h [m] and the smallest link angle theta_1S.

    Attributes: ``d`` [m] the horizontal offset of link 1 at Q2 (eq. 14), ``theta_2l`` [rad] the
    largest link angle (pi/2 - theta_1S, eq. 13), ``length`` (Wu's l) and ``d1`` [m] (eq. 15), ``y_d1`` [m] the slider
    travel from Q2 to Q3 (eq. 12, equal to b) and ``stroke`` [m] |q_iL - q_iS| (eq. 16).
    """

    b: float
    h: float
    theta_1s: float
    d: float
    theta_2l: float
    length: float
    d1: float
    y_d1: float
    stroke: float


def workspace_synthesis(b: float, h: float, theta_1s: float) -> WorkspaceSynthesis:
    """Wu eqs. 10-16: l, d1 and the stroke for the task rectangle b x h [m] and theta_1S [rad].

    theta_1S must lie in (0, 45 deg): eq. 14's d = b tan(theta_1S) / (1 - tan(theta_1S)) is positive
    only there (at 45 deg the two angle limits meet and l is unbounded).
    """
    b = _positive("b", b)
    h = _positive("h", h)
    theta_1s = float(theta_1s)
    if not (math.isfinite(theta_1s) and 0 < theta_1s < math.pi / 4):
        raise DesignError(
            f"theta_1S = {theta_1s:g} rad ({theta_1s / DEG:g} deg) violates 0 < theta_1S < 45 deg (Wu eq. 14)"
        )
    t = math.tan(theta_1s)
    d = b * t / (1 - t)
    theta_2l = math.pi / 2 - theta_1s
    length = (b + d) / math.sin(theta_2l)
    y_d1 = length * (math.cos(theta_1s) - math.sin(math.pi / 2 - theta_2l))
    return WorkspaceSynthesis(
        b=b,
        h=h,
        theta_1s=theta_1s,
        d=d,
        theta_2l=theta_2l,
        length=length,
        d1=(b + 2 * d) / 2,
        y_d1=y_d1,
        stroke=y_d1 + h,
    )


def placement(length: float, d1: float, b: float, h: float, *, l2: float, centre_y: float) -> tuple[float, float]:
    """Stroke limits (qs, ql) [m] that put the bottom of a b x h rectangle centred at (0, centre_y) on
    the lower stroke limit (Q2, Q3 of Wu Fig. 2) and its top on the upper one (Q1, Q4)."""
    qs = centre_y - h / 2 - l2 / 2 - math.sqrt(length**2 - (d1 - b / 2) ** 2)
    ql = centre_y + h / 2 - l2 / 2 - math.sqrt(length**2 - (d1 + b / 2) ** 2)
    return qs, ql


def two_step_design(
    b: float,
    h: float,
    theta_1s: float,
    *,
    d2: float,
    l2: float,
    centre_y: float = 0.5,
    mechanism: str = "slider_gantry",
    **inertial: float,
) -> dict[str, float]:
    """A complete design from Wu's first step, the task rectangle centred at (0, centre_y) [m].

    The angle margins are theta_s = theta_1S and theta_l = theta_2L; the strokes put the rectangle's
    bottom and top on the slider limits (:func:`placement`). ``inertial`` overrides Table 2's values.
    """
    import pkm

    first = workspace_synthesis(b, h, theta_1s)
    d2 = _positive("d2", d2, closed=True)
    l2 = _positive("l2", l2)
    qs, ql = placement(first.length, first.d1, b, h, l2=l2, centre_y=centre_y)
    values = {
        "l": first.length,
        "d1": first.d1,
        "d2": d2,
        "l2": l2,
        "qs": qs,
        "ql": ql,
        "theta_s": first.theta_1s,
        "theta_l": first.theta_2l,
        **inertial,
    }
    return dict(pkm.load(mechanism).design(values))


def k_av_closed_form(length: float, d1: float, b: float) -> float:
    """Wu eq. 7 in closed form: the mean of k_v = cot(theta_1) = sqrt(l^2 - u^2) / u over u = x + d1,
    x in [-b/2, b/2]; an antiderivative of sqrt(l^2 - u^2) / u is sqrt(l^2 - u^2) - l artanh(sqrt(l^2 -
    u^2) / l)."""

    def antiderivative(u: float) -> float:
        s = math.sqrt(length**2 - u**2)
        return s - length * math.atanh(s / length)

    lo, hi = d1 - b / 2, d1 + b / 2
    if not (lo > 0 and hi <= length):
        raise DesignError(f"k_av needs 0 < d1 - b/2 and d1 + b/2 <= l; got d1 = {d1:g}, b = {b:g}, l = {length:g}")
    return (antiderivative(hi) - antiderivative(lo)) / b


def required_stroke(length, d1, b: float, h: float):
    """Slider stroke [m] that a b x h rectangle centred on x = 0 needs: h plus the rise between the
    links' extreme angles (Wu eq. 16 with y_d1 = l (cos theta_min - cos theta_max))."""
    return h + _sqrt(length**2 - (d1 - b / 2) ** 2) - _sqrt(length**2 - (d1 + b / 2) ** 2)


@dataclass(frozen=True)
class TaskProblem:
    """A slider-gantry synthesis for a fixed task rectangle: optimise a global index over it in (l, d1).

    The rectangle b x h is centred at (0, centre_y); the platform d2, l2 and Table 2's masses are fixed;
    the links keep their mass and s = l/2 and their inertia about the pivot scales as l^2 from Table 2's
    (``reference_length`` = Table 1's l). Constraints: the angle margins theta_s <= |theta_i| <= theta_l
    over the rectangle, the stroke it needs at most ``max_stroke``, the frame width 2 (d1 + d2) at most
    ``max_frame_width`` and k_av at least ``min_k_av``; bounds ``length_bounds`` and ``d1_bounds``.

    A design's own angle margins theta_s, theta_l are its extreme link angles over the rectangle and its
    strokes put the rectangle's bottom and top on the slider limits, so that its task region is the
    b x h rectangle. IPOPT starts from the best feasible points of a screening grid over the bounds and
    of Wu's two-step family.
    """

    name: str
    mechanism: str
    index: str
    sense: str
    doc: str
    width: float = 0.5
    height: float = 0.4
    centre_y: float = 0.5
    d2: float = 0.1
    l2: float = 0.2
    theta_s: float = 10 * DEG
    theta_l: float = 80 * DEG
    max_stroke: float = 0.9
    max_frame_width: float = 1.0
    min_k_av: float = 1.0
    reference_length: float = 0.6164
    length_bounds: tuple[float, float] = (0.4, 1.2)
    d1_bounds: tuple[float, float] = (0.25, 0.75)
    resolution: int = 8
    screening_resolution: int = 9
    baseline_resolution: int = 61
    two_step_samples: int = 351
    starts: int = 4
    max_iter: int = 200

    @property
    def mode(self) -> str:
        return "below"


TASK_PROBLEMS: dict[str, TaskProblem] = {
    p.name: p
    for p in (
        TaskProblem(
            "slider_gantry.min_kappa_d_task",
            "slider_gantry",
            "kappa_d_mean",
            "min",
            "minimise the mean of kappa_D (Wu eq. 44) over Wu's 500 x 400 mm task rectangle in the link "
            "length l and the half distance d1, with the angle margins 10 <= |theta_i| <= 80 deg, the "
            "stroke at most Wu's 900 mm, the frame width 2 (d1 + d2) at most 1 m and k_av >= 1; Table 2 "
            "masses, link inertia scaled with l^2; against Wu's two-step family (theta_1S swept) and a grid",
        ),
    )
}


def task_problem(name: str) -> TaskProblem:
    if name not in TASK_PROBLEMS:
        from pkm.errors import UnknownNameError

        raise UnknownNameError("synthesis problem", name, sorted(TASK_PROBLEMS))
    return TASK_PROBLEMS[name]


def _asin(value):
    return ca.asin(value) if isinstance(value, ca.MX | ca.SX) else np.arcsin(value)


def _sqrt(value):
    return ca.sqrt(value) if isinstance(value, ca.MX | ca.SX) else np.sqrt(value)


class _TaskModel:
    """The problem's objective, k_av and constraints in w = (l, d1), numeric and symbolic."""

    def __init__(self, prob: TaskProblem) -> None:
        import pkm

        self.prob = prob
        self.mech = pkm.load(prob.mechanism)
        self.spec = indices.global_spec(prob.index)
        self.k_av = indices.global_spec("k_av")
        self.branch = self.mech.working_mode(prob.mode)
        self.region = self.mech.parametrised_regions()["task"]
        self.base = dict(self.mech.design())
        self.placement = (np.array([0.0, prob.centre_y]), np.array([prob.width / 2, prob.height / 2]))
        self._functions: dict[int, ca.Function] = {}

    def design(self, length, d1) -> list:
        """The design vector (parameter order) of (l, d1): floats, arrays or CasADi expressions."""
        p = self.prob
        b, h = p.width, p.height
        qs = p.centre_y - h / 2 - p.l2 / 2 - _sqrt(length**2 - (d1 - b / 2) ** 2)
        ql = p.centre_y + h / 2 - p.l2 / 2 - _sqrt(length**2 - (d1 + b / 2) ** 2)
        scale = (length / p.reference_length) ** 2
        values = {
            **self.base,
            "l": length,
            "d1": d1,
            "d2": p.d2,
            "l2": p.l2,
            "qs": qs,
            "ql": ql,
            "theta_s": _asin((d1 - b / 2) / length),
            "theta_l": _asin((d1 + b / 2) / length),
            "s12": length / 2,
            "s22": length / 2,
            "s4": length / 2,
        }
        for name in ("I12", "I22", "I4", "I5"):
            if name in values:
                values[name] = self.base[name] * scale
        for name in ("s5",):
            if name in values:
                values[name] = length / 2
        return [values[q.name] for q in self.mech.parameters]

    def constraints(self, length, d1) -> list:
        """g >= 0: the angle margins, the stroke and the frame width (k_av is added by the caller)."""
        p = self.prob
        b = p.width
        return [
            d1 - b / 2 - length * math.sin(p.theta_s),
            length * math.sin(p.theta_l) - d1 - b / 2,
            p.max_stroke - required_stroke(length, d1, b, p.height),
            p.max_frame_width - 2 * (d1 + p.d2),
        ]

    def function(self, resolution: int) -> ca.Function:
        """w -> (objective, k_av, g): g >= 0 where feasible (k_av - min_k_av last)."""
        if resolution not in self._functions:
            w = ca.MX.sym("w", 2)
            design = ca.vertcat(*self.design(w[0], w[1]))
            out = []
            for spec in (self.spec, self.k_av):
                values, weights = regions.node_values(
                    self.mech, spec, self.region, self.branch, design, resolution=resolution, placement=self.placement
                )
                out.append(regions.reduce_nodes(values, weights, spec.reduce))
            g = ca.vertcat(*self.constraints(w[0], w[1]), out[1] - self.prob.min_k_av)
            self._functions[resolution] = ca.Function(
                f"{self.prob.name.replace('.', '_')}_{resolution}",
                [w],
                [out[0], out[1], g],
                ["w"],
                ["objective", "k_av", "g"],
            )
        return self._functions[resolution]

    def evaluate(
        self, points: np.ndarray, resolution: int, *, feasible: bool = True
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Objective, k_av and feasibility at the points (N, 2) of (l, d1); with ``feasible`` the
        objective is NaN where a constraint is violated."""
        points = np.atleast_2d(points)
        with np.errstate(invalid="ignore"):
            geometric = np.stack(self.constraints(points[:, 0], points[:, 1]), axis=1)
        ok = np.all(geometric >= -FEASIBILITY_TOLERANCE, axis=1)
        run = ok if feasible else np.ones(len(points), dtype=bool)
        objective = np.full(len(points), np.nan)
        k_av = np.full(len(points), np.nan)
        if run.any():
            obj, kav, g = evaluate(self.function(resolution), points[run])
            objective[run] = obj[:, 0, 0]
            k_av[run] = kav[:, 0, 0]
            ok[run] &= np.all(g[:, :, 0] >= -FEASIBILITY_TOLERANCE, axis=1)
        return (np.where(ok, objective, np.nan) if feasible else objective), k_av, ok

    def better(self, values: np.ndarray) -> int:
        """Index of the best finite value for the problem's sense."""
        score = np.where(np.isfinite(values), values if self.prob.sense == "min" else -values, np.inf)
        return int(np.argmin(score))

    def candidate(self, point, objective: float, resolution: int) -> Candidate:
        """A design with its objective as optimised, at a 4x denser quadrature and sampled on a grid."""
        length, d1 = (float(c) for c in point)
        vector = np.array(self.design(length, d1), dtype=float)
        cand = Candidate(
            (length, d1),
            (length / self.prob.width, d1 / self.prob.width),
            self.mech.design_dict(vector),
            float(objective),
        )
        dense = self.evaluate(np.array([[length, d1]]), 2 * resolution, feasible=False)
        cand.verified_objective = float(dense[0][0])
        sampled = regions.sampled_region_global(
            self.mech,
            self.spec,
            self.region,
            vector,
            branch=self.branch,
            resolution=16 * resolution,
            placement=self.placement,
        )
        cand.sampled_objective, cand.sampled_points = float(sampled), sampled.points
        return cand


@dataclass
class TaskSynthesisResult(SynthesisResult):
    """A :class:`pkm.synthesis.SynthesisResult` with Wu's two-step family and Wu's own design as
    further baselines; ``sense`` says whether the objective is minimised or maximised."""

    sense: str = "max"
    two_step: Candidate | None = None
    two_step_cost: dict[str, float] = field(default_factory=dict)
    paper: Candidate | None = None

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out["sense"] = self.sense
        out["two_step"] = {**asdict(self.two_step), **self.two_step_cost} if self.two_step else None
        out["paper_design"] = asdict(self.paper) if self.paper else None
        return out


def synthesize_task(
    name: str,
    *,
    resolution: int | None = None,
    baseline_resolution: int | None = None,
    starts: int | None = None,
    verbose: bool = False,
    progress: Callable[[str], None] | None = None,
) -> TaskSynthesisResult:
    """Solve a registered :class:`TaskProblem` with IPOPT from the best screening points; run Wu's
    two-step family and a grid on the same model; verify every optimum (4x quadrature and sampled)."""
    prob = task_problem(name)
    res, base_res, n_starts = resolve_options(prob, resolution, baseline_resolution, starts)
    model = _TaskModel(prob)
    say = progress or (lambda _msg: None)
    sign = 1.0 if prob.sense == "min" else -1.0

    def box_grid(n: int) -> np.ndarray:
        L, D = np.meshgrid(np.linspace(*prob.length_bounds, n), np.linspace(*prob.d1_bounds, n), indexing="ij")
        return np.stack([L.ravel(), D.ravel()], axis=1)

    say("screening")
    t0 = time.perf_counter()
    two_step_points = _two_step_points(prob)
    every = max(len(two_step_points) // prob.screening_resolution, 1)
    screen_points = np.concatenate([box_grid(prob.screening_resolution), two_step_points[::every]])
    screen, _, feasible = model.evaluate(screen_points, res)
    calls = int(feasible.sum())
    order = [k for k in np.argsort(sign * np.where(feasible, screen, np.nan)) if feasible[k]][:n_starts]
    starts_at = [screen_points[k] for k in order]
    if not starts_at:
        raise ComputationError(f"no feasible design among the {len(screen_points)} screening points of {prob.name}")

    fn = model.function(res)
    w = ca.MX.sym("w", 2)
    objective, _, g = fn(w)
    nlp = {"x": w, "f": sign * objective, "g": g}
    solver = ipopt_solver("task_synthesis", nlp, verbose=verbose, max_iter=prob.max_iter)
    runs, ipopt_calls, best = solve_from(
        solver,
        starts_at,
        sense=prob.sense,
        axes="l, d1",
        say=say,
        lbg=0.0,
        ubg=np.inf,
        lbx=[b[0] for b in (prob.length_bounds, prob.d1_bounds)],
        ubx=[b[1] for b in (prob.length_bounds, prob.d1_bounds)],
    )
    calls += ipopt_calls
    opt_time = time.perf_counter() - t0

    say("baseline: Wu's two-step family")
    t0 = time.perf_counter()
    values, _, _ = model.evaluate(two_step_points, res)
    k = model.better(values)
    two_step_time = time.perf_counter() - t0
    if not np.isfinite(values[k]):
        raise ComputationError(f"no design of Wu's two-step family satisfies the constraints of {prob.name}")

    say("baseline: grid")
    t0 = time.perf_counter()
    grid_points = box_grid(base_res)
    grid_values, _, _ = model.evaluate(grid_points, res)
    j = model.better(grid_values)
    grid_time = time.perf_counter() - t0

    say("verification")
    paper_point = _two_step_points(prob, samples=1)[0]
    paper_value = model.evaluate(paper_point[None], res)[0][0]
    return TaskSynthesisResult(
        problem=prob.name,
        optimum=model.candidate(best.chart, best.objective, res),
        baseline=model.candidate(grid_points[j], grid_values[j], res),
        status=best.status,
        iterations=sum(r.iterations for r in runs),
        runs=runs,
        optimizer={"wall_time_s": opt_time, "evaluations": calls},
        baseline_cost={
            "wall_time_s": grid_time,
            "evaluations": int(np.isfinite(grid_values).sum()),
            "grid_points": len(grid_points),
        },
        resolutions={
            "quadrature": res,
            "quadrature_points": len(model.region.nodes(res)[1]),
            "verification_points": len(model.region.nodes(2 * res)[1]),
            "baseline_grid": base_res,
        },
        sense=prob.sense,
        two_step=model.candidate(two_step_points[k], values[k], res),
        two_step_cost={
            "wall_time_s": two_step_time,
            "evaluations": len(two_step_points),
            "theta_1s_deg": float(_two_step_angles(prob)[k] / DEG),
        },
        paper=model.candidate(paper_point, paper_value, res),
    )


def _two_step_angles(prob: TaskProblem, samples: int | None = None) -> np.ndarray:
    """theta_1S of Wu's two-step family from the margin theta_s up to 44.9 deg."""
    return np.linspace(prob.theta_s, 44.9 * DEG, prob.two_step_samples if samples is None else samples)


def _two_step_points(prob: TaskProblem, samples: int | None = None) -> np.ndarray:
    """(l, d1) of Wu's eqs. 14-15 along the two-step family; the first is theta_1S = theta_s."""
    out = [workspace_synthesis(prob.width, prob.height, t) for t in _two_step_angles(prob, samples)]
    return np.array([[w.length, w.d1] for w in out])
