"""What a synthesis problem states (DESIGN.md section 6).

A :class:`Problem` names its variables with bounds and units, maps them to a complete design vector
(numpy or CasADi, so that the same map serves the grids and the NLP), names the quantities it reads
(global indices over regions), states an objective and named constraints as expressions of those
quantities, the variables, the design parameters and the outputs of generated design functions
(:class:`Terms`), a working mode, and the baselines it is compared with. A problem may state
:class:`Setting` s, values its user chooses (a task's size, a joint limit, a load): :meth:`Problem.configure`
builds the same problem with other values. Problems are declared by the mechanism packages
(``pkm/models/<name>/problems.py``) and solved by the one driver, :func:`pkm.synthesis.synthesize`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from pkm.errors import PkmError, UnknownNameError, check_real
from pkm.indices import GlobalIndex
from pkm.indices.local import SINGULARITY


@dataclass(frozen=True)
class Variable:
    """A design variable of a synthesis: name, bounds, unit, meaning."""

    name: str
    lower: float
    upper: float
    unit: str = "-"
    doc: str = ""


@dataclass(frozen=True)
class Setting:
    """A value the user of a problem chooses (a task's size, a joint limit, a load): name, default,
    bounds (closed), unit, meaning."""

    name: str
    default: float
    lower: float
    upper: float
    unit: str = "-"
    doc: str = ""

    def check(self, value: object) -> float:
        """``value`` as a float; :class:`PkmError` naming the setting unless it lies within the bounds."""
        condition = f"{self.lower:g} <= {self.name} <= {self.upper:g} [{self.unit}]"
        number = check_real(self.name, value, condition)
        if not self.lower <= number <= self.upper:
            raise PkmError(f"{self.name} = {number:g} violates: {condition}")
        return number


@dataclass(frozen=True)
class Quantity:
    """A global index over a parametrised region, in the problem's working mode."""

    index: GlobalIndex
    region: Any


MARGIN = "singularity_margin_min"  # the quantity of the singularity margin a problem holds over its task
SINGULARITY_MARGIN = 0.01  # the least singularity margin a task holds by default


@dataclass(frozen=True)
class Margin:
    """The singularity margin a problem holds over its task, the region ``region``: the least of the type I and
    type II margins over it at least ``value`` (0: none), and why, which its results state."""

    value: float | None  # None: the problem's own constraint on singularity_margin_min states it
    why: str
    region: Any

    def __str__(self) -> str:
        if self.value is None:
            return f"singularity margin over {self.region.name} as {self.why} states it"
        if self.value > 0:
            return f"singularity margin held at {self.value:g} over {self.region.name} ({self.why})"
        return f"singularity margin off over {self.region.name} ({self.why})"


class Terms(Mapping[str, Any]):
    """The values an objective or constraint expression reads, by name: the problem's quantities,
    its variables and the design parameters (numpy or CasADi), and with :meth:`call` the outputs of
    the mechanism's generated design functions at the design."""

    def __init__(self, values: Mapping[str, Any], functions: Mapping[str, Any], design: Any) -> None:
        self._values = dict(values)
        self._functions = functions
        self._design = design

    def __getitem__(self, name: str) -> Any:
        if name not in self._values:
            raise PkmError(f"an expression reads {name!r}, which is none of {', '.join(self._values)}")
        return self._values[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def call(self, function: str, output: str) -> Any:
        """Output ``output`` of the generated function ``function(design)``."""
        fn = self._functions[function]
        return fn(self._design)[fn.name_out().index(output)]


@dataclass(frozen=True)
class Constraint:
    """A named constraint lower <= expression(terms) <= upper. The optimiser holds it ``margin`` inside
    its bounds at its quadrature, so that it holds between the nodes too; checks use the bounds."""

    name: str
    expression: Callable[[Terms], Any]
    lower: float = 0.0
    upper: float = math.inf
    margin: float = 0.0


def requirement_constraints(space: Any, coordinates: Callable[[Terms], Mapping[str, Any]]) -> tuple[Constraint, ...]:
    """The requirements of a design space's admissible designs (:class:`pkm.design_space.Requirement`) as
    constraints, ``coordinates(terms)`` the normalised coordinates by name: a synthesis over the space
    admits the designs its atlases admit."""
    return tuple(Constraint(r.name, lambda t, r=r: r.value(coordinates(t), t.call), r.lower, r.upper)
                 for r in space.requirements)


@dataclass(frozen=True)
class Objective:
    """The objective: an expression of the terms and its sense (``"max"`` or ``"min"``). ``quantity``
    names the quantity when the objective is that quantity alone; a region minimum maximised is then
    solved in epigraph form."""

    expression: Callable[[Terms], Any]
    sense: str
    doc: str
    quantity: str | None = None

    @classmethod
    def of(cls, name: str, quantity: Quantity) -> Objective:
        """A quantity as the objective, in its index's sense."""
        return cls(lambda t: t[name], quantity.index.sense, quantity.index.doc, name)


MAX_GRID_POINTS = 10_000_000


def grid_points(variables: Sequence[Variable], resolution: int) -> np.ndarray:
    """A regular grid (resolution^n, n) over the variables' bounds, bounds included; at most
    MAX_GRID_POINTS points."""
    if resolution ** len(variables) > MAX_GRID_POINTS:
        raise PkmError(f"resolution = {resolution} violates: resolution^{len(variables)} <= {MAX_GRID_POINTS} "
                       "grid points")
    axes = [np.linspace(v.lower, v.upper, resolution) for v in variables]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1)


@dataclass(frozen=True)
class Baseline:
    """A search by the papers' own method, run through the same model: ``points(resolution)`` gives its
    candidate variable values (N, n); the best feasible one is its result. A baseline that
    ``follows_resolution`` takes the resolution a caller asks of the baselines instead of its own."""

    name: str
    doc: str
    points: Callable[[int], np.ndarray]
    resolution: int
    follows_resolution: bool = True


@dataclass(frozen=True, eq=False)
class Problem:
    """A dimensional synthesis: variables, their map to a design, quantities, objective, constraints,
    working mode, baselines and the resolutions and IPOPT settings it is solved with.

    ``design(values)`` takes the variables in order (arrays of one shape, or CasADi scalars) and returns
    the complete design vector: (..., n_p) numpy, or an n_p x 1 CasADi column. ``starting_points`` adds
    screening points (N, n) to the grid over the bounds. ``settings`` are the values its user may choose,
    ``values`` the ones it was built with, and ``build(values)`` builds it with others (:meth:`configure`).
    """

    name: str
    doc: str
    mechanism: Any
    variables: tuple[Variable, ...]
    design: Callable[[Sequence[Any]], Any]
    quantities: Mapping[str, Quantity]
    objective: Objective
    constraints: tuple[Constraint, ...] = ()
    mode: str | None = None
    baselines: tuple[Baseline, ...] = ()
    starting_points: Callable[[], np.ndarray] | None = None
    resolution: int = 8
    screening_resolution: int = 9
    starts: int = 4
    hessian: str = "exact"
    max_iter: int = 500
    tol: float = 1e-10
    feasibility_tolerance: float = 1e-7
    notes: Mapping[str, Any] = field(default_factory=dict)
    settings: tuple[Setting, ...] = ()
    values: Mapping[str, float] = field(default_factory=dict)
    build: Callable[[Mapping[str, float]], Problem] | None = None
    secondaries: Mapping[str, Objective | Quantity] = field(default_factory=dict)
    margin: Margin | None = None  # the singularity margin it holds over its task; None where it states none

    def configure(self, **values: object) -> Problem:
        """The same problem with some settings at other values (the others as they are here); every problem
        takes ``singularity_margin`` (:meth:`holding`)."""
        known = {s.name: s for s in self.settings}
        margin = values.pop("singularity_margin", None)
        for name in values:
            if name not in known:
                raise UnknownNameError(f"setting of {self.name}", name, [*known, "singularity_margin"])
        checked = {name: known[name].check(value) for name, value in values.items()}
        problem = self.build({**self.values, **checked}) if checked else self
        if margin is None:
            held = self.margin is not None and self.margin.value and problem.margin != self.margin
            return problem.holding(self.margin.value, self.margin.why) if held else problem
        value = check_real("singularity_margin", margin, "0 <= singularity_margin < 1")
        if not 0 <= value < 1:
            raise PkmError(f"singularity_margin violates: 0 <= singularity_margin < 1; got {value:g}")
        return problem.holding(value, "as asked")

    def holding(self, value: float, why: str, region: Any = None) -> Problem:
        """The problem holding its task ``value`` from singularity: the constraint ``singularity_margin_min >=
        value`` over ``region`` (its task's, stated or the objective's quantity's, by default) in place of any it
        held, none at 0; ``why`` its reason, which its results state."""
        if region is None and self.margin is not None:
            region = self.margin.region
        if region is None:
            quantity = self.quantities.get(self.objective.quantity or "")
            if quantity is None:
                raise PkmError(f"problem {self.name}: a singularity margin needs a region (its objective is not "
                               "one quantity)")
            region = quantity.region
        quantities = {k: v for k, v in self.quantities.items() if k != MARGIN}
        constraints = tuple(c for c in self.constraints if not c.name.startswith(MARGIN))
        if value > 0:
            quantities[MARGIN] = Quantity(GlobalIndex(MARGIN, SINGULARITY, f"the region minimum of "
                                                      f"{SINGULARITY.name} ({SINGULARITY.doc})", "min", "max"), region)
            constraints += (Constraint(f"{MARGIN} over {region.name} >= {value:g} ({why})", lambda t: t[MARGIN],
                                       value, math.inf),)
        hessian = "limited-memory" if value > 0 else self.hessian  # a region minimum's epigraph holds every node
        return replace(self, quantities=quantities, constraints=constraints, hessian=hessian,
                       margin=Margin(value, why, region))

    @property
    def variable_names(self) -> tuple[str, ...]:
        return tuple(v.name for v in self.variables)

    def grid_baseline(self, resolution: int, doc: str = "the best node of a regular grid over the bounds") -> Baseline:
        """The grid search over the variables' bounds as a baseline."""
        return Baseline("grid", doc, lambda n: grid_points(self.variables, n), resolution)
