"""``pkm compare``: designs side by side (:func:`pkm.card.compare`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pkm import io
from pkm.cli.arguments import card_options, example, listed, map_resolution, units_option
from pkm.cli.common import emit, given_design, given_modes, given_region, given_units, load_mechanism

HELP = ("designs side by side: their cards and one table of every global index per design and mode (JSON, CSV, "
        "markdown)")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism, two designs or more, the modes and region, the maps' resolution."""
    listed(p, "mechanism", key="mechanism")
    example(p, "--design", action="append", required=True, help="a design as name=value in SI (repeat for each "
                                                                "design, at least two; no default); e.g. {parameter}")
    card_options(p, "the global indices")
    map_resolution(p, default=61, suggested=81)
    p.add_argument("--out", required=True, help="folder for comparison.json, .csv, .md and a card per design "
                                                "(no default); e.g. compared")
    units_option(p)


def run(args: argparse.Namespace) -> None:
    """Designs side by side (:func:`pkm.card.compare`) into ``--out``."""
    from pkm.card import compare

    m = load_mechanism(args.mechanism)
    units = given_units(args)
    designs = [given_design(m, text, units) for text in args.design]
    modes = given_modes(m, args.mode)
    comparison = compare(m, designs, modes=modes, region=given_region(m, args.region) if args.region else None,
                         resolution=args.resolution, units=units)
    folder = Path(args.out)
    written = io.write_result(folder, comparison.write)
    data = {**comparison.to_dict(), "files": [str(p) for p in written]}
    emit(args, data, comparison.markdown() + f"\n\nwrote {len(written)} files to {io.kept_path(folder)}")
