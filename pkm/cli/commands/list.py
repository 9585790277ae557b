"""``pkm list``: what pkm knows (mechanisms, indices, problems, papers) and how it evaluates."""

from __future__ import annotations

import argparse
from typing import Any

from pkm import registry
from pkm.cli.common import emit, evaluation_lines, unit_text
from pkm.compiled import status as compiled_status

HELP = ("mechanisms with their parameters, units, modes, regions and design spaces; indices; problems; papers; "
        "the evaluation path")
PARALLEL = False


def options(_parser: argparse.ArgumentParser) -> None:
    """None but ``--json``."""


def run(args: argparse.Namespace) -> None:
    """Every registered mechanism, index, problem and paper, and the evaluation path."""
    data = {}
    for name in registry.mechanisms():
        m = registry.mechanism(name)
        data[name] = {
            "doc": m.doc,
            "parameters": [
                {"name": p.name, "default": p.default, "lower": p.lower, "upper": p.upper, "unit": p.unit, "doc": p.doc}
                for p in m.parameters
            ],
            "modes": {b.name: {"aliases": list(b.aliases), "doc": b.doc} for b in m.working_modes},
            "assemblies": {b.name: b.doc for b in m.assembly_modes},
            "pose": dict(zip(m.pose_names, m.pose_units, strict=True)),
            "actuators": dict(zip(m.actuator_names, m.actuator_units, strict=True)),
            "regions": list(m.region_names()),
            "design_spaces": sorted(m.design_spaces),
            "indices": list(m.global_indices()),
            "trajectory_quantities": list(m.trajectory_quantities),
        }
    out = {
        "mechanisms": data,
        "indices": {i.name: {"doc": i.doc, "reduce": i.reduce, "sense": i.sense} for i in registry.global_indices()},
        "problems": {
            p.name: {"doc": p.doc, "variables": [v.name for v in p.variables],
                     "settings": {x.name: {"value": p.values[x.name], "lower": x.lower, "upper": x.upper,
                                           "unit": x.unit, "doc": x.doc} for x in p.settings}}
            for p in registry.problems().values()
        },
        "papers": {key: module.TITLE for key, module in registry.papers().items()},
        "evaluation": compiled_status(),
    }
    emit(args, out, "\n".join(_lines(out)))


def _lines(out: dict[str, Any]) -> list[str]:
    """The text of ``pkm list``."""
    lines = []
    for name, info in out["mechanisms"].items():
        lines.append(f"{name}: {info['doc']}")
        lines += [f"  {p['name']} = {p['default']:g} {p['unit']}: {p['doc']}" for p in info["parameters"]]
        lines.append("  modes: " + ", ".join(f"{k} ({'/'.join(v['aliases'])})" for k, v in info["modes"].items()))
        lines.append("  regions: " + ", ".join(info["regions"]))
        lines.append("  design spaces: " + (", ".join(info["design_spaces"]) or "none (atlases take --axes)"))
        lines.append("  along a trajectory region: " + ", ".join(info["trajectory_quantities"]))
        lines.append("  pose: " + ", ".join(f"{k} [{u}]" for k, u in info["pose"].items())
                     + "; actuators: " + ", ".join(f"{k} [{u}]" for k, u in info["actuators"].items()))
    lines.append("indices: " + ", ".join(out["indices"]))
    lines.append("problems: " + ", ".join(out["problems"]))
    lines += [f"  {name} settings (--set): " + ", ".join(f"{k} = {v['value']:.6g}{unit_text(v['unit'])}"
                                                      for k, v in problem["settings"].items())
              for name, problem in out["problems"].items() if problem["settings"]]
    lines.append("papers:")
    lines += [f"  {key}: {title}" for key, title in out["papers"].items()]
    lines += evaluation_lines(out["evaluation"])
    return lines
