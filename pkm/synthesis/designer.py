"""A synthesis problem built from a designer's data (DESIGN.md section 6): a task region of the mechanism,
the design variables with their bounds, the parameters held at given values, an objective (a global index
over the task, in its sense) and constraints (global indices over the task between bounds), for any
mechanism. :func:`design_problem` returns a :class:`pkm.synthesis.Problem` for the one driver, with a grid
or Monte Carlo baseline over the same bounds on the same model."""

from __future__ import annotations

import itertools
import math
import os
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions, io, registry, spec
from pkm.design import stack_design
from pkm.dynamics import Trajectory
from pkm.dynamics.quantities import effort_unit, joint_extremes, trajectory_indices
from pkm.errors import PkmError, UnknownNameError, check_name
from pkm.indices import GlobalIndex, LocalIndex
from pkm.regions import Box, Cylinder, Disc, Poses, Rectangle, TrajectoryRegion, trajectory_region
from pkm.synthesis.problem import Baseline, Constraint, Objective, Problem, Quantity, Variable

MONTE_CARLO_SEED = 0


class ProblemError(PkmError):
    """A designer's problem that names an unknown field or violates a condition."""


def _fail(field: str, condition: str) -> ProblemError:
    return ProblemError(f"problem field {field} violates: {condition}")


def _variables(mech: Any, raw: Mapping[str, Sequence[float]]) -> tuple[Variable, ...]:
    if not isinstance(raw, Mapping) or not raw:
        raise _fail("variables", "a non-empty mapping of parameter names to (lower, upper)")
    known = {p.name: p for p in mech.parameters}
    out = []
    for name, bounds in raw.items():
        check_name(f"{mech.name} design parameter", name, list(known))
        if name not in known:
            raise UnknownNameError(f"{mech.name} design parameter", name, list(known))
        if not isinstance(bounds, Sequence) or len(bounds) != 2:
            raise _fail(f"variables.{name}", "a pair (lower, upper)")
        lower, upper = (float(b) for b in bounds)
        p = known[name]
        if not (math.isfinite(lower) and math.isfinite(upper) and lower < upper):
            raise _fail(f"variables.{name}", f"finite lower < upper; got {lower:g}, {upper:g}")
        if lower < p.lower or upper > p.upper:
            raise _fail(f"variables.{name}", f"within the parameter's bounds [{p.lower:g}, {p.upper:g}]; got "
                                             f"[{lower:g}, {upper:g}]")
        out.append(Variable(name, lower, upper, p.unit, p.doc))
    return tuple(out)


SHAPES = {"disc": (Disc, 2, 1), "rectangle": (Rectangle, 2, 2), "box": (Box, 3, 3), "cylinder": (Cylinder, 3, 2)}


def task_poses(mech: Any, raw: Mapping[str, Any]) -> Poses:
    """A task of given poses in SI: {poses = [[...], ...]} or {file = a .npy or CSV file of them}, each a pose
    of the mechanism, every one of the same weight."""
    extra = set(raw) - {"poses", "file", "name"}
    if extra or len({"poses", "file"} & set(raw)) != 1:
        field = f"task.{sorted(extra)[0]}" if extra else "task"
        raise _fail(field, "a table {poses} or {file}, with an optional name")
    if "file" in raw:
        if not isinstance(raw["file"], str):
            raise _fail("task.file", f"a file name; got {raw['file']!r}")
        try:
            poses = io.read_poses(raw["file"], mech.pose_names)
        except PkmError as exc:
            raise _fail("task.file", str(exc)) from None
    else:
        rows = raw["poses"]
        if (not isinstance(rows, Sequence) or isinstance(rows, str) or not rows
                or not all(_numbers(row, mech.n_out) for row in rows)):
            raise _fail("task.poses", f"a non-empty list of poses, each {mech.n_out} finite numbers "
                                      f"({', '.join(mech.pose_names)})")
        poses = np.array(rows, dtype=float)
    if not np.all(np.isfinite(poses)):
        raise _fail("task.file", "finite poses")
    name = raw.get("name", "task")
    return Poses(name, f"the designer's {len(poses)} poses", tuple(map(tuple, poses.tolist())))


def _numbers(value: Any, count: int) -> bool:
    return (isinstance(value, Sequence) and not isinstance(value, str) and len(value) == count
            and all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in value))


