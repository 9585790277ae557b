"""The 2-UPS-PU synthesis for a prescribed workspace (Zhao section 6) and pkm's IPOPT solution of it.

Variables: beta, r, R, l0_min and the UPS legs' shortest length l_min, with alpha = 90 deg (step 2),
the legs' longest length l_max = 1.8 l_min (the stroke rule of eq. 10 and step 5) and the PU leg's
stroke exactly the task cylinder's height (l0_max = l0_min + task_height). Section 6 states no joint
limits: with section 5.3's 60 deg for the spherical joints no screening design (nor Table 1) holds a
cylinder tilted 60 deg, so the synthesis allows 90 deg, the universal joints' limit. The task cylinder (tilt up
to task_tilt over l0 in [l0_min, l0_min + task_height]) must lie in the workspace: the least margin
of the four constraints at every node of its quadrature is >= 0. Objective (eq. 17): minimise
pi R^2 l0_min F, F the largest actuator force over the cylinder that holds the payload (the paper
states no load: pkm's payload parameters, documented in docs/papers/zhao2008.md). Baselines on the
same model: the paper's Monte Carlo search over the same bounds (steps 4-5, l_min from the legs over
the cylinder's bottom rim) and Table 1's design.
"""

from __future__ import annotations

import math
from dataclasses import replace

import casadi as ca
import numpy as np

from pkm import registry
from pkm.design import stack_design
from pkm.indices import GlobalIndex, LocalIndex
from pkm.models.ups_pu.workspace import MARGINS, tilt_to_angles
from pkm.synthesis import Baseline, Constraint, Objective, Problem, Quantity, Variable

DEG = math.pi / 180
STROKE_RATIO = 1.8  # l_max / l_min (eq. 10 with the equality of step 5)
TABLE1 = (27 * DEG, 0.124, 0.186, 0.450, 0.396)  # beta, r, R, l0_min, l_min of Table 1
MONTE_CARLO_SEED = 2008
RIM_POINTS = 360  # step 5's equally spaced angles phi
NODE_MARGIN = 2e-3  # [m, or -] held at the optimiser's nodes, so that the margins between them stay >= 0
SPHERICAL_LIMIT = 90 * DEG  # section 6 states no joint limits; section 5.3's 60 deg leaves nothing feasible


# The PU leg's stroke limits hold by construction (its stroke is the cylinder's height) and are 0 at the
# cylinder's ends: the task margin is the least of the others.
KEPT = [k for k, name in enumerate(MARGINS) if name not in ("l0_min", "l0_max")]
TASK_MARGIN = LocalIndex(
    "task_margin",
    "least workspace margin but the PU leg's stroke limits (which the design map keeps at the task's ends)",
    "-", -np.inf, np.inf, -np.inf,
    lambda m: ca.mmin(m[KEPT]), "workspace_margins", ("margins",), lambda m, t: m[KEPT] - t,
)
TASK_MARGIN_MIN = GlobalIndex("task_margin_min", TASK_MARGIN, "region minimum of the task margin", "min")


def design_map(mech, values):
    """The design vector of (beta, r, R, l0_min, l_min) (:func:`pkm.design.stack_design`)."""
    beta, r, R, l0_min, l_min = values
    base = dict(mech.design())
    given = {
        "alpha": 90 * DEG, "beta": beta, "r": r, "R": R, "l0_min": l0_min, "l_min": l_min,
        "l_max": STROKE_RATIO * l_min, "l0_max": l0_min + base["task_height"], "theta_s_max": SPHERICAL_LIMIT,
    }
    return stack_design([given.get(name, base[name]) for name in mech.parameter_names()])


