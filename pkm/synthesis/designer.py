"""A synthesis problem built from a designer's data (DESIGN.md section 6): a task region of the mechanism,
the design variables with their bounds, the parameters held at given values, an objective (a global index
over the task, in its sense) and constraints (global indices over the task between bounds), for any
mechanism. :func:`design_problem` returns a :class:`pkm.synthesis.Problem` for the one driver, with a grid
or Monte Carlo baseline over the same bounds on the same model.

Every field is checked before anything is computed, each kind of field by one helper (:func:`_table`,
:func:`_list`, :func:`_number`, :func:`_name`, :func:`_string`), and a violation is a :class:`ProblemError`
naming the field, the condition and the value given. Expressions (a constraint's ``expression``, a
``derived`` parameter) are read into :mod:`pkm.expressions`' tree, never evaluated as Python."""

from __future__ import annotations

import itertools
import math
import numbers
import os
import re
import reprlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions, io, registry
from pkm.accuracy import error_model
from pkm.design import MAX_MAGNITUDE, completed, stack_design
from pkm.dynamics import Trajectory
from pkm.dynamics.quantities import effort_unit, joint_extremes, trajectory_indices
from pkm.errors import PkmError
from pkm.indices import GlobalIndex, LocalIndex
from pkm.regions import Box, Cylinder, Disc, Poses, Rectangle, TrajectoryRegion, trajectory_region
from pkm.spec.machine import resolve_name
from pkm.synthesis.problem import (
    MARGIN,
    SINGULARITY_MARGIN,
    Baseline,
    Constraint,
    Margin,
    Objective,
    Problem,
    Quantity,
    Variable,
)

MONTE_CARLO_SEED = 0
MAX_BOUND = 1e15  # the largest magnitude of a constraint's bound or an objective's weight (SI): IPOPT takes
# a bound beyond 1e19 for none, and one near 1e308 overflows in its restoration phase, which then never ends
MAX_BASELINE_POINTS = 1_000_000  # designs a baseline evaluates at most: a grid's nodes, Monte Carlo's samples
NAME = re.compile(r"[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)*")  # CasADi's function names, which pkm's follow
DOTTED = re.compile(rf"{NAME.pattern}(?:\.{NAME.pattern})*")  # a problem's: its dots become underscores
FIELD_CHARACTERS = 80  # of a field's name in an error at most
_MISSING = object()


class ProblemError(PkmError):
    """A designer's problem that names an unknown field or violates a condition."""


def _fail(field: str, condition: str, value: Any = _MISSING) -> ProblemError:
    """The error of ``field`` violating ``condition``, quoting ``value`` where one is given; both shortened
    (a field's name holds the file's keys)."""
    field = field if len(field) <= FIELD_CHARACTERS else f"{field[: FIELD_CHARACTERS - 3]}..."
    got = "" if value is _MISSING else f"; got {reprlib.repr(value)}"
    return ProblemError(f"problem field {field} violates: {condition}{got}")


@contextmanager
def _field(field: str) -> Iterator[None]:
    """A :class:`PkmError` of another module's check within the block (a mechanism's, a region's, a
    design's, a trajectory's) as the :class:`ProblemError` of ``field``."""
    try:
        yield
    except ProblemError:
        raise
    except PkmError as exc:
        raise _fail(field, str(exc)) from None


def _table(value: Any, field: str, condition: str = "a table") -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise _fail(field, condition, value)
    return value


def _list(value: Any, field: str, condition: str) -> Sequence[Any]:
    if isinstance(value, str | bytes | Mapping) or not isinstance(value, Sequence):
        raise _fail(field, condition, value)
    return value


def _string(value: Any, field: str, condition: str) -> str:
    if not isinstance(value, str):
        raise _fail(field, condition, value)
    return value


def _file_name(value: Any, field: str, condition: str) -> str:
    """A string the system takes for a file name: one without a NUL character."""
    if "\0" in _string(value, field, condition):
        raise _fail(field, f"{condition} (without a NUL character)", value)
    return value


