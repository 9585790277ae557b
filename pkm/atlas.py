"""Atlases: a global index over a normalised design space, per working mode (Gao 1998 Figs. 4-9).

The chart of a normalised design space is sampled on a regular grid; each node inside the space is a
design at scale 1, and the global index of every node is evaluated in one vectorised call into
:mod:`pkm.regions` per mode. Axis labels come from the design space, the sense from the index.

A grid's largest value is no recommendation by itself: where a design's region holds a handful of poses
(a workspace shrunk to a sliver) or the index is not converged in the pose resolution (a mean of an
integrand that grows without bound towards a singular boundary), it is an artefact of the sampling. The
best an atlas reports (:class:`Best`) is the best of its top nodes that pass :class:`Checks`: a region
that is not degenerate and a value that changes by less than a stated tolerance when the pose resolution
doubles.
"""

from __future__ import annotations

import json
import math
import os
import textwrap
import time
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, field
from functools import cached_property, partial
from importlib.metadata import version as installed_version
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from pkm import figures, io, parallel, regions, registry
from pkm.design_space import DesignSpace
from pkm.errors import ComputationError, PkmError, UnknownNameError, check_integer
from pkm.indices import GlobalIndex
from pkm.kinematics import Branch
from pkm.mechanism import Mechanism
from pkm.parallel import ChunkStore, task_key
from pkm.progress import Progress
from pkm.regions.shapes import MAX_RESOLUTION
from pkm.spec.machine import resolve


class BestPoint(NamedTuple):
    """The best grid node of an atlas, unchecked: chart coordinates, index value, normalised coordinates."""

    u: float
    v: float
    value: float
    coordinates: tuple[float, ...]


@dataclass(frozen=True)
class Checks:
    """What the best design an atlas reports must pass.

    tolerance : float
        Largest relative change |v(2r) - v(r)| / |v(2r)| of the value when the pose resolution r (the
        sampled grid's poses per axis, or the quadrature resolution of a parametrised region) doubles.
    min_points : int
        Fewest poses (sampled region) or quadrature nodes the design's region must hold.
    min_fraction : float
        Smallest measure of the region as a fraction of the design's size, its workspace box
        (``mech.workspace_box``): for the sampled region the share of the grid's poses that it keeps.
    candidates : int
        How many of the grid's best nodes that pass the size checks are re-evaluated.
    refinements : int
        Most doublings of the pose resolution per candidate: a candidate whose value still changes by
        more than ``tolerance`` at the last one is not converged.
    """

    tolerance: float = 0.01
    min_points: int = 16
    min_fraction: float = 0.02
    candidates: int = 12
    refinements: int = 2

    def __post_init__(self) -> None:
        if not (isinstance(self.tolerance, int | float) and 0 < self.tolerance < 1):
            raise PkmError(f"tolerance = {self.tolerance!r} violates 0 < tolerance < 1")
        if not (isinstance(self.min_fraction, int | float) and 0 <= self.min_fraction < 1):
            raise PkmError(f"min_fraction = {self.min_fraction!r} violates 0 <= min_fraction < 1")
        check_integer("min_points", self.min_points, 1)
        check_integer("candidates", self.candidates, 1, MAX_CANDIDATES)
        check_integer("refinements", self.refinements, 1, MAX_REFINEMENTS)

    def describe(self) -> str:
        return (f"a region of at least {self.min_points} poses and {self.min_fraction:.0%} of the design's workspace "
                f"box, and a value that changes by less than {self.tolerance:.2%} when the pose resolution doubles")


MAX_CANDIDATES = 1000
MAX_REFINEMENTS = 4


