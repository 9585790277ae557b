"""The designer's commands (issue 25): ``python -m bench.designer [--json PATH]``.

For each registered mechanism, ``pkm show MECHANISM --out DIR`` at its defaults (its first working mode, a
map of 81 x 81 poses and every global index over its first parametrised region), run twice in one process (the
first call compiles what the kernel cache lacks; the second is reported; goal: a card in under 2 s once
compiled); and for each example task file of docs/tasks/, ``pkm design`` run twice likewise: the synthesis's
wall time and evaluations, its verified objective against its baseline's on the same model. Nothing asserts
on time.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Any

import pkm
from bench import json_main
from pkm.card import design_card
from pkm.synthesis.designer import read_problem

ROOT = Path(__file__).resolve().parent.parent
TASKS = ROOT / "docs" / "tasks"
CARD_GOAL_S = 2.0


def _card(name: str) -> dict[str, Any]:
    m = pkm.load(name)
    mode = m.modes[0]
    with tempfile.TemporaryDirectory() as folder:
        design_card(m, modes=[mode]).write(Path(folder))
        start = time.perf_counter()
        card = design_card(m, modes=[mode])
        files = card.write(Path(folder))
        seconds = time.perf_counter() - start
    return {"mode": mode, "region": card.region, "indices": len(card.indices), "files": len(files),
            "wall_time_s": seconds}


def _task(path: Path) -> dict[str, Any]:
    problem = read_problem(path)
    pkm.synthesize(problem, progress=False)
    start = time.perf_counter()
    result = pkm.synthesize(problem, progress=False)
    seconds = time.perf_counter() - start
    (name, baseline), = result.baselines.items()
    return {"problem": problem.name, "mechanism": problem.mechanism.name, "sense": result.sense,
            "whole_call_s": seconds, "wall_time_s": result.optimizer["wall_time_s"],
            "evaluations": result.optimizer["evaluations"], "verified_objective": result.verified_objective,
            "baseline": name, "baseline_evaluations": baseline.evaluations,
            "baseline_wall_time_s": baseline.wall_time_s,
            "baseline_verified_objective": baseline.best.verified_objective}


def run(*, log: Any = print) -> dict[str, Any]:
    cards = {}
    for name in pkm.mechanisms():
        cards[name] = _card(name)
        log(f"show {name}: {cards[name]['wall_time_s']:.2f} s")
    tasks = {}
    for path in sorted(TASKS.glob("*.toml")):
        tasks[path.name] = _task(path)
        log(f"design {path.name}: {tasks[path.name]['whole_call_s']:.2f} s")
    return {"command": "python -m bench.designer --json docs/benchmarks/designer.json", "card_goal_s": CARD_GOAL_S,
            "cards": cards, "tasks": tasks}


def markdown(data: dict[str, Any]) -> str:
    """The docs/benchmarks.md section of a run."""
    lines = [f"Command: `{data['command']}` (second calls, the kernels compiled; goal: a card in under "
             f"{data['card_goal_s']:g} s).", "", "| `pkm show` | mode | region | global indices | files | wall time |",
             "|---|---|---|---|---|---|"]
    for name, c in data["cards"].items():
        lines.append(f"| {name} | {c['mode']} | {c['region']} | {c['indices']} | {c['files']} | "
                     f"{c['wall_time_s']:.2f} s |")
    lines += ["", "| `pkm design` | sense | wall time | evaluations | verified objective | baseline | baseline "
              "evaluations | baseline wall time | baseline verified |", "|---|---|---|---|---|---|---|---|---|"]
    for name, t in data["tasks"].items():
        lines.append(f"| docs/tasks/{name} | {t['sense']} | {t['whole_call_s']:.2f} s | {t['evaluations']} | "
                     f"{t['verified_objective']:.6g} | {t['baseline']} | {t['baseline_evaluations']} | "
                     f"{t['baseline_wall_time_s']:.2f} s | {t['baseline_verified_objective']:.6g} |")
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    return json_main("python -m bench.designer", __doc__, run, markdown, argv)


if __name__ == "__main__":
    raise SystemExit(main())
