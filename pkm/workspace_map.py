"""A design's workspace seen through a plane of two pose coordinates: a local index over the poses a working
mode reaches, the singularity curves (det = 0 of the type-I and type-II matrices) and a task region's
nodes near the plane, as arrays (npz) and as a figure (PNG or SVG).

The other pose coordinates are held at given values (by default the centre of the mechanism's workspace
box). Everything is evaluated through the mechanism's batch methods (compiled at first use)."""

from __future__ import annotations

import json
import os
import reprlib
import textwrap
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from pkm import figures, io
from pkm.errors import PkmError, check_real
from pkm.regions import region_name
from pkm.units import Units

RESOLUTION = 121  # poses per axis of the plane
MAX_RESOLUTION = 2001  # 4 million poses, a few hundred MB of arrays; odd, so that the plane's middle is a pose
REGION_RESOLUTION = 8  # of the region's quadrature whose nodes are drawn
NEAR = 0.02  # a region's node is drawn where its held coordinates lie within this share of the box's width
POSITION = ("x", "y", "z")  # pose coordinates that are the columns of a linkage's points


class CellsDrawing(NamedTuple):
    """A certification's boxes in the plane of the pose's first two coordinates
    (:func:`pkm.certify.certificate_drawing`): its boxes by state, each a quadrilateral ((n, 4, 2), "proved" and
    "undecided"), the region's outline (k, 2) and the witnesses' positions (w, 2)."""

    cells: dict[str, np.ndarray]
    outline: np.ndarray
    witnesses: np.ndarray


CELL_COLOURS = {"proved": "tab:green", "undecided": "tab:orange"}


def draw_cells(ax: Any, drawing: CellsDrawing, scales: tuple[float, float] = (1.0, 1.0), *,
               filled: bool = True) -> None:
    """The drawing on ``ax`` (its coordinates divided by ``scales``), each part labelled for a legend: the boxes by
    state (filled, or outlined over a map), the outline, the witnesses."""
    from matplotlib.collections import PolyCollection

    scale = np.asarray(scales)
    for state, colour in CELL_COLOURS.items():
        polygons = drawing.cells[state] / scale
        if len(polygons):
            ax.add_collection(PolyCollection(polygons, facecolors=colour if filled or state != "proved" else "none",
                                             edgecolors="white" if filled else colour,
                                             linewidths=0.2 if filled else 0.4, alpha=0.8 if filled else 0.6,
                                             label=f"{state} ({len(polygons)} boxes)"))
    ax.plot(*(drawing.outline / scale).T, color="k", linewidth=1.0, label="the region")
    for k, point in enumerate(drawing.witnesses / scale):
        ax.plot(*point, marker="x", color="tab:red", markersize=10, linestyle="none",
                label="" if k else "witness (refuted)")