@dataclass(frozen=True)
class Best:
    """The best design of one working mode of an atlas that passed the :class:`Checks`, or why none did.

    ``design`` holds the mechanism's design parameters (SI), ``coordinates`` the normalised ones of the
    design space and ``u``, ``v`` the chart's. ``value`` is the index at the finest pose resolution
    evaluated; ``values`` the node's value at each of ``resolutions`` (the atlas's own first), ``change``
    the relative change of the last doubling, ``points`` the poses (or nodes) of the region at the finest
    resolution and ``fraction`` its measure per the design's workspace box. ``found`` is False with the
    ``reason`` when no candidate passed (then the other fields are empty or NaN). ``varied`` names the
    design parameters the design space sets (the summary shows those).
    """

    index: str
    mode: str
    found: bool
    reason: str
    u: float = math.nan
    v: float = math.nan
    coordinates: dict[str, float] = field(default_factory=dict)
    design: dict[str, float] = field(default_factory=dict)
    value: float = math.nan
    values: tuple[float, ...] = ()
    resolutions: tuple[int, ...] = ()
    change: float = math.nan
    points: int = 0
    fraction: float = math.nan
    varied: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The fields, JSON-ready: NaN (no value) as None."""
        return {name: None if isinstance(value, float) and math.isnan(value) else value
                for name, value in ((name, getattr(self, name)) for name in self.__dataclass_fields__)}

    def __str__(self) -> str:
        if not self.found:
            return f"no best {self.index} in {self.mode}: {self.reason}"
        chart = ", ".join(f"{k:.4g}" for k in (self.u, self.v))
        design = ", ".join(f"{k} = {self.design[k]:.4g}" for k in self.varied or self.design)
        return (f"best {self.index} in {self.mode}: {self.value:.6g} at chart ({chart}), design {design} "
                f"({self.reason})")


@dataclass
class Atlas:
    """A global index over the chart grid of a design space, one (n, n) array per working mode.

    ``values[mode][i, j]`` is the index of the design at chart node (u[i], v[j]); NaN outside the
    space (``inside`` False) and where the region holds no point. ``points[mode]`` counts the poses
    the index averaged over. ``wall_time`` is in seconds; ``evaluations`` counts the design-pose
    pairs evaluated (all modes); ``singularity_margin`` is None for a parametrised region.
    ``checked[mode]`` is the best design that passed ``checks`` (a :class:`Best`, with the reason
    where none did); :meth:`best` is the grid's best node, unchecked. ``admissible`` marks the nodes
    whose design meets the space's requirements (:class:`pkm.design_space.Requirement`), the designs a
    synthesis over the space admits: the checked best is one of them.
    """

    mechanism: Mechanism
    index: GlobalIndex
    space: DesignSpace
    region: regions.RegionLike
    modes: tuple[str, ...]
    u: np.ndarray
    v: np.ndarray
    inside: np.ndarray
    values: dict[str, np.ndarray]
    points: dict[str, np.ndarray]
    resolution: int
    pose_resolution: int
    singularity_margin: float | None
    wall_time: float
    evaluations: int
    checks: Checks = field(default_factory=Checks)
    checked: dict[str, Best] = field(default_factory=dict)
    admissible: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.admissible is None:
            self.admissible = self.inside.copy()

    @property
    def region_name(self) -> str:
        return regions.region_name(self.region)

    def __str__(self) -> str:
        head = (f"{self.index.name} atlas of the {self.mechanism.name} over {self.region_name} in the "
                f"{self.space.name} "
                f"space: {int(self.inside.sum())} designs x {len(self.modes)} modes, pose resolution "
                f"{self.pose_resolution}, {self.wall_time:.1f} s")
        return "\n".join([head, *(f"  {self.checked[mode]}" for mode in self.modes if mode in self.checked)])

    def _mode(self, mode: str | None) -> str:
        name = self.modes[0] if mode is None else self.mechanism.working_mode(mode).name
        if name not in self.modes:
            raise UnknownNameError("atlas mode", name, self.modes)
        return name

    def best(self, mode: str | None = None, *, min_points: int = 1) -> BestPoint:
        """The best grid node of ``mode`` (the first mode by default) in the index's sense, unchecked
        (``checked[mode]`` is the best that passed the convergence and size checks).

        Only nodes whose value averages at least ``min_points`` poses count: the sampled grid puts
        few poses in a tiny workspace, whose value is then coarse.
        """
        mode = self._mode(mode)
        z = np.where(self.points[mode] >= min_points, self.values[mode], np.nan)
        if not np.isfinite(z).any():
            raise ComputationError(f"no node of the {self.index.name} atlas of mode {mode} has a value "
                                   f"from >= {min_points} poses")
        flat = np.nanargmax(z) if self.index.sense == "max" else np.nanargmin(z)
        i, j = np.unravel_index(flat, z.shape)
        c = self.space.from_chart(self.u[i], self.v[j])
        return BestPoint(float(self.u[i]), float(self.v[j]), float(z[i, j]), tuple(float(x) for x in c))

    def metadata(self) -> dict:
        """Everything but the arrays, JSON-serialisable."""
        names = ("region_name", "resolution", "pose_resolution", "singularity_margin", "wall_time", "evaluations")
        return {
            "mechanism": self.mechanism.name,
            "index": self.index.name,
            "sense": self.index.sense,
            "space": self.space.name,
            "modes": list(self.modes),
            "chart_axes": list(self.space.chart_axes),
            "chart_labels": list(self.space.chart_labels),
            "held": dict(self.space.base),
            **{name.removesuffix("_name"): getattr(self, name) for name in names},
            "checks": asdict(self.checks),
            "requirements": [r.name for r in self.space.requirements],
            "admissible_designs": int(self.admissible.sum()),
            "best": {mode: self.checked[mode].to_dict() for mode in self.modes if mode in self.checked},
        }

    def _star(self, mode: str, min_points: int | None) -> tuple[list[float], list[float], str]:
        """Where the figure marks the best of ``mode`` and its legend."""
        space = self.space
        if min_points is None:
            best = self.checked.get(mode)
            if best is None or not best.found:
                reason = best.reason if best is not None else "not checked"
                return [], [], textwrap.shorten(f"no best: {reason}", 90)
            at = ", ".join(f"{n}={best.design[n]:.3g}" for n in best.varied)
            return [best.u], [best.v], f"best {self.index.name} = {best.value:.3g} at {at} ({best.points} poses)"
        node = self.best(mode, min_points=min_points)
        points = self.points[mode][self.u == node.u, self.v == node.v][0]
        at = ", ".join(f"{n}={c:.2f}" for n, c in zip(space.coordinates, node.coordinates, strict=True))
        return [node.u], [node.v], f"best node {self.index.name} = {node.value:.3g} at {at} ({points} poses)"

    def save_npz(self, path: str | os.PathLike) -> Path:
        """Write u, v, inside, admissible, ``values_<mode>``, ``points_<mode>`` and JSON ``metadata``,
        atomically."""
        arrays = {"u": self.u, "v": self.v, "inside": self.inside, "admissible": self.admissible}
        for mode in self.modes:
            arrays[f"values_{mode}"] = self.values[mode]
            arrays[f"points_{mode}"] = self.points[mode]
        arrays["metadata"] = np.array(json.dumps(self.metadata()))
        return io.atomic_write(Path(path), lambda tmp: np.savez_compressed(tmp, **arrays))

    def _axis_label(self, k: int) -> str:
        """The label of chart axis ``k``: its name and meaning (the meaning alone where it starts with the
        name, as ``"R [m]"`` does)."""
        name, meaning = self.space.chart_axes[k], self.space.chart_labels[k]
        return meaning if meaning.split(" ")[0] == name else f"{name} = {meaning}"

    def plot(self, path: str | os.PathLike, *, min_points: int | None = None) -> Path:
        """A PNG like Gao's Figs. 4-9: filled and labelled contours over the chart, one panel per mode, the
        checked best marked by a star (or the reason there is none); with ``min_points`` the star marks
        the grid's best node of at least that many poses instead. The colours span the bulk of the values
        (:func:`pkm.figures.robust_limits`); the colour bar says where outliers are clipped."""
        from matplotlib.ticker import MaxNLocator

        space = self.space
        values = np.concatenate([z.ravel() for z in self.values.values()])
        if not np.isfinite(values).any():
            raise ComputationError(f"the {self.index.name} atlas has no finite value to plot")
        limits = figures.robust_limits(values)
        levels = limits.levels()
        U, V = np.meshgrid(self.u, self.v, indexing="ij")
        excluded = self.inside & ~self.admissible
        poly = np.vstack([space.polygon, space.polygon[:1]])
        width, height = np.ptp(poly, axis=0)
        shape = height / width
        to_scale = 1 / 3 <= shape <= 3  # a chart of like coordinates is drawn to scale, others fill the panel
        panel = 4.6
        tall = (panel - 0.8) * min(max(shape, 0.6), 1.0) if to_scale else panel
        fig = figures.figure(panel * len(self.modes) + 1.4, tall + 2.2)
        axes = fig.subplots(1, len(self.modes), squeeze=False)[0]
        labels = []
        for ax, mode in zip(axes, self.modes, strict=True):
            z = np.ma.masked_invalid(self.values[mode])
            filled = ax.contourf(U, V, z, levels=levels, cmap="viridis", extend=limits.extend)
            lines = ax.contour(U, V, z, levels=levels, colors="k", linewidths=0.6)
            labels.extend(ax.clabel(lines, lines.levels[::2], fmt="%.3g", fontsize=7))
            ax.plot(poly[:, 0], poly[:, 1], color="k", linewidth=1.2)
            if excluded.any():
                ax.contourf(U, V, excluded.astype(float), levels=[0.5, 1.5], colors="none", hatches=["///"])
            star_u, star_v, label = self._star(mode, min_points)
            ax.plot(star_u, star_v, marker="*", color="red", markersize=12, linestyle="none",
                    label=textwrap.fill(label, 60))
            aliases = self.mechanism.working_mode(mode).aliases
            alias = f" ({', '.join(aliases)})" if aliases else ""
            ax.set_title(textwrap.fill(f"{self.index.name} over {self.region_name}, mode {mode}{alias}", 50),
                         fontsize=10)
            ax.set_xlabel(textwrap.fill(self._axis_label(0), 50))
            ax.set_ylabel(textwrap.fill(self._axis_label(1), 40))
            ax.xaxis.set_major_locator(MaxNLocator(6))
            ax.yaxis.set_major_locator(MaxNLocator(6))
            ax.set_aspect("equal" if to_scale else "auto")
        sense = "larger" if self.index.sense == "max" else "smaller"
        unit = self.mechanism.index_unit(self.index.name)
        figures.colour_bar(fig, filled, limits, ax=list(axes), shrink=0.8,
                           label=f"{self.index.name}{'' if unit == '-' else f' [{unit}]'} ({sense} is better)")
        hatched = " Hatched: designs that fail the space's requirements." if excluded.any() else ""
        title = (f"{self.mechanism.name}: {self.index.name} atlas over the {space.name} design space. {space.note}."
                 f"{hatched}")
        fig.suptitle(textwrap.fill(title, int(14 * fig.get_figwidth())), fontsize=9)
        figures.legends_below(axes, fontsize=8, frameon=False)
        figures.hide_overlapping(fig, labels)
        return figures.save(fig, path, dpi=120)


CHUNK = 64
MAX_CHART = 4001  # chart nodes per axis


class AtlasTask(NamedTuple):
    """One chunk of a sweep by names and numbers: designs (n, n_p) of a mechanism in one working mode,
    every index of the sweep."""

    mechanism: str
    indices: tuple[str, ...]
    region: regions.RegionLike
    mode: str
    designs: np.ndarray
    resolution: int
    margin: float | None

    def describe(self) -> str:
        return (f"{registry.label(self.mechanism)} {', '.join(self.indices)} over "
                f"{regions.region_name(self.region)} in {self.mode}, "
                f"{len(self.designs)} designs from {self.designs[0].tolist()}, resolution {self.resolution}")


def _chunk(mech: Mechanism, task: AtlasTask) -> dict[str, np.ndarray]:
    """Every index of a task at its designs: ``values_<index>`` (n,) and ``points_<index>`` (n,)."""
    where, branch = mech.region(task.region), mech.working_mode(task.mode)
    out = {}
    for name in task.indices:
        spec = mech.global_spec(name)
        if isinstance(where, regions.SampledWorkspace):
            result = regions.sampled_global(mech, spec, task.designs, branch, resolution=task.resolution,
                                            singularity_margin=task.margin)
            values, points = np.array(result, dtype=float), np.array([g.points for g in result])
        else:
            index = regions.RegionIndex(mech, spec, where, branch)
            values = regions.global_values(index, task.designs, resolution=task.resolution)
            points = np.where(np.isfinite(values), index.node_count(task.resolution), 0)
        out[f"values_{name}"], out[f"points_{name}"] = values, points
    return out


def atlas_chunk(task: AtlasTask) -> dict[str, np.ndarray]:
    """One task of an atlas in a worker: the mechanism by its name or description (:func:`pkm.registry.reference`,
    :mod:`pkm.parallel`)."""
    parallel.as_worker()
    return _chunk(resolve(task.mechanism), task)


def region_fraction(
    mech: Mechanism, where: regions.Region, designs: np.ndarray, *, mode: Branch, resolution: int
) -> np.ndarray:
    """The measure of each design's parametrised region (D,) in the working mode ``mode`` as a fraction of its
    workspace box: its ``region_measure`` over the volume of ``mech.workspace_box``; NaN for every design where
    the region's extent (its quadrature's weights summed, reached or not) is the same at EXTENT_DESIGNS designs
    spread over them (two or more): a task the designer fixed, not a region the design sizes, which the size
    check leaves alone. (For the sampled region it is the share of the grid's cells kept, points /
    pose_resolution^n.)"""
    spread = designs[np.unique(np.linspace(0, len(designs) - 1, EXTENT_DESIGNS).astype(int))]
    extent = np.array([np.sum(where.quadrature(mech.functions, d, 1)[1]) for d in spread])
    if len(spread) > 1 and np.ptp(extent) <= FIXED * np.abs(extent).max():
        return np.full(len(designs), np.nan)
    measure = regions.global_values(regions.RegionIndex(mech, registry.global_index("region_measure"), where, mode),
                                    designs, resolution=resolution)
    box = np.array([np.prod(np.diff(mech.workspace_box(d), axis=1)) for d in designs])
    return measure / box


FIXED = 1e-12  # relative spread of a region's extent over an atlas's designs below which the region is fixed
EXTENT_DESIGNS = 5  # designs, spread over an atlas's, at which a region's extent is compared


def _relative_change(values: list[float]) -> float:
    new, old = values[-1], values[-2]
    return abs(new - old) / max(abs(new), np.finfo(float).tiny)


def checked_best(atlas: Atlas, mode: str, designs: np.ndarray, fraction: np.ndarray) -> Best:
    """The best design of ``mode`` that passes ``atlas.checks``: the best ``candidates`` nodes whose region
    holds enough poses and measure are re-evaluated at twice the pose resolution (and twice again, up to
    ``refinements`` times) until their value changes by less than ``tolerance``; the best of those that
    converge, by its value at the finest resolution; only admissible designs are candidates (``atlas.admissible``,
    the designs a synthesis over the space admits). ``designs`` (D, n_p) and ``fraction`` (D,) are the
    atlas's inside nodes in row-major order."""
    mech, checks, name = atlas.mechanism, atlas.checks, atlas.index.name
    values, points = atlas.values[mode][atlas.inside], atlas.points[mode][atlas.inside]
    nodes = np.argwhere(atlas.inside)
    sampled = isinstance(mech.region(atlas.region), regions.SampledWorkspace)

    def sized(value: float, count: int, share: float) -> bool:
        return (bool(np.isfinite(value)) and count >= checks.min_points
                and (bool(np.isnan(share)) or share >= checks.min_fraction))

    ok = np.array([sized(*row) for row in zip(values, points, fraction, strict=True)], dtype=bool)
    ok &= atlas.admissible[atlas.inside]
    if not ok.any():
        return Best(name, mode, False, f"no admissible design's region has a finite {name} over at least "
                                       f"{checks.min_points} points and {checks.min_fraction:.0%} of its workspace box")
    sign = -1.0 if atlas.index.sense == "max" else 1.0
    order = np.flatnonzero(ok)[np.argsort(sign * values[ok], kind="stable")][: checks.candidates]
    history = {k: [float(values[k])] for k in order}
    state = {k: (int(points[k]), float(fraction[k])) for k in order}
    resolutions, pending, converged = [atlas.pose_resolution], list(order), []
    for _ in range(checks.refinements):
        if not pending or 2 * resolutions[-1] > MAX_RESOLUTION:
            break
        resolutions.append(2 * resolutions[-1])
        task = AtlasTask(mech.name, (name,), atlas.region, mode, designs[pending], resolutions[-1],
                         atlas.singularity_margin)
        out = _chunk(mech, task)
        still = []
        for k, value, count in zip(pending, out[f"values_{name}"], out[f"points_{name}"], strict=True):
            history[k].append(float(value))
            share = count / resolutions[-1] ** mech.n_out if sampled else state[k][1]
            state[k] = (int(count), float(share))
            if not sized(value, count, share):
                continue
            (converged if _relative_change(history[k]) < checks.tolerance else still).append(k)
        pending = still
    if not converged:
        changes = [_relative_change(h) for h in history.values() if len(h) > 1 and np.isfinite(h[-1])]
        smallest = f"; the smallest change was {min(changes):.2%}" if changes else ""
        return Best(name, mode, False,
                    f"none of the {len(order)} best designs with a region of at least {checks.min_points} points and "
                    f"{checks.min_fraction:.0%} of the workspace box converged to {checks.tolerance:.2%} within "
                    f"{len(resolutions) - 1} doubling(s) of the pose resolution ({', '.join(map(str, resolutions))})"
                    f"{smallest}")
    k = min(converged, key=lambda c: sign * history[c][-1])
    i, j = nodes[k]
    u, v = float(atlas.u[i]), float(atlas.v[j])
    count, share = state[k]
    used = tuple(resolutions[: len(history[k])])
    change = _relative_change(history[k])
    size = "a fixed region" if np.isnan(share) else f"{share:.0%} of the workspace box"
    return Best(
        name, mode, True,
        f"converged: {change:.2%} change from pose resolution {used[-2]} to {used[-1]}; {count} points, {size}",
        u=u, v=v,
        coordinates={c: float(x) for c, x in zip(atlas.space.coordinates, atlas.space.from_chart(u, v), strict=True)},
        design=mech.design_dict(designs[k]), value=history[k][-1], values=tuple(history[k]), resolutions=used,
        change=change, points=count, fraction=share, varied=tuple(atlas.space.parameters),
    )


