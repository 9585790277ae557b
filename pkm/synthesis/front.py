"""A Pareto front as data (:func:`pkm.synthesis.pareto.pareto` computes it): its points, its baselines' fronts,
the front itself with what it writes (front.json, front.csv, the figure and report.md), and the geometry of two
objectives (:func:`minimised`, :func:`non_dominated`, :func:`hypervolume`)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io


@dataclass
class FrontPoint:
    """One point of the front: its epsilon, what IPOPT found (``objective`` f1 and ``secondary`` f2 at the
    optimiser's quadrature), the verified values, the epsilon constraint's multiplier and the trade-off rate
    d f1 / d f2, the status (``optimal``, ``dominated``, ``infeasible``, ``failed``) and IPOPT's."""

    epsilon: float
    status: str
    ipopt_status: str
    variables: dict[str, float]
    design: dict[str, float]
    objective: float
    secondary: float
    verified_objective: float
    verified_secondary: float
    multiplier: float
    trade_off: float
    iterations: int
    evaluations: int
    wall_time_s: float
    resolution: int = 0  # the quadrature's that IPOPT solved at (verified at twice it)

    @property
    def accuracy(self) -> tuple[float, float]:
        """Each objective's change from the optimiser's quadrature to the verification's."""
        return abs(self.verified_objective - self.objective), abs(self.verified_secondary - self.secondary)


@dataclass
class BaselineFront:
    """A baseline's non-dominated feasible points (f1, f2) on the same model, what they cost and their
    hypervolume."""

    name: str
    doc: str
    objective: list[float]
    secondary: list[float]
    evaluations: int
    wall_time_s: float
    variables: list[list[float]] = field(default_factory=list)  # of each of its points
    resolution: int = 0  # the quadrature's its points are verified at
    hypervolume: float = float("nan")
    dominating: int = 0  # pkm front points one of its points dominates (beyond DOMINANCE of a span)
    dominating_beyond_accuracy: int = 0  # those it beats in both objectives by more than their verification change


@dataclass
class ParetoFront:
    """A verified front of ``objective`` against ``secondary`` with its baselines."""

    problem: str
    objective: dict[str, str]
    secondary: dict[str, str]
    points: list[FrontPoint]
    baselines: dict[str, BaselineFront]
    reference: list[float]
    hypervolume: float
    resolution: int
    wall_time_s: float
    evaluations: int
    iterations: int
    anchors: dict[str, dict[str, Any]] = field(default_factory=dict)
    open_hypervolume: float = float("nan")  # the most its points can miss of the front's hypervolume between them

    @property
    def optimal(self) -> list[FrontPoint]:
        return [p for p in self.points if p.status == "optimal"]

    def to_dict(self) -> dict[str, Any]:
        return {
            "problem": self.problem, "objective": self.objective, "secondary": self.secondary,
            "resolution": self.resolution, "wall_time_s": self.wall_time_s, "evaluations": self.evaluations,
            "iterations": self.iterations, "hypervolume": self.hypervolume,
            "open_hypervolume": self.open_hypervolume, "reference": self.reference,
            "anchors": self.anchors, "points": [asdict(p) for p in self.points],
            "baselines": {k: asdict(b) for k, b in self.baselines.items()},
        }

    def __str__(self) -> str:
        counts = {s: sum(p.status == s for p in self.points) for s in ("optimal", "dominated", "infeasible", "failed")}
        text = ", ".join(f"{v} {k}" for k, v in counts.items() if v)
        return (f"{self.problem}: front of {self.objective['name']} against {self.secondary['name']}, "
                f"{len(self.points)} points ({text}), hypervolume {self.hypervolume:.6g}, {self.wall_time_s:.1f} s")

    def write(self, folder: str | Path) -> Path:
        """front.json, front.csv, front.png and front.svg (with the baselines) and report.md into ``folder``,
        all or nothing (:func:`pkm.io.staged_folder`)."""
        target = Path(folder)
        with io.staged_folder(target) as stage:
            io.write_text(stage / "front.json", io.to_json(self.to_dict()))
            io.write_text(stage / "front.csv", csv(self))
            fig = figure(self)
            from pkm.figures import save

            for suffix in ("png", "svg"):
                save(fig, stage / f"front.{suffix}", dpi=150)
            io.write_text(stage / "report.md", report(self))
        return target


def minimised(f1: np.ndarray, f2: np.ndarray, senses: tuple[str, str]) -> np.ndarray:
    """The objectives (N, 2) as both minimised."""
    return np.stack([f1 if senses[0] == "min" else -f1, f2 if senses[1] == "min" else -f2], axis=1)


def non_dominated(costs: np.ndarray, tolerance: np.ndarray | float = 0.0) -> np.ndarray:
    """Mask of the rows of ``costs`` (N, 2), both minimised, that no other row dominates: no worse in both by more
    than ``tolerance`` and better in one by more than it."""
    costs = np.asarray(costs, dtype=float)
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), (2,))
    keep = np.ones(len(costs), dtype=bool)
    for i, c in enumerate(costs):
        no_worse = np.all(costs <= c + tol, axis=1)
        better = np.any(costs < c - tol, axis=1)
        keep[i] = not np.any(no_worse & better)
    return keep


