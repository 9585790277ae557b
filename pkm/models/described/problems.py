"""Syntheses of the described machines over their task regions (:func:`pkm.synthesis.designer.design_problem`):
the GCI over the task maximised with the task inside the workspace (the least margin of the legs' reach, the
actuated joints' ranges and, for the Stewart-Gough platform, its joints' cones over the task at least 0),
against the baseline the literature uses for each: a grid for the planar 3-RRR (Gosselin and Angeles' atlases)
and the Delta (two link lengths), Monte Carlo for the Stewart-Gough platform."""

from __future__ import annotations

from pkm import registry
from pkm.synthesis import Problem
from pkm.synthesis.designer import design_problem


def problems() -> tuple[Problem, ...]:
    return (
        design_problem(
            registry.mechanism("rrr3"), task="task", name="rrr3.max_gci_task",
            variables={"r_p": (0.1, 0.6), "l1": (0.3, 1.0), "l2": (0.3, 1.0)},
            doc="maximise the GCI over the task cylinder (a disc of radius 0.15 m, platform angles within 15 deg) "
                "in the platform radius and the two link lengths, the base radius 1 m, working mode left_left_left; "
                "the task inside the workspace",
            baseline=("grid", 11),
        ),
        design_problem(
            registry.mechanism("delta"), task="task", name="delta.max_gci_task",
            variables={"L_a": (0.15, 0.5), "L_b": (0.3, 1.0)},
            doc="maximise the GCI over the task cylinder (radius 0.15 m, height 0.1 m, 0.5 m below the base) in "
                "the arm and forearm lengths, working mode elbow_out; the task inside the workspace and the arms' "
                "sweep",
            baseline=("grid", 41),
        ),
        design_problem(
            registry.mechanism("stewart"), task="task", name="stewart.max_gci_task",
            variables={"r_p": (0.3, 0.9), "theta_b": (0.1, 1.0), "theta_p": (0.1, 1.0)},
            doc="maximise the GCI over the task box (0.2 x 0.2 x 0.1 m, 1 m above the base, the platform parallel "
                "to the base) in the platform radius and the angles of the joint pairs, the base radius 1 m; the "
                "task inside the legs' strokes and the joints' cones",
            baseline=("monte_carlo", 1000),
        ),
    )