def default_modes(mech: Mechanism, region: regions.RegionLike) -> tuple[str, ...]:
    """The working modes an atlas draws over ``region`` by default: ``mech.distinct_modes[region]`` where
    the mechanism's symmetry makes some modes equal, the modes the region is defined on where it says,
    else all working modes."""
    defined = getattr(mech.region(region), "modes", None)
    return tuple(mech.distinct_modes.get(region, defined or mech.modes))


@dataclass(frozen=True)
class Sweep:
    """What a sweep computes, its options checked (:func:`compute_sweep`): the ``indices`` over the chart of
    ``space`` at ``resolution`` nodes per axis in each of the working ``modes``, over ``region`` (as given: a
    name, or a region) resolved as ``where``, at ``pose_resolution``; ``margin`` is the singularity margin of a
    sampled region (None for a parametrised one)."""

    mechanism: Mechanism
    indices: tuple[GlobalIndex, ...]
    space: DesignSpace
    modes: tuple[str, ...]
    region: regions.RegionLike
    where: regions.Region | regions.SampledWorkspace
    resolution: int
    pose_resolution: int
    margin: float | None
    checks: Checks

    @property
    def sampled(self) -> bool:
        return isinstance(self.where, regions.SampledWorkspace)

    @cached_property
    def reference(self) -> str | None:
        """The mechanism as a worker finds it (:func:`pkm.registry.reference`); None: in this process only."""
        return registry.reference(self.mechanism)

    def nodes(self, index: GlobalIndex) -> int:
        """The poses (a sampled region) or quadrature nodes of one design's region for ``index``."""
        if self.sampled:
            return self.pose_resolution**self.mechanism.n_out
        return self.where.node_count(self.pose_resolution, index.reduce)


