"""The pages of the shipped descriptions: ``python -m pkm.models.described.pages [--check]`` writes
docs/mechanisms/<name>.md and its workspace figures from each description and its registered synthesis
(everything in a page comes from code; ``--check`` compares the text with the committed pages instead of
writing, as tests/test_described_pages.py does)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pkm import registry
from pkm.models.described import DESCRIPTIONS
from pkm.workspace_map import workspace_slice

ROOT = Path(__file__).resolve().parents[3]
FOLDER = ROOT / "docs" / "mechanisms"
# the planes of each machine's workspace figures: the axes and the values held for the other coordinates
PLANES = {
    "rrr3": ((("x", "y"), {"phi": 0.0}), (("x", "phi"), {"y": 0.0})),
    "delta": ((("x", "y"), {"z": -0.5}), (("x", "z"), {"y": 0.0})),
    "stewart": ((("x", "y"), {"z": 1.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0}),
                (("x", "z"), {"y": 0.0, "roll": 0.0, "pitch": 0.0, "yaw": 0.0})),
}
ANCHORS = {
    "rrr3": "inverse kinematics and J against an independent numpy model in every working mode to 1e-12 / 1e-10 "
            "(tests/test_spec.py), that model against robsynth's Maple-generated code for the 3-RRR to 3e-15 "
            "(tests/test_oracles.py)",
    "delta": "inverse kinematics and J against an independent numpy model (a 3-RUU Delta equivalent of "
             "robsynth's) to 1e-12 / 1e-10, that model against robsynth to 3e-15",
    "stewart": "leg lengths and J against an independent numpy model to 1e-12 / 1e-10, that model against "
               "robsynth's 6-UPS to 3e-15; at the home pose of the symmetric platform every leg has the length of "
               "one closed form (tests/test_spec.py)",
}


def _with_units(names: tuple[str, ...], units: tuple[str, ...]) -> str:
    return ", ".join(f"{n} [{u}]" for n, u in zip(names, units, strict=True))


def _figure_name(name: str, axes: tuple[str, str]) -> str:
    return f"{name}_workspace_{axes[0]}_{axes[1]}.png"


def page(name: str) -> str:
    """The markdown page of the shipped description ``name``."""
    mech = registry.mechanism(name)
    problem = registry.problem(f"{name}.max_gci_task")
    text = DESCRIPTIONS[name].read_text().rstrip()
    lines = [
        f"# {name}: {mech.doc}",
        "",
        f"Described as data in `pkm/models/described/{name}.toml`, derived on first use (`pkm.load(\"{name}\")`).",
        "",
        "```toml",
        text,
        "```",
        "",
        "## Parameters",
        "",
        "| name | default | bounds | unit | meaning |",
        "|---|---|---|---|---|",
        *(f"| {p.name} | {p.default:g} | [{p.lower:g}, {p.upper:g}] | {p.unit} | {p.doc} |" for p in mech.parameters),
        "",
        "## Pose, actuators and branches",
        "",
        f"Pose ({_with_units(mech.pose_names, mech.pose_units)}); actuated joints "
        f"({_with_units(mech.actuator_names, mech.actuator_units)}).",
        "",
        "Working modes (inverse-kinematic branches, the first the default):",
        "",
        *(f"- `{b.name}`: {b.doc}" for b in mech.working_modes),
        "",
        f"Assembly modes: {len(mech.assemblies)}, named by the signature of a configuration (each RR leg's elbow "
        "side, the sign of the type-II determinant) and, where a frame admits several solutions of one signature, "
        "their rank by the last pose coordinate (`pkm.kinematics.NearestSeeds`).",
        "",
        "## Regions and indices",
        "",
        *(f"- `{r}`: {mech.region(r).doc}" for r in mech.regions),
        "",
        f"Local indices: {', '.join(f'`{i}`' for i in mech.local_indices())}.",
        "",
        f"Global indices: {', '.join(f'`{i}`' for i in mech.global_indices())}.",
        "",
        "## Synthesis",
        "",
        f"`pkm synth {problem.name}`: {problem.doc}.",
        "",
        "| variable | bounds | unit |",
        "|---|---|---|",
        *(f"| {v.name} | [{v.lower:g}, {v.upper:g}] | {v.unit} |" for v in problem.variables),
        "",
        f"Baseline on the same model: {', '.join(f'{b.name} ({b.doc}, {b.resolution})' for b in problem.baselines)}. "
        "Its optimum, wall time and evaluations against IPOPT's are in docs/benchmarks.md (described machines); "
        "tests/test_optima.py holds the synthesis to a brute force on the same model.",
        "",
        "## Anchors outside pkm",
        "",
        f"{ANCHORS[name]}.",
        "",
        "## Workspace",
        "",
        "The local index 1/kappa_f (`inverse_condition_f`) at the default design in the default working mode over "
        "planes of the pose (`pkm.workspace_map`), the singularity curves, the task region's nodes near the "
        "plane and the linkage at the task's centre (`pkm show` draws the same for any design):",
        "",
        *(f"![{name} workspace over {axes[0]}, {axes[1]}]({_figure_name(name, axes)})" for axes, _ in PLANES[name]),
        "",
    ]
    return "\n".join(lines)


def write(names: list[str]) -> None:
    FOLDER.mkdir(parents=True, exist_ok=True)
    for name in names:
        (FOLDER / f"{name}.md").write_text(page(name))
        mech = registry.mechanism(name)
        centre = mech.region("task").quadrature(mech.functions, mech.design().vector(), 2)[0].mean(axis=0)
        linkage = mech.linkage(centre)
        for axes, held in PLANES[name]:
            workspace_slice(mech, axes=axes, held=held, region="task").plot(FOLDER / _figure_name(name, axes),
                                                                            linkage=linkage)


def check(names: list[str]) -> list[str]:
    """The pages whose committed text differs from :func:`page`."""
    return [name for name in names if (FOLDER / f"{name}.md").read_text() != page(name)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pkm.models.described.pages", description=__doc__)
    parser.add_argument("--check", action="store_true", help="compare with the committed pages, write nothing")
    args = parser.parse_args(argv)
    names = list(DESCRIPTIONS)
    if args.check:
        stale = check(names)
        for name in stale:
            print(f"docs/mechanisms/{name}.md differs from its description: run python -m pkm.models.described.pages")
        return 1 if stale else 0
    write(names)
    return 0


if __name__ == "__main__":
    sys.exit(main())
