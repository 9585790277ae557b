"""``pkm show``: a design card (:mod:`pkm.card`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pkm import io
from pkm.cli.arguments import card_options, design_option, example, listed, map_resolution, number, units_option
from pkm.cli.common import (
    design_in,
    emit,
    given_design,
    given_modes,
    given_region,
    given_units,
    load_mechanism,
    numbers,
    unit_text,
    with_units,
)
from pkm.design import parse_design
from pkm.errors import PkmError
from pkm.units import placement_text

HELP = ("a design card: workspace maps per working mode with singularity curves, the region and the linkage, every "
        "assembly at the linkage's actuated joints, and a table of parameters and global indices")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism and design, the modes and region, the maps' index, plane and resolution."""
    listed(p, "mechanism", key="mechanism")
    design_option(p)
    card_options(p, "the global indices and the map's nodes")
    example(p, "--index", default="inverse_condition_f", help="local index of the maps (default "
                                                              "inverse_condition_f); e.g. {local}")
    p.add_argument("--tolerances", type=number, help="maps of the worst-case position error under this tolerance "
                   "on every part's geometry (the error model's pose_error, docs/accuracy.md) instead of --index "
                   "[m, or --units' length] (default: none, the maps of --index); e.g. 1e-5")
    p.add_argument("--plane", help="two pose coordinates of the maps (default: the first two); e.g. x,z")
    p.add_argument("--held", help="values of the other pose coordinates (default: the region's centre); e.g. "
                                  "z=-0.5")
    p.add_argument("--certify", action="store_true", help="certify the region in each mode (singularities and "
                   "limits, pkm certify) and draw its boxes over the maps (default: off)")
    map_resolution(p, default=81, suggested=121)
    p.add_argument("--out", required=True, help="folder for report.json, report.md, the maps and "
                                                "assemblies.png, .svg (no default); e.g. card")
    units_option(p)


def run(args: argparse.Namespace) -> None:
    """A design card (:mod:`pkm.card`) into ``--out``."""
    from pkm.card import design_card

    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    modes = given_modes(m, args.mode)
    axes = tuple(args.plane.split(",")) if args.plane else None
    held = parse_design(args.held, "held coordinates", "pose coordinate", PkmError) if args.held else None
    if held is not None:
        named = dict(zip(m.pose_names, m.pose_units, strict=True))
        held = {k: v * units.scale(named.get(k, "-")) for k, v in held.items()}
    index = args.index
    if args.tolerances is not None:
        index = m.error_model().index(args.tolerances * units.scale("m"))
    card = design_card(m, d, modes=modes, region=given_region(m, args.region) if args.region else None,
                       index=index, axes=axes, held=held, resolution=args.resolution, units=units,
                       certify=args.certify)
    folder = Path(args.out)
    written = io.write_result(folder, card.write)
    data = {**card.to_dict(), "files": [str(p) for p in written]}
    lines = [f"{m.name} at {with_units(design_in(m, d, units), m, units)}"]
    if card.placement is not None:
        lines.append(f"region {card.region}: {placement_text(card.placement)}")
    lines += [f"SINGULAR: the linkage's pose {numbers(data['pose'].values())} is a {' and '.join(types)} "
              f"singularity in mode {mode}" for mode, types in card.singular.items()]
    if card.assemblies is not None:
        lines.append(card.assemblies.text())
    lines += [f"certified over {card.region} in mode {mode}: {c.verdict.upper()} ({c.boxes} boxes"
              + (f"; {c.undecided:.3g} of the region's box undecided" if c.undecided else "") + ")"
              for mode, c in card.certified.items()]
    lines += [f"{r['index']} ({r['mode']}) = {r['value']:.6g}{unit_text(r['unit'])} (resolution {r['resolution']}, "
              f"accuracy {r['accuracy']:.1e})" for r in card.indices]
    lines.append(f"wrote {len(written)} files to {io.kept_path(folder)}")
    emit(args, data, "\n".join(lines))