@dataclass(frozen=True)
class WorkspaceSlice:
    """A local index over a plane of the pose (NaN where the mode does not reach), the singularity
    measures there and the plane's placement."""

    mechanism: Any
    design: Any
    mode: str
    index: Any  # a local index's name, or the index (an error model's pose_error)
    axes: tuple[str, str]
    held: Mapping[str, float]
    u: np.ndarray
    v: np.ndarray
    values: np.ndarray  # (len(u), len(v))
    singular: Mapping[str, np.ndarray] = field(default_factory=dict)
    region: str | None = None
    region_points: np.ndarray | None = None  # (k, 2): the region's nodes near the plane
    certified: CellsDrawing | None = None  # a certification of the region drawn over the map

    @property
    def index_name(self) -> str:
        return getattr(self.index, "name", self.index)

    def metadata(self, units: Units | None = None) -> dict[str, Any]:
        """What the map is of; with ``units``, its numbers and their units' names in them."""
        m, units = self.mechanism, units or Units()
        named = dict(zip(m.pose_names, m.pose_units, strict=True))
        return {"mechanism": m.name, "design": {p.name: units.value(float(self.design[p.name]), p.unit)
                                                for p in m.parameters},
                "mode": self.mode, "index": self.index_name, "unit": units.convert(m.index_unit(self.index))[1],
                "axes": list(self.axes), "held": {k: units.value(v, named[k]) for k, v in self.held.items()},
                "region": self.region}

    def save(self, path: str | os.PathLike) -> Path:
        """The arrays and the metadata (JSON) as an npz file, written atomically."""
        singular = {f"singular_{k}": v for k, v in self.singular.items()}
        arrays = {"u": self.u, "v": self.v, "values": self.values, **singular,
                  "metadata": np.array(json.dumps(self.metadata()))}
        if self.region_points is not None:
            arrays["region_points"] = self.region_points
        return io.atomic_write(Path(path), lambda tmp: np.savez_compressed(tmp, **arrays))

    def plot(self, path: str | os.PathLike, *, linkage: Sequence[np.ndarray] = (), units: Units | None = None
             ) -> Path:
        """The map: the index's colours (robust limits), the type-I (black) and type-II (red) singularity
        curves, the region's nodes near the plane (white dots), a certification's boxes where the map has one
        (outlined: proved green, undecided orange, witnesses red), axes to scale where both are lengths; with
        ``linkage`` (each leg's joint points, :meth:`pkm.Mechanism.linkage`) the legs and the platform drawn
        in the plane's coordinates where they are positions; with ``units`` every axis and value in them."""
        m, units = self.mechanism, units or Units()
        if not np.isfinite(self.values).any():
            raise PkmError(f"the {self.mode} mode of {m.name} reaches no pose of the plane {', '.join(self.axes)} "
                           f"at {self.held}")
        named = dict(zip(m.pose_names, m.pose_units, strict=True))
        su, sv = (units.scale(named[a]) for a in self.axes)
        values = self.values / units.convert(m.index_unit(self.index))[0]
        limits = figures.robust_limits(values)
        U, V = np.meshgrid(self.u / su, self.v / sv, indexing="ij")
        fig = figures.figure(6.4, 5.6)
        ax = fig.subplots()
        filled = ax.pcolormesh(U, V, np.ma.masked_invalid(values), cmap="viridis", vmin=limits.vmin,
                               vmax=limits.vmax, shading="nearest")
        styles = {"det_type1": ("k", "type I"), "det_type2": ("tab:red", "type II")}
        for name, det in self.singular.items():
            colour, label = styles.get(name, ("tab:orange", name))
            if np.nanmin(det) < 0 < np.nanmax(det):
                ax.contour(U, V, det, levels=[0.0], colors=colour, linewidths=1.2)
                ax.plot([], [], color=colour, label=f"{label} singularity")
        if self.region_points is not None and len(self.region_points):
            ax.plot(self.region_points[:, 0] / su, self.region_points[:, 1] / sv, "o", markerfacecolor="white",
                    markeredgecolor="k", markeredgewidth=0.3, markersize=3, linestyle="none",
                    label=f"region {self.region} (nodes near the plane)")
        if self.certified is not None:
            draw_cells(ax, self.certified, (su, sv), filled=False)
        self._draw_linkage(ax, linkage, (su, sv))
        ax.set_xlabel(f"{self.axes[0]} [{units.name(named[self.axes[0]])}]")
        ax.set_ylabel(f"{self.axes[1]} [{units.name(named[self.axes[1]])}]")
        if named[self.axes[0]] == named[self.axes[1]]:
            ax.set_aspect("equal")
        held = ", ".join(f"{k} = {units.value(v, named[k]):.3g} {units.name(named[k])}" for k, v in self.held.items())
        ax.set_title(textwrap.fill(f"{m.name}, mode {self.mode}" + (f"; {held}" if held else ""), 60), fontsize=10)
        unit = units.convert(m.index_unit(self.index))[1]
        figures.colour_bar(fig, filled, limits, ax=ax,
                           label=f"{self.index_name}" + (f" [{unit}]" if unit != "-" else ""))
        if ax.get_legend_handles_labels()[0]:
            figures.legends_below([ax], fontsize=8, ncols=3)
        return figures.save(fig, path, dpi=120)


    def _draw_linkage(self, ax: Any, linkage: Sequence[np.ndarray], scales: tuple[float, float]) -> None:
        columns = plane_columns(self.axes, linkage)
        if columns is None:
            return
        scale = np.asarray(scales)
        for k, leg in enumerate(linkage):
            drawn = leg[:, list(columns)] / scale
            ax.plot(drawn[:, 0], drawn[:, 1], "-o", color="k", linewidth=1.6, markersize=3.5,
                    markerfacecolor="white", label="linkage" if k == 0 else None)
        ends = np.array([leg[-1, columns] for leg in linkage] + [linkage[0][-1, columns]]) / scale
        ax.plot(ends[:, 0], ends[:, 1], "-", color="k", linewidth=1.0)


