"""A design card: one design of a mechanism shown and tabulated (``pkm show``).

Per working mode, a workspace map of a local index over a plane of the pose (:mod:`pkm.workspace_map`) with
the singularity curves, a region's nodes and the linkage drawn at a pose where the mechanism can draw it; every
assembly at the actuated joints of that pose in the first mode (:mod:`pkm.drawn_assemblies`), one panel each; a
table of the design's parameters with units and of its global indices over the region, each with its unit,
resolution and accuracy. Written as report.json, report.md, one PNG and SVG per mode and assemblies.png and .svg
(where pkm can list the mechanism's assemblies and the pose is in reach)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io, registry
from pkm.drawn_assemblies import AssembliesAtPose, assemblies_at_pose, assemblies_figure
from pkm.errors import PkmError
from pkm.regions import region_name
from pkm.units import Units, placement_in, placement_text
from pkm.workspace_map import WorkspaceSlice, check_plane, workspace_slice

SLOW = ("lambda_e",)  # indices whose adaptive quadrature a card leaves out (an eigenvalue problem per node)


@dataclass
class Card:
    """A design's card: its maps per mode and its table."""

    mechanism: Any
    design: Any
    region: str
    maps: dict[str, WorkspaceSlice]
    pose: np.ndarray
    indices: list[dict[str, Any]] = field(default_factory=list)
    placement: dict[str, Any] | None = None
    units: Units = field(default_factory=Units)  # every number of the card's files in them
    singular: dict[str, list[str]] = field(default_factory=dict)  # the singularities the pose is at, per mode
    assemblies: AssembliesAtPose | None = None  # every assembly at the pose's actuated joints in the first mode
    certified: dict[str, Any] = field(default_factory=dict)  # the region certified per mode (pkm.certify)

    def to_dict(self) -> dict[str, Any]:
        m, units = self.mechanism, self.units
        return {
            "mechanism": m.name,
            "design": [{"name": p.name, "value": units.value(float(self.design[p.name]), p.unit),
                        "unit": units.convert(p.unit)[1], "doc": p.doc} for p in m.parameters],
            "region": self.region,
            "placement": self.placement,
            "pose": dict(zip(m.pose_names, units.from_si(self.pose, m.pose_units).tolist(), strict=True)),
            "pose_units": dict(zip(m.pose_names, [units.name(u) for u in m.pose_units], strict=True)),
            "singular": self.singular,
            "maps": {mode: s.metadata(units) for mode, s in self.maps.items()},
            "global_indices": self.indices,
            "assemblies": None if self.assemblies is None else self.assemblies.summary(m, units),
            "certified": {mode: c.as_dict() for mode, c in self.certified.items()},
        }

    def markdown(self, figures: Mapping[str, str], assemblies: str | None = None) -> str:
        """The card as Markdown: its tables, the maps ``figures`` (file name per mode) and the assemblies' figure
        ``assemblies`` (a file name, None where none was drawn)."""
        m, units = self.mechanism, self.units
        lines = [f"# {m.name}: design card", "", m.doc, "", "## Design", "", "| parameter | value | unit | meaning |",
                 "|---|---|---|---|"]
        lines += [f"| {p.name} | {units.value(float(self.design[p.name]), p.unit):.6g} | {units.convert(p.unit)[1]} "
                  f"| {p.doc} |" for p in m.parameters]
        if self.placement is not None:
            lines += ["", f"Region {self.region}: {placement_text(self.placement)}."]
        for mode, types in self.singular.items():
            lines += ["", f"SINGULAR: the linkage's pose is a {' and '.join(types)} singularity in mode {mode}: the "
                          "local indices there are their limits, not the machine's."]
        lines += ["", f"## Global indices over {self.region}", "", "| index | mode | value | unit | resolution | "
                  "accuracy |", "|---|---|---|---|---|---|"]
        for row in self.indices:
            value = "NaN" if not math.isfinite(row["value"]) else f"{row['value']:.6g}"
            lines.append(f"| {row['index']} | {row['mode']} | {value} | {row['unit']} | {row['resolution']} | "
                         f"{row['accuracy']:.1e} |")
        if self.certified:
            lines += ["", f"## Certified over {self.region}", "", "| mode | properties | verdict | boxes | undecided | "
                      "witness |", "|---|---|---|---|---|---|"]
            for mode, c in self.certified.items():
                properties = ", ".join(f"{p} >= {v:g}" for p, v in c.properties.items())
                witness = ", ".join(f"{k} = {v:.6g}" for k, v in c.witnesses[0]["pose"].items()) if c.witnesses else ""
                lines.append(f"| {mode} | {properties} | {c.verdict} | {c.boxes} | {c.undecided:.3g} | {witness} |")
        lines += ["", "## Workspace", ""]
        for mode, name in figures.items():
            lines += [f"![{m.name} {mode}]({name})", ""]
        if self.assemblies is not None:
            lines += ["## Assemblies", "", self.assemblies.text() + ".", ""]
            lines += [f"![{m.name} assemblies]({assemblies})", ""] if assemblies else []
        return "\n".join(lines)

    def write(self, folder: Path) -> list[Path]:
        """report.json, report.md, the maps and the assemblies' figure (PNG and SVG) in ``folder``."""
        from pkm.figures import save

        folder.mkdir(parents=True, exist_ok=True)
        written, figures, assemblies = [], {}, None
        for mode, s in self.maps.items():
            linkage = self.mechanism.linkage(self.pose, self.design, mode=mode)
            for suffix in ("png", "svg"):
                name = f"workspace_{mode}.{suffix}"
                written.append(s.plot(folder / name, linkage=linkage, units=self.units))
            figures[mode] = f"workspace_{mode}.png"
        if self.assemblies is not None and len(self.assemblies.poses):
            fig = assemblies_figure(self.mechanism, self.design, self.assemblies.poses, self.assemblies.modes)
            written += [save(fig, folder / f"assemblies.{suffix}", dpi=150) for suffix in ("png", "svg")]
            assemblies = "assemblies.png"
        written.append(io.atomic_write(folder / "report.json", lambda p: p.write_text(io.to_json(self.to_dict()))))
        text = self.markdown(figures, assemblies)
        written.append(io.atomic_write(folder / "report.md", lambda p: p.write_text(text)))
        return written