def task_region(mech: Any, raw: Mapping[str, Any]) -> Any:
    """A task region placed in SI: {shape (disc, rectangle, box, cylinder), centre (a pose), size (a disc's
    radius; a rectangle's or box's half extents; a cylinder's radius and half length), axis (a cylinder's,
    a pose coordinate; the last by default)} over the mechanism's whole pose, or given poses
    (:func:`task_poses`)."""
    if not isinstance(raw, Mapping):
        raise _fail("task", "a region name of the mechanism or a table {shape, centre, size, axis} or {poses}")
    if "poses" in raw or "file" in raw:
        return task_poses(mech, raw)
    extra = set(raw) - {"shape", "centre", "size", "axis", "name"}
    if extra:
        raise _fail(f"task.{sorted(extra)[0]}", "a field of a task (shape, centre, size, axis, name)")
    if raw.get("shape") not in SHAPES:
        raise _fail("task.shape", f"one of {', '.join(SHAPES)}; got {raw.get('shape')!r}")
    cls, dimension, sizes = SHAPES[raw["shape"]]
    if dimension != mech.n_out:
        raise _fail("task.shape", f"a shape of the pose's dimension {mech.n_out} ({', '.join(mech.pose_names)}); "
                                  f"a {raw['shape']} has {dimension}")
    values = {}
    for field, count in (("centre", dimension), ("size", sizes)):
        value = raw.get(field)
        if not _numbers(value, count):
            raise _fail(f"task.{field}", f"a list of {count} finite numbers")
        values[field] = tuple(float(v) for v in value)
    if min(values["size"]) <= 0:
        raise _fail("task.size", f"every entry > 0; got {list(values['size'])}")
    extra_fields = {}
    if raw["shape"] == "cylinder":
        axis = raw.get("axis", mech.pose_names[-1])
        if axis not in mech.pose_names:
            raise _fail("task.axis", f"one of {', '.join(mech.pose_names)}; got {axis!r}")
        extra_fields["axis"] = mech.pose_names.index(axis)
    name = raw.get("name", "task")
    return cls(name, f"the designer's {raw['shape']} at {list(values['centre'])}, size {list(values['size'])}",
               fixed=(values["centre"], values["size"]), **extra_fields)


EXTREMES = {"_min": ("min", "max"), "_max": ("max", "min")}  # suffix of a local index's extreme: reduce, sense


def _index(mech: Any, name: str, field: str) -> GlobalIndex:
    """A global index the mechanism offers, or ``<local index>_min`` / ``_max``: a local index's least or
    largest value over the task."""
    if name in mech.global_indices():
        return registry.global_index(name)
    for suffix, (reduce, sense) in EXTREMES.items():
        local = name[: -len(suffix)]
        if name.endswith(suffix) and local in mech.local_indices():
            spec = registry.local_index(local)
            return GlobalIndex(name, spec, f"the region {reduce}imum of {local} ({spec.doc})", reduce, sense)
    offered = [*mech.global_indices(), *(f"{i}_min" for i in mech.local_indices())]
    raise _fail(field, f"a global index {mech.name} offers or a local index's _min or _max ({', '.join(offered)}); "
                       f"got {name!r}")


def _trajectory(mech: Any, raw: Any) -> TrajectoryRegion | None:
    """A trajectory through the task: a region or move as given, or in SI moves from rest to rest between
    consecutive waypoints: {waypoints = [[...], ...], v_max, a_max}, trapezoidal velocity profiles (jumps of
    acceleration at the switches), or {waypoints, durations = [...]}, one smooth move per segment in its
    duration (the degree-9 polynomial of :func:`pkm.dynamics.trajectories.rest_to_rest`: velocity,
    acceleration, jerk and snap zero at both ends, the jerk bounded)."""
    if raw is None or isinstance(raw, TrajectoryRegion):
        return raw
    if isinstance(raw, Trajectory):
        return trajectory_region(raw)
    if not isinstance(raw, Mapping) or set(raw) not in ({"waypoints", "v_max", "a_max"}, {"waypoints", "durations"}):
        raise _fail("trajectory", "a table {waypoints = [[...], ...], v_max, a_max} (trapezoidal) or {waypoints, "
                                  "durations} (smooth) in SI")
    points = raw["waypoints"]
    if not (isinstance(points, Sequence) and len(points) >= 2 and all(_numbers(p, mech.n_out) for p in points)):
        raise _fail("trajectory.waypoints", f"two or more poses, each {mech.n_out} finite numbers "
                                            f"({', '.join(mech.pose_names)})")
    segments = list(itertools.pairwise(points))
    if "durations" in raw and not _numbers(raw["durations"], len(segments)):
        raise _fail("trajectory.durations", f"{len(segments)} finite durations in s, one per segment between the "
                                            "waypoints")
    try:
        moves = ([Trajectory.trapezoidal(a, b, raw["v_max"], raw["a_max"]) for a, b in segments]
                 if "v_max" in raw else
                 [Trajectory.point_to_point(a, b, t) for (a, b), t in zip(segments, raw["durations"], strict=True)])
    except PkmError as exc:
        raise _fail("trajectory", str(exc)) from None
    return trajectory_region(moves)


