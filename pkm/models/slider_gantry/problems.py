"""The slider gantry's synthesis for a fixed task rectangle (Wu 2008 section 4) and pkm's IPOPT
synthesis beyond it.

The link length l and the half distance d1 are free; the b x h task rectangle, centred at (0,
centre_y), must lie in the workspace with the angle margins theta_s <= |theta_i| <= theta_l
(singularity margins) and within the slider stroke; the platform d2, l2 and Table 2's masses are fixed;
the links keep their mass and s = l/2 and their inertia about the pivot scales as l^2 from Table 2's
(at Table 1's l). A design's own angle margins are its extreme link angles over the rectangle and its
strokes put the rectangle's bottom and top on the slider limits, so that its task region is the
rectangle. A global index over the rectangle is optimised with IPOPT, compared with Wu's two-step
family (theta_1S swept) and with a grid over (l, d1), all on the same model.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from pkm import registry
from pkm.design import stack_design
from pkm.models.slider_gantry.mechanism import TABLE3_MOVE
from pkm.models.slider_gantry.wu2008 import (
    DEG,
    asin,
    required_stroke,
    scaled_links,
    sqrt,
    two_step_angles,
    two_step_points,
)
from pkm.synthesis import Baseline, Constraint, Margin, Objective, Problem, Quantity, Variable

WIDTH, HEIGHT = 0.5, 0.4  # Wu's task rectangle [m], centred at the height of Table 3's move
CENTRE_Y = TABLE3_MOVE["start"][1]
D2, L2 = 0.1, 0.2  # Wu's Table 1 platform [m]
THETA_S, THETA_L = 10 * DEG, 80 * DEG  # Wu's angle margins
MAX_STROKE = 0.9  # [m] Wu's stroke
MAX_FRAME_WIDTH = 1.0  # [m] 2 (d1 + d2)
MIN_K_AV = 1.0
TWO_STEP_SAMPLES = 351


def task_design(mech: Any, length: Any, d1: Any) -> Any:
    """The design vector of (l, d1) for Wu's task rectangle (:func:`pkm.design.stack_design`)."""
    base = dict(mech.design())
    b, h = WIDTH, HEIGHT
    values = {
        **base,
        "l": length,
        "d1": d1,
        "d2": D2,
        "l2": L2,
        "qs": CENTRE_Y - h / 2 - L2 / 2 - sqrt(length**2 - (d1 - b / 2) ** 2),
        "ql": CENTRE_Y + h / 2 - L2 / 2 - sqrt(length**2 - (d1 + b / 2) ** 2),
        "theta_s": asin((d1 - b / 2) / length),
        "theta_l": asin((d1 + b / 2) / length),
    }
    values.update(scaled_links(base, length))
    return stack_design([values[n] for n in mech.parameter_names()])


def _family() -> np.ndarray:
    return two_step_points(WIDTH, HEIGHT, two_step_angles(THETA_S, TWO_STEP_SAMPLES))


def _min_kappa_d_task() -> Problem:
    mech = registry.mechanism("slider_gantry")
    task = mech.regions["task"].at((0.0, CENTRE_Y), (WIDTH / 2, HEIGHT / 2))
    quantities = {
        "kappa_d_mean": Quantity(registry.global_index("kappa_d_mean"), task),
        "k_av": Quantity(registry.global_index("k_av"), task),
    }
    constraints = (
        Constraint("theta_1 >= theta_s over the rectangle", lambda t: t["d1"] - WIDTH / 2 - t["l"] * math.sin(THETA_S)),
        Constraint("theta_2 <= theta_l over the rectangle", lambda t: t["l"] * math.sin(THETA_L) - t["d1"] - WIDTH / 2),
        Constraint("stroke <= max_stroke", lambda t: MAX_STROKE - required_stroke(t["l"], t["d1"], WIDTH, HEIGHT)),
        Constraint("frame width 2 (d1 + d2) <= max_frame_width", lambda t: MAX_FRAME_WIDTH - 2 * (t["d1"] + D2)),
        Constraint("k_av >= min_k_av", lambda t: t["k_av"], MIN_K_AV),
    )
    family = _family()
    every = max(len(family) // 9, 1)
    problem = Problem(
        name="slider_gantry.min_kappa_d_task",
        doc=(
            "minimise the mean of kappa_D (Wu eq. 44) over Wu's 500 x 400 mm task rectangle in the link "
            "length l and the half distance d1, with the angle margins 10 <= |theta_i| <= 80 deg, the "
            "stroke at most Wu's 900 mm, the frame width 2 (d1 + d2) at most 1 m and k_av >= 1; Table 2 "
            "masses, link inertia scaled with l^2; against Wu's two-step family (theta_1S swept) and a grid; "
            "its secondary objective effort_peak, the largest driving force along Wu's Table 3 move (pkm pareto)"
        ),
        mechanism=mech,
        variables=(
            Variable("l", 0.4, 1.2, "m", "length of each link"),
            Variable("d1", 0.25, 0.75, "m", "Wu's half distance between the slider joints, less d2"),
        ),
        design=lambda w: task_design(mech, w[0], w[1]),
        quantities=quantities,
        objective=Objective.of("kappa_d_mean", quantities["kappa_d_mean"]),
        constraints=constraints,
        mode="below",
        starting_points=lambda: family[::every],
        max_iter=200,
        secondaries={"effort_peak": Quantity(mech.trajectory_quantities["effort_peak"], mech.region("table3_move"))},
        notes={
            "width": WIDTH, "height": HEIGHT, "centre_y": CENTRE_Y, "d2": D2, "l2": L2,
            "theta_s": THETA_S, "theta_l": THETA_L, "max_stroke": MAX_STROKE,
            "max_frame_width": MAX_FRAME_WIDTH, "min_k_av": MIN_K_AV, "move": TABLE3_MOVE,
        },
        margin=Margin(0.0, "as Wu states the problem: its angle margins theta_s <= |theta_i| <= theta_l, "
                      "constraints here, are its singularity margins", task),
    )
    baselines = (
        problem.grid_baseline(61),
        Baseline(
            "two_step",
            "Wu's two-step family: eqs. 14-15 with theta_1S swept from theta_s to 44.9 deg",
            lambda n: two_step_points(WIDTH, HEIGHT, two_step_angles(THETA_S, n)),
            TWO_STEP_SAMPLES,
            follows_resolution=False,
        ),
    )
    return replace(problem, baselines=baselines)


def problems() -> tuple[Problem, ...]:
    return (_min_kappa_d_task(),)