def _default_region(mech: Any) -> str:
    return next(iter(mech.regions), "reachable")


def region_centre(mech: Any, design: Any, region: str | Any) -> tuple[dict[str, Any] | None, np.ndarray | None]:
    """A region's placement at a design (:meth:`pkm.Mechanism.region_placement`, None where it has none) and its
    centre in the pose's coordinates: the placement's centre, else the mean of its coarsest quadrature's nodes;
    None for a sampled region."""
    if region in ("reachable", "assembled"):
        return None, None
    try:
        placement = mech.region_placement(region, design)
    except PkmError:
        placement = None
    if placement is not None and not placement["mapped"]:
        return placement, np.array(placement["centre"])
    nodes, _ = mech.region(region).quadrature(mech.functions, mech.design_vector(design), 2)
    return placement, np.mean(nodes, axis=0)


def design_card(
    mech: Any,
    design: Any = None,
    *,
    modes: Sequence[str] | None = None,
    region: str | Any | None = None,
    index: Any = "inverse_condition_f",
    axes: tuple[str, str] | None = None,
    held: Mapping[str, float] | None = None,
    pose: Sequence[float] | None = None,
    indices: Sequence[str] | None = None,
    resolution: int = 81,
    units: Units | None = None,
    certify: bool = False,
) -> Card:
    """The card of a design in ``modes`` (all by default): maps of ``index`` (a local index's name, or the index:
    an error model's ``pose_error``) over the plane ``axes`` (the
    other coordinates at ``held``, by default the region's centre or the workspace box's), the linkage at
    ``pose`` (by default the region's centre, else the plane's middle), and every global index the mechanism
    offers (or ``indices``) over ``region`` (its first parametrised region by default, or a region given as it
    is: a task file's, :func:`pkm.synthesis.designer.task_of`), and every assembly at the actuated joints of the
    linkage's pose in the first of ``modes`` (:func:`pkm.drawn_assemblies.assemblies_at_pose`). The maps' options are
    checked before anything is computed (:func:`pkm.workspace_map.check_plane`). With ``units``, every number of
    the card's files (its table, its report and its figures' axes) is in them (:class:`pkm.units.Units`). With
    ``certify``, the region is certified in each mode (:meth:`pkm.Mechanism.certify`, its default properties) and,
    where the maps' plane is the pose's first two coordinates, its boxes drawn over each mode's map."""
    units = units or Units()
    axes, _, resolution = check_plane(mech, axes=axes, held=held, resolution=resolution)
    design = mech.design(design)
    region = region or _default_region(mech)
    where = mech.region(region)
    names = list(mech.pose_names)
    placement, centre = region_centre(mech, design, region)
    if held is None and centre is not None:
        held = {n: float(centre[k]) for k, n in enumerate(names) if n not in axes}
    chosen = list(modes or mech.modes)
    allowed = getattr(where, "modes", None)
    maps = {mode: workspace_slice(mech, design, index=index, mode=mode, axes=axes, held=held,
                                  region=None if region in ("reachable", "assembled") else region,
                                  resolution=resolution) for mode in chosen}
    first = next(iter(maps.values()))
    if pose is None:
        pose = centre if centre is not None else np.array(
            [first.held.get(n, float(np.mean(first.u if n == axes[0] else first.v))) for n in names])
    pose = np.asarray(pose, dtype=float)
    singular = {mode: mech.singular_types(pose[None], design, mode=mode)[0] for mode in chosen}
    assemblies = assemblies_at_pose(mech, pose, design, mode=chosen[0])
    rows = []
    for name in indices or [i for i in mech.global_indices() if i not in SLOW]:
        for mode in chosen:
            if allowed and mode not in allowed:
                continue
            value = mech.global_index(name, design, region=region, mode=mode)
            scale, unit = units.convert(mech.index_unit(name))
            rows.append({"index": name, "mode": mode, "value": float(value) / scale, "unit": unit,
                         "resolution": value.resolution, "points": value.points,
                         "accuracy": float(value.accuracy) / scale if math.isfinite(value.accuracy) else float("nan")})
    if placement is not None:
        placement = placement_in(mech, where, placement, units)
    certified = {}
    if certify:
        if region in ("reachable", "assembled"):
            raise PkmError(f"region {region} violates: a parametrised region to certify (a sampled one is not)")
        from pkm.certify import certificate_drawing

        for mode in chosen:
            certified[mode] = mech.certify(region, design, mode=mode)
            if tuple(axes) == tuple(names[:2]):
                maps[mode] = replace(maps[mode], certified=certificate_drawing(mech, region, certified[mode], design))
    return Card(mech, design, region_name(where), maps, pose, rows, placement, units,
                {mode: types for mode, types in singular.items() if types}, assemblies, certified)


