"""The one fused pipeline: pose -> inverse kinematics -> first order (and inertia) -> local indices.

:func:`pipeline` composes a mechanism's generated ``inverse_kinematics``, the generated functions the
local indices read (``first_order``, ``inertia``) and the indices' formulas into one ``casadi.SX``
graph ``(x, mode, design) -> (q, reach, values...)``. Where the mechanism has ``first_order_from_pose``
(the inverse kinematics and the first order in one function, the first order without trigonometric
calls), it takes the joints and the first order from it instead, and likewise any other source ``f``
from ``f_from_pose(x, mode, design)`` where the mechanism has it (``inertia_from_pose``: the inertia
matrices without the joint angles). Everything that evaluates a local
index uses it: local indices at poses, the sampled regions and atlases (numerically, through
:func:`evaluate_at` and :func:`index_pipeline`, which leaves out the joints: no angle is computed
there when the first order comes from the pose), and the quadratures of the parametrised regions
(mapped over the nodes, symbolically in the design).

Poses that mix metres and radians are normalised by a characteristic length L of the design before any
index is taken: each angular coordinate is replaced by the arc length L theta (Gosselin 1990; Angeles
2007 section 5.7), so that the matrices become

    J_n = S_q J S_x^-1,  J_f_n = S_x J_f S_q^-1,  M_w_n = S_x^-1 M_w S_x^-1,
    M_t_n = S_q^-1 M_t S_q^-1,  M_d_n = S_q^-1 M_d S_x^-1,

with S_x = diag(1 for a length, L for an angle) over the pose and S_q likewise over the actuators.
A mechanism whose pose and actuators each have one unit is left as it is (its indices are invariant
to a uniform scaling).

A local index of the source ``"motion"`` reads the pose's motion as well: the pipeline then takes a fourth
input, ``motion`` = (x_dot, x_ddot) at the pose (a trajectory's pieces give it, exact for the velocity
profile, :mod:`pkm.regions.trajectory`), and offers the arguments ``x_dot``, ``x_ddot``, ``q_dot`` = J x_dot
and ``tau``, the actuator efforts of the mechanism's rigid inverse dynamics
(:func:`pkm.dynamics.rigid.inverse_dynamics_pipeline`), each in SI. Such a graph is built with common
subexpressions merged, as the inverse dynamics repeats the kinematics.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Protocol

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate_finite
from pkm.errors import PkmError
from pkm.indices import LocalIndex, local_function
from pkm.kinematics import ASSEMBLED, FunctionTable, closed, from_pose, limited_reach, nan_unless

ANGLE = "rad"
MOTION = "motion"  # the source of the local indices that read the pose's velocity and acceleration
MOTION_ARGUMENTS = ("x_dot", "x_ddot", "q_dot", "tau")
FROM_POSE = from_pose("first_order")
TRANSFORMS: dict[str, tuple[str, str]] = {
    "J": ("q", "x^-1"),
    "J_f": ("x", "q^-1"),
    "M_w": ("x^-1", "x^-1"),
    "M_t": ("q^-1", "q^-1"),
    "M_d": ("q^-1", "x^-1"),
}


class PipelineModel(Protocol):
    """What the fused pipeline, the regions and their indices read of a mechanism (a :class:`pkm.Mechanism`):
    its generated functions and coordinates, and where its pose mixes metres and radians the characteristic
    length, a function of the design by parameter name (CasADi). A mechanism with stated limits also names
    their function in ``limits`` (:func:`pkm.kinematics.within_limits`)."""

    name: str
    n_act: int
    n_out: int
    functions: FunctionTable
    pose_units: tuple[str, ...]
    actuator_units: tuple[str, ...]

    characteristic_length: Callable[[Mapping[str, ca.SX]], ca.SX] | None

    def parameter_names(self) -> tuple[str, ...]: ...


def mixed(units: Sequence[str]) -> bool:
    """Whether coordinates of these units mix angles with other units."""
    return ANGLE in units and len(set(units)) > 1


def _scales(mech: PipelineModel, design: ca.SX) -> dict[str, ca.SX] | None:
    """S_x and S_q as column vectors, or None when no normalisation is needed."""
    if not (mixed(mech.pose_units) or mixed(mech.actuator_units)):
        return None
    length_of = type(mech).characteristic_length
    if length_of is None:
        raise PkmError(
            f"the {mech.name} mixes {', '.join(sorted(set(mech.pose_units) | set(mech.actuator_units)))} "
            "in its coordinates: its indices need a characteristic_length"
        )
    names = mech.parameter_names()
    length = length_of({n: design[k] for k, n in enumerate(names)})

    def scale(units: Sequence[str]) -> ca.SX:
        return ca.vertcat(*[length if mixed(units) and u == ANGLE else ca.SX(1) for u in units])

    return {"x": scale(mech.pose_units), "q": scale(mech.actuator_units)}


def _side(scales: dict[str, ca.SX], key: str) -> ca.SX:
    s = scales[key.removesuffix("^-1")]
    return ca.diag(1 / s if key.endswith("^-1") else s)


def normalise(name: str, matrix: ca.SX, scales: dict[str, ca.SX] | None) -> ca.SX:
    """A matrix of the port convention in normalised coordinates (module docstring)."""
    if scales is None or name not in TRANSFORMS:
        return matrix
    left, right = TRANSFORMS[name]
    return _side(scales, left) @ matrix @ _side(scales, right)


def _outputs(fn: ca.Function, args: list[ca.SX]) -> dict[str, ca.SX]:
    """The outputs of ``fn`` called on symbolic arguments, by name."""
    return dict(zip(fn.name_out(), fn.call(args), strict=True))


def reads_motion(locals_: Sequence[LocalIndex]) -> bool:
    """Whether any of the local indices reads the pose's motion (the source ``"motion"``)."""
    return any(spec.source == MOTION for spec in locals_)


