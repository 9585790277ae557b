"""Verified Pareto fronts against NSGA-II and the grid (issue 27): ``python -m bench.pareto [--json PATH]``.

For each front (the five-bar's GCI against its MIW radius, the slider gantry's mean kappa_D against the largest
driving force along Wu's Table 3 move), :func:`pkm.pareto` with its default tolerance (the points placed until
the boxes they leave open sum to that share of the anchors' box) at the problem's resolution and the grid
baseline (``GRID`` nodes per variable), run twice in one process (the first call compiles what the kernel cache
lacks; the second is reported); then, on the same model, pymoo's NSGA-II (population ``POPULATION``) with as
many evaluations as the pkm front took and with as much wall time, and for the five-bar a dense grid of
``DENSE`` nodes per variable. Every method's non-dominated
feasible points are verified alike (twice the resolution, extremes refined) and its hypervolume taken from the
pkm front's reference point; ``dominating`` counts the pkm points that a method's points dominate, and
``dominating_beyond_accuracy`` those they beat in both objectives by more than the points' verification change
(:func:`pkm.synthesis.pareto.compare_fronts`). An IPOPT
evaluation is the objective and constraints with their gradient, an NSGA-II or grid one without. Nothing
asserts on time.
"""

from __future__ import annotations

import math
from typing import Any

from bench import json_main
from pkm import registry
from pkm.synthesis.pareto import FRONT_TOLERANCE, compare_fronts, front_model, grid_front, nsga2_front, pareto

FRONTS = (("five_bar.max_gci_miw", "miw_radius"), ("slider_gantry.min_kappa_d_task", "effort_peak"))
GRID = 21
DENSE = {"five_bar.max_gci_miw": 601}  # nodes per variable of a dense grid a front is compared with
POPULATION = 40


def _method(base: Any) -> dict[str, Any]:
    return {"points": len(base.objective), "evaluations": base.evaluations, "wall_time_s": base.wall_time_s,
            "hypervolume": base.hypervolume, "dominating": base.dominating,
            "dominating_beyond_accuracy": base.dominating_beyond_accuracy}


def _front(name: str, secondary: str) -> dict[str, Any]:
    problem = registry.problem(name)
    pareto(problem, secondary, grid=GRID, progress=False)
    front = pareto(problem, secondary, grid=GRID, progress=False)
    model = front_model(problem, secondary)
    senses = (front.objective["sense"], front.secondary["sense"])
    generations = math.ceil(front.evaluations / POPULATION)
    front.baselines["nsga2_equal_evaluations"] = nsga2_front(model, front.resolution, nsga=(POPULATION, generations),
                                                             senses=senses)
    front.baselines["nsga2_equal_time"] = nsga2_front(model, front.resolution, nsga=(POPULATION, 0), senses=senses,
                                                      budget=front.wall_time_s)
    if name in DENSE:
        front.baselines[f"grid_{DENSE[name]}"] = grid_front(model, front.resolution, grid=DENSE[name], senses=senses)
    compare_fronts(front, model)
    return {
        "problem": name, "secondary": secondary, "resolution": front.resolution,
        "pkm": {"points": len(front.optimal), "failed": sum(p.status == "failed" for p in front.points),
                "dominated": sum(p.status == "dominated" for p in front.points), "evaluations": front.evaluations,
                "iterations": front.iterations, "wall_time_s": front.wall_time_s, "hypervolume": front.hypervolume,
                "open_hypervolume": front.open_hypervolume},
        "baselines": {kind: _method(base) for kind, base in front.baselines.items()},
        "reference": front.reference,
        "front": [{"verified_objective": p.verified_objective, "verified_secondary": p.verified_secondary,
                   "trade_off": p.trade_off, "status": p.status} for p in front.points],
    }


def run(*, log: Any = print) -> dict[str, Any]:
    fronts = {}
    for name, secondary in FRONTS:
        fronts[f"{name}/{secondary}"] = _front(name, secondary)
        log(f"{name} against {secondary}: {fronts[f'{name}/{secondary}']['pkm']['wall_time_s']:.2f} s")
    return {"command": "python -m bench.pareto --json docs/benchmarks/pareto.json", "tolerance": FRONT_TOLERANCE,
            "grid": GRID, "dense": DENSE, "population": POPULATION, "fronts": fronts}


def markdown(data: dict[str, Any]) -> str:
    """The docs/benchmarks.md section of a run."""
    lines = [f"Command: `{data['command']}` (second calls, the kernels compiled): fronts placed by their shape "
             f"until the boxes their points leave open sum to {data['tolerance']:g} of the anchors' box, a "
             f"{data['grid']}-per-variable grid, NSGA-II with a population of {data['population']}; every method's "
             "points verified alike, again at the front's verification resolution, hypervolumes from the pkm "
             "front's reference point.", ""]
    for f in data["fronts"].values():
        p = f["pkm"]
        lines += [f"`pkm pareto {f['problem']} --secondary {f['secondary']}` (resolution {f['resolution']}):", "",
                  "| method | points on its front | evaluations | wall time | hypervolume | pkm points it dominates | "
                  "beyond their accuracy in both |",
                  "|---|---|---|---|---|---|---|",
                  f"| pkm (IPOPT, {p['iterations']} iterations; {p['dominated']} dominated, {p['failed']} failed) | "
                  f"{p['points']} | {p['evaluations']} | {p['wall_time_s']:.2f} s | {p['hypervolume']:.6g} (open "
                  f"{p['open_hypervolume']:.2g}) | - | - |"]
        for kind, b in f["baselines"].items():
            lines.append(f"| {kind} | {b['points']} | {b['evaluations']} | {b['wall_time_s']:.2f} s | "
                         f"{b['hypervolume']:.6g} | {b['dominating']} | {b['dominating_beyond_accuracy']} |")
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def main(argv: list[str] | None = None) -> int:
    return json_main("python -m bench.pareto", __doc__, run, markdown, argv)


if __name__ == "__main__":
    raise SystemExit(main())
