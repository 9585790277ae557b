"""A problem turned into CasADi functions of its variables, numeric and symbolic.

One graph per quadrature resolution maps the variables w to the objective, the constraint values and
the quantities: the design map, the regions' quadratures and the fused pipeline of
:mod:`pkm.regions` composed, so the NLP has exact derivatives and the grids and checks evaluate the
same model in batches.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError
from pkm.regions import (
    RegionIndex,
    epigraph_margins,
    epigraph_point_margins,
    epigraph_values,
    global_values,
    node_values,
    quadrature_value,
    refined_extremes,
    sampled_value,
)
from pkm.regions.integrand import point_values
from pkm.synthesis.problem import Problem, Terms

TIGHT = 1e-5  # relative gap between an extreme's variable and its quantity at a converged optimum
EPIGRAPH_SLACK = 1e-3  # an extreme's variable starts this far (relative) inside its node bounds
SAMPLED_FACTOR = 16  # a 2-D sampled check's grid per axis, in units of the quadrature resolution
SAMPLED_LIMIT = 512**2  # cells of a sampled check at most
EXCHANGE_ROWS = 2  # least (and after a solve most violated) epigraph rows of each margin output an exchange adds
EXCHANGE_LIMIT = 2048  # epigraph rows that IPOPT holds all at once

ACTIVE = 1e-6  # a constraint within its margin plus this (relative to its bound, at least absolute) is active

Points = dict[str, tuple[tuple[int, tuple[float, ...]], ...]]  # per extreme: (piece, reference point) between nodes


@dataclass
class ConstraintValue:
    """One constraint at a candidate, as verified: its value, bounds, slack (the distance to the nearer bound,
    negative where violated), whether it is active (within its margin plus :data:`ACTIVE` of a bound) and
    IPOPT's multiplier where the candidate is an IPOPT run's (None for a baseline's point)."""

    name: str
    value: float
    lower: float
    upper: float
    slack: float
    active: bool
    multiplier: float | None = None


@dataclass
class Candidate:
    """A design found by one method: its variables, design, objective as optimised, as verified with
    a quadrature 4x denser, and by sampling each quantity on a grid (with the fewest points used)."""

    variables: dict[str, float]
    design: dict[str, float]
    objective: float
    verified_objective: float = float("nan")
    sampled_objective: float = float("nan")
    sampled_points: int = 0
    feasible: bool = True
    constraints: list[ConstraintValue] = field(default_factory=list)


class ProblemModel:
    """The problem's objective and constraints in the variables, numeric and symbolic. ``indices`` holds each
    quantity of the problem by name as the global index over its region in the problem's working mode."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.mech = problem.mechanism
        self.branch = self.mech.working_mode(problem.mode)
        self.indices = {name: RegionIndex(self.mech, q.index, q.region, self.branch)
                        for name, q in problem.quantities.items()}
        self._functions: dict[int, ca.Function] = {}
        self._with_values: ca.Function | None = None
        self._design: ca.Function | None = None
        self.lower = np.array([c.lower for c in problem.constraints], dtype=float)
        self.upper = np.array([c.upper for c in problem.constraints], dtype=float)
        margin = np.array([c.margin for c in problem.constraints], dtype=float)
        self.nlp_lower, self.nlp_upper = self.lower + margin, self.upper - margin
        for c, lo, hi in zip(problem.constraints, self.nlp_lower, self.nlp_upper, strict=True):
            if not (c.margin >= 0 and lo <= hi):
                raise PkmError(f"constraint {c.name!r}: margin {c.margin:g} violates 0 <= margin <= half its range")

    @property
    def sign(self) -> float:
        """+1 to minimise the objective, -1 to maximise it."""
        return 1.0 if self.problem.objective.sense == "min" else -1.0

    def design(self, w: ca.MX) -> ca.MX:
        """The design vector of the variables (a CasADi column)."""
        return self.problem.design([w[k] for k in range(w.numel())])

    def terms(self, w: ca.MX, design: ca.MX, quantities: dict[str, ca.MX]) -> Terms:
        names = self.mech.parameter_names()
        values = {n: design[k] for k, n in enumerate(names)}
        values.update({v.name: w[k] for k, v in enumerate(self.problem.variables)})
        values.update(quantities)
        return Terms(values, self.mech.functions, design)

    def expressions(self, w: ca.MX, quantities: dict[str, ca.MX]) -> tuple[ca.MX, ca.MX]:
        """The objective and the constraint column at w with the given quantity values."""
        design = self.design(w)
        terms = self.terms(w, design, quantities)
        g = ca.vertcat(*[c.expression(terms) for c in self.problem.constraints])
        return self.problem.objective.expression(terms), g

    def quantities(self, design: ca.MX, resolution: int) -> dict[str, ca.MX]:
        return {name: quadrature_value(index, design, resolution=resolution) for name, index in self.indices.items()}

    def function(self, resolution: int) -> ca.Function:
        """w -> (objective, g, *quantities) with the quadratures at ``resolution``."""
        if resolution not in self._functions:
            w = ca.MX.sym("w", len(self.problem.variables))
            quantities = self.quantities(self.design(w), resolution)
            f, g = self.expressions(w, quantities)
            self._functions[resolution] = ca.Function(
                f"{self.problem.name.replace('.', '_')}_{resolution}",
                [w],
                [f, g, *quantities.values()],
                ["w"],
                ["objective", "constraints", *quantities],
            )
        return self._functions[resolution]

    def feasible(self, g: np.ndarray) -> np.ndarray:
        """Mask of constraint rows (N, m) within their bounds up to the problem's tolerance."""
        tol = self.problem.feasibility_tolerance
        with np.errstate(invalid="ignore"):
            return np.all((g >= self.lower - tol) & (g <= self.upper + tol), axis=1)

    def evaluate(self, points: np.ndarray, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        """Objective (N,) and feasibility (N,) at the variable points (N, n)."""
        objective, ok, _ = self.assess_points(points, resolution)
        return objective, ok

    def values(self, points: np.ndarray, resolution: int) -> tuple[np.ndarray, np.ndarray]:
        """The objective (N,) and the constraint values (N, m) at the variable points (N, n), the quantities
        at ``resolution`` (region extremes over the nodes)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        quantities = self.quantity_values(points, resolution)
        f, g = evaluate(self._with_quantities(), points, *(v[:, None] for v in quantities.values()))
        return f[:, 0, 0], g[:, :, 0]

    def assess_points(self, points: np.ndarray, resolution: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Objective (N,), feasibility (N,) and the total constraint violation (N,; inf where the
        model is undefined) at the variable points (N, n)."""
        objective, g = self.values(points, resolution)
        ok = self.feasible(g) & np.isfinite(objective)
        with np.errstate(invalid="ignore"):
            violation = np.sum(np.maximum(self.lower - g, 0) + np.maximum(g - self.upper, 0), axis=1)
        violation = np.where(np.isfinite(objective) & np.isfinite(violation), violation, np.inf)
        return objective, ok, violation

    def best(self, objective: np.ndarray, ok: np.ndarray, count: int = 1) -> np.ndarray:
        """Indices of the ``count`` best feasible values in the objective's sense."""
        score = np.where(ok, self.sign * objective, np.inf)
        order = np.argsort(score, kind="stable")
        return order[: min(count, int(ok.sum()))]

    @property
    def extremes(self) -> tuple[str, ...]:
        """The quantities that are region minima or maxima: the NLP replaces each by a variable t
        bounded by the local index at every node (t <= the index for a minimum, t >= it for a
        maximum), exact where the objective and constraints push t towards the extreme (a minimum
        maximised or bounded below, a maximum minimised or bounded above)."""
        return tuple(name for name, index in self.indices.items() if index.reduce in ("min", "max"))

    def nlp(
        self, resolution: int, held: dict[str, tuple[int, ...]] | None = None, points: Points | None = None
    ) -> tuple[dict[str, ca.MX], np.ndarray, np.ndarray]:
        """The NLP in (w, s for each of :attr:`extremes`) with the bounds on its constraints; with ``held``
        only those rows of each extreme's epigraph margins (:func:`pkm.regions.epigraph_values`). Each
        extreme's variable is t = p s, its scale p a parameter of the NLP (:meth:`scale`), so that IPOPT
        steps in variables of one size (a force of 2000 N beside lengths of 0.2 m). With ``points``, the
        epigraph holds at those points between the nodes too, and the constraints take their exact bounds
        instead of the node margins that stand in for the points between the nodes."""
        prob = self.problem
        w = ca.MX.sym("w", len(prob.variables))
        lower, upper = (self.lower, self.upper) if points is not None else (self.nlp_lower, self.nlp_upper)
        if not self.extremes:
            f, g = self.function(resolution)(w)[:2]
            return {"x": w, "f": self.sign * f, "g": g}, lower, upper
        design = self.design(w)
        scale = ca.MX.sym("scale", len(self.extremes))
        s = [ca.MX.sym(f"s_{name}") for name in self.extremes]
        t = {name: scale[k] * s[k] for k, name in enumerate(self.extremes)}
        values = self.quantities(design, resolution)
        f, g = self.expressions(w, {**values, **t})
        rows, lower, upper = [g], [lower], [upper]
        for name, bound in t.items():
            index = self.indices[name]
            margins = [epigraph_margins(index, design=design, bound=bound, resolution=resolution,
                                        rows=None if held is None else held[name])]
            if points is not None and points[name]:
                margins.append(epigraph_point_margins(index, design=design, bound=bound, points=points[name]))
            for block in margins:
                rows.append(ca.vec(block))
                lower.append(np.zeros(block.numel()))
                upper.append(np.full(block.numel(), np.inf))
        nlp = {"x": ca.vertcat(w, *s), "p": scale, "f": self.sign * f, "g": ca.vertcat(*rows)}
        return nlp, np.concatenate(lower), np.concatenate(upper)

    def extreme_points(self, point: np.ndarray, resolution: int) -> Points:
        """Where each region extreme lies at the variables ``point``, refined between the nodes of its rule
        at ``resolution`` (:func:`pkm.regions.refined_extremes`): one (piece, reference point) per extreme."""
        design = np.asarray(self.problem.design(list(point)), dtype=float).ravel()
        out = {}
        for name in self.extremes:
            refined = refined_extremes(self.indices[name], design[None], resolution=resolution)
            out[name] = ((int(refined.piece[0]), tuple(float(u) for u in refined.point[0])),)
        return out

    def scale(self, x: np.ndarray) -> np.ndarray:
        """The scales p of the extremes' variables at a point x = (w, t for each extreme) of the NLP: the
        power of ten nearest to each |t| (1 where t is 0)."""
        t = np.abs(np.asarray(x, dtype=float)[len(self.problem.variables):])
        return 10.0 ** np.round(np.log10(np.where(t > 0, t, 1.0)))

    def margins(self, x: np.ndarray, resolution: int) -> dict[str, np.ndarray]:
        """Every epigraph margin of each extreme at a point x = (w, t for each extreme) of the NLP."""
        w, bounds = x[: len(self.problem.variables)], x[len(self.problem.variables):]
        design = np.asarray(self.problem.design(list(w)), dtype=float).ravel()
        return {
            name: epigraph_values(self.indices[name], design=design, bound=float(t), resolution=resolution)
            for name, t in zip(self.extremes, bounds, strict=True)
        }

    def exchange_rows(
        self, x: np.ndarray, resolution: int, rows: dict[str, tuple[int, ...]] | None = None
    ) -> dict[str, tuple[int, ...]] | None:
        """The epigraph rows an NLP solved from x should hold (the exchange method of semi-infinite
        programming), chosen in each output of an extreme's margins (:func:`pkm.regions.epigraph_values`:
        one per actuator, workspace constraint, ...) so that every constraint that can become active is
        represented, not only the neighbours of the worst node: at a start (``rows`` None) the EXCHANGE_ROWS
        least margins of each output; after a solve, ``rows``, the EXCHANGE_ROWS rows of each output that
        x violates most (an undefined one first) and the EXCHANGE_ROWS least; None when x violates no
        row, so that x solves the NLP with every row, and at a start where the extremes have
        EXCHANGE_LIMIT rows or fewer (IPOPT then holds every row)."""
        margins = self.margins(x, resolution)
        if rows is None and sum(len(m) for m in margins.values()) <= EXCHANGE_LIMIT:
            return None
        out, grown = {}, rows is None
        tol = self.problem.feasibility_tolerance
        for name, margin in margins.items():
            count = self.indices[name].node_count(resolution)
            per = margin.reshape(-1, count)
            held = np.zeros(per.shape, dtype=bool)
            least = np.argsort(np.where(np.isnan(per), np.inf, per), axis=1, kind="stable")[:, :EXCHANGE_ROWS]
            np.put_along_axis(held, least, True, axis=1)
            if rows is not None:
                before = np.zeros(margin.shape, dtype=bool)
                before[list(rows[name])] = True
                before = before.reshape(per.shape)
                violated = ~before & ~(per >= -tol)
                grown |= bool(violated.any())
                held |= before
                worst = np.argsort(np.where(violated, np.nan_to_num(per, nan=-np.inf), np.inf), axis=1,
                                   kind="stable")[:, :EXCHANGE_ROWS]
                np.put_along_axis(held, worst, np.take_along_axis(violated, worst, axis=1), axis=1)
            out[name] = tuple(np.flatnonzero(held.ravel()).tolist())
        return out if grown else None

    def tight(self, w: np.ndarray, bounds: np.ndarray, resolution: int, points: Points | None = None) -> bool:
        """Whether every extreme's variable equals its quantity at w (over the nodes and the ``points``
        the NLP holds), or, where one does not (a constraint on an extreme that is not active), the
        quantities in their place give the same objective and hold the constraints: the problem uses each
        extreme in the direction its epigraph represents (otherwise the optimiser moved t away from it)."""
        if not self.extremes:
            return True
        named = self._quantities_at(w, resolution)
        if points is not None:
            design = np.asarray(self.problem.design(list(w)), dtype=float).ravel()
            for name in self.extremes:
                if points[name]:
                    index = self.indices[name]
                    extreme = np.nanmin if index.reduce == "min" else np.nanmax
                    named[name] = float(extreme([named[name], *point_values(index, design, points[name])]))
        if all(abs(t - named[name]) <= TIGHT * max(1.0, abs(named[name]))
               for name, t in zip(self.extremes, bounds, strict=True)):
            return True
        held = {**named, **dict(zip(self.extremes, bounds, strict=True))}
        f_held, _ = self._expressions_with(w, held)
        f, g = self._expressions_with(w, named)
        return abs(f - f_held) <= TIGHT * max(1.0, abs(f)) and bool(self.feasible(g[None, :])[0])

    def start(self, point: np.ndarray, resolution: int) -> list[float]:
        """A starting point of the NLP: the variables and each extreme a little inside its bound."""
        if not self.extremes:
            return list(point)
        named = self._quantities_at(point, resolution)
        starts = []
        for name in self.extremes:
            value = named[name]
            inside = -1.0 if self.indices[name].reduce == "min" else 1.0
            starts.append(value + inside * EPIGRAPH_SLACK * max(abs(value), 1.0))
        return [*point, *starts]

    def verified_values(self, point: np.ndarray, design: np.ndarray, resolution: int) -> tuple[float, np.ndarray]:
        """The objective and the constraint values (m,) at ``point`` with the quadratures at ``resolution`` and
        each region extreme refined between the nodes (:mod:`pkm.regions.extremes`)."""
        named = self._quantities_at(point, resolution)
        for name in self.extremes:
            named[name] = float(global_values(self.indices[name], design[None], resolution=resolution)[0])
        return self._expressions_with(point, named)

    def constraint_values(self, g: np.ndarray) -> list[ConstraintValue]:
        """Each constraint's record at the values ``g`` (m,) (:class:`ConstraintValue`, no multiplier)."""
        out = []
        for c, value in zip(self.problem.constraints, np.asarray(g, dtype=float).ravel(), strict=True):
            with np.errstate(invalid="ignore"):
                slack = float(min(value - c.lower, c.upper - value))
            finite = [b for b in (c.lower, c.upper) if np.isfinite(b)]
            reach = c.margin + max(self.problem.feasibility_tolerance, ACTIVE * max([1.0, *map(abs, finite)]))
            out.append(ConstraintValue(c.name, float(value), float(c.lower), float(c.upper), slack,
                                       bool(slack <= reach)))
        return out

    def candidate(self, point: np.ndarray, objective: float, resolution: int) -> Candidate:
        """A candidate at ``point`` with its objective verified at twice the resolution (4x the
        points of a 2-D rule, region extremes refined between the nodes) and by sampling every quantity
        on a grid of its region."""
        point = np.asarray(point, dtype=float)
        design = np.asarray(self.problem.design(list(point)), dtype=float).ravel()
        verified, g = self.verified_values(point, design, 2 * resolution)
        ok = bool(self.feasible(g[None])[0] and np.isfinite(verified))
        sampled, points = {}, []
        # as many grid cells as a 2-D check in every dimension: (16 resolution)^2 in all
        cells = min((SAMPLED_FACTOR * resolution) ** 2, SAMPLED_LIMIT)
        per_axis = max(2, round(cells ** (1 / self.mech.n_out)))
        for name, index in self.indices.items():
            value = sampled_value(index, design, resolution=per_axis)
            sampled[name] = float(value)
            points.append(value.points)
        sampled_objective = self._expressions_with(point, sampled)[0]
        return Candidate(
            variables=dict(zip(self.problem.variable_names, point.tolist(), strict=True)),
            design=self.mech.design_dict(design),
            objective=float(objective),
            verified_objective=verified,
            sampled_objective=sampled_objective,
            sampled_points=min(points) if points else 0,
            feasible=ok,
            constraints=self.constraint_values(g),
        )

    def assess(self, point: np.ndarray, resolution: int) -> Candidate:
        """The candidate at a given point of the variables: its objective at ``resolution``, verified."""
        objective, _ = self.evaluate(np.atleast_2d(point), resolution)
        return self.candidate(np.ravel(point), float(objective[0]), resolution)

    def quantity_values(self, points: np.ndarray, resolution: int) -> dict[str, np.ndarray]:
        """Each quantity (N,) at the variable points (N, n) with the quadratures at ``resolution`` (region
        extremes over the nodes), evaluated in batches of designs."""
        if self._design is None:
            w = ca.MX.sym("w", len(self.problem.variables))
            self._design = ca.Function("design", [w], [self.design(w)])
        designs = evaluate(self._design, points)[0][:, :, 0]
        return {name: node_values(index, designs, resolution=resolution) for name, index in self.indices.items()}

    def _quantities_at(self, point: np.ndarray, resolution: int) -> dict[str, float]:
        """Each quantity at one point of the variables (:meth:`quantity_values`)."""
        return {name: float(v[0]) for name, v in self.quantity_values(np.atleast_2d(point), resolution).items()}

    def _with_quantities(self) -> ca.Function:
        """``(w, *quantities) -> (objective, constraints)`` with the quantity values given."""
        if self._with_values is None:
            w = ca.MX.sym("w", len(self.problem.variables))
            values = {k: ca.MX.sym(k) for k in self.problem.quantities}
            f, g = self.expressions(w, values)
            self._with_values = ca.Function("with_quantities", [w, *values.values()], [f, g])
        return self._with_values

    def _expressions_with(self, point: np.ndarray, quantities: dict[str, float]) -> tuple[float, np.ndarray]:
        """The objective and the constraint values (m,) at ``point`` with the given quantity values in
        place of the quadratures."""
        f, g = self._with_quantities()(point, *quantities.values())
        return float(f), np.asarray(g, dtype=float).ravel()
