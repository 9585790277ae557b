"""report.json and report.md of a reproduction."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pkm import io

STATUSES = ("match", "differs", "not_stated")


def claim(
    id: str, description: str, paper_value: Any, pkm_value: Any, unit: str, status: str, note: str = ""
) -> dict[str, Any]:
    """One checked statement of a paper."""
    if status not in STATUSES:
        raise ValueError(f"claim status {status!r} is not one of {STATUSES}")
    return {
        "id": id,
        "description": description,
        "paper_value": paper_value,
        "pkm_value": pkm_value,
        "unit": unit,
        "status": status,
        "note": note,
    }


def status(ok: bool) -> str:
    """A claim's status from whether pkm's value agrees with the paper's."""
    return "match" if ok else "differs"


def reproduced_by(readings: dict[str, dict[str, bool]], statement: str) -> str:
    """The readings of a paper that reproduce one of its statements, for a claim's note."""
    names = [name for name, ok in readings[statement].items() if ok]
    return ", ".join(names) if names else "no reading"


def synthesis_record(result: Any) -> dict[str, Any]:
    """The fields of a reproduction's ``beyond_paper`` entry for a :class:`pkm.synthesis.SynthesisResult`,
    labelled by the result's own variable and parameter names; ``<baseline>_objective`` for each
    baseline and ``baseline_objective`` for the first."""
    o = result.optimum
    baselines = {
        name: {
            "variables": b.best.variables,
            "objective": b.best.objective,
            "verified_objective": b.best.verified_objective,
            "feasible": b.best.feasible,
            "wall_time_s": b.wall_time_s,
            "evaluations": b.evaluations,
            "doc": b.doc,
        }
        for name, b in result.baselines.items()
    }
    first = next(iter(baselines.values()), {"objective": None, "verified_objective": None})
    return {
        "problem": result.problem,
        "sense": result.sense,
        "mode": result.mode,
        "regions": result.regions,
        "variables": o.variables,
        "design": o.design,
        "objective": o.objective,
        "verified_objective": o.verified_objective,
        "accuracy": result.accuracy,
        "resolutions": result.resolutions,
        "sampled_objective": o.sampled_objective,
        "sampled_points": o.sampled_points,
        "status": result.status,
        "optimizer": result.optimizer,
        "baseline_objective": first["objective"],
        "baseline_verified_objective": first["verified_objective"],
        **{f"{name}_objective": b["objective"] for name, b in baselines.items()},
        "baselines": baselines,
    }


def _fmt(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, dict):
        return ", ".join(f"{k}: {_fmt(v)}" for k, v in value.items())
    return "" if value is None else str(value)


def write_report(folder: Path, report: dict[str, Any]) -> None:
    """Write report.json and a readable report.md into ``folder``."""
    io.write_text(folder / "report.json", io.to_json(report))
    lines = [f"# {report['title']}", "", report.get("summary", ""), ""]
    lines += ["## Claims", "", "| id | claim | paper | pkm | unit | status | note |", "|---|---|---|---|---|---|---|"]
    for c in report["claims"]:
        cells = [
            c["id"],
            c["description"],
            _fmt(c["paper_value"]),
            _fmt(c["pkm_value"]),
            c["unit"],
            c["status"],
            c["note"],
        ]
        lines.append("| " + " | ".join(str(x).replace("|", "/") for x in cells) + " |")
    beyond = report.get("beyond_paper")
    if beyond:
        lines += ["", "## Beyond the paper", "", beyond["text"], ""]
    lines += ["", "## Settings", ""]
    lines += [f"- {k}: {_fmt(v)}" for k, v in report.get("settings", {}).items()]
    if report.get("figures"):
        lines += ["", "## Figures", ""]
        lines += [f"![{f}]({f})" for f in report["figures"]]
    io.write_text(folder / "report.md", "\n".join(lines) + "\n")
