"""``pkm design``: a designer's synthesis from a TOML file (:func:`pkm.synthesis.designer.read_problem`)."""

from __future__ import annotations

import argparse

from pkm.cli.arguments import integer
from pkm.cli.commands.synth import certified, certify_option, report
from pkm.cli.common import logs_to_stderr
from pkm.synthesis import SynthesisError, synthesize

HELP = ("a synthesis for the designer's task, variables, objective and constraints, from a TOML file "
        "(docs/mechanisms.md), solved with IPOPT and verified")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The task file, the resolution, starts and log, the output folder."""
    p.add_argument("task", help="the problem's TOML file: mechanism, task, variables, fixed, objective, "
                                "constraints, mode, baseline; e.g. my_task.toml")
    p.add_argument("--resolution", type=integer, help="quadrature resolution (default: the file's, 8); e.g. 6")
    p.add_argument("--starts", type=integer, help="IPOPT starts from the best screening points (default 4); e.g. 2")
    p.add_argument("--verbose", action="store_true", help="show IPOPT's iterations (default off)")
    p.add_argument("--out", help="folder for <problem>.json, written also when the synthesis fails (default: "
                                 "none); e.g. results")
    certify_option(p)


def run(args: argparse.Namespace) -> None:
    """A designer's synthesis from a TOML file (:func:`pkm.synthesis.designer.read_problem`), solved and
    reported as ``synth`` does."""
    from pkm.synthesis.designer import read_problem

    problem = read_problem(args.task)
    args.problem = problem.name
    try:
        with logs_to_stderr(args.json):
            result = synthesize(problem, resolution=args.resolution, starts=args.starts, verbose=args.verbose)
    except SynthesisError as exc:
        if exc.result is not None:
            report(args, exc.result)
        raise
    report(args, result, certified(problem, result) if args.certify else None)