def _sweep(
    mech: Mechanism, indices: tuple[GlobalIndex, ...], *, space: DesignSpace,
    modes: str | tuple[str, ...] | list[str] | None, region: regions.RegionLike,
    resolution: int, pose_resolution: int | None, singularity_margin: float, checks: Checks | None,
) -> Sweep:
    """The options of :func:`compute_sweep` checked, as a :class:`Sweep`."""
    where = mech.region(region)
    indices = tuple(indices)
    if not indices or len({i.name for i in indices}) != len(indices):
        raise PkmError(f"indices = {[i.name for i in indices]} violates: at least one global index, none repeated")
    for index in indices:
        mech.global_spec(index.name)
    if modes is None:
        modes = default_modes(mech, region)
    elif isinstance(modes, str):
        modes = (modes,)
    modes = tuple(mech.working_mode(m).name for m in modes)
    if not modes or len(set(modes)) != len(modes):
        raise PkmError(f"modes = {modes} violates: at least one working mode, none repeated")
    defined = getattr(where, "modes", None)
    if defined and not set(modes) <= set(defined):
        raise PkmError(f"region {region} is defined on working mode {', '.join(defined)} only, not on "
                       f"{', '.join(m for m in modes if m not in defined)}")
    resolution = check_integer("resolution", resolution, 3, MAX_CHART)
    sampled = isinstance(where, regions.SampledWorkspace)
    if pose_resolution is None:
        pose_resolution = regions.SAMPLED_RESOLUTION if sampled else regions.QUADRATURE_RESOLUTION
    pose_resolution = check_integer("pose_resolution", pose_resolution, 2 if sampled else 1, MAX_RESOLUTION)
    if sampled:
        regions.check_margin(singularity_margin)
    checks = Checks() if checks is None else checks
    if not isinstance(checks, Checks):
        raise PkmError(f"checks = {checks!r} violates: a pkm.atlas.Checks")
    return Sweep(mech, indices, space, modes, region, where, resolution, pose_resolution,
                 float(singularity_margin) if sampled else None, checks)


