"""Accuracy with real parts (issue 42): a machine's error model, its pose error under tolerances, the widest
tolerances within a budget, and calibration.

The error model expands the machine's legs in the description vocabulary (a described machine's description, or the
legs a hand-derived machine gives: :meth:`pkm.Mechanism.described_legs`) per leg (:func:`expanded`): each leg's
base and platform attachments and each of its lengths (a kind's proximal, distal, arm or rod; a chain joint's
non-zero link, per component) get an error parameter of their own, default 0, so that the nominal machine is the same
graphs at zero error; each actuated joint's zero offset (the joint's own less the joint the drive reads) is one
more. The pose error Jacobian E = dx/dp at fixed actuated joints follows from the closure h(q_a, q_p, x, p) = 0:
[H_p H_x] [dq_p; dx] = -dh/dp dp for the geometric errors, and the forward Jacobian's columns for the zero offsets;
composed in CasADi and evaluated over batches like every other graph.

Under tolerances |p_k| <= t_k the linearised worst case of each pose coordinate is sum_k |E_ik| t_k; under
independent Gaussian errors of deviations s_k its RMS is sqrt(sum_k (E_ik s_k)^2); a Monte Carlo run draws
the errors, closes the loops of the perturbed machine at the same actuated joints and compares.

The widest tolerances (:func:`widest_tolerances`) maximise sum_k w_k log t_k (or the user's weights) with
every translational coordinate's worst case within the budget at every task pose: linear constraints in t, a
convex problem IPOPT solves exactly. Calibration (:func:`calibrate`) identifies the errors from measured poses
at read actuated joints by bounded, regularised Gauss-Newton steps on the closed loops, and reports the
identifiability of each parameter (the stacked Jacobian's rank and singular values) and its confidence."""

from __future__ import annotations

import copy
import functools
import reprlib
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions
from pkm.batch import evaluate
from pkm.errors import PkmError
from pkm.indices import GlobalIndex, LocalIndex
from pkm.kinematics import as_batch
from pkm.spec.vocabulary import CHAIN, KINDS

SPAN = 0.1  # [m] an error parameter's bounds in the expanded description, either way
CLOSURE_STEPS = 20  # Newton steps closing a perturbed machine's loops
CLOSED = 1e-12  # [m] a loop closed to this
MONTE_CARLO_ROWS = 100_000  # machines of a Monte Carlo run closed in one batch


@dataclass(frozen=True)
class ErrorParameter:
    """One geometric error: its name (a design parameter of the expanded machine, or a drive's zero offset),
    unit, meaning and leg (1-based)."""

    name: str
    unit: str
    doc: str
    leg: int


def _plus(tree: Any, name: str) -> Any:
    return ["+", tree, name]


ATTACHMENTS = ("cartesian", "polar")  # how an attachment's errors are named


def _circle(x: Any, y: Any) -> tuple[Any, Any] | None:
    """The radius and angle of an attachment placed on a circle (the schema's normal form, x = rho cos(a) and
    y = rho sin(a)), else None."""
    if (isinstance(x, list) and isinstance(y, list) and len(x) == len(y) == 3 and x[0] == y[0] == "*"
            and x[1] == y[1] and isinstance(x[2], list) and isinstance(y[2], list) and x[2][0] == "cos"
            and y[2][0] == "sin" and x[2][1:] == y[2][1:]):
        return x[1], x[2][1]
    return None


def expanded(data: dict[str, Any], attachments: str = "cartesian", axes: bool = False
             ) -> tuple[dict[str, Any], list[ErrorParameter]]:
    """The normalised description with an error parameter added to each leg's attachments and lengths, and
    those parameters: an attachment's errors along x, y and z, or with ``attachments="polar"``, where it is
    placed on a circle, of its circle's radius [m] and its angle on it [rad] (a tower's radius and angle) and
    along z; with ``axes``, the joints' axes' tilts (:func:`_tilted`)."""
    if attachments not in ATTACHMENTS:
        raise PkmError(f"attachments violates: one of {', '.join(ATTACHMENTS)}; got {attachments!r}")
    out = copy.deepcopy(dict(data))
    out["legs"] = [copy.deepcopy(leg) for leg in data["legs"]]  # each its own: legs of one table share their joints
    out["name"] = f"{data['name']}_errors" if attachments == "cartesian" else f"{data['name']}_{attachments}_errors"
    out["doc"] = f"{data['doc']}, each leg's geometry with errors of its own"
    named = "xyz"
    design = {p["name"]: p["default"] for p in data["parameters"]}
    errors: list[ErrorParameter] = []

    def add(name: str, doc: str, leg: int, unit: str = "m") -> str:
        errors.append(ErrorParameter(name, unit, doc, leg))
        return name

    for k, leg in enumerate(out["legs"], 1):
        for end in ("base", "platform"):
            circle = _circle(*leg[end][:2]) if attachments == "polar" and len(leg[end]) == 3 else None
            if circle is None:
                leg[end] = [_plus(t, add(f"e_{end}{k}_{named[c]}", f"leg {k}'s {end} attachment along {named[c]}", k))
                            for c, t in enumerate(leg[end])]
                continue
            rho = _plus(circle[0], add(f"e_{end}{k}_radius", f"leg {k}'s {end} attachment's circle radius", k))
            angle = _plus(circle[1], add(f"e_{end}{k}_angle", f"leg {k}'s {end} attachment's angle on its circle",
                                         k, "rad"))
            leg[end] = [["*", rho, ["cos", angle]], ["*", rho, ["sin", angle]],
                        _plus(leg[end][2], add(f"e_{end}{k}_z", f"leg {k}'s {end} attachment along z", k))]
        if leg["kind"] != CHAIN:
            for field in KINDS[leg["kind"]].lengths:
                leg[field] = _plus(leg[field], add(f"e_{field}{k}", f"leg {k}'s {field} length", k))
        for j, joint in enumerate(leg["joints"]):
            link = joint.get("link", [])
            if leg["kind"] == CHAIN and any(not (isinstance(c, int | float) and c == 0) for c in link):
                joint["link"] = [_plus(t, add(f"e_link{k}_{j + 1}{named[c]}", f"leg {k}'s link {j + 1} along "
                                                                             f"{named[c]} of its joint's frame", k))
                                 for c, t in enumerate(link)]
        if axes:
            _tilted(leg, k, add, design)
    out["parameters"] = [*out["parameters"], *({"name": e.name, "default": 0.0, "lower": -SPAN, "upper": SPAN,
                                               "unit": e.unit, "doc": e.doc} for e in errors)]
    return out, errors