def _real(value: Any, limit: float = MAX_BOUND) -> bool:
    """Whether ``value`` is a real number (not a boolean) of magnitude at most ``limit``, so finite."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_) and abs(value) <= limit


def _number(value: Any, field: str, *, limit: float = MAX_BOUND) -> float:
    if not _real(value, limit):
        raise _fail(field, f"a finite number of magnitude at most {limit:g}", value)
    return float(value)


def _numbers(value: Any, count: int) -> bool:
    """Whether ``value`` is a list of ``count`` finite numbers (:func:`_real`)."""
    return (isinstance(value, Sequence) and not isinstance(value, str) and len(value) == count
            and all(_real(v) for v in value))


def _name(value: Any, field: str, *, dotted: bool = False) -> str:
    """A name pkm gives CasADi's functions too: ASCII letters and digits, single underscores (and dots,
    where ``dotted``) between them, a letter first."""
    pattern = DOTTED if dotted else NAME
    if not (isinstance(value, str) and pattern.fullmatch(value) and ca.Function.check_name(value.replace(".", "_"))):
        joints = "underscores or dots" if dotted else "underscores"
        raise _fail(field, f"a name of ASCII letters and digits with single {joints} between them, a letter first",
                    value)
    return value


def _bound(value: Any, field: str, none: float) -> float:
    """A constraint's bound: a finite number of magnitude at most MAX_BOUND, or ``none`` (-inf for a lower
    bound, inf for an upper one) for no bound."""
    if isinstance(value, float) and value == none:
        return value
    if not _real(value):
        raise _fail(field, f"a finite number of magnitude at most {MAX_BOUND:g} (left out: no bound)", value)
    return float(value)


def _variables(mech: Any, raw: Any) -> tuple[Variable, ...]:
    """The design variables {name = (lower, upper)}, each a parameter of the mechanism between finite bounds
    within the parameter's own."""
    if not _table(raw, "variables", "a non-empty table {parameter = [lower, upper]}"):
        raise _fail("variables", "a non-empty table {parameter = [lower, upper]}", raw)
    known = {p.name: p for p in mech.parameters}
    out = []
    for name, bounds in raw.items():
        if name not in known:
            raise _fail("variables", f"a parameter of the {mech.name} ({', '.join(known)})", name)
        if len(_list(bounds, f"variables.{name}", "a pair [lower, upper]")) != 2:
            raise _fail(f"variables.{name}", "a pair [lower, upper]", bounds)
        lower, upper = (_number(b, f"variables.{name}", limit=MAX_MAGNITUDE) for b in bounds)
        p = known[name]
        if not lower < upper:
            raise _fail(f"variables.{name}", "lower < upper", list(bounds))
        if lower < p.lower or upper > p.upper:
            raise _fail(f"variables.{name}", f"within the parameter's bounds [{p.lower:g}, {p.upper:g}]", list(bounds))
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
        with _field("task.file"):
            poses = io.read_poses(_file_name(raw["file"], "task.file", "a file name"), mech.pose_names)
    else:
        rows = raw["poses"]
        if (not isinstance(rows, Sequence) or isinstance(rows, str) or not rows
                or not all(_numbers(row, mech.n_out) for row in rows)):
            raise _fail("task.poses", f"a non-empty list of poses, each {mech.n_out} finite numbers "
                                      f"({', '.join(mech.pose_names)})")
        poses = np.array(rows, dtype=float)
    name = _name(raw.get("name", "task"), "task.name")
    return Poses(name, f"the designer's {len(poses)} poses", tuple(map(tuple, poses.tolist())))