def hypervolume(costs: np.ndarray, reference: np.ndarray) -> float:
    """The area (both objectives minimised) that the points (N, 2) dominate up to the reference point."""
    costs = np.asarray(costs, dtype=float).reshape(-1, 2)
    costs = costs[np.all(np.isfinite(costs), axis=1) & np.all(costs < reference, axis=1)]
    if not len(costs):
        return 0.0
    costs = costs[non_dominated(costs)]
    costs = costs[np.argsort(costs[:, 0])]
    heights = reference[1] - costs[:, 1]
    widths = np.diff(np.append(costs[:, 0], reference[0]))
    return float(np.sum(widths * np.maximum.accumulate(heights)))


def csv(front: ParetoFront) -> str:
    """One row per point: its values, its variables, then the rest of its design (every parameter)."""
    names = list(front.points[0].variables) if front.points else []
    held = [n for n in (front.points[0].design if front.points else {}) if n not in names]
    columns = ["epsilon", "status", "ipopt_status", "objective", "secondary", "verified_objective",
               "verified_secondary", "multiplier", "trade_off", "iterations", "evaluations", "wall_time_s", *names,
               *held]
    rows = [[p.epsilon, p.status, p.ipopt_status, p.objective, p.secondary, p.verified_objective,
             p.verified_secondary, p.multiplier, p.trade_off, p.iterations, p.evaluations, p.wall_time_s,
             *p.variables.values(), *(p.design.get(n, float("nan")) for n in held)] for p in front.points]
    return io.csv_text(columns, rows)


MARKERS = {"optimal": ("o", "C0"), "dominated": ("s", "C3"), "infeasible": ("x", "C3"), "failed": ("X", "k")}


def figure(front: ParetoFront) -> Any:
    """The front (f2 across, f1 up) by status, with each baseline's points."""
    from pkm.figures import figure as new_figure

    fig = new_figure(6.4, 4.6)
    ax = fig.add_subplot()
    for kind, base in front.baselines.items():
        ax.plot(base.secondary, base.objective, ".", ms=5, alpha=0.6,
                label=f"{kind}: {base.evaluations} evaluations, {base.wall_time_s:.1f} s")
    good = [p for p in front.points if p.status in ("optimal", "dominated")]
    ax.plot([p.verified_secondary for p in good], [p.verified_objective for p in good], "-", color="C0", lw=1)
    for status, (marker, colour) in MARKERS.items():
        mine = [p for p in front.points if p.status == status and np.isfinite(p.verified_objective)]
        if mine:
            ax.plot([p.verified_secondary for p in mine], [p.verified_objective for p in mine], marker, color=colour,
                    ms=7, mfc="none" if status != "optimal" else colour,
                    label=f"pkm {status}" + (f": {front.evaluations} evaluations, {front.wall_time_s:.1f} s"
                                             if status == "optimal" else ""))
    ax.set_xlabel(f"{front.secondary['name']} ({'larger' if front.secondary['sense'] == 'max' else 'smaller'} "
                  "is better)")
    ax.set_ylabel(f"{front.objective['name']} ({'larger' if front.objective['sense'] == 'max' else 'smaller'} "
                  "is better)")
    ax.set_title(f"{front.problem}: verified epsilon-constraint front", fontsize=10)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    return fig


def report(front: ParetoFront) -> str:
    """A reproduction-style report: the problem, the front point by point, the baselines."""
    lines = [f"# Pareto front of {front.problem}", "",
             f"{front.objective['name']} ({front.objective['sense']}imised: {front.objective['doc']}) against "
             f"{front.secondary['name']} ({front.secondary['sense']}imised: {front.secondary['doc']}), by the "
             f"epsilon-constraint method at quadrature resolution {front.resolution}, each point verified at "
             f"{2 * front.resolution} (region extremes refined between the nodes).", "",
             f"{len(front.points)} points, {len(front.optimal)} optimal; {front.iterations} IPOPT iterations, "
             f"{front.evaluations} evaluations, {front.wall_time_s:.2f} s; hypervolume {front.hypervolume:.6g} from "
             f"the reference point {[float(f'{v:.6g}') for v in front.reference]} (both objectives as minimised)"
             + (f"; between its points it can miss at most {front.open_hypervolume:.3g} (the open boxes left by its "
                "placement)." if np.isfinite(front.open_hypervolume) else "."),
             "", "![front](front.png)", "",
             "| epsilon | verified objective | verified secondary | trade-off d f1/d f2 | status | IPOPT "
             "| iterations |",
             "|---|---|---|---|---|---|---|"]
    for p in front.points:
        lines.append(f"| {p.epsilon:.6g} | {p.verified_objective:.8g} | {p.verified_secondary:.8g} | "
                     f"{p.trade_off:.6g} | {p.status} | {p.ipopt_status} | {p.iterations} |")
    if front.baselines:
        lines += ["", "| method | points on its front | evaluations | wall time [s] | hypervolume | pkm points it "
                  "dominates | beyond their accuracy in both |", "|---|---|---|---|---|---|---|",
                  f"| pkm (IPOPT) | {len(front.optimal)} | {front.evaluations} | {front.wall_time_s:.2f} | "
                  f"{front.hypervolume:.6g} | - | - |"]
        lines += [f"| {b.name} | {len(b.objective)} | {b.evaluations} | {b.wall_time_s:.2f} | {b.hypervolume:.6g} | "
                  f"{b.dominating} | {b.dominating_beyond_accuracy} |" for b in front.baselines.values()]
    return "\n".join(lines) + "\n"
