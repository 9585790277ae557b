"""The mechanism interface shared by every model in pkm.

A mechanism loads its generated CasADi functions, which follow one convention:

* ``inverse_kinematics(x, mode, design) -> (q, reach)``: all joints, actuated first; reach >= 0;
* ``forward_kinematics(q_a, assembly, design) -> (x, q, reach)``;
* ``first_order(q, x, design) -> (J, J_f, psi, det_type1, det_type2)`` with q_a_dot = J x_dot;
* ``constraint(q, x, design) -> (h, H_q, H_x)``.

Everything here is evaluated over batches through :func:`pkm.batch.evaluate`.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np

from pkm import indices, regions
from pkm.batch import evaluate, reached
from pkm.design import Condition, Design, Parameter, make_design
from pkm.errors import DesignError, PkmError, PoseError, SingularityError, UnknownNameError

SINGULAR_CONDITION = 1e12

DesignLike = Mapping[str, float] | Design | Sequence[float] | np.ndarray | None


@dataclass(frozen=True)
class Branch:
    """A working mode (IK branch) or assembly mode (FK branch): name, signs, the papers' names."""

    name: str
    signs: tuple[float, ...]
    doc: str
    aliases: tuple[str, ...] = ()


class Mechanism:
    """Base class of pkm's mechanisms; subclasses set the class attributes and regions."""

    name: str = ""
    doc: str = ""
    parameters: tuple[Parameter, ...] = ()
    conditions: tuple[Condition, ...] = ()
    working_modes: tuple[Branch, ...] = ()
    assembly_modes: tuple[Branch, ...] = ()
    pose_names: tuple[str, ...] = ()
    pose_units: tuple[str, ...] = ()
    actuator_names: tuple[str, ...] = ()

    @cached_property
    def functions(self) -> dict[str, ca.Function]:
        """The generated CasADi functions of this mechanism, by name."""
        return importlib.import_module(f"generated.{self.name}").build()

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
        return ("reachable", *self.parametrised_regions())

    def parametrised_regions(self) -> dict[str, regions.ParametrisedRegion]:
        """Design-dependent regions with a fixed quadrature (differentiable in the design)."""
        return {}

    def design(self, values: DesignLike = None, *, partial: bool = False) -> Design:
        """Validate a design: a mapping of parameter values, a sequence in parameter order, or None
        for the defaults."""
        if values is not None and not isinstance(values, Mapping):
            flat = np.asarray(values, dtype=float).ravel()
            if flat.size != len(self.parameters):
                names = ", ".join(p.name for p in self.parameters)
                raise DesignError(f"a design vector needs {len(self.parameters)} values ({names}); got {flat.size}")
            values = self.design_dict(flat)
        return make_design(self.parameters, self.conditions, values, partial=partial)

    def _design_vector(self, design: DesignLike) -> np.ndarray:
        if isinstance(design, Design):
            return design.vector()
        return self.design(design).vector()

    def _branch(self, name: str | None, branches: tuple[Branch, ...], kind: str) -> Branch:
        if name is None:
            return branches[0]
        for b in branches:
            if name == b.name or name in b.aliases:
                return b
        raise UnknownNameError(kind, name, [b.name for b in branches])

    def working_mode(self, mode: str | None) -> Branch:
        """The working mode by name or paper alias; the first one by default."""
        return self._branch(mode, self.working_modes, f"{self.name} working mode")

    def assembly_mode(self, assembly: str | None) -> Branch:
        return self._branch(assembly, self.assembly_modes, f"{self.name} assembly mode")

    @staticmethod
    def _batch(values: Any, width: int, what: str) -> tuple[np.ndarray, bool]:
        arr = np.asarray(values, dtype=float)
        single = arr.ndim == 1
        arr = np.atleast_2d(arr)
        if arr.ndim != 2 or arr.shape[1] != width:
            raise PoseError(f"{what} must have shape ({width},) or (N, {width}); got {np.shape(values)}")
        if not np.all(np.isfinite(arr)):
            raise PoseError(f"{what} contains non-finite values")
        return arr, single

    @staticmethod
    def _unbatch(arr: np.ndarray, single: bool) -> np.ndarray:
        return arr[0] if single else arr

    def _joints(self, pose: Any, design: DesignLike, mode: str | None, strict: bool):
        x, single = self._batch(pose, self.n_out, "pose")
        d = self._design_vector(design)
        signs = np.array(self.working_mode(mode).signs)
        q, reach = evaluate(self.functions["inverse_kinematics"], x, signs, d)
        q = q[:, :, 0]
        ok = reached(q, reach)
        if strict and not ok.all():
            bad = int(np.flatnonzero(~ok)[0])
            raise PoseError(f"pose {x[bad].tolist()} is out of reach of the {self.name} design {self.design_dict(d)}")
        q[~ok] = np.nan
        return x, d, q, ok, single

    def design_dict(self, vector: np.ndarray) -> dict[str, float]:
        return {p.name: float(v) for p, v in zip(self.parameters, vector, strict=True)}

    def reachable(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> np.ndarray:
        """Boolean mask (N,) of the poses the working mode reaches."""
        _, _, _, ok, single = self._joints(pose, design, mode, strict=False)
        return self._unbatch(ok, single)

    def inverse_kinematics(
        self,
        pose: Any,
        design: DesignLike = None,
        *,
        mode: str | None = None,
        passive: bool = False,
        strict: bool = False,
    ) -> np.ndarray:
        """Actuated joints (N, n_act) of the poses (N, n_out) in a working mode; NaN where out of reach.

        With ``passive`` all joints (actuated first) are returned; with ``strict`` an unreachable pose
        raises :class:`PoseError`.
        """
        _, _, q, _, single = self._joints(pose, design, mode, strict)
        return self._unbatch(q if passive else q[:, : self.n_act], single)

    def forward_kinematics(
        self, q: Any, design: DesignLike = None, *, assembly: str | None = None, strict: bool = False
    ) -> np.ndarray:
        """Poses (N, n_out) from actuated joints (N, n_act) in an assembly mode; NaN where not closable."""
        qa, single = self._batch(q, self.n_act, "actuated joints")
        d = self._design_vector(design)
        signs = np.array(self.assembly_mode(assembly).signs)
        x, _, reach = evaluate(self.functions["forward_kinematics"], qa, signs, d)
        x = x[:, :, 0]
        ok = reached(x, reach)
        if strict and not ok.all():
            bad = int(np.flatnonzero(~ok)[0])
            raise PoseError(f"actuated joints {qa[bad].tolist()} cannot be assembled")
        x[~ok] = np.nan
        return self._unbatch(x, single)

    def _first_order(self, pose: Any, design: DesignLike, mode: str | None, strict: bool):
        x, d, q, ok, single = self._joints(pose, design, mode, strict)
        J, J_f, psi, det1, det2 = evaluate(self.functions["first_order"], q, x, d)
        return {
            "J": J,
            "J_f": J_f,
            "psi": psi,
            "det_type1": det1[:, 0, 0],
            "det_type2": det2[:, 0, 0],
            "reachable": ok,
            "q": q,
        }, single

    def _strict_check(self, fo: dict[str, np.ndarray], pose: Any, design: DesignLike, kind: str) -> None:
        """Raise SingularityError where the loop equations cannot be solved for J (type I) or J_f (type II)."""
        x = np.atleast_2d(np.asarray(pose, dtype=float))
        _, H_q, H_x = evaluate(self.functions["constraint"], fo["q"], x, self._design_vector(design))
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
            raise SingularityError(f"{what}: pose {x[int(np.flatnonzero(bad)[0])].tolist()}")

    def jacobian(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, strict: bool = False
    ) -> np.ndarray:
        """J (N, n_act, n_out) with q_a_dot = J x_dot; unbounded entries at serial singularities.

        With ``strict`` an unreachable pose raises :class:`PoseError` and a serial singularity (the
        condition number of dh/dq above 1e12) raises :class:`SingularityError`.
        """
        fo, single = self._first_order(pose, design, mode, strict)
        if strict:
            self._strict_check(fo, pose, design, "type I")
        return self._unbatch(fo["J"], single)

    def forward_jacobian(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, strict: bool = False
    ) -> np.ndarray:
        """J_f (N, n_out, n_act) with x_dot = J_f q_a_dot, the inverse of :meth:`jacobian`.

        With ``strict`` a parallel singularity raises :class:`SingularityError`.
        """
        fo, single = self._first_order(pose, design, mode, strict)
        if strict:
            self._strict_check(fo, pose, design, "type II")
        return self._unbatch(fo["J_f"], single)

    def psi(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> np.ndarray:
        """Psi (N, n_joints, n_act): all joint rates from the actuated rates."""
        fo, single = self._first_order(pose, design, mode, False)
        return self._unbatch(fo["psi"], single)

    def singularity(self, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> dict[str, np.ndarray]:
        """Type I and type II determinants (zero at serial and parallel singularities)."""
        fo, single = self._first_order(pose, design, mode, False)
        return {k: self._unbatch(fo[k], single) for k in ("det_type1", "det_type2")}

    def local_index(self, name: str, pose: Any, design: DesignLike = None, *, mode: str | None = None) -> np.ndarray:
        """A local index (see :data:`pkm.indices.LOCAL`) at each pose; NaN where out of reach."""
        spec = self.local_spec(name)
        fo, single = self._first_order(pose, design, mode, False)
        values = indices.evaluate_local(spec, self._matrices(spec, fo, pose, design))
        values[~fo["reachable"]] = np.nan
        return self._unbatch(values, single)

    def local_spec(self, name: str) -> indices.LocalIndex:
        """The local index by name, if this mechanism has the generated function it needs."""
        spec = indices.local_spec(name)
        if not self._has(spec):
            raise PkmError(
                f"local index {name} needs the {', '.join(spec.arguments)} of a {spec.source} model, "
                f"which {self.name} does not have"
            )
        return spec

    def _has(self, spec: indices.LocalIndex) -> bool:
        fn = self.functions.get(spec.source)
        return fn is not None and set(spec.arguments) <= set(fn.name_out())

    def local_indices(self) -> tuple[str, ...]:
        """Names of the local indices this mechanism can evaluate."""
        return tuple(k for k, v in indices.LOCAL.items() if self._has(v))

    def global_indices(self) -> tuple[str, ...]:
        """Names of the global indices this mechanism can evaluate."""
        local = set(self.local_indices())
        return tuple(k for k, v in indices.GLOBAL.items() if v.local in local)

    def _matrices(self, spec: indices.LocalIndex, fo: dict[str, np.ndarray], pose: Any, design: DesignLike):
        if spec.source == "first_order":
            return fo
        fn = self.functions[spec.source]
        x = np.atleast_2d(np.asarray(pose, dtype=float))
        outs = evaluate(fn, fo["q"], x, self._design_vector(design))
        return dict(zip(fn.name_out(), outs, strict=True))

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """Bounding box ((lo, hi) per output coordinate) of the reachable workspace, shape (n_out, 2)."""
        raise NotImplementedError

    def global_index(
        self,
        name: str,
        design: DesignLike = None,
        *,
        region: str = "reachable",
        mode: str | None = None,
        resolution: int | None = None,
        gradient: bool = False,
        singularity_margin: float | None = None,
    ) -> float | tuple[float, dict[str, float]] | regions.GlobalValue:
        """A global index: the mean of its local index over a region (DESIGN.md section 5).

        ``region="reachable"`` samples the working mode's reachable workspace on a grid with a mask;
        a parametrised region (e.g. ``"miw"``) uses a fixed quadrature mapped into the design's region
        and, with ``gradient=True``, returns CasADi's exact gradient in the design parameters too.
        ``singularity_margin`` (sampled region only) drops poses with 1/kappa_f below it.
        """
        spec = indices.global_spec(name)
        self.local_spec(spec.local)
        d = self._design_vector(design)
        branch = self.working_mode(mode)
        if region == "reachable":
            if gradient:
                raise PkmError(
                    "gradient=True needs a parametrised region "
                    f"({', '.join(self.parametrised_regions())}); the reachable region is sampled"
                )
            margin = regions.SINGULARITY_MARGIN if singularity_margin is None else singularity_margin
            return regions.sampled_global(
                self, spec, d[None, :], branch, resolution=resolution, singularity_margin=margin
            )[0]
        param = self.parametrised_regions()
        if region not in param:
            raise UnknownNameError(f"{self.name} region", region, self.region_names())
        if singularity_margin is not None:
            raise PkmError(f"singularity_margin applies to the sampled region only, not to {region!r}")
        resolution = regions.DISC_RESOLUTION if resolution is None else resolution
        fn = regions.parametrised_global_function(self, spec, param[region], branch, resolution)
        value, grad = fn(d)
        nodes = len(param[region].nodes(resolution, spec.reduce)[1])
        value = regions.GlobalValue(float(value), points=nodes, region=region, resolution=resolution)
        if not gradient:
            return value
        return value, self.design_dict(np.asarray(grad).ravel())

    def inertia_matrix(
        self, pose: Any, design: DesignLike = None, *, mode: str | None = None, space: str = "task"
    ) -> np.ndarray:
        """Inertia matrix (N, n, n) at the poses: ``space="task"`` M_w = J^T M_t J (n = n_out) or
        ``"actuated"`` M_t = Psi^T M Psi (n = n_act); NaN where out of reach.

        See :func:`pkm.dynamics.inertia_matrix`.
        """
        from pkm import dynamics

        return dynamics.inertia_matrix(self, pose, design, mode=mode, space=space)

    def inverse_dynamics(
        self,
        pose: Any,
        velocity: Any,
        acceleration: Any,
        design: DesignLike = None,
        *,
        mode: str | None = None,
        joint_torques: bool = False,
    ) -> np.ndarray:
        """Motor torques (N, n_act) for end-effector positions, velocities and accelerations (N, n_out)
        with rigid transmissions; with ``joint_torques`` the torques the transmissions apply to the
        actuated joints.

        See :func:`pkm.dynamics.inverse_dynamics`.
        """
        from pkm import dynamics

        return dynamics.inverse_dynamics(
            self, pose, velocity, acceleration, design, mode=mode, joint_torques=joint_torques
        )

    def natural_frequencies(self, pose: Any, design: DesignLike = None, *, mode: str | None = None):
        """Natural frequencies, mode shapes and rigid-body flags of the flexible-joint model at the poses.

        See :func:`pkm.dynamics.natural_frequencies`.
        """
        from pkm import dynamics

        return dynamics.natural_frequencies(self, pose, design, mode=mode)

    def simulate(
        self,
        design: DesignLike = None,
        *,
        z0: Any,
        z_dot0: Any,
        times: Any,
        torque: Any = None,
        assembly: str | None = None,
        method: str = "adams",
        rtol: float = 1e-10,
        atol: float = 1e-12,
    ):
        """Forward dynamics of the flexible-joint model from (z0, z_dot0), sampled at ``times``.

        See :func:`pkm.dynamics.simulate`.
        """
        from pkm import dynamics

        return dynamics.simulate(
            self,
            design,
            z0=z0,
            z_dot0=z_dot0,
            times=times,
            torque=torque,
            assembly=assembly,
            method=method,
            rtol=rtol,
            atol=atol,
        )
