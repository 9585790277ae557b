"""Nam and Park's optimal design (section 6.2, eq. 32): maximise the composed index eta of eq. 31 over
r/R and l_b/R in [0.5, 2] with R = 1 and l_b - l_a = R - r, in the reading the paper's statements
support (:mod:`pkm.models.passive_leg.nam2006`), against a dense grid over the same design space (the
paper's own method, Figs. 4-7).

For r < R a folded leg (a type-1 singularity) lies inside the region (docs/papers/nam2006.md): the
design space's requirement r >= R, a constraint here, keeps the optimiser where the region is the
workspace (and an atlas's best there); the indices are undefined
(NaN) at designs whose region holds a type-2 singularity or leaves a joint range of section 4.
"""

from __future__ import annotations

from dataclasses import replace

from pkm import registry
from pkm.models.passive_leg import nam2006
from pkm.synthesis import Margin, Objective, Problem, Quantity, Variable, requirement_constraints

GRID = 61  # the baseline's chart nodes per axis


def _composed(t, reading: nam2006.Reading):
    bounds = nam2006.extremes(reading)
    return nam2006.composed([t["eta1"], t["eta2"], t["eta3"]], bounds, reading.normalise)


def _max_composed() -> Problem:
    mech = registry.mechanism("passive_leg")
    reading = nam2006.SUPPORTED
    region = mech.regions[reading.region]
    space = mech.design_spaces["nam2006"]
    quantities = {
        f"eta{k + 1}": Quantity(registry.global_index(name), region) for k, name in enumerate(reading.indices)
    }
    variables = (
        Variable("r", 0.5, 2.0, "-", "platform half-width r / R"),
        Variable("l_b", 0.5, 2.0, "-", "upper link l_b / R (l_a = l_b - R + r)"),
    )
    problem = Problem(
        name="passive_leg.max_composed",
        doc=(
            "maximise eta = eta_1^ eta_2^ eta_3^ (Nam eq. 31: GCI, manipulability |det J_f| and space utilisation "
            "over the workspace measured in the plane, each normalised by its range over the admissible designs) "
            "in r/R, l_b/R in [0.5, 2] with R = 1 and l_b - l_a = R - r (eq. 32), working mode out_out (Fig. 1), "
            "r >= R so that no folded leg lies inside the region; against a 61 x 61 grid"
        ),
        mechanism=mech,
        variables=variables,
        design=lambda w: space.designs(mech.parameters, [w[0], w[1]], check=False),
        quantities=quantities,
        objective=Objective(lambda t: _composed(t, reading), "max", "eta of eq. 31 [-]"),
        constraints=requirement_constraints(space, lambda t: {"r": t["r"], "l_b": t["l_b"]}),
        mode=nam2006.MODE,
        resolution=nam2006.RESOLUTION,
        screening_resolution=5,
        starts=3,
        notes={"reading": reading.name, "extremes_grid": nam2006.EXTREMES_GRID},
        margin=Margin(0.0, "as Nam and Park state the problem: r >= R keeps folded legs (type 1) out of the "
                      "region, and the indices are undefined where it holds a type-2 singularity", region),
    )
    return replace(problem, baselines=(problem.grid_baseline(GRID, "the best node of a 61 x 61 grid over the "
                                                                   "design space (Nam Figs. 4-7)"),))


def problems() -> tuple[Problem, ...]:
    return (_max_composed(),)
