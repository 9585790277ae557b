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


def synthesis_record(result: Any) -> dict[str, Any]:
    """The fields of a reproduction's ``beyond_paper`` entry for a :class:`pkm.synthesis.SynthesisResult`."""
    o, b = result.optimum, result.baseline
    return {
        "problem": result.problem,
        "design_normalised": dict(zip(("r1", "r2", "r3"), o.normalised, strict=True)),
        "objective": o.objective,
        "verified_objective": o.verified_objective,
        "sampled_objective": o.sampled_objective,
        "status": result.status,
        "baseline_objective": b.objective,
        "baseline_verified_objective": b.verified_objective,
        "baseline_design_normalised": dict(zip(("r1", "r2", "r3"), b.normalised, strict=True)),
        "optimizer": result.optimizer,
        "baseline_cost": result.baseline_cost,
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