def task_region(mech: Any, raw: Mapping[str, Any]) -> Any:
    """A task region placed in SI: {shape (disc, rectangle, box, cylinder), centre (a pose), size (a disc's
    radius; a rectangle's or box's half extents; a cylinder's radius and half length), axis (a cylinder's,
    a pose coordinate; the last by default)} over the mechanism's whole pose, or given poses
    (:func:`task_poses`)."""
    _table(raw, "task", "a region name of the mechanism or a table {shape, centre, size, axis} or {poses}")
    if "poses" in raw or "file" in raw:
        return task_poses(mech, raw)
    extra = set(raw) - {"shape", "centre", "size", "axis", "name"}
    if extra:
        raise _fail(f"task.{sorted(extra)[0]}", "a field of a task (shape, centre, size, axis, name)")
    shape = raw.get("shape")
    if not isinstance(shape, str) or shape not in SHAPES:
        raise _fail("task.shape", f"one of {', '.join(SHAPES)}", shape)
    cls, dimension, sizes = SHAPES[shape]
    if dimension != mech.n_out:
        raise _fail("task.shape", f"a shape of the pose's dimension {mech.n_out} ({', '.join(mech.pose_names)}); "
                                  f"a {shape} has {dimension}")
    values = {}
    for field, count in (("centre", dimension), ("size", sizes)):
        value = raw.get(field)
        if not _numbers(value, count):
            raise _fail(f"task.{field}", f"a list of {count} finite numbers of magnitude at most {MAX_BOUND:g}",
                        value)
        values[field] = tuple(float(v) for v in value)
    if min(values["size"]) <= 0:
        raise _fail("task.size", "every entry > 0", list(values["size"]))
    extra_fields = {}
    if shape == "cylinder":
        axis = raw.get("axis", mech.pose_names[-1])
        if not isinstance(axis, str) or axis not in mech.pose_names:
            raise _fail("task.axis", f"one of {', '.join(mech.pose_names)}", axis)
        extra_fields["axis"] = mech.pose_names.index(axis)
    name = _name(raw.get("name", "task"), "task.name")
    return cls(name, f"the designer's {shape} at {list(values['centre'])}, size {list(values['size'])}",
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
    raise _fail(field, f"a global index {mech.name} offers or a local index's _min or _max ({', '.join(offered)})",
                name)


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
    points = _list(raw["waypoints"], "trajectory.waypoints", "a list of poses")
    if not (len(points) >= 2 and all(_numbers(p, mech.n_out) for p in points)):
        raise _fail("trajectory.waypoints", f"two or more poses, each {mech.n_out} finite numbers "
                                            f"({', '.join(mech.pose_names)})", points)
    segments = list(itertools.pairwise(points))
    if "durations" in raw and not _numbers(raw["durations"], len(segments)):
        raise _fail("trajectory.durations", f"{len(segments)} finite durations in s, one per segment between the "
                                            "waypoints", raw["durations"])
    with _field("trajectory"):
        if "v_max" in raw:
            v_max, a_max = (_number(raw[k], f"trajectory.{k}") for k in ("v_max", "a_max"))
            moves = [Trajectory.trapezoidal(a, b, v_max, a_max) for a, b in segments]
        else:
            moves = [Trajectory.point_to_point(a, b, t) for (a, b), t in zip(segments, raw["durations"], strict=True)]
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


PHYSICAL = ("joint", "joint_range", "effort", "deflection", "pose_error")


def _joint_extremes(mech: Any, name: str, field: str) -> tuple[GlobalIndex, GlobalIndex]:
    """The least and the largest value of an actuated joint over the task (:func:`joint_extremes`)."""
    if not isinstance(name, str) or name not in mech.actuator_names:
        raise _fail(field, f"an actuated joint of {mech.name} ({', '.join(mech.actuator_names)})", name)
    return joint_extremes(mech, name)


def _effort(mech: Any, wrench: Any, field: str) -> LocalIndex:
    """The largest actuator effort |tau_i| that holds the wrench w at the end effector, tau = J_f^T w (virtual
    work: tau . q_dot = w . x_dot with x_dot = J_f q_dot); w in the pose's dual units (N for a length, N m for
    an angle)."""
    if not _numbers(wrench, mech.n_out):
        raise _fail(field, f"a wrench of {mech.n_out} finite numbers, dual to the pose ({', '.join(mech.pose_names)})",
                    wrench)
    w = ca.DM(wrench)
    return LocalIndex(
        "effort", f"largest actuator effort |J_f^T w| holding the wrench w = {list(wrench)} at the end effector",
        effort_unit(mech), 0.0, np.inf, np.inf, lambda J_f: ca.mmax(ca.fabs(J_f.T @ w)), "first_order",
        ("J_f",), epigraph_upper=lambda J_f, t: ca.vertcat(t - J_f.T @ w, t + J_f.T @ w), dimension=None, raw=True,
    )


def _deflection(mech: Any, wrench: Any, field: str) -> LocalIndex:
    """The platform's displacement under the wrench w, |K^-1 w| over its translation [m] (K the Cartesian
    stiffness, :mod:`pkm.spec.stiffness`; w the force [N] and, where the platform turns, the moment [N m] about
    the pose's origin)."""
    if "stiffness" not in mech.functions:
        raise _fail(field, f"a mechanism with elastic elements (legs' elastic tables); {mech.name} has none",
                    wrench)
    if not _numbers(wrench, mech.n_out):
        raise _fail(field, f"a wrench of {mech.n_out} finite numbers, dual to the pose ({', '.join(mech.pose_names)})",
                    wrench)
    w = ca.DM(wrench)
    moved = [k for k, unit in enumerate(mech.pose_units) if unit == "m"]

    def displacement(K: ca.SX) -> ca.SX:
        return ca.solve(K, w)[moved]

    return LocalIndex(
        "deflection", f"the platform's displacement |K^-1 w| over its translation under the wrench w = {list(wrench)}",
        "m", 0.0, np.inf, np.inf, lambda K: ca.norm_2(displacement(K)), "stiffness", ("K",),
        epigraph_upper=lambda K, t: t - ca.norm_2(displacement(K)), dimension=None, raw=True,
    )


def _pose_error(mech: Any, value: Any, field: str) -> LocalIndex:
    """The linearised worst-case pose error under the tolerances, the largest over the translational coordinates
    of sum_k |E_ik| t_k [m] (E = dx/dp, the error model's pose error Jacobian;
    :meth:`pkm.accuracy.ErrorModel.index`)."""
    if not (isinstance(value, Mapping) and set(value) == {"tolerances"}):
        raise _fail(field, "a table {tolerances = a number [m], every geometric error's, or a table by error "
                           "parameter}", value)
    try:
        return error_model(mech).index(value["tolerances"])
    except PkmError as exc:
        raise _fail(f"{field}.tolerances", str(exc).split(" violate: ", 1)[-1], value["tolerances"]) from None


def _physical(mech: Any, what: Mapping[str, Any], bounds: tuple[float, float], field: str, *, region: Any,
              quantities: dict[str, Quantity]) -> list[Constraint]:
    """{joint: an actuated joint} within [lower, upper] over the task, {joint_range: one} moving at most
    ``upper`` over it (its largest minus its least value), {effort: a wrench} needing actuator efforts of
    at most ``upper`` at every pose of it, {deflection: a wrench} moving the platform by at most ``upper`` at
    every pose of it (:func:`_deflection`), or {pose_error: {tolerances}} whose worst-case pose error is at most
    ``upper`` at every pose of it (:func:`_pose_error`); each a region extreme, refined between the nodes."""
    if len(what) != 1 or next(iter(what)) not in PHYSICAL:
        raise _fail(field, f"a table with one of {', '.join(PHYSICAL)}", what)
    kind, value = next(iter(what.items()))
    lower, upper = bounds
    if kind in ("effort", "deflection", "pose_error"):
        local = {"effort": _effort, "deflection": _deflection, "pose_error": _pose_error}[kind](
            mech, value, f"{field}.{kind}")
        name = next(n for n in (f"{kind}_{k}" if k else kind for k in range(len(quantities) + 1))
                    if n not in quantities)
        quantities[name] = Quantity(GlobalIndex(name, local, f"the region maximum of {local.doc}", "max", "min"),
                                    region)
        held = "under its tolerances" if kind == "pose_error" else f"holding {list(value)}"
        return [Constraint(f"{name} {held} <= {upper:g} {local.unit}", lambda t: t[name], -math.inf, upper)]
    low, high = _joint_extremes(mech, value, f"{field}.{kind}")
    least, largest, local = low.name, high.name, low.local
    quantities[least], quantities[largest] = Quantity(low, region), Quantity(high, region)
    if kind == "joint_range":
        return [Constraint(f"range of {value} <= {upper:g} {local.unit}", lambda t: t[largest] - t[least],
                           -math.inf, upper)]
    return [Constraint(f"{least} >= {lower:g} {local.unit}", lambda t: t[least], lower, math.inf),
            Constraint(f"{largest} <= {upper:g} {local.unit}", lambda t: t[largest], -math.inf, upper)]


def _parameter_expression(mech: Any, text: Any, field: str) -> Callable[[Mapping[str, Any]], Any]:
    """An expression of the design parameters (a frame size, a sum of lengths) as a function of their values
    by name: :mod:`pkm.expressions`' tree of it, evaluated with numpy's functions on numbers and arrays and
    CasADi's on symbols."""
    names = mech.parameter_names()
    condition = f"arithmetic of the design parameters ({', '.join(names)}), pi and {', '.join(expressions.FUNCTIONS)}"
    try:
        tree = expressions.parse(_string(text, field, f"{condition}, as text"))
    except expressions.ExpressionError as exc:
        raise _fail(field, f"{condition}: {exc}", text) from None
    unknown = expressions.unknown_names(tree, names)
    if unknown:
        raise _fail(field, f"{condition}; {unknown[0]} is none of them", text)
    return expressions.function(tree)


def _objective(raw: Any, quantity: Callable[[str, str], Quantity], quantities: dict[str, Quantity]) -> Objective:
    """A global index in its sense, or a weighted combination {index: weight}: maximise the sum of each
    weight times its index (negated where the index is better smaller); ``quantity(name, field)`` the quantity
    a name stands for."""
    if isinstance(raw, str):
        quantities[raw] = quantity(raw, "objective")
        return Objective.of(raw, quantities[raw])
    if not _table(raw, "objective", "a global index or a table {index = weight}"):
        raise _fail("objective", "a global index or a non-empty table {index = weight}", raw)
    signs = {}
    for name, weight in raw.items():
        number = _number(weight, f"objective.{name}")
        quantities[name] = quantity(name, f"objective.{name}")
        signs[name] = number * (1.0 if quantities[name].index.sense == "max" else -1.0)
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


BASELINES = ("grid", "monte_carlo")


def _baseline(problem: Problem, baseline: Any) -> Baseline:
    """The baseline ``(kind, size)``: a grid of ``size`` nodes per variable or ``size`` Monte Carlo samples,
    at most MAX_BASELINE_POINTS designs either way."""
    if len(_list(baseline, "baseline", "a pair (kind, size)")) != 2:
        raise _fail("baseline", "a pair (kind, size)", baseline)
    kind, size = baseline
    if not isinstance(kind, str) or kind not in BASELINES:
        raise _fail("baseline.kind", f"one of {', '.join(BASELINES)}", kind)
    n = len(problem.variables)
    grid = kind == "grid"
    if (isinstance(size, bool) or not isinstance(size, numbers.Integral) or size < 2
            or (size**n if grid else size) > MAX_BASELINE_POINTS):
        nodes = f"size^{n} grid nodes" if grid else "samples"
        raise _fail("baseline.size", f"an integer >= 2 with {nodes} <= {MAX_BASELINE_POINTS}", size)
    return problem.grid_baseline(int(size)) if grid else monte_carlo_baseline(problem, int(size))


MAX_RESOLUTION = 64  # a problem's quadrature resolution at most
MECHANISM = "a mechanism's name or a description file"


def _task(mech: Any, task: str | Any) -> Any:
    """The region of a task: a region name of the mechanism, a table placing one (:func:`task_region`) or a
    region."""
    if isinstance(task, str):
        with _field("task"):
            return mech.region(task)
    if isinstance(task, Mapping):
        return task_region(mech, task)
    if isinstance(getattr(task, "name", None), str):
        return task
    raise _fail("task", "a region name of the mechanism, a table {shape, centre, size, axis}, {poses} or {file}, or "
                        "a region", task)


def _held(mech: Any, fixed: Mapping[str, float] | None, chosen: Sequence[Any]) -> dict[str, float]:
    """The parameters held at given values, checked as a design's, none of them a variable."""
    given = {} if fixed is None else dict(_table(fixed, "fixed", "a table {parameter = value}"))
    for held_name, value in given.items():
        _number(value, f"fixed.{held_name}")
    with _field("fixed"):
        checked = dict(mech.design(given, partial=True)) if given else {}
    held = {n: checked[n] for n in given}
    overlap = set(held) & {v.name for v in chosen}
    if overlap:
        raise _fail("fixed", f"no parameter that is also a variable; {sorted(overlap)[0]} is both")
    return held


def _rules(mech: Any, derived: Mapping[str, str] | None, taken: Sequence[str]) -> dict[str, Any]:
    """The derived parameters' rules, in order, each an expression of the design parameters setting one that is
    neither a variable nor fixed (``taken``)."""
    rules = {}
    for target, text in ({} if derived is None else _table(derived, "derived", "a table {parameter = expression}")
                         ).items():
        if target not in mech.parameter_names() or target in taken:
            raise _fail(f"derived.{target}", "a design parameter that is neither a variable nor fixed")
        rules[target] = _parameter_expression(mech, text, f"derived.{target}")
    return rules


def _constraints(mech: Any, constraints: Sequence[Any], quantity: Any, quantities: dict[str, Quantity], *,
                 region: Any, task_name: str) -> list[Constraint]:
    """The stated constraints (what, lower, upper), the quantities they read added to ``quantities``."""
    stated = []
    for k, item in enumerate(_list(constraints, "constraints", "a list of (index or expression, lower, upper)")):
        field = f"constraints[{k}]"
        if not (isinstance(item, Sequence) and len(item) == 3):
            raise _fail(field, "a triple (index or expression, lower, upper)", item)
        what, lower, upper = item
        if not isinstance(what, str | Mapping):
            raise _fail(field, "an index's name, an expression of the design parameters or a table {joint}, "
                               "{joint_range}, {effort}, {deflection} or {pose_error}", what)
        lower, upper = _bound(lower, f"{field}.lower", -math.inf), _bound(upper, f"{field}.upper", math.inf)
        if not lower <= upper:
            raise _fail(field, f"lower <= upper; got {lower:g}, {upper:g}")
        if isinstance(what, Mapping):
            stated += _physical(mech, what, (lower, upper), field, region=region, quantities=quantities)
        elif what.isidentifier() and what not in mech.parameter_names():
            quantities.setdefault(what, quantity(what, field))
            stated.append(Constraint(f"{lower:g} <= {what} over {task_name} <= {upper:g}",
                                     lambda t, what=what: t[what], lower, upper))
        else:
            rule = _parameter_expression(mech, what, field)
            stated.append(Constraint(f"{lower:g} <= {what} <= {upper:g}",
                                     lambda t, rule=rule: rule({n: t[n] for n in mech.parameter_names()}),
                                     lower, upper))
    return stated


def _holding(problem: Problem, margin: float, region: Any) -> Problem:
    """The problem holding its task ``margin`` from singularity, unless a constraint of its own on
    singularity_margin_min states the margin."""
    if MARGIN in problem.quantities:
        return replace(problem, margin=Margin(None, f"its constraint on {MARGIN}", region))
    return problem.holding(margin, "the default margin" if margin == SINGULARITY_MARGIN else "as asked", region)


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
    singularity_margin: float = SINGULARITY_MARGIN,
) -> Problem:
    """A synthesis over the task region ``task`` (a region name of the mechanism, a region, a table placing one in SI,
    :func:`task_region`, or given poses, :func:`task_poses`) of ``mechanism`` (a name, a description file or a
    mechanism): the ``variables`` between their bounds, the parameters in ``fixed`` at their values and the others
    at their defaults; ``objective`` a global index over the task in its sense, or a weighted combination {index:
    weight} (maximised, each index negated where smaller is better); ``constraints`` (what, lower, upper): a global
    index over the task, a local index's least or largest value over it (``inverse_condition_f_min``: a singularity
    margin), an expression of the design parameters (a frame size, ``2 * (d1 + d2)``), or a table: ``{"joint":
    name}`` (an actuated joint within [lower, upper] over the task), ``{"joint_range": name}`` (its largest minus
    its least value at most upper), ``{"effort": wrench}`` (the actuator efforts that hold a payload's wrench at
    every pose of the task at most upper), ``{"deflection": wrench}`` (the platform's displacement under it) or
    ``{"pose_error": {"tolerances": t}}`` (the worst-case pose error under the tolerances, :mod:`pkm.accuracy`); by
    default the task inside the workspace (the least workspace margin over it at least 0); ``derived`` parameters
    set by expressions of the others, in order (a stroke that follows a link length); the baseline ``("grid", points
    per axis)`` or ``("monte_carlo", samples)``, at most MAX_BASELINE_POINTS designs. A bound is a finite number of
    magnitude at most MAX_BOUND, or -inf (a lower one), inf (an upper one) for none; ``name`` letters, digits and
    single underscores or dots. Every problem holds its task ``singularity_margin`` (in [0, 1), SINGULARITY_MARGIN
    by default) from singularity: the constraint ``singularity_margin_min >= singularity_margin`` over the task,
    which a constraint on ``singularity_margin_min`` given in ``constraints`` replaces and 0 leaves out. IPOPT takes
    a limited-memory Hessian where a quantity is a region minimum or maximum (its epigraph holds every node, and the
    exact Hessian of those rows costs more than it saves). With ``trajectory`` (a
    :class:`pkm.regions.TrajectoryRegion`, a move, or {waypoints, v_max, a_max}: trapezoidal moves between the
    waypoints), the objective and constraints may name the trajectory quantities (``effort_peak``, ``energy``, ...,
    :mod:`pkm.dynamics.quantities`; ``encoder`` the resolutions of ``positioning_error``), taken along it."""
    if isinstance(mechanism, str):
        with _field("mechanism"):
            mechanism = resolve_name(_file_name(mechanism, "mechanism", MECHANISM))
    mech = mechanism
    region = _task(mech, task)
    task_name = task if isinstance(task, str) else region.name
    chosen = _variables(mech, variables)
    if (isinstance(resolution, bool) or not isinstance(resolution, numbers.Integral)
            or not 2 <= resolution <= MAX_RESOLUTION):
        raise _fail("resolution", f"an integer from 2 to {MAX_RESOLUTION}", resolution)
    held = _held(mech, fixed, chosen)
    order = [v.name for v in chosen]
    with _field("mode"):
        mode = mech.working_mode(_string(mode, "mode", "a working mode's name") if mode is not None else None).name
    rules = _rules(mech, derived, (*order, *held))

    def design(values: Sequence[Any]) -> Any:
        given = {**held, **dict(zip(order, values, strict=True))}
        full = completed(mech.parameters, given)
        given |= {target: rule(full) for target, rule in rules.items()}
        return stack_design(list(completed(mech.parameters, given).values()))

    along = _trajectory(mech, trajectory)
    if encoder is not None and not (_numbers(encoder, mech.n_act) and min(encoder) > 0):
        raise _fail("encoder", f"{mech.n_act} finite resolutions > 0, one per actuator "
                               f"({', '.join(mech.actuator_names)}), in SI", encoder)
    indices = mech.trajectory_quantities if encoder is None else trajectory_indices(mech, encoder=encoder)

    def quantity(name: str, field: str) -> Quantity:
        return _quantity(mech, name, field, region=region, along=along, indices=indices)

    quantities: dict[str, Quantity] = {}
    goal = _objective(objective, quantity, quantities)
    stated = _constraints(mech, constraints, quantity, quantities, region=region, task_name=task_name)
    margin = _number(singularity_margin, "singularity_margin")
    if not 0 <= margin < 1:
        raise _fail("singularity_margin", "a number in [0, 1) (0: no margin)", singularity_margin)
    measured = [n for n, q in quantities.items() if q.index.reduce == "measure"]
    if measured and isinstance(region, Poses):
        raise _fail("task", f"a region with a measure for {measured[0]}; given poses have none")
    sense = "maximise" if goal.sense == "max" else "minimise"
    named = objective if isinstance(objective, str) else "weighted"
    problem = Problem(
        name=f"{mech.name}.{named}_{task_name}" if name is None else _name(name, "name", dotted=True),
        doc=(f"{sense} {goal.doc if named == 'weighted' else named} over the region {task_name} in "
             f"{', '.join(order)}, working mode {mode}") if doc is None else _string(doc, "doc", "a text"),
        mechanism=mech,
        variables=chosen,
        design=design,
        quantities=quantities,
        objective=goal,
        constraints=tuple(stated),
        mode=mode,
        resolution=int(resolution),
        hessian="limited-memory" if any(q.index.reduce in ("min", "max") for q in quantities.values()) else "exact",
        notes={"task": task_name, "fixed": held},
    )
    problem = _holding(problem, margin, region)
    return replace(problem, baselines=(_baseline(problem, baseline),))