def _quantity(mech: Any, name: str, field: str, *, region: Any, along: TrajectoryRegion | None,
              indices: Mapping[str, GlobalIndex]) -> Quantity:
    """A trajectory quantity (:mod:`pkm.dynamics.quantities`) over the trajectory, or a global index over the
    task (:func:`_index`)."""
    if name in indices:
        if along is None:
            raise _fail(field, f"{name} is taken along a trajectory: give the problem a trajectory")
        return Quantity(indices[name], along)
    return Quantity(_index(mech, name, field), region)


PHYSICAL = ("joint", "joint_range", "effort")


def _joint_extremes(mech: Any, name: str, field: str) -> tuple[GlobalIndex, GlobalIndex]:
    """The least and the largest value of an actuated joint over the task (:func:`joint_extremes`)."""
    if name not in mech.actuator_names:
        raise _fail(field, f"an actuated joint of {mech.name} ({', '.join(mech.actuator_names)}); got {name!r}")
    return joint_extremes(mech, name)


def _effort(mech: Any, wrench: Any, field: str) -> LocalIndex:
    """The largest actuator effort |tau_i| that holds the wrench w at the end effector, tau = J_f^T w (virtual
    work: tau . q_dot = w . x_dot with x_dot = J_f q_dot); w in the pose's dual units (N for a length, N m for
    an angle)."""
    if not _numbers(wrench, mech.n_out):
        raise _fail(field, f"a wrench of {mech.n_out} finite numbers, dual to the pose ({', '.join(mech.pose_names)})")
    w = ca.DM(wrench)
    return LocalIndex(
        "effort", f"largest actuator effort |J_f^T w| holding the wrench w = {list(wrench)} at the end effector",
        effort_unit(mech), 0.0, np.inf, np.inf, lambda J_f: ca.mmax(ca.fabs(J_f.T @ w)), "first_order",
        ("J_f",), epigraph_upper=lambda J_f, t: ca.vertcat(t - J_f.T @ w, t + J_f.T @ w), dimension=None, raw=True,
    )


def _physical(mech: Any, what: Mapping[str, Any], bounds: tuple[float, float], field: str, *, region: Any,
              quantities: dict[str, Quantity]) -> list[Constraint]:
    """{joint: an actuated joint} within [lower, upper] over the task, {joint_range: one} moving at most
    ``upper`` over it (its largest minus its least value), or {effort: a wrench} needing actuator efforts of
    at most ``upper`` at every pose of it; each a region extreme, refined between the nodes."""
    if len(what) != 1 or next(iter(what)) not in PHYSICAL:
        raise _fail(field, f"a table with one of {', '.join(PHYSICAL)}; got {sorted(what)}")
    kind, value = next(iter(what.items()))
    lower, upper = bounds
    if kind == "effort":
        local = _effort(mech, value, f"{field}.effort")
        name = next(n for n in (f"effort_{k}" if k else "effort" for k in range(len(quantities) + 1))
                    if n not in quantities)
        quantities[name] = Quantity(GlobalIndex(name, local, f"the region maximum of {local.doc}", "max", "min"),
                                    region)
        return [Constraint(f"{name} holding {list(value)} <= {upper:g} {local.unit}", lambda t: t[name], -math.inf,
                           upper)]
    low, high = _joint_extremes(mech, value, f"{field}.{kind}")
    least, largest, local = low.name, high.name, low.local
    quantities[least], quantities[largest] = Quantity(low, region), Quantity(high, region)
    if kind == "joint_range":
        return [Constraint(f"range of {value} <= {upper:g} {local.unit}", lambda t: t[largest] - t[least],
                           -math.inf, upper)]
    return [Constraint(f"{least} >= {lower:g} {local.unit}", lambda t: t[least], lower, math.inf),
            Constraint(f"{largest} <= {upper:g} {local.unit}", lambda t: t[largest], -math.inf, upper)]