class Chart(NamedTuple):
    """A design space's chart grid: its axes u (n,) and v (n,), the nodes inside the space (n, n), their
    designs (D, n_p, row-major) and the nodes whose design meets the space's requirements (n, n)."""

    u: np.ndarray
    v: np.ndarray
    inside: np.ndarray
    designs: np.ndarray
    admissible: np.ndarray


def _chart(sweep: Sweep) -> Chart:
    mech, space = sweep.mechanism, sweep.space
    u, v, inside = space.chart_grid(sweep.resolution)
    U, V = np.meshgrid(u, v, indexing="ij")
    coordinates = space.from_chart(U[inside], V[inside])
    designs = space.designs(mech.parameters, coordinates)
    admissible = np.zeros(inside.shape, dtype=bool)
    admissible[inside] = space.admissible(mech.functions, coordinates, designs)[0]
    return Chart(u, v, inside, designs, admissible)


def _tasks(sweep: Sweep, designs: np.ndarray, chunk: int) -> list[AtlasTask]:
    """The sweep's designs in chunks of ``chunk`` per working mode, each chunk a task of every index."""
    names = tuple(index.name for index in sweep.indices)
    tasks = [
        AtlasTask(sweep.reference or sweep.mechanism.name, names, sweep.region, mode, designs[k : k + chunk],
                  sweep.pose_resolution, sweep.margin)
        for mode in sweep.modes
        for k in range(0, len(designs), chunk)
    ]
    if not tasks:
        raise PkmError(f"the {sweep.space.name} chart at resolution {sweep.resolution} has no design inside the space")
    return tasks