def _cross(a: list[Any], b: list[Any]) -> list[Any]:
    return [["-", ["*", a[(i + 1) % 3], b[(i + 2) % 3]], ["*", a[(i + 2) % 3], b[(i + 1) % 3]]] for i in range(3)]


def _turned(u: list[Any], v: list[Any], angle: str) -> list[Any]:
    """u cos(angle) + v sin(angle), entry by entry (u turned towards v, both unit and at right angles)."""
    return [["+", ["*", x, ["cos", angle]], ["*", y, ["sin", angle]]] for x, y in zip(u, v, strict=True)]


def _tilted(leg: dict[str, Any], k: int, add: Any, design: Mapping[str, float]) -> None:
    """A leg's joint axes with errors of their own: an R_parallelogram's drive axis (:func:`_parallelogram_tilted`), a
    PRR's slide turned in the plane by e_axis<k>, and each axis of a chain's joints in space (an R's, a P's, a U's or
    a parallelogram's two, not a revolute's in the plane, which is the plane's normal) turned by two angles,
    e_axis<k>_<j>_1 and _2 (e_axis<k>_<j>a_1 ... for a joint's first of two axes, b for its second): the unit axis a
    turned towards n1 (across a and the coordinate axis a is least along at the default design), then towards
    n2 = a x n1, exact rotations; in a planar chain a P's slide turned in the plane by e_axis<k>_<j>."""
    if leg["kind"] == "R_parallelogram":
        _parallelogram_tilted(leg, k, add)
    elif leg["kind"] == "PRR":
        name = add(f"e_axis{k}", f"leg {k}'s slide turned in the plane", k, "rad")
        leg["axis"] = leg["joints"][0]["axis"] = _turned_in_plane(leg["axis"], name, design)
    elif leg["kind"] == CHAIN:
        planar = len(leg["base"]) == 2
        for j, joint in enumerate(leg["joints"], 1):
            if joint["type"] == "P" and planar:
                name = add(f"e_axis{k}_{j}", f"leg {k}'s joint {j}'s slide turned in the plane", k, "rad")
                joint["axis"] = _turned_in_plane(joint["axis"], name, design)
            elif not planar and joint["type"] == "P":
                joint["axis"] = _turned_in_space(joint["axis"], f"e_axis{k}_{j}", f"leg {k}'s joint {j}'s slide",
                                                 k=k, add=add, design=design)
            elif not planar and "axes" in joint:
                letters = [""] if len(joint["axes"]) == 1 else ["a", "b"]
                joint["axes"] = [_turned_in_space(a, f"e_axis{k}_{j}{letter}", f"leg {k}'s joint {j}'s "
                                                  f"{'first ' if letter == 'a' else 'second ' if letter else ''}axis",
                                                  k=k, add=add, design=design)
                                 for a, letter in zip(joint["axes"], letters, strict=True)]


def _unit(axis: list[Any], design: Mapping[str, float]) -> tuple[list[Any], np.ndarray]:
    """A direction's unit vector (numbers where it is constant, else trees) and its value at the default design."""
    values = np.array([float(expressions.evaluate(t, design)) for t in axis])
    if all(isinstance(t, int | float) for t in axis):
        unit = values / np.linalg.norm(values)
        return [float(c) for c in unit], unit
    norm = ["sqrt", functools.reduce(lambda a, b: ["+", a, b], [["*", t, t] for t in axis])]
    return [["/", t, norm] for t in axis], values / np.linalg.norm(values)


def _turned_in_plane(axis: list[Any], name: str, design: Mapping[str, float]) -> list[Any]:
    """A direction in the plane turned by the angle ``name`` (its unit vector towards its normal)."""
    unit, _ = _unit(axis, design)
    return _turned(unit, [["neg", unit[1]], unit[0]], name)