def _parameter_expression(mech: Any, text: str, field: str) -> Callable[[Mapping[str, Any]], Any]:
    """An expression of the design parameters (a frame size, a sum of lengths) as a function of their values
    by name (numbers, arrays or CasADi)."""
    names = set(mech.parameter_names())
    if not isinstance(text, str):
        raise _fail(field, f"an expression of the design parameters; got {text!r}")
    tree = expressions.parse(text)
    if tree is None or expressions.unknown_names(tree, {*names, *FUNCTIONS}):
        raise _fail(field, f"arithmetic of the design parameters ({', '.join(sorted(names))}) and "
                           f"{', '.join(FUNCTIONS)}; got {text!r}")
    code = compile(tree, field, "eval")

    def value(values: Mapping[str, Any]) -> Any:
        symbolic = any(isinstance(values[n], ca.SX | ca.MX) for n in names)
        functions = {k: getattr(ca, k) if symbolic else getattr(np, NUMPY.get(k, k)) for k in FUNCTIONS if k != "pi"}
        return eval(code, {"__builtins__": {}}, {"pi": math.pi, **functions, **{n: values[n] for n in names}})

    return value


FUNCTIONS = ("pi", "cos", "sin", "tan", "sqrt", "asin", "acos", "atan")
NUMPY = {"asin": "arcsin", "acos": "arccos", "atan": "arctan"}


def _objective(raw: str | Mapping[str, float], quantity: Callable[[str, str], Quantity],
               quantities: dict[str, Quantity]) -> Objective:
    """A global index in its sense, or a weighted combination {index: weight}: maximise the sum of each
    weight times its index (negated where the index is better smaller); ``quantity(name, field)`` the quantity
    a name stands for."""
    if isinstance(raw, str):
        quantities[raw] = quantity(raw, "objective")
        return Objective.of(raw, quantities[raw])
    if not isinstance(raw, Mapping) or not raw:
        raise _fail("objective", "a global index or a table {index = weight}")
    signs = {}
    for name, weight in raw.items():
        if isinstance(weight, bool) or not isinstance(weight, int | float) or not math.isfinite(weight):
            raise _fail(f"objective.{name}", "a finite weight")
        quantities[name] = quantity(name, f"objective.{name}")
        signs[name] = float(weight) * (1.0 if quantities[name].index.sense == "max" else -1.0)
    text = " + ".join(f"{w:g} {n}" for n, w in raw.items())
    return Objective(lambda t: sum(s * t[n] for n, s in signs.items()), "max", f"the weighted sum {text} "
                     "(each index negated where smaller is better)")


def monte_carlo_baseline(problem: Problem, samples: int, seed: int = MONTE_CARLO_SEED,
                         doc: str = "the best of designs drawn uniformly over the bounds") -> Baseline:
    """Random search over the variables' bounds (a fixed seed) as a baseline."""
    lower = np.array([v.lower for v in problem.variables])
    upper = np.array([v.upper for v in problem.variables])
    return Baseline("monte_carlo", doc,
                    lambda n: np.random.default_rng(seed).uniform(lower, upper, size=(n, len(lower))), samples)