def _results(
    sweep: Sweep, tasks: list[AtlasTask], *, progress: Callable[[int, int], object] | bool | None,
    executor: str | Executor | None, store: Path | None,
) -> list[dict[str, np.ndarray]]:
    """Every task's values (:func:`_chunk`): those ``store`` holds loaded, the others computed on ``executor``
    and stored as each finishes with its mode and rows (:func:`compute_sweep` says how); ``progress`` told of
    the design-modes done."""
    mech = sweep.mechanism
    saved = ChunkStore(store) if store is not None and sweep.reference is not None else None
    stamp = (installed_version("pkm"), mech.functions.source_hash) if saved is not None else ()
    starts = dict.fromkeys(sweep.modes, 0)
    offsets = []
    for task in tasks:
        offsets.append(starts[task.mode])
        starts[task.mode] += len(task.designs)
    keys = [task_key(*stamp, *task) for task in tasks]
    results: list[dict[str, np.ndarray] | None] = [None] * len(tasks)
    if saved is not None:
        results = [saved.load(key) for key in keys]
    missing = [k for k, r in enumerate(results) if r is None]

    def finished(k: int, result: dict[str, np.ndarray]) -> None:
        task = tasks[missing[k]]
        if saved is not None:
            meta = {"mode": np.array(task.mode), "start": np.array(offsets[missing[k]]),
                    "count": np.array(len(task.designs))}
            saved.save(keys[missing[k]], {**result, **meta})
        step(len(task.designs))

    total = sum(len(task.designs) for task in tasks)
    bar = Progress(total, f"atlas {mech.name}", enabled=None if progress is None else False)
    done = [0]

    def step(n: int) -> None:
        done[0] += n
        bar.advance(n)
        if callable(progress):
            progress(done[0], total)

    work = total * sum(sweep.nodes(index) for index in sweep.indices)
    kind = executor if sweep.reference is not None else "serial"
    with bar, parallel.executor(kind, work=work, tasks=len(missing)) as pool:
        step(sum(len(task.designs) for task, result in zip(tasks, results, strict=True) if result is not None))
        fn = partial(_chunk, mech) if isinstance(pool, parallel.SerialExecutor) else atlas_chunk
        computed = parallel.run_tasks(
            pool, fn, [tasks[k] for k in missing], describe=AtlasTask.describe, done=finished,
        )
    for k, result in zip(missing, computed, strict=True):
        results[k] = result
    return results


