"""The kinematic core shared by every mechanism: branches, batch shaping, design vectors, the typed
wrapper over the generated functions, joint solutions and forward kinematics.

Every mechanism's generated module follows one port convention (written by ``symbolic/kinematics.py``):

* ``inverse_kinematics(x, mode, design) -> (q, reach)``: all joints, actuated first; reach >= 0;
* ``forward_kinematics(q_a, assembly, design) -> (x, q, reach)`` where a closed form exists;
* ``first_order(q, x, design) -> (J, J_f, psi, det_type1, det_type2)`` with q_a_dot = J x_dot;
* ``constraint(q, x, design) -> (h, H_q, H_x)``;
* where the inverse kinematics gives the joint angles' cosines and sines without trigonometric calls,
  twins of functions of the joints that take the pose instead (:func:`from_pose`);

and carries the names of its design parameters, pose coordinates and actuators (``PARAMETERS``,
``POSE``, ``ACTUATORS``), which :class:`GeneratedFunctions` checks against the runtime's on loading.
Forward kinematics is closed form (:class:`ClosedForm`), a Newton rootfinder on the loop residual
(:class:`Rootfinder`) or the real roots of an emitted polynomial (:class:`PolynomialRoots`), all behind
the one contract of :meth:`ForwardKinematics.solve`.
"""

from __future__ import annotations

import importlib
import numbers
import reprlib
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import TYPE_CHECKING, Any, Protocol

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, all_finite, evaluate, evaluate_finite, reached
from pkm.errors import PkmError, PoseError, UnknownNameError, check_name

if TYPE_CHECKING:
    from pkm.design import Design

DesignLike = Mapping[str, float] | Sequence[float] | np.ndarray | None
ROOT_TOLERANCE = 1e-10  # [residual units] a numerical FK solution closes the loop to this
IMAGINARY_TOLERANCE = 1e-8  # relative imaginary part below which a polynomial root counts as real


@dataclass(frozen=True)
class Branch:
    """A working mode (IK branch) or assembly mode (FK branch): name, signs (or index), the papers' names."""

    name: str
    signs: tuple[float, ...]
    doc: str
    aliases: tuple[str, ...] = ()


def find_branch(name: str | None, branches: Sequence[Branch], kind: str) -> Branch:
    """The branch called ``name`` (or one of its aliases); the first one when ``name`` is None."""
    if name is None:
        return branches[0]
    check_name(kind, name, [b.name for b in branches])
    for b in branches:
        if name == b.name or name in b.aliases:
            return b
    raise UnknownNameError(kind, name, [b.name for b in branches])


def as_real(values: Any, what: str, shape: str) -> np.ndarray:
    """``values`` as a float array; :class:`PoseError` naming ``what`` and the expected ``shape`` for what
    is not an array of real numbers: text, mappings, sets, None, booleans, complex numbers, ragged
    nesting, integers too large for a float."""
    if isinstance(values, np.ndarray) and values.dtype == np.float64:
        return values

    def violated() -> PoseError:
        return PoseError(f"{what} = {reprlib.repr(values)} violates: an array of real numbers of shape {shape}")

    if isinstance(values, str | bytes | Mapping | set | frozenset):
        raise violated()
    try:
        arr = np.asarray(values)
        if arr.dtype.kind == "O" and all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in arr.flat):
            arr = arr.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise violated() from None
    if arr.dtype.kind not in "iuf":
        raise violated()
    return arr.astype(float, copy=False)


def as_batch(values: Any, width: int, what: str, *, finite: bool = True) -> tuple[np.ndarray, bool]:
    """``values`` as an (N, width) array (N may be 0), and whether it was a single 1-D row;
    :class:`PoseError` naming ``what`` for what is not real numbers, a wrong shape or (with ``finite``)
    non-finite values. A caller whose kernel reads every entry leaves ``finite`` off and calls
    :func:`require_finite` where :func:`pkm.batch.evaluate_finite` says an entry was not finite."""
    shape = f"({width},) or (N, {width})"
    arr = as_real(values, what, shape)
    if arr.ndim not in (1, 2) or arr.shape[-1] != width:
        raise PoseError(f"{what} must have shape {shape}; got {arr.shape}")
    single = arr.ndim == 1
    arr = np.atleast_2d(arr)
    if finite:
        require_finite(arr, what)
    return arr, single


