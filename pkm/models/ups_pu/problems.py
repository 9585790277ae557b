"""The 2-UPS-PU synthesis for a prescribed workspace (Zhao section 6) and pkm's IPOPT solution of it.

Variables: beta, r, R, l0_min and the UPS legs' shortest length l_min, with alpha = 90 deg (step 2),
the legs' longest length l_max = 1.8 l_min (the stroke rule of eq. 10 and step 5) and the PU leg's
stroke exactly the task cylinder's height (l0_max = l0_min + task_height). The task cylinder (tilt up
to task_tilt over l0 in [l0_min, l0_min + task_height]) must lie in the workspace of section 5's four
constraints with section 5.3's joint limits (90 deg at the universal joints, 60 deg at the spherical
ones): the least margin of the constraints at every node of its quadrature is >= 0. Zhao's "cylinder
with radius gamma, gamma_u = 60 deg" is read as a cone of apex angle 60 deg, a tilt radius of 30 deg:
that reading gives Table 1's leg lengths by step 5 and holds Table 1's design feasible under section
5.3's limits, which the literal tilt radius of 60 deg does not (docs/papers/zhao2008.md; the literal
reading is ``configure(task_tilt=pi / 3)``). Objective (eq. 17): minimise pi R^2 l0_min F, F the
largest actuator force over the cylinder that holds the payload (the paper states no load: pkm's
payload, a setting). The task's tilt and height, the joint limits and the load are the problem's
settings (:meth:`pkm.synthesis.Problem.configure`, ``pkm synth --set``). Baselines on the same model:
the paper's Monte Carlo search over the same bounds (steps 4-5, l_min from the legs over the
cylinder's bottom rim) and Table 1's design.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace

import casadi as ca
import numpy as np

from pkm import registry
from pkm.design import stack_design
from pkm.indices import GlobalIndex, LocalIndex
from pkm.models.ups_pu.workspace import MARGINS, tilt_to_angles
from pkm.synthesis import Baseline, Constraint, Margin, Objective, Problem, Quantity, Setting, Variable

DEG = math.pi / 180
STROKE_RATIO = 1.8  # l_max / l_min (eq. 10 with the equality of step 5)
TABLE1 = (27 * DEG, 0.124, 0.186, 0.450, 0.396)  # beta, r, R, l0_min, l_min of Table 1
MONTE_CARLO_SEED = 2008
RIM_POINTS = 360  # step 5's equally spaced angles phi
NODE_MARGIN = 2e-3  # [m, or -] held at the optimiser's nodes, so that the margins between them stay >= 0
SETTINGS = (
    Setting("task_tilt", 30 * DEG, 1e-3, 90 * DEG, "rad", "tilt radius gamma of the task cylinder: Zhao's gamma_u = "
            "60 deg read as the cone's apex angle (pi / 3 is the literal reading, a tilt radius of 60 deg)"),
    Setting("task_height", 0.1, 1e-3, 2.0, "m", "height h of the task cylinder in l0 (Zhao section 6.2: 100 mm)"),
    Setting("theta_u_max", 90 * DEG, 1e-3, 180 * DEG, "rad", "largest misalignment of a universal joint (section "
            "5.3: 90 deg)"),
    Setting("theta_s_max", 60 * DEG, 1e-3, 180 * DEG, "rad", "largest misalignment of a spherical joint (section "
            "5.3: 60 deg)"),
    Setting("payload", 50.0, 0.0, 1e5, "kg", "mass held by the platform (Zhao states none)"),
    Setting("payload_height", 0.2, -2.0, 2.0, "m", "height of the payload's centre of mass above U0 along the "
            "platform normal"),
)
DEFAULTS = {s.name: s.default for s in SETTINGS}


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


def design_map(mech, values, settings: Mapping[str, float] = DEFAULTS):
    """The design vector of (beta, r, R, l0_min, l_min) with the problem's settings
    (:func:`pkm.design.stack_design`)."""
    beta, r, R, l0_min, l_min = values
    base = {**dict(mech.design()), **settings}
    given = {
        "alpha": 90 * DEG, "beta": beta, "r": r, "R": R, "l0_min": l0_min, "l_min": l_min,
        "l_max": STROKE_RATIO * l_min, "l0_max": l0_min + base["task_height"],
    }
    return stack_design([given.get(name, base[name]) for name in mech.parameter_names()])


def shortest_leg_on_rim(mech, beta: float, r: float, R: float, l0_min: float, *,
                        settings: Mapping[str, float] = DEFAULTS) -> float:
    """Zhao's step 5: the shortest UPS leg over the cylinder's bottom rim (l0 = l0_min, tilt task_tilt,
    360 equally spaced phi), which sets l_min (and l_max = 1.8 l_min)."""
    phi = 2 * math.pi * np.arange(RIM_POINTS) / RIM_POINTS
    theta1, theta2 = tilt_to_angles(phi, np.full(RIM_POINTS, settings["task_tilt"]))
    design = np.asarray(design_map(mech, (beta, r, R, l0_min, mech.design()["l_min"]), settings), dtype=float)
    poses = np.column_stack([np.full(RIM_POINTS, l0_min), theta1, theta2])
    return float(mech.inverse_kinematics(poses, design, limits=False)[:, :2].min())


def _monte_carlo(mech, variables: tuple[Variable, ...], count: int, settings: Mapping[str, float]) -> np.ndarray:
    """Zhao's steps 4-5: beta, r, R, l0_min drawn uniformly within their bounds, l_min from the rim."""
    rng = np.random.default_rng(MONTE_CARLO_SEED)
    lower = np.array([v.lower for v in variables[:4]])
    upper = np.array([v.upper for v in variables[:4]])
    drawn = lower + (upper - lower) * rng.uniform(size=(count, 4))
    legs = [shortest_leg_on_rim(mech, *row, settings=settings) for row in drawn]
    return np.column_stack([drawn, legs])


def _prescribed_workspace(values: Mapping[str, float] = DEFAULTS) -> Problem:
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
            f"the task cylinder (tilt <= {values['task_tilt'] / DEG:.4g} deg, height {values['task_height'] * 1e3:.4g} "
            "mm above l0_min), in beta, r, R, l0_min, l_min with alpha = 90 deg and l_max = 1.8 l_min, the "
            "cylinder inside the workspace of the four constraints of section 5 (joint limits "
            f"{values['theta_u_max'] / DEG:.4g} / {values['theta_s_max'] / DEG:.4g} deg); against the paper's "
            "Monte Carlo search and Table 1"
        ),
        mechanism=mech,
        variables=variables,
        design=lambda w: design_map(mech, w, values),
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
        margin=Margin(0.0, "as Zhao states the problem: section 5's constraints and joint limits bound its "
                      "workspace", task),
        settings=SETTINGS,
        values=dict(values),
        build=_prescribed_workspace,
    )
    baselines = (
        Baseline(
            "monte_carlo",
            "Zhao section 6.2: beta, r, R, l0_min drawn uniformly within the bounds (step 4), l_min the shortest "
            "leg over the cylinder's bottom rim and l_max = 1.8 l_min (step 5), the best feasible kept",
            lambda n: _monte_carlo(mech, variables, n, values),
            400,
        ),
        Baseline("table1", "Zhao Table 1's design on the same model", lambda _n: np.array([TABLE1]), 1,
                 follows_resolution=False),
    )
    return replace(problem, baselines=baselines)


def problems() -> tuple[Problem, ...]:
    return (_prescribed_workspace(),)