def _atlases(
    sweep: Sweep, chart: Chart, tasks: list[AtlasTask], results: list[dict[str, np.ndarray]]
) -> dict[str, Atlas]:
    """An :class:`Atlas` per index from the tasks' values, with the best design of each mode checked
    (:func:`checked_best`)."""
    mech, inside, designs = sweep.mechanism, chart.inside, chart.designs
    atlases = {}
    for index in sweep.indices:
        values, points = {}, {}
        for mode in sweep.modes:
            rows = [r for task, r in zip(tasks, results, strict=True) if task.mode == mode]
            values[mode] = np.full(inside.shape, np.nan)
            points[mode] = np.zeros(inside.shape, dtype=int)
            values[mode][inside] = np.concatenate([r[f"values_{index.name}"] for r in rows])
            points[mode][inside] = np.concatenate([r[f"points_{index.name}"] for r in rows])
        atlases[index.name] = Atlas(
            mechanism=mech, index=index, space=sweep.space, region=sweep.region, modes=sweep.modes, u=chart.u,
            v=chart.v, inside=inside, values=values, points=points, resolution=sweep.resolution,
            pose_resolution=sweep.pose_resolution, singularity_margin=sweep.margin, wall_time=0.0,
            evaluations=len(designs) * sweep.nodes(index) * len(sweep.modes), checks=sweep.checks,
            admissible=chart.admissible,
        )
    for mode in sweep.modes:
        share = None if sweep.sampled else region_fraction(mech, sweep.where, designs, mode=mech.working_mode(mode),
                                                           resolution=sweep.pose_resolution)
        for atlas in atlases.values():
            fraction = atlas.points[mode][inside] / sweep.pose_resolution**mech.n_out if sweep.sampled else share
            atlas.checked[mode] = checked_best(atlas, mode, designs, fraction)
    return atlases


