"""pkm: design of parallel kinematic machines.

>>> import pkm
>>> m = pkm.load(pkm.mechanisms()[0])
>>> m.inverse_kinematics(m.workspace_box(m.design().vector()).mean(axis=1)).shape == (m.n_act,)
True
"""

from __future__ import annotations

from typing import Any

from pkm import registry
from pkm.design import Design, Parameter
from pkm.errors import ComputationError, DesignError, PkmError, PoseError, SingularityError, UnknownNameError
from pkm.mechanism import Mechanism
from pkm.parallel import use_scheduler
from pkm.synthesis import Problem, SynthesisResult
from pkm.synthesis import synthesize as _synthesize

__all__ = [
    "ComputationError",
    "Design",
    "DesignError",
    "Mechanism",
    "Parameter",
    "PkmError",
    "PoseError",
    "Problem",
    "SingularityError",
    "UnknownNameError",
    "load",
    "mechanisms",
    "synthesize",
    "use_scheduler",
]

__version__ = "0.1.0"


def mechanisms() -> list[str]:
    """Names of the registered mechanisms."""
    return registry.mechanisms()


def load(name: str) -> Mechanism:
    """The mechanism registered under ``name``."""
    return registry.mechanism(name)


def synthesize(problem: str | Problem, **options: Any) -> SynthesisResult:
    """Solve a synthesis problem (a registered name or a :class:`pkm.synthesis.Problem`) with IPOPT and
    verify it; see :func:`pkm.synthesis.synthesize` for the options."""
    if not isinstance(problem, Problem):
        problem = registry.problem(problem)
    return _synthesize(problem, **options)
