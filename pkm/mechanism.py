"""The public Mechanism (DESIGN.md section 7): what every model of pkm offers.

A mechanism is a subclass that declares data: its parameters and validity conditions, its working and
assembly modes, the names and units of its pose and actuators, its regions, design spaces and its
forward-kinematics method. Everything it computes comes from its generated functions (see
:mod:`pkm.kinematics` for the port convention) through the generic layers: local indices through the
fused pipeline (:mod:`pkm.regions.pipeline`), global indices over sampled or parametrised regions
(:mod:`pkm.regions`), and the dynamics (:mod:`pkm.dynamics`), to which the facade delegates.
"""

from __future__ import annotations

import importlib
import itertools
import types
from collections.abc import Callable, Mapping
from functools import cached_property, lru_cache
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from pkm import regions, registry
from pkm.batch import evaluate, evaluate_finite
from pkm.design import Condition, Design, Parameter, design_mapping, make_design
from pkm.design_space import DesignSpace
from pkm.errors import DesignError, PkmError, PoseError, SingularityError, UnknownNameError, check_name
from pkm.kinematics import (
    Branch,
    ClosedForm,
    DesignLike,
    ForwardKinematics,
    FunctionTable,
    GeneratedFunctions,
    as_batch,
    find_branch,
    require_finite,
    solve_joints,
    unbatch,
)

if TYPE_CHECKING:
    from pkm.indices import GlobalIndex, LocalIndex

SINGULAR_CONDITION = 1e12
ONE_SIDED_STEP = 1e-7  # relative step to the side of a design where a one-sided derivative is taken
ONE_SIDED_AGREEMENT = 1e-6  # relative: the value on that side, extrapolated back, equals the design's to this
SINGULAR_SAMPLES = 64  # cells per axis of the grid of a region's poses searched for a singularity
SINGULARITY_TYPES = ("type I", "type II")


class _Delegate:
    """A method that is the function of the same name in ``module`` called as ``function(self, ...)``:
    the facade keeps the function's docstring and signature instead of copying them, and the module is
    imported at the method's first use, not with every mechanism."""

    def __init__(self, module: str) -> None:
        self.module = module

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    @cached_property
    def function(self) -> Callable[..., Any]:
        return getattr(importlib.import_module(self.module), self.name)

    def __get__(self, instance: Any, owner: type | None = None) -> Callable[..., Any]:
        if instance is None:
            return self.function
        return types.MethodType(self.function, instance)


