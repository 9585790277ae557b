"""What ``pkm atlas`` and ``pkm sweep`` share: the options of a design grid, the design space they read, and
the atlases over it (:func:`pkm.atlas.compute_sweep`), chunks kept for an interrupted run to resume."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from pkm import parallel
from pkm.cli.arguments import RESOLUTION, example, integer, listed, number
from pkm.cli.common import given_design, given_region
from pkm.design_space import parameter_plane, parse_axes
from pkm.errors import PkmError, UnknownNameError, check_integer
from pkm.mechanism import Mechanism
from pkm.parallel import task_key


def options(p: argparse.ArgumentParser) -> None:
    """The design space or axes, the region and modes, the resolutions, the checks of the best design and the
    executor."""
    from pkm.atlas import Checks

    listed(p, "--space", key="space")
    example(p, "--axes", help="two design parameters with bounds instead of a design space (default: none): "
                              "name=lower:upper,name=lower:upper; e.g. --axes {axes}")
    example(p, "--design", help="with --axes, the design whose other parameters the atlas holds (default: "
                                "the defaults): name=value in SI; e.g. {parameter}")
    listed(p, "--region", key="region", default="reachable")
    listed(p, "--modes", key="modes")
    p.add_argument("--resolution", type=integer, default=41, help="design grid nodes per chart axis (default 41, "
                                                                  "3 to 4001); e.g. 21")
    p.add_argument("--pose-resolution", type=integer, help=RESOLUTION)
    p.add_argument("--tolerance", type=number, default=Checks.tolerance,
                   help=f"the best design's value must change by less than this (relative) when the pose "
                        f"resolution doubles (default {Checks.tolerance}, in (0, 1)); e.g. 0.005")
    p.add_argument("--min-points", type=integer, default=Checks.min_points,
                   help=f"the best design's region must hold at least this many poses or nodes "
                        f"(default {Checks.min_points}); e.g. 100")
    p.add_argument("--min-fraction", type=number, default=Checks.min_fraction,
                   help=f"the best design's region must measure at least this fraction of its workspace box "
                        f"(default {Checks.min_fraction}, in [0, 1)); e.g. 0.05")
    p.add_argument("--executor", choices=parallel.EXECUTORS, default="auto",
                   help="where the chunks run: auto (a Dask scheduler if set, else serial for small jobs and "
                        "local processes for large ones), serial or processes; default auto; e.g. serial")


def _space(m: Mechanism, args: argparse.Namespace) -> Any:
    """The design space of the command: a plane of two parameters (``--axes``) or one of the mechanism's."""
    if args.axes:
        base = dict(given_design(m, args.design)) if args.design else None
        return parameter_plane(m.parameters, parse_axes(args.axes, "--axes"), base=base)
    if args.design:
        raise PkmError("--design holds the parameters off the chart of an atlas over --axes; a design space "
                       "fixes its own")
    if not m.design_spaces:
        raise PkmError(f"the {m.name} has no design space to draw an atlas in: give --axes")
    name = args.space or next(iter(m.design_spaces))
    if name not in m.design_spaces:
        raise UnknownNameError(f"{m.name} design space", name, sorted(m.design_spaces))
    return m.design_spaces[name]


def atlases(m: Mechanism, args: argparse.Namespace, names: list[str], store: Path) -> dict[str, Any]:
    """The atlases of ``names`` over the command's design space, chunks kept in ``store``."""
    from pkm.atlas import MAX_CHART, Checks, compute_sweep, default_modes

    space = _space(m, args)
    indices = tuple(m.global_spec(name) for name in names)
    region = given_region(m, args.region)
    modes = tuple(args.modes.split(",")) if args.modes else default_modes(m, region)
    check_integer("resolution", args.resolution, 3, MAX_CHART)
    checks = Checks(tolerance=args.tolerance, min_points=args.min_points, min_fraction=args.min_fraction)
    return compute_sweep(
        m, indices, space=space, modes=modes, region=region, resolution=args.resolution,
        pose_resolution=args.pose_resolution, executor=args.executor, store=store, checks=checks,
    )


def run_key(m: Mechanism, args: argparse.Namespace, names: list[str]) -> str:
    """The key of a run's chunks: what the atlases depend on."""
    return task_key(m.name, names, args.space, args.axes, args.design, args.region, args.modes, args.resolution,
                    args.pose_resolution)