def _motion(mech: PipelineModel, arguments: set[str], *, x: ca.SX, mode: ca.SX, design: ca.SX, motion: ca.SX,
            first: dict[str, ca.SX]) -> dict[str, ca.SX]:
    """The arguments of the source ``"motion"`` that the local indices read, from the pose, the motion
    (x_dot, x_ddot) and the first order's J."""
    n = mech.n_out
    x_dot, x_ddot = motion[:n], motion[n:]
    out = {"x_dot": x_dot, "x_ddot": x_ddot}
    if "q_dot" in arguments:
        out["q_dot"] = first["J"] @ x_dot
    if "tau" in arguments:
        from pkm.dynamics.rigid import inverse_dynamics_pipeline

        fns = mech.functions
        if not any(name in fns for name in ("inverse_dynamics", "inverse_dynamics_from_pose", "elastic_dynamics")):
            raise PkmError(f"the {mech.name} has no dynamic model: its actuator efforts along a motion are undefined")
        out["tau"] = inverse_dynamics_pipeline(mech)(x, x_dot, x_ddot, mode, design)[1]
    return out


@lru_cache(maxsize=256)
def pipeline(
    mech: PipelineModel, locals_: tuple[LocalIndex, ...], matrices: bool = False, first_order: bool = False,
    assembled: bool = False, *, smooth: bool = False,
) -> ca.Function:
    """``(x, mode, design) -> (q, reach, valid, *values)``: one fused SX graph for the local indices
    ``locals_``; ``valid`` is 1 where the pose is reached and 0 elsewhere, where the values are NaN. Where an
    index reads the motion (:func:`reads_motion`), ``(x, mode, design, motion)`` with motion (x_dot, x_ddot).
    With ``matrices`` the normalised argument matrices of the first index follow, with ``first_order``
    every output of the generated ``first_order`` (as generated, not normalised). A pose is reached
    where the mechanism assembles within its stated limits (:func:`pkm.kinematics.within_limits`); with
    ``assembled``, and for indices that measure those limits, where it assembles; where every index is
    signed (a margin of the reach and the limits, defined beyond them), where each value is finite, the
    values unmasked. With
    ``smooth``, an index's smooth stand-in replaces its formula where it has one."""
    fns = mech.functions
    measures_limits = bool(locals_) and all(spec.source == getattr(mech, "limits", None) for spec in locals_)
    signed = bool(locals_) and all(spec.signed for spec in locals_)
    unlimited = (assembled or measures_limits) and ASSEMBLED in fns
    ik = fns[ASSEMBLED if unlimited else "inverse_kinematics"]
    x = ca.SX.sym("x", mech.n_out)
    mode = ca.SX.sym("mode", ik.numel_in(1))
    design = ca.SX.sym("design", ik.numel_in(2))
    sources: dict[str, dict[str, ca.SX]] = {}
    if FROM_POSE in fns and ASSEMBLED not in fns:
        sources["first_order"] = _outputs(fns[FROM_POSE], [x, mode, design])
        q, reach = sources["first_order"].pop("q"), sources["first_order"].pop("reach")
    else:
        q, reach = ik(x, mode, design)
    # the reach with the stated limits, whichever set the pipeline reads
    limited = limited_reach(fns, mech.limits, reach, q=q, x=x, design=design) if unlimited else reach
    sources["inverse_kinematics"] = {"q": q, "reach": limited}
    reachable = ca.mmin(reach) >= -REACH_TOLERANCE
    # the normalisation by a characteristic length, where an index takes normalised matrices
    scales = _scales(mech, design) if matrices or any(not spec.raw for spec in locals_) else None
    moving = reads_motion(locals_)
    wanted = [s.source for s in locals_ if s.source != MOTION] + (["first_order"] if first_order or moving else [])
    for source in [name for name in dict.fromkeys(wanted) if name not in sources]:
        if isinstance(source, ca.Function):  # a local index's own function of (q, x, design)
            sources[source] = _outputs(source, [q, x, design])
        elif from_pose(source) in fns and ASSEMBLED not in fns:
            sources[source] = _outputs(fns[from_pose(source)], [x, mode, design])
            del sources[source]["q"], sources[source]["reach"]
        else:
            fn = fns.require(source, f"the {mech.name} pipeline")
            sources[source] = _outputs(fn, [q, x, design])
    inputs, input_names = [x, mode, design], ["x", "mode", "design"]
    if moving:
        motion = ca.SX.sym("motion", 2 * mech.n_out)
        read = {a for spec in locals_ if spec.source == MOTION for a in spec.arguments}
        unknown = sorted(read - set(MOTION_ARGUMENTS))
        if unknown:
            raise PkmError(f"a local index reads {unknown[0]} of the motion, which offers "
                           f"{', '.join(MOTION_ARGUMENTS)}")
        sources[MOTION] = _motion(mech, read, x=x, mode=mode, design=design, motion=motion,
                                  first=sources["first_order"])
        inputs.append(motion)
        input_names.append("motion")
    outputs, names = [q, reach, reachable], ["q", "reach", "valid"]
    arguments = {}
    for spec in locals_:
        missing = [a for a in spec.arguments if a not in sources[spec.source]]
        if missing:
            raise PkmError(f"the local index {spec.name} needs {', '.join(missing)} of {spec.source}")
        args = [sources[spec.source][a] if spec.raw else normalise(a, sources[spec.source][a], scales)
                for a in spec.arguments]
        arguments[spec.name] = args
        formula = replace(spec, formula=spec.smooth, smooth=None) if smooth and spec.smooth is not None else spec
        value = local_function(formula, args[0].size1(), tuple(a.shape for a in args))(*args)
        outputs.append(value if signed else ca.if_else(reachable, value, np.nan))
        names.append(spec.name)
    if signed:
        outputs[2] = ca.mmin(ca.fabs(ca.vertcat(*outputs[3:])) < np.inf)
    if matrices:
        outputs += arguments[locals_[0].name]
        names += [f"argument_{a}" for a in locals_[0].arguments]
    if first_order:
        outputs += list(sources["first_order"].values())
        names += list(sources["first_order"])
    label = "_".join([*(s.name for s in locals_), *(["first_order"] if first_order else [])])
    return ca.Function(f"{mech.name}_{label}", inputs, outputs, input_names, names, {"cse": True} if moving else {})


