"""Atlases: a global index over a normalised design space, per working mode (Gao 1998 Figs. 4-9).

The chart of a normalised design space is sampled on a regular grid; each node inside the space is a
design at scale 1, and the global index of every node is evaluated in one vectorised call into
:mod:`pkm.regions` per mode. Axis labels come from the design space, the sense from the index.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from pkm import io, regions
from pkm.design_space import DesignSpace
from pkm.errors import ComputationError, PkmError, UnknownNameError, check_integer
from pkm.indices import GlobalIndex
from pkm.mechanism import Mechanism


class BestPoint(NamedTuple):
    """The best grid node of an atlas: chart coordinates, index value, normalised coordinates."""

    u: float
    v: float
    value: float
    coordinates: tuple[float, ...]


@dataclass
class Atlas:
    """A global index over the chart grid of a design space, one (n, n) array per working mode.

    ``values[mode][i, j]`` is the index of the design at chart node (u[i], v[j]); NaN outside the
    space (``inside`` False) and where the region holds no point. ``points[mode]`` counts the poses
    the index averaged over. ``wall_time`` is in seconds; ``evaluations`` counts the design-pose
    pairs evaluated (all modes); ``singularity_margin`` is None for a parametrised region.
    """

    mechanism: Mechanism
    index: GlobalIndex
    space: DesignSpace
    region: str
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

    def _mode(self, mode: str | None) -> str:
        name = self.modes[0] if mode is None else self.mechanism.working_mode(mode).name
        if name not in self.modes:
            raise UnknownNameError("atlas mode", name, self.modes)
        return name

    def best(self, mode: str | None = None, *, min_points: int = 1) -> BestPoint:
        """The best node of ``mode`` (the first mode by default) in the index's sense.

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
        names = ("region", "resolution", "pose_resolution", "singularity_margin", "wall_time", "evaluations")
        return {
            "mechanism": self.mechanism.name,
            "index": self.index.name,
            "sense": self.index.sense,
            "space": self.space.name,
            "modes": list(self.modes),
            "chart_axes": list(self.space.chart_axes),
            "chart_labels": list(self.space.chart_labels),
            **{name: getattr(self, name) for name in names},
        }

    def save_npz(self, path: str | os.PathLike) -> Path:
        """Write u, v, inside, ``values_<mode>``, ``points_<mode>`` and JSON ``metadata``, atomically."""
        arrays = {"u": self.u, "v": self.v, "inside": self.inside}
        for mode in self.modes:
            arrays[f"values_{mode}"] = self.values[mode]
            arrays[f"points_{mode}"] = self.points[mode]
        arrays["metadata"] = np.array(json.dumps(self.metadata()))
        return io.atomic_write(Path(path), lambda tmp: np.savez_compressed(tmp, **arrays))

    def plot(self, path: str | os.PathLike, *, min_points: int = 1) -> Path:
        """A PNG like Gao's Figs. 4-9: filled and labelled contours over the chart, one panel per mode."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.ticker import MaxNLocator

        space = self.space
        finite = np.concatenate([z[np.isfinite(z)] for z in self.values.values()])
        if finite.size == 0:
            raise ComputationError(f"the {self.index.name} atlas has no finite value to plot")
        levels = MaxNLocator(12).tick_values(finite.min(), finite.max())
        U, V = np.meshgrid(self.u, self.v, indexing="ij")
        poly = np.vstack([space.polygon, space.polygon[:1]])
        fig = Figure(figsize=(5.2 * len(self.modes) + 1.0, 5.0), layout="constrained")
        FigureCanvasAgg(fig)
        axes = fig.subplots(1, len(self.modes), squeeze=False)[0]
        for ax, mode in zip(axes, self.modes, strict=True):
            z = np.ma.masked_invalid(self.values[mode])
            filled = ax.contourf(U, V, z, levels=levels, cmap="viridis", extend="both")
            lines = ax.contour(U, V, z, levels=levels, colors="k", linewidths=0.6)
            ax.clabel(lines, lines.levels[::2], fmt="%.3g", fontsize=7)
            ax.plot(poly[:, 0], poly[:, 1], color="k", linewidth=1.2)
            best = self.best(mode, min_points=min_points)
            points = self.points[mode][self.u == best.u, self.v == best.v][0]
            at = ", ".join(f"{n}={c:.2f}" for n, c in zip(space.coordinates, best.coordinates, strict=True))
            ax.plot(best.u, best.v, marker="*", color="red", markersize=12, linestyle="none",
                    label=f"best {self.index.name} = {best.value:.3g} at {at} ({points} poses)")
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8, frameon=False)
            aliases = self.mechanism.working_mode(mode).aliases
            alias = f" ({', '.join(aliases)})" if aliases else ""
            ax.set_title(f"{self.index.name} over {self.region}\nmode {mode}{alias}", fontsize=10)
            ax.set_xlabel(f"{space.chart_axes[0]} = {space.chart_labels[0]}")
            ax.set_ylabel(f"{space.chart_axes[1]} = {space.chart_labels[1]}")
            ax.set_aspect("equal")
        sense = "larger" if self.index.sense == "max" else "smaller"
        fig.colorbar(filled, ax=list(axes), label=f"{self.index.name} ({sense} is better)", shrink=0.8)
        title = f"{self.mechanism.name}: {self.index.name} atlas over the {space.name} design space"
        fig.suptitle(f"{title}\n{space.note}", fontsize=9)
        return io.atomic_write(Path(path), lambda tmp: fig.savefig(tmp, format="png", dpi=120))


def default_modes(mech: Mechanism, region: str) -> tuple[str, ...]:
    """The working modes an atlas draws over ``region`` by default: ``mech.distinct_modes[region]`` where
    the mechanism's symmetry makes some modes equal, the modes the region is defined on where it says,
    else all working modes."""
    defined = getattr(mech.region(region), "modes", None)
    return tuple(mech.distinct_modes.get(region, defined or mech.modes))


def compute_atlas(
    mech: Mechanism,
    index: GlobalIndex,
    *,
    space: DesignSpace,
    modes: str | tuple[str, ...] | list[str] | None = None,
    region: str = "reachable",
    resolution: int = 41,
    pose_resolution: int | None = None,
    singularity_margin: float = regions.SINGULARITY_MARGIN,
    progress: Callable[[int], object] | None = None,
) -> Atlas:
    """The atlas of a global index over a design space's chart, per working mode.

    Parameters
    ----------
    mech : Mechanism
    index : GlobalIndex
        The global index (``pkm.registry.global_index(name)``).
    space : DesignSpace
        The normalised design space (one of ``mech.design_spaces``); designs are taken at scale 1.
    modes : str or sequence of str, optional
        Working modes (names or paper aliases); by default :func:`default_modes`.
    region : str
        ``"reachable"`` (sampled, masked by ``singularity_margin``) or a parametrised region of the
        mechanism.
    resolution : int
        Chart nodes per axis (>= 3); the atlas arrays are (resolution, resolution).
    pose_resolution : int, optional
        Poses per axis of the sampled grid (default ``regions.SAMPLED_RESOLUTION``) or the quadrature
        resolution of a parametrised region (default ``regions.QUADRATURE_RESOLUTION``).
    singularity_margin : float
        Poses with 1/kappa_f below it are left out of the sampled region.
    progress : callable, optional
        Called with the number of designs just finished; the total is ``inside.sum() * len(modes)``.

    Returns
    -------
    Atlas
    """
    where = mech.region(region)
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
    resolution = check_integer("resolution", resolution, 3)
    sampled = isinstance(where, regions.SampledWorkspace)
    if pose_resolution is None:
        pose_resolution = regions.SAMPLED_RESOLUTION if sampled else regions.QUADRATURE_RESOLUTION
    pose_resolution = check_integer("pose_resolution", pose_resolution, 2 if sampled else 1)
    if sampled:
        regions.check_margin(singularity_margin)

    start = time.perf_counter()
    u, v, inside = space.chart_grid(resolution)
    U, V = np.meshgrid(u, v, indexing="ij")
    designs = space.designs(mech.parameters, space.from_chart(U[inside], V[inside]))
    per_design = pose_resolution**mech.n_out if sampled else where.node_count(pose_resolution, index.reduce)
    values, points = {}, {}
    for mode in modes:
        branch = mech.working_mode(mode)
        values[mode] = np.full(inside.shape, np.nan)
        points[mode] = np.zeros(inside.shape, dtype=int)
        if sampled:
            result = regions.sampled_global(
                mech, index, designs, branch, resolution=pose_resolution,
                singularity_margin=singularity_margin, progress=progress,
            )
            values[mode][inside] = np.array(result, dtype=float)
            points[mode][inside] = [g.points for g in result]
        else:
            values[mode][inside] = regions.parametrised_global(
                mech, index, where, designs, branch=branch, resolution=pose_resolution
            )
            points[mode][inside] = np.where(np.isfinite(values[mode][inside]), per_design, 0)
            if progress is not None:
                progress(len(designs))
    return Atlas(
        mechanism=mech, index=index, space=space, region=region, modes=modes, u=u, v=v, inside=inside,
        values=values, points=points, resolution=resolution, pose_resolution=pose_resolution,
        singularity_margin=float(singularity_margin) if sampled else None,
        wall_time=time.perf_counter() - start, evaluations=len(designs) * per_design * len(modes),
    )