def require_finite(arr: np.ndarray, what: str) -> None:
    """:class:`PoseError` naming ``what`` where ``arr`` has a non-finite value."""
    if not all_finite(arr):
        raise PoseError(f"{what} contains non-finite values")


def from_pose(name: str) -> str:
    """The name of the twin of the generated function ``name(q, x, ...)`` that takes the pose and the
    working mode instead of the joints: ``name_from_pose(x, mode, ...) -> (q, reach, outputs of name...)``,
    equal to the inverse kinematics composed with ``name`` (``symbolic.kinematics.add_from_pose``)."""
    return f"{name}_from_pose"


def unbatch(arr: np.ndarray, single: bool) -> np.ndarray:
    """The first row of a batch that came from a single 1-D input, else the batch."""
    return arr[0] if single else arr


class FunctionTable(Mapping[str, ca.Function]):
    """A mechanism's CasADi functions by name; ``source`` says where they come from in messages."""

    def __init__(self, functions: Mapping[str, ca.Function], source: str) -> None:
        self._table = dict(functions)
        self.source = source

    def _load(self) -> dict[str, ca.Function]:
        return self._table

    def __getitem__(self, name: str) -> ca.Function:
        return self._load()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._load())

    def __len__(self) -> int:
        return len(self._load())

    def check(self) -> None:
        """Raise :class:`PkmError` where the functions do not fit the mechanism (nothing to check here)."""

    def require(self, name: str, purpose: str) -> ca.Function:
        """The function ``name``; :class:`PkmError` saying what needs it when the model lacks it."""
        functions = self._load()
        if name not in functions:
            raise PkmError(
                f"{purpose} needs the {name!r} function, which {self.source} does not have "
                f"(it has {', '.join(sorted(functions))})"
            )
        return functions[name]


class GeneratedFunctions(FunctionTable):
    """The functions of ``generated.<module>``, loaded on first use with the names of its ports checked,
    and the functions ``extra`` composes from them (CasADi, for what sympy would render poorly).

    Loading checks that the module's ``PARAMETERS``, ``POSE`` and ``ACTUATORS`` equal the runtime's
    names, so that a design vector means the same on both sides.
    """

    def __init__(
        self,
        module: str,
        *,
        parameters: Sequence[str],
        pose: Sequence[str],
        actuators: Sequence[str],
        extra: Callable[[Mapping[str, ca.Function]], Mapping[str, ca.Function]] | None = None,
    ) -> None:
        super().__init__({}, f"generated.{module}")
        self.module = module
        self.expected = {"PARAMETERS": tuple(parameters), "POSE": tuple(pose), "ACTUATORS": tuple(actuators)}
        self.extra = extra

    @property
    def source_hash(self) -> str:
        """The generated module's hash of the symbolic sources it was derived from."""
        return importlib.import_module(f"generated.{self.module}").SOURCE_HASH

    def check(self) -> None:
        """Import the generated module (without building its functions) and compare its names."""
        generated = importlib.import_module(f"generated.{self.module}")
        for attribute, expected in self.expected.items():
            found = tuple(getattr(generated, attribute, ()))
            if found != expected:
                raise PkmError(
                    f"generated.{self.module}.{attribute} = {found} differs from the runtime's {expected}: "
                    "regenerate with `make generate` or fix the mechanism's names"
                )

    @cached_property
    def _generated(self) -> dict[str, ca.Function]:
        self.check()
        functions = importlib.import_module(f"generated.{self.module}").build()
        if self.extra is not None:
            functions.update(self.extra(functions))
        return functions

    def _load(self) -> dict[str, ca.Function]:
        return self._generated


class KinematicModel(Protocol):
    """What the generic layers read of a mechanism."""

    name: str
    n_act: int
    n_out: int
    functions: FunctionTable
    assembly_modes: tuple[Branch, ...]

    def design_vector(self, design: DesignLike | Design) -> np.ndarray: ...

    def working_mode(self, mode: str | None) -> Branch: ...

    def assembly_mode(self, assembly: str | None) -> Branch: ...


@dataclass(frozen=True)
class Joints:
    """Joint solutions of a batch of poses: poses x (N, n_out), design vector (n_p,), the joints q (N, n_q,
    or N, n_act where only the actuated ones were asked; NaN where out of reach), the reach mask (N,) and
    whether the input was a single pose."""

    x: np.ndarray
    design: np.ndarray
    q: np.ndarray
    reachable: np.ndarray
    single: bool

    def unbatch(self, arr: np.ndarray) -> np.ndarray:
        return unbatch(arr, self.single)


