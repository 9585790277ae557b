"""What a region offers, and a global index taken over one (DESIGN.md section 5).

A region is parametrised or sampled. :class:`Region` is the protocol of every parametrised region (the
shapes of :mod:`pkm.regions.shapes`, a trajectory of :mod:`pkm.regions.trajectory`) and :class:`Piece` that of
the simple shapes its nodes come from; :class:`SampledWorkspace` is the working mode's workspace sampled on a
grid (:mod:`pkm.regions.sampled`).

:class:`RegionIndex` is a global index over one region in one working mode of one mechanism: what the
quadratures (:mod:`pkm.regions.quadrature`), the point integrands (:mod:`pkm.regions.integrand`), the region
extremes (:mod:`pkm.regions.extremes`) and a synthesis's model evaluate for designs.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Protocol

import casadi as ca
import numpy as np

from pkm.indices import GlobalIndex, LocalIndex
from pkm.indices.local import WORKSPACE_MARGIN
from pkm.kinematics import Branch

if TYPE_CHECKING:
    from pkm.regions.pipeline import PipelineModel

Functions = Mapping[str, ca.Function]  # a mechanism's generated functions by name (its ``functions``)
Array = ca.SX | ca.MX | ca.DM | np.ndarray  # a design, a reference point or a pose: CasADi, or numpy


class Piece(Protocol):
    """A simple shape a region's nodes come from, in reference coordinates that do not depend on the design.

    A piece is :class:`Refinable` unless its ``refinable`` is False (nothing lies between its nodes); a
    trajectory's pieces also offer ``motion(u)``, the pose's velocity and acceleration at a reference time."""

    @property
    def dimension(self) -> int: ...

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
        """The nodes (n, d) and weights (n,) of the rule for the reduction ``reduce``, in reference coordinates."""

    def node_count(self, resolution: int, reduce: str = "mean") -> int: ...

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:
        """The pose (n_out x 1) at the reference point u (CasADi), for a design (CasADi)."""

    def element(self, functions: Functions, design: Array, u: Array) -> Array:
        """The measure element at the reference point u: a node's weight is its reference weight times it."""


class Refinable(Piece, Protocol):
    """A piece whose extremes :mod:`pkm.regions.extremes` refines between its nodes."""

    def project(self, u: np.ndarray) -> np.ndarray:
        """Reference points (n, d) moved onto the closed reference domain."""


class Region(Protocol):
    """A parametrised region: placed by the design, with a fixed quadrature on its pieces' reference domains
    (:mod:`pkm.regions.shapes` describes the rules).

    ``guard`` names a mechanism function of margins that must hold over the region (None: none). A region
    may also offer ``sample(functions, design, resolution, reduce)`` (the cell centres of a grid inside it, for
    a check by sampling; a trajectory: ``samples`` and ``timed``), ``modes`` (the working modes it is
    defined on) and ``inner`` (the shape a :class:`pkm.regions.Mapped` region maps)."""

    name: str
    doc: str

    @property
    def guard(self) -> str | None: ...

    @property
    def dimension(self) -> int: ...

    def node_count(self, resolution: int, reduce: str = "mean") -> int: ...

    def pieces(self) -> tuple[Piece, ...]:
        """The pieces its nodes come from, in node order."""

    def quadrature(
        self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"
    ) -> tuple[Array, Array]:
        """Points (d x n) and weights (1 x n), CasADi for a CasADi design; numpy (n, d) and (n,) for a numeric one."""


@dataclass(frozen=True)
class SampledWorkspace:
    """The reachable workspace of a working mode, sampled on a grid over ``mech.workspace_box``
    (:mod:`pkm.regions.sampled`): the poses it reaches within the mechanism's stated limits, or with
    ``assembled`` the poses where it assembles whatever those limits (:func:`pkm.kinematics.within_limits`)."""

    name: str = "reachable"
    doc: str = "the working mode's reachable workspace, sampled on a grid with a mask"
    assembled: bool = False


REACHABLE_WORKSPACE = SampledWorkspace()
ASSEMBLED_WORKSPACE = SampledWorkspace(
    "assembled", "the working mode's assembled configurations whatever the stated limits (strokes, joint ranges, "
    "interference), sampled on a grid with a mask", assembled=True)


RegionLike = str | Region | SampledWorkspace  # a region by name (a mechanism's), or given as it is (a task's)


def region_name(region: RegionLike) -> str:
    """A region's name: a region given by name is its name, one given as a region (a task's) its ``name``."""
    return getattr(region, "name", region)


def guard_index(region: Region) -> LocalIndex | None:
    """The least of the region's guard margins as a local index (None for a region without a guard)."""
    if region.guard is None:
        return None
    return replace(WORKSPACE_MARGIN, name=f"{region.guard}_min", source=region.guard, arguments=("margins",),
                   signed=False,
                   doc=f"least of the margins {region.guard} that the region {region.name} needs at every node")


@dataclass(frozen=True)
class RegionIndex:
    """A global index over one region in one working mode of one mechanism.

    ``mechanism`` is a :class:`pkm.Mechanism` (what :class:`pkm.regions.pipeline.PipelineModel` states of it),
    ``spec`` gives the local index, the reduction and what the reduction is divided by (its ``per`` function),
    ``mode`` the working mode, whose ``signs`` pick the inverse kinematics' branch at every node.
    A resolution is not part of it: one index is evaluated at several (a refinement doubles it, a
    verification takes twice the optimiser's)."""

    mechanism: PipelineModel
    spec: GlobalIndex
    region: Region
    mode: Branch

    @property
    def local(self) -> LocalIndex:
        return self.spec.local

    @property
    def reduce(self) -> str:
        return self.spec.reduce

    @property
    def signs(self) -> np.ndarray:
        """The working mode's signs, the ``mode`` input of every pipeline."""
        return np.array(self.mode.signs, dtype=float)

    @property
    def design_size(self) -> int:
        """The entries of the mechanism's design vector."""
        return self.mechanism.functions["inverse_kinematics"].numel_in(2)

    def node_count(self, resolution: int) -> int:
        """The nodes of the region's rule for this index's reduction at ``resolution``."""
        return self.region.node_count(resolution, self.reduce)

    def guard(self) -> RegionIndex | None:
        """The region's guard in this mode (:func:`region_guard`)."""
        return region_guard(self.mechanism, self.region, self.mode)


def region_guard(mechanism: PipelineModel, region: Region, mode: Branch) -> RegionIndex | None:
    """The least of the region's guard margins (:func:`guard_index`) as a region minimum over the region in the
    working mode ``mode``; None for a region without a guard."""
    local = guard_index(region)
    if local is None:
        return None
    return RegionIndex(mechanism, GlobalIndex(local.name, local, local.doc, reduce="min"), region, mode)
