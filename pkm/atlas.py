"""Atlases: a global index over a normalised design space, per working mode (Gao 1998 Figs. 4-9).

The chart of a design space (for the five-bar, Gao's trapezoid of 2 r1 + 2 r2 + r3 = 4 drawn in
(u, v)) is sampled on a regular grid; each node inside the space is a design at scale L = 1, and the
global index of every node is evaluated in one vectorised call into :mod:`pkm.regions` per mode.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO, NamedTuple

import numpy as np

from pkm import indices, regions
from pkm.errors import ComputationError, PkmError, UnknownNameError
from pkm.mechanism import Mechanism

#: Whether larger ("max") or smaller ("min") values of a global index are better.
SENSE: dict[str, str] = {
    "gci": "max",
    "gci_2": "max",
    "gamma_max": "max",
    "gamma_min": "max",
    "dynamic_dexterity": "max",
    "lambda_e": "max",
}

#: What the chart axes of a design space mean, and a note on its coordinates, for figures.
CHART_NOTES: dict[str, tuple[str, str, str]] = {
    "gao1998": (
        "(r1 - r2)/\u221a2",
        "3 r3/(2\u221a2)",
        "r_i = R_i / L, L the mean link length, r3 the full base, 2 r1 + 2 r2 + r3 = 4 (Gao 1998 eqs. 1-5)",
    ),
    "lara_molina2016": (
        "(2 r1 + r3)/\u221a3",
        "r3",
        "r_i = R_i / D, D the mean of r1, r2 and the half base r3, r1 + r2 + r3 = 3 (Lara-Molina 2016 eqs. 1-2, "
        "32-34)",
    ),
}


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
    index: str
    space: str
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
        """The best node of ``mode`` (the first mode by default), by :data:`SENSE`.

        Only nodes whose value averages at least ``min_points`` poses count: the sampled grid puts
        few poses in a tiny workspace, whose value is then coarse.
        """
        mode = self._mode(mode)
        if self.index not in SENSE:
            raise PkmError(f"index {self.index!r} has no sense; add it to pkm.atlas.SENSE ('max' or 'min')")
        z = np.where(self.points[mode] >= min_points, self.values[mode], np.nan)
        if not np.isfinite(z).any():
            raise ComputationError(f"no node of the {self.index} atlas of mode {mode} has a value "
                                   f"from >= {min_points} poses")
        flat = np.nanargmax(z) if SENSE[self.index] == "max" else np.nanargmin(z)
        i, j = np.unravel_index(flat, z.shape)
        c = self.mechanism.design_spaces[self.space].from_chart(self.u[i], self.v[j])
        return BestPoint(float(self.u[i]), float(self.v[j]), float(z[i, j]), tuple(float(x) for x in c))

    def metadata(self) -> dict:
        """Everything but the arrays, JSON-serialisable."""
        names = ("index", "space", "region", "resolution", "pose_resolution", "singularity_margin",
                 "wall_time", "evaluations")
        return {
            "mechanism": self.mechanism.name,
            "modes": list(self.modes),
            "chart_axes": list(self.mechanism.design_spaces[self.space].chart_axes),
            **{name: getattr(self, name) for name in names},
        }

    def save_npz(self, path: str | os.PathLike) -> Path:
        """Write u, v, inside, ``values_<mode>``, ``points_<mode>`` and JSON ``metadata``, atomically."""
        arrays = {"u": self.u, "v": self.v, "inside": self.inside}
        for mode in self.modes:
            arrays[f"values_{mode}"] = self.values[mode]
            arrays[f"points_{mode}"] = self.points[mode]
        arrays["metadata"] = np.array(json.dumps(self.metadata()))
        return _write_atomically(path, lambda fh: np.savez_compressed(fh, **arrays))

    def plot(self, path: str | os.PathLike, *, min_points: int = 1) -> Path:
        """A PNG like Gao's Figs. 4-9: filled and labelled contours over the chart, one panel per mode."""
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.ticker import MaxNLocator

        space = self.mechanism.design_spaces[self.space]
        finite = np.concatenate([z[np.isfinite(z)] for z in self.values.values()])
        if finite.size == 0:
            raise ComputationError(f"the {self.index} atlas has no finite value to plot")
        levels = MaxNLocator(12).tick_values(finite.min(), finite.max())
        U, V = np.meshgrid(self.u, self.v, indexing="ij")
        poly = np.vstack([space.polygon, space.polygon[:1]])
        notes = CHART_NOTES.get(self.space, ())
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
                    label=f"best {self.index} = {best.value:.3g} at {at} ({points} poses)")
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8, frameon=False)
            aliases = self.mechanism.working_mode(mode).aliases
            alias = f" ({', '.join(aliases)})" if aliases else ""
            ax.set_title(f"{self.index} over {self.region}\nmode {mode}{alias}", fontsize=10)
            ax.set_xlabel(" = ".join([space.chart_axes[0], *notes[:1]]))
            ax.set_ylabel(" = ".join([space.chart_axes[1], *notes[1:2]]))
            ax.set_aspect("equal")
        fig.colorbar(filled, ax=list(axes), label=self.index, shrink=0.8)
        title = f"{self.mechanism.name}: {self.index} atlas over the {self.space} design space"
        fig.suptitle("\n".join([title, *notes[2:]]), fontsize=9)
        return _write_atomically(path, lambda fh: fig.savefig(fh, format="png", dpi=120))


