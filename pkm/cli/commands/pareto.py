"""``pkm pareto``: a verified Pareto front of a problem's objective against a secondary one
(:func:`pkm.synthesis.pareto.pareto`, docs/pareto.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pkm.cli.arguments import example, integer, listed, number
from pkm.cli.common import emit, given_problem, logs_to_stderr
from pkm.synthesis.pareto import FRONT_TOLERANCE

HELP = ("a verified Pareto front of a problem's objective against a secondary one by the epsilon-constraint method "
        "(front.json, front.csv, figures, report.md)")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The problem and its secondary objective, the front's points and tolerance, the resolution, the
    baselines, the output folder."""
    listed(p, "problem", key="problem")
    example(p, "--secondary", required=True, help="the secondary objective, one of the problem's quantities or "
                                                  "secondaries (required, no default); e.g. {secondary}")
    p.add_argument("--points", type=integer, help="distinct designs on the front, at least 2 (default: as many as "
                                                  "it takes for --tolerance); e.g. 5")
    p.add_argument("--tolerance", type=number, default=FRONT_TOLERANCE,
                   help="the hypervolume the front's points may leave open between them, as a share of the anchors' "
                        f"box (default {FRONT_TOLERANCE:g}); e.g. 0.01")
    p.add_argument("--resolution", type=integer, help="quadrature resolution (default: the problem's); e.g. 4")
    p.add_argument("--baselines", default="grid", help="comma-separated among grid and nsga2 (pymoo) (default "
                                                       "grid); e.g. grid,nsga2")
    p.add_argument("--out", help="folder for the front's files (default: none); e.g. fronts")


def run(args: argparse.Namespace) -> None:
    """A verified Pareto front of a problem's objective against a secondary one (:func:`pkm.pareto`), written
    with its figure and report where ``--out`` is given."""
    from pkm.synthesis.pareto import pareto

    with logs_to_stderr(args.json):
        front = pareto(given_problem(args.problem), args.secondary, n=args.points, tolerance=args.tolerance,
                       resolution=args.resolution, baselines=tuple(b for b in args.baselines.split(",") if b))
    if args.out:
        front.write(Path(args.out))
    emit(args, front.to_dict(), str(front))
