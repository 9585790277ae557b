"""The five-bar's synthesis problems: a global index over the maximum inscribed workspace, maximised
in the chart of a normalised design space (Gao 1998; Lara-Molina 2016), against the papers' atlas grid; each
may be traded against the MIW's radius (``pkm pareto five_bar.max_gci_miw --secondary miw_radius``)."""

from __future__ import annotations

from dataclasses import replace

from pkm import registry
from pkm.design_space import DesignSpace
from pkm.models.five_bar.spaces import MIN_LENGTH, MIN_RADIUS
from pkm.synthesis import Margin, Objective, Problem, Quantity, Variable, requirement_constraints


def _chart_problem(
    name: str, space_name: str, index: str, doc: str, *, baseline_resolution: int, hessian: str = "exact"
) -> Problem:
    mech = registry.mechanism("five_bar")
    space: DesignSpace = mech.design_spaces[space_name]
    u, v = space.chart_axes
    xs = [p[0] for p in space.polygon]
    ys = [p[1] for p in space.polygon]
    variables = (
        Variable(u, min(xs), max(xs), "-", f"chart axis {u} = {space.chart_labels[0]} of the {space.name} space"),
        Variable(v, min(ys), max(ys), "-", f"chart axis {v} = {space.chart_labels[1]} of the {space.name} space"),
    )

    constraints = requirement_constraints(
        space, lambda t: dict(zip(space.coordinates, space.from_chart(t[u], t[v]), strict=True))
    )
    quantity = Quantity(registry.global_index(index), mech.regions["miw"])
    problem = Problem(
        name=name,
        doc=doc,
        mechanism=mech,
        variables=variables,
        design=lambda w: space.designs(mech.parameters, space.from_chart(w[0], w[1]), check=False),
        quantities={index: quantity},
        objective=Objective.of(index, quantity),
        constraints=constraints,
        mode="out_out",
        hessian=hessian,
        notes={"space": space.name, "min_length": MIN_LENGTH, "min_radius": MIN_RADIUS},
        margin=Margin(0.0, "as the papers state the problem: the MIW's rim reaches the working mode's "
                      "singular boundary, where every margin is 0", quantity.region),
        secondaries={"miw_radius": Objective(lambda t: t.call("maximum_inscribed_circle", "radius"), "max",
                                             f"radius of the maximum inscribed circle [{space.name} unit length]")},
    )
    baseline = problem.grid_baseline(baseline_resolution, "the best node of the atlas grid over the chart")
    return replace(problem, baselines=(baseline,))


def problems() -> tuple[Problem, ...]:
    return (
        _chart_problem(
            "five_bar.max_gci_miw",
            "gao1998",
            "gci",
            "maximise the GCI over the maximum inscribed workspace in Gao's normalised solution space "
            "(2 r1 + 2 r2 + r3 = 4), working mode out_out (OABCD); every link at least min_length and the "
            "MIC radius at least min_radius (both in units of Gao's average link length L): without it "
            "the optimum shrinks the MIW towards a point",
            baseline_resolution=81,
        ),
        _chart_problem(
            "five_bar.max_dynamic_dexterity_miw",
            "lara_molina2016",
            "dynamic_dexterity",
            "maximise the global dynamic dexterity (Lara-Molina eq. 36) over the MIW in the design space "
            "r1 + r2 + r3 = 3 with the paper's non-dimensional dynamics (m1 = 1.2, m2 = 0.8, k = 1, "
            "j = 0.5 m1), working mode out_out; every length at least min_length from the bounds of eq. 32 "
            "and the MIC radius at least min_radius (units of D)",
            baseline_resolution=61,
        ),
        _chart_problem(
            "five_bar.max_lambda_e_miw",
            "lara_molina2016",
            "lambda_e",
            "maximise the elastodynamic index lambda_e (Lara-Molina eq. 38: the smallest non-zero natural "
            "frequency over the MIW, boundary included) in the design space r1 + r2 + r3 = 3 with the "
            "paper's non-dimensional dynamics, working mode out_out; solved in epigraph form (maximise t "
            "subject to S_e - t^2 I positive semidefinite at every node); lengths at least min_length from "
            "the bounds of eq. 32 and the MIC radius at least min_radius (units of D); limited-memory "
            "Hessian (the exact one of the node constraints costs more than it saves)",
            baseline_resolution=61,
            hessian="limited-memory",
        ),
    )