def design_problem(
    mechanism: Any,
    *,
    task: str | Any,
    variables: Mapping[str, Sequence[float]],
    fixed: Mapping[str, float] | None = None,
    objective: str | Mapping[str, float] = "gci",
    constraints: Sequence[tuple[str, float, float]] = (("workspace_margin_min", 0.0, math.inf),),
    derived: Mapping[str, str] | None = None,
    mode: str | None = None,
    name: str | None = None,
    doc: str | None = None,
    baseline: tuple[str, int] = ("grid", 21),
    resolution: int = 8,
    trajectory: Any = None,
    encoder: Sequence[float] | None = None,
) -> Problem:
    """A synthesis over the task region ``task`` (a region name of the mechanism, a region, a table placing one in
    SI, :func:`task_region`, or given poses, :func:`task_poses`) of ``mechanism`` (a name, a description file or a
    mechanism): the ``variables`` between their bounds, the parameters in ``fixed`` at their values and the others
    at their defaults; ``objective`` a global index over the task in its sense, or a weighted combination {index:
    weight} (maximised, each index negated where smaller is better); ``constraints`` (what, lower, upper): a global
    index over the task, a local index's least or largest value over it (``inverse_condition_f_min``: a singularity
    margin), an expression of the design parameters (a frame size, ``2 * (d1 + d2)``), or a table: ``{"joint":
    name}`` (an actuated joint within [lower, upper] over the task), ``{"joint_range": name}`` (its largest minus
    its least value at most upper) or ``{"effort": wrench}`` (the actuator efforts that hold a payload's wrench at
    every pose of the task at most upper, :func:`_effort`); by default the task inside the workspace (the least
    workspace margin over it at least 0); ``derived`` parameters set by expressions of the others, in order (a
    stroke that follows a link length); the baseline ``("grid", points per axis)`` or ``("monte_carlo", samples)``.
    IPOPT takes a limited-memory Hessian where a quantity is a region minimum or maximum (its epigraph
    holds every node, and the exact Hessian of those rows costs more than it saves). With ``trajectory`` (a
    :class:`pkm.regions.TrajectoryRegion`, a move, or {waypoints, v_max, a_max}: trapezoidal moves between the
    waypoints), the objective and constraints may name the trajectory quantities (``effort_peak``, ``energy``,
    ..., :mod:`pkm.dynamics.quantities`; ``encoder`` the resolutions of ``positioning_error``), taken along it.
    """
    mech = spec.resolve_name(mechanism) if isinstance(mechanism, str) else mechanism
    region = mech.region(task) if isinstance(task, str) else task_region(mech, task) if isinstance(task, Mapping) \
        else task
    task_name = task if isinstance(task, str) else region.name
    chosen = _variables(mech, variables)
    given = dict(fixed or {})
    checked = dict(mech.design(given, partial=True)) if given else {}
    held = {name: checked[name] for name in given}
    overlap = set(held) & {v.name for v in chosen}
    if overlap:
        raise _fail("fixed", f"no parameter that is also a variable; {sorted(overlap)[0]} is both")
    base = {**dict(mech.design()), **held}
    order = [v.name for v in chosen]
    mode = mech.working_mode(mode).name
    rules = {}
    for target, text in (derived or {}).items():
        if target not in base or target in order or target in held:
            raise _fail(f"derived.{target}", "a design parameter that is neither a variable nor fixed")
        rules[target] = _parameter_expression(mech, text, f"derived.{target}")

    def design(values: Sequence[Any]) -> Any:
        given = {**base, **dict(zip(order, values, strict=True))}
        for target, rule in rules.items():
            given[target] = rule(given)
        return stack_design([given[n] for n in mech.parameter_names()])

    along = _trajectory(mech, trajectory)
    indices = mech.trajectory_quantities if encoder is None else trajectory_indices(mech, encoder=encoder)

    def quantity(name: str, field: str) -> Quantity:
        return _quantity(mech, name, field, region=region, along=along, indices=indices)

    quantities: dict[str, Quantity] = {}
    goal = _objective(objective, quantity, quantities)
    stated = []
    for k, item in enumerate(constraints):
        if not (isinstance(item, Sequence) and len(item) == 3):
            raise _fail(f"constraints[{k}]", "a triple (index or expression, lower, upper)")
        what, lower, upper = item
        if not isinstance(what, str | Mapping):
            raise _fail(f"constraints[{k}]", "an index's name, an expression of the design parameters or a table "
                                             "{joint}, {joint_range} or {effort}")
        lower, upper = float(lower), float(upper)
        if not lower <= upper:
            raise _fail(f"constraints[{k}]", f"lower <= upper; got {lower:g}, {upper:g}")
        if isinstance(what, Mapping):
            stated += _physical(mech, what, (lower, upper), f"constraints[{k}]", region=region,
                                quantities=quantities)
        elif what.isidentifier() and what not in mech.parameter_names():
            quantities.setdefault(what, quantity(what, f"constraints[{k}]"))
            stated.append(Constraint(f"{lower:g} <= {what} over {task_name} <= {upper:g}",
                                     lambda t, what=what: t[what], lower, upper))
        else:
            rule = _parameter_expression(mech, what, f"constraints[{k}]")
            stated.append(Constraint(f"{lower:g} <= {what} <= {upper:g}",
                                     lambda t, rule=rule: rule({n: t[n] for n in mech.parameter_names()}),
                                     lower, upper))
    measured = [n for n, q in quantities.items() if q.index.reduce == "measure"]
    if measured and isinstance(region, Poses):
        raise _fail("task", f"a region with a measure for {measured[0]}; given poses have none")
    sense = "maximise" if goal.sense == "max" else "minimise"
    named = objective if isinstance(objective, str) else "weighted"
    problem = Problem(
        name=name or f"{mech.name}.{named}_{task_name}",
        doc=doc or f"{sense} {goal.doc if named == 'weighted' else named} over the region {task_name} in "
                   f"{', '.join(order)}, working mode {mode}",
        mechanism=mech,
        variables=chosen,
        design=design,
        quantities=quantities,
        objective=goal,
        constraints=tuple(stated),
        mode=mode,
        resolution=resolution,
        hessian="limited-memory" if any(q.index.reduce in ("min", "max") for q in quantities.values()) else "exact",
        notes={"task": task_name, "fixed": held},
    )
    kind, size = baseline
    if kind == "grid":
        found = problem.grid_baseline(size)
    elif kind == "monte_carlo":
        found = monte_carlo_baseline(problem, size)
    else:
        raise _fail("baseline", f"('grid', points per axis) or ('monte_carlo', samples); got {kind!r}")
    return replace(problem, baselines=(found,))