def plane_columns(axes: Sequence[str], linkage: Sequence[np.ndarray]) -> list[int] | None:
    """The columns of the linkage's points (:meth:`pkm.Mechanism.linkage`) that are the plane's ``axes``, where
    both axes are positions and the linkage is drawn (finite); None otherwise."""
    if not len(linkage) or not all(a in POSITION for a in axes) or not np.all(np.isfinite(linkage[0])):
        return None
    columns = [POSITION.index(a) for a in axes]
    return None if max(columns) >= linkage[0].shape[1] else columns


def check_plane(
    mech: Any,
    *,
    axes: Sequence[str] | None = None,
    held: Mapping[str, float] | None = None,
    resolution: int = RESOLUTION,
) -> tuple[tuple[str, str], dict[str, float], int]:
    """A plane's ``axes`` (the first two pose coordinates by default), its ``held`` coordinates (each a pose
    coordinate off the plane, at a finite value) and its ``resolution`` (3 to MAX_RESOLUTION poses per axis),
    checked before anything is computed; :class:`PkmError` naming the one that violates its condition."""
    names = list(mech.pose_names)
    axes = tuple(axes or names[:2])
    if len(axes) != 2 or len(set(axes)) != 2 or not set(axes) <= set(names):
        raise PkmError(f"axes = {reprlib.repr(axes)} violates: two distinct pose coordinates of {mech.name} "
                       f"({', '.join(names)})")
    if (isinstance(resolution, bool) or not isinstance(resolution, int | np.integer)
            or not 3 <= resolution <= MAX_RESOLUTION):
        raise PkmError(f"resolution = {reprlib.repr(resolution)} violates: resolution >= 3 and <= {MAX_RESOLUTION}, "
                       "an integer (poses per axis)")
    checked = {}
    for name, value in dict(held or {}).items():
        if name not in names:
            raise PkmError(f"held coordinate {reprlib.repr(name)} violates: one of {', '.join(names)}")
        if name in axes:
            raise PkmError(f"held coordinate {name!r} violates: a coordinate off the plane {', '.join(axes)}")
        checked[name] = check_real(f"held coordinate {name}", value)
    return axes, checked, int(resolution)


def workspace_slice(
    mech: Any,
    design: Any = None,
    *,
    index: Any = "inverse_condition_f",
    mode: str | None = None,
    axes: tuple[str, str] | None = None,
    held: Mapping[str, float] | None = None,
    region: str | Any | None = None,
    resolution: int = RESOLUTION,
) -> WorkspaceSlice:
    """The local index ``index`` (a name, or the index: an error model's ``pose_error``) over the plane of the pose
    coordinates ``axes`` (the first two by default)
    across the workspace box, the others at ``held`` (by default the box's centre), in working mode
    ``mode``; with ``region`` (a parametrised region of the mechanism, or one given as it is) its nodes near
    the plane. The plane's
    options are checked first (:func:`check_plane`)."""
    axes, given, resolution = check_plane(mech, axes=axes, held=held, resolution=resolution)
    design = mech.design(design)
    branch = mech.working_mode(mode)
    names = list(mech.pose_names)
    box = mech.workspace_box(design.vector())
    centre = box.mean(axis=1)
    for k, name in enumerate(names):
        if name not in axes:
            given.setdefault(name, float(centre[k]))
    i, j = names.index(axes[0]), names.index(axes[1])
    u = np.linspace(box[i, 0], box[i, 1], resolution)
    v = np.linspace(box[j, 0], box[j, 1], resolution)
    x = np.tile(np.array([given.get(n, 0.0) for n in names]), (resolution * resolution, 1))
    U, V = np.meshgrid(u, v, indexing="ij")
    x[:, i], x[:, j] = U.ravel(), V.ravel()
    values = mech.local_index(index, x, design, mode=branch.name).reshape(resolution, resolution)
    reach = mech.reachable(x, design, mode=branch.name).reshape(resolution, resolution)
    values = np.where(reach, values, np.nan)
    singular = {k: np.where(reach, d.reshape(resolution, resolution), np.nan)
                for k, d in mech.singularity(x, design, mode=branch.name).items()}
    nodes = None
    if region is not None:
        points, _ = mech.region(region).quadrature(mech.functions, design.vector(), REGION_RESOLUTION)
        others = [k for k in range(len(names)) if k not in (i, j)]
        width = np.maximum(box[:, 1] - box[:, 0], 1e-12)
        near = np.all(np.abs(points[:, others] - x[0, others]) <= NEAR * width[others], axis=1)
        nodes = points[near][:, [i, j]]
    return WorkspaceSlice(mech, design, branch.name, index, axes, {k: v for k, v in given.items() if k not in axes},
                          u, v, values, singular, region_name(region), nodes)