@lru_cache(maxsize=256)
def first_order_outputs(mech: PipelineModel, names: tuple[str, ...]) -> ca.Function:
    """``(x, mode, design) -> (valid, *names)``: the named outputs of :func:`pipeline` with the first
    order (``q`` and those of ``first_order``: ``J``, ``J_f``, ``psi``, ``det_type1``, ``det_type2``), each
    NaN where the pose is not reached (a reach margin below tolerance or a joint not finite), so that
    the kernel computes and writes only what is asked. The first order is the kinematics' own: defined
    wherever the mechanism assembles, its stated limits aside."""
    fused = pipeline(mech, (), first_order=True, assembled=True)
    x, mode, design = (ca.SX.sym(fused.name_in(i), fused.sparsity_in(i)) for i in range(3))
    out = dict(zip(fused.name_out(), fused(x, mode, design), strict=True))
    valid = closed(out["reach"], out["q"])
    finished = [nan_unless(valid, out[name]) for name in names]
    return ca.Function(f"{fused.name()}_{'_'.join(names)}", [x, mode, design], [valid, *finished], fused.name_in(),
                       ["valid", *names])


@lru_cache(maxsize=256)
def index_pipeline(mech: PipelineModel, locals_: tuple[LocalIndex, ...], assembled: bool = False,
                   reach: bool = True) -> ca.Function:
    """``(x, mode, design) -> (valid, *values)``: the local indices of :func:`pipeline` as
    :func:`evaluate_at` returns them, without the joints: each value NaN where the pose is not reached
    and the index's limit (``at_singularity``) where it is not finite at a reached pose; without ``reach``,
    ``(x, mode, design) -> values`` (:func:`index_values`: one output less for the kernel to write)."""
    fused = pipeline(mech, locals_, assembled=assembled)
    x, mode, design = (ca.SX.sym(fused.name_in(i), fused.sparsity_in(i)) for i in range(3))
    _, _, valid, *values = fused(x, mode, design)
    finished = [
        ca.if_else(valid, ca.if_else(ca.fabs(v) < np.inf, v, spec.at_singularity), np.nan)
        for spec, v in zip(locals_, values, strict=True)
    ]
    names = [spec.name for spec in locals_]
    if not reach:
        return ca.Function(f"{fused.name()}_only", [x, mode, design], finished, fused.name_in(), names)
    return ca.Function(f"{fused.name()}_values", [x, mode, design], [valid, *finished], fused.name_in(),
                       ["valid", *names])