PROBLEM_FIELDS = {"name", "doc", "mechanism", "task", "variables", "fixed", "derived", "objective", "constraints",
                  "mode", "baseline", "resolution", "trajectory", "encoder"}


def read_problem(path: str | os.PathLike) -> Problem:
    """:func:`design_problem` from a TOML file: ``mechanism`` (a name or a description file, relative to the
    file), ``task`` (a region name or a table {shape, centre, size, axis}), ``variables`` {name = [lower,
    upper]}, optionally ``fixed`` {name = value}, ``objective`` (a global index), ``constraints`` (a list of
    {index, lower, upper}), ``mode``, ``baseline`` {kind = "grid" or "monte_carlo", size}, ``resolution``,
    ``trajectory`` {waypoints, v_max, a_max} and ``encoder`` (:func:`design_problem`), ``name`` and ``doc``."""
    path = Path(path)
    try:
        raw = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ProblemError(f"problem file {path}: {exc}") from None
    extra = set(raw) - PROBLEM_FIELDS
    if extra:
        raise _fail(sorted(extra)[0], f"a known field ({', '.join(sorted(PROBLEM_FIELDS))})")
    for field in ("mechanism", "task", "variables"):
        if field not in raw:
            raise _fail(field, "given")
    mechanism = raw["mechanism"]
    if not isinstance(mechanism, str):
        raise _fail("mechanism", "a mechanism's name or a description file")
    if mechanism.endswith(".toml"):
        mechanism = str((path.parent / mechanism).resolve())
    constraints = raw.get("constraints", [{"index": "workspace_margin_min", "lower": 0.0}])
    if not isinstance(constraints, list):
        raise _fail("constraints", "a list of tables {index, lower, upper}")
    triples = []
    kinds = ("index", "expression", *PHYSICAL)
    for k, c in enumerate(constraints):
        if not isinstance(c, Mapping) or len(set(kinds) & set(c)) != 1 or set(c) - {*kinds, "lower", "upper"}:
            raise _fail(f"constraints[{k}]", f"a table {{one of {', '.join(kinds)}; lower, upper}}")
        (kind,) = set(kinds) & set(c)
        what = c[kind] if kind in ("index", "expression") else {kind: c[kind]}
        triples.append((what, float(c.get("lower", -math.inf)), float(c.get("upper", math.inf))))
    task = raw["task"]
    if isinstance(task, Mapping) and isinstance(task.get("file"), str):
        task = {**task, "file": str(path.parent / task["file"])}
    baseline = raw.get("baseline", {"kind": "grid", "size": 21})
    if not isinstance(baseline, Mapping) or set(baseline) - {"kind", "size"}:
        raise _fail("baseline", "a table {kind, size}")
    size = baseline.get("size", 21)
    if isinstance(size, bool) or not isinstance(size, int) or size < 2:
        raise _fail("baseline.size", f"an integer >= 2; got {size!r}")
    resolution = raw.get("resolution", 8)
    if isinstance(resolution, bool) or not isinstance(resolution, int) or not 2 <= resolution <= 64:
        raise _fail("resolution", f"an integer from 2 to 64; got {resolution!r}")
    return design_problem(
        mechanism, task=task, variables=raw["variables"], fixed=raw.get("fixed"), derived=raw.get("derived"),
        objective=raw.get("objective", "gci"), constraints=triples, mode=raw.get("mode"),
        name=raw.get("name"), doc=raw.get("doc"), baseline=(baseline.get("kind", "grid"), size),
        resolution=resolution, trajectory=raw.get("trajectory"), encoder=raw.get("encoder"),
    )