def compute_sweep(
    mech: Mechanism,
    indices: tuple[GlobalIndex, ...],
    *,
    space: DesignSpace,
    modes: str | tuple[str, ...] | list[str] | None = None,
    region: regions.RegionLike = "reachable",
    resolution: int = 41,
    pose_resolution: int | None = None,
    singularity_margin: float = regions.SINGULARITY_MARGIN,
    progress: Callable[[int, int], object] | bool | None = None,
    executor: str | Executor | None = None,
    store: Path | None = None,
    chunk: int = CHUNK,
    checks: Checks | None = None,
) -> dict[str, Atlas]:
    """Atlases of several global indices over a design space's chart, per working mode, in one pass:
    each task evaluates every index at its designs.

    Parameters
    ----------
    mech : Mechanism
    indices : tuple of GlobalIndex
        The global indices (``pkm.registry.global_index(name)``), none repeated.
    space : DesignSpace
        The normalised design space (one of ``mech.design_spaces``); designs are taken at scale 1.
    modes : str or sequence of str, optional
        Working modes (names or paper aliases); by default :func:`default_modes`.
    region : str or region
        ``"reachable"`` (sampled, masked by ``singularity_margin``) or a parametrised region of the
        mechanism, by name or as a region (a task's).
    resolution : int
        Chart nodes per axis (>= 3); the atlas arrays are (resolution, resolution).
    pose_resolution : int, optional
        Poses per axis of the sampled grid (default ``regions.SAMPLED_RESOLUTION``) or the quadrature
        resolution of a parametrised region (default ``regions.QUADRATURE_RESOLUTION``).
    singularity_margin : float
        Poses with 1/kappa_f below it are left out of the sampled region.
    progress : callable or bool, optional
        ``progress(done, total)`` in design-modes after each chunk (resumed chunks counted at once); by
        default (None) a progress bar on standard error when it is a terminal, nothing otherwise; False:
        nothing.
    executor : "auto", "serial", "processes" or a concurrent.futures.Executor, optional
        Where the chunks of designs run (:mod:`pkm.parallel`); by default a Dask cluster when a scheduler
        is set, else in this process for small atlases and a local process pool for large ones. The
        values are the same on every executor. A mechanism neither registered nor described as data runs in
        this process (a task carries a described machine's description, :func:`pkm.registry.reference`).
    store : path, optional
        A folder for the finished chunks (:class:`pkm.parallel.ChunkStore`; a registered or described mechanism's):
        run again with the same folder, an interrupted atlas computes only the chunks it lacks. A chunk
        is keyed by its task, pkm's version and the hash of the mechanism's generated module, and holds
        ``values_<index>``, ``points_<index>``, its ``mode`` and the ``start`` and ``count`` of its rows
        among the space's inside nodes (row-major).
    chunk : int
        Designs per task.
    checks : Checks, optional
        What the best design of each mode must pass (``Checks()`` by default): its top candidates are
        re-evaluated in this process at doubled pose resolutions; ``Atlas.checked`` holds the result.

    Returns
    -------
    dict
        An :class:`Atlas` per index name.
    """
    sweep = _sweep(mech, indices, space=space, modes=modes, region=region, resolution=resolution,
                   pose_resolution=pose_resolution, singularity_margin=singularity_margin, checks=checks)
    chunk = check_integer("chunk", chunk, 1)
    start = time.perf_counter()
    chart = _chart(sweep)
    tasks = _tasks(sweep, chart.designs, chunk)
    results = _results(sweep, tasks, progress=progress, executor=executor, store=store)
    atlases = _atlases(sweep, chart, tasks, results)
    wall = time.perf_counter() - start
    for atlas in atlases.values():
        atlas.wall_time = wall
    return atlases


def compute_atlas(mech: Mechanism, index: GlobalIndex, **options: Any) -> Atlas:
    """The atlas of one global index over a design space's chart, per working mode: :func:`compute_sweep`
    with one index, the same options."""
    return compute_sweep(mech, (index,), **options)[index.name]
