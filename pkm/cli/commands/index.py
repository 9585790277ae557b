"""``pkm index``: a global index of a design over a region, with its accuracy and, asked, its gradient."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.cli.arguments import RESOLUTION, integer, listed, number, units_option
from pkm.cli.common import design_in, emit, given_design, given_region, given_units, load_mechanism, unit_text
from pkm.errors import PkmError
from pkm.regions import SINGULARITY_MARGIN, region_name
from pkm.units import placement_in, placement_text

HELP = "a global index of a design"
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism and index, the design, mode and region, the resolution and margin, the gradient."""
    listed(p, "mechanism", key="mechanism")
    listed(p, "index", key="index")
    listed(p, "--design", key="design")
    listed(p, "--mode", key="mode")
    listed(p, "--region", key="region", default="reachable")
    p.add_argument("--resolution", type=integer, help=RESOLUTION)
    p.add_argument("--margin", type=number, help=f"singularity margin of the sampled region: poses with 1/kappa_f "
                                                 f"below it are left out (default {SINGULARITY_MARGIN}, in [0, 1)); "
                                                 f"e.g. 0.05")
    p.add_argument("--gradient", action="store_true",
                   help="also the exact gradient in every design parameter (parametrised regions; default off)")
    p.add_argument("--out", help="folder for index.json and index.csv (default: none); e.g. results")
    units_option(p)


def run(args: argparse.Namespace) -> None:
    """The index's value, accuracy and convergence, the region's placement, and the gradient where asked."""
    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    mode = m.working_mode(args.mode).name
    region = given_region(m, args.region)
    args.region = region_name(region)
    out = m.global_index(
        args.index,
        d,
        region=region,
        mode=mode,
        resolution=args.resolution,
        gradient=args.gradient,
        singularity_margin=args.margin,
    )
    value, grad = out if args.gradient else (out, None)
    unit = m.index_unit(args.index)
    scale, shown = units.convert(unit)
    data = {
        "mechanism": m.name,
        "index": args.index,
        "region": args.region,
        "mode": mode,
        "design": design_in(m, d, units),
        "value": float(value) / scale,
        "points": value.points,
        "resolution": value.resolution,
        "accuracy": value.accuracy / scale,
        "unit": shown,
    }
    if grad is not None:
        grad = {p.name: grad[p.name] * units.convert(p.unit)[0] / scale for p in m.parameters}
    text = f"{args.index} over {args.region} ({mode}, {value.points} points) = {data['value']:.8g}{unit_text(shown)}"
    if np.isfinite(value.accuracy):
        text += f" (accuracy {data['accuracy']:.1e}, resolution {value.resolution})"
    data["converged"] = value.converged
    if not value.converged:
        text += f"\nNOT CONVERGED: {value.note.removeprefix('not converged: ')}"
    if np.isnan(float(value)):
        data["undefined"] = _undefined(m, region)
        text += f" (undefined: {data['undefined']})"
    if args.region not in {"reachable", "assembled"}:
        try:
            placed = m.region_placement(region, d)
        except PkmError:
            placed = None
        if placed is not None:
            data["placement"] = placed = placement_in(m, region, placed, units)
            text += f"\nregion {args.region}: {placement_text(placed)}"
    if args.out:
        columns = ["mechanism", "index", "region", "mode", f"value [{shown}]", "points", "resolution",
                   f"accuracy [{shown}]", *(f"{p.name} [{units.convert(p.unit)[1]}]" for p in m.parameters)]
        row = [m.name, args.index, args.region, mode, data["value"], value.points, value.resolution,
               data["accuracy"], *data["design"].values()]

        def write(folder: Path) -> list[Path]:
            return [io.write_text(folder / "index.json", io.to_json({**data, **({"gradient": grad} if grad else {})})),
                    io.write_text(folder / "index.csv", io.csv_text(columns, [row]))]

        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(Path(args.out), write))
    if grad is not None:
        data["gradient"] = grad
        text += "\ngradient: " + ", ".join(
            f"d/d{p.name} = {grad[p.name]:.6g}{unit_text(_per(shown, units.convert(p.unit)[1]))}"
            for p in m.parameters)
        if value.note and value.converged:
            text += f"\nnote: {value.note}"
    if value.note:
        data["note"] = value.note
    emit(args, data, text)


def _per(unit: str, other: str) -> str:
    """The unit of a derivative of ``unit`` in a quantity of unit ``other`` (``-`` for a pure number)."""
    if other == "-":
        return unit
    other = f"({other})" if any(c in other for c in " /") else other
    return f"1/{other}" if unit == "-" else f"{unit}/{other}"


def _undefined(m: Any, region: str | Any) -> str:
    """Why an index over a region can be NaN."""
    guard = getattr(m.region(region), "guard", None)
    reasons = ["a node of the region is out of reach in this mode"]
    if guard is not None:
        reasons.append(f"or fails a margin of {guard} (a singularity or a joint limit inside the region)")
    return " ".join(reasons)