class Mechanism:
    """Base class of pkm's mechanisms; subclasses set the class attributes.

    ``regions`` maps a region name to a parametrised region (:mod:`pkm.regions.shapes`);
    ``forward`` is the forward-kinematics method (:mod:`pkm.kinematics`); a mechanism whose pose or
    actuators mix metres and radians sets ``characteristic_length``, a function (plain or static) of the
    design values by parameter name (numpy or CasADi) giving the length [m] that turns an angle into an
    arc length. A mechanism with stated limits (strokes, joint ranges, interference) names in ``limits``
    its function ``(q, x, design) -> margins`` (>= 0 where each holds, named by ``limit_names``) and puts
    them in its inverse
    kinematics' reach (:func:`pkm.kinematics.within_limits`): its reach masks, its sampled workspace and the
    indices over it respect them, and the region ``"assembled"`` is the workspace without them.
    """

    name: str = ""
    doc: str = ""
    parameters: tuple[Parameter, ...] = ()
    conditions: tuple[Condition, ...] = ()
    working_modes: tuple[Branch, ...] = ()
    assembly_modes: tuple[Branch, ...] = ()
    pose_names: tuple[str, ...] = ()
    pose_units: tuple[str, ...] = ()
    actuator_names: tuple[str, ...] = ()
    actuator_units: tuple[str, ...] = ()
    design_spaces: ClassVar[dict[str, DesignSpace]] = {}
    regions: ClassVar[dict[str, Any]] = {}
    skeleton_legs: ClassVar[tuple[int, ...]] = ()  # joints per leg of the generated ``skeleton`` (for drawing)
    distinct_modes: ClassVar[dict[str, tuple[str, ...]]] = {}
    forward: ForwardKinematics = ClosedForm()
    characteristic_length: ClassVar[Callable[[Mapping[str, Any]], Any] | None] = None
    limits: ClassVar[str | None] = None
    limit_names: tuple[str, ...] = ()
    structure: ClassVar[Callable[..., Any] | None] = None  # (mechanism, design, pose, mode) -> its links and joints

    @cached_property
    def functions(self) -> FunctionTable:
        """The generated CasADi functions of this mechanism, by name, and those it composes from them
        (:meth:`composed`)."""
        return GeneratedFunctions(self.name, parameters=self.parameter_names(), pose=self.pose_names,
                                  actuators=self.actuator_names, extra=self.composed)

    def composed(self, _generated: Mapping[str, Any]) -> Mapping[str, Any]:
        """The functions this mechanism composes in CasADi from its generated ones (what sympy would render
        poorly: a segment distance, a 6 x 6 solve), by name; none by default."""
        return {}

    def parameter_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    @property
    def modes(self) -> tuple[str, ...]:
        """Names of the working modes (inverse-kinematic branches)."""
        return tuple(b.name for b in self.working_modes)

    @property
    def assemblies(self) -> tuple[str, ...]:
        """Names of the assembly modes (forward-kinematic branches)."""
        return tuple(b.name for b in self.assembly_modes)

    @property
    def n_act(self) -> int:
        return len(self.actuator_names)

    @property
    def n_out(self) -> int:
        return len(self.pose_names)

    def region_names(self) -> tuple[str, ...]:
        return ("reachable", *(("assembled",) if self.limits else ()), *self.regions)

    def region(self, name: str | Any) -> Any:
        """The parametrised region ``name``, or the sampled workspace for ``"reachable"`` (within the stated
        limits) and ``"assembled"`` (wherever the mechanism assembles, for a mechanism with limits); a region
        given as one (a task's, :func:`pkm.synthesis.designer.task_region`) as it is."""
        if hasattr(name, "quadrature"):
            return name
        if check_name(f"{self.name} region", name, self.region_names()) == "reachable":
            return regions.SampledWorkspace()
        if name == "assembled" and self.limits:
            return regions.ASSEMBLED_WORKSPACE
        if name not in self.regions:
            raise UnknownNameError(f"{self.name} region", name, self.region_names())
        return self.regions[name]

    def described_legs(self) -> Any:
        """The machine's legs in the description vocabulary (a :class:`pkm.spec.schema.Description`), where it has
        them: a described machine's own description, or a hand-derived machine's legs that it gives; its error
        model expands them per leg (:mod:`pkm.accuracy`) and builds them with ``variant``. None otherwise."""
        return getattr(self, "description", None)

    def linkage(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> list[np.ndarray]:
        """The joints' points of each leg at one pose (base joint, the leg's joints, platform joint), for
        drawing, from the generated ``skeleton`` where the mechanism has one (NaN where the pose is out of
        reach), else from its structure (:func:`pkm.export.linkage`, points in 3-D; empty out of reach), else
        an empty list."""
        if "skeleton" not in self.functions or not self.skeleton_legs:
            if self.structure is None:
                return []
            return importlib.import_module("pkm.export").linkage(self, pose, design, mode=mode)
        x = np.asarray(pose, dtype=float).ravel()
        d = self.design_vector(design)
        q = self.inverse_kinematics(x, d, mode=mode, passive=True)
        (points,) = evaluate(self.functions["skeleton"], q, x, d)
        points = points[0]
        bounds = np.cumsum([0, *self.skeleton_legs])
        return [points[a:b] for a, b in itertools.pairwise(bounds)]

    def region_placement(self, name: str | Any, design: DesignLike = None) -> dict[str, Any]:
        """Where the parametrised region ``name`` (or a region given as one) lies at a design: its shape, centre
        and size (a disc's or cylinder's radius first; half extents otherwise) in the coordinates it spans (the
        pose's, or those a mapped region names), SI."""
        where = self.region(name)
        name = regions.region_name(where)
        inner = getattr(where, "inner", where)
        if isinstance(where, regions.SampledWorkspace) or not hasattr(inner, "placement"):
            raise PkmError(f"region {name} of {self.name} violates: a placed shape (a disc, rectangle, box or "
                           "cylinder) to have a centre and a size")
        centre, size = (np.asarray(v, dtype=float).ravel() for v in inner.placement(self.functions,
                                                                                     self.design_vector(design)))
        return {"region": name, "shape": type(inner).__name__.lower(), "centre": centre.tolist(),
                "size": size.tolist(), "mapped": inner is not where, "doc": where.doc}

    def design(self, values: DesignLike | Design = None, *, partial: bool = False) -> Design:
        """Validate a design: a mapping of parameter values, a sequence in parameter order, or None
        for the defaults."""
        return make_design(self.parameters, self.conditions, design_mapping(self.parameters, values), partial=partial)

    def design_vector(self, design: DesignLike | Design) -> np.ndarray:
        """The validated design as a vector in parameter order. A mapping of names to numbers is validated
        once per distinct value (batch methods take the same design call after call)."""
        if isinstance(design, Design):
            if tuple(design) != self.parameter_names():
                raise DesignError(f"design {design!r} violates: a design of the {self.name}, whose parameters are "
                                  f"{', '.join(self.parameter_names())}")
            return design.vector()
        if isinstance(design, dict) and all(type(v) in (float, int) for v in design.values()):
            return self._validated_vector(tuple(design.items())).copy()
        return self.design(design).vector()

    @cached_property
    def _validated_vector(self) -> Any:
        @lru_cache(maxsize=64)
        def validated(items: tuple[tuple[str, float], ...]) -> np.ndarray:
            return self.design(dict(items)).vector()

        return validated

    def design_dict(self, vector: np.ndarray) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.parameters, vector, strict=True)}

    def working_mode(self, mode: str | None) -> Branch:
        """The working mode by name or paper alias; the first one by default."""
        return find_branch(mode, self.working_modes, f"{self.name} working mode")

    def assembly_mode(self, assembly: str | None) -> Branch:
        return find_branch(assembly, self.assembly_modes, f"{self.name} assembly mode")

    def reachable(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, limits: bool = True
    ) -> np.ndarray:
        """Boolean mask (N,) of the poses the working mode reaches within the mechanism's stated limits
        (strokes, joint ranges, interference: :attr:`limits`), or without ``limits`` where it assembles."""
        joints = solve_joints(self, pose, design, mode, limits=limits)
        return joints.unbatch(joints.reachable)

    def limit_margins(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None
    ) -> dict[str, np.ndarray]:
        """The margins of the mechanism's stated limits (:attr:`limits`) by name, each (N,) or a float, >= 0
        where the limit holds, wherever the mechanism assembles (NaN elsewhere); empty without limits."""
        if not self.limits:
            return {}
        joints = solve_joints(self, pose, design, mode, limits=False)
        (margins,) = evaluate(self.functions[self.limits], joints.q, joints.x, joints.design)
        return {name: joints.unbatch(margins[:, k, 0]) for k, name in enumerate(self.limit_names)}

    def inverse_kinematics(
        self,
        pose: Any,
        design: DesignLike = None,
        *,
        mode: str | None = None,
        passive: bool = False,
        strict: bool = False,
        limits: bool = True,
    ) -> np.ndarray:
        """Actuated joints (N, n_act) of the poses (N, n_out) in a working mode; NaN where out of reach:
        where the mechanism does not assemble or violates a stated limit (:attr:`limits`), or without
        ``limits`` only where it does not assemble.

        With ``passive`` all joints (actuated first) are returned; with ``strict`` an unreachable pose
        raises :class:`PoseError`.
        """
        joints = solve_joints(self, pose, design, mode, strict=strict, actuated=not passive, limits=limits)
        return joints.unbatch(joints.q)

    def forward_kinematics(
        self,
        q: Any,
        design: DesignLike = None,
        *,
        assembly: str | None = None,
        passive: bool = False,
        strict: bool = False,
    ) -> np.ndarray:
        """Poses (N, n_out) from actuated joints (N, n_act) in an assembly mode; NaN where the loops
        cannot be closed in it. With ``passive`` all joints (N, n_q) are returned instead."""
        qa, single = as_batch(q, self.n_act, "actuated joints")
        d = self.design_vector(design)
        x, q_all, ok = self.forward.solve(self.functions, qa, self.assembly_mode(assembly), d, joints=passive)
        closed = ok.all()
        if strict and not closed:
            bad = int(np.flatnonzero(~ok)[0])
            raise PoseError(f"actuated joints {qa[bad].tolist()} cannot be assembled")
        out = q_all if passive else x  # fresh arrays of this call, masked in place
        if not closed:
            out[~ok] = np.nan
        return unbatch(out, single)

    def _first_order(self, pose: Any, design: DesignLike, mode: str | None, names: tuple[str, ...]) -> list[Any]:
        """Outputs of the first order at poses by name (NaN where the mechanism does not assemble: the
        kinematics holds beyond the stated limits), in one compiled pass of the fused pipeline, each as
        its input was batched."""
        x, single = as_batch(pose, self.n_out, "pose", finite=False)
        fused = regions.first_order_outputs(self, names)
        (_, *outputs), finite = evaluate_finite(fused, x, np.array(self.working_mode(mode).signs),
                                                self.design_vector(design))
        if not finite:
            require_finite(x, "pose")
        return [unbatch(value, single) for value in outputs]

    def _check_singular(self, joints: Any, kind: str) -> None:
        """Raise SingularityError where the loop equations cannot be solved for J (type I) or J_f (type II)."""
        _, H_q, H_x = evaluate(self.functions["constraint"], joints.q, joints.x, joints.design)
        if kind == "type I":
            matrix, what = H_q, "J is unbounded at a serial (type I) singularity"
        else:
            n_p = H_q.shape[2] - self.n_act
            matrix = np.concatenate([H_q[:, :, self.n_act :][:, :, :n_p], H_x], axis=2)
            what = "J_f is unbounded at a parallel (type II) singularity"
        with np.errstate(divide="ignore", invalid="ignore"):
            condition = np.linalg.cond(matrix)
        bad = ~np.isfinite(condition) | (condition > SINGULAR_CONDITION)
        if bad.any():
            raise SingularityError(f"{what}: pose {joints.x[int(np.flatnonzero(bad)[0])].tolist()}")

    def jacobian(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, strict: bool = False
    ) -> np.ndarray:
        """J (N, n_act, n_out) with q_a_dot = J x_dot; unbounded entries at serial singularities.

        With ``strict`` an unreachable pose raises :class:`PoseError` and a serial singularity (the
        condition number of dh/dq above 1e12) raises :class:`SingularityError`.
        """
        if strict:
            self._check_singular(solve_joints(self, pose, design, mode, strict=True), "type I")
        return self._first_order(pose, design, mode, ("J",))[0]

    def forward_jacobian(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, strict: bool = False
    ) -> np.ndarray:
        """J_f (N, n_out, n_act) with x_dot = J_f q_a_dot, the inverse of :meth:`jacobian`.

        With ``strict`` a parallel singularity raises :class:`SingularityError`.
        """
        if strict:
            self._check_singular(solve_joints(self, pose, design, mode, strict=True), "type II")
        return self._first_order(pose, design, mode, ("J_f",))[0]

    def psi(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> np.ndarray:
        """Psi (N, n_joints, n_act): all joint rates from the actuated rates."""
        return self._first_order(pose, design, mode, ("psi",))[0]

    def singularity(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> dict[str, np.ndarray]:
        """Type I and type II determinants (zero at serial and parallel singularities)."""
        names = ("det_type1", "det_type2")
        values = self._first_order(pose, design, mode, names)
        return {k: v[..., 0, 0] for k, v in zip(names, values, strict=True)}

    def _singularity_margins(self, pose: Any, design: DesignLike, mode: str | None) -> np.ndarray:
        """The type I and type II singularity margins at each pose, (N, 2)."""
        return np.stack([np.atleast_1d(self.local_index(f"singularity_margin_type{k}", pose, design, mode=mode))
                         for k in (1, 2)], axis=-1)

    def singular_types(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> list[list[str]]:
        """Per pose, the singularities it is at: ``"type I"`` and ``"type II"`` where that margin
        (``singularity_margin_type1``, ``_type2``: normalised, in [0, 1]) is below
        :data:`pkm.indices.local.SINGULAR`; none where the pose is out of reach."""
        from pkm.indices.local import SINGULAR

        return [[name for name, m in zip(SINGULARITY_TYPES, row, strict=True) if m < SINGULAR]
                for row in self._singularity_margins(pose, design, mode)]

    def singularity_note(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> str:
        """Empty where the pose (one) is not singular in the working mode, else which singularity and its
        margin, in words."""
        from pkm.indices.local import SINGULAR

        (row,) = self._singularity_margins(np.atleast_2d(pose), design, mode)
        singular = [(k, name, m) for k, (name, m) in enumerate(zip(SINGULARITY_TYPES, row, strict=True), 1)
                    if m < SINGULAR]
        if not singular:
            return ""
        margins = ", ".join(f"singularity_margin_type{k} = {m:.2g}" for k, _, m in singular)
        return (f"pose {np.ravel(pose).tolist()} is a {' and '.join(name for _, name, _ in singular)} singularity "
                f"of the {self.name} in mode {self.working_mode(mode).name} ({margins} < {SINGULAR:g})")

    def _has(self, spec: LocalIndex) -> bool:
        """Whether this mechanism offers the local index: its source function has every output the index
        reads, none of them empty (a machine without stated limits has no workspace margin)."""
        fn = self.functions.get(spec.source) if isinstance(spec.source, str) else spec.source  # its own function
        fits = spec.dimension is None or self.n_out <= spec.dimension
        return (fits and fn is not None and set(spec.arguments) <= set(fn.name_out())
                and all(fn.numel_out(fn.index_out(a)) > 0 for a in spec.arguments))

    def local_spec(self, name: str | LocalIndex) -> LocalIndex:
        """The local index by name (or one given as it is, such as an error model's ``pose_error``), if this
        mechanism has the function it needs."""
        spec = name if hasattr(name, "arguments") else registry.local_index(name)
        if not self._has(spec):
            source = spec.source if isinstance(spec.source, str) else spec.source.name()
            raise PkmError(
                f"local index {spec.name} needs the {', '.join(spec.arguments)} of a {source} model, "
                f"which {self.name} does not have"
            )
        return spec

    @cached_property
    def trajectory_quantities(self) -> dict[str, GlobalIndex]:
        """The quantities along a trajectory this mechanism offers, by name (:mod:`pkm.dynamics.quantities`: the
        peak and RMS actuator effort, the energy with and without regeneration and the peak power where it has
        dynamics; the peak actuator speed, the positioning error from the default encoder resolutions and the
        velocity amplification): global indices over a trajectory region (:class:`pkm.regions.TrajectoryRegion`)."""
        return importlib.import_module("pkm.dynamics.quantities").trajectory_indices(self)

    def global_spec(self, name: str | GlobalIndex) -> GlobalIndex:
        """The global index by name, if this mechanism can evaluate its local index: a registered one, or one of
        its :attr:`trajectory_quantities`; or one given as it is (an error model's ``pose_error_max``)."""
        if hasattr(name, "reduce"):
            self.local_spec(name.local)
            if name.per is not None:
                self.functions.require(name.per, f"the global index {name.name}")
            return name
        try:
            spec = registry.global_index(name)
        except UnknownNameError:
            if isinstance(name, str) and name in self.trajectory_quantities:
                return self.trajectory_quantities[name]
            raise
        self.local_spec(spec.local.name)
        if spec.per is not None:
            self.functions.require(spec.per, f"the global index {spec.name}")
        return spec

    def index_unit(self, name: Any) -> str:
        """The unit of a local or global index of this mechanism (by name, or the index itself): its template
        filled with the unit of the
        pose coordinates and of the actuators (angles count as lengths where a mechanism's coordinates mix
        them: indices are taken in arc lengths, :mod:`pkm.regions.pipeline`)."""
        if hasattr(name, "unit"):
            spec = name
        else:
            is_global = isinstance(name, str) and (name in {i.name for i in registry.global_indices()}
                                                   or name in self.trajectory_quantities)
            spec = self.global_spec(name) if is_global else self.local_spec(name)
        return spec.unit.format(pose=_coordinate_unit(self.pose_units), actuator=_coordinate_unit(self.actuator_units),
                                n=self.n_out, volume=_product_unit(self.pose_units))

    def local_indices(self) -> tuple[str, ...]:
        """Names of the local indices this mechanism can evaluate."""
        return tuple(i.name for i in registry.local_indices() if self._has(i))

    def global_indices(self) -> tuple[str, ...]:
        """Names of the global indices this mechanism can evaluate."""
        return tuple(
            i.name for i in registry.global_indices()
            if self._has(i.local) and (i.per is None or i.per in self.functions)
        )

    def local_index(self, name: str | LocalIndex, pose: Any, design: DesignLike = None, *, mode: str | None = None
                    ) -> np.ndarray:
        """A local index (by name, or given as it is) at each pose (N,); NaN where out of reach, its limit at
        singular poses."""
        spec = self.local_spec(name)
        x, single = as_batch(pose, self.n_out, "pose", finite=False)
        (values,), finite = regions.index_values(
            self, (spec,), x, np.array(self.working_mode(mode).signs), self.design_vector(design)
        )
        if not finite:
            require_finite(x, "pose")
        return unbatch(values, single)

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """Bounding box ((lo, hi) per output coordinate) of the reachable workspace, shape (n_out, 2)."""
        raise NotImplementedError

    def global_index(
        self,
        name: str | GlobalIndex,
        design: DesignLike = None,
        *,
        region: str | Any = "reachable",
        mode: str | None = None,
        resolution: int | None = None,
        gradient: bool = False,
        singularity_margin: float | None = None,
    ) -> regions.GlobalValue | tuple[regions.GlobalValue, dict[str, float]]:
        """A global index: its local index reduced over a region (DESIGN.md section 5).

        ``region="reachable"`` samples the working mode's reachable workspace on a grid with a mask;
        a parametrised region (one of ``regions`` by name, or a region object such as one of them fixed by
        ``region.at(centre, size)``) uses a fixed quadrature mapped into the design's region
        and, with ``gradient=True``, returns CasADi's exact gradient in the design parameters too. Without a
        ``resolution`` the quadrature doubles from QUADRATURE_RESOLUTION until the index changes by at most
        ``regions.INDEX_ACCURACY`` (relative above 1); region extremes are refined between the nodes.
        ``singularity_margin`` (sampled region only) drops poses with 1/kappa_f below it. The value
        reports its points, resolution and accuracy (:class:`pkm.regions.GlobalValue`).
        """
        spec = self.global_spec(name)
        d = self.design_vector(design)
        where = region if hasattr(region, "quadrature") else self.region(region)
        region = regions.region_name(where)
        if spec.local.source == regions.MOTION and not isinstance(where, regions.TrajectoryRegion):
            raise PkmError(f"{spec.name} is taken along a trajectory: region {region} is not one (a "
                           "pkm.regions.TrajectoryRegion, such as a mechanism's named move)")
        branch = self.working_mode(mode)
        allowed = getattr(where, "modes", None)
        if allowed and branch.name not in allowed:
            raise PkmError(
                f"region {region} is defined on working mode {', '.join(allowed)} only, not on {branch.name}"
            )
        if isinstance(where, regions.SampledWorkspace):
            if gradient:
                raise PkmError(
                    f"gradient=True needs a parametrised region ({', '.join(self.regions)}); "
                    "the reachable region is sampled"
                )
            margin = regions.SINGULARITY_MARGIN if singularity_margin is None else singularity_margin
            return regions.sampled_global(
                self, spec, d[None, :], branch, resolution=resolution, singularity_margin=margin, region=where
            )[0]
        if singularity_margin is not None:
            raise PkmError(f"singularity_margin applies to the sampled region only, not to {region!r}")
        index = regions.RegionIndex(self, spec, where, branch)

        def at(design: np.ndarray) -> tuple[regions.GlobalValue, np.ndarray | None]:
            if resolution is None:
                return regions.adaptive_value(index, design, gradient=gradient)
            return regions.value_at(index, design, resolution=resolution, gradient=gradient)

        value, grad = at(d)
        if not value.converged:
            value.note += self._singular_in(where, d, branch.name, spec.reduce)
        if grad is None:
            return value
        if np.isfinite(value) and not np.all(np.isfinite(grad)):
            grad = self._one_sided(at, d, value, grad)
        return value, self.design_dict(grad)

    def _singular_in(self, region: Any, d: np.ndarray, mode: str, reduce: str) -> str:
        """Where a parametrised region holds a pose near a singularity (either margin below SINGULAR_NEAR at a
        grid of its poses), that pose and its margins, in words for a note; else empty."""
        from pkm.indices.local import SINGULAR_NEAR

        x, _ = region.sample(self.functions, d, SINGULAR_SAMPLES, reduce)
        margins = self._singularity_margins(x, d, mode)
        least = margins.min(axis=1)
        if not np.any(least < SINGULAR_NEAR):
            return ""
        k = int(np.nanargmin(least))
        kinds = ", ".join(f"type {t} {v:.1e}" for t, v in zip(("I", "II"), margins[k], strict=True))
        return (f"; the region holds poses near a singularity, where the index grows without bound or kinks: at "
                f"{np.round(x[k], 6).tolist()} the singularity margins are {kinds}")

    def _one_sided(self, at: Callable[[np.ndarray], Any], d: np.ndarray, value: Any, grad: np.ndarray) -> np.ndarray:
        """Where the gradient of a finite value is not (the design sits where the region's placement switches
        between two smooth forms), each undefined partial derivative from the side whose value is the
        design's (the value there, less the derivative times the step, is the design's): the derivative one
        step of ONE_SIDED_STEP (relative) away, which ``value.note`` states; NaN with the reason where neither
        side has one."""
        sided, jumps = [], []
        for k in np.flatnonzero(~np.isfinite(grad)):
            step = ONE_SIDED_STEP * max(1.0, abs(d[k]))
            for sign, side in ((1.0, "above"), (-1.0, "below")):
                nudged = d.copy()
                nudged[k] += sign * step
                near, near_grad = at(nudged)
                extrapolated = near - sign * step * near_grad[k]
                if abs(extrapolated - value) <= ONE_SIDED_AGREEMENT * max(1.0, abs(value)):
                    grad[k] = near_grad[k]
                    sided.append(f"d/d{self.parameters[k].name} from {side}")
                    break
            else:
                jumps.append(self.parameters[k].name)
        notes = []
        if sided:
            notes.append(f"one-sided derivatives ({', '.join(sided)}): the region's placement switches at this "
                         "design, where the gradient is not defined")
        if jumps:
            notes.append(f"no one-sided derivative in {', '.join(jumps)}: on each side the index jumps or its slope "
                         "grows without bound (the region's placement switches at this design)")
        value.note = "; ".join(notes)
        return grad

    inertia_matrix = _Delegate("pkm.dynamics")
    inverse_dynamics = _Delegate("pkm.dynamics")
    natural_frequencies = _Delegate("pkm.dynamics")
    simulate = _Delegate("pkm.dynamics")
    export_urdf = _Delegate("pkm.export")
    every_assembly = _Delegate("pkm.assemblies")
    stiffness = _Delegate("pkm.stiffness")
    deflection = _Delegate("pkm.stiffness")
    stiffness_units = _Delegate("pkm.stiffness")
    certify = _Delegate("pkm.certify")
    largest_region = _Delegate("pkm.certify")
    certified_extreme = _Delegate("pkm.certify_extreme")
    error_model = _Delegate("pkm.accuracy")


def _product_unit(units: tuple[str, ...]) -> str:
    """The unit of a product of coordinates of these units: ``m^2``, ``m rad^2``."""
    counts = {u: units.count(u) for u in dict.fromkeys(units)}
    return " ".join(u if k == 1 else f"{u}^{k}" for u, k in counts.items())


def _coordinate_unit(units: tuple[str, ...]) -> str:
    """The unit of coordinates of these units as indices see them: angles among lengths are arc lengths."""
    lengths = sorted(set(units) - {"rad"})
    return lengths[0] if len(lengths) == 1 else "rad" if not lengths else "/".join(lengths)