def _turned_in_space(axis: list[Any], name: str, what: str, *, k: int, add: Any, design: Mapping[str, float]
                     ) -> list[Any]:
    """A direction in space turned by two angles, ``name``_1 towards n1 and ``name``_2 towards n2 (:func:`_tilted`)."""
    unit, value = _unit(axis, design)
    across = [0.0, 0.0, 0.0]
    across[int(np.argmin(np.abs(value)))] = 1.0
    first, _ = _unit(_cross(unit, across), design)
    second = _cross(unit, first)
    one = add(f"{name}_1", f"{what} turned towards its first normal", k, "rad")
    two = add(f"{name}_2", f"{what} turned towards its second normal", k, "rad")
    return _turned(_turned(unit, first, one), second, two)


def _parallelogram_tilted(leg: dict[str, Any], k: int, add: Any) -> None:
    """An R_parallelogram's drive axis a with errors of its own (its arm's zero direction z, n = a x z): turned
    about z by e_axis<k>_zero, a' = a cos - n sin, then about the normal of a' and z by e_axis<k>_normal, a'' = a'
    cos + z sin, z' = z cos - a' sin, its arm, rods and parallelogram turned with it: exact rotations, so that the
    axis stays a unit vector at right angles to the zero direction, which the kind's derivation never normalises."""
    a, z = leg["axis"], leg["zero"]
    about_zero = add(f"e_axis{k}_zero", f"leg {k}'s drive axis turned about its arm's zero direction", k, "rad")
    about_normal = add(f"e_axis{k}_normal", f"leg {k}'s drive axis turned towards its arm's zero direction", k, "rad")
    first = _turned(a, [["neg", c] for c in _cross(a, z)], about_zero)
    axis, zero = _turned(first, z, about_normal), _turned(z, [["neg", c] for c in first], about_normal)
    leg["axis"], leg["zero"] = axis, zero
    arm, rods = leg["joints"]
    arm["axes"], arm["link"] = [axis], [["*", leg["arm"], c] for c in zero]
    rods["axes"], rods["link"] = [axis, _cross(zero, axis)], [["*", leg["rod"], c] for c in zero]