@dataclass(frozen=True)
class Evaluation:
    """Local indices at a batch of poses: one (N,) array of values per index, NaN where out of reach
    and the index's limit at singular poses, and the reach mask (N,), formed when it is read."""

    valid: np.ndarray
    values: tuple[np.ndarray, ...]
    finite: bool = True  # every entry of the poses (and of designs given per pose) the kernel read is finite

    @property
    def reachable(self) -> np.ndarray:
        return self.valid[:, 0, 0] > 0


def evaluate_at(
    mech: PipelineModel, locals_: Sequence[LocalIndex], x: np.ndarray, signs: np.ndarray, design: np.ndarray, *,
    assembled: bool = False,
) -> Evaluation:
    """The fused pipeline over poses x (N, n_out) of one design (n_p,) or of designs (N, n_p); with
    ``assembled``, reached where the mechanism assembles whatever its stated limits (:func:`pipeline`)."""
    (valid, *values), finite = evaluate_finite(index_pipeline(mech, tuple(locals_), assembled), x, signs, design)
    return Evaluation(valid, tuple(v[:, 0, 0] for v in values), finite)


def index_values(
    mech: PipelineModel, locals_: Sequence[LocalIndex], x: np.ndarray, signs: np.ndarray, design: np.ndarray
) -> tuple[tuple[np.ndarray, ...], bool]:
    """The local indices at poses x (N, n_out) as :func:`evaluate_at` gives them, without the reach mask
    (NaN marks what is out of reach), and whether every entry the kernel read is finite."""
    values, finite = evaluate_finite(index_pipeline(mech, tuple(locals_), reach=False), x, signs, design)
    return tuple(v[:, 0, 0] for v in values), finite