@dataclass
class Comparison:
    """Designs of one mechanism side by side: their cards and one table of every global index per design and
    mode, the best value of each row marked."""

    cards: list[Card]

    def rows(self) -> list[dict[str, Any]]:
        """One row per index and mode: each design's value, and which design is best in the index's sense."""
        table: dict[tuple[str, str], dict[str, Any]] = {}
        for k, card in enumerate(self.cards):
            for r in card.indices:
                empty = {"index": r["index"], "mode": r["mode"], "unit": r["unit"],
                         "values": [math.nan] * len(self.cards)}
                table.setdefault((r["index"], r["mode"]), empty)["values"][k] = r["value"]
        for row in table.values():
            sense = registry.global_index(row["index"]).sense
            finite = [(v, k) for k, v in enumerate(row["values"]) if math.isfinite(v)]
            row["best"] = (max if sense == "max" else min)(finite)[1] if finite else None
            row["differ"] = len({round(v, 9) for v, _ in finite}) > 1
        return list(table.values())

    def csv(self) -> str:
        names = [f"design_{k + 1}" for k in range(len(self.cards))]
        lines = [",".join(["index", "mode", "unit", *names, "best"])]
        for row in self.rows():
            best = "" if row["best"] is None else names[row["best"]]
            lines.append(",".join([row["index"], row["mode"], row["unit"], *(repr(v) for v in row["values"]), best]))
        return "\n".join(lines) + "\n"

    def to_dict(self) -> dict[str, Any]:
        return {"mechanism": self.cards[0].mechanism.name, "designs": [c.to_dict()["design"] for c in self.cards],
                "rows": self.rows()}

    def markdown(self) -> str:
        m = self.cards[0].mechanism
        names = [f"design {k + 1}" for k in range(len(self.cards))]
        lines = [f"# {m.name}: {len(self.cards)} designs compared", "",
                 "| parameter | unit | " + " | ".join(names) + " |", "|---|---|" + "---|" * len(names)]
        units = self.cards[0].units
        for p in m.parameters:
            lines.append(f"| {p.name} | {units.convert(p.unit)[1]} | "
                         + " | ".join(f"{units.value(float(c.design[p.name]), p.unit):.6g}" for c in self.cards) + " |")
        lines += ["", "Global indices (the best of each row in bold, where the designs differ):", "",
                  "| index | mode | unit | " + " | ".join(names) + " |", "|---|---|---|" + "---|" * len(names)]
        for row in self.rows():
            cells = []
            for k, v in enumerate(row["values"]):
                text = "NaN" if not math.isfinite(v) else f"{v:.6g}"
                cells.append(f"**{text}**" if row["differ"] and row["best"] == k else text)
            lines.append(f"| {row['index']} | {row['mode']} | {row['unit']} | " + " | ".join(cells) + " |")
        lines += ["", "Each design's card is in design_<k>/."]
        return "\n".join(lines)

    def write(self, folder: Path) -> list[Path]:
        folder.mkdir(parents=True, exist_ok=True)
        written = []
        for k, card in enumerate(self.cards):
            written += card.write(folder / f"design_{k + 1}")
        written.append(io.atomic_write(folder / "comparison.json", lambda p: p.write_text(io.to_json(self.to_dict()))))
        written.append(io.atomic_write(folder / "comparison.csv", lambda p: p.write_text(self.csv())))
        written.append(io.atomic_write(folder / "comparison.md", lambda p: p.write_text(self.markdown())))
        return written


def compare(mech: Any, designs: Sequence[Any], **options: Any) -> Comparison:
    """The cards of ``designs`` (:func:`design_card` with ``options``) and their table."""
    if len(designs) < 2:
        raise PkmError(f"designs = {len(designs)} violates: at least two designs to compare")
    return Comparison([design_card(mech, d, **options) for d in designs])
