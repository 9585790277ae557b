"""The one catalogue of the compiled path: the kernels a mechanism warms up (``pkm build``), which the
contract suite and the integrand tests compare with the interpreter.

Any function pkm evaluates over a batch is compiled at first use (:mod:`pkm.compiled`); the catalogue lists
the ones a mechanism's users meet, built the way the runtime builds them, so that they can be compiled
ahead of time, in parallel: every
generated function of every mechanism with dense ports, the fused pipeline of each of its local indices
alone (its values only, as ``Mechanism.local_index`` evaluates them), of 1/kappa_f with its reach and of
each index with 1/kappa_f, without the joints (:func:`pkm.regions.pipeline.index_pipeline`, as the sampled
regions and atlases evaluate them; also the least margin of each region's guard, as
a sampled check evaluates it), the one of its first order and the outputs the Jacobians return
(:func:`pkm.regions.pipeline.first_order_outputs`), the inverse kinematics and the closed-form forward
kinematics with their reach check (:func:`pkm.kinematics.with_reach`), its fused
inertia matrices and inverse dynamics (:func:`pkm.dynamics.rigid.inertia_pipeline`,
:func:`pkm.dynamics.rigid.inverse_dynamics_pipeline`),
by :func:`pkm.regions.pipeline.pipeline`, the core's one builder; and the point
integrands of its global indices over its parametrised regions and over the regions of its synthesis
problems (:mod:`pkm.regions.integrand`): summed over blocks of nodes with their gradient for every pair,
with the Hessian for the problems that IPOPT solves with exact Hessians, for a region extreme the node
values and the epigraph margins with their gradient, and the margins of each region's guard.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import casadi as ca

from pkm import compiled, registry
from pkm.compiled.emit import emittable
from pkm.dynamics.rigid import SPACES, inertia_pipeline, inverse_dynamics_pipeline
from pkm.kinematics import with_reach
from pkm.regions.integrand import SUMMED, rows_function, sum_function
from pkm.regions.pipeline import first_order_outputs, index_pipeline, pipeline
from pkm.regions.quadrature import guard_index
from pkm.regions.sampled import CONDITION as SAMPLED_CONDITION
from pkm.regions.trajectory import TrajectoryRegion


@dataclass(frozen=True)
class Kernel:
    """A kernel of the catalogue: a label, the function, whether it sums over the batch, and for a point
    integrand the region piece whose reference nodes it takes and the reduction whose rule places them."""

    label: str
    function: ca.Function
    summed: bool = False
    piece: Any = None
    reduce: str = ""


@lru_cache(maxsize=16)
def kernels(mech: Any) -> tuple[Kernel, ...]:
    """Every kernel of a mechanism (module docstring), in a fixed order, each once; built once per mechanism
    (kept for the last 16)."""
    out = [Kernel(name, mech.functions[name]) for name in sorted(mech.functions)
           if emittable(mech.functions[name])]
    fused = {index: index_pipeline(mech, (mech.local_spec(index),), reach=False) for index in mech.local_indices()}
    condition = mech.local_spec(SAMPLED_CONDITION.name)
    fused.update({f"{index}_{condition.name}": index_pipeline(mech, (mech.local_spec(index), condition))
                  for index in mech.local_indices() if index != condition.name})
    fused[f"{condition.name} with its reach"] = index_pipeline(mech, (condition,))
    for region in dict.fromkeys(region for _, region, _ in _pairs(mech)):
        guard = guard_index(region)
        if guard is not None:
            fused[f"{guard.name}_{condition.name}"] = index_pipeline(mech, (guard, condition))
    fused["first_order"] = pipeline(mech, (), first_order=True, assembled=True)
    for names in (("J",), ("J_f",), ("psi",), ("det_type1", "det_type2")):
        fused[f"first order {' '.join(names)}"] = first_order_outputs(mech, names)
    ik = mech.functions["inverse_kinematics"]
    fused["inverse kinematics"] = with_reach(ik, ("q",))
    fused["inverse kinematics, actuated joints"] = with_reach(ik, ("q",), mech.n_act)
    closed = getattr(mech.forward, "function", None)
    if closed in mech.functions:
        fused["forward kinematics"] = with_reach(mech.functions[closed], ("x", "q"))
        fused["forward kinematics, pose"] = with_reach(mech.functions[closed], ("x",))
    if {"inverse_dynamics", "second_order"} & set(mech.functions):
        fused["inverse_dynamics"] = inverse_dynamics_pipeline(mech)
    if "inertia" in mech.functions:
        fused |= {f"inertia {output}": inertia_pipeline(mech, output) for output in SPACES.values()
                  if output in mech.functions["inertia"].name_out()}
    out += [Kernel(f"pipeline {label}", fn) for label, fn in fused.items() if emittable(fn)]
    out += integrands(mech)
    seen: set[tuple[str, bool]] = set()
    unique = []
    for kernel in out:
        identity = (kernel.function.serialize(), kernel.summed)
        if identity not in seen:
            seen.add(identity)
            unique.append(kernel)
    return tuple(unique)


def _pairs(mech: Any) -> list[tuple[Any, Any, bool]]:
    """(global index, region, whether IPOPT takes its exact Hessian) of every global index over every
    region of the mechanism but its trajectories (a move is where its trajectory quantities are taken, compiled
    at their first use) and of every quantity of its synthesis problems, in a fixed order."""
    pairs = [(mech.global_spec(index), region, False) for region in mech.regions.values()
             if not isinstance(region, TrajectoryRegion) for index in mech.global_indices()]
    for problem in (registry.problem(p) for p in sorted(registry.problems())):
        if problem.mechanism.name == mech.name:
            pairs += _problem_pairs(problem)
    return pairs


def _problem_pairs(problem: Any) -> list[tuple[Any, Any, bool]]:
    return [(q.index, q.region, problem.hessian == "exact") for q in problem.quantities.values()]


@lru_cache(maxsize=16)
def integrands(mech: Any) -> tuple[Kernel, ...]:
    """The point integrands of a mechanism (module docstring), in a fixed order; built once per mechanism (kept
    for the last 16)."""
    return tuple(_integrands(mech, _pairs(mech)))


def problem_integrands(problem: Any) -> list[Kernel]:
    """The point integrands a synthesis problem evaluates (its quantities over their regions)."""
    return _integrands(problem.mechanism, _problem_pairs(problem))


def _integrands(mech: Any, pairs: list[tuple[Any, Any, bool]]) -> list[Kernel]:
    out = []
    for region in dict.fromkeys(region for _, region, _ in pairs):
        if region.guard is not None:
            out += [_integrand(rows_function(mech, guard_index(region), piece, None, order)[0], False, piece, "min")
                    for piece in region.pieces() for order in range(2)]
    for spec, region, hessian in pairs:
        for piece in region.pieces():
            if spec.reduce in SUMMED:
                out += [_integrand(sum_function(mech, spec.local, piece, spec.reduce, order)[0], True, piece,
                                   spec.reduce) for order in range(3 if hessian else 2)]
            else:
                out.append(_integrand(rows_function(mech, spec.local, piece, None, 0)[0], False, piece, spec.reduce))
                out += [_integrand(rows_function(mech, spec.local, piece, spec.reduce, order)[0], False, piece,
                                   spec.reduce) for order in range(2)]
    return out


def _integrand(fn: ca.Function, summed: bool, piece: Any, reduce: str) -> Kernel:
    return Kernel(f"integrand {fn.name()}", fn, summed, piece, reduce)


def warm(mechanisms: Iterable[Any], *, progress: Callable[[int, int], None] | None = None) -> dict[str, int]:
    """Compile the catalogue's kernels of ``mechanisms`` ahead of time, in parallel
    (:func:`pkm.compiled.build`): how many were in the cache, compiled, and left on the interpreter."""
    return compiled.build([(k.function, k.summed) for mech in mechanisms for k in kernels(mech)],
                          progress=progress)