class ErrorModel:
    """A machine's error model (module docstring), from its legs in the description vocabulary
    (:meth:`pkm.Mechanism.described_legs`): ``machine`` the expanded machine, ``parameters`` its geometric
    errors and the drives' zero offsets, in the order of E's columns."""

    def __init__(self, mech: Any, attachments: str = "cartesian", axes: bool = False) -> None:
        description = mech.described_legs()
        if description is None:
            raise PkmError(f"mechanism {mech.name} violates: a described machine (pkm.spec), or a hand-derived one "
                           "that gives its legs in the description vocabulary, which pkm expands per leg")
        data, geometric = expanded(description.data, attachments, axes)
        self.nominal, self.attachments, self.axes = mech, attachments, axes
        self.machine = mech.variant(data)
        offsets = [ErrorParameter(f"e_zero{k + 1}", unit, f"the zero offset of leg {k + 1}'s drive: its joint less "
                                  "the joint the drive reads", k + 1)
                   for k, unit in enumerate(mech.actuator_units)]
        self.parameters = (*geometric, *offsets)
        self._geometric = [self.machine.parameter_names().index(e.name) for e in geometric]
        self.function = self._compose()
        self._indices: dict[tuple[float, ...], LocalIndex] = {}

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def design(self, design: Any = None, errors: Any = None) -> np.ndarray:
        """The expanded machine's design vector: the nominal design's values and the geometric errors (by name,
        0 where not given)."""
        names = set(self.machine.parameter_names())
        values = {k: v for k, v in self.nominal.design(design).items() if k in names}
        given = dict(errors or {})
        unknown = sorted(set(given) - set(self.names))
        if unknown:
            raise PkmError(f"errors violate: parameters of the error model ({', '.join(self.names)}); got "
                           f"{', '.join(unknown)}")
        geometric = {p.name: 0.0 for p in self.parameters if not p.name.startswith("e_zero")}
        return self.machine.design_vector({**values, **geometric, **{n: float(v) for n, v in given.items()
                                                                     if n in geometric}})

    def _compose(self) -> ca.Function:
        m = self.machine
        constraint, first = m.functions["constraint"], m.functions["first_order"]
        q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
        h, H_q, H_x = constraint(q, x, d)
        A = ca.horzcat(H_q[:, m.n_act:], H_x)
        B = ca.jacobian(h, d)[:, self._geometric]
        moved = -ca.solve(A, B)[A.size2() - m.n_out:, :]
        J_f = first(q, x, d)[1]
        return ca.Function("error_jacobian", [q, x, d], [ca.horzcat(moved, J_f)], ["q", "x", "design"], ["E"])

    def nominal_function(self) -> ca.Function:
        """E as a function of the nominal machine's joints, pose and design, ``(q, x, design) -> E``: the expanded
        machine's at zero errors, for a local index of the nominal machine (the designer's ``pose_error``)."""
        full, names = self.function, self.nominal.parameter_names()
        q, x = (ca.SX.sym(full.name_in(i), full.size_in(i)) for i in range(2))
        d = ca.SX.sym("design", len(names))
        zero = ca.SX(0)
        expanded_design = ca.vertcat(*[d[names.index(n)] if n in names else zero
                                       for n in self.machine.parameter_names()])
        return ca.Function("pose_error_jacobian", [q, x, d], [full(q, x, expanded_design)], ["q", "x", "design"],
                           ["E"])

    def index(self, tolerances: Any) -> LocalIndex:
        """The linearised worst-case position error under ``tolerances`` (:meth:`widths`) as a local index of the
        nominal machine, ``pose_error`` [m]: the largest over the pose's translational coordinates of
        sum_k |E_ik| t_k, E read from the nominal machine's joints, pose and design (:meth:`nominal_function`), so
        that maps, global indices with exact design gradients and task constraints take it like any other."""
        key = tuple(self.widths(tolerances))
        if key not in self._indices:  # one object per tolerances, so that the graphs built from it are kept
            self._indices[key] = self._index(tolerances)
        return self._indices[key]

    def _index(self, tolerances: Any) -> LocalIndex:
        widths = ca.DM(self.widths(tolerances)).T
        moved = [k for k, unit in enumerate(self.nominal.pose_units) if unit == "m"]

        def rows(E: ca.SX) -> ca.SX:
            return ca.vertcat(*[ca.sum2(ca.fabs(E[i, :]) * widths) for i in moved])

        return LocalIndex(
            "pose_error", "the worst-case pose error over the translation, max_i sum_k |E_ik| t_k, under the "
            f"tolerances {reprlib.repr(tolerances)}", "m", 0.0, np.inf, np.inf, lambda E: ca.mmax(rows(E)),
            self.nominal_function(), ("E",), epigraph_upper=lambda E, t: t - rows(E), dimension=None, raw=True,
        )

    def global_index(self, tolerances: Any, reduce: str = "max") -> GlobalIndex:
        """The region's largest (``reduce`` "max"; or "mean", "rms") worst-case position error under the
        tolerances, a global index to be minimised (:meth:`index`; ``m.global_index(model.global_index(t),
        design, region=...)``)."""
        local = self.index(tolerances)
        return GlobalIndex(f"pose_error_{reduce}", local, f"the region's {reduce} of {local.doc}", reduce, "min")

    def certified_worst_case(self, region: Any, tolerances: Any, design: Any = None, *, mode: str | None = None,
                             gap: float = 0.05, **budget: Any) -> Any:
        """The largest linearised worst-case position error (:meth:`index`) over the region, certified from both
        sides within the relative ``gap``: a pose where it is found, and a bound proved over the whole region by
        branch and prune on its graph's enclosures, or None where the budget (``depth``, ``max_boxes``,
        ``seconds`` of each certification) proves none (:func:`pkm.certify_extreme.certified_extreme`)."""
        from pkm.certify_extreme import certified_extreme

        return certified_extreme(self.nominal, self.index(tolerances), region, design, sense="max", mode=mode,
                                 gap=gap, **budget)

    def widths(self, tolerances: Any) -> np.ndarray:
        """The tolerances as E's columns: a number, every geometric error's in metres (the angles' and the drives'
        zero offsets' 0), or a table by error parameter (0 where not given)."""
        if isinstance(tolerances, int | float) and not isinstance(tolerances, bool):
            if not (np.isfinite(tolerances) and tolerances >= 0):
                raise PkmError(f"tolerances violate: finite and not negative; got {tolerances!r}")
            return np.array([float(tolerances) if p.unit == "m" and not p.name.startswith("e_zero") else 0.0
                             for p in self.parameters])
        return self._widths(tolerances, "tolerances")

    def jacobian(self, pose: Any, design: Any = None, *, mode: str | None = None, errors: Any = None) -> np.ndarray:
        """E = dx/dp (N, n_out, n_params) at the poses (NaN where out of reach), in the working mode."""
        x, single = as_batch(pose, self.nominal.n_out, "pose", finite=False)
        d = self.design(design, errors)
        q = self.machine.inverse_kinematics(x, d, mode=mode, passive=True)
        (E,) = evaluate(self.function, q, x, d)
        return E[0] if single else E

    def deviations(self, deviations: Any) -> np.ndarray:
        """The deviations by name (0 where not given) as E's columns."""
        return self._widths(deviations, "deviations")

    def _widths(self, values: Any, what: str) -> np.ndarray:
        if not isinstance(values, Mapping):
            raise PkmError(f"{what} violate: a table of numbers by error parameter; got {type(values).__name__}")
        given = dict(values)
        unknown = sorted(set(given) - set(self.names))
        if unknown:
            raise PkmError(f"{what} violate: parameters of the error model ({', '.join(self.names)}); got "
                           f"{', '.join(unknown)}")
        if any(isinstance(v, bool) or not isinstance(v, int | float) for v in given.values()):
            raise PkmError(f"{what} violate: numbers")
        widths = np.array([float(given.get(n, 0.0)) for n in self.names])
        if not np.all(np.isfinite(widths) & (widths >= 0)):
            raise PkmError(f"{what} violate: finite and not negative")
        return widths

    def worst_case(self, pose: Any, tolerances: Any, design: Any = None, *, mode: str | None = None) -> np.ndarray:
        """The linearised worst case of each pose coordinate (N, n_out) under |p_k| <= t_k (``tolerances`` by
        name, 0 where not given): sum_k |E_ik| t_k."""
        return np.abs(self.jacobian(pose, design, mode=mode)) @ self._widths(tolerances, "tolerances")

    def rms(self, pose: Any, deviations: Any, design: Any = None, *, mode: str | None = None) -> np.ndarray:
        """The RMS of each pose coordinate (N, n_out) under independent Gaussian errors of the deviations (by
        name): sqrt(sum_k (E_ik s_k)^2)."""
        s = self._widths(deviations, "deviations")
        return np.sqrt(np.sum((self.jacobian(pose, design, mode=mode) * s) ** 2, axis=-1))

    def closed(self, joints: np.ndarray, start: np.ndarray, design: np.ndarray, *, mode: str | None = None
               ) -> np.ndarray:
        """The poses (N, n_out) of the expanded machine at the design (one, or one per row) at the actuated joints
        (N, n_act), its loops closed by Newton's method from the poses ``start`` (their configurations in the
        working mode)."""
        return self._closing(joints, self._configurations(start, design, mode), design)

    def _closing(self, joints: np.ndarray, z: np.ndarray, design: np.ndarray) -> np.ndarray:
        """Newton's method on the loops from z (N, passive joints and pose) at the actuated joints: the poses."""
        m = self.machine
        passive = z.shape[1] - m.n_out
        residual = np.full(len(z), np.inf)
        for _ in range(CLOSURE_STEPS):
            full = np.concatenate([joints, z[:, :passive]], axis=1)
            h, H_q, H_x = evaluate(m.functions["constraint"], full, z[:, passive:], design)
            residual = np.max(np.abs(h[..., 0]), axis=1)
            if np.all(residual < CLOSED):
                break
            A = np.concatenate([H_q[:, :, m.n_act:], H_x], axis=2)
            try:
                z = z - np.linalg.solve(A, h[..., 0][..., None])[..., 0]
            except np.linalg.LinAlgError:  # a singular configuration: its row does not close, and is named below
                break
        bad = np.flatnonzero(~(residual < CLOSED))
        if len(bad):
            raise PkmError(f"joints violate: loops that close from the given poses; rows {bad[:5].tolist()} do not "
                           f"(residual {np.nan_to_num(residual[bad[0]], nan=np.inf):.1e} m)")
        return z[:, passive:]

    def _built(self, base: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Machines built with the errors p (S, n_params) on the expanded design ``base``: their designs (S, n_d)
        and their drives' zero offsets (S, n_act), read as joint errors."""
        n_geometric = len(self._geometric)
        designs = np.repeat(base[None], len(p), axis=0)
        designs[:, self._geometric] += p[:, :n_geometric]
        return designs, p[:, n_geometric:]

    def _configurations(self, x: np.ndarray, base: np.ndarray, mode: str | None) -> np.ndarray:
        """The nominal machine's configurations (N, passive joints and pose) at the poses x, in the working mode."""
        q = self.machine.inverse_kinematics(x, base, mode=mode, passive=True)
        return np.concatenate([q[:, self.machine.n_act:], x], axis=1)

    def _perturbed(self, z: np.ndarray, q: np.ndarray, p: np.ndarray, base: np.ndarray) -> np.ndarray:
        """The pose errors (S, n_out) of S machines with the errors p (S, n_params), each at its nominal
        configuration z (S, passive joints and pose) and that pose's actuated joints q (S, n_act), their loops
        closed from there."""
        designs, offsets = self._built(base, p)
        return self._closing(q + offsets, z, designs) - z[:, z.shape[1] - self.nominal.n_out:]

    def monte_carlo(self, pose: Any, deviations: Any, design: Any = None, *, mode: str | None = None,
                    samples: int = 200, seed: int = 0) -> dict[str, np.ndarray]:
        """The pose errors of ``samples`` machines drawn with independent Gaussian errors (the drives' offsets
        read as joint errors) at the nominal poses' actuated joints, their loops closed (MONTE_CARLO_ROWS machines
        at a time, each a row of one batch, each batch drawn from its own stream of ``seed``: :meth:`squares`):
        the sampled RMS of each pose coordinate (N, n_out) beside the linearised one. :mod:`pkm.accuracy_parallel`
        runs the batches on workers and gives the same numbers."""
        x, _ = as_batch(pose, self.nominal.n_out, "pose")
        squares = sum((self.squares(x, deviations, design, mode=mode, batch=b, samples=samples, seed=seed)
                       for b in range(batches(samples))), np.zeros(x.shape))
        return self.sampled(x, squares, deviations, design, mode=mode, samples=samples)

    def squares(self, x: np.ndarray, deviations: Any, design: Any = None, *, mode: str | None = None, batch: int,
                samples: int, seed: int) -> np.ndarray:
        """The summed squared pose errors (N, n_out) of batch ``batch`` of a Monte Carlo run of ``samples``
        machines per pose: rows ``batch * MONTE_CARLO_ROWS`` on, drawn from the stream (seed, pose, batch)."""
        s = self._widths(deviations, "deviations")
        base = self.design(design)
        q = self.nominal.inverse_kinematics(x, design, mode=mode)
        z = self._configurations(x, base, mode)
        rows = min(MONTE_CARLO_ROWS, samples - batch * MONTE_CARLO_ROWS)
        out = np.zeros(x.shape)
        for k in range(len(x)):
            p = np.random.default_rng([seed, k, batch]).normal(size=(rows, len(s))) * s
            at = np.repeat(z[k : k + 1], rows, axis=0), np.repeat(q[k : k + 1], rows, axis=0)
            out[k] = np.sum(self._perturbed(*at, p, base) ** 2, axis=0)
        return out

    def sampled(self, x: np.ndarray, squares: np.ndarray, deviations: Any, design: Any = None, *,
                mode: str | None = None, samples: int) -> dict[str, np.ndarray]:
        """A Monte Carlo run's result from its summed squares: the sampled RMS beside the linearised one."""
        return {"sampled": np.sqrt(squares / samples), "linearised": self.rms(x, deviations, design, mode=mode)}

    def worst_case_checked(self, pose: Any, tolerances: Any, design: Any = None, *, mode: str | None = None
                           ) -> dict[str, np.ndarray]:
        """The linearised worst case (N, n_out) beside the error of the machine built at its worst vertex, each
        coordinate's: p_k = t_k sign(E_ik), the loops closed at the nominal pose's actuated joints."""
        x, _ = as_batch(pose, self.nominal.n_out, "pose")
        t = self.widths(tolerances)
        base = self.design(design)
        E = self.jacobian(x, design, mode=mode)
        q = self.nominal.inverse_kinematics(x, design, mode=mode)
        n = self.nominal.n_out  # a vertex per pose and coordinate, all in one batch
        errors = self._perturbed(np.repeat(self._configurations(x, base, mode), n, axis=0), np.repeat(q, n, axis=0),
                                 (np.sign(E) * t).reshape(-1, len(t)), base)
        return {"linearised": np.abs(E) @ t, "built": np.abs(np.diagonal(errors.reshape(len(x), n, n), axis1=1,
                                                                          axis2=2))}


def batches(samples: int) -> int:
    """The batches of a Monte Carlo run of ``samples`` machines per pose (MONTE_CARLO_ROWS each)."""
    return -(-samples // MONTE_CARLO_ROWS)


def error_model(mech: Any, attachments: str = "cartesian", axes: bool = False) -> ErrorModel:
    """The mechanism's error model (:class:`ErrorModel`): each attachment's errors along x, y and z, or with
    ``attachments="polar"``, where it is placed on a circle, of the circle's radius and its angle on it; with
    ``axes``, the joints' axes' tilts as well (:func:`expanded`: an R_parallelogram's drive axis, a PRR's slide, a
    chain's joints' axes)."""
    return ErrorModel(mech, attachments, axes)


@dataclass
class Tolerances:
    """The widest tolerances within the budget: each by name, its share of the budget where the budget binds
    (``shares``: |E_ik| t_k / budget at the binding row of the largest sum), and the binding poses and their
    coordinates."""

    tolerances: dict[str, float]
    units: dict[str, str]
    budget: float
    shares: dict[str, float]
    binding: list[dict[str, Any]]
    status: str


def widest_tolerances(model: ErrorModel, poses: Any, budget: float, design: Any = None, *, mode: str | None = None,
                      weights: Any = None, fixed: Any = None) -> Tolerances:
    """The tolerances maximising sum_k w_k log t_k (``weights`` by name, 1 by default; a part's cost per
    halving) with every translational coordinate's linearised worst case at every pose at most ``budget`` [m];
    ``fixed`` tolerances (by name) held at their values. IPOPT on log t, the constraints linear in t."""
    if isinstance(budget, bool) or not (isinstance(budget, int | float) and np.isfinite(budget) and budget > 0):
        raise PkmError(f"budget violates: a positive length [m]; got {budget!r}")
    x, _ = as_batch(poses, model.nominal.n_out, "poses")
    E = model.jacobian(x, design, mode=mode)
    moved = [i for i, unit in enumerate(model.nominal.pose_units) if unit == "m"]
    rows = np.abs(E[:, moved, :]).reshape(-1, len(model.names))
    if not np.all(np.isfinite(rows)):
        raise PkmError("poses violate: every pose in reach in the working mode")
    w = model._widths(weights, "weights") if weights is not None else np.ones(len(model.names))
    held = model._widths(fixed or {}, "fixed")
    moving = np.any(rows > 0, axis=0)  # a parameter that moves no translation has no bound: left unbounded
    free = np.array([n not in (fixed or {}) for n in model.names]) & moving
    held[~moving & ~np.isin(model.names, list(fixed or {}))] = np.inf
    if not free.any():
        raise PkmError("fixed violates: at least one tolerance left to choose that moves the platform")
    y = ca.SX.sym("y", int(free.sum()))
    t = ca.SX(ca.DM(np.where(moving, held, 0.0)))
    for j, k in enumerate(np.flatnonzero(free)):
        t[int(k)] = ca.exp(y[j])
    solver = ca.nlpsol("tolerances", "ipopt", {"x": y, "f": -ca.dot(ca.DM(w[free]), y),
                                                "g": ca.DM(rows / budget) @ t},
                       {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-12,
                                                       "constr_viol_tol": 1e-12, "bound_relax_factor": 0.0}})
    reach = np.log(budget / np.maximum(rows[:, free], 1e-300).max(axis=0))  # each alone at the budget
    solution = solver(x0=reach - np.log(max(1, int(free.sum()))), ubx=reach, ubg=1.0)
    widths = held.copy()
    widths[free] = np.exp(np.asarray(solution["x"]).ravel())
    sums = rows[:, moving] @ widths[moving]
    binding = np.flatnonzero(sums >= budget * (1 - 1e-6))  # at the budget, to the solver's tolerance
    worst = int(np.argmax(sums))
    return Tolerances(dict(zip(model.names, widths.tolist(), strict=True)),
                      {p.name: p.unit for p in model.parameters}, float(budget),
                      dict(zip(model.names, np.where(moving, rows[worst] * np.where(moving, widths, 0) / budget,
                                                     0.0).tolist(), strict=True)),
                      [{"pose": x[r // len(moved)].tolist(),
                        "coordinate": model.nominal.pose_names[moved[r % len(moved)]], "worst_case": float(sums[r])}
                       for r in binding],
                      solver.stats()["return_status"])


@dataclass
class Calibration:
    """Identified errors by name with their standard deviations, the residual RMS before and after, and the
    identifiability: the stacked Jacobian's rank of its columns, singular values, the parameters (or
    combinations) it cannot tell apart (``unidentifiable``: each null direction's largest components) and those
    it tells apart poorly (``weakly_identified``: the directions of singular values below WEAK of the largest,
    weakest first, each with its relative singular value under ``"ratio"``)."""

    errors: dict[str, float]
    deviations: dict[str, float]
    rms_before: float
    rms_after: float
    rank: int
    singular_values: list[float]
    unidentifiable: list[dict[str, float]]
    weakly_identified: list[dict[str, float]]
    iterations: int


RANK = 1e-8  # a singular value below this (relative to the largest) is a direction the data do not identify
WEAK = 1e-2  # one below this identifies its direction poorly: the measurements' noise grows 100x along it


def calibrate(model: ErrorModel, joints: Any, poses: Any, design: Any = None, *, mode: str | None = None,
              bounds: Any = None, regularisation: float = 1e-12, iterations: int = 10,
              parameters: Any = None) -> Calibration:
    """The errors that make the expanded machine at the read actuated joints (M, n_act) meet the measured poses
    (M, n_out; NaN where a coordinate is not measured: a probe's one coordinate), by Gauss-Newton steps on the
    closed loops, each a bounded least-squares problem (``bounds`` by name: |p_k| <= b_k; SPAN by default)
    regularised by ``regularisation`` |p|^2 (a relative weight of the data's scale); ``parameters`` the names
    identified (every one by default), the others held at 0."""
    q, _ = as_batch(joints, model.nominal.n_act, "joints")
    measured = np.asarray(poses, dtype=float).reshape(len(q), model.nominal.n_out)
    seen = np.isfinite(measured)
    if not seen.any(axis=1).all():
        raise PkmError("poses violate: at least one measured coordinate per pose")
    chosen = _chosen(model, parameters)
    limit = np.full(len(model.names), SPAN)
    if bounds is not None:
        given = dict(bounds)
        limit = np.where([n in given for n in model.names], model._widths(given, "bounds"), limit)
    base = model.design(design)
    start = np.where(seen, measured, _nearest_assembly(model.nominal, q, measured, design))
    p = np.zeros(len(model.names))

    def closed(p: np.ndarray) -> np.ndarray:
        (d,), (offsets,) = model._built(base, p[None])
        return model.closed(q + offsets, start, d, mode=mode)

    x = closed(p)
    before = float(np.sqrt(np.mean((measured - x)[seen] ** 2)))
    done = 0
    names = [model.names[k] for k in chosen]
    for _ in range(iterations):
        E = model.jacobian(x, design, mode=mode, errors=dict(zip(model.names, p, strict=True)))[seen][:, chosen]
        step = _bounded_step(E, (measured - x)[seen], p[chosen], limit[chosen],
                             regularisation * max(1.0, float(np.sum(E**2))))
        p[chosen], done = p[chosen] + step, done + 1
        x = closed(p)
        if np.max(np.abs(step)) < 1e-12:
            break
    E = model.jacobian(x, design, mode=mode, errors=dict(zip(model.names, p, strict=True)))[seen][:, chosen]
    r = (measured - x)[seen]
    _, sv, Vt = np.linalg.svd(E, full_matrices=False)
    rank = int(np.sum(sv > RANK * sv[0])) if len(sv) else 0
    variance = float(r @ r) / max(1, len(r) - rank)
    inverse = np.linalg.pinv(E.T @ E, rcond=RANK**2)
    null = [_direction(names, v) for v in Vt[rank:]]
    weak = [{**_direction(names, Vt[k]), "ratio": float(sv[k] / sv[0])} for k in range(rank - 1, -1, -1)
            if sv[k] < WEAK * sv[0]]
    deviations = np.sqrt(np.maximum(np.diag(inverse) * variance, 0))
    return Calibration(dict(zip(names, p[chosen].tolist(), strict=True)),
                       dict(zip(names, deviations.tolist(), strict=True)), before, float(np.sqrt(np.mean(r**2))),
                       rank, sv.tolist(), null, weak, done)


def _direction(names: list[str], v: np.ndarray) -> dict[str, float]:
    """A direction in the parameters by its largest components (at most 4, those of at least a tenth)."""
    order = [k for k in np.argsort(-np.abs(v))[:4] if abs(v[k]) >= 0.1]
    return {names[k]: float(v[k]) for k in order}


@dataclass
class Selection:
    """The measurement poses chosen from the candidates (their rows, in the order chosen), the log-determinant of
    the chosen rows' information matrix E^T E and its condition number, in the parameters identified."""

    rows: list[int]
    log_determinant: float
    condition: float


def select_poses(model: ErrorModel, candidates: Any, count: int, design: Any = None, *, mode: str | None = None,
                 parameters: Any = None, measured: Any = None) -> Selection:
    """The ``count`` candidate poses whose measurements best identify the parameters (all by default): greedy
    D-optimal design, each step the candidate that most increases det(E^T E + eps I) (its rows E_c: the
    coordinates ``measured``, by name, all by default; a probe measures one), then exchanges of a chosen pose for
    an unchosen one while one raises it."""
    x, _ = as_batch(candidates, model.nominal.n_out, "candidates")
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= len(x):
        raise PkmError(f"count violates: an integer from 1 to the {len(x)} candidates; got {count!r}")
    names = model.nominal.pose_names
    rows = [names.index(n) for n in (names if measured is None else measured) if n in names]
    if measured is not None and (isinstance(measured, str) or len(rows) != len(measured) or not rows):
        raise PkmError(f"measured violates: a list of the pose's coordinates ({', '.join(names)}); got {measured!r}")
    E = model.jacobian(x, design, mode=mode)[:, rows][:, :, _chosen(model, parameters)]
    usable = np.flatnonzero(np.all(np.isfinite(E), axis=(1, 2)))
    if len(usable) < count:
        raise PkmError(f"candidates violate: {count} poses within the machine's reach; {len(usable)} are")
    information = np.einsum("nri,nrj->nij", E, E)
    eps = 1e-12 * max(float(np.trace(information.sum(axis=0))), 1e-300)

    ridge = eps * np.eye(E.shape[2])

    def score(chosen: list[int]) -> float:
        return float(np.linalg.slogdet(information[chosen].sum(axis=0) + ridge)[1])

    def scores(others: list[int], pool: np.ndarray) -> np.ndarray:
        """The score of ``others`` with each candidate of ``pool`` added, in one batch."""
        return np.linalg.slogdet(information[others].sum(axis=0) + information[pool] + ridge)[1]

    chosen: list[int] = []
    for _ in range(count):
        pool = np.array([c for c in usable if c not in chosen], dtype=int)
        chosen.append(int(pool[np.argmax(scores(chosen, pool))]))
    improved = True
    while improved:
        improved = False
        best = score(chosen)
        for k in range(len(chosen)):
            pool = np.array([c for c in usable if c not in chosen], dtype=int)
            for c, value in zip(pool, scores(chosen[:k] + chosen[k + 1:], pool), strict=True):
                if value > best + 1e-9:  # each candidate in turn against the best so far, as one by one
                    chosen[k], best, improved = int(c), float(value), True
    sv = np.linalg.svd(information[chosen].sum(axis=0), compute_uv=False)
    return Selection([int(c) for c in chosen], score(chosen), float(sv[0] / sv[-1]) if sv[-1] > 0 else np.inf)


def _chosen(model: ErrorModel, parameters: Any) -> np.ndarray:
    """The columns of the parameters a calibration identifies (every one where None)."""
    if parameters is None:
        return np.arange(len(model.names))
    if isinstance(parameters, str) or not all(isinstance(n, str) for n in parameters) or not len(parameters):
        raise PkmError(f"parameters violate: a list of the error model's parameters; got {parameters!r}")
    unknown = sorted(set(parameters) - set(model.names))
    if unknown:
        raise PkmError(f"parameters violate: parameters of the error model ({', '.join(model.names)}); got "
                       f"{', '.join(unknown)}")
    return np.array([k for k, n in enumerate(model.names) if n in set(parameters)])


def _nearest_assembly(mech: Any, joints: np.ndarray, measured: np.ndarray, design: Any) -> np.ndarray:
    """Each row's assembly of the nominal machine at its joints nearest the measured coordinates
    (:meth:`pkm.Mechanism.every_assembly`), where a coordinate is not measured the loops' start."""
    found = mech.every_assembly(joints, design)
    gap = np.where(np.isfinite(measured)[:, None, :], found.poses - measured[:, None, :], 0.0)
    distance = np.where(np.all(np.isfinite(found.poses), axis=2), np.sum(gap**2, axis=2), np.inf)
    none = np.flatnonzero(~np.isfinite(distance).any(axis=1))
    if len(none):
        raise PkmError(f"joints violate: joints at which the nominal machine assembles; rows {none[:5].tolist()} do "
                       "not")
    return found.poses[np.arange(len(joints)), np.argmin(distance, axis=1)]


def _bounded_step(E: np.ndarray, r: np.ndarray, p: np.ndarray, limit: np.ndarray, weight: float) -> np.ndarray:
    """The step s minimising |E s - r|^2 + weight |p + s|^2 with |p + s| <= limit: the least-squares step of the
    stacked system [E; sqrt(weight) I] s = [r; -sqrt(weight) p] where it keeps within the bounds (the problem is
    convex: a minimiser inside them is theirs too), else IPOPT's."""
    root = np.sqrt(weight)
    free = np.linalg.lstsq(np.vstack([E, root * np.eye(len(p))]), np.concatenate([r, -root * p]), rcond=None)[0]
    if np.all(np.abs(p + free) <= limit):
        return free
    step = ca.SX.sym("step", len(p))
    residual = ca.DM(E) @ step - ca.DM(r)
    solver = ca.nlpsol("calibration", "ipopt", {"x": step, "f": ca.sumsqr(residual) + weight * ca.sumsqr(p + step)},
                       {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes", "tol": 1e-14}})
    solution = solver(x0=np.zeros(len(p)), lbx=-limit - p, ubx=limit - p)
    return np.asarray(solution["x"]).ravel()