@lru_cache(maxsize=64)
def with_reach(fn: ca.Function, outputs: tuple[str, ...], rows: int | None = None) -> ca.Function:
    """``fn`` with its reach check in the graph: its inputs -> ``(valid, *outputs)``, ``valid`` 1 where
    every margin of its output ``reach`` is >= -REACH_TOLERANCE and the first of ``outputs`` is finite,
    else 0, and every output NaN where ``valid`` is 0; with ``rows``, the first output's first rows alone
    (the actuated joints of all joints). An SX function stays one, so that its kernel writes the batch's
    results whole and nothing is left for numpy to check."""
    symbol = ca.SX.sym if fn.is_a("SXFunction") else ca.MX.sym
    args = [symbol(fn.name_in(i), fn.sparsity_in(i)) for i in range(fn.n_in())]
    out = dict(zip(fn.name_out(), fn.call(args), strict=True))
    if rows is not None:
        out[outputs[0]] = out[outputs[0]][:rows, :]
    valid = closed(out["reach"], out[outputs[0]])
    finished = [nan_unless(valid, out[name]) for name in outputs]
    return ca.Function(f"{fn.name()}_reached", args, [valid, *finished], fn.name_in(), ["valid", *outputs])


ASSEMBLED = "inverse_kinematics_assembled"


def within_limits(functions: Mapping[str, ca.Function], limits: str) -> dict[str, ca.Function]:
    """The inverse kinematics of ``functions`` with the mechanism's stated limits (strokes, joint ranges,
    interference: ``functions[limits](q, x, design) -> margins``, >= 0 where each holds) in its reach, so
    that a pose is reached where the mechanism assembles within them; the inverse kinematics without them
    stays under the name :data:`ASSEMBLED`."""
    ik = functions["inverse_kinematics"]
    args = [ca.SX.sym(ik.name_in(i), ik.sparsity_in(i)) for i in range(ik.n_in())]
    q, reach = ik(*args)
    reach = limited_reach(functions, limits, reach, q=q, x=args[0], design=args[2])
    limited = ca.Function("inverse_kinematics", args, [q, reach], ik.name_in(), ik.name_out())
    return {"inverse_kinematics": limited, ASSEMBLED: ik}


def limited_reach(functions: Mapping[str, ca.Function], limits: str, reach: Any, *, q: Any, x: Any, design: Any
                  ) -> Any:
    """In a graph: the reach margins of the inverse kinematics without the stated limits, followed by the limits'
    margins ``functions[limits](q, x, design)``: the reach of :func:`within_limits`' inverse kinematics."""
    return ca.vertcat(reach, functions[limits](q, x, design))


def closed(reach: Any, values: Any) -> Any:
    """In a graph: 1 where every reach margin is >= -REACH_TOLERANCE and every entry of ``values`` (the
    joints, say) is finite, else 0."""
    finite = ca.mmin(ca.fabs(ca.vec(ca.densify(values))) < np.inf)
    return ca.logic_and(ca.mmin(reach) >= -REACH_TOLERANCE, finite)


def nan_unless(valid: Any, value: Any) -> Any:
    """In a graph: ``value`` (dense) where ``valid``, NaN elsewhere."""
    return ca.if_else(valid, ca.densify(value), ca.DM.nan(*value.shape))


def as_joints(
    x: np.ndarray, design: np.ndarray, valid: np.ndarray, q: np.ndarray, single: bool, *, strict: bool, what: str
) -> Joints:
    """Joints from :func:`with_reach` of the inverse kinematics (``valid`` (N, 1, 1), q NaN where out of
    reach), or :class:`PoseError` naming ``what`` with ``strict`` where a pose is out of reach."""
    ok = valid[:, 0, 0] > 0
    if strict and not ok.all():
        bad = int(np.flatnonzero(~ok)[0])
        raise PoseError(f"pose {x[bad].tolist()} is out of reach of {what}")
    return Joints(x, design, q, ok, single)


