"""Dimensional synthesis with IPOPT (DESIGN.md section 6): one :class:`Problem` type
(:mod:`pkm.synthesis.problem`), its CasADi model (:mod:`pkm.synthesis.model`) and one driver
(:mod:`pkm.synthesis.driver`) for every mechanism and any number of variables. Problems are declared
by the mechanism packages and found by name through :mod:`pkm.registry`."""

from pkm.synthesis.driver import BaselineResult, InfeasibleError, Run, SynthesisError, SynthesisResult, synthesize
from pkm.synthesis.model import Candidate, ProblemModel
from pkm.synthesis.problem import (
    Baseline,
    Constraint,
    Margin,
    Objective,
    Problem,
    Quantity,
    Setting,
    Terms,
    Variable,
    grid_points,
    requirement_constraints,
)

__all__ = [
    "Baseline",
    "BaselineResult",
    "Candidate",
    "Constraint",
    "InfeasibleError",
    "Margin",
    "Objective",
    "Problem",
    "ProblemModel",
    "Quantity",
    "Run",
    "Setting",
    "SynthesisError",
    "SynthesisResult",
    "Terms",
    "Variable",
    "grid_points",
    "requirement_constraints",
    "synthesize",
]