PROBLEM_FIELDS = {"name", "doc", "mechanism", "task", "variables", "fixed", "derived", "objective", "constraints",
                  "singularity_margin", "mode", "baseline", "resolution", "trajectory", "encoder"}
CONSTRAINT_KINDS = ("index", "expression", *PHYSICAL)


def task_of(path: str | os.PathLike, mech: Any) -> Any:
    """The task region of a task file (:func:`read_problem`) for ``mech``: the region its objective is taken
    over, or :class:`ProblemError` where the file's mechanism is another."""
    problem = read_problem(path)
    if problem.mechanism.name != mech.name:
        raise ProblemError(f"task file {path}: its mechanism is the {problem.mechanism.name}, not the {mech.name}")
    quantity = problem.objective.quantity or next(iter(problem.quantities))
    return problem.quantities[quantity].region


def read_problem(path: str | os.PathLike) -> Problem:
    """:func:`design_problem` from a TOML file: ``mechanism`` (a name or a description file, relative to the
    file), ``task`` (a region name or a table {shape, centre, size, axis}), ``variables`` {name = [lower,
    upper]}, optionally ``fixed`` {name = value}, ``objective`` (a global index), ``constraints`` (a list of
    {index, lower, upper}, a bound left out for none), ``mode``, ``baseline`` {kind = "grid" or "monte_carlo",
    size}, ``resolution``, ``trajectory`` {waypoints, v_max, a_max} and ``encoder`` (:func:`design_problem`),
    ``name`` and ``doc``. Every field is checked as :func:`design_problem` checks it; the file must be UTF-8
    TOML (:func:`pkm.io.read_toml`)."""
    path = Path(path)
    raw = io.read_toml(path, ProblemError, "problem file")
    extra = set(raw) - PROBLEM_FIELDS
    if extra:
        raise _fail(sorted(extra)[0], f"a known field ({', '.join(sorted(PROBLEM_FIELDS))})")
    for field in ("mechanism", "task", "variables"):
        if field not in raw:
            raise _fail(field, "given")
    mechanism = _file_name(raw["mechanism"], "mechanism", MECHANISM)
    if mechanism.endswith(".toml"):
        mechanism = str((path.parent / mechanism).resolve())
    constraints = _list(raw.get("constraints", [{"index": "workspace_margin_min", "lower": 0.0}]), "constraints",
                        "a list of tables {index, lower, upper}")
    triples = []
    for k, c in enumerate(constraints):
        table = _table(c, f"constraints[{k}]", f"a table {{one of {', '.join(CONSTRAINT_KINDS)}; lower, upper}}")
        kinds = [kind for kind in CONSTRAINT_KINDS if kind in table]
        if len(kinds) != 1 or set(table) - {*CONSTRAINT_KINDS, "lower", "upper"}:
            raise _fail(f"constraints[{k}]", f"a table {{one of {', '.join(CONSTRAINT_KINDS)}; lower, upper}}",
                        dict(table))
        (kind,) = kinds
        what = table[kind] if kind in ("index", "expression") else {kind: table[kind]}
        if kind in ("index", "expression") and not isinstance(what, str):
            raise _fail(f"constraints[{k}].{kind}", "an index's name" if kind == "index" else "an expression, as text",
                        what)
        triples.append((what, table.get("lower", -math.inf), table.get("upper", math.inf)))
    task = raw["task"]
    if isinstance(task, Mapping) and "file" in task:
        task = {**task, "file": str(path.parent / _file_name(task["file"], "task.file", "a file name"))}
    elif not isinstance(task, str | Mapping):
        raise _fail("task", "a region name of the mechanism or a table {shape, centre, size, axis}, {poses} or "
                            "{file}", task)
    baseline = _table(raw.get("baseline", {"kind": "grid", "size": 21}), "baseline", "a table {kind, size}")
    if set(baseline) - {"kind", "size"}:
        raise _fail("baseline", "a table {kind, size}", dict(baseline))
    return design_problem(
        mechanism, task=task, variables=raw["variables"], fixed=raw.get("fixed"), derived=raw.get("derived"),
        objective=raw.get("objective", "gci"), constraints=triples, mode=raw.get("mode"),
        name=raw.get("name"), doc=raw.get("doc"), baseline=(baseline.get("kind", "grid"), baseline.get("size", 21)),
        resolution=raw.get("resolution", 8), trajectory=raw.get("trajectory"), encoder=raw.get("encoder"),
        singularity_margin=raw.get("singularity_margin", SINGULARITY_MARGIN),
    )