def solve_joints(
    mech: KinematicModel, pose: Any, design: Any, mode: str | None, *, strict: bool = False, actuated: bool = False,
    limits: bool = True,
) -> Joints:
    """Inverse kinematics of a batch of poses in a working mode (with ``actuated``, the actuated joints
    alone); NaN where out of reach (within the mechanism's stated limits, or without ``limits`` wherever
    it assembles: :func:`within_limits`), or :class:`PoseError` with ``strict``."""
    x, single = as_batch(pose, mech.n_out, "pose", finite=False)
    d = mech.design_vector(design)
    branch = mech.working_mode(mode)
    name = "inverse_kinematics" if limits or ASSEMBLED not in mech.functions else ASSEMBLED
    fused = with_reach(mech.functions[name], ("q",), mech.n_act if actuated else None)
    (valid, q), finite = evaluate_finite(fused, x, np.array(branch.signs), d)
    if not finite:
        require_finite(x, "pose")
    return as_joints(x, d, valid, q[:, :, 0], single, strict=strict, what=f"the {mech.name} in mode {branch.name}")


class ForwardKinematics(Protocol):
    """A forward-kinematics method: poses and all joints from actuated joints in an assembly mode."""

    def solve(
        self, functions: Mapping[str, ca.Function], q_a: np.ndarray, branch: Branch, design: np.ndarray, *,
        joints: bool = True,
    ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
        """Poses (N, n_out), all joints (N, n_q; None where ``joints`` is off and the method saves their
        computation) and the mask (N,) of the actuated joints that close."""
        ...


@dataclass(frozen=True)
class ClosedForm:
    """Forward kinematics by the generated closed form ``forward_kinematics(q_a, assembly, design)``."""

    function: str = "forward_kinematics"

    def solve(self, functions, q_a, branch, design, *, joints=True):
        outputs = ("x", "q") if joints else ("x",)
        valid, x, *q = evaluate(with_reach(functions[self.function], outputs), q_a, np.array(branch.signs), design)
        return x[:, :, 0], q[0][:, :, 0] if joints else None, valid[:, 0, 0] > 0


@lru_cache(maxsize=32)
def _newton(constraint: ca.Function, n_act: int, max_iter: int) -> tuple[ca.Function, ca.Function]:
    """The loop residual h(z, p) in z = (q_p, x), p = (q_a, design), and a Newton rootfinder on it."""
    n_q = constraint.numel_in(0)
    z = ca.MX.sym("z", n_q - n_act + constraint.numel_in(1))
    p = ca.MX.sym("p", n_act + constraint.numel_in(2))
    q = ca.vertcat(p[:n_act], z[: n_q - n_act])
    h = constraint(q, z[n_q - n_act :], p[n_act:])[0]
    residual = ca.Function("loop_residual", [z, p], [h])
    finder = ca.rootfinder("forward_kinematics", "newton", residual, {"max_iter": max_iter, "error_on_fail": False})
    return residual, finder


@dataclass(frozen=True)
class Rootfinder:
    """Forward kinematics by Newton's method on the loop residual h(q_a, q_p, x) = 0 in (q_p, x).

    ``seed`` is the name of a generated function ``(q_a, assembly, design) -> z0`` giving the starting
    point (q_p, x) of an assembly mode; the solution closes the loop to :data:`ROOT_TOLERANCE` and is
    the assembly mode's where Newton's method converges from its seed.
    """

    seed: str = "forward_seed"
    max_iter: int = 50

    def solve(self, functions, q_a, branch, design, *, joints=True):
        constraint = functions["constraint"]
        residual, finder = _newton(constraint, q_a.shape[1], self.max_iter)
        (z0,) = evaluate(functions[self.seed], q_a, np.array(branch.signs), design)
        params = np.hstack([q_a, np.broadcast_to(design, (len(q_a), len(design)))])
        (z,) = evaluate(finder, z0[:, :, 0], params)
        return _closing(residual, constraint, q_a, z[:, :, 0], design, joints=joints)


def _closing(residual: ca.Function, constraint: ca.Function, q_a: np.ndarray, z: np.ndarray, design: np.ndarray, *,
             joints: bool) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """The poses, all joints (with ``joints``) and the mask of the rows whose solution z = (q_p, x) of the
    loop at actuated joints q_a closes it (``residual``, :func:`_newton`) to ROOT_TOLERANCE."""
    n_act, n_q = q_a.shape[1], constraint.numel_in(0)
    params = np.hstack([q_a, np.broadcast_to(design, (len(q_a), len(design)))])
    q = np.hstack([q_a, z[:, : n_q - n_act]])
    with np.errstate(invalid="ignore"):
        (h,) = evaluate(residual, z, params)
        ok = np.all(np.abs(h[:, :, 0]) <= ROOT_TOLERANCE * max(1.0, float(np.abs(design).max())), axis=1)
    return z[:, n_q - n_act :], q if joints else None, ok & np.all(np.isfinite(z), axis=1)


@lru_cache(maxsize=32)
def _newton_step(constraint: ca.Function, n_act: int) -> ca.Function:
    """``(q_a, z, design) -> z'``: one Newton step on the loop residual in z = (q_p, x) at actuated q_a."""
    n_q = constraint.numel_in(0)
    q_a = ca.SX.sym("q_a", n_act)
    z = ca.SX.sym("z", n_q - n_act + constraint.numel_in(1))
    design = ca.SX.sym("design", constraint.numel_in(2))
    h, H_q, H_x = constraint(ca.vertcat(q_a, z[: n_q - n_act]), z[n_q - n_act :], design)
    step = z - ca.solve(ca.horzcat(H_q[:, n_act:], H_x), h)
    return ca.Function("newton_step", [q_a, z, design], [step], ["q_a", "z", "design"], ["z_next"])


class SeedTable(Protocol):
    """Known configurations of a mechanism with the signature of their assembly mode (:class:`NearestSeeds`)."""

    periodic: tuple[bool, ...]  # which actuated joints are angles
    angles: tuple[bool, ...]  # which entries of z = (q_p, x) are angles

    def table(self, functions: FunctionTable, design: np.ndarray) -> dict[tuple[float, ...], tuple[np.ndarray, ...]]:
        """Configurations by signature: actuated joints (M, n_act) and z = (q_p, x) (M, n_z)."""

    def signature(self, functions: FunctionTable, q: np.ndarray, x: np.ndarray, design: np.ndarray) -> np.ndarray:
        """The signs (N, k) of configurations that an assembly mode's branch begins with."""


SOLUTIONS_KEPT = 8  # solution sets kept (per actuated joints and design)
_SOLUTIONS: dict[tuple, tuple[Any, dict[tuple[float, ...], tuple[np.ndarray, np.ndarray]]]] = {}


@lru_cache(maxsize=32)
def _loop_residual(constraint: ca.Function, n_act: int) -> ca.Function:
    """``(z, p) -> h``: the loop residual in z = (q_p, x) at p = (q_a, design)."""
    n_q = constraint.numel_in(0)
    z = ca.SX.sym("z", n_q - n_act + constraint.numel_in(1))
    p = ca.SX.sym("p", n_act + constraint.numel_in(2))
    h = constraint(ca.vertcat(p[:n_act], z[: n_q - n_act]), z[n_q - n_act :], p[n_act:])[0]
    return ca.Function("loop_residual", [z, p], [h], ["z", "p"], ["h"])


SEED_CHUNK = 2**22  # distances between rows and seeds computed at once


def _embedded(q: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """Joints with each angle replaced by its cosine and sine: Euclidean distances there order the joints'
    distances (angles wrapped) as the chords order the arcs."""
    return np.hstack([q[:, ~periodic], np.cos(q[:, periodic]), np.sin(q[:, periodic])])


_EMBEDDED: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _embedded_table(q0: np.ndarray, periodic: np.ndarray) -> np.ndarray:
    """:func:`_embedded` of a seed table, kept while the table lives (a table is computed once per design)."""
    kept = _EMBEDDED.get(id(q0))
    if kept is None or kept[0] is not q0:
        if len(_EMBEDDED) >= 64:
            _EMBEDDED.pop(next(iter(_EMBEDDED)))
        kept = _EMBEDDED[id(q0)] = (q0, _embedded(q0, periodic))
    return kept[1]


def _nearest(q_a: np.ndarray, q0: np.ndarray, periodic: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` seeds nearest each row of q_a (indices (N, count), nearest first), and the gaps q_a - q0
    (N, count, n_act) to them, angles (``periodic``) wrapped into [-pi, pi)."""
    a, b = _embedded(q_a, periodic), _embedded_table(q0, periodic)
    order = []
    chunk = max(1, SEED_CHUNK // max(1, len(q0)))
    norms = np.sum(b**2, axis=1)[None, :]
    for start in range(0, len(q_a), chunk):
        part = a[start : start + chunk]
        distance = norms - 2.0 * part @ b.T
        nearest = np.argpartition(distance, count - 1, axis=1)[:, :count] if count < len(q0) else \
            np.broadcast_to(np.arange(len(q0)), (len(part), len(q0))).copy()
        order.append(np.take_along_axis(nearest, np.argsort(np.take_along_axis(distance, nearest, axis=1), axis=1),
                                        axis=1))
    order = np.concatenate(order)
    gaps = q_a[:, None, :] - q0[order]
    gaps[..., periodic] = np.mod(gaps[..., periodic] + np.pi, 2 * np.pi) - np.pi
    return order, gaps


CANDIDATES = 4  # seeds nearest the actuated joints per try, among which the tries are spread


def _spread(z0: np.ndarray, order: np.ndarray, gaps: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` of each row's candidate seeds (``order``, nearest first): the nearest half, then each time
    the one farthest from those chosen (in z), so that the tries also reach the several solutions of a
    cuspidal machine whose configurations meet at similar actuated joints."""
    rows = np.arange(len(order))
    near = max(1, count // 2)
    chosen = list(np.broadcast_to(np.arange(near), (len(order), near)).T)
    candidates = z0[order]

    def squared(c: np.ndarray) -> np.ndarray:  # each candidate's squared distance from the c-th
        gap = candidates - candidates[rows, c][:, None, :]
        return np.einsum("nck,nck->nc", gap, gap)

    spread = np.min([squared(c) for c in chosen], axis=0)
    for _ in range(near, count):
        pick = np.argmax(spread, axis=1)
        chosen.append(pick)
        spread = np.minimum(spread, squared(pick))
    picks = np.column_stack(chosen)
    return np.take_along_axis(order, picks, axis=1), np.take_along_axis(gaps, picks[:, :, None], axis=1)


@dataclass(frozen=True)
class NearestSeeds:
    """Forward kinematics by Newton's method with continuation from the known configurations nearest the
    actuated joints.

    An assembly mode's branch is a signature (the signs :class:`SeedTable` computes at a configuration,
    such as the side of each elbow and the sign of the type-II determinant) and a rank k: among the
    solutions of the signature, ordered by the last pose coordinate, the k-th (from 1). The solutions of a
    signature are those reached from ``tries`` of its configurations near the actuated joints (angles
    wrapped; spread among the CANDIDATES x ``tries`` nearest, :func:`_spread`): the actuated joints move to
    the given ones in ``steps`` equal steps, each solved from the last by ``iterations`` Newton steps (at
    the last, up to ``polish`` until the row no longer moves: Newton's method slows to halving the error
    near a type-II singularity); those that close the loop to :data:`ROOT_TOLERANCE` with the signature
    count, each once. A cuspidal machine has several solutions of one signature at the same actuated
    joints: the rank tells them apart. Every signature is solved at once, in one batch, and the solutions
    of the last few inputs are kept, so that asking for each assembly mode in turn solves once.
    """

    seeds: SeedTable
    steps: int = 8
    iterations: int = 4
    polish: int = 60
    tries: int = 12

    def solve(self, functions, q_a, branch, design, *, joints=True):
        constraint = functions["constraint"]
        *signature, rank = branch.signs
        n_z = constraint.numel_in(0) - q_a.shape[1] + constraint.numel_in(1)
        chosen = np.full((len(q_a), n_z), np.nan)
        found = self.solutions(functions, q_a, design).get(tuple(signature))
        if found is not None and int(rank) <= found[1].shape[1]:
            z, order = found
            pick = order[:, int(rank) - 1]
            chosen[pick >= 0] = z[np.flatnonzero(pick >= 0), pick[pick >= 0]]
        return _closing(_loop_residual(constraint, q_a.shape[1]), constraint, q_a, chosen, design, joints=joints)

    def solutions(self, functions, q_a, design) -> dict[tuple[float, ...], tuple[np.ndarray, np.ndarray]]:
        """By signature: the solutions z (N, tries, n_z) (NaN where a try failed or repeats one; angles in
        [-pi, pi)) and their order by the last pose coordinate (N, tries; -1 past the last)."""
        design = np.asarray(design, dtype=float)
        key = (id(functions), id(self.seeds), self.steps, self.iterations, self.polish, self.tries, q_a.shape,
               q_a.tobytes(), design.tobytes())
        if key not in _SOLUTIONS:
            if len(_SOLUTIONS) >= SOLUTIONS_KEPT:
                _SOLUTIONS.pop(next(iter(_SOLUTIONS)))
            _SOLUTIONS[key] = (functions, self._solve(functions, q_a, design))
        return _SOLUTIONS[key][1]

    def _starts(self, q_a, table):
        """Per signature, its tries' seeds (q_a0, z0, gaps), each (N, T, ...)."""
        out = {}
        periodic = np.array(self.seeds.periodic)
        for signature, (q0, z0) in table.items():
            order, gaps = _nearest(q_a, q0, periodic, min(CANDIDATES * self.tries, len(q0)))
            order, gaps = _spread(z0, order, gaps, min(self.tries, len(q0)))
            out[signature] = (q0[order], z0[order], gaps)
        return out

    def _solve(self, functions, q_a, design):
        if not len(q_a):
            return {}
        distinct, inverse = np.unique(q_a, axis=0, return_inverse=True)
        if len(distinct) < len(q_a):
            return {k: (z[inverse.ravel()], order[inverse.ravel()])
                    for k, (z, order) in self._solve(functions, distinct, design).items()}
        constraint = functions["constraint"]
        n_act = q_a.shape[1]
        starts = self._starts(q_a, self.seeds.table(functions, design))
        if not starts:
            return {}
        q0, z0, gap = (np.concatenate([s[k].reshape(-1, s[k].shape[2]) for s in starts.values()]) for k in range(3))
        row = np.concatenate([np.repeat(np.arange(len(q_a)), s[0].shape[1]) for s in starts.values()])
        z = self._continue(constraint, q0, gap, z0, design)
        with np.errstate(invalid="ignore"):
            x, q, closed = _closing(_loop_residual(constraint, n_act), constraint, q_a[row], z, design, joints=True)
            signature = self.seeds.signature(functions, q, x, design)
        out, first = {}, 0
        for name, (s, _, _) in starts.items():
            rows = slice(first, first + s.shape[0] * s.shape[1])
            part = np.where((closed[rows] & np.all(signature[rows] == name, axis=1))[:, None], z[rows], np.nan)
            part = part.reshape(len(q_a), s.shape[1], -1)
            self._forget_repeats(part, np.array(self.seeds.angles))
            last = np.where(np.isnan(part[:, :, -1]), np.inf, part[:, :, -1])
            order = np.argsort(last, axis=1, kind="stable")
            order[np.take_along_axis(np.isinf(last), order, axis=1)] = -1
            out[name] = (part, order)
            first += s.shape[0] * s.shape[1]
        return out

    def _continue(self, constraint, q0, gap, z, design):
        """The rows' z after the continuation from (q0, z) to q0 + gap, each polished until it stops."""
        step = _newton_step(constraint, q0.shape[1])
        with np.errstate(invalid="ignore", over="ignore"):
            for k in range(1, self.steps):
                target = q0 + (k / self.steps) * gap
                for _ in range(self.iterations):
                    (z,) = evaluate(step, target, z, design)
                    z = z[:, :, 0]
            target = q0 + gap
            active = np.arange(len(z))
            for _ in range(self.polish):
                (moved,) = evaluate(step, target[active], z[active], design)
                moved = moved[:, :, 0]
                change = np.abs(moved - z[active])
                z[active] = moved
                active = active[np.any(change > STALL * (1.0 + np.abs(moved)), axis=1)]
                if not len(active):
                    break
        return z

    def _forget_repeats(self, z: np.ndarray, angles: np.ndarray) -> None:
        """Angles wrapped into [-pi, pi) in place, and NaN in place of a solution equal to an earlier try's."""
        z[:, :, angles] = np.mod(z[:, :, angles] + np.pi, 2 * np.pi) - np.pi
        gap = np.abs(z[:, :, None, :] - z[:, None, :, :])
        gap[..., angles] = np.minimum(gap[..., angles], 2 * np.pi - gap[..., angles])
        with np.errstate(invalid="ignore"):
            same = np.all(gap <= REPEAT_TOLERANCE * (1.0 + np.abs(z[:, None, :, :])), axis=3)
        z[np.any(np.tril(same, k=-1), axis=2)] = np.nan


REPEAT_TOLERANCE = 1e-7  # two solutions closer than this (relative) are one
STALL = 1e-15  # a Newton step smaller than this (relative) moves nothing


POLISH_LIMIT = 1e-6
ROOTS_KEPT = 8
_ROOTS: dict[tuple, tuple[Any, np.ndarray]] = {}


def _polish(c: np.ndarray, roots: np.ndarray, steps: int = 2) -> np.ndarray:
    """Newton steps on each row's polynomial (coefficients c (N, degree + 1), highest first) from its
    real roots (N, k): the companion matrix's eigenvalues carry errors of the matrix's norm. A step
    larger than POLISH_LIMIT (relative) is not taken: near a double root Newton would wander."""
    for _ in range(steps):
        value = np.zeros_like(roots)
        slope = np.zeros_like(roots)
        for k in range(c.shape[1]):
            slope = slope * roots + value
            value = value * roots + c[:, k : k + 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(slope != 0, value / slope, 0.0)
        small = np.isfinite(step) & (np.abs(step) <= POLISH_LIMIT * np.maximum(1.0, np.abs(roots)))
        roots = roots - np.where(small, step, 0.0)
    return roots


@dataclass(frozen=True)
class PolynomialRoots:
    """Forward kinematics through the real roots of an emitted univariate polynomial.

    ``polynomial(q_a, design) -> c`` gives the coefficients (highest degree first); ``back(root, q_a,
    design) -> (x, q, reach)`` recovers the pose and the joints from one root. Assembly mode k (its
    ``signs[0]``, counted from 0) is the k-th real root in ascending order: NaN where fewer exist. With
    ``scale`` (a function design -> a typical size of the roots, for a root with a unit) the roots are
    found in the dimensionless variable root / scale, so that the tolerances hold at any scale.
    """

    polynomial: str = "forward_polynomial"
    back: str = "forward_from_root"
    scale: str | None = None

    def roots(self, functions: Mapping[str, ca.Function], q_a: np.ndarray, design: np.ndarray) -> np.ndarray:
        """Real roots (N, degree), ascending, NaN-padded; by the eigenvalues of the companion matrices.

        Leading coefficients that vanish (relative to the largest) lower the degree of that row's
        polynomial instead of sending its roots to infinity. The roots of the last few inputs are kept,
        so that asking for each assembly mode of the same actuator values in turn solves once.
        """
        q_a, design = np.asarray(q_a, dtype=float), np.asarray(design, dtype=float)
        key = (id(functions), self, q_a.shape, q_a.tobytes(), design.tobytes())
        if key not in _ROOTS:
            if len(_ROOTS) >= ROOTS_KEPT:
                _ROOTS.pop(next(iter(_ROOTS)))
            # the table is kept with its roots, so that its id cannot be reused while the entry lives
            _ROOTS[key] = (functions, self.compute(functions, q_a, design))
        return _ROOTS[key][1].copy()

    def compute(self, functions: Mapping[str, ca.Function], q_a: np.ndarray, design: np.ndarray) -> np.ndarray:
        """The real roots as :meth:`roots` gives them, computed afresh (no kept results)."""
        (c,) = evaluate(functions[self.polynomial], q_a, design)
        c = c.reshape(len(q_a), functions[self.polynomial].numel_out(0))
        degree = c.shape[1] - 1
        size = 1.0 if self.scale is None else float(functions[self.scale](np.asarray(design, dtype=float)))
        c = c * size ** np.arange(degree, -1, -1)
        scale = np.max(np.abs(c), axis=1, keepdims=True)
        leading = np.argmax(np.abs(c) > IMAGINARY_TOLERANCE**2 * scale, axis=1)
        values = np.full((len(c), degree), np.nan + 0j)
        for skip in np.unique(leading[np.all(np.isfinite(c), axis=1)]):
            rows = np.flatnonzero((leading == skip) & np.all(np.isfinite(c), axis=1))
            d = degree - skip
            if d < 1:
                continue
            coefficients = c[rows, skip:]
            companion = np.zeros((len(rows), d, d))
            companion[:, 0, :] = -coefficients[:, 1:] / coefficients[:, :1]
            companion[:, np.arange(1, d), np.arange(d - 1)] = 1.0
            values[rows, :d] = np.linalg.eigvals(companion)
        real = np.abs(values.imag) <= IMAGINARY_TOLERANCE * np.maximum(1.0, np.abs(values))
        return size * np.sort(_polish(c, np.where(real, values.real, np.nan)), axis=1)

    def solve(self, functions, q_a, branch, design, *, joints=True):
        k = int(branch.signs[0])
        root = self.roots(functions, q_a, design)[:, k : k + 1]
        x, q, reach = evaluate(functions[self.back], np.nan_to_num(root), q_a, design)
        ok = reached(x, reach) & np.isfinite(root[:, 0])
        return x[:, :, 0], q[:, :, 0] if joints else None, ok
