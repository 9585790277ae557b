"""``pkm synth``: a synthesis problem solved with IPOPT and verified (:func:`pkm.synthesis.synthesize`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from pkm import io
from pkm.cli.arguments import example, integer, listed, number, scheduled
from pkm.cli.common import emit, given_problem, logs_to_stderr, named
from pkm.design import parse_design
from pkm.errors import PkmError
from pkm.synthesis import SynthesisError, SynthesisResult, synthesize
from pkm.synthesis.driver import constraint_lines

HELP = ("solve a synthesis problem with IPOPT and verify it (exit 1 with the record of the last iterate when it "
        "fails)")
PARALLEL = True


def options(p: argparse.ArgumentParser) -> None:
    """The problem and its settings, IPOPT's options, the output folder and the scheduler."""
    listed(p, "problem", key="problem")
    p.add_argument("--resolution", type=integer, help="quadrature resolution of the optimised indices (default: the "
                                                      "problem's, 8 for most); e.g. 6")
    p.add_argument("--starts", type=integer, help="IPOPT starts from the best screening points (default: the "
                                                  "problem's, 3 or 4; 1 to 1000); e.g. 2")
    p.add_argument("--max-iter", type=integer, help="IPOPT's max_iter per start (default: the problem's, 100 to 500); "
                                                    "e.g. 1000")
    p.add_argument("--tol", type=number, help="IPOPT's tol, > 0 (default: the problem's, 1e-10); e.g. 1e-8")
    p.add_argument("--print-level", type=integer, help="IPOPT's print_level, 0 to 12 (default 0, or 5 with "
                                                       "--verbose); e.g. 3")
    p.add_argument("--verbose", action="store_true", help="show IPOPT's iterations (default off)")
    example(p, "--set", help="the problem's settings as name=value in SI, comma-separated (default: the "
                             "problem's; `pkm list` names them); e.g. {setting}")
    p.add_argument("--out", help="folder for <problem>.json, written also when the synthesis fails (default: none); "
                                 "e.g. results")
    certify_option(p)
    scheduled(p)


def certify_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--certify", action="store_true", help="end with the optimum certified over the task: no "
                                                          "singularity (the problem's margin), every limit held "
                                                          "(pkm certify; default: off)")


def certified(problem: Any, result: SynthesisResult) -> dict[str, Any]:
    """The optimum certified over the problem's task region in its mode: its singularity margin (the problem's
    where it holds one, else pkm's singular pose's) and its limits (:func:`pkm.certify.certify`)."""
    region = problem.margin.region
    margin = problem.margin.value
    found = problem.mechanism.certify(region, result.optimum.design, properties=("singularity", "limits"),
                                      mode=result.mode, threshold=margin if margin else None)
    return found.as_dict()


def run(args: argparse.Namespace) -> None:
    """Solve and report; a failed synthesis still writes and prints its record (the last iterate) before
    it fails with the reason (exit 1; 3 where no design meets the constraints)."""
    try:
        _synth(args)
    except SynthesisError as exc:
        if exc.result is not None:
            report(args, exc.result)
        raise


def _synth(args: argparse.Namespace) -> None:
    with logs_to_stderr(args.json):
        problem = given_problem(args.problem)
        args.problem = problem.name
        settings = parse_design(args.set, "settings", "setting", PkmError) if args.set else {}
        result = synthesize(
            problem.configure(**settings),
            resolution=args.resolution,
            starts=args.starts,
            max_iter=args.max_iter,
            tol=args.tol,
            print_level=args.print_level,
            verbose=args.verbose,
        )
    report(args, result, certified(problem, result) if args.certify else None)


def report(args: argparse.Namespace, result: SynthesisResult, certificate: dict[str, Any] | None = None) -> None:
    """A synthesis's record into ``--out`` (``<problem>.json``), and its summary: status, optimum, objective
    as optimised, verified and sampled, constraints and baselines, and the optimum's certificate where one was
    asked."""
    data = result.to_dict()
    if certificate is not None:
        data["certified"] = certificate
    if args.out:
        io.write_result(Path(args.out), lambda out: io.write_text(out / f"{args.problem}.json", io.to_json(data)))
    o = result.optimum
    lines = [
        f"{result.problem}: {result.status} after {result.iterations} iterations "
        f"({result.optimizer['wall_time_s']:.2f} s, {result.optimizer['evaluations']} evaluations)",
        f"variables: {named(o.variables)}",
        f"design: {named(o.design)}",
        f"mode {result.mode}; regions: " + ", ".join(f"{q} over {r}" for q, r in result.regions.items()),
        f"objective ({result.sense}; {result.objective_unit}) {o.objective:.6g} at resolution "
        f"{result.resolutions['quadrature']}, "
        f"verified {o.verified_objective:.6g} (4x quadrature; accuracy {result.accuracy:.1e}), "
        f"sampled {o.sampled_objective:.6g} ({o.sampled_points} points)",
    ]
    lines += constraint_lines(o.constraints)
    for base in result.baselines.values():
        lines.append(
            f"baseline {base.name} ({base.evaluations} evaluations, {base.wall_time_s:.2f} s): "
            f"{base.best.objective:.6g}, verified {base.best.verified_objective:.6g}"
            f"{'' if base.best.feasible else ' (infeasible)'} at {named(base.best.variables)}"
        )
    if certificate is not None:
        c = certificate
        lines.append(f"certified over {c['region']}: {', '.join(f'{k} >= {v:g}' for k, v in c['properties'].items())}"
                     f" {c['verdict'].upper()} ({c['boxes']} boxes, {c['seconds']:.2f} s"
                     + (f"; {c['undecided']:.3g} of the region's box undecided" if c["undecided"] else "")
                     + (f"; witness {named(c['witnesses'][0]['pose'])}" if c["witnesses"] else "") + ")")
    emit(args, data, "\n".join(lines))