def shortest_leg_on_rim(mech, beta: float, r: float, R: float, l0_min: float) -> float:
    """Zhao's step 5: the shortest UPS leg over the cylinder's bottom rim (l0 = l0_min, tilt task_tilt,
    360 equally spaced phi), which sets l_min (and l_max = 1.8 l_min)."""
    base = dict(mech.design())
    phi = 2 * math.pi * np.arange(RIM_POINTS) / RIM_POINTS
    theta1, theta2 = tilt_to_angles(phi, np.full(RIM_POINTS, base["task_tilt"]))
    design = np.asarray(design_map(mech, (beta, r, R, l0_min, base["l_min"])), dtype=float)
    poses = np.column_stack([np.full(RIM_POINTS, l0_min), theta1, theta2])
    return float(mech.inverse_kinematics(poses, design)[:, :2].min())


def _monte_carlo(mech, variables: tuple[Variable, ...], count: int) -> np.ndarray:
    """Zhao's steps 4-5: beta, r, R, l0_min drawn uniformly within their bounds, l_min from the rim."""
    rng = np.random.default_rng(MONTE_CARLO_SEED)
    lower = np.array([v.lower for v in variables[:4]])
    upper = np.array([v.upper for v in variables[:4]])
    drawn = lower + (upper - lower) * rng.uniform(size=(count, 4))
    legs = [shortest_leg_on_rim(mech, *row) for row in drawn]
    return np.column_stack([drawn, legs])


def _prescribed_workspace() -> Problem:
    mech = registry.mechanism("ups_pu")
    task = mech.regions["task"]
    quantities = {
        "force": Quantity(registry.global_index("actuator_force_max"), task),
        "margin": Quantity(TASK_MARGIN_MIN, task),
    }
    variables = (
        Variable("beta", 5 * DEG, 85 * DEG, "rad", "angular position of the second UPS leg"),
        Variable("r", 0.05, 0.30, "m", "platform radius"),
        Variable("R", 0.05, 0.40, "m", "base radius"),
        Variable("l0_min", 0.20, 0.80, "m", "lowest position of U0"),
        Variable("l_min", 0.20, 0.80, "m", "shortest UPS leg (l_max = 1.8 l_min)"),
    )
    problem = Problem(
        name="ups_pu.min_size_force_task",
        doc=(
            "minimise pi R^2 l0_min F (Zhao eq. 17), F the largest actuator force holding the payload over "
            "the task cylinder (tilt <= 60 deg, height 100 mm above l0_min), in beta, r, R, l0_min, l_min with "
            "alpha = 90 deg and l_max = 1.8 l_min, the cylinder inside the workspace of the four constraints "
            "of section 5; against the paper's Monte Carlo search and Table 1"
        ),
        mechanism=mech,
        variables=variables,
        design=lambda w: design_map(mech, w),
        quantities=quantities,
        objective=Objective(
            lambda t: math.pi * t["R"] ** 2 * t["l0_min"] * t["force"],
            "min",
            "pi R^2 l0_min F [m^3 N] (Zhao eq. 17)",
        ),
        constraints=(
            Constraint(
                "task cylinder inside the workspace (least margin >= 0)", lambda t: t["margin"], margin=NODE_MARGIN
            ),
        ),
        mode="legs",
        starting_points=lambda: np.array([TABLE1]),
        resolution=3,
        screening_resolution=4,
        starts=3,
        hessian="limited-memory",
        max_iter=100,
        notes={"stroke_ratio": STROKE_RATIO, "table1": TABLE1},
    )
    baselines = (
        Baseline(
            "monte_carlo",
            "Zhao section 6.2: beta, r, R, l0_min drawn uniformly within the bounds (step 4), l_min the shortest "
            "leg over the cylinder's bottom rim and l_max = 1.8 l_min (step 5), the best feasible kept",
            lambda n: _monte_carlo(mech, variables, n),
            400,
        ),
        Baseline("table1", "Zhao Table 1's design on the same model", lambda _n: np.array([TABLE1]), 1,
                 follows_resolution=False),
    )
    return replace(problem, baselines=baselines)


def problems() -> tuple[Problem, ...]:
    return (_prescribed_workspace(),)