def _write_atomically(path: str | os.PathLike, write: Callable[[IO[bytes]], object]) -> Path:
    """Write through a temporary file in the target folder, then rename: never a half-written file."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    return path


def default_modes(mech: Mechanism, region: str) -> tuple[str, ...]:
    """The working modes whose global indices differ over ``region``.

    ``mech.distinct_modes`` is a mapping region -> modes, or a tuple that holds for the sampled
    ``reachable`` region only: Gao's eqs. 26-27 (out_out == in_in, out_in == in_out) rest on the
    workspace's symmetry about the base line, which a design-dependent region such as the MIW lacks.
    Without it, all working modes.
    """
    distinct = getattr(mech, "distinct_modes", None)
    if isinstance(distinct, Mapping):
        return tuple(distinct.get(region, mech.modes))
    return tuple(distinct) if distinct is not None and region == "reachable" else mech.modes


def _check_int(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise PkmError(f"{name} = {value!r} violates: an integer >= {minimum}")
    return int(value)


def compute_atlas(
    mech: Mechanism,
    index: str,
    *,
    space: str = "gao1998",
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
        A mechanism with ``design_spaces``.
    index : str
        A global index key (:data:`pkm.indices.GLOBAL`), e.g. ``"gci"``, ``"gamma_max"``.
    space : str
        The normalised design space; designs are taken at scale L = 1.
    modes : str or sequence of str, optional
        Working modes (names or paper aliases); by default :func:`default_modes`.
    region : str
        ``"reachable"`` (sampled, masked by ``singularity_margin``) or a parametrised region (``"miw"``).
    resolution : int
        Chart nodes per axis (>= 3); the atlas arrays are (resolution, resolution).
    pose_resolution : int, optional
        Poses per axis of the sampled grid (default ``regions.SAMPLED_RESOLUTION``) or the disc
        quadrature order of a parametrised region (default ``regions.DISC_RESOLUTION``).
    singularity_margin : float
        Poses with 1/kappa_f below it are left out of the sampled region.
    progress : callable, optional
        Called with the number of designs just finished; the total is ``inside.sum() * len(modes)``.

    Returns
    -------
    Atlas
    """
    spec = indices.global_spec(index)
    spaces = getattr(mech, "design_spaces", {})
    if space not in spaces:
        raise UnknownNameError(f"{mech.name} design space", space, sorted(spaces))
    if region not in mech.region_names():
        raise UnknownNameError(f"{mech.name} region", region, mech.region_names())
    if modes is None:
        modes = default_modes(mech, region)
    elif isinstance(modes, str):
        modes = (modes,)
    modes = tuple(mech.working_mode(m).name for m in modes)
    if not modes or len(set(modes)) != len(modes):
        raise PkmError(f"modes = {modes} violates: at least one working mode, none repeated")
    resolution = _check_int("resolution", resolution, 3)
    sampled = region == "reachable"
    if pose_resolution is None:
        pose_resolution = regions.SAMPLED_RESOLUTION if sampled else regions.DISC_RESOLUTION
    pose_resolution = _check_int("pose_resolution", pose_resolution, 2 if sampled else 1)
    if sampled and not 0 <= singularity_margin < 1:
        raise PkmError(f"singularity_margin = {singularity_margin} violates 0 <= singularity_margin < 1")

    start = time.perf_counter()
    ds = spaces[space]
    u, v, inside = ds.chart_grid(resolution)
    U, V = np.meshgrid(u, v, indexing="ij")
    designs = ds.designs(mech.parameters, ds.from_chart(U[inside], V[inside]))
    if sampled:
        per_design = pose_resolution**2
    else:
        per_design = len(mech.parametrised_regions()[region].nodes(pose_resolution, spec.reduce)[1])
    values, points = {}, {}
    for mode in modes:
        branch = mech.working_mode(mode)
        values[mode] = np.full(inside.shape, np.nan)
        points[mode] = np.zeros(inside.shape, dtype=int)
        if sampled:
            result = regions.sampled_global(
                mech, spec, designs, branch, resolution=pose_resolution,
                singularity_margin=singularity_margin, progress=progress,
            )
            values[mode][inside] = np.array(result, dtype=float)
            points[mode][inside] = [g.points for g in result]
        else:
            param = mech.parametrised_regions()[region]
            values[mode][inside] = regions.parametrised_global(
                mech, spec, param, designs, branch=branch, resolution=pose_resolution
            )
            points[mode][inside] = np.where(np.isfinite(values[mode][inside]), per_design, 0)
            if progress is not None:
                progress(len(designs))
    return Atlas(
        mechanism=mech, index=spec.name, space=space, region=region, modes=modes, u=u, v=v, inside=inside,
        values=values, points=points, resolution=resolution, pose_resolution=pose_resolution,
        singularity_margin=float(singularity_margin) if sampled else None,
        wall_time=time.perf_counter() - start, evaluations=len(designs) * per_design * len(modes),
    )
